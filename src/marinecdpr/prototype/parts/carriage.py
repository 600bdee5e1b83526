"""The carriage that carries the frame along its rail (``[ship.carriage]`` with its ``mass_kg``):
the force its drive gives along the rail at each exchange, against its limit.

The carriage moves the frame along the carriage's trajectory (on MuJoCo a body on the ship's
body on four driven joints, :mod:`~marinecdpr.prototype.mujoco_model`; on the own plant C's
composed motion); what its drive must give for that is the plan's equation
(:mod:`marinecdpr.planning.carriage`) at the plant's state: the carriage's own mass's, with
the frame and its winches, m_c (a_OC - g) . t (accelerated with C in the moving ship), and the
cables' pull on the frame along the rail, the tensions the cables apply at the true pose::

    F_k = m_c (a_OC - g)(t_k) . t_k + sum_i T_app,i u_i . t_k      (u_i: J~'s rows' first three)

The run's result carries it (:attr:`~marinecdpr.prototype.simulation.SimResult.carriage_drive`)
and its summary gives its peak against ``drive_force_max_N``. A robot over pulleys has none (as
the plan's). This module is the whole part: its record, its step, its build.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from marinecdpr.prototype.parts import part

__all__ = ["CarriageDrive", "build"]


@njit(cache=True)
def carriage_step(k, h, part, bus):
    f = part.own[k]
    t = part.along[k]
    J, T = bus.J, bus.T_app
    for i in range(T.shape[0]):
        f += T[i] * (J[i, 0] * t[0] + J[i, 1] * t[1] + J[i, 2] * t[2])
    part.force[k] = f


@part(step=carriage_step, order=60, reads=("J", "T_app"), writes=())
class CarriageDrive(NamedTuple):
    """own : (n_steps,) m_c (a_OC - g) . t at t_k, N. along : (n_steps, 3) the rail's unit
    tangent in C at t_k. force : (n_steps,) the drive's force along the rail, N (written)."""

    own: np.ndarray
    along: np.ndarray
    force: np.ndarray


def build(context) -> list:
    from marinecdpr.planning.carriage import carriage_load

    sc = context.scenario
    c = sc.ship.carriage
    if c is None or c.mass_kg is None or sc.robot.has_pulleys:
        return []
    n = context.n_steps
    t = np.arange(n) * sc.time.step_s
    own, along = carriage_load(sc, context.ship_h.take(slice(0, 2 * n, 2)), t)
    return [CarriageDrive(own=np.ascontiguousarray(own), along=np.ascontiguousarray(along), force=np.zeros(n))]
