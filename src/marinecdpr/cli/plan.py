"""The ``plan`` command: plan cable tensions along the scenario's trajectory on its moving ship."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Optional

import typer
from rich.table import Table

from marinecdpr.cli.common import (EXIT_INFEASIBLE, console, err_console, fail, fail_scenario, output, plain, styled,
    warn_scale)
from marinecdpr.errors import ScenarioError
from marinecdpr.scenario.fields import TENSION_METHODS
from marinecdpr.scenario.loading import load_scenario


def plan(
    scenario: str = typer.Argument("paper", help="A scenario file, or a built-in name."),
    out: Path = typer.Option(Path("out"), "--out", "-o", help="Folder for plan.csv and figures."),
    method: Optional[str] = typer.Option(
        None, help=f"Tension method (default: the scenario's): {', '.join(TENSION_METHODS)}."
    ),
    fixed_base: bool = typer.Option(
        False, "--fixed-base", help="Plan as if the ship were still (the traditional model)."
    ),
    allow_infeasible: bool = typer.Option(
        False, help="Exit 0 even where the cables cannot hold the platform, or come closer than "
                    "robot.clearance_m to each other, the platform or an obstacle."
    ),
) -> None:
    """Plan cable tensions along the scenario's trajectory on its moving ship."""
    from marinecdpr.planning import planner as planning
    from marinecdpr.planning.budget import check_run_size
    from marinecdpr.report.writers import write_plan_stream

    if method is not None and method not in TENSION_METHODS:
        fail(f"--method {method}: expected one of {', '.join(TENSION_METHODS)}")
    try:
        sc = load_scenario(scenario)
        warn_scale(sc, scenario)
        check_run_size(sc, "plan_stream")
        with output(out) as folder:
            # planned, written and drawn in chunks: memory stays flat however long the plan
            pieces = planning.iter_plan(sc, method=method, base_model="fixed" if fixed_base else None,
                                        chunk_steps=planning.DEFAULT_CHUNK_STEPS)
            result = write_plan_stream(pieces, sc, folder / "plan.csv", folder / "tensions.png")
            elapsed = result.planning_s
    except ScenarioError as exc:
        fail_scenario(exc, scenario)
    csv_path, fig_path = out / "plan.csv", out / "tensions.png"

    table = Table(title=f"plan: {plain(sc.name)} ({result.method}, {result.base_model} base)")
    table.add_column("quantity")
    table.add_column("value", justify="right")
    table.add_row("steps", f"{result.n_steps} ({elapsed * 1e3:.1f} ms)")
    table.add_row("feasible steps", f"{result.n_feasible} of {result.n_steps}")
    if result.n_singular:
        table.add_row("singular steps (J~ loses rank)", f"{result.n_singular} of {result.n_steps}")
    for name, (lo, hi) in (("eq. 18 tensions (N)", result.pinv_range), ("planned tensions (N)", result.tension_range)):
        table.add_row(name, "none" if math.isnan(lo) else f"{lo:.2f} .. {hi:.2f}")
    if sc.robot.clearance_m is not None:
        table.add_row(f"steps closer than {sc.robot.clearance_m:g} m (interference)",
                      f"{result.n_interfering} of {result.n_steps}")
    table.add_row("written", f"{csv_path}\n{fig_path}")
    console.print(table)
    problem, close = result.infeasibility(), result.interference()
    for label, text in (("infeasible:", problem), ("interference:", close)):
        if text is not None:
            err_console.print(styled(label, "bold yellow", f"{plain(sc.name)}: {plain(text)}"), highlight=False,
                              soft_wrap=True)
    if (problem is not None or close is not None) and not allow_infeasible:
        raise typer.Exit(EXIT_INFEASIBLE)
