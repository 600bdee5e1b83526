"""Figures of merit of simulated runs, beside the paper's reported ones."""

from __future__ import annotations

import numpy as np

from dataclasses import dataclass
from typing import Callable

from .planning import Plan, plan
from .scenario import Scenario
from .simulation import RUNS, SimResult, simulate

__all__ = ["PAPER_REPORTED", "VirtualPrototype", "virtual_prototype", "run_summary", "summary"]

PAPER_REPORTED = {
    "max_abs_error_x_m": 0.025,
    "max_abs_error_z_m": 0.013,
    "max_abs_error_theta_deg": 0.48,
    "max_cable_length_error_m": 0.15,
}
"""The paper's section 4.2: Adams open loop, largest errors (cable length: cable 2)."""

_NAMES = ("x", "y", "z", "rx", "ry", "rz")


def _rotation_error_deg(res: SimResult) -> np.ndarray:
    """Angle of R_planned^T R_actual at each step, deg."""
    from .rotations import matrix_from_euler

    Rp = matrix_from_euler(res.pose_planned[:, 3:])
    Ra = matrix_from_euler(res.pose[:, 3:])
    cos = (np.einsum("nij,nij->n", Rp, Ra) - 1.0) / 2.0
    return np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))


def run_summary(res: SimResult, scenario: Scenario) -> dict:
    """The figures of one run.

    Keys: ``max_abs_error_x_m``, ``max_abs_error_z_m``, ``max_abs_error_theta_deg``
    (theta_y for a planar robot; the rotation angle between planned and actual
    orientation for a spatial one, which also gets ``y``, ``rx``, ``ry``, ``rz``),
    ``max_abs_cable_length_error_m`` (one per cable), ``tension_min_N``,
    ``tension_max_N`` (applied), ``tension_limit_excess_N`` (how far applied tensions left
    their limits, 0 if never), ``rms_error_x_m``, ``rms_error_z_m``,
    ``controller_fallbacks``, ``ship_tracking_error`` (m or rad), ``plant``.
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
    out["tension_limit_excess_N"] = float(max(0.0, (lo - res.tensions).max(), (res.tensions - hi).max()))
    out["rms_error_x_m"] = float(np.sqrt(np.mean(err[:, 0] ** 2)))
    out["rms_error_z_m"] = float(np.sqrt(np.mean(err[:, 2] ** 2)))
    out["controller_fallbacks"] = res.controller_fallbacks
    out["ship_tracking_error"] = res.ship_tracking_error
    out["plant"] = res.plant
    return out


def summary(plan: Plan, results: dict[str, SimResult], scenario: Scenario) -> dict:
    """``summary.json``: each run's figures and the plan's tension range."""
    out: dict = {
        "scenario": scenario.name,
        "steps": int(plan.n_steps),
        "step_s": scenario.time.step_s,
        "method": plan.method,
        "pinv_tension_min_N": float(np.nanmin(plan.tensions_pinv)),
        "opt_tension_min_N": float(np.nanmin(plan.tensions)),
        "opt_tension_max_N": float(np.nanmax(plan.tensions)),
        "paper_reported": PAPER_REPORTED,
    }
    for name, res in results.items():
        out[name] = run_summary(res, scenario)
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
    progress : callable(run, done, total), optional

    Raises
    ------
    InfeasibleError, SimulationDivergedError
    """
    p = plan(scenario)
    results = {}
    for run in runs:
        cb = None if progress is None else (lambda done, total, run=run: progress(run, done, total))
        results[run] = simulate(scenario, run=run, reference=p, plant=plant, progress=cb)
    return VirtualPrototype(scenario, p, results, summary(p, results, scenario))
