"""Swivelling pulleys: hand-worked plane geometry, the point model's limit, the length shift
a 25 mm pulley makes, J~ against finite differences, the force's direction, degenerate
anchors, and the per-step function's cost."""


import numpy as np
import pytest
from numba import njit

from marinecdpr.geometry.kinematics import cable_kinematics
from marinecdpr.geometry.pulley import (INSIDE, INVALID, ON_AXIS, REGULAR, pulley_kinematics,
                                        pulleys_step)
from marinecdpr.geometry.rotations import matrix_from_euler

R25 = 0.025


def _one(b, a=(0.0, 0.0, 0.0), z=(0.0, 0.0, -1.0), r=R25):
    """One cable, one pose: P's origin at b, p = 0, R = I."""
    return pulley_kinematics(np.array([b], float), np.eye(3)[None], np.array([a], float),
                             np.array([z], float), np.array([r]), np.zeros((1, 3)))


def _rotation(w):
    """exp([w x]) (Rodrigues), for rows of w (n, 3)."""
    w = np.atleast_2d(w)
    th = np.linalg.norm(w, axis=1)[:, None, None]
    K = np.zeros((w.shape[0], 3, 3))
    K[:, 0, 1], K[:, 0, 2], K[:, 1, 2] = -w[:, 2], w[:, 1], -w[:, 0]
    K = K - K.transpose(0, 2, 1)
    with np.errstate(invalid="ignore", divide="ignore"):
        s = np.where(th > 0, np.sin(th) / th, 1.0)
        c = np.where(th > 0, (1 - np.cos(th)) / th**2, 0.5)
    return np.eye(3) + s * K + c * K @ K


# ------------------------------------------------------------- plane geometry by hand


def _tangent_by_hand(bs, bh, r):
    """The cable's exit point and wrap angle in the pulley's plane, by the tangent
    construction: coordinates (s, h), s across the axis towards b, h along the arrival
    direction; a = (0, 0), centre M = (r, 0); the cable arrives going +h.

    The two tangent points from b are where the pulley's circle meets the circle on the
    diameter M-b (Thales): at distance r^2/d from M along D = b - M, +-r l/d across it.
    The cable takes the one it reaches by wrapping on from a: it turns clockwise in (s, h)
    (at a it runs +h with M on its +s side), so (C - M) x (b - C) < 0. The wrap angle is the
    clockwise angle at M from a - M = (-r, 0) to C - M."""
    M = np.array([r, 0.0])
    D = np.array([bs, bh]) - M
    d2 = D @ D
    ell = np.sqrt(d2 - r * r)
    across = np.array([-D[1], D[0]])  # D turned +90 deg
    pts = [M + (r * r / d2) * D + sgn * (r * ell / d2) * across for sgn in (1.0, -1.0)]
    cw = [((P - M)[0] * (np.array([bs, bh]) - P)[1] - (P - M)[1] * (np.array([bs, bh]) - P)[0]) < 0
          for P in pts]
    assert sum(cw) == 1
    C = pts[cw.index(True)]
    beta = (np.pi - np.arctan2(C[1] - M[1], C[0] - M[0])) % (2 * np.pi)
    return C, beta, ell


@pytest.mark.parametrize("b", [(1.0, 0.0, -1.0), (0.5, 0.0, 0.0), (1.0, 0.0, 0.2), (0.02, 0.0, -1.0)])
def test_exit_point_wrap_and_length_in_the_pulley_plane_by_hand(b):
    # a = 0, z = (0, 0, -1): the cable comes down onto the pulley; k = +x; plane (s, h) =
    # (x, -z)
    kin = _one(b)
    C2, beta, ell = _tangent_by_hand(b[0], -b[2], R25)
    assert kin.status[0, 0] == REGULAR
    np.testing.assert_allclose(kin.exits_C[0, 0], [C2[0], 0.0, -C2[1]], rtol=0, atol=1e-12)
    np.testing.assert_allclose(kin.wrap_angles[0, 0], beta, rtol=0, atol=1e-12)
    np.testing.assert_allclose(kin.free_lengths[0, 0], ell, rtol=0, atol=1e-12)
    np.testing.assert_allclose(kin.lengths[0, 0], R25 * beta + ell, rtol=0, atol=1e-12)
    # the free span is the straight line from C to b, pulled towards C
    np.testing.assert_allclose(np.linalg.norm(np.array(b) - kin.exits_C[0, 0]), ell, rtol=1e-12)
    np.testing.assert_allclose(kin.units[0, 0], (kin.exits_C[0, 0] - b) / ell, atol=1e-12)


def test_closed_forms_of_two_plane_cases():
    # b level with the axis' foot, 0.5 m across: beta = pi/2 + asin(r / |b - M|),
    # l = sqrt(0.475^2 - 0.025^2) = sqrt(0.225)
    kin = _one((0.5, 0.0, 0.0))
    assert kin.wrap_angles[0, 0] == pytest.approx(np.pi / 2 + np.arcsin(1 / 19), abs=1e-14)
    assert kin.free_lengths[0, 0] == pytest.approx(np.sqrt(0.225), abs=1e-14)
    assert kin.lengths[0, 0] == pytest.approx(R25 * (np.pi / 2 + np.arcsin(1 / 19)) + np.sqrt(0.225), abs=1e-14)
    assert np.degrees(kin.wrap_angles[0, 0]) == pytest.approx(93.01696, abs=1e-5)
    # b 1 m above the pulley's far rim (x = 2r), behind the arrival: the cable wraps half
    # the pulley and runs back up from the far rim, beta = pi, l = 1
    kin = _one((2 * R25, 0.0, 1.0))
    assert kin.wrap_angles[0, 0] == pytest.approx(np.pi, abs=1e-14)
    np.testing.assert_allclose(kin.exits_C[0, 0], [2 * R25, 0, 0], atol=1e-15)
    assert kin.lengths[0, 0] == pytest.approx(R25 * np.pi + 1.0, abs=1e-14)


def test_wraps_beyond_a_half_turn_take_the_tangent_that_continues_the_wrap():
    # b behind the pulley and close to the incoming cable: the wrap passes pi towards 2 pi
    for bs, bh in [(0.01, -0.05), (0.004, -0.03), (0.03, -0.2)]:
        kin = _one((bs, 0.0, -bh))
        C2, beta, ell = _tangent_by_hand(bs, bh, R25)
        assert beta > np.pi
        np.testing.assert_allclose(kin.wrap_angles[0, 0], beta, atol=1e-12)
        np.testing.assert_allclose(kin.exits_C[0, 0], [C2[0], 0.0, -C2[1]], atol=1e-12)


# ------------------------------------------------------------------- the point model


def _random_robot(seed, m=8, n=40):
    rng = np.random.default_rng(seed)
    a = rng.uniform(-2, 2, size=(m, 3))
    z = rng.normal(size=(m, 3))
    z /= np.linalg.norm(z, axis=1, keepdims=True)
    p = rng.uniform(-0.3, 0.3, size=(m, 3))
    x = rng.uniform(-1, 1, size=(n, 3))
    R = matrix_from_euler(rng.uniform(-0.6, 0.6, size=(n, 3)))
    tw = rng.normal(size=(n, 6))
    return a, z, p, x, R, tw


def test_radius_zero_is_the_point_model_exactly_and_small_radii_converge_to_it():
    a, z, p, x, R, tw = _random_robot(1)
    point = cable_kinematics(x, R, a, p, tw)
    zero = pulley_kinematics(x, R, a, z, np.zeros(8), p, tw)
    assert (zero.status == REGULAR).all()
    assert np.array_equal(zero.lengths, point.lengths)
    assert np.array_equal(zero.J_tilde, point.J_tilde)
    assert np.array_equal(zero.length_rates, point.length_rates)
    assert np.array_equal(zero.free_lengths, point.lengths)
    assert np.array_equal(zero.exits_C, np.broadcast_to(a, zero.exits_C.shape))
    tiny = pulley_kinematics(x, R, a, z, np.full(8, 1e-9), p, tw)
    assert (tiny.status == REGULAR).all()
    np.testing.assert_allclose(tiny.lengths, point.lengths, rtol=0, atol=1e-8)
    np.testing.assert_allclose(tiny.J_tilde, point.J_tilde, rtol=0, atol=1e-8)
    np.testing.assert_allclose(tiny.exits_C, zero.exits_C, rtol=0, atol=1e-8)
    # beta's limit, kept at r = 0: the angle between z and b - a
    np.testing.assert_allclose(tiny.wrap_angles, zero.wrap_angles, rtol=0, atol=1e-8)
    b_minus_a = x[:, None] + np.einsum("nij,mj->nmi", R, p) - a
    cosang = (b_minus_a @ z.T).diagonal(axis1=1, axis2=2) / np.linalg.norm(b_minus_a, axis=2)
    np.testing.assert_allclose(zero.wrap_angles, np.arccos(cosang), atol=1e-7)
    # mixed radii: the r = 0 cables keep the point model's numbers to the bit
    mixed = pulley_kinematics(x, R, a, z, np.array([0, R25] * 4), p)
    assert np.array_equal(mixed.lengths[:, ::2], point.lengths[:, ::2])
    assert np.array_equal(mixed.J_tilde[:, ::2], point.J_tilde[:, ::2])
    assert (mixed.lengths[:, 1::2] > point.lengths[:, 1::2]).all()  # r (beta - sin beta) > 0


# ------------------------------------------------------------------- the length shift


SHIFT_30_MM = 0.58443  # exact below; r (th - sin th) = 0.5900 mm, less r^2 (1 - cos th)^2 / 2l
SHIFT_90_MM = 13.96508  # r (th - sin th) = 14.2699 mm, less 0.31 mm


@pytest.mark.parametrize("deg, expected_mm", [(30.0, SHIFT_30_MM), (90.0, SHIFT_90_MM)])
def test_a_25_mm_pulley_lengthens_a_1_m_cable_by_06_mm_at_30_deg_and_14_mm_at_90(deg, expected_mm):
    # deflection = the angle between the arrival direction z and the free span: the cable
    # leaves C along t = sin(th) k + cos(th) z and runs 1 m to b. Here z = (0, 0, -1),
    # k = (1, 0, 0) and a = (0.3, -0.2, 1.4).
    th, lf = np.radians(deg), 1.0
    a = np.array([0.3, -0.2, 1.4])
    k, z = np.array([1.0, 0, 0]), np.array([0, 0, -1.0])
    C = a + R25 * (1 - np.cos(th)) * k + R25 * np.sin(th) * z  # on the rim, centre a + r k
    assert np.linalg.norm(C - (a + R25 * k)) == pytest.approx(R25, abs=1e-15)
    b = C + lf * (np.sin(th) * k + np.cos(th) * z)
    kin = _one(b, a=a, z=z)
    assert kin.wrap_angles[0, 0] == pytest.approx(th, abs=1e-12)
    assert kin.free_lengths[0, 0] == pytest.approx(lf, abs=1e-12)
    shift = kin.lengths[0, 0] - np.linalg.norm(b - a)
    # |b - a|^2 = (l + r sin th)^2 + r^2 (1 - cos th)^2 (b - a along and across t)
    exact = R25 * th + lf - np.hypot(lf + R25 * np.sin(th), R25 * (1 - np.cos(th)))
    assert shift == pytest.approx(exact, abs=1e-13)
    assert shift * 1e3 == pytest.approx(expected_mm, abs=5e-6)
    # long cables: r (th - sin th) - r^2 (1 - cos th)^2 / (2 l) + O(r^3 / l^2)
    assert shift == pytest.approx(R25 * (th - np.sin(th)) - R25**2 * (1 - np.cos(th))**2 / (2 * lf), abs=1e-5)
    # the "about 0.6 mm" and "about 14 mm" of the figure, within 10 %
    assert shift * 1e3 == pytest.approx({30.0: 0.6, 90.0: 14.0}[deg], rel=0.1)


# ------------------------------------------------------------------ J~ and the force


def _fd_rates(x, R, a, z, r, p, v, w, h=1e-4):
    """dL/ds, dl_f/ds at s = 0 along x + s v, exp(s [w x]) R: five-point stencil (error
    O(h^4)), and whether every cable was regular on the stencil."""
    s = np.array([-2, -1, 1, 2]) * h
    xs = x + s[:, None] * v
    Rs = _rotation(s[:, None] * w) @ R
    k = pulley_kinematics(xs, Rs, a, z, r, p)
    stencil = np.array([1, -8, 8, -1]) / (12 * h)
    return stencil @ k.lengths, stencil @ k.free_lengths, (k.status == REGULAR).all(axis=0)


def _regular_robot(rng, m, planar):
    """Random frame anchors, unit axes, radii (1-10 cm) and platform anchors."""
    a = rng.uniform(-1.5, 1.5, size=(m, 3))
    z = rng.normal(size=(m, 3))
    p = rng.uniform(-0.3, 0.3, size=(m, 3))
    if planar:
        a[:, 1] = z[:, 1] = p[:, 1] = 0.0
    z /= np.linalg.norm(z, axis=1, keepdims=True)
    return a, z, rng.uniform(0.01, 0.1, size=m), p


@pytest.mark.parametrize("planar", [True, False])
def test_length_rates_from_J_tilde_match_finite_differences(planar):
    rng = np.random.default_rng(7 if planar else 8)
    betas, wrap_share, checked = [], [], 0
    for _ in range(40):
        a, z, r, p = _regular_robot(rng, 8, planar)
        x = rng.uniform(-0.5, 0.5, size=3)
        if planar:
            x[1] = 0.0
            R = matrix_from_euler(np.array([[0.0, rng.uniform(-1, 1), 0.0]]))[0]
            v = rng.normal(size=3) * [1, 0, 1]
            w = np.array([0.0, rng.normal(), 0.0])
        else:
            R = matrix_from_euler(rng.uniform(-1, 1, size=(1, 3)))[0]
            v, w = rng.normal(size=3), rng.normal(size=3)
        b = x + (R @ p.T).T
        # half the cables placed close behind their pulleys (wraps up to nearly 2 pi): a = b -
        # (s k + h z), k a unit vector across z, s in 2-15 cm
        k = np.cross(z[:4], rng.normal(size=(4, 3)) * ([1, 0, 1] if planar else 1))
        k /= np.linalg.norm(k, axis=1, keepdims=True)
        a[:4] = b[:4] - rng.uniform(0.02, 0.15, size=(4, 1)) * k - rng.uniform(-0.8, 0.4, size=(4, 1)) * z[:4]
        r[:4] = rng.uniform(0.03, 0.1, size=4)
        twist = np.concatenate([v, w])
        kin = pulley_kinematics(x[None], R[None], a, z, r, p, twist[None])
        rates = kin.length_rates[0]
        np.testing.assert_allclose(rates, -kin.J_tilde[0] @ twist, rtol=1e-14, atol=1e-15)
        # away from the singularities: 2 cm from the axis and from the rim
        wa = b - a
        across = np.linalg.norm(wa - (wa * z).sum(1, keepdims=True) * z, axis=1)
        M = a + r[:, None] * (wa - (wa * z).sum(1, keepdims=True) * z) / across[:, None]
        fd, fd_free, regular = _fd_rates(x, R, a, z, r, p, v, w)
        good = regular & (across > 0.02) & (np.linalg.norm(b - M, axis=1) > r + 0.02)
        scale = np.linalg.norm(twist)
        err = np.abs(rates - fd)[good]
        assert np.all(err <= 1e-7 * np.abs(fd[good]) + 1e-10 * scale), (rates, fd)
        # the wrap's rate r beta' is what makes L' the projection onto the free span: the
        # free span's own rate differs from it by r beta'
        wrap_share.extend((np.abs(fd - fd_free) / (np.abs(fd) + 1e-3 * scale))[good])
        betas.extend(kin.wrap_angles[0][good])
        checked += good.sum()
    betas = np.array(betas)
    assert checked >= 250
    assert betas.min() < np.pi / 4 and betas.max() > 1.25 * np.pi  # every kind of wrap was checked
    assert max(wrap_share) > 0.1  # ... and r beta' mattered


def test_free_span_is_tangent_at_the_exit_point_and_in_the_pulley_plane():
    rng = np.random.default_rng(11)
    a, z, r, p = _regular_robot(rng, 8, planar=False)
    x = rng.uniform(-0.5, 0.5, size=(50, 3))
    R = matrix_from_euler(rng.uniform(-1, 1, size=(50, 3)))
    kin = pulley_kinematics(x, R, a, z, r, p)
    ok = kin.status == REGULAR
    assert ok.mean() > 0.95
    b = x[:, None] + np.einsum("nij,mj->nmi", R, p)
    w = b - a
    across = w - (w * z).sum(-1, keepdims=True) * z
    k = across / np.linalg.norm(across, axis=-1, keepdims=True)
    M = a + r[:, None] * k  # the pulley's centre
    C, u = kin.exits_C, kin.units
    np.testing.assert_allclose(np.linalg.norm(C - M, axis=-1)[ok], np.broadcast_to(r, ok.shape)[ok], atol=1e-14)
    np.testing.assert_allclose(np.linalg.norm(u, axis=-1)[ok], 1.0, atol=1e-14)
    # tangent: perpendicular to the radius at C
    assert np.abs((u * (C - M)).sum(-1))[ok].max() < 1e-14
    # in the plane of z and b - a (the pulley's plane), as is C
    normal = np.cross(z, w)
    normal /= np.linalg.norm(normal, axis=-1, keepdims=True)
    assert np.abs((u * normal).sum(-1))[ok].max() < 1e-14
    assert np.abs(((C - a) * normal).sum(-1))[ok].max() < 1e-15
    # the free span runs from b along u to C
    np.testing.assert_allclose((b + kin.free_lengths[..., None] * u)[ok], C[ok], atol=1e-13)
    # the moment part of J~ is (R p) x u
    np.testing.assert_allclose(kin.J_tilde[..., 3:], np.cross(b - x[:, None], u), atol=1e-14)


# ------------------------------------------------------------------------- degenerate


def test_anchors_on_the_axis_or_inside_the_pulley_are_flagged_with_nans():
    z = np.array([0.0, 0.0, -1.0])
    M = np.array([R25, 0.0, 0.0])
    cases = [((0.0, 0.0, -0.7), ON_AXIS),  # on the axis ahead
             ((0.0, 0.0, 0.3), ON_AXIS),  # on the axis behind
             ((0.0, 0.0, 0.0), ON_AXIS),  # at a
             ((1e-14, 0.0, -0.7), ON_AXIS),  # k within round-off
             (tuple(M + [0.5 * R25, 0, 0.3 * R25]), INSIDE),
             (tuple(M), INSIDE),
             ((2 * R25, 0.0, 0.0), INSIDE),  # on the rim
             ((np.nan, 0.0, 0.0), INVALID)]
    for b, code in cases:
        kin = _one(b, z=z)
        assert kin.status[0, 0] == code, b
        for f in (kin.lengths, kin.free_lengths, kin.wrap_angles, kin.exits_C, kin.J_tilde):
            assert np.isnan(f).all(), (b, f)
    # just off the axis and just outside the rim are regular
    assert _one((1e-6, 0.0, -0.7)).status[0, 0] == REGULAR
    assert _one((2 * R25 + 1e-9, 0.0, 0.0)).status[0, 0] == REGULAR
    # radius 0: on the axis is the point model's straight cable; at a, its zero length
    kin = _one((0.0, 0.0, 0.3), r=0.0)
    assert kin.status[0, 0] == REGULAR and kin.lengths[0, 0] == 0.3 and kin.wrap_angles[0, 0] == np.pi
    kin = _one((0.0, 0.0, 0.0), r=0.0)
    assert kin.status[0, 0] == ON_AXIS and kin.lengths[0, 0] == 0.0 and np.isnan(kin.J_tilde).all()


def test_step_function_reports_the_first_flagged_cable_and_leaves_the_others_right():
    a = np.zeros((3, 3))
    z = np.tile([0.0, 0.0, -1.0], (3, 1))
    r = np.full(3, R25)
    p = np.array([[0.5, 0, 0], [0.0, 0, -0.7], [0.01, 0, 0]])  # cable 1 on its axis, 2 inside
    L, J, C, B, F = np.empty(3), np.empty((3, 6)), np.empty((3, 3)), np.empty(3), np.empty(3)
    S = np.empty(3, dtype=np.int64)
    assert pulleys_step(np.zeros(3), np.eye(3), a, z, r, p, L, J, C, B, F, S) == ON_AXIS
    assert S.tolist() == [REGULAR, ON_AXIS, INSIDE]
    assert L[0] == pytest.approx(R25 * (np.pi / 2 + np.arcsin(1 / 19)) + np.sqrt(0.225), abs=1e-14)
    assert np.isnan(L[1:]).all() and np.isnan(J[1:]).all() and np.isfinite(J[0]).all()
    assert pulleys_step(np.zeros(3), np.eye(3), a[:1], z[:1], r[:1], p[:1], L, J, C, B) == REGULAR
    assert pulleys_step.targetoptions.get("_nrt") is False  # cannot allocate


def test_bad_arguments_are_refused():
    x, R = np.zeros((1, 3)), np.eye(3)[None]
    one = np.array([[1.0, 0, 0]])
    with pytest.raises(ValueError, match="unit"):
        pulley_kinematics(x, R, one, 2 * one, [R25], one)
    with pytest.raises(ValueError, match=">= 0"):
        pulley_kinematics(x, R, one, one, [-R25], one)
    with pytest.raises(ValueError, match="n_cables"):
        pulley_kinematics(x, R, one, np.tile(one, (2, 1)), [R25], one)


# -------------------- formerly tests/test_pulleys_model.py

"""Pulleys through the whole chain (issue 14, item 1): the planner's cable lengths and J~ over
swivelling pulleys, the same in the controller and the own plant, and MuJoCo's own tendon
wrapping agreeing with them: the geometry checked by an independent engine."""

import numpy as np
import pytest

import marinecdpr
from marinecdpr.errors import ScenarioError
from marinecdpr.prototype.simulation import simulate

from conftest import make_scenario
from test_tension import EXAMPLES

RADIUS = 0.025
AXES = ([0.0, 0.0, -1.0], [0.0, 0.0, -1.0], [0.0, 0.0, 1.0], [0.0, 0.0, 1.0])  # top cables come down, bottom up


def with_pulleys(data, radius=RADIUS, axes=AXES):
    for cable, z in zip(data["robot"]["cables"], axes):
        cable["pulley_radius_m"] = radius
        cable["pulley_axis"] = z


@pytest.fixture(scope="module")
def paper_pulleys():
    sc = make_scenario(with_pulleys)
    return sc, marinecdpr.plan(sc)


def test_mujocos_wrapped_tendons_are_the_planners_lengths(paper_pulleys):
    """At poses along the plan MuJoCo's tendon over its cylinder, less the inlet, is the
    planner's r beta + l_f to 1e-12 m; the point model's is millimetres shorter."""
    import mujoco

    from marinecdpr.prototype.mujoco_model import build_model

    sc, plan = paper_pulleys
    mm = build_model(sc)
    data = mujoco.MjData(mm.model)
    point = marinecdpr.plan(marinecdpr.load_scenario("paper"))
    for k in range(0, plan.n_steps, 1500):
        data.qpos[mm.platform_qpos] = plan.pose[k, [0, 2, 4]]
        mujoco.mj_forward(mm.model, data)
        np.testing.assert_allclose(data.ten_length - mm.tendon_offset, plan.lengths[k], rtol=0, atol=1e-12)
        assert (plan.lengths[k] - point.lengths[k]).max() > 3e-3  # some cable bends by millimetres


def test_the_paper_with_pulleys_flies_open_loop_on_mujoco(paper_pulleys):
    """Planner and engine agree on the geometry: open loop within 1e-3 m (issue 14), in fact
    within a micrometre; the point-model plan flown on the same pulleys leaves it by more."""
    sc, plan = paper_pulleys
    res = simulate(sc, run="open_loop", plant="mujoco", reference=plan, n_steps=3000)
    assert np.abs(res.pose_error[:, :3]).max() < 1e-6
    np.testing.assert_allclose(res.lengths, res.lengths_planned, rtol=0, atol=1e-6)
    point_plan = marinecdpr.plan(marinecdpr.load_scenario("paper"))
    assert np.abs(point_plan.tensions - plan.tensions).max() > 5.0  # N: the pulleys change the tensions


def test_the_own_plant_and_the_controller_use_the_pulleys(paper_pulleys):
    sc, plan = paper_pulleys
    for run in ("open_loop", "closed_loop"):
        res = simulate(sc, run=run, plant="own", reference=plan, n_steps=2000)
        assert np.abs(res.pose_error[:, :3]).max() < 1e-6, run


def test_a_spatial_robots_pulleys_on_the_own_plant():
    """spatial_cube8 with pulleys whose axes point at the frame's centre: the closed loop holds it."""
    def edit(data):
        for cable in data["robot"]["cables"]:
            a = np.array(cable["frame_anchor_m"])
            z = (np.array([1.0, 1.0, 1.0]) - a) / np.linalg.norm(np.array([1.0, 1.0, 1.0]) - a)
            cable["pulley_radius_m"] = 0.02
            cable["pulley_axis"] = z.tolist()

    import tomllib

    from marinecdpr.scenario.loading import scenario_from_dict

    data = tomllib.loads((EXAMPLES / "spatial_cube8.toml").read_text())
    edit(data)
    sc = scenario_from_dict(data, source="test")
    res = simulate(sc, run="closed_loop", plant="own", n_steps=1000)
    assert np.abs(res.pose_error[:, :3]).max() < 1e-5
    with pytest.raises(ScenarioError, match="pulleys of planar robots only"):
        simulate(sc, run="closed_loop", plant="mujoco", n_steps=10)


@pytest.mark.parametrize("edit, message", [
    (lambda c: c.update(pulley_radius_m=0.02), "pulley_axis: missing"),
    (lambda c: c.update(pulley_radius_m=0.02, pulley_axis=[0.0, 0.0, 2.0]), "must be a unit vector"),
    (lambda c: c.update(pulley_axis=[0.0, 0.0, 1.0]), "given without pulley_radius_m"),
    (lambda c: c.update(pulley_radius_m=0.02, pulley_axis=[0.0, 1.0, 0.0]), "x-z plane"),
    (lambda c: c.update(pulley_radius_m=-0.02, pulley_axis=[0.0, 0.0, 1.0]), "pulley_radius_m"),
])
def test_pulley_keys_are_checked(edit, message):
    with pytest.raises(ScenarioError, match=message):
        make_scenario(lambda d: edit(d["robot"]["cables"][0]))


def test_encoders_over_pulleys_fly_as_a_pose_sensor():
    """The closed loop with its pose from the encoders (forward kinematics over the pulleys)
    moves the platform as the one with a pose sensor, to 1e-9 m, on both plants."""
    def edit(source):
        return lambda d: (with_pulleys(d), d.setdefault("simulation", {}).update(sensors={"pose_from": source}))

    for plant in ("own", "mujoco"):
        by_sensor = simulate(make_scenario(edit("sensor")), run="closed_loop", plant=plant, n_steps=300)
        by_encoders = simulate(make_scenario(edit("encoders")), run="closed_loop", plant=plant, n_steps=300)
        np.testing.assert_allclose(by_encoders.pose, by_sensor.pose, rtol=0, atol=1e-9)
