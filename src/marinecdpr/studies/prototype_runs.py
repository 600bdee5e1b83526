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

__all__ = ["PAPER_REPORTED", "VirtualPrototype", "virtual_prototype", "RunFigures", "run_figures", "run_summary",
           "PrototypeFigures", "prototype_figures", "summary",
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


@dataclass(frozen=True)
class RunFigures:
    """The figures of one run (:func:`run_figures`); :meth:`to_json` is its part of ``summary.json``.

    The orientation error ``max_abs_error_theta_deg`` is theta_y for a planar robot and the
    rotation angle between planned and actual orientation for a spatial one, which also has
    ``max_abs_error_y_m`` and ``max_abs_error_{rx,ry,rz}_deg`` (None for a planar robot).
    ``controller_bypassed_share`` and ``controller_verdict`` (:func:`controller_verdict`) are
    None for a run without a controller; ``winch_limited_steps`` and ``winch_overspeed_steps``
    None without motor winches. ``carriage_drive`` (a frame carried by a carriage with its
    mass): the drive's largest force along the rail over the run, ``{"peak_N", "at_s",
    "limit_N"}`` (the carriage part's record, :mod:`~marinecdpr.prototype.parts.carriage`),
    and ``carriage_tracking_error`` (any carriage) the carriage's largest deviation from its
    trajectory (m or rad; 0 on the own plant); else None. ``detections`` (a closed loop whose
    controller detected a fault, ``[simulation.control.safety]``): each detection's ``step``,
    ``t_s``, ``kind``, ``sensor`` and ``cable`` (1-based; 0: none), and ``reaction`` the
    controller's reaction at the end; else None (and not in ``summary.json``). ``faults`` (a
    scenario with ``[[faults]]``): each fault and when it acted, ``{"kind", "cable", "at_s",
    "acted_s"}`` (:attr:`~marinecdpr.prototype.simulation.SimResult.faults`); else None.
    ``within_error_bound`` is False if a position or cable-length
    error passed :func:`error_bounds`' first value or the angle error its second;
    ``beyond_error_bound`` names the quantities that did, e.g. ``("x", "rz", "cable 3")``.
    """

    max_abs_error_x_m: float
    max_abs_error_z_m: float
    max_abs_error_theta_deg: float
    max_abs_cable_length_error_m: tuple[float, ...]
    tension_min_N: float
    tension_max_N: float
    tension_limit_excess_N: float
    rms_error_x_m: float
    rms_error_z_m: float
    controller_fallbacks: int
    ship_tracking_error: float
    plant: str
    within_error_bound: bool
    beyond_error_bound: tuple[str, ...]
    max_abs_error_y_m: float | None = None
    max_abs_error_rx_deg: float | None = None
    max_abs_error_ry_deg: float | None = None
    max_abs_error_rz_deg: float | None = None
    controller_bypassed_share: float | None = None
    controller_verdict: str | None = None
    winch_limited_steps: int | None = None
    winch_overspeed_steps: int | None = None
    carriage_drive: dict | None = None
    carriage_tracking_error: float | None = None
    detections: tuple[dict, ...] | None = None
    reaction: str | None = None
    faults: list | None = None

    @property
    def largest_position_error_m(self) -> float:
        """The largest of the position errors (x, z, and y for a spatial robot), m."""
        return max(v for v in (self.max_abs_error_x_m, self.max_abs_error_z_m, self.max_abs_error_y_m)
                   if v is not None)

    def max_abs_error(self, dof: str) -> float:
        """The largest error of one controlled DOF: ``x``, ``y``, ``z`` (m) or ``rx``, ``ry``,
        ``rz`` (deg; for a spatial robot)."""
        value = getattr(self, f"max_abs_error_{dof}_{'m' if dof in ('x', 'y', 'z') else 'deg'}")
        if value is None:
            raise ValueError(f"this run has no {dof} error (a planar robot)")
        return value

    def to_json(self) -> dict:
        """This run's part of ``summary.json`` (the optional figures only where they exist)."""
        out: dict = {"max_abs_error_x_m": self.max_abs_error_x_m, "max_abs_error_z_m": self.max_abs_error_z_m,
                     "max_abs_error_theta_deg": self.max_abs_error_theta_deg}
        if self.max_abs_error_y_m is not None:
            out["max_abs_error_y_m"] = self.max_abs_error_y_m
            out["max_abs_error_rx_deg"] = self.max_abs_error_rx_deg
            out["max_abs_error_ry_deg"] = self.max_abs_error_ry_deg
            out["max_abs_error_rz_deg"] = self.max_abs_error_rz_deg
        out["max_abs_cable_length_error_m"] = list(self.max_abs_cable_length_error_m)
        out["tension_min_N"] = self.tension_min_N
        out["tension_max_N"] = self.tension_max_N
        out["tension_limit_excess_N"] = self.tension_limit_excess_N
        out["rms_error_x_m"] = self.rms_error_x_m
        out["rms_error_z_m"] = self.rms_error_z_m
        out["controller_fallbacks"] = self.controller_fallbacks
        if self.controller_verdict is not None:
            out["controller_bypassed_share"] = self.controller_bypassed_share
            out["controller_verdict"] = self.controller_verdict
        if self.winch_limited_steps is not None:
            out["winch_limited_steps"] = self.winch_limited_steps
            out["winch_overspeed_steps"] = self.winch_overspeed_steps
        out["ship_tracking_error"] = self.ship_tracking_error
        if self.carriage_tracking_error is not None:
            out["carriage_tracking_error"] = self.carriage_tracking_error
        if self.carriage_drive is not None:
            out["carriage_drive"] = dict(self.carriage_drive)
        if self.detections:
            out["detections"] = [dict(d) for d in self.detections]
            out["reaction"] = self.reaction
        if self.faults is not None:
            out["faults"] = [dict(f) for f in self.faults]
        out["plant"] = self.plant
        out["within_error_bound"] = self.within_error_bound
        out["beyond_error_bound"] = list(self.beyond_error_bound)
        return out

    @classmethod
    def from_json(cls, data: dict) -> RunFigures:
        """The record back from :meth:`to_json`'s dict (a run's part of a ``summary.json`` read back).

        Raises
        ------
        ValueError
            A key that is not a run's figure, or a figure missing.
        """
        return cls(**_record_fields(cls, data, "a run's figures",
                                    tuples=("max_abs_cable_length_error_m", "beyond_error_bound", "detections")))


def run_figures(res: SimResult, scenario: Scenario, *, max_error_m: float | None = None) -> RunFigures:
    """The figures of one run (:class:`RunFigures`)."""
    err = res.pose_error
    f: dict = {}
    for i in (0, 2):
        f[f"max_abs_error_{_NAMES[i]}_m"] = float(np.abs(err[:, i]).max())
    if scenario.robot.dofs == "planar":
        f["max_abs_error_theta_deg"] = float(np.degrees(np.abs(err[:, 4]).max()))
    else:
        f["max_abs_error_theta_deg"] = float(_rotation_error_deg(res).max())
        f["max_abs_error_y_m"] = float(np.abs(err[:, 1]).max())
        for i in (3, 4, 5):
            f[f"max_abs_error_{_NAMES[i]}_deg"] = float(np.degrees(np.abs(err[:, i]).max()))
    cables = tuple(float(v) for v in np.abs(res.lengths - res.lengths_planned).max(axis=0))
    lo, hi = scenario.robot.tension_min, scenario.robot.tension_max
    # by how much the applied tensions left their limits (elastic dynamics, lag, noise)
    excess = float(max(0.0, (lo - res.tensions).max(), (res.tensions - hi).max()))
    verdict = controller_verdict(res, scenario)
    if scenario.simulation.cables.winch == "motor":
        f["winch_limited_steps"] = res.winch_limited_steps
        f["winch_overspeed_steps"] = res.winch_overspeed_steps
    if scenario.ship.carriage is not None:
        f["carriage_tracking_error"] = res.carriage_tracking_error
    if res.carriage_drive is not None:
        d = res.carriage_drive
        f["carriage_drive"] = {"peak_N": d.peak_N, "at_s": d.peak_at_s, "limit_N": d.limit_N}
    if res.detections:
        f["detections"] = tuple({"step": d.step, "t_s": d.t, "kind": d.kind, "sensor": d.sensor, "cable": d.cable + 1}
                                for d in res.detections)
        f["reaction"] = res.reaction
    if res.faults:  # which faults acted, and when
        f["faults"] = [dict(x) for x in res.faults]
    bound_m, bound_deg = error_bounds(scenario, max_error_m)
    beyond = [name for name in ("x", "y", "z") if f.get(f"max_abs_error_{name}_m", 0.0) > bound_m]
    if scenario.robot.dofs == "planar":
        beyond += ["theta_y"] if f["max_abs_error_theta_deg"] > bound_deg else []
    else:
        beyond += [name for name in ("rx", "ry", "rz") if f[f"max_abs_error_{name}_deg"] > bound_deg]
    beyond += [f"cable {i + 1}" for i, v in enumerate(cables) if v > bound_m]
    return RunFigures(
        **f, max_abs_cable_length_error_m=cables,
        tension_min_N=float(res.tensions.min()), tension_max_N=float(res.tensions.max()),
        tension_limit_excess_N=excess if excess > _tension_tolerance(hi) else 0.0,
        rms_error_x_m=float(np.sqrt(np.mean(err[:, 0] ** 2))), rms_error_z_m=float(np.sqrt(np.mean(err[:, 2] ** 2))),
        controller_fallbacks=res.controller_fallbacks,
        controller_bypassed_share=verdict.get("controller_bypassed_share"),
        controller_verdict=verdict.get("controller_verdict"),
        ship_tracking_error=res.ship_tracking_error, plant=res.plant,
        within_error_bound=not beyond, beyond_error_bound=tuple(beyond))


def run_summary(res: SimResult, scenario: Scenario, *, max_error_m: float | None = None) -> dict:
    """The figures of one run as in ``summary.json``: :func:`run_figures`' :meth:`RunFigures.to_json`."""
    return run_figures(res, scenario, max_error_m=max_error_m).to_json()


def _tension_tolerance(hi: np.ndarray) -> float:
    from marinecdpr.model.tension import TENSION_TOLERANCE

    return TENSION_TOLERANCE * max(1.0, float(np.max(np.abs(hi))))


@dataclass(frozen=True)
class PrototypeFigures:
    """The main job's figures (:func:`prototype_figures`); :meth:`to_json` is ``summary.json``.

    Attributes
    ----------
    scenario : str
    steps : int
    step_s : float
    method : str
        The planner's tension method.
    pinv_tension_min_N, opt_tension_min_N, opt_tension_max_N : float
        The plan's tension range, the pseudo-inverse's (eq. 18) least alone, N.
    error_bound_m, error_bound_deg : float
        :func:`error_bounds`.
    controller_bypassed_share_max : float
        ``simulation.max_bypassed_share``.
    open_loop_growth_rate_1_s : float
    stability : dict
        :func:`~marinecdpr.studies.stability.stability_summary`.
    error_budget : dict
        The cables-as-built error budget (:func:`~marinecdpr.studies.error_budget.budget_summary`),
        with ``error_budget_workspace_held_share_point`` where maps were made and ``winches``
        with a winch report (else None).
    error_budget_workspace_held_share_point : float or None
    winches : dict or None
    paper_reported : dict or None
        :data:`PAPER_REPORTED`, for the paper's experiment only (:func:`is_paper_scenario`).
    runs : dict of str to RunFigures
        Each run's, in the order flown.
    runs_beyond_error_bound, runs_controller_bypassed : tuple of str
    warnings : tuple of str
        :func:`run_warnings`, and the plan's first close approach.
    interference : dict or None
        :meth:`~marinecdpr.planning.planner.Plan.interference_summary`.
    runs_beyond_carriage_drive : tuple of str or None
        A carriage with a drive limit: the runs whose drive had to give more than
        ``ship.carriage.drive_force_max_N`` (:meth:`drive_verdict`); None without one.
    """

    scenario: str
    steps: int
    step_s: float
    method: str
    pinv_tension_min_N: float
    opt_tension_min_N: float
    opt_tension_max_N: float
    error_bound_m: float
    error_bound_deg: float
    controller_bypassed_share_max: float
    open_loop_growth_rate_1_s: float
    stability: dict
    error_budget: dict
    runs: dict
    runs_beyond_error_bound: tuple[str, ...]
    runs_controller_bypassed: tuple[str, ...]
    warnings: tuple[str, ...]
    error_budget_workspace_held_share_point: float | None = None
    winches: dict | None = None
    paper_reported: dict | None = None
    interference: dict | None = None
    runs_beyond_carriage_drive: tuple[str, ...] | None = None

    def drive_verdict(self) -> str | None:
        """One line where a run's carriage drive had to give more than its limit (the run of
        the largest force, and how many more), as ``plan`` says it of the plan; None otherwise."""
        from marinecdpr.planning.carriage import DrivePeak

        beyond = self.runs_beyond_carriage_drive
        if not beyond:
            return None
        worst = max(beyond, key=lambda name: self.runs[name].carriage_drive["peak_N"])
        d = self.runs[worst].carriage_drive
        more = f" (and {len(beyond) - 1} more run{'s' if len(beyond) > 2 else ''})" if len(beyond) > 1 else ""
        return f"{worst}{more}: " + DrivePeak(peak_N=d["peak_N"], at_s=d["at_s"], limit_N=d["limit_N"]).verdict()

    def to_json(self) -> dict:
        """``summary.json``'s content (each run's figures under its name)."""
        out: dict = {
            "scenario": self.scenario,
            "steps": self.steps,
            "step_s": self.step_s,
            "method": self.method,
            "pinv_tension_min_N": self.pinv_tension_min_N,
            "opt_tension_min_N": self.opt_tension_min_N,
            "opt_tension_max_N": self.opt_tension_max_N,
            "error_bound_m": self.error_bound_m,
            "error_bound_deg": self.error_bound_deg,
            "controller_bypassed_share_max": self.controller_bypassed_share_max,
            "open_loop_growth_rate_1_s": self.open_loop_growth_rate_1_s,
            "stability": self.stability,
            "error_budget": self.error_budget,
        }
        if self.error_budget_workspace_held_share_point is not None:
            out["error_budget_workspace_held_share_point"] = self.error_budget_workspace_held_share_point
        if self.winches is not None:
            out["winches"] = self.winches
        if self.paper_reported is not None:
            out["paper_reported"] = self.paper_reported
        for name, run in self.runs.items():
            out[name] = run.to_json()
        out["runs_beyond_error_bound"] = list(self.runs_beyond_error_bound)
        out["runs_controller_bypassed"] = list(self.runs_controller_bypassed)
        out["warnings"] = list(self.warnings)
        if self.interference is not None:
            out["interference"] = self.interference
        if self.runs_beyond_carriage_drive is not None:
            out["runs_beyond_carriage_drive"] = list(self.runs_beyond_carriage_drive)
        return out

    @classmethod
    def from_json(cls, data: dict) -> PrototypeFigures:
        """The record back from :meth:`to_json`'s dict (a ``summary.json`` read back).

        Raises
        ------
        ValueError
            A key that is neither a figure nor a run's name, or a figure missing.
        """
        runs = {name: RunFigures.from_json(data[name]) for name in RUNS if name in data}
        rest = {k: v for k, v in data.items() if k not in runs}
        return cls(runs=runs, **_record_fields(cls, rest, "the main job's figures",
                                               tuples=("runs_beyond_error_bound", "runs_controller_bypassed",
                                                       "warnings", "runs_beyond_carriage_drive")))


def _record_fields(cls, data: dict, what: str, *, tuples: tuple[str, ...]) -> dict:
    """``data``'s keys as ``cls``'s fields (``tuples`` as tuples), refusing a key it does not
    have or a required field missing, with one line naming them."""
    from dataclasses import MISSING, fields

    names = {f.name for f in fields(cls)}
    unknown = sorted(set(data) - names)
    if unknown:
        raise ValueError(f"{what}: unknown key(s) {', '.join(unknown)}")
    missing = sorted(f.name for f in fields(cls) if f.default is MISSING and f.name not in data and f.name != "runs")
    if missing:
        raise ValueError(f"{what}: missing key(s) {', '.join(missing)}")
    return {k: tuple(v) if k in tuples else v for k, v in data.items()}


def prototype_figures(plan: Plan, results: dict[str, SimResult], scenario: Scenario, *,
                      max_error_m: float | None = None,
                      progress: Callable[[int, int], None] | None = None) -> PrototypeFigures:
    """The main job's figures (:class:`PrototypeFigures`): each run's, the plan's tension range,
    the error bounds, the open loop's stability along the plan (:mod:`~marinecdpr.studies.stability`),
    the cables-as-built error budget (:mod:`~marinecdpr.studies.error_budget`), the closed loops
    whose controller was bypassed (beyond ``controller_bypassed_share_max``:
    :func:`controller_verdict`), and (for the paper's experiment only, see
    :func:`is_paper_scenario`) the paper's errors."""
    bound_m, bound_deg = error_bounds(scenario, max_error_m)
    g = plan_stability(plan, scenario)
    budget = budget_summary(*error_budget(scenario, plan, progress=progress))
    runs = {name: run_figures(res, scenario, max_error_m=max_error_m) for name, res in results.items()}
    warnings = run_warnings(results, scenario)
    close = plan.interference_summary()
    if close is not None and close["first"] is not None:
        warnings.append(f"plan: {close['first']}")
    return PrototypeFigures(
        scenario=scenario.name, steps=int(plan.n_steps), step_s=scenario.time.step_s, method=plan.method,
        pinv_tension_min_N=float(np.nanmin(plan.tensions_pinv)), opt_tension_min_N=float(np.nanmin(plan.tensions)),
        opt_tension_max_N=float(np.nanmax(plan.tensions)), error_bound_m=bound_m, error_bound_deg=bound_deg,
        controller_bypassed_share_max=scenario.simulation.max_bypassed_share,
        open_loop_growth_rate_1_s=g.rate, stability=stability_summary(g),
        error_budget=budget["error_budget"],
        error_budget_workspace_held_share_point=budget.get("error_budget_workspace_held_share_point"),
        winches=budget.get("winches"),
        paper_reported=PAPER_REPORTED if is_paper_scenario(scenario) else None,
        runs=runs,
        runs_beyond_error_bound=tuple(name for name, r in runs.items() if not r.within_error_bound),
        runs_controller_bypassed=tuple(name for name, r in runs.items() if r.controller_verdict == "bypassed"),
        warnings=tuple(warnings), interference=close,
        runs_beyond_carriage_drive=_beyond_drive(runs, scenario))


def _beyond_drive(runs: dict, scenario: Scenario) -> tuple[str, ...] | None:
    """The runs whose carriage drive passed its limit; None without a carriage's drive limit."""
    c = scenario.ship.carriage
    if c is None or c.drive_force_max_N is None or not any(r.carriage_drive for r in runs.values()):
        return None
    return tuple(name for name, r in runs.items()
                 if r.carriage_drive is not None and r.carriage_drive["peak_N"] > c.drive_force_max_N)


def summary(plan: Plan, results: dict[str, SimResult], scenario: Scenario, *,
            max_error_m: float | None = None, progress: Callable[[int, int], None] | None = None) -> dict:
    """``summary.json``: :func:`prototype_figures`' :meth:`PrototypeFigures.to_json`."""
    return prototype_figures(plan, results, scenario, max_error_m=max_error_m, progress=progress).to_json()


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
    """The paper's verification, done: the plan, each simulated run, and their figures
    (``figures``, :class:`PrototypeFigures`; ``summary``, its JSON)."""

    scenario: Scenario
    plan: Plan
    results: dict
    figures: PrototypeFigures

    @property
    def summary(self) -> dict:
        """``summary.json``'s content: :meth:`PrototypeFigures.to_json`."""
        return self.figures.to_json()


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
                            figures=prototype_figures(p, results, scenario, max_error_m=max_error_m,
                                                      progress=maps))
