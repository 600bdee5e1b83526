"""Dense linear algebra on small matrices, compiled: what the rigid body's forward dynamics
and the tension solver solve with, written out (no LAPACK call, no allocation) because the
systems are k x k with k <= 6 and a LAPACK call costs more than the arithmetic.

- :func:`lu_det_solve`    A x = b and det A by Gaussian elimination (forward dynamics);
- :func:`gram`, :func:`gram_free`  A^T A of every row, or of the rows not held;
- :func:`cholesky`, :func:`cholesky_solve`  G = L L^T and (L L^T)^-1 x;
- :func:`gram_full_rank`  the one rank test of every tension method (:data:`RCOND`), from
  bounds on the Gram matrix's eigenvalue ratio (:func:`rank_bounds`) and its eigenvalues
  where they do not decide (:func:`eigen_ratio_above`);
- :func:`block_gram_factor`, :func:`block_cholesky_solve`, :func:`block_full_rank`  the same
  over a block of time steps, the step innermost (the Gram matrices, their factors and the
  solves vectorise across steps), with the same decisions from the same numbers.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["lu_det_solve", "gram", "gram_free", "cholesky", "cholesky_solve", "int_power", "RCOND", "rank_bounds",
           "eigen_ratio_above", "gram_full_rank", "block_gram_factor", "block_cholesky_solve", "block_full_rank"]

_cache = True


@njit(cache=_cache)
def lu_det_solve(A, b):
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
def gram(A, Gf):
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
def gram_free(A, state, Gf, G):
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
def cholesky(G, L):
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
def int_power(x, k):
    """x^k for a small integer k >= 1 (a few multiplications, not a call to pow)."""
    out = x
    for _ in range(k - 1):
        out *= x
    return out


@njit(cache=_cache)
def cholesky_solve(L, x):
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


RCOND = 1e-12
"""The rank test's bound: J~ (or the free cables' A_F) has full column rank where the
eigenvalues of its Gram matrix G = A^T A have lambda_min / lambda_max > RCOND."""


@njit(cache=_cache)
def rank_bounds(det, piv, tr, dmax, k, rcond):
    """The rank test from bounds on lambda_min / lambda_max of a k x k Gram matrix G:
    1 (above rcond), 0 (not), -1 (the bounds do not decide). det: det G (the product of
    the Cholesky pivots), piv: the smallest pivot, tr: trace G, dmax: the largest G_aa.
    lambda_min / lambda_max >= det / lambda_max^k >= det / tr^k, and every pivot is at
    least lambda_min while lambda_max >= dmax."""
    if not piv > 0.0:
        return 0  # a pivot <= 0 (or NaN): lambda_min is at rounding level
    if det > rcond * int_power(tr, k):
        return 1
    if piv <= rcond * dmax:
        return 0
    return -1


@njit(cache=_cache)
def eigen_ratio_above(G, rcond):
    """lambda_min / lambda_max > rcond for a symmetric G (k, k), from its eigenvalues."""
    eig = np.linalg.eigvalsh(G)
    return eig[0] > rcond * max(eig[G.shape[0] - 1], 2.2250738585072014e-308)


@njit(cache=_cache)
def gram_full_rank(G, L, det, rcond):
    """The rank test of every tension method, per step and over a series: is
    lambda_min / lambda_max of the Gram matrix G (k, k) above rcond (:data:`RCOND`)?

    L and det are :func:`cholesky`'s factor and determinant of G; the pivots are
    recomputed in the factor's own order (the same bits), the bounds of
    :func:`rank_bounds` decide almost every case and the eigenvalues the rest. rcond 0
    asks only that every pivot be positive.
    """
    k = G.shape[0]
    piv, tr, dmax = np.inf, 0.0, 0.0
    for j in range(k):
        d = G[j, j]
        tr += d
        dmax = max(dmax, d)
        for c in range(j):
            d -= L[j, c] * L[j, c]
        piv = min(piv, d)
        if not d > 0.0:
            break  # cholesky stopped here
    decision = rank_bounds(det, piv, tr, dmax, k, rcond)
    if decision >= 0:
        return decision == 1
    return eigen_ratio_above(G, rcond)


@njit(cache=_cache)
def block_gram_factor(Jt, s0, nb, G, L, det, piv, tr, dmax):
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
def block_cholesky_solve(L, nb, Y):
    """Y (k, B) <- G^-1 Y per step, G = L L^T from :func:`block_gram_factor`."""
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
def block_full_rank(G, j, det, piv, tr, dmax):
    """:func:`gram_full_rank` for step j of a block (:func:`block_gram_factor`'s G, det, piv,
    tr, dmax): the same decision from the same numbers."""
    k = G.shape[0]
    decision = rank_bounds(det, piv, tr, dmax, k, RCOND)
    if decision >= 0:
        return decision == 1
    Gs = np.empty((k, k))
    for p in range(k):
        for q in range(p, k):
            Gs[p, q] = G[p, q, j]
            Gs[q, p] = G[p, q, j]
    return eigen_ratio_above(Gs, RCOND)
