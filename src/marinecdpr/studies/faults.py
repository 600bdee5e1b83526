"""What a single fault does to the robot at the job's hardest moments (issue 40, item 4).

Each fault of a list (a cable snapping, a winch's brake, a motor losing its power, a load
cell's or an encoder's fault, the controller missing its deadline: ``[[faults]]``' kinds,
:mod:`marinecdpr.scenario.faults`) strikes one cable at a time at one moment of the job, and
the job is flown closed loop up to ``after_s`` past it, with the controller's watch and its
reaction (``[simulation.control.safety]``). The moments, unless given: the plan's step of the
highest cable tension, and of the platform's highest speed (relative to the frame C), each
within [``EARLIEST_S``, the job's duration less ``after_s``] (a later one could not be flown
for ``after_s``; the watch needs its first exchanges).

Per fault (:class:`FaultRow`): whether the watch detected it and how long after it acted;
the controller's reaction at the end; after the fault, the platform's largest deviation from
its plan and from where it was when the fault struck, and its largest speed; whether its body
(the platform's cable anchors, x + R p_i, in C) stays within the frame's box (the frame
anchors' bounding box, along the controlled translations) and, where it leaves it, its speed
and translational kinetic energy there; whether it moves towards the hull (``[cleaning]``'s
hull plane, through the brush's planned position, normal ``hull_normal``) beyond
``HULL_CONTACT_M`` of its plan, and its speed and energy along the normal there; the
remaining cables' peak tension against each cable's breaking load (the robot's
``breaking_load``: ``breaking_load_N`` where given, else its working limit ``tension_max``
stands in) and against its working limit (``tension_max``), the cable the one loaded most
against its breaking load (a snap load); the static margin of the remaining cables at the fault's pose
(:func:`~marinecdpr.planning.redundancy.single_failure_margin`, for a cable lost); and a
verdict: ``"safe"``, or why not in one clause (:func:`verdict`).

Velocities are the logged positions' central differences (:func:`numpy.gradient`), m/s.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from marinecdpr.errors import SimulationDivergedError
from marinecdpr.geometry.rotations import matrix_from_euler
from marinecdpr.planning.redundancy import single_failure_margin
from marinecdpr.scenario.schema import Scenario

__all__ = ["FaultCase", "FaultRow", "FaultStudy", "hardest_moments", "fault_entry", "judge_run", "verdict",
           "fault_study", "combined", "EARLIEST_S", "HULL_CONTACT_M", "REST_M_S", "CABLE_LOST"]

EARLIEST_S = 0.1
"""The earliest moment a fault is flown at, s (the watch compares each reading with the one before)."""
HULL_CONTACT_M = 1e-3
"""A platform that moves this far towards the hull beyond its plan (which holds the brush on the
hull) meets it, m."""
REST_M_S = 0.02
"""A platform slower than this in C at the run's end has come to rest, m/s."""
CABLE_LOST = ("cable_snap", "motor_power_loss")
"""Faults after which the cable may no longer hold: the static margin without it is said."""


@dataclass(frozen=True)
class FaultCase:
    """One fault flown: its kind, cable (from 1; None for the controller), when, and which
    moment that is ("highest tension", "highest speed" or "given")."""

    kind: str
    cable: int | None
    at_s: float
    moment: str


@dataclass(frozen=True)
class FaultRow:
    """One fault's outcome (a row of ``faults.csv``). Times in s, lengths in m, speeds in m/s,
    energies in J, tensions in N; NaN where not applicable (no detection, the frame or the hull
    not met, the run lost).

    Attributes
    ----------
    kind, cable, moment, at_s : as :class:`FaultCase`'s
    acted_s : float
        The exchange from which the fault acted (SimResult.faults), s.
    detected : bool
    detection_delay_s : float
        The first detection at or after the fault acted, less acted_s.
    detection : str
        Its kind (and sensor, or cable from 1), "" where none.
    reaction : str
        The controller's reaction at the run's end (normal, go_on, park, stop, brake).
    brakes_held : int
        Drums a brake held.
    max_deviation_m, max_displacement_m, max_speed_m_s : float
        After the fault: the platform's largest distance from its plan, from its position at
        the fault, and its largest speed relative to C.
    end_deviation_m, end_speed_m_s : float
        At the run's end: its distance from its plan and its speed in C.
    within_frame : bool
        The platform's body stays within the frame's box over the whole run.
    frame_time_s, frame_speed_m_s, frame_energy_J : float
        Where its body first leaves the box: when, its speed, 1/2 m v^2.
    hull_speed_m_s, hull_energy_J : float
        Where it first meets the hull: its speed towards the hull and 1/2 m v_n^2.
    peak_tension_N : float
        The largest tension after the fault of ``peak_cable`` (from 1), the remaining cable
        loaded most against its breaking load (with one breaking load for all: the largest
        tension of any).
    working_limit_N : float
        That cable's working limit (``tension_max``).
    breaking_N : float
        That cable's breaking load (``breaking_load_N``; where not given, its working limit
        stands in).
    static_margin_N : float
        A cable lost: the margin by which the others hold the plan's wrench at the fault's
        pose within their limits (< 0: they cannot), N.
    verdict : str
        "safe", or why not.
    hs_m, tp_s, heading_deg : float
        The sea state flown (NaN without one).
    """

    kind: str
    cable: int | None
    moment: str
    at_s: float
    acted_s: float
    detected: bool
    detection_delay_s: float
    detection: str
    reaction: str
    brakes_held: int
    max_deviation_m: float
    max_displacement_m: float
    max_speed_m_s: float
    end_deviation_m: float
    end_speed_m_s: float
    within_frame: bool
    frame_time_s: float
    frame_speed_m_s: float
    frame_energy_J: float
    hull_speed_m_s: float
    hull_energy_J: float
    peak_tension_N: float
    peak_cable: int
    working_limit_N: float
    breaking_N: float
    static_margin_N: float
    verdict: str
    hs_m: float = float("nan")
    tp_s: float = float("nan")
    heading_deg: float = float("nan")


@dataclass(frozen=True)
class FaultStudy:
    """The faults flown on one scenario, in one sea state or several (:func:`combined`).

    Attributes
    ----------
    scenario : str
    plant : str
    seas : tuple of dict
        The sea states flown (hs_m, tp_s, heading_deg), ({},) without one.
    after_s : float
        Flown past each fault, s.
    rows : tuple of FaultRow
    traces : tuple of (t, x) per row
        The platform's positions (n, 3) in C over time (n,), s, m: its trajectory.
    frame_box : ndarray, shape (2, 3)
        The frame's box in C (its lower and upper corners), m.
    """

    scenario: str
    plant: str
    seas: tuple
    after_s: float
    rows: tuple
    traces: tuple = field(repr=False, default=())
    frame_box: np.ndarray = field(repr=False, default=None)

    @property
    def unsafe(self) -> tuple:
        return tuple(r for r in self.rows if r.verdict != "safe")


def hardest_moments(plan, *, earliest_s: float, latest_s: float) -> list[tuple[str, float]]:
    """The plan's step of the highest cable tension and of the platform's highest speed in C,
    within [earliest_s, latest_s]: [("highest tension", t), ("highest speed", t)] (one entry
    where both are the same step)."""
    t = plan.t
    inside = (t >= earliest_s - 1e-12) & (t <= latest_s + 1e-12)
    idx = np.flatnonzero(inside)
    k_T = idx[int(np.argmax(plan.tensions[idx].max(axis=1)))]
    k_v = idx[int(np.argmax(np.linalg.norm(plan.twist[idx, :3], axis=1)))]
    out = [("highest tension", float(t[k_T]))]
    if k_v != k_T:
        out.append(("highest speed", float(t[k_v])))
    return out


def fault_entry(case: FaultCase, *, sensor_mode: str, drift_per_s: float, brake_delay_s: float | None,
                deadline_steps: int) -> dict:
    """The ``[[faults]]`` entry that flies ``case``."""
    f = {"kind": case.kind, "at_s": case.at_s}
    if case.kind == "controller_deadline":
        f["steps"] = deadline_steps
        return f
    if case.kind == "brush_contact_loss":
        return f
    if case.kind == "mru":
        f["mode"] = sensor_mode
        if sensor_mode == "drift":
            f["drift_per_s"] = drift_per_s
        return f
    f["cable"] = case.cable
    if case.kind in ("load_cell", "encoder"):
        f["mode"] = sensor_mode
        if sensor_mode == "drift":
            f["drift_per_s"] = drift_per_s
    elif case.kind in ("winch_brake", "motor_power_loss") and brake_delay_s is not None:
        f["brake_delay_s"] = brake_delay_s
    return f


def frame_box(scenario: Scenario) -> np.ndarray:
    """The frame's box in C: the frame anchors' bounding box along the controlled
    translations, unbounded along the others. Shape (2, 3), m."""
    c = scenario.robot.frame_anchors
    box = np.array([c.min(axis=0), c.max(axis=0)])
    free = [i for i in range(3) if i not in scenario.robot.controlled]
    box[0, free], box[1, free] = -np.inf, np.inf
    return box


def body_points(scenario: Scenario, pose: np.ndarray) -> np.ndarray:
    """The platform's body (its cable anchors) in C at each pose (n, 6): (n, m, 3), m."""
    R = matrix_from_euler(pose[:, 3:])
    return pose[:, None, :3] + np.einsum("nij,mj->nmi", R, scenario.robot.platform_anchors)


def verdict(row: dict, *, error_bound_m: float) -> str:
    """"safe", or the first reason it is not, in this order: the run lost; the platform's body
    leaving the frame (where the remaining cables cannot hold it there, said with their static
    margin); it meeting the hull; a remaining cable beyond its breaking load (``breaking_N``:
    the robot's ``breaking_load_N``, or where unknown its working limit ``tension_max``); a
    fault that acted, undetected, taking the platform off its plan beyond the error bound."""
    if row["lost"]:
        return "the platform is lost (the run diverged: more than 10 m off its plan)"
    if not row["within_frame"]:
        why = (f" (the other cables cannot hold it there: static margin {row['static_margin_N']:.0f} N)"
               if np.isfinite(row["static_margin_N"]) and row["static_margin_N"] < 0 else "")
        return (f"leaves the frame {row['frame_time_s'] - row['acted_s']:.3g} s after the fault at "
                f"{row['frame_speed_m_s']:.2g} m/s ({row['frame_energy_J']:.2g} J){why}")
    if np.isfinite(row["hull_speed_m_s"]):
        return f"meets the hull at {row['hull_speed_m_s']:.2g} m/s ({row['hull_energy_J']:.2g} J)"
    if row["peak_tension_N"] > row["breaking_N"]:
        return (f"cable {row['peak_cable']} pulls {row['peak_tension_N']:.0f} N, beyond its breaking load "
                f"{row['breaking_N']:.0f} N")
    if not row["detected"] and row["max_deviation_m"] > error_bound_m:
        return f"undetected, {row['max_deviation_m']:.2g} m off its plan (bound {error_bound_m:.2g} m)"
    if row["end_deviation_m"] > error_bound_m and row["end_speed_m_s"] > REST_M_S:
        return (f"neither on its plan nor at rest at the run's end ({row['end_deviation_m']:.2g} m off it, "
                f"{row['end_speed_m_s']:.2g} m/s)")
    return "safe"


def judge_run(scenario: Scenario, case: FaultCase, res, plan, *, k_fault: int) -> dict:
    """A flown fault's figures (:class:`FaultRow`'s fields but ``verdict``, and ``lost``) from
    the run ``res`` (SimResult) of ``scenario`` (its one fault, ``case``) and the plan it flew."""
    robot = scenario.robot
    t, pose, h = res.t, res.pose, scenario.time.step_s
    acted = res.faults[0]["acted_s"]
    k0 = k_fault if acted is None else int(round(acted / h))
    acted = float(k0 * h) if acted is None else acted
    x = pose[:, :3]
    v = np.gradient(x, t, axis=0) if t.size > 1 else np.zeros_like(x)
    speed = np.linalg.norm(v, axis=1)
    after = slice(k0, None)
    row = dict(kind=case.kind, cable=case.cable, moment=case.moment, at_s=case.at_s, acted_s=acted, lost=False)
    det = [d for d in res.detections if d.step >= k0]
    row["detected"] = bool(det)
    row["detection_delay_s"] = det[0].t - acted if det else np.nan
    row["detection"] = "" if not det else (det[0].kind + (f" ({det[0].sensor})" if det[0].sensor else "")
                                           + (f" cable {det[0].cable + 1}" if det[0].cable >= 0 else ""))
    row["reaction"] = res.reaction
    row["brakes_held"] = len(res.brakes_held)
    row["max_deviation_m"] = float(np.linalg.norm(x[after] - res.pose_planned[after, :3], axis=1).max())
    row["max_displacement_m"] = float(np.linalg.norm(x[after] - x[k0], axis=1).max())
    row["max_speed_m_s"] = float(speed[after].max())
    row["end_deviation_m"] = float(np.linalg.norm(x[-1] - res.pose_planned[-1, :3]))
    row["end_speed_m_s"] = float(speed[-1])
    box = frame_box(scenario)
    pts = body_points(scenario, pose)
    outside = np.any((pts < box[0] - 1e-9) | (pts > box[1] + 1e-9), axis=(1, 2))
    row["within_frame"] = not bool(outside.any())
    if outside.any():
        k = int(np.argmax(outside))
        row["frame_time_s"], row["frame_speed_m_s"] = float(t[k]), float(speed[k])
        row["frame_energy_J"] = 0.5 * robot.mass_kg * float(speed[k]) ** 2
    else:
        row["frame_time_s"] = row["frame_speed_m_s"] = row["frame_energy_J"] = np.nan
    row["hull_speed_m_s"] = row["hull_energy_J"] = np.nan
    if scenario.cleaning is not None:  # towards the hull: along -n, beyond the plan that holds the brush on it
        n = np.asarray(scenario.cleaning.hull_normal, dtype=float)
        into = -(x - res.pose_planned[:, :3]) @ n
        met = np.flatnonzero(into[after] > HULL_CONTACT_M)
        if met.size:
            k = k0 + int(met[0])
            vn = max(0.0, float(-v[k] @ n))
            row["hull_speed_m_s"], row["hull_energy_J"] = vn, 0.5 * robot.mass_kg * vn ** 2
    remaining = np.ones(robot.n_cables, dtype=bool)
    if case.kind in CABLE_LOST[:1]:
        remaining[case.cable - 1] = False
    cables = np.flatnonzero(remaining)
    peaks = res.tensions[after][:, remaining].max(axis=0)
    breaking = robot.breaking_load[cables]
    load = peaks / breaking
    most = np.flatnonzero(load == load.max())  # of these, the largest tension (one breaking load: the largest of all)
    j = int(most[np.argmax(peaks[most])])
    row["peak_tension_N"], row["peak_cable"] = float(peaks[j]), int(cables[j] + 1)
    row["working_limit_N"] = float(robot.tension_max[cables[j]])
    row["breaking_N"] = float(breaking[j])
    row["static_margin_N"] = np.nan
    if case.kind in CABLE_LOST:
        kp = min(k0, plan.pose.shape[0] - 1)
        margin = single_failure_margin(robot, plan.pose[kp:kp + 1, :3], matrix_from_euler(plan.pose[kp:kp + 1, 3:]),
                                       plan.wrench[kp:kp + 1])
        row["static_margin_N"] = float(margin[0, case.cable - 1])
    return row


def lost_row(case: FaultCase, scenario: Scenario, k_fault: int) -> dict:
    """A run that diverged: nothing measured but that it was lost."""
    nan = np.nan
    return dict(kind=case.kind, cable=case.cable, moment=case.moment, at_s=case.at_s,
                acted_s=k_fault * scenario.time.step_s, lost=True, detected=False, detection_delay_s=nan,
                detection="", reaction="", brakes_held=0, max_deviation_m=nan, max_displacement_m=nan,
                max_speed_m_s=nan, end_deviation_m=nan, end_speed_m_s=nan, within_frame=False, frame_time_s=nan, frame_speed_m_s=nan, frame_energy_J=nan,
                hull_speed_m_s=nan, hull_energy_J=nan, peak_tension_N=nan, peak_cable=0, working_limit_N=nan,
                breaking_N=nan,
                static_margin_N=nan)


def fault_study(scenario: Scenario, cases: list[FaultCase], *, after_s: float, plant: str, plan=None,
                sensor_mode: str = "dropout", drift_per_s: float = 1.0, brake_delay_s: float | None = None,
                deadline_steps: int = 50, sea: dict | None = None,
                progress: Callable[[int, int], None] | None = None) -> FaultStudy:
    """Each case flown closed loop on ``plant`` from the job's start to ``after_s`` past its
    fault, on the plan of ``scenario`` (computed here where not given), and judged
    (:func:`judge_run`, :func:`verdict`).

    Parameters
    ----------
    scenario : Scenario
        The job (its sea), without ``[[faults]]``; its time covers every case's run.
    cases : list of FaultCase
    after_s : float
        Flown past each fault, s.
    plant : {"mujoco", "own"}
    """
    from marinecdpr.planning.planner import plan as make_plan
    from marinecdpr.prototype.simulation import simulate
    from marinecdpr.studies.prototype_runs import error_bounds

    plan = make_plan(scenario) if plan is None else plan
    h = scenario.time.step_s
    bound_m = error_bounds(scenario)[0]
    rows, traces = [], []
    for i, case in enumerate(cases):
        k_fault = int(np.ceil(case.at_s / h - 1e-9))
        entry = fault_entry(case, sensor_mode=sensor_mode, drift_per_s=drift_per_s, brake_delay_s=brake_delay_s,
                            deadline_steps=deadline_steps)
        faulty = scenario.with_changes(faults=[entry])
        n = min(k_fault + int(round(after_s / h)) + 1, scenario.time.n_steps)
        try:
            res = simulate(faulty, run="closed_loop", plant=plant, reference=plan, n_steps=n)
        except SimulationDivergedError:
            row = lost_row(case, scenario, k_fault)
            traces.append((np.zeros(0), np.zeros((0, 3))))
        else:
            row = judge_run(faulty, case, res, plan, k_fault=k_fault)
            traces.append((res.t, res.pose[:, :3].copy()))
        rows.append(FaultRow(**{k: v for k, v in row.items() if k != "lost"},
                             verdict=verdict(row, error_bound_m=bound_m), **(sea or {})))
        if progress is not None:
            progress(i + 1, len(cases))
    return FaultStudy(scenario=scenario.name, plant=plant, seas=(dict(sea or {}),), after_s=after_s,
                      rows=tuple(rows), traces=tuple(traces), frame_box=frame_box(scenario))


def combined(studies: list[FaultStudy]) -> FaultStudy:
    """One study of several (one scenario, plant and ``after_s``; a sea state each): their
    sea states, rows and traces in order."""
    first = studies[0]
    return FaultStudy(scenario=first.scenario, plant=first.plant, seas=tuple(s for st in studies for s in st.seas),
                      after_s=first.after_s, rows=tuple(r for st in studies for r in st.rows),
                      traces=tuple(t for st in studies for t in st.traces), frame_box=first.frame_box)
