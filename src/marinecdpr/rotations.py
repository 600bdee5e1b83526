"""Rotations in the marine (SNAME) convention, vectorised over time.

Convention (see ``docs/conventions.md``): a rotation from three angles
``(roll, pitch, yaw) = (phi, theta, psi)`` in radians is

    R = Rz(psi) @ Ry(theta) @ Rx(phi),

which maps vectors from the rotated (body) frame to the reference frame. The
same convention is used for the ship (R_SO = R_S^O) and for the platform's
orientation in the robot frame C (R_PC = R_P^C, angles ``(rx, ry, rz)``).

Angular velocity and acceleration follow exactly from the angles and their
rates: no small-angle approximation (MODEL_NOTES, "Frames and conventions").
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "matrix_from_euler",
    "body_rates_from_euler",
    "skew",
]


def matrix_from_euler(angles: np.ndarray) -> np.ndarray:
    """Rotation matrices ``Rz(psi) Ry(theta) Rx(phi)``.

    Parameters
    ----------
    angles : ndarray, shape (..., 3)
        ``(phi, theta, psi)`` = roll, pitch, yaw in rad.

    Returns
    -------
    R : ndarray, shape (..., 3, 3)
        Maps body-frame vectors to the reference frame.
    """
    angles = np.asarray(angles, dtype=float)
    c = np.cos(angles)
    s = np.sin(angles)
    cph, cth, cps = c[..., 0], c[..., 1], c[..., 2]
    sph, sth, sps = s[..., 0], s[..., 1], s[..., 2]
    R = np.empty(angles.shape[:-1] + (3, 3))
    R[..., 0, 0] = cps * cth
    R[..., 0, 1] = cps * sth * sph - sps * cph
    R[..., 0, 2] = cps * sth * cph + sps * sph
    R[..., 1, 0] = sps * cth
    R[..., 1, 1] = sps * sth * sph + cps * cph
    R[..., 1, 2] = sps * sth * cph - cps * sph
    R[..., 2, 0] = -sth
    R[..., 2, 1] = cth * sph
    R[..., 2, 2] = cth * cph
    return R


def body_rates_from_euler(
    angles: np.ndarray, rates: np.ndarray, accels: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Angular velocity and acceleration in the body frame from Euler angles.

    For ``R = Rz(psi) Ry(theta) Rx(phi)``, ``dR/dt = R [omega_b x]`` with

        omega_b = (phi' - s_th psi',
                   c_ph th' + s_ph c_th psi',
                  -s_ph th' + c_ph c_th psi')

    and ``alpha_b = d(omega_b)/dt`` differentiated exactly. Because
    ``d(R omega_b)/dt = R alpha_b``, the same vector expressed in the reference
    frame is ``R @ alpha_b``.

    Parameters
    ----------
    angles, rates, accels : ndarray, shape (..., 3)
        ``(phi, theta, psi)`` in rad, their first (rad/s) and second (rad/s^2)
        time derivatives.

    Returns
    -------
    omega_b : ndarray, shape (..., 3)
        Angular velocity of the body, in the body frame, rad/s.
    alpha_b : ndarray, shape (..., 3)
        Angular acceleration of the body, in the body frame, rad/s^2.
    """
    angles = np.asarray(angles, dtype=float)
    rates = np.asarray(rates, dtype=float)
    accels = np.asarray(accels, dtype=float)
    sph, cph = np.sin(angles[..., 0]), np.cos(angles[..., 0])
    sth, cth = np.sin(angles[..., 1]), np.cos(angles[..., 1])
    dph, dth, dps = rates[..., 0], rates[..., 1], rates[..., 2]
    ddph, ddth, ddps = accels[..., 0], accels[..., 1], accels[..., 2]
    omega = np.empty(np.broadcast_shapes(angles.shape, rates.shape))
    omega[..., 0] = dph - sth * dps
    omega[..., 1] = cph * dth + sph * cth * dps
    omega[..., 2] = -sph * dth + cph * cth * dps
    alpha = np.empty_like(omega)
    alpha[..., 0] = ddph - sth * ddps - cth * dth * dps
    alpha[..., 1] = (
        cph * ddth - sph * dph * dth + sph * cth * ddps
        + cph * cth * dph * dps - sph * sth * dth * dps
    )
    alpha[..., 2] = (
        -sph * ddth - cph * dph * dth + cph * cth * ddps
        - sph * cth * dph * dps - cph * sth * dth * dps
    )
    return omega, alpha


def skew(v: np.ndarray) -> np.ndarray:
    """Cross-product matrices ``[v x]``.

    Parameters
    ----------
    v : ndarray, shape (..., 3)

    Returns
    -------
    S : ndarray, shape (..., 3, 3)
        ``S @ a == np.cross(v, a)``.
    """
    v = np.asarray(v, dtype=float)
    S = np.zeros(v.shape + (3,))
    S[..., 0, 1] = -v[..., 2]
    S[..., 0, 2] = v[..., 1]
    S[..., 1, 0] = v[..., 2]
    S[..., 1, 2] = -v[..., 0]
    S[..., 2, 0] = -v[..., 1]
    S[..., 2, 1] = v[..., 0]
    return S
