"""Cable kinematics over a whole time series (the paper's eqs. 1-6 and 14).

All vectors are in the robot frame C unless a name says otherwise. For cable i,

    l_i = c_i - (x_PC + R_PC p_i)                      (eq. 2)
    u_i = l_i / |l_i|        (from the platform anchor towards the frame anchor)
    l_i' = -J~_i . (v_PC, omega_PC)                    (eqs. 4-5)
    J~_i = (u_i^T, ((R_PC p_i) x u_i)^T)               (eq. 6)

and the cable pulls the platform with t_i u_i, so the cables' wrench on the
platform about its centre of mass is J~^T T (the structure equation).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from marinecdpr.geometry import _vec as vec

__all__ = ["CableKinematics", "cable_kinematics", "global_jacobian"]


@dataclass(frozen=True)
class CableKinematics:
    """Cable geometry over a time series, in C.

    Attributes
    ----------
    lengths : ndarray, shape (n_steps, n_cables)
        |l_i|, m.
    anchors_C : ndarray, shape (n_steps, n_cables, 3)
        R_PC p_i, the platform anchors relative to P's origin, in C, m.
    J_tilde : ndarray, shape (n_steps, n_cables, 6)
        J~ (eq. 6): rows (u_i^T, ((R_PC p_i) x u_i)^T).
    length_rates : ndarray, shape (n_steps, n_cables) or None
        l_i' = -J~ (v_PC, omega_PC) (eq. 5), m/s, when a twist was given.
    """

    lengths: np.ndarray
    anchors_C: np.ndarray
    J_tilde: np.ndarray
    length_rates: np.ndarray | None

    @property
    def units(self) -> np.ndarray:
        """u_i = l_i / |l_i|, shape (n_steps, n_cables, 3) (the first columns of J~)."""
        return self.J_tilde[:, :, :3]

    @property
    def vectors(self) -> np.ndarray:
        """l_i, platform anchor to frame anchor, shape (n_steps, n_cables, 3), m (eq. 2)."""
        return self.units * self.lengths[:, :, None]


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
    u = vec.scale(inv, l_vec)
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
