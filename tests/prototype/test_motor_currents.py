"""The motor winches' measured currents (issue 40: detection from what the controller measures,
no false alarm in normal work): ``[simulation.noise] motor_torque_N_m`` puts a seeded noise on
the motor torques the closed-loop controller reads (:class:`~marinecdpr.prototype.parts.sensors.MotorCurrents`),
not on the drives' demands nor on what acts on the drums. paper_as_built's motor winches
(2 N m motors), flown on the own plant for a few seconds."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.stats import chi2

import marinecdpr
from marinecdpr.geometry.rotations import matrix_from_euler
from marinecdpr.prototype.parts import exchange
from marinecdpr.prototype.parts.sensors import MotorCurrents, motor_currents
from marinecdpr.prototype.simulation import prototype, simulate

TAU_MAX = 2.0  # paper_as_built's motors' torque limit, N m
SIGMA = 0.02 * TAU_MAX  # a servo drive's current measured to 2 % of its rating


def as_built(duration_s: float, sigma: float = SIGMA, **changes):
    sc = marinecdpr.load_scenario("paper_as_built").with_updates("time", duration_s=duration_s)
    assert sc.simulation.cables.winch == "motor" and sc.robot.winch.torque_max_Nm == TAU_MAX
    sc = sc.with_updates("simulation.noise", motor_torque_N_m=sigma, seed=3)
    return sc.with_changes(**changes) if changes else sc


def test_the_noise_reaches_the_controller_s_measured_torque_with_its_standard_deviation():
    """Exchanges of the closed loop's parts on the plan for 2.5 s (10 000 samples, 4 motors):
    after each, what the controller's measurement holds (``meas.tau``, the very arrays its step
    reads) less the torque the drive gave is the noise: mean 0 and sample variance within
    the chi-square band (1e-4 two-sided) of 0.04 N m's; the drives' demands untouched (equal
    to the true torques, bit for bit). The noise is drawn once per run, the same for the same
    seed; without it the part is not built."""
    sc = as_built(2.5)
    n = int(round(sc.time.duration_s / sc.time.step_s))
    asm = prototype(sc, "closed_loop", n)
    assert any(isinstance(p, MotorCurrents) for p in asm.system.parts)
    motor = asm.get("MotorWinch")
    meas = asm.system.bus.meas
    assert np.shares_memory(meas.tau, asm.ctl.meas.tau)  # the controller's own measurement
    ref = asm.ref
    R = matrix_from_euler(ref.pose[:, 3:])
    residual = np.empty((n, 4))
    for k in range(n):
        assert not exchange(k, sc.time.step_s, ref.pose[k, :3], R[k], ref.twist[k, :3], ref.twist[k, 3:],
                            asm.wired)
        residual[k] = meas.tau - motor.drive.tau
        np.testing.assert_array_equal(meas.tau_set, motor.drive.tau)
    N = residual.size
    var = residual.var(ddof=1)
    lo, hi = chi2.ppf([5e-5, 1.0 - 5e-5], N - 1) / (N - 1) * SIGMA ** 2
    assert lo < var < hi, (np.sqrt(var), np.sqrt(lo), np.sqrt(hi))
    assert abs(residual.mean()) < 5.0 * SIGMA / np.sqrt(N)
    assert np.ptp(motor.drive.tau) > 0.1  # the motors worked: the torques moved along the circle
    np.testing.assert_array_equal(motor_currents(sc, "closed_loop", n).noise, motor_currents(sc, "closed_loop", n).noise)
    quiet = as_built(0.1, sigma=0.0)
    assert not any(isinstance(p, MotorCurrents) for p in prototype(quiet, "closed_loop", 100).system.parts)
    assert motor_currents(sc, "open_loop", n) is None  # nothing reads it there


def test_the_physics_is_the_same_bit_for_bit_and_the_watch_saw_exactly_the_noise():
    """Flown closed loop 2 s with and without the noise: the platform's trajectory and the
    tensions are the same bit for bit (the controller reads the current only in its watch,
    which acts only on a detection, and there is none), and the watch's peak current residual
    is the noise's largest |n| over the torque threshold, 0.2 x 2 N m (0 without the noise)."""
    noisy, quiet = as_built(2.0), as_built(2.0, sigma=0.0)
    a, b = simulate(quiet, run="closed_loop", plant="own"), simulate(noisy, run="closed_loop", plant="own")
    np.testing.assert_array_equal(a.pose, b.pose)
    np.testing.assert_array_equal(a.tensions, b.tensions)
    assert a.detections == b.detections == ()
    n = a.t.size
    noise = motor_currents(noisy, "closed_loop", n).noise[:n - 1]  # the watch at k reads exchange k - 1's
    assert a.residual_peaks["current"] == 0.0
    assert b.residual_peaks["current"] == pytest.approx(np.abs(noise).max() / (0.2 * TAU_MAX), rel=1e-12)


@pytest.mark.parametrize("hs_m, tp_s", [(0.5, 7.0), (1.5, 9.0), (2.5, 10.0)])
def test_a_sound_motor_winch_robot_at_sea_with_realistic_current_noise_raises_no_alarm(hs_m, tp_s):
    """paper_as_built on paper_sea's ship and seas (JONSWAP, its BEM RAOs, 150 deg), three sea
    states of the operability's scatter, 4 s closed loop with the current measured to 2 % of
    the motors' rating: no detection at all (of 4 001 exchanges), the current residual's peak
    below half its threshold."""
    sea = marinecdpr.load_scenario("paper_sea").base_motion.model_dump()
    sea.update(hs_m=hs_m, tp_s=tp_s)
    r = simulate(as_built(4.0, base_motion=sea), run="closed_loop", plant="own")
    assert r.t.size == 4001 and r.detections == () and r.reaction == "normal"
    assert 0.0 < r.residual_peaks["current"] < 0.5


def test_a_stalled_winch_is_still_found_in_its_delay_with_the_noise():
    """Cable 1's motor stalls at 0.5 s with the 2 % current noise: its drive is found failed on
    the 20th exchange of the stall (current_delay_s 0.02 s: step 520), as without the noise,
    and nothing else is detected."""
    stall = [{"kind": "winch_stall", "cable": 1, "at_s": 0.5}]
    for sigma in (SIGMA, 0.0):
        r = simulate(as_built(1.0, sigma=sigma, faults=stall), run="closed_loop", plant="own")
        assert [(d.step, d.kind, d.cable) for d in r.detections] == [(520, "drive", 0)], sigma
