"""``check``: is a scenario sound? Its keys, units and physics (checked as it loads), its
trajectory inside the frame, where the robot is singular and where its cables come too
close to something; no dynamics solved.

:class:`CheckSpec` holds the options (none beyond the scenario), :func:`estimate` the plan's
size (a scenario too long to plan fails its check), :func:`run` the checks
(:class:`CheckResult`). The command writes no file."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from marinecdpr.commands.base import Estimate, Spec

if TYPE_CHECKING:
    from marinecdpr.scenario.schema import Scenario

__all__ = ["CheckSpec", "CheckResult", "estimate", "run"]


class CheckSpec(Spec):
    """The options of a check: none (the scenario is the run's argument)."""


def estimate(spec: CheckSpec, scenario: Scenario) -> Estimate:
    """The scenario's plan's size, made in chunks as ``plan`` makes it
    (:func:`marinecdpr.commands.plan.estimate`'s)."""
    from marinecdpr.commands import plan

    return plan.estimate(plan.PlanSpec(), scenario)


@dataclass(frozen=True)
class CheckResult:
    """A sound scenario, and what a plan of it will meet.

    Attributes
    ----------
    scenario : Scenario
    frame : SingularPoses
        Where over the frame (level poses) J~ loses rank
        (:func:`~marinecdpr.studies.workspace.singular_poses`).
    along : SingularPoses
        Where along the trajectory J~ loses rank (:func:`~marinecdpr.planning.planner.check_trajectory`).
    interference : str or None
        Where along the trajectory a cable first comes closer than ``robot.clearance_m`` to
        something, one line (:func:`~marinecdpr.planning.planner.trajectory_interference`); None if nowhere.
    path : CleaningPath or None
        A coverage trajectory's path (:func:`~marinecdpr.motion.trajectory.cleaning_path`).
    """

    scenario: Scenario
    frame: Any
    along: Any
    interference: str | None
    path: Any = None

    @property
    def path_cut(self) -> bool:
        """Does the scenario end before its coverage path (only part of the panel cleaned)?"""
        if self.path is None:
            return False
        return self.scenario.trajectory.start_time_s + self.path.duration_s > self.scenario.time.duration_s + 1e-9

    def summary(self) -> dict:
        """The scenario in figures: ``name``, ``dofs``, ``cables``, ``mass_kg``, ``base_motion``
        and ``trajectory`` (types), ``steps``, ``step_s`` (s), ``method``; the singular level poses
        over the frame and steps along the trajectory (counted), ``interference`` (the line or
        None); for a coverage path, its ``lanes``, ``spacing_m``, ``direction_deg``, ``length_m``,
        ``duration_s``, the pass along the edges' ``boundary_length_m`` and ``boundary_duration_s``
        (m, s), and ``cut`` (:attr:`path_cut`)."""
        sc, r = self.scenario, self.scenario.robot
        out = {"name": sc.name, "dofs": r.dofs, "cables": r.n_cables, "mass_kg": r.mass_kg,
               "base_motion": sc.base_motion.type, "trajectory": sc.trajectory.type, "steps": sc.time.n_steps,
               "step_s": sc.time.step_s, "method": sc.planning.method,
               "singular_frame": {"poses": self.frame.n_poses, "singular": self.frame.n_singular},
               "singular_steps": {"steps": self.along.n_poses, "singular": self.along.n_singular},
               "interference": self.interference}
        if self.path is not None:
            p = self.path
            out["coverage"] = {"lanes": p.lanes, "spacing_m": p.spacing_m, "direction_deg": p.direction_deg,
                               "length_m": p.length_m, "duration_s": p.duration_s,
                               "boundary_length_m": p.boundary_length_m, "boundary_duration_s": p.boundary_duration_s,
                               "cut": self.path_cut}
        return out


def run(spec: CheckSpec, scenario: Scenario, *, estimated: Estimate | None = None) -> CheckResult:
    """Check the scenario: its size (unless ``estimated``), its trajectory inside the frame
    and any motion file over the whole duration; then where it is singular and where its
    cables come too close. Some milliseconds to a second; no dynamics solved.

    Raises
    ------
    ScenarioError
        One line: the plan too large, the trajectory leaving the frame, a bad motion file.
    """
    from marinecdpr.planning.planner import check_trajectory, trajectory_interference
    from marinecdpr.studies.workspace import singular_poses

    if estimated is None:
        estimate(spec, scenario)
    along = check_trajectory(scenario)
    frame = singular_poses(scenario)
    close = trajectory_interference(scenario)
    path = None
    if scenario.trajectory.type == "coverage":
        from marinecdpr.motion.trajectory import cleaning_path

        path = cleaning_path(scenario.cleaning)
    return CheckResult(scenario=scenario, frame=frame, along=along, interference=close, path=path)
