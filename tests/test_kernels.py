"""The compiled per-step kernels against the vectorised library (the same equations twice)."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from marinecdpr.model import rigid_body as RB
from marinecdpr.model import tension_solver as TS
from marinecdpr.motion.basemotion import evaluate_base_motion
from marinecdpr.model.dynamics import forward_dynamics, spatial_inertia, wrench_terms
from marinecdpr.geometry.kinematics import cable_kinematics, cables_step
from marinecdpr.geometry.rotations import euler_kinematics, euler_step
from marinecdpr.model.tension import distribute_tensions
from marinecdpr.motion.trajectory import evaluate_trajectory

from test_against_reference import I_PP, TRAJ, X_CS
from test_dynamics import SIX_DOF_SEA
from test_tension import random_problem


def _setting(t):
    ship = evaluate_base_motion(SIX_DOF_SEA, t)
    plat = evaluate_trajectory(TRAJ, t)
    rng = np.random.default_rng(0)
    f_C, m_C = rng.normal(size=(t.size, 3)), rng.normal(size=(t.size, 3))
    return ship, plat, f_C, m_C


def test_euler_step_matches_vectorised():
    """The compiled step and series against the former numpy implementation."""
    import vectorised

    rng = np.random.default_rng(1)
    a, r, acc = rng.uniform(-1, 1, (3, 5, 3))
    R, w, al = vectorised.euler_kinematics(a, r, acc)
    Rs, ws, als = euler_kinematics(a, r, acc)
    np.testing.assert_allclose(Rs, R, rtol=0, atol=1e-15)
    np.testing.assert_allclose(ws, w, rtol=0, atol=1e-15)
    np.testing.assert_allclose(als, al, rtol=0, atol=1e-14)
    # broadcasting, a leading shape of two axes, no rates, constant angles (trig reused)
    grid = rng.uniform(-1, 1, (4, 6, 3))
    np.testing.assert_allclose(euler_kinematics(grid)[0], vectorised.euler_kinematics(grid)[0], atol=1e-15)
    assert euler_kinematics(grid)[1] is None
    const = np.broadcast_to(a[0], (7, 3))
    for got, ref in zip(euler_kinematics(const, r[0], acc[:1]), vectorised.euler_kinematics(const, r[0], acc[:1])):
        np.testing.assert_allclose(got, ref, rtol=0, atol=1e-14)
    Rk, wk, alk = np.empty((3, 3)), np.empty(3), np.empty(3)
    for i in range(5):
        euler_step(a[i], r[i], acc[i], Rk, wk, alk)
        np.testing.assert_allclose(Rk, R[i], atol=1e-15)
        np.testing.assert_allclose(wk, w[i], atol=1e-15)
        np.testing.assert_allclose(alk, al[i], atol=1e-14)


def test_wrench_and_cables_match_vectorised():
    t = np.linspace(0.1, 3.9, 12)
    ship, plat, f_C, m_C = _setting(t)
    terms = wrench_terms(plat.x_PC_C, plat.twist, plat.twist_dot, plat.R_PC, ship, frame_origin_S=X_CS,
                         mass=5.0, I_PP=I_PP, gravity=9.8, f_ext_C=f_C, m_ext_C=m_C)
    rng = np.random.default_rng(2)
    c, p = rng.uniform(-1, 3, (7, 3)), rng.uniform(-0.2, 0.2, (7, 3))
    kin = cable_kinematics(plat.x_PC_C, plat.R_PC, c, p)
    out, L, J = np.empty(6), np.empty(7), np.empty((7, 6))
    for i in range(t.size):
        RB.wrench_step(plat.x_PC_C[i].copy(), plat.v_PC_C[i].copy(), plat.a_PC_C[i].copy(),
                      np.ascontiguousarray(plat.R_PC[i]), plat.omega_PC_C[i].copy(),
                      plat.alpha_PC_C[i].copy(), np.ascontiguousarray(ship.R_SO[i]),
                      ship.omega_SO_S[i].copy(), ship.alpha_SO_S[i].copy(), ship.a_SO_O[i].copy(),
                      X_CS, 5.0, I_PP, 9.8, f_C[i], m_C[i], out)
        np.testing.assert_allclose(out, terms.total[i], rtol=1e-12, atol=1e-12)
        cables_step(plat.x_PC_C[i].copy(), np.ascontiguousarray(plat.R_PC[i]), c, p, L, J)
        np.testing.assert_allclose(L, kin.lengths[i], rtol=1e-14)
        np.testing.assert_allclose(J, kin.J_tilde[i], atol=1e-14)


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**32 - 1), st.sampled_from(["pseudo_inverse", "closed_form", "minimum_variance",
                                                   "minimum_norm", "improved_closed_form"]),
       st.sampled_from([(4, 3), (7, 6), (6, 3), (8, 6), (9, 6)]))
def test_tensions_step_matches_distribute_tensions(seed, method, shape):
    m, k = shape
    J, w, lo, hi = random_problem(seed, 20, m, k, 150.0)
    sol = distribute_tensions(J, w, lo, hi, method=method)
    dofs = np.array([0, 2, 4]) if k == 3 else np.arange(6)
    J6 = np.zeros((m, 6))
    w6 = np.zeros(6)
    T = np.empty(m)
    work = TS.tension_work(m, k)
    for i in range(len(w)):
        J6[:, dofs] = J[i]
        w6[dofs] = w[i]
        ok = TS.tensions_step(J6, w6, dofs, lo, hi, TS.METHOD_CODES[method], T, work)
        assert ok == sol.feasible[i]
        # one implementation: the series (blocks of steps) and the step give the same bits
        np.testing.assert_array_equal(T, sol.tensions[i])


def test_tensions_step_does_every_method_for_any_redundancy():
    """Redundancy above 1 for the exact methods, and the improved closed form, per step too
    (they used to fall back to the library through numba's objmode)."""
    J, _, lo, hi = random_problem(5, 1, 8, 6, 10.0)
    w = np.einsum("nmk,m->nk", J, lo + 0.3 * (hi - lo))  # made by tensions within limits
    T = np.empty(8)
    for method in ("minimum_variance", "minimum_norm", "improved_closed_form"):
        sol = distribute_tensions(J, w, lo, hi, method=method)
        assert sol.feasible[0]
        assert TS.tensions_step(J[0], w[0], np.arange(6), lo, hi, TS.METHOD_CODES[method], T, TS.tension_work(8, 6))
        np.testing.assert_allclose(T, sol.tensions[0], rtol=1e-9)
    J4, w4, lo4, hi4 = random_problem(5, 1, 4, 3, 10.0)
    J6 = np.zeros((4, 6))
    J6[:, [0, 2, 4]] = J4[0]
    T4 = np.empty(4)
    assert TS.tensions_step(J6, np.array([w4[0, 0], 0, w4[0, 1], 0, w4[0, 2], 0]), np.array([0, 2, 4]),
                           lo4, hi4, TS.METHOD_CODES["improved_closed_form"], T4, TS.tension_work(4, 3))
    np.testing.assert_allclose(T4, distribute_tensions(J4, w4, lo4, hi4, method="improved_closed_form")
                               .tensions[0], rtol=1e-9)


@pytest.mark.parametrize("controlled", [(0, 2, 4), (0, 1, 2, 3, 4, 5)])
def test_forward_step_matches_forward_dynamics(controlled):
    rng = np.random.default_rng(4)
    n, m = 6, 8
    R = euler_kinematics(rng.uniform(-0.5, 0.5, (n, 3)))[0]
    J = rng.normal(size=(n, m, 6))
    T = rng.uniform(10, 300, (n, m))
    bias = rng.normal(size=(n, 6))
    M = spatial_inertia(R, 5.0, I_PP)
    acc, _ = forward_dynamics(T, J, M, bias, controlled)
    out = np.empty(6)
    for i in range(n):
        RB.forward_step(J[i], T[i], bias[i], np.ascontiguousarray(R[i]), 5.0, I_PP,
                       np.array(controlled), out)
        np.testing.assert_allclose(out, acc[i], rtol=1e-11, atol=1e-11)
