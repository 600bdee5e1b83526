"""Cable tension distribution over a whole time series (the paper's eqs. 17-20).

Every method solves, at each step, the structure equation

    J~^T T = w,     T_min <= T <= T_max,

where J~ holds the controlled columns of eq. (6) (shape (n_steps, n_cables, k))
and w the controlled part of the required wrench. With redundancy r = n - k,
every solution is T = T_s + N lambda (eqs. 17, 19), T_s = J~ (J~^T J~)^-1 w the
minimum-norm (pseudo-inverse) solution of eq. (18) and N a basis of the null
space of J~^T.

Methods (``method=``):

``pseudo_inverse``
    T_s alone (eq. 18). Feasible only where it happens to be within limits.
``minimum_variance``
    The paper's eq. (20): minimise sum_i (T_i - E_i)^2 with E_i = (T_min,i + T_max,i)/2,
    within limits. Exact: for r = 1 the convex objective's minimiser clipped to
    [lambda_low, lambda_high] (MODEL_NOTES' corrected bounds); for r > 1 the
    quadratic programme is solved exactly (an active-set QP) at the steps where the
    unconstrained optimum breaks a limit.
``closed_form``
    Pott's closed form, T = E + J~ (J~^T J~)^-1 (w - J~^T E): the unconstrained
    minimiser of the same objective; feasible only where it is within limits.
``improved_closed_form``
    Pott's improved closed form: while a tension breaks a limit, fix the worst one
    at that limit, remove it, and repeat on the remaining cables.
``minimum_norm``
    Minimise sum_i T_i^2 within limits (exact, as ``minimum_variance``).

A step where the method finds no tensions within limits is flagged infeasible and
its tensions are NaN: out-of-range tensions are never returned silently.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = [
    "TensionSolution",
    "pseudo_inverse_tensions",
    "null_space",
    "distribute_tensions",
    "TENSION_TOLERANCE",
]

TENSION_TOLERANCE = 1e-9
"""Relative tolerance (times max T_max) within which a tension counts as within limits."""

_RCOND = 1e-12


@dataclass(frozen=True)
class TensionSolution:
    """Tensions over a time series.

    Attributes
    ----------
    tensions : ndarray, shape (n_steps, n_cables)
        N; NaN at infeasible steps.
    feasible : ndarray of bool, shape (n_steps,)
    """

    tensions: np.ndarray
    feasible: np.ndarray


def _gram_solve(J: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Solve (J^T J) x = b per step.

    Parameters
    ----------
    J : ndarray, shape (n_steps, n_cables, k)
    b : ndarray, shape (n_steps, k)

    Returns
    -------
    x : ndarray, shape (n_steps, k)
        NaN where J^T J is singular.
    ok : ndarray of bool, shape (n_steps,)
        J has full column rank (reciprocal condition above 1e-12).
    """
    k = J.shape[2]
    G = np.einsum("nmi,nmj->nij", J, J)
    if k == 3:
        a, b_, c = G[:, 0, 0], G[:, 0, 1], G[:, 0, 2]
        d, e, f = G[:, 1, 1], G[:, 1, 2], G[:, 2, 2]
        A00, A01, A02 = d * f - e * e, c * e - b_ * f, b_ * e - c * d
        A11, A12, A22 = a * f - c * c, b_ * c - a * e, a * d - b_ * b_
        det = a * A00 + b_ * A01 + c * A02
        scale = ((a + d + f) / 3.0) ** 3
        with np.errstate(invalid="ignore", divide="ignore"):
            ok = np.abs(det) > _RCOND * scale
            inv_det = np.where(ok, 1.0 / np.where(ok, det, 1.0), np.nan)
        x = np.empty_like(b)
        x[:, 0] = (A00 * b[:, 0] + A01 * b[:, 1] + A02 * b[:, 2]) * inv_det
        x[:, 1] = (A01 * b[:, 0] + A11 * b[:, 1] + A12 * b[:, 2]) * inv_det
        x[:, 2] = (A02 * b[:, 0] + A12 * b[:, 1] + A22 * b[:, 2]) * inv_det
        return x, ok
    eig = np.linalg.eigvalsh(G)
    ok = eig[:, 0] > _RCOND * np.maximum(eig[:, -1], np.finfo(float).tiny)
    G = np.where(ok[:, None, None], G, np.eye(k))
    x = np.linalg.solve(G, b[..., None])[..., 0]
    x[~ok] = np.nan
    return x, ok


def pseudo_inverse_tensions(J: np.ndarray, w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Minimum-norm solution of J~^T T = w (eq. 18): T_s = J~ (J~^T J~)^-1 w.

    Parameters
    ----------
    J : ndarray, shape (n_steps, n_cables, k)
        Controlled columns of J~.
    w : ndarray, shape (n_steps, k)
        Controlled part of the required wrench (N, N m).

    Returns
    -------
    T_s : ndarray, shape (n_steps, n_cables)
        N; NaN where J~ loses rank (a singular pose).
    ok : ndarray of bool, shape (n_steps,)
        J~ has full column rank.
    """
    x, ok = _gram_solve(J, w)
    return np.einsum("nmk,nk->nm", J, x), ok


def null_space(J: np.ndarray) -> np.ndarray:
    """An orthonormal basis N of the null space of J~^T at every step (eq. 19).

    Parameters
    ----------
    J : ndarray, shape (n_steps, n_cables, k)
        With full column rank.

    Returns
    -------
    N : ndarray, shape (n_steps, n_cables, n_cables - k)
        For r = 1 the signed k x k minors of J~ (a closed form), normalised.
    """
    n, m, k = J.shape
    if m - k == 1:
        # N_j = (-1)^j det(J~ without row j): J~^T N = 0 (a determinant with a repeated row).
        rows = [np.delete(J, j, axis=1) for j in range(m)]
        if k == 3:
            dets = [np.einsum("ni,ni->n", R[:, 0], np.cross(R[:, 1], R[:, 2])) for R in rows]
        else:
            dets = [np.linalg.det(R) for R in rows]
        N = np.stack([(-1.0) ** j * d for j, d in enumerate(dets)], axis=1)
        with np.errstate(invalid="ignore", divide="ignore"):
            N /= np.linalg.norm(N, axis=1, keepdims=True)
        return N[:, :, None]
    U = np.linalg.svd(J, full_matrices=True)[0]
    return U[:, :, k:]


def _within(T: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    tol = TENSION_TOLERANCE * max(1.0, float(np.max(np.abs(hi))))
    with np.errstate(invalid="ignore"):
        return np.all((T >= lo - tol) & (T <= hi + tol), axis=1)


def _finish(T: np.ndarray, feasible: np.ndarray) -> TensionSolution:
    T = np.where(feasible[:, None], T, np.nan)
    return TensionSolution(T, feasible)


def _least_distance(
    J: np.ndarray,
    w: np.ndarray,
    target: np.ndarray,
    lo: np.ndarray,
    hi: np.ndarray,
    T_s: np.ndarray,
    ok: np.ndarray,
) -> TensionSolution:
    """Exactly minimise |T - target|^2 subject to J~^T T = w and lo <= T <= hi."""
    n, m, k = J.shape
    r = m - k
    if r == 0:
        return _finish(T_s, ok & _within(T_s, lo, hi))
    N = null_space(J)
    if r == 1:
        N1 = N[:, :, 0]
        # lambda* = N^T (target - T_s) / N^T N, with N^T N = 1
        lam = np.einsum("nm,nm->n", N1, target - T_s)
        # Corrected bounds of eq. (20) (MODEL_NOTES): a_i, b_i per cable with N_i != 0.
        tiny = 1e-12
        with np.errstate(invalid="ignore", divide="ignore"):
            nz = np.abs(N1) > tiny
            safe = np.where(nz, N1, 1.0)
            a = (lo - T_s) / safe
            b = (hi - T_s) / safe
            low = np.where(nz, np.minimum(a, b), -np.inf).max(axis=1)
            high = np.where(nz, np.maximum(a, b), np.inf).min(axis=1)
            # a cable the null space cannot change must already be within its limits
            fixed_ok = np.all(nz | ((T_s >= lo) & (T_s <= hi)), axis=1)
        lam = np.clip(lam, low, high)
        T = T_s + lam[:, None] * N1
        feasible = ok & fixed_ok & (low <= high) & _within(T, lo, hi)
        return _finish(T, feasible)
    # r > 1: the unconstrained optimum, then an exact QP where it breaks a limit.
    T = T_s + np.einsum("nmr,nr->nm", N, np.einsum("nmr,nm->nr", N, target - T_s))
    inside = ok & _within(T, lo, hi)
    feasible = inside.copy()
    for i in np.flatnonzero(ok & ~inside):
        sol = _qp_step(J[i], w[i], target, lo, hi)
        if sol is not None:
            T[i] = sol
            feasible[i] = True
    return _finish(T, feasible)


def _qp_step(J: np.ndarray, w: np.ndarray, target: np.ndarray, lo: np.ndarray, hi: np.ndarray):
    """One step's QP (Goldfarb-Idnani dual active set, quadprog); None if infeasible."""
    import quadprog

    m, k = J.shape
    C = np.hstack([J, np.eye(m), -np.eye(m)])
    bvec = np.concatenate([w, lo, -hi])
    try:
        return quadprog.solve_qp(np.eye(m), np.asarray(target, dtype=float), C, bvec, k)[0]
    except ValueError:
        return None


def _improved_closed_form(
    J: np.ndarray, w: np.ndarray, lo: np.ndarray, hi: np.ndarray, ok: np.ndarray
) -> TensionSolution:
    n, m, k = J.shape
    mid = 0.5 * (lo + hi)
    tol = TENSION_TOLERANCE * max(1.0, float(np.max(np.abs(hi))))
    free = np.ones((n, m), dtype=bool)
    T_fixed = np.zeros((n, m))
    T_out = np.full((n, m), np.nan)
    feasible = np.zeros(n, dtype=bool)
    active = ok.copy()
    steps = np.arange(n)
    for it in range(m - k + 1):
        if not active.any():
            break
        Jf = J * free[:, :, None]
        tm = np.where(free, mid, 0.0)
        rhs = w - np.einsum("nmk,nm->nk", J, T_fixed) - np.einsum("nmk,nm->nk", Jf, tm)
        x, rank_ok = _gram_solve(Jf, rhs)
        T = tm + np.einsum("nmk,nk->nm", Jf, x) + T_fixed
        with np.errstate(invalid="ignore"):
            viol = np.where(free, np.maximum(np.maximum(lo - T, T - hi), 0.0), 0.0)
        done = active & rank_ok & (viol.max(axis=1) <= tol)
        T_out[done] = T[done]
        feasible |= done
        active &= rank_ok & ~done
        worst = np.argmax(viol, axis=1)
        idx = steps[active]
        j = worst[active]
        free[idx, j] = False
        T_fixed[idx, j] = np.where(T[idx, j] < lo[j], lo[j], hi[j])
    return TensionSolution(T_out, feasible)


def distribute_tensions(
    J: np.ndarray,
    w: np.ndarray,
    t_min: np.ndarray,
    t_max: np.ndarray,
    *,
    method: str = "minimum_variance",
    T_s: np.ndarray | None = None,
    ok: np.ndarray | None = None,
) -> TensionSolution:
    """Cable tensions that produce the wrench ``w``, by ``method``.

    Parameters
    ----------
    J : ndarray, shape (n_steps, n_cables, k)
        Controlled columns of J~ (eq. 6).
    w : ndarray, shape (n_steps, k)
        Controlled part of the required wrench, in C (N, N m).
    t_min, t_max : ndarray, shape (n_cables,)
        Tension limits, N.
    method : str
        One of ``pseudo_inverse``, ``minimum_variance``, ``closed_form``,
        ``improved_closed_form``, ``minimum_norm`` (see the module docstring).
    T_s, ok : ndarray, optional
        :func:`pseudo_inverse_tensions` of ``(J, w)`` if already computed.

    Returns
    -------
    TensionSolution
        NaN tensions and ``feasible = False`` where no tensions within limits
        were found.
    """
    J = np.asarray(J, dtype=float)
    w = np.asarray(w, dtype=float)
    lo = np.asarray(t_min, dtype=float)
    hi = np.asarray(t_max, dtype=float)
    if T_s is None or ok is None:
        T_s, ok = pseudo_inverse_tensions(J, w)
    mid = 0.5 * (lo + hi)
    if method == "pseudo_inverse":
        return _finish(T_s, ok & _within(T_s, lo, hi))
    if method == "minimum_variance":
        return _least_distance(J, w, mid, lo, hi, T_s, ok)
    if method == "minimum_norm":
        return _least_distance(J, w, np.zeros_like(mid), lo, hi, T_s, ok)
    if method == "closed_form":
        x, _ = _gram_solve(J, w - np.einsum("nmk,m->nk", J, mid))
        T = mid + np.einsum("nmk,nk->nm", J, x)
        return _finish(T, ok & _within(T, lo, hi))
    if method == "improved_closed_form":
        return _improved_closed_form(J, w, lo, hi, ok)
    raise ValueError(
        f"unknown tension method {method!r} (expected pseudo_inverse, minimum_variance, "
        "closed_form, improved_closed_form or minimum_norm)"
    )
