"""The virtual prototype: a plan flown on a physics plant, open or closed loop.

Like the paper's co-simulation (its figure 4), the controller and the plant exchange
data once per time step (``time.step_s``, 1 ms): at t_k the controller reads the
plant's state (with sensor noise), commands cable tensions (or a winch's unstretched
length), the cable/actuator model turns the command into applied tensions, and the
plant advances one step with those tensions held. The parts are records with step
functions and declared signals (:mod:`~marinecdpr.prototype.parts`), assembled from the
scenario by :mod:`~marinecdpr.prototype.builder`; this module runs a plant's compiled
loop (:mod:`~marinecdpr.prototype.plants`) over blocks of steps.

Plants (``simulation.plant``):
  ``mujoco``  the independent engine (:mod:`~marinecdpr.prototype.mujoco_model`), the default;
  ``own``     this package's forward dynamics (:func:`~marinecdpr.model.rigid_body.forward_step`),
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

from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np

from marinecdpr.compiled_cache import bound
from marinecdpr.control.controller import (
    controller_parts, detections, known_loads, planned_brush_loads, planned_wind_loads, plans, reaction,
    stand_in_plans, step_loads,
)
from marinecdpr.control.records import RESIDUALS, Loads
from marinecdpr.motion.basemotion import frame_ship_motion
from marinecdpr.prototype import builder
from marinecdpr.prototype.parts import DIVERGENCE_M, law_pointer
from marinecdpr.prototype.parts.brush import normal_force
from marinecdpr.prototype.plants import (
    MujocoPlant, OwnPlant, ShipDrive, mujoco_exchange, mujoco_law, mujoco_library, mujoco_loop, own_loop,
)
from marinecdpr.errors import ScenarioError, SimulationDivergedError
from marinecdpr.geometry.rotations import matrix_from_euler, quaternion_from_matrix
from marinecdpr.planning.carriage import DriveForce
from marinecdpr.planning.planner import Plan
from marinecdpr.scenario.schema import MRU_UNITS, Scenario

__all__ = ["RUNS", "SimResult", "simulate", "kernels_cached", "KERNEL_COMPILE_S", "prototype", "normal_force"]

RUNS = ("open_loop", "closed_loop", "fixed_base_open_loop")
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
        0 for the own plant, which moves the ship exactly); a carried frame's ship body moves
        as C (:mod:`~marinecdpr.prototype.mujoco_model`).
    winch_limited_steps, winch_overspeed_steps : int
        Motor winches (``simulation.cables.winch = "motor"``): the steps where any motor's
        torque was cut to its torque, power or speed limit, and where any turned past its
        speed limit; 0 for other winches.
    carriage_tracking_error : float
        A frame carried on a rail, on MuJoCo: the largest deviation of C from its composed
        motion (the ship body, which moves as C: its origin in O, m; the Euler angles of R_CO,
        rad), the same as ``ship_tracking_error`` (0 otherwise).
    detections : tuple of Detection
        What the closed loop's controller detected (``[simulation.control.safety]``;
        :class:`~marinecdpr.control.controller.Detection`: step, time, kind, sensor, cable), in
        order; empty without a fault.
    reaction : str
        The controller's reaction at the run's end: normal, go_on, park, stop or brake.
    residual_peaks : dict
        Each watched residual's largest ratio to its threshold before the first detection
        (:data:`~marinecdpr.control.records.RESIDUALS`; >= 1 trips); empty where not watched.
    carriage_drive : DriveForce or None
        A carriage with its mass (``ship.carriage.mass_kg``): the force its drive gives along
        the rail at each step (:class:`~marinecdpr.planning.carriage.DriveForce`, from the
        carriage part, :mod:`~marinecdpr.prototype.parts.carriage`); None otherwise.
    faults : tuple of dict
        The scenario's ``[[faults]]`` in order, each ``{"kind", "cable", "at_s", "acted_s"}``:
        ``acted_s`` the time of the exchange from which the fault acted (t_k >= at_s; a
        winch_brake's, when its brake held), s, or None where the run ended before it; a
        motor_power_loss's also ``brake_held_s`` (None: no brake held); () without faults.
    brakes_held : tuple of (int, float)
        Each winch brake that held its drum in the run (a fault's or the controller's
        command's, after ``[simulation.control.safety] brake_delay_s``): (cable from 1, the
        time from which it held, s), by cable; () where none held (and without a winch).
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
    winch_limited_steps: int = 0
    winch_overspeed_steps: int = 0
    carriage_tracking_error: float = 0.0
    carriage_drive: Any = None
    detections: tuple = ()
    reaction: str = "normal"
    residual_peaks: dict = field(default_factory=dict)
    faults: tuple = ()
    brakes_held: tuple = ()

    @property
    def pose_error(self) -> np.ndarray:
        """Actual minus planned pose, shape (n_steps, 6), m and rad."""
        return self.pose - self.pose_planned


# ------------------------------------------------------------------- orchestration
_quat_from_R = quaternion_from_matrix


def simulate(
    scenario: Scenario,
    *,
    run: str = "open_loop",
    reference: Plan | None = None,
    plant: str | None = None,
    n_steps: int | None = None,
    progress: Callable[[int, int], None] | None = None,
    stand_in: bool = False,
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
    stand_in : bool
        Fly stand-in plans (:func:`~marinecdpr.control.controller.stand_in_plans`) instead
        of the scenario's: the run has a real run's types, so it compiles the loop a real
        run takes, without the planner's kernels; its result means nothing
        (:func:`~marinecdpr.prototype.warmup.compile_apart`). Not with ``reference``.

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
    plant = plant or scenario.simulation.plant
    if plant not in ("mujoco", "own"):
        raise ValueError(f"plant must be 'mujoco' or 'own', not {plant!r}")
    if stand_in and reference is not None:
        raise ValueError("a stand-in run flies no reference plan")
    if plant == "mujoco" and scenario.simulation.cables.model == "catenary":
        raise ScenarioError("simulation.cables.model: catenary cables need the own plant (--plant own): "
                            "MuJoCo's tendons are straight", source=scenario.name)
    h = scenario.time.step_s
    n = scenario.time.n_steps if n_steps is None else min(n_steps, scenario.time.n_steps)
    check_run_size(scenario, "simulate", n_steps=n)  # before any array of n steps
    t = np.arange(n) * h
    asm = prototype(scenario, run, n, reference=reference, stand_in=stand_in)
    ship_h, ref = asm.ship_h, asm.ref
    x0, R0, v0, w0 = _initial_state(scenario, ref)
    system = asm.wired
    if plant == "own":
        system.law[0] = law_pointer(asm.system.cable, system.bus)  # the cable part's law within the step
        y = np.concatenate([x0, quaternion_from_matrix(R0), v0, w0])
        loads = asm.loads_h
        own = OwnPlant(y=y, R_SO=np.ascontiguousarray(ship_h.R_SO), w_s=np.ascontiguousarray(ship_h.omega_SO_S),
                       al_s=np.ascontiguousarray(ship_h.alpha_SO_S), a_SO=np.ascontiguousarray(ship_h.a_SO_O),
                       f=loads.f, m=loads.m, in_P=loads.in_P)
        fallbacks = _blocks(scenario, run, t, progress, bound(own_loop, h, own, system), asm)
        ship_error = carriage_error = 0.0  # the own plant moves the ship (and C) exactly
    else:
        fallbacks, ship_error, carriage_error = _run_mujoco(scenario, run, t, ship_h, (x0, R0, v0, w0), asm,
                                                            progress)
    log = asm.get("Log")
    log.pose[:, 3:] = np.unwrap(log.pose[:, 3:], axis=0)
    motor = asm.get("MotorWinch") or asm.get("CatenaryMotorWinch")
    limited = motor.limited if motor is not None else (0, 0)
    drive = asm.get("CarriageDrive")
    watch = asm.ctl.safety
    watched = run == "closed_loop" and watch.detect
    return SimResult(
        run=run, plant=plant, t=t, pose_planned=np.ascontiguousarray(ref.pose[:n]), pose=log.pose,
        lengths_planned=np.ascontiguousarray(ref.lengths[:n]), lengths=log.lengths,
        tensions_commanded=log.T_cmd, tensions=log.T_app, controller_fallbacks=int(fallbacks),
        ship_tracking_error=ship_error, winch_limited_steps=int(limited[0]),
        winch_overspeed_steps=int(limited[1]), carriage_tracking_error=carriage_error,
        carriage_drive=None if drive is None else DriveForce(
            t=t, force_N=drive.force, limit_N=scenario.ship.carriage.drive_force_max_N),
        detections=tuple(detections(watch, h)), reaction=reaction(watch),
        residual_peaks=_residual_peaks(scenario, watch) if watched else {},
        faults=_faults_acted(scenario, n), brakes_held=_brakes_held(asm, h),
    )


def _brakes_held(asm, h: float) -> tuple:
    """(cable from 1, time from which its brake held, s) for each drum a brake held."""
    braked = asm.get("BrakedLagWinch") or asm.get("FaultyMotorWinch")
    if braked is None:
        return ()
    return tuple((i + 1, float(braked.k_brake[i] * h)) for i in range(braked.held.shape[0]) if braked.held[i])


def _faults_acted(scenario: Scenario, n: int) -> tuple:
    """Each of the scenario's faults and when it acted in a run of n steps (SimResult.faults):
    the first exchange at or after its time, as its part takes it
    (:func:`~marinecdpr.prototype.parts.cables.snap_steps`,
    :func:`~marinecdpr.prototype.parts.winches.fault_steps`); a brake's, when it held."""
    from marinecdpr.prototype.parts.cables import snap_steps
    from marinecdpr.prototype.parts.winches import fault_steps

    h, m = scenario.time.step_s, scenario.robot.n_cables
    snap = snap_steps(scenario.faults, m, h)
    power, brake = fault_steps(scenario.faults, m, h)
    out = []
    for f in scenario.faults:
        i = (f.cable or 1) - 1
        k = {"cable_snap": snap[i], "motor_power_loss": power[i], "winch_brake": brake[i]}.get(
            f.kind, int(np.ceil(f.at_s / h - 1e-9)))  # a sensor's, from its first exchange at or after at_s
        entry = {"kind": f.kind, "cable": f.cable, "at_s": f.at_s, "acted_s": float(k * h) if k < n else None}
        if f.kind == "controller_deadline":
            entry["steps"] = f.steps
        if f.kind == "motor_power_loss":
            entry["brake_held_s"] = float(brake[i] * h) if brake[i] < n else None
        out.append(entry)
    return tuple(out)


@dataclass(frozen=True)
class Prototype(builder.Assembly):
    """The assembled prototype of a run (:class:`~marinecdpr.prototype.builder.Assembly`: its
    system and each part by its record's class name) with what it was built from: the ship's
    motion on the half-step grid ``ship_h``, the plans ``ref`` (at t_k) and ``ff`` (at
    mid-step), and the known loads: on the half-step grid ``loads_h`` (f, m (2 n + 1, 3) in C,
    or in P if ``in_P``) that the own plant applies; at t_k ``known`` (the controller's model
    of them: the same, but with ``[wind]`` the wind the plan holds where the plants meet the
    gust series); ``held``, what MuJoCo's ship drive holds over each step (the loads at t_k;
    with ``[wind]``, the wind's at mid-step); ``ctl``, the controller's records
    (:class:`~marinecdpr.control.records.ControllerParts`; what its watch detected is in
    their ``safety``)."""

    ship_h: Any
    ref: Plan
    ff: Plan
    loads_h: Loads
    known: Loads
    held: Loads
    ctl: Any = None


def prototype(scenario: Scenario, run: str, n: int, *, reference: Plan | None = None, include=None,
              given: tuple[str, ...] = (), brush: bool = True, stand_in: bool = False):
    """The run's assembled :class:`Prototype` with the ship's motion on the half-step grid and
    the plans at t_k and at mid-step (parts built from the scenario by
    :func:`~marinecdpr.prototype.builder.assemble`; ``include`` chooses part modules, ``given``
    names the signals the caller writes instead). With ``stand_in``, the plans are
    :func:`~marinecdpr.control.controller.stand_in_plans`: every part has a real run's
    types, nothing of the planner is compiled, and the prototype is only to compile."""
    h = scenario.time.step_s
    # the ship's motion and the loads on the half-step grid: j = 2k is t_k, j = 2k + 1 is t_k + h/2
    t_h = np.arange(2 * n + 1) * (0.5 * h)
    ship_h = frame_ship_motion(scenario, t_h)  # C's own motion for a frame on a carriage
    base_model = "fixed" if run == "fixed_base_open_loop" else "moving"
    if stand_in:
        p = stand_in_plans(scenario, n, base_model=base_model, ship_h=ship_h)
    else:
        p = plans(scenario, n, reference=reference, base_model=base_model, ship_h=ship_h)
    ref, ff = p.ref, p.ff
    brush_h = planned_brush_loads(scenario, ref, ff, n) if brush else None
    loads_h = known_loads(scenario, ship_h, brush_h)
    loads = held = step_loads(loads_h, n)
    if scenario.wind is not None:  # the plants meet the gust series, the controller knows the plan's wind
        loads = step_loads(known_loads(scenario, ship_h, brush_h, planned_wind_loads(scenario, ref, ff, n, ship_h)), n)
        calm_h, loads_h = loads_h, known_loads(scenario, ship_h, brush_h,
                                               planned_wind_loads(scenario, ref, ff, n, ship_h, gust="series"))
        held = _held_with_wind(calm_h, loads_h, n)
    ctl = controller_parts(scenario, ff, loads, closed=run == "closed_loop")
    x0, R0, _, _ = _initial_state(scenario, ref)
    ctx = builder.context(scenario, run, n, plan=ref, ff=ff, ship_h=ship_h, brush_h=brush_h, loads=loads, ctl=ctl,
                          x0=x0, R0=R0)
    asm = builder.assemble(ctx, include=include, given=given)
    return Prototype(system=asm.system, by_name=asm.by_name, wired=asm.wired, ship_h=ship_h, ref=ref, ff=ff, loads_h=loads_h,
                     known=loads, held=held, ctl=ctl)


def _held_with_wind(calm_h: Loads, loads_h: Loads, n: int) -> Loads:
    """The loads MuJoCo holds over each step with a wind: the calm loads at t_k (as without
    wind) plus the wind's at mid-step, t_k + h/2 (the midpoint rule: a gust that changes within
    the step held at its start would lag the own plant's RK4 by h/2)."""
    f = calm_h.f[0:2 * n:2] + (loads_h.f[1:2 * n:2] - calm_h.f[1:2 * n:2])
    m = calm_h.m[0:2 * n:2] + (loads_h.m[1:2 * n:2] - calm_h.m[1:2 * n:2])
    return Loads(f=np.ascontiguousarray(f), m=np.ascontiguousarray(m), in_P=loads_h.in_P)


def _initial_state(scenario: Scenario, ref: Plan):
    """The platform at t = 0: on the plan, plus the scenario's initial error: x, R, v, w in C."""
    sim = scenario.simulation
    x0 = ref.pose[0, :3] + np.asarray(sim.initial_error_m)
    R0 = matrix_from_euler(np.radians(sim.initial_error_deg)) @ matrix_from_euler(ref.pose[0, 3:])
    return x0, R0, ref.twist[0, :3].copy(), ref.twist[0, 3:].copy()


def _blocks(scenario: Scenario, run: str, t: np.ndarray, progress, loop, asm, block: int = 500) -> int:
    """Run ``loop(k0, k1)`` over blocks of steps; the fallbacks. Raises on divergence, or
    where a part's step failed (``asm.wired.failed``)."""
    n = len(t)
    fallbacks = 0
    for k0 in range(0, n, block):
        k1 = min(n, k0 + block)
        fb, bad = loop(k0, k1)
        fallbacks += fb
        if bad >= 0 and asm.wired.failed[0] > 0:
            place = asm.wired.failed[1]  # in the parts + 1; 0: the cable law the builder added
            name = type(asm.system.parts[place - 1] if place > 0 else asm.system.cable).__name__
            raise SimulationDivergedError(
                f"{scenario.name}: {run} stopped at t = {t[asm.wired.failed[0] - 1]:.3f} s: the prototype's "
                f"{name} part failed in its step (a division by zero or a value out of its range)")
        if bad >= 0:
            raise SimulationDivergedError(_diverged_message(scenario, run, t[bad]))
        if progress is not None:
            progress(k1, n)
    return fallbacks


KERNEL_COMPILE_S = 40.0
"""About how long the first simulation compiles its loop on a fresh install, s (README)."""


def compiled_cached(*dispatchers) -> bool:
    """False if one of numba's ``dispatchers`` must first be compiled: neither this process
    nor numba's cache (an index for the current source with an entry) holds it. True when
    unsure (numba's cache internals changed): no notice rather than a wrong one."""
    try:
        return all(bool(d.signatures) or bool(d._cache._cache_file._load_index()) for d in dispatchers)
    except Exception:  # noqa: BLE001 - a private numba API
        return True


def kernels_cached(plant: str) -> bool:
    """False if simulating on ``plant`` must first compile its loop (see :func:`compiled_cached`)."""
    if plant == "own":
        return compiled_cached(own_loop)
    if mujoco_library():
        return compiled_cached(mujoco_loop)
    return compiled_cached(mujoco_exchange)  # MuJoCo's library not found: each exchange compiled


def _residual_peaks(scenario: Scenario, watch) -> dict:
    """The watched residuals' peaks by name (:data:`~marinecdpr.control.records.RESIDUALS`):
    the motors' currents only where the winches are motor winches."""
    motors = scenario.simulation.cables.winch == "motor"
    return {name: float(v) for name, v in zip(RESIDUALS, watch.peak) if motors or name != "current"}


def _diverged_message(scenario: Scenario, run: str, t: float) -> str:
    return (f"{scenario.name}: {run} diverged at t = {t:.3f} s: the platform is more than "
            f"{DIVERGENCE_M:g} m from its plan or its state is not finite")


# ----------------------------------------------------------------------- MuJoCo plant
def _ship_drive(ship_h, loads: Loads, n: int, carried: bool = False) -> ShipDrive:
    """Feed-forward forces that move the (gravity-compensated, isotropic) MuJoCo ship along
    eta, evaluated at mid-step; a servo acts on the error at the step's start. Loads in C
    are applied in O (a load given in P is turned at each exchange).

    For a frame on a carriage (``carried``), ``ship_h`` is C's composed motion (a body's,
    :func:`~marinecdpr.motion.ship.body_motion`) and the ship body moves as C
    (:mod:`~marinecdpr.prototype.mujoco_model`): its eta is C's origin and the Euler angles of
    R_CO, and the yaw that turns its pitch axis at mid-step is R_CO's own (atan2 of its first
    column), so that C's angles are derived at t_k alone (the motion reference unit reads the
    same)."""
    from marinecdpr.prototype.mujoco_model import SHIP_INERTIA_KG_M2, SHIP_MASS_KG

    Is = SHIP_INERTIA_KG_M2
    perm = [0, 1, 2, 5, 4, 3]  # eta (x, y, z, roll, pitch, yaw) -> joints (x, y, z, yaw, pitch, roll)
    mid = slice(1, 2 * n, 2)
    R_mid = ship_h.R_SO[mid]
    alpha_O = np.einsum("nij,nj->ni", R_mid, ship_h.alpha_SO_S[mid])
    yaw = np.arctan2(R_mid[:, 1, 0], R_mid[:, 0, 0]) if carried else ship_h.eta[mid][:, 5]
    axes = np.stack([np.broadcast_to([0.0, 0.0, 1.0], (n, 3)),
                     np.stack([-np.sin(yaw), np.cos(yaw), np.zeros(n)], axis=1),
                     R_mid[:, :, 0]], axis=1)  # yaw, pitch, roll axes in O
    tau_ff = np.empty((n, 6))
    tau_ff[:, :3] = SHIP_MASS_KG * ship_h.a_SO_O[mid]
    tau_ff[:, 3:] = Is * np.einsum("nja,na->nj", axes, alpha_O)
    wn = 2.0 * np.pi * SHIP_SERVO_HZ
    inertia = np.array([SHIP_MASS_KG] * 3 + [Is] * 3)
    q_des = np.ascontiguousarray(ship_h.eta[0:2 * n:2][:, perm])
    qd_des = np.ascontiguousarray(ship_h.eta_dot[0:2 * n:2][:, perm])
    R_SO = np.ascontiguousarray(ship_h.R_SO[0:2 * n:2])
    return ShipDrive(
        tau_ff=tau_ff, q_des=q_des, qd_des=qd_des, kp=inertia * wn * wn,
        kd=inertia * 2.0 * wn, f_O=np.ascontiguousarray(np.einsum("nij,nj->ni", R_SO, loads.f)),
        m_O=np.ascontiguousarray(np.einsum("nij,nj->ni", R_SO, loads.m)), R_SO=R_SO,
        f_P=loads.f, m_P=loads.m, in_P=bool(loads.in_P))


def _mujoco_plant(scenario: Scenario, model, data, mm, state0, drive: ShipDrive) -> MujocoPlant:
    """MuJoCo's arrays as a record, the ship and the platform put at their initial state."""
    x0, R0, v0, w0 = state0
    ship_dofs = mm.ship_dofs.astype(np.int64)
    data.qpos[ship_dofs] = drive.q_des[0]
    data.qvel[ship_dofs] = drive.qd_des[0]
    planar = scenario.robot.dofs == "planar"
    pq, pd = mm.platform_qpos.astype(np.int64), mm.platform_dofs.astype(np.int64)
    if planar:
        data.qpos[pq] = [x0[0], x0[2], np.arctan2(R0[0, 2], R0[0, 0])]
        data.qvel[pd] = [v0[0], v0[2], w0[1]]
    else:
        data.qpos[pq[:3]] = x0
        data.qpos[pq[3:]] = quaternion_from_matrix(R0)
        data.qvel[pd[:3]] = v0
        data.qvel[pd[3:]] = R0.T @ w0
    return MujocoPlant(qpos=data.qpos, qvel=data.qvel, ctrl=data.ctrl, qfrc=data.qfrc_applied,
                       xfrc=data.xfrc_applied, ten_k=model.tendon_stiffness, ten_spring=model.tendon_lengthspring,
                       ten_c=model.tendon_damping, planar=planar, pq=pq, pd=pd, body=mm.platform_body,
                       ship_dofs=ship_dofs, ship_err=np.zeros(1), x=np.empty(3), R=np.empty((3, 3)), v=np.empty(3),
                       w=np.empty(3), R_PO=np.empty((3, 3)), q=np.empty(4),
                       offset=np.ascontiguousarray(mm.tendon_offset))


def _run_mujoco(scenario: Scenario, run: str, t: np.ndarray, ship_h, state0, asm: Prototype, progress):
    """Fly on MuJoCo: the compiled loop calls mj_step itself where MuJoCo's library can be
    loaded by name, else a Python loop calls the compiled exchange and mj_step. Returns the
    fallbacks, the ship body's largest deviation from its motion and a carried frame's (the
    same: the body moves as C; 0 without a carriage)."""
    import mujoco

    from marinecdpr.prototype.mujoco_model import build_model

    n, h = len(t), scenario.time.step_s
    mm = build_model(scenario)
    model = mm.model
    data = mujoco.MjData(model)
    drive = _ship_drive(ship_h, asm.held, n, carried=scenario.ship.carriage is not None)
    system = asm.wired
    mj = _mujoco_plant(scenario, model, data, mm, state0, drive)
    addresses = (model._address, data._address) if mujoco_library() else None
    law = mujoco_law(asm.system.cable, mj, system.bus)  # the cable part's inputs to MuJoCo
    compiled_loop = bound(mujoco_loop, addresses, h, mj, drive, system, law) if addresses is not None else None
    one_exchange = bound(mujoco_exchange, h, mj, drive, system, law)

    def loop(k0: int, k1: int) -> tuple[int, int]:
        if compiled_loop is not None:
            fb, bad = compiled_loop(k0, k1)
        else:  # the same, one Python call per step
            fb, bad = 0, -1
            for k in range(k0, k1):
                f = one_exchange(k)
                if f < 0:
                    bad = k
                    break
                fb += f
                mujoco.mj_step(model, data)
        if bad < 0 and data.warning[mujoco.mjtWarning.mjWARN_BADQACC].number > 0:
            # MuJoCo met a non-finite or huge acceleration and reset its state: the run is lost
            raise SimulationDivergedError(
                f"{scenario.name}: {run} diverged between t = {t[k0]:.3f} s and {t[k1 - 1]:.3f} s: MuJoCo "
                "met a non-finite or huge acceleration")
        return fb, bad

    fallbacks = _blocks(scenario, run, t, progress, loop, asm)
    ship_error = float(mj.ship_err[0])  # a carried frame's: C's (the ship body moves as C)
    return fallbacks, ship_error, ship_error if scenario.ship.carriage is not None else 0.0
