"""Compiled per-step kernels: the model at one instant, for controllers and plants.

Planning works on whole time series (:mod:`~marinecdpr.model.dynamics`, vectorised).
A controller in the loop and a plant integrator go step by step, where numpy's
per-call cost would dominate; these numba-compiled functions compute the same
equations for one step on small arrays (tests check them against the
vectorised functions). Frames and conventions are those of
:mod:`~marinecdpr.model.dynamics`; every vector here is in C unless named otherwise.

Every tension method is available per step (:func:`tensions_step`), for any
redundancy: ``minimum_variance`` and ``minimum_norm`` exactly (a closed form for
redundancy 1, else the compiled active-set QP :func:`least_distance`), and Pott's
improved closed form (:func:`improved_closed_form`).
:func:`marinecdpr.model.tension.distribute_tensions` runs the same compiled solvers over a
time series (:func:`tension_series`): one implementation for planning and the loop.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = [
    "METHOD_CODES",
    "euler_step",
    "wrench_step",
    "cables_step",
    "tensions_step",
    "least_distance",
    "improved_closed_form",
    "tension_series",
    "gram_solve_series",
    "forward_step",
]

METHOD_CODES = {"pseudo_inverse": 0, "closed_form": 1, "minimum_variance": 2, "minimum_norm": 3,
                "improved_closed_form": 4}
_cache = True


@njit(cache=_cache)
def euler_step(ang, rate, acc, R, omega, alpha):
    """R = Rz Ry Rx and body-frame rates from Euler angles (see rotations.euler_kinematics).

    ang, rate, acc: (3,) rad, rad/s, rad/s^2. Writes R (3, 3), omega (3,), alpha (3,).
    """
    cph, sph = np.cos(ang[0]), np.sin(ang[0])
    cth, sth = np.cos(ang[1]), np.sin(ang[1])
    cps, sps = np.cos(ang[2]), np.sin(ang[2])
    R[0, 0] = cps * cth
    R[0, 1] = cps * sth * sph - sps * cph
    R[0, 2] = cps * sth * cph + sps * sph
    R[1, 0] = sps * cth
    R[1, 1] = sps * sth * sph + cps * cph
    R[1, 2] = sps * sth * cph - cps * sph
    R[2, 0] = -sth
    R[2, 1] = cth * sph
    R[2, 2] = cth * cph
    dph, dth, dps = rate[0], rate[1], rate[2]
    ddph, ddth, ddps = acc[0], acc[1], acc[2]
    omega[0] = dph - sth * dps
    omega[1] = cph * dth + sph * cth * dps
    omega[2] = -sph * dth + cph * cth * dps
    alpha[0] = ddph - sth * ddps - cth * dth * dps
    alpha[1] = (cph * ddth - sph * dph * dth + sph * cth * ddps
                + cph * cth * dph * dps - sph * sth * dth * dps)
    alpha[2] = (-sph * ddth - cph * dph * dth + cph * cth * ddps
                - sph * cth * dph * dps - cph * sth * dth * dps)


@njit(cache=_cache, inline="always")
def _cross(a, b, out):
    out[0] = a[1] * b[2] - a[2] * b[1]
    out[1] = a[2] * b[0] - a[0] * b[2]
    out[2] = a[0] * b[1] - a[1] * b[0]


@njit(cache=_cache)
def wrench_step(x, v, a, R_PC, w_pc, al_pc, R_SO, w_s, al_s, a_SO_O, origin, mass, I_PP, g,
                f_C, m_C, out):
    """Required wrench w (eq. 15) at one step: force and moment in C, written to out (6,).

    x, v, a: platform position, velocity, acceleration relative to C (3,);
    R_PC (3, 3); w_pc, al_pc: angular velocity and acceleration relative to C, in C;
    R_SO (3, 3); w_s, al_s: ship angular velocity and acceleration in S; a_SO_O: ship
    origin acceleration in O; origin: C's origin in S; I_PP (3, 3); g > 0;
    f_C, m_C: disturbance in C.
    """
    r = np.empty(3)
    for i in range(3):
        r[i] = x[i] + origin[i]
    t1 = np.empty(3)
    t2 = np.empty(3)
    t3 = np.empty(3)
    _cross(al_s, r, t1)
    _cross(w_s, r, t2)
    _cross(w_s, t2, t3)
    _cross(w_s, v, t2)
    for i in range(3):
        # R_SO^T a_SO + Euler + centripetal + Coriolis + relative (eq. 9), minus gravity in S
        a_base = R_SO[0, i] * a_SO_O[0] + R_SO[1, i] * a_SO_O[1] + R_SO[2, i] * a_SO_O[2]
        g_S = -g * R_SO[2, i]
        out[i] = mass * (a_base + t1[i] + t3[i] + 2.0 * t2[i] + a[i] - g_S) - f_C[i]
    # I_C = R_PC I_PP R_PC^T
    RI = np.empty((3, 3))
    for i in range(3):
        for k in range(3):
            RI[i, k] = R_PC[i, 0] * I_PP[0, k] + R_PC[i, 1] * I_PP[1, k] + R_PC[i, 2] * I_PP[2, k]
    I_C = np.empty((3, 3))
    for i in range(3):
        for j in range(3):
            I_C[i, j] = RI[i, 0] * R_PC[j, 0] + RI[i, 1] * R_PC[j, 1] + RI[i, 2] * R_PC[j, 2]
    W = np.empty(3)
    for i in range(3):
        W[i] = w_s[i] + w_pc[i]
    _cross(w_s, w_pc, t1)
    for i in range(3):
        t1[i] += al_s[i] + al_pc[i]  # absolute angular acceleration in S (eq. 11)
    IW = np.empty(3)
    for i in range(3):
        IW[i] = I_C[i, 0] * W[0] + I_C[i, 1] * W[1] + I_C[i, 2] * W[2]
    _cross(W, IW, t2)
    for i in range(3):
        out[3 + i] = I_C[i, 0] * t1[0] + I_C[i, 1] * t1[1] + I_C[i, 2] * t1[2] + t2[i] - m_C[i]


@njit(cache=_cache)
def cables_step(x, R_PC, c_C, p_P, lengths, J):
    """Cable lengths (n,) and J~ (n, 6) at one pose (eqs. 2, 6), written in place."""
    for i in range(c_C.shape[0]):
        r0 = R_PC[0, 0] * p_P[i, 0] + R_PC[0, 1] * p_P[i, 1] + R_PC[0, 2] * p_P[i, 2]
        r1 = R_PC[1, 0] * p_P[i, 0] + R_PC[1, 1] * p_P[i, 1] + R_PC[1, 2] * p_P[i, 2]
        r2 = R_PC[2, 0] * p_P[i, 0] + R_PC[2, 1] * p_P[i, 1] + R_PC[2, 2] * p_P[i, 2]
        l0 = c_C[i, 0] - x[0] - r0
        l1 = c_C[i, 1] - x[1] - r1
        l2 = c_C[i, 2] - x[2] - r2
        L = np.sqrt(l0 * l0 + l1 * l1 + l2 * l2)
        lengths[i] = L
        u0, u1, u2 = l0 / L, l1 / L, l2 / L
        J[i, 0] = u0
        J[i, 1] = u1
        J[i, 2] = u2
        J[i, 3] = r1 * u2 - r2 * u1
        J[i, 4] = r2 * u0 - r0 * u2
        J[i, 5] = r0 * u1 - r1 * u0


@njit(cache=_cache)
def _lu_det_solve(A, b):
    """Determinant of A (k, k) and, in b, the solution of A x = b (Gaussian elimination with
    partial pivoting; A and b are overwritten). For the small systems here it is an order of
    magnitude faster than a LAPACK call."""
    k = A.shape[0]
    det = 1.0
    for col in range(k):
        piv = col
        for r in range(col + 1, k):
            if abs(A[r, col]) > abs(A[piv, col]):
                piv = r
        if A[piv, col] == 0.0:
            return 0.0
        if piv != col:
            det = -det
            for c in range(k):
                A[col, c], A[piv, c] = A[piv, c], A[col, c]
            b[col], b[piv] = b[piv], b[col]
        det *= A[col, col]
        for r in range(col + 1, k):
            f = A[r, col] / A[col, col]
            for c in range(col, k):
                A[r, c] -= f * A[col, c]
            b[r] -= f * b[col]
    for r in range(k - 1, -1, -1):
        acc = b[r]
        for c in range(r + 1, k):
            acc -= A[r, c] * b[c]
        b[r] = acc / A[r, r]
    return det


# ----------------------------------------------------------------- exact tension QP
# The exact methods for any redundancy and Pott's improved closed form, per step, all
# compiled: one implementation for planning (tension.distribute_tensions loops over the
# steps here) and for the closed loop (tensions_step). Arrays: A = J~_c (n, k) with rows
# a_i (cables), b = w_c (k,). An active set is ``state`` (n,): 0 free, +1 held at its lower
# limit, -1 held at its upper limit (the sign of the constraint's normal, +-e_i).
# Work arrays, preallocated by the caller: M (3, k, k) holds the Gram matrix A^T A of
# every cable, that of the free ones and its Cholesky factor; v (2, k) and wn (2, n).


@njit(cache=_cache)
def _gram(A, Gf):
    """Gf = A^T A (k, k), the Gram matrix of every cable."""
    n, k = A.shape
    for a in range(k):
        for b in range(a, k):
            acc = 0.0
            for i in range(n):
                acc += A[i, a] * A[i, b]
            Gf[a, b] = acc
            Gf[b, a] = acc


@njit(cache=_cache)
def _gram_free(A, state, Gf, G):
    """G = A_F^T A_F, F the free cables: Gf less a_i a_i^T of the active ones (at most r)."""
    n, k = A.shape
    for a in range(k):
        for b in range(a, k):
            G[a, b] = Gf[a, b]
    for i in range(n):
        if state[i] != 0:
            for a in range(k):
                ai = A[i, a]
                for b in range(a, k):
                    G[a, b] -= ai * A[i, b]
    for a in range(k):
        for b in range(a + 1, k):
            G[b, a] = G[a, b]


@njit(cache=_cache)
def _cholesky(G, L):
    """G = L L^T (lower L, G left intact). Returns det G, 0.0 if a pivot is not positive."""
    k = G.shape[0]
    det = 1.0
    for j in range(k):
        d = G[j, j]
        for c in range(j):
            d -= L[j, c] * L[j, c]
        if not d > 0.0:
            return 0.0
        det *= d
        ljj = np.sqrt(d)
        L[j, j] = ljj
        for i in range(j + 1, k):
            acc = G[i, j]
            for c in range(j):
                acc -= L[i, c] * L[j, c]
            L[i, j] = acc / ljj
    return det


@njit(cache=_cache, inline="always")
def _pow(x, k):
    """x^k for a small integer k >= 1 (a few multiplications, not a call to pow)."""
    out = x
    for _ in range(k - 1):
        out *= x
    return out


@njit(cache=_cache)
def _max_diag(G):
    scale = 0.0
    for a in range(G.shape[0]):
        scale = max(scale, G[a, a])
    return scale


@njit(cache=_cache)
def _cholesky_solve(L, x):
    """x <- (L L^T)^-1 x."""
    k = L.shape[0]
    for i in range(k):
        acc = x[i]
        for c in range(i):
            acc -= L[i, c] * x[c]
        x[i] = acc / L[i, i]
    for i in range(k - 1, -1, -1):
        acc = x[i]
        for c in range(i + 1, k):
            acc -= L[c, i] * x[c]
        x[i] = acc / L[i, i]


@njit(cache=_cache)
def _solve_active(A, b, target, lo, hi, state, rcond, M, y, T):
    """The equality-constrained minimiser of |T - target|^2 with the active set held at its
    limits: T_W = limits, T_F = target_F + A_F y, (A_F^T A_F) y = b - A_W^T T_W - A_F^T target_F.
    M[0] holds A^T A. Returns False (T untouched) where A_F^T A_F is singular: a pivot not
    positive, or det <= rcond (max diagonal)^k (the per-step kernels' rank test)."""
    n, k = A.shape
    G, L = M[1], M[2]
    _gram_free(A, state, M[0], G)
    det = _cholesky(G, L)
    if not (det > 0.0 and det > rcond * _pow(_max_diag(G), k)):
        return False
    for a in range(k):
        y[a] = b[a]
    for i in range(n):
        v = target[i] if state[i] == 0 else (lo[i] if state[i] > 0 else hi[i])
        for a in range(k):
            y[a] -= A[i, a] * v
    _cholesky_solve(L, y)
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
def _within(T, lo, hi, tol):
    for i in range(T.shape[0]):
        if not (T[i] >= lo[i] - tol and T[i] <= hi[i] + tol):
            return False
    return True


@njit(cache=_cache)
def least_distance(A, b, target, lo, hi, tol, rcond, T, M, v, wn, state):
    """Exactly minimise |T - target|^2 subject to A^T T = b and lo <= T <= hi, written to T.

    A (n, k), b (k,), target, lo, hi (n,); tol: the tolerance within which a tension counts
    as within limits (TENSION_TOLERANCE x max(1, max hi)); rcond: the rank test of
    :func:`_solve_active` for A^T A (0 to flag only a breakdown). Work arrays: M (3, k, k),
    v (2, k), wn (2, n) float and state (n,) int64 (it holds the final active set).

    The unconstrained (equality-only) optimum where it is within limits, else
    :func:`_active_set`. Returns 1 (T optimal, within limits to tol), 0 (infeasible: no T
    within limits satisfies A^T T = b; T NaN) or -1 (A^T A singular; T NaN).
    """
    n = A.shape[0]
    _gram(A, M[0])
    for i in range(n):
        state[i] = 0
    if not _solve_active(A, b, target, lo, hi, state, rcond, M, v[0], T):
        T[:] = np.nan
        return -1
    if _within(T, lo, hi, tol):  # the unconstrained optimum (the usual case)
        return 1
    return _active_set(A, b, target, lo, hi, tol, T, M, v, wn, state)


@njit(cache=_cache)
def _active_set(A, b, target, lo, hi, tol, T, M, v, wn, state):
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
            _gram_free(A, state, M[0], G)
            det = _cholesky(G, L)
            if not det > 0.0:
                T[:] = np.nan
                return 0
            for a in range(k):
                c[a] = A[p, a]
            _cholesky_solve(L, c)
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
            dependent = n_free <= k or not (zz > 0.0 and det * zz > 1e-12 * _pow(scale, k))
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
    if not (_solve_active(A, b, target, lo, hi, state, 0.0, M, y, T) and _within(T, lo, hi, tol)
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
def improved_closed_form(A, b, mid, lo, hi, tol, rcond, T, M, y, state):
    """Pott's improved closed form at one step, written to T; True if within limits.

    mid (n,): E = (lo + hi) / 2. The closed form T = E + A_F (A_F^T A_F)^-1
    (b - A^T T_fixed - A_F^T E_F) on the free cables; while a free tension breaks a limit
    by more than tol, the worst one (the first on a tie) is held at that limit, at most
    n - k times. False (T NaN) if a subproblem is singular (the rank test of
    :func:`_solve_active` with rcond) or limits are still broken. Work arrays M (3, k, k),
    y (k,), state (n,) as in :func:`least_distance`.
    """
    n, k = A.shape
    _gram(A, M[0])
    for i in range(n):
        state[i] = 0
    for _ in range(n - k + 1):
        if not _solve_active(A, b, mid, lo, hi, state, rcond, M, y, T):
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
# unconstrained optimum): these run on blocks of steps with the step innermost, so that
# the Gram matrices, their Cholesky factors and the solves vectorise across steps. Steps
# that need more (a broken limit, a borderline rank test) go to the per-step solvers.
_BLOCK = 128


@njit(cache=_cache)
def _block_factor(Jt, s0, nb, G, L, det, piv, tr, dmax):
    """Gram matrices J~^T J~ of steps s0..s0+nb-1 and their Cholesky factors, step last.

    G, L (k, k, B): G's upper triangle, L lower (diagonal 1 where a pivot is not positive);
    det, piv, tr, dmax (B,): det G (product of the pivots), the smallest pivot, the trace
    and the largest diagonal entry.
    """
    k, n = Jt.shape[0], Jt.shape[1]
    for p in range(k):
        for q in range(p, k):
            g = G[p, q]
            for j in range(nb):
                g[j] = 0.0
            for i in range(n):
                jp = Jt[p, i, s0:s0 + nb]
                jq = Jt[q, i, s0:s0 + nb]
                for j in range(nb):
                    g[j] += jp[j] * jq[j]
    for j in range(nb):
        det[j] = 1.0
        piv[j] = np.inf
        tr[j] = 0.0
        dmax[j] = 0.0
    for c in range(k):
        d = L[c, c]
        gcc = G[c, c]
        for j in range(nb):
            d[j] = gcc[j]
            tr[j] += gcc[j]
            dmax[j] = max(dmax[j], gcc[j])
        for m in range(c):
            lcm = L[c, m]
            for j in range(nb):
                d[j] -= lcm[j] * lcm[j]
        for j in range(nb):
            dj = d[j]
            det[j] *= dj
            piv[j] = min(piv[j], dj)
            d[j] = np.sqrt(dj) if dj > 0.0 else 1.0
        for i in range(c + 1, k):
            lic = L[i, c]
            gci = G[c, i]
            for j in range(nb):
                lic[j] = gci[j]
            for m in range(c):
                lim = L[i, m]
                lcm = L[c, m]
                for j in range(nb):
                    lic[j] -= lim[j] * lcm[j]
            for j in range(nb):
                lic[j] /= d[j]


@njit(cache=_cache)
def _block_solve(L, nb, Y):
    """Y (k, B) <- G^-1 Y per step, G = L L^T from :func:`_block_factor`."""
    k = L.shape[0]
    for c in range(k):
        yc = Y[c]
        for m in range(c):
            lcm = L[c, m]
            ym = Y[m]
            for j in range(nb):
                yc[j] -= lcm[j] * ym[j]
        lcc = L[c, c]
        for j in range(nb):
            yc[j] /= lcc[j]
    for c in range(k - 1, -1, -1):
        yc = Y[c]
        for m in range(c + 1, k):
            lmc = L[m, c]
            ym = Y[m]
            for j in range(nb):
                yc[j] -= lmc[j] * ym[j]
        lcc = L[c, c]
        for j in range(nb):
            yc[j] /= lcc[j]


@njit(cache=_cache)
def _step_matrix(Jt, wt, s, A, b):
    """Step s of a time-last series as A (n, k), b (k,)."""
    k, n = Jt.shape[0], Jt.shape[1]
    for a in range(k):
        b[a] = wt[a, s]
        for i in range(n):
            A[i, a] = Jt[a, i, s]


@njit(cache=_cache)
def _rank_ok(G, j, det, piv, tr, dmax):
    """The planning layer's rank test of J~^T J~, eigenvalue ratio lambda_min / lambda_max >
    1e-12 (as numpy's eigvalsh decides it), for step j of a block: from bounds where they
    suffice (lambda_min / lambda_max >= det / trace^k, and <= smallest pivot / largest
    diagonal, every Cholesky pivot being at least lambda_min), the eigenvalues in between."""
    k = G.shape[0]
    if not piv > 0.0:
        return False  # a pivot <= 0: lambda_min is at rounding level
    if det > 1e-12 * _pow(tr, k):
        return True
    if piv <= 1e-12 * dmax:
        return False
    Gs = np.empty((k, k))
    for p in range(k):
        for q in range(p, k):
            Gs[p, q] = G[p, q, j]
            Gs[q, p] = G[p, q, j]
    eig = np.linalg.eigvalsh(Gs)
    return eig[0] > 1e-12 * max(eig[k - 1], 2.2250738585072014e-308)


@njit(cache=_cache)
def gram_solve_series(Jt, B, X, ok, Tt):
    """(J~^T J~) x = b at every step, for the planning layer's k != 3 (k = 3 has a closed form).

    Jt (k, n, n_steps): J~, time last; B (k, n_steps). Writes X (k, n_steps) and, unless Tt
    has no rows, Tt (n, n_steps) = J~ x (the pseudo-inverse tensions for b = w), NaN where
    J~ loses rank, and ok (n_steps,): eigenvalue ratio of J~^T J~ above 1e-12
    (:func:`_rank_ok`).
    """
    k, n, n_steps = Jt.shape
    G = np.empty((k, k, _BLOCK))
    L = np.empty((k, k, _BLOCK))
    det, piv, tr, dmax = np.empty(_BLOCK), np.empty(_BLOCK), np.empty(_BLOCK), np.empty(_BLOCK)
    Y = np.empty((k, _BLOCK))
    good = np.empty(_BLOCK, dtype=np.bool_)
    for s0 in range(0, n_steps, _BLOCK):
        nb = min(_BLOCK, n_steps - s0)
        _block_factor(Jt, s0, nb, G, L, det, piv, tr, dmax)
        for a in range(k):
            for j in range(nb):
                Y[a, j] = B[a, s0 + j]
        _block_solve(L, nb, Y)
        for j in range(nb):
            good[j] = _rank_ok(G, j, det[j], piv[j], tr[j], dmax[j])
            ok[s0 + j] = good[j]
            if not good[j]:
                for a in range(k):
                    Y[a, j] = np.nan
        for a in range(k):
            ya = Y[a]
            xa = X[a, s0:s0 + nb]
            for j in range(nb):
                xa[j] = ya[j]
        if Tt.shape[0] > 0:
            for i in range(n):
                ti = Tt[i, s0:s0 + nb]
                for j in range(nb):
                    ti[j] = 0.0
                for a in range(k):
                    ja = Jt[a, i, s0:s0 + nb]
                    ya = Y[a]
                    for j in range(nb):
                        ti[j] += ja[j] * ya[j]


@njit(cache=_cache)
def tension_series(Jt, wt, target, lo, hi, ok, method, tol, Tt, feasible):
    """The exact methods (any redundancy) or the improved closed form over a time series.

    Jt (k, n, n_steps) and wt (k, n_steps): J~_c and w_c, time last; target (n,): the
    exact methods' target (E or 0), E for the improved closed form (method 4); ok
    (n_steps,): J~_c has full rank (steps without are infeasible); tol as in
    :func:`least_distance`. Writes Tt (n, n_steps), NaN where infeasible, and feasible
    (n_steps,). Both methods start from the same closed form on every cable (blocks of
    steps); where it breaks a limit, the active-set method (:func:`_active_set`, from there)
    or :func:`improved_closed_form`.
    """
    k, n, n_steps = Jt.shape
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
    for s0 in range(0, n_steps, _BLOCK):
        nb = min(_BLOCK, n_steps - s0)
        _block_factor(Jt, s0, nb, G, Lb, det, piv, tr, dmax)
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
        _block_solve(Lb, nb, Y)
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
            if ok[s]:
                # the improved closed form's rank test on the full set is the per-step one
                if piv[j] > 0.0 and (method != 4 or det[j] > 1e-12 * _pow(dmax[j], k)):
                    status = 1
                    for i in range(n):
                        if not (Tb[i, j] >= lo[i] - tol and Tb[i, j] <= hi[i] + tol):
                            status = 0
                            break
                if status == 0 and method == 4:
                    _step_matrix(Jt, wt, s, A, b)
                    if improved_closed_form(A, b, target, lo, hi, tol, 1e-12, T, M, v[0], state):
                        status = 2
                elif status == 0 and piv[j] > 0.0:
                    # the active-set method from this unconstrained optimum and Gram matrix
                    _step_matrix(Jt, wt, s, A, b)
                    for p in range(k):
                        for q in range(p, k):
                            M[0, p, q] = G[p, q, j]
                            M[0, q, p] = G[p, q, j]
                    for i in range(n):
                        state[i] = 0
                        T[i] = Tb[i, j]
                    if _active_set(A, b, target, lo, hi, tol, T, M, v, wn, state) == 1:
                        status = 2
            for i in range(n):
                Tt[i, s] = Tb[i, j] if status == 1 else (T[i] if status == 2 else np.nan)
            feasible[s] = status > 0


@njit(cache=_cache)
def tensions_step(J, w, controlled, lo, hi, method, T):
    """Tensions at one step, written to T (n,); returns True if within limits.

    J: J~ (n, 6); w: required wrench (6,); controlled: int indices (k,); method: a
    METHOD_CODES value. Every method, for any redundancy. Returns False (and NaN tensions)
    where infeasible or singular.
    """
    n = J.shape[0]
    k = controlled.shape[0]
    A = np.empty((n, k))
    wc = np.empty(k)
    for a in range(k):
        wc[a] = w[controlled[a]]
        for i in range(n):
            A[i, a] = J[i, controlled[a]]
    mid = 0.5 * (lo + hi)
    tol = 1e-9 * max(1.0, np.max(np.abs(hi)))
    if method == 4 or (method >= 2 and n - k != 1):
        # the improved closed form, or an exact method with redundancy other than 1: the
        # compiled active-set solvers (rank test as below, det G <= 1e-12 (max G_aa)^k)
        M = np.zeros((3, k, k))
        v = np.empty((2, k))
        state = np.empty(n, dtype=np.int64)
        if method == 4:
            return improved_closed_form(A, wc, mid, lo, hi, tol, 1e-12, T, M, v[0], state)
        target = mid if method == 2 else np.zeros(n)
        return least_distance(A, wc, target, lo, hi, tol, 1e-12, T, M, v, np.empty((2, n)), state) == 1
    G = np.empty((k, k))
    _gram(A, G)
    scale = 0.0
    for a in range(k):
        scale = max(scale, G[a, a])
    x = wc
    if method == 1:
        for a in range(k):
            for i in range(n):
                x[a] -= A[i, a] * mid[i]
    if abs(_lu_det_solve(G, x)) <= 1e-12 * scale**k:
        T[:] = np.nan
        return False
    Ts = np.empty(n)
    for i in range(n):
        acc = mid[i] if method == 1 else 0.0
        for a in range(k):
            acc += A[i, a] * x[a]
        Ts[i] = acc
    if method >= 2:
        # null vector of A^T from the signed k x k minors (r = 1), then clip lambda (eq. 20)
        N = np.empty(n)
        sub = np.empty((k, k))
        rhs = np.zeros(k)
        for j in range(n):
            row = 0
            for i in range(n):
                if i != j:
                    sub[row, :] = A[i, :]
                    row += 1
            N[j] = _lu_det_solve(sub, rhs) * (1.0 if j % 2 == 0 else -1.0)
        N /= np.sqrt(np.sum(N * N))
        lam = 0.0
        for i in range(n):
            lam += N[i] * ((mid[i] if method == 2 else 0.0) - Ts[i])
        low, high = -np.inf, np.inf
        for i in range(n):
            if abs(N[i]) > 1e-12:
                a_i = (lo[i] - Ts[i]) / N[i]
                b_i = (hi[i] - Ts[i]) / N[i]
                low = max(low, min(a_i, b_i))
                high = min(high, max(a_i, b_i))
            elif Ts[i] < lo[i] or Ts[i] > hi[i]:
                T[:] = np.nan
                return False
        if low > high:
            T[:] = np.nan
            return False
        lam = min(max(lam, low), high)
        Ts += lam * N
    for i in range(n):
        if not (Ts[i] >= lo[i] - tol and Ts[i] <= hi[i] + tol):
            T[:] = np.nan
            return False
    T[:] = Ts
    return True


@njit(cache=_cache)
def forward_step(J, T, bias, R_PC, mass, I_PP, controlled, out):
    """Relative acceleration (a_PC, alpha_PC) in C from tensions (forward dynamics).

    Solves M_cc acc_c = (J~^T T - bias)_c; uncontrolled components are zero.
    J (n, 6), T (n,), bias (6,) = required wrench at zero relative acceleration.
    """
    M = np.zeros((6, 6))
    for i in range(3):
        M[i, i] = mass
        for j in range(3):
            acc = 0.0
            for a in range(3):
                for b in range(3):
                    acc += R_PC[i, a] * I_PP[a, b] * R_PC[j, b]
            M[3 + i, 3 + j] = acc
    f = -bias.copy()
    for a in range(6):
        for i in range(J.shape[0]):
            f[a] += J[i, a] * T[i]
    k = controlled.shape[0]
    Mc = np.empty((k, k))
    fc = np.empty(k)
    for a in range(k):
        fc[a] = f[controlled[a]]
        for b in range(k):
            Mc[a, b] = M[controlled[a], controlled[b]]
    _lu_det_solve(Mc, fc)
    out[:] = 0.0
    for a in range(k):
        out[controlled[a]] = fc[a]
