"""A load cell's or an encoder's faults as a part after the sensors (issue 40, item 2): from
the fault's time (for its duration) the measurement holds what the faulty sensor gives,
frozen, drifting, lost (NaN) or non-finite; before it, and after it, what the sound one
gives."""

from __future__ import annotations

import numpy as np
import pytest

from marinecdpr import ScenarioError
from marinecdpr.prototype.parts import empty_signals, part_step
from marinecdpr.prototype.parts.sensors import sensor_faults
from marinecdpr.prototype.simulation import simulate
from marinecdpr.control.records import empty_measurement
from numba import njit

from conftest import make_scenario

H = 0.01


def with_faults(*faults):
    def edit(d):
        d["faults"] = list(faults)
    return make_scenario(edit)


@njit
def _fly(part, bus, T, L, Ldot, out):
    """Feed the sound readings T, L, Ldot (n, m) through the faults' step; the measurement
    after it at each exchange into out (n, 3, m)."""
    for k in range(T.shape[0]):
        for i in range(T.shape[1]):
            bus.meas.T[i] = T[k, i]
            bus.meas.L[i] = L[k, i]
            bus.meas.Ldot[i] = Ldot[k, i]
        part_step(k, H, part, bus)
        for i in range(T.shape[1]):
            out[k, 0, i] = bus.meas.T[i]
            out[k, 1, i] = bus.meas.L[i]
            out[k, 2, i] = bus.meas.Ldot[i]


def flown(*faults):
    s = with_faults(*faults)
    part = sensor_faults(s.faults, H)
    m, n = 4, 100
    t = np.arange(n) * H
    T = 100.0 + 10.0 * np.sin(t)[:, None] + np.arange(m)
    L = 1.0 + 0.1 * np.cos(t)[:, None] + 0.01 * np.arange(m)
    Ldot = -0.1 * np.sin(t)[:, None] + np.zeros(m)
    bus = empty_signals(empty_measurement(m), np.zeros(m), np.zeros(m), np.zeros(m))
    out = np.empty((n, 3, m))
    _fly(part, bus, T, L, Ldot, out)
    return t, (T, L, Ldot), out


def test_a_frozen_load_cell_repeats_its_reading_for_its_duration():
    t, (T, L, Ldot), out = flown({"kind": "load_cell", "cable": 2, "at_s": 0.3, "mode": "freeze", "duration_s": 0.4})
    np.testing.assert_array_equal(out[:30, 0], T[:30])
    np.testing.assert_array_equal(out[30:70, 0, 1], T[30, 1])  # the reading at 0.3 s, until 0.7 s
    np.testing.assert_array_equal(out[70:, 0], T[70:])
    np.testing.assert_array_equal(out[:, 0, [0, 2, 3]], T[:, [0, 2, 3]])
    np.testing.assert_array_equal(out[:, 1:], np.stack([L, Ldot], axis=1))


def test_a_drifting_encoder_adds_its_rate_times_the_time_since():
    """By hand: from 0.25 s the length reads L + 0.02 m/s (t - 0.25 s); its rate is sound."""
    t, (T, L, Ldot), out = flown({"kind": "encoder", "cable": 4, "at_s": 0.25, "mode": "drift",
                                  "drift_per_s": 0.02})
    np.testing.assert_array_equal(out[:25, 1, 3], L[:25, 3])
    np.testing.assert_allclose(out[25:, 1, 3], L[25:, 3] + 0.02 * (t[25:] - 0.25), rtol=0, atol=1e-15)
    np.testing.assert_array_equal(out[:, 2], Ldot)
    np.testing.assert_array_equal(out[:, 0], T)


@pytest.mark.parametrize("mode, value", [("dropout", np.nan), ("non_finite", np.inf)])
def test_a_lost_encoder_says_so(mode, value):
    t, (T, L, Ldot), out = flown({"kind": "encoder", "cable": 1, "at_s": 0.5, "mode": mode})
    np.testing.assert_array_equal(out[50:, 1:, 0], np.full((50, 2), value))
    np.testing.assert_array_equal(out[:50, 1, 0], L[:50, 0])
    np.testing.assert_array_equal(out[:, 1, 1:], L[:, 1:])


def test_a_frozen_encoder_derails_a_loop_that_flies_on_its_encoders():
    """The closed loop with the pose from the encoders: bit for bit the fault-free run until
    the encoder freezes at 0.5 s, then off the plan by far more than the sound run (measured
    0.137 m against 1.0e-7 m after 0.6 s)."""
    def edit(d):
        d["simulation"]["sensors"] = {"pose_from": "encoders"}
        d["time"] = {"step_s": 0.001, "duration_s": 1.5}
    sound = simulate(make_scenario(edit), run="closed_loop", plant="own")
    faulty_s = make_scenario(lambda d: (edit(d), d.update(faults=[{"kind": "encoder", "cable": 1, "at_s": 0.5,
                                                                  "mode": "freeze"}])))
    faulty = simulate(faulty_s, run="closed_loop", plant="own")
    np.testing.assert_array_equal(faulty.pose[:501], sound.pose[:501])
    err = lambda r: np.abs(r.pose_error[600:, [0, 2]]).max()  # noqa: E731
    assert err(sound) < 1e-6 and err(faulty) > 0.05
    assert faulty.faults[0]["acted_s"] == 0.5


@pytest.mark.parametrize("fault, key, says", [
    ({"kind": "load_cell", "cable": 1, "at_s": 1.0}, "faults[1].mode", "missing"),
    ({"kind": "encoder", "cable": 1, "at_s": 1.0, "mode": "drift"}, "faults[1].drift_per_s", "missing"),
    ({"kind": "encoder", "cable": 1, "at_s": 1.0, "mode": "freeze", "drift_per_s": 1.0}, "faults[1].drift_per_s",
     "is for a drifting sensor"),
    ({"kind": "cable_snap", "cable": 1, "at_s": 1.0, "mode": "freeze"}, "faults[1].mode", "is for a sensor's faults"),
    ({"kind": "load_cell", "cable": 1, "at_s": 1.0, "mode": "stuck"}, "faults[1].mode", "'freeze'"),
])
def test_a_sensor_fault_mistake_is_one_line(fault, key, says):
    with pytest.raises(ScenarioError) as err:
        with_faults(fault)
    text = str(err.value)
    assert "\n" not in text and f"{key}" in text and says in text, text


@njit
def _fly_mru(part, bus, eta, stamp, out, out_stamp):
    """Feed the MRU's sound samples eta (n, 3, 6) and stamps (n,) through the faults' step;
    the measurement's sample and stamp after it into out, out_stamp."""
    for k in range(eta.shape[0]):
        for d in range(3):
            for j in range(6):
                bus.meas.eta[d, j] = eta[k, d, j]
        bus.meas.clock[2] = stamp[k]
        part_step(k, H, part, bus)
        for d in range(3):
            for j in range(6):
                out[k, d, j] = bus.meas.eta[d, j]
        out_stamp[k] = bus.meas.clock[2]


def flown_mru(fault):
    """The MRU's samples (a ship rolling and heaving at 0.5 rad/s, a sample every 20 ms: the
    stamp is the latest one's) through the fault's part on the compiled step."""
    part = sensor_faults(with_faults(fault).faults, H)
    n = 100
    t = np.arange(n) * H
    eta = np.zeros((n, 3, 6))
    for j, a in ((2, 0.3), (3, 0.05)):  # heave (m) and roll (rad), and their rates
        eta[:, 0, j] = a * np.sin(0.5 * t)
        eta[:, 1, j] = 0.5 * a * np.cos(0.5 * t)
        eta[:, 2, j] = -0.25 * a * np.sin(0.5 * t)
    stamp = 0.02 * np.floor(t / 0.02 + 1e-9)
    bus = empty_signals(empty_measurement(4), np.zeros(4), np.zeros(4), np.zeros(4))
    out, out_stamp = np.empty((n, 3, 6)), np.empty(n)
    _fly_mru(part, bus, eta, stamp, out, out_stamp)
    return t, eta, stamp, out, out_stamp


def test_a_frozen_mru_repeats_its_sample_and_its_stamp_for_its_duration():
    """Frozen from 0.3 s for 0.4 s: the sample and its stamp (0.30 s) as at 0.3 s, so the
    sample ages; sound before and after."""
    t, eta, stamp, out, out_stamp = flown_mru({"kind": "mru", "at_s": 0.3, "mode": "freeze", "duration_s": 0.4})
    np.testing.assert_array_equal(out[:30], eta[:30])
    np.testing.assert_array_equal(out[30:70], np.broadcast_to(eta[30], (40, 3, 6)))
    np.testing.assert_array_equal(out_stamp[30:70], 0.3)
    np.testing.assert_array_equal(out[70:], eta[70:])
    np.testing.assert_array_equal(out_stamp[:30], stamp[:30])
    np.testing.assert_array_equal(out_stamp[70:], stamp[70:])


def test_a_drifting_mru_adds_its_rate_to_each_displacement():
    """By hand: from 0.25 s each of eta's six displacements reads eta + 0.01 (t - 0.25 s)
    (m on the translations, rad on the angles); its rates and its stamp are sound."""
    t, eta, stamp, out, out_stamp = flown_mru({"kind": "mru", "at_s": 0.25, "mode": "drift", "drift_per_s": 0.01})
    np.testing.assert_array_equal(out[:25], eta[:25])
    np.testing.assert_allclose(out[25:, 0], eta[25:, 0] + 0.01 * (t[25:, None] - 0.25), rtol=0, atol=1e-15)
    assert out[-1, 0, 0] == pytest.approx(0.01 * 0.74, abs=1e-15)  # surge: 0 + 0.01 m/s x 0.74 s
    np.testing.assert_array_equal(out[:, 1:], eta[:, 1:])
    np.testing.assert_array_equal(out_stamp, stamp)


@pytest.mark.parametrize("mode, value, stamp_lost", [("dropout", np.nan, True), ("non_finite", np.inf, False)])
def test_a_lost_mru_says_so(mode, value, stamp_lost):
    """Dropout: the sample and its stamp NaN; non-finite: the sample +inf, the stamp sound."""
    t, eta, stamp, out, out_stamp = flown_mru({"kind": "mru", "at_s": 0.5, "mode": mode})
    np.testing.assert_array_equal(out[50:], np.full((50, 3, 6), value))
    np.testing.assert_array_equal(out[:50], eta[:50])
    np.testing.assert_array_equal(out_stamp[:50], stamp[:50])
    np.testing.assert_array_equal(out_stamp[50:], np.full(50, np.nan) if stamp_lost else stamp[50:])


@pytest.mark.parametrize("mode, kind, step, reaction", [("non_finite", "non_finite", 200, None),
                                                        ("freeze", "dropout", None, "park")])
def test_the_watch_detects_a_frozen_or_non_finite_mru_in_a_run(mode, kind, step, reaction):
    """The paper's closed loop (a sample every exchange, no latency) with the MRU failing at
    0.2 s: a non-finite sample detected at that exchange; a frozen one as dropped out once its
    stamp (0.2 s) is older than mru_timeout_s, at the first t_k with t_k - 0.2 s > that (0.701
    s), and the controller parks; the run bit for bit the sound one (which detects nothing)
    before the fault. (On a non-finite sample the present reaction goes to the brakes: the
    sample reaches the state estimate; not pinned here.)"""
    def edit(d):
        d["time"] = {"step_s": 0.001, "duration_s": 1.0}
    s = make_scenario(lambda d: (edit(d), d.update(faults=[{"kind": "mru", "at_s": 0.2, "mode": mode}])))
    r = simulate(s, run="closed_loop", plant="own")
    sound = simulate(make_scenario(edit), run="closed_loop", plant="own")
    timeout = s.simulation.control.safety.mru_timeout_s
    if step is None:
        step = int(np.floor((0.2 + timeout) / 0.001 + 1e-9)) + 1
    [d] = r.detections
    assert (d.sensor, d.kind, d.step) == ("mru", kind, step)
    assert sound.detections == () and (reaction is None or r.reaction == reaction)
    np.testing.assert_array_equal(r.pose[:201], sound.pose[:201])
    assert np.isfinite(r.pose).all()


@pytest.mark.parametrize("fault, key, says", [
    ({"kind": "mru", "cable": 1, "at_s": 0.5, "mode": "freeze"}, "faults[1].cable", "leave it out"),
    ({"kind": "mru", "at_s": 0.5}, "faults[1].mode", "missing"),
    ({"kind": "mru", "at_s": 0.5, "mode": "drift"}, "faults[1].drift_per_s", "rad/s on the mru"),
])
def test_an_mru_fault_mistake_is_one_line(fault, key, says):
    with pytest.raises(ScenarioError) as err:
        with_faults(fault)
    text = str(err.value)
    assert "\n" not in text and key in text and says in text, text
