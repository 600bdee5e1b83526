"""Exact tensions for r > 1, compiled (issue 10, item 2): spatial_cube8 (8 cables, k = 6, r = 2).

Run:  .venv/bin/python benchmarks/bench_qp.py [--quick] [--before REV | --no-before]

Prints side by side (medians over repeats; the machine may be shared):
  * planning: marinecdpr.plan() (everything: motion, kinematics, dynamics, tensions) and its
    tension problem alone (eqs. 18-20: pseudo-inverse, then the method), against calling
    quadprog per step from Python on the same J~ and w (what a user would write), for
    minimum variance (the scenario's method; its optimum is inside the limits) and
    minimum norm (the lower limit holds cables at every step: the QP's active set works
    every step), with the largest difference from quadprog;
  * the closed loop (8001 steps, own plant and MuJoCo) and plan() now, and before: the
    same runs with the package as of REV (default 530035b, whose loop called the
    library's solver through numba's objmode every step and whose planning found r > 1
    null spaces by SVD), extracted read-only with ``git archive`` into a temporary
    directory and timed in a subprocess.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

import marinecdpr
from marinecdpr.geometry.kinematics import cable_kinematics
from marinecdpr.model.tension import distribute_tensions, pseudo_inverse_tensions
from marinecdpr.motion.trajectory import evaluate_trajectory

from _common import machine, quadprog_per_step as qp_per_step  # benchmarks/_common.py
from bench_plan import time_calls

ROOT = Path(__file__).resolve().parents[1]
CUBE8 = ROOT / "examples" / "spatial_cube8.toml"
BEFORE = "530035b"

CLOSED_LOOP = """
import json, statistics, sys, time
import marinecdpr
try:
    from marinecdpr.prototype.simulation import simulate
except ImportError:  # before the layout in subpackages
    from marinecdpr.simulation import simulate
sc = marinecdpr.load_scenario(sys.argv[1])
p = marinecdpr.plan(sc)
out = {"module": marinecdpr.__file__}
times = []
for _ in range(10 * int(sys.argv[2])):
    t0 = time.perf_counter()
    marinecdpr.plan(sc)
    times.append(time.perf_counter() - t0)
out["plan"] = statistics.median(times)
for plant in ("own", "mujoco"):
    simulate(sc, run="closed_loop", plant=plant, reference=p, n_steps=50)  # compile / load the cache
    times = []
    for _ in range(int(sys.argv[2])):
        t0 = time.perf_counter()
        r = simulate(sc, run="closed_loop", plant=plant, reference=p)
        times.append(time.perf_counter() - t0)
    out[plant] = {"median": statistics.median(times), "steps": int(r.t.size),
                  "fallbacks": r.controller_fallbacks,
                  "max_error_m": float(abs(r.pose[:, :3] - r.pose_planned[:, :3]).max())}
print(json.dumps(out))
"""


def closed_loop(pythonpath: str | None, repeats: int) -> dict:
    env = dict(os.environ)
    if pythonpath:
        env["PYTHONPATH"] = pythonpath
    res = subprocess.run([sys.executable, "-c", CLOSED_LOOP, str(CUBE8), str(repeats)], env=env,
                         capture_output=True, text=True, cwd=tempfile.gettempdir(), check=True)
    return json.loads(res.stdout.strip().splitlines()[-1])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer repeats")
    ap.add_argument("--before", default=BEFORE, help=f"the revision to compare the closed loop with ({BEFORE})")
    ap.add_argument("--no-before", action="store_true", help="skip the closed loop before")
    args = ap.parse_args()
    repeats = 10 if args.quick else 40
    print(f"machine: {machine()}")
    sc = marinecdpr.load_scenario(CUBE8)
    r = sc.robot
    n = sc.time.n_steps
    lo, hi = r.tension_min, r.tension_max
    print(f"spatial_cube8: {n} steps, {r.n_cables} cables, k = {len(r.controlled)}, "
          f"r = {r.n_cables - len(r.controlled)}")

    # ---------------------------------------------------------------- planning
    p = marinecdpr.plan(sc)
    plan_t = statistics.median(time_calls(lambda: marinecdpr.plan(sc), repeats))
    plat = evaluate_trajectory(sc.trajectory, p.t)
    c = list(r.controlled)
    Jv = cable_kinematics(plat.x_PC_C, plat.R_PC, r.frame_anchors, r.platform_anchors).J_tilde
    J = Jv.transpose(2, 1, 0)[c].transpose(2, 1, 0)  # planning's (time-last) layout
    w = p.wrench[:, c]
    Jc, wc = np.ascontiguousarray(J), np.ascontiguousarray(w)  # what suits quadprog best
    print("\nplanning (medians):")
    print(f"  marinecdpr.plan(), everything:                {plan_t * 1e3:8.2f} ms")
    for method, target in (("minimum_variance", 0.5 * (lo + hi)), ("minimum_norm", np.zeros(r.n_cables))):
        def ours(method=method):
            T_s, ok = pseudo_inverse_tensions(J, w)
            return distribute_tensions(J, w, lo, hi, method=method, ok=ok)

        sol = ours()
        ours_t = statistics.median(time_calls(ours, repeats))
        qp_t = statistics.median(time_calls(lambda: qp_per_step(Jc, wc, target, lo, hi), 1 if args.quick else 3))
        T_qp = qp_per_step(Jc, wc, target, lo, hi)
        held = int(np.any(np.isclose(sol.tensions, lo, rtol=0, atol=1e-9)
                          | np.isclose(sol.tensions, hi, rtol=0, atol=1e-9), axis=1).sum())
        print(f"  {method} ({held} of {n} steps with a cable held at a limit):")
        print(f"    quadprog per step from Python:              {qp_t * 1e3:8.2f} ms")
        print(f"    tension problem (pseudo-inverse + method):  {ours_t * 1e3:8.2f} ms   -> {qp_t / ours_t:5.0f}x faster")
        if method == "minimum_variance":
            print(f"    marinecdpr.plan(), everything:              {plan_t * 1e3:8.2f} ms   -> {qp_t / plan_t:5.0f}x faster"
                  f" than quadprog's tensions alone")
        rel = np.abs(sol.tensions - T_qp).max() / np.abs(T_qp).max()
        print(f"    agreement with quadprog: max |dT| = {np.abs(sol.tensions - T_qp).max():.1e} N "
              f"({rel:.1e} relative)")

    # ---------------------------------------------------------------- closed loop
    cl_repeats = 3 if args.quick else 5
    print("\nnow and before, spatial_cube8 (a subprocess each; closed loop: all steps, median of "
          f"{cl_repeats} after a warm-up run; plan(): median of {10 * cl_repeats}):")
    now = closed_loop(None, cl_repeats)
    before = None
    if not args.no_before:
        with tempfile.TemporaryDirectory() as tmp:
            try:
                archive = subprocess.run(["git", "-C", str(ROOT), "archive", args.before, "src"],
                                         capture_output=True, check=True).stdout
                subprocess.run(["tar", "-x", "-C", tmp], input=archive, check=True)
                before = closed_loop(str(Path(tmp) / "src"), cl_repeats)
                assert Path(before["module"]).is_relative_to(tmp)
            except (subprocess.CalledProcessError, FileNotFoundError) as exc:
                print(f"  (no 'before' run: {exc})")
    line = f"  plan()  now {now['plan'] * 1e3:7.2f} ms"
    if before is not None:
        line += (f"   before ({args.before}) {before['plan'] * 1e3:7.2f} ms -> "
                 f"{before['plan'] / now['plan']:4.0f}x faster")
    print(line)
    for plant in ("own", "mujoco"):
        line = (f"  {plant:6s}  now {now[plant]['median']:7.3f} s "
                f"({now[plant]['median'] / now[plant]['steps'] * 1e6:6.1f} us/step, "
                f"fallbacks {now[plant]['fallbacks']}, max error {now[plant]['max_error_m']:.2e} m)")
        if before is not None:
            b = before[plant]
            line += (f"   before ({args.before}) {b['median']:7.3f} s -> {b['median'] / now[plant]['median']:4.0f}x faster"
                     f" (max error {b['max_error_m']:.2e} m)")
        print(line)


if __name__ == "__main__":
    main()
