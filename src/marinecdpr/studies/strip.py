"""A strip of the hull cleaned from a rail: the frame steps along ``[ship.carriage]``'s rail,
cleaning its panel at each station (``clean --surface --rail``; issue 39, item 3).

The stations
    C's origin stops on the rail one panel's width (the ``[cleaning]`` panel's extent along
    C's x) apart, from the start of each stretch of the rail the carriage can follow to its
    end (the last step shorter): :func:`rail_stations`. A bend of the rail whose radius
    (``corner_radius_m``) is below ``[cleaning.surface.relocation.rail] min_radius_m`` is not
    followed; the frame's pose at station s is the carriage's (:mod:`marinecdpr.motion.carriage`:
    C's origin at rail(s), its axes turned about S's z by the frame's yaw, the lean
    ``ship.frame_orientation_deg`` gives at the rail's start): :func:`station_poses`.

At each station
    The job's plan is made with the frame standing at the station's pose (the ship's motion
    at that place, the weight along the station's lean): the brush's planned centre in C and
    its normal force (:func:`~marinecdpr.prototype.parts.brush.normal_force`). Each brush
    point (x, 0, z) in C is carried to S and along the hull normal (C's y) onto the hull
    y = +-f(x, z) (:func:`surface_hits`): the hull's offset from the frame's plane there (the
    pusher's stand-off, within ``stand_off_tolerance_m`` or the brush loses the hull) and
    the angle between the push and the hull's own normal (the brush presses the hull with
    F_n cos(beta)). The brush cleans while the offset is within the tolerance and F_n cos(beta)
    within ``normal_force_N``; its swept discs are rasterised in the panel's plane
    (:func:`~marinecdpr.studies.coverage.coverage_map`, clipped to the panel).

Coverage on the hull
    The band of ``[cleaning.surface]`` (stations_m x heights_m) is rastered in the surface's
    own parameters (x, z) of S, each cell weighted by its true area (h^2 sqrt(1 + f_x^2 +
    f_z^2)); a cell is cleaned by a station when its point on the hull, taken into the
    station's C, falls on a cleaned cell of that station's raster: :func:`strip_coverage`.
    Its share of the strip counts the gaps where neighbouring panels do not meet on a
    flared or curved side, and the cells cleaned from more than one station.

Crane stretches
    The band's stretches along the ship that no rail station's panel reaches (beyond the
    rail's ends, across a bend it cannot follow) are cleaned from crane placements, as
    ``clean --surface`` tiles them (:func:`~marinecdpr.geometry.surface.tile_surface`), with
    the crane of ``[cleaning.surface.relocation]``; without one the job is refused naming the
    stretch. Their area is the placements' patches (not recounted here).

Continuous runs
    With ``mode`` "continuous" or "fastest" a followed stretch may instead be cleaned while the
    carriage moves (:class:`ContinuousRun`, :func:`continuous_run`): the brush's path laid on
    the ship over the stretch's footprint (``trajectory.on_hull``), the carriage running at
    V = lane spacing / (a lane and a step) so that the platform's path in C is a sawtooth in
    the panel; planned with the carriage moving over the horizon, the brush's contact carried
    to the hull by the carriage's pose at each step and rastered in the run's first C. Its
    hours are its path's; "fastest" takes, per stretch, the fewer hours. The first run (or
    every one) is also flown closed loop over the horizon (:func:`fly_continuous`: the
    controller flies the path held on the ship, the brush slides over the hull), its flown
    brush carried onto the hull the same way and its cleaned cells counted there beside the
    plan's.

Hours
    Each rail station's cleaning is the panel's coverage path; the carriage's move to the next
    station the double-S move of ``[ship.carriage]``'s speed, acceleration and jerk limits
    over their distance along the rail (:func:`~marinecdpr.motion.rail.scurve_move`) and the
    relocation's ``rail.settle_s`` (0 without); every move into or out of a crane stretch and
    between its placements a crane's (:func:`~marinecdpr.studies.relocation.crane_move_s`).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Callable

import numpy as np

from marinecdpr.errors import ScenarioError
from marinecdpr.scenario.schema import Scenario

__all__ = ["RailStrip", "StripCoverage", "CraneStretch", "ContinuousRun", "StretchChoice", "ContinuousError", "RAIL_MODES",
           "RunOnHull", "RunFlight", "run_on_hull", "fly_continuous", "FLY_RUNS", "followed_stretches",
           "continuous_run", "run_scenario", "rail_stations", "station_poses", "surface_hits", "strip_coverage",
           "rail_strip", "MAX_STRIP_CELLS", "STRIP_CELLS_PER_BRUSH"]

MAX_STRIP_CELLS = 10_000_000
"""The most cells of the strip's raster on the hull (the cell grows past width / 100 to hold it)."""
STRIP_CELLS_PER_BRUSH = 100
"""The strip's raster has at least this many cells across the brush's width, where it fits."""
_FD_M = 1e-4
"""The step of the surface's slopes by central differences, m."""


def rail_stations(rail, width_m: float, min_radius_m: float = 0.0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Where C's origin stops along a rail: ``width_m`` apart from the start of each stretch
    the carriage can follow, the last at its end.

    Parameters
    ----------
    rail : Rail
    width_m : float
        The step, m (the frame's panel along C's x).
    min_radius_m : float
        The tightest bend the carriage follows, m: the rail's bends of a smaller radius are
        left out (the stretches either side are followed apart).

    Returns
    -------
    s : ndarray, shape (n,)
        Arc lengths of the stations, m, increasing.
    stretch : ndarray of int, shape (n,)
        The followed stretch of each station, from 0.
    sharp : ndarray, shape (k, 2)
        The bends left out: their start and end arc lengths, m.
    """
    a, b, _, _ = rail.bends
    sharp = (np.column_stack([a, b]) if rail.least_radius_m < min_radius_m
             else np.zeros((0, 2)))
    starts = np.concatenate([[0.0], sharp[:, 1]])
    ends = np.concatenate([sharp[:, 0], [rail.length_m]])
    s, stretch = [], []
    for k, (lo, hi) in enumerate(zip(starts, ends)):
        steps = max(int(np.ceil((hi - lo) / width_m - 1e-9)), 0)
        here = lo + width_m * np.arange(steps)
        here = np.append(here, hi) if steps == 0 or hi - here[-1] > 1e-9 else here
        s.append(here)
        stretch.append(np.full(here.size, k))
    return np.concatenate(s), np.concatenate(stretch), sharp


def station_poses(ship, rail, s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The frame's pose on S at stations ``s`` of the carriage's rail, as the carriage
    carries it (:func:`~marinecdpr.motion.carriage.on_rail` at rest).

    Returns
    -------
    r_S : ndarray, shape (n, 3)
        C's origin in S, m.
    R_SC : ndarray, shape (n, 3, 3)
        C's axes in S (columns).
    """
    from marinecdpr.motion.carriage import frame_yaw, on_rail
    from marinecdpr.motion.ship import frame_axes

    s = np.asarray(s, dtype=float)
    points = rail.at(s)
    zero = np.zeros(s.size)
    r, _, _, R, _, _ = on_rail(points, frame_yaw(rail, s), zero, zero, frame_axes(ship.frame_orientation_deg))
    return r, R


def surface_hits(f: Callable, sign: float, p_S: np.ndarray, n_S: np.ndarray, *, iterations: int = 30
                 ) -> tuple[np.ndarray, np.ndarray]:
    """Where lines from points of the frame's plane along its normal meet the hull side
    y = sign f(x, z).

    Parameters
    ----------
    f : callable(X, Z) -> Y
        The side's distance from the centreline, m.
    sign : {1, -1}
        Port (+y) or starboard (-y).
    p_S : ndarray, shape (..., 3)
        Points of the frame's plane, in S, m.
    n_S : ndarray, shape (..., 3)
        The plane's unit normal (from the hull towards the robot) at each, in S.

    Returns
    -------
    t : ndarray, shape (...)
        The hull's offset from the plane along ``n_S``, m: it meets the line at p + t n
        (t > 0: the hull stands proud of the plane; NaN where no side is there).
    normal_S : ndarray, shape (..., 3)
        The hull's own unit normal out of the hull there, (-f_x, sign, -f_z) normalised.
    """
    p, n = np.asarray(p_S, dtype=float), np.broadcast_to(np.asarray(n_S, dtype=float), np.shape(p_S))

    def g(t):
        q = p + t[..., None] * n
        return sign * f(q[..., 0], q[..., 2]) - q[..., 1]

    t = np.zeros(p.shape[:-1])
    for _ in range(iterations):  # Newton's method, the slope by central differences
        g0 = g(t)
        slope = (g(t + _FD_M) - g(t - _FD_M)) / (2.0 * _FD_M)
        step = g0 / np.where(np.abs(slope) > 1e-12, slope, np.nan)
        t = t - step
        if not np.any(np.abs(step) > 1e-12):
            break
    q = p + t[..., None] * n
    x, z = q[..., 0], q[..., 2]
    fx = (f(x + _FD_M, z) - f(x - _FD_M, z)) / (2.0 * _FD_M)
    fz = (f(x, z + _FD_M) - f(x, z - _FD_M)) / (2.0 * _FD_M)
    N = np.stack([-fx, np.full_like(fx, float(sign)), -fz], axis=-1)
    return t, N / np.linalg.norm(N, axis=-1, keepdims=True)


@dataclass(frozen=True)
class StripCoverage:
    """The cleaned share of a strip of the hull, counted on the hull.

    Attributes
    ----------
    x, z : ndarray, shape (nx,), (nz,)
        The raster's cell centres: stations and heights of S, m (the surface's parameters).
    passes : ndarray of int16, shape (nz, nx)
        The stations that cleaned each cell; -1 outside the strip (a crane stretch).
    weight_m2 : ndarray of float32, shape (nz, nx)
        Each cell's area on the hull, m^2.
    station_pct : ndarray, shape (n_stations,)
        Each station's cleaned share of its own panel's footprint on the strip, %; then each
        continuous run's, of its raster's (the box of its brush's discs in its first C).
    resolution_m : float
    """

    x: np.ndarray
    z: np.ndarray
    passes: np.ndarray
    weight_m2: np.ndarray
    station_pct: np.ndarray
    resolution_m: float

    @property
    def area_m2(self) -> float:
        """The strip's area on the hull, m^2."""
        return float(self.weight_m2[self.passes >= 0].sum(dtype=np.float64))

    @property
    def cleaned_area_m2(self) -> float:
        return float(self.weight_m2[self.passes >= 1].sum(dtype=np.float64))

    @property
    def overlap_area_m2(self) -> float:
        """Cleaned from two or more stations, m^2."""
        return float(self.weight_m2[self.passes >= 2].sum(dtype=np.float64))

    @property
    def coverage_pct(self) -> float:
        return 100.0 * self.cleaned_area_m2 / self.area_m2 if self.area_m2 > 0 else 0.0

    @property
    def overlap_pct(self) -> float:
        """The area cleaned twice or more over the area cleaned, %."""
        return 100.0 * self.overlap_area_m2 / self.cleaned_area_m2 if self.cleaned_area_m2 > 0 else 0.0


def strip_coverage(f: Callable, sign: float, x_range, z_range, r_S: np.ndarray, R_SC: np.ndarray, maps: list, *,
                   width_m: float, excluded=(), resolution_m: float | None = None) -> StripCoverage:
    """The cleaned share of the band ``x_range`` x ``z_range`` of the hull y = sign f(x, z),
    from the stations' cleaned rasters in their panels' planes.

    Parameters
    ----------
    f, sign
        The side (:func:`surface_hits`).
    x_range, z_range : tuple of float
        The strip's stations and heights in S, m.
    r_S : ndarray, shape (n, 3)
        Each station's C origin in S, m.
    R_SC : ndarray, shape (n, 3, 3)
        Each station's C axes in S.
    maps : list of CoverageMap
        Each station's passes in its panel's plane, (x, z) of its C
        (:func:`~marinecdpr.studies.coverage.coverage_map`).
    width_m : float
        The brush's width, m (the raster's cell: width / :data:`STRIP_CELLS_PER_BRUSH`, or
        coarser to keep :data:`MAX_STRIP_CELLS`).
    excluded : sequence of (x0, x1)
        Stretches along the ship not in the strip (cleaned otherwise), m.
    resolution_m : float, optional
        The cell, m (default as above).

    Returns
    -------
    StripCoverage
    """
    (x0, x1), (z0, z1) = (float(v) for v in x_range), (float(v) for v in z_range)
    h = resolution_m or max(width_m / STRIP_CELLS_PER_BRUSH, float(np.sqrt((x1 - x0) * (z1 - z0) / MAX_STRIP_CELLS)))
    nx, nz = max(1, int(np.ceil((x1 - x0) / h))), max(1, int(np.ceil((z1 - z0) / h)))
    x = x0 + (np.arange(nx) + 0.5) * (x1 - x0) / nx
    z = z0 + (np.arange(nz) + 0.5) * (z1 - z0) / nz
    hx, hz = (x1 - x0) / nx, (z1 - z0) / nz

    def cells(i0: int, i1: int):  # columns i0:i1: the hull's points (nz, i1 - i0, 3) and their areas
        X, Z = np.meshgrid(x[i0:i1], z)
        fx = (f(X + _FD_M, Z) - f(X - _FD_M, Z)) / (2.0 * _FD_M)
        fz = (f(X, Z + _FD_M) - f(X, Z - _FD_M)) / (2.0 * _FD_M)
        return np.stack([X, sign * f(X, Z), Z], axis=-1), (hx * hz * np.sqrt(1.0 + fx * fx + fz * fz))

    chunk = max(1, 2_000_000 // nz)
    weight = np.concatenate([cells(i, min(i + chunk, nx))[1] for i in range(0, nx, chunk)], axis=1).astype(np.float32)
    passes = np.zeros((nz, nx), dtype=np.int16)
    out = np.zeros(nx, dtype=bool)
    for a, b in excluded:
        out |= (x >= a) & (x < b)
    passes[:, out] = -1
    station_pct = np.zeros(len(maps))
    for k, cov in enumerate(maps):
        R, r = R_SC[k], r_S[k]
        # the columns the station's panel can reach: its raster's corners carried to S, and a margin
        corners = np.array([[cov.x[0], cov.z[0]], [cov.x[-1], cov.z[0]], [cov.x[-1], cov.z[-1]], [cov.x[0], cov.z[-1]]])
        xs = r[0] + R[0, 0] * corners[:, 0] + R[0, 2] * corners[:, 1]
        reach = 2.0 * cov.resolution_m + 0.5 * width_m + abs(R[0, 1]) * 1.0
        i0, i1 = int(np.searchsorted(x, xs.min() - reach)), int(np.searchsorted(x, xs.max() + reach))
        if i1 <= i0:
            continue
        q, w = cells(i0, i1)
        c = (q - r) @ R  # R^T (q - r): the hull's points in the station's C
        ix = np.floor((c[..., 0] - (cov.x[0] - 0.5 * cov.resolution_m)) / cov.resolution_m).astype(np.int64)
        iz = np.floor((c[..., 2] - (cov.z[0] - 0.5 * cov.resolution_m)) / cov.resolution_m).astype(np.int64)
        inside = (ix >= 0) & (ix < cov.x.size) & (iz >= 0) & (iz < cov.z.size)
        got = np.full(ix.shape, -1, dtype=np.int32)
        got[inside] = cov.passes[iz[inside], ix[inside]]
        block = passes[:, i0:i1]
        mine = (got >= 0) & (block >= 0)
        cleaned = (got >= 1) & (block >= 0)
        block[cleaned] += 1
        station_pct[k] = 100.0 * w[cleaned].sum() / w[mine].sum() if mine.any() else 0.0
    return StripCoverage(x=x, z=z, passes=passes, weight_m2=weight, station_pct=station_pct,
                         resolution_m=float(max(hx, hz)))


@dataclass(frozen=True)
class CraneStretch:
    """A stretch of the band along the ship cleaned from crane placements.

    Attributes
    ----------
    x_m : tuple of float
        Its stations in S, m.
    why : str
        Aft or forward of the rail's reach, or across a bend it does not follow.
    placements : int
    cleaning_hours : float
    crane_moves : int
        The crane's moves into it, within it and back onto the rail.
    hours : float
        Its cleaning and those moves, h.
    """

    x_m: tuple
    why: str
    placements: int
    cleaning_hours: float
    crane_moves: int
    hours: float

    def as_dict(self) -> dict:
        """For summary.json."""
        return {"x_m": [float(v) for v in self.x_m], "why": self.why, "placements": self.placements,
                "cleaning_hours": self.cleaning_hours, "crane_moves": self.crane_moves, "hours": self.hours}


@dataclass(frozen=True)
class RailStrip:
    """A strip of the hull cleaned from a rail's stations and, where the rail does not reach,
    from crane placements; visits in order along the ship.

    Attributes
    ----------
    s_m : ndarray, shape (n,)
        The rail stations' arc lengths, m.
    origin_S : ndarray, shape (n, 3)
    axes_S : ndarray, shape (n, 3, 3)
        Each station's frame pose in S (C's origin, m; its axes as columns).
    clean_s : float
        One station's cleaning: the panel's coverage path, s.
    stand_off_m : ndarray, shape (n, 2)
        The least and largest offset of the hull from the frame's plane under the brush's
        planned path, m.
    force_N : ndarray, shape (n, 2)
        The least and largest normal force on the hull (F_n cos(beta)) along it, N.
    in_band_pct : ndarray, shape (n,)
        The share of the steps the brush cleans (in its stand-off and force band), %.
    coverage : StripCoverage
        On the hull.
    crane : list of Placement
        The crane stretches' placements, in the order visited (as ``clean --surface`` tiles
        them: a starboard side's with y as |y|, :func:`~marinecdpr.studies.surface.surface_function`).
    crane_s : ndarray, shape (m,)
        Their cleaning times, s.
    stretches : list of CraneStretch
        The band's stretches cleaned by crane, along the ship.
    visits : ndarray of int, shape (n + m,)
        The order of the visits: k >= 0 the rail station k, -1 - j the crane placement j.
    move_in_s : ndarray, shape (n + m,)
        The move into each visit, s (0 at the first).
    by_crane : ndarray of bool, shape (n + m,)
        Whether a crane made it.
    surface : str
    band_m : tuple
        The band's (stations, heights), m.
    tolerance_m : float
    side_sign : float
        1 port, -1 starboard (the crane placements' y and the side's).
    partial : bool
        The flown horizon ends before the panel's path (or a run's): each station's (run's)
        coverage is that part's.
    sharp : ndarray, shape (k, 2)
        The bends not followed (:func:`rail_stations`).
    runs : tuple of ContinuousRun
        The stretches cleaned while the carriage moves; visit ``n + j`` (n = ``s_m.size``) is run j.
    choices : tuple of StretchChoice
        Each followed stretch of the rail: the hours stepped and continuous, the mode taken.
    mode : {"stepped", "continuous", "fastest"}
        The mode asked.
    flights : tuple of RunFlight
        The continuous runs flown closed loop (:func:`fly_continuous`), in the runs' order: the
        first, or every one.
    """

    s_m: np.ndarray
    origin_S: np.ndarray
    axes_S: np.ndarray
    clean_s: float
    stand_off_m: np.ndarray
    force_N: np.ndarray
    in_band_pct: np.ndarray
    coverage: StripCoverage
    crane: list
    crane_s: np.ndarray
    stretches: list
    visits: np.ndarray
    move_in_s: np.ndarray
    by_crane: np.ndarray
    surface: str
    band_m: tuple
    tolerance_m: float
    side_sign: float = 1.0
    partial: bool = False
    sharp: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    runs: tuple = ()
    choices: tuple = ()
    mode: str = "stepped"
    flights: tuple = ()

    @property
    def flight(self) -> "RunFlight | None":
        """The first run's flight (:attr:`flights`), or None."""
        return self.flights[0] if self.flights else None

    @property
    def beyond_tolerance(self) -> np.ndarray:
        """The stations where the hull departs from the frame's plane under the brush by more
        than the tool's stand-off tolerance, shape (n,)."""
        return np.abs(self.stand_off_m).max(axis=1) > self.tolerance_m

    @property
    def run_beyond_tolerance(self) -> np.ndarray:
        """:attr:`beyond_tolerance` of the runs, shape (len(runs),)."""
        return np.array([max(abs(v) for v in r.stand_off_m) > self.tolerance_m if r.stand_off_m else False
                         for r in self.runs], dtype=bool)

    @property
    def run_seconds(self) -> float:
        """The continuous runs' cleaning (the carriage moving within it), s."""
        return float(sum(r.duration_s for r in self.runs))

    @property
    def seconds(self) -> float:
        """All the cleaning and moves, s."""
        out = self.s_m.size * self.clean_s + float(self.crane_s.sum()) + float(self.move_in_s.sum())
        return out + self.run_seconds if self.runs else out

    @property
    def hours(self) -> float:
        return self.seconds / 3600.0

    def parts_h(self) -> dict:
        """The hours by what they are spent on: ``cleaning_rail``, ``cleaning_crane``,
        ``moves_rail``, ``moves_crane``; they sum to :attr:`hours`."""
        return {"cleaning_rail": (self.s_m.size * self.clean_s + self.run_seconds) / 3600.0,
                "cleaning_crane": float(self.crane_s.sum()) / 3600.0,
                "moves_rail": float(self.move_in_s[~self.by_crane].sum()) / 3600.0,
                "moves_crane": float(self.move_in_s[self.by_crane].sum()) / 3600.0}

    def station_hours(self) -> np.ndarray:
        """Each rail station's cleaning and the move into it, h, shape (n,)."""
        out = np.full(self.s_m.size, self.clean_s)
        rail = (self.visits >= 0) & (self.visits < self.s_m.size)
        out[self.visits[rail]] += self.move_in_s[rail]
        return out / 3600.0

    def summary(self) -> dict:
        """``summary.json``'s ``strip``."""
        from marinecdpr.geometry.rotations import euler_from_matrix

        c = self.coverage
        return {"surface": self.surface, "stations_m": list(self.band_m[0]), "heights_m": list(self.band_m[1]),
                "rail_stations": int(self.s_m.size), "station_step_s": self.clean_s,
                "strip_area_m2": c.area_m2, "cleaned_area_m2": c.cleaned_area_m2, "coverage_pct": c.coverage_pct,
                "overlap_pct": c.overlap_pct, "coverage_resolution_m": c.resolution_m, "partial": bool(self.partial),
                "stand_off_m": [float(self.stand_off_m[:, 0].min()), float(self.stand_off_m[:, 1].max())]
                if self.s_m.size else [],
                "normal_force_N": [float(np.nanmin(self.force_N[:, 0])), float(np.nanmax(self.force_N[:, 1]))]
                if self.s_m.size else [],
                "stations_beyond_tolerance": int(self.beyond_tolerance.sum()),
                "bends_not_followed_m": [list(map(float, b)) for b in self.sharp],
                "crane_stretches": [c.as_dict() for c in self.stretches], "crane_placements": len(self.crane),
                "moves": {"rail": int((~self.by_crane[1:]).sum()), "crane": int(self.by_crane.sum())},
                "hours": self.hours, "hours_by_part": self.parts_h(),
                "first_pose_deg": (np.degrees(euler_from_matrix(self.axes_S[0])).tolist() if self.s_m.size else []),
                "rail_mode": self.mode, "rail_stretches": [c.as_dict() for c in self.choices],
                "continuous_runs": [r.as_dict() for r in self.runs]} | (
                    {"continuous_flight": self.flight.as_dict(),
                     "continuous_flights": [f.as_dict() for f in self.flights]} if self.flights else {})


RAIL_MODES = ("stepped", "continuous", "fastest")
"""How a stretch of the rail is cleaned: the carriage stepping the frame panel by panel, moving
it without stopping, or whichever of the two is the faster on each stretch."""
_T0_TOL_S = 1e-6
"""The carriage's start in a continuous run is found to this, s."""
_SAWTOOTH_TOL_M = 1e-6
"""How far the brush's centre may leave the panel's inset in a continuous run, m."""


class ContinuousError(ScenarioError):
    """A stretch the continuous mode cannot clean (its reason, one line, naming the key)."""


@dataclass(frozen=True)
class ContinuousRun:
    """A stretch of the rail cleaned while the carriage moves (the continuous mode).

    The brush's path is laid on the ship: a boustrophedon of lanes across the panel's height
    (C's z) over the stretch's whole footprint, in the frame's C at the stretch's first station
    (the panel's x from its least at the first station to its largest at the last); the
    carriage runs from the first station to the last, a double-S move at the speed V = lane
    spacing / (one lane and one step) within ``[ship.carriage]``'s acceleration and jerk,
    starting ``start_s`` after the path, so that the platform's path in C (the brush held on
    the ship, :func:`~marinecdpr.motion.trajectory.evaluate_trajectory` given the ship) is a sawtooth that stays within
    the panel; after the carriage stops, the brush cleans the last station's panel.

    Attributes
    ----------
    stretch : int
        The rail's followed stretch (:func:`rail_stations`).
    s_m : tuple of float
        The carriage's first and last arc lengths, m.
    speed_m_s : float
        V, m/s.
    start_s : float
        The carriage's start after the path's, s.
    carriage_s : float
        Its move, s.
    duration_s : float
        The run: the path's, s (the carriage moves within it).
    lanes : int
    spacing_m : float
    sawtooth_m : tuple of float
        The brush centre's least and largest x in C over the run, m.
    panel_m : ndarray, shape (4, 2)
        The path's rectangle on the ship, (x, z) in the first station's C, m.
    origin_S : ndarray, shape (3,)
    axes_S : ndarray, shape (3, 3)
        The first station's frame pose in S (C's origin, m; its axes).
    end_S : ndarray, shape (3,)
        The last station's panel centre in S, m (where a move out of the run starts).
    stand_off_m, force_N : tuple of float
        The least and largest hull offset under the brush and normal force on the hull over
        the planned horizon (:func:`rail_strip`), m, N.
    in_band_pct : float
        The share of the planned steps the brush cleans, %.
    """

    stretch: int
    s_m: tuple
    speed_m_s: float
    start_s: float
    carriage_s: float
    duration_s: float
    lanes: int
    spacing_m: float
    sawtooth_m: tuple
    panel_m: np.ndarray
    origin_S: np.ndarray
    axes_S: np.ndarray
    end_S: np.ndarray
    stand_off_m: tuple = ()
    force_N: tuple = ()
    in_band_pct: float = float("nan")

    def as_dict(self) -> dict:
        """For summary.json."""
        return {"stretch": self.stretch, "s_m": [float(v) for v in self.s_m], "speed_m_s": self.speed_m_s,
                "carriage_start_s": self.start_s, "carriage_move_s": self.carriage_s, "duration_s": self.duration_s,
                "lanes": self.lanes, "spacing_m": self.spacing_m, "sawtooth_m": [float(v) for v in self.sawtooth_m],
                "stand_off_m": [float(v) for v in self.stand_off_m], "normal_force_N": [float(v) for v in self.force_N],
                "in_band_pct": float(self.in_band_pct)}


@dataclass(frozen=True)
class StretchChoice:
    """How a followed stretch of the rail is cleaned, and the hours either way.

    Attributes
    ----------
    stretch : int
        The stretch (:func:`rail_stations`).
    s_m : tuple of float
        Its first and last stations' arc lengths, m.
    stations : int
    stepped_h : float
        Its stations' cleaning, the carriage's moves and settles, h.
    continuous_h : float or None
        Its continuous run's, h; None where the continuous mode cannot clean it.
    continuous_speed_m_s : float or None
        The run's carriage speed V, m/s.
    why_not : str or None
        Why the continuous mode cannot clean it (the refusal's line).
    mode : {"stepped", "continuous"}
        The mode taken.
    """

    stretch: int
    s_m: tuple
    stations: int
    stepped_h: float
    continuous_h: float | None
    continuous_speed_m_s: float | None
    why_not: str | None
    mode: str

    def as_dict(self) -> dict:
        """For summary.json."""
        return {"stretch": self.stretch, "s_m": [float(v) for v in self.s_m], "stations": self.stations,
                "stepped_h": self.stepped_h, "continuous_h": self.continuous_h,
                "continuous_speed_m_s": self.continuous_speed_m_s, "continuous_why_not": self.why_not,
                "mode": self.mode}


def run_scenario(scenario: Scenario, s_a: float, s_b: float, dwell_s: float = 0.0, speed_m_s: float | None = None
                 ) -> Scenario:
    """The scenario of a continuous run from rail arc length ``s_a`` to ``s_b``: the carriage
    resting ``dwell_s`` at ``s_a`` and moving to ``s_b`` at ``speed_m_s`` (default its
    ``speed_max_m_s``), the brush's path laid on the ship (``trajectory.on_hull``) across the
    stretch's footprint, lanes along C's z, no boundary pass.

    Raises
    ------
    ContinuousError
        A panel that is not a rectangle along C's axes, or one with holes.
    """
    cleaning = scenario.cleaning
    panel = np.asarray(cleaning.panel_m, dtype=float)
    (x_lo, z_lo), (x_hi, z_hi) = panel.min(axis=0), panel.max(axis=0)
    from marinecdpr.geometry.polygons import polygon_area

    if cleaning.holes_m or panel.shape[0] != 4 or \
            abs(abs(polygon_area(panel)) - (x_hi - x_lo) * (z_hi - z_lo)) > 1e-9 * (x_hi - x_lo) * (z_hi - z_lo):
        raise ContinuousError("the continuous mode sweeps a rectangle along C's x and z without holes: the panel "
                              "slides under the frame", key="cleaning.panel_m")
    L = float(s_b - s_a)
    sc = scenario.with_updates("trajectory", on_hull=True)
    carriage = {"stations_m": [float(s_a), float(s_b)], "dwell_s": [float(dwell_s), 0.0]}
    if speed_m_s is not None:
        carriage["speed_max_m_s"] = float(speed_m_s)
    sc = sc.with_updates("ship.carriage", **carriage)
    rect = [[x_lo, z_lo], [x_hi + L, z_lo], [x_hi + L, z_hi], [x_lo, z_hi]]
    return sc.with_updates("cleaning", panel_m=rect, holes_m=[], direction_deg=90.0, boundary_pass=False)


def continuous_run(scenario: Scenario, rail, s_a: float, s_b: float, stretch: int = 0) -> ContinuousRun:
    """A stretch of the rail from ``s_a`` to ``s_b`` cleaned while the carriage moves (the
    geometry and timing of :class:`ContinuousRun`; no plan).

    The carriage's start after the path's is the earliest at which the brush's centre never
    falls behind the panel's inset (x >= x_min + r in C), found by bisection to
    :data:`_T0_TOL_S` over the path's corners, a fine grid after each (where the brush, leaving
    a corner at rest, falls furthest behind) and a 0.05 s grid (the platform's path in C
    from :func:`~marinecdpr.motion.trajectory.evaluate_trajectory`: the path less the
    carriage's travel along the rail); the run is refused where the brush's centre must then pass the panel's other
    edge by more than :data:`_SAWTOOTH_TOL_M` (its heights are the path's own: the compensation
    is along C's x).

    Raises
    ------
    ContinuousError
        One line naming the key: a panel that is not a rectangle without holes; a stretch of
        one station; a V above the carriage's ``speed_max_m_s``; a sawtooth the panel cannot
        hold (a panel narrower than a lane and the carriage's lag).
    """
    from marinecdpr.motion.rail import scurve_move
    from marinecdpr.motion.trajectory import cleaning_path, evaluate_trajectory

    carriage = scenario.ship.carriage
    if not s_b - s_a > 1e-9:
        raise ContinuousError(f"the stretch at s = {s_a:.4g} m has one station: nothing to run along",
                              key="ship.carriage.rail_m")
    sc = run_scenario(scenario, s_a, s_b)
    cleaning = sc.cleaning
    path = cleaning_path(cleaning)
    if path.lanes < 2:
        raise ContinuousError("the continuous mode needs two lanes or more across the stretch", key="cleaning.panel_m")
    cycle = float(path.vertex_time_s[2] - path.vertex_time_s[0])  # a lane and a step
    V = path.spacing_m / cycle
    if V > carriage.speed_max_m_s:
        raise ContinuousError(f"the continuous mode runs the carriage at {V:.4g} m/s (a lane of {path.spacing_m:.4g} "
                              f"m every {cycle:.4g} s), above its speed_max_m_s {carriage.speed_max_m_s:g} m/s",
                              key="ship.carriage.speed_max_m_s")
    move = scurve_move(s_b - s_a, V, carriage.accel_max_m_s2, carriage.jerk_max_m_s3)
    T = float(path.duration_s)
    panel = np.asarray(scenario.cleaning.panel_m, dtype=float)
    x_lo, x_hi = panel[:, 0].min(), panel[:, 0].max()
    r = 0.5 * cleaning.brush_diameter_m
    start = sc.trajectory.start_time_s
    # the brush's least x in C comes just after each corner (it leaves at rest while the carriage
    # runs on): the corners, a fine grid after each, and a 0.05 s grid
    after = 2.0 * (cleaning.acceleration_m_s2 / cleaning.jerk_m_s3 + V / cleaning.acceleration_m_s2) + 0.05
    fine = (path.vertex_time_s[:, None] + np.linspace(0.0, after, 151)[None, :]).ravel()
    grid = start + np.union1d(np.union1d(path.vertex_time_s, np.arange(0.0, T, 0.05)), fine[fine <= T])
    offset = np.asarray(cleaning.brush_offset_m, dtype=float)

    def brush_C(t0: float) -> np.ndarray:  # the brush centre's (x, z) in C over the grid
        run = sc.with_updates("ship.carriage", dwell_s=[start + t0, 0.0], speed_max_m_s=V)
        pose = evaluate_trajectory(run.trajectory, grid, run.cleaning, run.ship)
        return (pose.pose[:, :3] + np.einsum("nij,j->ni", pose.R_PC, offset))[:, [0, 2]]

    latest = T - move.duration_s
    if latest < 0.0:
        raise ContinuousError(f"the carriage's move over the stretch ({move.duration_s:.4g} s) outlasts the brush's "
                              f"path ({T:.4g} s)", key="ship.carriage.accel_max_m_s2")
    lo_edge = x_lo + r - 1e-12 * max(1.0, abs(x_lo) + r)  # the inset's edge, where the path starts
    if brush_C(0.0)[:, 0].min() >= lo_edge:
        t0 = 0.0
    else:
        a, b = 0.0, latest
        if brush_C(b)[:, 0].min() < lo_edge:
            raise ContinuousError("the brush falls behind the panel however late the carriage starts",
                                  key="cleaning.panel_m")
        while b - a > _T0_TOL_S:
            mid = 0.5 * (a + b)
            a, b = (a, mid) if brush_C(mid)[:, 0].min() >= lo_edge else (mid, b)
        t0 = b
    c = brush_C(t0)
    if c[:, 0].max() > x_hi - r + _SAWTOOTH_TOL_M:
        raise ContinuousError(f"the continuous mode's sawtooth leaves the panel: the brush's centre reaches x = "
                              f"{c[:, 0].max():.4g} m in C, beyond the panel's {x_hi - r:.4g} m less the brush's "
                              f"radius (a lane of {path.spacing_m:.4g} m and the carriage's lag)",
                              key="cleaning.panel_m")
    r0, R0 = station_poses(scenario.ship, rail, np.array([s_a, s_b]))
    centre = panel.mean(axis=0)
    end = r0[1] + R0[1][:, 0] * centre[0] + R0[1][:, 2] * centre[1]
    return ContinuousRun(stretch=int(stretch), s_m=(float(s_a), float(s_b)), speed_m_s=float(V), start_s=float(t0),
                         carriage_s=float(move.duration_s), duration_s=T, lanes=int(path.lanes),
                         spacing_m=float(path.spacing_m), sawtooth_m=(float(c[:, 0].min()), float(c[:, 0].max())),
                         panel_m=np.asarray(cleaning.panel_m, dtype=float), origin_S=r0[0], axes_S=R0[0], end_S=end)


@dataclass(frozen=True)
class RunOnHull:
    """A continuous run's brush carried onto the hull (:func:`run_on_hull`); arrays (n_steps, ...).

    Attributes
    ----------
    stand_off_m : ndarray, shape (n_steps,)
        The hull's offset from the frame's plane under the brush along C's y, m.
    force_N : ndarray, shape (n_steps,)
        The normal force on the hull, F_n cos(beta), N.
    contact : ndarray of bool, shape (n_steps,)
        The brush cleans: the stand-off within the tolerance, the force in ``normal_force_N``.
    on_ship : ndarray, shape (n_steps, 3)
        The brush's contact point on the hull in the run's first C (the panel on the ship), m.
    """

    stand_off_m: np.ndarray
    force_N: np.ndarray
    contact: np.ndarray
    on_ship: np.ndarray

    def coverage_map(self, brush_diameter_m: float):
        """The contact's discs rastered in the run's first C (:func:`~marinecdpr.studies.coverage.
        coverage_map`) over the box they span: the brush stays in the panel of the frame that
        carries it, but where the rail bends the frame turns and its discs land off the first
        C's panel."""
        from marinecdpr.studies.coverage import coverage_map

        r_b = 0.5 * brush_diameter_m
        xz = self.on_ship[:, [0, 2]]
        (x_a, z_a), (x_b, z_b) = xz.min(axis=0) - r_b, xz.max(axis=0) + r_b
        box = np.array([[x_a, z_a], [x_b, z_a], [x_b, z_b], [x_a, z_b]])
        return coverage_map(box, [], xz, self.contact, width_m=brush_diameter_m)


def run_on_hull(run: "ContinuousRun", scenario: Scenario, t: np.ndarray, pose: np.ndarray, F_n: np.ndarray
                ) -> RunOnHull:
    """A continuous run's brush on the hull: each brush centre (x, 0, z) in C (from the
    platform's ``pose``) carried to S by the carriage's pose at its time, then along C's y onto
    the hull (:func:`surface_hits`), its normal force ``F_n`` pressing the hull by cos(beta).

    Parameters
    ----------
    run : ContinuousRun
    scenario : Scenario
        The run's (:func:`run_scenario`: its carriage's motion, ``[cleaning.surface]``).
    t : ndarray, shape (n_steps,)
        Times, s.
    pose : ndarray, shape (n_steps, 6)
        The platform's pose in C (planned or flown), m and rad.
    F_n : ndarray, shape (n_steps,)
        The brush's normal force along C's y, N.

    Raises
    ------
    ScenarioError
        Where the brush's path meets no side of the surface (key ship.carriage.rail_m).
    """
    from marinecdpr.motion.carriage import carriage_motion
    from marinecdpr.studies.cleaning import brush_positions
    from marinecdpr.studies.surface import surface_function

    cleaning = scenario.cleaning
    surface = cleaning.surface
    f, _ = surface_function(surface)
    sign = 1.0 if surface.side == "port" else -1.0
    tol = float(surface.stand_off_tolerance_m)
    lo, hi = cleaning.band_N
    b = brush_positions(pose, cleaning.brush_offset_m)[:, [0, 2]]
    r_t, _, _, R_t, _, _ = carriage_motion(scenario.ship, t)
    pts = r_t + b[:, :1] * R_t[:, :, 0] + b[:, 1:] * R_t[:, :, 2]
    n_S = float(cleaning.hull_normal[1]) * R_t[:, :, 1]
    off, N = surface_hits(f, sign, pts, n_S)
    if not np.isfinite(off).all():
        raise ScenarioError(f"the rail leaves the hull: in the run from s = {run.s_m[0]:.4g} m the brush's path "
                            "meets no side of the surface", key="ship.carriage.rail_m")
    F_hull = F_n * np.einsum("ni,ni->n", N, n_S)
    contact = (np.abs(off) <= tol) & (F_hull >= lo - 1e-9 * max(hi, 1.0)) & (F_hull <= hi + 1e-9 * max(hi, 1.0))
    on_ship = ((pts + off[:, None] * n_S) - run.origin_S) @ run.axes_S  # the contact in the run's first C
    return RunOnHull(stand_off_m=off, force_N=F_hull, contact=contact, on_ship=on_ship)


@dataclass(frozen=True)
class RunFlight:
    """A continuous run flown closed loop on the virtual prototype over the scenario's horizon
    (:func:`fly_continuous`), the flown brush carried onto the hull. Arrays share ``n_steps``.

    Attributes
    ----------
    stretch : int
        The run's stretch of the rail (:class:`ContinuousRun`).
    plant : str
    t : ndarray, shape (n_steps,)
        s.
    pose, pose_planned : ndarray, shape (n_steps, 6)
        The platform's pose in C flown and planned (the path held on the ship), m and rad.
    hull, planned : RunOnHull
        The flown brush on the hull, and the plan's over the same steps.
    tracking_m : ndarray, shape (n_steps,)
        The flown brush's distance from the planned one in C's x-z plane, m.
    cross_track_m : ndarray, shape (n_steps,)
        Its part across the planned brush's direction of travel on the hull (its velocity in C
        with the carriage's added, :func:`~marinecdpr.planning.planner.twist_on_hull`), m.
    tensions : ndarray, shape (n_steps, m)
        The cables' applied tensions, N.
    coverage, planned_coverage : StripCoverage
        The band's cells the flown (planned) brush cleaned, counted on the hull over the run's reach
        along the ship (:func:`strip_coverage`).
    path_s : float
        The run's whole path, s (``partial`` where the horizon ends before it).
    step_s : float
        The exchange's step, s.
    controller_fallbacks : int
    controller_bypassed_share : float
    controller_verdict : str
        :func:`~marinecdpr.studies.prototype_runs.controller_verdict`'s.
    """

    stretch: int
    plant: str
    t: np.ndarray
    pose: np.ndarray
    pose_planned: np.ndarray
    hull: RunOnHull
    planned: RunOnHull
    tracking_m: np.ndarray
    cross_track_m: np.ndarray
    tensions: np.ndarray
    coverage: StripCoverage
    planned_coverage: StripCoverage
    path_s: float
    step_s: float
    controller_fallbacks: int
    controller_bypassed_share: float
    controller_verdict: str

    @property
    def flown_s(self) -> float:
        """The horizon flown, s (its steps' exchanges)."""
        return float(self.t.size * self.step_s)

    @property
    def partial(self) -> bool:
        """The horizon ends before the run's path."""
        return self.flown_s < self.path_s * (1.0 - 1e-9)

    @property
    def in_band_pct(self) -> float:
        """The share of the steps the flown brush cleans (stand-off and force in band), %."""
        return 100.0 * float(self.hull.contact.mean())

    @property
    def force_range_N(self) -> tuple[float, float]:
        """The least and largest normal force on the hull, N."""
        return float(self.hull.force_N.min()), float(self.hull.force_N.max())

    @property
    def stand_off_range_m(self) -> tuple[float, float]:
        """The least and largest stand-off under the flown brush, m."""
        return float(self.hull.stand_off_m.min()), float(self.hull.stand_off_m.max())

    @property
    def tension_range_N(self) -> tuple[float, float]:
        return float(self.tensions.min()), float(self.tensions.max())

    @property
    def cleaned_of_planned_pct(self) -> float:
        """The flown record's cleaned area on the hull over the plan's, %."""
        planned = self.planned_coverage.cleaned_area_m2
        return 100.0 * self.coverage.cleaned_area_m2 / planned if planned > 0 else 0.0

    def as_dict(self) -> dict:
        """For summary.json's ``strip`` (``continuous_flight``): forces N, lengths m, areas m^2, %."""
        return {"stretch": self.stretch, "plant": self.plant, "steps": int(self.t.size), "flown_s": self.flown_s,
                "run_s": self.path_s, "partial": self.partial, "normal_force_in_band_pct": self.in_band_pct,
                "normal_force_N": list(self.force_range_N), "stand_off_m": list(self.stand_off_range_m),
                "max_tracking_error_m": float(self.tracking_m.max()),
                "p95_tracking_error_m": float(np.percentile(self.tracking_m, 95)),
                "max_cross_track_error_m": float(self.cross_track_m.max()),
                "p95_cross_track_error_m": float(np.percentile(self.cross_track_m, 95)),
                "tension_min_N": self.tension_range_N[0], "tension_max_N": self.tension_range_N[1],
                "cleaned_area_m2": self.coverage.cleaned_area_m2,
                "planned_cleaned_area_m2": self.planned_coverage.cleaned_area_m2,
                "cleaned_of_planned_pct": self.cleaned_of_planned_pct, "overlap_pct": self.coverage.overlap_pct,
                "coverage_resolution_m": self.coverage.resolution_m, "controller_fallbacks": self.controller_fallbacks,
                "controller_bypassed_share": self.controller_bypassed_share,
                "controller_verdict": self.controller_verdict}


FLY_RUNS = ("first", "all")
"""Which of a strip's continuous runs :func:`fly_continuous` flies closed loop: its first, or
every one (each over the scenario's horizon)."""


def fly_continuous(strip: "RailStrip", scenario: Scenario, *, runs: str = "first", plant: str | None = None,
                   progress: Callable[[int, int], None] | None = None) -> "RailStrip":
    """The strip with its continuous runs flown closed loop (:attr:`RailStrip.flights`), as the
    stepped job's closed loop is flown: each planned with the carriage moving (:func:`run_scenario`,
    the carriage starting as :func:`rail_strip` found), over ``scenario``'s horizon, on the
    virtual prototype (the controller flying the path held on the ship, the brush sliding over
    the hull); the flown brush carried onto the hull by the carriage's pose at each step
    (:func:`run_on_hull`, the plan's normal force) and its cleaned cells counted there. The
    strip unchanged where it has no continuous run.

    Parameters
    ----------
    strip : RailStrip
        :func:`rail_strip`'s of ``scenario``.
    runs : {"first", "all"}
        The first run, or every one (:data:`FLY_RUNS`), one after the other.
    plant : {"mujoco", "own"}, optional
        Default the scenario's ``simulation.plant``.
    progress : callable(done, total), optional
        Steps flown, each run's from 0 to its ``n_steps``.

    Raises
    ------
    InfeasibleError, SimulationDivergedError, ScenarioError
        As the runs' plans and flights raise them.
    ValueError
        ``runs`` not one of :data:`FLY_RUNS`.
    """
    if runs not in FLY_RUNS:
        raise ValueError(f"runs must be first or all, got {runs!r}")
    if not strip.runs:
        return strip
    flights = tuple(_fly_run(strip, scenario, run, plant=plant, progress=progress)
                    for run in (strip.runs if runs == "all" else strip.runs[:1]))
    return replace(strip, flights=flights)


def followed_stretches(scenario: Scenario) -> int:
    """How many stretches of ``scenario``'s rail the carriage follows (:func:`rail_stations`,
    the bends tighter than ``[cleaning.surface.relocation.rail] min_radius_m`` left out): the
    most continuous runs its strip can have."""
    from marinecdpr.motion.carriage import rail_of

    _check_scenario(scenario)
    relocation = scenario.cleaning.surface.relocation
    min_radius = relocation.rail.min_radius_m if relocation is not None and relocation.rail is not None else 0.0
    _, stretch, _ = rail_stations(rail_of(scenario.ship), 1.0, min_radius)  # every stretch has a station at any step
    return int(np.unique(stretch).size)


def _fly_run(strip: "RailStrip", scenario: Scenario, run: "ContinuousRun", *, plant: str | None,
             progress: Callable[[int, int], None] | None) -> RunFlight:
    """One continuous run of ``strip`` flown closed loop (:func:`fly_continuous`)."""
    from marinecdpr.geometry.rotations import matrix_from_euler
    from marinecdpr.model.brush import brush_velocity
    from marinecdpr.planning.planner import plan, twist_on_hull
    from marinecdpr.prototype.parts.brush import normal_force
    from marinecdpr.prototype.simulation import simulate
    from marinecdpr.prototype.warmup import compile_apart
    from marinecdpr.studies.cleaning import brush_positions, cross_track_error
    from marinecdpr.studies.prototype_runs import controller_verdict
    from marinecdpr.studies.surface import surface_function

    sc = run_scenario(scenario, *run.s_m, dwell_s=scenario.trajectory.start_time_s + run.start_s,
                      speed_m_s=run.speed_m_s)
    compile_apart(sc, plant=plant)  # on a cold cache: the planner, the controller and the loop at once
    p = plan(sc)
    res = simulate(sc, run="closed_loop", reference=p, plant=plant, progress=progress)
    n, cleaning = res.t.size, sc.cleaning
    F = normal_force(p, sc)[:n]
    flown = run_on_hull(run, sc, res.t, res.pose, F)
    planned = run_on_hull(run, sc, res.t, res.pose_planned, F)
    offset = cleaning.brush_offset_m
    e = (brush_positions(res.pose, offset) - brush_positions(res.pose_planned, offset))[:, [0, 2]]
    twist = twist_on_hull(sc, p.pose[:n, :3], p.twist[:n], res.t)
    v_hull = brush_velocity(twist[:, :3], twist[:, 3:], matrix_from_euler(p.pose[:n, 3:]), offset)
    cross = cross_track_error(e, np.zeros_like(e), v_hull[:, [0, 2]])
    # the band's cells along the ship the run's discs reach (both records'): counted on the hull
    f, _ = surface_function(cleaning.surface)
    sign = 1.0 if cleaning.surface.side == "port" else -1.0
    maps = [flown.coverage_map(cleaning.brush_diameter_m), planned.coverage_map(cleaning.brush_diameter_m)]
    corners = np.array([[m.x[i], m.z[j]] for m in maps for i in (0, -1) for j in (0, -1)])  # in the first C
    xs = run.origin_S[0] + corners @ run.axes_S[0, [0, 2]]
    (X0, X1), (Z0, Z1) = strip.band_m
    margin = cleaning.brush_diameter_m
    x_range = (max(X0, float(xs.min()) - margin), min(X1, float(xs.max()) + margin))
    cov = [strip_coverage(f, sign, x_range, (Z0, Z1), run.origin_S[None], run.axes_S[None], [m],
                          width_m=cleaning.brush_diameter_m) for m in maps]
    return RunFlight(stretch=run.stretch, plant=res.plant, t=res.t, pose=res.pose, pose_planned=res.pose_planned,
                     hull=flown, planned=planned,
                     tracking_m=np.linalg.norm(e, axis=1), cross_track_m=cross, tensions=res.tensions,
                     coverage=cov[0], planned_coverage=cov[1], path_s=run.duration_s, step_s=sc.time.step_s,
                     controller_fallbacks=int(res.controller_fallbacks), **controller_verdict(res, sc))


def _check_scenario(scenario: Scenario):
    """The rail strip's inputs: ``[cleaning.surface]``, ``[ship.carriage]``, a hull normal
    along C's y, one robot. ScenarioError (one line, the key) otherwise."""
    cleaning = scenario.cleaning
    if cleaning is None or cleaning.surface is None:
        raise ScenarioError("missing: clean --surface --rail cleans the [cleaning.surface] band of the hull",
                            key="cleaning.surface")
    if scenario.ship.carriage is None:
        raise ScenarioError("missing: clean --rail steps the frame along [ship.carriage]'s rail: give the rail "
                            "and the carriage's limits", key="ship.carriage")
    if abs(abs(cleaning.hull_normal[1]) - 1.0) > 1e-9:
        raise ScenarioError("must be [0, 1, 0] or [0, -1, 0] with --rail: the panel lies in C's x-z plane and the "
                            "pusher reaches the hull along C's y", key="cleaning.hull_normal")
    relocation = cleaning.surface.relocation
    if relocation is not None and relocation.robots != 1:
        raise ScenarioError(f"must be 1 with --rail, got {relocation.robots}: one carriage steps one frame along "
                            "the rail", key="cleaning.surface.relocation.robots")


def rail_strip(scenario: Scenario, *, progress: Callable[[float], None] | None = None,
               resolution_m: float | None = None, mode: str = "stepped") -> RailStrip:
    """The strip of ``[cleaning.surface]`` cleaned from the stations of ``[ship.carriage]``'s
    rail (the module's rules), over the scenario's horizon (``time.duration_s``: each
    station's plan and coverage are of that part of the panel's path; its hours the whole
    path's).

    Parameters
    ----------
    progress : callable(share), optional
        The share of the stations (and runs) planned, 0 to 1.
    mode : {"stepped", "continuous", "fastest"}
        How each followed stretch of the rail is cleaned (:data:`RAIL_MODES`): stepped from its
        stations; while the carriage moves (:class:`ContinuousRun`, planned with the carriage
        moving over the horizon from the stretch's start); or whichever takes the fewer
        hours (stepped: its stations' cleaning, the carriage's moves and settles; continuous:
        the run's path, the carriage moving within it). Either way both hours are in
        :attr:`RailStrip.choices`.
    resolution_m : float, optional
        The cell of the coverage's raster on the hull, m (default :func:`strip_coverage`'s).
        Its worst error is where the cleaned region's edge runs along the raster (the band's
        own edges: x or z constant): h / 2 a metre of such an edge.

    Raises
    ------
    ScenarioError
        One line naming the key: no surface or carriage; a hull normal off C's y; more than one
        robot; a rail that leaves the band (a station's panel wholly beyond its stations_m or
        its heights_m) or the mesh; a rail that stands off the hull beyond the
        tool's stand-off tolerance at every station; a crane stretch without a crane, or a frame
        the crane cannot lift; a crane stretch that cannot be tiled; with ``mode`` "continuous",
        a stretch the continuous mode cannot clean (:func:`continuous_run`); an unknown mode.
    """
    from marinecdpr.geometry.rotations import euler_from_matrix
    from marinecdpr.geometry.surface import MIN_PATCH_M, tile_surface
    from marinecdpr.motion.carriage import rail_of
    from marinecdpr.motion.rail import scurve_move
    from marinecdpr.motion.trajectory import cleaning_path
    from marinecdpr.planning.planner import plan
    from marinecdpr.prototype.parts.brush import normal_force
    from marinecdpr.studies.cleaning import brush_positions
    from marinecdpr.studies.coverage import coverage_map
    from marinecdpr.studies.relocation import crane_move_s, visit_order
    from marinecdpr.studies.surface import MAX_SURFACE_PATCHES, _panel_times, frame_panel, surface_function

    if mode not in RAIL_MODES:
        raise ScenarioError(f"unknown rail mode {mode!r}: expected stepped, continuous or fastest", key="rail_mode")
    _check_scenario(scenario)
    cleaning, ship = scenario.cleaning, scenario.ship
    surface, carriage = cleaning.surface, ship.carriage
    relocation = surface.relocation
    f, label = surface_function(surface)
    sign = 1.0 if surface.side == "port" else -1.0
    (X0, X1), (Z0, Z1) = surface.stations_m, surface.heights_m
    tol = float(surface.stand_off_tolerance_m)
    rail = rail_of(ship)
    panel = np.asarray(cleaning.panel_m, dtype=float)
    holes = [np.asarray(h, dtype=float) for h in cleaning.holes_m]
    width, height = frame_panel(cleaning)
    min_radius = relocation.rail.min_radius_m if relocation is not None and relocation.rail is not None else 0.0
    settle = relocation.rail.settle_s if relocation is not None and relocation.rail is not None else 0.0
    s, stretch, sharp = rail_stations(rail, width, min_radius)
    r_S, R_SC = station_poses(ship, rail, s)
    # the rail on the band: each station's panel reaching its stations and its heights
    corners_S = r_S[:, None, :] + np.einsum("nij,kj->nki", R_SC[:, :, [0, 2]], panel)
    for axis, (a, b), what, key in ((0, (X0, X1), "stations", "stations_m"), (2, (Z0, Z1), "heights", "heights_m")):
        lo_k, hi_k = corners_S[..., axis].min(axis=1), corners_S[..., axis].max(axis=1)
        off = np.flatnonzero((hi_k <= a) | (lo_k >= b))
        if off.size:
            k = int(off[0])
            raise ScenarioError(f"the rail leaves the [cleaning.surface] band: at s = {s[k]:.4g} m the frame's panel "
                                f"spans {what} {lo_k[k]:.4g} to {hi_k[k]:.4g} m in S, outside its {key} "
                                f"[{a:g}, {b:g}] m", key="ship.carriage.rail_m")
    # each followed stretch: stepped or continuous, by the hours of each
    path = cleaning_path(cleaning)
    choices, runs = [], []
    for k in np.unique(stretch):
        idx = np.flatnonzero(stretch == k)
        stepped_s = idx.size * float(path.duration_s) + sum(
            scurve_move(s[i + 1] - s[i], carriage.speed_max_m_s, carriage.accel_max_m_s2,
                        carriage.jerk_max_m_s3).duration_s + settle for i in idx[:-1])
        run, why = None, None
        try:
            run = continuous_run(scenario, rail, float(s[idx[0]]), float(s[idx[-1]]), int(k))
        except ScenarioError as exc:
            if mode == "continuous":
                raise ScenarioError(f"the continuous mode cannot clean the rail's stretch from s = {s[idx[0]]:.4g} to "
                                    f"{s[idx[-1]]:.4g} m: {exc.detail}", key=exc.key) from None
            why = f"{exc.key}: {exc.detail}" if exc.key else exc.detail
        take = "continuous" if run is not None and (mode == "continuous" or (
            mode == "fastest" and run.duration_s < stepped_s)) else "stepped"
        if take == "continuous":
            runs.append(run)
        choices.append(StretchChoice(stretch=int(k), s_m=(float(s[idx[0]]), float(s[idx[-1]])), stations=int(idx.size),
                                     stepped_h=stepped_s / 3600.0,
                                     continuous_h=None if run is None else run.duration_s / 3600.0,
                                     continuous_speed_m_s=None if run is None else run.speed_m_s, why_not=why,
                                     mode=take))
    continuous_stretches = {r.stretch for r in runs}
    keep = np.flatnonzero([int(k) not in continuous_stretches for k in stretch])
    all_s, all_stretch, all_r, all_R = s, stretch, r_S, R_SC
    s, stretch, r_S, R_SC = s[keep], stretch[keep], r_S[keep], R_SC[keep]
    # each station: the plan with the frame standing there, the brush on the hull
    flown = scenario.with_updates("ship", carriage=None)
    n_y = float(cleaning.hull_normal[1])
    lo, hi = cleaning.band_N
    maps, stand_off, force, in_band = [], np.zeros((s.size, 2)), np.zeros((s.size, 2)), np.zeros(s.size)
    touches = np.zeros(s.size, dtype=bool)  # the hull within the tolerance somewhere under the brush
    planned = s.size + len(runs)
    for k in range(s.size):
        pose = np.degrees(euler_from_matrix(R_SC[k]))
        sc = flown.with_updates("ship", frame_origin_m=r_S[k].tolist(), frame_orientation_deg=pose.tolist())
        p = plan(sc)
        F = normal_force(p, sc)
        b = brush_positions(p.pose, cleaning.brush_offset_m)[:, [0, 2]]
        pts = r_S[k] + b[:, :1] * R_SC[k][:, 0] + b[:, 1:] * R_SC[k][:, 2]
        n_S = n_y * R_SC[k][:, 1]
        t, N = surface_hits(f, sign, pts, n_S)
        if not np.isfinite(t).all():
            raise ScenarioError(f"the rail leaves the hull: at s = {s[k]:.4g} m the brush's path meets no side of "
                                "the surface", key="ship.carriage.rail_m")
        F_hull = F * (N @ n_S)
        contact = (np.abs(t) <= tol) & (F_hull >= lo - 1e-9 * max(hi, 1.0)) & (F_hull <= hi + 1e-9 * max(hi, 1.0))
        stand_off[k] = t.min(), t.max()
        touches[k] = bool((np.abs(t) <= tol).any())
        force[k] = F_hull.min(), F_hull.max()
        in_band[k] = 100.0 * contact.mean()
        maps.append(coverage_map(panel, holes, b, contact, width_m=cleaning.brush_diameter_m))
        if progress is not None:
            progress((k + 1) / planned)
    # each run: the plan with the carriage moving, the brush's contact on the hull taken into the
    # run's first C (the panel on the ship) for its raster
    run_touch = []
    for j, run in enumerate(runs):
        sc = run_scenario(scenario, *run.s_m, dwell_s=scenario.trajectory.start_time_s + run.start_s,
                          speed_m_s=run.speed_m_s)
        p = plan(sc)
        hull = run_on_hull(run, sc, p.t, p.pose, normal_force(p, sc))
        maps.append(hull.coverage_map(cleaning.brush_diameter_m))
        t, F_hull = hull.stand_off_m, hull.force_N
        run_touch.append(bool((np.abs(t) <= tol).any()))
        runs[j] = replace(run, stand_off_m=(float(t.min()), float(t.max())),
                          force_N=(float(F_hull.min()), float(F_hull.max())),
                          in_band_pct=100.0 * float(hull.contact.mean()))
        if progress is not None:
            progress((s.size + j + 1) / planned)
    if not touches.any() and not any(run_touch):
        k = int(np.argmin(np.abs(stand_off).min(axis=1))) if s.size else 0
        best, at = ((np.abs(stand_off[k]).min(), s[k]) if s.size else
                    (min(min(abs(v) for v in r.stand_off_m) for r in runs), runs[0].s_m[0]))
        raise ScenarioError(f"the rail does not follow the hull: at every station the hull stands off the frame's "
                            f"plane under the brush by more than stand_off_tolerance_m ({tol:g} m); at best "
                            f"{best:.3g} m, at s = {at:.4g} m", key="ship.carriage.rail_m")
    # the band's stretches along the ship no rail station's panel reaches: by crane
    reach = []
    for k in np.unique(all_stretch):
        xs = corners_S[all_stretch == k][..., 0]
        reach.append((max(float(xs.min()), X0), min(float(xs.max()), X1)))
    reach.sort()
    gaps, at = [], X0
    for a, b in reach + [(X1, X1)]:
        if a - at >= MIN_PATCH_M:
            gaps.append((at, a))
        at = max(at, b)
    crane, crane_s, stretches = [], [], []
    if gaps:
        crane_figures = None if relocation is None else relocation.crane
        a, b = gaps[0]
        if crane_figures is None:
            raise ScenarioError(f"missing: the rail does not reach the band's stations {a:.4g} to {b:.4g} m "
                                f"({_why(a, b, X0, X1)}); give [cleaning.surface.relocation.crane] to place the "
                                "frame there", key="cleaning.surface.relocation.crane")
        try:
            relocation.check_lift(scenario.robot.mass_kg)
        except ValueError as exc:
            raise ScenarioError(str(exc), key="cleaning.surface.relocation.crane.capacity_kg") from None
    cache: dict = {}
    pieces = []  # (x start, kind, items): the visits in order along the ship
    for k in np.unique(all_stretch):
        x_first = float(corners_S[all_stretch == k][..., 0].min())
        if int(k) in continuous_stretches:
            j = [r.stretch for r in runs].index(int(k))
            pieces.append((x_first, "run", np.array([s.size + j])))
        else:
            pieces.append((x_first, "rail", np.flatnonzero(stretch == k)))
    for a, b in gaps:
        try:
            placed, _ = tile_surface(f, (a, b), (Z0, Z1), width_m=width, height_m=height, tolerance_m=tol,
                                     max_patches=MAX_SURFACE_PATCHES)
        except ScenarioError as exc:
            raise ScenarioError(exc.detail, key="cleaning.surface") from None
        placed = [placed[i] for i in visit_order(placed, "crane")]
        first = len(crane)
        crane += placed
        times = [_panel_times(cleaning, *p.extent_m, cache, 3)[0] for p in placed]
        crane_s += times
        pieces.append((a, "crane", np.arange(first, len(crane))))
        stretches.append((float(sum(times)) / 3600.0, len(placed)))
    pieces.sort(key=lambda piece: piece[0])
    if all_r.shape[0] > 1 and all_r[-1, 0] < all_r[0, 0]:  # a rail laid from the bow aft: the visits that way
        pieces.reverse()
        pieces = [(x, kind, items if kind == "rail" else items[::-1]) for x, kind, items in pieces]
    centre_C = panel.mean(axis=0)
    visits, move_in, by_crane, where = [], [], [], []
    for _, kind, items in pieces:
        for i in items:
            if kind == "run":
                run = runs[int(i) - s.size]
                here = run.origin_S + run.axes_S[:, 0] * centre_C[0] + run.axes_S[:, 2] * centre_C[1]
                visits.append(int(i))
                if not where:
                    move_in.append(0.0), by_crane.append(False)
                else:
                    move_in.append(float(crane_move_s(np.linalg.norm(here - where[-1]), relocation.crane)))
                    by_crane.append(True)
                where.append(run.end_S)  # it leaves from the last station
                continue
            if kind == "rail":
                here = r_S[i] + R_SC[i][:, 0] * centre_C[0] + R_SC[i][:, 2] * centre_C[1]
                visits.append(int(i))
            else:
                here = np.asarray(crane[i].centre_S, dtype=float) * np.array([1.0, sign, 1.0])  # the side's
                visits.append(-1 - int(i))
            if not where:
                move_in.append(0.0), by_crane.append(False)
            elif kind == "rail" and 0 <= visits[-2] < s.size and stretch[visits[-2]] == stretch[i]:
                move = scurve_move(s[i] - s[visits[-2]], carriage.speed_max_m_s, carriage.accel_max_m_s2,
                                   carriage.jerk_max_m_s3)
                move_in.append(move.duration_s + settle), by_crane.append(False)
            else:
                move_in.append(float(crane_move_s(np.linalg.norm(here - where[-1]), relocation.crane)))
                by_crane.append(True)
            where.append(here)
    visits, move_in, by_crane = np.array(visits, dtype=int), np.array(move_in), np.array(by_crane, dtype=bool)
    done = []
    for (hours, count), (a, b) in zip(stretches, gaps):  # each stretch's moves: in, within, back to the rail
        j = np.flatnonzero(visits < 0)
        mine = [v for v in j if a <= crane[-1 - visits[v]].x_range[0] < b]
        if mine and max(mine) + 1 < visits.size and visits[max(mine) + 1] >= 0:
            mine.append(max(mine) + 1)
        done.append(CraneStretch(x_m=(float(a), float(b)), why=_why(a, b, X0, X1), placements=count,
                                 cleaning_hours=hours, crane_moves=int(by_crane[mine].sum()),
                                 hours=hours + float(move_in[mine].sum()) / 3600.0))
    stretches = done
    origins = np.concatenate([r_S, np.array([r.origin_S for r in runs]).reshape(-1, 3)])
    axes = np.concatenate([R_SC, np.array([r.axes_S for r in runs]).reshape(-1, 3, 3)])
    cov = strip_coverage(f, sign, (X0, X1), (Z0, Z1), origins, axes, maps, width_m=cleaning.brush_diameter_m,
                         excluded=gaps, resolution_m=resolution_m)
    horizon = scenario.time.duration_s - scenario.trajectory.start_time_s
    partial = (s.size and horizon < path.duration_s * (1.0 - 1e-9)) or any(
        horizon < r.duration_s * (1.0 - 1e-9) for r in runs)
    return RailStrip(s_m=s, origin_S=r_S, axes_S=R_SC, clean_s=float(path.duration_s), stand_off_m=stand_off,
                     force_N=force, in_band_pct=in_band, coverage=cov, crane=crane, crane_s=np.array(crane_s, float),
                     stretches=stretches, visits=visits, move_in_s=move_in, by_crane=by_crane,
                     surface=f"{label}, {surface.side} side, stations {X0:g} to {X1:g} m, heights {Z0:g} to {Z1:g} m",
                     band_m=((float(X0), float(X1)), (float(Z0), float(Z1))), tolerance_m=tol, side_sign=sign,
                     partial=bool(partial), sharp=sharp, runs=tuple(runs), choices=tuple(choices), mode=mode)


def _why(a: float, b: float, x0: float, x1: float) -> str:
    """Why a crane cleans the band's stretch a to b: beyond the rail's ends or across a bend."""
    if a <= x0 + 1e-9:
        return "aft of the rail's reach"
    if b >= x1 - 1e-9:
        return "forward of the rail's reach"
    return "across a bend of the rail sharper than min_radius_m"
