"""RAOs as a long-format CSV table: :func:`read_rao_csv` (one line per refusal, naming the
row, never quoting the file) and :func:`write_rao_csv` (atomic, read back exactly)."""

from __future__ import annotations

import csv
import math
from os import PathLike
from typing import NamedTuple, NoReturn, Sequence

import numpy as np

from marinecdpr.errors import ScenarioError
from marinecdpr.motion.rao.table import (
    DOFS, OMEGA_MAX_RAD_S, RAO, ROTATION_RAO_MAX_DEG_M, ROTATIONS, TRANSLATION_RAO_MAX_M_M, Fail, out_of_range,
)
from marinecdpr.textfiles import MAX_FIELD_CHARS, atomic_path, long_field, read_lines, strip_control

__all__ = ["read_rao_csv", "write_rao_csv", "PHASE_MAX_DEG"]

_CSV_COLUMNS = ("omega_rad_s", "heading_deg", "dof", "amplitude", "phase_deg")

PHASE_MAX_DEG = 1.0e6
"""Largest |phase| in an RAO CSV table, deg (unwrapped phases pass)."""


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
                  elevation at S's origin (:mod:`marinecdpr.motion.rao`)
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


def _read_csv_table(path: str | PathLike, fail: Fail) -> _CsvTable:
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


def _check_field_lengths(table: _CsvTable, fail: Fail) -> None:
    """Refuse a field (header included) over :data:`MAX_FIELD_CHARS` characters."""
    if (long := long_field([table.header] + table.rows)) is not None:
        i, j = long
        fail(f"row {table.header_row if i == 0 else table.row_numbers[i - 1]}, field {j + 1}: over "
             f"{MAX_FIELD_CHARS} characters; expected {_CSV_WHAT}")


def _column_indices(table: _CsvTable, fail: Fail) -> dict[str, int]:
    """The header's index of each column of the format; refuses a missing or repeated one."""
    col: dict[str, int] = {}
    for name in _CSV_COLUMNS:
        if table.header.count(name) != 1:
            what = "lacks" if name not in table.header else "repeats"
            fail(f"row {table.header_row}: the header {what} column {name!r} (expected {_CSV_EXPECTED})")
        col[name] = table.header.index(name)
    return col


def _check_row_lengths(table: _CsvTable, fail: Fail) -> None:
    """Refuse a table without data rows, or a row whose number of fields differs from the header's."""
    if not table.rows:
        fail(f"row {table.header_row}: no data rows after the header")
    for rec, line in zip(table.rows, table.row_numbers):
        if len(rec) != len(table.header):
            fail(f"row {line}: {len(rec)} fields, but the header has {len(table.header)}")


def _parse_rows(table: _CsvTable, col: dict[str, int], fail: Fail) -> _RaoRows:
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


def _numbers(table: _CsvTable, col: dict[str, int], name: str, fail: Fail) -> np.ndarray:
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


def _check_row_ranges(rows: _RaoRows, fail: Fail) -> None:
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


def _check_row_limits(rows: _RaoRows, fail: Fail) -> None:
    """Refuse an omega (rad/s), amplitude (m/m, deg/m) or |phase| (deg) beyond the module's limits."""
    lines, omega, amplitude, dof = rows.lines, rows.omega, rows.amplitude, rows.dof
    if (i := _first(omega > OMEGA_MAX_RAD_S)) is not None:
        fail(f"row {lines[i]}: omega_rad_s {omega[i]:g} is above {OMEGA_MAX_RAD_S:g} rad/s; "
             f"expected wave frequencies in rad/s")
    limit = np.where(ROTATIONS[np.maximum(dof, 0)], ROTATION_RAO_MAX_DEG_M, TRANSLATION_RAO_MAX_M_M)
    if (i := _first(amplitude > limit)) is not None:
        unit = "deg/m" if ROTATIONS[dof[i]] else "m/m"
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


def _check_duplicates(rows: _RaoRows, grid: _Grid, fail: Fail) -> None:
    """Refuse two rows of the same (omega, heading, DOF), naming the later row of the first such pair."""
    order = np.argsort(grid.key, kind="stable")
    same = np.flatnonzero(grid.key[order][1:] == grid.key[order][:-1])
    if same.size:
        later, earlier = order[same + 1], order[same]
        j = int(np.argmin(later))
        i, e = int(later[j]), int(earlier[j])
        fail(f"row {rows.lines[i]}: duplicate of row {rows.lines[e]} (omega {rows.omega[i]:g} rad/s, "
             f"heading {rows.heading[i]:g} deg, dof {DOFS[rows.dof[i]]})")


def _check_full_grid(rows: _RaoRows, grid: _Grid, fail: Fail) -> None:
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
    amp = np.where(ROTATIONS[rows.dof], np.radians(rows.amplitude), rows.amplitude)
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
    if (problem := out_of_range(rao.omega, rao.heading_deg, rao.values)) is not None:
        raise ValueError(f"{problem}: read_rao_csv would refuse the file")
    n_h, n_o = rao.heading_deg.size, rao.omega.size
    ih, io, d = np.meshgrid(np.arange(n_h), np.arange(n_o), np.arange(6), indexing="ij")
    ih, io, d = ih.ravel(), io.ravel(), d.ravel()
    v = rao.values[d, ih, io]
    amp = np.abs(v)
    amp = np.where(ROTATIONS[d], np.degrees(amp), amp)
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

