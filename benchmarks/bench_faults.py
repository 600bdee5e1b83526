"""A fault's cost in the virtual prototype: a closed loop with a cable that snaps against the
same closed loop without it (issue 40: within 2x).

Run:  PYTHONPATH=src .venv/bin/python benchmarks/bench_faults.py [--quick]

For paper_clean (four cables; cable 1, top left, snaps) and examples/clean_six_cables.toml
(six; cable 5, mid left, snaps), at the job's 5 s, the first 10 s of the job (10 001
exchanges) flown closed loop on MuJoCo and on the own plant, with the plan computed once
beforehand (``reference``): the best of a few repeats of ``simulate`` (each run once first,
so that the compiling is not timed), and the fault case's ratio to the fault-free one. The
snap adds one part's mode (the cables' part wrapped); the controller, not told, is bypassed
where its feedback's tensions leave the limits, which it costs it to find out.

Then the faults study's own case (``marinecdpr faults``: :func:`~marinecdpr.studies.faults.fault_study`
with one case, the same snap, flown to the same 10 s and judged: detection, excursion, frame,
tensions, static margin, verdict) against the same fault-free flight on MuJoCo.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import marinecdpr
from marinecdpr.prototype.simulation import simulate
from marinecdpr.studies.faults import FaultCase, fault_study

from _common import machine

ROOT = Path(__file__).resolve().parents[1]
CASES = (("paper_clean", "paper_clean", 1), ("clean_six_cables", str(ROOT / "examples" / "clean_six_cables.toml"), 5))
HORIZON_S, SNAP_S = 10.0, 5.0


def best(fn, repeats: int) -> float:
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def main() -> None:
    repeats = 2 if "--quick" in sys.argv else 5
    print(machine())
    print(f"closed loop, the first {HORIZON_S:g} s of each job, a cable snapping at {SNAP_S:g} s; best of {repeats}")
    for name, source, cable in CASES:
        sc = marinecdpr.load_scenario(source)
        sc = sc.with_changes(time={"step_s": sc.time.step_s, "duration_s": HORIZON_S})
        snapped = sc.with_changes(faults=[{"kind": "cable_snap", "cable": cable, "at_s": SNAP_S}])
        plan = marinecdpr.plan(sc)
        for plant in ("mujoco", "own"):
            runs = {}
            for label, s in (("fault-free", sc), ("snap", snapped)):
                simulate(s, run="closed_loop", plant=plant, reference=plan)  # compiled and warm
                runs[label] = best(lambda: simulate(s, run="closed_loop", plant=plant, reference=plan), repeats)
            print(f"  {name:17s} {plant:6s} fault-free {runs['fault-free']:6.3f} s, cable {cable} snapping "
                  f"{runs['snap']:6.3f} s: {runs['snap'] / runs['fault-free']:.2f}x")
        case = [FaultCase(kind="cable_snap", cable=cable, at_s=SNAP_S, moment="given")]

        def study():
            return fault_study(sc, case, after_s=HORIZON_S - SNAP_S, plant="mujoco", plan=plan)

        study()
        judged = best(study, repeats)
        free = best(lambda: simulate(sc, run="closed_loop", plant="mujoco", reference=plan), repeats)
        print(f"  {name:17s} faults study, one case (flown and judged) {judged:6.3f} s against the fault-free "
              f"flight {free:6.3f} s: {judged / free:.2f}x ({study().rows[0].verdict})")


if __name__ == "__main__":
    main()
