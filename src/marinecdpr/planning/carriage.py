"""The force a carriage's drive gives along its rail while it carries the frame (``[ship.carriage]``).

The carriage, with the frame and its winches (mass m_c, ``ship.carriage.mass_kg``), is held
across the rail by the rail and driven along it. Along the rail's tangent t (in C), the drive
gives what accelerates the carriage and holds it against gravity, plus what the cables pull
it by: each cable pulls the frame towards the platform with its tension, the opposite of the
force f_p = sum_i T_i u_i = (J~^T T)_force it gives the platform (eq. 6's u_i from the platform
anchor to where the cable leaves the frame). So

    F_drive = m_c (a_OC - g) . t + f_p . t

with a_OC C's acceleration in O and g = (0, 0, -g) in O, both in C. On a still ship with a
level rail along x and the platform held, this is (m_c + m_p) a: the drive accelerates the
carriage and the platform the cables hold.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from marinecdpr.errors import ScenarioError
from marinecdpr.geometry.kinematics import cable_kinematics
from marinecdpr.geometry.rotations import matrix_from_euler
from marinecdpr.motion.basemotion import fixed_ship_motion, frame_ship_motion
from marinecdpr.motion.carriage import rail_tangent_C

__all__ = ["DriveForce", "DrivePeak", "drive_force", "carriage_load"]


@dataclass(frozen=True)
class DriveForce:
    """The carriage's drive force along its rail over a plan.

    Attributes
    ----------
    t : ndarray, shape (n_steps,)
        s.
    force_N : ndarray, shape (n_steps,)
        Along the rail's tangent (towards increasing arc length), N.
    limit_N : float or None
        ``ship.carriage.drive_force_max_N``.
    """

    t: np.ndarray
    force_N: np.ndarray
    limit_N: float | None

    @property
    def peak_N(self) -> float:
        """The largest force either way, N."""
        return float(np.max(np.abs(self.force_N)))

    @property
    def peak_at_s(self) -> float:
        """When it is reached, s."""
        return float(self.t[int(np.argmax(np.abs(self.force_N)))])

    @property
    def within(self) -> bool:
        """The drive gives it at every step (True without a limit)."""
        return self.limit_N is None or self.peak_N <= self.limit_N


@dataclass(frozen=True)
class DrivePeak:
    """The drive's largest force over a plan made in chunks (:meth:`DriveForce.peak_N` of each).

    Attributes
    ----------
    peak_N : float
        The largest force either way, N. at_s : float, when, s. limit_N : float or None.
    """

    peak_N: float
    at_s: float
    limit_N: float | None

    @property
    def within(self) -> bool:
        return self.limit_N is None or self.peak_N <= self.limit_N

    def verdict(self) -> str | None:
        """One line where the drive cannot give the force, or None."""
        if self.within:
            return None
        return (f"the carriage's drive must give {self.peak_N:.4g} N along the rail at t = {self.at_s:.6g} s, more than "
                f"its {self.limit_N:.4g} N (ship.carriage.drive_force_max_N): a stronger drive, gentler moves "
                f"(accel_max_m_s2) or a lighter carriage")

    @staticmethod
    def of(forces) -> "DrivePeak":
        """The peak over :class:`DriveForce` pieces (at least one)."""
        best = max(forces, key=lambda d: d.peak_N)
        return DrivePeak(peak_N=best.peak_N, at_s=best.peak_at_s, limit_N=best.limit_N)


def drive_force(plan, scenario) -> DriveForce:
    """The drive's force along the rail at each step of a plan (the module's equation).

    Parameters
    ----------
    plan : Plan
        Of ``scenario`` (its poses and tensions; a fixed-base plan's ship is still, the
        carriage moving).
    scenario : Scenario
        With ``[ship.carriage]`` and its ``mass_kg``.

    Raises
    ------
    ScenarioError
        Without a carriage or its mass; a robot over pulleys (not yet).
    """
    c = scenario.ship.carriage
    if c is None or c.mass_kg is None:
        raise ScenarioError("the drive's force needs a carriage and its mass", key="ship.carriage.mass_kg")
    robot = scenario.robot
    if robot.has_pulleys:
        raise ScenarioError("the drive's force over pulleys is not built yet", key="ship.carriage")
    t = np.asarray(plan.t, dtype=float)
    ship = fixed_ship_motion(scenario, t) if plan.base_model == "fixed" else frame_ship_motion(scenario, t)
    own, along = carriage_load(scenario, ship, t)
    pose = np.asarray(plan.pose, dtype=float)
    kin = cable_kinematics(pose[:, :3], matrix_from_euler(pose[:, 3:]), robot.frame_anchors, robot.platform_anchors)
    f_p = np.einsum("nij,ni->nj", kin.units, np.asarray(plan.tensions, dtype=float))  # sum_i T_i u_i
    force = own + np.einsum("ni,ni->n", f_p, along)
    return DriveForce(t=t, force_N=force, limit_N=c.drive_force_max_N)


def carriage_load(scenario, ship, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The drive's force for the carriage's own mass, m_c (a_OC - g) . t, and the rail's tangent
    t in C (the cables' pull f_p . t is the rest of the module's equation).

    Parameters
    ----------
    scenario : Scenario
        With ``[ship.carriage]`` and its ``mass_kg``.
    ship : ShipMotion
        C's motion in O at the times ``t`` (:func:`~marinecdpr.motion.basemotion.frame_ship_motion`,
        or a fixed-base plan's :func:`~marinecdpr.motion.basemotion.fixed_ship_motion`).
    t : ndarray, shape (n_steps,)
        s.

    Returns
    -------
    own : ndarray, shape (n_steps,)
        N, along the rail.
    along : ndarray, shape (n_steps, 3)
        The rail's unit tangent in C (:func:`~marinecdpr.motion.carriage.rail_tangent_C`).
    """
    R_OC = ship.R_SO
    a_C = np.einsum("nji,nj->ni", R_OC, ship.a_SO_O)  # R_OC^T a_OC
    g_C = np.einsum("nji,j->ni", R_OC, [0.0, 0.0, -scenario.environment.gravity_m_s2])
    along = rail_tangent_C(scenario.ship, t)
    return np.einsum("ni,ni->n", scenario.ship.carriage.mass_kg * (a_C - g_C), along), along
