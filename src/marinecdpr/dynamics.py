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

from .basemotion import ShipMotion

__all__ = [
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


def _rotate(R: np.ndarray, v: np.ndarray) -> np.ndarray:
    """R @ v for stacks: R (n, 3, 3), v (n, 3)."""
    return np.einsum("nij,nj->ni", R, v)


def _rotate_T(R: np.ndarray, v: np.ndarray) -> np.ndarray:
    """R^T @ v for stacks: R (n, 3, 3), v (n, 3)."""
    return np.einsum("nji,nj->ni", R, v)


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
    M = np.zeros((n, 6, 6))
    M[:, 0, 0] = M[:, 1, 1] = M[:, 2, 2] = mass
    M[:, 3:, 3:] = np.einsum("nij,jk,nlk->nil", R_PC, I_PP, R_PC)
    return M


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
    if frame == "O":
        return _rotate_T(R_SO, f), _rotate_T(R_SO, m)
    if frame == "P":
        return _rotate(R_PC, f), _rotate(R_PC, m)
    return np.asarray(f, dtype=float), np.asarray(m, dtype=float)


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
    v, w_pc = twist[:, :3], twist[:, 3:]
    a, al_pc = twist_dot[:, :3], twist_dot[:, 3:]
    w_s, al_s = ship.omega_SO_S, ship.alpha_SO_S
    r = x_PC + np.asarray(frame_origin_S, dtype=float)  # x_PS^S

    I_C = np.einsum("nij,jk,nlk->nil", R_PC, I_PP, R_PC)

    def I_dot(x: np.ndarray) -> np.ndarray:
        return np.einsum("nij,nj->ni", I_C, x)

    relative = np.empty((n, 6))
    relative[:, :3] = mass * a
    relative[:, 3:] = I_dot(al_pc) + np.cross(w_pc, I_dot(w_pc))

    C_s = np.empty((n, 6))
    # eq. (9) in S: base, Euler, centripetal and Coriolis accelerations
    C_s[:, :3] = mass * (
        _rotate_T(ship.R_SO, ship.a_SO_O)
        + np.cross(al_s, r)
        + np.cross(w_s, np.cross(w_s, r))
        + 2.0 * np.cross(w_s, v)
    )
    W = w_s + w_pc  # eq. (10) in S
    C_s[:, 3:] = (
        I_dot(al_s + np.cross(w_s, w_pc))  # eq. (11) in S
        + np.cross(W, I_dot(W))
        - np.cross(w_pc, I_dot(w_pc))
    )

    g_O = np.array([0.0, 0.0, -gravity])
    grav = np.zeros((n, 6))
    grav[:, :3] = -mass * g_O
    tilt = np.zeros((n, 6))
    tilt[:, :3] = mass * (g_O - _rotate_T(ship.R_SO, np.broadcast_to(g_O, (n, 3))))

    external = np.zeros((n, 6))
    if f_ext_C is not None:
        external[:, :3] = -f_ext_C
    if m_ext_C is not None:
        external[:, 3:] = -m_ext_C
    return WrenchTerms(relative, grav, C_s, tilt, external)


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
