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

from numba import cfunc, njit, typeof, types
from numba.typed import List

from marinecdpr.control.step import control_step
from marinecdpr.prototype.parts import part

__all__ = ["ControllerPart", "build", "pointer_step", "stand_in"]


@njit(cache=True, inline="always")  # a few lines: inlined into its one caller, part_step
def controller_step(k, h, part, bus):
    bus.fallbacks[0] += part.step(k, h, part.held)  # the records read in place from their list


@part(step=controller_step, order=20, reads=tuple(f"meas.{f}" for f in ("x", "R", "v", "w", "L", "Ldot", "T", "eta", "clock")), writes=("T_cmd", "L0_cmd", "fallbacks"))
class ControllerPart(NamedTuple):
    """The controller's records (:class:`~marinecdpr.control.records.ControllerParts`), held
    in a one-item typed list: the loop passes one pointer, not the records' ~90 arrays
    (a record that large costs seconds of compiling in every function it passes through);
    and ``step``, :func:`pointer_step` for their type. Its ``meas`` and ``cmd`` arrays are
    the bus's ``meas``, ``T_cmd`` and ``L0_cmd``."""

    held: object
    step: object


def _control_step(k, h, held):
    return control_step(k, h, held)


def _no_step(k, h, held):
    return 0


_POINTER_STEPS: dict = {}
_STAND_INS: dict = {}
_standing_in: list = []


def pointer_step(held):
    """:func:`~marinecdpr.control.step.control_step` for ``held``'s type as a C function
    (``int64(int64, float64, held)``), compiled once per type and cached on disk; within
    :func:`stand_in`, a step of that type that does nothing."""
    sig = types.int64(types.int64, types.float64, typeof(held))
    fn, made = (_no_step, _STAND_INS) if _standing_in else (_control_step, _POINTER_STEPS)
    if sig not in made:
        made[sig] = cfunc(sig, cache=True)(fn)
    return made[sig]


@contextmanager
def stand_in():
    """Within this, a built controller part steps nothing: its ``step`` and ``held`` (an empty
    list) have the controller's types, so a loop compiled for it is the loop the real
    controller runs in, but costs no compiling of the controller
    (:func:`~marinecdpr.prototype.warmup.compile_apart`)."""
    _standing_in.append(True)
    try:
        yield
    finally:
        _standing_in.pop()


def build(context) -> ControllerPart:
    from marinecdpr.control.controller import held_records

    if _standing_in:  # a step that reads nothing: an empty list of the records' type (no compiling of their unboxing)
        held = List.empty_list(typeof(context.ctl))
    else:
        held = held_records(context.ctl)
    return ControllerPart(held=held, step=pointer_step(held))
