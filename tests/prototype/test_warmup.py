"""The first run compiles on two cores (issue 22, item 2): the loop calls the controller
through a function pointer, so the two compile apart (the controller's step in a forked
copy, the loop here with a stand-in of the controller's type); the stand-in has the real
step's type, steps nothing, and never reaches a run."""

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
