"""Stiffness, natural frequencies and the linearised open loop (marinecdpr.model.stiffness).

The ground truth for every matrix is a central finite difference of the model itself: the
cables' wrench J~^T T (tensions held, or elastic about fixed lengths), the required wrench
of eq. (15) (``wrench_terms``), and the forward dynamics the prototype's own plant integrates.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import marinecdpr
from marinecdpr.geometry.kinematics import cable_kinematics
from marinecdpr.geometry.rotations import matrix_from_euler
from marinecdpr.model.dynamics import forward_dynamics, spatial_inertia, wrench_terms
from marinecdpr.model.stiffness import (
    cable_stiffness, load_linearisation, natural_frequencies, open_loop_growth_rate, plan_stiffness,
)
from marinecdpr.motion.basemotion import evaluate_base_motion
from marinecdpr.scenario.schema import SinusoidalMotion

CUBE8 = str(Path(__file__).resolve().parents[2] / "examples" / "spatial_cube8.toml")
H = 1e-5  # finite-difference step, m and rad


@pytest.fixture(scope="module")
def cube8():
    return marinecdpr.load_scenario(CUBE8)


@pytest.fixture(scope="module")
def cube8_plan(cube8):
    return marinecdpr.plan(cube8)


def _perturbed(x, R, h=H):
    """The 12 poses x +- h e_a, exp(+-h [e_a x]) R (rotation vector in C), in the order
    (+e_0, -e_0, +e_1, ...): x (12, 3), R (12, 3, 3)."""
    xs, Rs = [], []
    for a in range(6):
        for s in (1.0, -1.0):
            d = np.zeros(6)
            d[a] = s * h
            xs.append(x + d[:3])
            Rs.append(Rotation.from_rotvec(d[3:]).as_matrix() @ R)
    return np.array(xs), np.array(Rs)


def _random_poses(plan, rng, n):
    """n poses near the plan's (a few cm, a few degrees off), as x (n, 3), R (n, 3, 3)."""
    k = rng.integers(0, plan.n_steps, n)
    pose = plan.pose[k].copy()
    c = list(plan.controlled)
    d = np.zeros((n, 6))
    d[:, c] = rng.normal(size=(n, len(c))) * np.where(np.array(c) < 3, 0.03, np.radians(4.0))
    pose += d
    return pose[:, :3], matrix_from_euler(pose[:, 3:])


@pytest.mark.parametrize("which", ["paper", "cube8"])
def test_stiffness_matches_finite_differences_of_the_cable_wrench(which, paper, paper_plan, cube8, cube8_plan):
    """K = -d(J~^T T)/d(dx, dphi): held tensions (K_geometric), elastic cables at fixed
    lengths T = T0 + EA (L - L0) / L0 (K_axial + K_geometric), and the prototype's law
    T = EA (L - L0u) / L0u ("unstretched"), at random poses, all 6 x 6, rel 1e-6."""
    sc, plan = (paper, paper_plan) if which == "paper" else (cube8, cube8_plan)
    rng = np.random.default_rng(7)
    c_C, p_P = sc.robot.frame_anchors, sc.robot.platform_anchors
    x, R = _random_poses(plan, rng, 12)
    T0 = rng.uniform(10.0, 450.0, size=(x.shape[0], sc.robot.n_cables))
    EA = rng.uniform(2e4, 2e5, size=sc.robot.n_cables)
    held = cable_stiffness(x, R, c_C, p_P, T0)
    elastic = cable_stiffness(x, R, c_C, p_P, T0, EA=EA)
    unstretched = cable_stiffness(x, R, c_C, p_P, T0, EA=EA, reference_length="unstretched")
    for s in range(x.shape[0]):
        xp, Rp = _perturbed(x[s], R[s])
        kin = cable_kinematics(xp, Rp, c_C, p_P)
        L, J = kin.lengths, kin.J_tilde
        L0 = held.lengths[s]
        L0u = L0 / (1.0 + T0[s] / EA)
        for K, T in ((held.K, np.broadcast_to(T0[s], L.shape)),
                     (elastic.K, T0[s] + EA * (L - L0) / L0),
                     (unstretched.K, EA * (L - L0u) / L0u)):
            W = np.einsum("pia,pi->pa", J, T)  # J~^T T at each perturbed pose
            K_fd = -(W[0::2] - W[1::2]).T / (2 * H)  # column a: -dW/dq_a
            scale = np.abs(K_fd).max()
            np.testing.assert_allclose(K[s], K_fd, rtol=1e-6, atol=1e-6 * scale)
    # the geometric stiffness is not negligible: it is what holds a tension-controlled platform
    assert np.abs(held.K).max() > 100.0


def test_load_linearisation_matches_finite_differences_of_the_required_wrench(paper):
    """K_load = dw/dq and D_load = dw/dnu (eq. 15, ``wrench_terms``) on a six-DOF sea, with the
    platform moving and turning and a disturbance fixed to the platform (in P)."""
    sea = SinusoidalMotion.model_validate({"type": "sinusoidal", "components": [
        {"dof": "surge", "amplitude_m": 0.4, "period_s": 7.0, "phase_deg": 10.0},
        {"dof": "heave", "amplitude_m": 0.8, "period_s": 8.0, "phase_deg": 40.0},
        {"dof": "roll", "amplitude_deg": 12.0, "period_s": 4.0},
        {"dof": "pitch", "amplitude_deg": 8.0, "period_s": 3.0, "phase_deg": 70.0},
        {"dof": "yaw", "amplitude_deg": 6.0, "period_s": 5.0, "offset_deg": 20.0}]})
    rng = np.random.default_rng(3)
    n = 8
    ship = evaluate_base_motion(sea, rng.uniform(0, 20, n))
    x = rng.uniform(0.3, 1.2, (n, 3))
    R = Rotation.from_rotvec(rng.normal(size=(n, 3)) * 0.5).as_matrix()
    tw = rng.normal(size=(n, 6)) * [0.3, 0.3, 0.3, 1.0, 1.0, 1.0]
    td = rng.normal(size=(n, 6)) * [1.0, 1.0, 1.0, 3.0, 3.0, 3.0]
    f_P, m_P = rng.normal(size=(n, 3)) * 20.0, rng.normal(size=(n, 3)) * 2.0
    I_PP = np.array([[0.05, 0.004, -0.002], [0.004, 0.03, 0.001], [-0.002, 0.001, 0.06]])
    mass, origin = 5.0, np.array([-0.78, 0.3, 2.2])
    lin = load_linearisation(R, tw, td, ship, mass=mass, I_PP=I_PP, f_P=f_P, m_P=m_P)
    for s in range(n):
        xp, Rp = _perturbed(x[s], R[s])
        one = ship.take(np.full(12, s))

        def w(xq, Rq, twq):
            f_C, m_C = np.einsum("pab,b->pa", Rq, f_P[s]), np.einsum("pab,b->pa", Rq, m_P[s])
            return wrench_terms(xq, twq, np.tile(td[s], (12, 1)), Rq, one, frame_origin_S=origin, mass=mass,
                                I_PP=I_PP, gravity=9.8, f_ext_C=f_C, m_ext_C=m_C).total

        Wq = w(xp, Rp, np.tile(tw[s], (12, 1)))
        K_fd = (Wq[0::2] - Wq[1::2]).T / (2 * H)
        twp = tw[s] + np.kron(np.eye(6), [[1.0], [-1.0]]) * H
        Wv = w(np.tile(x[s], (12, 1)), np.tile(R[s], (12, 1, 1)), twp)
        D_fd = (Wv[0::2] - Wv[1::2]).T / (2 * H)
        np.testing.assert_allclose(lin.K[s], K_fd, rtol=1e-6, atol=1e-6 * np.abs(K_fd).max())
        np.testing.assert_allclose(lin.D[s], D_fd, rtol=1e-6, atol=1e-6 * np.abs(D_fd).max())
    assert np.abs(lin.K).max() > 1.0 and np.abs(lin.D).max() > 1.0


@pytest.mark.parametrize("which", ["paper", "cube8"])
def test_linearised_open_loop_matches_the_forward_dynamics(which, paper, paper_plan, cube8, cube8_plan):
    """A's lower rows, -M^-1 K_eff and -M^-1 D, are the derivatives of the forward dynamics
    the own plant integrates (plan tensions held, bias = eq. 15 at zero acceleration), about
    the plan's state at a few steps."""
    sc, plan = (paper, paper_plan) if which == "paper" else (cube8, cube8_plan)
    ps = plan_stiffness(plan, sc)
    A = ps.state_matrix()
    c, k = list(plan.controlled), len(plan.controlled)
    r = sc.robot
    ship_all = evaluate_base_motion(sc.base_motion, plan.t)
    for s in np.linspace(0, plan.n_steps - 1, 5).astype(int):
        x0, R0 = plan.pose[s, :3], matrix_from_euler(plan.pose[s, 3:])
        one = ship_all.take(np.full(2 * k, s))
        rows = [2 * a + b for a in c for b in (0, 1)]  # the controlled perturbations

        def acc(xq, Rq, twq):
            kin = cable_kinematics(xq, Rq, r.frame_anchors, r.platform_anchors)
            bias = wrench_terms(xq, twq, np.zeros_like(twq), Rq, one,
                                frame_origin_S=np.asarray(sc.ship.frame_origin_m), mass=r.mass_kg,
                                I_PP=r.inertia, gravity=sc.environment.gravity_m_s2).total
            M = spatial_inertia(Rq, r.mass_kg, r.inertia)
            T = np.tile(plan.tensions[s], (twq.shape[0], 1))
            return forward_dynamics(T, kin.J_tilde, M, bias, tuple(c))[0][:, c]

        xp, Rp = _perturbed(x0, R0)
        a_q = acc(xp[rows], Rp[rows], np.tile(plan.twist[s], (2 * k, 1)))
        twp = (plan.twist[s] + np.kron(np.eye(6), [[1.0], [-1.0]]) * H)[rows]
        a_v = acc(np.tile(x0, (2 * k, 1)), np.tile(R0, (2 * k, 1, 1)), twp)
        for got, fd in ((A[s, k:, :k], (a_q[0::2] - a_q[1::2]).T / (2 * H)),
                        (A[s, k:, k:], (a_v[0::2] - a_v[1::2]).T / (2 * H))):
            np.testing.assert_allclose(got, fd, rtol=1e-5, atol=1e-6 * np.abs(A[s, k:, :k]).max())


def test_symmetric_planar_robot_by_hand():
    """A point-like platform (p_i = 0) at the centre of a 2a x 2b rectangle of 4 cables, equal
    tensions T, length L = sqrt(a^2 + b^2), cos(beta) = a / L:

        k_x = 4 (EA cos^2 beta + T sin^2 beta) / L,   k_z = 4 (EA sin^2 beta + T cos^2 beta) / L,

    (the square: k = 2 (EA + T) / L), natural frequencies sqrt(k / m) / (2 pi); the rotation
    has no stiffness (every cable through the centre of mass): flagged, NaN."""
    m, T, EA = 5.0, 120.0, 1e5
    I_PP = np.diag([0.03, 0.03, 0.06])
    for a, b in ((0.8, 0.8), (0.9, 0.6)):
        c_C = np.array([[-a, 0, b], [a, 0, b], [a, 0, -b], [-a, 0, -b]])
        p_P = np.zeros((4, 3))
        x, R = np.zeros((1, 3)), np.eye(3)[None]
        cs = cable_stiffness(x, R, c_C, p_P, np.full((1, 4), T), EA=EA)
        L = np.hypot(a, b)
        cb2, sb2 = (a / L) ** 2, (b / L) ** 2
        k_x = 4 * (EA * cb2 + T * sb2) / L
        k_z = 4 * (EA * sb2 + T * cb2) / L
        c = [0, 2, 4]
        K = cs.K[:, c][:, :, c]
        np.testing.assert_allclose(np.diag(K[0])[:2], [k_x, k_z], rtol=1e-12)
        assert abs(K[0, 2, 2]) < 1e-12
        if a == b:
            np.testing.assert_allclose(k_x, 2 * (EA + T) / L, rtol=1e-14)
        M = spatial_inertia(R, m, I_PP)[:, c][:, :, c]
        fr = natural_frequencies(K, M)
        expect = np.sort([np.sqrt(k_x / m), np.sqrt(k_z / m)]) / (2 * np.pi)
        finite = fr.hz[0][np.isfinite(fr.hz[0])]
        np.testing.assert_allclose(finite, expect, rtol=1e-9)
        assert not fr.positive_definite[0]  # theta_y: zero stiffness
        # tension-controlled (no EA): k = 4 T sin^2 / L and 4 T cos^2 / L, the string's T / L
        Kg = cable_stiffness(x, R, c_C, p_P, np.full((1, 4), T)).K[:, c][:, :, c]
        np.testing.assert_allclose(np.diag(Kg[0])[:2], [4 * T * sb2 / L, 4 * T * cb2 / L], rtol=1e-12)


def test_crossed_cube_is_unstable_in_yaw_with_held_tensions_as_the_prototype_tumbles(cube8, cube8_plan):
    """spatial_cube8's open loop (ideal cables, tensions held): the crossed cables pull every
    platform anchor across the centre (r_i . u_i < 0 in the horizontal plane), which makes the
    yaw stiffness negative (an inverted pendulum in rz): K_rz = sum_i t_i [(r_i x e_z)^T P_i
    (r_i x e_z) + r_i,xy . u_i,xy] ~ -15 to -29 N m/rad, growth rate sqrt(-K_rz / I_zz).

    The prototype's own plant flying the plan open loop: its rz error grows like
    exp(rate t) from ~1e-10 rad at the start (discretisation) until it tumbles; the fitted
    rate matches the linear prediction (~21.5 1/s there) to well within a factor 2."""
    g = open_loop_growth_rate(cube8_plan, cube8, "tension")
    print(f"\ncube8 tension-controlled: {g.describe()}; mode {np.round(g.mode.real, 4)}; "
          f"e-folding {1e3 * g.e_folding_time_s:.1f} ms; rates along the plan "
          f"{np.nanmin(g.rates):.2f}..{np.nanmax(g.rates):.2f} 1/s")
    assert g.rate > 20.0  # e-folding in less than 50 ms
    assert g.stability == "unstable" and g.eigenvalue.imag == 0.0  # a divergence, not a flutter
    assert g.dominant[0] == "rz"
    assert np.all(g.rates > 20.0)  # unstable at every step of the plan
    ps = plan_stiffness(cube8_plan, cube8)
    assert ps.K[:, 5, 5].max() < -10.0  # negative yaw stiffness throughout
    assert not ps.frequencies().positive_definite.any()
    # the yaw stiffness by its two parts at the first step
    kin = cable_kinematics(cube8_plan.pose[:1, :3], matrix_from_euler(cube8_plan.pose[:1, 3:]),
                           cube8.robot.frame_anchors, cube8.robot.platform_anchors)
    t, L, u, r = cube8_plan.tensions[0], kin.lengths[0], kin.units[0], kin.anchors_C[0]
    rxe = np.cross(r, [0.0, 0.0, 1.0])
    string = np.sum(t * (np.sum(rxe * rxe, 1) - np.sum(u * rxe, 1) ** 2) / L)
    lever = np.sum(t * np.sum(r[:, :2] * u[:, :2], 1))
    assert lever < 0 < string < -lever
    np.testing.assert_allclose(ps.K_geometric[0, 5, 5], string + lever, rtol=1e-10)

    sim = marinecdpr.simulate(cube8, run="open_loop", plant="own", reference=cube8_plan, n_steps=1200)
    e = np.abs(sim.pose_error[:, 5])
    window = (e > 1e-7) & (e < 1e-2) & (sim.t < 1.2)
    fitted = np.polyfit(sim.t[window], np.log(e[window]), 1)[0]
    predicted = float(np.nanmean(g.rates[: sim.t.size][window]))
    print(f"prototype rz error {e[np.searchsorted(sim.t, 0.3)]:.2e} rad at 0.3 s -> "
          f"{e[np.searchsorted(sim.t, 1.0)]:.2e} rad at 1 s: fitted growth {fitted:.2f} 1/s, "
          f"predicted {predicted:.2f} 1/s over the same window")
    assert window.sum() > 300
    assert 0.5 < fitted / predicted < 2.0
    assert abs(fitted / predicted - 1.0) < 0.05  # in fact within a few per cent


def test_cube8_on_length_controlled_elastic_cables_is_neutral(cube8, cube8_plan):
    """The axial stiffness (EA = 1e5 N) outweighs the negative yaw term: every frequency real
    and positive (15-72 Hz), and the open loop is neutral (no growth faster than ~1e-4 1/s)."""
    g = open_loop_growth_rate(cube8_plan, cube8, "length", EA=1e5)
    fr = plan_stiffness(cube8_plan, cube8, winches="length", EA=1e5).frequencies()
    print(f"\ncube8 length-controlled: {g.describe()}; frequencies {np.round(g.frequencies_hz, 2)} Hz")
    assert fr.positive_definite.all()
    assert np.nanmin(fr.hz) > 10.0
    assert abs(g.rate) < 1e-4 and g.stability == "neutral"


def test_paper_open_loop_is_neutral_and_elastic_winches_stiffen_it(paper, paper_plan):
    """The paper's planar robot: its cables are not crossed and its held tensions alone make K
    positive definite at every step (natural frequencies ~0.6-13 Hz), so the tension-controlled
    open loop is neutral: no damping, and the ship's non-conservative terms (Euler, Coriolis)
    give a growth rate of a few 1e-5 1/s (e-folding ~ 7 h) - the prototype's open loop
    follows the plan to ~1e-7 m. Length-controlled elastic winches (EA 1e5 N) keep every
    frequency real and positive and raise them to ~13-75 Hz."""
    g = open_loop_growth_rate(paper_plan, paper, "tension")
    fr = plan_stiffness(paper_plan, paper).frequencies()
    print(f"\npaper tension-controlled: {g.describe()}; frequencies there {np.round(g.frequencies_hz, 3)} Hz")
    assert fr.positive_definite.all()
    assert 0.3 < np.nanmin(fr.hz) and np.nanmax(fr.hz) < 20.0
    assert abs(g.rate) < 1e-3 and g.stability == "neutral"  # e-folding beyond 1000 s
    assert abs(g.eigenvalue.imag) > 1.0  # an undamped oscillation, not a divergence
    no_load = open_loop_growth_rate(paper_plan, paper, "tension", include_load=False)
    assert abs(no_load.rate) < 1e-9  # conservative without the ship's terms: purely imaginary
    gl = open_loop_growth_rate(paper_plan, paper, "length", EA=1e5)
    frl = plan_stiffness(paper_plan, paper, winches="length", EA=1e5).frequencies()
    print(f"paper length-controlled (EA 1e5 N): {gl.describe()}; frequencies "
          f"{np.round(np.nanmin(frl.hz, 0), 2)}..{np.round(np.nanmax(frl.hz, 0), 2)} Hz")
    assert frl.positive_definite.all() and np.isfinite(frl.hz).all()
    assert (frl.hz > fr.hz).all()
    assert abs(gl.rate) < 1e-4 and gl.stability == "neutral"
    # the damping of the cables (c J~^T J~) makes the length-controlled loop stable
    damped = open_loop_growth_rate(paper_plan, paper, "length", EA=1e5, damping=50.0)
    assert damped.rate < -0.1 and damped.stability == "stable"
