"""Issue 21, item 7: the boundary pass covers what the lanes leave, and flies no lane again.

paper_clean's panel (1.3 x 0.8 m, a 0.2 m brush, 0.03 m overlap): 5 lanes along x at
z = 0.4 .. 1.0, from x = 0.4 to 1.5. The old pass went round the whole inset outline,
its bottom and top edges the first and last lanes again (2 x 1.1 m of 9.5 m).
"""

import numpy as np
import pytest

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
    total = 0.0
    for p, q in segs:
        n = max(2, int(np.ceil(np.linalg.norm(q - p) / step)) + 1)
        s = p + np.linspace(0, 1, n)[:, None] * (q - p)
        new = np.array([np.any(np.linalg.norm(dirty - x, axis=1) <= R - 2 * h) for x in s])
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
