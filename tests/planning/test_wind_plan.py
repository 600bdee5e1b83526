"""The planner's required wrench with ``[wind]`` (issue 40, item 1): on a held pose, the wrench
is the windless one less the wind's drag worked by hand (the mean, a gust factor, the series),
and the planned tensions give it through J~ (J~^T T = w in the cables' DOFs, the guide the
rest)."""

from __future__ import annotations

import numpy as np
import pytest

from marinecdpr.geometry.kinematics import cable_kinematics
from marinecdpr.geometry.rotations import matrix_from_euler
from marinecdpr.model.wind import scenario_gust
from marinecdpr.planning.planner import plan_at
from marinecdpr.scenario.loading import scenario_from_dict

from conftest import paper_dict

POSE = [0.95, 0.0, 0.7]
AREA, C, U10, D_CABLE = (0.3, 0.5, 0.2), 1.6, 14.0, 0.008


def held(wind=None, pitch_deg=8.0):
    d = paper_dict()
    d["base_motion"] = {"type": "still"}
    d["trajectory"] = {"type": "line", "start_position_m": POSE, "end_position_m": POSE,
                       "start_orientation_deg": [0.0, pitch_deg, 0.0], "duration_s": 2.0}
    d["time"] = {"step_s": 0.05, "duration_s": 2.0}
    if wind is not None:
        d["wind"] = {"speed_m_s": U10, "direction_deg": 180.0, "platform_shape_coefficient": C,
                     "platform_area_m2": list(AREA), "cable_diameter_m": D_CABLE, **wind}
    return scenario_from_dict(d, source="test")


def drag_by_hand(scenario, U):
    """The wind's force and moment on the held platform in C, one speed U (m/s) along +x, worked
    one cable at a time (a still ship: C is O shifted by the frame origin)."""
    robot = scenario.robot
    R = matrix_from_euler(np.radians([[0.0, 8.0, 0.0]]))[0]
    x = np.array(POSE)
    u = np.array([U, 0.0, 0.0])
    u_P = R.T @ u
    f = R @ (0.5 * 1.226 * C * np.linalg.norm(u_P) * np.array(AREA) * u_P)
    m = np.zeros(3)
    for a, p in zip(robot.frame_anchors, robot.platform_anchors):
        r = R @ p
        d = x + r - a
        L = np.linalg.norm(d)
        e = d / L
        u_n = u - (u @ e) * e
        F = L * 0.5 * 1.226 * 1.2 * D_CABLE * np.linalg.norm(u_n) * u_n
        f, m = f + F / 2.0, m + np.cross(r, F / 2.0)
    return np.concatenate([f, m])


@pytest.mark.parametrize("plan_gust, factor", [("mean", 1.0), (1.4, 1.4)])
def test_wind_in_the_required_wrench_by_hand(plan_gust, factor):
    base, windy = held(), held({"profile_exponent": 0.0, "gust": "none", "plan_gust": plan_gust})
    t = np.arange(41) * 0.05
    p0, p1 = plan_at(base, t), plan_at(windy, t)
    w_hand = drag_by_hand(windy, factor * U10)
    # the cables (and the guide) supply what the wind pushes: w = w_0 - (f_wind, m_wind)
    assert np.abs(p1.wrench - (p0.wrench - w_hand)).max() < 1e-12 * np.abs(p0.wrench).max()
    assert abs(w_hand[0]) > 40.0  # tens of newtons: the wind matters
    # J~^T T = w in the cables' DOFs, the guide's reaction the rest
    kin = cable_kinematics(p1.pose[:, :3], matrix_from_euler(p1.pose[:, 3:]), windy.robot.frame_anchors,
                           windy.robot.platform_anchors)
    JT_T = np.einsum("nci,nc->ni", kin.J_tilde, p1.tensions)
    c = list(windy.robot.controlled)
    assert p1.feasible.all()
    assert np.abs(JT_T[:, c] - p1.wrench[:, c]).max() < 1e-9 * np.abs(p1.wrench).max()
    u = [i for i in range(6) if i not in c]
    assert np.abs(JT_T[:, u] + p1.reaction - p1.wrench[:, u]).max() < 1e-9 * np.abs(p1.wrench).max()


def test_planned_gust_series_is_the_mean_plus_the_series():
    windy = held({"profile_exponent": 0.0, "plan_gust": "series", "seed": 4})
    base = held()
    t = np.arange(41) * 0.05
    p0, p1 = plan_at(base, t), plan_at(windy, t)
    u_g = scenario_gust(windy.wind).at(t)
    w_hand = np.array([drag_by_hand(windy, U10 + g) for g in u_g])
    assert np.abs(p1.wrench - (p0.wrench - w_hand)).max() < 1e-12 * np.abs(p0.wrench).max()
    assert np.ptp(w_hand[:, 0]) > 0.5  # the gust moves the drag over the 2 s
