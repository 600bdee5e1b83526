"""Surfaces to clean from the hull (issue 23, item 2): a curved band of the hull tiled into
frame placements within the tool's stand-off tolerance, and the hours from the placements."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

import marinecdpr
from marinecdpr.cli.app import app
from marinecdpr.errors import ScenarioError
from marinecdpr.geometry.surface import MIN_PATCH_M, patch_points, tile_surface
from marinecdpr.motion.trajectory import cleaning_path
from marinecdpr.scenario.cleaning import Cleaning
from marinecdpr.studies.surface import surface_function, surface_job
from tests.conftest import one_line_exit_2

runner = CliRunner()
BUILTIN = Path(marinecdpr.__file__).parent / "scenario" / "builtin"


@pytest.fixture(scope="module")
def paper_clean():
    return marinecdpr.load_scenario("paper_clean")


@pytest.fixture(scope="module")
def paper_clean_job(paper_clean):
    return surface_job(paper_clean, move_time_s=600.0)


def _dense_deviation(f, p, n=41) -> float:
    """The surface's largest distance from a placement's plane over n x n points of its patch."""
    P = patch_points(f, p.x_range, p.z_range, n).reshape(-1, 3)
    return float(np.abs((P - p.centre_S) @ p.normal_S).max())


def test_a_tilted_plane_is_tiled_as_worked_by_hand():
    """y = 5 + 0.2 z over x in [0, 10], z in [0, 4], a 2.5 x 2 m panel: along x the middle line
    is 10 m long, cut into ceil(10 / (0.98 2.5)) = 5 pieces of 2 m; up the plane it is
    4 sqrt(1.04) = 4.079 m, cut into ceil(4.079 / 1.96) = 3 pieces of 4/3 m of z. 15 flat
    patches, normal (0, 1, -0.2) / sqrt(1.04), each 2 x 4/3 sqrt(1.04) in its plane."""
    placements, bad = tile_surface(lambda X, Z: 5.0 + 0.2 * np.asarray(Z), (0.0, 10.0), (0.0, 4.0),
                                   width_m=2.5, height_m=2.0, tolerance_m=0.01)
    assert bad == [] and len(placements) == 15
    k = np.sqrt(1.04)
    for p in placements:
        assert p.x_range[1] - p.x_range[0] == pytest.approx(2.0, abs=1e-12)
        assert p.z_range[1] - p.z_range[0] == pytest.approx(4.0 / 3.0, abs=1e-12)
        np.testing.assert_allclose(p.normal_S, [0.0, 1.0 / k, -0.2 / k], atol=1e-14)
        np.testing.assert_allclose(p.extent_m, [2.0, 4.0 / 3.0 * k], rtol=1e-12)
        assert p.area_m2 == pytest.approx(2.0 * 4.0 / 3.0 * k, rel=1e-12)
        assert p.deviation_m < 1e-14
        # the frame's axes: x along the ship, y the normal, z = x cross y up the plane
        np.testing.assert_allclose(p.axes_S @ p.axes_S.T, np.eye(3), atol=1e-14)
        np.testing.assert_allclose(p.axes_S[:, 2], [0.0, 0.2 / k, 1.0 / k], atol=1e-14)
    first = placements[0]
    np.testing.assert_allclose(first.centre_S, [1.0, 5.0 + 0.2 * 2.0 / 3.0, 2.0 / 3.0], atol=1e-13)
    assert sum(p.area_m2 for p in placements) == pytest.approx(40.0 * k, rel=1e-12)


def test_every_placement_stays_within_the_stand_off_tolerance_between_its_samples(paper_clean, paper_clean_job):
    """The flared Wigley side of paper_clean, sampled 41 x 41 per placement (the tiling looks
    at 9 x 9); and a tighter tolerance that forces splits, on a tumbling-home bilge band (6 m
    of it along the ship, its whole 17 m of height: 509 placements in 127 sizes, the largest
    dense deviation 1.80 mm; 30 m gave 2334 placements and 1.80 mm, in 4.6 times the time)."""
    f, _ = surface_function(paper_clean.cleaning.surface)
    tol = paper_clean.cleaning.surface.stand_off_tolerance_m
    worst = max(_dense_deviation(f, p) for p in paper_clean_job.placements)
    assert worst <= tol
    assert worst == pytest.approx(paper_clean_job.summary()["largest_stand_off_deviation_m"], rel=1e-9)
    bilge = paper_clean.with_updates("cleaning.surface", flare=-0.5, heights_m=[-9.0, 8.0], stations_m=[-90.0, -84.0],
                                     stand_off_tolerance_m=0.002)
    sj = surface_job(bilge, move_time_s=600.0)
    fb, _ = surface_function(bilge.cleaning.surface)
    sizes = {(round(p.x_range[1] - p.x_range[0], 6), round(p.z_range[1] - p.z_range[0], 6)) for p in sj.placements}
    assert len(sizes) > 3  # patches were halved where the bilge curves
    assert max(_dense_deviation(fb, p) for p in sj.placements) <= 0.002
    assert sj.uncleanable == []


def test_the_placements_partition_the_band_and_sum_to_its_curved_area(paper_clean, paper_clean_job):
    """The patches' station-height rectangles add up to the band's and do not overlap; their
    curved areas add up to the band's area by an independent integral of sqrt(1 + f_x^2 + f_z^2)."""
    s = paper_clean.cleaning.surface
    P = paper_clean_job.placements
    rect = sum((p.x_range[1] - p.x_range[0]) * (p.z_range[1] - p.z_range[0]) for p in P)
    assert rect == pytest.approx((s.stations_m[1] - s.stations_m[0]) * (s.heights_m[1] - s.heights_m[0]), rel=1e-12)
    centres = np.array([[0.5 * sum(p.x_range), 0.5 * sum(p.z_range)] for p in P])
    for p in P[::97]:  # no other patch holds this one's centre
        inside = ((centres[:, 0] > p.x_range[0]) & (centres[:, 0] < p.x_range[1])
                  & (centres[:, 1] > p.z_range[0]) & (centres[:, 1] < p.z_range[1]))
        assert inside.sum() == 1
    L, B, T, flare = s.length_m, s.beam_m, s.draught_m, s.flare
    x = np.linspace(*s.stations_m, 4001)
    z = np.linspace(*s.heights_m, 801)
    X, Z = np.meshgrid(x, z, indexing="ij")
    f_x = 0.5 * B * (-8.0 * X / L**2) * (1.0 + flare * (Z / T) ** 2)
    f_z = 0.5 * B * (1.0 - (2.0 * X / L) ** 2) * 2.0 * flare * Z / T**2
    from scipy.integrate import trapezoid

    area = trapezoid(trapezoid(np.sqrt(1.0 + f_x**2 + f_z**2), z, axis=1), x)
    assert paper_clean_job.area_m2 == pytest.approx(area, rel=2e-6)


def test_hours_are_the_sum_of_the_placements_and_the_moves(paper_clean, paper_clean_job):
    """Each placement's time is the coverage path's over a rectangle of its extent; the job's
    seconds are their sum and (n - 1) moves (another move time moves the hours by exactly
    that: on the band's 15 m at the stern, tiled twice)."""
    sj = paper_clean_job
    data = paper_clean.cleaning.model_dump(exclude_none=True)
    data.pop("surface")
    for i in (0, len(sj.placements) // 2, len(sj.placements) - 1):
        u, v = sj.placements[i].extent_m
        u, v = round(u, 3), round(v, 3)
        panel = Cleaning.model_validate(data | {"panel_m": [[0.0, 0.0], [u, 0.0], [u, v], [0.0, v]], "holes_m": []})
        assert sj.job_s[i] == cleaning_path(panel).duration_s
    n = len(sj.placements)
    assert sj.hours * 3600.0 == pytest.approx(float(sum(sj.job_s)) + (n - 1) * 600.0, rel=1e-14)
    stern = paper_clean.with_updates("cleaning.surface", stations_m=[-95.0, -80.0])
    slow, moves = surface_job(stern, move_time_s=600.0), surface_job(stern, move_time_s=300.0)
    m = len(slow.placements)
    assert m == len(moves.placements) > 100 and np.array_equal(slow.job_s, moves.job_s)
    assert (slow.hours - moves.hours) * 3600.0 == pytest.approx((m - 1) * 300.0, rel=1e-12)


def test_hours_fall_as_the_frame_grows_until_the_curvature_limits_it(paper_clean, paper_clean_job):
    """Doubling the frame's panel each way: fewer placements and hours each time, the curved
    area cleaned the band's. From 1.3 x 0.8 m to 2.6 x 1.6 m the patches are set by the panel
    (about a quarter of the placements: 3.45); from there to 5.2 x 3.2 m by the flare's
    curvature against the 1 cm tolerance, which a 5 cm tolerance lifts."""
    jobs = [paper_clean_job] + [surface_job(paper_clean, move_time_s=600.0, panel_m=(1.3 * k, 0.8 * k)) for k in (2, 4)]
    n = [len(j.placements) for j in jobs]
    hours = [j.hours for j in jobs]
    assert n[0] > n[1] > n[2] and hours[0] > hours[1] > hours[2]
    assert 3.0 < n[0] / n[1] < 4.0 and n[1] / n[2] < 1.5
    for j in jobs[1:]:
        assert j.area_m2 == pytest.approx(jobs[0].area_m2, rel=1e-5)
        assert max(p.extent_m[0] for p in j.placements) <= j.frame_panel_m[0] * (1 + 1e-9)
        assert max(p.extent_m[1] for p in j.placements) <= j.frame_panel_m[1] * (1 + 1e-9)
    tol = paper_clean.cleaning.surface.stand_off_tolerance_m
    assert np.median([p.deviation_m for p in jobs[2].placements]) > 0.5 * tol  # curvature-limited
    # the looser tolerance's placements: the tiling's alone (surface_job's placements; no hours asserted)
    s = paper_clean.cleaning.surface
    n_loose = [len(tile_surface(surface_function(s)[0], s.stations_m, s.heights_m, width_m=1.3 * k, height_m=0.8 * k,
                                tolerance_m=0.05)[0]) for k in (2, 4)]
    assert 3.0 < n_loose[0] / n_loose[1] < 4.0


def test_a_surface_curved_beyond_the_tolerance_is_reported_uncleanable():
    """A ridge y = 10 - 0.5 |z - 0.9| bends at z = 0.9: a plane fitted over a patch holding the
    bend departs from it by about 0.5 dz / 8, over 1 mm unless dz < 16 mm. The patches along it
    are cut to the smallest height and reported; the rest are kept, flat."""
    placements, bad = tile_surface(lambda X, Z: 10.0 - 0.5 * np.abs(np.asarray(Z) - 0.9), (0.0, 2.0), (0.0, 2.0),
                                   width_m=1.0, height_m=1.0, tolerance_m=0.001)
    assert bad and placements
    for p in bad:
        assert p.z_range[0] < 0.9 < p.z_range[1]
        assert p.z_range[1] - p.z_range[0] < 2 * MIN_PATCH_M
    assert all(not (p.z_range[0] < 0.9 < p.z_range[1]) for p in placements)
    assert all(p.deviation_m < 1e-12 for p in placements)
    rect = sum((p.x_range[1] - p.x_range[0]) * (p.z_range[1] - p.z_range[0]) for p in placements + bad)
    assert rect == pytest.approx(4.0, rel=1e-12)


def test_a_mesh_side_gives_the_analytic_form_s_placements(tmp_path, paper_clean):
    """The Wigley hull meshed in 1 m panels (write_wigley_gdf) read as form = "mesh": below the
    waterline its faceted side gives the analytic form's area within 0.1 % and nearly the same
    placements (a few more: the facets kink)."""
    pytest.importorskip("capytaine")
    from marinecdpr.motion.hullmesh import write_wigley_gdf

    gdf = write_wigley_gdf(tmp_path / "w.gdf", length_m=100.0, beam_m=20.0, draught_m=6.0, panel_m=1.0)
    band = dict(stations_m=[-40.0, 40.0], heights_m=[-5.0, -0.5], stand_off_tolerance_m=0.02)
    analytic = paper_clean.with_updates("cleaning.surface", length_m=100.0, beam_m=20.0, draught_m=6.0, flare=0.0,
                                        **band)
    meshed = paper_clean.with_updates("cleaning.surface", form="mesh", mesh=str(gdf), length_m=None, beam_m=None,
                                      draught_m=None, flare=None, **band)
    s = analytic.cleaning.surface  # the analytic form's placements: the tiling's alone (surface_job's; no hours asserted)
    a = tile_surface(surface_function(s)[0], s.stations_m, s.heights_m, width_m=2.0, height_m=1.5,
                     tolerance_m=s.stand_off_tolerance_m)[0]
    m = surface_job(meshed, move_time_s=600.0, panel_m=(2.0, 1.5))
    assert m.area_m2 == pytest.approx(sum(p.area_m2 for p in a), rel=1e-3)
    # the faceted side kinks between its 1 m panels: a few more patches are cut
    assert len(a) <= len(m.placements) <= 1.15 * len(a)
    f, _ = surface_function(meshed.cleaning.surface)
    assert max(_dense_deviation(f, p) for p in m.placements) <= 0.02
    off = meshed.with_updates("cleaning.surface", heights_m=[-5.0, 2.0])  # above the mesh's top
    with pytest.raises(ScenarioError, match="the band leaves the mesh"):
        surface_job(off, move_time_s=600.0)


@pytest.mark.figures
def test_clean_surface_writes_the_placements_and_their_hours(tmp_path, monkeypatch):
    """The figures of docs/cleaning.md for paper_clean's band: 2 660 placements, 497 h with moves of 600 s;
    the frame (1.9 x 1.4 m, its anchors' extent) and the panel it cleans (1.3 x 0.8 m) each
    called by its name, in the line and in surface.png's title (issue 37, item 7)."""
    import marinecdpr.report.cleaning as cleaning_report

    titles = {}
    real_save = cleaning_report._save

    def keep_title(fig, path, dpi=None):
        titles[Path(path).name] = fig._suptitle.get_text() if fig._suptitle is not None else None
        return real_save(fig, path)

    monkeypatch.setattr(cleaning_report, "_save", keep_title)
    out = tmp_path / "o"
    res = runner.invoke(app, ["clean", "paper_clean", "--surface", "--duration", "0.2", "--no-compare",
                              "--out", str(out)])
    assert res.exit_code == 0, res.output
    u = json.loads((out / "summary.json").read_text())["surface"]
    assert u["placements"] == 2660 and round(u["hours"], 1) == 497.3 and round(u["cleaning_hours"]) == 54
    assert round(u["area_m2"]) == 2350 and round(u["area_rate_m2_h"], 1) == 4.7
    assert ("2660 placements of the 1.9 x 1.4 m frame, each cleaning its 1.3 x 0.8 m panel, 2350 m2: 497.3 h "
            "(54.11 h cleaning") in res.stdout
    assert titles["surface.png"].startswith("2660 placements of the frame, each cleaning its 1.3 x 0.8 m panel: "
                                            "497.3 h")
    rows = np.loadtxt(out / "placements.csv", delimiter=",", skiprows=1, comments="#")
    assert rows.shape == (2660, 17) and (rows[:, -1] == 1).all()
    assert (rows[:, 15].sum() + 2659 * 600.0) / 3600.0 == pytest.approx(u["hours"], rel=1e-9)
    np.testing.assert_allclose(np.linalg.norm(rows[:, 7:10], axis=1), 1.0, atol=1e-9)
    assert (out / "surface.png").stat().st_size > 10_000


def _paper_clean_file(tmp_path: Path, surface: str | None) -> Path:
    """paper_clean.toml with its [cleaning.surface] replaced, beside the files it reads."""
    for data in BUILTIN.glob("*.csv"):
        shutil.copy(data, tmp_path / data.name)
    text = (BUILTIN / "paper_clean.toml").read_text()
    head, rest = text.split("[cleaning.surface]", 1)
    tail = rest[rest.index("\n[", 1):]
    path = tmp_path / "job.toml"
    path.write_text(head + (surface or "") + tail)
    return path


@pytest.mark.parametrize("surface, flags, words", [
    (None, ["--surface"], ["cleaning.surface: missing"]),
    ('[cleaning.surface]\nform = "wigley"\nlength_m = 200.0\nbeam_m = 32.0\ndraught_m = 10.0\n'
     'stations_m = [10.0, -10.0]\nheights_m = [0.0, 5.0]\nstand_off_tolerance_m = 0.01\n', ["--surface"],
     ["cleaning.surface.stations_m", "low < high"]),
    ('[cleaning.surface]\nform = "mesh"\nmesh = "nowhere.gdf"\nstations_m = [-1.0, 1.0]\nheights_m = [0.0, 1.0]\n'
     'stand_off_tolerance_m = 0.01\n', ["--surface"], ["cleaning.surface.mesh", "no such file"]),
    ('[cleaning.surface]\nform = "wigley"\nlength_m = 200.0\nbeam_m = 32.0\ndraught_m = 10.0\n'
     'stations_m = [-100.0, 10.0]\nheights_m = [0.0, 5.0]\nstand_off_tolerance_m = 0.01\n', ["--surface"],
     ["cleaning.surface.stations_m", "within the hull's length"]),
    ("", ["--surface", "--hull-area", "2200"], ["--surface with --hull-area 2200: choose one"]),
    ("", ["--surface", "--seas"], ["--surface with --seas: cannot go together yet"]),
])
def test_clean_surface_refuses_bad_input_in_one_line(tmp_path, surface, flags, words):
    scen = BUILTIN / "paper_clean.toml" if surface == "" else _paper_clean_file(tmp_path, surface)
    res = runner.invoke(app, ["clean", str(scen), *flags, "--duration", "0.1", "--out", str(tmp_path / "o")])
    one_line_exit_2(res, *words)
    assert not (tmp_path / "o").exists()


# -------------------- formerly tests/test_mesh_side.py

"""A hull mesh's side as a surface y = f(x, z) (:func:`marinecdpr.geometry.surface.mesh_side`):
its binned search against every triangle tested for every point."""


import numpy as np
import pytest

from marinecdpr.geometry.surface import mesh_side
from marinecdpr.motion.hullmesh import faces_to_triangles, read_mesh, write_wigley_gdf


def _every_triangle(vertices, triangles, side, x, z):
    """The outermost |y| over every triangle facing ``side`` whose x-z projection holds each
    point (the same barycentric test and tolerance), one point at a time."""
    sign = 1.0 if side == "port" else -1.0
    out = np.full(len(x), np.nan)
    for i, (px, pz) in enumerate(zip(x, z)):
        for tri in triangles:
            a, b, c = (np.asarray(vertices[j], dtype=float) for j in tri)
            if sign * np.cross(b - a, c - a)[1] <= 0:
                continue
            det = (b[0] - a[0]) * (c[2] - a[2]) - (c[0] - a[0]) * (b[2] - a[2])
            if abs(det) <= 1e-15:
                continue
            l1 = ((px - a[0]) * (c[2] - a[2]) - (c[0] - a[0]) * (pz - a[2])) / det
            l2 = ((b[0] - a[0]) * (pz - a[2]) - (px - a[0]) * (b[2] - a[2])) / det
            if l1 >= -1e-12 and l2 >= -1e-12 and l1 + l2 <= 1 + 1e-12:
                y = sign * (a[1] + l1 * (b[1] - a[1]) + l2 * (c[1] - a[1]))
                out[i] = y if np.isnan(out[i]) else max(out[i], y)
    return out


@pytest.mark.parametrize("side", ["port", "starboard"])
def test_the_binned_search_finds_what_every_triangle_finds(tmp_path, side):
    """A Wigley hull in 4 m panels, at random points, at its vertices and its edges'
    midpoints (where a point lies on several triangles' boundaries and the tolerance decides):
    the same values, bit for bit, as testing every triangle; NaN off the side."""
    v, faces = read_mesh(write_wigley_gdf(tmp_path / "w.gdf", length_m=60.0, beam_m=12.0, draught_m=5.0, panel_m=4.0))
    tri = faces_to_triangles(faces)
    rng = np.random.default_rng(7)
    mid = 0.5 * (v[tri[:, 0]] + v[tri[:, 1]])
    x = np.concatenate([rng.uniform(-32.0, 32.0, 150), v[::3, 0], mid[::5, 0]])
    z = np.concatenate([rng.uniform(-6.0, 1.0, 150), v[::3, 2], mid[::5, 2]])
    got = mesh_side(v, tri, side=side)(x, z)
    want = _every_triangle(v, tri, side, x, z)
    assert np.array_equal(got, want, equal_nan=True)
    assert np.isnan(got).sum() > 10 and np.isfinite(got).sum() > 100  # both kinds of point were asked


def test_overlapping_triangles_give_the_outermost_and_shapes_are_kept():
    """Two port-facing triangles over the same x-z square at y = 1 and y = 3 (the outer
    wins), one facing starboard at y = 5 (ignored), a degenerate one: by hand."""
    v = np.array([[0, 1, 0], [0, 1, 1], [1, 1, 0],     # port-facing at y = 1
                  [0, 3, 0], [0, 3, 1], [1, 3, 0],     # port-facing at y = 3
                  [0, 5, 0], [1, 5, 0], [0, 5, 1],     # facing starboard
                  [0, 9, 0], [1, 9, 0], [2, 9, 0]], dtype=float)  # no area in x-z
    tri = np.arange(12).reshape(4, 3)
    f = mesh_side(v, tri, side="port")
    X = np.array([[0.2, 0.9], [0.5, np.nan]])
    Z = np.array([[0.2, 0.9], [0.5, 0.0]])
    got = f(X, Z)
    assert got.shape == (2, 2)
    np.testing.assert_array_equal(got, [[3.0, np.nan], [3.0, np.nan]])
    np.testing.assert_array_equal(mesh_side(v, tri, side="starboard")(0.2, 0.2), -5.0)


# -------------------- formerly tests/test_surface_limits.py

"""``[cleaning.surface]`` and ``clean --surface`` refuse what cannot be a job before the work
(issue 37, items 17 and 18): a band too large to tile (counted from its first grid before a
patch is fitted), a tool's stand-off tolerance below a millimetre, a tumblehome side past the
centreline, a move time that makes the hours infinite; they never write a non-finite figure;
a long tiling says how far it is."""


import csv
import shutil
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

import marinecdpr
from marinecdpr.cli.app import app
from marinecdpr.errors import ScenarioError
from marinecdpr.geometry.surface import first_grid, tile_surface
from marinecdpr.report.cleaning import write_surface
from marinecdpr.scenario.loading import load_scenario
from marinecdpr.studies.surface import (
    MAX_SURFACE_PATCHES, MOVE_TIME_MAX_S, SurfaceJob, check_move_time, surface_job, surface_patches,
)
from tests.conftest import one_line_exit_2

runner = CliRunner()
BUILTIN = Path(marinecdpr.__file__).parent / "scenario" / "builtin"


def _scenario(tmp_path: Path, **changes: str) -> Path:
    """paper_clean.toml with keys of its [cleaning.surface] changed, beside its RAO file."""
    text = (BUILTIN / "paper_clean.toml").read_text()
    head, surface = text.split("[cleaning.surface]", 1)
    for key, value in changes.items():
        lines = surface.splitlines()
        i = next(k for k, ln in enumerate(lines) if ln.startswith(f"{key} = "))
        lines[i] = f"{key} = {value}"
        surface = "\n".join(lines) + "\n"
    shutil.copy(BUILTIN / "paper_sea_rao.csv", tmp_path / "paper_sea_rao.csv")
    path = tmp_path / "job.toml"
    path.write_text(head + "[cleaning.surface]" + surface)
    return path


def flat(X, Z):
    return 5.0 + 0.0 * np.asarray(X) * np.asarray(Z)


def test_the_first_grid_is_counted_as_worked_by_hand():
    """A flat side 10 m by 4 m with a 1 x 1 m panel: ceil(10 / 0.98) = 11 stations' pieces and
    ceil(4 / 0.98) = 5 heights', 55 patches, which the tiling keeps whole (flat: no cut)."""
    xs, zs = first_grid(flat, (0.0, 10.0), (0.0, 4.0), width_m=1.0, height_m=1.0)
    np.testing.assert_allclose(xs, np.linspace(0.0, 10.0, 12), atol=1e-12)
    np.testing.assert_allclose(zs, np.linspace(0.0, 4.0, 6), atol=1e-12)
    placements, bad = tile_surface(flat, (0.0, 10.0), (0.0, 4.0), width_m=1.0, height_m=1.0, tolerance_m=0.01)
    assert len(placements) == 55 and not bad
    with pytest.raises(ScenarioError, match=r"the band needs 55 patches of the 1 x 1 m panel, more than the 54 a run"):
        first_grid(flat, (0.0, 10.0), (0.0, 4.0), width_m=1.0, height_m=1.0, max_patches=54)


def test_a_band_too_large_is_refused_before_a_patch_is_fitted(tmp_path, monkeypatch):
    """heights_m = [0, 200] on paper_clean's 200 m Wigley side: its first grid alone counts
    855 040 patches of the 1.3 x 0.8 m panel (the side flares out to 1 296 m from the
    centreline at 200 m: 80 times the half-beam), refused at once; no patch is fitted."""
    import marinecdpr.geometry.surface as gs

    sc = load_scenario(_scenario(tmp_path, heights_m="[0.0, 200.0]"))
    monkeypatch.setattr(gs, "_fit", lambda *a: pytest.fail("a patch was fitted"))
    with pytest.raises(ScenarioError) as err:
        surface_job(sc, move_time_s=600.0)
    assert err.value.key == "cleaning.surface"
    assert f"needs 855,040 patches of the 1.3 x 0.8 m panel, more than the {MAX_SURFACE_PATCHES:,}" in str(err.value)
    with pytest.raises(ScenarioError, match="855,040"):
        surface_patches(sc)
    res = runner.invoke(app, ["clean", str(tmp_path / "job.toml"), "--surface", "--duration", "0.1",
                              "--out", str(tmp_path / "o")])
    one_line_exit_2(res, "cleaning.surface: the band needs 855,040 patches")
    assert not (tmp_path / "o").exists()


def test_paper_clean_s_band_is_within_the_budget_as_counted():
    """paper_clean's band: 2 584 patches in its first grid, which the tiling ends with
    2 660 placements (its cuts)."""
    assert surface_patches(load_scenario("paper_clean")) == 2584 < MAX_SURFACE_PATCHES


def test_pieces_cut_beyond_the_budget_are_refused():
    """The ridge of test_issue23_surface: 4 patches in the first grid, cut along the bend to
    the smallest height; a budget of 10 fits stops the cutting with the count."""
    ridge = lambda X, Z: 10.0 - 0.5 * np.abs(np.asarray(Z) - 0.9)  # noqa: E731
    with pytest.raises(ScenarioError, match="the band curves so that cutting it into patches flat enough for the "
                                            "tolerance passed the 10 a run may fit"):
        tile_surface(ridge, (0.0, 2.0), (0.0, 2.0), width_m=1.0, height_m=1.0, tolerance_m=0.001, max_patches=10)


def test_the_tiling_s_progress_rises_to_the_whole_band():
    """The progress is the settled share of the band's stations x heights: it never falls and
    ends at 1 (the kept and uncleanable patches partition the band)."""
    ridge = lambda X, Z: 10.0 - 0.5 * np.abs(np.asarray(Z) - 0.9)  # noqa: E731
    shares: list[float] = []
    placements, bad = tile_surface(ridge, (0.0, 2.0), (0.0, 2.0), width_m=0.1, height_m=0.1, tolerance_m=0.001,
                                   progress=shares.append)
    assert bad and len(shares) >= 3
    assert all(b >= a for a, b in zip(shares, shares[1:]))
    assert shares[0] == 0.0 and shares[-1] == pytest.approx(1.0, abs=1e-12)


@pytest.mark.parametrize("changes, key, words", [
    ({"stand_off_tolerance_m": "1e-9"}, "cleaning.surface.stand_off_tolerance_m", "between 0.001 and 1 m"),
    ({"stand_off_tolerance_m": "0.0"}, "cleaning.surface.stand_off_tolerance_m", "between 0.001 and 1 m"),
    ({"flare": "-1.0", "heights_m": "[0.0, 20.0]"}, "cleaning.surface.heights_m",
     "must stay below 10 m, where the side tumbling home (flare -1) meets the centreline, got 20"),
    ({"flare": "-0.25", "heights_m": "[0.0, 20.0]"}, "cleaning.surface.heights_m", "must stay below 20 m"),
])
def test_impossible_surfaces_are_refused_as_the_scenario_loads(tmp_path, changes, key, words):
    """A tool cannot hold a nanometre of stand-off; a Wigley side with flare f < 0 meets the
    centreline at z = T / sqrt(-f) (1 + f z^2 / T^2 = 0): T = 10 m, f = -1 at 10 m, f = -0.25
    at 20 m (the band's top on it is refused too: no breadth there)."""
    with pytest.raises(ScenarioError) as err:
        load_scenario(_scenario(tmp_path, **changes))
    assert err.value.key == key and words in str(err.value)


def test_a_tumblehome_band_below_the_crossing_is_kept(tmp_path):
    sc = load_scenario(_scenario(tmp_path, flare="-0.25", heights_m="[0.0, 19.9]"))
    assert sc.cleaning.surface.heights_m == (0.0, 19.9)


def test_a_design_study_s_tolerance_below_a_millimetre_is_refused():
    from marinecdpr.scenario.design import Limits

    with pytest.raises(ValueError, match="between 0.001 and 1 m"):
        Limits.model_validate({"stand_off_tolerance_m": 1e-9})


@pytest.mark.parametrize("move", [1e308, MOVE_TIME_MAX_S * 1.0001, -1.0, float("nan"), float("inf")])
def test_a_move_time_beyond_the_cap_is_refused_before_the_tiling(move):
    """With 1e308 s between placements the hours are infinite (written as null before):
    refused by the cap --hull-area's estimate has, before any patch."""
    with pytest.raises(ScenarioError, match="move_time_s: must be a number of seconds from 0 to 1e\\+06"):
        surface_job(load_scenario("paper_clean"), move_time_s=move)
    with pytest.raises(ScenarioError):
        check_move_time(move)
    assert check_move_time(MOVE_TIME_MAX_S) == MOVE_TIME_MAX_S


def test_clean_surface_with_an_endless_move_is_one_line(tmp_path):
    res = runner.invoke(app, ["clean", "paper_clean", "--surface", "--move-time", "1e308",
                              "--out", str(tmp_path / "o")])
    one_line_exit_2(res, "--move-time 1e+308", "from 0 to 1e+06")
    assert not (tmp_path / "o").exists()


def test_a_band_with_no_flat_patch_is_refused(tmp_path):
    """A 10 m hull 200 m wide and 0.1 m deep, flared: its side near the bow bends more over
    5 cm than a millimetre's tolerance allows; no placement, no hours (0 h before)."""
    sc = load_scenario(_scenario(tmp_path, length_m="10.0", beam_m="200.0", draught_m="0.1", flare="1.0",
                                 stations_m="[-4.9, -4.7]", heights_m="[0.0, 0.2]",
                                 stand_off_tolerance_m="0.001"))
    with pytest.raises(ScenarioError) as err:
        surface_job(sc, move_time_s=600.0)
    assert err.value.key == "cleaning.surface.stand_off_tolerance_m"
    assert "no patch of the band is flat enough for the tool" in str(err.value)


def test_placements_csv_holds_only_finite_numbers_with_uncleanable_patches(tmp_path):
    """The ridge's uncleanable patches are written with cleanable 0 and no cleaning time (0 s,
    not an empty field): the job's seconds are the cleanable rows' sum."""
    ridge = lambda X, Z: 10.0 - 0.5 * np.abs(np.asarray(Z) - 0.9)  # noqa: E731
    placements, bad = tile_surface(ridge, (0.0, 2.0), (0.0, 2.0), width_m=1.0, height_m=1.0, tolerance_m=0.001)
    job_s = np.arange(1.0, len(placements) + 1.0)
    sj = SurfaceJob(placements=placements, uncleanable=bad, job_s=job_s, move_time_s=60.0, frame_panel_m=(1.0, 1.0),
                    surface="a ridge")
    path = write_surface(sj, tmp_path)[0]
    rows = list(csv.reader(open(path)))[1:]
    values = np.array(rows, dtype=float)  # an empty field would not parse
    assert len(rows) == len(placements) + len(bad) and np.isfinite(values).all()
    assert (values[:, -1] == 0).sum() == len(bad) and (values[values[:, -1] == 0, 15] == 0.0).all()
    assert values[:, 15].sum() == job_s.sum() == pytest.approx(sj.seconds - (len(placements) - 1) * 60.0)
