"""The compiled per-step kernels against the vectorised library (the same equations twice)."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from marinecdpr.model import rigid_body as RB
from marinecdpr.model import tension_solver as TS
from marinecdpr.motion.basemotion import evaluate_base_motion
from marinecdpr.model.dynamics import forward_dynamics, spatial_inertia, wrench_terms
from marinecdpr.geometry.kinematics import cable_kinematics, cables_step
from marinecdpr.geometry.rotations import euler_kinematics, euler_step
from marinecdpr.model.tension import distribute_tensions
from marinecdpr.motion.trajectory import evaluate_trajectory

from test_against_reference import I_PP, TRAJ, X_CS
from test_dynamics import SIX_DOF_SEA
from test_tension import random_problem


def _setting(t):
    ship = evaluate_base_motion(SIX_DOF_SEA, t)
    plat = evaluate_trajectory(TRAJ, t)
    rng = np.random.default_rng(0)
    f_C, m_C = rng.normal(size=(t.size, 3)), rng.normal(size=(t.size, 3))
    return ship, plat, f_C, m_C


def test_euler_step_matches_vectorised():
    """The compiled step and series against the former numpy implementation."""
    import vectorised

    rng = np.random.default_rng(1)
    a, r, acc = rng.uniform(-1, 1, (3, 5, 3))
    R, w, al = vectorised.euler_kinematics(a, r, acc)
    Rs, ws, als = euler_kinematics(a, r, acc)
    np.testing.assert_allclose(Rs, R, rtol=0, atol=1e-15)
    np.testing.assert_allclose(ws, w, rtol=0, atol=1e-15)
    np.testing.assert_allclose(als, al, rtol=0, atol=1e-14)
    # broadcasting, a leading shape of two axes, no rates, constant angles (trig reused)
    grid = rng.uniform(-1, 1, (4, 6, 3))
    np.testing.assert_allclose(euler_kinematics(grid)[0], vectorised.euler_kinematics(grid)[0], atol=1e-15)
    assert euler_kinematics(grid)[1] is None
    const = np.broadcast_to(a[0], (7, 3))
    for got, ref in zip(euler_kinematics(const, r[0], acc[:1]), vectorised.euler_kinematics(const, r[0], acc[:1])):
        np.testing.assert_allclose(got, ref, rtol=0, atol=1e-14)
    Rk, wk, alk = np.empty((3, 3)), np.empty(3), np.empty(3)
    for i in range(5):
        euler_step(a[i], r[i], acc[i], Rk, wk, alk)
        np.testing.assert_allclose(Rk, R[i], atol=1e-15)
        np.testing.assert_allclose(wk, w[i], atol=1e-15)
        np.testing.assert_allclose(alk, al[i], atol=1e-14)


def test_wrench_and_cables_match_vectorised():
    t = np.linspace(0.1, 3.9, 12)
    ship, plat, f_C, m_C = _setting(t)
    terms = wrench_terms(plat.x_PC_C, plat.twist, plat.twist_dot, plat.R_PC, ship, frame_origin_S=X_CS,
                         mass=5.0, I_PP=I_PP, gravity=9.8, f_ext_C=f_C, m_ext_C=m_C)
    rng = np.random.default_rng(2)
    c, p = rng.uniform(-1, 3, (7, 3)), rng.uniform(-0.2, 0.2, (7, 3))
    kin = cable_kinematics(plat.x_PC_C, plat.R_PC, c, p)
    out, L, J = np.empty(6), np.empty(7), np.empty((7, 6))
    for i in range(t.size):
        RB.wrench_step(plat.x_PC_C[i].copy(), plat.v_PC_C[i].copy(), plat.a_PC_C[i].copy(),
                      np.ascontiguousarray(plat.R_PC[i]), plat.omega_PC_C[i].copy(),
                      plat.alpha_PC_C[i].copy(),
                      RB.ShipAt(np.ascontiguousarray(ship.R_SO[i]), ship.omega_SO_S[i].copy(),
                                ship.alpha_SO_S[i].copy(), ship.a_SO_O[i].copy()),
                      RB.RigidBody(5.0, I_PP, 9.8, X_CS), f_C[i], m_C[i], out)
        np.testing.assert_allclose(out, terms.total[i], rtol=1e-12, atol=1e-12)
        cables_step(plat.x_PC_C[i].copy(), np.ascontiguousarray(plat.R_PC[i]), c, p, L, J)
        np.testing.assert_allclose(L, kin.lengths[i], rtol=1e-14)
        np.testing.assert_allclose(J, kin.J_tilde[i], atol=1e-14)


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**32 - 1), st.sampled_from(["pseudo_inverse", "closed_form", "minimum_variance",
                                                   "minimum_norm", "improved_closed_form"]),
       st.sampled_from([(4, 3), (7, 6), (6, 3), (8, 6), (9, 6)]))
def test_tensions_step_matches_distribute_tensions(seed, method, shape):
    m, k = shape
    J, w, lo, hi = random_problem(seed, 20, m, k, 150.0)
    sol = distribute_tensions(J, w, lo, hi, method=method)
    dofs = np.array([0, 2, 4]) if k == 3 else np.arange(6)
    J6 = np.zeros((m, 6))
    w6 = np.zeros(6)
    T = np.empty(m)
    work = TS.tension_work(m, k)
    for i in range(len(w)):
        J6[:, dofs] = J[i]
        w6[dofs] = w[i]
        ok = TS.tensions_step(J6, w6, dofs, lo, hi, TS.METHOD_CODES[method], T, work)
        assert ok == sol.feasible[i]
        # one implementation: the series (blocks of steps) and the step give the same bits
        np.testing.assert_array_equal(T, sol.tensions[i])


def test_tensions_step_does_every_method_for_any_redundancy():
    """Redundancy above 1 for the exact methods, and the improved closed form, per step too
    (they used to fall back to the library through numba's objmode)."""
    J, _, lo, hi = random_problem(5, 1, 8, 6, 10.0)
    w = np.einsum("nmk,m->nk", J, lo + 0.3 * (hi - lo))  # made by tensions within limits
    T = np.empty(8)
    for method in ("minimum_variance", "minimum_norm", "improved_closed_form"):
        sol = distribute_tensions(J, w, lo, hi, method=method)
        assert sol.feasible[0]
        assert TS.tensions_step(J[0], w[0], np.arange(6), lo, hi, TS.METHOD_CODES[method], T, TS.tension_work(8, 6))
        np.testing.assert_allclose(T, sol.tensions[0], rtol=1e-9)
    J4, w4, lo4, hi4 = random_problem(5, 1, 4, 3, 10.0)
    J6 = np.zeros((4, 6))
    J6[:, [0, 2, 4]] = J4[0]
    T4 = np.empty(4)
    assert TS.tensions_step(J6, np.array([w4[0, 0], 0, w4[0, 1], 0, w4[0, 2], 0]), np.array([0, 2, 4]),
                           lo4, hi4, TS.METHOD_CODES["improved_closed_form"], T4, TS.tension_work(4, 3))
    np.testing.assert_allclose(T4, distribute_tensions(J4, w4, lo4, hi4, method="improved_closed_form")
                               .tensions[0], rtol=1e-9)


@pytest.mark.parametrize("controlled", [(0, 2, 4), (0, 1, 2, 3, 4, 5)])
def test_forward_step_matches_forward_dynamics(controlled):
    rng = np.random.default_rng(4)
    n, m = 6, 8
    R = euler_kinematics(rng.uniform(-0.5, 0.5, (n, 3)))[0]
    J = rng.normal(size=(n, m, 6))
    T = rng.uniform(10, 300, (n, m))
    bias = rng.normal(size=(n, 6))
    M = spatial_inertia(R, 5.0, I_PP)
    acc, _ = forward_dynamics(T, J, M, bias, controlled)
    out = np.empty(6)
    for i in range(n):
        RB.forward_step(J[i], T[i], bias[i], np.ascontiguousarray(R[i]), 5.0, I_PP,
                       np.array(controlled), out)
        np.testing.assert_allclose(out, acc[i], rtol=1e-11, atol=1e-11)


# -------------------- formerly tests/test_one_model.py

"""One model, written once: the compiled path against the vectorised reference (tests/vectorised.py).

The package computes the model with compiled functions of one step
(:mod:`marinecdpr.geometry.kinematics`, :mod:`marinecdpr.model.kernels`), run over time
series in compiled loops by the array functions. ``tests/vectorised.py`` is the former
numpy implementation over whole series. They must agree to 1e-10 of each result's scale on
random robots (planar and spatial, 3 to 12 cables), random poses, twists and accelerations,
random 6-DOF ship motions, with and without a disturbance given in C, O or P.
"""

import numpy as np
import pytest

import vectorised as V
from marinecdpr.geometry import kinematics as GK
from marinecdpr.geometry.rotations import matrix_from_euler
from marinecdpr.model import dynamics as D
from marinecdpr.model import rigid_body as K
from marinecdpr.motion.ship import ship_motion

N_CASES = 1200
"""Random cases (a robot, a ship's motion, a disturbance and a few steps of motion each)."""
RTOL = 1e-10
PLANAR, SPATIAL = (0, 2, 4), (0, 1, 2, 3, 4, 5)


def _case(seed: int) -> dict:
    """A random robot on a random ship, over a few random steps (every step independent)."""
    rng = np.random.default_rng(seed)
    planar = bool(rng.integers(2))
    n_cab = int(rng.integers(3, 13))
    n = int(rng.integers(1, 9))
    c_C = rng.uniform(-3.0, 3.0, (n_cab, 3))
    p_P = rng.uniform(-0.4, 0.4, (n_cab, 3))
    A = rng.normal(size=(3, 3))
    inertia = A @ A.T + rng.uniform(0.01, 1.0) * np.eye(3)  # symmetric positive definite, kg m^2
    pose = np.concatenate([rng.uniform(-1.0, 1.0, (n, 3)), rng.uniform(-np.pi, np.pi, (n, 3))], axis=1)
    twist, twist_dot = rng.normal(size=(n, 6)), rng.normal(scale=3.0, size=(n, 6))
    if planar:  # the cables control (x, z, ry); the guide holds the rest still
        c_C[:, 1] = 0.0
        for a in (pose, twist, twist_dot):
            a[:, [1, 3, 5]] = 0.0
    eta = np.concatenate([rng.uniform(-5.0, 5.0, (n, 3)), rng.uniform(-np.pi, np.pi, (n, 1)),
                          rng.uniform(-1.2, 1.2, (n, 1)), rng.uniform(-np.pi, np.pi, (n, 1))], axis=1)
    ship = ship_motion(eta, rng.normal(size=(n, 6)), rng.normal(scale=2.0, size=(n, 6)))
    disturbed = bool(rng.integers(2))
    return dict(
        seed=seed, planar=planar, controlled=PLANAR if planar else SPATIAL, c_C=c_C, p_P=p_P,
        mass=float(rng.uniform(0.5, 50.0)), inertia=inertia, gravity=float(rng.uniform(9.7, 9.9)),
        origin=rng.uniform(-2.0, 2.0, 3), x_PC=pose[:, :3], R_PC=matrix_from_euler(pose[:, 3:]),
        twist=twist, twist_dot=twist_dot, ship=ship,
        f=rng.normal(scale=20.0, size=(n, 3)) if disturbed else None,
        m=rng.normal(scale=5.0, size=(n, 3)) if disturbed else None,
        frame=str(rng.choice(["C", "O", "P"])),
        tensions=rng.uniform(1.0, 500.0, (n, n_cab)),
    )


CASES = [_case(seed) for seed in range(N_CASES)]


def _close(actual, expected, what=""):
    """Equal to RTOL of the expected values' scale, NaN where they are NaN."""
    actual, expected = np.asarray(actual), np.asarray(expected)
    assert actual.shape == expected.shape, what
    nan = np.isnan(expected)
    np.testing.assert_array_equal(np.isnan(actual), nan, err_msg=what)
    finite = expected[~nan]
    scale = float(np.abs(finite).max()) if finite.size else 0.0
    np.testing.assert_allclose(actual[~nan], finite, rtol=0, atol=RTOL * max(scale, 1e-300), err_msg=what)


def _same_terms(a, b, what):
    for name in ("relative", "gravity", "C_s", "gravity_tilt", "external", "F_s", "total"):
        _close(getattr(a, name), getattr(b, name), f"{what}: {name}")


def _wrench(module, c, twist_dot=None, f_C=None, m_C=None):
    return module.wrench_terms(
        c["x_PC"], c["twist"], c["twist_dot"] if twist_dot is None else twist_dot, c["R_PC"], c["ship"],
        frame_origin_S=c["origin"], mass=c["mass"], I_PP=c["inertia"], gravity=c["gravity"],
        f_ext_C=f_C, m_ext_C=m_C)


def test_there_are_enough_cases_of_every_kind():
    assert len(CASES) >= 1000
    assert {c["planar"] for c in CASES} == {True, False}
    assert {c["frame"] for c in CASES if c["f"] is not None} == {"C", "O", "P"}
    assert any(c["f"] is None for c in CASES)
    assert {c["c_C"].shape[0] for c in CASES} == set(range(3, 13))


def test_cable_kinematics_and_global_jacobian():
    for c in CASES:
        what = f"case {c['seed']}"
        for twist in (c["twist"], None):
            a = GK.cable_kinematics(c["x_PC"], c["R_PC"], c["c_C"], c["p_P"], twist)
            b = V.cable_kinematics(c["x_PC"], c["R_PC"], c["c_C"], c["p_P"], twist)
            for name in ("lengths", "anchors_C", "J_tilde", "units", "vectors"):
                _close(getattr(a, name), getattr(b, name), f"{what}: {name}")
            if twist is None:
                assert a.length_rates is None and b.length_rates is None
            else:
                _close(a.length_rates, b.length_rates, f"{what}: length_rates")
        _close(GK.global_jacobian(b.J_tilde, c["ship"].R_SO), V.global_jacobian(b.J_tilde, c["ship"].R_SO), what)


def test_disturbance_in_C_in_every_frame():
    for c in CASES:
        if c["f"] is None:
            continue
        for frame in ("C", "O", "P"):
            a = D.disturbance_in_C(c["f"], c["m"], frame, c["ship"].R_SO, c["R_PC"])
            b = V.disturbance_in_C(c["f"], c["m"], frame, c["ship"].R_SO, c["R_PC"])
            for x, y in zip(a, b):
                _close(x, y, f"case {c['seed']}, frame {frame}")


def test_disturbance_in_C_reads_only_the_frames_rotation():
    """The simulation passes None for the rotation a frame does not need."""
    c = next(c for c in CASES if c["f"] is not None)
    for frame, R_SO, R_PC in (("O", c["ship"].R_SO, None), ("P", None, c["R_PC"]), ("C", None, None)):
        for x, y in zip(D.disturbance_in_C(c["f"], c["m"], frame, R_SO, R_PC),
                        V.disturbance_in_C(c["f"], c["m"], frame, c["ship"].R_SO, c["R_PC"])):
            _close(x, y, frame)


def test_wrench_terms_with_and_without_disturbance():
    for c in CASES:
        what = f"case {c['seed']}"
        _same_terms(_wrench(D, c), _wrench(V, c), what)
        if c["f"] is not None:
            f_C, m_C = V.disturbance_in_C(c["f"], c["m"], c["frame"], c["ship"].R_SO, c["R_PC"])
            _same_terms(_wrench(D, c, f_C=f_C, m_C=m_C), _wrench(V, c, f_C=f_C, m_C=m_C),
                        f"{what}, disturbance in {c['frame']}")


def test_absolute_motion_inertial_terms_and_spatial_inertia():
    for c in CASES:
        what = f"case {c['seed']}"
        a = D.absolute_motion(c["x_PC"], c["twist"], c["twist_dot"], c["ship"], frame_origin_S=c["origin"])
        b = V.absolute_motion(c["x_PC"], c["twist"], c["twist_dot"], c["ship"], frame_origin_S=c["origin"])
        for name in ("x_PO_O", "v_PO_O", "a_PO_O", "omega_PO_O", "alpha_PO_O"):
            _close(getattr(a, name), getattr(b, name), f"{what}: {name}")
        kw = dict(mass=c["mass"], I_PP=c["inertia"], gravity=c["gravity"])
        for x, y, name in zip(D.inertial_frame_terms(c["ship"].R_SO, c["R_PC"], b.omega_PO_O, **kw),
                              V.inertial_frame_terms(c["ship"].R_SO, c["R_PC"], b.omega_PO_O, **kw), "MCG"):
            _close(x, y, f"{what}: {name}")
        _close(D.spatial_inertia(c["R_PC"], c["mass"], c["inertia"]),
               V.spatial_inertia(c["R_PC"], c["mass"], c["inertia"]), what)


def test_forward_dynamics():
    for c in CASES:
        kin = V.cable_kinematics(c["x_PC"], c["R_PC"], c["c_C"], c["p_P"])
        M = V.spatial_inertia(c["R_PC"], c["mass"], c["inertia"])
        bias = _wrench(V, c, twist_dot=np.zeros_like(c["twist"])).total
        for controlled in (c["controlled"], (0, 1, 2), (5,)):
            a = D.forward_dynamics(c["tensions"], kin.J_tilde, M, bias, controlled)
            b = V.forward_dynamics(c["tensions"], kin.J_tilde, M, bias, controlled)
            for x, y, name in zip(a, b, ("twist_dot", "reaction")):
                _close(x, y, f"case {c['seed']}, controlled {controlled}: {name}")


def test_the_closed_loops_per_step_functions():
    """What the simulation calls at every step: the same numbers, one step at a time."""
    L, J, A, rates, parts = np.empty(12), np.empty((12, 6)), np.empty((12, 3)), np.empty(12), np.empty((5, 6))
    w, acc, zero3 = np.empty(6), np.empty(6), np.zeros(3)
    for c in CASES[:300]:
        ship, m = c["ship"], c["c_C"].shape[0]
        kin = V.cable_kinematics(c["x_PC"], c["R_PC"], c["c_C"], c["p_P"], c["twist"])
        f_C, m_C = (np.zeros_like(c["x_PC"]),) * 2 if c["f"] is None else \
            V.disturbance_in_C(c["f"], c["m"], c["frame"], ship.R_SO, c["R_PC"])
        terms = _wrench(V, c, f_C=f_C, m_C=m_C)
        M = V.spatial_inertia(c["R_PC"], c["mass"], c["inertia"])
        bias = _wrench(V, c, twist_dot=np.zeros_like(c["twist"]), f_C=f_C, m_C=m_C).total
        acc_v, _ = V.forward_dynamics(c["tensions"], kin.J_tilde, M, bias, c["controlled"])
        for k in range(c["x_PC"].shape[0]):
            what = f"case {c['seed']}, step {k}"
            x, R = np.ascontiguousarray(c["x_PC"][k]), np.ascontiguousarray(c["R_PC"][k])
            GK.cables_step(x, R, c["c_C"], c["p_P"], L[:m], J[:m])
            _close(L[:m], kin.lengths[k], what)
            _close(J[:m], kin.J_tilde[k], what)
            GK.cables_step(x, R, c["c_C"], c["p_P"], L[:m], J[:m], A[:m])
            _close(A[:m], kin.anchors_C[k], what)
            GK.length_rates_step(J[:m], np.ascontiguousarray(c["twist"][k]), rates[:m])
            _close(rates[:m], kin.length_rates[k], what)
            v, w_pc = np.ascontiguousarray(c["twist"][k, :3]), np.ascontiguousarray(c["twist"][k, 3:])
            a, al_pc = np.ascontiguousarray(c["twist_dot"][k, :3]), np.ascontiguousarray(c["twist_dot"][k, 3:])
            ship_k = K.ShipAt(np.ascontiguousarray(ship.R_SO[k]), ship.omega_SO_S[k].copy(),
                              ship.alpha_SO_S[k].copy(), ship.a_SO_O[k].copy())
            body = K.RigidBody(c["mass"], c["inertia"], c["gravity"], c["origin"])
            args = (x, v, a, R, w_pc, al_pc, ship_k, body, f_C[k].copy(), m_C[k].copy())
            K.wrench_step(*args, w)
            _close(w, terms.total[k], what)
            K.wrench_parts_step(*args, parts)
            for p, name in enumerate(("relative", "gravity", "C_s", "gravity_tilt", "external")):
                _close(parts[p], getattr(terms, name)[k], f"{what}: {name}")
            K.wrench_step(x, v, zero3, R, w_pc, zero3, *args[6:], w)
            K.forward_step(J[:m], c["tensions"][k], w, R, c["mass"], c["inertia"],
                           np.array(c["controlled"]), acc)
            _close(acc, acc_v[k], what)


@pytest.mark.parametrize("p_i", [np.zeros(3), np.array([0.5, -0.25, 0.125])])
def test_coincident_anchors_give_zero_length_and_nan_rows(p_i):
    """A platform anchor exactly on its frame anchor: length 0, J~ row and length rate NaN."""
    rng = np.random.default_rng(7)
    c_C, p_P = rng.uniform(-2, 2, (5, 3)), rng.uniform(-0.3, 0.3, (5, 3))
    p_P[2] = p_i
    R = matrix_from_euler(rng.uniform(-1, 1, (4, 3)))
    R[1] = np.eye(3)  # step 1: R_PC p_2 = p_2 exactly
    x = rng.uniform(-1, 1, (4, 3))
    c_C[2] = [1.5, -0.75, 0.625]
    x[1] = c_C[2] - p_i  # exact in binary: l_2 = c_2 - x - p_2 = 0
    twist = rng.normal(size=(4, 6))
    a = GK.cable_kinematics(x, R, c_C, p_P, twist)
    with np.errstate(invalid="ignore"):  # the reference's 0 * inf
        b = V.cable_kinematics(x, R, c_C, p_P, twist)
    assert a.lengths[1, 2] == 0.0 and np.isnan(a.J_tilde[1, 2]).all() and np.isnan(a.length_rates[1, 2])
    assert np.isfinite(np.delete(a.J_tilde[1], 2, axis=0)).all() and np.isfinite(a.J_tilde[[0, 2, 3]]).all()
    for name in ("lengths", "anchors_C", "J_tilde", "length_rates"):
        _close(getattr(a, name), getattr(b, name), name)
    L, J = np.empty(5), np.empty((5, 6))
    GK.cables_step(x[1].copy(), R[1].copy(), c_C, p_P, L, J)  # the closed loop's kernel: the same
    assert L[2] == 0.0 and np.isnan(J[2]).all()


def test_layout_of_inputs_does_not_matter_and_outputs_are_time_last():
    """Time-first C arrays and time-last views give the same numbers; results are time-last views."""
    c = CASES[3]
    n = c["x_PC"].shape[0]

    def time_last_view(a):  # the same values, time-first, as a view of a time-last buffer
        return np.moveaxis(np.ascontiguousarray(np.moveaxis(a, 0, -1)), -1, 0)

    x2, R2, tw2 = (time_last_view(c[k]) for k in ("x_PC", "R_PC", "twist"))
    assert not x2.flags.c_contiguous and np.array_equal(x2, c["x_PC"])
    a = GK.cable_kinematics(c["x_PC"], c["R_PC"], c["c_C"], c["p_P"], c["twist"])
    b = GK.cable_kinematics(x2, R2, c["c_C"], c["p_P"], tw2)
    for name in ("lengths", "anchors_C", "J_tilde", "length_rates"):
        assert np.array_equal(getattr(a, name), getattr(b, name), equal_nan=True)
        assert getattr(a, name).transpose(*range(getattr(a, name).ndim)[::-1]).flags.c_contiguous
    terms = _wrench(D, c)
    assert terms.relative.T.flags.c_contiguous and terms.total.shape == (n, 6)


def test_empty_series():
    c = CASES[0]
    kin = GK.cable_kinematics(np.empty((0, 3)), np.empty((0, 3, 3)), c["c_C"], c["p_P"], np.empty((0, 6)))
    assert kin.lengths.shape == (0, c["c_C"].shape[0]) and kin.J_tilde.shape == (0, c["c_C"].shape[0], 6)
    ship = ship_motion(np.empty((0, 6)), np.empty((0, 6)), np.empty((0, 6)))
    terms = D.wrench_terms(np.empty((0, 3)), np.empty((0, 6)), np.empty((0, 6)), np.empty((0, 3, 3)), ship,
                           frame_origin_S=c["origin"], mass=1.0, I_PP=np.eye(3), gravity=9.8)
    assert terms.total.shape == (0, 6)


def test_the_closed_loop_and_planning_share_the_kernel():
    from marinecdpr.control import step

    assert step.cables_step is GK.cables_step


def test_the_rigid_body_and_the_ship_go_in_as_records():
    """The body's constants (mass, I_PP, g, origin) and the ship's state at a step (R_SO,
    omega_s, alpha_s, a_SO) are one record each (issue 38, item 5); any record with the
    body's attributes serves, in any field order, bit for bit (the controller passes its
    RobotModel). Hand-worked: the platform at rest at C's origin, the ship level and still
    but accelerating at a_SO = (1, 0, 0) m/s^2 in O: w = (m a_SO + (0, 0, m g), 0) - (f, m)."""
    from typing import NamedTuple

    class Other(NamedTuple):  # the attributes of RigidBody among others, in another order
        origin: np.ndarray
        method: int
        g: float
        I_PP: np.ndarray
        mass: float

    zero, I3 = np.zeros(3), np.eye(3)
    ship = RB.ShipAt(I3.copy(), zero.copy(), zero.copy(), np.array([1.0, 0.0, 0.0]))
    f, m = np.array([0.5, -0.25, 2.0]), np.array([0.125, 0.0, -1.0])
    body = RB.RigidBody(4.0, np.diag([0.1, 0.2, 0.3]), 9.8, zero.copy())
    w, w_other = np.empty(6), np.empty(6)
    RB.wrench_step(zero, zero, zero, I3, zero, zero, ship, body, f, m, w)
    np.testing.assert_array_equal(w, [4.0 - 0.5, 0.25, 4.0 * 9.8 - 2.0, -0.125, 0.0, 1.0])
    # a general state: the record's type changes nothing in the arithmetic
    rng = np.random.default_rng(3)
    x, v, a, w_pc, al_pc = rng.normal(size=(5, 3))
    R = np.linalg.qr(rng.normal(size=(3, 3)))[0]
    ship = RB.ShipAt(np.linalg.qr(rng.normal(size=(3, 3)))[0], *rng.normal(size=(3, 3)))
    body = RB.RigidBody(4.0, np.diag([0.1, 0.2, 0.3]), 9.8, rng.normal(size=3))
    RB.wrench_step(x, v, a, R, w_pc, al_pc, ship, body, f, m, w)
    RB.wrench_step(x, v, a, R, w_pc, al_pc, ship, Other(body.origin, 1, body.g, body.I_PP, body.mass), f, m,
                   w_other)
    np.testing.assert_array_equal(w_other, w)
