"""The virtual prototype: plant agreement, the paper's verification, cables, control, failures."""

import json
from pathlib import Path

import mujoco
import numpy as np
import pytest
from typer.testing import CliRunner

import marinecdpr
from marinecdpr import InfeasibleError
from marinecdpr.studies.prototype_runs import run_summary
from marinecdpr.cli.app import app
from marinecdpr.errors import SimulationDivergedError
from marinecdpr.geometry.kinematics import cable_kinematics
from marinecdpr.prototype.mujoco_model import build_model
from marinecdpr.prototype.simulation import simulate
from marinecdpr.motion.trajectory import evaluate_trajectory

from conftest import make_scenario

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


@pytest.fixture(scope="module")
def paper_runs(paper, paper_plan):
    return {(plant, run): simulate(paper, run=run, reference=paper_plan, plant=plant)
            for plant in ("mujoco", "own") for run in ("open_loop", "fixed_base_open_loop")}


def test_mujoco_and_own_plant_agree_on_the_paper_open_loop(paper_runs):
    """Open loop, ideal cables, 15 s: within 1e-4 m and 0.01 deg of each other."""
    a, b = paper_runs["mujoco", "open_loop"], paper_runs["own", "open_loop"]
    assert a.t.size == b.t.size == 15001
    d = a.pose - b.pose
    assert np.abs(d[:, :3]).max() <= 1e-4
    assert np.degrees(np.abs(d[:, 3:]).max()) <= 0.01
    np.testing.assert_allclose(a.lengths, b.lengths, atol=1e-4)
    assert a.ship_tracking_error < 1e-6  # MuJoCo's heavy ship stays on its prescribed motion


def test_open_loop_tracks_better_than_the_paper_and_fixed_base_much_worse(paper_runs, paper):
    """The paper's Adams run: 0.025 m in x, 0.013 m in z, 0.48 deg, cable length 0.15 m."""
    s = run_summary(paper_runs["mujoco", "open_loop"], paper)
    assert s["max_abs_error_x_m"] < 0.025 and s["max_abs_error_z_m"] < 0.013
    assert s["max_abs_error_theta_deg"] < 0.48 and max(s["max_abs_cable_length_error_m"]) < 0.15
    f = run_summary(paper_runs["mujoco", "fixed_base_open_loop"], paper)
    # ignoring the ship costs centimetres: the paper's claim, in numbers
    assert f["max_abs_error_x_m"] > 0.01 and f["max_abs_error_x_m"] > 1000 * s["max_abs_error_x_m"]
    assert f["max_abs_error_theta_deg"] > 1000 * s["max_abs_error_theta_deg"]


def test_mujoco_tendons_have_the_plans_geometry():
    """MuJoCo's tendon lengths and moment arms equal the kinematics of eqs. (2) and (6)."""
    for source, pose in (("paper", [0.7, 0.0, 0.9, 0.0, 0.3, 0.0]),
                         (EXAMPLES / "spatial_cube8.toml", [1.1, 0.9, 1.2, 0.2, -0.3, 0.4])):
        sc = marinecdpr.load_scenario(source)
        mm = build_model(sc)
        d = mujoco.MjData(mm.model)
        pose = np.array(pose)
        from marinecdpr.geometry.rotations import matrix_from_euler
        from marinecdpr.prototype.simulation import _quat_from_R

        R = matrix_from_euler(pose[3:])
        if sc.robot.dofs == "planar":
            d.qpos[mm.platform_qpos] = [pose[0], pose[2], pose[4]]
        else:
            d.qpos[mm.platform_qpos] = np.concatenate([pose[:3], _quat_from_R(R)])
        mujoco.mj_forward(mm.model, d)
        kin = cable_kinematics(pose[None, :3], R[None], sc.robot.frame_anchors, sc.robot.platform_anchors)
        np.testing.assert_allclose(d.ten_length, kin.lengths[0], rtol=1e-12)


def test_closed_loop_recovers_from_an_initial_error_open_loop_does_not(paper):
    sc = paper.with_changes(simulation={"initial_error_m": [0.02, 0.0, -0.01], "initial_error_deg": [0, 3.0, 0]},
                            time={"step_s": 0.001, "duration_s": 3.0})
    closed = simulate(sc, run="closed_loop")
    opened = simulate(sc, run="open_loop")
    e0 = np.abs(closed.pose_error[0, [0, 2, 4]])
    assert np.all(np.abs(closed.pose_error[-1, [0, 2, 4]]) < 1e-3 * e0)
    assert np.abs(opened.pose_error[-1000:, 0]).max() > 0.1 * e0[0]  # no feedback: it keeps swinging


def test_closed_loop_beats_open_loop_with_elastic_cables_and_noise():
    sc = marinecdpr.load_scenario("paper_elastic")
    p = marinecdpr.plan(sc)
    s = {run: run_summary(simulate(sc, run=run, reference=p), sc)
         for run in ("open_loop", "closed_loop")}
    for key in ("max_abs_error_x_m", "max_abs_error_z_m", "max_abs_error_theta_deg"):
        assert s["closed_loop"][key] < 0.5 * s["open_loop"][key], key
    assert s["closed_loop"]["controller_fallbacks"] == 0


def _hanging(edit_sim):
    """The paper's robot at rest at the frame's centre on a still ship."""
    def edit(d):
        d["base_motion"] = {"type": "still"}
        d["trajectory"] = {"type": "line", "start_position_m": [0.95, 0.0, 0.7],
                           "end_position_m": [0.95, 0.0, 0.7], "duration_s": 1.0}
        d["time"] = {"step_s": 0.001, "duration_s": 0.3}
        d["simulation"] = edit_sim
    return make_scenario(edit)


def test_elastic_cable_holds_the_hand_worked_statics():
    """At rest, tensions = E A (L - L0) / L0 = the minimum-variance statics (test_tension)."""
    sc = _hanging({"cables": {"model": "elastic", "stiffness_EA_N": 2.0e5, "damping_N_s_m": 100.0}})
    a = 49.0 * np.hypot(0.825, 0.55) / 2.2
    expected = np.array([a, a, -a, -a]) + 230.0
    for plant in ("mujoco", "own"):
        r = simulate(sc, run="open_loop", plant=plant)
        np.testing.assert_allclose(r.tensions, np.broadcast_to(expected, r.tensions.shape), rtol=1e-7)
        assert np.abs(r.pose_error).max() < 1e-9


def test_elastic_cable_goes_slack_when_shorter_than_its_rest_length():
    """5 cm down: the lower cables shorten past their ~1 mm stretch (slack, 0 N); the upper ones
    stretch by the geometry, T = E A (L - L0) / L0 with L0 set for the planned tension."""
    EA = 2.0e5
    sc = _hanging({"cables": {"model": "elastic", "stiffness_EA_N": EA}, "initial_error_m": [0.0, 0.0, -0.05]})
    r = simulate(sc, run="open_loop", plant="own", n_steps=1)
    a = 49.0 * np.hypot(0.825, 0.55) / 2.2
    T_plan = np.array([a, a, -a, -a]) + 230.0
    L_plan = np.hypot(0.825, 0.55)
    L_now = np.hypot(0.825, [0.60, 0.60, 0.50, 0.50])
    L0 = L_plan / (1 + T_plan / EA)
    expected = np.where(L_now > L0, EA * (L_now - L0) / L0, 0.0)
    assert expected[2] == expected[3] == 0.0
    np.testing.assert_allclose(r.tensions[0], expected, rtol=1e-9)


STIFF = {"cables": {"model": "elastic", "stiffness_EA_N": 1.0e7}}


def test_divergence_is_reported_with_time():
    """A 1e7 N cable on a 5 kg platform at 20 ms steps: omega h ~ 57, far past RK4's limit."""
    sc = marinecdpr.load_scenario("paper").with_changes(simulation=STIFF, time={"step_s": 0.02, "duration_s": 15.0})
    for plant in ("mujoco", "own"):
        with pytest.raises(SimulationDivergedError, match=r"paper: open_loop diverged at t = \d+\.\d+ s"):
            simulate(sc, run="open_loop", plant=plant)


def test_infeasible_plan_is_not_simulated():
    sc = make_scenario(lambda d: d["robot"].update(mass_kg=200.0))
    with pytest.raises(InfeasibleError, match="cannot simulate the moving-base plan: the cables cannot hold"):
        simulate(sc, run="open_loop", n_steps=10)


def test_spatial_robot_on_both_plants():
    """The 8-cable example: both plants agree; under pure tension control its crossed cables
    have negative stiffness in yaw, so open loop departs exponentially; feedback holds it."""
    sc = marinecdpr.load_scenario(EXAMPLES / "spatial_cube8.toml")
    p = marinecdpr.plan(sc)
    a = simulate(sc, run="open_loop", reference=p, plant="mujoco", n_steps=1200)
    b = simulate(sc, run="open_loop", reference=p, plant="own", n_steps=1200)
    np.testing.assert_allclose(a.pose[:500], b.pose[:500], rtol=0, atol=1e-7)
    err = np.abs(a.pose_error).max(axis=1)
    assert err[300] < 1e-5  # then it grows exponentially:
    assert err[1100] / err[700] > 50 and err[700] / err[300] > 50
    sc2 = sc.with_changes(simulation={"initial_error_m": [0.01, -0.01, 0.02], "initial_error_deg": [2.0, -1.0, 3.0]})
    c = simulate(sc2, run="closed_loop", plant="mujoco", n_steps=3000)
    assert np.abs(c.pose_error[-1]).max() < 1e-3 * np.abs(c.pose_error[0]).max()


runner = CliRunner()


@pytest.mark.figures
def test_simulate_command_writes_the_report(tmp_path):
    res = runner.invoke(app, ["simulate", "--duration", "0.4", "--out", str(tmp_path)])
    assert res.exit_code == 0, res.output
    names = {p.name for p in tmp_path.iterdir()}
    assert names == {"plan.csv", "sim_open_loop.csv", "sim_closed_loop.csv", "sim_fixed_base_open_loop.csv",
                     "tensions.png", "cable_lengths.png", "tracking.png", "path.png", "summary.json", "report.html",
                     ".marinecdpr-files"}
    s = json.loads((tmp_path / "summary.json").read_text())
    for key in ("pinv_tension_min_N", "opt_tension_min_N", "opt_tension_max_N"):
        assert isinstance(s[key], float)
    for run in ("open_loop", "closed_loop", "fixed_base_open_loop"):
        for key in ("max_abs_error_x_m", "max_abs_error_z_m", "max_abs_error_theta_deg",
                    "tension_min_N", "tension_max_N"):
            assert np.isfinite(s[run][key])
        assert len(s[run]["max_abs_cable_length_error_m"]) == 4
    assert s["open_loop"]["max_abs_error_x_m"] < s["fixed_base_open_loop"]["max_abs_error_x_m"]
    sim = np.loadtxt(tmp_path / "sim_closed_loop.csv", delimiter=",", skiprows=1)
    assert sim.shape == (401, 1 + 3 + 3 + 4 + 4 + 4 + 4)
    html = (tmp_path / "report.html").read_text()
    assert html.count('<img src="data:image/png;base64,') == 4 and "paper (Adams, open loop)" in html
    assert "<th>x (mm)</th><td>25</td>" in html  # the paper's x error beside ours


def test_simulate_command_failures(tmp_path):
    heavy = tmp_path / "heavy.toml"
    heavy.write_text((EXAMPLES / "paper.toml").read_text().replace("mass_kg = 5.0", "mass_kg = 200.0"))
    res = runner.invoke(app, ["simulate", str(heavy), "--duration", "0.1", "--out", str(tmp_path / "o")])
    assert res.exit_code == 3 and "cannot hold the platform" in res.stderr
    wild = tmp_path / "wild.toml"
    wild.write_text((EXAMPLES / "paper.toml").read_text()
                    .replace('model = "ideal"', 'model = "elastic"\nstiffness_EA_N = 1e7')
                    .replace("step_s = 0.001", "step_s = 0.02"))
    res = runner.invoke(app, ["simulate", str(wild), "--out", str(tmp_path / "o")])
    assert res.exit_code == 4 and "open_loop diverged at t = " in res.stderr
    assert not (tmp_path / "o").exists()


def test_the_run_flown_in_a_forked_process_is_the_same_run(monkeypatch):
    from marinecdpr import forked

    if not forked.can_fork():
        pytest.skip("no second CPU or no fork here: every run flies in this process")
    sc = marinecdpr.load_scenario("paper_elastic")
    sc = sc.with_changes(time={"step_s": sc.time.step_s, "duration_s": 0.4})
    calls = []
    apart = marinecdpr.virtual_prototype(sc, progress=lambda run, done, total: calls.append((run, done, total)))
    # the last run is reported at its start and its end only: it flew in the copy
    n = sc.time.n_steps
    assert [c for c in calls if c[0] == "fixed_base_open_loop"] == [("fixed_base_open_loop", 0, n),
                                                                    ("fixed_base_open_loop", n, n)]
    assert [c for c in calls if c[0] == "open_loop"][-1] == ("open_loop", n, n)
    monkeypatch.setattr(forked, "can_fork", lambda: False)
    here = marinecdpr.virtual_prototype(sc)
    assert list(apart.results) == list(here.results) == ["open_loop", "closed_loop", "fixed_base_open_loop"]
    for run in here.results:
        for field in ("pose", "lengths", "tensions", "tensions_commanded"):
            np.testing.assert_array_equal(getattr(apart.results[run], field), getattr(here.results[run], field))
    assert apart.summary == here.summary


def test_a_flat_plate_s_inertia_compiles_and_flies_on_both_plants():
    """A 4.9 kg plate 0.26 x 0.28 m in the frame's plane: its principal moments m h^2 / 12 and
    m w^2 / 12 sum to m (w^2 + h^2) / 12 less 7e-18 by rounding, which the scenario accepts
    (a plate is a rigid body) and MuJoCo refused ("A + B >= C"). The model compiles with the
    moment about y (the planar robot's only one) exactly the scenario's and the other two
    raised by 1e-12 of it; the paper's 15 s flown open loop on both plants agree as the
    paper robot's do."""
    m, w, h = 4.8972988942744875, 0.26236629040209714, 0.28466528979451516
    moments = [m * h * h / 12, m * (w * w + h * h) / 12, m * w * w / 12]
    assert moments[0] + moments[2] < moments[1]
    sc = marinecdpr.load_scenario("paper").with_updates("robot", mass_kg=m, inertia_kg_m2=moments)
    mm = build_model(sc)
    got = np.sort(mm.model.body_inertia[mm.platform_body])
    assert got[2] == moments[1]
    raised = got[:2] - sorted([moments[0], moments[2]])
    assert (raised > 0).all() and (raised <= 1e-12 * moments[1]).all()
    assert got[0] + got[1] >= got[2]
    from marinecdpr.prototype.mujoco_model import _compilable_inertia

    paper = marinecdpr.load_scenario("paper").robot.inertia  # 0.03 + 0.03 = 0.06: compiled as it is
    assert _compilable_inertia(paper) is paper
    runs = {plant: simulate(sc, run="open_loop", plant=plant) for plant in ("mujoco", "own")}
    assert np.abs(runs["mujoco"].pose - runs["own"].pose).max() < 1e-4


def test_both_plants_agree_over_a_continuous_cleaning_run():
    """A strip cleaned while the carriage moves (issue 39, item 3): examples/rail_strip.toml's
    brush path held on the ship (``trajectory.on_hull``), the carriage starting at 0.5 s at
    2 cm/s along its bent rail, in its sea: the closed loop on MuJoCo and on the own plant.
    Measured over 3 s: 3.1e-6 m in x, 5.8e-6 m in z, 5.5e-9 rad (3.4e-6 m, 5.3e-6 m, 5.7e-9 rad
    when MuJoCo's frame hung from a carriage body on a ship body; the stepped job at the rail's
    start, its frame standing: 3.4e-6 m, 5.3e-6 m, 5.6e-9 rad: the brush's drag reversing at
    the lanes' ends); 1e-5 m and 1e-8 rad allowed."""
    from marinecdpr.motion.carriage import carriage_travel, rail_of
    from marinecdpr.studies.strip import run_scenario

    sc = marinecdpr.load_scenario(str(EXAMPLES / "rail_strip.toml"))
    sc = run_scenario(sc, 0.0, rail_of(sc.ship).length_m, dwell_s=0.5, speed_m_s=0.02).with_updates(
        "time", duration_s=3.0)
    a = simulate(sc, run="closed_loop", plant="mujoco")
    b = simulate(sc, run="closed_loop", plant="own")
    assert carriage_travel(sc.ship, a.t)[0][-1] > 0.04  # the carriage moves the frame 4.6 cm
    d = a.pose - b.pose
    assert np.abs(d[:, :3]).max() <= 1e-5 and np.abs(d[:, 3:]).max() <= 1e-8
    assert a.controller_fallbacks == b.controller_fallbacks == 0


def test_both_plants_agree_over_a_rail_move_in_a_seaway():
    """A frame carried along a curved rail (issue 39) while the ship moves in a sea state:
    the closed loop on MuJoCo and on the own plant. Measured: 2.1e-8 m, 3.1e-8 deg (the issue
    asks 1e-4 m); MuJoCo's heavy ship body, driven along C's motion, follows it within 1.0e-6
    (with a yaw locked to the rail's tangent, whose rate steps at the joins, it lagged 7 mm and
    the plants parted by 1.04e-4 m)."""
    sc = marinecdpr.load_scenario("paper_sea")
    sc = sc.with_changes(ship={"carriage": {
        "rail_m": [[-0.78, 0.0, 2.2], [0.0, 0.0, 2.2], [1.0, 1.0, 2.2]], "corner_radius_m": 0.5,
        "speed_max_m_s": 0.6, "accel_max_m_s2": 0.8, "jerk_max_m_s3": 4.0, "stations_m": [0.0, 1.3], "dwell_s": 0.2}})
    a = simulate(sc, run="closed_loop", plant="mujoco", n_steps=3000)
    b = simulate(sc, run="closed_loop", plant="own", n_steps=3000)
    d = a.pose - b.pose
    assert np.abs(d[:, :3]).max() <= 1e-7
    assert np.degrees(np.abs(d[:, 3:]).max()) <= 1e-6
    assert a.ship_tracking_error < 3e-6
