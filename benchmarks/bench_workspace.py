"""Workspace-map speed: the paper robot and an 8-cable spatial robot, against a per-pose plan loop.

Run:  .venv/bin/python benchmarks/bench_workspace.py [--quick]

For each robot, times ``marinecdpr.studies.workspace.workspace_map`` over a grid of held poses
(each planned over the scenario's whole ship-motion record) and prints poses per second
and time steps per second. Side by side: what a user would write without it, a loop
over the same poses that builds a held-pose scenario and calls ``marinecdpr.plan`` on
it; both must give the same map. The last column projects the time of the command's
default 30 x 20 grid.

  * ``paper``: 4 cables, planar (redundancy 1), 15 s at 1 ms = 15 001 steps per pose;
  * ``examples/spatial_cube8.toml``: 8 cables, spatial (redundancy 2), 8 s at 1 ms =
    8 001 steps per pose.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

import marinecdpr
from marinecdpr.errors import ScenarioError
from marinecdpr.studies.workspace import pose_range, workspace_map
from _common import best_of, machine  # benchmarks/_common.py (the script's folder is on sys.path)


ROOT = Path(__file__).resolve().parents[1]


def per_pose_loop(sc, n: tuple[int, int]) -> np.ndarray:
    """The user's loop: a held-pose scenario per grid point (x-z plane, y mid-frame), plan() on each,
    over the same poses as the map (where the platform fits inside the frame)."""
    lo, hi = pose_range(sc)
    xs = np.linspace(lo[0], hi[0], n[0] + 2)[1:-1]
    zs = np.linspace(lo[2], hi[2], n[1] + 2)[1:-1]
    y = 0.0 if sc.robot.dofs == "planar" else 0.5 * (lo[1] + hi[1])
    frac = np.full(n, np.nan)
    for a, x in enumerate(xs):
        for b, z in enumerate(zs):
            pos = [float(x), y, float(z)]
            held = sc.with_changes(trajectory={"type": "line", "start_position_m": pos,
                                               "end_position_m": pos, "duration_s": 1.0})
            try:
                frac[a, b] = marinecdpr.plan(held).feasible.mean()
            except ScenarioError:
                pass  # outside the frame
    return frac


def bench(name: str, sc, n: tuple[int, int], repeats: int) -> None:
    steps = sc.time.n_steps
    poses = n[0] * n[1]
    workspace_map(sc, n=(1, 1))  # warm-up (imports, JIT)
    ws, t_ws = best_of(repeats, lambda: workspace_map(sc, n=n))
    frac, t_loop = best_of(repeats, lambda: per_pose_loop(sc, n))
    same = np.array_equal(np.isnan(frac), np.isnan(ws.fraction_feasible)) and np.allclose(
        frac[~np.isnan(frac)], ws.fraction_feasible[~np.isnan(frac)], rtol=0, atol=1e-12)
    inside = int(np.isfinite(ws.fraction_feasible).sum())
    print(f"{name}: {sc.robot.n_cables} cables, {sc.robot.dofs}; grid {n[0]}x{n[1]} = {poses} poses "
          f"({inside} inside the frame) x {steps} steps; best of {repeats}")
    for label, t in (("workspace_map", t_ws), ("per-pose plan() loop", t_loop)):
        print(f"  {label:<22} {t:7.2f} s  {poses / t:7.1f} poses/s  {inside * steps / t:11,.0f} steps/s"
              f"   default 30x20 grid: ~{600 / (poses / t):4.0f} s")
    print(f"  workspace_map vs the loop: {t_loop / t_ws:.2f}x; same map: {same}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="smaller grids")
    args = ap.parse_args()
    print(f"machine: {machine()}")
    paper = marinecdpr.load_scenario("paper")
    cube = marinecdpr.load_scenario(str(ROOT / "examples" / "spatial_cube8.toml"))
    repeats = 1 if args.quick else 2
    bench("paper", paper, (6, 4) if args.quick else (12, 8), repeats)
    bench("spatial_cube8", cube, (4, 3) if args.quick else (6, 4), repeats)


if __name__ == "__main__":
    main()
