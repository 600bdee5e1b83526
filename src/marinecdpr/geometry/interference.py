"""Interference: how close the cables come to each other, to the platform and to obstacles.

A cable is the straight segment from where it leaves the frame (its frame anchor, or its
pulley's exit point) to its platform anchor. Three kinds of distance are measured, each
over arrays of poses:

- **cable-cable**: the least distance between two cables' segments
  (:func:`segment_distance`); pairs of cables that share a frame anchor or a platform
  point meet there by design and are not measured (:func:`cable_pairs`);
- **cable-platform**: the platform's body is the convex hull of its cable attachment
  points (:class:`PlatformBody`). A cable touches it where it runs into the body from its
  own attachment point, or comes near one of the body's edges that does not meet its own
  point (:func:`cable_platform_distance`);
- **cable-obstacle**: planes (a hull's side: the distance is signed, negative behind the
  plane) and boxes fixed to the frame (:func:`segment_plane_distance`,
  :func:`segment_box_distance`).

All positions are in C, m, unless a name says P. The cables' sag is not modelled here:
the straight chord stands for the cable (a catenary's sag lies in the vertical plane
through the chord, below it by at most ``w L^2 / (8 T)``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["segment_distance", "point_segment_distance", "segment_plane_distance", "segment_box_distance",
           "segment_box_bounds", "cable_pairs", "PlatformBody", "platform_body", "cable_platform_distance",
           "interference_angle", "SHARED_POINT_M", "BOUND_SLACK"]

SHARED_POINT_M = 1e-9
"""Two cables' anchors closer than this share a point (the scenario's anchor tolerance)."""

_TINY = 1e-300


def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Dot products of 3-vectors over their last axis, broadcast (component by component:
    faster than einsum on broadcast operands)."""
    return a[..., 0] * b[..., 0] + a[..., 1] * b[..., 1] + a[..., 2] * b[..., 2]


def segment_distance(p0: np.ndarray, p1: np.ndarray, q0: np.ndarray, q1: np.ndarray
                     ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Least distance between segments p0-p1 and q0-q1, and where it is attained.

    Minimises ``|p0 + s (p1 - p0) - q0 - t (q1 - q0)|`` over ``s, t`` in [0, 1]: the
    unconstrained stationary point of the two lines, clamped to the segments and the other
    parameter then re-solved and clamped (exact for this convex problem; parallel and
    zero-length segments included).

    Parameters
    ----------
    p0, p1, q0, q1 : ndarray, shape (..., 3)
        The segments' ends, m; broadcast against each other.

    Returns
    -------
    distance, s, t : ndarray, shape (...)
        The distance, m, and the parameters of the closest points along each segment.
    """
    p0, p1, q0, q1 = (np.asarray(a, dtype=float) for a in (p0, p1, q0, q1))
    shape = np.broadcast_shapes(p0.shape, p1.shape, q0.shape, q1.shape)[:-1]
    d1, d2, r = p1 - p0, q1 - q0, p0 - q0  # each segment's own terms at its own shape, then broadcast
    a, e, b = _dot(d1, d1), _dot(d2, d2), _dot(d1, d2)
    c, f = _dot(d1, r), _dot(d2, r)
    scale = np.maximum(np.maximum(a, e), _TINY)
    point_p, point_q = a <= 1e-24 * scale, e <= 1e-24 * scale  # a segment of no length
    denom = a * e - b * b  # >= 0 (Cauchy-Schwarz); 0 for parallel lines
    a_, e_ = np.where(point_p, 1.0, a), np.where(point_q, 1.0, e)  # safe divisors
    crossing = denom > 1e-14 * a * e
    s = np.where(crossing, np.clip((b * f - c * e) / np.where(crossing, denom, 1.0), 0.0, 1.0), 0.0)
    t = (b * s + f) / e_
    t_c = np.clip(t, 0.0, 1.0)  # t outside [0, 1]: clamped, and s the closest point to that end of q
    s = np.where(t_c != t, np.clip((t_c * b - c) / a_, 0.0, 1.0), s)
    t = t_c
    # a segment of no length: the other's closest point to it
    s = np.where(point_p, 0.0, np.where(point_q, np.clip(-c / a_, 0.0, 1.0), s))
    t = np.where(point_q, 0.0, np.where(point_p, np.clip(f / e_, 0.0, 1.0), t))
    s, t = np.broadcast_to(s, shape), np.broadcast_to(t, shape)
    gap = r + s[..., None] * d1 - t[..., None] * d2
    return np.sqrt(_dot(gap, gap)), s, t


def point_segment_distance(x: np.ndarray, q0: np.ndarray, q1: np.ndarray) -> np.ndarray:
    """Distance from points x to segments q0-q1, shape (...), m (arguments (..., 3), broadcast)."""
    return segment_distance(x, x, q0, q1)[0]


def segment_plane_distance(p0: np.ndarray, p1: np.ndarray, point: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """Signed least distance of segments p0-p1 to a plane, shape (...), m.

    Positive on the side the unit ``normal`` points to, negative where the segment reaches
    behind the plane (then the depth of its deepest end). The distance is linear along a
    segment, so it is the smaller of its ends'.

    Parameters
    ----------
    p0, p1 : ndarray, shape (..., 3)
    point, normal : ndarray, shape (3,)
        A point of the plane and its unit normal.
    """
    return np.minimum(_dot(np.asarray(p0) - point, normal), _dot(np.asarray(p1) - point, normal))


_BOX_CORNERS = np.array([[i, j, k] for i in (-1, 1) for j in (-1, 1) for k in (-1, 1)], dtype=float)
_BOX_EDGES = np.array([(a, b) for a in range(8) for b in range(a + 1, 8)
                       if np.abs(_BOX_CORNERS[a] - _BOX_CORNERS[b]).sum() == 2])  # 12 edges


def segment_box_distance(p0: np.ndarray, p1: np.ndarray, centre: np.ndarray, R_BC: np.ndarray,
                         half_size: np.ndarray, where: np.ndarray | None = None) -> np.ndarray:
    """Least distance of segments p0-p1 to a box, shape (...), m (0 where a segment enters it).

    A segment that meets the box (the slab test) is at 0. Otherwise the closest point of
    the box lies on a face, an edge or a corner; on a face only opposite one of the
    segment's ends or along a segment parallel to it, where an edge's distance is the same.
    So the distance is the least of the ends' distances to the box and the segment's to
    the box's 12 edges.

    Parameters
    ----------
    p0, p1 : ndarray, shape (..., 3)
        In C, m.
    centre : ndarray, shape (3,)
        The box's centre in C, m.
    R_BC : ndarray, shape (3, 3)
        The box's axes in C (columns), so a point's box coordinates are ``R_BC.T @ (x - centre)``.
    half_size : ndarray, shape (3,)
        Half the box's size along its axes, m.
    where : ndarray of bool, shape (...), optional
        Measure only these segments: the result is then their distances, shape (n_true,),
        in C order, each the same number, bit for bit, as the whole call's.
    """
    a = (np.asarray(p0, dtype=float) - centre) @ R_BC  # box coordinates
    b = (np.asarray(p1, dtype=float) - centre) @ R_BC
    if where is not None:  # after the turn, on all as above; the rest is element by element
        a, b = a[where], b[where]
    h = np.asarray(half_size, dtype=float)

    def point_box(x: np.ndarray) -> np.ndarray:
        out = np.maximum(np.abs(x) - h, 0.0)
        return np.sqrt(_dot(out, out))

    d = np.minimum(point_box(a), point_box(b))
    corners = _BOX_CORNERS * h
    for i, j in _BOX_EDGES:
        d = np.minimum(d, segment_distance(a, b, corners[i], corners[j])[0])
    # the slab test: the part of [0, 1] inside every pair of faces
    v = b - a
    lo, hi = np.zeros(a.shape[:-1]), np.ones(a.shape[:-1])
    with np.errstate(divide="ignore", invalid="ignore"):
        for k in range(3):
            moving = np.abs(v[..., k]) > 1e-300
            t1 = np.where(moving, (-h[k] - a[..., k]) / np.where(moving, v[..., k], 1.0), -np.inf)
            t2 = np.where(moving, (h[k] - a[..., k]) / np.where(moving, v[..., k], 1.0), np.inf)
            still_in = np.abs(a[..., k]) <= h[k]
            lo = np.where(moving, np.maximum(lo, np.minimum(t1, t2)), np.where(still_in, lo, np.inf))
            hi = np.where(moving, np.minimum(hi, np.maximum(t1, t2)), hi)
    return np.where(lo <= hi, 0.0, d)


BOUND_SLACK = 1e-9
"""The relative allowance :func:`segment_box_bounds` keeps for rounding, against the
coordinates' size (far above the few units in the last place the distances are computed to)."""


def segment_box_bounds(p0: np.ndarray, p1: np.ndarray, centre: np.ndarray, R_BC: np.ndarray,
                       half_size: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Cheap bounds of :func:`segment_box_distance`: ``lower <= distance <= upper``, for
    the values that function computes (rounding included), without its 12 edges.

    The distance ``f(x)`` of a point to a segment is convex and 1-Lipschitz; at the box's
    centre ``c``, off the segment, its gradient is the unit vector ``g`` from the nearest
    point of the segment to ``c``. So over the box ``c + y`` (``y`` within the half sizes
    ``h_i`` along its axes ``a_i``) ``f(c + y) >= f(c) + g . y >= f(c) - sum_i h_i |g . a_i|``
    (the lower bound, never below the bounding sphere's ``f(c) - |h|``), and the box's
    corner towards the segment, ``c - sum_i h_i sign(g . a_i) a_i``, is a point of the box:
    its distance to the segment is the upper bound. Both are tight to the box's size
    squared over the distance. Each is moved out by ``BOUND_SLACK`` times the coordinates'
    size (and the gradient's rounding where the centre is near the segment), so they hold
    for the rounded values too.

    Parameters
    ----------
    p0, p1 : ndarray, shape (..., 3)
        The segments' ends in C, m.
    centre : ndarray, shape (..., 3)
        The boxes' centres in C, m.
    R_BC : ndarray, shape (..., 3, 3)
        The boxes' axes in C (columns), as :func:`segment_box_distance`'s.
    half_size : ndarray, shape (..., 3)
        Half the boxes' sizes along their axes, m. All broadcast against each other.

    Returns
    -------
    lower, upper : ndarray, shape (...)
        m.
    """
    p0, p1, c = (np.asarray(a, dtype=float) for a in (p0, p1, centre))
    R, h = np.asarray(R_BC, dtype=float), np.asarray(half_size, dtype=float)
    d = p1 - p0
    dd = _dot(d, d)
    dd_ = np.where(dd > 0.0, dd, 1.0)[..., None]

    def from_segment(x: np.ndarray) -> np.ndarray:  # x - its nearest point on the segment
        w = x - p0
        t = np.clip(_dot(w, d)[..., None] / dd_, 0.0, 1.0)
        return w - t * d

    v = from_segment(c)
    dist = np.sqrt(_dot(v, v))
    axes = [R[..., :, i] for i in range(3)]
    along = [_dot(v, a) for a in axes]  # v along the box's axes: dist * (g . a_i)
    radius = np.sqrt(_dot(h, h))
    size = (np.maximum(np.abs(p0).max(axis=-1), np.abs(p1).max(axis=-1)) + np.abs(c).max(axis=-1) + radius)
    slack = BOUND_SLACK * size
    sphere = dist - radius - 4.0 * slack
    far = dist > 1e-6 * size  # the gradient is sound (else the sphere alone)
    dist_ = np.where(far, dist, 1.0)
    reach = sum(np.abs(along[i]) * h[..., i] for i in range(3))  # dist * the box's extent along g
    tangent = dist - reach / dist_ - slack * (4.0 + 4.0 * radius / dist_)
    lower = np.where(far, np.maximum(tangent, sphere), sphere)
    corner = c - sum((np.sign(along[i]) * h[..., i])[..., None] * axes[i] for i in range(3))
    u = from_segment(corner)
    upper = np.sqrt(_dot(u, u)) + 4.0 * slack
    return lower, upper


def cable_pairs(frame_anchors: np.ndarray, platform_anchors: np.ndarray) -> np.ndarray:
    """The pairs of cables whose distance is measured: all but those sharing an end.

    Parameters
    ----------
    frame_anchors, platform_anchors : ndarray, shape (n_cables, 3)
        c_i in C and p_i in P, m.

    Returns
    -------
    ndarray of int, shape (n_pairs, 2)
        (i, j) with i < j, 0-based.
    """
    n = frame_anchors.shape[0]
    i, j = np.triu_indices(n, k=1)
    share = ((np.linalg.norm(frame_anchors[i] - frame_anchors[j], axis=1) <= SHARED_POINT_M)
             | (np.linalg.norm(platform_anchors[i] - platform_anchors[j], axis=1) <= SHARED_POINT_M))
    return np.stack([i[~share], j[~share]], axis=1).astype(np.int64)


@dataclass(frozen=True)
class PlatformBody:
    """The platform's body as the cables see it: the convex hull of its attachment points, in P.

    Attributes
    ----------
    edges_P : ndarray, shape (n_edges, 2, 3)
        The hull's edges (for points in a plane, the outline's; on a line, the segment), m.
    away : ndarray of bool, shape (n_cables, n_edges)
        The edges that do not meet cable i's attachment point (those it is measured to).
    normals_P : tuple of ndarray, each shape (n_faces_i, 3)
        A solid hull's outward unit face normals at each cable's attachment point (the
        faces whose planes hold it; none for a point inside). Empty arrays for a flat or
        linear platform, which has no inside a cable could run through.
    solid : bool
        The attachment points span three dimensions.
    """

    edges_P: np.ndarray
    away: np.ndarray
    normals_P: tuple
    solid: bool


def platform_body(platform_anchors: np.ndarray) -> PlatformBody:
    """The convex hull of the platform's attachment points (:class:`PlatformBody`).

    Parameters
    ----------
    platform_anchors : ndarray, shape (n_cables, 3)
        p_i in P, m.
    """
    from scipy.spatial import ConvexHull

    p = np.asarray(platform_anchors, dtype=float)
    n = p.shape[0]
    size = max(float(np.ptp(p, axis=0).max()), 1e-12)
    tol = 1e-9 * size
    centre = p.mean(axis=0)
    _, sv, Vt = np.linalg.svd(p - centre)
    rank = int((sv > 1e-9 * max(sv[0], 1e-300)).sum()) if n > 1 else 0
    unique = [0]
    for k in range(1, n):
        if np.linalg.norm(p[unique] - p[k], axis=1).min() > tol:
            unique.append(k)
    q = p[unique]
    edges: list[tuple[np.ndarray, np.ndarray]] = []
    normals: list[np.ndarray] = [np.zeros((0, 3)) for _ in range(n)]
    if rank == 1:
        along = (q - centre) @ Vt[0]
        edges.append((q[int(np.argmin(along))], q[int(np.argmax(along))]))
    elif rank == 2:
        hull = ConvexHull((q - centre) @ Vt[:2].T)
        ring = list(hull.vertices) + [hull.vertices[0]]  # counter-clockwise in the plane
        edges += [(q[ring[k]], q[ring[k + 1]]) for k in range(len(ring) - 1)]
    elif rank == 3:
        hull = ConvexHull(q)
        eq = hull.equations  # (n_facets, 4): unit outward normal, offset
        for f, simplex in enumerate(hull.simplices):
            for k in range(3):
                a, b = sorted((simplex[k], simplex[(k + 1) % 3]))
                g = hull.neighbors[f][(k + 2) % 3]  # the facet across the edge opposite vertex k+2
                coplanar = np.allclose(eq[f], eq[g], atol=1e-9)
                if not coplanar and f < g:  # a real edge, once
                    edges.append((q[a], q[b]))
        for i in range(n):  # the faces through each attachment point, one normal per plane
            on = np.abs(eq[:, :3] @ p[i] + eq[:, 3]) <= tol
            planes = []
            for row in eq[on, :3]:
                if not any(np.allclose(row, other, atol=1e-9) for other in planes):
                    planes.append(row)
            normals[i] = np.array(planes).reshape(-1, 3)
    edges_P = np.array(edges, dtype=float).reshape(-1, 2, 3)
    away = np.ones((n, edges_P.shape[0]), dtype=bool)
    for i in range(n):
        if edges_P.shape[0]:
            away[i] = point_segment_distance(p[i], edges_P[:, 0], edges_P[:, 1]) > tol
    return PlatformBody(edges_P=edges_P, away=away, normals_P=tuple(normals), solid=rank == 3)


def cable_platform_distance(body: PlatformBody, x_PC: np.ndarray, R_PC: np.ndarray, starts_C: np.ndarray,
                            ends_C: np.ndarray) -> np.ndarray:
    """Each cable's least distance to the platform's body, shape (n_steps, n_cables), m.

    0 where a cable runs from its attachment point into a solid body (its direction
    points inside every face through that point); else its segment's distance to the
    body's edges that do not meet its own point (infinite where there are none).

    Parameters
    ----------
    body : PlatformBody
    x_PC : ndarray, shape (n_steps, 3)
        The platform's centre in C, m.
    R_PC : ndarray, shape (n_steps, 3, 3)
        Its orientation.
    starts_C, ends_C : ndarray, shape (n_steps, n_cables, 3)
        Where each cable leaves the frame and its platform anchor, in C, m.
    """
    n_steps, n_cables = starts_C.shape[:2]
    d = np.full((n_steps, n_cables), np.inf)
    if body.edges_P.shape[0]:
        edges_C = x_PC[:, None, None, :] + np.einsum("nij,ekj->neki", R_PC, body.edges_P)  # (n, e, 2, 3)
        dist = segment_distance(starts_C[:, :, None, :], ends_C[:, :, None, :],
                                edges_C[:, None, :, 0, :], edges_C[:, None, :, 1, :])[0]  # (n, c, e)
        d = np.where(body.away[None], dist, np.inf).min(axis=2)
    if body.solid:
        u_C = starts_C - ends_C
        u_P = np.einsum("nji,ncj->nci", R_PC, u_C)  # the cable's direction from its point, in P
        for i, normals in enumerate(body.normals_P):
            length = np.linalg.norm(u_P[:, i], axis=1)
            if normals.shape[0] == 0:  # a point inside the body: the cable starts inside it
                d[:, i] = 0.0
                continue
            outward = (u_P[:, i] @ normals.T).max(axis=1)
            d[:, i] = np.where(outward < -1e-12 * np.maximum(length, _TINY), 0.0, d[:, i])
    return d


def interference_angle(frame_anchors: np.ndarray, platform_anchors: np.ndarray, R_PC: np.ndarray | None = None
                       ) -> tuple[float, tuple[int, int]]:
    """The least turn of the platform away from which two cables can cross: pi minus the
    largest angle between a pair's frame-anchor offset ``c_j - c_i`` and its platform-anchor
    offset ``R (p_j - p_i)``, over the pairs that share no point, and that pair.

    Two cables i, j can meet only where their segments are coplanar. With the offsets
    antiparallel (angle pi) they form a crossed quadrilateral and meet at some position of
    the platform whatever its orientation's small changes; the smaller pi - angle, the
    nearer the design is to cables that cross in its workspace at that orientation. It is
    WireX's ``getMinInterferenceAngle`` (``WireLib/Interference.cpp``), a design figure of the
    layout, not a distance.

    Parameters
    ----------
    frame_anchors, platform_anchors : ndarray, shape (n_cables, 3)
        c_i in C and p_i in P, m.
    R_PC : ndarray, shape (3, 3), optional
        The platform's orientation (default level).

    Returns
    -------
    angle : float
        rad, in [0, pi].
    pair : tuple of int
        The pair (i, j), 0-based, that sets it.
    """
    pairs = cable_pairs(frame_anchors, platform_anchors)
    R = np.eye(3) if R_PC is None else np.asarray(R_PC, dtype=float)
    a = frame_anchors[pairs[:, 1]] - frame_anchors[pairs[:, 0]]
    b = (platform_anchors[pairs[:, 1]] - platform_anchors[pairs[:, 0]]) @ R.T
    cos = _dot(a, b) / (np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1))
    angles = np.arccos(np.clip(cos, -1.0, 1.0))
    k = int(np.argmax(angles))
    return float(np.pi - angles[k]), (int(pairs[k, 0]), int(pairs[k, 1]))
