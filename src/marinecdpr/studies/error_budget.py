"""How much each effect of cables as built changes the plan against the ideal point model
(issue 14's error budget): pulleys, the cables' stretch, their sag, and the winches' limits.

Each effect is measured on the scenario's plan, as the scenario describes the robot: an
effect the scenario does not describe (no pulleys, ideal cables, no cable weight, no
winch) is reported as not evaluated, with the key that would describe it.

- pulleys: the plan over the pulleys against the same plan from point anchors: the
  largest change of a cable's length and of its tension;
- stretch: the elastic cables' stretch T L / EA along the plan (a length-controlled winch
  pays out that much less than the geometry);
- sag: each cable an elastic catenary (``robot.cable_weight_N_m``) carrying the plan's
  tension at the platform, in the true vertical (the ship's attitude), as the planner
  computes it (:attr:`~marinecdpr.planning.planner.CableSag.lengths`): the extra unstretched
  length the winch pays out against a straight cable, and the tension at the winch
  against the platform's;
- winch limits: the plan keeps each tension within the range its winch can give at that
  step (torque, speed, power, inertia, friction: ``marinecdpr.model.winch``); against the
  same plan without the winches' limits, the largest change of a tension, the steps the
  winches cannot follow, and each winch's peak torque, speed, power and energy over the
  plan's feasible steps.

The reachable workspace: a workspace map (:func:`~marinecdpr.studies.workspace.workspace_map`,
held poses over the frame under the scenario's ship motion) of the point model, and one
with each effect that changes which tensions hold a pose (pulleys: the cables' directions;
the winches' limits: the tensions they can give). Each effect's change is the difference
of the share of the map where the platform is held at every step. Stretch and sag do not
change it (they change the lengths a winch pays out, not the tensions that hold a pose):
0.
"""

from __future__ import annotations

from typing import Any, Callable, NamedTuple

from dataclasses import dataclass, replace

import numpy as np

from marinecdpr.model.winch import WinchParams, winch_report
from marinecdpr.planning.planner import Plan, plan
from marinecdpr.scenario.schema import Scenario

__all__ = ["Effect", "error_budget", "budget_summary"]


@dataclass(frozen=True)
class Effect:
    """One effect's change of the plan, largest over the steps and cables.

    ``None`` figures: the scenario does not describe the effect (``note`` says how to).
    """

    name: str
    length_change_m: float | None
    tension_change_N: float | None
    note: str
    workspace_change: float | None = None
    """The change of the share of the workspace map held at every step (e.g. -0.03: 3 % of
    the map lost); None if not evaluated."""


WORKSPACE_GRID = (16, 10)
"""The workspace maps' grid of held poses."""


def _point_robot(scenario: Scenario, *, pulleys: bool = False, winch: bool = False) -> Scenario:
    """The scenario's robot with point anchors and no winch, keeping the pulleys or the winch
    if asked."""
    robot = scenario.robot
    if not winch and scenario.simulation.cables.winch == "motor":  # without a motor: an ideal tension loop
        scenario = scenario.with_updates("simulation.cables", winch="tension")
    if not winch:
        scenario = scenario.with_updates("robot", winch=None)
    if not pulleys:
        scenario = scenario.with_updates("robot", cables=[
            c.model_copy(update={"pulley_radius_m": 0.0, "pulley_axis": None}).model_dump(exclude_none=True)
            for c in robot.cables])
    return scenario


def _held_share(scenario: Scenario, grid: tuple[int, int], progress=None) -> float:
    """The share of the workspace map (over the cells where the platform fits) where every
    step of the ship's motion has tensions within limits; ``progress(done, total)`` per pose."""
    from marinecdpr.studies.workspace import workspace_map

    f = workspace_map(scenario, n=grid, progress=progress).fraction_feasible
    return float(np.mean(f[np.isfinite(f)] == 1.0))


def _pulleys(scenario: Scenario, p: Plan) -> Effect:
    robot = scenario.robot
    if not robot.has_pulleys:
        return Effect(name="pulleys", length_change_m=None, tension_change_N=None,
                      note="no pulleys (robot.cables[].pulley_radius_m)")
    point = plan(_point_robot(scenario, winch=True))
    dL = float(np.nanmax(np.abs(p.lengths - point.lengths)))
    dT = float(np.nanmax(np.abs(p.tensions - point.tensions)))
    return Effect(name="pulleys", length_change_m=dL, tension_change_N=dT,
                  note=f"largest radius {robot.pulley_radii.max() * 1e3:.3g} mm")


def _stretch(scenario: Scenario, p: Plan) -> Effect:
    cab = scenario.simulation.cables
    if cab.model == "ideal":
        return Effect(name="stretch", length_change_m=None, tension_change_N=None,
                      note="ideal cables (simulation.cables.model = \"elastic\" with EA)")
    stretch = p.tensions * p.lengths / (cab.stiffness_EA_N + p.tensions)  # L - L0 with T = EA (L - L0) / L0
    return Effect(name="stretch", length_change_m=float(np.nanmax(stretch)), tension_change_N=0.0,
                  note=f"EA {cab.stiffness_EA_N:.4g} N")


def _sag(scenario: Scenario, p: Plan) -> Effect:
    w = scenario.robot.cable_weight_N_m
    if w == 0.0 or p.sag is None:
        return Effect(name="sag", length_change_m=None, tension_change_N=None,
                      note="weightless cables (robot.cable_weight_N_m)")
    ok = np.isfinite(p.sag.lengths)
    if not ok.any():
        return Effect(name="sag", length_change_m=float("nan"), tension_change_N=float("nan"),
                      note=f"{w:g} N/m; no step solved")
    dL = float(np.max(np.abs(p.sag.lengths[ok])))
    dT = float(np.max(np.abs(p.sag.winch_tensions[ok] - p.tensions[ok])))
    note = f"{w:g} N/m"
    unsolved = int((~ok & np.isfinite(p.tensions)).sum())
    if unsolved:
        note += f"; {unsolved} cable-steps slack or unsolved"
    return Effect(name="sag", length_change_m=dL, tension_change_N=dT, note=note)


def _winches(scenario: Scenario, p: Plan):
    robot = scenario.robot
    if robot.winch is None or p.winch is None:
        return Effect(name="winch limits", length_change_m=None, tension_change_N=None,
                      note="no winch described (robot.winch)"), None
    params = WinchParams(**robot.winch.model_dump())
    free = plan(_point_robot(scenario, pulleys=True), method=p.method, base_model=p.base_model)
    both = p.feasible & free.feasible
    dT = float(np.max(np.abs(p.tensions[both] - free.tensions[both]), initial=0.0))
    lost = int((free.feasible & ~p.feasible).sum())
    ok = p.feasible
    report = winch_report(p.tensions[ok], p.length_rates[ok], p.winch.length_accelerations[ok], scenario.time.step_s,
                          params)
    asks = winch_report(free.tensions[free.feasible], free.length_rates[free.feasible],
                        p.winch.length_accelerations[free.feasible], scenario.time.step_s, params)
    if lost:
        note = (f"{lost} of {p.n_steps} steps lost to the winches' limits (no tensions within what "
                f"each can give at that motion); without those limits the plan asks up to "
                f"{asks.peak_torque_Nm.max():.3g} N m, {asks.peak_speed_rad_s.max():.3g} rad/s, "
                f"{asks.peak_power_W.max():.3g} W")
    elif dT > 0.0:
        note = "the winches' limits bind: the plan keeps within what each can give"
    else:
        note = "every step within the winches' torque, speed and power"
    return Effect(name="winch limits", length_change_m=None, tension_change_N=dT, note=note), report


class ErrorBudget(NamedTuple):
    """:func:`error_budget`'s result: the effects (a tuple of :class:`Effect`), the winches'
    :class:`~marinecdpr.model.winch.WinchReport` (None without ``robot.winch``), and the share
    of the point model's workspace map held at every step (None if no map was made)."""

    effects: tuple
    report: Any
    held_share: float | None


def error_budget(scenario: Scenario, p: Plan | None = None, *, workspace_grid: tuple[int, int] | None = WORKSPACE_GRID,
                 progress: Callable[[int, int], None] | None = None) -> ErrorBudget:
    """The effects of pulleys, stretch, sag and winch limits on the scenario's plan.

    Parameters
    ----------
    scenario : Scenario
    p : Plan, optional
        ``plan(scenario)`` if already computed.
    workspace_grid : (int, int) or None
        The workspace maps' grid (None: no workspace change); maps are made only for a
        scenario that describes pulleys or winches.
    progress : callable(done, total), optional
        Called as the maps' poses are planned (all maps' poses on one count): tens of
        seconds for paper_as_built's three 16 x 10 maps.

    Returns
    -------
    ErrorBudget
    """
    p = plan(scenario) if p is None else p
    winch, report = _winches(scenario, p)
    effects = [_pulleys(scenario, p), _stretch(scenario, p), _sag(scenario, p), winch]
    robot = scenario.robot
    base = None
    if workspace_grid is not None and (robot.has_pulleys or robot.winch is not None):
        mapped = [i for i, e in enumerate(effects) if e.tension_change_N is not None and e.name not in ("stretch", "sag")]
        poses = workspace_grid[0] * workspace_grid[1]
        total = poses * (1 + len(mapped))

        def share(sc: Scenario, k: int) -> float:  # the k-th map of 1 + len(mapped), on one count
            cb = None if progress is None else (lambda done, _n: progress(k * poses + done, total))
            return _held_share(sc, workspace_grid, cb)

        base = share(_point_robot(scenario), 0)
        for i, e in enumerate(effects):
            if e.tension_change_N is None:
                continue
            if e.name in ("stretch", "sag"):
                change = 0.0
            else:
                kept = dict(pulleys=e.name == "pulleys", winch=e.name == "winch limits")
                change = share(_point_robot(scenario, **kept), 1 + mapped.index(i)) - base
            effects[i] = replace(e, workspace_change=change)
    return ErrorBudget(effects=tuple(effects), report=report, held_share=base)


def budget_summary(effects, report, held_share=None) -> dict:
    """``summary.json``'s ``error_budget`` (and ``winches`` with a winch report), with
    ``error_budget_workspace_held_share_point`` (the point model's share of the workspace map
    held at every step) where maps were made."""
    out = {"error_budget": {e.name: {"length_change_m": e.length_change_m, "tension_change_N": e.tension_change_N,
                                     "workspace_change": e.workspace_change, "note": e.note} for e in effects}}
    if held_share is not None:
        out["error_budget_workspace_held_share_point"] = held_share
    if report is not None:
        out["winches"] = {"peak_torque_Nm": report.peak_torque_Nm.tolist(),
                          "peak_speed_rad_s": report.peak_speed_rad_s.tolist(),
                          "peak_power_W": report.peak_power_W.tolist(),
                          "energy_positive_J": report.energy_positive_J.tolist(),
                          "within_limits": report.within_limits.tolist()}
    return out
