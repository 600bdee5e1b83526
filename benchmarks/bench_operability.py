"""Operability at scale: 100 sea states, 20-minute records at 50 Hz, on Dask.

Run:  .venv/bin/python benchmarks/bench_operability.py [--cells 100]
      .venv/bin/python benchmarks/bench_operability.py --crossover [--repeat 3]

The paper's robot and circle trajectory (the built-in ``paper_sea`` scenario: box-hull
RAOs, JONSWAP, cos-2s spreading) over a 10 x 10 Hs x Tp scatter diagram, one heading.
Prints the wall time with one and with two local Dask workers (the cluster's start-up
included and also shown apart), the speed-up, steps per second, and checks that both
runs and a serial run give identical verdicts. Target: 100 cells in <= 20 s on 2 cores.

``--crossover`` measures where a 2-worker local Dask cluster starts to beat a serial run,
as the ``marinecdpr operability`` command meets them (each run in a fresh process, the
cluster's start included), over studies of growing size; the fastest of ``--repeat``
runs counts. ``marinecdpr.studies.executor.AUTO_DASK_MIN_STEPS`` is set from it.
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import subprocess
import sys
import time

import numpy as np

import marinecdpr
from marinecdpr.studies.executor import Executor
from marinecdpr.studies.operability import ScatterDiagram, operability


_ONE_RUN = """
import json, sys, time
import numpy as np
import marinecdpr
from marinecdpr.studies.executor import Executor
from marinecdpr.studies.operability import ScatterDiagram, operability, study_steps
if __name__ == "__main__":
    marinecdpr.keep_freed_memory()
    executor, k, duration, grid = sys.argv[1], int(sys.argv[2]), float(sys.argv[3]), sys.argv[4]
    grid = tuple(int(n) for n in grid.split("x")) if grid != "-" else None
    scatter = ScatterDiagram(np.linspace(0.5, 5.0, k), np.linspace(5.0, 14.0, k), np.full((k, k), 1.0 / (k * k)))
    sc = marinecdpr.load_scenario("paper_sea")
    t0 = time.perf_counter()
    op = operability(sc, scatter, executor=Executor.serial() if executor == "serial" else Executor.local(2), duration_s=duration, workspace=grid)
    print(json.dumps({"t": time.perf_counter() - t0, "steps": study_steps(k * k, duration_s=duration, step_s=0.02,
                                                                         workspace=grid),
                      "verdicts": [r.operable for r in op.results]}))
"""


def crossover(repeat: int) -> None:
    """Serial vs a 2-worker local Dask cluster, fresh processes, over growing studies."""
    from marinecdpr.studies.executor import AUTO_DASK_MIN_STEPS

    studies = [(4, 600.0, "-"), (6, 1200.0, "-"), (10, 1200.0, "-"), (15, 1200.0, "-"), (20, 1200.0, "-"),
               (3, 60.0, "12x8"), (6, 60.0, "12x8")]
    print(f"machine: {os.cpu_count()} cores, {datetime.date.today().isoformat()}; fastest of {repeat} runs, "
          "each in a fresh process, Dask's start included")
    print(f"{'study':>26} {'M steps':>8} {'serial s':>9} {'Dask s':>8} {'Dask/serial':>12}")
    for k, duration, grid in studies:
        best = {}
        for _ in range(repeat):
            for executor in ("serial", "dask"):   # interleaved: a busy spell hurts both alike
                out = subprocess.run([sys.executable, "-c", _ONE_RUN, executor, str(k), str(duration), grid],
                                     capture_output=True, text=True, check=True).stdout
                r = json.loads(out.strip().splitlines()[-1])
                best[executor] = min(best.get(executor, float("inf")), r["t"])
        label = f"{k * k} cells x {duration:g} s" + (f" x {grid}" if grid != "-" else "")
        print(f"{label:>26} {r['steps'] / 1e6:8.2f} {best['serial']:9.2f} {best['dask']:8.2f} "
              f"{best['dask'] / best['serial']:12.2f}", flush=True)
    print(f"auto runs serially below {AUTO_DASK_MIN_STEPS / 1e6:g} M steps")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cells", type=int, default=100, help="a square number of cells")
    ap.add_argument("--crossover", action="store_true", help="time serial vs Dask over growing studies")
    ap.add_argument("--repeat", type=int, default=3, help="with --crossover: runs per study and executor")
    args = ap.parse_args()
    if args.crossover:
        crossover(args.repeat)
        return
    k = int(round(args.cells ** 0.5))
    hs = np.linspace(0.5, 5.0, k)
    tp = np.linspace(5.0, 14.0, k)
    scatter = ScatterDiagram(hs, tp, np.full((k, k), 1.0 / (k * k)))
    sc = marinecdpr.load_scenario("paper_sea")
    steps = int(1200 / 0.02) + 1
    print(f"machine: {os.cpu_count()} cores, {datetime.date.today().isoformat()}; {k * k} cells x "
          f"{steps} steps (20 min at 50 Hz)")
    from dask.distributed import Client, LocalCluster

    verdicts = {}
    times = {}
    for workers in (1, 2):
        t0 = time.perf_counter()
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None)
        address = cluster.scheduler_address
        t_up = time.perf_counter() - t0
        op = operability(sc, scatter, executor=Executor.at(address))
        total = time.perf_counter() - t0
        cluster.close()
        times[workers] = total
        verdicts[workers] = [r.operable for r in op.results]
        print(f"{workers} worker(s): {total:6.2f} s (cluster start {t_up:.1f} s), "
              f"{k * k * steps / (total - t_up) / 1e6:.2f} M steps/s; operability {100 * op.operability:.1f} %"
              + ("   target <= 20 s" if workers == 2 else ""))
    print(f"speed-up from 1 to 2 workers: {times[1] / times[2]:.2f}x")
    serial = operability(sc, ScatterDiagram(hs[:3], tp[:3], np.full((3, 3), 1 / 9)), executor=Executor.serial())
    on_dask = operability(sc, ScatterDiagram(hs[:3], tp[:3], np.full((3, 3), 1 / 9)), executor=Executor.local())
    same = all(a.operable == b.operable and a.min_margin_N == b.min_margin_N
               for a, b in zip(serial.results, on_dask.results))
    print(f"identical verdicts 1 vs 2 workers: {verdicts[1] == verdicts[2]}; serial vs Dask (9 cells, "
          f"margins to the bit): {same}")


if __name__ == "__main__":
    main()
