"""Boustrophedon coverage paths (marinecdpr.motion.coverage): lanes, geometry, time law, errors.

Hand numbers: a 1.0 x 0.6 m panel, brush width 0.2 m, overlap 0.05 m. Nominal spacing
0.15 m; lanes along x (the long side), the first and last 0.1 m inside the panel, so at
z = 0.1 and 0.5: 0.4 m to span, ceil(0.4 / 0.15) = 3 gaps, 4 lanes, spacing 0.4 / 3 m.
Each lane runs from x = 0.1 to 0.9 (0.8 m); the path is 4 x 0.8 + 3 x 0.4 / 3 = 3.6 m.
"""

import dataclasses

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from marinecdpr.errors import ScenarioError
from marinecdpr.motion.coverage import CoveragePath, coverage_path

V, A, J = 0.2, 0.5, 2.0  # m/s, m/s^2, m/s^3: A^2/J = 0.125 m/s < V, so A is reached
LIMITS = dict(speed_m_s=V, accel_m_s2=A, jerk_m_s3=J)
BRUSH = dict(width_m=0.2, overlap_m=0.05)
R = 0.1  # brush radius, m

RECT = [(0.0, 0.0), (1.0, 0.0), (1.0, 0.6), (0.0, 0.6)]
# 2.0 x 1.2 m panel with a 0.4 x 0.3 m opening
BIG = [(0.0, 0.0), (2.0, 0.0), (2.0, 1.2), (0.0, 1.2)]
HOLE = [(0.8, 0.45), (1.2, 0.45), (1.2, 0.75), (0.8, 0.75)]
HEXAGON = [(0.3, 0.0), (1.0, 0.0), (1.3, 0.5), (1.0, 1.0), (0.3, 1.0), (0.0, 0.5)]
U_SHAPE = [(0, 0), (1.5, 0), (1.5, 1.2), (1.0, 1.2), (1.0, 0.5), (0.5, 0.5), (0.5, 1.2), (0, 1.2)]


def path(panel=RECT, holes=(), **kw):
    return coverage_path(panel, holes, **{**BRUSH, **LIMITS, **kw})


# --- independent geometry for the checks --------------------------------------------------


def point_seg(p, a, b):
    """Distance from points p (n, 2) to the segment a-b."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    d = b - a
    t = np.clip((p - a) @ d / (d @ d), 0.0, 1.0)
    return np.linalg.norm(p - (a + t[:, None] * d), axis=1)


def seg_seg(a, b, c, d):
    """Distance between segments a-b and c-d (0 if they cross)."""
    a, b, c, d = (np.asarray(x, float) for x in (a, b, c, d))

    def side(o, p, q):
        return np.sign((p[0] - o[0]) * (q[1] - o[1]) - (p[1] - o[1]) * (q[0] - o[0]))

    if side(a, b, c) * side(a, b, d) < 0 and side(c, d, a) * side(c, d, b) < 0:
        return 0.0
    return min(point_seg(a[None], c, d)[0], point_seg(b[None], c, d)[0],
               point_seg(c[None], a, b)[0], point_seg(d[None], a, b)[0])


def edges(poly):
    poly = np.asarray(poly, float)
    return list(zip(poly, np.roll(poly, -1, axis=0)))


def dist_to_boundary(p, poly):
    return np.min([point_seg(p, a, b) for a, b in edges(poly)], axis=0)


def inside(p, poly):
    """Ray casting towards +x."""
    count = np.zeros(len(p), dtype=int)
    for a, b in edges(poly):
        straddle = (a[1] > p[:, 1]) != (b[1] > p[:, 1])
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):  # a level edge straddles nothing
            x = a[0] + (p[:, 1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1])
        count += straddle & (p[:, 0] < x)
    return count % 2 == 1


def path_clearance(c, poly):
    """Smallest distance from any segment of the path to the polygon's boundary (exact)."""
    return min(seg_seg(p, q, a, b) for p, q in zip(c.vertices[:-1], c.vertices[1:]) for a, b in edges(poly))


def samples(c, n=20001):
    return c.evaluate(np.linspace(0.0, c.duration_s, n))[0]


def lane_z(c):
    lanes = [(p, q) for p, q, lane in zip(c.vertices[:-1], c.vertices[1:], c.lane_segment) if lane]
    for p, q in lanes:
        assert p[1] == pytest.approx(q[1], abs=1e-12)  # horizontal
    return np.array([p[1] for p, _ in lanes]), lanes


def scurve_duration(L, v, a, j):
    """Rest-to-rest S-curve duration, from the closed forms of its three regimes."""
    if v >= a * a / j and L >= v * (v / a + a / j):  # cruise at v, a reached
        return L / v + v / a + a / j
    if (L * np.sqrt(j) / 2) ** (2 / 3) <= a * a / j:  # a not reached: 4 phases of jerk
        return 4.0 * (L / (2.0 * j)) ** (1 / 3)
    return a / j + np.sqrt((a / j) ** 2 + 4.0 * L / a)  # a reached, no cruise


# --- the rectangle by hand -------------------------------------------------------------------


def test_rectangle_lanes_spacing_and_positions():
    c = path()
    assert isinstance(c, CoveragePath)
    assert c.direction_deg == 0.0
    assert c.lanes == 4
    assert c.spacing_m == pytest.approx(0.4 / 3, rel=1e-12)
    z, lanes = lane_z(c)
    np.testing.assert_allclose(z, [0.1, 0.1 + 0.4 / 3, 0.1 + 0.8 / 3, 0.5], atol=1e-12)
    for p, q in lanes:
        np.testing.assert_allclose(sorted([p[0], q[0]]), [0.1, 0.9], atol=1e-12)
    expected = [(0.1, 0.1), (0.9, 0.1), (0.9, 0.1 + 0.4 / 3), (0.1, 0.1 + 0.4 / 3),
                (0.1, 0.1 + 0.8 / 3), (0.9, 0.1 + 0.8 / 3), (0.9, 0.5), (0.1, 0.5)]
    np.testing.assert_allclose(c.vertices, expected, atol=1e-12)
    assert c.lane_segment.tolist() == [True, False, True, False, True, False, True]


def test_rectangle_length_is_the_hand_sum():
    assert path().length_m == pytest.approx(4 * 0.8 + 3 * (0.4 / 3), rel=1e-12)


def test_rectangle_duration_is_the_sum_of_the_segments_s_curves():
    # lane 0.8 m: 0.8/0.2 + 0.2/0.5 + 0.5/2 = 4.65 s; step 0.4/3 m: 2/3 + 0.4 + 0.25 s
    c = path()
    np.testing.assert_allclose(np.diff(c.vertex_time_s), [4.65, 1.3166666666666667] * 3 + [4.65], rtol=1e-12)
    assert c.duration_s == pytest.approx(4 * 4.65 + 3 * (2 / 3 + 0.65), rel=1e-12)
    assert c.duration_s == pytest.approx(22.55, rel=1e-12)


@pytest.mark.parametrize(
    "length, v, expected",
    [
        (0.8, 0.2, 4.65),  # cruises at v, reaches a: L/v + v/a + a/j
        (0.8, 1.0, 0.25 + np.sqrt(0.0625 + 6.4)),  # reaches a, never v: a/j + sqrt((a/j)^2 + 4L/a)
        (0.05, 0.2, 4.0 * 0.0125 ** (1 / 3)),  # reaches neither: 4 (L / 2j)^(1/3)
    ],
)
def test_one_rest_to_rest_segment_against_the_s_curve_formula(length, v, expected):
    # a panel exactly one brush wide: one lane of the given length
    c = path([(0, 0), (length + 0.2, 0), (length + 0.2, 0.2), (0, 0.2)], overlap_m=0.0, speed_m_s=v)
    assert c.lanes == 1 and len(c.vertices) == 2
    assert c.length_m == pytest.approx(length, rel=1e-12)
    assert c.duration_s == pytest.approx(expected, rel=1e-12)
    assert c.duration_s == pytest.approx(scurve_duration(length, v, A, J), rel=1e-12)
    ts = np.linspace(0, c.duration_s, 20001)
    _, vel, acc = c.evaluate(ts)
    speed, accel = np.linalg.norm(vel, axis=1), np.linalg.norm(acc, axis=1)
    assert speed.max() <= v * (1 + 1e-9) and accel.max() <= A * (1 + 1e-9)
    if length == 0.05:  # peak acceleration sqrt(v_peak j) < a
        assert accel.max() == pytest.approx(np.sqrt(J * (0.05 * np.sqrt(J) / 2) ** (2 / 3)), rel=1e-3)
    else:
        assert accel.max() == pytest.approx(A, rel=1e-9)


def test_explicit_direction_across_the_long_side():
    c = path(direction_deg=90.0)
    assert c.direction_deg == 90.0
    # lanes along z, x from 0.1 to 0.9: ceil(0.8 / 0.15) = 6 gaps, 7 lanes
    assert c.lanes == 7
    assert c.spacing_m == pytest.approx(0.8 / 6, rel=1e-12)
    lanes = c.vertices[:-1][c.lane_segment]
    np.testing.assert_allclose(np.sort(lanes[:, 0]), 0.1 + np.arange(7) * 0.8 / 6, atol=1e-12)
    assert c.length_m == pytest.approx(7 * 0.4 + 6 * 0.8 / 6, rel=1e-12)
    assert path(direction_deg=270.0).direction_deg == 90.0  # modulo 180


@pytest.mark.parametrize(
    "start, first",
    [("lower_left", (0.1, 0.1)), ("lower_right", (0.9, 0.1)), ("upper_left", (0.1, 0.5)), ("upper_right", (0.9, 0.5))],
)
def test_start_corner(start, first):
    c = path(start=start)
    np.testing.assert_allclose(c.vertices[0], first, atol=1e-12)
    assert c.length_m == pytest.approx(3.6, rel=1e-12)


def test_orientation_and_a_closing_vertex_do_not_matter():
    c = path()
    for panel in (RECT[::-1], RECT + [RECT[0]], np.roll(RECT, 2, axis=0)):
        other = path(panel)
        np.testing.assert_allclose(other.vertices, c.vertices, atol=1e-12)
        assert other.duration_s == pytest.approx(c.duration_s, rel=1e-12)


# --- the time law ---------------------------------------------------------------------------


@pytest.fixture(scope="module")
def holed():
    return path(BIG, [HOLE])


def test_velocity_and_acceleration_are_the_derivatives_of_position(holed):
    c, h = holed, 1e-4
    t = np.linspace(h, c.duration_s - h, 40001)
    p_plus, v_plus, _ = c.evaluate(t + h)
    p_minus, v_minus, _ = c.evaluate(t - h)
    _, v, a = c.evaluate(t)
    # p is piecewise cubic with |p'''| <= J: central differences are off by at most J h^2 / 6
    np.testing.assert_allclose((p_plus - p_minus) / (2 * h), v, atol=J * h * h / 6 + 1e-10, rtol=0)
    # v is piecewise quadratic, |v''| <= J: off by at most J h
    np.testing.assert_allclose((v_plus - v_minus) / (2 * h), a, atol=J * h + 1e-9, rtol=0)


def test_position_velocity_and_acceleration_are_continuous(holed):
    c, dt = holed, 1e-3
    p, v, a = c.evaluate(np.arange(0.0, c.duration_s + dt, dt))
    assert np.linalg.norm(np.diff(a, axis=0), axis=1).max() <= J * dt * (1 + 1e-9)
    assert np.linalg.norm(np.diff(v, axis=0), axis=1).max() <= A * dt * (1 + 1e-9)
    assert np.linalg.norm(np.diff(p, axis=0), axis=1).max() <= V * dt * (1 + 1e-9)


def test_limits_are_respected_and_reached_over_the_whole_path(holed):
    c = holed
    _, v, a = c.evaluate(np.linspace(0.0, c.duration_s, 400001))
    speed, accel = np.linalg.norm(v, axis=1), np.linalg.norm(a, axis=1)
    assert speed.max() <= V * (1 + 1e-9)
    assert accel.max() <= A * (1 + 1e-9)
    assert speed.max() >= V * (1 - 1e-9)  # the lanes cruise at the speed limit
    assert accel.max() >= A * (1 - 1e-6)


def test_rest_at_every_vertex_and_outside_the_duration(holed):
    c = holed
    p, v, a = c.evaluate(c.vertex_time_s)
    np.testing.assert_allclose(p, c.vertices, atol=1e-12)
    np.testing.assert_allclose(v, 0.0, atol=1e-12)
    np.testing.assert_allclose(a, 0.0, atol=1e-12)
    p, v, a = c.evaluate(np.array([-5.0, c.duration_s + 5.0]))
    np.testing.assert_allclose(p, c.vertices[[0, -1]], atol=1e-12)
    assert not v.any() and not a.any()
    p, v, a = c.evaluate(1.0)  # a scalar time is one sample
    assert p.shape == v.shape == a.shape == (1, 2)
    p, v, a = c.evaluate(np.linspace(0, 1, 7))
    assert p.shape == v.shape == a.shape == (7, 2)


def test_the_result_is_frozen(holed):
    with pytest.raises(dataclasses.FrozenInstanceError):
        holed.lanes = 3
    with pytest.raises(ValueError):
        holed.vertices[0, 0] = 1.0


# --- holes and non-convex panels ----------------------------------------------------------------


def test_a_hole_keeps_the_brush_clear(holed):
    c = holed
    # path segments, exactly, and samples of the timed motion
    assert path_clearance(c, HOLE) >= R * (1 - 1e-8)
    assert path_clearance(c, BIG) >= R * (1 - 1e-8)
    p = np.vstack([samples(c), c.vertices])
    assert dist_to_boundary(p, HOLE).min() >= R * (1 - 1e-8)
    assert not inside(p, HOLE).any()
    assert inside(p, BIG).all()


def test_lanes_around_a_hole_by_hand(holed):
    # z extent 1.2: 1.0 to span, ceil(1.0 / 0.15) = 7 gaps, 8 lines at 0.1 + k/7. The hole
    # (z 0.45..0.75) outset by 0.1 blocks z 0.35..0.85: lines 2..5 are cut in two pieces
    c = holed
    assert c.spacing_m == pytest.approx(1 / 7, rel=1e-12)
    assert c.lanes == 4 * 1 + 4 * 2
    z, lanes = lane_z(c)
    lines = 0.1 + np.arange(8) / 7
    for k, line in enumerate(lines):
        pieces = sorted(tuple(sorted([p[0], q[0]])) for (p, q), zz in zip(lanes, z) if abs(zz - line) < 1e-12)
        if k in (0, 1, 6, 7):
            np.testing.assert_allclose(pieces, [(0.1, 1.9)], atol=1e-12)
        else:
            dz = max(0.0, 0.45 - line, line - 0.75)  # beside the hole's corner: the disc meets the corner
            dx = np.sqrt(R * R - dz * dz)
            np.testing.assert_allclose(pieces, [(0.1, 0.8 - dx), (1.2 + dx, 1.9)], atol=1e-9)
    assert 0.8 - np.sqrt(R * R - (0.45 - lines[2]) ** 2) == pytest.approx(0.7234014, abs=1e-7)


def test_the_free_region_is_covered_by_the_brush_on_the_rectangle_hexagon_and_u_shape():
    """Every point the brush centre may reach is within a brush radius of the path."""
    for panel, kw in ((RECT, {}), (HEXAGON, {}), (U_SHAPE, {}), (U_SHAPE, {"direction_deg": 90.0})):
        c = path(panel, **kw)
        poly = np.asarray(panel, float)
        lo, hi = poly.min(axis=0), poly.max(axis=0)
        g = np.stack(np.meshgrid(np.linspace(lo[0], hi[0], 151), np.linspace(lo[1], hi[1], 151)), -1).reshape(-1, 2)
        free = inside(g, panel) & (dist_to_boundary(g, panel) >= R)
        near = np.min([point_seg(g[free], p, q) for p, q in zip(c.vertices[:-1], c.vertices[1:])], axis=0)
        assert near.max() <= R * (1 + 1e-9), panel
        assert path_clearance(c, panel) >= R * (1 - 1e-8)
        assert inside(samples(c, 4001), panel).all()


def test_convex_polygon_lanes_end_on_the_inset_boundary():
    c = path(HEXAGON)
    assert c.direction_deg == 0.0 and c.lanes == 7  # 1.0 high: ceil(0.8 / 0.15) = 6 gaps
    z, lanes = lane_z(c)
    np.testing.assert_allclose(np.sort(z), 0.1 + np.arange(7) * 0.8 / 6, atol=1e-12)
    ends = np.array([e for lane in lanes for e in lane])
    np.testing.assert_allclose(dist_to_boundary(ends, HEXAGON), R, rtol=1e-9)
    # all steps between lanes are straight: one segment between consecutive lanes
    assert c.lane_segment.tolist() == [True, False] * 6 + [True]


def test_u_shape_transfer_goes_round_the_notch():
    c = path(U_SHAPE)
    z, lanes = lane_z(c)
    # 1.2 high: 1.0 to span, 7 gaps, 8 lines at 0.1 + k/7; the upper 5 (z >= 0.529, above the
    # notch's floor at 0.5 outset by 0.1) are cut in two, one piece per arm
    assert c.lanes == 3 + 5 * 2
    transfers = [(p, q) for p, q, lane in zip(c.vertices[:-1], c.vertices[1:], c.lane_segment) if not lane]
    # no segment crosses the notch between the arms (x 0.5..1.0 above z = 0.5)
    notch = [(0.5, 0.5), (1.0, 0.5), (1.0, 1.2), (0.5, 1.2)]
    assert path_clearance(c, notch) >= R * (1 - 1e-8)
    assert max(np.linalg.norm(q - p) for p, q in transfers) < 1.0


def test_automatic_direction_follows_the_long_side():
    tall = [(0, 0), (0.3, 0), (0.3, 2.0), (0, 2.0)]
    c = path(tall)
    assert c.direction_deg == 90.0 and c.lanes == 2  # 0.1 m apart across 0.3 m
    assert c.spacing_m == pytest.approx(0.1, rel=1e-12)
    th = np.radians(30.0)
    rot = np.array([[np.cos(th), -np.sin(th)], [np.sin(th), np.cos(th)]])
    slanted = np.array([(0, 0), (2.0, 0), (2.0, 0.3), (0, 0.3)]) @ rot.T
    assert path(slanted).direction_deg == pytest.approx(30.0, abs=1e-9)
    # a rotated rectangle gives the rotated path: same lanes, length and duration
    c0, c30 = path(), path(np.array(RECT) @ rot.T)
    assert c30.direction_deg == pytest.approx(30.0, abs=1e-9)
    assert (c30.lanes, c30.spacing_m) == (c0.lanes, pytest.approx(c0.spacing_m, rel=1e-12))
    assert c30.length_m == pytest.approx(c0.length_m, rel=1e-9)
    assert c30.duration_s == pytest.approx(c0.duration_s, rel=1e-9)


@settings(max_examples=40, deadline=None)
@given(st.lists(st.tuples(st.floats(0, 2), st.floats(0, 2)), min_size=3, max_size=9),
       st.one_of(st.none(), st.floats(0, 180)))
def test_random_convex_panels_stay_inside_and_within_limits(points, direction):
    from scipy.spatial import ConvexHull, QhullError

    pts = np.array(points)
    try:
        hull = pts[ConvexHull(pts).vertices]
    except (QhullError, ValueError):
        assume(False)
    try:
        c = path(hull, direction_deg=direction)
    except ScenarioError as e:  # too small for the brush, or degenerate
        assume(False)
        raise AssertionError(e)
    assert c.lanes >= 1
    assert path_clearance(c, hull) >= R * (1 - 1e-8)
    p, v, a = c.evaluate(np.linspace(0, c.duration_s, 2001))
    assert inside(p, hull).all()
    assert np.linalg.norm(v, axis=1).max() <= V * (1 + 1e-9)
    assert np.linalg.norm(a, axis=1).max() <= A * (1 + 1e-9)


# --- errors -----------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "panel, holes, kw, names",
    [
        (RECT, (), {"overlap_m": 0.2}, "overlap_m"),  # overlap = width: zero spacing
        (RECT, (), {"overlap_m": 0.25}, "overlap_m"),
        (RECT, (), {"overlap_m": -0.01}, "overlap_m"),
        (RECT, (), {"width_m": 0.0}, "width_m"),
        (RECT, (), {"speed_m_s": 0.0}, "speed_m_s"),
        (RECT, (), {"accel_m_s2": -1.0}, "accel_m_s2"),
        (RECT, (), {"jerk_m_s3": float("nan")}, "jerk_m_s3"),
        (RECT, (), {"jerk_m_s3": "fast"}, "jerk_m_s3"),
        (RECT, (), {"direction_deg": float("inf")}, "direction_deg"),
        (RECT, (), {"start": "middle"}, "start"),
        (RECT, [[(2, 2), (3, 2), (3, 3)]], {}, "holes[1]"),  # outside the panel
        (RECT, [[(0.5, 0.2), (1.5, 0.2), (1.5, 0.4), (0.5, 0.4)]], {}, "holes[1]"),  # across its edge
        (RECT, [[(0.2, 0.2), (0.4, 0.2), (0.3, 0.4)], [(0.3, 0.25), (0.5, 0.25), (0.4, 0.45)]], {}, "holes[2]"),
        ([(0, 0), (1, 0), (2, 0)], (), {}, "panel"),  # zero area
        ([(0, 0), (1, 1), (1, 1), (0, 0)], (), {}, "panel"),
        ([(0, 0), (1, 0), (0, 1), (1, 1)], (), {}, "panel"),  # a bow tie crosses itself
        ([(0, 0), (1, 0)], (), {}, "panel"),
        ([(0, 0), (0.15, 0), (0.15, 1), (0, 1)], (), {}, "width_m"),  # narrower than the brush
        # two rooms joined by a passage narrower than the brush
        ([(0, 0), (1, 0), (1, 0.45), (1.5, 0.45), (1.5, 0), (2.5, 0), (2.5, 1), (1.5, 1), (1.5, 0.55),
          (1, 0.55), (1, 1), (0, 1)], (), {}, "separate parts"),
    ],
)
def test_errors_are_one_line_scenario_errors_naming_what(panel, holes, kw, names):
    with pytest.raises(ScenarioError) as info:
        path(panel, holes, **kw)
    assert isinstance(info.value, ValueError)
    text = str(info.value)
    assert "\n" not in text and names in text


# -------------------- formerly tests/test_issue21_coverage_pass.py

"""Issue 21, item 7: the boundary pass covers what the lanes leave, and flies no lane again.

paper_clean's panel (1.3 x 0.8 m, a 0.2 m brush, 0.03 m overlap): 5 lanes along x at
z = 0.4 .. 1.0, from x = 0.4 to 1.5. The old pass went round the whole inset outline,
its bottom and top edges the first and last lanes again (2 x 1.1 m of 9.5 m).
"""

import numpy as np
import pytest
from scipy.spatial import cKDTree

from marinecdpr.motion.coverage import coverage_path
from marinecdpr.motion.trajectory import cleaning_path
from marinecdpr.scenario.loading import load_scenario

R = 0.1
H = 0.001  # raster cell, m


def segments(c, which):
    return [(p, q) for p, q, k in zip(c.vertices[:-1], c.vertices[1:], which) if k]


def seg_distance(points, p, q):
    d = q - p
    t = np.clip((points - p) @ d / max(d @ d, 1e-300), 0.0, 1.0)
    return np.linalg.norm(points - (p + t[:, None] * d), axis=1)


def raster(panel, h=H):
    lo, hi = np.min(panel, axis=0), np.max(panel, axis=0)
    x = np.arange(lo[0] + h / 2, hi[0], h)
    z = np.arange(lo[1] + h / 2, hi[1], h)
    return np.stack(np.meshgrid(x, z), -1).reshape(-1, 2)


def footprint(cells, segs, radius=R):
    out = np.zeros(len(cells), dtype=bool)
    for p, q in segs:
        out |= seg_distance(cells, p, q) <= radius
    return out


def length_over_cleaned(cells, cleaned, segs, step=0.002, h=H):
    """Length of ``segs`` along which the brush's disc (shrunk by 2 cells, against the
    raster's rounding) finds no cell the lanes left: flown over cleaned area only."""
    dirty = cells[~cleaned]
    tree = cKDTree(dirty) if len(dirty) else None  # the nearest dirty cell of each sample
    total = 0.0
    for p, q in segs:
        n = max(2, int(np.ceil(np.linalg.norm(q - p) / step)) + 1)
        s = p + np.linspace(0, 1, n)[:, None] * (q - p)
        new = np.zeros(n, dtype=bool) if tree is None else tree.query(s)[0] <= R - 2 * h
        total += np.linalg.norm(q - p) * float(np.mean(~new))
    return total


def paper_clean_path():
    return cleaning_path(load_scenario("paper_clean").cleaning)


def test_paper_cleans_outline_pass_flies_no_lane_again_and_the_panel_is_covered():
    c = paper_clean_path()
    panel = np.array(load_scenario("paper_clean").cleaning.panel_m)
    cells = raster(panel)
    lanes = footprint(cells, segments(c, c.lane_segment))
    steps = segments(c, ~c.lane_segment & ~c.boundary_segment)
    outline = segments(c, c.boundary_segment)
    assert outline, "paper_clean has a boundary pass"
    # over what the lanes cleaned, the outline pass flies (almost) nothing: it was 2.2 m.
    # Where the pass crosses a lane's end the sliver it cleans thins to nothing: the raster
    # counts a few mm there as flown over cleaned area (5 cm over its 10 lane ends)
    assert length_over_cleaned(cells, lanes, outline) < 0.1
    # the lanes and their turns with the pass: only the turns are flown twice
    turns = sum(np.linalg.norm(q - p) for p, q in steps)
    everything = footprint(cells, segments(c, np.ones_like(c.lane_segment)))
    # every point a round brush can reach is cleaned: within R of the free rectangle
    lo, hi = panel.min(axis=0) + R, panel.max(axis=0) - R
    reachable = np.linalg.norm(cells - np.clip(cells, lo, hi), axis=1) <= R - 2 * H
    assert everything[reachable].all()
    assert turns == pytest.approx(0.6, abs=1e-9)  # 4 steps of 0.15 m
    assert c.length_m == pytest.approx(5 * 1.1 + 0.6 + 2 * 0.6, abs=1e-9)  # lanes, turns, two sides


def test_the_pass_costs_what_it_adds_and_the_path_still_starts_at_its_corner():
    c = paper_clean_path()
    bare = coverage_path(np.array(load_scenario("paper_clean").cleaning.panel_m), width_m=0.2, overlap_m=0.03,
                         speed_m_s=0.1, accel_m_s2=0.3, jerk_m_s3=3.0)
    assert c.boundary_length_m == pytest.approx(c.length_m - bare.length_m, abs=1e-9)
    assert c.boundary_length_m == pytest.approx(1.2, abs=1e-9)
    assert c.boundary_duration_s == pytest.approx(c.duration_s - bare.duration_s, abs=1e-9)
    assert 0 < c.boundary_duration_s < 20.0
    np.testing.assert_allclose(c.vertices[0], [0.4, 0.4], atol=1e-12)  # lower_left


@pytest.mark.parametrize("height", [0.8, 0.65])
def test_an_even_number_of_lanes_becomes_odd_rather_than_cross_the_panel(height):
    """0.65 m high: 0.45 / 0.17 -> 3 gaps, 4 lanes, which would end on the side they began
    from; one lane more (spacing 0.1125 m) lets the other side follow the lanes."""
    panel = np.array([[0.3, 0.3], [1.6, 0.3], [1.6, 0.3 + height], [0.3, 0.3 + height]])
    c = coverage_path(panel, width_m=0.2, overlap_m=0.03, speed_m_s=0.1, accel_m_s2=0.3, jerk_m_s3=3.0,
                      boundary_pass=True)
    assert c.lanes % 2 == 1 and c.spacing_m <= 0.17 + 1e-12
    cells = raster(panel)
    lanes = footprint(cells, segments(c, c.lane_segment))
    assert length_over_cleaned(cells, lanes, segments(c, c.boundary_segment)) < 0.1
    # no transfer: the pass is the two sides, height - 0.2 each
    assert sum(np.linalg.norm(q - p) for p, q in segments(c, c.boundary_segment)) == pytest.approx(
        2 * (height - 0.2), abs=1e-9)


HEXAGON = [(0.3, 0.0), (1.0, 0.0), (1.3, 0.5), (1.0, 1.0), (0.3, 1.0), (0.0, 0.5)]
DIAMOND = [(0.6, 0.0), (1.2, 0.5), (0.6, 1.0), (0.0, 0.5)]
TRIANGLE = [(0.0, 0.0), (1.4, 0.0), (0.7, 1.0)]


@pytest.mark.parametrize("panel, direction", [(HEXAGON, None), (DIAMOND, None), (TRIANGLE, 0.0), (HEXAGON, 30.0)])
def test_on_convex_panels_the_pass_stays_free_and_leaves_nothing_within_reach(panel, direction):
    """The pass keeps the disc inside the panel, and every point the disc may reach is
    within a radius of the path; the outline pass flies little over what the lanes cleaned."""
    poly = np.asarray(panel, float)
    c = coverage_path(poly, width_m=0.2, overlap_m=0.05, speed_m_s=0.2, accel_m_s2=0.5, jerk_m_s3=2.0,
                      direction_deg=direction, boundary_pass=True)
    edges = list(zip(poly, np.roll(poly, -1, axis=0)))
    h = 0.002
    cells = raster(poly, h)
    # the cells the centre may reach: inside, at least R from every edge (convex: the half-planes)
    n = np.array([[-(b - a)[1], (b - a)[0]] / np.linalg.norm(b - a) for a, b in edges])
    signed = np.stack([(cells - a) @ ni for (a, _), ni in zip(edges, n)], axis=1)
    free = np.all(signed >= R, axis=1)
    samples = c.evaluate(np.linspace(0.0, c.duration_s, 20001))[0]
    ss = np.stack([(samples - a) @ ni for (a, _), ni in zip(edges, n)], axis=1)
    assert ss.min() >= R * (1 - 1e-8)
    near = np.min([seg_distance(cells[free], p, q) for p, q in zip(c.vertices[:-1], c.vertices[1:])], axis=0)
    assert near.max() <= R * (1 + 1e-9)
    lanes = footprint(cells, segments(c, c.lane_segment))
    over = length_over_cleaned(cells, lanes, segments(c, c.boundary_segment), h=h)
    assert over < 0.1 * c.boundary_length_m + 0.02
