"""Ship (base) motion as time series: the 6-DOF record and its exact derivatives.

The ship's generalised coordinates are ``eta = (x, y, z, roll, pitch, yaw)``:
the position of S's origin in O (surge, sway, heave; m) and the SNAME Euler
angles of R_SO = R_S^O = Rz(yaw) Ry(pitch) Rx(roll) (rad). Every source of base
motion (sinusoids here; sea spectra and records later) produces ``eta`` and its
first two time derivatives; :func:`ship_motion` turns them into the quantities the
dynamics need.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from marinecdpr.geometry.rotations import euler_kinematics

__all__ = ["ShipMotion", "ship_motion", "still_ship"]


@dataclass(frozen=True)
class ShipMotion:
    """The ship's motion over a time series (all arrays share ``n_steps``).

    Attributes
    ----------
    eta, eta_dot, eta_ddot : ndarray, shape (n_steps, 6)
        ``(x, y, z, roll, pitch, yaw)`` of S in O (m, rad) and derivatives.
    R_SO : ndarray, shape (n_steps, 3, 3)
        R_S^O: maps S-frame vectors to O.
    omega_SO_S : ndarray, shape (n_steps, 3)
        Ship angular velocity omega_SO expressed in S, rad/s.
    alpha_SO_S : ndarray, shape (n_steps, 3)
        Ship angular acceleration expressed in S, rad/s^2.
    """

    eta: np.ndarray
    eta_dot: np.ndarray
    eta_ddot: np.ndarray
    R_SO: np.ndarray
    omega_SO_S: np.ndarray
    alpha_SO_S: np.ndarray

    @property
    def x_SO_O(self) -> np.ndarray:
        """Position of S's origin in O, shape (n_steps, 3), m."""
        return self.eta[:, :3]

    @property
    def a_SO_O(self) -> np.ndarray:
        """Acceleration of S's origin in O, shape (n_steps, 3), m/s^2."""
        return self.eta_ddot[:, :3]

    def take(self, rows) -> "ShipMotion":
        """The motion at some of the samples: ``rows`` indexes the time axis (a slice, an
        integer array or a mask)."""
        return ShipMotion(eta=self.eta[rows], eta_dot=self.eta_dot[rows], eta_ddot=self.eta_ddot[rows],
                          R_SO=self.R_SO[rows],
                          omega_SO_S=self.omega_SO_S[rows], alpha_SO_S=self.alpha_SO_S[rows])

    @property
    def is_still(self) -> bool:
        return not (np.any(self.eta) or np.any(self.eta_dot) or np.any(self.eta_ddot))


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
    return ShipMotion(eta=eta, eta_dot=eta_dot, eta_ddot=eta_ddot, R_SO=R, omega_SO_S=omega, alpha_SO_S=alpha)


def still_ship(n_steps: int) -> ShipMotion:
    """A ship at rest with S on O, for ``n_steps`` samples (the fixed-base model)."""
    z = np.zeros((n_steps, 6))
    return ship_motion(z, z, z)


