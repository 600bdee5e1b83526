"""The virtual prototype's parts: each a typed record of its parameters and state, with a
compiled step function.

One exchange (every ``time.step_s``, 1 ms; the paper's figure 4) passes through the parts
in this order::

    plant state (x, R, v, w)
      -> sensors      :func:`sense`          pose sensor, MRU, encoders, load cells: ``ctl.meas``
      -> controller   :func:`~marinecdpr.control.step.control_step`
                                             the deployable controller -> T_cmd, L0_cmd
      -> winch        :func:`winch_step`     lag on the length or tension command
      -> cables       :func:`cable_step`     ideal (T = T_cmd) or elastic (T from stretch)
      -> brush        :func:`brush_step`     a cleaning brush's loads at the actual velocity
      -> plant        (:mod:`~marinecdpr.prototype.plants`) advances one step with the tensions
    and :func:`log_step` records what happened.

The controller is :mod:`marinecdpr.control`'s, the same compiled step a user calls from
their own loop (:class:`~marinecdpr.control.Controller`): what is verified here is what is
deployed. Every record is a ``NamedTuple`` of numpy arrays and numbers, so the compiled
functions take it as one typed argument; time series have ``n_steps`` rows (index ``k``),
the cables ``m`` columns. Vectors are in the frame C of the robot's frame unless named
otherwise; units are SI (m, rad, N, s).

A new part (a sensor delay, a pulley, a brush contact) is a new record and step function
here, a field of :class:`Parts`, a call in :func:`exchange`, and a scenario section that
fills its record.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from marinecdpr.control.records import ControllerParts, Loads
from marinecdpr.control.step import cables_at, control_step, mm3
from marinecdpr.geometry.rotations import euler_step
from marinecdpr.model.brush import BrushParams, brush_velocity_step, brush_wrench_step

__all__ = ["Sensors", "Mru", "Encoders", "LoadCells", "Loads", "Winch", "Cables", "Bus", "Log", "BrushContact", "Parts", "exchange", "sense",
           "winch_step", "cable_step", "log_step"]

_cache = True
DIVERGENCE_M = 10.0
"""A run stops as diverged when the platform is this far from its plan."""


# --------------------------------------------------------------------------- records
class Sensors(NamedTuple):
    """The pose sensor: what it adds to the truth, drawn in advance (zeros when not measured).

    pose : (n_steps, 6) position (m) and small rotation (rad) errors of the platform.
    twist : (n_steps, 6) velocity (m/s) and angular velocity (rad/s) errors.
    zero : (3,) zeros; scratch : (2, 3, 3) the sensor's working memory.
    """

    pose: np.ndarray
    twist: np.ndarray
    zero: np.ndarray
    scratch: np.ndarray


class Mru(NamedTuple):
    """The motion reference unit: its samples of the ship's motion, drawn in advance (the
    ship's motion does not depend on the robot), with their errors.

    eta : (3, n_samples, 6) eta, eta', eta'' as sampled (m, rad). t : (n_samples,) the
    samples' times, s. latest : (n_steps,) int, the latest sample that has reached the
    controller at t_k (its latency past).
    """

    eta: np.ndarray
    t: np.ndarray
    latest: np.ndarray


class Encoders(NamedTuple):
    """The winches' encoders: the unstretched length each winch has paid out (the
    geometric length of an inextensible cable), to ``resolution`` (m; 0: exact)."""

    resolution: float


class LoadCells(NamedTuple):
    """The load cells: noise (n_steps, m) on the tension each cable applied over the last
    step, N, then a first-order low-pass (alpha: the fraction of the difference closed per
    step; 1: none). State: T (m,) the filtered reading, N. The tension-controlled winches'
    loops read the same noisy cells, unfiltered."""

    noise: np.ndarray
    alpha: float
    T: np.ndarray


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


class Parts(NamedTuple):
    """The prototype: every part's record, composed by :func:`exchange`. ``loads`` are the
    loads the plant applies (the same record as the controller's model of them)."""

    ctl: ControllerParts
    sensors: Sensors
    mru: Mru
    encoders: Encoders
    load_cells: LoadCells
    loads: Loads
    winch: Winch
    cables: Cables
    bus: Bus
    log: Log
    brush: BrushContact


def empty_bus(ctl: ControllerParts) -> Bus:
    """The bus of an exchange; its commands are the controller's (the same arrays), the
    applied tensions start at the plan's first."""
    m = ctl.cmd.T_cmd.shape[0]
    return Bus(np.empty(m), np.empty(m), np.empty((m, 6)), ctl.cmd.T_cmd, ctl.cmd.L0_cmd, np.array(ctl.ref.T[0]))


def empty_log(n_steps: int, m: int) -> Log:
    return Log(np.empty((n_steps, 6)), np.empty((n_steps, m)), np.empty((n_steps, m)), np.empty((n_steps, m)))


# ------------------------------------------------------------------ small compiled maths
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
def sense(k, h, x, R, v, w, parts, meas):
    """The sensors at t_k, written to the controller's measurement ``meas``: the pose sensor's
    pose and twist with their errors, the encoders' lengths and rates, the load cells'
    tensions (time-stamped t_k) and the motion reference unit's latest sample (stamped with
    its own time)."""
    sensors, bus, cells = parts.sensors, parts.bus, parts.load_cells
    Rn, tmp = sensors.scratch[0], sensors.scratch[1, 0]  # the pose error's rotation
    euler_step(sensors.pose[k, 3:], sensors.zero, sensors.zero, Rn, tmp, tmp)
    mm3(Rn, R, meas.R)  # the measured R = Rn R
    for i in range(3):
        meas.x[i] = x[i] + sensors.pose[k, i]
        meas.v[i] = v[i] + sensors.twist[k, i]
        meas.w[i] = w[i] + sensors.twist[k, 3 + i]
    cables, winch, res = parts.cables, parts.winch, parts.encoders.resolution
    for i in range(bus.L.shape[0]):
        cells.T[i] += cells.alpha * (bus.T_app[i] + cells.noise[k, i] - cells.T[i])
        meas.T[i] = cells.T[i]
        # a winch pays out the unstretched length: the stretch of an elastic cable is the
        # tension it carries (the winch's own L0 where it holds a length)
        if cables.elastic and not winch.tension_controlled:
            L0 = winch.L0[i]
        else:
            L0 = bus.L[i] / (1.0 + bus.T_app[i] / cables.EA)
        meas.L[i] = L0 if res == 0.0 else res * np.floor(L0 / res + 0.5)
        meas.Ldot[i] = bus.Ldot[i]
    mru = parts.mru
    j = mru.latest[k]
    for d in range(3):
        for i in range(6):
            meas.eta[d, i] = mru.eta[d, j, i]
    t = k * h
    meas.clock[0] = t
    meas.clock[1] = t
    meas.clock[2] = mru.t[j]

@njit(cache=_cache, inline="always")
def winch_step(k, winch, bus, cells):
    """Advance the winches one step: L0 towards L0_cmd, or the tension loop (on its noisy
    load cell) towards T_cmd, each with the first-order lag."""
    for i in range(bus.T_cmd.shape[0]):
        if winch.tension_controlled:
            winch.T[i] += winch.lag * (bus.T_cmd[i] - cells.noise[k, i] - winch.T[i])
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
    ctl, bus = parts.ctl, parts.bus
    cables_at(x, R, ctl.model, bus.L, bus.J)
    length_rates(bus.J, v, w, bus.Ldot)
    sense(k, h, x, R, v, w, parts, ctl.meas)
    fallback = control_step(k, h, ctl)
    if parts.cables.elastic:  # ideal cables apply the command: no winch dynamics
        winch_step(k, parts.winch, bus, parts.load_cells)
    cable_step(parts.cables, parts.winch, bus)
    if parts.brush.active:
        brush_step(k, R, v, w, parts.brush)
    log_step(k, x, R, bus, parts.log)
    return fallback
