"""The cleaning job: the hull panel to clean, the brush, and its contact with the hull.

The panel lies in the frame's x-z plane (the hull side the frame stands on); its outline
and any openings to keep clear are polygons of ``[x, z]`` points in C, m. The brush's
centre moves along a boustrophedon coverage path over the panel (``[trajectory]
type = "coverage"``), pressed on the hull with a normal force that must stay within a
band for the brush to clean.
"""

from __future__ import annotations

from typing import Annotated, Literal

import numpy as np
from pydantic import (
    AfterValidator, Field, StrictBool, StrictFloat, StrictStr, ValidationInfo, field_validator, model_validator,
)

from marinecdpr.geometry.polygons import inside_or_on, polygon_area
from marinecdpr.scenario.fields import (
    POSITION_MAX_M, UNIT_TOLERANCE, HullBeam, HullDraught, HullLength, Orientation, Position, TimeOfDay, _KeyedError,
    _Model, _num, _ranged, _resolve_file, normalised_unit,
)
from marinecdpr.scenario.relocation import Relocation

__all__ = ["Cleaning", "CoverageTrajectory", "Surface", "StandOffTolerance", "STAND_OFF_MIN_M"]

STAND_OFF_MIN_M = 1e-3
"""The least stand-off tolerance of a tool, m: a pusher's stroke of a millimetre. Below it no
patch of a hull is flat enough to place a frame on (a tolerance of 1e-9 m left every patch
uncleanable)."""
StandOffTolerance = _ranged(STAND_OFF_MIN_M, 1.0, "m", "a tool's stand-off range, from a pusher's millimetre")
"""The most the surface may depart from the frame's plane over one placement, m."""

Coordinate = _ranged(-POSITION_MAX_M, POSITION_MAX_M, "m", "positions on a ship, in metres")


def _point(value: list) -> tuple[float, float]:
    return tuple(value)


Point = Annotated[tuple[Coordinate, Coordinate], AfterValidator(_point)]
Polygon = Annotated[list[Point], Field(min_length=3, max_length=10_000)]


class Surface(_Model):
    """``[cleaning.surface]``: the hull surface the job cleans, placement after placement
    (``marinecdpr clean --surface``): a band of one side of the hull, between two stations
    and two heights, in S (x forward from amidships, z up from the waterline).

    The side is a Wigley hull's (``form = "wigley"``: half-breadth (B/2)(1 - (2x/L)^2)
    (1 - (z/T)^2) below the waterline and (B/2)(1 - (2x/L)^2)(1 + flare (z/T)^2) above it) or a
    mesh's (``form = "mesh"``: any format ``rao --mesh`` reads, its topsides included).
    """

    form: Literal["wigley", "mesh"]
    mesh: StrictStr | None = None
    """form = "mesh": the mesh file (relative paths from the scenario's folder)."""
    mesh_units: Literal["m", "cm", "mm", "ft"] = "m"
    waterline_m: _ranged(-POSITION_MAX_M, POSITION_MAX_M, "m", "a height on a ship") = 0.0
    """form = "mesh": the waterline's z in the mesh, in its units."""
    length_m: HullLength | None = None
    beam_m: HullBeam | None = None
    draught_m: HullDraught | None = None
    flare: _ranged(-1.0, 1.0, "", "the half-breadth's growth per draught of height, a share") = 0.0
    """form = "wigley": how the topside flares out (> 0) or tumbles home (< 0) above the waterline
    (the half-breadth's share gained at a draught's height)."""
    side: Literal["port", "starboard"] = "port"
    stations_m: tuple[Coordinate, Coordinate]
    """The band's ends along the ship, [aft, forward], m from amidships."""
    heights_m: tuple[Coordinate, Coordinate]
    """The band's [lower, upper] heights above the waterline, m."""
    stand_off_tolerance_m: StandOffTolerance
    """The most the surface may depart from the frame's plane over one placement, m."""
    relocation: Relocation | None = None
    """How the frame moves between placements (crane, rail) and how many robots share the
    band (:class:`~marinecdpr.scenario.relocation.Relocation`); none: every move takes the
    command's ``--move-time``, one robot."""

    @field_validator("mesh")
    @classmethod
    def _check_mesh(cls, value: str | None, info: ValidationInfo) -> str | None:
        return None if value is None else _resolve_file(value, info)

    @model_validator(mode="after")
    def _check(self) -> "Surface":
        for key in ("stations_m", "heights_m"):
            lo, hi = getattr(self, key)
            if not lo < hi:
                raise _KeyedError(key, f"must be [low, high] with low < high, got [{_num(lo)}, {_num(hi)}]")
        if self.form == "mesh":
            if self.mesh is None:
                raise _KeyedError("mesh", "missing: form = \"mesh\" cleans a mesh's side")
            for key in ("length_m", "beam_m", "draught_m"):
                if getattr(self, key) is not None:
                    raise _KeyedError(key, "is for form = \"wigley\": a mesh gives its own dimensions")
            return self
        for key in ("length_m", "beam_m", "draught_m"):
            if getattr(self, key) is None:
                raise _KeyedError(key, "missing: the Wigley hull needs its length, beam and draught")
        if self.mesh is not None:
            raise _KeyedError("mesh", "is for form = \"mesh\"")
        half = 0.5 * self.length_m
        lo, hi = self.stations_m
        if lo <= -half or hi >= half:
            raise _KeyedError("stations_m", f"must lie within the hull's length, between {_num(-half)} and "
                                            f"{_num(half)} m (its ends have no breadth), got [{_num(lo)}, {_num(hi)}]")
        if self.heights_m[0] < -self.draught_m:
            raise _KeyedError("heights_m", f"must be above the keel ({_num(-self.draught_m)} m), got "
                                           f"{_num(self.heights_m[0])}")
        top = self.heights_m[1]
        if self.flare < 0 and top > 0 and 1.0 + self.flare * (top / self.draught_m) ** 2 <= 0:
            meets = self.draught_m / np.sqrt(-self.flare)
            raise _KeyedError("heights_m", f"must stay below {_num(float(meets))} m, where the side tumbling home "
                                           f"(flare {_num(self.flare)}) meets the centreline, got {_num(top)}")
        return self


class Cleaning(_Model):
    """``[cleaning]``: the panel, the tool and the contact."""

    panel_m: Polygon
    """The panel's outline, [x, z] points in C (m), in order."""
    holes_m: list[Polygon] = []
    """Openings to keep clear (sea chests, anodes), each an outline inside the panel."""
    brush: Literal["disc", "pair"] = "disc"
    """A single disc brush (its drag turns the platform about the hull normal) or a
    counter-rotating pair (whose moments cancel)."""
    brush_diameter_m: _ranged(0.01, 5.0, "m", "from a 1 cm pad to a 5 m roller", above=True)
    overlap_m: _ranged(0.0, 5.0, "m", "between neighbouring lanes") = 0.0
    speed_m_s: _ranged(0.0, 5.0, "m/s", "a brush's travel speed", above=True)
    acceleration_m_s2: _ranged(0.0, 50.0, "m/s^2", "of the travel at turns", above=True)
    jerk_m_s3: _ranged(0.0, 5000.0, "m/s^3", "of the travel at turns", above=True)
    direction_deg: _ranged(-180.0, 180.0, "deg", "the lanes' angle from x towards z") | None = None
    """The lanes' direction; by default the one with the fewest lanes."""
    boundary_pass: StrictBool | None = None
    """After the lanes, once round the panel's outline inset by the brush's radius (cleans
    the slivers along the edges); by default on for a convex panel without holes."""
    normal_force_N: tuple[_ranged(0.0, 1e6, "N", "a brush's contact force"),
                          _ranged(0.0, 1e6, "N", "a brush's contact force")]
    """The band [F_min, F_max] within which the brush cleans, N."""
    preload_N: _ranged(0.0, 1e6, "N", "a brush's contact force") | None = None
    """The force the pusher presses the brush on with, N; by default mid-band."""
    friction: _ranged(0.0, 2.0, "", "brush on paint, about 0.3-0.6")
    jet_N: _ranged(-1e5, 1e5, "N", "a water jet's reaction") = 0.0
    """A water jet's reaction on the tool, N, positive away from the hull."""
    brush_offset_m: Position = (0.0, 0.0, 0.0)
    """The brush's centre in the platform frame P, m."""
    surface: Surface | None = None
    """The hull surface the whole job cleans, placement after placement of this panel's frame
    (``clean --surface``); none by default."""
    hull_normal: tuple[StrictFloat, StrictFloat, StrictFloat] = (0.0, 1.0, 0.0)
    """The hull's normal in C, pointing from the hull towards the robot (the frame's y); a unit
    vector within ``UNIT_TOLERANCE`` (1e-6), normalised."""

    @field_validator("hull_normal", mode="after")
    @classmethod
    def _unit_normal(cls, n: tuple[float, float, float]) -> tuple[float, float, float]:
        return normalised_unit(n)

    @model_validator(mode="after")
    def _check(self) -> "Cleaning":
        if self.overlap_m >= self.brush_diameter_m:
            raise _KeyedError("overlap_m", f"must be less than brush_diameter_m ({_num(self.brush_diameter_m)} m), "
                                           f"got {_num(self.overlap_m)}")
        lo, hi = self.normal_force_N
        if lo > hi:
            raise _KeyedError("normal_force_N", f"the band [F_min, F_max] must have F_min <= F_max, "
                                                f"got [{_num(lo)}, {_num(hi)}]")
        if self.preload_N is not None and not lo <= self.preload_N <= hi:
            raise _KeyedError("preload_N", f"must be within normal_force_N [{_num(lo)}, {_num(hi)}] N, "
                                           f"got {_num(self.preload_N)}")
        n = np.asarray(self.hull_normal, dtype=float)
        if not np.isfinite(n).all() or abs(float(np.linalg.norm(n)) - 1.0) > UNIT_TOLERANCE:
            raise _KeyedError("hull_normal", f"must be a unit vector [x, y, z] in C (length 1 within "
                                             f"{UNIT_TOLERANCE:g}), got length {_num(float(np.linalg.norm(n)))}")
        panel = np.asarray(self.panel_m, dtype=float)
        size = float(np.ptp(panel, axis=0).max())
        if abs(polygon_area(panel)) <= 1e-9 * max(size, 1e-9) ** 2:
            raise _KeyedError("panel_m", "the outline encloses no area")
        for i, hole in enumerate(self.holes_m, start=1):
            if not inside_or_on(np.asarray(hole, dtype=float), panel).all():
                raise _KeyedError(f"holes_m[{i}]", "must lie inside panel_m")
        return self

    @property
    def band_N(self) -> tuple[float, float]:
        return tuple(float(v) for v in self.normal_force_N)

    @property
    def preload(self) -> float:
        """The pusher's force, N (mid-band unless given)."""
        lo, hi = self.normal_force_N
        return float(self.preload_N if self.preload_N is not None else 0.5 * (lo + hi))


class CoverageTrajectory(_Model):
    """``type = "coverage"``: the brush's centre along a boustrophedon path over the
    ``[cleaning]`` panel (lanes, then rest-to-rest jerk-limited moves at the turns)."""

    type: Literal["coverage"]
    start_time_s: TimeOfDay = 0.0
    """When the path starts; the platform waits at its start before."""
    orientation_deg: Orientation = (0.0, 0.0, 0.0)
    """The platform's (fixed) orientation while cleaning."""
    plane_y_m: _ranged(-POSITION_MAX_M, POSITION_MAX_M, "m", "positions on a ship, in metres") = 0.0
    """y of the brush's centre in C (the panel's plane)."""
    on_hull: StrictBool = False
    """The path is laid on the ship, not in C: its (x, z) are in the frame's C at the carriage's
    first station (``[ship.carriage] stations_m[0]``, where it stands at t = 0), x along the
    rail, and as the carriage carries the frame the platform's path in C compensates: the
    carriage's travel along the rail is taken off the path's x, holding the brush at its
    place along the rail (exact on a straight level rail along C's x; on a bend, the frame
    turning with the rail, the brush keeps its arc length along it). Needs
    ``[ship.carriage]``; ``clean --surface --rail``'s continuous mode cleans so."""
