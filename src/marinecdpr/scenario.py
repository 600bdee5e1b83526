"""Scenario files: the robot, the ship, its motion, the trajectory, the plan's options.

A scenario is a TOML file (see ``docs/scenario.md`` for every key and its unit) or
a built-in name (``paper``). Keys carry their unit in their name (``mass_kg``,
``amplitude_deg``); angles in files are in degrees, everything is SI otherwise.

Structure and types are checked by pydantic; physical sense (a positive definite
inertia, T_min < T_max, enough cables, distinct anchors, a planar trajectory for a
planar robot) by validators on the models. Every failure surfaces as one
:class:`~marinecdpr.errors.ScenarioError` naming the source and the key.
"""

from __future__ import annotations

import difflib
import math
import tomllib
from importlib import resources
from pathlib import Path
from typing import Annotated, Any, Literal, Union

import numpy as np
from pydantic import (
    AfterValidator,
    BaseModel,
    BeforeValidator,
    ConfigDict,
    Field,
    StrictFloat,
    StrictStr,
    ValidationError,
    ValidationInfo,
    field_validator,
    model_validator,
)

from .errors import ScenarioError

__all__ = [
    "Scenario",
    "Robot",
    "Cable",
    "load_scenario",
    "builtin_scenarios",
    "SHIP_DOFS",
    "CONTROLLED_DOFS",
    "TENSION_METHODS",
    "scale_warnings",
]

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
RANK_TOLERANCE = 1e-9
"""Singular values of J~ (moment columns over the robot's size) below this fraction of the
largest count as zero."""


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
TimeOfDay = _ranged(0.0, TIME_MAX_S, "s", "11.6 days")
Force = _ranged_vec3(1e8, "N", "beyond what ten cables of 10 MN can hold")
Moment = _ranged_vec3(1e9, "N m", "beyond what ten cables of 10 MN can hold")


class _KeyedError(ValueError):
    """A validator's error that names a key below the model that raised it."""

    def __init__(self, key: str, message: str):
        self.key = key
        super().__init__(message)


class _Model(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)


# --------------------------------------------------------------------------- robot
class Cable(_Model):
    """One cable: where it leaves the frame and where it holds the platform."""

    frame_anchor_m: Position
    """c_i in frame C, m."""
    platform_anchor_m: Position
    """p_i in frame P (origin at the platform's centre of mass), m."""
    tension_min_N: Tension | None = None
    """Smallest allowed tension, N (default: ``robot.tension_min_N``)."""
    tension_max_N: TensionMax | None = None
    """Largest allowed tension, N (default: ``robot.tension_max_N``)."""


class Robot(_Model):
    """The cable robot: platform, cables and which degrees of freedom they control."""

    dofs: Literal["planar", "spatial"] = "planar"
    mass_kg: _ranged(1e-3, 1e5, "kg", "a platform from 1 g to 100 t")
    inertia_kg_m2: Any
    """About the centre of mass in P: 3 principal moments or a 3x3 matrix."""
    tension_min_N: Tension | None = None
    tension_max_N: TensionMax | None = None
    cables: list[Cable] = Field(min_length=1)

    @field_validator("inertia_kg_m2", mode="before")
    @classmethod
    def _check_inertia(cls, value: Any) -> Any:
        def is_number(x: Any) -> bool:
            return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)

        if isinstance(value, (list, tuple)) and len(value) == 3 and all(map(is_number, value)):
            I = np.diag(np.asarray(value, dtype=float))
            value = tuple(float(v) for v in value)
        elif (isinstance(value, (list, tuple)) and len(value) == 3
              and all(isinstance(r, (list, tuple)) and len(r) == 3 and all(map(is_number, r))
                      for r in value)):
            I = np.asarray(value, dtype=float)
            value = tuple(tuple(float(v) for v in r) for r in value)
        else:
            shown = repr(value)
            raise ValueError(
                "expected 3 principal moments or a 3x3 matrix of numbers, got "
                + (shown if len(shown) <= 60 else shown[:57] + "...")
            )
        scale = max(float(np.abs(I).max()), 1e-300)
        if not np.allclose(I, I.T, rtol=0, atol=1e-12 * scale):
            raise ValueError("inertia matrix is not symmetric")
        eig = np.linalg.eigvalsh(I)
        if eig[0] <= 0:
            raise ValueError(f"inertia is not positive definite (eigenvalues {eig.round(6).tolist()})")
        if eig[0] + eig[1] < eig[2] * (1 - 1e-9):
            raise ValueError(
                "no rigid body has this inertia: principal moments break the triangle "
                f"inequality ({eig[0]:g} + {eig[1]:g} < {eig[2]:g})"
            )
        return value

    @model_validator(mode="after")
    def _check_cables(self) -> "Robot":
        n_dof = len(CONTROLLED_DOFS[self.dofs])
        if len(self.cables) < n_dof:
            raise _KeyedError(
                "cables",
                f"{len(self.cables)} cables cannot control the {n_dof} degrees of freedom "
                f"of a {self.dofs} robot (need at least {n_dof})",
            )
        if len(self.cables) > CABLES_MAX:
            raise _KeyedError("cables", f"must be between {n_dof} and {CABLES_MAX} cables (far more than "
                                        f"any cable robot has), got {len(self.cables)}")
        for i, cable in enumerate(self.cables, start=1):
            lo = cable.tension_min_N if cable.tension_min_N is not None else self.tension_min_N
            hi = cable.tension_max_N if cable.tension_max_N is not None else self.tension_max_N
            for name, val in (("tension_min_N", lo), ("tension_max_N", hi)):
                if val is None:
                    raise _KeyedError(
                        f"cables[{i}].{name}", f"missing, and no robot.{name} default is given"
                    )
            if lo >= hi:
                raise _KeyedError(
                    f"cables[{i}]",
                    f"tension_min_N ({lo:g}) must be below tension_max_N ({hi:g})",
                )
        for attr, what in (("frame_anchor_m", "frame"), ("platform_anchor_m", "platform")):
            pts = np.array([getattr(c, attr) for c in self.cables])
            d = np.linalg.norm(pts[:, None, :] - pts[None, :, :], axis=-1)
            i, j = np.nonzero(np.triu(d <= ANCHOR_TOLERANCE_M, k=1))
            if i.size:
                raise _KeyedError(
                    f"cables[{j[0] + 1}].{attr}",
                    f"same {what} anchor as cable {i[0] + 1} ({pts[i[0]].tolist()} m)",
                )
        return self

    @model_validator(mode="after")
    def _check_inertia_scale(self) -> "Robot":
        lo, hi = (self.mass_kg * k**2 for k in RADIUS_OF_GYRATION_RANGE_M)
        for moment in np.linalg.eigvalsh(self.inertia):
            if not lo <= moment <= hi:
                k_lo, k_hi = RADIUS_OF_GYRATION_RANGE_M
                raise _KeyedError(
                    "inertia_kg_m2",
                    f"principal moments must be between {_num(lo)} and {_num(hi)} kg m^2 for a "
                    f"{_num(self.mass_kg)} kg platform (radii of gyration from {_num(k_lo)} to "
                    f"{_num(k_hi)} m), got {_num(moment)}",
                )
        return self

    @model_validator(mode="after")
    def _check_geometry(self) -> "Robot":
        reason = _degenerate_geometry(self)
        if reason:
            raise _KeyedError("cables", reason)
        return self

    # Arrays the numerical layers use.
    @property
    def n_cables(self) -> int:
        return len(self.cables)

    @property
    def controlled(self) -> tuple[int, ...]:
        """Twist components the cables control (indices into (v, omega) in C)."""
        return CONTROLLED_DOFS[self.dofs]

    @property
    def frame_anchors(self) -> np.ndarray:
        """c_i^C, shape (n_cables, 3), m."""
        return np.array([c.frame_anchor_m for c in self.cables], dtype=float)

    @property
    def platform_anchors(self) -> np.ndarray:
        """p_i^P, shape (n_cables, 3), m."""
        return np.array([c.platform_anchor_m for c in self.cables], dtype=float)

    @property
    def inertia(self) -> np.ndarray:
        """I_PP, shape (3, 3), kg m^2, about the centre of mass in P."""
        I = np.asarray(self.inertia_kg_m2, dtype=float)
        return np.diag(I) if I.shape == (3,) else I

    @property
    def tension_min(self) -> np.ndarray:
        """T_min per cable, shape (n_cables,), N."""
        return np.array(
            [c.tension_min_N if c.tension_min_N is not None else self.tension_min_N for c in self.cables],
            dtype=float,
        )

    @property
    def tension_max(self) -> np.ndarray:
        """T_max per cable, shape (n_cables,), N."""
        return np.array(
            [c.tension_max_N if c.tension_max_N is not None else self.tension_max_N for c in self.cables],
            dtype=float,
        )


DOF_NAMES = ("x", "y", "z", "theta_x", "theta_y", "theta_z")


def _diameter(points: np.ndarray) -> float:
    """Largest distance between two of the points."""
    return float(np.linalg.norm(points[:, None, :] - points[None, :, :], axis=-1).max())


def _off_line(points: np.ndarray) -> tuple[float, np.ndarray]:
    """Largest distance of the points from their best-fitting line, and its direction."""
    d = points - points.mean(axis=0)
    axis = np.linalg.svd(d)[2][0]
    return float(np.linalg.norm(d - np.outer(d @ axis, axis), axis=1).max()), axis


def _direction(axis: np.ndarray) -> str:
    """A unit vector as a reader would name it: "along y", or its rounded components."""
    i = int(np.argmax(np.abs(axis)))
    if abs(axis[i]) > 1 - 1e-6:
        return f"along {'xyz'[i]}"
    return "along [" + ", ".join(f"{v:.3g}" for v in axis * np.sign(axis[i])) + "]"


def _degenerate_geometry(robot: Robot) -> str | None:
    """Why no pose gives J~ (eq. 6) full rank on the controlled DOFs, or None.

    Anchors collapsed to a point (within :data:`DEGENERATE_RELATIVE` of the robot's size),
    for a spatial robot anchors on one line, and otherwise J~ rank-deficient (to
    :data:`RANK_TOLERANCE`, moment columns divided by the robot's size) at every one of
    a handful of poses across the frame. A planar robot is judged in the x-z plane.
    """
    from .kinematics import cable_kinematics
    from .rotations import matrix_from_euler

    frame, platform = robot.frame_anchors, robot.platform_anchors
    planar = robot.dofs == "planar"
    plane = [0, 2] if planar else [0, 1, 2]
    size_f, size_p = _diameter(frame[:, plane]), _diameter(platform[:, plane])
    size = max(size_f, size_p)
    if size == 0.0:
        return "all anchors coincide: the cables cannot hold the platform"
    tol = DEGENERATE_RELATIVE * size
    where = " in the x-z plane" if planar else ""

    def within(d: float, other: str, other_size: float) -> str:
        if d <= 1e-12 * size:
            return f"coincide{where}"
        return (f"lie within {_num(float(f'{d:.3g}'))} m of each other{where}, less than "
                f"{_num(DEGENERATE_RELATIVE)} of the {other}'s size ({other_size:.3g} m)")

    if size_p <= tol:
        return (f"the platform anchors {within(size_p, 'frame', size_f)}: the cables cannot exert a "
                f"moment on the platform" + (" about y (theta_y)" if planar else ""))
    if size_f <= tol:
        return (f"the frame anchors {within(size_f, 'platform', size_p)}: every cable passes through "
                f"one point, and the cables cannot exert a moment about it")
    if not planar:
        for what, points in (("platform", platform), ("frame", frame)):
            off, axis = _off_line(points)
            if off <= tol:
                near = "" if off <= 1e-12 * size else f", all within {_num(float(f'{off:.3g}'))} m of it"
                return (f"the {what} anchors lie on one line ({_direction(axis)}{near}): every cable meets "
                        f"that line, so the cables cannot turn the platform about it")
    # J~ at the frame's centre and at random poses across (and, for a flat frame, off) it
    controlled = list(robot.controlled)
    lo, hi = frame.min(axis=0), frame.max(axis=0)
    centre, half = (lo + hi) / 2, (hi - lo) / 2
    half = np.where(half <= tol, size / 2, half)
    rng = np.random.default_rng(0)
    n = 8
    x = centre + rng.uniform(-0.8, 0.8, (n, 3)) * half
    angles = np.radians(rng.uniform(-30.0, 30.0, (n, 3)))
    x[0], angles[0] = centre, 0.0
    if planar:
        x[:, 1] = centre[1]
        angles[:, [0, 2]] = 0.0
    J = cable_kinematics(x, matrix_from_euler(angles), frame, platform).J_tilde[:, :, controlled]
    J[:, :, [k >= 3 for k in controlled]] /= size
    ranks, null = [], None
    for Jk in J:
        if not np.isfinite(Jk).all():
            continue  # a platform anchor on a frame anchor: no direction at this pose
        _, s, vt = np.linalg.svd(Jk)
        rank = int(np.sum(s > RANK_TOLERANCE * s[0]))
        if rank == len(controlled):
            return None
        ranks.append(rank)
        if null is None:
            null = vt[-1]
    if not ranks:
        return None
    dofs = [DOF_NAMES[k] for k, v in zip(controlled, null) if abs(v) > 0.3 * np.abs(null).max()]
    what = dofs[0] if len(dofs) == 1 else "a combination of " + ", ".join(dofs[:-1]) + " and " + dofs[-1]
    return (f"the cables cannot control {what}: the structure matrix J~ has rank {max(ranks)} of "
            f"{len(controlled)} at every pose tried ({len(ranks)} across the frame)")


# ---------------------------------------------------------------------- ship, sea
class Ship(_Model):
    """Where the robot stands on the ship."""

    frame_origin_m: Position = (0.0, 0.0, 0.0)
    """Origin of the robot frame C in the ship frame S, m (C's axes are S's)."""


class StillMotion(_Model):
    """A ship that does not move (S coincides with O)."""

    type: Literal["still"]


ShipDisplacement = _ranged(0.0, 30.0, "m", "a ship's surge, sway or heave in the worst storm")
ShipAngle = _ranged(0.0, 180.0, "deg", "at most 90 deg for roll and pitch, 180 deg for yaw")
ShipAngleOffset = _ranged(-180.0, 180.0, "deg", "at most 90 deg for roll and pitch, 180 deg for yaw")
ShipPeriod = _ranged(0.5, 3600.0, "s", "a ship's motion, from vibration to a slow drift")


class SineComponent(_Model):
    """``offset + amplitude * sin(2 pi t / period_s + phase)`` on one ship DOF."""

    dof: Literal["surge", "sway", "heave", "roll", "pitch", "yaw"]
    amplitude_m: ShipDisplacement | None = None
    amplitude_deg: ShipAngle | None = None
    offset_m: _ranged(-POSITION_MAX_M, POSITION_MAX_M, "m", "positions, in metres") | None = None
    offset_deg: ShipAngleOffset | None = None
    period_s: ShipPeriod
    phase_deg: Phase = 0.0

    @model_validator(mode="after")
    def _check_units(self) -> "SineComponent":
        angular = self.dof in ("roll", "pitch", "yaw")
        want, wrong = ("deg", "m") if angular else ("m", "deg")
        kind = "an angle" if angular else "a displacement"
        for stem in ("amplitude", "offset"):
            if getattr(self, f"{stem}_{wrong}") is not None:
                raise _KeyedError(
                    f"{stem}_{wrong}", f"{self.dof} is {kind}: give {stem}_{want}, not {stem}_{wrong}"
                )
        if getattr(self, f"amplitude_{want}") is None:
            raise _KeyedError(f"amplitude_{want}", f"missing (the amplitude of {self.dof})")
        if self.dof in ("roll", "pitch"):
            for key, lo in (("amplitude_deg", 0.0), ("offset_deg", -90.0)):
                value = getattr(self, key)
                if value is not None and not lo <= value <= 90.0:
                    raise _KeyedError(key, f"{_range_text(lo, 90.0, 'deg')} for {self.dof} (a ship "
                                           f"heeled or trimmed past 90 deg has capsized), got {_num(value)}")
        return self

    @property
    def amplitude(self) -> float:
        """Amplitude in SI (m or rad)."""
        return self._si(self.amplitude_m, self.amplitude_deg)

    @property
    def offset(self) -> float:
        """Mean value in SI (m or rad)."""
        return self._si(self.offset_m, self.offset_deg)

    @staticmethod
    def _si(metres: float | None, degrees: float | None) -> float:
        if degrees is not None:
            return math.radians(degrees)
        return metres or 0.0


class SinusoidalMotion(_Model):
    """A sum of sinusoids on the ship's six degrees of freedom."""

    type: Literal["sinusoidal"]
    components: list[SineComponent] = Field(min_length=1)


def _resolve_file(value: str, info: ValidationInfo) -> str:
    """A path relative to the scenario file's folder (or the working folder), made absolute."""
    base = (info.context or {}).get("base_dir")
    path = Path(value).expanduser()
    if not path.is_absolute() and base is not None:
        path = Path(base) / path
    if not path.is_file():
        raise ValueError(f"no such file: {path}")
    return str(path.resolve())


class RAOSource(_Model):
    """Where the ship's response amplitude operators come from."""

    source: Literal["box_hull", "csv", "capytaine"] = "box_hull"
    file: StrictStr | None = None
    """csv or capytaine: the file (relative paths from the scenario's folder)."""
    length_m: _ranged(1.0, 1000.0, "m", "a hull from a dinghy to the longest ship") | None = None
    beam_m: _ranged(0.5, 200.0, "m", "a hull from a dinghy to the widest platform") | None = None
    draught_m: _ranged(0.1, 50.0, "m", "a hull from a dinghy to the deepest tanker") | None = None
    gm_m: _ranged(0.01, 100.0, "m", "a floating hull's metacentric height") | None = None
    roll_damping_ratio: _ranged(0.01, 1.0, "", "a fraction of critical damping") = 0.05

    @field_validator("file")
    @classmethod
    def _check_file(cls, value: str | None, info: ValidationInfo) -> str | None:
        return None if value is None else _resolve_file(value, info)

    @model_validator(mode="after")
    def _check_source(self) -> "RAOSource":
        if self.source == "box_hull":
            for key in ("length_m", "beam_m", "draught_m", "gm_m"):
                if getattr(self, key) is None:
                    raise _KeyedError(key, "missing: the box-hull model needs the hull's length, "
                                           "beam, draught and GM")
        elif self.file is None:
            raise _KeyedError("file", f"missing: a {self.source} RAO source needs its file")
        return self


SEA_COMPONENTS_MAX = 12_000
"""Most wave frequencies a sea-state record may sum (6 record_s / tp_s): the synthesis holds
thousands of samples of each at once."""


class SeaStateMotion(_Model):
    """Irregular seas: a wave spectrum turned into 6-DOF ship motion through RAOs."""

    type: Literal["sea_state"]
    spectrum: Literal["jonswap", "pierson_moskowitz"] = "jonswap"
    hs_m: _ranged(0.01, 30.0, "m", "from ripples to the highest storm seas")
    tp_s: _ranged(1.0, 40.0, "s", "from ripples to the longest swell")
    gamma: _ranged(1.0, 10.0, "", "JONSWAP peak enhancement; measured seas lie within 1 to 7") | None = None
    """JONSWAP peak enhancement; default from Tp / sqrt(Hs) (DNV-RP-C205)."""
    heading_deg: Phase = 180.0
    """Direction the waves travel towards, from the ship's +x, counter-clockwise: 180 = head seas."""
    spreading: Literal["none", "cos2s", "cosn"] = "none"
    spreading_exponent: _ranged(0.0, 100.0, "", "cos-2s s: about 1 for wind seas, 75 for swell",
                                above=True) = 10.0
    n_directions: Annotated[int, Field(ge=1, le=181, strict=True)] = 15
    seed: Annotated[int, Field(ge=0, strict=True)] = 0
    record_s: _ranged(60.0, 10800.0, "s", "a sea state holds for at most about 3 hours") = 1800.0
    """Repeat period of the synthesised record (frequency step 2 pi / record_s)."""
    rao: RAOSource

    @model_validator(mode="after")
    def _check_components(self) -> "SeaStateMotion":
        n = 6.0 * self.record_s / self.tp_s  # frequencies up to 6 omega_p in steps of 2 pi / record_s
        if n > SEA_COMPONENTS_MAX:
            raise _KeyedError(
                "record_s",
                f"a {_num(self.record_s)} s record at Tp = {_num(self.tp_s)} s sums {_num(round(n))} wave "
                f"frequencies (6 record_s / tp_s), more than {SEA_COMPONENTS_MAX}: make record_s at most "
                f"{_num(SEA_COMPONENTS_MAX * self.tp_s / 6)} s",
            )
        return self


class RecordedMotion(_Model):
    """Ship motion measured on board, from a CSV file."""

    type: Literal["recorded"]
    file: StrictStr
    """Columns time_s, surge_m, sway_m, heave_m, roll, pitch, yaw (relative paths from the
    scenario's folder)."""
    z_axis: Literal["up", "down"] = "up"
    """up: x forward, y to port, z up (ours); down: x forward, y to starboard, z down."""
    angles: Literal["deg", "rad"] = "deg"
    smoothing_s: _ranged(0.0, 60.0, "s", "a spline's time scale; slower motion is what the ship does",
                         above=True) | None = None
    """Time scale of the smoothing spline that gives velocities and accelerations."""
    start_s: TimeOfDay = 0.0
    """Time in the record that the scenario's t = 0 corresponds to."""

    @field_validator("file")
    @classmethod
    def _check_file(cls, value: str, info: ValidationInfo) -> str:
        return _resolve_file(value, info)


BaseMotion = Annotated[
    Union[StillMotion, SinusoidalMotion, SeaStateMotion, RecordedMotion], Field(discriminator="type")
]


# ----------------------------------------------------------------------- trajectory
class CircleTrajectory(_Model):
    """``center + r (cos(2 pi t/T + phase) e1 + sin(2 pi t/T + phase) e2)`` in C (eq. 21)."""

    type: Literal["circle"]
    center_m: Position
    radius_m: _ranged(0.0, POSITION_MAX_M, "m", "positions on a ship, in metres", above=True)
    period_s: _ranged(MOVE_MIN_S, TIME_MAX_S, "s", "from faster than any cable robot to 11.6 days")
    phase_deg: Phase = 0.0
    plane: Literal["xz", "xy", "yz"] = "xz"
    """Axes (e1, e2) of the circle's plane: "xz" runs x = cos, z = sin as in eq. 21."""
    orientation_deg: Orientation = (0.0, 0.0, 0.0)
    """Constant platform orientation (rx, ry, rz) in C, deg."""


class Waypoint(_Model):
    time_s: TimeOfDay
    position_m: Position
    orientation_deg: Orientation = (0.0, 0.0, 0.0)


class WaypointsTrajectory(_Model):
    """Rest-to-rest quintic segments through poses; holds the first and last pose outside."""

    type: Literal["waypoints"]
    waypoints: list[Waypoint] = Field(min_length=2)

    @model_validator(mode="after")
    def _check_times(self) -> "WaypointsTrajectory":
        for i in range(1, len(self.waypoints)):
            if self.waypoints[i].time_s < self.waypoints[i - 1].time_s + MOVE_MIN_S:
                raise _KeyedError(
                    f"waypoints[{i + 1}].time_s",
                    f"must be later than waypoint {i}'s ({self.waypoints[i - 1].time_s:g} s), by at "
                    f"least {_num(MOVE_MIN_S)} s (faster than any cable robot moves)",
                )
        return self


class LineTrajectory(_Model):
    """A straight rest-to-rest move (quintic time law) between two poses."""

    type: Literal["line"]
    start_position_m: Position
    end_position_m: Position
    start_orientation_deg: Orientation = (0.0, 0.0, 0.0)
    end_orientation_deg: Orientation | None = None
    """Defaults to the start orientation."""
    start_time_s: TimeOfDay = 0.0
    duration_s: _ranged(MOVE_MIN_S, TIME_MAX_S, "s", "from faster than any cable robot to 11.6 days")

    @model_validator(mode="after")
    def _check_end(self) -> "LineTrajectory":
        if self.start_time_s + self.duration_s > TIME_MAX_S:
            raise _KeyedError("duration_s", f"the move must end by {_num(TIME_MAX_S)} s (11.6 days), "
                                            f"got start_time_s + duration_s = "
                                            f"{_num(self.start_time_s + self.duration_s)}")
        return self

    def as_waypoints(self) -> WaypointsTrajectory:
        end_rot = self.end_orientation_deg or self.start_orientation_deg
        return WaypointsTrajectory(
            type="waypoints",
            waypoints=[
                Waypoint(time_s=self.start_time_s, position_m=self.start_position_m,
                         orientation_deg=self.start_orientation_deg),
                Waypoint(time_s=self.start_time_s + self.duration_s,
                         position_m=self.end_position_m, orientation_deg=end_rot),
            ],
        )


Trajectory = Annotated[
    Union[CircleTrajectory, WaypointsTrajectory, LineTrajectory], Field(discriminator="type")
]


# ------------------------------------------------------------------ the rest
class Disturbance(_Model):
    """External force f_r and moment m_r on the platform (eq. 12): constant plus sinusoid."""

    frame: Literal["O", "C", "P"] = "O"
    """Frame the vectors are given in: O (earth, as the paper), C (ship-fixed) or P (platform)."""
    force_N: Force = (0.0, 0.0, 0.0)
    moment_N_m: Moment = (0.0, 0.0, 0.0)
    force_amplitude_N: Force = (0.0, 0.0, 0.0)
    moment_amplitude_N_m: Moment = (0.0, 0.0, 0.0)
    period_s: _ranged(1e-3, TIME_MAX_S, "s", "from a 1 kHz vibration to 11.6 days") | None = None
    phase_deg: Phase = 0.0

    @model_validator(mode="after")
    def _check_period(self) -> "Disturbance":
        if self.period_s is None and any(self.force_amplitude_N + self.moment_amplitude_N_m):
            raise _KeyedError("period_s", "missing: a sinusoidal disturbance needs its period")
        return self


class Time(_Model):
    step_s: _ranged(1e-5, 1.0, "s", "from 100 kHz to one sample a second") = 0.001
    duration_s: _ranged(0.0, TIME_MAX_S, "s", "11.6 days", above=True)

    @property
    def n_steps(self) -> int:
        """Number of samples, both ends included."""
        return int(math.floor(self.duration_s / self.step_s + 1e-9)) + 1


class Planning(_Model):
    method: Literal[
        "pseudo_inverse", "minimum_variance", "closed_form", "improved_closed_form", "minimum_norm"
    ] = "minimum_variance"
    base_model: Literal["moving", "fixed"] = "moving"
    """"fixed" plans as if the ship were still (the traditional model), for comparison."""


class CableModel(_Model):
    """How a cable turns a command into tension (the virtual prototype's actuators)."""

    model: Literal["ideal", "elastic"] = "ideal"
    """ideal: the commanded tension acts (as in the paper). elastic: a cable on a winch."""
    stiffness_EA_N: _ranged(1.0, 1e10, "N", "from a rubber cord to a 25 cm steel rope") | None = None
    """Axial stiffness E A of an elastic cable, N: tension = E A (L - L0) / L0 + damping."""
    damping_N_s_m: _ranged(0.0, 1e9, "N s/m", "beyond critical for the stiffest cable") = 0.0
    """Axial damping of an elastic cable, N per (m/s) of stretch rate."""
    winch: Literal["length", "tension"] = "length"
    """length: the winch pays out a commanded unstretched length L0; tension: it tracks a
    commanded tension (with its tension sensor)."""
    winch_time_constant_s: _ranged(0.0, 60.0, "s", "a winch that lags a minute holds nothing") = 0.0
    """First-order lag of the winch on its command (0: none)."""

    @model_validator(mode="after")
    def _check_stiffness(self) -> "CableModel":
        if self.model == "elastic" and self.stiffness_EA_N is None:
            raise _KeyedError("stiffness_EA_N", "missing: an elastic cable needs its axial stiffness")
        return self


def _noise(hi: float, unit: str) -> Any:
    return _ranged(0.0, hi, unit, "a sensor's standard deviation, not what it measures")


class Noise(_Model):
    """Gaussian noise (standard deviations) on what the closed-loop controller measures."""

    seed: Annotated[int, Field(ge=0, strict=True)] = 0
    pose_m: _noise(10.0, "m") = 0.0
    pose_deg: _noise(30.0, "deg") = 0.0
    velocity_m_s: _noise(10.0, "m/s") = 0.0
    rate_deg_s: _noise(360.0, "deg/s") = 0.0
    tension_N: _noise(1e7, "N") = 0.0
    """On the winch's tension sensor (tension-controlled winches)."""
    ship_position_m: _noise(30.0, "m") = 0.0
    ship_angle_deg: _noise(30.0, "deg") = 0.0
    ship_velocity_m_s: _noise(30.0, "m/s") = 0.0
    ship_rate_deg_s: _noise(360.0, "deg/s") = 0.0
    ship_acceleration_m_s2: _noise(100.0, "m/s^2") = 0.0
    ship_angular_acceleration_deg_s2: _noise(3600.0, "deg/s^2") = 0.0


class Control(_Model):
    """Closed-loop computed-torque gains: a critically damped second-order error by default."""

    bandwidth_hz: _ranged(1e-3, 1000.0, "Hz", "from a drifting loop to beyond any winch") = 5.0
    damping_ratio: _ranged(0.01, 10.0, "", "from barely damped to heavily overdamped") = 1.0


class Simulation(_Model):
    """The virtual prototype: which plant, its cables, the controller's gains and sensors."""

    plant: Literal["mujoco", "own"] = "mujoco"
    """mujoco: the independent physics engine; own: this package's forward dynamics (RK4)."""
    integrator: Literal["RK4", "Euler", "implicitfast"] = "RK4"
    """MuJoCo's integrator (the own plant always uses RK4)."""
    cables: CableModel = CableModel()
    noise: Noise = Noise()
    control: Control = Control()
    initial_error_m: _ranged_vec3(100.0, "m", "an error, not another pose") = (0.0, 0.0, 0.0)
    """Platform position error at t = 0 (actual minus planned), in C, m."""
    initial_error_deg: _ranged_vec3(90.0, "deg", "an error, not another pose",
                                    ("rx", "ry", "rz")) = (0.0, 0.0, 0.0)
    """Platform orientation error at t = 0 (rx, ry, rz), deg."""
    max_error_m: _ranged(0.0, POSITION_MAX_M, "m", "positions on a ship, in metres", above=True) | None = None
    """A run whose position or cable-length error passes this is flagged; default 1% of
    the frame's largest extent."""
    max_error_deg: _ranged(0.0, 180.0, "deg", "half a turn", above=True) = 1.0
    """A run whose orientation error passes this is flagged, deg."""


class Environment(_Model):
    gravity_m_s2: _ranged(0.1, 30.0, "m/s^2", "from a small moon's to beyond Jupiter's") = 9.8
    """Magnitude of gravity; it points along -z of O."""


class Scenario(_Model):
    """A complete description of one robot, one ship motion and one task."""

    name: StrictStr = "scenario"
    description: StrictStr = ""
    robot: Robot
    ship: Ship = Ship()
    base_motion: BaseMotion = StillMotion(type="still")
    trajectory: Trajectory
    disturbance: Disturbance = Disturbance()
    time: Time
    planning: Planning = Planning()
    simulation: Simulation = Simulation()
    environment: Environment = Environment()

    @model_validator(mode="after")
    def _check_record(self) -> "Scenario":
        if isinstance(self.base_motion, SeaStateMotion) and self.base_motion.record_s < self.time.duration_s:
            raise _KeyedError("base_motion.record_s",
                              f"the sea-state record ({self.base_motion.record_s:g} s) would repeat within "
                              f"the duration ({self.time.duration_s:g} s): make it at least as long")
        return self

    @model_validator(mode="after")
    def _check_planar_trajectory(self) -> "Scenario":
        if self.robot.dofs != "planar":
            return self
        traj = self.trajectory
        msg_rot = "a planar robot turns only about y: rx and rz must be 0"
        if isinstance(traj, CircleTrajectory):
            if traj.plane != "xz":
                raise _KeyedError("trajectory.plane", "a planar robot moves in the x-z plane of C: use \"xz\"")
            if traj.orientation_deg[0] or traj.orientation_deg[2]:
                raise _KeyedError("trajectory.orientation_deg", msg_rot)
            return self
        if isinstance(traj, LineTrajectory):
            poses = [("start_", traj.start_position_m, traj.start_orientation_deg),
                     ("end_", traj.end_position_m, traj.end_orientation_deg or (0.0, 0.0, 0.0))]
        else:
            poses = [(f"waypoints[{i}].", w.position_m, w.orientation_deg)
                     for i, w in enumerate(traj.waypoints, start=1)]
        y0 = poses[0][1][1]
        for prefix, pos, rot in poses:
            if rot[0] or rot[2]:
                raise _KeyedError(f"trajectory.{prefix}orientation_deg", msg_rot)
            if pos[1] != y0:
                raise _KeyedError(
                    f"trajectory.{prefix}position_m",
                    f"a planar robot moves in the x-z plane of C: y must stay {y0:g} m",
                )
        return self

    def with_changes(self, **sections: Any) -> "Scenario":
        """A validated copy with top-level sections replaced, e.g. ``planning={...}``.

        Raises
        ------
        ScenarioError
            One line naming the key, as for a file.
        """
        data = self.model_dump(exclude_none=True)
        for key, value in sections.items():
            data[key] = value.model_dump(exclude_none=True) if isinstance(value, BaseModel) else value
        try:
            return Scenario.model_validate(data)
        except ValidationError as exc:
            raise _to_scenario_error(exc, data, None) from None


# ----------------------------------------------------------------------- scale
FRAME_EXTENT_RANGE_M = (0.05, 200.0)
"""Sizes of a cable robot's frame (the box of its frame anchors, largest side) that pass unremarked, m."""
PLATFORM_EXTENT_MAX_M = 50.0
"""Largest platform (the box of its anchors, largest side) that passes unremarked, m."""


def scale_warnings(scenario: Scenario) -> list[str]:
    """One-line warnings when the robot's size is far outside cable-robot scale.

    Lengths in scenarios are in metres; a robot drawn in millimetres (a 4 km frame,
    a 400 m platform) still validates, and only plans badly. This names the sizes
    that look wrong and the likely cause. The frame's size is the largest side of
    the box of its frame anchors; the platform's, of the box of its platform anchors.

    Parameters
    ----------
    scenario : Scenario

    Returns
    -------
    list of str
        Empty when the sizes look like a cable robot's.
    """
    robot = scenario.robot
    frame = float(np.ptp(robot.frame_anchors, axis=0).max())
    platform = float(np.ptp(robot.platform_anchors, axis=0).max())
    lo, hi = FRAME_EXTENT_RANGE_M
    facts = []
    if frame > hi:
        facts.append(f"the frame anchors span {frame:.4g} m (more than {hi:g} m)")
    elif frame < lo:
        facts.append(f"the frame anchors span only {frame:.4g} m (less than {lo * 100:g} cm)")
    if platform > PLATFORM_EXTENT_MAX_M:
        facts.append(f"the platform anchors span {platform:.4g} m (more than {PLATFORM_EXTENT_MAX_M:g} m)")
    if platform > frame:
        facts.append(f"the platform ({platform:.4g} m) is larger than the frame ({frame:.4g} m)")
    if not facts:
        return []
    if frame > hi and lo <= frame / 1000 <= hi:
        cause = "coordinates look like millimetres: scenario lengths are in metres (divide by 1000)"
    elif lo <= frame <= hi and platform > PLATFORM_EXTENT_MAX_M and platform / 1000 <= frame:
        cause = "the platform anchors look like millimetres: platform_anchor_m is in metres"
    elif lo <= frame <= hi:
        cause = "platform_anchor_m is measured from the platform's centre of mass (in P), in metres"
    else:
        cause = "scenario lengths are in metres"
    return [f"robot size far outside cable-robot scale: {'; '.join(facts)}; {cause}"]


# --------------------------------------------------------------------- loading
def builtin_scenarios() -> list[str]:
    """Names of the scenarios shipped with the package."""
    folder = resources.files("marinecdpr") / "scenarios"
    return sorted(p.name[:-5] for p in folder.iterdir() if p.name.endswith(".toml"))


def load_scenario(path_or_name: str | Path = "paper") -> Scenario:
    """Read and validate a scenario from a TOML file or a built-in name.

    Parameters
    ----------
    path_or_name : str or Path
        A path to a ``.toml`` file, or the name of a built-in scenario
        (see :func:`builtin_scenarios`).

    Raises
    ------
    ScenarioError
        One line naming the source, the key and what was expected.
    """
    path = Path(path_or_name)
    if path.is_file():
        source = str(path)
        text = _scenario_text(path, source)
    elif str(path_or_name) in builtin_scenarios():
        source = f"built-in scenario '{path_or_name}'"
        text = (resources.files("marinecdpr") / "scenarios" / f"{path_or_name}.toml").read_text(
            encoding="utf-8"
        )
    else:
        raise ScenarioError(
            f"no such file, and no built-in scenario of that name "
            f"(built-ins: {', '.join(builtin_scenarios())})",
            source=str(path_or_name),
        )
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ScenarioError(f"not valid TOML: {exc}", source=source) from None
    except RecursionError:  # tomllib recurses into nested arrays and inline tables
        raise ScenarioError("not valid TOML: arrays or inline tables too deeply nested "
                            "(a scenario nests a few levels)", source=source) from None
    base_dir = path.parent if path.is_file() else Path.cwd()
    return scenario_from_dict(data, source=source, base_dir=base_dir)


def _scenario_text(path: Path, source: str, max_bytes: int = 64 * 2**20) -> str:
    """A scenario file's text: UTF-8 (a byte-order mark dropped), no NUL byte, at most 64 MiB."""
    from .textfiles import position

    try:
        with path.open("rb") as f:
            raw = f.read(max_bytes + 1)
    except OSError as exc:
        raise ScenarioError(f"cannot read the file ({exc.strerror or exc})", source=source) from None
    if len(raw) > max_bytes:
        raise ScenarioError(f"larger than a scenario file can be ({max_bytes // 2**20} MiB)", source=source)
    raw = raw.removeprefix(b"\xef\xbb\xbf")
    if (nul := raw.find(b"\0")) >= 0:
        raise ScenarioError(f"{position(raw, nul, 'line')}: a NUL byte, so not text; "
                            f"expected a TOML scenario file", source=source)
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise ScenarioError(f"{position(raw, exc.start, 'line')}: not UTF-8 text; "
                            f"expected a TOML scenario file in UTF-8", source=source) from None


def _too_deep(data: Any, limit: int = 32) -> str | None:
    """The top-level key under which tables and lists nest more than ``limit`` deep, or None."""
    for key, value in (data.items() if isinstance(data, dict) else ()):
        stack = [(value, 2)]  # the top-level table is level 1
        while stack:  # not recursive: a deep (or circular) structure ends at the limit
            node, depth = stack.pop()
            if isinstance(node, (dict, list, tuple)):
                if depth > limit:
                    return str(key)
                stack.extend((v, depth + 1) for v in (node.values() if isinstance(node, dict) else node))
    return None


def scenario_from_dict(
    data: dict[str, Any], *, source: str | None = None, base_dir: str | Path | None = None
) -> Scenario:
    """Validate a scenario given as nested dicts (as read from TOML).

    Parameters
    ----------
    base_dir : str or Path, optional
        Folder that relative file paths (RAOs, recorded motion) are taken from;
        default the working folder.
    """
    if (key := _too_deep(data)) is not None:
        raise ScenarioError("too deeply nested (tables or arrays more than 32 levels deep; "
                            "a scenario nests a few)", source=source, key=key)
    try:
        try:
            return Scenario.model_validate(data, context={"base_dir": base_dir or Path.cwd()})
        except ValidationError as exc:
            raise _to_scenario_error(exc, data, source) from None
    except RecursionError:  # a backstop: _too_deep should have caught it
        raise ScenarioError("too deeply nested", source=source) from None


def _to_scenario_error(exc: ValidationError, data: Any, source: str | None) -> ScenarioError:
    """The first validation error as one line: the dotted key (entries counted from 1)."""
    # a misspelt key explains the "missing" error that comes with it: report it first
    errors = sorted(exc.errors(), key=lambda e: e["type"] != "extra_forbidden")
    err = errors[0]
    loc = list(err["loc"])
    kind = err["type"]
    message = err["msg"].removeprefix("Value error, ")
    if (kind == "missing" and loc and isinstance(loc[-1], int)) or kind in ("too_long", "tuple_type"):
        # a 3-vector with the wrong number of entries: name the vector, not its element
        if isinstance(loc[-1], int):
            loc.pop()
        value = _lookup(data, loc)
        got = f"{len(value)}" if isinstance(value, list) else repr(value)
        message = f"expected 3 numbers [x, y, z], got {got}"
    elif kind == "extra_forbidden":
        message = "unknown key" + _suggest(err["loc"], data)
    elif kind == "missing":
        message = "missing"
    elif kind in ("union_tag_invalid", "union_tag_not_found"):
        loc.append("type")
        got = _lookup(data, loc)
        message = (f"expected one of {_union_tags(loc[:-1])}"
                   + (" (missing)" if got is None else f" (got {got!r})"))
    elif kind not in ("value_error", "assertion_error") and "input" in err:
        shown = repr(err["input"])
        message += f" (got {shown if len(shown) <= 60 else shown[:57] + '...'})"
    key_parts: list[str] = []
    for part in _strip_tags(data, loc):
        if isinstance(part, int):
            key_parts[-1] += f"[{part + 1}]"
        else:
            key_parts.append(str(part))
    error_obj = (err.get("ctx") or {}).get("error")
    if isinstance(error_obj, _KeyedError):
        key_parts.append(error_obj.key)
    # the field a misspelt key was meant to be is reported missing too: not another problem
    others = [e for e in errors[1:] if not (
        kind == "extra_forbidden" and e["type"] == "missing" and f"'{e['loc'][-1]}'?" in message)]
    if others:
        message += f" (and {len(others)} more problem{'s' if len(others) > 1 else ''})"
    return ScenarioError(message, source=source, key=".".join(key_parts) or None)


def _union_tags(loc: list) -> str:
    """The ``type`` values a union field at ``loc`` accepts, quoted."""
    model: Any = Scenario
    for part in loc:
        fields = getattr(model, "model_fields", {})
        if isinstance(part, str) and part in fields:
            model = fields[part].annotation
    tags: list[str] = []
    stack = [model]
    while stack:
        ann = stack.pop()
        if isinstance(ann, type) and issubclass(ann, BaseModel):
            tag = ann.model_fields.get("type")
            tags += list(getattr(tag.annotation, "__args__", ())) if tag else []
        else:
            stack.extend(getattr(ann, "__args__", ()))
            if hasattr(ann, "__metadata__"):
                stack.append(ann.__origin__)
    return ", ".join(f"'{t}'" for t in sorted(tags))


def _strip_tags(data: Any, loc: list) -> list:
    """The location without the tags ("circle") pydantic inserts after a union field."""
    out: list = []
    node: Any = data
    after_field = False
    for part in loc:
        if isinstance(part, int):
            node = node[part] if isinstance(node, list) and part < len(node) else None
            after_field = False
        elif after_field and isinstance(node, dict) and node.get("type") == part:
            after_field = False  # the tag: skip it, once
            continue
        else:
            node = node.get(part) if isinstance(node, dict) else None
            after_field = True
        out.append(part)
    return out


def _lookup(data: Any, loc: list) -> Any:
    """The raw value at a pydantic location; None if absent."""
    node = data
    for part in _strip_tags(data, loc):
        if isinstance(part, int):
            node = node[part] if isinstance(node, list) and part < len(node) else None
        else:
            node = node.get(part) if isinstance(node, dict) else None
    return node


def _suggest(loc: tuple, data: Any) -> str:
    """'; did you mean X? (expected one of: ...)' for a misspelt key."""
    model: Any = Scenario
    node: Any = data
    for part in _strip_tags(data, list(loc[:-1])):
        if isinstance(part, int):
            node = node[part] if isinstance(node, list) and part < len(node) else None
            continue
        node = node.get(part) if isinstance(node, dict) else None
        model = _field_model(model.model_fields[part].annotation, node)
    fields = list(getattr(model, "model_fields", {}))
    close = difflib.get_close_matches(str(loc[-1]), fields, n=1, cutoff=0.5)
    hint = f"; did you mean '{close[0]}'?" if close else ""
    return f"{hint} (expected one of: {', '.join(fields)})" if fields else hint


def _field_model(annotation: Any, node: Any) -> Any:
    """The model class a field holds (through lists, unions and Annotated), picked by "type"."""
    candidates, stack = [], [annotation]
    while stack:
        ann = stack.pop()
        if isinstance(ann, type) and issubclass(ann, BaseModel):
            candidates.append(ann)
        else:
            stack.extend(getattr(ann, "__args__", ()))
            if getattr(ann, "__origin__", None) is not None and hasattr(ann, "__metadata__"):
                stack.append(ann.__origin__)
    if isinstance(node, dict):
        for cand in candidates:
            tag = cand.model_fields.get("type")
            if tag is not None and node.get("type") in getattr(tag.annotation, "__args__", ()):
                return cand
    return candidates[0] if candidates else None
