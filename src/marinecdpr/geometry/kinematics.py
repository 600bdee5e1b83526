"""Cable kinematics (the paper's eqs. 1-6 and 14), compiled per step and over time series.

All vectors are in the robot frame C unless a name says otherwise. For cable i,

    l_i = c_i - (x_PC + R_PC p_i)                      (eq. 2)
    u_i = l_i / |l_i|        (from the platform anchor towards the frame anchor)
    l_i' = -J~_i . (v_PC, omega_PC)                    (eqs. 4-5)
    J~_i = (u_i^T, ((R_PC p_i) x u_i)^T)               (eq. 6)

and the cable pulls the platform with t_i u_i, so the cables' wrench on the
platform about its centre of mass is J~^T T (the structure equation).

The model is written once, as numba-compiled functions of one step: one cable
(:func:`cable_geometry`, eqs. 2 and 6; :func:`length_rate`, eq. 5), every cable
(:func:`cables_step`, :func:`length_rates_step`) and J~'s rows in O
(:func:`rows_in_O_step`, eq. 14). The closed loop calls them step by step
(:func:`marinecdpr.control.step.control_step` calls :func:`cables_step`); the array functions
(:func:`cable_kinematics`, :func:`global_jacobian`) run them in compiled loops over the
steps. Those take and return arrays shaped ``(n_steps, ...)``; the loops hand each step
views of time-last buffers (the per-step functions are inlined there, so a loop over the
steps runs as one piece of machine code), and the returned arrays are views of those
buffers (``docs/conventions.md``, "Array layout").
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

__all__ = ["CableKinematics", "cable_kinematics", "global_jacobian", "cable_geometry", "length_rate",
           "cables_step", "length_rates_step", "rows_in_O_step"]

_cache = True


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


# ------------------------------------------------------------------- one step, compiled


@njit(cache=_cache, inline="always")
def cable_geometry(x, R_PC, c, p):
    """One cable at one pose (eqs. 2, 6): its length, its row of J~ and R_PC p_i.

    Parameters
    ----------
    x : ndarray, shape (3,)
        x_PC: position of P's origin in C, m.
    R_PC : ndarray, shape (3, 3)
        R_P^C.
    c : ndarray, shape (3,)
        The frame anchor c_i in C, m.
    p : ndarray, shape (3,)
        The platform anchor p_i in P, m.

    Returns
    -------
    length : float
        |l_i|, m; zero where the anchors coincide.
    row : tuple of 6 floats
        J~_i = (u_i^T, ((R_PC p_i) x u_i)^T); NaN where the anchors coincide.
    anchor : tuple of 3 floats
        R_PC p_i, the platform anchor relative to P's origin, in C, m.
    """
    # R_PC p_i
    r0 = R_PC[0, 0] * p[0] + R_PC[0, 1] * p[1] + R_PC[0, 2] * p[2]
    r1 = R_PC[1, 0] * p[0] + R_PC[1, 1] * p[1] + R_PC[1, 2] * p[2]
    r2 = R_PC[2, 0] * p[0] + R_PC[2, 1] * p[1] + R_PC[2, 2] * p[2]
    l0 = c[0] - x[0] - r0  # eq. (2)
    l1 = c[1] - x[1] - r1
    l2 = c[2] - x[2] - r2
    L = np.sqrt(l0 * l0 + l1 * l1 + l2 * l2)
    inv = 1.0 / L if L != 0.0 else np.inf  # anchors coinciding: u = 0 * inf = NaN
    u0, u1, u2 = inv * l0, inv * l1, inv * l2
    # eq. (6): (u_i, (R_PC p_i) x u_i)
    row = (u0, u1, u2, r1 * u2 - r2 * u1, r2 * u0 - r0 * u2, r0 * u1 - r1 * u0)
    return L, row, (r0, r1, r2)


@njit(cache=_cache, inline="always")
def length_rate(row, twist):
    """One cable's length rate l_i' = -J~_i (v_PC, omega_PC) (eq. 5), m/s.

    row : J~_i, 6 floats (array or tuple); twist : ndarray, shape (6,): (v_PC, omega_PC) in
    C, m/s and rad/s.
    """
    acc = row[0] * twist[0]
    for a in range(1, 6):
        acc += row[a] * twist[a]
    return -acc


@njit(cache=_cache)
def cables_step(x, R_PC, c_C, p_P, lengths, J, anchors=None):
    """Cable lengths and J~ at one pose (eqs. 2, 6), written in place.

    :func:`cable_geometry` for every cable.

    Parameters
    ----------
    x : ndarray, shape (3,)
        x_PC: position of P's origin in C, m.
    R_PC : ndarray, shape (3, 3)
        R_P^C.
    c_C : ndarray, shape (n_cables, 3)
        Frame anchors c_i in C, m.
    p_P : ndarray, shape (n_cables, 3)
        Platform anchors p_i in P, m.
    lengths : ndarray, shape (n_cables,)
        Written: |l_i|, m; zero where an anchor pair coincides.
    J : ndarray, shape (n_cables, 6)
        Written: J~ (eq. 6), rows (u_i^T, ((R_PC p_i) x u_i)^T); NaN rows where an anchor
        pair coincides.
    anchors : ndarray, shape (n_cables, 3), optional
        Written if given: R_PC p_i, the platform anchors relative to P's origin, in C, m.
    """
    for i in range(c_C.shape[0]):
        L, row, r = cable_geometry(x, R_PC, c_C[i], p_P[i])
        lengths[i] = L
        for a in range(6):
            J[i, a] = row[a]
        if anchors is not None:
            for a in range(3):
                anchors[i, a] = r[a]


@njit(cache=_cache)
def length_rates_step(J, twist, rates):
    """Cable length rates l' = -J~ (v_PC, omega_PC) at one step (eq. 5), written in place.

    Parameters
    ----------
    J : ndarray, shape (n_cables, 6)
        J~ (eq. 6).
    twist : ndarray, shape (6,)
        (v_PC, omega_PC) in C, m/s and rad/s.
    rates : ndarray, shape (n_cables,)
        Written: l_i', m/s.
    """
    for i in range(J.shape[0]):
        rates[i] = length_rate(J[i], twist)


@njit(cache=_cache, inline="always")
def rows_in_O_step(J_tilde, R_SO, J):
    """J = J~ S^T with S = diag(R_SO, R_SO) at one step (eq. 14), written in place.

    Parameters
    ----------
    J_tilde : ndarray, shape (n_cables, 6)
        J~, rows in C.
    R_SO : ndarray, shape (3, 3)
        R_S^O (C's axes are S's).
    J : ndarray, shape (n_cables, 6)
        Written: the same rows with both halves expressed in O.
    """
    for i in range(J_tilde.shape[0]):
        for h in (0, 3):
            for a in range(3):
                J[i, h + a] = (R_SO[a, 0] * J_tilde[i, h] + R_SO[a, 1] * J_tilde[i, h + 1]
                               + R_SO[a, 2] * J_tilde[i, h + 2])


# ------------------------------------------------------------- over the steps, compiled


@njit(cache=_cache)
def _cables_series(xt, Rt, c_C, p_P, twt, Lt, At, Jt, rates_t):
    """:func:`cable_geometry` (and :func:`length_rate` where ``twt`` has 6 rows) at every
    step, on views of time-last, C-contiguous buffers: xt (3, n_steps), Rt (3, 3, n_steps),
    twt (6 or 0, n_steps); writes Lt (n_cables, n_steps), At (3, n_cables, n_steps), Jt (6,
    n_cables, n_steps) and, with a twist, rates_t (n_cables, n_steps).

    Cable by cable, the steps innermost: each output row is then written in order (twice
    as fast as all cables at each step, :func:`cables_step`'s order, over many steps)."""
    with_rates = twt.shape[0] == 6
    for i in range(c_C.shape[0]):
        c, p = c_C[i], p_P[i]
        for k in range(xt.shape[1]):
            L, row, r = cable_geometry(xt[:, k], Rt[:, :, k], c, p)
            Lt[i, k] = L
            for a in range(6):
                Jt[a, i, k] = row[a]
            for a in range(3):
                At[a, i, k] = r[a]
            if with_rates:
                rates_t[i, k] = length_rate(row, twt[:, k])


@njit(cache=_cache)
def _rows_in_O_series(Jt, Rt, Ot):
    """:func:`rows_in_O_step` at every step: Jt, Ot (6, n_cables, n_steps), Rt (3, 3, n_steps)."""
    for k in range(Jt.shape[2]):
        rows_in_O_step(Jt[:, :, k].T, Rt[:, :, k], Ot[:, :, k].T)


def _time_last(a: np.ndarray) -> np.ndarray:
    """(n_steps, ...) as a C-contiguous (..., n_steps) float array (no copy for a time-last view)."""
    return np.ascontiguousarray(np.moveaxis(np.asarray(a, dtype=float), 0, -1))


# --------------------------------------------------------------------- over time series


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
    xt = _time_last(x_PC)
    n = xt.shape[1]
    c_C = np.ascontiguousarray(c_C, dtype=float)
    m = c_C.shape[0]
    twt = np.empty((0, n)) if twist is None else _time_last(twist)
    Lt, At, Jt = np.empty((m, n)), np.empty((3, m, n)), np.empty((6, m, n))
    rates_t = np.empty((m if twist is not None else 0, n))
    _cables_series(xt, _time_last(R_PC), c_C, np.ascontiguousarray(p_P, dtype=float), twt,
                   Lt, At, Jt, rates_t)  # eqs. (2), (5), (6)
    return CableKinematics(
        lengths=Lt.T,
        anchors_C=At.transpose(2, 1, 0),
        J_tilde=Jt.transpose(2, 1, 0),
        length_rates=None if twist is None else rates_t.T,
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
    Jt = np.ascontiguousarray(np.asarray(J_tilde, dtype=float).transpose(2, 1, 0))
    Ot = np.empty(Jt.shape)
    _rows_in_O_series(Jt, _time_last(R_SO), Ot)
    return Ot.transpose(2, 1, 0)
