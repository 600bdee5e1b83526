"""Co-simulation speed: the paper scenario's closed loop on MuJoCo against bare MuJoCo stepping.

Run:  .venv/bin/python benchmarks/bench_simulate.py

Prints, for the built-in ``paper`` scenario (15 s at 1 ms, 15 001 exchanges):
  * bare MuJoCo: the same model stepped from Python with constant controls (the floor);
  * marinecdpr.simulate(run="closed_loop"): sensors, computed torque, minimum-variance
    tensions and the cable model at every exchange, ship driven along its motion;
  * the same for open loop, and the own plant (RK4) for both;
with the real-time factor of each and the closed loop's ratio to bare stepping. Targets:
>= 20x real time and <= 2.5x bare MuJoCo.
"""

from __future__ import annotations

import datetime
import platform
import statistics
import time

import mujoco
import numpy as np

import marinecdpr
from marinecdpr.mjmodel import build_model
from marinecdpr.simulation import simulate


def best(fn, repeats: int) -> float:
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def main() -> None:
    marinecdpr.keep_freed_memory()
    sc = marinecdpr.load_scenario("paper")
    n = sc.time.n_steps
    duration = sc.time.duration_s
    cpu = next((ln.split(":", 1)[1].strip() for ln in open("/proc/cpuinfo") if ln.startswith("model name")),
               "unknown CPU")
    print(f"machine: {cpu}, Python {platform.python_version()}, MuJoCo {mujoco.__version__}, "
          f"{datetime.date.today().isoformat()}")
    mm = build_model(sc)
    model = mm.model
    data = mujoco.MjData(model)
    ctrl = np.full(model.nu, 100.0)

    def bare():
        mujoco.mj_resetData(model, data)
        data.qpos[mm.platform_qpos] = [0.98, 0.7, 0.0]
        for _ in range(n):
            data.ctrl[:] = ctrl
            mujoco.mj_step(model, data)

    p = marinecdpr.plan(sc)
    simulate(sc, run="closed_loop", reference=p, n_steps=100)  # compile / load the kernels
    simulate(sc, run="closed_loop", reference=p, plant="own", n_steps=100)
    t_bare = best(bare, 5)
    print(f"bare MuJoCo ({model.opt.integrator.name if hasattr(model.opt.integrator, 'name') else 'RK4'}), "
          f"constant controls, {n} steps: {t_bare:6.3f} s  ({duration / t_bare:5.0f}x real time)")
    for plant in ("mujoco", "own"):
        for run in ("closed_loop", "open_loop"):
            t_run = best(lambda: simulate(sc, run=run, reference=p, plant=plant), 5)
            extra = f"   {t_run / t_bare:.2f}x bare MuJoCo (target <= 2.5x)" if plant == "mujoco" else ""
            print(f"simulate {run:12s} on {plant:6s}: {t_run:6.3f} s  ({duration / t_run:5.0f}x real time,"
                  f" target >= 20x){extra}")
    t_main = best(lambda: marinecdpr.virtual_prototype(sc), 3)
    print(f"virtual_prototype (plan + three runs on MuJoCo, no files): {t_main:.3f} s")


if __name__ == "__main__":
    main()
