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

from typing import NamedTuple

import numpy as np
from numba import njit

__all__ = [
    "matrix_from_euler",
    "euler_from_matrix",
    "euler_kinematics",
    "euler_step",
    "skew",
    "matrix_from_quaternion_step",
    "matrix_about_y_step",
    "euler_from_matrix_step",
    "quaternion_from_matrix",
    "angle_rate_matrix",
    "rotation_and_rates",
]


@njit(cache=True, inline="always")
def _matrix_values(cph, sph, cth, sth, cps, sps):
    """R = Rz(psi) Ry(theta) Rx(phi) (9 entries, row by row) from the angles' cosines and
    sines: the one implementation of the rotation matrix."""
    return (cps * cth, cps * sth * sph - sps * cph, cps * sth * cph + sps * sph,
            sps * cth, sps * sth * sph + cps * cph, sps * sth * cph - cps * sph,
            -sth, cth * sph, cth * cph)


@njit(cache=True, inline="always")
def _angle_rate_columns(cy, sy, cz, sz):
    """E's columns (rx', ry', rz' -> omega in the reference frame) for R = Rz(rz) Ry(ry)
    Rx(rx), from the cosines and sines of ry and rz: R e_x, Rz e_y, e_z (E does not
    depend on rx)."""
    return (cz * cy, sz * cy, -sy), (-sz, cz, 0.0), (0.0, 0.0, 1.0)


@njit(cache=True, inline="always")
def rotation_and_rates(rx, ry, rz):
    """R = Rz(rz) Ry(ry) Rx(rx) by rows (three 3-tuples) and the columns of E (omega = E
    angles', :func:`angle_rate_matrix`), from the angles (rad)."""
    c1, s1 = np.cos(rx), np.sin(rx)
    c2, s2 = np.cos(ry), np.sin(ry)
    c3, s3 = np.cos(rz), np.sin(rz)
    v = _matrix_values(c1, s1, c2, s2, c3, s3)
    return ((v[0], v[1], v[2]), (v[3], v[4], v[5]), (v[6], v[7], v[8])), _angle_rate_columns(c2, s2, c3, s3)


@njit(cache=True)
def angle_rate_matrix(angles, E):
    """E(angles) such that omega = E angles' for R = Rz(rz) Ry(ry) Rx(rx), written in place.

    Parameters
    ----------
    angles : ndarray, shape (3,)
        (rx, ry, rz), rad.
    E : ndarray, shape (3, 3)
        Written: columns R e_x, Rz(rz) e_y, e_z; maps the angles' rates (rad/s) to the
        angular velocity in the reference frame (C for the platform), rad/s.
    """
    cols = _angle_rate_columns(np.cos(angles[1]), np.sin(angles[1]), np.cos(angles[2]), np.sin(angles[2]))
    for j in range(3):
        for a in range(3):
            E[a, j] = cols[j][a]


@njit(cache=True, inline="always")
def _euler_values(cph, sph, cth, sth, cps, sps, dph, dth, dps, ddph, ddth, ddps):
    """R (9 entries, row by row), omega_b (3) and alpha_b (3) from the angles' cosines and
    sines and their rates: the one implementation of :func:`euler_kinematics`' formulas."""
    return _matrix_values(cph, sph, cth, sth, cps, sps) + (
            dph - sth * dps,
            cph * dth + sph * cth * dps,
            -sph * dth + cph * cth * dps,
            ddph - sth * ddps - cth * dth * dps,
            (cph * ddth - sph * dph * dth + sph * cth * ddps
             + cph * cth * dph * dps - sph * sth * dth * dps),
            (-sph * ddth - cph * dph * dth + cph * cth * ddps
             - sph * cth * dph * dps - cph * sth * dth * dps))


@njit(cache=True)
def euler_step(ang, rate, acc, R, omega, alpha):
    """:func:`euler_kinematics` at one instant, compiled (the closed loop's sensors call it).

    ang, rate, acc: (3,) rad, rad/s, rad/s^2. Writes R (3, 3), omega (3,), alpha (3,).
    """
    v = _euler_values(np.cos(ang[0]), np.sin(ang[0]), np.cos(ang[1]), np.sin(ang[1]), np.cos(ang[2]),
                      np.sin(ang[2]), rate[0], rate[1], rate[2], acc[0], acc[1], acc[2])
    for i in range(3):
        for j in range(3):
            R[i, j] = v[3 * i + j]
        omega[i] = v[9 + i]
        alpha[i] = v[12 + i]


@njit(cache=True, inline="always")
def matrix_about_y_step(theta, R):
    """R (3, 3) = Ry(theta) (a planar robot's orientation, theta_y in rad), written in place."""
    c, s = np.cos(theta), np.sin(theta)
    R[0, 0], R[0, 1], R[0, 2] = c, 0.0, s
    R[1, 0], R[1, 1], R[1, 2] = 0.0, 1.0, 0.0
    R[2, 0], R[2, 1], R[2, 2] = -s, 0.0, c


@njit(cache=True)
def matrix_from_quaternion_step(q, R):
    """R (3, 3) of a unit quaternion q (4,) = (w, x, y, z), written in place."""
    qw, qx, qy, qz = q[0], q[1], q[2], q[3]
    R[0, 0] = 1 - 2 * (qy * qy + qz * qz)
    R[0, 1] = 2 * (qx * qy - qz * qw)
    R[0, 2] = 2 * (qx * qz + qy * qw)
    R[1, 0] = 2 * (qx * qy + qz * qw)
    R[1, 1] = 1 - 2 * (qx * qx + qz * qz)
    R[1, 2] = 2 * (qy * qz - qx * qw)
    R[2, 0] = 2 * (qx * qz - qy * qw)
    R[2, 1] = 2 * (qy * qz + qx * qw)
    R[2, 2] = 1 - 2 * (qx * qx + qy * qy)


@njit(cache=True)
def euler_from_matrix_step(R, out):
    """The angles (phi, theta, psi) (rad) with R = Rz(psi) Ry(theta) Rx(phi), written to out (3,)."""
    out[0] = np.arctan2(R[2, 1], R[2, 2])
    out[1] = np.arcsin(min(1.0, max(-1.0, -R[2, 0])))
    out[2] = np.arctan2(R[1, 0], R[0, 0])


def quaternion_from_matrix(R: np.ndarray) -> np.ndarray:
    """The unit quaternion (4,) (w, x, y, z) of a rotation matrix R (3, 3) (Shepperd's method)."""
    tr = np.trace(R)
    if tr > 0:
        s = 2.0 * np.sqrt(tr + 1.0)
        q = [0.25 * s, (R[2, 1] - R[1, 2]) / s, (R[0, 2] - R[2, 0]) / s, (R[1, 0] - R[0, 1]) / s]
    else:
        i = int(np.argmax(np.diag(R)))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = 2.0 * np.sqrt(1.0 + R[i, i] - R[j, j] - R[k, k])
        q = [0.0] * 4
        q[0] = (R[k, j] - R[j, k]) / s
        q[1 + i] = 0.25 * s
        q[1 + j] = (R[j, i] + R[i, j]) / s
        q[1 + k] = (R[k, i] + R[i, k]) / s
    q = np.asarray(q)
    return q / np.linalg.norm(q)


@njit(cache=True)
def _euler_series(ang, rate, acc, Rt, wt, at):
    """:func:`euler_step` for every row of ang, rate, acc (n, 3), written time-last: Rt
    (3, 3, n), wt, at (3, n). A row with the previous row's angles reuses its cosines and
    sines (a constant orientation costs no trigonometry)."""
    last0, last1, last2 = np.nan, np.nan, np.nan
    cph = sph = cth = sth = cps = sps = 0.0
    for k in range(ang.shape[0]):
        a0, a1, a2 = ang[k, 0], ang[k, 1], ang[k, 2]
        if not (a0 == last0 and a1 == last1 and a2 == last2):
            cph, sph, cth, sth, cps, sps = np.cos(a0), np.sin(a0), np.cos(a1), np.sin(a1), np.cos(a2), np.sin(a2)
            last0, last1, last2 = a0, a1, a2
        v = _euler_values(cph, sph, cth, sth, cps, sps, rate[k, 0], rate[k, 1], rate[k, 2],
                          acc[k, 0], acc[k, 1], acc[k, 2])
        for i in range(3):
            for j in range(3):
                Rt[i, j, k] = v[3 * i + j]
            wt[i, k] = v[9 + i]
            at[i, k] = v[12 + i]


class EulerKinematics(NamedTuple):
    """:func:`euler_kinematics`'s result: R (..., 3, 3), and omega_b, alpha_b (..., 3) in the
    body frame, rad/s and rad/s^2 (None without rates)."""

    R: np.ndarray
    omega_b: np.ndarray | None
    alpha_b: np.ndarray | None


def euler_kinematics(
    angles: np.ndarray, rates: np.ndarray | None = None, accels: np.ndarray | None = None
) -> EulerKinematics:
    """Rotation matrix and body-frame angular velocity and acceleration from Euler angles.

    ``R = Rz(psi) Ry(theta) Rx(phi)`` maps body-frame vectors to the reference
    frame, and ``dR/dt = R [omega_b x]`` with

        omega_b = (phi' - s_th psi',
                   c_ph th' + s_ph c_th psi',
                  -s_ph th' + c_ph c_th psi')

    and ``alpha_b = d(omega_b)/dt`` differentiated exactly. Because
    ``d(R omega_b)/dt = R alpha_b``, the same vectors expressed in the reference
    frame are ``R @ omega_b`` and ``R @ alpha_b``. Computed by a compiled loop over the
    samples (:func:`euler_step` per sample); ``tests/vectorised.py`` keeps the former
    numpy implementation as the reference.

    Parameters
    ----------
    angles : ndarray, shape (..., 3)
        ``(phi, theta, psi)`` = roll, pitch, yaw, rad.
    rates, accels : ndarray, shape (..., 3), optional
        First (rad/s) and second (rad/s^2) time derivatives of the angles.

    Returns
    -------
    EulerKinematics
        R : ndarray, shape (..., 3, 3); omega_b, alpha_b : ndarray, shape (..., 3), or None without rates:
        rad/s and rad/s^2, in the body frame. Views of time-last buffers (R[..., i, j] is
        contiguous).
    """
    angles = np.asarray(angles, dtype=float)
    with_rates = rates is not None
    rates = np.zeros_like(angles) if rates is None else np.asarray(rates, dtype=float)
    accels = np.zeros_like(rates) if accels is None else np.asarray(accels, dtype=float)
    shape = np.broadcast_shapes(angles.shape, rates.shape, accels.shape)[:-1]

    def rows(a: np.ndarray) -> np.ndarray:
        return np.ascontiguousarray(np.broadcast_to(a, shape + (3,)).reshape(-1, 3))

    n = int(np.prod(shape, dtype=np.int64))
    Rt, wt, at = np.empty((3, 3, n)), np.empty((3, n)), np.empty((3, n))
    _euler_series(rows(angles), rows(rates), rows(accels), Rt, wt, at)
    R = np.moveaxis(Rt.reshape((3, 3) + shape), (0, 1), (-2, -1))
    if not with_rates:
        return EulerKinematics(R=R, omega_b=None, alpha_b=None)
    return EulerKinematics(R=R, omega_b=np.moveaxis(wt.reshape((3,) + shape), 0, -1),
                           alpha_b=np.moveaxis(at.reshape((3,) + shape), 0, -1))


def euler_from_matrix(R: np.ndarray) -> np.ndarray:
    """The angles (phi, theta, psi) with R = Rz(psi) Ry(theta) Rx(phi) (the inverse of
    :func:`matrix_from_euler` for |theta| < 90 deg), vectorised.

    Parameters
    ----------
    R : ndarray, shape (..., 3, 3)

    Returns
    -------
    ndarray, shape (..., 3)
        Roll, pitch, yaw, rad (roll and yaw in (-pi, pi]).
    """
    R = np.asarray(R, dtype=float)
    return np.stack([np.arctan2(R[..., 2, 1], R[..., 2, 2]), np.arcsin(np.clip(-R[..., 2, 0], -1.0, 1.0)),
                     np.arctan2(R[..., 1, 0], R[..., 0, 0])], axis=-1)


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
    return euler_kinematics(angles).R


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
