"""Cable kinematics: hand-worked lengths, J~ against finite differences, eq. (14)."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from marinecdpr.geometry.kinematics import cable_kinematics, global_jacobian
from marinecdpr.geometry.rotations import matrix_from_euler
from marinecdpr.motion.trajectory import platform_motion


def test_paper_lengths_at_t0_by_hand(paper_plan):
    # P at (0.98, 0, 0.7): cable 1 runs from (0.855, 0.85) to (0, 1.4); cable 2 from
    # (1.105, 0.85) to (1.9, 1.4); 3 and 4 mirror them about z = 0.7.
    L1 = np.hypot(0.855, 0.55)
    L2 = np.hypot(0.795, 0.55)
    np.testing.assert_allclose(paper_plan.lengths[0], [L1, L2, L2, L1], rtol=1e-12)


def _random_motion(seed, n=5, h=1e-6):
    """Poses at t - h, t, t + h along a random smooth motion, for each of n samples."""
    rng = np.random.default_rng(seed)
    p0 = rng.uniform([0.5, -0.3, 0.5, -0.5, -0.5, -1], [1.5, 0.3, 1.5, 0.5, 0.5, 1], size=(n, 6))
    v = rng.normal(size=(n, 6))
    pose = np.concatenate([p0 - h * v, p0, p0 + h * v])
    return pose, v, h


@settings(max_examples=20, deadline=None)
@given(st.integers(0, 2**32 - 1))
def test_J_tilde_matches_finite_differences_of_lengths(seed):
    """l' = -J~ (v_PC, omega_PC) (eq. 5) for spatial motions with rotation."""
    rng = np.random.default_rng(seed)
    c = rng.uniform(-1, 3, size=(8, 3))
    p = rng.uniform(-0.2, 0.2, size=(8, 3))
    pose, v, h = _random_motion(seed)
    n = v.shape[0]
    motion = platform_motion(pose, np.concatenate([v, v, v]), np.zeros_like(pose))
    kin = cable_kinematics(motion.x_PC_C, motion.R_PC, c, p, motion.twist)
    fd = (kin.lengths[2 * n:] - kin.lengths[:n]) / (2 * h)
    np.testing.assert_allclose(kin.length_rates[n:2 * n], fd, atol=1e-6)
    # the cable vectors and unit vectors are consistent with the anchors
    np.testing.assert_allclose(
        kin.vectors, c[None] - motion.x_PC_C[:, None] - kin.anchors_C, atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(kin.units, axis=2), 1.0, rtol=1e-12)


def test_global_jacobian_rotates_rows_into_O():
    rng = np.random.default_rng(3)
    J_tilde = rng.normal(size=(4, 5, 6))
    R_SO = matrix_from_euler(rng.uniform(-0.3, 0.3, size=(4, 3)))
    J = global_jacobian(J_tilde, R_SO)
    S = np.zeros((4, 6, 6))
    S[:, :3, :3] = S[:, 3:, 3:] = R_SO
    np.testing.assert_allclose(J, J_tilde @ np.transpose(S, (0, 2, 1)), atol=1e-14)  # eq. (14)
