"""The scenario's interference check: how close each cable comes to the other cables, the
platform's body and the ``[[obstacles]]``, against ``robot.clearance_m``.

The distances are :mod:`marinecdpr.geometry.interference`'s; this module picks what to
measure from the scenario (which cable pairs, the platform's hull, the obstacles' shapes)
and says in words what comes too close.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from marinecdpr.geometry.interference import (
    BOUND_SLACK, cable_pairs, cable_platform_distance, platform_body, point_segment_distance, segment_box_bounds,
    segment_box_distance, segment_distance, segment_plane_distance,
)
from marinecdpr.geometry.rotations import matrix_from_euler
from marinecdpr.scenario.robot import Robot

__all__ = ["Clearances", "clearances", "pose_clearances", "describe_clearances", "obstacle_labels",
           "obstacle_distances"]


@dataclass(frozen=True)
class Clearances:
    """The cables' distances over a series of poses. Arrays share the first axis ``n_steps``.

    Attributes
    ----------
    pairs : ndarray of int, shape (n_pairs, 2)
        The cable pairs measured (0-based; those sharing an end are not).
    cable_cable : ndarray, shape (n_steps, n_pairs)
        Least distance between the two cables of each pair, m.
    cable_platform : ndarray, shape (n_steps, n_cables)
        Each cable's least distance to the platform's body (0 where it runs into it), m.
    cable_obstacle : ndarray, shape (n_steps, n_cables, n_obstacles)
        Each cable's least distance to each obstacle, m (a plane's signed: negative behind it),
        where it can matter: a box's is ``inf`` where it is neither closer than the clearance
        nor possibly the cable's nearest thing (:func:`obstacle_distances`; it is farther).
        So :attr:`per_cable` and every distance below the clearance are exact.
    """

    pairs: np.ndarray
    cable_cable: np.ndarray
    cable_platform: np.ndarray
    cable_obstacle: np.ndarray

    @property
    def per_cable(self) -> np.ndarray:
        """Each cable's least distance to anything measured, shape (n_steps, n_cables), m."""
        d = np.minimum(self.cable_platform, self.cable_obstacle.min(axis=2, initial=np.inf))
        for k, (i, j) in enumerate(self.pairs):
            d[:, i] = np.minimum(d[:, i], self.cable_cable[:, k])
            d[:, j] = np.minimum(d[:, j], self.cable_cable[:, k])
        return d


_BOUND_PAIRS = 1 << 16
"""How many (segment, box) bounds :func:`obstacle_distances` holds at once."""
_GROUP_BOXES = 32
"""The most boxes in a group :func:`obstacle_distances` first bounds as one."""


_SIGNS = np.array([[i, j, k] for i in (-1.0, 1.0) for j in (-1.0, 1.0) for k in (-1.0, 1.0)])


def _groups(centres: np.ndarray, limit: int = _GROUP_BOXES) -> list[np.ndarray]:
    """The boxes (indices) in groups of at most ``limit`` near each other: halved at the
    median along the centres' widest spread until small enough."""
    todo, done = [np.arange(centres.shape[0])], []
    while todo:
        idx = todo.pop()
        if idx.size <= limit:
            done.append(idx)
            continue
        axis = int(np.argmax(np.ptp(centres[idx], axis=0)))
        order = idx[np.argsort(centres[idx, axis], kind="stable")]
        todo += [order[: idx.size // 2], order[idx.size // 2:]]
    return done


def obstacle_distances(obstacles, starts_C: np.ndarray, ends_C: np.ndarray, clearance_m: float | None = None,
                       nearest: np.ndarray | None = None) -> np.ndarray:
    """Each cable's least distance to each obstacle where it can matter: shape (n_steps,
    n_cables, n_obstacles), m (a plane's signed: negative behind it).

    A plane's distance is measured everywhere. A box's
    (:func:`~marinecdpr.geometry.interference.segment_box_distance`) is measured where it
    could be closer than ``clearance_m``, or be the cable's nearest thing: the nearest of
    the obstacles, and of ``nearest`` (the cable's least distance to everything else). The
    boxes are bounded first in groups (a sphere around each group), then one by one
    (:func:`~marinecdpr.geometry.interference.segment_box_bounds`); where a box's lower
    bound is at least the clearance and above an upper bound of the cable's least distance
    to anything, it is not measured and its entry is ``inf``. So every distance below the
    clearance, and each cable's least distance to anything (that over the obstacles and
    ``nearest``), are the exhaustive measure's, bit for bit.

    Parameters
    ----------
    obstacles : sequence of PlaneObstacle or BoxObstacle
        In C.
    starts_C, ends_C : ndarray, shape (n_steps, n_cables, 3)
        The cables' free spans, in C, m.
    clearance_m : float, optional
        Distances below it are all measured (None: only those that can be the least).
    nearest : ndarray, shape (n_steps, n_cables), optional
        Each cable's least distance to the other things measured (cables, the platform), m;
        default none.
    """
    n, m = starts_C.shape[:2]
    out = np.empty((n, m, len(obstacles)))
    least = np.full((n, m), np.inf) if nearest is None else np.array(nearest, dtype=float)
    boxes = []
    for k, ob in enumerate(obstacles):
        if ob.type == "plane":
            out[..., k] = segment_plane_distance(starts_C, ends_C, np.asarray(ob.point_m, dtype=float),
                                                 np.asarray(ob.normal, dtype=float))
            least = np.minimum(least, out[..., k])
        else:  # a box
            boxes.append((k, np.asarray(ob.center_m, dtype=float),
                          matrix_from_euler(np.radians(np.asarray(ob.orientation_deg, dtype=float))),
                          0.5 * np.asarray(ob.size_m, dtype=float)))
    if not boxes or n * m == 0:
        return out
    cols = np.array([b[0] for b in boxes])
    centres, R_BC, half = (np.stack([b[i] for b in boxes]) for i in (1, 2, 3))
    floor = -np.inf if clearance_m is None else float(clearance_m)
    out[..., cols] = np.inf
    flat = out.reshape(n * m, len(obstacles))  # a view
    p0, p1 = np.reshape(starts_C, (-1, 3)), np.reshape(ends_C, (-1, 3))
    least = least.reshape(-1)
    size = np.maximum(np.abs(p0).max(axis=1), np.abs(p1).max(axis=1))
    # 1. each group of boxes within a sphere: the groups nothing of which can matter
    groups = _groups(centres)
    spheres = []
    for idx in groups:
        corners = centres[idx, None, :] + np.einsum("bij,bkj->bki", R_BC[idx], _SIGNS * half[idx, None, :])
        lo, hi = corners.reshape(-1, 3).min(axis=0), corners.reshape(-1, 3).max(axis=0)
        spheres.append((0.5 * (lo + hi), float(np.linalg.norm(0.5 * (hi - lo))) * (1.0 + BOUND_SLACK)))
    g_lower = np.empty((n * m, len(groups)))
    for g, (c, r) in enumerate(spheres):
        dist = point_segment_distance(c, p0, p1)
        slack = BOUND_SLACK * (size + np.abs(c).max() + r)
        g_lower[:, g] = dist - r - slack
        least = np.minimum(least, dist + r + slack)  # every box of the group lies within
    # 2. the boxes of the groups left, one by one
    bounded = []
    for g, idx in enumerate(groups):
        e = np.flatnonzero(~((g_lower[:, g] > least) & (g_lower[:, g] >= floor)))  # NaN is kept
        lower = np.empty((e.size, idx.size))
        step = max(1, _BOUND_PAIRS // idx.size)
        for s in range(0, e.size, step):
            ee = e[s:s + step]
            lower[s:s + step], upper = segment_box_bounds(p0[ee, None, :], p1[ee, None, :], centres[idx], R_BC[idx],
                                                          half[idx])
            least[ee] = np.minimum(least[ee], upper.min(axis=1))
        bounded.append((e, lower))
    # 3. measured where the lower bound leaves it possible
    for idx, (e, lower) in zip(groups, bounded):
        for j, b in enumerate(idx):
            ee = e[~((lower[:, j] > least[e]) & (lower[:, j] >= floor))]  # NaN is measured
            if ee.size == 0:
                continue
            at = np.unique(ee // m)  # whole steps: the box's turn as on all of them
            where = np.zeros((at.size, m), dtype=bool)
            where[np.searchsorted(at, ee // m), ee % m] = True
            _, centre, R, h = boxes[b]
            flat[ee, cols[b]] = segment_box_distance(starts_C[at], ends_C[at], centre, R, h, where=where)
    return out


def clearances(robot: Robot, obstacles, x_PC: np.ndarray, R_PC: np.ndarray, starts_C: np.ndarray,
               ends_C: np.ndarray) -> Clearances:
    """The cables' distances to each other, the platform and the obstacles at each pose.

    Parameters
    ----------
    robot : Robot
    obstacles : sequence of PlaneObstacle or BoxObstacle
        The scenario's ``obstacles``, in C.
    x_PC : ndarray, shape (n_steps, 3)
        The platform's centre in C, m.
    R_PC : ndarray, shape (n_steps, 3, 3)
    starts_C, ends_C : ndarray, shape (n_steps, n_cables, 3)
        Where each cable's free span leaves the frame (its anchor or its pulley's exit) and
        its platform anchor, in C, m.
    """
    pairs = cable_pairs(robot.frame_anchors, robot.platform_anchors)
    cc = segment_distance(starts_C[:, pairs[:, 0]], ends_C[:, pairs[:, 0]],
                          starts_C[:, pairs[:, 1]], ends_C[:, pairs[:, 1]])[0]
    cc = cc.reshape(x_PC.shape[0], pairs.shape[0])
    cp = cable_platform_distance(platform_body(robot.platform_anchors), x_PC, R_PC, starts_C, ends_C)
    nearest = Clearances(pairs, cc, cp, np.empty(cp.shape + (0,))).per_cable  # all but the obstacles
    return Clearances(pairs=pairs, cable_cable=cc, cable_platform=cp,
                      cable_obstacle=obstacle_distances(obstacles, starts_C, ends_C, robot.clearance_m, nearest))


def pose_clearances(robot: Robot, obstacles, x_PC: np.ndarray, R_PC: np.ndarray) -> Clearances:
    """:func:`clearances` at poses of the platform (the cables' spans from the kinematics,
    over the pulleys if the robot has them); shapes as there."""
    x_PC = np.ascontiguousarray(x_PC, dtype=float)
    R_PC = np.ascontiguousarray(R_PC, dtype=float)
    ends = x_PC[:, None, :] + np.einsum("nij,cj->nci", R_PC, robot.platform_anchors)
    starts = np.broadcast_to(robot.frame_anchors, ends.shape)
    if robot.has_pulleys:
        from marinecdpr.geometry.pulley import pulley_kinematics

        starts = pulley_kinematics(x_PC, R_PC, robot.frame_anchors, robot.pulley_axes, robot.pulley_radii,
                                   robot.platform_anchors, None).exits_C
    return clearances(robot, obstacles, x_PC, R_PC, starts, ends)


def obstacle_labels(obstacles) -> list[str]:
    """How messages name each obstacle: ``obstacle 2 ('hull', a plane)``."""
    return [f"obstacle {k} ({repr(ob.name) + ', ' if ob.name else ''}a {ob.type})"
            for k, ob in enumerate(obstacles, start=1)]


def describe_clearances(c: Clearances, k: int, clearance_m: float, labels: list[str], *, most: int = 3) -> str:
    """What comes closer than ``clearance_m`` at step ``k``, nearest first, in words:
    ``cables 1 and 3 0.012 m apart; cable 2 0 m from the platform`` (at most ``most`` of them)."""
    found: list[tuple[float, str]] = []
    for p, (i, j) in enumerate(c.pairs):
        d = float(c.cable_cable[k, p])
        if d < clearance_m:
            found.append((d, f"cables {i + 1} and {j + 1} {d:.3g} m apart"))
    for i in range(c.cable_platform.shape[1]):
        d = float(c.cable_platform[k, i])
        if d < clearance_m:
            found.append((d, f"cable {i + 1} {d:.3g} m from the platform"
                             + (" (it runs into it)" if d == 0.0 else "")))
        for o, label in enumerate(labels):
            d = float(c.cable_obstacle[k, i, o])
            if d < clearance_m:
                found.append((d, f"cable {i + 1} {d:.3g} m from {label}" + (" (behind it)" if d < 0 else "")))
    found.sort(key=lambda item: item[0])
    words = [w for _, w in found[:most]]
    if len(found) > most:
        words.append(f"{len(found) - most} more")
    return "; ".join(words)
