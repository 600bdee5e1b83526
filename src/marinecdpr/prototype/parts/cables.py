"""The cables: what tension each applies, at the exchange (onto the bus's ``T_app``) and,
for the plant, at its state within the step (the part's tension law):

``HeldTensions``    ideal cables apply the command (T = T_cmd); tension-controlled winches
                    the tension their loop holds. Held over the step.
``ElasticCables``   straight elastic cables over the winch's unstretched length: EA strain
                    plus damping when taut, 0 when slack (:func:`~marinecdpr.geometry.elastic.elastic_tension`, the
                    one implementation of the law); the plant's state sets the tension.
``CatenaryCables``  heavy cables (``simulation.cables.model = "catenary"``, own plant):
                    each an elastic catenary (:mod:`marinecdpr.model.catenary`) from its
                    frame anchor over the winch's L0, in the true vertical, pulling along
                    its tangent at the platform; at the exchange, over what the drum has
                    paid out now, also its tension at the winch end (``T_winch``: a motor
                    winch's load).
``SnappedCables``   any of these with cables that snap (``[[faults]]`` of kind
                    ``cable_snap``): from the first exchange at or after a cable's ``at_s``
                    its tension is zero, at the exchange and within the step, and on MuJoCo
                    its motor and spring stop acting. Built only where a scenario lists a
                    snap: without one, the cables' part is the one above, as it was.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from marinecdpr.control.records import RobotModel
from marinecdpr.geometry.elastic import axial_stiffness, elastic_tension
from marinecdpr.model.catenary import N_OUT, OUT_H, OUT_TA, OUT_VB, catenary_forces
from marinecdpr.prototype.parts import cable_tensions, mujoco_cables, part, part_step
from marinecdpr.prototype.parts.geometry import length_rates

__all__ = ["HeldTensions", "ElasticCables", "CatenaryCables", "SnappedCables", "catenary_cables", "snap_steps",
           "build"]


# ----------------------------------------------------------------------- held tensions
@njit(cache=True, inline="always")  # a few lines: inlined into its one caller, part_step
def held_step(k, h, part, bus):
    for i in range(bus.T_app.shape[0]):
        bus.T_app[i] = max(0.0, bus.T_hold[i]) if part.from_winch else bus.T_cmd[i]


@njit(cache=True)
def held_tensions(part, j, x, R, v, w, L, J, bus, T):
    return bus.T_app


@njit(cache=True)
def held_mujoco(part, mj, bus):
    for i in range(bus.T_app.shape[0]):
        mj.ctrl[i] = bus.T_app[i]


@part(step=held_step, order=40, reads=("T_cmd", "T_hold"), writes=("T_app",), tensions=held_tensions,
      mujoco=held_mujoco)
class HeldTensions(NamedTuple):
    """Tensions held over the step: the command (ideal cables) or, ``from_winch``, what the
    tension-controlled winches hold."""

    from_winch: bool


# ---------------------------------------------------------------------- elastic cables
@njit(cache=True, inline="always")  # a few lines: inlined into its one caller, part_step
def elastic_step(k, h, part, bus):
    for i in range(bus.T_app.shape[0]):
        bus.T_app[i] = elastic_tension(bus.L[i], bus.L0_drum[i], bus.Ldot[i], part.EA, part.damping)


@njit(cache=True)
def elastic_tensions(part, j, x, R, v, w, L, J, bus, T):
    length_rates(J, v, w, part.Ldot)
    for i in range(T.shape[0]):
        T[i] = elastic_tension(L[i], bus.L0[i], part.Ldot[i], part.EA, part.damping)
    return T


@njit(cache=True)
def elastic_mujoco(part, mj, bus):
    # the cable is a spring MuJoCo integrates: taut above L0 (dead band [0, L0])
    for i in range(bus.T_app.shape[0]):
        mj.ctrl[i] = 0.0
        mj.ten_k[i] = axial_stiffness(bus.L0[i], part.EA)
        mj.ten_spring[i, 0] = 0.0
        mj.ten_spring[i, 1] = bus.L0[i] + mj.offset[i]  # a pulley cable's tendon starts behind it
        mj.ten_c[i] = part.damping if bus.L[i] > bus.L0[i] else 0.0


@part(step=elastic_step, order=40, reads=("L", "Ldot", "L0_drum", "L0"), writes=("T_app",),
      tensions=elastic_tensions, mujoco=elastic_mujoco)
class ElasticCables(NamedTuple):
    """Straight elastic cables: EA (N), damping (N s/m); Ldot (m,) scratch. At the exchange
    the tension is the stretch over what the drums have paid out (``L0_drum``: the motor
    winches read it before they step); in the plant, over the L0 held over the step."""

    EA: float
    damping: float
    Ldot: np.ndarray


# --------------------------------------------------------------------- heavy cables
@njit(cache=True)
def catenary_cables(x, R, j, part, L0, Ldot, J, T):
    """Heavy cables' forces on the platform at the pose (x, R_PC) at half-step row j: each
    cable's catenary over its unstretched length L0 (m,) from its frame anchor to its
    platform anchor, in the vertical ``part.up[j]``. Writes J (m, 6) rows (u, (R p) x u)
    along each force and T (m,) its magnitude, the tension at the platform plus the cable's
    damping on its chord's rate Ldot (m,), N: J^T T is the cables' wrench (J's rows on
    entry: any unit vector per cable, used where a cable pulls with no force)."""
    up = part.up[j]
    f = part.f
    model = part.model
    for i in range(J.shape[0]):
        r0 = R[0, 0] * model.p_P[i, 0] + R[0, 1] * model.p_P[i, 1] + R[0, 2] * model.p_P[i, 2]
        r1 = R[1, 0] * model.p_P[i, 0] + R[1, 1] * model.p_P[i, 1] + R[1, 2] * model.p_P[i, 2]
        r2 = R[2, 0] * model.p_P[i, 0] + R[2, 1] * model.p_P[i, 1] + R[2, 2] * model.p_P[i, 2]
        d0, d1, d2 = x[0] + r0 - model.c_C[i, 0], x[1] + r1 - model.c_C[i, 1], x[2] + r2 - model.c_C[i, 2]
        v = d0 * up[0] + d1 * up[1] + d2 * up[2]
        e0, e1, e2 = d0 - v * up[0], d1 - v * up[1], d2 - v * up[2]  # the horizontal span
        h = np.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
        out = part.out[i]
        if catenary_forces(h, v, L0[i], part.w, part.EA, part.guess[i], out, 100) == 1:
            part.status[0] += 1
        part.guess[i, 0] = out[OUT_H]
        part.guess[i, 1] = out[OUT_VB]
        H, VB = out[OUT_H], out[OUT_VB]
        if h > 0.0:
            e0, e1, e2 = e0 / h, e1 / h, e2 / h
        f[0] = -(H * e0 + VB * up[0])  # the cable's pull on the platform: -(H e_h + V_B up)
        f[1] = -(H * e1 + VB * up[1])
        f[2] = -(H * e2 + VB * up[2])
        Tb = np.sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2])
        if Tb > 0.0:
            u0, u1, u2 = f[0] / Tb, f[1] / Tb, f[2] / Tb
        else:  # no force: any direction (the chord's)
            u0, u1, u2 = J[i, 0], J[i, 1], J[i, 2]
        J[i, 0], J[i, 1], J[i, 2] = u0, u1, u2
        J[i, 3], J[i, 4], J[i, 5] = r1 * u2 - r2 * u1, r2 * u0 - r0 * u2, r0 * u1 - r1 * u0
        T[i] = max(0.0, Tb + part.damping * Ldot[i]) if Tb > 0.0 else 0.0


@njit(cache=True)
def catenary_step(k, h, part, bus):
    """The catenaries at the exchange's pose over what the drums have paid out now
    (``L0_drum``; the L0 a length-controlled winch holds): the tension at the platform
    (``T_app``) and at the winch end (``T_winch``, the catenary's T_A), each with the
    cable's damping on its chord's rate."""
    for i in range(part.J.shape[0]):
        for c in range(6):
            part.J[i, c] = bus.J[i, c]
    catenary_cables(bus.x, bus.R, 2 * k, part, bus.L0_drum, bus.Ldot, part.J, bus.T_app)
    for i in range(part.J.shape[0]):
        bus.T_winch[i] = max(0.0, part.out[i, OUT_TA] + part.damping * bus.Ldot[i])


@njit(cache=True)
def catenary_tensions(part, j, x, R, v, w, L, J, bus, T):
    length_rates(J, v, w, part.Ldot)
    for i in range(T.shape[0]):
        T[i] = 0.0
    catenary_cables(x, R, j, part, bus.L0, part.Ldot, J, T)
    return T


@njit(cache=True)
def catenary_mujoco(part, mj, bus):  # never called: the scenario check keeps catenaries off MuJoCo
    for i in range(bus.T_app.shape[0]):
        mj.ctrl[i] = bus.T_app[i]


@part(step=catenary_step, order=40, reads=("x", "R", "J", "Ldot", "L0_drum", "L0"), writes=("T_app", "T_winch"),
      tensions=catenary_tensions, mujoco=catenary_mujoco)
class CatenaryCables(NamedTuple):
    """Heavy cables of weight w (N/m), stiffness EA (N) and damping (N s/m) between the
    model's anchors (``model``), in the true vertical.

    up (2 n_steps + 1, 3): the true vertical (against gravity) in C on the half-step grid
    (row j: t = j h / 2). guess (m, 2): the last (H, V_B) of each cable, the next warm
    start, N. out (m, N_OUT): scratch of :func:`~marinecdpr.model.catenary.catenary_forces`.
    f (3,), J (m, 6), Ldot (m,): scratch. status (1,) int64: the number of solves that did
    not converge (none in a sound run).
    """

    model: RobotModel
    w: float
    EA: float
    damping: float
    up: np.ndarray
    guess: np.ndarray
    out: np.ndarray
    f: np.ndarray
    J: np.ndarray
    Ldot: np.ndarray
    status: np.ndarray


def catenary_part(model: RobotModel, w: float, EA: float, damping: float, up: np.ndarray) -> CatenaryCables:
    """A :class:`CatenaryCables` for the model's cables of weight w (N/m), stiffness EA (N)
    and damping (N s/m) in the vertical ``up`` (rows, 3), no warm start yet."""
    m = model.c_C.shape[0]
    return CatenaryCables(model=model, w=float(w), EA=float(EA), damping=float(damping),
                          up=np.ascontiguousarray(up, dtype=float), guess=np.full((m, 2), np.nan),
                          out=np.zeros((m, N_OUT)), f=np.zeros(3), J=np.zeros((m, 6)), Ldot=np.zeros(m),
                          status=np.zeros(1, dtype=np.int64))


# ------------------------------------------------------------------- snapped cables
@njit(cache=True)
def snapped_step(k, h, part, bus):
    """The cables' own step, then each cable snapped by t_k (k >= its snap step) marked
    broken and its tensions (at the platform and at the winch) zero."""
    part_step(k, h, part.cables, bus)
    for i in range(part.k_snap.shape[0]):
        if k >= part.k_snap[i]:
            part.broken[i] = True
            bus.T_app[i] = 0.0
            bus.T_winch[i] = 0.0


@njit(cache=True)
def snapped_tensions(part, j, x, R, v, w, L, J, bus, T):
    T = cable_tensions(part.cables, j, x, R, v, w, L, J, bus, T)
    for i in range(T.shape[0]):
        if part.broken[i]:
            T[i] = 0.0
    return T


@njit(cache=True)
def snapped_mujoco(part, mj, bus):
    mujoco_cables(part.cables, mj, bus)
    for i in range(part.broken.shape[0]):
        if part.broken[i]:  # its motor and its spring stop acting
            mj.ctrl[i] = 0.0
            mj.ten_k[i] = 0.0
            mj.ten_c[i] = 0.0


@part(step=snapped_step, order=40,
      reads=("T_cmd", "T_hold", "x", "R", "J", "L", "Ldot", "L0_drum", "L0"), writes=("T_app", "T_winch"),
      tensions=snapped_tensions, mujoco=snapped_mujoco)
class SnappedCables(NamedTuple):
    """Cables (``cables``: a :class:`HeldTensions`, :class:`ElasticCables` or
    :class:`CatenaryCables`) some of which snap. k_snap (m,) int64: the exchange from which
    each cable is broken (n_steps or more: never). broken (m,) bool: which are broken now
    (set at the exchange, read by the plant within the step)."""

    cables: object
    k_snap: np.ndarray
    broken: np.ndarray


def snap_steps(faults, m: int, h: float) -> np.ndarray:
    """The exchange k from which each of ``m`` cables is snapped (the first with t_k = k h
    >= at_s, to 1e-9 of a step), from the scenario's ``faults``; cables that do not snap get
    the largest int64. Shape (m,), int64."""
    k = np.full(m, np.iinfo(np.int64).max, dtype=np.int64)
    for f in faults:
        if f.kind == "cable_snap":
            k[f.cable - 1] = int(np.ceil(f.at_s / h - 1e-9))
    return k


def build(context) -> list:
    """The scenario's cables; ``context.cable`` is set by the builder to the last one (the
    plant's tension law). With cables that snap, the part wrapped in :class:`SnappedCables`."""
    scenario = context.scenario
    cab = scenario.simulation.cables
    m = scenario.robot.n_cables
    EA = float(cab.stiffness_EA_N or np.inf)
    if cab.model == "ideal" or cab.winch == "tension":
        cables = HeldTensions(from_winch=cab.model != "ideal")
    elif cab.model == "catenary":  # on a length-controlled or motor winch (the scenario's check)
        cables = catenary_part(context.model, scenario.robot.cable_weight_N_m, EA, cab.damping_N_s_m,
                               context.ship_h.R_SO[:, 2, :])
    else:
        cables = ElasticCables(EA=EA, damping=float(cab.damping_N_s_m), Ldot=np.zeros(m))
    if not any(f.kind == "cable_snap" for f in scenario.faults):
        return [cables]
    return [SnappedCables(cables=cables, k_snap=snap_steps(scenario.faults, m, scenario.time.step_s),
                          broken=np.zeros(m, dtype=np.bool_))]
