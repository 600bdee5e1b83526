"""The wind's drag (issue 40, item 1): on a still platform in a steady wind, DNV-RP-C205's
1/2 rho C A U^2 by hand; per axis of P; on the wind relative to a moving ship; on the cables
(the normal component per metre, the platform's half share and its moment) by hand."""

from __future__ import annotations

import numpy as np
import pytest

from marinecdpr.geometry.rotations import matrix_from_euler
from marinecdpr.model.wind import cable_drag, platform_drag, wind_loads
from marinecdpr.motion.ship import ship_motion, still_ship
from marinecdpr.scenario.loading import scenario_from_dict
from marinecdpr.scenario.wind import AIR_DENSITY_KG_M3 as RHO

from conftest import paper_dict

ORIGIN = np.array([-0.78, 0.0, 2.2])  # the paper's frame origin in S


def wind(**changes):
    d = paper_dict()
    d["wind"] = {"speed_m_s": 14.0, "direction_deg": 180.0, "gust": "none", "platform_shape_coefficient": 1.6,
                 "platform_area_m2": [0.3, 0.5, 0.2], **changes}
    return scenario_from_dict(d, source="test").wind


def held(n=3, x=(0.95, 0.0, 0.7), euler=(0.0, 0.0, 0.0)):
    x_PC = np.tile(np.asarray(x, dtype=float), (n, 1))
    return x_PC, np.zeros((n, 6)), matrix_from_euler(np.tile(np.radians(euler), (n, 1)))


def test_still_platform_in_steady_wind_is_half_rho_c_a_u_squared():
    w = wind()  # from -x: blows along +x, onto the area normal to P's x
    x_PC, twist, R_PC = held()
    f, m = wind_loads(w, x_PC, twist, R_PC, still_ship(3), frame_origin_S=ORIGIN, frame_anchors=np.zeros((4, 3)),
                      platform_anchors=np.zeros((4, 3)), rho=RHO)
    z = 2.2 + 0.7  # the platform's height above the sea (O's origin on it)
    U = 14.0 * (z / 10.0) ** 0.12
    by_hand = 0.5 * 1.226 * 1.6 * 0.3 * U * U  # = 42.85 N
    assert np.abs(f[:, 0] / by_hand - 1.0).max() < 1e-13
    assert np.abs(f[:, 1:]).max() < 1e-12 * by_hand and not m.any()
    assert by_hand == pytest.approx(42.848, abs=1e-3)


def test_platform_drag_per_axis_of_the_turned_platform():
    # a wind of 10 m/s along O's x on a platform turned 30 deg about y: in P, u = 10 (cos 30, 0, sin 30)
    u = np.array([[10.0, 0.0, 0.0]])
    R_PC = matrix_from_euler(np.radians([[0.0, 30.0, 0.0]]))
    A = np.array([0.3, 0.5, 0.2])
    f = platform_drag(u, np.eye(3)[None], R_PC, rho=RHO, shape_coefficient=1.6, area_P=A)
    c, s = np.cos(np.radians(30.0)), np.sin(np.radians(30.0))
    F_P = 0.5 * 1.226 * 1.6 * 10.0 * np.array([0.3 * 10.0 * c, 0.0, 0.2 * 10.0 * s])
    assert np.allclose(f[0], R_PC[0] @ F_P, rtol=1e-14, atol=1e-12)
    assert np.allclose(R_PC[0].T @ f[0], F_P, rtol=1e-14, atol=1e-12)  # in P: each axis its own area


def test_drag_takes_the_wind_relative_to_the_moving_ship():
    # the ship surges at 2 m/s into a head wind (from +x, direction 0): the platform meets U + 2
    n = 3
    eta_dot = np.zeros((n, 6))
    eta_dot[:, 0] = 2.0
    ship = ship_motion(np.zeros((n, 6)), eta_dot, np.zeros((n, 6)))
    w = wind(direction_deg=0.0, profile_exponent=0.0)
    x_PC, twist, R_PC = held(n)
    twist[:, 0] = 0.5  # and the platform moves along C's x at 0.5 m/s on its cables
    f, _ = wind_loads(w, x_PC, twist, R_PC, ship, frame_origin_S=ORIGIN, frame_anchors=np.zeros((4, 3)),
                      platform_anchors=np.zeros((4, 3)), rho=RHO)
    by_hand = -0.5 * 1.226 * 1.6 * 0.3 * (14.0 + 2.5) ** 2
    assert np.abs(f[:, 0] / by_hand - 1.0).max() < 1e-13


def test_cable_drag_is_the_normal_component_per_metre_by_hand():
    u = np.array([[[10.0, 0.0, 0.0], [10.0, 0.0, 0.0], [10.0, 0.0, 0.0]]])
    s = np.sqrt(0.5)
    e = np.array([[[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [s, 0.0, s]]])  # across, along, at 45 deg
    L = np.array([[2.0, 3.0, 4.0]])
    F = cable_drag(u, e, L, rho=RHO, drag_coefficient=1.2, diameter=0.01)
    q = 0.5 * 1.226 * 1.2 * 0.01
    assert np.allclose(F[0, 0], [2.0 * q * 100.0, 0.0, 0.0], rtol=1e-14, atol=0)
    assert np.abs(F[0, 1]).max() == 0.0
    u_n = 10.0 * np.array([0.5, 0.0, -0.5])  # u - (u.e) e
    assert np.allclose(F[0, 2], 4.0 * q * np.linalg.norm(u_n) * u_n, rtol=1e-14, atol=1e-15)


def test_cables_give_the_platform_half_their_drag_and_its_moment():
    sc = paper_dict()
    w = wind(cable_diameter_m=0.008, profile_exponent=0.0)  # one speed at every height: the midpoint rule exact
    frame = np.array([c["frame_anchor_m"] for c in sc["robot"]["cables"]], dtype=float)
    plat = np.array([c["platform_anchor_m"] for c in sc["robot"]["cables"]], dtype=float)
    x_PC, twist, R_PC = held(2, x=(0.6, 0.0, 0.4), euler=(0.0, 10.0, 0.0))
    f, m = wind_loads(w, x_PC, twist, R_PC, still_ship(2), frame_origin_S=ORIGIN, frame_anchors=frame,
                      platform_anchors=plat, rho=RHO)
    f0, _ = wind_loads(w.model_copy(update={"cable_diameter_m": 0.0}), x_PC, twist, R_PC, still_ship(2),
                       frame_origin_S=ORIGIN, frame_anchors=frame, platform_anchors=plat, rho=RHO)
    u = np.array([14.0, 0.0, 0.0])
    f_hand, m_hand = np.zeros(3), np.zeros(3)
    for a, p in zip(frame, plat):  # each cable, one at a time, by hand
        r = R_PC[0] @ p
        d = x_PC[0] + r - a
        L = np.linalg.norm(d)
        e = d / L
        u_n = u - (u @ e) * e
        F = L * 0.5 * 1.226 * 1.2 * 0.008 * np.linalg.norm(u_n) * u_n
        f_hand += F / 2.0
        m_hand += np.cross(r, F / 2.0)
    assert np.allclose(f[0] - f0[0], f_hand, rtol=1e-13, atol=1e-14)
    assert np.allclose(m[0], m_hand, rtol=1e-13, atol=1e-15)
    assert abs(m_hand[1]) > 1e-3  # the bottom and top cables' halves turn the platform about y
