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

The equations are written once, as compiled functions of one step in
:mod:`~marinecdpr.model.rigid_body` (:func:`~marinecdpr.model.rigid_body.wrench_parts_step`,
:func:`~marinecdpr.model.rigid_body.forward_step`, ...), which the closed loop calls step by
step. The functions here take whole time series, shaped ``(n_steps, ...)``, and run those
per-step functions in compiled loops over the steps (``rigid_body.wrench_series`` and the
like), reading and writing time-last buffers: the arrays they return are views of them
(``docs/conventions.md``, "Array layout").
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from marinecdpr.model import rigid_body as RB
from marinecdpr.motion.ship import ShipMotion

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


def _time_last(a: np.ndarray) -> np.ndarray:
    """(n_steps, ...) as a C-contiguous (..., n_steps) float array (no copy for a time-last view)."""
    return np.ascontiguousarray(np.moveaxis(np.asarray(a, dtype=float), 0, -1))


def _const(a: np.ndarray) -> np.ndarray:
    """A constant of the model (an inertia, an origin) as a C-contiguous float array."""
    return np.ascontiguousarray(a, dtype=float)


# ------------------------------------------------------------------------ over time series


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
    xt = _time_last(x_PC)
    out = np.empty((5, 3, xt.shape[1]))
    ship_t = RB.ShipAt(_time_last(ship.R_SO), _time_last(ship.omega_SO_S), _time_last(ship.alpha_SO_S),
                       _time_last(ship.a_SO_O))
    RB.absolute_series(xt, _time_last(twist), _time_last(twist_dot), _time_last(ship.x_SO_O),
                       _time_last(ship.v_SO_O), ship_t, _const(frame_origin_S), out)  # eqs. (7)-(11)
    return AbsoluteMotion(*(out[p].T for p in range(5)))


class InertialTerms(NamedTuple):
    """:func:`inertial_frame_terms`' result: M, C (n_steps, 6, 6) and G (n_steps, 6) of eq. (13), in O."""

    M: np.ndarray
    C: np.ndarray
    G: np.ndarray


def inertial_frame_terms(
    R_SO: np.ndarray, R_PC: np.ndarray, omega_PO_O: np.ndarray, *, mass: float,
    I_PP: np.ndarray, gravity: float,
) -> InertialTerms:
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
    InertialTerms
        M (n_steps, 6, 6): diag(m E, I) with I = R_SO R_PC I_PP R_PC^T R_SO^T;
        C (n_steps, 6, 6): diag(0, [omega_PO x] I);
        G (n_steps, 6): (m g, 0) with g = (0, 0, -g): the paper's "G = [0 0 mg 0 0 0]" with its g = -9.8.
    """
    wt = _time_last(omega_PO_O)
    n = wt.shape[1]
    Mt, Ct, Gt = np.empty((6, 6, n)), np.empty((6, 6, n)), np.empty((6, n))
    RB.inertial_series(_time_last(R_SO), _time_last(R_PC), wt, float(mass), _const(I_PP), float(gravity),
                      Mt, Ct, Gt)  # eq. (13)
    return InertialTerms(M=Mt.transpose(2, 0, 1), C=Ct.transpose(2, 0, 1), G=Gt.T)


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
    Rt = _time_last(R_PC)
    Mt = np.empty((6, 6, Rt.shape[2]))
    RB.spatial_inertia_series(Rt, float(mass), _const(I_PP), Mt)
    return Mt.transpose(2, 0, 1)


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
    ft = _time_last(f)
    fCt, mCt = np.empty(ft.shape), np.empty(ft.shape)
    # only the frame's own rotation is read (the other may be None): R_SO^T for O, R_PC for P
    in_O = frame == "O"
    R = _time_last(R_SO if in_O else R_PC)
    RB.disturbance_series(ft, _time_last(m), RB.FRAME_CODES["O" if in_O else "P"], R, R, fCt, mCt)
    return fCt.T, mCt.T


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
    xt = _time_last(x_PC)
    n = xt.shape[1]
    ft = np.zeros((3, n)) if f_ext_C is None else _time_last(f_ext_C)
    mt = np.zeros((3, n)) if m_ext_C is None else _time_last(m_ext_C)
    out = np.empty((5, 6, n))
    ship_t = RB.ShipAt(_time_last(ship.R_SO), _time_last(ship.omega_SO_S), _time_last(ship.alpha_SO_S),
                       _time_last(ship.a_SO_O))
    body = RB.RigidBody(float(mass), _const(I_PP), float(gravity), _const(frame_origin_S))
    RB.wrench_series(xt, _time_last(twist), _time_last(twist_dot), _time_last(R_PC), ship_t, body, ft, mt,
                     out)  # eqs. (9)-(16)
    return WrenchTerms(*(out[p].T for p in range(5)))


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
    Tt = _time_last(tensions)
    n = Tt.shape[1]
    c = np.asarray(controlled, dtype=np.int64)
    acc_t, react_t = np.empty((6, n)), np.empty((6 - c.size, n))
    Jt = np.ascontiguousarray(np.asarray(J_tilde, dtype=float).transpose(2, 1, 0))  # (6, n_cables, n)
    RB.forward_series(Tt, Jt, _time_last(M), _time_last(bias), c, acc_t, react_t)
    return acc_t.T, react_t.T
