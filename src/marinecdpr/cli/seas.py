"""The sea-state studies' options (headings, executor), their scatter diagram and their table."""

from __future__ import annotations

import math
import os
from pathlib import Path

from rich.table import Table

from marinecdpr.cli.common import console, count, err_console, fail, headings_option, interval, percent, plain
from marinecdpr.errors import ScenarioError


WORKERS_PER_CORE = 4
"""Most local Dask workers per core a sea-state study starts."""


def sea_study_options(headings: str, serial: bool, workers: int | None, scheduler: str | None) -> tuple[float, ...]:
    """A sea-state study's headings (deg) from ``--headings``, its executor options checked
    (``--serial`` alone; a ``--scheduler`` that answers)."""
    from marinecdpr.studies.operability import check_scheduler

    if serial and (workers is not None or scheduler):
        fail("--serial cannot go with --workers or --scheduler (they run the sea states on Dask)")
    cores = os.cpu_count() or 1
    if workers is not None and workers > WORKERS_PER_CORE * cores:
        fail(f"--workers {workers}: more than {WORKERS_PER_CORE} per core of this machine's {cores} gains nothing "
              f"(each is a process of its own); use at most {WORKERS_PER_CORE * cores}")
    heads = headings_option(headings, "180,150")
    if scheduler:
        try:
            check_scheduler(scheduler)
        except ScenarioError as exc:
            fail(str(exc))
    return heads


def sea_executor(serial: bool, workers: int | None, scheduler: str | None, steps: int) -> str:
    """What runs a sea-state study's cells ("serial" or "dask") from the options and its size;
    a note when Dask would help but is not installed."""
    from marinecdpr.studies.operability import choose_executor, dask_installed

    asked = "serial" if serial else "dask" if (workers is not None or scheduler) else "auto"
    executor, why = choose_executor(asked, steps, scheduler=scheduler)
    if why == "no dask":
        err_console.print("note: running the sea states serially: Dask is not installed "
                          "(pip install 'marinecdpr[dask]' to run them in parallel)", highlight=False,
                          soft_wrap=True)
    elif executor == "dask" and not dask_installed():
        fail("--workers and --scheduler run on Dask, which is not installed: pip install 'marinecdpr[dask]' "
              "(or leave them out to run serially)")
    return executor


def scatter_diagram(path: Path | None):
    """The scatter diagram of ``--scatter`` (default: the package's illustrative one)."""
    from importlib import resources

    from marinecdpr.studies.operability import read_scatter_csv

    try:
        return read_scatter_csv(path or Path(str(resources.files("marinecdpr") / "data" / "scatter_illustrative.csv")))
    except ScenarioError as exc:
        fail(str(exc))


def print_sea_table(op, title: str, scheduler: str | None, n_workers: int, elapsed: float) -> None:
    """A sea-state study's table: per heading the workable share and the limiting Hs per Tp."""
    ran = ("serial" if op.executor == "serial" else f"Dask at {scheduler}" if scheduler
           else f"Dask, {count(n_workers, 'worker')}")
    table = Table(title=title, caption=f"{count(len(op.results), 'sea state')}, {plain(ran)}, {elapsed:.1f} s")
    table.add_column("heading (deg)")
    table.add_column("operable", justify="right")
    table.add_column("Tp (s)", justify="right")
    table.add_column("limiting Hs (m)")
    for h in op.headings_deg:
        first = True
        for tp, v in zip(op.scatter.tp, op.limiting_hs[h]):
            if v != v:   # no sea state of this Tp
                continue
            band = interval((op.per_heading_interval or {}).get(h, (0.0, 1.0)), op.results[0].realisations)
            table.add_row(f"{h:g}" if first else "", percent(op.per_heading[h]) + band if first else "",
                          f"{tp:g}", "none within the diagram" if math.isinf(v) else f"{v:g}")
            first = False
    console.print(table)
    console.print("limiting Hs: the largest Hs up to which every sea state of that Tp is workable in every "
                  "record (0: not even the smallest; none within the diagram: all are)", highlight=False)
