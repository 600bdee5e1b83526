"""The platform's planned motion in the robot frame C, and the disturbance on it.

A pose is ``(x, y, z, rx, ry, rz)``: the position of P's origin (the platform's
centre of mass) in C, m, and the SNAME Euler angles of R_PC = R_P^C =
Rz(rz) Ry(ry) Rx(rx), rad. A planar robot uses x, z and ry (= theta_y) only.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from marinecdpr.errors import ScenarioError
from marinecdpr.geometry import vec
from marinecdpr.geometry.rotations import euler_kinematics
from marinecdpr.scenario.cleaning import Cleaning, CoverageTrajectory
from marinecdpr.scenario.robot import frame_axes
from marinecdpr.scenario.schema import CircleTrajectory, Disturbance, LineTrajectory, WaypointsTrajectory

__all__ = [
    "PlatformMotion",
    "platform_motion",
    "evaluate_trajectory",
    "evaluate_disturbance",
    "check_in_frame",
    "cleaning_path",
]


@dataclass(frozen=True)
class PlatformMotion:
    """Planned platform motion relative to C (all arrays share ``n_steps``).

    Attributes
    ----------
    pose, pose_dot, pose_ddot : ndarray, shape (n_steps, 6)
        ``(x, y, z, rx, ry, rz)`` in C (m, rad) and its time derivatives.
    R_PC : ndarray, shape (n_steps, 3, 3)
        R_P^C: maps P-frame vectors to C.
    omega_PC_C, alpha_PC_C : ndarray, shape (n_steps, 3)
        Angular velocity and acceleration of P relative to C, in C.
    """

    pose: np.ndarray
    pose_dot: np.ndarray
    pose_ddot: np.ndarray
    R_PC: np.ndarray
    omega_PC_C: np.ndarray
    alpha_PC_C: np.ndarray

    @property
    def x_PC_C(self) -> np.ndarray:
        """Position of P in C, shape (n_steps, 3), m."""
        return self.pose[:, :3]

    @property
    def v_PC_C(self) -> np.ndarray:
        """Velocity of P relative to C, in C, shape (n_steps, 3), m/s."""
        return self.pose_dot[:, :3]

    @property
    def a_PC_C(self) -> np.ndarray:
        """Acceleration of P relative to C, in C, shape (n_steps, 3), m/s^2."""
        return self.pose_ddot[:, :3]

    @property
    def twist(self) -> np.ndarray:
        """``(v_PC, omega_PC)`` in C, shape (n_steps, 6)."""
        return np.concatenate([self.v_PC_C, self.omega_PC_C], axis=1)

    @property
    def twist_dot(self) -> np.ndarray:
        """``(a_PC, alpha_PC)`` in C, shape (n_steps, 6)."""
        return np.concatenate([self.a_PC_C, self.alpha_PC_C], axis=1)


def platform_motion(pose: np.ndarray, pose_dot: np.ndarray, pose_ddot: np.ndarray) -> PlatformMotion:
    """Rotation and angular rates of the platform from its pose and pose derivatives.

    Parameters
    ----------
    pose, pose_dot, pose_ddot : ndarray, shape (n_steps, 6)
        ``(x, y, z, rx, ry, rz)`` of P in C (m, rad) and derivatives.
    """
    pose = np.asarray(pose, dtype=float)
    pose_dot = np.asarray(pose_dot, dtype=float)
    pose_ddot = np.asarray(pose_ddot, dtype=float)
    R, omega_b, alpha_b = euler_kinematics(pose[:, 3:], pose_dot[:, 3:], pose_ddot[:, 3:])
    # d(R omega_b)/dt = R alpha_b, so both rates rotate into C with R.
    n = pose.shape[0]
    omega = vec.pack(vec.matvec(R, vec.comps(omega_b)), n)
    alpha = vec.pack(vec.matvec(R, vec.comps(alpha_b)), n)
    return PlatformMotion(pose=pose, pose_dot=pose_dot, pose_ddot=pose_ddot, R_PC=R, omega_PC_C=omega, alpha_PC_C=alpha)


def _quintic(tau: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Rest-to-rest time law s(tau) = 10 tau^3 - 15 tau^4 + 6 tau^5 and its derivatives."""
    t2 = tau * tau
    s = t2 * tau * (10.0 + tau * (-15.0 + 6.0 * tau))
    ds = 30.0 * t2 * (1.0 + tau * (-2.0 + tau))
    dds = 60.0 * tau * (1.0 + tau * (-3.0 + 2.0 * tau))
    return s, ds, dds


def cleaning_path(cleaning: Cleaning):
    """The coverage path (:class:`~marinecdpr.motion.coverage.CoveragePath`) of a
    ``[cleaning]`` section: the brush's centre over the panel (cached per section)."""
    return _cleaning_path(cleaning.model_dump_json())


@lru_cache(maxsize=8)
def _cleaning_path(key: str):
    from marinecdpr.motion.coverage import coverage_path

    c = Cleaning.model_validate_json(key)

    def path(boundary_pass: bool):
        return coverage_path(np.asarray(c.panel_m), [np.asarray(h) for h in c.holes_m], width_m=c.brush_diameter_m,
                             overlap_m=c.overlap_m, speed_m_s=c.speed_m_s, accel_m_s2=c.acceleration_m_s2,
                             jerk_m_s3=c.jerk_m_s3, direction_deg=c.direction_deg, boundary_pass=boundary_pass)

    try:
        return path(c.boundary_pass is not False)
    except ScenarioError as exc:
        if exc.key == "boundary_pass" and c.boundary_pass is None:
            return path(False)  # by default only where it can be done
        raise ScenarioError(exc.detail, key=f"cleaning.{exc.key}" if exc.key else "cleaning") from None


def evaluate_trajectory(
    config: CircleTrajectory | WaypointsTrajectory | LineTrajectory | CoverageTrajectory, t: np.ndarray,
    cleaning: Cleaning | None = None, ship=None,
) -> PlatformMotion:
    """The planned platform motion a scenario's ``[trajectory]`` describes.

    Parameters
    ----------
    config : CircleTrajectory, WaypointsTrajectory, LineTrajectory or CoverageTrajectory
    t : ndarray, shape (n_steps,)
        Times, s.
    cleaning : Cleaning, optional
        The scenario's ``[cleaning]`` section, which a coverage trajectory follows: the
        brush's centre (``cleaning.brush_offset_m`` in P) runs along the coverage path in
        the plane y = ``plane_y_m``, the platform's orientation fixed.
    ship : marinecdpr.scenario.schema.Ship, optional
        The scenario's ``[ship]``: a coverage trajectory ``on_hull`` takes its carriage's
        motion (the carriage's travel along the rail taken off the path's x); refused without it.
    """
    t = np.asarray(t, dtype=float)
    n = t.size
    if isinstance(config, CoverageTrajectory):
        return _coverage_motion(config, cleaning, t, ship)
    # time-last buffers (see geometry.vec); the (n_steps, 6) views are taken at the end
    pose = np.zeros((6, n))
    pose_dot = np.zeros((6, n))
    pose_ddot = np.zeros((6, n))
    if isinstance(config, LineTrajectory):
        config = config.as_waypoints()
    if isinstance(config, CircleTrajectory):
        # eq. (21): x = r cos(w t) + x0, z = r sin(w t) + z0 for plane "xz"
        e1, e2 = {"xz": (0, 2), "xy": (0, 1), "yz": (1, 2)}[config.plane]
        w = 2.0 * np.pi / config.period_s
        phase = w * t + np.radians(config.phase_deg)
        c, s = np.cos(phase), np.sin(phase)
        r = config.radius_m
        pose[:3] = np.asarray(config.center_m)[:, None]
        pose[e1] += r * c
        pose[e2] += r * s
        pose_dot[e1] = -r * w * s
        pose_dot[e2] = r * w * c
        pose_ddot[e1] = -r * w * w * c
        pose_ddot[e2] = -r * w * w * s
        pose[3:] = np.radians(config.orientation_deg)[:, None]
    else:
        times = np.array([wp.time_s for wp in config.waypoints])
        knots = np.array(
            [list(wp.position_m) + list(np.radians(wp.orientation_deg)) for wp in config.waypoints]
        )
        seg = np.clip(np.searchsorted(times, t, side="right") - 1, 0, len(times) - 2)
        dur = times[seg + 1] - times[seg]
        tau = np.clip((t - times[seg]) / dur, 0.0, 1.0)
        s, ds, dds = _quintic(tau)
        delta = (knots[seg + 1] - knots[seg]).T
        pose[:] = knots[seg].T + delta * s
        pose_dot[:] = delta * (ds / dur)
        pose_ddot[:] = delta * (dds / dur**2)
    return platform_motion(pose.T, pose_dot.T, pose_ddot.T)


def _coverage_motion(config: CoverageTrajectory, cleaning: Cleaning | None, t: np.ndarray, ship=None
                     ) -> PlatformMotion:
    if cleaning is None:
        raise ScenarioError("missing: a coverage trajectory cleans the [cleaning] section's panel", key="cleaning")
    p, v, a = cleaning_path(cleaning).evaluate(t - config.start_time_s)
    if config.on_hull:
        p, v, a = _held_on_ship(ship, t, p, v, a)
    angles = np.radians(config.orientation_deg)
    R = euler_kinematics(angles[None], np.zeros((1, 3)), np.zeros((1, 3))).R[0]
    r_C = R @ np.asarray(cleaning.brush_offset_m, dtype=float)  # brush centre from P's origin, in C
    n = t.size
    pose, pose_dot, pose_ddot = np.zeros((n, 6)), np.zeros((n, 6)), np.zeros((n, 6))
    pose[:, 0], pose[:, 1], pose[:, 2] = p[:, 0] - r_C[0], config.plane_y_m - r_C[1], p[:, 1] - r_C[2]
    pose[:, 3:] = angles
    pose_dot[:, [0, 2]] = v
    pose_ddot[:, [0, 2]] = a
    return platform_motion(pose, pose_dot, pose_ddot)


def _held_on_ship(ship, t: np.ndarray, p: np.ndarray, v: np.ndarray, a: np.ndarray):
    """A coverage path laid on the ship (``on_hull``): the brush's (x, z) in C, their velocity
    and acceleration, as the carriage carries the frame: its travel along the rail from its
    first station taken off along C's x (:func:`~marinecdpr.motion.carriage.carriage_travel`)."""
    from marinecdpr.motion.carriage import carriage_travel

    if ship is None:  # a caller that did not give the ship (the planner, the controller, the plants give it)
        raise ScenarioError("is held on the ship while the carriage moves: evaluate the path with the scenario's "
                            "[ship] (its carriage's motion)", key="trajectory.on_hull")
    if ship.carriage is None:
        raise ScenarioError("needs [ship.carriage]: the path is held on the ship while the carriage carries the frame",
                            key="trajectory.on_hull")
    d, d_dot, d_ddot = carriage_travel(ship, t)
    p, v, a = p.copy(), v.copy(), a.copy()
    p[:, 0] -= d
    v[:, 0] -= d_dot
    a[:, 0] -= d_ddot
    return p, v, a


def evaluate_disturbance(config: Disturbance, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """External force f_r and moment m_r on the platform, in ``config.frame``.

    Parameters
    ----------
    config : Disturbance
    t : ndarray, shape (n_steps,)
        Times, s.

    Returns
    -------
    f_r : ndarray, shape (n_steps, 3)
        Force at the centre of mass, N.
    m_r : ndarray, shape (n_steps, 3)
        Moment, N m.
    """
    t = np.asarray(t, dtype=float)
    f = np.broadcast_to(np.asarray(config.force_N, dtype=float), (t.size, 3)).copy()
    m = np.broadcast_to(np.asarray(config.moment_N_m, dtype=float), (t.size, 3)).copy()
    if config.period_s is not None:
        s = np.sin(2.0 * np.pi * t / config.period_s + np.radians(config.phase_deg))[:, None]
        f += s * np.asarray(config.force_amplitude_N)
        m += s * np.asarray(config.moment_amplitude_N_m)
    return f, m


def check_in_frame(x_PC: np.ndarray, anchors_C: np.ndarray, c_C: np.ndarray, t: np.ndarray) -> None:
    """Raise if the platform's centre or an anchor leaves the frame.

    The frame is the axis-aligned box of the frame anchors in C; an axis along
    which the anchors span at most :data:`~marinecdpr.scenario.fields.FLAT_FRAME_SHARE`
    of the frame's largest extent (a suspended robot's anchors, all near one height,
    as CoGiRo's; a planar robot's y) is not checked
    (:func:`~marinecdpr.scenario.robot.frame_axes`).

    Parameters
    ----------
    x_PC : ndarray, shape (n_steps, 3)
        Platform centre in C, m.
    anchors_C : ndarray, shape (n_steps, n_cables, 3)
        Platform anchors relative to the centre, in C (R_PC p_i), m.
    c_C : ndarray, shape (n_cables, 3)
        Frame anchors in C, m.
    t : ndarray, shape (n_steps,)
        Times, s, to name where the platform leaves.

    Raises
    ------
    ScenarioError
        With key ``trajectory``, the first time and the point outside.
    """
    lo, hi = c_C.min(axis=0), c_C.max(axis=0)
    tol = 1e-9 * max(1.0, float(np.abs(c_C).max()))
    spanned = frame_axes(c_C)
    for axis in range(3):
        if not spanned[axis]:
            continue
        x = x_PC[:, axis]
        ext = anchors_C[:, :, axis]
        # quick test on the extremes, then locate the first offender
        if (x + ext.min(axis=1)).min() >= lo[axis] - tol and (x + ext.max(axis=1)).max() <= hi[axis] + tol \
                and x.min() >= lo[axis] - tol and x.max() <= hi[axis] + tol:
            continue
        pts = np.concatenate([x[:, None], x[:, None] + ext], axis=1)
        bad = (pts < lo[axis] - tol) | (pts > hi[axis] + tol)
        step, point = np.argwhere(bad)[0]
        what = "the platform's centre" if point == 0 else f"platform anchor {point}"
        value = float(pts[step, point])
        edge = float(lo[axis] if value < lo[axis] else hi[axis])
        raise ScenarioError(
            f"the platform leaves the frame at t = {t[step]:.3f} s: {what} is at "
            f"{'xyz'[axis]} = {format_apart(value, edge)} m, outside the frame anchors' "
            f"range [{float(lo[axis])!r}, {float(hi[axis])!r}] m",
            key="trajectory",
        )


def format_apart(value: float, other: float, digits: int = 4) -> str:
    """``value`` with at least ``digits`` significant digits and as many more as it takes
    to read differently from ``other`` (so 4.0000012 outside [0, 4] does not print as 4)."""
    for d in range(digits, 18):
        text = f"{value:.{d}g}"
        if text != f"{other:.{d}g}":
            return text
    return repr(value)
