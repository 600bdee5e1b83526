"""Forward kinematics: poses back from the lengths the inverse kinematics (eq. 2) gives."""

from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import least_squares
from scipy.spatial.transform import Rotation

import marinecdpr
from marinecdpr.geometry.forward import (forward_work, pose_from_lengths, pose_from_lengths_step, residuals_and_jacobian,
                                         stretched_lengths)
from marinecdpr.geometry.kinematics import cable_kinematics
from marinecdpr.geometry.rotations import angle_rate_matrix, euler_kinematics, matrix_from_euler

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
# workspace boxes (x, y, z, rx, ry, rz) well inside each frame: paper 1.9 x 1.4 m (x-z plane),
# cube8 a 2 m cube
BOXES = {
    "paper": (np.array([0.5, 0, 0.35, 0, -0.35, 0]), np.array([1.4, 0, 1.05, 0, 0.35, 0])),
    "cube8": (np.array([0.6, 0.6, 0.6, -0.35, -0.35, -0.35]), np.array([1.4, 1.4, 1.4, 0.35, 0.35, 0.35])),
}


@pytest.fixture(scope="module", params=["paper", "cube8"])
def robot(request):
    name = request.param
    r = marinecdpr.load_scenario("paper" if name == "paper" else EXAMPLES / "spatial_cube8.toml").robot
    return name, r.frame_anchors, r.platform_anchors, np.array(r.controlled, dtype=np.int64)


def lengths_at(poses, c, p):
    """Geometric lengths (n, m) at poses (n, 6) by the inverse kinematics (eq. 2)."""
    poses = np.atleast_2d(poses)
    return cable_kinematics(poses[:, :3], matrix_from_euler(poses[:, 3:]), c, p).lengths


def random_poses(name, ctrl, n, rng):
    lo, hi = BOXES[name]
    q = rng.uniform(lo, hi, size=(n, 6))
    assert np.all(q[:, np.setdiff1d(np.arange(6), ctrl)] == 0)
    return q


def off_by(q, ctrl, rng, metres=0.05, degrees=5.0):
    """q moved by `metres` in a random direction of its controlled positions and by `degrees`
    in one of its controlled angles."""
    out = q.copy()
    for part, size in (([d for d in ctrl if d < 3], metres), ([d for d in ctrl if d >= 3], np.radians(degrees))):
        v = rng.normal(size=len(part))
        out[part] += size * v / np.linalg.norm(v)
    return out


def path(name, n):
    """A smooth closed path through the workspace, (n, 6) poses, one period."""
    s = np.linspace(0, 2 * np.pi, n)
    q = np.zeros((n, 6))
    if name == "paper":
        q[:, 0], q[:, 2], q[:, 4] = 0.95 + 0.3 * np.cos(s), 0.7 + 0.25 * np.sin(s), 0.15 * np.sin(2 * s)
    else:
        q[:, 0], q[:, 1], q[:, 2] = 1 + 0.3 * np.cos(s), 1 + 0.3 * np.sin(s), 1 + 0.2 * np.sin(2 * s)
        q[:, 3], q[:, 4], q[:, 5] = 0.1 * np.sin(s), 0.15 * np.cos(s), 0.2 * np.sin(s)
    return q


def test_random_poses_recovered_from_a_guess_5cm_5deg_off(robot):
    name, c, p, ctrl = robot
    rng = np.random.default_rng(1)
    truth = random_poses(name, ctrl, 250, rng)
    L = np.ascontiguousarray(lengths_at(truth, c, p))
    work = forward_work(len(c), len(ctrl))
    found, status, iters = np.empty_like(truth), [], []
    for s in range(len(truth)):
        q = off_by(truth[s], ctrl, rng)
        status.append(pose_from_lengths_step(L[s], c, p, ctrl, q, 1e-12, 50, work))
        iters.append(work.info[1])
        found[s] = q
        assert work.info[0] < 1e-12  # RMS residual, m
    assert status == [0] * len(truth)
    np.testing.assert_allclose(found[:, :3], truth[:, :3], rtol=0, atol=1e-9)  # m
    np.testing.assert_allclose(found[:, 3:], truth[:, 3:], rtol=0, atol=1e-9)  # rad
    assert max(iters) <= 8


def test_angle_rate_matrix_gives_omega_in_C():
    """omega = E(angles) angles' (R = Rz Ry Rx): against rotations.euler_kinematics (R omega_b)
    and against dR/dt R^T = [omega x] by central differences."""
    rng = np.random.default_rng(2)
    E = np.empty((3, 3))
    for _ in range(20):
        ang, rate = rng.uniform(-1.2, 1.2, 3), rng.normal(size=3)
        angle_rate_matrix(ang, E)
        R, omega_b, _ = euler_kinematics(ang, rate)
        np.testing.assert_allclose(E @ rate, R @ omega_b, rtol=0, atol=1e-14)
        h = 1e-6
        W = (matrix_from_euler(ang + h * rate) - matrix_from_euler(ang - h * rate)) / (2 * h) @ R.T
        np.testing.assert_allclose([W[2, 1], W[0, 2], W[1, 0]], E @ rate, rtol=1e-8, atol=1e-9)


def test_analytic_jacobian_matches_central_differences(robot):
    name, c, p, ctrl = robot
    rng = np.random.default_rng(3)
    m, k, h = len(c), len(ctrl), 1e-6
    r, J, rp, rm, scratch = np.empty(m), np.empty((m, k)), np.empty(m), np.empty(m), np.empty((m, k))
    for q in random_poses(name, ctrl, 20, rng):
        L = lengths_at(q, c, p)[0] + rng.uniform(-0.1, 0.1, m)  # any lengths: dr/dq does not depend on them
        cost = residuals_and_jacobian(L, c, p, ctrl, q, r, J)
        np.testing.assert_allclose(r, lengths_at(q, c, p)[0] - L, rtol=0, atol=1e-14)
        assert cost == pytest.approx(0.5 * r @ r, rel=1e-14)
        fd = np.empty((m, k))
        for j, d in enumerate(ctrl):
            dq = np.zeros(6)
            dq[d] = h
            residuals_and_jacobian(L, c, p, ctrl, q + dq, rp, scratch)
            residuals_and_jacobian(L, c, p, ctrl, q - dq, rm, scratch)
            fd[:, j] = (rp - rm) / (2 * h)
        np.testing.assert_allclose(J, fd, rtol=1e-6, atol=1e-9)
        assert np.abs(J).max() > 0.05


def test_lengths_of_no_pose_are_flagged_never_converged(robot):
    name, c, p, ctrl = robot
    q = path(name, 7)[2]
    q0 = off_by(q, ctrl, np.random.default_rng(4), 0.01, 1.0)
    L = lengths_at(q, c, p)[0]
    longer = L.copy()
    longer[1] *= 1.3  # one cable 30 % longer than the others allow
    unreachable = 0.3 * L  # no pose reaches every frame anchor
    for bad, least in ((longer, 0.01), (unreachable, 0.5)):
        fk = pose_from_lengths(bad, c, p, ctrl, q0)
        assert fk.status[0] in (1, 2) and fk.residual_m[0] > least  # m
        # large-residual least squares converges slowly (linearly): given the iterations it
        # stops at a least-squares point and says the lengths are of no pose
        fk = pose_from_lengths(bad, c, p, ctrl, q0, max_iter=1000)
        assert fk.status[0] == 2 and fk.iterations[0] < 1000 and fk.residual_m[0] > least
    # noise of 1e-8 m is consistent (threshold 1e-6 m + 1e-6 L): status 0 at the pose to ~1e-7
    noisy = pose_from_lengths(L + 1e-8 * np.random.default_rng(5).standard_normal(len(L)), c, p, ctrl, q0)
    assert noisy.status[0] == 0 and 1e-10 < noisy.residual_m[0] < 2e-8
    np.testing.assert_allclose(noisy.poses[0], q, rtol=0, atol=1e-6)
    # NaN lengths: not converged, no crash
    assert pose_from_lengths(np.full(len(L), np.nan), c, p, ctrl, q0).status[0] == 1


def test_stretched_cables_give_the_pose_back_through_tensions_and_EA(robot):
    name, c, p, ctrl = robot
    rng = np.random.default_rng(6)
    truth = path(name, 200)
    L = lengths_at(truth, c, p)
    T = rng.uniform(10, 450, L.shape)  # N
    L0 = L / (1 + T / 1e5)  # the winches' unstretched lengths, EA = 1e5 N
    np.testing.assert_allclose(stretched_lengths(L0, T, 1e5), L, rtol=1e-15)
    assert np.array_equal(stretched_lengths(L0, T, np.inf), L0)
    fk = pose_from_lengths(L0, c, p, ctrl, truth[0], tensions=T, EA=1e5)
    assert (fk.status == 0).all()
    np.testing.assert_allclose(fk.poses, truth, rtol=0, atol=1e-9)
    raw = pose_from_lengths(L0, c, p, ctrl, truth[0])  # the stretch ignored
    err = np.linalg.norm(raw.poses[:, :3] - truth[:, :3], axis=1)
    assert np.median(err) > 1e-4 and err.max() > 1e-3  # m: mm of stretch move the pose
    with pytest.raises(ValueError, match="both tensions and EA"):
        pose_from_lengths(L0, c, p, ctrl, truth[0], tensions=T)


def reference_pose(L, c, p, ctrl, q_start):
    """The obvious slow way: scipy's least squares on |c_i - x - R p_i| - L_i with R from
    scipy's intrinsic Z-Y-X Euler angles (rz, ry, rx), finite-difference Jacobian."""
    def residual(z):
        q = q_start.copy()
        q[ctrl] = z
        R = Rotation.from_euler("ZYX", [q[5], q[4], q[3]]).as_matrix()
        return np.linalg.norm(c - q[:3] - p @ R.T, axis=1) - L

    sol = least_squares(residual, q_start[ctrl], method="lm", xtol=1e-15, ftol=1e-15, gtol=1e-15)
    q = q_start.copy()
    q[ctrl] = sol.x
    return q


def test_warm_started_series_takes_few_iterations_and_matches_scipy(robot):
    name, c, p, ctrl = robot
    truth = path(name, 1000)
    L = lengths_at(truth, c, p)
    q0 = off_by(truth[0], ctrl, np.random.default_rng(7))
    fk = pose_from_lengths(L, c, p, ctrl, q0)
    assert (fk.status == 0).all()
    assert np.median(fk.iterations) <= 3 and fk.iterations[1:].max() <= 4
    assert fk.residual_m.max() < 1e-12
    np.testing.assert_allclose(fk.poses, truth, rtol=0, atol=1e-9)
    uncontrolled = np.setdiff1d(np.arange(6), ctrl)
    assert np.array_equal(fk.poses[:, uncontrolled], np.broadcast_to(q0[uncontrolled], (1000, len(uncontrolled))))
    for s in range(1, 1000, 50):
        ref = reference_pose(L[s], c, p, ctrl, fk.poses[s - 1])
        np.testing.assert_allclose(fk.poses[s], ref, rtol=0, atol=1e-9)


def _with_pulleys(name, c):
    """25 mm pulleys: the paper's top cables come down, the bottom ones up; cube8's axes point
    at the frame's centre."""
    m = len(c)
    if name == "paper":
        z = np.array([[0, 0, -1], [0, 0, -1], [0, 0, 1], [0, 0, 1]], dtype=float)
    else:
        z = 0.5 * (c.min(axis=0) + c.max(axis=0)) - c
        z /= np.linalg.norm(z, axis=1, keepdims=True)
    return np.ascontiguousarray(z), np.full(m, 0.025)


def test_poses_over_pulleys_recovered_and_the_jacobian_is_the_lengths_derivative(robot):
    """Lengths over swivelling pulleys (pulley_kinematics, the planner's) back to the pose from
    5 cm and 5 deg off, to 1e-9; the analytic Jacobian against central differences."""
    from marinecdpr.geometry.forward import pulley_residuals_and_jacobian
    from marinecdpr.geometry.pulley import pulley_kinematics

    name, c, p, ctrl = robot
    z, radius = _with_pulleys(name, c)
    rng = np.random.default_rng(4)
    truth = random_poses(name, ctrl, 120, rng)
    pk = pulley_kinematics(truth[:, :3], matrix_from_euler(truth[:, 3:]), c, z, radius, p)
    assert np.all(pk.status == 0)
    L = np.ascontiguousarray(pk.lengths)
    point = lengths_at(truth, c, p)
    assert np.abs(L - point).max() > 1e-4  # the pulleys matter
    work = forward_work(len(c), len(ctrl))
    for s in range(len(truth)):
        q = off_by(truth[s], ctrl, rng)
        assert pose_from_lengths_step(L[s], c, p, ctrl, q, 1e-12, 50, work, z, radius) == 0
        np.testing.assert_allclose(q, truth[s], rtol=0, atol=1e-9)
    # the series API and its warm start
    fk = pose_from_lengths(L[:20], c, p, ctrl, off_by(truth[0], ctrl, rng, 0.01, 1.0), pulley_axes=z,
                           pulley_radii=radius)
    assert np.all(fk.status == 0)
    np.testing.assert_allclose(fk.poses, truth[:20], atol=1e-9)
    q0 = truth[0].copy()
    r, J = np.empty(len(c)), np.empty((len(c), len(ctrl)))
    pulley_residuals_and_jacobian(L[1], c, z, radius, p, ctrl, q0, r, J, work)
    r2, J2 = np.empty(len(c)), np.empty((len(c), len(ctrl)))
    for a, d in enumerate(ctrl):
        h = 1e-6
        qp, qm = q0.copy(), q0.copy()
        qp[d] += h
        qm[d] -= h
        pulley_residuals_and_jacobian(L[1], c, z, radius, p, ctrl, qp, r2, J2, work)
        rp = r2.copy()
        pulley_residuals_and_jacobian(L[1], c, z, radius, p, ctrl, qm, r2, J2, work)
        np.testing.assert_allclose(J[:, a], (rp - r2) / (2 * h), atol=1e-7)
