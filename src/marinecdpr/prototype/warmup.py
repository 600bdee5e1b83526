"""Compile, once, everything the virtual prototype needs for a set of scenarios.

The first run of a prototype compiles its loop (numba, cached on disk:
:mod:`marinecdpr.compiled_cache`); :func:`warm_up` does that ahead, by flying a few steps
of each scenario on its plant, open and closed loop, so that a later run (a demonstration,
a sweep's workers, a CI job) starts at once. What a run compiles depends on its parts
(cables, winches, brush, sensors, predictor), so each scenario is flown as it is described.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Callable

import numpy as np

__all__ = ["WarmUp", "warm_up", "warmup_jobs", "compile_apart", "compile_at_once", "planner_copy", "stand_in_held",
           "controller_copy", "tension_solver_args", "WARMUP_STEPS"]

WARMUP_STEPS = 3
"""Steps flown per run: enough to run every part's step once."""


@dataclass(frozen=True)
class WarmUp:
    """What :func:`warm_up` did: each (scenario, plant, run) flown and the seconds it took
    (compiling, or loading from the cache), and the cache folder."""

    runs: tuple[tuple[str, str, str, float], ...]
    seconds: float
    cache_dir: str


def warm_up(scenarios, *, plants: tuple[str, ...] | None = None,
            progress: Callable[[int, int, str], None] | None = None) -> WarmUp:
    """Fly :data:`WARMUP_STEPS` steps of each scenario, open and closed loop, on its plant
    (or each of ``plants``), compiling what is not cached yet.

    Parameters
    ----------
    scenarios : sequence of Scenario
    plants : tuple of {"mujoco", "own"}, optional
        Default: each scenario's ``simulation.plant`` (the own plant for catenary cables).
    progress : callable(done, total, what), optional
        Called before each run.

    Returns
    -------
    WarmUp
    """
    from marinecdpr.compiled_cache import cache_dir
    from marinecdpr.prototype.simulation import simulate

    jobs = warmup_jobs(scenarios, plants=plants)
    done, t0 = [], time.perf_counter()
    for i, (sc, plant, run) in enumerate(jobs):
        if progress is not None:
            progress(i, len(jobs), f"{sc.name}: {plant} {run.replace('_', ' ')}")
        t1 = time.perf_counter()
        if run == "open_loop":  # on a cold cache, the planner, the controller and the loop at once
            compile_apart(sc, plant=plant)
        simulate(sc, run=run, plant=plant, n_steps=WARMUP_STEPS)
        done.append((sc.name, plant, run, time.perf_counter() - t1))
    if progress is not None:
        progress(len(jobs), len(jobs), "done")
    return WarmUp(runs=tuple(done), seconds=time.perf_counter() - t0, cache_dir=str(cache_dir()))


def warmup_jobs(scenarios, *, plants: tuple[str, ...] | None = None) -> list[tuple]:
    """The runs :func:`warm_up` flies, in order: (scenario, plant, run) for each scenario, each
    of ``plants`` (default: the scenario's ``simulation.plant``; MuJoCo left out for catenary
    cables, which only the own plant flies), open and closed loop."""
    jobs = []
    for sc in scenarios:
        own_only = sc.simulation.cables.model == "catenary"
        for plant in (plants or (sc.simulation.plant,)):
            if plant == "mujoco" and own_only:
                continue
            for run in ("open_loop", "closed_loop"):
                jobs.append((sc, plant, run))
    return jobs


def tension_solver_args(scenario) -> tuple:
    """Arguments of the controller's per-step tension solver
    (:func:`~marinecdpr.model.tension_solver.tensions_step`) with the types its step passes: J~,
    the wrench, the controlled DOFs, the limits, the method, the tensions and their working
    memory, as :func:`~marinecdpr.control.controller.controller_parts` makes them."""
    from marinecdpr.control.controller import robot_model
    from marinecdpr.model.tension_solver import tension_work

    model = robot_model(scenario)
    m, k = scenario.robot.n_cables, len(scenario.robot.controlled)
    return (np.zeros((m, 6)), np.zeros(6), model.controlled, model.lo, model.hi, model.method, np.zeros(m),
            tension_work(m, k))


def planner_copy(scenario, n: int, solver_ready) -> None:
    """The planner's share of compiling a first run at once (:func:`compile_apart`): the
    per-step tension solver for the controller's types (:func:`tension_solver_args`), then
    ``solver_ready`` set (a ``multiprocessing`` event: a copy compiling the controller's
    step waits for it, to load the solver from the cache rather than compile it again; set
    even if that failed), then the plan of n steps on moving and fixed bases (the planner's
    kernels, whose types do not depend on n, sharing the solver's), and the controller's
    records put in their list on stand-in plans (its unboxing of ~90 arrays)."""
    from marinecdpr.compiled_cache import entry_point
    from marinecdpr.control.controller import controller_records, held_records, stand_in_plans, types_only
    from marinecdpr.model.tension_solver import tensions_step
    from marinecdpr.planning.planner import plan_at

    try:
        entry_point(tensions_step, tension_solver_args(scenario))
    finally:
        solver_ready.set()
    for base_model in ("moving", "fixed"):
        plan_at(scenario, np.arange(n) * scenario.time.step_s, base_model=base_model)
    with types_only():
        records = controller_records(scenario, stand_in_plans(scenario, n), n, closed=False)
    entry_point(held_records, (records,))


def stand_in_held(scenario, n: int):
    """An empty typed list of the type of the controller's records' list
    (:func:`~marinecdpr.control.controller.held_records`) for n steps, from stand-in plans: what a
    step is compiled for, without compiling the records' unboxing."""
    from numba import typeof
    from numba.typed import List

    from marinecdpr.control.controller import controller_records, stand_in_plans, types_only

    with types_only():
        return List.empty_list(typeof(controller_records(scenario, stand_in_plans(scenario, n), n, closed=False)))


def controller_copy(scenario, n: int) -> None:
    """The controller's share of compiling a first run at once (:func:`compile_apart`): its
    step for its records' type (:func:`stand_in_held`), then what only some controllers
    have, for this scenario's (its predictor's and its encoders' slots:
    :func:`~marinecdpr.control.controller.slot`), on stand-in plans."""
    from marinecdpr.control.controller import controller_records, stand_in_plans
    from marinecdpr.prototype.parts.controller import pointer_step

    pointer_step(stand_in_held(scenario, n))
    controller_records(scenario, stand_in_plans(scenario, n), n, closed=False)


def compile_at_once(scenario, n: int, *, step: Callable[[], None], here: Callable[[], None]) -> None:
    """Run :func:`planner_copy` in a forked copy, ``step`` (compiling a controller's step)
    in a second copy once the tension solver is in the cache, and ``here`` in this process,
    all at once; wait for both copies (their exceptions raised here), and end them in any
    case. The caller has checked :func:`~marinecdpr.forked.can_fork`."""
    import multiprocessing

    from marinecdpr import forked

    solver_ready = multiprocessing.get_context("fork").Event()

    def after_solver() -> None:
        solver_ready.wait(600.0)
        step()

    apart = [forked.Forked(lambda: planner_copy(scenario, n, solver_ready)), forked.Forked(after_solver)]
    try:
        here()
        for job in apart:
            job.result()
    finally:
        for job in apart:
            job.stop()


def compile_apart(scenario, *, plant: str | None = None) -> bool:
    """Compile the scenario's first run in three processes at once: the planner's kernels
    in a forked copy of this process, the controller's step in a second copy, and the loop
    here. Each builds what it compiles on stand-in plans where it needs plans
    (:func:`~marinecdpr.control.controller.stand_in_plans`: a real run's types, no
    planner kernel run), so none waits for a plan:

    * the planner's copy first compiles the per-step tension solver for the controller's
      types (:func:`tension_solver_args`), whose solvers the plan's series shares, then
      plans a few steps, moving and fixed base, and puts the controller's records in their
      list (:func:`~marinecdpr.control.controller.controller_records`);
    * the controller's copy waits for the tension solver to be in numba's cache, then
      compiles the controller's step for its records' type
      (:func:`~marinecdpr.prototype.parts.controller.pointer_step`, on an empty list of
      that type), loading the solver rather than compiling it a second time;
    * here, :data:`WARMUP_STEPS` steps are flown on stand-in plans with a stand-in
      controller of the controller's type
      (:func:`~marinecdpr.prototype.parts.controller.stand_in`): the loop compiled.

    The copies' code lands in numba's cache (saves under a lock:
    :func:`~marinecdpr.compiled_cache.lock_saves`), where the run's plan and prototype
    find it; this process holds the loop. Returns False (nothing done) where the loop is
    cached already (:func:`~marinecdpr.prototype.simulation.kernels_cached`) or work
    cannot go to a forked process.

    Parameters
    ----------
    scenario : Scenario
    plant : {"mujoco", "own"}, optional
        Default ``scenario.simulation.plant``.
    """
    from marinecdpr import forked
    from marinecdpr.prototype.parts.controller import stand_in
    from marinecdpr.prototype.simulation import kernels_cached, simulate

    if kernels_cached(plant or scenario.simulation.plant) or not forked.can_fork():
        return False
    n = min(WARMUP_STEPS, scenario.time.n_steps)

    def here() -> None:
        with stand_in():
            simulate(scenario, run="open_loop", plant=plant, n_steps=n, stand_in=True)

    compile_at_once(scenario, n, step=lambda: controller_copy(scenario, n), here=here)
    return True
