"""Heavy cables in the own plant (issue 14, item 3): each cable an elastic catenary over the
winch's paid-out length, pulling the platform along its tangent; the planner's sag fed
forward to the length-controlled winches."""

import numpy as np
import pytest
from numba import njit

import marinecdpr
from marinecdpr import ScenarioError
from marinecdpr.control.controller import robot_model
from marinecdpr.geometry.rotations import matrix_from_euler
from marinecdpr.model.catenary import catenary_series
from marinecdpr.prototype.parts.cables import catenary_cables, catenary_part
from marinecdpr.prototype.simulation import simulate

from conftest import make_scenario

EA, W = 1.0e5, 3.5  # a heavy rope: 1.2 m of it weighs 4.2 N against the paper's 10 N least tension


def heavy(model="catenary", w=W):
    def edit(d):
        d["robot"]["cable_weight_N_m"] = w
        d["simulation"]["plant"] = "own"
        d["simulation"]["cables"] = {"model": model, "stiffness_EA_N": EA}
    return make_scenario(edit)


@njit
def _cables(x, R, cat, L0):
    m = L0.shape[0]
    J, T = np.zeros((m, 6)), np.zeros(m)
    for i in range(m):
        J[i, 0] = 1.0
    catenary_cables(x, R, 0, cat, L0, np.zeros(m), J, T)
    return J, T


def _wrench(x, R, up, model, L0, w, EA_):
    return _cables(x, R, catenary_part(model, w, EA_, 0.0, up), L0)


def _reference_wrench(x, R, up, c_C, p_P, L0, w, EA_):
    """Sum of -(H e_h + V_B up) and its moments about P, from catenary_series (numpy geometry)."""
    b = x + p_P @ R.T
    d = b - c_C
    v = d @ up
    hv = d - v[:, None] * up
    h = np.linalg.norm(hv, axis=1)
    cat = catenary_series(h, v, w, EA_, L0=L0)
    assert np.all(cat.status == 0)
    f = -(cat.H[:, None] * hv / h[:, None] + cat.V_B[:, None] * up)
    r = b - x
    return np.concatenate([f.sum(axis=0), np.cross(r, f).sum(axis=0)]), cat


@pytest.mark.parametrize("seed", range(5))
def test_the_plants_wrench_is_the_catenaries(seed):
    """At random poses, up vectors (a rolling ship) and paid-out lengths (taut to sagging),
    J^T T of the part equals the catenaries' end forces summed independently, to 1e-9."""
    rng = np.random.default_rng(seed)
    sc = heavy()
    model = robot_model(sc)
    x = np.array([0.0, 0.0, 0.8]) + rng.uniform(-0.2, 0.2, 3) * [1, 0, 1]
    R = matrix_from_euler(np.array([[0.0, rng.uniform(-0.3, 0.3), 0.0]]))[0]
    up = matrix_from_euler(np.array([[rng.uniform(-0.2, 0.2), rng.uniform(-0.2, 0.2), 0.0]]))[0][2]
    chord = np.linalg.norm(x + model.p_P @ R.T - model.c_C, axis=1)
    L0 = chord * rng.uniform(0.995, 1.002, 4)
    J, T = _wrench(x, R, np.ascontiguousarray(up[None]), model, L0, W, EA)
    ref, cat = _reference_wrench(x, R, up, model.c_C, model.p_P, L0, W, EA)
    np.testing.assert_allclose(J.T @ T, ref, rtol=0, atol=1e-9 * np.abs(ref).max())
    np.testing.assert_allclose(T, cat.T_B, rtol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(J[:, :3], axis=1), 1.0, rtol=1e-12)


def test_weightless_catenaries_are_straight_elastic_cables():
    sc = heavy()
    model = robot_model(sc)
    x, R = np.array([0.1, 0.0, 0.9]), np.eye(3)
    L, J0 = np.empty(4), np.empty((4, 6))
    from marinecdpr.control.step import cables_at

    @njit
    def chord(x, R, model, L, J):
        cables_at(x, R, model, L, J)

    chord(x, R, model, L, J0)
    L0 = L / (1.0 + 100.0 / EA)  # 100 N in every cable
    J, T = _wrench(x, R, np.array([[0.0, 0.0, 1.0]]), model, L0, 1e-12, EA)
    np.testing.assert_allclose(T, EA * (L - L0) / L0, rtol=1e-9)
    np.testing.assert_allclose(J, J0, atol=1e-12)


def test_the_plans_sag_fed_forward_holds_the_heavy_cables(monkeypatch):
    """Open loop for 3 s on the own plant: a heavy rope sags by up to several mm at low
    tension. With the plan's sag fed to the winches the platform stays closer to the
    straight-cable run than without (the rest is the tangent's angle to the chord, which the
    plan does not see); the applied tension is the catenary's at the platform."""
    import marinecdpr.control.controller as C

    n = 3000
    straight = simulate(heavy("elastic"), run="open_loop", n_steps=n)
    sc = heavy()
    fed = simulate(sc, run="open_loop", n_steps=n)
    original = C.reference
    monkeypatch.setattr(C, "reference", lambda ff, sag=False: original(ff, sag=False))
    blind = simulate(sc, run="open_loop", n_steps=n)
    gap = [float(np.abs(r.pose - straight.pose)[:, :3].max()) for r in (fed, blind)]
    assert gap[0] < 0.6 * gap[1] and gap[1] > 1e-4
    assert np.abs(straight.pose_error[:, :3]).max() < 1e-5
    p = marinecdpr.plan(sc)
    assert np.nanmax(p.sag.lengths) > 2e-3  # what the winches pay out for the sag


@pytest.mark.parametrize("edit, says", [
    (lambda d: d["simulation"].update(cables={"model": "catenary", "stiffness_EA_N": EA}, plant="own"),
     r"robot\.cable_weight_N_m: missing: catenary cables"),
    (lambda d: (d["robot"].update(cable_weight_N_m=W), d["simulation"].update(cables={"model": "catenary", "stiffness_EA_N": EA})),
     r"simulation\.plant: must be \"own\" for catenary cables"),
    (lambda d: (d["robot"].update(cable_weight_N_m=W),
                d["simulation"].update(plant="own", cables={"model": "catenary", "stiffness_EA_N": EA, "winch": "tension"})),
     r"simulation\.cables\.winch: must be \"length\" or \"motor\" for catenary cables"),
    (lambda d: (d["robot"].update(cable_weight_N_m=W),
                d["simulation"].update(plant="own", cables={"model": "catenary"})),
     r"simulation\.cables\.stiffness_EA_N: missing: a catenary cable"),
    (lambda d: (d["robot"].update(cable_weight_N_m=W),
                d["simulation"].update(plant="own", cables={"model": "catenary", "stiffness_EA_N": EA},
                                       sensors={"pose_from": "encoders"})),
     r"simulation\.sensors\.pose_from: the encoders' pose with catenary cables is not supported yet"),
])
def test_catenary_cables_need_their_weight_and_the_own_plant(edit, says):
    with pytest.raises(ScenarioError, match=says):
        make_scenario(edit)


def test_mujoco_refuses_catenary_cables():
    with pytest.raises(ScenarioError, match="catenary cables need the own plant"):
        simulate(heavy(), run="open_loop", plant="mujoco", n_steps=10)
