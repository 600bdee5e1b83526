"""Boustrophedon coverage paths for a hull-cleaning brush, and their jerk-limited time law.

The robot moves a round brush of diameter ``width_m`` over a panel of the hull in the
frame's x-z plane. Points of that plane are written ``(x, z)``, m, in C's x and z axes.
:func:`coverage_path` lays parallel lanes over the panel (Choset & Pignon's boustrophedon
cellular decomposition, as surveyed by Galceran & Carreras 2013), joins them into one
path of straight segments and times it; :class:`CoveragePath` evaluates the brush centre's
position, velocity and acceleration at any times.

Where the brush centre may go (the *free region*): every point whose brush disc, of radius
``width_m / 2``, lies inside the panel and clear of the holes. That is the panel inset by
``width_m / 2`` minus the holes outset by ``width_m / 2`` (with rounded corners), computed
exactly on each lane; every segment of the path lies in it (to 2e-9 of the radius).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra

from marinecdpr.errors import ScenarioError
from marinecdpr.motion.checks import check_finite, check_positive
from marinecdpr.motion.rail import scurve_move

__all__ = ["CoveragePath", "coverage_path"]

#: the named corners of the panel's bounding box in (x, z): (which x, which z), 0 = min, 1 = max
_STARTS = {"lower_left": (0, 0), "lower_right": (1, 0), "upper_left": (0, 1), "upper_right": (1, 1)}
#: relative tolerance on lengths (of the panel's size) and on the brush radius
_REL = 1e-9
#: kinds of the path's segments: steps between lanes and transfers, lanes, the boundary pass
_STEP, _LANE, _BOUNDARY = 0, 1, 2


@dataclass(frozen=True)
class CoveragePath:
    """A brush path over a panel and its time law (see :func:`coverage_path`).

    The path is a polyline through ``vertices``; each segment is traversed from rest to
    rest, so the brush stops at every vertex.

    Attributes
    ----------
    vertices : ndarray, shape (m + 1, 2)
        The path's corner points in order, ``(x, z)`` in C, m.
    lane_segment : ndarray of bool, shape (m,)
        True for the segments that are lanes, False for the steps between lanes, the
        transfers between cells and the boundary pass.
    boundary_segment : ndarray of bool, shape (m,)
        True for the segments of the boundary pass (``boundary_pass``) and of the transfers
        it needs; all False without it.
    vertex_time_s : ndarray, shape (m + 1,)
        Time at which the brush is (at rest) at each vertex, s; 0 for the first.
    lanes : int
        Number of lanes (lane segments) on the path.
    spacing_m : float
        Distance between neighbouring lanes' centre lines, m: ``width - overlap`` adjusted
        down so the lanes span the panel exactly; ``width - overlap`` when there is one lane.
    direction_deg : float
        Direction of the lanes, deg in [0, 180), from +x towards +z.
    length_m : float
        Length of the path, m.
    duration_s : float
        Time to traverse the path, s.
    boundary_length_m, boundary_duration_s : float
        What the boundary pass costs: the path's length (m) and duration (s) less those of
        the same panel's path without it (which may have one lane fewer); 0 without it.
    speed_m_s, accel_m_s2, jerk_m_s3 : float
        The limits the time law respects (m/s, m/s^2, m/s^3).
    """

    vertices: np.ndarray
    lane_segment: np.ndarray
    boundary_segment: np.ndarray
    vertex_time_s: np.ndarray
    lanes: int
    spacing_m: float
    direction_deg: float
    length_m: float
    duration_s: float
    boundary_length_m: float
    boundary_duration_s: float
    speed_m_s: float
    accel_m_s2: float
    jerk_m_s3: float
    # the time law's constant-jerk phases: start time (s), position along the segment (m),
    # speed (m/s), acceleration (m/s^2) at the phase's start, its jerk (m/s^3), its segment
    _phases: tuple = field(repr=False, compare=False)

    def evaluate(self, t) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Position, velocity and acceleration of the brush centre at times ``t``.

        Parameters
        ----------
        t : array_like, shape (n,)
            Times, s. Times before 0 or after ``duration_s`` give the first or last vertex
            with zero velocity and acceleration.

        Returns
        -------
        p : ndarray, shape (n, 2)
            Position ``(x, z)`` in C, m.
        v : ndarray, shape (n, 2)
            Velocity relative to C, m/s.
        a : ndarray, shape (n, 2)
            Acceleration relative to C, m/s^2.
        """
        t = np.asarray(t, dtype=float)
        if t.ndim > 1:
            raise ScenarioError(f"must be one-dimensional, shape (n,), got shape {t.shape}", key="t")
        t = np.atleast_1d(t)
        if not np.all(np.isfinite(t)):
            raise ScenarioError("must be finite", key="t")
        start, s0, v0, a0, jerk, seg = self._phases
        tc = np.clip(t, 0.0, self.duration_s)
        k = np.clip(np.searchsorted(start, tc, side="right") - 1, 0, start.size - 1)
        tau = tc - start[k]
        j = jerk[k]
        s = s0[k] + tau * (v0[k] + tau * (0.5 * a0[k] + tau * j / 6.0))
        v = v0[k] + tau * (a0[k] + 0.5 * tau * j)
        a = a0[k] + tau * j
        outside = (t < 0.0) | (t > self.duration_s)
        v[outside] = 0.0
        a[outside] = 0.0
        p0 = self.vertices[:-1][seg[k]]
        unit = self.vertices[1:][seg[k]] - p0
        unit /= np.linalg.norm(unit, axis=1)[:, None]
        return p0 + unit * s[:, None], unit * v[:, None], unit * a[:, None]

    def flown(self, t: float) -> tuple[float, float]:
        """How much of the path the brush has travelled by time ``t`` (a partial run).

        Parameters
        ----------
        t : float
            Time since the path's start, s; clipped to ``[0, duration_s]``.

        Returns
        -------
        length_m : float
            Distance along the path by ``t``, m: the segments finished and the part of the
            current one (``length_m`` at ``duration_s``).
        boundary_m : float
            The part of it on the boundary pass's segments (``boundary_segment``: the pass
            along the edges and its transfers), m.
        """
        start, s0, v0, a0, jerk, seg = self._phases
        tc = min(max(float(t), 0.0), self.duration_s)
        k = int(np.clip(np.searchsorted(start, tc, side="right") - 1, 0, start.size - 1))
        tau = tc - start[k]
        along = float(s0[k] + tau * (v0[k] + tau * (0.5 * a0[k] + tau * jerk[k] / 6.0)))
        lengths = np.linalg.norm(np.diff(self.vertices, axis=0), axis=1)
        i = int(seg[k])
        along = min(max(along, 0.0), float(lengths[i]))
        done = float(lengths[:i].sum()) + along
        edge = float(lengths[:i][self.boundary_segment[:i]].sum()) + (along if self.boundary_segment[i] else 0.0)
        return done, edge


def coverage_path(
    panel,
    holes=(),
    *,
    width_m: float,
    overlap_m: float,
    speed_m_s: float,
    accel_m_s2: float,
    jerk_m_s3: float,
    direction_deg: float | None = None,
    start: str = "lower_left",
    boundary_pass: bool = False,
) -> CoveragePath:
    """A boustrophedon (back-and-forth) path for a round brush over a panel, timed.

    Lanes are parallel lines across the panel. On each lane the brush centre runs over
    the part of the line that is in the free region: its disc (radius ``width_m / 2``)
    stays inside the panel and clear of every hole, i.e. the lane ends lie on the panel's
    boundary inset by ``width_m / 2`` or on a hole's boundary outset by ``width_m / 2``.
    The first and last lanes are ``width_m / 2`` inside the panel's extent across the
    lanes, and the lanes between them are evenly spaced, at ``width_m - overlap_m`` or
    less (never more): the spacing used is ``spacing_m``.

    Where a lane line meets the free region in several pieces (holes, a non-convex
    panel), the lanes are grouped into cells (boustrophedon cellular decomposition): a
    cell continues from one lane to the next while each piece has exactly one neighbour
    on the other lane (their spans along the lanes overlap, or the straight step between
    their ends on one side is free). Each cell is swept back and forth, stepping between
    neighbouring lanes' ends; cells are visited greedily, the next one being the one
    whose nearest entry corner (either end of its first or last lane) is closest. Steps
    and transfers are straight where the straight segment is free, otherwise the
    shortest path in a visibility graph of the lane ends and points around the
    boundary's corners.

    Time law: every segment (lane, step, transfer) is traversed from rest to rest with
    a 7-phase S-curve (constant jerk +J, 0, -J, 0, -J, 0, +J, with the cruise and
    constant-acceleration phases shortened to zero on short segments), so position,
    velocity and acceleration are continuous and ``|v| <= speed_m_s``,
    ``|a| <= accel_m_s2``, ``|jerk| <= jerk_m_s3`` along the whole path. The brush stops
    at every corner: simple and exact, at the cost of time on paths with many short
    segments.

    Parameters
    ----------
    panel : array_like, shape (k, 2)
        Vertices ``(x, z)`` of the panel in C, m: a simple polygon (convex or not), in
        either orientation, not closed (a repeated first vertex is dropped).
    holes : sequence of array_like, each shape (k_i, 2)
        Openings to keep the brush off, ``(x, z)`` in C, m: simple polygons strictly
        inside the panel and apart from each other.
    width_m : float
        Brush diameter, m, > 0.
    overlap_m : float
        Overlap between neighbouring lanes' strips, m, in [0, width_m).
    speed_m_s, accel_m_s2, jerk_m_s3 : float
        Limits on the brush centre's speed (m/s), acceleration (m/s^2) and jerk (m/s^3),
        each > 0.
    direction_deg : float, optional
        Direction of the lanes, deg from +x towards +z (taken modulo 180). None: the
        direction, among 0, 90 and the panel's edge directions, that needs the fewest
        lanes (the panel's smallest extent across the lanes); ties go to 0, then 90, then
        the edges in order.
    start : {"lower_left", "lower_right", "upper_left", "upper_right"}
        The corner of the panel's bounding box in (x, z) near which the path starts: it
        starts at the cell entry corner nearest to it.
    boundary_pass : bool
        Also run the brush along the panel's outline inset by ``width_m / 2`` where the
        lanes do not: it cleans the slivers the lanes leave along the edges (where no step
        runs between lane ends). The pass follows the inset outline less its edges along
        the lanes (the first and last lanes lie on them): on a rectangle, its two sides.
        The lanes and the pieces of the pass are ordered to need the shortest transfers,
        the path still starting at the point nearest ``start``: on a rectangle, up one
        side from the start, the lanes back from the far end, up the other side, with no
        transfer and nothing flown twice but the steps between lanes. That needs an odd
        number of lanes (an even number would end on the side it started from, a
        transfer across the panel away from the other side): where the spacing gives an
        even number, one lane more is laid, closer together. What the pass costs, against
        the path without it, is ``boundary_length_m`` and ``boundary_duration_s``. A
        convex panel without holes only.

    Returns
    -------
    CoveragePath

    Raises
    ------
    ScenarioError
        A limit or size that is not a positive number, ``overlap_m`` not in
        [0, width_m), a degenerate or self-intersecting polygon, a hole not inside the
        panel or overlapping another, a brush that fits nowhere, or a free region in
        separate parts (the brush cannot go from one to another without leaving it).

    Notes
    -----
    What is handled: any simple polygon (convex or not) with any number of polygonal
    holes. On a rectangle, and on a convex panel whose free region has its corners on
    lanes, every point the brush centre may reach is within a brush radius of a lane.
    Elsewhere small slivers stay uncleaned: between two lanes next to a corner of the
    free region that no lane reaches (a slanted panel edge, a hole's corner), typically
    well under 1 % of the free region; so do the parts of the panel the disc cannot
    reach at all (corners, gaps narrower than the brush). No pass follows the boundary.
    The order of the cells is greedy, not shortest; the automatic direction counts
    lanes, not path length or time. Detours (steps or transfers that cannot be
    straight) follow a visibility graph whose points go round the boundary's corners at
    a little more than the brush radius: free, slightly longer than the shortest path;
    building it costs O(N^2 E) for N lane ends and corner points and E edges. A free
    region in separate parts raises ScenarioError.
    """
    width = check_positive(width_m, "width_m")
    overlap = check_finite(overlap_m, "overlap_m")
    if overlap < 0.0:
        raise ScenarioError(f"must be >= 0, got {overlap!r}", key="overlap_m")
    if overlap >= width:
        raise ScenarioError(
            f"must be less than width_m = {width!r}, got {overlap!r} (the lane spacing width - overlap must be > 0)",
            key="overlap_m",
        )
    speed = check_positive(speed_m_s, "speed_m_s")
    accel = check_positive(accel_m_s2, "accel_m_s2")
    jerk = check_positive(jerk_m_s3, "jerk_m_s3")
    if not isinstance(start, str) or start not in _STARTS:
        raise ScenarioError(f"must be one of {', '.join(_STARTS)}, got {start!r}", key="start")
    outer = _polygon(panel, "panel")
    inner = [_polygon(h, f"holes[{i}]")[::-1] for i, h in enumerate(holes, 1)]  # clockwise
    scale = float(np.ptp(outer, axis=0).max())
    _check_holes(outer, inner, scale)
    radius = 0.5 * width
    nominal = width - overlap
    tol = _REL * scale

    if direction_deg is None:
        theta = _automatic_direction(outer, width, nominal, tol)
    else:
        theta = check_finite(direction_deg, "direction_deg") % 180.0
    c, s = _cos_sin(theta)
    to_lane = np.array([[c, -s], [s, c]])  # (x, z) @ to_lane = (u, v): u along the lanes
    loops = [outer @ to_lane] + [h @ to_lane for h in inner]
    e0 = np.concatenate(loops)
    e1 = np.concatenate([np.roll(loop, -1, axis=0) for loop in loops])
    geo = _Free(e0, e1, radius, tol, loops)

    # sweep lines across the lanes
    v_lo, v_hi = loops[0][:, 1].min(), loops[0][:, 1].max()
    span = v_hi - v_lo - width
    if span < -tol:
        raise ScenarioError(
            f"the panel is {v_hi - v_lo:.6g} m across the lanes ({theta:.6g} deg), narrower than the brush "
            f"(width_m = {width!r})", key="width_m",
        )
    ring = along = None
    if boundary_pass:
        ring, along = _inset_ring(loops[0], radius, bool(inner), tol)
    if span <= tol:
        lines = np.array([0.5 * (v_lo + v_hi)])
        spacing = nominal
    else:
        gaps = max(1, int(np.ceil(span / nominal - 1e-9)))
        if boundary_pass and along.sum() >= 2 and gaps % 2 == 1:
            # the pass's two sides, one before the lanes and one after, need an odd number
            # of lanes (an even number ends on the side it started from: a transfer across)
            gaps += 1
        spacing = span / gaps
        lines = v_lo + radius + spacing * np.arange(gaps + 1)
        lines[-1] = v_hi - radius
    pieces = [geo.free_intervals(v) for v in lines]
    if not any(len(p) for p in pieces):
        raise ScenarioError(
            f"the brush (width_m = {width!r}) fits nowhere in the panel clear of the holes", key="width_m",
        )

    cells = _cells(pieces, lines, geo)
    corner = np.array([[outer[:, 0].min(), outer[:, 0].max()][_STARTS[start][0]],
                       [outer[:, 1].min(), outer[:, 1].max()][_STARTS[start][1]]]) @ to_lane
    if boundary_pass:
        points, kind = _with_boundary_pass(cells, corner, ring, along, tol)
    else:
        points, is_lane = _sweep(cells, corner, geo)
        kind = np.where(is_lane, _LANE, _STEP).astype(np.int8)
    points, kind = _merge_collinear(points, kind, tol)
    vertices = points @ to_lane.T
    vertices.flags.writeable = False
    lengths = np.linalg.norm(np.diff(vertices, axis=0), axis=1)
    phases, times = _time_law(lengths, speed, accel, jerk)
    is_lane, on_boundary = kind == _LANE, kind == _BOUNDARY
    if boundary_pass:  # the same path without the pass, for what the pass costs
        bare = coverage_path(panel, holes, width_m=width, overlap_m=overlap, speed_m_s=speed, accel_m_s2=accel,
                             jerk_m_s3=jerk, direction_deg=theta, start=start)
    for a in (is_lane, on_boundary, times):
        a.flags.writeable = False
    return CoveragePath(
        vertices=vertices,
        lane_segment=is_lane,
        boundary_segment=on_boundary,
        vertex_time_s=times,
        lanes=int(is_lane.sum()),
        spacing_m=float(spacing),
        direction_deg=float(theta),
        length_m=float(lengths.sum()),
        duration_s=float(times[-1]),
        boundary_length_m=float(lengths.sum()) - bare.length_m if boundary_pass else 0.0,
        boundary_duration_s=float(times[-1]) - bare.duration_s if boundary_pass else 0.0,
        speed_m_s=speed,
        accel_m_s2=accel,
        jerk_m_s3=jerk,
        _phases=phases,
    )


def _inset_ring(outer: np.ndarray, radius: float, holes: bool, tol: float) -> tuple[np.ndarray, np.ndarray]:
    """The convex panel ``outer`` (k, 2), counter-clockwise, in lane coordinates, inset by
    ``radius``: its corners (k', 2), counter-clockwise, and which of its edges (corner i to
    i + 1) run along the lanes (constant v), (k',) bool."""
    edges = np.roll(outer, -1, axis=0) - outer
    turn = edges[:, 0] * np.roll(edges, -1, axis=0)[:, 1] - edges[:, 1] * np.roll(edges, -1, axis=0)[:, 0]
    if holes or np.any(turn < -tol * tol):
        raise ScenarioError("a boundary pass needs a convex panel without holes", key="boundary_pass")
    unit = edges / np.linalg.norm(edges, axis=1)[:, None]
    inward = np.stack([-unit[:, 1], unit[:, 0]], axis=1)  # left of a counter-clockwise edge
    # corner i: where the inset lines of edges i - 1 and i meet
    a0, d0 = np.roll(outer + radius * inward, 1, axis=0), np.roll(unit, 1, axis=0)
    a1, d1 = outer + radius * inward, unit
    cross = d0[:, 0] * d1[:, 1] - d0[:, 1] * d1[:, 0]
    keep = np.abs(cross) > 1e-12  # collinear edges share their inset line: no corner
    w = a1 - a0
    lam = (w[:, 0] * d1[:, 1] - w[:, 1] * d1[:, 0])[keep] / cross[keep]
    ring = a0[keep] + lam[:, None] * d0[keep]
    along = np.abs(np.roll(ring, -1, axis=0)[:, 1] - ring[:, 1]) <= tol
    return ring, along


def _with_boundary_pass(cells, corner: np.ndarray, ring: np.ndarray, along: np.ndarray,
                        tol: float) -> tuple[np.ndarray, np.ndarray]:
    """The lanes and the boundary pass (see :func:`coverage_path`), in lane coordinates:
    points (m + 1, 2) and each segment's kind (m,) (``_LANE``, ``_STEP``, ``_BOUNDARY``).

    ``ring``, ``along``: :func:`_inset_ring`. The pass covers the inset panel's outline
    less its edges along the lanes (the first and last lanes lie on them): one or two
    open chains, or the closed outline when no edge runs along the lanes. The single
    cell's sweep (four ways to enter it) and the chains (either way round) are put in the
    order that needs the shortest transfers (straight: the inset panel is convex), among
    the orders that start at the point nearest ``corner``.
    """
    from itertools import permutations

    if len(cells) != 1:
        raise ScenarioError("a boundary pass needs a convex panel without holes", key="boundary_pass")
    closed = not along.any()
    chains = []
    if not closed:  # walk round from the end of an edge along the lanes, cutting at each such edge
        k = len(ring)
        first = int(np.flatnonzero(along)[0])
        current = None
        for e in (np.arange(1, k + 1) + first) % k:
            if along[e]:
                if current is not None:
                    chains.append(np.array(current))
                current = None
            else:
                current = [ring[e]] if current is None else current
                current.append(ring[(e + 1) % k])
        chains = [c for c in chains if np.linalg.norm(np.diff(c, axis=0), axis=1).sum() > tol]

    lanes = cells[0]

    def sweep(order, side):
        pts, kinds = [], []
        for lane in (lanes if order == 0 else lanes[::-1]):
            v, lo, hi = lane
            a, b = ((lo, v), (hi, v)) if side == 0 else ((hi, v), (lo, v))
            if pts:
                pts.append(np.array(a))
                kinds.append(_STEP)
            else:
                pts.append(np.array(a))
            pts.append(np.array(b))
            kinds.append(_LANE)
            side = 1 - side
        return pts, kinds

    sweeps = [sweep(order, side) for order in (0, 1) for side in (0, 1)]
    if closed:
        # once round from where the lanes end: the pass starts and ends there, no transfer
        best = None
        for pts, kinds in sweeps:
            d = float(np.linalg.norm(pts[0] - corner))
            if best is None or d < best[0] - tol:
                best = (d, pts, kinds)
        _, pts, kinds = best
        end = pts[-1]
        e = int(np.argmin([_point_seg(end, p, q) for p, q in zip(ring, np.roll(ring, -1, axis=0))]))
        loop = [end] + [ring[(e + 1 + i) % len(ring)] for i in range(len(ring))] + [end]
        pts = pts + loop[1:]
        kinds = kinds + [_BOUNDARY] * (len(loop) - 1)
        return np.array(pts), np.array(kinds, dtype=np.int8)

    items = [("sweep", None)] + [("chain", c) for c in chains]
    best = None
    for order in permutations(range(len(items))):
        for variant in np.ndindex(*[4 if items[i][0] == "sweep" else 2 for i in order]):
            parts = []
            for i, var in zip(order, variant):
                if items[i][0] == "sweep":
                    parts.append(sweeps[var])
                else:
                    c = items[i][1] if var == 0 else items[i][1][::-1]
                    parts.append((list(c), [_BOUNDARY] * (len(c) - 1)))
            start_d = float(np.linalg.norm(parts[0][0][0] - corner))
            transfer = sum(float(np.linalg.norm(q[0][0] - p[0][-1])) for p, q in zip(parts[:-1], parts[1:]))
            key = (round(start_d / tol), round(transfer / tol))
            if best is None or key < best[0]:
                best = (key, parts)
    pts, kinds = list(best[1][0][0]), list(best[1][0][1])
    for part_pts, part_kinds in best[1][1:]:
        pts.append(part_pts[0])
        kinds.append(_BOUNDARY)  # the transfer the pass needs (zero long where none is)
        pts += part_pts[1:]
        kinds += part_kinds
    return np.array(pts), np.array(kinds, dtype=np.int8)


# --- inputs -------------------------------------------------------------------------------


def _polygon(points, name: str) -> np.ndarray:
    """A simple polygon's vertices, shape (k, 2), counter-clockwise, repeated vertices dropped."""
    try:
        p = np.asarray(points, dtype=float)
    except (TypeError, ValueError):
        raise ScenarioError("must be an array of (x, z) vertices, shape (k, 2), m", key=name) from None
    if p.ndim != 2 or p.shape[1] != 2 or p.shape[0] < 3:
        raise ScenarioError(f"must be (x, z) vertices, shape (k, 2) with k >= 3, got shape {p.shape}", key=name)
    if not np.all(np.isfinite(p)):
        raise ScenarioError("has a non-finite vertex", key=name)
    scale = float(np.ptp(p, axis=0).max())
    keep = np.linalg.norm(p - np.roll(p, 1, axis=0), axis=1) > 1e-12 * scale
    p = p[keep]
    area = 0.5 * float(np.sum(p[:, 0] * np.roll(p[:, 1], -1) - np.roll(p[:, 0], -1) * p[:, 1])) if len(p) else 0.0
    if len(p) < 3 or abs(area) <= 1e-12 * scale * scale:
        raise ScenarioError("is degenerate: its area is zero", key=name)
    k = len(p)
    q = np.roll(p, -1, axis=0)
    d = q - p
    # neighbouring edges folding back onto each other
    dn = np.roll(d, -1, axis=0)
    fold = (np.abs(d[:, 0] * dn[:, 1] - d[:, 1] * dn[:, 0]) <= 1e-12 * scale * scale) & (np.sum(d * dn, axis=1) < 0)
    if fold.any():
        i = int(np.argmax(fold))
        raise ScenarioError(f"is not a simple polygon: edges {i + 1} and {(i + 1) % k + 1} overlap", key=name)
    # edges that are not neighbours must stay apart
    i, j = np.triu_indices(k, 2)
    pair = ~((i == 0) & (j == k - 1))
    i, j = i[pair], j[pair]
    if i.size:
        dist = _seg_seg(p[i], q[i], p[j], q[j])
        bad = dist <= 1e-12 * scale
        if bad.any():
            b = int(np.argmax(bad))
            raise ScenarioError(f"is not a simple polygon: edges {i[b] + 1} and {j[b] + 1} cross or touch", key=name)
    return p if area > 0 else p[::-1]


def _check_holes(outer: np.ndarray, inner: list[np.ndarray], scale: float) -> None:
    """Raise unless every hole is strictly inside the panel and apart from the others."""
    o0, o1 = outer, np.roll(outer, -1, axis=0)
    tol = 1e-12 * scale
    for n, hole in enumerate(inner, 1):
        h0, h1 = hole, np.roll(hole, -1, axis=0)
        near = _seg_seg(h0[:, None], h1[:, None], o0[None], o1[None]).min() <= tol
        if near or not _inside(hole, o0, o1).all():
            raise ScenarioError("is not strictly inside the panel", key=f"holes[{n}]")
        for m, other in enumerate(inner[:n - 1], 1):
            g0, g1 = other, np.roll(other, -1, axis=0)
            if (_seg_seg(h0[:, None], h1[:, None], g0[None], g1[None]).min() <= tol
                    or _inside(hole[:1], g0, g1)[0] or _inside(other[:1], h0, h1)[0]):
                raise ScenarioError(f"overlaps or touches holes[{m}]", key=f"holes[{n}]")


def _cos_sin(theta_deg: float) -> tuple[float, float]:
    """cos and sin of an angle in degrees, exact at multiples of 90."""
    quarter = theta_deg / 90.0
    if quarter == round(quarter):
        return [(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0)][int(round(quarter)) % 4]
    t = np.radians(theta_deg)
    return float(np.cos(t)), float(np.sin(t))


def _automatic_direction(outer: np.ndarray, width: float, nominal: float, tol: float) -> float:
    """The lane direction, deg in [0, 180), that needs the fewest lanes (0, 90, then edges)."""
    d = np.roll(outer, -1, axis=0) - outer
    candidates = [0.0, 90.0] + list(np.degrees(np.arctan2(d[:, 1], d[:, 0])) % 180.0)
    best, best_n, seen = 0.0, None, []
    for theta in candidates:
        if any(abs(theta - t) < 1e-9 or abs(abs(theta - t) - 180.0) < 1e-9 for t in seen):
            continue
        seen.append(theta)
        c, s = _cos_sin(theta)
        v = -outer[:, 0] * s + outer[:, 1] * c
        span = v.max() - v.min() - width
        if span < -tol:
            continue
        n = 1 if span <= tol else 1 + max(1, int(np.ceil(span / nominal - 1e-9)))
        if best_n is None or n < best_n:
            best, best_n = float(theta), n
    return best


# --- geometry -------------------------------------------------------------------------------


def _point_seg(p: np.ndarray, s0: np.ndarray, s1: np.ndarray) -> np.ndarray:
    """Distance from points p to segments s0-s1 (broadcast, last axis (u, v))."""
    dx, dy = s1[..., 0] - s0[..., 0], s1[..., 1] - s0[..., 1]
    px, py = p[..., 0] - s0[..., 0], p[..., 1] - s0[..., 1]
    dd = dx * dx + dy * dy
    t = np.clip((px * dx + py * dy) / np.where(dd > 0, dd, 1.0), 0.0, 1.0)
    return np.hypot(px - t * dx, py - t * dy)


def _seg_seg(a0: np.ndarray, a1: np.ndarray, b0: np.ndarray, b1: np.ndarray) -> np.ndarray:
    """Distance between segments a0-a1 and b0-b1 (broadcast, last axis (u, v)); 0 where they cross."""

    def orient(o, p, q):
        return (p[..., 0] - o[..., 0]) * (q[..., 1] - o[..., 1]) - (p[..., 1] - o[..., 1]) * (q[..., 0] - o[..., 0])

    crossing = (orient(a0, a1, b0) * orient(a0, a1, b1) < 0) & (orient(b0, b1, a0) * orient(b0, b1, a1) < 0)
    d = np.minimum(np.minimum(_point_seg(a0, b0, b1), _point_seg(a1, b0, b1)),
                   np.minimum(_point_seg(b0, a0, a1), _point_seg(b1, a0, a1)))
    return np.where(crossing, 0.0, d)


def _inside(p: np.ndarray, e0: np.ndarray, e1: np.ndarray) -> np.ndarray:
    """Even-odd test of points p (n, 2) against the closed loops of edges e0-e1 (m, 2)."""
    px, py = p[:, None, 0], p[:, None, 1]
    y0, y1 = e0[None, :, 1], e1[None, :, 1]
    straddle = (y0 > py) != (y1 > py)
    with np.errstate(divide="ignore", invalid="ignore"):
        x = e0[None, :, 0] + (py - y0) * (e1[None, :, 0] - e0[None, :, 0]) / (y1 - y0)
    return (np.sum(straddle & (px < x), axis=1) % 2) == 1


def _linear_interval(alpha, beta, lo, hi, lo_flat, hi_flat):
    """Where lo < alpha u + beta < hi, per row: (start, end); empty as (inf, -inf).

    Rows with alpha ~ 0 (constant in u) use lo_flat < beta < hi_flat: all u or none.
    """
    flat = np.abs(alpha) <= 1e-12
    a = np.where(flat, 1.0, alpha)
    u1, u2 = (lo - beta) / a, (hi - beta) / a
    start, end = np.minimum(u1, u2), np.maximum(u1, u2)
    whole = (lo_flat < beta) & (beta < hi_flat)
    start = np.where(flat, np.where(whole, -np.inf, np.inf), start)
    end = np.where(flat, np.where(whole, np.inf, -np.inf), end)
    return start, end


class _Free:
    """The free region of the brush centre, in lane coordinates (u along the lanes, v across).

    Parameters
    ----------
    e0, e1 : ndarray, shape (n_edges, 2)
        Boundary edges (panel and holes), free side on the left, (u, v), m.
    radius : float
        Brush radius, m.
    tol : float
        Length tolerance, m.
    loops : list of ndarray, each (k, 2)
        The boundary loops, to place roadmap points around their corners.
    """

    def __init__(self, e0, e1, radius, tol, loops):
        self.e0, self.e1, self.r, self.tol, self.loops = e0, e1, radius, tol, loops
        self.r_flat = radius * (1.0 - _REL)  # tangent lanes (parallel edges, vertices) are free
        self.clear_min = radius * (1.0 - 2.0 * _REL)  # a free segment keeps this far from the boundary
        self.nodes = None  # the roadmap: lane ends first (add_ends), then corner points
        self._ends = []
        self._graph = None
        self._routes = {}

    def free_intervals(self, v: float) -> np.ndarray:
        """Where the lane line at ``v`` is free, shape (n, 2): (start, end) in u, m, ascending."""
        e0, e1, r = self.e0, self.e1, self.r
        y0, y1 = e0[:, 1], e1[:, 1]
        hit = (y0 > v) != (y1 > v)
        cross = np.sort(e0[hit, 0] + (v - y0[hit]) * (e1[hit, 0] - e0[hit, 0]) / (y1[hit] - y0[hit]))
        inside = cross.reshape(-1, 2)
        # where the disc meets an edge: the line inside the edge's capsule (convex: one interval)
        d = e1 - e0
        length = np.linalg.norm(d, axis=1)
        du, dv = d[:, 0] / length, d[:, 1] / length
        w = v - y0
        # across the edge: |(u - u0) n_u + w n_v| < r with n = (-dv, du)
        a_lo, a_hi = _linear_interval(-dv, dv * e0[:, 0] + w * du, -r, r, -self.r_flat, self.r_flat)
        # along the edge: 0 < (u - u0) du + w dv < length
        b_lo, b_hi = _linear_interval(du, -du * e0[:, 0] + w * dv, 0.0, length, 0.0, length)
        lo, hi = np.maximum(a_lo, b_lo), np.minimum(a_hi, b_hi)
        for end in (e0, e1):
            h = self.r_flat**2 - (v - end[:, 1]) ** 2
            half = np.sqrt(np.maximum(h, 0.0))
            lo = np.minimum(lo, np.where(h > 0, end[:, 0] - half, np.inf))
            hi = np.maximum(hi, np.where(h > 0, end[:, 0] + half, -np.inf))
        keep = lo < hi
        blocked = sorted(zip(lo[keep], hi[keep]))
        merged = []
        for b_start, b_end in blocked:
            if merged and b_start <= merged[-1][1]:
                merged[-1][1] = max(merged[-1][1], b_end)
            else:
                merged.append([b_start, b_end])
        free = []
        for start, end in inside:
            cur = start
            for b_start, b_end in merged:
                if b_end <= cur or b_start >= end:
                    continue
                if b_start > cur:
                    free.append((cur, b_start))
                cur = max(cur, b_end)
            if cur < end:
                free.append((cur, end))
        free = [f for f in free if f[1] - f[0] > self.tol]
        return np.array(free, dtype=float).reshape(-1, 2)

    def clear(self, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        """Whether segments a-b (n, 2) keep the disc off the boundary (both ends free)."""
        out = np.ones(len(a), dtype=bool)
        lo_e, hi_e = np.minimum(self.e0, self.e1), np.maximum(self.e0, self.e1)
        step = max(1, 4_000_000 // max(1, len(self.e0)))
        for i in range(0, len(a), step):
            ai, bi = a[i:i + step], b[i:i + step]
            lo, hi = np.minimum(ai, bi) - self.r, np.maximum(ai, bi) + self.r
            # only edges whose bounding box comes within r of the segment's can be closer than r
            near = ((lo[:, None, 0] <= hi_e[None, :, 0]) & (hi[:, None, 0] >= lo_e[None, :, 0])
                    & (lo[:, None, 1] <= hi_e[None, :, 1]) & (hi[:, None, 1] >= lo_e[None, :, 1]))
            k, e = np.nonzero(near)
            d = _seg_seg(ai[k], bi[k], self.e0[e], self.e1[e])
            out[i + k[d < self.clear_min]] = False
        return out

    def add_end(self, point: np.ndarray) -> int:
        """Register a lane end as a roadmap node; its index."""
        self._ends.append(np.asarray(point, dtype=float))
        return len(self._ends) - 1

    def point(self, node: int) -> np.ndarray:
        return self._ends[node] if self.nodes is None else self.nodes[node]

    def route(self, i: int, j: int) -> list[np.ndarray]:
        """Free path from lane end i to lane end j: the points after i, ending with j."""
        p, q = self.point(i), self.point(j)
        if np.linalg.norm(q - p) <= self.tol:
            return []
        if self.clear(p[None], q[None])[0]:
            return [q]
        if self._graph is None:
            self._build()
        if i not in self._routes:
            self._routes[i] = dijkstra(self._graph, indices=i, return_predecessors=True)
        dist, pred = self._routes[i]
        if not np.isfinite(dist[j]):
            raise ScenarioError(
                f"the region the brush centre may reach (the panel inset and the holes outset by width_m / 2 = "
                f"{self.r!r} m) is in separate parts: cover each part with its own path"
            )
        path = [j]
        while path[-1] != i:
            path.append(int(pred[path[-1]]))
        return [self.nodes[k] for k in path[-2::-1]]

    def _build(self) -> None:
        """The visibility graph of the lane ends and free points around the boundary's corners."""
        rho = self.r * (1.0 + 1e-6)
        ring = rho / np.cos(np.pi / 8.0)  # chords between neighbours 45 deg apart clear the corner by rho
        angles = np.arange(8) * (np.pi / 4.0)
        extra = []
        for loop in self.loops:
            d_in = loop - np.roll(loop, 1, axis=0)
            d_out = np.roll(loop, -1, axis=0) - loop
            n1 = np.stack([-d_in[:, 1], d_in[:, 0]], axis=1) / np.linalg.norm(d_in, axis=1)[:, None]
            n2 = np.stack([-d_out[:, 1], d_out[:, 0]], axis=1) / np.linalg.norm(d_out, axis=1)[:, None]
            extra += [loop + rho * n1, loop + rho * n2]
            cos_ = np.sum(n1 * n2, axis=1)
            ok = 1.0 + cos_ > 0.2
            extra.append(loop[ok] + rho * (n1[ok] + n2[ok]) / (1.0 + cos_[ok])[:, None])
            extra.append((loop[:, None, :] + ring * np.stack([np.cos(angles), np.sin(angles)], axis=1)).reshape(-1, 2))
        extra = np.concatenate(extra)
        dist = _seg_seg(extra[:, None], extra[:, None], self.e0[None], self.e1[None]).min(axis=1)
        extra = extra[(dist >= self.r_flat) & _inside(extra, self.e0, self.e1)]
        self.nodes = np.concatenate([np.array(self._ends).reshape(-1, 2), extra])
        n = len(self.nodes)
        i, j = np.triu_indices(n, 1)
        ok = self.clear(self.nodes[i], self.nodes[j])
        i, j = i[ok], j[ok]
        w = np.maximum(np.linalg.norm(self.nodes[j] - self.nodes[i], axis=1), 1e-3 * self.tol)
        self._graph = csr_matrix((np.concatenate([w, w]), (np.concatenate([i, j]), np.concatenate([j, i]))),
                                 shape=(n, n))


# --- lanes, cells, the path -----------------------------------------------------------------


def _cells(pieces: list[np.ndarray], lines: np.ndarray, geo: _Free) -> list[list[tuple[float, float, float]]]:
    """Boustrophedon cells: lists of lanes (v, start, end) on consecutive sweep lines."""
    cells: list[list[tuple[float, float, float]]] = []
    prev_cells: list[int] = []
    prev = np.zeros((0, 2))
    for k, (v, cur) in enumerate(zip(lines, pieces)):
        adj = np.zeros((len(prev), len(cur)), dtype=bool)
        for a, (a_lo, a_hi) in enumerate(prev):
            for b, (b_lo, b_hi) in enumerate(cur):
                overlap = min(a_hi, b_hi) - max(a_lo, b_lo) > geo.tol
                if not overlap:
                    v0 = lines[k - 1]
                    ends = np.array([[a_lo, v0], [a_hi, v0]]), np.array([[b_lo, v], [b_hi, v]])
                    overlap = bool(geo.clear(*ends).any())
                adj[a, b] = overlap
        here = []
        for b, (lo, hi) in enumerate(cur):
            above = np.flatnonzero(adj[:, b])
            if len(above) == 1 and adj[above[0]].sum() == 1:  # one neighbour each way: same cell
                cell = prev_cells[above[0]]
            else:
                cell = len(cells)
                cells.append([])
            cells[cell].append((float(v), float(lo), float(hi)))
            here.append(cell)
        prev, prev_cells = cur, here
    return cells


def _sweep(cells, corner: np.ndarray, geo: _Free) -> tuple[np.ndarray, np.ndarray]:
    """The path through all cells: points (m + 1, 2) in (u, v) and which segments are lanes (m,)."""
    # lane ends as roadmap nodes: ends[c][l] = (node at start u, node at end u)
    ends = [[(geo.add_end((lo, v)), geo.add_end((hi, v))) for v, lo, hi in cell] for cell in cells]

    def entries(c):
        """A cell's entry corners: (lane order, side of the first lane: 0 = low u)."""
        n = len(cells[c])
        for order in (range(n), range(n - 1, -1, -1)):
            for side in (0, 1):
                yield order, side

    todo = set(range(len(cells)))
    here = corner
    points, is_lane = [], []
    current_node = None
    while todo:
        # the nearest entry corner of a cell still to do (ties: lowest cell, first listed)
        candidates = [(float(np.linalg.norm(geo.point(ends[c][order[0]][side]) - here)), c, k, order, side)
                      for c in sorted(todo) for k, (order, side) in enumerate(entries(c))]
        _, c, _, lanes, side = min(candidates, key=lambda x: x[:3])
        todo.discard(c)
        for lane in lanes:
            a, b = ends[c][lane][side], ends[c][lane][1 - side]
            if current_node is None:
                points.append(geo.point(a))
            else:
                for p in geo.route(current_node, a):
                    points.append(p)
                    is_lane.append(False)
            points.append(geo.point(b))
            is_lane.append(True)
            current_node = b
            side = 1 - side
        here = geo.point(current_node)
    return np.array(points, dtype=float), np.array(is_lane, dtype=bool)


def _merge_collinear(points: np.ndarray, kind: np.ndarray, tol: float) -> tuple[np.ndarray, np.ndarray]:
    """Drop zero-length segments and join consecutive collinear segments of one kind that
    are not lanes (transfers, steps, the boundary pass)."""
    keep_p, keep_k = [points[0]], []
    for p, k in zip(points[1:], kind):
        if np.linalg.norm(p - keep_p[-1]) <= tol:
            continue
        if keep_k and k != _LANE and keep_k[-1] == k:
            d0 = keep_p[-1] - keep_p[-2]
            d1 = p - keep_p[-1]
            cross = d0[0] * d1[1] - d0[1] * d1[0]
            if abs(cross) <= tol * (np.linalg.norm(d0) + np.linalg.norm(d1)) and np.dot(d0, d1) > 0:
                keep_p[-1] = p
                continue
        keep_p.append(p)
        keep_k.append(k)
    return np.array(keep_p), np.array(keep_k, dtype=np.int8)


# --- time law -------------------------------------------------------------------------------


def _scurve(length: float, v_max: float, a_max: float, j_max: float) -> tuple[np.ndarray, np.ndarray]:
    """A rest-to-rest 7-phase S-curve over ``length`` (:func:`~marinecdpr.motion.rail.scurve_move`):
    the phases' durations (s) and jerks (m/s^3)."""
    move = scurve_move(length, v_max, a_max, j_max)
    return np.array(move.phases_s), np.array([1.0, 0.0, -1.0, 0.0, -1.0, 0.0, 1.0]) * j_max


def _time_law(lengths: np.ndarray, v_max: float, a_max: float, j_max: float):
    """Phase table of the whole path and the time at each vertex."""
    start, s0, v0, a0, jerk, seg = ([] for _ in range(6))
    times = [0.0]
    t = 0.0
    for i, length in enumerate(lengths):
        durations, jerks = _scurve(float(length), v_max, a_max, j_max)
        s = v = a = 0.0
        for dt, j in zip(durations, jerks):
            start.append(t)
            s0.append(s)
            v0.append(v)
            a0.append(a)
            jerk.append(j)
            seg.append(i)
            s += dt * (v + dt * (0.5 * a + dt * j / 6.0))
            v += dt * (a + 0.5 * dt * j)
            a += dt * j
            t += dt
        times.append(t)
    phases = tuple(np.array(x, dtype=float) for x in (start, s0, v0, a0, jerk)) + (np.array(seg, dtype=np.intp),)
    for x in phases:
        x.flags.writeable = False
    return phases, np.array(times)
