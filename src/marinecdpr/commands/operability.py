"""``operability``: in which sea states, over a scatter diagram, can the robot work?

:class:`OperabilitySpec` holds the options (the one source of their defaults, the
executor's among them), :func:`estimate` reads the scatter diagram, sizes the study by its
largest sea state, looks for singular poses and chooses what runs the sea states (an
:class:`~marinecdpr.studies.executor.Executor`), all before any work; :func:`run` judges
every sea state (:class:`OperabilityResult`)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable

from pydantic import field_validator

from marinecdpr.commands.base import Estimate, figures_field, grid, headings, positive
from marinecdpr.commands.seas import ExecutorOptions

if TYPE_CHECKING:  # the spec is read when the command line starts: the work's modules load with the work
    from marinecdpr.scenario.schema import Scenario
    from marinecdpr.studies.executor import Executor
    from marinecdpr.studies.operability import Operability, ScatterDiagram

__all__ = ["OperabilitySpec", "OperabilityEstimate", "OperabilityResult", "estimate", "run"]


class OperabilitySpec(ExecutorOptions):
    """The options of an operability study.

    Attributes
    ----------
    scatter : Path, optional
        Scatter diagram CSV (``hs_m,tp_s,probability`` or ``hs_m,tz_s,probability``), or a
        package diagram's name (``illustrative``, the default; ``north_atlantic``:
        :data:`~marinecdpr.studies.operability.BUILTIN_SCATTERS`).
    headings : tuple of float
        Wave headings, deg, equally likely (``"180,150"`` is taken too).
    margin : float
        Tension margin to the limits a workable sea state keeps at every step, N (>= 0).
    duration : float
        The operation's duration: the length of each record, s.
    step : float
        Time step, s.
    realisations : int
        Independent records per sea state: the probability of success is the share that hold.
    serial, workers, scheduler
        What runs the sea states (:class:`~marinecdpr.commands.seas.ExecutorOptions`).
    max_error : float, optional
        Also fly the closed loop in each sea state and require its position error below
        this, m.
    workspace : (int, int), optional
        Judge a grid of held poses (``"12x8"``) instead of the trajectory.
    min_area : float
        With ``workspace``: the share of the frame's poses that must stay feasible, 0..1.
    figures : bool
        Draw ``operability.png`` (default: the defaults table's ``"report.figures"``,
        :mod:`marinecdpr.defaults`; True as shipped).
    """

    scatter: Path | None = None
    headings: tuple[float, ...] = (180.0,)
    margin: float = 0.0
    duration: float = 1200.0
    step: float = 0.02
    realisations: int = 10
    max_error: float | None = None
    workspace: tuple[int, int] | None = None
    min_area: float = 1.0
    figures: bool = figures_field()

    @field_validator("headings", mode="before")
    @classmethod
    def _headings(cls, v):
        return headings(v, example="180,150")

    @field_validator("margin")
    @classmethod
    def _margin(cls, v):
        return positive(v, zero_ok=True)

    @field_validator("duration", "step", "max_error")
    @classmethod
    def _positive(cls, v):
        return positive(v)

    @field_validator("realisations")
    @classmethod
    def _realisations(cls, v):
        if v < 1:
            raise ValueError("expected at least 1 record per sea state")
        return v

    @field_validator("workspace", mode="before")
    @classmethod
    def _grid(cls, v):
        return None if v is None else grid(v, example="12x8")

    @field_validator("min_area")
    @classmethod
    def _share(cls, v):
        if not 0.0 <= v <= 1.0:
            raise ValueError("expected a share between 0 and 1")
        return v


@dataclass(frozen=True)
class OperabilityEstimate(Estimate):
    """:class:`~marinecdpr.commands.base.Estimate` (of the largest sea state's records, all
    of them) and what the study will run on.

    Attributes
    ----------
    scatter : ScatterDiagram
        As read from the spec's file.
    cells : int
        Sea states judged: the diagram's of positive probability at each heading.
    steps : int
        The study's work in planned time steps (:func:`~marinecdpr.studies.operability.study_steps`).
    executor : Executor
        What runs the sea states; its ``note`` says when Dask would help but is missing.
    singular : SingularPoses
        Where J~ loses rank along the largest sea state's path (or over the frame, with
        ``workspace``): no sea state is workable there.
    """

    scatter: Any = None
    cells: int = 0
    steps: int = 0
    executor: Any = None
    singular: Any = None


def estimate(spec: OperabilitySpec, scenario: Scenario) -> OperabilityEstimate:
    """The scatter diagram read, the study sized by its largest sea state (the highest Hs
    and the shortest Tp that occur: its records at the spec's duration and step, every
    cell's records on the local processes) and the executor chosen, before any work; then
    the singular poses (the largest sea state's ship motion at its ends).

    Raises
    ------
    ScenarioError
        A bad scatter diagram (naming the file), a template without a sea-state base motion,
        or a study the machine cannot hold or finish.
    SpecError
        The executor's options against the machine: a scheduler that does not answer, Dask
        asked for but not installed.
    """
    import numpy as np

    from marinecdpr.planning.budget import check_run_size
    from marinecdpr.planning.planner import check_trajectory
    from marinecdpr.studies.operability import (Cell, cell_scenario, read_scatter_csv, scatter_path, study_steps,
                                                tz_conversion_gamma)
    from marinecdpr.studies.workspace import singular_poses

    diagram = read_scatter_csv(scatter_path(spec.scatter), gamma=tz_conversion_gamma(scenario))
    occurs = diagram.probability > 0
    n_cells = int(occurs.sum()) * len(spec.headings)
    tp_min = float(diagram.tp[occurs.any(axis=0)].min())  # the highest sea with the shortest period
    wind = {} if diagram.wind_m_s is None else {"wind_m_s": float(np.nanmax(diagram.wind_m_s))}  # the strongest
    largest = cell_scenario(scenario, Cell(index=0, hs=float(diagram.hs.max()), tp=tp_min,
                                           heading_deg=spec.headings[0], probability=1.0, **wind),
                            spec.duration, spec.step)
    size = check_run_size(largest, "operability", cells=n_cells * spec.realisations, grid=spec.workspace,
                          closed_loop=spec.max_error is not None, workers=spec.processes)
    steps = study_steps(n_cells * spec.realisations, duration_s=spec.duration, step_s=spec.step,
                        workspace=spec.workspace, max_error_m=spec.max_error)
    executor = spec.executor(steps)
    # where no sea state can be workable: the robot singular along its path or over the frame
    singular = singular_poses(scenario) if spec.workspace is not None else check_trajectory(largest)
    return OperabilityEstimate(scenario=scenario.name, size=size, grid=spec.workspace, scatter=diagram, cells=n_cells,
                               steps=steps, executor=executor, singular=singular)


@dataclass(frozen=True)
class OperabilityResult:
    """An operability study.

    Attributes
    ----------
    scenario : Scenario
        The template (its sea state's RAOs, spectrum and spreading in every cell).
    operability : Operability
        Per sea state and heading, the probability of success, the limiting Hs.
    executor : Executor
        What ran the sea states.
    figures : bool
        :meth:`write` draws ``operability.png`` (the spec's ``figures``).
    """

    scenario: Scenario
    operability: Operability
    executor: Executor
    figures: bool = True

    def summary(self) -> dict:
        """``operability.json``'s content (:func:`~marinecdpr.report.writers.operability_summary`)."""
        from marinecdpr.report.writers import operability_summary

        return operability_summary(self.operability, self.scenario)

    def write(self, folder: str | Path) -> list[Path]:
        """``operability.csv``, ``operability.json`` and (with :attr:`figures`) ``operability.png``
        in ``folder`` (:func:`~marinecdpr.report.writers.write_operability`)."""
        from marinecdpr.report.writers import write_operability

        return write_operability(self.operability, self.scenario, Path(folder), figures=self.figures)


def run(spec: OperabilitySpec, scenario: Scenario, *, estimated: OperabilityEstimate | None = None,
        progress: Callable[[int, int], None] | None = None) -> OperabilityResult:
    """Every sea state of the diagram at every heading judged
    (:func:`~marinecdpr.studies.operability.operability`) on the estimate's executor; the
    estimate made first where none is given.

    Parameters
    ----------
    estimated : OperabilityEstimate, optional
        :func:`estimate`'s of this spec and scenario, where the caller has it.
    progress : callable(done, total), optional
        Sea states judged so far.
    """
    from marinecdpr.studies.operability import operability

    est = estimated or estimate(spec, scenario)
    op = operability(scenario, est.scatter, headings_deg=spec.headings, margin_N=spec.margin,
                     duration_s=spec.duration, step_s=spec.step, executor=est.executor, max_error_m=spec.max_error,
                     workspace=spec.workspace, min_area=spec.min_area, realisations=spec.realisations,
                     progress=progress)
    return OperabilityResult(scenario=scenario, operability=op, executor=est.executor, figures=spec.figures)
