"""Stiffness of the platform on its cables, natural frequencies, and the linearised open loop.

Everything is in the robot frame C (axes of the ship S), about P's origin, which is the
platform's centre of mass (``docs/conventions.md``). A small displacement of the platform
from a pose is q = (dx, dphi): dx the displacement of P's origin in C (m) and dphi the
rotation vector of the extra rotation, in C (rad), so that

    x_PC -> x_PC + dx,        R_PC -> exp([dphi x]) R_PC.

Cable i (:mod:`marinecdpr.geometry.kinematics`): r_i = R_PC p_i, l_i = c_i - x_PC - r_i,
L_i = |l_i|, u_i = l_i / L_i, J~_i = (u_i^T, (r_i x u_i)^T); it pulls the platform with
t_i u_i, so the cables' wrench about the centre of mass is W = J~^T T = sum_i t_i (u_i, r_i x u_i).

Stiffness
---------
K = -dW/dq (N/m, N/rad, N m/m, N m/rad; 6 x 6, rows (force, moment), columns (dx, dphi)):

    K_axial     = sum_i k_i J~_i^T J~_i                       (tensions change with length)
    K_geometric = sum_i t_i [[ P_i,          -P_i [r_i x]                       ],
                             [ [r_i x] P_i,  -[r_i x] P_i [r_i x] - [u_i x][r_i x] ]]

with P_i = (I - u_i u_i^T) / L_i and [a x] the cross-product matrix. Derivation, at held
tensions: dr_i = dphi x r_i = -[r_i x] dphi, dl_i = -dx - dr_i = -dx + [r_i x] dphi, and
du_i = P_i dl_i, so

    d(t_i u_i)       = t_i P_i (-dx + [r_i x] dphi)
    d(t_i r_i x u_i) = t_i (dr_i x u_i + r_i x du_i) = t_i ([u_i x][r_i x] dphi + [r_i x] du_i).

The last term, [u_i x][r_i x] = r_i u_i^T - (u_i . r_i) I, comes from turning the anchor's
lever arm; it is not symmetric: sum_i t_i of its antisymmetric part is -1/2 [m x] with
m = sum_i t_i r_i x u_i the cables' moment, so K_geometric is symmetric where the cables
apply no net moment. Cf. Behzadipour & Khajepour, "Stiffness of cable-based parallel
manipulators with application to stability analysis", J. Mech. Des. 128 (2006); the
matrix here is checked against central differences of J~^T T (``tests/model/test_stiffness.py``).

For yaw alone (dphi = e_z dpsi) the rotational entry reads
K_psi = sum_i t_i [(r_i x e_z)^T P_i (r_i x e_z) + r_i,xy . u_i,xy]: a string term >= 0 and
a lever term that is negative where a cable pulls its anchor across the centre
(r_i . u_i < 0, crossed cables): an inverted pendulum when tensions are held.

k_i is the cable's axial stiffness at the winch's fixed unstretched length: for
T_i = T0_i + EA_i (L_i - L_ref,i) / L_ref,i linearised about the present length,
k_i = EA_i / L_i (``reference_length="stretched"``, the default); for the prototype's law
T_i = EA_i (L_i - L0_i) / L0_i with the unstretched length L0_i = L_i / (1 + t_i / EA_i),
k_i = EA_i / L0_i = (EA_i + t_i) / L_i (``"unstretched"``). The two differ by t_i / EA_i.
A tension-controlled winch holds t_i whatever the length: K_axial = 0 there.

Load
----
The platform also needs the wrench w of eq. (15) (``wrench_terms(...).total``); the
equations of motion are M_s(R) nu' + bias(q, nu, t) = J~^T T, w = M_s nu'_ref + bias. The
load's stiffness and damping are K_load = dw/dq and D_load = dw/dnu at the reference
acceleration (a perturbation of the pose or the twist changes the wrench the cables must
supply; the linearised restoring wrench is -(K + K_load) dq - (D + D_load) dnu). From
:func:`~marinecdpr.model.rigid_body.wrench_parts_step`, with omega_s, alpha_s the ship's angular
velocity and acceleration (in S = C's axes), r = x_CS + x_PC, I_C = R_PC I_PP R_PC^T,
W = omega_s + omega_PC, beta = alpha_PC + alpha_s + omega_s x omega_PC:

    force  = m (a + R_SO^T a_SO + alpha_s x r + omega_s x (omega_s x r) + 2 omega_s x v) + gravity terms - f_r
    moment = I_C beta + W x I_C W - m_r

    d force / dx      = m ([alpha_s x] + [omega_s x]^2)          Euler and centrifugal
    d force / dv      = 2 m [omega_s x]                          Coriolis
    d moment / dphi   = G(beta) + [W x] G(W),   G(b) = I_C [b x] - [(I_C b) x]   (d(I_C b) = G(b) dphi)
    d moment / domega = I_C [omega_s x] + [W x] I_C - [(I_C W) x]                gyroscopic

plus, for a disturbance given in P (it turns with the platform; f_C = R_PC f_P),
d(-f_C)/dphi = [f_C x] and d(-m_C)/dphi = [m_C x]. Gravity adds no stiffness: the weight
acts at P's origin, the centre of mass, so its moment about P is zero at every pose, and
its direction in C depends on the ship's attitude only (the gravity tilt); the ship's base
acceleration term does not depend on the pose either. A disturbance given in O or C does
not depend on the pose. Not included: the cleaning brush's loads (:mod:`.brush`).

Linearised open loop
--------------------
About the plan at each step (frozen coefficients), with state s = (dq, dnu) in the
controlled DOFs c and dnu = (dv, domega) the twist's deviation:

    dq'  = Omega dq + dnu,             Omega = diag(0, [omega_PC x])    (the rotation vector's
                                        rate: R = exp([dphi x]) R_ref gives domega = dphi' + dphi x omega_PC)
    M dnu' = -K_eff dq - D dnu

    A = [[Omega_cc, I], [-M_cc^-1 K_eff, -M_cc^-1 D]]

with K_eff = K_axial (length-controlled elastic winches only) + K_geometric + K_load and
D = sum_i c_i J~_i^T J~_i (the cables' axial damping, length-controlled elastic winches) +
D_load. The uncontrolled DOFs (a planar robot's y, rx, rz) are held by the guide. The
largest real part of A's eigenvalues along the plan is the open loop's growth rate (1/s):
> 0 means a small error grows like exp(rate t) while the coefficients stay near those
values. Omega is exact for the rotation vector; it vanishes for a planar robot.

Arrays are shaped time first, ``(n_steps, ...)``; the functions are vectorised NumPy
(the paper's 15 001-step plan: about 0.2 s for the stiffness, 0.1 s for the eigenvalues).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Literal

import numpy as np

from marinecdpr.geometry.elastic import axial_stiffness, unstretched_length
from marinecdpr.geometry.kinematics import cable_kinematics
from marinecdpr.geometry.rotations import matrix_from_euler, skew
from marinecdpr.model.dynamics import spatial_inertia
from marinecdpr.motion.basemotion import fixed_ship_motion, frame_ship_motion
from marinecdpr.motion.ship import ShipMotion
from marinecdpr.motion.trajectory import evaluate_disturbance

if TYPE_CHECKING:  # the planning layer is above this one: a Plan is only read, never imported
    from marinecdpr.scenario.schema import Scenario

__all__ = [
    "CableStiffness",
    "cable_stiffness",
    "LoadLinearisation",
    "load_linearisation",
    "PlanStiffness",
    "plan_stiffness",
    "NaturalFrequencies",
    "natural_frequencies",
    "state_matrix",
    "GrowthRate",
    "open_loop_growth_rate",
    "DOF_NAMES",
]

DOF_NAMES = ("x", "y", "z", "rx", "ry", "rz")
"""Names of the displacement components (dx, dphi) in C: m for x, y, z; rad for rx, ry, rz."""

Winches = Literal["tension", "length"]


# ---------------------------------------------------------------------------- cables


@dataclass(frozen=True)
class CableStiffness:
    """The cables' stiffness and damping at a series of poses, full 6 x 6 in C.

    Rows (force N, moment N m about P's origin); columns (dx m, dphi rad), the rotation
    vector in C. Each shaped (n_steps, 6, 6).

    Attributes
    ----------
    K_axial : ndarray
        sum_i k_i J~_i^T J~_i (zero without EA).
    K_geometric : ndarray
        From the turning of u_i and of the lever arms R_PC p_i at held tensions.
    D : ndarray
        sum_i c_i J~_i^T J~_i, N s/m (zero without damping).
    J_tilde : ndarray, shape (n_steps, n_cables, 6)
        J~ at the poses.
    lengths : ndarray, shape (n_steps, n_cables)
        L_i, m.
    """

    K_axial: np.ndarray
    K_geometric: np.ndarray
    D: np.ndarray
    J_tilde: np.ndarray
    lengths: np.ndarray

    @property
    def K(self) -> np.ndarray:
        """K_axial + K_geometric, shape (n_steps, 6, 6)."""
        return self.K_axial + self.K_geometric


def _per_cable(value, shape: tuple[int, int]) -> np.ndarray | None:
    """A cable property (scalar or (n_cables,)) broadcast to (n_steps, n_cables); None stays."""
    if value is None:
        return None
    return np.broadcast_to(np.asarray(value, dtype=float), shape)


def cable_stiffness(
    x_PC: np.ndarray,
    R_PC: np.ndarray,
    c_C: np.ndarray,
    p_P: np.ndarray,
    tensions: np.ndarray,
    *,
    EA: float | np.ndarray | None = None,
    damping: float | np.ndarray | None = None,
    reference_length: Literal["stretched", "unstretched"] = "stretched",
) -> CableStiffness:
    """The cables' stiffness K = -d(J~^T T)/d(dx, dphi) at a series of poses.

    Parameters
    ----------
    x_PC : ndarray, shape (n_steps, 3)
        Position of P's origin (centre of mass) in C, m.
    R_PC : ndarray, shape (n_steps, 3, 3)
        R_P^C.
    c_C : ndarray, shape (n_cables, 3)
        Frame anchors c_i in C, m.
    p_P : ndarray, shape (n_cables, 3)
        Platform anchors p_i in P, m.
    tensions : ndarray, shape (n_steps, n_cables)
        t_i at the poses, N (held for K_geometric; the operating point for K_axial).
    EA : float or ndarray, shape (n_cables,), optional
        Axial stiffness E A of each cable, N, for cables held at a fixed unstretched
        length (length-controlled winches). None: no axial term (tension-controlled).
    damping : float or ndarray, shape (n_cables,), optional
        Axial damping c_i, N per (m/s) of length rate: D = sum_i c_i J~_i^T J~_i.
    reference_length : {"stretched", "unstretched"}
        k_i = EA_i / L_i (tension linearised about the present length), or
        EA_i / L0_i = (EA_i + t_i) / L_i (strain over the unstretched length, as the
        prototype's elastic cables).

    Returns
    -------
    CableStiffness
        NaN where an anchor pair coincides or a tension is NaN.
    """
    x_PC = np.asarray(x_PC, dtype=float)
    R_PC = np.asarray(R_PC, dtype=float)
    T = np.asarray(tensions, dtype=float)
    kin = cable_kinematics(x_PC, R_PC, c_C, p_P)
    J = np.ascontiguousarray(kin.J_tilde)  # (n, m, 6)
    L = np.ascontiguousarray(kin.lengths)  # (n, m)
    r = np.ascontiguousarray(kin.anchors_C)  # (n, m, 3): r_i = R_PC p_i
    u = J[..., :3]
    n, m = L.shape
    # P_i = (I - u u^T) / L_i
    P = (np.eye(3) - u[..., :, None] * u[..., None, :]) / L[..., None, None]
    Sr, Su = skew(r), skew(u)
    tP = T[..., None, None] * P
    K = np.empty((n, 6, 6))
    K[:, :3, :3] = tP.sum(axis=1)                                   # t P
    K[:, :3, 3:] = -(tP @ Sr).sum(axis=1)                           # -t P [r x]
    K[:, 3:, :3] = (Sr @ tP).sum(axis=1)                            # [r x] t P
    K[:, 3:, 3:] = -(Sr @ tP @ Sr + T[..., None, None] * (Su @ Sr)).sum(axis=1)  # -t([r x]P[r x] + [u x][r x])
    zero = np.zeros((n, 6, 6))
    ea = _per_cable(EA, (n, m))
    if ea is None:
        K_axial = zero
    else:
        if reference_length == "stretched":
            k = ea / L  # T = T0 + EA (L - L_ref) / L_ref about L_ref = L
        elif reference_length == "unstretched":
            k = axial_stiffness(unstretched_length(L, T, ea), ea)  # EA / L0
        else:
            raise ValueError(f"reference_length must be 'stretched' or 'unstretched', not {reference_length!r}")
        K_axial = np.einsum("nm,nma,nmb->nab", k, J, J)  # sum_i k_i J~_i^T J~_i
    c = _per_cable(damping, (n, m))
    D = zero if c is None else np.einsum("nm,nma,nmb->nab", c, J, J)  # sum_i c_i J~_i^T J~_i
    return CableStiffness(K_axial=K_axial, K_geometric=K, D=D, J_tilde=J, lengths=L)


# ------------------------------------------------------------------------------ load


@dataclass(frozen=True)
class LoadLinearisation:
    """How the wrench the platform needs (eq. 15) changes with its pose and twist.

    Attributes
    ----------
    K : ndarray, shape (n_steps, 6, 6)
        K_load = dw/d(dx, dphi) at held twist and acceleration; rows (force N, moment N m)
        in C, columns (m, rad).
    D : ndarray, shape (n_steps, 6, 6)
        D_load = dw/d(v, omega), N s/m, N m s/rad.
    """

    K: np.ndarray
    D: np.ndarray


def load_linearisation(
    R_PC: np.ndarray,
    twist: np.ndarray,
    twist_dot: np.ndarray,
    ship: ShipMotion,
    *,
    mass: float,
    I_PP: np.ndarray,
    f_P: np.ndarray | None = None,
    m_P: np.ndarray | None = None,
) -> LoadLinearisation:
    """K_load = dw/dq and D_load = dw/dnu of the required wrench w (eq. 15), at a series of steps.

    Parameters
    ----------
    R_PC : ndarray, shape (n_steps, 3, 3)
        R_P^C.
    twist : ndarray, shape (n_steps, 6)
        (v_PC, omega_PC) in C, m/s and rad/s.
    twist_dot : ndarray, shape (n_steps, 6)
        (a_PC, alpha_PC) in C, m/s^2 and rad/s^2 (held: the reference acceleration).
    ship : ShipMotion
        The ship's motion at the steps (omega_s, alpha_s in S, rad/s and rad/s^2).
    mass : float
        m, kg.
    I_PP : ndarray, shape (3, 3)
        Inertia about the centre of mass in P, kg m^2.
    f_P, m_P : ndarray, shape (n_steps, 3), optional
        A disturbance force (N) and moment (N m) given in P (it turns with the platform).

    Returns
    -------
    LoadLinearisation
        The position x_PC does not enter: the load's position dependence is the ship's
        Euler and centrifugal terms, m ([alpha_s x] + [omega_s x]^2), whatever x_PC.
    """
    R = np.asarray(R_PC, dtype=float)
    tw, td = np.asarray(twist, dtype=float), np.asarray(twist_dot, dtype=float)
    n = R.shape[0]
    ws, als = np.asarray(ship.omega_SO_S, dtype=float), np.asarray(ship.alpha_SO_S, dtype=float)
    w, al = tw[:, 3:], td[:, 3:]
    I_C = R @ np.asarray(I_PP, dtype=float) @ np.swapaxes(R, 1, 2)  # R I_PP R^T

    def IC(b):  # I_C b, (n, 3)
        return np.einsum("nab,nb->na", I_C, b)

    def G(b):  # d(I_C b)/dphi = I_C [b x] - [(I_C b) x]
        return I_C @ skew(b) - skew(IC(b))

    W = ws + w  # omega_s + omega_PC
    beta = al + als + np.cross(ws, w)  # alpha_PC + alpha_s + omega_s x omega_PC
    Sws, SW = skew(ws), skew(W)
    K = np.zeros((n, 6, 6))
    D = np.zeros((n, 6, 6))
    K[:, :3, :3] = mass * (skew(als) + Sws @ Sws)  # m ([alpha_s x] + [omega_s x]^2)
    K[:, 3:, 3:] = G(beta) + SW @ G(W)  # d(I_C beta + W x I_C W)/dphi
    D[:, :3, :3] = 2.0 * mass * Sws  # Coriolis, 2 m omega_s x v
    D[:, 3:, 3:] = I_C @ Sws + SW @ I_C - skew(IC(W))  # d(I_C beta + W x I_C W)/domega
    if f_P is not None:
        K[:, :3, 3:] += skew(np.einsum("nab,nb->na", R, np.asarray(f_P, dtype=float)))  # d(-R f_P)/dphi
    if m_P is not None:
        K[:, 3:, 3:] += skew(np.einsum("nab,nb->na", R, np.asarray(m_P, dtype=float)))
    return LoadLinearisation(K=K, D=D)


# -------------------------------------------------------------------- plan, scenario


@dataclass(frozen=True)
class PlanStiffness:
    """Stiffness, damping and inertia along a plan, in its controlled DOFs c (k of them).

    Each matrix is shaped (n_steps, k, k), rows and columns in the order of
    ``controlled`` (displacements dx m, dphi rad, in C; forces N, moments N m).

    Attributes
    ----------
    controlled : tuple of int
        Indices into (dx, dphi): (0, 2, 4) planar, (0, ..., 5) spatial.
    winches : {"tension", "length"}
        Tension-controlled (K_axial = 0) or length-controlled elastic cables.
    K_axial, K_geometric, K_load : ndarray
        The parts of K (module docstring).
    D : ndarray
        Cable damping (length-controlled) plus the load's D_load.
    M : ndarray
        M_s's controlled block, diag(m E, R_PC I_PP R_PC^T) (kg, kg m^2).
    Omega : ndarray
        The rotation vector's kinematic term diag(0, [omega_PC x]), 1/s.
    """

    controlled: tuple[int, ...]
    winches: str
    K_axial: np.ndarray
    K_geometric: np.ndarray
    K_load: np.ndarray
    D: np.ndarray
    M: np.ndarray
    Omega: np.ndarray

    @property
    def K(self) -> np.ndarray:
        """K_eff = K_axial + K_geometric + K_load, shape (n_steps, k, k)."""
        return self.K_axial + self.K_geometric + self.K_load

    @property
    def dof_names(self) -> tuple[str, ...]:
        return tuple(DOF_NAMES[j] for j in self.controlled)

    def frequencies(self) -> "NaturalFrequencies":
        """:func:`natural_frequencies` of K_eff and M."""
        return natural_frequencies(self.K, self.M)

    def state_matrix(self) -> np.ndarray:
        """:func:`state_matrix` of K_eff, D, M and Omega, shape (n_steps, 2k, 2k)."""
        return state_matrix(self.K, self.D, self.M, self.Omega)


def _ship_of(plan, scenario: "Scenario") -> ShipMotion:
    if getattr(plan, "base_model", "moving") == "fixed":
        return fixed_ship_motion(scenario, plan.t)
    return frame_ship_motion(scenario, plan.t)


def plan_stiffness(
    plan,
    scenario: "Scenario",
    *,
    winches: Winches = "tension",
    EA: float | np.ndarray | None = None,
    damping: float | np.ndarray | None = None,
    include_load: bool = True,
    reference_length: Literal["stretched", "unstretched"] = "stretched",
) -> PlanStiffness:
    """Stiffness, damping and inertia at every step of a plan, in its controlled DOFs.

    Parameters
    ----------
    plan : Plan
        From :func:`marinecdpr.plan` (read: ``t``, ``pose``, ``twist``, ``twist_dot``,
        ``tensions``, ``controlled``, ``base_model``); its tensions are the operating point.
    scenario : Scenario
        The plan's scenario (robot, ship motion, disturbance).
    winches : {"tension", "length"}
        "tension": the winches hold the tensions (K_axial = 0, no cable damping: the
        open loop the prototype flies with ideal cables). "length": elastic cables held at
        fixed unstretched lengths (K_axial and the cables' damping).
    EA : float or ndarray, shape (n_cables,), optional
        N; for "length", default the scenario's ``simulation.cables.stiffness_EA_N``.
    damping : float or ndarray, shape (n_cables,), optional
        N s/m; for "length", default the scenario's ``simulation.cables.damping_N_s_m``
        (for elastic cables, else 0).
    include_load : bool
        Add K_load, D_load (:func:`load_linearisation`).
    reference_length : {"stretched", "unstretched"}
        See :func:`cable_stiffness`.

    Returns
    -------
    PlanStiffness
        NaN at infeasible steps (NaN tensions).
    """
    if winches not in ("tension", "length"):
        raise ValueError(f"winches must be 'tension' or 'length', not {winches!r}")
    robot = scenario.robot
    cables = scenario.simulation.cables
    if winches == "length":
        if EA is None:
            EA = cables.stiffness_EA_N
        if EA is None:
            raise ValueError("length-controlled winches need the cables' EA: pass EA= or give "
                             "simulation.cables.stiffness_EA_N")
        if damping is None and cables.model != "ideal":
            damping = cables.damping_N_s_m
    else:
        EA, damping = None, None
    pose = np.asarray(plan.pose, dtype=float)
    R_PC = matrix_from_euler(pose[:, 3:])
    cs = cable_stiffness(pose[:, :3], R_PC, robot.frame_anchors, robot.platform_anchors, plan.tensions,
                         EA=EA, damping=damping, reference_length=reference_length)
    n = pose.shape[0]
    c = list(plan.controlled)
    K_load = np.zeros((n, 6, 6))
    D = cs.D
    if include_load:
        f_P = m_P = None
        if scenario.disturbance.frame == "P":
            f_P, m_P = evaluate_disturbance(scenario.disturbance, plan.t)
        load = load_linearisation(R_PC, plan.twist, plan.twist_dot, _ship_of(plan, scenario),
                                  mass=robot.mass_kg, I_PP=robot.inertia, f_P=f_P, m_P=m_P)
        K_load, D = load.K, D + load.D
    M = spatial_inertia(R_PC, robot.mass_kg, robot.inertia)
    Omega = np.zeros((n, 6, 6))
    Omega[:, 3:, 3:] = skew(np.asarray(plan.twist, dtype=float)[:, 3:])  # dphi' = domega + omega x dphi

    def cc(a):
        return np.ascontiguousarray(a[:, c][:, :, c])

    return PlanStiffness(controlled=tuple(c), winches=winches, K_axial=cc(cs.K_axial),
                         K_geometric=cc(cs.K_geometric), K_load=cc(K_load), D=cc(D), M=cc(M),
                         Omega=cc(Omega))


# ------------------------------------------------------------------ natural frequencies


@dataclass(frozen=True)
class NaturalFrequencies:
    """Undamped natural frequencies from M^-1 K at each step.

    Attributes
    ----------
    hz : ndarray, shape (n_steps, k)
        sqrt(lambda_j) / (2 pi), Hz, ascending; NaN where lambda_j is not real and positive.
    eigenvalues : ndarray, shape (n_steps, k), complex
        lambda_j of M^-1 K (rad^2/s^2), sorted by real part.
    modes : ndarray, shape (n_steps, k, k), complex
        Column j: the mode shape of lambda_j in the controlled DOFs (m, rad), unit norm.
    positive_definite : ndarray of bool, shape (n_steps,)
        Every lambda_j real and positive (K positive definite for a symmetric K): the
        platform returns to the pose from any small displacement, statically.
    """

    hz: np.ndarray
    eigenvalues: np.ndarray
    modes: np.ndarray
    positive_definite: np.ndarray


def natural_frequencies(K: np.ndarray, M: np.ndarray, *, rtol: float = 1e-8) -> NaturalFrequencies:
    """Natural frequencies f_j = sqrt(lambda_j(M^-1 K)) / (2 pi).

    Parameters
    ----------
    K : ndarray, shape (n_steps, k, k)
        Stiffness in the controlled DOFs (N/m, N/rad, N m/m, N m/rad).
    M : ndarray, shape (n_steps, k, k)
        Inertia in the same DOFs (kg, kg m^2).
    rtol : float
        An eigenvalue counts as real if |Im lambda| <= rtol max_j |lambda_j|, and as positive
        if Re lambda > rtol max_j |lambda_j|.

    Returns
    -------
    NaturalFrequencies
        Steps with NaN entries give NaN throughout.
    """
    K = np.asarray(K, dtype=float)
    M = np.asarray(M, dtype=float)
    n, k = K.shape[:2]
    good = np.isfinite(K).all(axis=(1, 2)) & np.isfinite(M).all(axis=(1, 2))
    lam = np.full((n, k), np.nan + 0j)
    vec = np.full((n, k, k), np.nan + 0j)
    if good.any():
        l, v = np.linalg.eig(np.linalg.solve(M[good], K[good]))  # M^-1 K
        order = np.argsort(l.real, axis=1, kind="stable")
        lam[good] = np.take_along_axis(l, order, axis=1)
        vec[good] = np.take_along_axis(v, order[:, None, :], axis=2)
    scale = np.nanmax(np.abs(lam), axis=1, initial=0.0)[:, None]
    ok = (np.abs(lam.imag) <= rtol * scale) & (lam.real > rtol * scale)
    hz = np.where(ok, np.sqrt(np.where(ok, lam.real, 0.0)) / (2.0 * np.pi), np.nan)
    return NaturalFrequencies(hz=hz, eigenvalues=lam, modes=vec, positive_definite=ok.all(axis=1) & good)


# ------------------------------------------------------------------ linearised open loop


def state_matrix(K: np.ndarray, D: np.ndarray, M: np.ndarray, Omega: np.ndarray | None = None) -> np.ndarray:
    """A = [[Omega, I], [-M^-1 K, -M^-1 D]]: the linearised dynamics s' = A s, s = (dq, dnu).

    Parameters
    ----------
    K, D, M : ndarray, shape (n_steps, k, k)
        Stiffness (N/m ... N m/rad), damping (N s/m ... N m s/rad), inertia (kg, kg m^2)
        in the controlled DOFs.
    Omega : ndarray, shape (n_steps, k, k), optional
        dq' = Omega dq + dnu (the rotation vector's kinematics, 1/s); default 0.

    Returns
    -------
    A : ndarray, shape (n_steps, 2k, 2k)
        1/s and 1/s^2 blocks.
    """
    K, D, M = (np.asarray(a, dtype=float) for a in (K, D, M))
    n, k = K.shape[:2]
    A = np.zeros((n, 2 * k, 2 * k))
    if Omega is not None:
        A[:, :k, :k] = Omega
    A[:, :k, k:] = np.eye(k)
    A[:, k:, :k] = -np.linalg.solve(M, K)
    A[:, k:, k:] = -np.linalg.solve(M, D)
    return A


@dataclass(frozen=True)
class GrowthRate:
    """The linearised open loop's fastest growth along a plan.

    ``float(result)`` is ``rate``.

    Attributes
    ----------
    rate : float
        max over the steps of max Re(eig A), 1/s; > 0: unstable (an error grows like
        exp(rate t)); about 0: neutral (undamped oscillation); < 0: damped.
    step : int
        Where it occurs (index into the plan).
    t : float
        Its time, s.
    pose : ndarray, shape (6,)
        The plan's pose there, (x, y, z, rx, ry, rz) in C, m and rad.
    eigenvalue : complex
        The eigenvalue, 1/s (imaginary part: the mode's oscillation, rad/s).
    dof_names : tuple of str
        The controlled DOFs, the order of ``mode``.
    mode : ndarray, shape (k,), complex
        The displacement part of the eigenvector (m, rad), phase turned so that its largest
        component is real and 1.
    dominant : tuple of str
        The DOFs carrying the mode: components at least 0.3 of the largest, rotations
        weighted by the platform's anchor radius (the displacement they cause at the
        anchors).
    rates : ndarray, shape (n_steps,)
        max Re(eig A) at each step, 1/s (NaN where the plan is infeasible).
    frequencies_hz : ndarray, shape (k,)
        Natural frequencies at the step (:func:`natural_frequencies`; NaN where
        M^-1 K_eff has no real positive eigenvalue).
    winches : str
    """

    rate: float
    step: int
    t: float
    pose: np.ndarray
    eigenvalue: complex
    dof_names: tuple[str, ...]
    mode: np.ndarray
    dominant: tuple[str, ...]
    rates: np.ndarray
    frequencies_hz: np.ndarray
    winches: str

    def __float__(self) -> float:
        return float(self.rate)

    @property
    def e_folding_time_s(self) -> float:
        """1 / rate, s (inf if the rate is not positive)."""
        return 1.0 / self.rate if self.rate > 0 else float("inf")

    @property
    def stability(self) -> str:
        """"unstable", "neutral" or "stable": the rate against the eigenvalue's size, with
        neutral meaning |rate| <= 1e-4 |eigenvalue| (an oscillation that grows or decays by
        less than e over 10^4 radians, some 1600 periods)."""
        tol = 1e-4 * max(abs(self.eigenvalue), 1e-12)
        return "unstable" if self.rate > tol else ("neutral" if self.rate >= -tol else "stable")

    def describe(self) -> str:
        """One line: the rate, where and what moves."""
        return (f"{self.winches}-controlled open loop {self.stability}: growth rate {self.rate:.4g} 1/s "
                f"(eigenvalue {self.eigenvalue:.4g}) at t = {self.t:.4g} s, mode in "
                f"{', '.join(self.dominant)}")


def open_loop_growth_rate(
    plan,
    scenario: "Scenario",
    winches: Winches = "tension",
    *,
    EA: float | np.ndarray | None = None,
    damping: float | np.ndarray | None = None,
    include_load: bool = True,
    stiffness: PlanStiffness | None = None,
) -> GrowthRate:
    """The largest real part of the linearised open loop's eigenvalues along a plan.

    Parameters
    ----------
    plan : Plan
        From :func:`marinecdpr.plan`.
    scenario : Scenario
        Its scenario.
    winches : {"tension", "length"}
        See :func:`plan_stiffness`; "tension" is the open loop the prototype flies with
        ideal cables (the plan's tensions held whatever the pose).
    EA, damping, include_load
        See :func:`plan_stiffness`.
    stiffness : PlanStiffness, optional
        Already computed (then the other options are not used).

    Returns
    -------
    GrowthRate
    """
    ps = stiffness if stiffness is not None else plan_stiffness(
        plan, scenario, winches=winches, EA=EA, damping=damping, include_load=include_load)
    A = ps.state_matrix()
    n, k2 = A.shape[:2]
    k = k2 // 2
    good = np.isfinite(A).all(axis=(1, 2))
    if not good.any():
        raise ValueError("the plan has no feasible step to linearise about")
    rates = np.full(n, np.nan)
    rates[good] = np.linalg.eigvals(A[good]).real.max(axis=1)
    i = int(np.nanargmax(rates))
    lam, vec = np.linalg.eig(A[i])
    j = int(np.argmax(lam.real))
    mode = vec[:k, j]
    big = int(np.argmax(np.abs(mode)))
    mode = mode / mode[big] if abs(mode[big]) > 0 else mode
    names = ps.dof_names
    radius = max(float(np.linalg.norm(scenario.robot.platform_anchors, axis=1).max()), 1e-3)
    weight = np.array([1.0 if d < 3 else radius for d in ps.controlled])
    size = np.abs(mode) * weight
    dominant = tuple(names[a] for a in np.argsort(-size) if size[a] >= 0.3 * size.max())
    freq = natural_frequencies(ps.K[i:i + 1], ps.M[i:i + 1]).hz[0]
    return GrowthRate(rate=float(rates[i]), step=i, t=float(plan.t[i]), pose=np.array(plan.pose[i], dtype=float),
                      eigenvalue=complex(lam[j]), dof_names=names, mode=mode, dominant=dominant, rates=rates,
                      frequencies_hz=freq, winches=ps.winches)
