"""Forward kinematics: the platform's pose from its cable lengths, compiled for a controller.

For cable i with frame anchor c_i (in C) and platform anchor p_i (in P) the length at pose
q = (x, y, z, rx, ry, rz) is |c_i - x - R(q) p_i| (eq. 2, R = Rz(rz) Ry(ry) Rx(rx)). The
pose is found by Levenberg-Marquardt on the residuals

    r_i(q) = |c_i - x - R(q) p_i| - L_i                         (m)

over the controlled DOFs only (the others stay as given), with the analytic Jacobian

    dr_i/dx      = -u_i
    dr_i/dangles = -((R p_i) x u_i)^T E(angles),     omega = E(angles) angles',

u_i = l_i / |l_i| (J~'s rows, eq. 6, with a minus sign since l' = -J~ (v, omega), eq. 5)
and, for R = Rz Ry Rx, E's columns R e_x (for rx'), Rz e_y (for ry'), e_z (for rz')
(:func:`~marinecdpr.geometry.rotations.angle_rate_matrix`). The first step is Gauss-Newton's; a step that does not lower
the sum of squares is rejected and the damping raised (Marquardt's scaling, diag(J^T J);
Nielsen's update from the ratio of actual to predicted decrease), so a warm start near the
pose converges quadratically. The k x k normal equations (k <= 6) are solved by Cholesky.

Status: 0 a pose (the iteration stopped and every residual is within the consistency
threshold, default 1e-6 m + 1e-6 L_i); 1 no stop within ``max_iter``; 2 a least-squares
point of lengths that no pose gives. A pose is recovered to round-off (RMS residual
~1e-16 m); lengths with noise below the threshold give status 0 at their least-squares
pose. Large residuals (status 2) converge only linearly: tens of iterations.

:func:`pose_from_lengths_step` solves one step without allocating (working memory from
:func:`forward_work`); :func:`pose_from_lengths` runs it over a series in a compiled loop,
each step warm-started from the previous solution, optionally from the winches' unstretched
lengths and the cables' tensions (:func:`stretched_lengths`).

Cables over swivelling pulleys (axes z_i, radii r_i: :mod:`marinecdpr.geometry.pulley`)
have lengths r_i beta_i + l_f (:func:`~marinecdpr.geometry.pulley.pulleys_step`) and the
same Jacobian with u_i along the free span (J~'s rows over the pulleys):
:func:`pulley_residuals_and_jacobian`, used by both solvers when given ``z_C`` and
``radius``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numba import njit

from marinecdpr.geometry.elastic import stretched_length
from marinecdpr.geometry.pulley import pulleys_step
from marinecdpr.geometry.rotations import rotation_and_rates

__all__ = ["ForwardKinematics", "ForwardWork", "forward_work", "pose_from_lengths", "pose_from_lengths_step",
           "residuals_and_jacobian", "pulley_residuals_and_jacobian", "stretched_lengths",
           "CONVERGED", "NOT_CONVERGED", "INCONSISTENT"]

CONVERGED, NOT_CONVERGED, INCONSISTENT = 0, 1, 2
"""Status codes of :func:`pose_from_lengths_step`: see there."""

_cache = True
_GTOL = 1e-10
"""Stationary also where the residuals' cosine with every Jacobian column is at most this."""


class ForwardWork(NamedTuple):
    """Working memory of :func:`pose_from_lengths_step` for m cables and k controlled DOFs
    (:func:`forward_work`); info holds the last call's results."""

    r: np.ndarray  # (m,) residuals at the current pose, m
    J: np.ndarray  # (m, k) their Jacobian in the controlled DOFs
    rt: np.ndarray  # (m,) residuals at the trial pose
    Jt: np.ndarray  # (m, k)
    qt: np.ndarray  # (6,) trial pose
    A: np.ndarray  # (k, k) J^T J
    M: np.ndarray  # (k, k) A + damping, then its Cholesky factor
    g: np.ndarray  # (k,) J^T r
    step: np.ndarray  # (k,) the step in the controlled DOFs (m, rad)
    consistency: np.ndarray  # (2,) lengths are a pose's when max |r_i| <= [0] + [1] L_i (m, -)
    info: np.ndarray  # (2,) written: RMS residual (m), iterations (trial steps)
    R: np.ndarray  # (3, 3) scratch over pulleys: R_PC at the pose
    Lq: np.ndarray  # (m,) the lengths at the pose
    J6: np.ndarray  # (m, 6) J~ at the pose
    exits: np.ndarray  # (m, 3) exit points
    wraps: np.ndarray  # (m,) wrap angles


def forward_work(m: int, k: int, atol_m: float = 1e-6, rtol: float = 1e-6) -> ForwardWork:
    """A :class:`ForwardWork` for m cables and k controlled DOFs.

    Parameters
    ----------
    m, k : int
        Number of cables and of controlled DOFs.
    atol_m, rtol : float
        Consistency threshold: the lengths are a pose's when the residuals where the
        iteration stops satisfy |r_i| <= atol_m + rtol L_i for every cable (m; rtol
        dimensionless). Raise it to the encoders' noise for measured lengths.
    """
    return ForwardWork(r=np.empty(m), J=np.empty((m, k)), rt=np.empty(m), Jt=np.empty((m, k)), qt=np.empty(6),
                       A=np.empty((k, k)), M=np.empty((k, k)), g=np.empty(k), step=np.empty(k),
                       consistency=np.array([atol_m, rtol], dtype=float), info=np.zeros(2), R=np.empty((3, 3)),
                       Lq=np.empty(m), J6=np.empty((m, 6)), exits=np.empty((m, 3)), wraps=np.empty(m))


# ------------------------------------------------------------------- one step, compiled


@njit(cache=_cache)
def residuals_and_jacobian(L, c_C, p_P, controlled, q, r, J):
    """Residuals r_i = |c_i - x - R p_i| - L_i and their analytic Jacobian, written in place.

    Parameters
    ----------
    L : ndarray, shape (m,)
        Cable lengths, m.
    c_C : ndarray, shape (m, 3)
        Frame anchors c_i in C, m.
    p_P : ndarray, shape (m, 3)
        Platform anchors p_i in P, m.
    controlled : int ndarray, shape (k,)
        Indices into q of J's columns.
    q : ndarray, shape (6,)
        (x, y, z, rx, ry, rz) in C, m and rad.
    r : ndarray, shape (m,)
        Written: r_i, m.
    J : ndarray, shape (m, k)
        Written: dr_i/dq_controlled[j]: -u_i[d] for a position d (m/m), -((R p_i) x u_i) .
        E[:, d - 3] for an angle d (m/rad).

    Returns
    -------
    float
        sum_i r_i^2 / 2, m^2.
    """
    rows, E = rotation_and_rates(q[3], q[4], q[5])
    (R00, R01, R02), (R10, R11, R12), (R20, R21, R22) = rows
    cost = 0.0
    for i in range(c_C.shape[0]):
        px, py, pz = p_P[i, 0], p_P[i, 1], p_P[i, 2]
        a0 = R00 * px + R01 * py + R02 * pz  # R p_i
        a1 = R10 * px + R11 * py + R12 * pz
        a2 = R20 * px + R21 * py + R22 * pz
        l0 = c_C[i, 0] - q[0] - a0  # eq. (2): l_i = c_i - (x + R p_i)
        l1 = c_C[i, 1] - q[1] - a1
        l2 = c_C[i, 2] - q[2] - a2
        n = np.sqrt(l0 * l0 + l1 * l1 + l2 * l2)
        u0, u1, u2 = l0 / n, l1 / n, l2 / n
        w0, w1, w2 = a1 * u2 - a2 * u1, a2 * u0 - a0 * u2, a0 * u1 - a1 * u0  # (R p_i) x u_i
        ri = n - L[i]
        r[i] = ri
        cost += 0.5 * ri * ri
        for j in range(controlled.shape[0]):
            d = controlled[j]
            if d == 0:
                J[i, j] = -u0
            elif d == 1:
                J[i, j] = -u1
            elif d == 2:
                J[i, j] = -u2
            else:
                e = E[d - 3]
                J[i, j] = -(w0 * e[0] + w1 * e[1] + w2 * e[2])
    return cost


@njit(cache=_cache)
def pulley_residuals_and_jacobian(L, c_C, z_C, radius, p_P, controlled, q, r, J, work):
    """:func:`residuals_and_jacobian` for cables over swivelling pulleys: r_i = L_i(q) - L_i
    with L_i(q) = r_i beta_i + l_f (:func:`~marinecdpr.geometry.pulley.pulleys_step`), and
    dr_i/dx = -u_i, dr_i/dangles = -((R p_i) x u_i)^T E with u_i along the free span.

    z_C (m, 3) and radius (m,) are the pulleys' swivel axes and radii (0: a point); the
    other arguments as for :func:`residuals_and_jacobian`; ``work`` (:class:`ForwardWork`)
    gives the scratch. A pose with a platform anchor on a pulley's axis or inside it gives
    NaN (the solver rejects it). Returns sum_i r_i^2 / 2, m^2.
    """
    rows, E = rotation_and_rates(q[3], q[4], q[5])
    R = work.R
    (R[0, 0], R[0, 1], R[0, 2]), (R[1, 0], R[1, 1], R[1, 2]), (R[2, 0], R[2, 1], R[2, 2]) = rows
    if pulleys_step(q[:3], R, c_C, z_C, radius, p_P, work.Lq, work.J6, work.exits, work.wraps) != 0:
        return np.nan
    cost = 0.0
    J6 = work.J6
    for i in range(c_C.shape[0]):
        ri = work.Lq[i] - L[i]
        r[i] = ri
        cost += 0.5 * ri * ri
        for j in range(controlled.shape[0]):
            d = controlled[j]
            if d < 3:
                J[i, j] = -J6[i, d]
            else:
                e = E[d - 3]
                J[i, j] = -(J6[i, 3] * e[0] + J6[i, 4] * e[1] + J6[i, 5] * e[2])
    return cost


@njit(cache=_cache, inline="always")
def _residuals(L, c_C, p_P, controlled, q, r, J, work, z_C, radius):
    """The point model's residuals, or over the pulleys when z_C is given."""
    if z_C is None:
        return residuals_and_jacobian(L, c_C, p_P, controlled, q, r, J)
    return pulley_residuals_and_jacobian(L, c_C, z_C, radius, p_P, controlled, q, r, J, work)


@njit(cache=_cache, inline="always")
def _damped_step(A, g, mu, M, step):
    """Solve (A + mu diag(A)) step = -g by Cholesky (k x k, in M); False if not positive
    definite. diag(A) is floored at 1e-12 max diag(A) so that mu > 0 always regularises."""
    k = A.shape[0]
    top = 0.0
    for a in range(k):
        top = max(top, A[a, a])
    for a in range(k):
        for b in range(k):
            M[a, b] = A[a, b]
        M[a, a] += mu * max(A[a, a], 1e-12 * top)
    for a in range(k):  # M = L L^T, L in the lower triangle
        for b in range(a + 1):
            s = M[a, b]
            for c in range(b):
                s -= M[a, c] * M[b, c]
            if a == b:
                if not s > 0.0:  # also NaN
                    return False
                M[a, a] = np.sqrt(s)
            else:
                M[a, b] = s / M[b, b]
    for a in range(k):  # L y = -g
        s = -g[a]
        for c in range(a):
            s -= M[a, c] * step[c]
        step[a] = s / M[a, a]
    for a in range(k - 1, -1, -1):  # L^T step = y
        s = step[a]
        for c in range(a + 1, k):
            s -= M[c, a] * step[c]
        step[a] = s / M[a, a]
    return True


@njit(cache=_cache)
def pose_from_lengths_step(L, c_C, p_P, controlled, q, tol_m, max_iter, work, z_C=None, radius=None):
    """The pose whose cable lengths are L, by Levenberg-Marquardt from the warm start q.

    No allocation: all scratch is in ``work`` (:func:`forward_work` (m, k)).

    Parameters
    ----------
    L : ndarray, shape (m,)
        Geometric cable lengths |l_i| (eq. 2), m.
    c_C : ndarray, shape (m, 3)
        Frame anchors c_i in C, m.
    p_P : ndarray, shape (m, 3)
        Platform anchors p_i in P, m.
    controlled : int ndarray, shape (k,)
        The DOFs solved for, indices into q (0..5 = x, y, z, rx, ry, rz; planar (0, 2, 4)).
    q : ndarray, shape (6,)
        (x, y, z, rx, ry, rz): P's origin in C (m) and R_PC's angles (rad). The warm start on
        entry, the solution on exit; only the controlled DOFs change. Left at the best pose
        found when the status is not 0.
    tol_m : float
        Step tolerance: the iteration stops when the step it would take from q is at most
        tol_m in every controlled DOF (m for positions, rad for angles), or when r is
        orthogonal to J's columns (cosine <= 1e-10: a least-squares point); q is then within
        about tol_m of the pose.
    max_iter : int
        Largest number of trial steps.
    work : ForwardWork
        Overwritten; on return work.info[0] is the RMS residual at q (m) and work.info[1] the
        number of trial steps taken (accepted or rejected).
    z_C, radius : ndarray, shape (m, 3) and (m,), optional
        Swivelling pulleys' axes (unit, in C) and radii (m): L are then the lengths over them
        (:func:`pulley_residuals_and_jacobian`); c_C are the frame anchors on their rims.

    Returns
    -------
    status : int
        0 (CONVERGED): stopped with consistent lengths, max_i |r_i| <= atol_m + rtol L_i
        (work.consistency, default 1e-6 m + 1e-6 L_i). 1 (NOT_CONVERGED): no stop within
        max_iter, or NaN lengths, warm start or Jacobian. 2 (INCONSISTENT): stopped at a
        least-squares point whose residual is above that threshold: the lengths are not
        those of any pose.
    """
    k = controlled.shape[0]
    r, J, rt, Jt, qt, A, g, step = work.r, work.J, work.rt, work.Jt, work.qt, work.A, work.g, work.step
    cost = _residuals(L, c_C, p_P, controlled, q, r, J, work, z_C, radius)
    if not np.isfinite(cost):  # NaN lengths or warm start
        work.info[0], work.info[1] = np.nan, 0.0
        return NOT_CONVERGED
    mu, nu = 0.0, 2.0  # damping (relative to diag(J^T J)) and its growth; Gauss-Newton first
    status = NOT_CONVERGED
    it = 0
    fresh = True  # r, J changed since the normal equations were formed
    while True:
        for a in range(k if fresh else 0):  # normal equations J^T J step = -J^T r
            s = 0.0
            for i in range(r.shape[0]):
                s += J[i, a] * r[i]
            g[a] = s
            for b in range(a + 1):
                s = 0.0
                for i in range(r.shape[0]):
                    s += J[i, a] * J[i, b]
                A[a, b] = s
                A[b, a] = s
        fresh = False
        while not _damped_step(A, g, mu, work.M, step):  # damp until the equations factor
            mu = 1e-3 if mu == 0.0 else 10.0 * mu
            if mu > 1e30:  # NaN pose or lengths
                break
        if mu > 1e30:
            break
        # stationary: the step is below tol_m, or r is orthogonal to J's columns (MINPACK's
        # gtol: a least-squares point; at a pose r is round-off and no column is orthogonal)
        biggest, cosine = 0.0, 0.0
        for a in range(k):
            biggest = max(biggest, abs(step[a]))
            cosine = max(cosine, abs(g[a]) / np.sqrt(A[a, a] * 2.0 * cost + 1e-300))
        if biggest <= tol_m or cosine <= _GTOL:
            status = CONVERGED
            for i in range(r.shape[0]):
                if not abs(r[i]) <= work.consistency[0] + work.consistency[1] * L[i]:
                    status = INCONSISTENT
            break
        if it >= max_iter:
            break
        it += 1
        for a in range(6):
            qt[a] = q[a]
        top = 0.0
        for a in range(k):
            top = max(top, A[a, a])
        predicted = 0.0  # the drop in cost the damped linear model predicts (> 0)
        for a in range(k):
            qt[controlled[a]] += step[a]
            predicted += 0.5 * step[a] * (mu * max(A[a, a], 1e-12 * top) * step[a] - g[a])
        trial = _residuals(L, c_C, p_P, controlled, qt, rt, Jt, work, z_C, radius)
        if trial < cost:  # accept (a NaN trial is rejected); Nielsen's damping update
            rho = (cost - trial) / predicted
            cost = trial
            for a in range(k):
                q[controlled[a]] = qt[controlled[a]]
            for i in range(r.shape[0]):
                r[i] = rt[i]
                for a in range(k):
                    J[i, a] = Jt[i, a]
            fresh = True
            mu *= max(1.0 / 3.0, 1.0 - (2.0 * rho - 1.0) ** 3)
            nu = 2.0
            if mu < 1e-12:
                mu = 0.0
        else:
            mu = 1e-3 if mu == 0.0 else nu * mu
            nu *= 2.0
    work.info[0] = np.sqrt(2.0 * cost / r.shape[0])
    work.info[1] = it
    return status


# ------------------------------------------------------------- over the steps, compiled


@njit(cache=_cache)
def _series(lengths, c_C, p_P, controlled, q0, tol_m, max_iter, work, poses, status, residual, iterations,
            z_C=None, radius=None):
    """:func:`pose_from_lengths_step` at every row of lengths (n, m), each step started from
    the previous solution (q0 for the first); writes poses (n, 6), status, residual,
    iterations (n,)."""
    for s in range(lengths.shape[0]):
        prev = q0 if s == 0 else poses[s - 1]
        for a in range(6):
            poses[s, a] = prev[a]
        status[s] = pose_from_lengths_step(lengths[s], c_C, p_P, controlled, poses[s], tol_m, max_iter, work,
                                           z_C, radius)
        residual[s] = work.info[0]
        iterations[s] = int(work.info[1])


# --------------------------------------------------------------------- over time series


def stretched_lengths(L0, T, EA):
    """Geometric length of a cable stretched by its tension: L0 (1 + T / EA).

    Parameters
    ----------
    L0 : array_like, m
        Unstretched length paid out by the winch.
    T : array_like, N
        Cable tension.
    EA : array_like, N
        Axial stiffness; inf for an inextensible cable (the length is then L0).

    Returns
    -------
    ndarray, m
        Broadcast shape of the arguments.
    """
    return stretched_length(np.asarray(L0, dtype=float), np.asarray(T, dtype=float), np.asarray(EA, dtype=float))


@dataclass(frozen=True)
class ForwardKinematics:
    """Poses solved from cable lengths over a time series.

    Attributes
    ----------
    poses : ndarray, shape (n_steps, 6)
        (x, y, z, rx, ry, rz): P's origin in C (m) and R_PC's angles (rad).
    status : ndarray, shape (n_steps,), int
        0 converged, 1 not converged within max_iter, 2 lengths of no pose (least-squares
        point returned); see :func:`pose_from_lengths_step`.
    residual_m : ndarray, shape (n_steps,)
        RMS of |c_i - x - R p_i| - L_i at the pose, m.
    iterations : ndarray, shape (n_steps,), int
        Trial steps taken.
    """

    poses: np.ndarray
    status: np.ndarray
    residual_m: np.ndarray
    iterations: np.ndarray


def pose_from_lengths(lengths, c_C, p_P, controlled, q0, *, tensions=None, EA=None, tol_m=1e-12, max_iter=50,
                      consistency=(1e-6, 1e-6), pulley_axes=None, pulley_radii=None) -> ForwardKinematics:
    """Platform poses from cable lengths, each step warm-started from the previous one.

    Parameters
    ----------
    lengths : ndarray, shape (n_steps, m) or (m,)
        Geometric lengths |l_i| (eq. 2), m; with ``tensions`` and ``EA``, the unstretched
        lengths the winches paid out (encoder lengths), m.
    c_C : ndarray, shape (m, 3)
        Frame anchors c_i in C, m.
    p_P : ndarray, shape (m, 3)
        Platform anchors p_i in P, m.
    controlled : sequence of int, length k
        The DOFs solved for, indices into the pose (``robot.controlled``: planar (0, 2, 4)).
    q0 : ndarray, shape (6,)
        (x, y, z, rx, ry, rz) in C, m and rad: the first step's starting guess; its
        uncontrolled DOFs are kept at every step.
    tensions : ndarray, shape (n_steps, m) or broadcastable, optional
        Cable tensions, N.
    EA : float or ndarray, shape (m,), optional
        Axial stiffness, N (inf: inextensible). Given with ``tensions``.
    tol_m : float
        Step tolerance, m for positions and rad for angles (:func:`pose_from_lengths_step`).
    max_iter : int
        Largest number of trial steps per step.
    consistency : (float, float)
        (atol_m, rtol): lengths are a pose's when max_i |r_i| <= atol_m + rtol L_i; above,
        status 2.
    pulley_axes, pulley_radii : ndarray, shape (m, 3) and (m,), optional
        Swivelling pulleys (``robot.pulley_axes``, ``robot.pulley_radii``): the lengths are
        over them. Both or neither.

    Returns
    -------
    ForwardKinematics
    """
    L = np.atleast_2d(np.asarray(lengths, dtype=float))
    c_C = np.array(c_C, dtype=float, order="C")  # copies: writable, C-contiguous (one compiled type)
    p_P = np.array(p_P, dtype=float, order="C")
    m = c_C.shape[0]
    if L.shape[1] != m or p_P.shape != (m, 3) or c_C.shape != (m, 3):
        raise ValueError(f"lengths {L.shape}, c_C {c_C.shape} and p_P {p_P.shape} disagree on the "
                         "number of cables (expected (n_steps, m), (m, 3), (m, 3))")
    if (tensions is None) != (EA is None):
        raise ValueError("give both tensions and EA to stretch the lengths, or neither")
    if tensions is not None:
        L = stretched_lengths(L, tensions, EA)
    L = np.array(np.broadcast_to(L, (L.shape[0], m)), order="C")
    ctrl = np.asarray(controlled, dtype=np.int64)
    if ctrl.ndim != 1 or ctrl.size == 0 or len(set(ctrl.tolist())) != ctrl.size or ctrl.min() < 0 or ctrl.max() > 5:
        raise ValueError(f"controlled must be distinct DOF indices in 0..5, got {controlled!r}")
    q0 = np.array(q0, dtype=float)
    if q0.shape != (6,):
        raise ValueError(f"q0 must have shape (6,), got {q0.shape}")
    n = L.shape[0]
    poses, status = np.empty((n, 6)), np.empty(n, dtype=np.int64)
    residual, iterations = np.empty(n), np.empty(n, dtype=np.int64)
    work = forward_work(m, ctrl.size, *consistency)
    if (pulley_axes is None) != (pulley_radii is None):
        raise ValueError("give both pulley_axes and pulley_radii, or neither")
    if pulley_axes is None:
        _series(L, c_C, p_P, ctrl, q0, float(tol_m), int(max_iter), work, poses, status, residual, iterations)
    else:
        z_C = np.array(pulley_axes, dtype=float, order="C")
        radius = np.array(pulley_radii, dtype=float, order="C")
        if z_C.shape != (m, 3) or radius.shape != (m,):
            raise ValueError(f"pulley_axes {z_C.shape} and pulley_radii {radius.shape}: expected ({m}, 3) and ({m},)")
        _series(L, c_C, p_P, ctrl, q0, float(tol_m), int(max_iter), work, poses, status, residual, iterations,
                z_C, radius)
    return ForwardKinematics(poses=poses, status=status, residual_m=residual, iterations=iterations)
