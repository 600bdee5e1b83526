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
    "euler_kinematics",
    "cos_sin",
    "skew",
]


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
    """Rotation matrix and body-frame angular velocity and acceleration from Euler angles.

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


def matrix_from_euler(angles: np.ndarray) -> np.ndarray:
    """Rotation matrices ``Rz(psi) Ry(theta) Rx(phi)`` (see :func:`euler_kinematics`).

    Parameters
    ----------
    angles : ndarray, shape (..., 3)
        ``(phi, theta, psi)`` = roll, pitch, yaw in rad.

    Returns
    -------
    R : ndarray, shape (..., 3, 3)
        Maps body-frame vectors to the reference frame.
    """
    return euler_kinematics(angles)[0]


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
