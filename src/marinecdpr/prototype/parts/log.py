"""The run's record: what each exchange logs, the last part of the exchange."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from marinecdpr.geometry.rotations import euler_from_matrix_step
from marinecdpr.prototype.parts import part

__all__ = ["Log", "build"]


@njit(cache=True, inline="always")  # a few lines: inlined into its one caller, part_step
def log_step(k, h, part, bus):
    for i in range(3):
        part.pose[k, i] = bus.x[i]
    euler_from_matrix_step(bus.R, part.pose[k, 3:])
    for i in range(bus.L.shape[0]):
        part.lengths[k, i] = bus.L[i]
        part.T_cmd[k, i] = bus.T_cmd[i]
        part.T_app[k, i] = bus.T_app[i]


@part(step=log_step, order=90, reads=("x", "R", "L", "T_cmd", "T_app"), writes=())
class Log(NamedTuple):
    """pose (n_steps, 6) (x, y, z, rx, ry, rz) of P in C, m and rad; lengths (m), T_cmd and
    T_app (N): (n_steps, m)."""

    pose: np.ndarray
    lengths: np.ndarray
    T_cmd: np.ndarray
    T_app: np.ndarray


def build(context) -> Log:
    n, m = context.n_steps, context.scenario.robot.n_cables
    return Log(pose=np.empty((n, 6)), lengths=np.empty((n, m)), T_cmd=np.empty((n, m)), T_app=np.empty((n, m)))
