"""The workspace map against statics computed independently (a linear feasibility problem)."""

import numpy as np
from scipy.optimize import linprog

from marinecdpr.geometry.kinematics import cable_kinematics
from marinecdpr.studies.workspace import workspace_map

from conftest import make_scenario


def _statically_feasible(sc, x, z):
    """Is there T in [T_min, T_max] with J~^T T = (0, m g, 0) at this pose? (LP, HiGHS)"""
    r = sc.robot
    J = cable_kinematics(np.array([[x, 0.0, z]]), np.eye(3)[None], r.frame_anchors, r.platform_anchors).J_tilde[0]
    A = J[:, [0, 2, 4]].T
    w = np.array([0.0, r.mass_kg * sc.environment.gravity_m_s2, 0.0])
    res = linprog(np.zeros(r.n_cables), A_eq=A, b_eq=w, bounds=list(zip(r.tension_min, r.tension_max)),
                  method="highs")
    return res.status == 0


def test_on_a_still_ship_the_map_is_static_feasibility():
    # a heavy platform makes the feasible region a strict part of the frame
    sc = make_scenario(lambda d: (d.update(base_motion={"type": "still"}, time={"step_s": 0.1, "duration_s": 0.3}),
                                  d["robot"].update(mass_kg=40.0)))
    ws = workspace_map(sc, n=(14, 10))
    inside = np.isfinite(ws.fraction_feasible)
    assert inside.sum() > 60
    expected = np.array([[_statically_feasible(sc, u, v) for v in ws.v] for u in ws.u])
    np.testing.assert_array_equal(ws.fraction_feasible[inside] == 1.0, expected[inside])
    assert 0 < expected[inside].sum() < inside.sum()   # the test discriminates
    assert set(np.unique(ws.fraction_feasible[inside])) <= {0.0, 1.0}  # still: all or nothing


def test_ship_motion_shrinks_the_workspace(paper):
    sc = paper.with_changes(time={"step_s": 0.02, "duration_s": 6.0})
    moving = workspace_map(sc, n=(12, 8))
    still = workspace_map(sc.with_changes(base_motion={"type": "still"}), n=(12, 8))
    ok_m = np.nan_to_num(moving.fraction_feasible) == 1.0
    ok_s = np.nan_to_num(still.fraction_feasible) == 1.0
    assert np.all(ok_s[ok_m])                        # what works at sea works in port
    both = ok_m & ok_s
    assert np.all(moving.min_margin_N[both] <= still.min_margin_N[both] + 1e-9)
