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
    cable_pairs, cable_platform_distance, platform_body, segment_box_distance, segment_distance,
    segment_plane_distance,
)
from marinecdpr.geometry.rotations import matrix_from_euler
from marinecdpr.scenario.robot import Robot

__all__ = ["Clearances", "clearances", "pose_clearances", "describe_clearances", "obstacle_labels"]


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
        Each cable's least distance to each obstacle, m (a plane's signed: negative behind it).
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


def _obstacle_distances(obstacles, starts_C: np.ndarray, ends_C: np.ndarray) -> np.ndarray:
    out = np.empty(starts_C.shape[:2] + (len(obstacles),))
    for k, ob in enumerate(obstacles):
        if ob.type == "plane":
            out[..., k] = segment_plane_distance(starts_C, ends_C, np.asarray(ob.point_m, dtype=float),
                                                 np.asarray(ob.normal, dtype=float))
        else:  # a box
            R_BC = matrix_from_euler(np.radians(np.asarray(ob.orientation_deg, dtype=float)))
            out[..., k] = segment_box_distance(starts_C, ends_C, np.asarray(ob.center_m, dtype=float), R_BC,
                                               0.5 * np.asarray(ob.size_m, dtype=float))
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
    cp = cable_platform_distance(platform_body(robot.platform_anchors), x_PC, R_PC, starts_C, ends_C)
    return Clearances(pairs=pairs, cable_cable=cc.reshape(x_PC.shape[0], pairs.shape[0]), cable_platform=cp,
                      cable_obstacle=_obstacle_distances(obstacles, starts_C, ends_C))


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
