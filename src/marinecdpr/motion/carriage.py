"""A frame carried along the ship: C's motion in O, the ship's composed with the carriage's.

Without a carriage C stands still on S (``ship.frame_origin_m``, ``frame_orientation_deg``)
and the models take the ship's motion and C's constant place on it. With one, C's place and
axes on S change with time, and the models take C's own motion in O instead (a
:class:`~marinecdpr.motion.ship.ShipMotion` of the body C, whose origin is C's: the frame
then stands at its own origin, ``frame_origin_S = 0``). For C at r_SC(t) on S with axes
R_SC(t), moving relative to S with v = dr/dt, a = d2r/dt2 (in S) and angular velocity and
acceleration omega_CS, alpha_CS (relative to S, in C), and the ship's omega, alpha (in S):

    x_OC   = x_OS + R_OS r
    v_OC   = v_OS + R_OS (omega x r + v)
    a_OC   = a_OS + R_OS (alpha x r + omega x (omega x r) + 2 omega x v + a)
             (the transport, centripetal and Coriolis terms of the ship's rotation)
    R_OC   = R_OS R_SC
    omega_C = R_SC^T omega + omega_CS
    alpha_C = R_SC^T alpha + (R_SC^T omega) x omega_CS + alpha_CS

On a rail (:mod:`marinecdpr.motion.rail`) at arc length s(t), r = rail(s), v = t s', a =
(dt/ds) s'^2 + t s''; C's axes turn about S's z by the frame's yaw psi(s) (its lean kept):
R_SC = Rz(psi(s)) R_SC0, so omega_CS = R_SC^T z psi' s' and alpha_CS = R_SC^T z (psi''
s'^2 + psi' s''). The yaw (:func:`frame_yaw`) is the rail's heading on its straight pieces
and turns through each bend by a quintic law in s, so that C's angular velocity and
acceleration stay continuous: a yaw locked to the tangent of a line-and-arc rail would step
the angular velocity by s' / R at each join (an impulse of angular acceleration, which no
drive gives).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from marinecdpr.motion.ship import ShipMotion, body_motion

if TYPE_CHECKING:
    from marinecdpr.motion.rail import Rail

__all__ = ["carried_motion", "on_rail", "frame_yaw", "rail_of", "carriage_motion", "rail_tangent_C",
           "carriage_joints", "carriage_motion_and_joints"]


def _rz(angle: np.ndarray) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    R = np.zeros(angle.shape + (3, 3))
    R[..., 0, 0], R[..., 0, 1], R[..., 1, 0], R[..., 1, 1], R[..., 2, 2] = c, -s, s, c, 1.0
    return R


def frame_yaw(rail, s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The frame's yaw on the ship relative to its yaw at the rail's start, and its first two
    derivatives along the rail, at arc lengths ``s``.

    On the straight pieces it is the rail's heading (from the start's); through each bend,
    from the arc's start a to its end b, it turns by the bend's change of heading d along the
    quintic S(x) = 10 x^3 - 15 x^4 + 6 x^5, x = (s - a) / (b - a), whose first and second
    derivatives vanish at both ends: the yaw is twice continuously differentiable in s.

    Parameters
    ----------
    rail : Rail
    s : ndarray, shape (n,)
        Arc lengths, m.

    Returns
    -------
    yaw, dyaw, ddyaw : ndarray, shape (n,)
        rad, rad/m, rad/m^2.
    """
    s = np.asarray(s, dtype=float)
    a, b, psi_a, psi_b = rail.bends
    yaw, dyaw, ddyaw = np.zeros(s.size), np.zeros(s.size), np.zeros(s.size)
    for a_k, b_k, d_k in zip(a, b, psi_b - psi_a):  # one pass per bend, over every sample
        w = b_k - a_k
        x = np.clip((s - a_k) / w, 0.0, 1.0)
        x2 = x * x
        yaw += d_k * x2 * x * (10.0 + x * (6.0 * x - 15.0))
        dyaw += d_k / w * 30.0 * x2 * (1.0 + x * (x - 2.0))
        ddyaw += d_k / (w * w) * 60.0 * x * (1.0 + x * (2.0 * x - 3.0))
    return yaw, dyaw, ddyaw


def on_rail(points, yaw: tuple[np.ndarray, np.ndarray, np.ndarray], s_dot: np.ndarray, s_ddot: np.ndarray,
            R_SC0: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """C's motion relative to S, carried along a rail with its axes turned by its yaw.

    Parameters
    ----------
    points : RailPoints
        The rail at the carriage's arc lengths s(t) (:meth:`~marinecdpr.motion.rail.Rail.at`),
        n_steps of them: r (m), t and dt (1/m) along s.
    yaw : tuple of ndarray, each shape (n_steps,)
        The frame's yaw on S from its start (:func:`frame_yaw`) and its first two derivatives
        along s: rad, rad/m, rad/m^2.
    s_dot, s_ddot : ndarray, shape (n_steps,)
        The carriage's speed (m/s) and acceleration (m/s^2) along the rail.
    R_SC0 : ndarray, shape (3, 3)
        C's axes in S at the rail's start (``ship.frame_orientation_deg``: the frame's lean).

    Returns
    -------
    r_S, v_S, a_S : ndarray, shape (n_steps, 3)
        C's origin on S, its velocity and acceleration relative to S, in S: m, m/s, m/s^2.
    R_SC : ndarray, shape (n_steps, 3, 3)
    omega_CS_C, alpha_CS_C : ndarray, shape (n_steps, 3)
        C's angular velocity (rad/s) and acceleration (rad/s^2) relative to S, in C.
    """
    s_dot = np.asarray(s_dot, dtype=float)
    s_ddot = np.asarray(s_ddot, dtype=float)
    psi, dpsi, ddpsi = yaw
    v = points.t * s_dot[:, None]
    a = points.dt * (s_dot * s_dot)[:, None] + points.t * s_ddot[:, None]
    R_SC = _rz(psi) @ R_SC0
    z_C = R_SC[:, 2, :]  # rows: R_SC^T z, S's z in C
    omega = z_C * (dpsi * s_dot)[:, None]
    alpha = z_C * (ddpsi * s_dot * s_dot + dpsi * s_ddot)[:, None]
    return points.r, v, a, R_SC, omega, alpha


def carried_motion(ship: ShipMotion, r_S: np.ndarray, v_S: np.ndarray, a_S: np.ndarray, R_SC: np.ndarray,
                   omega_CS_C: np.ndarray, alpha_CS_C: np.ndarray) -> ShipMotion:
    """C's motion in O: the ship's motion composed with C's motion on the ship (the module's equations).

    Parameters
    ----------
    ship : ShipMotion
        S's motion in O, n_steps samples.
    r_S, v_S, a_S : ndarray, shape (n_steps, 3)
        C's origin on S and its velocity and acceleration relative to S, in S (m, m/s, m/s^2).
    R_SC : ndarray, shape (n_steps, 3, 3)
        C's axes in S.
    omega_CS_C, alpha_CS_C : ndarray, shape (n_steps, 3)
        C's angular velocity and acceleration relative to S, in C (rad/s, rad/s^2).

    Returns
    -------
    ShipMotion
        The motion of the body C (origin C's, axes C's) as the models take a ship's: its eta
        is C's origin in O and the Euler angles of R_OC, with their exact derivatives.
    """
    R_OS = ship.R_SO  # R_S^O
    w, al = ship.omega_SO_S, ship.alpha_SO_S
    x = ship.eta[:, :3] + np.einsum("nij,nj->ni", R_OS, r_S)
    w_r = np.cross(w, r_S)
    v = ship.eta_dot[:, :3] + np.einsum("nij,nj->ni", R_OS, w_r + v_S)
    rel = np.cross(al, r_S) + np.cross(w, w_r) + 2.0 * np.cross(w, v_S) + a_S
    a = ship.eta_ddot[:, :3] + np.einsum("nij,nj->ni", R_OS, rel)
    R_OC = R_OS @ R_SC
    w_C = np.einsum("nji,nj->ni", R_SC, w)  # R_SC^T omega
    omega_C = w_C + omega_CS_C
    alpha_C = np.einsum("nji,nj->ni", R_SC, al) + np.cross(w_C, omega_CS_C) + alpha_CS_C
    return body_motion(x, v, a, R_OC, omega_C, alpha_C)


def rail_of(ship) -> "Rail":
    """The rail of a scenario's ``[ship.carriage]``, checked (:func:`~marinecdpr.motion.rail.check_rail`);
    a rail that cannot be built raises the ScenarioError naming the key."""
    from marinecdpr.errors import ScenarioError
    from marinecdpr.motion.rail import RailError, check_rail, check_stations

    c = ship.carriage

    def where(e: RailError) -> str:  # the rail's own key as the scenario's
        key = (e.key or "rail_m").replace("points_S", "rail_m")
        return f"ship.carriage.{key}"

    try:
        rail = check_rail(np.asarray(c.rail_m, dtype=float), c.corner_radius_m)
        check_stations(rail, np.asarray(c.stations_m, dtype=float))
    except RailError as e:
        raise ScenarioError(e.detail, key=where(e)) from None
    return rail


def carriage_motion(ship, t: np.ndarray
                    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """C's motion relative to S at times ``t`` for a scenario's ``[ship]`` with a carriage
    (:func:`on_rail`'s returns): the carriage's jerk-limited moves between its stations
    (:func:`~marinecdpr.motion.rail.carriage_profile`) on its rail.

    Parameters
    ----------
    ship : marinecdpr.scenario.schema.Ship
        With ``carriage`` set.
    t : ndarray, shape (n_steps,)
        Times, s (from 0).
    """
    return _on_its_rail(ship, t)[1]


def carriage_joints(ship, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The carriage's pose on S as joint coordinates, at times ``t``: C's origin in S and the
    frame's yaw about S's z from its start, R_SC = Rz(yaw) R_SC0 (a body on slides along S's
    x, y, z and a hinge about its z, in that order, has these coordinates: MuJoCo's carriage),
    and their first two time derivatives (``ship`` and ``t`` as :func:`carriage_motion`'s).

    Returns
    -------
    q, q_dot, q_ddot : ndarray, shape (n_steps, 4)
        (x, y, z, yaw): m, rad; m/s, rad/s; m/s^2, rad/s^2. The position's are
        :func:`on_rail`'s r, v, a; the yaw's rates are the components of C's angular velocity
        and acceleration on S along S's z (the yaw turns C about it alone).
    """
    return carriage_motion_and_joints(ship, t)[1]


def carriage_motion_and_joints(ship, t: np.ndarray) -> tuple[tuple, tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """:func:`carriage_motion` and :func:`carriage_joints` at once (the rail evaluated once)."""
    _, motion, yaw = _on_its_rail(ship, t, with_yaw=True)
    r, v, a, R_SC, omega, alpha = motion
    z_C = R_SC[:, 2, :]  # S's z in C
    q = np.concatenate([r, yaw[:, None]], axis=1)
    q_dot = np.concatenate([v, np.einsum("ni,ni->n", omega, z_C)[:, None]], axis=1)
    q_ddot = np.concatenate([a, np.einsum("ni,ni->n", alpha, z_C)[:, None]], axis=1)
    return motion, (q, q_dot, q_ddot)


def rail_tangent_C(ship, t: np.ndarray) -> np.ndarray:
    """The rail's unit tangent at the carriage's place at times ``t``, in C: shape (n_steps, 3)
    (``ship`` and ``t`` as :func:`carriage_motion`'s)."""
    points, (_, _, _, R_SC, _, _) = _on_its_rail(ship, t)
    return np.einsum("nji,nj->ni", R_SC, points.t)  # R_SC^T t_S


def _on_its_rail(ship, t: np.ndarray, *, with_yaw: bool = False):
    """The rail at the carriage's arc lengths at times ``t``, and C's motion on S there (and
    the frame's yaw from its start, rad, ``with_yaw``)."""
    from marinecdpr.motion.rail import carriage_profile
    from marinecdpr.motion.ship import frame_axes

    c = ship.carriage
    rail = rail_of(ship)
    s, s_dot, s_ddot, _ = carriage_profile(np.asarray(c.stations_m, dtype=float), c.dwell_s, c.speed_max_m_s,
                                           c.accel_max_m_s2, c.jerk_max_m_s3, np.asarray(t, dtype=float))
    points = rail.at(s)
    yaw = frame_yaw(rail, s)
    motion = on_rail(points, yaw, s_dot, s_ddot, frame_axes(ship.frame_orientation_deg))
    return (points, motion, yaw[0]) if with_yaw else (points, motion)
