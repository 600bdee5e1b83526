"""The tension methods in numpy: the slow, obvious reference for the compiled solvers.

This is :func:`marinecdpr.model.tension.distribute_tensions` as it was before every
method was written once, compiled (:func:`marinecdpr.model.kernels.solve_tensions`):
numpy over whole time series, the paper's formulas as written. T_s = J~ (J~^T J~)^-1 w
(eq. 18) by the adjugate, the null vector of J~^T by the signed minors (r = 1, eq. 19),
the minimum-variance lambda clipped to MODEL_NOTES' corrected bounds of eq. (20), and
Pott's closed form. For redundancy r > 1 and the improved closed form the tests check the
compiled solvers against quadprog, brute force and a transcription
(``test_compiled_qp.py``); here they are not implemented. The rank test is the one the
package states: the eigenvalues of J~^T J~ with lambda_min / lambda_max > 1e-12, by
numpy's ``eigvalsh``.
"""

from __future__ import annotations

import numpy as np

from marinecdpr.model.tension import TENSION_TOLERANCE, TensionSolution

__all__ = ["reference_full_rank", "reference_pseudo_inverse", "reference_distribute_tensions"]


def reference_full_rank(J: np.ndarray) -> np.ndarray:
    """(n_steps,) bool: lambda_min / lambda_max of J~^T J~ above 1e-12 (J: (n_steps, m, k))."""
    J = np.asarray(J, dtype=float)
    finite = np.isfinite(J).all(axis=(1, 2))
    G = np.einsum("nia,nib->nab", np.where(finite[:, None, None], J, 0.0), np.where(finite[:, None, None], J, 0.0))
    eig = np.linalg.eigvalsh(G)
    return finite & (eig[:, 0] > 1e-12 * np.maximum(eig[:, -1], np.finfo(float).tiny))


def reference_pseudo_inverse(J: np.ndarray, w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """T_s (n_steps, m), NaN where J~ loses rank, and the rank test (n_steps,)."""
    J = np.asarray(J, dtype=float)
    ok = reference_full_rank(J)
    G = np.einsum("nia,nib->nab", J, J)
    G[~ok] = np.eye(J.shape[2])
    x = np.linalg.solve(G, np.asarray(w, dtype=float)[..., None])[..., 0]
    T = np.einsum("nia,na->ni", J, x)
    T[~ok] = np.nan
    return T, ok


def _null_vector(J: np.ndarray) -> np.ndarray:
    """Unit null vector of J~^T for r = 1 by the signed k x k minors, (n_steps, m)."""
    n, m, k = J.shape
    N = np.stack([(-1) ** j * np.linalg.det(np.delete(J, j, axis=1)) for j in range(m)], axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        return N / np.linalg.norm(N, axis=1, keepdims=True)


def _within(T: np.ndarray, lo: np.ndarray, hi: np.ndarray, tol: float) -> np.ndarray:
    with np.errstate(invalid="ignore"):
        return np.all((T >= lo - tol) & (T <= hi + tol), axis=1)


def reference_distribute_tensions(J: np.ndarray, w: np.ndarray, t_min: np.ndarray, t_max: np.ndarray, *,
                                  method: str = "minimum_variance") -> TensionSolution:
    """The package's :func:`~marinecdpr.model.tension.distribute_tensions` for
    ``pseudo_inverse``, ``closed_form`` (any redundancy) and ``minimum_variance``,
    ``minimum_norm`` (redundancy 0 or 1), in numpy."""
    J = np.asarray(J, dtype=float)
    w = np.asarray(w, dtype=float)
    n, m, k = J.shape
    lo = np.broadcast_to(np.asarray(t_min, dtype=float), (m,))
    hi = np.broadcast_to(np.asarray(t_max, dtype=float), (m,))
    mid = 0.5 * (lo + hi)
    tol = TENSION_TOLERANCE * max(1.0, float(np.max(np.abs(hi))))
    T_s, ok = reference_pseudo_inverse(J, w)
    if method == "pseudo_inverse":
        T = T_s
    elif method == "closed_form":
        T = mid + reference_pseudo_inverse(J, w - np.einsum("nia,i->na", J, mid))[0]   # Pott's closed form
    elif method in ("minimum_variance", "minimum_norm") and m - k <= 1:
        target = mid if method == "minimum_variance" else np.zeros(m)
        if m == k:
            T = T_s
        else:
            N = _null_vector(J)
            lam = np.einsum("ni,ni->n", N, target - T_s)          # the unconstrained optimum (N^T N = 1)
            with np.errstate(invalid="ignore", divide="ignore"):
                a, b = (lo - T_s) / N, (hi - T_s) / N            # MODEL_NOTES' corrected bounds of eq. (20)
                moves = np.abs(N) > 1e-12
                low = np.where(moves, np.minimum(a, b), -np.inf).max(axis=1)
                high = np.where(moves, np.maximum(a, b), np.inf).min(axis=1)
            ok = ok & (low <= high) & np.all(moves | ((T_s >= lo) & (T_s <= hi)), axis=1)
            T = T_s + np.clip(lam, low, high)[:, None] * N
    else:
        raise NotImplementedError(f"{method} with redundancy {m - k} has no numpy reference here")
    feasible = ok & _within(T, lo, hi, tol)
    T = np.where(feasible[:, None], T, np.nan)
    return TensionSolution(T, feasible)
