"""The ``check`` command: validate a scenario file (keys, units, physics, trajectory inside the frame)
(:mod:`marinecdpr.commands.check`: the plan's size and the checks)."""

from __future__ import annotations

import typer

from marinecdpr.cli.common import console, err_console, fail_scenario, load, plain, spec_of, warn_singular
from marinecdpr.commands.check import CheckSpec
from marinecdpr.errors import ScenarioError


def check(scenario: str = typer.Argument(..., help="A scenario file, or a built-in name.")) -> None:
    """Validate a scenario file (keys, units, physics, trajectory inside the frame)."""
    from marinecdpr.commands import check as command

    spec = spec_of(CheckSpec)
    sc = load(scenario, None, None)
    try:
        result = command.run(spec, sc, estimated=command.estimate(spec, sc))
    except ScenarioError as exc:
        fail_scenario(exc, scenario)
    warn_singular(scenario, (result.frame, result.along))  # valid, but the robot is singular there
    if result.interference is not None:  # valid, but the cables come too close there
        err_console.print(plain(f"warning: {scenario}: {result.interference}"), highlight=False, soft_wrap=True)
    flown, r = result.scenario, result.scenario.robot
    console.print(
        f"{plain(scenario)}: ok: '{plain(flown.name)}', {r.dofs} robot, {r.n_cables} cables, {r.mass_kg:g} kg; "
        f"base motion {flown.base_motion.type}; trajectory {flown.trajectory.type}; "
        f"{flown.time.n_steps} steps of {flown.time.step_s:g} s; method {flown.planning.method}",
        highlight=False, soft_wrap=True,
    )
    if result.path is not None:
        c = result.path
        console.print(f"coverage path: {c.lanes} lanes {c.spacing_m:.4g} m apart at {c.direction_deg:g} deg, "
                      f"{c.length_m:.4g} m, {c.duration_s:.4g} s"
                      + (f" (the pass along the edges {c.boundary_length_m:.4g} m, {c.boundary_duration_s:.4g} s "
                         "of it)" if c.boundary_length_m > 0 else "")
                      + ("" if not result.path_cut else
                         f" (the scenario's {sc.time.duration_s:g} s ends before the path: only part of the panel)"),
                      highlight=False, soft_wrap=True)
