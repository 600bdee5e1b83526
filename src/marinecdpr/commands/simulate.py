"""``simulate``: the main job. Plan, fly the plan on the virtual prototype open loop, closed
loop and with the fixed-base plan on the moving ship, and report.

:class:`SimulateSpec` holds the options, :func:`estimate` the scenario as it will be flown
(its first ``duration`` seconds) and the run's size, refused before any work where it would
not fit; :func:`run` flies it (:class:`SimulateResult`)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable

from pydantic import field_validator

from marinecdpr.commands.base import PLANTS, Estimate, Spec, figures_field, plant, positive

if TYPE_CHECKING:
    from marinecdpr.scenario.schema import Scenario

__all__ = ["SimulateSpec", "SimulateEstimate", "SimulateResult", "DurationCut", "duration_cut", "first_seconds", "estimate",
           "run", "PLANTS"]


class SimulateSpec(Spec):
    """The options of the main job.

    Attributes
    ----------
    plant : {"mujoco", "own"}, optional
        The virtual prototype's plant (default: the scenario's ``simulation.plant``).
    duration : float, optional
        Fly only the scenario's first seconds, s (default: all of it; longer than the
        scenario flies all of it, with a warning: :attr:`SimulateEstimate.cut`).
    max_error : float, optional
        Flag runs whose position or cable-length error passes this, m (default: the
        scenario's, 1% of the frame: :func:`~marinecdpr.studies.prototype_runs.error_bounds`).
    figures : bool
        Draw the four figures (PNG) and the report's images (default: the defaults table's ``"report.figures"``,
        :mod:`marinecdpr.defaults`; True as shipped).
    """

    plant: str | None = None
    duration: float | None = None
    max_error: float | None = None
    figures: bool = figures_field()

    @field_validator("plant")
    @classmethod
    def _plant(cls, v):
        return plant(v)

    @field_validator("duration", "max_error")
    @classmethod
    def _positive(cls, v):
        return positive(v)


@dataclass(frozen=True)
class DurationCut:
    """A ``duration`` longer than the scenario: the run flies the scenario's whole length.

    Attributes
    ----------
    given : float
        The duration asked for, s.
    lasts : float
        The scenario's ``time.duration_s``, s: what is flown.
    """

    given: float
    lasts: float

    def warning(self, scenario: str) -> str:
        """The line that says so, naming the scenario as the user gave it (a name or a file)."""
        return f"--duration {self.given:g}: {scenario} lasts {self.lasts:g} s; flying those {self.lasts:g} s"


def duration_cut(scenario: Scenario, duration: float | None) -> DurationCut | None:
    """The cut where ``duration`` is longer than the scenario (all of it flown), else None."""
    lasts = scenario.time.duration_s
    return DurationCut(given=duration, lasts=lasts) if duration is not None and duration > lasts else None


def first_seconds(scenario: Scenario, duration: float | None) -> tuple[Scenario, DurationCut | None]:
    """The scenario's first ``duration`` seconds (all of it where None), and the cut where
    ``duration`` is longer than the scenario (:func:`duration_cut`)."""
    if duration is None:
        return scenario, None
    lasts = scenario.time.duration_s
    cut = duration_cut(scenario, duration)
    return scenario.with_changes(time={"step_s": scenario.time.step_s, "duration_s": min(duration, lasts)}), cut


@dataclass(frozen=True)
class SimulateEstimate(Estimate):
    """:class:`~marinecdpr.commands.base.Estimate` and what will be flown: ``flown``, the
    scenario cut to the spec's ``duration``; ``cut``, a :class:`DurationCut` where that
    duration is longer than the scenario (None otherwise)."""

    flown: Any = None
    cut: DurationCut | None = None

    def warnings(self, scenario: str | None = None) -> tuple[str, ...]:
        """The estimate's warnings (the run goes on), one line each, naming the scenario as
        ``scenario`` (default: its name)."""
        return () if self.cut is None else (self.cut.warning(self.scenario if scenario is None else scenario),)


def estimate(spec: SimulateSpec, scenario: Scenario) -> SimulateEstimate:
    """The scenario as it will be flown (its first ``duration`` seconds) and the run's size
    (the plan and three runs), before any work.

    Raises
    ------
    ScenarioError
        One line where the run would not fit in memory or finish in sane time
        (:func:`~marinecdpr.planning.budget.check_run_size`, ``"virtual_prototype"``).
    """
    from marinecdpr.planning.budget import check_run_size

    sc, cut = first_seconds(scenario, spec.duration)
    size = check_run_size(sc, "virtual_prototype")
    return SimulateEstimate(scenario=sc.name, size=size, flown=sc, cut=cut)


@dataclass(frozen=True)
class SimulateResult:
    """The main job, done.

    Attributes
    ----------
    spec : SimulateSpec
    scenario : Scenario
        As flown (cut to the spec's ``duration``).
    prototype : VirtualPrototype
        The plan, each run's :class:`~marinecdpr.prototype.simulation.SimResult` (``results``,
        by run name) and the summary (:class:`~marinecdpr.studies.prototype_runs.VirtualPrototype`).
    """

    spec: SimulateSpec
    scenario: Scenario
    prototype: Any

    @property
    def plant(self) -> str:
        """The plant flown."""
        return self.prototype.results["open_loop"].plant

    @property
    def figures(self):
        """Each run's errors, tensions and verdicts, the runs beyond the error bound, those whose
        controller was bypassed, and the warnings
        (:class:`~marinecdpr.studies.prototype_runs.PrototypeFigures`)."""
        return self.prototype.figures

    def summary(self) -> dict:
        """``summary.json``'s content: :attr:`figures` as JSON."""
        return self.prototype.figures.to_json()

    def bypassed(self) -> list[tuple[str, int, int]]:
        """Each run whose controller was bypassed on more than ``simulation.max_bypassed_share``
        of its steps, as (name, bypassed steps, steps): the command then exits 5."""
        f = self.prototype.figures
        return [(run, self.prototype.results[run].controller_fallbacks, f.steps)
                for run in f.runs_controller_bypassed]

    def write(self, folder: str | Path) -> list[Path]:
        """``plan.csv``, ``sim_<run>.csv``, the four figures (with the spec's ``figures``),
        ``summary.json`` and ``report.html`` in ``folder``
        (:func:`~marinecdpr.report.writers.write_virtual_prototype`)."""
        from marinecdpr.report.writers import write_virtual_prototype

        return write_virtual_prototype(self.prototype, Path(folder), figures=self.spec.figures)


def run(spec: SimulateSpec, scenario: Scenario, *, estimated: SimulateEstimate | None = None,
        progress: Callable[[str, int, int], None] | None = None) -> SimulateResult:
    """Plan and fly the scenario's first ``duration`` seconds on the virtual prototype
    (:func:`~marinecdpr.studies.prototype_runs.virtual_prototype`), its size checked first.

    Parameters
    ----------
    estimated : SimulateEstimate, optional
        :func:`estimate`'s of this spec and scenario, where the caller has it: not made again.
    progress : callable(run, done, total), optional
        Steps flown so far in each run (``open_loop``, ``closed_loop``,
        ``fixed_base_open_loop``), then ``("error_budget", poses, total)`` while a scenario
        with pulleys or winches maps its error budget.

    Raises
    ------
    InfeasibleError, SimulationDivergedError
    """
    from marinecdpr.studies.prototype_runs import virtual_prototype

    est = estimate(spec, scenario) if estimated is None else estimated
    vp = virtual_prototype(est.flown, plant=spec.plant, max_error_m=spec.max_error, progress=progress)
    return SimulateResult(spec=spec, scenario=est.flown, prototype=vp)
