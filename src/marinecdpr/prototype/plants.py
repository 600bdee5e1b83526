"""The plants the prototype's parts act on, and the compiled loops that step them.

``own``     this package's forward dynamics (:func:`~marinecdpr.model.rigid_body.forward_step`),
            integrated with classic RK4 on the platform's state relative to C, the ship
            moving exactly along its motion;
``mujoco``  the independent engine (:mod:`~marinecdpr.prototype.mujoco_model`): robot and
            ship in one model, the ship held on its motion by a stiff servo.

Each plant is a record (:class:`OwnPlant`, :class:`MujocoPlant` with :class:`ShipDrive`)
and a loop over a block of steps that reads the plant's state, calls
:func:`~marinecdpr.prototype.parts.exchange` on the assembled parts (wired:
:class:`~marinecdpr.prototype.parts.Wired`), and advances the plant with what is on the
bus: the applied tensions (or the cable part's law within the step) and the extra loads.
A plant reads no part's record. A loop returns ``(fallbacks, k)`` with ``k`` the step
where the platform diverged or a part's step failed (``Wired.failed``), or -1.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit, types

from marinecdpr.borrowed import borrowed, call_stored, data_address, load, with_function
from marinecdpr.control.step import cables_at, disturbance_C, mm3
from marinecdpr.geometry.rotations import matrix_about_y_step, matrix_from_quaternion_step
from marinecdpr.model import rigid_body as RB
from marinecdpr.prototype.parts import diverged, exchange, law_tensions, mujoco_cables

__all__ = ["OwnPlant", "MujocoPlant", "ShipDrive", "own_loop", "mujoco_loop", "mujoco_exchange", "mujoco_law",
           "mujoco_library"]

_cache = True


# ------------------------------------------------------------------------- own plant
class OwnPlant(NamedTuple):
    """The own plant: its state and the ship's motion on the half-step grid.

    y : (13,) state (x, quaternion of R_PC, v, omega), in C; advanced in place.
    R_SO : (2 n + 1, 3, 3); w_s, al_s : (2 n + 1, 3) ship angular velocity and acceleration
    in S; a_SO : (2 n + 1, 3) acceleration of S's origin in O; f, m : (2 n + 1, 3) the
    disturbance, in C, or in P if ``in_P``. Row j is t = j h / 2.
    """

    y: np.ndarray
    R_SO: np.ndarray
    w_s: np.ndarray
    al_s: np.ndarray
    a_SO: np.ndarray
    f: np.ndarray
    m: np.ndarray
    in_P: bool


@njit(cache=_cache)
def _own_rhs(y, j, plant, system, dy):
    """d/dt of y = (x, quaternion of R_PC, v, omega) in C at half-step row j, with the cable
    part's tensions at this state (held over the step, or the elastic law over the held L0)
    and the bus's extra loads held."""
    plant, system = borrowed(plant), borrowed(system)
    model, bus = system.model, system.bus
    x, q, v, w = y[0:3], y[3:7], y[7:10], y[10:13]
    q = q / np.sqrt(np.sum(q * q))
    R = np.empty((3, 3))
    matrix_from_quaternion_step(q, R)
    n = model.c_C.shape[0]
    L = np.empty(n)
    J = np.empty((n, 6))
    cables_at(x, R, model, L, J)
    T = law_tensions(system, j, x, R, v, w, L, J, np.empty(n))  # the cable part's law, by its address
    bias = np.empty(6)
    zero = np.zeros(3)
    f_j, m_j = np.empty(3), np.empty(3)
    disturbance_C(plant.f[j], plant.m[j], plant.in_P, R, f_j, m_j)
    for i in range(3):  # the extra loads (a brush's at the actual velocity), held over the step
        f_j[i] += bus.f_ext[i]
        m_j[i] += bus.m_ext[i]
    ship = RB.ShipAt(plant.R_SO[j], plant.w_s[j], plant.al_s[j], plant.a_SO[j])
    RB.wrench_step(x, v, zero, R, w, zero, ship, model, f_j, m_j, bias)
    acc = np.empty(6)
    RB.forward_step(J, T, bias, R, model.mass, model.I_PP, model.controlled, acc)
    dy[0:3] = v
    # q' = 1/2 (0, omega) * q with omega in the parent frame C
    dy[3] = -0.5 * (w[0] * q[1] + w[1] * q[2] + w[2] * q[3])
    dy[4] = 0.5 * (w[0] * q[0] + w[1] * q[3] - w[2] * q[2])
    dy[5] = 0.5 * (w[1] * q[0] + w[2] * q[1] - w[0] * q[3])
    dy[6] = 0.5 * (w[2] * q[0] + w[0] * q[2] - w[1] * q[1])
    dy[7:10] = acc[:3]
    dy[10:13] = acc[3:]


@njit(cache=_cache)
def own_loop(k0, k1, h, plant, system):
    """Steps k0..k1-1 of the own plant (RK4). Returns (fallbacks, -1 or the diverged step)."""
    plant, system = borrowed(plant), borrowed(system)  # no reference counting per step
    y = plant.y
    R = np.empty((3, 3))
    k1_, k2_, k3_, k4_ = np.empty(13), np.empty(13), np.empty(13), np.empty(13)
    fallbacks0 = system.bus.fallbacks[0]
    for k in range(k0, k1):
        matrix_from_quaternion_step(y[3:7], R)
        x, v, w = y[0:3], y[7:10], y[10:13]
        if diverged(x, system.ref_x[k]) or exchange(k, h, x, R, v, w, system):
            return system.bus.fallbacks[0] - fallbacks0, k
        j = 2 * k
        _own_rhs(y, j, plant, system, k1_)
        _own_rhs(y + 0.5 * h * k1_, j + 1, plant, system, k2_)
        _own_rhs(y + 0.5 * h * k2_, j + 1, plant, system, k3_)
        _own_rhs(y + h * k3_, j + 2, plant, system, k4_)
        if system.failed[0] != 0:  # the cable part's law raised
            return system.bus.fallbacks[0] - fallbacks0, k
        y += (h / 6.0) * (k1_ + 2.0 * k2_ + 2.0 * k3_ + k4_)
        y[3:7] /= np.sqrt(np.sum(y[3:7] * y[3:7]))
    return system.bus.fallbacks[0] - fallbacks0, -1


# ---------------------------------------------------------------------- MuJoCo plant
class MujocoPlant(NamedTuple):
    """MuJoCo's arrays the loop reads and writes (views of ``mjData``/``mjModel``).

    qpos, qvel, ctrl, qfrc (qfrc_applied), xfrc (xfrc_applied); ten_k, ten_spring, ten_c:
    the tendons' stiffness, spring length range and damping (elastic cables on
    length-controlled winches are MuJoCo springs). planar: the platform's joints are
    (x, z, theta_y) slides and a hinge, else a free joint. pq, pd: the platform's qpos and
    dof indices; body: its body id; ship_dofs: the ship body's six dof indices (a frame carried
    on a rail: the body moves as C, :mod:`~marinecdpr.prototype.mujoco_model`).
    ship_err (1,): the largest deviation of the ship body from its motion so far (m or rad).
    x, v, w (3,), R (3, 3): the platform's state in C, read each step; R_PO (3, 3), q (4,) scratch.
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
    q: np.ndarray
    offset: np.ndarray


class ShipDrive(NamedTuple):
    """What moves MuJoCo's ship along its motion, and the disturbance in O, per step.

    tau_ff : (n, 6) feed-forward joint forces at mid-step; q_des, qd_des : (n, 6) the ship
    joints' positions and rates at t_k; kp, kd : (6,) servo gains; f_O, m_O : (n, 3) the
    disturbance in O (loads given in C); R_SO : (n, 3, 3) the ship's rotation at t_k;
    f_P, m_P : (n, 3) the disturbance in P where ``in_P`` (turned with the platform's
    actual orientation at each exchange).
    """

    tau_ff: np.ndarray
    q_des: np.ndarray
    qd_des: np.ndarray
    kp: np.ndarray
    kd: np.ndarray
    f_O: np.ndarray
    m_O: np.ndarray
    R_SO: np.ndarray
    f_P: np.ndarray
    m_P: np.ndarray
    in_P: bool


@njit(cache=_cache)
def _mujoco_state(mj):
    """The platform's (x, R, v, w) in C from MuJoCo's qpos and qvel, into mj.x, .R, .v, .w."""
    qpos, qvel, pq, pd = mj.qpos, mj.qvel, mj.pq, mj.pd
    x, R, v, w = mj.x, mj.R, mj.v, mj.w
    if mj.planar:
        x[0], x[1], x[2] = qpos[pq[0]], 0.0, qpos[pq[1]]
        matrix_about_y_step(qpos[pq[2]], R)
        v[0], v[1], v[2] = qvel[pd[0]], 0.0, qvel[pd[1]]
        w[0], w[1], w[2] = 0.0, qvel[pd[2]], 0.0
    else:
        for i in range(3):
            x[i] = qpos[pq[i]]
            v[i] = qvel[pd[i]]
        q0, q1, q2, q3 = qpos[pq[3]], qpos[pq[4]], qpos[pq[5]], qpos[pq[6]]
        norm = np.sqrt(q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3)
        q = mj.q
        q[0], q[1], q[2], q[3] = q0 / norm, q1 / norm, q2 / norm, q3 / norm
        matrix_from_quaternion_step(q, R)
        for i in range(3):  # the ball's angular velocity is in the platform frame
            w[i] = R[i, 0] * qvel[pd[3]] + R[i, 1] * qvel[pd[4]] + R[i, 2] * qvel[pd[5]]
    return x, R, v, w


@njit(cache=_cache)
def _mujoco_law_at(at, triple):
    """:func:`~marinecdpr.prototype.parts.mujoco_cables` of the cable part, MuJoCo's arrays
    and the bus stored at ``at`` (of the type ``triple``, a type reference): compiled once
    per cable law, called through its C wrapper (:func:`mujoco_law`). Returns 1 where it
    raised, else 0."""
    cable, mj, bus = load(at, triple)
    try:
        mujoco_cables(cable, mj, bus)
    except Exception:  # noqa: BLE001 - through a C wrapper: the loop stops and says which part
        return 1
    return 0


def mujoco_law(cable, mj: MujocoPlant, bus) -> np.ndarray:
    """The cable part's inputs to MuJoCo by address: int64 words, [0] the address of
    :func:`_mujoco_law_at`'s C wrapper for the types of (``cable``, ``mj``, ``bus``) (compiled,
    or read from the disk cache, once per cable law), [1:] the three stored (the words keep
    them alive): what the MuJoCo loop takes, so that it compiles once for every law."""
    return with_function(_mujoco_law_at, (cable, mj, bus), (types.intp,))


@njit(cache=_cache)
def _mujoco_inputs(k, R, mj, drive, law, bus):
    """Write the cable part's inputs (forces or springs: ``law``, :func:`mujoco_law`), the
    ship's servo, the disturbance and the bus's extra loads. Given the bus, not the whole
    system: a record of ~170 arrays costs seconds of compiling in each function it passes
    through. Returns 1 where the cable part's inputs raised (nothing else written), else 0."""
    mj, drive, bus = borrowed(mj), borrowed(drive), borrowed(bus)
    if call_stored(law[0], (data_address(law) + 8,)) != 0:
        return 1
    for j in range(mj.ship_dofs.shape[0]):  # the ship body's six
        dof = mj.ship_dofs[j]
        mj.ship_err[0] = max(mj.ship_err[0], abs(mj.qpos[dof] - drive.q_des[k, j]))
        mj.qfrc[dof] = (drive.tau_ff[k, j] + drive.kp[j] * (drive.q_des[k, j] - mj.qpos[dof])
                        + drive.kd[j] * (drive.qd_des[k, j] - mj.qvel[dof]))
    if drive.in_P:  # a load fixed to the platform turns with its actual orientation
        R_PO = mj.R_PO
        mm3(drive.R_SO[k], R, R_PO)
        f, m = drive.f_P, drive.m_P
        for i in range(3):
            mj.xfrc[mj.body, i] = R_PO[i, 0] * f[k, 0] + R_PO[i, 1] * f[k, 1] + R_PO[i, 2] * f[k, 2]
            mj.xfrc[mj.body, 3 + i] = R_PO[i, 0] * m[k, 0] + R_PO[i, 1] * m[k, 1] + R_PO[i, 2] * m[k, 2]
    else:
        for i in range(3):
            mj.xfrc[mj.body, i] = drive.f_O[k, i]
            mj.xfrc[mj.body, 3 + i] = drive.m_O[k, i]
    for i in range(3):  # the extra loads (in C), into O
        for j in range(3):
            mj.xfrc[mj.body, i] += drive.R_SO[k, i, j] * bus.f_ext[j]
            mj.xfrc[mj.body, 3 + i] += drive.R_SO[k, i, j] * bus.m_ext[j]
    return 0


@njit(cache=_cache, inline="always")
def _inputs_failed(k, system):
    """Record that the cable part's inputs to MuJoCo raised at exchange k (as a part's step
    that raised: ``system.failed``)."""
    if system.failed[0] == 0:
        system.failed[0] = k + 1
        system.failed[1] = system.law[1]


@njit(cache=_cache)
def mujoco_exchange(k, h, mj, drive, system, law):
    """Read MuJoCo's state, exchange, write MuJoCo's inputs (``law``: the cable part's,
    :func:`mujoco_law`). Returns -1 if diverged, else the exchange's fallback count (0 or 1)."""
    x, R, v, w = _mujoco_state(mj)
    if diverged(x, system.ref_x[k]):
        return -1
    before = system.bus.fallbacks[0]
    if exchange(k, h, x, R, v, w, system):
        return -1
    if _mujoco_inputs(k, R, mj, drive, law, system.bus) != 0:
        _inputs_failed(k, system)
        return -1
    return system.bus.fallbacks[0] - before


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
def mujoco_loop(k0, k1, addresses, h, mj, drive, system, law):
    """Exchange and mj_step, k0..k1-1, all compiled; ``addresses`` = (mjModel*, mjData*);
    ``law`` the cable part's inputs (:func:`mujoco_law`). Returns (fallbacks, -1 or the
    diverged step)."""
    mj, drive, system = borrowed(mj), borrowed(drive), borrowed(system)  # no counting per step
    fallbacks0 = system.bus.fallbacks[0]
    for k in range(k0, k1):
        x, R, v, w = _mujoco_state(mj)
        if diverged(x, system.ref_x[k]) or exchange(k, h, x, R, v, w, system):
            return system.bus.fallbacks[0] - fallbacks0, k
        if _mujoco_inputs(k, R, mj, drive, law, system.bus) != 0:
            _inputs_failed(k, system)
            return system.bus.fallbacks[0] - fallbacks0, k
        _c_mj_step(addresses[0], addresses[1])
    return system.bus.fallbacks[0] - fallbacks0, -1
