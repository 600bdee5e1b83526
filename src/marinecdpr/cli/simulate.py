"""The ``simulate`` command: the main job: plan, fly the plan on the virtual prototype, write the report
(:mod:`marinecdpr.commands.simulate`: the options' spec, the scenario as flown and its size, the run)."""

from __future__ import annotations

import time
from pathlib import Path
from typing import Optional

import typer
from rich.table import Table

from marinecdpr.cli.common import (EXIT_INFEASIBLE, compile_notice, console, err_console, fail, fail_bypassed,
    fail_scenario, figures_option, load, output, plain, run_errors, spec_of, styled)
from marinecdpr.cli.progress import progress_bar
from marinecdpr.commands.simulate import SimulateSpec
from marinecdpr.errors import ScenarioError


def simulate(
    scenario: str = typer.Argument("paper", help="A scenario file, or a built-in name."),
    out: Path = typer.Option(Path("out"), "--out", "-o", help="Folder for the CSVs, figures and report."),
    plant: Optional[str] = typer.Option(SimulateSpec.default("plant"), help="mujoco or own (default: the scenario's)."),
    duration: Optional[float] = typer.Option(SimulateSpec.default("duration"), help="Simulate only the first seconds."),
    max_error: Optional[float] = typer.Option(SimulateSpec.default("max_error"),
                                              help="Flag runs whose position or cable-length "
                                              "error passes this, m (default: the scenario's, 1% of the frame)."),
    figures: bool = figures_option("the figures (PNG) and the report's images"),
) -> None:
    """The main job: plan, fly the plan on the virtual prototype, write the report.

    Runs open loop, closed loop and the fixed-base plan on the moving ship; writes
    plan.csv, sim_<run>.csv, figures like the paper's 5-7, the path, summary.json and
    report.html. Exits 5 (the files written) if the closed loop's controller was bypassed on
    more than simulation.max_bypassed_share of its steps.
    """
    from marinecdpr.commands import simulate as command
    from marinecdpr.prototype.simulation import RUNS
    from marinecdpr.report.figures import RUN_TITLES
    from marinecdpr.report.text import beyond_text, error_table, findings

    spec = spec_of(SimulateSpec, plant=plant, duration=duration, max_error=max_error, figures=figures)
    sc = load(scenario, None, None)
    try:
        est = command.estimate(spec, sc)  # the first --duration seconds; too big is one line, exit 2
    except ScenarioError as exc:
        cut = command.duration_cut(sc, spec.duration)  # said before the refusal, as the run was meant
        _warn(() if cut is None else (cut.warning(plain(scenario)),))
        fail_scenario(exc, scenario)
    _warn(est.warnings(plain(scenario)))
    sc = est.flown
    t0 = time.perf_counter()
    with output(out) as folder:
        compile_notice(spec.plant or sc.simulation.plant)
        with progress_bar("simulate", "steps") as bar:
            tasks = {run: bar.add_task(RUN_TITLES[run], total=sc.time.n_steps) for run in RUNS}

            def progress(run: str, done: int, total: int) -> None:
                if run not in tasks:  # after the runs: the error budget's workspace maps, in poses
                    tasks[run] = bar.add_task(RUN_TITLES.get(run, "error budget: workspace maps"), total=total,
                                              unit="poses")
                bar.update(tasks[run], completed=done, total=total)

            with run_errors(scenario):
                result = command.run(spec, sc, estimated=est, progress=progress)
        paths = result.write(folder)
    elapsed = time.perf_counter() - t0

    f = result.figures
    header, rows = error_table(f, sc)
    table = Table(title=f"simulate: {plain(sc.name)} ({f.steps} steps, plant {result.plant}, "
                        f"{elapsed:.1f} s wall time)")
    for i, h in enumerate(header):
        table.add_column(h, justify="left" if i == 0 else "right")
    for row in rows:
        table.add_row(*row)
    console.print(table)
    for sentence in findings(f, sc, warnings=False):
        console.print(plain(sentence), highlight=False)
    for run in f.runs_beyond_error_bound:
        err_console.print(plain(f"warning: {run} leaves its plan beyond the error bound "
                                 f"({beyond_text(f.runs[run].beyond_error_bound)}): see {out / 'report.html'}"),
                          highlight=False, soft_wrap=True)
    for warning in f.warnings:
        err_console.print(plain(f"warning: {warning}"), highlight=False, soft_wrap=True)
    console.print(plain(f"written to {out}/: " + ", ".join(p.name for p in paths)), highlight=False)
    drive = f.drive_verdict()
    if drive is not None:  # as plan says it of the plan: one line, exit 3, the files written
        fail(f"carriage drive: {plain(sc.name)}: {plain(drive)}; see {out / 'summary.json'}", EXIT_INFEASIBLE)
    fail_bypassed(result.bypassed(), sc, out)


def _warn(lines) -> None:
    for line in lines:
        err_console.print(styled("warning:", "bold yellow", line), highlight=False, soft_wrap=True)
