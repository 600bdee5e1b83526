"""A hull surface cleaned placement after placement: the frame's placements on a curved band
of the hull (``[cleaning.surface]``), and the hours they take.

Each placement is a patch of the surface that fits the frame's panel (the bounding box of
``[cleaning] panel_m``, along the frame's x and z) and stays within the tool's stand-off
tolerance of its plane (:func:`~marinecdpr.geometry.surface.tile_surface`). Its cleaning
time is the coverage path's over a panel of the patch's size in its plane, with the
scenario's brush, lanes and speeds (:func:`~marinecdpr.motion.trajectory.cleaning_path`);
moving the frame to the next placement takes ``move_time_s``, or, with
``[cleaning.surface.relocation]``, a crane's or a rail's move each
(:mod:`marinecdpr.studies.relocation`), with one or more robots on the band. The hours are
the sum over the placements (the slowest robot's), not an area division.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import Callable

import numpy as np

from marinecdpr.errors import ScenarioError
from marinecdpr.geometry.surface import MIN_PATCH_M, tile_surface
from marinecdpr.scenario.cleaning import Cleaning, Surface
from marinecdpr.scenario.relocation import Relocation
from marinecdpr.scenario.schema import Scenario
from marinecdpr.studies.relocation import NO_COST, Moves, RelocationCost, plan_moves, relocation_cost

__all__ = ["SurfaceJob", "surface_function", "frame_panel", "surface_job", "wigley_side", "surface_patches",
           "MAX_SURFACE_PATCHES", "MOVE_TIME_MAX_S", "check_move_time", "turn_time"]

MAX_SURFACE_PATCHES = 30_000
"""The most patches a tiling fits by default (its first grid's and every piece cut from them),
about ten times paper_clean's: some 4 ms each on a loaded core, two minutes. A band of
200 m of a 200 m Wigley side's height (855 040 patches of paper_clean's panel in the first
grid alone) is refused at once."""
MOVE_TIME_MAX_S = 1e6
"""The longest move of the frame to its next place, s (some 11 days): ``clean --move-time``,
with ``--surface`` or ``--hull-area`` (:func:`~marinecdpr.studies.cleaning.check_hull_estimate`)."""


def check_move_time(move_time_s: float) -> float:
    """``move_time_s`` if it is a time from 0 to :data:`MOVE_TIME_MAX_S`, else ScenarioError
    (with 1e308 s between placements the hours are not finite)."""
    if not (np.isfinite(move_time_s) and 0.0 <= move_time_s <= MOVE_TIME_MAX_S):
        raise ScenarioError(f"must be a number of seconds from 0 to {MOVE_TIME_MAX_S:g} to move the frame to its "
                            f"next placement, got {move_time_s:g}", key="move_time_s")
    return float(move_time_s)


def wigley_side(surface: Surface) -> Callable:
    """The Wigley hull's half-breadth y = f(x, z) of ``[cleaning.surface]``, m: below the
    waterline (B/2)(1 - xi^2)(1 - zeta^2), above it (B/2)(1 - xi^2)(1 + flare zeta^2) (smooth
    at the waterline), with xi = 2x/L and zeta = z/T."""
    L, B, T, flare = surface.length_m, surface.beam_m, surface.draught_m, surface.flare

    def f(X, Z):
        xi2 = (2.0 * np.asarray(X, dtype=float) / L) ** 2
        zeta = np.asarray(Z, dtype=float) / T
        return 0.5 * B * (1.0 - xi2) * np.where(zeta < 0.0, 1.0 - zeta * zeta, 1.0 + flare * zeta * zeta)

    return f


def surface_function(surface: Surface) -> tuple[Callable, str]:
    """The side's y = f(x, z) (port: y > 0; starboard given as |y|) and how to name it (a
    mesh is read once per surface: a design study asks for it at every candidate)."""
    return _surface_function(surface.model_dump_json())


@lru_cache(maxsize=8)
def _surface_function(surface_json: str) -> tuple[Callable, str]:
    surface = Surface.model_validate_json(surface_json)
    if surface.form == "wigley":
        return wigley_side(surface), (f"Wigley hull {surface.length_m:g} x {surface.beam_m:g} x {surface.draught_m:g} m"
                                      + (f", flare {surface.flare:g}" if surface.flare else ""))
    from marinecdpr.geometry.surface import mesh_side
    from marinecdpr.motion.hullmesh import faces_to_triangles, read_mesh

    vertices, faces = read_mesh(surface.mesh, units=surface.mesh_units, waterline_m=surface.waterline_m)
    return mesh_side(vertices, faces_to_triangles(faces), side=surface.side), f"mesh {surface.mesh}"


def frame_panel(cleaning: Cleaning) -> tuple[float, float]:
    """What one placement of the frame cleans: the panel's extent along C's x and z, m."""
    panel = np.asarray(cleaning.panel_m, dtype=float)
    return float(np.ptp(panel[:, 0])), float(np.ptp(panel[:, 1]))


@dataclass(frozen=True)
class SurfaceJob:
    """The frame's placements on a surface and the time they take.

    Attributes
    ----------
    placements : list of Placement
    uncleanable : list of Placement
        Patches curved beyond the tolerance even at the smallest size.
    job_s : ndarray, shape (n_placements,)
        Each placement's cleaning time (its coverage path), s.
    move_time_s : float
    frame_panel_m : tuple of float
        The frame's panel (along x, along z), m.
    surface : str
        What the surface is.
    turn_s : ndarray, shape (n_placements,)
        The part of each placement's ``job_s`` the brush spends off its lanes and boundary
        pass: stepping between lanes and moving between cells (the path's other
        segments), s.
    relocation : Relocation, optional
        ``[cleaning.surface.relocation]`` where given (None: every move ``move_time_s``,
        one robot, the visits in the tiling's order).
    moves : Moves, optional
        With ``relocation``: the visits, each robot's, and the move into each
        (:func:`~marinecdpr.studies.relocation.plan_moves`); ``move_time_s`` is then their
        mean.
    band_length_m : float
        The band's length along the ship (its stations' span), m: a rail's length.
    platform_kg : float
        The robot's platform mass, kg (a rail carriage's drive accelerates it with the frame).
    """

    placements: list
    uncleanable: list
    job_s: np.ndarray
    move_time_s: float
    frame_panel_m: tuple[float, float]
    surface: str
    turn_s: np.ndarray | None = None
    relocation: Relocation | None = None
    moves: Moves | None = None
    band_length_m: float = 0.0
    platform_kg: float = 0.0

    @property
    def seconds(self) -> float:
        """All placements' cleaning and the moves between them (with robots, the slowest
        robot's), s."""
        if self.moves is None:
            return float(self.job_s.sum()) + max(len(self.placements) - 1, 0) * self.move_time_s
        return float(self.robot_seconds.max(initial=0.0))

    @property
    def robot_seconds(self) -> np.ndarray:
        """Each robot's cleaning and moves, s, shape (robots,)."""
        if self.moves is None:
            return np.array([self.seconds])
        return self.moves.robot_seconds(self.job_s)

    @property
    def move_s(self) -> np.ndarray:
        """Each move's time in the order made (robot after robot), s, shape (n_moves,)."""
        if self.moves is None:
            return np.full(max(len(self.placements) - 1, 0), float(self.move_time_s))
        return self.moves.move_in_s[self.moves.kind != ""]

    def parts_s(self) -> tuple[float, float, float]:
        """The slowest robot's cleaning (the lanes and the boundary pass), turns between
        lanes and moves, s: they sum to :attr:`seconds` (one robot: the whole job's)."""
        turn = np.zeros_like(self.job_s) if self.turn_s is None else self.turn_s
        if self.moves is None:
            t = float(turn.sum())
            return float(self.job_s.sum()) - t, t, max(len(self.placements) - 1, 0) * self.move_time_s
        m = self.moves
        slow = m.robot == int(np.argmax(self.robot_seconds))
        clean, t = float(self.job_s[m.order[slow]].sum()), float(turn[m.order[slow]].sum())
        return clean - t, t, float(m.move_in_s[slow].sum())

    def moves_said(self) -> str:
        """The moves in words: ``moves of 600 s``; with ``relocation`` how many by each kind,
        their hours, and the robots."""
        if self.moves is None or (self.relocation.mode == "fixed" and self.moves.robots == 1):
            return f"moves of {self.move_time_s:g} s"
        m = self.moves
        kinds = [f"{m.count(k)} by {k} ({m.seconds(k) / 3600.0:.4g} h)" if k != "fixed" else
                 f"{m.count(k)} of {self.move_time_s:g} s" for k in ("rail", "crane", "fixed") if m.count(k)]
        robots = f"; {m.robots} robots, each on its own stretch, the slowest's hours" if m.robots > 1 else ""
        return f"moves: {', '.join(kinds) or 'none'}{robots}"

    @property
    def relocation_cost(self) -> RelocationCost:
        """The moves' cost (:func:`~marinecdpr.studies.relocation.relocation_cost`): crane hire,
        rail, carriages and total, in the user's cost unit (all 0 without ``relocation``)."""
        if self.moves is None:
            return NO_COST
        return relocation_cost(self.relocation, self.moves, self.hours, self.band_length_m, self.platform_kg)

    @property
    def hours(self) -> float:
        return self.seconds / 3600.0

    @property
    def area_m2(self) -> float:
        """The cleanable patches' curved area, m^2."""
        return float(sum(p.area_m2 for p in self.placements))

    @property
    def uncleanable_area_m2(self) -> float:
        """The patches curved beyond the stand-off tolerance: their curved area, m^2."""
        return float(sum(p.area_m2 for p in self.uncleanable))

    @property
    def cleaning_hours(self) -> float:
        """All placements' cleaning, without the moves, h."""
        return float(self.job_s.sum()) / 3600.0

    @property
    def area_rate_m2_h(self) -> float:
        """The cleanable area over the whole time, moves included, m^2/h."""
        return self.area_m2 / self.hours if self.hours > 0 else 0.0

    def summary(self) -> dict:
        """``summary.json``'s ``surface``."""
        dev = [p.deviation_m for p in self.placements]
        return {"surface": self.surface, "frame_panel_m": list(self.frame_panel_m), "placements": len(self.placements),
                "uncleanable_patches": len(self.uncleanable),
                "uncleanable_area_m2": self.uncleanable_area_m2,
                "area_m2": self.area_m2, "cleaning_hours": self.cleaning_hours,
                "move_time_s": self.move_time_s, "hours": self.hours,
                "area_rate_m2_h": self.area_rate_m2_h,
                "largest_stand_off_deviation_m": float(max(dev)) if dev else 0.0} | self._relocation_summary()

    def _relocation_summary(self) -> dict:
        """With ``relocation``: ``relocation`` (its mode, robots, the moves and their hours by
        kind, each robot's hours, the costs)."""
        if self.moves is None:
            return {}
        m = self.moves
        kinds = ("fixed", "crane", "rail")
        return {"relocation": {
            "mode": self.relocation.mode, "robots": m.robots,
            "moves": {k: m.count(k) for k in kinds},
            "move_hours": {k: m.seconds(k) / 3600.0 for k in kinds},
            "robot_hours": [float(v) / 3600.0 for v in self.robot_seconds],
            "cost": self.relocation_cost.as_dict()}}


def _panel_time(cleaning: Cleaning, u: float, v: float, cache: dict, digits: int = 3) -> float:
    """The coverage path's duration over a u x v panel (its sides rounded to ``digits``
    decimals of a metre) with the scenario's tool, s."""
    return _panel_times(cleaning, u, v, cache, digits)[0]


def _panel_times(cleaning: Cleaning, u: float, v: float, cache: dict, digits: int = 3) -> tuple[float, float]:
    """The coverage path's duration over a u x v panel (its sides rounded to ``digits``
    decimals of a metre) with the scenario's tool, and the part of it spent off the lanes
    and the boundary pass (:func:`turn_time`), s."""
    from marinecdpr.motion.trajectory import cleaning_path

    key = (round(u, digits), round(v, digits))
    if key not in cache:
        u_, v_ = max(key[0], 1e-3), max(key[1], 1e-3)
        rect = [[0.0, 0.0], [u_, 0.0], [u_, v_], [0.0, v_]]
        data = cleaning.model_dump(exclude_none=True) | {"panel_m": rect, "holes_m": []}
        data.pop("surface", None)
        panel = Cleaning.model_validate(data)
        try:
            path = cleaning_path(panel)
            cache[key] = (float(path.duration_s), turn_time(path))
        except (ValueError, ScenarioError):  # a patch narrower than a lane: one pass along it
            cache[key] = (max(u_, v_) / cleaning.speed_m_s, 0.0)
    return cache[key]


def surface_patches(scenario: Scenario, panel_m: tuple[float, float] | None = None) -> int:
    """The patches of the first grid the tiling of ``[cleaning.surface]`` starts from
    (:func:`~marinecdpr.geometry.surface.first_grid`): the fewest it fits, known at once.

    Raises
    ------
    ScenarioError
        Over :data:`MAX_SURFACE_PATCHES`, or the band leaves the mesh.
    """
    from marinecdpr.geometry.surface import first_grid

    surface = scenario.cleaning.surface
    f = _band_function(surface)
    width, height = panel_m or frame_panel(scenario.cleaning)
    try:
        xs, zs = first_grid(f, surface.stations_m, surface.heights_m, width_m=width, height_m=height,
                            max_patches=MAX_SURFACE_PATCHES)
    except ScenarioError as exc:
        raise ScenarioError(exc.detail, key="cleaning.surface") from None
    return (xs.size - 1) * (zs.size - 1)


def _band_function(surface: Surface) -> Callable:
    f, _ = surface_function(surface)
    probe = f(np.linspace(*surface.stations_m, 5)[:, None], np.linspace(*surface.heights_m, 5)[None, :])
    if not np.isfinite(probe).all():
        raise ScenarioError("the band leaves the mesh: no hull side there at some stations or heights",
                            key="cleaning.surface.stations_m")
    return f


def turn_time(path) -> float:
    """The time a coverage path (:class:`~marinecdpr.motion.coverage.CoveragePath`) spends
    on segments that are neither lanes nor its boundary pass (the steps between lanes, the
    transfers between cells), s."""
    off = ~(np.asarray(path.lane_segment, dtype=bool) | np.asarray(path.boundary_segment, dtype=bool))
    return float(np.diff(path.vertex_time_s)[off].sum())


def surface_job(scenario: Scenario, *, move_time_s: float, panel_m: tuple[float, float] | None = None,
                digits: int = 3, progress: Callable[[float], None] | None = None,
                max_patches: int | None = MAX_SURFACE_PATCHES) -> SurfaceJob:
    """The placements on ``[cleaning.surface]`` and their hours.

    Parameters
    ----------
    scenario : Scenario
        With ``[cleaning]`` and its ``surface``.
    move_time_s : float
        Moving the frame from one placement to the next, s (without
        ``[cleaning.surface.relocation]``, or with its mode "fixed").
    panel_m : tuple of float, optional
        The frame's panel (along x, along z), m; default the scenario's (:func:`frame_panel`).
    digits : int
        Each placement's cleaning time is the coverage path's over its extent rounded to this
        many decimals of a metre (3: a millimetre; a design search takes 2, a centimetre:
        within about 1 % of the time, with far fewer paths to plan).
    progress : callable(share), optional
        The tiling's progress: the share of the band settled, 0 to 1
        (:func:`~marinecdpr.geometry.surface.tile_surface`).
    max_patches : int or None
        The most patches the tiling may fit (None: no limit).

    Raises
    ------
    ScenarioError
        The scenario has no ``[cleaning.surface]``, or its surface cannot be read there; a
        move time outside [0, :data:`MOVE_TIME_MAX_S`]; a band of more than
        ``max_patches`` patches; no patch of it flat enough for the tool's
        stand-off tolerance (no placement: no hours to give); hours that are not finite;
        a frame heavier than the relocation's crane lifts; a rail move the rail cannot make
        without a crane (:func:`~marinecdpr.studies.relocation.plan_moves`).
    """
    cleaning = scenario.cleaning
    if cleaning is None or cleaning.surface is None:
        raise ScenarioError("missing: clean --surface cleans the [cleaning.surface] band of the hull",
                            key="cleaning.surface")
    surface = cleaning.surface
    move_time_s = check_move_time(move_time_s)
    if surface.relocation is not None:
        try:  # before the tiling: a frame the crane cannot lift is one line at once
            surface.relocation.check_lift(scenario.robot.mass_kg)
        except ValueError as exc:
            raise ScenarioError(str(exc), key="cleaning.surface.relocation.crane.capacity_kg") from None
    f = _band_function(surface)
    _, label = surface_function(surface)
    width, height = panel_m or frame_panel(cleaning)
    try:
        placements, bad = tile_surface(f, surface.stations_m, surface.heights_m, width_m=width, height_m=height,
                                       tolerance_m=surface.stand_off_tolerance_m, max_patches=max_patches,
                                       progress=progress)
    except ScenarioError as exc:
        raise ScenarioError(exc.detail, key="cleaning.surface") from None
    if not placements:
        raise ScenarioError(f"no patch of the band is flat enough for the tool: each departs from its plane by more "
                            f"than stand_off_tolerance_m ({surface.stand_off_tolerance_m:g} m) even at "
                            f"{MIN_PATCH_M:g} m", key="cleaning.surface.stand_off_tolerance_m")
    cache: dict = {}
    times = np.array([_panel_times(cleaning, *p.extent_m, cache, digits) for p in placements]).reshape(-1, 2)
    job = times[:, 0]
    fields = np.array([[*p.centre_S, *p.normal_S, *p.offset_range_m, *p.extent_m, p.area_m2]
                       for p in placements + bad])
    if not np.isfinite(fields).all():
        raise ScenarioError("the band leaves the mesh between its samples: a patch has no hull side under it",
                            key="cleaning.surface.stations_m")
    if not (np.isfinite(job).all() and np.isfinite(job.sum() + len(placements) * move_time_s)):
        raise ScenarioError("the placements' hours are not finite", key="cleaning.surface")
    relocation, moves = surface.relocation, None
    if relocation is not None:
        moves = plan_moves(placements, job, relocation, move_time_s)
        if relocation.mode != "fixed":
            moved = moves.move_in_s[moves.kind != ""]
            move_time_s = float(moved.mean()) if moved.size else 0.0
    return SurfaceJob(placements=placements, uncleanable=bad, job_s=job, turn_s=times[:, 1],
                      move_time_s=float(move_time_s), relocation=relocation, moves=moves,
                      band_length_m=float(surface.stations_m[1] - surface.stations_m[0]),
                      platform_kg=float(scenario.robot.mass_kg),
                      frame_panel_m=(width, height), surface=f"{label}, {surface.side} side, stations "
                      f"{surface.stations_m[0]:g} to {surface.stations_m[1]:g} m, heights {surface.heights_m[0]:g} "
                      f"to {surface.heights_m[1]:g} m")
