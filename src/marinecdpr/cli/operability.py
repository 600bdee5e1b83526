"""The ``operability`` command: in which sea states, over a scatter diagram, can the robot work?"""

from __future__ import annotations

import time
from pathlib import Path
from typing import Optional

import typer

from marinecdpr.cli.common import (compile_notice, console, count, err_console, fail_scenario, grid_option, interval,
    load, number, output, percent, plain, warn_singular)
from marinecdpr.cli.progress import progress_bar
from marinecdpr.cli.seas import print_sea_table, scatter_diagram, sea_executor, sea_study_options
from marinecdpr.errors import ScenarioError


def operability(
    scenario: str = typer.Argument("paper_sea", help="A scenario with a sea_state base motion."),
    scatter: Optional[Path] = typer.Option(None, help="Scatter diagram CSV (hs_m,tp_s,probability); "
                                                      "default: the package's illustrative one."),
    headings: str = typer.Option("180", help="Wave headings, deg, comma-separated."),
    margin: float = typer.Option(0.0, help="Tension margin to the limits a workable sea keeps, N."),
    duration: float = typer.Option(1200.0, help="The operation's duration: the length of each record, s."),
    step: float = typer.Option(0.02, help="Time step, s."),
    realisations: int = typer.Option(10, min=1, help="Independent records per sea state: the probability of "
                                     "success is the share that hold."),
    out: Path = typer.Option(Path("out"), "--out", "-o", help="Folder for operability.csv/.json/.png."),
    serial: bool = typer.Option(False, "--serial", help="Run the cells in this process, not on Dask "
                                "(the default for small studies, and without Dask)."),
    workers: Optional[int] = typer.Option(None, min=1, help="Run on a local Dask cluster of this many "
                                          "workers (the default for large studies: 2)."),
    scheduler: Optional[str] = typer.Option(None, help="Run on a running Dask scheduler at this address."),
    max_error: Optional[float] = typer.Option(None, help="Also fly the closed loop in each "
                                              "sea state and require its position error below this, m."),
    workspace_grid: Optional[str] = typer.Option(None, "--workspace", help="Judge a grid of held poses "
                                                 "(e.g. 12x8) instead of the trajectory."),
    min_area: float = typer.Option(1.0, min=0.0, max=1.0, help="With --workspace: share of the frame's "
                                   "poses that must stay feasible."),
) -> None:
    """In which sea states, over a scatter diagram, can the robot work?

    Runs serially for small studies and where Dask is not installed, on a
    local Dask cluster for large ones; --serial, --workers or --scheduler
    choose. Results are the same whichever runs.
    """
    from marinecdpr.planning.budget import check_run_size
    from marinecdpr.studies.executor import LOCAL_WORKERS
    from marinecdpr.studies.operability import Cell, cell_scenario, study_steps
    from marinecdpr.studies.operability import operability as run
    from marinecdpr.report.writers import write_operability

    heads = sea_study_options(headings, serial, workers, scheduler)
    number("--margin", margin, zero_ok=True)
    number("--duration", duration)
    number("--step", step)
    number("--max-error", max_error)
    grid = None
    if workspace_grid is not None:
        grid = grid_option("--workspace", workspace_grid, "12x8")
    sc = load(scenario, None, None)
    diagram = scatter_diagram(scatter)
    n_cells = int((diagram.probability > 0).sum()) * len(heads)
    try:  # the largest cell's run: the highest sea and the shortest period that occur
        tp_min = float(diagram.tp[(diagram.probability > 0).any(axis=0)].min())
        probe = cell_scenario(sc, Cell(index=0, hs=float(diagram.hs.max()), tp=tp_min, heading_deg=heads[0],
                                       probability=1.0), duration, step)
        check_run_size(probe, "operability", cells=n_cells * realisations, grid=grid,
                       closed_loop=max_error is not None, workers=1 if serial else (workers or LOCAL_WORKERS))
        from marinecdpr.planning.planner import check_trajectory
        from marinecdpr.studies.workspace import singular_poses

        # where no sea state can be workable: the robot singular along its path or over the frame
        warn_singular(scenario, (singular_poses(sc),) if grid is not None else (check_trajectory(probe),))
    except ScenarioError as exc:
        fail_scenario(exc, scenario)
    executor = sea_executor(serial, workers, scheduler, study_steps(n_cells * realisations, duration_s=duration,
                                                                     step_s=step, workspace=grid,
                                                                     max_error_m=max_error))
    t0 = time.perf_counter()
    with output(out) as folder:
        if max_error is not None:  # each cell flies the closed loop on the own plant
            compile_notice("own")
        with progress_bar("sea states") as bar:
            task = bar.add_task("", total=n_cells)
            try:
                op = run(sc, diagram, headings_deg=heads, margin_N=margin, duration_s=duration, step_s=step,
                         executor=executor, max_error_m=max_error, workspace=grid, min_area=min_area, realisations=realisations,
                         progress=lambda d, tot: bar.update(task, completed=d, total=tot))
            except ScenarioError as exc:
                fail_scenario(exc, scenario)
        elapsed = time.perf_counter() - t0
        paths = [out / p.name for p in write_operability(op, sc, folder)]

    print_sea_table(op, f"operability: {plain(sc.name)}", executor, elapsed)
    console.print(f"overall {percent(op.operability)}{interval(op.interval, realisations)}, the probability that "
                  f"a {duration:g} s operation succeeds ({count(realisations, 'record')} "
                  "per sea state); written: " + ", ".join(plain(p) for p in paths), highlight=False,
                  soft_wrap=True)
    bypassed = sum(r.controller_bypassed for r in op.results)
    if bypassed:
        err_console.print(plain(f"warning: in {count(bypassed, 'record')} the closed loop's "
                                 "controller was bypassed (the plan's tensions fed forward) on more than "
                                 f"simulation.max_bypassed_share = {sc.simulation.max_bypassed_share:g} of the steps: "
                                 "counted as failures (operability.csv controller_bypassed)"),
                          highlight=False, soft_wrap=True)
