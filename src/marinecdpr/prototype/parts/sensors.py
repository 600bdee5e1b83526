"""The sensors: the pose sensor, the load cells, the winches' encoders and the motion
reference unit (MRU), each writing its part of the controller's measurement ``meas``; with
motor winches and ``[simulation.noise] motor_torque_N_m``, the drives' current sensors
(:class:`MotorCurrents`: noise on the motor torques the controller reads).

Their errors are drawn in advance from ``[simulation.noise]`` (seeded, one stream in a
fixed order: a scenario's noise is the same whatever else changes): the closed loop
measures the platform (pose sensor, or the encoders through the controller's forward
kinematics) and the ship (the MRU, ``[simulation.mru]``); the load cells measure the
tensions in open and closed loop.

A load cell's, an encoder's or the MRU's faults (``[[faults]]``) are one more part after
them, :class:`SensorFaults`, built only where a scenario lists one: it turns the faulty
sensors' readings in the measurement into what they give (frozen, drifting, lost or
non-finite).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from marinecdpr.control.step import mm3
from marinecdpr.geometry.elastic import unstretched_length
from marinecdpr.geometry.rotations import euler_step
from marinecdpr.motion.basemotion import frame_ship_motion
from marinecdpr.prototype.parts import part
from marinecdpr.scenario.schema import MRU_UNITS

__all__ = ["PoseSensor", "LoadCells", "Encoders", "Mru", "MotorCurrents", "SensorFaults", "sensor_parts",
           "motor_currents", "sensor_faults", "CURRENT_STREAM", "build"]


@njit(cache=True, inline="always")  # a few lines: inlined into its one caller, part_step
def pose_sensor_step(k, h, part, bus):
    meas = bus.meas
    Rn, tmp = part.scratch[0], part.scratch[1, 0]  # the pose error's rotation
    euler_step(part.pose[k, 3:], part.zero, part.zero, Rn, tmp, tmp)
    mm3(Rn, bus.R, meas.R)  # the measured R = Rn R
    for i in range(3):
        meas.x[i] = bus.x[i] + part.pose[k, i]
        meas.v[i] = bus.v[i] + part.twist[k, i]
        meas.w[i] = bus.w[i] + part.twist[k, 3 + i]
    t = k * h
    meas.clock[0] = t
    meas.clock[1] = t


@part(step=pose_sensor_step, order=10, reads=("x", "R", "v", "w"),
      writes=("meas.x", "meas.R", "meas.v", "meas.w", "meas.clock"))
class PoseSensor(NamedTuple):
    """What the pose sensor adds to the truth, drawn in advance (zeros when not measured).

    pose : (n_steps, 6) position (m) and small rotation (rad) errors of the platform.
    twist : (n_steps, 6) velocity (m/s) and angular velocity (rad/s) errors.
    zero : (3,) zeros; scratch : (2, 3, 3) the sensor's working memory.
    """

    pose: np.ndarray
    twist: np.ndarray
    zero: np.ndarray
    scratch: np.ndarray


@njit(cache=True, inline="always")  # a few lines: inlined into its one caller, part_step
def load_cells_step(k, h, part, bus):
    meas = bus.meas
    for i in range(bus.T_app.shape[0]):
        part.T[i] += part.alpha * (bus.T_app[i] + part.noise[k, i] - part.T[i])
        meas.T[i] = part.T[i]
        bus.cell_noise[i] = part.noise[k, i]


@part(step=load_cells_step, order=11, reads=("T_app",), writes=("meas.T", "cell_noise"))
class LoadCells(NamedTuple):
    """The load cells: noise (n_steps, m) on the tension each cable applied over the last
    step, N, then a first-order low-pass (alpha: the fraction of the difference closed per
    step; 1: none). State: T (m,) the filtered reading, N. The tension-controlled winches'
    loops read the same noisy cells, unfiltered (``cell_noise`` on the bus)."""

    noise: np.ndarray
    alpha: float
    T: np.ndarray


@njit(cache=True, inline="always")  # a few lines: inlined into its one caller, part_step
def encoders_step(k, h, part, bus):
    meas, res = bus.meas, part.resolution
    for i in range(bus.L.shape[0]):
        # a winch pays out the unstretched length: the stretch of an elastic cable is the
        # tension it carries (a drum's length where a winch holds one)
        if part.from_stretch:
            L0 = unstretched_length(bus.L[i], bus.T_app[i], part.EA)
        else:
            L0 = bus.L0_drum[i]
        meas.L[i] = L0 if res == 0.0 else res * np.floor(L0 / res + 0.5)
        meas.Ldot[i] = bus.Ldot[i]


@part(step=encoders_step, order=12, reads=("L", "Ldot", "T_app", "L0_drum"), writes=("meas.L", "meas.Ldot"))
class Encoders(NamedTuple):
    """The winches' encoders: the unstretched length each winch has paid out, to
    ``resolution`` (m; 0: exact). from_stretch : no winch holds a length (ideal cables, or
    tension-controlled winches): the length is the cable's less its stretch at the applied
    tension, EA (N) its stiffness; else the drums' ``L0_drum``."""

    resolution: float
    from_stretch: bool
    EA: float


@njit(cache=True, inline="always")  # a few lines: inlined into its one caller, part_step
def mru_step(k, h, part, bus):
    meas = bus.meas
    j = part.latest[k]
    for d in range(3):
        for i in range(6):
            meas.eta[d, i] = part.eta[d, j, i]
    meas.clock[2] = part.t[j]


@part(step=mru_step, order=13, reads=(), writes=("meas.eta", "meas.clock"))
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


@njit(cache=True, inline="always")  # a few lines: inlined into its one caller, part_step
def motor_currents_step(k, h, part, bus):
    meas = bus.meas
    for i in range(meas.tau.shape[0]):  # the motor winch part wrote the true torque this exchange
        meas.tau[i] += part.noise[k, i]


@part(step=motor_currents_step, order=46, reads=("meas.tau",), writes=("meas.tau",))
class MotorCurrents(NamedTuple):
    """The motor winches' current sensors: noise (n_steps, m) on the torque each motor gave
    over the step as its drive's current measures it, N m at the motor, added to ``meas.tau``
    after the motor winch part has written the true torque (order 45, every exchange): what
    the controller's current watch reads next exchange. Not on the drives' demands
    (``meas.tau_set``), nor on what acts on the drums."""

    noise: np.ndarray


CURRENT_STREAM = 1
"""The spawn key of the current sensors' own stream of ``[simulation.noise] seed``
(``numpy.random.SeedSequence(seed, spawn_key=(CURRENT_STREAM,))``): drawing it changes no
other sensor's noise."""


def motor_currents(scenario, run: str, n: int) -> MotorCurrents | None:
    """The motor winches' current sensors of ``run`` over n steps, their noise (n, m) drawn at
    once, N m, from ``[simulation.noise] motor_torque_N_m`` (a standard deviation) on the
    seed's own stream (:data:`CURRENT_STREAM`); None where nothing reads them noisy (not the
    closed loop, no motor winches, or no noise: the measured torque then the true one)."""
    sigma = scenario.simulation.noise.motor_torque_N_m
    if run != "closed_loop" or scenario.simulation.cables.winch != "motor" or sigma == 0.0:
        return None
    seq = np.random.SeedSequence(scenario.simulation.noise.seed, spawn_key=(CURRENT_STREAM,))
    return MotorCurrents(noise=np.random.default_rng(seq).normal(0.0, sigma, (n, scenario.robot.n_cables)))


def build(context) -> list:
    """The four sensors (:func:`sensor_parts`), the load cells reading the plan's first tensions;
    with a sensor's faults, their part (:class:`SensorFaults`) after them; with noisy motor
    currents, their sensors (:func:`motor_currents`, after the motor winches)."""
    parts = sensor_parts(context.scenario, context.run, context.ship_h, context.n_steps, T0=context.ctl.ref.T[0])
    faults = sensor_faults(context.scenario.faults, context.scenario.time.step_s)
    currents = motor_currents(context.scenario, context.run, context.n_steps)
    return parts + [p for p in (faults, currents) if p is not None]


def sensor_parts(scenario, run: str, ship_h, n: int, *, T0=None) -> list:
    """The pose sensor, load cells, encoders and MRU of ``run`` over n steps, their errors
    drawn from ``[simulation.noise]`` in one seeded stream; ``ship_h`` the ship's motion on
    the half-step grid; T0 (m,) the load cells' first reading, N (default 0)."""
    nz, mru, sens = scenario.simulation.noise, scenario.simulation.mru, scenario.simulation.sensors
    h = scenario.time.step_s
    rng = np.random.default_rng(nz.seed)
    deg = np.pi / 180.0
    pose, twist = np.zeros((n, 6)), np.zeros((n, 6))
    unit_rate, unit_angle_deg, unit_heave_m = MRU_UNITS[mru.unit]
    rate = mru.rate_hz if mru.rate_hz is not None else unit_rate
    if rate is None and mru.latency_s == 0.0:  # a sample at every exchange, as it happens
        t_s, latest = np.arange(n) * h, np.arange(n)
        eta = np.stack([ship_h.eta[::2], ship_h.eta_dot[::2], ship_h.eta_ddot[::2]])[:, :n].copy()
    else:
        period = h if rate is None else 1.0 / rate
        # the latest sample j with j period + latency <= t_k (the first, until one has arrived)
        latest = np.maximum(np.floor((np.arange(n) * h - mru.latency_s) / period + 1e-9), 0).astype(np.int64)
        t_s = np.arange(latest[-1] + 1) * period
        ship_s = frame_ship_motion(scenario, t_s)  # an MRU on the frame: its axes' motion
        eta = np.stack([ship_s.eta, ship_s.eta_dot, ship_s.eta_ddot])
    n_s = eta.shape[1]
    if run == "closed_loop":
        pose[:, :3] = rng.normal(0.0, nz.pose_m, (n, 3))
        pose[:, 3:] = rng.normal(0.0, nz.pose_deg * deg, (n, 3))
        twist[:, :3] = rng.normal(0.0, nz.velocity_m_s, (n, 3))
        twist[:, 3:] = rng.normal(0.0, nz.rate_deg_s * deg, (n, 3))
        for i, (s_lin, s_ang) in enumerate(((nz.ship_position_m, nz.ship_angle_deg * deg),
                                            (nz.ship_velocity_m_s, nz.ship_rate_deg_s * deg),
                                            (nz.ship_acceleration_m_s2,
                                             nz.ship_angular_acceleration_deg_s2 * deg))):
            eta[i, :, :3] += rng.normal(0.0, s_lin, (n_s, 3))
            eta[i, :, 3:] += rng.normal(0.0, s_ang, (n_s, 3))
    noise = rng.normal(0.0, nz.tension_N, (n, scenario.robot.n_cables))
    noise_m = np.array(mru.noise_m if mru.noise_m is not None else (0.0, 0.0, unit_heave_m))
    noise_rad = np.radians(mru.noise_deg if mru.noise_deg is not None else (unit_angle_deg, unit_angle_deg, 0.0))
    if run == "closed_loop" and (noise_m.any() or noise_rad.any()):  # the unit's own noise, after the rest
        eta[0, :, :3] += rng.normal(0.0, 1.0, (n_s, 3)) * noise_m
        eta[0, :, 3:] += rng.normal(0.0, 1.0, (n_s, 3)) * noise_rad
    eta[0, :, :3] += np.asarray(mru.bias_m)
    eta[0, :, 3:] += np.radians(mru.bias_deg)
    fc = sens.load_cell_filter_hz
    alpha = 1.0 if fc == 0.0 else float(-np.expm1(-2.0 * np.pi * fc * h))
    cab = scenario.simulation.cables
    holds_length = cab.winch == "motor" or (cab.model != "ideal" and cab.winch != "tension")
    return [
        PoseSensor(pose=pose, twist=twist, zero=np.zeros(3), scratch=np.zeros((2, 3, 3))),
        LoadCells(noise=noise, alpha=alpha,
                  T=np.zeros(scenario.robot.n_cables) if T0 is None else np.array(T0, dtype=float)),
        Encoders(resolution=float(sens.encoder_resolution_m), from_stretch=not holds_length,
                 EA=float(cab.stiffness_EA_N or np.inf)),
        Mru(eta=np.ascontiguousarray(eta), t=np.ascontiguousarray(t_s, dtype=float),
            latest=np.ascontiguousarray(latest)),
    ]


# ----------------------------------------------------------------- a sensor's faults
SENSOR_CHANNELS = {"load_cell": 0, "encoder": 1, "mru": 2}
SENSOR_MODE_CODES = {"freeze": 0, "drift": 1, "dropout": 2, "non_finite": 3}
NEVER = np.iinfo(np.int64).max


@njit(cache=True, inline="always")
def _faulty(value, f, k, h, part):
    """A faulty sensor's reading from its sound one, fault f at exchange k (see SensorFaults)."""
    mode = part.mode[f]
    if mode == 0:
        if k == part.k0[f]:
            part.held[f] = value
        return part.held[f]
    if mode == 1:
        return value + part.rate[f] * (k * h - part.at_s[f])
    if mode == 2:
        return np.nan
    return np.inf


@njit(cache=True, inline="always")
def _faulty_mru(f, k, h, part, meas):
    """The MRU's fault f at exchange k on its sample meas.eta (3, 6) and its time stamp
    meas.clock[2]: frozen (both as at k0), drifting (eta's six displacements plus the rate
    times the time since at_s, m/s or rad/s; its rates and the stamp sound), lost (NaN, the
    stamp too) or non-finite (eta +inf; the stamp sound)."""
    mode = part.mode[f]
    if mode == 0:
        if k == part.k0[f]:
            for d in range(3):
                for j in range(6):
                    part.held_eta[f, d, j] = meas.eta[d, j]
            part.held_rate[f] = meas.clock[2]
        for d in range(3):
            for j in range(6):
                meas.eta[d, j] = part.held_eta[f, d, j]
        meas.clock[2] = part.held_rate[f]
    elif mode == 1:
        for j in range(6):
            meas.eta[0, j] += part.rate[f] * (k * h - part.at_s[f])
    else:
        bad = np.nan if mode == 2 else np.inf
        for d in range(3):
            for j in range(6):
                meas.eta[d, j] = bad
        if mode == 2:
            meas.clock[2] = np.nan


@njit(cache=True)
def sensor_faults_step(k, h, part, bus):
    """Each fault that acts at t_k (k0 <= k < k1) turns its sensor's reading in the
    measurement into the faulty one: a load cell's meas.T, an encoder's meas.L (and a frozen,
    lost or non-finite encoder's meas.Ldot as its length: held, NaN or +inf), the MRU's
    meas.eta and meas.clock[2] (:func:`_faulty_mru`)."""
    meas = bus.meas
    for f in range(part.mode.shape[0]):
        if k < part.k0[f] or k >= part.k1[f]:
            continue
        i = part.cable[f]
        if part.channel[f] == 2:
            _faulty_mru(f, k, h, part, meas)
        elif part.channel[f] == 0:
            meas.T[i] = _faulty(meas.T[i], f, k, h, part)
        else:
            meas.L[i] = _faulty(meas.L[i], f, k, h, part)
            if part.mode[f] == 0:
                if k == part.k0[f]:
                    part.held_rate[f] = meas.Ldot[i]
                meas.Ldot[i] = part.held_rate[f]
            elif part.mode[f] == 2:
                meas.Ldot[i] = np.nan
            elif part.mode[f] == 3:
                meas.Ldot[i] = np.inf


@part(step=sensor_faults_step, order=13.5, reads=("meas.T", "meas.L", "meas.Ldot", "meas.eta", "meas.clock"),
      writes=("meas.T", "meas.L", "meas.Ldot", "meas.eta", "meas.clock"))
class SensorFaults(NamedTuple):
    """The load cells', encoders' and the MRU's faults (``[[faults]]`` of kind ``load_cell``,
    ``encoder`` or ``mru``), after the sensors have measured: one entry per fault. channel
    (f,) int64: 0 a load cell, 1 an encoder, 2 the MRU; cable (f,) int64, from 0 (-1: the
    MRU); mode (f,) int64: 0 freeze, 1 drift, 2 dropout (NaN), 3 non-finite (+inf); k0, k1
    (f,) int64: the exchanges from which and until which (excluded) it acts; at_s (f,), s;
    rate (f,): a drift's, N/s, m/s (or on the MRU m/s and rad/s). State: held, held_rate
    (f,): a frozen sensor's reading and (an encoder's) rate (the MRU's time stamp, s);
    held_eta (f, 3, 6): a frozen MRU's sample."""

    channel: np.ndarray
    cable: np.ndarray
    mode: np.ndarray
    k0: np.ndarray
    k1: np.ndarray
    at_s: np.ndarray
    rate: np.ndarray
    held: np.ndarray
    held_rate: np.ndarray
    held_eta: np.ndarray


def sensor_faults(faults, h: float) -> SensorFaults | None:
    """The :class:`SensorFaults` of a scenario's ``faults`` with steps of h (s), or None
    without a sensor's fault. A fault acts from the first exchange at or after at_s until the
    first at or after at_s + duration_s."""
    fs = [f for f in faults if f.kind in SENSOR_CHANNELS]
    if not fs:
        return None

    def step(t: float) -> int:
        return int(np.ceil(t / h - 1e-9))

    return SensorFaults(
        channel=np.array([SENSOR_CHANNELS[f.kind] for f in fs], dtype=np.int64),
        cable=np.array([-1 if f.cable is None else f.cable - 1 for f in fs], dtype=np.int64),
        mode=np.array([SENSOR_MODE_CODES[f.mode] for f in fs], dtype=np.int64),
        k0=np.array([step(f.at_s) for f in fs], dtype=np.int64),
        k1=np.array([NEVER if f.duration_s is None else step(f.at_s + f.duration_s) for f in fs], dtype=np.int64),
        at_s=np.array([f.at_s for f in fs], dtype=float),
        rate=np.array([f.drift_per_s or 0.0 for f in fs], dtype=float),
        held=np.zeros(len(fs)), held_rate=np.zeros(len(fs)), held_eta=np.zeros((len(fs), 3, 6)))
