"""The frame's moves between its placements on a surface, by crane or along a rail, the
robots that share the surface, and what the moves cost
(``[cleaning.surface.relocation]``, :class:`~marinecdpr.scenario.relocation.Relocation`).

- **crane**: ``rig + 2 lift / hoist + distance / travel + retension``, the distance between
  the two placements' centres (:func:`crane_move_s`);
- **rail**: the carriage's time-optimal double-S move over that distance
  (:func:`~marinecdpr.motion.rail.scurve_move`) and the settle (:func:`rail_move_s`), between
  placements of one height row (the same heights cleaned: the frame's height on the rail
  does not change) where the side turns no sharper than the rail's least radius (the
  frames' headings in plan turn by d(yaw) over the plan distance s: radius s / |d(yaw)|);
  any other move by crane where one is given, else refused;
- **fixed**: every move the given time.

The order of the visits: fixed as the tiling lists the placements (along the ship, then
up; the hours as without the section); crane up one column and down the next; rail along
one height row and back along the next (:func:`visit_order`). With ``robots`` > 1 the
placements in the tiling's order (along the ship) are cut into that many stretches of
near-equal work (:func:`stretches`), each robot visits its own in the mode's order, and the
job takes the slowest robot's time.

Costs (:func:`relocation_cost`): a crane (where any move is by crane) is hired for the whole
job, one per robot (each robot's moves wait for no other's): ``robots x hire_per_h x the
job's hours``; a rail (mode rail) runs the band's length along the ship (its stations'
span) at ``cost_per_m``, with one carriage per robot at ``carriage_cost`` and its drive at
``drive_cost_per_kW`` x its peak power (:func:`carriage_drive_kW`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from marinecdpr.errors import ScenarioError
from marinecdpr.scenario.relocation import Crane, RailMoves, Relocation

__all__ = ["Moves", "crane_move_s", "rail_move_s", "plan_yaw", "turn_radius_m", "visit_order", "stretches",
           "plan_moves", "relocation_cost", "carriage_drive_kW", "RelocationCost", "NO_COST", "rail_move_scenario", "level_rail_S"]

_ROUND_M = 1e-6
"""Placements whose heights (rows) or stations (columns) agree to this, m, share a row or column."""


def crane_move_s(distance_m, crane: Crane) -> np.ndarray:
    """A crane's move of the frame over ``distance_m`` (any shape, m): rig + 2 lift / hoist +
    distance / travel + retension, s (the same shape)."""
    d = np.asarray(distance_m, dtype=float)
    return crane.rig_s + 2.0 * crane.lift_m / crane.hoist_m_s + d / crane.travel_m_s + crane.retension_s


def rail_move_s(distance_m, rail: RailMoves) -> np.ndarray:
    """The carriage's move over ``distance_m`` (any shape, m) along the rail: the double-S
    move's duration (:func:`~marinecdpr.motion.rail.scurve_move`, each distinct distance
    once) and the settle, s (the same shape)."""
    from marinecdpr.motion.rail import scurve_move

    d = np.asarray(distance_m, dtype=float)
    values, inverse = np.unique(d.ravel(), return_inverse=True)
    durations = np.array([scurve_move(float(v), rail.speed_m_s, rail.accel_m_s2, rail.jerk_m_s3).duration_s
                          for v in values])
    return (durations[inverse] + rail.settle_s).reshape(d.shape)


def plan_yaw(placements) -> np.ndarray:
    """Each placement's heading in plan: the angle of its frame's x axis (``axes_S[:, 0]``)
    projected on S's x-y plane, from S's x towards y, rad, shape (n,)."""
    R = np.array([p.axes_S for p in placements], dtype=float).reshape(-1, 3, 3)
    return np.arctan2(R[:, 1, 0], R[:, 0, 0])


def turn_radius_m(centres: np.ndarray, yaw: np.ndarray) -> np.ndarray:
    """The side's radius of turn between consecutive placements: their plan distance over
    the change of their heading, m, shape (n - 1,) (inf where the heading does not turn).

    Parameters
    ----------
    centres : ndarray, shape (n, 3)
        The placements' centres in S, m.
    yaw : ndarray, shape (n,)
        Their headings in plan (:func:`plan_yaw`), rad.
    """
    s = np.linalg.norm(np.diff(centres[:, :2], axis=0), axis=1)
    turn = np.abs(np.angle(np.exp(1j * np.diff(yaw))))
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(turn > 0.0, s / turn, np.inf)


def _groups(keys: np.ndarray) -> np.ndarray:
    """A group number for each run of equal rows of ``keys`` (n, k), in order."""
    if len(keys) == 0:
        return np.zeros(0, dtype=int)
    new = np.any(np.diff(keys, axis=0) != 0, axis=1)
    return np.concatenate([[0], np.cumsum(new)])


def visit_order(placements, mode: str) -> np.ndarray:
    """The order the frame visits ``placements`` (as the tiling lists them: along the ship,
    then up) in, indices, shape (n,).

    fixed: as listed. crane: each column (placements of the same stations) in turn, up the
    first, down the next. rail: each height row (placements cleaning the same heights) in
    turn from the lowest, along the ship in the first, back in the next.
    """
    n = len(placements)
    if mode == "fixed" or n == 0:
        return np.arange(n)
    x = np.round(np.array([p.x_range for p in placements], dtype=float) / _ROUND_M)
    z = np.round(np.array([p.z_range for p in placements], dtype=float) / _ROUND_M)
    if mode == "crane":
        order = np.lexsort((z[:, 1], z[:, 0], x[:, 1], x[:, 0]))
        column = _groups(x[order])
        flip = column % 2 == 1
        key = np.where(flip, -z[order, 0], z[order, 0])
        return order[np.lexsort((key, column))]
    order = np.lexsort((x[:, 1], x[:, 0], z[:, 1], z[:, 0]))  # rows from the lowest, each along the ship
    row = _groups(z[order])
    key = np.where(row % 2 == 1, -x[order, 0], x[order, 0])
    return order[np.lexsort((key, row))]


def stretches(work_s: np.ndarray, robots: int) -> np.ndarray:
    """Which robot takes each item of a sequence: ``robots`` contiguous stretches of
    near-equal work, item k to robot floor(robots x (its work's midpoint) / total)
    (each stretch's work within one item's of total / robots), shape (n,), 0-based.

    Parameters
    ----------
    work_s : ndarray, shape (n,)
        Each item's work, s (>= 0).
    robots : int
    """
    w = np.asarray(work_s, dtype=float)
    total = float(w.sum())
    if robots <= 1 or total <= 0.0:
        return np.zeros(w.size, dtype=int)
    mid = np.cumsum(w) - 0.5 * w
    return np.minimum((robots * mid / total).astype(int), robots - 1)


@dataclass(frozen=True)
class Moves:
    """The visits of a surface's placements and the moves between them.

    Attributes
    ----------
    order : ndarray of int, shape (n,)
        The placements (indices into the job's list) in the order visited, robot after robot.
    robot : ndarray of int, shape (n,)
        The robot of each visit, 0-based (non-decreasing).
    move_in_s : ndarray, shape (n,)
        The move into each visit from its robot's previous one, s (0 at each robot's first).
    kind : ndarray of str, shape (n,)
        "fixed", "crane" or "rail" for each move into a visit, "" at each robot's first.
    robots : int
    """

    order: np.ndarray
    robot: np.ndarray
    move_in_s: np.ndarray
    kind: np.ndarray
    robots: int

    def robot_seconds(self, job_s: np.ndarray) -> np.ndarray:
        """Each robot's cleaning (``job_s`` per placement, shape (n,)) and moves, s, shape (robots,)."""
        per_visit = np.asarray(job_s, dtype=float)[self.order] + self.move_in_s
        return np.bincount(self.robot, weights=per_visit, minlength=self.robots)

    def count(self, kind: str) -> int:
        """How many moves were of this kind."""
        return int((self.kind == kind).sum())

    def seconds(self, kind: str) -> float:
        """The moves of this kind, all robots', s."""
        return float(self.move_in_s[self.kind == kind].sum())


def _robot_moves(placements, visits: np.ndarray, relocation: Relocation, move_time_s: float,
                 yaw: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The moves between one robot's consecutive visits (placement indices ``visits``):
    their times (s) and kinds, each shape (len(visits) - 1,)."""
    n = len(visits) - 1
    if n <= 0:
        return np.zeros(0), np.zeros(0, dtype="<U5")
    if relocation.mode == "fixed":
        return np.full(n, float(move_time_s)), np.full(n, "fixed", dtype="<U5")
    centres = np.array([placements[i].centre_S for i in visits], dtype=float)
    d = np.linalg.norm(np.diff(centres, axis=0), axis=1)
    if relocation.mode == "crane":
        return crane_move_s(d, relocation.crane), np.full(n, "crane", dtype="<U5")
    rail = relocation.rail
    z = np.array([placements[i].z_range for i in visits], dtype=float)
    same_row = np.all(np.abs(np.diff(z, axis=0)) <= _ROUND_M, axis=1)
    follows = turn_radius_m(centres, yaw[visits]) >= rail.min_radius_m
    on_rail = same_row & follows
    if not on_rail.all() and relocation.crane is None:
        k = int(np.flatnonzero(~on_rail)[0])
        p = placements[visits[k + 1]]
        why = ("cleans other heights than the one before it: the frame's height changes" if not same_row[k] else
               f"lies where the side turns sharper than min_radius_m ({rail.min_radius_m:g} m)")
        raise ScenarioError(f"the rail cannot reach the placement at stations {p.x_range[0]:.4g} to "
                            f"{p.x_range[1]:.4g} m, heights {p.z_range[0]:.4g} to {p.z_range[1]:.4g} m: it {why}; "
                            "give [cleaning.surface.relocation.crane] to lift the frame there",
                            key="cleaning.surface.relocation.rail")
    times = np.empty(n)
    times[on_rail] = rail_move_s(d[on_rail], rail)
    if not on_rail.all():
        times[~on_rail] = crane_move_s(d[~on_rail], relocation.crane)
    return times, np.where(on_rail, "rail", "crane").astype("<U5")


def plan_moves(placements, job_s: np.ndarray, relocation: Relocation, move_time_s: float) -> Moves:
    """The visits and moves of a surface job (the module's rules).

    Parameters
    ----------
    placements : list of Placement
        As the tiling lists them (along the ship, then up).
    job_s : ndarray, shape (n,)
        Each placement's cleaning time, s.
    relocation : Relocation
    move_time_s : float
        The time of a fixed move, s (mode fixed).

    Raises
    ------
    ScenarioError
        Mode rail without a crane and a move the rail cannot make (the placement named).
    """
    n = len(placements)
    yaw = plan_yaw(placements) if relocation.mode == "rail" else np.zeros(n)
    robots = relocation.robots
    if robots > 1:  # stretches along the ship, each placement's work its cleaning and the one-robot mean move
        whole = visit_order(placements, relocation.mode)
        times, _ = _robot_moves(placements, whole, relocation, move_time_s, yaw)
        mean = float(times.mean()) if times.size else 0.0
        owner = stretches(np.asarray(job_s, dtype=float) + mean, robots)
    else:
        owner = np.zeros(n, dtype=int)
    order, robot, move_in, kind = [], [], [], []
    for r in range(robots):
        mine = np.flatnonzero(owner == r)
        if mine.size == 0:
            continue
        visits = mine[visit_order([placements[i] for i in mine], relocation.mode)]
        times, kinds = _robot_moves(placements, visits, relocation, move_time_s, yaw)
        order.append(visits)
        robot.append(np.full(visits.size, r))
        move_in.append(np.concatenate([[0.0], times]))
        kind.append(np.concatenate([np.array([""], dtype="<U5"), kinds]))
    cat = (lambda parts, dtype: np.concatenate(parts) if parts else np.zeros(0, dtype=dtype))  # noqa: E731
    return Moves(order=cat(order, int), robot=cat(robot, int), move_in_s=cat(move_in, float),
                 kind=cat(kind, "<U5"), robots=robots)


@dataclass(frozen=True)
class RelocationCost:
    """What the moves cost, in the user's cost unit (:func:`relocation_cost`)."""

    crane_hire: float
    rail: float
    carriages: float

    @property
    def total(self) -> float:
        return self.crane_hire + self.rail + self.carriages

    def as_dict(self) -> dict:
        """For summary.json: ``crane_hire``, ``rail``, ``carriages`` and their ``total``."""
        return {"crane_hire": self.crane_hire, "rail": self.rail, "carriages": self.carriages, "total": self.total}


NO_COST = RelocationCost(0.0, 0.0, 0.0)
"""The cost of moves without a relocation model."""


def carriage_drive_kW(rail: RailMoves, moved_kg: float) -> float:
    """A carriage drive's peak power: the force accelerating ``moved_kg`` (the frame with
    its winches and the platform) at the rail's ``accel_m_s2``, times its ``speed_m_s``
    (the drive's force and speed at once, as at the end of a double-S move's acceleration
    where it reaches its top speed; a bound on the power it draws), kW."""
    return float(moved_kg) * rail.accel_m_s2 * rail.speed_m_s / 1000.0


def relocation_cost(relocation: Relocation, moves: Moves, hours: float, band_length_m: float,
                    platform_kg: float = 0.0) -> RelocationCost:
    """What the moves cost (the module's rules), in the user's cost unit.

    Parameters
    ----------
    hours : float
        The job's hours (the slowest robot's), h.
    band_length_m : float
        The band's length along the ship (its stations' span), m: the rail's length.
    platform_kg : float
        The platform's mass, kg: the carriage's drive accelerates it with the frame
        (``rail.drive_cost_per_kW``).

    Returns
    -------
    RelocationCost
        Crane hire, rail, carriages and their total.
    """
    robots = relocation.robots
    crane = relocation.crane is not None and moves.count("crane") > 0
    hire = robots * relocation.crane.hire_per_h * hours if crane else 0.0
    on_rail = relocation.mode == "rail"
    rail = relocation.rail.cost_per_m * band_length_m if on_rail else 0.0
    carriages = 0.0
    if on_rail:
        moves_on = relocation.rail
        drive = (moves_on.drive_cost_per_kW * carriage_drive_kW(moves_on, relocation.lifted_kg(platform_kg))
                 if moves_on.drive_cost_per_kW > 0.0 else 0.0)
        carriages = robots * (moves_on.carriage_cost + drive)
    return RelocationCost(float(hire), float(rail), float(carriages))


def level_rail_S(orientation_deg) -> np.ndarray | None:
    """The direction in S of a rail along a frame turned by ``orientation_deg`` (``ship.
    frame_orientation_deg``): its x axis laid level, (3,), not normalised; None where that
    axis stands vertical (no level rail along it)."""
    from marinecdpr.motion.ship import frame_axes

    x_S = frame_axes([float(v) for v in orientation_deg])[:, 0]
    level = np.array([x_S[0], x_S[1], 0.0])
    return None if np.linalg.norm(level) < 1e-6 else level


def rail_move_scenario(scenario, rail: RailMoves, distance_m: float, *, hold_C, mass_kg: float | None = None,
                       dwell_s: float = 2.0, tail_s: float = 5.0):
    """The scenario's frame carried ``distance_m`` along a straight rail from where it stands,
    the platform held still at ``hold_C`` and the tool off the hull: a rail move between two
    placements of one row, for the time domain (the carriage's accelerations a load the
    cables hold in the ship's motion).

    The rail runs from the frame's origin along its x axis laid level in S (a rail along the
    sheer); the frame keeps its orientation (a straight rail turns it by nothing). The
    carriage rests ``dwell_s``, moves at the rail's limits (:func:`rail_move_s`'s double-S
    move) and rests; the run lasts ``dwell_s`` + the move + ``tail_s``.

    Parameters
    ----------
    scenario : Scenario
        A frame set down on the ship (``ship.frame_origin_m``, ``frame_orientation_deg``).
    rail : RailMoves
        The carriage's limits.
    distance_m : float
        How far along the rail, m, > 0.
    hold_C : array_like, shape (3,)
        Where the platform is held in C, m.
    mass_kg : float, optional
        The carriage with the frame and its winches (its drive's force is then known).

    Returns
    -------
    Scenario
    """
    from marinecdpr.motion.rail import scurve_move
    from marinecdpr.scenario.schema import validated_scenario

    if not np.isfinite(distance_m) or distance_m <= 0.0:
        raise ValueError(f"a rail move's distance must be positive and finite, got {distance_m!r}")
    ship = scenario.ship
    if ship.carriage is not None:
        raise ScenarioError("the frame is carried on a rail already", key="ship.carriage", source=scenario.name)
    origin = np.asarray(ship.frame_origin_m, dtype=float)
    level = level_rail_S(ship.frame_orientation_deg)
    if level is None:
        raise ScenarioError("the frame's x axis stands vertical: no level rail along it", key="ship.frame_orientation_deg",
                            source=scenario.name)
    level /= np.linalg.norm(level)
    move = scurve_move(float(distance_m), rail.speed_m_s, rail.accel_m_s2, rail.jerk_m_s3)
    duration = dwell_s + float(move.duration_s) + tail_s
    hold = [float(v) for v in hold_C]
    data = scenario.model_dump(exclude_none=True)
    data.pop("cleaning", None)
    carriage = {"rail_m": [origin.tolist(), (origin + (distance_m + 1e-3) * level).tolist()],
                "speed_max_m_s": rail.speed_m_s, "accel_max_m_s2": rail.accel_m_s2, "jerk_max_m_s3": rail.jerk_m_s3,
                "stations_m": [0.0, float(distance_m)], "dwell_s": [float(dwell_s), float(tail_s)]}
    if mass_kg is not None:
        carriage["mass_kg"] = float(mass_kg)
    data["ship"] = dict(data["ship"], frame_origin_m=[0.0, 0.0, 0.0], carriage=carriage)
    data["trajectory"] = {"type": "line", "start_position_m": hold, "end_position_m": hold, "duration_s": 1.0}
    data["time"] = dict(data["time"], duration_s=duration)
    data["description"] = f"{scenario.name}: the frame carried {distance_m:.4g} m along a rail, the platform held"
    return validated_scenario(data)
