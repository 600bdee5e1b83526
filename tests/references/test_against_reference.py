"""The fast, vectorised library against the slow per-step reference (tests/reference.py).

The reference was written from the paper's equations without reading the
package: absolute acceleration by product-rule differentiation of
x_PO = x_SO + R_SO (x_CS + x_PC), Newton-Euler in O, then rotated into C.
"""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

import reference as ref
from marinecdpr.motion.basemotion import evaluate_base_motion
from marinecdpr.model.dynamics import disturbance_in_C, wrench_terms
from marinecdpr.geometry.kinematics import cable_kinematics
from marinecdpr.scenario.schema import Disturbance, WaypointsTrajectory
from marinecdpr.model.tension import distribute_tensions
from marinecdpr.motion.trajectory import evaluate_disturbance, evaluate_trajectory

from test_dynamics import SIX_DOF_SEA

TRAJ = WaypointsTrajectory.model_validate({"type": "waypoints", "waypoints": [
    {"time_s": 0.0, "position_m": [0.9, 0.1, 0.7]},
    {"time_s": 2.0, "position_m": [1.2, -0.1, 0.9], "orientation_deg": [10.0, -20.0, 30.0]},
    {"time_s": 4.0, "position_m": [0.8, 0.2, 0.6], "orientation_deg": [-15.0, 25.0, -40.0]},
]})
DIST = Disturbance(frame="O", force_N=(3.0, -2.0, 1.0), moment_N_m=(0.2, 0.1, -0.3),
                   force_amplitude_N=(1.0, 0.5, 0.0), moment_amplitude_N_m=(0.0, 0.1, 0.2), period_s=1.3)
X_CS = np.array([-0.78, 0.0, 2.2])
MASS, G = 5.0, 9.8
I_PP = np.array([[0.03, 0.002, -0.001], [0.002, 0.04, 0.003], [-0.001, 0.003, 0.06]])


def test_required_wrench_matches_reference_on_a_six_dof_sea():
    t = np.linspace(0.05, 3.95, 40)
    ship = evaluate_base_motion(SIX_DOF_SEA, t)
    plat = evaluate_trajectory(TRAJ, t)
    f, m = evaluate_disturbance(DIST, t)
    f_C, m_C = disturbance_in_C(f, m, "O", ship.R_SO, plat.R_PC)
    w = wrench_terms(plat.x_PC_C, plat.twist, plat.twist_dot, plat.R_PC, ship, frame_origin_S=X_CS,
                     mass=MASS, I_PP=I_PP, gravity=G, f_ext_C=f_C, m_ext_C=m_C).total
    for i in range(t.size):
        expected = ref.required_wrench(plat.pose[i], plat.pose_dot[i], plat.pose_ddot[i], ship.eta[i],
                                       ship.eta_dot[i], ship.eta_ddot[i], X_CS, MASS, I_PP, G, f[i], m[i])
        np.testing.assert_allclose(w[i], expected, rtol=1e-10, atol=1e-10)


def test_ship_rates_match_reference():
    t = np.linspace(0, 9, 25)
    ship = evaluate_base_motion(SIX_DOF_SEA, t)
    for i in range(t.size):
        st_ = ref.ship_state(ship.eta[i], ship.eta_dot[i], ship.eta_ddot[i])
        np.testing.assert_allclose(ship.R_SO[i], st_["R_SO"], atol=1e-14)
        np.testing.assert_allclose(ship.R_SO[i] @ ship.omega_SO_S[i], st_["omega_O"], atol=1e-12)
        np.testing.assert_allclose(ship.R_SO[i] @ ship.alpha_SO_S[i], st_["alpha_O"], atol=1e-12)


def test_cable_quantities_match_reference():
    rng = np.random.default_rng(7)
    c, p = rng.uniform(-1, 3, size=(7, 3)), rng.uniform(-0.2, 0.2, size=(7, 3))
    t = np.linspace(0, 4, 11)
    plat = evaluate_trajectory(TRAJ, t)
    kin = cable_kinematics(plat.x_PC_C, plat.R_PC, c, p, plat.twist)
    for i in range(t.size):
        L, u, J = ref.cable_quantities(plat.pose[i], c, p)
        np.testing.assert_allclose(kin.lengths[i], L, rtol=1e-13)
        np.testing.assert_allclose(kin.units[i], u, atol=1e-13)
        np.testing.assert_allclose(kin.J_tilde[i], J, atol=1e-13)


def _check_against_brute_force(seed: int, n: int, m: int, k: int) -> None:
    rng = np.random.default_rng(seed)
    J = rng.normal(size=(n, m, k))
    J[:, :, :3] /= np.linalg.norm(J[:, :, :3], axis=2, keepdims=True)
    J[:, :, 3:] *= 0.2
    w = rng.normal(scale=150.0, size=(n, k))
    lo, hi = np.full(m, 10.0), np.full(m, 300.0)
    for method, target in (("minimum_variance", 155.0), ("minimum_norm", 0.0)):
        sol = distribute_tensions(J, w, lo, hi, method=method)
        for i in range(n):
            expected = ref.brute_force_least_distance(J[i], w[i], target, lo, hi)
            assert sol.feasible[i] == (expected is not None), (method, i)
            if expected is not None:
                np.testing.assert_allclose(sol.tensions[i], expected, atol=1e-6)


@settings(max_examples=30, deadline=None)
@given(st.integers(0, 2**32 - 1), st.sampled_from([5, 6]))
def test_planar_r2_r3_exact_qp_matches_brute_force(seed, m):
    """Minimum variance and minimum norm, 3 DOFs and 5 or 6 cables: the exact optimum."""
    _check_against_brute_force(seed, 8, m, 3)


@settings(max_examples=3, deadline=None)
@given(st.integers(0, 2**32 - 1))
def test_spatial_r2_exact_qp_matches_brute_force(seed):
    """8 cables and 6 DOFs (r = 2); 3^8 active sets per step, so few examples."""
    _check_against_brute_force(seed, 3, 8, 6)
