"""Interference check speed: the cables' pairwise distances along a trajectory, against FCL.

Run:  .venv/bin/python benchmarks/bench_interference.py [--quick]

Prints, for examples/spatial_cube8.toml (8 cables, 28 pairs) along its trajectory:
  * marinecdpr's whole-array check (:func:`marinecdpr.planning.interference.pose_clearances`:
    cable-cable, cable-platform over the platform's 12 edges) per call, and per step;
  * the cable-cable distances alone (:func:`marinecdpr.geometry.interference.segment_distance`
    on all steps and pairs at once);
  * the same cable-cable distances with FCL (python-fcl, the ``bench`` extra), the collision
    library a user would pick: a capsule per cable (radius 1e-9 m, added back), its transform
    set and ``fcl.distance`` called pair by pair, step by step;
  * the largest difference between the two, m;
  * 1 000 box ``[[obstacles]]`` (the cap; issue 37's hostile input, 1 cm cubes 1 mm apart along
    x), on paper's 4 cables: the culled measure (:func:`marinecdpr.planning.interference.pose_clearances`,
    boxes bounded before they are measured) against every box measured by
    :func:`marinecdpr.geometry.interference.segment_box_distance` one by one, with the boxes
    3 m off the cables' plane (the platform is nearer: no box measured) and 5 cm off it (the
    boxes are the nearest); the share of entries measured, and whether each cable's least
    distance is the same bit for bit.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

import marinecdpr
from marinecdpr.geometry.interference import segment_box_distance, segment_distance
from marinecdpr.geometry.rotations import matrix_from_euler
from marinecdpr.motion.trajectory import evaluate_trajectory
from marinecdpr.planning.interference import pose_clearances
from _common import best_of, machine  # benchmarks/_common.py (the script's folder is on sys.path)

RADIUS = 1e-9  # FCL's capsule needs one; its distance is the axes' less twice this


def _capsule_pose(p0: np.ndarray, p1: np.ndarray):
    """FCL's transform of a capsule along z whose axis is p0-p1 (Rodrigues' rotation of z)."""
    import fcl

    d = p1 - p0
    L = float(np.linalg.norm(d))
    z = np.array([0.0, 0.0, 1.0])
    v, c = np.cross(z, d / L), float(z @ d) / L
    s = float(np.linalg.norm(v))
    if s < 1e-12:
        R = np.eye(3) if c > 0 else np.diag([1.0, -1.0, -1.0])
    else:
        k = v / s
        K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
        a = np.arctan2(s, c)
        R = np.eye(3) + np.sin(a) * K + (1 - np.cos(a)) * K @ K
    return L, fcl.Transform(R, 0.5 * (p0 + p1))


def fcl_pair_distances(starts: np.ndarray, ends: np.ndarray, pairs: np.ndarray) -> np.ndarray:
    """(n_steps, n_pairs) cable-cable distances with FCL, step by step, pair by pair."""
    import fcl

    n, m = starts.shape[:2]
    out = np.empty((n, pairs.shape[0]))
    request = fcl.DistanceRequest()
    for k in range(n):
        objects = []
        for i in range(m):
            L, tf = _capsule_pose(starts[k, i], ends[k, i])
            objects.append(fcl.CollisionObject(fcl.Capsule(RADIUS, L), tf))
        for p, (i, j) in enumerate(pairs):
            out[k, p] = fcl.distance(objects[i], objects[j], request, fcl.DistanceResult()) + 2 * RADIUS
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer steps for FCL")
    args = parser.parse_args()
    print(machine())
    sc = marinecdpr.load_scenario(Path(__file__).resolve().parent.parent / "examples" / "spatial_cube8.toml")
    sc = sc.with_updates("robot", clearance_m=0.01).with_changes(time={"step_s": 0.001, "duration_s": 15.0})
    t = np.arange(sc.time.n_steps) * sc.time.step_s
    platform = evaluate_trajectory(sc.trajectory, t, None)
    robot = sc.robot
    gaps, t_all = best_of(5, lambda: pose_clearances(robot, [], platform.x_PC_C, platform.R_PC))
    ends = platform.x_PC_C[:, None, :] + np.einsum("nij,cj->nci", platform.R_PC, robot.platform_anchors)
    starts = np.broadcast_to(robot.frame_anchors, ends.shape)
    pairs = gaps.pairs
    _, t_cc = best_of(5, lambda: segment_distance(starts[:, pairs[:, 0]], ends[:, pairs[:, 0]],
                                                  starts[:, pairs[:, 1]], ends[:, pairs[:, 1]]))
    n = t.size
    print(f"spatial_cube8, {n} steps, {robot.n_cables} cables, {pairs.shape[0]} pairs:")
    print(f"  marinecdpr, the whole check (cable-cable, cable-platform): {t_all * 1e3:8.1f} ms "
          f"({t_all / n * 1e6:.2f} us/step)")
    print(f"  marinecdpr, cable-cable alone:                              {t_cc * 1e3:8.1f} ms "
          f"({t_cc / n * 1e6:.2f} us/step)")
    k = 1000 if args.quick else n
    fcl_d, t_fcl = best_of(1, lambda: fcl_pair_distances(starts[:k], ends[:k], pairs))
    print(f"  FCL (python-fcl) cable-cable, per step and pair, {k} steps: {t_fcl * 1e3:8.1f} ms "
          f"({t_fcl / k * 1e6:.2f} us/step): {t_fcl / k / (t_cc / n):.0f}x marinecdpr's per step")
    diff = float(np.abs(fcl_d - gaps.cable_cable[:k]).max())
    print(f"  largest difference, FCL against marinecdpr: {diff:.2e} m")
    sys.stdout.flush()
    obstacles_case(1501 if args.quick else 15001)


def obstacles_case(n_steps: int) -> None:
    """1 000 boxes on paper: culled against exhaustive (see the module's docstring)."""
    from marinecdpr.planning.interference import Clearances
    from marinecdpr.scenario.obstacles import BoxObstacle

    sc = marinecdpr.load_scenario("paper").with_updates("robot", clearance_m=0.0)
    t = np.linspace(0.0, 15.0, n_steps)
    path = evaluate_trajectory(sc.trajectory, t, None)
    ends = path.x_PC_C[:, None, :] + np.einsum("nij,cj->nci", path.R_PC, sc.robot.platform_anchors)
    starts = np.broadcast_to(sc.robot.frame_anchors, ends.shape)
    for y in (3.0, 0.05):
        boxes = [BoxObstacle(type="box", center_m=(0.001 * k, y, 0.5), size_m=(0.01, 0.01, 0.01)) for k in range(1000)]
        gaps, t_culled = best_of(1, lambda: pose_clearances(sc.robot, boxes, path.x_PC_C, path.R_PC))

        def exhaustive():
            return np.stack([segment_box_distance(starts, ends, np.asarray(b.center_m), np.eye(3),
                                                  0.5 * np.asarray(b.size_m)) for b in boxes], axis=2)

        every, t_all = best_of(1, exhaustive)
        same = np.array_equal(gaps.per_cable,
                              Clearances(gaps.pairs, gaps.cable_cable, gaps.cable_platform, every).per_cable)
        print(f"1000 boxes at y = {y:g} m, {n_steps} steps, 4 cables: culled {t_culled:6.2f} s "
              f"({np.isfinite(gaps.cable_obstacle).mean() * 100:.2f} % of entries measured), every box measured "
              f"{t_all:6.2f} s ({t_all / t_culled:.0f}x); each cable's least distance the same bit for bit: {same}")
        sys.stdout.flush()


if __name__ == "__main__":
    main()
