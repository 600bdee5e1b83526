"""The paper's example end to end, and plan-level properties."""

import numpy as np
import pytest

import marinecdpr
from marinecdpr.scenario.fields import TENSION_METHODS
from marinecdpr.planning.planner import plan_at

from conftest import make_scenario


def test_structure_equation_holds_at_every_step(paper, paper_plan):
    """J~^T T = w in the controlled DOFs, for the plan and for eq. (18)."""
    from marinecdpr.geometry.kinematics import cable_kinematics
    from marinecdpr.motion.trajectory import evaluate_trajectory

    plat = evaluate_trajectory(paper.trajectory, paper_plan.t)
    r = paper.robot
    J = cable_kinematics(plat.x_PC_C, plat.R_PC, r.frame_anchors, r.platform_anchors).J_tilde
    c = list(r.controlled)
    for T in (paper_plan.tensions, paper_plan.tensions_pinv):
        np.testing.assert_allclose(np.einsum("nmk,nm->nk", J, T)[:, c], paper_plan.wrench[:, c],
                                   atol=1e-9)


def test_paper_qualitative_results(paper_plan):
    """Figure 5: eq. (18) goes negative; optimised in [10, 450] N; cables 1, 2 pull harder at t = 0."""
    assert paper_plan.tensions_pinv.min() < 0.0
    assert paper_plan.all_feasible
    assert paper_plan.tensions.min() >= 10.0 - 1e-9 and paper_plan.tensions.max() <= 450.0 + 1e-9
    T0 = paper_plan.tensions[0]
    assert min(T0[0], T0[1]) > max(T0[2], T0[3])
    # continuity: no jump between 1 ms steps larger than the motion explains
    assert np.abs(np.diff(paper_plan.tensions, axis=0)).max() < 1.0


def test_planar_reaction_is_what_the_cables_cannot_supply(paper_plan):
    """On a rolling ship gravity leans out of the robot's plane: the guide takes F_y."""
    assert paper_plan.reaction_dofs == ("y", "rx", "rz")
    np.testing.assert_allclose(paper_plan.reaction, paper_plan.wrench[:, [1, 3, 5]], atol=1e-9)
    assert np.abs(paper_plan.reaction[:, 0]).max() > 5.0  # ~ m g sin(6 deg) = 5.1 N and more


def test_fixed_base_plan_differs_from_moving_base(paper, paper_plan):
    fixed = marinecdpr.plan(paper, base_model="fixed")
    assert fixed.base_model == "fixed" and fixed.all_feasible
    assert not fixed.C_s.any()
    # ignoring the ship changes the required wrench by newtons: that is the paper's point
    assert np.abs(fixed.wrench - paper_plan.wrench).max() > 5.0
    np.testing.assert_allclose(fixed.lengths, paper_plan.lengths)  # kinematics in C is the same


def test_chunking_does_not_change_the_plan(paper, paper_plan):
    chunked = marinecdpr.plan(paper, chunk_steps=1000)
    for name in ("tensions", "tensions_pinv", "lengths", "wrench", "reaction"):
        np.testing.assert_array_equal(getattr(chunked, name), getattr(paper_plan, name))
    pieces = list(marinecdpr.iter_plan(paper, chunk_steps=4096))
    assert [p.n_steps for p in pieces] == [4096, 4096, 4096, 2713]
    np.testing.assert_array_equal(np.concatenate([p.tensions for p in pieces]), paper_plan.tensions)


@pytest.mark.parametrize("method", TENSION_METHODS)
def test_every_method_on_the_paper_scenario(paper, method):
    p = marinecdpr.plan(paper, method=method)
    ok = p.feasible
    T = p.tensions[ok]
    assert np.all(T >= 10.0 - 1e-9) and np.all(T <= 450.0 + 1e-9)
    if method == "pseudo_inverse":
        assert not p.all_feasible  # negative tensions: figure 5(a)
    elif method == "closed_form":
        # Pott's closed form is minimum variance without limits: it fails exactly where
        # the minimum-variance solution rests on a limit (cable 2 near t = 8 s).
        mv = marinecdpr.plan(paper, method="minimum_variance").tensions
        at_limit = np.any(np.isclose(mv, 10.0, atol=1e-6) | np.isclose(mv, 450.0, atol=1e-6), axis=1)
        assert at_limit.any()
        np.testing.assert_array_equal(p.feasible[~at_limit], True)
        assert not p.feasible[at_limit & (np.min(mv, axis=1) < 10.0 - 1e-3)].any()
        assert p.feasible.sum() >= 0.9 * p.n_steps
    else:
        assert p.all_feasible, method


def test_overloaded_platform_is_reported_not_crashed():
    sc = make_scenario(lambda d: d["robot"].update(mass_kg=200.0))
    p = marinecdpr.plan(sc)
    assert not p.all_feasible
    msg = p.infeasibility()
    assert msg.startswith("the cables cannot hold the platform") and "t = 0 s" in msg
    assert np.isnan(p.tensions[~p.feasible]).all()


def test_disturbance_adds_to_the_wrench_in_its_frame(paper, paper_plan):
    sc = make_scenario(lambda d: d["disturbance"].update(frame="C", force_N=[3.0, 0.0, -2.0],
                                                         moment_N_m=[0.0, 0.5, 0.0]))
    p = marinecdpr.plan(sc)
    np.testing.assert_allclose(p.wrench - paper_plan.wrench,
                               np.broadcast_to([-3.0, 0, 2.0, 0, -0.5, 0], p.wrench.shape), atol=1e-9)


def test_spatial_robot_plans_with_redundancy_two():
    """An 8-cable spatial robot (r = 2) on the paper's sea, waypoints with rotation."""
    corners = [(x, y, z) for x in (0.0, 2.0) for y in (0.0, 2.0) for z in (0.0, 2.0)]
    # crossed in x: anchors on the diagonals towards their corners would give a singular J~
    plat = [(-0.1 if x else 0.1, 0.1 if y else -0.1, 0.15 if z else -0.15) for x, y, z in corners]

    def edit(d):
        d["robot"] = dict(dofs="spatial", mass_kg=5.0, inertia_kg_m2=[0.05, 0.05, 0.05],
                          tension_min_N=10.0, tension_max_N=450.0,
                          cables=[dict(frame_anchor_m=list(c), platform_anchor_m=list(p))
                                  for c, p in zip(corners, plat)])
        d["trajectory"] = dict(type="waypoints", waypoints=[
            dict(time_s=0.0, position_m=[1.0, 1.0, 1.0]),
            dict(time_s=1.0, position_m=[1.2, 0.9, 1.1], orientation_deg=[5.0, -5.0, 10.0]),
            dict(time_s=2.0, position_m=[1.0, 1.0, 1.0])])
        d["time"] = dict(step_s=0.01, duration_s=2.0)

    sc = make_scenario(edit)
    for method in ("minimum_variance", "minimum_norm", "improved_closed_form"):
        p = marinecdpr.plan(sc, method=method)
        assert p.all_feasible and p.reaction.shape == (201, 0)
        assert np.all(p.tensions >= 10.0 - 1e-9) and np.all(p.tensions <= 450.0 + 1e-9)
    # minimum norm rests on T_min: the exact QP path for r > 1 is exercised
    assert np.isclose(marinecdpr.plan(sc, method="minimum_norm").tensions, 10.0).any()


def test_a_plan_s_piece_is_the_plan_of_those_steps():
    """Plan.take (issue 38, item 5: the core plan and its records): the steps of a plan with
    winches, heavy cables and clearances are the plan of those steps, every record sliced."""
    sc = marinecdpr.load_scenario("paper_as_built").with_updates("robot", clearance_m=0.05)
    sc = sc.with_changes(time={"step_s": sc.time.step_s, "duration_s": 0.5})
    whole = marinecdpr.plan(sc)
    assert whole.winch is not None and whole.sag is not None and whole.clearances is not None
    part = plan_at(sc, whole.t[100:140])
    piece = whole.take(slice(100, 140))
    for name in ("t", "pose", "lengths", "tensions", "tensions_pinv", "wrench", "feasible"):
        np.testing.assert_array_equal(getattr(piece, name), getattr(part, name))
    for record, names in (("winch", ("length_accelerations", "lower", "upper", "limit")),
                          ("sag", ("lengths", "winch_tensions")),
                          ("clearances", ("cable_cable", "cable_platform", "cable_obstacle"))):
        for name in names:
            a, b = getattr(getattr(piece, record), name), getattr(getattr(part, record), name)
            if record == "winch" and name in ("length_accelerations", "lower", "upper", "limit"):
                a, b = a[1:-1], b[1:-1]  # L'' by central differences: the piece's ends see one side only
            np.testing.assert_array_equal(a, b)
    np.testing.assert_array_equal(piece.clearance, part.clearance)
    assert piece.take(slice(0, 1)).winch.lower.shape == (1, 4)
