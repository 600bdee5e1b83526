"""Independent, slow, obviously-correct reference model for the tests.

This module re-derives the kinematics and dynamics of a cable-driven parallel
robot (CDPR) mounted on a moving ship directly from the equations of the
paper (eqs. 1-16, see ``/work/shared/paper``) and its reading notes.  It is
deliberately written without looking at the package under test, handles one
time step per call, and favours explicit, step-by-step code over speed.

Frames
------
O
    Inertial (earth) frame, z axis up.  Gravity is ``(0, 0, -g)`` in O.
S
    Ship frame.  Its pose in O is the ship's generalised coordinates
    ``eta = (x, y, z, roll, pitch, yaw)``: ``(x, y, z)`` is the position of
    S's origin in O [m], the angles [rad] give ``R_SO = rot((roll, pitch, yaw))``.
C
    Robot (frame) frame, rigidly fixed to the ship, axes parallel to S, origin
    at ``x_CS`` (given in S) [m].  Hence ``R_CO = R_SO`` and ``R_CS = I``.
P
    Platform frame, origin at the platform's centre of mass.  Its pose in C is
    ``pose = (x, y, z, rx, ry, rz)``: position of P's origin in C [m] and Euler
    angles [rad] giving ``R_PC = rot((rx, ry, rz))``.

Rotation convention
-------------------
``rot((phi, theta, psi)) = Rz(psi) @ Ry(theta) @ Rx(phi)`` maps vectors
expressed in the body frame into the reference frame (marine / SNAME
"roll-pitch-yaw" convention).

Rates convention (a decision of this reference)
-----------------------------------------------
``eta_dot``, ``eta_ddot``, ``pose_dot`` and ``pose_ddot`` are the plain first
and second time derivatives of the generalised coordinates, i.e. the angular
parts are *Euler-angle rates* (rad/s, rad/s^2), **not** angular velocities.
Angular velocities and accelerations are derived from them exactly.

Naming
------
``R_XY`` maps vectors expressed in X into Y.  ``x_AB`` is the position of A's
origin relative to B's origin.  ``omega_*`` are angular velocities [rad/s],
``alpha_*`` angular accelerations [rad/s^2].
"""

from __future__ import annotations

import functools
import itertools
import math

import numpy as np

__all__ = [
    "rot",
    "skew",
    "vee",
    "ship_state",
    "platform_state",
    "cable_quantities",
    "position_in_O",
    "absolute_kinematics",
    "required_wrench",
    "brute_force_least_distance",
]


# ---------------------------------------------------------------------------
# Elementary rotations and their first and second derivatives w.r.t. the angle
# ---------------------------------------------------------------------------


def _rx(a: float) -> np.ndarray:
    """Elementary rotation about x by ``a`` [rad]; shape (3, 3)."""
    c, s = np.cos(a), np.sin(a)
    return np.array([[1.0, 0.0, 0.0],
                     [0.0, c, -s],
                     [0.0, s, c]])


def _rx_d1(a: float) -> np.ndarray:
    """d Rx / d a; shape (3, 3)."""
    c, s = np.cos(a), np.sin(a)
    return np.array([[0.0, 0.0, 0.0],
                     [0.0, -s, -c],
                     [0.0, c, -s]])


def _rx_d2(a: float) -> np.ndarray:
    """d^2 Rx / d a^2; shape (3, 3)."""
    c, s = np.cos(a), np.sin(a)
    return np.array([[0.0, 0.0, 0.0],
                     [0.0, -c, s],
                     [0.0, -s, -c]])


def _ry(a: float) -> np.ndarray:
    """Elementary rotation about y by ``a`` [rad]; shape (3, 3)."""
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, 0.0, s],
                     [0.0, 1.0, 0.0],
                     [-s, 0.0, c]])


def _ry_d1(a: float) -> np.ndarray:
    """d Ry / d a; shape (3, 3)."""
    c, s = np.cos(a), np.sin(a)
    return np.array([[-s, 0.0, c],
                     [0.0, 0.0, 0.0],
                     [-c, 0.0, -s]])


def _ry_d2(a: float) -> np.ndarray:
    """d^2 Ry / d a^2; shape (3, 3)."""
    c, s = np.cos(a), np.sin(a)
    return np.array([[-c, 0.0, -s],
                     [0.0, 0.0, 0.0],
                     [s, 0.0, -c]])


def _rz(a: float) -> np.ndarray:
    """Elementary rotation about z by ``a`` [rad]; shape (3, 3)."""
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0.0],
                     [s, c, 0.0],
                     [0.0, 0.0, 1.0]])


def _rz_d1(a: float) -> np.ndarray:
    """d Rz / d a; shape (3, 3)."""
    c, s = np.cos(a), np.sin(a)
    return np.array([[-s, -c, 0.0],
                     [c, -s, 0.0],
                     [0.0, 0.0, 0.0]])


def _rz_d2(a: float) -> np.ndarray:
    """d^2 Rz / d a^2; shape (3, 3)."""
    c, s = np.cos(a), np.sin(a)
    return np.array([[-c, s, 0.0],
                     [-s, -c, 0.0],
                     [0.0, 0.0, 0.0]])


# ---------------------------------------------------------------------------
# Small helpers
# ---------------------------------------------------------------------------


def rot(angles) -> np.ndarray:
    """Rotation matrix from Euler angles, ``Rz(psi) @ Ry(theta) @ Rx(phi)``.

    Parameters
    ----------
    angles : array_like, shape (3,)
        ``(phi, theta, psi)`` [rad]: rotation about x (roll), y (pitch),
        z (yaw).

    Returns
    -------
    ndarray, shape (3, 3)
        Matrix mapping body-frame vectors into the reference frame.
    """
    phi, theta, psi = (float(a) for a in angles)
    return _rz(psi) @ _ry(theta) @ _rx(phi)


def skew(v) -> np.ndarray:
    """Cross-product matrix: ``skew(v) @ w == np.cross(v, w)``.

    Parameters
    ----------
    v : array_like, shape (3,)

    Returns
    -------
    ndarray, shape (3, 3)
    """
    x, y, z = (float(a) for a in v)
    return np.array([[0.0, -z, y],
                     [z, 0.0, -x],
                     [-y, x, 0.0]])


def vee(S) -> np.ndarray:
    """Vector of the antisymmetric part of a 3x3 matrix (inverse of `skew`).

    Parameters
    ----------
    S : array_like, shape (3, 3)
        Ideally antisymmetric; only ``(S - S.T) / 2`` is used.

    Returns
    -------
    ndarray, shape (3,)
    """
    S = np.asarray(S, dtype=float)
    A = 0.5 * (S - S.T)
    return np.array([A[2, 1], A[0, 2], A[1, 0]])


def _euler_kinematics(angles, rates, accels) -> dict:
    """Exact rotation kinematics of ``R = Rz(psi) Ry(theta) Rx(phi)``.

    ``Rdot`` and ``Rddot`` are obtained by the product rule from the
    elementary rotations and their explicit derivatives; then
    ``skew(omega) = Rdot R^T`` and, since ``Rddot = (skew(alpha) +
    skew(omega)^2) R``, ``skew(alpha) = Rddot R^T - skew(omega)^2``.

    Parameters
    ----------
    angles, rates, accels : array_like, shape (3,)
        ``(phi, theta, psi)`` [rad], their first [rad/s] and second
        [rad/s^2] time derivatives.

    Returns
    -------
    dict
        ``R``, ``Rdot``, ``Rddot`` (3, 3); ``omega``, ``alpha`` (3,) expressed
        in the reference frame (the frame ``R`` maps into).
    """
    phi, theta, psi = (float(a) for a in angles)
    dphi, dtheta, dpsi = (float(a) for a in rates)
    ddphi, ddtheta, ddpsi = (float(a) for a in accels)

    # R = A B C with A = Rz(psi), B = Ry(theta), C = Rx(phi).
    A, B, C = _rz(psi), _ry(theta), _rx(phi)
    # First time derivatives (chain rule).
    A1 = _rz_d1(psi) * dpsi
    B1 = _ry_d1(theta) * dtheta
    C1 = _rx_d1(phi) * dphi
    # Second time derivatives: d/dt (f'(a) a') = f''(a) a'^2 + f'(a) a''.
    A2 = _rz_d2(psi) * dpsi**2 + _rz_d1(psi) * ddpsi
    B2 = _ry_d2(theta) * dtheta**2 + _ry_d1(theta) * ddtheta
    C2 = _rx_d2(phi) * dphi**2 + _rx_d1(phi) * ddphi

    R = A @ B @ C
    Rdot = A1 @ B @ C + A @ B1 @ C + A @ B @ C1
    Rddot = (A2 @ B @ C + A @ B2 @ C + A @ B @ C2
             + 2.0 * (A1 @ B1 @ C + A1 @ B @ C1 + A @ B1 @ C1))

    W = Rdot @ R.T
    omega = vee(W)
    Wo = skew(omega)
    # Rddot R^T - [w][w] is exactly skew; [w][w] is symmetric, so subtracting
    # it does not change `vee` (which takes the antisymmetric part), but it
    # makes the matrix itself skew, which the self-checks verify.
    alpha = vee(Rddot @ R.T - Wo @ Wo)
    return {"R": R, "Rdot": Rdot, "Rddot": Rddot, "omega": omega, "alpha": alpha}


# ---------------------------------------------------------------------------
# Public API
# ---------------------------------------------------------------------------


def ship_state(eta, eta_dot, eta_ddot) -> dict:
    """Ship orientation, angular velocity and angular acceleration in O.

    Parameters
    ----------
    eta : array_like, shape (6,)
        ``(x, y, z, roll, pitch, yaw)``: position of S's origin in O [m] and
        Euler angles [rad], ``R_SO = rot((roll, pitch, yaw))``.
    eta_dot : array_like, shape (6,)
        Time derivative of ``eta`` [m/s, rad/s] (Euler-angle *rates*).
    eta_ddot : array_like, shape (6,)
        Second time derivative of ``eta`` [m/s^2, rad/s^2].

    Returns
    -------
    dict
        ``R_SO`` (3, 3): maps S vectors into O.
        ``Rdot_SO``, ``Rddot_SO`` (3, 3): its first and second time
        derivatives [1/s, 1/s^2].
        ``omega_O`` (3,): ship angular velocity expressed in O [rad/s],
        from ``skew(omega_O) = Rdot_SO @ R_SO.T``.
        ``alpha_O`` (3,): ship angular acceleration in O [rad/s^2],
        the time derivative of ``omega_O``.
        ``x_SO``, ``v_SO``, ``a_SO`` (3,): position, velocity, acceleration
        of S's origin in O [m, m/s, m/s^2].
    """
    eta = np.asarray(eta, dtype=float)
    eta_dot = np.asarray(eta_dot, dtype=float)
    eta_ddot = np.asarray(eta_ddot, dtype=float)
    k = _euler_kinematics(eta[3:6], eta_dot[3:6], eta_ddot[3:6])
    return {
        "R_SO": k["R"],
        "Rdot_SO": k["Rdot"],
        "Rddot_SO": k["Rddot"],
        "omega_O": k["omega"],
        "alpha_O": k["alpha"],
        "x_SO": eta[0:3].copy(),
        "v_SO": eta_dot[0:3].copy(),
        "a_SO": eta_ddot[0:3].copy(),
    }


def platform_state(pose, pose_dot, pose_ddot) -> dict:
    """Platform motion relative to the robot frame C, expressed in C.

    Parameters
    ----------
    pose : array_like, shape (6,)
        ``(x, y, z, rx, ry, rz)``: position of P's origin (the centre of mass)
        in C [m] and Euler angles [rad], ``R_PC = rot((rx, ry, rz))``.
    pose_dot : array_like, shape (6,)
        Time derivative of ``pose`` [m/s, rad/s] (Euler-angle *rates*).
    pose_ddot : array_like, shape (6,)
        Second time derivative of ``pose`` [m/s^2, rad/s^2].

    Returns
    -------
    dict
        ``R_PC``, ``Rdot_PC``, ``Rddot_PC`` (3, 3).
        ``omega_PC`` (3,): angular velocity of P relative to C, in C [rad/s].
        ``alpha_PC`` (3,): its time derivative (seen from C), in C [rad/s^2].
        ``x_PC``, ``v_PC``, ``a_PC`` (3,): position, velocity and acceleration
        of P's origin relative to C, in C [m, m/s, m/s^2].
    """
    pose = np.asarray(pose, dtype=float)
    pose_dot = np.asarray(pose_dot, dtype=float)
    pose_ddot = np.asarray(pose_ddot, dtype=float)
    k = _euler_kinematics(pose[3:6], pose_dot[3:6], pose_ddot[3:6])
    return {
        "R_PC": k["R"],
        "Rdot_PC": k["Rdot"],
        "Rddot_PC": k["Rddot"],
        "omega_PC": k["omega"],
        "alpha_PC": k["alpha"],
        "x_PC": pose[0:3].copy(),
        "v_PC": pose_dot[0:3].copy(),
        "a_PC": pose_ddot[0:3].copy(),
    }


def cable_quantities(pose, c, p):
    """Cable lengths, unit vectors and the local Jacobian J~ (eqs. 2-6).

    For cable i: ``l_i = c_i - (x_PC + R_PC p_i)`` (in C), ``u_i = l_i/|l_i|``
    points from the platform anchor to the frame anchor, and row i of J~ is
    ``[u_i^T, ((R_PC p_i) x u_i)^T]``, so that ``ldot = -J~ @ [v_PC; omega_PC]``
    and ``J~.T @ T`` is the cable wrench (force; moment about the centre of
    mass) in C.

    Parameters
    ----------
    pose : array_like, shape (6,)
        Platform pose in C, ``(x, y, z, rx, ry, rz)`` [m, rad].
    c : array_like, shape (n_cables, 3)
        Frame anchors in C [m].
    p : array_like, shape (n_cables, 3)
        Platform anchors in P (relative to the centre of mass) [m].

    Returns
    -------
    lengths : ndarray, shape (n_cables,)
        Cable lengths [m].
    u : ndarray, shape (n_cables, 3)
        Unit cable vectors in C.
    J_tilde : ndarray, shape (n_cables, 6)
        Jacobian rows in C (dimensionless | m).
    """
    pose = np.asarray(pose, dtype=float)
    c = np.asarray(c, dtype=float)
    p = np.asarray(p, dtype=float)
    n = c.shape[0]
    x_PC = pose[0:3]
    R_PC = rot(pose[3:6])
    lengths = np.zeros(n)
    u = np.zeros((n, 3))
    J_tilde = np.zeros((n, 6))
    for i in range(n):
        r_i = R_PC @ p[i]                  # platform anchor rel. to COM, in C
        l_vec = c[i] - (x_PC + r_i)
        lengths[i] = np.sqrt(l_vec @ l_vec)
        u[i] = l_vec / lengths[i]
        J_tilde[i, 0:3] = u[i]
        J_tilde[i, 3:6] = np.cross(r_i, u[i])
    return lengths, u, J_tilde


def position_in_O(pose, eta, x_CS) -> np.ndarray:
    """Position of the platform's centre of mass in O (eq. 7).

    ``x_PO = x_SO + R_SO (x_CS + x_PC)``.

    Parameters
    ----------
    pose : array_like, shape (6,)
        Platform pose in C [m, rad].
    eta : array_like, shape (6,)
        Ship generalised coordinates [m, rad].
    x_CS : array_like, shape (3,)
        Origin of C in S [m].

    Returns
    -------
    ndarray, shape (3,)
        ``x_PO`` in O [m].
    """
    pose = np.asarray(pose, dtype=float)
    eta = np.asarray(eta, dtype=float)
    x_CS = np.asarray(x_CS, dtype=float)
    return eta[0:3] + rot(eta[3:6]) @ (x_CS + pose[0:3])


def absolute_kinematics(pose, pose_dot, pose_ddot, eta, eta_dot, eta_ddot,
                        x_CS) -> dict:
    """Absolute (inertial) motion of the platform, expressed in O.

    Translation: with ``r = x_CS + x_PC`` (in S, constant ``x_CS``),
    ``x_PO = x_SO + R_SO r`` is differentiated twice by the product rule::

        v_PO = v_SO + Rdot_SO r + R_SO rdot
        a_PO = a_SO + Rddot_SO r + 2 Rdot_SO rdot + R_SO rddot

    Rotation: ``omega_PO = omega_SO + R_SO omega_PC`` and, by the product
    rule, ``alpha_PO = alpha_SO + Rdot_SO omega_PC + R_SO alpha_PC``.

    Parameters
    ----------
    pose, pose_dot, pose_ddot : array_like, shape (6,)
        Platform pose in C and its first and second time derivatives
        [m, rad; m/s, rad/s; m/s^2, rad/s^2] (angular parts are Euler rates).
    eta, eta_dot, eta_ddot : array_like, shape (6,)
        Ship coordinates and their first and second time derivatives.
    x_CS : array_like, shape (3,)
        Origin of C in S [m].

    Returns
    -------
    dict
        ``x_PO``, ``v_PO``, ``a_PO`` (3,): COM position, velocity and
        acceleration in O [m, m/s, m/s^2].
        ``R_PO`` (3, 3): ``R_SO @ R_PC`` (P into O).
        ``omega_PO``, ``alpha_PO`` (3,): absolute angular velocity and
        acceleration of P, in O [rad/s, rad/s^2].
        ``ship`` and ``platform``: the dicts of `ship_state`, `platform_state`.
    """
    x_CS = np.asarray(x_CS, dtype=float)
    sh = ship_state(eta, eta_dot, eta_ddot)
    pl = platform_state(pose, pose_dot, pose_ddot)

    R, Rd, Rdd = sh["R_SO"], sh["Rdot_SO"], sh["Rddot_SO"]
    r = x_CS + pl["x_PC"]
    r_d = pl["v_PC"]
    r_dd = pl["a_PC"]

    x_PO = sh["x_SO"] + R @ r
    v_PO = sh["v_SO"] + Rd @ r + R @ r_d
    a_PO = sh["a_SO"] + Rdd @ r + 2.0 * (Rd @ r_d) + R @ r_dd

    omega_PO = sh["omega_O"] + R @ pl["omega_PC"]
    alpha_PO = sh["alpha_O"] + Rd @ pl["omega_PC"] + R @ pl["alpha_PC"]

    return {
        "x_PO": x_PO,
        "v_PO": v_PO,
        "a_PO": a_PO,
        "R_PO": R @ pl["R_PC"],
        "omega_PO": omega_PO,
        "alpha_PO": alpha_PO,
        "ship": sh,
        "platform": pl,
    }


def required_wrench(pose, pose_dot, pose_ddot, eta, eta_dot, eta_ddot, x_CS,
                    mass, I_PP, g, f_r_O, m_r_O) -> np.ndarray:
    """Cable wrench needed for the given motion, expressed in C (eq. 12).

    Newton-Euler in the inertial frame O::

        m a_PO = F_cables + m g_O + f_r
        I_O alpha_PO + omega_PO x (I_O omega_PO) = M_cables + m_r

    with ``g_O = (0, 0, -g)`` and ``I_O = R_SO R_PC I_PP R_PC^T R_SO^T``.
    The result is ``w = (R_SO^T F_cables, R_SO^T M_cables)``; the moment is
    about the centre of mass.  It should equal ``J_tilde.T @ T`` for the cable
    tensions T.

    Parameters
    ----------
    pose, pose_dot, pose_ddot : array_like, shape (6,)
        Platform pose in C and its time derivatives (Euler-angle rates).
    eta, eta_dot, eta_ddot : array_like, shape (6,)
        Ship coordinates and their time derivatives (Euler-angle rates).
    x_CS : array_like, shape (3,)
        Origin of C in S [m].
    mass : float
        Platform mass [kg].
    I_PP : array_like, shape (3, 3)
        Inertia tensor about the centre of mass, in P [kg m^2].
    g : float
        Gravity *magnitude* [m/s^2], positive (e.g. 9.8); gravity is
        ``(0, 0, -g)`` in O.
    f_r_O, m_r_O : array_like, shape (3,)
        External disturbance force [N] and moment about the centre of mass
        [N m], both in O.

    Returns
    -------
    ndarray, shape (6,)
        ``(F_cables, M_cables)`` expressed in C [N, N m].
    """
    kin = absolute_kinematics(pose, pose_dot, pose_ddot,
                              eta, eta_dot, eta_ddot, x_CS)
    I_PP = np.asarray(I_PP, dtype=float)
    f_r_O = np.asarray(f_r_O, dtype=float)
    m_r_O = np.asarray(m_r_O, dtype=float)
    mass = float(mass)

    R_SO = kin["ship"]["R_SO"]
    R_PO = kin["R_PO"]
    I_O = R_PO @ I_PP @ R_PO.T
    g_O = np.array([0.0, 0.0, -float(g)])

    w = kin["omega_PO"]
    F_cables_O = mass * kin["a_PO"] - mass * g_O - f_r_O
    M_cables_O = I_O @ kin["alpha_PO"] + np.cross(w, I_O @ w) - m_r_O

    return np.concatenate([R_SO.T @ F_cables_O, R_SO.T @ M_cables_O])


@functools.lru_cache(maxsize=None)
def _active_sets(n):
    """brute_force_least_distance's 3^n cases of n cables, by their number nf of free
    cables: (nf, the free sets (G, nf), every case of each (G, F, n): 0 free, 1 lo, 2 hi,
    each free set's cases the F = 2^(n - nf) assignments of its other cables to lo or hi)."""
    out = []
    for nf in range(n + 1):
        sets = np.array(list(itertools.combinations(range(n), nf)), dtype=int).reshape(math.comb(n, nf), nf)
        fixed = np.array([[i for i in range(n) if i not in s] for s in sets], dtype=int).reshape(len(sets), n - nf)
        bounds = np.array(list(itertools.product((1, 2), repeat=n - nf)), dtype=int).reshape(2 ** (n - nf), n - nf)
        G, F = len(sets), len(bounds)
        case = np.zeros((G, F, n), dtype=int)
        np.put_along_axis(case, np.broadcast_to(fixed[:, None, :], (G, F, n - nf)),
                          np.broadcast_to(bounds[None], (G, F, n - nf)), axis=2)
        out.append((nf, sets, case))
    return tuple(out)


def brute_force_least_distance(Jc, w, target, lo, hi):
    """Exact minimum-distance tensions by enumerating all active sets.

    Solves ``min |T - target|^2  s.t.  Jc.T @ T = w,  lo <= T <= hi``.

    Every cable is assigned to one of {free, at ``lo``, at ``hi``} (3^n
    cases).  For each case the equality-constrained least-squares problem in
    the free cables is solved exactly, the result is kept if it satisfies the
    bounds and the equality, and the best kept candidate is returned.  Since
    the optimum has *some* such active set, and the case problem's minimiser
    is at least as good as the optimum, this is exact.  Cost grows as 3^n:
    meant for ``n_cables <= 8``.  The cases sharing a free set share its
    KKT matrix: they are solved together, one right-hand side each (the
    same solution as one case at a time), and the free sets of one size
    in one batch; ties in the objective go to the first case in
    ``itertools.product((0, 1, 2), repeat=n)`` order.

    Parameters
    ----------
    Jc : array_like, shape (n_cables, k)
        Structure matrix, row i = contribution of a unit tension in cable i to
        the k controlled wrench components (e.g. selected columns of J~).
    w : array_like, shape (k,)
        Required wrench components.
    target : float or array_like, shape (n_cables,)
        Preferred tensions [N] (e.g. the middle of the range).
    lo, hi : float or array_like, shape (n_cables,)
        Tension bounds [N], ``lo <= hi``.

    Returns
    -------
    ndarray, shape (n_cables,) or None
        The optimal tensions, or None if no tension within the bounds
        produces ``w``.

    Notes
    -----
    Tolerances: bounds within 1e-9 (absolute); equality within
    ``1e-8 * max(1, |w|, | |Jc|.T @ |T| |)`` (2-norms).  A free set whose
    ``Jc`` rows have rank < k is solved with the pseudo-inverse and kept only
    if the equality still holds within that tolerance.
    """
    Jc = np.asarray(Jc, dtype=float)
    w = np.asarray(w, dtype=float).reshape(-1)
    n, k = Jc.shape
    target = np.broadcast_to(np.asarray(target, dtype=float), (n,)).copy()
    lo = np.broadcast_to(np.asarray(lo, dtype=float), (n,)).copy()
    hi = np.broadcast_to(np.asarray(hi, dtype=float), (n,)).copy()

    # the cases by their number of free cables: for each free set (in a batch of all free
    # sets of that size) every lo/hi assignment of the other cables; 0 free, 1 lo, 2 hi
    kept_T, kept_obj, kept_case = [], [], []
    for nf, sets, case in _active_sets(n):
        G, F = case.shape[:2]
        T = np.where(case == 1, lo, np.where(case == 2, hi, 0.0))        # (G, F, n), free cables 0
        if nf:
            A = Jc[sets].transpose(0, 2, 1)               # (G, k, n_free): each free set's
            rhs = w - T @ Jc                              # (G, F, k): wrench left for free cables
            t0 = target[sets]                             # (G, n_free)
            full = np.linalg.matrix_rank(A) == k
            x = np.empty((G, F, nf))
            if full.any():
                # KKT system of min |x - t0|^2 s.t. A x = rhs, one per free set, a
                # right-hand side per assignment of the fixed cables:
                #   [ I   A^T ] [x  ]   [t0 ]
                #   [ A   0   ] [mu ] = [rhs]
                Af = A[full]
                K = np.zeros((len(Af), nf + k, nf + k))
                K[:, :nf, :nf] = np.eye(nf)
                K[:, :nf, nf:] = Af.transpose(0, 2, 1)
                K[:, nf:, :nf] = Af
                b = np.concatenate([np.broadcast_to(t0[full][:, None, :], (len(Af), F, nf)), rhs[full]], axis=2)
                x[full] = np.linalg.solve(K, b.transpose(0, 2, 1)).transpose(0, 2, 1)[..., :nf]
            if not full.all():
                # Rank deficient: minimum-norm correction (exact if consistent;
                # consistency is checked below).
                Ad, td = A[~full], t0[~full]
                x[~full] = td[:, None, :] + (rhs[~full] - (Ad @ td[..., None])[:, None, :, 0]) \
                    @ np.linalg.pinv(Ad).transpose(0, 2, 1)
            np.put_along_axis(T, np.broadcast_to(sets[:, None, :], (G, F, nf)), x, axis=2)
        T, case = T.reshape(-1, n), case.reshape(-1, n)
        inside = np.all((T >= lo - 1e-9) & (T <= hi + 1e-9), axis=1)
        resid = np.linalg.norm(T @ Jc - w, axis=1)
        scale = np.maximum(max(1.0, np.linalg.norm(w)), np.linalg.norm(np.abs(T) @ np.abs(Jc), axis=1))
        ok = inside & (resid <= 1e-8 * scale)
        kept_T.append(T[ok])
        kept_obj.append(np.sum((T[ok] - target) ** 2, axis=1))
        kept_case.append(case[ok])
    T, obj = np.concatenate(kept_T), np.concatenate(kept_obj)
    if obj.size == 0:
        return None
    place = np.concatenate(kept_case) @ 3 ** np.arange(n - 1, -1, -1)  # a case's place in the enumeration
    best = np.flatnonzero(obj == obj.min())
    return T[best[np.argmin(place[best])]].copy()
