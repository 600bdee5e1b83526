"""Motor winches in the virtual prototype (issue 14, item 2): the tension loop through each
winch's motor (torque, speed and power limits, inertia, friction) drives the drum, and the
elastic cable's stretch over what the drum paid out is the tension."""

import numpy as np
import pytest

from marinecdpr import ScenarioError
from marinecdpr.model.winch import WinchParams, winch_report
from marinecdpr.prototype.simulation import simulate
import marinecdpr

from conftest import make_scenario

WINCH = dict(drum_radius_m=0.05, gear_ratio=10.0, torque_max_Nm=2.0, speed_max_rad_s=300.0, power_max_W=200.0,
             rotor_inertia_kg_m2=1e-4, drum_inertia_kg_m2=1e-3)
N = 3000  # 3 s of the paper's circle


def motor_scenario(winch="motor", **changes):
    def edit(d):
        d["robot"]["winch"] = dict(WINCH, **changes)
        d["simulation"]["cables"] = {"model": "elastic", "stiffness_EA_N": 1e5, "winch": winch}
    return make_scenario(edit)


@pytest.fixture(scope="module")
def runs():
    sc = motor_scenario()
    ref = marinecdpr.plan(sc)
    out = {(run, plant): simulate(sc, run=run, plant=plant, reference=ref, n_steps=N)
           for run in ("open_loop", "closed_loop") for plant in ("own", "mujoco")}
    ideal = simulate(motor_scenario("tension"), run="open_loop", plant="own", reference=ref, n_steps=N)
    return sc, ref, out, ideal


def test_motor_winches_hold_the_commanded_tensions(runs):
    """A 34 Hz tension loop (EA / L 1e5 N/m through a 50 mm drum at 10:1, J_eff 1.1e-4 kg m^2,
    damping ratio 0.7) with the plan's L' and L'' fed forward holds the tensions within 1 N of
    the commands, and the platform within 2 mm of the plan open loop, against 1e-6 m for an
    ideal tension source; no motor reaches a limit."""
    sc, ref, out, ideal = runs
    for (run, plant), r in out.items():
        err = np.abs(r.tensions - r.tensions_commanded).max()
        assert 0.05 < err < 1.0, (run, plant, err)
        assert r.winch_limited_steps == 0 and r.winch_overspeed_steps == 0
    assert np.abs(ideal.pose_error[:, :3]).max() < 1e-6
    open_err = np.abs(out["open_loop", "own"].pose_error[:, :3]).max()
    assert 1e-5 < open_err < 2e-3
    # the closed loop corrects the tension loop's error
    assert np.abs(out["closed_loop", "own"].pose_error[:, :3]).max() < 0.5 * open_err


def test_both_plants_agree_on_the_motor_winches(runs):
    _, _, out, _ = runs
    for run in ("open_loop", "closed_loop"):
        own, mj = out[run, "own"], out[run, "mujoco"]
        np.testing.assert_allclose(mj.pose, own.pose, atol=1e-6)
        np.testing.assert_allclose(mj.tensions, own.tensions, atol=0.05)


def test_a_motor_sized_at_the_plans_peak_is_limited_in_open_loop():
    """Sized at the plan's own peak torque (winch_report), the motors reach their limit while
    the open loop's tension loop corrects its error; the closed loop's errors stay smaller."""
    sc = motor_scenario()
    p = marinecdpr.plan(sc)
    peak = winch_report(p.tensions, p.length_rates, p.length_accelerations, sc.time.step_s,
                        WinchParams(**WINCH)).peak_torque_Nm.max()
    tight = motor_scenario(torque_max_Nm=float(peak) * (1 + 1e-4))
    p = marinecdpr.plan(tight)
    assert p.all_feasible
    r = simulate(tight, run="open_loop", plant="own", reference=p)
    assert r.winch_limited_steps > 0 and r.winch_overspeed_steps == 0
    from marinecdpr.studies.prototype_runs import run_summary, run_warnings

    assert run_summary(r, tight)["winch_limited_steps"] == r.winch_limited_steps
    assert run_warnings({"open_loop": r}, tight) == [
        f"open_loop: at {r.winch_limited_steps} of {p.n_steps} steps a winch's motor was held at its torque, "
        "power or speed limit (robot.winch)"]


@pytest.mark.parametrize("edit, says", [
    (lambda d: d["simulation"].__setitem__("cables", {"model": "elastic", "stiffness_EA_N": 1e5, "winch": "motor"}),
     r"^test: robot\.winch: missing: motor winches"),
    (lambda d: (d["robot"].__setitem__("winch", WINCH),
                d["simulation"].__setitem__("cables", {"model": "ideal", "winch": "motor"})),
     r"^test: simulation\.cables\.model: must be \"elastic\" or \"catenary\" for motor winches"),
    (lambda d: (d["robot"].__setitem__("winch", dict(WINCH, rotor_inertia_kg_m2=0.0, drum_inertia_kg_m2=0.0)),
                d["simulation"].__setitem__("cables", {"model": "elastic", "stiffness_EA_N": 1e5, "winch": "motor"})),
     r"^test: robot\.winch\.rotor_inertia_kg_m2: must be > 0"),
])
def test_motor_winches_need_their_design(edit, says):
    with pytest.raises(ScenarioError, match=says):
        make_scenario(edit)


def test_the_encoders_read_the_motors_drums():
    """paper_as_built (motor winches over pulleys), closed loop: the pose from the encoders
    (the drums' paid-out lengths, stretched by the load cells' tensions, over the pulleys)
    holds the platform as the pose sensor does, to 2 um."""
    base = marinecdpr.load_scenario("paper_as_built").with_updates("simulation", plant="own")
    runs = [simulate(base.with_updates("simulation.sensors", pose_from=source), run="closed_loop", n_steps=2000)
            for source in ("sensor", "encoders")]
    np.testing.assert_allclose(runs[1].pose[:, :3], runs[0].pose[:, :3], rtol=0, atol=2e-6)
