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

from functools import lru_cache
from typing import TYPE_CHECKING

import numpy as np
from numba import njit

from marinecdpr.motion.ship import ShipMotion, body_motion

if TYPE_CHECKING:
    from marinecdpr.motion.rail import Rail

__all__ = ["carried_motion", "on_rail", "carriage_travel", "frame_yaw", "rail_of", "carriage_motion", "rail_tangent_C",
           "forget_carriage_motions", "CACHED_STEPS"]


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
    s = np.ascontiguousarray(s, dtype=float).ravel()
    a, b, psi_a, psi_b = rail.bends
    yaw, dyaw, ddyaw = np.empty(s.size), np.empty(s.size), np.empty(s.size)
    _yaw_series(s, np.asarray(a, dtype=float), np.asarray(b, dtype=float), np.asarray(psi_b - psi_a, dtype=float),
                yaw, dyaw, ddyaw)
    return yaw, dyaw, ddyaw


@njit(cache=True)
def _yaw_series(s, a, b, d, yaw, dyaw, ddyaw):
    """:func:`frame_yaw`'s sums over the bends (from a to b, turning by d) at every sample."""
    for j in range(s.size):
        y = dy = ddy = 0.0
        for k in range(a.size):
            w = b[k] - a[k]
            x = min(max((s[j] - a[k]) / w, 0.0), 1.0)
            x2 = x * x
            y += d[k] * x2 * x * (10.0 + x * (6.0 * x - 15.0))
            dy += d[k] / w * 30.0 * x2 * (1.0 + x * (x - 2.0))
            ddy += d[k] / (w * w) * 60.0 * x * (1.0 + x * (2.0 * x - 3.0))
        yaw[j], dyaw[j], ddyaw[j] = y, dy, ddy


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
    psi, dpsi, ddpsi = (np.asarray(y, dtype=float) for y in yaw)
    n = s_dot.size
    v, a, omega, alpha = (np.empty((n, 3)) for _ in range(4))
    R_SC = np.empty((n, 3, 3))
    _on_rail_series(np.asarray(points.t, dtype=float), np.asarray(points.dt, dtype=float), np.cos(psi), np.sin(psi),
                    dpsi, ddpsi, s_dot, s_ddot, np.asarray(R_SC0, dtype=float), v, a, R_SC, omega, alpha)
    return points.r, v, a, R_SC, omega, alpha


@njit(cache=True)
def _on_rail_series(t, dt, c, sn, dpsi, ddpsi, s_dot, s_ddot, R0, v, a, R_SC, omega, alpha):
    """:func:`on_rail`'s equations at every sample k (t, dt (n, 3) the rail's tangent and its
    derivative along s; c, sn the cosine and sine of the yaw): v, a (n, 3), R_SC = Rz(psi)
    R_SC0 (n, 3, 3), omega, alpha (n, 3). S's z in C, R_SC^T z, is R_SC0's third row (the yaw
    turns about z)."""
    for k in range(s_dot.size):
        sd, sdd = s_dot[k], s_ddot[k]
        wz = dpsi[k] * sd
        az = ddpsi[k] * sd * sd + dpsi[k] * sdd
        for i in range(3):
            v[k, i] = t[k, i] * sd
            a[k, i] = dt[k, i] * (sd * sd) + t[k, i] * sdd
            R_SC[k, 0, i] = c[k] * R0[0, i] - sn[k] * R0[1, i]
            R_SC[k, 1, i] = sn[k] * R0[0, i] + c[k] * R0[1, i]
            R_SC[k, 2, i] = R0[2, i]
            omega[k, i] = R0[2, i] * wz
            alpha[k, i] = R0[2, i] * az


def carried_motion(ship: ShipMotion, r_S: np.ndarray, v_S: np.ndarray, a_S: np.ndarray, R_SC: np.ndarray,
                   omega_CS_C: np.ndarray, alpha_CS_C: np.ndarray) -> ShipMotion:
    """C's motion in O: the ship's motion composed with C's motion on the ship (the module's
    equations, :func:`_compose` over the samples).

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
        The motion of the body C (origin C's, axes C's) as the models take a ship's
        (:func:`~marinecdpr.motion.ship.body_motion`: its R_SO is R_OC, its eta C's origin in
        O and the Euler angles of R_OC, with their exact derivatives). Its arrays are views
        of time-last buffers, as :func:`~marinecdpr.motion.ship.ship_motion`'s.
    """
    n = r_S.shape[0]
    xt, vt, at, wt, alt = (np.empty((3, n)) for _ in range(5))
    Rt = np.empty((3, 3, n))
    f = np.asarray
    _compose(f(ship.x_SO_O, dtype=float), f(ship.v_SO_O, dtype=float), f(ship.a_SO_O, dtype=float),
             f(ship.R_SO, dtype=float), f(ship.omega_SO_S, dtype=float), f(ship.alpha_SO_S, dtype=float),
             f(r_S, dtype=float), f(v_S, dtype=float), f(a_S, dtype=float), f(R_SC, dtype=float),
             f(omega_CS_C, dtype=float), f(alpha_CS_C, dtype=float), xt, vt, at, Rt, wt, alt)
    return body_motion(xt.T, vt.T, at.T, np.moveaxis(Rt, (0, 1), (-2, -1)), wt.T, alt.T)


@njit(cache=True)
def _compose(x0, v0, a0, R, w, al, r, v, a, Q, wq, aq, xt, vt, at, Rt, wt, alt):
    """The module's composition at every sample k: the ship's x0, v0, a0 (n, 3) in O, R = R_OS
    (n, 3, 3), w, al (n, 3) in S; C on S: r, v, a (n, 3) in S, Q = R_SC (n, 3, 3), wq, aq (n, 3)
    in C. Written time-last: xt, vt, at (3, n) in O, Rt = R_OC (3, 3, n), wt, alt (3, n) in C."""
    for k in range(r.shape[0]):
        w0, w1, w2 = w[k, 0], w[k, 1], w[k, 2]
        r0, r1, r2 = r[k, 0], r[k, 1], r[k, 2]
        u0, u1, u2 = v[k, 0], v[k, 1], v[k, 2]
        wr0, wr1, wr2 = w1 * r2 - w2 * r1, w2 * r0 - w0 * r2, w0 * r1 - w1 * r0  # omega x r
        p0, p1, p2 = wr0 + u0, wr1 + u1, wr2 + u2  # omega x r + v
        # alpha x r + omega x (omega x r) + 2 omega x v + a
        q0 = (al[k, 1] * r2 - al[k, 2] * r1) + (w1 * wr2 - w2 * wr1) + 2.0 * (w1 * u2 - w2 * u1) + a[k, 0]
        q1 = (al[k, 2] * r0 - al[k, 0] * r2) + (w2 * wr0 - w0 * wr2) + 2.0 * (w2 * u0 - w0 * u2) + a[k, 1]
        q2 = (al[k, 0] * r1 - al[k, 1] * r0) + (w0 * wr1 - w1 * wr0) + 2.0 * (w0 * u1 - w1 * u0) + a[k, 2]
        for i in range(3):
            xt[i, k] = x0[k, i] + (R[k, i, 0] * r0 + R[k, i, 1] * r1 + R[k, i, 2] * r2)
            vt[i, k] = v0[k, i] + (R[k, i, 0] * p0 + R[k, i, 1] * p1 + R[k, i, 2] * p2)
            at[i, k] = a0[k, i] + (R[k, i, 0] * q0 + R[k, i, 1] * q1 + R[k, i, 2] * q2)
            for j in range(3):
                Rt[i, j, k] = R[k, i, 0] * Q[k, 0, j] + R[k, i, 1] * Q[k, 1, j] + R[k, i, 2] * Q[k, 2, j]
        c0 = Q[k, 0, 0] * w0 + Q[k, 1, 0] * w1 + Q[k, 2, 0] * w2  # R_SC^T omega
        c1 = Q[k, 0, 1] * w0 + Q[k, 1, 1] * w1 + Q[k, 2, 1] * w2
        c2 = Q[k, 0, 2] * w0 + Q[k, 1, 2] * w1 + Q[k, 2, 2] * w2
        o0, o1, o2 = wq[k, 0], wq[k, 1], wq[k, 2]
        wt[0, k], wt[1, k], wt[2, k] = c0 + o0, c1 + o1, c2 + o2
        cross = (c1 * o2 - c2 * o1, c2 * o0 - c0 * o2, c0 * o1 - c1 * o0)  # (R_SC^T omega) x omega_CS
        for j in range(3):
            alt[j, k] = (Q[k, 0, j] * al[k, 0] + Q[k, 1, j] * al[k, 1] + Q[k, 2, j] * al[k, 2]) + cross[j] + aq[k, j]


def carriage_travel(ship, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """How far the carriage has run along its rail from its first station at times ``t``, and
    its speed and acceleration there (:func:`~marinecdpr.motion.rail.carriage_profile`).

    Parameters
    ----------
    ship : marinecdpr.scenario.schema.Ship
        With ``carriage`` set.
    t : ndarray, shape (n_steps,)
        Times, s (from 0).

    Returns
    -------
    travel, speed, accel : ndarray, shape (n_steps,)
        m, m/s, m/s^2 along the rail.
    """
    from marinecdpr.motion.rail import carriage_profile

    c = ship.carriage
    stations = np.asarray(c.stations_m, dtype=float)
    s, s_dot, s_ddot, _ = carriage_profile(stations, c.dwell_s, c.speed_max_m_s, c.accel_max_m_s2, c.jerk_max_m_s3,
                                           np.asarray(t, dtype=float))
    return s - stations[0], s_dot, s_ddot


def rail_of(ship) -> "Rail":
    """The rail of a scenario's ``[ship.carriage]``, checked (:func:`~marinecdpr.motion.rail.check_rail`);
    a rail that cannot be built raises the ScenarioError naming the key. Built once per rail
    (its points, corner radius and stations; :class:`~marinecdpr.motion.rail.Rail` is immutable)."""
    c = ship.carriage
    return _rail(tuple(map(tuple, np.asarray(c.rail_m, dtype=float).tolist())), float(c.corner_radius_m),
                 tuple(np.asarray(c.stations_m, dtype=float).ravel().tolist()))


@lru_cache(maxsize=16)
def _rail(points: tuple, corner_radius_m: float, stations: tuple) -> "Rail":
    from marinecdpr.errors import ScenarioError
    from marinecdpr.motion.rail import RailError, check_rail, check_stations

    def where(e: RailError) -> str:  # the rail's own key as the scenario's
        key = (e.key or "rail_m").replace("points_S", "rail_m")
        return f"ship.carriage.{key}"

    try:
        rail = check_rail(np.asarray(points, dtype=float), corner_radius_m)
        check_stations(rail, np.asarray(stations, dtype=float))
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

    Returns
    -------
    tuple of ndarray
        :func:`on_rail`'s, read-only: kept for the last few time grids (of at most
        :data:`CACHED_STEPS` times), since a run evaluates one grid for its plan, its plant,
        its controller and its drive (:func:`forget_carriage_motions` drops them).
    """
    return _on_its_rail(ship, t)[1]


def rail_tangent_C(ship, t: np.ndarray) -> np.ndarray:
    """The rail's unit tangent at the carriage's place at times ``t``, in C: shape (n_steps, 3)
    (``ship`` and ``t`` as :func:`carriage_motion`'s)."""
    points, (_, _, _, R_SC, _, _) = _on_its_rail(ship, t)
    return np.einsum("nji,nj->ni", R_SC, points.t)  # R_SC^T t_S


CACHED_STEPS = 1 << 17
"""The longest time grid whose carriage motion is kept (:func:`carriage_motion`): about 35 MB at
most for each of the 4 kept."""


def _on_its_rail(ship, t: np.ndarray):
    """The rail at the carriage's arc lengths at times ``t``, and C's motion on S there:
    read-only arrays, kept for the last few grids of at most :data:`CACHED_STEPS` times, as a
    run evaluates the same grid for its plan, its plant, its controller and its drive."""
    t = np.asarray(t, dtype=float)
    if t.size > CACHED_STEPS:
        out = _evaluate_on_rail(ship, t)
    else:
        key = (ship.carriage.model_dump_json(), tuple(float(v) for v in ship.frame_orientation_deg), t.shape,
               t.tobytes())
        out = _kept_on_rail(_Keyed(key, ship, t))
    return out


def forget_carriage_motions() -> None:
    """Drop the kept carriage motions (:func:`carriage_motion` evaluates afresh)."""
    _kept_on_rail.cache_clear()


class _Keyed:
    """A carriage and a time grid, hashed and compared by ``key`` (for the cache)."""

    __slots__ = ("key", "ship", "t")

    def __init__(self, key, ship, t):
        self.key, self.ship, self.t = key, ship, t

    def __hash__(self) -> int:
        return hash(self.key)

    def __eq__(self, other) -> bool:
        return isinstance(other, _Keyed) and self.key == other.key


@lru_cache(maxsize=4)
def _kept_on_rail(keyed: _Keyed):
    points, rel = out = _evaluate_on_rail(keyed.ship, keyed.t)
    for a in (points.r, points.t, points.dt, points.ddt, *rel):
        a.flags.writeable = False
    return out


def _evaluate_on_rail(ship, t: np.ndarray):
    from marinecdpr.motion.rail import carriage_profile
    from marinecdpr.motion.ship import frame_axes

    c = ship.carriage
    rail = rail_of(ship)
    s, s_dot, s_ddot, _ = carriage_profile(np.asarray(c.stations_m, dtype=float), c.dwell_s, c.speed_max_m_s,
                                           c.accel_max_m_s2, c.jerk_max_m_s3, t)
    points = rail.at(s, heading=False)
    return points, on_rail(points, frame_yaw(rail, s), s_dot, s_ddot, frame_axes(ship.frame_orientation_deg))
