"""Compiled per-step kernels: the model at one instant, the only implementation of its equations.

The robot's model is written once, as numba-compiled functions of one step: the cables
(:func:`cables_step`, eqs. 2 and 6; defined in :mod:`marinecdpr.geometry.kinematics` and
re-exported here), the required wrench split by cause (:func:`wrench_parts_step`, eqs.
9-16; :func:`wrench_step` is its sum, eq. 15), the motion in O (:func:`absolute_step`, eqs.
7-11), the inertia (:func:`spatial_inertia_step`, :func:`inertial_terms_step`, eq. 13), a
disturbance in C (:func:`disturbance_step`) and the forward dynamics
(:func:`forward_solve_step`, :func:`forward_step`). A controller in the loop and a plant
integrator call them step by step; the array functions of
:mod:`~marinecdpr.model.dynamics` and :mod:`~marinecdpr.geometry.kinematics` run them in
compiled loops over time series (``tests/vectorised.py`` keeps the former numpy
implementation as the tests' reference). Frames and conventions are those of
:mod:`~marinecdpr.model.dynamics`; every vector here is in C unless named otherwise.

Every tension method is written once, per step (:func:`solve_tensions`), for any
redundancy, with one rank test (:func:`gram_full_rank`): the pseudo-inverse and Pott's
closed form, ``minimum_variance`` and ``minimum_norm`` exactly (the compiled active-set
QP :func:`least_distance`) and Pott's improved closed form (:func:`improved_closed_form`).
The closed loop calls it at every step (:func:`tensions_step`); planning, the workspace
and the studies over time series (:func:`tension_series`, through
:func:`marinecdpr.model.tension.distribute_tensions`), in blocks of steps that keep its
order of operations: a plan and the loop get the same bits at the same step.
``tests/tension_reference.py`` keeps the former numpy implementation as the tests' check.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from marinecdpr.geometry.kinematics import cables_step
from marinecdpr.geometry.rotations import euler_step

__all__ = [
    "METHOD_CODES",
    "FRAME_CODES",
    "euler_step",
    "wrench_parts_step",
    "wrench_step",
    "absolute_step",
    "spatial_inertia_step",
    "inertial_terms_step",
    "disturbance_step",
    "cables_step",
    "tensions_step",
    "TensionWork",
    "tension_work",
    "sum_wrench_parts",
    "least_distance",
    "improved_closed_form",
    "tension_series",
    "solve_tensions",
    "gram_full_rank",
    "headroom_one_series",
    "RCOND",
    "forward_solve_step",
    "forward_step",
    "absolute_series",
    "inertial_series",
    "spatial_inertia_series",
    "disturbance_series",
    "wrench_series",
    "forward_series",
]

METHOD_CODES = {"pseudo_inverse": 0, "closed_form": 1, "minimum_variance": 2, "minimum_norm": 3,
                "improved_closed_form": 4}
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


# ------------------------------------------------------------ the dynamics at one step
# Eqs. (7)-(16) for one instant, the only implementation: the closed loop calls these step
# by step and :mod:`~marinecdpr.model.dynamics` runs them over time series (the
# ``*_series`` functions below), on views of its time-last buffers. The ``*_step``
# functions are inlined (numba's inline="always") into the compiled code that calls them,
# so a loop over the steps is one piece of machine code; the helpers take and return
# 3-vectors as tuples of their components (no allocation per step).


@njit(cache=_cache)
def _cross(a0, a1, a2, b0, b1, b2):
    """a x b, by components."""
    return a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0


@njit(cache=_cache)
def _matvec(R, v0, v1, v2):
    """R v for R (3, 3)."""
    return (R[0, 0] * v0 + R[0, 1] * v1 + R[0, 2] * v2,
            R[1, 0] * v0 + R[1, 1] * v1 + R[1, 2] * v2,
            R[2, 0] * v0 + R[2, 1] * v1 + R[2, 2] * v2)


@njit(cache=_cache)
def _matTvec(R, v0, v1, v2):
    """R^T v for R (3, 3)."""
    return (R[0, 0] * v0 + R[1, 0] * v1 + R[2, 0] * v2,
            R[0, 1] * v0 + R[1, 1] * v1 + R[2, 1] * v2,
            R[0, 2] * v0 + R[1, 2] * v1 + R[2, 2] * v2)


@njit(cache=_cache)
def _rotate_inertia(R, I):
    """R I R^T for R (3, 3) and a symmetric I (3, 3), as (xx, yy, zz, xy, xz, yz)."""
    a00 = R[0, 0] * I[0, 0] + R[0, 1] * I[1, 0] + R[0, 2] * I[2, 0]  # R I
    a01 = R[0, 0] * I[0, 1] + R[0, 1] * I[1, 1] + R[0, 2] * I[2, 1]
    a02 = R[0, 0] * I[0, 2] + R[0, 1] * I[1, 2] + R[0, 2] * I[2, 2]
    a10 = R[1, 0] * I[0, 0] + R[1, 1] * I[1, 0] + R[1, 2] * I[2, 0]
    a11 = R[1, 0] * I[0, 1] + R[1, 1] * I[1, 1] + R[1, 2] * I[2, 1]
    a12 = R[1, 0] * I[0, 2] + R[1, 1] * I[1, 2] + R[1, 2] * I[2, 2]
    a20 = R[2, 0] * I[0, 0] + R[2, 1] * I[1, 0] + R[2, 2] * I[2, 0]
    a21 = R[2, 0] * I[0, 1] + R[2, 1] * I[1, 1] + R[2, 2] * I[2, 1]
    a22 = R[2, 0] * I[0, 2] + R[2, 1] * I[1, 2] + R[2, 2] * I[2, 2]
    return (a00 * R[0, 0] + a01 * R[0, 1] + a02 * R[0, 2],
            a10 * R[1, 0] + a11 * R[1, 1] + a12 * R[1, 2],
            a20 * R[2, 0] + a21 * R[2, 1] + a22 * R[2, 2],
            a00 * R[1, 0] + a01 * R[1, 1] + a02 * R[1, 2],
            a00 * R[2, 0] + a01 * R[2, 1] + a02 * R[2, 2],
            a10 * R[2, 0] + a11 * R[2, 1] + a12 * R[2, 2])


@njit(cache=_cache)
def _sym_matvec(S, v0, v1, v2):
    """S v for a symmetric S given as (xx, yy, zz, xy, xz, yz)."""
    xx, yy, zz, xy, xz, yz = S
    return (xx * v0 + xy * v1 + xz * v2,
            xy * v0 + yy * v1 + yz * v2,
            xz * v0 + yz * v1 + zz * v2)


@njit(cache=_cache, inline="always")
def wrench_parts_step(x, v, a, R_PC, w_pc, al_pc, R_SO, w_s, al_s, a_SO_O, origin, mass, I_PP, g,
                      f_C, m_C, parts):
    """The required wrench (eq. 15) at one step, split by cause, written to parts (5, 6).

    Rows of ``parts``, each (force N, moment N m) in C about the centre of mass, in the
    order of :class:`~marinecdpr.model.dynamics.WrenchTerms`; w = their sum:

    0. relative = M_s (a, alpha_PC) + C_rel = (m a, I_C alpha_PC + omega_PC x I_C omega_PC);
    1. gravity = -G = (-m g_O, 0) = (0, 0, m g, 0, 0, 0);
    2. C_s = (m (R_SO^T a_SO + alpha_s x r + omega_s x (omega_s x r) + 2 omega_s x v),
       I_C (alpha_s + omega_s x omega_PC) + W x I_C W - omega_PC x I_C omega_PC), W = omega_s
       + omega_PC (eqs. 9-11);
    3. gravity_tilt = (m (g_O - R_SO^T g_O), 0) (eq. 16);
    4. external = (-f_r, -m_r) (eq. 16),

    with r = x_CS + x_PC and I_C = R_PC I_PP R_PC^T.

    Parameters
    ----------
    x, v, a : ndarray, shape (3,)
        x_PC, v_PC, a_PC: P's position (m), velocity (m/s) and acceleration (m/s^2)
        relative to C, in C.
    R_PC : ndarray, shape (3, 3)
        R_P^C.
    w_pc, al_pc : ndarray, shape (3,)
        omega_PC, alpha_PC: P's angular velocity (rad/s) and acceleration (rad/s^2)
        relative to C, in C.
    R_SO : ndarray, shape (3, 3)
        R_S^O.
    w_s, al_s : ndarray, shape (3,)
        omega_s, alpha_s: the ship's angular velocity (rad/s) and acceleration (rad/s^2)
        in S.
    a_SO_O : ndarray, shape (3,)
        Acceleration of S's origin in O, m/s^2.
    origin : ndarray, shape (3,)
        x_CS: C's origin in S, m.
    mass : float
        m, kg.
    I_PP : ndarray, shape (3, 3)
        Inertia about the centre of mass in P, kg m^2.
    g : float
        Magnitude of gravity, m/s^2; g_O = (0, 0, -g).
    f_C, m_C : ndarray, shape (3,)
        Disturbance force f_r (N) and moment m_r (N m) in C.
    parts : ndarray, shape (5, 6)
        Written: relative, gravity, C_s, gravity_tilt, external.
    """
    I_C = _rotate_inertia(R_PC, I_PP)  # R_PC I_PP R_PC^T
    Iw = _sym_matvec(I_C, w_pc[0], w_pc[1], w_pc[2])
    gyro = _cross(w_pc[0], w_pc[1], w_pc[2], Iw[0], Iw[1], Iw[2])  # omega_PC x I_C omega_PC
    Ial = _sym_matvec(I_C, al_pc[0], al_pc[1], al_pc[2])
    # eq. (9) in S: base, Euler, centripetal and Coriolis accelerations
    r0, r1, r2 = x[0] + origin[0], x[1] + origin[1], x[2] + origin[2]  # x_PS^S
    base = _matTvec(R_SO, a_SO_O[0], a_SO_O[1], a_SO_O[2])  # R_SO^T a_SO
    euler = _cross(al_s[0], al_s[1], al_s[2], r0, r1, r2)
    wr = _cross(w_s[0], w_s[1], w_s[2], r0, r1, r2)
    centripetal = _cross(w_s[0], w_s[1], w_s[2], wr[0], wr[1], wr[2])
    coriolis = _cross(w_s[0], w_s[1], w_s[2], v[0], v[1], v[2])
    # eqs. (10)-(11) in S: W = omega_s + omega_PC, and alpha_s + omega_s x omega_PC
    W0, W1, W2 = w_s[0] + w_pc[0], w_s[1] + w_pc[1], w_s[2] + w_pc[2]
    ws_wpc = _cross(w_s[0], w_s[1], w_s[2], w_pc[0], w_pc[1], w_pc[2])
    Ib = _sym_matvec(I_C, al_s[0] + ws_wpc[0], al_s[1] + ws_wpc[1], al_s[2] + ws_wpc[2])
    IW = _sym_matvec(I_C, W0, W1, W2)
    WIW = _cross(W0, W1, W2, IW[0], IW[1], IW[2])
    for i in range(3):
        parts[0, i] = mass * a[i]
        parts[0, 3 + i] = Ial[i] + gyro[i]
        parts[1, i] = 0.0
        parts[1, 3 + i] = 0.0
        parts[2, i] = mass * (base[i] + euler[i] + centripetal[i] + 2.0 * coriolis[i])
        parts[2, 3 + i] = Ib[i] + WIW[i] - gyro[i]
        parts[3, 3 + i] = 0.0
        parts[4, i] = -f_C[i]
        parts[4, 3 + i] = -m_C[i]
    parts[1, 2] = mass * g
    # gravity in S: R_SO^T g_O = -g (third row of R_SO)
    parts[3, 0] = -mass * (-g * R_SO[2, 0])
    parts[3, 1] = -mass * (-g * R_SO[2, 1])
    parts[3, 2] = mass * (-g - (-g * R_SO[2, 2]))


@njit(cache=_cache)
def wrench_step(x, v, a, R_PC, w_pc, al_pc, R_SO, w_s, al_s, a_SO_O, origin, mass, I_PP, g,
                f_C, m_C, out):
    """Required wrench w (eq. 15) at one step: force and moment in C, written to out (6,).

    The sum relative + gravity + C_s + gravity_tilt + external of :func:`wrench_parts_step`,
    which documents the arguments.
    """
    parts = np.empty((5, 6))
    wrench_parts_step(x, v, a, R_PC, w_pc, al_pc, R_SO, w_s, al_s, a_SO_O, origin, mass, I_PP, g,
                      f_C, m_C, parts)
    sum_wrench_parts(parts, out)


@njit(cache=_cache, inline="always")
def sum_wrench_parts(parts, out):
    """w = the sum of :func:`wrench_parts_step`'s five rows (eq. 15), written to out (6,)."""
    for j in range(6):
        out[j] = parts[0, j] + parts[1, j] + parts[2, j] + parts[3, j] + parts[4, j]


@njit(cache=_cache, inline="always")
def absolute_step(x, v, a, w_pc, al_pc, x_SO_O, v_SO_O, a_SO_O, R_SO, w_s, al_s, origin, out):
    """The platform's motion in O at one step (eqs. 7-11), written to out (5, 3).

    Rows of ``out``: x_PO, v_PO, a_PO (m, m/s, m/s^2: P's centre of mass in O), omega_PO and
    alpha_PO (rad/s, rad/s^2, in O).

    Parameters
    ----------
    x, v, a : ndarray, shape (3,)
        x_PC, v_PC, a_PC relative to C, in C (m, m/s, m/s^2).
    w_pc, al_pc : ndarray, shape (3,)
        omega_PC, alpha_PC relative to C, in C (rad/s, rad/s^2).
    x_SO_O, v_SO_O, a_SO_O : ndarray, shape (3,)
        Position, velocity and acceleration of S's origin in O (m, m/s, m/s^2).
    R_SO : ndarray, shape (3, 3)
        R_S^O.
    w_s, al_s : ndarray, shape (3,)
        The ship's angular velocity and acceleration in S (rad/s, rad/s^2).
    origin : ndarray, shape (3,)
        x_CS: C's origin in S, m.
    out : ndarray, shape (5, 3)
        Written.
    """
    r0, r1, r2 = x[0] + origin[0], x[1] + origin[1], x[2] + origin[2]  # x_PS^S
    wr = _cross(w_s[0], w_s[1], w_s[2], r0, r1, r2)
    Rr = _matvec(R_SO, r0, r1, r2)
    Rv = _matvec(R_SO, wr[0] + v[0], wr[1] + v[1], wr[2] + v[2])
    euler = _cross(al_s[0], al_s[1], al_s[2], r0, r1, r2)  # eq. (9), products taken in S
    centripetal = _cross(w_s[0], w_s[1], w_s[2], wr[0], wr[1], wr[2])
    coriolis = _cross(w_s[0], w_s[1], w_s[2], v[0], v[1], v[2])
    Ra = _matvec(R_SO, euler[0] + centripetal[0] + 2.0 * coriolis[0] + a[0],
                 euler[1] + centripetal[1] + 2.0 * coriolis[1] + a[1],
                 euler[2] + centripetal[2] + 2.0 * coriolis[2] + a[2])
    Rw = _matvec(R_SO, w_s[0] + w_pc[0], w_s[1] + w_pc[1], w_s[2] + w_pc[2])
    ws_wpc = _cross(w_s[0], w_s[1], w_s[2], w_pc[0], w_pc[1], w_pc[2])
    Ral = _matvec(R_SO, al_s[0] + ws_wpc[0] + al_pc[0], al_s[1] + ws_wpc[1] + al_pc[1],
                  al_s[2] + ws_wpc[2] + al_pc[2])
    for i in range(3):
        out[0, i] = x_SO_O[i] + Rr[i]  # eq. (7)
        out[1, i] = v_SO_O[i] + Rv[i]  # eq. (8)
        out[2, i] = a_SO_O[i] + Ra[i]  # eq. (9)
        out[3, i] = Rw[i]  # eq. (10)
        out[4, i] = Ral[i]  # eq. (11)


@njit(cache=_cache, inline="always")
def spatial_inertia_step(R_PC, mass, I_PP, M):
    """M_s = diag(m E, R_PC I_PP R_PC^T) at one step, written to M (6, 6).

    R_PC (3, 3): R_P^C (or any body-to-frame rotation: the result is in that frame);
    mass: kg; I_PP (3, 3): inertia about the centre of mass in P, kg m^2.
    """
    xx, yy, zz, xy, xz, yz = _rotate_inertia(R_PC, I_PP)
    M[:, :] = 0.0
    for i in range(3):
        M[i, i] = mass
    M[3, 3], M[4, 4], M[5, 5] = xx, yy, zz
    M[3, 4] = M[4, 3] = xy
    M[3, 5] = M[5, 3] = xz
    M[4, 5] = M[5, 4] = yz


@njit(cache=_cache, inline="always")
def inertial_terms_step(R_SO, R_PC, omega_PO_O, mass, I_PP, g, M, C, G):
    """M, C and G of eq. (13) at one step, in O: M X'' + C X' - G - F_r = J^T T.

    Parameters
    ----------
    R_SO, R_PC : ndarray, shape (3, 3)
        R_S^O and R_P^C (R_PO = R_SO R_PC).
    omega_PO_O : ndarray, shape (3,)
        The platform's angular velocity in O, rad/s.
    mass : float
        kg.
    I_PP : ndarray, shape (3, 3)
        kg m^2, in P.
    g : float
        m/s^2 (gravity is (0, 0, -g) in O).
    M, C : ndarray, shape (6, 6)
        Written: diag(m E, I) with I = R_PO I_PP R_PO^T, and diag(0, [omega_PO x] I).
    G : ndarray, shape (6,)
        Written: (m g_O, 0) = (0, 0, -m g, 0, 0, 0).
    """
    R_PO = np.empty((3, 3))
    for i in range(3):
        for j in range(3):
            R_PO[i, j] = R_SO[i, 0] * R_PC[0, j] + R_SO[i, 1] * R_PC[1, j] + R_SO[i, 2] * R_PC[2, j]
    spatial_inertia_step(R_PO, mass, I_PP, M)
    C[:, :] = 0.0
    for j in range(3):
        col = _cross(omega_PO_O[0], omega_PO_O[1], omega_PO_O[2], M[3, 3 + j], M[4, 3 + j],
                     M[5, 3 + j])
        for i in range(3):
            C[3 + i, 3 + j] = col[i]
    G[:] = 0.0
    G[2] = -mass * g


FRAME_CODES = {"C": 0, "O": 1, "P": 2}
"""The frames a disturbance may be given in, as :func:`disturbance_step` takes them."""


@njit(cache=_cache, inline="always")
def disturbance_step(f, m, frame, R_SO, R_PC, f_C, m_C):
    """A disturbance force and moment given in O, C or P, expressed in C, at one step.

    f, m (3,): force (N) and moment (N m) in ``frame`` (a :data:`FRAME_CODES` value); R_SO,
    R_PC (3, 3). Writes f_C, m_C (3,): R_SO^T f (O), f (C) or R_PC f (P), and the same for m.
    """
    if frame == 1:  # O
        f_C[0], f_C[1], f_C[2] = _matTvec(R_SO, f[0], f[1], f[2])
        m_C[0], m_C[1], m_C[2] = _matTvec(R_SO, m[0], m[1], m[2])
    elif frame == 2:  # P
        f_C[0], f_C[1], f_C[2] = _matvec(R_PC, f[0], f[1], f[2])
        m_C[0], m_C[1], m_C[2] = _matvec(R_PC, m[0], m[1], m[2])
    else:  # C
        f_C[0], f_C[1], f_C[2] = f[0], f[1], f[2]
        m_C[0], m_C[1], m_C[2] = m[0], m[1], m[2]


# ------------------------------------------------------ the dynamics over time series
# The per-step functions above at every step, for :mod:`~marinecdpr.model.dynamics`'s array
# functions. Arguments are time-last, C-contiguous buffers, n the number of steps; each step
# hands the per-step function views of step k (it is inlined here: the loop over the steps
# runs as one piece of machine code). Scalars and constants as in the per-step functions.


@njit(cache=_cache)
def absolute_series(xt, twt, tdt, et, edt, eddt, RSt, wst, alst, origin, out):
    """:func:`absolute_step` at every step.

    xt (3, n): x_PC; twt, tdt (6, n): the twist and its rate; et, edt, eddt (6, n): eta
    and its rates; RSt (3, 3, n): R_SO; wst, alst (3, n): the ship's angular velocity and
    acceleration in S. Writes out (5, 3, n).
    """
    for k in range(xt.shape[1]):
        absolute_step(xt[:, k], twt[:3, k], tdt[:3, k], twt[3:, k], tdt[3:, k], et[:3, k],
                      edt[:3, k], eddt[:3, k], RSt[:, :, k], wst[:, k], alst[:, k], origin,
                      out[:, :, k])


@njit(cache=_cache)
def inertial_series(RSt, RPt, wt, mass, I_PP, g, Mt, Ct, Gt):
    """:func:`inertial_terms_step` at every step.

    RSt, RPt (3, 3, n): R_SO, R_PC; wt (3, n): omega_PO in O. Writes Mt, Ct (6, 6, n) and
    Gt (6, n).
    """
    for k in range(wt.shape[1]):
        inertial_terms_step(RSt[:, :, k], RPt[:, :, k], wt[:, k], mass, I_PP, g, Mt[:, :, k],
                            Ct[:, :, k], Gt[:, k])


@njit(cache=_cache)
def spatial_inertia_series(Rt, mass, I_PP, Mt):
    """:func:`spatial_inertia_step` at every step: Rt (3, 3, n): R_PC. Writes Mt (6, 6, n)."""
    for k in range(Rt.shape[2]):
        spatial_inertia_step(Rt[:, :, k], mass, I_PP, Mt[:, :, k])


@njit(cache=_cache)
def disturbance_series(ft, mt, frame, RSt, RPt, fCt, mCt):
    """:func:`disturbance_step` at every step.

    ft, mt (3, n): force and moment in ``frame``; RSt, RPt (3, 3, n): R_SO, R_PC. Writes
    fCt, mCt (3, n).
    """
    # one loop per frame, the frame a constant in each (the branch then leaves the loop)
    if frame == 1:
        for k in range(ft.shape[1]):
            disturbance_step(ft[:, k], mt[:, k], 1, RSt[:, :, k], RPt[:, :, k], fCt[:, k], mCt[:, k])
    elif frame == 2:
        for k in range(ft.shape[1]):
            disturbance_step(ft[:, k], mt[:, k], 2, RSt[:, :, k], RPt[:, :, k], fCt[:, k], mCt[:, k])
    else:
        for k in range(ft.shape[1]):
            disturbance_step(ft[:, k], mt[:, k], 0, RSt[:, :, k], RPt[:, :, k], fCt[:, k], mCt[:, k])


@njit(cache=_cache)
def wrench_series(xt, twt, tdt, RPt, RSt, wst, alst, aSt, origin, mass, I_PP, g, ft, mt, out):
    """:func:`wrench_parts_step` at every step.

    xt (3, n): x_PC; twt, tdt (6, n): the twist and its rate; RPt, RSt (3, 3, n): R_PC,
    R_SO; wst, alst (3, n): the ship's angular velocity and acceleration in S; aSt (3, n):
    a_SO in O; ft, mt (3, n): the disturbance in C. Writes out (5, 6, n): the parts.
    """
    for k in range(xt.shape[1]):
        wrench_parts_step(xt[:, k], twt[:3, k], tdt[:3, k], RPt[:, :, k], twt[3:, k], tdt[3:, k],
                          RSt[:, :, k], wst[:, k], alst[:, k], aSt[:, k], origin, mass, I_PP, g,
                          ft[:, k], mt[:, k], out[:, :, k])


@njit(cache=_cache)
def forward_series(Tt, Jt, Mt, bt, controlled, acc_t, react_t):
    """:func:`forward_solve_step` at every step.

    Tt (n_cables, n): tensions; Jt (6, n_cables, n): J~; Mt (6, 6, n): M_s; bt (6, n): the
    bias wrench. Writes acc_t (6, n) and react_t (6 - k, n).
    """
    for k in range(Tt.shape[1]):
        forward_solve_step(Jt[:, :, k].T, Tt[:, k], bt[:, k], Mt[:, :, k], controlled,
                           acc_t[:, k], react_t[:, k])


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


RCOND = 1e-12
"""The rank test's bound: J~ (or the free cables' A_F) has full column rank where the
eigenvalues of its Gram matrix G = A^T A have lambda_min / lambda_max > RCOND."""


@njit(cache=_cache)
def _rank_bounds(det, piv, tr, dmax, k, rcond):
    """The rank test from bounds on lambda_min / lambda_max of a k x k Gram matrix G:
    1 (above rcond), 0 (not), -1 (the bounds do not decide). det: det G (the product of
    the Cholesky pivots), piv: the smallest pivot, tr: trace G, dmax: the largest G_aa.
    lambda_min / lambda_max >= det / lambda_max^k >= det / tr^k, and every pivot is at
    least lambda_min while lambda_max >= dmax."""
    if not piv > 0.0:
        return 0  # a pivot <= 0 (or NaN): lambda_min is at rounding level
    if det > rcond * _pow(tr, k):
        return 1
    if piv <= rcond * dmax:
        return 0
    return -1


@njit(cache=_cache)
def _eigen_ratio_above(G, rcond):
    """lambda_min / lambda_max > rcond for a symmetric G (k, k), from its eigenvalues."""
    eig = np.linalg.eigvalsh(G)
    return eig[0] > rcond * max(eig[G.shape[0] - 1], 2.2250738585072014e-308)


@njit(cache=_cache)
def gram_full_rank(G, L, det, rcond):
    """The rank test of every tension method, per step and over a series: is
    lambda_min / lambda_max of the Gram matrix G (k, k) above rcond (:data:`RCOND`)?

    L and det are :func:`_cholesky`'s factor and determinant of G; the pivots are
    recomputed in the factor's own order (the same bits), the bounds of
    :func:`_rank_bounds` decide almost every case and the eigenvalues the rest. rcond 0
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
            break  # _cholesky stopped here
    decision = _rank_bounds(det, piv, tr, dmax, k, rcond)
    if decision >= 0:
        return decision == 1
    return _eigen_ratio_above(G, rcond)


@njit(cache=_cache)
def _solve_active(A, b, target, lo, hi, state, rcond, M, y, T):
    """The equality-constrained minimiser of |T - target|^2 with the active set held at its
    limits: T_W = limits, T_F = target_F + A_F y, (A_F^T A_F) y = b - A_W^T T_W - A_F^T target_F.
    M[0] holds A^T A. Returns False (T untouched) where A_F^T A_F fails the rank test
    (:func:`gram_full_rank` with rcond)."""
    n, k = A.shape
    G, L = M[1], M[2]
    _gram_free(A, state, M[0], G)
    if not gram_full_rank(G, L, _cholesky(G, L), rcond):
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
    """:func:`gram_full_rank` for step j of a block (:func:`_block_factor`'s G, det, piv,
    tr, dmax): the same decision from the same numbers."""
    k = G.shape[0]
    decision = _rank_bounds(det, piv, tr, dmax, k, RCOND)
    if decision >= 0:
        return decision == 1
    Gs = np.empty((k, k))
    for p in range(k):
        for q in range(p, k):
            Gs[p, q] = G[p, q, j]
            Gs[q, p] = G[p, q, j]
    return _eigen_ratio_above(Gs, RCOND)


@njit(cache=_cache)
def tension_series(Jt, wt, target, lo, hi, ok, method, tol, Tt, feasible):
    """Every tension method over a time series: :func:`solve_tensions` at every step.

    Jt (k, n, n_steps) and wt (k, n_steps): J~_c and w_c, time last; method: a
    :data:`METHOD_CODES` value; target (n,): the closed forms' and exact methods' target (0
    for the pseudo-inverse and minimum norm, E for the others); lo, hi (n, 1) the tension
    limits of every step, or (n, n_steps) each step's own; ok (n_steps,): steps to solve
    (the others are infeasible); tol as in :func:`least_distance`. Writes Tt (n, n_steps),
    NaN where infeasible, and feasible (n_steps,).

    The common case, the closed form on every cable within limits, runs on blocks of steps
    with the step innermost (Gram matrices, Cholesky factors and solves vectorise across
    steps) in the per-step solvers' own order of operations, so every step's tensions and
    rank test are those :func:`solve_tensions` gives (the tests check it bit for bit).
    Where the closed form breaks a limit, the step goes on as there: the active-set method
    (:func:`_active_set`) from this optimum, or :func:`improved_closed_form`.
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
    lo_s, hi_s = np.empty(n), np.empty(n)  # this step's limits
    per_step = lo.shape[1] > 1
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
            c = s if per_step else 0
            for i in range(n):
                lo_s[i] = lo[i, c]
                hi_s[i] = hi[i, c]
            if ok[s] and _rank_ok(G, j, det[j], piv[j], tr[j], dmax[j]):
                status = 1
                for i in range(n):
                    if not (Tb[i, j] >= lo_s[i] - tol and Tb[i, j] <= hi_s[i] + tol):
                        status = 0
                        break
                if status == 0 and method == 4:
                    _step_matrix(Jt, wt, s, A, b)
                    if improved_closed_form(A, b, target, lo_s, hi_s, tol, RCOND, T, M, v[0], state):
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
                    if _active_set(A, b, target, lo_s, hi_s, tol, T, M, v, wn, state) == 1:
                        status = 2
            for i in range(n):
                Tt[i, s] = Tb[i, j] if status == 1 else (T[i] if status == 2 else np.nan)
            feasible[s] = status > 0


@njit(cache=_cache)
def solve_tensions(A, b, target, lo, hi, tol, method, T, M, v, wn, state):
    """Tensions at one step by ``method`` (a :data:`METHOD_CODES` value), written to T (n,);
    True if within limits (else T is NaN). The one implementation of every method.

    A (n, k): J~_c; b (k,): w_c; target (n,): 0 for the pseudo-inverse and minimum norm, E
    = (lo + hi) / 2 for the others; tol as in :func:`least_distance`. Work arrays M (3, k,
    k), v (2, k), wn (2, n), state (n,) int64. Every method starts from the closed form
    on every cable, T = target + A (A^T A)^-1 (b - A^T target) (eq. 18 for target 0), under
    the one rank test (:func:`gram_full_rank`, :data:`RCOND`): the pseudo-inverse and
    Pott's closed form keep it where it is within limits; the exact methods
    (minimum variance, eq. 20, and minimum norm) go on to the exact QP from it
    (:func:`least_distance`), for any redundancy; the improved closed form holds the worst
    tension at its limit and repeats (:func:`improved_closed_form`).
    """
    if method == 4:
        return improved_closed_form(A, b, target, lo, hi, tol, RCOND, T, M, v[0], state)
    if method >= 2:
        return least_distance(A, b, target, lo, hi, tol, RCOND, T, M, v, wn, state) == 1
    _gram(A, M[0])
    for i in range(A.shape[0]):
        state[i] = 0
    if _solve_active(A, b, target, lo, hi, state, RCOND, M, v[0], T) and _within(T, lo, hi, tol):
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
    return solve_tensions(A, wc, target, lo, hi, tol, method, T, work.M, work.v, work.wn, work.state)


@njit(cache=_cache, inline="always")
def forward_solve_step(J, T, bias, M, controlled, out, reaction):
    """Relative acceleration from tensions at one step (forward dynamics), and the guide's reaction.

    Solves M_cc acc_c = (J~^T T - bias)_c in the controlled DOFs c; the others are held
    (zero relative acceleration) and the wrench the guide supplies there is
    reaction = M_uc acc_c + bias_u - (J~^T T)_u.

    Parameters
    ----------
    J : ndarray, shape (n_cables, 6)
        J~ (eq. 6).
    T : ndarray, shape (n_cables,)
        Tensions, N.
    bias : ndarray, shape (6,)
        The required wrench (eq. 15) at zero relative acceleration, in C (N, N m).
    M : ndarray, shape (6, 6)
        M_s (:func:`spatial_inertia_step`), in C.
    controlled : ndarray of int, shape (k,)
        Controlled twist indices.
    out : ndarray, shape (6,)
        Written: (a_PC, alpha_PC) in C, m/s^2 and rad/s^2; zero in the uncontrolled DOFs.
    reaction : ndarray, shape (6 - k,)
        Written: the reaction in the uncontrolled DOFs (increasing index), in C (N, N m).
    """
    n = J.shape[0]
    k = controlled.shape[0]
    cw = np.empty(6)  # J~^T T, the cables' wrench
    for a in range(6):
        acc = 0.0
        for i in range(n):
            acc += J[i, a] * T[i]
        cw[a] = acc
    Mc = np.empty((k, k))
    fc = np.empty(k)
    for a in range(k):
        fc[a] = cw[controlled[a]] - bias[controlled[a]]
        for b in range(k):
            Mc[a, b] = M[controlled[a], controlled[b]]
    lu_det_solve(Mc, fc)
    out[:] = 0.0
    for a in range(k):
        out[controlled[a]] = fc[a]
    j = 0
    for d in range(6):
        held = True
        for a in range(k):
            if controlled[a] == d:
                held = False
        if held:
            acc = 0.0
            for a in range(k):
                acc += M[d, controlled[a]] * fc[a]
            reaction[j] = acc + bias[d] - cw[d]
            j += 1


@njit(cache=_cache)
def forward_step(J, T, bias, R_PC, mass, I_PP, controlled, out):
    """Relative acceleration (a_PC, alpha_PC) in C from tensions (forward dynamics).

    Solves M_cc acc_c = (J~^T T - bias)_c (:func:`forward_solve_step` with
    M = :func:`spatial_inertia_step`); uncontrolled components are zero.
    J (n, 6), T (n,), bias (6,) = required wrench at zero relative acceleration;
    R_PC (3, 3); mass kg; I_PP (3, 3) kg m^2; controlled (k,) int; writes out (6,).
    """
    M = np.empty((6, 6))
    spatial_inertia_step(R_PC, mass, I_PP, M)
    forward_solve_step(J, T, bias, M, controlled, out, np.empty(6 - controlled.shape[0]))


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
