"""The ``latency`` command: how long the controller's step takes on this machine: called from Python and inside a
    compiled loop along the scenario's plan, beside one quadprog solve of the same tension
    problem (the bench extra) (:mod:`marinecdpr.commands.latency`)."""

from __future__ import annotations

import typer

from marinecdpr.cli.common import compiling, console, load, plain, run_errors, spec_of
from marinecdpr.commands.latency import LatencySpec


def latency(
    scenario: str = typer.Argument("paper", help="A scenario file, or a built-in name."),
    calls: int = typer.Option(LatencySpec.default("calls"), "--calls", help="Steps timed from Python and in a "
                              "compiled loop (1 to 10,000,000)."),
    as_json: bool = typer.Option(LatencySpec.default("as_json"), "--json",
                                 help="Print one JSON object instead of a table."),
) -> None:
    """How long the controller's step takes on this machine: called from Python and inside a
    compiled loop along the scenario's plan, beside one quadprog solve of the same tension
    problem (the bench extra)."""
    from marinecdpr.commands import latency as command
    from marinecdpr.report.files import json_text

    spec = spec_of(LatencySpec, calls=calls, as_json=as_json)  # the count, before any work
    sc = load(scenario, None, None)
    est = command.estimate(spec, sc)
    if est.compile_s is not None:
        compiling("the controller's step", est.compile_s)
    with run_errors(scenario):
        result = command.run(spec, sc, estimated=est)
    if spec.as_json:
        print(json_text(result.summary(), indent=None))
        return
    lat = result.latency
    qp = "quadprog not installed (pip install 'marinecdpr[bench]')" if lat.quadprog_p50_us is None else \
        f"{lat.quadprog_p50_us:.2f} us per solve (p50)"
    console.print(f"{plain(lat.scenario)}: {lat.cables} cables, redundancy {lat.redundancy}, {lat.method}; "
                  f"{lat.calls} calls", highlight=False, soft_wrap=True)
    for where in ("python", "compiled"):
        p50, p99, top = (getattr(lat, f"{where}_{q}_us") for q in ("p50", "p99", "max"))
        console.print(f"  step from {'Python' if where == 'python' else 'a compiled loop'}: p50 {p50:.2f} us, "
                      f"p99 {p99:.2f} us, max {top:.1f} us", highlight=False)
    console.print(f"  quadprog: {qp}", highlight=False)
