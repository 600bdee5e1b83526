"""Figures of merit of simulated runs, beside the paper's reported ones."""

from __future__ import annotations

import numpy as np

from dataclasses import dataclass
from typing import Callable

from marinecdpr import forked
from marinecdpr.planning.planner import Plan, plan
from marinecdpr.prototype.simulation import RUNS, SimResult, simulate
from marinecdpr.prototype.warmup import compile_apart
from marinecdpr.scenario.schema import Scenario
from marinecdpr.studies.error_budget import budget_summary, error_budget
from marinecdpr.studies.stability import plan_stability, stability_summary

__all__ = ["PAPER_REPORTED", "VirtualPrototype", "virtual_prototype", "run_summary", "summary",
           "is_paper_scenario", "error_bounds", "run_warnings", "controller_verdict", "bypassed_text"]

PAPER_REPORTED = {
    "max_abs_error_x_m": 0.025,
    "max_abs_error_z_m": 0.013,
    "max_abs_error_theta_deg": 0.48,
    "max_abs_cable_length_error_m": 0.15,
}
"""The paper's section 4.2: Adams open loop, largest errors (cable length: cable 2)."""

DEFAULT_ERROR_BOUND_FRACTION = 0.01
"""Default bound on a run's position error: this fraction of the frame's largest extent."""

_NAMES = ("x", "y", "z", "rx", "ry", "rz")
_PAPER_SECTIONS = ("robot", "ship", "base_motion", "trajectory", "disturbance", "environment")


def is_paper_scenario(scenario: Scenario) -> bool:
    """True if the scenario is the paper's experiment: its robot, ship and ship motion,
    trajectory, disturbance and gravity (cables, sensors and controller may differ).

    Only then are the paper's reported errors a fair comparison.
    """
    from marinecdpr.scenario.loading import load_scenario

    paper = load_scenario("paper")
    return all(getattr(scenario, k).model_dump() == getattr(paper, k).model_dump() for k in _PAPER_SECTIONS)


def error_bounds(scenario: Scenario, max_error_m: float | None = None) -> tuple[float, float]:
    """The bounds beyond which a run is flagged: (position and cable length, m; angle, deg).

    ``max_error_m`` overrides ``simulation.max_error_m``, whose default is
    :data:`DEFAULT_ERROR_BOUND_FRACTION` of the frame's largest extent.
    """
    pos = max_error_m if max_error_m is not None else scenario.simulation.max_error_m
    if pos is None:
        c = scenario.robot.frame_anchors
        pos = DEFAULT_ERROR_BOUND_FRACTION * float((c.max(axis=0) - c.min(axis=0)).max())
    return float(pos), float(scenario.simulation.max_error_deg)


def _rotation_error_deg(res: SimResult) -> np.ndarray:
    """Angle of R_planned^T R_actual at each step, deg."""
    from marinecdpr.geometry.rotations import matrix_from_euler

    Rp = matrix_from_euler(res.pose_planned[:, 3:])
    Ra = matrix_from_euler(res.pose[:, 3:])
    cos = (np.einsum("nij,nij->n", Rp, Ra) - 1.0) / 2.0
    return np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))


def run_summary(res: SimResult, scenario: Scenario, *, max_error_m: float | None = None) -> dict:
    """The figures of one run.

    Keys: ``max_abs_error_x_m``, ``max_abs_error_z_m``, ``max_abs_error_theta_deg``
    (theta_y for a planar robot; the rotation angle between planned and actual
    orientation for a spatial one, which also gets ``y``, ``rx``, ``ry``, ``rz``),
    ``max_abs_cable_length_error_m`` (one per cable), ``tension_min_N``,
    ``tension_max_N`` (applied), ``tension_limit_excess_N`` (how far applied tensions left
    their limits beyond the tension tolerance, 0 if never), ``rms_error_x_m``,
    ``rms_error_z_m``, ``controller_fallbacks``, for the closed loop its
    :func:`controller_verdict` (``controller_bypassed_share``, ``controller_verdict``), with
    motor winches ``winch_limited_steps``
    and ``winch_overspeed_steps``, ``ship_tracking_error`` (m or rad),
    ``plant``, ``within_error_bound`` (False if a position or cable-length error passed
    :func:`error_bounds`' first value or the angle error its second) and
    ``beyond_error_bound`` (the quantities that did, e.g. ``["x", "rz", "cable 3"]``).
    """
    err = res.pose_error
    out: dict = {}
    for i in (0, 2):
        out[f"max_abs_error_{_NAMES[i]}_m"] = float(np.abs(err[:, i]).max())
    if scenario.robot.dofs == "planar":
        out["max_abs_error_theta_deg"] = float(np.degrees(np.abs(err[:, 4]).max()))
    else:
        out["max_abs_error_theta_deg"] = float(_rotation_error_deg(res).max())
        out["max_abs_error_y_m"] = float(np.abs(err[:, 1]).max())
        for i in (3, 4, 5):
            out[f"max_abs_error_{_NAMES[i]}_deg"] = float(np.degrees(np.abs(err[:, i]).max()))
    out["max_abs_cable_length_error_m"] = [
        float(v) for v in np.abs(res.lengths - res.lengths_planned).max(axis=0)]
    out["tension_min_N"] = float(res.tensions.min())
    out["tension_max_N"] = float(res.tensions.max())
    lo, hi = scenario.robot.tension_min, scenario.robot.tension_max
    # by how much the applied tensions left their limits (elastic dynamics, lag, noise)
    excess = float(max(0.0, (lo - res.tensions).max(), (res.tensions - hi).max()))
    out["tension_limit_excess_N"] = excess if excess > _tension_tolerance(hi) else 0.0
    out["rms_error_x_m"] = float(np.sqrt(np.mean(err[:, 0] ** 2)))
    out["rms_error_z_m"] = float(np.sqrt(np.mean(err[:, 2] ** 2)))
    out["controller_fallbacks"] = res.controller_fallbacks
    out.update(controller_verdict(res, scenario))
    if scenario.simulation.cables.winch == "motor":
        out["winch_limited_steps"] = res.winch_limited_steps
        out["winch_overspeed_steps"] = res.winch_overspeed_steps
    out["ship_tracking_error"] = res.ship_tracking_error
    out["plant"] = res.plant
    bound_m, bound_deg = error_bounds(scenario, max_error_m)
    beyond = [name for name in ("x", "y", "z") if out.get(f"max_abs_error_{name}_m", 0.0) > bound_m]
    if scenario.robot.dofs == "planar":
        beyond += ["theta_y"] if out["max_abs_error_theta_deg"] > bound_deg else []
    else:
        beyond += [name for name in ("rx", "ry", "rz") if out[f"max_abs_error_{name}_deg"] > bound_deg]
    beyond += [f"cable {i + 1}" for i, v in enumerate(out["max_abs_cable_length_error_m"]) if v > bound_m]
    out["within_error_bound"] = not beyond
    out["beyond_error_bound"] = beyond
    return out


def _tension_tolerance(hi: np.ndarray) -> float:
    from marinecdpr.model.tension import TENSION_TOLERANCE

    return TENSION_TOLERANCE * max(1.0, float(np.max(np.abs(hi))))


def summary(plan: Plan, results: dict[str, SimResult], scenario: Scenario, *,
            max_error_m: float | None = None, progress: Callable[[int, int], None] | None = None) -> dict:
    """``summary.json``: each run's figures, the plan's tension range, the error bounds, the
    open loop's stability along the plan (``open_loop_growth_rate_1_s`` and ``stability``:
    :mod:`~marinecdpr.studies.stability`), the cables-as-built error budget
    (``error_budget``, ``winches``: :mod:`~marinecdpr.studies.error_budget`), the closed loops
    whose controller was bypassed (``runs_controller_bypassed``, beyond
    ``controller_bypassed_share_max``: :func:`controller_verdict`), and (for the paper's
    experiment only, see :func:`is_paper_scenario`) the paper's errors."""
    bound_m, bound_deg = error_bounds(scenario, max_error_m)
    out: dict = {
        "scenario": scenario.name,
        "steps": int(plan.n_steps),
        "step_s": scenario.time.step_s,
        "method": plan.method,
        "pinv_tension_min_N": float(np.nanmin(plan.tensions_pinv)),
        "opt_tension_min_N": float(np.nanmin(plan.tensions)),
        "opt_tension_max_N": float(np.nanmax(plan.tensions)),
        "error_bound_m": bound_m,
        "error_bound_deg": bound_deg,
        "controller_bypassed_share_max": scenario.simulation.max_bypassed_share,
    }
    g = plan_stability(plan, scenario)
    out["open_loop_growth_rate_1_s"] = g.rate
    out["stability"] = stability_summary(g)
    out.update(budget_summary(*error_budget(scenario, plan, progress=progress)))
    if is_paper_scenario(scenario):
        out["paper_reported"] = PAPER_REPORTED
    for name, res in results.items():
        out[name] = run_summary(res, scenario, max_error_m=max_error_m)
    out["runs_beyond_error_bound"] = [name for name in results if not out[name]["within_error_bound"]]
    out["runs_controller_bypassed"] = [name for name in results
                                       if out[name].get("controller_verdict") == "bypassed"]
    out["warnings"] = run_warnings(results, scenario)
    close = plan.interference_summary()
    if close is not None:
        out["interference"] = close
        if close["first"] is not None:
            out["warnings"].append(f"plan: {close['first']}")
    return out


def controller_verdict(res: SimResult, scenario: Scenario) -> dict:
    """Whether a closed loop ran closed: its controller is bypassed at a step whose feedback
    asks for tensions outside the limits (the plan's are fed forward instead,
    ``res.controller_fallbacks``); on more than ``[simulation] max_bypassed_share`` of its
    steps the run shows the plan, not the controller, and is a failed run.

    Returns ``{"controller_bypassed_share": fallbacks / steps (0 to 1),
    "controller_verdict": "held" or "bypassed"}``; empty for a run without a controller
    (the open loops).
    """
    if res.run != "closed_loop":
        return {}
    share = res.controller_fallbacks / res.t.size if res.t.size else 0.0
    bypassed = share > scenario.simulation.max_bypassed_share
    return {"controller_bypassed_share": float(share), "controller_verdict": "bypassed" if bypassed else "held"}


def bypassed_text(fallbacks: int, steps: int, max_share: float) -> str:
    """Why a run whose controller was bypassed failed, as a clause (after its name)."""
    return (f"the controller was bypassed at {fallbacks} of {steps} steps ({100.0 * fallbacks / max(steps, 1):.3g} %, "
            f"above simulation.max_bypassed_share = {max_share:g}): the feedback asked for tensions outside "
            "the limits and the plan's were fed forward instead, so the run shows the plan, not the controller "
            "(gains too high for the step, or measurements too noisy)")


SAMPLES_PER_BANDWIDTH = 10.0
"""A sampled controller behaves as designed only with an exchange rate at least this many
times its bandwidth."""


def run_warnings(results: dict[str, SimResult], scenario: Scenario) -> list[str]:
    """Runs that mean less than their numbers say, one sentence each: a closed loop sampled
    too slowly for its bandwidth, or a motor winch held at its limits. (A closed loop whose
    controller was bypassed is a failed run: :func:`controller_verdict`.)"""
    out = []
    h = scenario.time.step_s
    bw = scenario.simulation.control.bandwidth_hz
    if "closed_loop" in results and bw * SAMPLES_PER_BANDWIDTH * h > 1.0:
        out.append(f"closed_loop: the controller's bandwidth ({bw:g} Hz) is above 1/{SAMPLES_PER_BANDWIDTH:g} of "
                   f"the {1.0 / h:g} Hz exchange: sampled this slowly it does not behave as designed "
                   f"(use at most {1.0 / (SAMPLES_PER_BANDWIDTH * h):g} Hz)")
    for name, res in results.items():
        n = res.t.size
        if res.winch_overspeed_steps:
            out.append(f"{name}: at {res.winch_overspeed_steps} of {n} steps a winch's motor turned past its speed "
                       "limit (robot.winch.speed_max_rad_s): the cable drove it")
        elif res.winch_limited_steps:
            out.append(f"{name}: at {res.winch_limited_steps} of {n} steps a winch's motor was held at its torque, "
                       "power or speed limit (robot.winch)")
    return out


@dataclass(frozen=True)
class VirtualPrototype:
    """The paper's verification, done: the plan, each simulated run, and their figures."""

    scenario: Scenario
    plan: Plan
    results: dict
    summary: dict


def virtual_prototype(
    scenario: Scenario,
    *,
    runs: tuple[str, ...] = RUNS,
    plant: str | None = None,
    max_error_m: float | None = None,
    progress: Callable[[str, int, int], None] | None = None,
) -> VirtualPrototype:
    """Plan, then fly the plan on the virtual prototype (the main job, without files).

    Parameters
    ----------
    scenario : Scenario
    runs : tuple of str
        Any of ``open_loop``, ``closed_loop``, ``fixed_base_open_loop``.
    plant : {"mujoco", "own"}, optional
        Default ``scenario.simulation.plant``.
    max_error_m : float, optional
        Position error bound beyond which a run is flagged (default: the scenario's,
        see :func:`error_bounds`).
    progress : callable(run, done, total), optional
        Called as each run goes on; for a run flown in a forked process (below), at its
        start (done = 0) and at its end; then as ``progress("error_budget", poses, total)``
        while the error budget's workspace maps are made (a scenario with pulleys or winches).

    Where it is safe and pays (:func:`~marinecdpr.forked.can_fork`: Linux, two CPUs or
    more, no other thread), the last run flies in a forked copy of this process while
    this one flies the others; the results are the same either way.

    Raises
    ------
    InfeasibleError, SimulationDivergedError
    """
    compile_apart(scenario, plant=plant)  # on a cold cache: the planner, the controller and the loop at once
    p = plan(scenario)
    results = {}
    apart, here = None, list(runs)
    if len(runs) > 1 and forked.can_fork():
        # the last run flies in a forked copy of this process (on the second core) meanwhile;
        # its progress is known when it ends
        last = here.pop()
        apart = forked.Forked(lambda: simulate(scenario, run=last, reference=p, plant=plant))
        if progress is not None:
            progress(last, 0, scenario.time.n_steps)
    try:
        for run in here:
            cb = None if progress is None else (lambda done, total, run=run: progress(run, done, total))
            results[run] = simulate(scenario, run=run, reference=p, plant=plant, progress=cb)
        if apart is not None:
            res = results[last] = apart.result()
            if progress is not None:
                progress(last, res.t.size, res.t.size)
    finally:
        if apart is not None:
            apart.stop()
    results = {run: results[run] for run in runs}
    # the error budget's workspace maps (a scenario with pulleys or winches) take a while: told as "error_budget"
    maps = None if progress is None else (lambda done, total: progress("error_budget", done, total))
    return VirtualPrototype(scenario=scenario, plan=p, results=results,
                            summary=summary(p, results, scenario, max_error_m=max_error_m,
                                                          progress=maps))
