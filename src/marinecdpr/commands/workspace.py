"""``workspace``: where on the frame the platform can be held while the ship moves.

:class:`WorkspaceSpec` holds the options, :func:`estimate` the run's size and the poses
over the frame where J~ loses rank (known before any work), :func:`run` the map
(:class:`WorkspaceResult`)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Callable

from pydantic import field_validator

from marinecdpr.commands.base import Estimate, Spec, figures_field, finite, grid, positive, with_time

if TYPE_CHECKING:  # the spec is read when the command line starts: the work's modules load with the work
    from marinecdpr.scenario.schema import Scenario
    from marinecdpr.studies.workspace import SingularPoses, WorkspaceMap

__all__ = ["WorkspaceSpec", "WorkspaceEstimate", "WorkspaceResult", "estimate", "run"]


class WorkspaceSpec(Spec):
    """The options of a workspace map.

    Attributes
    ----------
    points : (int, int)
        Grid points along the two axes (``"30x20"`` is taken too).
    axes : str
        The grid's plane: two different letters of x, y, z.
    fixed : float, optional
        The third coordinate, m (default: mid-frame).
    duration : float, optional
        Seconds of ship motion per pose (default: the scenario's ``time.duration_s``).
    step : float, optional
        Time step, s (default: the scenario's ``time.step_s``).
    figures : bool
        Draw ``workspace.png`` (default: the defaults table's ``"report.figures"``,
        :mod:`marinecdpr.defaults`; True as shipped).
    """

    points: tuple[int, int] = (30, 20)
    axes: str = "xz"
    fixed: float | None = None
    duration: float | None = None
    step: float | None = None
    figures: bool = figures_field()

    @field_validator("points", mode="before")
    @classmethod
    def _grid(cls, v):
        return grid(v)

    @field_validator("axes")
    @classmethod
    def _axes(cls, v):
        if len(v) != 2 or any(a not in "xyz" for a in v) or v[0] == v[1]:
            raise ValueError("expected two different letters of x, y, z")
        return v

    @field_validator("fixed")
    @classmethod
    def _fixed(cls, v):
        return finite(v)

    @field_validator("duration", "step")
    @classmethod
    def _time(cls, v):
        return positive(v)


@dataclass(frozen=True)
class WorkspaceEstimate(Estimate):
    """:class:`~marinecdpr.commands.base.Estimate`, and ``singular``: where over the frame J~
    loses rank (:func:`~marinecdpr.studies.workspace.singular_poses`; no dynamics solved)."""

    singular: SingularPoses | None = None


def estimate(spec: WorkspaceSpec, scenario: Scenario) -> WorkspaceEstimate:
    """The map's size (``n_steps`` of ship motion at each of the grid's poses) and the
    singular poses over the frame, before any work.

    Raises
    ------
    ScenarioError
        One line where the run would not fit in memory or finish in sane time
        (:func:`~marinecdpr.planning.budget.check_run_size`).
    """
    from marinecdpr.planning.budget import check_run_size
    from marinecdpr.studies.workspace import singular_poses

    sc = with_time(spec, scenario)
    size = check_run_size(sc, "workspace", grid=spec.points)
    return WorkspaceEstimate(scenario=sc.name, size=size, grid=spec.points, singular=singular_poses(sc))


@dataclass(frozen=True)
class WorkspaceResult:
    """A workspace map and what was found on its grid.

    Attributes
    ----------
    scenario : Scenario
        As flown (with the spec's time).
    map : WorkspaceMap
    singular : SingularPoses
        Where on the map's own grid, and between its points, J~ loses rank
        (:func:`~marinecdpr.studies.workspace.map_singular_poses`).
    figures : bool
        :meth:`write` draws ``workspace.png`` (the spec's ``figures``).
    """

    scenario: Scenario
    map: WorkspaceMap
    singular: SingularPoses
    figures: bool = True

    @property
    def poses(self) -> int:
        """The map's poses inside the frame's range."""
        import numpy as np

        return int(np.isfinite(self.map.fraction_feasible).sum())

    @property
    def feasible_throughout(self) -> int:
        """The poses feasible at every step."""
        import numpy as np

        f = self.map.fraction_feasible
        return int((f[np.isfinite(f)] == 1.0).sum())

    @property
    def interference_free(self) -> int | None:
        """The poses free of interference (None without ``robot.clearance_m``)."""
        import numpy as np

        ws = self.map
        if ws.interference_free is None:
            return None
        return int(ws.interference_free[np.isfinite(ws.fraction_feasible)].sum())

    @property
    def both(self) -> int | None:
        """The poses feasible throughout and free of interference (None without ``robot.clearance_m``)."""
        import numpy as np

        ws = self.map
        if ws.interference_free is None:
            return None
        return int((ws.interference_free & (ws.fraction_feasible == 1.0))[np.isfinite(ws.fraction_feasible)].sum())

    def summary(self) -> dict:
        """The poses inside the frame's range, those feasible throughout, and with
        ``robot.clearance_m`` those free of interference and both; steps per pose."""
        ws = self.map
        out = {"poses": self.poses, "feasible_throughout": self.feasible_throughout, "n_steps": int(ws.n_steps)}
        if ws.interference_free is not None:
            out["interference_free"] = self.interference_free
            out["both"] = self.both
            out["clearance_m"] = float(ws.clearance_m)
        return out

    def write(self, folder: str | Path) -> list[Path]:
        """``workspace.csv`` and (with :attr:`figures`) ``workspace.png`` in ``folder``
        (:func:`~marinecdpr.report.writers.write_workspace`)."""
        from marinecdpr.report.writers import write_workspace

        return write_workspace(self.map, self.scenario, Path(folder), figures=self.figures)


def run(spec: WorkspaceSpec, scenario: Scenario, *, estimated: WorkspaceEstimate | None = None,
        progress: Callable[[int, int], None] | None = None) -> WorkspaceResult:
    """The map of held poses over the frame under the scenario's ship motion
    (:func:`~marinecdpr.studies.workspace.workspace_map`), its size checked first.

    Parameters
    ----------
    estimated : WorkspaceEstimate, optional
        :func:`estimate`'s of this spec and scenario, where the caller has it: the size is
        not checked again.
    progress : callable(done, total), optional
        Poses planned so far.
    """
    from marinecdpr.planning.budget import check_run_size
    from marinecdpr.studies.workspace import map_singular_poses, workspace_map

    sc = with_time(spec, scenario)
    if estimated is None:
        check_run_size(sc, "workspace", grid=spec.points)
    ws = workspace_map(sc, axes=(spec.axes[0], spec.axes[1]), n=spec.points, fixed_m=spec.fixed, progress=progress)
    return WorkspaceResult(scenario=sc, map=ws, singular=map_singular_poses(sc, ws), figures=spec.figures)
