"""Weather windows: when, in a series of sea states, an operation of a given duration fits.

A sea-state series (hindcast or forecast: time, Hs, Tp, optionally the mean wind) is
workable at a sample when its Hs is at most the operational limit: alpha times the design
limit (DNV-ST-N001's alpha factor for the forecast's uncertainty, which the user takes from
the standard for the operation's duration and forecast level: the standard's tables are not
shipped). The design limit is a constant Hs or, per Tp, the limiting Hs of an operability
study. With an operational wind limit (DNV-ST-N001 limits operations by the mean wind too)
a sample is workable when, as well, its mean wind is at most that limit.

Each sample holds until the next one (the last one for the series' median step). A
window is a run of workable time; an operation of ``duration_h`` can start at t if
[t, t + duration_h] is all workable. From every start time of the series (each sample's
time, equally likely) the study finds the wait until the operation can start, its mean
(over the start times from which it can start at all before the series ends) and the
probability that the operation is finished within a number of days.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path
from typing import NoReturn

import numpy as np

from marinecdpr.errors import ScenarioError
from marinecdpr.textfiles import MAX_FIELD_CHARS, long_field, read_csv_records, read_text

__all__ = ["SeaStateSeries", "read_sea_state_series", "Windows", "weather_windows", "read_operability_json",
           "limit_from_operability", "SERIES_HOURS_MAX"]


@dataclass(frozen=True)
class SeaStateSeries:
    """Sea states over time: t_h (n,) hours from the series' start, increasing; hs_m (n,)
    significant wave height, m; tp_s (n,) peak period, s; wind_m_s (n,) the mean wind speed
    at 10 m above the sea, m/s, or None (a series without the column ``wind_m_s``)."""

    t_h: np.ndarray
    hs_m: np.ndarray
    tp_s: np.ndarray
    wind_m_s: np.ndarray | None = None

    @property
    def step_h(self) -> np.ndarray:
        """(n,) how long each sample holds: until the next, the last for the median step."""
        d = np.diff(self.t_h)
        return np.append(d, np.median(d) if d.size else 1.0)


SERIES_HOURS_MAX = 1e7
"""Largest time of a sea-state series, in magnitude, h (some 1100 years: a hindcast spans
decades). Beyond it, times lose the hour's resolution and their differences overflow."""


def read_sea_state_series(path: str | Path) -> SeaStateSeries:
    """A CSV with columns ``time_h, hs_m, tp_s`` and optionally ``wind_m_s`` (header row;
    further columns ignored; ``#`` comment lines skipped). Read through
    :func:`marinecdpr.textfiles.read_lines` (a regular UTF-8 text file of at most 256 MiB;
    a byte-order mark and CRLF accepted). Times lie within +-:data:`SERIES_HOURS_MAX` h, Hs
    and Tp within the ranges of a scatter diagram
    (:data:`~marinecdpr.studies.operability.HS_RANGE_M`,
    :data:`~marinecdpr.studies.operability.TP_RANGE_S`), the wind (the mean speed at 10 m,
    m/s) within 0 .. the scatter diagram's largest mean wind
    (:data:`~marinecdpr.studies.operability.WIND_COLUMNS`, 70 m/s): calm (0) is a wind.
    One-line errors name the file, line and column, and never quote more than a field."""
    from marinecdpr.studies.operability import HS_RANGE_M, TP_RANGE_S, WIND_COLUMNS

    src = str(path)
    what = "a sea-state series CSV file (time_h,hs_m,tp_s)"

    def fail(message: str) -> NoReturn:
        raise ScenarioError(message, source=src)

    rows = [(i, r) for i, r in enumerate(read_csv_records(path, fail, what), start=1)
            if r and r[0].strip() and not r[0].lstrip().startswith("#")]
    if not rows:
        raise ScenarioError("empty: expected a header time_h,hs_m,tp_s and rows", source=src)
    if (long := long_field([r for _, r in rows])) is not None:
        k, j = long
        fail(f"line {rows[k][0]}, field {j + 1}: over {MAX_FIELD_CHARS} characters; expected {what}")
    header = [h.strip() for h in rows[0][1]]
    missing = [c for c in ("time_h", "hs_m", "tp_s") if c not in header]
    if missing:
        raise ScenarioError(f"line {rows[0][0]}: missing column(s) {', '.join(missing)} (expected time_h,hs_m,tp_s)",
                            source=src)
    names = ("time_h", "hs_m", "tp_s") + (("wind_m_s",) if "wind_m_s" in header else ())
    cols = [header.index(c) for c in names]
    ranges = {"time_h": (-SERIES_HOURS_MAX, SERIES_HOURS_MAX, "h"), "hs_m": (*HS_RANGE_M, "m"),
              "tp_s": (*TP_RANGE_S, "s"), "wind_m_s": (0.0, WIND_COLUMNS["wind_m_s"][1], "m/s")}
    sign = {"time_h": "", "hs_m": " positive", "tp_s": " positive", "wind_m_s": " non-negative"}
    values = np.empty((len(rows) - 1, len(names)))
    for k, (line, r) in enumerate(rows[1:]):
        for j, (c, name) in enumerate(zip(cols, names)):
            try:
                v = float(r[c])
            except (IndexError, ValueError):
                raise ScenarioError(f"line {line}, {name}: expected a number, got {r[c] if c < len(r) else ''!r}",
                                    source=src) from None
            if not math.isfinite(v) or (name in ("hs_m", "tp_s") and v <= 0) or (name == "wind_m_s" and v < 0):
                raise ScenarioError(f"line {line}, {name}: expected a finite{sign[name]} number, got {v:g}",
                                    source=src)
            lo, hi, unit = ranges[name]
            if not lo <= v <= hi:
                raise ScenarioError(f"line {line}, {name}: {v:g} {unit} is outside {lo:g} .. {hi:g} {unit}",
                                    source=src)
            values[k, j] = v
    if values.shape[0] < 2:
        raise ScenarioError("fewer than two sea states: no series", source=src)
    if np.any(np.diff(values[:, 0]) <= 0):
        bad = int(np.flatnonzero(np.diff(values[:, 0]) <= 0)[0]) + 2
        raise ScenarioError(f"line {rows[bad][0]}, time_h: times must increase", source=src)
    return SeaStateSeries(values[:, 0] - values[0, 0], values[:, 1], values[:, 2],
                          values[:, 3] if len(names) > 3 else None)


OPERABILITY_JSON_MAX_BYTES = 64 * 2**20
"""Largest operability.json read, bytes (a study of 10 000 sea states writes some 2 MB)."""


def read_operability_json(path: str | Path) -> dict:
    """An ``operability.json`` (what ``marinecdpr operability`` writes), read through
    :func:`marinecdpr.textfiles.read_text` (a regular UTF-8 text file of at most
    :data:`OPERABILITY_JSON_MAX_BYTES`) as strict JSON (``NaN`` and ``Infinity`` refused).

    Raises
    ------
    ScenarioError
        One line naming the file (and the line and column where the JSON is malformed).
    """
    src = str(path)
    what = "an operability.json file (marinecdpr operability writes one)"

    def fail(message: str) -> NoReturn:
        raise ScenarioError(message, source=src)

    def constant(name: str):
        fail(f"{name} is not a JSON number; expected {what}")

    text = read_text(path, fail, what, max_bytes=OPERABILITY_JSON_MAX_BYTES)
    try:
        data = json.loads(text, parse_constant=constant)
    except json.JSONDecodeError as exc:
        fail(f"line {exc.lineno}, column {exc.colno}: not JSON ({exc.msg}); expected {what}")
    except RecursionError:
        fail(f"nested too deep; expected {what}")
    if not isinstance(data, dict):
        fail(f"expected a JSON object with the key limiting_hs_m, got a {type(data).__name__}")
    return data


def limit_from_operability(summary: dict, heading_deg: float) -> tuple[np.ndarray, np.ndarray]:
    """The design Hs limit per Tp (tp (k,), hs (k,)) from an ``operability.json``'s
    ``limiting_hs_m`` at one heading; ``None`` (no limit within the diagram) becomes inf.

    Raises
    ------
    ScenarioError
        If the summary has no such heading, or its table is not an object of Tp (s, in
        :data:`~marinecdpr.studies.operability.TP_RANGE_S`) to a limiting Hs (a finite
        number >= 0 m, or null); ``key`` names the entry.
    """
    from marinecdpr.studies.operability import TP_RANGE_S

    limits = summary.get("limiting_hs_m") if isinstance(summary, dict) else None
    if not isinstance(limits, dict):
        raise ScenarioError("expected limiting_hs_m: an object of headings (deg) to tables of Tp to Hs",
                            key="limiting_hs_m")
    table = limits.get(f"{heading_deg:g}")
    if not table:
        raise ScenarioError(f"the operability summary has no heading {heading_deg:g} deg "
                            f"(it has {', '.join(map(str, limits)) or 'none'})")
    key = f"limiting_hs_m.{heading_deg:g}"
    if not isinstance(table, dict):
        raise ScenarioError(f"expected an object of Tp (s) to the limiting Hs (m), got a {type(table).__name__}",
                            key=key)
    pairs = []
    for k, v in table.items():
        try:
            tp = float(k)
        except ValueError:
            tp = math.nan
        if not TP_RANGE_S[0] <= tp <= TP_RANGE_S[1]:
            raise ScenarioError(f"the Tp {k[:40]!r} is not a number of seconds in {TP_RANGE_S[0]:g} .. "
                                f"{TP_RANGE_S[1]:g}", key=key)
        if v is None:
            hs = math.inf
        elif isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) and v >= 0:
            hs = float(v)
        else:
            shown = type(v).__name__ if isinstance(v, (dict, list, str, bool)) else f"{v:g}"
            raise ScenarioError(f"expected a limiting Hs: a finite number >= 0 m or null, got {shown}",
                                key=f"{key}.{k}")
        pairs.append((tp, hs))
    pairs.sort()
    tp = np.array([p[0] for p in pairs])
    hs = np.array([p[1] for p in pairs])
    if np.any(np.diff(tp) <= 0):
        raise ScenarioError("a Tp appears twice", key=key)
    return tp, hs


@dataclass(frozen=True)
class Windows:
    """A weather-window study (:func:`weather_windows`).

    Attributes
    ----------
    workable : ndarray of bool, shape (n,)
        Each sample's sea state within the operational limit (and its wind within
        ``wind_limit_m_s`` where given).
    hs_workable : ndarray of bool, shape (n,)
        Each sample's Hs within the operational limit, the wind aside (``workable`` without
        a wind limit).
    limit_m : ndarray, shape (n,)
        The operational Hs limit at each sample (alpha x the design limit), m.
    windows : list of (start_h, end_h)
        The runs of workable time.
    wait_h : ndarray, shape (n,)
        From each sample's time, the wait until the operation can start, h; NaN if it
        cannot start before the series ends.
    duration_h, alpha : float
    mean_wait_h : float
        Mean of ``wait_h`` over the start times from which the operation can start.
    can_start : float
        Share of start times from which it can start before the series ends.
    workable_share, hs_workable_share : float
        The share of the series' time that is workable, and that by Hs alone (each sample
        weighted by how long it holds).
    wind_limit_m_s : float or None
        The operational limit of the mean wind at 10 m, m/s; None: the wind not judged.
    """

    workable: np.ndarray
    hs_workable: np.ndarray
    limit_m: np.ndarray
    windows: list
    wait_h: np.ndarray
    duration_h: float
    alpha: float
    mean_wait_h: float
    can_start: float
    workable_share: float
    hs_workable_share: float
    wind_limit_m_s: float | None = None

    @property
    def long_enough(self) -> int:
        """How many windows the operation fits in (``duration_h`` or longer)."""
        return sum(1 for a, b in self.windows if b - a >= self.duration_h - 1e-12)

    def finish_probability(self, days: float) -> float:
        """The probability (over start times) that the operation is finished within
        ``days``: it can start, and wait + duration <= days x 24 h."""
        can = np.isfinite(self.wait_h)  # (inf + d <= inf would count the start times that never start)
        done = can & (np.where(can, self.wait_h, 0.0) + self.duration_h <= days * 24.0 + 1e-9)
        return float(done.mean())


def weather_windows(series: SeaStateSeries, *, duration_h: float, alpha: float = 1.0,
                    hs_limit_m: float | None = None, limit_table: tuple[np.ndarray, np.ndarray] | None = None,
                    wind_limit_m_s: float | None = None) -> Windows:
    """The weather windows of ``series`` for an operation of ``duration_h``.

    Parameters
    ----------
    series : SeaStateSeries
    duration_h : float
        The operation's duration, h (> 0).
    alpha : float
        DNV-ST-N001's alpha factor in (0, 1]: the operational limit is alpha x the design limit.
    hs_limit_m : float, optional
        A constant design Hs limit, m.
    limit_table : (tp (k,), hs (k,)), optional
        The design Hs limit per Tp (e.g. :func:`limit_from_operability`): a sample takes the
        limit of the nearest tabulated Tp.
    wind_limit_m_s : float, optional
        The operational limit of the mean wind at 10 m, m/s (> 0; alpha does not scale it): a
        sample is workable when its Hs is within its limit and its ``series.wind_m_s`` within
        this one (at most, as Hs). None: the wind, if the series has it, is not judged.

    Raises
    ------
    ValueError
        A duration, alpha or wind limit out of range, not one design limit, or a wind limit
        for a series without the wind.
    """
    if not (math.isfinite(duration_h) and duration_h > 0):
        raise ValueError(f"duration_h must be a positive number of hours, got {duration_h}")
    if not (math.isfinite(alpha) and 0 < alpha <= 1):
        raise ValueError(f"alpha must be in (0, 1], got {alpha}")
    if (hs_limit_m is None) == (limit_table is None):
        raise ValueError("give exactly one of hs_limit_m and limit_table")
    if wind_limit_m_s is not None:
        if not (math.isfinite(wind_limit_m_s) and wind_limit_m_s > 0):
            raise ValueError(f"wind_limit_m_s must be a positive number of m/s, got {wind_limit_m_s}")
        if series.wind_m_s is None:
            raise ValueError("wind_limit_m_s needs the series' wind (its column wind_m_s)")
    if hs_limit_m is not None:
        design = np.full(series.t_h.size, float(hs_limit_m))
    else:
        tp, hs = limit_table
        nearest = np.abs(series.tp_s[:, None] - np.asarray(tp)[None, :]).argmin(axis=1)
        design = np.asarray(hs, dtype=float)[nearest]
    limit = alpha * design
    hs_ok = series.hs_m <= limit
    ok = hs_ok if wind_limit_m_s is None else hs_ok & (series.wind_m_s <= wind_limit_m_s)
    t0, step = series.t_h, series.step_h
    t1 = t0 + step
    windows, i, n = [], 0, ok.size
    while i < n:
        if ok[i]:
            j = i
            while j + 1 < n and ok[j + 1]:
                j += 1
            windows.append((float(t0[i]), float(t1[j])))
            i = j + 1
        else:
            i += 1
    # from each sample's time: the first time s >= t with [s, s + duration] workable. Within a
    # window (a, b) an operation can start at any s in [a, b - duration]
    # (the windows are in time order, so are their last start times: the first window whose
    # last start is not before t is found by bisection)
    fits = [(a, b - duration_h) for a, b in windows if b - a >= duration_h - 1e-12]
    first = np.array([a for a, _ in fits])
    last = np.array([e for _, e in fits])
    k = np.searchsorted(last, t0 - 1e-12, side="left")
    found = k < last.size
    wait = np.full(n, np.nan)
    wait[found] = np.maximum(first[k[found]], t0[found]) - t0[found]
    can = np.isfinite(wait)
    mean = float(wait[can].mean()) if can.any() else float("nan")
    return Windows(workable=ok, hs_workable=hs_ok, limit_m=limit, windows=windows, wait_h=wait,
                   duration_h=float(duration_h), alpha=float(alpha), mean_wait_h=mean, can_start=float(can.mean()),
                   workable_share=float(np.sum(step * ok) / np.sum(step)),
                   hs_workable_share=float(np.sum(step * hs_ok) / np.sum(step)),
                   wind_limit_m_s=None if wind_limit_m_s is None else float(wind_limit_m_s))
