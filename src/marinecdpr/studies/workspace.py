"""Where on the frame the robot can hold the platform while the ship moves.

For a grid of platform poses (held still relative to the frame) and the scenario's
ship motion, the plan at every step says whether tensions within limits exist; the
map reports, per pose, the fraction of time they do, the smallest tension margin, and
the fraction of time the pseudo-inverse solution (eq. 18) alone is already within limits.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from marinecdpr.errors import ScenarioError
from marinecdpr.planning.planner import DEFAULT_CHUNK_STEPS, plan_at, ship_motion_at
from marinecdpr.planning.verdicts import SingularPoses, describe_pose
from marinecdpr.scenario.schema import Scenario

__all__ = ["WorkspaceMap", "workspace_map", "tension_margin", "pose_range", "singular_poses", "singular_set",
           "map_singular_poses"]

AXES = {"x": 0, "y": 1, "z": 2}


@dataclass(frozen=True)
class WorkspaceMap:
    """Feasibility over a grid of poses in C.

    Attributes
    ----------
    axes : tuple of str
        The two grid axes, e.g. ("x", "z").
    u, v : ndarray, shape (n_u,), (n_v,)
        Grid coordinates of the platform's centre along them, m: evenly inside the range
        where the platform, held at the given orientation, fits within the frame (see
        :func:`pose_range`).
    fraction_feasible : ndarray, shape (n_u, n_v)
        Fraction of the time steps with tensions within limits (NaN: the platform
        would leave the frame there; only where it cannot fit at all).
    min_margin_N : ndarray, shape (n_u, n_v)
        Smallest distance of the chosen method's tensions to their limits over the
        record, N (0 where the method rests a cable on a limit; -inf where some step is
        infeasible).
    pinv_fraction_feasible : ndarray, shape (n_u, n_v)
        Fraction of steps where eq. (18) alone is within limits.
    fixed : dict
        The other coordinate and the orientation held, m and deg.
    n_steps : int
        Time steps per pose.
    least_clearance_m : ndarray, shape (n_u, n_v), optional
        With ``robot.clearance_m``: the least distance of any cable to another cable, the
        platform's body or an obstacle at the held pose, m (the pose is held in C and the
        obstacles are fixed to the frame, so the ship's motion does not change it; NaN where
        the platform would leave the frame). The pose is interference-free where it is at
        least the clearance (:attr:`interference_free`). None without.
    clearance_m : float, optional
        ``robot.clearance_m``.
    singular : ndarray of bool, shape (n_u, n_v), optional
        Poses at which J~ loses rank (held in C, so at every step; the tension solver's rank
        test): no plan holds the platform there (:func:`map_singular_poses` names them).
    """

    axes: tuple[str, str]
    u: np.ndarray
    v: np.ndarray
    fraction_feasible: np.ndarray
    min_margin_N: np.ndarray
    pinv_fraction_feasible: np.ndarray
    fixed: dict
    n_steps: int
    least_clearance_m: np.ndarray | None = None
    clearance_m: float | None = None
    singular: np.ndarray | None = None

    @property
    def interference_free(self) -> np.ndarray | None:
        """Poses at which no cable comes closer than the clearance to anything, shape
        (n_u, n_v) of bool (False where the platform would leave the frame); None without a
        clearance."""
        if self.least_clearance_m is None:
            return None
        with np.errstate(invalid="ignore"):
            return self.least_clearance_m >= self.clearance_m


def tension_margin(T: np.ndarray, t_min: np.ndarray, t_max: np.ndarray) -> np.ndarray:
    """Smallest distance of each step's tensions to their limits, shape (n_steps,), N (NaN if infeasible)."""
    return np.minimum(T - t_min, t_max - T).min(axis=1)


def pose_range(scenario: Scenario, orientation_deg: tuple[float, float, float] = (0.0, 0.0, 0.0)
               ) -> tuple[np.ndarray, np.ndarray]:
    """Where the platform's centre can be with the platform inside the frame: (lo, hi), m, in C.

    The frame is the box of the frame anchors (as the trajectory check has it); along each
    axis the range is inset by the platform's extent there (its anchors at the given
    orientation, and its centre), so every platform anchor stays within the frame.
    Along an axis where the frame has no extent (a planar robot's y), or where the
    platform is wider than the frame, the frame anchors' range is returned.
    """
    from marinecdpr.geometry.rotations import matrix_from_euler

    c = scenario.robot.frame_anchors
    lo, hi = c.min(axis=0), c.max(axis=0)
    anchors = scenario.robot.platform_anchors @ matrix_from_euler(np.radians(np.asarray(orientation_deg,
                                                                                        dtype=float))).T
    in_lo = lo - np.minimum(anchors.min(axis=0), 0.0)
    in_hi = hi - np.maximum(anchors.max(axis=0), 0.0)
    from marinecdpr.scenario.robot import frame_axes

    keep = frame_axes(c) & (in_hi > in_lo)
    return np.where(keep, in_lo, lo), np.where(keep, in_hi, hi)


def _j_tilde(robot, x: np.ndarray, R: np.ndarray) -> np.ndarray:
    """J~'s controlled columns at poses (x, R) (over the pulleys, if any), shape (n, n_cables, k)."""
    from marinecdpr.geometry.kinematics import cable_kinematics

    if robot.has_pulleys:
        from marinecdpr.geometry.pulley import pulley_kinematics

        kin = pulley_kinematics(x, R, robot.frame_anchors, robot.pulley_axes, robot.pulley_radii,
                                robot.platform_anchors, None)
    else:
        kin = cable_kinematics(x, R, robot.frame_anchors, robot.platform_anchors)
    return kin.J_tilde[:, :, list(robot.controlled)]


def _rank_ratio(robot, x: np.ndarray, R: np.ndarray) -> np.ndarray:
    """sigma_min / sigma_max of J~'s controlled columns at poses (x, R), shape (n,); 0 where
    J~ is not finite (the rank test of :func:`~marinecdpr.model.tension.full_rank` asks this
    ratio squared to pass 1e-12)."""
    J = _j_tilde(robot, x, R)
    finite = np.isfinite(J).all(axis=(1, 2))
    s = np.linalg.svd(np.where(finite[:, None, None], J, 0.0), compute_uv=False)
    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = s[:, -1] / s[:, 0]
    return np.where(finite & np.isfinite(ratio), ratio, 0.0)


GOLDEN_STEPS = 60
"""Golden-section steps of :func:`singular_set`'s search between grid points: each shrinks
the bracket by 0.618, 60 of them to 3e-13 of a grid step."""


def singular_set(robot, axes: list[np.ndarray], R: np.ndarray, spans: list[int]) -> tuple[np.ndarray, str | None, int]:
    """Where J~ loses rank between the points of a grid: the singular set a grid of poses misses.

    Along every line of the grid parallel to an axis it spans, sigma_min / sigma_max of J~
    (its controlled columns; :func:`_rank_ratio`) is sampled at the grid's points; each
    dip (a local minimum of the samples, with its two neighbours as the bracket) is followed
    down by golden-section search, and the pose it ends at judged by the tension solver's
    own rank test (:func:`~marinecdpr.model.tension.full_rank`). A singular set that lies
    between the grid's points (a plane at one height, say) is so found on every line that
    crosses it, however fine or coarse the grid. Only the grid's own span is searched (from
    its first point to its last along each axis).

    Parameters
    ----------
    robot : Robot
    axes : list of 3 ndarray
        The grid's coordinates along x, y, z, m (one value along an axis not spanned).
    R : ndarray, shape (3, 3)
        The platform's orientation held.
    spans : list of int
        The axes the grid spans (searched along).

    Returns
    -------
    poses : ndarray, shape (n_found, 3)
        Singular poses found (platform centres in C, m).
    set : str or None
        The set as a reader would name it: ``"the plane z = 1.95 m"`` where every pose found
        shares one coordinate and the grid spans three axes (``"the line ..."`` where they
        share all but one of the spanned axes, ``"the pose ..."`` all), else ``"N poses"``;
        None if none is found.
    n_lines : int
        Lines searched.
    """
    from marinecdpr.model.tension import full_rank

    shape = tuple(a.size for a in axes)
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1)
    ratio = _rank_ratio(robot, grid.reshape(-1, 3), np.broadcast_to(R, (grid[..., 0].size, 3, 3))).reshape(shape)
    starts, lows, highs, along = [], [], [], []
    n_lines = 0
    for a in spans:
        u = axes[a]
        if u.size < 2:
            continue
        r = np.moveaxis(ratio, a, -1)                           # (..., n_a)
        g = np.moveaxis(grid, a, -2)                            # (..., n_a, 3)
        n_lines += r[..., 0].size
        left = np.concatenate([np.full(r.shape[:-1] + (1,), np.inf), r[..., :-1]], axis=-1)
        right = np.concatenate([r[..., 1:], np.full(r.shape[:-1] + (1,), np.inf)], axis=-1)
        dip = (r <= left) & (r <= right)
        for idx in zip(*np.nonzero(dip)):
            *line, i = idx
            starts.append(g[tuple(line)][i])
            lows.append(u[max(i - 1, 0)])
            highs.append(u[min(i + 1, u.size - 1)])
            along.append(a)
    if not starts:
        return np.zeros((0, 3)), None, n_lines
    x0 = np.array(starts)
    lo, hi, along = np.array(lows), np.array(highs), np.array(along)
    rows = np.arange(x0.shape[0])
    Rs = np.broadcast_to(R, (x0.shape[0], 3, 3))

    def at(v: np.ndarray) -> np.ndarray:
        x = x0.copy()
        x[rows, along] = v
        return x

    g = (np.sqrt(5.0) - 1.0) / 2.0
    c, d = hi - g * (hi - lo), lo + g * (hi - lo)
    fc, fd = _rank_ratio(robot, at(c), Rs), _rank_ratio(robot, at(d), Rs)
    for _ in range(GOLDEN_STEPS):
        left = fc < fd                     # the minimum in [lo, d]
        hi = np.where(left, d, hi)
        lo = np.where(left, lo, c)
        c_new, d_new = hi - g * (hi - lo), lo + g * (hi - lo)
        x_new = np.where(left, c_new, d_new)
        f_new = _rank_ratio(robot, at(x_new), Rs)
        fd, fc = np.where(left, fc, f_new), np.where(left, f_new, fd)
        c, d = np.where(left, c_new, d), np.where(left, c, d_new)
    best = at(0.5 * (lo + hi))
    found = best[~(full_rank(_j_tilde(robot, best, Rs)))]
    if found.shape[0] == 0:
        return found, None, n_lines
    size = max(float(np.ptp(np.concatenate([a for a in axes]))), 1.0)
    same = [j for j in spans if np.ptp(found[:, j]) <= 1e-6 * size]
    names = "xyz"
    where = ", ".join(f"{names[j]} = {float(np.mean(found[:, j])):.4g} m" for j in same)
    free = len(spans) - len(same)  # the set's dimension, as far as the poses found tell
    text = (f"{found.shape[0]} poses" if not same else
            f"the {('pose', 'line', 'plane')[min(free, 2)]} {where}")
    return found, text, n_lines


def singular_poses(scenario: Scenario, *, orientation_deg: tuple[float, float, float] = (0.0, 0.0, 0.0),
                   n: int | None = None) -> SingularPoses:
    """Where over the frame, at one orientation, J~ loses rank: the poses every plan fails at.

    The platform's centre is held on a grid inside :func:`pose_range` (as :func:`workspace_map`
    lays its grid: ``n`` points along each axis the frame spans, the range's ends left out;
    a planar robot's in its x-z plane), and J~ (over the pulleys, if any) judged at each by the
    tension solver's rank test (:func:`~marinecdpr.model.tension.full_rank`); between the
    grid's points, :func:`singular_set` follows every dip of J~'s smallest singular value
    along the grid's lines, so a singular set no grid point lies on (a plane at one height)
    is found too. No dynamics are solved: some milliseconds.

    Parameters
    ----------
    scenario : Scenario
    orientation_deg : tuple of 3 float
        The platform's orientation held, (rx, ry, rz) deg; default level.
    n : int, optional
        Grid points per axis; default 30 for a planar robot, 12 for a spatial one.

    Returns
    -------
    SingularPoses
    """
    from marinecdpr.geometry.rotations import matrix_from_euler
    from marinecdpr.model.tension import full_rank
    from marinecdpr.scenario.robot import scaled_copy

    robot = scenario.robot
    planar = robot.dofs == "planar"
    n = n or (30 if planar else 12)
    lo, hi = pose_range(scenario, orientation_deg)
    spans = [0, 2] if planar else [0, 1, 2]
    axes = [np.linspace(lo[i], hi[i], n + 2)[1:-1] if i in spans else np.array([0.0])
            for i in range(3)]
    x = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    angles = np.broadcast_to(np.radians(np.asarray(orientation_deg, dtype=float)), x.shape)
    R = matrix_from_euler(np.ascontiguousarray(angles))
    J = _j_tilde(robot, x, R)
    bad = ~(full_rank(J) & np.isfinite(J).all(axis=(1, 2)))
    first = None
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        first = describe_pose(np.r_[x[i], angles[i]], robot.controlled)
    between = None
    if not bad.all():
        found, text, n_lines = singular_set(robot, axes, R[0], [i for i in spans if axes[i].size > 1])
        if text is not None:
            between = (f"on {text} (found between the grid's points, on {found.shape[0]} of the {n_lines} lines "
                       f"along its axes searched)")
    level = not np.any(orientation_deg)
    what = ("level poses across the frame" if level
            else f"poses across the frame at ({', '.join(f'{a:g}' for a in orientation_deg)}) deg")
    return SingularPoses(what=what, n_poses=int(x.shape[0]), n_singular=int(bad.sum()), first=first,
                         scale=scaled_copy(robot) if level else None, level=level, between=between)


def workspace_map(
    scenario: Scenario,
    *,
    axes: tuple[str, str] | None = None,
    n: tuple[int, int] = (30, 20),
    fixed_m: float | None = None,
    orientation_deg: tuple[float, float, float] = (0.0, 0.0, 0.0),
    progress: Callable[[int, int], None] | None = None,
) -> WorkspaceMap:
    """Map the feasibility of held poses over the frame under the scenario's ship motion.

    Parameters
    ----------
    scenario : Scenario
        Robot, ship motion, time grid and tension method; its trajectory is ignored.
    axes : tuple of two of "x", "y", "z", optional
        Grid plane; default ("x", "z"), the plane of a planar robot.
    n : tuple of int
        Grid points along each axis, evenly inside the range where the platform fits in the
        frame (:func:`pose_range`: the frame anchors' range inset by the platform's size;
        the range's ends, where an anchor would touch the frame's edge, are left out).
    fixed_m : float, optional
        The third coordinate (default: the middle of the frame along it; 0 for a planar robot's y).
    orientation_deg : tuple of 3 float
        Platform orientation held, (rx, ry, rz) deg.
    progress : callable(done, total), optional
    """
    from marinecdpr.planning.budget import check_run_size

    axes = axes or ("x", "z")
    if len(axes) != 2 or any(a not in AXES for a in axes) or axes[0] == axes[1]:
        raise ValueError(f"axes must be two of x, y, z, not {axes!r}")
    check_run_size(scenario, "workspace", grid=(int(n[0]), int(n[1])))  # before the grid's arrays
    c = scenario.robot.frame_anchors
    lo, hi = c.min(axis=0), c.max(axis=0)
    i_u, i_v = AXES[axes[0]], AXES[axes[1]]
    i_w = 3 - i_u - i_v
    # the platform's centre over where the platform fits (not over the frame anchors' range:
    # there the outer poses put an anchor a grid step or less from the frame's edge, where
    # cables run along the edge and cannot hold the platform even in calm water)
    fit_lo, fit_hi = pose_range(scenario, orientation_deg)
    grid = [np.linspace(fit_lo[i], fit_hi[i], k + 2)[1:-1] for i, k in zip((i_u, i_v), n)]
    if fixed_m is None:
        fixed_m = 0.0 if scenario.robot.dofs == "planar" else 0.5 * (lo[i_w] + hi[i_w])
    shape = (grid[0].size, grid[1].size)
    lo_T, hi_T = scenario.robot.tension_min, scenario.robot.tension_max
    total = shape[0] * shape[1]
    n_steps, step = scenario.time.n_steps, scenario.time.step_s
    held = []
    for u in grid[0]:
        for v in grid[1]:
            pos = [0.0, 0.0, 0.0]
            pos[i_u], pos[i_v], pos[i_w] = float(u), float(v), float(fixed_m)
            held.append(scenario.with_changes(trajectory={
                "type": "line", "start_position_m": pos, "end_position_m": pos,
                "start_orientation_deg": list(orientation_deg), "duration_s": 1.0}))
    ok = np.zeros(total, dtype=np.int64)
    pinv_ok = np.zeros(total, dtype=np.int64)
    worst = np.full(total, np.inf)
    outside = np.zeros(total, dtype=bool)  # the platform would leave the frame: NaN
    singular = np.zeros(total, dtype=bool)  # J~ loses rank (held in C: at every step)
    method, base_model = scenario.planning.method, scenario.planning.base_model
    chunks = range(0, n_steps, DEFAULT_CHUNK_STEPS)
    for j, i0 in enumerate(chunks):
        # the chunks of iter_plan, each pose planned on them; the ship's motion, the same for
        # every held pose, evaluated once per chunk (not once per pose: a sea state's sum)
        t = np.arange(i0, min(i0 + DEFAULT_CHUNK_STEPS, n_steps)) * step
        ship = ship_motion_at(scenario, t)
        for p, sc in enumerate(held):
            if not outside[p]:
                try:
                    piece = plan_at(sc, t, method=method, base_model=base_model, ship=ship)
                except ScenarioError:
                    outside[p] = True
                else:
                    ok[p] += int(piece.feasible.sum())
                    singular[p] |= bool(piece.singular.any())
                    T_s = piece.tensions_pinv
                    with np.errstate(invalid="ignore"):
                        pinv_ok[p] += int(np.all((T_s >= lo_T) & (T_s <= hi_T), axis=1).sum())
                    m = tension_margin(piece.tensions, lo_T, hi_T)
                    worst[p] = min(worst[p], float(np.nanmin(m)) if np.isfinite(m).any() else np.inf)
            if progress is not None:
                progress((j * total + p + 1) // len(chunks), total)
    inside = ~outside
    frac = np.where(inside, ok / n_steps, np.nan).reshape(shape)
    pinv = np.where(inside, pinv_ok / n_steps, np.nan).reshape(shape)
    margin = np.where(inside, np.where(ok == n_steps, np.maximum(worst, 0.0), -np.inf), np.nan).reshape(shape)
    fixed = {"axis": "xyz"[i_w], "value_m": float(fixed_m), "orientation_deg": list(orientation_deg)}
    least = None
    robot = scenario.robot
    if robot.clearance_m is not None:  # one pose each: held still in C, as the obstacles are
        from marinecdpr.geometry.rotations import matrix_from_euler
        from marinecdpr.planning.interference import pose_clearances

        x = np.zeros((total, 3))
        x[:, i_u], x[:, i_v], x[:, i_w] = np.repeat(grid[0], grid[1].size), np.tile(grid[1], grid[0].size), fixed_m
        R = np.broadcast_to(matrix_from_euler(np.radians(np.asarray(orientation_deg, dtype=float))), (total, 3, 3))
        gaps = pose_clearances(robot, scenario.obstacles, x, R).per_cable.min(axis=1)
        least = np.where(inside, gaps, np.nan).reshape(shape)
    return WorkspaceMap(axes=(axes[0], axes[1]), u=grid[0], v=grid[1], fraction_feasible=frac, min_margin_N=margin,
                        pinv_fraction_feasible=pinv, fixed=fixed, n_steps=n_steps, least_clearance_m=least,
                        clearance_m=robot.clearance_m, singular=(singular & inside).reshape(shape))


def map_singular_poses(scenario: Scenario, ws: WorkspaceMap) -> SingularPoses:
    """Where on a workspace map's own grid J~ loses rank, and between its points.

    The map's poses found singular while it was planned (:attr:`WorkspaceMap.singular`),
    with a whole row or column of them named as such (``"every pose of the row z = 1.95 m"``);
    where none is, :func:`singular_set` along the map's grid lines for a singular set
    between them.

    Parameters
    ----------
    scenario : Scenario
        The scenario the map was made of.
    ws : WorkspaceMap

    Returns
    -------
    SingularPoses
    """
    from marinecdpr.geometry.rotations import matrix_from_euler
    from marinecdpr.scenario.robot import scaled_copy

    robot = scenario.robot
    i_u, i_v = AXES[ws.axes[0]], AXES[ws.axes[1]]
    i_w = AXES[ws.fixed["axis"]]
    angles = np.radians(np.asarray(ws.fixed["orientation_deg"], dtype=float))
    R = matrix_from_euler(angles)
    bad = np.zeros((ws.u.size, ws.v.size), dtype=bool) if ws.singular is None else ws.singular
    inside = np.isfinite(ws.fraction_feasible)
    first = None
    if bad.any():
        a, b = np.argwhere(bad)[0]
        pose = np.zeros(6)
        pose[[i_u, i_v, i_w]] = ws.u[a], ws.v[b], ws.fixed["value_m"]
        pose[3:] = angles
        first = describe_pose(pose, robot.controlled)
        rows = [f"{ws.axes[1]} = {ws.v[j]:.4g} m" for j in range(ws.v.size)
                if bad[:, j].any() and np.all(bad[:, j] | ~inside[:, j])]
        cols = [f"{ws.axes[0]} = {ws.u[j]:.4g} m" for j in range(ws.u.size)
                if bad[j].any() and np.all(bad[j] | ~inside[j])]
        whole = [f"every pose of the row {r}" for r in rows] + [f"every pose of the column {c}" for c in cols]
        if whole:
            first += " (" + "; ".join(whole) + ")"
    between = None
    if not bad.any():  # a singular set the map's points miss (where they show one, that is the warning)
        axes = [np.array([ws.fixed["value_m"]])] * 3
        axes[i_u], axes[i_v] = ws.u, ws.v
        found, text, n_lines = singular_set(robot, axes, R, [i_u, i_v])
        if text is not None:
            between = (f"on {text} (found between the map's points, on {found.shape[0]} of the {n_lines} lines "
                       f"along its axes searched)")
    level = not np.any(ws.fixed["orientation_deg"])
    return SingularPoses(what="poses of the map", n_poses=int(inside.sum()), n_singular=int(bad.sum()), first=first,
                         scale=scaled_copy(robot) if level else None, level=level, between=between)
