"""Interference (issue 23, item 4): cable-cable, cable-platform and cable-obstacle distances,
checked against hand-worked cases and slow obvious references, and through every command."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import minimize_scalar
from typer.testing import CliRunner

import marinecdpr
from marinecdpr.cli.app import app
from marinecdpr.geometry.interference import (
    cable_pairs, cable_platform_distance, platform_body, segment_box_bounds, segment_box_distance, segment_distance,
    segment_plane_distance,
)
from marinecdpr.geometry.rotations import matrix_from_euler
from marinecdpr.planning.interference import pose_clearances
from marinecdpr.planning.planner import iter_plan, plan, PlanSummary, trajectory_interference
from tests.conftest import one_line_exit_2

runner = CliRunner()
EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


# ------------------------------------------------------------------ references (slow, obvious)
def reference_segment_distance(p0, p1, q0, q1) -> float:
    """The least of |P(s) - Q(t)| over the convex problem's candidates: the two lines'
    stationary point if inside the square, and each edge's (one parameter at 0 or 1, the
    other the clamped projection), written out one by one."""
    d1, d2 = p1 - p0, q1 - q0

    def dist(s, t):
        return float(np.linalg.norm(p0 + s * d1 - q0 - t * d2))

    def project(x, a, d):  # the parameter of the closest point of segment a + t d to x
        dd = float(d @ d)
        return 0.0 if dd == 0.0 else min(1.0, max(0.0, float((x - a) @ d) / dd))

    best = min(dist(0.0, project(p0, q0, d2)), dist(1.0, project(p1, q0, d2)),
               dist(project(q0, p0, d1), 0.0), dist(project(q1, p0, d1), 1.0))
    A = np.array([[d1 @ d1, -(d1 @ d2)], [-(d1 @ d2), d2 @ d2]])
    if abs(np.linalg.det(A)) > 1e-12 * max(np.abs(A).max(), 1e-300) ** 2:
        s, t = np.linalg.solve(A, [-(d1 @ (p0 - q0)), d2 @ (p0 - q0)])
        if 0.0 <= s <= 1.0 and 0.0 <= t <= 1.0:
            best = min(best, dist(s, t))
    return best


def reference_box_distance(p0, p1, centre, R, half) -> float:
    """min over the segment of the point-box distance (convex in s): a dense scan, then a
    bounded scalar minimisation around the best sample."""
    def f(s):
        x = (p0 + s * (p1 - p0) - centre) @ R
        out = np.maximum(np.abs(x) - half, 0.0)
        return float(np.sqrt(out @ out))

    grid = np.linspace(0.0, 1.0, 2001)
    x = (p0 + grid[:, None] * (p1 - p0) - centre) @ R  # f at every sample, as one array
    values = np.sqrt(np.sum(np.maximum(np.abs(x) - half, 0.0) ** 2, axis=1))
    k = int(np.argmin(values))
    res = minimize_scalar(f, bounds=(grid[max(k - 1, 0)], grid[min(k + 1, 2000)]), method="bounded",
                          options={"xatol": 1e-14})
    return min(float(res.fun), float(values[k]))


# ------------------------------------------------------------------ segments by hand
def test_two_crossing_segments_by_hand():
    # along x at z = 0, along y at z = 0.3: they cross above each other's middles, 0.3 m apart
    d, s, t = segment_distance(np.array([-1.0, 0, 0]), np.array([1.0, 0, 0]), np.array([0, -1.0, 0.3]),
                               np.array([0, 1.0, 0.3]))
    assert float(d) == pytest.approx(0.3, abs=1e-15) and float(s) == 0.5 and float(t) == 0.5
    # the same, the second moved off the first's end: the closest points are the end and the middle
    d, s, t = segment_distance(np.array([-1.0, 0, 0]), np.array([1.0, 0, 0]), np.array([1.5, -1.0, 0.3]),
                               np.array([1.5, 1.0, 0.3]))
    assert float(d) == pytest.approx(math.hypot(0.5, 0.3), abs=1e-15) and float(s) == 1.0 and float(t) == 0.5
    # parallel, overlapping along x: the lines' distance
    d, *_ = segment_distance(np.array([0.0, 0, 0]), np.array([1.0, 0, 0]), np.array([0.5, 0.4, 0]),
                             np.array([2.0, 0.4, 0]))
    assert float(d) == pytest.approx(0.4, abs=1e-15)
    # collinear, apart: end to end
    d, *_ = segment_distance(np.array([0.0, 0, 0]), np.array([1.0, 0, 0]), np.array([3.0, 0, 0]),
                             np.array([4.0, 0, 0]))
    assert float(d) == 2.0
    # a segment of no length is a point: its distance to the other
    d, *_ = segment_distance(np.array([0.5, 2.0, 0]), np.array([0.5, 2.0, 0]), np.array([0.0, 0, 0]),
                             np.array([1.0, 0, 0]))
    assert float(d) == 2.0
    # two crossing (intersecting) cables
    d, *_ = segment_distance(np.array([0.0, 0, 0]), np.array([2.0, 2.0, 0]), np.array([2.0, 0, 0]),
                             np.array([0.0, 2.0, 0]))
    assert float(d) == 0.0


def test_segment_distance_equals_the_candidates_reference_on_random_segments():
    rng = np.random.default_rng(23)
    P = rng.normal(size=(3000, 4, 3))
    P[:300, 1] = P[:300, 0] + (P[:300, 3] - P[:300, 2]) * rng.uniform(-2, 2, (300, 1))  # parallel pairs
    P[300:400, 1] = P[300:400, 0]  # points
    d, s, t = segment_distance(P[:, 0], P[:, 1], P[:, 2], P[:, 3])
    ref = np.array([reference_segment_distance(*p) for p in P])
    np.testing.assert_allclose(d, ref, rtol=0, atol=2e-14)  # measured: 6e-15
    gap = P[:, 0] + s[:, None] * (P[:, 1] - P[:, 0]) - P[:, 2] - t[:, None] * (P[:, 3] - P[:, 2])
    np.testing.assert_allclose(np.linalg.norm(gap, axis=1), d, rtol=0, atol=1e-15)  # where it says
    assert ((0 <= s) & (s <= 1) & (0 <= t) & (t <= 1)).all()


def test_plane_distance_is_signed_by_hand():
    p0, p1 = np.array([0.0, 0.5, 0.0]), np.array([1.0, -0.2, 0.0])
    d = segment_plane_distance(p0, p1, np.array([0.0, 0.1, 0.0]), np.array([0.0, 1.0, 0.0]))
    assert float(d) == pytest.approx(-0.3, abs=1e-15)  # its far end 0.3 m behind y = 0.1


def test_box_distance_equals_a_scan_and_minimisation_of_the_point_distance():
    rng = np.random.default_rng(7)
    R = matrix_from_euler(np.array([0.3, -0.6, 1.1]))
    centre, half = np.array([0.3, -0.2, 0.5]), np.array([0.4, 0.2, 0.7])
    P = rng.normal(size=(400, 2, 3)) * 1.5
    d = segment_box_distance(P[:, 0], P[:, 1], centre, R, half)
    ref = np.array([reference_box_distance(p[0], p[1], centre, R, half) for p in P])
    np.testing.assert_allclose(d, ref, rtol=0, atol=1e-12)  # measured: 9e-16
    assert 0.03 < (d == 0).mean() < 0.5  # both kinds drawn: through the box and clear of it
    # by hand: a segment along x 0.5 m above an axis-aligned unit box's top face
    d = segment_box_distance(np.array([-3.0, 0, 1.0]), np.array([3.0, 0, 1.0]), np.zeros(3), np.eye(3),
                             np.array([0.5, 0.5, 0.5]))
    assert float(d) == 0.5


# ------------------------------------------------------------------ the platform's body
def test_a_flat_platform_is_its_outline():
    p = np.array([[-0.125, 0, 0.15], [0.125, 0, 0.15], [0.125, 0, -0.15], [-0.125, 0, -0.15]])
    body = platform_body(p)
    assert body.edges_P.shape == (4, 2, 3) and not body.solid
    assert (body.away.sum(axis=1) == 2).all()  # each corner is measured to the two edges away from it
    x, R = np.zeros((1, 3)), np.eye(3)[None]
    # cable 1 leaves its corner up and out: nearest edge away from it is the right one, 0.25 m off
    ends = p[None]
    starts = ends + np.array([[-1.0, 0, 1.0], [1.0, 0, 1.0], [1.0, 0, -1.0], [-1.0, 0, -1.0]])[None]
    assert cable_platform_distance(body, x, R, starts, ends)[0] == pytest.approx([0.25] * 4, abs=1e-15)
    # cable 1 turned to run across the platform towards the right: it crosses the edges away
    starts[0, 0] = [2.0, 0.0, 0.0]
    assert cable_platform_distance(body, x, R, starts, ends)[0, 0] == pytest.approx(0.0, abs=1e-15)


def test_a_cable_into_a_solid_platform_touches_it():
    a = 0.1
    cube = np.array([[i, j, k] for i in (-a, a) for j in (-a, a) for k in (-a, a)])
    body = platform_body(cube)
    assert body.solid and body.edges_P.shape == (12, 2, 3) and (body.away.sum(axis=1) == 9).all()
    x, R = np.zeros((1, 3)), np.eye(3)[None]
    ends = cube[None]
    outward = ends + 3.0 * cube[None] / a  # each along its own diagonal, out
    d = cable_platform_distance(body, x, R, outward, ends)
    np.testing.assert_allclose(d, 2 * a, rtol=0, atol=1e-15)  # a corner's nearest edges away: 2a by hand
    inward = ends - 3.0 * cube[None] / a  # through the body to the opposite side
    assert (cable_platform_distance(body, x, R, inward, ends) == 0.0).all()


def test_cables_sharing_a_point_are_not_paired():
    c = np.array([[0.0, 0, 0], [0.0, 0, 0], [1.0, 0, 0]])
    p = np.array([[0.0, 0, 0.1], [0.1, 0, 0], [0.1, 0, 0]])
    assert cable_pairs(c, p).tolist() == [[0, 2]]


# ------------------------------------------------------------------ a robot whose cables touch
@pytest.fixture(scope="module")
def cube8():
    return marinecdpr.load_scenario(EXAMPLES / "spatial_cube8.toml").with_updates("robot", clearance_m=0.01)


def test_crossed_cube8_cables_touch_at_the_frames_centre(cube8):
    """The example's crossed cables: cable 1 from (0, 0, 0) to the corner (0.1, -0.1, -0.1) of the
    platform at the centre (1, 1, 1), cable 2 from (2, 0, 0) to (-0.1, -0.1, -0.1): both lie in
    the plane y = z and meet at x = 1 (by hand: t = 1 / 1.1 along each)."""
    gaps = pose_clearances(cube8.robot, cube8.obstacles, np.array([[1.0, 1.0, 1.0]]), np.eye(3)[None])
    pair = {tuple(p): k for k, p in enumerate(gaps.pairs.tolist())}
    for i, j in ((0, 1), (2, 3), (4, 7), (5, 6)):  # each crossed pair meets
        assert gaps.cable_cable[0, pair[(i, j)]] == pytest.approx(0.0, abs=1e-15)
    assert gaps.cable_cable[0, pair[(0, 2)]] == pytest.approx(
        reference_segment_distance(np.array([0.0, 0, 0]), np.array([1.1, 0.9, 0.9]),
                                   np.array([2.0, 2.0, 0]), np.array([0.9, 1.1, 0.9])), abs=1e-15)
    line = trajectory_interference(cube8)
    assert line.startswith("the cables come closer than robot.clearance_m = 0.01 m at ")
    assert "first at t = 0 s (x = 1 m, y = 1 m, z = 1 m" in line and "cables 3 and 4 0 m apart" in line


def test_the_plan_flags_the_same_steps_in_pieces_and_whole(cube8):
    sc = cube8.with_changes(time={"step_s": 0.01, "duration_s": 8.0})
    whole = plan(sc)
    summary = PlanSummary()
    for piece in iter_plan(sc, chunk_steps=200):
        summary.add(piece)
    assert summary.n_interfering == int(whole.interfering.sum()) > 0
    assert summary.interference() == whole.interference()
    # the plan's distances are the references' at the planned poses
    for k in (0, 333, 650):
        x, R = whole.pose[k, :3], matrix_from_euler(whole.pose[k, 3:])
        ends = x + sc.robot.platform_anchors @ R.T
        for n, (i, j) in enumerate(whole.clearances.pairs):
            ref = reference_segment_distance(sc.robot.frame_anchors[i], ends[i], sc.robot.frame_anchors[j], ends[j])
            assert whole.clearances.cable_cable[k, n] == pytest.approx(ref, abs=1e-14)


# ------------------------------------------------------------------ through every command
def _planar(tmp_path: Path, extra: str = "", duration: float = 0.5) -> Path:
    text = (Path(marinecdpr.__file__).parent / "scenario" / "builtin" / "paper.toml").read_text()
    text = text.replace("tension_max_N = 450.0", "tension_max_N = 450.0\nclearance_m = 0.05", 1)
    text = text.replace("duration_s = 15.0", f"duration_s = {duration}")
    path = tmp_path / "clear.toml"
    path.write_text(text + extra)
    return path


BOLLARD = """
[[obstacles]]
type = "box"
name = "bollard"
center_m = [1.5, 0.0, 1.2]
size_m = [0.1, 0.3, 0.1]
"""


def test_plan_exits_3_naming_the_cable_and_the_obstacle(tmp_path):
    scen = _planar(tmp_path, BOLLARD)
    res = runner.invoke(app, ["plan", str(scen), "--out", str(tmp_path / "o")])
    assert res.exit_code == 3, res.output
    line = [ln for ln in res.stderr.splitlines() if ln.startswith("interference:")]
    assert len(line) == 1 and "cable 2 0 m from obstacle 1 ('bollard', a box)" in line[0]
    header = (tmp_path / "o" / "plan.csv").read_text().splitlines()[0].split(",")
    assert header[-5:] == ["gap1", "gap2", "gap3", "gap4", "feasible"]
    data = np.loadtxt(tmp_path / "o" / "plan.csv", delimiter=",", skiprows=1)
    sc = marinecdpr.load_scenario(scen)
    p = plan(sc)
    np.testing.assert_allclose(data[:, -5:-1], p.clearance, rtol=1e-9)
    # cable 2 runs from (1.9, 0, 1.4) to the platform's top right corner, past the box: the steps
    # the line counts are those where its gap is under the clearance
    flagged = int((data[:, -4] < 0.05).sum())
    assert 0 < flagged and f"at {int((data[:, -5:-1] < 0.05).any(axis=1).sum())} of 501 steps" in line[0]
    assert runner.invoke(app, ["plan", str(scen), "--out", str(tmp_path / "o2"),
                               "--allow-infeasible"]).exit_code == 0


def test_plan_without_a_clearance_is_unchanged(tmp_path, paper_plan):
    assert paper_plan.clearance is None and not paper_plan.interfering.any() and paper_plan.interference() is None


def test_check_warns_and_workspace_maps_the_layer(tmp_path):
    scen = _planar(tmp_path, BOLLARD)
    res = runner.invoke(app, ["check", str(scen)])
    assert res.exit_code == 0 and "warning:" in res.stderr and "('bollard', a box)" in res.stderr
    res = runner.invoke(app, ["workspace", str(scen), "--out", str(tmp_path / "w"), "--points", "6x5",
                              "--duration", "0.05"])
    assert res.exit_code == 0, res.output
    names = (tmp_path / "w" / "workspace.csv").read_text().splitlines()[0].split(",")
    assert names[-2:] == ["least_clearance_m", "interference_free"]
    data = np.loadtxt(tmp_path / "w" / "workspace.csv", delimiter=",", skiprows=1)
    sc = marinecdpr.load_scenario(scen)
    x = np.column_stack([data[:, 0], np.zeros(len(data)), data[:, 1]])
    want = pose_clearances(sc.robot, sc.obstacles, x, np.broadcast_to(np.eye(3), (len(data), 3, 3)))
    # the grid's coordinates as the CSV prints them (10 digits): distances agree to that
    np.testing.assert_allclose(data[:, -2], want.per_cable.min(axis=1), rtol=0, atol=1e-9)
    assert ((data[:, -1] == 1) == (data[:, -2] >= 0.05)).all() and 0 < data[:, -1].sum() < len(data)


def test_simulate_and_clean_report_interference(tmp_path):
    scen = _planar(tmp_path, BOLLARD, duration=0.05)
    res = runner.invoke(app, ["simulate", str(scen), "--out", str(tmp_path / "s"), "--plant", "own"])
    assert res.exit_code == 0, res.output
    s = json.loads((tmp_path / "s" / "summary.json").read_text())
    assert s["interference"]["clearance_m"] == 0.05 and s["interference"]["steps_closer"] == 51
    assert any(w.startswith("plan: the cables come closer") for w in s["warnings"])
    assert "('bollard', a box)" in res.stderr

    text = (Path(marinecdpr.__file__).parent / "scenario" / "builtin" / "paper_clean.toml").read_text()
    text = text.replace("tension_max_N = 450.0", "tension_max_N = 450.0\nclearance_m = 0.02", 1)
    text += '\n[[obstacles]]\ntype = "plane"\nname = "hull"\npoint_m = [0.0, -0.01, 0.0]\nnormal = [0.0, 1.0, 0.0]\n'
    (tmp_path / "c.toml").write_text(text)
    (tmp_path / "paper_sea_rao.csv").write_bytes(
        (Path(marinecdpr.__file__).parent / "scenario" / "builtin" / "paper_sea_rao.csv").read_bytes())
    res = runner.invoke(app, ["clean", str(tmp_path / "c.toml"), "--out", str(tmp_path / "c"), "--duration", "0.2",
                              "--no-compare", "--plant", "own"])
    assert res.exit_code == 0, res.output
    s = json.loads((tmp_path / "c" / "summary.json").read_text())
    # the planar robot's cables lie in y = 0, 0.01 m in front of the hull plane: every step closer than 0.02 m
    assert s["interference"]["least_clearance_m"] == pytest.approx([0.01] * 4, abs=1e-15)
    assert s["interference"]["steps_closer"] == s["steps"]
    assert "obstacle 1 ('hull', a plane)" in res.stderr


@pytest.mark.parametrize("extra, words", [
    ('\n[[obstacles]]\ntype = "plane"\npoint_m = [0.0, 0.0, 0.0]\nnormal = [0.0, 2.0, 0.0]\n',
     ("obstacles[1].normal", "unit vector")),
    ('\n[[obstacles]]\ntype = "box"\ncenter_m = [0.0, 0.0, 0.0]\nsize_m = [1.0, 0.0, 1.0]\n',
     ("obstacles[1].size_m[2]", "above 0")),
    ('\n[[obstacles]]\ntype = "cone"\n', ("obstacles[1].type", "'box', 'plane'")),
    ('\n[[obstacles]]\ntype = "box"\ncentre_m = [0.0, 0.0, 0.0]\nsize_m = [1.0, 1.0, 1.0]\n',
     ("obstacles[1].centre_m", "did you mean 'center_m'")),
])
def test_bad_obstacles_are_one_line(tmp_path, extra, words):
    res = runner.invoke(app, ["check", str(_planar(tmp_path, extra))])
    one_line_exit_2(res, *words)


def test_obstacles_need_a_clearance(tmp_path):
    text = _planar(tmp_path, BOLLARD).read_text().replace("clearance_m = 0.05\n", "")
    (tmp_path / "n.toml").write_text(text)
    one_line_exit_2(runner.invoke(app, ["check", str(tmp_path / "n.toml")]), "robot.clearance_m", "missing")


# ------------------------------------------------------------------ WireX's IPAnema 3
# IPAnema 3 as WireX's generator builds it (gldkhoward/WireX @ 8a0db46, MIT, (c) 2006-2019
# Andreas Pott: wirex-master/WireLib/GeometryGenerator.cpp, IPAnema3Design, lines 483-551:
# frame 8 x 3.5 x 3.25 m (lower anchors at 0.25 m, 0.2 m and 0.25 m further out), platform
# 1.5 x 0.5 x 0.5 m with its lower points 0.2 m and 0.1 m further in), anchors worked out
# from its parameters.
IPANEMA3_FRAME = np.array([(-3.8, 1.75, 3.25), (3.8, 1.75, 3.25), (3.8, -1.75, 3.25), (-3.8, -1.75, 3.25),
                           (-4.0, 1.5, 0.25), (4.0, 1.5, 0.25), (4.0, -1.5, 0.25), (-4.0, -1.5, 0.25)])
IPANEMA3_PLATFORM = np.array([(-0.55, 0.25, 0.0), (0.55, 0.25, 0.0), (0.55, -0.25, 0.0), (-0.55, -0.25, 0.0),
                              (-0.75, 0.15, 0.5), (0.75, 0.15, 0.5), (0.75, -0.15, 0.5), (-0.75, -0.15, 0.5)])


def test_ipanema3_interference_angle_is_wirex_s():
    """WireX's unit test ``test_Iws_cablecableinterference`` (wirex-master/Scripts/wcUnitTest.py,
    lines 276-282) asserts getMinInterferenceAngle() == 0.5188656962010074 for IPAnema3Design."""
    from marinecdpr.geometry.interference import interference_angle

    angle, pair = interference_angle(IPANEMA3_FRAME, IPANEMA3_PLATFORM)
    assert angle == pytest.approx(0.5188656962010074, abs=1e-15) and pair == (0, 4)


def test_ipanema3_cables_4_and_8_touch_on_wirex_s_colliding_path():
    """WireX's ``test_Iws_checkPoseForCableCableCollision`` (wcUnitTest.py, lines 301-304): at
    yaw 0.8 rad, going from (0, 0, 1.5) to (-4, -2, 0) crosses a cable-cable collision. Along
    that line the cables' segments say which and where: cables 4 and 8 pass through each
    other (the triple product of their directions and anchor offset changes sign, with the
    closest points inside both spans); at that pose their distance is 0."""
    from scipy.optimize import brentq

    from marinecdpr.geometry.interference import segment_distance

    c, s = math.cos(0.8), math.sin(0.8)
    R = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    start, end = np.array([0.0, 0.0, 1.5]), np.array([-4.0, -2.0, 0.0])
    i, j = 3, 7

    def triple(lam: float) -> float:
        r = start + lam * (end - start)
        u_i, u_j = r + R @ IPANEMA3_PLATFORM[i] - IPANEMA3_FRAME[i], r + R @ IPANEMA3_PLATFORM[j] - IPANEMA3_FRAME[j]
        return float(np.cross(u_i, u_j) @ (IPANEMA3_FRAME[j] - IPANEMA3_FRAME[i]))

    lam = brentq(triple, 0.2, 0.5, xtol=1e-15)
    r = start + lam * (end - start)
    assert r == pytest.approx([-1.358, -0.679, 0.991], abs=1e-3)
    ends = r + IPANEMA3_PLATFORM @ R.T
    d, s_i, s_j = segment_distance(IPANEMA3_FRAME[i], ends[i], IPANEMA3_FRAME[j], ends[j])
    assert float(d) < 1e-12 and 0.0 < float(s_i) < 1.0 and 0.0 < float(s_j) < 1.0
    # the robot's check names them there (and only them, at a clearance of 1 mm)
    sc = marinecdpr.load_scenario(EXAMPLES / "spatial_cube8.toml")  # any spatial scenario to carry the robot
    data = sc.model_dump(exclude_none=True)
    data["robot"]["cables"] = [{"frame_anchor_m": list(a), "platform_anchor_m": list(p)}
                               for a, p in zip(IPANEMA3_FRAME, IPANEMA3_PLATFORM)]
    data["robot"]["clearance_m"] = 0.001
    from marinecdpr.scenario.loading import scenario_from_dict

    robot = scenario_from_dict(data, source="test").robot
    gaps = pose_clearances(robot, [], r[None], R[None])
    close = [tuple(p) for p, dist in zip(gaps.pairs.tolist(), gaps.cable_cable[0]) if dist < 0.001]
    assert close == [(3, 7)] and gaps.cable_cable[0].min() < 1e-12


# ------------------------------------------------------------------ culling the boxes (issue 37, 1 000 obstacles)
def _random_boxes(rng, n):
    """Boxes of all sizes: many on the cables' paths (inside the unit cube the segments span),
    some overlapping each other, some far away; a plane or two among them."""
    from marinecdpr.scenario.obstacles import BoxObstacle, PlaneObstacle

    found = []
    for k in range(n):
        far = rng.random() < 0.3
        centre = rng.uniform(-1.0, 2.0, 3) + (rng.uniform(-30.0, 30.0, 3) if far else 0.0)
        size = rng.uniform(0.001, 0.3, 3) * 10.0 ** rng.uniform(-1.0, 0.5)
        turn = rng.uniform(-180.0, 180.0, 3) if rng.random() < 0.6 else np.zeros(3)
        found.append(BoxObstacle(type="box", center_m=tuple(centre), size_m=tuple(size), orientation_deg=tuple(turn)))
        if k % 97 == 5:
            found.append(PlaneObstacle(type="plane", point_m=tuple(rng.uniform(-3.0, -1.0, 3)),
                                       normal=tuple(np.array([0.0, 0.6, 0.8]))))
    return found


def _exhaustive(obstacles, starts, ends):
    out = np.empty(starts.shape[:2] + (len(obstacles),))
    for k, ob in enumerate(obstacles):
        if ob.type == "plane":
            out[..., k] = segment_plane_distance(starts, ends, np.asarray(ob.point_m), np.asarray(ob.normal))
        else:
            out[..., k] = segment_box_distance(starts, ends, np.asarray(ob.center_m),
                                               matrix_from_euler(np.radians(np.asarray(ob.orientation_deg))),
                                               0.5 * np.asarray(ob.size_m))
    return out


def test_box_bounds_hold_the_computed_distance_and_are_tight():
    """segment_box_bounds: lower <= segment_box_distance's own (rounded) value <= upper on
    random boxes and segments (points, crossing, touching, far), and tight to a box's size
    squared over the distance where the box is far (1e-3 m boxes 3 m away: within 1e-6 m)."""
    rng = np.random.default_rng(37)
    for _ in range(60):
        c, h = rng.uniform(-2, 2, 3), rng.uniform(1e-4, 1.0, 3) * 10.0 ** rng.uniform(-2, 0.5)
        R = matrix_from_euler(rng.uniform(-np.pi, np.pi, 3))
        p0, p1 = rng.uniform(-3, 3, (400, 3)), rng.uniform(-3, 3, (400, 3))
        p1[:40] = p0[:40]  # points
        p1[40:80] = c + (p0[40:80] - c) * 1e-3  # ends inside or at the box
        d = segment_box_distance(p0, p1, c, R, h)
        lower, upper = segment_box_bounds(p0, p1, c, R, h)
        assert np.all(lower <= d) and np.all(d <= upper)
    c, h = np.zeros(3), np.full(3, 5e-4)
    p0, p1 = rng.uniform(-1, 1, (200, 3)) + [0.0, 3.0, 0.0], rng.uniform(-1, 1, (200, 3)) + [0.0, 3.0, 0.0]
    lower, upper = segment_box_bounds(p0, p1, c, np.eye(3), h)
    d = segment_box_distance(p0, p1, c, np.eye(3), h)
    assert np.all(upper - lower < 1e-6) and np.all((lower <= d) & (d <= upper))


def test_a_box_distance_where_asked_is_the_whole_call_s_bit_for_bit():
    rng = np.random.default_rng(5)
    p0, p1 = rng.uniform(-2, 2, (300, 4, 3)), rng.uniform(-2, 2, (300, 4, 3))
    c, R, h = rng.uniform(-1, 1, 3), matrix_from_euler(rng.uniform(-3, 3, 3)), rng.uniform(0.01, 0.5, 3)
    where = rng.random((300, 4)) < 0.2
    whole = segment_box_distance(p0, p1, c, R, h)
    assert np.array_equal(segment_box_distance(p0, p1, c, R, h, where=where), whole[where])


@pytest.mark.parametrize("seed", range(6))
def test_culled_obstacles_report_what_the_exhaustive_measure_does(seed):
    """obstacle_distances against every box measured (property test, random boxes: many on
    the cables' paths, overlapping, far away, planes among them; random cables, points
    among them): each cable's least distance to anything, every distance below the
    clearance and each measured entry are the exhaustive ones exactly (==), the others
    inf and truly at least the clearance and above the cable's least; the words
    describe_clearances reports are the same."""
    from marinecdpr.planning.interference import Clearances, describe_clearances, obstacle_distances

    rng = np.random.default_rng(seed)
    boxes = _random_boxes(rng, int(rng.integers(40, 400)))
    n, m = int(rng.integers(20, 120)), int(rng.integers(1, 6))
    starts = np.broadcast_to(rng.uniform(-1.0, 2.0, (1, m, 3)), (n, m, 3))
    ends = starts + np.cumsum(rng.normal(0.0, 0.05, (n, m, 3)), axis=0) + rng.uniform(-1.0, 1.0, (1, m, 3))
    ends[:, 0] = np.where(rng.random((n, 1)) < 0.2, starts[:, 0], ends[:, 0])  # a cable of no length at times
    exact = _exhaustive(boxes, starts, ends)
    nearest = [None, np.full((n, m), 0.4), rng.uniform(0.0, 1.0, (n, m))][seed % 3]
    clearance = [None, 0.0, 0.05, 0.3][seed % 4]
    culled = obstacle_distances(boxes, starts, ends, clearance, nearest)
    other = np.full((n, m), np.inf) if nearest is None else nearest
    assert np.array_equal(np.minimum(other, culled.min(axis=2)), np.minimum(other, exact.min(axis=2)))
    measured = np.isfinite(culled)
    assert np.array_equal(culled[measured], exact[measured])
    floor = -np.inf if clearance is None else clearance
    least = np.minimum(other, exact.min(axis=2))[..., None]
    assert np.all(measured | ((exact >= floor) & (exact > least)))  # what is left out cannot be reported
    assert 0 < measured.mean() < 0.6  # and the culling works (the near ones are measured)
    if clearance is not None:
        assert np.array_equal(culled < clearance, exact < clearance)
        c_exact = Clearances(np.zeros((0, 2), dtype=np.int64), np.zeros((n, 0)), other, exact)
        c_culled = Clearances(np.zeros((0, 2), dtype=np.int64), np.zeros((n, 0)), other, culled)
        labels = [f"obstacle {k}" for k in range(len(boxes))]
        assert np.array_equal(c_exact.per_cable, c_culled.per_cable)
        for k in range(n):
            assert describe_clearances(c_culled, k, clearance, labels, most=5) == \
                describe_clearances(c_exact, k, clearance, labels, most=5)


def test_a_thousand_boxes_check_as_every_box_measured():
    """The hostile input's 1 000 tiny boxes (issue 37: `check` took 217 s), moved onto the
    cables' plane: pose_clearances' per-cable figures and the check's line are those of
    every box measured, exactly."""
    from marinecdpr.motion.trajectory import evaluate_trajectory
    from marinecdpr.planning.interference import Clearances, describe_clearances, obstacle_labels
    from marinecdpr.scenario.obstacles import BoxObstacle

    sc = marinecdpr.load_scenario("paper").with_updates("robot", clearance_m=0.06)
    boxes = [BoxObstacle(type="box", center_m=(0.001 * k, 0.05, 0.5), size_m=(0.01, 0.01, 0.01)) for k in range(1000)]
    t = np.arange(0, 15.0, 0.05)
    path = evaluate_trajectory(sc.trajectory, t, None)
    gaps = pose_clearances(sc.robot, boxes, path.x_PC_C, path.R_PC)
    ends = path.x_PC_C[:, None, :] + np.einsum("nij,cj->nci", path.R_PC, sc.robot.platform_anchors)
    exact = Clearances(gaps.pairs, gaps.cable_cable, gaps.cable_platform,
                       _exhaustive(boxes, np.broadcast_to(sc.robot.frame_anchors, ends.shape), ends))
    assert np.array_equal(gaps.per_cable, exact.per_cable)
    labels = obstacle_labels(boxes)
    lines = [describe_clearances(gaps, k, 0.06, labels) for k in range(t.size)]
    assert lines == [describe_clearances(exact, k, 0.06, labels) for k in range(t.size)]
    assert any("from obstacle" in line for line in lines)
    assert np.isfinite(gaps.cable_obstacle).mean() < 0.1
