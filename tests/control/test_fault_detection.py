"""The controller's fault detection and reaction (issue 40, item 3), through
:class:`~marinecdpr.control.Controller` as a user's loop calls it, with synthetic measurements:
the plan itself, measured perfectly, and one sensor made to lie from a chosen step."""

from __future__ import annotations

import numpy as np
import pytest

import marinecdpr
from marinecdpr.control import Controller

from conftest import make_scenario
from test_controller import on_the_plan, six_cables

N = 120  # steps: 0.12 s
K0 = 40  # the step the fault starts


def fly(scenario, fault, n=N, **given):
    """The controller on the plan (pose sensor, MRU at mid-step, load cells reading the last
    command, encoders the plan's lengths) with ``fault(k, meas)`` editing the measurement
    dict at each step; the commands (copies) and the controller."""
    h = scenario.time.step_s
    ff, R, eta = on_the_plan(scenario, n)
    ctl = Controller(scenario, n_steps=n)
    out = []
    for k in range(n):
        t = k * h
        meas = dict(x=ff.pose[k, :3].copy(), R=R[k], v=ff.twist[k, :3], w=ff.twist[k, 3:], eta=eta[k].copy(),
                    t_pose=t + 0.5 * h, t_ship=t + 0.5 * h, tensions=ctl.command.T_cmd.copy(),
                    lengths=ff.lengths[k].copy(), length_rates=ff.length_rates[k].copy())
        meas.update(given)
        fault(k, meas)
        cmd = ctl.step(t, **meas)
        out.append((cmd.T_cmd.copy(), cmd.brake.copy(), ctl.parts.work.J.copy(), ctl.parts.work.wrench.copy(),
                    ctl.reaction))
    return out, ctl


def cut(cable):
    def fault(k, meas):
        if k >= K0:
            meas["tensions"][cable] = 0.0
    return fault


def no_fault(k, meas):
    pass


@pytest.fixture(scope="module")
def six():
    return make_scenario(six_cables)


@pytest.mark.parametrize("cable", [2, 4])
def test_a_load_cell_reading_zero_loses_its_cable_after_the_delay_and_the_rest_hold_the_wrench(six, cable):
    """Six cables (r = 3): cable i's load cell reads 0 from step K0; after slack_delay_s (20
    exchanges: the 20th low reading, step K0 + 19) cable i is lost and the controller goes
    on along the plan with J~^T T = w on the controlled DOFs, T_i = 0, every other tension
    within its limits."""
    out, ctl = fly(six, cut(cable))
    steps = ctl.parts.safety.slack_steps
    assert steps == 20
    [d] = ctl.detections
    assert (d.step, d.kind, d.cable) == (K0 + steps - 1, "cable_slack", cable)
    assert [o[4] for o in out[:K0 + steps - 1]] == ["normal"] * (K0 + steps - 1)
    dofs = list(six.robot.controlled)
    lo, hi = six.robot.tension_min, six.robot.tension_max
    others = np.arange(6) != cable
    worst = 0.0
    for T, brake, J, w, mode in out[K0 + steps - 1:]:
        assert mode == "go_on"
        assert T[cable] == 0.0
        assert np.all(T[others] >= lo[others] - 1e-9) and np.all(T[others] <= hi[others] + 1e-9)
        assert not brake.any()
        worst = max(worst, np.abs((J.T @ T)[dofs] - w[dofs]).max())
    assert worst < 1e-9  # N, N m


def test_it_goes_on_exactly_where_an_lp_finds_tensions_without_the_cable(six):
    """Which lost cable the remaining five can replace, against scipy's linear program (an
    independent solver) on the same J~ and wrench at the detection's step: the two top cables
    (0, 1) cannot (the stop cannot either: the brakes), the other four can."""
    from scipy.optimize import linprog

    dofs = list(six.robot.controlled)
    modes = []
    for cable in range(6):
        out, ctl = fly(six, cut(cable), n=K0 + 21)
        T, brake, J, w, mode = out[K0 + 19]
        lo, hi = six.robot.tension_min.copy(), six.robot.tension_max.copy()
        lo[cable] = hi[cable] = 0.0
        lp = linprog(np.zeros(6), A_eq=J[:, dofs].T, b_eq=w[dofs], bounds=list(zip(lo, hi)))
        assert (mode == "go_on") == (lp.status == 0)
        modes.append(mode)
    assert modes == ["brake", "brake", "go_on", "go_on", "go_on", "go_on"]


def test_before_the_delay_a_low_reading_is_no_detection(six):
    """A load cell reading 0 for one exchange less than the delay, then right again: nothing
    detected, and every command is the fault-free run's, bit for bit."""
    steps = 20

    def blip(k, meas):
        if K0 <= k < K0 + steps - 1:
            meas["tensions"][2] = 0.0

    out, ctl = fly(six, blip)
    ref, _ = fly(six, no_fault)
    assert ctl.detections == []
    for a, b in zip(out, ref):
        np.testing.assert_array_equal(a[0], b[0])


def test_a_lost_cable_the_rest_cannot_replace_stops_and_brakes():
    """The paper's four cables (r = 1): without one, the three left cannot hold the plan nor
    the stop within their limits (their unique tensions leave [10, 450] N): the brakes."""
    paper = marinecdpr.load_scenario("paper")
    out, ctl = fly(paper, cut(1))
    [d] = ctl.detections
    assert (d.step, d.cable) == (K0 + 19, 1)
    T, brake, *_ , mode = out[-1]
    assert mode == "brake"
    np.testing.assert_array_equal(brake, [1, 0, 1, 1])
    assert T[1] == 0.0


def test_park_holds_the_pose_where_the_loss_was_detected(six):
    """With on_cable_loss = "park" the controller holds the plan's pose of the detection's
    step (cable 4 lost: the park's deceleration from 0.16 m/s at kd = 63 1/s is within the
    other five's limits; without cable 2 or 3 it is not, and the controller stops instead);
    measured there at rest afterwards, it asks for no acceleration, and its tensions make the
    wrench with T_4 = 0."""
    data_six = six.model_dump(exclude_none=True)
    parked = six.with_changes(simulation={**data_six["simulation"],
                                          "control": {**data_six["simulation"]["control"],
                                                      "safety": {"on_cable_loss": "park"}}})
    k_d = K0 + 19
    ff, R, _ = on_the_plan(parked, N)

    def cut_and_stay(k, meas):  # the platform stays where it was at the detection, at rest
        cut(4)(k, meas)
        if k > k_d:
            meas.update(x=ff.pose[k_d, :3].copy(), R=R[k_d], v=np.zeros(3), w=np.zeros(3))

    out, ctl = fly(parked, cut_and_stay)
    assert ctl.reaction == "park"
    s = ctl.parts.safety
    np.testing.assert_array_equal(s.hold_x, ff.pose[k_d, :3])
    np.testing.assert_array_equal(s.hold_R, R[k_d])
    dofs = list(six.robot.controlled)
    for T, brake, J, w, mode in out[k_d:]:
        assert mode == "park" and T[4] == 0.0
        assert np.abs((J.T @ T)[dofs] - w[dofs]).max() < 1e-9
    # held at rest where it is: no acceleration asked, the wrench is the plan's less its inertia
    assert np.abs(ctl.parts.work.a_cmd).max() < 1e-12


@pytest.mark.parametrize("what, sensor, kind", [
    ("nan pose", "pose", "non_finite"),
    ("frozen pose", "pose", "frozen"),
    ("jumping pose", "pose", "jump"),
    ("nan load cell", "load_cell", "non_finite"),
    ("frozen encoder", "encoder", "frozen"),
    ("mru dropout", "mru", "dropout"),
    ("mru nan", "mru", "non_finite"),
    ("encoders disagree", "encoder", "disagree"),
])
def test_a_lying_sensor_is_detected_and_the_controller_parks(six, what, sensor, kind):
    """Each sensor fault from step K0, on a plan that moves (the paper's circle, some 0.2 m/s:
    0.2 mm an exchange): detected at the step the stated rule says, and the controller parks."""
    h = six.time.step_s
    s0 = Controller(six, n_steps=2).parts.safety
    held = {}

    def fault(k, meas):
        if k < K0:
            return
        if what == "nan pose":
            meas["x"][1] = np.nan
        elif what == "frozen pose":
            held.setdefault("x", meas["x"].copy())
            meas["x"] = held["x"].copy()
        elif what == "jumping pose":
            meas["x"] = meas["x"] + [0.06, 0.0, 0.0]
        elif what == "nan load cell":
            meas["tensions"][5] = np.inf
        elif what == "frozen encoder":
            held.setdefault("L", meas["lengths"].copy())
            meas["lengths"] = held["L"].copy()
        elif what == "mru dropout":  # its last sample: K0's
            meas["t_ship"] = (K0 + 0.5) * h
        elif what == "mru nan":  # lost, as the prototype's MRU fault reads it: no sample, no stamp
            meas["eta"][:] = np.nan
            meas["t_ship"] = np.nan
        elif what == "encoders disagree":  # cable 2's encoder drifts 1.1 mm an exchange
            meas["lengths"][2] += 0.0011 * (k - K0 + 1)

    n = {"frozen pose": 400, "frozen encoder": 400, "mru dropout": 600, "encoders disagree": 160}.get(what, N)
    out, ctl = fly(six, fault, n=n)
    [d] = ctl.detections
    assert (d.sensor, d.kind) == (sensor, kind)
    ff, R, _ = on_the_plan(six, n)
    if what == "frozen pose":  # the first step at which the plan moved more than frozen_m under it
        moved = np.cumsum(np.linalg.norm(np.diff(ff.pose[K0:, :3], axis=0), axis=1))
        expect = K0 + 1 + int(np.argmax(moved > s0.frozen_m))
    elif what == "frozen encoder":  # the first cable whose plan length moved more than frozen_m
        moved = np.cumsum(np.abs(np.diff(ff.lengths[K0:], axis=0)), axis=0)
        first = np.array([np.argmax(moved[:, i] > s0.frozen_m) if (moved[:, i] > s0.frozen_m).any() else n
                          for i in range(6)])
        expect = K0 + 1 + int(first.min())
        assert d.cable == int(np.argmin(first))
    elif what == "mru dropout":  # 0.5 s past the sample's latency (0) and period (one exchange)
        assert s0.mru_timeout_s == pytest.approx(0.5 + h)
        expect = K0 + 502  # its age (k - K0 - 1/2) h passes 0.501 s
    elif what == "encoders disagree":  # 46 x 1.1 mm > 50 mm > 45 x 1.1 mm, then 20 exchanges
        expect = K0 + 45 + s0.disagree_steps - 1
        assert d.cable == 2
    else:
        expect = K0
    assert d.step == expect
    assert ctl.reaction == "park"
    assert all(o[4] == "normal" for o in out[:expect])
    if sensor == "mru":  # parked on the last sound sample: tensions that hold the wrench, no brake
        dofs = list(six.robot.controlled)
        for T, brake, J, w, mode in out[expect:]:
            assert np.isfinite(T).all() and not brake.any()
            assert np.abs((J.T @ T)[dofs] - w[dofs]).max() < 1e-9


def test_on_the_plan_nothing_is_detected_and_the_watch_changes_no_command(six):
    """Fault-free: no detection, and the commands are those of a controller without the watch
    (``detect = false``), bit for bit."""
    out, ctl = fly(six, no_fault)
    assert ctl.detections == [] and ctl.reaction == "normal"
    data_six = six.model_dump(exclude_none=True)
    off = six.with_changes(simulation={**data_six["simulation"],
                                       "control": {**data_six["simulation"]["control"], "safety": {"detect": False}}})
    ref, ctl_off = fly(off, no_fault)
    for a, b in zip(out, ref):
        np.testing.assert_array_equal(a[0], b[0])
    assert ctl_off.parts.safety.peak.max() == 0.0  # not watched
    assert ctl.parts.safety.peak.max() < 1e-9  # measured exactly on the plan: every residual 0


def test_the_watch_and_the_reaction_allocate_nothing_beyond_the_normal_step(six):
    """numba's runtime counts allocations: a step on the plan and a step that goes on without
    a lost cable (the watch, the tension method with the cable's limits 0) allocate the same
    (9 a call here: the arrays handed in, unboxed), nothing per step of their own."""
    from numba.core.runtime import _nrt_python, rtsys

    h = six.time.step_s
    ff, R, eta = on_the_plan(six, N)
    was = _nrt_python.memsys_stats_enabled()
    _nrt_python.memsys_enable_stats()
    try:
        counts = {}
        for cut_at in (N, K0):
            ctl = Controller(six, n_steps=N)
            per_step = set()
            for k in range(N):
                t = k * h
                T = ctl.command.T_cmd.copy()
                if k >= cut_at:
                    T[4] = 0.0
                a0 = rtsys.get_allocation_stats().alloc
                ctl.step(t, x=ff.pose[k, :3], R=R[k], v=ff.twist[k, :3], w=ff.twist[k, 3:], eta=eta[k],
                         t_pose=t + 0.5 * h, t_ship=t + 0.5 * h, tensions=T)
                per_step.add(rtsys.get_allocation_stats().alloc - a0)
            counts[ctl.reaction] = per_step
    finally:
        if not was:
            _nrt_python.memsys_disable_stats()
    assert counts["normal"] == counts["go_on"] and len(counts["normal"]) == 1


# ------------------------------------------------------------------ a motor's current
TAU_MAX = 2.0  # N m: test_winch_faults' drive


def _motor_winches(data):
    data["simulation"]["cables"] = {"model": "elastic", "stiffness_EA_N": 1.0e5, "damping_N_s_m": 0.0, "winch": "motor"}
    data["robot"]["winch"] = {"drum_radius_m": 0.05, "gear_ratio": 10.0, "torque_max_Nm": TAU_MAX,
                              "speed_max_rad_s": 300.0, "power_max_W": 200.0, "rotor_inertia_kg_m2": 1.0e-4,
                              "drum_inertia_kg_m2": 1.0e-3, "gear_efficiency": 1.0, "coulomb_friction_Nm": 0.0,
                              "viscous_friction_Nm_s": 0.0}


def _torque_off(cable, share):
    """Motor ``cable``'s torque (from its current) ``share`` of its torque limit above its
    drive's demand (0.4 N m) from step K0; the others' as demanded."""
    def fault(k, meas):
        demand = np.full(len(meas["tensions"]), 0.4)
        torque = demand.copy()
        if k >= K0:
            torque[cable] += share * TAU_MAX
        meas["motor_torques"], meas["motor_demands"] = torque, demand
    return fault


@pytest.fixture(scope="module")
def motors():
    """Six cables (r = 3: the other five hold the wrench without one) on motor winches."""
    return make_scenario(lambda d: (six_cables(d), _motor_winches(d)))


def test_a_motor_whose_current_leaves_its_demand_fails_its_drive_and_its_cable_is_lost(motors):
    """Cable 3's motor gives 0.3 tau_max more than its drive asks from step K0 (a stall's
    signature): 1.5 times current_fraction (0.2) of its limit, so on the 20th such exchange
    (current_delay_s 0.02 s at 1 ms: step K0 + 19) its drive has failed, kind "drive": its cable
    is lost (its command 0, no brake), the other five holding the wrench on the plan (go on, as
    after a lost cable: J~^T T = w over the rest); until then every command is the fault-free run's, bit for bit, and the
    watched residual's peak is 1.5 (by hand: 0.3 / 0.2)."""
    out, ctl = fly(motors, _torque_off(2, 0.3))
    ref, _ = fly(motors, no_fault)
    det = ctl.detections
    assert [(d.step, d.kind, d.sensor, d.cable) for d in det] == [(K0 + 19, "drive", "", 2)]
    for k in range(K0 + 19):
        np.testing.assert_array_equal(out[k][0], ref[k][0])
        assert out[k][4] == "normal" and not out[k][1].any()
    for k in range(K0 + 19, N):
        T, brake, J, w, mode = out[k]
        assert mode == "go_on" and not brake.any() and T[2] == 0.0 and not J[2].any()
        c = [0, 2, 4]  # the planar robot's controlled DOFs
        np.testing.assert_allclose((J.T @ T)[c], w[c], rtol=0.0, atol=1e-9 * np.abs(w).max())
    assert ctl.parts.safety.peak[5] == pytest.approx(1.5, rel=1e-12)


def test_a_motor_within_its_band_is_never_a_fault(motors):
    """0.19 tau_max off its demand (0.95 of the band) for the whole run: no detection, the same
    commands as the run without, and the residual's peak 0.95; a torque given without its
    demand is refused in one line."""
    out, ctl = fly(motors, _torque_off(3, 0.19))
    ref, _ = fly(motors, no_fault)
    assert ctl.detections == [] and all(o[4] == "normal" for o in out)
    for a, b in zip(out, ref):
        np.testing.assert_array_equal(a[0], b[0])
    assert ctl.parts.safety.peak[5] == pytest.approx(0.95, rel=1e-12)
    with pytest.raises(ValueError, match="motor_torques and motor_demands go together"):
        fly(motors, lambda k, meas: meas.update(motor_torques=np.zeros(4)), n=2)


def test_without_motor_winches_the_current_is_not_watched():
    """The paper's ideal cables have no motor: a torque far from its demand changes nothing."""
    sc = make_scenario()
    out, ctl = fly(sc, _torque_off(0, 5.0))
    ref, _ = fly(sc, no_fault)
    assert ctl.detections == [] and ctl.parts.safety.peak[5] == 0.0
    for a, b in zip(out, ref):
        np.testing.assert_array_equal(a[0], b[0])
