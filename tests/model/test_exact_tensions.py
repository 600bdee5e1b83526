"""The exact tension methods find tensions wherever any exist; the advice follows the limit
that holds (issue 37, item 10).

The robot is tests/test_singular_sets.py's eight-cable one with a singular plane at z = 1.95 m:
near it J~ is ill-conditioned, and there the compiled active-set method had given up at steps
where a linear programme finds tensions with several newtons of headroom (t = 5.935 s: 3.7 N).
"""

from __future__ import annotations

import re

import numpy as np
import pytest
from scipy.optimize import linprog

import marinecdpr
from marinecdpr.geometry.kinematics import cable_kinematics
from marinecdpr.geometry.rotations import matrix_from_euler
from marinecdpr.model.tension import (TENSION_TOLERANCE, _series, distribute_tensions, exact_fallback, null_space,
                                      pseudo_inverse_tensions)
from marinecdpr.planning.planner import _sizing_hint, plan_at

from test_singular_sets import plane_robot_toml

TIMES = np.r_[np.arange(1.78, 1.99, 0.01), np.arange(5.93, 6.13, 0.005)]


@pytest.fixture(scope="module")
def plane(tmp_path_factory):
    path = tmp_path_factory.mktemp("plane") / "plane8.toml"
    text = plane_robot_toml().replace('period_s = 8.0\n', 'period_s = 8.0\n[[base_motion.components]]\n'
                                      'dof = "heave"\namplitude_m = 0.5\nperiod_s = 8.0\nphase_deg = 90.0\n')
    text = text.replace('time_s = 4.0\nposition_m = [2.5, 1.8, 2.7]',
                        'time_s = 4.0\nposition_m = [2.5, 1.8, 2.7]\n[[trajectory.waypoints]]\n'
                        'time_s = 8.0\nposition_m = [1.5, 1.2, 1.2]')
    path.write_text(text.replace("duration_s = 0.2", "duration_s = 8.0"))
    return marinecdpr.load_scenario(str(path))


def _steps(sc, t):
    """J~ (controlled columns) and the wrench at times t, as the plan has them."""
    p = plan_at(sc, t, method="minimum_variance")
    r = sc.robot
    J = cable_kinematics(p.pose[:, :3], matrix_from_euler(p.pose[:, 3:]), r.frame_anchors,
                         r.platform_anchors).J_tilde
    return p, J, p.wrench


def _lp_headroom(J, w, lo, hi):
    """max h: J^T T = w, lo + h <= T <= hi - h (HiGHS), one step: the independent check."""
    m = J.shape[0]
    A_ub = np.r_[np.c_[-np.eye(m), np.ones(m)], np.c_[np.eye(m), np.ones(m)]]
    b_ub = np.r_[-lo, hi]
    res = linprog(np.r_[np.zeros(m), -1.0], A_ub=A_ub, b_ub=b_ub, A_eq=np.c_[J.T, np.zeros(J.shape[1])], b_eq=w,
                  bounds=[(None, None)] * (m + 1), method="highs")
    return -res.fun if res.status == 0 else -np.inf


def _brute_force_qp(J, w, target, lo, hi):
    """min |T - target|^2, J^T T = w, lo <= T <= hi by every active set of up to r limits in
    the null space (slow and obvious): the projection of lambda_0 onto the polygon."""
    from itertools import combinations

    T_s = J @ np.linalg.solve(J.T @ J, w)
    N = null_space(J[None])[0]
    r = N.shape[1]
    lam0 = N.T @ (target - T_s)
    G = np.r_[N, -N]
    h = np.r_[lo - T_s, T_s - hi]     # G lam >= h
    best, best_d = None, np.inf
    for q in range(r + 1):
        for act in combinations(range(G.shape[0]), q):
            if q:
                Ga = G[list(act)]
                if np.linalg.matrix_rank(Ga) < q:
                    continue
                # project lam0 onto Ga lam = h_a
                lam = lam0 - Ga.T @ np.linalg.solve(Ga @ Ga.T, Ga @ lam0 - h[list(act)])
            else:
                lam = lam0
            if np.all(G @ lam >= h - 1e-7):
                d = np.linalg.norm(lam - lam0)
                if d < best_d:
                    best, best_d = T_s + N @ lam, d
    return best


@pytest.mark.parametrize("method", ["minimum_variance", "minimum_norm"])
def test_the_exact_methods_find_tensions_wherever_a_linear_programme_does(plane, method):
    r = plane.robot
    p, J, w = _steps(plane, TIMES)
    p = plan_at(plane, TIMES, method=method)
    lo, hi = r.tension_min, r.tension_max
    room = np.array([_lp_headroom(J[i], w[i], lo, hi) for i in range(TIMES.size)])
    regular = ~p.singular
    assert (room[regular] > 1.0).sum() >= 10 and (room[regular] < -1.0).sum() >= 5  # both kinds of step
    clear = regular & (np.abs(room) > 1e-6)
    np.testing.assert_array_equal(p.feasible[clear], room[clear] > 0)
    # and the compiled method alone had given up at some of them: the fallback is exercised
    target = np.zeros(8) if method == "minimum_norm" else 0.5 * (lo + hi)
    raw = _series(J, w, 2 if method == "minimum_variance" else 3, target, lo, hi, None,
                  TENSION_TOLERANCE * hi.max())
    assert (p.feasible & ~raw.feasible).sum() >= 3
    T = p.tensions[p.feasible]
    assert np.all(T >= lo - 1e-6) and np.all(T <= hi + 1e-6)
    np.testing.assert_allclose(np.einsum("nmk,nm->nk", J[p.feasible], T), w[p.feasible], atol=1e-6)


@pytest.mark.parametrize("method", ["minimum_variance", "minimum_norm"])
def test_the_fallback_is_the_exact_optimum_and_succeeded_steps_are_bit_for_bit(plane, method):
    r = plane.robot
    _, J, w = _steps(plane, TIMES)
    lo, hi = r.tension_min, r.tension_max
    target = np.zeros(8) if method == "minimum_norm" else 0.5 * (lo + hi)
    tol = TENSION_TOLERANCE * hi.max()
    raw = _series(J, w, 2 if method == "minimum_variance" else 3, target, lo, hi, None, tol)
    sol = distribute_tensions(J, w, lo, hi, method=method)
    # where the compiled method succeeds: its tensions, bit for bit
    np.testing.assert_array_equal(sol.tensions[raw.feasible], raw.tensions[raw.feasible])
    # the fallback agrees with the compiled method where that succeeds (two implementations)
    T_fb, found = exact_fallback(J[raw.feasible], w[raw.feasible], target, lo, hi, tol)
    assert found.all()
    np.testing.assert_allclose(T_fb, raw.tensions[raw.feasible], rtol=0, atol=1e-6)
    # where only the fallback finds tensions: the optimum, by brute force over the active sets
    new = np.flatnonzero(sol.feasible & ~raw.feasible)
    assert new.size >= 3
    for i in new:
        best = _brute_force_qp(J[i], w[i], target, lo, hi)
        np.testing.assert_allclose(sol.tensions[i], best, rtol=0, atol=1e-5)


def test_a_method_that_misses_them_names_the_one_that_finds_them(plane):
    t = np.array([5.95])
    pinv = plan_at(plane, t, method="pseudo_inverse")
    assert not pinv.feasible[0]
    line = pinv.limiting_cables(0)
    assert line.startswith("tensions within the limits exist there, but the pseudo inverse method did not find "
                           "them: the minimum variance method does"), line
    assert "--method minimum_variance" in line
    assert plan_at(plane, t, method="minimum_variance").feasible[0]


def _range(A, w, r, lo, hi):
    others = [q for q in range(len(w)) if q != r]
    ends = []
    for sign in (1.0, -1.0):
        res = linprog(sign * A[r], A_eq=A[others] if others else None, b_eq=w[others] if others else None,
                      bounds=list(zip(lo, hi)), method="highs")
        ends.append(A[r] @ res.x)
    return np.array(ends)


def test_the_advice_follows_the_limit_that_holds_the_near_end_of_the_range(plane):
    # hand-worked: two cables both pulling +x, 10 .. 100 N each: the force ranges over 20 .. 200 N
    A, lo, hi = np.array([[1.0, 1.0]]), np.array([10.0, 10.0]), np.array([100.0, 100.0])
    axes = np.array(["x"])
    lacking = ("force", "N", "along", np.array([0]), np.array([1.0]))
    below = _sizing_hint(A, np.array([5.0]), lo, hi, lacking, axes, False)
    assert "give 20 to 200 N along x there, against 5 N needed: lower robot.tension_min_N" in below
    assert "tension_max" not in below
    above = _sizing_hint(A, np.array([250.0]), lo, hi, lacking, axes, False)
    assert "against 250 N needed: raise robot.tension_max_N," in above and "tension_min" not in above
    # antagonistic: cable 1 pulls +x, cable 2 -x: -90 .. 90 N; past 90 N both limits hold the end
    # (cable 1 at T_max, cable 2 at T_min, 1 N each per N): lowering T_min to 0 closes 10 N at
    # most, so it is named where the gap is 5 N and not where it is 60 N
    A = np.array([[1.0, -1.0]])
    near = _sizing_hint(A, np.array([95.0]), lo, hi, lacking, axes, False)
    assert ("against 95 N needed: raise robot.tension_max_N or lower robot.tension_min_N (cables held at their "
            "least tension pull the wrong way there), or move") in near
    far = _sizing_hint(A, np.array([150.0]), lo, hi, lacking, axes, False)
    assert "against 150 N needed: raise robot.tension_max_N, or move" in far and "tension_min" not in far
    # checked by moving each side's limits: the ends the duals say
    assert _range(A, np.array([0.0]), 0, lo - 1.0, hi)[1] - 90.0 == pytest.approx(1.0)
    assert _range(A, np.array([0.0]), 0, lo, hi + 1.0)[1] - 90.0 == pytest.approx(1.0)
    assert _range(np.array([[1.0, 1.0]]), np.array([0.0]), 0, lo - 1.0, hi)[0] == pytest.approx(18.0)


def test_the_one_redundancy_screen_agrees_with_the_largest_headroom(paper):
    """For r = 1 the steps worth solving alone are told apart as an interval's ends; they are
    those where the largest headroom (its own closed form over the cables' tents) is >= 0."""
    from marinecdpr.model.tension import _may_hold, largest_headroom

    r = paper.robot
    rng = np.random.default_rng(11)
    n = 4000
    x = np.c_[rng.uniform(0.3, 1.6, n), np.zeros(n), rng.uniform(0.3, 1.1, n)]
    R = matrix_from_euler(np.c_[np.zeros(n), rng.uniform(-0.3, 0.3, n), np.zeros(n)])
    J = cable_kinematics(x, R, r.frame_anchors, r.platform_anchors).J_tilde[:, :, [0, 2, 4]]
    w = np.c_[rng.normal(0, 150, n), rng.normal(49, 150, n), rng.normal(0, 20, n)]
    T_s, _ = pseudo_inverse_tensions(J, w)
    room = largest_headroom(J, T_s, r.tension_min, r.tension_max)
    keep = _may_hold(J, w, r.tension_min, r.tension_max, 1e-9 * r.tension_max.max())
    clear = np.abs(room) > 1e-6
    assert 200 < (room[clear] > 0).sum() < clear.sum() - 200   # both kinds, many of each
    np.testing.assert_array_equal(keep[clear], room[clear] > 0)
