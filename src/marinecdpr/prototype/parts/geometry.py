"""The cables at the platform's true pose: lengths, their rates and J~ (eqs. 2, 5, 6), over
the pulleys where the robot has them. The first part of every exchange."""

from __future__ import annotations

from typing import NamedTuple

from numba import njit

from marinecdpr.control.records import RobotModel
from marinecdpr.control.step import cables_at
from marinecdpr.prototype.parts import part

__all__ = ["CableGeometry", "length_rates", "build"]


@njit(cache=True)
def length_rates(J, v, w, out):
    """l' = -J~ (v, omega) (eq. 5), written to out (m,)."""
    for i in range(J.shape[0]):
        out[i] = -(J[i, 0] * v[0] + J[i, 1] * v[1] + J[i, 2] * v[2]
                   + J[i, 3] * w[0] + J[i, 4] * w[1] + J[i, 5] * w[2])


@njit(cache=True, inline="always")  # a few lines: inlined into its one caller, part_step
def geometry_step(k, h, part, bus):
    cables_at(bus.x, bus.R, part.model, bus.L, bus.J)
    length_rates(bus.J, bus.v, bus.w, bus.Ldot)


@part(step=geometry_step, order=0, reads=("x", "R", "v", "w"), writes=("L", "Ldot", "J"))
class CableGeometry(NamedTuple):
    """The robot's cables (:class:`~marinecdpr.control.records.RobotModel`: anchors, pulleys)."""

    model: RobotModel


def build(context) -> CableGeometry:
    return CableGeometry(model=context.model)
