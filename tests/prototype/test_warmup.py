"""The first run compiles on two cores (issue 22, item 2): the loop calls the controller
through a function pointer, so the two compile apart (the controller's step in a forked
copy, the loop here with a stand-in of the controller's type); the stand-in has the real
step's type, steps nothing, and never reaches a run."""

from __future__ import annotations

import hashlib
import subprocess
import sys

import numba
import numpy as np

import marinecdpr
from marinecdpr.prototype.parts import controller as controller_part
from marinecdpr.prototype.simulation import prototype, simulate


def _digest(res) -> str:
    h = hashlib.sha256()
    for a in (res.pose, res.lengths, res.tensions_commanded, res.tensions):
        h.update(np.ascontiguousarray(a).tobytes())
    return h.hexdigest()


def test_the_stand_in_has_the_controllers_type_and_steps_nothing():
    sc = marinecdpr.load_scenario("paper")
    p = marinecdpr.plan(sc)
    real = prototype(sc, "closed_loop", 3, reference=p).get("ControllerPart")
    with controller_part.stand_in():
        stand_in = prototype(sc, "closed_loop", 3, reference=p).get("ControllerPart")
    assert numba.typeof(stand_in.step) == numba.typeof(real.step)  # the loop compiled for it is the real loop
    assert numba.typeof(stand_in.held) == numba.typeof(real.held)
    assert len(stand_in.held) == 0 and len(real.held) == 1
    assert stand_in.step is not real.step
    with controller_part.stand_in():
        held = simulate(sc, run="closed_loop", reference=p, n_steps=20)
    flown = simulate(sc, run="closed_loop", reference=p, n_steps=20)
    # the stand-in commands nothing (the loop's zeroed commands); the controller commands the
    # plan's tensions corrected by its feedback, within the cables' limits
    assert np.all(held.tensions_commanded == 0.0)
    lo, hi = sc.robot.tension_min_N, sc.robot.tension_max_N
    assert np.all((flown.tensions_commanded >= lo) & (flown.tensions_commanded <= hi))
    np.testing.assert_allclose(flown.tensions_commanded[0], p.tensions[0], rtol=0.05)
    # and after it, a run builds the real controller again
    again = simulate(sc, run="closed_loop", reference=p, n_steps=20)
    assert _digest(again) == _digest(flown)


def test_a_run_after_compiling_apart_is_the_run_without_it():
    # in a process of its own (no other thread: the copy is forked), compile apart, then fly
    script = """
import hashlib, numpy as np, marinecdpr
from marinecdpr.prototype import simulation
from marinecdpr.prototype.simulation import simulate
from marinecdpr.prototype.warmup import compile_apart
simulation.kernels_cached = lambda plant: False  # as on a cold cache, whatever this one holds
sc = marinecdpr.load_scenario("paper")
p = marinecdpr.plan(sc)
print(compile_apart(sc))
res = simulate(sc, run="closed_loop", reference=p, n_steps=300)
h = hashlib.sha256()
for a in (res.pose, res.lengths, res.tensions_commanded, res.tensions):
    h.update(np.ascontiguousarray(a).tobytes())
print(h.hexdigest())
"""
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr
    forked, digest = out.stdout.split()
    assert forked == "True"  # a process without threads on this 2-core machine forks
    sc = marinecdpr.load_scenario("paper")
    res = simulate(sc, run="closed_loop", reference=marinecdpr.plan(sc), n_steps=300)
    assert digest == _digest(res)


def test_the_readme_gives_the_first_compile_the_notice_gives():
    from pathlib import Path

    from marinecdpr.prototype.simulation import KERNEL_COMPILE_S

    readme = (Path(__file__).resolve().parents[2] / "README.md").read_text()
    assert f"compiles the per-step kernels (about {KERNEL_COMPILE_S:g} s, once)" in readme


def test_the_readme_gives_latencys_first_compile_the_notice_gives():
    from pathlib import Path

    from marinecdpr.studies.latency import LATENCY_COMPILE_S

    readme = (Path(__file__).resolve().parents[2] / "README.md").read_text()
    assert f"`latency` first compiles the controller's step for about {LATENCY_COMPILE_S:g} s" in readme


def test_latency_compiled_apart_on_stand_in_records_is_what_its_run_takes():
    # the stand-in records' list has the real Controller's type (its entry point compiled
    # for it in a copy is the one the run loads) ...
    from marinecdpr.control.controller import Controller
    from marinecdpr.prototype.warmup import stand_in_held

    sc = marinecdpr.load_scenario("paper")
    stand_in = stand_in_held(sc, 3)
    assert len(stand_in) == 0
    assert numba.typeof(stand_in) == numba.typeof(Controller(sc, n_steps=3).held)
    # ... and in a process of its own, compiling apart leaves the run nothing to compile
    script = """
import marinecdpr
from marinecdpr.studies import latency
latency.latency_kernels_cached = lambda: False  # as on a cold cache, whatever this one holds
sc = marinecdpr.load_scenario("paper")
print(latency.compile_apart(sc), len(latency._timed_steps.signatures))
lat = latency.controller_latency(sc, calls=50)
print(len(latency._timed_steps.signatures), lat.compiled_p50_us > 0.0)
"""
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr
    assert out.stdout.split() == ["True", "1", "1", "True"]


def test_compiling_apart_does_nothing_where_the_loop_is_cached():
    from marinecdpr.prototype.simulation import kernels_cached
    from marinecdpr.prototype.warmup import compile_apart

    sc = marinecdpr.load_scenario("paper")
    simulate(sc, run="open_loop", n_steps=3)  # compiled or loaded: the loop is cached now
    assert kernels_cached("mujoco")
    assert compile_apart(sc) is False


# -------------------- formerly tests/test_issue22_stand_in_plans.py

"""Issue 22, item 2: the planner, the controller and the loop compile at once, because a
prototype built on stand-in plans (no planner kernel run) has every part's type of a
real run's: whatever compiles for it is what the real run takes.

The check is numba's own type of the assembled system (every part's record, the bus, the
controller's records in their list): equal, for every built-in scenario and run, and for
scenarios with heavy catenary cables, pulleys, motor winches, encoders and a predictor.
"""


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
