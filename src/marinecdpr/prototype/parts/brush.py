"""A cleaning brush on the hull (``[cleaning]``): its loads at the platform's actual velocity
(:mod:`marinecdpr.model.brush`), less those along the plan that the controller's load
model already holds, onto the bus's ``f_ext``, ``m_ext`` (in C, about P; held over the
step by the plant).

Where the brush's path is held on the ship while the carriage carries the frame
(``trajectory.on_hull``) the brush slides over the hull, not over C: the part is then
:class:`BrushOnHull`, whose velocity relative to the hull adds the carriage's (the plan's
:func:`~marinecdpr.planning.planner.twist_on_hull` at the plant's state).

A ``brush_contact_loss`` fault (``[[faults]]``) is the part's mode: its normal force is zero
over the fault's window (:func:`contact_lost`), so that the brush presses and drags nothing
there; the controller's load model still holds the plan's brush loads (it is not told)."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from marinecdpr.model.brush import BrushParams, brush_velocity_step, brush_wrench_step
from marinecdpr.prototype.parts import part

__all__ = ["BrushContact", "BrushOnHull", "build", "contact_force", "contact_lost", "normal_force"]


@njit(cache=True)
def _brush_loads(k, brush, v, w, bus):
    """The brush's loads at exchange k, the platform moving over the hull with twist (v, w) in C,
    less the plan's, onto the bus's f_ext, m_ext."""
    brush_velocity_step(v, w, bus.R, brush.params.offset_P, brush.v)
    brush_wrench_step(brush.v, brush.n_C, brush.F_n[k], bus.R, brush.params, bus.f_ext, bus.m_ext)
    for i in range(3):
        bus.f_ext[i] -= brush.f_plan[k, i]
        bus.m_ext[i] -= brush.m_plan[k, i]


@njit(cache=True)
def brush_step(k, h, part, bus):
    _brush_loads(k, part, bus.v, bus.w, bus)


@part(step=brush_step, order=50, reads=("R", "v", "w"), writes=("f_ext", "m_ext"))
class BrushContact(NamedTuple):
    """params : the brush (:class:`~marinecdpr.model.brush.BrushParams`). n_C : (3,) the hull
    normal in C. F_n : (n_steps,) the normal force, N. f_plan, m_plan : (n_steps, 3) the
    brush's loads along the planned path, in C (what the controller's ``Loads`` hold).
    v (3,): scratch, the brush's velocity."""

    params: BrushParams
    n_C: np.ndarray
    F_n: np.ndarray
    f_plan: np.ndarray
    m_plan: np.ndarray
    v: np.ndarray


@njit(cache=True)
def brush_on_hull_step(k, h, part, bus):
    x, v, w, vc, wc, vh, wh = bus.x, bus.v, bus.w, part.v_c[k], part.w_c[k], part.v_h, part.w_h
    vh[0] = v[0] + vc[0] + (wc[1] * x[2] - wc[2] * x[1])  # v_PC + R_SC^T v_S + omega_CS x x_PC
    vh[1] = v[1] + vc[1] + (wc[2] * x[0] - wc[0] * x[2])
    vh[2] = v[2] + vc[2] + (wc[0] * x[1] - wc[1] * x[0])
    for i in range(3):
        wh[i] = w[i] + wc[i]
    _brush_loads(k, part.brush, vh, wh, bus)


@part(step=brush_on_hull_step, order=50, reads=("x", "R", "v", "w"), writes=("f_ext", "m_ext"))
class BrushOnHull(NamedTuple):
    """A :class:`BrushContact` (``brush``) on a hull that moves under the frame
    (``trajectory.on_hull``); v_c, w_c : (n_steps, 3) the carriage's R_SC^T v_S (m/s) and
    omega_CS (rad/s) in C at t_k (:func:`~marinecdpr.motion.carriage.carriage_motion`); v_h,
    w_h (3,): scratch, the platform's twist relative to the hull."""

    brush: BrushContact
    v_c: np.ndarray
    w_c: np.ndarray
    v_h: np.ndarray
    w_h: np.ndarray


def normal_force(p, scenario) -> np.ndarray:
    """The brush's contact force over the plan's steps, (n_steps,), N: on a planar robot the
    plan's guide reaction along the hull normal plus twice the preload (the pusher presses
    with the preload; the planned loads include the hull's push at the preload); on a
    robot whose cables control the normal, the preload."""
    cleaning = scenario.cleaning
    n = np.asarray(cleaning.hull_normal, dtype=float)
    if "y" not in p.reaction_dofs or abs(n[1]) < 1.0 - 1e-9:
        return np.full(p.n_steps, cleaning.preload)
    return contact_force(p.reaction[:, p.reaction_dofs.index("y")], cleaning, static_y_N=static_weight_y(scenario))


def static_weight_y(scenario) -> float:
    """The platform's weight along C's y with the frame at its orientation on a ship at rest,
    N: m (R_SC^T g)_y, g = (0, 0, -g) (0 for a frame upright on the ship; on a frame leaning
    with a flared side, the part of the weight the pusher carries)."""
    if not scenario.ship.turned:
        return 0.0
    from marinecdpr.motion.ship import frame_axes

    g_C = frame_axes(scenario.ship.frame_orientation_deg).T @ np.array([0.0, 0.0, -scenario.environment.gravity_m_s2])
    return float(scenario.robot.mass_kg * g_C[1])


def contact_force(reaction_y, cleaning, *, static_y_N: float = 0.0):
    """A planar robot's brush force from the guide's reaction along y (its hull normal), N:
    the reaction along the normal plus twice the preload (the planned wrench holds the hull's
    push at the preload), plus the platform's static weight along the normal, which the
    pusher's setpoint carries (a frame leaning on a flared side: :func:`static_weight_y`).

    Parameters
    ----------
    reaction_y : ndarray
        The required wrench's y force, which the guide holds, N.
    cleaning : Cleaning
        ``hull_normal`` along +-y.
    static_y_N : float
        The weight's y force at rest, in C, N (0 for a frame upright on the ship).
    """
    n_y = cleaning.hull_normal[1]
    out = np.asarray(reaction_y) * n_y + 2.0 * cleaning.preload
    return out if static_y_N == 0.0 else out + static_y_N * n_y


def contact_lost(F_n, faults, h: float) -> np.ndarray:
    """The brush's normal force (n_steps,), N, with the scenario's ``brush_contact_loss``
    faults: zero from the first exchange at or after at_s until the first at or after at_s +
    duration_s (to the end without it); a copy, F_n itself where there is none."""
    lost = [f for f in faults if f.kind == "brush_contact_loss"]
    if not lost:
        return F_n
    out = np.array(F_n, dtype=float, copy=True)
    for f in lost:
        k0 = int(np.ceil(f.at_s / h - 1e-9))
        k1 = out.shape[0] if f.duration_s is None else int(np.ceil((f.at_s + f.duration_s) / h - 1e-9))
        out[k0:k1] = 0.0
    return out


def build(context) -> list:
    """The brush's contact part (none without ``[cleaning]``): its planned loads at t_k
    (``context.brush_h``'s every other row) and the normal force (:func:`normal_force`; zero
    where the contact is lost, :func:`contact_lost`); a :class:`BrushOnHull` where the path is
    held on the ship (``trajectory.on_hull``), with the carriage's motion at t_k."""
    from marinecdpr.model.brush import cleaning_brush

    scenario, n = context.scenario, context.n_steps
    cleaning = scenario.cleaning
    if cleaning is None:
        return []
    f_b, m_b = context.brush_h.f, context.brush_h.m
    brush = BrushContact(params=cleaning_brush(cleaning), n_C=np.asarray(cleaning.hull_normal, dtype=float),
                         F_n=np.ascontiguousarray(contact_lost(normal_force(context.plan, scenario)[:n],
                                                               scenario.faults, scenario.time.step_s)),
                         f_plan=np.ascontiguousarray(f_b[::2][:n]), m_plan=np.ascontiguousarray(m_b[::2][:n]),
                         v=np.zeros(3))
    if not getattr(scenario.trajectory, "on_hull", False):
        return [brush]
    from marinecdpr.motion.carriage import carriage_motion

    _, v_S, _, R_SC, omega, _ = carriage_motion(scenario.ship, np.arange(n) * scenario.time.step_s)
    return [BrushOnHull(brush=brush, v_c=np.ascontiguousarray(np.einsum("nji,nj->ni", R_SC, v_S)),
                        w_c=np.ascontiguousarray(omega, dtype=float), v_h=np.zeros(3), w_h=np.zeros(3))]
