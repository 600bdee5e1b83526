"""The cleaning job's speed: a 10-minute panel job at 1 ms closed loop on MuJoCo.

Run:  .venv/bin/python benchmarks/bench_clean.py [--quick]

A panel of paper_clean's robot made large enough for about 10 minutes of path (600 000
closed-loop steps), in calm water and in paper_clean's sea; prints, side by side:
  * bare MuJoCo stepping the same model from Python, constant controls, the same steps;
  * the closed-loop run of the job (sensors, computed torque, minimum-variance tensions
    and the brush's loads at every exchange), and its ratio to bare MuJoCo (issue 11 asks
    <= 1.5x);
  * the coverage computation on the simulated path (issue 11 asks < 1 s);
  * the whole cleaning_job (plan, run, measures).
"""

from __future__ import annotations

import sys
import time

import mujoco
import numpy as np

import marinecdpr
from _common import machine  # benchmarks/_common.py
from marinecdpr.motion.trajectory import cleaning_path
from marinecdpr.prototype.mujoco_model import build_model
from marinecdpr.prototype.simulation import simulate
from marinecdpr.studies.cleaning import brush_positions, cleaning_job
from marinecdpr.studies.coverage import coverage_map


def main() -> None:
    marinecdpr.keep_freed_memory()
    print(f"machine: {machine()}")
    sc = marinecdpr.load_scenario("paper_clean")
    slow = sc.cleaning.model_dump(exclude_none=True) | {"speed_m_s": 0.02, "overlap_m": 0.1}
    sc = sc.with_changes(cleaning=slow)
    path = cleaning_path(sc.cleaning)
    quick = "--quick" in sys.argv
    duration = min(path.duration_s, 60.0 if quick else 600.0)
    # the sea's record covers the job without repeating: 10 minutes (2 for the quick run)
    sc = sc.with_changes(time={"step_s": 0.001, "duration_s": round(duration, 3)},
                         base_motion=sc.base_motion.model_dump(exclude_none=True) | {"record_s": 120.0 if quick else 600.0})
    n = sc.time.n_steps
    print(f"path: {path.lanes} lanes, {path.length_m:.3g} m, {path.duration_s:.0f} s; job of {duration:.0f} s = {n} steps")

    mm = build_model(sc)
    data = mujoco.MjData(mm.model)
    ctrl = np.full(mm.model.nu, 100.0)
    t0 = time.perf_counter()
    data.qpos[mm.platform_qpos] = [0.9, 0.7, 0.0]
    for _ in range(n):
        data.ctrl[:] = ctrl
        mujoco.mj_step(mm.model, data)
    bare = time.perf_counter() - t0
    print(f"bare MuJoCo, {n} steps from Python:       {bare:7.2f} s")

    p = marinecdpr.plan(sc)
    simulate(sc, run="closed_loop", reference=p, n_steps=100)  # loaded, compiled
    t0 = time.perf_counter()
    res = simulate(sc, run="closed_loop", reference=p)
    run = time.perf_counter() - t0
    print(f"closed loop of the job (brush loads):      {run:7.2f} s   {run / bare:.2f}x bare MuJoCo (asked <= 1.5x)")
    brush = brush_positions(res.pose, sc.cleaning.brush_offset_m)[:, [0, 2]]
    t0 = time.perf_counter()
    cov = coverage_map(np.asarray(sc.cleaning.panel_m), [], brush, np.ones(n, dtype=bool),
                       width_m=sc.cleaning.brush_diameter_m)
    print(f"coverage of the simulated path:            {time.perf_counter() - t0:7.2f} s   (asked < 1 s; "
          f"{cov.coverage_pct:.2f} % covered)")
    t0 = time.perf_counter()
    job = cleaning_job(sc)
    print(f"whole cleaning_job (plan, run, measures):  {time.perf_counter() - t0:7.2f} s   "
          f"coverage {job.summary['coverage_pct']:.2f} %")


if __name__ == "__main__":
    main()
