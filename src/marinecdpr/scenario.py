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
    BaseModel,
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
PositiveFloat = Annotated[StrictFloat, Field(gt=0)]
NonNegativeFloat = Annotated[StrictFloat, Field(ge=0)]
ANCHOR_TOLERANCE_M = 1e-9


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

    frame_anchor_m: Vec3
    """c_i in frame C, m."""
    platform_anchor_m: Vec3
    """p_i in frame P (origin at the platform's centre of mass), m."""
    tension_min_N: NonNegativeFloat | None = None
    """Smallest allowed tension, N (default: ``robot.tension_min_N``)."""
    tension_max_N: PositiveFloat | None = None
    """Largest allowed tension, N (default: ``robot.tension_max_N``)."""


class Robot(_Model):
    """The cable robot: platform, cables and which degrees of freedom they control."""

    dofs: Literal["planar", "spatial"] = "planar"
    mass_kg: PositiveFloat
    inertia_kg_m2: Any
    """About the centre of mass in P: 3 principal moments or a 3x3 matrix."""
    tension_min_N: NonNegativeFloat | None = None
    tension_max_N: PositiveFloat | None = None
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


# ---------------------------------------------------------------------- ship, sea
class Ship(_Model):
    """Where the robot stands on the ship."""

    frame_origin_m: Vec3 = (0.0, 0.0, 0.0)
    """Origin of the robot frame C in the ship frame S, m (C's axes are S's)."""


class StillMotion(_Model):
    """A ship that does not move (S coincides with O)."""

    type: Literal["still"]


class SineComponent(_Model):
    """``offset + amplitude * sin(2 pi t / period_s + phase)`` on one ship DOF."""

    dof: Literal["surge", "sway", "heave", "roll", "pitch", "yaw"]
    amplitude_m: StrictFloat | None = None
    amplitude_deg: StrictFloat | None = None
    offset_m: StrictFloat | None = None
    offset_deg: StrictFloat | None = None
    period_s: PositiveFloat
    phase_deg: StrictFloat = 0.0

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
    length_m: PositiveFloat | None = None
    beam_m: PositiveFloat | None = None
    draught_m: PositiveFloat | None = None
    gm_m: PositiveFloat | None = None
    roll_damping_ratio: PositiveFloat = 0.05

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


class SeaStateMotion(_Model):
    """Irregular seas: a wave spectrum turned into 6-DOF ship motion through RAOs."""

    type: Literal["sea_state"]
    spectrum: Literal["jonswap", "pierson_moskowitz"] = "jonswap"
    hs_m: PositiveFloat
    tp_s: PositiveFloat
    gamma: Annotated[StrictFloat, Field(ge=1.0)] | None = None
    """JONSWAP peak enhancement; default from Tp / sqrt(Hs) (DNV-RP-C205)."""
    heading_deg: StrictFloat = 180.0
    """Direction the waves travel towards, from the ship's +x, counter-clockwise: 180 = head seas."""
    spreading: Literal["none", "cos2s", "cosn"] = "none"
    spreading_exponent: PositiveFloat = 10.0
    n_directions: Annotated[int, Field(ge=1, le=181, strict=True)] = 15
    seed: Annotated[int, Field(ge=0, strict=True)] = 0
    record_s: PositiveFloat = 1800.0
    """Repeat period of the synthesised record (frequency step 2 pi / record_s)."""
    rao: RAOSource


class RecordedMotion(_Model):
    """Ship motion measured on board, from a CSV file."""

    type: Literal["recorded"]
    file: StrictStr
    """Columns time_s, surge_m, sway_m, heave_m, roll, pitch, yaw (relative paths from the
    scenario's folder)."""
    z_axis: Literal["up", "down"] = "up"
    """up: x forward, y to port, z up (ours); down: x forward, y to starboard, z down."""
    angles: Literal["deg", "rad"] = "deg"
    smoothing_s: PositiveFloat | None = None
    """Time scale of the smoothing spline that gives velocities and accelerations."""
    start_s: NonNegativeFloat = 0.0
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
    center_m: Vec3
    radius_m: PositiveFloat
    period_s: PositiveFloat
    phase_deg: StrictFloat = 0.0
    plane: Literal["xz", "xy", "yz"] = "xz"
    """Axes (e1, e2) of the circle's plane: "xz" runs x = cos, z = sin as in eq. 21."""
    orientation_deg: Vec3 = (0.0, 0.0, 0.0)
    """Constant platform orientation (rx, ry, rz) in C, deg."""


class Waypoint(_Model):
    time_s: NonNegativeFloat
    position_m: Vec3
    orientation_deg: Vec3 = (0.0, 0.0, 0.0)


class WaypointsTrajectory(_Model):
    """Rest-to-rest quintic segments through poses; holds the first and last pose outside."""

    type: Literal["waypoints"]
    waypoints: list[Waypoint] = Field(min_length=2)

    @model_validator(mode="after")
    def _check_times(self) -> "WaypointsTrajectory":
        for i in range(1, len(self.waypoints)):
            if self.waypoints[i].time_s <= self.waypoints[i - 1].time_s:
                raise _KeyedError(
                    f"waypoints[{i + 1}].time_s",
                    f"must be later than waypoint {i}'s ({self.waypoints[i - 1].time_s:g} s)",
                )
        return self


class LineTrajectory(_Model):
    """A straight rest-to-rest move (quintic time law) between two poses."""

    type: Literal["line"]
    start_position_m: Vec3
    end_position_m: Vec3
    start_orientation_deg: Vec3 = (0.0, 0.0, 0.0)
    end_orientation_deg: Vec3 | None = None
    """Defaults to the start orientation."""
    start_time_s: NonNegativeFloat = 0.0
    duration_s: PositiveFloat

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
    force_N: Vec3 = (0.0, 0.0, 0.0)
    moment_N_m: Vec3 = (0.0, 0.0, 0.0)
    force_amplitude_N: Vec3 = (0.0, 0.0, 0.0)
    moment_amplitude_N_m: Vec3 = (0.0, 0.0, 0.0)
    period_s: PositiveFloat | None = None
    phase_deg: StrictFloat = 0.0

    @model_validator(mode="after")
    def _check_period(self) -> "Disturbance":
        if self.period_s is None and any(self.force_amplitude_N + self.moment_amplitude_N_m):
            raise _KeyedError("period_s", "missing: a sinusoidal disturbance needs its period")
        return self


class Time(_Model):
    step_s: PositiveFloat = 0.001
    duration_s: PositiveFloat

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
    stiffness_EA_N: PositiveFloat | None = None
    """Axial stiffness E A of an elastic cable, N: tension = E A (L - L0) / L0 + damping."""
    damping_N_s_m: NonNegativeFloat = 0.0
    """Axial damping of an elastic cable, N per (m/s) of stretch rate."""
    winch: Literal["length", "tension"] = "length"
    """length: the winch pays out a commanded unstretched length L0; tension: it tracks a
    commanded tension (with its tension sensor)."""
    winch_time_constant_s: NonNegativeFloat = 0.0
    """First-order lag of the winch on its command (0: none)."""

    @model_validator(mode="after")
    def _check_stiffness(self) -> "CableModel":
        if self.model == "elastic" and self.stiffness_EA_N is None:
            raise _KeyedError("stiffness_EA_N", "missing: an elastic cable needs its axial stiffness")
        return self


class Noise(_Model):
    """Gaussian noise (standard deviations) on what the closed-loop controller measures."""

    seed: Annotated[int, Field(ge=0, strict=True)] = 0
    pose_m: NonNegativeFloat = 0.0
    pose_deg: NonNegativeFloat = 0.0
    velocity_m_s: NonNegativeFloat = 0.0
    rate_deg_s: NonNegativeFloat = 0.0
    tension_N: NonNegativeFloat = 0.0
    """On the winch's tension sensor (tension-controlled winches)."""
    ship_position_m: NonNegativeFloat = 0.0
    ship_angle_deg: NonNegativeFloat = 0.0
    ship_velocity_m_s: NonNegativeFloat = 0.0
    ship_rate_deg_s: NonNegativeFloat = 0.0
    ship_acceleration_m_s2: NonNegativeFloat = 0.0
    ship_angular_acceleration_deg_s2: NonNegativeFloat = 0.0


class Control(_Model):
    """Closed-loop computed-torque gains: a critically damped second-order error by default."""

    bandwidth_hz: PositiveFloat = 5.0
    damping_ratio: PositiveFloat = 1.0


class Simulation(_Model):
    """The virtual prototype: which plant, its cables, the controller's gains and sensors."""

    plant: Literal["mujoco", "own"] = "mujoco"
    """mujoco: the independent physics engine; own: this package's forward dynamics (RK4)."""
    integrator: Literal["RK4", "Euler", "implicitfast"] = "RK4"
    """MuJoCo's integrator (the own plant always uses RK4)."""
    cables: CableModel = CableModel()
    noise: Noise = Noise()
    control: Control = Control()
    initial_error_m: Vec3 = (0.0, 0.0, 0.0)
    """Platform position error at t = 0 (actual minus planned), in C, m."""
    initial_error_deg: Vec3 = (0.0, 0.0, 0.0)
    """Platform orientation error at t = 0 (rx, ry, rz), deg."""
    max_error_m: PositiveFloat | None = None
    """A run whose position or cable-length error passes this is flagged; default 1% of
    the frame's largest extent."""
    max_error_deg: PositiveFloat = 1.0
    """A run whose orientation error passes this is flagged, deg."""


class Environment(_Model):
    gravity_m_s2: PositiveFloat = 9.8
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
        """A validated copy with top-level sections replaced, e.g. ``planning={...}``."""
        data = self.model_dump(exclude_none=True)
        for key, value in sections.items():
            data[key] = value.model_dump(exclude_none=True) if isinstance(value, BaseModel) else value
        return Scenario.model_validate(data)


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
        try:
            text = path.read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError) as exc:
            raise ScenarioError(f"cannot read the file ({exc})", source=source) from None
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
    base_dir = path.parent if path.is_file() else Path.cwd()
    return scenario_from_dict(data, source=source, base_dir=base_dir)


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
    try:
        return Scenario.model_validate(data, context={"base_dir": base_dir or Path.cwd()})
    except ValidationError as exc:
        raise _to_scenario_error(exc, data, source) from None


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
