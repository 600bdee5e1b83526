"""``[[obstacles]]``: what the cables must keep clear of besides each other and the platform.

Obstacles are fixed to the frame (they move with the ship) and given in C. A plane is a
hull's side or a deck, the robot on the side its normal points to; a box is a fitting,
a rail or a hatch coaming. They are checked only with ``robot.clearance_m``, the least
distance a cable may keep (``marinecdpr.geometry.interference``).
"""

from __future__ import annotations

from typing import Annotated, Literal, Union

import numpy as np
from pydantic import Field, StrictFloat, StrictStr, field_validator

from marinecdpr.scenario.fields import (
    POSITION_MAX_M, UNIT_TOLERANCE, Orientation, Position, _Model, _num, _ranged, normalised_unit,
)

__all__ = ["PlaneObstacle", "BoxObstacle", "Obstacle", "MAX_OBSTACLES"]

MAX_OBSTACLES = 1000
"""The most ``[[obstacles]]`` a scenario holds: each is measured against every cable at every
step (an array of steps x cables x obstacles), and a thousand fittings is more than one frame
meets; more are refused as "obstacles: at most 1000 entries, got N"."""


class PlaneObstacle(_Model):
    """``type = "plane"``: an unbounded plane; the cables must stay on its normal's side."""

    type: Literal["plane"]
    name: StrictStr = ""
    point_m: Position
    """A point of the plane in C, m."""
    normal: tuple[StrictFloat, StrictFloat, StrictFloat]
    """Its unit normal in C, pointing to the robot's side (within ``UNIT_TOLERANCE``, normalised)."""

    @field_validator("normal", mode="after")
    @classmethod
    def _unit(cls, n: tuple[float, float, float]) -> tuple[float, float, float]:
        n = normalised_unit(n)
        length = float(np.linalg.norm(np.asarray(n, dtype=float)))
        if not np.isfinite(length) or abs(length - 1.0) > UNIT_TOLERANCE:
            raise ValueError(f"must be a unit vector [x, y, z] in C (length 1 within {UNIT_TOLERANCE:g}), "
                             f"got length {_num(length)}")
        return n


class BoxObstacle(_Model):
    """``type = "box"``: a box, its centre and size in C, turned by ``orientation_deg``."""

    type: Literal["box"]
    name: StrictStr = ""
    center_m: Position
    size_m: tuple[_ranged(0.0, 2 * POSITION_MAX_M, "m", "a fitting, not more than a ship", above=True),
                  _ranged(0.0, 2 * POSITION_MAX_M, "m", "a fitting, not more than a ship", above=True),
                  _ranged(0.0, 2 * POSITION_MAX_M, "m", "a fitting, not more than a ship", above=True)]
    """Its edges' lengths along its own axes, m."""
    orientation_deg: Orientation = (0.0, 0.0, 0.0)
    """Its axes in C, SNAME angles (as the platform's), deg."""


Obstacle = Annotated[Union[PlaneObstacle, BoxObstacle], Field(discriminator="type")]
