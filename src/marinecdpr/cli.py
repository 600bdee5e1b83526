"""The ``marinecdpr`` command: parses arguments, calls the library, prints.

Exit codes: 0 success; 2 bad input (a scenario or an option); 3 the cables cannot
hold the platform somewhere on the plan (``plan`` still writes its outputs, complete);
4 a simulation diverged.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path
from typing import Optional

import typer
from rich.console import Console
from rich.markup import escape
from rich.table import Table

from .errors import InfeasibleError, ScenarioError, SimulationDivergedError
from .memory import keep_freed_memory
from .scenario import TENSION_METHODS, builtin_scenarios, load_scenario

EXIT_BAD_INPUT = 2
EXIT_INFEASIBLE = 3
EXIT_DIVERGED = 4

app = typer.Typer(
    add_completion=False,
    no_args_is_help=True,
    help="Cable-driven parallel robots on a moving ship.",
    pretty_exceptions_show_locals=False,
)
console = Console()
err_console = Console(stderr=True)


def _fail(message: str, code: int = EXIT_BAD_INPUT) -> None:
    err_console.print(f"[bold red]error:[/] {escape(message)}", highlight=False, soft_wrap=True)
    raise typer.Exit(code)


def _fail_scenario(exc: ScenarioError, scenario: str) -> None:
    """A scenario's error, prefixed with the scenario given when the error names no file."""
    _fail(str(exc) if exc.source else f"{scenario}: {exc}")


def _out_dir(out: Path) -> Path:
    if out.exists() and not out.is_dir():
        _fail(f"--out {out}: exists and is not a folder")
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        _fail(f"--out {out}: cannot create the folder ({exc.strerror})")
    return out


@app.command()
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
        False, help="Exit 0 even where the cables cannot hold the platform."
    ),
) -> None:
    """Plan cable tensions along the scenario's trajectory on its moving ship."""
    from .planning import plan as make_plan
    from .reports import plot_tensions, write_plan_csv

    if method is not None and method not in TENSION_METHODS:
        _fail(f"--method {method}: expected one of {', '.join(TENSION_METHODS)}")
    try:
        sc = load_scenario(scenario)
        t0 = time.perf_counter()
        result = make_plan(sc, method=method, base_model="fixed" if fixed_base else None)
        elapsed = time.perf_counter() - t0
    except ScenarioError as exc:
        _fail_scenario(exc, scenario)
    folder = _out_dir(out)
    csv_path = write_plan_csv(result, sc, folder / "plan.csv")
    fig_path = plot_tensions(result, sc, folder / "tensions.png")

    table = Table(title=f"plan: {sc.name} ({result.method}, {result.base_model} base)")
    table.add_column("quantity")
    table.add_column("value", justify="right")
    table.add_row("steps", f"{result.n_steps} ({elapsed * 1e3:.1f} ms)")
    table.add_row("feasible steps", f"{int(result.feasible.sum())} of {result.n_steps}")
    table.add_row("eq. 18 tensions (N)", f"{_nanmin(result.tensions_pinv):.2f} .. {_nanmax(result.tensions_pinv):.2f}")
    table.add_row("planned tensions (N)", f"{_nanmin(result.tensions):.2f} .. {_nanmax(result.tensions):.2f}")
    table.add_row("written", f"{csv_path}\n{fig_path}")
    console.print(table)
    problem = result.infeasibility()
    if problem is not None:
        err_console.print(f"[bold yellow]infeasible:[/] {escape(sc.name)}: {escape(problem)}", highlight=False,
                          soft_wrap=True)
        if not allow_infeasible:
            raise typer.Exit(EXIT_INFEASIBLE)


def _nanmin(a) -> float:
    import numpy as np

    return float(np.nanmin(a)) if np.isfinite(a).any() else float("nan")


def _nanmax(a) -> float:
    import numpy as np

    return float(np.nanmax(a)) if np.isfinite(a).any() else float("nan")


@app.command()
def simulate(
    scenario: str = typer.Argument("paper", help="A scenario file, or a built-in name."),
    out: Path = typer.Option(Path("out"), "--out", "-o", help="Folder for the CSVs, figures and report."),
    plant: Optional[str] = typer.Option(None, help="mujoco or own (default: the scenario's)."),
    duration: Optional[float] = typer.Option(None, min=0.0, help="Simulate only the first seconds."),
) -> None:
    """The main job: plan, fly the plan on the virtual prototype, write the report.

    Runs open loop, closed loop and the fixed-base plan on the moving ship; writes
    plan.csv, sim_<run>.csv, figures like the paper's 5-7, summary.json and report.html.
    """
    from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

    from .analysis import PAPER_REPORTED, virtual_prototype
    from .reports import RUN_TITLES, write_virtual_prototype
    from .simulation import RUNS

    if plant is not None and plant not in ("mujoco", "own"):
        _fail(f"--plant {plant}: expected mujoco or own")
    try:
        sc = load_scenario(scenario)
        if duration is not None:
            sc = sc.with_changes(time={"step_s": sc.time.step_s, "duration_s": min(duration, sc.time.duration_s)})
    except ScenarioError as exc:
        _fail_scenario(exc, scenario)
    t0 = time.perf_counter()
    with Progress(TextColumn("{task.description:<34}"), BarColumn(), TextColumn("{task.percentage:>3.0f}%"),
                  TimeElapsedColumn(), console=err_console, transient=False,
                  disable=not err_console.is_terminal) as bar:
        tasks = {run: bar.add_task(RUN_TITLES[run], total=sc.time.n_steps) for run in RUNS}

        def progress(run: str, done: int, total: int) -> None:
            bar.update(tasks[run], completed=done, total=total)

        try:
            vp = virtual_prototype(sc, plant=plant, progress=progress)
        except ScenarioError as exc:
            _fail_scenario(exc, scenario)
        except InfeasibleError as exc:
            _fail(str(exc), EXIT_INFEASIBLE)
        except SimulationDivergedError as exc:
            _fail(str(exc), EXIT_DIVERGED)
    elapsed = time.perf_counter() - t0
    paths = write_virtual_prototype(vp, _out_dir(out))

    s = vp.summary
    table = Table(title=f"simulate: {sc.name} ({s['steps']} steps, {elapsed:.1f} s, "
                        f"plant {vp.results['open_loop'].plant})")
    table.add_column("max |error|")
    table.add_column("paper", justify="right")
    for run in RUNS:
        table.add_column(RUN_TITLES[run], justify="right")
    for label, key, scale, unit in (("x", "max_abs_error_x_m", 1e3, "mm"), ("z", "max_abs_error_z_m", 1e3, "mm"),
                                    ("angle", "max_abs_error_theta_deg", 1.0, "deg")):
        table.add_row(f"{label} ({unit})", f"{PAPER_REPORTED[key] * scale:.3g}",
                      *(f"{s[run][key] * scale:.3g}" for run in RUNS))
    table.add_row("cable length (mm)", "150",
                  *(f"{max(s[run]['max_abs_cable_length_error_m']) * 1e3:.3g}" for run in RUNS))
    console.print(table)
    console.print(f"written to {out}/: " + ", ".join(p.name for p in paths), highlight=False)


def _progress_bar(label: str):
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    return Progress(TextColumn(f"{label:<16}"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn(),
                    console=err_console, disable=not err_console.is_terminal)


@app.command()
def workspace(
    scenario: str = typer.Argument("paper", help="A scenario file, or a built-in name."),
    out: Path = typer.Option(Path("out"), "--out", "-o", help="Folder for workspace.csv and workspace.png."),
    axes: str = typer.Option("xz", help="Grid plane: two of x, y, z."),
    points: str = typer.Option("30x20", help="Grid points along the two axes, e.g. 30x20."),
    fixed: Optional[float] = typer.Option(None, help="The third coordinate, m (default: mid-frame)."),
    duration: Optional[float] = typer.Option(None, min=0.0, help="Seconds of ship motion per pose."),
    step: Optional[float] = typer.Option(None, min=0.0, help="Time step, s."),
) -> None:
    """Map where on the frame the platform can be held while the ship moves."""
    from .reports import write_workspace
    from .workspace import workspace_map

    try:
        n = tuple(int(k) for k in points.lower().split("x"))
        assert len(n) == 2 and min(n) > 0
    except (ValueError, AssertionError):
        _fail(f"--points {points}: expected two positive integers like 30x20")
    if len(axes) != 2 or any(a not in "xyz" for a in axes) or axes[0] == axes[1]:
        _fail(f"--axes {axes}: expected two different letters of x, y, z")
    sc = _load(scenario, duration, step)
    with _progress_bar("workspace") as bar:
        task = bar.add_task("", total=n[0] * n[1])
        try:
            ws = workspace_map(sc, axes=(axes[0], axes[1]), n=n, fixed_m=fixed,
                               progress=lambda d, tot: bar.update(task, completed=d, total=tot))
        except ScenarioError as exc:
            _fail_scenario(exc, scenario)
    paths = write_workspace(ws, sc, _out_dir(out))
    import numpy as np

    inside = np.isfinite(ws.fraction_feasible)
    always = int((ws.fraction_feasible[inside] == 1.0).sum())
    console.print(f"{sc.name}: {always} of {int(inside.sum())} poses feasible throughout "
                  f"({ws.n_steps} steps each); written: " + ", ".join(str(p) for p in paths), highlight=False)


@app.command()
def operability(
    scenario: str = typer.Argument("paper_sea", help="A scenario with a sea_state base motion."),
    scatter: Optional[Path] = typer.Option(None, help="Scatter diagram CSV (hs_m,tp_s,probability); "
                                                      "default: the package's illustrative one."),
    headings: str = typer.Option("180", help="Wave headings, deg, comma-separated."),
    margin: float = typer.Option(0.0, min=0.0, help="Tension margin to the limits a workable sea keeps, N."),
    duration: float = typer.Option(1200.0, min=0.0, help="Record length per sea state, s."),
    step: float = typer.Option(0.02, min=0.0, help="Time step, s."),
    out: Path = typer.Option(Path("out"), "--out", "-o", help="Folder for operability.csv/.json/.png."),
    serial: bool = typer.Option(False, "--serial", help="Run the cells in this process, not on Dask."),
    workers: int = typer.Option(2, min=1, help="Local Dask workers."),
    scheduler: Optional[str] = typer.Option(None, help="Address of a running Dask scheduler."),
    max_error: Optional[float] = typer.Option(None, min=0.0, help="Also fly the closed loop in each "
                                              "sea state and require its position error below this, m."),
    workspace_grid: Optional[str] = typer.Option(None, "--workspace", help="Judge a grid of held poses "
                                                 "(e.g. 12x8) instead of the trajectory."),
    min_area: float = typer.Option(1.0, min=0.0, max=1.0, help="With --workspace: share of the frame's "
                                   "poses that must stay feasible."),
) -> None:
    """In which sea states, over a scatter diagram, can the robot work?"""
    from importlib import resources

    from .operability import operability as run, read_scatter_csv
    from .reports import write_operability

    try:
        heads = tuple(float(h) for h in headings.split(","))
    except ValueError:
        _fail(f"--headings {headings}: expected numbers separated by commas, e.g. 180,150")
    grid = None
    if workspace_grid is not None:
        try:
            grid = tuple(int(k) for k in workspace_grid.lower().split("x"))
            assert len(grid) == 2 and min(grid) > 0
        except (ValueError, AssertionError):
            _fail(f"--workspace {workspace_grid}: expected two positive integers like 12x8")
    sc = _load(scenario, None, None)
    try:
        path = scatter or Path(str(resources.files("marinecdpr") / "data" / "scatter_illustrative.csv"))
        diagram = read_scatter_csv(path)
    except ScenarioError as exc:
        _fail(str(exc))
    n_cells = int((diagram.probability > 0).sum()) * len(heads)
    t0 = time.perf_counter()
    with _progress_bar("sea states") as bar:
        task = bar.add_task("", total=n_cells)
        try:
            op = run(sc, diagram, headings_deg=heads, margin_N=margin, duration_s=duration, step_s=step,
                     executor="serial" if serial else "dask", scheduler=scheduler, workers=workers,
                     max_error_m=max_error, workspace=grid, min_area=min_area,
                     progress=lambda d, tot: bar.update(task, completed=d, total=tot))
        except ScenarioError as exc:
            _fail_scenario(exc, scenario)
    elapsed = time.perf_counter() - t0
    paths = write_operability(op, sc, _out_dir(out))
    table = Table(title=f"operability: {sc.name} ({len(op.results)} sea states, {elapsed:.1f} s)")
    table.add_column("heading (deg)")
    table.add_column("operable", justify="right")
    table.add_column("limiting Hs (m) for Tp = " + ", ".join(f"{tp:g}" for tp in diagram.tp) + " s")
    for h in heads:
        lims = ", ".join("-" if v != v else f"{v:g}" for v in op.limiting_hs[h])
        table.add_row(f"{h:g}", f"{100 * op.per_heading[h]:.1f} %", lims)
    console.print(table)
    console.print(f"overall {100 * op.operability:.1f} %; written: " + ", ".join(str(p) for p in paths),
                  highlight=False)


def _load(scenario: str, duration: float | None, step: float | None):
    try:
        sc = load_scenario(scenario)
        if duration is not None or step is not None:
            sc = sc.with_changes(time={"step_s": step or sc.time.step_s,
                                       "duration_s": duration or sc.time.duration_s})
        return sc
    except ScenarioError as exc:
        _fail_scenario(exc, scenario)


@app.command()
def check(scenario: str = typer.Argument(..., help="A scenario file, or a built-in name.")) -> None:
    """Validate a scenario file (keys, units, physics, trajectory inside the frame)."""
    from .planning import check_trajectory

    try:
        sc = load_scenario(scenario)
        check_trajectory(sc)
    except ScenarioError as exc:
        _fail_scenario(exc, scenario)
    r = sc.robot
    console.print(
        f"{scenario}: ok: '{sc.name}', {r.dofs} robot, {r.n_cables} cables, {r.mass_kg:g} kg; "
        f"base motion {sc.base_motion.type}; trajectory {sc.trajectory.type}; "
        f"{sc.time.n_steps} steps of {sc.time.step_s:g} s; method {sc.planning.method}",
        highlight=False,
    )


@app.command()
def scenarios() -> None:
    """List the built-in scenarios."""
    for name in builtin_scenarios():
        console.print(name, highlight=False)


def main() -> None:
    """Console entry point."""
    keep_freed_memory()
    app()


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
