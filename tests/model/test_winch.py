"""Winches as built (marinecdpr.model.winch): motor state, tension bounds and report against
hand-worked numbers, their round trip, and the compiled dynamics step's responses.

The hand-worked winch (HAND): r_d = 0.05 m, G = 10, eta_g = 1, tau_max = 2 N m,
omega_max = 300 rad/s, P_max = 200 W, J_m = 1e-4, J_d = 1e-3 kg m^2, no friction, so
J_eff = 1e-4 + 1e-3 / 100 = 1.1e-4 kg m^2, r_d / G = 0.005 m, line speed limit
300 * 0.005 = 1.5 m/s, and the torque and power limits meet at 200 / 2 = 100 rad/s
(|L'| = 0.5 m/s).
"""

import numpy as np
import pytest

from marinecdpr.model.winch import (
    FREE,
    OVERSPEED,
    SPEED_LIMITED,
    TORQUE_LIMITED,
    WinchParams,
    length_accelerations,
    tension_loop_damping,
    winch_drive,
    winch_dynamics_step,
    winch_motor_state,
    winch_motor_step,
    winch_report,
    winch_tension_bounds,
)

HAND = WinchParams(drum_radius_m=0.05, gear_ratio=10.0, torque_max_Nm=2.0, speed_max_rad_s=300.0,
                   power_max_W=200.0, rotor_inertia_kg_m2=1e-4, drum_inertia_kg_m2=1e-3)
EXACT = dict(rel=1e-12, abs=1e-12)


def test_params_derived_and_checked():
    assert HAND.inertia_kg_m2 == pytest.approx(1.1e-4, **EXACT)
    assert HAND.line_speed_max_m_s == pytest.approx(1.5, **EXACT)
    assert HAND.holding_tension_N == pytest.approx(400.0, **EXACT)
    for bad in (dict(drum_radius_m=0.0), dict(gear_ratio=-1.0), dict(torque_max_Nm=0.0),
                dict(power_max_W=np.nan), dict(gear_efficiency=1.1), dict(gear_efficiency=0.0),
                dict(rotor_inertia_kg_m2=-1e-6), dict(coulomb_friction_Nm=np.inf), dict(gear_ratio=True)):
        with pytest.raises(ValueError):
            WinchParams(**{**HAND.__dict__, **bad})
    WinchParams(**{**HAND.__dict__, "power_max_W": np.inf, "speed_max_rad_s": np.inf})  # no limit
    with pytest.raises(ValueError, match="3 WinchParams given for 2 cables"):
        winch_tension_bounds(np.zeros((4, 2)), np.zeros((4, 2)), [HAND] * 3)


def test_hand_worked_bounds():
    """Steps: at rest; winding in at 1 m/s; the same accelerating the winding
    (L'' = -2 m/s^2) and slowing it (L'' = +2 m/s^2); winding in at 0.25 m/s; paying out
    at 1 m/s."""
    L_dot = np.array([[0.0], [-1.0], [-1.0], [-1.0], [-0.25], [1.0]])
    L_ddot = np.array([[0.0], [0.0], [-2.0], [2.0], [0.0], [0.0]])
    b = winch_tension_bounds(L_dot, L_ddot, HAND, T_min=10.0, T_max=450.0)
    st = winch_motor_state(b.winch_upper_N, L_dot, L_ddot, HAND)
    # omega_m = -G L'/r_d = -200 L'; alpha_m = -200 L''
    assert st.speed_rad_s[:, 0] == pytest.approx([0.0, 200.0, 200.0, 200.0, 50.0, -200.0], **EXACT)
    assert st.acceleration_rad_s2[:, 0] == pytest.approx([0.0, 0.0, 400.0, -400.0, 0.0, 0.0], **EXACT)
    # at rest: tau_max G / r_d = 2 * 10 / 0.05 = 400 N
    # 1 m/s in: omega 200 > 100, the power binds: tau_lim = 200 / 200 = 1 N m -> T = 1 * 200
    #           = 200 N = P_max / |L'|
    # accelerating the winding: J_eff alpha = 1.1e-4 * 400 = 0.044 N m -> (1 - 0.044) * 200
    #           = 191.2 N; slowing it: (1 + 0.044) * 200 = 208.8 N
    # 0.25 m/s in: omega 50 < 100, the torque binds: 2 * 200 = 400 N
    # 1 m/s out (generating, eta = 1): 200 N, the power binds both ways
    assert b.winch_upper_N[:, 0] == pytest.approx([400.0, 200.0, 191.2, 208.8, 400.0, 200.0], **EXACT)
    assert b.winch_lower_N[:, 0] == pytest.approx([-400.0, -200.0, -208.8, -191.2, -400.0, -200.0], **EXACT)
    assert b.upper_N[:, 0] == pytest.approx([400.0, 200.0, 191.2, 208.8, 400.0, 200.0], **EXACT)
    assert b.lower_N[:, 0] == pytest.approx([10.0] * 6, **EXACT)
    assert not b.flag.any() and b.all_ok
    # the motor at the bound: torque 2 (torque-bound) or 1 N m (power-bound), power 200 W
    assert st.torque_Nm[:, 0] == pytest.approx([2.0, 1.0, 1.0, 1.0, 2.0, 1.0], **EXACT)
    assert st.power_W[:, 0] == pytest.approx([0.0, 200.0, 200.0, 200.0, 100.0, -200.0], **EXACT)
    # T_max cuts the range at rest
    assert winch_tension_bounds(0.0, 0.0, HAND, 10.0, 350.0).upper_N[0, 0] == pytest.approx(350.0, **EXACT)


def test_hand_worked_efficiency_and_friction():
    """eta_g = 0.8, tau_c = 0.1 N m, b = 1e-3 N m s/rad, L'' = 0."""
    p = WinchParams(**{**HAND.__dict__, "gear_efficiency": 0.8, "coulomb_friction_Nm": 0.1,
                       "viscous_friction_Nm_s": 1e-3})
    b = winch_tension_bounds([[0.0], [-1.0], [1.0]], 0.0, p)
    # at rest (motoring, friction 0 without acceleration): 2 * 0.8 * 200 = 320 N
    # 1 m/s in (motoring): tau_lim 1, friction 1e-3 * 200 + 0.1 = 0.3 -> 0.7 * 0.8 * 200 = 112 N
    # 1 m/s out (generating, omega -200): friction -0.3 helps -> (1 + 0.3) * 200 / 0.8 = 325 N
    assert b.winch_upper_N[:, 0] == pytest.approx([320.0, 112.0, 325.0], **EXACT)
    st = winch_motor_state([[320.0], [112.0], [325.0]], [[0.0], [-1.0], [1.0]], 0.0, p)
    # out: tau_T = 325 * 0.005 * 0.8 = 1.3 N m, friction -0.3 -> 1.0 N m at -200 rad/s: -200 W
    assert st.torque_Nm[:, 0] == pytest.approx([2.0, 1.0, 1.0], **EXACT)
    assert st.power_W[:, 0] == pytest.approx([0.0, 200.0, -200.0], **EXACT)


def test_speed_limit_flags():
    """|L'| > omega_max r_d / G = 1.5 m/s flags the step, either way; an empty range too."""
    L_dot = np.array([[1.5, -1.5, 1.5 * (1 + 1e-9), -1.6, -1.0, 0.0]])
    T_min = np.array([10.0, 10.0, 10.0, 10.0, 150.0, 10.0])  # one per cable (column)
    b = winch_tension_bounds(L_dot, np.array([[0, 0, 0, 0, -20.0, 0]]), HAND, T_min=T_min, T_max=450.0)
    assert b.overspeed.tolist() == [[False, False, True, True, False, False]]
    # accelerating the winding at 20 m/s^2: (1 - 1.1e-4 * 4000) * 200 = 112 N < T_min = 150 N
    assert b.winch_upper_N[0, 4] == pytest.approx(112.0, **EXACT)
    assert b.empty.tolist() == [[False, False, False, False, True, False]]
    assert b.flag.tolist() == [[False, False, True, True, True, False]]
    assert not b.all_ok
    # NaN motion: flagged, not silently in range
    assert winch_tension_bounds([[np.nan]], 0.0, HAND).flag.all()


def test_round_trip_at_the_bound():
    """At T_hi and T_lo the torque or the power is at its limit exactly; one winch per cable."""
    rng = np.random.default_rng(7)
    params = [HAND,
              WinchParams(0.08, 25.0, 5.0, 250.0, 600.0, 3e-4, 0.2, 0.85, 0.15, 2e-3),
              WinchParams(0.03, 6.0, 1.5, np.inf, 150.0, 5e-5, 5e-4, 0.95, 0.0, 1e-4)]
    L_dot = rng.uniform(-1.4, 1.4, size=(500, 3))
    L_dot[:5] = 0.0
    L_ddot = rng.uniform(-3.0, 3.0, size=(500, 3))
    b = winch_tension_bounds(L_dot, L_ddot, params)
    for T in (b.winch_upper_N, b.winch_lower_N):
        st = winch_motor_state(T, L_dot, L_ddot, params)
        tau_max = np.array([p.torque_max_Nm for p in params])
        P_max = np.array([p.power_max_W for p in params])
        use = np.maximum(np.abs(st.torque_Nm) / tau_max, np.abs(st.power_W) / P_max)
        np.testing.assert_allclose(use, 1.0, rtol=1e-12, atol=0)
        # inside the range, the winch is within both limits; 1 % outside, it is not
        inside = winch_motor_state(0.5 * (b.winch_upper_N + b.winch_lower_N), L_dot, L_ddot, params)
        assert np.all(np.abs(inside.torque_Nm) < tau_max) and np.all(np.abs(inside.power_W) < P_max)
    over = winch_motor_state(b.winch_upper_N + 0.01 * np.abs(b.winch_upper_N) + 1e-6, L_dot, L_ddot, params)
    assert np.all(np.maximum(np.abs(over.torque_Nm) / tau_max, np.abs(over.power_W) / P_max) > 1.0)


def test_energy_constant_tension_and_speed():
    """T = 200 N, |L'| = 0.5 m/s for 10 s (1000 steps of 0.01 s): T |L'| 10 = 1000 J."""
    n, dt = 1000, 0.01
    T = np.full((n, 2), 200.0)
    L_dot = np.tile([-0.5, 0.5], (n, 1))  # cable 1 winds in, cable 2 pays out
    r = winch_report(T, L_dot, np.zeros((n, 2)), dt, HAND)
    assert r.energy_net_J == pytest.approx([1000.0, -1000.0], **EXACT)
    assert r.energy_positive_J == pytest.approx([1000.0, 0.0], **EXACT)
    assert r.peak_torque_Nm == pytest.approx([1.0, 1.0], **EXACT)  # 200 * 0.005
    assert r.peak_speed_rad_s == pytest.approx([100.0, 100.0], **EXACT)
    assert r.peak_power_W == pytest.approx([100.0, 100.0], **EXACT)
    assert r.within_limits.tolist() == [True, True]
    # through a gearbox of 0.8: the motor gives 1000 / 0.8 winding in, takes 1000 * 0.8 back
    lossy = WinchParams(**{**HAND.__dict__, "gear_efficiency": 0.8})
    r = winch_report(T, L_dot, np.zeros((n, 2)), dt, lossy)
    assert r.energy_net_J == pytest.approx([1250.0, -800.0], **EXACT)
    # 2 m/s is past the speed limit; 450 N at rest past the torque limit
    r = winch_report([[200.0, 450.0]], [[-2.0, 0.0]], 0.0, dt, HAND)
    assert r.within_limits.tolist() == [False, False]
    assert np.isnan(winch_report([[np.nan, 1.0]], 0.0, 0.0, dt, HAND).energy_net_J[0])


def test_length_accelerations():
    t = np.arange(50) * 0.01
    L_dot = np.column_stack([0.3 * t**2, np.sin(t)])
    np.testing.assert_allclose(length_accelerations(L_dot, 0.01)[:, 0], 0.6 * t, rtol=0, atol=1e-12)


def test_report_agrees_with_bounds_on_the_paper_plan(paper_plan):
    """Within limits at every step <=> the plan's tensions inside the winch's range (no
    overspeed) at every step, for a winch that is enough and one that is not."""
    dt = float(paper_plan.t[1] - paper_plan.t[0])
    T, L_dot = paper_plan.tensions, paper_plan.length_rates
    L_ddot = length_accelerations(L_dot, dt)
    for tau_max in (2.0, 1.0):
        p = WinchParams(**{**HAND.__dict__, "torque_max_Nm": tau_max, "power_max_W": 1e3})
        rep = winch_report(T, L_dot, L_ddot, dt, p)
        b = winch_tension_bounds(L_dot, L_ddot, p)
        inside = ((b.winch_lower_N <= T) & (T <= b.winch_upper_N) & ~b.overspeed).all(axis=0)
        assert rep.within_limits.tolist() == inside.tolist()
        assert rep.within_limits.all() == (tau_max == 2.0)  # the paper's tensions reach ~326 N


# ------------------------------------------------------------------------ dynamics

K_CABLE = 1e5  # N/m: the cable's stiffness, its far end held (or moved) by the test


def run(drive, T_cmd, T0, steps, h=1e-3, v=0.0, L_end=10.0):
    """Tension-controlled winch on an elastic cable whose far end moves towards the winch at
    v (m/s): T = k (L - L0), the winch's reference L' = -v. Returns the first winch's
    tensions (steps,) and the number of steps at which every winch was limited."""
    m = drive.L0.shape[0]
    drive.L0[:] = L_end - T0 / K_CABLE
    T_cmd = np.full(m, float(T_cmd))
    Ld, Ldd, T = np.full(m, -v), np.zeros(m), np.empty(m)
    out = np.empty(steps)
    L, n_limited = L_end, 0
    for k in range(steps):
        T[:] = np.maximum(0.0, K_CABLE * (L - drive.L0))
        out[k] = T[0]
        n_limited += winch_dynamics_step(drive, T_cmd, T, Ld, Ldd, h) == m
        L -= v * h
    return out, n_limited


def test_dynamics_step_response_follows_the_command():
    """Limits inactive: the tension steps 100 -> 300 N as the loop's second-order response."""
    p = WinchParams(**{**HAND.__dict__, "torque_max_Nm": np.inf, "speed_max_rad_s": np.inf,
                       "power_max_W": np.inf})
    zeta, k_T = 0.7, 1.0
    k_w = tension_loop_damping(p, K_CABLE, zeta, k_T)
    h, steps = 1e-5, 20_000
    drive = winch_drive(p, 1, L0=0.0, k_T=k_T, k_w=k_w)
    T, n_limited = run(drive, 300.0, 100.0, steps, h=h)
    # w_n^2 = k (r_d/G)^2 (1 + k_T) / J_eff = 1e5 * 2.5e-5 * 2 / 1.1e-4 -> w_n = 213.2 rad/s
    wn = 0.005 * np.sqrt(K_CABLE * (1 + k_T) / p.inertia_kg_m2)
    wd = wn * np.sqrt(1 - zeta**2)
    t = np.arange(steps) * h
    exact = 300.0 - 200.0 * np.exp(-zeta * wn * t) * (np.cos(wd * t) + zeta / np.sqrt(1 - zeta**2) * np.sin(wd * t))
    assert np.max(np.abs(T - exact)) < 0.5  # N, of 200: the loop acts a step h late
    assert T.max() == pytest.approx(exact.max(), abs=0.5)  # overshoot 9.2 N (4.6 %)
    assert T[-1] == pytest.approx(300.0, abs=1e-6)
    assert n_limited == 0 and (drive.limited == FREE).all()
    # and at 1 ms steps (the prototype's) it settles on the command too
    drive = winch_drive(p, 1, L0=0.0, k_T=k_T, k_w=k_w)
    assert run(drive, 300.0, 100.0, 500)[0][-1] == pytest.approx(300.0, abs=1e-6)


def test_dynamics_torque_saturation_at_rest():
    """A command past tau_max G / r_d = 400 N: the torque saturates at 2 N m, the tension
    settles at 400 N (viscous friction damps the saturated loop; no torque at rest)."""
    p = WinchParams(**{**HAND.__dict__, "viscous_friction_Nm_s": 5e-3})
    drive = winch_drive(p, 2, L0=0.0, k_T=1.0, k_w=tension_loop_damping(p, K_CABLE))
    T, n_limited = run(drive, 600.0, 100.0, 2000)
    assert T[-1] == pytest.approx(400.0, rel=1e-9)
    assert n_limited > 1900  # saturated but for a few steps of the first swing (T to 562 N)
    assert drive.tau == pytest.approx([2.0, 2.0], **EXACT)
    assert (drive.limited == TORQUE_LIMITED).all()


def test_dynamics_torque_saturation_winding_in():
    """The far end comes in at 0.5 m/s (omega_m = 100 rad/s): the saturated winch holds
    (tau_max - b omega_m - tau_c) G / r_d = (2 - 5e-3 * 100 - 0.1) * 200 = 280 N."""
    p = WinchParams(**{**HAND.__dict__, "power_max_W": 1e3, "viscous_friction_Nm_s": 5e-3,
                       "coulomb_friction_Nm": 0.1})
    drive = winch_drive(p, 1, L0=0.0, omega0=100.0, k_T=1.0, k_w=tension_loop_damping(p, K_CABLE))
    T, n_limited = run(drive, 600.0, 100.0, 2000, v=0.5)
    assert n_limited == 2000
    assert T[-1] == pytest.approx(280.0, rel=1e-9)
    assert drive.omega[0] == pytest.approx(100.0, rel=1e-9)
    assert drive.limited[0] == TORQUE_LIMITED


def test_dynamics_power_limit_meets_the_static_bound():
    """Winding in at 1 m/s (200 rad/s) the power limit binds: the tension the saturated winch
    settles on is winch_tension_bounds' T_hi, (200/200 - 2e-3 * 200) * 200 = 120 N."""
    p = WinchParams(**{**HAND.__dict__, "viscous_friction_Nm_s": 2e-3})
    drive = winch_drive(p, 1, L0=0.0, omega0=200.0, k_T=1.0, k_w=tension_loop_damping(p, K_CABLE))
    T, n_limited = run(drive, 600.0, 100.0, 3000, v=1.0)
    assert n_limited == 3000
    bound = winch_tension_bounds(-1.0, 0.0, p).winch_upper_N[0, 0]
    assert bound == pytest.approx(120.0, **EXACT)
    assert T[-1] == pytest.approx(bound, rel=1e-9)
    assert drive.tau[0] * drive.omega[0] == pytest.approx(200.0, rel=1e-9)


def test_dynamics_speed_limit_and_overspeed():
    """A slack cable: the torque-then-power-limited motor winds in up to omega_max exactly.
    A 1000 N load on a winch that holds 400 N: it runs out past omega_max (overspeed)."""
    drive = winch_drive(HAND, 1, L0=5.0, k_T=1.0)
    zero, h = np.zeros(1), 1e-3
    omega_prev = []
    for _ in range(400):
        omega_prev.append(drive.omega[0])
        winch_dynamics_step(drive, np.array([600.0]), zero, zero, zero, h)
        w0 = omega_prev[-1]
        assert abs(drive.tau[0]) <= min(2.0, 200.0 / abs(w0) if w0 else np.inf) * (1 + 1e-12)
    assert drive.omega[0] == 300.0
    assert drive.limited[0] == SPEED_LIMITED
    assert drive.tau[0] == pytest.approx(0.0, abs=1e-12)  # no load, no friction: none needed at speed
    # rest to 300 rad/s: 2 N m / J_eff to 100 rad/s, then 200 W
    drive = winch_drive(HAND, 1, L0=5.0)
    load = np.array([1000.0])
    for _ in range(100):
        winch_motor_step(drive, np.array([2.0]), load, h)
    assert drive.omega[0] < -300.0 and drive.limited[0] == OVERSPEED
    assert drive.L0[0] > 5.0  # paid out


def test_dynamics_coulomb_sticks():
    """At rest a net torque within tau_c leaves the motor at rest; past it, it breaks away."""
    p = WinchParams(**{**HAND.__dict__, "coulomb_friction_Nm": 0.1})
    drive = winch_drive(p, 2, L0=1.0)
    # holding 100 N needs 0.5 N m; 0.55 and 0.45 are within 0.1, 0.65 is not
    winch_motor_step(drive, np.array([0.55, 0.45]), np.array([100.0, 100.0]), 1e-3)
    assert drive.omega.tolist() == [0.0, 0.0] and drive.L0.tolist() == [1.0, 1.0]
    winch_motor_step(drive, np.array([0.65, 0.45]), np.array([100.0, 100.0]), 1e-3)
    # (0.65 - 0.5 - 0.1) / 1.1e-4 * 1e-3 = 0.4545... rad/s, winding in
    assert drive.omega[0] == pytest.approx(0.05 / 1.1e-4 * 1e-3, rel=1e-12)
    assert drive.omega[1] == 0.0
    assert drive.L0[0] == pytest.approx(1.0 - 0.005 * 1e-3 * drive.omega[0], rel=1e-15)
