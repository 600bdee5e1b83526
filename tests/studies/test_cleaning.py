"""The cleaning job: the [cleaning] section, the coverage trajectory, the brush's loads in
the plan, and `marinecdpr clean` measured from the simulated brush."""

from __future__ import annotations

import json

import numpy as np
import pytest
from scipy.spatial import cKDTree
from typer.testing import CliRunner

import marinecdpr
from marinecdpr.cli.app import app
from marinecdpr.errors import ScenarioError
from marinecdpr.motion.trajectory import cleaning_path
from marinecdpr.studies.cleaning import cleaning_job

runner = CliRunner()


@pytest.fixture(scope="module")
def clean():
    return marinecdpr.load_scenario("paper_clean")


def _with(sc, **cleaning):
    return sc.with_changes(cleaning=sc.cleaning.model_dump(exclude_none=True) | cleaning)


@pytest.mark.parametrize("change, key, words", [
    (dict(overlap_m=0.2), "cleaning.overlap_m", "less than brush_diameter_m"),
    (dict(normal_force_N=[90.0, 40.0]), "cleaning.normal_force_N", "F_min <= F_max"),
    (dict(preload_N=100.0), "cleaning.preload_N", "within normal_force_N"),
    (dict(panel_m=[[-0.5, 0.3], [1.6, 0.3], [1.6, 1.1]]), "cleaning.panel_m[1]", "outside the frame"),
    (dict(panel_m=[[0.3, 0.3], [1.6, 0.3], [0.9, 0.3]]), "cleaning.panel_m", "encloses no area"),
    (dict(holes_m=[[[1.5, 0.5], [1.8, 0.5], [1.8, 0.7]]]), "cleaning.holes_m[1]", "inside panel_m"),
])
def test_a_wrong_cleaning_section_is_one_line_naming_the_key(clean, change, key, words):
    with pytest.raises(ScenarioError) as info:
        _with(clean, **change)
    assert info.value.key == key and words in str(info.value) and "\n" not in str(info.value)


def test_a_coverage_trajectory_needs_the_cleaning_section(clean):
    data = clean.model_dump(exclude_none=True)
    del data["cleaning"]
    with pytest.raises(ScenarioError, match="cleaning: missing: a coverage trajectory"):
        marinecdpr.scenario.scenario_from_dict(data)


def test_the_brush_loads_enter_the_planned_wrench_by_hand(clean):
    # calm water, mid-lane at cruise speed: friction mu F_n against the travel along x, the
    # disc's reaction moment (2/3) mu F_n R about the hull normal y, and the hull's push F_n
    calm = clean.with_changes(base_motion={"type": "still"}, time={"step_s": 0.001, "duration_s": 25.0})
    dry = _with(calm, friction=0.0)
    p, p0 = marinecdpr.plan(calm), marinecdpr.plan(dry)
    path = cleaning_path(calm.cleaning)
    lane = int(np.flatnonzero(path.lane_segment)[0])  # after the pass up the first side
    first_lane_mid = 0.5 * (path.vertex_time_s[lane] + path.vertex_time_s[lane + 1])  # cruise on it (along +x)
    k = int(round(first_lane_mid / calm.time.step_s))
    v = p.twist[k, :3]
    assert v[0] == pytest.approx(calm.cleaning.speed_m_s) and abs(v[2]) < 1e-12
    mu, F, R = calm.cleaning.friction, calm.cleaning.preload, calm.cleaning.brush_diameter_m / 2
    dw = p.wrench[k] - p0.wrench[k]
    # w = inertia - loads: the friction -mu F_n (+x) needs +mu F_n; the disc's moment
    # -(2/3) mu F_n R about +y needs +(2/3) mu F_n R (the brush is at P's origin)
    smooth = v[0] / np.hypot(v[0], 1e-3)  # friction smoothed through zero speed (1 mm/s)
    assert dw[0] == pytest.approx(mu * F * smooth, rel=1e-9) and dw[2] == pytest.approx(0.0, abs=1e-9)
    assert dw[4] == pytest.approx(2.0 / 3.0 * mu * F * R, rel=1e-9)
    # the hull's push along y is the same with and without friction, and the guide holds it
    y = p.reaction_dofs.index("y")
    assert p.reaction[k, y] == pytest.approx(p0.reaction[k, y]) == pytest.approx(-F, rel=1e-9)


def test_coverage_agrees_with_an_independent_computation_from_clean_csv(clean, tmp_path):
    # --no-compare: the calm-water and no-drag variants add only summary.json's "comparison"
    # (clean.csv and every other figure the same, byte for byte and to the bit)
    res = runner.invoke(app, ["clean", "paper_clean", "--duration", "12", "--no-compare", "--out", str(tmp_path)])
    assert res.exit_code == 0, res.output
    s = json.loads((tmp_path / "summary.json").read_text())
    rows = np.genfromtxt(tmp_path / "clean.csv", delimiter=",", names=True)
    assert rows.size == 12001 and np.all(rows["in_band"] == 1)
    # independent: dense samples of the in-band brush path in a k-d tree, a fine grid of the
    # panel's points, each cleaned if a sample lies within the brush's radius
    xz = np.column_stack([rows["brush_x_m"], rows["brush_z_m"]])[rows["in_band"] == 1]
    seg = np.linalg.norm(np.diff(xz, axis=0), axis=1)
    dense = np.concatenate([xz[:-1] + f * np.diff(xz, axis=0) for f in np.linspace(0, 1, 4, endpoint=False)]
                           + [xz[-1:]]) if seg.max() > 5e-4 else xz
    panel = np.asarray(s["panel_polygon_m"])
    gx = np.linspace(panel[:, 0].min(), panel[:, 0].max(), 1301)
    gz = np.linspace(panel[:, 1].min(), panel[:, 1].max(), 801)
    X, Z = np.meshgrid(gx, gz)
    # each grid point's nearest sample (not every sample within the radius: the same test, 10 times sooner)
    radius = s["brush_width_m"] / 2
    nearest, _ = cKDTree(dense).query(np.column_stack([X.ravel(), Z.ravel()]),
                                      distance_upper_bound=np.nextafter(radius, np.inf))
    independent = 100.0 * np.count_nonzero(nearest <= radius) / nearest.size
    assert abs(s["coverage_pct"] - independent) < 0.2
    assert 10.0 < s["coverage_pct"] < 60.0  # a part of the panel in 12 s: the numbers are not trivial


def test_in_calm_water_the_paper_robot_cleans_what_a_round_brush_can_reach(clean):
    calm = clean.with_changes(base_motion={"type": "still"})
    job = cleaning_job(calm)
    s = job.summary
    assert s["reachable_coverage_pct"] >= 99.5 and s["normal_force_in_band_pct"] == 100.0
    # what is missed is the panel's four corners a round brush cannot reach: r^2 (1 - pi/4) each
    r = calm.cleaning.brush_diameter_m / 2
    assert s["missed_area_m2"] == pytest.approx(4 * r * r * (1 - np.pi / 4), abs=0.002)
    assert s["panel_area_m2"] == pytest.approx(1.3 * 0.8, rel=1e-12)
    assert s["infeasible_steps"] == 0 and s["job_time_s"] == pytest.approx(cleaning_path(calm.cleaning).duration_s)
    assert s["area_rate_m2_h"] == pytest.approx((s["panel_area_m2"] - s["missed_area_m2"]) / s["job_time_s"] * 3600)


def test_the_sea_changes_the_normal_force_and_the_tensions_in_numbers(clean):
    n = 20001
    sea = cleaning_job(clean, n_steps=n)
    calm = cleaning_job(clean.with_changes(base_motion={"type": "still"}), n_steps=n)
    lo, hi = clean.cleaning.band_N
    # calm water: the pusher's preload exactly (the platform does not accelerate along y)
    np.testing.assert_allclose(calm.normal_force, clean.cleaning.preload, rtol=1e-9)
    # the ship's roll and pitch load the brush along the hull normal through gravity and inertia
    assert np.ptp(sea.normal_force) > 0.3 and lo <= sea.normal_force.min() and sea.normal_force.max() <= hi
    assert sea.summary["normal_force_in_band_pct"] == calm.summary["normal_force_in_band_pct"] == 100.0
    assert np.abs(sea.result.tensions - calm.result.tensions).max() > 0.1  # 1.3 N: a mild sea for a 5 kg robot


def test_the_brush_part_applies_the_loads_at_the_actual_velocity_less_the_planned_ones():
    from marinecdpr.model.brush import brush_params
    from marinecdpr.control.records import empty_measurement
    from marinecdpr.prototype.parts import empty_signals
    from marinecdpr.prototype.parts.brush import BrushContact, brush_step

    params = brush_params(0.5, 0.1, kind=0)
    plan_f, plan_m = np.array([[1.0, 2.0, 3.0]]), np.array([[0.5, 0.0, -0.5]])
    b = BrushContact(params=params, n_C=np.array([0.0, 1.0, 0.0]), F_n=np.array([100.0]), f_plan=plan_f,
                     m_plan=plan_m, v=np.zeros(3))
    bus = empty_signals(empty_measurement(4), np.zeros(4), np.zeros(4), np.zeros(4))
    # the platform moves along +x at 0.2 m/s and turns about y: the brush at P's origin
    bus.v[:] = [0.2, 0.0, 0.0]
    bus.w[:] = [0.0, 0.3, 0.0]
    brush_step(0, 0.001, b, bus)
    drag = -0.5 * 100.0 * 0.2 / np.hypot(0.2, 1e-3)
    np.testing.assert_allclose(bus.f_ext, [drag - 1.0, 100.0 - 2.0, -3.0], rtol=1e-12)
    np.testing.assert_allclose(bus.m_ext, [-0.5, -2.0 / 3.0 * 0.5 * 100.0 * 0.1, 0.5], rtol=1e-12)


def test_open_loop_with_the_brush_tracks_as_planned_in_calm_water(clean):
    # the plan compensates the drag along the planned velocity; the prototype's brush drags
    # along the actual one: open loop stays on the plan only if the two agree
    calm = clean.with_changes(base_motion={"type": "still"}, time={"step_s": 0.001, "duration_s": 10.0})
    for plant in ("own", "mujoco"):
        res = marinecdpr.simulate(calm, run="open_loop", plant=plant)
        assert np.abs(res.pose_error[:, [0, 2]]).max() < 1e-4, plant


def test_guarantee_sets_the_overlap_from_the_first_runs_tracking_and_checks_it(clean, tmp_path):
    from marinecdpr.studies.cleaning import guaranteed_job

    short = _with(clean, overlap_m=0.0).with_changes(time={"step_s": 0.001, "duration_s": 8.0})
    first = cleaning_job(short)
    job = guaranteed_job(short)
    g = job.summary["guarantee"]
    e95 = first.summary["p95_cross_track_error_m"]
    assert g["first_run_p95_cross_track_error_m"] == e95 > 0.0
    assert g["second_run"] and g["overlap_m"] == pytest.approx(2.1 * e95, rel=1e-12)
    assert g["lane_spacing_m"] <= short.cleaning.brush_diameter_m - 2.0 * e95
    assert g["checked"] == (2.0 * g["checked_p95_cross_track_error_m"] <= g["overlap_m"])
    # the typed record is what summary.json says, the guarantee last; its figures the job's arrays'
    assert job.figures.to_json() == job.summary and list(job.summary)[-1] == "guarantee"
    assert job.figures.guarantee.to_json() == g and job.figures.guarantee.second_run is True
    assert job.figures.p95_cross_track_error_m == float(np.percentile(job.cross_track, 95)) == g[
        "checked_p95_cross_track_error_m"]
    assert first.figures.guarantee is None and first.figures.steps == first.result.t.size
    # enough overlap already: one run, and it says so
    kept = guaranteed_job(_with(short, overlap_m=0.03)).summary["guarantee"]
    assert not kept["second_run"] and kept["overlap_m"] == 0.03 and "already covers" in kept["reason"]
    res = runner.invoke(app, ["clean", "paper_clean", "--guarantee", "--duration", "2", "--out", str(tmp_path)])
    assert res.exit_code == 0 and "guarantee:" in res.stdout
    assert json.loads((tmp_path / "summary.json").read_text())["guarantee"]["checked"] is True


def test_a_ship_side_is_placements_of_the_frame_by_hand():
    from marinecdpr.studies.cleaning import ship_side

    # 1.04 m2 panels, 0.04 m2 missed each: 1 m2 per placement in 100 s; 10.5 m2 of hull
    from types import SimpleNamespace

    s = SimpleNamespace(panel_area_m2=1.04, missed_area_m2=0.04, job_time_s=100.0)
    hull = ship_side(s, hull_area_m2=10.5, move_time_s=60.0)
    assert hull["placements"] == 11
    assert hull["hours"] == pytest.approx((11 * 100.0 + 10 * 60.0) / 3600.0)
    assert hull["area_rate_m2_h"] == pytest.approx(10.5 / (1700.0 / 3600.0))
    assert ship_side(s, hull_area_m2=10.0, move_time_s=0.0)["placements"] == 10
    with pytest.raises(ValueError, match="hull_area_m2"):
        ship_side(s, hull_area_m2=0.0, move_time_s=60.0)
    res = runner.invoke(app, ["clean", "paper_clean", "--duration", "1", "--hull-area", "100", "--move-time",
                              "-1", "--out", "unused"])
    assert res.exit_code == 2 and "--move-time -1: expected a non-negative number" in res.stderr


def test_the_job_beside_calm_water_and_without_the_brush_drag_in_numbers(clean, tmp_path):
    """Issue 11: what the sea and the brush's load do, side by side: each variant is the
    same job flown by cleaning_job in that condition; in calm water the normal force is the
    preload exactly; without the drag the tensions and the winches' energy change."""
    from marinecdpr.report.cleaning import cleaning_findings
    from marinecdpr.studies.cleaning import COMPARED, compare_conditions, job_variants

    n = 3000
    job = cleaning_job(clean, n_steps=n)
    cmp = compare_conditions(job, n_steps=n)
    assert list(cmp) == ["as asked", "calm water", "no brush drag"]
    variants = job_variants(clean)
    for name in ("calm water", "no brush drag"):
        direct = cleaning_job(variants[name], n_steps=n).summary
        assert cmp[name] == {k: direct[k] for k in COMPARED}
    calm = cmp["calm water"]
    assert calm["normal_force_min_N"] == pytest.approx(clean.cleaning.preload, rel=1e-9)
    assert calm["normal_force_max_N"] == pytest.approx(clean.cleaning.preload, rel=1e-9)
    here, free = cmp["as asked"], cmp["no brush drag"]
    assert here["normal_force_max_N"] - here["normal_force_min_N"] > 0.3  # the sea moves it (0.52 N)
    assert free["winch_energy_kJ"] != here["winch_energy_kJ"] and free["tension_max_N"] != here["tension_max_N"]
    assert "calm water" not in job_variants(variants["calm water"])  # a still ship has no calm variant
    # the command writes them into summary.json and the report
    out = tmp_path / "cmp"
    res = runner.invoke(app, ["clean", "paper_clean", "--duration", "1", "--out", str(out)])
    assert res.exit_code == 0, res.output
    summary = json.loads((out / "summary.json").read_text())
    assert set(summary["comparison"]) == {"as asked", "calm water", "no brush drag"}
    page = (out / "report.html").read_text()
    assert "What the sea and the brush do" in page and "The sea: in calm water" in page
    assert any(line.startswith("The sea: in calm water") for line in cleaning_findings(job.figures, comparison=cmp))
    res = runner.invoke(app, ["clean", "paper_clean", "--duration", "1", "--no-compare", "--out", str(out)])
    assert res.exit_code == 0 and "comparison" not in json.loads((out / "summary.json").read_text())


# -------------------- formerly tests/test_cleaning_partial_run.py

"""A cleaning job cut short (``clean --duration``, a scenario ending before its path) reports
the part flown, labelled as partial: the path flown in the time flown, not the whole path's
length beside the short time (issue 37, item 6)."""

import json

import numpy as np
import pytest
from typer.testing import CliRunner

import marinecdpr
from marinecdpr.cli.app import app
from marinecdpr.motion.trajectory import cleaning_path

runner = CliRunner()


def _flown_slowly(path, t_end: float, n: int = 400001) -> tuple[float, float]:
    """The distance travelled by ``t_end`` as the integral of the path's speed, and of it the
    part on the boundary pass's segments (its time windows from the vertices' times)."""
    t = np.linspace(0.0, t_end, n)
    speed = np.linalg.norm(path.evaluate(t)[1], axis=1)
    on_edge = np.zeros(n, dtype=bool)
    for i in np.flatnonzero(path.boundary_segment):
        on_edge |= (t >= path.vertex_time_s[i]) & (t <= path.vertex_time_s[i + 1])
    return float(np.trapezoid(speed, t)), float(np.trapezoid(np.where(on_edge, speed, 0.0), t))


@pytest.mark.parametrize("t_end", [0.0, 3.0, 15.0, 40.0, 77.0])
def test_the_path_flown_is_the_integral_of_the_speed(t_end):
    path = cleaning_path(marinecdpr.load_scenario("paper_clean").cleaning)
    length, edge = path.flown(t_end)
    slow_length, slow_edge = _flown_slowly(path, t_end)
    assert length == pytest.approx(slow_length, abs=1e-6)
    assert edge == pytest.approx(slow_edge, abs=2e-4)  # the windows' ends on the sampled grid
    assert path.flown(path.duration_s + 5.0) == pytest.approx((path.length_m, path.boundary_length_m), rel=1e-12)


def test_clean_for_15_s_reports_the_path_flown_in_15_s(tmp_path):
    out = tmp_path / "o"
    res = runner.invoke(app, ["clean", "--duration", "15", "--no-compare", "--out", str(out)], terminal_width=4000)
    assert res.exit_code == 0, res.output
    s = json.loads((out / "summary.json").read_text())
    path = cleaning_path(marinecdpr.load_scenario("paper_clean").cleaning)
    length, edge = _flown_slowly(path, 15.001)  # 15 001 steps of 1 ms: to t = 15.001 s
    assert s["partial"] is True and s["path_flown_s"] == pytest.approx(15.001, abs=1e-9)
    assert s["path_flown_m"] == pytest.approx(length, abs=1e-6)  # 1.435 m, not the whole path's 7.3 m
    assert s["boundary_pass_flown_m"] == pytest.approx(edge, abs=2e-4)  # up the first side, 0.6 m
    assert s["path_length_m"] == pytest.approx(path.length_m)  # the whole path's, beside it
    line = next(x for x in res.stdout.splitlines() if "of path" in x or "path (" in x)
    assert line.startswith(f"A PARTIAL run: {length:.3g} m of the {path.length_m:.3g} m path")
    assert "flown in the first 15.0 s" in line and f"{s['boundary_pass_flown_m']:.3g} m of it along the edges" in line
    assert f"{path.boundary_duration_s:.1f} s" not in line  # not the whole edge pass's time
    html = (out / "report.html").read_text()
    assert "job time (a PARTIAL run)" in html and "area rate (over the part flown)" in html


def test_a_whole_run_is_not_partial():
    sc = marinecdpr.load_scenario("paper_clean")
    path = cleaning_path(sc.cleaning)
    assert sc.time.duration_s >= path.duration_s  # the built-in job flies its whole path
    from marinecdpr.report.cleaning import cleaning_findings

    s = {"coverage_pct": 99.0, "panel_area_m2": 1.04, "reachable_coverage_pct": 99.9, "reachable_area_m2": 1.03,
         "brush_width_m": 0.2, "missed_area_m2": 0.01, "lanes": 5, "lane_spacing_m": 0.15, "path_length_m": 7.3,
         "job_time_s": 77.8, "area_rate_m2_h": 47.7, "boundary_pass_length_m": 1.2, "boundary_pass_time_s": 12.9,
         "partial": False, "normal_force_in_band_pct": 100.0, "contact_lost_s": 0.0, "tension_min_N": 50.0,
         "tension_max_N": 300.0, "infeasible_steps": 0, "max_cross_track_error_m": 1e-5,
         "p95_cross_track_error_m": 1e-6, "winch_energy_kJ": 1.0}
    from dataclasses import fields

    from marinecdpr.studies.cleaning import CleaningFigures

    s = CleaningFigures(**({f.name: None for f in fields(CleaningFigures)} | s))  # the rest unread here
    assert cleaning_findings(s)[1] == ("5 lanes 0.15 m apart, 7.3 m of path in 77.8 s: 47.7 m2/h; the pass along "
                                       "the edges the lanes leave takes 1.2 m and 12.9 s of it.")


def test_clean_seas_on_part_of_the_path_says_so(tmp_path):
    """The sibling in ``clean --seas``: a sea state judged on the first second of the path
    (its coverage and hours the part's) is said to be a partial job."""
    csv = tmp_path / "one.csv"
    csv.write_text("hs_m,tp_s,probability\n0.5,6,1.0\n")
    res = runner.invoke(app, ["clean", "paper_clean", "--seas", "--scatter", str(csv), "--duration", "1",
                              "--coverage-target", "0", "--serial", "--out", str(tmp_path / "o")],
                        terminal_width=4000)
    assert res.exit_code == 0, res.output
    path = cleaning_path(marinecdpr.load_scenario("paper_clean").cleaning)
    assert (f"warning: paper_clean: a PARTIAL job: each sea state flies the first 1 s of the {path.duration_s:.4g} s "
            "path; its coverage and hours are that part's") in res.stderr.splitlines()


# -------------------- formerly tests/test_cleaning_seas.py

"""The cleaning job over a scatter diagram (`clean --seas`): per sea state the same job as
`cleaning_job`, verdicts and expected hours summed by hand, independent of the request's
order, the same on Dask."""

import json
import math

import numpy as np
import pytest
from typer.testing import CliRunner

import marinecdpr
from marinecdpr.cli.app import app
from marinecdpr.errors import ScenarioError
from marinecdpr.motion.trajectory import cleaning_path
from marinecdpr.studies.cleaning import cleaning_job, cleaning_seas, evaluate_cleaning_cell, ship_side
from marinecdpr.studies.operability import Cell, ScatterDiagram, cell_scenario
from dask_cluster import dask_scheduler  # noqa: F401  (a fixture: the test process's shared Dask cluster)

runner = CliRunner()
# calm seas work; in 14 m, 10 s beam seas the ship's motion pushes the brush out of its force band;
# three sea states of positive probability a heading (each is a whole cleaning job flown)
DIAGRAM = ScatterDiagram(np.array([0.1, 1.0, 14.0]), np.array([8.0, 10.0]),
                         np.array([[0.3, 0.0], [0.0, 0.4], [0.0, 0.3]]))


@pytest.fixture(scope="module")
def small():
    """paper_clean on a 0.3 m x 0.3 m panel: two lanes, the whole path in a few seconds."""
    sc = marinecdpr.load_scenario("paper_clean")
    sc = sc.with_changes(cleaning=sc.cleaning.model_dump(exclude_none=True)
                         | {"panel_m": [[0.8, 0.5], [1.1, 0.5], [1.1, 0.8], [0.8, 0.8]]})
    return sc.with_changes(time={"step_s": 0.001, "duration_s": math.ceil(cleaning_path(sc.cleaning).duration_s)})


def test_a_sea_state_is_the_cleaning_job_in_that_sea(small):
    cell = Cell(3, 1.0, 8.0, 150.0, 0.2)
    r = evaluate_cleaning_cell(small, cell, coverage_target_pct=90.0, in_band_target_pct=95.0)
    job = cleaning_job(cell_scenario(small, cell, small.time.duration_s, small.time.step_s))
    s = job.summary
    assert (r.coverage_pct, r.reachable_coverage_pct, r.in_band_pct, r.tension_min_N, r.tension_max_N,
            r.job_time_s) == (s["coverage_pct"], s["reachable_coverage_pct"], s["normal_force_in_band_pct"],
                              s["tension_min_N"], s["tension_max_N"], s["job_time_s"])
    assert r.operable and r.reason == "" and r.hours == s["job_time_s"] / 3600.0
    hull = evaluate_cleaning_cell(small, cell, coverage_target_pct=90.0, hull_area_m2=50.0, move_time_s=300.0)
    assert hull.hours == ship_side(job.figures, hull_area_m2=50.0, move_time_s=300.0)["hours"]
    strict = evaluate_cleaning_cell(small, cell, coverage_target_pct=100.0, in_band_target_pct=100.0)
    assert not strict.operable and "reachable coverage" in strict.reason
    rough = evaluate_cleaning_cell(small, Cell(0, 14.0, 10.0, 90.0, 0.2))
    assert not rough.operable and "normal force in band" in rough.reason and rough.in_band_pct < 95.0
    # a job that cannot be flown: limits no tension distribution meets
    tight = small.with_changes(robot=small.robot.model_dump(exclude_none=True) | {"tension_max_N": 60.0})
    none = evaluate_cleaning_cell(tight, cell)
    assert not none.operable and "tensions within the limits" in none.reason and math.isnan(none.hours)


def test_a_sea_state_whose_plan_fails_is_judged_by_its_plan_as_its_flight_would_be(small, monkeypatch):
    """``plan_first`` (the design study's finalists): a sea state whose plan holds the normal
    force in band too little is not flown, its verdict and share of time in band those of
    the flown job (which takes both from its plan); one whose plan passes is flown, its result
    the same as without ``plan_first``, from one plan."""
    from marinecdpr.studies import cleaning

    rough, calm = Cell(0, 14.0, 10.0, 90.0, 0.2), Cell(3, 1.0, 8.0, 150.0, 0.2)
    flown = evaluate_cleaning_cell(small, rough)
    assert not flown.operable and "normal force in band" in flown.reason and np.isfinite(flown.coverage_pct)
    flights = []
    real = cleaning.simulate
    monkeypatch.setattr(cleaning, "simulate", lambda *a, **k: flights.append(1) or real(*a, **k))
    planned = evaluate_cleaning_cell(small, rough, plan_first=True)
    assert flights == [] and not planned.operable and planned.reason.endswith(cleaning.NOT_FLOWN)
    assert planned.in_band_pct == flown.in_band_pct < 95.0 and math.isnan(planned.coverage_pct)
    plans = []
    real_plan = cleaning.plan
    monkeypatch.setattr(cleaning, "plan", lambda *a, **k: plans.append(1) or real_plan(*a, **k))
    assert evaluate_cleaning_cell(small, calm, plan_first=True) == evaluate_cleaning_cell(small, calm)
    assert flights == [1, 1] and plans == [1, 1]


def test_over_a_scatter_diagram_the_share_and_hours_sum_by_hand(small):
    cs = cleaning_seas(small, DIAGRAM, headings_deg=(180.0, 90.0), coverage_target_pct=90.0)
    rs = cs.sea.results
    assert len(rs) == 2 * 3  # the cells of probability 0 are not flown
    works = [r for r in rs if r.operable]
    assert all(r.operable for r in rs if r.cell.hs == 0.1)  # calm works
    assert not [r for r in rs if (r.cell.hs, r.cell.heading_deg) == (14.0, 90.0)][0].operable
    assert 0 < len(works) < len(rs)
    for h in (180.0, 90.0):
        mine = [r for r in rs if r.cell.heading_deg == h]
        assert cs.sea.per_heading[h] == pytest.approx(sum(r.cell.probability for r in mine if r.operable)
                                                      / sum(r.cell.probability for r in mine), rel=1e-12)
    assert cs.sea.operability == pytest.approx(np.mean(list(cs.sea.per_heading.values())), rel=1e-12)
    p = np.array([r.cell.probability for r in works])
    assert cs.expected_hours == pytest.approx(np.sum(p * [r.hours for r in works]) / p.sum(), rel=1e-12)
    assert cs.expected_hours_with_weather == pytest.approx(cs.expected_hours / cs.sea.operability, rel=1e-12)
    # the same sea states asked in another order: the same verdicts and figures
    again = cleaning_seas(small, DIAGRAM, headings_deg=(90.0, 180.0), coverage_target_pct=90.0)
    key = lambda r: (r.cell.hs, r.cell.tp, r.cell.heading_deg)  # noqa: E731
    assert {key(r): (r.operable, r.coverage_pct, r.tension_max_N) for r in rs} == \
        {key(r): (r.operable, r.coverage_pct, r.tension_max_N) for r in again.sea.results}


def test_on_dask_the_cleaning_job_gives_the_serial_results(small, dask_scheduler):
    diagram = ScatterDiagram(np.array([0.5, 2.0]), np.array([6.0]), np.array([[0.5], [0.5]]))
    sc = small.with_changes(time={"duration_s": 2.0})
    from marinecdpr.studies.executor import Executor

    serial = cleaning_seas(sc, diagram, executor=Executor.serial())
    dask = cleaning_seas(sc, diagram, executor=Executor.at(dask_scheduler))  # two worker processes
    assert dask.sea.executor == "dask"
    assert [(r.operable, r.coverage_pct, r.tension_min_N, r.tension_max_N) for r in serial.sea.results] == \
        [(r.operable, r.coverage_pct, r.tension_min_N, r.tension_max_N) for r in dask.sea.results]


def test_cleaning_seas_needs_a_sea_state_and_a_cleaning_job(small):
    with pytest.raises(ScenarioError, match="sea_state"):
        cleaning_seas(small.with_changes(base_motion={"type": "still"}), DIAGRAM)
    with pytest.raises(ScenarioError, match="no cleaning job"):
        cleaning_seas(marinecdpr.load_scenario("paper_sea"), DIAGRAM)


@pytest.mark.figures
def test_clean_seas_writes_what_it_found_and_refuses_bad_options(small, tmp_path):
    csv = tmp_path / "diagram.csv"
    csv.write_text("hs_m,tp_s,probability\n0.5,6,0.6\n10,14,0.4\n")
    out = tmp_path / "out"
    res = runner.invoke(app, ["clean", "paper_clean", "--seas", "--scatter", str(csv), "--duration", "1",
                              "--coverage-target", "0", "--headings", "180,90", "--serial", "--out", str(out)])
    assert res.exit_code == 0, res.output
    summary = json.loads((out / "summary.json").read_text())
    rows = np.genfromtxt(out / "sea_states.csv", delimiter=",", names=True)
    assert rows.size == 4 and sorted(p.name for p in out.iterdir() if not p.name.startswith(".")) == ["sea_states.csv", "sea_states.png",
                                                                         "summary.json"]
    # the summary's share is the CSV's verdicts weighted by probability, headings equally likely
    share = np.mean([np.sum(rows["probability"][rows["heading_deg"] == h] * rows["works"][rows["heading_deg"] == h])
                     for h in (180.0, 90.0)])
    assert summary["operability"] == pytest.approx(share, rel=1e-9)
    failing = rows[rows["works"] == 0]
    assert [(c["heading_deg"], c["hs_m"], c["tp_s"]) for c in summary["not_working"]] == \
        [(float(r["heading_deg"]), float(r["hs_m"]), float(r["tp_s"])) for r in failing]
    for args, words in ((["--guarantee"], "--guarantee with --seas: cannot go together"),
                        (["--coverage-target", "120"], "--coverage-target 120: expected a percentage"),
                        (["--serial", "--workers", "2"], "--workers 2: cannot go with --serial")):
        res = runner.invoke(app, ["clean", "paper_clean", "--seas", "--duration", "1", *args, "--out", str(out)])
        assert res.exit_code == 2 and words in res.stderr and res.stderr.count("\n") == 1, res.output


# -------------------- formerly tests/test_issue21_spatial_clean.py

"""Issue 21, item 14: ``clean`` works for a spatial robot (examples/spatial_cube8.toml with
a [cleaning] section): its cables hold the brush on the hull at the preload, and the
cleaned area is the brush's swept footprint in C's x-z plane at ``plane_y_m``."""


import csv
import json
import math
from pathlib import Path

from typer.testing import CliRunner

from marinecdpr.cli.app import app

runner = CliRunner()
EXAMPLES = Path(__file__).resolve().parents[2] / "examples"

CLEANING = '''[trajectory]
type = "coverage"
plane_y_m = 1.0                     # the panel's plane: the frame's middle

[cleaning]
panel_m = [[0.7, 0.7], [1.3, 0.7], [1.3, 1.3], [0.7, 1.3]]
brush = "disc"
brush_diameter_m = 0.2
overlap_m = 0.03
speed_m_s = 0.1
acceleration_m_s2 = 0.3
jerk_m_s3 = 3.0
normal_force_N = [40.0, 80.0]
preload_N = 60.0
friction = 0.4
hull_normal = [0.0, 1.0, 0.0]

'''


def _spatial_cleaning(tmp_path: Path) -> Path:
    text = (EXAMPLES / "spatial_cube8.toml").read_text()
    start, end = text.index("[trajectory]"), text.index("[time]")
    path = tmp_path / "cube8_clean.toml"
    path.write_text(text[:start] + CLEANING + '[time]\nstep_s = 0.001\nduration_s = 45.0\n\n'
                    '[simulation]\nplant = "own"\n', encoding="utf-8")
    return path


def test_clean_works_for_a_spatial_robot(tmp_path):
    out = tmp_path / "out"
    res = runner.invoke(app, ["clean", str(_spatial_cleaning(tmp_path)), "--duration", "1", "--no-compare",
                              "--out", str(out)])
    assert res.exit_code == 0, res.output
    s = json.loads((out / "summary.json").read_text())
    assert s["steps"] == 1001 and s["infeasible_steps"] == 0 and s["controller_verdict"] == "held"
    # the cables hold the brush on at the preload
    assert s["normal_force_min_N"] == s["normal_force_max_N"] == 60.0 and s["normal_force_in_band_pct"] == 100.0
    rows = list(csv.DictReader((out / "clean.csv").open()))
    # on the panel's plane (y = 1 m) and on its path, across the rolling, heaving ship
    assert max(abs(float(r["brush_y_m"]) - 1.0) for r in rows) < 1e-6
    assert s["max_cross_track_error_m"] < 1e-5
    # the first second is a straight stretch from the corner (0.8, 0.8) inset by the brush's
    # radius: the cleaned area is the swept stadium
    xz = [(float(r["brush_x_m"]), float(r["brush_z_m"])) for r in rows]
    assert xz[0] == (0.8, 0.8)
    length = math.dist(xz[0], xz[-1])
    assert 0.05 < length < 0.1 and abs(sum(math.dist(a, b) for a, b in zip(xz, xz[1:])) - length) < 1e-5
    stadium = length * 0.2 + math.pi * 0.1 ** 2
    assert abs(s["coverage_pct"] - 100.0 * stadium / 0.36) < 0.5
    # the report says how the normal force was had: the cables, not a guide
    assert s["robot_dofs"] == "spatial"
    html = (out / "report.html").read_text()
    assert "the cables hold the brush on the hull at the preload" in html and "the guide holds" not in html


def test_a_rectangle_s_reachable_cells_miss_its_corners_and_are_kept_for_the_next_flight():
    """reachable_cells: on a 0.4 x 0.3 m rectangle a disc of r = 0.05 m misses r^2 (1 - pi/4)
    at each corner (by hand: 0.12 - 4 * 0.0025 * 0.2146 = 0.117854 m^2; within the 1 mm
    raster's staircase); asked again for the same panel, the kept answer (the same cells, read
    only); for another radius or another panel, its own."""
    from types import SimpleNamespace

    from marinecdpr.studies import cleaning as C

    passes = np.zeros((300, 400), dtype=np.int64)  # 1 mm cells
    cov = SimpleNamespace(passes=passes, resolution_m=0.001)
    reach = C.reachable_cells(cov, 0.05)
    area = reach.sum() * 1e-6
    assert abs(area - (0.12 - 4 * 0.05**2 * (1 - np.pi / 4))) < 4e-4  # the staircase: ~ the corners' arcs x 1 mm
    assert not reach[0, 0] and not reach[0, -1] and reach[150, 0] and reach[0, 200]
    again = C.reachable_cells(SimpleNamespace(passes=passes.copy(), resolution_m=0.001), 0.05)
    assert again is reach and not again.flags.writeable
    wider = C.reachable_cells(cov, 0.1)
    assert wider.sum() < reach.sum()
    holed = passes.copy()
    holed[100:200, 150:250] = -1  # a hole: outside the panel
    with_hole = C.reachable_cells(SimpleNamespace(passes=holed, resolution_m=0.001), 0.05)
    np.testing.assert_array_equal(with_hole, C._reachable(holed >= 0, 0.001, 0.05))
    assert with_hole.sum() == reach.sum() - 100 * 100  # a disc outside a square hole reaches up to its edges and corners
    for r in np.linspace(0.01, 0.02, 9):  # more panels than are kept: the first is asked afresh
        C.reachable_cells(cov, float(r))
    fresh = C.reachable_cells(cov, 0.05)
    assert fresh is not reach
    np.testing.assert_array_equal(fresh, reach)
