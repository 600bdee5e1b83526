"""The virtual prototype: a plan flown on a physics plant, open or closed loop.

Like the paper's co-simulation (its figure 4), the controller and the plant exchange
data once per time step (``time.step_s``, 1 ms): at t_k the controller reads the
plant's state (with sensor noise), commands cable tensions (or a winch's unstretched
length), the cable/actuator model turns the command into applied tensions, and the
plant advances one step with those tensions held.

Plants (``simulation.plant``):
  ``mujoco``  the independent engine (:mod:`~marinecdpr.prototype.mujoco_model`), the default;
  ``own``     this package's forward dynamics (:func:`~marinecdpr.model.kernels.forward_step`),
              integrated with classic RK4 on the platform's state relative to C.

Runs:
  ``open_loop``             the plan's tensions fed forward, as in the paper;
  ``closed_loop``           computed-torque feedback on the measured pose error, with the
                            scenario's tension method and the measured ship motion;
  ``fixed_base_open_loop``  the fixed-base (still ship) plan fed forward on the moving ship.

Feed-forward tensions are the plan evaluated at mid-step, t_k + h/2, so that holding
them over the step is second-order accurate.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np
from numba import njit, types

from marinecdpr.model import kernels as K
from marinecdpr.motion.basemotion import evaluate_base_motion
from marinecdpr.model.dynamics import disturbance_in_C
from marinecdpr.errors import InfeasibleError, SimulationDivergedError
from marinecdpr.planning.planner import Plan, plan_at
from marinecdpr.geometry.rotations import matrix_from_euler
from marinecdpr.scenario.schema import Scenario
from marinecdpr.motion.trajectory import evaluate_disturbance

__all__ = ["RUNS", "SimResult", "simulate", "kernels_cached", "KERNEL_COMPILE_S"]

RUNS = ("open_loop", "closed_loop", "fixed_base_open_loop")
_cache = True
DIVERGENCE_M = 10.0
"""A run stops as diverged when the platform is this far from its plan."""
SHIP_SERVO_HZ = 10.0
"""Bandwidth of the servo that keeps the heavy MuJoCo ship on its prescribed motion."""


@dataclass(frozen=True)
class SimResult:
    """One simulated run. Arrays share the first axis ``n_steps`` (times ``t``).

    Attributes
    ----------
    run, plant : str
    t : ndarray, shape (n_steps,)
    pose_planned, pose : ndarray, shape (n_steps, 6)
        Planned and actual (x, y, z, rx, ry, rz) of P in C, m and rad.
    lengths_planned, lengths : ndarray, shape (n_steps, n_cables)
        Planned and actual cable lengths, m.
    tensions_commanded, tensions : ndarray, shape (n_steps, n_cables)
        What the controller commanded and what the cables applied, N.
    controller_fallbacks : int
        Closed-loop steps where the per-step tension problem had no solution within
        limits and the feed-forward tensions were commanded instead.
    ship_tracking_error : float
        Largest deviation of the plant's ship from its prescribed motion (m or rad;
        0 for the own plant, which moves the ship exactly).
    """

    run: str
    plant: str
    t: np.ndarray
    pose_planned: np.ndarray
    pose: np.ndarray
    lengths_planned: np.ndarray
    lengths: np.ndarray
    tensions_commanded: np.ndarray
    tensions: np.ndarray
    controller_fallbacks: int
    ship_tracking_error: float

    @property
    def pose_error(self) -> np.ndarray:
        """Actual minus planned pose, shape (n_steps, 6), m and rad."""
        return self.pose - self.pose_planned


# ----------------------------------------------------------------- compiled parts
@njit(cache=_cache)
def _mm3(A, B, out, transpose_B=False):
    """out = A @ B (or A @ B^T) for 3x3 matrices, without BLAS's per-call cost."""
    for i in range(3):
        for j in range(3):
            acc = 0.0
            for k in range(3):
                acc += A[i, k] * (B[j, k] if transpose_B else B[k, j])
            out[i, j] = acc


@njit(cache=_cache)
def _euler_from_R(R, out):
    out[0] = np.arctan2(R[2, 1], R[2, 2])
    out[1] = np.arcsin(min(1.0, max(-1.0, -R[2, 0])))
    out[2] = np.arctan2(R[1, 0], R[0, 0])


@njit(cache=_cache)
def _command(k, h, x, R, v, w, L, Ldot, ref_x, ref_R, ref_v, ref_w, ref_a, ref_al, T_ff, L_ff, Ld_ff,
             closed, kp, kd, eta_m, noise_pose, noise_twist, noise_T, f_C, m_C, dist_P,
             c_C, p_P, mass, I_PP, g, origin, controlled, lo, hi, method,
             cable_model, EA, damping, winch, lag, tau, L0, T_state, T_cmd, T_app):
    """One exchange: controller command, then the cable/actuator model. Returns 1 on fallback.

    The ``ref_*`` arrays hold the plan at mid-step, t_k + h/2. ``f_C``, ``m_C`` hold the
    disturbance in C, or in P if ``dist_P`` (then turned with the measured orientation).
    """
    n = c_C.shape[0]
    fallback = 0
    if closed:
        # what the sensors report at t_k ...
        x_m = x + noise_pose[k, :3]
        Rn = np.empty((3, 3))
        tmp = np.empty(3)
        K.euler_step(noise_pose[k, 3:], np.zeros(3), np.zeros(3), Rn, tmp, tmp)
        R_m = np.empty((3, 3))
        _mm3(Rn, R, R_m)
        v_m = v + noise_twist[k, :3]
        w_m = w + noise_twist[k, 3:]
        # ... predicted to mid-step, where the held command acts on average
        hh = 0.5 * h
        x_m = x_m + hh * v_m
        v_m = v_m + hh * ref_a[k]
        Wx = np.array([[0.0, -w_m[2], w_m[1]], [w_m[2], 0.0, -w_m[0]], [-w_m[1], w_m[0], 0.0]])
        WR = np.empty((3, 3))
        _mm3(Wx, R_m, WR)
        R_m = R_m + hh * WR
        w_m = w_m + hh * ref_al[k]
        eta_p = eta_m[0, k] + hh * eta_m[1, k]
        deta_p = eta_m[1, k] + hh * eta_m[2, k]
        R_SO = np.empty((3, 3))
        w_s = np.empty(3)
        al_s = np.empty(3)
        K.euler_step(eta_p[3:], deta_p[3:], eta_m[2, k, 3:], R_SO, w_s, al_s)
        # computed torque on the mid-step reference: a = a_ref + Kd e_v + Kp e, rotation error in C
        E = np.empty((3, 3))
        _mm3(ref_R[k], R_m, E, True)
        e_rot = 0.5 * np.array([E[2, 1] - E[1, 2], E[0, 2] - E[2, 0], E[1, 0] - E[0, 1]])
        a_cmd = ref_a[k] + kd * (ref_v[k] - v_m) + kp * (ref_x[k] - x_m)
        al_cmd = ref_al[k] + kd * (ref_w[k] - w_m) + kp * e_rot
        wr = np.empty(6)
        f_k, m_k = _disturbance_C(f_C[k], m_C[k], dist_P, R_m)
        K.wrench_step(x_m, v_m, a_cmd, R_m, w_m, al_cmd, R_SO, w_s, al_s, eta_m[2, k, :3], origin,
                      mass, I_PP, g, f_k, m_k, wr)
        L_m = np.empty(n)
        J = np.empty((n, 6))
        K.cables_step(x_m, R_m, c_C, p_P, L_m, J)
        # every method, exact for any redundancy, compiled (the planning layer's solvers)
        ok = K.tensions_step(J, wr, controlled, lo, hi, method, T_cmd)
        if not ok:
            T_cmd[:] = T_ff[k]
            fallback = 1
    else:
        T_cmd[:] = T_ff[k]
    # a length-controlled winch pays out the reference length less the stretch the
    # commanded tension needs: the cable's stiffness holds the plan, T_cmd corrects it
    # (the cable's damping adds c L' of the plan: the stretch makes the rest)
    L0_cmd = L_ff[k] / (1.0 + (T_cmd - damping * Ld_ff[k]) / EA)
    if closed and tau > 0.0:
        # the controller knows its winches' lag: it leads the planned part of the command
        # by tau times the plan's (smooth) rate, u = r + tau r'
        kf, kb = min(k + 1, T_ff.shape[0] - 1), max(k - 1, 0)
        dt = (kf - kb) * h
        if winch == 1:
            T_cmd += tau * (T_ff[kf] - T_ff[kb]) / dt
            for i in range(n):  # a command stays within the cable's limits
                T_cmd[i] = min(max(T_cmd[i], lo[i]), hi[i])
        else:
            L0_cmd += tau * (L_ff[kf] / (1.0 + (T_ff[kf] - damping * Ld_ff[kf]) / EA)
                             - L_ff[kb] / (1.0 + (T_ff[kb] - damping * Ld_ff[kb]) / EA)) / dt
    if cable_model == 0:
        T_app[:] = T_cmd
    elif winch == 0:
        # the winch pays out L0 (with a first-order lag); the elastic cable makes the tension
        for i in range(n):
            L0[i] += lag * (L0_cmd[i] - L0[i])
            if L[i] > L0[i]:
                T_app[i] = max(0.0, EA * (L[i] - L0[i]) / L0[i] + damping * Ldot[i])
            else:
                T_app[i] = 0.0  # slack
    else:
        # the winch drives its (noisy) tension sensor to the command
        for i in range(n):
            T_state[i] += lag * (T_cmd[i] - noise_T[k, i] - T_state[i])
            T_app[i] = max(0.0, T_state[i])
    return fallback


@njit(cache=_cache)
def _disturbance_C(f, m, dist_P, R):
    """The disturbance in C: (f, m) as given if in C, R (f, m) if given in P."""
    if not dist_P:
        return f, m
    return R @ f, R @ m


@njit(cache=_cache)
def _length_rates(J, v, w):
    """l' = -J~ (v, omega) (eq. 5)."""
    out = np.empty(J.shape[0])
    for i in range(J.shape[0]):
        out[i] = -(J[i, 0] * v[0] + J[i, 1] * v[1] + J[i, 2] * v[2]
                   + J[i, 3] * w[0] + J[i, 4] * w[1] + J[i, 5] * w[2])
    return out


@njit(cache=_cache)
def _log(k, x, R, L, T_cmd, T_app, pose_log, len_log, Tcmd_log, Tapp_log):
    pose_log[k, :3] = x
    e = np.empty(3)
    _euler_from_R(R, e)
    pose_log[k, 3:] = e
    len_log[k] = L
    Tcmd_log[k] = T_cmd
    Tapp_log[k] = T_app


@njit(cache=_cache)
def _diverged(x, ref_x):
    d = 0.0
    for i in range(3):
        if not np.isfinite(x[i]):
            return True
        d = max(d, abs(x[i] - ref_x[i]))
    return d > DIVERGENCE_M


@njit(cache=_cache)
def _mujoco_exchange(k, h, qpos, qvel, ctrl, qfrc, xfrc, ten_k, ten_spring, ten_c, planar, pq, pd,
                     ship_dofs, body, ship_err,
                     tau_ff, q_des, qd_des, kp_s, kd_s, f_O, m_O, R_SO_k,
                     ref_x, ref_R, ref_v, ref_w, ref_a, ref_al, T_ff, L_ff, Ld_ff,
                     closed, kp, kd, eta_m, noise_pose, noise_twist, noise_T, f_C, m_C, dist_P,
                     c_C, p_P, mass, I_PP, g, origin, controlled, lo, hi, method,
                     cable_model, EA, damping, winch, lag, tau, L0, T_state, T_cmd, T_app,
                     pose_log, len_log, Tcmd_log, Tapp_log):
    """Read MuJoCo's state, command, write ctrl and the ship's drive. Returns -1 if diverged."""
    x = np.zeros(3)
    v = np.zeros(3)
    w = np.zeros(3)
    R = np.empty((3, 3))
    if planar:
        x[0], x[2] = qpos[pq[0]], qpos[pq[1]]
        th = qpos[pq[2]]
        c, s = np.cos(th), np.sin(th)
        R[0, 0], R[0, 1], R[0, 2] = c, 0.0, s
        R[1, 0], R[1, 1], R[1, 2] = 0.0, 1.0, 0.0
        R[2, 0], R[2, 1], R[2, 2] = -s, 0.0, c
        v[0], v[2] = qvel[pd[0]], qvel[pd[1]]
        w[1] = qvel[pd[2]]
    else:
        for i in range(3):
            x[i] = qpos[pq[i]]
            v[i] = qvel[pd[i]]
        q = np.array([qpos[pq[3]], qpos[pq[4]], qpos[pq[5]], qpos[pq[6]]])
        _quat_to_R(q / np.sqrt(np.sum(q * q)), R)
        for i in range(3):  # the ball's angular velocity is in the platform frame
            w[i] = R[i, 0] * qvel[pd[3]] + R[i, 1] * qvel[pd[4]] + R[i, 2] * qvel[pd[5]]
    if _diverged(x, ref_x[k]):
        return -1
    n = c_C.shape[0]
    L = np.empty(n)
    J = np.empty((n, 6))
    K.cables_step(x, R, c_C, p_P, L, J)
    Ldot = _length_rates(J, v, w)
    fb = _command(k, h, x, R, v, w, L, Ldot, ref_x, ref_R, ref_v, ref_w, ref_a, ref_al, T_ff, L_ff, Ld_ff,
                  closed, kp, kd, eta_m, noise_pose, noise_twist, noise_T, f_C, m_C, dist_P,
                  c_C, p_P, mass, I_PP, g, origin, controlled, lo, hi, method,
                  cable_model, EA, damping, winch, lag, tau, L0, T_state, T_cmd, T_app)
    _log(k, x, R, L, T_cmd, T_app, pose_log, len_log, Tcmd_log, Tapp_log)
    if cable_model == 1 and winch == 0:
        # the cable is a spring MuJoCo integrates: taut above L0 (dead band [0, L0])
        ctrl[:] = 0.0
        for i in range(n):
            ten_k[i] = EA / L0[i]
            ten_spring[i, 0] = 0.0
            ten_spring[i, 1] = L0[i]
            ten_c[i] = damping if L[i] > L0[i] else 0.0
    else:
        ctrl[:] = T_app
    for j in range(6):
        dof = ship_dofs[j]
        ship_err[0] = max(ship_err[0], abs(qpos[dof] - q_des[k, j]))
        qfrc[dof] = (tau_ff[k, j] + kp_s[j] * (q_des[k, j] - qpos[dof])
                     + kd_s[j] * (qd_des[k, j] - qvel[dof]))
    if dist_P:  # a load fixed to the platform turns with its actual orientation
        R_PO = R_SO_k[k] @ R
        xfrc[body, :3] = R_PO @ f_C[k]
        xfrc[body, 3:] = R_PO @ m_C[k]
    else:
        xfrc[body, :3] = f_O[k]
        xfrc[body, 3:] = m_O[k]
    return fb


@njit(cache=_cache)
def _quat_to_R(q, R):
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


@njit(cache=_cache)
def _own_rhs(y, T_held, j, R_SO_h, w_s_h, al_s_h, a_SO_h, f_C_h, m_C_h, dist_P, c_C, p_P, mass, I_PP, g,
             origin, controlled, springs, EA, damping, L0, dy):
    """d/dt of y = (x, quaternion of R_PC, v, omega) in C.

    Tensions are held over the step, except elastic cables on length-controlled winches
    (``springs``): their tension follows the state, with the winch's L0 held.
    """
    x, q, v, w = y[0:3], y[3:7], y[7:10], y[10:13]
    q = q / np.sqrt(np.sum(q * q))
    R = np.empty((3, 3))
    _quat_to_R(q, R)
    n = c_C.shape[0]
    L = np.empty(n)
    J = np.empty((n, 6))
    K.cables_step(x, R, c_C, p_P, L, J)
    T = T_held
    if springs:
        T = np.zeros(n)
        Ldot = _length_rates(J, v, w)
        for i in range(n):
            if L[i] > L0[i]:
                T[i] = max(0.0, EA * (L[i] - L0[i]) / L0[i] + damping * Ldot[i])
    bias = np.empty(6)
    zero = np.zeros(3)
    f_j, m_j = _disturbance_C(f_C_h[j], m_C_h[j], dist_P, R)
    K.wrench_step(x, v, zero, R, w, zero, R_SO_h[j], w_s_h[j], al_s_h[j], a_SO_h[j], origin,
                  mass, I_PP, g, f_j, m_j, bias)
    acc = np.empty(6)
    K.forward_step(J, T, bias, R, mass, I_PP, controlled, acc)
    dy[0:3] = v
    # q' = 1/2 (0, omega) * q with omega in the parent frame C
    dy[3] = -0.5 * (w[0] * q[1] + w[1] * q[2] + w[2] * q[3])
    dy[4] = 0.5 * (w[0] * q[0] + w[1] * q[3] - w[2] * q[2])
    dy[5] = 0.5 * (w[1] * q[0] + w[2] * q[1] - w[0] * q[3])
    dy[6] = 0.5 * (w[2] * q[0] + w[0] * q[2] - w[1] * q[1])
    dy[7:10] = acc[:3]
    dy[10:13] = acc[3:]


@njit(cache=_cache)
def _own_loop(k0, k1, y, h, R_SO_h, w_s_h, al_s_h, a_SO_h, f_Ch, m_Ch,
              ref_x, ref_R, ref_v, ref_w, ref_a, ref_al, T_ff, L_ff, Ld_ff,
              closed, kp, kd, eta_m, noise_pose, noise_twist, noise_T, f_C, m_C, dist_P,
              c_C, p_P, mass, I_PP, g, origin, controlled, lo, hi, method,
              cable_model, EA, damping, winch, lag, tau, L0, T_state, T_cmd, T_app,
              pose_log, len_log, Tcmd_log, Tapp_log):
    """Steps k0..k1-1 of the own plant (RK4). Returns (fallbacks, -1 or the diverged step)."""
    n = c_C.shape[0]
    R = np.empty((3, 3))
    L = np.empty(n)
    J = np.empty((n, 6))
    k1_, k2_, k3_, k4_ = np.empty(13), np.empty(13), np.empty(13), np.empty(13)
    fallbacks = 0
    for k in range(k0, k1):
        _quat_to_R(y[3:7], R)
        x, v, w = y[0:3], y[7:10], y[10:13]
        if _diverged(x, ref_x[k]):
            return fallbacks, k
        K.cables_step(x, R, c_C, p_P, L, J)
        Ldot = _length_rates(J, v, w)
        fallbacks += _command(k, h, x.copy(), R, v.copy(), w.copy(), L, Ldot, ref_x, ref_R, ref_v,
                              ref_w, ref_a, ref_al, T_ff, L_ff, Ld_ff, closed, kp, kd, eta_m, noise_pose,
                              noise_twist, noise_T, f_C, m_C, dist_P, c_C, p_P, mass, I_PP, g, origin,
                              controlled, lo, hi, method, cable_model, EA, damping, winch, lag,
                              tau, L0, T_state, T_cmd, T_app)
        _log(k, x, R, L, T_cmd, T_app, pose_log, len_log, Tcmd_log, Tapp_log)
        j = 2 * k
        springs = cable_model == 1 and winch == 0
        _own_rhs(y, T_app, j, R_SO_h, w_s_h, al_s_h, a_SO_h, f_Ch, m_Ch, dist_P, c_C, p_P, mass, I_PP, g,
                 origin, controlled, springs, EA, damping, L0, k1_)
        _own_rhs(y + 0.5 * h * k1_, T_app, j + 1, R_SO_h, w_s_h, al_s_h, a_SO_h, f_Ch, m_Ch, dist_P, c_C,
                 p_P, mass, I_PP, g, origin, controlled, springs, EA, damping, L0, k2_)
        _own_rhs(y + 0.5 * h * k2_, T_app, j + 1, R_SO_h, w_s_h, al_s_h, a_SO_h, f_Ch, m_Ch, dist_P, c_C,
                 p_P, mass, I_PP, g, origin, controlled, springs, EA, damping, L0, k3_)
        _own_rhs(y + h * k3_, T_app, j + 2, R_SO_h, w_s_h, al_s_h, a_SO_h, f_Ch, m_Ch, dist_P, c_C, p_P,
                 mass, I_PP, g, origin, controlled, springs, EA, damping, L0, k4_)
        y += (h / 6.0) * (k1_ + 2.0 * k2_ + 2.0 * k3_ + k4_)
        y[3:7] /= np.sqrt(np.sum(y[3:7] * y[3:7]))
    return fallbacks, -1


# ------------------------------------------------------------------- orchestration
def _quat_from_R(R: np.ndarray) -> np.ndarray:
    """Unit quaternion (w, x, y, z) of a rotation matrix (Shepperd's method)."""
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


def simulate(
    scenario: Scenario,
    *,
    run: str = "open_loop",
    reference: Plan | None = None,
    plant: str | None = None,
    n_steps: int | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> SimResult:
    """Fly the scenario's plan on a physics plant.

    Parameters
    ----------
    scenario : Scenario
    run : {"open_loop", "closed_loop", "fixed_base_open_loop"}
    reference : Plan, optional
        The moving-base plan (``marinecdpr.plan(scenario)``) if already computed.
    plant : {"mujoco", "own"}, optional
        Default ``scenario.simulation.plant``.
    n_steps : int, optional
        Simulate only the first steps (short horizons in tests).
    progress : callable(done, total), optional
        Called every few hundred steps.

    Returns
    -------
    SimResult

    Raises
    ------
    InfeasibleError
        If the plan to fly (moving-base, or fixed-base for that run) is infeasible.
    SimulationDivergedError
        If the platform ends up more than 10 m from its plan or its state is not finite.
    ScenarioError
        If the run would not fit in memory (:func:`marinecdpr.planning.budget.check_run_size`).
    """
    from marinecdpr.planning.budget import check_run_size

    if run not in RUNS:
        raise ValueError(f"run must be one of {', '.join(RUNS)}, not {run!r}")
    sim = scenario.simulation
    plant = plant or sim.plant
    if plant not in ("mujoco", "own"):
        raise ValueError(f"plant must be 'mujoco' or 'own', not {plant!r}")
    robot = scenario.robot
    h = scenario.time.step_s
    n = scenario.time.n_steps if n_steps is None else min(n_steps, scenario.time.n_steps)
    check_run_size(scenario, "simulate", n_steps=n)  # before any array of n steps
    t = np.arange(n) * h
    method = scenario.planning.method
    ref = reference if reference is not None else plan_at(scenario, t, method=method)
    base_model = "fixed" if run == "fixed_base_open_loop" else "moving"
    ff = plan_at(scenario, t + 0.5 * h, method=method, base_model=base_model)
    for p in (ref, ff):
        if not p.feasible[:n].all():
            raise InfeasibleError(f"{scenario.name}: cannot simulate the {p.base_model}-base plan: "
                                  f"{p.infeasibility()}")
    mid_pose = np.ascontiguousarray(ff.pose)
    mid_twist = np.ascontiguousarray(ff.twist)
    mid_acc = np.ascontiguousarray(ff.twist_dot)
    mid_R = np.ascontiguousarray(matrix_from_euler(mid_pose[:, 3:]))
    T_ff = np.ascontiguousarray(ff.tensions)
    L_ff = np.ascontiguousarray(ff.lengths)
    Ld_ff = np.ascontiguousarray(ff.length_rates)

    # ship motion on the half-step grid: j = 2k is t_k, j = 2k + 1 is t_k + h/2
    t_half = np.arange(2 * n + 1) * (0.5 * h)
    ship_h = evaluate_base_motion(scenario.base_motion, t_half)
    dist_f, dist_m = evaluate_disturbance(scenario.disturbance, t_half)
    # loads given in O turn into C with the ship's motion; loads given in P stay in P and the
    # plant and the controller turn them with the platform's actual (measured) orientation
    dist_P = scenario.disturbance.frame == "P"
    if dist_P:
        f_C_h, m_C_h = dist_f, dist_m
    else:
        f_C_h, m_C_h = disturbance_in_C(dist_f, dist_m, scenario.disturbance.frame, ship_h.R_SO, None)
    f_C_h, m_C_h = np.ascontiguousarray(f_C_h, dtype=float), np.ascontiguousarray(m_C_h, dtype=float)

    # sensors
    rng = np.random.default_rng(sim.noise.seed)
    nz = sim.noise
    deg = np.pi / 180.0
    closed = run == "closed_loop"
    noise_pose = np.zeros((n, 6))
    noise_twist = np.zeros((n, 6))
    eta = np.stack([ship_h.eta[::2], ship_h.eta_dot[::2], ship_h.eta_ddot[::2]])[:, :n].copy()
    if closed:
        noise_pose[:, :3] = rng.normal(0.0, nz.pose_m, (n, 3))
        noise_pose[:, 3:] = rng.normal(0.0, nz.pose_deg * deg, (n, 3))
        noise_twist[:, :3] = rng.normal(0.0, nz.velocity_m_s, (n, 3))
        noise_twist[:, 3:] = rng.normal(0.0, nz.rate_deg_s * deg, (n, 3))
        for i, (s_lin, s_ang) in enumerate(((nz.ship_position_m, nz.ship_angle_deg * deg),
                                            (nz.ship_velocity_m_s, nz.ship_rate_deg_s * deg),
                                            (nz.ship_acceleration_m_s2,
                                             nz.ship_angular_acceleration_deg_s2 * deg))):
            eta[i, :, :3] += rng.normal(0.0, s_lin, (n, 3))
            eta[i, :, 3:] += rng.normal(0.0, s_ang, (n, 3))
    noise_T = rng.normal(0.0, nz.tension_N, (n, robot.n_cables))
    f_C = np.ascontiguousarray(f_C_h[::2][:n])
    m_C = np.ascontiguousarray(m_C_h[::2][:n])

    # controller and cables
    wn = 2.0 * np.pi * sim.control.bandwidth_hz
    kp, kd = wn * wn, 2.0 * sim.control.damping_ratio * wn
    cab = sim.cables
    cable_model = 1 if cab.model == "elastic" else 0
    EA = float(cab.stiffness_EA_N or np.inf)
    winch = 1 if cab.winch == "tension" else 0
    lag = 1.0 if cab.winch_time_constant_s == 0 else float(-np.expm1(-h / cab.winch_time_constant_s))
    c_C = np.ascontiguousarray(robot.frame_anchors)
    p_P = np.ascontiguousarray(robot.platform_anchors)
    I_PP = np.ascontiguousarray(robot.inertia)
    origin = np.asarray(scenario.ship.frame_origin_m, dtype=float)
    controlled = np.asarray(robot.controlled, dtype=np.int64)
    lo, hi = robot.tension_min, robot.tension_max
    g = scenario.environment.gravity_m_s2
    method_code = K.METHOD_CODES[method]

    # initial state: on the plan, plus the scenario's initial error
    ref_pose = np.ascontiguousarray(ref.pose[:n])
    err_R = matrix_from_euler(np.radians(sim.initial_error_deg))
    x0 = ref_pose[0, :3] + np.asarray(sim.initial_error_m)
    R0 = err_R @ matrix_from_euler(ref_pose[0, 3:])
    v0, w0 = ref.twist[0, :3].copy(), ref.twist[0, 3:].copy()
    L_init = np.empty(robot.n_cables)
    K.cables_step(x0, R0, c_C, p_P, L_init, np.empty((robot.n_cables, 6)))
    L0 = L_init / (1.0 + (T_ff[0] - cab.damping_N_s_m * Ld_ff[0]) / EA)
    T_state = T_ff[0].copy()
    T_cmd = np.empty(robot.n_cables)
    T_app = np.empty(robot.n_cables)
    m = robot.n_cables
    pose_log, len_log = np.empty((n, 6)), np.empty((n, m))
    Tcmd_log, Tapp_log = np.empty((n, m)), np.empty((n, m))

    shared = (mid_pose[:, :3], mid_R, mid_twist[:, :3], mid_twist[:, 3:], mid_acc[:, :3], mid_acc[:, 3:],
              T_ff, L_ff, Ld_ff, closed, kp, kd, eta, noise_pose, noise_twist, noise_T, f_C, m_C, dist_P,
              c_C, p_P, robot.mass_kg, I_PP, g, origin, controlled, lo, hi, method_code,
              cable_model, EA, cab.damping_N_s_m, winch, lag, float(cab.winch_time_constant_s),
              L0, T_state, T_cmd, T_app,
              pose_log, len_log, Tcmd_log, Tapp_log)
    chunk = 500
    fallbacks = 0
    ship_error = 0.0  # the own plant moves the ship exactly
    if plant == "own":
        y = np.concatenate([x0, _quat_from_R(R0), v0, w0])
        halves = (np.ascontiguousarray(ship_h.R_SO), np.ascontiguousarray(ship_h.omega_SO_S),
                  np.ascontiguousarray(ship_h.alpha_SO_S), np.ascontiguousarray(ship_h.a_SO_O),
                  f_C_h, m_C_h)
        for k0 in range(0, n, chunk):
            fb, bad = _own_loop(k0, min(n, k0 + chunk), y, h, *halves, *shared)
            fallbacks += fb
            if bad >= 0:
                raise SimulationDivergedError(_diverged_message(scenario, run, t[bad]))
            if progress is not None:
                progress(min(n, k0 + chunk), n)
    else:
        fallbacks, ship_error = _run_mujoco(scenario, run, n, t, h, ship_h, x0, R0, v0, w0, f_C, m_C,
                                            shared, progress)
    pose_log[:, 3:] = np.unwrap(pose_log[:, 3:], axis=0)
    return SimResult(
        run=run, plant=plant, t=t, pose_planned=ref_pose, pose=pose_log,
        lengths_planned=np.ascontiguousarray(ref.lengths[:n]), lengths=len_log,
        tensions_commanded=Tcmd_log, tensions=Tapp_log, controller_fallbacks=int(fallbacks),
        ship_tracking_error=ship_error,
    )


KERNEL_COMPILE_S = 30.0
"""About how long the first simulation compiles its loop on a fresh install, s (README)."""


def kernels_cached(plant: str) -> bool:
    """False if simulating on ``plant`` must first compile its loop: neither this process nor
    numba's cache (an index for the current source with an entry) holds it. True when unsure
    (numba's cache internals changed): no notice rather than a wrong one."""
    try:
        if plant == "own":
            loop = _own_loop
        elif _mujoco_library():
            loop = _compiled_loop
        else:  # MuJoCo's library not found: the loop runs in Python, each exchange compiled
            loop = _exchange_args
        return bool(loop.signatures) or bool(loop._cache._cache_file._load_index())
    except Exception:  # noqa: BLE001 - a private numba API
        return True


def _diverged_message(scenario: Scenario, run: str, t: float) -> str:
    return (f"{scenario.name}: {run} diverged at t = {t:.3f} s: the platform is more than "
            f"{DIVERGENCE_M:g} m from its plan or its state is not finite")


def _mujoco_library() -> bool:
    """Make MuJoCo's C library known to numba by name; False if it cannot be found."""
    import glob
    import os

    import mujoco
    from llvmlite import binding

    libs = glob.glob(os.path.join(os.path.dirname(mujoco.__file__), "libmujoco.so*"))
    if not libs or not hasattr(mujoco.MjModel, "_address"):
        return False
    binding.load_library_permanently(libs[0])
    return True


# mj_step(const mjModel*, mjData*), resolved by symbol name so that the loop can be cached;
# the pointers travel as 64-bit integers (the same in the C calling convention)
_c_mj_step = types.ExternalFunction("mj_step", types.void(types.uint64, types.uint64))


@njit(cache=_cache)
def _compiled_loop(k0, k1, model_addr, data_addr, h, args):
    """Exchange and step, k0..k1-1, all compiled. Returns (fallbacks, -1 or the diverged step)."""
    fallbacks = 0
    for k in range(k0, k1):
        fb = _mujoco_exchange(k, h, *args)  # direct: one compiled call level less
        if fb < 0:
            return fallbacks, k
        fallbacks += fb
        _c_mj_step(model_addr, data_addr)
    return fallbacks, -1


@njit(cache=_cache)
def _exchange_args(k, h, a):
    return _mujoco_exchange(k, h, *a)


def _run_mujoco(scenario, run, n, t, h, ship_h, x0, R0, v0, w0, f_C, m_C, shared, progress):
    import mujoco

    from marinecdpr.prototype.mujoco_model import SHIP_INERTIA_KG_M2, SHIP_MASS_KG, build_model

    mm = build_model(scenario)
    model = mm.model
    data = mujoco.MjData(model)
    perm = [0, 1, 2, 5, 4, 3]  # eta (x, y, z, roll, pitch, yaw) -> joints (x, y, z, yaw, pitch, roll)
    # feed-forward forces that move the (gravity-compensated, isotropic) ship along eta,
    # evaluated at mid-step; the servo acts on the error at the step's start
    mid = slice(1, 2 * n, 2)
    R_mid = ship_h.R_SO[mid]
    alpha_O = np.einsum("nij,nj->ni", R_mid, ship_h.alpha_SO_S[mid])
    yaw = ship_h.eta[mid][:, 5]
    axes = np.stack([np.broadcast_to([0.0, 0.0, 1.0], (n, 3)),
                     np.stack([-np.sin(yaw), np.cos(yaw), np.zeros(n)], axis=1),
                     R_mid[:, :, 0]], axis=1)  # yaw, pitch, roll axes in O
    tau_ff = np.empty((n, 6))
    tau_ff[:, :3] = SHIP_MASS_KG * ship_h.a_SO_O[mid]
    tau_ff[:, 3:] = SHIP_INERTIA_KG_M2 * np.einsum("nja,na->nj", axes, alpha_O)
    q_des = np.ascontiguousarray(ship_h.eta[0:2 * n:2][:, perm])
    qd_des = np.ascontiguousarray(ship_h.eta_dot[0:2 * n:2][:, perm])
    wn = 2.0 * np.pi * SHIP_SERVO_HZ
    inertia = np.array([SHIP_MASS_KG] * 3 + [SHIP_INERTIA_KG_M2] * 3)
    kp_s, kd_s = inertia * wn * wn, inertia * 2.0 * wn
    # the plant applies the disturbance in O (one given in P is turned at each exchange)
    R_SO = np.ascontiguousarray(ship_h.R_SO[0:2 * n:2])
    f_O = np.ascontiguousarray(np.einsum("nij,nj->ni", R_SO, f_C))
    m_O = np.ascontiguousarray(np.einsum("nij,nj->ni", R_SO, m_C))

    ship_dofs = mm.ship_dofs.astype(np.int64)
    data.qpos[ship_dofs] = q_des[0]
    data.qvel[ship_dofs] = qd_des[0]
    planar = scenario.robot.dofs == "planar"
    pq, pd = mm.platform_qpos.astype(np.int64), mm.platform_dofs.astype(np.int64)
    if planar:
        data.qpos[pq] = [x0[0], x0[2], np.arctan2(R0[0, 2], R0[0, 0])]
        data.qvel[pd] = [v0[0], v0[2], w0[1]]
    else:
        data.qpos[pq[:3]] = x0
        data.qpos[pq[3:]] = _quat_from_R(R0)
        data.qvel[pd[:3]] = v0
        data.qvel[pd[3:]] = R0.T @ w0
    fallbacks = 0
    ship_err = np.zeros(1)
    qpos, qvel, ctrl, qfrc, xfrc = data.qpos, data.qvel, data.ctrl, data.qfrc_applied, data.xfrc_applied
    ten_k, ten_spring, ten_c = model.tendon_stiffness, model.tendon_lengthspring, model.tendon_damping
    args = (qpos, qvel, ctrl, qfrc, xfrc, ten_k, ten_spring, ten_c, planar, pq, pd, ship_dofs,
            mm.platform_body, ship_err, tau_ff, q_des, qd_des, kp_s, kd_s, f_O, m_O, R_SO, *shared)
    compiled = _mujoco_library()
    every = 500
    for k0 in range(0, n, every):
        k1 = min(n, k0 + every)
        if compiled:
            fb, bad = _compiled_loop(k0, k1, model._address, data._address, h, args)
        else:  # the same, one Python call per step
            fb, bad = 0, -1
            for k in range(k0, k1):
                f = _exchange_args(k, h, args)
                if f < 0:
                    bad = k
                    break
                fb += f
                mujoco.mj_step(model, data)
        fallbacks += fb
        if bad >= 0:
            raise SimulationDivergedError(_diverged_message(scenario, run, t[bad]))
        if data.warning[mujoco.mjtWarning.mjWARN_BADQACC].number > 0:
            # MuJoCo met a non-finite or huge acceleration and reset its state: the run is lost
            raise SimulationDivergedError(
                f"{scenario.name}: {run} diverged between t = {t[k0]:.3f} s and {t[k1 - 1]:.3f} s: MuJoCo "
                "met a non-finite or huge acceleration")
        if progress is not None:
            progress(k1, n)
    return fallbacks, float(ship_err[0])
