"""Euler-angle kinematics against finite differences (no small-angle shortcut)."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from marinecdpr.geometry.rotations import euler_kinematics, matrix_from_euler, skew


def test_matrix_is_rz_ry_rx():
    phi, theta, psi = 0.3, -0.2, 1.1
    c, s = np.cos, np.sin
    Rx = np.array([[1, 0, 0], [0, c(phi), -s(phi)], [0, s(phi), c(phi)]])
    Ry = np.array([[c(theta), 0, s(theta)], [0, 1, 0], [-s(theta), 0, c(theta)]])
    Rz = np.array([[c(psi), -s(psi), 0], [s(psi), c(psi), 0], [0, 0, 1]])
    np.testing.assert_allclose(matrix_from_euler(np.array([phi, theta, psi])), Rz @ Ry @ Rx, atol=1e-15)


@settings(max_examples=30, deadline=None)
@given(st.lists(st.floats(-1.2, 1.2), min_size=9, max_size=9))
def test_body_rates_match_finite_differences(v):
    """dR/dt = R [omega_b x] and alpha_b = d(omega_b)/dt along a smooth angle path."""
    a0, a1, a2 = np.array(v[:3]), np.array(v[3:6]), np.array(v[6:9])
    h = 1e-5
    ts = np.array([-h, 0.0, h])
    ang = a0 + a1 * ts[:, None] + 0.5 * a2 * ts[:, None] ** 2
    rate = a1 + a2 * ts[:, None]
    acc = np.broadcast_to(a2, (3, 3))
    R, omega, alpha = euler_kinematics(ang, rate, acc)
    R_dot = (R[2] - R[0]) / (2 * h)
    np.testing.assert_allclose(R_dot, R[1] @ skew(omega[1]), atol=1e-8)
    np.testing.assert_allclose((omega[2] - omega[0]) / (2 * h), alpha[1], atol=1e-7)


def test_constant_angles_take_the_fast_path_with_the_same_result():
    ang = np.tile([0.1, -0.4, 2.0], (5, 1))
    R, omega, alpha = euler_kinematics(ang, np.zeros((5, 3)), np.zeros((5, 3)))
    np.testing.assert_allclose(R, np.broadcast_to(matrix_from_euler(ang[0]), (5, 3, 3)), atol=1e-15)
    assert not omega.any() and not alpha.any()
