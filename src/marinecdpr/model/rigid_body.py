"""The platform as a rigid body on the moving ship, compiled: the model at one instant and
its loops over time series, the only implementation of its equations.

The required wrench split by cause (:func:`wrench_parts_step`, eqs. 9-16; :func:`wrench_step`
is its sum, eq. 15), the motion in O (:func:`absolute_step`, eqs. 7-11), the inertia
(:func:`spatial_inertia_step`, :func:`inertial_terms_step`, eq. 13), a disturbance in C
(:func:`disturbance_step`) and the forward dynamics (:func:`forward_solve_step`,
:func:`forward_step`). A controller in the loop and a plant integrator call them step by
step; the array functions of :mod:`~marinecdpr.model.dynamics` run them in compiled loops
over time series (the ``*_series`` functions here; ``tests/vectorised.py`` keeps the former
numpy implementation as the tests' reference). The cables (eqs. 2 and 6) are
:func:`marinecdpr.geometry.kinematics.cables_step`; the tensions,
:mod:`~marinecdpr.model.tension_solver`. Frames and conventions are those of
:mod:`~marinecdpr.model.dynamics`; every vector here is in C unless named otherwise.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from marinecdpr.model.linalg import lu_det_solve

__all__ = [
    "FRAME_CODES",
    "RigidBody",
    "ShipAt",
    "wrench_parts_step",
    "wrench_step",
    "sum_wrench_parts",
    "absolute_step",
    "spatial_inertia_step",
    "inertial_terms_step",
    "disturbance_step",
    "forward_solve_step",
    "forward_step",
    "absolute_series",
    "inertial_series",
    "spatial_inertia_series",
    "disturbance_series",
    "wrench_series",
    "forward_series",
]

_cache = True


class RigidBody(NamedTuple):
    """The platform's constants as the compiled functions take them (one record, passed by
    numba as a struct).

    mass : float, kg. I_PP : ndarray (3, 3), inertia about the centre of mass in P, kg m^2.
    g : float, magnitude of gravity, m/s^2 (g_O = (0, 0, -g)). origin : ndarray (3,), x_CS:
    C's origin in S, m. Any record with these attributes serves (the controller's
    ``RobotModel`` has them; numba compiles once per record type).
    """

    mass: float
    I_PP: np.ndarray
    g: float
    origin: np.ndarray


class ShipAt(NamedTuple):
    """The ship's motion as the compiled functions take it: at one step, or as time-last
    series for the ``*_series`` functions (then each field gains a last axis of n steps).

    R_SO : ndarray (3, 3), R_S^O. w_s, al_s : ndarray (3,), omega_s and alpha_s, the ship's
    angular velocity (rad/s) and acceleration (rad/s^2) in S. a_SO_O : ndarray (3,), the
    acceleration of S's origin in O, m/s^2.
    """

    R_SO: np.ndarray
    w_s: np.ndarray
    al_s: np.ndarray
    a_SO_O: np.ndarray


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
def wrench_parts_step(x, v, a, R_PC, w_pc, al_pc, ship, body, f_C, m_C, parts):
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
    ship : ShipAt
        The ship at this step: R_SO (3, 3); omega_s, alpha_s (3,) in S (rad/s, rad/s^2);
        a_SO (3,) in O, m/s^2.
    body : RigidBody
        Or any record with its attributes: mass (kg), I_PP (3, 3, kg m^2, in P), g (m/s^2;
        g_O = (0, 0, -g)) and origin (3,): x_CS, C's origin in S, m.
    f_C, m_C : ndarray, shape (3,)
        Disturbance force f_r (N) and moment m_r (N m) in C.
    parts : ndarray, shape (5, 6)
        Written: relative, gravity, C_s, gravity_tilt, external.
    """
    R_SO, w_s, al_s, a_SO_O = ship.R_SO, ship.w_s, ship.al_s, ship.a_SO_O
    mass, I_PP, g, origin = body.mass, body.I_PP, body.g, body.origin
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
def wrench_step(x, v, a, R_PC, w_pc, al_pc, ship, body, f_C, m_C, out):
    """Required wrench w (eq. 15) at one step: force and moment in C, written to out (6,).

    The sum relative + gravity + C_s + gravity_tilt + external of :func:`wrench_parts_step`,
    which documents the arguments.
    """
    parts = np.empty((5, 6))
    wrench_parts_step(x, v, a, R_PC, w_pc, al_pc, ship, body, f_C, m_C, parts)
    sum_wrench_parts(parts, out)


@njit(cache=_cache, inline="always")
def sum_wrench_parts(parts, out):
    """w = the sum of :func:`wrench_parts_step`'s five rows (eq. 15), written to out (6,)."""
    for j in range(6):
        out[j] = parts[0, j] + parts[1, j] + parts[2, j] + parts[3, j] + parts[4, j]


@njit(cache=_cache, inline="always")
def absolute_step(x, v, a, w_pc, al_pc, x_SO_O, v_SO_O, ship, origin, out):
    """The platform's motion in O at one step (eqs. 7-11), written to out (5, 3).

    Rows of ``out``: x_PO, v_PO, a_PO (m, m/s, m/s^2: P's centre of mass in O), omega_PO and
    alpha_PO (rad/s, rad/s^2, in O).

    Parameters
    ----------
    x, v, a : ndarray, shape (3,)
        x_PC, v_PC, a_PC relative to C, in C (m, m/s, m/s^2).
    w_pc, al_pc : ndarray, shape (3,)
        omega_PC, alpha_PC relative to C, in C (rad/s, rad/s^2).
    x_SO_O, v_SO_O : ndarray, shape (3,)
        Position and velocity of S's origin in O (m, m/s).
    ship : ShipAt
        The ship at this step: R_SO (3, 3); omega_s, alpha_s (3,) in S (rad/s, rad/s^2);
        a_SO (3,) in O, m/s^2.
    origin : ndarray, shape (3,)
        x_CS: C's origin in S, m.
    out : ndarray, shape (5, 3)
        Written.
    """
    R_SO, w_s, al_s, a_SO_O = ship.R_SO, ship.w_s, ship.al_s, ship.a_SO_O
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


# ------------------------------------------------------ the dynamics over time series
# The per-step functions above at every step, for :mod:`~marinecdpr.model.dynamics`'s array
# functions. Arguments are time-last, C-contiguous buffers, n the number of steps; each step
# hands the per-step function views of step k (it is inlined here: the loop over the steps
# runs as one piece of machine code). Scalars and constants as in the per-step functions.


@njit(cache=_cache)
def absolute_series(xt, twt, tdt, xSt, vSt, ship_t, origin, out):
    """:func:`absolute_step` at every step.

    xt (3, n): x_PC; twt, tdt (6, n): the twist and its rate; xSt, vSt (3, n): x_SO, v_SO
    in O; ship_t: a :class:`ShipAt` of series (R_SO (3, 3, n); omega_s, alpha_s, a_SO
    (3, n)). Writes out (5, 3, n).
    """
    for k in range(xt.shape[1]):
        ship = ShipAt(ship_t.R_SO[:, :, k], ship_t.w_s[:, k], ship_t.al_s[:, k], ship_t.a_SO_O[:, k])
        absolute_step(xt[:, k], twt[:3, k], tdt[:3, k], twt[3:, k], tdt[3:, k], xSt[:, k], vSt[:, k],
                      ship, origin, out[:, :, k])


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
def wrench_series(xt, twt, tdt, RPt, ship_t, body, ft, mt, out):
    """:func:`wrench_parts_step` at every step.

    xt (3, n): x_PC; twt, tdt (6, n): the twist and its rate; RPt (3, 3, n): R_PC; ship_t:
    a :class:`ShipAt` of series (R_SO (3, 3, n); omega_s, alpha_s, a_SO (3, n)); body: a
    :class:`RigidBody`; ft, mt (3, n): the disturbance in C. Writes out (5, 6, n): the parts.
    """
    for k in range(xt.shape[1]):
        ship = ShipAt(ship_t.R_SO[:, :, k], ship_t.w_s[:, k], ship_t.al_s[:, k], ship_t.a_SO_O[:, k])
        wrench_parts_step(xt[:, k], twt[:3, k], tdt[:3, k], RPt[:, :, k], twt[3:, k], tdt[3:, k],
                          ship, body, ft[:, k], mt[:, k], out[:, :, k])


@njit(cache=_cache)
def forward_series(Tt, Jt, Mt, bt, controlled, acc_t, react_t):
    """:func:`forward_solve_step` at every step.

    Tt (n_cables, n): tensions; Jt (6, n_cables, n): J~; Mt (6, 6, n): M_s; bt (6, n): the
    bias wrench. Writes acc_t (6, n) and react_t (6 - k, n).
    """
    for k in range(Tt.shape[1]):
        forward_solve_step(Jt[:, :, k].T, Tt[:, k], bt[:, k], Mt[:, :, k], controlled,
                           acc_t[:, k], react_t[:, k])
