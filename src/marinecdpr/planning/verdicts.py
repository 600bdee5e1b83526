"""Why a plan cannot be flown, in words: the lines a user reads when the cables cannot hold the
platform, and the advice in them.

- :func:`infeasibility_line` :meth:`~marinecdpr.planning.planner.Plan.infeasibility`'s line:
  which steps, the first one's time and pose, and why there: the winches that cannot follow
  (:func:`winch_cause`) or the cables at their limits in the best tensions within them and
  the wrench still missing (:func:`limiting_cables`), with what the cables can give in the
  short direction and which limit to change (:func:`sizing_hint`), or the method to try;
- :func:`sampled_line` that line for a plan of some of a scenario's steps
  (:func:`~marinecdpr.planning.planner.sampled_infeasibility`);
- :class:`SingularPoses` where J~ loses rank, and what in the robot's layout to change;
- :func:`closer_line` the cables coming closer than ``robot.clearance_m``;
- :func:`describe_pose` a pose as a reader writes it, and the names of its components.

The planner (:mod:`marinecdpr.planning.planner`) computes; this module words what it found. Its
functions take a :class:`~marinecdpr.planning.planner.Plan` (``plan``) and read its fields; the
planner imports this module, never the other way round.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from marinecdpr.geometry.kinematics import cable_kinematics
from marinecdpr.geometry.rotations import matrix_from_euler
from marinecdpr.model.tension import EXACT_METHODS, TENSION_TOLERANCE, full_rank
from marinecdpr.scenario.robot import scaled_copy

__all__ = ["infeasibility_line", "sampled_line", "winch_cause", "limiting_cables", "sizing_hint", "direction_words",
           "closer_line", "describe_pose", "controlled_pose_names", "SingularPoses", "TWIST_NAMES",
           "WINCH_OVERSPEED", "WINCH_NO_TENSION"]

TWIST_NAMES = ("x", "y", "z", "rx", "ry", "rz")
"""Names of pose / twist components in C (positions m, angles rad)."""


def controlled_pose_names(controlled: tuple[int, ...]) -> list[str]:
    """Names of the controlled pose components: ("x", "z", "theta_y") for a planar robot."""
    if tuple(controlled) == (0, 2, 4):
        return ["x", "z", "theta_y"]
    return [TWIST_NAMES[j] for j in controlled]


WINCH_OVERSPEED, WINCH_NO_TENSION = 1, 2
"""Codes of :attr:`~marinecdpr.planning.planner.WinchBounds.limit`, each worded by :func:`winch_cause`."""


def infeasibility_line(plan, i: int, n_bad: int, n_steps: int, steps: str = "steps",
                       there: str = "") -> str:
    """:meth:`Plan.infeasibility`'s line for step ``i`` of ``plan``, first of ``n_bad``
    infeasible steps of ``n_steps`` (a chunk's step, for a plan made in chunks); ``steps``
    names them, ``there`` says more of step ``i`` (after its pose)."""
    pose = describe_pose(plan.pose[i], plan.controlled)
    message = (
        f"the cables cannot hold the platform within their tension limits at "
        f"{n_bad} of {n_steps} {steps}, first at t = {plan.t[i]:.4g} s ({pose}{there})"
    )
    cause = winch_cause(plan, i) or limiting_cables(plan, i)
    return message if cause is None else f"{message}: {cause}"


def winch_cause(plan, i: int) -> str | None:
    """Which of ``plan``'s winches cannot follow at step ``i`` (None if all can)."""
    if plan.winch is None or not plan.winch.limit[i].any():
        return None
    parts = []
    for code, why in ((WINCH_OVERSPEED, "the cable moves faster than its motor can turn "
                                         "(robot.winch.speed_max_rad_s)"),
                      (WINCH_NO_TENSION, "its torque and power give no tension within the cable's "
                                          "limits at that motion (robot.winch)")):
        cables = [str(c + 1) for c in np.flatnonzero(plan.winch.limit[i] == code)]
        if cables:
            parts.append(f"winch{'es' if len(cables) > 1 else ''} {', '.join(cables)}: {why}")
    return "; ".join(parts)


def limiting_cables(plan, i: int) -> str | None:
    """Why step ``i`` of ``plan`` is infeasible: the cables at their limits in the best attainable tensions.

    Solves the bounded least-squares problem min |J~_c^T T - w_c| subject to
    T_min <= T <= T_max at that step (moments weighted by 1 / the platform's
    anchor radius, so both rows are forces) and names the cables that sit on a
    limit in its solution, and the force and moment still missing,
    ``w_c - J~_c^T T``. None if the plan does not know its robot.
    """
    from scipy.optimize import lsq_linear

    robot = plan.robot
    if robot is None:
        return None
    c = list(plan.controlled)
    kin = cable_kinematics(plan.pose[i : i + 1, :3], matrix_from_euler(plan.pose[i : i + 1, 3:]),
                           robot.frame_anchors, robot.platform_anchors)
    A = kin.J_tilde[0][:, c].T
    w = plan.wrench[i, c]
    if not (np.isfinite(A).all() and np.isfinite(w).all()):
        return None
    lo, hi = robot.tension_min, robot.tension_max
    if plan.winch is not None:  # what the winches can give at that step
        lo, hi = plan.winch.lower[i], plan.winch.upper[i]
    is_moment = np.array(c) >= 3
    radius = max(float(np.linalg.norm(robot.platform_anchors, axis=1).max()), 1e-3)
    weight = np.where(is_moment, 1.0 / radius, 1.0)
    T = np.clip(lsq_linear(A * weight[:, None], w * weight, bounds=(lo, hi), method="bvls").x, lo, hi)
    missing = w - A @ T
    # what the tension solver's own tolerance on the limits can make up (J~'s force rows
    # are unit vectors, its moment rows weighted to forces), with lsq_linear's rounding
    tol = len(lo) * TENSION_TOLERANCE * max(1.0, float(hi.max())) + 1e-12 * float(np.abs(w * weight).max())
    force, moment = missing[~is_moment], missing[is_moment]
    f, m = float(np.linalg.norm(force)), float(np.linalg.norm(moment))
    singular = None  # J~'s rank test as the tension solver has it, and the layout's part in it
    if not full_rank(A.T[None])[0]:
        scale = scaled_copy(robot)
        singular = "J~ loses rank there (a singular pose" + (
            "" if scale is None else f"; the platform's anchors are a scaled copy (x {scale:.3g}) of the "
            "frame's: `marinecdpr check` says what to change") + ")"
    if f <= tol and m <= tol * radius:
        if singular:
            return singular
        if plan.method in EXACT_METHODS:
            return (f"tensions within the limits exist there, but the {plan.method.replace('_', ' ')} "
                    f"method did not find them, nor its exact fallback (report it, please)")
        return (f"tensions within the limits exist there, but the {plan.method.replace('_', ' ')} "
                f"method did not find them: the minimum variance method does (planning.method = "
                f"\"minimum_variance\", or --method minimum_variance)")
    axes = np.array([name[-1] for name in np.array(TWIST_NAMES)[c]])  # "x", "z", "y" of ry...
    short, lacking = [], None
    for value, part, unit, word, axis_word, rows in ((f, force, "N", "force", "along", ~is_moment),
                                                     (m, moment, "N m", "moment", "about", is_moment)):
        if value > (tol if unit == "N" else tol * radius):
            short.append(f"{value:.4g} {unit} of {word} ({axis_word} {direction_words(part / value, axes[rows])})")
            if lacking is None or (unit == "N m" and m / radius > f):  # the larger shortfall, as a force
                lacking = (word, unit, axis_word, np.flatnonzero(rows), part / value)
    at, n_at = [], 0
    tol_T = 1e-6 * float(hi.max())
    labels = ("T_min", "T_max") if plan.winch is None else ("its winch's least", "its winch's most")
    for label, on, limit in ((labels[0], T <= lo + tol_T, lo), (labels[1], T >= hi - tol_T, hi)):
        for value in sorted(set(limit[on].tolist())):
            cables = [str(k + 1) for k in np.flatnonzero(on & (limit == value))]
            n_at += len(cables)
            at.append(f"cable{'s' if len(cables) > 1 else ''} {', '.join(cables)} at {label} = {value:g} N")
    who = (", ".join(at[:-1]) + " and " + at[-1]) if len(at) > 1 else (at[0] if at else "the best tensions")
    prefix = f"{singular}; " if singular else ""
    line = f"{prefix}at best, {who} still leave{'s' if n_at == 1 else ''} {' and '.join(short)} short"
    if singular:
        return line
    return line + sizing_hint(A, w, lo, hi, lacking, axes, plan.winch is not None)


def sampled_line(plan, i: int, n_bad: int, n_planned: int, n_steps: int,
                 at_rest_weight_N: float | None = None) -> str:
    """:func:`infeasibility_line` for a plan of ``n_planned`` of a scenario's ``n_steps`` steps
    (:func:`~marinecdpr.planning.planner.sampled_infeasibility`): step ``i`` of ``plan`` the
    first of ``n_bad`` infeasible ones; with ``at_rest_weight_N`` (the platform at rest on a
    still frame there), what the wrench then is: the platform's weight alone, N."""
    what = "steps" if n_planned == n_steps else f"steps planned (spread over its {n_steps})"
    there = ""
    if at_rest_weight_N is not None:
        there = f"; at rest on a still frame: the wrench is the platform's weight alone, {at_rest_weight_N:.4g} N"
    return infeasibility_line(plan, i, n_bad, n_planned, what, there)


def direction_words(d: np.ndarray, axes) -> str:
    """A unit vector over the named axes as a reader would write it: ``+z`` where one axis
    carries it (90 % or more), else its components, ``+0.77 x, -0.64 z``."""
    k = int(np.argmax(np.abs(d)))
    if abs(d[k]) >= 0.9:
        return f"{'+' if d[k] > 0 else '-'}{axes[k]}"
    return ", ".join(f"{v:+.2g} {a}" for v, a in zip(d, axes) if abs(v) >= 0.005)


def sizing_hint(A: np.ndarray, w: np.ndarray, lo: np.ndarray, hi: np.ndarray, lacking, axes,
                winches: bool) -> str:
    """What the cables can give in the DOF that is short, with the rest of the wrench held, and
    which change of the robot gives more: the part of :meth:`Plan.limiting_cables`'s line after
    the shortfall.

    The range is two linear programmes over T_min <= T <= T_max: the smallest and largest
    component r of J~_c^T T with every other component equal to w's (scipy's HiGHS); left out
    where no tensions hold the rest. The change advised follows the end of the range the need
    lies beyond: the programme's duals on the tension bounds tell how far that end moves per
    newton of lower least tensions and of higher most tensions; where only the least tensions
    hold it (cables at T_min pulling the wrong way), lowering ``robot.tension_min_N`` is
    advised, not raising ``robot.tension_max_N``; where both do and lowering the least
    tensions towards 0 could close the gap, both, the stronger first; where only the least
    tensions hold it and not even 0 N closes the gap, no limit is named.

    Parameters
    ----------
    A : ndarray, shape (k, n_cables)
        J~_c^T at the step.
    w : ndarray, shape (k,)
        The required wrench's controlled part, N and N m.
    lo, hi : ndarray, shape (n_cables,)
        The tension bounds at the step, N.
    lacking : tuple
        (word, unit, axis word, rows, direction) of the short part (force or moment).
    axes : ndarray of str, shape (k,)
        The axis letter of each controlled component.
    winches : bool
        Are the bounds the winches' (the limit to raise is then theirs)?
    """
    from scipy.optimize import linprog

    word, unit, axis_word, rows, d = lacking
    r = int(rows[int(np.argmax(np.abs(d)))])  # the component that carries most of the shortfall
    others = np.array([q for q in range(len(w)) if q != r], dtype=int)
    span, gains = [], []
    for sign in (1.0, -1.0):
        res = linprog(sign * A[r], A_eq=A[others] if others.size else None,
                      b_eq=w[others] if others.size else None, bounds=list(zip(lo, hi)), method="highs")
        ok = res.status == 0
        span.append(float(A[r] @ res.x) if ok else np.nan)
        # what moving each side's limits by 1 N gives that end of the range (HiGHS's duals):
        # lowering the least tensions, raising the most
        gains.append((float(np.sum(res.lower.marginals)), float(-np.sum(res.upper.marginals)),
                      float(np.sum(res.lower.marginals * np.maximum(lo, 0.0)))) if ok else None)
    out = ""
    raise_max = f"raise {'the winches' + chr(39) + ' torque and power (robot.winch)' if winches else 'robot.tension_max_N'}"
    change = raise_max
    if np.isfinite(span).all():
        # as many digits as tell the need from the nearer end of the range
        end = 0 if abs(w[r] - span[0]) < abs(w[r] - span[1]) else 1
        near = span[end]
        gap = abs(w[r] - near)
        digits = 4 if gap == 0.0 else int(min(12, max(4, np.ceil(np.log10(max(abs(near), abs(w[r])) / gap)) + 2)))
        out = (f"; with the rest of the wrench held the cables give {span[0]:.{digits}g} to {span[1]:.{digits}g} "
               f"{unit} {axis_word} {axes[r]} there, against {w[r]:.{digits}g} {unit} needed")
        # the side of the range the need falls on, and which limits hold that end there
        lower_min = (f"lower {'the least tension the winches hold (robot.winch)' if winches else 'robot.tension_min_N'}"
                     f" (cables held at their least tension pull the wrong way there)")
        # (per newton; the least tensions go no lower than 0: where even that falls short of the
        # gap, as far as the duals tell, only the most tensions' side is named if it helps)
        g_lo, g_hi, reach_lo = gains[end]
        small = 1e-9 * max(1.0, g_lo, g_hi)
        if g_lo > small and g_hi <= small:
            change = lower_min if reach_lo >= gap else None  # (not below 0 N: then no limit helps)
        elif g_lo > small and g_hi > small and reach_lo >= gap:
            change = f"{lower_min} or {raise_max}" if g_lo > g_hi else f"{raise_max} or {lower_min}"
    if word == "moment":
        return out + (f": spread the platform's anchors wider (robot.cables platform_anchor_m: the moment grows "
                      f"with their spacing){'' if change is None else ' or ' + change}; a brush's reaction moment "
                      "is cancelled by a counter-rotating pair (cleaning.brush = \"pair\")")
    if change is None:
        return out + (": no change of the tension limits closes it (not even 0 N for the cables held at their "
                      "least tension, which pull the wrong way there): move the frame anchors so that more cables "
                      "pull that way (robot.cables frame_anchor_m)")
    return out + (f": {change}, or move the frame anchors so that more cables pull that way "
                  "(robot.cables frame_anchor_m)")


def closer_line(clearance_m: float, n_close: int, n_steps: int, first: str) -> str:
    """The line saying the cables come closer than ``clearance_m`` (m) at ``n_close`` of
    ``n_steps`` steps, the first described by ``first``."""
    return (f"the cables come closer than robot.clearance_m = {clearance_m:g} m at {n_close} of {n_steps} steps, "
            f"first at {first}")


def describe_pose(pose: np.ndarray, controlled: tuple[int, ...]) -> str:
    """A pose's controlled DOFs as a reader would write them: ``x = 2.38 m, z = 1.5 m,
    theta_y = 0 deg``.

    Parameters
    ----------
    pose : ndarray, shape (6,)
        (x, y, z) in C, m, and the XYZ Euler angles, rad.
    controlled : tuple of int
        Indices into ``pose`` of the controlled DOFs.
    """
    return ", ".join(
        f"{name} = {pose[j] if j < 3 else np.degrees(pose[j]):.4g}{' m' if j < 3 else ' deg'}"
        for name, j in zip(controlled_pose_names(controlled), controlled)
    )


@dataclass(frozen=True)
class SingularPoses:
    """Poses of a survey at which J~ loses rank on the controlled DOFs (singular poses).

    Attributes
    ----------
    what : str
        The poses surveyed, as a reader would name them (``"steps of the trajectory"``,
        ``"level poses across the frame"``).
    n_poses, n_singular : int
        Poses surveyed, and singular among them.
    first : str or None
        The first singular pose, described (:func:`describe_pose`, with its time for a
        trajectory); None if none is.
    scale : float or None
        :func:`~marinecdpr.scenario.robot.scaled_copy` of the robot: the ratio of its
        platform's anchor pattern to its frame's where it is a scaled copy (which makes
        every level pose singular), else None.
    level : bool
        Are the poses surveyed all level (where a scaled copy is singular)?
    between : str or None
        A singular set found between the poses surveyed (a survey's grid can miss a plane
        at one height: :func:`~marinecdpr.studies.workspace.singular_set`), named, e.g.
        ``"on the plane z = 1.95 m (found between the grid's points, on 136 of the 432 lines along
        its axes searched)"``;
        None if none was searched for or found.
    """

    what: str
    n_poses: int
    n_singular: int
    first: str | None
    scale: float | None
    level: bool
    between: str | None = None

    def message(self, *, hint: bool = True) -> str | None:
        """One line for a user: where J~ loses rank and (with ``hint``, where the robot's
        layout is the cause) what in the robot to change, or None if no pose surveyed is
        singular."""
        if self.n_singular == 0 and self.between is None:
            return None
        count = (f"every one of the {self.n_poses}" if self.n_singular == self.n_poses
                 else f"{self.n_singular} of the {self.n_poses}")
        where = []
        if self.n_singular:
            where.append(f"at {count} {self.what}, first at {self.first}")
        if self.between is not None:
            where.append(f"{self.between}, among the {self.n_poses} {self.what}")
        line = (f"J~ loses rank (a singular pose) {'; and '.join(where)}: there the "
                f"cables cannot give every component of the wrench, and no plan holds the platform")
        if hint and self.scale is not None:
            line += (f"; the platform's anchors are a scaled copy (x {self.scale:.3g}) of the frame's, so at every "
                     f"level pose all the cables' lines meet at one point and no tensions give a moment about "
                     f"it: give the platform's anchor pattern another shape (aspect ratio) than the frame's")
        return line
