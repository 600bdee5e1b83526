"""Scenario files: the robot, the ship, its motion, the trajectory, the plan's options.

This module: the shared field types (ranges with units) and constants.

A scenario is a TOML file (see ``docs/scenario.md`` for every key and its unit) or
a built-in name (``paper``). Keys carry their unit in their name (``mass_kg``,
``amplitude_deg``); angles in files are in degrees, everything is SI otherwise.

Structure and types are checked by pydantic; physical sense (a positive definite
inertia, T_min < T_max, enough cables, distinct anchors, a planar trajectory for a
planar robot) by validators on the models. Every failure surfaces as one
:class:`~marinecdpr.errors.ScenarioError` naming the source and the key.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated, Any

from pydantic import AfterValidator, BaseModel, BeforeValidator, ConfigDict, StrictFloat


SHIP_DOFS = ("surge", "sway", "heave", "roll", "pitch", "yaw")
"""Ship degrees of freedom, in the order of the 6-vector eta = (x, y, z, roll, pitch, yaw)."""

CONTROLLED_DOFS = {"planar": (0, 2, 4), "spatial": (0, 1, 2, 3, 4, 5)}
"""Indices into the twist (v_x, v_y, v_z, w_x, w_y, w_z) in C that the cables control."""

TENSION_METHODS = (
    "pseudo_inverse",
    "minimum_variance",
    "closed_form",
    "improved_closed_form",
    "minimum_norm",
)

PREDICTIONS = ("none", "kinematic", "ar")
"""How a controller brings the motion sensor's samples of the ship to the present
(``[simulation.mru] prediction``)."""

POSE_SOURCES = ("sensor", "encoders")
"""Where a controller's pose comes from (``[simulation.sensors] pose_from``)."""

Vec3 = tuple[StrictFloat, StrictFloat, StrictFloat]
ANCHOR_TOLERANCE_M = 1e-9

POSITION_MAX_M = 1e4
"""Largest coordinate of a position (anchors, the frame's origin on the ship, the trajectory),
m: any ship, with room for a robot drawn in millimetres to load and be flagged by
:func:`scale_warnings`."""
TIME_MAX_S = 1e6
"""Longest duration (of a plan, of a move, a trajectory's times), s: 11.6 days."""
MOVE_MIN_S = 0.01
"""Shortest move (a line, between waypoints) and circle period, s."""
CABLES_MAX = 1000
"""Most cables a robot may have."""
RADIUS_OF_GYRATION_RANGE_M = (1e-4, POSITION_MAX_M)
"""The platform's radii of gyration sqrt(I / m) about its principal axes, m."""
DEGENERATE_RELATIVE = 1e-4
"""Anchors within this fraction of the robot's size of one point (or, spatial, one line)
make a degenerate robot."""
FLAT_FRAME_SHARE = 0.05
"""An axis along which the frame anchors span at most this share of the frame's largest
extent is the frame's thin axis (a suspended robot's anchors, all near one height, or a
planar robot's y): the platform is not kept within the anchors' range along it."""
RANK_TOLERANCE = 1e-9
"""Singular values of J~ (moment columns over the robot's size) below this fraction of the
largest count as zero."""


UNIT_TOLERANCE = 1e-6
"""How far from 1 a unit vector's length may be in a scenario file (a direction written
to six digits); within it the vector is normalised, beyond it refused."""


def normalised_unit(values: Any) -> Any:
    """``values`` as a unit 3-vector when it is one within :data:`UNIT_TOLERANCE`, else unchanged.

    Three finite numbers whose length is within ``UNIT_TOLERANCE`` of 1 come back divided by
    their length (left as given when already unit to 1e-12, so exact inputs keep their bits);
    anything else comes back as it was, for the caller's validator to refuse by name.
    """
    if not (isinstance(values, (list, tuple)) and len(values) == 3 and all(
            isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) for v in values)):
        return values
    length = math.sqrt(sum(float(v) * float(v) for v in values))
    if abs(length - 1.0) > UNIT_TOLERANCE or abs(length - 1.0) <= 1e-12:
        return values
    return tuple(float(v) / length for v in values)


def _num(x: float) -> str:
    """A number as messages show it: 6 significant digits, exponents as 1e6 and 1e-5."""
    text = f"{x:g}"
    if "e" in text:
        mantissa, exponent = text.split("e")
        text = f"{mantissa}e{int(exponent)}"
    return text


def _range_text(lo: float, hi: float, unit: str, *, above: bool = False) -> str:
    u = f" {unit}" if unit else ""
    if above:
        return f"must be above {_num(lo)} and at most {_num(hi)}{u}"
    return f"must be between {_num(lo)} and {_num(hi)}{u}"


def _not_finite(value: Any) -> bool:
    return isinstance(value, float) and not math.isfinite(value)


def _ranged(lo: float, hi: float, unit: str, why: str, *, above: bool = False) -> Any:
    """A finite number in [lo, hi] ((lo, hi] with ``above``); refused with the range, unit and why."""
    text = _range_text(lo, hi, unit, above=above)

    def finite(value: Any) -> Any:
        if _not_finite(value):
            raise ValueError(f"{text.replace('must be', 'must be a finite number')} ({why}), got {value}")
        return value

    def check(value: float) -> float:
        if (value <= lo if above else value < lo) or value > hi:
            raise ValueError(f"{text} ({why}), got {_num(value)}")
        return value

    return Annotated[StrictFloat, BeforeValidator(finite), AfterValidator(check)]


def _ranged_vec3(bound: float, unit: str, why: str, names: tuple[str, ...] = ("x", "y", "z")) -> Any:
    """A 3-vector of finite numbers, each within +-bound."""
    text = _range_text(-bound, bound, unit)

    def finite(value: Any) -> Any:
        if isinstance(value, (list, tuple)) and len(value) == 3:
            for name, v in zip(names, value):
                if _not_finite(v):
                    raise ValueError(f"each entry {text.replace('must be', 'must be a finite number')} "
                                     f"({why}), got {name} = {v}")
        return value

    def check(value: tuple[float, float, float]) -> tuple[float, float, float]:
        for name, v in zip(names, value):
            if abs(v) > bound:
                raise ValueError(f"each entry {text} ({why}), got {name} = {_num(v)}")
        return value

    return Annotated[Vec3, BeforeValidator(finite), AfterValidator(check)]


Position = _ranged_vec3(POSITION_MAX_M, "m", "positions on a ship, in metres")
Orientation = _ranged_vec3(180.0, "deg", "SNAME angles: at most half a turn", ("rx", "ry", "rz"))
Phase = _ranged(-360.0, 360.0, "deg", "one turn either way")
Tension = _ranged(0.0, 1e7, "N", "a cable's tension, up to 10 MN")
TensionMax = _ranged(0.0, 1e7, "N", "a cable's tension, up to 10 MN", above=True)
BreakingLoad = _ranged(0.0, 1e9, "N", "a rope's breaking load, up to 1 GN", above=True)
TimeOfDay = _ranged(0.0, TIME_MAX_S, "s", "11.6 days")
Force = _ranged_vec3(1e8, "N", "beyond what ten cables of 10 MN can hold")
Moment = _ranged_vec3(1e9, "N m", "beyond what ten cables of 10 MN can hold")
HullLength = _ranged(1.0, 1000.0, "m", "a hull from a dinghy to the longest ship")
HullBeam = _ranged(0.5, 200.0, "m", "a hull from a dinghy to the widest platform")
HullDraught = _ranged(0.1, 50.0, "m", "a hull from a dinghy to the deepest tanker")
"""A hull's main dimensions (the RAOs' box or Wigley hull, a surface's Wigley side)."""


def _resolve_file(value: str, info: Any) -> str:
    """A path relative to the scenario file's folder (or the working folder), made absolute."""
    base = (info.context or {}).get("base_dir")
    path = Path(value).expanduser()
    if not path.is_absolute() and base is not None:
        path = Path(base) / path
    if path.is_dir():
        raise ValueError(f"a folder, not a file: {path}")
    if not path.is_file():
        raise ValueError(f"no such file: {path}")
    return str(path.resolve())


class _KeyedError(ValueError):
    """A validator's error that names a key below the model that raised it."""

    def __init__(self, key: str, message: str):
        self.key = key
        super().__init__(message)


class _Model(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)


