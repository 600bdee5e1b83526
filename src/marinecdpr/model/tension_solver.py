"""The tension solver, compiled: every tension method per step, for any redundancy, and over
time series in blocks of steps, the only implementation of each.

Every tension method is written once, per step (:func:`solve_tensions`), with one rank test
(:func:`~marinecdpr.model.linalg.gram_full_rank`): the pseudo-inverse and Pott's closed form,
``minimum_variance`` and ``minimum_norm`` exactly (the compiled active-set QP
:func:`least_distance`) and Pott's improved closed form (:func:`improved_closed_form`). The
closed loop calls it at every step (:func:`tensions_step`, with its working memory
:class:`TensionWork`); planning, the workspace and the studies over time series
(:func:`tension_series`, through :func:`marinecdpr.model.tension.distribute_tensions`), in
blocks of steps that keep its order of operations: a plan and the loop get the same bits at
the same step. :func:`headroom_one_series` is the headroom of one degree of redundancy.
``tests/tension_reference.py`` keeps the former numpy implementation as the tests' check.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from marinecdpr.model.linalg import (
    RCOND, block_cholesky_solve, block_full_rank, block_gram_factor, cholesky, cholesky_solve, gram, gram_free,
    gram_full_rank, int_power,
)

__all__ = [
    "METHOD_CODES",
    "tensions_step",
    "Limits",
    "TensionWork",
    "tension_work",
    "least_distance",
    "improved_closed_form",
    "tension_series",
    "solve_tensions",
    "headroom_one_series",
]

METHOD_CODES = {"pseudo_inverse": 0, "closed_form": 1, "minimum_variance": 2, "minimum_norm": 3,
                "improved_closed_form": 4}
"""The tension methods by the code the compiled solver takes."""
_cache = True


class Limits(NamedTuple):
    """The tension limits as the compiled solvers take them (one record, a struct to numba).

    lo, hi : ndarray, N: (n,) at one step; for :func:`tension_series` (n, 1), the same at
    every step, or (n, n_steps), each step's own. tol : float, N: a tension within [lo -
    tol, hi + tol] counts as within limits (TENSION_TOLERANCE x max(1, max hi)).
    """

    lo: np.ndarray
    hi: np.ndarray
    tol: float


# ----------------------------------------------------------------- exact tension QP
# The exact methods for any redundancy and Pott's improved closed form, per step, all
# compiled: one implementation for planning (tension.distribute_tensions loops over the
# steps here) and for the closed loop (tensions_step). Arrays: A = J~_c (n, k) with rows
# a_i (cables), b = w_c (k,). An active set is ``state`` (n,): 0 free, +1 held at its lower
# limit, -1 held at its upper limit (the sign of the constraint's normal, +-e_i).
# Work arrays, preallocated by the caller: M (3, k, k) holds the Gram matrix A^T A of
# every cable, that of the free ones and its Cholesky factor; v (2, k) and wn (2, n).


@njit(cache=_cache)
def _solve_active(A, b, target, limits, state, rcond, M, y, T):
    """The equality-constrained minimiser of |T - target|^2 with the active set held at its
    limits: T_W = limits, T_F = target_F + A_F y, (A_F^T A_F) y = b - A_W^T T_W - A_F^T target_F.
    M[0] holds A^T A. Returns False (T untouched) where A_F^T A_F fails the rank test
    (:func:`gram_full_rank` with rcond)."""
    n, k = A.shape
    lo, hi = limits.lo, limits.hi
    G, L = M[1], M[2]
    gram_free(A, state, M[0], G)
    if not gram_full_rank(G, L, cholesky(G, L), rcond):
        return False
    for a in range(k):
        y[a] = b[a]
    for i in range(n):
        v = target[i] if state[i] == 0 else (lo[i] if state[i] > 0 else hi[i])
        for a in range(k):
            y[a] -= A[i, a] * v
    cholesky_solve(L, y)
    for i in range(n):
        if state[i] == 0:
            acc = target[i]
            for a in range(k):
                acc += A[i, a] * y[a]
            T[i] = acc
        else:
            T[i] = lo[i] if state[i] > 0 else hi[i]
    return True


@njit(cache=_cache)
def _within(T, limits):
    lo, hi, tol = limits.lo, limits.hi, limits.tol
    for i in range(T.shape[0]):
        if not (T[i] >= lo[i] - tol and T[i] <= hi[i] + tol):
            return False
    return True


@njit(cache=_cache)
def least_distance(A, b, target, limits, rcond, T, M, v, wn, state):
    """Exactly minimise |T - target|^2 subject to A^T T = b and lo <= T <= hi, written to T.

    A (n, k), b (k,), target (n,); limits: a :class:`Limits`, lo, hi (n,) and tol, the
    tolerance within which a tension counts as within limits; rcond: the rank test of
    :func:`_solve_active` for A^T A (0 to flag only a breakdown). Work arrays: M (3, k, k),
    v (2, k), wn (2, n) float and state (n,) int64 (it holds the final active set).

    The unconstrained (equality-only) optimum where it is within limits, else
    :func:`_active_set`. Returns 1 (T optimal, within limits to tol), 0 (infeasible: no T
    within limits satisfies A^T T = b; T NaN) or -1 (A^T A singular; T NaN).
    """
    n = A.shape[0]
    gram(A, M[0])
    for i in range(n):
        state[i] = 0
    if not _solve_active(A, b, target, limits, state, rcond, M, v[0], T):
        T[:] = np.nan
        return -1
    if _within(T, limits):  # the unconstrained optimum (the usual case)
        return 1
    return _active_set(A, b, target, limits, T, M, v, wn, state)


@njit(cache=_cache)
def _active_set(A, b, target, limits, T, M, v, wn, state):
    """:func:`least_distance` from the unconstrained optimum T (M[0] = A^T A, state all 0).

    The dual active-set method of Goldfarb and Idnani (quadprog's algorithm) specialised to
    an identity Hessian and bound constraints, the equality-constrained subproblems solved
    afresh (a k x k Cholesky of A_F^T A_F) at every change of the active set. It starts
    from the equality-constrained minimiser (dual feasible). While a limit is broken (by
    more than rounding, 1e-3 tol), it adds the most violated one, p: it steps along the
    primal direction z (p's normal projected onto the complement of the active normals)
    and the dual one r, and drops an active limit whose multiplier reaches zero first
    (partial step) until p holds (full step). The dual objective rises with every full
    step and partial steps shrink the active set, so the method ends after finitely many
    steps with the exact optimum, or proves the problem infeasible: a violated limit whose
    normal depends on the active ones (z = 0: dropping p's row from A_F would lose rank k)
    with no multiplier to drop. A limit broken by less than tol then is accepted, as
    everywhere. The optimum is re-solved on its final active set and checked (limits,
    A^T T = b); a cap on the iterations guards against rounding-induced cycling.
    """
    n, k = A.shape
    lo, hi, tol = limits.lo, limits.hi, limits.tol
    G, L = M[1], M[2]
    y, c = v[0], v[1]
    u, zr = wn[0], wn[1]
    for i in range(n):
        u[i] = 0.0
    eps = 1e-3 * tol
    it = 0
    max_it = 20 * (n + k) + 100
    accepted = False
    while not accepted:
        p = -1
        vp = eps
        for i in range(n):
            if state[i] == 0:
                vi = max(lo[i] - T[i], T[i] - hi[i])
                if vi > vp:
                    p = i
                    vp = vi
        if p < 0:
            break  # every limit holds: optimal
        sp = 1 if T[p] < lo[p] else -1
        u_p = 0.0
        while True:
            it += 1
            if it > max_it:
                T[:] = np.nan
                return 0
            viol = lo[p] - T[p] if sp > 0 else T[p] - hi[p]  # of the limit being added
            # c = (A_F^T A_F)^-1 a_p, F the free set (p included)
            gram_free(A, state, M[0], G)
            det = cholesky(G, L)
            if not det > 0.0:
                T[:] = np.nan
                return 0
            for a in range(k):
                c[a] = A[p, a]
            cholesky_solve(L, c)
            zz = 1.0  # z^T n_p = |z|^2 = 1 - a_p^T c
            for a in range(k):
                zz -= A[p, a] * c[a]
            # the normals stay independent iff A_F without p's row keeps rank k:
            # det(G - a_p a_p^T) = det(G) zz above the rank test (1e-12 relative)
            n_free = 0
            for i in range(n):
                if state[i] == 0:
                    n_free += 1
            scale = 0.0
            for a in range(k):
                scale = max(scale, G[a, a] - A[p, a] * A[p, a])
            dependent = n_free <= k or not (zz > 0.0 and det * zz > 1e-12 * int_power(scale, k))
            # z on the free cables, r on the active ones; the first multiplier to reach 0
            t1 = np.inf
            drop = -1
            for i in range(n):
                acc = 0.0
                for a in range(k):
                    acc += A[i, a] * c[a]
                if state[i] == 0:
                    zr[i] = sp * ((1.0 if i == p else 0.0) - acc)
                else:
                    zr[i] = -state[i] * sp * acc
                    if zr[i] > 0.0:
                        ratio = max(u[i], 0.0) / zr[i]
                        if ratio < t1:
                            t1 = ratio
                            drop = i
            if dependent:
                # only dropping an active limit can help
                if drop < 0:
                    if viol <= tol:
                        accepted = True  # broken by less than the tolerance: accept
                        break
                    T[:] = np.nan
                    return 0  # no T within limits satisfies A^T T = b
                for i in range(n):
                    if state[i] != 0:
                        u[i] -= t1 * zr[i]
                u_p += t1
                state[drop] = 0
                u[drop] = 0.0
                continue
            t2 = max(viol, 0.0) / zz
            full = t2 <= t1
            t = t2 if full else t1
            for i in range(n):
                if state[i] == 0:
                    T[i] += t * zr[i]
                else:
                    u[i] -= t * zr[i]
            u_p += t
            if full:
                state[p] = sp
                u[p] = u_p
                T[p] = lo[p] if sp > 0 else hi[p]
                break
            state[drop] = 0
            u[drop] = 0.0
    # the optimum, re-solved exactly on its active set (and checked: never out of range)
    if not (_solve_active(A, b, target, limits, state, 0.0, M, y, T) and _within(T, limits)
            and _residual_ok(A, b, T)):
        T[:] = np.nan
        return 0
    return 1


@njit(cache=_cache)
def _residual_ok(A, b, T):
    """A^T T = b to 1e-9 of the largest term."""
    n, k = A.shape
    for a in range(k):
        acc = -b[a]
        size = abs(b[a])
        for i in range(n):
            acc += A[i, a] * T[i]
            size = max(size, abs(A[i, a] * T[i]))
        if not abs(acc) <= 1e-9 * max(size, 1.0):
            return False
    return True


@njit(cache=_cache)
def improved_closed_form(A, b, mid, limits, rcond, T, M, y, state):
    """Pott's improved closed form at one step, written to T; True if within limits.

    mid (n,): E = (lo + hi) / 2; limits: a :class:`Limits`. The closed form T = E + A_F (A_F^T A_F)^-1
    (b - A^T T_fixed - A_F^T E_F) on the free cables; while a free tension breaks a limit
    by more than tol, the worst one (the first on a tie) is held at that limit, at most
    n - k times. False (T NaN) if a subproblem is singular (the rank test of
    :func:`_solve_active` with rcond) or limits are still broken. Work arrays M (3, k, k),
    y (k,), state (n,) as in :func:`least_distance`.
    """
    n, k = A.shape
    lo, hi, tol = limits.lo, limits.hi, limits.tol
    gram(A, M[0])
    for i in range(n):
        state[i] = 0
    for _ in range(n - k + 1):
        if not _solve_active(A, b, mid, limits, state, rcond, M, y, T):
            break
        j = -1
        worst = 0.0
        for i in range(n):
            if state[i] == 0:
                vi = max(lo[i] - T[i], T[i] - hi[i])
                if vi > worst:
                    worst = vi
                    j = i
        if worst <= tol:
            return True
        state[j] = 1 if T[j] < lo[j] else -1
    T[:] = np.nan
    return False


# Over a time series the common case is the full set of cables (pseudo-inverse, the
# unconstrained optimum): tension_series runs it on blocks of steps with the step innermost
# (linalg's block_gram_factor, block_cholesky_solve and block_full_rank), so that the Gram
# matrices, their Cholesky factors and the solves vectorise across steps. Steps that need
# more (a broken limit, a borderline rank test) go to the per-step solvers.
_BLOCK = 128


@njit(cache=_cache)
def _step_matrix(Jt, wt, s, A, b):
    """Step s of a time-last series as A (n, k), b (k,)."""
    k, n = Jt.shape[0], Jt.shape[1]
    for a in range(k):
        b[a] = wt[a, s]
        for i in range(n):
            A[i, a] = Jt[a, i, s]


@njit(cache=_cache)
def tension_series(Jt, wt, target, limits, ok, method, Tt, feasible):
    """Every tension method over a time series: :func:`solve_tensions` at every step.

    Jt (k, n, n_steps) and wt (k, n_steps): J~_c and w_c, time last; method: a
    :data:`METHOD_CODES` value; target (n,): the closed forms' and exact methods' target (0
    for the pseudo-inverse and minimum norm, E for the others); limits: a :class:`Limits`
    with lo, hi (n, 1) the tension limits of every step, or (n, n_steps) each step's own;
    ok (n_steps,): steps to solve (the others are infeasible). Writes Tt (n, n_steps),
    NaN where infeasible, and feasible (n_steps,).

    The common case, the closed form on every cable within limits, runs on blocks of steps
    with the step innermost (Gram matrices, Cholesky factors and solves vectorise across
    steps) in the per-step solvers' own order of operations, so every step's tensions and
    rank test are those :func:`solve_tensions` gives (the tests check it bit for bit).
    Where the closed form breaks a limit, the step goes on as there: the active-set method
    (:func:`_active_set`) from this optimum, or :func:`improved_closed_form`.
    """
    k, n, n_steps = Jt.shape
    lo, hi, tol = limits.lo, limits.hi, limits.tol
    G = np.empty((k, k, _BLOCK))
    Lb = np.empty((k, k, _BLOCK))
    det, piv, tr, dmax = np.empty(_BLOCK), np.empty(_BLOCK), np.empty(_BLOCK), np.empty(_BLOCK)
    Y = np.empty((k, _BLOCK))
    Tb = np.empty((n, _BLOCK))
    A = np.empty((n, k))
    b = np.empty(k)
    T = np.empty(n)
    M = np.zeros((3, k, k))
    v = np.empty((2, k))
    wn = np.empty((2, n))
    state = np.empty(n, dtype=np.int64)
    lo_s, hi_s = np.empty(n), np.empty(n)  # this step's limits
    limits_s = Limits(lo_s, hi_s, tol)
    per_step = lo.shape[1] > 1
    for s0 in range(0, n_steps, _BLOCK):
        nb = min(_BLOCK, n_steps - s0)
        block_gram_factor(Jt, s0, nb, G, Lb, det, piv, tr, dmax)
        # the closed form T = target + A (A^T A)^-1 (b - A^T target), every cable free
        for a in range(k):
            ya = Y[a]
            wa = wt[a, s0:s0 + nb]
            for j in range(nb):
                ya[j] = wa[j]
            for i in range(n):
                ja = Jt[a, i, s0:s0 + nb]
                ti = target[i]
                for j in range(nb):
                    ya[j] -= ja[j] * ti
        block_cholesky_solve(Lb, nb, Y)
        for i in range(n):
            Ti = Tb[i]
            ti = target[i]
            for j in range(nb):
                Ti[j] = ti
            for a in range(k):
                ja = Jt[a, i, s0:s0 + nb]
                ya = Y[a]
                for j in range(nb):
                    Ti[j] += ja[j] * ya[j]
        for j in range(nb):
            s = s0 + j
            status = 0  # 0 infeasible, 1 the closed form above, 2 a per-step solution in T
            c = s if per_step else 0
            for i in range(n):
                lo_s[i] = lo[i, c]
                hi_s[i] = hi[i, c]
            if ok[s] and block_full_rank(G, j, det[j], piv[j], tr[j], dmax[j]):
                status = 1
                for i in range(n):
                    if not (Tb[i, j] >= lo_s[i] - tol and Tb[i, j] <= hi_s[i] + tol):
                        status = 0
                        break
                if status == 0 and method == 4:
                    _step_matrix(Jt, wt, s, A, b)
                    if improved_closed_form(A, b, target, limits_s, RCOND, T, M, v[0], state):
                        status = 2
                elif status == 0 and method >= 2:
                    # the active-set method from this unconstrained optimum and Gram matrix
                    _step_matrix(Jt, wt, s, A, b)
                    for p in range(k):
                        for q in range(p, k):
                            M[0, p, q] = G[p, q, j]
                            M[0, q, p] = G[p, q, j]
                    for i in range(n):
                        state[i] = 0
                        T[i] = Tb[i, j]
                    if _active_set(A, b, target, limits_s, T, M, v, wn, state) == 1:
                        status = 2
            for i in range(n):
                Tt[i, s] = Tb[i, j] if status == 1 else (T[i] if status == 2 else np.nan)
            feasible[s] = status > 0


@njit(cache=_cache)
def solve_tensions(A, b, target, limits, method, T, M, v, wn, state):
    """Tensions at one step by ``method`` (a :data:`METHOD_CODES` value), written to T (n,);
    True if within limits (else T is NaN). The one implementation of every method.

    A (n, k): J~_c; b (k,): w_c; target (n,): 0 for the pseudo-inverse and minimum norm, E
    = (lo + hi) / 2 for the others; limits: a :class:`Limits`. Work arrays M (3, k,
    k), v (2, k), wn (2, n), state (n,) int64. Every method starts from the closed form
    on every cable, T = target + A (A^T A)^-1 (b - A^T target) (eq. 18 for target 0), under
    the one rank test (:func:`gram_full_rank`, :data:`RCOND`): the pseudo-inverse and
    Pott's closed form keep it where it is within limits; the exact methods
    (minimum variance, eq. 20, and minimum norm) go on to the exact QP from it
    (:func:`least_distance`), for any redundancy; the improved closed form holds the worst
    tension at its limit and repeats (:func:`improved_closed_form`).
    """
    if method == 4:
        return improved_closed_form(A, b, target, limits, RCOND, T, M, v[0], state)
    if method >= 2:
        return least_distance(A, b, target, limits, RCOND, T, M, v, wn, state) == 1
    gram(A, M[0])
    for i in range(A.shape[0]):
        state[i] = 0
    if _solve_active(A, b, target, limits, state, RCOND, M, v[0], T) and _within(T, limits):
        return True
    T[:] = np.nan
    return False


class TensionWork(NamedTuple):
    """Working memory of :func:`tensions_step` for n cables and k controlled DOFs, allocated
    once (:func:`tension_work`) so that a loop solves every step without allocating."""

    A: np.ndarray  # (n, k) J~'s controlled columns
    wc: np.ndarray  # (k,) the controlled wrench
    mid: np.ndarray  # (n,) the middle of the tension range
    zero: np.ndarray  # (n,) zeros: the pseudo-inverse's and minimum norm's target
    M: np.ndarray  # (3, k, k) the solvers' matrices
    v: np.ndarray  # (2, k)
    wn: np.ndarray  # (2, n)
    state: np.ndarray  # (n,) int64 active set


def tension_work(n: int, k: int) -> TensionWork:
    """A :class:`TensionWork` for n cables and k controlled DOFs."""
    return TensionWork(A=np.empty((n, k)), wc=np.empty(k), mid=np.empty(n), zero=np.zeros(n),
                       M=np.zeros((3, k, k)), v=np.empty((2, k)), wn=np.empty((2, n)),
                       state=np.empty(n, dtype=np.int64))


@njit(cache=_cache)
def tensions_step(J, w, controlled, lo, hi, method, T, work):
    """Tensions at one step, written to T (n,); returns True if within limits.

    J: J~ (n, 6); w: required wrench (6,); controlled: int indices (k,); method: a
    METHOD_CODES value; work: a :class:`TensionWork` for (n, k), overwritten. Every method,
    for any redundancy, by :func:`solve_tensions` (what planning runs over a series); no
    allocation. Returns False (and NaN tensions) where infeasible or singular.
    """
    n = J.shape[0]
    k = controlled.shape[0]
    A, wc, mid = work.A, work.wc, work.mid
    for a in range(k):
        wc[a] = w[controlled[a]]
        for i in range(n):
            A[i, a] = J[i, controlled[a]]
    top = 1.0
    for i in range(n):
        mid[i] = 0.5 * (lo[i] + hi[i])
        top = max(top, abs(hi[i]))
    tol = 1e-9 * top
    target = work.zero if (method == 0 or method == 3) else mid
    return solve_tensions(A, wc, target, Limits(lo, hi, tol), method, T, work.M, work.v, work.wn, work.state)


@njit(cache=_cache)
def headroom_one_series(N, T_s, lo, hi, out):
    """The largest headroom tensions T = T_s + N lambda (lambda scalar: one degree of
    redundancy) can keep from the limits, at every step (see
    :func:`marinecdpr.model.tension._headroom_one`). N, T_s (n_steps, n_cables), lo, hi
    (n_cables,); writes out (n_steps,)."""
    n_steps, m = N.shape
    a = np.empty(m)
    c = np.empty(m)
    top = np.empty(m)
    for s in range(n_steps):
        for i in range(m):
            mid, half = 0.5 * (lo[i] + hi[i]), 0.5 * (hi[i] - lo[i])
            a[i] = abs(N[s, i])
            if a[i] == 0.0:
                c[i], top[i] = 0.0, half - abs(T_s[s, i] - mid)
            else:
                c[i], top[i] = (mid - T_s[s, i]) / N[s, i], half
        best = -np.inf
        for i in range(m):
            for j in range(-1, m):  # j = -1: cable i's apex; else where i's falling side meets j's rising one
                if j < 0:
                    lam = c[i]
                elif a[i] + a[j] > 0.0:
                    lam = (top[i] - top[j] + a[i] * c[i] + a[j] * c[j]) / (a[i] + a[j])
                else:
                    continue
                h = np.inf
                for q in range(m):
                    h = min(h, top[q] - a[q] * abs(lam - c[q]))
                best = max(best, h)
        out[s] = best
