"""Files a plan and its simulations produce: CSVs, figures like the paper's 5-7, a report.

Every file is written to a temporary name beside its target and renamed into
place when complete, so an interrupted run never leaves a half-written file; a
command writes all its files into a staging folder first (:class:`StagedOutput`), so
an output folder holds one complete run or the previous one, never a mixture.
"""

from __future__ import annotations

import os
import shutil
import signal
import sys
import tempfile
import threading
from contextlib import contextmanager
from pathlib import Path
from typing import Iterator

import numpy as np

from marinecdpr.errors import OutputError
from marinecdpr.planning.planner import TWIST_NAMES, Plan
from marinecdpr.scenario.schema import Scenario
from marinecdpr.textfiles import strip_control

__all__ = [
    "StagedOutput",
    "atomic_path",
    "plan_columns",
    "write_plan_csv",
    "plot_tensions",
    "decimate",
    "plan_csv_writer",
    "TensionEnvelope",
    "plot_tension_envelope",
    "write_plan_stream",
    "write_sim_csv",
    "plot_cable_lengths",
    "plot_tracking",
    "write_json",
    "write_report_html",
    "write_virtual_prototype",
    "plot_path",
    "error_table",
    "findings",
    "describe_base_motion",
    "length_unit",
    "beyond_text",
    "write_workspace",
    "write_operability",
]


def _file_mode() -> int:
    """The mode a new file gets from open(): 0o666 less the process's umask."""
    mask = os.umask(0)
    os.umask(mask)
    return 0o666 & ~mask


@contextmanager
def atomic_path(path: Path, suffix: str = "") -> Iterator[Path]:
    """A temporary path in ``path``'s folder, renamed to ``path`` if the block succeeds.

    The file ends with the mode ``open()`` would give it (the umask honoured), not the
    temporary file's private 0600.
    """
    path = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=suffix, dir=path.parent)
    os.close(fd)
    try:
        yield Path(tmp)
        os.chmod(tmp, _file_mode())
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)


MANIFEST = ".marinecdpr-files"
"""Hidden file in an output folder listing the files of the run that wrote it."""


class StagedOutput:
    """An output folder that receives a command's files all at once.

    Construct it before the work starts: it creates ``target`` (if needed) and a hidden
    staging folder inside it, so a folder that cannot be written fails at once. Write
    every file into the path the ``with`` block yields; when the block ends normally
    the files replace those of the previous run (the ones its manifest lists; other
    files in ``target`` are left alone), with SIGINT and SIGTERM held off for the few
    renames. If the block raises, the staged files are deleted and ``target`` keeps the
    previous run (or, if this created it, is removed again while still empty).

    Raises
    ------
    OutputError
        If ``target`` is not a folder or cannot be written.
    """

    def __init__(self, target: Path):
        self.target = Path(target)
        if self.target.exists() and not self.target.is_dir():
            raise OutputError(f"{self.target}: exists and is not a folder")
        self._created = not self.target.exists()
        try:
            self.target.mkdir(parents=True, exist_ok=True)
            self.stage = Path(tempfile.mkdtemp(prefix=f".staging-{os.getpid()}-", dir=self.target))
        except OSError as exc:
            raise OutputError(f"{self.target}: cannot write there ({exc.strerror or exc})") from None
        _remove_orphans(self.target)

    def __enter__(self) -> Path:
        return self.stage

    def __exit__(self, exc_type, exc, tb) -> None:
        try:
            if exc_type is None:
                self._commit()
        finally:
            shutil.rmtree(self.stage, ignore_errors=True)
            if exc_type is not None and self._created:
                try:
                    self.target.rmdir()  # only while empty
                except OSError:
                    pass

    def _commit(self) -> None:
        new = sorted(p.name for p in self.stage.iterdir())
        manifest = self.target / MANIFEST
        try:
            old = set(manifest.read_text(encoding="utf-8").split("\n")) - {""}
        except (OSError, UnicodeDecodeError):
            old = set()
        with _signals_held():
            for name in sorted(old - set(new)):
                stale = self.target / name
                if "/" not in name and stale.is_file():
                    stale.unlink()
            for name in new:
                os.replace(self.stage / name, self.target / name)
            with atomic_path(manifest) as tmp:
                tmp.write_text("\n".join(new) + "\n", encoding="utf-8")


def _remove_orphans(folder: Path) -> None:
    """Delete staging folders left in ``folder`` by runs that were killed (their process is gone)."""
    for stage in folder.glob(".staging-*-*"):
        try:
            os.kill(int(stage.name.split("-")[1]), 0)
        except ProcessLookupError:
            shutil.rmtree(stage, ignore_errors=True)
        except (ValueError, OSError):
            pass  # not ours, or a live process of another user


@contextmanager
def _signals_held() -> Iterator[None]:
    """Hold SIGINT and SIGTERM off (delivered after the block) in the main thread."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    held = {signal.SIGINT, signal.SIGTERM}
    previous = signal.pthread_sigmask(signal.SIG_BLOCK, held)
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, previous)


def plan_columns(plan: Plan, scenario: Scenario) -> tuple[list[str], np.ndarray]:
    """Column names and values of ``plan.csv``.

    Columns: ``t`` (s); the controlled pose in C (``x``, ``z``, ``theta_y`` for a
    planar robot, ``x, y, z, rx, ry, rz`` for a spatial one; m and deg);
    ``L1..Ln`` (cable lengths, m); ``Tpinv1..Tpinvn`` (eq. 18 tensions, N);
    ``T1..Tn`` (the method's tensions, N; empty where infeasible); ``feasible`` (1/0).

    Returns
    -------
    names : list of str
    values : ndarray, shape (n_steps, n_columns)
    """
    pose_names, dofs = _pose_names(scenario)
    pose = _pose_columns(plan.pose, dofs)
    n = scenario.robot.n_cables
    names = (
        ["t"] + pose_names + [f"L{i}" for i in range(1, n + 1)]
        + [f"Tpinv{i}" for i in range(1, n + 1)] + [f"T{i}" for i in range(1, n + 1)]
        + ["feasible"]
    )
    values = np.column_stack(
        [plan.t, pose, plan.lengths, plan.tensions_pinv, plan.tensions, plan.feasible.astype(float)]
    )
    return names, values


def _pose_names(scenario: Scenario) -> tuple[list[str], list[int]]:
    if scenario.robot.dofs == "planar":
        return ["x", "z", "theta_y"], [0, 2, 4]
    return list(TWIST_NAMES), list(range(6))


def _pose_columns(pose: np.ndarray, dofs: list[int]) -> np.ndarray:
    """The pose's controlled columns, angles in degrees."""
    out = pose[:, dofs].copy()
    for col, i in enumerate(dofs):
        if i >= 3:
            out[:, col] = np.degrees(out[:, col])
    return out


def write_plan_csv(plan: Plan, scenario: Scenario, path: Path) -> Path:
    """Write :func:`plan_columns` as CSV (NaN written as an empty field)."""
    names, values = plan_columns(plan, scenario)
    return _write_csv(names, values, path)


def _write_csv(names: list[str], values: np.ndarray, path: Path, int_last: bool = True) -> Path:
    path = Path(path)
    with atomic_path(path) as tmp:
        with open(tmp, "w", encoding="utf-8", newline="") as fh:
            fh.write(",".join(names) + "\n")
            if len(values) == 0:
                fh.write("\n")
            _write_rows(fh, _row_format(len(names), int_last), values)
    return path


def _row_format(n_columns: int, int_last: bool) -> str:
    """A CSV row's ``%`` format: 10 significant digits, the last column an integer flag if ``int_last``."""
    return ",".join(["%.10g"] * (n_columns - 1) + ["%d" if int_last else "%.10g"])


CSV_BLOCK_ROWS = 4096
"""Rows formatted per ``%`` operation when writing a CSV."""


def _write_rows(fh, fmt: str, values: np.ndarray) -> None:
    """Each row of ``values`` as ``fmt % row`` and a newline, NaN left empty.

    A block of rows is formatted by one ``%`` on the row format repeated (the loop over the
    numbers runs in C, not a Python call per row): the same bytes, about 25 % sooner.
    """
    line = fmt + "\n"
    for i in range(0, len(values), CSV_BLOCK_ROWS):
        block = values[i:i + CSV_BLOCK_ROWS]
        fh.write((line * len(block) % tuple(block.ravel().tolist())).replace("nan", ""))


# ------------------------------------------------------- figures at their resolution
def _column_groups(first: int, k: int, n: int, columns: int) -> tuple[np.ndarray, np.ndarray]:
    """Samples ``first`` .. ``first + k - 1`` of a series of ``n``, split as the whole series is
    into ``columns`` consecutive groups of (almost) equal size: the groups met, and where
    each starts among the ``k`` (the first one possibly a group begun before ``first``)."""
    col = (np.arange(first, first + k, dtype=np.int64) * columns) // n
    starts = np.flatnonzero(np.r_[True, col[1:] != col[:-1]])
    return col[starts], starts


def decimate(x: np.ndarray, y: np.ndarray, columns: int) -> tuple[np.ndarray, np.ndarray]:
    """A line thinned to what ``columns`` pixel columns can show, every extreme kept.

    The samples are split into ``columns`` consecutive groups (one per pixel column for
    a uniformly sampled series drawn across ``columns`` pixels); of each group only its
    first, smallest, largest and last sample are kept, in time order (the M4 rule: the
    line drawn through them covers the pixels the whole line covers), and the first
    NaN of each gap in the group, so that gaps stay gaps. A series of at most
    ``4 * columns`` samples is returned whole.

    Parameters
    ----------
    x : ndarray, shape (n,)
    y : ndarray, shape (n,) or (n, m)
        With m series (a path's coordinates), a sample is kept where any of them needs it.
    columns : int

    Returns
    -------
    x, y : ndarray
        The kept samples, at most about ``4 * columns`` (``4 * m * columns`` for m series).
    """
    x, y = np.asarray(x), np.asarray(y, dtype=float)
    n = y.shape[0]
    if n <= 4 * max(int(columns), 1):
        return x, y
    _, starts = _column_groups(0, n, n, int(columns))
    ends = np.r_[starts[1:], n]
    grid = starts[:, None] + np.arange(int((ends - starts).max()))
    outside = grid >= ends[:, None]
    grid = np.minimum(grid, n - 1)
    nan = np.isnan(y)
    gap = nan & ~np.concatenate([np.zeros((1,) + y.shape[1:], dtype=bool), nan[:-1]])
    vals, gap = y[grid], gap[grid]                      # (groups, width[, m])
    if y.ndim > 1:
        outside = outside[:, :, None]
    skip = outside | np.isnan(vals)
    offsets = [np.where(skip, np.inf, vals).argmin(axis=1), np.where(skip, -np.inf, vals).argmax(axis=1),
               np.where(outside, False, gap).argmax(axis=1)]  # a group without a gap gives its first
    starts_m = starts if y.ndim == 1 else starts[:, None]
    kept = np.unique(np.concatenate([starts, ends - 1] + [(starts_m + o).ravel() for o in offsets]))
    return x[kept], y[kept]


def _figure_columns(fig, dpi: float) -> int:
    """Pixel columns across ``fig`` saved at ``dpi``: more than any of its axes spans."""
    return int(np.ceil(fig.get_figwidth() * dpi))


def plot_tensions(plan: Plan, scenario: Scenario, path: Path) -> Path:
    """Figure like the paper's figure 5: tensions (a) before and (b) after optimisation."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    robot = scenario.robot
    fig, axes = plt.subplots(2, 1, figsize=(11, 7.5), sharex=True, constrained_layout=True)
    titles = (
        "(a) pseudo-inverse tensions, eq. (18)",
        f"(b) {plan.method.replace('_', ' ')} tensions ({plan.base_model} base)",
    )
    columns = _figure_columns(fig, TENSION_FIGURE_DPI)
    for ax, T, title in zip(axes, (plan.tensions_pinv, plan.tensions), titles):
        for i in range(robot.n_cables):
            ax.plot(*decimate(plan.t, T[:, i], columns), label=f"cable {i + 1}", lw=1.2)
        for j, v in enumerate(np.unique(np.concatenate([robot.tension_min, robot.tension_max]))):
            ax.axhline(v, color="k", ls="--", lw=0.8, label="limits" if j == 0 else None)
        ax.axhline(0.0, color="0.6", lw=0.6)
        ax.set_ylabel("tension (N)")
        ax.set_title(title, loc="left", fontsize=10)
        ax.grid(alpha=0.3)
    # (a) keeps its own range: eq. (18)'s tensions are small and may be negative
    lo_a, hi_a = np.nanmin(plan.tensions_pinv), np.nanmax(plan.tensions_pinv)
    pad = 0.1 * max(hi_a - lo_a, 1.0)
    axes[0].set_ylim(min(lo_a, 0.0) - pad, max(hi_a, robot.tension_min.max()) + pad)
    if not plan.all_feasible:
        bad = ~plan.feasible
        axes[1].fill_between(plan.t, 0, 1, where=bad, color="red", alpha=0.15,
                             transform=axes[1].get_xaxis_transform(), label="infeasible steps")
    _legend_below(fig, axes, max_columns=8)
    axes[1].set_xlabel("t (s)")
    fig.suptitle(f"Cable tensions: {_plain(scenario.name)}", fontsize=11)
    return _save(fig, path, dpi=TENSION_FIGURE_DPI)


# ------------------------------------------------------------ plans made in chunks
@contextmanager
def plan_csv_writer(scenario: Scenario, path: Path) -> Iterator:
    """``plan.csv`` written piece by piece: yields ``write(piece)``, to call with each piece
    of a plan (:func:`~marinecdpr.iter_plan`) in order, at least one.

    The file is byte for byte what :func:`write_plan_csv` writes for the whole plan, and
    appears (atomically) only when the block ends without an error; memory holds one
    piece's text at a time.
    """
    path = Path(path)
    with atomic_path(path) as tmp, open(tmp, "w", encoding="utf-8", newline="") as fh:
        rows = [0]

        def write(piece: Plan) -> None:
            names, values = plan_columns(piece, scenario)
            if len(values) == 0:
                return
            if rows[0] == 0:
                fh.write(",".join(names) + "\n")
            _write_rows(fh, _row_format(len(names), int_last=True), values)
            rows[0] += len(values)

        yield write
        if rows[0] == 0:
            raise ValueError("plan_csv_writer: no piece of a plan was written")


TENSION_FIGURE_COLUMNS = 2000
"""Time columns the streamed tension figure keeps, each with its smallest and largest
tension: more than the figure's axes have pixel columns, so no extreme is lost."""


class _TensionTrace:
    """What :func:`plot_tensions` draws, from a :class:`TensionEnvelope` instead of a Plan."""

    def __init__(self, t, tensions_pinv, tensions, feasible, method, base_model):
        self.t, self.tensions_pinv, self.tensions, self.feasible = t, tensions_pinv, tensions, feasible
        self.method, self.base_model = method, base_model

    @property
    def all_feasible(self) -> bool:
        return bool(self.feasible.all())


class TensionEnvelope:
    """A plan's tensions decimated to the figure's resolution while it streams.

    The plan's steps are split into ``columns`` consecutive groups; for each, the
    smallest and largest eq. 18 and planned tension of every cable (NaN ignored), the
    first and last time, and whether any step is infeasible. Memory does not grow with
    the plan. Feed every piece in order to :meth:`add`; draw with :func:`plot_tension_envelope`.

    Parameters
    ----------
    n_steps : int
        Steps of the whole plan.
    n_cables : int
    columns : int
        Groups kept (at most ``n_steps``: a short plan keeps every step).
    """

    def __init__(self, n_steps: int, n_cables: int, columns: int = TENSION_FIGURE_COLUMNS):
        self.n_steps = int(n_steps)
        self.columns = max(1, min(int(columns), self.n_steps))
        shape = (self.columns, int(n_cables))
        self.lo = {name: np.full(shape, np.nan) for name in ("tensions_pinv", "tensions")}
        self.hi = {name: np.full(shape, np.nan) for name in ("tensions_pinv", "tensions")}
        # each group's first and last values: a falling group is drawn from its largest to its smallest
        self.first = {name: np.full(shape, np.nan) for name in ("tensions_pinv", "tensions")}
        self.last = {name: np.full(shape, np.nan) for name in ("tensions_pinv", "tensions")}
        self.t_first = np.full(self.columns, np.nan)
        self.t_last = np.full(self.columns, np.nan)
        self.infeasible = np.zeros(self.columns, dtype=bool)
        self.counts = np.zeros(self.columns, dtype=np.int64)
        self.done = 0
        self.method: str | None = None
        self.base_model: str | None = None

    def add(self, piece: Plan) -> None:
        """Take in the next piece of the plan."""
        k = piece.n_steps
        if k == 0:
            return
        if self.done + k > self.n_steps:
            raise ValueError(f"the pieces hold more than the {self.n_steps} steps announced")
        self.method, self.base_model = piece.method, piece.base_model
        cols, starts = _column_groups(self.done, k, self.n_steps, self.columns)
        new = self.counts[cols] == 0
        ends = np.r_[starts[1:], k] - 1
        for name in self.lo:
            a = getattr(piece, name)
            self.first[name][cols[new]] = a[starts[new]]
            self.last[name][cols] = a[ends]
            self.lo[name][cols] = np.fmin(self.lo[name][cols], np.fmin.reduceat(a, starts, axis=0))
            self.hi[name][cols] = np.fmax(self.hi[name][cols], np.fmax.reduceat(a, starts, axis=0))
        self.t_first[cols] = np.fmin(self.t_first[cols], np.minimum.reduceat(piece.t, starts))
        self.t_last[cols] = np.fmax(self.t_last[cols], np.maximum.reduceat(piece.t, starts))
        self.infeasible[cols] |= np.logical_or.reduceat(~np.asarray(piece.feasible, dtype=bool), starts)
        self.counts[cols] += np.diff(np.r_[starts, k])
        self.done += k

    def trace(self) -> _TensionTrace:
        """The line to draw: per group and cable, its smallest and largest tension at the group's
        first and last time (the largest first where the tension falls over the group; one
        point per step where each group is one step)."""
        used = self.counts > 0
        lo = {name: v[used] for name, v in self.lo.items()}
        if (self.counts[used] <= 1).all():
            return _TensionTrace(self.t_first[used], lo["tensions_pinv"], lo["tensions"],
                                 ~self.infeasible[used], self.method, self.base_model)
        t = np.column_stack([self.t_first[used], self.t_last[used]]).ravel()

        def zigzag(name: str) -> np.ndarray:
            hi = self.hi[name][used]
            falls = self.first[name][used] > self.last[name][used]
            pair = (np.where(falls, hi, lo[name]), np.where(falls, lo[name], hi))
            return np.stack(pair, axis=1).reshape(t.size, -1)

        return _TensionTrace(t, zigzag("tensions_pinv"), zigzag("tensions"),
                             np.repeat(~self.infeasible[used], 2), self.method, self.base_model)


def plot_tension_envelope(envelope: TensionEnvelope, scenario: Scenario, path: Path) -> Path:
    """:func:`plot_tensions` (the paper's figure 5) from a :class:`TensionEnvelope`: each pixel
    column spans its steps' smallest to largest tension, so extremes stay visible."""
    return plot_tensions(envelope.trace(), scenario, path)


def write_plan_stream(pieces, scenario: Scenario, csv_path: Path, figure_path: Path):
    """``plan.csv`` and ``tensions.png`` from a plan made in pieces (:func:`~marinecdpr.iter_plan`),
    holding one piece at a time.

    Parameters
    ----------
    pieces : iterable of Plan
        The scenario's whole plan, in order.
    scenario : Scenario
    csv_path, figure_path : Path

    Returns
    -------
    marinecdpr.planning.planner.PlanSummary
        The plan's figures (steps, feasible steps, tension ranges, :meth:`infeasibility`),
        with ``planning_s``, the time spent making the pieces, s.
    """
    import time

    from marinecdpr.planning.planner import PlanSummary

    summary = PlanSummary()
    envelope = TensionEnvelope(scenario.time.n_steps, scenario.robot.n_cables)
    summary.planning_s = 0.0
    it = iter(pieces)
    with plan_csv_writer(scenario, csv_path) as write:
        while True:
            t0 = time.perf_counter()
            piece = next(it, None)
            summary.planning_s += time.perf_counter() - t0
            if piece is None:
                break
            write(piece)
            envelope.add(piece)
            summary.add(piece)
            del piece
    plot_tension_envelope(envelope, scenario, figure_path)
    return summary


# ------------------------------------------------------------------ simulations
RUN_TITLES = {
    "open_loop": "open loop (plan fed forward)",
    "closed_loop": "closed loop (computed torque)",
    "fixed_base_open_loop": "fixed-base plan, open loop",
}
RUN_COLOURS = {"open_loop": "C0", "closed_loop": "C2", "fixed_base_open_loop": "C3"}
# the open loop (the paper's test) is drawn wide and underneath, the closed loop dashed on
# top, so that both stay visible where they coincide
RUN_STYLES = {"fixed_base_open_loop": dict(lw=1.3, ls="-"), "open_loop": dict(lw=3.0, ls="-", alpha=0.55),
              "closed_loop": dict(lw=1.1, ls=(0, (4, 2)))}


def _drawing_order(results: dict):
    """Runs in drawing order: the closed loop, usually the smallest error, last (on top)."""
    order = ["fixed_base_open_loop", "open_loop", "closed_loop"]
    return sorted(results.items(), key=lambda kv: order.index(kv[0]) if kv[0] in order else -1)


def _run_style(name: str) -> dict:
    return dict(color=RUN_COLOURS.get(name), **RUN_STYLES.get(name, dict(lw=1.0)))


def _legend_below(fig, axes, max_columns: int = 4) -> None:
    """One legend for the figure, below the axes, from every labelled artist of ``axes``."""
    handles, labels = [], []
    for ax in np.ravel(axes):
        for h, lab in zip(*ax.get_legend_handles_labels()):
            if lab not in labels:
                handles.append(h)
                labels.append(lab)
    fig.legend(handles, labels, loc="outside lower center", ncol=min(len(labels), max_columns), fontsize=9)


def write_sim_csv(res, scenario: Scenario, path: Path) -> Path:
    """``sim_<run>.csv``: t; planned and actual pose (``x_plan``.., ``x``..; m, deg);
    planned and actual cable lengths (``Lplan1``.., ``L1``..; m); applied and commanded
    tensions (``T1``.., ``Tcmd1``..; N)."""
    pose_names, dofs = _pose_names(scenario)
    n = scenario.robot.n_cables
    names = (["t"] + [f"{p}_plan" for p in pose_names] + pose_names
             + [f"Lplan{i}" for i in range(1, n + 1)] + [f"L{i}" for i in range(1, n + 1)]
             + [f"T{i}" for i in range(1, n + 1)] + [f"Tcmd{i}" for i in range(1, n + 1)])
    values = np.column_stack([
        res.t, _pose_columns(res.pose_planned, dofs), _pose_columns(res.pose, dofs),
        res.lengths_planned, res.lengths, res.tensions, res.tensions_commanded])
    return _write_csv(names, values, path, int_last=False)


FIGURE_DPI = 110
"""Resolution of the main job's figures but the tension figure's (TENSION_FIGURE_DPI)."""
TENSION_FIGURE_DPI = 120


def _save(fig, path: Path, dpi: int = FIGURE_DPI) -> Path:
    import matplotlib.pyplot as plt

    path = Path(path)
    with atomic_path(path, suffix=path.suffix) as tmp:
        fig.savefig(tmp, dpi=dpi)
    plt.close(fig)
    return path


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


LENGTH_UNITS = ((1.0, "m"), (1e-3, "mm"), (1e-6, "µm"), (1e-9, "nm"))
"""Units a length is shown in, largest first, with their size in metres."""


def length_unit(largest_m: float) -> tuple[float, str]:
    """The unit (metres per unit, name) in which ``largest_m`` reads as 1 to 999 (nm at least)."""
    for size, name in LENGTH_UNITS:
        if abs(largest_m) >= size:
            return size, name
    return LENGTH_UNITS[-1]


def _planned_vs_actual(results: dict, rows: list, *, planned_label: str, row_height: float, title: str,
                       path: Path) -> Path:
    """Two columns per row: planned and each run's actual value, and |actual - planned| on a
    log scale (so runs whose errors differ by orders of magnitude all show), in a unit
    chosen from the data.

    ``rows``: (label, angular, value) with ``value(res, planned)`` the (n_steps,) series
    of a SimResult (planned or actual) in m, or in deg if ``angular``.
    """
    plt = _pyplot()
    fig, axes = plt.subplots(len(rows), 2, figsize=(11, row_height * len(rows) + 1.5), sharex=True,
                             squeeze=False, constrained_layout=True)
    first = next(iter(results.values()))
    columns = _figure_columns(fig, FIGURE_DPI)
    for (ax, ax_e), (label, angular, value) in zip(axes, rows):
        errors = {name: np.abs(value(res, False) - value(res, True)) for name, res in results.items()}
        largest = max(float(e.max()) for e in errors.values())
        size, unit_e = (1.0, "deg") if angular else length_unit(largest)
        for name, res in _drawing_order(results):
            ax.plot(*decimate(res.t, value(res, False), columns), label=RUN_TITLES.get(name, name),
                    **_run_style(name))
            err = errors[name] / size
            # the log scale shows the positive errors: decimated among themselves (zeros are gaps)
            ax_e.plot(*decimate(res.t, np.where(err > 0, err, np.nan), columns), color=RUN_COLOURS.get(name),
                      lw=0.8)
        ax.plot(*decimate(first.t, value(first, True), columns), "k:", lw=1.1, label=planned_label)
        ax.set_ylabel(f"{label} ({'deg' if angular else 'm'})")
        ax_e.set_ylabel(f"|{label} error| ({unit_e})")
        if largest > 0:
            ax_e.set_yscale("log")
        ax.grid(alpha=0.3)
        ax_e.grid(alpha=0.3, which="both")
    _legend_below(fig, axes[0, 0])
    axes[-1, 0].set_xlabel("t (s)")
    axes[-1, 1].set_xlabel("t (s)")
    fig.suptitle(title, fontsize=11)
    return _save(fig, path)


def plot_cable_lengths(results: dict, scenario: Scenario, path: Path) -> Path:
    """Like the paper's figure 6: planned and actual cable lengths, and their difference."""
    rows = [(f"L{i + 1}", False, lambda res, planned, i=i: (res.lengths_planned if planned else res.lengths)[:, i])
            for i in range(scenario.robot.n_cables)]
    return _planned_vs_actual(results, rows, planned_label="planned (kinematics)", row_height=1.9, path=path,
                              title=f"Cable lengths, planned and on the virtual prototype: {_plain(scenario.name)}")


def plot_tracking(results: dict, scenario: Scenario, path: Path) -> Path:
    """Like the paper's figure 7: planned and actual pose, and the tracking errors."""
    pose_names, dofs = _pose_names(scenario)
    rows = [(name, i >= 3, lambda res, planned, i=i: (np.degrees if i >= 3 else np.asarray)(
                (res.pose_planned if planned else res.pose)[:, i]))
            for name, i in zip(pose_names, dofs)]
    return _planned_vs_actual(results, rows, planned_label="planned", row_height=2.2, path=path,
                              title=f"Tracking on the virtual prototype: {_plain(scenario.name)}")


def plot_path(results: dict, scenario: Scenario, path: Path) -> Path:
    """The platform's path in C, planned and of each run, with the frame anchors: the x-z
    plane for a planar robot; x-z and x-y for a spatial one."""
    plt = _pyplot()
    planes = [(0, 2)] if scenario.robot.dofs == "planar" else [(0, 2), (0, 1)]
    fig, axes = plt.subplots(1, len(planes), figsize=(6.5 * len(planes), 6.0), squeeze=False,
                             constrained_layout=True)
    c = scenario.robot.frame_anchors
    first = next(iter(results.values()))
    columns = _figure_columns(fig, FIGURE_DPI)
    for ax, (i, j) in zip(axes[0], planes):
        ax.plot(c[:, i], c[:, j], "ks", ms=7, label="frame anchors")
        for name, res in _drawing_order(results):
            # each coordinate's extremes kept, over time groups as fine as the figure's pixels
            _, xy = decimate(res.t, res.pose[:, [i, j]], columns)
            ax.plot(xy[:, 0], xy[:, 1], label=RUN_TITLES.get(name, name), **_run_style(name))
        _, xy = decimate(first.t, first.pose_planned[:, [i, j]], columns)
        ax.plot(xy[:, 0], xy[:, 1], "k:", lw=1.1, label="planned")
        ax.plot(*first.pose_planned[0, [i, j]], "ko", ms=5, label="start")
        ax.set_xlabel(f"{'xyz'[i]} in C (m)")
        ax.set_ylabel(f"{'xyz'[j]} in C (m)")
        ax.set_aspect("equal", adjustable="datalim")
        ax.grid(alpha=0.3)
    _legend_below(fig, axes[0, 0])
    fig.suptitle(f"Platform path in the robot frame C: {_plain(scenario.name)}", fontsize=11)
    return _save(fig, path)


def _plain(text: str) -> str:
    """``text`` for a matplotlib title, read literally: no mathtext, no control characters."""
    return strip_control(text).replace("$", r"\$")


def write_json(data: dict, path: Path) -> Path:
    import json

    path = Path(path)
    with atomic_path(path) as tmp:
        Path(tmp).write_text(json.dumps(data, indent=2) + "\n", encoding="utf-8")
    return path


def _sim_runs(summary: dict) -> list[str]:
    return [r for r in ("open_loop", "closed_loop", "fixed_base_open_loop") if r in summary]


def _error_rows(summary: dict, scenario: Scenario) -> list[tuple[str, str, list[float], float | None]]:
    """(label, kind, each run's value, the paper's value or None) of every tracking error:
    each controlled DOF, the spatial rotation angle, and the largest cable-length error.
    kind is "m" or "deg"."""
    runs = _sim_runs(summary)
    paper = summary.get("paper_reported")
    rows = []
    for name, i in zip(*_pose_names(scenario)):
        if i < 3:
            key = f"max_abs_error_{TWIST_NAMES[i]}_m"
            rows.append((name, "m", [summary[r][key] for r in runs], paper.get(key) if paper else None))
        elif scenario.robot.dofs == "planar":
            key = "max_abs_error_theta_deg"
            rows.append((name, "deg", [summary[r][key] for r in runs], paper.get(key) if paper else None))
        else:
            rows.append((name, "deg", [summary[r][f"max_abs_error_{name}_deg"] for r in runs], None))
    if scenario.robot.dofs != "planar":
        rows.append(("rotation angle", "deg", [summary[r]["max_abs_error_theta_deg"] for r in runs], None))
    rows.append(("cable length", "m", [max(summary[r]["max_abs_cable_length_error_m"]) for r in runs],
                 paper.get("max_abs_cable_length_error_m") if paper else None))
    return rows


def error_table(summary: dict, scenario: Scenario) -> tuple[list[str], list[list[str]]]:
    """The tracking errors as text: header and rows, one unit per row (chosen from its
    largest value), the paper's column only for the paper's experiment, and a last row
    saying which runs stayed within the error bound."""
    runs = _sim_runs(summary)
    paper = "paper_reported" in summary
    header = ["max |error|"] + (["paper (Adams, open loop)"] if paper else []) + [RUN_TITLES[r] for r in runs]
    rows = []
    for label, kind, values, paper_value in _error_rows(summary, scenario):
        everything = values + ([paper_value] if paper_value is not None else [])
        size, unit = (1.0, "deg") if kind == "deg" else length_unit(max(everything))
        cells = [f"{v / size:.3g}" for v in values]
        lead = ([f"{paper_value / size:.3g}" if paper_value is not None else "–"] if paper else [])
        rows.append([f"{label} ({unit})"] + lead + cells)
    size, unit = length_unit(summary["error_bound_m"])
    rows.append([f"within {summary['error_bound_m'] / size:.3g} {unit} / {summary['error_bound_deg']:g} deg"]
                + (["–"] if paper else [])
                + ["yes" if summary[r]["within_error_bound"] else "NO: " + beyond_text(summary[r]["beyond_error_bound"])
                   for r in runs])
    return header, rows


def beyond_text(names: list[str]) -> str:
    """``["x", "rz", "cable 1", "cable 2", "cable 3", "cable 5"]`` as "x, rz, cables 1-3, 5"."""
    cables = [int(n.split()[1]) for n in names if n.startswith("cable ")]
    parts = [n for n in names if not n.startswith("cable ")]
    runs: list[str] = []
    for i in cables:
        if runs and runs[-1][1] == i - 1:
            runs[-1] = (runs[-1][0], i)
        else:
            runs.append((i, i))
    if runs:
        text = ", ".join(f"{a}" if a == b else f"{a}-{b}" for a, b in runs)
        parts.append(("cable " if len(cables) == 1 else "cables ") + text)
    return ", ".join(parts)


def _times(ratio: float) -> str:
    """A ratio for a sentence: 3.56, 61 100 (not 6.11e+04)."""
    return f"{ratio:.3g}" if ratio < 1000 else f"{float(f'{ratio:.3g}'):,.0f}".replace(",", " ")


def _fmt_length(v: float) -> str:
    size, unit = length_unit(v)
    return f"{v / size:.3g} {unit}"


def findings(summary: dict, scenario: Scenario, *, warnings: bool = True) -> list[str]:
    """What the numbers say, as sentences written from them (for the report and terminal);
    with ``warnings``, the summary's warnings too."""
    runs = _sim_runs(summary)
    out = []
    bound = f"{_fmt_length(summary['error_bound_m'])} and {summary['error_bound_deg']:g} deg"

    def worst(r: str) -> tuple[float, float]:
        s = summary[r]
        pos = max(v for k, v in s.items() if k.startswith("max_abs_error_") and k.endswith("_m"))
        return max(pos, max(s["max_abs_cable_length_error_m"])), s["max_abs_error_theta_deg"]

    for r in runs:
        pos, ang = worst(r)
        verdict = ("within the bound" if summary[r]["within_error_bound"] else
                   "BEYOND the bound (" + beyond_text(summary[r]["beyond_error_bound"]) + ")")
        out.append(f"{RUN_TITLES[r]}: largest position or cable-length error {_fmt_length(pos)}, "
                   f"angle {ang:.3g} deg: {verdict} of {bound}.")
    ideal = scenario.simulation.cables.model == "ideal"
    if "open_loop" in summary:
        pos, _ = worst("open_loop")
        if not summary["open_loop"]["within_error_bound"]:
            out.append("Open loop leaves its plan: tensions fed forward without feedback do not hold this "
                       "robot on its path" + (" (with ideal cables plan and plant share one model, so this is "
                                              "the platform's open-loop instability, not a modelling error)"
                                              if ideal else "") + "; judge the robot by the closed loop.")
        elif ideal and pos < 1e-3 * summary["error_bound_m"]:
            out.append("With ideal cables the plan and the plant share one model: open loop follows the plan "
                       "but for the hold of the tensions over each step.")
    if "closed_loop" in summary:
        c = summary["closed_loop"]
        if not c["within_error_bound"]:
            out.append("The closed loop too leaves the bound: the feedback gains, the sensors or the "
                       "cables do not hold this robot on its plan.")
        elif c["controller_fallbacks"] > 0.01 * summary["steps"]:
            out.append("The closed loop stays within the bound, but on the plan's tensions at "
                       f"{c['controller_fallbacks']} of {summary['steps']} steps: it shows the plan, not the controller.")
        else:
            out.append("The closed loop holds the platform within the bound.")
    if "open_loop" in summary and "fixed_base_open_loop" in summary:
        fixed, moving = worst("fixed_base_open_loop")[0], worst("open_loop")[0]
        if fixed > 2 * moving:
            out.append(f"The fixed-base plan, which leaves out the ship's motion, errs by {_fmt_length(fixed)}, "
                       f"{_times(fixed / max(moving, 1e-300))} times the moving-base plan's {_fmt_length(moving)}: "
                       "what ignoring the ship costs.")
    if "paper_reported" in summary:
        out.append("The paper's column is its section 4.2: open loop on Adams with a 1 ms exchange.")
    out += [f"Warning: {w}." for w in summary.get("warnings", [])] if warnings else []
    for r in runs:
        excess = summary[r]["tension_limit_excess_N"]
        if excess > 0:
            out.append(f"{RUN_TITLES[r]}: applied tensions left their limits by up to {excess:.3g} N.")
    return out


def write_report_html(summary: dict, scenario: Scenario, figures: dict[str, Path], path: Path) -> Path:
    """One self-contained page: the scenario, the error table (beside the paper's for the
    paper's experiment), what the numbers say, and every figure."""
    import base64
    import html

    def esc(text: str) -> str:
        return html.escape(strip_control(text))

    runs = _sim_runs(summary)
    header, rows = error_table(summary, scenario)
    body = []
    for row in rows:
        cells = "".join(f"<td><b>{esc(c)}</b></td>" if c.startswith("NO") else f"<td>{esc(c)}</td>"
                        for c in row[1:])
        body.append(f"<tr><th>{esc(row[0])}</th>{cells}</tr>")
    lead = "<td>–</td>" if "paper_reported" in summary else ""
    cells = "".join(f"<td>{summary[r]['tension_min_N']:.1f} .. {summary[r]['tension_max_N']:.1f} N</td>"
                    for r in runs)
    body.append(f"<tr><th>applied tensions</th>{lead}{cells}</tr>")
    cells = "".join(
        "<td>within</td>" if summary[r]["tension_limit_excess_N"] == 0 else
        f"<td><b>outside by {summary[r]['tension_limit_excess_N']:.3g} N</b></td>" for r in runs)
    limits = f"{scenario.robot.tension_min.min():g} .. {scenario.robot.tension_max.max():g} N"
    body.append(f"<tr><th>tension limits ({limits})</th>{lead}{cells}</tr>")
    head = "".join(f"<th>{esc(h)}</th>" for h in header)
    sim = scenario.simulation
    r = scenario.robot
    facts = [
        ("robot", f"{r.dofs}, {r.n_cables} cables, {r.mass_kg:g} kg, tensions "
                  f"{r.tension_min.min():g} .. {r.tension_max.max():g} N"),
        ("base motion", describe_base_motion(scenario.base_motion)),
        ("trajectory", scenario.trajectory.type),
        ("time", f"{scenario.time.duration_s:g} s at {scenario.time.step_s * 1e3:g} ms "
                 f"({summary['steps']} steps)"),
        ("tensions", f"{summary['method'].replace('_', ' ')}: {summary['opt_tension_min_N']:.1f} .. "
                     f"{summary['opt_tension_max_N']:.1f} N (pseudo-inverse, eq. 18, alone: down to "
                     f"{summary['pinv_tension_min_N']:.1f} N)"),
        ("plant", f"{sim.plant} ({sim.integrator}), cables {sim.cables.model}"
                  + (f", EA {sim.cables.stiffness_EA_N:g} N, {sim.cables.winch} winch, lag "
                     f"{sim.cables.winch_time_constant_s * 1e3:g} ms" if sim.cables.model == "elastic" else "")),
        ("closed loop", f"computed torque, bandwidth {sim.control.bandwidth_hz:g} Hz, damping ratio "
                        f"{sim.control.damping_ratio:g}"),
    ]
    fact_rows = "".join(f"<tr><th>{esc(k)}</th><td>{esc(v)}</td></tr>" for k, v in facts)
    notes = "".join(f"<li>{esc(sentence)}</li>" for sentence in findings(summary, scenario))
    imgs = []
    for caption, fig_path in figures.items():
        data = base64.b64encode(Path(fig_path).read_bytes()).decode("ascii")
        imgs.append(f'<figure><img src="data:image/png;base64,{data}" alt="{esc(caption)}">'
                    f"<figcaption>{esc(caption)}</figcaption></figure>")
    title = "Tracking errors, the paper's and ours" if "paper_reported" in summary else "Tracking errors"
    page = f"""<!doctype html>
<html lang="en"><head><meta charset="utf-8"><title>marinecdpr: {esc(scenario.name)}</title>
<style>
body {{ font-family: system-ui, sans-serif; max-width: 1100px; margin: 2em auto; padding: 0 1em;
       color: #222; }}
table {{ border-collapse: collapse; margin: 1em 0; }}
th, td {{ border: 1px solid #ccc; padding: 0.3em 0.7em; text-align: left; }}
thead th {{ background: #f2f2f2; }}
figure {{ margin: 1.5em 0; }} img {{ max-width: 100%; }}
figcaption {{ color: #555; font-size: 0.9em; }}
</style></head><body>
<h1>Virtual prototype, scenario: {esc(scenario.name)}</h1>
<p>{esc(scenario.description)}</p>
<h2>Scenario</h2><table>{fact_rows}</table>
<h2>{title}</h2>
<table><thead><tr>{head}</tr></thead>
<tbody>{''.join(body)}</tbody></table>
<p>Errors are the largest of |actual − planned| over the run, each row in one unit.</p>
<ul>{notes}</ul>
<h2>Figures</h2>
{''.join(imgs)}
</body></html>
"""
    path = Path(path)
    with atomic_path(path) as tmp:
        Path(tmp).write_text(page, encoding="utf-8")
    return path


def describe_base_motion(bm) -> str:
    """One line describing a ``[base_motion]`` of any type."""
    if bm.type == "still":
        return "still"
    if bm.type == "sinusoidal":
        return "sinusoidal: " + ", ".join(
            f"{c.dof} {c.amplitude_deg if c.amplitude_deg is not None else c.amplitude_m:g}"
            f"{' deg' if c.amplitude_deg is not None else ' m'} / {c.period_s:g} s" for c in bm.components)
    if bm.type == "sea_state":
        spectrum = {"jonswap": "JONSWAP", "pierson_moskowitz": "Pierson-Moskowitz"}[bm.spectrum]
        return (f"sea state: {spectrum}, Hs {bm.hs_m:g} m, Tp {bm.tp_s:g} s, heading {bm.heading_deg:g} deg, "
                f"spreading {bm.spreading}, RAOs from {bm.rao.source.replace('_', ' ')}, seed {bm.seed}")
    if bm.type == "recorded":
        return (f"recorded: {Path(bm.file).name} (z {bm.z_axis}, angles in {bm.angles}, "
                f"from {bm.start_s:g} s of the record)")
    return bm.type


def _can_fork() -> bool:
    """True where work can go to a forked process, safely and to some gain: on Linux, with
    two CPUs or more, from a process running no other Python thread (one could hold a
    lock the copy would wait for forever) and allowed children (not a daemon, such as a
    pool's worker)."""
    import multiprocessing

    return (sys.platform.startswith("linux") and "fork" in multiprocessing.get_all_start_methods()
            and len(os.sched_getaffinity(0)) >= 2 and threading.active_count() == 1
            and not multiprocessing.current_process().daemon)


class _Forked:
    """``fn()`` run in a forked copy of this process while this one goes on (where
    :func:`_can_fork`; else by :meth:`result`, here).

    The copy shares this process's state as it is at the fork (data, imports, caches:
    nothing is pickled on the way in); it ignores Ctrl-C (this process handles it and
    ends the copy) and is killed if this process dies. Call :meth:`result` for ``fn``'s
    value or exception (an OSError keeps its errno), and :meth:`stop` in any case.
    """

    def __init__(self, fn):
        self._fn = fn
        self._process = None
        if not _can_fork():
            return
        import multiprocessing
        import warnings

        ctx = multiprocessing.get_context("fork")
        self._conn, child_end = ctx.Pipe(duplex=False)
        self._process = ctx.Process(target=_forked_main, args=(fn, child_end, os.getpid()), daemon=True)
        with warnings.catch_warnings():
            # Python >= 3.12 warns of fork() in a process with threads; ours are BLAS's idle
            # workers (fork-safe), and the copy only draws figures
            warnings.filterwarnings("ignore", category=DeprecationWarning, message=".*fork")
            self._process.start()
        child_end.close()

    def result(self):
        if self._process is None:
            return self._fn()
        try:
            ok, value = self._conn.recv()
        except EOFError:  # it died without a word
            self._process.join()
            ok, value = False, RuntimeError(f"the process drawing figures ended with exit code "
                                            f"{self._process.exitcode}")
        self._process.join()
        if not ok:
            raise value
        return value

    def stop(self) -> None:
        """End the copy if it still runs, and wait for it."""
        if self._process is None:
            return
        if self._process.is_alive():
            self._process.terminate()
        self._process.join()
        self._conn.close()


def _forked_main(fn, conn, parent: int) -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:  # die with the parent (Linux): a killed command leaves no process drawing
        import ctypes

        ctypes.CDLL(None, use_errno=True).prctl(1, signal.SIGKILL, 0, 0, 0)  # PR_SET_PDEATHSIG
    except (OSError, AttributeError):
        pass
    if os.getppid() != parent:
        os._exit(1)
    try:
        out = (True, fn())
    except BaseException as exc:  # noqa: BLE001 - handed to the parent, which raises it
        out = (False, exc)
    try:
        conn.send(out)
    except Exception as exc:  # noqa: BLE001 - the value or exception does not pickle
        failure = out[1] if not out[0] else exc
        conn.send((False, RuntimeError(f"{type(failure).__name__}: {failure}")))
    conn.close()


def write_virtual_prototype(vp, folder: Path) -> list[Path]:
    """Every file of the main job in ``folder``: plan.csv, sim_<run>.csv, the figures,
    summary.json and report.html. Returns the paths written.

    Where it pays (:func:`_can_fork`), two of the figures are drawn by a forked copy of this
    process meanwhile; the files are the same either way.
    """
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    sc = vp.scenario
    # drawing the figures is most of the work: two of them (about half) are drawn in a
    # second process while this one writes the CSVs and draws the other two
    _pyplot()  # imported once, before the fork, for both
    apart = _Forked(lambda: (plot_tensions(vp.plan, sc, folder / "tensions.png"),
                             plot_cable_lengths(vp.results, sc, folder / "cable_lengths.png")))
    try:
        paths = [write_plan_csv(vp.plan, sc, folder / "plan.csv")]
        for name, res in vp.results.items():
            paths.append(write_sim_csv(res, sc, folder / f"sim_{name}.csv"))
        tracking = plot_tracking(vp.results, sc, folder / "tracking.png")
        path_figure = plot_path(vp.results, sc, folder / "path.png")
        tensions, lengths = apart.result()
    finally:
        apart.stop()
    figures = {
        "Figure 5: cable tensions (a) from eq. (18) and (b) after optimisation": tensions,
        "Figure 6: cable lengths, planned (kinematics) and actual (virtual prototype)": lengths,
        "Figure 7: planned and actual pose, and the tracking errors": tracking,
        "The platform's path in C, planned and actual": path_figure,
    }
    paths += list(figures.values())
    paths.append(write_json(vp.summary, folder / "summary.json"))
    paths.append(write_report_html(vp.summary, sc, figures, folder / "report.html"))
    return paths


# ------------------------------------------------------------ workspace, operability
def write_workspace(ws, scenario: Scenario, folder: Path) -> list[Path]:
    """``workspace.csv`` (one row per grid pose) and ``workspace.png`` (the maps)."""
    plt = _pyplot()
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    U, V = np.meshgrid(ws.u, ws.v, indexing="ij")
    names = [f"{ws.axes[0]}_m", f"{ws.axes[1]}_m", "fraction_feasible", "min_margin_N",
             "pinv_fraction_feasible"]
    values = np.column_stack([U.ravel(), V.ravel(), ws.fraction_feasible.ravel(),
                              ws.min_margin_N.ravel(), ws.pinv_fraction_feasible.ravel()])
    csv_path = _write_csv(names, values, folder / "workspace.csv", int_last=False)
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.8), constrained_layout=True)
    extent = (ws.u[0], ws.u[-1], ws.v[0], ws.v[-1])
    panels = (
        (ws.fraction_feasible, "fraction of time feasible", "RdYlGn", (0, 1)),
        (np.where(np.isfinite(ws.min_margin_N), ws.min_margin_N, np.nan),
         "smallest tension margin (N), poses feasible throughout", "viridis", (None, None)),
        (ws.pinv_fraction_feasible, "fraction of time eq. (18) alone is feasible", "RdYlGn", (0, 1)),
    )
    c = scenario.robot.frame_anchors
    i_u, i_v = "xyz".index(ws.axes[0]), "xyz".index(ws.axes[1])
    for ax, (data, title, cmap, (vmin, vmax)) in zip(axes, panels):
        im = ax.imshow(data.T, origin="lower", extent=extent, cmap=cmap, vmin=vmin, vmax=vmax,
                       aspect="equal", interpolation="nearest")
        ax.plot(c[:, i_u], c[:, i_v], "ks", ms=6, label="frame anchors")
        ax.set_title(title, fontsize=9)
        ax.set_xlabel(f"{ws.axes[0]} in C (m)")
        ax.set_ylabel(f"{ws.axes[1]} in C (m)")
        fig.colorbar(im, ax=ax, shrink=0.8)
    fig.suptitle(f"Workspace under ship motion: {_plain(scenario.name)} ({scenario.base_motion.type}, "
                 f"{ws.n_steps} steps; {ws.fixed['axis']} = {ws.fixed['value_m']:g} m held)", fontsize=10)
    return [csv_path, _save(fig, folder / "workspace.png")]


def write_operability(op, scenario: Scenario, folder: Path) -> list[Path]:
    """``operability.csv`` (one row per sea state), ``operability.json`` and ``operability.png``."""
    from marinecdpr.studies.operability import LIMITING_HS_MEANING

    plt = _pyplot()
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    names = ["heading_deg", "hs_m", "tp_s", "probability", "operable", "fraction_feasible", "min_margin_N",
             "max_error_m"]
    values = np.array([[r.cell.heading_deg, r.cell.hs, r.cell.tp, r.cell.probability, float(r.operable),
                        r.fraction_feasible, r.min_margin_N, r.max_error_m] for r in op.results])
    paths = [_write_csv(names, values, folder / "operability.csv", int_last=False)]
    summary = {
        "scenario": scenario.name,
        "operability": op.operability,
        "margin_N": op.margin_N,
        "per_heading": {f"{h:g}": v for h, v in op.per_heading.items()},
        "limiting_hs_m": op.limiting_hs_json(),
        "limiting_hs_meaning": LIMITING_HS_MEANING,
        "cells": len(op.results),
        "steps_per_cell": op.results[0].n_steps if op.results else 0,
    }
    paths.append(write_json(summary, folder / "operability.json"))
    k = len(op.headings_deg)
    fig, axes = plt.subplots(1, k, figsize=(6.5 * k, 5.2), squeeze=False, constrained_layout=True)
    from matplotlib.colors import ListedColormap

    cmap = ListedColormap(["#d73027", "#1a9850"])
    for ax, h in zip(axes[0], op.headings_deg):
        grid = op.operable_grid(h)
        ax.imshow(grid, origin="lower", cmap=cmap, vmin=0, vmax=1, aspect="auto",
                  extent=(-0.5, op.scatter.tp.size - 0.5, -0.5, op.scatter.hs.size - 0.5))
        for i in range(op.scatter.hs.size):
            for j in range(op.scatter.tp.size):
                p = op.scatter.probability[i, j]
                if p > 0:
                    ax.text(j, i, f"{100 * p:.2g}", ha="center", va="center", fontsize=7, color="white")
        ax.set_xticks(range(op.scatter.tp.size), [f"{v:g}" for v in op.scatter.tp])
        ax.set_yticks(range(op.scatter.hs.size), [f"{v:g}" for v in op.scatter.hs])
        ax.set_xlabel("Tp (s)")
        ax.set_ylabel("Hs (m)")
        ax.set_title(f"heading {h:g} deg: operable {100 * op.per_heading[h]:.1f} %", fontsize=10)
    fig.suptitle(f"Operability of {_plain(scenario.name)} (green: workable with {op.margin_N:g} N margin; "
                 "numbers: probability %)", fontsize=10)
    paths.append(_save(fig, folder / "operability.png"))
    return paths
