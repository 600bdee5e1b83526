"""``plan``: cable tensions along the scenario's trajectory on its moving ship.

:class:`PlanSpec` holds the options, :func:`estimate` the plan's size (refused before any
work where it would not fit), :func:`run` plans and writes (:class:`PlanResult`).

The plan streams: it is made, written to ``plan.csv`` and drawn in ``tensions.png`` a chunk
of :data:`~marinecdpr.planning.planner.DEFAULT_CHUNK_STEPS` steps at a time, so memory stays
flat however long the scenario. :func:`run` therefore takes the output folder: the result
holds the plan's figures (:class:`~marinecdpr.planning.planner.PlanSummary`) and the files,
never the whole plan (:func:`marinecdpr.plan` gives that, where it fits)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable

from pydantic import field_validator

from marinecdpr.commands.base import Estimate, Spec, figures_field
from marinecdpr.scenario.fields import TENSION_METHODS

if TYPE_CHECKING:
    from marinecdpr.scenario.schema import Scenario

__all__ = ["PlanSpec", "PlanResult", "estimate", "run", "FILES"]

FILES = ("plan.csv", "tensions.png")
"""What the command writes, in this order (``tensions.png`` with the spec's ``figures``)."""


class PlanSpec(Spec):
    """The options of a plan.

    Attributes
    ----------
    method : str, optional
        The tension method, one of :data:`~marinecdpr.scenario.fields.TENSION_METHODS`
        (default: the scenario's ``planning.method``).
    fixed_base : bool
        Plan as if the ship were still (the traditional model).
    allow_infeasible : bool
        The command exits 0 even where the cables cannot hold the platform or come closer
        than ``robot.clearance_m`` to something (the plan and its files are the same either
        way: :attr:`PlanResult.failed` reads it).
    figures : bool
        Draw ``tensions.png`` (default: the defaults table's ``"report.figures"``,
        :mod:`marinecdpr.defaults`; True as shipped).
    """

    method: str | None = None
    fixed_base: bool = False
    allow_infeasible: bool = False
    figures: bool = figures_field()

    @field_validator("method")
    @classmethod
    def _method(cls, v):
        if v is not None and v not in TENSION_METHODS:
            raise ValueError(f"expected one of {', '.join(TENSION_METHODS)}")
        return v


def estimate(spec: PlanSpec, scenario: Scenario) -> Estimate:
    """The plan's size (its steps, one chunk in memory at a time), before any work.

    Raises
    ------
    ScenarioError
        One line where the plan would not fit in memory or finish in sane time
        (:func:`~marinecdpr.planning.budget.check_run_size`, ``"plan_stream"``).
    """
    from marinecdpr.planning.budget import check_run_size

    return Estimate(scenario=scenario.name, size=check_run_size(scenario, "plan_stream"))


@dataclass(frozen=True)
class PlanResult:
    """A plan made and written in chunks.

    Attributes
    ----------
    spec : PlanSpec
    scenario : Scenario
    plan : PlanSummary
        The plan's figures (:class:`~marinecdpr.planning.planner.PlanSummary`: steps, feasible,
        singular and interfering steps, tension ranges, N; :meth:`infeasibility`,
        :meth:`interference`), and ``planning_s``, the time spent planning, s.
    paths : tuple of Path
        ``plan.csv`` and (with the spec's ``figures``) ``tensions.png``, as written by :func:`run`.
    """

    spec: PlanSpec
    scenario: Scenario
    plan: Any
    paths: tuple[Path, ...]
    drive: Any = None

    def infeasibility(self) -> str | None:
        """Where the cables cannot hold the platform first: one line, or None."""
        return self.plan.infeasibility()

    def drive_verdict(self) -> str | None:
        """Where a carriage's drive cannot give the force along its rail: one line, or None
        (``drive``, the :class:`~marinecdpr.planning.carriage.DrivePeak` of a scenario whose
        carriage has a mass)."""
        return None if self.drive is None else self.drive.verdict()

    def interference(self) -> str | None:
        """Where a cable first comes closer than ``robot.clearance_m`` to something: one line, or None."""
        return self.plan.interference()

    @property
    def failed(self) -> bool:
        """Infeasible, interfering or beyond the carriage's drive somewhere, and the spec does not allow it
        (the command exits 3)."""
        return ((self.infeasibility() is not None or self.interference() is not None
                 or self.drive_verdict() is not None) and not self.spec.allow_infeasible)

    def summary(self) -> dict:
        """The plan's figures as the command's table gives them: ``steps``, ``feasible``,
        ``singular``, ``interfering`` (steps), ``pinv_range`` and ``tension_range`` (N; NaN
        where no tension is finite), ``method``, ``base_model``, ``planning_s`` (s)."""
        p = self.plan
        out = {"steps": p.n_steps, "feasible": p.n_feasible, "singular": p.n_singular,
               "interfering": p.n_interfering, "pinv_range": tuple(p.pinv_range),
               "tension_range": tuple(p.tension_range), "method": p.method, "base_model": p.base_model,
               "planning_s": p.planning_s}
        if self.drive is not None:
            out["carriage_drive"] = {"peak_N": self.drive.peak_N, "at_s": self.drive.at_s,
                                     "limit_N": self.drive.limit_N}
        return out

    def write(self, folder: str | Path) -> list[Path]:
        """The files :func:`run` wrote, copied into ``folder`` (each atomically; the plan is
        not made again); the paths. The run's own folder gives its paths back as they are."""
        import shutil

        from marinecdpr.textfiles import atomic_path

        folder = Path(folder)
        out = []
        for path in self.paths:
            target = folder / path.name
            if target.resolve() != path.resolve():
                folder.mkdir(parents=True, exist_ok=True)
                with atomic_path(target) as tmp:
                    shutil.copyfile(path, tmp)
            out.append(target)
        return out


def run(spec: PlanSpec, scenario: Scenario, folder: str | Path, *, estimated: Estimate | None = None,
        progress: Callable[[int, int], None] | None = None) -> PlanResult:
    """Plan the scenario chunk by chunk (:func:`~marinecdpr.planning.planner.iter_plan`) and
    write each chunk as it comes (:func:`~marinecdpr.report.writers.write_plan_stream`):
    ``plan.csv`` and (with ``spec.figures``) ``tensions.png`` in ``folder`` (a streaming command's run takes its
    output folder: only one chunk is ever in memory). Each file appears whole or not at all.

    Parameters
    ----------
    folder : str or Path
        Where the files go (created if missing).
    estimated : Estimate, optional
        :func:`estimate`'s of this spec and scenario, where the caller has it: the size is not
        checked again.
    progress : callable(done, total), optional
        Steps planned so far, after each chunk.
    """
    from marinecdpr.planning import planner
    from marinecdpr.report.writers import write_plan_stream

    if estimated is None:
        estimate(spec, scenario)
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    pieces = planner.iter_plan(scenario, method=spec.method, base_model="fixed" if spec.fixed_base else None,
                               chunk_steps=planner.DEFAULT_CHUNK_STEPS)
    if progress is not None:
        pieces = _counted(pieces, scenario.time.n_steps, progress)
    drives: list = []
    carriage = scenario.ship.carriage
    if carriage is not None and carriage.mass_kg is not None and not scenario.robot.has_pulleys:
        pieces = _driven(pieces, scenario, drives)
    paths = (folder / FILES[0], folder / FILES[1]) if spec.figures else (folder / FILES[0],)
    summary = write_plan_stream(pieces, scenario, paths[0], paths[1] if spec.figures else None)
    from marinecdpr.planning.carriage import DrivePeak

    return PlanResult(spec=spec, scenario=scenario, plan=summary, paths=paths,
                      drive=DrivePeak.of(drives) if drives else None)


def _driven(pieces, scenario, drives: list):
    """The pieces, each one's carriage drive force (:func:`~marinecdpr.planning.carriage.drive_force`)
    kept in ``drives``."""
    from marinecdpr.planning.carriage import drive_force

    for piece in pieces:
        drives.append(drive_force(piece, scenario))
        yield piece


def _counted(pieces, total: int, progress: Callable[[int, int], None]):
    """The pieces, telling ``progress(steps so far, total)`` after each."""
    done = 0
    for piece in pieces:
        done += piece.n_steps
        yield piece
        progress(done, total)
