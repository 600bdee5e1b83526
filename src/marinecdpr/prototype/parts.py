"""The virtual prototype's parts: each a typed record of its parameters and state, with a
compiled step function.

One exchange (every ``time.step_s``, 1 ms; the paper's figure 4) passes through the parts
in this order::

    plant state (x, R, v, w)
      -> sensors      :func:`sense`          pose sensor, MRU, encoders, load cells: ``ctl.meas``
      -> controller   :func:`~marinecdpr.control.step.control_step`
                                             the deployable controller -> T_cmd, L0_cmd
      -> winch        :func:`winch_step`     lag on the length or tension command, or
                      :func:`motor_step`     the motor's dynamics behind a tension loop
      -> cables       :func:`cable_step`     ideal (T = T_cmd) or elastic (T from stretch);
                      :func:`catenary_cables` heavy cables' sag
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
from marinecdpr.model.catenary import N_OUT, OUT_H, OUT_VB, catenary_forces
from marinecdpr.model.winch import OVERSPEED, WinchDrive, tension_control_step, winch_motor_step

__all__ = ["Sensors", "Mru", "Encoders", "LoadCells", "Loads", "Winch", "Motor", "Catenary", "Cables", "Bus", "Log",
           "BrushContact", "Parts", "exchange", "sense", "winch_step", "motor_step", "cable_step", "catenary_cables",
           "log_step", "motor_part", "no_motor", "catenary_part", "no_catenary"]

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


class Motor(NamedTuple):
    """The winches' motors (``simulation.cables.winch = "motor"``): each drum driven through
    its gearbox by a motor with torque, speed and power limits, inertia and friction
    (:mod:`marinecdpr.model.winch`), its tension loop on the load cell with feed-forward of
    the planned cable motion. The drum pays out ``drive.L0``, which the winch record's L0
    follows; the elastic cable's stretch over it is the tension.

    active : False for the other winches (the record is then empty). drive : WinchDrive
    (state: motor speeds, L0, torques, limit codes). Ldot_ref, Lddot_ref (n_steps, m): the
    plan's L' (m/s) and L'' (m/s^2). T_load, T_meas (m,): scratch, the cables' tensions and
    their load-cell readings, N. limited (2,) int64: the steps with any motor limited, and
    with any past its speed (OVERSPEED).
    """

    active: bool
    drive: WinchDrive
    Ldot_ref: np.ndarray
    Lddot_ref: np.ndarray
    T_load: np.ndarray
    T_meas: np.ndarray
    limited: np.ndarray


def motor_part(drive: WinchDrive, Ldot_ref: np.ndarray, Lddot_ref: np.ndarray, *, active: bool = True) -> Motor:
    """A :class:`Motor` record for ``drive``'s winches following the plan's L' and L''
    (n_steps, m), its scratch and counters allocated."""
    m = drive.omega.shape[0]
    return Motor(active, drive, np.ascontiguousarray(Ldot_ref, dtype=float),
                 np.ascontiguousarray(Lddot_ref, dtype=float), np.zeros(m), np.zeros(m), np.zeros(2, dtype=np.int64))


def no_motor(m: int) -> Motor:
    """An inactive :class:`Motor` record for m cables (of the same types as an active one)."""
    drive = WinchDrive(*(np.zeros(m) for _ in range(14)), np.zeros(m, dtype=np.int64))
    return motor_part(drive, np.zeros((1, m)), np.zeros((1, m)), active=False)


class Catenary(NamedTuple):
    """Heavy cables (``simulation.cables.model = "catenary"``, own plant): each an elastic
    catenary (:mod:`marinecdpr.model.catenary`) of weight w (N/m) and stiffness EA (N) from
    its frame anchor over the winch's L0, in the true vertical: the force on the platform is
    along the cable's tangent there, not its chord.

    active : False for straight cables (the record is then empty). up (2 n_steps + 1, 3):
    the true vertical (against gravity) in C on the half-step grid (row j: t = j h / 2).
    guess (m, 2): the last (H, V_B) of each cable, the next warm start, N. out (m, N_OUT):
    scratch of :func:`~marinecdpr.model.catenary.catenary_forces`. f (3,), J (m, 6): scratch.
    status (1,) int64: the number of solves that did not converge (none in a sound run).
    """

    active: bool
    w: float
    EA: float
    up: np.ndarray
    guess: np.ndarray
    out: np.ndarray
    f: np.ndarray
    J: np.ndarray
    status: np.ndarray


def catenary_part(m: int, w: float, EA: float, up: np.ndarray, *, active: bool = True) -> Catenary:
    """A :class:`Catenary` record for m cables of weight w (N/m) and stiffness EA (N) in the
    vertical ``up`` (2 n_steps + 1, 3), its scratch allocated and no warm start yet."""
    return Catenary(active, float(w), float(EA), np.ascontiguousarray(up, dtype=float), np.full((m, 2), np.nan),
                    np.zeros((m, N_OUT)), np.zeros(3), np.zeros((m, 6)), np.zeros(1, dtype=np.int64))


def no_catenary(m: int) -> Catenary:
    """An inactive :class:`Catenary` record for m cables (of the same types as an active one)."""
    return catenary_part(m, 0.0, np.inf, np.zeros((1, 3)), active=False)


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
    motor: Motor
    catenary: Catenary


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
        # tension it carries (the winch's own L0 where it holds a length, the drum's now
        # where a motor turns it)
        if parts.motor.active:
            L0 = parts.motor.drive.L0[i]
        elif cables.elastic and not winch.tension_controlled:
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
def motor_step(k, h, motor, winch, cables, bus, cells):
    """Advance the motors one step: the tension loop on each cable's load cell (its tension
    from the stretch over the drum's L0 now, plus the cell's noise), the motor under that
    tension over the step; the winch's L0, which the plant holds over the step, becomes the
    drum's mean over it (the trapezoid of its start and end: second-order in the step)."""
    drive = motor.drive
    for i in range(bus.T_cmd.shape[0]):
        motor.T_load[i] = elastic_tension(bus.L[i], drive.L0[i], bus.Ldot[i], cables)
        motor.T_meas[i] = motor.T_load[i] + cells.noise[k, i]
    tension_control_step(drive, bus.T_cmd, motor.T_meas, motor.Ldot_ref[k], motor.Lddot_ref[k])
    if winch_motor_step(drive, drive.tau, motor.T_load, h) > 0:
        motor.limited[0] += 1
        for i in range(bus.T_cmd.shape[0]):
            if drive.limited[i] == OVERSPEED:
                motor.limited[1] += 1
                break
    for i in range(bus.T_cmd.shape[0]):  # L0 moved by -(r_d / G) h omega over the step
        winch.L0[i] = drive.L0[i] + 0.5 * drive.r[i] / drive.G[i] * h * drive.omega[i]


@njit(cache=_cache, inline="always")
def elastic_tension(L, L0, Ldot, cables):
    """An elastic cable's tension: EA strain plus damping when taut, 0 when slack, N."""
    if L > L0:
        return max(0.0, cables.EA * (L - L0) / L0 + cables.damping * Ldot)
    return 0.0


@njit(cache=_cache, inline="always")
def catenary_cables(x, R, j, model, winch, cables, cat, Ldot, J, T):
    """Heavy cables' forces on the platform at the pose (x, R_PC) at half-step row j: each
    cable's catenary over the winch's L0 from its frame anchor to its platform anchor, in
    the vertical ``cat.up[j]``. Writes J (m, 6) rows (u, (R p) x u) along each force and T
    (m,) its magnitude, the tension at the platform plus the cable's damping on its chord's
    rate Ldot (m,), N: J^T T is the cables' wrench (J's rows on entry: any unit vector per
    cable, used where a cable pulls with no force)."""
    up = cat.up[j]
    f = cat.f
    for i in range(J.shape[0]):
        r0 = R[0, 0] * model.p_P[i, 0] + R[0, 1] * model.p_P[i, 1] + R[0, 2] * model.p_P[i, 2]
        r1 = R[1, 0] * model.p_P[i, 0] + R[1, 1] * model.p_P[i, 1] + R[1, 2] * model.p_P[i, 2]
        r2 = R[2, 0] * model.p_P[i, 0] + R[2, 1] * model.p_P[i, 1] + R[2, 2] * model.p_P[i, 2]
        d0, d1, d2 = x[0] + r0 - model.c_C[i, 0], x[1] + r1 - model.c_C[i, 1], x[2] + r2 - model.c_C[i, 2]
        v = d0 * up[0] + d1 * up[1] + d2 * up[2]
        e0, e1, e2 = d0 - v * up[0], d1 - v * up[1], d2 - v * up[2]  # the horizontal span
        h = np.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
        out = cat.out[i]
        if catenary_forces(h, v, winch.L0[i], cat.w, cat.EA, cat.guess[i], out, 100) == 1:
            cat.status[0] += 1
        cat.guess[i, 0] = out[OUT_H]
        cat.guess[i, 1] = out[OUT_VB]
        H, VB = out[OUT_H], out[OUT_VB]
        if h > 0.0:
            e0, e1, e2 = e0 / h, e1 / h, e2 / h
        f[0] = -(H * e0 + VB * up[0])  # the cable's pull on the platform: -(H e_h + V_B up)
        f[1] = -(H * e1 + VB * up[1])
        f[2] = -(H * e2 + VB * up[2])
        Tb = np.sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2])
        if Tb > 0.0:
            u0, u1, u2 = f[0] / Tb, f[1] / Tb, f[2] / Tb
        else:  # no force: any direction (the chord's)
            u0, u1, u2 = J[i, 0], J[i, 1], J[i, 2]
        J[i, 0], J[i, 1], J[i, 2] = u0, u1, u2
        J[i, 3], J[i, 4], J[i, 5] = r1 * u2 - r2 * u1, r2 * u0 - r0 * u2, r0 * u1 - r1 * u0
        T[i] = max(0.0, Tb + cables.damping * Ldot[i]) if Tb > 0.0 else 0.0


@njit(cache=_cache, inline="always")
def cable_step(cables, winch, motor, bus):
    """The tensions the cables apply, T_app: the command (ideal cables), the stretch over the
    drum's L0 now (motor winches), the stretch over the winch's L0 (elastic,
    length-controlled), or the winch's tension loop (elastic, tension-controlled)."""
    for i in range(bus.T_app.shape[0]):
        if motor.active:
            bus.T_app[i] = motor.T_load[i]
        elif not cables.elastic:
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
    if parts.motor.active:
        motor_step(k, h, parts.motor, parts.winch, parts.cables, bus, parts.load_cells)
    elif parts.cables.elastic:  # ideal cables apply the command: no winch dynamics
        winch_step(k, parts.winch, bus, parts.load_cells)
    cable_step(parts.cables, parts.winch, parts.motor, bus)
    if parts.catenary.active:  # heavy cables: the tension at the platform, from the sag
        cat = parts.catenary
        cat.J[:] = bus.J
        catenary_cables(x, R, 2 * k, ctl.model, parts.winch, parts.cables, cat, bus.Ldot, cat.J, bus.T_app)
    if parts.brush.active:
        brush_step(k, R, v, w, parts.brush)
    log_step(k, x, R, bus, parts.log)
    return fallback
