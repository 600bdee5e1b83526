"""The winches: a first-order lag on the length or tension command (elastic cables), or
the motors' dynamics behind a tension loop (``simulation.cables.winch = "motor"``): on
straight elastic cables (:class:`MotorWinch`, under the tension the cable part computed
over the drum's length), or on sagging ones (:class:`CatenaryMotorWinch`, under each
catenary's tension at the winch end, which the cable part computes too).

Ideal cables apply the command as it is: they have no winch part.

A winch's faults (``[[faults]]`` of kind ``winch_brake``, ``motor_power_loss`` or
``winch_stall``) are a mode of these parts, built only where a scenario lists one:
:class:`BrakedLagWinch` (a length-controlled winch whose brake holds its drum) and
:class:`FaultyMotorWinch` (motor winches whose motor loses its power, the drum running under
the cable's pull, or stalls at its torque limit, and whose brake holds the drum after its
delay).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from marinecdpr.model.catenary import catenary_drum_stiffness
from marinecdpr.model.winch import OVERSPEED, WinchDrive, tension_control_step, winch_motor_step
from marinecdpr.prototype.parts import part, part_step

__all__ = ["LagWinch", "MotorWinch", "CatenaryMotorWinch", "BrakedLagWinch", "FaultyMotorWinch",
           "MOTOR_LOOP_DAMPING", "fault_steps", "stall_steps", "brake_failure_steps", "build"]


@njit(cache=True, inline="always")  # a few lines: inlined into its one caller, part_step
def lag_winch_step(k, h, part, bus):
    for i in range(bus.T_cmd.shape[0]):
        if part.tension_controlled:  # the tension loop on its noisy load cell
            bus.T_hold[i] += part.lag * (bus.T_cmd[i] - bus.cell_noise[i] - bus.T_hold[i])
        else:
            bus.L0[i] += part.lag * (bus.L0_cmd[i] - bus.L0[i])
            bus.L0_drum[i] = bus.L0[i]


@part(step=lag_winch_step, order=30, reads=("T_cmd", "L0_cmd", "cell_noise"), writes=("L0", "L0_drum", "T_hold"))
class LagWinch(NamedTuple):
    """Winches that close ``lag`` = 1 - exp(-h / tau) of their command's error per step:
    length-controlled (state: the bus's L0 they pay out) or tension-controlled (state: the
    bus's T_hold). Elastic cables only."""

    tension_controlled: bool
    lag: float


@njit(cache=True, inline="always")  # inlined into each motor winch's step
def drive_step(k, h, part, bus, T_cmd, T_drum):
    """A motor winch part's tension loop (commanded drum tensions ``T_cmd`` (m,), N, on its
    load cells' ``part.T_meas``) and its motors over the step under the drums' tensions
    ``T_drum`` (m,), N; the steps limited counted; the bus's L0 (the drum's mean over the
    step) and L0_drum (the drum's now) written, and the measurement's motor torques (from the
    drives' currents: the torques that acted) and the drives' demands, the same numbers."""
    drive = part.drive
    tension_control_step(drive, T_cmd, part.T_meas, part.Ldot_ref[k], part.Lddot_ref[k])
    if winch_motor_step(drive, drive.tau, T_drum, h) > 0:
        part.limited[0] += 1
        for i in range(bus.T_cmd.shape[0]):
            if drive.limited[i] == OVERSPEED:
                part.limited[1] += 1
                break
    meas = bus.meas
    for i in range(bus.T_cmd.shape[0]):  # L0 moved by -(r_d / G) h omega over the step
        bus.L0[i] = drive.L0[i] + 0.5 * drive.r[i] / drive.G[i] * h * drive.omega[i]
        bus.L0_drum[i] = drive.L0[i]
        meas.tau[i] = drive.tau[i]  # a sound drive's current is its demand (after its limits)
        meas.tau_set[i] = drive.tau[i]


@njit(cache=True)
def motor_winch_step(k, h, part, bus):
    """The tension loop on each cable's load cell (the tension the cable applies over the
    drum's length now, plus the cell's noise), the motor under that tension over the step;
    the L0 the plant holds over the step is the drum's mean over it (the trapezoid of its
    start and end: second-order in the step)."""
    for i in range(bus.T_cmd.shape[0]):
        part.T_meas[i] = bus.T_app[i] + bus.cell_noise[i]
    drive_step(k, h, part, bus, bus.T_cmd, bus.T_app)


@part(step=motor_winch_step, order=45, reads=("T_cmd", "T_app", "cell_noise"),
      writes=("L0", "L0_drum", "meas.tau", "meas.tau_set"))
class MotorWinch(NamedTuple):
    """The winches' motors: each drum driven through its gearbox by a motor with torque,
    speed and power limits, inertia and friction (:mod:`marinecdpr.model.winch`), its
    tension loop on the load cell with feed-forward of the planned cable motion.

    drive : WinchDrive (state: motor speeds, L0, torques, limit codes). Ldot_ref, Lddot_ref
    (n_steps, m): the plan's L' (m/s) and L'' (m/s^2). T_meas (m,): scratch, the load
    cells' readings, N. limited (2,) int64: the steps with any motor limited, and with any
    past its speed (OVERSPEED).
    """

    drive: WinchDrive
    Ldot_ref: np.ndarray
    Lddot_ref: np.ndarray
    T_meas: np.ndarray
    limited: np.ndarray


@njit(cache=True)
def catenary_motor_winch_step(k, h, part, bus):
    """Motor winches on sagging cables: each drum's load is its catenary's tension at the
    winch end over what the drum has paid out now (``T_winch``: T_A, carrying the cable's
    weight), the cable part's at this exchange. The tension loop reads the drum's load cell
    (T_A and the cell's noise) and holds the drum's tension that the commanded platform
    tension asks for, T_cmd + (T_A - T_B) (T_B = ``T_app``: the catenary's weight and slope
    between its ends at this pose and length): at rest without friction the platform's end
    then carries T_cmd. The L0 the plant holds over the step is the drum's mean over it, as
    :func:`motor_winch_step`'s."""
    for i in range(bus.T_cmd.shape[0]):
        part.T_meas[i] = bus.T_winch[i] + bus.cell_noise[i]
        part.T_drum_cmd[i] = bus.T_cmd[i] + (bus.T_winch[i] - bus.T_app[i])
    drive_step(k, h, part, bus, part.T_drum_cmd, bus.T_winch)


@part(step=catenary_motor_winch_step, order=45, reads=("T_cmd", "T_app", "T_winch", "cell_noise"),
      writes=("L0", "L0_drum", "meas.tau", "meas.tau_set"))
class CatenaryMotorWinch(NamedTuple):
    """Motor winches (:class:`MotorWinch`'s drives, loops and limits) on sagging cables
    (``simulation.cables.model = "catenary"``): each drum turns under its catenary's
    tension at the winch end (:func:`catenary_motor_winch_step`).

    drive, Ldot_ref, Lddot_ref, T_meas, limited: as :class:`MotorWinch`'s; T_drum_cmd (m,):
    the drums' commanded tensions, N (scratch).
    """

    drive: WinchDrive
    Ldot_ref: np.ndarray
    Lddot_ref: np.ndarray
    T_meas: np.ndarray
    limited: np.ndarray
    T_drum_cmd: np.ndarray


# ------------------------------------------------------------------ a winch's faults
NEVER = np.iinfo(np.int64).max


@njit(cache=True, inline="always")
def commanded_brakes(k, part, bus):
    """The controller's brake commands (``bus.brake``): a brake first commanded at exchange k
    holds its drum from k + ``part.delay`` on (``part.k_brake`` moved earlier where a fault's
    brake would hold later); where its primary has failed (k >= ``part.k_fails``), from k +
    ``part.secondary`` (the secondary brake's delay; NEVER: none holds)."""
    for i in range(part.k_brake.shape[0]):
        if bus.brake[i] == 0:
            continue
        d = part.delay if k < part.k_fails[i] else part.secondary[i]
        if d != NEVER and part.k_brake[i] > k + d:
            part.k_brake[i] = k + d


@njit(cache=True)
def braked_lag_step(k, h, part, bus):
    """The winches' own step; a drum whose brake holds (k >= its brake step: a fault's, or
    the controller's command's after the brake's delay) keeps the length it had paid out when
    the brake took hold."""
    part_step(k, h, part.winch, bus)
    commanded_brakes(k, part, bus)
    for i in range(part.k_brake.shape[0]):
        if k >= part.k_brake[i]:
            if not part.held[i]:
                part.held[i] = True
                part.L0_held[i] = part.L0_prev[i]
            bus.L0[i] = part.L0_held[i]
            bus.L0_drum[i] = part.L0_held[i]
        part.L0_prev[i] = bus.L0[i]


@part(step=braked_lag_step, order=30, reads=("T_cmd", "L0_cmd", "cell_noise", "brake"),
      writes=("L0", "L0_drum", "T_hold"))
class BrakedLagWinch(NamedTuple):
    """Length-controlled winches (``winch``, a :class:`LagWinch`) some of whose brakes hold
    their drums. k_brake (m,) int64: the exchange from which each brake holds (NEVER: never;
    a brake the controller commands at k holds from k + delay). held (m,) bool; L0_held (m,):
    the length each held drum keeps, m; L0_prev (m,): each drum's length after the last
    exchange, m; delay : int, the brakes' delay from the controller's command, exchanges;
    k_fails (m,) int64: the exchange from which each primary brake fails (NEVER: never);
    secondary (m,) int64: then the secondary's delay from the command (NEVER: none)."""

    winch: LagWinch
    k_brake: np.ndarray
    held: np.ndarray
    L0_held: np.ndarray
    L0_prev: np.ndarray
    delay: int
    k_fails: np.ndarray
    secondary: np.ndarray


@njit(cache=True)
def faulty_motor_step(k, h, part, bus):
    """The motor winches' own step for the sound ones; a winch whose motor has lost its power
    (k >= k_power) steps again from where it was with no torque (its drive's copy ``free``:
    the drum under the cable's pull against the inertia and friction); one whose motor has
    stalled (k >= k_stall, its power not lost) steps so with its torque limit ``tau_max``
    winding in, whatever its loop commands (the drum reels in until the cable's pull balances
    the limit, and pays out where the pull exceeds it); a drum whose brake
    holds (k >= k_brake: a fault's, or the controller's command's after the brake's delay)
    keeps the length it had paid out when the brake took hold, at rest. The measurement's
    motor torques are the torques that acted (0 without power or braked, the stalled
    motor's), the drives' demands the sound loops' (:func:`drive_step`; 0 where the brake holds:
    the drive is disabled)."""
    drive, free = part.winch.drive, part.free
    m = drive.omega.shape[0]
    for i in range(m):
        free.omega[i] = drive.omega[i]
        free.L0[i] = drive.L0[i]
        stalled = k >= part.k_stall[i] and k < part.k_power[i]
        part.tau_fault[i] = drive.tau_max[i] if stalled else 0.0
    part_step(k, h, part.winch, bus)
    commanded_brakes(k, part, bus)
    T = bus.T_winch if part.heavy else bus.T_app
    any_free = False
    for i in range(m):
        any_free = any_free or ((k >= part.k_power[i] or k >= part.k_stall[i]) and k < part.k_brake[i])
    if any_free:
        winch_motor_step(free, part.tau_fault, T, h)
    for i in range(m):
        if k >= part.k_brake[i]:
            if not part.held[i]:
                part.held[i] = True
                part.L0_held[i] = free.L0[i]  # the drum's length at the step's start
            drive.omega[i] = 0.0
            drive.L0[i] = part.L0_held[i]
            drive.tau[i] = 0.0
            bus.meas.tau_set[i] = 0.0  # a drive whose brake holds is disabled: it asks for nothing
            bus.L0[i] = part.L0_held[i]
            bus.L0_drum[i] = part.L0_held[i]
        elif k >= part.k_power[i] or k >= part.k_stall[i]:
            drive.omega[i] = free.omega[i]
            drive.L0[i] = free.L0[i]
            drive.tau[i] = 0.0 if k >= part.k_power[i] else free.tau[i]
            bus.L0[i] = free.L0[i] + 0.5 * free.r[i] / free.G[i] * h * free.omega[i]
            bus.L0_drum[i] = free.L0[i]
        bus.meas.tau[i] = drive.tau[i]  # the torque that acted; its demand is the sound loop's


@part(step=faulty_motor_step, order=45, reads=("T_cmd", "T_app", "cell_noise", "brake"),
      writes=("L0", "L0_drum", "meas.tau", "meas.tau_set"))  # heavy: T_winch too
class FaultyMotorWinch(NamedTuple):
    """Motor winches (``winch``: a :class:`MotorWinch` or :class:`CatenaryMotorWinch`; ``heavy``
    for the latter, whose drums carry ``T_winch``) some of which lose their motor's power or
    brake, or whose motor stalls. k_power, k_brake, k_stall (m,) int64: the exchange from which
    each motor has no power, each brake holds, and each motor is stalled at its torque limit
    (NEVER: never). free : WinchDrive, a copy of the drive stepped with the faulty motors'
    torques; tau_fault (m,): those torques (0 without power, tau_max stalled), N m (scratch);
    held (m,) bool; L0_held (m,), m; delay : int, the
    brakes' delay from the controller's command (``bus.brake``), exchanges; k_fails, secondary
    (m,) int64: as :class:`BrakedLagWinch`'s."""

    winch: object
    heavy: bool
    k_power: np.ndarray
    k_brake: np.ndarray
    k_stall: np.ndarray
    free: WinchDrive
    tau_fault: np.ndarray
    held: np.ndarray
    L0_held: np.ndarray
    delay: int
    k_fails: np.ndarray
    secondary: np.ndarray


def fault_steps(faults, m: int, h: float) -> tuple[np.ndarray, np.ndarray]:
    """The exchange k from which each of m winches has lost its motor's power, and from which
    its brake holds (the first with t_k = k h >= the time, to 1e-9 of a step: a winch_brake's
    primary after brake_delay_s, or where it fails its secondary after secondary_delay_s),
    from the scenario's ``faults``; NEVER where not. Two (m,) int64 arrays."""
    power, brake = np.full(m, NEVER, dtype=np.int64), np.full(m, NEVER, dtype=np.int64)

    def step(t: float) -> int:
        return int(np.ceil(t / h - 1e-9))

    for f in faults:
        if f.kind == "motor_power_loss":
            power[f.cable - 1] = step(f.at_s)
            if f.brake_delay_s is not None:
                brake[f.cable - 1] = step(f.at_s + f.brake_delay_s)
        elif f.kind == "winch_brake":
            if not f.primary_fails:
                brake[f.cable - 1] = step(f.at_s + (f.brake_delay_s or 0.0))
            elif f.secondary_delay_s is not None:  # the secondary brake, the primary having failed
                brake[f.cable - 1] = step(f.at_s + f.secondary_delay_s)
    return power, brake


def brake_failure_steps(faults, m: int, h: float) -> tuple[np.ndarray, np.ndarray]:
    """From the scenario's ``brake_failure`` faults: the exchange from which each of m winches'
    primary brake fails (the first with t_k = k h >= at_s, to 1e-9 of a step), and the
    secondary's delay from a command in exchanges (rounded up); NEVER where not. Two (m,)
    int64 arrays."""
    fails, secondary = np.full(m, NEVER, dtype=np.int64), np.full(m, NEVER, dtype=np.int64)
    for f in faults:
        if f.kind == "brake_failure":
            fails[f.cable - 1] = int(np.ceil(f.at_s / h - 1e-9))
            if f.secondary_delay_s is not None:
                secondary[f.cable - 1] = int(np.ceil(f.secondary_delay_s / h - 1e-9))
    return fails, secondary


def stall_steps(faults, m: int, h: float) -> np.ndarray:
    """The exchange k from which each of m winches' motor is stalled at its torque limit (the
    first with t_k = k h >= at_s, to 1e-9 of a step) from the scenario's ``winch_stall``
    faults; NEVER where not. (m,) int64."""
    stall = np.full(m, NEVER, dtype=np.int64)
    for f in faults:
        if f.kind == "winch_stall":
            stall[f.cable - 1] = int(np.ceil(f.at_s / h - 1e-9))
    return stall


def with_faults(context, winch):
    """``winch`` (a built part) in its faults' mode where the scenario lists any fault: a
    winch's fault acts on it, and the brakes the controller may command in its reaction
    (``bus.brake``) hold the drums ``[simulation.control.safety] brake_delay_s`` after the
    command. Without a fault, the winch as it is (no brake is ever commanded there but on a
    false alarm, which the watch is shown not to raise)."""
    scenario = context.scenario
    if not scenario.faults:
        return winch
    m = scenario.robot.n_cables
    h = scenario.time.step_s
    power, brake = fault_steps(scenario.faults, m, h)
    delay = int(np.ceil(scenario.simulation.control.safety.brake_delay_s / h - 1e-9))
    fails, secondary = brake_failure_steps(scenario.faults, m, h)
    if isinstance(winch, LagWinch):
        return BrakedLagWinch(winch=winch, k_brake=brake, held=np.zeros(m, dtype=np.bool_), L0_held=np.zeros(m),
                              L0_prev=context.bus.L0.copy(), delay=delay, k_fails=fails, secondary=secondary)
    d = winch.drive
    free = WinchDrive(*(np.array(a, copy=True) for a in d))
    return FaultyMotorWinch(winch=winch, heavy=isinstance(winch, CatenaryMotorWinch), k_power=power, k_brake=brake,
                            k_stall=stall_steps(scenario.faults, m, h), free=free, tau_fault=np.zeros(m), held=np.zeros(m, dtype=np.bool_), L0_held=np.zeros(m),
                            delay=delay, k_fails=fails, secondary=secondary)


MOTOR_LOOP_DAMPING = 0.7
"""The damping ratio of the motor winches' tension loops, on each cable's stiffness at t = 0
(:func:`~marinecdpr.model.winch.tension_loop_damping`, tension gain k_T = 1)."""


def build(context) -> list:
    """The scenario's winches (none for ideal cables): ``context.bus``'s L0, L0_drum and
    T_hold hold their state at t = 0 (paid out so that the plan's first tension stretches
    each cable to its actual length; the tension loops holding the plan's first tensions)."""
    from marinecdpr.model.winch import WinchParams, tension_loop_damping, winch_drive

    scenario, bus = context.scenario, context.bus
    cab, robot = scenario.simulation.cables, scenario.robot
    h = scenario.time.step_s
    if cab.winch == "motor":
        params = WinchParams(**robot.winch.model_dump())
        L0 = bus.L0.copy()
        heavy = cab.model == "catenary"
        if heavy:  # the loop's damping on the sagging cable's stiffness at its first pose
            model, ref = context.model, context.ctl.ref
            d = ref.x[0] + model.p_P @ ref.R[0].T - model.c_C
            v = d @ context.ship_h.R_SO[0, 2, :]
            k = catenary_drum_stiffness(np.sqrt(np.maximum(np.einsum("mi,mi->m", d, d) - v * v, 0.0)), v, L0,
                                        robot.cable_weight_N_m, float(cab.stiffness_EA_N))
            stiffness = np.where(np.isfinite(k) & (k > 0.0), k, float(cab.stiffness_EA_N) / L0)
        else:
            stiffness = float(cab.stiffness_EA_N) / L0
        k_w = tension_loop_damping(params, stiffness, zeta=MOTOR_LOOP_DAMPING, k_T=1.0)
        omega0 = -params.gear_ratio * context.plan.length_rates[0] / params.drum_radius_m
        drive = winch_drive(params, robot.n_cables, L0, omega0=omega0, k_T=1.0, k_w=k_w)
        n = context.n_steps
        common = dict(drive=drive, Ldot_ref=np.ascontiguousarray(context.plan.length_rates[:n], dtype=float),
                      Lddot_ref=np.ascontiguousarray(context.plan.winch.length_accelerations[:n], dtype=float),
                      T_meas=np.zeros(robot.n_cables), limited=np.zeros(2, dtype=np.int64))
        if heavy:
            return [with_faults(context, CatenaryMotorWinch(**common, T_drum_cmd=np.zeros(robot.n_cables)))]
        return [with_faults(context, MotorWinch(**common))]
    if cab.model == "ideal":
        return []
    lag = 1.0 if cab.winch_time_constant_s == 0 else float(-np.expm1(-h / cab.winch_time_constant_s))
    return [with_faults(context, LagWinch(tension_controlled=cab.winch == "tension", lag=lag))]
