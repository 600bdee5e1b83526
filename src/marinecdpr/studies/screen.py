"""The fast screen: does a robot's job hold in a sea state? Decided in the frequency domain,
in about a millisecond per sea state, and erring towards "does not work".

A time-domain run of a job in one sea state (``clean --seas``) takes seconds; a design search
asks the question for thousands of (design, sea state) pairs. The screen answers it from the
same models, linearised in the ship's motion:

1. **Poses.** The job's path (the scenario's trajectory) sampled every 10 ms; the samples
   nearest to a grid over its bounding box in C (:data:`GRID`, the path's corners included)
   are the poses judged.
2. **The wrench the platform needs** at each pose, as the planner computes it
   (:func:`~marinecdpr.model.dynamics.wrench_terms`, eqs. 9-16, with the scenario's
   disturbance and the tool's loads at the preload), linearised in the ship's coordinates
   q = (eta, eta_dot, eta_ddot) (18 numbers) by central differences about a ship at rest:
   w = w0 + D q.
3. **Its spectrum in a sea state.** With the RAOs X(omega, beta), the wrench's response is
   H = D [X; i omega X; -omega^2 X]; its variance m0 = sum_k sum_d a_kd^2 |H(omega_k,
   beta_d)|^2 / 2 and m2 likewise with omega_k^2, over the frequencies and directions the
   time domain's sea record uses (:func:`~marinecdpr.motion.seastate.sea_record`: a_kd =
   sqrt(2 S(omega_k) d_omega w_d)): the expectation of the record's own variance.
4. **Its extremes over the job.** Along each principal axis of the controlled components'
   covariance (correlated components make the box narrow), the level exceeded with
   probability ``p`` over the job's duration T (Rice: N = T sqrt(m2 / m0) / 2 pi
   up-crossings of the mean; e = sigma sqrt(2 ln(N / p))).
5. **The wrenches the cables must give:** w0, plus every corner of that box, grown by the
   box of the path's own inertia (the largest change the path's accelerations make to each
   component), plus the tool's loads: its friction for each direction the path moves in
   (and none, a still brush) with the normal force at either end of its range. The
   wrenches the cables can give with tensions in their limits form a convex set, so the
   corners decide the whole set: each is solved by the planner's own tension solver
   (:func:`~marinecdpr.model.tension.distribute_tensions`, the scenario's method), and the
   margin is the least of their largest headrooms
   (:func:`~marinecdpr.model.tension.largest_headroom`, concave in the wrench).
6. **The normal force** (a planar robot's pusher): F_n = preload + the sea's and the weight's
   force along the hull normal (:func:`~marinecdpr.prototype.parts.brush.contact_force`), a
   Gaussian process at each pose: its share of time in the band, exact for its mean and
   sigma, averaged over the poses (which sample the panel as the path covers it). One
   record's share over a short job scatters about that expectation, so the verdict takes
   the share less :data:`IN_BAND_SIGMAS` standard errors (one independent sample per
   up-crossing of the mean).

Left out (said where it matters): winch torque, speed and power, cable sag and stretch, and
the closed loop's tracking. The time domain judges those.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from scipy.special import ndtr

from marinecdpr.errors import ScenarioError
from marinecdpr.model.dynamics import uncontrolled
from marinecdpr.motion.basemotion import seen_by_frame
from marinecdpr.motion.ship import ship_motion
from marinecdpr.motion.trajectory import check_in_frame, evaluate_trajectory
from marinecdpr.planning.planner import required_wrench
from marinecdpr.scenario.schema import Scenario
from marinecdpr.studies.operability import Cell

__all__ = ["ScreenResult", "ScreenModel", "screen_model", "at_origin", "screen_cells", "extreme_factor", "GRID",
           "EXCEEDANCE", "SAMPLE_S", "MAX_DIRECTIONS", "IN_BAND_SIGMAS"]

GRID = (5, 3)
"""Poses judged along the path's two widest axes in C."""
EXCEEDANCE = 0.01
"""The chance that a component's extreme over the job exceeds the level the screen takes."""
SAMPLE_S = 0.01
"""The path's sampling, s."""
IN_BAND_SIGMAS = 2.0
"""The normal force's time in band passes where its expected share, less this many standard
errors of one record's share over the job, reaches the target: a single record of a short job
scatters several points about the expectation (ship_side's finalists: up to 6.6 points)."""
MAX_DIRECTIONS = 16
"""The most directions of the path's motion judged one by one for the tool's friction."""
_H = 1e-6
"""Central differences' step in the ship's coordinates (m, rad and their rates)."""


@dataclass(frozen=True)
class ScreenModel:
    """A robot's job linearised in the ship's motion (:func:`screen_model`).

    Attributes
    ----------
    pose : ndarray, shape (n_poses, 6)
        The poses judged, (x, y, z, rx, ry, rz) in C, m and rad.
    w0 : ndarray, shape (n_poses, 6)
        The wrench each needs on a ship at rest, in C (N, N m), with the tool's loads at no
        normal force (its jet's alone).
    D : ndarray, shape (n_poses, 6, 18)
        dw / dq: the wrench's change with the ship's (eta, eta_dot, eta_ddot).
    J : ndarray, shape (n_poses, n_cables, k)
        J~'s controlled columns at each pose.
    path_box : ndarray, shape (6,)
        The largest change the path's own accelerations make to each wrench component.
    friction : ndarray, shape (n_directions + 1, 6)
        The tool's friction wrench per newton of normal force: none (a still brush), and
        for each direction the path moves in (at most :data:`MAX_DIRECTIONS`; beyond, the
        corners of an octagon holding every direction of the panel's plane).
    tool_n : ndarray, shape (6,)
        The rest of the tool's wrench per newton of normal force (the hull's push, a disc's
        reaction moment).
    duration_s : float
    controlled : tuple of int
    planar_normal : bool
        The hull normal is a direction the cables do not control (a planar robot's pusher).
    x_PC_C, twist, R_PC, t : ndarray
        The poses' position (n_poses, 3) m, twist (n_poses, 6), orientation (n_poses, 3, 3)
        and time (n_poses,) s on the path: what :func:`at_origin` linearises again.
    """

    pose: np.ndarray
    w0: np.ndarray
    D: np.ndarray
    J: np.ndarray
    path_box: np.ndarray
    friction: np.ndarray
    tool_n: np.ndarray
    duration_s: float
    controlled: tuple
    planar_normal: bool
    x_PC_C: np.ndarray
    twist: np.ndarray
    R_PC: np.ndarray
    t: np.ndarray


@dataclass(frozen=True)
class ScreenResult:
    """The screen's verdict per sea state.

    Attributes
    ----------
    cells : list of Cell
    works : ndarray of bool, shape (n_cells,)
        Tensions within limits at every judged wrench, and the normal force in band long enough.
    tensions_ok : ndarray of bool, shape (n_cells,)
    margin_N : ndarray, shape (n_cells,)
        The least, over the judged wrenches, of the largest headroom tensions producing
        them can keep (:func:`~marinecdpr.model.tension.largest_headroom`): by how much the
        cables' limits could be tightened with the job still holding, N (negative: by how
        much they are broken; -inf at a singular pose).
    in_band_low_pct : ndarray, shape (n_cells,)
        That share less :data:`IN_BAND_SIGMAS` standard errors of one record's share over the
        job (a share p over N independent samples, N the up-crossings of the normal force's
        mean: sqrt(p (1 - p) / N)): what the verdict compares with the target, %.
    in_band_pct : ndarray, shape (n_cells,)
        The normal force's expected share of time in its band, %, over the judged poses (100
        where the cables hold it, or there is no tool).
    in_band_target_pct : float
    """

    cells: list
    works: np.ndarray
    tensions_ok: np.ndarray
    margin_N: np.ndarray
    in_band_pct: np.ndarray
    in_band_low_pct: np.ndarray
    in_band_target_pct: float

    @property
    def share(self) -> float:
        """The probability that the job works: the working sea states' probabilities over all."""
        p = np.array([c.probability for c in self.cells], dtype=float)
        return float(p[self.works].sum() / p.sum()) if p.sum() > 0 else 0.0


def extreme_factor(m0: np.ndarray, m2: np.ndarray, duration_s: float, exceedance: float = EXCEEDANCE) -> np.ndarray:
    """The extreme over ``duration_s`` of a stationary Gaussian process as a multiple of its
    sigma: sqrt(2 ln(N / p)), N = T sqrt(m2 / m0) / (2 pi) (Rice's up-crossings, at least one).

    Parameters
    ----------
    m0, m2 : ndarray
        The process's spectral moments (variance, and that of its rate).
    duration_s : float
    exceedance : float
        p: the chance that the extreme exceeds the level returned.
    """
    m0 = np.asarray(m0, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        n = np.where(m0 > 0.0, duration_s * np.sqrt(np.asarray(m2, dtype=float) / m0) / (2.0 * np.pi), 1.0)
    return np.sqrt(2.0 * np.log(np.maximum(n, 1.0) / exceedance))


def _still_plus(dq: np.ndarray, scenario: Scenario):
    """Ship motions at the perturbations ``dq`` (n, 18) of a ship at rest, as the scenario's
    frame sees them (:func:`~marinecdpr.motion.ship.in_frame_axes`)."""
    return seen_by_frame(ship_motion(dq[:, 0:6], dq[:, 6:12], dq[:, 12:18]), scenario)


def _wrench(scenario: Scenario, x, twist, twist_dot, R_PC, ship, t, F_n) -> np.ndarray:
    """The planner's required wrench (n, 6) in C, the disturbance and the tool's loads at
    ``F_n`` included (:func:`~marinecdpr.planning.planner.required_wrench`)."""
    return required_wrench(scenario, x, twist, twist_dot, R_PC, ship, t, F_n).total


def _grid_rows(points: np.ndarray, grid: tuple[int, int]) -> np.ndarray:
    """Indices of the points (n, 3) nearest to a grid over their two widest axes."""
    span = np.ptp(points, axis=0)
    a, b = np.argsort(span)[::-1][:2]
    lo, hi = points.min(axis=0), points.max(axis=0)
    ua, ub = np.linspace(lo[a], hi[a], grid[0]), np.linspace(lo[b], hi[b], grid[1])
    rows = []
    for u in ua:
        for v in ub:
            rows.append(int(np.argmin((points[:, a] - u) ** 2 + (points[:, b] - v) ** 2)))
    return np.unique(rows)


def _sensitivity(scenario: Scenario, x_PC_C, twist, R_PC, t) -> tuple[np.ndarray, np.ndarray]:
    """w0 (n_p, 6) and D = dw/dq (n_p, 6, 18) at the poses (x_PC_C (n_p, 3) m, twist (n_p, 6),
    R_PC (n_p, 3, 3), t (n_p,) s), held, by central differences on 1 + 36 ship states: at rest
    and +-h along each coordinate (the module's step 2). The tool at no normal force: its jet
    alone; what grows with F_n is added per cell."""
    n_p = len(t)
    dq = np.zeros((37, 18))
    for i in range(18):
        dq[1 + 2 * i, i], dq[2 + 2 * i, i] = _H, -_H
    ship = _still_plus(np.tile(dq, (n_p, 1)), scenario)
    rep = np.repeat(np.arange(n_p), 37)
    w = _wrench(scenario, x_PC_C[rep], twist[rep], np.zeros((rep.size, 6)), R_PC[rep], ship, t[rep],
                0.0).reshape(n_p, 37, 6)
    return w[:, 0], np.moveaxis((w[:, 1::2] - w[:, 2::2]) / (2.0 * _H), 1, 2)


def screen_model(scenario: Scenario, *, grid: tuple[int, int] = GRID) -> ScreenModel:
    """Linearise the scenario's job in the ship's motion (the module's steps 1, 2 and 5).

    Raises
    ------
    ScenarioError
        The path takes the platform out of the frame (as the planner says it). A pose where
        the cables lose rank is not an error: no tensions hold it, and the screen says so.
    """
    from marinecdpr.geometry.kinematics import cable_kinematics

    robot = scenario.robot
    duration = float(scenario.time.duration_s)
    t = np.arange(0.0, duration + 1e-12, max(SAMPLE_S, scenario.time.step_s))
    path = evaluate_trajectory(scenario.trajectory, t, scenario.cleaning)
    rows = _grid_rows(path.x_PC_C, grid)
    n_p = rows.size
    preload = scenario.cleaning.preload if scenario.cleaning is not None else 0.0
    # the path's own inertia: each component's largest change from its accelerations, calm sea
    calm = _still_plus(np.zeros((t.size, 18)), scenario)
    moving = _wrench(scenario, path.x_PC_C, path.twist, path.twist_dot, path.R_PC, calm, t, preload)
    still = _wrench(scenario, path.x_PC_C, path.twist, np.zeros_like(path.twist_dot), path.R_PC, calm, t, preload)
    path_box = np.abs(moving - still).max(axis=0)
    w0, D = _sensitivity(scenario, path.x_PC_C[rows], path.twist[rows], path.R_PC[rows], t[rows])
    # the tool, per newton of normal force: its friction for each direction the path moves in
    # (the brush slides the way the platform moves in C; a path turning through many, an
    # octagon that holds the circle), and the rest (the hull's push, a disc's moment)
    friction = np.zeros((1, 6))
    tool_n = np.zeros(6)
    if scenario.cleaning is not None:
        from marinecdpr.model.brush import cleaning_loads

        v = path.twist[:, :3]
        speed = np.linalg.norm(v, axis=1)
        dirs = np.unique(np.round(v[speed > 1e-3] / speed[speed > 1e-3, None], 6), axis=0)
        if len(dirs) > MAX_DIRECTIONS:
            n_C = np.asarray(scenario.cleaning.hull_normal, dtype=float)
            e1 = np.cross(n_C, [0.0, 0.0, 1.0]) if abs(n_C[2]) < 0.9 else np.cross(n_C, [1.0, 0.0, 0.0])
            e1 /= np.linalg.norm(e1)
            ang = np.arange(8)[:, None] * np.pi / 4
            dirs = (np.cos(ang) * e1 + np.sin(ang) * np.cross(n_C, e1)) / np.cos(np.pi / 8)
        R0 = path.R_PC[rows[:1]].repeat(len(dirs) + 1, axis=0)
        tw = np.zeros((len(dirs) + 1, 6))
        tw[1:, :3] = dirs  # at 1 m/s the friction's smoothing (below 1 mm/s) is nil; row 0 still
        f0, m0 = cleaning_loads(scenario.cleaning, tw, R0, 0.0)  # the jet alone
        f1, m1 = cleaning_loads(scenario.cleaning, tw, R0, 1.0)
        loads = np.concatenate([f1 - f0, m1 - m0], axis=1)
        tool_n = loads[0]  # still: no friction
        friction = loads - tool_n
        friction[1:] *= np.linalg.norm(dirs, axis=1)[:, None]  # the octagon's corners lie beyond the circle
    c = list(robot.controlled)
    kin = cable_kinematics(path.x_PC_C[rows], path.R_PC[rows], robot.frame_anchors, robot.platform_anchors,
                           np.zeros((n_p, 6)))
    check_in_frame(path.x_PC_C[rows], kin.anchors_C, robot.frame_anchors, t[rows])
    n_C = np.asarray(scenario.cleaning.hull_normal, dtype=float) if scenario.cleaning is not None else None
    planar_normal = (n_C is not None and 1 in uncontrolled(robot.controlled) and abs(n_C[1]) >= 1.0 - 1e-9)
    return ScreenModel(pose=path.pose[rows], w0=w0, D=D, J=kin.J_tilde[:, :, c], path_box=path_box, friction=friction,
                       x_PC_C=path.x_PC_C[rows], twist=path.twist[rows], R_PC=path.R_PC[rows], t=t[rows],
                       tool_n=tool_n, duration_s=duration, controlled=tuple(c), planar_normal=planar_normal)


def at_origin(model: ScreenModel, scenario: Scenario) -> ScreenModel:
    """:func:`screen_model` of the scenario from the model of the same robot and job with
    its frame elsewhere on the ship (another ``ship.frame_origin_m`` and
    ``frame_orientation_deg``): only the wrench's sensitivity to the ship's motion (w0 and
    D) is made again, the path, its poses and the tool being the same.

    Returns
    -------
    ScreenModel
        Equal to ``screen_model(scenario)`` (its path box to rounding).
    """
    w0, D = _sensitivity(scenario, model.x_PC_C, model.twist, model.R_PC, model.t)
    return replace(model, w0=w0, D=D)


def _rao_of(scenario: Scenario):
    """The RAOs of the scenario's sea-state base motion (read once per source)."""
    from marinecdpr.motion.basemotion import _rao

    return _rao(scenario.base_motion.rao.model_dump_json())


def _response_moments(model: ScreenModel, rao, cells: list, template: Scenario) -> tuple[np.ndarray, np.ndarray]:
    """The covariances C0 and C2 (n_cells, n_poses, 6, 6) of the wrench's response and of its
    rate in each cell's sea (their diagonals are m0 and m2), on the time domain's record
    frequencies and directions (step 3): C0 = sum_k sum_d a_kd^2 Re(H H^*) / 2."""
    from marinecdpr.motion.seastate import jonswap, pierson_moskowitz, spread_directions

    sea = template.base_motion
    record_s = max(sea.record_s, model.duration_s)
    d_omega = 2.0 * np.pi / record_s
    omega_max = max(6.0 * 2.0 * np.pi / c.tp for c in cells)
    omega = np.arange(1, int(omega_max / d_omega) + 1) * d_omega
    rel, weight = spread_directions(None if sea.spreading == "none" else sea.spreading, sea.spreading_exponent,
                                    sea.n_directions)
    n_p = model.D.shape[0]
    C0 = np.zeros((len(cells), n_p, 6, 6))
    C2 = np.zeros_like(C0)
    transfer: dict[float, np.ndarray] = {}
    for i, cell in enumerate(cells):
        wp = 2.0 * np.pi / cell.tp
        S = (jonswap(omega, cell.hs, cell.tp, sea.gamma) if sea.spectrum == "jonswap"
             else pierson_moskowitz(omega, cell.hs, cell.tp))
        S = np.where((omega <= 6.0 * wp) & (S > 1e-12 * S.max()), S, 0.0)  # sea_record's components
        for r, wd in zip(rel, weight):
            beta = float(np.mod(cell.heading_deg + np.degrees(r), 360.0))
            if beta not in transfer:
                X = rao.at(omega, beta)  # (6, n_omega)
                Q = np.concatenate([X, 1j * omega * X, -(omega**2) * X])  # (18, n_omega)
                transfer[beta] = np.einsum("pjq,qk->pjk", model.D, Q)  # (n_p, 6, n_omega)
            H = transfer[beta]
            a2 = S * d_omega * wd  # a_kd^2 / 2
            Ha = H * a2
            C0[i] += np.einsum("pjk,plk->pjl", Ha, H.conj()).real
            C2[i] += np.einsum("pjk,plk->pjl", Ha * omega**2, H.conj()).real
    return C0, C2


def screen_cells(scenario: Scenario, cells: list[Cell], *, model: ScreenModel | None = None,
                 exceedance: float = EXCEEDANCE, in_band_target_pct: float = 95.0) -> ScreenResult:
    """The screen's verdict on the scenario's job in each sea state.

    Parameters
    ----------
    scenario : Scenario
        A sea-state base motion (``[base_motion] type = "sea_state"``): its RAOs, spectrum,
        spreading and record length; each cell sets Hs, Tp and the heading.
    cells : list of Cell
    model : ScreenModel, optional
        :func:`screen_model` of the scenario, if already made.
    exceedance : float
        The chance that a wrench component's extreme over the job exceeds the level taken.
    in_band_target_pct : float
        The share of time the normal force must stay in its band, %.
    """
    from marinecdpr.model.tension import distribute_tensions, largest_headroom, pseudo_inverse_tensions

    if scenario.base_motion.type != "sea_state":
        raise ScenarioError("the screen needs a sea-state base motion (its RAOs and spectrum)", key="base_motion.type")
    model = model if model is not None else screen_model(scenario)
    C0, C2 = _response_moments(model, _rao_of(scenario), cells, scenario)
    robot = scenario.robot
    c = list(model.controlled)
    k = len(c)
    n_cells, n_p = C0.shape[:2]
    P = scenario.cleaning.preload if scenario.cleaning is not None else 0.0
    # the normal force's range and its share of time in the band (step 6)
    in_band = np.full(n_cells, 100.0)
    in_band_low = in_band
    Fn_lo = Fn_hi = np.full((n_cells, n_p), P)
    if model.planar_normal:
        from marinecdpr.prototype.parts.brush import contact_force, static_weight_y

        lo_b, hi_b = scenario.cleaning.band_N
        mean = contact_force(model.w0[:, 1] - P * model.tool_n[1], scenario.cleaning,
                             static_y_N=static_weight_y(scenario))  # (n_p,), as planned
        s_n = np.sqrt(C0[:, :, 1, 1])
        e_n = extreme_factor(C0[:, :, 1, 1], C2[:, :, 1, 1], model.duration_s, exceedance) * s_n
        with np.errstate(divide="ignore", invalid="ignore"):
            share = np.where(s_n > 0, ndtr((hi_b - mean) / s_n) - ndtr((lo_b - mean) / s_n),
                             ((mean >= lo_b) & (mean <= hi_b)).astype(float))
        in_band = 100.0 * share.mean(axis=1)  # the poses sample the panel as the path covers it
        Fn_lo, Fn_hi = np.maximum(mean - e_n, 0.0), mean + e_n
        # one record's share scatters about that expectation: about one independent sample
        # per up-crossing of the mean over the job (N = T sqrt(m2 / m0) / 2 pi)
        with np.errstate(divide="ignore", invalid="ignore"):
            rate = np.where(C0[:, :, 1, 1] > 0, np.sqrt(C2[:, :, 1, 1] / C0[:, :, 1, 1]), 0.0) / (2.0 * np.pi)
        n_ind = np.maximum(model.duration_s * rate.mean(axis=1), 1.0)
        p_in = in_band / 100.0
        in_band_low = 100.0 * (p_in - IN_BAND_SIGMAS * np.sqrt(np.maximum(p_in * (1.0 - p_in), 0.0) / n_ind))
    # the sea's box (step 5) along the principal axes of the controlled components' covariance
    # (correlated components make it narrow), each half-width that coordinate's extreme, grown
    # by the path's own inertia box's reach along it
    lam, V = np.linalg.eigh(C0[:, :, c][:, :, :, c])  # (n_cells, n_p, k), (..., k, k) columns
    lam = np.maximum(lam, 0.0)
    rate = np.einsum("cpji,cpjl,cpli->cpi", V, C2[:, :, c][:, :, :, c], V)
    half = (extreme_factor(lam, rate, model.duration_s, exceedance) * np.sqrt(lam)
            + np.abs(V).transpose(0, 1, 3, 2) @ model.path_box[c])  # (n_cells, n_p, k)
    signs = np.array(np.meshgrid(*[[-1.0, 1.0]] * k, indexing="ij")).reshape(k, -1).T  # (2^k, k)
    box = np.einsum("cpji,cpsi->cpsj", V, signs[None, None] * half[:, :, None, :])  # (n_cells, n_p, 2^k, k)
    # the tool: its friction for each direction the path moves in, the normal force at either
    # end of its range
    fric = model.friction[:, c]
    rest = model.tool_n[c]
    n_t = fric.shape[0]
    tool = np.empty((n_cells, n_p, 2 * n_t, k))
    for j, Fn in enumerate((Fn_lo, Fn_hi)):  # a load on the platform is a wrench the cables need not give
        tool[:, :, n_t * j:n_t * (j + 1)] = -Fn[:, :, None, None] * (fric[None, None] + rest[None, None, None])
    w = (model.w0[None, :, None, None, c] + box[:, :, :, None, :] + tool[:, :, None, :, :])  # (cells, p, 2^k, 2 n_t, k)
    w = w.reshape(n_cells, n_p, -1, k)
    m = w.shape[2]
    J = np.broadcast_to(model.J[None, :, None], (n_cells, n_p, m) + model.J.shape[1:]).reshape(-1, *model.J.shape[1:])
    sol = distribute_tensions(J, w.reshape(-1, k), robot.tension_min, robot.tension_max,
                              method=scenario.planning.method)
    tensions_ok = sol.feasible.reshape(n_cells, n_p * m).all(axis=1)
    # the margin: the largest headroom any tensions keep, concave in the wrench, so its least
    # over the box is at a corner
    T_s, _ = pseudo_inverse_tensions(J, w.reshape(-1, k))
    head = largest_headroom(J, T_s, robot.tension_min, robot.tension_max).reshape(n_cells, -1)
    margin = np.where(np.isnan(head), -np.inf, head).min(axis=1)
    works = tensions_ok & (in_band_low >= in_band_target_pct)
    return ScreenResult(cells=list(cells), works=works, tensions_ok=tensions_ok, margin_N=margin,
                        in_band_pct=in_band, in_band_low_pct=in_band_low, in_band_target_pct=float(in_band_target_pct))
