"""A camera's estimate of the platform's position, late and noisy, fused with the pose
sensor's (``[simulation.camera]``; closed loop only: the open loop measures nothing).

At t_k the camera delivers the true position of t_k - d h (d = round(latency / h) steps)
plus its noise; brought to now by the measured velocity, it is blended into the pose
sensor's measurement::

    x_cam  = x(t_k - d h) + n_k + d h v_meas
    meas.x = (1 - weight) meas.x + weight x_cam

Until d steps have passed the camera has nothing to give and the sensor's position stands.
This module is the whole part: its record, its step, its build (and the schema's
``Camera`` section); the loop, the plants and the other parts do not know of it.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from marinecdpr.prototype.parts import part

__all__ = ["Camera", "build"]


@njit(cache=True)
def camera_step(k, h, part, bus):
    d = part.delay
    slot = k % (d + 1)
    for i in range(3):  # the ring of the true positions of the last d + 1 exchanges
        part.history[slot, i] = bus.x[i]
    if k < d:
        return
    old = (k - d) % (d + 1)
    meas, w = bus.meas, part.weight
    for i in range(3):
        x_cam = part.history[old, i] + part.noise[k, i] + d * h * meas.v[i]
        meas.x[i] = (1.0 - w) * meas.x[i] + w * x_cam


@part(step=camera_step, order=14, reads=("x", "meas.x", "meas.v"), writes=("meas.x",))
class Camera(NamedTuple):
    """delay : the camera's latency in exchanges, d. weight : its share of the fused position.
    noise : (n_steps, 3) its position errors, m. history : (d + 1, 3) the true positions of
    the last d + 1 exchanges, m (the camera's pipeline)."""

    delay: int
    weight: float
    noise: np.ndarray
    history: np.ndarray


def build(context) -> list:
    cam = context.scenario.simulation.camera
    if cam is None or context.run != "closed_loop":
        return []
    h = context.scenario.time.step_s
    d = int(round(cam.latency_s / h))
    noise = np.random.default_rng(cam.seed).normal(0.0, cam.noise_m, (context.n_steps, 3))
    return [Camera(delay=d, weight=float(cam.weight), noise=noise, history=np.zeros((d + 1, 3)))]
