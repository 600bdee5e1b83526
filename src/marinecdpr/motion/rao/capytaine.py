"""Response amplitude operators (RAOs) of the ship's six DOFs in regular waves.

Conventions (fixed throughout the package):

* **DOF order** ``(surge, sway, heave, roll, pitch, yaw)`` in the ship frame S
  (x forward, y to port, z up; roll, pitch and yaw right-handed about +x, +y, +z).
  Translations in m per m of wave amplitude, rotations in **rad** per m of wave
  amplitude (files may use deg/m; see :func:`read_rao_csv`).
* **Time convention**: a regular wave of amplitude ``a`` and phase ``eps`` has the
  elevation ``zeta(t) = Re(a exp(i (omega t + eps)))`` at S's origin, and the ship
  responds with ``eta_j(t) = Re(RAO_j a exp(i (omega t + eps)))``. So ``|RAO_j|`` is
  the amplitude ratio and ``arg(RAO_j)`` the phase **lead** of the motion over the
  wave elevation at S's origin.
* **Wave heading** ``beta`` (deg): the direction the waves travel towards, from the
  ship's +x axis, counter-clockwise about +z. 0 = following seas, 90 = waves
  travelling towards +y (coming from starboard), 180 = head seas. In [0, 360).

So a long wave (omega -> 0) makes the ship follow the sea surface: heave -> 1,
pitch -> i k cos(beta) and roll -> -i k sin(beta) (k = omega^2 / g), because
the surface ``zeta = a exp(i (omega t - k (x cos beta + y sin beta)))`` rises
towards the bow (pitch down is positive) and towards port (roll up to port is
positive) a quarter period after it rises at the origin.

Sources of RAOs: a CSV table (:func:`read_rao_csv`, :func:`write_rao_csv`), a
NetCDF file from the BEM code Capytaine (:func:`read_capytaine`) and a built-in
box-hull approximation (:func:`box_hull_rao`).
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from os import PathLike
from typing import Any, Callable, NamedTuple, NoReturn, Sequence

import numpy as np

from marinecdpr.errors import ScenarioError
from marinecdpr.textfiles import MAX_FIELD_CHARS, atomic_path, check_file, long_field, read_lines, strip_control

__all__ = [
    "DOFS",
    "RAO",
    "read_rao_csv",
    "write_rao_csv",
    "read_capytaine",
    "box_hull_rao",
    "ROLL_GYRADIUS_OVER_BEAM",
]

DOFS = ("surge", "sway", "heave", "roll", "pitch", "yaw")
"""The DOF order of :attr:`RAO.values` (first axis)."""

_ROTATIONS = np.array([False, False, False, True, True, True])
_CSV_COLUMNS = ("omega_rad_s", "heading_deg", "dof", "amplitude", "phase_deg")

# Limits of what the RAO readers accept: far beyond any ship, they refuse garbage
# (1e300, a unit off by 1000) without second-guessing a real table.
OMEGA_MAX_RAD_S = 100.0
"""Largest wave frequency in an RAO table, rad/s: a 6 mm wave (period 0.063 s)."""
TRANSLATION_RAO_MAX_M_M = 100.0
"""Largest surge, sway or heave RAO, m/m (real ones are about 1; a table in mm/m is refused)."""
ROTATION_RAO_MAX_DEG_M = 1000.0
"""Largest roll, pitch or yaw RAO, deg/m (17.5 rad/m). A lightly damped small hull's linear
roll peak is a few hundred deg/m; a potential-flow table without viscous roll damping can
exceed this at resonance, and then needs that damping."""
PHASE_MAX_DEG = 1.0e6
"""Largest |phase| in an RAO CSV table, deg (unwrapped phases pass)."""
MAX_NETCDF_BYTES = 2**30
"""Largest Capytaine NetCDF file read, bytes (1 GiB; an RAO dataset is a few MB, and
the whole file is loaded into memory)."""



# ---------------------------------------------------------------------------------------
# The RAO table
# ---------------------------------------------------------------------------------------


@dataclass(frozen=True)
class RAO:
    """A ship's RAOs tabulated over wave frequency and heading.

    Attributes
    ----------
    omega : ndarray, shape (n_omega,)
        Wave angular frequencies, rad/s, strictly increasing, > 0.
    heading_deg : ndarray, shape (n_heading,)
        Wave headings beta (direction the waves travel towards, from S's +x,
        counter-clockwise), deg, strictly increasing, in [0, 360).
    values : ndarray of complex, shape (6, n_heading, n_omega)
        RAO of ``(surge, sway, heave, roll, pitch, yaw)`` in S: m/m for
        translations, rad/m for rotations; the argument is the phase lead over
        the wave elevation at S's origin (module docstring).

    The arrays are stored as read-only copies (float64 and complex128).
    """

    omega: np.ndarray
    heading_deg: np.ndarray
    values: np.ndarray

    def __post_init__(self) -> None:
        omega = np.array(self.omega, dtype=float)
        heading = np.array(self.heading_deg, dtype=float)
        values = np.array(self.values, dtype=complex)
        if omega.ndim != 1 or omega.size == 0:
            raise ValueError(f"omega must have shape (n_omega,) with n_omega >= 1; got {omega.shape}")
        if heading.ndim != 1 or heading.size == 0:
            raise ValueError(f"heading_deg must have shape (n_heading,) with n_heading >= 1; "
                             f"got {heading.shape}")
        if values.shape != (6, heading.size, omega.size):
            raise ValueError(f"values must have shape (6, n_heading, n_omega) = "
                             f"(6, {heading.size}, {omega.size}); got {values.shape}")
        if not (np.all(np.isfinite(omega)) and np.all(omega > 0.0)):
            raise ValueError("omega must be finite and > 0 rad/s")
        if np.any(np.diff(omega) <= 0.0):
            raise ValueError("omega must be strictly increasing")
        if not (np.all(np.isfinite(heading)) and np.all(heading >= 0.0) and np.all(heading < 360.0)):
            raise ValueError("heading_deg must be in [0, 360)")
        if np.any(np.diff(heading) <= 0.0):
            raise ValueError("heading_deg must be strictly increasing")
        if not np.all(np.isfinite(values)):
            raise ValueError("values must be finite")
        for a in (omega, heading, values):
            a.flags.writeable = False
        object.__setattr__(self, "omega", omega)
        object.__setattr__(self, "heading_deg", heading)
        object.__setattr__(self, "values", values)

    def at(self, omega: np.ndarray, heading_deg: float | np.ndarray) -> np.ndarray:
        """The RAOs at given wave frequencies and heading, interpolated.

        Linear interpolation of the complex values: in omega between tabulated
        frequencies (the value at the smallest tabulated omega below it, zero
        above the largest), and in heading with wrap-around over 360 deg (one
        tabulated heading is used for all headings).

        Parameters
        ----------
        omega : array_like, shape (n,) or scalar
            Wave angular frequencies, rad/s.
        heading_deg : float or array_like broadcastable to omega's shape
            Wave heading(s) beta, deg (any real value; taken modulo 360).

        Returns
        -------
        ndarray of complex, shape (6, n)
            RAO of ``(surge, sway, heave, roll, pitch, yaw)``: m/m and rad/m.
        """
        w = np.atleast_1d(np.asarray(omega, dtype=float))
        if w.ndim != 1:
            raise ValueError(f"omega must be a scalar or have shape (n,); got {w.shape}")
        h = np.broadcast_to(np.asarray(heading_deg, dtype=float), w.shape)
        # omega: bracketing indices i0, i1 and weight t (clipped: constant below, zero above)
        tab = self.omega
        if tab.size == 1:
            i0 = np.zeros(w.size, dtype=np.intp)
            i1 = i0
            t = np.zeros(w.size)
        else:
            i0 = np.clip(np.searchsorted(tab, w, side="right") - 1, 0, tab.size - 2)
            i1 = i0 + 1
            t = np.clip((w - tab[i0]) / (tab[i1] - tab[i0]), 0.0, 1.0)
        above = w > tab[-1]
        # heading: bracketing indices j0, j1 over the circle and weight s
        hd = self.heading_deg
        n_h = hd.size
        if n_h == 1:
            j0 = np.zeros(w.size, dtype=np.intp)
            j1 = j0
            s = np.zeros(w.size)
        else:
            hm = np.mod(h, 360.0)
            ext = np.concatenate(([hd[-1] - 360.0], hd, [hd[0] + 360.0]))
            k = np.clip(np.searchsorted(ext, hm, side="right") - 1, 0, n_h)
            s = (hm - ext[k]) / (ext[k + 1] - ext[k])
            j0 = np.mod(k - 1, n_h)  # ext[k] is heading k - 1 (mod n_h)
            j1 = np.mod(k, n_h)
        v = self.values
        lo = v[:, j0, i0] * (1.0 - t) + v[:, j0, i1] * t
        hi = v[:, j1, i0] * (1.0 - t) + v[:, j1, i1] * t
        out = lo * (1.0 - s) + hi * s
        out[:, above] = 0.0
        return out


def _rao_out_of_range(omega: np.ndarray, heading: np.ndarray, values: np.ndarray) -> str | None:
    """What is beyond the limits in an RAO table (rad/m for rotations), or None."""
    if (i := np.flatnonzero(omega > OMEGA_MAX_RAD_S)).size:
        return f"omega {omega[i[0]]:g} rad/s is above {OMEGA_MAX_RAD_S:g} rad/s; expected wave frequencies in rad/s"
    amp = np.abs(values)
    limit = np.where(_ROTATIONS, math.radians(ROTATION_RAO_MAX_DEG_M), TRANSLATION_RAO_MAX_M_M)
    over = amp > limit[:, None, None]
    if over.any():
        d, h, w = np.argwhere(over)[0]
        unit = "rad/m" if _ROTATIONS[d] else "m/m"
        return (f"{DOFS[d]} RAO {amp[d, h, w]:g} {unit} at omega {omega[w]:g} rad/s, heading "
                f"{heading[h]:g} deg is above {limit[d]:.3g} {unit}; expected a ship's response")
    return None


# ---------------------------------------------------------------------------------------
# CSV
# ---------------------------------------------------------------------------------------


def read_rao_csv(path: str | PathLike) -> RAO:
    """Read RAOs from a long-format CSV table.

    Format: a header row naming the columns ``omega_rad_s, heading_deg, dof,
    amplitude, phase_deg`` (any order; further columns are ignored), then one
    row per (omega, heading, DOF):

    ============  =========================================================
    omega_rad_s   wave angular frequency, rad/s, > 0
    heading_deg   wave heading beta (travel direction from +x, CCW), deg,
                  in [0, 360)
    dof           one of ``surge, sway, heave, roll, pitch, yaw``
                  (case-insensitive)
    amplitude     |RAO|, >= 0: **m/m** for surge, sway, heave; **deg/m**
                  for roll, pitch, yaw (converted to rad/m)
    phase_deg     arg(RAO), deg: the phase lead of the motion over the wave
                  elevation at S's origin (module docstring)
    ============  =========================================================

    Every (omega, heading) pair must have all six DOFs, and the pairs must form
    a full grid (every omega at every heading). Row order is free. Blank lines
    and lines whose first field starts with ``#`` are skipped. Equal values are
    compared exactly as parsed, so write the same frequency the same way in
    every row.

    The file is UTF-8 text, with or without a byte-order mark, lines ending in
    LF, CRLF or CR (as spreadsheets write it), at most :data:`MAX_CSV_BYTES`
    bytes, lines of at most :data:`MAX_LINE_CHARS` and fields of at most
    :data:`MAX_FIELD_CHARS` characters. Values must be within omega <=
    :data:`OMEGA_MAX_RAD_S` rad/s, amplitude <= :data:`TRANSLATION_RAO_MAX_M_M`
    m/m or :data:`ROTATION_RAO_MAX_DEG_M` deg/m, |phase| <= :data:`PHASE_MAX_DEG`.

    Parameters
    ----------
    path : str or path-like
        The CSV file.

    Returns
    -------
    RAO

    Raises
    ------
    ScenarioError
        If the file cannot be read or is malformed: not a regular file, too
        large, not UTF-8 text (NUL bytes, control characters), a line or field
        too long, a missing column, a row with the wrong number of fields, an
        unknown DOF name, a field that is not a finite number, an omega <= 0 or
        above the limit, a heading outside [0, 360), a negative or absurdly
        large amplitude, a duplicate row or an incomplete grid. The one-line
        message names the row (the file's line number, the header being row 1)
        and never quotes the file's text.
    """
    src = str(path)

    def fail(message: str) -> NoReturn:
        raise ScenarioError(message, source=src)

    table = _read_csv_table(path, fail)
    _check_field_lengths(table, fail)
    col = _column_indices(table, fail)
    _check_row_lengths(table, fail)
    rows = _parse_rows(table, col, fail)
    _check_row_ranges(rows, fail)
    _check_row_limits(rows, fail)
    grid = _grid_of(rows)
    _check_duplicates(rows, grid, fail)
    _check_full_grid(rows, grid, fail)
    return RAO(grid.omegas, grid.headings, _grid_values(rows, grid))


# Steps of read_rao_csv, in the order it takes them. Messages name the file's row (line)
# numbers and the expected columns, never the file's text.

_Fail = Callable[[str], NoReturn]
_CSV_EXPECTED = ",".join(_CSV_COLUMNS)
_CSV_WHAT = f"an RAO table in CSV ({_CSV_EXPECTED})"


class _CsvTable(NamedTuple):
    """An RAO CSV file's header (stripped, lower case) and data records, with their row numbers."""

    header: list[str]
    header_row: int
    rows: list[list[str]]
    row_numbers: list[int]


class _RaoRows(NamedTuple):
    """The data rows parsed, each of shape (n_rows,).

    ``lines`` the row numbers, ``omega`` rad/s, ``heading`` deg, ``dof`` the index in
    :data:`DOFS` (-1 if unknown), ``amplitude`` m/m or deg/m, ``phase`` deg.
    """

    lines: np.ndarray
    omega: np.ndarray
    heading: np.ndarray
    dof: np.ndarray
    amplitude: np.ndarray
    phase: np.ndarray


class _Grid(NamedTuple):
    """The (heading, omega) grid of the rows.

    ``omegas`` (n_o,) rad/s and ``headings`` (n_h,) deg are the distinct values, sorted;
    ``io``, ``ih`` and ``key = (ih * n_o + io) * 6 + dof``, shape (n_rows,), place each row.
    """

    omegas: np.ndarray
    headings: np.ndarray
    io: np.ndarray
    ih: np.ndarray
    key: np.ndarray


def _read_csv_table(path: str | PathLike, fail: _Fail) -> _CsvTable:
    """The header and data records, comments (``#``) and blank lines skipped; refuses a file without a header."""
    header: list[str] | None = None
    header_row = 0
    rows: list[list[str]] = []
    row_numbers: list[int] = []
    reader = csv.reader(read_lines(path, fail, _CSV_WHAT, word="row"))
    try:
        for rec in reader:
            first_field = rec[0].strip() if rec else ""
            if first_field.startswith("#") or not (first_field or any(c.strip() for c in rec)):
                continue  # a comment or a blank line
            if header is None:
                header = [c.strip().lower() for c in rec]
                header_row = reader.line_num
            else:
                rows.append(rec)
                row_numbers.append(reader.line_num)
    except csv.Error as exc:
        fail(f"row {reader.line_num}: not readable as CSV ({exc})")
    if header is None:
        fail(f"empty file: expected a header row {_CSV_EXPECTED}")
    return _CsvTable(header=header, header_row=header_row, rows=rows, row_numbers=row_numbers)


def _check_field_lengths(table: _CsvTable, fail: _Fail) -> None:
    """Refuse a field (header included) over :data:`MAX_FIELD_CHARS` characters."""
    if (long := long_field([table.header] + table.rows)) is not None:
        i, j = long
        fail(f"row {table.header_row if i == 0 else table.row_numbers[i - 1]}, field {j + 1}: over "
             f"{MAX_FIELD_CHARS} characters; expected {_CSV_WHAT}")


def _column_indices(table: _CsvTable, fail: _Fail) -> dict[str, int]:
    """The header's index of each column of the format; refuses a missing or repeated one."""
    col: dict[str, int] = {}
    for name in _CSV_COLUMNS:
        if table.header.count(name) != 1:
            what = "lacks" if name not in table.header else "repeats"
            fail(f"row {table.header_row}: the header {what} column {name!r} (expected {_CSV_EXPECTED})")
        col[name] = table.header.index(name)
    return col


def _check_row_lengths(table: _CsvTable, fail: _Fail) -> None:
    """Refuse a table without data rows, or a row whose number of fields differs from the header's."""
    if not table.rows:
        fail(f"row {table.header_row}: no data rows after the header")
    for rec, line in zip(table.rows, table.row_numbers):
        if len(rec) != len(table.header):
            fail(f"row {line}: {len(rec)} fields, but the header has {len(table.header)}")


def _parse_rows(table: _CsvTable, col: dict[str, int], fail: _Fail) -> _RaoRows:
    """The data rows' numbers and DOF indices; refuses a field that is not a finite number."""
    lines = np.asarray(table.row_numbers)
    omega = _numbers(table, col, "omega_rad_s", fail)
    heading = _numbers(table, col, "heading_deg", fail)
    amplitude = _numbers(table, col, "amplitude", fail)
    phase = _numbers(table, col, "phase_deg", fail)
    dof_names = np.char.lower(np.asarray(_column(table, col, "dof"), dtype=str))
    names, inverse = np.unique(dof_names, return_inverse=True)
    known = np.array([DOFS.index(n) if n in DOFS else -1 for n in names.tolist()])
    return _RaoRows(lines=lines, omega=omega, heading=heading, dof=known[inverse.ravel()], amplitude=amplitude,
                    phase=phase)


def _column(table: _CsvTable, col: dict[str, int], name: str) -> list[str]:
    """The stripped fields of column ``name``, one per data row."""
    return [rec[col[name]].strip() for rec in table.rows]


def _numbers(table: _CsvTable, col: dict[str, int], name: str, fail: _Fail) -> np.ndarray:
    """Column ``name`` as floats, shape (n_rows,); refuses a non-number, NaN or inf, naming the first."""
    text = _column(table, col, name)
    try:
        x = np.asarray(text, dtype=float)
    except ValueError:
        x = None
    if x is None or not np.all(np.isfinite(x)):
        for i, s in enumerate(text):  # only on error: find the first bad field
            try:
                v = float(s)
            except ValueError:  # say where, not what: the text is not echoed
                fail(f"row {table.row_numbers[i]}, column {name}: "
                     f"{'not a number' if s else 'an empty field is not a number'}")
            if not math.isfinite(v):
                fail(f"row {table.row_numbers[i]}: {name} '{v:g}' is not a finite number")
    return x


def _first(mask: np.ndarray) -> int | None:
    """The index of the first True in ``mask``, or None."""
    hit = np.flatnonzero(mask)
    return int(hit[0]) if hit.size else None


def _check_row_ranges(rows: _RaoRows, fail: _Fail) -> None:
    """Refuse an unknown DOF, omega <= 0, a heading outside [0, 360) deg or a negative amplitude."""
    lines = rows.lines
    if (i := _first(rows.dof < 0)) is not None:
        fail(f"row {lines[i]}: unknown dof (expected one of {', '.join(DOFS)})")
    if (i := _first(rows.omega <= 0.0)) is not None:
        fail(f"row {lines[i]}: omega_rad_s must be > 0; got {rows.omega[i]:g}")
    if (i := _first((rows.heading < 0.0) | (rows.heading >= 360.0))) is not None:
        fail(f"row {lines[i]}: heading_deg must be in [0, 360); got {rows.heading[i]:g}")
    if (i := _first(rows.amplitude < 0.0)) is not None:
        fail(f"row {lines[i]}: negative amplitude {rows.amplitude[i]:g}")


def _check_row_limits(rows: _RaoRows, fail: _Fail) -> None:
    """Refuse an omega (rad/s), amplitude (m/m, deg/m) or |phase| (deg) beyond the module's limits."""
    lines, omega, amplitude, dof = rows.lines, rows.omega, rows.amplitude, rows.dof
    if (i := _first(omega > OMEGA_MAX_RAD_S)) is not None:
        fail(f"row {lines[i]}: omega_rad_s {omega[i]:g} is above {OMEGA_MAX_RAD_S:g} rad/s; "
             f"expected wave frequencies in rad/s")
    limit = np.where(_ROTATIONS[np.maximum(dof, 0)], ROTATION_RAO_MAX_DEG_M, TRANSLATION_RAO_MAX_M_M)
    if (i := _first(amplitude > limit)) is not None:
        unit = "deg/m" if _ROTATIONS[dof[i]] else "m/m"
        fail(f"row {lines[i]}: {DOFS[dof[i]]} amplitude {amplitude[i]:g} {unit} is above "
             f"{limit[i]:g} {unit}; expected a ship's response per metre of wave amplitude")
    if (i := _first(np.abs(rows.phase) > PHASE_MAX_DEG)) is not None:
        fail(f"row {lines[i]}: phase_deg {rows.phase[i]:g} is beyond +-{PHASE_MAX_DEG:g} deg")


def _grid_of(rows: _RaoRows) -> _Grid:
    """The distinct omegas and headings of the rows, and each row's place in the grid."""
    omegas, io = np.unique(rows.omega, return_inverse=True)
    headings, ih = np.unique(rows.heading, return_inverse=True)
    io, ih = io.ravel(), ih.ravel()
    key = (ih * omegas.size + io) * 6 + rows.dof
    return _Grid(omegas=omegas, headings=headings, io=io, ih=ih, key=key)


def _check_duplicates(rows: _RaoRows, grid: _Grid, fail: _Fail) -> None:
    """Refuse two rows of the same (omega, heading, DOF), naming the later row of the first such pair."""
    order = np.argsort(grid.key, kind="stable")
    same = np.flatnonzero(grid.key[order][1:] == grid.key[order][:-1])
    if same.size:
        later, earlier = order[same + 1], order[same]
        j = int(np.argmin(later))
        i, e = int(later[j]), int(earlier[j])
        fail(f"row {rows.lines[i]}: duplicate of row {rows.lines[e]} (omega {rows.omega[i]:g} rad/s, "
             f"heading {rows.heading[i]:g} deg, dof {DOFS[rows.dof[i]]})")


def _check_full_grid(rows: _RaoRows, grid: _Grid, fail: _Fail) -> None:
    """Refuse an (omega, heading) pair lacking a DOF, or an omega lacking a heading."""
    n_o, n_h = grid.omegas.size, grid.headings.size
    present = np.zeros(n_h * n_o * 6, dtype=bool)
    present[grid.key] = True
    if not present.all():
        m = int(np.flatnonzero(~present)[0])
        pair, d = divmod(m, 6)
        mh, mo = divmod(pair, n_o)
        in_pair = _first((grid.ih == mh) & (grid.io == mo))
        if in_pair is not None:
            fail(f"row {rows.lines[in_pair]}: omega {grid.omegas[mo]:g} rad/s at heading "
                 f"{grid.headings[mh]:g} deg lacks dof {DOFS[d]} "
                 f"(every (omega, heading) pair needs all six DOFs)")
        i = _first(grid.io == mo)
        fail(f"row {rows.lines[i]}: omega {grid.omegas[mo]:g} rad/s has no rows at heading "
             f"{grid.headings[mh]:g} deg (the (omega, heading) pairs must form a full grid)")


def _grid_values(rows: _RaoRows, grid: _Grid) -> np.ndarray:
    """The RAO values, complex shape (6, n_heading, n_omega): m/m and rad/m (rotations from deg/m)."""
    amp = np.where(_ROTATIONS[rows.dof], np.radians(rows.amplitude), rows.amplitude)
    values = np.zeros((6, grid.headings.size, grid.omegas.size), dtype=complex)
    values[rows.dof, grid.ih, grid.io] = amp * np.exp(1j * np.radians(rows.phase))
    return values


def write_rao_csv(rao: RAO, path: str | PathLike, *, comments: Sequence[str] = ()) -> None:
    """Write RAOs as the CSV table :func:`read_rao_csv` reads.

    Rows are ordered by heading, then omega, then DOF; numbers are written with
    the shortest text that reads back to the same float. Rotations are written
    in deg/m, phases in deg in (-180, 180] (0 where the amplitude is 0).

    Parameters
    ----------
    rao : RAO
        The table to write.
    path : str or path-like
        The CSV file (replaced whole: written to a temporary file beside it and renamed,
        so it is never left half-written).
    comments : sequence of str
        Lines written first, each as ``# line`` (read back as comments).

    Raises
    ------
    ValueError
        If the table is beyond what :func:`read_rao_csv` accepts (omega above
        :data:`OMEGA_MAX_RAD_S`, an amplitude above :data:`TRANSLATION_RAO_MAX_M_M`
        or :data:`ROTATION_RAO_MAX_DEG_M`): the file would not read back.
    """
    if (problem := _rao_out_of_range(rao.omega, rao.heading_deg, rao.values)) is not None:
        raise ValueError(f"{problem}: read_rao_csv would refuse the file")
    n_h, n_o = rao.heading_deg.size, rao.omega.size
    ih, io, d = np.meshgrid(np.arange(n_h), np.arange(n_o), np.arange(6), indexing="ij")
    ih, io, d = ih.ravel(), io.ravel(), d.ravel()
    v = rao.values[d, ih, io]
    amp = np.abs(v)
    amp = np.where(_ROTATIONS[d], np.degrees(amp), amp)
    phase = np.where(amp > 0.0, np.degrees(np.angle(v)), 0.0)
    phase = np.where(phase <= -180.0, phase + 360.0, phase) + 0.0  # (-180, 180], no -0.0
    cols = [
        map(repr, rao.omega[io].tolist()),
        map(repr, rao.heading_deg[ih].tolist()),
        (DOFS[k] for k in d.tolist()),
        map(repr, amp.tolist()),
        map(repr, phase.tolist()),
    ]
    body = "\n".join(",".join(r) for r in zip(*cols))
    head = "".join(f"# {strip_control(line)}\n" for line in comments)
    with atomic_path(path) as tmp, open(tmp, "w", newline="", encoding="utf-8") as f:
        f.write(head + ",".join(_CSV_COLUMNS) + "\n" + body + "\n")


# ---------------------------------------------------------------------------------------
# Capytaine
# ---------------------------------------------------------------------------------------

_FREQ_DIMS = ("omega", "freq", "period", "wavelength", "wavenumber")
_CAPYTAINE_DOFS = {name: i for i, name in enumerate(DOFS)}  # "Surge" etc., case-insensitive


def read_capytaine(path: str | PathLike) -> RAO:
    """Read RAOs from a NetCDF file exported by the BEM code Capytaine.

    The file is Capytaine's xarray Dataset saved with ``capytaine.export_dataset(path,
    ds)`` (checked with Capytaine 3.0; its older recipe
    ``separate_complex_values(ds).to_netcdf(path)`` fails there on the DOFs' categorical
    coordinates): complex variables are split along a leading ``complex`` dimension with
    coordinates ``"re"``, ``"im"`` (variables stored natively complex are also accepted).
    Both NETCDF4 (HDF5) files and classic NETCDF3 ones (what xarray writes where netCDF4
    and h5netcdf are not installed) are read. Two kinds of file are read:

    * with an ``RAO`` variable (e.g. ``ds["RAO"] = capytaine.post_pro.rao(ds)``),
      dimensions frequency, ``wave_direction`` and ``radiating_dof``;
    * without it: the RAO is computed as Capytaine's ``post_pro.rao`` does, for
      every frequency and wave direction, from ``excitation_force`` (or
      ``Froude_Krylov_force + diffraction_force``; dims frequency,
      ``wave_direction``, ``influenced_dof``), ``added_mass`` and
      ``radiation_damping`` (frequency, ``influenced_dof``, ``radiating_dof``),
      ``hydrostatic_stiffness`` and ``inertia_matrix`` (``influenced_dof``,
      ``radiating_dof``; these two must have been added to the dataset)::

          H = -omega^2 (M + A) - i omega B + K,      H X = F,

      with H indexed [influenced_dof, radiating_dof] (all DOFs of the file in
      the solve, generalised modes included).

    Conversions to the package's conventions (module docstring):

    * Capytaine's phasors use ``x(t) = Re(X exp(-i omega t))`` and its incoming
      wave has unit elevation, zero phase, at (0, 0, 0); ours use
      ``exp(+i omega t)``, so ``RAO = conj(X)``.
    * ``wave_direction`` (rad, 0 = waves travelling towards +x, counter-clockwise)
      becomes ``heading_deg`` in [0, 360) -- the same direction, in degrees.
    * DOFs named ``Surge, Sway, Heave, Roll, Pitch, Yaw`` (case-insensitive) fill
      the six rows (rotations in rad/m about Capytaine's rotation centre, which
      should be S's origin); DOFs the file lacks get a zero RAO, other DOFs
      (generalised modes) are dropped.
    * The frequency is the dimension named ``omega``, ``freq`` (Hz),
      ``period`` (s), ``wavelength`` or ``wavenumber`` (the latter two need the
      ``omega`` coordinate Capytaine adds); rows are sorted by omega and
      frequencies 0 and infinity (radiation-only cases) are dropped.
    * Other dimensions (``g``, ``rho``, ``water_depth``, ``body_name``, ...) must
      have a single value. Non-zero ``forward_speed`` is refused (the RAOs here
      are per wave frequency for a ship without way).

    Parameters
    ----------
    path : str or path-like
        The NetCDF file (read with xarray's h5netcdf engine).

    Returns
    -------
    RAO

    Raises
    ------
    ScenarioError
        If xarray or h5netcdf is missing (install the ``bem`` extra), the path
        is not a regular file of at most :data:`MAX_NETCDF_BYTES` bytes, the file
        cannot be read, its content does not have Capytaine's layout, or a
        frequency or RAO is beyond the limits of :func:`read_rao_csv`.
    """
    src = str(path)

    def fail(message: str) -> NoReturn:
        raise ScenarioError(message, source=src)

    xr = _import_xarray(fail)
    check_file(path, fail, "a Capytaine NetCDF file", MAX_NETCDF_BYTES)
    ds = _merge_complex_values(_load_dataset(xr, path, fail), fail)
    _check_forward_speed(ds, fail)
    response = _stored_rao(ds, fail) if "RAO" in ds.data_vars else _computed_rao(ds, fail)
    _check_response(response, fail)
    rows = _rigid_body_rows(response.dofs, fail)
    axes = _sorted_axes(response.omega, response.directions, fail)
    values = _six_dof_values(response.X, rows, axes)
    _check_capytaine_limits(axes, values, fail)
    return RAO(axes.omega, axes.headings, values)


# Steps of read_capytaine, in the order it takes them.


class _Response(NamedTuple):
    """A Capytaine RAO as in the file, at the frequencies in (0, inf).

    ``omega`` (n_w,) rad/s, ``dofs`` the n_dof radiating DOF names, ``X`` complex
    (n_w, n_dir, n_dof) in Capytaine's exp(-i omega t) convention, ``directions``
    (n_dir,) the wave directions, rad.
    """

    omega: np.ndarray
    dofs: list[str]
    X: np.ndarray
    directions: np.ndarray


class _Frequencies(NamedTuple):
    """A variable's frequency dimension ``dim``, ``omega`` (n_w,) rad/s and ``keep`` (n_w,): omega in (0, inf)."""

    dim: str
    omega: np.ndarray
    keep: np.ndarray


class _Terms(NamedTuple):
    """The terms of H X = F: A, B (n_w, n_dof, n_dof), M, K (n_dof, n_dof), F (n_w, n_dir, n_dof).

    Indexed [influenced_dof, radiating_dof]; xarray DataArrays until :func:`_arranged_terms`
    makes them arrays.
    """

    added_mass: Any
    damping: Any
    inertia: Any
    stiffness: Any
    force: Any


class _Axes(NamedTuple):
    """The RAO's axes, sorted: ``omega`` (n_omega,) rad/s, ``headings`` (n_heading,) deg, and the
    orders ``o_order``, ``h_order`` that sort the file's frequencies and directions."""

    omega: np.ndarray
    headings: np.ndarray
    o_order: np.ndarray
    h_order: np.ndarray


def _import_xarray(fail: _Fail) -> Any:
    """The xarray module; refuses to go on without it, h5netcdf or h5py (the `bem` extra)."""
    try:
        import h5netcdf  # noqa: F401  (xarray's engine)
        import h5py  # noqa: F401  (h5netcdf's HDF5 backend, an extra since h5netcdf 1.7)
        import xarray as xr
    except ImportError:
        fail("reading a Capytaine file needs xarray, h5netcdf and h5py: install the `bem` extra "
             "(pip install marinecdpr[bem])")
    return xr


NETCDF3_MAGIC = b"CDF"
"""The first bytes of a classic (NETCDF3) file: what xarray writes through SciPy where
netCDF4 and h5netcdf are not installed (Capytaine's ``export_dataset`` then does)."""


def _load_dataset(xr: Any, path: str | PathLike, fail: _Fail) -> Any:
    """The file's xarray Dataset, loaded into memory: NETCDF4 (HDF5) through h5netcdf, a
    classic NETCDF3 file through SciPy; refuses a file that is neither."""
    with open(path, "rb") as fh:
        classic = fh.read(3) == NETCDF3_MAGIC
    try:
        with xr.open_dataset(path, engine="scipy" if classic else "h5netcdf") as opened:
            ds = opened.load()
    except Exception as exc:  # h5py/h5netcdf/xarray raise many kinds for a bad file
        first_line = (str(exc).strip().splitlines() or [type(exc).__name__])[0]
        fail(f"cannot read as a NetCDF file: {first_line}")
    return ds


def _check_forward_speed(ds: Any, fail: _Fail) -> None:
    """Refuse a non-zero ``forward_speed`` (m/s)."""
    if "forward_speed" in ds.variables:
        speed = np.asarray(ds["forward_speed"].values, dtype=float)
        if np.any(speed != 0.0):
            fail(f"forward_speed {np.max(np.abs(speed)):g} m/s: only zero forward speed is supported")


def _frequencies(ds: Any, da: Any, name: str, fail: _Fail) -> _Frequencies:
    """The frequency dimension of variable ``da`` (called ``name``) and its angular frequencies."""
    fdim = _frequency_dim(da, name, fail)
    omega = _omega_values(ds, fdim, fail)
    return _Frequencies(fdim, omega, np.isfinite(omega) & (omega > 0.0))


def _stored_rao(ds: Any, fail: _Fail) -> _Response:
    """The RAO of the file's ``RAO`` variable."""
    rao = _with_direction_dim(ds["RAO"])
    freq = _frequencies(ds, rao, "RAO", fail)
    dofs = _labels(rao, "radiating_dof", "RAO", fail)
    X = _arranged(rao, (freq.dim, "wave_direction", "radiating_dof"), "RAO", fail)[freq.keep]
    return _Response(omega=freq.omega[freq.keep], dofs=dofs, X=X, directions=_coordinate(rao, "wave_direction", fail))


def _computed_rao(ds: Any, fail: _Fail) -> _Response:
    """The RAO solved from the file's coefficients and excitation force, as Capytaine's ``post_pro.rao``."""
    F_da = _excitation_force(ds, fail)
    freq = _frequencies(ds, F_da, "excitation_force", fail)
    dofs = _labels(ds["added_mass"], "radiating_dof", "added_mass", fail)
    terms = _select_dofs(ds, F_da, dofs, fail)
    X = _solve_rao(freq.omega[freq.keep], _arranged_terms(terms, freq, fail), fail)
    return _Response(omega=freq.omega[freq.keep], dofs=dofs, X=X,
                     directions=_coordinate(terms.force, "wave_direction", fail))


def _excitation_force(ds: Any, fail: _Fail) -> Any:
    """The excitation force DataArray (FK + diffraction if need be); refuses a file lacking a needed variable."""
    missing = [v for v in ("added_mass", "radiation_damping", "hydrostatic_stiffness", "inertia_matrix")
               if v not in ds.data_vars]
    if "excitation_force" in ds.data_vars:
        F_da = ds["excitation_force"]
    elif "Froude_Krylov_force" in ds.data_vars and "diffraction_force" in ds.data_vars:
        F_da = ds["Froude_Krylov_force"] + ds["diffraction_force"]
    else:
        F_da = None
        missing.insert(0, "excitation_force (or Froude_Krylov_force and diffraction_force)")
    if missing:
        fail(f"no 'RAO' variable, and computing it needs {', '.join(missing)} in the file")
    return _with_direction_dim(F_da)


def _select_dofs(ds: Any, F_da: Any, dofs: list[str], fail: _Fail) -> _Terms:
    """The terms as DataArrays over the radiating DOFs ``dofs``; refuses influenced DOFs that differ."""
    sel = {"influenced_dof": dofs, "radiating_dof": dofs}
    try:
        A = ds["added_mass"].sel(sel)
        B = ds["radiation_damping"].sel(sel)
        M = ds["inertia_matrix"].sel(sel)
        K = ds["hydrostatic_stiffness"].sel(sel)
        F_da = F_da.sel(influenced_dof=dofs)
    except (KeyError, ValueError) as exc:
        fail(f"the radiating and influenced DOFs do not match: {exc}")
    return _Terms(added_mass=A, damping=B, inertia=M, stiffness=K, force=F_da)


def _arranged_terms(terms: _Terms, freq: _Frequencies, fail: _Fail) -> _Terms:
    """The terms as arrays in the shapes of :class:`_Terms`, at the kept frequencies."""
    mat = ("influenced_dof", "radiating_dof")
    fdim, keep = freq.dim, freq.keep
    return _Terms(
        added_mass=_arranged(terms.added_mass, (fdim,) + mat, "added_mass", fail)[keep],
        damping=_arranged(terms.damping, (fdim,) + mat, "radiation_damping", fail)[keep],
        inertia=_arranged(terms.inertia, mat, "inertia_matrix", fail),
        stiffness=_arranged(terms.stiffness, mat, "hydrostatic_stiffness", fail),
        force=_arranged(terms.force, (fdim, "wave_direction", "influenced_dof"), "excitation_force", fail)[keep],
    )


def _solve_rao(omega: np.ndarray, terms: _Terms, fail: _Fail) -> np.ndarray:
    """X, complex (n_w, n_dir, n_dof), solving H X = F at each omega (n_w,) rad/s; refuses a bad H or F."""
    A, B, M, K, F = terms
    w = omega[:, None, None]
    H = -w**2 * (M + A) - 1j * w * B + K  # Capytaine's rao_transfer_function
    if not (np.all(np.isfinite(H)) and np.all(np.isfinite(F))):
        fail("the added mass, damping, matrices or excitation force are not finite "
             "at a frequency in (0, inf)")
    try:
        X = np.linalg.solve(H[:, None], F[..., None])[..., 0]
    except np.linalg.LinAlgError:
        fail("the matrix -omega^2 (M + A) - i omega B + K is singular at a frequency")
    return X


def _check_response(response: _Response, fail: _Fail) -> None:
    """Refuse an RAO without a frequency in (0, inf) or with a value that is not finite."""
    if response.omega.size == 0:
        fail("no frequency in (0, inf)")
    if not np.all(np.isfinite(response.X)):
        bad = np.argwhere(~np.isfinite(response.X))[0]
        fail(f"RAO not finite at omega {response.omega[bad[0]]:g} rad/s")


def _rigid_body_rows(dofs: list[str], fail: _Fail) -> list[tuple[int, int]]:
    """(index in ``dofs``, index in :data:`DOFS`) of each rigid-body DOF of the file; refuses none."""
    rows = [(j, _CAPYTAINE_DOFS.get(name.lower())) for j, name in enumerate(dofs)]
    rows = [(j, k) for j, k in rows if k is not None]
    if not rows:
        fail(f"no rigid-body DOF among {', '.join(dofs)} (expected Surge, Sway, Heave, Roll, Pitch, Yaw)")
    return rows


def _sorted_axes(omega: np.ndarray, directions: np.ndarray, fail: _Fail) -> _Axes:
    """omega (rad/s) and the headings in [0, 360) deg of the directions (rad), sorted; refuses repeats."""
    headings = np.round(np.mod(np.degrees(directions), 360.0), 10)
    headings[headings >= 360.0] -= 360.0
    h_order = np.argsort(headings, kind="stable")
    o_order = np.argsort(omega, kind="stable")
    headings, omega = headings[h_order], omega[o_order]
    if np.any(np.diff(headings) == 0.0):
        fail(f"two wave directions give the same heading {headings[1:][np.diff(headings) == 0.0][0]:g} deg")
    if np.any(np.diff(omega) == 0.0):
        fail(f"omega {omega[1:][np.diff(omega) == 0.0][0]:g} rad/s appears twice")
    return _Axes(omega=omega, headings=headings, o_order=o_order, h_order=h_order)


def _six_dof_values(X: np.ndarray, rows: list[tuple[int, int]], axes: _Axes) -> np.ndarray:
    """The RAO values, complex (6, n_heading, n_omega), exp(+i omega t): conj(X) sorted, 0 for absent DOFs."""
    X = X[axes.o_order][:, axes.h_order]  # (n_omega, n_heading, n_dof)
    values = np.zeros((6, axes.headings.size, axes.omega.size), dtype=complex)
    for j, k in rows:
        values[k] = np.conj(X[:, :, j]).T  # exp(-i w t) -> exp(+i w t)
    return values


def _check_capytaine_limits(axes: _Axes, values: np.ndarray, fail: _Fail) -> None:
    """Refuse a frequency or RAO beyond the limits of :func:`read_rao_csv`."""
    if (problem := _rao_out_of_range(axes.omega, axes.headings, values)) is not None:
        fail(problem + (" (potential flow lacks viscous roll damping)" if "roll RAO" in problem else ""))


def _label(x) -> str:
    return x.decode() if isinstance(x, bytes) else str(x)


def _merge_complex_values(ds, fail):
    """Undo Capytaine's ``separate_complex_values``: re/im along ``complex`` -> complex."""
    if "complex" not in ds.dims:
        return ds
    if "complex" in ds.coords:
        labels = [_label(x) for x in np.atleast_1d(ds["complex"].values)]
        if sorted(labels) != ["im", "re"]:
            fail(f"the 'complex' coordinate is {labels}; expected ['re', 'im']")
        i_re, i_im = labels.index("re"), labels.index("im")
    elif ds.sizes["complex"] == 2:
        i_re, i_im = 0, 1
    else:
        fail("the 'complex' dimension must have the two entries 're' and 'im'")
    ds = ds.copy()
    for name in list(ds.data_vars):
        da = ds[name]
        if "complex" in da.dims:
            ds[name] = da.isel(complex=i_re, drop=True) + 1j * da.isel(complex=i_im, drop=True)
    return ds.drop_vars("complex", errors="ignore")


def _with_direction_dim(da):
    """A scalar ``wave_direction`` coordinate (one direction selected) as a dimension of size 1."""
    if "wave_direction" not in da.dims and "wave_direction" in da.coords and da["wave_direction"].ndim == 0:
        return da.expand_dims("wave_direction")
    return da


def _frequency_dim(da, name: str, fail) -> str:
    found = [d for d in _FREQ_DIMS if d in da.dims]
    if len(found) != 1:
        fail(f"{name} must have exactly one frequency dimension among {', '.join(_FREQ_DIMS)}; "
             f"it has dimensions {', '.join(map(str, da.dims))}")
    return found[0]


def _omega_values(ds, fdim: str, fail) -> np.ndarray:
    """Angular frequencies (rad/s) along the frequency dimension ``fdim``."""
    if "omega" in ds.variables and ds["omega"].dims == (fdim,):
        return np.asarray(ds["omega"].values, dtype=float)
    if fdim == "freq":
        return 2.0 * np.pi * np.asarray(ds["freq"].values, dtype=float)
    if fdim == "period":
        with np.errstate(divide="ignore"):
            return 2.0 * np.pi / np.asarray(ds["period"].values, dtype=float)
    fail(f"the frequency dimension is {fdim!r} but the file has no 'omega' coordinate along it")


def _labels(da, dim: str, name: str, fail) -> list[str]:
    if dim not in da.dims:
        fail(f"{name} has no {dim!r} dimension (dimensions {', '.join(map(str, da.dims))})")
    return [_label(x) for x in _coordinate(da, dim, fail)]


def _coordinate(da, dim: str, fail) -> np.ndarray:
    if dim not in da.dims:
        fail(f"no {dim!r} dimension: the file lacks the diffraction (wave) results")
    if dim not in da.coords:
        fail(f"the {dim!r} dimension has no coordinate values")
    return np.asarray(da[dim].values)


def _arranged(da, dims: tuple[str, ...], name: str, fail) -> np.ndarray:
    """``da``'s values with dimensions ``dims``; other dimensions must have one entry."""
    for d in dims:
        if d not in da.dims:
            fail(f"{name} has no {d!r} dimension (dimensions {', '.join(map(str, da.dims))})")
    for d in da.dims:
        if d not in dims:
            if da.sizes[d] != 1:
                fail(f"{name} has {da.sizes[d]} values of {d!r}; export one case per file")
            da = da.isel({d: 0})
    return np.asarray(da.transpose(*dims).values)


# ---------------------------------------------------------------------------------------
# Box hull
# ---------------------------------------------------------------------------------------

ROLL_GYRADIUS_OVER_BEAM = 0.4
"""The box hull's roll radius of gyration over its beam, added inertia included."""


def _sincos_deg(deg: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """sin and cos of angles in degrees, exactly 0 and +-1 at multiples of 90 deg."""
    r = np.radians(deg)
    s, c = np.sin(r), np.cos(r)
    quarter = np.mod(deg, 90.0) == 0.0
    q = np.mod(np.round(deg / 90.0), 4).astype(int)
    s = np.where(quarter, np.array([0.0, 1.0, 0.0, -1.0])[q], s)
    c = np.where(quarter, np.array([1.0, 0.0, -1.0, 0.0])[q], c)
    return s, c


def _slope_factor(u: np.ndarray) -> np.ndarray:
    """3 (sin u - u cos u) / u^3: the waterplane-averaged slope of a wave, -> 1 as u -> 0."""
    u = np.abs(u)
    small = u < 1e-2
    us = np.where(small, 1.0, u)
    exact = 3.0 * (np.sin(us) - us * np.cos(us)) / us**3
    u2 = u * u
    series = 1.0 - u2 / 10.0 + u2 * u2 / 280.0
    return np.where(small, series, exact)


def check_positive(**params: float) -> None:
    """Refuse a parameter that is not a finite number > 0 (ValueError naming it)."""
    for key, value in params.items():
        if not (np.isfinite(value) and value > 0.0):
            raise ValueError(f"{key} must be finite and > 0; got {value}")


def box_hull_rao(
    *,
    length_m: float,
    beam_m: float,
    draught_m: float,
    gm_m: float,
    roll_damping_ratio: float,
    omega: np.ndarray,
    heading_deg: np.ndarray,
    gml_m: float | None = None,
    rho: float = 1025.0,
    g: float = 9.81,
) -> RAO:
    """RAOs of a box-shaped hull at zero speed in deep water: an approximation.

    A quick estimate for when no BEM data are at hand. Heave and pitch follow the
    closed-form expressions of Jensen, Mansour & Olsen (2004), "Estimation of ship
    motions using closed-form expressions", Ocean Engineering 31, 61-85, for zero
    speed (alpha = 1) and block coefficient 1, written as complex RAOs; roll is a
    damped one-DOF oscillator excited by the wave slope; **surge, sway and yaw are
    zero**. S's origin is the box's centre on the waterline.

    With k = omega^2/g, k_x = k cos(beta), k_y = k sin(beta), u = k_x L/2 and

        kappa = exp(-k T)                       (Smith correction)
        A     = 2 sin(k B/2) exp(-k T)          (2D radiated-wave amplitude ratio)
        D     = A^2 / (k B)                     (heave damping over stiffness, omega b/c)
        P     = 1 - k T + i D,   Q = 1 - 2 k T + i D

    (strip theory for a uniformly loaded box with sectional added mass equal to
    its mass, damping b = rho g^2 A^2 / omega^3, stiffness c = rho g B):

        heave = kappa P / Q * sin(u) / u
        pitch = kappa (P + delta) / (Q + delta) * i k_x R(u),
                R(u) = 3 (sin u - u cos u) / u^3,
                delta = 12 T GM_L / L^2 - 1
        roll  = -i k_y R(k_y B/2) / (1 - r^2 + 2 i zeta r),
                r = omega / omega_roll,  omega_roll = sqrt(g GM) / (0.4 B)

    The magnitudes of heave and pitch are Jensen et al.'s eta |F| and eta |G|
    (their eqs. for F, G, f and eta at zero speed); the phases follow from the same
    strip-theory equations in this module's time convention. ``gml_m = None``
    gives delta = 0, the paper's pitch stiffness rho g B L^3/12 (GM_L = L^2/(12 T),
    the box's BM_L); a given GM_L sets the pitch stiffness to rho g LBT GM_L, added
    to both sides so that pitch still follows the wave slope in long waves.

    Roll: a one-DOF oscillator with restoring rho g LBT GM and inertia including
    the added inertia through the radius of gyration 0.4 B
    (:data:`ROLL_GYRADIUS_OVER_BEAM`, as in the IMO roll-period estimate
    T = 2 C B / sqrt(GM), C ~ 0.4), damping ratio zeta as given, excited by the
    wave slope k sin(beta) averaged over the beam (R, which makes roll fall off
    in waves shorter than the beam). No depth (Smith) reduction is applied to
    roll, which errs on the large side by up to a factor exp(k T). So roll is zero
    in head and following seas, follows the slope in long beam waves
    (-> -i k sin(beta)), and peaks at about slope / (2 zeta) at omega_roll in beam
    seas.

    Limits: no coupling, no forward speed, no viscous heave/pitch damping, no
    beam-wise reduction of heave; realistic only for omega below a few times the
    natural frequencies and for ship-like proportions.

    Error against BEM (Capytaine via :func:`marinecdpr.motion.bem.box_hull_bem`, the same
    box: 100 x 20 x 6 m, GM 2 m, 5 % roll damping; ``tests/test_bem.py``): heave in head
    seas within 0.1 m/m (0.04-0.10 near 0.8 rad/s, where the box's heave cancels and
    BEM's does not); in beam seas heave up to 0.75 m/m too high (no reduction across the
    beam); **roll in beam seas peaks 2.5-5 times too high** (17.5 against 4.7 deg/m at
    0.05 rad/s resolution) and stays several times too high in short waves (about 2 against
    0.3 deg/m at 1 rad/s). Use it for a first, pessimistic look; use BEM RAOs
    (``marinecdpr rao``) for any operability figure.

    Parameters
    ----------
    length_m, beam_m, draught_m : float
        Box length L, beam B and draught T, m (> 0).
    gm_m : float
        Transverse metacentric height GM, m (> 0).
    roll_damping_ratio : float
        Roll damping over critical damping zeta (> 0).
    omega : array_like, shape (n_omega,)
        Wave angular frequencies, rad/s, strictly increasing, > 0.
    heading_deg : array_like, shape (n_heading,)
        Wave headings beta (travel direction from S's +x, CCW), deg, strictly
        increasing in [0, 360).
    gml_m : float, optional
        Longitudinal metacentric height GM_L, m (> 0). Default: L^2 / (12 T).
    rho : float
        Water density, kg/m^3 (> 0; it cancels out of these ratios).
    g : float
        Gravitational acceleration, m/s^2.

    Returns
    -------
    RAO
    """
    L, B, T = float(length_m), float(beam_m), float(draught_m)
    params = {"length_m": L, "beam_m": B, "draught_m": T, "gm_m": gm_m,
              "roll_damping_ratio": roll_damping_ratio, "rho": rho, "g": g}
    if gml_m is not None:
        params["gml_m"] = gml_m
    check_positive(**params)
    zeta = float(roll_damping_ratio)
    w = np.asarray(omega, dtype=float)
    beta = np.asarray(heading_deg, dtype=float)
    if w.ndim != 1 or beta.ndim != 1:
        raise ValueError("omega and heading_deg must be 1-D arrays")
    if np.any(w <= 0.0):
        raise ValueError("omega must be > 0 rad/s")
    sin_b, cos_b = _sincos_deg(beta)
    k = (w * w / g)[None, :]  # (1, n_omega)
    kx = k * cos_b[:, None]  # (n_heading, n_omega)
    ky = k * sin_b[:, None]
    kappa = np.exp(-k * T)
    A = 2.0 * np.sin(0.5 * k * B) * kappa
    D = A * A / (k * B)
    P = 1.0 - k * T + 1j * D
    Q = 1.0 - 2.0 * k * T + 1j * D
    u = 0.5 * kx * L
    delta = 0.0 if gml_m is None else 12.0 * T * float(gml_m) / L**2 - 1.0
    heave = kappa * P / Q * np.sinc(u / np.pi)
    pitch = kappa * (P + delta) / (Q + delta) * 1j * kx * _slope_factor(u)
    omega_roll = math.sqrt(g * float(gm_m)) / (ROLL_GYRADIUS_OVER_BEAM * B)
    r = w[None, :] / omega_roll
    roll = -1j * ky * _slope_factor(0.5 * ky * B) / (1.0 - r * r + 2j * zeta * r)
    values = np.zeros((6, beta.size, w.size), dtype=complex)
    values[2], values[3], values[4] = heave, roll, pitch
    return RAO(w, beta, values)
