"""Dynamics: ship-induced terms against finite differences, forward/inverse consistency."""

import numpy as np

from marinecdpr.motion.basemotion import evaluate_base_motion
from marinecdpr.motion.ship import still_ship
from marinecdpr.model.dynamics import forward_dynamics, spatial_inertia, wrench_terms
from marinecdpr.geometry.kinematics import cable_kinematics
from marinecdpr.planning.planner import _columns
from marinecdpr.scenario.schema import SinusoidalMotion
from marinecdpr.motion.trajectory import evaluate_trajectory

from conftest import make_scenario

SIX_DOF_SEA = SinusoidalMotion.model_validate({
    "type": "sinusoidal",
    "components": [
        {"dof": "surge", "amplitude_m": 0.4, "period_s": 7.0, "phase_deg": 10.0},
        {"dof": "sway", "amplitude_m": 0.3, "period_s": 6.5},
        {"dof": "heave", "amplitude_m": 0.8, "period_s": 8.0, "phase_deg": 40.0},
        {"dof": "roll", "amplitude_deg": 12.0, "period_s": 6.0},
        {"dof": "pitch", "amplitude_deg": 5.0, "period_s": 5.0, "phase_deg": 70.0},
        {"dof": "yaw", "amplitude_deg": 4.0, "period_s": 9.0, "offset_deg": 20.0},
    ],
})


def _terms(scenario, ship, t):
    plat = evaluate_trajectory(scenario.trajectory, t)
    r = scenario.robot
    return plat, wrench_terms(
        plat.x_PC_C, plat.twist, plat.twist_dot, plat.R_PC, ship,
        frame_origin_S=np.asarray(scenario.ship.frame_origin_m), mass=r.mass_kg,
        I_PP=r.inertia, gravity=scenario.environment.gravity_m_s2,
    )


def test_ship_induced_acceleration_matches_finite_differences_of_position_in_O(paper):
    """(relative + C_s) force / m = R_SO^T x_PO'' with x_PO = x_SO + R_SO (x_CS + x_PC) (eqs. 7, 9)."""
    h = 1e-4
    t = np.arange(0.0, 15.0, 0.37)
    tt = np.concatenate([t - h, t, t + h])
    ship = evaluate_base_motion(SIX_DOF_SEA, tt)
    plat, terms = _terms(paper, ship, tt)
    x_PS = plat.x_PC_C + np.asarray(paper.ship.frame_origin_m)
    x_PO = ship.x_SO_O + np.einsum("nij,nj->ni", ship.R_SO, x_PS)  # eq. (7)
    n = t.size
    acc_fd = (x_PO[2 * n:] - 2 * x_PO[n:2 * n] + x_PO[:n]) / h**2
    force = (terms.relative + terms.C_s)[n:2 * n, :3]
    acc_model = np.einsum("nij,nj->ni", ship.R_SO[n:2 * n], force) / paper.robot.mass_kg
    np.testing.assert_allclose(acc_model, acc_fd, atol=2e-5 * np.abs(acc_fd).max())
    assert np.abs(terms.C_s[:, :3]).max() > 1.0  # the sea matters here


def test_gravity_tilt_is_gravity_in_the_rolled_frame(paper):
    t = np.linspace(0, 6, 7)
    ship = evaluate_base_motion(SIX_DOF_SEA, t)
    _, terms = _terms(paper, ship, t)
    m, g = paper.robot.mass_kg, paper.environment.gravity_m_s2
    g_C = np.einsum("nji,j->ni", ship.R_SO, [0, 0, -g])
    np.testing.assert_allclose((terms.gravity + terms.gravity_tilt)[:, :3], -m * g_C, atol=1e-12)


def test_still_ship_has_no_ship_terms(paper):
    t = np.linspace(0, 15, 31)
    _, terms = _terms(paper, still_ship(t.size), t)
    assert not terms.C_s.any() and not terms.gravity_tilt.any()


def test_forward_dynamics_inverts_the_plan(paper, paper_plan):
    """Tensions from the plan, fed to forward dynamics, reproduce the planned acceleration."""
    idx = np.arange(0, paper_plan.n_steps, 250)
    t = paper_plan.t[idx]
    ship = evaluate_base_motion(paper.base_motion, t)
    plat = evaluate_trajectory(paper.trajectory, t)
    r = paper.robot
    kin = cable_kinematics(plat.x_PC_C, plat.R_PC, r.frame_anchors, r.platform_anchors)
    M = spatial_inertia(plat.R_PC, r.mass_kg, r.inertia)
    bias = wrench_terms(
        plat.x_PC_C, plat.twist, np.zeros_like(plat.twist), plat.R_PC, ship,
        frame_origin_S=np.asarray(paper.ship.frame_origin_m), mass=r.mass_kg, I_PP=r.inertia,
        gravity=paper.environment.gravity_m_s2,
    ).total
    acc, reaction = forward_dynamics(paper_plan.tensions[idx], kin.J_tilde, M, bias, r.controlled)
    np.testing.assert_allclose(acc, plat.twist_dot, atol=1e-9)
    np.testing.assert_allclose(reaction, paper_plan.reaction[idx], atol=1e-9)


def test_spatial_inertia_rotates_the_tensor():
    R = np.array([[[0.0, -1, 0], [1, 0, 0], [0, 0, 1]]])  # 90 deg about z
    M = spatial_inertia(R, 2.0, np.diag([1.0, 2.0, 3.0]))
    np.testing.assert_allclose(M[0], np.diag([2.0, 2, 2, 2, 1, 3]), atol=1e-15)


def test_absolute_motion_matches_finite_differences_and_eq13_equals_eq15(paper):
    """Eqs. (7)-(11) against differences of x_PO and R_SO R_PC; eq. (13) in O is S times eq. (15)."""
    from marinecdpr.model.dynamics import absolute_motion, inertial_frame_terms
    from marinecdpr.geometry.rotations import skew
    from test_against_reference import TRAJ, I_PP

    h = 1e-5
    t = np.linspace(0.25, 3.75, 8)  # away from the waypoints, where the jerk jumps
    tt = np.concatenate([t - h, t, t + h])
    ship = evaluate_base_motion(SIX_DOF_SEA, tt)
    plat = evaluate_trajectory(TRAJ, tt)
    origin = np.asarray(paper.ship.frame_origin_m)
    absm = absolute_motion(plat.x_PC_C, plat.twist, plat.twist_dot, ship, frame_origin_S=origin)
    n = t.size
    mid = slice(n, 2 * n)

    def d(x):
        return (x[2 * n:] - x[:n]) / (2 * h)

    np.testing.assert_allclose(absm.v_PO_O[mid], d(absm.x_PO_O), atol=1e-7)
    np.testing.assert_allclose(absm.a_PO_O[mid], d(absm.v_PO_O), atol=1e-6)
    np.testing.assert_allclose(absm.alpha_PO_O[mid], d(absm.omega_PO_O), atol=1e-6)
    R_PO = np.einsum("nij,njk->nik", ship.R_SO, plat.R_PC)
    np.testing.assert_allclose(d(R_PO), skew(absm.omega_PO_O[mid]) @ R_PO[mid], atol=1e-7)

    m, g = 5.0, 9.8
    M, C, G = inertial_frame_terms(ship.R_SO, plat.R_PC, absm.omega_PO_O, mass=m, I_PP=I_PP, gravity=g)
    X_dd = np.concatenate([absm.a_PO_O, absm.alpha_PO_O], axis=1)
    X_d = np.concatenate([absm.v_PO_O, absm.omega_PO_O], axis=1)
    lhs_O = np.einsum("nij,nj->ni", M, X_dd) + np.einsum("nij,nj->ni", C, X_d) - G  # eq. (13), F_r = 0
    w_C = wrench_terms(plat.x_PC_C, plat.twist, plat.twist_dot, plat.R_PC, ship, frame_origin_S=origin,
                       mass=m, I_PP=I_PP, gravity=g).total
    S = np.zeros((tt.size, 6, 6))
    S[:, :3, :3] = S[:, 3:, 3:] = ship.R_SO
    np.testing.assert_allclose(lhs_O, np.einsum("nij,nj->ni", S, w_C), atol=1e-10)  # eq. (15)
