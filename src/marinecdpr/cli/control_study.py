"""The ``control-study`` command: what the ship-motion sensor's latency costs in tracking and tension margin, with the
    ship's motion predicted or not, and the pose from a pose sensor or the winches' encoders;
    and the ship-motion predictor's error against the horizon."""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer

from marinecdpr.cli.common import (compile_notice, console, fail_bypassed, fail_spec, figures_option, load, output, plain,
    run_errors, spec_of)
from marinecdpr.cli.progress import task_progress
from marinecdpr.commands.control_study import ControlStudySpec


def control_study(
    scenario: str = typer.Argument("paper_sea", help="A scenario file, or a built-in name."),
    latencies: str = typer.Option(",".join(f"{x:g}" for x in ControlStudySpec.default("latencies")), "--latencies",
                                  help="Motion sensor latencies, ms, comma-separated."),
    predictions: str = typer.Option(",".join(ControlStudySpec.default("predictions")), "--predictions",
                                    help="How the controller brings the ship's samples to the present: none, "
                                         "kinematic, ar."),
    pose_from: str = typer.Option(",".join(ControlStudySpec.default("pose_from")), "--pose-from",
                                  help="Pose sources: sensor, encoders."),
    rate: float = typer.Option(ControlStudySpec.default("rate"), "--rate",
                               help="The motion sensor's samples per second, Hz."),
    encoder_resolution: Optional[float] = typer.Option(ControlStudySpec.default("encoder_resolution"),
                                                       "--encoder-resolution",
                                                       help="The encoders' length step, m (default: the scenario's)."),
    duration: float = typer.Option(ControlStudySpec.default("duration"), "--duration", help="Each run's length, s."),
    settle: Optional[float] = typer.Option(ControlStudySpec.default("settle"), "--settle",
                                           help="Errors count from this time on, s (default: the predictor's "
                                                "warm-up and a second)."),
    plant: str = typer.Option(ControlStudySpec.default("plant"), "--plant", help="own or mujoco."),
    out: Path = typer.Option(Path("out"), "--out", "-o", help="Folder for control_study.csv/.png, prediction.csv, "
                                                              "summary.json."),
    figures: bool = figures_option("control_study.png"),
) -> None:
    """What the ship-motion sensor's latency costs in tracking and tension margin, with the
    ship's motion predicted or not, and the pose from a pose sensor or the winches' encoders;
    and the ship-motion predictor's error against the horizon."""
    from marinecdpr.commands import control_study as command
    from marinecdpr.commands.base import SpecError

    spec = spec_of(ControlStudySpec, latencies=latencies, predictions=predictions, pose_from=pose_from, rate=rate,
                 encoder_resolution=encoder_resolution, duration=duration, settle=settle, plant=plant,
                 figures=figures)
    sc = load(scenario, None, None)
    try:  # before any work: what the scenario cannot take, and runs the machine cannot hold or finish
        est = command.estimate(spec, sc)
    except SpecError as exc:
        fail_spec(exc)
    with output(out) as folder:
        compile_notice(spec.plant)
        with run_errors(scenario), task_progress("closed-loop runs", spec.n_runs, "runs") as bar:
            result = command.run(spec, sc, estimated=est, progress=bar)
        _, paths = result.write(folder)
    name, settle = est.flown.name, result.settle
    console.print(f"{plain(name)}: MRU {spec.rate:g} Hz, judged from {settle:g} s of {spec.duration:g} s runs",
                  highlight=False)
    for r in result.study.runs:
        console.print(f"  latency {1e3 * r.latency_s:5.1f} ms, {r.prediction:9s}, pose from {r.pose_from:8s}: "
                      f"RMS error {r.rms_error_m:.3g} m, max {r.max_error_m:.3g} m, headroom {r.headroom_N:.4g} N, "
                      f"slack margin {r.slack_margin_N:.4g} N"
                      + (f"; controller BYPASSED at {r.fallbacks} steps" if r.controller_verdict == "bypassed" else ""),
                      highlight=False, soft_wrap=True)
    console.print(plain(f"written to {out}/: {', '.join(p.name for p in paths)}"), highlight=False, soft_wrap=True)
    fail_bypassed([(f"latency {1e3 * r.latency_s:g} ms, prediction {r.prediction}, pose from {r.pose_from}",
                     r.fallbacks, result.study.steps) for r in result.study.bypassed], est.flown, out)
