"""Tension planning: the scenario's trajectory on the moving ship, step by step as arrays.

:func:`plan` runs the whole chain for a scenario, over the whole time series at
once (in chunks that keep temporaries in cache and memory bounded):
ship motion -> platform motion -> cable kinematics -> required wrench ->
pseudo-inverse tensions (eq. 18) -> the chosen method's tensions.
:func:`iter_plan` yields the same results chunk by chunk, for records too long
to hold.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Iterator

import numpy as np

from marinecdpr.errors import ScenarioError
from marinecdpr.geometry.elastic import unstretched_length
from marinecdpr.geometry.kinematics import cable_kinematics
from marinecdpr.model.brush import cleaning_loads
from marinecdpr.model.dynamics import WrenchTerms, disturbance_in_C, uncontrolled, wrench_terms
from marinecdpr.model.wind import scenario_wind_loads
from marinecdpr.model.tension import (
    distribute_tensions, full_rank, largest_headroom, pseudo_inverse_tensions,
)
from marinecdpr.motion.basemotion import evaluate_base_motion, fixed_ship_motion, frame_origin_of, frame_ship_motion
from marinecdpr.motion.carriage import rail_of
from marinecdpr.motion.ship import ShipMotion
from marinecdpr.motion.trajectory import check_in_frame, evaluate_disturbance, evaluate_trajectory
from marinecdpr.scenario.robot import Robot, scaled_copy
from marinecdpr.planning.budget import ship_at_once
from marinecdpr.planning import verdicts
from marinecdpr.planning.interference import Clearances, clearances, describe_clearances, obstacle_labels
from marinecdpr.planning.verdicts import (  # also planner's public names, as before the words moved
    TWIST_NAMES, WINCH_NO_TENSION, WINCH_OVERSPEED, SingularPoses, describe_pose,
)
from marinecdpr.scenario.schema import Scenario

__all__ = ["Plan", "WinchBounds", "CableSag", "plan", "plan_at", "iter_plan", "ship_motion_at", "PlanSummary", "check_trajectory", "SingularPoses",
           "describe_pose", "DEFAULT_CHUNK_STEPS", "stand_in_plan", "trajectory_interference", "required_wrench", "twist_on_hull",
           "TWIST_NAMES", "WINCH_OVERSPEED", "WINCH_NO_TENSION"]

DEFAULT_CHUNK_STEPS = 16384


def _rows(a: np.ndarray, rows: slice) -> np.ndarray:
    return a[rows].copy()


@dataclass(frozen=True)
class WinchBounds:
    """What the winches (``robot.winch``) can do along a plan. Arrays shaped (n_steps, n_cables).

    Attributes
    ----------
    length_accelerations : ndarray
        The cables' L'', m/s^2.
    lower, upper : ndarray
        The tensions each winch can give at that step within the cable's limits, N (the
        tension method's bounds: :func:`~marinecdpr.model.winch.winch_tension_bounds`).
    limit : ndarray of int8
        0 the winch can give the planned tension; :data:`WINCH_OVERSPEED` the cable moves
        faster than the motor can turn; :data:`WINCH_NO_TENSION` no tension within the
        cable's limits is within the motor's torque and power at that motion. A step with
        either is infeasible.
    """

    length_accelerations: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    limit: np.ndarray

    def take(self, rows: slice) -> "WinchBounds":
        """The steps ``rows``, copied."""
        return WinchBounds(*(_rows(a, rows) for a in (self.length_accelerations, self.lower, self.upper, self.limit)))


@dataclass(frozen=True)
class CableSag:
    """Heavy cables (``robot.cable_weight_N_m`` > 0) along a plan: each free span an elastic
    catenary (:mod:`~marinecdpr.model.catenary`, EA of ``simulation.cables``, infinite for
    ideal cables) in the true vertical, carrying the planned tension at the platform. Arrays
    shaped (n_steps, n_cables); NaN where infeasible.

    Attributes
    ----------
    lengths : ndarray
        The extra unstretched length the winch pays out against a straight cable at that
        tension, m.
    winch_tensions : ndarray
        The tension at the winch end, N.
    """

    lengths: np.ndarray
    winch_tensions: np.ndarray

    def take(self, rows: slice) -> "CableSag":
        """The steps ``rows``, copied."""
        return CableSag(_rows(self.lengths, rows), _rows(self.winch_tensions, rows))


@dataclass(frozen=True)
class Plan:
    """A tension plan over a time series. Arrays share the first axis ``n_steps``.

    Attributes
    ----------
    t : ndarray, shape (n_steps,)
        s.
    pose : ndarray, shape (n_steps, 6)
        ``(x, y, z, rx, ry, rz)`` of P in C, m and rad.
    twist, twist_dot : ndarray, shape (n_steps, 6)
        (v_PC, omega_PC) in C and its derivative.
    lengths, length_rates : ndarray, shape (n_steps, n_cables)
        Cable lengths (m) and their rates (m/s).
    wrench : ndarray, shape (n_steps, 6)
        Required wrench w in C (eq. 15), N and N m.
    C_s, F_s : ndarray, shape (n_steps, 6)
        Ship-induced inertial terms and external interference (eqs. 15-16), in C.
    tensions_pinv : ndarray, shape (n_steps, n_cables)
        Pseudo-inverse tensions T_s (eq. 18), N; may be negative.
    tensions : ndarray, shape (n_steps, n_cables)
        The method's tensions, N; NaN where infeasible.
    feasible : ndarray of bool, shape (n_steps,)
    reaction : ndarray, shape (n_steps, 6 - k)
        Wrench the hull or guide supplies in the DOFs the cables do not control
        (``reaction_dofs``), in C; NaN where infeasible.
    reaction_dofs : tuple of str
        Names of the uncontrolled twist components, e.g. ("y", "rx", "rz").
    method, base_model : str
    robot : Robot, optional
        The robot planned for; with it, :meth:`infeasibility` names the cables at their
        limits.
    winch : WinchBounds, optional
        With winches (``robot.winch``): what they can do at each step. None without.
    sag : CableSag, optional
        With heavy cables (``robot.cable_weight_N_m`` > 0): the catenaries' extra lengths and
        winch-end tensions. None without.
    clearances : Clearances, optional
        With ``robot.clearance_m``: the cables' least distances to each other, to the
        platform's body and to each obstacle
        (:class:`~marinecdpr.planning.interference.Clearances`). None without.
    obstacle_labels : tuple of str
        How :meth:`interference` names the obstacles.
    tension_headroom : ndarray, shape (n_steps,), optional
        Asked for (:func:`iter_plan`'s ``headroom``): at each step the largest headroom to
        the robot's tension limits that any tensions producing the wrench could keep
        (:func:`~marinecdpr.model.tension.largest_headroom`), N, whatever the method's
        tensions; NaN at singular poses. None otherwise.
    """

    t: np.ndarray
    pose: np.ndarray
    twist: np.ndarray
    twist_dot: np.ndarray
    lengths: np.ndarray
    length_rates: np.ndarray
    wrench: np.ndarray
    C_s: np.ndarray
    F_s: np.ndarray
    tensions_pinv: np.ndarray
    tensions: np.ndarray
    feasible: np.ndarray
    reaction: np.ndarray
    reaction_dofs: tuple[str, ...]
    method: str
    base_model: str
    robot: Robot | None = None
    tension_headroom: np.ndarray | None = None
    winch: WinchBounds | None = None
    sag: CableSag | None = None
    clearances: Clearances | None = None
    obstacle_labels: tuple[str, ...] = ()

    @property
    def n_steps(self) -> int:
        return self.t.size

    def take(self, rows: slice) -> "Plan":
        """The steps ``rows`` of the plan, copied (a piece of it, or one step)."""
        from dataclasses import replace

        per_step = {f: _rows(getattr(self, f), rows) for f in _STEP_FIELDS}
        if self.tension_headroom is not None:
            per_step["tension_headroom"] = _rows(self.tension_headroom, rows)
        c = self.clearances
        return replace(self, **per_step, winch=None if self.winch is None else self.winch.take(rows),
                       sag=None if self.sag is None else self.sag.take(rows),
                       clearances=None if c is None else replace(
                           c, cable_cable=_rows(c.cable_cable, rows), cable_platform=_rows(c.cable_platform, rows),
                           cable_obstacle=_rows(c.cable_obstacle, rows)))

    @property
    def clearance(self) -> np.ndarray | None:
        """Each cable's least distance to another cable, the platform or an obstacle, shape
        (n_steps, n_cables), m; None unless the robot has a ``clearance_m``."""
        c = self.clearances
        return None if c is None else c.per_cable

    @property
    def interfering(self) -> np.ndarray:
        """Steps at which a cable comes closer than ``robot.clearance_m`` to another cable,
        the platform or an obstacle, shape (n_steps,) (all False without a clearance)."""
        gap = self.clearance
        if gap is None:
            return np.zeros(self.n_steps, dtype=bool)
        return (gap < self.robot.clearance_m).any(axis=1)

    def interference(self) -> str | None:
        """One line naming the steps and cables that come closer than ``robot.clearance_m``,
        the first such step's time, pose and what is too close there; None if none does."""
        bad = np.flatnonzero(self.interfering)
        if bad.size == 0:
            return None
        return self._interference_at(int(bad[0]), bad.size, self.n_steps)

    def interference_summary(self) -> dict | None:
        """``summary.json``'s ``interference``: the clearance asked for, the steps that come
        closer, each cable's least distance over the plan (m) and :meth:`interference`'s line;
        None without ``robot.clearance_m``."""
        gap = self.clearance
        if gap is None:
            return None
        least = gap.min(axis=0, initial=np.inf)
        return {"clearance_m": self.robot.clearance_m, "steps_closer": int(self.interfering.sum()),
                "least_clearance_m": [float(v) for v in least], "first": self.interference()}

    def _interference_at(self, i: int, n_bad: int, n_steps: int) -> str:
        what = describe_clearances(self.clearances, i, self.robot.clearance_m, list(self.obstacle_labels))
        return verdicts.closer_line(self.robot.clearance_m, n_bad, n_steps,
                                    f"t = {self.t[i]:.4g} s ({describe_pose(self.pose[i], self.controlled)}): {what}")

    @property
    def all_feasible(self) -> bool:
        return bool(self.feasible.all())

    @property
    def singular(self) -> np.ndarray:
        """Steps at which J~ loses rank (a singular pose: no eq. 18 tensions), shape (n_steps,)."""
        return np.isnan(self.tensions_pinv).any(axis=1)

    @property
    def controlled(self) -> tuple[int, ...]:
        """Twist components the cables control (indices into (v, omega) in C)."""
        return tuple(j for j, name in enumerate(TWIST_NAMES) if name not in self.reaction_dofs)

    def infeasibility(self) -> str | None:
        """One line naming the infeasible steps, or None if every step is feasible.

        It gives the first infeasible step's time and pose (the controlled DOFs) and,
        when the plan knows its robot, which cables sit at which limit in the best
        tensions within limits there and the wrench still missing (see
        :meth:`limiting_cables`).
        """
        bad = np.flatnonzero(~self.feasible)
        if bad.size == 0:
            return None
        return verdicts.infeasibility_line(self, int(bad[0]), bad.size, self.n_steps)

    def limiting_cables(self, i: int) -> str | None:
        """Why step ``i`` is infeasible: the cables at their limits in the best attainable tensions
        (:func:`~marinecdpr.planning.verdicts.limiting_cables`); None if the plan does not know
        its robot."""
        return verdicts.limiting_cables(self, i)


_STEP_FIELDS = ("t", "pose", "twist", "twist_dot", "lengths", "length_rates", "wrench", "C_s", "F_s",
                "tensions_pinv", "tensions", "feasible", "reaction")
"""The plan's arrays every robot has, each shaped (n_steps, ...)."""
_CHUNK_ARRAYS = _STEP_FIELDS + (
    "length_accelerations", "tension_lower", "tension_upper", "winch_limit",  # with winches only
    "sag_lengths", "winch_tensions",  # with heavy cables only
    "tension_headroom",  # when asked for (iter_plan(headroom=True))
    "clearance_cables", "clearance_platform", "clearance_obstacles",  # with robot.clearance_m only
)
"""A piece's arrays as :func:`_plan_chunk` gives them, before :func:`_make_plan` gathers
the winches', the sag's and the clearances' into their records."""
LENGTH_ACCELERATION_STEP_S = 1e-4
"""The step of the central difference of the cables' L' that gives L'', s."""


def _columns(J: np.ndarray, dofs: list[int]) -> np.ndarray:
    """J[:, :, dofs], keeping J's (time-last) memory layout."""
    return J.transpose(2, 1, 0)[dofs].transpose(2, 1, 0)


def _over_pulleys(robot, platform, twist: np.ndarray, t: np.ndarray):
    """The cables' lengths, rates and J~ over the robot's pulleys
    (:func:`~marinecdpr.geometry.pulley.pulley_kinematics`); a pose where a platform anchor
    is on a pulley's swivel axis or inside it is refused, naming the cable and the time."""
    from marinecdpr.geometry.pulley import pulley_kinematics

    pk = pulley_kinematics(platform.x_PC_C, platform.R_PC, robot.frame_anchors, robot.pulley_axes,
                           robot.pulley_radii, robot.platform_anchors, twist)
    bad = np.argwhere(pk.status != 0)
    if bad.size:
        k, i = bad[0]
        why = {1: "on its pulley's swivel axis", 2: "inside its pulley"}.get(int(pk.status[k, i]), "not finite")
        raise ScenarioError(f"cable {i + 1}'s platform anchor is {why} at t = {t[k]:.6g} s")
    return pk


def _cable_rates(scenario: Scenario, t: np.ndarray) -> np.ndarray:
    """The cables' L' at times t (over the pulleys, if any), m/s, shape (n_steps, m)."""
    robot = scenario.robot
    platform = evaluate_trajectory(scenario.trajectory, t, scenario.cleaning, scenario.ship)
    if robot.has_pulleys:
        return _over_pulleys(robot, platform, platform.twist, t).length_rates
    return cable_kinematics(platform.x_PC_C, platform.R_PC, robot.frame_anchors, robot.platform_anchors,
                            platform.twist).length_rates


def _length_accelerations(scenario: Scenario, t: np.ndarray, length_rates: np.ndarray) -> np.ndarray:
    """The cables' L'' at t, m/s^2, shape (n_steps, m), from their L' at t (``length_rates``)
    and around it: second-order differences over :data:`LENGTH_ACCELERATION_STEP_S`,
    central, and forward before it (the trajectory's start): the same at any step whatever
    the chunk."""
    h = LENGTH_ACCELERATION_STEP_S
    ahead = _cable_rates(scenario, t + h)
    first = t < h
    back = _cable_rates(scenario, np.where(first, t + 2.0 * h, t - h))
    central = (ahead - back) / (2.0 * h)
    if first.any():
        central[first] = (4.0 * ahead[first] - 3.0 * length_rates[first] - back[first]) / (2.0 * h)
    return central


def _winch_bounds(scenario: Scenario, t: np.ndarray, length_rates: np.ndarray) -> dict:
    """With ``robot.winch``: the cables' L'', the tensions each winch can give at each step
    (:func:`~marinecdpr.model.winch.winch_tension_bounds`) and :attr:`WinchBounds.limit`."""
    from marinecdpr.model.winch import WinchParams, winch_tension_bounds

    robot = scenario.robot
    L_ddot = _length_accelerations(scenario, t, length_rates)
    b = winch_tension_bounds(length_rates, L_ddot, WinchParams(**robot.winch.model_dump()),
                             robot.tension_min, robot.tension_max)
    limit = np.where(b.overspeed, WINCH_OVERSPEED, np.where(b.empty, WINCH_NO_TENSION, 0)).astype(np.int8)
    return dict(length_accelerations=L_ddot, tension_lower=b.lower_N, tension_upper=b.upper_N, winch_limit=limit)


def _sag(scenario: Scenario, spans_from: np.ndarray, anchors: np.ndarray, up_C: np.ndarray,
         tensions: np.ndarray) -> dict:
    """Heavy cables (``robot.cable_weight_N_m``): each free span from ``spans_from`` (n, m, 3)
    to the platform anchors (n, m, 3), in C, an elastic catenary in the vertical ``up_C``
    (n, 3) carrying ``tensions`` (n, m) at the platform: :attr:`CableSag.lengths` and
    :attr:`CableSag.winch_tensions` (NaN where the tension is, or where no catenary carries it)."""
    from marinecdpr.model.catenary import catenary_series

    cab = scenario.simulation.cables
    EA = float(cab.stiffness_EA_N) if cab.model != "ideal" else np.inf
    d = anchors - spans_from
    v = np.einsum("nmi,ni->nm", d, up_C)
    chord2 = np.einsum("nmi,nmi->nm", d, d)
    h = np.sqrt(np.maximum(chord2 - v * v, 0.0))
    ok = np.isfinite(tensions)
    sag, T_A = np.full(tensions.shape, np.nan), np.full(tensions.shape, np.nan)
    if ok.any():
        T = tensions[ok]
        cat = catenary_series(h[ok], v[ok], scenario.robot.cable_weight_N_m, EA, T_B=T)
        good = cat.status == 0
        sag[ok] = np.where(good, cat.L0 - unstretched_length(np.sqrt(chord2[ok]), T, EA), np.nan)
        T_A[ok] = np.where(good, cat.T_A, np.nan)
    return dict(sag_lengths=sag, winch_tensions=T_A)


def twist_on_hull(scenario: Scenario, x_PC: np.ndarray, twist: np.ndarray, t: np.ndarray) -> np.ndarray:
    """The platform's twist relative to the hull (to S), in C, where a coverage path is held on
    the ship while the carriage moves (``trajectory.on_hull``): the brush slides over the hull
    with the carriage's velocity added, (v_PC + R_SC^T v_S + omega_CS x x_PC, omega_PC +
    omega_CS); elsewhere ``twist`` itself (relative to C, which the brush's model takes as the
    hull's).

    Parameters
    ----------
    x_PC : ndarray, shape (n_steps, 3)
        P's origin in C, m.
    twist : ndarray, shape (n_steps, 6)
        (v_PC, omega_PC) in C, m/s, rad/s.
    t : ndarray, shape (n_steps,)
        Times, s (the carriage's).

    Returns
    -------
    ndarray, shape (n_steps, 6)
        In C, m/s, rad/s (``twist``, the same object, without ``on_hull``).
    """
    if not getattr(scenario.trajectory, "on_hull", False):
        return twist
    from marinecdpr.motion.carriage import carriage_motion

    _, v_S, _, R_SC, omega, _ = carriage_motion(scenario.ship, t)
    out = np.array(twist, dtype=float)
    out[:, :3] += np.einsum("nji,nj->ni", R_SC, v_S) + np.cross(omega, x_PC)
    out[:, 3:] += omega
    return out


def required_wrench(scenario: Scenario, x_PC: np.ndarray, twist: np.ndarray, twist_dot: np.ndarray,
                    R_PC: np.ndarray, ship: ShipMotion, t: np.ndarray, F_n) -> WrenchTerms:
    """The wrench the platform needs (eqs. 9-16), with the scenario's disturbance f_r, m_r,
    with ``[cleaning]`` the brush's loads pressed on with ``F_n`` (N; the planner takes the
    pusher's preload), and with ``[wind]`` the wind's drag on the platform and its cables'
    shares at the wind ``wind.plan_gust`` names (:func:`~marinecdpr.model.wind.scenario_wind_loads`).

    Parameters
    ----------
    x_PC : ndarray, shape (n_steps, 3)
    twist, twist_dot : ndarray, shape (n_steps, 6)
        In C.
    R_PC : ndarray, shape (n_steps, 3, 3)
    ship : ShipMotion
    t : ndarray, shape (n_steps,)
        s (the disturbance's times).
    F_n : float or ndarray, shape (n_steps,)
    """
    f_r, m_r = evaluate_disturbance(scenario.disturbance, t)
    f_C, m_C = disturbance_in_C(f_r, m_r, scenario.disturbance.frame, ship.R_SO, R_PC)
    if scenario.cleaning is not None:
        f_b, m_b = cleaning_loads(scenario.cleaning, twist_on_hull(scenario, x_PC, twist, t), R_PC, F_n)
        f_C, m_C = f_C + f_b, m_C + m_b
    if scenario.wind is not None:
        f_w, m_w = scenario_wind_loads(scenario, x_PC, twist, R_PC, ship, t)
        f_C, m_C = f_C + f_w, m_C + m_w
    robot = scenario.robot
    return wrench_terms(x_PC, twist, twist_dot, R_PC, ship, frame_origin_S=frame_origin_of(scenario),
                        mass=robot.mass_kg, I_PP=robot.inertia, gravity=scenario.environment.gravity_m_s2,
                        f_ext_C=f_C, m_ext_C=m_C)


def _plan_chunk(scenario: Scenario, t: np.ndarray, method: str, base_model: str,
                ship: ShipMotion | None = None, headroom: bool = False) -> dict:
    robot = scenario.robot
    platform = evaluate_trajectory(scenario.trajectory, t, scenario.cleaning, scenario.ship)
    if base_model == "fixed":
        ship = fixed_ship_motion(scenario, t)
    elif ship is None:
        ship = frame_ship_motion(scenario, t)
    twist = platform.twist
    kin = cable_kinematics(
        platform.x_PC_C, platform.R_PC, robot.frame_anchors, robot.platform_anchors, twist
    )
    check_in_frame(platform.x_PC_C, kin.anchors_C, robot.frame_anchors, t)
    anchors = platform.x_PC_C[:, None, :] + kin.anchors_C  # the platform anchors in C
    spans_from = np.broadcast_to(robot.frame_anchors, anchors.shape)  # where the free spans start
    if robot.has_pulleys:  # the cables leave their pulleys where their directions say
        kin = _over_pulleys(robot, platform, twist, t)
        spans_from = kin.exits_C
    # the brush's drag, reaction moment, jet and the hull's push, at the pusher's preload
    preload = scenario.cleaning.preload if scenario.cleaning is not None else 0.0
    terms = required_wrench(scenario, platform.x_PC_C, twist, platform.twist_dot, platform.R_PC, ship, t, preload)
    w = terms.total
    c = list(robot.controlled)
    J = _columns(kin.J_tilde, c)
    T_s, ok = pseudo_inverse_tensions(J, w[:, c])
    winch = {} if robot.winch is None else _winch_bounds(scenario, t, kin.length_rates)
    lower, upper = winch.get("tension_lower"), winch.get("tension_upper")
    if winch:  # a winch that cannot turn as fast as its cable moves holds no tension
        lower = np.where(winch["winch_limit"] == WINCH_OVERSPEED, np.nan, lower)
    sol = distribute_tensions(
        J, w[:, c], robot.tension_min, robot.tension_max, method=method, ok=ok,
        lower=lower, upper=upper,
    )
    u = list(uncontrolled(robot.controlled))
    # the guide supplies what the cables do not: w - J~^T T in the uncontrolled DOFs
    J_u = _columns(kin.J_tilde, u)
    reaction = w[:, u] - sum(J_u[:, i] * sol.tensions[:, i, None] for i in range(J_u.shape[1]))
    sag = {} if robot.cable_weight_N_m == 0.0 else _sag(scenario, spans_from, anchors, ship.R_SO[:, 2, :],
                                                         sol.tensions)
    # the largest headroom any tensions could keep, within the cables' own limits
    extra = {"tension_headroom": largest_headroom(J, T_s, robot.tension_min, robot.tension_max)} if headroom else {}
    if robot.clearance_m is not None:  # how close the cables come to each other, the platform, obstacles
        gaps = clearances(robot, scenario.obstacles, platform.x_PC_C, platform.R_PC, spans_from, anchors)
        extra.update(clearance_cables=gaps.cable_cable, clearance_platform=gaps.cable_platform,
                     clearance_obstacles=gaps.cable_obstacle)
    return dict(
        t=t, pose=platform.pose, twist=twist, twist_dot=platform.twist_dot,
        lengths=kin.lengths, length_rates=kin.length_rates, wrench=w,
        C_s=terms.C_s, F_s=terms.F_s, tensions_pinv=T_s, tensions=sol.tensions,
        feasible=sol.feasible, reaction=reaction, **winch, **sag, **extra,
    )


def stand_in_plan(scenario: Scenario, t: np.ndarray, *, base_model: str | None = None) -> Plan:
    """A plan with the fields, shapes and dtypes :func:`plan_at` gives the scenario at t, made
    without its dynamics: the trajectory's poses and twists and the straight cables'
    lengths and rates, every wrench zero, every tension (and each winch's bound) at the
    middle of the cables' limits, every step feasible, no sag. Its one use: to build a
    prototype whose compiled parts have the types of a real run's, and so compile them
    while the plan's own kernels compile in another process
    (:func:`~marinecdpr.prototype.warmup.compile_apart`). Not a plan to fly or to judge.

    Parameters
    ----------
    t : ndarray, shape (n_steps,)
        Times, s.
    base_model : {"moving", "fixed"}, optional
        Default the scenario's ``planning.base_model``.
    """
    method, base_model = _options(scenario, None, base_model)
    robot = scenario.robot
    t = np.asarray(t, dtype=float)
    n, m, k = t.size, robot.n_cables, len(robot.controlled)
    platform = evaluate_trajectory(scenario.trajectory, t, scenario.cleaning, scenario.ship)
    kin = cable_kinematics(platform.x_PC_C, platform.R_PC, robot.frame_anchors, robot.platform_anchors,
                           platform.twist)
    middle = np.full((n, m), 0.5 * (robot.tension_min + robot.tension_max))
    arrays = dict(t=t, pose=platform.pose, twist=platform.twist, twist_dot=platform.twist_dot,
                  lengths=kin.lengths, length_rates=kin.length_rates, wrench=np.zeros((n, 6)),
                  C_s=np.zeros((n, 6)), F_s=np.zeros((n, 6)), tensions_pinv=middle.copy(), tensions=middle,
                  feasible=np.ones(n, dtype=bool), reaction=np.zeros((n, 6 - k)))
    if robot.winch is not None:
        arrays.update(length_accelerations=np.zeros((n, m)), tension_lower=middle.copy(),
                      tension_upper=middle.copy(), winch_limit=np.zeros((n, m), dtype=np.int8))
    if robot.cable_weight_N_m != 0.0:
        arrays.update(sag_lengths=np.zeros((n, m)), winch_tensions=middle.copy())
    return _make_plan(scenario, arrays, method, base_model)


VERDICT_STEPS = 200
"""Most steps :func:`sampled_infeasibility` plans."""


def sampled_infeasibility(scenario: Scenario, *, max_steps: int = VERDICT_STEPS) -> str | None:
    """Whether the scenario can be flown at all, from a plan of some of its steps: one line, or None.

    Plans at most ``max_steps`` of the scenario's time steps, spread evenly over its duration
    (its first and last included), by its own method on its own ship, and returns
    :meth:`Plan.infeasibility`'s line for them (which steps, the first's pose, the cables at
    their limits, the wrench still missing, the change that helps), with what the wrench is
    where the platform is held still on a still frame: its weight alone. None where every
    step planned is feasible. For a scenario just made (``marinecdpr import``): a robot
    that cannot hold its platform is said so at once. A trajectory leaving the frame raises
    :class:`ScenarioError`, as a plan does.

    Parameters
    ----------
    scenario : Scenario
    max_steps : int
        Steps planned at most.
    """
    n, step = scenario.time.n_steps, scenario.time.step_s
    idx = np.unique(np.linspace(0, n - 1, min(n, max_steps)).round().astype(np.int64))
    p = plan_at(scenario, idx * step)
    bad = np.flatnonzero(~p.feasible)
    if bad.size == 0:
        return None
    i = int(bad[0])
    weight = None
    if scenario.base_motion.type == "still" and not np.any(p.twist[i]) and not np.any(p.twist_dot[i]):
        weight = scenario.robot.mass_kg * scenario.environment.gravity_m_s2
    return verdicts.sampled_line(p, i, int(bad.size), int(idx.size), n, weight)


def check_trajectory(scenario: Scenario, *, chunk_steps: int = DEFAULT_CHUNK_STEPS) -> "SingularPoses":
    """Raise :class:`ScenarioError` if the trajectory leaves the frame or a motion file is bad
    (no dynamics solved); return where along it J~ loses rank.

    Parameters
    ----------
    scenario : Scenario
    chunk_steps : int
        Steps evaluated at once.

    Returns
    -------
    SingularPoses
        The trajectory's steps at which J~ (over the pulleys, if any) loses rank on the
        controlled DOFs, by the tension solver's own rank test
        (:func:`~marinecdpr.model.tension.full_rank`): the steps every plan fails at.
    """
    robot = scenario.robot
    c = list(robot.controlled)
    n, step = scenario.time.n_steps, scenario.time.step_s
    # reads and checks any file the ship's motion comes from, over the whole duration
    evaluate_base_motion(scenario.base_motion, np.array([0.0, (n - 1) * step]))
    if scenario.ship.carriage is not None:  # the rail can be built and holds the stations
        rail_of(scenario.ship)
    n_singular, first = 0, None
    for start in range(0, n, chunk_steps):
        t = np.arange(start, min(start + chunk_steps, n)) * step
        platform = evaluate_trajectory(scenario.trajectory, t, scenario.cleaning, scenario.ship)
        kin = cable_kinematics(platform.x_PC_C, platform.R_PC, robot.frame_anchors,
                               robot.platform_anchors)
        check_in_frame(platform.x_PC_C, kin.anchors_C, robot.frame_anchors, t)
        if robot.has_pulleys:
            kin = _over_pulleys(robot, platform, platform.twist, t)
        bad = ~full_rank(_columns(kin.J_tilde, c))
        if bad.any():
            n_singular += int(bad.sum())
            if first is None:
                i = int(np.flatnonzero(bad)[0])
                first = f"t = {t[i]:.4g} s ({describe_pose(platform.pose[i], robot.controlled)})"
    return SingularPoses(what="steps of the trajectory", n_poses=n, n_singular=n_singular, first=first,
                         scale=scaled_copy(robot), level=False)


def trajectory_interference(scenario: Scenario, *, chunk_steps: int = DEFAULT_CHUNK_STEPS) -> str | None:
    """Where along the trajectory a cable comes closer than ``robot.clearance_m`` to another
    cable, the platform's body or an obstacle (no dynamics solved): :meth:`Plan.interference`'s
    line, or None if nowhere (or the robot has no clearance)."""
    from marinecdpr.planning.interference import pose_clearances

    robot = scenario.robot
    if robot.clearance_m is None:
        return None
    n, step = scenario.time.n_steps, scenario.time.step_s
    labels = obstacle_labels(scenario.obstacles)
    n_close, first = 0, None
    for start in range(0, n, chunk_steps):
        t = np.arange(start, min(start + chunk_steps, n)) * step
        platform = evaluate_trajectory(scenario.trajectory, t, scenario.cleaning, scenario.ship)
        gaps = pose_clearances(robot, scenario.obstacles, platform.x_PC_C, platform.R_PC)
        close = (gaps.per_cable < robot.clearance_m).any(axis=1)
        if close.any() and first is None:
            i = int(np.flatnonzero(close)[0])
            first = (f"t = {t[i]:.4g} s ({describe_pose(platform.pose[i], robot.controlled)}): "
                     + describe_clearances(gaps, i, robot.clearance_m, labels))
        n_close += int(close.sum())
    return None if first is None else verdicts.closer_line(robot.clearance_m, n_close, n, first)




def _options(scenario: Scenario, method: str | None, base_model: str | None) -> tuple[str, str]:
    method = method or scenario.planning.method
    base_model = base_model or scenario.planning.base_model
    if base_model not in ("moving", "fixed"):
        raise ValueError(f"base_model must be 'moving' or 'fixed', not {base_model!r}")
    return method, base_model


def ship_motion_at(scenario: Scenario, t: np.ndarray, base_model: str | None = None) -> ShipMotion | None:
    """The ship's motion a plan at times ``t`` rests on, to share between plans on the same
    ship (:func:`plan_at`'s ``ship``): e.g. a workspace map's held poses, which would each
    evaluate it again (for a sea state, a sum over thousands of wave components).

    Parameters
    ----------
    scenario : Scenario
    t : ndarray, shape (n_steps,)
        Times, s.
    base_model : {"moving", "fixed"}, optional
        Default the scenario's ``planning.base_model``.

    Returns
    -------
    ShipMotion or None
        The scenario's base motion at t; None for a fixed-base plan (it takes a still ship).
    """
    _, base_model = _options(scenario, None, base_model)
    return None if base_model == "fixed" else frame_ship_motion(scenario, np.asarray(t, dtype=float))


def _make_plan(scenario: Scenario, arrays: dict, method: str, base_model: str) -> Plan:
    """The plan of a piece's arrays (:data:`_CHUNK_ARRAYS`): what only some robots have in
    its records."""
    arrays = dict(arrays)
    names = tuple(TWIST_NAMES[i] for i in uncontrolled(scenario.robot.controlled))
    winch = sag = gaps = None
    if "winch_limit" in arrays:
        winch = WinchBounds(arrays.pop("length_accelerations"), arrays.pop("tension_lower"),
                            arrays.pop("tension_upper"), arrays.pop("winch_limit"))
    if "sag_lengths" in arrays:
        sag = CableSag(arrays.pop("sag_lengths"), arrays.pop("winch_tensions"))
    if "clearance_platform" in arrays:
        from marinecdpr.geometry.interference import cable_pairs

        robot = scenario.robot
        gaps = Clearances(pairs=cable_pairs(robot.frame_anchors, robot.platform_anchors),
                          cable_cable=arrays.pop("clearance_cables"), cable_platform=arrays.pop("clearance_platform"),
                          cable_obstacle=arrays.pop("clearance_obstacles"))
    return Plan(**arrays, reaction_dofs=names, method=method, base_model=base_model, robot=scenario.robot,
                winch=winch, sag=sag, clearances=gaps, obstacle_labels=tuple(obstacle_labels(scenario.obstacles)))


def iter_plan(
    scenario: Scenario,
    *,
    method: str | None = None,
    base_model: str | None = None,
    chunk_steps: int = DEFAULT_CHUNK_STEPS,
    headroom: bool = False,
) -> Iterator[Plan]:
    """Plan the scenario chunk by chunk; memory stays bounded by ``chunk_steps``.

    Parameters
    ----------
    scenario : Scenario
    method : str, optional
        Tension method; default the scenario's ``planning.method``.
    base_model : {"moving", "fixed"}, optional
        Default the scenario's ``planning.base_model``.
    chunk_steps : int
        Steps per yielded :class:`Plan`.
    headroom : bool
        Also give each step's :attr:`Plan.tension_headroom`: the largest headroom to the
        robot's tension limits any tensions producing the wrench could keep
        (:func:`~marinecdpr.model.tension.largest_headroom`), N.

    Yields
    ------
    Plan
        Consecutive pieces of the plan.

    Raises
    ------
    ScenarioError
        If the trajectory leaves the frame.
    """
    method, base_model = _options(scenario, method, base_model)
    n, step = scenario.time.n_steps, scenario.time.step_s
    for i0 in range(0, n, chunk_steps):
        # each chunk's times alone (the values of np.arange(n) * step): nothing of size n is held
        t = np.arange(i0, min(i0 + chunk_steps, n)) * step
        yield _make_plan(scenario, _plan_chunk(scenario, t, method, base_model, headroom=headroom), method,
                         base_model)


class PlanSummary:
    """What a plan made in chunks (:func:`iter_plan`) amounts to, gathered piece by piece
    without holding the pieces: the figures a whole :class:`Plan` would give.

    Feed every piece, in order, to :meth:`add`.

    Attributes
    ----------
    n_steps, n_feasible, n_singular, n_interfering : int
        Steps; feasible ones; singular ones (:attr:`Plan.singular`); those where a cable comes
        closer than ``robot.clearance_m`` to something (:attr:`Plan.interfering`).
    pinv_range, tension_range : tuple of float
        (smallest, largest) eq. 18 and planned tensions, N, NaN ignored (as ``np.nanmin``
        and ``np.nanmax`` on the whole plan; (NaN, NaN) if no tension is finite).
    method, base_model : str
        As the pieces' (None before the first).
    """

    def __init__(self) -> None:
        self.n_steps = 0
        self.n_feasible = 0
        self.n_singular = 0
        self.method: str | None = None
        self.base_model: str | None = None
        self._ranges = {"tensions_pinv": [np.inf, -np.inf, False], "tensions": [np.inf, -np.inf, False]}
        self._first_bad: Plan | None = None  # the first infeasible step, as a one-step plan
        self.n_interfering = 0
        self._first_close: Plan | None = None  # the first step a cable comes too close, likewise

    def add(self, piece: Plan) -> None:
        """Count one piece of the plan (the next in time)."""
        self.method, self.base_model = piece.method, piece.base_model
        for name, acc in self._ranges.items():
            a = getattr(piece, name)
            if np.isfinite(a).any():
                acc[2] = True
            if not np.isnan(a).all():
                acc[0] = min(acc[0], float(np.nanmin(a)))
                acc[1] = max(acc[1], float(np.nanmax(a)))
        def step(i: int) -> Plan:
            return piece.take(slice(i, i + 1))

        ok = int(piece.feasible.sum())
        if self._first_bad is None and ok < piece.n_steps:
            self._first_bad = step(int(np.flatnonzero(~piece.feasible)[0]))
        close = piece.interfering
        if self._first_close is None and close.any():
            self._first_close = step(int(np.flatnonzero(close)[0]))
        self.n_interfering += int(close.sum())
        self.n_steps += piece.n_steps
        self.n_feasible += ok
        self.n_singular += int(piece.singular.sum())

    def _range(self, name: str) -> tuple[float, float]:
        lo, hi, finite = self._ranges[name]
        return (lo, hi) if finite else (float("nan"), float("nan"))

    @property
    def pinv_range(self) -> tuple[float, float]:
        return self._range("tensions_pinv")

    @property
    def tension_range(self) -> tuple[float, float]:
        return self._range("tensions")

    @property
    def all_feasible(self) -> bool:
        return self.n_feasible == self.n_steps

    def infeasibility(self) -> str | None:
        """:meth:`Plan.infeasibility` of the whole plan."""
        if self._first_bad is None:
            return None
        return verdicts.infeasibility_line(self._first_bad, 0, self.n_steps - self.n_feasible, self.n_steps)

    def interference(self) -> str | None:
        """:meth:`Plan.interference` of the whole plan."""
        if self._first_close is None:
            return None
        return self._first_close._interference_at(0, self.n_interfering, self.n_steps)


def _chunks(scenario: Scenario, t: np.ndarray, method: str, base_model: str, chunk_steps: int,
            ship: ShipMotion | None = None):
    """The plan's arrays for consecutive pieces of ``t`` (and of ``ship``, the ship's motion
    at t, if given)."""
    for i0 in range(0, t.size, chunk_steps):
        rows = slice(i0, i0 + chunk_steps)
        yield _plan_chunk(scenario, t[rows], method, base_model, None if ship is None else ship.take(rows))


def plan(
    scenario: Scenario,
    *,
    method: str | None = None,
    base_model: str | None = None,
    chunk_steps: int = DEFAULT_CHUNK_STEPS,
) -> Plan:
    """Plan cable tensions for the scenario's trajectory on its moving ship.

    Parameters
    ----------
    scenario : Scenario
        From :func:`~marinecdpr.load_scenario`.
    method : str, optional
        Tension method (see :mod:`marinecdpr.model.tension`); default the scenario's.
    base_model : {"moving", "fixed"}, optional
        "fixed" plans as if the ship were still (the traditional model).
    chunk_steps : int
        Steps computed at once; results do not depend on it.

    Returns
    -------
    Plan
        Infeasible steps are flagged (``feasible``), with NaN tensions; see
        :meth:`Plan.infeasibility`.

    Raises
    ------
    ScenarioError
        If the plan would not fit in memory (see :func:`marinecdpr.planning.budget.check_run_size`;
        :func:`iter_plan` streams longer ones), or the trajectory leaves the frame.
    """
    from marinecdpr.planning.budget import check_run_size

    check_run_size(scenario, "plan", chunk_steps=chunk_steps)
    t = np.arange(scenario.time.n_steps) * scenario.time.step_s
    return plan_at(scenario, t, method=method, base_model=base_model, chunk_steps=chunk_steps)


def plan_at(
    scenario: Scenario,
    t: np.ndarray,
    *,
    method: str | None = None,
    base_model: str | None = None,
    chunk_steps: int = DEFAULT_CHUNK_STEPS,
    ship: ShipMotion | None = None,
) -> Plan:
    """The plan at any times, e.g. mid-steps for a zero-order hold (see :func:`plan`).

    Parameters
    ----------
    t : ndarray, shape (n_steps,)
        Times, s.
    ship : ShipMotion, optional
        The ship's motion at t, if already known (a simulation's finer grid holds it);
        else evaluated from the scenario's base motion.
    """
    method, base_model = _options(scenario, method, base_model)
    t = np.asarray(t, dtype=float)
    n = t.size
    if (ship is None and base_model == "moving" and n > 1
            and ship_at_once(scenario, n, float(t[1] - t[0]), chunk_steps)):
        ship = frame_ship_motion(scenario, t)
    if n <= chunk_steps:
        return _make_plan(scenario, _plan_chunk(scenario, t, method, base_model, ship), method, base_model)
    out: dict[str, np.ndarray] = {}
    i0 = 0
    for piece in _chunks(scenario, t, method, base_model, chunk_steps, ship):
        for name in _CHUNK_ARRAYS:
            arr = piece.get(name)
            if arr is None:
                continue
            if name not in out:
                out[name] = np.empty((n,) + arr.shape[1:], dtype=arr.dtype)
            out[name][i0 : i0 + arr.shape[0]] = arr
        i0 += piece["t"].size
    return _make_plan(scenario, out, method, base_model)
