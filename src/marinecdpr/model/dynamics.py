"""Newton-Euler dynamics of the platform on a moving ship (the paper's eqs. 7-16).

Everything is written in the robot frame C, whose axes are the ship's (S). With
r = x_CS + x_PC the platform's position in S, (v, a) its velocity and acceleration
relative to the ship, omega_s and alpha_s the ship's angular velocity and
acceleration in S, and I_C = R_PC I_PP R_PC^T, the wrench the cables (and, in the
DOFs they do not control, the guide) must supply is eq. (15):

    w = M_s (a, alpha_PC) + C_rel + C_s - G + F_s

    M_s (a, alpha)  = (m a, I_C alpha_PC)                                relative inertia
    C_rel           = (0, omega_PC x I_C omega_PC)                       platform's own gyroscopic term
    C_s  (force)    = m (R_SO^T a_SO + alpha_s x r + omega_s x (omega_s x r) + 2 omega_s x v)
                                                                         eq. (9), ship-induced
    C_s  (moment)   = I_C (alpha_s + omega_s x omega_PC) + W x I_C W - omega_PC x I_C omega_PC
                      with W = omega_s + omega_PC                        eqs. (10)-(11)
    -G              = (-m g_O, 0)                                        gravity as if the ship were level
    F_s             = (m (g_O - R_SO^T g_O) - f_r^C, -m_r^C)             eq. (16): gravity tilt and disturbance

The fixed-base (traditional) model is the same with the ship still, so that
C_s = 0 and the gravity tilt vanishes.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from marinecdpr.geometry import _vec as vec
from marinecdpr.motion.ship import ShipMotion
from marinecdpr.geometry.rotations import skew

__all__ = [
    "AbsoluteMotion",
    "absolute_motion",
    "inertial_frame_terms",
    "WrenchTerms",
    "wrench_terms",
    "spatial_inertia",
    "disturbance_in_C",
    "forward_dynamics",
    "uncontrolled",
]


@dataclass(frozen=True)
class WrenchTerms:
    """The wrench the platform needs, split by cause; each (n_steps, 6) = (force N, moment N m) in C.

    ``total = relative + gravity + C_s + gravity_tilt + external``.
    """

    relative: np.ndarray
    """M_s (a, alpha_PC) + C_rel: the platform's own motion relative to the ship."""
    gravity: np.ndarray
    """-G: holding the platform against gravity on a level ship."""
    C_s: np.ndarray
    """Ship-induced inertial terms (hull interference and Coriolis, eq. 15)."""
    gravity_tilt: np.ndarray
    """Change of gravity in C as the ship rolls and pitches (part of F_s, eq. 16)."""
    external: np.ndarray
    """-(f_r, m_r) in C (part of F_s, eq. 16)."""

    @property
    def F_s(self) -> np.ndarray:
        """External interference of eq. (16): gravity tilt plus disturbance."""
        return self.gravity_tilt + self.external

    @property
    def total(self) -> np.ndarray:
        """The wrench w of eq. (15), shape (n_steps, 6)."""
        return self.relative + self.gravity + self.C_s + self.gravity_tilt + self.external


@dataclass(frozen=True)
class AbsoluteMotion:
    """The platform's motion in the inertial frame O (eqs. 7-11); each (n_steps, 3).

    Attributes
    ----------
    x_PO_O, v_PO_O, a_PO_O : ndarray
        Position (m), velocity (m/s) and acceleration (m/s^2) of P's centre of mass in O.
    omega_PO_O, alpha_PO_O : ndarray
        Angular velocity (rad/s) and acceleration (rad/s^2) of P in O.
    """

    x_PO_O: np.ndarray
    v_PO_O: np.ndarray
    a_PO_O: np.ndarray
    omega_PO_O: np.ndarray
    alpha_PO_O: np.ndarray


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
    x = vec.add(vec.comps(ship.x_SO_O), vec.matvec(R, r))  # eq. (7)
    vel = vec.add(vec.comps(ship.eta_dot[:, :3]), vec.matvec(R, vec.add(vec.cross(w_s, r), v)))  # eq. (8)
    acc = vec.add(vec.comps(ship.a_SO_O), vec.matvec(R, vec.add(  # eq. (9), products taken in S
        vec.cross(al_s, r), vec.cross(w_s, vec.cross(w_s, r)), vec.scale(2.0, vec.cross(w_s, v)), a)))
    omega = vec.matvec(R, vec.add(w_s, w_pc))  # eq. (10)
    alpha = vec.matvec(R, vec.add(al_s, vec.cross(w_s, w_pc), al_pc))  # eq. (11)
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
    xx, yy, zz, xy, xz, yz = vec.rotate_inertia(R_PC, np.asarray(I_PP, dtype=float))
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
    rot = vec.matTvec if frame == "O" else vec.matvec
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
    I_C = vec.rotate_inertia(R_PC, np.asarray(I_PP, dtype=float))  # R_PC I_PP R_PC^T

    def I_dot(x):
        return vec.sym_matvec(I_C, x)

    I_w_pc = I_dot(w_pc)
    gyro_pc = vec.cross(w_pc, I_w_pc)
    relative = vec.scale(mass, a) + vec.add(I_dot(al_pc), gyro_pc)

    # eq. (9) in S: base, Euler, centripetal and Coriolis accelerations
    a_base = vec.matTvec(ship.R_SO, vec.comps(ship.a_SO_O))
    acc = vec.add(
        a_base,
        vec.cross(al_s, r),
        vec.cross(w_s, vec.cross(w_s, r)),
        vec.scale(2.0, vec.cross(w_s, v)),
    )
    W = vec.add(w_s, w_pc)  # eq. (10) in S
    # eq. (11) in S, and the gyroscopic term beyond the platform's own
    mom = vec.add(I_dot(vec.add(al_s, vec.cross(w_s, w_pc))), vec.cross(W, I_dot(W)))
    C_s = vec.scale(mass, acc) + [mom[i] - gyro_pc[i] for i in range(3)]

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


def uncontrolled(controlled: tuple[int, ...]) -> tuple[int, ...]:
    """Twist indices the cables do not control (held by the hull or a guide)."""
    return tuple(i for i in range(6) if i not in controlled)


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
