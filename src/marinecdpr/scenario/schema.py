"""The scenario's sections other than the robot, and the scenario itself."""

from __future__ import annotations

import math
from typing import Annotated, Any, Literal, Union

from pydantic import (
    BaseModel,
    Field,
    StrictStr,
    ValidationError,
    ValidationInfo,
    field_validator,
    model_validator,
)

from marinecdpr.scenario.carriage import Carriage
from marinecdpr.scenario.cleaning import Cleaning, CoverageTrajectory
from marinecdpr.scenario.faults import MAX_FAULTS, Fault
from marinecdpr.scenario.fields import (
    MOVE_MIN_S, POSITION_MAX_M, TIME_MAX_S, Force, HullBeam, HullDraught, HullLength, Moment, Orientation, Phase,
    Position, TimeOfDay, _KeyedError, _Model, _num, _range_text, _ranged, _ranged_vec3, _resolve_file,
)
from marinecdpr.scenario.messages import scenario_error
from marinecdpr.scenario.obstacles import MAX_OBSTACLES, Obstacle
from marinecdpr.scenario.robot import Robot
from marinecdpr.scenario.wind import Wind, sea_wind
# ---------------------------------------------------------------------- ship, sea
class Ship(_Model):
    """Where the robot stands on the ship."""

    frame_origin_m: Position = (0.0, 0.0, 0.0)
    """Origin of the robot frame C in the ship frame S, m."""
    frame_orientation_deg: Orientation = (0.0, 0.0, 0.0)
    """C's axes in S: roll, pitch and yaw as the ship's own angles (R_SC = Rz Ry Rx), deg
    (a frame leaning with a flared side, turned with the hull's curve; default S's axes). With a
    carriage, C's axes at the rail's start: they turn with the rail's heading from there."""
    carriage: Carriage | None = None
    """A rail that carries the frame along the ship (:mod:`marinecdpr.scenario.carriage`); none:
    the frame stands at ``frame_origin_m``."""

    @model_validator(mode="after")
    def _check_carriage(self) -> "Ship":
        if self.carriage is not None and any(v != 0.0 for v in self.frame_origin_m):
            raise _KeyedError("frame_origin_m", "the carriage carries C's origin along ship.carriage.rail_m: "
                                                "leave frame_origin_m out (or at [0, 0, 0])")
        return self

    @property
    def turned(self) -> bool:
        """C's axes are not S's."""
        return any(v != 0.0 for v in self.frame_orientation_deg)


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


class RAOSource(_Model):
    """Where the ship's response amplitude operators come from."""

    source: Literal["box_hull", "csv", "capytaine"] = "box_hull"
    file: StrictStr | None = None
    """csv or capytaine: the file (relative paths from the scenario's folder)."""
    length_m: HullLength | None = None
    beam_m: HullBeam | None = None
    draught_m: HullDraught | None = None
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
    Union[CircleTrajectory, WaypointsTrajectory, LineTrajectory, CoverageTrajectory], Field(discriminator="type")
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

    model: Literal["ideal", "elastic", "catenary"] = "ideal"
    """ideal: the commanded tension acts (as in the paper). elastic: a straight cable on a
    winch. catenary: an elastic cable that sags under its weight (``robot.cable_weight_N_m``;
    Irvine's elastic catenary, pulling along its tangent), on a length-controlled winch
    that pays out the sag the plan computes, or on a motor winch whose drum carries the
    catenary's tension at the winch end; own plant only."""
    stiffness_EA_N: _ranged(1.0, 1e10, "N", "from a rubber cord to a 25 cm steel rope") | None = None
    """Axial stiffness E A of an elastic cable, N: tension = E A (L - L0) / L0 + damping."""
    damping_N_s_m: _ranged(0.0, 1e9, "N s/m", "beyond critical for the stiffest cable") = 0.0
    """Axial damping of an elastic cable, N per (m/s) of stretch rate."""
    winch: Literal["length", "tension", "motor"] = "length"
    """length: the winch pays out a commanded unstretched length L0; tension: it tracks a
    commanded tension (with its tension sensor); motor: a tension loop through the motor's
    dynamics, limits, inertia and friction (``[robot.winch]``; elastic or catenary cables),
    the drum paying out what the motor turns."""
    winch_time_constant_s: _ranged(0.0, 60.0, "s", "a winch that lags a minute holds nothing") = 0.0
    """First-order lag of the winch on its command (0: none)."""

    @model_validator(mode="after")
    def _check_stiffness(self) -> "CableModel":
        if self.model != "ideal" and self.stiffness_EA_N is None:
            kind = "an elastic" if self.model == "elastic" else "a catenary"
            raise _KeyedError("stiffness_EA_N", f"missing: {kind} cable needs its axial stiffness")
        if self.model == "catenary" and self.winch == "tension":
            raise _KeyedError("winch", "must be \"length\" or \"motor\" for catenary cables: the winch pays "
                                       "out the length the sag takes")
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
    motor_torque_N_m: _noise(1e6, "N m") = 0.0
    """On each motor winch's torque as its drive's current measures it, N m at the motor
    (motor winches, closed loop): what the controller's current watch reads, not what acts."""


MRU_UNITS = {
    # data sheets (shared/cleaning/FACTS.md): samples per second, roll/pitch and heave noise
    # (one standard deviation); the heading and the horizontal positions are not a unit's
    "ideal": (None, 0.0, 0.0),
    "kongsberg_mru5": (200.0, 0.02, 0.05),  # roll/pitch 0.01-0.02 deg, heave 5 cm, up to 200 Hz
    "xsens_mti300": (100.0, 0.2, 0.0),  # roll/pitch 0.2 deg RMS; rate: an MRU's usual 100 Hz
}
"""Motion reference units with their data sheet's figures: (rate_hz or None for one sample
every exchange, roll and pitch noise in deg, heave noise in m)."""


class Mru(_Model):
    """The motion reference unit that tells the controller the ship's motion (eta, eta',
    eta'') in samples that arrive late; and how the controller brings them to the present."""

    unit: Literal[tuple(MRU_UNITS)] = "ideal"
    """A unit whose data-sheet rate and noise apply (added to ``[simulation.noise]``'s ship
    noise); ideal: a noiseless sample every exchange."""
    rate_hz: _ranged(0.1, 1e5, "Hz", "from a sample every 10 s to far beyond any exchange", above=True) | None = None
    """Samples per second (default: the unit's)."""
    latency_s: _ranged(0.0, 5.0, "s", "a ship's motion older than seconds is another motion") = 0.0
    """How long a sample takes to reach the controller, s."""
    noise_m: _ranged_vec3(30.0, "m", "a sensor's standard deviation", ("surge", "sway", "heave")) | None = None
    """White noise on each sampled translation, one standard deviation (default: the unit's
    heave noise; added to ``[simulation.noise] ship_position_m``), m."""
    noise_deg: _ranged_vec3(30.0, "deg", "a sensor's standard deviation", ("roll", "pitch", "yaw")) | None = None
    """The same for each angle (default: the unit's roll and pitch noise), deg."""
    bias_m: _ranged_vec3(10.0, "m", "a bias, not a position", ("surge", "sway", "heave")) = (0.0, 0.0, 0.0)
    bias_deg: _ranged_vec3(30.0, "deg", "a bias, not an attitude", ("roll", "pitch", "yaw")) = (0.0, 0.0, 0.0)
    prediction: Literal["kinematic", "none", "ar"] = "kinematic"
    """How the controller brings the last sample to mid-step: kinematic, eta + dt eta'
    (and eta' + dt eta''); none, the sample as if it were now; ar, an autoregressive model
    of the sea fitted online (:mod:`marinecdpr.motion.prediction`)."""
    ar_step_s: _ranged(0.01, 5.0, "s", "ship motion has periods of seconds", above=True) = 0.25
    """The autoregressive model's time step, s (order x step: the history it spans)."""
    ar_order: Annotated[int, Field(ge=2, le=64, strict=True)] = 20
    """Its order: at least twice the spectral lines it follows."""
    ar_forgetting: _ranged(0.9, 1.0, "", "the fit's memory, 1 / (1 - lambda) AR steps", above=True) = 0.998
    ar_warmup_s: _ranged(0.0, 3600.0, "s", "an hour of sea is plenty") = 10.0
    """How long the model fits before it predicts (the kinematic extrapolation until then), s."""

    @model_validator(mode="after")
    def _check_noise(self) -> "Mru":
        for key, names in (("noise_m", ("surge", "sway", "heave")), ("noise_deg", ("roll", "pitch", "yaw"))):
            for name, value in zip(names, getattr(self, key) or ()):
                if value < 0:
                    raise _KeyedError(key, f"each entry must be >= 0 (a standard deviation), got {name} = {value:g}")
        return self


class Sensors(_Model):
    """Where the controller's pose comes from, and the winches' encoders and load cells."""

    pose_from: Literal["sensor", "encoders"] = "sensor"
    """sensor: a pose sensor (with ``[simulation.noise]``'s pose noise); encoders: forward
    kinematics from the winches' encoder lengths, stretched by the measured tensions, and
    the twist from their rates."""
    encoder_resolution_m: _ranged(0.0, 0.1, "m", "an encoder's step, not a cable length") = 0.0
    """The encoders' length step (0: exact)."""
    load_cell_filter_hz: _ranged(0.0, 1e4, "Hz", "beyond any exchange") = 0.0
    """A first-order low-pass on the load cells' tensions (0: none)."""


class Camera(_Model):
    """A camera's estimate of the platform's position (``[simulation.camera]``; closed loop):
    the true position as it was ``latency_s`` ago with noise, brought to now by the
    measured velocity, and fused with the pose sensor's: the controller sees
    (1 - weight) x_sensor + weight x_camera."""

    latency_s: _ranged(0.0, 1.0, "s", "a camera's processing time, not a second or more") = 0.05
    """How old the camera's estimate is when it reaches the controller."""
    noise_m: _ranged(0.0, 1.0, "m", "an estimate's error, not a distance") = 0.001
    """The standard deviation of its position error, per axis."""
    weight: _ranged(0.0, 1.0, "", "the camera's share of the fused position") = 0.5
    """The camera's share of the fused position (0: the pose sensor's alone; 1: the camera's)."""
    seed: int = 1
    """Seed of the camera's noise (its own stream: the other sensors' noise is unchanged)."""


class Safety(_Model):
    """What the closed-loop controller watches for in its own measurements, and how it reacts
    (``[simulation.control.safety]``; :mod:`marinecdpr.control.step`). Each detection names the
    step, its kind and the cable or sensor; with ``detect = false``, or no fault, a run is
    what it was without them."""

    detect: bool = True
    """Watch the measurements (closed loop only)."""
    slack_fraction: _ranged(0.0, 1.0, "", "a share of the commanded tension", above=True) = 0.25
    """A cable is slack or broken where its load cell reads below this share of the tension
    last commanded for it ..."""
    slack_delay_s: _ranged(0.0, 10.0, "s", "a detection's delay, not a minute") = 0.02
    """... for this long, s."""
    jump_m: _ranged(0.0, 10.0, "m", "a sensor's step, not a distance across the frame", above=True) = 0.05
    """A pose sensor's position (or an encoder's length) that moves in one exchange by this
    much more than the plan's velocity moves it has jumped, m."""
    frozen_m: _ranged(0.0, 10.0, "m", "a motion along the plan", above=True) = 0.02
    """A pose sensor's position (or an encoder's length) that reads the same while the plan
    has moved by this much is frozen, m."""
    disagree_m: _ranged(0.0, 10.0, "m", "a length error, not a cable", above=True) = 0.05
    """With a pose sensor, a cable whose encoder length (stretched by its load cell's tension)
    differs from its length at the measured pose by this much ..."""
    disagree_delay_s: _ranged(0.0, 10.0, "s", "a detection's delay, not a minute") = 0.02
    """... for this long: the encoders and the pose sensor disagree, s."""
    mru_timeout_s: _ranged(0.0, 60.0, "s", "a sample's age, not a sea's period", above=True) = 0.5
    """The motion reference unit has dropped out when its last sample is older than this, s."""
    current_fraction: _ranged(0.0, 1.0, "", "a share of the motor's torque limit", above=True) = 0.2
    """Motor winches: a motor whose torque (from its drive's current) differs from its drive's
    demand by this share of its torque limit ..."""
    current_delay_s: _ranged(0.0, 10.0, "s", "a detection's delay, not a minute") = 0.02
    """... for this long has failed (stalled, or without power): its cable is lost to the
    controller (``on_cable_loss``), the others holding its measured pull besides the wrench, s."""
    on_cable_loss: Literal["go_on", "park"] = "go_on"
    """Where the remaining cables still hold the wrench within their limits: go on along the
    plan with the lost cable's tension redistributed (go_on), or hold the pose where the loss
    was detected (park). Where they cannot, the controller stops (a wrench opposing the motion,
    to rest) and, where even that has no tensions within limits, commands the brakes."""
    stop_damping_hz: _ranged(1e-3, 1000.0, "Hz", "from a drifting stop to beyond any winch") = 2.0
    """The stop's deceleration: a = -2 pi f v on the platform's velocity."""
    brake_delay_s: _ranged(0.0, 60.0, "s", "a brake that takes a minute holds nothing") = 0.2
    """The winches' brakes hold their drums this long after the controller commands them
    (its last resort), s: on length-controlled and motor winches (ideal cables have no
    drum to hold: there the brakes' command changes nothing but the tensions it asks for)."""


class Control(_Model):
    """Closed-loop computed-torque gains: a critically damped second-order error by default."""

    bandwidth_hz: _ranged(1e-3, 1000.0, "Hz", "from a drifting loop to beyond any winch") = 5.0
    damping_ratio: _ranged(0.01, 10.0, "", "from barely damped to heavily overdamped") = 1.0
    safety: Safety = Safety()
    """Fault detection and reaction (``[simulation.control.safety]``)."""


class Simulation(_Model):
    """The virtual prototype: which plant, its cables, the controller's gains and sensors."""

    plant: Literal["mujoco", "own"] = "mujoco"
    """mujoco: the independent physics engine; own: this package's forward dynamics (RK4)."""
    integrator: Literal["RK4", "Euler", "implicitfast"] = "RK4"
    """MuJoCo's integrator (the own plant always uses RK4)."""
    cables: CableModel = CableModel()
    noise: Noise = Noise()
    control: Control = Control()
    sensors: Sensors = Sensors()
    mru: Mru = Mru()
    camera: Camera | None = None
    """A camera's position estimate fused with the pose sensor's (none by default)."""
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
    max_bypassed_share: _ranged(0.0, 1.0, "", "a share of the run's steps") = 0.01
    """A closed loop whose controller was bypassed (its feedback's tensions outside the
    limits, the plan's fed forward instead) on more than this share of its steps is a
    failed run: it shows the plan, not the controller."""


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
    cleaning: Cleaning | None = None
    obstacles: list[Obstacle] = Field(default=[], max_length=MAX_OBSTACLES)
    """What the cables must keep ``robot.clearance_m`` from, fixed to the frame, in C."""
    wind: Wind | None = None
    """The wind on the platform and the cables (:mod:`marinecdpr.scenario.wind`); none: no wind."""
    faults: list[Fault] = Field(default=[], max_length=MAX_FAULTS)
    """What fails during a run, and when (:mod:`marinecdpr.scenario.faults`); none by default."""

    @model_validator(mode="after")
    def _check_obstacles(self) -> "Scenario":
        if self.obstacles and self.robot.clearance_m is None:
            raise _KeyedError("robot.clearance_m", "missing: [[obstacles]] are checked against the cables at "
                                                   "this clearance (0 to flag contact only)")
        return self

    @model_validator(mode="after")
    def _wind_with_sea(self) -> "Scenario":
        """A wind that follows the sea state (``wind.with_sea``) takes its speed and direction
        from the scenario's own ``[base_motion]`` (:func:`~marinecdpr.scenario.wind.sea_wind`)."""
        wind = self.wind
        if wind is None or wind.with_sea == "none":
            return self
        sea = self.base_motion
        if not isinstance(sea, SeaStateMotion):
            raise _KeyedError("wind.with_sea", f"a wind that follows the sea state needs a [base_motion] of type "
                                               f"\"sea_state\" (its Hs and heading), got \"{sea.type}\"")
        speed, direction = sea_wind(wind, hs_m=sea.hs_m, heading_deg=sea.heading_deg,
                                    gravity_m_s2=self.environment.gravity_m_s2)
        object.__setattr__(self, "wind", wind.model_copy(update={"speed_m_s": speed, "direction_deg": direction}))
        return self

    @model_validator(mode="after")
    def _check_motor_noise(self) -> "Scenario":
        noise = self.simulation.noise.motor_torque_N_m
        if noise == 0.0:
            return self
        if self.simulation.cables.winch != "motor":
            raise _KeyedError("simulation.noise.motor_torque_N_m", "is the noise on a motor's measured torque: it "
                                                                   "needs motor winches (simulation.cables.winch = "
                                                                   f"\"motor\"), got {_num(noise)} N m")
        limit = None if self.robot.winch is None else self.robot.winch.torque_max_Nm  # its absence: said elsewhere
        if limit is not None and noise >= limit:
            raise _KeyedError("simulation.noise.motor_torque_N_m", f"must be below the motor's torque limit "
                                                                   f"(robot.winch.torque_max_Nm = {_num(limit)} N m): "
                                                                   f"a sensor's standard deviation, not what it "
                                                                   f"measures, got {_num(noise)} N m")
        return self

    @model_validator(mode="after")
    def _check_faults(self) -> "Scenario":
        m, end = self.robot.n_cables, self.time.duration_s
        snapped: set[int] = set()
        on_winch: set[int] = set()
        failing: set[int] = set()
        for i, fault in enumerate(self.faults, start=1):
            if fault.cable is not None and fault.cable > m:
                raise _KeyedError(f"faults[{i}].cable", f"the robot has {m} cables (counted from 1), got {fault.cable}")
            if fault.at_s > end:
                raise _KeyedError(f"faults[{i}].at_s", f"{_num(fault.at_s)} s is beyond the run's end "
                                                      f"(time.duration_s = {_num(end)} s)")
            if fault.kind == "cable_snap":
                if fault.cable in snapped:
                    raise _KeyedError(f"faults[{i}].cable", f"cable {fault.cable} snaps once: it is listed "
                                                            "twice")
                snapped.add(fault.cable)
                continue
            if fault.kind == "brush_contact_loss" and self.cleaning is None:
                raise _KeyedError(f"faults[{i}].kind", "a brush_contact_loss needs a brush: the scenario has no "
                                                       "[cleaning]")
            if fault.kind in ("load_cell", "encoder", "mru", "brush_contact_loss", "controller_deadline"):
                continue
            cab = self.simulation.cables
            if fault.kind in ("motor_power_loss", "winch_stall") and cab.winch != "motor":
                raise _KeyedError(f"faults[{i}].kind", f"a {fault.kind} needs motor winches "
                                                       "(simulation.cables.winch = \"motor\")")
            if cab.model == "ideal" or cab.winch == "tension":
                raise _KeyedError(f"faults[{i}].kind", f"a {fault.kind} needs a winch that pays out the cable: "
                                                       "elastic or catenary cables (simulation.cables.model) on "
                                                       "a length-controlled or motor winch")
            if fault.kind == "brake_failure":  # beside the winch's other fault, if any: one a winch
                delay = self.simulation.control.safety.brake_delay_s
                if fault.secondary_delay_s is not None and fault.secondary_delay_s < delay:
                    raise _KeyedError(f"faults[{i}].secondary_delay_s",
                                      f"{fault.secondary_delay_s:g} s is before the primary brake's "
                                      f"simulation.control.safety.brake_delay_s ({delay:g} s): the secondary holds "
                                      "when the primary has failed")
                if fault.cable in failing:
                    raise _KeyedError(f"faults[{i}].cable", f"winch {fault.cable}'s primary brake fails once: it "
                                                            "is listed twice")
                failing.add(fault.cable)
                continue
            if fault.cable in on_winch:
                raise _KeyedError(f"faults[{i}].cable", f"winch {fault.cable} has one fault: it is listed twice")
            on_winch.add(fault.cable)
        return self

    @model_validator(mode="after")
    def _check_cleaning(self) -> "Scenario":
        if isinstance(self.trajectory, CoverageTrajectory) and self.cleaning is None:
            raise _KeyedError("cleaning", "missing: a coverage trajectory cleans the [cleaning] section's panel")
        if self.cleaning is None:
            return self
        if isinstance(self.trajectory, CoverageTrajectory) and self.trajectory.on_hull:
            if self.ship.carriage is None:
                raise _KeyedError("trajectory.on_hull", "needs [ship.carriage]: the path is held on the ship while "
                                                        "the carriage carries the frame")
            return self  # the panel lies on the ship, the platform's path in C is checked against the frame
        frame = self.robot.frame_anchors[:, [0, 2]]
        lo, hi = frame.min(axis=0), frame.max(axis=0)
        tol = 1e-9 * max(1.0, float(abs(frame).max()))
        for i, (x, z) in enumerate(self.cleaning.panel_m, start=1):
            if not (lo[0] - tol <= x <= hi[0] + tol and lo[1] - tol <= z <= hi[1] + tol):
                raise _KeyedError(f"cleaning.panel_m[{i}]",
                                  f"[{_num(x)}, {_num(z)}] m is outside the frame: its anchors span x in "
                                  f"[{_num(float(lo[0]))}, {_num(float(hi[0]))}] and z in "
                                  f"[{_num(float(lo[1]))}, {_num(float(hi[1]))}] m")
        return self

    @model_validator(mode="after")
    def _check_camera(self) -> "Scenario":
        sim = self.simulation
        if sim.camera is not None and sim.sensors.pose_from == "encoders":
            raise _KeyedError("simulation.camera", "fuses with a pose sensor's position: with "
                                                   "simulation.sensors.pose_from = \"encoders\" use \"sensor\" or "
                                                   "remove [simulation.camera]")
        return self

    @model_validator(mode="after")
    def _check_catenary(self) -> "Scenario":
        sim = self.simulation
        if sim.cables.model != "catenary":
            return self
        if self.robot.cable_weight_N_m == 0.0:
            raise _KeyedError("robot.cable_weight_N_m", "missing: catenary cables (simulation.cables.model = "
                                                        "\"catenary\") sag under their weight per metre")
        if sim.plant != "own":
            raise _KeyedError("simulation.plant", "must be \"own\" for catenary cables: MuJoCo's tendons are "
                                                  "straight")
        if self.robot.has_pulleys:
            raise _KeyedError("simulation.cables.model", "catenary cables over pulleys are not supported yet: "
                                                         "use \"elastic\" (the sag is then in the error budget)")
        if sim.sensors.pose_from == "encoders":
            raise _KeyedError("simulation.sensors.pose_from", "the encoders' pose with catenary cables is not "
                                                              "supported yet (their forward kinematics knows "
                                                              "straight cables): use \"sensor\"")
        return self

    @model_validator(mode="after")
    def _check_motor(self) -> "Scenario":
        cab = self.simulation.cables
        if cab.winch != "motor":
            return self
        if self.robot.winch is None:
            raise _KeyedError("robot.winch", "missing: motor winches (simulation.cables.winch = \"motor\") "
                                             "need the winches' design")
        if cab.model == "ideal":
            raise _KeyedError("simulation.cables.model", "must be \"elastic\" or \"catenary\" for motor winches: "
                                                         "the tension is the cable's stretch (and sag) over what "
                                                         "the drum pays out")
        w = self.robot.winch
        if w.rotor_inertia_kg_m2 + w.drum_inertia_kg_m2 <= 0.0:
            raise _KeyedError("robot.winch.rotor_inertia_kg_m2", "must be > 0 (or drum_inertia_kg_m2) for motor "
                                                                 "winches: a motor without inertia has no dynamics")
        return self

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
        if isinstance(traj, CoverageTrajectory):
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
        return validated_scenario(data)

    def with_updates(self, section: str, **values: Any) -> "Scenario":
        """A validated copy with some keys of one section or sub-section changed, the others
        kept, e.g. ``with_updates("simulation.mru", latency_s=0.02)``; a value of None removes
        the key (its default applies). A missing optional section starts empty.

        Raises
        ------
        ScenarioError
            One line naming the key, as for a file.
        """
        data = self.model_dump(exclude_none=True)
        node = data
        for key in section.split("."):
            node = node.setdefault(key, {})
        for key, value in values.items():
            if value is None:
                node.pop(key, None)
            else:
                node[key] = value.model_dump(exclude_none=True) if isinstance(value, BaseModel) else value
        return validated_scenario(data)


def validated_scenario(data: dict) -> Scenario:
    """A :class:`Scenario` from nested dicts (as ``model_dump`` writes them), without a
    source's base folder: file paths are taken as they stand.

    Raises
    ------
    ScenarioError
        One line naming the key (:func:`~marinecdpr.scenario.messages.scenario_error`).
    """
    try:
        return Scenario.model_validate(data)
    except ValidationError as exc:
        raise scenario_error(exc, data, None, Scenario) from None


