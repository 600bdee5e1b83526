"""A rail along the ship with rounded corners, and the carriage's jerk-limited motion on it
(issue 39, item 1): hand-worked rails and moves, an independent construction of the rounded
path, finite differences of every derivative, and property tests of the double-S move
against a brute-force search of its peak speed."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from marinecdpr.errors import ScenarioError
from marinecdpr.motion.rail import (
    RailError,
    carriage_profile,
    check_rail,
    check_stations,
    profile_schedule,
    scurve_move,
)

L_RAIL = [[0.0, 0.0, 0.0], [10.0, 0.0, 0.0], [10.0, 10.0, 0.0]]
# a sheer line: a deck edge that rises and turns in plan, one corner in a steeply tilted plane,
# one collinear middle point (no arc there)
SHEER = [
    [0.0, 0.0, 0.0],
    [30.0, 0.5, 0.4],
    [60.0, 1.0, 0.8],  # collinear with the two before
    [90.0, 4.0, 2.5],
    [110.0, 12.0, 9.0],
    [115.0, 30.0, 11.0],
    [100.0, 45.0, 11.5],
]


def _independent_rounding(points, radius, per_arc=20001, per_line=3):
    """The rounded path sampled densely, built another way: each arc's centre on the corner's
    inner bisector at R / cos(theta/2), its points the start point's radius turned about the
    corner's normal (Rodrigues); with the arc length at each sample and the joins."""
    p = np.asarray(points, float)
    u = np.diff(p, axis=0)
    u /= np.linalg.norm(u, axis=1)[:, None]
    samples, s_of, joins = [p[0][None]], [np.zeros(1)], [0.0]
    s = 0.0
    here = p[0]
    for i in range(1, len(p) - 1):
        a, b = u[i - 1], u[i]
        axis = np.cross(a, b)
        if np.linalg.norm(axis) < 1e-12:
            continue
        theta = np.arccos(np.clip(a @ b, -1.0, 1.0))
        tan_len = radius * np.tan(theta / 2)
        start, end = p[i] - tan_len * a, p[i] + tan_len * b
        line = np.linalg.norm(start - here)
        w = np.linspace(0.0, 1.0, per_line)[1:]
        samples.append(here + w[:, None] * (start - here))
        s_of.append(s + w * line)
        s += line
        joins.append(s)
        bis = (b - a) / np.linalg.norm(b - a)
        centre = p[i] + bis * radius / np.cos(theta / 2)
        k = axis / np.linalg.norm(axis)
        v0 = start - centre
        phi = np.linspace(0.0, theta, per_arc)[1:, None]
        turned = v0 * np.cos(phi) + np.cross(k, v0) * np.sin(phi) + k * (k @ v0) * (1 - np.cos(phi))
        samples.append(centre + turned)
        s_of.append(s + radius * phi[:, 0])
        s += radius * theta
        joins.append(s)
        here = end
    w = np.linspace(0.0, 1.0, per_line)[1:]
    samples.append(here + w[:, None] * (p[-1] - here))
    s_of.append(s + w * np.linalg.norm(p[-1] - here))
    s += np.linalg.norm(p[-1] - here)
    joins.append(s)
    return np.concatenate(samples), np.concatenate(s_of), np.array(joins)


# --- the rail ---------------------------------------------------------------------------------


def test_an_l_shaped_rail_worked_by_hand():
    """(0,0,0)->(10,0,0)->(10,10,0), R = 2: the arc's tangent points are 2 m from the corner,
    so the length is 20 - 4 + pi exactly; the heading goes from 0 to pi/2 turning at 1/2 rad/m
    on the arc; mid-arc the point is the centre (8, 2) plus 2 (cos -45, sin -45)."""
    rail = check_rail(L_RAIL, 2.0)
    assert rail.length_m == pytest.approx(16.0 + np.pi, rel=1e-15)
    assert rail.least_radius_m == 2.0
    s = np.array([0.0, 4.0, 8.0, 8.0 + np.pi / 4, 8.0 + np.pi / 2, 8.0 + np.pi, 12.0 + np.pi, 16.0 + np.pi])
    g = rail.at(s)
    expected_r = [
        [0, 0, 0], [4, 0, 0], [8, 0, 0], [8 + 2 * np.sin(np.pi / 8), 2 - 2 * np.cos(np.pi / 8), 0],
        [8 + np.sqrt(2), 2 - np.sqrt(2), 0], [10, 2, 0], [10, 6, 0], [10, 10, 0],
    ]
    np.testing.assert_allclose(g.r, expected_r, rtol=0, atol=1e-14)
    np.testing.assert_allclose(g.heading, [0, 0, 0, np.pi / 8, np.pi / 4, np.pi / 2, np.pi / 2, np.pi / 2], atol=1e-15)
    np.testing.assert_allclose(g.dheading, [0, 0, 0.5, 0.5, 0.5, 0, 0, 0], atol=1e-15)
    np.testing.assert_allclose(g.ddheading, 0.0, atol=1e-15)
    mid = 4  # mid-arc: the curvature vector points to the centre, magnitude 1/R; ddt = -t/R^2
    np.testing.assert_allclose(g.t[mid], [np.sqrt(0.5), np.sqrt(0.5), 0], atol=1e-15)
    np.testing.assert_allclose(g.dt[mid], 0.5 * np.array([-np.sqrt(0.5), np.sqrt(0.5), 0]), atol=1e-15)
    np.testing.assert_allclose(g.ddt[mid], -g.t[mid] / 4.0, atol=1e-15)
    np.testing.assert_array_equal(g.dt[[0, 1, 6, 7]], 0.0)


def test_a_corner_in_a_tilted_plane_worked_by_hand():
    """(0,0,0)->(10,0,0)->(10,8,6): a right-angle turn in a plane tilted 36.87 deg about x.
    On the arc t = cos(phi) x + sin(phi) (0, .8, .6), so psi = atan2(.8 sin, cos) and
    dpsi/ds = .8 / (R (cos^2 + .64 sin^2)): 0.8/R entering, 1/(0.8 R) leaving."""
    R = 3.0
    rail = check_rail([[0, 0, 0], [10, 0, 0], [10, 8, 6]], R)
    assert rail.length_m == pytest.approx(20.0 - 2 * R + R * np.pi / 2, rel=1e-15)
    phi = np.array([0.0, 0.3, np.pi / 4, 1.2, np.pi / 2])
    g = rail.at(10.0 - R + R * phi)
    c, s = np.cos(phi), np.sin(phi)
    np.testing.assert_allclose(g.t, np.c_[c, 0.8 * s, 0.6 * s], atol=1e-15)
    np.testing.assert_allclose(g.r[:, 2], 0.6 * R * (1 - c), atol=1e-14)
    np.testing.assert_allclose(g.heading, np.arctan2(0.8 * s, c), atol=1e-15)
    np.testing.assert_allclose(g.dheading[:-1], (0.8 / (c * c + 0.64 * s * s) / R)[:-1], rtol=1e-14)
    # the last point is the arc's end: the straight piece that starts there turns no more
    assert g.dheading[-1] == 0.0
    q = c * c + 0.64 * s * s
    np.testing.assert_allclose(g.ddheading[:-1], (0.8 * 2 * 0.36 * c * s / q**2 / R**2)[:-1], rtol=1e-13, atol=1e-16)
    np.testing.assert_allclose(rail.at([rail.length_m]).r[0], [10, 8, 6], atol=1e-14)


def test_arc_length_and_points_against_an_independent_construction():
    """The sheer-line rail's length against the summed chords of its independent dense
    construction (8.2e-12 relative, the chords' own shortfall R theta dphi^2 / 24 over the
    length), and every sample of that construction is where the rail puts the same arc
    length (2.8e-14 m)."""
    R = 6.0
    rail = check_rail(SHEER, R)
    pts, s, joins = _independent_rounding(SHEER, R)
    chords = np.linalg.norm(np.diff(pts, axis=0), axis=1).sum()
    assert abs(chords - rail.length_m) / rail.length_m < 1.5e-11
    assert abs(s[-1] - rail.length_m) / rail.length_m < 1e-15
    gap = np.abs(rail.at(np.clip(s, 0, rail.length_m)).r - pts).max()
    assert gap < 1e-13
    assert rail.least_radius_m == R


def _fd_gaps(rail, s, h):
    """Largest gaps between each derivative and the central differences of its integral,
    relative to the derivative's largest magnitude over ``s``."""
    g, up, dn = rail.at(s), rail.at(s + h), rail.at(s - h)
    pairs = [("r", "t"), ("t", "dt"), ("dt", "ddt"), ("heading", "dheading"), ("dheading", "ddheading")]
    out = {}
    for f, d in pairs:
        fd = (getattr(up, f) - getattr(dn, f)) / (2 * h)
        out[d] = np.abs(fd - getattr(g, d)).max() / np.abs(getattr(g, d)).max()
    return out


def test_derivatives_against_finite_differences_along_the_sheer_line():
    """t, dt, ddt, dpsi/ds, d2psi/ds2 against central differences of the rail (h = 1e-4 m)
    at 4000 arc lengths at least 2h from a join: worst 1.1e-10 relative (h = 1e-3 gives
    4.6e-9, h^2 truncation; h = 1e-5 1.3e-9, rounding)."""
    R = 6.0
    rail = check_rail(SHEER, R)
    _, _, joins = _independent_rounding(SHEER, R, per_arc=3)
    h = 1e-4
    s = np.linspace(2 * h, rail.length_m - 2 * h, 4000)
    s = s[np.abs(s[:, None] - joins[None, :]).min(axis=1) > 2 * h]
    gaps = _fd_gaps(rail, s, h)
    assert max(gaps.values()) < 3e-10, gaps


def test_at_the_joins_one_sided_differences_and_continuity():
    """At each straight/arc join of the sheer line: r, t and the heading are continuous (they
    change across 2e-10 m by no more than 2e-10 m and 2e-10/R); just after the join the
    values are the next piece's (second-order forward differences, h = 1e-4, agree to
    3.5e-10 relative), just before it the previous piece's (backward differences); dt does
    jump there (by 1/R = 0.167 1/m: a line-and-arc path's curvature is piecewise constant)."""
    R = 6.0
    rail = check_rail(SHEER, R)
    _, _, joins = _independent_rounding(SHEER, R, per_arc=3)
    inner = joins[1:-1]
    assert inner.size == 8  # four corners with arcs, the collinear point without
    h = 1e-4
    eps = 1e-10  # the joins here and in the rail agree to ~1e-14 m, not to the last bit
    at, before = rail.at(inner + eps), rail.at(inner - eps)
    assert np.abs(at.r - before.r).max() < 2.01 * eps
    for f in ("t", "heading"):
        assert np.abs(getattr(at, f) - getattr(before, f)).max() < 2.01 * eps / R
    jumps = np.linalg.norm(at.dt - before.dt, axis=1)
    np.testing.assert_allclose(jumps, 1.0 / R, rtol=1e-12)
    f0, f1, f2 = at, rail.at(inner + eps + h), rail.at(inner + eps + 2 * h)
    b1, b2 = rail.at(inner - eps - h), rail.at(inner - eps - 2 * h)
    for f, d in [("r", "t"), ("t", "dt"), ("dt", "ddt"), ("heading", "dheading"), ("dheading", "ddheading")]:
        fwd = (-3 * getattr(f0, f) + 4 * getattr(f1, f) - getattr(f2, f)) / (2 * h)
        bwd = (3 * getattr(before, f) - 4 * getattr(b1, f) + getattr(b2, f)) / (2 * h)
        scale = max(np.abs(getattr(f0, d)).max(), np.abs(getattr(before, d)).max())
        assert np.abs(fwd - getattr(f0, d)).max() <= 5e-10 * scale, (f, d)
        assert np.abs(bwd - getattr(before, d)).max() <= 5e-10 * scale, (f, d)


def test_the_heading_is_unwrapped_along_a_rail_that_circles_twice():
    """A square loop driven round twice while rising (a ramp): the heading climbs to 4 pi at
    the end, steps no more than the arcs' turn between dense samples, and the total turn is
    the eight corners' 8 x pi/2 (only 7 are rounded: the last leg ends at the start's x)."""
    square = [[0, 0], [10, 0], [10, 10], [0, 10]]
    pts = [[*square[k % 4], 0.3 * k] for k in range(9)] + [[5.0, 0.0, 2.55]]
    rail = check_rail(pts, 1.5)
    s = np.linspace(0.0, rail.length_m, 20001)
    g = rail.at(s)
    # a corner's plane barely tilted (0.3 m rise in 10 m): the heading turns at about 1/R
    assert np.abs(np.diff(g.heading)).max() < 1.01 / 1.5 * rail.length_m / 20000
    # each corner's horizontal turn is exactly pi/2 (the plane of each corner is tilted,
    # but both segments' horizontal directions are axis-aligned)
    assert g.heading[-1] == pytest.approx(4 * np.pi, abs=1e-14)
    # the turn rate integrates to the heading (trapezoid, 20001 samples)
    # (measured 1.8e-3 short: the trapezoid's error at the 14 jumps of dpsi/ds at the joins)
    assert np.trapezoid(g.dheading, s) == pytest.approx(4 * np.pi, abs=2.5e-3)


def test_collinear_points_and_a_straight_rail():
    """Collinear middle points get no arc (length = the sum of the segments) and a straight
    rail's least radius is infinite; radius 0 is allowed there."""
    rail = check_rail([[0, 0, 0], [3, 4, 0], [6, 8, 0], [9, 12, 0]], 0.0)
    assert rail.length_m == pytest.approx(15.0, rel=1e-15)
    assert rail.least_radius_m == np.inf
    g = rail.at([0.0, 7.5, 15.0])
    np.testing.assert_allclose(g.r, [[0, 0, 0], [4.5, 6, 0], [9, 12, 0]], atol=1e-14)
    np.testing.assert_allclose(g.heading, np.arctan2(4, 3), atol=1e-15)


def test_the_largest_radius_that_fits_is_named_and_fits():
    """Two right-angle turns 4 m apart: the tangent lengths R tan 45 deg add up to 2R, so
    R = 2 m is the largest that fits; 2.1 m is refused naming the corner and 2 m, and
    2 m itself gives a rail with no straight piece between the arcs (length 10+4+10-8+2pi).
    A radius quoted in the message (rounded down to 6 digits) fits (a 60 deg turn here)."""
    pts = [[0, 0, 0], [10, 0, 0], [10, 4, 0], [20, 4, 0]]
    with pytest.raises(RailError, match=r"corner at point 2 .*largest radius that fits is 2.0 m") as e:
        check_rail(pts, 2.1)
    assert "\n" not in str(e.value)
    rail = check_rail(pts, 2.0)
    assert rail.length_m == pytest.approx(24.0 - 8.0 + 2 * np.pi, rel=1e-15)
    pts = [[0, 0, 0], [10, 0, 0], [15, 5 * np.sqrt(3), 0]]  # fits R tan 30 deg <= 10
    with pytest.raises(RailError, match=r"largest radius that fits is 17.3205 m") as e:
        check_rail(pts, 20.0)
    assert check_rail(pts, 17.3205).least_radius_m == 17.3205


@pytest.mark.parametrize(
    "points, radius, pattern",
    [
        ([[0, 0, 0]], 1.0, r"points_S: needs at least 2 points, got 1"),
        ([[0, 0], [1, 0]], 1.0, r"points_S: must have shape \(n_points, 3\), got shape \(2, 2\)"),
        ([[0, 0, 0], [1, np.nan, 0]], 1.0, r"points_S\[2\]: must be finite"),
        ([[0, 0, 0], [1, 0, 0], [1, 0, 1e-10]], 1.0, r"points_S\[3\]: points 2 and 3 are .* closer than 1e-09 m"),
        ([[0, 0, 0], [1, 0, 0], [0, 0, 0]], 0.1, r"points_S\[2\]: the rail turns back on itself at point 2"),
        ([[0, 0, 0], [1, 0, 0], [1, 1, 0]], 0.0, r"corner_radius_m: must be > 0: the rail has a corner at point 2"),
        ([[0, 0, 0], [1, 0, 0]], -1.0, r"corner_radius_m: must be >= 0"),
        ([[0, 0, 0], [1, 0, 0]], np.inf, r"corner_radius_m: must be finite"),
        ([[0, 0, 0], [1, 0, 0], [1, 0, 5]], 0.5, r"tangent turns vertical near s = 0.5 m"),
        # an arc from (1, 0, 1) to (-1, 0, 1): vertical at its middle only
        ([[0, 0, 0], [10, 0, 10], [0, 0, 20]], 1.0, r"tangent turns vertical near s = 13.1421 m"),
        ([[0, 0, 0], [10, 0, 0], [10, 10, 0]], 10.5, r"largest radius that fits is 10.0 m"),
    ],
)
def test_bad_rails_are_refused_in_one_line(points, radius, pattern):
    with pytest.raises(RailError, match=pattern) as e:
        check_rail(points, radius)
    assert "\n" not in str(e.value)
    assert isinstance(e.value, ScenarioError) and isinstance(e.value, ValueError)


def test_arc_lengths_and_stations_off_the_rail_are_refused():
    rail = check_rail(L_RAIL, 2.0)
    with pytest.raises(RailError, match=r"s: arc lengths outside the rail's \[0, 19.14\d+\] m: \[2\]=-0.5, \[3\]=20.0"):
        rail.at([1.0, -0.5, 20.0])
    with pytest.raises(RailError, match=r"stations_m: stations outside .*\[1\]=-1.0"):
        check_stations(rail, [-1.0, 5.0])
    np.testing.assert_array_equal(check_stations(rail, [0.0, 5.0, rail.length_m + 1e-10]), [0.0, 5.0, rail.length_m])


# --- the double-S move ------------------------------------------------------------------------


def test_the_textbook_double_s():
    """Biagiotti & Melchiorri's example (h = 10, v_max = 5, a_max = 10, j_max = 30): v_max and
    a_max reached, Tj = 1/3, Ta = 5/6, Tv = 7/6, T = 17/6."""
    m = scurve_move(10.0, 5.0, 10.0, 30.0)
    np.testing.assert_allclose(m.phases_s, [1 / 3, 1 / 6, 1 / 3, 7 / 6, 1 / 3, 1 / 6, 1 / 3], rtol=0, atol=1e-15)
    assert m.duration_s == pytest.approx(17 / 6, rel=1e-15)
    assert m.jerk == 30.0
    t = np.array([1 / 3, 5 / 6, 2.0, 17 / 6])
    s, v, a, _ = carriage_profile([0.0, 10.0], 0.0, 5.0, 10.0, 30.0, t)
    # after Tj: a = j Tj = 10, v = j Tj^2 / 2 = 5/3, s = j Tj^3 / 6 = 5/27; at Ta: v = 5, s = v Ta / 2
    np.testing.assert_allclose(s, [5 / 27, 25 / 12, 10 - 25 / 12, 10.0], rtol=1e-14)
    np.testing.assert_allclose(v, [5 / 3, 5.0, 5.0, 0.0], atol=1e-14)
    np.testing.assert_allclose(a, [10.0, 0.0, 0.0, 0.0], atol=1e-13)


def test_v_max_not_reached():
    """h = 10, v_max = 10, a_max = 10, j_max = 30: Tv = 0, Tj = 1/3 and
    Ta = (a^2/j + sqrt(a^4/j^2 + 4 h a)) / (2a) = (1 + sqrt 37) / 6, so T = (1 + sqrt 37) / 3;
    the peak speed a (Ta - Tj) = 10 (sqrt 37 - 1) / 6 = 8.47 m/s."""
    m = scurve_move(10.0, 10.0, 10.0, 30.0)
    ta = (1 + np.sqrt(37)) / 6
    np.testing.assert_allclose(m.phases_s, [1 / 3, ta - 2 / 3, 1 / 3, 0, 1 / 3, ta - 2 / 3, 1 / 3], atol=1e-15)
    assert m.duration_s == pytest.approx((1 + np.sqrt(37)) / 3, rel=1e-15)
    s, v, a, _ = carriage_profile([0.0, 10.0], 0.0, 10.0, 10.0, 30.0, [ta, m.duration_s])
    np.testing.assert_allclose([s[0], v[0], a[0]], [5.0, 10 * (np.sqrt(37) - 1) / 6, 0.0], atol=1e-13)
    assert s[1] == pytest.approx(10.0, rel=1e-15)


def test_a_max_not_reached():
    """h = 1 with the same limits: a triangular acceleration, Tj = (h / 2j)^(1/3) = 0.2554 s,
    T = 4 Tj, peak acceleration j Tj = 7.66 < 10; and v_max = 1 reached without a_max:
    Tj = sqrt(v/j), Ta = 2 Tj, Tv = h/v - Ta, T = 10 + 2 sqrt(1/30)."""
    m = scurve_move(1.0, 10.0, 10.0, 30.0)
    tj = (1 / 60) ** (1 / 3)
    np.testing.assert_allclose(m.phases_s, [tj, 0, tj, 0, tj, 0, tj], atol=1e-15)
    _, v, a, _ = carriage_profile([0.0, 1.0], 0.0, 10.0, 10.0, 30.0, [tj, 2 * tj])
    np.testing.assert_allclose([a[0], v[1]], [30 * tj, 30 * tj * tj], rtol=1e-14)
    m = scurve_move(10.0, 1.0, 10.0, 30.0)
    tj = np.sqrt(1 / 30)
    np.testing.assert_allclose(m.phases_s, [tj, 0, tj, 10 - 2 * tj, tj, 0, tj], atol=1e-14)
    assert m.duration_s == pytest.approx(10 + 2 * tj, rel=1e-15)


def test_zero_and_backward_moves():
    """Distance 0 is a move of no time; a move backwards has the same phases and the mirror
    profile: s_back(t) = 7.5 - s_fwd(t), its rates negated (1e-14)."""
    m0 = scurve_move(0.0, 1.0, 1.0, 1.0)
    assert m0.duration_s == 0.0 and m0.phases_s == (0.0,) * 7
    fwd, back = scurve_move(7.5, 2.0, 1.0, 3.0), scurve_move(-7.5, 2.0, 1.0, 3.0)
    assert back.phases_s == fwd.phases_s and back.distance_m == -7.5
    t = np.linspace(0.0, fwd.duration_s, 101)
    s_f, v_f, a_f, j_f = carriage_profile([0, 7.5], 0, 2.0, 1.0, 3.0, t)
    s_b, v_b, a_b, j_b = carriage_profile([7.5, 0], 0, 2.0, 1.0, 3.0, t)
    np.testing.assert_allclose(s_b, 7.5 - s_f, atol=1e-14)
    np.testing.assert_allclose(np.c_[v_b, a_b, j_b], -np.c_[v_f, a_f, j_f], atol=1e-14)


def _brute_force_duration(h, v, a, j):
    """The least time of a rest-to-rest move from a bisection on its peak speed vp: reaching
    vp from rest takes at least T(vp) = vp/a + a/j (if a is reached) or 2 sqrt(vp/j) and
    covers vp T(vp) / 2; accelerate, cruise at vp, brake symmetrically; vp the largest
    <= v whose acceleration and braking fit within h."""

    def t_acc(vp):
        return vp / a + a / j if vp * j >= a * a else 2.0 * np.sqrt(vp / j)

    def d_both(vp):
        return vp * t_acc(vp)

    if d_both(v) <= h:
        vp = v
    else:
        lo, hi = 0.0, v
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if d_both(mid) <= h else (lo, mid)
        vp = lo
    return 2.0 * t_acc(vp) + (h - d_both(vp)) / vp


@settings(max_examples=150, deadline=None)
@given(
    h=st.floats(1e-3, 1e3) | st.floats(-1e3, -1e-3),
    v=st.floats(1e-2, 10.0),
    a=st.floats(1e-2, 10.0),
    j=st.floats(1e-2, 100.0),
)
def test_double_s_property(h, v, a, j):
    """For random limits and distances: the move ends at the distance at rest (1e-12
    relative; measured 0 on 2000 draws), keeps |v| <= v_max, |a| <= a_max, |jerk| <= j_max on
    4001 samples and at every phase switch, and its duration is the brute-force least time
    (measured 4.4e-16 relative)."""
    m = scurve_move(h, v, a, j)
    T = m.duration_s
    assert T == pytest.approx(_brute_force_duration(abs(h), v, a, j), rel=1e-12)
    switches = np.cumsum((0.0,) + m.phases_s)
    t = np.concatenate([np.linspace(0.0, T, 4001), switches, [T, 2 * T + 1.0]])
    s, sd, sdd, sddd = carriage_profile([0.0, h], 0.0, v, a, j, t)
    assert abs(s[-1] - h) <= 1e-12 * abs(h) and abs(s[-2] - h) <= 1e-12 * abs(h)
    assert abs(sd[-2]) <= 1e-12 * v and abs(sdd[-2]) <= 1e-12 * a
    assert sd[-1] == 0.0 and sdd[-1] == 0.0 and sddd[-1] == 0.0
    assert np.abs(sd).max() <= v * (1 + 1e-12)
    assert np.abs(sdd).max() <= a * (1 + 1e-12)
    assert np.abs(sddd).max() <= j
    assert np.all(np.diff(np.sign(h) * s[:4001]) >= -1e-12 * abs(h))  # it never backs up


# --- the carriage's profile -------------------------------------------------------------------

STATIONS = [0.0, 40.0, 15.0, 15.0, 60.0, 59.9]
DWELLS = [2.0, 0.0, 1.0, 3.0, 1.5, 4.0]
LIMITS = (1.2, 0.8, 2.0)


def _switch_times():
    """Every time the jerk may change: the arrivals, departures and each move's phases."""
    sched = profile_schedule(STATIONS, DWELLS, *LIMITS)
    times = [sched.ravel()]
    for i in range(len(STATIONS) - 1):
        m = scurve_move(STATIONS[i + 1] - STATIONS[i], *LIMITS)
        times.append(sched[i, 1] + np.cumsum((0.0,) + m.phases_s))
    return sched, np.concatenate(times)


def test_the_profile_against_finite_differences():
    """s_dot and s_ddot against central differences of s and s_dot (h = 1e-4 s) everywhere
    (both are continuous): 3.4e-9 m/s (h^2 jerk / 6) and 2.7e-11 m/s^2; the jerk against
    differences of s_ddot at least 2h from a phase switch: 6.6e-11 m/s^3."""
    sched, switches = _switch_times()
    h = 1e-4
    t = np.linspace(h, sched[-1, 1] + 5.0, 20001)
    s, v, a, j = carriage_profile(STATIONS, DWELLS, *LIMITS, t)
    up = carriage_profile(STATIONS, DWELLS, *LIMITS, t + h)
    dn = carriage_profile(STATIONS, DWELLS, *LIMITS, t - h)
    assert np.abs((up[0] - dn[0]) / (2 * h) - v).max() < 5e-9
    assert np.abs((up[1] - dn[1]) / (2 * h) - a).max() < 5e-11
    away = np.abs(t[:, None] - switches[None, :]).min(axis=1) > 2 * h
    assert np.abs((up[2] - dn[2]) / (2 * h) - j)[away].max() < 1e-10


def test_stations_are_held_exactly_during_the_dwells():
    """Between each arrival and departure s is the station exactly and the carriage still;
    each move lasts its double-S duration; after the last dwell it rests at the last station."""
    sched, _ = _switch_times()
    for i, station in enumerate(STATIONS):
        t = np.linspace(sched[i, 0], sched[i, 1], 7)
        s, v, a, j = carriage_profile(STATIONS, DWELLS, *LIMITS, t)
        np.testing.assert_array_equal(s, station)
        np.testing.assert_array_equal(np.c_[v, a], 0.0)
        np.testing.assert_array_equal(j[t < sched[i, 1]], 0.0)  # at the departure the move's jerk starts
        if i + 1 < len(STATIONS):
            move = scurve_move(STATIONS[i + 1] - station, *LIMITS)
            assert sched[i + 1, 0] - sched[i, 1] == pytest.approx(move.duration_s, rel=1e-14)
        assert sched[i, 1] - sched[i, 0] == pytest.approx(DWELLS[i], abs=1e-13)
    s, v, _, _ = carriage_profile(STATIONS, DWELLS, *LIMITS, [sched[-1, 1] + 1e6])
    assert s[0] == STATIONS[-1] and v[0] == 0.0


def test_the_profile_does_not_depend_on_the_order_of_times():
    """Times shuffled give the same values shuffled (a vectorised lookup, no state)."""
    t = np.linspace(0.0, 150.0, 3001)
    perm = np.random.default_rng(3).permutation(t.size)
    a = carriage_profile(STATIONS, 1.0, *LIMITS, t)
    b = carriage_profile(STATIONS, 1.0, *LIMITS, t[perm])
    for x, y in zip(a, b):
        np.testing.assert_array_equal(x[perm], y)


@pytest.mark.parametrize(
    "args, pattern",
    [
        (dict(v_max=0.0), r"v_max: must be > 0, got 0.0"),
        (dict(a_max=-1.0), r"a_max: must be > 0, got -1.0"),
        (dict(j_max=np.nan), r"j_max: must be finite"),
        (dict(stations_m=[0.0, np.inf]), r"stations_m\[2\]: must be finite"),
        (dict(dwell_s=-1.0), r"dwell_s: must be >= 0, got -1.0"),
        (dict(dwell_s=[1.0, 2.0]), r"dwell_s: must be a number or one per station \(3\), got 2"),
        (dict(dwell_s=[1.0, -2.0, 0.0]), r"dwell_s\[2\]: must be >= 0"),
        (dict(t=[0.0, -0.1]), r"t: times before 0: \[2\]=-0.1"),
        (dict(stations_m=[]), r"stations_m: needs at least 1 station"),
        (dict(stations_m=[[0.0, 1.0]]), r"stations_m: must be one-dimensional"),
    ],
)
def test_bad_profiles_are_refused_in_one_line(args, pattern):
    kw = dict(stations_m=[0.0, 5.0, 2.0], dwell_s=1.0, v_max=1.0, a_max=1.0, j_max=1.0, t=[0.0, 1.0])
    kw.update(args)
    with pytest.raises(RailError, match=pattern) as e:
        carriage_profile(**kw)
    assert "\n" not in str(e.value)
