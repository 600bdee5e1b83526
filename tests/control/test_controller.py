"""The controller a user calls (`marinecdpr.control.Controller`): on the plan, without error
or noise, it commands the planner's tensions for every method and redundancy; its
commands follow the error the way computed torque says; the prototype's closed loop is
that same step."""

import numpy as np
import pytest
from numba import njit, typeof

import marinecdpr
from marinecdpr.borrowed import data_address, load
from marinecdpr.errors import InfeasibleError
from marinecdpr.control import Controller
from marinecdpr.control.controller import controller_records, plans
from marinecdpr.control.records import encoders_record
from marinecdpr.control.step import encoders_pose, pose_from_encoders, ship_forecast
from marinecdpr.motion.prediction import make_predictor, predictor_forecast, predictor_update
from marinecdpr.geometry.rotations import matrix_from_euler
from marinecdpr.model.tension_solver import METHOD_CODES
from marinecdpr.motion.basemotion import evaluate_base_motion

from conftest import make_scenario
from test_tension import EXAMPLES

N = 300  # steps: 0.3 s


def six_cables(data):
    """The paper's robot with two more cables at mid-height (r = 3)."""
    data["robot"]["cables"] += [
        {"frame_anchor_m": [0.0, 0.0, 0.7], "platform_anchor_m": [-0.125, 0.0, 0.0]},
        {"frame_anchor_m": [1.9, 0.0, 0.7], "platform_anchor_m": [0.125, 0.0, 0.0]},
    ]


def suspended(data):
    """The paper's frame with every cable from its top edge: gravity keeps every tension
    positive, so even the pseudo-inverse stays within limits (the first second of the circle)."""
    data["robot"]["cables"] = [
        {"frame_anchor_m": [0.0, 0.0, 1.4], "platform_anchor_m": [-0.125, 0.0, 0.15]},
        {"frame_anchor_m": [1.9, 0.0, 1.4], "platform_anchor_m": [0.125, 0.0, 0.15]},
        {"frame_anchor_m": [0.7, 0.0, 1.4], "platform_anchor_m": [0.1, 0.0, 0.1]},
        {"frame_anchor_m": [1.2, 0.0, 1.4], "platform_anchor_m": [-0.1, 0.0, 0.1]},
    ]


def with_method(scenario, method):
    return scenario.model_copy(update={"planning": scenario.planning.model_copy(update={"method": method})})


ROBOTS = {
    "paper (r = 1)": lambda: marinecdpr.load_scenario("paper"),
    "spatial_cube8 (r = 2)": lambda: marinecdpr.load_scenario(EXAMPLES / "spatial_cube8.toml"),
    "six cables (r = 3)": lambda: make_scenario(six_cables),
    "suspended (r = 1)": lambda: make_scenario(suspended),
}


def on_the_plan(scenario, n=N):
    """The plan at mid-step as the controller's measurements: pose, twist and the ship's
    motion, time-stamped at t_k + h/2."""
    h = scenario.time.step_s
    ff = plans(scenario, n).ff
    ship = evaluate_base_motion(scenario.base_motion, (np.arange(n) + 0.5) * h)
    eta = np.stack([ship.eta, ship.eta_dot, ship.eta_ddot], axis=1)  # (n, 3, 6)
    return ff, matrix_from_euler(ff.pose[:, 3:]), eta


@pytest.mark.parametrize("robot", ROBOTS)
@pytest.mark.parametrize("method", METHOD_CODES)
def test_on_the_plan_it_commands_the_planners_tensions(robot, method):
    scenario = with_method(ROBOTS[robot](), method)
    h = scenario.time.step_s
    try:
        ff, R, eta = on_the_plan(scenario)
    except InfeasibleError:  # the method leaves the limits on this path: no plan to track
        assert method in ("pseudo_inverse", "closed_form")
        assert (robot, method) != ("suspended (r = 1)", "pseudo_inverse")  # every method runs somewhere
        pytest.skip(f"{method} has no plan within limits on {robot}")
    ctl = Controller(scenario, n_steps=N)
    worst = 0.0
    for k in range(0, N, 7):
        t = k * h
        cmd = ctl.step(t, x=ff.pose[k, :3], R=R[k], v=ff.twist[k, :3], w=ff.twist[k, 3:], eta=eta[k],
                       t_pose=t + 0.5 * h, t_ship=t + 0.5 * h)
        assert cmd.flags[0] == 0
        worst = max(worst, np.abs(cmd.T_cmd - ff.tensions[k]).max())
    assert worst < 1e-9  # N


def test_commands_follow_a_position_error_as_computed_torque_says():
    """An error e along x asks m kp e more force along x (eq. 15 with a = a_ref + kp e), and
    the commanded tensions make the wrench asked for (J~^T T = w on the controlled DOFs)."""
    scenario = marinecdpr.load_scenario("paper")
    h = scenario.time.step_s
    ff, R, eta = on_the_plan(scenario, 50)
    ctl = Controller(scenario, n_steps=50)
    k, t, e = 20, 20 * h, 1e-3
    args = dict(R=R[k], v=ff.twist[k, :3], w=ff.twist[k, 3:], eta=eta[k], t_pose=t + 0.5 * h, t_ship=t + 0.5 * h)
    dofs = list(scenario.robot.controlled)
    wrench = []
    for x in (ff.pose[k, :3], ff.pose[k, :3] - [e, 0.0, 0.0]):
        T = ctl.step(t, x=x, **args).T_cmd
        w = ctl.parts.work.wrench.copy()
        np.testing.assert_allclose((ctl.parts.work.J.T @ T)[dofs], w[dofs], atol=1e-9)
        wrench.append(w)
    # the ship's inertial terms change with x by O(omega^2 e m): 1e-5 of it here
    assert wrench[1][0] - wrench[0][0] == pytest.approx(scenario.robot.mass_kg * ctl.parts.gains.kp * e, rel=1e-3)
    assert abs(wrench[1][2] - wrench[0][2]) < 1e-3 * scenario.robot.mass_kg * ctl.parts.gains.kp * e


def test_at_limit_flags_say_which_cables_are_at_a_limit():
    scenario = marinecdpr.load_scenario("paper")
    h = scenario.time.step_s
    ff, R, eta = on_the_plan(scenario, 50)
    ctl = Controller(scenario, n_steps=50)
    k = 10
    # a large error to the left asks the right-hand cables for more than they may give
    cmd = ctl.step(k * h, x=ff.pose[k, :3] + [0.5, 0.0, 0.0], R=R[k], v=ff.twist[k, :3], w=ff.twist[k, 3:],
                   eta=eta[k])
    lo, hi = scenario.robot.tension_min, scenario.robot.tension_max
    expect = np.where(cmd.T_cmd <= lo + 1e-6, -1, np.where(cmd.T_cmd >= hi - 1e-6, 1, 0))
    np.testing.assert_array_equal(cmd.at_limit, expect)
    assert cmd.flags[1] == np.count_nonzero(expect)


def test_a_time_outside_the_plan_is_refused():
    ctl = Controller(marinecdpr.load_scenario("paper"), n_steps=10)
    with pytest.raises(ValueError, match="outside the controller's plan"):
        ctl.step(1.0, x=np.zeros(3), R=np.eye(3), v=np.zeros(3), w=np.zeros(3), eta=np.zeros((3, 6)))


def test_latency_times_the_step_and_quadprog_solves_the_same_problem():
    """`marinecdpr latency --json` prints the figures; the quadprog problem it times is the
    step's own (its optimum is the step's minimum-variance tensions)."""
    import json

    import quadprog
    from typer.testing import CliRunner

    from marinecdpr.cli.app import app
    from marinecdpr.studies.latency import quadprog_problem

    result = CliRunner().invoke(app, ["latency", "paper", "--calls", "30", "--json"])
    assert result.exit_code == 0, result.output
    figures = json.loads(result.stdout)  # stderr may hold the compile notice
    for where in ("python", "compiled"):
        assert 0 < figures[f"{where}_p50_us"] <= figures[f"{where}_p99_us"] <= figures[f"{where}_max_us"]
    assert figures["quadprog_p50_us"] > 0 and figures["calls"] == 30 and figures["redundancy"] == 1
    for robot in ("paper (r = 1)", "spatial_cube8 (r = 2)", "six cables (r = 3)"):
        scenario = ROBOTS[robot]()
        h = scenario.time.step_s
        ff, R, eta = on_the_plan(scenario, 40)
        ctl = Controller(scenario, n_steps=40)
        k = 30
        cmd = ctl.step(k * h, x=ff.pose[k, :3] + 0.002, R=R[k], v=ff.twist[k, :3], w=ff.twist[k, 3:], eta=eta[k])
        assert cmd.flags[0] == 0
        np.testing.assert_allclose(quadprog.solve_qp(*quadprog_problem(ctl))[0], cmd.T_cmd, atol=1e-6)


def test_the_examples_python_loop_flies_as_the_prototypes_compiled_loop():
    """examples/controller_loop.py: the Controller called from Python against the rig's
    MuJoCo plant moves the platform exactly as simulate's compiled closed loop (the same
    step, the same plant, no sensor noise)."""
    import runpy
    from pathlib import Path

    from marinecdpr.prototype.simulation import simulate

    example = runpy.run_path(str(Path(__file__).resolve().parents[2] / "examples" / "controller_loop.py"))
    sc, poses = example["fly"](0.5)
    res = simulate(sc, run="closed_loop", plant="mujoco")
    np.testing.assert_allclose(poses, res.pose[:, :3], rtol=0, atol=1e-12)
    assert np.abs(poses - res.pose_planned[:, :3]).max() < 1e-5


def _variant(encoders=False, ar=False, pulleys=False, heavy=False):
    def edit(d):
        if encoders:
            d["simulation"]["sensors"] = {"pose_from": "encoders"}
        if ar:
            d["simulation"]["mru"] = {"prediction": "ar", "latency_s": 0.05}
        if pulleys:
            for cable in d["robot"]["cables"]:
                cable["pulley_radius_m"] = 0.05
                cable["pulley_axis"] = [0.0, 0.0, 1.0]
        if heavy:
            d["robot"]["cable_weight_N_m"] = 3.5
            d["simulation"]["plant"] = "own"
            d["simulation"]["cables"] = {"model": "catenary", "stiffness_EA_N": 1.0e5}
    return make_scenario(edit)


VARIANTS = {"paper": {}, "encoders": dict(encoders=True), "ar": dict(ar=True),
            "encoders, ar, pulleys": dict(encoders=True, ar=True, pulleys=True), "catenary": dict(heavy=True)}


@njit
def _by_address(slot, t_s, eta, t, fc):
    return ship_forecast(slot, t_s, eta, t, fc)


@njit
def _forecast_directly(slot, t_s, eta, t, fc, ty):
    pred = load(data_address(slot.words) + 8, ty)
    predictor_update(pred, t_s, eta[0], eta[1], eta[2])
    return predictor_forecast(pred, t, fc)


@njit
def _encoders_by_address(slot):
    return encoders_pose(slot)


@njit
def _encoders_directly(slot, ty):
    return pose_from_encoders(load(data_address(slot.words) + 8, ty))


def test_every_controller_is_one_type_its_slots_holding_what_it_has():
    """The ship-motion predictor and the encoders' forward kinematics sit in slots by address
    (issue 37, the suite on a cold cache: the step compiled once, not once per combination):
    every controller's records are of one numba type; a slot holds a function where the
    scenario asks for it, and that function called by address does what it does called
    directly, bit for bit (two controllers fed the same samples)."""
    n = 40
    records = {}
    for name, options in VARIANTS.items():
        sc = _variant(**options)
        records[name] = [controller_records(sc, plans(sc, n), n, closed=True) for _ in range(2)] + [plans(sc, n)]
    assert len({typeof(r[0]) for r in records.values()}) == 1
    for name, (a, b, p) in records.items():
        assert (a.predictor.words[0] != 0) == VARIANTS[name].get("ar", False)
        assert (a.encoders.words[0] != 0) == VARIANTS[name].get("encoders", False)

    # the AR predictor: a ship rolling and heaving, sampled at 20 Hz, forecast 0.1 s ahead
    a, b, _ = records["ar"]
    ty = typeof(make_predictor(step_s=0.1, order=4, forgetting=0.99))
    fa, fb = np.zeros((3, 6)), np.zeros((3, 6))
    statuses, errors = [], []
    for i in range(400):
        t = 0.05 * i
        w = np.array([0.5, 0.6, 0.7, 0.8, 0.9, 1.0])
        eta = np.stack([0.3 * np.sin(w * t), 0.3 * w * np.cos(w * t), -0.3 * w**2 * np.sin(w * t)])
        s_a = _by_address(a.predictor, t, eta, t + 0.1, fa)
        s_b = _forecast_directly(b.predictor, t, eta, t + 0.1, fb, ty)
        assert s_a == s_b
        np.testing.assert_array_equal(fa, fb)
        statuses.append(s_a)
        if s_a >= 0:
            errors.append(np.abs(fa[0] - 0.3 * np.sin(w * (t + 0.1))).max())
    assert len(errors) > 300 and max(errors[-100:]) < 1e-3  # it forecasts, and well

    # the encoders: the planned lengths and tensions give the planned pose, both ways
    for name in ("encoders", "encoders, ar, pulleys"):
        a, b, p = records[name]
        ty = typeof(encoders_record(b.meas, b.model, b.gains, b.work))
        for k in (0, n // 2, n - 1):
            for r in (a, b):
                r.meas.L[:] = p.ff.lengths[k]
                r.meas.Ldot[:] = p.ff.length_rates[k]
                r.meas.T[:] = p.ff.tensions[k]
            assert _encoders_by_address(a.encoders) == _encoders_directly(b.encoders, ty) == 0
            for f in ("x", "v", "w", "R"):
                np.testing.assert_array_equal(getattr(a.meas, f), getattr(b.meas, f))
            np.testing.assert_allclose(a.meas.x, p.ff.pose[k, :3], rtol=0, atol=1e-6)
