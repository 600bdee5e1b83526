"""The ``operability`` command: in which sea states, over a scatter diagram, can the robot work?
Options -> :class:`~marinecdpr.commands.operability.OperabilitySpec`; the estimate, the run and
its files are :mod:`marinecdpr.commands.operability`'s."""

from __future__ import annotations

import time
from pathlib import Path
from typing import Optional

import typer

from marinecdpr.cli.common import (compile_notice, console, count, err_console, fail_scenario, fail_spec,
    figures_option, interval, load, output, percent, plain, spec_of, warn_singular)
from marinecdpr.cli.progress import progress_bar
from marinecdpr.cli.seas import print_sea_table
from marinecdpr.commands.base import SpecError
from marinecdpr.commands.operability import OperabilitySpec
from marinecdpr.errors import ScenarioError

_default = OperabilitySpec.default


def operability(
    scenario: str = typer.Argument("paper_sea", help="A scenario with a sea_state base motion."),
    scatter: Optional[Path] = typer.Option(_default("scatter"), help="Scatter diagram CSV (hs_m,tp_s,probability "
                                                                     "or hs_m,tz_s,probability), or a package "
                                                                     "diagram's name: illustrative (the default), "
                                                                     "north_atlantic."),
    headings: str = typer.Option(",".join(f"{h:g}" for h in _default("headings")),
                                 help="Wave headings, deg, comma-separated."),
    margin: float = typer.Option(_default("margin"), help="Tension margin to the limits a workable sea keeps, N."),
    duration: float = typer.Option(_default("duration"), help="The operation's duration: the length of each "
                                   "record, s."),
    step: float = typer.Option(_default("step"), help="Time step, s."),
    realisations: int = typer.Option(_default("realisations"), min=1, help="Independent records per sea state: the "
                                     "probability of success is the share that hold."),
    out: Path = typer.Option(Path("out"), "--out", "-o", help="Folder for operability.csv/.json/.png."),
    serial: bool = typer.Option(_default("serial"), "--serial", help="Run the cells in this process, not on Dask "
                                "(the default for small studies, and without Dask)."),
    workers: Optional[int] = typer.Option(_default("workers"), min=1, help="Run on a local Dask cluster of this many "
                                          "workers (the default for large studies: 2)."),
    scheduler: Optional[str] = typer.Option(_default("scheduler"), help="Run on a running Dask scheduler at this "
                                            "address."),
    max_error: Optional[float] = typer.Option(_default("max_error"), help="Also fly the closed loop in each "
                                              "sea state and require its position error below this, m."),
    workspace: Optional[str] = typer.Option(_default("workspace"), "--workspace", help="Judge a grid of held poses "
                                            "(e.g. 12x8) instead of the trajectory."),
    min_area: float = typer.Option(_default("min_area"), min=0.0, max=1.0, help="With --workspace: share of the "
                                   "frame's poses that must stay feasible."),
    figures: bool = figures_option("operability.png"),
) -> None:
    """In which sea states, over a scatter diagram, can the robot work?

    Runs serially for small studies and where Dask is not installed, on a
    local Dask cluster for large ones; --serial, --workers or --scheduler
    choose. Results are the same whichever runs.
    """
    from marinecdpr.commands import operability as command

    spec = spec_of(OperabilitySpec, scatter=scatter, headings=headings, margin=margin, duration=duration, step=step,
                   realisations=realisations, serial=serial, workers=workers, scheduler=scheduler,
                   max_error=max_error, workspace=workspace, min_area=min_area, figures=figures)
    sc = load(scenario, None, None)
    try:  # before any work: the diagram, the largest sea state's size, the executor
        est = command.estimate(spec, sc)
    except SpecError as exc:
        fail_spec(exc)
    except ScenarioError as exc:
        fail_scenario(exc, scenario)
    warn_singular(scenario, (est.singular,))  # where no sea state can be workable
    if est.executor.note:
        err_console.print(f"note: {est.executor.note}", highlight=False, soft_wrap=True)
    t0 = time.perf_counter()
    with output(out) as folder:
        if spec.max_error is not None:  # each cell flies the closed loop on the own plant
            compile_notice("own")
        with progress_bar("sea states") as bar:
            task = bar.add_task("", total=est.cells)
            try:
                result = command.run(spec, sc, estimated=est,
                                     progress=lambda d, tot: bar.update(task, completed=d, total=tot))
            except ScenarioError as exc:
                fail_scenario(exc, scenario)
        elapsed = time.perf_counter() - t0
        paths = [out / p.name for p in result.write(folder)]

    op = result.operability
    print_sea_table(op, f"operability: {plain(sc.name)}", result.executor, elapsed)
    console.print(f"overall {percent(op.operability)}{interval(op.interval, spec.realisations)}, the probability "
                  f"that a {spec.duration:g} s operation succeeds ({count(spec.realisations, 'record')} "
                  "per sea state); written: " + ", ".join(plain(p) for p in paths), highlight=False,
                  soft_wrap=True)
    bypassed = sum(r.controller_bypassed for r in op.results)
    if bypassed:
        err_console.print(plain(f"warning: in {count(bypassed, 'record')} the closed loop's "
                                "controller was bypassed (the plan's tensions fed forward) on more than "
                                f"simulation.max_bypassed_share = {sc.simulation.max_bypassed_share:g} of the steps: "
                                "counted as failures (operability.csv controller_bypassed)"),
                          highlight=False, soft_wrap=True)
