"""Each cable removed in turn: can the others hold the platform's wrench within their limits
(:mod:`marinecdpr.planning.redundancy`, issue 40 item 5)? A hand-worked point mass on three
cables, and agreement with an independent linear programme (scipy's HiGHS) on random robots,
poses and wrenches, with and without the sea's part."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import linprog

from marinecdpr.geometry.kinematics import cable_kinematics
from marinecdpr.geometry.rotations import matrix_from_euler
from marinecdpr.planning.redundancy import failure_margins, single_failure_margin
from marinecdpr.scenario.robot import Robot

S2 = np.sqrt(2.0)
# a point mass in the x-z plane (k = 2) on three cables: to (-1, 1), (1, 1) and (0, -1) from it
J3 = np.array([[-1.0 / S2, 1.0 / S2], [1.0 / S2, 1.0 / S2], [0.0, -1.0]])


def test_a_point_mass_on_three_cables_as_worked_by_hand():
    """The cables must give w. Limits [10, 1000] N (the cap: 495 N, half a range).

    w = (0, 100) N: cable 3 gone, T1 = T2 = 100 / sqrt 2 = 70.71 N, margin 60.71 N; cable 1
    gone, T2 / sqrt 2 = 0 and T2 / sqrt 2 - T3 = 100: T2 = 0, T3 = -100 N, margin -110 N
    (cable 2 alike). w = (50, 100): cable 3 gone, T2 - T1 = 50 sqrt 2 and T1 + T2 = 100 sqrt 2:
    T1 = 25 sqrt 2 = 35.36 N, T2 = 75 sqrt 2, margin 25.36 N; cable 1 gone, T2 = 50 sqrt 2,
    T3 = -50 N: margin -60 N; cable 2 gone, T1 = -50 sqrt 2, T3 = -150 N: margin -160 N.
    With a sea along x of sigma 10 N held to 3 sigmas, w = (0, 100) +- (30, 0): cable 3 gone,
    T1 = 35 sqrt 2 = 49.50 N at worst: margin 39.50 N."""
    J = np.repeat(J3[None], 2, axis=0)
    w = np.array([[0.0, 100.0], [50.0, 100.0]])
    m = failure_margins(J, w, [10.0] * 3, [1000.0] * 3)
    np.testing.assert_allclose(m, [[-110.0, -110.0, 100.0 / S2 - 10.0],
                                   [-60.0, -160.0, 25.0 * S2 - 10.0]], rtol=0, atol=1e-9)
    C0 = np.zeros((1, 2, 2, 2))
    C0[0, :, 0, 0] = 100.0
    sea = failure_margins(J, w, [10.0] * 3, [1000.0] * 3, sea=(C0, C0),
                          extreme=lambda m0, m2: np.full_like(m0, 3.0))
    assert sea.shape == (1, 2, 3)
    assert sea[0, 0, 2] == pytest.approx(35.0 * S2 - 10.0, abs=1e-9)
    # the sea only takes: never a larger margin than the still sea's
    assert np.all(sea[0] <= m + 1e-12)


def _lp_margin(Jr: np.ndarray, w: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> float:
    """max h s.t. Jr^T T = w, lo + h <= T <= hi - h, by HiGHS: the independent second
    implementation (nan where HiGHS says the programme is infeasible even for h very negative)."""
    m = Jr.shape[0]
    c = np.r_[np.zeros(m), -1.0]
    A_ub = np.block([[-np.eye(m), np.ones((m, 1))], [np.eye(m), np.ones((m, 1))]])
    b_ub = np.r_[-lo, hi]
    A_eq = np.c_[Jr.T, np.zeros((Jr.shape[1], 1))]
    res = linprog(c, A_ub=A_ub, b_ub=b_ub, A_eq=A_eq, b_eq=w, bounds=[(None, None)] * m + [(-1e7, None)],
                  method="highs")
    return float(-res.fun) if res.status == 0 else float("nan")


def _random_robot(rng, m: int) -> Robot:
    """A planar robot with m cables: frame anchors about a 4 x 3 m frame, platform anchors
    about a 0.6 x 0.4 m platform (random, in the x-z plane)."""
    frame = np.c_[rng.uniform(-0.5, 4.5, m), np.zeros(m), rng.uniform(-0.5, 3.5, m)]
    plat = np.c_[rng.uniform(-0.3, 0.3, m), np.zeros(m), rng.uniform(-0.2, 0.2, m)]
    lo = rng.uniform(5.0, 50.0, m)
    return Robot.model_validate({
        "dofs": "planar", "mass_kg": 10.0, "inertia_kg_m2": [1.0, 1.0, 1.0],
        "cables": [{"frame_anchor_m": list(map(float, f)), "platform_anchor_m": list(map(float, p)),
                    "tension_min_N": float(a), "tension_max_N": float(a + rng.uniform(200.0, 800.0))}
                   for f, p, a in zip(frame, plat, lo)]})


def test_the_margins_agree_with_a_linear_programme_on_random_robots_poses_and_wrenches():
    """200 random planar robots of 4, 5 and 6 cables, 3 poses each, a wrench each: per cable
    removed, the margin is HiGHS's max h (1e-6 N), and so is the verdict (margin >= 0) on every
    case; where HiGHS finds no tensions at all the margin is negative too."""
    rng = np.random.default_rng(40)
    agree = compared = held = 0
    for trial in range(200):
        m = 4 + trial % 3
        robot = _random_robot(rng, m)
        x = np.c_[rng.uniform(1.0, 3.0, 3), np.zeros(3), rng.uniform(1.0, 2.0, 3)]
        R = matrix_from_euler(np.c_[np.zeros(3), rng.uniform(-0.3, 0.3, 3), np.zeros(3)])
        w6 = np.zeros((3, 6))
        w6[:, [0, 2, 4]] = rng.normal(0.0, [80.0, 80.0, 10.0], (3, 3)) + [0.0, 100.0, 0.0]
        margin = single_failure_margin(robot, x, R, w6)
        J = cable_kinematics(x, R, robot.frame_anchors, robot.platform_anchors).J_tilde[:, :, [0, 2, 4]]
        for p in range(3):
            for i in range(m):
                keep = np.arange(m) != i
                lp = _lp_margin(J[p, keep], w6[p, [0, 2, 4]], robot.tension_min[keep], robot.tension_max[keep])
                compared += 1
                if np.isnan(lp):
                    assert margin[p, i] < 0.0
                    agree += 1
                    continue
                assert margin[p, i] == pytest.approx(lp, abs=1e-6, rel=1e-9), (trial, p, i)
                agree += (margin[p, i] >= 0.0) == (lp >= 0.0)
                held += lp >= 0.0
    assert agree == compared == 3 * sum(4 + t % 3 for t in range(200))
    assert 0 < held < compared  # both verdicts met


def test_a_sea_along_one_direction_is_the_worse_of_its_two_extremes():
    """A random part of rank one (covariance g g^T) held to k sigmas reaches w +- k g: the zonotope
    is convex, so the margin with the sea is the lesser of the still margins at w + k g and
    w - k g; the linear programme at both ends agrees (1e-6 N) on random robots and poses."""
    rng = np.random.default_rng(7)
    for trial in range(60):
        m = 4 + trial % 3
        robot = _random_robot(rng, m)
        x = np.c_[rng.uniform(1.0, 3.0, 2), np.zeros(2), rng.uniform(1.0, 2.0, 2)]
        R = matrix_from_euler(np.zeros((2, 3)))
        w6 = np.zeros((2, 6))
        w6[:, 2] = 100.0
        g = np.zeros((2, 6))
        g[:, [0, 2, 4]] = rng.normal(0.0, [10.0, 10.0, 1.0], (2, 3))
        C0 = (g[:, :, None] * g[:, None, :])[None]
        k = 2.5
        sea = single_failure_margin(robot, x, R, w6, sea=(C0, 4.0 * C0), extreme=lambda a, b: np.full_like(a, k))[0]
        J = cable_kinematics(x, R, robot.frame_anchors, robot.platform_anchors).J_tilde[:, :, [0, 2, 4]]
        for p in range(2):
            for i in range(m):
                keep = np.arange(m) != i
                ends = [_lp_margin(J[p, keep], (w6[p] + s * k * g[p])[[0, 2, 4]], robot.tension_min[keep],
                                   robot.tension_max[keep]) for s in (1.0, -1.0)]
                if np.isnan(ends).any():
                    assert sea[p, i] < 0.0
                    continue
                assert sea[p, i] == pytest.approx(min(ends), abs=1e-6, rel=1e-9)


def test_three_cables_in_line_lose_rank():
    """Three of four cables pull along x only: whichever cable goes, the three left span two
    directions at most (-inf). A fifth cable along (0, 0.5, -0.5): with cable 1 gone, the
    other four span all three (a finite margin); with cable 4 or 5 gone, still -inf."""
    J = np.array([[[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0], [0.5, 0.0, 0.0], [0.0, 1.0, 0.3]]])
    m = failure_margins(J, np.array([[0.0, 50.0, 0.0]]), [10.0] * 4, [500.0] * 4)
    assert np.all(m == -np.inf)
    J5 = np.concatenate([J, [[[0.0, 0.5, -0.5]]]], axis=1)
    m5 = failure_margins(J5, np.array([[0.0, 50.0, 0.0]]), [10.0] * 5, [500.0] * 5)
    assert m5[0, 3] == m5[0, 4] == -np.inf and np.all(np.isfinite(m5[0, :3]))
