"""The elastic catenary (Irvine's equations, :mod:`marinecdpr.model.catenary`) against an
independent integration of the cable's ODE, its limits (inextensible, weightless), hand
numbers for the paper robot's cable, the inverses' round trips and finite differences.

Cable data: a 3 mm steel wire rope weighs about 0.035 kg/m, w = 0.35 N/m in air (about 0.30
N/m submerged); EA = 1e5 N as in the brief (a 3 mm 7x19 steel rope is nearer 4e5 N; the
sag hardly depends on it). The paper robot's frame is about 1.9 x 1.4 m: spans of ~1.2 m.
"""

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq, minimize_scalar, root

from marinecdpr.model.catenary import (CONVERGED, IMPOSSIBLE, N_OUT, OUT_DIR_A, OUT_DIR_B, OUT_H, OUT_L0, OUT_TA,
                                       OUT_TB, OUT_VA, OUT_VB, SLACK, cable_force_3d, catenary_arc_length,
                                       catenary_forces, catenary_geometry, catenary_length_from_end_force,
                                       catenary_sag, catenary_series, catenary_stiffness,
                                       catenary_unstretched_length)

W_STEEL = 0.35  # N/m, 3 mm steel rope in air
EA_ROPE = 1e5  # N

# (h, v, L0, w, EA): B relative to A (m), unstretched length (m), N/m, N
CASES = {
    "paper taut level": (1.2, 0.0, 1.1988, W_STEEL, EA_ROPE),  # ~100 N
    "paper platform below": (0.9, -0.8, 1.2028, W_STEEL, EA_ROPE),
    "slack, lowest point inside": (1.0, 0.3, 2.0, W_STEEL, EA_ROPE),  # V_A < 0 < V_B
    "heavy steep 10 m": (3.0, -9.0, 9.6, 5.0, 2e6),
    "inextensible 10 m": (10.0, 2.0, 11.0, W_STEEL, np.inf),
}


def solve(h, v, L0, w, EA, guess=None):
    out = np.empty(N_OUT)
    status = catenary_forces(h, v, L0, w, EA, np.full(2, np.nan) if guess is None else np.asarray(guess, float),
                             out)
    return status, out


def integrate(H, V_A, L0, w, EA, dense=False):
    """The elastic catenary's ODE in the unstretched arc length s from A: V = V_A + w s,
    T = |(H, V)|, dx/ds = (H/T)(1 + T/EA), dz/ds = (V/T)(1 + T/EA), and the stretched length
    d(arc)/ds = 1 + T/EA. Returns the ODE solution (y = x, z, arc)."""

    def rhs(s, y):
        V = V_A + w * s
        T = np.hypot(H, V)
        stretch = 1.0 + T / EA
        return [H / T * stretch, V / T * stretch, stretch]

    return solve_ivp(rhs, (0.0, L0), [0.0, 0.0, 0.0], method="DOP853", rtol=1e-13, atol=1e-15,
                     dense_output=dense)


# ------------------------------------------------------------- against the cable's ODE


@pytest.mark.parametrize("name", list(CASES))
def test_end_point_of_the_integrated_cable_is_B(name):
    h, v, L0, w, EA = CASES[name]
    status, out = solve(h, v, L0, w, EA)
    assert status == CONVERGED
    H, V_B, V_A = out[OUT_H], out[OUT_VB], out[OUT_VA]
    assert V_A - V_B == pytest.approx(-w * L0, rel=1e-12)
    if name.startswith("slack"):
        assert V_A < 0 < V_B and V_B / H > 1  # its lowest point well inside the span
    sol = integrate(H, V_A, L0, w, EA, dense=True)
    x, z, arc = sol.y[:, -1]
    assert abs(x - h) < 1e-9 and abs(z - v) < 1e-9
    # stretched length and sag from the integrated curve
    assert catenary_arc_length(H, V_B, L0, w, EA) == pytest.approx(arc, abs=1e-9)
    if h > 0:
        below = minimize_scalar(lambda s: -(v * sol.sol(s)[0] / h - sol.sol(s)[1]), bounds=(0, L0),
                                method="bounded", options={"xatol": 1e-10})
        assert catenary_sag(H, V_B, L0, w, EA) == pytest.approx(-below.fun, abs=1e-9)
    # tangents at the ends are the ODE's
    for s, col in ((0.0, OUT_DIR_A), (L0, OUT_DIR_B)):
        V = V_A + w * s
        assert out[col:col + 2] == pytest.approx(np.array([H, V]) / np.hypot(H, V), abs=1e-14)


@pytest.mark.parametrize("name", list(CASES))
def test_shooting_on_the_ode_finds_the_same_forces(name):
    """Independent of Irvine's closed form: shoot (H, V_A) through the ODE to hit B."""
    h, v, L0, w, EA = CASES[name]
    _, out = solve(h, v, L0, w, EA)
    H, V_A = out[OUT_H], out[OUT_VA]
    scale = np.hypot(H, V_A)

    def miss(p):
        y = integrate(p[0] * scale, p[1] * scale, L0, w, EA).y[:, -1]
        return [y[0] - h, y[1] - v]

    shot = root(miss, [1.03 * H / scale, V_A / scale + 0.02], method="hybr", options={"xtol": 1e-13})
    # hybr may stop short of xtol 1e-13 once the ODE's round-off stalls it ("not making good
    # progress", scipy 1.17 on "paper platform below", 4e-16 m off B): judge the shot by its miss
    assert np.abs(miss(shot.x)).max() < 1e-12
    assert shot.x * scale == pytest.approx([H, V_A], rel=1e-8, abs=1e-8 * scale)


# ---------------------------------------------------------------------------- limits


@pytest.mark.parametrize("h, v, L0, w", [(1.2, 0.0, 1.5, 0.35), (10.0, 2.0, 11.0, 0.35), (4.0, -3.0, 9.0, 2.0),
                                         (1.0, 0.5, 1.1181, 0.35)])
def test_stiff_cable_is_the_inextensible_catenary(h, v, L0, w):
    """EA = 1e15 N (and inf) against the classic closed form: sqrt(L^2 - v^2) = (2H/w)
    sinh(w h/(2H)), V_B = H sinh(w h/(2H) + atanh(v/L))."""
    H = brentq(lambda H: 2 * H / w * np.sinh(w * h / (2 * H)) - np.sqrt(L0**2 - v**2), 1e-2 * w * h, 1e9, xtol=1e-14,
               rtol=1e-15)
    V_B = H * np.sinh(w * h / (2 * H) + np.arctanh(v / L0))
    for EA in (1e15, np.inf):
        status, out = solve(h, v, L0, w, EA)
        assert status == CONVERGED
        assert out[OUT_H] == pytest.approx(H, rel=1e-9)
        assert out[OUT_VB] == pytest.approx(V_B, rel=1e-9, abs=1e-9 * H)
    assert catenary_arc_length(out[OUT_H], out[OUT_VB], L0, w, np.inf) == L0


@pytest.mark.parametrize("h, v, L0", [(1.2, 0.0, 1.1988), (0.9, -0.8, 1.2028), (3.0, 4.0, 4.99), (0.01, -2.0, 1.9)])
@pytest.mark.parametrize("w", [1e-12, 0.0])
def test_weightless_cable_is_the_straight_elastic_cable(h, v, L0, w):
    d = np.hypot(h, v)
    T = EA_ROPE * (d - L0) / L0
    status, out = solve(h, v, L0, w, EA_ROPE)
    assert status == CONVERGED
    for col in (OUT_TA, OUT_TB):
        assert out[col] == pytest.approx(T, rel=1e-6)
    for col in (OUT_DIR_A, OUT_DIR_B):
        assert out[col:col + 2] == pytest.approx([h / d, v / d], rel=1e-6, abs=1e-9)
    assert catenary_sag(out[OUT_H], out[OUT_VB], L0, w, EA_ROPE) < 1e-12
    assert catenary_arc_length(out[OUT_H], out[OUT_VB], L0, w, EA_ROPE) == pytest.approx(d, rel=1e-12)


def test_weightless_slack_cable_carries_nothing():
    status, out = solve(1.0, 0.0, 1.2, 0.0, EA_ROPE)
    assert status == SLACK and out[OUT_TA] == out[OUT_TB] == 0.0


# ---------------------------------------------------------------- the paper robot's cable


def test_taut_level_cable_by_hand():
    """1.2 m level span at T = 100 N, 3 mm steel rope: the parabola's sag (w L0) h/(8H) (the
    cable's weight over the span; w h^2/(8H) = 0.63 mm less the 0.1 % stretch), end slopes
    +-w L0/(2H), equal tensions at the ends."""
    h, T = 1.2, 100.0
    out, K = np.empty(N_OUT), np.empty((2, 2))
    assert catenary_unstretched_length(h, 0.0, T, W_STEEL, EA_ROPE, out, K) == CONVERGED
    L0 = out[OUT_L0]
    H, V_B = out[OUT_H], out[OUT_VB]
    assert L0 == pytest.approx(h / (1 + T / EA_ROPE), rel=1e-6)  # stretch 1.2 mm; the sag needs 1 um more
    assert V_B == pytest.approx(W_STEEL * L0 / 2, rel=1e-12)  # symmetric: each end carries half the weight
    assert out[OUT_TA] == pytest.approx(out[OUT_TB], rel=1e-14)
    sag = catenary_sag(H, V_B, L0, W_STEEL, EA_ROPE)
    assert sag == pytest.approx(W_STEEL * L0 * h / (8 * H), rel=1e-4)
    assert 0.62e-3 < sag < 0.64e-3
    assert np.degrees(np.arctan2(V_B, H)) == pytest.approx(np.degrees(W_STEEL * L0 / (2 * H)), rel=1e-4)  # 0.12 deg


def test_taut_inclined_cable_by_hand():
    """Platform 0.5 m below the frame anchor, 1.2 m away, 100 N at the platform: the winch
    carries T_A = T_B + w (|v| + L0 V_m/EA) (T_B - T_A = w times the unstretched cable's
    rise), V_A - V_B = -w L0, sag ~ (w L0) h/(8H) (the parabola under the cable's weight)."""
    h, v, T = 1.2, -0.5, 100.0
    out, K = np.empty(N_OUT), np.empty((2, 2))
    assert catenary_unstretched_length(h, v, T, W_STEEL, EA_ROPE, out, K) == CONVERGED
    L0, H, V_B, V_A = out[OUT_L0], out[OUT_H], out[OUT_VB], out[OUT_VA]
    assert out[OUT_TB] == pytest.approx(T, rel=1e-12)
    assert V_A - V_B == pytest.approx(-W_STEEL * L0, rel=1e-12)
    V_m = (V_A + V_B) / 2
    assert out[OUT_TB] - out[OUT_TA] == pytest.approx(W_STEEL * (v - L0 * V_m / EA_ROPE), rel=1e-10)
    assert out[OUT_TA] - out[OUT_TB] == pytest.approx(W_STEEL * 0.5, rel=2e-3)  # 0.175 N
    assert catenary_sag(H, V_B, L0, W_STEEL, EA_ROPE) == pytest.approx(W_STEEL * L0 * h / (8 * H), rel=1e-4)


# --------------------------------------------------------------------------- inverses


ROUND_TRIP = [(1.2, 0.0, 1.1988, W_STEEL, EA_ROPE), (0.9, -0.8, 1.2028, W_STEEL, EA_ROPE),
              (1.2, 0.5, 1.3001, W_STEEL, EA_ROPE), (10.0, -3.0, 10.45, W_STEEL, EA_ROPE),
              (10.0, 2.0, 10.3, W_STEEL, np.inf), (3.0, -9.0, 9.6, 5.0, 2e6), (0.05, -3.0, 2.998, W_STEEL, EA_ROPE)]


@pytest.mark.parametrize("h, v, L0, w, EA", ROUND_TRIP)
def test_length_for_a_tension_round_trip(h, v, L0, w, EA):
    status, out = solve(h, v, L0, w, EA)
    assert status == CONVERGED
    back, K = np.empty(N_OUT), np.empty((2, 2))
    assert catenary_unstretched_length(h, v, out[OUT_TB], w, EA, back, K) == CONVERGED
    assert back[OUT_L0] == pytest.approx(L0, rel=1e-10)
    assert back[:5] == pytest.approx(out[:5], rel=1e-10, abs=1e-10 * out[OUT_TB])
    # and forward again from the solved length
    assert solve(h, v, back[OUT_L0], w, EA)[1][OUT_TB] == pytest.approx(out[OUT_TB], rel=1e-10)


@pytest.mark.parametrize("h, v, L0, w, EA", ROUND_TRIP)
def test_length_from_end_force_round_trip(h, v, L0, w, EA):
    _, out = solve(h, v, L0, w, EA)
    status, L_back, v_back = catenary_length_from_end_force(h, out[OUT_H], out[OUT_VB], w, EA)
    assert status == CONVERGED
    assert L_back == pytest.approx(L0, rel=1e-10)
    assert v_back == pytest.approx(v, abs=1e-10 * (h + abs(v)))


def test_length_for_a_tension_takes_the_taut_branch():
    """Long cables hang deep and pull harder again: the shortest L0 is returned."""
    h, v, w, EA = 1.0, -0.5, W_STEEL, EA_ROPE
    _, deep = solve(h, v, 6.0, w, EA)
    out, K = np.empty(N_OUT), np.empty((2, 2))
    assert catenary_unstretched_length(h, v, deep[OUT_TB], w, EA, out, K) == CONVERGED
    assert out[OUT_TB] == pytest.approx(deep[OUT_TB], rel=1e-10)
    assert out[OUT_L0] < 1.2
    dH, dV = catenary_stiffness(out[OUT_H], out[OUT_VB], out[OUT_L0], w, EA, K)
    assert out[OUT_H] * dH + out[OUT_VB] * dV < 0  # paying out slackens it
    # below the least tension this geometry allows with this cable it is impossible
    assert catenary_unstretched_length(h, v, 1e-4, w, EA, out, K) == IMPOSSIBLE


# ------------------------------------------------------------------------- stiffness


@pytest.mark.parametrize("name", list(CASES))
def test_end_stiffness_against_finite_differences(name):
    h, v, L0, w, EA = CASES[name]
    _, out = solve(h, v, L0, w, EA)
    H, V_B = out[OUT_H], out[OUT_VB]
    K = np.empty((2, 2))
    dF_dL0 = np.array(catenary_stiffness(H, V_B, L0, w, EA, K))
    J = np.empty((2, 2))
    catenary_geometry(H, V_B, L0, w, EA, J)
    assert J[0, 1] == J[1, 0] and np.all(np.linalg.eigvalsh(J) > 0)  # a flexibility: symmetric, positive
    assert K @ J == pytest.approx(np.eye(2), abs=1e-12)
    d = np.hypot(h, v)
    step = 1e-6 * d
    K_fd = np.empty((2, 2))
    for j, (dh, dv) in enumerate(((step, 0.0), (0.0, step))):
        plus = solve(h + dh, v + dv, L0, w, EA, guess=(H, V_B))[1]
        minus = solve(h - dh, v - dv, L0, w, EA, guess=(H, V_B))[1]
        K_fd[:, j] = (plus[[OUT_H, OUT_VB]] - minus[[OUT_H, OUT_VB]]) / (2 * step)
    scale = np.linalg.norm(K)
    assert K_fd == pytest.approx(K, rel=1e-6, abs=1e-6 * scale)
    # entry by entry, against the geometric mean of the diagonal (the transverse stiffness of a
    # taut cable, ~H/L, is ~1e-3 of the axial one, EA/L)
    assert np.all(np.abs(K_fd - K) <= 1e-6 * np.sqrt(np.outer(np.diag(K), np.diag(K))))
    dL = 1e-6 * L0
    fd = (solve(h, v, L0 + dL, w, EA)[1][[OUT_H, OUT_VB]] - solve(h, v, L0 - dL, w, EA)[1][[OUT_H, OUT_VB]]) / (2 * dL)
    assert fd == pytest.approx(dF_dL0, rel=1e-6, abs=1e-6 * np.linalg.norm(dF_dL0))


# ------------------------------------------------------------- vertical and degenerate


def test_vertical_cable_hanging_from_the_frame():
    h, v, L0, w = 0.0, -2.0, 1.999, W_STEEL
    status, out = solve(h, v, L0, w, EA_ROPE)
    assert status == CONVERGED and out[OUT_H] == 0.0
    # v = -L0 (1 - V_m/EA)... : V_m = EA (v + L0)/L0, T_A = T_B + w L0
    assert (out[OUT_VA] + out[OUT_VB]) / 2 == pytest.approx(EA_ROPE * (v + L0) / L0, rel=1e-12)
    assert out[OUT_TA] - out[OUT_TB] == pytest.approx(w * L0, rel=1e-10)
    assert list(out[OUT_DIR_A:OUT_DIR_A + 2]) == [0.0, -1.0]
    back, K = np.empty(N_OUT), np.empty((2, 2))
    assert catenary_unstretched_length(h, v, out[OUT_TB], w, EA_ROPE, back, K) == CONVERGED
    assert back[OUT_L0] == pytest.approx(L0, rel=1e-10)


def test_vertical_cable_longer_than_the_drop_folds():
    status, out = solve(0.0, -1.0, 2.0, W_STEEL, EA_ROPE)
    assert status == SLACK
    assert out[OUT_VA] < 0 < out[OUT_VB]
    # the loop's bottom hangs (L0 - |v|)/2 below the lower end (plus the stretch)
    assert catenary_sag(out[OUT_H], out[OUT_VB], 2.0, W_STEEL, EA_ROPE) == pytest.approx(0.5, rel=1e-5)


@pytest.mark.parametrize("args", [(1.0, 0.0, 1.0, W_STEEL, np.inf), (1.0, 0.5, 1.0, W_STEEL, np.inf),
                                  (-1.0, 0.0, 2.0, W_STEEL, EA_ROPE), (1.0, 0.0, 0.0, W_STEEL, EA_ROPE),
                                  (1.0, np.nan, 2.0, W_STEEL, EA_ROPE), (1.0, 0.0, 2.0, -1.0, EA_ROPE),
                                  (1.0, 0.0, 2.0, W_STEEL, 0.0)])
def test_impossible_cables(args):
    status, out = solve(*args)
    assert status == IMPOSSIBLE and np.isnan(out[OUT_H])


def test_warm_start_from_out_itself():
    h, v, L0, w, EA = CASES["paper platform below"]
    _, cold = solve(h, v, L0, w, EA)
    out = cold.copy()
    out[OUT_H] *= 1.1
    assert catenary_forces(h, v, L0, w, EA, out[:2], out) == CONVERGED
    assert out[:5] == pytest.approx(cold[:5], rel=1e-13)
    bad_guess = np.array([-5.0, 1e30])  # unusable: ignored
    assert catenary_forces(h, v, L0, w, EA, bad_guess, out) == CONVERGED
    assert out[:5] == pytest.approx(cold[:5], rel=1e-13)


def test_converges_over_a_wide_range():
    """Spans 1 cm..1 km, slopes up to ~90 deg, L0 from 0.9 to 30 chords, w, EA over decades."""
    rng = np.random.default_rng(7)
    out, J = np.empty(N_OUT), np.empty((2, 2))
    n = 0
    for _ in range(3000):
        h = 10 ** rng.uniform(-2, 3)
        v = h * np.sinh(rng.uniform(-4, 4))
        d = np.hypot(h, v)
        EA = np.inf if rng.random() < 0.2 else 10 ** rng.uniform(3, 11)
        L0 = d * (1 + 10 ** rng.uniform(-8, 1.5)) if (EA == np.inf or rng.random() < 0.6) else d * (
            1 - 10 ** rng.uniform(-8, -1.5))
        w = 10 ** rng.uniform(-3, 2)
        status = catenary_forces(h, v, L0, w, EA, np.full(2, np.nan), out)
        if max(out[OUT_TA], out[OUT_TB]) > 0.05 * EA:  # strains above 5 %: outside Hooke's law
            continue
        n += 1
        assert status == CONVERGED, (h, v, L0, w, EA)
        hh, vv = catenary_geometry(out[OUT_H], out[OUT_VB], L0, w, EA, J)
        assert np.hypot(hh - h, vv - v) <= 1e-14 * (h + abs(v) + L0)
        assert out[10] <= 25
    assert n > 2500


# --------------------------------------------------------------------------- 3D, series


def test_force_on_the_platform_in_3d():
    a, b = np.array([0.3, -0.2, 2.0]), np.array([1.1, 0.4, 1.1])  # h = 1.0, v = -0.9
    L0 = 1.345
    force, out = np.empty(3), np.empty(N_OUT)
    assert cable_force_3d(a, b, L0, W_STEEL, EA_ROPE, np.full(2, np.nan), force, out) == CONVERGED
    h, v = np.hypot(*(b - a)[:2]), (b - a)[2]
    assert (h, v) == pytest.approx((1.0, -0.9), rel=1e-15)
    _, planar = solve(h, v, L0, W_STEEL, EA_ROPE)
    e_h = np.array([0.8, 0.6, 0.0])
    assert out == pytest.approx(planar, rel=1e-14)
    assert force == pytest.approx(-(planar[OUT_H] * e_h + planar[OUT_VB] * np.array([0, 0, 1.0])), rel=1e-14)
    frame = planar[OUT_H] * e_h + planar[OUT_VA] * np.array([0, 0, 1.0])  # the cable's pull on the frame anchor
    assert force + frame == pytest.approx([0, 0, -W_STEEL * L0], abs=1e-12)  # together: the cable's weight
    assert force @ (a - b) > 0 and force[2] > 0  # pulls the platform towards the frame, holds it up
    assert out[OUT_TA] == pytest.approx(np.linalg.norm(frame), rel=1e-14)  # the winch's tension


def test_series_matches_the_steps():
    s = np.linspace(0, 2 * np.pi, 200)
    h, v = 1.0 + 0.3 * np.cos(s), -0.7 + 0.25 * np.sin(s)
    L0 = np.hypot(h, v) * (1 - 1e-3) + 1e-3 * np.sin(3 * s)  # from taut to slack
    res = catenary_series(h, v, W_STEEL, EA_ROPE, L0=L0)
    assert res.H.shape == (200,) and res.dir_A.shape == (200, 2) and res.stiffness.shape == (200, 2, 2)
    assert np.all(res.status == CONVERGED)
    K = np.empty((2, 2))
    for k in range(0, 200, 17):
        _, out = solve(h[k], v[k], L0[k], W_STEEL, EA_ROPE)
        assert [res.H[k], res.V_B[k], res.V_A[k], res.T_A[k], res.T_B[k]] == pytest.approx(out[:5], rel=1e-12)
        assert res.sag[k] == pytest.approx(catenary_sag(out[OUT_H], out[OUT_VB], L0[k], W_STEEL, EA_ROPE), rel=1e-9)
        catenary_stiffness(out[OUT_H], out[OUT_VB], L0[k], W_STEEL, EA_ROPE, K)
        assert res.stiffness[k] == pytest.approx(K, rel=1e-9)
    # planning: the lengths for 100 N at the platform, and back
    plan = catenary_series(h, v, W_STEEL, EA_ROPE, T_B=100.0)
    assert np.all(plan.status == CONVERGED)
    assert plan.T_B == pytest.approx(100.0, rel=1e-12)
    again = catenary_series(h, v, W_STEEL, EA_ROPE, L0=plan.L0)
    assert again.T_B == pytest.approx(100.0, rel=1e-10)
    with pytest.raises(ValueError, match="exactly one"):
        catenary_series(h, v, W_STEEL, EA_ROPE)
