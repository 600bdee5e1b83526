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
    peak = winch_report(p.tensions, p.length_rates, p.winch.length_accelerations, sc.time.step_s,
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


# -------------------- formerly tests/test_catenary_motor_winch.py

"""Motor winches on sagging cables (issue 37, item 1): each drum turns under its catenary's
tension at the winch end over what it has paid out, and its tension loop holds the
platform's end at the commanded tension; own plant only (MuJoCo's tendons are straight)."""

import numpy as np
import pytest
from numba import njit

from marinecdpr import ScenarioError
from marinecdpr.geometry.rotations import matrix_from_euler
from marinecdpr.model.catenary import catenary_drum_stiffness, catenary_series
from marinecdpr.prototype.parts import exchange
from marinecdpr.prototype.simulation import prototype, simulate

from conftest import make_scenario

EA, W = 1.0e5, 3.5  # test_catenary_plant's heavy rope: 1.2 m of it weighs 4.2 N
# test_motor_winch's winch: no friction, no gearbox losses (at rest its loop settles exactly;
# a gearbox's losses switch with the sense of turning and keep a held drum hunting)
WINCH = dict(drum_radius_m=0.05, gear_ratio=10.0, torque_max_Nm=2.0, speed_max_rad_s=300.0, power_max_W=200.0,
             rotor_inertia_kg_m2=1e-4, drum_inertia_kg_m2=1e-3)


def heavy_motor(model="catenary", w=W, plant="own"):
    def edit(d):
        d["robot"]["winch"] = dict(WINCH)
        d["robot"]["cable_weight_N_m"] = w
        d["simulation"]["plant"] = plant
        d["simulation"]["cables"] = {"model": model, "stiffness_EA_N": EA, "winch": "motor"}
    return make_scenario(edit)


@njit
def _hold(n, h, x, R, wired):
    """n exchanges with the platform held at (x, R), at rest, the ship as at t = 0."""
    z = np.zeros(3)
    for _ in range(n):
        exchange(0, h, x, R, z, z, wired)


def test_a_held_platform_s_drums_settle_on_the_catenaries_static_solution():
    """The platform held still at its first pose, a constant command at the platform: the
    drums settle where each catenary carries the command at the platform (its unstretched
    length from model.catenary's static solution, solved independently), and each motor's
    torque through its gearbox over the drum's radius holds the catenary's tension at the
    winch end, which differs from the platform's by 1.9 N here (the cable's weight): a
    motor that held the command at its drum would leave the platform that much short."""
    sc = heavy_motor()
    n = 3000
    proto = prototype(sc, "open_loop", n, include=lambda name: name in ("geometry", "cables", "winches"),
                      given=("T_cmd", "cell_noise"), brush=False)
    system = proto.system
    assert [type(p).__name__ for p in system.parts] == ["CableGeometry", "CatenaryCables", "CatenaryMotorWinch"]
    motor = proto.get("CatenaryMotorWinch")
    motor.Ldot_ref[:] = 0.0  # the plan's cable motion: none, the platform is held
    motor.Lddot_ref[:] = 0.0
    bus = system.bus
    T_cmd = np.array([60.0, 45.0, 80.0, 70.0])
    bus.T_cmd[:] = T_cmd
    bus.cell_noise[:] = 0.0
    x = np.ascontiguousarray(proto.ref.pose[0, :3])  # the plan's first pose
    R = np.ascontiguousarray(matrix_from_euler(proto.ref.pose[:1, 3:])[0])
    _hold(n, sc.time.step_s, x, R, proto.wired)
    drive = motor.drive
    assert np.abs(drive.omega).max() < 1e-9  # at rest
    # the catenaries by model.catenary, from the anchors in the ship's vertical at t = 0
    model = system.model
    up = proto.ship_h.R_SO[0, 2, :]
    d = x + model.p_P @ R.T - model.c_C
    v = d @ up
    hz = np.sqrt(np.einsum("mi,mi->m", d, d) - v * v)
    cat = catenary_series(hz, v, W, EA, T_B=T_cmd)
    assert np.all(cat.status == 0)
    # measured: the platform's end 1.9e-10 N from the command, the drums 2.4e-15 m from the
    # static solution, the torques 1.9e-10 N (as tension) from the winch end's
    np.testing.assert_allclose(bus.T_app, T_cmd, rtol=0, atol=1e-7)
    np.testing.assert_allclose(drive.L0, cat.L0, rtol=0, atol=1e-11)
    r, G = WINCH["drum_radius_m"], WINCH["gear_ratio"]
    np.testing.assert_allclose(drive.tau * G / r, cat.T_A, rtol=0, atol=1e-7)
    np.testing.assert_allclose(bus.T_winch, cat.T_A, rtol=0, atol=1e-7)
    assert np.abs(cat.T_A - T_cmd).min() > 1.5


def test_weightless_sagging_cables_on_motor_winches_fly_as_straight_elastic_ones():
    """A rope of 1e-9 N/m: catenary cables on motor winches fly the paper's circle open loop
    as straight elastic cables on the same motors do. Measured over 1 s: tensions within
    1.7e-4 N of each other (of 150-280 N), the platform within 1.5e-7 m: the sagging
    cables' loops are tuned on the drum's exact stiffness E A L / L0^2, the straight ones'
    on E A / L0 (0.25 % strain apart); the motors' own error is 0.25 N."""
    n = 1000
    runs = [simulate(heavy_motor(model, w=1e-9), run="open_loop", n_steps=n) for model in ("elastic", "catenary")]
    straight, sagging = runs
    assert np.abs(sagging.tensions - straight.tensions).max() < 3e-4
    assert np.abs(sagging.pose - straight.pose).max() < 3e-7
    # the motors' own error against the commands is far larger: the comparison can tell
    assert np.abs(straight.tensions - straight.tensions_commanded).max() > 0.1


@pytest.mark.parametrize("w, T, irvine", [(1e-12, 100.0, 1.5e-3), (3.5, 100.0, 0.015), (3.5, 300.0, 0.004)])
def test_the_drum_s_stiffness_is_the_catenary_s(w, T, irvine):
    """-dT_A/dL0 at held ends: central differences of catenary_series (to 1e-7; measured
    7e-8), E A L / L0^2 for a weightless rope (to 1e-12), and Irvine's shallow cable,
    1 / (L0 / EA + (w h)^2 L / (12 T^3)) (Cable Structures, 1981; measured within 0.1 %
    weightless, 1.2 % for 3.5 N/m at 100 N where the sag leaves 27-62 % of E A / L0, 0.3 %
    at 300 N). Three spans: level, falling and rising, 3.6-5.1 m."""
    d = np.array([[4.0, 0.0, 0.0], [3.0, 0.0, -2.0], [5.0, 0.0, 1.0]])  # B - A, z up
    v, h = d[:, 2], np.hypot(d[:, 0], d[:, 1])
    L = np.linalg.norm(d, axis=1)
    cat = catenary_series(h, v, w, EA, T_B=np.full(3, T))
    L0 = cat.L0
    k = catenary_drum_stiffness(h, v, L0, w, EA)
    dL = 1e-6 * L0
    up, down = (catenary_series(h, v, w, EA, L0=L0 + s * dL) for s in (1.0, -1.0))
    np.testing.assert_allclose(k, -(up.T_A - down.T_A) / (2.0 * dL), rtol=1e-7)
    T_m = 0.5 * (cat.T_A + cat.T_B)
    np.testing.assert_allclose(k, 1.0 / (L0 / EA + (w * h) ** 2 * L / (12.0 * T_m**3)), rtol=irvine)
    if w < 1e-9:
        np.testing.assert_allclose(k, EA * L / L0**2, rtol=1e-12)
    else:
        assert np.all(k < 0.98 * EA / L0)


def test_motor_winches_on_sagging_cables_need_the_own_plant():
    with pytest.raises(ScenarioError, match=r"simulation\.plant: must be \"own\" for catenary cables"):
        heavy_motor(plant="mujoco")
    with pytest.raises(ScenarioError, match="catenary cables need the own plant"):
        simulate(heavy_motor(), run="open_loop", plant="mujoco", n_steps=10)
