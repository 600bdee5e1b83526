"""The ``windows`` command: weather windows in a series of sea states: when an operation of --duration-h fits,
    the expected wait before it can start, and the probability it is done within days.

Options to :class:`~marinecdpr.commands.windows.WindowsSpec`, the work to
:mod:`marinecdpr.commands.windows`, the result to a line."""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer

from marinecdpr.cli.common import console, count, fail, figures_option, output, plain, spec_of
from marinecdpr.commands.windows import WindowsSpec
from marinecdpr.errors import ScenarioError


def windows(
    series: Optional[Path] = typer.Argument(None, help="Sea-state series CSV (time_h,hs_m,tp_s, optionally "
                                            "wind_m_s); default: the package's illustrative, synthetic one."),
    duration_h: float = typer.Option(..., "--duration-h", help="The operation's duration, h."),
    hs_limit: Optional[float] = typer.Option(WindowsSpec.default("hs_limit"), help="A constant design Hs limit, m."),
    operability: Optional[Path] = typer.Option(WindowsSpec.default("operability"), "--operability", help="An "
                                               "operability.json: its limiting Hs per Tp is the design limit."),
    heading: float = typer.Option(WindowsSpec.default("heading"), help="With --operability: the heading whose limits "
                                  "apply, deg."),
    alpha: float = typer.Option(WindowsSpec.default("alpha"), help="DNV-ST-N001's alpha factor for the operation's "
                                "duration and forecast (operational limit = alpha x design limit)."),
    days: str = typer.Option(",".join(f"{d:g}" for d in WindowsSpec.default("days")),
                             help="Report the probability of finishing within these many days."),
    wind_limit: Optional[float] = typer.Option(WindowsSpec.default("wind_limit"), help="A constant operational limit "
                                               "of the mean wind at 10 m, m/s: a sample is workable when its wind "
                                               "(the series' wind_m_s) is within it too."),
    out: Path = typer.Option(Path("out"), "--out", "-o", help="Folder for windows.csv, summary.json, windows.png."),
    figures: bool = figures_option("windows.png"),
) -> None:
    """Weather windows in a series of sea states: when an operation of --duration-h fits,
    the expected wait before it can start, and the probability it is done within days."""
    from marinecdpr.commands import windows as command

    spec = spec_of(WindowsSpec, duration_h=duration_h, hs_limit=hs_limit, operability=operability, heading=heading,
                   alpha=alpha, days=days, wind_limit=wind_limit, figures=figures)
    try:  # the series and the operability.json read and checked: one line naming the file
        est = command.estimate(spec, series)
    except ScenarioError as exc:
        fail(str(exc))
    result = command.run(spec, estimated=est)
    with output(out) as folder:
        paths = result.write(folder)
    w = result.windows
    wait = "never within the series" if w.mean_wait_h != w.mean_wait_h else f"{w.mean_wait_h:.1f} h on average"
    finish = {f"{d:g}": w.finish_probability(d) for d in spec.days}
    console.print(plain(f"{count(len(w.windows), 'window')}{_judged(result)}, {w.long_enough} of them "
                        f"{spec.duration_h:g} h or longer; wait before the operation can start: {wait} (it can "
                        f"start from {100 * w.can_start:.1f} % of the start times); done within "
                        + ", ".join(f"{count(d, 'day')}: {100 * p:.1f} %" for d, p in finish.items())
                        + f"; written to {out}/: {', '.join(p.name for p in paths)}"), highlight=False,
                  soft_wrap=True)


def _judged(result) -> str:
    """What the windows were judged by, where the series has a wind: by Hs and the wind (with
    the workable share and the share by Hs alone), or by Hs alone (no --wind-limit)."""
    w, sea = result.windows, result.series
    if w.wind_limit_m_s is not None:
        return (f" with Hs within its limit and the wind within {w.wind_limit_m_s:g} m/s (workable "
                f"{100 * w.workable_share:.1f} % of the time, {100 * w.hs_workable_share:.1f} % by Hs alone)")
    if sea.wind_m_s is not None:
        return " by Hs alone (the series' wind_m_s is read, not judged: no --wind-limit)"
    return ""
