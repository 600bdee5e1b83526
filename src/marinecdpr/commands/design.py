"""``design``: search the robot (frame, platform, winches, rope, tool) that cleans a design
study's surface in the fewest expected hours for the power installed, in its seas, and fly
the best through the cleaning job in every sea state.

:class:`DesignCommandSpec` holds the options (the one source of their defaults; the study
file's own model is :class:`~marinecdpr.scenario.design.DesignSpec`), :func:`estimate` reads
the study, chooses what judges the candidates and what flies the finalists (each an
:class:`~marinecdpr.studies.executor.Executor`) and checks the journal a ``resume`` goes on
from, all before any work; :func:`run` searches and verifies (:class:`DesignResult`), or a
caller takes the two steps itself (:func:`search`, :func:`verify`) to do something between
them (the command line opens a second progress bar)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable

from pydantic import Field, field_validator

from marinecdpr.commands.base import BadValue, figures_field
from marinecdpr.commands.seas import ExecutorOptions
from marinecdpr.scenario.design import GENERATIONS, POPULATION, SEED_MAX

if TYPE_CHECKING:  # the spec is read when the command line starts: the work's modules load with the work
    from marinecdpr.scenario.schema import Scenario
    from marinecdpr.studies.design import DesignStudy, Verification

__all__ = ["DesignCommandSpec", "DesignEstimate", "DesignResult", "estimate", "search", "verify", "run", "PLANTS",
           "JOURNAL"]

PLANTS = ("mujoco", "own")
"""The plants the finalists may fly on."""
JOURNAL = "journal.jsonl"
"""The search's journal's name in the output folder: a line a candidate, kept when a run is cut."""


class DesignCommandSpec(ExecutorOptions):
    """The options of a design study (the study itself is the command's argument).

    Attributes
    ----------
    population : int, optional
        Candidates a generation, 4..1000 (default: the study's).
    generations : int, optional
        Generations, 1..1000 (default: the study's).
    seed : int, optional
        The search's seed, 0..2**32-1 (default: the study's): the same seed, the same candidates.
    resume : bool
        Go on with the search an interrupted run kept in its journal (the same study, the
        same seed): its candidates are taken, not judged again.
    verify : bool
        Fly the finalists through the cleaning job in every sea state, closed loop.
    plant : {"mujoco", "own"}, optional
        The finalists' plant (default: the study's, else the template's).
    serial, workers, scheduler
        What judges the candidates (on Dask only where ``workers`` or ``scheduler`` asks)
        and flies the finalists' sea states (on Dask where asked, or by their size)
        (:class:`~marinecdpr.commands.seas.ExecutorOptions`).
    figures : bool
        Draw ``pareto.png``, ``convergence.png``, ``finalists.png`` and the report's images (default: the defaults table's ``"report.figures"``,
        :mod:`marinecdpr.defaults`; True as shipped).
    """

    population: int | None = Field(default=None, ge=POPULATION[0], le=POPULATION[1])
    generations: int | None = Field(default=None, ge=GENERATIONS[0], le=GENERATIONS[1])
    seed: int | None = Field(default=None, ge=0, le=SEED_MAX)
    resume: bool = False
    verify: bool = True
    plant: str | None = None
    figures: bool = figures_field()

    @field_validator("plant", mode="before")
    @classmethod
    def _plant(cls, v):
        v = getattr(v, "value", v)  # the command line's choice
        if v is not None and v not in PLANTS:
            raise BadValue(v, f"expected one of {', '.join(PLANTS)}")
        return v


@dataclass(frozen=True)
class DesignEstimate:
    """What a design run will do, known before it starts.

    Attributes
    ----------
    path : Path
        The study file.
    study : DesignSpec
        The study with the spec's population, generations and seed.
    template : Scenario
        The study's template scenario.
    cells : list of Cell
        The study's sea states (its scatter diagram at each heading).
    scatter : ScatterDiagram
    candidates : int
        Candidates the search judges: population x generations.
    finalists : int
        Finalists to fly (0 without ``verify``).
    search_executor : Executor
        What judges the candidates: a local cluster or a scheduler only where asked (a
        generation is too few candidates to pay for a cluster's start on its own).
    verify_executor : Executor
        What flies the finalists' sea states: as asked, else by their size
        (:meth:`~marinecdpr.studies.executor.Executor.auto`); serial when none is flown.
    journal : Path, optional
        Where the search keeps its candidates.
    resumed : int
        Candidates the journal holds that ``resume`` takes.
    columns_flown : int
        The diagram's columns (one period, one heading) the finalists fly about their
        boundary: all of them less ``[sea] unflown_share``'s (with ``verify = "boundary"``).
    """

    path: Path
    study: Any
    template: Any
    cells: list
    scatter: Any
    candidates: int
    finalists: int
    search_executor: Any
    verify_executor: Any
    journal: Path | None = None
    resumed: int = 0
    columns_flown: int = 0


def estimate(spec: DesignCommandSpec, study: str | Path = "ship_side", *,
             journal: str | Path | None = None) -> DesignEstimate:
    """The study read (its file, template, scatter diagram: every file it names), the
    spec's options applied to it, the executors chosen, and with ``resume`` the journal
    checked, before any work.

    Parameters
    ----------
    study : str or Path
        A design study file (.toml), or a built-in study's name
        (:func:`~marinecdpr.studies.design.builtin_studies`).
    journal : str or Path, optional
        The search's journal (the command line's ``OUT/journal.jsonl``); needed with ``resume``.

    Raises
    ------
    ScenarioError
        pymoo not installed; the study, its template or its seas wrong (naming the file and
        key); a journal that cannot be resumed (another study, not a journal, none there).
    SpecError
        The executor's options against the machine (a scheduler that does not answer, Dask
        asked for but not installed); ``resume`` without a journal.
    """
    from marinecdpr.commands.base import SpecError, headings
    from marinecdpr.errors import ScenarioError
    from marinecdpr.studies.design import (load_design, read_journal, sea_columns, study_cells, study_key, study_path,
                                           study_scatter, unflown_columns, with_options)
    from marinecdpr.studies.executor import Executor
    from marinecdpr.studies.operability import CLOSED_LOOP_STEP_COST

    path = study_path(study)
    try:
        import pymoo  # noqa: F401
    except ImportError:
        raise ScenarioError("design needs pymoo: pip install 'marinecdpr[design]'") from None
    design, template = load_design(path)
    design = with_options(design, population=spec.population, generations=spec.generations, seed=spec.seed)
    try:  # the study's headings by the rule of every command's --headings
        headings(design.sea.headings_deg)
    except ValueError as exc:
        raise ScenarioError(str(exc), source=str(path), key="sea.headings_deg") from None
    cells = study_cells(design, path.parent, template)
    finalists = design.finalists if spec.verify else 0
    # about: each finalist's every sea state flown closed loop over the template's duration (or,
    # about each column's boundary, some four of its seas)
    flown_columns = len(sea_columns(cells)) - len(unflown_columns(cells, design.sea.unflown_share))
    flights = len(cells) if design.sea.verify == "all" else min(len(cells), 4 * flown_columns)
    steps = finalists * flights * template.time.n_steps * CLOSED_LOOP_STEP_COST
    verify_executor = spec.executor(steps) if finalists else Executor.serial()
    asked = not spec.serial and (spec.workers is not None or bool(spec.scheduler))
    search_executor = spec.executor() if asked else Executor.serial()
    journal = Path(journal) if journal is not None else None
    resumed = 0
    if spec.resume:  # before the search's first candidate: a journal that cannot be resumed is one line
        if journal is None:
            raise SpecError("resume", True, "needs the journal of the run it goes on with")
        resumed = len(read_journal(journal, study_key(design, template, cells)))
    return DesignEstimate(path=path, study=design, template=template, cells=cells,
                          scatter=study_scatter(design, path.parent, template), candidates=design.population * design.generations,
                          finalists=finalists, search_executor=search_executor, verify_executor=verify_executor,
                          journal=journal, resumed=resumed, columns_flown=flown_columns)


@dataclass(frozen=True)
class DesignResult:
    """A design study: the search and its finalists flown.

    Attributes
    ----------
    study : DesignStudy
        Every candidate judged, the Pareto front, the baseline (the template's robot).
    template : Scenario
    verified : tuple of Verification
        The finalists flown through every sea state (empty without ``verify``, or with no
        feasible candidate).
    cells : int
        The study's sea states.
    figures : bool
        :meth:`write` draws the PNGs and the report's images (the spec's ``figures``).
    """

    study: DesignStudy
    template: Scenario
    verified: tuple = ()
    cells: int = 0
    figures: bool = True

    def summary(self) -> dict:
        """``summary.json``'s content (:func:`~marinecdpr.report.design.design_summary`)."""
        from marinecdpr.report.design import design_summary

        return design_summary(self.study, list(self.verified))

    def write(self, folder: str | Path) -> list[Path]:
        """candidates.csv, pareto.csv and .png, convergence.png, finalists.csv and .png,
        designs/*.toml, summary.json and report.html in ``folder`` (the PNGs with
        :attr:`figures`), made if missing
        (:func:`~marinecdpr.report.design.write_design`; each file written whole or not at all)."""
        from marinecdpr.report.design import write_design

        folder = Path(folder)
        folder.mkdir(parents=True, exist_ok=True)
        return write_design(self.study, self.template, folder, list(self.verified), figures=self.figures)


def search(spec: DesignCommandSpec, estimated: DesignEstimate, *,
           progress: Callable[[int, int, float], None] | None = None) -> DesignStudy:
    """The search (:func:`~marinecdpr.studies.design.search`) on the estimate's executor,
    each candidate kept in the estimate's journal as it is judged.

    Parameters
    ----------
    progress : callable(done, total, best_hours), optional
        After each candidate, with the best feasible expected hours so far.
    """
    from marinecdpr.studies.design import search as search_study

    est = estimated
    return search_study(est.study, est.template, est.cells, progress=progress, journal=est.journal,
                        resume=spec.resume, executor=est.search_executor)


def verify(spec: DesignCommandSpec, estimated: DesignEstimate, study: DesignStudy, *,
           progress: Callable[[int, int], None] | None = None) -> list[Verification]:
    """The front's best finalists flown through the cleaning job in every sea state
    (:func:`~marinecdpr.studies.design.verify`) on the estimate's executor; none where
    the estimate has no finalists or the study no feasible candidate.

    Parameters
    ----------
    progress : callable(done, total), optional
        Sea states flown over all finalists.
    """
    from marinecdpr.studies.design import verify as verify_study

    est = estimated
    if not est.finalists or not study.front:
        return []
    return verify_study(study, est.template, est.scatter, executor=est.verify_executor, plant=spec.plant,
                        progress=progress)


def run(spec: DesignCommandSpec, study: str | Path = "ship_side", *, journal: str | Path | None = None,
        estimated: DesignEstimate | None = None, progress: Callable[[int, int, float], None] | None = None,
        verify_progress: Callable[[int, int], None] | None = None) -> DesignResult:
    """:func:`search`, then :func:`verify`; the estimate made first where none is given.

    Parameters
    ----------
    study : str or Path
        The study file or built-in name (with ``estimated``: unused, the estimate's).
    journal : str or Path, optional
        Where the search keeps its candidates (with ``estimated``: the estimate's).
    progress, verify_progress : callable, optional
        :func:`search`'s and :func:`verify`'s.
    """
    est = estimated or estimate(spec, study, journal=journal)
    found = search(spec, est, progress=progress)
    checked = verify(spec, est, found, progress=verify_progress)
    return DesignResult(study=found, template=est.template, verified=tuple(checked), cells=len(est.cells),
                        figures=spec.figures)
