"""The virtual prototype's parts: each a typed record of its parameters and state, with a
compiled step function.

One exchange (every ``time.step_s``, 1 ms; the paper's figure 4) passes through the parts
in this order::

    plant state (x, R, v, w)
      -> sensors      :func:`measure`        what the controller sees, predicted to mid-step
      -> controller   :func:`command`        computed torque + the tension method -> T_cmd, L0_cmd
      -> winch        :func:`winch_step`     lag on the length or tension command
      -> cables       :func:`cable_step`     ideal (T = T_cmd) or elastic (T from stretch)
      -> brush        :func:`brush_step`     a cleaning brush's loads at the actual velocity
      -> plant        (:mod:`~marinecdpr.prototype.plants`) advances one step with the tensions
    and :func:`log_step` records what happened.

Every record is a ``NamedTuple`` of numpy arrays and numbers, so the compiled functions
take it as one typed argument; time series have ``n_steps`` rows (index ``k``), the
cables ``m`` columns. Vectors are in the frame C of the robot's frame unless named
otherwise; units are SI (m, rad, N, s).

A new part (a sensor delay, a pulley, a brush contact) is a new record and step function
here, a field of :class:`Parts`, a call in :func:`exchange`, and a scenario section that
fills its record.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from marinecdpr.model import kernels as K
from marinecdpr.model.brush import BrushParams, brush_velocity_step, brush_wrench_step

__all__ = ["Reference", "RobotModel", "Sensors", "Controller", "Loads", "Winch", "Cables", "Bus", "Log",
           "BrushContact", "Work", "Parts", "exchange", "measure", "command", "winch_step", "cable_step", "log_step"]

_cache = True
DIVERGENCE_M = 10.0
"""A run stops as diverged when the platform is this far from its plan."""


# --------------------------------------------------------------------------- records
class Reference(NamedTuple):
    """The plan at mid-step, t_k + h/2: what the controller tracks and feeds forward.

    x, v, a : (n_steps, 3) position, velocity, acceleration of P relative to C, in C.
    R : (n_steps, 3, 3) R_PC. w, al : (n_steps, 3) angular velocity and acceleration in C.
    T, L, Ldot : (n_steps, m) planned tensions (N), cable lengths (m) and their rates (m/s).
    """

    x: np.ndarray
    R: np.ndarray
    v: np.ndarray
    w: np.ndarray
    a: np.ndarray
    al: np.ndarray
    T: np.ndarray
    L: np.ndarray
    Ldot: np.ndarray


class RobotModel(NamedTuple):
    """The controller's model of the robot (the scenario's robot and ship layout).

    c_C : (m, 3) frame anchors in C. p_P : (m, 3) platform anchors in P. mass : kg.
    I_PP : (3, 3) inertia about the centre of mass in P. g : gravity, m/s^2 (> 0).
    origin : (3,) C's origin in S. controlled : (k,) int indices of the controlled DOFs.
    lo, hi : (m,) tension limits, N. method : a ``kernels.METHOD_CODES`` value.
    """

    c_C: np.ndarray
    p_P: np.ndarray
    mass: float
    I_PP: np.ndarray
    g: float
    origin: np.ndarray
    controlled: np.ndarray
    lo: np.ndarray
    hi: np.ndarray
    method: int


class Sensors(NamedTuple):
    """What the sensors add to the truth, drawn in advance (zeros when not measured).

    pose : (n_steps, 6) position (m) and small rotation (rad) errors of the platform.
    twist : (n_steps, 6) velocity (m/s) and angular velocity (rad/s) errors.
    tension : (n_steps, m) tension sensor errors of tension-controlled winches, N.
    eta : (3, n_steps, 6) the measured ship motion at t_k: eta, eta', eta'' (m, rad).
    """

    pose: np.ndarray
    twist: np.ndarray
    tension: np.ndarray
    eta: np.ndarray


class Controller(NamedTuple):
    """Computed torque on the measured pose error, then the tension method.

    closed : False feeds the plan's tensions forward (open loop).
    kp, kd : gains, 1/s^2 and 1/s. lead_s : the winches' time constant the controller leads
    its commands by (0: none), s.
    """

    closed: bool
    kp: float
    kd: float
    lead_s: float


class Loads(NamedTuple):
    """The disturbance on the platform at t_k: f, m (n_steps, 3), N and N m; in C, or in P
    (turned with the platform's orientation) if ``in_P``."""

    f: np.ndarray
    m: np.ndarray
    in_P: bool


class Winch(NamedTuple):
    """The winches: length-controlled (pay out L0) or tension-controlled, with a first-order
    lag. lag : the fraction of the command error closed per step, 1 - exp(-h / tau).
    State: L0 (m,) unstretched lengths, m; T (m,) tensions the tension loops hold, N."""

    tension_controlled: bool
    lag: float
    L0: np.ndarray
    T: np.ndarray


class Cables(NamedTuple):
    """Ideal (inextensible, T = T_cmd) or elastic cables: EA (N), damping (N s/m)."""

    elastic: bool
    EA: float
    damping: float


class BrushContact(NamedTuple):
    """A cleaning brush on the hull (``[cleaning]``); inactive otherwise.

    params : the brush (:class:`~marinecdpr.model.brush.BrushParams`). n_C : (3,) the hull
    normal in C. F_n : (n_steps,) the normal force, N. f_plan, m_plan : (n_steps, 3) the
    brush's loads along the planned path, in C, which ``Loads`` holds for the controller's
    model. State: f, m (3,) the loads at the actual brush velocity, in C about P, which
    the plant applies instead of the planned ones; v (3,) scratch.
    """

    active: bool
    params: BrushParams
    n_C: np.ndarray
    F_n: np.ndarray
    f_plan: np.ndarray
    m_plan: np.ndarray
    f: np.ndarray
    m: np.ndarray
    v: np.ndarray


class Bus(NamedTuple):
    """The signals of the current exchange: L, Ldot (m,) actual lengths and rates; J (m, 6)
    J~ at the actual pose; T_cmd, L0_cmd (m,) the commands; T_app (m,) the applied tensions."""

    L: np.ndarray
    Ldot: np.ndarray
    J: np.ndarray
    T_cmd: np.ndarray
    L0_cmd: np.ndarray
    T_app: np.ndarray


class Log(NamedTuple):
    """What each exchange records: pose (n_steps, 6) (x, y, z, rx, ry, rz); lengths, T_cmd,
    T_app (n_steps, m)."""

    pose: np.ndarray
    lengths: np.ndarray
    T_cmd: np.ndarray
    T_app: np.ndarray


class Work(NamedTuple):
    """The exchange's working memory, allocated once per run (:func:`empty_work`) so that
    no step allocates: the measured state (x, v, w (3,), R (3, 3)), the ship's (R_SO (3, 3),
    w_s, al_s (3,)), the commanded accelerations, the wrench and its parts, the cables at
    the measured pose (L (m,), J (m, 6)) and the tension solver's memory."""

    x: np.ndarray
    R: np.ndarray
    v: np.ndarray
    w: np.ndarray
    R_SO: np.ndarray
    w_s: np.ndarray
    al_s: np.ndarray
    eta: np.ndarray  # (2, 6) the ship's eta and eta' predicted to mid-step
    a_cmd: np.ndarray  # (2, 3) commanded a and alpha
    m3: np.ndarray  # (3, 3, 3) scratch matrices
    v3: np.ndarray  # (4, 3) scratch vectors: zeros, angles, loads f and m
    wrench: np.ndarray  # (6,)
    wrench_parts: np.ndarray  # (5, 6)
    L: np.ndarray
    J: np.ndarray
    tension: K.TensionWork


class Parts(NamedTuple):
    """The prototype: every part's record, composed by :func:`exchange`."""

    ref: Reference
    model: RobotModel
    sensors: Sensors
    controller: Controller
    loads: Loads
    winch: Winch
    cables: Cables
    bus: Bus
    log: Log
    brush: BrushContact
    work: Work


def empty_bus(m: int) -> Bus:
    return Bus(np.empty(m), np.empty(m), np.empty((m, 6)), np.empty(m), np.empty(m), np.empty(m))


def empty_work(m: int, k: int) -> Work:
    """The working memory of an exchange with m cables and k controlled DOFs."""
    return Work(np.empty(3), np.empty((3, 3)), np.empty(3), np.empty(3), np.empty((3, 3)), np.empty(3),
                np.empty(3), np.empty((2, 6)), np.empty((2, 3)), np.empty((3, 3, 3)), np.zeros((4, 3)),
                np.empty(6), np.empty((5, 6)), np.empty(m), np.empty((m, 6)), K.tension_work(m, k))


def empty_log(n_steps: int, m: int) -> Log:
    return Log(np.empty((n_steps, 6)), np.empty((n_steps, m)), np.empty((n_steps, m)), np.empty((n_steps, m)))


# ------------------------------------------------------------------ small compiled maths
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
def euler_from_R(R, out):
    """(rx, ry, rz) with R = Rz Ry Rx, written to out (3,)."""
    out[0] = np.arctan2(R[2, 1], R[2, 2])
    out[1] = np.arcsin(min(1.0, max(-1.0, -R[2, 0])))
    out[2] = np.arctan2(R[1, 0], R[0, 0])


@njit(cache=_cache)
def quat_to_R(q, R):
    """R (3, 3) of a unit quaternion q = (w, x, y, z)."""
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
def length_rates(J, v, w, out):
    """l' = -J~ (v, omega) (eq. 5), written to out (m,)."""
    for i in range(J.shape[0]):
        out[i] = -(J[i, 0] * v[0] + J[i, 1] * v[1] + J[i, 2] * v[2]
                   + J[i, 3] * w[0] + J[i, 4] * w[1] + J[i, 5] * w[2])


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
def diverged(x, ref_x):
    """True if the position is not finite or more than DIVERGENCE_M from the reference."""
    d = 0.0
    for i in range(3):
        if not np.isfinite(x[i]):
            return True
        d = max(d, abs(x[i] - ref_x[i]))
    return d > DIVERGENCE_M


# ---------------------------------------------------------------------------- steps
@njit(cache=_cache, inline="always")
def measure(k, h, x, R, v, w, sensors, ref, work):
    """What the sensors report at t_k, predicted to mid-step, where the held command acts.

    Writes the measured x, R, v, w of the platform in C and the ship's R_SO, omega and alpha
    in S, all at t_k + h/2, to ``work``; returns the acceleration of S's origin in O (3,).
    """
    x_m, R_m, v_m, w_m = work.x, work.R, work.v, work.w
    Rn, WR = work.m3[0], work.m3[1]
    zero, tmp = work.v3[0], work.v3[1]
    K.euler_step(sensors.pose[k, 3:], zero, zero, Rn, tmp, tmp)
    mm3(Rn, R, R_m)
    hh = 0.5 * h
    a, al = ref.a[k], ref.al[k]
    for i in range(3):
        v_m[i] = v[i] + sensors.twist[k, i]
        w_m[i] = w[i] + sensors.twist[k, 3 + i]
        x_m[i] = (x[i] + sensors.pose[k, i]) + hh * v_m[i]
    for i in range(3):
        v_m[i] = v_m[i] + hh * a[i]
    # R' = [w]x R over half a step
    for j in range(3):
        WR[0, j] = -w_m[2] * R_m[1, j] + w_m[1] * R_m[2, j]
        WR[1, j] = w_m[2] * R_m[0, j] - w_m[0] * R_m[2, j]
        WR[2, j] = -w_m[1] * R_m[0, j] + w_m[0] * R_m[1, j]
    for i in range(3):
        w_m[i] = w_m[i] + hh * al[i]
        for j in range(3):
            R_m[i, j] = R_m[i, j] + hh * WR[i, j]
    eta, eta_p = sensors.eta, work.eta
    for i in range(6):
        eta_p[0, i] = eta[0, k, i] + hh * eta[1, k, i]
        eta_p[1, i] = eta[1, k, i] + hh * eta[2, k, i]
    K.euler_step(eta_p[0, 3:], eta_p[1, 3:], eta[2, k, 3:], work.R_SO, work.w_s, work.al_s)
    return eta[2, k, :3]


@njit(cache=_cache, inline="always")
def _feedback_tensions(k, h, x, R, v, w, parts):
    """Computed torque on the mid-step reference (a = a_ref + Kd e_v + Kp e, rotation error
    in C), the wrench it needs (eq. 15) and the tension method: T_cmd. Returns 1 where the
    method has no solution within limits (then the feed-forward tensions are commanded)."""
    ref, model, ctl, bus, work = parts.ref, parts.model, parts.controller, parts.bus, parts.work
    a_SO = measure(k, h, x, R, v, w, parts.sensors, ref, work)
    x_m, R_m, v_m, w_m = work.x, work.R, work.v, work.w
    E = work.m3[2]
    mm3(ref.R[k], R_m, E, True)
    e0, e1, e2 = 0.5 * (E[2, 1] - E[1, 2]), 0.5 * (E[0, 2] - E[2, 0]), 0.5 * (E[1, 0] - E[0, 1])
    a_cmd, al_cmd = work.a_cmd[0], work.a_cmd[1]
    for i in range(3):
        a_cmd[i] = ref.a[k, i] + ctl.kd * (ref.v[k, i] - v_m[i]) + ctl.kp * (ref.x[k, i] - x_m[i])
        al_cmd[i] = ref.al[k, i] + ctl.kd * (ref.w[k, i] - w_m[i]) + ctl.kp * (e0 if i == 0 else (e1 if i == 1 else e2))
    f_k, m_k = work.v3[2], work.v3[3]
    disturbance_C(parts.loads.f[k], parts.loads.m[k], parts.loads.in_P, R_m, f_k, m_k)
    K.wrench_parts_step(x_m, v_m, a_cmd, R_m, w_m, al_cmd, work.R_SO, work.w_s, work.al_s, a_SO, model.origin,
                        model.mass, model.I_PP, model.g, f_k, m_k, work.wrench_parts)
    K.sum_wrench_parts(work.wrench_parts, work.wrench)
    K.cables_step(x_m, R_m, model.c_C, model.p_P, work.L, work.J)
    # every method, exact for any redundancy, compiled (the planning layer's solvers)
    if K.tensions_step(work.J, work.wrench, model.controlled, model.lo, model.hi, model.method, bus.T_cmd,
                       work.tension):
        return 0
    bus.T_cmd[:] = ref.T[k]
    return 1


@njit(cache=_cache, inline="always")
def _unstretched(ref, k, cables, i):
    """The winch length of cable i that holds the plan's length at the plan's tension, m."""
    return ref.L[k, i] / (1.0 + (ref.T[k, i] - cables.damping * ref.Ldot[k, i]) / cables.EA)


@njit(cache=_cache, inline="always")
def command(k, h, x, R, v, w, parts):
    """The controller: T_cmd (tension-controlled winches, ideal cables) and L0_cmd
    (length-controlled winches) into the bus. Returns 1 on a fallback to feed-forward."""
    ref, ctl, cables, bus = parts.ref, parts.controller, parts.cables, parts.bus
    fallback = 0
    if ctl.closed:
        fallback = _feedback_tensions(k, h, x, R, v, w, parts)
    else:
        bus.T_cmd[:] = ref.T[k]
    # a length-controlled winch pays out the reference length less the stretch the
    # commanded tension needs: the cable's stiffness holds the plan, T_cmd corrects it
    # (the cable's damping adds c L' of the plan: the stretch makes the rest)
    for i in range(bus.L0_cmd.shape[0]):
        bus.L0_cmd[i] = ref.L[k, i] / (1.0 + (bus.T_cmd[i] - cables.damping * ref.Ldot[k, i]) / cables.EA)
    if ctl.closed and ctl.lead_s > 0.0:
        # the controller knows its winches' lag: it leads the planned part of the command
        # by tau times the plan's (smooth) rate, u = r + tau r'
        kf, kb = min(k + 1, ref.T.shape[0] - 1), max(k - 1, 0)
        dt = (kf - kb) * h
        if parts.winch.tension_controlled:
            lo, hi = parts.model.lo, parts.model.hi
            for i in range(bus.T_cmd.shape[0]):  # a command stays within the cable's limits
                T_i = bus.T_cmd[i] + ctl.lead_s * (ref.T[kf, i] - ref.T[kb, i]) / dt
                bus.T_cmd[i] = min(max(T_i, lo[i]), hi[i])
        else:
            for i in range(bus.L0_cmd.shape[0]):
                bus.L0_cmd[i] += ctl.lead_s * (_unstretched(ref, kf, cables, i)
                                               - _unstretched(ref, kb, cables, i)) / dt
    return fallback


@njit(cache=_cache, inline="always")
def winch_step(k, winch, bus, sensors):
    """Advance the winches one step: L0 towards L0_cmd, or the tension loop (on its noisy
    sensor) towards T_cmd, each with the first-order lag."""
    for i in range(bus.T_cmd.shape[0]):
        if winch.tension_controlled:
            winch.T[i] += winch.lag * (bus.T_cmd[i] - sensors.tension[k, i] - winch.T[i])
        else:
            winch.L0[i] += winch.lag * (bus.L0_cmd[i] - winch.L0[i])


@njit(cache=_cache, inline="always")
def elastic_tension(L, L0, Ldot, cables):
    """An elastic cable's tension: EA strain plus damping when taut, 0 when slack, N."""
    if L > L0:
        return max(0.0, cables.EA * (L - L0) / L0 + cables.damping * Ldot)
    return 0.0


@njit(cache=_cache, inline="always")
def cable_step(cables, winch, bus):
    """The tensions the cables apply, T_app: the command (ideal cables), the stretch over the
    winch's L0 (elastic, length-controlled), or the winch's tension loop (elastic,
    tension-controlled)."""
    for i in range(bus.T_app.shape[0]):
        if not cables.elastic:
            bus.T_app[i] = bus.T_cmd[i]
        elif winch.tension_controlled:
            bus.T_app[i] = max(0.0, winch.T[i])
        else:
            bus.T_app[i] = elastic_tension(bus.L[i], winch.L0[i], bus.Ldot[i], cables)


@njit(cache=_cache, inline="always")
def brush_step(k, R, v, w, brush):
    """The brush's loads at the platform's actual velocity (v, w in C) and orientation R,
    less those along the plan that the controller's load model holds: written to
    ``brush.f``, ``brush.m`` (in C, about P), held over the step by the plant."""
    brush_velocity_step(v, w, R, brush.params.offset_P, brush.v)
    brush_wrench_step(brush.v, brush.n_C, brush.F_n[k], R, brush.params, brush.f, brush.m)
    for i in range(3):
        brush.f[i] -= brush.f_plan[k, i]
        brush.m[i] -= brush.m_plan[k, i]


@njit(cache=_cache, inline="always")
def log_step(k, x, R, bus, log):
    log.pose[k, :3] = x
    euler_from_R(R, log.pose[k, 3:])
    log.lengths[k] = bus.L
    log.T_cmd[k] = bus.T_cmd
    log.T_app[k] = bus.T_app


@njit(cache=_cache, inline="always")
def exchange(k, h, x, R, v, w, parts):
    """One exchange at t_k from the plant's state (x, R, v, w) in C: sensors, controller,
    winches, cables, log. Leaves the applied tensions in ``parts.bus.T_app``; returns 1 on a
    controller fallback, else 0."""
    model, bus = parts.model, parts.bus
    K.cables_step(x, R, model.c_C, model.p_P, bus.L, bus.J)
    length_rates(bus.J, v, w, bus.Ldot)
    fallback = command(k, h, x, R, v, w, parts)
    if parts.cables.elastic:  # ideal cables apply the command: no winch dynamics
        winch_step(k, parts.winch, bus, parts.sensors)
    cable_step(parts.cables, parts.winch, bus)
    if parts.brush.active:
        brush_step(k, R, v, w, parts.brush)
    log_step(k, x, R, bus, parts.log)
    return fallback
