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

__all__ = ["CableKinematics", "cable_kinematics", "global_jacobian"]


@dataclass(frozen=True)
class CableKinematics:
    """Cable geometry over a time series, in C.

    Attributes
    ----------
    vectors : ndarray, shape (n_steps, n_cables, 3)
        l_i, platform anchor to frame anchor, m (eq. 2).
    lengths : ndarray, shape (n_steps, n_cables)
        |l_i|, m.
    units : ndarray, shape (n_steps, n_cables, 3)
        u_i = l_i / |l_i|.
    anchors_C : ndarray, shape (n_steps, n_cables, 3)
        R_PC p_i, the platform anchors relative to P's origin, in C, m.
    J_tilde : ndarray, shape (n_steps, n_cables, 6)
        J~ (eq. 6): rows (u_i^T, ((R_PC p_i) x u_i)^T).
    length_rates : ndarray, shape (n_steps, n_cables) or None
        l_i' = -J~ (v_PC, omega_PC) (eq. 5), m/s, when a twist was given.
    """

    vectors: np.ndarray
    lengths: np.ndarray
    units: np.ndarray
    anchors_C: np.ndarray
    J_tilde: np.ndarray
    length_rates: np.ndarray | None


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
    # R_PC p_i for every step and cable: (n, m, 3)
    r = np.einsum("nij,mj->nmi", R_PC, np.asarray(p_P, dtype=float))
    l_vec = np.asarray(c_C, dtype=float)[None, :, :] - x_PC[:, None, :] - r  # eq. (2)
    lengths = np.sqrt(np.einsum("nmi,nmi->nm", l_vec, l_vec))
    with np.errstate(invalid="ignore", divide="ignore"):
        u = l_vec / lengths[:, :, None]
    J = np.empty(l_vec.shape[:2] + (6,))
    J[:, :, :3] = u
    J[:, :, 3:] = np.cross(r, u)  # eq. (6)
    rates = None
    if twist is not None:
        rates = -np.einsum("nmk,nk->nm", J, np.asarray(twist, dtype=float))  # eq. (5)
    return CableKinematics(l_vec, lengths, u, r, J, rates)


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
    J = np.empty_like(J_tilde)
    J[..., :3] = np.einsum("nij,nmj->nmi", R_SO, J_tilde[..., :3])
    J[..., 3:] = np.einsum("nij,nmj->nmi", R_SO, J_tilde[..., 3:])
    return J
