"""The deployable controller as a part: :func:`~marinecdpr.control.step.control_step`, the
same compiled step a user calls from their own loop (:class:`~marinecdpr.control.Controller`):
what is verified here is what is deployed. Its measurement and commands are the bus's.

The loop calls the step through a function pointer (a numba ``cfunc``, compiled and cached
once for the records' type): the controller's machine code is not linked into the loop,
so the loop's compiler neither re-optimises nor re-emits it (seconds, in each function it
would pass through), and the two compile on their own.
"""

from __future__ import annotations

from contextlib import contextmanager
from typing import NamedTuple

import numpy as np
from numba import cfunc, njit, typeof, types
from numba.typed import List

from marinecdpr.control.controller import step_function, types_only
from marinecdpr.control.records import Measurement
from marinecdpr.prototype.parts import part, part_step

__all__ = ["ControllerPart", "LateController", "build", "pointer_step", "stand_in"]


@njit(cache=True, inline="always")  # a few lines: inlined into its one caller, part_step
def controller_step(k, h, part, bus):
    bus.fallbacks[0] += part.step(k, h, part.held)  # the records read in place from their list


@part(step=controller_step, order=20, reads=tuple(f"meas.{f}" for f in Measurement._fields),
      writes=("T_cmd", "L0_cmd", "fallbacks", "brake"))
class ControllerPart(NamedTuple):
    """The controller's records (:class:`~marinecdpr.control.records.ControllerParts`), held
    in a one-item typed list: the loop passes one pointer, not the records' ~90 arrays
    (a record that large costs seconds of compiling in every function it passes through);
    and ``step``, :func:`pointer_step` for their type. Its ``meas`` and ``cmd`` arrays are
    the bus's ``meas``, ``T_cmd`` and ``L0_cmd``."""

    held: object
    step: object


def _no_step(k, h, held):
    return 0


_STAND_INS: dict = {}
_standing_in: list = []


def pointer_step(held):
    """:func:`~marinecdpr.control.step.control_step` for ``held``'s type as a C function
    (``int64(int64, float64, held)``: :func:`~marinecdpr.control.controller.step_function`,
    compiled once per type and cached on disk); within :func:`stand_in`, a step of that type
    that does nothing."""
    if not _standing_in:
        return step_function(held)
    sig = types.int64(types.int64, types.float64, typeof(held))
    if sig not in _STAND_INS:
        _STAND_INS[sig] = cfunc(sig, cache=True)(_no_step)
    return _STAND_INS[sig]


@contextmanager
def stand_in():
    """Within this, a built controller part steps nothing: its ``step`` and ``held`` (an empty
    list) have the controller's types, so a loop compiled for it is the loop the real
    controller runs in, but costs no compiling of the controller
    (:func:`~marinecdpr.prototype.warmup.compile_apart`); the controller's records are built
    for their type only (:func:`~marinecdpr.control.controller.types_only`)."""
    _standing_in.append(True)
    try:
        with types_only():
            yield
    finally:
        _standing_in.pop()


@njit(cache=True)
def late_controller_step(k, h, part, bus):
    """The controller's step, but where it misses its deadline (k0 <= k < k1 for a window):
    there it delivers nothing and the bus's commands (T_cmd, L0_cmd) stay the last ones."""
    for f in range(part.k0.shape[0]):
        if part.k0[f] <= k < part.k1[f]:
            part.missed[0] += 1
            return
    part_step(k, h, part.controller, bus)


@part(step=late_controller_step, order=20, reads=tuple(f"meas.{f}" for f in Measurement._fields),
      writes=("T_cmd", "L0_cmd", "fallbacks", "brake"))
class LateController(NamedTuple):
    """The controller (``controller``, a :class:`ControllerPart`) missing its deadline
    (``[[faults]]`` of kind ``controller_deadline``): k0, k1 (f,) int64 the exchanges from
    which and until which (excluded) each window's commands are held; missed (1,) int64 the
    exchanges missed so far."""

    controller: ControllerPart
    k0: object
    k1: object
    missed: object


def build(context):
    from marinecdpr.control.controller import held_records

    if _standing_in:  # a step that reads nothing: an empty list of the records' type (no compiling of their unboxing)
        held = List.empty_list(typeof(context.ctl))
    else:
        held = held_records(context.ctl)
    controller = ControllerPart(held=held, step=pointer_step(held))
    late = [f for f in context.scenario.faults if f.kind == "controller_deadline"]
    if not late:
        return controller
    h = context.scenario.time.step_s
    k0 = np.array([int(np.ceil(f.at_s / h - 1e-9)) for f in late], dtype=np.int64)
    return LateController(controller=controller, k0=k0, k1=k0 + np.array([f.steps for f in late], dtype=np.int64),
                          missed=np.zeros(1, dtype=np.int64))
