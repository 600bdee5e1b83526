"""A curved hull surface tiled into frame placements.

The surface is one side of a hull as a height field: its distance from the centreline
``y = f(x, z)`` over stations x and heights z (S's axes: x forward, y to the side cleaned,
z up), given by a function (an analytic form) or read off a mesh
(:func:`mesh_side`). The frame cleans a flat panel at a time; a patch of the curved
surface can be cleaned from one placement if

- its extent in its own best-fitting plane fits the frame's panel (``width`` along the
  ship, ``height`` across), and
- the surface departs from that plane by at most the tool's stand-off tolerance (its
  :data:`SAMPLES` x :data:`SAMPLES` samples by at most :data:`KEEP_WITHIN` of it).

:func:`tile_surface` lays a grid of patches of the panel's size over the band, and cuts
any patch that breaks either rule into equal pieces (along the side that breaks it, or
that brings the deviation down most) until each keeps both. Each
placement carries its plane (centre, outward normal, the frame's axes in S), the surface's
offsets from the plane over the patch (the tool's stand-off varies by these), its true
area and its extent in the plane.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

__all__ = ["Placement", "tile_surface", "first_grid", "mesh_side", "patch_points", "SAMPLES"]

SAMPLES = 9
"""Points per side of a patch at which the surface is sampled (the plane's fit, the offsets)."""
KEEP_WITHIN = 0.9
"""A patch is kept when its samples stay within this share of the tolerance: the surface
between them then stays within the tolerance (checked on 41 x 41 samples in the tests)."""
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


def fit_placement(f: Callable, x_range, z_range) -> Placement:
    """The placement of a frame over the patch ``x_range`` x ``z_range`` (stations and
    heights in S, m) of the side y = f(x, z) (port: y > 0): the plane fitted to its 9 x 9
    points, its axes and extent (:class:`Placement`)."""
    return _fit(f, x_range, z_range)


def _fit(f: Callable, x_range, z_range) -> Placement:
    P = patch_points(f, x_range, z_range)
    pts = P.reshape(-1, 3)
    centre = pts.mean(axis=0)
    # the plane y = centre_y + b (x - centre_x) + c (z - centre_z) by least squares in y: the
    # surface is a height field over x-z, and a plane fitted across a patch much thinner one way
    # than it is curved (a total least-squares fit) would lie along the patch instead
    d = pts - centre
    (b, c), *_ = np.linalg.lstsq(d[:, [0, 2]], d[:, 1], rcond=None)
    n = np.array([-b, 1.0, -c]) / np.sqrt(1.0 + b * b + c * c)  # out of the hull: towards +y, the side cleaned
    e_x = np.array([1.0, 0.0, 0.0]) - n[0] * n  # the ship's x in the plane
    e_x /= np.linalg.norm(e_x)
    e_z = np.cross(e_x, n)  # up along the plane (a side whose normal points less than 90 deg from +y)
    offsets = (pts - centre) @ n
    u, v = (pts - centre) @ e_x, (pts - centre) @ e_z
    return Placement(x_range=(float(x_range[0]), float(x_range[1])), z_range=(float(z_range[0]), float(z_range[1])),
                     centre_S=centre, normal_S=n, axes_S=np.column_stack([e_x, n, e_z]),
                     offset_range_m=(float(offsets.min()), float(offsets.max())),
                     extent_m=(float(np.ptp(u)), float(np.ptp(v))), area_m2=_area(P))


def first_grid(f: Callable, x_range, z_range, *, width_m: float, height_m: float,
               max_patches: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The stations and heights that cut the band into :func:`tile_surface`'s first grid of
    patches: equal lengths along the surface (not in x and z: a sloping side is longer than
    its stations' span), along the band's middle line each way, each at most 98 % of the
    panel's side. Its (n_x - 1) x (n_z - 1) patches are the fewest the tiling fits, known
    before any is fitted (what a run's size is judged by).

    Returns
    -------
    xs : ndarray, shape (n_x,)
        Stations, m.
    zs : ndarray, shape (n_z,)
        Heights, m.

    Raises
    ------
    ScenarioError
        The grid has more than ``max_patches`` patches (refused before it is made).
    """
    z_mid, x_mid = 0.5 * (z_range[0] + z_range[1]), 0.5 * (x_range[0] + x_range[1])
    along = _lengths(lambda x: np.stack([x, f(x, np.full_like(x, z_mid)), np.full_like(x, z_mid)], -1), x_range)
    up = _lengths(lambda z: np.stack([np.full_like(z, x_mid), f(np.full_like(z, x_mid), z), z], -1), z_range)
    nx, nz = _piece_count(along[1][-1], width_m), _piece_count(up[1][-1], height_m)
    if max_patches is not None and nx * nz > max_patches:
        raise _too_many(f"{nx * nz:,.0f}", width_m, height_m, max_patches)
    return (np.interp(np.linspace(0.0, along[1][-1], int(nx) + 1), along[1], along[0]),
            np.interp(np.linspace(0.0, up[1][-1], int(nz) + 1), up[1], up[0]))


def _too_many(count: str | None, width_m: float, height_m: float, max_patches: int):
    """The refusal of a tiling of ``count`` patches in its first grid (None: its cuts for the
    tolerance passed the budget on the way)."""
    from marinecdpr.errors import ScenarioError

    needs = (f"needs {count} patches of the {width_m:.3g} x {height_m:.3g} m panel, more than the {max_patches:,}"
             if count is not None else
             f"curves so that cutting it into patches flat enough for the tolerance passed the {max_patches:,}")
    return ScenarioError(f"the band {needs} a run may fit: clean a smaller band, or with a larger frame or stand-off "
                         "tolerance")


def tile_surface(f: Callable, x_range, z_range, *, width_m: float, height_m: float, tolerance_m: float,
                 max_patches: int | None = None, progress: Callable[[float], None] | None = None
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
    max_patches : int, optional
        The most patches fitted (the first grid's and every piece cut from them): beyond it
        the tiling stops with a ScenarioError saying so.
    progress : callable(share), optional
        Called now and then with the share of the band's stations x heights settled (each
        patch kept or left uncleanable), 0 to 1.

    Returns
    -------
    placements : list of Placement
        Patches that keep both rules.
    uncleanable : list of Placement
        Patches still curved beyond the tolerance at the smallest size (:data:`MIN_PATCH_M`).

    Raises
    ------
    ScenarioError
        More than ``max_patches`` patches (the first grid alone, or with the pieces cut).
    """
    xs, zs = first_grid(f, x_range, z_range, width_m=width_m, height_m=height_m, max_patches=max_patches)
    nx, nz = xs.size - 1, zs.size - 1
    todo = [_fit(f, (xs[i], xs[i + 1]), (zs[k], zs[k + 1])) for i in range(nx) for k in range(nz)]
    fitted = len(todo)
    band = max((x_range[1] - x_range[0]) * (z_range[1] - z_range[0]), 1e-300)
    settled = 0.0
    limit = KEEP_WITHIN * tolerance_m
    done, bad = [], []
    while todo:
        p = todo.pop()
        if progress is not None and (len(done) + len(bad)) % 256 == 0:
            progress(min(settled / band, 1.0))
        too_wide, too_high = p.extent_m[0] > width_m * (1 + 1e-9), p.extent_m[1] > height_m * (1 + 1e-9)
        if p.deviation_m <= limit and not (too_wide or too_high):
            done.append(p)
            settled += (p.x_range[1] - p.x_range[0]) * (p.z_range[1] - p.z_range[0])
            continue
        # cut the patch into equal pieces along one side: along the side too long for the panel
        # (as many as its extent needs), else, for the tolerance, along the side that brings the
        # deviation down most (as many pieces as a deviation growing with the side's square
        # asks for, at least two)
        if too_wide or too_high:
            axis = 0 if too_wide else 1
            sides = [(axis, int(np.ceil(p.extent_m[axis] / (0.98 * (width_m, height_m)[axis]))))]
        else:
            n = max(2, int(np.ceil(np.sqrt(p.deviation_m / limit))))
            sides = [(0, n), (1, n)]
        options = [(_pieces(f, p, axis, max(n, 2))) for axis, n in sides]
        options = [o for o in options if o]
        if not options:  # the side to cut is already at the smallest size
            bad.append(p)
            settled += (p.x_range[1] - p.x_range[0]) * (p.z_range[1] - p.z_range[0])
            continue
        fitted += sum(len(o) for o in options)
        if max_patches is not None and fitted > max_patches:
            raise _too_many(None, width_m, height_m, max_patches)
        todo += min(options, key=lambda pieces: (not all(q.deviation_m <= limit for q in pieces), len(pieces),
                                                 max(q.deviation_m for q in pieces)))
    if progress is not None:  # the kept and uncleanable patches partition the band: 1 within rounding
        progress(settled / band)
    key = lambda p: (p.x_range[0], p.z_range[0])  # noqa: E731 - along the ship, then up
    return sorted(done, key=key), sorted(bad, key=key)


def _pieces(f: Callable, p: Placement, axis: int, n: int) -> list[Placement]:
    """Patch ``p`` cut into ``n`` equal pieces along x (axis 0) or z (axis 1), each fitted; none
    where a piece would be shorter than :data:`MIN_PATCH_M`."""
    span = (p.x_range, p.z_range)[axis]
    if (span[1] - span[0]) / n < MIN_PATCH_M:
        return []
    cuts = np.linspace(span[0], span[1], n + 1)
    pieces = [(c0, c1) for c0, c1 in zip(cuts[:-1], cuts[1:])]
    return [_fit(f, piece, p.z_range) if axis == 0 else _fit(f, p.x_range, piece) for piece in pieces]


def _lengths(curve: Callable, span, n: int = 4001) -> tuple[np.ndarray, np.ndarray]:
    """The parameters t along ``span`` (n of them) and the curve's length from its start to
    each (the curve: points (n, 3) of a parameter), m."""
    t = np.linspace(span[0], span[1], n)
    P = curve(t)
    return t, np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(P, axis=0), axis=1))])


def _piece_count(length: float, step: float) -> float:
    """The fewest pieces of equal length no longer than 98 % of ``step`` that cut a curve of
    ``length`` (the margin leaves room for the slope across the band, which the middle line
    does not see; of 0.99, 0.98, 0.95 and 0.92 it split fewest patches on paper_clean's
    surface); a float, so that an absurd count is compared before anything is allocated."""
    return max(1.0, float(np.ceil(length / (0.98 * step) - 1e-9)))


def mesh_side(vertices: np.ndarray, triangles: np.ndarray, *, side: str = "port") -> Callable:
    """The surface y = f(x, z) of one side of a hull mesh: at each (x, z), |y| of the
    mesh's triangles facing that side whose projection on the x-z plane holds it (the
    outermost where several do); NaN where none does.

    The triangles are binned by their x-z boxes on a uniform grid of about one triangle a
    cell, so that each point is tested against its cell's few triangles only (a real hull's
    tens of thousands of panels, a surface job's millions of points).

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
    grid = _TriangleGrid(np.stack([a, b, c], axis=1)[:, :, [0, 2]])

    def f(X, Z):
        X, Z = np.asarray(X, dtype=float), np.asarray(Z, dtype=float)
        shape = np.broadcast_shapes(X.shape, Z.shape)
        x, z = np.broadcast_to(X, shape).ravel(), np.broadcast_to(Z, shape).ravel()
        out = np.full(x.size, -np.inf)
        for i0 in range(0, x.size, 4096):  # points in chunks: their (point, triangle) pairs at once
            xs, zs = x[i0:i0 + 4096], z[i0:i0 + 4096]
            point, t = grid.pairs(xs, zs)
            px, pz = xs[point], zs[point]
            at, bt, ct, dt = a[t], b[t], c[t], det[t]
            l1 = ((px - at[:, 0]) * (ct[:, 2] - at[:, 2]) - (ct[:, 0] - at[:, 0]) * (pz - at[:, 2])) / dt
            l2 = ((bt[:, 0] - at[:, 0]) * (pz - at[:, 2]) - (px - at[:, 0]) * (bt[:, 2] - at[:, 2])) / dt
            inside = (l1 >= -1e-12) & (l2 >= -1e-12) & (l1 + l2 <= 1 + 1e-12)
            y = sign * (at[:, 1] + l1 * (bt[:, 1] - at[:, 1]) + l2 * (ct[:, 1] - at[:, 1]))
            np.maximum.at(out[i0:i0 + 4096], point[inside], y[inside])
        return np.where(np.isfinite(out), out, np.nan).reshape(shape)

    return f


class _TriangleGrid:
    """Triangles (n, 3, 2) in a plane binned by their boxes, grown by a margin that holds
    the barycentric test's tolerance, on a uniform grid: :meth:`pairs` gives each point's
    candidate triangles (every triangle whose box holds the point is among them)."""

    def __init__(self, tri: np.ndarray) -> None:
        lo, hi = tri.min(axis=1), tri.max(axis=1)
        span = float(np.max(hi.max(axis=0) - lo.min(axis=0))) if len(tri) else 1.0
        pad = 1e-9 * max(span, 1.0)  # >> the 1e-12 tolerance on barycentrics times a side
        lo, hi = lo - pad, hi + pad
        self.origin = lo.min(axis=0) if len(tri) else np.zeros(2)
        extent = (hi.max(axis=0) - self.origin) if len(tri) else np.ones(2)
        n_cells = max(len(tri), 1)
        cell = np.sqrt(max(extent[0] * extent[1], 1e-300) / n_cells)
        self.n = np.maximum(np.minimum(np.ceil(extent / max(cell, 1e-300)), 4 * n_cells), 1).astype(np.int64)
        self.cell = extent / self.n
        i0 = self._index(lo)
        i1 = self._index(hi)
        counts = (i1[:, 0] - i0[:, 0] + 1) * (i1[:, 1] - i0[:, 1] + 1)
        tri_of = np.repeat(np.arange(len(tri)), counts)
        k = _within(counts)
        w = np.repeat(i1[:, 1] - i0[:, 1] + 1, counts)
        cx = np.repeat(i0[:, 0], counts) + k // w
        cz = np.repeat(i0[:, 1], counts) + k % w
        cells = cx * self.n[1] + cz
        order = np.argsort(cells, kind="stable")
        self.triangles = tri_of[order]
        self.start = np.searchsorted(cells[order], np.arange(self.n[0] * self.n[1] + 1))

    def _index(self, p: np.ndarray) -> np.ndarray:
        return np.clip(np.floor((p - self.origin) / self.cell).astype(np.int64), 0, self.n - 1)

    def pairs(self, x: np.ndarray, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The (point, triangle) pairs to test: each point's index into x, z and a triangle
        of its cell (points outside the grid have none)."""
        p = np.stack([x, z], axis=1)
        inside = np.all((p >= self.origin) & (p <= self.origin + self.cell * self.n), axis=1)
        idx = self._index(np.where(inside[:, None], p, self.origin))
        cell = idx[:, 0] * self.n[1] + idx[:, 1]
        first, count = self.start[cell], np.where(inside, self.start[cell + 1] - self.start[cell], 0)
        return np.repeat(np.arange(len(x)), count), self.triangles[np.repeat(first, count) + _within(count)]


def _within(counts: np.ndarray) -> np.ndarray:
    """Each item's place within its group, groups of ``counts`` items laid end to end:
    [2, 3] -> [0, 1, 0, 1, 2]."""
    return np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)
