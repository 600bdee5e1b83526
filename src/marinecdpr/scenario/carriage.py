"""``[ship.carriage]``: a rail on the ship that carries the frame from place to place.

The frame C hangs from a carriage that runs along a rail fixed to the ship (a deck edge, a
sheer line): C's origin travels on the rail (``rail_m``, its points in S; each inner corner
rounded by a circular arc of ``corner_radius_m``), its axes turn about S's z as the rail turns
(through each bend smoothly: :func:`marinecdpr.motion.carriage.frame_yaw`), keeping the lean
``ship.frame_orientation_deg`` gives them at the rail's start. The
carriage rests at each of ``stations_m`` (arc lengths along the rail) for ``dwell_s`` and
moves between them jerk-limited (``speed_max_m_s``, ``accel_max_m_s2``, ``jerk_max_m_s3``).
The rail's geometry (do its corners' arcs fit?) and the stations' places on it are checked
where the carriage's motion is first made (:mod:`marinecdpr.motion.carriage`), with the key.
"""

from __future__ import annotations

from pydantic import Field, model_validator

from marinecdpr.scenario.fields import POSITION_MAX_M, TIME_MAX_S, Position, _KeyedError, _Model, _ranged

__all__ = ["Carriage", "MAX_RAIL_POINTS", "MAX_STATIONS"]

MAX_RAIL_POINTS = 1000
"""The most points a rail's polyline holds (a deck edge's sheer line, sampled)."""
MAX_STATIONS = 10_000
"""The most stations a carriage stops at (a 200 m side in 2 cm steps)."""

Dwell = _ranged(0.0, TIME_MAX_S, "s", "the time at one station, at most the longest run")


class Carriage(_Model):
    """A carriage on a rail that carries the frame along the ship."""

    rail_m: list[Position] = Field(min_length=2, max_length=MAX_RAIL_POINTS)
    """The rail's polyline: the path of C's origin, points in S, m."""
    corner_radius_m: _ranged(0.0, POSITION_MAX_M, "m", "a rail's bend, from none to a ship's length") = 0.0
    """Each inner corner of the polyline rounded by a circular arc of this radius, m (0: a
    straight rail, whose points all lie on one line)."""
    speed_max_m_s: _ranged(0.0, 10.0, "m/s", "a carriage on a rail, not a vehicle", above=True)
    accel_max_m_s2: _ranged(0.0, 20.0, "m/s^2", "two g: beyond any carriage's drive", above=True)
    jerk_max_m_s3: _ranged(0.0, 1000.0, "m/s^3", "beyond any carriage's drive", above=True)
    stations_m: list[_ranged(0.0, 1e5, "m", "an arc length along the rail")] = Field(min_length=1,
                                                                                       max_length=MAX_STATIONS)
    """Where the carriage stops, as arc lengths along the rail from its first point, m, in the
    order it visits them (it starts at the first)."""
    dwell_s: Dwell | list[Dwell] = 0.0
    """The time at each station, s: one for every station, or a list (one each)."""
    mass_kg: _ranged(0.0, 1e6, "kg", "a carriage with its frame and winches, not a ship") | None = None
    """The carriage with the frame and its winches, kg: what its drive accelerates besides
    the cables' pull (:func:`marinecdpr.planning.carriage.drive_force`)."""
    drive_force_max_N: _ranged(0.0, 1e8, "N", "a carriage's drive, not a ship's", above=True) | None = None
    """The most force the carriage's drive gives along the rail, N."""

    @model_validator(mode="after")
    def _check_dwell(self) -> "Carriage":
        if isinstance(self.dwell_s, list) and len(self.dwell_s) != len(self.stations_m):
            raise _KeyedError("dwell_s", f"one time for every station: {len(self.stations_m)} stations, "
                                         f"got {len(self.dwell_s)} times (or give one number for all)")
        if self.drive_force_max_N is not None and self.mass_kg is None:
            raise _KeyedError("mass_kg", "missing: the drive's force is checked against what it accelerates: give "
                                         "the carriage's mass with the frame and its winches, kg")
        return self
