"""Measured ship motion: a 6-DOF record read from CSV, smoothed and differentiated.

A motion reference unit (or a seakeeping code) gives the ship's coordinates
sampled in time. :func:`read_motion_csv` reads them, checks them, converts them to
the package's convention (``eta = (x, y, z, roll, pitch, yaw)`` of S in O, m and
rad, ``R_SO = Rz(yaw) Ry(pitch) Rx(roll)``, z up; see ``docs/conventions.md``) and
returns a :class:`RecordedMotion`, whose :meth:`RecordedMotion.evaluate` gives
eta, eta' and eta'' at any time inside the record as a
:class:`~marinecdpr.motion.ship.ShipMotion`.

CSV format
----------
One header row with exactly the columns (any order)::

    time_s,surge_m,sway_m,heave_m,roll,pitch,yaw

then one row per sample: time (s, strictly increasing, uniformly sampled to 1 %),
position of the ship's reference point (m) and the three Euler angles in the unit
given by ``angles`` (``"deg"`` or ``"rad"``). At least 10 samples.

The file is UTF-8 text, with or without a byte-order mark, lines ending in LF,
CRLF or CR, as spreadsheets write it (rows of empty fields are skipped like blank
lines); at most 256 MiB, lines of at most 10 000 and fields of at most 100
characters (:data:`marinecdpr.textfiles.MAX_CSV_BYTES` and the limits beside it). Values
must be finite, with |time| <= 1e10 s, a sampling interval >= 0.1 ms, positions
within 1 km (:data:`MAX_TRANSLATION_M`), |roll|, |pitch| <= 90 deg and
|yaw| <= 36 000 deg.

Two axis conventions (``z_axis``):

``"up"`` (the package's)
    x forward, y to port, z up. Roll is right-handed about +x (positive: starboard
    side down), pitch about +y (positive: bow down), yaw about +z (positive: bow
    turns to port).
``"down"`` (the common NED-style ship convention)
    x forward, y to starboard, z down (heave positive downwards). Roll, pitch and
    yaw are right-handed about those axes (positive: starboard down, bow up, bow
    to starboard), with the same order R = Rz(yaw) Ry(pitch) Rx(roll).

The two differ by the half-turn about x, D = diag(1, -1, -1) (D = D^T = D^-1),
applied to both the earth-fixed and the ship-fixed axes: vectors convert as
v_up = D v_down, so R_up = D R_down D. Since D Rx(a) D = Rx(a),
D Ry(a) D = Ry(-a) and D Rz(a) D = Rz(-a),

    R_up = Rz(-yaw_d) Ry(-pitch_d) Rx(roll_d),

that is (:func:`flip_z_axis`, its own inverse)::

    (x, y, z, roll, pitch, yaw)_up = (x, -y, -z, roll, -pitch, -yaw)_down.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, NamedTuple, NoReturn

import numpy as np
from scipy.interpolate import BSpline, make_smoothing_spline

from marinecdpr.errors import ScenarioError
from marinecdpr.motion.ship import ShipMotion, ship_motion
from marinecdpr.textfiles import MAX_FIELD_CHARS, atomic_path, long_field, read_csv_records

__all__ = [
    "MOTION_CSV_COLUMNS",
    "DEFAULT_SMOOTHING_S",
    "RecordedMotion",
    "read_motion_csv",
    "write_motion_csv",
    "flip_z_axis",
]

MOTION_CSV_COLUMNS = ("time_s", "surge_m", "sway_m", "heave_m", "roll", "pitch", "yaw")
"""The columns of a motion CSV file, in the order :func:`write_motion_csv` writes them."""

DEFAULT_SMOOTHING_S = 0.25
"""Default smoothing time scale tau, s: components slower than a 4 s period lose
less than 2.5 % of their amplitude (1 % at 5 s, 0.1 % at 9 s)."""

_MIN_SAMPLES = 10
_MAX_JITTER = 0.01  # relative deviation of a sampling interval from the median

# Limits of what read_motion_csv accepts: far beyond a ship's motion, they refuse
# garbage (1e300, a unit off by 1000) without second-guessing a real record.
MAX_TRANSLATION_M = 1000.0
"""Largest |surge|, |sway| or |heave| in a motion file, m: motion about a nearby point."""
MAX_YAW_DEG = 36000.0
"""Largest |yaw| in a motion file, deg: 100 turns of an unwrapped heading."""
MAX_TIME_S = 1.0e10
"""Largest |time| in a motion file, s (317 years: Unix times pass)."""
MIN_INTERVAL_S = 1.0e-4
"""Shortest sampling interval, s (10 kHz; a motion reference unit samples at most a few 100 Hz)."""
_FLIP = np.array([1.0, -1.0, -1.0, 1.0, -1.0, -1.0])  # z-down <-> z-up, see flip_z_axis
_ANGLE_UNITS = ("deg", "rad")
_Z_AXES = ("up", "down")


def flip_z_axis(eta: np.ndarray) -> np.ndarray:
    """Convert ship coordinates between the z-down and z-up conventions.

    ``(x, y, z, roll, pitch, yaw) -> (x, -y, -z, roll, -pitch, -yaw)``, which is
    R -> D R D with D = diag(1, -1, -1) (see the module docstring). The map is its
    own inverse, so it converts either way.

    Parameters
    ----------
    eta : ndarray, shape (..., 6)
        ``(x, y, z, roll, pitch, yaw)`` in one convention, m and rad (any angle
        unit works: the map only changes signs).

    Returns
    -------
    ndarray, shape (..., 6)
        The same motion in the other convention.
    """
    eta = np.asarray(eta, dtype=float)
    if eta.shape[-1:] != (6,):
        raise ValueError(f"eta must have shape (..., 6); got {eta.shape}")
    return eta * _FLIP


@dataclass(frozen=True, eq=False)
class RecordedMotion:
    """A sampled 6-DOF ship motion and its smoothing-spline derivatives.

    Velocities and accelerations come from a cubic smoothing spline per DOF
    (:func:`scipy.interpolate.make_smoothing_spline`), differentiated
    analytically. The spline f minimises

        sum_i (eta_i - f(t_i))^2 + lam * integral f''(t)^2 dt,
        lam = smoothing_s^4 / dt,

    with dt the sampling interval. Far from the ends of the record this is the
    linear filter with frequency response H(w) = 1 / (1 + (w tau)^4),
    tau = ``smoothing_s``, applied alike to eta, eta' and eta'': motion with period
    2 pi tau is halved, slower motion passes almost unchanged (relative loss
    ~(w tau)^4), faster motion and sample noise are removed. White noise of
    standard deviation sigma per sample leaves errors of standard deviation about
    0.51 sigma sqrt(dt/tau), 0.30 sigma sqrt(dt/tau^3) and 0.30 sigma sqrt(dt/tau^5)
    in eta, eta' and eta''. ``smoothing_s = 0`` interpolates the samples exactly.

    The spline is natural (f'' = 0 at both ends), so near the first and last
    sample the acceleration is pulled towards zero: it can be off by tens of
    percent within 4 tau of an end and by a few percent up to about 6 tau (the
    velocity by a few percent within 4 tau). Trim the record's ends if they
    matter. On a 20 Hz record of ship motion (periods 7-11 s) with noise of
    1e-4 m or rad, the default tau = 0.25 s gives eta, eta' and eta'' within
    0.4 %, 0.6 % and 2 % of each DOF's amplitude more than 8 tau from the ends.

    Attributes
    ----------
    t : ndarray, shape (n,)
        Sample times, s, strictly increasing, uniformly spaced, n >= 10.
    eta : ndarray, shape (n, 6)
        ``(x, y, z, roll, pitch, yaw)`` of S in O at ``t`` in the package's
        convention (z up), m and rad; yaw continuous (unwrapped).
    smoothing_s : float
        The smoothing time scale tau, s (>= 0).
    """

    t: np.ndarray
    eta: np.ndarray
    smoothing_s: float = DEFAULT_SMOOTHING_S
    _spline: BSpline = field(init=False, repr=False)

    def __post_init__(self) -> None:
        t = np.array(self.t, dtype=float)  # own read-only copies
        eta = np.array(self.eta, dtype=float)
        if t.ndim != 1 or eta.shape != (t.size, 6):
            raise ValueError(f"t must have shape (n,) and eta (n, 6); got {t.shape} and {eta.shape}")
        if t.size < _MIN_SAMPLES:
            raise ValueError(f"a recorded motion needs at least {_MIN_SAMPLES} samples; got {t.size}")
        if not (np.all(np.isfinite(t)) and np.all(np.isfinite(eta))):
            raise ValueError("t and eta must be finite")
        if np.any(np.diff(t) <= 0.0):
            raise ValueError("t must be strictly increasing")
        tau = float(self.smoothing_s)
        if not (np.isfinite(tau) and tau >= 0.0):
            raise ValueError(f"smoothing_s must be a finite time >= 0 s; got {self.smoothing_s}")
        t.flags.writeable = False
        eta.flags.writeable = False
        dt = (t[-1] - t[0]) / (t.size - 1)
        spline = make_smoothing_spline(t, eta, lam=tau**4 / dt)
        object.__setattr__(self, "t", t)
        object.__setattr__(self, "eta", eta)
        object.__setattr__(self, "smoothing_s", tau)
        object.__setattr__(self, "_spline", spline)

    @property
    def sample_interval_s(self) -> float:
        """The mean sampling interval, s."""
        return float((self.t[-1] - self.t[0]) / (self.t.size - 1))

    @property
    def time_range_s(self) -> tuple[float, float]:
        """``(t[0], t[-1])``: the times :meth:`evaluate` accepts, s."""
        return float(self.t[0]), float(self.t[-1])

    def evaluate(self, t: np.ndarray) -> ShipMotion:
        """The ship's smoothed motion and its derivatives at times inside the record.

        Parameters
        ----------
        t : array_like, shape (n_steps,) or scalar
            Times, s, within ``[self.t[0], self.t[-1]]`` (an overshoot of 1e-6
            sample intervals, e.g. from rounding, is clipped to the record).

        Returns
        -------
        ShipMotion
            eta (smoothed; m, rad), eta', eta'' (m/s, rad/s; m/s^2, rad/s^2) in the
            package's convention, each shape (n_steps, 6), with R_SO and the
            ship's angular velocity and acceleration in S.

        Raises
        ------
        ValueError
            If a time is not finite or lies outside the record.
        """
        t = np.atleast_1d(np.asarray(t, dtype=float))
        if t.ndim != 1:
            raise ValueError(f"t must be a scalar or have shape (n_steps,); got {t.shape}")
        t0, t1 = self.time_range_s
        eps = 1e-6 * self.sample_interval_s
        outside = ~((t >= t0 - eps) & (t <= t1 + eps))  # also catches NaN
        if np.any(outside):
            k = int(np.argmax(outside))
            raise ValueError(
                f"recorded ship motion is defined for {t0:g} s <= t <= {t1:g} s; "
                f"got t[{k}] = {t[k]:g} s"
            )
        t = np.clip(t, t0, t1)
        s = self._spline
        return ship_motion(s(t), s(t, nu=1), s(t, nu=2))


def read_motion_csv(
    path: str | Path,
    *,
    z_axis: str = "up",
    angles: str = "deg",
    smoothing_s: float = DEFAULT_SMOOTHING_S,
) -> RecordedMotion:
    """Read a recorded ship motion from a CSV file (format in the module docstring).

    Parameters
    ----------
    path : str or Path
        The CSV file.
    z_axis : {"up", "down"}
        The file's axes: ``"up"`` the package's (x forward, y port, z up),
        ``"down"`` NED-style (x forward, y starboard, z down); converted with
        :func:`flip_z_axis`.
    angles : {"deg", "rad"}
        Unit of the roll, pitch and yaw columns.
    smoothing_s : float
        Smoothing time scale tau, s, of the derivatives (see
        :class:`RecordedMotion`); default 0.25 s, 0 interpolates.

    Returns
    -------
    RecordedMotion
        Times as in the file (s); eta in the package's convention (m, rad), yaw
        unwrapped (jumps of about 360 deg, e.g. 359 -> 1, removed).

    Raises
    ------
    ScenarioError
        With ``source`` the file, naming the line and column: not a regular
        file, too large, not UTF-8 text (NUL bytes, control characters), a line
        or field too long, a wrong header (missing, unexpected or repeated
        columns), a row with the wrong number of fields, a non-number, NaN or
        inf, time not strictly increasing, fewer than 10 samples, a sampling
        interval more than 1 % from the median or below 0.1 ms, a position
        beyond 1 km, |roll| or |pitch| beyond 90 deg (a wrong angle unit or
        wrapped angles) or |yaw| beyond 100 turns. The message never quotes the
        file's text (the path may name any file), only the expected columns and
        numbers parsed from the file.
    ValueError
        For an unknown ``z_axis`` or ``angles``.
    """
    _check_choice("z_axis", z_axis, _Z_AXES)
    _check_choice("angles", angles, _ANGLE_UNITS)
    src = str(path)

    def fail(message: str) -> NoReturn:
        raise ScenarioError(message, source=src)

    row_lines, rows = _nonblank_rows(read_csv_records(path, fail, _WHAT, one_per_line=True), fail)
    order = _column_order(rows[0], row_lines[0], fail)
    samples = _parse_samples(rows[1:], row_lines[1:], order, fail)
    _check_times(samples, fail)
    _check_sampling(samples, fail)
    _check_positions(samples, fail)
    _check_roll_pitch(samples, angles, fail)
    _check_yaw(samples, angles, fail)
    return RecordedMotion(samples.values[:, 0], _to_eta(samples.values, angles, z_axis), smoothing_s)


# Steps of read_motion_csv, in the order it takes them. Messages name the file's line
# numbers (counted from 1, blank lines included) and the expected columns, never the file's text.

_Fail = Callable[[str], NoReturn]
_EXPECTED = ",".join(MOTION_CSV_COLUMNS)
_WHAT = f"a ship-motion CSV file ({_EXPECTED})"


class _Samples(NamedTuple):
    """The data rows of a motion file: ``lines`` (n,) their line numbers, ``values`` (n, 7) the numbers.

    ``values`` has the columns of :data:`MOTION_CSV_COLUMNS` in that order, in the file's
    units and axes (s, m, and ``angles``).
    """

    lines: np.ndarray
    values: np.ndarray


def _nonblank_rows(records: list[list[str]], fail: _Fail) -> tuple[list[int], list[list[str]]]:
    """The line numbers and records of the non-blank rows; refuses an empty file or an overlong field."""
    # blank lines (and spreadsheets' rows of empty cells ",,,") are skipped
    row_lines = [k for k, rec in enumerate(records, 1) if "".join(rec).strip()]
    rows = [records[k - 1] for k in row_lines]
    if not rows:
        fail(f"the file is empty; expected a header row {_EXPECTED}")
    if (long := long_field(rows)) is not None:
        k, j = long
        fail(f"line {row_lines[k]}, field {j + 1}: over {MAX_FIELD_CHARS} characters; expected {_WHAT}")
    return row_lines, rows


def _column_order(row: list[str], line: int, fail: _Fail) -> list[int]:
    """The header row's index of each of :data:`MOTION_CSV_COLUMNS`; refuses any other set of columns."""
    header = [h.strip() for h in row]
    missing = [c for c in MOTION_CSV_COLUMNS if c not in header]
    if len(missing) == len(MOTION_CSV_COLUMNS):
        n = len(header)
        fail(f"line {line}: expected a header row with the columns {_EXPECTED} "
             f"(got {n} other column{'s' if n != 1 else ''})")
    unexpected = [j + 1 for j, h in enumerate(header) if h not in MOTION_CSV_COLUMNS]
    repeated = sorted({h for h in header if h in MOTION_CSV_COLUMNS and header.count(h) > 1})
    if missing or unexpected or repeated:
        problems = _header_problems(missing, unexpected, repeated)
        fail(f"line {line}: wrong columns ({'; '.join(problems)}); expected exactly {_EXPECTED}")
    return [header.index(c) for c in MOTION_CSV_COLUMNS]


def _header_problems(missing: list[str], unexpected: list[int], repeated: list[str]) -> list[str]:
    """One phrase per kind of header fault, naming expected columns and the positions (from 1) of others."""
    problems = []
    if missing:
        problems.append(f"missing {', '.join(repr(c) for c in missing)}")
    if unexpected:
        shown = ", ".join(map(str, unexpected[:5])) + (f", ... ({len(unexpected)} in all)"
                                                       if len(unexpected) > 5 else "")
        problems.append(f"unexpected column{'s' if len(unexpected) > 1 else ''} {shown}")
    if repeated:
        problems.append(f"repeated {', '.join(repr(c) for c in repeated)}")
    return problems


def _parse_samples(data: list[list[str]], data_lines: list[int], order: list[int], fail: _Fail) -> _Samples:
    """The data rows as finite numbers; refuses none, wrong field counts, non-numbers or under 10 rows."""
    lines = np.array(data_lines, dtype=int)
    if not data:
        fail("no data rows after the header")
    n_fields = np.array([len(r) for r in data])
    bad = np.flatnonzero(n_fields != len(MOTION_CSV_COLUMNS))
    if bad.size:
        k = bad[0]
        fail(f"line {lines[k]} has {n_fields[k]} fields; expected {len(MOTION_CSV_COLUMNS)} ({_EXPECTED})")
    cells = np.char.strip(np.array(data, dtype=str)[:, order])
    values = _to_float(cells, lines, fail)
    nonfinite = ~np.isfinite(values)
    if nonfinite.any():
        k, j = np.argwhere(nonfinite)[0]
        fail(f"line {lines[k]}, column {MOTION_CSV_COLUMNS[j]}: '{values[k, j]:g}' is not a finite number")
    n = values.shape[0]
    if n < _MIN_SAMPLES:
        fail(f"only {n} samples; a recorded motion needs at least {_MIN_SAMPLES}")
    return _Samples(lines, values)


def _check_times(samples: _Samples, fail: _Fail) -> None:
    """Refuse a time (s) beyond :data:`MAX_TIME_S` or times that do not strictly increase."""
    t, lines = samples.values[:, 0], samples.lines
    over = np.flatnonzero(np.abs(t) > MAX_TIME_S)
    if over.size:
        k = over[0]
        fail(f"line {lines[k]}, column time_s: {t[k]:g} s is beyond {MAX_TIME_S:g} s; expected times in seconds")
    bad = np.flatnonzero(np.diff(t) <= 0.0)
    if bad.size:
        k = bad[0] + 1
        fail(
            f"line {lines[k]}, column time_s: time {t[k]:g} s does not increase "
            f"(previous sample at {t[k - 1]:g} s, line {lines[k - 1]})"
        )


def _check_sampling(samples: _Samples, fail: _Fail) -> None:
    """Refuse a sampling interval over 1 % from the median interval, or a median below :data:`MIN_INTERVAL_S`."""
    t, lines = samples.values[:, 0], samples.lines
    dt = np.diff(t)
    dt_med = float(np.median(dt))
    bad = np.flatnonzero(np.abs(dt - dt_med) > _MAX_JITTER * dt_med)
    if bad.size:
        k = bad[0] + 1
        fail(
            f"line {lines[k]}, column time_s: non-uniform sampling, interval {dt[k - 1]:g} s "
            f"from line {lines[k - 1]} against a median of {dt_med:g} s (more than "
            f"{_MAX_JITTER:.0%} off); resample the record to a uniform rate"
        )
    if dt_med < MIN_INTERVAL_S:
        fail(f"line {lines[1]}, column time_s: sampling interval {dt_med:g} s is below {MIN_INTERVAL_S:g} s "
             f"(faster than {1.0 / MIN_INTERVAL_S:g} Hz); expected times in seconds")


def _check_positions(samples: _Samples, fail: _Fail) -> None:
    """Refuse a surge, sway or heave (m) beyond :data:`MAX_TRANSLATION_M`: another unit or absolute coordinates."""
    values, lines = samples.values, samples.lines
    for j, name in ((1, "surge_m"), (2, "sway_m"), (3, "heave_m")):
        over = np.flatnonzero(np.abs(values[:, j]) > MAX_TRANSLATION_M)
        if over.size:
            k = over[0]
            fail(f"line {lines[k]}, column {name}: {values[k, j]:g} m is beyond {MAX_TRANSLATION_M:g} m; "
                 f"expected the motion in metres about a nearby point (not mm, not absolute coordinates)")


def _check_roll_pitch(samples: _Samples, angles: str, fail: _Fail) -> None:
    """Refuse a |roll| or |pitch| over 90 deg (in unit ``angles``): a wrong unit or wrapped angles."""
    values, lines = samples.values, samples.lines
    limit = 90.0 if angles == "deg" else np.pi / 2
    for j, name in ((4, "roll"), (5, "pitch")):
        over = np.flatnonzero(np.abs(values[:, j]) > limit)
        if over.size:
            k = over[0]
            hint = (
                "is the unit deg? (read with angles='deg')"
                if angles == "rad"
                else "is the column in another unit, or wrapped to [0, 360)?"
            )
            fail(
                f"line {lines[k]}, column {name}: {name} exceeds "
                f"{'90 deg' if angles == 'deg' else 'pi/2 rad'} ({values[k, j]:g} {angles}): {hint}"
            )


def _check_yaw(samples: _Samples, angles: str, fail: _Fail) -> None:
    """Refuse a |yaw| (in unit ``angles``) over :data:`MAX_YAW_DEG`, 100 turns."""
    values, lines = samples.values, samples.lines
    yaw_limit = MAX_YAW_DEG if angles == "deg" else np.radians(MAX_YAW_DEG)
    over = np.flatnonzero(np.abs(values[:, 6]) > yaw_limit)
    if over.size:
        k = over[0]
        fail(f"line {lines[k]}, column yaw: {values[k, 6]:g} {angles} is beyond {yaw_limit:g} {angles} "
             f"(100 turns); expected the ship's heading in {angles}")


def _to_eta(values: np.ndarray, angles: str, z_axis: str) -> np.ndarray:
    """eta, shape (n, 6), in the package's convention (m, rad, z up, yaw unwrapped) from values (n, 7)."""
    eta = values[:, 1:].copy()
    if angles == "deg":
        eta[:, 3:] = np.radians(eta[:, 3:])
    eta[:, 5] = np.unwrap(eta[:, 5])
    if z_axis == "down":
        eta = flip_z_axis(eta)
    return eta


def write_motion_csv(
    path: str | Path,
    t: np.ndarray,
    eta: np.ndarray,
    *,
    z_axis: str = "up",
    angles: str = "deg",
) -> None:
    """Write a ship motion as a CSV file that :func:`read_motion_csv` reads back.

    Numbers are written with 17 significant digits, so a round trip is exact up
    to the degree/radian conversion (~1e-16 relative).

    Parameters
    ----------
    path : str or Path
        The file to write (replaced whole: written to a temporary file beside it and
        renamed, so it is never left half-written).
    t : array_like, shape (n,)
        Times, s.
    eta : array_like, shape (n, 6)
        ``(x, y, z, roll, pitch, yaw)`` of S in O in the package's convention
        (z up), m and rad.
    z_axis : {"up", "down"}
        The convention to write (see the module docstring).
    angles : {"deg", "rad"}
        Unit of the angle columns.
    """
    _check_choice("z_axis", z_axis, _Z_AXES)
    _check_choice("angles", angles, _ANGLE_UNITS)
    t = np.asarray(t, dtype=float)
    eta = np.asarray(eta, dtype=float)
    if t.ndim != 1 or eta.shape != (t.size, 6):
        raise ValueError(f"t must have shape (n,) and eta (n, 6); got {t.shape} and {eta.shape}")
    out = flip_z_axis(eta) if z_axis == "down" else eta.copy()
    if angles == "deg":
        out[:, 3:] = np.degrees(out[:, 3:])
    with atomic_path(path) as tmp:  # complete or not at all
        np.savetxt(
            tmp,
            np.column_stack([t, out]),
            fmt="%.17g",
            delimiter=",",
            header=",".join(MOTION_CSV_COLUMNS),
            comments="",
        )


def _check_choice(name: str, value: str, choices: tuple[str, ...]) -> None:
    if value not in choices:
        raise ValueError(f"{name} must be one of {', '.join(map(repr, choices))}; got {value!r}")


def _to_float(cells: np.ndarray, lines: np.ndarray, fail) -> np.ndarray:
    """Parse a (n, 7) array of strings; on failure name the first bad cell."""
    try:
        return cells.astype(float)
    except ValueError:
        pass
    ok = np.vectorize(_is_float, otypes=[bool])(cells)  # error path only: find the culprit
    bad = np.argwhere(~ok)
    if bad.size == 0:  # pragma: no cover - numpy and float() disagree
        fail("a field is not a number")
    k, j = bad[0]
    shown = "not a number" if cells[k, j] else "an empty field is not a number"  # the text is not echoed
    fail(f"line {lines[k]}, column {MOTION_CSV_COLUMNS[j]}: {shown}")


def _is_float(cell: str) -> bool:
    try:
        float(cell)
    except ValueError:
        return False
    return True
