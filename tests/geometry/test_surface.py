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
    at 9 x 9); and a tighter tolerance that forces splits, on a tumbling-home bilge band."""
    f, _ = surface_function(paper_clean.cleaning.surface)
    tol = paper_clean.cleaning.surface.stand_off_tolerance_m
    worst = max(_dense_deviation(f, p) for p in paper_clean_job.placements)
    assert worst <= tol
    assert worst == pytest.approx(paper_clean_job.summary()["largest_stand_off_deviation_m"], rel=1e-9)
    bilge = paper_clean.with_updates("cleaning.surface", flare=-0.5, heights_m=[-9.0, 8.0], stations_m=[-90.0, -60.0],
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
    seconds are their sum and (n - 1) moves."""
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
    moves = surface_job(paper_clean, move_time_s=300.0)
    assert (sj.hours - moves.hours) * 3600.0 == pytest.approx((n - 1) * 300.0, rel=1e-12)


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
    loose = paper_clean.with_updates("cleaning.surface", stand_off_tolerance_m=0.05)
    n_loose = [len(surface_job(loose, move_time_s=600.0, panel_m=(1.3 * k, 0.8 * k)).placements) for k in (2, 4)]
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
    a = surface_job(analytic, move_time_s=600.0, panel_m=(2.0, 1.5))
    m = surface_job(meshed, move_time_s=600.0, panel_m=(2.0, 1.5))
    assert m.area_m2 == pytest.approx(a.area_m2, rel=1e-3)
    # the faceted side kinks between its 1 m panels: a few more patches are cut
    assert len(a.placements) <= len(m.placements) <= 1.15 * len(a.placements)
    f, _ = surface_function(meshed.cleaning.surface)
    assert max(_dense_deviation(f, p) for p in m.placements) <= 0.02
    off = meshed.with_updates("cleaning.surface", heights_m=[-5.0, 2.0])  # above the mesh's top
    with pytest.raises(ScenarioError, match="the band leaves the mesh"):
        surface_job(off, move_time_s=600.0)


def test_clean_surface_writes_the_placements_and_their_hours(tmp_path, monkeypatch):
    """The README's figures for paper_clean's band: 2 660 placements, 497 h with moves of 600 s;
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
    ("", ["--surface", "--hull-area", "2200"], ["--surface and --hull-area"]),
    ("", ["--surface", "--seas"], ["--surface cannot go with --seas"]),
])
def test_clean_surface_refuses_bad_input_in_one_line(tmp_path, surface, flags, words):
    scen = BUILTIN / "paper_clean.toml" if surface == "" else _paper_clean_file(tmp_path, surface)
    res = runner.invoke(app, ["clean", str(scen), *flags, "--duration", "0.1", "--out", str(tmp_path / "o")])
    one_line_exit_2(res, *words)
    assert not (tmp_path / "o").exists()
