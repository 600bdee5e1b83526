"""The cleaning job: plan the coverage path, fly it closed loop, and measure what got cleaned.

:func:`cleaning_job` plans a scenario whose ``[trajectory]`` is the ``coverage`` path of
its ``[cleaning]`` panel, flies the plan closed loop on the virtual prototype in the
scenario's sea, and measures the job from the *simulated* brush: the cleaned area is the
union of the brush's footprint along its actual path while the normal force is within
the band, clipped to the panel (:func:`~marinecdpr.studies.coverage.coverage_map`).

The normal force. The pusher presses the brush on the hull with the preload P along
-n (n: the hull normal, from the hull towards the robot). On a planar robot the cables
act in the x-z plane and nothing else holds the platform along n, so the contact force
is what balances the pusher and the platform's inertia and weight along n:
F_n = P + (m a - m g - jet)_n. The plan's reaction along n is that requirement less the
planned contact (P) and jet, so F_n = reaction_n + 2 P, from the plan at each step
(the platform's motion along n is the plan's: the guide holds it). On a spatial robot the
cables hold the brush on at the preload: F_n = P.

On the prototype the brush's drag and reaction moment follow the platform's actual
velocity (a part of its own, :class:`~marinecdpr.prototype.parts.BrushContact`), with
the normal force above; the controller's load model holds them along the plan.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace
from typing import Callable

import numpy as np

from marinecdpr.errors import InfeasibleError, ScenarioError, SimulationDivergedError
from marinecdpr.geometry.rotations import matrix_from_euler
from marinecdpr.model.brush import brush_velocity
from marinecdpr.motion.trajectory import cleaning_path
from marinecdpr.planning.planner import Plan, plan
from marinecdpr.prototype.simulation import SimResult, normal_force, simulate
from marinecdpr.prototype.warmup import compile_apart
from marinecdpr.scenario.cleaning import CoverageTrajectory
from marinecdpr.scenario.schema import Scenario
from marinecdpr.studies.coverage import CoverageMap, coverage_map
from marinecdpr.studies.executor import Executor
from marinecdpr.studies.operability import (
    Cell, Operability, ScatterDiagram, cell_scenario, check_sea_state, scatter_cells, summarise,
)
from marinecdpr.studies.prototype_runs import controller_verdict

__all__ = ["CleaningFigures", "Guarantee", "CleaningJob", "cleaning_job", "guaranteed_job", "ship_side",
           "check_hull_estimate", "brush_positions", "normal_force",
           "cross_track_error", "reachable_cells", "CleaningCellResult", "CleaningSeas", "evaluate_cleaning_cell",
           "cleaning_seas", "COVERAGE_TARGET_PCT", "IN_BAND_TARGET_PCT", "COMPARED", "job_variants",
           "compare_conditions", "planned_in_band", "NOT_FLOWN"]


@dataclass(frozen=True)
class Guarantee:
    """Which lane spacing :func:`guaranteed_job` flew and why (``summary.json``'s ``guarantee``)."""

    first_run_p95_cross_track_error_m: float
    overlap_m: float
    lane_spacing_m: float
    reason: str
    second_run: bool
    checked: bool
    """False if the run's p95 cross-track error still passes half the overlap."""
    checked_p95_cross_track_error_m: float
    first_run_controller_fallbacks: int
    first_run_controller_verdict: str | None

    def to_json(self) -> dict:
        """``summary.json``'s ``guarantee``."""
        return {f.name: getattr(self, f.name) for f in fields(self)}


_OPTIONAL = ("controller_bypassed_share", "controller_verdict", "interference", "guarantee")
""":class:`CleaningFigures`' fields that ``summary.json`` holds only where they exist."""


@dataclass(frozen=True)
class CleaningFigures:
    """A cleaning job's figures (``summary.json``: :meth:`to_json`, its keys these fields' names
    in this order). Areas m^2, lengths m, times s, forces N, percentages 0-100.

    ``partial``: the run ended before the path (the figures are the part flown's);
    ``controller_bypassed_share`` and ``controller_verdict``
    (:func:`~marinecdpr.studies.prototype_runs.controller_verdict`) None without a controller;
    ``interference`` (:meth:`~marinecdpr.planning.planner.Plan.interference_summary`) None
    without clearances; ``guarantee`` (:class:`Guarantee`) None unless :func:`guaranteed_job`.
    """

    scenario: str
    robot_dofs: str
    steps: int
    panel_polygon_m: tuple[tuple[float, ...], ...]
    brush_width_m: float
    lane_spacing_m: float
    panel_area_m2: float
    coverage_pct: float
    missed_area_m2: float
    reachable_area_m2: float
    reachable_coverage_pct: float
    overlap_pct: float
    path_length_m: float
    lanes: int
    path_duration_s: float
    boundary_pass_length_m: float
    boundary_pass_time_s: float
    partial: bool
    path_flown_m: float
    path_flown_s: float
    boundary_pass_flown_m: float
    job_time_s: float
    area_rate_m2_h: float
    normal_force_band_N: tuple[float, float]
    normal_force_in_band_pct: float
    normal_force_min_N: float
    normal_force_max_N: float
    contact_lost_s: float
    tension_min_N: float
    tension_max_N: float
    infeasible_steps: int
    max_cross_track_error_m: float
    p95_cross_track_error_m: float
    winch_energy_kJ: float
    coverage_resolution_m: float
    controller_fallbacks: int
    controller_bypassed_share: float | None
    controller_verdict: str | None
    controller_bypassed_share_max: float
    interference: dict | None
    guarantee: Guarantee | None

    def to_json(self) -> dict:
        """``summary.json``'s job figures (the optional ones only where they exist)."""
        out: dict = {}
        for f in fields(self):
            v = getattr(self, f.name)
            if v is None and f.name in _OPTIONAL:
                continue
            if f.name == "panel_polygon_m":
                v = [list(p) for p in v]
            elif f.name == "normal_force_band_N":
                v = list(v)
            elif f.name == "guarantee":
                v = v.to_json()
            out[f.name] = v
        return out


@dataclass(frozen=True)
class CleaningJob:
    """A cleaning job flown on the virtual prototype. Arrays share ``n_steps`` (times ``t``).

    Attributes
    ----------
    scenario : Scenario
    plan : Plan
    result : SimResult
        The closed-loop run.
    brush, brush_planned : ndarray, shape (n_steps, 3)
        The brush's centre in C, actual and planned, m.
    normal_force : ndarray, shape (n_steps,)
        The brush's contact force on the hull, N.
    in_band : ndarray of bool, shape (n_steps,)
        True where the normal force is within ``[cleaning] normal_force_N``.
    cross_track : ndarray, shape (n_steps,)
        The actual brush's distance across its planned direction of travel, m.
    coverage : CoverageMap
    figures : CleaningFigures
        The job's figures.
    summary : dict
        ``summary.json``'s content: ``figures.to_json()``, and what a command sets beside it.
    """

    scenario: Scenario
    plan: Plan
    result: SimResult
    brush: np.ndarray
    brush_planned: np.ndarray
    normal_force: np.ndarray
    in_band: np.ndarray
    cross_track: np.ndarray
    coverage: CoverageMap
    figures: CleaningFigures
    summary: dict


def brush_positions(pose: np.ndarray, offset_P) -> np.ndarray:
    """The brush's centre in C, (n_steps, 3), m, from the platform's pose (n_steps, 6)
    ``(x, y, z, rx, ry, rz)`` in C and the brush's centre ``offset_P`` (3,) in P."""
    R = matrix_from_euler(pose[:, 3:])
    return pose[:, :3] + np.einsum("nij,j->ni", R, np.asarray(offset_P, dtype=float))


def cross_track_error(brush: np.ndarray, planned: np.ndarray, planned_velocity: np.ndarray) -> np.ndarray:
    """Distance of the actual brush (n, 2) from the planned one (n, 2) across the planned
    direction of travel (from ``planned_velocity`` (n, 2)); the whole distance where the
    plan is at rest. m."""
    e = brush - planned
    speed = np.linalg.norm(planned_velocity, axis=1)
    moving = speed > 1e-9
    d = np.zeros_like(planned_velocity)
    d[moving] = planned_velocity[moving] / speed[moving, None]
    along = np.einsum("ni,ni->n", e, d)
    across = e - along[:, None] * d
    return np.linalg.norm(across, axis=1)


_REACHABLE: dict = {}
_REACHABLE_KEPT = 8
"""The last few panels' reachable cells, by their question (:func:`reachable_cells`)."""


def reachable_cells(cov: CoverageMap, radius_m: float) -> np.ndarray:
    """Cells of the panel a round brush of ``radius_m`` can reach at all (its disc kept within
    the panel and clear of the holes): the panel's opening by the disc, on the coverage
    raster. (nz, nx) bool, read-only. A rectangle's four corners, r^2 (1 - pi/4) each, are
    out of reach.

    A pure function of the raster's cells inside the panel, its cell size and the radius,
    kept for the last few panels asked: every flight of a panel (each sea state of a study,
    each finalist's verification) asks the same, and two distance transforms of a 0.3 m
    panel's 2001 x 2001 cells were some 40 % of a short flight.
    """
    inside = cov.passes >= 0
    key = (inside.shape, np.packbits(inside).tobytes(), float(cov.resolution_m), float(radius_m))
    reach = _REACHABLE.pop(key, None)
    if reach is None:
        reach = _reachable(inside, float(cov.resolution_m), float(radius_m))
        reach.flags.writeable = False
        while len(_REACHABLE) >= _REACHABLE_KEPT:
            _REACHABLE.pop(next(iter(_REACHABLE)))
    _REACHABLE[key] = reach  # the most recent last
    return reach


def _reachable(inside: np.ndarray, resolution_m: float, radius_m: float) -> np.ndarray:
    from scipy.ndimage import distance_transform_edt

    inside = np.pad(inside, 1)
    centres = distance_transform_edt(inside) * resolution_m >= radius_m
    reach = distance_transform_edt(~centres) * resolution_m <= radius_m
    return (reach & inside)[1:-1, 1:-1]


def cleaning_job(
    scenario: Scenario,
    *,
    plant: str | None = None,
    n_steps: int | None = None,
    progress: Callable[[int, int], None] | None = None,
    reference: Plan | None = None,
) -> CleaningJob:
    """Plan the coverage path, fly it closed loop, and measure the cleaning.

    Parameters
    ----------
    scenario : Scenario
        With a ``[cleaning]`` section and a ``coverage`` trajectory.
    plant : {"mujoco", "own"}, optional
    n_steps : int, optional
        Only the first steps (short horizons).
    progress : callable(done, total), optional
    reference : Plan, optional
        The scenario's plan, if already made (:func:`~marinecdpr.planning.planner.plan`).

    Raises
    ------
    ScenarioError
        If the scenario has no cleaning job.
    InfeasibleError, SimulationDivergedError
    """
    cleaning = scenario.cleaning
    if cleaning is None or not isinstance(scenario.trajectory, CoverageTrajectory):
        raise ScenarioError("no cleaning job: give a [cleaning] section and [trajectory] type = \"coverage\"",
                            key="cleaning", source=scenario.name)
    if reference is None:
        compile_apart(scenario, plant=plant)  # on a cold cache: the planner, the controller and the loop at once
    p = plan(scenario) if reference is None else reference
    res = simulate(scenario, run="closed_loop", reference=p, plant=plant, n_steps=n_steps, progress=progress)
    n = res.t.size
    brush = brush_positions(res.pose, cleaning.brush_offset_m)
    planned = brush_positions(res.pose_planned, cleaning.brush_offset_m)
    v_planned = brush_velocity(p.twist[:n, :3], p.twist[:n, 3:], matrix_from_euler(p.pose[:n, 3:]),
                               cleaning.brush_offset_m)
    F_n, in_band = planned_in_band(p, scenario, n)
    cross = cross_track_error(brush[:, [0, 2]], planned[:, [0, 2]], v_planned[:, [0, 2]])
    cov = coverage_map(np.asarray(cleaning.panel_m), [np.asarray(h) for h in cleaning.holes_m],
                       brush[:, [0, 2]], in_band, width_m=cleaning.brush_diameter_m)
    figures = _figures(scenario, p, res, F_n, in_band, cross, cov)
    return CleaningJob(scenario=scenario, plan=p, result=res, brush=brush, brush_planned=planned, normal_force=F_n,
                       in_band=in_band, cross_track=cross, coverage=cov, figures=figures, summary=figures.to_json())


def planned_in_band(p: Plan, scenario: Scenario, n: int) -> tuple[np.ndarray, np.ndarray]:
    """The brush's normal force over the plan's first ``n`` steps (N, shape (n,): the pusher's,
    :func:`~marinecdpr.prototype.simulation.normal_force`) and whether it is within
    ``cleaning.band_N`` (to 1e-9 of the band's top), shape (n,) of bool: what a flown job's
    share of time in band is of."""
    F_n = normal_force(p, scenario)[:n]
    lo, hi = scenario.cleaning.band_N
    tol = 1e-9 * max(hi, 1.0)
    return F_n, (F_n >= lo - tol) & (F_n <= hi + tol)


def _figures(scenario: Scenario, p: Plan, res: SimResult, normal_force_N: np.ndarray, in_band: np.ndarray,
             cross: np.ndarray, cov: CoverageMap) -> CleaningFigures:
    cleaning = scenario.cleaning
    path = cleaning_path(cleaning)
    reach = reachable_cells(cov, 0.5 * cleaning.brush_diameter_m)
    cleaned = cov.passes > 0
    h = scenario.time.step_s
    n = res.t.size
    job_time = min(path.duration_s, float(res.t[-1]) + h) if n else 0.0
    # the path's time flown (the run may end before the path: --duration, a short scenario)
    path_time = min(max(float(res.t[-1]) + h - scenario.trajectory.start_time_s, 0.0), path.duration_s) if n else 0.0
    flown_m, flown_edge_m = path.flown(path_time)
    partial = path_time < path.duration_s * (1.0 - 1e-9)
    rates = np.gradient(res.lengths, h, axis=0) if n > 1 else np.zeros_like(res.lengths)
    energy = float(np.sum(np.abs(res.tensions * rates)) * h)  # sum over cables of |T L'| dt, J
    verdict = controller_verdict(res, scenario)
    return CleaningFigures(
        scenario=scenario.name,
        robot_dofs=scenario.robot.dofs,
        steps=int(n),
        panel_polygon_m=tuple(tuple(map(float, v)) for v in cleaning.panel_m),
        brush_width_m=float(cleaning.brush_diameter_m),
        lane_spacing_m=float(path.spacing_m),
        panel_area_m2=float(cov.panel_area_m2),
        coverage_pct=float(cov.coverage_pct),
        missed_area_m2=float(cov.missed_area_m2),
        reachable_area_m2=float(reach.sum() * cov.resolution_m ** 2),
        reachable_coverage_pct=float(100.0 * (cleaned & reach).sum() / max(reach.sum(), 1)),
        overlap_pct=float(cov.overlap_pct),
        path_length_m=float(path.length_m),
        lanes=int(path.lanes),
        path_duration_s=float(path.duration_s),
        boundary_pass_length_m=float(path.boundary_length_m),
        boundary_pass_time_s=float(path.boundary_duration_s),
        partial=bool(partial),
        path_flown_m=float(flown_m),
        path_flown_s=float(path_time),
        boundary_pass_flown_m=float(flown_edge_m),
        job_time_s=float(job_time),
        area_rate_m2_h=float(cov.cleaned_area_m2 / job_time * 3600.0) if job_time > 0 else 0.0,
        normal_force_band_N=tuple(float(v) for v in cleaning.band_N),
        normal_force_in_band_pct=float(100.0 * in_band.mean()) if n else 0.0,
        normal_force_min_N=float(normal_force_N.min()) if n else 0.0,
        normal_force_max_N=float(normal_force_N.max()) if n else 0.0,
        contact_lost_s=float(np.count_nonzero(~in_band) * h),
        tension_min_N=float(res.tensions.min()),
        tension_max_N=float(res.tensions.max()),
        infeasible_steps=int(np.count_nonzero(~p.feasible)),
        max_cross_track_error_m=float(cross.max()) if n else 0.0,
        p95_cross_track_error_m=float(np.percentile(cross, 95)) if n else 0.0,
        winch_energy_kJ=energy / 1000.0,
        coverage_resolution_m=float(cov.resolution_m),
        controller_fallbacks=int(res.controller_fallbacks),
        controller_bypassed_share=verdict.get("controller_bypassed_share"),
        controller_verdict=verdict.get("controller_verdict"),
        controller_bypassed_share_max=float(scenario.simulation.max_bypassed_share),
        interference=None if p.clearance is None else p.interference_summary(),
        guarantee=None,
    )


def guaranteed_job(
    scenario: Scenario,
    *,
    plant: str | None = None,
    n_steps: int | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> CleaningJob:
    """The cleaning job with lanes close enough that the brush's tracking cannot open a gap.

    A first run measures the brush's cross-track error; its 95th percentile e95 calls for
    lanes no more than ``brush_diameter_m - 2 e95`` apart, an overlap of at least 2 e95. If
    the scenario's overlap is less, a second run flies the path with that overlap and checks
    that its own e95 stays within half of it. ``figures.guarantee`` says which spacing
    was used and why; ``checked`` is False if the second run's error still passes the margin.
    """
    first = cleaning_job(scenario, plant=plant, n_steps=n_steps, progress=progress)
    e95 = first.figures.p95_cross_track_error_m
    cleaning = scenario.cleaning
    needed = 2.0 * e95
    if cleaning.overlap_m >= needed:
        reason = (f"the scenario's overlap {cleaning.overlap_m:g} m already covers twice the p95 cross-track "
                  f"error ({e95:.3g} m)")
        job, overlap = first, cleaning.overlap_m
    else:
        overlap = min(needed * 1.05, 0.95 * cleaning.brush_diameter_m)  # a 5 % margin, within the brush
        reason = (f"overlap raised from {cleaning.overlap_m:g} m to {overlap:.4g} m: twice the first run's p95 "
                  f"cross-track error ({e95:.3g} m) with a 5 % margin")
        wider = scenario.with_changes(cleaning=cleaning.model_dump(exclude_none=True) | {"overlap_m": overlap})
        job = cleaning_job(wider, plant=plant, n_steps=n_steps, progress=progress)
    e95_check = job.figures.p95_cross_track_error_m
    guarantee = Guarantee(
        first_run_p95_cross_track_error_m=float(e95), overlap_m=float(overlap),
        lane_spacing_m=float(job.figures.lane_spacing_m), reason=reason, second_run=job is not first,
        checked=bool(2.0 * e95_check <= overlap + 1e-12), checked_p95_cross_track_error_m=float(e95_check),
        first_run_controller_fallbacks=int(first.result.controller_fallbacks),
        first_run_controller_verdict=first.figures.controller_verdict)
    figures = replace(job.figures, guarantee=guarantee)
    return replace(job, figures=figures, summary=figures.to_json())


HULL_AREA_MAX_M2 = 1e6
"""Largest hull area :func:`ship_side` estimates, m^2 (a square kilometre; the largest
ships' wetted surface is some 40 000 m^2)."""
from marinecdpr.studies.surface import MOVE_TIME_MAX_S  # noqa: E402 - one cap for --move-time, with --surface too


def check_hull_estimate(hull_area_m2: float, move_time_s: float) -> None:
    """Refuse a hull area outside (0, :data:`HULL_AREA_MAX_M2`] m^2 or a move time outside
    [0, :data:`MOVE_TIME_MAX_S`] s (ValueError naming it): beyond them the hours are no
    estimate (or not finite)."""
    if not (math.isfinite(hull_area_m2) and 0 < hull_area_m2 <= HULL_AREA_MAX_M2):
        raise ValueError(f"hull_area_m2 must be a positive number of m2 up to {HULL_AREA_MAX_M2:g}, "
                         f"got {hull_area_m2:g}")
    if not (math.isfinite(move_time_s) and 0 <= move_time_s <= MOVE_TIME_MAX_S):
        raise ValueError(f"move_time_s must be a number of seconds from 0 to {MOVE_TIME_MAX_S:g}, got {move_time_s:g}")


def ship_side(figures: CleaningFigures, *, hull_area_m2: float, move_time_s: float) -> dict:
    """How long a hull of ``hull_area_m2`` takes, panel by panel, from one panel's job.

    Each frame placement cleans what the panel's job cleaned (``figures``' ``panel_area_m2``
    less ``missed_area_m2``, m^2) in ``job_time_s``; moving the frame to its next place takes
    ``move_time_s``. Placements = ceil(hull area / cleaned area).

    Returns
    -------
    dict
        ``hull_area_m2``, ``move_time_s``, ``placements``, ``hours``, ``area_rate_m2_h``
        (hull area over the whole time, moves included).
    """
    check_hull_estimate(hull_area_m2, move_time_s)
    cleaned = figures.panel_area_m2 - figures.missed_area_m2
    if not (cleaned > 0 and math.isfinite(hull_area_m2 / cleaned)):
        raise ValueError("the panel's job cleaned nothing: no estimate for the hull")
    placements = int(np.ceil(hull_area_m2 / cleaned - 1e-9))
    seconds = placements * figures.job_time_s + max(placements - 1, 0) * move_time_s
    return {"hull_area_m2": float(hull_area_m2), "move_time_s": float(move_time_s), "placements": placements,
            "hours": seconds / 3600.0, "area_rate_m2_h": float(hull_area_m2 / seconds * 3600.0) if seconds else 0.0}


# ------------------------------------------------------------ beside calm water
COMPARED = ("coverage_pct", "reachable_coverage_pct", "normal_force_in_band_pct", "normal_force_min_N",
            "normal_force_max_N", "tension_min_N", "tension_max_N", "max_cross_track_error_m",
            "p95_cross_track_error_m", "winch_energy_kJ", "controller_fallbacks", "controller_bypassed_share")
"""The figures :func:`compare_conditions` sets side by side."""


def job_variants(scenario: Scenario) -> dict[str, Scenario]:
    """The job as asked, and what it would be in calm water (a still ship: what the sea does)
    and without the brush's drag (friction and jet 0, the pusher's preload kept: what the
    brush's loads do); the calm variant only for a moving ship."""
    variants = {"as asked": scenario}
    if scenario.base_motion.type != "still":
        variants["calm water"] = scenario.with_changes(base_motion={"type": "still"})
    variants["no brush drag"] = scenario.with_changes(
        cleaning=scenario.cleaning.model_dump(exclude_none=True) | {"friction": 0.0, "jet_N": 0.0})
    return variants


def compare_conditions(job: CleaningJob, *, plant: str | None = None, n_steps: int | None = None,
                       progress: Callable[[int, int], None] | None = None) -> dict[str, dict]:
    """The job's figures (:data:`COMPARED`) beside those of the same job in calm water and
    without the brush's drag (:func:`job_variants`), each flown as :func:`cleaning_job` does.
    Returns {variant: {figure: value}}, the job itself first ("as asked")."""
    out = {}
    for name, sc in job_variants(job.scenario).items():
        f = job.figures if name == "as asked" else cleaning_job(sc, plant=plant, n_steps=n_steps,
                                                               progress=progress).figures
        out[name] = {k: getattr(f, k) for k in COMPARED}
    return out


# ------------------------------------------------------------ over a scatter diagram
COVERAGE_TARGET_PCT = 99.0
"""Default share of the reachable panel a workable sea state's job cleans, %."""
IN_BAND_TARGET_PCT = 95.0
"""Default share of the job's time a workable sea state keeps the normal force in band, %."""


@dataclass(frozen=True)
class CleaningCellResult:
    """The cleaning job in one sea state.

    ``operable``: the job works there: the plan has tensions within limits at every step
    and the closed loop held (its controller not bypassed, see
    :func:`~marinecdpr.studies.prototype_runs.controller_verdict`; no divergence), the reachable coverage and the
    share of time in band reach their targets. ``reason`` says why not ("" if it works).
    Percentages are NaN where the job could not be flown.
    """

    cell: Cell
    operable: bool
    reason: str
    coverage_pct: float
    reachable_coverage_pct: float
    in_band_pct: float
    tension_min_N: float
    tension_max_N: float
    job_time_s: float
    hours: float
    """Hours of the job (the hull with ``hull_area_m2``, else the panel); NaN if it failed."""

    realisations = 1  # one record per sea state

    @property
    def successes(self) -> int:
        return int(self.operable)

    @property
    def success_probability(self) -> float:
        return float(self.operable)


NOT_FLOWN = "(in the plan: not flown)"
"""How the reason of a sea state judged by its plan alone ends (:func:`evaluate_cleaning_cell`)."""


def evaluate_cleaning_cell(template: Scenario, cell: Cell, *, coverage_target_pct: float = COVERAGE_TARGET_PCT,
                           in_band_target_pct: float = IN_BAND_TARGET_PCT, plant: str | None = None,
                           hull_area_m2: float | None = None, move_time_s: float = 600.0,
                           plan_first: bool = False) -> CleaningCellResult:
    """Fly the template's cleaning job in one sea state (the template's time and sea
    otherwise; the record's seed from the sea state, :func:`~marinecdpr.studies.operability.sea_state_seed`)
    and judge it.

    With ``plan_first``, a job whose plan already fails is not flown: the plan's tensions
    and its normal force's share of time in band (:func:`planned_in_band`: a flown job's
    verdict takes both from its plan) decide it, and the result's flown figures are NaN;
    the verdict is the flown job's."""
    sc = cell_scenario(template, cell, template.time.duration_s, template.time.step_s)
    nan = float("nan")
    try:
        reference = None
        if plan_first:
            compile_apart(sc, plant=plant)
            reference = plan(sc)
            in_band = 100.0 * float(planned_in_band(reference, sc, reference.n_steps)[1].mean())
            if in_band < in_band_target_pct:
                return CleaningCellResult(cell=cell, operable=False,
                                          reason=f"normal force in band {in_band:.2f} % of the time < "
                                                 f"{in_band_target_pct:g} % {NOT_FLOWN}",
                                          coverage_pct=nan, reachable_coverage_pct=nan, in_band_pct=in_band,
                                          tension_min_N=nan, tension_max_N=nan, job_time_s=nan, hours=nan)
        job = cleaning_job(sc, plant=plant, reference=reference)
    except InfeasibleError:
        return CleaningCellResult(cell=cell, operable=False,
                                  reason="no tensions within the limits at some step of the plan",
                                  coverage_pct=nan, reachable_coverage_pct=nan, in_band_pct=nan, tension_min_N=nan,
                                  tension_max_N=nan, job_time_s=nan, hours=nan)
    except SimulationDivergedError:
        return CleaningCellResult(cell=cell, operable=False, reason="the closed loop diverged", coverage_pct=nan,
                                  reachable_coverage_pct=nan, in_band_pct=nan, tension_min_N=nan, tension_max_N=nan,
                                  job_time_s=nan, hours=nan)
    s = job.figures
    reasons = []
    if s.controller_verdict == "bypassed":
        reasons.append(f"the controller was bypassed at {s.controller_fallbacks} of {s.steps} steps (above "
                       f"simulation.max_bypassed_share = {s.controller_bypassed_share_max:g}): its tensions "
                       "outside the limits, the plan's fed forward")
    if s.reachable_coverage_pct < coverage_target_pct:
        reasons.append(f"reachable coverage {s.reachable_coverage_pct:.2f} % < {coverage_target_pct:g} %")
    if s.normal_force_in_band_pct < in_band_target_pct:
        reasons.append(f"normal force in band {s.normal_force_in_band_pct:.2f} % of the time "
                       f"< {in_band_target_pct:g} %")
    if hull_area_m2 is None:
        hours = s.job_time_s / 3600.0
    elif s.panel_area_m2 > s.missed_area_m2:
        hours = ship_side(s, hull_area_m2=hull_area_m2, move_time_s=move_time_s)["hours"]
    else:  # nothing cleaned: the hull never gets done
        hours = float("inf")
    return CleaningCellResult(cell=cell, operable=not reasons, reason="; ".join(reasons),
                              coverage_pct=s.coverage_pct, reachable_coverage_pct=s.reachable_coverage_pct,
                              in_band_pct=s.normal_force_in_band_pct, tension_min_N=s.tension_min_N,
                              tension_max_N=s.tension_max_N, job_time_s=s.job_time_s,
                              hours=float(hours))


@dataclass(frozen=True)
class CleaningSeas:
    """The cleaning job over a scatter diagram.

    Attributes
    ----------
    sea : Operability
        The verdicts summed up as for tensions (:func:`~marinecdpr.studies.operability.summarise`):
        ``sea.results`` are :class:`CleaningCellResult`; ``sea.operability`` is the
        probability that the job works (headings equally likely), ``sea.per_heading`` and
        ``sea.limiting_hs`` per heading.
    coverage_target_pct, in_band_target_pct : float
        What a workable job reached, %.
    hull_area_m2 : float or None
        The hull the hours are for (None: one panel).
    expected_hours : float
        Hours of the job averaged over the sea states it works in, weighted by their
        probability; NaN if it works in none.
    expected_hours_with_weather : float
        ``expected_hours / sea.operability``: the calendar hours when the work waits for
        workable sea states (each hour's sea state drawn independently from the diagram).
    """

    sea: Operability
    coverage_target_pct: float
    in_band_target_pct: float
    hull_area_m2: float | None
    expected_hours: float
    expected_hours_with_weather: float


def cleaning_seas(
    template: Scenario,
    scatter: ScatterDiagram,
    *,
    headings_deg: tuple[float, ...] = (180.0,),
    coverage_target_pct: float = COVERAGE_TARGET_PCT,
    in_band_target_pct: float = IN_BAND_TARGET_PCT,
    plant: str | None = None,
    hull_area_m2: float | None = None,
    move_time_s: float = 600.0,
    executor: Executor | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> CleaningSeas:
    """The cleaning job in every sea state of a scatter diagram: where it works, and the
    expected hours.

    Each sea state (and heading) flies the template's job (its ``[cleaning]`` path, time
    and ``sea_state`` base motion with the cell's Hs, Tp and heading) closed loop on the
    plant, as :func:`cleaning_job` does, and judges it (:func:`evaluate_cleaning_cell`).
    Cells run on the ``executor`` (:class:`~marinecdpr.studies.executor.Executor`; default
    serial) as :func:`~marinecdpr.studies.operability.operability`'s do, with the same
    results whichever runs them.

    Parameters
    ----------
    template : Scenario
        With ``[cleaning]``, a ``coverage`` trajectory and a ``sea_state`` base motion.
    scatter : ScatterDiagram
    headings_deg : tuple of float
        Wave headings, equally likely, deg.
    coverage_target_pct, in_band_target_pct : float
        The reachable coverage and the share of time with the normal force in band a
        workable job reaches, %.
    plant : {"mujoco", "own"}, optional
    hull_area_m2 : float, optional
        Give the hours for this hull area panel after panel (:func:`ship_side`), else for
        one panel.
    move_time_s : float
        With ``hull_area_m2``: seconds to move the frame to its next place.
    """
    check_sea_state(template)
    if template.cleaning is None or not isinstance(template.trajectory, CoverageTrajectory):
        raise ScenarioError("no cleaning job: give a [cleaning] section and [trajectory] type = \"coverage\"",
                            key="cleaning", source=template.name)
    for name, value in (("coverage_target_pct", coverage_target_pct), ("in_band_target_pct", in_band_target_pct)):
        if not 0.0 <= value <= 100.0:
            raise ValueError(f"{name} must be within 0..100 %, got {value}")
    headings = tuple(float(h) for h in headings_deg)
    cells = scatter_cells(scatter, headings)
    kwargs = dict(coverage_target_pct=coverage_target_pct, in_band_target_pct=in_band_target_pct, plant=plant,
                  hull_area_m2=hull_area_m2, move_time_s=move_time_s)
    executor = executor or Executor.serial()
    results = executor.map(evaluate_cleaning_cell, template, cells, kwargs, progress=progress)
    sea = summarise(scatter, headings, results, 0.0, executor.name)
    # headings equally likely: a cell's weight is its probability over the headings
    weight = np.array([r.cell.probability / len(headings) for r in results])
    works = np.array([r.operable for r in results], dtype=bool)
    hours = np.array([r.hours for r in results])
    expected = float(np.sum(weight[works] * hours[works]) / np.sum(weight[works])) if works.any() else float("nan")
    with_weather = expected / sea.operability if sea.operability > 0 else float("nan")
    return CleaningSeas(sea=sea, coverage_target_pct=float(coverage_target_pct),
                        in_band_target_pct=float(in_band_target_pct),
                        hull_area_m2=None if hull_area_m2 is None else float(hull_area_m2), expected_hours=expected,
                        expected_hours_with_weather=with_weather)
