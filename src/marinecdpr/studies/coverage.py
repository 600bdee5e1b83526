"""How much of a hull panel a brush cleaned: a raster of passes over the panel.

The brush cleans a disc of diameter ``width_m`` about its centre. Over a recorded or
planned path of the brush's centre (x, z), sampled in time, the cleaned region is the
region swept by that disc while the brush presses within its force band
(``in_contact``): the union of the capsules (disc swept along a straight segment) between
consecutive in-contact samples, and of the disc at an in-contact sample that has no
in-contact neighbour. A sample interval with either end out of contact cleans nothing.
The region is clipped to the panel, a polygon, minus its holes (openings, fittings: not
to be cleaned, and not part of the panel's area).

All coordinates are in the panel's plane, (x, z) in metres, in whatever frame the panel
and the path share (for the planar robot: C's x-z plane). The raster is over the panel's
bounding box; a cell belongs to the panel, and is cleaned, when its centre is.

Passes
    A cell's count is the number of separate passes of the brush that cleaned it: a cell
    swept by two overlapping lanes counts 2, a cell under a slow or resting brush for many
    samples counts 1. A pass starts when the cell is cleaned while not already in a pass,
    and ends when the brush centre is farther than width / 2 + ``pass_margin_m`` from the
    cell (default margin 5 % of the width), whether the brush is in contact or not. The
    margin is a hysteresis: jitter of the tracked path about the brush's edge, and a
    brief lapse of contact while the brush stays put, do not count as new passes; a lift,
    a move away and a return do, and so does a sharp corner for the cells on its inner
    side that the brush uncovers by more than the margin on its way in and sweeps again
    on its way out. Time is resolved to the decimated samples below.

Decimation
    At 1 ms a path has far more samples than the raster can see. The samples on both
    sides of every change of ``in_contact`` are kept, and otherwise a sample is dropped
    when it lies within ``DECIMATE_CELLS`` = 1/4 cell of the chord joining the kept samples
    around it (one O(n) pass), chords being at most ``pass_margin_m`` long. The kept
    polyline is then within 1/4 cell of the recorded one (Hausdorff distance), so the
    swept region moves by at most 1/4 cell; a straight stretch with sub-cell jitter
    becomes a few chords.

Resolution and area error
    A region's area is counted as (cells whose centre is inside) x h^2, h the cell size.
    Each cell the region's boundary crosses errs by less than h^2, and along a curved or
    oblique boundary these errors have both signs and cancel. They add up only along a
    straight boundary parallel to a grid axis: at most h/2 per metre of it. The default h
    is therefore chosen so that

    - h divides the brush width (h = width / N, N whole): a lane of the brush parallel to
      an axis is counted exactly N cells across, wherever it lies, so the errors of its
      two edges cancel exactly;
    - N >= 100 and h <= 0.002 A / P (A, P: the panel's area and perimeter), so that a
      whole axis-parallel boundary as long as the panel's perimeter, e.g. the panel's
      own edges or those of a band of merged lanes across it, costs at most
      h P / 2 <= 0.1 % of the panel: 0.1 percentage points of coverage;
    - the grid has at most ``MAX_CELLS`` (2e7) cells; on panels so large that this binds
      (a 10 m x 10 m panel with a 0.1 m brush: h = 2.3 mm = width / 44), h P / (2 A) is
      smaller still (0.05 % there).

    ``coverage_pct`` is the ratio of cleaned to panel cells, so errors of the panel's own
    edges cancel where the cleaned region reaches them (a fully cleaned panel is exactly
    100 %); the areas in m^2 are that ratio times the panel's exact area (shoelace), so
    ``cleaned_area_m2 + missed_area_m2 == panel_area_m2``. Measured against exact areas
    (``tests/studies/test_coverage.py``; boustrophedons with gaps and overlaps at 0-180 deg
    over 1-10 m panels with 0.1-0.5 m brushes, random polylines, clipped paths) the error
    of ``coverage_pct`` is at most about 0.04 percentage points, usually under 0.01; the
    bound above is the worst case, for long axis-parallel boundaries.

Cost
    O(kept samples x width / h) for the passes (each segment visits its rows once, and
    only the cells entering or leaving the brush), plus O(cells) for the panel's mask
    and the sums: 0.06 s for 600 000 samples of a 10-minute boustrophedon on a 2 x 1.4 m
    panel (``benchmarks/bench_coverage.py``). Jitter larger than 1/4 cell cannot be
    decimated away: every sample is then a segment (about 3 s for 600 000 there).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence

import numpy as np
from numba import njit

from marinecdpr.geometry.polygons import (
    as_polygon, boundary_distance, boundary_tolerance, edges, inside_or_on, points_in_polygon, polygon_area,
)

__all__ = [
    "CoverageMap",
    "coverage_map",
    "default_resolution_m",
    "polygon_area",
    "points_in_polygon",
    "decimate_path",
    "DECIMATE_CELLS",
    "MAX_CELLS",
]

DECIMATE_CELLS = 0.25
"""The decimated path stays within this fraction of a cell of the recorded one."""
MAX_CELLS = 20_000_000
"""The default resolution keeps the raster at most this many cells (80 MB of counts)."""
_HARD_MAX_CELLS = 200_000_000
_MIN_CELLS_ACROSS = 100
_EDGE_BUDGET = 0.001      # h P / (2 A) at most this (0.1 % of the panel)
_cache = True


@dataclass(frozen=True)
class CoverageMap:
    """Passes of the brush over a panel, on a raster of square cells.

    Attributes
    ----------
    x : ndarray, shape (nx,)
        Cell-centre x coordinates, m, in the panel's frame (increasing, spacing ``resolution_m``).
    z : ndarray, shape (nz,)
        Cell-centre z coordinates, m (increasing).
    passes : ndarray of int32, shape (nz, nx)
        Number of separate passes of the brush that cleaned the cell (module notes;
        ``passes[j, i]`` at ``(x[i], z[j])``); 0 missed; -1 outside the panel or in a hole.
    panel_area_m2 : float
        Exact area of the panel less its holes (shoelace), m^2.
    cleaned_area_m2 : float
        Area cleaned at least once, m^2 (``coverage_pct`` of ``panel_area_m2``).
    missed_area_m2 : float
        ``panel_area_m2 - cleaned_area_m2``, m^2.
    overlap_area_m2 : float
        Area cleaned in two or more passes, m^2.
    coverage_pct : float
        Cleaned cells over panel cells, percent.
    overlap_pct : float
        ``overlap_area_m2`` over ``cleaned_area_m2``, percent (0 when nothing was cleaned).
    resolution_m : float
        Cell size h, m.
    """

    x: np.ndarray
    z: np.ndarray
    passes: np.ndarray
    panel_area_m2: float
    cleaned_area_m2: float
    missed_area_m2: float
    overlap_area_m2: float
    coverage_pct: float
    overlap_pct: float
    resolution_m: float


# --------------------------------------------------------------------------- polygons

def _any_proper_crossing(p: np.ndarray, q: np.ndarray) -> bool:
    """Does an edge of ring p properly cross (interiors, at one point) an edge of ring q?"""
    a, b = edges(p)
    c, d = edges(q)
    chunk = max(1, 4_000_000 // max(1, len(c)))
    for s in range(0, len(a), chunk):
        A, B = a[s:s + chunk, None, :], b[s:s + chunk, None, :]

        def orient(P, Q, R):
            return np.sign((Q[..., 0] - P[..., 0]) * (R[..., 1] - P[..., 1])
                           - (Q[..., 1] - P[..., 1]) * (R[..., 0] - P[..., 0]))

        o1, o2 = orient(A, B, c[None]), orient(A, B, d[None])
        o3, o4 = orient(c[None], d[None], A), orient(c[None], d[None], B)
        if np.any((o1 * o2 < 0) & (o3 * o4 < 0)):
            return True
    return False


def _check_holes(panel: np.ndarray, holes: list[np.ndarray]) -> None:
    if _any_proper_crossing(panel, panel):
        raise ValueError("panel: the polygon crosses itself")
    for i, h in enumerate(holes):
        if _any_proper_crossing(h, h):
            raise ValueError(f"holes[{i}]: the polygon crosses itself")
        if _any_proper_crossing(h, panel) or not np.all(inside_or_on(h, panel)):
            raise ValueError(f"holes[{i}]: must lie inside the panel")
        for j in range(i):
            o = holes[j]
            if (_any_proper_crossing(h, o) or np.any(_strictly_inside(h, o))
                    or np.any(_strictly_inside(o, h))):
                raise ValueError(f"holes[{j}] and holes[{i}] overlap; merge them into one hole")


def _strictly_inside(pts: np.ndarray, poly: np.ndarray) -> np.ndarray:
    return points_in_polygon(pts, poly) & (boundary_distance(pts, poly) > boundary_tolerance(poly))


# --------------------------------------------------------------------------- resolution

def default_resolution_m(panel, width_m: float) -> float:
    """The default cell size for a panel and a brush width (see the module's notes).

    h = width / N with N whole, N >= 100, h <= 0.002 A / P (A, P: the panel's area and
    perimeter, holes not counted), and at most ``MAX_CELLS`` cells over the panel's
    bounding box (that limit wins).

    Parameters
    ----------
    panel : array_like, shape (k, 2)
        Panel polygon (x, z), m.
    width_m : float
        Brush diameter, m.

    Returns
    -------
    float
        Cell size, m.
    """
    p = as_polygon(panel, "panel")
    w = _check_width(width_m)
    area = polygon_area(p)
    perimeter = float(np.linalg.norm(np.roll(p, -1, axis=0) - p, axis=1).sum())
    if area <= 0:
        raise ValueError("panel: the polygon has no area")
    n = max(_MIN_CELLS_ACROSS, math.ceil(w / (2 * _EDGE_BUDGET * area / perimeter)))
    span = p.max(axis=0) - p.min(axis=0)
    h_min = math.sqrt(span[0] * span[1] / MAX_CELLS)
    n = max(1, min(n, math.floor(w / h_min)))
    h = w / n
    while _grid_size(span, h) > MAX_CELLS and n > 1:   # rounding of ceil() at the edges
        n -= 1
        h = w / n
    return h


def _grid_size(span: np.ndarray, h: float) -> int:
    return max(1, math.ceil(span[0] / h)) * max(1, math.ceil(span[1] / h))


def _check_width(width_m) -> float:
    w = float(width_m)
    if not (math.isfinite(w) and w > 0):
        raise ValueError(f"width_m must be positive and finite, got {width_m!r}")
    return w


# --------------------------------------------------------------------------- compiled kernels

@njit(cache=_cache)
def _sleeve(px, pz, s, e, tol, max_len, idx, m):
    """Decimate samples s..e (both kept) into idx from position m; returns the new m.

    From the last kept sample a, each later sample q at distance d > tol_w restricts the
    chord's direction to within asin(tol_w / d) of q's direction (q then lies within tol_w
    of the chord's line). A sample may end the chord when its direction is admissible, it
    is within ``max_len`` of a, and it reaches to within ``slack`` of the farthest sample
    so far (which then projects at most ``slack`` beyond the chord's end). With
    tol_w = 0.9 tol and slack = 0.43 tol, every dropped sample is within
    sqrt(tol_w^2 + slack^2) < tol of its chord. The scan stops when no direction is left,
    a sample is beyond ``max_len``, the path turns back by more than ``tol``, or 64 samples
    pass without a possible end; the last possible end is kept and the scan restarts there.
    """
    tol_w = 0.9 * tol
    slack = 0.43 * tol
    idx[m] = s
    m += 1
    a = s
    while a < e:
        have_ref = False
        rx = 1.0
        rz = 0.0
        lo = -np.inf
        hi = np.inf
        dmax = 0.0
        last = a
        i = a + 1
        while i <= e:
            vx = px[i] - px[a]
            vz = pz[i] - pz[a]
            d = math.sqrt(vx * vx + vz * vz)
            if d > max_len or d < dmax - tol or i - last > 64:
                break
            phi = 0.0
            if have_ref and d > 0.0:
                phi = math.atan2(rx * vz - rz * vx, rx * vx + rz * vz)
            if d >= dmax - slack and (not have_ref or (d > 0.0 and lo <= phi <= hi)):
                last = i
            dmax = max(dmax, d)
            if d > tol_w:
                if not have_ref:
                    rx = vx / d
                    rz = vz / d
                    have_ref = True
                    phi = 0.0
                half = math.asin(tol_w / d)
                lo = max(lo, phi - half)
                hi = min(hi, phi + half)
                if lo > hi:
                    break
            i += 1
        if last == a:          # the next sample is farther than max_len: keep it
            last = a + 1
        idx[m] = last
        m += 1
        a = last
    return m


@njit(cache=_cache)
def _decimate(px, pz, contact, tol, max_len):
    """Indices of the kept samples, increasing: a polyline within ``tol`` of the path.

    Each stretch of constant ``contact`` is decimated on its own (:func:`_sleeve`), its
    first and last samples kept: the first and last samples of the path and both samples
    on either side of every change of ``contact`` are kept. Every dropped sample lies
    within ``tol`` (m) of the chord between the kept samples around it, and no chord is
    longer than ``max_len`` (m) unless two consecutive samples are.
    """
    n = px.shape[0]
    idx = np.empty(n, dtype=np.int64)
    m = 0
    s = 0
    for i in range(1, n + 1):
        if i == n or contact[i] != contact[i - 1]:
            m = _sleeve(px, pz, s, i - 1, tol, max_len, idx, m)
            s = i
    return idx[:m]


@njit(cache=_cache, inline="always")
def _cells(lo, hi, x0, h, nx):
    """Indices i (inclusive range) of the cell centres x0 + (i + 1/2) h within [lo, hi], clipped."""
    if not (lo <= hi):
        return 0, -1
    a = (lo - x0) / h - 0.5
    b = (hi - x0) / h - 0.5
    if b < 0.0 or a > nx - 1:
        return 0, -1
    i0 = max(0, int(math.ceil(a)))
    i1 = min(nx - 1, int(math.floor(b)))
    return i0, i1


@njit(cache=_cache, inline="always")
def _minus(c0, c1, p0, p1):
    """[c0, c1] less [p0, p1] (integer ranges; empty when first > last): two ranges."""
    if p0 > p1 or p1 < c0 or p0 > c1:
        return c0, c1, 0, -1
    return c0, min(c1, p0 - 1), max(c0, p1 + 1), c1


@njit(cache=_cache, inline="always")
def _section(ax, az, bx, bz, ux, uz, tlo, thi, rad, z):
    """x-interval of the capsule (segment AB swept by a disc of radius ``rad``) on the line at z.

    (ux, uz) is the segment's unit direction and ax + [tlo, thi] the x-range where the line
    is between the perpendiculars at A and B (tlo > thi: nowhere, or A = B). Returns (lo,
    hi), lo > hi when the line misses the capsule. The capsule is convex, so its section
    is one interval: the hull of the sections of the end discs and of the rectangle
    between them (within ``rad`` of the segment's line, between the perpendiculars).
    """
    lo = np.inf
    hi = -np.inf
    r2 = rad * rad
    d = z - az
    if d * d <= r2:
        s = math.sqrt(r2 - d * d)
        lo = ax - s
        hi = ax + s
    d = z - bz
    if d * d <= r2:
        s = math.sqrt(r2 - d * d)
        lo = min(lo, bx - s)
        hi = max(hi, bx + s)
    if tlo <= thi:
        c = (z - az) * ux
        if uz != 0.0:
            e1 = (c + rad) / uz
            e2 = (c - rad) / uz
            t0 = max(tlo, min(e1, e2))
            t1 = min(thi, max(e1, e2))
        elif -rad <= c <= rad:
            t0 = tlo
            t1 = thi
        else:
            t0 = 1.0
            t1 = 0.0
        if t0 <= t1:
            lo = min(lo, ax + t0)
            hi = max(hi, ax + t1)
    return lo, hi


@njit(cache=_cache)
def _spans(ax, az, bx, bz, r, R, clean, x0, z0, h, nx, nz, r0, r1, q0, q1):
    """Cell ranges of the capsules of radius R and (if ``clean``) r, row by row.

    Writes q0/q1[j] (radius R) and r0/r1[j] (radius r) for the rows each covers; returns
    those rows (jr0, jr1, jR0, jR1) (jr0 > jr1 when not ``clean``).
    """
    ux = bx - ax
    uz = bz - az
    length = math.sqrt(ux * ux + uz * uz)
    seg = length > 0.0
    if seg:
        ux /= length
        uz /= length
    jR0, jR1 = _cells(min(az, bz) - R, max(az, bz) + R, z0, h, nz)
    jr0, jr1 = _cells(min(az, bz) - r, max(az, bz) + r, z0, h, nz)
    if not clean:
        jr0, jr1 = 0, -1
    for j in range(jR0, jR1 + 1):
        z = z0 + (j + 0.5) * h
        tlo = 1.0
        thi = 0.0
        if seg:   # along the segment: 0 <= (x - ax) ux + (z - az) uz <= length
            c = (z - az) * uz
            if ux != 0.0:
                e1 = -c / ux
                e2 = (length - c) / ux
                tlo = min(e1, e2)
                thi = max(e1, e2)
            elif 0.0 <= c <= length:
                tlo = -np.inf
                thi = np.inf
        lo, hi = _section(ax, az, bx, bz, ux, uz, tlo, thi, R, z)
        q0[j], q1[j] = _cells(lo, hi, x0, h, nx)
        if jr0 <= j <= jr1:
            lo, hi = _section(ax, az, bx, bz, ux, uz, tlo, thi, r, z)
            r0[j], r1[j] = _cells(lo, hi, x0, h, nx)
    return jr0, jr1, jR0, jR1


@njit(cache=_cache)
def _enter_disc(passes, state, ax, az, r, x0, z0, h, nx, nz):
    """Every cell of the disc of radius r about A starts a pass unless it is in one."""
    j0, j1 = _cells(az - r, az + r, z0, h, nz)
    for j in range(j0, j1 + 1):
        lo, hi = _section(ax, az, ax, az, 1.0, 0.0, 1.0, 0.0, r, z0 + (j + 0.5) * h)
        i0, i1 = _cells(lo, hi, x0, h, nx)
        for i in range(i0, i1 + 1):
            if state[j, i] == 0:
                passes[j, i] += 1
                state[j, i] = 1


@njit(cache=_cache)
def _rasterise(kx, kz, kc, r, R, x0, z0, h, nx, nz):
    """Pass counts along the kept samples (x, z, in contact), (nz, nx) int32.

    Segment k joins kept samples k-1 and k; it cleans (capsule of radius r) when both are
    in contact; an in-contact sample with neither neighbour in contact cleans its disc. A
    cell is in a pass (``state`` 1) from when it is first cleaned until it is farther than
    R from the brush (contact or not); being cleaned while not in a pass starts one.
    Only the changes are visited: cells entering the cleaning capsule (capsule k less
    capsule k-1) and cells leaving the R-capsule (capsule k-1 less capsule k), each found
    row by row from the capsules' exact sections; per-row ranges are kept from one segment
    to the next.
    """
    passes = np.zeros((nz, nx), dtype=np.int32)
    state = np.zeros((nz, nx), dtype=np.uint8)
    m = kx.shape[0]
    # per-row cell ranges: [previous, current] x [cleaning radius r, presence radius R]
    r0 = np.zeros((2, nz), dtype=np.int64)
    r1 = np.zeros((2, nz), dtype=np.int64)
    q0 = np.zeros((2, nz), dtype=np.int64)
    q1 = np.zeros((2, nz), dtype=np.int64)
    rr = np.array([0, -1, 0, -1])      # row ranges (j0, j1) of the previous r- and R-capsules
    prev_clean = False
    for k in range(m):
        if k > 0:
            cur = k % 2
            prv = 1 - cur
            clean = kc[k - 1] and kc[k]
            jr0, jr1, jR0, jR1 = _spans(kx[k - 1], kz[k - 1], kx[k], kz[k], r, R, clean, x0, z0, h, nx, nz,
                                        r0[cur], r1[cur], q0[cur], q1[cur])
            # leaving: cells of the previous R-capsule outside this one
            for j in range(rr[2], rr[3] + 1):
                c0, c1 = q0[prv, j], q1[prv, j]
                if jR0 <= j <= jR1:
                    a0, a1, b0, b1 = _minus(c0, c1, q0[cur, j], q1[cur, j])
                else:
                    a0, a1, b0, b1 = c0, c1, 0, -1
                for i in range(a0, a1 + 1):
                    state[j, i] = 0
                for i in range(b0, b1 + 1):
                    state[j, i] = 0
            if clean:
                for j in range(jr0, jr1 + 1):
                    if prev_clean and rr[0] <= j <= rr[1]:
                        a0, a1, b0, b1 = _minus(r0[cur, j], r1[cur, j], r0[prv, j], r1[prv, j])
                    else:
                        a0, a1, b0, b1 = r0[cur, j], r1[cur, j], 0, -1
                    for i in range(a0, a1 + 1):
                        if state[j, i] == 0:
                            passes[j, i] += 1
                            state[j, i] = 1
                    for i in range(b0, b1 + 1):
                        if state[j, i] == 0:
                            passes[j, i] += 1
                            state[j, i] = 1
                rr[0] = jr0
                rr[1] = jr1
            rr[2] = jR0
            rr[3] = jR1
            prev_clean = clean
        if kc[k] and (k == 0 or not kc[k - 1]) and (k == m - 1 or not kc[k + 1]):
            _enter_disc(passes, state, kx[k], kz[k], r, x0, z0, h, nx, nz)
    return passes


@njit(cache=_cache)
def _ring_fill(mask, ring, x0, z0, h, value):
    """Set mask cells whose centres are inside the ring (even-odd, the rule of points_in_polygon)."""
    nz, nx = mask.shape
    k = ring.shape[0]
    xs = np.empty(k)
    zmin = ring[:, 1].min()
    zmax = ring[:, 1].max()
    j0 = max(0, int(math.ceil((zmin - z0) / h - 0.5)))
    j1 = min(nz - 1, int(math.floor((zmax - z0) / h - 0.5)))
    for j in range(j0, j1 + 1):
        zc = z0 + (j + 0.5) * h
        c = 0
        for e in range(k):
            ax = ring[e, 0]
            az = ring[e, 1]
            f = e + 1 if e + 1 < k else 0
            bx = ring[f, 0]
            bz = ring[f, 1]
            if (az > zc) != (bz > zc):
                xs[c] = ax + (zc - az) * (bx - ax) / (bz - az)
                c += 1
        s = np.sort(xs[:c])
        for q in range(0, c - 1, 2):
            # centres with s[q] <= x < s[q+1]: an odd number of crossings right of x
            # (points_in_polygon's rule)
            i0 = max(0, int(math.ceil((s[q] - x0) / h - 0.5)))
            i1 = min(nx - 1, int(math.ceil((s[q + 1] - x0) / h - 0.5)) - 1)
            for i in range(i0, i1 + 1):
                mask[j, i] = value


def decimate_path(path, in_contact, *, tol_m: float, max_chord_m: float) -> np.ndarray:
    """The samples :func:`coverage_map` keeps: a polyline within ``tol_m`` of the path.

    Parameters
    ----------
    path : array_like, shape (n, 2)
        Positions (x, z), m, in time order.
    in_contact : array_like of bool, shape (n,)
        Samples on both sides of every change are kept.
    tol_m : float
        Every dropped sample lies within this distance of the chord joining the kept
        samples around it, m (so the polylines are within ``tol_m`` of each other).
    max_chord_m : float
        Longest chord, m (longer only where two consecutive samples are farther apart).

    Returns
    -------
    ndarray of int64, shape (m,)
        Indices of the kept samples, increasing; the first and last are always kept.
    """
    xy = np.asarray(path, dtype=float)
    contact = np.ascontiguousarray(in_contact, dtype=np.bool_)
    if xy.ndim != 2 or xy.shape[1] != 2 or contact.shape != (xy.shape[0],) or xy.shape[0] == 0:
        raise ValueError(f"path (n, 2) and in_contact (n,) expected, got {xy.shape} and {contact.shape}")
    return _decimate(np.ascontiguousarray(xy[:, 0]), np.ascontiguousarray(xy[:, 1]), contact,
                     float(tol_m), float(max_chord_m))


# --------------------------------------------------------------------------- the map

def coverage_map(
    panel,
    holes: Sequence,
    path,
    in_contact,
    *,
    width_m: float,
    resolution_m: float | None = None,
    pass_margin_m: float | None = None,
) -> CoverageMap:
    """Raster of the brush's passes over a panel, and the cleaned, missed and overlapped areas.

    Parameters
    ----------
    panel : array_like, shape (k, 2)
        The panel's outline, a simple polygon (x, z), m, in the frame of ``path``.
    holes : sequence of array_like, each shape (k_i, 2)
        Regions inside the panel not to be cleaned (x, z), m: simple polygons inside the
        panel, not overlapping one another. Excluded from the panel's area.
    path : array_like, shape (n, 2)
        The brush centre over time (x, z), m, in time order (e.g. every 1 ms; n may be
        large, e.g. 600 000).
    in_contact : array_like of bool, shape (n,)
        True where the brush cleans (its normal force within its band). A segment between
        two consecutive samples cleans when both are True; a True sample whose neighbours
        are both False cleans its disc.
    width_m : float
        Diameter of the disc the brush cleans, m.
    resolution_m : float, optional
        Cell size, m. Default :func:`default_resolution_m` (about width / 100 or finer;
        the module's notes give the error bound). A width that is a whole number of
        cells counts straight axis-parallel lanes exactly.
    pass_margin_m : float, optional
        A pass over a cell ends when the brush centre is farther than
        ``width_m / 2 + pass_margin_m`` from it (in contact or not). Default 5 % of the
        width: tracking jitter and brief lapses of contact at the brush's edge do not
        count as new passes.

    Returns
    -------
    CoverageMap

    Raises
    ------
    ValueError
        Malformed or non-finite inputs, holes outside the panel or overlapping, a panel
        smaller than a cell, or a raster over 2e8 cells.
    """
    p = as_polygon(panel, "panel")
    hole_list = [as_polygon(h, f"holes[{i}]") for i, h in enumerate(holes)]
    w = _check_width(width_m)
    xy = np.asarray(path, dtype=float)
    if xy.ndim != 2 or xy.shape[1] != 2:
        raise ValueError(f"path: expected shape (n, 2), got {xy.shape}")
    contact = np.asarray(in_contact)
    if contact.dtype != np.bool_:
        raise ValueError(f"in_contact: expected booleans, got dtype {contact.dtype}")
    if contact.shape != (xy.shape[0],):
        raise ValueError(f"in_contact: expected shape ({xy.shape[0]},) to match path, got {contact.shape}")
    if not np.all(np.isfinite(xy)):
        raise ValueError("path: positions must be finite")
    margin = 0.05 * w if pass_margin_m is None else float(pass_margin_m)
    if not (math.isfinite(margin) and margin >= 0):
        raise ValueError(f"pass_margin_m must be non-negative and finite, got {pass_margin_m!r}")
    _check_holes(p, hole_list)

    panel_area = polygon_area(p) - sum(polygon_area(h) for h in hole_list)
    if resolution_m is None:
        h = default_resolution_m(p, w)
    else:
        h = float(resolution_m)
        if not (math.isfinite(h) and h > 0):
            raise ValueError(f"resolution_m must be positive and finite, got {resolution_m!r}")
    lo = p.min(axis=0)
    span = p.max(axis=0) - lo
    nx, nz = max(1, math.ceil(span[0] / h)), max(1, math.ceil(span[1] / h))
    if nx * nz > _HARD_MAX_CELLS:
        raise ValueError(f"resolution_m = {h:g} m gives {nx} x {nz} cells over the panel; "
                         f"use a coarser resolution (at most {_HARD_MAX_CELLS:.0e} cells)")
    x0, z0 = float(lo[0]), float(lo[1])

    mask = np.zeros((nz, nx), dtype=np.bool_)
    _ring_fill(mask, p, x0, z0, h, True)
    for hole in hole_list:
        _ring_fill(mask, hole, x0, z0, h, False)
    n_panel = int(np.count_nonzero(mask))
    if n_panel == 0:
        raise ValueError(f"the panel contains no cell centre at resolution_m = {h:g} m; use a finer resolution")

    px = np.ascontiguousarray(xy[:, 0])
    pz = np.ascontiguousarray(xy[:, 1])
    kc = np.ascontiguousarray(contact)
    idx = _decimate(px, pz, kc, DECIMATE_CELLS * h, max(margin, DECIMATE_CELLS * h))
    passes = _rasterise(px[idx], pz[idx], kc[idx], 0.5 * w, 0.5 * w + margin, x0, z0, h, nx, nz)
    passes[~mask] = -1

    n_clean = int(np.count_nonzero(passes >= 1))
    n_over = int(np.count_nonzero(passes >= 2))
    frac_clean = n_clean / n_panel
    cleaned = panel_area * frac_clean
    overlap = panel_area * n_over / n_panel
    return CoverageMap(
        x=x0 + (np.arange(nx) + 0.5) * h,
        z=z0 + (np.arange(nz) + 0.5) * h,
        passes=passes,
        panel_area_m2=float(panel_area),
        cleaned_area_m2=float(cleaned),
        missed_area_m2=float(panel_area - cleaned),
        overlap_area_m2=float(overlap),
        coverage_pct=100.0 * frac_clean,
        overlap_pct=100.0 * n_over / n_clean if n_clean else 0.0,
        resolution_m=h,
    )
