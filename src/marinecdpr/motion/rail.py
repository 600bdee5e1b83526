"""A rail along the ship and the carriage's jerk-limited motion on it (issue 39, item 1).

The rail is a polyline in the ship frame S whose inner corners are rounded by circular
arcs of one radius, each tangent to its two segments and lying in their plane. It is
parametrised by its arc length ``s`` (m, from the first point); :meth:`Rail.at` gives the
position, the unit tangent and its two arc-length derivatives, and the heading of the
tangent's horizontal part with its derivatives, exactly (closed forms on each straight
piece and arc).

The tangent is continuous along the rail, but its derivative (the curvature vector
``dt``) jumps where a straight piece meets an arc (from 0 to ``|dt| = 1/R`` and back):
a line-and-arc path has piecewise-constant curvature. So do ``ddt``, ``dheading`` and
``ddheading``. At a join, :meth:`Rail.at` returns the values of the piece that starts
there (the one-sided limit from above); at the rail's end, those of the last piece.

The carriage moves from station to station with rest-to-rest double-S (7-phase,
jerk-limited) moves, Biagiotti & Melchiorri, *Trajectory planning for automatic machines
and robots* (Springer 2008), sec. 3.4, and rests at each station for a dwell:
:func:`scurve_move`, :func:`carriage_profile`, :func:`profile_schedule`.

Every bad input is refused with a :class:`RailError` (a
:class:`~marinecdpr.errors.ScenarioError`, hence a ``ValueError``) whose message is one
line naming the offending entry (array entries counted from 1, like the cables).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numba import njit

from marinecdpr.errors import ScenarioError
from marinecdpr.motion.checks import check_finite, check_positive

__all__ = [
    "RailError",
    "RailPoints",
    "Rail",
    "check_rail",
    "check_stations",
    "Move",
    "scurve_move",
    "carriage_profile",
    "profile_schedule",
]

_MIN_SPACING_M = 1e-9  # two consecutive points closer than this are refused
_COLLINEAR_SIN = 1e-12  # |sin(turn)| below this (and the turn forward) is a straight joint, no arc
_UTURN_RAD = 1e-6  # a turn within this of 180 deg is a U-turn (refused)
_MIN_HORIZONTAL = 1e-6  # the tangent's horizontal part below this: heading undefined (refused)
_S_TOL_M = 1e-9  # arc lengths / stations this far outside [0, length] are clipped, not refused


class RailError(ScenarioError):
    """A rail, a station on it or a carriage's limits are malformed or impossible."""


# --- validation helpers ----------------------------------------------------------------------


def _finite(value, name: str) -> float:
    return check_finite(value, name, error=RailError)


def _positive(value, name: str) -> float:
    return check_positive(value, name, error=RailError)


def _vector(values, name: str) -> np.ndarray:
    """A finite 1-D float array (a scalar becomes shape (1,))."""
    try:
        a = np.array(values, dtype=float)
    except (TypeError, ValueError):
        raise RailError("must be numbers", key=name) from None
    if a.ndim > 1:
        raise RailError(f"must be one-dimensional, shape (n,), got shape {a.shape}", key=name)
    a = np.atleast_1d(a)
    bad = np.flatnonzero(~np.isfinite(a))
    if bad.size:
        raise RailError(f"must be finite, got {float(a[bad[0]])!r}", key=f"{name}[{bad[0] + 1}]")
    return a


def _listed(values: np.ndarray, idx: np.ndarray, limit: int = 3) -> str:
    """``[i]=v`` for the first few offending entries (counted from 1), and how many more."""
    items = ", ".join(f"[{i + 1}]={float(values[i])!r}" for i in idx[:limit])
    more = f" and {idx.size - limit} more" if idx.size > limit else ""
    return items + more


def _on_rail(values: np.ndarray, length: float, what: str, key: str) -> np.ndarray:
    """``values`` (arc lengths, m) clipped to [0, length], those within _S_TOL_M outside it
    taken as its ends; any further out refused in one line naming them."""
    out = np.flatnonzero((values < -_S_TOL_M) | (values > length + _S_TOL_M))
    if out.size:
        raise RailError(f"{what} outside the rail's [0, {length:.6g}] m: {_listed(values, out)}", key=key)
    return np.clip(values, 0.0, length)


# --- the rail ---------------------------------------------------------------------------------


@dataclass(frozen=True)
class RailPoints:
    """The rail's geometry at arc lengths ``s`` (every array's leading axis is ``n``).

    Attributes
    ----------
    r : ndarray, shape (n, 3)
        Position on the rail, in S, m.
    t : ndarray, shape (n, 3)
        ``dr/ds``, the unit tangent, in S.
    dt : ndarray, shape (n, 3)
        ``d2r/ds2``, the curvature vector, in S, 1/m (0 on a straight piece, ``1/R``
        towards the arc's centre on an arc; it jumps at the joins).
    ddt : ndarray, shape (n, 3)
        ``d3r/ds3``, in S, 1/m^2 (``-t/R^2`` on an arc).
    heading : ndarray, shape (n,)
        ``psi = atan2(t_y, t_x)``, rad: the direction of the tangent's horizontal part,
        from S's x axis towards its y axis, unwrapped continuous along ``s`` (its value at
        the rail's start is in (-pi, pi]).
    dheading : ndarray, shape (n,)
        ``dpsi/ds``, rad/m.
    ddheading : ndarray, shape (n,)
        ``d2psi/ds2``, rad/m^2. (The three are None where :meth:`Rail.at` is asked without
        the heading.)
    """

    r: np.ndarray
    t: np.ndarray
    dt: np.ndarray
    ddt: np.ndarray
    heading: np.ndarray
    dheading: np.ndarray
    ddheading: np.ndarray


@dataclass(frozen=True)
class Rail:
    """A polyline rail in S with its inner corners rounded by circular arcs.

    Build it with :func:`check_rail` (constructing it directly checks the same things).

    Attributes
    ----------
    points_S : ndarray, shape (n_points, 3)
        The polyline's vertices in S, m (a read-only copy).
    corner_radius_m : float
        Radius of the arc that rounds each inner corner, m: tangent to both segments at
        ``R tan(theta/2)`` from the corner (``theta`` the turn there), in their plane.
        Collinear middle points get no arc.
    """

    points_S: np.ndarray
    corner_radius_m: float
    # the pieces (straight or arc) in order along s: start arc length (m), start point (m),
    # tangent at the start, unit normal towards the arc's centre (0 on straight pieces),
    # curvature 1/R (0 on straight pieces), heading at the start (rad, unwrapped)
    _pieces: tuple = field(init=False, repr=False, compare=False)
    _length: float = field(init=False, repr=False, compare=False)
    _corners: int = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        points, radius = _checked_rail_input(self.points_S, self.corner_radius_m)
        pieces, length, corners = _build_pieces(points, radius)
        object.__setattr__(self, "points_S", points)
        object.__setattr__(self, "corner_radius_m", radius)
        object.__setattr__(self, "_pieces", pieces)
        object.__setattr__(self, "_length", length)
        object.__setattr__(self, "_corners", corners)

    @property
    def length_m(self) -> float:
        """Total arc length of the rounded path, m."""
        return self._length

    @property
    def least_radius_m(self) -> float:
        """The least radius of curvature along the rail, m: ``corner_radius_m`` if it has a
        corner (a non-collinear inner point), ``inf`` for a straight rail."""
        return self.corner_radius_m if self._corners else float("inf")

    @property
    def bends(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """The arcs along the rail: where each starts and ends (arc lengths, m) and the
        tangent's heading there (rad, unwrapped as :meth:`at` gives it); each shape (n_arcs,)."""
        s0, _, _, _, kappa, psi0 = self._pieces
        ends = np.append(s0[1:], self._length)
        psi_end = np.append(psi0[1:], psi0[-1])
        arc = kappa > 0.0
        return s0[arc], ends[arc], psi0[arc], psi_end[arc]

    def at(self, s, heading: bool = True) -> RailPoints:
        """The rail's geometry at arc lengths ``s``.

        Parameters
        ----------
        s : array_like, shape (n,)
            Arc lengths from the first point, m, in ``[0, length_m]`` (values within 1e-9 m
            outside are clipped; others are refused with :class:`RailError` naming them).
        heading : bool
            False leaves out the heading and its derivatives (None), which a carriage's
            motion on the rail does not take.

        Returns
        -------
        RailPoints
            Position, tangent and its derivatives in S, heading and its derivatives, each
            with leading axis ``n``. At a join between a straight piece and an arc the
            piece starting there is used (``dt``, ``ddt`` and the heading's derivatives
            jump there).
        """
        s = _on_rail(_vector(s, "s"), self._length, "arc lengths", "s")
        s0, a0, u, nrm, kappa, psi0 = self._pieces
        k = np.empty(s.size, dtype=np.int64)
        r, t, dt, ddt = (np.empty((s.size, 3)) for _ in range(4))
        _rail_series(s, s0, kappa, a0, u, nrm, k, r, t, dt, ddt)
        if not heading:
            return RailPoints(r=r, t=t, dt=dt, ddt=ddt, heading=None, dheading=None, ddheading=None)
        # heading: exact on each piece, continued from the piece's unwrapped start value
        raw = np.arctan2(t[:, 1], t[:, 0])
        psi = psi0[k] + (raw - psi0[k] + np.pi) % (2.0 * np.pi) - np.pi
        q = t[:, 0] ** 2 + t[:, 1] ** 2
        num = t[:, 0] * dt[:, 1] - t[:, 1] * dt[:, 0]
        dnum = t[:, 0] * ddt[:, 1] - t[:, 1] * ddt[:, 0]
        dq = 2.0 * (t[:, 0] * dt[:, 0] + t[:, 1] * dt[:, 1])
        dpsi = num / q
        ddpsi = (dnum * q - num * dq) / (q * q)
        return RailPoints(r=r, t=t, dt=dt, ddt=ddt, heading=psi, dheading=dpsi, ddheading=ddpsi)


@njit(cache=True)
def _rail_series(s, s0, kappa, a0, u, nrm, k, r, t, dt, ddt):
    """:func:`_rail_point` at each arc length s[j] (on the rail): its piece k[j] and r, t, dt,
    ddt (n, 3) (the pieces' s0, kappa, a0, u, nrm as :meth:`Rail.at` reads them)."""
    p, last, c, sn, h = 0, np.nan, 0.0, 0.0, 0.0
    for j in range(s.size):
        p, last, c, sn, h = _rail_point(s0, kappa, a0, u, nrm, s[j], p, last, c, sn, h, r, t, dt, ddt, j)
        k[j] = p


@njit(cache=True, inline="always")
def _rail_point(s0, kappa, a0, u, nrm, x, p, last, c, sn, h, r, t, dt, ddt, j):
    """The rail at one arc length x (on it), written in row j of r, t, dt, ddt (n, 3); returns
    its piece, the one starting at or before x (as ``searchsorted(s0, x, "right") - 1``, the
    first for x = 0), looked for only where the piece p of the point before is not it, and
    the last arc's angle and trigonometry (below).

    On an arc of curvature kap, sigma = x - s0 along it, the point is sin(kap sigma)/kap along
    the start's tangent and (1 - cos(kap sigma))/kap = 2 sin^2(kap sigma / 2)/kap across
    towards the centre; on a straight piece sigma along and 0 across. last, c, sn, h: the last
    arc point's kap sigma, its cosine, sine and sine of half, taken again only for a new angle
    (a carriage at rest takes them once; NaN for none)."""
    if not ((p == 0 or s0[p] <= x) and (p + 1 == s0.size or x < s0[p + 1])):
        p = min(max(np.searchsorted(s0, x, side="right") - 1, 0), s0.size - 1)
    sigma = x - s0[p]
    kj = kappa[p]
    if kj > 0.0:
        phi = sigma * kj
        if phi != last:
            last, c, sn, h = phi, np.cos(phi), np.sin(phi), np.sin(0.5 * phi)
        cj, sj = c, sn
        along, across = sj / kj, 2.0 * (h * h) / kj
    else:
        along, across = sigma, 0.0
        cj, sj = 1.0, 0.0
    for i in range(3):
        ui, ni = u[p, i], nrm[p, i]
        r[j, i] = a0[p, i] + along * ui + across * ni
        ti = cj * ui + sj * ni
        t[j, i] = ti
        dt[j, i] = kj * (cj * ni - sj * ui)
        ddt[j, i] = -kj * kj * ti
    return p, last, c, sn, h


def check_rail(points_S, corner_radius_m) -> Rail:
    """Check a rail's polyline and corner radius; return the :class:`Rail`.

    Parameters
    ----------
    points_S : array_like, shape (n_points, 3)
        The polyline's vertices in S, m; at least 2, finite, consecutive points at least
        1e-9 m apart.
    corner_radius_m : float
        Radius of the arcs rounding the inner corners, m: > 0 if the rail has a corner
        (>= 0 otherwise).

    Returns
    -------
    Rail
        The rail, its points a read-only float copy.

    Raises
    ------
    RailError
        One line naming the entry: fewer than 2 points, a wrong shape, non-finite values,
        two consecutive points closer than 1e-9 m, a U-turn (a turn within 1e-6 rad of
        180 deg), a non-positive radius with a corner, a rounding that does not fit (the
        tangent lengths ``R tan(theta/2)`` of the corners at a segment's two ends exceed
        its length; the message names the corner and the largest radius that fits the
        whole rail), or a rail whose tangent turns vertical (heading undefined).
    """
    return Rail(points_S, corner_radius_m)


def _checked_rail_input(points_S, corner_radius_m) -> tuple[np.ndarray, float]:
    try:
        p = np.array(points_S, dtype=float)
    except (TypeError, ValueError):
        raise RailError("must be numbers, shape (n_points, 3)", key="points_S") from None
    if p.ndim != 2 or p.shape[1] != 3:
        raise RailError(f"must have shape (n_points, 3), got shape {p.shape}", key="points_S")
    if p.shape[0] < 2:
        raise RailError(f"needs at least 2 points, got {p.shape[0]}", key="points_S")
    bad = np.argwhere(~np.isfinite(p))
    if bad.size:
        i, j = bad[0]
        raise RailError(f"must be finite, got {float(p[i, j])!r}", key=f"points_S[{i + 1}]")
    radius = _finite(corner_radius_m, "corner_radius_m")
    if radius < 0.0:
        raise RailError(f"must be >= 0, got {radius!r}", key="corner_radius_m")
    gaps = np.linalg.norm(np.diff(p, axis=0), axis=1)
    close = np.flatnonzero(gaps < _MIN_SPACING_M)
    if close.size:
        i = close[0]
        raise RailError(
            f"points {i + 1} and {i + 2} are {gaps[i]!r} m apart, closer than {_MIN_SPACING_M} m",
            key=f"points_S[{i + 2}]",
        )
    p.flags.writeable = False
    return p, radius


def _build_pieces(p: np.ndarray, radius: float):
    """The rail's pieces (straight, arc, straight, ...), its length and corner count."""
    d = np.diff(p, axis=0)
    seg = np.linalg.norm(d, axis=1)
    u = d / seg[:, None]
    n_seg = seg.size
    # the turn at each inner point and its arc's tangent length
    theta = np.zeros(n_seg + 1)
    normal = np.zeros((n_seg + 1, 3))
    for i in range(1, n_seg):
        a, b = u[i - 1], u[i]
        cross = np.linalg.norm(np.cross(a, b))
        dot = float(a @ b)
        if cross <= _COLLINEAR_SIN and dot > 0.0:
            continue  # collinear: no arc
        th = float(np.arctan2(cross, dot))
        if th > np.pi - _UTURN_RAD:
            raise RailError(
                f"the rail turns back on itself at point {i + 1} (a U-turn of {np.degrees(th):.6g} deg)",
                key=f"points_S[{i + 1}]",
            )
        theta[i] = th
        normal[i] = (b - dot * a) / cross
    corners = int(np.count_nonzero(theta))
    if corners and radius <= 0.0:
        first = int(np.flatnonzero(theta)[0])
        raise RailError(
            f"must be > 0: the rail has a corner at point {first + 1} "
            f"(a turn of {np.degrees(theta[first]):.6g} deg)",
            key="corner_radius_m",
        )
    tan_half = np.tan(0.5 * theta)
    need = tan_half[:-1] + tan_half[1:]  # per segment: the two tangent lengths over R
    with np.errstate(divide="ignore"):
        fits = np.where(need > 0.0, seg / np.where(need > 0.0, need, 1.0), np.inf)
    over = np.flatnonzero(radius * need > seg * (1.0 + 1e-12))
    if over.size:
        i = int(over[0])
        corner = i if tan_half[i] >= tan_half[i + 1] else i + 1
        raise RailError(
            f"the corner at point {corner + 1} cannot be rounded with radius {radius!r} m: the arcs' "
            f"tangent lengths R tan(theta/2) at points {i + 1} and {i + 2} add up to "
            f"{radius * need[i]:.6g} m, more than the segment's {seg[i]:.6g} m; "
            f"the largest radius that fits is {_round_down(float(fits.min()))!r} m",
            key="corner_radius_m",
        )
    tangent = radius * tan_half
    s0, a0, tu, tn, kap = [], [], [], [], []
    s = 0.0
    for i in range(n_seg):
        start = p[i] + tangent[i] * u[i]
        straight = max(0.0, seg[i] - tangent[i] - tangent[i + 1])
        s0.append(s), a0.append(start), tu.append(u[i]), tn.append(np.zeros(3)), kap.append(0.0)
        s += straight
        if i + 1 < n_seg and theta[i + 1] > 0.0:
            s0.append(s), a0.append(p[i + 1] - tangent[i + 1] * u[i])
            tu.append(u[i]), tn.append(normal[i + 1]), kap.append(1.0 / radius)
            s += radius * theta[i + 1]
    s0, a0, tu, tn, kap = (np.array(x, dtype=float) for x in (s0, a0, tu, tn, kap))
    # the tangent's horizontal part along each piece: refuse a rail that turns vertical
    for k in range(s0.size):
        low = _least_horizontal(tu[k], tn[k], kap[k] * _piece_length(k, s0, s))
        if low < _MIN_HORIZONTAL:
            raise RailError(
                f"the rail's tangent turns vertical near s = {s0[k]:.6g} m (its horizontal part "
                f"falls to {low:.3g}); the carriage's heading is undefined there",
                key="points_S",
            )
    # heading at each piece's start, unwrapped along the rail (the tangent is continuous)
    psi0 = np.empty(s0.size)
    psi = float(np.arctan2(tu[0, 1], tu[0, 0]))
    for k in range(s0.size):
        raw = np.arctan2(tu[k, 1], tu[k, 0])
        psi = psi + (raw - psi + np.pi) % (2.0 * np.pi) - np.pi
        psi0[k] = psi
        if kap[k] > 0.0:  # carry the heading across the arc
            phi = kap[k] * _piece_length(k, s0, s)
            end = np.cos(phi) * tu[k] + np.sin(phi) * tn[k]
            psi = _continued(psi, end)
    pieces = (s0, a0, tu, tn, kap, psi0)
    for x in pieces:
        x.flags.writeable = False
    return pieces, float(s), corners


def _round_down(x: float, digits: int = 6) -> float:
    """``x > 0`` rounded down to ``digits`` significant digits (a radius quoted that fits)."""
    scale = 10.0 ** (digits - 1 - int(np.floor(np.log10(x))))
    return float(np.floor(x * scale * (1.0 + 1e-15)) / scale)


def _piece_length(k: int, s0: np.ndarray, total: float) -> float:
    return (s0[k + 1] if k + 1 < s0.size else total) - s0[k]


def _continued(psi: float, end: np.ndarray) -> float:
    """The unwrapped heading of tangent ``end`` at an arc's end from ``psi`` at its start:
    the horizontal tangent turns by less than pi along an arc of turn below pi, so the
    wrapped difference is the turn."""
    raw = np.arctan2(end[1], end[0])
    return psi + (raw - psi + np.pi) % (2.0 * np.pi) - np.pi


def _least_horizontal(u: np.ndarray, n: np.ndarray, phi: float) -> float:
    """Least horizontal norm of ``cos(f) u + sin(f) n`` over ``f`` in ``[0, phi]``."""
    a = u[0] ** 2 + u[1] ** 2
    c = n[0] ** 2 + n[1] ** 2
    b = u[0] * n[0] + u[1] * n[1]
    cands = [0.0, phi]
    f = 0.5 * np.arctan2(2.0 * b, a - c)  # stationary points of the quadratic form
    for g in (f, f + 0.5 * np.pi, f + np.pi, f - 0.5 * np.pi):
        if 0.0 <= g <= phi:
            cands.append(g)
    vals = [a * np.cos(g) ** 2 + 2.0 * b * np.cos(g) * np.sin(g) + c * np.sin(g) ** 2 for g in cands]
    return float(np.sqrt(max(min(vals), 0.0)))


def check_stations(rail: Rail, stations_m) -> np.ndarray:
    """Check the carriage's stations against a rail.

    Parameters
    ----------
    rail : Rail
        The rail.
    stations_m : array_like, shape (m,)
        Arc lengths along the rail where the carriage stops, m, finite, in
        ``[0, rail.length_m]`` (values within 1e-9 m outside are clipped).

    Returns
    -------
    ndarray, shape (m,)
        The stations, m.

    Raises
    ------
    RailError
        One line naming the stations outside the rail (counted from 1) and its length.
    """
    return _on_rail(_vector(stations_m, "stations_m"), rail.length_m, "stations", "stations_m")


# --- the carriage's motion --------------------------------------------------------------------


@dataclass(frozen=True)
class Move:
    """A rest-to-rest jerk-limited (double-S, 7-phase) move.

    Attributes
    ----------
    distance_m : float
        Signed distance, m (negative: a move backwards).
    duration_s : float
        Its duration, s (the sum of the phases).
    phases_s : tuple of 7 float
        The phases' durations, s: ``(Tj, Ta - 2Tj, Tj, Tv, Tj, Ta - 2Tj, Tj)`` with
        Biagiotti & Melchiorri's ``Tj`` (jerk), ``Ta`` (acceleration; equal to the
        deceleration ``Td`` rest to rest) and ``Tv`` (constant speed).
    jerk : float
        The jerk's magnitude, m/s^3 (``j_max``); its sign per phase is
        ``+, 0, -, 0, -, 0, +`` times the sign of ``distance_m``.
    """

    distance_m: float
    duration_s: float
    phases_s: tuple
    jerk: float


_JERK_SIGNS = np.array([1.0, 0.0, -1.0, 0.0, -1.0, 0.0, 1.0])


def scurve_move(distance_m, v_max, a_max, j_max) -> Move:
    """The time-optimal rest-to-rest double-S move over a distance (Biagiotti & Melchiorri
    (2008), sec. 3.4 with ``v0 = v1 = 0``): jerk +J, 0, -J to the peak speed, a cruise, and
    -J, 0, +J to rest.

    The peak speed is ``v_max`` where the distance allows (to reach a speed vp from rest and
    stop again takes ``vp (vp / a_max + a_max / j_max)`` where vp reaches ``a_max^2 / j_max``,
    the speed gained by ramping the acceleration to ``a_max`` and back, else
    ``2 vp sqrt(vp / j_max)``); otherwise the largest that stops within the distance:
    ``(h sqrt(j_max) / 2)^(2/3)`` without reaching ``a_max``, else the root of the first
    form. The one implementation of the move: the cleaning path's time law
    (:mod:`marinecdpr.motion.coverage`) takes it too.

    Parameters
    ----------
    distance_m : float
        Signed distance, m; 0 gives a move of duration 0; a negative one the same phases
        with the signs flipped.
    v_max, a_max, j_max : float
        Limits on the speed (m/s), acceleration (m/s^2) and jerk (m/s^3), > 0.

    Returns
    -------
    Move
        The move's phases and jerk.

    Raises
    ------
    RailError
        One line: a non-finite distance or a limit not finite and > 0.
    """
    h_signed = _finite(distance_m, "distance_m")
    v_max = _positive(v_max, "v_max")
    a_max = _positive(a_max, "a_max")
    j_max = _positive(j_max, "j_max")
    length = abs(h_signed)
    if length == 0.0:
        return Move(distance_m=h_signed, duration_s=0.0, phases_s=(0.0,) * 7, jerk=j_max)
    v_sat = a_max * a_max / j_max  # speed gained by ramping the acceleration to a_max and back

    def accel_and_stop(vp):  # distance to reach vp from rest and stop again
        return vp * (vp / a_max + a_max / j_max) if vp >= v_sat else 2.0 * vp * np.sqrt(vp / j_max)

    if accel_and_stop(v_max) <= length:
        vp = v_max
    else:
        vp = (0.5 * length * np.sqrt(j_max)) ** (2.0 / 3.0)  # a_max not reached
        if vp > v_sat:
            vp = 0.5 * a_max * (np.sqrt((a_max / j_max) ** 2 + 4.0 * length / a_max) - a_max / j_max)
    if vp >= v_sat:
        tj, ta = a_max / j_max, vp / a_max - a_max / j_max
    else:
        tj, ta = float(np.sqrt(vp / j_max)), 0.0
    tc = max(0.0, length / vp - (2.0 * tj + ta))
    phases = tuple(float(x) for x in (tj, ta, tj, tc, tj, ta, tj))
    return Move(distance_m=h_signed, duration_s=float(sum(phases)), phases_s=phases, jerk=j_max)


def _dwells(dwell_s, n: int) -> np.ndarray:
    if np.ndim(dwell_s) == 0:
        d = np.full(n, _finite(dwell_s, "dwell_s"))
    else:
        d = _vector(dwell_s, "dwell_s")
        if d.size != n:
            raise RailError(f"must be a number or one per station ({n}), got {d.size}", key="dwell_s")
    neg = np.flatnonzero(d < 0.0)
    if neg.size:
        key = "dwell_s" if np.ndim(dwell_s) == 0 else f"dwell_s[{neg[0] + 1}]"
        raise RailError(f"must be >= 0, got {float(d[neg[0]])!r}", key=key)
    return d


def _phase_table(stations_m, dwell_s, v_max, a_max, j_max):
    """The profile's constant-jerk phases: start time (s), and s (m), speed (m/s),
    acceleration (m/s^2) at the start, jerk (m/s^3); the last phase is the final rest.
    Also the schedule (arrival, departure) per station, shape (m, 2), s."""
    st = _vector(stations_m, "stations_m")
    if st.size == 0:
        raise RailError("needs at least 1 station, got none", key="stations_m")
    dwell = _dwells(dwell_s, st.size)
    moves = [scurve_move(st[i + 1] - st[i], v_max, a_max, j_max) for i in range(st.size - 1)]
    start, s0, v0, a0, jerk = [], [], [], [], []
    schedule = np.empty((st.size, 2))
    time = 0.0
    for i in range(st.size):
        schedule[i, 0] = time
        start.append(time), s0.append(st[i]), v0.append(0.0), a0.append(0.0), jerk.append(0.0)
        time += dwell[i]
        schedule[i, 1] = time
        if i + 1 == st.size:
            break
        m = moves[i]
        sign = np.sign(m.distance_m)
        s, v, a = float(st[i]), 0.0, 0.0
        for dt, jsign in zip(m.phases_s, _JERK_SIGNS):
            if dt == 0.0:
                continue
            jj = sign * jsign * m.jerk + 0.0  # no -0.0 on the coasting phases
            start.append(time), s0.append(s), v0.append(v), a0.append(a), jerk.append(jj)
            s += dt * (v + dt * (0.5 * a + dt * jj / 6.0))
            v += dt * (a + 0.5 * dt * jj)
            a += dt * jj
            time += dt
    table = tuple(np.array(x, dtype=float) for x in (start, s0, v0, a0, jerk))
    return table, schedule


def carriage_profile(stations_m, dwell_s, v_max, a_max, j_max, t):
    """The carriage's arc length along the rail and its derivatives at times ``t``.

    The carriage rests at ``stations_m[0]`` for ``dwell[0]``, moves to ``stations_m[1]``
    (a :func:`scurve_move`), rests there for ``dwell[1]``, and so on; after its last dwell
    it rests at the last station for ever. Each phase is evaluated exactly (a cubic in time)
    from its start state; during a dwell ``s`` is the station exactly.

    Parameters
    ----------
    stations_m : array_like, shape (m,)
        Arc lengths of the stations in visiting order, m (any order, repeats allowed; check
        them against the rail with :func:`check_stations`).
    dwell_s : float or array_like, shape (m,)
        Rest at each station, s, >= 0: one figure for every station or one per station.
    v_max, a_max, j_max : float
        The carriage's limits on speed (m/s), acceleration (m/s^2), jerk (m/s^3), > 0.
    t : array_like, shape (n,)
        Times from the profile's start, s, finite, >= 0 (any order).

    Returns
    -------
    s, s_dot, s_ddot, s_dddot : ndarray, shape (n,)
        Arc length (m), speed (m/s), acceleration (m/s^2) and jerk (m/s^3) along the rail.
        At a phase switch the phase that starts there is used (the jerk jumps there).

    Raises
    ------
    RailError
        One line: non-finite values, a limit not > 0, a negative dwell, a wrong count of
        dwells, or times before 0.
    """
    (start, s0, v0, a0, jerk), _ = _phase_table(stations_m, dwell_s, v_max, a_max, j_max)
    t = _vector(t, "t")
    early = np.flatnonzero(t < 0.0)
    if early.size:
        raise RailError(f"times before 0: {_listed(t, early)}", key="t")
    s, v, a, j = (np.empty(t.size) for _ in range(4))
    _profile_series(start, s0, v0, a0, jerk, t, s, v, a, j)
    return s, v, a, j


@njit(cache=True)
def _profile_series(start, s0, v0, a0, jerk, t, s, v, a, j):
    """:func:`_profile_point` at each time t[n] >= 0: s, v, a, j (n,)."""
    k = 0
    for n in range(t.size):
        k, s[n], v[n], a[n], j[n] = _profile_point(start, s0, v0, a0, jerk, t[n], k)


@njit(cache=True, inline="always")
def _profile_point(start, s0, v0, a0, jerk, time, k):
    """:func:`carriage_profile` at one time >= 0: its phase (the one starting at or before it,
    looked for only where the phase k of the time before is not it) evaluated tau = time -
    start into it (a cubic in tau); returns the phase, s, v, a, j."""
    if not (start[k] <= time and (k + 1 == start.size or time < start[k + 1])):
        k = np.searchsorted(start, time, side="right") - 1
    tau = time - start[k]
    jk = jerk[k]
    return (k, s0[k] + tau * (v0[k] + tau * (0.5 * a0[k] + tau * jk / 6.0)), v0[k] + tau * (a0[k] + 0.5 * tau * jk),
            a0[k] + tau * jk, jk)


def profile_schedule(stations_m, dwell_s, v_max, a_max, j_max) -> np.ndarray:
    """When the carriage arrives at and leaves each station.

    Parameters
    ----------
    stations_m, dwell_s, v_max, a_max, j_max
        As for :func:`carriage_profile`.

    Returns
    -------
    ndarray, shape (m, 2)
        Row ``i``: ``[arrival, departure]`` at station ``i``, s. The dwell at station ``i``
        starts at ``[i, 0]``; the move to station ``i + 1`` starts at ``[i, 1]`` and ends at
        ``[i + 1, 0]``. ``[0, 0]`` is 0; after ``[m - 1, 1]`` the carriage rests for ever.
    """
    _, schedule = _phase_table(stations_m, dwell_s, v_max, a_max, j_max)
    return schedule
