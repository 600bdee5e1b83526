"""The controller's sensors as they are: a motion reference unit that samples late, the pose
from the winches' encoders, and the ship-motion prediction that makes up for the latency."""

import json

import numpy as np
import pytest
from typer.testing import CliRunner

import marinecdpr
from marinecdpr.cli.app import app
from marinecdpr.control import Controller
from marinecdpr.control.controller import plans
from marinecdpr.geometry.kinematics import cable_kinematics
from marinecdpr.geometry.pulley import pulley_kinematics
from marinecdpr.geometry.rotations import matrix_from_euler
from marinecdpr.motion.basemotion import evaluate_base_motion
from marinecdpr.prototype.parts.sensors import sensor_parts
from marinecdpr.prototype.simulation import simulate
from marinecdpr.studies.control import control_study

from conftest import make_scenario
from test_tension import EXAMPLES

runner = CliRunner()


def with_simulation(scenario, **sections):
    sim = scenario.simulation.model_dump(exclude_none=True)
    for key, value in sections.items():
        sim[key].update(value)
    return scenario.with_changes(simulation=sim)


def test_the_mru_gives_the_latest_sample_that_has_arrived_with_its_bias():
    """100 Hz, 20 ms late: at t_k the controller holds sample j = floor((t_k - 0.02) / 0.01)
    (the first until one has arrived), stamped j / 100 s, biased."""
    sc = with_simulation(marinecdpr.load_scenario("paper"),
                         mru={"rate_hz": 100.0, "latency_s": 0.02, "bias_m": [0.0, 0.0, 0.1],
                              "bias_deg": [1.0, 0.0, 0.0]})
    n, h = 200, sc.time.step_s
    ship_h = evaluate_base_motion(sc.base_motion, np.arange(2 * n + 1) * 0.5 * h)
    _, _, _, mru = sensor_parts(sc, "closed_loop", ship_h, n)
    for k, j in ((0, 0), (19, 0), (29, 0), (30, 1), (39, 1), (40, 2), (199, 17)):
        assert mru.latest[k] == j, k
    assert mru.t[17] == pytest.approx(0.17, abs=1e-15)
    true = evaluate_base_motion(sc.base_motion, np.array([0.17]))
    expect = true.eta[0] + [0.0, 0.0, 0.1, np.radians(1.0), 0.0, 0.0]
    np.testing.assert_allclose(mru.eta[0, 17], expect, atol=1e-15)
    np.testing.assert_allclose(mru.eta[1, 17], true.eta_dot[0], atol=1e-15)
    np.testing.assert_allclose(mru.eta[2, 17], true.eta_ddot[0], atol=1e-15)


def test_a_units_data_sheet_noise_reaches_the_samples():
    """The Kongsberg MRU 5: 200 Hz, roll and pitch 0.02 deg, heave 5 cm (FACTS.md)."""
    sc = with_simulation(marinecdpr.load_scenario("paper"), mru={"unit": "kongsberg_mru5"})
    n, h = 4000, sc.time.step_s
    ship_h = evaluate_base_motion(sc.base_motion, np.arange(2 * n + 1) * 0.5 * h)
    _, _, _, mru = sensor_parts(sc, "closed_loop", ship_h, n)
    assert mru.t[1] == pytest.approx(0.005) and mru.latest[-1] == 799
    err = mru.eta[0] - evaluate_base_motion(sc.base_motion, mru.t).eta
    assert np.degrees(err[:, 3:5].std(axis=0)) == pytest.approx([0.02, 0.02], rel=0.1)
    assert err[:, 2].std() == pytest.approx(0.05, rel=0.1)
    assert np.abs(err[:, [0, 1, 5]]).max() == 0.0
    # per axis, in place of the unit's
    sc = with_simulation(sc, mru={"noise_m": [0.0, 0.1, 0.0], "noise_deg": [0.0, 0.0, 0.5]})
    _, _, _, mru = sensor_parts(sc, "closed_loop", ship_h, n)
    err = mru.eta[0] - evaluate_base_motion(sc.base_motion, mru.t).eta
    assert err[:, 1].std() == pytest.approx(0.1, rel=0.1) and np.degrees(err[:, 5].std()) == pytest.approx(0.5, rel=0.1)
    assert np.abs(err[:, [0, 2, 3, 4]]).max() == 0.0


@pytest.mark.parametrize("source", ["paper", "cube8", "paper_as_built"])
def test_the_pose_from_the_encoders_commands_what_a_pose_sensor_would(source):
    """Stretched encoder lengths and their rates at a pose off the plan: forward kinematics and
    the rates' least squares give the controller the pose and twist a pose sensor gives it,
    so the commands agree to 1e-9 N; over pulleys too (paper_as_built's 25 mm)."""
    sc = (marinecdpr.load_scenario(source) if source != "cube8"
          else marinecdpr.load_scenario(EXAMPLES / "spatial_cube8.toml"))
    EA = 2.0e5
    sc = with_simulation(sc, cables={"model": "elastic", "stiffness_EA_N": EA})
    enc = with_simulation(sc, sensors={"pose_from": "encoders"})
    h, n = sc.time.step_s, 60
    ref = plans(sc, n).ref
    ship = evaluate_base_motion(sc.base_motion, np.arange(n) * h)
    eta = np.stack([ship.eta, ship.eta_dot, ship.eta_ddot], axis=1)
    by_sensor, by_encoders = Controller(sc, n_steps=n), Controller(enc, n_steps=n)
    rng = np.random.default_rng(4)
    robot = sc.robot
    free = np.zeros(6)
    free[list(robot.controlled)] = 1.0
    for k in range(0, n, 3):
        pose = ref.pose[k] + free * rng.normal(0.0, [2e-3] * 3 + [5e-3] * 3)
        twist = ref.twist[k] + free * rng.normal(0.0, 1e-2, 6)
        R = matrix_from_euler(pose[3:])
        if robot.has_pulleys:
            kin = pulley_kinematics(pose[None, :3], R[None], robot.frame_anchors, robot.pulley_axes,
                                    robot.pulley_radii, robot.platform_anchors, twist[None])
        else:
            kin = cable_kinematics(pose[None, :3], R[None], robot.frame_anchors, robot.platform_anchors, twist[None])
        T = rng.uniform(20.0, 400.0, robot.n_cables)
        T_s = by_sensor.step(k * h, x=pose[:3], R=R, v=twist[:3], w=twist[3:], eta=eta[k]).T_cmd.copy()
        cmd = by_encoders.step(k * h, eta=eta[k], lengths=kin.lengths[0] / (1.0 + T / EA),
                               length_rates=kin.length_rates[0], tensions=T)
        assert cmd.flags[2] == 0
        np.testing.assert_allclose(by_encoders.parts.work.q[list(robot.controlled)],
                                   pose[list(robot.controlled)], atol=1e-9)
        np.testing.assert_allclose(cmd.T_cmd, T_s, atol=1e-9)


def test_lengths_no_pose_has_are_flagged():
    sc = with_simulation(marinecdpr.load_scenario("paper"), sensors={"pose_from": "encoders"})
    ctl = Controller(sc, n_steps=10)
    ref = plans(sc, 10).ref
    L = cable_kinematics(ref.pose[None, 0, :3], matrix_from_euler(ref.pose[None, 0, 3:]),
                         sc.robot.frame_anchors, sc.robot.platform_anchors).lengths[0]
    cmd = ctl.step(0.0, eta=np.zeros((3, 6)), lengths=L * [1.0, 1.0, 1.3, 1.0], length_rates=np.zeros(4),
                   tensions=np.zeros(4))
    assert cmd.flags[2] == 1


def test_a_late_mru_costs_tracking_and_the_prediction_wins_it_back():
    """paper_sea, 100 Hz, 20 ms late: without prediction the closed loop's error grows
    several-fold over a sample at every exchange; the autoregressive predictor (warm after
    5 s) gives most of it back, the kinematic extrapolation some."""
    sc = with_simulation(marinecdpr.load_scenario("paper_sea"),
                         mru={"ar_warmup_s": 5.0, "ar_step_s": 0.1, "ar_order": 12})
    study = control_study(sc, latencies_s=(0.02,), predictions=("none", "kinematic", "ar"), pose_from=("sensor",),
                          duration_s=12.0, settle_s=6.0)
    short = sc.with_changes(time={"step_s": sc.time.step_s, "duration_s": 12.0})
    ideal = simulate(short, run="closed_loop", plant="own")
    e = np.linalg.norm(ideal.pose_error[ideal.t >= 6.0, :3], axis=1)
    base = np.sqrt(np.mean(e * e))
    none, kin, ar = (study.run(0.02, p).rms_error_m for p in ("none", "kinematic", "ar"))
    assert none > 5.0 * base
    assert base < kin < none
    assert ar - base < 0.2 * (none - base)


def test_control_study_command(tmp_path):
    res = runner.invoke(app, ["control-study", "paper_sea", "--latencies", "0,20", "--predictions", "none,ar",
                              "--pose-from", "sensor,encoders", "--encoder-resolution", "1e-4", "--duration", "3",
                              "--settle", "1", "--out", str(tmp_path / "cs")])
    assert res.exit_code == 0, res.output
    s = json.loads((tmp_path / "cs" / "summary.json").read_text())
    runs = {(r["latency_s"], r["prediction"], r["pose_from"]): r for r in s["runs"]}
    assert len(runs) == 8
    # 0.1 mm encoder steps cost tracking that a pose sensor without noise does not have
    assert runs[(0.0, "none", "encoders")]["rms_error_m"] > 2.0 * runs[(0.0, "none", "sensor")]["rms_error_m"]
    assert runs[(0.02, "none", "sensor")]["rms_error_m"] > runs[(0.0, "none", "sensor")]["rms_error_m"]
    rows = (tmp_path / "cs" / "prediction.csv").read_text().splitlines()
    assert rows[0] == "horizon_s,dof,predictor,kinematic,hold"
    for args, message in ((["--predictions", "magic"], "--predictions magic: expected one of none, kinematic, ar"),
                          (["--latencies", "ten"], "--latencies ten: expected numbers of ms"),
                          (["--duration", "5"], "--duration 5: must be longer than --settle")):
        res = runner.invoke(app, ["control-study", "paper_sea", "--out", str(tmp_path / "bad")] + args)
        assert res.exit_code == 2 and message in res.stderr, res.output
        assert len(res.stderr.strip().splitlines()) == 1
        assert not (tmp_path / "bad").exists()


def test_scenario_keys_of_the_sensors_are_checked():
    from marinecdpr.errors import ScenarioError

    for section, bad, message in (("mru", {"latency_s": -0.01}, "latency_s"), ("mru", {"unit": "mru9"}, "unit"),
                                  ("sensors", {"pose_from": "gps"}, "pose_from"),
                                  ("mru", {"ar_forgetting": 1.5}, "ar_forgetting"),
                                  ("mru", {"noise_deg": [0.1, -0.1, 0.0]}, "noise_deg: each entry must be >= 0")):
        with pytest.raises(ScenarioError, match=message):
            make_scenario(lambda d: d.setdefault("simulation", {}).update({section: bad}))
