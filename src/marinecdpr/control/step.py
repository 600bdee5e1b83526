"""The controller's step, compiled: from one exchange's measurements to the commands.

:func:`control_step` is the one implementation: the virtual prototype's closed loop calls
it every exchange, and :class:`~marinecdpr.control.controller.Controller` calls it for a
user's own loop. In order:

1. the state at mid-step, t_k + h/2, where the held command acts: the measured pose and
   twist (from a pose sensor, or from the encoders: :func:`pose_from_encoders`) predicted
   over their age plus half a step (:func:`estimate_state`), the ship's motion from the
   motion reference unit's last sample (as it is, kinematically, or by the online
   autoregressive predictor);
2. computed torque on the error to the plan at mid-step, a = a_ref + Kd e_v + Kp e (the
   rotation error in C), and the wrench it needs (eq. 15, with the known loads);
3. the tension method (every method, exact for any redundancy: ``tension_solver.tensions_step``),
   or the plan's tensions where it has no solution within limits;
4. the unstretched length a length-controlled winch pays out for that tension, and the
   lead on the winches' lag.

No step allocates; every record is :mod:`marinecdpr.control.records`'.
"""

from __future__ import annotations

from numba import njit
from numba.extending import overload

from marinecdpr.borrowed import borrowed_first
from marinecdpr.geometry.elastic import stretched_length, unstretched_length
from marinecdpr.geometry.forward import pose_from_lengths_step
from marinecdpr.geometry.kinematics import cables_step
from marinecdpr.geometry.pulley import pulleys_step
from marinecdpr.geometry.rotations import angle_rate_matrix, euler_step
from marinecdpr.model.linalg import lu_det_solve
from marinecdpr.model.rigid_body import ShipAt, sum_wrench_parts, wrench_parts_step
from marinecdpr.model.tension_solver import tensions_step
from marinecdpr.control.records import NoForwardWork, NoPredictor
from marinecdpr.motion.prediction import predictor_forecast, predictor_update

__all__ = ["control_step", "estimate_state", "pose_from_encoders", "cables_at", "mm3", "disturbance_C"]

_cache = True


@njit(cache=_cache)
def mm3(A, B, out, transpose_B=False):
    """out = A @ B (or A @ B^T) for 3x3 matrices, without BLAS's per-call cost."""
    for i in range(3):
        for j in range(3):
            acc = 0.0
            for k in range(3):
                acc += A[i, k] * (B[j, k] if transpose_B else B[k, j])
            out[i, j] = acc


@njit(cache=_cache)
def disturbance_C(f, m, in_P, R, f_C, m_C):
    """The disturbance in C, written to f_C, m_C (3,): (f, m) as given if in C, R (f, m) if
    given in P."""
    for i in range(3):
        if in_P:
            f_C[i] = R[i, 0] * f[0] + R[i, 1] * f[1] + R[i, 2] * f[2]
            m_C[i] = R[i, 0] * m[0] + R[i, 1] * m[1] + R[i, 2] * m[2]
        else:
            f_C[i] = f[i]
            m_C[i] = m[i]


@njit(cache=_cache)
def cables_at(x, R, model, L, J):
    """The cables' lengths L (m,) and J~ (m, 6) at the pose (x, R_PC), over their pulleys
    where the robot has them (:func:`~marinecdpr.geometry.pulley.pulleys_step`), else from
    point anchors (eqs. 2, 6)."""
    if model.pulleys:
        pulleys_step(x, R, model.c_C, model.z_C, model.radius, model.p_P, L, J, model.exits, model.wraps)
    else:
        cables_step(x, R, model.c_C, model.p_P, L, J)


@njit(cache=_cache, inline="always")
def estimate_state(k, h, meas, ref, work, how, predictor):
    """The platform's and the ship's state at mid-step, t_k + h/2, from the measurement.

    Writes x, R, v, w of the platform in C and the ship's R_SO, omega and alpha in S to
    ``work``; returns the acceleration of S's origin in O (3,). Each is predicted from its
    measurement's time stamp to mid-step, first order in the plan's accelerations. ``how``
    is the gains' ``prediction``.
    """
    x_m, R_m, v_m, w_m = work.x, work.R, work.v, work.w
    WR = work.m3[1]
    hh = (meas.clock[0] - meas.clock[1]) + 0.5 * h  # the pose's age plus half a step
    a, al = ref.a[k], ref.al[k]
    for i in range(3):
        v_m[i] = meas.v[i]
        w_m[i] = meas.w[i]
        x_m[i] = meas.x[i] + hh * v_m[i]
        for j in range(3):
            R_m[i, j] = meas.R[i, j]
    for i in range(3):
        v_m[i] = v_m[i] + hh * a[i]
    # R' = [w]x R over the horizon
    for j in range(3):
        WR[0, j] = -w_m[2] * R_m[1, j] + w_m[1] * R_m[2, j]
        WR[1, j] = w_m[2] * R_m[0, j] - w_m[0] * R_m[2, j]
        WR[2, j] = -w_m[1] * R_m[0, j] + w_m[0] * R_m[1, j]
    for i in range(3):
        w_m[i] = w_m[i] + hh * al[i]
        for j in range(3):
            R_m[i, j] = R_m[i, j] + hh * WR[i, j]
    eta, eta_p = meas.eta, work.eta
    if how == 2:  # the autoregressive model (the kinematic extrapolation while it warms up)
        fc = work.forecast
        if ship_forecast(predictor, meas.clock[2], eta, meas.clock[0] + 0.5 * h, fc) >= 0:
            for i in range(6):
                eta_p[0, i] = fc[0, i]
                eta_p[1, i] = fc[1, i]
            euler_step(eta_p[0, 3:], eta_p[1, 3:], fc[2, 3:], work.R_SO, work.w_s, work.al_s)
            return fc[2, :3]
    # kinematic: over the sample's age plus half a step; none: the sample as if it were now
    hs = (meas.clock[0] - meas.clock[2]) + 0.5 * h if how != 0 else 0.0
    for i in range(6):
        eta_p[0, i] = eta[0, i] + hs * eta[1, i]
        eta_p[1, i] = eta[1, i] + hs * eta[2, i]
    euler_step(eta_p[0, 3:], eta_p[1, 3:], eta[2, 3:], work.R_SO, work.w_s, work.al_s)
    return eta[2, :3]


def ship_forecast(predictor, t_sample, eta, t, fc):
    """The predictor's forecast of the ship's motion at t into fc (3, 6) after it takes the
    sample eta (3, 6) of t_sample; its status (< 0: none yet). A controller without a
    predictor (:class:`~marinecdpr.control.records.NoPredictor`) has none. Compiled code only."""
    raise NotImplementedError("ship_forecast is called from compiled code")


@overload(ship_forecast, jit_options={"cache": True})
def _ship_forecast(predictor, t_sample, eta, t, fc):
    if getattr(predictor, "instance_class", None) is NoPredictor:
        return lambda predictor, t_sample, eta, t, fc: -1

    def impl(predictor, t_sample, eta, t, fc):
        predictor_update(predictor, t_sample, eta[0], eta[1], eta[2])
        return predictor_forecast(predictor, t, fc)
    return impl


def encoders_pose(fk, meas, model, work, gains):
    """:func:`pose_from_encoders` where the controller has the encoders' forward kinematics;
    0 (nothing done) where its pose comes from a sensor (:class:`NoForwardWork`). Compiled
    code only."""
    raise NotImplementedError("encoders_pose is called from compiled code")


@overload(encoders_pose, jit_options={"cache": True})
def _encoders_pose(fk, meas, model, work, gains):
    if getattr(fk, "instance_class", None) is NoForwardWork:
        return lambda fk, meas, model, work, gains: 0
    return lambda fk, meas, model, work, gains: pose_from_encoders(meas, model, work, gains)


@njit(cache=_cache)
def pose_from_encoders(meas, model, work, gains):
    """The platform's pose and twist from the encoders, written to the measurement.

    The encoders' unstretched lengths are stretched by the measured tensions (L = L0 (1 +
    T / EA)); forward kinematics (Levenberg-Marquardt, warm-started from the last pose)
    gives the pose, and the lengths' rates the twist in the controlled DOFs, by least
    squares on l' = (dl/dq) q'. Returns the forward kinematics' status (0: converged; see
    :func:`~marinecdpr.geometry.forward.pose_from_lengths_step`).
    """
    for i in range(meas.L.shape[0]):
        work.Lg[i] = stretched_length(meas.L[i], meas.T[i], model.EA)
    q = work.q
    if model.pulleys:  # the lengths over the pulleys
        status = pose_from_lengths_step(work.Lg, model.c_C, model.p_P, model.controlled, q, gains.fk_tol_m,
                                        gains.fk_iter, work.fk, model.z_C, model.radius)
    else:
        status = pose_from_lengths_step(work.Lg, model.c_C, model.p_P, model.controlled, q, gains.fk_tol_m,
                                        gains.fk_iter, work.fk)
    # the rates: dl/dq (work.fk.J, at q) q'_c = l', least squares
    J, G, b = work.fk.J, work.Gk, work.bk
    k = model.controlled.shape[0]
    for a in range(k):
        s = 0.0
        for i in range(J.shape[0]):
            s += J[i, a] * meas.Ldot[i]
        b[a] = s
        for c in range(k):
            s = 0.0
            for i in range(J.shape[0]):
                s += J[i, a] * J[i, c]
            G[a, c] = s
    lu_det_solve(G, b)
    work.qdot[:] = 0.0
    for a in range(k):
        work.qdot[model.controlled[a]] = b[a]
    zero = work.v3[0]
    euler_step(q[3:], zero, zero, meas.R, work.v3[1], work.v3[1])  # R_PC (its rates unused)
    angle_rate_matrix(q[3:], work.E)
    for i in range(3):
        meas.x[i] = q[i]
        meas.v[i] = work.qdot[i]
        meas.w[i] = work.E[i, 0] * work.qdot[3] + work.E[i, 1] * work.qdot[4] + work.E[i, 2] * work.qdot[5]
    meas.clock[1] = meas.clock[0]  # read now
    return status


@njit(cache=_cache, inline="always")
def _feedback_tensions(k, h, ref, model, gains, loads, meas, cmd, work, predictor):
    """Computed torque on the mid-step reference, the wrench it needs (eq. 15) and the
    tension method: T_cmd. Returns 1 where the method has no solution within limits (then
    the plan's tensions are commanded)."""
    a_SO = estimate_state(k, h, meas, ref, work, gains.prediction, predictor)
    x_m, R_m, v_m, w_m = work.x, work.R, work.v, work.w
    E = work.m3[2]
    mm3(ref.R[k], R_m, E, True)
    e0, e1, e2 = 0.5 * (E[2, 1] - E[1, 2]), 0.5 * (E[0, 2] - E[2, 0]), 0.5 * (E[1, 0] - E[0, 1])
    a_cmd, al_cmd = work.a_cmd[0], work.a_cmd[1]
    for i in range(3):
        a_cmd[i] = ref.a[k, i] + gains.kd * (ref.v[k, i] - v_m[i]) + gains.kp * (ref.x[k, i] - x_m[i])
        al_cmd[i] = (ref.al[k, i] + gains.kd * (ref.w[k, i] - w_m[i])
                     + gains.kp * (e0 if i == 0 else (e1 if i == 1 else e2)))
    f_k, m_k = work.v3[2], work.v3[3]
    disturbance_C(loads.f[k], loads.m[k], loads.in_P, R_m, f_k, m_k)
    ship = ShipAt(work.R_SO, work.w_s, work.al_s, a_SO)
    wrench_parts_step(x_m, v_m, a_cmd, R_m, w_m, al_cmd, ship, model, f_k, m_k, work.wrench_parts)
    sum_wrench_parts(work.wrench_parts, work.wrench)
    cables_at(x_m, R_m, model, work.L, work.J)
    # every method, exact for any redundancy, compiled (the planning layer's solvers)
    if tensions_step(work.J, work.wrench, model.controlled, model.lo, model.hi, model.method, cmd.T_cmd,
                       work.tension):
        return 0
    for i in range(cmd.T_cmd.shape[0]):  # element by element: a slice copy compiles numba's shape-error text (1.4 s)
        cmd.T_cmd[i] = ref.T[k, i]
    return 1


@njit(cache=_cache, inline="always")
def _unstretched(ref, k, model, i):
    """The winch length of cable i that holds the plan's length at the plan's tension, m."""
    return unstretched_length(ref.L[k, i], ref.T[k, i] - model.damping * ref.Ldot[k, i], model.EA) + ref.sag[k, i]


@njit(cache=_cache, inline="always")
def _limits(model, cmd):
    """Which commanded tensions are at a limit (``cmd.at_limit``); their number."""
    at = 0
    for i in range(cmd.T_cmd.shape[0]):
        tol = 1e-9 * max(1.0, abs(model.hi[i]))
        if cmd.T_cmd[i] <= model.lo[i] + tol:
            cmd.at_limit[i] = -1
        elif cmd.T_cmd[i] >= model.hi[i] - tol:
            cmd.at_limit[i] = 1
        else:
            cmd.at_limit[i] = 0
        at += cmd.at_limit[i] != 0
    return at


@njit(cache=_cache)
def control_step(k, h, held):
    """One controller step at t_k = k h: the measurement ``ctl.meas`` in, ``ctl.cmd`` out.

    T_cmd (tension-controlled winches, ideal cables) and L0_cmd (length-controlled winches)
    for the step [t_k, t_k + h), and the flags (:class:`~marinecdpr.control.records.Command`).
    Returns 1 on a fallback to the plan's tensions, else 0.
    """
    ctl = borrowed_first(held)  # no counting of its arrays' references: the caller holds them
    # its records are taken apart once, here: a helper is handed the records it reads, never
    # all of ctl (each copy of a record of ~90 arrays costs seconds of compiling)
    ref, gains, model, cmd = ctl.ref, ctl.gains, ctl.model, ctl.cmd
    meas, work = ctl.meas, ctl.work
    fallback = 0
    cmd.flags[2] = 0
    if gains.closed:
        if gains.pose_from == 1:
            cmd.flags[2] = encoders_pose(work.fk, meas, model, work, gains) != 0
        fallback = _feedback_tensions(k, h, ref, model, gains, ctl.loads, meas, cmd, work, ctl.predictor)
    else:
        for i in range(cmd.T_cmd.shape[0]):
            cmd.T_cmd[i] = ref.T[k, i]
    # a length-controlled winch pays out the reference length less the stretch the
    # commanded tension needs: the cable's stiffness holds the plan, T_cmd corrects it
    # (the cable's damping adds c L' of the plan: the stretch makes the rest), plus what a
    # heavy cable's sag takes at the planned tension
    for i in range(cmd.L0_cmd.shape[0]):
        cmd.L0_cmd[i] = (unstretched_length(ref.L[k, i], cmd.T_cmd[i] - model.damping * ref.Ldot[k, i], model.EA)
                         + ref.sag[k, i])
    if gains.closed and gains.lead_s > 0.0:
        # the controller knows its winches' lag: it leads the planned part of the command
        # by tau times the plan's (smooth) rate, u = r + tau r'
        kf, kb = min(k + 1, ref.T.shape[0] - 1), max(k - 1, 0)
        dt = (kf - kb) * h
        if gains.tension_winches:
            lo, hi = model.lo, model.hi
            for i in range(cmd.T_cmd.shape[0]):  # a command stays within the cable's limits
                T_i = cmd.T_cmd[i] + gains.lead_s * (ref.T[kf, i] - ref.T[kb, i]) / dt
                cmd.T_cmd[i] = min(max(T_i, lo[i]), hi[i])
        else:
            for i in range(cmd.L0_cmd.shape[0]):
                cmd.L0_cmd[i] += gains.lead_s * (_unstretched(ref, kf, model, i) - _unstretched(ref, kb, model, i)) / dt
    cmd.flags[0] = fallback
    cmd.flags[1] = _limits(model, cmd)
    return fallback
