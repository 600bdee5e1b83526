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

Before that, in closed loop with ``[simulation.control.safety] detect``, :func:`watch`
checks the measurements (a cable's load cell far below its command, a sensor's reading not
finite, frozen or jumping, the encoders and the pose sensor disagreeing, the MRU dropping
out); after a detection, :func:`react` commands instead, by what is left: the lost cable's
tension redistributed, a parked pose, a stop, or the brakes (``cmd.brake``). Until a
detection the commands are the same numbers as without the watch.

No step allocates; every record is :mod:`marinecdpr.control.records`'.
"""

from __future__ import annotations

import math

from numba import carray, njit
from numba.core.errors import TypingError
from numba.extending import overload

from marinecdpr.borrowed import borrowed_first, call_stored, data_address, float64_pointer, load
from marinecdpr.geometry.elastic import stretched_length, unstretched_length
from marinecdpr.geometry.forward import pose_from_lengths_step
from marinecdpr.geometry.kinematics import cables_step
from marinecdpr.geometry.pulley import pulleys_step
from marinecdpr.geometry.rotations import angle_rate_matrix, euler_step
from marinecdpr.model.linalg import lu_det_solve
from marinecdpr.model.rigid_body import ShipAt, sum_wrench_parts, wrench_parts_step
from marinecdpr.model.tension_solver import tensions_step
from marinecdpr.motion.prediction import predictor_forecast, predictor_update

__all__ = ["control_step", "estimate_state", "pose_from_encoders", "forecast_at", "encoders_at", "ship_forecast",
           "encoders_pose", "cables_at", "mm3", "disturbance_C", "watch", "react"]

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
def estimate_state(k, h, meas, eta, ref, work, how, predictor):
    """The platform's and the ship's state at mid-step, t_k + h/2, from the measurement and
    the MRU's sample eta (3, 6) (the measurement's, or its last sound one: :func:`react`).

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
    eta_p = work.eta
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
    sample eta (3, 6) of t_sample; its status (< 0: none yet). ``predictor`` is the
    controller's :class:`~marinecdpr.control.records.Slot`: a controller without one has
    none (-1); else its :func:`forecast_at` is called by address. Compiled code only."""
    raise NotImplementedError("ship_forecast is called from compiled code")


@overload(ship_forecast, jit_options={"cache": True})
def _ship_forecast(predictor, t_sample, eta, t, fc):
    if eta.layout != "C" or fc.layout != "C":
        raise TypingError("ship_forecast: eta and fc must be C-contiguous (3, 6) arrays")

    def impl(predictor, t_sample, eta, t, fc):
        words = predictor.words
        if words[0] == 0:
            return -1
        return call_stored(words[0], (data_address(words) + 8, t_sample, data_address(eta), t, data_address(fc)))
    return impl


@njit(cache=_cache)
def forecast_at(at, t_sample, eta_at, t, fc_at, record):
    """:func:`ship_forecast` of the predictor stored at ``at`` (a
    :class:`~marinecdpr.motion.prediction.Predictor`, of numba type ``record``, a type
    reference), with eta and fc (3, 6) at the addresses eta_at and fc_at: compiled once
    for the predictor's type and called through its C wrapper (the step's code holds no
    predictor). Returns the forecast's status; -2 where it raised."""
    pred = load(at, record)
    eta = carray(float64_pointer(eta_at), (3, 6))
    fc = carray(float64_pointer(fc_at), (3, 6))
    try:
        predictor_update(pred, t_sample, eta[0], eta[1], eta[2])
        return predictor_forecast(pred, t, fc)
    except Exception:  # noqa: BLE001 - through a C wrapper: no forecast, the kinematic estimate
        return -2


@njit(cache=_cache, inline="always")
def encoders_pose(encoders):
    """:func:`pose_from_encoders` where the controller has the encoders' forward kinematics
    (its :class:`~marinecdpr.control.records.Slot` ``encoders``, called by address: its
    status); 0 (nothing done) where its pose comes from a sensor."""
    words = encoders.words
    if words[0] == 0:
        return 0
    return call_stored(words[0], (data_address(words) + 8,))


@njit(cache=_cache)
def encoders_at(at, record):
    """:func:`pose_from_encoders` on the :class:`~marinecdpr.control.records.Encoders` stored
    at ``at`` (of numba type ``record``, a type reference): compiled once and called through
    its C wrapper. Returns its status; -1 where it raised."""
    try:
        return pose_from_encoders(load(at, record))
    except Exception:  # noqa: BLE001 - through a C wrapper: the step flags the pose as failed
        return -1


@njit(cache=_cache)
def pose_from_encoders(enc):
    """The platform's pose and twist from the encoders, written to the measurement.

    The encoders' unstretched lengths are stretched by the measured tensions (L = L0 (1 +
    T / EA)); forward kinematics (Levenberg-Marquardt, warm-started from the last pose)
    gives the pose, and the lengths' rates the twist in the controlled DOFs, by least
    squares on l' = (dl/dq) q'. Returns the forward kinematics' status (0: converged; see
    :func:`~marinecdpr.geometry.forward.pose_from_lengths_step`). ``enc``: the step's
    :class:`~marinecdpr.control.records.Encoders`.
    """
    meas, model, gains, work = enc.meas, enc.model, enc.gains, enc
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
def _computed_torque(kp, kd, x_t, R_t, v_t, w_t, a_t, al_t, work):
    """Computed torque on the error to the target (x_t, R_t, v_t, w_t, a_t, al_t) from the
    estimated state (``work.x``, R, v, w): a = a_t + kd (v_t - v) + kp (x_t - x), the rotation
    error in C; written to ``work.a_cmd``."""
    x_m, R_m, v_m, w_m = work.x, work.R, work.v, work.w
    E = work.m3[2]
    mm3(R_t, R_m, E, True)
    e0, e1, e2 = 0.5 * (E[2, 1] - E[1, 2]), 0.5 * (E[0, 2] - E[2, 0]), 0.5 * (E[1, 0] - E[0, 1])
    a_cmd, al_cmd = work.a_cmd[0], work.a_cmd[1]
    for i in range(3):
        a_cmd[i] = a_t[i] + kd * (v_t[i] - v_m[i]) + kp * (x_t[i] - x_m[i])
        al_cmd[i] = (al_t[i] + kd * (w_t[i] - w_m[i])
                     + kp * (e0 if i == 0 else (e1 if i == 1 else e2)))


@njit(cache=_cache, inline="always")
def _required_wrench(k, model, loads, work, a_SO):
    """The wrench (eq. 15, with the known loads at t_k) the commanded accelerations
    ``work.a_cmd`` need at the estimated state, and the cables there: ``work.wrench``,
    ``work.L``, ``work.J``."""
    x_m, R_m, v_m, w_m = work.x, work.R, work.v, work.w
    f_k, m_k = work.v3[2], work.v3[3]
    disturbance_C(loads.f[k], loads.m[k], loads.in_P, R_m, f_k, m_k)
    ship = ShipAt(work.R_SO, work.w_s, work.al_s, a_SO)
    wrench_parts_step(x_m, v_m, work.a_cmd[0], R_m, w_m, work.a_cmd[1], ship, model, f_k, m_k, work.wrench_parts)
    sum_wrench_parts(work.wrench_parts, work.wrench)
    cables_at(x_m, R_m, model, work.L, work.J)


@njit(cache=_cache)
def _tensions_for(k, h, eta, how, blind, hold_x, hold_R, kp, kd, x_t, R_t, v_t, w_t, a_t, al_t, lost, known, lo, hi,
                  ref, model, loads, meas, cmd, work, predictor):
    """The state at mid-step (:func:`estimate_state` from the MRU's sample eta (3, 6), ``how``
    a ``Gains.prediction``; where ``blind``, the pose ``hold_x``, ``hold_R`` at rest instead),
    computed torque with gains kp, kd on the error to the target (x_t, R_t, v_t, w_t, a_t,
    al_t), the wrench it needs (eq. 15) and the tension method within lo, hi (m,), the cables
    where ``lost`` (m,) is non-zero left out (their rows of J~ zeroed), the wrench of the
    tension ``known`` (m,), N, that such a cable still pulls with (a failed drive's, from its
    load cell; 0 for a broken one) taken from the wrench the others hold (J~^T T = w): T_cmd.
    True where within the limits. The one solve of the normal step and of every reaction, compiled once
    (inlined at each of their call sites, it cost seconds of compiling each)."""
    a_SO = estimate_state(k, h, meas, eta, ref, work, how, predictor)
    if blind:  # no pose to feed back: the held pose, at rest (feed-forward)
        for i in range(3):
            work.x[i] = hold_x[i]
            work.v[i] = 0.0
            work.w[i] = 0.0
            for j in range(3):
                work.R[i, j] = hold_R[i, j]
    _computed_torque(kp, kd, x_t, R_t, v_t, w_t, a_t, al_t, work)
    _required_wrench(k, model, loads, work, a_SO)
    for i in range(cmd.T_cmd.shape[0]):
        if lost[i] != 0:
            for j in range(6):
                work.wrench[j] -= work.J[i, j] * known[i]
                work.J[i, j] = 0.0
    # every method, exact for any redundancy, compiled (the planning layer's solvers)
    return tensions_step(work.J, work.wrench, model.controlled, lo, hi, model.method, cmd.T_cmd, work.tension)


@njit(cache=_cache, inline="always")
def _blind(gains, s):
    """The pose the controller feeds back is lost (its sensor faulty): never in the normal step."""
    return (s.bad[_POSE] != 0 and gains.pose_from == 0) or (s.bad[_ENCODER] != 0 and gains.pose_from == 1)


@njit(cache=_cache, inline="always")
def _feedback_tensions(k, h, ref, model, gains, loads, meas, cmd, work, predictor, s):
    """Computed torque on the mid-step reference, the wrench it needs (eq. 15) and the
    tension method: T_cmd. Returns 1 where the method has no solution within limits (then
    the plan's tensions are commanded). ``s``, the safety record: in the normal step no cable
    is lost and no sensor faulty (each argument of the solve a run-time value, as the
    reaction's: one compiled solve for both)."""
    x_t, R_t = ref.x[k], ref.R[k]
    if _tensions_for(k, h, meas.eta, gains.prediction, _blind(gains, s), x_t, R_t, gains.kp, gains.kd, x_t, R_t,
                     ref.v[k], ref.w[k], ref.a[k], ref.al[k], s.lost, s.known, model.lo, model.hi, ref, model, loads,
                     meas, cmd, work, predictor):
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


# ------------------------------------------------------------ detection and reaction
_POSE, _CELL, _ENCODER, _MRU = 0, 1, 2, 3  # records.SENSORS
_SLACK, _NON_FINITE, _FROZEN, _JUMP, _DISAGREE, _DROPOUT, _DRIVE = 1, 2, 3, 4, 5, 6, 7  # records.KINDS
_NORMAL, _GO_ON, _PARK, _STOP, _BRAKE = 0, 1, 2, 3, 4  # records.MODES


@njit(cache=_cache, inline="always")
def _detected(s, k, kind, sensor, cable):
    """Record a detection (:attr:`~marinecdpr.control.records.Safety.events`)."""
    n = s.n_events[0]
    if n < s.events.shape[0]:
        s.events[n, 0] = k
        s.events[n, 1] = kind
        s.events[n, 2] = sensor
        s.events[n, 3] = cable
        s.n_events[0] = n + 1


@njit(cache=_cache, inline="always")
def _residual(s, j, r):
    """A watched residual's ratio r to its threshold, kept as the largest before any detection."""
    if s.n_events[0] == 0 and r > s.peak[j]:
        s.peak[j] = r


@njit(cache=_cache, inline="always")
def _finite(a):
    for v in a.flat:
        if not math.isfinite(v):
            return False
    return True


@njit(cache=_cache)
def watch(k, h, ref, model, gains, meas, cmd, work, s):
    """Detection from what the controller measures at step k, before it commands.

    A cable whose load cell reads below ``slack_fraction`` of its last commanded tension for
    ``slack_steps`` exchanges is lost (slack or broken); a reading that is not finite, a pose
    sensor's position or an encoder's length that jumps by more than ``jump_m`` beyond what
    the plan moves in the exchange, or that reads the same while the plan moved ``frozen_m``,
    marks its sensor faulty; with a pose sensor, a cable whose encoder length stretched by
    its load cell's tension (less the plan's sag) differs from its length at the measured
    pose by ``disagree_m`` for ``disagree_steps`` exchanges marks the encoders and the pose
    sensor as disagreeing; the MRU's sample older than ``mru_timeout_s`` marks it dropped out; a
    motor whose torque (from its drive's current) differs from its drive's demand by more than
    ``current_fraction`` of its torque limit for ``current_steps`` exchanges marks its winch's
    drive failed (stalled, or without power): its cable is lost to the tensions' solve, the
    tension its load cell reads taken as known (``s.known``). Each detection is recorded
    (step, kind, sensor, cable); the watched residuals' largest ratios to their thresholds
    before the first detection are kept in ``s.peak``. Returns the number of new detections.
    Reads ``cmd.T_cmd`` as the last exchange's command; may
    overwrite ``work.L`` and ``work.J``.
    """
    m = cmd.T_cmd.shape[0]
    n0 = s.n_events[0]
    held = s.mode[0] == _PARK or s.mode[0] == _STOP or s.mode[0] == _BRAKE  # the plan no longer moves
    use_pose = gains.pose_from == 0 and s.present[_POSE] != 0
    if use_pose and s.bad[_POSE] == 0:
        if not (_finite(meas.x) and _finite(meas.R) and _finite(meas.v) and _finite(meas.w)):
            s.bad[_POSE] = 1
            _detected(s, k, _NON_FINITE, _POSE, -1)
    if s.present[_CELL] != 0 and s.bad[_CELL] == 0:
        for i in range(m):
            if not math.isfinite(meas.T[i]):
                s.bad[_CELL] = 1
                _detected(s, k, _NON_FINITE, _CELL, i)
                break
    if s.present[_ENCODER] != 0 and s.bad[_ENCODER] == 0:
        for i in range(m):
            if not (math.isfinite(meas.L[i]) and math.isfinite(meas.Ldot[i])):
                s.bad[_ENCODER] = 1
                _detected(s, k, _NON_FINITE, _ENCODER, i)
                break
    if s.present[_MRU] != 0 and s.bad[_MRU] == 0:
        if not (_finite(meas.eta) and math.isfinite(meas.clock[2])):
            s.bad[_MRU] = 1
            _detected(s, k, _NON_FINITE, _MRU, -1)
        else:
            r = (meas.clock[0] - meas.clock[2]) / s.mru_timeout_s
            _residual(s, 4, r)
            if r > 1.0:
                s.bad[_MRU] = 1
                _detected(s, k, _DROPOUT, _MRU, -1)
        if s.bad[_MRU] == 0:  # kept for the reaction, should the MRU fail
            for d in range(3):
                for j in range(6):
                    s.last_eta[d, j] = meas.eta[d, j]
    # a cable's load cell far below its command, for the stated time
    if s.present[_CELL] != 0 and s.bad[_CELL] == 0:
        for i in range(m):
            Tc = cmd.T_cmd[i]
            if s.lost[i] != 0 or not Tc > 0.0:
                continue
            _residual(s, 0, (1.0 - meas.T[i] / Tc) / (1.0 - s.slack_fraction))
            if meas.T[i] < s.slack_fraction * Tc:
                s.count[0, i] += 1
                if s.count[0, i] >= s.slack_steps:
                    s.lost[i] = 1
                    s.lo[i] = 0.0
                    s.hi[i] = 0.0
                    _detected(s, k, _SLACK, -1, i)
            else:
                s.count[0, i] = 0
    # a motor's torque (its drive's current) far from its drive's demand, for the stated time
    for i in range(m):
        if not s.tau_max[i] > 0.0 or s.failed[i] != 0 or s.lost[i] != 0:
            continue
        r = abs(meas.tau[i] - meas.tau_set[i]) / (s.current_fraction * s.tau_max[i])
        _residual(s, 5, r)
        if r > 1.0:
            s.count[2, i] += 1
            if s.count[2, i] >= s.current_steps:
                s.failed[i] = 1  # its cable no longer controlled: lost to the solve, its measured
                s.lost[i] = 1  # tension's wrench taken from what the others hold (below)
                s.lo[i] = 0.0
                s.hi[i] = 0.0
                _detected(s, k, _DRIVE, -1, i)
        else:
            s.count[2, i] = 0
    for i in range(m):  # a failed drive's cable still pulls: with what its load cell reads
        if s.failed[i] != 0:
            T = meas.T[i] if (s.present[_CELL] != 0 and s.bad[_CELL] == 0) else 0.0
            s.known[i] = T if (math.isfinite(T) and T > 0.0) else 0.0
    # the pose sensor: a jump beyond the plan's move, or frozen while the plan moves
    if use_pose and s.bad[_POSE] == 0:
        if math.isfinite(s.last_x[0]):
            d, moved, same = 0.0, 0.0, True
            for i in range(3):
                dp = ref.x[k, i] - ref.x[k - 1, i] if (k > 0 and not held) else 0.0
                d += (meas.x[i] - s.last_x[i] - dp) ** 2
                moved += dp * dp
                same = same and meas.x[i] == s.last_x[i]
            d = math.sqrt(d)
            _residual(s, 1, d / s.jump_m)
            s.moved_x[0] = s.moved_x[0] + math.sqrt(moved) if same else 0.0
            _residual(s, 2, s.moved_x[0] / s.frozen_m)
            if d > s.jump_m:
                s.bad[_POSE] = 1
                _detected(s, k, _JUMP, _POSE, -1)
            elif s.moved_x[0] > s.frozen_m:
                s.bad[_POSE] = 1
                _detected(s, k, _FROZEN, _POSE, -1)
        for i in range(3):
            s.last_x[i] = meas.x[i]
    # the encoders: the same, cable by cable
    if s.present[_ENCODER] != 0 and s.bad[_ENCODER] == 0:
        for i in range(m):
            if s.lost[i] != 0:
                continue
            if math.isfinite(s.last_L[i]):
                dp = ref.L[k, i] - ref.L[k - 1, i] if (k > 0 and not held) else 0.0
                d = abs(meas.L[i] - s.last_L[i] - dp)
                _residual(s, 1, d / s.jump_m)
                s.moved_L[i] = s.moved_L[i] + abs(dp) if meas.L[i] == s.last_L[i] else 0.0
                _residual(s, 2, s.moved_L[i] / s.frozen_m)
                if d > s.jump_m:
                    s.bad[_ENCODER] = 1
                    _detected(s, k, _JUMP, _ENCODER, i)
                elif s.moved_L[i] > s.frozen_m:
                    s.bad[_ENCODER] = 1
                    _detected(s, k, _FROZEN, _ENCODER, i)
            s.last_L[i] = meas.L[i]
    # the encoders against the pose sensor
    if (use_pose and s.present[_ENCODER] != 0 and s.present[_CELL] != 0 and s.bad[_POSE] == 0
            and s.bad[_ENCODER] == 0 and s.bad[_CELL] == 0):
        cables_at(meas.x, meas.R, model, work.L, work.J)
        for i in range(m):
            if s.lost[i] != 0:
                continue
            d = abs(stretched_length(meas.L[i] - ref.sag[k, i], meas.T[i], model.EA) - work.L[i])
            _residual(s, 3, d / s.disagree_m)
            if d > s.disagree_m:
                s.count[1, i] += 1
                if s.count[1, i] >= s.disagree_steps:
                    s.bad[_ENCODER] = 1
                    _detected(s, k, _DISAGREE, _ENCODER, i)
                    break
            else:
                s.count[1, i] = 0
    return s.n_events[0] - n0


@njit(cache=_cache, inline="always")
def _hold_here(k, ref, s):
    """Hold the plan's pose at step k (where the platform is, within its tracking error)."""
    for i in range(3):
        s.hold_x[i] = ref.x[k, i]
        for j in range(3):
            s.hold_R[i, j] = ref.R[k, i, j]


@njit(cache=_cache, inline="always")
def _reaction_tensions(k, h, mode, scale, ref, model, gains, loads, meas, cmd, work, predictor, s):
    """The tensions of a reaction ``mode`` with ``scale`` times its feedback (go on, park) or
    its deceleration (stop), within the safety record's limits (a lost cable's both 0, its row
    of J~ zeroed), written to T_cmd; True if within them. The target: the plan's (go on), the
    held pose at rest (park), or rest where it is (the stop: a wrench opposing the motion)."""
    z = s.zero
    kp, kd = scale * gains.kp, scale * gains.kd
    x_t, R_t, v_t, w_t, a_t, al_t = ref.x[k], ref.R[k], ref.v[k], ref.w[k], ref.a[k], ref.al[k]
    if mode == _PARK:
        x_t, R_t, v_t, w_t, a_t, al_t = s.hold_x, s.hold_R, z, z, z, z
    elif mode != _GO_ON:  # the stop: its target is the estimate itself (written before it is read)
        kp, kd = 0.0, scale * s.stop_kd
        x_t, R_t, v_t, w_t, a_t, al_t = work.x, work.R, z, z, z, z
    eta, how = meas.eta, gains.prediction
    if s.bad[_MRU] != 0:  # the MRU's last sound sample, as it is
        eta, how = s.last_eta, 0
    return _tensions_for(k, h, eta, how, _blind(gains, s), s.hold_x, s.hold_R, kp, kd, x_t, R_t, v_t, w_t, a_t, al_t,
                         s.lost, s.known, s.lo, s.hi, ref, model, loads, meas, cmd, work, predictor)


_SCALES = (1.0, 0.5, 0.25, 0.0)
"""The shares of a reaction's feedback (or of the stop's deceleration) tried in turn, until
the remaining cables have tensions within their limits for it."""


@njit(cache=_cache)
def react(k, h, ref, model, gains, loads, meas, cmd, work, predictor, s):
    """The commands after a detection, by what is left (``s.mode``, escalated as needed).

    A lost cable where the rest still hold the wrench within their limits: its tension
    redistributed on the plan (go on) or, with ``park``, the pose held; a faulty sensor: the
    pose held (fed forward from the held pose where the pose itself is lost; the MRU's last
    sound sample as it is where it dropped out or read non-finite). Each with its full
    feedback, or where that has no tensions within limits, half, a quarter or none of it (the
    plan's, or the held pose's, feed-forward). Where the remaining cables have no tensions
    within limits even for that, the stop: a = -stop_kd v (a wrench opposing the motion, to
    rest), or the largest share of that deceleration (1, 1/2, 1/4, 0: held at its velocity)
    within limits; where not even that, the brakes (``cmd.brake``), the remaining winches
    holding the plan's tensions within their limits. A winch whose drive has failed is such a
    lost cable, whose measured pull the others hold besides the wrench (``s.known``). Writes
    T_cmd, L0_cmd (the lengths at the held pose, or the plan's when going on) and brake;
    returns 1 once the reaction is the brakes, else 0.
    """
    mode = s.mode[0]
    while mode != _BRAKE:  # the mode, then the stop, then the brakes: one call site of the solve
        ok = False
        for scale in _SCALES:
            if _reaction_tensions(k, h, mode, scale, ref, model, gains, loads, meas, cmd, work, predictor, s):
                ok = True
                break
        if ok:
            break
        if mode != _STOP:  # the stop, from where it is
            mode = _STOP
            for i in range(3):
                s.hold_x[i] = work.x[i]
                for j in range(3):
                    s.hold_R[i, j] = work.R[i, j]
        else:
            mode = _BRAKE
        s.mode[0] = mode
        s.since[0] = k
    m = cmd.T_cmd.shape[0]
    if mode == _BRAKE:
        for i in range(m):
            cmd.T_cmd[i] = min(max(ref.T[k, i], s.lo[i]), s.hi[i])
            cmd.brake[i] = 1 - s.lost[i]
    if mode == _GO_ON:
        for i in range(m):
            cmd.L0_cmd[i] = (unstretched_length(ref.L[k, i], cmd.T_cmd[i] - model.damping * ref.Ldot[k, i], model.EA)
                             + ref.sag[k, i])
    else:  # the lengths that hold the held pose (the stop's: where it began) at the commanded tensions
        cables_at(s.hold_x, s.hold_R, model, s.Ls, s.Js)
        for i in range(m):
            cmd.L0_cmd[i] = unstretched_length(s.Ls[i], cmd.T_cmd[i], model.EA) + ref.sag[k, i]
    return 1 if mode == _BRAKE else 0


@njit(cache=_cache, inline="always")
def _choose_reaction(k, ref, s):
    """After a new detection: a lost cable goes on (or parks, with ``park``) until the rest
    cannot hold the wrench (a winch's failed drive, whose motor no longer does what its loop
    asks, is such a loss, its cable's measured pull held by the others); a faulty sensor
    parks; a stop or the brakes stay."""
    mode = s.mode[0]
    if mode == _STOP or mode == _BRAKE:
        return
    sensor = s.bad[_POSE] + s.bad[_CELL] + s.bad[_ENCODER] + s.bad[_MRU] > 0
    new = _PARK if (sensor or s.park) else _GO_ON
    if new != mode:
        if new == _PARK:
            _hold_here(k, ref, s)
        s.mode[0] = new
        s.since[0] = k


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
    safety = ctl.safety
    if gains.closed and safety.detect:
        if watch(k, h, ref, model, gains, meas, cmd, work, safety) > 0:
            _choose_reaction(k, ref, safety)
        if safety.mode[0] != _NORMAL:
            if gains.pose_from == 1 and safety.bad[_ENCODER] == 0:
                cmd.flags[2] = encoders_pose(ctl.encoders) != 0
            fallback = react(k, h, ref, model, gains, ctl.loads, meas, cmd, work, ctl.predictor, safety)
            cmd.flags[0] = fallback
            cmd.flags[1] = _limits(model, cmd)
            return fallback
    if gains.closed:
        if gains.pose_from == 1:
            cmd.flags[2] = encoders_pose(ctl.encoders) != 0
        fallback = _feedback_tensions(k, h, ref, model, gains, ctl.loads, meas, cmd, work, ctl.predictor, safety)
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
