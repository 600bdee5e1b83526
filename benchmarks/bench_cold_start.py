"""The main job's first run: ``marinecdpr simulate --out TMP`` with numba's cache empty.

Run:  .venv/bin/python benchmarks/bench_cold_start.py [--repeats N]

Each repeat runs the command as a subprocess of this checkout with a fresh, empty cache
folder (``MARINECDPR_CACHE_DIR``), three ways:
  * on every core: where it can fork, the planner's kernels and the controller's step
    compile in two forked copies while the loop compiles in the main process
    (:func:`~marinecdpr.prototype.warmup.compile_apart`);
  * on one core (``taskset -c 0``): everything compiles in turn, what a one-core machine
    (or the code before the split) pays;
  * warm: the same command again, the cache filled;
  * then, on that cache, the first run of two other scenarios: ``paper_clean`` (a brush part
    more: the loop is reused, only the new part's step compiles) and ``paper_as_built``
    (motor winches on elastic cables: the loop is reused too, since the cable law is
    called by its address; its parts' steps, its law and its planner's kernels compile),
    what a user meets moving on from the paper's scenario.
Issue 22's goal: the first run within 20 s, a warm run within 3 s, on this 2-core machine
with nothing else running. Prints the minimum and median of each.
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import machine  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
CLI = [sys.executable, "-m", "marinecdpr"]


def _run(env: dict, out: Path, prefix: list[str], scenario: tuple[str, ...] = ()) -> float:
    t0 = time.perf_counter()
    done = subprocess.run([*prefix, *CLI, "simulate", *scenario, "--out", str(out)], env=env, cwd=ROOT,
                          capture_output=True, text=True)
    seconds = time.perf_counter() - t0
    if done.returncode != 0:
        raise SystemExit(f"marinecdpr simulate failed: {done.stderr.strip().splitlines()[-1:]}")
    return seconds


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=2)
    args = parser.parse_args()
    print(machine())
    if shutil.which("taskset") is None:
        raise SystemExit("taskset (util-linux) is needed for the one-core run")
    times: dict[str, list[float]] = {"cold, every core": [], "cold, one core": [], "warm": [],
                                     "then paper_clean": [], "then paper_as_built": []}
    for _ in range(args.repeats):
        for name, prefix in (("cold, every core", []), ("cold, one core", ["taskset", "-c", "0"])):
            with tempfile.TemporaryDirectory() as tmp:
                env = dict(os.environ, MARINECDPR_CACHE_DIR=str(Path(tmp) / "cache"),
                           PYTHONPATH=str(ROOT / "src"))
                env.pop("NUMBA_CACHE_DIR", None)
                times[name].append(_run(env, Path(tmp) / "out", prefix))
                if name == "cold, every core":
                    times["warm"].append(_run(env, Path(tmp) / "out2", []))
                    for other in ("paper_clean", "paper_as_built"):
                        times[f"then {other}"].append(_run(env, Path(tmp) / other, [], (other,)))
    for name, values in times.items():
        print(f"{name:20s} min {min(values):6.1f} s   median {statistics.median(values):6.1f} s   "
              f"({len(values)} runs)")
    print("goal: cold within 20 s, warm within 3 s")


if __name__ == "__main__":
    main()
