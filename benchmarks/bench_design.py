"""The built-in design study `ship_side` end to end, and what one finalist's sea state costs.

Run:  .venv/bin/python benchmarks/bench_design.py [--plant own|mujoco] [--pairs-only]

Prints:
  * `marinecdpr design ship_side --workers 2 --out TMP` as a user runs it (a subprocess,
    wall time): the search (its candidates on two Dask workers) and the time-domain
    verification of its finalists in every sea state, with the lines it prints;
  * one sea state of the study's best design flown closed loop (the hardest sea of the
    diagram, the frame where the template puts it), side by side: the
    own plant and MuJoCo, with the candidate's sea record (a fast FFT length) and with a
    record exactly as long as the job (what a user writing the scenario by hand would
    choose: its length in steps a product with a large prime, the sea summed term by term
    or by a slow FFT).
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from _common import best_of, machine  # benchmarks/_common.py (the script's folder is on sys.path)


def _record(sc) -> str:
    """The record's length and how the sea is synthesised over it."""
    steps = sc.base_motion.record_s / sc.time.step_s
    if abs(steps - round(steps)) > 1e-6:
        how = "not a whole number of steps: summed term by term"
    else:
        n, factors, p = round(steps), [], 2
        while p * p <= n:
            while n % p == 0:
                factors.append(p)
                n //= p
            p += 1
        factors += [n] if n > 1 else []
        how = f"an FFT of {round(steps)} = " + " x ".join(map(str, factors)) + " steps"
    return f"{sc.base_motion.record_s:.9g} s ({how})"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--plant", choices=["own", "mujoco"], default=None, help="the finalists' plant "
                        "(default: the study's)")
    parser.add_argument("--pairs-only", action="store_true", help="only the one-sea-state comparison")
    args = parser.parse_args()
    from importlib import resources

    from marinecdpr.studies.cleaning import evaluate_cleaning_cell
    from marinecdpr.studies.design import candidate_scenario, load_design, study_cells

    print(machine())
    path = Path(str(resources.files("marinecdpr") / "data" / "designs" / "ship_side.toml"))
    spec, template = load_design(path)
    cells = study_cells(spec, path.parent)
    best_x = None
    if not args.pairs_only:
        with tempfile.TemporaryDirectory() as tmp:
            cmd = [sys.executable, "-m", "marinecdpr", "design", "ship_side", "--workers", "2", "--out",
                   str(Path(tmp) / "out")] + (["--plant", args.plant] if args.plant else [])
            t0 = time.perf_counter()
            run = subprocess.run(cmd, capture_output=True, text=True)
            wall = time.perf_counter() - t0
            if run.returncode != 0:
                sys.exit(f"design failed (exit {run.returncode}): {run.stderr.strip()[-300:]}")
            print(f"marinecdpr design ship_side --workers 2{' --plant ' + args.plant if args.plant else ''}: "
                  f"{wall:.0f} s ({wall / 60:.1f} min) wall on this machine; it printed:")
            for line in run.stdout.splitlines():
                if "%)" not in line:  # not a progress line
                    print("   ", line)
            import json

            summary = json.loads((Path(tmp) / "out" / "summary.json").read_text())
            best_x = summary["best"]["variables"] if summary["best"] else None
    if best_x is None:  # the README's best design
        best_x = dict(frame_width_m=10.29726898927031, frame_height_m=4.613349522515445,
                      platform_width_m=0.4728468954495459, platform_height_m=1.3073649509822074,
                      tool_width_m=1.034420345477245, speed_m_s=0.4156234209383452, overlap_share=0.15,
                      winch="large", rope="dyneema_6mm", pattern="uncrossed")
    sc = candidate_scenario(spec, template, best_x)
    cell = max(cells, key=lambda c: (c.hs, c.tp))
    long = sc.with_changes(base_motion=dict(sc.base_motion.model_dump(exclude_none=True),
                                            record_s=float(sc.time.duration_s)))
    print(f"one sea state (Hs {cell.hs:g} m, Tp {cell.tp:g} s, heading {cell.heading_deg:g} deg) of the best design: "
          f"a {sc.time.duration_s:.0f} s job at {1 / sc.time.step_s:.0f} Hz ({sc.time.n_steps} steps), closed loop")
    for plant in ("own", "mujoco"):
        for label, s in (("the candidate's record, " + _record(sc), sc),
                         ("a record as long as the job, " + _record(long), long)):
            evaluate_cleaning_cell(s, cell, plant=plant)  # compiled, cached
            r, dt = best_of(2, lambda s=s: evaluate_cleaning_cell(s, cell, plant=plant))
            print(f"  {plant:>6} plant, {label}: {dt:.2f} s (works: {r.operable})")


if __name__ == "__main__":
    main()
