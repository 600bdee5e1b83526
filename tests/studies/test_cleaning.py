"""The cleaning job: the [cleaning] section, the coverage trajectory, the brush's loads in
the plan, and `marinecdpr clean` measured from the simulated brush."""

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
    res = runner.invoke(app, ["clean", "paper_clean", "--duration", "12", "--out", str(tmp_path)])
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
    hit = cKDTree(dense).query_ball_point(np.column_stack([X.ravel(), Z.ravel()]), r=s["brush_width_m"] / 2,
                                          return_length=True)
    independent = 100.0 * np.count_nonzero(hit) / hit.size
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

    short = _with(clean, overlap_m=0.0).with_changes(time={"step_s": 0.001, "duration_s": 15.0})
    first = cleaning_job(short)
    job = guaranteed_job(short)
    g = job.summary["guarantee"]
    e95 = first.summary["p95_cross_track_error_m"]
    assert g["first_run_p95_cross_track_error_m"] == e95 > 0.0
    assert g["second_run"] and g["overlap_m"] == pytest.approx(2.1 * e95, rel=1e-12)
    assert g["lane_spacing_m"] <= short.cleaning.brush_diameter_m - 2.0 * e95
    assert g["checked"] == (2.0 * g["checked_p95_cross_track_error_m"] <= g["overlap_m"])
    # enough overlap already: one run, and it says so
    kept = guaranteed_job(_with(short, overlap_m=0.03)).summary["guarantee"]
    assert not kept["second_run"] and kept["overlap_m"] == 0.03 and "already covers" in kept["reason"]
    res = runner.invoke(app, ["clean", "paper_clean", "--guarantee", "--duration", "2", "--out", str(tmp_path)])
    assert res.exit_code == 0 and "guarantee:" in res.stdout
    assert json.loads((tmp_path / "summary.json").read_text())["guarantee"]["checked"] is True


def test_a_ship_side_is_placements_of_the_frame_by_hand():
    from marinecdpr.studies.cleaning import ship_side

    # 1.04 m2 panels, 0.04 m2 missed each: 1 m2 per placement in 100 s; 10.5 m2 of hull
    s = {"panel_area_m2": 1.04, "missed_area_m2": 0.04, "job_time_s": 100.0}
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
    assert any(line.startswith("The sea: in calm water") for line in cleaning_findings(summary))
    res = runner.invoke(app, ["clean", "paper_clean", "--duration", "1", "--no-compare", "--out", str(out)])
    assert res.exit_code == 0 and "comparison" not in json.loads((out / "summary.json").read_text())
