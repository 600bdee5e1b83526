"""The plants the prototype's parts act on, and the compiled loops that step them.

``own``     this package's forward dynamics (:func:`~marinecdpr.model.kernels.forward_step`),
            integrated with classic RK4 on the platform's state relative to C, the ship
            moving exactly along its motion;
``mujoco``  the independent engine (:mod:`~marinecdpr.prototype.mujoco_model`): robot and
            ship in one model, the ship held on its motion by a stiff servo.

Each plant is a record (:class:`OwnPlant`, :class:`MujocoPlant` with :class:`ShipDrive`)
and a loop over a block of steps that reads the plant's state, calls
:func:`~marinecdpr.prototype.parts.exchange`, and advances the plant. A loop returns
``(fallbacks, k)`` with ``k`` the step where the platform diverged, or -1.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit, types

from marinecdpr.borrowed import borrowed
from marinecdpr.control.step import cables_at, disturbance_C, mm3
from marinecdpr.model import kernels as K
from marinecdpr.prototype.parts import catenary_cables, diverged, elastic_tension, exchange, length_rates, quat_to_R

__all__ = ["OwnPlant", "MujocoPlant", "ShipDrive", "own_loop", "mujoco_loop", "mujoco_exchange",
           "mujoco_library"]

_cache = True


# ------------------------------------------------------------------------- own plant
class OwnPlant(NamedTuple):
    """The own plant: its state and the ship's motion on the half-step grid.

    y : (13,) state (x, quaternion of R_PC, v, omega), in C; advanced in place.
    R_SO : (2 n + 1, 3, 3); w_s, al_s : (2 n + 1, 3) ship angular velocity and acceleration
    in S; a_SO : (2 n + 1, 3) acceleration of S's origin in O; f, m : (2 n + 1, 3) the
    disturbance (in C, or in P if the loads are). Row j is t = j h / 2.
    """

    y: np.ndarray
    R_SO: np.ndarray
    w_s: np.ndarray
    al_s: np.ndarray
    a_SO: np.ndarray
    f: np.ndarray
    m: np.ndarray


@njit(cache=_cache, inline="always")
def _own_rhs(y, j, plant, parts, dy):
    """d/dt of y = (x, quaternion of R_PC, v, omega) in C at half-step row j.

    Tensions are held over the step (``parts.bus.T_app``), except elastic cables on
    length-controlled winches: their tension follows the state, with the winch's L0 held.
    """
    model, cables, winch = parts.ctl.model, parts.cables, parts.winch
    x, q, v, w = y[0:3], y[3:7], y[7:10], y[10:13]
    q = q / np.sqrt(np.sum(q * q))
    R = np.empty((3, 3))
    quat_to_R(q, R)
    n = model.c_C.shape[0]
    L = np.empty(n)
    J = np.empty((n, 6))
    cables_at(x, R, model, L, J)
    T = parts.bus.T_app
    if cables.elastic and not winch.tension_controlled:
        T = np.zeros(n)
        Ldot = np.empty(n)
        length_rates(J, v, w, Ldot)
        if parts.catenary.active:  # heavy cables pull along their tangents
            catenary_cables(x, R, j, model, winch, cables, parts.catenary, Ldot, J, T)
        else:
            for i in range(n):
                T[i] = elastic_tension(L[i], winch.L0[i], Ldot[i], cables)
    bias = np.empty(6)
    zero = np.zeros(3)
    f_j, m_j = np.empty(3), np.empty(3)
    disturbance_C(plant.f[j], plant.m[j], parts.loads.in_P, R, f_j, m_j)
    if parts.brush.active:  # the brush's loads at the actual velocity, held over the step
        f_j += parts.brush.f
        m_j += parts.brush.m
    K.wrench_step(x, v, zero, R, w, zero, plant.R_SO[j], plant.w_s[j], plant.al_s[j], plant.a_SO[j],
                  model.origin, model.mass, model.I_PP, model.g, f_j, m_j, bias)
    acc = np.empty(6)
    K.forward_step(J, T, bias, R, model.mass, model.I_PP, model.controlled, acc)
    dy[0:3] = v
    # q' = 1/2 (0, omega) * q with omega in the parent frame C
    dy[3] = -0.5 * (w[0] * q[1] + w[1] * q[2] + w[2] * q[3])
    dy[4] = 0.5 * (w[0] * q[0] + w[1] * q[3] - w[2] * q[2])
    dy[5] = 0.5 * (w[1] * q[0] + w[2] * q[1] - w[0] * q[3])
    dy[6] = 0.5 * (w[2] * q[0] + w[0] * q[2] - w[1] * q[1])
    dy[7:10] = acc[:3]
    dy[10:13] = acc[3:]


@njit(cache=_cache)
def own_loop(k0, k1, h, plant, parts):
    """Steps k0..k1-1 of the own plant (RK4). Returns (fallbacks, -1 or the diverged step)."""
    plant, parts = borrowed(plant), borrowed(parts)  # no reference counting per step
    y = plant.y
    R = np.empty((3, 3))
    k1_, k2_, k3_, k4_ = np.empty(13), np.empty(13), np.empty(13), np.empty(13)
    fallbacks = 0
    for k in range(k0, k1):
        quat_to_R(y[3:7], R)
        x, v, w = y[0:3], y[7:10], y[10:13]
        if diverged(x, parts.ctl.ref.x[k]):
            return fallbacks, k
        fallbacks += exchange(k, h, x.copy(), R, v.copy(), w.copy(), parts)
        j = 2 * k
        _own_rhs(y, j, plant, parts, k1_)
        _own_rhs(y + 0.5 * h * k1_, j + 1, plant, parts, k2_)
        _own_rhs(y + 0.5 * h * k2_, j + 1, plant, parts, k3_)
        _own_rhs(y + h * k3_, j + 2, plant, parts, k4_)
        y += (h / 6.0) * (k1_ + 2.0 * k2_ + 2.0 * k3_ + k4_)
        y[3:7] /= np.sqrt(np.sum(y[3:7] * y[3:7]))
    return fallbacks, -1


# ---------------------------------------------------------------------- MuJoCo plant
class MujocoPlant(NamedTuple):
    """MuJoCo's arrays the loop reads and writes (views of ``mjData``/``mjModel``).

    qpos, qvel, ctrl, qfrc (qfrc_applied), xfrc (xfrc_applied); ten_k, ten_spring, ten_c:
    the tendons' stiffness, spring length range and damping (elastic cables on
    length-controlled winches are MuJoCo springs). planar: the platform's joints are
    (x, z, theta_y) slides and a hinge, else a free joint. pq, pd: the platform's qpos and
    dof indices; body: its body id; ship_dofs: the ship's six dof indices.
    ship_err (1,): the largest deviation of the ship from its motion so far (m or rad).
    x, v, w (3,), R (3, 3): the platform's state in C, read each step; R_PO (3, 3) scratch.
    offset (m,): each tendon's length beyond its cable's (a pulley's inlet), m.
    """

    qpos: np.ndarray
    qvel: np.ndarray
    ctrl: np.ndarray
    qfrc: np.ndarray
    xfrc: np.ndarray
    ten_k: np.ndarray
    ten_spring: np.ndarray
    ten_c: np.ndarray
    planar: bool
    pq: np.ndarray
    pd: np.ndarray
    body: int
    ship_dofs: np.ndarray
    ship_err: np.ndarray
    x: np.ndarray
    R: np.ndarray
    v: np.ndarray
    w: np.ndarray
    R_PO: np.ndarray
    offset: np.ndarray


class ShipDrive(NamedTuple):
    """What moves MuJoCo's ship along its motion, and the disturbance in O, per step.

    tau_ff : (n, 6) feed-forward joint forces at mid-step; q_des, qd_des : (n, 6) the ship
    joints' positions and rates at t_k; kp, kd : (6,) servo gains; f_O, m_O : (n, 3) the
    disturbance in O (loads given in C); R_SO : (n, 3, 3) the ship's rotation at t_k.
    """

    tau_ff: np.ndarray
    q_des: np.ndarray
    qd_des: np.ndarray
    kp: np.ndarray
    kd: np.ndarray
    f_O: np.ndarray
    m_O: np.ndarray
    R_SO: np.ndarray


@njit(cache=_cache, inline="always")
def _mujoco_state(mj):
    """The platform's (x, R, v, w) in C from MuJoCo's qpos and qvel, into mj.x, .R, .v, .w."""
    qpos, qvel, pq, pd = mj.qpos, mj.qvel, mj.pq, mj.pd
    x, R, v, w = mj.x, mj.R, mj.v, mj.w
    if mj.planar:
        x[0], x[1], x[2] = qpos[pq[0]], 0.0, qpos[pq[1]]
        th = qpos[pq[2]]
        c, s = np.cos(th), np.sin(th)
        R[0, 0], R[0, 1], R[0, 2] = c, 0.0, s
        R[1, 0], R[1, 1], R[1, 2] = 0.0, 1.0, 0.0
        R[2, 0], R[2, 1], R[2, 2] = -s, 0.0, c
        v[0], v[1], v[2] = qvel[pd[0]], 0.0, qvel[pd[1]]
        w[0], w[1], w[2] = 0.0, qvel[pd[2]], 0.0
    else:
        for i in range(3):
            x[i] = qpos[pq[i]]
            v[i] = qvel[pd[i]]
        q0, q1, q2, q3 = qpos[pq[3]], qpos[pq[4]], qpos[pq[5]], qpos[pq[6]]
        norm = np.sqrt(q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3)
        quat_to_R((q0 / norm, q1 / norm, q2 / norm, q3 / norm), R)
        for i in range(3):  # the ball's angular velocity is in the platform frame
            w[i] = R[i, 0] * qvel[pd[3]] + R[i, 1] * qvel[pd[4]] + R[i, 2] * qvel[pd[5]]
    return x, R, v, w


@njit(cache=_cache, inline="always")
def _mujoco_inputs(k, R, mj, drive, parts):
    """Write the cables' forces (or springs), the ship's servo and the disturbance."""
    bus, winch, cables = parts.bus, parts.winch, parts.cables
    n = bus.T_app.shape[0]
    if cables.elastic and not winch.tension_controlled:
        # the cable is a spring MuJoCo integrates: taut above L0 (dead band [0, L0])
        mj.ctrl[:] = 0.0
        for i in range(n):
            mj.ten_k[i] = cables.EA / winch.L0[i]
            mj.ten_spring[i, 0] = 0.0
            mj.ten_spring[i, 1] = winch.L0[i] + mj.offset[i]  # a pulley cable's tendon starts behind it
            mj.ten_c[i] = cables.damping if bus.L[i] > winch.L0[i] else 0.0
    else:
        mj.ctrl[:] = bus.T_app
    for j in range(6):
        dof = mj.ship_dofs[j]
        mj.ship_err[0] = max(mj.ship_err[0], abs(mj.qpos[dof] - drive.q_des[k, j]))
        mj.qfrc[dof] = (drive.tau_ff[k, j] + drive.kp[j] * (drive.q_des[k, j] - mj.qpos[dof])
                        + drive.kd[j] * (drive.qd_des[k, j] - mj.qvel[dof]))
    loads = parts.loads
    if loads.in_P:  # a load fixed to the platform turns with its actual orientation
        R_PO = mj.R_PO
        mm3(drive.R_SO[k], R, R_PO)
        for i in range(3):
            mj.xfrc[mj.body, i] = R_PO[i, 0] * loads.f[k, 0] + R_PO[i, 1] * loads.f[k, 1] + R_PO[i, 2] * loads.f[k, 2]
            mj.xfrc[mj.body, 3 + i] = (R_PO[i, 0] * loads.m[k, 0] + R_PO[i, 1] * loads.m[k, 1]
                                       + R_PO[i, 2] * loads.m[k, 2])
    else:
        mj.xfrc[mj.body, :3] = drive.f_O[k]
        mj.xfrc[mj.body, 3:] = drive.m_O[k]
    brush = parts.brush
    if brush.active:  # the brush's loads at the actual velocity (in C), into O
        for i in range(3):
            for j in range(3):
                mj.xfrc[mj.body, i] += drive.R_SO[k, i, j] * brush.f[j]
                mj.xfrc[mj.body, 3 + i] += drive.R_SO[k, i, j] * brush.m[j]


@njit(cache=_cache)
def mujoco_exchange(k, h, mj, drive, parts):
    """Read MuJoCo's state, exchange, write MuJoCo's inputs. Returns -1 if diverged, else
    the exchange's fallback count (0 or 1)."""
    x, R, v, w = _mujoco_state(mj)
    if diverged(x, parts.ctl.ref.x[k]):
        return -1
    fallback = exchange(k, h, x, R, v, w, parts)
    _mujoco_inputs(k, R, mj, drive, parts)
    return fallback


def mujoco_library() -> bool:
    """Make MuJoCo's C library known to numba by name; False if it cannot be found."""
    import glob
    import os

    import mujoco
    from llvmlite import binding

    libs = glob.glob(os.path.join(os.path.dirname(mujoco.__file__), "libmujoco.so*"))
    if not libs or not hasattr(mujoco.MjModel, "_address"):
        return False
    binding.load_library_permanently(libs[0])
    return True


# mj_step(const mjModel*, mjData*), resolved by symbol name so that the loop can be cached;
# the pointers travel as 64-bit integers (the same in the C calling convention)
_c_mj_step = types.ExternalFunction("mj_step", types.void(types.uint64, types.uint64))


@njit(cache=_cache)
def mujoco_loop(k0, k1, addresses, h, mj, drive, parts):
    """Exchange and mj_step, k0..k1-1, all compiled; ``addresses`` = (mjModel*, mjData*).
    Returns (fallbacks, -1 or the diverged step)."""
    mj, drive, parts = borrowed(mj), borrowed(drive), borrowed(parts)  # no counting per step
    fallbacks = 0
    for k in range(k0, k1):  # mujoco_exchange, written out: one compiled call level less
        x, R, v, w = _mujoco_state(mj)
        if diverged(x, parts.ctl.ref.x[k]):
            return fallbacks, k
        fallbacks += exchange(k, h, x, R, v, w, parts)
        _mujoco_inputs(k, R, mj, drive, parts)
        _c_mj_step(addresses[0], addresses[1])
    return fallbacks, -1
