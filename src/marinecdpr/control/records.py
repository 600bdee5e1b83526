"""The controller's records: what it knows (its model of the robot, the plan it tracks, its
gains), what it is told each exchange (:class:`Measurement`) and what it answers
(:class:`Command`), and its working memory.

Every record is a ``NamedTuple`` of numpy arrays and numbers, so a compiled step takes it
as one typed argument and writes into it without allocating; a record's scalars that
change at run time live in small arrays. Vectors are in the robot frame C unless named
otherwise; units are SI (m, rad, N, s); ``m`` is the number of cables, ``k`` the number of
controlled DOFs, ``n_steps`` the plan's length.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from marinecdpr.geometry.forward import ForwardWork, forward_work
from marinecdpr.model.tension_solver import TensionWork, tension_work

__all__ = ["Reference", "RobotModel", "Gains", "Loads", "Measurement", "Command", "Work", "Safety", "ControllerParts",
           "Slot", "Encoders", "empty_measurement", "empty_command", "empty_work", "empty_safety", "empty_slot",
           "encoders_record", "POSE_SENSOR", "ENCODERS", "PREDICTIONS", "SENSORS", "KINDS", "MODES", "RESIDUALS",
           "MAX_EVENTS"]

POSE_SENSOR = 0
"""``Gains.pose_from``: the platform's pose and twist come from a pose sensor."""
ENCODERS = 1
"""``Gains.pose_from``: the pose comes from the winches' encoder lengths (forward kinematics,
with the stretch the measured tensions cause) and the twist from their rates."""
PREDICTIONS = {"none": 0, "kinematic": 1, "ar": 2}
"""``Gains.prediction``: how the ship's last sample is brought to mid-step: as it is, by
eta + dt eta', or by the autoregressive predictor (:mod:`marinecdpr.motion.prediction`)."""


class Reference(NamedTuple):
    """The plan at mid-step, t_k + h/2: what the controller tracks and feeds forward.

    x, v, a : (n_steps, 3) position, velocity, acceleration of P relative to C, in C.
    R : (n_steps, 3, 3) R_PC. w, al : (n_steps, 3) angular velocity and acceleration in C.
    T, L, Ldot : (n_steps, m) planned tensions (N), cable lengths (m) and their rates (m/s).
    sag : (n_steps, m) the extra unstretched length a heavy cable's sag takes at the planned
    tension (:attr:`~marinecdpr.planning.planner.CableSag.lengths`; zeros for weightless cables), m.
    """

    x: np.ndarray
    R: np.ndarray
    v: np.ndarray
    w: np.ndarray
    a: np.ndarray
    al: np.ndarray
    T: np.ndarray
    L: np.ndarray
    Ldot: np.ndarray
    sag: np.ndarray


class RobotModel(NamedTuple):
    """The controller's model of the robot (the scenario's robot, ship layout and cables).

    c_C : (m, 3) frame anchors in C. p_P : (m, 3) platform anchors in P. mass : kg.
    I_PP : (3, 3) inertia about the centre of mass in P. g : gravity, m/s^2 (> 0).
    origin : (3,) C's origin in S. controlled : (k,) int indices of the controlled DOFs.
    lo, hi : (m,) tension limits, N. method : a ``tension_solver.METHOD_CODES`` value.
    EA : the cables' axial stiffness, N (inf: inextensible). damping : N s/m.
    pulleys : any cable leaves over a pulley; z_C (m, 3) their swivel axes in C and radius
    (m,) their radii, m (0: a point); exits (m, 3) and wraps (m,): scratch for the exit
    points and wrap angles.
    """

    c_C: np.ndarray
    p_P: np.ndarray
    mass: float
    I_PP: np.ndarray
    g: float
    origin: np.ndarray
    controlled: np.ndarray
    lo: np.ndarray
    hi: np.ndarray
    method: int
    EA: float
    damping: float
    pulleys: bool
    z_C: np.ndarray
    radius: np.ndarray
    exits: np.ndarray
    wraps: np.ndarray


class Gains(NamedTuple):
    """Computed torque on the measured pose error, then the tension method.

    closed : False feeds the plan's tensions forward (open loop).
    kp, kd : gains, 1/s^2 and 1/s. lead_s : the winches' time constant the controller leads
    its commands by (0: none), s. tension_winches : the winches hold tensions (else lengths).
    pose_from : :data:`POSE_SENSOR` or :data:`ENCODERS`. prediction : a :data:`PREDICTIONS`
    value. fk_tol_m, fk_iter : the forward kinematics' step tolerance (m) and iterations.
    """

    closed: bool
    kp: float
    kd: float
    lead_s: float
    tension_winches: bool
    pose_from: int
    prediction: int
    fk_tol_m: float
    fk_iter: int


class Loads(NamedTuple):
    """The known disturbance on the platform: f, m (n_steps, 3) at t_k (what the controller
    and the MuJoCo ship drive read), or (2 n + 1, 3) on the half-step grid (what the own plant
    reads), N and N m; in C, or in P (turned with the platform's orientation) if ``in_P``."""

    f: np.ndarray
    m: np.ndarray
    in_P: bool


class Measurement(NamedTuple):
    """One exchange's measurements, written by the caller (or the prototype's sensors).

    x, v, w : (3,) the platform's position (m), velocity (m/s) and angular velocity (rad/s),
    in C; R : (3, 3) R_PC (with a pose sensor). L, Ldot : (m,) cable lengths (m) and their
    rates (m/s) from the winches' encoders; T : (m,) measured tensions, N. eta : (3, 6) the
    motion reference unit's latest sample: the ship's eta, eta' and eta'' (m, rad).
    clock : (3,) the exchange's time t_k, the pose's time stamp and the ship sample's, s.
    tau, tau_set : (m,) motor winches' torques from their drives' currents and the drives'
    torque demands (after the drives' own torque, power and speed limits), motor side, N m,
    as of the last exchange; zeros where there is no motor.
    """

    x: np.ndarray
    R: np.ndarray
    v: np.ndarray
    w: np.ndarray
    L: np.ndarray
    Ldot: np.ndarray
    T: np.ndarray
    eta: np.ndarray
    clock: np.ndarray
    tau: np.ndarray
    tau_set: np.ndarray


class Command(NamedTuple):
    """What the controller answers.

    T_cmd : (m,) tensions for tension-controlled winches, N. L0_cmd : (m,) unstretched lengths
    for length-controlled winches, m. at_limit : (m,) int, -1 at the lower tension limit,
    +1 at the upper, 0 within. flags : (3,) int: 1 if the tension problem had no solution
    within limits (the plan's tensions were commanded), the number of cables at a limit,
    1 if the pose from the encoders did not converge. brake : (m,) int, 1 where the
    controller asks a winch's brake to engage (its last resort, :class:`Safety`), else 0.
    """

    T_cmd: np.ndarray
    L0_cmd: np.ndarray
    at_limit: np.ndarray
    flags: np.ndarray
    brake: np.ndarray


class Work(NamedTuple):
    """The step's working memory, allocated once (:func:`empty_work`) so that no step
    allocates: the estimated state (x, v, w (3,), R (3, 3)), the ship's (R_SO (3, 3), w_s,
    al_s (3,)), the commanded accelerations, the wrench and its parts, the cables at the
    estimated pose (L (m,), J (m, 6)) and the tension solver's memory."""

    x: np.ndarray
    R: np.ndarray
    v: np.ndarray
    w: np.ndarray
    R_SO: np.ndarray
    w_s: np.ndarray
    al_s: np.ndarray
    eta: np.ndarray  # (2, 6) the ship's eta and eta' predicted to mid-step
    a_cmd: np.ndarray  # (2, 3) commanded a and alpha
    m3: np.ndarray  # (3, 3, 3) scratch matrices
    v3: np.ndarray  # (4, 3) scratch vectors: zeros, angles, loads f and m
    wrench: np.ndarray  # (6,)
    wrench_parts: np.ndarray  # (5, 6)
    L: np.ndarray
    J: np.ndarray
    tension: TensionWork
    forecast: np.ndarray  # (3, 6) the ship's motion at mid-step, predicted
    q: np.ndarray  # (6,) the pose from the encoders (x, y, z, rx, ry, rz), the next warm start
    qdot: np.ndarray  # (6,) its rate
    Lg: np.ndarray  # (m,) the encoders' lengths stretched by the measured tensions
    E: np.ndarray  # (3, 3) angle rates to angular velocity
    Gk: np.ndarray  # (k, k) normal equations of the rates
    bk: np.ndarray  # (k,)


class ControllerParts(NamedTuple):
    """Everything a controller step reads and writes: the plan, the model, the gains, the
    known loads, this exchange's measurement and command, the working memory, and the fault
    detection's settings and memory."""

    ref: Reference
    model: RobotModel
    gains: Gains
    loads: Loads
    meas: Measurement
    cmd: Command
    work: Work
    predictor: Slot
    encoders: Slot
    safety: Safety


def empty_measurement(m: int) -> Measurement:
    """A zeroed measurement for m cables (R the identity)."""
    return Measurement(x=np.zeros(3), R=np.eye(3), v=np.zeros(3), w=np.zeros(3), L=np.zeros(m), Ldot=np.zeros(m),
                       T=np.zeros(m), eta=np.zeros((3, 6)), clock=np.zeros(3), tau=np.zeros(m), tau_set=np.zeros(m))


def empty_command(m: int) -> Command:
    return Command(T_cmd=np.zeros(m), L0_cmd=np.zeros(m), at_limit=np.zeros(m, dtype=np.int64),
                   flags=np.zeros(3, dtype=np.int64), brake=np.zeros(m, dtype=np.int64))


SENSORS = {"pose": 0, "load_cell": 1, "encoder": 2, "mru": 3}
"""A detection's sensor (the ``sensor`` column of :attr:`Safety.events`; -1: none, a cable)."""
KINDS = {"cable_slack": 1, "non_finite": 2, "frozen": 3, "jump": 4, "disagree": 5, "dropout": 6, "drive": 7}
"""A detection's kind (the ``kind`` column of :attr:`Safety.events`): a cable's load cell far
below its command for the stated time (slack or broken); a reading that is not a finite
number; a reading unchanged while the plan moved; a reading that moved far beyond what the plan
moves; the encoders and the pose sensor disagreeing on a cable's length for the stated time;
the motion reference unit's samples stopping; a motor winch's torque (from its current) far
from its drive's demand for the stated time (a stalled motor, or one without power)."""
MODES = {"normal": 0, "go_on": 1, "park": 2, "stop": 3, "brake": 4}
"""The controller's reaction (:attr:`Safety.mode`): nothing detected; a cable lost, its tension
redistributed on the plan; holding the pose where the fault was detected; a stop (a wrench
opposing the motion, to rest) where the remaining cables cannot hold the plan; the brakes,
where even the stop has no tensions within limits."""
RESIDUALS = ("slack", "jump", "frozen", "disagree", "mru_age", "current")
"""The watched residuals, each over its threshold (:attr:`Safety.peak`): a cable's 1 - T_meas /
T_cmd over 1 - ``slack_fraction``; a reading's move beyond the plan's over ``jump_m``; the
plan's move under an unchanged reading over ``frozen_m``; the encoders' and the pose
sensor's length difference over ``disagree_m``; the MRU sample's age over ``mru_timeout_s``; a
motor's torque less its drive's demand, over ``current_fraction`` of its torque limit."""
MAX_EVENTS = 16
"""The most detections a controller records (:attr:`Safety.events`)."""


class Safety(NamedTuple):
    """The controller's fault detection and reaction (``[simulation.control.safety]``): its
    settings, its memory, and what it detected.

    Settings: detect (bool); slack_fraction (-) and slack_steps (int): a cable's load cell
    below slack_fraction of its last command for slack_steps exchanges is a lost cable;
    jump_m, frozen_m, disagree_m (m) and disagree_steps (int); mru_timeout_s (s); park
    (bool): hold the pose after a cable loss even where the remaining cables hold the plan;
    stop_kd (1/s): the stop's a = -stop_kd v; current_fraction (-) and current_steps (int): a
    motor whose torque (from its current) differs from its drive's demand by more than
    current_fraction of its torque limit tau_max (m,), N m (0: no motor: not watched), for
    current_steps exchanges has failed.

    State (m cables): present (4,) int, 1 where the caller measures that sensor this exchange
    (:data:`SENSORS`; the prototype measures all four); count (3, m) int, the exchanges a
    cable's load cell has read low, its length has disagreed and its motor's torque has left its
    demand; lost (m,) int, 1 where a cable is lost; failed (m,) int, 1 where a winch's drive
    has failed; known (m,): the tension a lost cable still pulls with (a failed drive's, from
    its load cell; 0 for a broken one), N; bad (4,) int, 1 where a sensor is faulty; mode
    (1,) int, a :data:`MODES` value; since (1,) int, the step the reaction started; hold_x
    (3,), hold_R (3, 3): the pose the controller holds (park, stop), in C; last_x (3,), last_L
    (m,): the previous exchange's
    pose sensor's and encoders' readings; last_eta (3, 6): the MRU's last sound sample (what
    the reaction uses once the MRU is faulty; NaN before the first); moved_x (1,), moved_L (m,): how far the plan moved
    since each reading last changed, m; lo, hi (m,): the tension limits the step solves
    within (a lost cable's both 0), N; events (MAX_EVENTS, 4) int: each detection's step, kind
    (:data:`KINDS`), sensor (:data:`SENSORS`, -1 for a cable) and cable (-1 for none);
    n_events (1,) int; peak (len(RESIDUALS),): each watched residual's largest ratio to its
    threshold over the exchanges before the first detection (>= 1: it tripped).
    """

    detect: bool
    slack_fraction: float
    slack_steps: int
    jump_m: float
    frozen_m: float
    disagree_m: float
    disagree_steps: int
    mru_timeout_s: float
    park: bool
    stop_kd: float
    current_fraction: float
    current_steps: int
    tau_max: np.ndarray
    present: np.ndarray
    count: np.ndarray
    lost: np.ndarray
    failed: np.ndarray
    known: np.ndarray
    bad: np.ndarray
    mode: np.ndarray
    since: np.ndarray
    hold_x: np.ndarray
    hold_R: np.ndarray
    last_x: np.ndarray
    last_L: np.ndarray
    last_eta: np.ndarray
    moved_x: np.ndarray
    moved_L: np.ndarray
    lo: np.ndarray
    hi: np.ndarray
    events: np.ndarray
    n_events: np.ndarray
    peak: np.ndarray
    zero: np.ndarray  # (3,) zeros: the held pose's twist and acceleration
    Ls: np.ndarray  # (m,) scratch: the cables' lengths at the held pose
    Js: np.ndarray  # (m, 6) scratch


def empty_safety(m: int, lo: np.ndarray, hi: np.ndarray, *, detect: bool = False, slack_fraction: float = 0.25,
                 slack_steps: int = 20, jump_m: float = 0.05, frozen_m: float = 0.02, disagree_m: float = 0.05,
                 disagree_steps: int = 20, mru_timeout_s: float = 0.5, park: bool = False,
                 stop_kd: float = 4.0 * np.pi, current_fraction: float = 0.2, current_steps: int = 20,
                 tau_max=None) -> Safety:
    """A controller's safety record for m cables with tension limits lo, hi (m,), N, nothing
    detected yet, every sensor present; the motors' torque limits tau_max (m,), N m (default:
    none, zeros: no motor watched)."""
    return Safety(detect=bool(detect), slack_fraction=float(slack_fraction), slack_steps=int(slack_steps),
                  jump_m=float(jump_m), frozen_m=float(frozen_m), disagree_m=float(disagree_m),
                  disagree_steps=int(disagree_steps), mru_timeout_s=float(mru_timeout_s), park=bool(park),
                  stop_kd=float(stop_kd), current_fraction=float(current_fraction), current_steps=int(current_steps),
                  tau_max=np.zeros(m) if tau_max is None else np.array(np.broadcast_to(np.asarray(tau_max, dtype=float),
                                                                                         (m,))),
                  present=np.ones(4, dtype=np.int64), count=np.zeros((3, m), dtype=np.int64),
                  lost=np.zeros(m, dtype=np.int64), failed=np.zeros(m, dtype=np.int64), known=np.zeros(m),
                  bad=np.zeros(4, dtype=np.int64), mode=np.zeros(1, dtype=np.int64),
                  since=np.full(1, -1, dtype=np.int64), hold_x=np.zeros(3), hold_R=np.eye(3),
                  last_x=np.full(3, np.nan), last_L=np.full(m, np.nan), last_eta=np.full((3, 6), np.nan), moved_x=np.zeros(1), moved_L=np.zeros(m),
                  lo=np.array(lo, dtype=float), hi=np.array(hi, dtype=float),
                  events=np.full((MAX_EVENTS, 4), -1, dtype=np.int64), n_events=np.zeros(1, dtype=np.int64),
                  peak=np.zeros(len(RESIDUALS)), zero=np.zeros(3), Ls=np.zeros(m), Js=np.zeros((m, 6)))


class Slot(NamedTuple):
    """Code and data that only some controllers have (the ship-motion predictor, the
    encoders' forward kinematics), held by address so that the step's type, and so its
    compiled code, is the same for every controller: ``words`` (n,) int64, words[0] the
    address of a C function (0: none: the controller has no such thing), words[1:] the
    record it works on (:func:`~marinecdpr.borrowed.store`), whose arrays the words keep
    alive (:func:`~marinecdpr.borrowed.kept_words`). The function's code compiles where a
    controller first has it (:func:`~marinecdpr.control.controller.slot`)."""

    words: np.ndarray


class Encoders(NamedTuple):
    """What the encoders' forward kinematics reads and writes
    (:func:`~marinecdpr.control.step.pose_from_encoders`): the step's measurement, model and
    gains, its memory ``fk`` (:func:`~marinecdpr.geometry.forward.forward_work`), and the
    :class:`Work` arrays it shares with the step (Lg, q, qdot, E, Gk, bk, v3)."""

    meas: Measurement
    model: RobotModel
    gains: Gains
    fk: ForwardWork
    Lg: np.ndarray
    q: np.ndarray
    qdot: np.ndarray
    E: np.ndarray
    Gk: np.ndarray
    bk: np.ndarray
    v3: np.ndarray


def empty_work(m: int, k: int) -> Work:
    """The working memory of a step with m cables and k controlled DOFs."""
    return Work(x=np.empty(3), R=np.empty((3, 3)), v=np.empty(3), w=np.empty(3), R_SO=np.empty((3, 3)),
                w_s=np.empty(3), al_s=np.empty(3), eta=np.empty((2, 6)), a_cmd=np.empty((2, 3)),
                m3=np.empty((3, 3, 3)), v3=np.zeros((4, 3)), wrench=np.empty(6), wrench_parts=np.empty((5, 6)),
                L=np.empty(m), J=np.empty((m, 6)), tension=tension_work(m, k), forecast=np.zeros((3, 6)),
                q=np.zeros(6), qdot=np.zeros(6), Lg=np.empty(m), E=np.empty((3, 3)), Gk=np.empty((k, k)),
                bk=np.empty(k))


def encoders_record(meas: Measurement, model: RobotModel, gains: Gains, work: Work, *, fk_atol_m: float = 1e-4,
                    fk_rtol: float = 1e-4) -> Encoders:
    """The encoders' forward kinematics' record for a step of these records; lengths from the
    encoders are a pose's when its residuals are within fk_atol_m + fk_rtol L (m)."""
    m, k = work.L.shape[0], work.bk.shape[0]
    return Encoders(meas=meas, model=model, gains=gains, fk=forward_work(m, k, fk_atol_m, fk_rtol), Lg=work.Lg,
                    q=work.q, qdot=work.qdot, E=work.E, Gk=work.Gk, bk=work.bk, v3=work.v3)


def empty_slot() -> Slot:
    """The slot of a controller without the thing (no predictor, no encoders' kinematics)."""
    return Slot(words=np.zeros(1, dtype=np.int64))
