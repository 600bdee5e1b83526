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

__all__ = ["WarmUp", "warm_up", "compile_apart", "WARMUP_STEPS"]

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

    jobs = []
    for sc in scenarios:
        own_only = sc.simulation.cables.model == "catenary"
        for plant in (plants or (sc.simulation.plant,)):
            if plant == "mujoco" and own_only:
                continue
            for run in ("open_loop", "closed_loop"):
                jobs.append((sc, plant, run))
    done, t0 = [], time.perf_counter()
    for i, (sc, plant, run) in enumerate(jobs):
        if progress is not None:
            progress(i, len(jobs), f"{sc.name}: {plant} {run.replace('_', ' ')}")
        t1 = time.perf_counter()
        if run == "open_loop":  # on a cold cache, the controller and the loop side by side
            compile_apart(sc, reference=None, plant=plant)
        simulate(sc, run=run, plant=plant, n_steps=WARMUP_STEPS)
        done.append((sc.name, plant, run, time.perf_counter() - t1))
    if progress is not None:
        progress(len(jobs), len(jobs), "done")
    return WarmUp(runs=tuple(done), seconds=time.perf_counter() - t0, cache_dir=str(cache_dir()))


def compile_apart(scenario, *, reference, plant: str | None = None) -> bool:
    """Compile the scenario's prototype on two cores: its controller's step in a forked copy
    of this process (:func:`~marinecdpr.forked.Forked`), the loop here (flying
    :data:`WARMUP_STEPS` steps with a stand-in controller of the same type,
    :func:`~marinecdpr.prototype.parts.controller.stand_in`). Both land in numba's cache,
    where the next build of the prototype finds the controller and this process holds the
    loop. Returns False (nothing done) where the loop is cached already
    (:func:`~marinecdpr.prototype.simulation.kernels_cached`) or work cannot go to a forked
    process.

    Parameters
    ----------
    scenario : Scenario
    reference : Plan or None
        The moving-base plan (its types are the prototype's); None: each half plans the
        few steps it flies.
    plant : {"mujoco", "own"}, optional
        Default ``scenario.simulation.plant``.
    """
    from marinecdpr import forked
    from marinecdpr.prototype.parts.controller import stand_in
    from marinecdpr.prototype.simulation import kernels_cached, prototype, simulate

    if kernels_cached(plant or scenario.simulation.plant) or not forked.can_fork():
        return False

    def build() -> None:  # every part built: the controller's step compiled (and cached), no flight
        prototype(scenario, "open_loop", WARMUP_STEPS, reference=reference)

    apart = forked.Forked(build)
    try:
        with stand_in():
            simulate(scenario, run="open_loop", reference=reference, plant=plant, n_steps=WARMUP_STEPS)
        apart.result()
    finally:
        apart.stop()
    return True
