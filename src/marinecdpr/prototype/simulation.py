"""The virtual prototype: a plan flown on a physics plant, open or closed loop.

Like the paper's co-simulation (its figure 4), the controller and the plant exchange
data once per time step (``time.step_s``, 1 ms): at t_k the controller reads the
plant's state (with sensor noise), commands cable tensions (or a winch's unstretched
length), the cable/actuator model turns the command into applied tensions, and the
plant advances one step with those tensions held. The parts are records with step
functions (:mod:`~marinecdpr.prototype.parts`); this module builds each part's record
from the scenario (one builder per part) and runs a plant's compiled loop
(:mod:`~marinecdpr.prototype.plants`) over blocks of steps.

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
from marinecdpr.control.controller import controller_parts, known_loads, planned_brush_loads, plans, robot_model
from marinecdpr.control.step import cables_at
from marinecdpr.motion.basemotion import evaluate_base_motion
from marinecdpr.prototype import parts as P
from marinecdpr.prototype.plants import (
    MujocoPlant, OwnPlant, ShipDrive, mujoco_exchange, mujoco_library, mujoco_loop, own_loop,
)
from marinecdpr.errors import ScenarioError, SimulationDivergedError
from marinecdpr.geometry.rotations import matrix_from_euler
from marinecdpr.planning.planner import Plan
from marinecdpr.scenario.schema import MRU_UNITS, Scenario

__all__ = ["RUNS", "SimResult", "simulate", "kernels_cached", "KERNEL_COMPILE_S"]

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
        0 for the own plant, which moves the ship exactly).
    winch_limited_steps, winch_overspeed_steps : int
        Motor winches (``simulation.cables.winch = "motor"``): the steps where any motor's
        torque was cut to its torque, power or speed limit, and where any turned past its
        speed limit; 0 for other winches.
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

    @property
    def pose_error(self) -> np.ndarray:
        """Actual minus planned pose, shape (n_steps, 6), m and rad."""
        return self.pose - self.pose_planned


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
    plant = plant or scenario.simulation.plant
    if plant not in ("mujoco", "own"):
        raise ValueError(f"plant must be 'mujoco' or 'own', not {plant!r}")
    if plant == "mujoco" and scenario.simulation.cables.model == "catenary":
        raise ScenarioError("simulation.cables.model: catenary cables need the own plant (--plant own): "
                            "MuJoCo's tendons are straight", source=scenario.name)
    h = scenario.time.step_s
    n = scenario.time.n_steps if n_steps is None else min(n_steps, scenario.time.n_steps)
    check_run_size(scenario, "simulate", n_steps=n)  # before any array of n steps
    t = np.arange(n) * h
    # the ship's motion and the loads on the half-step grid: j = 2k is t_k, j = 2k + 1 is t_k + h/2
    ship_h = evaluate_base_motion(scenario.base_motion, np.arange(2 * n + 1) * (0.5 * h))
    base_model = "fixed" if run == "fixed_base_open_loop" else "moving"
    ref, ff, _ = plans(scenario, n, reference=reference, base_model=base_model, ship_h=ship_h)
    brush_h = planned_brush_loads(scenario, ref, ff, n)
    f_h, m_h, in_P = known_loads(scenario, ship_h, brush_h)
    m = scenario.robot.n_cables
    x0, R0, v0, w0 = _initial_state(scenario, ref)
    loads = P.Loads(np.ascontiguousarray(f_h[::2][:n]), np.ascontiguousarray(m_h[::2][:n]), in_P)
    ctl = controller_parts(scenario, ff, loads, closed=run == "closed_loop")
    sensors, mru, encoders, load_cells = _sensors(scenario, run, ship_h, n)
    load_cells.T[:] = ctl.ref.T[0]
    winch = _winch(scenario, ff, x0, R0)
    parts = P.Parts(
        ctl=ctl, sensors=sensors, mru=mru, encoders=encoders, load_cells=load_cells, loads=loads,
        winch=winch, cables=_cables(scenario), bus=P.empty_bus(ctl), log=P.empty_log(n, m),
        brush=_brush(scenario, ref, n, brush_h), motor=_motor(scenario, ref, winch, n),
        catenary=_catenary(scenario, ship_h, m))
    if plant == "own":
        y = np.concatenate([x0, _quat_from_R(R0), v0, w0])
        own = OwnPlant(y, *(np.ascontiguousarray(a) for a in (ship_h.R_SO, ship_h.omega_SO_S, ship_h.alpha_SO_S,
                                                              ship_h.a_SO_O, f_h, m_h)))
        fallbacks = _blocks(scenario, run, t, progress, lambda k0, k1: own_loop(k0, k1, h, own, parts))
        ship_error = 0.0  # the own plant moves the ship exactly
    else:
        fallbacks, ship_error = _run_mujoco(scenario, run, t, ship_h, (x0, R0, v0, w0), parts, progress)
    log = parts.log
    log.pose[:, 3:] = np.unwrap(log.pose[:, 3:], axis=0)
    return SimResult(
        run=run, plant=plant, t=t, pose_planned=np.ascontiguousarray(ref.pose[:n]), pose=log.pose,
        lengths_planned=np.ascontiguousarray(ref.lengths[:n]), lengths=log.lengths,
        tensions_commanded=log.T_cmd, tensions=log.T_app, controller_fallbacks=int(fallbacks),
        ship_tracking_error=ship_error, winch_limited_steps=int(parts.motor.limited[0]),
        winch_overspeed_steps=int(parts.motor.limited[1]),
    )


# ------------------------------------------------------- the parts, from the scenario
def _brush(scenario: Scenario, ref: Plan, n: int, brush_h) -> P.BrushContact:
    """The cleaning brush's contact part: its planned loads at t_k (``brush_h``'s every other
    row, what the controller's load model holds) and the normal force (:func:`normal_force`);
    inactive without ``[cleaning]``."""
    from marinecdpr.model.brush import brush_params, cleaning_brush

    cleaning = scenario.cleaning
    if cleaning is None:
        return P.BrushContact(False, brush_params(0.0, 0.0), np.zeros(3), np.zeros(1), np.zeros((1, 3)),
                              np.zeros((1, 3)), np.zeros(3), np.zeros(3), np.zeros(3))
    f_b, m_b, _ = brush_h
    return P.BrushContact(True, cleaning_brush(cleaning), np.asarray(cleaning.hull_normal, dtype=float),
                          np.ascontiguousarray(normal_force(ref, scenario)[:n]), np.ascontiguousarray(f_b[::2][:n]),
                          np.ascontiguousarray(m_b[::2][:n]), np.zeros(3), np.zeros(3), np.zeros(3))


def normal_force(p: Plan, scenario: Scenario) -> np.ndarray:
    """The brush's contact force over the plan's steps, (n_steps,), N: on a planar robot the
    plan's guide reaction along the hull normal plus twice the preload (the pusher presses
    with the preload; the planned loads include the hull's push at the preload); on a
    robot whose cables control the normal, the preload."""
    cleaning = scenario.cleaning
    P_n = cleaning.preload
    n = np.asarray(cleaning.hull_normal, dtype=float)
    if "y" not in p.reaction_dofs or abs(n[1]) < 1.0 - 1e-9:
        return np.full(p.n_steps, P_n)
    return p.reaction[:, p.reaction_dofs.index("y")] * n[1] + 2.0 * P_n


def _sensors(scenario: Scenario, run: str, ship_h, n: int) -> tuple[P.Sensors, P.Mru, P.Encoders, P.LoadCells]:
    """The sensors' parts, their errors drawn from ``[simulation.noise]`` (seeded): the closed
    loop measures the platform (pose sensor or encoders) and the ship (the motion reference
    unit, ``[simulation.mru]``); the load cells measure the tensions (open and closed loop)."""
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
        ship_s = evaluate_base_motion(scenario.base_motion, t_s)
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
    return (P.Sensors(pose, twist, np.zeros(3), np.zeros((2, 3, 3))),
            P.Mru(np.ascontiguousarray(eta), np.ascontiguousarray(t_s, dtype=float), np.ascontiguousarray(latest)),
            P.Encoders(float(sens.encoder_resolution_m)), P.LoadCells(noise, alpha, np.zeros(scenario.robot.n_cables)))


def _cables(scenario: Scenario) -> P.Cables:
    cab = scenario.simulation.cables
    return P.Cables(cab.model != "ideal", float(cab.stiffness_EA_N or np.inf), cab.damping_N_s_m)


def _catenary(scenario: Scenario, ship_h, m: int) -> P.Catenary:
    """Heavy cables (``simulation.cables.model = "catenary"``; else inactive): the true
    vertical in C on the half-step grid, O's z in S (row 2 of R_SO)."""
    cab = scenario.simulation.cables
    if cab.model != "catenary":
        return P.no_catenary(m)
    return P.catenary_part(m, scenario.robot.cable_weight_N_m, cab.stiffness_EA_N, ship_h.R_SO[:, 2, :])


def _winch(scenario: Scenario, ff: Plan, x0: np.ndarray, R0: np.ndarray) -> P.Winch:
    """The winches at t = 0: paid out so that the plan's first tension stretches the cable to
    its actual length, the tension loops holding the plan's first tensions."""
    cab, robot = scenario.simulation.cables, scenario.robot
    h = scenario.time.step_s
    lag = 1.0 if cab.winch_time_constant_s == 0 else float(-np.expm1(-h / cab.winch_time_constant_s))
    EA = float(cab.stiffness_EA_N or np.inf)
    L_init = np.empty(robot.n_cables)
    cables_at(x0, R0, robot_model(scenario), L_init, np.empty((robot.n_cables, 6)))
    L0 = L_init / (1.0 + (ff.tensions[0] - cab.damping_N_s_m * ff.length_rates[0]) / EA)
    if cab.model == "catenary":  # and what the sag takes
        L0 += ff.sag_lengths[0]
    return P.Winch(cab.winch == "tension", lag, L0, np.array(ff.tensions[0], dtype=float))


MOTOR_LOOP_DAMPING = 0.7
"""The damping ratio of the motor winches' tension loops, on each cable's stiffness at t = 0
(:func:`~marinecdpr.model.winch.tension_loop_damping`, tension gain k_T = 1)."""


def _motor(scenario: Scenario, ref: Plan, winch: P.Winch, n: int) -> P.Motor:
    """The motor winches at t = 0 (``simulation.cables.winch = "motor"``; else inactive): the
    drums paid out as the winch record, the motors turning with the plan's first L'."""
    from marinecdpr.model.winch import WinchParams, tension_loop_damping, winch_drive

    cab, robot = scenario.simulation.cables, scenario.robot
    m = robot.n_cables
    if cab.winch != "motor":
        return P.no_motor(m)
    params = WinchParams(**robot.winch.model_dump())
    k_w = tension_loop_damping(params, float(cab.stiffness_EA_N) / winch.L0, zeta=MOTOR_LOOP_DAMPING, k_T=1.0)
    omega0 = -params.gear_ratio * ref.length_rates[0] / params.drum_radius_m
    drive = winch_drive(params, m, winch.L0.copy(), omega0=omega0, k_T=1.0, k_w=k_w)
    return P.motor_part(drive, ref.length_rates[:n], ref.length_accelerations[:n])


def _initial_state(scenario: Scenario, ref: Plan):
    """The platform at t = 0: on the plan, plus the scenario's initial error: x, R, v, w in C."""
    sim = scenario.simulation
    x0 = ref.pose[0, :3] + np.asarray(sim.initial_error_m)
    R0 = matrix_from_euler(np.radians(sim.initial_error_deg)) @ matrix_from_euler(ref.pose[0, 3:])
    return x0, R0, ref.twist[0, :3].copy(), ref.twist[0, 3:].copy()


def _blocks(scenario: Scenario, run: str, t: np.ndarray, progress, loop, block: int = 500) -> int:
    """Run ``loop(k0, k1)`` over blocks of steps; the fallbacks. Raises on divergence."""
    n = len(t)
    fallbacks = 0
    for k0 in range(0, n, block):
        k1 = min(n, k0 + block)
        fb, bad = loop(k0, k1)
        fallbacks += fb
        if bad >= 0:
            raise SimulationDivergedError(_diverged_message(scenario, run, t[bad]))
        if progress is not None:
            progress(k1, n)
    return fallbacks


KERNEL_COMPILE_S = 75.0
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


def _diverged_message(scenario: Scenario, run: str, t: float) -> str:
    return (f"{scenario.name}: {run} diverged at t = {t:.3f} s: the platform is more than "
            f"{P.DIVERGENCE_M:g} m from its plan or its state is not finite")


# ----------------------------------------------------------------------- MuJoCo plant
def _ship_drive(ship_h, loads: P.Loads, n: int) -> ShipDrive:
    """Feed-forward forces that move the (gravity-compensated, isotropic) MuJoCo ship along
    eta, evaluated at mid-step; a servo acts on the error at the step's start. Loads in C
    are applied in O (a load given in P is turned at each exchange)."""
    from marinecdpr.prototype.mujoco_model import SHIP_INERTIA_KG_M2, SHIP_MASS_KG

    perm = [0, 1, 2, 5, 4, 3]  # eta (x, y, z, roll, pitch, yaw) -> joints (x, y, z, yaw, pitch, roll)
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
    wn = 2.0 * np.pi * SHIP_SERVO_HZ
    inertia = np.array([SHIP_MASS_KG] * 3 + [SHIP_INERTIA_KG_M2] * 3)
    R_SO = np.ascontiguousarray(ship_h.R_SO[0:2 * n:2])
    return ShipDrive(
        tau_ff, np.ascontiguousarray(ship_h.eta[0:2 * n:2][:, perm]),
        np.ascontiguousarray(ship_h.eta_dot[0:2 * n:2][:, perm]), inertia * wn * wn, inertia * 2.0 * wn,
        np.ascontiguousarray(np.einsum("nij,nj->ni", R_SO, loads.f)),
        np.ascontiguousarray(np.einsum("nij,nj->ni", R_SO, loads.m)), R_SO)


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
        data.qpos[pq[3:]] = _quat_from_R(R0)
        data.qvel[pd[:3]] = v0
        data.qvel[pd[3:]] = R0.T @ w0
    return MujocoPlant(data.qpos, data.qvel, data.ctrl, data.qfrc_applied, data.xfrc_applied,
                       model.tendon_stiffness, model.tendon_lengthspring, model.tendon_damping, planar,
                       pq, pd, mm.platform_body, ship_dofs, np.zeros(1), np.empty(3), np.empty((3, 3)), np.empty(3),
                       np.empty(3), np.empty((3, 3)), np.ascontiguousarray(mm.tendon_offset))


def _run_mujoco(scenario: Scenario, run: str, t: np.ndarray, ship_h, state0, parts: P.Parts, progress):
    """Fly on MuJoCo: the compiled loop calls mj_step itself where MuJoCo's library can be
    loaded by name, else a Python loop calls the compiled exchange and mj_step. Returns the
    fallbacks and the ship's largest deviation from its motion."""
    import mujoco

    from marinecdpr.prototype.mujoco_model import build_model

    n, h = len(t), scenario.time.step_s
    mm = build_model(scenario)
    model = mm.model
    data = mujoco.MjData(model)
    drive = _ship_drive(ship_h, parts.loads, n)
    mj = _mujoco_plant(scenario, model, data, mm, state0, drive)
    addresses = (model._address, data._address) if mujoco_library() else None

    def loop(k0: int, k1: int) -> tuple[int, int]:
        if addresses is not None:
            fb, bad = mujoco_loop(k0, k1, addresses, h, mj, drive, parts)
        else:  # the same, one Python call per step
            fb, bad = 0, -1
            for k in range(k0, k1):
                f = mujoco_exchange(k, h, mj, drive, parts)
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

    fallbacks = _blocks(scenario, run, t, progress, loop)
    return fallbacks, float(mj.ship_err[0])
