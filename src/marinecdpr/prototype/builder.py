"""One builder of the virtual prototype from a scenario: the bus, the active parts in their
declared order, and the cable part whose law the plant applies. The simulation
(:mod:`~marinecdpr.prototype.simulation`) and the rig (:mod:`~marinecdpr.prototype.rig`)
both build through it.

Each part module of :mod:`marinecdpr.prototype.parts` has a ``build(context)`` that returns
its part, a list of parts (none where the scenario has no such part), from the
:class:`Context`; :func:`assemble` calls every module's, sorts the parts by their declared
``order`` and checks the wiring: every signal a part reads is written by the plant or a
part, and no two parts write one signal (unless the later one completes the earlier's,
declared by the same order band: cables and the motor winch).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np

from marinecdpr.control.records import ControllerParts, Loads, RobotModel
from marinecdpr.geometry.elastic import unstretched_length
from marinecdpr.prototype import parts as parts_pkg
from marinecdpr.prototype.parts import PLANT_WRITES, STATE_SIGNALS, Signals, Wired, empty_signals, wire

__all__ = ["Context", "System", "Assembly", "context", "assemble", "WiringError"]


class WiringError(ValueError):
    """The parts' declared signals do not connect (a part reads what nothing writes)."""


@dataclass(frozen=True)
class Context:
    """What a part's ``build`` may read: the scenario and the run, the plans, the ship's motion
    on the half-step grid, the brush's planned loads, the known loads, the controller's
    records and their robot model, and the bus (whose arrays hold the winches' state)."""

    scenario: Any
    run: str
    n_steps: int
    plan: Any  # the plan at t_k (what the run is judged against)
    ff: Any  # the plan at mid-step the controller flies
    ship_h: Any
    brush_h: Any  # BrushLoads on the half-step grid, or None
    loads: Loads
    ctl: ControllerParts
    model: RobotModel
    bus: Signals


class System(NamedTuple):
    """What a plant's compiled loop takes: the bus, the parts (a tuple of records, in the
    exchange's order), the cable part whose law the plant applies within the step, the
    robot's cables (their anchors), and the reference positions (n_steps, 3) a divergence
    is measured from, m."""

    bus: Signals
    parts: tuple
    cable: Any
    model: RobotModel
    ref_x: np.ndarray


@dataclass(frozen=True)
class Assembly:
    """An assembled prototype: the :class:`System`, each part by its record's class name, and
    the parts as the plants' loops take them (:class:`~marinecdpr.prototype.parts.Wired`,
    valid while this lives)."""

    system: System
    by_name: dict
    wired: Wired

    def get(self, name: str):
        """The part whose record class is ``name`` (e.g. ``"MotorWinch"``), or None."""
        return self.by_name.get(name)


def context(scenario, run: str, n: int, *, plan, ff, ship_h, brush_h, loads: Loads, ctl: ControllerParts,
            x0: np.ndarray, R0: np.ndarray) -> Context:
    """The builders' context, its bus holding the state at t = 0: the winches paid out so that
    the plan's first tension (``ff``'s) stretches each cable to its length at (x0, R0) (and,
    for heavy cables, what the sag takes); the tension loops holding the plan's first
    tensions; the applied tensions the plan's first."""
    from marinecdpr.control.step import cables_at

    cab = scenario.simulation.cables
    m = scenario.robot.n_cables
    bus = empty_signals(ctl.meas, ctl.cmd.T_cmd, ctl.cmd.L0_cmd, ctl.ref.T[0], ctl.cmd.brake)
    EA = float(cab.stiffness_EA_N or np.inf)
    L_init = np.empty(m)
    cables_at(x0, R0, ctl.model, L_init, np.empty((m, 6)))
    L0 = unstretched_length(L_init, ff.tensions[0] - cab.damping_N_s_m * ff.length_rates[0], EA)
    if cab.model == "catenary":
        L0 += ff.sag.lengths[0]
    bus.L0[:] = L0
    bus.L0_drum[:] = L0
    bus.T_hold[:] = ff.tensions[0]
    return Context(scenario=scenario, run=run, n_steps=n, plan=plan, ff=ff, ship_h=ship_h, brush_h=brush_h,
                   loads=loads, ctl=ctl, model=ctl.model, bus=bus)


def assemble(ctx: Context, *, include=None, given: tuple[str, ...] = ()) -> Assembly:
    """The scenario's active parts, in order, wired on ``ctx.bus``.

    Parameters
    ----------
    include : callable(module_name) -> bool, optional
        Which part modules to build (default: all).
    given : tuple of str
        Signals the caller writes (a rig's user: the tensions).

    Raises
    ------
    WiringError
        If a part reads a signal that neither the plant nor another part writes.
    """
    built = []
    for module in parts_pkg.part_modules():
        if include is not None and not include(module.__name__.rsplit(".", 1)[1]):
            continue
        out = module.build(ctx)
        built.extend(out if isinstance(out, list) else [out])
    specs = parts_pkg.specs()
    built.sort(key=lambda p: specs[type(p)].order)
    check_wiring([specs[type(p)] for p in built], given=given)
    cables = [p for p in built if specs[type(p)].tensions is not None]
    if not cables:
        from marinecdpr.prototype.parts.cables import HeldTensions
        cables = [HeldTensions(from_winch=False)]
    system = System(bus=ctx.bus, parts=tuple(built), cable=cables[-1], model=ctx.model, ref_x=ctx.ctl.ref.x)
    return Assembly(system=system, by_name={type(p).__name__: p for p in built},
                    wired=wire(system.bus, system.parts, system.cable, system.model, system.ref_x))


def check_wiring(specs: list, *, given: tuple[str, ...] = ()) -> None:
    """Every signal read is written by the plant or by a part (before it within the exchange,
    or after it: then the value is the previous exchange's, a part's state), or is one of
    the signals :func:`context` sets at t = 0 (:data:`~marinecdpr.prototype.parts.STATE_SIGNALS`).

    Raises
    ------
    WiringError
    """
    written = set(PLANT_WRITES) | set(STATE_SIGNALS) | set(given)
    for s in specs:
        written |= set(s.writes)
    for s in specs:
        for signal in s.reads:
            if signal not in written:
                raise WiringError(f"part {s.record.__name__} reads {signal}, which no part writes")
