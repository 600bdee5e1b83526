"""The sea-state studies' options (headings, executor), their scatter diagram and their table."""

from __future__ import annotations

import math
from pathlib import Path

from rich.table import Table

from marinecdpr.cli.common import console, count, err_console, fail, headings_option, interval, percent, plain
from marinecdpr.errors import ScenarioError


def sea_study_options(headings: str, serial: bool, workers: int | None, scheduler: str | None) -> tuple[float, ...]:
    """A sea-state study's headings (deg) from ``--headings``, its executor options checked
    (``--serial`` alone; a ``--scheduler`` that answers)."""
    from marinecdpr.studies.executor import Executor, ExecutorError

    try:
        Executor.check(serial=serial, workers=workers, scheduler=scheduler)
        heads = headings_option(headings, "180,150")
        if scheduler:
            Executor.at(scheduler)
    except ExecutorError as exc:
        fail(str(exc))
    return heads


def sea_executor(serial: bool, workers: int | None, scheduler: str | None, steps: int):
    """What runs a sea-state study's cells (:class:`~marinecdpr.studies.executor.Executor`)
    from the options and its size; a note when Dask would help but is not installed."""
    from marinecdpr.studies.executor import Executor, ExecutorError

    try:
        executor = Executor.choose(serial=serial, workers=workers, scheduler=scheduler, steps=steps)
    except ExecutorError as exc:
        fail(str(exc))
    if executor.note:
        err_console.print(f"note: {executor.note}", highlight=False, soft_wrap=True)
    return executor


def scatter_diagram(path: Path | None):
    """The scatter diagram of ``--scatter`` (default: the package's illustrative one)."""
    from importlib import resources

    from marinecdpr.studies.operability import read_scatter_csv

    try:
        return read_scatter_csv(path or Path(str(resources.files("marinecdpr") / "data" / "scatter_illustrative.csv")))
    except ScenarioError as exc:
        fail(str(exc))


def print_sea_table(op, title: str, executor, elapsed: float) -> None:
    """A sea-state study's table: per heading the workable share and the limiting Hs per Tp,
    and what ran it (``executor``)."""
    ran = executor.describe()
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
