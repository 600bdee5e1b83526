"""The sea-state studies' table: per heading the workable share and the limiting Hs per Tp."""

from __future__ import annotations

import math

from rich.table import Table

from marinecdpr.cli.common import console, count, interval, percent, plain


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
