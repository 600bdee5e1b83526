"""Tension distribution: hand-worked statics, identities, and agreement with a QP solver."""

import numpy as np
import pytest
import quadprog
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from marinecdpr.scenario.fields import TENSION_METHODS
from marinecdpr.model.tension import distribute_tensions, null_space, pseudo_inverse_tensions

LO, HI = 10.0, 450.0


def symmetric_hanging():
    """The paper's robot, platform at the frame's centre, still: w = (0, m g, 0)."""
    L = np.hypot(0.825, 0.55)
    ux = np.array([-0.825, 0.825, 0.825, -0.825]) / L
    uz = np.array([0.55, 0.55, -0.55, -0.55]) / L
    my = np.array([-0.055, 0.055, -0.055, 0.055]) / L  # ((R p) x u)_y = r_z u_x - r_x u_z
    J = np.stack([ux, uz, my], axis=1)[None]
    w = np.array([[0.0, 5.0 * 9.8, 0.0]])
    return J, w, L


def test_symmetric_hanging_platform_by_hand():
    J, w, L = symmetric_hanging()
    # T1 = T2 = a, T3 = T4 = b: vertical balance 2 (a - b) 0.55 / L = m g, and T_s is
    # orthogonal to the null vector N = (1, 1, 1, 1) / 2, so b = -a.
    a = 49.0 * L / 2.2
    T_s, ok = pseudo_inverse_tensions(J, w)
    assert ok.all()
    np.testing.assert_allclose(T_s[0], [a, a, -a, -a], rtol=1e-12)
    N = null_space(J)[0, :, 0]
    np.testing.assert_allclose(np.abs(N), 0.5, rtol=1e-12)
    lo, hi = np.full(4, LO), np.full(4, HI)
    mv = distribute_tensions(J, w, lo, hi, method="minimum_variance")
    np.testing.assert_allclose(mv.tensions[0], np.array([a, a, -a, -a]) + 230.0, rtol=1e-12)
    mn = distribute_tensions(J, w, lo, hi, method="minimum_norm")
    np.testing.assert_allclose(mn.tensions[0], [2 * a + 10.0, 2 * a + 10.0, 10.0, 10.0], rtol=1e-12)
    # closed form (Pott) is the unconstrained minimum-variance solution: the same here
    cf = distribute_tensions(J, w, lo, hi, method="closed_form")
    np.testing.assert_allclose(cf.tensions, mv.tensions, rtol=1e-12)
    assert not distribute_tensions(J, w, lo, hi, method="pseudo_inverse").feasible[0]


def random_problem(seed: int, n_steps: int, m: int, k: int, wrench_scale: float):
    rng = np.random.default_rng(seed)
    J = rng.normal(size=(n_steps, m, k))
    J[:, :, :3] /= np.linalg.norm(J[:, :, :3], axis=2, keepdims=True)  # unit force directions
    J[:, :, 3:] *= 0.2
    w = rng.normal(scale=wrench_scale, size=(n_steps, k))
    lo = rng.uniform(0.0, 20.0, size=m)
    hi = lo + rng.uniform(100.0, 500.0, size=m)
    return J, w, lo, hi


def qp_reference(J, w, target, lo, hi):
    """A general QP solver per step: min |T - target|^2, J^T T = w, lo <= T <= hi."""
    m, k = J.shape
    C = np.hstack([J, np.eye(m), -np.eye(m)])
    try:
        return quadprog.solve_qp(np.eye(m), target, C, np.concatenate([w, lo, -hi]), k)[0]
    except ValueError:
        return None


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**32 - 1), st.sampled_from([(4, 3), (5, 4), (7, 6)]), st.floats(10, 400))
def test_r1_closed_form_matches_a_general_qp_solver(seed, shape, scale):
    """Minimum variance and minimum norm (r = 1, exact clipping) against quadprog."""
    m, k = shape
    J, w, lo, hi = random_problem(seed, 25, m, k, scale)
    for method, target in (("minimum_variance", 0.5 * (lo + hi)), ("minimum_norm", np.zeros(m))):
        sol = distribute_tensions(J, w, lo, hi, method=method)
        for i in range(len(w)):
            ref = qp_reference(J[i], w[i], target, lo, hi)
            assert sol.feasible[i] == (ref is not None), (method, i)
            if ref is not None:
                np.testing.assert_allclose(sol.tensions[i], ref, atol=1e-6 * hi.max())


@settings(max_examples=25, deadline=None)
@given(st.integers(0, 2**32 - 1), st.sampled_from(TENSION_METHODS),
       st.sampled_from([(4, 3), (6, 3), (8, 6)]))
def test_every_method_returns_exact_in_range_tensions_or_flags_the_step(seed, method, shape):
    """J~^T T = w and T_min <= T <= T_max at feasible steps; NaN otherwise. Never silent."""
    m, k = shape
    J, w, lo, hi = random_problem(seed, 40, m, k, 150.0)
    sol = distribute_tensions(J, w, lo, hi, method=method)
    T = sol.tensions[sol.feasible]
    np.testing.assert_allclose(np.einsum("nmk,nm->nk", J[sol.feasible], T), w[sol.feasible],
                               atol=1e-8 * max(1.0, np.abs(w).max()))
    tol = 1e-9 * hi.max()
    assert np.all(T >= lo - tol) and np.all(T <= hi + tol)
    assert np.isnan(sol.tensions[~sol.feasible]).all()


@settings(max_examples=25, deadline=None)
@given(st.integers(0, 2**32 - 1))
def test_improved_closed_form_never_loses_a_closed_form_solution(seed):
    J, w, lo, hi = random_problem(seed, 60, 6, 3, 200.0)
    cf = distribute_tensions(J, w, lo, hi, method="closed_form")
    icf = distribute_tensions(J, w, lo, hi, method="improved_closed_form")
    assert np.all(icf.feasible[cf.feasible])
    np.testing.assert_allclose(icf.tensions[cf.feasible], cf.tensions[cf.feasible], rtol=1e-10)
    # and it finds solutions the plain closed form misses, within the true feasible set
    mv = distribute_tensions(J, w, lo, hi, method="minimum_variance")
    assert not np.any(icf.feasible & ~mv.feasible)


def test_wrench_beyond_the_limits_is_infeasible_for_every_method():
    J, w, _ = symmetric_hanging()
    w = w * 100.0  # 4900 N on cables limited to 450 N
    for method in TENSION_METHODS:
        sol = distribute_tensions(J, w, np.full(4, LO), np.full(4, HI), method=method)
        assert not sol.feasible[0] and np.isnan(sol.tensions[0]).all(), method


def test_singular_pose_is_flagged_not_divided_by_zero():
    J, w, _ = symmetric_hanging()
    J = J.copy()
    J[0, :, 2] = 0.0  # no cable can exert a moment: J~ loses rank
    T_s, ok = pseudo_inverse_tensions(J, w)
    assert not ok[0] and np.isnan(T_s[0]).all()
    for method in TENSION_METHODS:
        sol = distribute_tensions(J, w, np.full(4, LO), np.full(4, HI), method=method)
        assert not sol.feasible[0], method


def test_unknown_method_is_a_value_error():
    J, w, _ = symmetric_hanging()
    with pytest.raises(ValueError, match="unknown tension method"):
        distribute_tensions(J, w, np.full(4, LO), np.full(4, HI), method="fastest")


@settings(max_examples=25, deadline=None)
@given(st.integers(0, 2**32 - 1), st.sampled_from([(4, 3), (6, 3), (8, 6)]))
def test_each_steps_own_bounds_against_a_general_qp_solver(seed, shape):
    """Per-step bounds (a winch's range) tighten the limits step by step; the target stays the
    middle of [t_min, t_max]. The exact methods against quadprog at every step, every method
    against itself solved one step at a time with that step's limits (r = 1 closed forms in
    numpy, r > 1 compiled)."""
    m, k = shape
    rng = np.random.default_rng(seed)
    n = 30
    J, w, lo, hi = random_problem(seed, n, m, k, 120.0)
    lower = lo + rng.uniform(-50.0, 150.0, size=(n, m)) * (rng.random((n, m)) < 0.5)
    upper = hi - rng.uniform(-50.0, 300.0, size=(n, m)) * (rng.random((n, m)) < 0.5)
    eff_lo, eff_hi = np.maximum(lo, lower), np.minimum(hi, upper)
    mid = 0.5 * (lo + hi)
    for method, target in (("minimum_variance", mid), ("minimum_norm", np.zeros(m))):
        sol = distribute_tensions(J, w, lo, hi, method=method, lower=lower, upper=upper)
        for i in range(n):
            ref = qp_reference(J[i], w[i], target, eff_lo[i], eff_hi[i]) if np.all(eff_lo[i] <= eff_hi[i]) else None
            assert sol.feasible[i] == (ref is not None), (method, i)
            if ref is not None:
                np.testing.assert_allclose(sol.tensions[i], ref, atol=1e-6 * hi.max())
    for method in TENSION_METHODS:
        sol = distribute_tensions(J, w, lo, hi, method=method, lower=lower, upper=upper)
        T = sol.tensions[sol.feasible]
        tol = 1e-9 * hi.max()
        assert np.all(T >= eff_lo[sol.feasible] - tol) and np.all(T <= eff_hi[sol.feasible] + tol), method
        if method in ("closed_form", "pseudo_inverse"):  # the static solution, kept where it is in bounds
            free = distribute_tensions(J, w, lo, hi, method=method)
            inside = free.feasible & np.all((free.tensions >= eff_lo - tol) & (free.tensions <= eff_hi + tol), axis=1)
            np.testing.assert_array_equal(sol.feasible, inside)
            np.testing.assert_array_equal(sol.tensions[inside], free.tensions[inside])
        if method == "improved_closed_form":
            for i in range(n):  # one step at a time: the same as the series
                one = distribute_tensions(J[i:i + 1], w[i:i + 1], lo, hi, method=method,
                                          lower=lower[i:i + 1], upper=upper[i:i + 1])
                assert one.feasible[0] == sol.feasible[i]
                np.testing.assert_array_equal(one.tensions[0], sol.tensions[i])


def test_bounds_that_never_bind_change_nothing():
    J, w, lo, hi = random_problem(3, 50, 6, 3, 150.0)
    for method in TENSION_METHODS:
        free = distribute_tensions(J, w, lo, hi, method=method)
        bound = distribute_tensions(J, w, lo, hi, method=method, lower=np.full((50, 6), -1e9),
                                    upper=np.full((50, 6), 1e9))
        np.testing.assert_array_equal(bound.tensions, free.tensions)
        np.testing.assert_array_equal(bound.feasible, free.feasible)
