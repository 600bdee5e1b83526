"""The ``plan`` command: plan cable tensions along the scenario's trajectory on its moving ship
(:mod:`marinecdpr.commands.plan`: the options' spec, the size and the streamed run)."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Optional

import typer
from rich.table import Table

from marinecdpr.cli.common import (EXIT_INFEASIBLE, console, err_console, fail_scenario, figures_option, load, output,
    plain, spec_of, styled)
from marinecdpr.commands.plan import PlanSpec
from marinecdpr.errors import ScenarioError
from marinecdpr.scenario.fields import TENSION_METHODS


def plan(
    scenario: str = typer.Argument("paper", help="A scenario file, or a built-in name."),
    out: Path = typer.Option(Path("out"), "--out", "-o", help="Folder for plan.csv and figures."),
    method: Optional[str] = typer.Option(
        PlanSpec.default("method"), help=f"Tension method (default: the scenario's): {', '.join(TENSION_METHODS)}."
    ),
    fixed_base: bool = typer.Option(
        PlanSpec.default("fixed_base"), "--fixed-base", help="Plan as if the ship were still (the traditional model)."
    ),
    allow_infeasible: bool = typer.Option(
        PlanSpec.default("allow_infeasible"),
        help="Exit 0 even where the cables cannot hold the platform, or come closer than "
             "robot.clearance_m to each other, the platform or an obstacle."
    ),
    figures: bool = figures_option("tensions.png"),
) -> None:
    """Plan cable tensions along the scenario's trajectory on its moving ship."""
    from marinecdpr.commands import plan as command

    spec = spec_of(PlanSpec, method=method, fixed_base=fixed_base, allow_infeasible=allow_infeasible,
                   figures=figures)
    sc = load(scenario, None, None)
    try:
        est = command.estimate(spec, sc)  # before any work: too big is one line, exit 2
        with output(out) as folder:
            # planned, written and drawn in chunks: memory stays flat however long the plan
            result = command.run(spec, sc, folder, estimated=est)
    except ScenarioError as exc:
        fail_scenario(exc, scenario)
    p = result.plan
    written = [out / path.name for path in result.paths]

    table = Table(title=f"plan: {plain(sc.name)} ({p.method}, {p.base_model} base)")
    table.add_column("quantity")
    table.add_column("value", justify="right")
    table.add_row("steps", f"{p.n_steps} ({p.planning_s * 1e3:.1f} ms)")
    table.add_row("feasible steps", f"{p.n_feasible} of {p.n_steps}")
    if p.n_singular:
        table.add_row("singular steps (J~ loses rank)", f"{p.n_singular} of {p.n_steps}")
    for name, (lo, hi) in (("eq. 18 tensions (N)", tuple(p.pinv_range)),
                           ("planned tensions (N)", tuple(p.tension_range))):
        table.add_row(name, "none" if math.isnan(lo) else f"{lo:.2f} .. {hi:.2f}")
    if sc.robot.clearance_m is not None:
        table.add_row(f"steps closer than {sc.robot.clearance_m:g} m (interference)",
                      f"{p.n_interfering} of {p.n_steps}")
    if result.drive is not None:
        d = result.drive
        table.add_row("carriage drive along the rail (N)", f"{d.peak_N:.4g} at {d.at_s:.4g} s"
                      + ("" if d.limit_N is None else f" (of {d.limit_N:.4g})"))
    table.add_row("written", "\n".join(str(p) for p in written))
    console.print(table)
    for label, text in (("infeasible:", result.infeasibility()), ("interference:", result.interference()),
                        ("carriage drive:", result.drive_verdict())):
        if text is not None:
            err_console.print(styled(label, "bold yellow", f"{plain(sc.name)}: {plain(text)}"), highlight=False,
                              soft_wrap=True)
    if result.failed:
        raise typer.Exit(EXIT_INFEASIBLE)
