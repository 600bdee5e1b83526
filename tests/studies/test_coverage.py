"""The coverage map against exact geometry and a slow, obvious reference.

shapely is not installed in the project's environment, so the independent references
are exact analytic areas (a lane's rectangle and half-discs; bands of lanes clipped to
the panel by half-plane clipping; the area of the tube about a polyline from its length
and turning angles) and a quasi-Monte Carlo integral of the distance definition with
matplotlib's point-in-polygon; and, cell by cell, a pure numpy reference (each cell
centre's distance to every segment, passes by a per-cell state machine).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from matplotlib.path import Path as MplPath
from scipy.stats import qmc

from marinecdpr.studies.coverage import (
    DECIMATE_CELLS,
    CoverageMap,
    coverage_map,
    decimate_path,
    default_resolution_m,
    points_in_polygon,
    polygon_area,
)


# --------------------------------------------------------------------------- helpers

def rect(x0, z0, x1, z1):
    return np.array([[x0, z0], [x1, z0], [x1, z1], [x0, z1]], dtype=float)


def shoelace(p):
    """Independent area: the trapezoid formula, (k, 2) vertices."""
    p = np.asarray(p, float)
    q = np.roll(p, -1, axis=0)
    return 0.5 * abs(np.sum((q[:, 0] - p[:, 0]) * (q[:, 1] + p[:, 1])))


def polyline(vertices, step):
    """Densely sampled polyline through the vertices, samples about ``step`` apart (all vertices kept)."""
    v = np.asarray(vertices, float)
    out = [v[:1]]
    for a, b in zip(v[:-1], v[1:]):
        n = max(1, int(math.ceil(np.linalg.norm(b - a) / step)))
        t = np.arange(1, n + 1)[:, None] / n
        out.append(a + t * (b - a))
    return np.concatenate(out)


def clip_halfplane(poly, n, c):
    """Sutherland-Hodgman: the part of poly where n . p <= c."""
    out = []
    k = len(poly)
    for i in range(k):
        p, q = poly[i], poly[(i + 1) % k]
        fp, fq = n @ p - c, n @ q - c
        if fp <= 0:
            out.append(p)
        if fp * fq < 0:
            out.append(p + (q - p) * fp / (fp - fq))
    return np.array(out) if out else np.zeros((0, 2))


def strip_area(poly, n, s0, s1):
    """Area of poly within s0 <= n . p <= s1 (n unit)."""
    part = clip_halfplane(np.asarray(poly, float), n, s1)
    if len(part) < 3:
        return 0.0
    part = clip_halfplane(part, -n, -s0)
    return shoelace(part) if len(part) >= 3 else 0.0


def merged(intervals):
    out = []
    for a, b in sorted(intervals):
        if out and a <= out[-1][1]:
            out[-1][1] = max(out[-1][1], b)
        else:
            out.append([a, b])
    return out


def seg_dist(points, a, b):
    """Distances of points (p, 2) to the segment ab."""
    d = b - a
    dd = float(d @ d)
    t = np.zeros(len(points)) if dd == 0 else np.clip((points - a) @ d / dd, 0.0, 1.0)
    return np.hypot(*(points - (a + t[:, None] * d)).T)


def lanes(panel, width, angle, spacing, offset, step=2e-3):
    """A boustrophedon over the panel: straight lanes at ``angle`` (rad), ``spacing`` apart,
    crossing the whole panel, turning outside it (farther than the brush radius plus
    its pass margin). Returns the path, the lanes' offsets s_k along the normal n, and n."""
    c = panel.mean(axis=0)
    u = np.array([math.cos(angle), math.sin(angle)])
    n = np.array([-u[1], u[0]])
    reach = np.abs((panel - c) @ n).max() + width
    half = np.linalg.norm(panel - c, axis=1).max() + 0.6 * width + 0.05
    s = np.arange(-reach + offset, reach, spacing)
    verts = []
    for k, sk in enumerate(s):
        ends = (-half, half) if k % 2 == 0 else (half, -half)
        verts += [c + sk * n + ends[0] * u, c + sk * n + ends[1] * u]
    return polyline(verts, step), s + c @ n, n


def grid_of(cm: CoverageMap):
    X, Z = np.meshgrid(cm.x, cm.z)
    return np.column_stack([X.ravel(), Z.ravel()])


def slow_passes(panel, holes, path, contact, width, h, margin):
    """The reference: on the same grid, for each cell centre its distance to every segment;
    passes by a per-cell state machine (a pass starts when cleaned while not in one, and
    ends when farther than width/2 + margin from a segment of the path). -1 outside."""
    lo = panel.min(axis=0)
    span = panel.max(axis=0) - lo
    nx, nz = int(math.ceil(span[0] / h)), int(math.ceil(span[1] / h))
    x = lo[0] + (np.arange(nx) + 0.5) * h
    z = lo[1] + (np.arange(nz) + 0.5) * h
    X, Z = np.meshgrid(x, z)
    pts = np.column_stack([X.ravel(), Z.ravel()])
    inside = MplPath(panel).contains_points(pts)
    for hole in holes:
        inside &= ~MplPath(hole).contains_points(pts)
    r, R = width / 2, width / 2 + margin
    passes = np.zeros(len(pts), int)
    in_pass = np.zeros(len(pts), bool)
    m = len(path)

    def enter(d):
        new = (d <= r) & ~in_pass
        passes[new] += 1
        in_pass[new] = True

    def isolated(k):
        return contact[k] and (k == 0 or not contact[k - 1]) and (k == m - 1 or not contact[k + 1])

    if isolated(0):
        enter(seg_dist(pts, path[0], path[0]))
    for k in range(1, m):
        d = seg_dist(pts, path[k - 1], path[k])
        in_pass[d > R] = False
        if contact[k - 1] and contact[k]:
            enter(d)
        if isolated(k):
            enter(seg_dist(pts, path[k], path[k]))
    passes[~inside] = -1
    return x, z, passes.reshape(nz, nx)


# --------------------------------------------------------------------------- polygons

def test_polygon_area_is_the_shoelace_formula():
    L = np.array([[0, 0], [3, 0], [3, 1], [1, 1], [1, 2], [0, 2]], float)      # area 3 + 1 = 4
    assert polygon_area(L) == pytest.approx(4.0, abs=1e-15)
    assert polygon_area(L[::-1]) == pytest.approx(4.0, abs=1e-15)
    assert polygon_area(np.vstack([L, L[:1]])) == pytest.approx(4.0, abs=1e-15)
    far = L + [1e5, -3e4]                                                         # far from the origin
    assert polygon_area(far) == pytest.approx(4.0, rel=1e-12)
    k = 7
    star = np.array([[math.cos(2 * math.pi * i / k), math.sin(2 * math.pi * i / k)] for i in range(k)])
    assert polygon_area(star) == pytest.approx(0.5 * k * math.sin(2 * math.pi / k), rel=1e-14)


def test_points_in_polygon_agrees_with_matplotlib():
    rng = np.random.default_rng(0)
    ang = np.sort(rng.uniform(0, 2 * np.pi, 12))
    poly = np.column_stack([np.cos(ang), np.sin(ang)]) * rng.uniform(0.3, 1.0, (12, 1))
    pts = rng.uniform(-1, 1, (20_000, 2))
    np.testing.assert_array_equal(points_in_polygon(pts, poly), MplPath(poly).contains_points(pts))
    assert points_in_polygon(pts.reshape(100, 200, 2), poly).shape == (100, 200)


# --------------------------------------------------------------------------- exact areas

@pytest.mark.parametrize("zc", [0.7, 0.6137, 0.35031])
def test_straight_pass_is_a_rectangle_and_two_half_discs(zc):
    panel = rect(0.0, 0.0, 2.0, 1.4)
    w = 0.2
    path = polyline([(0.45, zc), (1.55, zc)], 1e-3)
    cm = coverage_map(panel, [], path, np.ones(len(path), bool), width_m=w)
    exact = 1.1 * w + math.pi * (w / 2) ** 2
    assert cm.panel_area_m2 == pytest.approx(2.8, rel=1e-14)
    assert cm.cleaned_area_m2 == pytest.approx(exact, rel=2e-4)
    assert abs(cm.coverage_pct - 100 * exact / 2.8) < 0.01
    assert cm.missed_area_m2 == pytest.approx(2.8 - cm.cleaned_area_m2, rel=1e-14)
    assert set(np.unique(cm.passes)) <= {-1, 0, 1}
    assert cm.overlap_area_m2 == 0 and cm.overlap_pct == 0
    # the cleaned cells are those within w/2 of the segment
    pts = grid_of(cm)
    d = seg_dist(pts, np.array([0.45, zc]), np.array([1.55, zc])).reshape(cm.passes.shape)
    inside = cm.passes >= 0
    np.testing.assert_array_equal(cm.passes[inside] == 1, d[inside] <= w / 2)


def test_pass_across_the_panel_edge_is_clipped():
    panel = rect(0.0, 0.0, 2.0, 1.4)
    w = 0.25
    zc = 0.83
    path = polyline([(-0.7, zc), (1.2, zc)], 1e-3)          # starts outside the panel
    cm = coverage_map(panel, [], path, np.ones(len(path), bool), width_m=w)
    exact = 1.2 * w + 0.5 * math.pi * (w / 2) ** 2          # rectangle from x = 0, half-disc at x = 1.2
    assert cm.cleaned_area_m2 == pytest.approx(exact, rel=5e-4)


def test_two_lanes_with_a_gap_leave_the_exact_strip():
    panel = rect(0.0, 0.0, 2.0, 1.4)
    w, gap = 0.2, 0.0731
    z1 = 0.41
    z2 = z1 + w + gap
    path = polyline([(-0.3, z1), (2.3, z1), (2.3, z2), (-0.3, z2)], 1e-3)   # turn outside the panel
    cm = coverage_map(panel, [], path, np.ones(len(path), bool), width_m=w)
    h = cm.resolution_m
    assert cm.cleaned_area_m2 == pytest.approx(2 * 2.0 * w, abs=2.0 * h)    # at most a row of cells
    assert cm.missed_area_m2 == pytest.approx(2.8 - 4 * w, abs=2.0 * h)
    band = (cm.z > z1) & (cm.z < z2)
    assert set(np.unique(cm.passes[band])) == {0, 1}
    gap_cells = np.count_nonzero(cm.passes[band] == 0)
    assert gap_cells * h * h == pytest.approx(2.0 * gap, abs=2.0 * h)
    assert cm.passes.max() == 1


@pytest.mark.parametrize("lift", [True, False])
def test_overlapping_lanes_count_twice_in_the_exact_strip(lift):
    panel = rect(0.0, 0.0, 2.0, 1.4)
    w, lap = 0.2, 0.0413
    z1 = 0.52
    z2 = z1 + w - lap
    if lift:      # lane, lift and return to the start, lane
        a = polyline([(-0.3, z1), (2.3, z1)], 1e-3)
        b = polyline([(2.3, z1), (-0.3, z2)], 1e-3)[1:-1]
        c = polyline([(-0.3, z2), (2.3, z2)], 1e-3)
        path = np.vstack([a, b, c])
        contact = np.r_[np.ones(len(a), bool), np.zeros(len(b), bool), np.ones(len(c), bool)]
    else:         # boustrophedon, the turn outside the panel
        path = polyline([(-0.3, z1), (2.3, z1), (2.3, z2), (-0.3, z2)], 1e-3)
        contact = np.ones(len(path), bool)
    cm = coverage_map(panel, [], path, contact, width_m=w)
    h = cm.resolution_m
    assert cm.overlap_area_m2 == pytest.approx(2.0 * lap, abs=2.0 * h)
    assert cm.cleaned_area_m2 == pytest.approx(2.0 * (2 * w - lap), abs=2.0 * h)
    assert cm.overlap_pct == pytest.approx(100 * lap / (2 * w - lap), abs=100 * h / (2 * w - lap))
    twice = (cm.z > z2 - w / 2) & (cm.z < z1 + w / 2)
    inner = (cm.z > z2 - w / 2 + h) & (cm.z < z1 + w / 2 - h)
    assert np.all(cm.passes[inner] == 2)
    assert np.all(cm.passes[~twice] <= 1)


def test_out_of_contact_samples_clean_nothing():
    panel = rect(0.0, 0.0, 2.0, 1.4)
    w = 0.2
    path = polyline([(0.2, 0.3), (1.8, 0.3)], 1e-3)
    x = path[:, 0]
    contact = (x <= 0.7) | (x >= 1.3)
    a, b = x[contact & (x <= 0.7)].max(), x[contact & (x >= 1.3)].min()   # the last and first in contact
    cm = coverage_map(panel, [], path, contact, width_m=w)
    exact = (a - 0.2) * w + (1.8 - b) * w + 2 * math.pi * (w / 2) ** 2
    assert cm.cleaned_area_m2 == pytest.approx(exact, rel=5e-4)
    middle = (cm.x > a + w / 2 + cm.resolution_m) & (cm.x < b - w / 2 - cm.resolution_m)
    assert np.all(cm.passes[:, middle] <= 0)
    # one sample in contact between two out of contact: its disc, nothing between
    one = np.zeros(len(path), bool)
    one[len(path) // 2] = True
    cm1 = coverage_map(panel, [], path, one, width_m=w)
    assert cm1.cleaned_area_m2 == pytest.approx(math.pi * (w / 2) ** 2, rel=1e-3)
    none = coverage_map(panel, [], path, np.zeros(len(path), bool), width_m=w)
    assert none.cleaned_area_m2 == 0 and none.coverage_pct == 0 and none.overlap_pct == 0
    assert none.missed_area_m2 == pytest.approx(2.8, rel=1e-14)


def test_holes_are_taken_out_of_the_panel_exactly():
    # (vertices off the cell-centre lattice: no centre exactly on an edge)
    panel = np.array([[0, 0], [3, 0], [3.4, 1.1], [2.5, 2.2], [0.3, 1.9]], float) + [0.0123, -0.0071]
    panel[0] += [0.00317, 0.00491]
    tri = np.array([[0.5, 0.4], [1.1, 0.45], [0.7, 1.0]])
    pent = np.array([[1.8, 0.8], [2.3, 0.7], [2.6, 1.1], [2.2, 1.5], [1.7, 1.3]])
    path = polyline([(0.0, 1.0), (3.0, 1.0)], 1e-3)
    cm = coverage_map(panel, [tri, pent], path, np.ones(len(path), bool), width_m=0.3)
    assert cm.panel_area_m2 == pytest.approx(shoelace(panel) - shoelace(tri) - shoelace(pent), rel=1e-14)
    assert cm.cleaned_area_m2 + cm.missed_area_m2 == pytest.approx(cm.panel_area_m2, rel=1e-14)
    pts = grid_of(cm)
    expected = (MplPath(panel).contains_points(pts) & ~MplPath(tri).contains_points(pts)
                & ~MplPath(pent).contains_points(pts)).reshape(cm.passes.shape)
    np.testing.assert_array_equal(cm.passes >= 0, expected)
    # panel cells count the area to within the cells its boundary crosses
    h = cm.resolution_m
    perimeter = sum(np.linalg.norm(np.roll(p, -1, 0) - p, axis=1).sum() for p in (panel, tri, pent))
    assert abs(np.count_nonzero(expected) * h * h - cm.panel_area_m2) < 0.5 * h * perimeter


def test_a_lane_through_a_hole_does_not_clean_it():
    panel = rect(0.0, 0.0, 2.0, 1.4)
    hole = rect(0.9, 0.62, 1.15, 0.71)                      # inside the lane's band
    w, zc = 0.3, 0.66
    path = polyline([(-0.4, zc), (2.4, zc)], 1e-3)
    cm = coverage_map(panel, [hole], path, np.ones(len(path), bool), width_m=w)
    assert cm.panel_area_m2 == pytest.approx(2.8 - 0.25 * 0.09, rel=1e-14)
    assert cm.cleaned_area_m2 == pytest.approx(2.0 * w - 0.25 * 0.09, rel=1e-3)


# --------------------------------------------------------------------------- independent references

@pytest.mark.parametrize("seed", range(4))
def test_random_polyline_matches_the_exact_tube_area(seed):
    """Area of the r-neighbourhood of a polyline whose non-adjacent segments stay more than
    2r apart: 2 r L + pi r^2 + r^2 sum_i (theta_i / 2 - tan(theta_i / 2)), theta_i the
    turning angles (the outer sector each corner adds less the inner kite both rectangles
    cover)."""
    rng = np.random.default_rng(seed)
    r = rng.uniform(0.05, 0.25)
    while True:
        lengths = rng.uniform(0.3, 0.7, 9)
        turns = rng.uniform(-1.2, 1.2, 8)                   # up to 69 degrees
        heading = rng.uniform(0, 2 * np.pi) + np.concatenate([[0.0], np.cumsum(turns)])
        verts = np.vstack([[0.0, 0.0], np.cumsum(lengths[:, None] * np.column_stack(
            [np.cos(heading), np.sin(heading)]), axis=0)])
        kites = np.r_[0.0, r * np.tan(np.abs(turns) / 2), 0.0]
        if np.any(kites[:-1] + kites[1:] >= lengths):
            continue
        ok = True
        for i in range(9):
            for j in range(i + 2, 9):
                pts = polyline([verts[j], verts[j + 1]], 0.002)
                if seg_dist(pts, verts[i], verts[i + 1]).min() <= 2 * r:
                    ok = False
        if ok:
            break
    lo, hi = verts.min(axis=0) - r - 0.3, verts.max(axis=0) + r + 0.3
    panel = rect(*lo, *hi)
    path = polyline(verts, 5e-4)
    cm = coverage_map(panel, [], path, np.ones(len(path), bool), width_m=2 * r)
    tube = 2 * r * lengths.sum() + math.pi * r * r + r * r * np.sum(np.abs(turns) / 2 - np.tan(np.abs(turns) / 2))
    assert abs(cm.coverage_pct - 100 * tube / cm.panel_area_m2) < 0.01
    assert cm.cleaned_area_m2 == pytest.approx(tube, rel=1e-3)
    # twice only on the inner side of sharp corners, where the brush leaves a cell by more
    # than the pass margin on its way into the corner and sweeps it again on its way out
    twice = grid_of(cm)[(cm.passes >= 2).ravel()]
    near_corner = np.min([np.hypot(*(twice - v).T) for v in verts[1:-1]], axis=0) if len(twice) else []
    assert np.all(np.asarray(near_corner) < 2.5 * r)
    assert cm.overlap_area_m2 < 0.05 * cm.cleaned_area_m2


def test_random_polyline_clipped_by_panel_and_hole_matches_quasi_monte_carlo():
    rng = np.random.default_rng(7)
    ang = np.sort(rng.uniform(0, 2 * np.pi, 9))
    panel = np.column_stack([1.5 + np.cos(ang) * 1.4, 1.0 + np.sin(ang) * 0.9]) * rng.uniform(0.85, 1.0, (9, 1))
    hole = np.array([[1.3, 0.8], [1.7, 0.85], [1.6, 1.15], [1.35, 1.1]])
    verts = rng.uniform([0.0, 0.0], [3.0, 2.0], (14, 2))
    path = polyline(verts, 1e-3)
    contact = np.ones(len(path), bool)
    contact[len(path) // 3: len(path) // 3 + 400] = False
    w = 0.17
    cm = coverage_map(panel, [hole], path, contact, width_m=w)
    # reference: 2^20 scrambled Sobol points, inside the panel less the hole (matplotlib),
    # cleaned when within w/2 of a segment between two in-contact samples
    lo, hi = panel.min(axis=0), panel.max(axis=0)
    pts = lo + qmc.Sobol(2, seed=3).random_base2(20) * (hi - lo)
    inside = MplPath(panel).contains_points(pts) & ~MplPath(hole).contains_points(pts)
    pts = pts[inside]
    runs = np.flatnonzero(np.diff(np.r_[0, contact.astype(int), 0]))
    dmin = np.full(len(pts), np.inf)
    for a, b in zip(runs[::2], runs[1::2]):
        run = path[a:b]
        keep = decimate_path(run, np.ones(len(run), bool), tol_m=1e-6, max_chord_m=1.0)  # its corners
        for p, q in zip(run[keep[:-1]], run[keep[1:]]):
            dmin = np.minimum(dmin, seg_dist(pts, p, q))
    ref = 100 * np.mean(dmin <= w / 2)
    assert 20 < ref < 90                                          # a case with much clipped and missed
    assert abs(cm.coverage_pct - ref) < 0.2
    assert abs(cm.coverage_pct - ref) < 0.05                      # what it actually achieves
    assert cm.panel_area_m2 == pytest.approx(shoelace(panel) - shoelace(hole), rel=1e-14)


def test_random_polyline_matches_shapely_if_installed():
    """The computation a user would write with shapely (skipped where it is not installed)."""
    shapely_geometry = pytest.importorskip("shapely.geometry")
    rng = np.random.default_rng(11)
    panel = np.array([[0.0, 0.0], [2.6, 0.2], [3.0, 1.9], [0.4, 2.1]])
    hole = np.array([[1.2, 0.9], [1.6, 0.9], [1.5, 1.3]])
    verts = rng.uniform([0.0, 0.0], [3.0, 2.1], (12, 2))
    path = polyline(verts, 1e-3)
    w = 0.22
    cm = coverage_map(panel, [hole], path, np.ones(len(path), bool), width_m=w)
    region = shapely_geometry.Polygon(panel, [hole])
    cleaned = shapely_geometry.LineString(path).buffer(w / 2, 64).intersection(region)
    assert abs(cm.coverage_pct - 100 * cleaned.area / region.area) < 0.2
    assert cm.panel_area_m2 == pytest.approx(region.area, rel=1e-12)


CASES = [  # width, panel (x1, z1), lane angle (deg), spacing / width
    (0.1, (1.0, 1.0), 0.0, 0.9),
    (0.1, (1.0, 1.0), 23.0, 1.15),
    (0.25, (3.0, 2.0), 0.0, 1.3),
    (0.25, (3.0, 2.0), 61.0, 0.85),
    (0.5, (1.0, 1.0), 0.0, 0.8),
    (0.5, (1.2, 1.0), 37.0, 1.05),
    (0.5, (6.0, 4.0), 90.0, 0.95),
    (0.1, (10.0, 3.0), 0.0, 0.93),
]


@pytest.mark.parametrize("w, size, angle, spacing", CASES)
def test_boustrophedon_coverage_is_within_a_fifth_of_a_point(w, size, angle, spacing):
    """Typical coverage: lanes crossing the panel (with gaps or overlaps), turning outside it.
    Exact: the union of the lanes' bands, each clipped to the panel less its hole."""
    rng = np.random.default_rng(int(1000 * w + 10 * angle))
    panel = rect(0.0, 0.0, *size)
    hole = rect(0.31 * size[0], 0.43 * size[1], 0.47 * size[0], 0.58 * size[1])
    path, s, n = lanes(panel, w, math.radians(angle), spacing * w, rng.uniform(0, w), step=0.2 * w)
    cm = coverage_map(panel, [hole], path, np.ones(len(path), bool), width_m=w)

    def area(a, b):
        return strip_area(panel, n, a, b) - strip_area(hole, n, a, b)

    bands = [(sk - w / 2, sk + w / 2) for sk in s]
    cleaned = sum(area(a, b) for a, b in merged(bands))
    twice = sum(area(max(a1, a2), min(b1, b2)) for (a1, b1), (a2, b2) in zip(bands[:-1], bands[1:])
                if min(b1, b2) > max(a1, a2))
    A = shoelace(panel) - shoelace(hole)
    assert cm.panel_area_m2 == pytest.approx(A, rel=1e-14)
    assert abs(cm.coverage_pct - 100 * cleaned / A) < 0.2
    assert abs(cm.coverage_pct - 100 * cleaned / A) < 0.05       # what it actually achieves
    assert abs(cm.overlap_area_m2 - twice) / A < 0.002
    assert cm.passes.max() <= 2


# --------------------------------------------------------------------------- cell by cell

@pytest.mark.parametrize("seed", range(12))
def test_matches_the_slow_reference_cell_by_cell(seed):
    rng = np.random.default_rng(100 + seed)
    k = rng.integers(5, 10)
    ang = np.sort(rng.uniform(0, 2 * np.pi, k))
    panel = np.column_stack([np.cos(ang), np.sin(ang)]) * rng.uniform(0.5, 1.0, (k, 1)) + rng.uniform(-3, 3, 2)
    c = panel.mean(axis=0)
    holes = [c + 0.15 * np.array([[-1, -1], [1, -0.8], [0.6, 1.0]])] if seed % 2 else []
    w = rng.uniform(0.1, 0.6)
    n = rng.integers(2, 30)
    path = c + rng.normal(0, 0.6, (n, 2))
    contact = rng.random(n) < 0.75
    h = rng.uniform(0.008, 0.02)
    margin = rng.uniform(0.0, 0.1) * w
    assert len(decimate_path(path, contact, tol_m=DECIMATE_CELLS * h, max_chord_m=max(margin, h / 4))) == n
    cm = coverage_map(panel, holes, path, contact, width_m=w, resolution_m=h, pass_margin_m=margin)
    x, z, ref = slow_passes(panel, holes, path, contact, w, h, margin)
    np.testing.assert_allclose(cm.x, x, rtol=0, atol=1e-12)
    np.testing.assert_allclose(cm.z, z, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(cm.passes >= 1, ref >= 1)       # cleaned or not: exactly
    np.testing.assert_array_equal(cm.passes, ref)                 # and the passes
    assert (ref >= 1).any() and (ref == 0).any()


def test_decimated_path_moves_the_cleaned_edge_by_under_a_quarter_cell():
    rng = np.random.default_rng(5)
    panel = rect(0.0, 0.0, 1.0, 0.8)
    n = 3000
    t = np.linspace(0, 1, n)
    path = np.column_stack([0.1 + 0.8 * t, 0.4 + 0.25 * np.sin(7 * t)]) + rng.normal(0, 2e-4, (n, 2))
    contact = np.ones(n, bool)
    w, h = 0.12, 0.005
    cm = coverage_map(panel, [], path, contact, width_m=w, resolution_m=h)
    assert len(decimate_path(path, contact, tol_m=h / 4, max_chord_m=0.05 * w)) < n / 5
    pts = grid_of(cm)
    d = np.full(len(pts), np.inf)                    # every cell centre's distance to the recorded path
    for a, b in zip(path[:-1], path[1:]):
        d = np.minimum(d, seg_dist(pts, a, b))
    differ = (cm.passes.ravel() >= 1) != (d <= w / 2)
    assert np.all(np.abs(d[differ] - w / 2) <= h / 4)   # only cells within a quarter cell of the edge
    assert differ.sum() < 0.02 * np.count_nonzero(d <= w / 2)


# --------------------------------------------------------------------------- passes

def test_a_dwelling_jittering_brush_is_one_pass_and_scrubbing_is_three():
    panel = rect(0.0, 0.0, 2.0, 1.4)
    w = 0.2
    rng = np.random.default_rng(1)
    dwell = np.array([1.0, 0.7]) + rng.normal(0, 8e-4, (20_000, 2))    # 20 s of jitter, < margin / 8
    cm = coverage_map(panel, [], dwell, np.ones(len(dwell), bool), width_m=w)
    assert cm.passes.max() == 1
    # brief lapses of contact while it stays put: still one pass
    flicker = rng.random(len(dwell)) < 0.9
    assert coverage_map(panel, [], dwell, flicker, width_m=w).passes.max() == 1
    # three strokes along a line: three passes in the middle, fewer near the turns
    stroke = polyline([(0.5, 0.7), (1.5, 0.7), (0.5, 0.7), (1.5, 0.7)], 1e-3)
    cm3 = coverage_map(panel, [], stroke, np.ones(len(stroke), bool), width_m=w)
    mid = (np.abs(cm3.x - 1.0) < 0.2)
    rows = np.abs(cm3.z - 0.7) < 0.09
    assert np.all(cm3.passes[np.ix_(rows, mid)] == 3)
    # with no margin, the jitter at the brush's edge starts new passes
    assert coverage_map(panel, [], dwell, np.ones(len(dwell), bool), width_m=w, pass_margin_m=0.0).passes.max() > 1


# --------------------------------------------------------------------------- resolution and inputs

@pytest.mark.parametrize("w, size", [(0.1, (1, 1)), (0.5, (1, 1)), (0.2, (2, 1.4)), (0.1, (10, 10)), (0.5, (10, 3))])
def test_default_resolution_divides_the_width_and_bounds_the_edge_error(w, size):
    panel = rect(0.0, 0.0, *size)
    h = default_resolution_m(panel, w)
    n = w / h
    assert abs(n - round(n)) < 1e-9
    cells = math.ceil(size[0] / h) * math.ceil(size[1] / h)
    assert cells <= 20_000_000
    A, P = size[0] * size[1], 2 * (size[0] + size[1])
    if cells < 19_000_000:                                       # the cell cap does not bind
        assert round(n) >= 100 and h * P / (2 * A) <= 0.001 + 1e-12
    assert h * P / (2 * A) <= 0.001 + 1e-12                      # the panel's own edges: <= 0.1 point


def test_a_fully_cleaned_panel_is_exactly_100_percent():
    panel = rect(0.0, 0.0, 1.0, 0.7)
    path, _, _ = lanes(panel, 0.2, 0.0, 0.15, 0.03)
    cm = coverage_map(panel, [], path, np.ones(len(path), bool), width_m=0.2)
    assert cm.coverage_pct == 100.0 and cm.missed_area_m2 == 0.0
    assert cm.cleaned_area_m2 == pytest.approx(0.7, rel=1e-14)


def test_bad_inputs_are_refused():
    panel = rect(0.0, 0.0, 1.0, 1.0)
    path = np.array([[0.2, 0.2], [0.8, 0.8]])
    ok = np.ones(2, bool)
    with pytest.raises(ValueError, match="inside the panel"):
        coverage_map(panel, [rect(0.8, 0.8, 1.2, 0.9)], path, ok, width_m=0.1)
    with pytest.raises(ValueError, match="overlap"):
        coverage_map(panel, [rect(0.2, 0.2, 0.5, 0.5), rect(0.4, 0.4, 0.6, 0.6)], path, ok, width_m=0.1)
    with pytest.raises(ValueError, match="crosses itself"):
        coverage_map(np.array([[0, 0], [1, 1], [1, 0], [0, 1]], float), [], path, ok, width_m=0.1)
    with pytest.raises(ValueError, match="booleans"):
        coverage_map(panel, [], path, np.ones(2), width_m=0.1)
    with pytest.raises(ValueError, match="shape"):
        coverage_map(panel, [], path, np.ones(3, bool), width_m=0.1)
    with pytest.raises(ValueError, match="finite"):
        coverage_map(panel, [], np.array([[0.2, np.nan], [0.8, 0.8]]), ok, width_m=0.1)
    with pytest.raises(ValueError, match="width_m"):
        coverage_map(panel, [], path, ok, width_m=0.0)
    with pytest.raises(ValueError, match="coarser"):
        coverage_map(panel, [], path, ok, width_m=0.1, resolution_m=1e-5)
    with pytest.raises(ValueError, match="finer"):
        coverage_map(rect(0, 0, 1, 0.01), [], path, ok, width_m=0.1, resolution_m=0.5)
