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
    within limits, exactly, for any redundancy: the unconstrained optimum, and where it
    breaks a limit the quadratic programme solved by a compiled dual active-set method
    (:func:`marinecdpr.model.tension_solver.least_distance`). For r = 1 this is the convex
    objective's minimiser clipped to [lambda_low, lambda_high] (MODEL_NOTES' corrected
    bounds), which ``tests/tension_reference.py`` computes so as the check.
``closed_form``
    Pott's closed form, T = E + J~ (J~^T J~)^-1 (w - J~^T E): the unconstrained
    minimiser of the same objective; feasible only where it is within limits.
``improved_closed_form``
    Pott's improved closed form: while a tension breaks a limit, fix the worst one
    at that limit, remove it, and repeat on the remaining cables (compiled,
    :func:`marinecdpr.model.tension_solver.improved_closed_form`).
``minimum_norm``
    Minimise sum_i T_i^2 within limits (exact, as ``minimum_variance``).

A step where the method finds no tensions within limits is flagged infeasible and
its tensions are NaN: out-of-range tensions are never returned silently. The exact
methods (``minimum_variance``, ``minimum_norm``) are exact in exact arithmetic; where the
compiled active-set method gives up at a step that has tensions within limits (near a
singular pose its rank tests can call independent limits dependent), the same problem is
solved again at that step only, in the null space of J~^T as a least-distance programme
(:func:`exact_fallback`), and its tensions kept if they pass the same checks.

Every method is written once, compiled (:func:`marinecdpr.model.tension_solver.solve_tensions`),
with one rank test (:func:`full_rank`): this module runs it over time series, the closed
loop at every step (:func:`marinecdpr.model.tension_solver.tensions_step`), so a plan and the loop
give the same tensions, bit for bit, at the same J~ and wrench, and agree on which poses
are singular.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from marinecdpr.geometry import vec

__all__ = [
    "TensionSolution",
    "pseudo_inverse_tensions",
    "full_rank",
    "null_space",
    "distribute_tensions",
    "largest_headroom",
    "WrenchFaces",
    "wrench_faces",
    "exact_fallback",
    "EXACT_METHODS",
    "TENSION_TOLERANCE",
]

TENSION_TOLERANCE = 1e-9
"""Relative tolerance (times max T_max) within which a tension counts as within limits."""



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


def _time_last(J: np.ndarray) -> np.ndarray:
    """J~ (n_steps, n_cables, k) as a C-contiguous (k, n_cables, n_steps) array: a view of a
    time-last J~ (planning's layout), else one copy."""
    Jt = J.transpose(2, 1, 0)
    return Jt if Jt.flags.c_contiguous else np.ascontiguousarray(Jt)


def _cols(Jt: np.ndarray) -> list[list[np.ndarray]]:
    """J~ entries as ``cols[i][a]``: cable i, DOF a, each of shape (n_steps,), contiguous.

    ``Jt`` is :func:`_time_last` of J~."""
    return [[Jt[a, i] for a in range(Jt.shape[0])] for i in range(Jt.shape[1])]


def _stack(T: list, n: int) -> np.ndarray:
    """A list over cables of (n_steps,) arrays as an (n_steps, n_cables) view."""
    out = np.empty((len(T), n))
    for i, Ti in enumerate(T):
        out[i] = Ti
    return out.T


def _series(J: np.ndarray, w: np.ndarray, method: int, target: np.ndarray, lo: np.ndarray, hi: np.ndarray,
            ok: np.ndarray | None, tol: float) -> TensionSolution:
    """The compiled solver of every method over the steps
    (:func:`marinecdpr.model.tension_solver.tension_series`, the code the closed loop runs per step).
    ``lo``, ``hi``: (m,), or (m, n_steps) each step's own."""
    from marinecdpr.model import tension_solver

    n, m, k = J.shape
    Jt = _time_last(J)
    wt = w.T if w.T.flags.c_contiguous else np.ascontiguousarray(w.T)
    T = np.empty((m, n))
    feasible = np.empty(n, dtype=bool)
    if ok is None:
        ok = np.ones(n, dtype=bool)

    def columns(a: np.ndarray) -> np.ndarray:  # (m, 1) or (m, n_steps), as the kernel takes them
        return np.ascontiguousarray(a.reshape(m, -1), dtype=float)

    limits = tension_solver.Limits(columns(lo), columns(hi), float(tol))
    tension_solver.tension_series(Jt, np.asarray(wt, dtype=float), np.ascontiguousarray(target, dtype=float), limits,
                                  np.ascontiguousarray(ok, dtype=bool), method, T, feasible)
    return TensionSolution(T.T, feasible)


def pseudo_inverse_tensions(J: np.ndarray, w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Minimum-norm solution of J~^T T = w (eq. 18): T_s = J~ (J~^T J~)^-1 w, whatever the limits.

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
        J~ has full column rank (:func:`full_rank`).
    """
    J = np.asarray(J, dtype=float)
    m = J.shape[1]
    unlimited = np.full(m, np.inf)
    sol = _series(J, np.asarray(w, dtype=float), 0, np.zeros(m), -unlimited, unlimited, None, 0.0)
    return sol.tensions, sol.feasible


def full_rank(J: np.ndarray) -> np.ndarray:
    """Where J~ has full column rank: the one rank test of every tension method, in the
    plan and in the closed loop (:func:`marinecdpr.model.linalg.gram_full_rank`: the
    eigenvalues of J~^T J~ with lambda_min / lambda_max > 1e-12). False at a singular pose.

    Parameters
    ----------
    J : ndarray, shape (n_steps, n_cables, k)
        Controlled columns of J~.

    Returns
    -------
    ok : ndarray of bool, shape (n_steps,)
    """
    J = np.asarray(J, dtype=float)
    return pseudo_inverse_tensions(J, np.zeros((J.shape[0], J.shape[2])))[1]


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
        N = _stack(_null_vector(_cols(_time_last(np.asarray(J, dtype=float))), n), n)
        return N[:, :, None]
    U = np.linalg.svd(np.asarray(J), full_matrices=True)[0]
    return U[:, :, k:]


def _null_vector(cols: list, n: int) -> list:
    """Unit null vector of J~^T for r = 1, as a list over cables.

    N_j = (-1)^j det(J~ without row j): J~^T N = 0 since each entry of J~^T N is
    the determinant of a matrix with a repeated row.
    """
    m, k = len(cols), len(cols[0])
    if k == 3:
        # the four 3x3 minors of a 4x3 matrix share two cross products
        r0, r1, r2, r3 = cols
        c23, c01 = vec.cross(r2, r3), vec.cross(r0, r1)
        N = [vec.dot(r1, c23), -vec.dot(r0, c23), vec.dot(c01, r3), -vec.dot(c01, r2)]
    else:
        dets = [np.linalg.det(np.stack([np.stack(r, axis=-1) for r in cols[:j] + cols[j + 1:]], axis=1))
                for j in range(m)]
        N = [d if j % 2 == 0 else -d for j, d in enumerate(dets)]
    with np.errstate(invalid="ignore", divide="ignore"):
        inv = 1.0 / np.sqrt(sum(Nj * Nj for Nj in N))
        return [Nj * inv for Nj in N]


_METHODS = ("pseudo_inverse", "closed_form", "minimum_variance", "minimum_norm", "improved_closed_form")
"""The methods by their code in :data:`marinecdpr.model.tension_solver.METHOD_CODES`."""


def distribute_tensions(
    J: np.ndarray,
    w: np.ndarray,
    t_min: np.ndarray,
    t_max: np.ndarray,
    *,
    method: str = "minimum_variance",
    ok: np.ndarray | None = None,
    lower: np.ndarray | None = None,
    upper: np.ndarray | None = None,
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
    ok : ndarray of bool, shape (n_steps,), optional
        Steps to solve (the others are infeasible), e.g. :func:`full_rank` of J if already
        computed; every step is tested for rank in any case.
    lower, upper : ndarray, shape (n_steps, n_cables), optional
        Each step's own tension bounds, N, within which the tensions must also lie (e.g.
        what the winches can give: :func:`~marinecdpr.model.winch.winch_tension_bounds`).
        The methods' targets (the middle of the range) and the tolerance stay those of
        ``t_min``, ``t_max``: where these bounds do not bind, the tensions are the same as
        without them.

    Returns
    -------
    TensionSolution
        NaN tensions and ``feasible = False`` where no tensions within limits
        were found.
    """
    if method not in _METHODS:
        raise ValueError(
            f"unknown tension method {method!r} (expected pseudo_inverse, minimum_variance, "
            "closed_form, improved_closed_form or minimum_norm)"
        )
    J = np.asarray(J, dtype=float)
    w = np.asarray(w, dtype=float)
    lo = np.asarray(t_min, dtype=float)
    hi = np.asarray(t_max, dtype=float)
    n = J.shape[0]
    ok = np.ones(n, dtype=bool) if ok is None else np.asarray(ok, dtype=bool)
    mid = 0.5 * (lo + hi)
    tol = TENSION_TOLERANCE * max(1.0, float(np.max(np.abs(hi))))
    if lower is not None or upper is not None:  # each step's own bounds, (m, n_steps): lo[i] a row
        lo = (lo[:, None] if lower is None else np.maximum(lo[:, None], np.asarray(lower, dtype=float).T))
        hi = (hi[:, None] if upper is None else np.minimum(hi[:, None], np.asarray(upper, dtype=float).T))
        lo, hi = np.broadcast_arrays(lo, np.broadcast_to(hi, (hi.shape[0], n)))
        with np.errstate(invalid="ignore"):
            ok = ok & np.all(lo <= hi, axis=0)  # an empty (or NaN) range holds nothing
    code = _METHODS.index(method)
    target = np.zeros_like(mid) if method in ("pseudo_inverse", "minimum_norm") else mid
    sol = _series(J, w, code, target, lo, hi, ok, tol)
    if method in EXACT_METHODS:
        failed = np.flatnonzero(ok & ~sol.feasible)
        if failed.size and J.shape[1] > J.shape[2]:
            # those with tensions within the limits at all (vectorised), then each alone
            failed = failed[_may_hold(J[failed], w[failed], lo if lo.ndim == 1 else lo[:, failed].T,
                                      hi if hi.ndim == 1 else hi[:, failed].T, tol)]
        if failed.size:
            T, feasible = exact_fallback(J[failed], w[failed], target, lo if lo.ndim == 1 else lo[:, failed].T,
                                         hi if hi.ndim == 1 else hi[:, failed].T, tol)
            sol.tensions[failed[feasible]] = T[feasible]
            sol.feasible[failed[feasible]] = True
    return sol


EXACT_METHODS = ("minimum_variance", "minimum_norm")
"""The methods that minimise their objective exactly within the limits, so find tensions
wherever any exist (with :func:`exact_fallback` where the compiled method gives up)."""


def _may_hold(J: np.ndarray, w: np.ndarray, lo: np.ndarray, hi: np.ndarray, tol: float) -> np.ndarray:
    """Steps at which some tensions within the limits (widened by ``tol``) give the wrench,
    shape (n_steps,) of bool: :func:`exact_fallback`'s steps, told apart from the plainly
    infeasible at array speed.

    In the null space, T = T_s + N lambda, the limits cut a bounded polytope out of the r
    dimensions of lambda (each cable's two limits bound it along N's rows); it is not empty
    iff one of its vertices, where r of the 2 n_cables limits are tight, keeps every limit.
    For r = 1 the polytope is an interval: its ends compared, vectorised over the steps. For
    more redundancy every step is kept and solved alone (trying every vertex at once, r = 2,
    costs as much as that). True also on the edge of rounding: the solve alone decides there.
    """
    n, m, k = J.shape
    r = m - k
    keep = np.ones(n, dtype=bool)
    if r != 1:  # (for r = 2 every vertex tried at once costs what solving each step alone does)
        return keep
    T_s, ranked = pseudo_inverse_tensions(J, w)
    lo = np.broadcast_to(lo, (n, m))
    hi = np.broadcast_to(hi, (n, m))
    idx = np.flatnonzero(ranked)
    for s in range(0, idx.size, 1024):
        rows = idx[s:s + 1024]
        g = np.concatenate([N := null_space(J[rows])[..., 0], -N], axis=1)   # (b, 2m): g lambda >= h
        h = np.concatenate([lo[rows] - T_s[rows], T_s[rows] - hi[rows]], axis=1)
        margin = np.maximum(tol, 1e-9 * np.abs(h).max(axis=1))              # rounding, (b,)
        with np.errstate(divide="ignore", invalid="ignore"):
            q = h / g
        low = np.where(g > 1e-12, q, -np.inf).max(axis=1)                   # the interval's ends
        high = np.where(g < -1e-12, q, np.inf).min(axis=1)
        flat = np.where(np.abs(g) <= 1e-12, h, -np.inf).max(axis=1)         # limits lambda cannot move
        with np.errstate(invalid="ignore"):
            mid = 0.5 * (low + high)                                        # finite where low > high
            short = (g * mid[:, None] - h).min(axis=1)
        keep[rows] = (flat <= margin) & ((low <= high) | (short >= -margin))
    keep[~ranked] = False
    return keep


def exact_fallback(J: np.ndarray, w: np.ndarray, target: np.ndarray, lo: np.ndarray, hi: np.ndarray,
                   tol: float) -> tuple[np.ndarray, np.ndarray]:
    """min |T - target|^2 subject to J~^T T = w and lo <= T <= hi, step by step, in the null space.

    Every solution of J~^T T = w is T = T_s + N lambda (eqs. 17-19; N orthonormal, T_s
    orthogonal to it), so |T - target|^2 = |lambda - lambda_0|^2 + const with
    lambda_0 = N^T (target - T_s), and the limits read G mu >= h in mu = lambda - lambda_0:
    a least-distance programme, solved exactly by Lawson and Hanson's reduction to
    non-negative least squares (scipy.optimize.nnls): the dual vector u >= 0 minimising
    |E u - f|, E = [G^T; h^T], f = (0, ..., 0, 1); its residual rho gives mu = -rho[:r] /
    rho[r] (rho = 0: no mu holds every limit). The tensions are kept only where they are
    within the limits to ``tol`` and J~^T T = w to 1e-9 of its largest term (the compiled
    methods' own checks). A Python loop over the steps: for the few steps the compiled
    method gave up at.

    Parameters
    ----------
    J : ndarray, shape (n_steps, n_cables, k)
        Controlled columns of J~, full column rank.
    w : ndarray, shape (n_steps, k)
        Required wrench's controlled part, N and N m.
    target : ndarray, shape (n_cables,)
        The tensions the objective draws towards, N (the middle of the limits for
        minimum_variance, 0 for minimum_norm).
    lo, hi : ndarray, shape (n_cables,) or (n_steps, n_cables)
        Tension bounds, N.
    tol : float
        Tolerance on the limits, N.

    Returns
    -------
    T : ndarray, shape (n_steps, n_cables)
        N; NaN where no tensions were found.
    found : ndarray of bool, shape (n_steps,)
    """
    from scipy.optimize import nnls

    J = np.asarray(J, dtype=float)
    w = np.asarray(w, dtype=float)
    n, m, k = J.shape
    lo = np.broadcast_to(np.asarray(lo, dtype=float), (n, m))
    hi = np.broadcast_to(np.asarray(hi, dtype=float), (n, m))
    T = np.full((n, m), np.nan)
    found = np.zeros(n, dtype=bool)
    T_s, ranked = pseudo_inverse_tensions(J, w)
    if not ranked.any() or m == k:
        return T, found
    idx = np.flatnonzero(ranked)
    N = null_space(J[idx])
    r = m - k
    for j, i in enumerate(idx):
        Ni, Ts = N[j], T_s[i]
        lam0 = Ni.T @ (target - Ts)
        base = Ts + Ni @ lam0
        G = np.concatenate([Ni, -Ni])                        # G mu >= h
        h = np.concatenate([lo[i] - base, base - hi[i]])
        scale = max(1.0, float(np.abs(h).max()))
        E = np.vstack([G.T, h[None, :] / scale])
        f = np.zeros(r + 1)
        f[r] = 1.0
        try:
            u, _ = nnls(E, f, maxiter=50 * E.shape[1])
        except RuntimeError:
            continue
        rho = E @ u - f
        if not abs(rho[r]) > 1e-12:
            continue  # no tensions within the limits
        Ti = base + Ni @ (-rho[:r] / rho[r] * scale)
        if not (np.all(Ti >= lo[i] - tol) and np.all(Ti <= hi[i] + tol)):
            continue
        size = np.maximum(np.abs(w[i]), np.abs(J[i] * Ti[:, None]).max(axis=0))
        if not np.all(np.abs(J[i].T @ Ti - w[i]) <= 1e-9 * np.maximum(size, 1.0)):
            continue
        T[i], found[i] = Ti, True
    return T, found


_VERTEX_BUDGET = 4096
"""Largest number of candidate vertices per step :func:`largest_headroom` enumerates; above
it each step is solved as a linear programme (HiGHS)."""


def largest_headroom(J: np.ndarray, T_s: np.ndarray, t_min: np.ndarray, t_max: np.ndarray) -> np.ndarray:
    """The largest headroom any tensions producing the wrench could keep, at every step.

    The headroom of tensions T is their smallest distance to the limits,
    min_i min(T_i - T_min,i, T_max,i - T_i). Over every solution T = T_s + N lambda of
    J~^T T = w (eqs. 17, 19), this returns the largest: the linear programme
    max h s.t. T_s + N lambda - T_min >= h, T_max - T_s - N lambda >= h. It is the
    largest margin the limits could be tightened by with the step still feasible
    (negative: even the untightened limits cannot be met, by that much). Whatever the
    tension method, a step is feasible within the limits tightened by a margin M only
    if this is at least M (and the exact methods find tensions whenever it is).

    The programme is bounded (each cable's two limits bound lambda both ways along N's
    rows); its optimum is at a vertex where r + 1 of its 2 n_cables constraints are
    tight. For r = n_cables - k small enough (``_VERTEX_BUDGET`` candidates) every such
    vertex is tried, vectorised over the steps; otherwise HiGHS solves each step.

    Parameters
    ----------
    J : ndarray, shape (n_steps, n_cables, k)
        Controlled columns of J~ (eq. 6), full column rank where T_s is finite.
    T_s : ndarray, shape (n_steps, n_cables)
        The pseudo-inverse tensions (:func:`pseudo_inverse_tensions`), N; NaN at singular
        poses.
    t_min, t_max : ndarray, shape (n_cables,)
        Tension limits, N.

    Returns
    -------
    ndarray, shape (n_steps,)
        N; NaN where T_s is not finite (a singular pose).
    """
    from itertools import combinations
    from math import comb

    J = np.asarray(J, dtype=float)
    T_s = np.asarray(T_s, dtype=float)
    n, m, k = J.shape
    lo = np.broadcast_to(np.asarray(t_min, dtype=float), (m,))
    hi = np.broadcast_to(np.asarray(t_max, dtype=float), (m,))
    out = np.full(n, np.nan)
    good = np.all(np.isfinite(T_s), axis=1)
    if m == k:  # no redundancy: the tensions are T_s
        out[good] = np.minimum(T_s[good] - lo, hi - T_s[good]).min(axis=1)
        return out
    idx = np.flatnonzero(good)
    r = m - k
    if r == 1:  # a scalar lambda: the best of the cables' tents, in closed form
        for s in range(0, idx.size, 16384):
            rows = idx[s:s + 16384]
            out[rows] = _headroom_one(null_space(J[rows])[:, :, 0], T_s[rows], lo, hi)
        return out
    combos = np.array(list(combinations(range(2 * m), r + 1))) if comb(2 * m, r + 1) <= _VERTEX_BUDGET else None
    for s in range(0, idx.size, 2048):
        rows = idx[s:s + 2048]
        N = null_space(J[rows])                                    # (b, m, r)
        A = np.concatenate([N, -N], axis=1)                        # (b, 2m, r): h <= A lambda + b
        b = np.concatenate([T_s[rows] - lo, hi - T_s[rows]], axis=1)  # (b, 2m)
        if combos is None:
            out[rows] = [_headroom_lp(A[i], b[i]) for i in range(rows.size)]
            continue
        # vertex: A_j lambda - h = -b_j for the r + 1 constraints j of a combination
        A_c = A[:, combos]                                                                     # (b, c, r+1, r)
        M = np.concatenate([A_c, -np.ones(A_c.shape[:-1] + (1,))], axis=-1)                    # (b, c, r+1, r+1)
        rhs = -b[:, combos]                                                                    # (b, c, r+1)
        det = np.linalg.det(M)
        scale = np.abs(M).max(axis=(-2, -1)) ** (r + 1)
        regular = np.abs(det) > 1e-12 * scale
        M = np.where(regular[..., None, None], M, np.eye(r + 1))
        lam = np.linalg.solve(M, rhs[..., None])[..., :r, 0]                                  # (b, c, r)
        g = (np.einsum("bjr,bcr->bcj", A, lam) + b[:, None, :]).min(axis=-1)                  # (b, c)
        out[rows] = np.where(regular, g, -np.inf).max(axis=1)
    return out


@dataclass(frozen=True)
class WrenchFaces:
    """The facets of the wrenches tensions within limits can give (:func:`wrench_faces`).

    The set {J~^T T : T_min <= T <= T_max} is a zonotope: the sum of the cables' segments
    T_i g_i, g_i = J~'s row i. It is {w : |n_f . (w - c)| <= h_f for every facet f}, with
    n_f normal to k - 1 of the generators, c = J~^T (T_min + T_max) / 2 and
    h_f = sum_i |n_f . g_i| (T_max,i - T_min,i) / 2. Tightening every limit by M moves each
    facet in by M s_f, s_f = sum_i |n_f . g_i|.

    Attributes
    ----------
    normal : ndarray, shape (n_steps, n_faces, k)
        Unit normals n_f (in the wrench's mixed units, N and N m); zero where the k - 1
        generators are parallel (no facet: ``half_width`` is inf there).
    half_width : ndarray, shape (n_steps, n_faces)
        h_f, in n_f's units.
    centre : ndarray, shape (n_steps, k)
        c, N and N m.
    per_newton : ndarray, shape (n_steps, n_faces)
        s_f: how far the facet moves per newton the limits are tightened by.
    free : ndarray of int, shape (n_faces, k - 1)
        The cables (0-based) whose generators span facet f; the others sit at a limit on it:
        on the side +n_f, cable i at T_max where n_f . g_i > 0, at T_min where < 0.
    """

    normal: np.ndarray
    half_width: np.ndarray
    centre: np.ndarray
    per_newton: np.ndarray
    free: np.ndarray


def wrench_faces(J: np.ndarray, t_min: np.ndarray, t_max: np.ndarray) -> WrenchFaces:
    """The facets of the set of wrenches that tensions within limits produce (a zonotope).

    The headroom of a wrench w (:func:`largest_headroom`) is min_f (h_f - |n_f . (w - c)|) / s_f
    over the facets, capped at the narrowest range's half, min_i (T_max,i - T_min,i) / 2: by
    how much every limit can be tightened with w still inside.

    Parameters
    ----------
    J : ndarray, shape (n_steps, n_cables, k)
        Controlled columns of J~, full column rank.
    t_min, t_max : ndarray, shape (n_cables,)
        Tension limits, N.

    Returns
    -------
    WrenchFaces
        One facet for each choice of k - 1 cables (C(n_cables, k - 1) of them).
    """
    from itertools import combinations

    J = np.asarray(J, dtype=float)
    n, m, k = J.shape
    lo = np.broadcast_to(np.asarray(t_min, dtype=float), (m,))
    hi = np.broadcast_to(np.asarray(t_max, dtype=float), (m,))
    free = np.array(list(combinations(range(m), k - 1)), dtype=int).reshape(-1, k - 1)
    G = J[:, free]                                                    # (n, F, k-1, k)
    if k == 3:
        normal = np.cross(G[..., 0, :], G[..., 1, :])
    elif k == 2:
        normal = np.stack([G[..., 0, 1], -G[..., 0, 0]], axis=-1)
    else:
        normal = np.empty(G.shape[:2] + (k,))
        for j in range(k):  # the generalised cross product: n_j = (-1)^j det(G without column j)
            normal[..., j] = (-1.0) ** j * np.linalg.det(np.delete(G, j, axis=-1))
    size = np.linalg.norm(normal, axis=-1)
    scale = np.abs(J).max(axis=(1, 2))[:, None] ** (k - 1)
    facet = size > 1e-9 * scale
    normal = np.where(facet[..., None], normal / np.where(facet, size, 1.0)[..., None], 0.0)
    ng = np.abs(np.einsum("nfk,nik->nfi", normal, J))                 # |n_f . g_i|
    half = np.where(facet, ng @ ((hi - lo) / 2.0), np.inf)
    return WrenchFaces(normal=normal, half_width=half, centre=np.einsum("nik,i->nk", J, (lo + hi) / 2.0),
                       per_newton=np.where(facet, ng.sum(axis=-1), 1.0), free=free)


def _headroom_one(N: np.ndarray, T_s: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """:func:`largest_headroom` for one degree of redundancy: T = T_s + N lambda, lambda scalar.

    Cable i keeps min(T_i - lo_i, hi_i - T_i) = top_i - a_i |lambda - c_i|, a tent with apex
    c_i = (mid_i - T_s,i) / N_i, height top_i = (hi_i - lo_i) / 2 and slopes a_i = |N_i| (flat
    at top_i - |T_s,i - mid_i| where N_i = 0). Their minimum is concave and piecewise
    linear: its maximum lies at an apex or where the falling side of one tent meets the
    rising side of another, lambda = (top_i - top_j + a_i c_i + a_j c_j) / (a_i + a_j);
    every such lambda is tried.

    Parameters
    ----------
    N : ndarray, shape (n_steps, n_cables)
        The null space's vector (eq. 19).
    T_s : ndarray, shape (n_steps, n_cables)
    lo, hi : ndarray, shape (n_cables,)
    """
    from marinecdpr.model.tension_solver import headroom_one_series

    out = np.empty(N.shape[0])
    headroom_one_series(np.ascontiguousarray(N, dtype=float), np.ascontiguousarray(T_s, dtype=float),
                        np.ascontiguousarray(lo, dtype=float), np.ascontiguousarray(hi, dtype=float), out)
    return out


def _headroom_lp(A: np.ndarray, b: np.ndarray) -> float:
    """max h s.t. h <= A lambda + b (one step of :func:`largest_headroom`), by HiGHS."""
    from scipy.optimize import linprog

    r = A.shape[1]
    res = linprog(np.r_[np.zeros(r), -1.0], A_ub=np.c_[-A, np.ones(len(b))], b_ub=b,
                  bounds=[(None, None)] * (r + 1), method="highs")
    return float(-res.fun) if res.status == 0 else float("nan")
