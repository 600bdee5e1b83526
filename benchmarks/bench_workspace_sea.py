"""Workspace maps in a sea state: paper_sea and paper_clean, the map against the per-pose path it replaced.

Run:  .venv/bin/python benchmarks/bench_workspace_sea.py [--quick]

``marinecdpr workspace paper_sea`` took 21 min for its default 30 x 20 grid (0.47 poses/s)
where ``paper_clean``, also a sea state, ran 8.3 poses/s on 7x the steps: each held pose
evaluated the ship's motion again, and paper_sea's spread sea (1 350 frequencies x 11
directions, a 30 min record off the FFT grid at 1 ms) is a direct sum over its components
at every step; paper_clean's long-crested 2 min record is one cached inverse FFT. The map
now evaluates the ship's motion once per chunk of the time series for all poses.

For each scenario this prints poses per second (and plan steps per second) of
``workspace_map`` and of the per-pose path (each pose planned on its own with
``iter_plan``, as the map did before), the map's agreement with it (bit for bit), and the
projected time of the default 30 x 20 grid.
"""

from __future__ import annotations

import argparse

import numpy as np

import marinecdpr
from marinecdpr.errors import ScenarioError
from marinecdpr.planning.planner import iter_plan
from marinecdpr.studies.workspace import pose_range, tension_margin, workspace_map
from _common import best_of, machine  # benchmarks/_common.py (the script's folder is on sys.path)


def per_pose(sc, n: tuple[int, int]) -> np.ndarray:
    """The map's fraction feasible as it was made before: each held pose planned alone."""
    lo, hi = pose_range(sc)
    xs = np.linspace(lo[0], hi[0], n[0] + 2)[1:-1]
    zs = np.linspace(lo[2], hi[2], n[1] + 2)[1:-1]
    frac = np.full(n, np.nan)
    for a, x in enumerate(xs):
        for b, z in enumerate(zs):
            pos = [float(x), 0.0, float(z)]
            held = sc.with_changes(trajectory={"type": "line", "start_position_m": pos, "end_position_m": pos,
                                               "start_orientation_deg": [0.0, 0.0, 0.0], "duration_s": 1.0})
            try:
                ok = 0
                for piece in iter_plan(held):
                    ok += int(piece.feasible.sum())
                    tension_margin(piece.tensions, sc.robot.tension_min, sc.robot.tension_max)
                frac[a, b] = ok / sc.time.n_steps
            except ScenarioError:
                pass
    return frac


def bench(name: str, n: tuple[int, int], n_old: tuple[int, int], repeats: int) -> None:
    sc = marinecdpr.load_scenario(name)
    steps = sc.time.n_steps
    workspace_map(sc, n=(1, 1))  # warm-up (imports, caches)
    ws, t_new = best_of(repeats, lambda: workspace_map(sc, n=n))
    old, t_old = best_of(1, lambda: per_pose(sc, n_old))
    small = workspace_map(sc, n=n_old).fraction_feasible
    same = np.array_equal(old, small, equal_nan=True)
    print(f"{name}: {steps:,} steps per pose")
    for label, poses, t in ((f"workspace_map {n[0]}x{n[1]}", n[0] * n[1], t_new),
                            (f"per-pose path {n_old[0]}x{n_old[1]}", n_old[0] * n_old[1], t_old)):
        print(f"  {label:<24} {t:8.2f} s  {poses / t:8.2f} poses/s  {poses * steps / t:12,.0f} steps/s"
              f"   default 30x20 grid: ~{600 / (poses / t):6.0f} s")
    print(f"  speed-up {(n[0] * n[1] / t_new) / (n_old[0] * n_old[1] / t_old):.1f}x; same map as the per-pose "
          f"path: {same}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="smaller grids")
    args = ap.parse_args()
    print(f"machine: {machine()}")
    grid, old = ((6, 4), (2, 2)) if args.quick else ((30, 20), (4, 3))
    for name in ("paper_sea", "paper_clean"):
        bench(name, grid, old, 1 if args.quick else 2)


if __name__ == "__main__":
    main()
