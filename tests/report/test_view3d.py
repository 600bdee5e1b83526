"""Issue 23: the reports show the robot on the ship in 3D (plotly, inlined, offline).

The geometry is checked against the plan's numbers; the view is checked drawn by a real
headless browser (Debian's chromium, its WebGL in software: swiftshader), on the DOM it
renders and on a screenshot's pixels.
"""

from __future__ import annotations

import shutil
import subprocess
from html.parser import HTMLParser
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from typer.testing import CliRunner

import marinecdpr
import marinecdpr.report.text as text
from marinecdpr.cli.app import app
from marinecdpr.geometry.rotations import matrix_from_euler
from marinecdpr.report.view3d import (
    DEFAULT_HULL_M, PATH_POINTS_MAX, SECTION_TITLE, hull_box, sample_steps, scene_geometry, scene_html,
)

runner = CliRunner()
CHROMIUM = shutil.which("chromium")
needs_chromium = pytest.mark.skipif(CHROMIUM is None, reason="no chromium on PATH (.ci/run installs Debian's with apt)")
RESEARCH = Path("/work/research")
TRACES = ("frame anchors", "frame (box of the anchors)", "planned path of P", "platform (outline of its anchors)",
          "cables")


@pytest.fixture(scope="module")
def paper_scene():
    sc = marinecdpr.load_scenario("paper")
    plan = marinecdpr.plan(sc)
    return sc, plan, scene_geometry(sc, plan)


# ------------------------------------------------------------ the numbers
def test_cables_run_from_the_frame_anchors_at_the_plans_lengths(paper_scene):
    sc, plan, scene = paper_scene
    origin = np.asarray(sc.ship.frame_origin_m)
    assert scene.times[0] == 0.0 and scene.cables.shape == (scene.times.size, 4, 2, 3)
    lengths = np.linalg.norm(scene.cables[:, :, 1] - scene.cables[:, :, 0], axis=-1)
    np.testing.assert_allclose(lengths[0], plan.lengths[0], rtol=0, atol=1e-12)
    steps = np.rint(scene.times / sc.time.step_s).astype(int)
    np.testing.assert_allclose(lengths, plan.lengths[steps], rtol=0, atol=1e-12)  # every instant drawn
    np.testing.assert_array_equal(scene.cables[0, :, 0], sc.robot.frame_anchors + origin)
    np.testing.assert_array_equal(scene.frame_anchors, sc.robot.frame_anchors + origin)
    np.testing.assert_array_equal(scene.frame_origin, origin)


def test_the_platform_outline_is_its_anchors_at_the_first_pose(paper_scene):
    sc, plan, scene = paper_scene
    origin = np.asarray(sc.ship.frame_origin_m)
    R = matrix_from_euler(plan.pose[0, 3:])
    anchors = plan.pose[0, :3] + sc.robot.platform_anchors @ R.T + origin      # x_PC + R p_i, in S
    ends = scene.platform_edges[0].reshape(-1, 3)
    nearest = np.linalg.norm(ends[:, None] - anchors[None], axis=-1).min(axis=1)
    assert nearest.max() < 1e-12                          # every corner of the outline is an anchor
    assert scene.platform_edges.shape[1] == 4             # the paper's platform: a rectangle
    np.testing.assert_allclose(scene.cables[0, :, 1], anchors, rtol=0, atol=1e-12)
    # the path: the plan's centre, decimated, both ends kept
    assert scene.path.shape == (PATH_POINTS_MAX, 3) and plan.n_steps > PATH_POINTS_MAX
    np.testing.assert_array_equal(scene.path[[0, -1]], plan.pose[[0, -1], :3] + origin)
    assert scene.panel is None


def test_without_a_plan_the_trajectory_gives_the_same_scene(paper_scene):
    sc, _, scene = paper_scene
    alone = scene_geometry(sc)  # what the simulate report draws: the scenario's trajectory
    np.testing.assert_allclose(alone.cables, scene.cables, rtol=0, atol=1e-12)
    np.testing.assert_allclose(alone.path, scene.path, rtol=0, atol=1e-12)


def test_the_panel_sits_in_its_plane_in_S():
    sc = marinecdpr.load_scenario("paper_clean")
    short = sc.with_changes(time={"step_s": sc.time.step_s, "duration_s": 2.0})
    scene = scene_geometry(short, marinecdpr.plan(short))
    origin = np.asarray(sc.ship.frame_origin_m)
    xz = np.asarray(sc.cleaning.panel_m)
    expected = np.column_stack([xz[:, 0], np.full(len(xz), sc.trajectory.plane_y_m), xz[:, 1]]) + origin
    np.testing.assert_allclose(scene.panel[:-1], expected, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(scene.panel[-1], scene.panel[0])  # closed
    assert "illustrative" in scene.hull_label                       # its RAOs from a file: no dimensions


def test_the_hull_is_its_box_or_an_illustrative_one():
    rao = SimpleNamespace(length_m=80.0, beam_m=16.0, draught_m=5.0)
    vertices, faces, label = hull_box(SimpleNamespace(type="sea_state", rao=rao))
    np.testing.assert_array_equal(vertices.min(axis=0), [-40.0, -8.0, -5.0])
    np.testing.assert_array_equal(vertices.max(axis=0), [40.0, 8.0, 0.0])   # up to the waterline
    assert faces.shape == (12, 3) and set(faces.ravel()) == set(range(8)) and "main dimensions" in label
    vertices, _, label = hull_box(SimpleNamespace(type="sinusoidal"))
    np.testing.assert_array_equal(np.ptp(vertices, axis=0), DEFAULT_HULL_M)
    assert "illustrative" in label
    assert list(sample_steps(5, 10)) == [0, 1, 2, 3, 4] and list(sample_steps(101, 3)) == [0, 50, 100]


# ------------------------------------------------------------ in a browser
class _ViewFinder(HTMLParser):
    """Canvases inside the plot div, its legend's texts and all its text, of a rendered DOM."""

    def __init__(self, div_id: str):
        super().__init__()
        self.div_id, self.depth, self.canvases, self.gl, self.legend, self._in_legend = div_id, 0, 0, 0, [], False
        self.text: list[str] = []

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if self.depth == 0 and tag == "div" and a.get("id") == self.div_id:
            self.depth = 1
        elif self.depth and tag == "div":
            self.depth += 1
        if not self.depth:
            return
        self.canvases += tag == "canvas"
        self.gl += "gl-container" in (a.get("class") or "").split()
        self._in_legend = tag == "text" and "legendtext" in (a.get("class") or "")

    def handle_endtag(self, tag):
        if self.depth and tag == "div":
            self.depth -= 1
        self._in_legend = False

    def handle_data(self, data):
        if self.depth:
            self.text.append(data)
        if self._in_legend:
            self.legend.append(data)


def _chromium(tmp_path: Path, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run([CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
                           "--use-gl=swiftshader", "--enable-unsafe-swiftshader", "--hide-scrollbars",
                           f"--user-data-dir={tmp_path / 'profile'}", "--virtual-time-budget=10000", *args],
                          capture_output=True, text=True, timeout=60)


@needs_chromium
def test_a_headless_browser_draws_the_simulate_reports_view(tmp_path):
    out = tmp_path / "sim"
    res = runner.invoke(app, ["simulate", "paper", "--duration", "0.05", "--plant", "own", "--out", str(out)])
    assert res.exit_code == 0, res.output
    page = (out / "report.html").read_text()
    assert f"<h2>{SECTION_TITLE}</h2>" in page and page.index("<h2>Figures</h2>") < page.index(SECTION_TITLE)
    assert "<script src" not in page and 'charset="utf-8" src=' not in page  # the JS inlined: no network
    run = _chromium(tmp_path, "--dump-dom", (out / "report.html").as_uri())
    assert run.returncode == 0, run.stderr[-2000:]
    found = _ViewFinder("view3d")
    found.feed(run.stdout)
    assert found.gl >= 1 and found.canvases >= 1, "plotly drew no WebGL scene"
    assert "WebGL" not in " ".join(found.text)  # plotly's words where it cannot draw
    for name in TRACES + ("hull: illustrative (100 x 20 x 6 m box)",):
        assert name in found.legend, (name, found.legend)


@needs_chromium
def test_a_screenshot_of_the_view_shows_its_cables(paper_scene, tmp_path):
    sc, plan, scene = paper_scene
    page = tmp_path / "view.html"
    page.write_text("<!doctype html><html><head><meta charset='utf-8'></head><body style='margin:0'>"
                    + scene_html(scene, title="paper on its ship", include_js=True) + "</body></html>")
    shot = tmp_path / "view3d.png"
    run = _chromium(tmp_path, "--window-size=1200,900", f"--screenshot={shot}", page.as_uri())
    assert run.returncode == 0 and shot.exists(), run.stderr[-2000:]
    from PIL import Image

    rgb = np.asarray(Image.open(shot).convert("RGB")).astype(int)
    assert rgb.shape[:2] == (900, 1200) and len(np.unique(rgb.reshape(-1, 3), axis=0)) > 1  # not blank
    # the cables' red (#d62728) in the WebGL scene, right of the legend's (SVG) line samples
    red = (np.abs(rgb - [214, 39, 40]).sum(axis=-1) < 60)[:, 300:]
    assert red.sum() > 200, red.sum()
    if RESEARCH.is_dir():
        shutil.copyfile(shot, RESEARCH / "view3d.png")


# ------------------------------------------------------------ the pages
def test_the_report_changes_only_by_the_section(paper_scene, tmp_path, monkeypatch):
    sc, plan, scene = paper_scene
    summary = _summary(tmp_path)
    with_view = text.write_report_html(summary, sc, {}, tmp_path / "a.html", plan=plan).read_text()
    again = text.write_report_html(summary, sc, {}, tmp_path / "b.html", plan=plan).read_text()
    assert with_view == again  # the same run writes the same page
    section = text.view_section(sc, plan)
    monkeypatch.setattr(text, "view_section", lambda *args, **kwargs: "")
    without = text.write_report_html(summary, sc, {}, tmp_path / "c.html", plan=plan).read_text()
    assert with_view.count(section) == 1 and with_view.replace(section, "") == without
    assert section.count("Plotly.newPlot") == 1 and section.count("plotly.js v") == 1  # the JS once
    assert scene_html(scene, title="t", include_js=False).count("plotly.js v") == 0


def _summary(tmp_path: Path):
    import json

    out = tmp_path / "s"
    res = runner.invoke(app, ["simulate", "paper", "--duration", "0.05", "--plant", "own", "--out", str(out)])
    assert res.exit_code == 0, res.output
    from marinecdpr.studies.prototype_runs import PrototypeFigures

    return PrototypeFigures.from_json(json.loads((out / "summary.json").read_text()))


def test_the_clean_report_holds_the_view(tmp_path):
    out = tmp_path / "clean"
    res = runner.invoke(app, ["clean", "paper_clean", "--duration", "0.2", "--no-compare", "--plant", "own",
                              "--out", str(out)])
    assert res.exit_code == 0, res.output
    page = (out / "report.html").read_text()
    assert f"<h2>{SECTION_TITLE}</h2>" in page and 'id="view3d"' in page and page.count("Plotly.newPlot") == 1
    assert page.index("<h2>Figures</h2>") < page.index(SECTION_TITLE) < page.index("</body>")
    assert '"name":"panel"' in page and '"name":"cables"' in page and "the panel;" in page


# -------------------- formerly tests/test_view3d_axes.py

"""The 3D view's axes (issue 37, item 13): a planar robot's flat axis (every point at one y)
is drawn at a readable depth, not squashed to a sliver with its ticks crowded; every axis at
one scale."""

import json
import re

import numpy as np
import pytest

import marinecdpr
LEAST_AXIS_SHARE = 0.35
from marinecdpr.report.view3d import scene_geometry, scene_html


def _scene_layout(html: str) -> dict:
    # the layout plotly writes: Plotly.newPlot(id, data, layout, config)
    call = html[html.index("Plotly.newPlot("):]
    decoder = json.JSONDecoder()
    i = call.index("[")
    _, end = decoder.raw_decode(call, i)
    layout, _ = decoder.raw_decode(call, call.index("{", end))
    return layout["scene"]


@pytest.mark.parametrize("name", ["paper", "paper_clean"])
def test_a_planar_robot_s_flat_axis_keeps_a_readable_depth_at_one_scale(name):
    sc = marinecdpr.load_scenario(name)
    scene = scene_geometry(sc)
    assert np.ptp(scene.frame_anchors[:, 1]) == 0.0  # planar: the frame's anchors all at one y in S
    view = _scene_layout(scene_html(scene, title=name, include_js=False))
    spans = np.array([np.ptp(view[f"{a}axis"]["range"]) for a in "xyz"])
    ratio = np.array([view["aspectratio"][a] for a in "xyz"])
    assert spans[1] >= LEAST_AXIS_SHARE * spans.max() * (1 - 1e-12)  # was 0.2 of it: a sliver
    assert ratio / ratio.max() == pytest.approx(spans / spans.max(), rel=1e-12)  # one scale on every axis
    # the points all inside their ranges
    pts = np.concatenate([scene.frame_anchors, scene.path, scene.cables.reshape(-1, 3)])
    for k, a in enumerate("xyz"):
        lo, hi = view[f"{a}axis"]["range"]
        assert lo <= pts[:, k].min() and pts[:, k].max() <= hi


def test_a_frame_carried_on_a_rail_is_drawn_where_the_carriage_holds_it():
    """A frame on a straight rail along S's x (issue 39): at the first instant it stands at the
    rail's start, at the last (after the move, dwelling) 2 m further along x, every edge moved
    by exactly that; the cables still run from its anchors at the plan's lengths; the rail and
    the moving frame are drawn."""
    sc = marinecdpr.load_scenario("paper").with_changes(
        ship={"carriage": {"rail_m": [[-0.78, 0.0, 2.2], [20.0, 0.0, 2.2]], "speed_max_m_s": 1.0,
                           "accel_max_m_s2": 1.0, "jerk_max_m_s3": 5.0, "stations_m": [0.0, 2.0], "dwell_s": 1.0}},
        time={"step_s": 0.001, "duration_s": 8.0})
    plan = marinecdpr.plan(sc)
    scene = scene_geometry(sc, plan)
    first, last = scene.frame_moves[0], scene.frame_moves[-1]
    assert np.abs(first - scene.frame_edges).max() == 0.0
    assert np.abs(scene.frame_origin - [-0.78, 0.0, 2.2]).max() < 1e-15
    assert np.abs(last - first - [2.0, 0.0, 0.0]).max() < 1e-14
    lengths = np.linalg.norm(scene.cables[:, :, 1] - scene.cables[:, :, 0], axis=-1)
    at = np.rint(scene.times / sc.time.step_s).astype(int)
    assert np.abs(lengths - plan.lengths[at]).max() < 1e-12
    assert scene.rail[0] == pytest.approx([-0.78, 0.0, 2.2]) and scene.rail[-1] == pytest.approx([20.0, 0.0, 2.2])
    page = scene_html(scene, title="rail", include_js=False)
    assert "rail (C&#x27;s origin)" in page or "rail (C's origin)" in page
