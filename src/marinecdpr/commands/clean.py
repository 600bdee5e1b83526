"""``clean``: the cleaning job. Plan the coverage path over the panel, fly it closed loop in
the scenario's sea and measure the cleaned area from the simulated brush; beside it the same
job in calm water and without the brush's drag (``compare``); with ``guarantee`` lanes set
from a first run's tracking; with ``hull_area`` the hours of a hull panel after panel; with
``surface`` the frame's placements on the hull's curved band; with ``seas`` the job in every
sea state of a scatter diagram.

:class:`CleanSpec` holds the options (the one source of their defaults and of the rules on
which go together), :func:`estimate` checks them against the scenario and sizes the runs,
:func:`tile` places the frame on the surface (``surface``), :func:`run` flies the job
(:class:`CleanResult`; with ``seas``, :class:`CleanSeasResult`)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable

from pydantic import field_validator, model_validator

from marinecdpr.commands.base import Estimate, SpecError, figures_field, headings, positive
from marinecdpr.commands.seas import ExecutorOptions

if TYPE_CHECKING:  # the spec is read when the command line starts: the work's modules load with the work
    from marinecdpr.scenario.schema import Scenario
    from marinecdpr.studies.cleaning import CleaningJob, CleaningSeas
    from marinecdpr.studies.executor import Executor
    from marinecdpr.studies.operability import ScatterDiagram
    from marinecdpr.studies.strip import RailStrip
    from marinecdpr.studies.surface import SurfaceJob

__all__ = ["MOVE_TIME_S", "CleanSpec", "CleanEstimate", "CleanResult", "CleanSeasResult", "estimate", "tile", "run", "PLANTS"]

PLANTS = ("mujoco", "own")
"""The plants a job flies on."""
MOVE_TIME_S = 600.0
"""A move of the frame to its next place where ``move_time`` is not given, s."""


class CleanSpec(ExecutorOptions):
    """The options of a cleaning job.

    Attributes
    ----------
    plant : {"mujoco", "own"}, optional
        The plant the job flies on (default: the scenario's ``simulation.plant``).
    duration : float, optional
        Clean only the first seconds of the path, s (default: the scenario's ``time.duration_s``).
    guarantee : bool
        Set the lanes' overlap to twice the brush's p95 cross-track error from a first run,
        and check it with a second.
    hull_area : float, optional
        Estimate a hull of this many m2 panel after panel (at most 1e6 m2).
    move_time : float, optional
        Seconds to move the frame to its next place, s (0 to 1e6; default
        :data:`MOVE_TIME_S`, 600 s): every move's, where the scenario's
        ``[cleaning.surface.relocation]`` is absent or its mode "fixed"; refused with a crane or
        rail relocation, whose moves are timed by its model.
    surface : bool
        Clean the scenario's ``[cleaning.surface]`` band: the frame's placements on the
        curved surface, and their hours.
    rail : bool
        With ``surface``: clean the band as a strip from the stations of the scenario's
        ``[ship.carriage]`` rail, the carriage stepping the frame one panel along at a time
        (:func:`~marinecdpr.studies.strip.rail_strip`); crane placements where the rail does
        not reach.
    rail_mode : {"fastest", "stepped", "continuous"}
        With ``rail``: how each stretch of the rail is cleaned: the carriage stepping the frame
        panel by panel, moving it without stopping (the platform's path in C compensating), or
        whichever is the faster on each stretch (the default: the job the user wants done in the
        fewest hours; both hours are reported either way).
    fly_runs : {"first", "all"}
        With ``rail`` (not stepped): the continuous runs flown closed loop, each over the
        horizon: the first (the default: one run tells how the controller holds the moving
        frame) or every one (:func:`~marinecdpr.studies.strip.fly_continuous`; a run's flight
        costs a closed loop of the horizon).
    seas : bool
        Fly the job in every sea state of a scatter diagram and say where it works.
    scatter : Path, optional
        With ``seas`` (and implying it): the scatter diagram CSV (``hs_m,tp_s,probability``
        or ``hs_m,tz_s,probability``), or a package diagram's name (``illustrative``, the
        default; ``north_atlantic``).
    headings : tuple of float
        With ``seas``: wave headings, deg (``"180,150"`` is taken too).
    coverage_target : float
        With ``seas``: % of the reachable panel a working job cleans.
    in_band_target : float
        With ``seas``: % of the time a working job keeps the normal force in band.
    serial, workers, scheduler
        With ``seas``: what runs the sea states (:class:`~marinecdpr.commands.seas.ExecutorOptions`):
        this process, a local Dask cluster of this many workers (default 2 where Dask runs),
        a running Dask scheduler at this address.
    compare : bool
        Also fly the job in calm water and without the brush's drag.
    figures : bool
        Draw the figures (``coverage.png``, ``cleaning.png``, ``surface.png``,
        ``sea_states.png``) and the report's images (default: the defaults table's ``"report.figures"``,
        :mod:`marinecdpr.defaults`; True as shipped).
    """

    plant: str | None = None
    duration: float | None = None
    guarantee: bool = False
    hull_area: float | None = None
    move_time: float | None = None
    surface: bool = False
    rail: bool = False
    rail_mode: str = "fastest"
    fly_runs: str = "first"
    seas: bool = False
    scatter: Path | None = None
    headings: tuple[float, ...] = (180.0,)
    coverage_target: float = 99.0
    in_band_target: float = 95.0
    compare: bool = True
    figures: bool = figures_field()

    @field_validator("plant")
    @classmethod
    def _plant(cls, v):
        if v is not None and v not in PLANTS:
            raise ValueError("expected mujoco or own")
        return v

    @field_validator("rail_mode")
    @classmethod
    def _rail_mode(cls, v):
        if v not in ("fastest", "stepped", "continuous"):
            raise ValueError("expected fastest, stepped or continuous")
        return v

    @field_validator("fly_runs")
    @classmethod
    def _fly_runs(cls, v):
        if v not in ("first", "all"):
            raise ValueError("expected first or all")
        return v

    @field_validator("duration", "hull_area")
    @classmethod
    def _positive(cls, v):
        return positive(v)

    @field_validator("move_time")
    @classmethod
    def _move_time(cls, v):
        return positive(v, zero_ok=True)

    @field_validator("headings", mode="before")
    @classmethod
    def _headings(cls, v):
        return headings(v, example="180,150")

    @field_validator("coverage_target", "in_band_target")
    @classmethod
    def _percentage(cls, v):
        if not (math.isfinite(v) and 0.0 <= v <= 100.0):
            raise ValueError("expected a percentage between 0 and 100")
        return v

    @model_validator(mode="after")
    def _together(self):
        if self.surface:
            from marinecdpr.errors import ScenarioError
            from marinecdpr.studies.surface import check_move_time

            try:  # a move longer than the cap makes hours that mean nothing (1e308 s: not finite)
                check_move_time(self.move_time_s)
            except ScenarioError as exc:
                raise SpecError("move_time", self.move_time, exc.detail.split(", got")[0]) from None
        if self.hull_area is not None:
            from marinecdpr.studies.cleaning import check_hull_estimate

            try:  # before the job: an estimate that would mean nothing is one line
                check_hull_estimate(self.hull_area, self.move_time_s)
            except ValueError as exc:
                raise SpecError("hull_area", f"{self.hull_area:g} / --move-time {self.move_time_s:g}",
                                str(exc)) from None
        seas = "--seas" if self.seas else f"--scatter {self.scatter}"
        if self.rail and not self.surface:
            raise SpecError("rail", "without --surface", "--rail cleans the [cleaning.surface] band from the "
                            "carriage's rail: give --surface too")
        if self.rail_mode != "fastest" and not self.rail:
            raise SpecError("rail_mode", self.rail_mode, "goes with --rail: it says how the carriage carries the frame")
        if self.fly_runs != "first" and (not self.rail or self.rail_mode == "stepped"):
            raise SpecError("fly_runs", self.fly_runs, "goes with --rail and a --rail-mode that runs the carriage "
                            "continuously (fastest or continuous): it says which continuous runs are flown")
        if self.rail and self.move_time is not None:
            raise SpecError("move_time", self.move_time, "goes without --rail: the carriage and the crane time "
                            "the moves along the rail")
        if self.surface and self.hull_area is not None:
            raise SpecError("surface", f"with --hull-area {self.hull_area:g}",
                            "choose one (--surface has the hull's real placements)")
        if self.surface and self.over_seas:
            raise SpecError("surface", f"with {seas}", "cannot go together yet: its hours are for the scenario's sea")
        if self.guarantee and self.over_seas:
            raise SpecError("guarantee", f"with {seas}",
                            "cannot go together: it sets the lanes from one sea state's run")
        return self

    @property
    def move_time_s(self) -> float:
        """``move_time`` where given, else :data:`MOVE_TIME_S`, s."""
        return MOVE_TIME_S if self.move_time is None else float(self.move_time)

    def check_relocation(self, scenario: Scenario) -> None:
        """``move_time`` given where the scenario's ``[cleaning.surface.relocation]`` times
        the moves by a crane or a rail: SpecError (one line saying which options go together)."""
        cleaning = scenario.cleaning
        relocation = None if cleaning is None or cleaning.surface is None else cleaning.surface.relocation
        if self.surface and not self.rail and self.move_time is not None and relocation is not None \
                and relocation.mode != "fixed":
            raise SpecError("move_time", self.move_time,
                            f"goes with no [cleaning.surface.relocation] or its mode = \"fixed\"; the scenario's "
                            f"mode = \"{relocation.mode}\" times each move by its own figures: leave --move-time out")

    @property
    def over_seas(self) -> bool:
        """Is the job flown over a scatter diagram (``seas``, or a ``scatter`` given)?"""
        return self.seas or self.scatter is not None


@dataclass(frozen=True)
class CleanEstimate(Estimate):
    """:class:`~marinecdpr.commands.base.Estimate` and what the job will fly.

    Attributes
    ----------
    flown : Scenario
        The scenario as flown: its first ``duration`` seconds where the spec gives fewer.
    runs : int
        The most closed-loop runs of the whole job (the guarantee's two, the compared
        variants, with ``rail`` not stepped the first continuous run's, or with ``fly_runs``
        "all" one for each stretch the carriage follows), each of ``flown.time.n_steps`` steps.
    asked, lasts : float, optional
        Where the spec's ``duration`` asked for more than the scenario lasts: that duration
        and the scenario's own, s (the scenario's is flown).
    path_s : float, optional
        With ``seas``: the coverage path's end, s, where each sea state flies only its first part.
    diagram : ScatterDiagram, optional
        With ``seas``: the scatter diagram read.
    cells : int
        With ``seas``: the sea states (and headings) flown.
    steps : int
        With ``seas``: the study's work in planned steps (the measure an executor is chosen by,
        :meth:`~marinecdpr.studies.executor.Executor.choose`).
    executor : Executor, optional
        With ``seas``: what will run the sea states (the spec's ``serial``, ``workers``,
        ``scheduler``, and the study's size).
    """

    flown: Any = None
    runs: int = 1
    asked: float | None = None
    lasts: float | None = None
    path_s: float | None = None
    diagram: ScatterDiagram | None = None
    cells: int = 0
    steps: int = 0
    executor: Executor | None = None

    def warnings(self, name: str | None = None) -> list[str]:
        """What the run will not do as asked, a line each (the command line prints each after
        ``warning:``): ``name`` is the scenario as the user gave it (default its own name)."""
        name = self.scenario if name is None else name
        out = []
        if self.lasts is not None:
            out.append(f"--duration {self.asked:g}: "
                       f"{name} lasts {self.lasts:g} s; flying those {self.lasts:g} s")
        if self.path_s is not None:
            out.append(f"{name}: a PARTIAL job: each sea state flies the first {self.flown.time.duration_s:g} s of "
                       f"the {self.path_s:.4g} s path; its coverage and hours are that part's")
        return out


def estimate(spec: CleanSpec, scenario: Scenario) -> CleanEstimate:
    """The spec against the scenario (a cleaning job in it; with ``seas`` a sea-state base
    motion and the scatter diagram) and the runs' size, before any work.

    Raises
    ------
    ScenarioError
        One line: no cleaning job in the scenario, a scatter diagram that cannot be read, a
        scenario without a sea state for ``seas``, or runs the machine cannot hold or finish
        (:func:`~marinecdpr.planning.budget.check_run_size`).
    SpecError
        ``move_time`` with a crane or rail relocation (:meth:`CleanSpec.check_relocation`);
        with ``seas``: the executor cannot be made (a ``scheduler`` that does not answer; Dask
        not installed for ``workers``).
    """
    from marinecdpr.errors import ScenarioError
    from marinecdpr.planning.budget import check_run_size

    spec.check_relocation(scenario)
    sc = scenario
    if spec.rail and sc.ship.carriage is None:
        raise ScenarioError("missing: clean --rail steps the frame along [ship.carriage]'s rail: give the rail and "
                            "the carriage's limits", source=sc.name, key="ship.carriage")
    if sc.cleaning is None or sc.trajectory.type != "coverage":
        raise ScenarioError("no cleaning job: give a [cleaning] section and [trajectory] type = \"coverage\"",
                            source=sc.name, key="cleaning")
    asked = lasts = None
    if spec.duration is not None:
        if spec.duration > sc.time.duration_s:
            asked, lasts = spec.duration, sc.time.duration_s
        sc = sc.with_changes(time={"step_s": sc.time.step_s, "duration_s": min(spec.duration, sc.time.duration_s)})
    size = check_run_size(sc, "simulate")  # before any work: too big is one line
    if not spec.over_seas:
        from marinecdpr.studies.cleaning import job_variants

        flights = 0  # the continuous runs flown: the first, or at most one a followed stretch
        if spec.rail and spec.rail_mode != "stepped":
            from marinecdpr.studies.strip import followed_stretches

            flights = followed_stretches(sc) if spec.fly_runs == "all" else 1
        runs = (2 if spec.guarantee else 1) + (len(job_variants(sc)) - 1 if spec.compare else 0) + flights
        return CleanEstimate(scenario=sc.name, size=size, flown=sc, runs=runs, asked=asked, lasts=lasts)

    from marinecdpr.motion.trajectory import cleaning_path
    from marinecdpr.studies.operability import (CLOSED_LOOP_STEP_COST, check_sea_state, check_sea_wind,
                                                read_scatter_csv, scatter_path, tz_conversion_gamma)

    path_end = sc.trajectory.start_time_s + cleaning_path(sc.cleaning).duration_s
    diagram = read_scatter_csv(scatter_path(spec.scatter), gamma=tz_conversion_gamma(sc))
    check_sea_state(sc)
    check_sea_wind(sc, diagram)
    cells = int((diagram.probability > 0).sum()) * len(spec.headings)
    # every sea state flies the job closed loop
    size = check_run_size(sc, "operability", cells=cells, closed_loop=True, workers=spec.processes)
    steps = cells * sc.time.n_steps * CLOSED_LOOP_STEP_COST
    return CleanEstimate(scenario=sc.name, size=size, flown=sc, runs=cells, asked=asked, lasts=lasts,
                         path_s=path_end if sc.time.duration_s < path_end else None, diagram=diagram, cells=cells,
                         steps=steps, executor=spec.executor(steps))


def tile(spec: CleanSpec, scenario: Scenario, *, progress: Callable[[float], None] | None = None
         ) -> SurfaceJob | RailStrip:
    """The frame's placements on the scenario's ``[cleaning.surface]`` and their hours, the
    moves taking ``spec.move_time`` (:func:`~marinecdpr.studies.surface.surface_job`); with
    ``rail`` the strip cleaned from the carriage's stations
    (:func:`~marinecdpr.studies.strip.rail_strip`, over ``scenario``'s horizon: give the flown
    one, :attr:`CleanEstimate.flown`). A command line tiles before it opens its output, so a
    surface that cannot be tiled is one line before any job is flown.

    Parameters
    ----------
    progress : callable(share), optional
        The share of the band settled, 0 to 1 (first called once the band's checks pass).

    Raises
    ------
    ScenarioError
        No surface, or one that cannot be tiled; with ``rail`` the rail's refusals
        (:func:`~marinecdpr.studies.strip.rail_strip`).
    """
    from marinecdpr.studies.surface import surface_job

    spec.check_relocation(scenario)
    if spec.rail:
        from marinecdpr.studies.strip import rail_strip

        return rail_strip(scenario, progress=progress, mode=spec.rail_mode)
    return surface_job(scenario, move_time_s=spec.move_time_s, progress=progress)


@dataclass(frozen=True)
class CleanResult:
    """A cleaning job flown, and what was set beside it.

    Attributes
    ----------
    spec : CleanSpec
    scenario : Scenario
        As flown (its first ``duration`` seconds).
    job : CleaningJob
        The job (with ``guarantee``, the run whose lanes were kept; its ``figures`` hold
        ``guarantee``).
    comparison : dict of {str: dict of {str: float}}, optional
        With ``compare``: the job's figures beside calm water's and without the brush's drag
        (:func:`~marinecdpr.studies.cleaning.compare_conditions`), the job first ("as asked").
    hull : dict, optional
        With ``hull_area``: the hull's placements and hours (:func:`~marinecdpr.studies.cleaning.ship_side`).
    surface : SurfaceJob, optional
        With ``surface``: the frame's placements on the curved band.
    strip : RailStrip, optional
        With ``rail``: the band cleaned from the carriage's stations, its first continuous run
        (or every one, the spec's ``fly_runs``) flown closed loop
        (:attr:`~marinecdpr.studies.strip.RailStrip.flights`) where it has one.
    """

    spec: CleanSpec
    scenario: Scenario
    job: CleaningJob
    comparison: dict | None = None
    hull: dict | None = None
    surface: SurfaceJob | None = None
    strip: RailStrip | None = None

    def summary(self) -> dict:
        """``summary.json``'s content: the job's figures, then ``comparison``, ``hull``,
        ``surface`` and ``strip`` where flown."""
        out = dict(self.job.summary)
        if self.comparison is not None:
            out["comparison"] = self.comparison
        if self.hull is not None:
            out["hull"] = self.hull
        if self.surface is not None:
            out["surface"] = self.surface.summary()
        if self.strip is not None:
            out["strip"] = self.strip.summary()
        return out

    def findings(self) -> list[str]:
        """What the numbers say, in sentences (:func:`~marinecdpr.report.cleaning.cleaning_findings`)."""
        from marinecdpr.report.cleaning import cleaning_findings

        return cleaning_findings(self.job.figures, hull=self.hull, comparison=self.comparison)

    def bypassed(self) -> list[tuple[str, int, int]]:
        """The closed loops whose controller was bypassed: (name, bypassed steps, steps) of the
        job, the guarantee's first run, the compared variants and the strip's continuous runs (beyond
        ``simulation.max_bypassed_share``)."""
        f = self.job.figures
        share = self.scenario.simulation.max_bypassed_share
        runs = [("the cleaning job", f.controller_fallbacks, f.steps)] if f.controller_verdict == "bypassed" else []
        g = f.guarantee
        if g is not None and g.second_run and g.first_run_controller_verdict == "bypassed":
            runs.append(("the guarantee's first run", g.first_run_controller_fallbacks, f.steps))
        for name, figures in (self.comparison or {}).items():
            if name != "as asked" and figures["controller_bypassed_share"] > share:
                runs.append((f"the job in {name}" if name == "calm water" else f"the job with {name}",
                             figures["controller_fallbacks"], f.steps))
        flights = () if self.strip is None else self.strip.flights
        for j, flight in enumerate(flights):
            if flight.controller_verdict == "bypassed":
                runs.append(("the continuous run" if len(flights) == 1 else f"continuous run {j + 1}",
                             flight.controller_fallbacks, int(flight.t.size)))
        return runs

    def write(self, folder: str | Path) -> list[Path]:
        """``clean.csv``, ``coverage.png``, ``cleaning.png``, ``summary.json``, ``report.html``
        (:func:`~marinecdpr.report.cleaning.write_cleaning`), with ``surface``
        ``placements.csv``, ``surface.png`` (:func:`~marinecdpr.report.cleaning.write_surface`),
        with ``rail`` ``stations.csv``, ``stretches.csv`` and, where continuous runs were flown,
        ``continuous_flight.csv`` (the first) and ``continuous_flight_2.csv``, ... (the others)
        (:func:`~marinecdpr.report.cleaning.write_strip`) in
        ``folder``, the PNGs only with the spec's ``figures``; returns the paths."""
        from marinecdpr.report.cleaning import write_cleaning, write_strip, write_surface

        figures = self.spec.figures
        paths = write_cleaning(self.job, Path(folder), hull=self.hull, comparison=self.comparison,
                               summary=self.summary(), figures=figures)
        paths += write_surface(self.surface, Path(folder), figures=figures) if self.surface is not None else []
        return paths + (write_strip(self.strip, Path(folder)) if self.strip is not None else [])


@dataclass(frozen=True)
class CleanSeasResult:
    """The cleaning job over a scatter diagram.

    Attributes
    ----------
    spec : CleanSpec
    scenario : Scenario
        The template each sea state flies (its first ``duration`` seconds).
    seas : CleaningSeas
        Where the job works, and its expected hours (:func:`~marinecdpr.studies.cleaning.cleaning_seas`).
    executor : Executor
        What ran the sea states.
    """

    spec: CleanSpec
    scenario: Scenario
    seas: CleaningSeas
    executor: Executor

    def summary(self) -> dict:
        """``summary.json``'s content (:func:`~marinecdpr.report.cleaning.cleaning_seas_summary`)."""
        from marinecdpr.report.cleaning import cleaning_seas_summary

        return cleaning_seas_summary(self.seas, self.scenario)

    def write(self, folder: str | Path) -> list[Path]:
        """``sea_states.csv``, ``summary.json``, ``sea_states.png`` (with the spec's ``figures``)
        in ``folder`` (:func:`~marinecdpr.report.cleaning.write_cleaning_seas`); returns the paths."""
        from marinecdpr.report.cleaning import write_cleaning_seas

        return write_cleaning_seas(self.seas, self.scenario, Path(folder), figures=self.spec.figures)


def run(spec: CleanSpec, scenario: Scenario, *, estimated: CleanEstimate | None = None,
        progress: Callable[[int, int], None] | None = None, placed: SurfaceJob | RailStrip | None = None,
        executor: Executor | None = None) -> CleanResult | CleanSeasResult:
    """The cleaning job of the spec (:func:`~marinecdpr.studies.cleaning.cleaning_job`, or
    :func:`~marinecdpr.studies.cleaning.guaranteed_job`), the compared variants, the hull's
    hours and the surface's placements (with ``rail``, the strip's first continuous run or every
    one flown, :func:`~marinecdpr.studies.strip.fly_continuous`); with ``seas`` the job over the scatter diagram. The
    spec is checked against the scenario first (:func:`estimate`).

    Parameters
    ----------
    estimated : CleanEstimate, optional
        :func:`estimate`'s of this spec and scenario, where the caller has it: not made again.
    progress : callable(done, total), optional
        Steps flown over all the job's runs (``estimated.runs`` of ``n_steps`` each; at the
        end ``(done, done)``: a guarantee met at once skips its second run); with ``seas``, sea
        states flown.
    placed : SurfaceJob or RailStrip, optional
        With ``surface``: :func:`tile`'s, where the caller has it.
    executor : Executor, optional
        With ``seas``: what runs the sea states (default the estimate's: from ``serial``,
        ``workers``, ``scheduler`` and the study's size, :meth:`~marinecdpr.studies.executor.Executor.choose`).

    Raises
    ------
    ScenarioError, InfeasibleError, SimulationDivergedError
        As the job's runs raise them.
    SpecError
        ``hull_area`` where the panel's job cleaned nothing.
    """
    est = estimate(spec, scenario) if estimated is None else estimated
    if spec.over_seas:
        return _over_seas(spec, est, progress=progress, executor=executor)
    from marinecdpr.studies.cleaning import cleaning_job, compare_conditions, guaranteed_job, ship_side

    sc = est.flown
    if spec.surface and placed is None:
        placed = tile(spec, sc)
    done = [0]

    def step(k: int, n: int) -> None:  # the runs one after the other, on one count
        if progress is not None:
            progress(done[0] + k, est.runs * sc.time.n_steps)
        if k == n:
            done[0] += n

    job = (guaranteed_job if spec.guarantee else cleaning_job)(sc, plant=spec.plant, progress=step)
    comparison = compare_conditions(job, plant=spec.plant, progress=step) if spec.compare else None
    if spec.rail:  # the first continuous run (or every one) flown closed loop, where the strip has one
        from marinecdpr.studies.strip import fly_continuous

        placed = fly_continuous(placed, sc, runs=spec.fly_runs, plant=spec.plant, progress=step)
    if progress is not None:
        progress(done[0], done[0])  # the runs that were flown
    hull = None
    if spec.hull_area is not None:
        try:
            hull = ship_side(job.figures, hull_area_m2=spec.hull_area, move_time_s=spec.move_time_s)
        except ValueError as exc:
            raise SpecError("hull_area", spec.hull_area, str(exc)) from None
    return CleanResult(spec=spec, scenario=sc, job=job, comparison=comparison, hull=hull,
                       surface=placed if spec.surface and not spec.rail else None,
                       strip=placed if spec.rail else None)


def _over_seas(spec: CleanSpec, est: CleanEstimate, *, progress, executor: Executor | None) -> CleanSeasResult:
    """``seas``: the job in every sea state of the diagram, on the executor given or the estimate's."""
    from marinecdpr.studies.cleaning import cleaning_seas

    executor = executor or est.executor or spec.executor(est.steps)
    cs = cleaning_seas(est.flown, est.diagram, headings_deg=spec.headings, coverage_target_pct=spec.coverage_target,
                       in_band_target_pct=spec.in_band_target, plant=spec.plant, hull_area_m2=spec.hull_area,
                       move_time_s=spec.move_time_s, executor=executor, progress=progress)
    return CleanSeasResult(spec=spec, scenario=est.flown, seas=cs, executor=executor)
