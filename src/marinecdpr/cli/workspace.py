"""The ``workspace`` command: map where on the frame the platform can be held while the ship moves."""

from __future__ import annotations

import time
from pathlib import Path
from typing import Optional

import typer

from marinecdpr.cli.common import (console, err_console, fail_scenario, figures_option, load, output, plain, spec_of,
    warn_singular)
from marinecdpr.cli.progress import seconds, task_progress
from marinecdpr.commands.workspace import WorkspaceSpec
from marinecdpr.errors import ScenarioError


def workspace(
    scenario: str = typer.Argument("paper", help="A scenario file, or a built-in name."),
    out: Path = typer.Option(Path("out"), "--out", "-o", help="Folder for workspace.csv and workspace.png."),
    axes: str = typer.Option(WorkspaceSpec.default("axes"), help="Grid plane: two of x, y, z."),
    points: str = typer.Option("x".join(map(str, WorkspaceSpec.default("points"))),
                               help="Grid points along the two axes, e.g. 30x20."),
    fixed: Optional[float] = typer.Option(WorkspaceSpec.default("fixed"),
                                          help="The third coordinate, m (default: mid-frame)."),
    duration: Optional[float] = typer.Option(WorkspaceSpec.default("duration"),
                                             help="Seconds of ship motion per pose (default: the scenario's "
                                             "time.duration_s)."),
    step: Optional[float] = typer.Option(WorkspaceSpec.default("step"),
                                         help="Time step, s (default: the scenario's time.step_s)."),
    figures: bool = figures_option("workspace.png"),
) -> None:
    """Map where on the frame the platform can be held while the ship moves."""
    from marinecdpr.commands import workspace as command

    spec = spec_of(WorkspaceSpec, points=points, axes=axes, fixed=fixed, duration=duration, step=step,
                   figures=figures)
    sc = load(scenario, None, None)
    try:
        est = command.estimate(spec, sc)  # before any work: too big is one line, exit 2
    except ScenarioError as exc:
        fail_scenario(exc, scenario)
    warn_singular(scenario, (est.singular,))
    t0 = time.perf_counter()
    with output(out) as folder:
        err_console.print(plain(est.describe()), highlight=False, soft_wrap=True)
        with task_progress("workspace", spec.points[0] * spec.points[1], "poses") as update:
            try:
                result = command.run(spec, sc, estimated=est, progress=update)
            except ScenarioError as exc:
                fail_scenario(exc, scenario)
        elapsed = time.perf_counter() - t0
        paths = [out / p.name for p in result.write(folder)]
    if est.singular.n_singular < est.singular.n_poses:  # (every pose singular is said already)
        warn_singular(scenario, (result.singular,))  # the map's own grid, and between its points
    clear = ("" if result.interference_free is None else
             f", {result.interference_free} free of interference (clearance {result.map.clearance_m:g} m), "
             f"{result.both} both")
    console.print(f"{plain(result.scenario.name)}: {result.feasible_throughout} of {result.poses} poses feasible "
                  f"throughout{clear} ({result.map.n_steps} steps each, {seconds(elapsed)}); written: "
                  + ", ".join(plain(p) for p in paths), highlight=False)
