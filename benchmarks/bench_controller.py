"""The controller's step (issue 13): per-call time from Python and inside a compiled loop,
for the paper robot (r = 1) and spatial_cube8 (r = 2), beside a per-step quadprog solve of
the same tension problem (what a user would otherwise call) and the ship-motion
predictor's update and forecast.

Run:  .venv/bin/python benchmarks/bench_controller.py [--calls N] [--repeats R]

Prints, per robot, p50 / p99 / max over the calls of each repeat (the machine may be
shared: the spread across repeats is part of the answer). The goal (issue 13) on the
2-core CI machine: p99 under 20 us from Python and under 5 us in a compiled loop.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import marinecdpr
from marinecdpr.studies.latency import controller_latency

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--calls", type=int, default=20000)
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args()
    marinecdpr.keep_freed_memory()
    for label, source in (("paper (r = 1)", "paper"), ("spatial_cube8 (r = 2)", EXAMPLES / "spatial_cube8.toml")):
        sc = marinecdpr.load_scenario(source)
        print(f"{label}, {sc.planning.method}, {args.calls} calls per repeat (us: p50 / p99 / max)")
        for r in range(args.repeats):
            lat = controller_latency(sc, calls=args.calls)
            print(f"  repeat {r + 1}: Python {lat.python_p50_us:6.2f} / {lat.python_p99_us:6.2f} / "
                  f"{lat.python_max_us:8.1f}   compiled {lat.compiled_p50_us:5.2f} / {lat.compiled_p99_us:5.2f} / "
                  f"{lat.compiled_max_us:8.1f}   quadprog p50 "
                  + ("n/a" if lat.quadprog_p50_us is None else f"{lat.quadprog_p50_us:6.2f}"))


if __name__ == "__main__":
    main()
