"""Operability at scale: 100 sea states, 20-minute records at 50 Hz, on Dask.

Run:  .venv/bin/python benchmarks/bench_operability.py [--cells 100]

The paper's robot and circle trajectory (the built-in ``paper_sea`` scenario: box-hull
RAOs, JONSWAP, cos-2s spreading) over a 10 x 10 Hs x Tp scatter diagram, one heading.
Prints the wall time with one and with two local Dask workers (the cluster's start-up
included and also shown apart), the speed-up, steps per second, and checks that both
runs and a serial run give identical verdicts. Target: 100 cells in <= 20 s on 2 cores.
"""

from __future__ import annotations

import argparse
import datetime
import os
import time

import numpy as np

import marinecdpr
from marinecdpr.operability import ScatterDiagram, operability


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cells", type=int, default=100, help="a square number of cells")
    args = ap.parse_args()
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
        op = operability(sc, scatter, executor="dask", scheduler=address)
        total = time.perf_counter() - t0
        cluster.close()
        times[workers] = total
        verdicts[workers] = [r.operable for r in op.results]
        print(f"{workers} worker(s): {total:6.2f} s (cluster start {t_up:.1f} s), "
              f"{k * k * steps / (total - t_up) / 1e6:.2f} M steps/s; operability {100 * op.operability:.1f} %"
              + ("   target <= 20 s" if workers == 2 else ""))
    print(f"speed-up from 1 to 2 workers: {times[1] / times[2]:.2f}x")
    serial = operability(sc, ScatterDiagram(hs[:3], tp[:3], np.full((3, 3), 1 / 9)), executor="serial")
    on_dask = operability(sc, ScatterDiagram(hs[:3], tp[:3], np.full((3, 3), 1 / 9)), executor="dask")
    same = all(a.operable == b.operable and a.min_margin_N == b.min_margin_N
               for a, b in zip(serial.results, on_dask.results))
    print(f"identical verdicts 1 vs 2 workers: {verdicts[1] == verdicts[2]}; serial vs Dask (9 cells, "
          f"margins to the bit): {same}")


if __name__ == "__main__":
    main()
