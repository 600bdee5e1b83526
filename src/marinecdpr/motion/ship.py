"""Ship (base) motion as time series: the 6-DOF record and its exact derivatives.

The ship's generalised coordinates are ``eta = (x, y, z, roll, pitch, yaw)``:
the position of S's origin in O (surge, sway, heave; m) and the SNAME Euler
angles of R_SO = R_S^O = Rz(yaw) Ry(pitch) Rx(roll) (rad). Every source of base
motion (sinusoids here; sea spectra and records later) produces ``eta`` and its
first two time derivatives; :func:`ship_motion` turns them into the quantities the
dynamics need.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property, partial

import numpy as np

from marinecdpr.geometry.rotations import euler_from_matrix, euler_kinematics

__all__ = ["ShipMotion", "ship_motion", "still_ship", "frame_axes", "frame_origin_in_axes", "in_frame_axes",
           "body_motion", "body_coordinates"]


@dataclass(frozen=True, eq=False)
class ShipMotion:
    """The ship's motion over a time series (all arrays share ``n_steps``).

    Attributes
    ----------
    x_SO_O, v_SO_O, a_SO_O : ndarray, shape (n_steps, 3)
        Position of S's origin in O, its velocity and acceleration, m, m/s, m/s^2.
    R_SO : ndarray, shape (n_steps, 3, 3)
        R_S^O: maps S-frame vectors to O.
    omega_SO_S : ndarray, shape (n_steps, 3)
        Ship angular velocity omega_SO expressed in S, rad/s.
    alpha_SO_S : ndarray, shape (n_steps, 3)
        Ship angular acceleration expressed in S, rad/s^2.
    eta, eta_dot, eta_ddot : ndarray, shape (n_steps, 6)
        ``(x, y, z, roll, pitch, yaw)`` of S in O (m, rad) and derivatives (properties: a
        body's motion, :func:`body_motion`, derives its Euler angles the first time they are
        asked for).
    """

    x_SO_O: np.ndarray
    v_SO_O: np.ndarray
    a_SO_O: np.ndarray
    R_SO: np.ndarray
    omega_SO_S: np.ndarray
    alpha_SO_S: np.ndarray
    # (eta, eta_dot, eta_ddot), or a function of no arguments that gives them
    _coordinates: object = field(repr=False)

    @cached_property
    def _eta(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        c = self._coordinates
        return c() if callable(c) else c

    @property
    def eta(self) -> np.ndarray:
        return self._eta[0]

    @property
    def eta_dot(self) -> np.ndarray:
        return self._eta[1]

    @property
    def eta_ddot(self) -> np.ndarray:
        return self._eta[2]

    def take(self, rows) -> "ShipMotion":
        """The motion at some of the samples: ``rows`` indexes the time axis (a slice, an
        integer array or a mask)."""
        c = self._coordinates
        if callable(c) and "_eta" not in self.__dict__:  # still to be derived: from the whole series
            c = partial(_rows_of, self, rows)
        else:
            c = tuple(e[rows] for e in self._eta)
        return ShipMotion(self.x_SO_O[rows], self.v_SO_O[rows], self.a_SO_O[rows], self.R_SO[rows],
                          self.omega_SO_S[rows], self.alpha_SO_S[rows], c)

    @property
    def is_still(self) -> bool:
        return not (np.any(self.eta) or np.any(self.eta_dot) or np.any(self.eta_ddot))


def _rows_of(motion: ShipMotion, rows) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    return tuple(e[rows] for e in motion._eta)


def ship_motion(eta: np.ndarray, eta_dot: np.ndarray, eta_ddot: np.ndarray) -> ShipMotion:
    """Rotation, angular velocity and acceleration of the ship from its coordinates.

    Parameters
    ----------
    eta, eta_dot, eta_ddot : ndarray, shape (n_steps, 6)
        ``(x, y, z, roll, pitch, yaw)`` of S in O in m and rad, and their first
        and second time derivatives.

    Returns
    -------
    ShipMotion
    """
    eta = np.asarray(eta, dtype=float)
    eta_dot = np.asarray(eta_dot, dtype=float)
    eta_ddot = np.asarray(eta_ddot, dtype=float)
    R, omega, alpha = euler_kinematics(eta[:, 3:], eta_dot[:, 3:], eta_ddot[:, 3:])
    return ShipMotion(eta[:, :3], eta_dot[:, :3], eta_ddot[:, :3], R, omega, alpha, (eta, eta_dot, eta_ddot))


def still_ship(n_steps: int) -> ShipMotion:
    """A ship at rest with S on O, for ``n_steps`` samples (the fixed-base model)."""
    z = np.zeros((n_steps, 6))
    return ship_motion(z, z, z)


def frame_axes(orientation_deg) -> np.ndarray:
    """R_SC (3, 3): the robot frame C's axes in S from ``ship.frame_orientation_deg``
    (roll, pitch, yaw of C in S, deg, as eta's: R_SC = Rz(yaw) Ry(pitch) Rx(roll))."""
    return np.array(euler_kinematics(np.radians(np.asarray(orientation_deg, dtype=float))).R)


def frame_origin_in_axes(origin_S, orientation_deg) -> np.ndarray:
    """C's origin in S' (S's origin, C's axes: :func:`in_frame_axes`), shape (3,), m:
    R_SC^T times its position in S."""
    return frame_axes(orientation_deg).T @ np.asarray(origin_S, dtype=float)


def in_frame_axes(ship: ShipMotion, R_SC: np.ndarray) -> ShipMotion:
    """The ship's motion as a frame turned on it by R_SC sees it: the motion of S', which has
    S's origin and C's axes, so that the models (which take C's axes for the ship's) hold for
    a frame that stands tilted or turned on the hull.

    S' moves as S: its origin's position (eta's first three) is S's; R_S'O = R_SO R_SC; its
    angular velocity and acceleration in S' are R_SC^T times S's. eta' carries the Euler
    angles of R_S'O (:func:`body_coordinates`), and the motion's rotation, angular velocity
    and acceleration are :func:`ship_motion`'s of eta' (as MuJoCo's ship, driven by eta',
    has them).

    Parameters
    ----------
    ship : ShipMotion
    R_SC : ndarray, shape (3, 3)
        C's axes in S (:func:`frame_axes`).

    Returns
    -------
    ShipMotion
        The same ship where R_SC is the identity.
    """
    R_SC = np.asarray(R_SC, dtype=float)
    if np.array_equal(R_SC, np.eye(3)):
        return ship
    return ship_motion(*body_coordinates(ship.x_SO_O, ship.v_SO_O, ship.a_SO_O, ship.R_SO @ R_SC,
                                         ship.omega_SO_S @ R_SC, ship.alpha_SO_S @ R_SC))  # rows: (R_SC^T w)^T


def body_motion(x_O: np.ndarray, v_O: np.ndarray, a_O: np.ndarray, R_BO: np.ndarray, omega_B: np.ndarray,
                alpha_B: np.ndarray) -> ShipMotion:
    """A rigid body's motion as a :class:`ShipMotion` (the body in the ship's place), from its
    origin's motion and its rotation, angular velocity and acceleration, which it keeps as
    given; its ``eta`` (the Euler angles of R_BO and their rates, :func:`body_coordinates`)
    is derived the first time it is asked for (a prescribed body such as MuJoCo's ship is
    driven by it; the models take the rotation and its rates themselves).

    Parameters
    ----------
    x_O, v_O, a_O : ndarray, shape (n_steps, 3)
        The body's origin in O, its velocity and acceleration, m, m/s, m/s^2.
    R_BO : ndarray, shape (n_steps, 3, 3)
        R_B^O: the body's axes in O.
    omega_B, alpha_B : ndarray, shape (n_steps, 3)
        Its angular velocity (rad/s) and acceleration (rad/s^2) relative to O, in the body's axes.
    """
    return ShipMotion(x_O, v_O, a_O, R_BO, omega_B, alpha_B,
                      partial(body_coordinates, x_O, v_O, a_O, R_BO, omega_B, alpha_B, solve=False))


def body_coordinates(x_O: np.ndarray, v_O: np.ndarray, a_O: np.ndarray, R_BO: np.ndarray, omega_B: np.ndarray,
                     alpha_B: np.ndarray, *, solve: bool = True) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A rigid body's generalised coordinates as a ship's, eta = (x, y, z, roll, pitch, yaw),
    and their first two time derivatives (arguments as :func:`body_motion`'s).

    The angles are the Euler angles of R_BO (roll and yaw unwrapped over time), their exact
    rates and accelerations from omega_b = E(angles) rates and alpha_b = E rates' + (dE/dt)
    rates, so that :func:`ship_motion` of eta gives back R_BO, omega and alpha.

    Parameters
    ----------
    solve : bool
        True: E's systems solved by LAPACK, one 3 x 3 system a sample (a frame turned on the
        ship, :func:`in_frame_axes`, whose numbers stay those it has always had); False: E's
        inverse written out (:func:`_euler_rates`), the same to rounding and 5x faster (a
        carried frame's C, :func:`body_motion`, whose angles a run derives at 30 001 half-steps
        of 15 s).

    Returns
    -------
    eta, eta_dot, eta_ddot : ndarray, shape (n_steps, 6)
        m, rad and their rates.
    """
    angles = euler_from_matrix(R_BO)
    angles[:, [0, 2]] = np.unwrap(angles[:, [0, 2]], axis=0)  # roll and yaw continuous over time
    if solve:
        rates, accels = _euler_rates_solved(angles, omega_B, alpha_B)
    else:
        rates, accels = _euler_rates(angles, omega_B, alpha_B)
    eta = np.concatenate([x_O, angles], axis=1)
    eta_dot = np.concatenate([v_O, rates], axis=1)
    eta_ddot = np.concatenate([a_O, accels], axis=1)
    return eta, eta_dot, eta_ddot


def _euler_rates_solved(angles: np.ndarray, w: np.ndarray, a: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """:func:`body_coordinates`' Euler rates and accelerations (n, 3), rad/s and rad/s^2, of the
    angles (n, 3) whose body turns at w and accelerates at a (n, 3, in the body's axes): E's
    systems solved by LAPACK."""
    phi, theta = angles[:, 0], angles[:, 1]
    c1, s1, c2, s2 = np.cos(phi), np.sin(phi), np.cos(theta), np.sin(theta)
    E = np.zeros((phi.size, 3, 3))  # omega_b = E (phi', theta', psi')
    E[:, 0, 0], E[:, 0, 2] = 1.0, -s2
    E[:, 1, 1], E[:, 1, 2] = c1, s1 * c2
    E[:, 2, 1], E[:, 2, 2] = -s1, c1 * c2
    rates = np.linalg.solve(E, w[:, :, None])[:, :, 0]
    bias = euler_kinematics(angles, rates, np.zeros_like(rates)).alpha_b  # (dE/dt) rates
    return rates, np.linalg.solve(E, (a - bias)[:, :, None])[:, :, 0]


def _euler_rates(angles: np.ndarray, w: np.ndarray, a: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """:func:`_euler_rates_solved`'s rates and accelerations with E's inverse written out: for
    omega_b = E (phi', theta', psi'), with m = s_phi w_y + c_phi w_z = c_theta psi',

        psi' = m / c_theta,   theta' = c_phi w_y - s_phi w_z,   phi' = w_x + s_theta psi',

    and the accelerations the same of alpha_b less (dE/dt) rates,

        (-c_theta theta' psi',
         -s_phi phi' theta' + c_phi c_theta phi' psi' - s_phi s_theta theta' psi',
         -c_phi phi' theta' - s_phi c_theta phi' psi' - c_phi s_theta theta' psi')."""
    phi, theta = angles[:, 0], angles[:, 1]
    c1, s1, c2, s2 = np.cos(phi), np.sin(phi), np.cos(theta), np.sin(theta)

    def inverse(b: np.ndarray) -> np.ndarray:  # E^-1 b, rows of b
        yaw_rate = (s1 * b[:, 1] + c1 * b[:, 2]) / c2
        return np.stack([b[:, 0] + s2 * yaw_rate, c1 * b[:, 1] - s1 * b[:, 2], yaw_rate], axis=1)

    rates = inverse(w)
    p, q, r = rates[:, 0], rates[:, 1], rates[:, 2]
    bias = np.stack([-c2 * q * r, -s1 * p * q + c1 * c2 * p * r - s1 * s2 * q * r,
                     -c1 * p * q - s1 * c2 * p * r - c1 * s2 * q * r], axis=1)
    return rates, inverse(a - bias)
