"""The model's vectorised numpy implementation: the slow, obvious reference for the compiled path.

These are the package's array functions as they were before the model was written once as
compiled per-step functions (:mod:`marinecdpr.geometry.kinematics`,
:mod:`marinecdpr.model.kernels`, run over time series by :mod:`marinecdpr.model.dynamics`),
kept unchanged: numpy over whole time series, each equation as one line of component
arithmetic. ``tests/model/test_kernels.py`` checks the compiled path against them. Same names,
signatures, return types, frames and units as the package's functions.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

from marinecdpr.geometry import vec
from marinecdpr.geometry.kinematics import CableKinematics
from marinecdpr.geometry.rotations import skew
from marinecdpr.model.dynamics import AbsoluteMotion, WrenchTerms, uncontrolled
from marinecdpr.motion.ship import ShipMotion

__all__ = [
    "cable_kinematics",
    "global_jacobian",
    "absolute_motion",
    "inertial_frame_terms",
    "spatial_inertia",
    "disturbance_in_C",
    "wrench_terms",
    "forward_dynamics",
]


# --------------------------------------------- component helpers only this reference uses
# (moved from marinecdpr.geometry._vec, which keeps those the package still uses)
Vec = Sequence  # three components: arrays of shape (n,) or scalars


def add(*vs: Vec) -> list:
    return [sum(v[i] for v in vs) for i in range(3)]


def scale(s, a: Vec) -> list:
    return [s * a[0], s * a[1], s * a[2]]


def matTvec(R: np.ndarray, v: Vec) -> list:
    """R^T @ v with R of shape (n, 3, 3) (or (3, 3))."""
    return [R[..., 0, i] * v[0] + R[..., 1, i] * v[1] + R[..., 2, i] * v[2] for i in range(3)]


def sym_matvec(S: Sequence, v: Vec) -> list:
    """S @ v for a symmetric S given as (Sxx, Syy, Szz, Sxy, Sxz, Syz)."""
    xx, yy, zz, xy, xz, yz = S
    return [
        xx * v[0] + xy * v[1] + xz * v[2],
        xy * v[0] + yy * v[1] + yz * v[2],
        xz * v[0] + yz * v[1] + zz * v[2],
    ]


def rotate_inertia(R: np.ndarray, I: np.ndarray) -> list:
    """R I R^T as its six independent components (xx, yy, zz, xy, xz, yz)."""
    RI = [[R[..., i, 0] * I[0, k] + R[..., i, 1] * I[1, k] + R[..., i, 2] * I[2, k]
           for k in range(3)] for i in range(3)]

    def entry(i: int, j: int):
        return RI[i][0] * R[..., j, 0] + RI[i][1] * R[..., j, 1] + RI[i][2] * R[..., j, 2]

    return [entry(0, 0), entry(1, 1), entry(2, 2), entry(0, 1), entry(0, 2), entry(1, 2)]


# ------------------------------------------------------------ geometry/kinematics.py


def cable_kinematics(
    x_PC: np.ndarray,
    R_PC: np.ndarray,
    c_C: np.ndarray,
    p_P: np.ndarray,
    twist: np.ndarray | None = None,
) -> CableKinematics:
    """Cable vectors, lengths, unit vectors, J~ and length rates.

    Parameters
    ----------
    x_PC : ndarray, shape (n_steps, 3)
        Position of P's origin in C, m.
    R_PC : ndarray, shape (n_steps, 3, 3)
        R_P^C.
    c_C : ndarray, shape (n_cables, 3)
        Frame anchors c_i in C, m.
    p_P : ndarray, shape (n_cables, 3)
        Platform anchors p_i in P, m.
    twist : ndarray, shape (n_steps, 6), optional
        (v_PC, omega_PC) in C, m/s and rad/s.

    Returns
    -------
    CableKinematics
        Lengths are zero and J~ rows NaN where an anchor pair coincides.
    """
    x_PC = np.asarray(x_PC, dtype=float)
    R_PC = np.asarray(R_PC, dtype=float)
    c_C = np.asarray(c_C, dtype=float)
    p_P = np.asarray(p_P, dtype=float)
    n, m = x_PC.shape[0], c_C.shape[0]
    # Components as (n_cables, n_steps) arrays; results are packed time-last.
    r = [sum(p_P[:, j, None] * R_PC[:, a, j] for j in range(3)) for a in range(3)]  # R_PC p_i
    l_vec = [c_C[:, a, None] - x_PC[:, a] - r[a] for a in range(3)]  # eq. (2)
    lengths = np.sqrt(vec.dot(l_vec, l_vec))
    with np.errstate(invalid="ignore", divide="ignore"):
        inv = 1.0 / lengths
    u = scale(inv, l_vec)
    rxu = vec.cross(r, u)  # eq. (6)
    J = np.empty((6, m, n))
    for a in range(3):
        J[a] = u[a]
        J[3 + a] = rxu[a]
    rates = None
    if twist is not None:
        twist = np.asarray(twist, dtype=float)
        rates = -sum(J[k] * twist[:, k] for k in range(6)).T  # eq. (5)
    anchors = np.empty((3, m, n))
    for a in range(3):
        anchors[a] = r[a]
    return CableKinematics(
        lengths=lengths.T,
        anchors_C=anchors.transpose(2, 1, 0),
        J_tilde=J.transpose(2, 1, 0),
        length_rates=rates,
    )


def global_jacobian(J_tilde: np.ndarray, R_SO: np.ndarray) -> np.ndarray:
    """J = J~ S^T with S = diag(R_SO, R_SO) (eq. 14): J~'s rows expressed in O.

    Parameters
    ----------
    J_tilde : ndarray, shape (n_steps, n_cables, 6)
    R_SO : ndarray, shape (n_steps, 3, 3)

    Returns
    -------
    J : ndarray, shape (n_steps, n_cables, 6)
    """
    R = np.asarray(R_SO, dtype=float)[:, None]  # broadcast over cables
    parts = vec.matvec(R, [J_tilde[..., a] for a in range(3)])
    parts += vec.matvec(R, [J_tilde[..., 3 + a] for a in range(3)])
    J = np.empty((6,) + J_tilde.shape[:2])
    for k in range(6):
        J[k] = parts[k]
    return np.moveaxis(J, 0, -1)


# ------------------------------------------------------------------ model/dynamics.py


def absolute_motion(
    x_PC: np.ndarray, twist: np.ndarray, twist_dot: np.ndarray, ship: ShipMotion,
    *, frame_origin_S: np.ndarray,
) -> AbsoluteMotion:
    """Where the platform is and how it moves in O, from its motion on the ship.

    Parameters
    ----------
    x_PC : ndarray, shape (n_steps, 3)
        Position of P in C, m.
    twist, twist_dot : ndarray, shape (n_steps, 6)
        (v_PC, omega_PC) in C and its derivative.
    ship : ShipMotion
    frame_origin_S : ndarray, shape (3,)
        Origin of C in S, m.

    Returns
    -------
    AbsoluteMotion
    """
    n = x_PC.shape[0]
    R = ship.R_SO
    r = [x_PC[:, i] + float(frame_origin_S[i]) for i in range(3)]  # x_PS^S
    w_s, al_s = vec.comps(ship.omega_SO_S), vec.comps(ship.alpha_SO_S)
    v, w_pc = vec.comps(twist[:, :3]), vec.comps(twist[:, 3:])
    a, al_pc = vec.comps(twist_dot[:, :3]), vec.comps(twist_dot[:, 3:])
    x = add(vec.comps(ship.x_SO_O), vec.matvec(R, r))  # eq. (7)
    vel = add(vec.comps(ship.eta_dot[:, :3]), vec.matvec(R, add(vec.cross(w_s, r), v)))  # eq. (8)
    acc = add(vec.comps(ship.a_SO_O), vec.matvec(R, add(  # eq. (9), products taken in S
        vec.cross(al_s, r), vec.cross(w_s, vec.cross(w_s, r)), scale(2.0, vec.cross(w_s, v)), a)))
    omega = vec.matvec(R, add(w_s, w_pc))  # eq. (10)
    alpha = vec.matvec(R, add(al_s, vec.cross(w_s, w_pc), al_pc))  # eq. (11)
    return AbsoluteMotion(*(vec.pack(q, n) for q in (x, vel, acc, omega, alpha)))


def inertial_frame_terms(
    R_SO: np.ndarray, R_PC: np.ndarray, omega_PO_O: np.ndarray, *, mass: float,
    I_PP: np.ndarray, gravity: float,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """M, C and G of eq. (13): M X'' + C X' - G - F_r = J^T T, all in O.

    Parameters
    ----------
    R_SO, R_PC : ndarray, shape (n_steps, 3, 3)
    omega_PO_O : ndarray, shape (n_steps, 3)
        Platform angular velocity in O, rad/s.
    mass : float
        kg.
    I_PP : ndarray, shape (3, 3)
        kg m^2.
    gravity : float
        m/s^2 (gravity is (0, 0, -g) in O).

    Returns
    -------
    M : ndarray, shape (n_steps, 6, 6)
        diag(m E, I) with I = R_SO R_PC I_PP R_PC^T R_SO^T.
    C : ndarray, shape (n_steps, 6, 6)
        diag(0, [omega_PO x] I).
    G : ndarray, shape (n_steps, 6)
        (m g, 0) with g = (0, 0, -g): the paper's "G = [0 0 mg 0 0 0]" with its g = -9.8.
    """
    R_PO = np.einsum("nij,njk->nik", R_SO, R_PC)
    M = spatial_inertia(R_PO, mass, I_PP)
    n = M.shape[0]
    C = np.zeros((n, 6, 6))
    C[:, 3:, 3:] = np.einsum("nij,njk->nik", skew(omega_PO_O), M[:, 3:, 3:])
    G = np.zeros((n, 6))
    G[:, 2] = -mass * gravity
    return M, C, G


def spatial_inertia(R_PC: np.ndarray, mass: float, I_PP: np.ndarray) -> np.ndarray:
    """M_s = diag(m E, R_PC I_PP R_PC^T) in C.

    Parameters
    ----------
    R_PC : ndarray, shape (n_steps, 3, 3)
    mass : float
        kg.
    I_PP : ndarray, shape (3, 3)
        Inertia about the centre of mass in P, kg m^2.

    Returns
    -------
    M : ndarray, shape (n_steps, 6, 6)
    """
    n = R_PC.shape[0]
    xx, yy, zz, xy, xz, yz = rotate_inertia(R_PC, np.asarray(I_PP, dtype=float))
    zero = np.zeros(n)
    mass_row = [mass + zero, zero, zero]
    return vec.pack(
        [mass_row + [zero] * 3,
         [zero, mass + zero, zero] + [zero] * 3,
         [zero, zero, mass + zero] + [zero] * 3,
         [zero] * 3 + [xx, xy, xz],
         [zero] * 3 + [xy, yy, yz],
         [zero] * 3 + [xz, yz, zz]],
        n,
    )


def disturbance_in_C(
    f: np.ndarray, m: np.ndarray, frame: str, R_SO: np.ndarray, R_PC: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Express a disturbance force and moment given in O, C or P in C.

    Parameters
    ----------
    f, m : ndarray, shape (n_steps, 3)
        Force (N) and moment (N m) in ``frame``.
    frame : {"O", "C", "P"}
    R_SO, R_PC : ndarray, shape (n_steps, 3, 3)
    """
    f = np.asarray(f, dtype=float)
    m = np.asarray(m, dtype=float)
    if frame == "C":
        return f, m
    n = f.shape[0]
    rot = matTvec if frame == "O" else vec.matvec
    R = R_SO if frame == "O" else R_PC
    return vec.pack(rot(R, vec.comps(f)), n), vec.pack(rot(R, vec.comps(m)), n)


def wrench_terms(
    x_PC: np.ndarray,
    twist: np.ndarray,
    twist_dot: np.ndarray,
    R_PC: np.ndarray,
    ship: ShipMotion,
    *,
    frame_origin_S: np.ndarray,
    mass: float,
    I_PP: np.ndarray,
    gravity: float,
    f_ext_C: np.ndarray | None = None,
    m_ext_C: np.ndarray | None = None,
) -> WrenchTerms:
    """The wrench the platform needs for a motion on a moving ship (eqs. 9-16).

    Parameters
    ----------
    x_PC : ndarray, shape (n_steps, 3)
        Position of P (centre of mass) in C, m.
    twist : ndarray, shape (n_steps, 6)
        (v_PC, omega_PC) in C: motion relative to the ship, m/s and rad/s.
    twist_dot : ndarray, shape (n_steps, 6)
        (a_PC, alpha_PC) in C, m/s^2 and rad/s^2.
    R_PC : ndarray, shape (n_steps, 3, 3)
    ship : ShipMotion
    frame_origin_S : ndarray, shape (3,)
        Origin of C in S, m.
    mass : float
        kg.
    I_PP : ndarray, shape (3, 3)
        kg m^2.
    gravity : float
        Magnitude g, m/s^2; gravity is (0, 0, -g) in O.
    f_ext_C, m_ext_C : ndarray, shape (n_steps, 3), optional
        Disturbance force and moment f_r, m_r in C.

    Returns
    -------
    WrenchTerms
    """
    n = x_PC.shape[0]
    twist = np.asarray(twist, dtype=float)
    twist_dot = np.asarray(twist_dot, dtype=float)
    v, w_pc = vec.comps(twist[:, :3]), vec.comps(twist[:, 3:])
    a, al_pc = vec.comps(twist_dot[:, :3]), vec.comps(twist_dot[:, 3:])
    w_s, al_s = vec.comps(ship.omega_SO_S), vec.comps(ship.alpha_SO_S)
    origin = np.asarray(frame_origin_S, dtype=float)
    r = [x_PC[:, i] + origin[i] for i in range(3)]  # x_PS^S
    I_C = rotate_inertia(R_PC, np.asarray(I_PP, dtype=float))  # R_PC I_PP R_PC^T

    def I_dot(x):
        return sym_matvec(I_C, x)

    I_w_pc = I_dot(w_pc)
    gyro_pc = vec.cross(w_pc, I_w_pc)
    relative = scale(mass, a) + add(I_dot(al_pc), gyro_pc)

    # eq. (9) in S: base, Euler, centripetal and Coriolis accelerations
    a_base = matTvec(ship.R_SO, vec.comps(ship.a_SO_O))
    acc = add(
        a_base,
        vec.cross(al_s, r),
        vec.cross(w_s, vec.cross(w_s, r)),
        scale(2.0, vec.cross(w_s, v)),
    )
    W = add(w_s, w_pc)  # eq. (10) in S
    # eq. (11) in S, and the gyroscopic term beyond the platform's own
    mom = add(I_dot(add(al_s, vec.cross(w_s, w_pc))), vec.cross(W, I_dot(W)))
    C_s = scale(mass, acc) + [mom[i] - gyro_pc[i] for i in range(3)]

    # gravity (0, 0, -g) in O, and in S: R_SO^T g_O = -g (third row of R_SO)
    g_S = [-gravity * ship.R_SO[:, 2, i] for i in range(3)]
    zero = np.zeros(n)
    grav = [zero, zero, mass * gravity + zero, zero, zero, zero]
    tilt = [-mass * g_S[0], -mass * g_S[1], mass * (-gravity - g_S[2]), zero, zero, zero]
    if f_ext_C is None:
        f_ext_C = np.zeros((n, 3))
    if m_ext_C is None:
        m_ext_C = np.zeros((n, 3))
    external = [-f_ext_C[:, i] for i in range(3)] + [-m_ext_C[:, i] for i in range(3)]
    return WrenchTerms(
        vec.pack(relative, n), vec.pack(grav, n), vec.pack(C_s, n), vec.pack(tilt, n),
        vec.pack(external, n),
    )


def forward_dynamics(
    tensions: np.ndarray,
    J_tilde: np.ndarray,
    M: np.ndarray,
    bias: np.ndarray,
    controlled: tuple[int, ...],
) -> tuple[np.ndarray, np.ndarray]:
    """Platform acceleration relative to the ship from cable tensions.

    Solves ``M_cc twist_dot_c = (J~^T T - bias)_c`` in the controlled DOFs; the
    others are held (zero relative acceleration) and their reaction is returned.

    Parameters
    ----------
    tensions : ndarray, shape (n_steps, n_cables)
        T, N.
    J_tilde : ndarray, shape (n_steps, n_cables, 6)
    M : ndarray, shape (n_steps, 6, 6)
        :func:`spatial_inertia`.
    bias : ndarray, shape (n_steps, 6)
        ``wrench_terms(...).total`` evaluated with zero ``twist_dot``.
    controlled : tuple of int
        Controlled twist indices.

    Returns
    -------
    twist_dot : ndarray, shape (n_steps, 6)
        (a_PC, alpha_PC) in C.
    reaction : ndarray, shape (n_steps, 6 - len(controlled))
        Wrench the guide supplies in the uncontrolled DOFs, in C.
    """
    c = list(controlled)
    u = list(uncontrolled(controlled))
    cable_wrench = np.einsum("nmk,nm->nk", J_tilde, tensions)  # J~^T T
    rhs = (cable_wrench - bias)[:, c]
    twist_dot = np.zeros_like(bias)
    twist_dot[:, c] = np.linalg.solve(M[:, c][:, :, c], rhs[..., None])[..., 0]
    reaction = (
        np.einsum("nij,nj->ni", M[:, u][:, :, c], twist_dot[:, c]) + bias[:, u] - cable_wrench[:, u]
    )
    return twist_dot, reaction


# ------------------------------------------------------------------ rotations
def cos_sin(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """cos(x), sin(x); a constant series is evaluated once (trig dominates the hot path).

    Parameters
    ----------
    x : ndarray, shape (...)
        rad.
    """
    x = np.asarray(x, dtype=float)
    if x.size and x.flat[0] == x.flat[-1] and (x == x.flat[0]).all():
        x0 = float(x.flat[0])
        return np.full(x.shape, np.cos(x0)), np.full(x.shape, np.sin(x0))
    return np.cos(x), np.sin(x)


def euler_kinematics(
    angles: np.ndarray, rates: np.ndarray | None = None, accels: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray | None, np.ndarray | None]:
    """The former numpy implementation of ``geometry.rotations.euler_kinematics`` (now a
    compiled loop): the reference it is checked against.

    Rotation matrix and body-frame angular velocity and acceleration from Euler angles.

    ``R = Rz(psi) Ry(theta) Rx(phi)`` maps body-frame vectors to the reference
    frame, and ``dR/dt = R [omega_b x]`` with

        omega_b = (phi' - s_th psi',
                   c_ph th' + s_ph c_th psi',
                  -s_ph th' + c_ph c_th psi')

    and ``alpha_b = d(omega_b)/dt`` differentiated exactly. Because
    ``d(R omega_b)/dt = R alpha_b``, the same vectors expressed in the reference
    frame are ``R @ omega_b`` and ``R @ alpha_b``.

    Parameters
    ----------
    angles : ndarray, shape (..., 3)
        ``(phi, theta, psi)`` = roll, pitch, yaw, rad.
    rates, accels : ndarray, shape (..., 3), optional
        First (rad/s) and second (rad/s^2) time derivatives of the angles.

    Returns
    -------
    R : ndarray, shape (..., 3, 3)
    omega_b, alpha_b : ndarray, shape (..., 3), or None without rates
        rad/s and rad/s^2, in the body frame.
    """
    angles = np.asarray(angles, dtype=float)
    cph, sph = cos_sin(angles[..., 0])
    cth, sth = cos_sin(angles[..., 1])
    cps, sps = cos_sin(angles[..., 2])
    # time-last buffers: R[..., i, j] is then a contiguous array
    R = np.empty((3, 3) + angles.shape[:-1])
    R[0, 0] = cps * cth
    R[0, 1] = cps * sth * sph - sps * cph
    R[0, 2] = cps * sth * cph + sps * sph
    R[1, 0] = sps * cth
    R[1, 1] = sps * sth * sph + cps * cph
    R[1, 2] = sps * sth * cph - cps * sph
    R[2, 0] = -sth
    R[2, 1] = cth * sph
    R[2, 2] = cth * cph
    R = np.moveaxis(R, (0, 1), (-2, -1))
    if rates is None:
        return R, None, None
    rates = np.asarray(rates, dtype=float)
    accels = np.zeros_like(rates) if accels is None else np.asarray(accels, dtype=float)
    dph, dth, dps = rates[..., 0], rates[..., 1], rates[..., 2]
    ddph, ddth, ddps = accels[..., 0], accels[..., 1], accels[..., 2]
    shape = np.broadcast_shapes(angles.shape, rates.shape, accels.shape)[:-1]
    omega = np.empty((3,) + shape)
    omega[0] = dph - sth * dps
    omega[1] = cph * dth + sph * cth * dps
    omega[2] = -sph * dth + cph * cth * dps
    alpha = np.empty((3,) + shape)
    alpha[0] = ddph - sth * ddps - cth * dth * dps
    alpha[1] = (
        cph * ddth - sph * dph * dth + sph * cth * ddps
        + cph * cth * dph * dps - sph * sth * dth * dps
    )
    alpha[2] = (
        -sph * ddth - cph * dph * dth + cph * cth * ddps
        - sph * cth * dph * dps - cph * sth * dth * dps
    )
    return R, np.moveaxis(omega, 0, -1), np.moveaxis(alpha, 0, -1)
