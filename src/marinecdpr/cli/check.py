"""The ``check`` command: validate a scenario file (keys, units, physics, trajectory inside the frame)."""

from __future__ import annotations

import typer

from marinecdpr.cli.common import console, err_console, fail_scenario, plain, warn_scale, warn_singular
from marinecdpr.errors import ScenarioError
from marinecdpr.scenario.loading import load_scenario


def check(scenario: str = typer.Argument(..., help="A scenario file, or a built-in name.")) -> None:
    """Validate a scenario file (keys, units, physics, trajectory inside the frame)."""
    from marinecdpr.planning.budget import check_run_size
    from marinecdpr.planning.planner import check_trajectory

    try:
        sc = load_scenario(scenario)
        warn_scale(sc, scenario)
        check_run_size(sc, "plan_stream")
        along = check_trajectory(sc)
    except ScenarioError as exc:
        fail_scenario(exc, scenario)
    from marinecdpr.studies.workspace import singular_poses

    warn_singular(scenario, (singular_poses(sc), along))  # valid, but the robot is singular there
    from marinecdpr.planning.planner import trajectory_interference

    close = trajectory_interference(sc)  # valid, but the cables come too close there
    if close is not None:
        err_console.print(plain(f"warning: {scenario}: {close}"), highlight=False, soft_wrap=True)
    r = sc.robot
    console.print(
        f"{plain(scenario)}: ok: '{plain(sc.name)}', {r.dofs} robot, {r.n_cables} cables, {r.mass_kg:g} kg; "
        f"base motion {sc.base_motion.type}; trajectory {sc.trajectory.type}; "
        f"{sc.time.n_steps} steps of {sc.time.step_s:g} s; method {sc.planning.method}",
        highlight=False, soft_wrap=True,
    )
    if sc.trajectory.type == "coverage":
        from marinecdpr.motion.trajectory import cleaning_path

        path = cleaning_path(sc.cleaning)
        end = sc.trajectory.start_time_s + path.duration_s
        console.print(f"coverage path: {path.lanes} lanes {path.spacing_m:.4g} m apart at {path.direction_deg:g} deg, "
                      f"{path.length_m:.4g} m, {path.duration_s:.4g} s"
                      + (f" (the pass along the edges {path.boundary_length_m:.4g} m, {path.boundary_duration_s:.4g} s "
                         "of it)" if path.boundary_length_m > 0 else "")
                      + ("" if end <= sc.time.duration_s + 1e-9 else
                         f" (the scenario's {sc.time.duration_s:g} s ends before the path: only part of the panel)"),
                      highlight=False, soft_wrap=True)
