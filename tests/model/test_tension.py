"""Tension distribution: hand-worked statics, identities, and agreement with a QP solver."""

from __future__ import annotations

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


# -------------------- formerly tests/test_compiled_qp.py

"""The compiled exact tension solvers (issue 10, item 2) against independent references.

``marinecdpr.model.kernels.least_distance`` (a dual active-set QP) and
``marinecdpr.model.kernels.improved_closed_form`` run every step of planning
(``distribute_tensions``) and of the closed loop (``tensions_step``). Here they meet
quadprog (a general QP solver), an LP feasibility check (scipy's linprog) and a numpy
transcription of Pott's improved closed form, on random problems built so that many
limits are active and many problems have no solution, and on examples/spatial_cube8.toml.
"""

from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import linprog

import marinecdpr
from marinecdpr.model import tension_solver as K
from marinecdpr.geometry.kinematics import cable_kinematics
from marinecdpr.prototype.simulation import simulate
from marinecdpr.model.tension import TENSION_TOLERANCE, distribute_tensions
from marinecdpr.motion.trajectory import evaluate_trajectory


EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
SHAPES = [(4, 3), (5, 3), (6, 3), (7, 6), (8, 6), (9, 6)]  # (n, k): r = 1, 2, 3, planar and spatial


def tol_of(hi):
    return TENSION_TOLERANCE * max(1.0, float(np.max(np.abs(hi))))


def problem(rng, n, k):
    """A random structure equation whose optimum often sits on limits (or has none).

    Unit force directions, moment arms of ~0.2 m, limits of 0..20 N to +50..300 N, and a
    wrench made by tensions drawn within the limits (feasible) or up to 40 N beyond them.
    """
    A = rng.normal(size=(n, k))
    A[:, :3] /= np.linalg.norm(A[:, :3], axis=1, keepdims=True)
    A[:, 3:] *= 0.2
    lo = rng.uniform(0.0, 20.0, n)
    hi = lo + rng.uniform(50.0, 300.0, n)
    beyond = 40.0 * rng.integers(0, 2)
    b = A.T @ rng.uniform(lo - beyond, hi + beyond)
    return A, b, lo, hi


def targets(rng, lo, hi):
    """The methods' targets (E, 0) and an arbitrary one far from the box."""
    return [0.5 * (lo + hi), np.zeros(lo.size), rng.uniform(lo - 100.0, hi + 100.0)]


def solve(A, b, target, lo, hi, rcond=0.0):
    n, k = A.shape
    T = np.empty(n)
    state = np.empty(n, dtype=np.int64)
    status = K.least_distance(A, b, target, K.Limits(lo, hi, tol_of(hi)), rcond, T, np.zeros((3, k, k)),
                              np.empty((2, k)), np.empty((2, n)), state)
    return status, T, state


def assert_same_optimum(T, ref, target):
    scale = max(1.0, np.abs(ref).max())
    assert np.abs(T - ref).max() <= 1e-9 * scale
    f, f_ref = np.sum((T - target) ** 2), np.sum((ref - target) ** 2)
    assert abs(f - f_ref) <= 1e-9 * max(f_ref, 1.0)


@pytest.mark.parametrize("n, k", SHAPES)
def test_least_distance_equals_quadprog_on_random_problems(n, k):
    """>= 1000 problems per shape (x 3 targets), with r = n - k = 1, 2 and 3."""
    rng = np.random.default_rng(1000 * n + k)
    feasible = infeasible = active = 0
    for _ in range(1000):
        A, b, lo, hi = problem(rng, n, k)
        for target in targets(rng, lo, hi):
            status, T, state = solve(A, b, target, lo, hi)
            ref = qp_reference(A, b, target, lo, hi)
            assert (status == 1) == (ref is not None)
            if ref is None:
                infeasible += 1
                assert np.isnan(T).all()
                continue
            feasible += 1
            assert_same_optimum(T, ref, target)
            # exactly on the structure equation and within limits
            np.testing.assert_allclose(A.T @ T, b, atol=1e-9 * max(1.0, np.abs(b).max()))
            assert np.all(T >= lo - tol_of(hi)) and np.all(T <= hi + tol_of(hi))
            on_limit = (np.abs(ref - lo) < 1e-9) | (np.abs(ref - hi) < 1e-9)
            active += bool(on_limit.any())
            # the active set it reports is the limits the optimum sits on
            assert np.all(on_limit[state != 0])
    # the problems exercise the active set and the infeasibility proof, not just the easy case
    assert active > 0.4 * feasible and infeasible > 0.1 * 3000 and feasible > 0.4 * 3000


@pytest.mark.parametrize("n, k", SHAPES)
def test_distribute_tensions_equals_quadprog_over_a_series(n, k):
    """The planning path (blocks of steps, then the active set from the closed form)."""
    rng = np.random.default_rng(7 * n + k)
    lo = rng.uniform(0.0, 20.0, n)
    hi = lo + rng.uniform(50.0, 300.0, n)
    J = np.empty((400, n, k))
    w = np.empty((400, k))
    for s in range(400):
        A, _, _, _ = problem(rng, n, k)
        J[s] = A
        w[s] = A.T @ rng.uniform(lo - 40.0, hi + 40.0)
    for method, target in (("minimum_variance", 0.5 * (lo + hi)), ("minimum_norm", np.zeros(n))):
        sol = distribute_tensions(J, w, lo, hi, method=method)
        if n - k == 1:
            continue  # r = 1 has its closed form (tests/model/test_tension.py); the kernel below
        for s in range(len(w)):
            ref = qp_reference(J[s], w[s], target, lo, hi)
            assert sol.feasible[s] == (ref is not None), (method, s)
            if ref is not None:
                assert_same_optimum(sol.tensions[s], ref, target)
            else:
                assert np.isnan(sol.tensions[s]).all()
        assert 0.1 * len(w) < sol.feasible.sum() < len(w)


@pytest.mark.parametrize("n, k", SHAPES)
def test_tensions_step_equals_quadprog(n, k):
    """The closed loop's per-step path, for every redundancy (r = 1 has its own closed form)."""
    rng = np.random.default_rng(11 * n + k)
    dofs = np.array([0, 2, 4]) if k == 3 else np.arange(6)
    J6, w6, T = np.zeros((n, 6)), np.zeros(6), np.empty(n)
    work = K.tension_work(n, k)  # one working memory for every solve: nothing carries over
    for _ in range(300):
        A, b, lo, hi = problem(rng, n, k)
        J6[:, dofs], w6[dofs] = A, b
        for method, target in (("minimum_variance", 0.5 * (lo + hi)), ("minimum_norm", np.zeros(n))):
            ok = K.tensions_step(J6, w6, dofs, lo, hi, K.METHOD_CODES[method], T, work)
            ref = qp_reference(A, b, target, lo, hi)
            assert ok == (ref is not None)
            if ok:
                assert_same_optimum(T, ref, target)
            else:
                assert np.isnan(T).all()


def lp_margin(A, b, lo, hi):
    """The largest s with lo + s <= T <= hi - s and A^T T = b (linprog); -inf if none."""
    n, k = A.shape
    c = np.zeros(n + 1)
    c[-1] = -1.0
    A_ub = np.vstack([np.hstack([-np.eye(n), np.ones((n, 1))]), np.hstack([np.eye(n), np.ones((n, 1))])])
    res = linprog(c, A_ub=A_ub, b_ub=np.concatenate([-lo, hi]), A_eq=np.hstack([A.T, np.zeros((k, 1))]),
                  b_eq=b, bounds=[(None, None)] * (n + 1), method="highs")
    return -res.fun if res.status == 0 else -np.inf


@pytest.mark.parametrize("n, k", SHAPES)
def test_infeasible_problems_are_those_an_lp_finds_infeasible(n, k):
    rng = np.random.default_rng(100 + 10 * n + k)
    decided = {True: 0, False: 0}
    for _ in range(300):
        A, b, lo, hi = problem(rng, n, k)
        margin = lp_margin(A, b, lo, hi)
        if abs(margin) < 1e-6:
            continue  # on the edge of feasibility: either answer is right to rounding
        status, T, _ = solve(A, b, 0.5 * (lo + hi), lo, hi)
        assert (status == 1) == (margin > 0), margin
        decided[margin > 0] += 1
        if status != 1:
            assert np.isnan(T).all()
    assert min(decided.values()) > 20


def test_rank_deficient_and_degenerate_problems_are_flagged():
    rng = np.random.default_rng(3)
    A, b, lo, hi = problem(rng, 8, 6)
    mid = 0.5 * (lo + hi)
    # no cable can exert a moment about z: J~^T J~ singular
    A0 = A.copy()
    A0[:, 5] = 0.0
    assert solve(A0, b, mid, lo, hi)[0] == -1
    assert solve(A0, b, mid, lo, hi, rcond=1e-12)[0] == -1
    # two identical DOF columns: singular too
    A1 = A.copy()
    A1[:, 4] = A1[:, 3]
    status, T, _ = solve(A1, A1.T @ mid, mid, lo, hi, rcond=1e-12)
    assert status == -1 and np.isnan(T).all()
    # a wrench no tensions within limits make: every cable at its upper limit is not enough
    status, T, _ = solve(A, A.T @ hi * 3.0, mid, lo, hi)
    assert status == 0 and np.isnan(T).all()
    # as many cables as DOFs (r = 0): the one solution, or nothing
    Asq = A[:6]
    T0 = rng.uniform(lo[:6], hi[:6])
    status, T, _ = solve(Asq, Asq.T @ T0, mid[:6], lo[:6], hi[:6])
    assert status == 1 and np.allclose(T, T0, rtol=1e-9)
    T1 = T0.copy()
    T1[0] = hi[0] + 10.0  # the one solution breaks a limit
    status, T, _ = solve(Asq, Asq.T @ T1, mid[:6], lo[:6], hi[:6])
    assert status == 0 and np.isnan(T).all()
    # the target on the box already, the wrench of the target: the target itself
    status, T, _ = solve(A, A.T @ hi, hi, lo, hi)
    assert status == 1 and np.allclose(T, hi, rtol=1e-12)
    # degenerate: every limit equal (lo = hi), wrench made by exactly those tensions
    status, T, _ = solve(A, A.T @ lo, mid, lo, lo.copy())
    assert status == 1 and np.allclose(T, lo, rtol=1e-9)


def improved_closed_form_reference(A, b, lo, hi):
    """Pott's improved closed form, written out with numpy (the former vectorised code)."""
    n, k = A.shape
    tol = tol_of(hi)
    mid = 0.5 * (lo + hi)
    free = np.ones(n, dtype=bool)
    T_fixed = np.zeros(n)
    for _ in range(n - k + 1):
        Af = A[free]
        G = Af.T @ Af
        eig = np.linalg.eigvalsh(G)
        if not eig[0] > 1e-12 * eig[-1]:
            return None
        x = np.linalg.solve(G, b - A[~free].T @ T_fixed[~free] - Af.T @ mid[free])
        T = np.where(free, mid + A @ x, T_fixed)
        viol = np.where(free, np.maximum(np.maximum(lo - T, T - hi), 0.0), 0.0)
        if viol.max() <= tol:
            return T
        j = int(np.argmax(viol))
        free[j] = False
        T_fixed[j] = lo[j] if T[j] < lo[j] else hi[j]
    return None


@pytest.mark.parametrize("n, k", SHAPES)
def test_improved_closed_form_equals_its_numpy_transcription(n, k):
    rng = np.random.default_rng(500 + 10 * n + k)
    lo = rng.uniform(0.0, 20.0, n)
    hi = lo + rng.uniform(50.0, 300.0, n)
    J = np.empty((300, n, k))
    w = np.empty((300, k))
    for s in range(300):
        A, _, _, _ = problem(rng, n, k)
        J[s] = A
        w[s] = A.T @ rng.uniform(lo - 20.0, hi + 20.0)
    sol = distribute_tensions(J, w, lo, hi, method="improved_closed_form")
    dofs = np.array([0, 2, 4]) if k == 3 else np.arange(6)
    J6, w6, T = np.zeros((n, 6)), np.zeros(6), np.empty(n)
    work = K.tension_work(n, k)
    fixed = 0
    for s in range(len(w)):
        ref = improved_closed_form_reference(J[s], w[s], lo, hi)
        J6[:, dofs], w6[dofs] = J[s], w[s]
        ok = K.tensions_step(J6, w6, dofs, lo, hi, K.METHOD_CODES["improved_closed_form"], T, work)
        assert sol.feasible[s] == ok == (ref is not None), s
        if ref is not None:
            np.testing.assert_allclose(sol.tensions[s], ref, rtol=1e-9, atol=1e-9 * hi.max())
            np.testing.assert_allclose(T, ref, rtol=1e-9, atol=1e-9 * hi.max())
            fixed += bool(np.any((ref == lo) | (ref == hi)))
    assert fixed > 10  # cables were held at limits


# ------------------------------------------------------------------ spatial_cube8 (r = 2)
@pytest.fixture(scope="module")
def cube8():
    sc = marinecdpr.load_scenario(EXAMPLES / "spatial_cube8.toml")
    p = marinecdpr.plan(sc)
    plat = evaluate_trajectory(sc.trajectory, p.t)
    r = sc.robot
    J = cable_kinematics(plat.x_PC_C, plat.R_PC, r.frame_anchors, r.platform_anchors).J_tilde
    return sc, p, J, r


@pytest.mark.parametrize("method", ["minimum_variance", "minimum_norm"])
def test_spatial_cube8_plan_equals_quadprog(cube8, method):
    """The planned tensions equal those of the former path, quadprog at each step."""
    sc, _, J, r = cube8
    p = marinecdpr.plan(sc, method=method)
    lo, hi = r.tension_min, r.tension_max
    target = 0.5 * (lo + hi) if method == "minimum_variance" else np.zeros(r.n_cables)
    assert p.feasible.all()
    ref = np.array([qp_reference(np.ascontiguousarray(J[s]), p.wrench[s], target, lo, hi)
                    for s in range(p.n_steps)])
    np.testing.assert_allclose(p.tensions, ref, rtol=1e-9, atol=1e-9 * hi.max())
    if method == "minimum_norm":  # the lower limit holds cables at every step: the QP ran
        assert np.isclose(p.tensions, lo, rtol=0, atol=1e-9).any(axis=1).all()


def test_spatial_cube8_improved_closed_form_plan(cube8):
    sc, _, J, r = cube8
    p = marinecdpr.plan(sc, method="improved_closed_form")
    ref = np.array([improved_closed_form_reference(np.ascontiguousarray(J[s]), p.wrench[s], r.tension_min,
                                                   r.tension_max) for s in range(0, p.n_steps, 7)])
    np.testing.assert_allclose(p.tensions[::7], ref, rtol=1e-9)


def test_spatial_cube8_closed_loop_compiled(cube8):
    """The closed loop on the own plant: minimum variance (r = 2) runs the compiled QP's
    path every step and, its optimum being inside the limits here, equals Pott's closed
    form (the kernel's separate closed-form code) to rounding; minimum norm holds cables
    at the lower limit at every step and still tracks the plan to 1e-5 m."""
    sc, p, _, r = cube8
    n = 1500
    runs = {m: simulate(sc.with_changes(planning={"method": m}), run="closed_loop", plant="own", n_steps=n,
                        reference=p if m == "minimum_variance" else None)
            for m in ("minimum_variance", "closed_form", "minimum_norm")}
    mv, cf, mn = runs["minimum_variance"], runs["closed_form"], runs["minimum_norm"]
    np.testing.assert_allclose(mv.tensions_commanded, cf.tensions_commanded, rtol=1e-9)
    np.testing.assert_allclose(mv.pose, cf.pose, rtol=0, atol=1e-12)
    for res in runs.values():
        assert res.controller_fallbacks == 0
        assert np.abs(res.pose[:, :3] - res.pose_planned[:, :3]).max() < 1e-5
    lo, hi = r.tension_min, r.tension_max
    tol = tol_of(hi)
    assert np.all(mn.tensions_commanded >= lo - tol) and np.all(mn.tensions_commanded <= hi + tol)
    assert np.isclose(mn.tensions_commanded, lo, rtol=0, atol=1e-9).any(axis=1).all()
    # the minimum-norm commands are the planned minimum-norm tensions, corrected by feedback
    plan_mn = marinecdpr.plan(sc, method="minimum_norm")
    assert np.abs(mn.tensions_commanded - plan_mn.tensions[:n]).max() < 0.05 * hi.max()


def test_no_python_in_the_per_step_path():
    """No objmode in the loop and no quadprog in the library (it stays a test reference, and
    the comparison `marinecdpr latency` times beside the step, behind the bench extra)."""
    src = Path(marinecdpr.__file__).parent
    files = list(src.rglob("*.py"))
    assert len(files) > 20
    for f in files:
        assert "objmode" not in f.read_text(), f.name
        if f != src / "studies" / "latency.py":
            assert "import quadprog" not in f.read_text(), f.name


# -------------------- formerly tests/test_issue22_one_solver.py

"""Issue 22, item 3: one implementation of every tension method and one rank test.

The compiled solver (:func:`marinecdpr.model.kernels.solve_tensions`) is what planning
(:func:`~marinecdpr.model.tension.distribute_tensions`), the workspace, the studies and the
closed loop (:func:`~marinecdpr.model.kernels.tensions_step`) run. Checked here against the
former numpy implementation, kept in ``tests/tension_reference.py`` (the paper's formulas:
adjugate, signed minors, the clipped lambda of eq. 20), and at the rank test's threshold,
where the three rank tests there used to be let a plan be feasible at a pose the loop
called singular.
"""

import numpy as np
import pytest

from marinecdpr.model import tension_solver as K
from marinecdpr.model.tension import EXACT_METHODS, distribute_tensions, full_rank, pseudo_inverse_tensions
from tension_reference import reference_distribute_tensions, reference_full_rank, reference_pseudo_inverse

EXACT_R01 = [(4, 3), (7, 6), (3, 3), (6, 6)]


CASES = ([(shape, method) for shape in EXACT_R01 + [(6, 3), (8, 6)] for method in ("pseudo_inverse", "closed_form")]
         + [(shape, method) for shape in EXACT_R01 for method in ("minimum_variance", "minimum_norm")])
"""The exact methods' numpy formulas hold for r <= 1 (quadprog checks r > 1: test_compiled_qp.py)."""


@pytest.mark.parametrize(("shape", "method"), CASES)
def test_every_method_equals_the_numpy_formulas(shape, method):
    """Same steps feasible, and tensions within 1e-13 cond(J~) T_max of each other: the
    rounding of two ways of solving one system (measured: at most 5.7e-14 cond(J~) T_max,
    2.4e-13 T_max on 4 x 3 robots, 1.7e-9 T_max on the worst-conditioned random 6 x 6),
    over 20 x 200 random steps, half of them made by tensions within limits."""
    m, k = shape
    feasible = 0
    for seed in range(20):
        J, w, lo, hi = random_problem(seed, 200, m, k, 150.0)
        T_in = lo + np.random.default_rng(seed).uniform(0.3, 0.7, (100, m)) * (hi - lo)
        w[:100] = np.einsum("nia,ni->na", J[:100], T_in)  # half the steps made by tensions within limits
        ours = distribute_tensions(J, w, lo, hi, method=method)
        ref = reference_distribute_tensions(J, w, lo, hi, method=method)
        np.testing.assert_array_equal(ours.feasible, ref.feasible)
        f = ours.feasible
        gap = np.abs(ours.tensions[f] - ref.tensions[f]).max(axis=1)
        assert (gap <= 1e-13 * np.linalg.cond(J[f]) * hi.max()).all()
        feasible += int(ours.feasible.sum())
    assert feasible > 250  # the comparison is not between two NaN arrays


def test_pseudo_inverse_equals_the_numpy_formula_with_no_limits():
    for m, k in [(4, 3), (8, 6), (3, 3)]:
        J, w, _, _ = random_problem(7, 500, m, k, 150.0)
        T, ok = pseudo_inverse_tensions(J, w)
        T_ref, ok_ref = reference_pseudo_inverse(J, w)
        np.testing.assert_array_equal(ok, ok_ref)
        gap = np.abs(T - T_ref).max(axis=1)
        assert (gap <= 1e-13 * np.linalg.cond(J) * np.abs(T_ref).max()).all()
        np.testing.assert_allclose(np.einsum("nia,ni->na", J, T), w, rtol=0, atol=1e-11 * np.abs(w).max())


def near_singular(ratios, seed=3, m=4, k=3):
    """J~ (n, m, k) with singular values (1, ..., 1, sqrt(ratio)): the eigenvalues of J~^T J~
    have lambda_min / lambda_max = ratio exactly (to rounding), in random orientations."""
    rng = np.random.default_rng(seed)
    J = np.empty((len(ratios), m, k))
    for i, q in enumerate(ratios):
        U = np.linalg.qr(rng.normal(size=(m, m)))[0][:, :k]
        V = np.linalg.qr(rng.normal(size=(k, k)))[0]
        s = np.ones(k)
        s[-1] = np.sqrt(q)
        J[i] = U @ np.diag(s) @ V.T
    return J


def old_rank_tests(J):
    """The two rank tests planning and the loop used before (4 x 3): the planner's
    det G > 1e-12 (trace / 3)^3 and the loop's |det G| > 1e-12 (max G_aa)^3."""
    G = np.einsum("nia,nib->nab", J, J)
    det = np.linalg.det(G)
    plan = det > 1e-12 * (np.trace(G, axis1=1, axis2=2) / 3) ** 3
    loop = np.abs(det) > 1e-12 * np.diagonal(G, axis1=1, axis2=2).max(axis=1) ** 3
    return plan, loop


def test_plan_and_loop_agree_at_every_near_singular_pose():
    """Across lambda_min / lambda_max from 1e-13 to 1e-11: the old tests disagreed (a plan
    feasible where the loop fell back to the plan's tensions); now the plan, the loop and
    full_rank give one answer, that of the eigenvalues, and the same bits of tension."""
    ratios = np.geomspace(1e-13, 1e-11, 801)
    J = near_singular(ratios)
    plan_old, loop_old = old_rank_tests(J)
    assert (plan_old & ~loop_old).sum() > 50  # the bug: feasible in the plan, singular in the loop
    lo, hi = np.full(4, 10.0), np.full(4, 450.0)
    T0 = np.array([100.0, 200.0, 300.0, 150.0])
    w = np.einsum("nia,i->na", J, T0)  # made by tensions within limits: feasible where full rank
    ok = full_rank(J)
    clear = np.abs(ratios / 1e-12 - 1.0) > 1e-3  # eigenvalues to rounding: 1e-4 relative at 1e-12
    np.testing.assert_array_equal(ok[clear], ratios[clear] > 1e-12)
    np.testing.assert_array_equal(ok[clear], reference_full_rank(J)[clear])
    J6, w6, T = np.zeros((4, 6)), np.zeros(6), np.empty(4)
    dofs = np.array([0, 2, 4])
    work = K.tension_work(4, 3)
    for method, code in K.METHOD_CODES.items():
        sol = distribute_tensions(J, w, lo, hi, method=method)
        if method in ("closed_form", "minimum_variance", "improved_closed_form"):  # T0 is their closed form
            np.testing.assert_array_equal(sol.feasible, ok)
        for i in range(len(ratios)):
            J6[:, dofs] = J[i]
            w6[dofs] = w[i]
            if K.tensions_step(J6, w6, dofs, lo, hi, code, T, work):
                assert sol.feasible[i]
                np.testing.assert_array_equal(T, sol.tensions[i])
            elif sol.feasible[i]:
                # where the compiled step gives up, the plan's exact fallback (issue 37, item 10)
                # may find tensions, which the loop then takes from the plan: they must hold
                assert method in EXACT_METHODS
                Ti = sol.tensions[i]
                assert np.all(Ti >= lo - 1e-6) and np.all(Ti <= hi + 1e-6)
                np.testing.assert_allclose(np.einsum("ia,i->a", J[i], Ti), w[i], atol=1e-6 * np.abs(w[i]).max())
            else:
                assert np.isnan(sol.tensions[i]).all()


# -------------------- formerly tests/test_exact_tensions.py

"""The exact tension methods find tensions wherever any exist; the advice follows the limit
that holds (issue 37, item 10).

The robot is tests/geometry/test_singular.py's eight-cable one with a singular plane at z = 1.95 m:
near it J~ is ill-conditioned, and there the compiled active-set method had given up at steps
where a linear programme finds tensions with several newtons of headroom (t = 5.935 s: 3.7 N).
"""


import re

import numpy as np
import pytest
from scipy.optimize import linprog

import marinecdpr
from marinecdpr.geometry.kinematics import cable_kinematics
from marinecdpr.geometry.rotations import matrix_from_euler
from marinecdpr.model.tension import (TENSION_TOLERANCE, _series, distribute_tensions, exact_fallback, null_space,
                                      pseudo_inverse_tensions)
from marinecdpr.planning.planner import plan_at
from marinecdpr.planning.verdicts import sizing_hint as _sizing_hint

from test_singular import plane_robot_toml

TIMES = np.r_[np.arange(1.78, 1.99, 0.01), np.arange(5.93, 6.13, 0.005)]


@pytest.fixture(scope="module")
def plane(tmp_path_factory):
    path = tmp_path_factory.mktemp("plane") / "plane8.toml"
    text = plane_robot_toml().replace('period_s = 8.0\n', 'period_s = 8.0\n[[base_motion.components]]\n'
                                      'dof = "heave"\namplitude_m = 0.5\nperiod_s = 8.0\nphase_deg = 90.0\n')
    text = text.replace('time_s = 4.0\nposition_m = [2.5, 1.8, 2.7]',
                        'time_s = 4.0\nposition_m = [2.5, 1.8, 2.7]\n[[trajectory.waypoints]]\n'
                        'time_s = 8.0\nposition_m = [1.5, 1.2, 1.2]')
    path.write_text(text.replace("duration_s = 0.2", "duration_s = 8.0"))
    return marinecdpr.load_scenario(str(path))


def _steps(sc, t):
    """J~ (controlled columns) and the wrench at times t, as the plan has them."""
    p = plan_at(sc, t, method="minimum_variance")
    r = sc.robot
    J = cable_kinematics(p.pose[:, :3], matrix_from_euler(p.pose[:, 3:]), r.frame_anchors,
                         r.platform_anchors).J_tilde
    return p, J, p.wrench


def _lp_headroom(J, w, lo, hi):
    """max h: J^T T = w, lo + h <= T <= hi - h (HiGHS), one step: the independent check."""
    m = J.shape[0]
    A_ub = np.r_[np.c_[-np.eye(m), np.ones(m)], np.c_[np.eye(m), np.ones(m)]]
    b_ub = np.r_[-lo, hi]
    res = linprog(np.r_[np.zeros(m), -1.0], A_ub=A_ub, b_ub=b_ub, A_eq=np.c_[J.T, np.zeros(J.shape[1])], b_eq=w,
                  bounds=[(None, None)] * (m + 1), method="highs")
    return -res.fun if res.status == 0 else -np.inf


def _brute_force_qp(J, w, target, lo, hi):
    """min |T - target|^2, J^T T = w, lo <= T <= hi by every active set of up to r limits in
    the null space (slow and obvious): the projection of lambda_0 onto the polygon."""
    from itertools import combinations

    T_s = J @ np.linalg.solve(J.T @ J, w)
    N = null_space(J[None])[0]
    r = N.shape[1]
    lam0 = N.T @ (target - T_s)
    G = np.r_[N, -N]
    h = np.r_[lo - T_s, T_s - hi]     # G lam >= h
    best, best_d = None, np.inf
    for q in range(r + 1):
        for act in combinations(range(G.shape[0]), q):
            if q:
                Ga = G[list(act)]
                if np.linalg.matrix_rank(Ga) < q:
                    continue
                # project lam0 onto Ga lam = h_a
                lam = lam0 - Ga.T @ np.linalg.solve(Ga @ Ga.T, Ga @ lam0 - h[list(act)])
            else:
                lam = lam0
            if np.all(G @ lam >= h - 1e-7):
                d = np.linalg.norm(lam - lam0)
                if d < best_d:
                    best, best_d = T_s + N @ lam, d
    return best


@pytest.mark.parametrize("method", ["minimum_variance", "minimum_norm"])
def test_the_exact_methods_find_tensions_wherever_a_linear_programme_does(plane, method):
    r = plane.robot
    p, J, w = _steps(plane, TIMES)
    p = plan_at(plane, TIMES, method=method)
    lo, hi = r.tension_min, r.tension_max
    room = np.array([_lp_headroom(J[i], w[i], lo, hi) for i in range(TIMES.size)])
    regular = ~p.singular
    assert (room[regular] > 1.0).sum() >= 10 and (room[regular] < -1.0).sum() >= 5  # both kinds of step
    clear = regular & (np.abs(room) > 1e-6)
    np.testing.assert_array_equal(p.feasible[clear], room[clear] > 0)
    # and the compiled method alone had given up at some of them: the fallback is exercised
    target = np.zeros(8) if method == "minimum_norm" else 0.5 * (lo + hi)
    raw = _series(J, w, 2 if method == "minimum_variance" else 3, target, lo, hi, None,
                  TENSION_TOLERANCE * hi.max())
    assert (p.feasible & ~raw.feasible).sum() >= 3
    T = p.tensions[p.feasible]
    assert np.all(T >= lo - 1e-6) and np.all(T <= hi + 1e-6)
    np.testing.assert_allclose(np.einsum("nmk,nm->nk", J[p.feasible], T), w[p.feasible], atol=1e-6)


@pytest.mark.parametrize("method", ["minimum_variance", "minimum_norm"])
def test_the_fallback_is_the_exact_optimum_and_succeeded_steps_are_bit_for_bit(plane, method):
    r = plane.robot
    _, J, w = _steps(plane, TIMES)
    lo, hi = r.tension_min, r.tension_max
    target = np.zeros(8) if method == "minimum_norm" else 0.5 * (lo + hi)
    tol = TENSION_TOLERANCE * hi.max()
    raw = _series(J, w, 2 if method == "minimum_variance" else 3, target, lo, hi, None, tol)
    sol = distribute_tensions(J, w, lo, hi, method=method)
    # where the compiled method succeeds: its tensions, bit for bit
    np.testing.assert_array_equal(sol.tensions[raw.feasible], raw.tensions[raw.feasible])
    # the fallback agrees with the compiled method where that succeeds (two implementations)
    T_fb, found = exact_fallback(J[raw.feasible], w[raw.feasible], target, lo, hi, tol)
    assert found.all()
    np.testing.assert_allclose(T_fb, raw.tensions[raw.feasible], rtol=0, atol=1e-6)
    # where only the fallback finds tensions: the optimum, by brute force over the active sets
    new = np.flatnonzero(sol.feasible & ~raw.feasible)
    assert new.size >= 3
    for i in new:
        best = _brute_force_qp(J[i], w[i], target, lo, hi)
        np.testing.assert_allclose(sol.tensions[i], best, rtol=0, atol=1e-5)


def test_a_method_that_misses_them_names_the_one_that_finds_them(plane):
    t = np.array([5.95])
    pinv = plan_at(plane, t, method="pseudo_inverse")
    assert not pinv.feasible[0]
    line = pinv.limiting_cables(0)
    assert line.startswith("tensions within the limits exist there, but the pseudo inverse method did not find "
                           "them: the minimum variance method does"), line
    assert "--method minimum_variance" in line
    assert plan_at(plane, t, method="minimum_variance").feasible[0]


def _range(A, w, r, lo, hi):
    others = [q for q in range(len(w)) if q != r]
    ends = []
    for sign in (1.0, -1.0):
        res = linprog(sign * A[r], A_eq=A[others] if others else None, b_eq=w[others] if others else None,
                      bounds=list(zip(lo, hi)), method="highs")
        ends.append(A[r] @ res.x)
    return np.array(ends)


def test_the_advice_follows_the_limit_that_holds_the_near_end_of_the_range(plane):
    # hand-worked: two cables both pulling +x, 10 .. 100 N each: the force ranges over 20 .. 200 N
    A, lo, hi = np.array([[1.0, 1.0]]), np.array([10.0, 10.0]), np.array([100.0, 100.0])
    axes = np.array(["x"])
    lacking = ("force", "N", "along", np.array([0]), np.array([1.0]))
    below = _sizing_hint(A, np.array([5.0]), lo, hi, lacking, axes, False)
    assert "give 20 to 200 N along x there, against 5 N needed: lower robot.tension_min_N" in below
    assert "tension_max" not in below
    above = _sizing_hint(A, np.array([250.0]), lo, hi, lacking, axes, False)
    assert "against 250 N needed: raise robot.tension_max_N," in above and "tension_min" not in above
    # antagonistic: cable 1 pulls +x, cable 2 -x: -90 .. 90 N; past 90 N both limits hold the end
    # (cable 1 at T_max, cable 2 at T_min, 1 N each per N): lowering T_min to 0 closes 10 N at
    # most, so it is named where the gap is 5 N and not where it is 60 N
    A = np.array([[1.0, -1.0]])
    near = _sizing_hint(A, np.array([95.0]), lo, hi, lacking, axes, False)
    assert ("against 95 N needed: raise robot.tension_max_N or lower robot.tension_min_N (cables held at their "
            "least tension pull the wrong way there), or move") in near
    far = _sizing_hint(A, np.array([150.0]), lo, hi, lacking, axes, False)
    assert "against 150 N needed: raise robot.tension_max_N, or move" in far and "tension_min" not in far
    # checked by moving each side's limits: the ends the duals say
    assert _range(A, np.array([0.0]), 0, lo - 1.0, hi)[1] - 90.0 == pytest.approx(1.0)
    assert _range(A, np.array([0.0]), 0, lo, hi + 1.0)[1] - 90.0 == pytest.approx(1.0)
    assert _range(np.array([[1.0, 1.0]]), np.array([0.0]), 0, lo - 1.0, hi)[0] == pytest.approx(18.0)


def test_the_one_redundancy_screen_agrees_with_the_largest_headroom(paper):
    """For r = 1 the steps worth solving alone are told apart as an interval's ends; they are
    those where the largest headroom (its own closed form over the cables' tents) is >= 0."""
    from marinecdpr.model.tension import _may_hold, largest_headroom

    r = paper.robot
    rng = np.random.default_rng(11)
    n = 4000
    x = np.c_[rng.uniform(0.3, 1.6, n), np.zeros(n), rng.uniform(0.3, 1.1, n)]
    R = matrix_from_euler(np.c_[np.zeros(n), rng.uniform(-0.3, 0.3, n), np.zeros(n)])
    J = cable_kinematics(x, R, r.frame_anchors, r.platform_anchors).J_tilde[:, :, [0, 2, 4]]
    w = np.c_[rng.normal(0, 150, n), rng.normal(49, 150, n), rng.normal(0, 20, n)]
    T_s, _ = pseudo_inverse_tensions(J, w)
    room = largest_headroom(J, T_s, r.tension_min, r.tension_max)
    keep = _may_hold(J, w, r.tension_min, r.tension_max, 1e-9 * r.tension_max.max())
    clear = np.abs(room) > 1e-6
    assert 200 < (room[clear] > 0).sum() < clear.sum() - 200   # both kinds, many of each
    np.testing.assert_array_equal(keep[clear], room[clear] > 0)


# -------------------- formerly tests/test_wrench_facets.py

"""The facets of the wrenches that tensions within limits give (issue 37, item 3): the set is
a zonotope, and its facets' headrooms are the linear programme's headroom."""


import numpy as np
import pytest

from marinecdpr.model.tension import largest_headroom, pseudo_inverse_tensions, wrench_faces


@pytest.mark.parametrize("m,k", [(4, 3), (3, 2), (5, 3), (8, 6), (7, 6)])
def test_the_facets_headroom_is_the_linear_programme_s(m, k):
    """min_f (h_f - |n_f . (w - c)|) / s_f, capped at the narrowest range's half, equals
    largest_headroom (closed form for one degree of redundancy, vertices or HiGHS beyond) for
    random structure matrices, limits and wrenches, feasible or not."""
    rng = np.random.default_rng(m * 10 + k)
    J = rng.normal(size=(300, m, k))
    w = rng.normal(size=(300, k)) * 2.0
    lo = rng.uniform(1.0, 5.0, size=m)
    hi = lo + rng.uniform(5.0, 20.0, size=m)
    T_s, _ = pseudo_inverse_tensions(J, w)
    ref = largest_headroom(J, T_s, lo, hi)
    f = wrench_faces(J, lo, hi)
    u = np.einsum("nfk,nk->nf", f.normal, w - f.centre)
    h = np.minimum(((f.half_width - np.abs(u)) / f.per_newton).min(axis=1), ((hi - lo) / 2).min())
    np.testing.assert_allclose(h, ref, rtol=0, atol=1e-10 * np.abs(ref).max())
    assert (ref < 0).any() and (ref > 0).any()


def test_a_square_of_four_cables_by_hand():
    """Two cables along +x and -x, two along +z and -z (k = 2, T in [10, 110] N): the set is the
    square [-100, 100]^2 about 0. The wrench (60, -30) N lies 40 N inside the +x facet (cables
    1 and 2 at their limits there); tightening every limit by M moves that facet in by 2 M,
    so its headroom is 20 N: T_1 = 110 - M, T_2 = 10 + M give 100 - 2 M = 60."""
    J = np.array([[[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [0.0, -1.0]]])
    f = wrench_faces(J, np.full(4, 10.0), np.full(4, 110.0))
    np.testing.assert_allclose(f.centre[0], [0.0, 0.0], atol=1e-12)
    facet = np.flatnonzero(np.abs(f.normal[0, :, 0]) > 0.5)  # normals along x: cables 3 or 4 free
    assert set(f.free[facet, 0].tolist()) == {2, 3}
    np.testing.assert_allclose(f.half_width[0, facet], 100.0, rtol=1e-12)
    np.testing.assert_allclose(f.per_newton[0, facet], 2.0, rtol=1e-12)
    u = f.normal[0] @ np.array([60.0, -30.0])
    head = (f.half_width[0] - np.abs(u)) / f.per_newton[0]
    assert head.min() == pytest.approx(20.0, rel=1e-12)  # (100 - 60) / 2: each x cable gives 20 N


def test_the_limits_go_in_as_one_record():
    """The solvers take the limits and their tolerance as one record, Limits(lo, hi, tol)
    (issue 38, item 5). Hand-worked: two cables pull one DOF, T1 + T2 = 20 N nearest the
    target (5, 5) N: (10, 10) N within [0, 10] N; within [0, 9] N none (18 N at most);
    within [0, 9] N widened by tol = 1 N, (10, 10) N again (each 1 N over, which tol allows)."""
    A, b, target = np.array([[1.0], [1.0]]), np.array([20.0]), np.array([5.0, 5.0])

    def run(hi, tol):
        T, state = np.empty(2), np.empty(2, dtype=np.int64)
        limits = K.Limits(np.zeros(2), np.full(2, hi), tol)
        status = K.least_distance(A, b, target, limits, 0.0, T, np.zeros((3, 1, 1)), np.empty((2, 1)),
                                  np.empty((2, 2)), state)
        return status, T

    status, T = run(10.0, 1e-9)
    assert status == 1
    np.testing.assert_array_equal(T, [10.0, 10.0])
    status, T = run(9.0, 1e-9)
    assert status == 0 and np.isnan(T).all()
    status, T = run(9.0, 1.0)
    assert status == 1
    np.testing.assert_array_equal(T, [10.0, 10.0])
