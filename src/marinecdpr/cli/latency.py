"""The ``latency`` command: how long the controller's step takes on this machine: called from Python and inside a
    compiled loop along the scenario's plan, beside one quadprog solve of the same tension
    problem (the bench extra)."""

from __future__ import annotations

import typer

from marinecdpr.cli.common import compiling, console, fail, load, plain, run_errors
from marinecdpr.errors import ScenarioError


def latency(
    scenario: str = typer.Argument("paper", help="A scenario file, or a built-in name."),
    calls: int = typer.Option(20000, "--calls", help="Steps timed from Python and in a compiled loop (1 to "
                              "10,000,000)."),
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object instead of a table."),
) -> None:
    """How long the controller's step takes on this machine: called from Python and inside a
    compiled loop along the scenario's plan, beside one quadprog solve of the same tension
    problem (the bench extra)."""
    import dataclasses

    from marinecdpr.planning.budget import check_latency_calls
    from marinecdpr.report.files import json_text
    from marinecdpr.studies.latency import LATENCY_COMPILE_S, controller_latency, latency_kernels_cached

    try:
        check_latency_calls(calls)  # before any work
    except ScenarioError as exc:
        fail(str(exc))
    sc = load(scenario, None, None)
    if not latency_kernels_cached():
        compiling("the controller's step", LATENCY_COMPILE_S)
    with run_errors(scenario):
        lat = controller_latency(sc, calls=calls)
    if as_json:
        print(json_text(dataclasses.asdict(lat), indent=None))
        return
    qp = "quadprog not installed (pip install 'marinecdpr[bench]')" if lat.quadprog_p50_us is None else \
        f"{lat.quadprog_p50_us:.2f} us per solve (p50)"
    console.print(f"{plain(lat.scenario)}: {lat.cables} cables, redundancy {lat.redundancy}, {lat.method}; "
                  f"{lat.calls} calls", highlight=False, soft_wrap=True)
    for where in ("python", "compiled"):
        p50, p99, top = (getattr(lat, f"{where}_{q}_us") for q in ("p50", "p99", "max"))
        console.print(f"  step from {'Python' if where == 'python' else 'a compiled loop'}: p50 {p50:.2f} us, "
                      f"p99 {p99:.2f} us, max {top:.1f} us", highlight=False)
    console.print(f"  quadprog: {qp}", highlight=False)
