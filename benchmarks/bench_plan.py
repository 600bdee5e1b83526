"""Planning speed: the paper scenario, a per-step QP baseline, and a 1 M-step streamed plan.

Run:  .venv/bin/python benchmarks/bench_plan.py [--quick]

Prints, for the built-in ``paper`` scenario (15 001 steps at 1 ms):
  * marinecdpr.plan() per call after warm-up (min / median over repeats);
  * the same tension problems (minimum variance, eq. 20) solved step by step with a
    general QP solver (quadprog), given the same J~ and w: what a user would write;
  * a 1 000 001-step plan streamed with iter_plan(): steps per second and peak
    traced memory, against a 100 001-step one (bounded memory: the peaks match).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
import statistics
import time
import tracemalloc

import numpy as np

import marinecdpr
from marinecdpr.planning.planner import iter_plan
from marinecdpr.model.tension import distribute_tensions, pseudo_inverse_tensions
from _common import machine, quadprog_per_step as qp_per_step  # benchmarks/_common.py (the script's folder is on sys.path)



def time_calls(fn, repeats: int) -> list[float]:
    out = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        out.append(time.perf_counter() - t0)
    return out


def streamed(scenario, n_steps: int, trace: bool) -> tuple[float, int, float, float]:
    sc = scenario.with_changes(time={"step_s": 0.001, "duration_s": (n_steps - 1) * 0.001})
    if trace:
        tracemalloc.start()
    t0 = time.perf_counter()
    lo, hi, bad, count = np.inf, -np.inf, 0, 0
    for piece in iter_plan(sc):
        lo = min(lo, float(piece.tensions.min()))
        hi = max(hi, float(piece.tensions.max()))
        bad += int((~piece.feasible).sum())
        count += piece.n_steps
    elapsed = time.perf_counter() - t0
    peak = 0
    if trace:
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
    assert count == sc.time.n_steps and bad == 0
    return elapsed, peak, lo, hi


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer repeats, 200 k streamed steps")
    args = ap.parse_args()
    repeats = 10 if args.quick else 50
    print(f"machine: {machine()}")
    sc = marinecdpr.load_scenario("paper")
    n = sc.time.n_steps

    marinecdpr.plan(sc)  # warm-up
    times = time_calls(lambda: marinecdpr.plan(sc), repeats)
    print(f"plan(paper), {n} steps, default malloc:        min {min(times) * 1e3:6.2f} ms  "
          f"median {statistics.median(times) * 1e3:6.2f} ms")
    tuned = marinecdpr.keep_freed_memory()
    marinecdpr.plan(sc)
    times = time_calls(lambda: marinecdpr.plan(sc), repeats)
    med = statistics.median(times)
    print(f"plan(paper), {n} steps, keep_freed_memory()={tuned}: min {min(times) * 1e3:6.2f} ms  "
          f"median {med * 1e3:6.2f} ms  ({n / med / 1e6:.2f} M steps/s)   target <= 10 ms")

    # the same chain with the former vectorised numpy model (tests/vectorised.py) in place of
    # the compiled per-step model run in compiled loops; the tension solvers are the same
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
    import vectorised

    from marinecdpr.planning import planner

    compiled = {name: getattr(planner, name) for name in ("cable_kinematics", "wrench_terms", "disturbance_in_C")}
    try:
        for name in compiled:
            setattr(planner, name, getattr(vectorised, name))
        numpy_times = time_calls(lambda: marinecdpr.plan(sc), repeats)
    finally:
        for name, fn in compiled.items():
            setattr(planner, name, fn)
    numpy_med = statistics.median(numpy_times)
    print(f"plan(paper) with the numpy model (tests/vectorised.py): median {numpy_med * 1e3:6.2f} ms  "
          f"-> the compiled model is {numpy_med / med:.2f}x faster (issue 10 asked 10x)")

    # the baseline gets the same J~ and w; only the tension solve is timed
    p = marinecdpr.plan(sc)
    from marinecdpr.geometry.kinematics import cable_kinematics
    from marinecdpr.motion.trajectory import evaluate_trajectory

    plat = evaluate_trajectory(sc.trajectory, p.t)
    r = sc.robot
    c = list(r.controlled)
    J = np.ascontiguousarray(
        cable_kinematics(plat.x_PC_C, plat.R_PC, r.frame_anchors, r.platform_anchors).J_tilde[:, :, c])
    w = np.ascontiguousarray(p.wrench[:, c])
    mid = 0.5 * (r.tension_min + r.tension_max)  # minimum variance, eq. (20)
    qp_times = time_calls(lambda: qp_per_step(J, w, mid, r.tension_min, r.tension_max), 1 if args.quick else 3)
    T_qp = qp_per_step(J, w, mid, r.tension_min, r.tension_max)
    qp = min(qp_times)

    def ours():
        T_s, ok = pseudo_inverse_tensions(J, w)
        return distribute_tensions(J, w, r.tension_min, r.tension_max, method="minimum_variance", ok=ok)

    ours_t = statistics.median(time_calls(ours, 4 * repeats))
    print(f"tension problem, {n} steps, same J~ and w (eqs. 18-20):")
    print(f"  quadprog, step by step:             {qp * 1e3:8.2f} ms")
    print(f"  marinecdpr distribute_tensions:     {ours_t * 1e3:8.2f} ms   -> {qp / ours_t:.0f}x faster"
          f"   target >= 100x")
    print(f"  whole plan() (motion, kinematics, dynamics, tensions) vs quadprog's tensions alone: "
          f"{qp / med:.0f}x faster")
    print(f"  agreement with quadprog: max |dT| = {np.abs(T_qp - ours().tensions).max():.2e} N")

    # what a user without a vectorised toolkit writes: a per-step loop over the model
    # (tests/reference.py: kinematics and Newton-Euler per step) and quadprog
    import reference

    from marinecdpr.motion.basemotion import evaluate_base_motion

    ship = evaluate_base_motion(sc.base_motion, p.t)
    stride = 10 if args.quick else 3
    idx = np.arange(0, n, stride)
    origin = np.asarray(sc.ship.frame_origin_m)
    zero3 = np.zeros(3)
    t0 = time.perf_counter()
    for i in idx:
        _, _, Jt = reference.cable_quantities(plat.pose[i], r.frame_anchors, r.platform_anchors)
        wi = reference.required_wrench(plat.pose[i], plat.pose_dot[i], plat.pose_ddot[i], ship.eta[i],
                                       ship.eta_dot[i], ship.eta_ddot[i], origin, r.mass_kg, r.inertia,
                                       sc.environment.gravity_m_s2, zero3, zero3)
        qp_per_step(Jt[None][:, :, c], wi[None, c], mid, r.tension_min, r.tension_max)
    loop = (time.perf_counter() - t0) * n / idx.size
    print(f"  per-step Python pipeline (reference model + quadprog), extrapolated from every "
          f"{stride}th step: {loop * 1e3:8.0f} ms   -> plan() is {loop / med:.0f}x faster")

    big = 200_001 if args.quick else 1_000_001
    small = 100_001
    el_big, _, lo, hi = streamed(sc, big, trace=False)
    _, peak_big, _, _ = streamed(sc, big, trace=True)
    _, peak_small, _, _ = streamed(sc, small, trace=True)
    print(f"iter_plan, {big} steps:       {el_big:6.3f} s  ({big / el_big / 1e6:.2f} M steps/s)   "
          f"target >= 1 M steps/s")
    print(f"  peak traced memory: {peak_big / 2**20:.1f} MiB for {big} steps, "
          f"{peak_small / 2**20:.1f} MiB for {small} steps (bounded by the chunk, not the record)")
    print(f"  tensions over the record: {lo:.2f} .. {hi:.2f} N, all steps feasible")


if __name__ == "__main__":
    main()
