"""Compiled per-step kernels: the model at one instant, for controllers and plants.

Planning works on whole time series (:mod:`~marinecdpr.dynamics`, vectorised).
A controller in the loop and a plant integrator go step by step, where numpy's
per-call cost would dominate; these numba-compiled functions compute the same
equations for one step on small arrays (tests check them against the
vectorised functions). Frames and conventions are those of
:mod:`~marinecdpr.dynamics`; every vector here is in C unless named otherwise.

Methods available per step: ``pseudo_inverse``, ``closed_form`` and, for
redundancy 1, ``minimum_variance`` and ``minimum_norm`` (exact). Other cases
return ``ok = False`` from :func:`tensions_step` and the caller falls back to
:func:`marinecdpr.tension.distribute_tensions`.
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


@njit(cache=_cache)
def tensions_step(J, w, controlled, lo, hi, method, T):
    """Tensions at one step, written to T (n,); returns True if within limits.

    J: J~ (n, 6); w: required wrench (6,); controlled: int indices (k,); method: a
    METHOD_CODES value. Returns False (and NaN tensions) where infeasible, singular, or
    the method is not available per step (redundancy above 1 for the exact methods,
    improved closed form).
    """
    n = J.shape[0]
    k = controlled.shape[0]
    A = np.empty((n, k))
    wc = np.empty(k)
    for a in range(k):
        wc[a] = w[controlled[a]]
        for i in range(n):
            A[i, a] = J[i, controlled[a]]
    G = np.zeros((k, k))
    for a in range(k):
        for b in range(a, k):
            acc = 0.0
            for i in range(n):
                acc += A[i, a] * A[i, b]
            G[a, b] = acc
            G[b, a] = acc
    mid = 0.5 * (lo + hi)
    if method == 4 or (method >= 2 and n - k != 1):
        T[:] = np.nan
        return False
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
    tol = 1e-9 * max(1.0, np.max(np.abs(hi)))
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
