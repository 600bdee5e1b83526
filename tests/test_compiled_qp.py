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

from test_tension import qp_reference

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
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
    status = K.least_distance(A, b, target, lo, hi, tol_of(hi), rcond, T, np.zeros((3, k, k)),
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
            continue  # r = 1 has its closed form (tests/test_tension.py); the kernel below
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
