"""The deployable controller as a part: :func:`~marinecdpr.control.step.control_step`, the
same compiled step a user calls from their own loop (:class:`~marinecdpr.control.Controller`):
what is verified here is what is deployed. Its measurement and commands are the bus's."""

from __future__ import annotations

from typing import NamedTuple

from numba import njit

from marinecdpr.control.step import control_step
from marinecdpr.prototype.parts import part

__all__ = ["ControllerPart", "build"]


@njit(cache=True, inline="always")  # a few lines: inlined into its one caller, part_step
def controller_step(k, h, part, bus):
    bus.fallbacks[0] += control_step(k, h, part.held)  # the records read in place from their list


@part(step=controller_step, order=20, reads=tuple(f"meas.{f}" for f in ("x", "R", "v", "w", "L", "Ldot", "T", "eta", "clock")), writes=("T_cmd", "L0_cmd", "fallbacks"))
class ControllerPart(NamedTuple):
    """The controller's records (:class:`~marinecdpr.control.records.ControllerParts`), held
    in a one-item typed list: the loop passes one pointer, not the records' ~90 arrays
    (a record that large costs seconds of compiling in every function it passes through).
    Its ``meas`` and ``cmd`` arrays are the bus's ``meas``, ``T_cmd`` and ``L0_cmd``."""

    held: object


def build(context) -> ControllerPart:
    from marinecdpr.control.controller import _held

    return ControllerPart(held=_held(context.ctl))
