"""``[cleaning.surface.relocation]``: how the frame goes from one placement to the next, and
how many robots share the side.

``mode = "fixed"`` keeps one time per move (``clean --move-time``, a design study's
``move_time_s``), as without the section. ``mode = "crane"`` lifts the frame off and sets it
down again (``[cleaning.surface.relocation.crane]``: rigging, hoisting up and down, the travel
along the hull between the placements' centres, re-tensioning). ``mode = "rail"`` runs the frame
on a carriage along a rail at the height it stands (``[cleaning.surface.relocation.rail]``: a
jerk-limited move and a settle); a placement the rail cannot reach (another height row, or a
turn of the side sharper than the rail's least radius) is reached by the crane where one is
given, else refused. ``robots`` work the side at once, each on its own stretch
(:mod:`marinecdpr.studies.relocation`).

The frame's own mass is not in a scenario's robot (its ``mass_kg`` is the platform's):
``frame_mass_kg`` gives it where a crane lifts it (the crane lifts the frame and the platform).
"""

from __future__ import annotations

from typing import Literal

from pydantic import Field, StrictInt, model_validator

from marinecdpr.scenario.fields import _KeyedError, _Model, _num, _ranged

__all__ = ["Relocation", "Crane", "RailMoves", "MODES", "ROBOTS_MAX"]

MODES = ("fixed", "crane", "rail")
"""How the frame is moved between placements."""
ROBOTS_MAX = 100
"""The most robots on one side at once."""

_Time = _ranged(0.0, 86400.0, "s", "a part of one move, at most a day")
_Cost = _ranged(0.0, 1e12, "", "the user's cost unit")


class Crane(_Model):
    """``[cleaning.surface.relocation.crane]``: a move by crane takes
    ``rig_s + 2 lift_m / hoist_m_s + distance / travel_m_s + retension_s``."""

    rig_s: _Time
    """Attaching and detaching the slings, s (both, once per move)."""
    lift_m: _ranged(0.0, 100.0, "m", "the frame lifted clear of the hull and its fittings")
    """How high the frame is lifted off the hull (and lowered again), m."""
    hoist_m_s: _ranged(0.0, 10.0, "m/s", "a crane's hoist", above=True)
    travel_m_s: _ranged(0.0, 10.0, "m/s", "a crane's slew or travel along the hull", above=True)
    """The crane's speed carrying the frame along the hull (slew or travel), m/s."""
    retension_s: _Time
    """Setting the frame down and re-tensioning its cables, s."""
    capacity_kg: _ranged(0.0, 1e7, "kg", "a crane's safe working load", above=True)
    hire_per_h: _Cost = 0.0
    """The crane's hire (with its driver) per hour of the job, in the user's cost unit."""


class RailMoves(_Model):
    """``[cleaning.surface.relocation.rail]``: a carriage on a rail along the ship; a move
    along the rail is the double-S move of ``speed_m_s``, ``accel_m_s2`` and ``jerk_m_s3``
    (:func:`~marinecdpr.motion.rail.scurve_move`) and a settle."""

    speed_m_s: _ranged(0.0, 10.0, "m/s", "a carriage on a rail, not a vehicle", above=True)
    accel_m_s2: _ranged(0.0, 20.0, "m/s^2", "two g: beyond any carriage's drive", above=True)
    jerk_m_s3: _ranged(0.0, 1000.0, "m/s^3", "beyond any carriage's drive", above=True)
    settle_s: _Time = 0.0
    """The frame's swaying dying out after a move, s."""
    min_radius_m: _ranged(0.0, 1e5, "m", "the rail's tightest bend") = 0.0
    """The tightest turn of the side the rail can follow, m: between two placements of a row
    whose frames' headings turn by d(yaw) over their distance s, the side turns with radius
    s / |d(yaw)|; below this the crane moves the frame."""
    cost_per_m: _Cost = 0.0
    """The rail's cost per metre, in the user's cost unit."""
    carriage_cost: _Cost = 0.0
    """Each carriage's cost (one per robot), in the user's cost unit."""
    drive_cost_per_kW: _Cost = 0.0
    """Each carriage's drive, in the user's cost unit per kilowatt of its peak power: the
    force that accelerates the frame and the platform at ``accel_m_s2`` times ``speed_m_s``,
    (``frame_mass_kg`` + the platform's) x accel x speed
    (:func:`~marinecdpr.studies.relocation.carriage_drive_kW`); added to ``carriage_cost``.
    A faster or harder-accelerating carriage costs more (a design study's ``rail_speed_m_s``
    and ``rail_accel_m_s2`` then trade its hours against its cost). Needs ``frame_mass_kg``."""


class Relocation(_Model):
    """How the frame moves between placements, and how many robots share the side."""

    mode: Literal["fixed", "crane", "rail"] = "fixed"
    robots: StrictInt = Field(default=1, ge=1, le=ROBOTS_MAX)
    """Robots working the side at once, each on its own stretch of the placements."""
    frame_mass_kg: _ranged(0.0, 1e6, "kg", "a frame with its winches, as a crane lifts it") | None = None
    """The frame's own mass with its winches, kg (a crane lifts it with the platform); needed
    with a crane."""
    crane: Crane | None = None
    rail: RailMoves | None = None

    @model_validator(mode="after")
    def _check(self) -> "Relocation":
        if self.mode == "crane" and self.crane is None:
            raise _KeyedError("crane", "missing: mode = \"crane\" needs the crane's figures")
        if self.mode == "rail" and self.rail is None:
            raise _KeyedError("rail", "missing: mode = \"rail\" needs the carriage's figures")
        if self.rail is not None and self.rail.drive_cost_per_kW > 0.0 and self.frame_mass_kg is None:
            raise _KeyedError("frame_mass_kg", "missing: rail.drive_cost_per_kW prices the drive that accelerates "
                                               "the frame: give its mass (kg, with its winches)")
        if self.crane is not None and self.frame_mass_kg is None:
            raise _KeyedError("frame_mass_kg", "missing: a crane lifts the frame: give its mass (kg, with its "
                                               "winches; the platform's is the robot's mass_kg)")
        return self

    def lifted_kg(self, platform_kg: float) -> float:
        """What the crane lifts: the frame and the platform, kg."""
        return float((self.frame_mass_kg or 0.0) + platform_kg)

    def check_lift(self, platform_kg: float) -> None:
        """ValueError (one line) where a crane is given and the frame with the platform is
        heavier than its capacity."""
        if self.crane is not None and self.lifted_kg(platform_kg) > self.crane.capacity_kg:
            raise ValueError(f"the frame ({_num(self.frame_mass_kg)} kg) with the platform ({_num(platform_kg)} kg) "
                             f"is heavier than the crane's capacity_kg ({_num(self.crane.capacity_kg)} kg)")
