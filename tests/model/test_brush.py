"""The brush's loads on the platform (marinecdpr.model.brush): friction, normal force, jet,
disc moment, moment about P, against hand-worked numbers and a slow numpy reference."""

import numpy as np
import pytest

from marinecdpr.geometry.rotations import matrix_from_euler
from marinecdpr.model.brush import (
    BrushParams,
    brush_params,
    brush_velocity,
    brush_velocity_step,
    brush_wrench,
    brush_wrench_step,
)

Y = np.array([0.0, 1.0, 0.0])
RZ90 = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])


def step(v, n, F_n, R, p):
    f, m = np.empty(3), np.empty(3)
    brush_wrench_step(np.asarray(v, float), np.asarray(n, float), float(F_n), np.asarray(R, float), p, f, m)
    return f, m


def friction(v, n, F_n, p):
    """The tangential force alone: pair, no offset, no jet."""
    q = p._replace(kind=1, jet_N=0.0, offset_P=np.zeros(3))
    f, _ = step(v, n, F_n, np.eye(3), q)
    return f - F_n * np.asarray(n)


def unit(rng, size=None):
    a = rng.normal(size=(size, 3) if size else 3)
    return a / np.linalg.norm(a, axis=-1, keepdims=True)


def random_inputs(rng, n):
    v = rng.normal(scale=0.5, size=(n, 3))
    v[::7] *= 1e-4  # some steps in the smoothed band
    v[3] = 0.0
    nC = unit(rng, n)
    Fn = rng.uniform(0.0, 300.0, n)
    Fn[5] = 0.0
    R = matrix_from_euler(rng.uniform(-np.pi, np.pi, size=(n, 3)))
    return v, nC, Fn, np.ascontiguousarray(R)


def reference(v, nC, Fn, R, p):
    """The module's equations, the slow obvious way (one step at a time, numpy)."""
    f, m = np.empty_like(v), np.empty_like(v)
    for k in range(len(v)):
        n = nC[k]
        vt = v[k] - np.dot(v[k], n) * n
        f_fric = -p.mu * Fn[k] * vt / np.sqrt(np.dot(vt, vt) + p.v_smooth_m_s**2)
        f[k] = f_fric + Fn[k] * n + p.jet_N * n
        m_disc = -p.spin * 2.0 / 3.0 * p.mu * Fn[k] * p.radius_m * n if p.kind == 0 else np.zeros(3)
        m[k] = np.cross(R[k] @ p.offset_P, f[k]) + m_disc
    return f, m


PARAMS = [
    brush_params(0.45, 0.2, kind=0, spin=1, v_smooth_m_s=1e-3, jet_N=35.0, offset_P=(0.3, -0.25, 0.1)),
    brush_params(0.3, 0.15, kind=0, spin=-1, v_smooth_m_s=1e-2, jet_N=-10.0, offset_P=(-0.1, 0.4, 0.0)),
    brush_params(0.6, 0.25, kind=1, spin=1, v_smooth_m_s=1e-3, jet_N=0.0, offset_P=(0.0, 0.0, -0.35)),
]


# ----------------------------------------------------------------------------- friction


def test_friction_opposes_the_sliding_and_is_mu_Fn_when_fast():
    rng = np.random.default_rng(11)
    p = brush_params(0.45, 0.2, v_smooth_m_s=1e-7)  # |v_t| >= 2e6 v_smooth
    for _ in range(50):
        n = unit(rng)
        vt = np.cross(n, unit(rng))  # tangential
        vt *= rng.uniform(0.2, 2.0) / np.linalg.norm(vt)
        F_n = rng.uniform(10.0, 400.0)
        ft = friction(vt, n, F_n, p)
        direction = vt / np.linalg.norm(vt)
        assert np.dot(ft, direction) == pytest.approx(-0.45 * F_n, abs=1e-9)
        assert np.linalg.norm(ft) == pytest.approx(0.45 * F_n, abs=1e-9)
        assert np.linalg.norm(ft - np.dot(ft, direction) * direction) < 1e-12
        assert abs(np.dot(ft, n)) < 1e-12


def test_friction_goes_smoothly_through_zero_with_slope_mu_Fn_over_v_smooth():
    p = brush_params(0.4, 0.2, v_smooth_m_s=1e-3)
    F_n, n, t = 250.0, Y, np.array([0.6, 0.0, 0.8])
    assert np.all(friction(np.zeros(3), n, F_n, p) == 0.0)
    h = 1e-9
    slope = (friction(h * t, n, F_n, p) - friction(-h * t, n, F_n, p)) / (2 * h)
    # d f / d v at 0 = -mu F_n / v_smooth along the sliding direction: 0.4 * 250 / 1e-3 = 1e5
    np.testing.assert_allclose(slope, -1e5 * t, rtol=1e-6, atol=1e-6)
    # a sweep through zero: continuous and monotone, the smoothed law exactly
    s = np.linspace(-0.01, 0.01, 2001)
    fs = np.array([np.dot(friction(si * t, n, F_n, p), t) for si in s])
    np.testing.assert_allclose(fs, -100.0 * s / np.sqrt(s**2 + 1e-6), rtol=1e-12, atol=1e-12)
    assert np.all(np.diff(fs) < 0.0)
    assert np.max(np.abs(np.diff(fs))) < 1e5 * (s[1] - s[0]) * (1 + 1e-9)


def test_normal_velocity_does_not_change_the_friction():
    rng = np.random.default_rng(12)
    for p in PARAMS:
        for _ in range(20):
            n, v = unit(rng), rng.normal(size=3)
            R = matrix_from_euler(rng.uniform(-3, 3, 3))
            f0, m0 = step(v, n, 120.0, R, p)
            for a in (-1.0, 0.3, 7.0):
                f1, m1 = step(v + a * n, n, 120.0, R, p)
                np.testing.assert_allclose(f1, f0, rtol=0, atol=1e-12)
                np.testing.assert_allclose(m1, m0, rtol=0, atol=1e-12)
        # a purely normal velocity: no friction at all
        f, _ = step(3.0 * Y, Y, 120.0, np.eye(3), p._replace(offset_P=np.zeros(3)))
        np.testing.assert_allclose(f, (120.0 + p.jet_N) * Y, rtol=0, atol=1e-12)


def test_normal_force_and_jet_push_along_plus_n_away_from_the_hull():
    p = brush_params(0.4, 0.2, kind=1, jet_N=30.0)
    f, m = step(np.zeros(3), Y, 100.0, np.eye(3), p)
    np.testing.assert_array_equal(f, [0.0, 130.0, 0.0])
    np.testing.assert_array_equal(m, 0.0)
    # the jet does not load the contact: friction stays mu F_n = 40 N
    fast = np.array([1.0, 0.0, 0.0])
    f_jet, _ = step(fast, Y, 100.0, np.eye(3), p)
    f_none, _ = step(fast, Y, 100.0, np.eye(3), p._replace(jet_N=0.0))
    np.testing.assert_allclose(f_jet - f_none, [0.0, 30.0, 0.0], atol=1e-12)
    assert f_jet[0] == pytest.approx(-40.0 / np.sqrt(1.0 + 1e-6), abs=1e-12)
    # a negative jet presses the brush onto the hull
    f_onto, _ = step(np.zeros(3), Y, 100.0, np.eye(3), p._replace(jet_N=-100.0))
    np.testing.assert_array_equal(f_onto, 0.0)


# ------------------------------------------------------------------------------- moments


@pytest.mark.parametrize("spin", [1, -1])
def test_disc_moment_is_two_thirds_mu_Fn_R_about_the_normal_with_the_spin_sign(spin):
    # (2/3) 0.4 * 150 N * 0.2 m = 8 N m, opposing the spin
    p = brush_params(0.4, 0.2, kind=0, spin=spin)
    for v in (np.zeros(3), np.array([0.3, 0.0, -0.2])):
        _, m = step(v, Y, 150.0, np.eye(3), p)
        np.testing.assert_allclose(m, [0.0, -spin * 8.0, 0.0], rtol=0, atol=1e-12)
    n = np.array([0.0, 0.6, 0.8])
    _, m = step(np.zeros(3), n, 150.0, RZ90, p)
    np.testing.assert_allclose(m, -spin * 8.0 * n, rtol=0, atol=1e-12)


def test_counter_rotating_pair_gives_no_moment():
    rng = np.random.default_rng(13)
    p = brush_params(0.6, 0.3, kind=1, spin=1, jet_N=25.0)
    for _ in range(20):
        _, m = step(rng.normal(size=3), unit(rng), rng.uniform(0, 300), matrix_from_euler(rng.normal(size=3)), p)
        np.testing.assert_array_equal(m, 0.0)


def test_moment_about_P_of_an_offset_brush_by_hand():
    # R_PC = Rz(90 deg) takes offset_P = (-0.2, 0, 0.1) to r = (0, -0.2, 0.1) in C: the brush
    # 0.2 m from P towards the hull (n = +y). v_rel = (0.5, 0.3, 0): its normal part 0.3 is
    # dropped, v_t = (0.5, 0, 0). mu F_n = 0.4 * 100 = 40 N, so
    #   f = (fx, F_n + jet, 0) = (fx, 120, 0),  fx = -40 * 0.5 / sqrt(0.25 + 1e-6) ~ -40
    #   r x f = (ry fz - rz fy, rz fx - rx fz, rx fy - ry fx) = (-12, 0.1 fx, 0.2 fx)
    #   disc: -(2/3) 0.4 * 100 * 0.15 * (0, 1, 0) = (0, -4, 0)
    #   m = (-12, 0.1 fx - 4, 0.2 fx) ~ (-12, -8, -8)
    p = brush_params(0.4, 0.15, kind=0, spin=1, v_smooth_m_s=1e-3, jet_N=20.0, offset_P=(-0.2, 0.0, 0.1))
    fx = -40.0 * 0.5 / np.sqrt(0.25 + 1e-6)
    f, m = step([0.5, 0.3, 0.0], Y, 100.0, RZ90, p)
    np.testing.assert_allclose(f, [fx, 120.0, 0.0], rtol=0, atol=1e-12)
    np.testing.assert_allclose(m, [-12.0, 0.1 * fx - 4.0, 0.2 * fx], rtol=0, atol=1e-12)
    np.testing.assert_allclose(m, [-12.0, -8.0, -8.0], atol=1e-4)
    # the pair: only r x f is left
    _, m_pair = step([0.5, 0.3, 0.0], Y, 100.0, RZ90, p._replace(kind=1))
    np.testing.assert_allclose(m_pair, [-12.0, 0.1 * fx, 0.2 * fx], rtol=0, atol=1e-12)


# ---------------------------------------------------------------------- over time series


@pytest.mark.parametrize("p", PARAMS)
def test_series_equals_the_step_function_step_by_step(p):
    rng = np.random.default_rng(14)
    v, nC, Fn, R = random_inputs(rng, 400)
    f, m = brush_wrench(v, nC, Fn, R, p)
    assert f.shape == m.shape == (400, 3)
    for k in range(400):
        fk, mk = step(v[k], nC[k], Fn[k], R[k], p)
        np.testing.assert_allclose(f[k], fk, rtol=0, atol=1e-12)
        np.testing.assert_allclose(m[k], mk, rtol=0, atol=1e-12)


@pytest.mark.parametrize("p", PARAMS)
def test_series_agrees_with_a_slow_numpy_reference(p):
    rng = np.random.default_rng(15)
    v, nC, Fn, R = random_inputs(rng, 500)
    f, m = brush_wrench(v, nC, Fn, R, p)
    f_ref, m_ref = reference(v, nC, Fn, R, p)
    np.testing.assert_allclose(f, f_ref, rtol=0, atol=1e-12)
    np.testing.assert_allclose(m, m_ref, rtol=0, atol=1e-12)


def test_series_broadcasts_constant_normal_force_and_orientation():
    rng = np.random.default_rng(16)
    v = rng.normal(size=(50, 3))
    n = np.array([0.0, 0.6, -0.8])
    R = matrix_from_euler(np.array([0.1, -0.4, 0.7]))
    p = PARAMS[0]
    f, m = brush_wrench(v, n, 80.0, R, p)
    f_full, m_full = brush_wrench(v, np.tile(n, (50, 1)), np.full(50, 80.0), np.tile(R, (50, 1, 1)), p)
    np.testing.assert_array_equal(f, f_full)
    np.testing.assert_array_equal(m, m_full)


def test_series_accepts_unconverted_params_and_rejects_bad_input():
    v, n = np.array([[0.1, 0.0, 0.0]]), np.array([[0.0, 1.0, 0.0]])
    raw = BrushParams(0.4, 0.2, 0, 1, 1e-3, 0, [0.0, 0.0, 0.0])  # ints and a list: converted
    f, m = brush_wrench(v, n, 10.0, np.eye(3), raw)
    np.testing.assert_allclose(m, [[0.0, -(2 / 3) * 0.4 * 10.0 * 0.2, 0.0]], atol=1e-12)
    with pytest.raises(ValueError, match="F_n"):
        brush_wrench(v, n, -1.0, np.eye(3), raw)
    with pytest.raises(ValueError, match="unit"):
        brush_wrench(v, 2 * n, 1.0, np.eye(3), raw)
    with pytest.raises(ValueError, match="shape"):
        brush_wrench(v, n, np.ones(2), np.eye(3), raw)
    for bad in (dict(mu=-0.1), dict(kind=2), dict(spin=0), dict(v_smooth_m_s=0.0),
                dict(radius_m=np.nan), dict(offset_P=(1.0, 2.0))):
        args = dict(mu=0.4, radius_m=0.2) | bad
        with pytest.raises(ValueError):
            brush_params(**args)


# ------------------------------------------------------------------------ brush velocity


def test_brush_velocity_by_hand_and_against_numpy():
    # omega = (0, 0, 2) rad/s, r = Rz(90) (0.5, 0, 0) = (0, 0.5, 0): omega x r = (-1, 0, 0)
    v = brush_velocity(np.array([[0.1, 0.2, 0.3]]), np.array([[0.0, 0.0, 2.0]]), RZ90, (0.5, 0.0, 0.0))
    np.testing.assert_allclose(v, [[-0.9, 0.2, 0.3]], rtol=0, atol=1e-15)
    rng = np.random.default_rng(17)
    n = 300
    vP, w = rng.normal(size=(n, 3)), rng.normal(size=(n, 3))
    R = matrix_from_euler(rng.uniform(-np.pi, np.pi, size=(n, 3)))
    off = np.array([0.3, -0.2, 0.45])
    got = brush_velocity(vP, w, R, off)
    ref = np.array([vP[k] + np.cross(w[k], R[k] @ off) for k in range(n)])
    np.testing.assert_allclose(got, ref, rtol=0, atol=1e-12)
    one = np.empty(3)
    brush_velocity_step(vP[7], w[7], np.ascontiguousarray(R[7]), off, one)
    np.testing.assert_allclose(one, ref[7], rtol=0, atol=1e-12)


def test_velocity_feeds_the_wrench_consistently():
    # a platform spinning about the hull normal over a fixed point: the brush slides
    # tangentially at |omega| |r|, and the friction opposes that
    off = np.array([0.4, 0.0, 0.0])
    v = brush_velocity(np.zeros((1, 3)), np.array([[0.0, 1.0, 0.0]]), np.eye(3), off)
    np.testing.assert_allclose(v, [[0.0, 0.0, -0.4]], atol=1e-15)
    p = brush_params(0.5, 0.1, kind=1, v_smooth_m_s=1e-9, offset_P=off)
    f, m = brush_wrench(v, Y, 100.0, np.eye(3), p)
    np.testing.assert_allclose(f, [[0.0, 100.0, 50.0]], atol=1e-9)
    # r x f = (0.4, 0, 0) x (0, 100, 50) = (0, -20, 40)
    np.testing.assert_allclose(m, [[0.0, -20.0, 40.0]], atol=1e-9)
