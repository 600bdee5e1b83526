"""In which sea states can the robot work? Operability over a scatter diagram.

Each cell of a scatter diagram (Hs x Tp, with its probability) and each wave heading
is one sea state. For each, the scenario's trajectory is planned over a long record of
that sea (the scenario's ``[base_motion]`` must be a ``sea_state``: its RAOs,
spectrum and spreading are kept, Hs, Tp, heading and seed are the cell's). A cell is
workable when tensions exist within the limits tightened by the margin the user asks
for (T_min + margin, T_max - margin) at every step. Cells are independent: they run serially or on Dask
(``dask.distributed``), with the same results either way (each cell's seed is the
template's seed plus the cell's index).
"""

from __future__ import annotations

import csv
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np

from .errors import ScenarioError
from .memory import keep_freed_memory
from .planning import iter_plan
from .scenario import Scenario, SeaStateMotion
from .workspace import tension_margin

__all__ = ["ScatterDiagram", "read_scatter_csv", "Cell", "CellResult", "Operability",
           "evaluate_cell", "operability", "with_margin"]


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


def read_scatter_csv(path: str | Path) -> ScatterDiagram:
    """Read a scatter diagram: CSV with header ``hs_m,tp_s,probability``, one row per cell.

    Probabilities (or counts) are normalised to sum to 1; pairs left out have probability 0.

    Raises
    ------
    ScenarioError
        One line naming the file, the row and the problem.
    """
    path = Path(path)
    src = str(path)
    try:
        rows = list(csv.reader(path.read_text(encoding="utf-8").splitlines()))
    except (OSError, UnicodeDecodeError) as exc:
        raise ScenarioError(f"cannot read the file ({exc})", source=src) from None
    if not rows or [h.strip() for h in rows[0]] != ["hs_m", "tp_s", "probability"]:
        raise ScenarioError("the header must be hs_m,tp_s,probability", source=src, key="row 1")
    cells: dict[tuple[float, float], float] = {}
    for i, row in enumerate(rows[1:], start=2):
        if not row or not "".join(row).strip():
            continue
        if len(row) != 3:
            raise ScenarioError(f"expected 3 values, got {len(row)}", source=src, key=f"row {i}")
        try:
            hs, tp, p = (float(x) for x in row)
        except ValueError:
            raise ScenarioError(f"not numbers: {','.join(row)}", source=src, key=f"row {i}") from None
        if not (np.isfinite([hs, tp, p]).all() and hs > 0 and tp > 0 and p >= 0):
            raise ScenarioError("hs_m and tp_s must be positive and probability non-negative",
                                source=src, key=f"row {i}")
        if (hs, tp) in cells:
            raise ScenarioError(f"Hs {hs:g} m, Tp {tp:g} s appears twice", source=src, key=f"row {i}")
        cells[(hs, tp)] = p
    if not cells or sum(cells.values()) <= 0:
        raise ScenarioError("no cell with a positive probability", source=src)
    hs_v = np.array(sorted({k[0] for k in cells}))
    tp_v = np.array(sorted({k[1] for k in cells}))
    prob = np.zeros((hs_v.size, tp_v.size))
    for (hs, tp), p in cells.items():
        prob[np.searchsorted(hs_v, hs), np.searchsorted(tp_v, tp)] = p
    return ScatterDiagram(hs_v, tp_v, prob / prob.sum())


@dataclass(frozen=True)
class Cell:
    """One sea state to evaluate."""

    index: int
    hs: float
    tp: float
    heading_deg: float
    probability: float


@dataclass(frozen=True)
class CellResult:
    """The verdict on one sea state."""

    cell: Cell
    operable: bool
    fraction_feasible: float
    """Share of the record's steps with feasible tensions (with a workspace grid: share of
    the frame's poses feasible throughout)."""
    min_margin_N: float
    """Smallest distance of a planned tension to the untightened limits over the record
    (at least the margin asked for; -inf if some step is infeasible)."""
    n_steps: int
    max_error_m: float = float("nan")
    """Largest closed-loop position error (own plant) when asked for, m."""


def _cell_scenario(template: Scenario, cell: Cell, duration_s: float, step_s: float) -> Scenario:
    sea = template.base_motion
    return template.with_changes(
        base_motion=sea.model_copy(update={
            "hs_m": cell.hs, "tp_s": cell.tp, "heading_deg": cell.heading_deg,
            "seed": sea.seed + cell.index, "record_s": max(sea.record_s, duration_s)}),
        time={"step_s": step_s, "duration_s": duration_s},
    )


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
                  workspace: tuple[int, int] | None = None, min_area: float = 1.0) -> CellResult:
    """Plan the template's trajectory (or hold a workspace grid) over one sea state and judge it.

    The cell is workable if tensions exist within the limits tightened by ``margin_N``
    at every step (the plan is made with those tightened limits) and, if
    ``max_error_m`` is given, the closed loop flown on the own plant keeps the platform
    within that distance of its plan. With ``workspace = (n_u, n_v)`` the trajectory is
    replaced by a grid of held poses over the frame (:func:`~marinecdpr.workspace.workspace_map`),
    and the cell is workable if at least ``min_area`` of the poses inside the frame stay
    feasible throughout; ``fraction_feasible`` is then that share of poses.
    """
    sc = _cell_scenario(template, cell, duration_s, step_s)
    lo, hi = sc.robot.tension_min, sc.robot.tension_max
    tight = with_margin(sc, margin_N)
    if workspace is not None:
        from .workspace import workspace_map

        ws = workspace_map(tight, n=workspace)
        inside = np.isfinite(ws.fraction_feasible)
        area = float((ws.fraction_feasible[inside] == 1.0).mean()) if inside.any() else 0.0
        return CellResult(cell, area >= min_area, area, float("nan"), ws.n_steps)
    ok, worst, n = 0, np.inf, 0
    for piece in iter_plan(tight):
        ok += int(piece.feasible.sum())
        n += piece.n_steps
        m = tension_margin(piece.tensions, lo, hi)
        if np.isfinite(m).any():
            worst = min(worst, float(np.nanmin(m)))
    # feasible tensions are within limits up to rounding: no negative zero margins
    worst = max(worst, 0.0) if ok == n else -np.inf
    operable = ok == n
    error = float("nan")
    if max_error_m is not None and operable:
        from .simulation import simulate

        try:
            res = simulate(tight, run="closed_loop", plant="own")
            error = float(np.abs(res.pose_error[:, :3]).max())
        except ArithmeticError:  # diverged
            error = float("inf")
        operable = error <= max_error_m
    return CellResult(cell, bool(operable), ok / n, worst, n, error)


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
        Probability of a workable sea state, in [0, 1], headings equally likely.
    per_heading : dict
        Heading (deg) -> operability in that heading.
    limiting_hs : dict
        Heading -> array (n_tp,) of the largest Hs up to which every cell of that Tp is
        workable (0 if even the smallest fails; NaN where the Tp column is empty).
    margin_N : float
    """

    scatter: ScatterDiagram
    headings_deg: tuple[float, ...]
    results: list
    operability: float
    per_heading: dict
    limiting_hs: dict
    margin_N: float

    def operable_grid(self, heading_deg: float) -> np.ndarray:
        """(n_hs, n_tp): 1 workable, 0 not, NaN no such sea state."""
        grid = np.full(self.scatter.probability.shape, np.nan)
        for r in self.results:
            if r.cell.heading_deg == heading_deg:
                i = np.searchsorted(self.scatter.hs, r.cell.hs)
                j = np.searchsorted(self.scatter.tp, r.cell.tp)
                grid[i, j] = float(r.operable)
        return grid


def _cells(scatter: ScatterDiagram, headings: tuple[float, ...]) -> list[Cell]:
    cells = []
    for heading in headings:
        for i, hs in enumerate(scatter.hs):
            for j, tp in enumerate(scatter.tp):
                if scatter.probability[i, j] > 0:
                    cells.append(Cell(len(cells), float(hs), float(tp), float(heading),
                                      float(scatter.probability[i, j])))
    return cells


def operability(
    template: Scenario,
    scatter: ScatterDiagram,
    *,
    headings_deg: tuple[float, ...] = (180.0,),
    margin_N: float = 0.0,
    duration_s: float = 1200.0,
    step_s: float = 0.02,
    executor: str = "serial",
    scheduler: str | None = None,
    workers: int = 2,
    max_error_m: float | None = None,
    workspace: tuple[int, int] | None = None,
    min_area: float = 1.0,
    progress: Callable[[int, int], None] | None = None,
) -> Operability:
    """Decide, cell by cell, whether the robot can work, and sum up.

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
        Length and sampling of each cell's record (default 20 min at 50 Hz).
    executor : {"serial", "dask"}
        ``dask``: on a local cluster of ``workers`` processes, or on ``scheduler``.
    scheduler : str, optional
        Address of a running Dask scheduler (e.g. "tcp://10.0.0.5:8786").
    max_error_m : float, optional
        Also fly the closed loop (own plant) in each cell and require its position error
        to stay within this, m.
    workspace : tuple of two int, optional
        Judge a grid of held poses over the frame (this many points along x and z, or
        the robot's first two axes) instead of the trajectory.
    min_area : float
        With ``workspace``: the share of the frame's poses that must stay feasible, 0..1.
    progress : callable(done, total), optional
    """
    if not isinstance(template.base_motion, SeaStateMotion):
        raise ScenarioError("operability needs a [base_motion] of type sea_state (its RAOs, spectrum "
                            "and spreading are used in every cell)", key="base_motion.type")
    headings = tuple(float(h) for h in headings_deg)
    cells = _cells(scatter, headings)
    kwargs = dict(margin_N=margin_N, duration_s=duration_s, step_s=step_s, max_error_m=max_error_m,
                  workspace=workspace, min_area=min_area)
    if executor == "serial":
        results = []
        for k, cell in enumerate(cells, start=1):
            results.append(evaluate_cell(template, cell, **kwargs))
            if progress is not None:
                progress(k, len(cells))
    elif executor == "dask":
        results = _on_dask(template, cells, kwargs, scheduler, workers, progress)
    else:
        raise ValueError(f"executor must be 'serial' or 'dask', not {executor!r}")
    results.sort(key=lambda r: r.cell.index)
    return _summarise(scatter, headings, results, margin_N)


def _on_dask(template, cells, kwargs, scheduler, workers, progress):
    try:
        from dask.distributed import Client, LocalCluster, as_completed
    except ImportError:
        raise ScenarioError("Dask is not installed: pip install 'marinecdpr[dask]'") from None
    cluster = None
    if scheduler:
        client = Client(scheduler, timeout="20s")
    else:
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                               dashboard_address=None)
        client = Client(cluster)
    try:
        # Dask's nanny starts workers with MALLOC_TRIM_THRESHOLD_=65536: every cell would
        # page-fault its memory back in; the workers keep it instead (see marinecdpr.memory)
        client.run(keep_freed_memory)
        scattered = client.scatter(template, broadcast=True)
        futures = [client.submit(evaluate_cell, scattered, cell, pure=False, **kwargs) for cell in cells]
        results = []
        for k, fut in enumerate(as_completed(futures), start=1):
            results.append(fut.result())
            if progress is not None:
                progress(k, len(cells))
        return results
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


def _summarise(scatter, headings, results, margin_N) -> Operability:
    per_heading, limiting = {}, {}
    for h in headings:
        rs = [r for r in results if r.cell.heading_deg == h]
        per_heading[h] = float(sum(r.cell.probability for r in rs if r.operable))
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
        limiting[h] = lim
    total = float(np.mean([per_heading[h] for h in headings]))
    return Operability(scatter, headings, results, total, per_heading, limiting, float(margin_N))
