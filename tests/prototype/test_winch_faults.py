"""A winch's faults as a mode of the winch parts (issue 40, item 2): its brake holds the drum
after the brake's delay; its motor loses its power and the drum runs under the cable's pull
against the drive's inertia. Hand-worked: the unstretched length a held drum keeps (read back
from each step's tension and length, L0 = L EA / (EA + T)), and a free drum's acceleration
L0'' = (r_d / G)^2 T / J_eff."""

from __future__ import annotations

import numpy as np
import pytest

from marinecdpr import ScenarioError
from marinecdpr.prototype.simulation import simulate

from conftest import make_scenario

EA = 1.0e5
WINCH = {"drum_radius_m": 0.05, "gear_ratio": 10.0, "torque_max_Nm": 2.0, "speed_max_rad_s": 300.0,
         "power_max_W": 200.0, "rotor_inertia_kg_m2": 1.0e-4, "drum_inertia_kg_m2": 1.0e-3,
         "gear_efficiency": 1.0, "coulomb_friction_Nm": 0.0, "viscous_friction_Nm_s": 0.0}


def paper_on(winch: str, faults: list, duration_s: float = 2.0):
    """The paper's robot and circle on its rolling ship with undamped elastic cables (EA 1e5 N)
    on length-controlled or motor winches (a frictionless drive, eta_g = 1)."""
    def edit(d):
        d["simulation"]["cables"] = {"model": "elastic", "stiffness_EA_N": EA, "damping_N_s_m": 0.0, "winch": winch}
        d["robot"]["winch"] = WINCH
        d["time"] = {"step_s": 0.001, "duration_s": duration_s}
        d["faults"] = faults
    return make_scenario(edit)


def unstretched(r):
    """Each step's unstretched length from the logged tension and length (undamped elastic
    cables, tension EA (L - L0) / L0 over the drum's length), m; NaN where slack."""
    return np.where(r.tensions > 0.0, r.lengths * EA / (EA + r.tensions), np.nan)


def cable_1_drum_after(kind: str):
    """Cable 1's motor winch struck by ``kind`` at 0.5 s, 0.7 s flown open loop on the own plant
    (1 ms steps): the run, each step's unstretched length L0 (m), L0's second difference at
    steps 500 .. n-3 (m/s^2), the drive's J_eff = J_m + J_d / G^2 (kg m^2) and r_d / G (m)."""
    r = simulate(paper_on("motor", [{"kind": kind, "cable": 1, "at_s": 0.5}], duration_s=0.7),
                 run="open_loop", plant="own")
    h, k0 = 0.001, 500
    L0 = unstretched(r)
    J_eff = WINCH["rotor_inertia_kg_m2"] + WINCH["drum_inertia_kg_m2"] / WINCH["gear_ratio"] ** 2
    rg = WINCH["drum_radius_m"] / WINCH["gear_ratio"]
    seen = (L0[k0 + 1:-1, 0] - 2.0 * L0[k0:-2, 0] + L0[k0 - 1:-3, 0]) / h ** 2  # at steps k0 .. n-3
    return r, L0, seen, J_eff, rg


@pytest.mark.parametrize("plant", ["own", "mujoco"])
def test_a_braked_length_winch_holds_its_drum_after_the_delay(plant):
    """Cable 2's brake told at 0.8 s, holding 0.2 s later: from the exchange at 1.0 s its
    unstretched length stays what it was (to rounding, 1e-12 m), while before it followed the
    circle's (by mm) and the other cables' still do."""
    r = simulate(paper_on("length", [{"kind": "winch_brake", "cable": 2, "at_s": 0.8, "brake_delay_s": 0.2}]),
                 run="open_loop", plant=plant)
    L0 = unstretched(r)
    k = 1000
    held = L0[k:, 1]
    assert np.all(np.isfinite(held))
    np.testing.assert_allclose(held, held[0], rtol=0.0, atol=1e-12)
    assert np.ptp(L0[:k, 1]) > 1e-3 and np.ptp(L0[k:, 0]) > 1e-3
    assert r.faults[0]["acted_s"] == 1.0


def test_a_motor_without_power_lets_its_drum_run_under_the_pull():
    """Cable 1's motor loses its power at 0.5 s (no brake): the drum accelerates under its
    cable's pull alone, J_eff omega' = -T r_d / G, L0' = -(r_d / G) omega, so that each step's
    second difference of L0 is (r_d / G)^2 T / J_eff (the drive's exact step without
    friction); J_eff = J_m + J_d / G^2 = 1.1e-4 kg m^2. Measured to 9e-11 of it over the 73
    steps until the cable runs slack; the sound winches' drums do not follow it."""
    r, L0, seen, J_eff, rg = cable_1_drum_after("motor_power_loss")
    h, k0 = 0.001, 500
    by_hand = rg ** 2 * r.tensions[k0:-2, 0] / J_eff
    taut = np.isfinite(seen)  # until the running drum has paid out the stretch (73 steps)
    assert taut[:60].all() and by_hand[0] > 50.0  # 61 m/s^2 at first: 268 N on the drum
    np.testing.assert_allclose(seen[taut], by_hand[taut], rtol=1e-9)
    sound = (L0[k0 + 1:-1, 2] - 2.0 * L0[k0:-2, 2] + L0[k0 - 1:-3, 2]) / h ** 2
    assert np.nanmin(np.abs(sound - rg ** 2 * r.tensions[k0:-2, 2] / J_eff)[:60]) > 1.0
    assert r.faults[0] == {"kind": "motor_power_loss", "cable": 1, "at_s": 0.5, "acted_s": 0.5, "brake_held_s": None}


def test_a_motor_without_power_is_held_by_its_brake_after_the_delay():
    """The same loss with the fail-safe brake holding 50 ms later: the drum runs free for 50
    steps, then keeps the length it had reached."""
    r = simulate(paper_on("motor", [{"kind": "motor_power_loss", "cable": 1, "at_s": 0.5, "brake_delay_s": 0.05}],
                          duration_s=0.7), run="open_loop", plant="own")
    L0 = unstretched(r)[550:, 0]
    taut = np.isfinite(L0)  # the platform, flown on, leaves the held cable slack at times
    assert taut[:15].all() and taut.sum() > 100
    np.testing.assert_allclose(L0[taut], L0[0], rtol=0.0, atol=1e-12)
    assert abs(L0[0] - unstretched(r)[500, 0]) > 1e-3  # it ran before the brake held
    assert r.faults[0]["brake_held_s"] == pytest.approx(0.55)


def test_a_stalled_motor_pulls_at_its_torque_limit_until_the_cable_balances_it():
    """Cable 1's motor stalls at its torque limit at 0.5 s (winch_stall): its drive gives
    tau_max = 2 N m winding in whatever the loop asks, J_eff omega' = tau_max - T r_d / G, so
    each step's second difference of L0 is ((r_d / G)^2 T - (r_d / G) tau_max) / J_eff (the
    drive's exact step without friction, the drum below the power limit's 100 rad/s: at most
    80 rad/s here). Measured to 1e-6 m/s^2 (values up to 30 m/s^2) over the 199 steps flown;
    the drum reels in from 268 N until its pull balances the stall torque, T = G tau_max /
    r_d = 400 N: the last 100 ms' mean 400.7 N (the platform still moving on the circle)."""
    r, L0, seen, J_eff, rg = cable_1_drum_after("winch_stall")
    h, k0 = 0.001, 500
    by_hand = (rg ** 2 * r.tensions[k0:-2, 0] - rg * WINCH["torque_max_Nm"]) / J_eff
    assert np.isfinite(seen).all() and np.nanmax(np.abs(np.diff(L0[k0:, 0]))) / h / rg < 100.0
    np.testing.assert_allclose(seen, by_hand, rtol=0.0, atol=1e-6)
    assert np.abs(by_hand).max() > 20.0
    stall_T = WINCH["gear_ratio"] * WINCH["torque_max_Nm"] / WINCH["drum_radius_m"]
    assert r.tensions[k0 - 1, 0] < 300.0 and abs(r.tensions[-100:, 0].mean() - stall_T) < 1.0
    assert r.faults[0] == {"kind": "winch_stall", "cable": 1, "at_s": 0.5, "acted_s": 0.5}


@pytest.mark.parametrize("cables, kind, says", [
    ({"model": "ideal"}, "winch_brake", "needs a winch that pays out the cable"),
    ({"model": "elastic", "stiffness_EA_N": EA, "winch": "tension"}, "winch_brake", "length-controlled or motor"),
    ({"model": "elastic", "stiffness_EA_N": EA}, "motor_power_loss", "needs motor winches"),
    ({"model": "elastic", "stiffness_EA_N": EA}, "winch_stall", "a winch_stall needs motor winches"),
    ({"model": "ideal"}, "brake_failure", "needs a winch that pays out the cable"),
])
def test_a_winch_fault_without_such_a_winch_is_refused_in_one_line(cables, kind, says):
    def edit(d):
        d["simulation"]["cables"] = cables
        d["faults"] = [{"kind": kind, "cable": 1, "at_s": 1.0}]
    with pytest.raises(ScenarioError) as err:
        make_scenario(edit)
    assert "\n" not in str(err.value) and "faults[1].kind" in str(err.value) and says in str(err.value)


@pytest.mark.parametrize("kind", ["cable_snap", "winch_stall"])
def test_a_cable_snap_or_a_stall_has_no_brake_delay(kind):
    def edit(d):
        d["faults"] = [{"kind": kind, "cable": 1, "at_s": 1.0, "brake_delay_s": 0.1}]
    with pytest.raises(ScenarioError, match=r"faults\[1\]\.brake_delay_s: is for a winch's faults"):
        make_scenario(edit)


def test_a_failed_primary_brake_leaves_the_drum_to_the_secondary():
    """Cables 2 and 3 told to brake at 0.8 s, each primary (0.1 s) failing: cable 2's secondary
    holds 0.3 s after the command, from the exchange at 1.1 s, its unstretched length constant
    from then to 1e-12 m (having moved in the 0.2 s after the primary's moment, > 1 mm); cable
    3 has no secondary: its drum never holds, following the circle to the end (> 1 mm)."""
    r = simulate(paper_on("length", [
        {"kind": "winch_brake", "cable": 2, "at_s": 0.8, "brake_delay_s": 0.1, "primary_fails": True,
         "secondary_delay_s": 0.3},
        {"kind": "winch_brake", "cable": 3, "at_s": 0.8, "brake_delay_s": 0.1, "primary_fails": True}],
        duration_s=1.4), run="open_loop", plant="own")
    L0 = unstretched(r)
    held = L0[1100:, 1]
    assert np.all(np.isfinite(held)) and held.size == 301  # to the log's last row, at 1.4 s
    np.testing.assert_allclose(held, held[0], rtol=0.0, atol=1e-12)
    assert np.ptp(L0[900:1099, 1]) > 1e-3 and np.ptp(L0[900:, 2]) > 1e-3
    assert r.faults[0]["acted_s"] == pytest.approx(1.1) and r.faults[1]["acted_s"] is None


@pytest.mark.parametrize("fault, key, says", [
    ({"kind": "motor_power_loss", "cable": 1, "at_s": 0.5, "secondary_delay_s": 0.3}, "faults[1].secondary_delay_s",
     "is for a secondary brake (winch_brake, brake_failure)"),
    ({"kind": "cable_snap", "cable": 1, "at_s": 0.5, "primary_fails": True}, "faults[1].primary_fails",
     "is for a winch_brake's primary brake"),
    ({"kind": "winch_brake", "cable": 1, "at_s": 0.5, "brake_delay_s": 0.3, "secondary_delay_s": 0.1},
     "faults[1].secondary_delay_s", "before the primary brake's brake_delay_s"),
    ({"kind": "winch_brake", "cable": 1, "at_s": 0.5, "primary_fails": "yes"}, "faults[1].primary_fails", ""),
])
def test_a_brake_mistake_is_one_line(fault, key, says):
    def edit(d):
        d["simulation"]["cables"] = {"model": "elastic", "stiffness_EA_N": EA, "winch": "motor"}
        d["robot"]["winch"] = WINCH
        d["faults"] = [fault]
    with pytest.raises(ScenarioError) as err:
        make_scenario(edit)
    text = str(err.value)
    assert "\n" not in text and key in text and says in text, text


def _stall_flown(plant, detect):
    sc = paper_on("motor", [{"kind": "winch_stall", "cable": 1, "at_s": 0.5}], duration_s=1.5)
    return simulate(sc.with_updates("simulation.control.safety", detect=detect), run="closed_loop", plant=plant)


@pytest.mark.parametrize("plant", ["own", "mujoco"])
def test_a_stalled_motor_is_found_by_its_current_and_the_others_hold_the_plan_against_its_pull(plant):
    """Closed loop, cable 1's motor stalled at 0.5 s: its torque (its drive's current, the
    stall's 2 N m) leaves its loop's demand, so the watch finds its drive failed on the 20th
    exchange (current_delay_s 0.02 s: at 0.52 s) and loses its cable to the solve, the other
    three holding the plan against the pull its load cell reads (no brake). Its drum still
    balances the stall torque (the last 100 ms' mean 399.9 N, G tau_max / r_d = 400 N), and
    the platform stays within 3.9 mm of its plan after the stall, 0.24 mm at the end (measured
    both plants), where without the watch its loop fights the stall: 24.6 mm, and 13.5 mm at
    the end. The stalled cable's peak is higher for it, 506 N against 424 N. A powerless
    motor is found at the same exchange (its demand against no torque)."""
    r, blind = _stall_flown(plant, True), _stall_flown(plant, False)
    assert [(d.step, d.kind, d.cable) for d in r.detections] == [(520, "drive", 0)]
    assert r.reaction == "go_on" and r.brakes_held == () and blind.detections == ()
    stall_T = WINCH["gear_ratio"] * WINCH["torque_max_Nm"] / WINCH["drum_radius_m"]
    assert abs(r.tensions[-100:, 0].mean() - stall_T) < 0.5
    err = [np.linalg.norm(x.pose[500:, :3] - x.pose_planned[500:, :3], axis=1) for x in (r, blind)]
    assert err[0].max() < 0.004 and err[0][-1] < 0.0003
    assert err[1].max() > 0.02 and err[1][-1] > 0.01
    assert 500.0 < r.tensions[500:, 0].max() < 510.0 and r.tensions[500:, 0].max() > blind.tensions[500:, 0].max()
    assert r.residual_peaks["current"] > 1.0
    if plant == "own":
        power = simulate(paper_on("motor", [{"kind": "motor_power_loss", "cable": 1, "at_s": 0.5}], duration_s=0.6),
                         run="closed_loop", plant=plant)
        assert (power.detections[0].step, power.detections[0].kind, power.detections[0].cable) == (520, "drive", 0)


def test_a_sound_motor_s_current_is_its_demand():
    """Without a fault, on motor winches, the watched current residual is 0 in a closed loop
    on either plant (a sound drive's torque is its demand, after its own limits), and the
    run's summary names it; nothing is detected."""
    for plant in ("own", "mujoco"):
        r = simulate(paper_on("motor", [], duration_s=1.0), run="closed_loop", plant=plant)
        assert r.detections == () and r.residual_peaks["current"] == 0.0


@pytest.mark.parametrize("secondary_s, held_s", [(None, None), (0.3, 0.82)])
def test_a_commanded_brake_whose_primary_fails_holds_by_its_secondary_or_not_at_all(secondary_s, held_s):
    """Cable 2 snaps at 0.5 s: the watch finds it lost at 0.52 s and, the other three unable to
    hold the wrench, commands the brakes then, which hold 0.2 s later (0.72 s); but cable 1's
    primary brake has failed from 0.1 s (brake_failure): a secondary of 0.3 s holds its drum
    from 0.82 s (its length then as it was, to 1e-12 m), and without one it is never held. A
    primary that fails after the command has held: 0.72 s as the others. Both plants."""
    for plant in ("own", "mujoco"):
        failure = {"kind": "brake_failure", "cable": 1, "at_s": 0.1}
        if secondary_s is not None:
            failure["secondary_delay_s"] = secondary_s
        r = simulate(paper_on("motor", [{"kind": "cable_snap", "cable": 2, "at_s": 0.5}, failure], duration_s=1.0),
                     run="closed_loop", plant=plant)
        assert (r.detections[0].step, r.detections[0].kind, r.detections[0].cable) == (520, "cable_slack", 1)
        held = dict(r.brakes_held)
        assert held[3] == pytest.approx(0.72) and held[4] == pytest.approx(0.72)
        if held_s is None:
            assert 1 not in held
        else:
            assert held[1] == pytest.approx(held_s)
            L0 = unstretched(r)[820:, 0]
            taut = np.isfinite(L0)
            assert taut.sum() >= 30
            np.testing.assert_allclose(L0[taut], L0[taut][0], rtol=0.0, atol=1e-12)
    late = simulate(paper_on("motor", [{"kind": "cable_snap", "cable": 2, "at_s": 0.5},
                                       {"kind": "brake_failure", "cable": 1, "at_s": 0.6}], duration_s=1.0),
                    run="closed_loop", plant="own")
    assert dict(late.brakes_held)[1] == pytest.approx(0.72)


@pytest.mark.parametrize("faults, field, says", [
    ([{"kind": "brake_failure", "cable": 1, "at_s": 0.1, "secondary_delay_s": 0.1}], "faults[1].secondary_delay_s",
     "before the primary brake's simulation.control.safety.brake_delay_s (0.2 s)"),
    ([{"kind": "brake_failure", "cable": 2, "at_s": 0.1}, {"kind": "brake_failure", "cable": 2, "at_s": 0.3}],
     "faults[2].cable", "winch 2's primary brake fails once"),
    ([{"kind": "winch_stall", "cable": 1, "at_s": 0.1, "secondary_delay_s": 0.5}], "faults[1].secondary_delay_s",
     "is for a secondary brake (winch_brake, brake_failure), not a winch_stall"),
])
def test_a_brake_failure_that_cannot_be_is_refused_in_one_line(faults, field, says):
    with pytest.raises(ScenarioError) as err:
        paper_on("motor", faults)
    assert "\n" not in str(err.value) and field in str(err.value) and says in str(err.value)
