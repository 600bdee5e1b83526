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

import numpy as np
from numba import njit

from marinecdpr.errors import ScenarioError
from marinecdpr.motion.rail import (
    _S_TOL_M, Rail, RailError, _phase_table, _profile_point, _rail_point, carriage_profile, check_rail, check_stations,
)
from marinecdpr.motion.ship import ShipMotion, body_motion, frame_axes


__all__ = ["carried_motion", "carried_frame_motion", "on_rail", "carriage_travel", "frame_yaw", "rail_of",
           "carriage_motion", "rail_tangent_C", "forget_carriage_motions", "CACHED_STEPS"]


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
    """:func:`_yaw_point` at every sample (once for a run of equal arc lengths: a carriage at
    rest)."""
    for j in range(s.size):
        if j > 0 and s[j] == s[j - 1]:
            yaw[j], dyaw[j], ddyaw[j] = yaw[j - 1], dyaw[j - 1], ddyaw[j - 1]
        else:
            yaw[j], dyaw[j], ddyaw[j] = _yaw_point(s[j], a, b, d)


@njit(cache=True, inline="always")
def _yaw_point(x, a, b, d):
    """:func:`frame_yaw`'s sums over the bends (from a to b, turning by d) at one arc length x:
    yaw, dyaw, ddyaw."""
    y = dy = ddy = 0.0
    for k in range(a.size):
        w = b[k] - a[k]
        u = min(max((x - a[k]) / w, 0.0), 1.0)
        u2 = u * u
        y += d[k] * u2 * u * (10.0 + u * (6.0 * u - 15.0))
        dy += d[k] / w * 30.0 * u2 * (1.0 + u * (u - 2.0))
        ddy += d[k] / (w * w) * 60.0 * u * (1.0 + u * (2.0 * u - 3.0))
    return y, dy, ddy


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
    _on_rail_series(np.asarray(points.t, dtype=float), np.asarray(points.dt, dtype=float), psi, dpsi, ddpsi, s_dot,
                    s_ddot, np.asarray(R_SC0, dtype=float), v, a, R_SC, omega, alpha)
    return points.r, v, a, R_SC, omega, alpha


@njit(cache=True)
def _on_rail_series(t, dt, psi, dpsi, ddpsi, s_dot, s_ddot, R0, v, a, R_SC, omega, alpha):
    """:func:`_on_rail_point` at every sample k: v, a (n, 3), R_SC (n, 3, 3), omega, alpha (n, 3)."""
    last, cos, sin = np.nan, 0.0, 0.0
    for k in range(s_dot.size):
        last, cos, sin = _on_rail_point(t, dt, k, psi[k], dpsi[k], ddpsi[k], s_dot[k], s_ddot[k], R0, last, cos, sin,
                                        v, a, R_SC, omega, alpha, k)


@njit(cache=True, inline="always")
def _on_rail_point(t, dt, j, psi, dpsi, ddpsi, sd, sdd, R0, last, cos, sin, v, a, R_SC, omega, alpha, k):
    """:func:`on_rail`'s equations at one sample, the rail's tangent and its derivative along s
    in row j of t, dt (n, 3), the yaw psi and its derivatives, the speed and acceleration
    along the rail, written in row k of v, a (m, 3), R_SC = Rz(psi) R_SC0 (m, 3, 3), omega,
    alpha (m, 3). S's z in C, R_SC^T z, is R_SC0's third row (the yaw turns about z). last,
    cos, sin: the last sample's yaw, its cosine and sine, taken again only for a new yaw (a
    straight piece, a rest; NaN for none); returned for the next."""
    if psi != last:
        last, cos, sin = psi, np.cos(psi), np.sin(psi)
    wz = dpsi * sd
    az = ddpsi * sd * sd + dpsi * sdd
    for i in range(3):
        v[k, i] = t[j, i] * sd
        a[k, i] = dt[j, i] * (sd * sd) + t[j, i] * sdd
        R_SC[k, 0, i] = cos * R0[0, i] - sin * R0[1, i]
        R_SC[k, 1, i] = sin * R0[0, i] + cos * R0[1, i]
        R_SC[k, 2, i] = R0[2, i]
        omega[k, i] = R0[2, i] * wz
        alpha[k, i] = R0[2, i] * az
    return last, cos, sin


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
    out = np.empty((24, r_S.shape[0]))
    f = np.asarray
    _compose(*_time_last(ship), f(r_S, dtype=float), f(v_S, dtype=float), f(a_S, dtype=float), f(R_SC, dtype=float),
             f(omega_CS_C, dtype=float), f(alpha_CS_C, dtype=float), out)
    return _as_motion(out)


def _time_last(ship: ShipMotion) -> tuple:
    """The ship's x, v, a (3, n), R_OS (3, 3, n), omega, alpha (3, n) time-last and C-contiguous
    (views of its own buffers where they are so, as :func:`~marinecdpr.motion.ship.ship_motion`'s)."""
    f = np.ascontiguousarray
    R = np.asarray(ship.R_SO, dtype=float).transpose(1, 2, 0)
    return (*(f(np.asarray(a, dtype=float).T) for a in (ship.x_SO_O, ship.v_SO_O, ship.a_SO_O)), f(R),
            *(f(np.asarray(a, dtype=float).T) for a in (ship.omega_SO_S, ship.alpha_SO_S)))


def _as_motion(out: np.ndarray) -> ShipMotion:
    """C's motion from :func:`_compose_point`'s rows (24, n): views of time-last buffers, as
    :func:`~marinecdpr.motion.ship.ship_motion`'s."""
    R = np.moveaxis(out[9:18].reshape(3, 3, -1), (0, 1), (-2, -1))
    return body_motion(out[0:3].T, out[3:6].T, out[6:9].T, R, out[18:21].T, out[21:24].T)


@njit(cache=True)
def _compose(x0, v0, a0, R, w, al, r, v, a, Q, wq, aq, out):
    """:func:`_compose_point` at every sample k (C on S in row k of r, v, a, Q, wq, aq)."""
    for k in range(r.shape[0]):
        _compose_point(x0, v0, a0, R, w, al, k, r, v, a, Q, wq, aq, k, out)


@njit(cache=True, inline="always")
def _compose_point(x0, v0, a0, R, w, al, k, r, v, a, Q, wq, aq, j, out):
    """The module's composition at sample k: the ship's x0, v0, a0 (3, n) in O, R = R_OS (3, 3,
    n), w, al (3, n) in S, time-last, their column k; C on S: r, v, a (m, 3) in S, Q = R_SC (m,
    3, 3), wq, aq (m, 3) in C, their row j. Written in column k of out (24, n): x, v, a in O,
    R_OC (row-major), omega, alpha in C."""
    w0, w1, w2 = w[0, k], w[1, k], w[2, k]
    r0, r1, r2 = r[j, 0], r[j, 1], r[j, 2]
    u0, u1, u2 = v[j, 0], v[j, 1], v[j, 2]
    wr0, wr1, wr2 = w1 * r2 - w2 * r1, w2 * r0 - w0 * r2, w0 * r1 - w1 * r0  # omega x r
    p0, p1, p2 = wr0 + u0, wr1 + u1, wr2 + u2  # omega x r + v
    # alpha x r + omega x (omega x r) + 2 omega x v + a
    q0 = (al[1, k] * r2 - al[2, k] * r1) + (w1 * wr2 - w2 * wr1) + 2.0 * (w1 * u2 - w2 * u1) + a[j, 0]
    q1 = (al[2, k] * r0 - al[0, k] * r2) + (w2 * wr0 - w0 * wr2) + 2.0 * (w2 * u0 - w0 * u2) + a[j, 1]
    q2 = (al[0, k] * r1 - al[1, k] * r0) + (w0 * wr1 - w1 * wr0) + 2.0 * (w0 * u1 - w1 * u0) + a[j, 2]
    for i in range(3):
        Ri0, Ri1, Ri2 = R[i, 0, k], R[i, 1, k], R[i, 2, k]
        out[i, k] = x0[i, k] + (Ri0 * r0 + Ri1 * r1 + Ri2 * r2)
        out[3 + i, k] = v0[i, k] + (Ri0 * p0 + Ri1 * p1 + Ri2 * p2)
        out[6 + i, k] = a0[i, k] + (Ri0 * q0 + Ri1 * q1 + Ri2 * q2)
        for m in range(3):  # R_OC = R_OS R_SC
            out[9 + 3 * i + m, k] = Ri0 * Q[j, 0, m] + Ri1 * Q[j, 1, m] + Ri2 * Q[j, 2, m]
    c0 = Q[j, 0, 0] * w0 + Q[j, 1, 0] * w1 + Q[j, 2, 0] * w2  # R_SC^T omega
    c1 = Q[j, 0, 1] * w0 + Q[j, 1, 1] * w1 + Q[j, 2, 1] * w2
    c2 = Q[j, 0, 2] * w0 + Q[j, 1, 2] * w1 + Q[j, 2, 2] * w2
    o0, o1, o2 = wq[j, 0], wq[j, 1], wq[j, 2]
    out[18, k], out[19, k], out[20, k] = c0 + o0, c1 + o1, c2 + o2
    # R_SC^T alpha + (R_SC^T omega) x omega_CS + alpha_CS
    out[21, k] = (Q[j, 0, 0] * al[0, k] + Q[j, 1, 0] * al[1, k] + Q[j, 2, 0] * al[2, k]) \
        + (c1 * o2 - c2 * o1) + aq[j, 0]
    out[22, k] = (Q[j, 0, 1] * al[0, k] + Q[j, 1, 1] * al[1, k] + Q[j, 2, 1] * al[2, k]) \
        + (c2 * o0 - c0 * o2) + aq[j, 1]
    out[23, k] = (Q[j, 0, 2] * al[0, k] + Q[j, 1, 2] * al[1, k] + Q[j, 2, 2] * al[2, k]) \
        + (c0 * o1 - c1 * o0) + aq[j, 2]


def carried_frame_motion(ship: ShipMotion, carried, t: np.ndarray) -> ShipMotion:
    """C's motion in O for a scenario's ``[ship]`` with a carriage, at times ``t``:
    :func:`carried_motion` of ``ship`` and :func:`carriage_motion`, the same to the bit, in one
    compiled pass over the samples (the carriage's profile, the rail, the yaw, C on S and the
    composition at each; C on S once for a run of samples where the carriage rests), without
    keeping C's motion on S (what the models take: :func:`~marinecdpr.motion.basemotion.frame_ship_motion`).

    Parameters
    ----------
    ship : ShipMotion
        S's motion in O at times ``t``.
    carried : marinecdpr.scenario.schema.Ship
        With ``carriage`` set.
    t : ndarray, shape (n_steps,)
        Times, s (from 0).

    Returns
    -------
    ShipMotion
        As :func:`carried_motion`'s.

    Raises
    ------
    RailError
        As :func:`carriage_motion`'s (times before 0 or not numbers).
    ValueError
        ``ship`` and ``t`` of different lengths.
    """
    t = np.asarray(t, dtype=float)
    if t.ndim != 1 or t.size == 0:  # the series' own refusals
        return carried_motion(ship, *carriage_motion(carried, t))
    if np.shape(ship.R_SO)[0] != t.size:
        raise ValueError(f"the ship's motion has {np.shape(ship.R_SO)[0]} samples and t {t.size}: give one a time")
    out = np.empty((24, t.size))
    if _carried_series(t, *_carriage_tables(carried), *_time_last(ship), out) >= 0:
        # a time before 0 or not a number, or the carriage off its rail: the series say which
        return carried_motion(ship, *carriage_motion(carried, t))
    return _as_motion(out)


def _carriage_tables(carried) -> tuple:
    """What :func:`_carried_series` reads of a carriage, built once per carriage and frame
    orientation: its profile's phases (start, s, v, a, jerk), the rail's length and the
    tolerance on it, its pieces (s0, kappa, a0, u, nrm), its bends (start, end, turn) and
    R_SC0."""
    c = carried.carriage
    dwell = tuple(c.dwell_s) if isinstance(c.dwell_s, list) else float(c.dwell_s)
    return _tables(_rail_key(c), dwell, float(c.speed_max_m_s), float(c.accel_max_m_s2), float(c.jerk_max_m_s3),
                   tuple(float(v) for v in carried.frame_orientation_deg))


@lru_cache(maxsize=16)
def _tables(rail_key: tuple, dwell, v_max: float, a_max: float, j_max: float, orientation: tuple) -> tuple:
    rail = _rail(*rail_key)
    stations = np.array(rail_key[2])
    phases, _ = _phase_table(stations, dwell if isinstance(dwell, float) else list(dwell), v_max, a_max, j_max)
    s0, a0, u, nrm, kappa, _ = rail._pieces
    a, b, psi_a, psi_b = rail.bends
    f = np.ascontiguousarray
    return (*phases, rail.length_m, _S_TOL_M, s0, kappa, a0, u, nrm, f(a, dtype=float), f(b, dtype=float),
            f(psi_b - psi_a, dtype=float), frame_axes(orientation))


@njit(cache=True)
def _carried_series(t, start, p_s, p_v, p_a, p_j, length, tol, s0, kappa, a0, u, nrm, ba, bb, bd, R0,
                    x0, v0, ac0, R, w, al, out):
    """:func:`carried_frame_motion` at every sample k: the profile's phases (start, s, v, a,
    jerk), the rail's pieces, its bends (from ba to bb turning by bd), R_SC0, the ship's
    motion and the output (as :func:`_compose_point` reads and writes them). Returns -1, or the
    first sample whose time is not a number >= 0 or whose arc length is further than tol off
    the rail's [0, length] (none written after it)."""
    rows = np.empty((8, 1, 3))  # C on S at the sample: r, t, dt, ddt of the rail; v, a, omega, alpha
    r, tan, dt, ddt, v, a, om, alp = rows[0], rows[1], rows[2], rows[3], rows[4], rows[5], rows[6], rows[7]
    Q = np.empty((1, 3, 3))
    phase = piece = 0
    last_phi, c, sn, h = np.nan, 0.0, 0.0, 0.0  # the rail's arc angle and its trigonometry at the last point
    last_psi, cos, sin = np.nan, 0.0, 0.0  # the yaw's
    last_s = last_v = last_a = np.nan
    resting = False  # the last sample's phase is a rest (s, its speed and acceleration constant through it)
    for k in range(t.size):
        if not t[k] >= 0.0:
            return k
        if resting and start[phase] <= t[k] and (phase + 1 == start.size or t[k] < start[phase + 1]):
            pass  # C on S as at k - 1
        else:
            phase, s, sd, sdd, _ = _profile_point(start, p_s, p_v, p_a, p_j, t[k], phase)
            resting = p_v[phase] == 0.0 and p_a[phase] == 0.0 and p_j[phase] == 0.0
        if not (s == last_s and sd == last_v and sdd == last_a):  # else C on S as at k - 1
            if s < -tol or s > length + tol:
                return k
            piece, last_phi, c, sn, h = _rail_point(s0, kappa, a0, u, nrm, min(max(s, 0.0), length), piece, last_phi, c,
                                                    sn, h, r, tan, dt, ddt, 0)
            psi, dpsi, ddpsi = _yaw_point(s, ba, bb, bd)
            last_psi, cos, sin = _on_rail_point(tan, dt, 0, psi, dpsi, ddpsi, sd, sdd, R0, last_psi, cos, sin, v, a, Q,
                                                om, alp, 0)
            last_s, last_v, last_a = s, sd, sdd
        _compose_point(x0, v0, ac0, R, w, al, k, r, v, a, Q, om, alp, 0, out)
    return -1


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
    c = ship.carriage
    stations = np.asarray(c.stations_m, dtype=float)
    s, s_dot, s_ddot, _ = carriage_profile(stations, c.dwell_s, c.speed_max_m_s, c.accel_max_m_s2, c.jerk_max_m_s3,
                                           np.asarray(t, dtype=float))
    return s - stations[0], s_dot, s_ddot


def rail_of(ship) -> Rail:
    """The rail of a scenario's ``[ship.carriage]``, checked (:func:`~marinecdpr.motion.rail.check_rail`);
    a rail that cannot be built raises the ScenarioError naming the key. Built once per rail
    (its points, corner radius and stations; :class:`~marinecdpr.motion.rail.Rail` is immutable)."""
    return _rail(*_rail_key(ship.carriage))


def _rail_key(c) -> tuple:
    """A carriage's rail points, corner radius and stations as tuples (the rail's cache key)."""
    return (tuple(map(tuple, np.asarray(c.rail_m, dtype=float).tolist())), float(c.corner_radius_m),
            tuple(np.asarray(c.stations_m, dtype=float).ravel().tolist()))


@lru_cache(maxsize=16)
def _rail(points: tuple, corner_radius_m: float, stations: tuple) -> Rail:
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
    c = ship.carriage
    rail = rail_of(ship)
    s, s_dot, s_ddot, _ = carriage_profile(np.asarray(c.stations_m, dtype=float), c.dwell_s, c.speed_max_m_s,
                                           c.accel_max_m_s2, c.jerk_max_m_s3, t)
    points = rail.at(s, heading=False)
    return points, on_rail(points, frame_yaw(rail, s), s_dot, s_ddot, frame_axes(ship.frame_orientation_deg))
