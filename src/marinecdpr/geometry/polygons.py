"""Polygons in a plane: area, which points are inside, distances to the boundary.

Vertices are ``(k, 2)`` arrays of points in order, either orientation; a ring closes
itself (a repeated first vertex is allowed). Used by the scenario's checks of a cleaning
panel and by the coverage study.
"""

from __future__ import annotations

import numpy as np

__all__ = ["as_polygon", "polygon_area", "points_in_polygon", "edges", "boundary_distance", "boundary_tolerance",
           "inside_or_on"]


def as_polygon(poly, name: str) -> np.ndarray:
    """Vertices as a float (k, 2) array, a repeated closing vertex dropped; ValueError naming
    ``name`` unless k >= 3 finite points."""
    p = np.asarray(poly, dtype=float)
    if p.ndim != 2 or p.shape[1] != 2 or p.shape[0] < 3:
        raise ValueError(f"{name}: expected a polygon of shape (k, 2) with k >= 3, got shape {p.shape}")
    if not np.all(np.isfinite(p)):
        raise ValueError(f"{name}: vertices must be finite")
    if np.array_equal(p[0], p[-1]) and p.shape[0] > 3:
        p = p[:-1]                      # a closed ring given with its first vertex repeated
    return np.ascontiguousarray(p)


def polygon_area(poly) -> float:
    """Area of a simple polygon by the shoelace formula (exact up to rounding).

    Parameters
    ----------
    poly : array_like, shape (k, 2)
        Vertices (x, z) in order, either orientation, m; the ring closes itself (a
        repeated first vertex at the end is allowed).

    Returns
    -------
    float
        Area, m^2 (non-negative).
    """
    p = as_polygon(poly, "polygon")
    x, z = p[:, 0] - p[:, 0].mean(), p[:, 1] - p[:, 1].mean()   # centred: less cancellation
    return 0.5 * abs(float(np.dot(x, np.roll(z, -1)) - np.dot(np.roll(x, -1), z)))


def points_in_polygon(points, poly) -> np.ndarray:
    """Which points are inside a polygon (even-odd rule), vectorised.

    Parameters
    ----------
    points : array_like, shape (..., 2)
        Points (x, z), m.
    poly : array_like, shape (k, 2)
        Polygon vertices (x, z), m.

    Returns
    -------
    ndarray of bool, shape (...)
        True inside. An edge counts as crossing a point's horizontal ray when its ends are
        on opposite sides of the point's z, one end counted as above when level with it
        (points exactly on the boundary may land either side) - the rule the raster uses.
    """
    pts = np.asarray(points, dtype=float)
    p = as_polygon(poly, "polygon")
    shape = pts.shape[:-1]
    px, pz = pts.reshape(-1, 2).T
    inside = np.zeros(px.shape, dtype=bool)
    ax, az = p[:, 0], p[:, 1]
    bx, bz = np.roll(ax, -1), np.roll(az, -1)
    for e in range(p.shape[0]):       # one pass over the points per edge: memory O(points)
        if az[e] == bz[e]:
            continue
        crosses = (az[e] > pz) != (bz[e] > pz)
        xc = ax[e] + (pz - az[e]) * (bx[e] - ax[e]) / (bz[e] - az[e])
        inside ^= crosses & (px < xc)
    return inside.reshape(shape)


def edges(p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each edge's start and end points, (k, 2) each."""
    return p, np.roll(p, -1, axis=0)


def boundary_distance(pts: np.ndarray, poly: np.ndarray) -> np.ndarray:
    """Distance of each of (n, 2) points to the polygon's boundary, (n,)."""
    a, b = edges(poly)
    d = b - a
    t = np.clip(np.einsum("pek,ek->pe", pts[:, None, :] - a[None], d) / np.maximum((d * d).sum(1), 1e-300), 0, 1)
    return np.linalg.norm(pts[:, None, :] - (a[None] + t[..., None] * d[None]), axis=2).min(axis=1)


def boundary_tolerance(poly: np.ndarray) -> float:
    """How near the boundary counts as on it: 1e-9 of the coordinates' size (at least 1e-9)."""
    return 1e-9 * max(1.0, float(np.abs(poly).max()))


def inside_or_on(pts: np.ndarray, poly: np.ndarray) -> np.ndarray:
    """True for each of (n, 2) points inside the polygon or on its boundary."""
    return points_in_polygon(pts, poly) | (boundary_distance(pts, poly) <= boundary_tolerance(poly))
