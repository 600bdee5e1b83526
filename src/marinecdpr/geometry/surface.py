"""A curved hull surface tiled into frame placements.

The surface is one side of a hull as a height field: its distance from the centreline
``y = f(x, z)`` over stations x and heights z (S's axes: x forward, y to the side cleaned,
z up), given by a function (an analytic form) or read off a mesh
(:func:`mesh_side`). The frame cleans a flat panel at a time; a patch of the curved
surface can be cleaned from one placement if

- its extent in its own best-fitting plane fits the frame's panel (``width`` along the
  ship, ``height`` across), and
- the surface departs from that plane by at most the tool's stand-off tolerance.

:func:`tile_surface` lays a grid of patches of the panel's size over the band, and halves
any patch that breaks either rule (along its longer side) until it keeps both. Each
placement carries its plane (centre, outward normal, the frame's axes in S), the surface's
offsets from the plane over the patch (the tool's stand-off varies by these), its true
area and its extent in the plane.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

__all__ = ["Placement", "tile_surface", "mesh_side", "patch_points", "SAMPLES"]

SAMPLES = 9
"""Points per side of a patch at which the surface is sampled (the plane's fit, the offsets)."""
MIN_PATCH_M = 0.05
"""The smallest patch side tried, m: a surface curved more than the tolerance allows over this
is left uncleanable there."""


@dataclass(frozen=True)
class Placement:
    """One placement of the frame on the surface.

    Attributes
    ----------
    x_range, z_range : tuple of float
        The patch's stations and heights, m (in S).
    centre_S : ndarray, shape (3,)
        The fitted plane's point at the patch's centre, m.
    normal_S : ndarray, shape (3,)
        The plane's unit normal, out of the hull (towards the robot).
    axes_S : ndarray, shape (3, 3)
        The frame's axes in S as columns: x along the ship in the plane, y the normal (the
        frame's y, from the hull towards the robot, as ``cleaning.hull_normal``), z = x cross y,
        up along the plane (a right-handed frame, C's axes of the placed frame).
    offset_range_m : tuple of float
        The least and largest offset of the surface from the plane over the patch, along the
        normal, m (the tool's stand-off varies by their difference).
    extent_m : tuple of float
        The patch's size in its plane, along the frame's x and z, m.
    area_m2 : float
        The curved patch's area, m^2.
    """

    x_range: tuple[float, float]
    z_range: tuple[float, float]
    centre_S: np.ndarray
    normal_S: np.ndarray
    axes_S: np.ndarray
    offset_range_m: tuple[float, float]
    extent_m: tuple[float, float]
    area_m2: float

    @property
    def deviation_m(self) -> float:
        """The largest distance of the surface from the plane over the patch, m."""
        return max(abs(self.offset_range_m[0]), abs(self.offset_range_m[1]))


def patch_points(f: Callable, x_range, z_range, n: int = SAMPLES) -> np.ndarray:
    """The surface's points on an n x n grid over a patch, shape (n, n, 3), m."""
    x = np.linspace(x_range[0], x_range[1], n)
    z = np.linspace(z_range[0], z_range[1], n)
    X, Z = np.meshgrid(x, z, indexing="ij")
    return np.stack([X, f(X, Z), Z], axis=-1)


def _area(P: np.ndarray) -> float:
    """The area of the grid of points P (n, n, 3) as two triangles per cell, m^2."""
    a, b, c, d = P[:-1, :-1], P[1:, :-1], P[1:, 1:], P[:-1, 1:]
    return float(0.5 * (np.linalg.norm(np.cross(b - a, c - a), axis=-1)
                        + np.linalg.norm(np.cross(c - a, d - a), axis=-1)).sum())


def _fit(f: Callable, x_range, z_range) -> Placement:
    P = patch_points(f, x_range, z_range)
    pts = P.reshape(-1, 3)
    centre = pts.mean(axis=0)
    _, _, Vt = np.linalg.svd(pts - centre)
    n = Vt[2] if Vt[2][1] >= 0 else -Vt[2]  # out of the hull: towards +y, the side cleaned
    e_x = np.array([1.0, 0.0, 0.0]) - n[0] * n  # the ship's x in the plane
    e_x /= np.linalg.norm(e_x)
    e_z = np.cross(e_x, n)  # up along the plane (a side whose normal points less than 90 deg from +y)
    offsets = (pts - centre) @ n
    u, v = (pts - centre) @ e_x, (pts - centre) @ e_z
    return Placement(x_range=(float(x_range[0]), float(x_range[1])), z_range=(float(z_range[0]), float(z_range[1])),
                     centre_S=centre, normal_S=n, axes_S=np.column_stack([e_x, n, e_z]),
                     offset_range_m=(float(offsets.min()), float(offsets.max())),
                     extent_m=(float(np.ptp(u)), float(np.ptp(v))), area_m2=_area(P))


def tile_surface(f: Callable, x_range, z_range, *, width_m: float, height_m: float, tolerance_m: float
                 ) -> tuple[list[Placement], list[Placement]]:
    """The band ``x_range`` x ``z_range`` of the surface y = f(x, z) as frame placements.

    Parameters
    ----------
    f : callable(X, Z) -> Y
        The surface's distance from the centreline at stations X and heights Z (arrays), m.
    x_range, z_range : tuple of float
        The band's stations and heights, m.
    width_m, height_m : float
        The frame's panel: what one placement cleans, along the ship and across, m.
    tolerance_m : float
        The tool's stand-off tolerance: the most the surface may depart from the frame's
        plane over a placement, m.

    Returns
    -------
    placements : list of Placement
        Patches that keep both rules.
    uncleanable : list of Placement
        Patches still curved beyond the tolerance at the smallest size (:data:`MIN_PATCH_M`).
    """
    nx = max(1, int(np.ceil((x_range[1] - x_range[0]) / width_m - 1e-9)))
    nz = max(1, int(np.ceil((z_range[1] - z_range[0]) / height_m - 1e-9)))
    xs = np.linspace(x_range[0], x_range[1], nx + 1)
    zs = np.linspace(z_range[0], z_range[1], nz + 1)
    todo = [((xs[i], xs[i + 1]), (zs[k], zs[k + 1])) for i in range(nx) for k in range(nz)]
    done, bad = [], []
    while todo:
        xr, zr = todo.pop()
        p = _fit(f, xr, zr)
        too_wide, too_high = p.extent_m[0] > width_m * (1 + 1e-9), p.extent_m[1] > height_m * (1 + 1e-9)
        if p.deviation_m <= tolerance_m and not (too_wide or too_high):
            done.append(p)
            continue
        dx, dz = xr[1] - xr[0], zr[1] - zr[0]
        # halve the side that breaks a rule; for the tolerance, the longer in the plane
        split_x = too_wide or (not too_high and p.extent_m[0] >= p.extent_m[1])
        if max(dx, dz) / 2 < MIN_PATCH_M:
            bad.append(p)
            continue
        if split_x:
            m = 0.5 * (xr[0] + xr[1])
            todo += [((xr[0], m), zr), ((m, xr[1]), zr)]
        else:
            m = 0.5 * (zr[0] + zr[1])
            todo += [(xr, (zr[0], m)), (xr, (m, zr[1]))]
    key = lambda p: (p.x_range[0], p.z_range[0])  # noqa: E731 - along the ship, then up
    return sorted(done, key=key), sorted(bad, key=key)


def mesh_side(vertices: np.ndarray, triangles: np.ndarray, *, side: str = "port") -> Callable:
    """The surface y = f(x, z) of one side of a hull mesh: at each (x, z), |y| of the
    mesh's triangles facing that side whose projection on the x-z plane holds it (the
    outermost where several do); NaN where none does.

    Parameters
    ----------
    vertices : ndarray, shape (n_vertices, 3)
        m, in S.
    triangles : ndarray of int, shape (n_triangles, 3)
    side : {"port", "starboard"}
        +y or -y.
    """
    sign = 1.0 if side == "port" else -1.0
    P = np.asarray(vertices, dtype=float)[np.asarray(triangles)]
    normal = np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0])
    P = P[sign * normal[:, 1] > 0]  # the triangles facing that side
    a, b, c = P[:, 0], P[:, 1], P[:, 2]
    # barycentric coordinates in the x-z projection
    det = (b[:, 0] - a[:, 0]) * (c[:, 2] - a[:, 2]) - (c[:, 0] - a[:, 0]) * (b[:, 2] - a[:, 2])
    ok = np.abs(det) > 1e-15
    a, b, c, det = a[ok], b[ok], c[ok], det[ok]

    def f(X, Z):
        X, Z = np.asarray(X, dtype=float), np.asarray(Z, dtype=float)
        shape = np.broadcast_shapes(X.shape, Z.shape)
        x, z = np.broadcast_to(X, shape).ravel(), np.broadcast_to(Z, shape).ravel()
        out = np.full(x.size, np.nan)
        for i0 in range(0, x.size, 256):  # points in chunks: (chunk, triangles) at once
            px, pz = x[i0:i0 + 256, None], z[i0:i0 + 256, None]
            l1 = ((px - a[:, 0]) * (c[:, 2] - a[:, 2]) - (c[:, 0] - a[:, 0]) * (pz - a[:, 2])) / det
            l2 = ((b[:, 0] - a[:, 0]) * (pz - a[:, 2]) - (px - a[:, 0]) * (b[:, 2] - a[:, 2])) / det
            inside = (l1 >= -1e-12) & (l2 >= -1e-12) & (l1 + l2 <= 1 + 1e-12)
            y = sign * (a[:, 1] + l1 * (b[:, 1] - a[:, 1]) + l2 * (c[:, 1] - a[:, 1]))
            y = np.where(inside, y, -np.inf).max(axis=1)
            out[i0:i0 + 256] = np.where(np.isfinite(y), y, np.nan)
        return out.reshape(shape)

    return f
