"""Memory of long plans: ``marinecdpr plan`` streams in chunks, so its peak stays flat.

Run:  .venv/bin/python benchmarks/bench_plan_memory.py [--hours 1 10] [--quick]

For the built-in ``paper`` scenario at 1 kHz with ``duration_s`` set to each of the given
hours (the paper's circle is periodic, so any duration is valid), runs the command

    marinecdpr plan <scenario.toml> --out <tmp>

as a subprocess and prints its peak resident memory (the child's own ``ru_maxrss``,
from ``os.wait4``), wall time, steps per second and the size of the plan.csv it wrote.
Side by side, for the first duration only, the in-memory alternatives in a subprocess
each: ``marinecdpr.plan(sc)`` alone, and ``marinecdpr.plan(sc)`` followed by
``write_plan_csv`` and ``plot_tensions`` (what ``marinecdpr plan`` did before it streamed).

``--quick`` runs 0.1 h and 0.5 h instead (a smoke test, about a minute).
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from importlib import resources
from pathlib import Path

from _common import machine  # benchmarks/_common.py (the script's folder is on sys.path)

CLI = [sys.executable, "-m", "marinecdpr"]


def scenario_file(folder: Path, hours: float) -> Path:
    """The built-in paper scenario with ``duration_s`` set to ``hours``."""
    text = (resources.files("marinecdpr") / "scenarios" / "paper.toml").read_text(encoding="utf-8")
    old = "duration_s = 15.0"
    assert text.count(old) == 1, "the paper scenario's duration line changed"
    path = folder / f"paper_{hours:g}h.toml"
    path.write_text(text.replace(old, f"duration_s = {hours * 3600.0:.1f}"), encoding="utf-8")
    return path


def run(cmd: list[str]) -> tuple[float, float, int, str]:
    """(peak RSS in MiB, wall time in s, exit code, stderr's tail) of a subprocess."""
    t0 = time.perf_counter()
    with tempfile.TemporaryFile() as err:
        proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=err)
        _, status, usage = os.wait4(proc.pid, 0)
        proc.returncode = os.waitstatus_to_exitcode(status)
        wall = time.perf_counter() - t0
        err.seek(0)
        tail = err.read().decode(errors="replace").strip().splitlines()[-1:] or [""]
    return usage.ru_maxrss / 1024.0, wall, proc.returncode, tail[0]


IN_MEMORY = """
import sys, marinecdpr
from marinecdpr.report.figures import plot_tensions
from marinecdpr.report.writers import write_plan_csv

sc = marinecdpr.load_scenario(sys.argv[1])
p = marinecdpr.plan(sc)
if sys.argv[2] == "files":
    write_plan_csv(p, sc, sys.argv[3] + "/plan.csv")
    plot_tensions(p, sc, sys.argv[3] + "/tensions.png")
"""


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--hours", type=float, nargs="+", default=[1.0, 10.0], help="plan durations, h")
    ap.add_argument("--quick", action="store_true", help="0.1 h and 0.5 h")
    ap.add_argument("--no-in-memory", action="store_true", help="skip the in-memory comparison")
    args = ap.parse_args()
    hours = [0.1, 0.5] if args.quick else args.hours
    print(f"machine: {machine()}")
    print("marinecdpr plan on the paper scenario at 1 kHz (peak RSS of the whole process):")
    print(f"  {'duration':>9} {'steps':>12} {'peak RSS':>11} {'wall':>9} {'steps/s':>10} {'plan.csv':>10}  how")
    with tempfile.TemporaryDirectory(prefix="bench_plan_memory.") as tmp:
        tmp = Path(tmp)
        rows = []
        for h in hours:
            scen = scenario_file(tmp, h)
            out = tmp / f"out_{h:g}h"
            n = int(round(h * 3600 * 1000)) + 1
            rss, wall, code, tail = run(CLI + ["plan", str(scen), "--out", str(out)])
            size = (out / "plan.csv").stat().st_size if code == 0 else 0
            rows.append((h, rss))
            note = "streamed (chunks)" if code == 0 else f"exit {code}: {tail}"
            print(f"  {h:7g} h {n:12,d} {rss:8.0f} MiB {wall:7.1f} s {n / wall:10,.0f} {size / 1e9:7.2f} GB  {note}",
                  flush=True)
            if out.exists():
                for f in out.iterdir():
                    f.unlink()
        if not args.no_in_memory:
            h = hours[0]
            scen = scenario_file(tmp, h)
            n = int(round(h * 3600 * 1000)) + 1
            out = tmp / "out_mem"
            out.mkdir()
            for what, label in (("plan", "marinecdpr.plan(sc) alone, in memory"),
                                ("files", "plan(sc) + write_plan_csv + plot_tensions (the previous command)")):
                rss, wall, code, tail = run([sys.executable, "-c", IN_MEMORY, str(scen), what, str(out)])
                note = label if code == 0 else f"{label}: exit {code}: {tail}"
                print(f"  {h:7g} h {n:12,d} {rss:8.0f} MiB {wall:7.1f} s {n / wall:10,.0f} {'':>10}  {note}",
                      flush=True)
        if len(rows) > 1:
            (h0, r0), (h1, r1) = rows[0], rows[-1]
            print(f"streamed peak at {h1:g} h / at {h0:g} h: {r1 / r0:.2f} "
                  f"({h1 / h0:g}x the steps)")


if __name__ == "__main__":
    main()
