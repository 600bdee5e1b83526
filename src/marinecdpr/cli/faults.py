"""The ``faults`` command: what each single fault does to the robot at the job's hardest
moments. Options -> :class:`~marinecdpr.commands.faults.FaultsSpec`; the estimate, the run and
its files are :mod:`marinecdpr.commands.faults`'s."""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer

from marinecdpr.cli.common import (compile_notice, console, fail_spec, figures_option, load, output, plain, run_errors,
    spec_of)
from marinecdpr.cli.progress import task_progress
from marinecdpr.commands.faults import KINDS, FaultsSpec

_default = FaultsSpec.default


def _list(v) -> Optional[str]:
    return None if v is None else ",".join(f"{x:g}" if isinstance(x, float) else str(x) for x in v)


def faults(
    scenario: str = typer.Argument("paper_clean", help="A scenario file, or a built-in name."),
    kinds: str = typer.Option(",".join(next(k for k, v in KINDS.items() if v == kind) for kind in _default("kinds")),
                              "--kinds", help="Faults flown, comma-separated: " + ", ".join(KINDS) + "."),
    cables: Optional[str] = typer.Option(_list(_default("cables")), "--cables",
                                         help="Cables struck, from 1, comma-separated (default: every cable)."),
    at: Optional[str] = typer.Option(_list(_default("at")), "--at", help="When each fault strikes, s, "
                                     "comma-separated (default: the plan's highest tension and highest speed)."),
    after: float = typer.Option(_default("after"), "--after", help="Flown after each fault, s."),
    duration: Optional[float] = typer.Option(_default("duration"), "--duration",
                                             help="The job's first seconds considered, s (default: all of it)."),
    plant: Optional[str] = typer.Option(_default("plant"), "--plant", help="mujoco or own (default: the "
                                                                           "scenario's)."),
    hs: Optional[str] = typer.Option(_list(_default("hs")), "--hs", help="Significant wave heights, m, "
                                     "comma-separated: one sea state each (default: the scenario's sea)."),
    tp: Optional[str] = typer.Option(_list(_default("tp")), "--tp", help="Peak periods, s: one, or one a sea "
                                                                         "state."),
    heading: Optional[str] = typer.Option(_list(_default("heading")), "--heading", help="Wave headings, deg: "
                                          "one, or one a sea state."),
    sensor_mode: str = typer.Option(_default("sensor_mode"), "--sensor-mode", help="How a failing sensor fails: "
                                    "freeze, drift, dropout, non_finite."),
    drift: float = typer.Option(_default("drift"), "--drift", help="A drifting sensor's rate, N/s or m/s."),
    brake_delay: Optional[float] = typer.Option(_default("brake_delay"), "--brake-delay",
                                                help="A winch fault's brake delay, s."),
    deadline_steps: int = typer.Option(_default("deadline_steps"), "--deadline-steps",
                                       help="Exchanges a late controller's commands are held."),
    out: Path = typer.Option(Path("out"), "--out", "-o", help="Folder for faults.csv/.png, summary.json, "
                                                              "report.html."),
    figures: bool = figures_option("faults.png and the report's image"),
) -> None:
    """What each single fault does at the job's hardest moments: a cable that snaps, a
    winch's brake or motor, a sensor, the controller's deadline, each flown closed loop with
    the controller's watch; a verdict per fault (safe, or why not)."""
    from marinecdpr.commands import faults as command
    from marinecdpr.commands.base import SpecError

    spec = spec_of(FaultsSpec, kinds=kinds, cables=cables, at=at, after=after, duration=duration, plant=plant, hs=hs,
                   tp=tp, heading=heading, sensor_mode=sensor_mode, drift=drift, brake_delay=brake_delay,
                   deadline_steps=deadline_steps, figures=figures)
    sc = load(scenario, None, None)
    with run_errors(scenario):
        try:  # before any flight: the options against the scenario, the job planned, the moments chosen
            est = command.estimate(spec, sc)
        except SpecError as exc:
            fail_spec(exc)
    with output(out) as folder:
        compile_notice(est.plant)
        with run_errors(scenario), task_progress("faults", est.n_cases, "faults") as bar:
            result = command.run(spec, sc, estimated=est, progress=bar)
        paths = result.write(folder)
    study = result.study
    console.print(plain(f"faults: {sc.name}, {sc.robot.n_cables} cables, {study.plant}, {study.after_s:g} s "
                        "after each fault"), highlight=False, soft_wrap=True)
    for r in study.rows:
        det = f"detected after {r.detection_delay_s:.3g} s" if r.detected else "not detected"
        sea = f", Hs {r.hs_m:g} m Tp {r.tp_s:g} s {r.heading_deg:g} deg" if len(study.seas) > 1 else ""
        console.print(plain(f"  {r.kind}" + (f" cable {r.cable}" if r.cable else "") + f" at {r.at_s:g} s "
                            f"({r.moment}{sea}): {det}, {r.reaction}; {r.verdict}"), highlight=False, soft_wrap=True)
    console.print(plain(f"{len(study.rows) - len(study.unsafe)} of {len(study.rows)} safe; written to {out}/: "
                        + ", ".join(p.name for p in paths)), highlight=False, soft_wrap=True)
