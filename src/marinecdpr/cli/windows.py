"""The ``windows`` command: weather windows in a series of sea states: when an operation of --duration-h fits,
    the expected wait before it can start, and the probability it is done within days."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Optional

import typer

from marinecdpr.cli.common import console, count, fail, number, output, plain
from marinecdpr.errors import ScenarioError


def windows(
    series: Optional[Path] = typer.Argument(None, help="Sea-state series CSV (time_h,hs_m,tp_s); default: the "
                                            "package's illustrative, synthetic one."),
    duration_h: float = typer.Option(..., "--duration-h", help="The operation's duration, h."),
    hs_limit: Optional[float] = typer.Option(None, help="A constant design Hs limit, m."),
    operability_json: Optional[Path] = typer.Option(None, "--operability", help="An operability.json: its "
                                                    "limiting Hs per Tp is the design limit."),
    heading: float = typer.Option(180.0, help="With --operability: the heading whose limits apply, deg."),
    alpha: float = typer.Option(1.0, help="DNV-ST-N001's alpha factor for the operation's duration and forecast "
                                "(operational limit = alpha x design limit)."),
    days: str = typer.Option("1,3,7", help="Report the probability of finishing within these many days."),
    out: Path = typer.Option(Path("out"), "--out", "-o", help="Folder for windows.csv, summary.json, windows.png."),
) -> None:
    """Weather windows in a series of sea states: when an operation of --duration-h fits,
    the expected wait before it can start, and the probability it is done within days."""
    from importlib import resources

    from marinecdpr.report.writers import write_windows
    from marinecdpr.studies.weather import (limit_from_operability, read_operability_json, read_sea_state_series,
                                            weather_windows)

    number("--duration-h", duration_h)
    if (hs_limit is None) == (operability_json is None):
        fail("give one design limit: --hs-limit H or --operability FILE.json")
    number("--hs-limit", hs_limit)
    number("--heading", heading, finite_only=True)
    if not (math.isfinite(alpha) and 0.0 < alpha <= 1.0):
        fail(f"--alpha {alpha:g}: expected a factor in (0, 1]")
    try:
        day_list = [float(d) for d in days.split(",")]
    except ValueError:
        day_list = []
    if not day_list or not all(math.isfinite(d) and d > 0 for d in day_list):
        fail(f"--days {days}: expected positive numbers separated by commas, e.g. 1,3,7")
    try:
        path = series or Path(str(resources.files("marinecdpr") / "data" / "sea_states_illustrative.csv"))
        sea = read_sea_state_series(path)
        table = None
        if operability_json is not None:
            if operability_json.is_dir():
                raise ScenarioError("a folder, not a file; expected an operability.json", source=str(operability_json))
            try:
                table = limit_from_operability(read_operability_json(operability_json), heading)
            except ScenarioError as exc:
                raise ScenarioError(exc.detail, source=str(operability_json), key=exc.key) from None
    except ScenarioError as exc:
        fail(str(exc))
    w = weather_windows(sea, duration_h=duration_h, alpha=alpha, hs_limit_m=hs_limit, limit_table=table)
    limit = (f"Hs {hs_limit:g} m" if hs_limit is not None else
             f"limiting Hs per Tp of {operability_json} at {heading:g} deg")
    with output(out) as folder:
        summary, paths = write_windows(sea, w, folder, series_name=str(path), design_limit=limit,
                                       days=day_list)
    wait = "never within the series" if w.mean_wait_h != w.mean_wait_h else f"{w.mean_wait_h:.1f} h on average"
    finish = summary["finish_within_days_probability"]
    console.print(plain(f"{count(len(w.windows), 'window')}, {summary['windows_long_enough']} of them {duration_h:g} h or "
                         f"longer; wait before the operation can start: {wait} (it can start from "
                         f"{100 * w.can_start:.1f} % of the start times); done within "
                         + ", ".join(f"{count(d, 'day')}: {100 * p:.1f} %" for d, p in finish.items())
                         + f"; written to {out}/: {', '.join(p.name for p in paths)}"), highlight=False,
                  soft_wrap=True)
