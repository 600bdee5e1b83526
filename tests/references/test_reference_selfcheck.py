"""Self-checks of the independent reference model in ``reference.py``.

These tests check the reference against finite differences, closed forms and
limiting cases only (never against the package under test), so that it can
then serve as an oracle for the package's own tests.

Run with::

    /work/main/.venv/bin/python -m pytest /work/main/tests/references/test_reference_selfcheck.py -q
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
import reference as ref  # noqa: E402

# ---------------------------------------------------------------------------
# Test data
# ---------------------------------------------------------------------------

# Paper example (section 4): anchors, mass, inertia, bounds.
P_ANCHORS = np.array([[-0.125, 0.0, 0.15],
                      [0.125, 0.0, 0.15],
                      [0.125, 0.0, -0.15],
                      [-0.125, 0.0, -0.15]])
C_ANCHORS = np.array([[0.0, 0.0, 1.4],
                      [1.9, 0.0, 1.4],
                      [1.9, 0.0, 0.0],
                      [0.0, 0.0, 0.0]])
MASS = 5.0
I_PP = np.diag([0.03, 0.03, 0.06])
G = 9.8
X_CS = np.array([-0.78, 0.0, 2.2])
T_MIN, T_MAX = 10.0, 450.0


class Sinusoids:
    """Smooth test motion q_j(t) = a_j + b_j sin(w_j t + c_j), j = 0..5.

    Gives the value and exact first and second time derivatives, shape (6,).
    """

    def __init__(self, a, b, w, c):
        self.a, self.b, self.w, self.c = (np.asarray(v, dtype=float) for v in (a, b, w, c))

    def q(self, t):
        return self.a + self.b * np.sin(self.w * t + self.c)

    def qd(self, t):
        return self.b * self.w * np.cos(self.w * t + self.c)

    def qdd(self, t):
        return -self.b * self.w**2 * np.sin(self.w * t + self.c)


# A general 6-DOF ship motion with large angles (not only the paper's waves).
SHIP = Sinusoids(a=[1.0, -2.0, 0.3, 0.1, -0.2, 0.7],
                 b=[0.5, 0.4, 0.8, 0.4, 0.3, 0.9],
                 w=[0.7, 1.1, 1.3, 1.7, 0.9, 0.6],
                 c=[0.1, 0.2, 0.3, 0.4, 0.5, 0.6])
# A general 6-DOF platform motion in C, near the paper's workspace.
PLATFORM = Sinusoids(a=[0.9, 0.05, 0.7, 0.05, -0.1, 0.2],
                     b=[0.3, 0.1, 0.25, 0.3, 0.4, 0.5],
                     w=[1.2, 0.8, 1.5, 2.1, 1.4, 1.0],
                     c=[0.7, 0.1, 1.9, 0.3, 2.2, 1.1])
TIMES = [0.0, 0.37, 1.9, 4.25]


def paper_ship(t):
    """The paper's wave motion (eq. 22), degrees converted to rad."""
    k = np.pi / 3.0
    amp = np.deg2rad([6.0, 3.0, 0.5])
    eta = np.concatenate([np.zeros(3), amp * np.sin(k * t)])
    eta_d = np.concatenate([np.zeros(3), amp * k * np.cos(k * t)])
    eta_dd = np.concatenate([np.zeros(3), -amp * k**2 * np.sin(k * t)])
    return eta, eta_d, eta_dd


def paper_platform(t):
    """The paper's circular trajectory in C (eq. 21)."""
    k = 2.0 * np.pi / 15.0
    pose = np.array([0.38 * np.cos(k * t) + 0.6, 0.0, 0.38 * np.sin(k * t) + 0.7, 0, 0, 0])
    pose_d = np.array([-0.38 * k * np.sin(k * t), 0.0, 0.38 * k * np.cos(k * t), 0, 0, 0])
    pose_dd = np.array([-0.38 * k**2 * np.cos(k * t), 0.0, -0.38 * k**2 * np.sin(k * t), 0, 0, 0])
    return pose, pose_d, pose_dd


# ---------------------------------------------------------------------------
# Rotations
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("angles", [(0.1, -0.4, 2.0), (1.2, 0.3, -0.7), (0.0, 0.0, 0.0)])
def test_rot_matches_scipy_and_is_proper(angles):
    phi, theta, psi = angles
    R = ref.rot(angles)
    # Intrinsic z-y'-x'' with (psi, theta, phi) == Rz(psi) Ry(theta) Rx(phi).
    R_sp = Rotation.from_euler("ZYX", [psi, theta, phi]).as_matrix()
    np.testing.assert_allclose(R, R_sp, atol=1e-14)
    np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-14)
    assert np.linalg.det(R) == pytest.approx(1.0, abs=1e-14)


def test_rot_elementary_axes():
    a = 0.3
    # A positive rotation about z maps x onto (cos a, sin a, 0).
    np.testing.assert_allclose(ref.rot((0, 0, a)) @ [1, 0, 0], [np.cos(a), np.sin(a), 0], atol=1e-15)
    # About y maps z onto (sin a, 0, cos a); about x maps y onto (0, cos a, sin a).
    np.testing.assert_allclose(ref.rot((0, a, 0)) @ [0, 0, 1], [np.sin(a), 0, np.cos(a)], atol=1e-15)
    np.testing.assert_allclose(ref.rot((a, 0, 0)) @ [0, 1, 0], [0, np.cos(a), np.sin(a)], atol=1e-15)


@pytest.mark.parametrize("name", ["x", "y", "z"])
def test_elementary_derivatives_by_finite_difference(name):
    f = {"x": ref._rx, "y": ref._ry, "z": ref._rz}[name]
    f1 = {"x": ref._rx_d1, "y": ref._ry_d1, "z": ref._rz_d1}[name]
    f2 = {"x": ref._rx_d2, "y": ref._ry_d2, "z": ref._rz_d2}[name]
    h = 1e-5
    for a in (-2.0, 0.3, 1.4):
        np.testing.assert_allclose(f1(a), (f(a + h) - f(a - h)) / (2 * h), atol=1e-9)
        np.testing.assert_allclose(f2(a), (f1(a + h) - f1(a - h)) / (2 * h), atol=1e-9)


def test_skew_vee_roundtrip():
    v = np.array([0.3, -1.2, 2.5])
    u = np.array([-0.7, 0.4, 1.1])
    np.testing.assert_allclose(ref.skew(v) @ u, np.cross(v, u), atol=1e-15)
    np.testing.assert_allclose(ref.vee(ref.skew(v)), v, atol=1e-15)


# ---------------------------------------------------------------------------
# (a) Ship and platform angular kinematics
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("t", TIMES)
def test_ship_omega_alpha_by_finite_difference(t):
    h = 1e-5
    s = ref.ship_state(SHIP.q(t), SHIP.qd(t), SHIP.qdd(t))
    R = s["R_SO"]
    np.testing.assert_allclose(R, ref.rot(SHIP.q(t)[3:]), atol=1e-15)

    # Rdot by central difference of rot() along the motion.
    Rdot_fd = (ref.rot(SHIP.q(t + h)[3:]) - ref.rot(SHIP.q(t - h)[3:])) / (2 * h)
    np.testing.assert_allclose(s["Rdot_SO"], Rdot_fd, atol=1e-8)
    W = Rdot_fd @ R.T
    np.testing.assert_allclose(W + W.T, 0.0, atol=1e-8)       # really skew
    np.testing.assert_allclose(s["omega_O"], ref.vee(W), atol=1e-8)

    # Rddot by second difference.
    Rddot_fd = (ref.rot(SHIP.q(t + 1e-4)[3:]) - 2 * R + ref.rot(SHIP.q(t - 1e-4)[3:])) / 1e-8
    np.testing.assert_allclose(s["Rddot_SO"], Rddot_fd, atol=1e-6)
    # Rddot R^T - [w][w] must be skew (it is [alpha]).
    Wo = ref.skew(s["omega_O"])
    Alpha = s["Rddot_SO"] @ R.T - Wo @ Wo
    np.testing.assert_allclose(Alpha + Alpha.T, 0.0, atol=1e-13)
    np.testing.assert_allclose(Alpha, ref.skew(s["alpha_O"]), atol=1e-13)

    # alpha by central difference of omega.
    s_p = ref.ship_state(SHIP.q(t + h), SHIP.qd(t + h), SHIP.qdd(t + h))
    s_m = ref.ship_state(SHIP.q(t - h), SHIP.qd(t - h), SHIP.qdd(t - h))
    alpha_fd = (s_p["omega_O"] - s_m["omega_O"]) / (2 * h)
    np.testing.assert_allclose(s["alpha_O"], alpha_fd, atol=1e-8)


@pytest.mark.parametrize("t", TIMES)
def test_ship_omega_closed_form(t):
    """Independent closed form for Rz Ry Rx: body rates from Euler rates."""
    phi, theta, _ = SHIP.q(t)[3:]
    dphi, dtheta, dpsi = SHIP.qd(t)[3:]
    omega_body = np.array([
        dphi - dpsi * np.sin(theta),
        dtheta * np.cos(phi) + dpsi * np.cos(theta) * np.sin(phi),
        -dtheta * np.sin(phi) + dpsi * np.cos(theta) * np.cos(phi),
    ])
    s = ref.ship_state(SHIP.q(t), SHIP.qd(t), SHIP.qdd(t))
    np.testing.assert_allclose(s["omega_O"], s["R_SO"] @ omega_body, atol=1e-13)


@pytest.mark.parametrize("t", TIMES)
def test_platform_state_by_finite_difference(t):
    h = 1e-5
    s = ref.platform_state(PLATFORM.q(t), PLATFORM.qd(t), PLATFORM.qdd(t))
    R = s["R_PC"]
    Rdot_fd = (ref.rot(PLATFORM.q(t + h)[3:]) - ref.rot(PLATFORM.q(t - h)[3:])) / (2 * h)
    np.testing.assert_allclose(s["omega_PC"], ref.vee(Rdot_fd @ R.T), atol=1e-8)
    s_p = ref.platform_state(PLATFORM.q(t + h), PLATFORM.qd(t + h), PLATFORM.qdd(t + h))
    s_m = ref.platform_state(PLATFORM.q(t - h), PLATFORM.qd(t - h), PLATFORM.qdd(t - h))
    np.testing.assert_allclose(s["alpha_PC"], (s_p["omega_PC"] - s_m["omega_PC"]) / (2 * h), atol=1e-8)
    np.testing.assert_allclose(s["x_PC"], PLATFORM.q(t)[:3])
    np.testing.assert_allclose(s["v_PC"], PLATFORM.qd(t)[:3])
    np.testing.assert_allclose(s["a_PC"], PLATFORM.qdd(t)[:3])


# ---------------------------------------------------------------------------
# (b) Static cases of the required wrench
# ---------------------------------------------------------------------------


def test_wrench_still_ship_static_platform():
    z6 = np.zeros(6)
    pose = np.array([0.98, 0.0, 0.7, 0.0, 0.0, 0.0])
    w = ref.required_wrench(pose, z6, z6, z6, z6, z6, X_CS, MASS, I_PP, G, np.zeros(3), np.zeros(3))
    np.testing.assert_allclose(w, [0, 0, MASS * G, 0, 0, 0], atol=1e-12)


def test_wrench_still_ship_static_rotated_platform():
    """A static platform needs no moment, whatever its orientation."""
    z6 = np.zeros(6)
    pose = np.array([0.5, 0.1, 0.9, 0.3, -0.2, 1.0])
    w = ref.required_wrench(pose, z6, z6, z6, z6, z6, X_CS, MASS, I_PP, G, np.zeros(3), np.zeros(3))
    np.testing.assert_allclose(w, [0, 0, MASS * G, 0, 0, 0], atol=1e-12)


def test_wrench_tilted_static_ship_and_disturbance():
    """Ship held still at an angle: weight seen in C is R_SO^T (0, 0, m g)."""
    z6 = np.zeros(6)
    eta = np.array([3.0, -1.0, 0.5, 0.2, -0.1, 0.8])
    pose = np.array([0.5, 0.1, 0.9, 0.3, -0.2, 1.0])
    f_r = np.array([1.0, -2.0, 3.0])
    m_r = np.array([0.1, 0.2, -0.3])
    w = ref.required_wrench(pose, z6, z6, eta, z6, z6, X_CS, MASS, I_PP, G, f_r, m_r)
    R_SO = ref.rot(eta[3:])
    np.testing.assert_allclose(w[:3], R_SO.T @ (np.array([0, 0, MASS * G]) - f_r), atol=1e-12)
    np.testing.assert_allclose(w[3:], -R_SO.T @ m_r, atol=1e-12)


def test_wrench_uniform_translation_of_ship_changes_nothing():
    z6 = np.zeros(6)
    pose = np.array([0.98, 0.0, 0.7, 0.0, 0.0, 0.0])
    eta_d = np.array([2.0, -1.0, 0.3, 0, 0, 0])          # constant velocity
    w = ref.required_wrench(pose, z6, z6, z6, eta_d, z6, X_CS, MASS, I_PP, G, np.zeros(3), np.zeros(3))
    np.testing.assert_allclose(w, [0, 0, MASS * G, 0, 0, 0], atol=1e-12)


# ---------------------------------------------------------------------------
# (c) Absolute kinematics against finite differences of positions/rotations
# ---------------------------------------------------------------------------


def _abs_kin(t, ship=SHIP, plat=PLATFORM):
    return ref.absolute_kinematics(plat.q(t), plat.qd(t), plat.qdd(t),
                                   ship.q(t), ship.qd(t), ship.qdd(t), X_CS)


@pytest.mark.parametrize("t", TIMES)
def test_absolute_acceleration_by_finite_difference(t):
    k = _abs_kin(t)
    x = lambda s: ref.position_in_O(PLATFORM.q(s), SHIP.q(s), X_CS)  # noqa: E731
    np.testing.assert_allclose(k["x_PO"], x(t), atol=1e-15)
    h1 = 1e-5
    np.testing.assert_allclose(k["v_PO"], (x(t + h1) - x(t - h1)) / (2 * h1), atol=1e-8)
    h2 = 1e-3
    a_fd = (x(t + h2) - 2 * x(t) + x(t - h2)) / h2**2
    np.testing.assert_allclose(k["a_PO"], a_fd, atol=2e-6)


def test_paper_motion_acceleration_by_finite_difference():
    for t in (0.0, 0.8, 2.3, 7.1):
        pose, pose_d, pose_dd = paper_platform(t)
        eta, eta_d, eta_dd = paper_ship(t)
        k = ref.absolute_kinematics(pose, pose_d, pose_dd, eta, eta_d, eta_dd, X_CS)
        x = lambda s: ref.position_in_O(paper_platform(s)[0], paper_ship(s)[0], X_CS)  # noqa: E731
        h = 1e-3
        np.testing.assert_allclose(k["a_PO"], (x(t + h) - 2 * x(t) + x(t - h)) / h**2, atol=1e-7)


def test_paper_start_position():
    """With the ship level, the platform starts at x_PO(0) = (0.2, 0, 2.9)."""
    pose, _, _ = paper_platform(0.0)
    np.testing.assert_allclose(ref.position_in_O(pose, np.zeros(6), X_CS), [0.2, 0.0, 2.9], atol=1e-12)


@pytest.mark.parametrize("t", TIMES)
def test_absolute_angular_kinematics_by_finite_difference(t):
    k = _abs_kin(t)
    R = lambda s: ref.rot(SHIP.q(s)[3:]) @ ref.rot(PLATFORM.q(s)[3:])  # noqa: E731
    np.testing.assert_allclose(k["R_PO"], R(t), atol=1e-15)
    h = 1e-5
    Rdot_fd = (R(t + h) - R(t - h)) / (2 * h)
    np.testing.assert_allclose(k["omega_PO"], ref.vee(Rdot_fd @ R(t).T), atol=1e-8)
    alpha_fd = (_abs_kin(t + h)["omega_PO"] - _abs_kin(t - h)["omega_PO"]) / (2 * h)
    np.testing.assert_allclose(k["alpha_PO"], alpha_fd, atol=1e-8)


@pytest.mark.parametrize("t", TIMES)
def test_kinematics_match_paper_eqs_9_to_11(t):
    """The [omega x] forms of eqs. (9)-(11) give the same numbers."""
    k = _abs_kin(t)
    sh, pl = k["ship"], k["platform"]
    R, w, al = sh["R_SO"], sh["omega_O"], sh["alpha_O"]
    W, A = ref.skew(w), ref.skew(al)
    r = X_CS + pl["x_PC"]
    a9 = sh["a_SO"] + A @ R @ r + W @ W @ R @ r + 2 * W @ R @ pl["v_PC"] + R @ pl["a_PC"]
    np.testing.assert_allclose(k["a_PO"], a9, atol=1e-12)
    np.testing.assert_allclose(k["omega_PO"], w + R @ pl["omega_PC"], atol=1e-13)
    al11 = al + W @ R @ pl["omega_PC"] + R @ pl["alpha_PC"]
    np.testing.assert_allclose(k["alpha_PO"], al11, atol=1e-12)


@pytest.mark.parametrize("t", TIMES)
def test_wrench_is_rate_of_momentum(t):
    """Cable wrench in O == d(momentum)/dt - gravity - disturbance (by FD)."""
    f_r = np.array([0.4, -1.5, 2.0])
    m_r = np.array([-0.2, 0.3, 0.1])
    w = ref.required_wrench(PLATFORM.q(t), PLATFORM.qd(t), PLATFORM.qdd(t),
                            SHIP.q(t), SHIP.qd(t), SHIP.qdd(t), X_CS, MASS, I_PP, G, f_r, m_r)
    R_SO = ref.rot(SHIP.q(t)[3:])
    F_O, M_O = R_SO @ w[:3], R_SO @ w[3:]

    def momentum(s):
        k = _abs_kin(s)
        I_O = k["R_PO"] @ I_PP @ k["R_PO"].T
        return MASS * k["v_PO"], I_O @ k["omega_PO"]

    h = 1e-5
    (p_p, H_p), (p_m, H_m) = momentum(t + h), momentum(t - h)
    np.testing.assert_allclose(F_O, (p_p - p_m) / (2 * h) + MASS * np.array([0, 0, G]) - f_r, atol=1e-7)
    np.testing.assert_allclose(M_O, (H_p - H_m) / (2 * h) - m_r, atol=1e-8)


# ---------------------------------------------------------------------------
# Cable kinematics
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("t", TIMES)
def test_cable_rates_and_jacobian(t):
    pose = PLATFORM.q(t)
    lengths, u, J = ref.cable_quantities(pose, C_ANCHORS, P_ANCHORS)
    np.testing.assert_allclose(np.linalg.norm(u, axis=1), 1.0, atol=1e-15)
    # l_i = |c_i - x_PC - R_PC p_i|, written out once more.
    R = ref.rot(pose[3:])
    for i in range(4):
        assert lengths[i] == pytest.approx(np.linalg.norm(C_ANCHORS[i] - pose[:3] - R @ P_ANCHORS[i]))
    # Eq. (5): ldot = -J~ [v_PC; omega_PC].
    h = 1e-5
    ldot_fd = (ref.cable_quantities(PLATFORM.q(t + h), C_ANCHORS, P_ANCHORS)[0]
               - ref.cable_quantities(PLATFORM.q(t - h), C_ANCHORS, P_ANCHORS)[0]) / (2 * h)
    st = ref.platform_state(PLATFORM.q(t), PLATFORM.qd(t), PLATFORM.qdd(t))
    np.testing.assert_allclose(ldot_fd, -J @ np.concatenate([st["v_PC"], st["omega_PC"]]), atol=1e-8)


def test_jacobian_transpose_is_cable_wrench():
    pose = np.array([0.7, 0.02, 0.6, 0.1, -0.2, 0.3])
    _, u, J = ref.cable_quantities(pose, C_ANCHORS, P_ANCHORS)
    T = np.array([120.0, 80.0, 30.0, 55.0])
    R = ref.rot(pose[3:])
    F = sum(T[i] * u[i] for i in range(4))
    M = sum(np.cross(R @ P_ANCHORS[i], T[i] * u[i]) for i in range(4))
    np.testing.assert_allclose(J.T @ T, np.concatenate([F, M]), atol=1e-12)


# ---------------------------------------------------------------------------
# Brute-force least-distance tension distribution
# ---------------------------------------------------------------------------


def _one_d_clip_solution(Jc, w, target, lo, hi):
    """Redundancy 1 only: T = Ts + N lam, lam* clipped (MODEL_NOTES)."""
    Ts = np.linalg.pinv(Jc.T) @ w
    _, _, Vt = np.linalg.svd(Jc.T)
    N = Vt[-1]
    a = (lo - Ts) / N
    b = (hi - Ts) / N
    lam_lo = np.max(np.minimum(a, b))
    lam_hi = np.min(np.maximum(a, b))
    if lam_lo > lam_hi:
        return None
    lam = N @ (target - Ts) / (N @ N)
    return Ts + N * np.clip(lam, lam_lo, lam_hi)


def test_brute_force_interior_equals_projection():
    rng = np.random.default_rng(0)
    Jc = rng.normal(size=(6, 3))
    target = np.full(6, 100.0)
    w = Jc.T @ (target + rng.normal(size=6))          # close to target: no bound active
    T = ref.brute_force_least_distance(Jc, w, target, 0.0, 1000.0)
    A = Jc.T
    T_proj = target + A.T @ np.linalg.solve(A @ A.T, w - A @ target)
    np.testing.assert_allclose(T, T_proj, atol=1e-9)


def test_brute_force_matches_clipped_lambda_on_paper_trajectory():
    E = 0.5 * (T_MIN + T_MAX)
    for t in np.linspace(0.0, 15.0, 13):
        pose, pose_d, pose_dd = paper_platform(t)
        eta, eta_d, eta_dd = paper_ship(t)
        w = ref.required_wrench(pose, pose_d, pose_dd, eta, eta_d, eta_dd, X_CS, MASS, I_PP, G,
                                np.zeros(3), np.zeros(3))
        _, _, J = ref.cable_quantities(pose, C_ANCHORS, P_ANCHORS)
        sel = [0, 2, 4]                                 # planar: x, z, moment about y
        Jc, wc = J[:, sel], w[sel]
        T = ref.brute_force_least_distance(Jc, wc, E, T_MIN, T_MAX)
        T1 = _one_d_clip_solution(Jc, wc, np.full(4, E), np.full(4, T_MIN), np.full(4, T_MAX))
        assert T is not None and T1 is not None
        np.testing.assert_allclose(T, T1, atol=1e-8)
        np.testing.assert_allclose(Jc.T @ T, wc, atol=1e-9)


def test_brute_force_active_bounds_matches_clipped_lambda():
    """Tight bounds force some cables onto a bound."""
    rng = np.random.default_rng(1)
    hits = 0
    for _ in range(200):
        Jc = rng.normal(size=(4, 3))
        w = Jc.T @ rng.uniform(0.0, 10.0, size=4)
        target = rng.uniform(-5.0, 15.0, size=4)
        lo, hi = np.zeros(4), np.full(4, 10.0)
        T = ref.brute_force_least_distance(Jc, w, target, lo, hi)
        T1 = _one_d_clip_solution(Jc, w, target, lo, hi)
        assert T is not None and T1 is not None
        np.testing.assert_allclose(T, T1, atol=1e-8)
        hits += np.any(np.isclose(T, lo) | np.isclose(T, hi))
    assert hits > 20


def test_brute_force_kkt_spatial_8_cables():
    """6 wrench components, 8 cables: the answer satisfies the KKT conditions."""
    rng = np.random.default_rng(2)
    checked = 0
    for _ in range(10):
        Jc = rng.normal(size=(8, 6))
        w = Jc.T @ rng.uniform(1.0, 9.0, size=8)
        target = rng.uniform(-2.0, 12.0, size=8)
        lo, hi = np.full(8, 1.0), np.full(8, 9.0)
        T = ref.brute_force_least_distance(Jc, w, target, lo, hi)
        assert T is not None
        assert np.all(T >= lo - 1e-9) and np.all(T <= hi + 1e-9)
        np.testing.assert_allclose(Jc.T @ T, w, atol=1e-9)
        at_lo = np.isclose(T, lo, atol=1e-9)
        at_hi = np.isclose(T, hi, atol=1e-9)
        free = ~(at_lo | at_hi)
        if np.linalg.matrix_rank(Jc[free]) < 6:
            continue                                  # multipliers not unique; skip
        grad = T - target                              # half the gradient
        mu = np.linalg.lstsq(Jc[free], grad[free], rcond=None)[0]
        nu = grad - Jc @ mu
        np.testing.assert_allclose(nu[free], 0.0, atol=1e-8)
        assert np.all(nu[at_lo] >= -1e-8)              # pushing up would cost more
        assert np.all(nu[at_hi] <= 1e-8)
        checked += 1
    assert checked >= 5


def test_brute_force_infeasible_returns_none():
    # Two cables pulling along +x only; a force along -x is impossible.
    Jc = np.array([[1.0], [1.0]])
    assert ref.brute_force_least_distance(Jc, np.array([-1.0]), 5.0, 0.0, 10.0) is None
    # Too much force for the upper bounds.
    assert ref.brute_force_least_distance(Jc, np.array([25.0]), 5.0, 0.0, 10.0) is None
    # Exactly at the limit is feasible.
    np.testing.assert_allclose(ref.brute_force_least_distance(Jc, np.array([20.0]), 5.0, 0.0, 10.0),
                               [10.0, 10.0], atol=1e-12)


def test_brute_force_rank_deficient_free_set():
    # Both cables along x; k = 2 (x and y force) with zero y demand: every
    # free set is rank deficient, yet the problem is feasible.
    Jc = np.array([[1.0, 0.0], [1.0, 0.0]])
    T = ref.brute_force_least_distance(Jc, np.array([6.0, 0.0]), np.array([1.0, 2.0]), 0.0, 10.0)
    np.testing.assert_allclose(T, [2.5, 3.5], atol=1e-12)
