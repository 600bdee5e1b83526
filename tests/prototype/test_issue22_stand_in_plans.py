"""Issue 22, item 2: the planner, the controller and the loop compile at once, because a
prototype built on stand-in plans (no planner kernel run) has every part's type of a
real run's: whatever compiles for it is what the real run takes.

The check is numba's own type of the assembled system (every part's record, the bus, the
controller's records in their list): equal, for every built-in scenario and run, and for
scenarios with heavy catenary cables, pulleys, motor winches, encoders and a predictor.
"""

from __future__ import annotations

import numba
import numpy as np
import pytest

import marinecdpr
from marinecdpr.planning.planner import plan_at, stand_in_plan
from marinecdpr.prototype.simulation import RUNS, prototype, simulate

from conftest import make_scenario

N = 4


def _heavy(d):
    d["robot"]["cable_weight_N_m"] = 3.5
    d["simulation"]["plant"] = "own"
    d["simulation"]["cables"] = {"model": "catenary", "stiffness_EA_N": 1.0e5}


def _pulleys(d):
    for cable in d["robot"]["cables"]:
        cable["pulley_radius_m"] = 0.05
        cable["pulley_axis"] = [0.0, 0.0, 1.0]


def _sensing(d):
    d["simulation"]["sensors"] = {"pose_from": "encoders"}
    d["simulation"]["mru"] = {"prediction": "ar", "latency_s": 0.05}


EDITED = {"catenary": _heavy, "pulleys": _pulleys, "encoders_and_ar": _sensing}


def _scenarios():
    for name in marinecdpr.builtin_scenarios():
        yield name, marinecdpr.load_scenario(name)
    for name, edit in EDITED.items():
        yield name, make_scenario(edit)


@pytest.mark.parametrize("name,sc", list(_scenarios()), ids=lambda v: v if isinstance(v, str) else "")
def test_a_prototype_on_stand_in_plans_has_a_real_runs_types(name, sc):
    for run in RUNS:
        real = prototype(sc, run, N)
        stand_in = prototype(sc, run, N, stand_in=True)
        assert numba.typeof(stand_in.system) == numba.typeof(real.system), (name, run)


def test_a_stand_in_plan_has_the_plans_fields_and_the_trajectorys_motion(paper):
    t = np.arange(N) * paper.time.step_s
    real, stand_in = plan_at(paper, t), stand_in_plan(paper, t)
    for field in ("t", "pose", "twist", "twist_dot", "lengths", "length_rates"):  # kinematics: the plan's own
        np.testing.assert_array_equal(getattr(stand_in, field), getattr(real, field))
    r = paper.robot
    assert np.all(stand_in.tensions == 0.5 * (r.tension_min + r.tension_max))
    assert stand_in.feasible.all() and not np.any(stand_in.wrench)
    for field in ("tensions", "wrench", "reaction", "tensions_pinv"):
        assert getattr(stand_in, field).shape == getattr(real, field).shape
    assert (stand_in.method, stand_in.base_model, stand_in.reaction_dofs) == (
        real.method, real.base_model, real.reaction_dofs)


def test_a_stand_in_run_flies_no_reference(paper, paper_plan):
    with pytest.raises(ValueError, match="stand-in"):
        simulate(paper, reference=paper_plan, n_steps=3, stand_in=True)


@pytest.mark.parametrize("name", ["paper", "paper_as_built"])
def test_the_tension_solver_compiled_ahead_is_the_one_the_controllers_step_calls(name):
    # compile_apart's planner copy compiles tensions_step for these arguments, and the
    # controller's copy loads it: their types must be those the step passes
    from marinecdpr.control.controller import Controller
    from marinecdpr.prototype.warmup import tension_solver_args

    sc = marinecdpr.load_scenario(name)
    ctl = Controller(sc, n_steps=N).parts
    passed = (ctl.work.J, ctl.work.wrench, ctl.model.controlled, ctl.model.lo, ctl.model.hi, ctl.model.method,
              ctl.cmd.T_cmd, ctl.work.tension)
    assert [numba.typeof(a) for a in tension_solver_args(sc)] == [numba.typeof(a) for a in passed]
