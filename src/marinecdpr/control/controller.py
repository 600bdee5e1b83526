"""A controller a user calls from their own loop, built from a scenario.

:class:`Controller` holds the controller's records (:mod:`~marinecdpr.control.records`):
the scenario's plan at mid-step, its model of the robot and of the known loads, its gains
and its memory; :meth:`Controller.step` takes one exchange's measurements and returns the
commands, through the compiled :func:`~marinecdpr.control.step.control_step`. The virtual
prototype builds its controller with the same functions and runs the same step, so what
is verified is what is deployed.

Example (a plain Python loop; ``read_*`` and ``send`` are the robot's own)::

    ctl = Controller(scenario)
    for k in range(ctl.n_steps):
        cmd = ctl.step(k * ctl.step_s, x=read_position(), R=read_attitude(), v=..., w=...,
                       eta=read_mru())  # eta (3, 6): the ship's eta, eta', eta''
        send(cmd.T_cmd)
"""

from __future__ import annotations

import math
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Any

import numpy as np
from numba import cfunc, njit, typeof, types
from numba.typed import List

from marinecdpr.borrowed import borrowed_first, with_function
from marinecdpr.compiled_cache import entry_point
from marinecdpr.control.records import (
    ENCODERS, KINDS, MODES, POSE_SENSOR, PREDICTIONS, SENSORS, ControllerParts, Gains, Loads, Reference, RobotModel,
    Safety, Slot, empty_command, empty_measurement, empty_safety, empty_slot, empty_work, encoders_record,
)
from marinecdpr.control.step import control_step, encoders_at, forecast_at
from marinecdpr.errors import InfeasibleError
from marinecdpr.geometry.rotations import matrix_from_euler
from marinecdpr.model.brush import cleaning_loads
from marinecdpr.model.dynamics import disturbance_in_C
from marinecdpr.model.tension_solver import METHOD_CODES
from marinecdpr.model.wind import scenario_wind_loads
from marinecdpr.motion.basemotion import frame_origin_of, frame_ship_motion
from marinecdpr.motion.prediction import make_predictor
from marinecdpr.motion.trajectory import evaluate_disturbance, evaluate_trajectory
from marinecdpr.planning.planner import Plan, plan_at, stand_in_plan, twist_on_hull
from marinecdpr.scenario.schema import MRU_UNITS, Scenario

__all__ = ["Controller", "Plans", "BrushLoads", "Detection", "detections", "reaction", "safety",
           "controller_parts", "controller_records", "plans", "stand_in_plans",
           "planned_brush_loads", "planned_wind_loads", "known_loads", "step_loads", "reference", "predictor_options", "held_records",
           "step_from_arrays", "step_entry_point", "step_function", "slot", "predictor", "types_only"]


@dataclass(frozen=True)
class Plans:
    """The plans a run flies (:func:`plans`): ``ref`` at t_k (what the run is judged against),
    ``ff`` at mid-step t_k + h/2 (what the controller flies), and the ship's motion on the
    half-step grid ``ship_h`` (:class:`~marinecdpr.motion.ship.ShipMotion`; row 2k:
    t_k, 2k + 1: t_k + h/2)."""

    ref: Plan
    ff: Plan
    ship_h: Any


@dataclass(frozen=True)
class BrushLoads:
    """The cleaning brush's planned loads on the half-step grid (:func:`planned_brush_loads`):
    f, m (2 n + 1, 3), N and N m, in C about P, and the planned R_PC (2 n + 1, 3, 3)."""

    f: np.ndarray
    m: np.ndarray
    R_PC: np.ndarray


def plans(scenario: Scenario, n: int, *, reference: Plan | None = None, base_model: str = "moving",
          ship_h=None) -> Plans:
    """The plan at t_k (what a run is judged against) and the plan to fly at mid-step,
    t_k + h/2, for the first n steps, with the ship's motion from its half-step grid
    ``ship_h`` (rows 2k: t_k; 2k + 1: t_k + h/2; computed if not given), as :class:`Plans`.

    Raises
    ------
    InfeasibleError
        If either plan has a step without tensions within limits.
    """
    method = scenario.planning.method
    h = scenario.time.step_s
    t = np.arange(n) * h
    if ship_h is None:
        ship_h = frame_ship_motion(scenario, np.arange(2 * n + 1) * (0.5 * h))
    ref = (reference if reference is not None else
           plan_at(scenario, t, method=method, ship=ship_h.take(slice(0, 2 * n, 2))))
    ff = plan_at(scenario, t + 0.5 * h, method=method, base_model=base_model, ship=ship_h.take(slice(1, 2 * n, 2)))
    for p in (ref, ff):
        if not p.feasible[:n].all():
            raise InfeasibleError(f"{scenario.name}: cannot simulate the {p.base_model}-base plan: {p.infeasibility()}")
    return Plans(ref=ref, ff=ff, ship_h=ship_h)


def stand_in_plans(scenario: Scenario, n: int, *, base_model: str = "moving", ship_h=None) -> Plans:
    """:func:`plans`' plans with their fields, shapes and types but without their dynamics
    (:func:`~marinecdpr.planning.planner.stand_in_plan`, at t_k and at mid-step): to build
    a prototype that compiles a real run's parts without compiling the planner's kernels."""
    h = scenario.time.step_s
    t = np.arange(n) * h
    if ship_h is None:
        ship_h = frame_ship_motion(scenario, np.arange(2 * n + 1) * (0.5 * h))
    return Plans(ref=stand_in_plan(scenario, t), ff=stand_in_plan(scenario, t + 0.5 * h, base_model=base_model),
                 ship_h=ship_h)


def reference(ff: Plan, *, sag: bool = False) -> Reference:
    """The controller's reference: the plan at mid-step, t_k + h/2 (holding its tensions over
    the step is second-order accurate); with ``sag`` (catenary cables) the extra length the
    plan's heavy cables sag by, else zeros."""
    c = np.ascontiguousarray  # every array C-ordered: one compiled loop for every plan length
    sag = (np.nan_to_num(ff.sag.lengths, nan=0.0) if sag and ff.sag is not None
           else np.zeros_like(ff.lengths))
    return Reference(x=c(ff.pose[:, :3]), R=c(matrix_from_euler(ff.pose[:, 3:])), v=c(ff.twist[:, :3]),
                     w=c(ff.twist[:, 3:]), a=c(ff.twist_dot[:, :3]), al=c(ff.twist_dot[:, 3:]), T=c(ff.tensions),
                     L=c(ff.lengths), Ldot=c(ff.length_rates), sag=c(sag))


def robot_model(scenario: Scenario) -> RobotModel:
    """The controller's model of the scenario's robot, ship layout and cables."""
    robot, cables = scenario.robot, scenario.simulation.cables
    return RobotModel(
        c_C=np.ascontiguousarray(robot.frame_anchors), p_P=np.ascontiguousarray(robot.platform_anchors),
        mass=robot.mass_kg, I_PP=np.ascontiguousarray(robot.inertia), g=scenario.environment.gravity_m_s2,
        origin=frame_origin_of(scenario),
        controlled=np.asarray(robot.controlled, dtype=np.int64), lo=robot.tension_min, hi=robot.tension_max,
        method=METHOD_CODES[scenario.planning.method], EA=float(cables.stiffness_EA_N or np.inf),
        damping=cables.damping_N_s_m, pulleys=robot.has_pulleys, z_C=np.ascontiguousarray(robot.pulley_axes),
        radius=np.ascontiguousarray(robot.pulley_radii), exits=np.zeros((robot.n_cables, 3)),
        wraps=np.zeros(robot.n_cables))


FK_TOL_M = 1e-10
"""The forward kinematics' step tolerance, m (and rad)."""
FK_ITER = 20
"""The forward kinematics' largest number of steps in one exchange (warm-started, it takes 2-4)."""


def gains(scenario: Scenario, *, closed: bool) -> Gains:
    """The scenario's ``[simulation.control]`` gains (a second-order error response of the
    given bandwidth and damping ratio), its winches, where its pose comes from
    (``[simulation.sensors]``) and how it brings the ship's samples to the present
    (``[simulation.mru]``)."""
    sim = scenario.simulation
    control, cables = sim.control, sim.cables
    wn = 2.0 * np.pi * control.bandwidth_hz
    return Gains(closed=bool(closed), kp=wn * wn, kd=2.0 * control.damping_ratio * wn,
                 lead_s=float(cables.winch_time_constant_s), tension_winches=cables.winch != "length",
                 pose_from=ENCODERS if sim.sensors.pose_from == "encoders" else POSE_SENSOR,
                 prediction=PREDICTIONS[sim.mru.prediction], fk_tol_m=FK_TOL_M, fk_iter=FK_ITER)


def predictor_options(mru) -> dict:
    """:func:`~marinecdpr.motion.prediction.make_predictor`'s options from ``[simulation.mru]``:
    the AR model's step, order and forgetting, and its warm-up in AR steps."""
    return dict(step_s=mru.ar_step_s, order=mru.ar_order, forgetting=mru.ar_forgetting,
                warmup_fits=max(1, math.ceil(mru.ar_warmup_s / mru.ar_step_s - 1e-9)))


_TYPES_ONLY: list = []


@contextmanager
def types_only():
    """Within this, controller records are built for their type only, as a stand-in
    controller's: their slots (:func:`slot`) empty, nothing compiled for them."""
    _TYPES_ONLY.append(True)
    try:
        yield
    finally:
        _TYPES_ONLY.pop()


def slot(function, record, arg_types: tuple) -> Slot:
    """A :class:`~marinecdpr.control.records.Slot` holding ``record`` and the address of
    ``function``'s C wrapper compiled for ``arg_types`` and the record's type (its last
    argument, a type reference): compiled, or read from the disk cache, where a controller
    first holds such a record, never into the step; within :func:`types_only`, empty."""
    if _TYPES_ONLY:
        return empty_slot()
    return Slot(words=with_function(function, record, arg_types))


def predictor(scenario: Scenario) -> Slot:
    """The ship-motion predictor ``[simulation.mru]`` asks for, in its slot (empty if none):
    :func:`~marinecdpr.control.step.forecast_at` on a
    :func:`~marinecdpr.motion.prediction.make_predictor`."""
    mru = scenario.simulation.mru
    if mru.prediction != "ar":
        return empty_slot()
    pred = make_predictor(max_horizon_s=max(1.0, 2.0 * mru.latency_s + scenario.time.step_s),
                          **predictor_options(mru))
    return slot(forecast_at, pred, (types.intp, types.float64, types.intp, types.float64, types.intp))


def _half_step_path(scenario: Scenario, ref: Plan, ff: Plan, n: int):
    """The planned path on the half-step grid: pose and twist (2 n + 1, 6) (row 2k: t_k, from
    the plan ``ref``; row 2k + 1: t_k + h/2, from ``ff``; row 2n: t_n, the trajectory's)."""
    last = evaluate_trajectory(scenario.trajectory, np.array([n * scenario.time.step_s]), scenario.cleaning,
                               scenario.ship)
    pose, twist = np.empty((2 * n + 1, 6)), np.empty((2 * n + 1, 6))
    pose[0:2 * n:2], pose[1:2 * n:2], pose[2 * n] = ref.pose[:n], ff.pose[:n], last.pose[0]
    twist[0:2 * n:2], twist[1:2 * n:2], twist[2 * n] = ref.twist[:n], ff.twist[:n], last.twist[0]
    return pose, twist


def planned_brush_loads(scenario: Scenario, ref: Plan, ff: Plan, n: int) -> BrushLoads | None:
    """The cleaning brush's loads along the planned path at the preload, on the half-step
    grid (row 2k: t_k, from the plan ``ref``; row 2k + 1: t_k + h/2, from ``ff``; row 2n:
    t_n), as :class:`BrushLoads`; None without ``[cleaning]``. A path held on the ship
    (``trajectory.on_hull``) slides the brush over the hull with the carriage's velocity
    added, as the plan's (:func:`~marinecdpr.planning.planner.twist_on_hull`)."""
    if scenario.cleaning is None:
        return None
    pose, twist = _half_step_path(scenario, ref, ff, n)
    R_PC = matrix_from_euler(pose[:, 3:])
    t_h = np.arange(2 * n + 1) * (0.5 * scenario.time.step_s)
    f_b, m_b = cleaning_loads(scenario.cleaning, twist_on_hull(scenario, pose[:, :3], twist, t_h), R_PC,
                              scenario.cleaning.preload)
    return BrushLoads(f=f_b, m=m_b, R_PC=R_PC)


def planned_wind_loads(scenario: Scenario, ref: Plan, ff: Plan, n: int, ship_h, *,
                       gust: str = "plan") -> BrushLoads | None:
    """The wind's loads (``[wind]``; :func:`~marinecdpr.model.wind.scenario_wind_loads`) along
    the planned path on the half-step grid (as :func:`planned_brush_loads`), with the ship's
    motion ``ship_h`` on that grid: ``gust = "plan"`` the wind the plan holds (the controller's
    model), ``"series"`` the mean plus the gust series (what the plants meet: the drag at the
    planned pose and velocity, which the platform follows within its tracking error). None
    without ``[wind]``."""
    if scenario.wind is None:
        return None
    pose, twist = _half_step_path(scenario, ref, ff, n)
    R_PC = matrix_from_euler(pose[:, 3:])
    t_h = np.arange(2 * n + 1) * (0.5 * scenario.time.step_s)
    f_w, m_w = scenario_wind_loads(scenario, pose[:, :3], twist, R_PC, ship_h, t_h, gust=gust)
    return BrushLoads(f=f_w, m=m_w, R_PC=R_PC)


def known_loads(scenario: Scenario, ship_h, brush_h: BrushLoads | None, wind_h: BrushLoads | None = None) -> Loads:
    """The disturbance on the half-step grid (2 n + 1 rows), as :class:`~marinecdpr.control.
    records.Loads`: in C, or in P (then ``in_P``), with the brush's
    planned loads ``brush_h`` (:func:`planned_brush_loads`) if any: the controller's load
    model (the prototype's plant replaces the brush's by those at the actual velocity), and
    the wind's ``wind_h`` (:func:`planned_wind_loads`) if any.

    Loads given in O turn into C with the ship's motion; loads given in P stay in P, and the
    plant and the controller turn them with the platform's actual (measured) orientation.
    """
    dist = scenario.disturbance
    t_h = np.arange(ship_h.x_SO_O.shape[0]) * (0.5 * scenario.time.step_s)  # not eta: a body's derives its angles
    f, m = evaluate_disturbance(dist, t_h)
    in_P = dist.frame == "P"
    if not in_P:
        f, m = disturbance_in_C(f, m, dist.frame, ship_h.R_SO, None)
    for extra in (brush_h, wind_h):
        if extra is not None:
            f_b, m_b = extra.f, extra.m
            if in_P:  # into P with the planned orientation
                f_b, m_b = (np.einsum("nji,nj->ni", extra.R_PC, x) for x in (f_b, m_b))
            f, m = f + f_b, m + m_b
    return Loads(f=np.ascontiguousarray(f, dtype=float), m=np.ascontiguousarray(m, dtype=float), in_P=in_P)


def step_loads(loads_h: Loads, n: int) -> Loads:
    """The half-step grid's loads ``loads_h`` (:func:`known_loads`) at t_k, k < n: the
    controller's model of the known loads."""
    return Loads(f=np.ascontiguousarray(loads_h.f[::2][:n]), m=np.ascontiguousarray(loads_h.m[::2][:n]),
                 in_P=loads_h.in_P)


def safety(scenario: Scenario) -> Safety:
    """The controller's fault detection (``[simulation.control.safety]``), nothing detected yet:
    the delays in exchanges (at least one), the MRU's timeout past its own latency and
    sampling period, the stop's damping 2 pi f, 1/s; the motors' torque limits where the
    winches are motor winches (``robot.winch``)."""
    sim, h = scenario.simulation, scenario.time.step_s
    cfg, mru = sim.control.safety, sim.mru
    rate = mru.rate_hz if mru.rate_hz is not None else MRU_UNITS[mru.unit][0]
    period = h if rate is None else 1.0 / rate
    robot = scenario.robot
    return empty_safety(robot.n_cables, robot.tension_min, robot.tension_max, detect=cfg.detect,
                        slack_fraction=cfg.slack_fraction, slack_steps=max(1, math.ceil(cfg.slack_delay_s / h - 1e-9)),
                        jump_m=cfg.jump_m, frozen_m=cfg.frozen_m, disagree_m=cfg.disagree_m,
                        disagree_steps=max(1, math.ceil(cfg.disagree_delay_s / h - 1e-9)),
                        mru_timeout_s=cfg.mru_timeout_s + mru.latency_s + period, park=cfg.on_cable_loss == "park",
                        stop_kd=2.0 * np.pi * cfg.stop_damping_hz, current_fraction=cfg.current_fraction,
                        current_steps=max(1, math.ceil(cfg.current_delay_s / h - 1e-9)),
                        tau_max=robot.winch.torque_max_Nm if sim.cables.winch == "motor" else None)


@dataclass(frozen=True)
class Detection:
    """One detection of the controller's watch: the step and its time (s), the kind
    (:data:`~marinecdpr.control.records.KINDS`), the sensor (:data:`~marinecdpr.control.records.SENSORS`'
    name, or "" for a cable's load cell against its command) and the cable (0-based; -1: none)."""

    step: int
    t: float
    kind: str
    sensor: str
    cable: int


def detections(s: Safety, step_s: float) -> list[Detection]:
    """What the safety record ``s`` detected, in order."""
    kinds = {v: n for n, v in KINDS.items()}
    sensors = {v: n for n, v in SENSORS.items()}
    return [Detection(step=int(e[0]), t=float(e[0] * step_s), kind=kinds[int(e[1])], sensor=sensors.get(int(e[2]), ""),
                      cable=int(e[3])) for e in s.events[:int(s.n_events[0])]]


def reaction(s: Safety) -> str:
    """The controller's reaction now (:data:`~marinecdpr.control.records.MODES`' name)."""
    return {v: n for n, v in MODES.items()}[int(s.mode[0])]


def controller_parts(scenario: Scenario, ff: Plan, loads: Loads, *, closed: bool) -> ControllerParts:
    """The controller's records for the scenario flying the mid-step plan ``ff`` with the
    known ``loads`` at t_k."""
    m, k = scenario.robot.n_cables, len(scenario.robot.controlled)
    res = scenario.simulation.sensors.encoder_resolution_m
    work = empty_work(m, k)
    work.q[:] = ff.pose[0]  # the encoders' first warm start: the plan's first pose
    ref = reference(ff, sag=scenario.simulation.cables.model == "catenary")
    model, meas, g = robot_model(scenario), empty_measurement(m), gains(scenario, closed=closed)
    encoders = empty_slot()
    if g.pose_from == ENCODERS:
        encoders = slot(encoders_at, encoders_record(meas, model, g, work, fk_atol_m=1e-4 + 3.0 * res), (types.intp,))
    return ControllerParts(ref=ref, model=model, gains=g, loads=loads, meas=meas, cmd=empty_command(m), work=work,
                           predictor=predictor(scenario), encoders=encoders, safety=safety(scenario))


def controller_records(scenario: Scenario, p: Plans, n: int, *, closed: bool) -> ControllerParts:
    """The controller's records for flying the plans ``p`` (:func:`plans`) over n steps, with
    the known loads at t_k (the brush's planned ones included): :func:`controller_parts`."""
    loads_h = known_loads(scenario, p.ship_h, planned_brush_loads(scenario, p.ref, p.ff, n),
                          planned_wind_loads(scenario, p.ref, p.ff, n, p.ship_h))
    return controller_parts(scenario, p.ff, step_loads(loads_h, n), closed=closed)


@njit(cache=True)
def held_records(parts):
    """The records in a one-item typed list: passed to a compiled function, the list is
    one pointer, where the records are ~90 arrays to convert at every call (~7 us).

    Parameters
    ----------
    parts : ControllerParts
        The controller's records (:func:`controller_parts`).

    Returns
    -------
    numba.typed.List
        One item, ``parts``; what :func:`step_from_arrays` and
        :func:`~marinecdpr.control.step.control_step` take as ``held``.
    """
    held = List()
    held.append(parts)
    return held


def _control_step(k, h, held):
    return control_step(k, h, held)


_STEP_FUNCTIONS: dict = {}


def step_function(held):
    """:func:`~marinecdpr.control.step.control_step` for ``held``'s type as a C function
    (``int64(int64, float64, held)``, a numba ``cfunc``), compiled once per type and cached
    on disk: what :func:`step_from_arrays` and the prototype's loop
    (:mod:`~marinecdpr.prototype.parts.controller`) both call, so that the controller's
    machine code is compiled once for both and linked into neither."""
    sig = types.int64(types.int64, types.float64, typeof(held))
    if sig not in _STEP_FUNCTIONS:
        _STEP_FUNCTIONS[sig] = cfunc(sig, cache=True)(_control_step)
    return _STEP_FUNCTIONS[sig]


@njit(cache=True)
def step_from_arrays(k, h, held, step, x, R, v, w, eta, clock, L, Ldot, T, tau, tau_set):
    """:func:`control_step` on a measurement given as arrays (copied into the measurement
    record); ``held``: :func:`held_records`'s list of the controller's records; ``step``:
    :func:`step_function` of their type.

    Parameters
    ----------
    k : int
        The step's index.
    h : float
        The step, s.
    held : numba.typed.List
        :func:`held_records` of the controller's records.
    step : numba cfunc
        :func:`step_function` for ``held``'s type (what is called).
    x, R, v, w : ndarray, shapes (3,), (3, 3), (3,), (3,)
        The measured pose and twist of the platform in C (m, rotation R_PC, m/s, rad/s).
    eta : ndarray, shape (3, 6)
        The ship's measured eta, eta', eta'' (m and rad, per s and s^2).
    clock : ndarray, shape (3,)
        The exchange's time t_k, the pose's time stamp and the ship sample's, s.
    L, Ldot, T : ndarray, shape (n_cables,)
        The encoders' lengths (m) and rates (m/s), the measured tensions (N).
    tau, tau_set : ndarray, shape (n_cables,)
        The motors' torques from their drives' currents and the drives' demands, N m (zeros:
        no motor watched).

    Returns
    -------
    int
        1 on a fallback to the plan's tensions, else 0 (:func:`control_step`); the
        commands are in the records' ``cmd``.
    """
    ctl = borrowed_first(held)  # the records read in place from their list: no reference counting of their arrays
    meas = ctl.meas
    for i in range(L.shape[0]):
        meas.L[i] = L[i]
        meas.Ldot[i] = Ldot[i]
        meas.T[i] = T[i]
        meas.tau[i] = tau[i]
        meas.tau_set[i] = tau_set[i]
    for i in range(3):
        meas.x[i] = x[i]
        meas.v[i] = v[i]
        meas.w[i] = w[i]
        meas.clock[i] = clock[i]
        for j in range(3):
            meas.R[i, j] = R[i, j]
    for j in range(3):
        for i in range(6):
            meas.eta[j, i] = eta[j, i]
    return step(k, h, held)


def _array(a, name: str, shape: tuple) -> np.ndarray:
    """``a`` as a C-contiguous float64 array of the given shape (a copy only if needed)."""
    if type(a) is not np.ndarray or a.dtype != _FLOAT or not a.flags.c_contiguous:
        a = np.ascontiguousarray(a, dtype=np.float64)
    if a.shape != shape:
        raise ValueError(f"{name} must have shape {shape}, not {a.shape}")
    return a


_FLOAT = np.dtype(np.float64)


def step_entry_point(held, m: int):
    """:func:`step_from_arrays` compiled for these records (:func:`~marinecdpr.compiled_cache.entry_point`,
    without running a step); a measurement of another dtype or layout would not be
    converted, so :meth:`Controller.step` converts its arguments first."""
    z3, eye, zm = np.zeros(3), np.eye(3), np.zeros(m)
    return entry_point(step_from_arrays, (0, 1.0, held, step_function(held), z3, eye, z3, z3, np.zeros((3, 6)), z3,
                                          zm, zm, zm, zm, zm))


class Controller:
    """The scenario's closed-loop controller, to call once per exchange.

    It tracks the scenario's plan (flown at mid-step, t_k + h/2) by computed torque on the
    measured pose error, with the scenario's tension method (any redundancy), gains
    (``[simulation.control]``) and winches (``[simulation.cables]``).

    Parameters
    ----------
    scenario : Scenario
    n_steps : int, optional
        Plan only the first steps (default: the scenario's whole run).
    closed : bool
        False feeds the plan's tensions forward (open loop).
    plan : Plan, optional
        The plan at t_k if already computed (``marinecdpr.plan_at``).

    Attributes
    ----------
    parts : ControllerParts
        The records the compiled step reads and writes.
    step_s : float
        The exchange's period h, s. n_steps : int.
    """

    def __init__(self, scenario: Scenario, *, n_steps: int | None = None, closed: bool = True,
                 plan: Plan | None = None) -> None:
        self.step_s = scenario.time.step_s
        self.n_steps = scenario.time.n_steps if n_steps is None else min(n_steps, scenario.time.n_steps)
        p = plans(scenario, self.n_steps, reference=plan)
        self.parts = controller_records(scenario, p, self.n_steps, closed=closed)
        self._clock = np.zeros(3)
        self._m = scenario.robot.n_cables
        self._encoders = self.parts.gains.pose_from == ENCODERS
        self._z3, self._eye, self._zm = np.zeros(3), np.eye(3), np.zeros(self._m)
        self._held = held_records(self.parts)
        self._call = step_entry_point(self._held, self._m)  # m given: a typed list read from Python compiles its getitem
        self._step = step_function(self._held)

    @property
    def held(self):
        """The controller's records in their one-item typed list: what the compiled step
        (:func:`~marinecdpr.control.step.control_step`) takes, in a user's compiled loop."""
        return self._held

    @property
    def detections(self) -> list[Detection]:
        """What the controller's watch has detected so far (:class:`Detection`), in order."""
        return detections(self.parts.safety, self.step_s)

    @property
    def reaction(self) -> str:
        """The controller's reaction now: normal, go_on, park, stop or brake
        (:data:`~marinecdpr.control.records.MODES`)."""
        return reaction(self.parts.safety)

    @property
    def command(self):
        """The last step's :class:`~marinecdpr.control.records.Command` (overwritten by the next)."""
        return self.parts.cmd

    def step(self, t: float, *, eta: np.ndarray, x: np.ndarray | None = None, R: np.ndarray | None = None,
             v: np.ndarray | None = None, w: np.ndarray | None = None, lengths: np.ndarray | None = None,
             length_rates: np.ndarray | None = None, tensions: np.ndarray | None = None,
             t_pose: float | None = None, t_ship: float | None = None, motor_torques: np.ndarray | None = None,
             motor_demands: np.ndarray | None = None):
        """The commands for the exchange at time t (s from the plan's start).

        Parameters
        ----------
        t : float
            The exchange's time t_k, s; the step index is round(t / h).
        eta : ndarray, shape (3, 6)
            The motion reference unit's last sample: the ship's eta, eta', eta'' (m, rad).
        x, v, w : ndarray, shape (3,)
            From a pose sensor (``[simulation.sensors] pose_from = "sensor"``): the platform's
            position (m), velocity (m/s) and angular velocity (rad/s) in C.
        R : ndarray, shape (3, 3)
            R_PC, the platform's orientation in C (with a pose sensor).
        lengths, length_rates, tensions : ndarray, shape (m,)
            From the winches (needed with ``pose_from = "encoders"``; with a pose sensor, what
            the fault detection watches where given): the unstretched lengths paid out (m),
            their rates (m/s) and the cables' measured tensions (N).
        t_pose, t_ship : float, optional
            The pose's and the ship sample's time stamps, s (default t: measured now; the
            encoders are read now).
        motor_torques, motor_demands : ndarray, shape (m,), optional
            Motor winches: each motor's torque from its drive's current and the drive's torque
            demand, N m (motor side), both or neither; the fault detection watches their
            difference (``current_fraction`` of the torque limit for ``current_delay_s``: the
            drive has failed: its cable is lost to the controller, ``on_cable_loss``, the others
            holding the pull its load cell reads).

        Returns
        -------
        Command
            T_cmd, L0_cmd (m,), at_limit (m,), flags (3,): the controller's own arrays,
            overwritten by the next step.
        """
        m = self._m
        present = self.parts.safety.present
        if self._encoders:
            if lengths is None or length_rates is None or tensions is None:
                raise ValueError("a controller with its pose from the encoders needs lengths, length_rates and "
                                 "tensions")
            x, R, v, w = self._z3, self._eye, self._z3, self._z3
            present[0] = 0
        elif x is None or R is None or v is None or w is None:
            raise ValueError("a controller with a pose sensor needs x, R, v and w")
        else:
            present[0] = 1
            x, R, v, w = _array(x, "x", (3,)), _array(R, "R", (3, 3)), _array(v, "v", (3,)), _array(w, "w", (3,))
        # with a pose sensor the encoders and load cells are optional: the watch uses what is given
        present[1] = tensions is not None
        present[2] = lengths is not None and length_rates is not None
        tensions = self._zm if tensions is None else _array(tensions, "tensions", (m,))
        if present[2]:
            lengths = _array(lengths, "lengths", (m,))
            length_rates = _array(length_rates, "length_rates", (m,))
        else:
            lengths = length_rates = self._zm
        if (motor_torques is None) != (motor_demands is None):
            raise ValueError("motor_torques and motor_demands go together: give both or neither")
        if motor_torques is None:
            motor_torques = motor_demands = self._zm
        else:
            motor_torques = _array(motor_torques, "motor_torques", (m,))
            motor_demands = _array(motor_demands, "motor_demands", (m,))
        eta = _array(eta, "eta", (3, 6))
        k = int(round(t / self.step_s))
        if not 0 <= k < self.n_steps:
            raise ValueError(f"t = {t:g} s is outside the controller's plan (0 to "
                             f"{(self.n_steps - 1) * self.step_s:g} s)")
        clock = self._clock
        clock[0] = t
        clock[1] = t if t_pose is None else t_pose
        clock[2] = t if t_ship is None else t_ship
        self._call(k, self.step_s, self._held, self._step, x, R, v, w, eta, clock, lengths, length_rates, tensions,
                   motor_torques, motor_demands)
        return self.parts.cmd
