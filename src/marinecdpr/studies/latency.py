"""How long the controller's step takes on this machine (``marinecdpr latency``).

Along the scenario's plan (the plan at t_k as the measurement, so that every step solves a
real error), :func:`controller_latency` times :meth:`Controller.step
<marinecdpr.control.controller.Controller.step>` called from Python (``time.perf_counter_ns``
around each call) and :func:`~marinecdpr.control.step.control_step` inside a compiled loop
(the processor's time-stamp counter around each call, calibrated against the wall clock),
and one quadprog solve of the same steps' tension problem for comparison (minimum
distance to the method's target under the equality J~^T T = w and the limits; quadprog is
the ``bench`` extra).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
from llvmlite import ir
from numba import njit, types
from numba.core import cgutils
from numba.extending import intrinsic

from marinecdpr.borrowed import borrowed_first
from marinecdpr.control import Controller
from marinecdpr.control.controller import plans
from marinecdpr.control.step import control_step
from marinecdpr.geometry.rotations import matrix_from_euler
from marinecdpr.motion.basemotion import frame_ship_motion
from marinecdpr.planning.budget import check_latency_calls
from marinecdpr.scenario.schema import Scenario

__all__ = ["Latency", "controller_latency", "compile_apart", "quadprog_problem"]


@dataclass(frozen=True)
class Latency:
    """Per-call times of the controller's step, microseconds (percentiles over the calls).

    quadprog_p50_us is None where quadprog is not installed.
    """

    scenario: str
    method: str
    cables: int
    redundancy: int
    calls: int
    python_p50_us: float
    python_p99_us: float
    python_max_us: float
    compiled_p50_us: float
    compiled_p99_us: float
    compiled_max_us: float
    quadprog_p50_us: float | None


@intrinsic
def _cycles(typingctx):
    """The processor's cycle (time-stamp) counter."""
    def codegen(context, builder, signature, args):
        fn = cgutils.get_or_insert_function(builder.module, ir.FunctionType(ir.IntType(64), []),
                                            "llvm.readcyclecounter")
        return builder.call(fn, [])

    return types.uint64(), codegen


@njit(cache=True)
def _counter():
    return _cycles()


@njit(cache=True)
def _timed_steps(h, held, x, R, v, w, eta, ticks):
    """control_step over the measurements (rows cycled over the plan), each call's ticks;
    ``held``: the controller's records in their one-item list (as the prototype holds them)."""
    ctl = borrowed_first(held)  # as the prototype's loops: no reference counting per step
    meas = ctl.meas
    n = x.shape[0]
    for c in range(ticks.shape[0]):
        k = c % n
        for i in range(3):
            meas.x[i] = x[k, i]
            meas.v[i] = v[k, i]
            meas.w[i] = w[k, i]
            meas.clock[i] = k * h
            for j in range(3):
                meas.R[i, j] = R[k, i, j]
        for j in range(3):
            for i in range(6):
                meas.eta[j, i] = eta[k, j, i]
        t0 = _cycles()
        control_step(k, h, held)
        ticks[c] = _cycles() - t0


def _ticks_per_us() -> float:
    a, t0 = _counter(), time.perf_counter()
    time.sleep(0.2)
    b, t1 = _counter(), time.perf_counter()
    return (b - a) / ((t1 - t0) * 1e6)


def quadprog_problem(ctl: Controller) -> tuple:
    """The tension problem of the controller's last step as quadprog's arguments
    (G, a, C, b, meq): minimise |T - target|^2 / 2 subject to the controlled rows of
    J~^T T = w and lo <= T <= hi, the target the method's (the middle of the limits for the
    minimum-variance methods, zero for minimum norm)."""
    model, work = ctl.parts.model, ctl.parts.work
    dofs = model.controlled
    lo, hi = model.lo, model.hi
    target = 0.5 * (lo + hi) if model.method in (1, 2, 4) else np.zeros_like(lo)
    A = work.J[:, dofs]
    m, k = A.shape
    C = np.hstack([A, np.eye(m), -np.eye(m)])
    return np.eye(m), target, C, np.concatenate([work.wrench[dofs], lo, -hi]), k


def _quadprog_p50_us(ctl: Controller, calls: int) -> float | None:
    """quadprog on the tension problem of the controller's last step: the median of
    repeated solves, us; None without quadprog."""
    try:
        import quadprog
    except ImportError:
        return None
    problem = quadprog_problem(ctl)
    times = []
    for _ in range(min(calls, 2000)):
        t0 = time.perf_counter_ns()
        try:
            quadprog.solve_qp(*problem)
        except ValueError:  # infeasible: timed all the same
            pass
        times.append(time.perf_counter_ns() - t0)
    return float(np.percentile(times, 50)) / 1e3


LATENCY_COMPILE_S = 20.0
"""About how long ``marinecdpr latency`` first compiles the controller's step and its timed
loop on a fresh install, s (measured for ``latency paper`` with an empty cache, 2-core CI
machine, 2026-12-04: 20.3 s compiling at once (:func:`compile_apart`), 26.1 s in turn; 62 s on
2026-12-03, before the controller's records were passed by list)."""


def latency_kernels_cached() -> bool:
    """False if timing the controller must first compile its step and the timed loop
    (:func:`~marinecdpr.prototype.simulation.compiled_cached`)."""
    from marinecdpr.control.controller import step_from_arrays
    from marinecdpr.prototype.simulation import compiled_cached

    return compiled_cached(step_from_arrays, _timed_steps)


def compile_apart(scenario: Scenario) -> bool:
    """On a cold cache, compile what timing the controller takes in three processes at once,
    on stand-in records of the scenario's types
    (:func:`~marinecdpr.control.controller.stand_in_plans`): the planner's kernels and the
    records' list in a forked copy (:func:`~marinecdpr.prototype.warmup.planner_copy`), the
    controller's Python entry point in a second copy once the tension solver is cached, and
    the timed loop here. Returns False (nothing done) where they are cached
    (:func:`latency_kernels_cached`) or work cannot go to a forked process."""
    from marinecdpr import forked
    from marinecdpr.compiled_cache import entry_point
    from marinecdpr.control.controller import step_entry_point
    from marinecdpr.prototype.warmup import WARMUP_STEPS, compile_at_once, stand_in_held

    if latency_kernels_cached() or not forked.can_fork():
        return False
    n, m = min(WARMUP_STEPS, scenario.time.n_steps), scenario.robot.n_cables
    held = stand_in_held(scenario, n)
    z3, z33 = np.zeros((1, 3)), np.zeros((1, 3, 3))
    timed = (scenario.time.step_s, held, z3, z33, z3, z3, np.zeros((1, 3, 6)), np.zeros(1, dtype=np.uint64))
    compile_at_once(scenario, n, step=lambda: step_entry_point(held, m), here=lambda: entry_point(_timed_steps, timed))
    return True


def controller_latency(scenario: Scenario, *, calls: int = 20000) -> Latency:
    """Time the scenario's controller step from Python and inside a compiled loop.

    Parameters
    ----------
    scenario : Scenario
    calls : int
        Steps timed each way, 1 to :data:`~marinecdpr.planning.budget.MAX_LATENCY_CALLS`;
        the plan's steps are cycled over if fewer.

    Raises
    ------
    ScenarioError
        For a count outside that range (a ValueError), before any work.

    Returns
    -------
    Latency
    """
    check_latency_calls(int(calls))  # at most MAX_LATENCY_CALLS, and what memory holds
    compile_apart(scenario)  # on a cold cache: the planner, the entry point and the timed loop at once
    h = scenario.time.step_s
    n = min(calls, scenario.time.n_steps)
    ref = plans(scenario, n).ref
    ship = frame_ship_motion(scenario, np.arange(n) * h)
    c = np.ascontiguousarray
    x, v, w = c(ref.pose[:, :3]), c(ref.twist[:, :3]), c(ref.twist[:, 3:])
    R = c(matrix_from_euler(ref.pose[:, 3:]))
    eta = c(np.stack([ship.eta, ship.eta_dot, ship.eta_ddot], axis=1))
    ctl = Controller(scenario, n_steps=n, plan=ref)
    ticks = np.empty(calls, dtype=np.uint64)
    _timed_steps(h, ctl.held, x[:1], R[:1], v[:1], w[:1], eta[:1], ticks[:1])  # compile
    _timed_steps(h, ctl.held, x, R, v, w, eta, ticks)
    compiled = ticks.astype(float) / _ticks_per_us()
    python = np.empty(calls)
    step, clock = ctl.step, time.perf_counter_ns
    for i in range(min(calls, 50)):  # warm the dispatcher
        step(i % n * h, x=x[i % n], R=R[i % n], v=v[i % n], w=w[i % n], eta=eta[i % n])
    for i in range(calls):
        k = i % n
        t0 = clock()
        step(k * h, x=x[k], R=R[k], v=v[k], w=w[k], eta=eta[k])
        python[i] = clock() - t0
    python /= 1e3
    robot = scenario.robot
    return Latency(
        scenario=scenario.name, method=scenario.planning.method, cables=robot.n_cables,
        redundancy=robot.n_cables - len(robot.controlled), calls=calls,
        python_p50_us=float(np.percentile(python, 50)), python_p99_us=float(np.percentile(python, 99)),
        python_max_us=float(python.max()), compiled_p50_us=float(np.percentile(compiled, 50)),
        compiled_p99_us=float(np.percentile(compiled, 99)), compiled_max_us=float(compiled.max()),
        quadprog_p50_us=_quadprog_p50_us(ctl, calls))
