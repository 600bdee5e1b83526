"""In which sea states can the robot work? Operability over a scatter diagram.

Each cell of a scatter diagram (Hs x Tp, with its probability) and each wave heading
is one sea state. For each, the scenario's trajectory is planned over a long record of
that sea (the scenario's ``[base_motion]`` must be a ``sea_state``: its RAOs,
spectrum and spreading are kept, Hs, Tp, heading and seed are the cell's). A cell is
workable when tensions exist within the limits tightened by the margin the user asks
for (T_min + margin, T_max - margin) at every step. Cells are independent: they run on any
:class:`~marinecdpr.studies.executor.Executor` (serially, on a local Dask cluster or on a
scheduler) with the same results either way (each cell's seed is a function of the
template's seed and of the sea state, :func:`sea_state_seed`, so a cell's verdict does not
depend on the other cells asked for); :meth:`Executor.auto
<marinecdpr.studies.executor.Executor.auto>` picks serial for small studies and when Dask
is not installed, by :func:`study_steps`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, NoReturn

import numpy as np

from marinecdpr.errors import ScenarioError
from marinecdpr.planning.planner import iter_plan
from marinecdpr.scenario.schema import Scenario, SeaStateMotion
from marinecdpr.studies.executor import Executor
from marinecdpr.textfiles import MAX_FIELD_CHARS, long_field, read_csv_records

__all__ = ["ScatterDiagram", "read_scatter_csv", "illustrative_scatter_path", "scatter_path", "BUILTIN_SCATTERS",
           "tz_conversion_gamma", "Cell", "CellResult", "Operability", "cell_wind", "wind_scenario", "check_sea_wind",
           "gust_seed", "cell_winds", "WIND_COLUMNS",
           "evaluate_cell", "operability", "with_margin", "sea_state_seed", "scatter_cells", "summarise",
           "wilson_interval", "REALISATIONS", "study_steps", "CLOSED_LOOP_STEP_COST", "HS_RANGE_M", "TP_RANGE_S"]

HS_RANGE_M = (0.0, 30.0)
"""A scatter diagram's Hs must lie in (0, 30] m."""
TP_RANGE_S = (1.0, 30.0)
"""A scatter diagram's Tp must lie in [1, 30] s."""
PROBABILITY_SUM_TOL = 1e-3
"""A scatter diagram's probabilities must sum to 1 within this."""
PROBABILITY_MAX = 1000.0
"""A scatter diagram's cell above this is refused at once, as no probability (a cell of a
table in per mille reaches 1000; such a table is then named by its sum)."""


@dataclass(frozen=True)
class ScatterDiagram:
    """Sea-state probabilities.

    Attributes
    ----------
    hs : ndarray, shape (n_hs,)
        Significant wave heights, m, increasing.
    tp : ndarray, shape (n_tp,)
        Peak periods, s, increasing.
    probability : ndarray, shape (n_hs, n_tp)
        Probability of each cell (zero where the pair does not occur); sums to 1.
    """

    hs: np.ndarray
    tp: np.ndarray
    probability: np.ndarray
    wind_m_s: np.ndarray | None = None
    """(n_hs, n_tp): each cell's mean wind speed at the wind's reference height, m/s (the
    column ``wind_m_s``; NaN where no cell), None without that column."""
    wind_misalignment_deg: np.ndarray | None = None
    """(n_hs, n_tp): where each cell's wind comes from less where its waves come from, deg
    (the column ``wind_misalignment_deg``; ``[wind] misalignment_deg``), None without it."""


WIND_COLUMNS = {"wind_m_s": (0.0, 70.0, "m/s", "above 0 and at most 70 m/s (a mean wind)"),
                "wind_misalignment_deg": (-360.0, 360.0, "deg", "within -360 to 360 deg (one turn either way)")}
"""A scatter diagram's optional columns after ``probability``: the wind in each sea state
(``[wind] with_sea = "scatter"``), their ranges and words."""


BUILTIN_SCATTERS = {"illustrative": "scatter_illustrative.csv", "north_atlantic": "scatter_north_atlantic.csv"}
"""The package's scatter diagrams by name (``data/<file>``): ``illustrative`` (a North-Sea-like
diagram, the sea-state studies' default) and ``north_atlantic`` (IACS Rec. 34's North
Atlantic table, Hs against Tz, as published; its source is named in the file)."""


def illustrative_scatter_path() -> Path:
    """The package's illustrative scatter diagram (``data/scatter_illustrative.csv``): the
    sea-state studies' default."""
    return scatter_path("illustrative")


def scatter_path(name_or_path: str | Path | None, folder: str | Path | None = None) -> Path:
    """A scatter diagram's file: the package's by its name (:data:`BUILTIN_SCATTERS`), the
    illustrative one for None, else the path itself (relative to ``folder`` where given)."""
    from importlib import resources

    if name_or_path is None:
        name_or_path = "illustrative"
    if str(name_or_path) in BUILTIN_SCATTERS:
        return Path(str(resources.files("marinecdpr") / "data" / BUILTIN_SCATTERS[str(name_or_path)]))
    return Path(folder) / name_or_path if folder is not None else Path(name_or_path)


def tz_conversion_gamma(template: Scenario) -> float:
    """The JONSWAP peak enhancement at which a scatter diagram in Tz (``tz_s``) becomes Tp for
    this template's sea: its ``gamma`` where given; 1 (Pierson-Moskowitz) for a
    ``pierson_moskowitz`` spectrum and for a JONSWAP one without ``gamma``. In the last
    case the sea is synthesised with DNV-RP-C205's gamma from Tp / sqrt(Hs), which is also 1
    wherever Tp / sqrt(Hs) >= 5 (at Tp = 1.4049 Tz: Tz >= 3.56 sqrt(Hs)); in steeper cells
    the record's own Tz is up to 13 % (gamma = 5) above the diagram's."""
    sea = template.base_motion
    if isinstance(sea, SeaStateMotion) and sea.spectrum == "jonswap" and sea.gamma is not None:
        return float(sea.gamma)
    return 1.0


def read_scatter_csv(path: str | Path, *, gamma: float = 1.0) -> ScatterDiagram:
    """Read a scatter diagram: CSV with header ``hs_m,tp_s,probability`` (or
    ``hs_m,tz_s,probability``), one row per cell; lines starting with ``#`` are comments.
    Optional columns after ``probability``, in any order, give each sea state's wind
    (:data:`WIND_COLUMNS`; ``[wind] with_sea = "scatter"``): ``wind_m_s``, the mean speed at
    the wind's reference height (m/s, > 0), and ``wind_misalignment_deg``, where the wind
    comes from less where the waves come from (deg).

    Read through :func:`marinecdpr.textfiles.read_lines` (a regular UTF-8 text file of at
    most 256 MiB, no field over 100 characters). Probabilities must be finite,
    non-negative and sum to 1 within 1e-3 (they are then rescaled to sum to 1 exactly);
    pairs left out have probability 0. Hs must lie in
    0 < Hs <= 30 m and Tp in 1 s <= Tp <= 30 s. A UTF-8 byte-order mark and CRLF line
    ends (what spreadsheets write) are accepted.

    A diagram in zero-up-crossing periods (``tz_s``, as published tables are) is turned
    into peak periods at the JONSWAP peak enhancement ``gamma``:
    Tp = Tz / (Tz/Tp)(gamma), DNV-RP-C205's fit
    (:func:`~marinecdpr.motion.seastate.dnv_tz_over_tp`; gamma = 1: Tp = 1.4049 Tz); the
    Tp so found must lie in 1 s <= Tp <= 30 s.

    Parameters
    ----------
    path : str or Path
        The CSV file.
    gamma : float
        With a ``tz_s`` file: the peak enhancement of the seas it is used in, 1 to 7
        (:func:`tz_conversion_gamma` gives a template's). Unused with ``tp_s``.

    Raises
    ------
    ScenarioError
        One line naming the file, the row (and column) and the problem; a sum near 100
        or 1000 is named as percent or per mille.
    """
    from marinecdpr.motion.seastate import dnv_tz_over_tp

    path = Path(path)
    src = str(path)
    what = "a scatter diagram CSV file (hs_m,tp_s,probability or hs_m,tz_s,probability)"

    def fail(message: str) -> NoReturn:
        raise ScenarioError(message, source=src)

    rows = read_csv_records(path, fail, what, word="row", comments=True)
    if (long := long_field(rows)) is not None:
        fail(f"row {long[0] + 1}, field {long[1] + 1}: over {MAX_FIELD_CHARS} characters; expected {what}")
    head = next((i for i, row in enumerate(rows) if row and "".join(row).strip()), None)
    header = [h.strip() for h in rows[head]] if head is not None else []
    extra = header[3:]
    if header[:3] not in (["hs_m", "tp_s", "probability"], ["hs_m", "tz_s", "probability"]) or \
            any(h not in WIND_COLUMNS for h in extra) or len(set(extra)) != len(extra):
        raise ScenarioError("the header must be hs_m,tp_s,probability or hs_m,tz_s,probability, optionally "
                            "followed by wind_m_s and wind_misalignment_deg (each once)", source=src,
                            key=f"row {1 if head is None else head + 1}")
    winds: dict[str, dict[tuple[float, float], float]] = {h: {} for h in extra}
    in_tz = header[1] == "tz_s"
    if in_tz:
        try:
            ratio = dnv_tz_over_tp(gamma)
        except ValueError as exc:
            raise ScenarioError(f"tz_s becomes Tp only at a JONSWAP gamma within 1 to 7: {exc}", source=src) from None
    cells: dict[tuple[float, float], float] = {}
    for i, row in enumerate(rows[head + 1:], start=head + 2):
        if not row or not "".join(row).strip():
            continue
        if len(row) != len(header):
            raise ScenarioError(f"expected {len(header)} values, got {len(row)}", source=src, key=f"row {i}")
        try:
            hs, tp, p = (float(x) for x in row[:3])
            wind = [float(x) for x in row[3:]]
        except ValueError:
            raise ScenarioError(f"not numbers: {','.join(row)}", source=src, key=f"row {i}") from None
        (hs_lo, hs_hi), (tp_lo, tp_hi) = HS_RANGE_M, TP_RANGE_S
        if not hs_lo < hs <= hs_hi:   # False for NaN too
            raise ScenarioError(f"hs_m and {header[1]} must be positive and physical: hs_m = {row[0].strip()} "
                                f"(column 1) is outside {hs_lo:g} < Hs <= {hs_hi:g} m", source=src, key=f"row {i}")
        if in_tz:
            tz, tp = tp, tp / ratio   # NaN stays NaN and is refused below
            if not tp_lo <= tp <= tp_hi:
                raise ScenarioError(f"hs_m and tz_s must be positive and physical: tz_s = {row[1].strip()} "
                                    f"(column 2) gives Tp = {tp:.4g} s at gamma = {gamma:g} (Tp = "
                                    f"{1.0 / ratio:.5g} Tz), outside {tp_lo:g} s <= Tp <= {tp_hi:g} s", source=src,
                                    key=f"row {i}")
        elif not tp_lo <= tp <= tp_hi:
            raise ScenarioError(f"hs_m and tp_s must be positive and physical: tp_s = {row[1].strip()} "
                                f"(column 2) is outside {tp_lo:g} s <= Tp <= {tp_hi:g} s", source=src,
                                key=f"row {i}")
        if not (math.isfinite(p) and p >= 0):
            raise ScenarioError(f"probability = {row[2].strip()} (column 3) must be finite and non-negative",
                                source=src, key=f"row {i}")
        if p > PROBABILITY_MAX:  # not even per mille (and their sum stays finite)
            raise ScenarioError(f"probability = {row[2].strip()} (column 3) is not a probability (at most 1)",
                                source=src, key=f"row {i}")
        if (hs, tp) in cells:
            period = f"Tz {tz:g} s" if in_tz else f"Tp {tp:g} s"
            raise ScenarioError(f"Hs {hs:g} m, {period} appears twice", source=src, key=f"row {i}")
        for col, (name, v) in enumerate(zip(extra, wind), start=4):
            lo, hi, _, words = WIND_COLUMNS[name]
            if not (lo < v <= hi if name == "wind_m_s" else lo <= v <= hi):   # False for NaN too
                raise ScenarioError(f"{name} = {row[col - 1].strip()} (column {col}) must be {words}", source=src,
                                    key=f"row {i}")
            winds[name][(hs, tp)] = v
        cells[(hs, tp)] = p
    total = math.fsum(cells.values())
    if not cells or total <= 0:
        raise ScenarioError("no cell with a positive probability", source=src)
    if abs(total - 1.0) > PROBABILITY_SUM_TOL:
        hint = ""
        if abs(total - 100.0) <= 1.0:
            hint = "; they look like percent: divide them by 100"
        elif abs(total - 1000.0) <= 10.0:
            hint = "; they look like per mille: divide them by 1000"
        raise ScenarioError(f"the probabilities (column 3) sum to {total:.6g}, not 1 (within "
                            f"{PROBABILITY_SUM_TOL:g}){hint}", source=src)
    hs_v = np.array(sorted({k[0] for k in cells}))
    tp_v = np.array(sorted({k[1] for k in cells}))
    prob = np.zeros((hs_v.size, tp_v.size))
    for (hs, tp), p in cells.items():
        prob[np.searchsorted(hs_v, hs), np.searchsorted(tp_v, tp)] = p
    columns = {}
    for name, values in winds.items():
        grid = np.full(prob.shape, np.nan)
        for (hs, tp), v in values.items():
            grid[np.searchsorted(hs_v, hs), np.searchsorted(tp_v, tp)] = v
        columns[name] = grid
    return ScatterDiagram(hs_v, tp_v, prob / total, **columns)


@dataclass(frozen=True)
class Cell:
    """One sea state to evaluate."""

    index: int
    hs: float
    tp: float
    heading_deg: float
    probability: float
    wind_m_s: float | None = None
    """The scatter diagram's wind in this sea state (its ``wind_m_s``), m/s; None without it."""
    wind_misalignment_deg: float | None = None
    """Its ``wind_misalignment_deg``, deg; None without it."""


@dataclass(frozen=True)
class CellResult:
    """The verdict on one sea state, over its independent realisations (records)."""

    cell: Cell
    operable: bool
    """Workable in every realisation."""
    fraction_feasible: float
    """Share of the records' steps with feasible tensions (with a workspace grid: share of
    the frame's poses feasible throughout), averaged over the realisations."""
    min_margin_N: float
    """The sea state's smallest headroom over the records: at each step the largest
    distance to the cables' (untightened) limits that any tensions producing the wrench
    could keep (:func:`~marinecdpr.model.tension.largest_headroom`), the smallest over
    the steps, N: the largest ``margin`` the sea state allows (negative: by how much
    even the limits themselves are broken; -inf at a singular pose). A record is
    workable with margin M only where this is at least M. NaN with a workspace grid."""
    n_steps: int
    """Steps of one record."""
    max_error_m: float = float("nan")
    """Largest closed-loop position error (own plant) when asked for, m."""
    realisations: int = 1
    successes: int = 0
    """Realisations in which the operation succeeded."""
    controller_bypassed: int = 0
    """Realisations whose closed loop (``max_error_m``) had its controller bypassed on more
    than ``[simulation] max_bypassed_share`` of its steps: failures, whatever their error
    (:func:`~marinecdpr.studies.prototype_runs.controller_verdict`)."""

    @property
    def success_probability(self) -> float:
        """The share of realisations that succeeded: the estimate of the probability."""
        return self.successes / self.realisations

    @property
    def interval(self) -> tuple[float, float]:
        """95 % confidence interval of the probability of success (Wilson)."""
        return wilson_interval(self.successes, self.realisations)


CONFIDENCE_Z = 1.959964
"""The normal quantile of the 95 % confidence intervals."""
REALISATIONS = 10
"""Independent records per sea state by default."""


def wilson_interval(successes: int, n: int, z: float = CONFIDENCE_Z) -> tuple[float, float]:
    """Wilson's score interval for a binomial probability from ``successes`` of ``n``."""
    if n <= 0:
        return 0.0, 1.0
    p = successes / n
    denom = 1.0 + z * z / n
    centre = (p + z * z / (2 * n)) / denom
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / denom
    # all or none: the bound at 0 or 1 is exact (not 0.9999999999999999)
    return (0.0 if successes == 0 else max(0.0, centre - half)), (1.0 if successes == n else min(1.0, centre + half))


def check_sea_state(template: Scenario) -> None:
    """Refuse a template whose ship does not move in a sea state (operability varies its sea)."""
    if not isinstance(template.base_motion, SeaStateMotion):
        raise ScenarioError("operability needs a [base_motion] of type sea_state (its RAOs, spectrum "
                            "and spreading are used in every cell)", key="base_motion.type")


def sea_state_seed(seed: int, hs: float, tp: float, heading_deg: float, realisation: int = 0) -> int:
    """The seed of a sea state's record: a function of the template's ``seed``, of the sea
    state itself (Hs, Tp and heading, to 1e-6) and of the realisation's number, never of
    its place in a study, so a sea state gets the same records whichever other sea states
    are asked for and in whatever order."""
    key = [int(seed), round(hs * 1e6), round(tp * 1e6), round((heading_deg % 360.0) * 1e6), int(realisation)]
    return int(np.random.SeedSequence(key).generate_state(1, np.uint32)[0])


GUST_STREAM = 1
"""What tells a record's gust seed from its sea's (:func:`gust_seed`)."""


def gust_seed(seed: int, hs: float, tp: float, heading_deg: float, realisation: int = 0) -> int:
    """The gust's seed in a sea state's record where the wind follows the sea: like
    :func:`sea_state_seed` from ``[wind] seed`` and the sea state, on a stream of its own
    (:data:`GUST_STREAM`), so that the gust's phases are not the sea's even where both seeds
    are equal."""
    key = [sea_state_seed(seed, hs, tp, heading_deg, realisation), GUST_STREAM]
    return int(np.random.SeedSequence(key).generate_state(1, np.uint32)[0])


def cell_wind(template: Scenario, cell: Cell) -> tuple[float, float] | None:
    """The wind in one cell's sea state where the template's follows the sea (``[wind]
    with_sea``): its mean speed at the reference height (m/s) and where it comes from in O
    (deg), :func:`~marinecdpr.scenario.wind.sea_wind`; None where the wind (if any) does not
    follow the sea.

    Raises
    ------
    ScenarioError
        ``with_sea = "scatter"`` and the cell has no ``wind_m_s`` (the scatter diagram lacks
        the column); a misalignment both in ``[wind]`` and in the diagram.
    """
    from marinecdpr.scenario.wind import sea_wind

    wind = template.wind
    if wind is None or wind.with_sea == "none":
        return None
    if wind.with_sea == "scatter" and cell.wind_m_s is None:
        raise ScenarioError("with_sea = \"scatter\" takes each sea state's wind from the scatter diagram's "
                            "wind_m_s column, which this diagram does not have (add it, or use with_sea = "
                            "\"pierson_moskowitz\")", key="wind.with_sea")
    if cell.wind_misalignment_deg is not None and wind.misalignment_deg != 0.0:
        raise ScenarioError("the misalignment is given twice: in [wind] misalignment_deg and in the scatter "
                            "diagram's wind_misalignment_deg column: keep one", key="wind.misalignment_deg")
    return sea_wind(wind, hs_m=cell.hs, heading_deg=cell.heading_deg,
                    gravity_m_s2=template.environment.gravity_m_s2,
                    speed_m_s=cell.wind_m_s if wind.with_sea == "scatter" else None,
                    misalignment_deg=cell.wind_misalignment_deg)


def check_sea_wind(template: Scenario, scatter: ScatterDiagram) -> None:
    """Refuse, before any work, a scatter diagram the template's wind cannot follow: with
    ``[wind] with_sea = "scatter"`` and no ``wind_m_s`` column, or a misalignment both in
    ``[wind]`` and in the diagram (:func:`cell_wind`'s one-line errors)."""
    cells = scatter_cells(scatter, (0.0,))
    if cells:
        cell_wind(template, cells[0])


def cell_winds(template: Scenario, cells: list[Cell]) -> np.ndarray | None:
    """Each cell's wind (:func:`cell_wind`), shape (n_cells, 2): the speed at the reference
    height (m/s) and where it comes from in O (deg); None where the template's wind (if any)
    does not follow the sea. What the studies' files say beside each sea state."""
    if template.wind is None or template.wind.with_sea == "none":
        return None
    return np.array([cell_wind(template, c) for c in cells], dtype=float).reshape(-1, 2)


def cell_scenario(template: Scenario, cell: Cell, duration_s: float, step_s: float,
                  realisation: int = 0) -> Scenario:
    """The template in one cell's sea state (its ``realisation``-th record), over
    ``duration_s`` at ``step_s``; a wind that follows the sea (``[wind] with_sea``) takes the
    cell's (:func:`cell_wind`: the scatter's ``wind_m_s``, or the relation at the cell's Hs,
    from the cell's heading), and its gust phases of its own (:func:`gust_seed`): each record
    meets its own gust, independent of its sea's."""
    check_sea_state(template)
    sea = template.base_motion
    changes = {}
    if cell_wind(template, cell) is not None:  # the scenario's validation sets it from the cell's sea
        wind = template.wind.model_dump(exclude_none=True)
        wind["seed"] = gust_seed(template.wind.seed, cell.hs, cell.tp, cell.heading_deg, realisation)
        if template.wind.with_sea == "scatter":
            wind["speed_m_s"] = cell.wind_m_s
        if cell.wind_misalignment_deg is not None:
            wind["misalignment_deg"] = cell.wind_misalignment_deg
        changes["wind"] = wind
    return template.with_changes(
        base_motion=sea.model_copy(update={
            "hs_m": cell.hs, "tp_s": cell.tp, "heading_deg": cell.heading_deg,
            "seed": sea_state_seed(sea.seed, cell.hs, cell.tp, cell.heading_deg, realisation),
            "record_s": max(sea.record_s, duration_s)}),
        time={"step_s": step_s, "duration_s": duration_s},
        **changes,
    )


def wind_scenario(template: Scenario, wind: tuple[float, float]) -> Scenario:
    """The template with its wind fixed at ``wind`` = (speed at the reference height, m/s;
    where it comes from in O, deg), following no sea (``with_sea = "none"``): one of
    :func:`cell_wind`'s winds, for a study that judges many sea states at once."""
    data = template.wind.model_dump(exclude_none=True)
    data.pop("with_sea", None)
    data.pop("misalignment_deg", None)
    data.update(speed_m_s=float(wind[0]), direction_deg=float(wind[1]))
    return template.with_changes(wind=data)


def with_margin(scenario: Scenario, margin_N: float) -> Scenario:
    """The scenario with every cable's tension limits tightened by ``margin_N``."""
    if margin_N <= 0:
        return scenario
    lo, hi = scenario.robot.tension_min, scenario.robot.tension_max
    if np.any(hi - lo <= 2 * margin_N):
        raise ScenarioError(f"a {margin_N:g} N margin leaves no room between the tension limits",
                            key="margin")
    robot = scenario.robot.model_dump(exclude_none=True)
    robot.pop("tension_min_N", None)
    robot.pop("tension_max_N", None)
    for cable, a, b in zip(robot["cables"], lo, hi):
        cable.update(tension_min_N=float(a + margin_N), tension_max_N=float(b - margin_N))
    return scenario.with_changes(robot=robot)


def evaluate_cell(template: Scenario, cell: Cell, *, margin_N: float, duration_s: float,
                  step_s: float, max_error_m: float | None = None,
                  workspace: tuple[int, int] | None = None, min_area: float = 1.0,
                  realisations: int = 1) -> CellResult:
    """Plan the template's trajectory (or hold a workspace grid) over ``realisations``
    independent records of one sea state and judge each.

    A record is workable if tensions exist within the limits tightened by ``margin_N``
    at every step (the plan is made with those tightened limits) and, if
    ``max_error_m`` is given, the closed loop flown on the own plant keeps the platform
    within that distance of its plan with its controller not bypassed (on at most
    ``[simulation] max_bypassed_share`` of the steps). With ``workspace = (n_u, n_v)`` the trajectory is
    replaced by a grid of held poses over the frame (:func:`~marinecdpr.studies.workspace.workspace_map`),
    and a record is workable if at least ``min_area`` of the poses inside the frame stay
    feasible throughout; ``fraction_feasible`` is then that share of poses. The records
    last ``duration_s``, the operation's duration: the longer, the likelier a limit is met.
    """
    if realisations < 1:
        raise ValueError(f"realisations must be at least 1, got {realisations}")
    runs = [_evaluate_record(cell_scenario(template, cell, duration_s, step_s, r), margin_N=margin_N,
                             max_error_m=max_error_m, workspace=workspace, min_area=min_area)
            for r in range(realisations)]
    ok = [run[0] for run in runs]
    errors = np.array([run[4] for run in runs])
    error = float("nan") if np.isnan(errors).all() else float(np.nanmax(errors))
    return CellResult(cell=cell, operable=all(ok), fraction_feasible=float(np.mean([run[1] for run in runs])),
                      min_margin_N=min(run[2] for run in runs),
                      n_steps=runs[0][3], max_error_m=error, realisations=realisations, successes=int(sum(ok)),
                      controller_bypassed=int(sum(run[5] for run in runs)))


def _evaluate_record(sc: Scenario, *, margin_N: float, max_error_m: float | None,
                     workspace: tuple[int, int] | None, min_area: float) -> tuple[bool, float, float, int, float, bool]:
    """One record of :func:`evaluate_cell`: (workable, fraction feasible, smallest margin,
    steps, largest closed-loop error, the closed loop's controller bypassed)."""
    tight = with_margin(sc, margin_N)
    if workspace is not None:
        from marinecdpr.studies.workspace import workspace_map

        ws = workspace_map(tight, n=workspace)
        inside = np.isfinite(ws.fraction_feasible)
        area = float((ws.fraction_feasible[inside] == 1.0).mean()) if inside.any() else 0.0
        return area >= min_area, area, float("nan"), ws.n_steps, float("nan"), False
    ok, worst, n = 0, np.inf, 0
    for piece in iter_plan(tight, headroom=True):
        ok += int(piece.feasible.sum())
        n += piece.n_steps
        # the headroom to the tightened limits, plus the margin: to the cables' own limits
        h = piece.tension_headroom + margin_N if margin_N > 0 else piece.tension_headroom
        worst = min(worst, float(np.min(h)) if not np.isnan(h).any() else -np.inf)
    operable = ok == n
    error, bypassed = float("nan"), False
    if max_error_m is not None and operable:
        from marinecdpr.prototype.simulation import simulate
        from marinecdpr.studies.prototype_runs import controller_verdict

        try:
            res = simulate(tight, run="closed_loop", plant="own")
            error = float(np.abs(res.pose_error[:, :3]).max())
            bypassed = controller_verdict(res, tight)["controller_verdict"] == "bypassed"
        except ArithmeticError:  # diverged
            error = float("inf")
        operable = error <= max_error_m and not bypassed
    return bool(operable), ok / n, worst, n, error, bypassed


@dataclass(frozen=True)
class Operability:
    """Operability over a scatter diagram and headings.

    Attributes
    ----------
    scatter : ScatterDiagram
    headings_deg : tuple of float
    results : list of CellResult
        One per cell with a positive probability and heading.
    operability : float
        Probability that the operation succeeds in a sea state drawn from the diagram, in
        [0, 1], headings equally likely: the cells' probabilities of success (the share of
        their realisations that succeeded) weighted by the cells' probabilities.
    per_heading : dict
        Heading (deg) -> operability in that heading.
    limiting_hs : dict
        Heading -> array (n_tp,) of the largest Hs up to which every cell of that Tp is
        workable in every realisation: 0 if even the smallest fails; ``inf`` if every cell
        of that Tp is workable ("none within the diagram": the limit, if any, lies above
        the diagram's largest Hs); NaN where the Tp column has no sea state.
    margin_N : float
    executor : str
        What ran the cells: "serial" or "dask".
    interval : tuple of float
        95 % confidence interval of ``operability`` (normal approximation over the cells,
        each cell's variance from its Agresti-Coull estimate, so a cell whose realisations
        all agree still counts).
    per_heading_interval : dict
        Heading -> the interval of its operability.
    """

    scatter: ScatterDiagram
    headings_deg: tuple[float, ...]
    results: list
    operability: float
    per_heading: dict
    limiting_hs: dict
    margin_N: float
    executor: str = "serial"
    interval: tuple = (0.0, 1.0)
    per_heading_interval: dict | None = None

    def operable_grid(self, heading_deg: float) -> np.ndarray:
        """(n_hs, n_tp): 1 workable in every realisation, 0 not, NaN no such sea state."""
        return self._grid(heading_deg, lambda r: float(r.operable))

    def probability_grid(self, heading_deg: float) -> np.ndarray:
        """(n_hs, n_tp): each sea state's probability of success, NaN no such sea state."""
        return self._grid(heading_deg, lambda r: r.success_probability)

    def _grid(self, heading_deg: float, value) -> np.ndarray:
        grid = np.full(self.scatter.probability.shape, np.nan)
        for r in self.results:
            if r.cell.heading_deg == heading_deg:
                i = np.searchsorted(self.scatter.hs, r.cell.hs)
                j = np.searchsorted(self.scatter.tp, r.cell.tp)
                grid[i, j] = value(r)
        return grid

    def limiting_hs_json(self) -> dict:
        """``limiting_hs`` for a JSON file: heading -> Tp -> Hs, m, or None.

        None means "none within the diagram": every sea state of that Tp (and heading) is
        workable, so no Hs of the diagram limits the work. 0 means not even the smallest
        Hs of that Tp is workable. A Tp without sea states is left out. Keys are the
        heading and Tp written with ``:g``.
        """
        return {f"{h:g}": {f"{tp:g}": (None if np.isinf(v) else float(v))
                           for tp, v in zip(self.scatter.tp, lim) if not np.isnan(v)}
                for h, lim in self.limiting_hs.items()}


LIMITING_HS_MEANING = ("largest Hs (m) up to which every sea state of that heading and Tp is workable; "
                       "0: not even the smallest; null: none within the diagram (every sea state of "
                       "that Tp is workable); a Tp without sea states is left out")
"""What ``limiting_hs_m`` in operability.json means (written beside it)."""

CLOSED_LOOP_STEP_COST = 100
"""A closed-loop step (``max_error_m``) costs about this many planned steps (measured on
paper_sea, own plant at 50 Hz: 79 us against 0.6 us a step)."""


def study_steps(n_cells: int, *, duration_s: float, step_s: float,
                workspace: tuple[int, int] | None = None, max_error_m: float | None = None) -> int:
    """The work of a study in planned time steps, the measure
    :meth:`Executor.auto <marinecdpr.studies.executor.Executor.auto>` sizes by:
    cells x steps per record x poses of a workspace grid; with ``max_error_m`` each cell's
    closed-loop flight adds :data:`CLOSED_LOOP_STEP_COST` per step of its record."""
    steps = int(math.floor(duration_s / step_s + 1e-9)) + 1 if step_s > 0 else 1   # as Time.n_steps
    poses = workspace[0] * workspace[1] if workspace is not None else 1
    return int(n_cells) * steps * poses * (1 + (CLOSED_LOOP_STEP_COST if max_error_m is not None else 0))


def scatter_cells(scatter: ScatterDiagram, headings: tuple[float, ...]) -> list[Cell]:
    """One :class:`Cell` per heading and sea state of positive probability (with the
    diagram's wind in it, where it has one)."""
    cells = []
    for heading in headings:
        for i, hs in enumerate(scatter.hs):
            for j, tp in enumerate(scatter.tp):
                if scatter.probability[i, j] > 0:
                    wind = {name: float(grid[i, j]) for name, grid in (
                        ("wind_m_s", scatter.wind_m_s), ("wind_misalignment_deg", scatter.wind_misalignment_deg))
                        if grid is not None}
                    cells.append(Cell(index=len(cells), hs=float(hs), tp=float(tp), heading_deg=float(heading),
                                      probability=float(scatter.probability[i, j]), **wind))
    return cells


def operability(
    template: Scenario,
    scatter: ScatterDiagram,
    *,
    headings_deg: tuple[float, ...] = (180.0,),
    margin_N: float = 0.0,
    duration_s: float = 1200.0,
    step_s: float = 0.02,
    executor: Executor | None = None,
    max_error_m: float | None = None,
    workspace: tuple[int, int] | None = None,
    min_area: float = 1.0,
    realisations: int = REALISATIONS,
    progress: Callable[[int, int], None] | None = None,
) -> Operability:
    """Decide, cell by cell, how likely the robot can work, and sum up.

    Parameters
    ----------
    template : Scenario
        Robot, trajectory, tension method, and a ``sea_state`` base motion whose RAOs,
        spectrum and spreading every cell uses.
    scatter : ScatterDiagram
    headings_deg : tuple of float
        Wave headings to consider, equally likely, deg.
    margin_N : float
        Tension margin to the limits a workable sea state keeps at every step, N.
    duration_s, step_s : float
        The operation's duration, the length of each record (default 20 min), and its
        sampling (50 Hz).
    executor : Executor, optional
        What runs the cells (:class:`~marinecdpr.studies.executor.Executor`; default
        serial). ``Executor.auto(study_steps(...))`` is what the ``marinecdpr
        operability`` command uses: serial when Dask is not installed or the study is
        small. A local cluster starts worker processes, which a script must guard with
        ``if __name__ == "__main__":``. Results are identical whichever runs.
    max_error_m : float, optional
        Also fly the closed loop (own plant) in each cell and require its position error
        to stay within this, m.
    workspace : tuple of two int, optional
        Judge a grid of held poses over the frame (this many points along x and z, or
        the robot's first two axes) instead of the trajectory.
    min_area : float
        With ``workspace``: the share of the frame's poses that must stay feasible, 0..1.
    realisations : int
        Independent records per sea state (each seeded from the sea state and its number,
        :func:`sea_state_seed`); the probability of success is the share that succeed.
    progress : callable(done, total), optional
    """
    check_sea_state(template)
    headings = tuple(float(h) for h in headings_deg)
    cells = scatter_cells(scatter, headings)
    kwargs = dict(margin_N=margin_N, duration_s=duration_s, step_s=step_s, max_error_m=max_error_m,
                  workspace=workspace, min_area=min_area, realisations=realisations)
    executor = executor or Executor.serial()
    results = executor.map(evaluate_cell, template, cells, kwargs, progress=progress)
    return summarise(scatter, headings, results, margin_N, executor.name)


def summarise(scatter: ScatterDiagram, headings: tuple[float, ...], results: list, margin_N: float,
              executor: str = "serial") -> Operability:
    """The study's :class:`Operability` from per-cell results (anything with ``cell``,
    ``operable``, ``successes`` and ``realisations``): the probability of success per
    heading and overall with their intervals, and the limiting Hs."""
    per_heading, limiting, intervals, variances = {}, {}, {}, {}
    for h in headings:
        rs = [r for r in results if r.cell.heading_deg == h]
        # the share of the heading's probability, summed exactly: 1 when every realisation of
        # every cell succeeds, 0 when none does (not 0.9999999999999999)
        total = math.fsum(r.cell.probability for r in rs)
        per_heading[h] = (math.fsum(r.cell.probability * r.successes / r.realisations for r in rs) / total
                          if total > 0 else 0.0)
        variances[h] = (math.fsum((r.cell.probability / total) ** 2 * _cell_variance(r) for r in rs)
                        if total > 0 else 0.0)
        intervals[h] = _normal_interval(per_heading[h], variances[h])
        lim = np.full(scatter.tp.size, np.nan)
        for j, tp in enumerate(scatter.tp):
            col = sorted((r for r in rs if r.cell.tp == tp), key=lambda r: r.cell.hs)
            if not col:
                continue
            lim[j] = 0.0
            for r in col:
                if not r.operable:
                    break
                lim[j] = r.cell.hs
            else:
                lim[j] = np.inf   # every cell of the column workable: none within the diagram
        limiting[h] = lim
    k = len(headings)
    total = math.fsum(per_heading[h] for h in headings) / k
    interval = _normal_interval(total, math.fsum(variances[h] for h in headings) / (k * k))
    return Operability(scatter=scatter, headings_deg=headings, results=results, operability=total,
                       per_heading=per_heading, limiting_hs=limiting, margin_N=float(margin_N), executor=executor,
                       interval=interval, per_heading_interval=intervals)


def _cell_variance(r) -> float:
    """The variance of a cell's estimated probability of success, from the Agresti-Coull
    estimate (successes + 2) / (realisations + 4): not zero when every realisation agrees."""
    n = r.realisations
    p = (r.successes + 2.0) / (n + 4.0)
    return p * (1.0 - p) / n


def _normal_interval(p: float, variance: float) -> tuple[float, float]:
    half = CONFIDENCE_Z * math.sqrt(variance)
    return max(0.0, p - half), min(1.0, p + half)
