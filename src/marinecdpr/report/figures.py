"""The figures: like the paper's 5-7, the platform's path, the workspace and operability maps.

Every line is drawn at the figure's resolution (:func:`decimate`: each pixel column keeps its
extremes), so a long run draws as fast as a short one and shows what it holds. The main job
draws two of its figures in a forked copy of the process where that pays (:class:`_Forked`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from marinecdpr.planning.planner import TWIST_NAMES, Plan
from marinecdpr.report.files import atomic_path
from marinecdpr.scenario.schema import Scenario
from marinecdpr.textfiles import strip_control

__all__ = [
    "decimate",
    "plot_tensions",
    "TensionEnvelope",
    "plot_tension_envelope",
    "plot_cable_lengths",
    "plot_tracking",
    "plot_path",
    "plot_workspace",
    "plot_operability",
    "plot_control_study",
    "length_unit",
]


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


FIGURE_DPI = 110
"""Resolution of the main job's figures but the tension figure's (TENSION_FIGURE_DPI)."""
TENSION_FIGURE_DPI = 120


def _save(fig, path: Path, dpi: int = FIGURE_DPI) -> Path:
    import matplotlib.pyplot as plt

    path = Path(path)
    with atomic_path(path, suffix=path.suffix) as tmp:
        fig.savefig(tmp, dpi=dpi, pil_kwargs={"compress_level": 1})  # fast; some 10% larger
    plt.close(fig)
    return path


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _plain(text: str) -> str:
    """``text`` for a matplotlib title, read literally: no mathtext, no control characters."""
    return strip_control(text).replace("$", r"\$")


def _pose_names(scenario: Scenario) -> tuple[list[str], list[int]]:
    if scenario.robot.dofs == "planar":
        return ["x", "z", "theta_y"], [0, 2, 4]
    return list(TWIST_NAMES), list(range(6))


# ------------------------------------------------------------------ plan tensions
def plot_tensions(plan: Plan, scenario: Scenario, path: Path) -> Path:
    """Figure like the paper's figure 5: tensions (a) before and (b) after optimisation."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    robot = scenario.robot
    fig, axes = plt.subplots(2, 1, figsize=(11, 7.5), sharex=True)
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
    finite = plan.tensions_pinv[np.isfinite(plan.tensions_pinv)]
    lo_a, hi_a = (float(finite.min()), float(finite.max())) if finite.size else (0.0, 0.0)
    pad = 0.1 * max(hi_a - lo_a, 1.0)
    axes[0].set_ylim(min(lo_a, 0.0) - pad, max(hi_a, robot.tension_min.max()) + pad)
    for ax, T, why in zip(axes, (plan.tensions_pinv, plan.tensions),
                          ("J~ loses rank at every step (a singular pose)", "no step feasible")):
        if not np.isfinite(T).any():  # e.g. J~ singular at every step: say so, not an empty axis
            ax.text(0.5, 0.5, f"no tensions: {why}", transform=ax.transAxes, ha="center", va="center",
                    fontsize=10, color="0.3")
    if not plan.all_feasible:
        bad = ~plan.feasible
        axes[1].fill_between(plan.t, 0, 1, where=bad, color="red", alpha=0.15,
                             transform=axes[1].get_xaxis_transform(), label="infeasible steps")
    _legend_below(fig, axes, max_columns=8, hspace=0.2)
    axes[1].set_xlabel("t (s)")
    fig.suptitle(f"Cable tensions: {_plain(scenario.name)}", fontsize=11)
    return _save(fig, path, dpi=TENSION_FIGURE_DPI)


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


# ------------------------------------------------------------------ simulations
RUN_TITLES = {
    "open_loop": "open loop (plan fed forward)",
    "closed_loop": "closed loop (computed torque)",
    "fixed_base_open_loop": "fixed-base plan, open loop",
}
RUN_COLOURS = {"open_loop": "C0", "closed_loop": "C2", "fixed_base_open_loop": "C3"}
# the open loop (the paper's test) is drawn wide, pale and underneath, the closed loop thin
# on top, so that both stay visible where they coincide. All solid: a dashed line drawn
# through a decimated series (each pixel column's extremes, a zigzag) spends its dashes
# on the zigzag and looks solid, unlike its legend entry
RUN_STYLES = {"fixed_base_open_loop": dict(lw=1.3, ls="-"), "open_loop": dict(lw=3.0, ls="-", alpha=0.55),
              "closed_loop": dict(lw=1.0, ls="-")}


def _drawing_order(results: dict):
    """Runs in drawing order: the closed loop, usually the smallest error, last (on top)."""
    order = ["fixed_base_open_loop", "open_loop", "closed_loop"]
    return sorted(results.items(), key=lambda kv: order.index(kv[0]) if kv[0] in order else -1)


def _run_style(name: str) -> dict:
    return dict(color=RUN_COLOURS.get(name), **RUN_STYLES.get(name, dict(lw=1.0)))


def _legend_below(fig, axes, max_columns: int = 4, *, wspace: float = 0.2, hspace: float = 0.12) -> None:
    """One legend for the figure, below the axes, from every labelled artist of ``axes``.

    A figure without a layout engine gets fixed margins (:func:`_fixed_margins`) with room
    for the legend's rows: the main job's figures, where the constrained layout's measuring
    of every tick label took half the drawing time."""
    handles, labels = [], []
    for ax in np.ravel(axes):
        for h, lab in zip(*ax.get_legend_handles_labels()):
            if lab not in labels:
                handles.append(h)
                labels.append(lab)
    ncol = max(1, min(len(labels), max_columns))
    if fig.get_layout_engine() is not None:
        fig.legend(handles, labels, loc="outside lower center", ncol=ncol, fontsize=9)
        return
    while True:  # as many columns as fit across the figure
        legend = fig.legend(handles, labels, loc="lower center", bbox_to_anchor=(0.5, 0.005), ncol=ncol,
                            fontsize=9, frameon=False)
        if ncol == 1 or legend.get_window_extent(fig.canvas.get_renderer()).width <= 0.98 * fig.bbox.width:
            break
        legend.remove()
        ncol -= 1
    _fixed_margins(fig, legend_rows=-(-len(labels) // ncol), wspace=wspace, hspace=hspace)


LEGEND_ROW_IN = 0.24
"""Height of one row of a figure's legend (9-point text), inches."""


def _fixed_margins(fig, *, legend_rows: int, wspace: float, hspace: float, left_in: float = 0.9,
                   right_in: float = 0.2, top_in: float = 0.55, bottom_in: float = 0.55) -> None:
    """Margins in inches, whatever the figure's size: room for the y labels and log-scale tick
    labels on the left, the title on top, the x label and ``legend_rows`` rows of legend
    below. ``wspace``, ``hspace``: gaps between axes, as fractions of their width, height."""
    width, height = fig.get_size_inches()
    bottom = bottom_in + LEGEND_ROW_IN * legend_rows + 0.1
    fig.subplots_adjust(left=left_in / width, right=1.0 - right_in / width, top=1.0 - top_in / height,
                        bottom=min(bottom / height, 0.5), wspace=wspace, hspace=hspace)


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
    from matplotlib.ticker import LogFormatter, NullLocator

    fig, axes = plt.subplots(len(rows), 2, figsize=(11, row_height * len(rows) + 1.5), sharex=True,
                             squeeze=False)
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
            ax_e.plot(*decimate(res.t, np.where(err > 0, err, np.nan), columns), **_run_style(name))
        ax.plot(*decimate(first.t, value(first, True), columns), "k:", lw=1.1, label=planned_label)
        ax.set_ylabel(f"{label} ({'deg' if angular else 'm'})")
        ax_e.set_ylabel(f"|{label} error| ({unit_e})")
        if largest > 0:
            ax_e.set_yscale("log")
            # decades only: a log axis's minor ticks (eight a decade) were most of the
            # figure's drawing time
            ax_e.yaxis.set_minor_locator(NullLocator())
            ax_e.yaxis.set_major_formatter(LogFormatter())  # 1e-05, not mathtext (slow to lay out)
        ax.grid(alpha=0.3)
        ax_e.grid(alpha=0.3)
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
    fig, axes = plt.subplots(1, len(planes), figsize=(6.5 * len(planes), 6.0), squeeze=False)
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
    _legend_below(fig, axes[0, 0], wspace=0.25)
    fig.suptitle(f"Platform path in the robot frame C: {_plain(scenario.name)}", fontsize=11)
    return _save(fig, path)


# ------------------------------------------------------------ workspace, operability
def plot_workspace(ws, scenario: Scenario, path: Path) -> Path:
    """The workspace maps over the grid of a :func:`~marinecdpr.studies.workspace.workspace_map`:
    the fraction of time feasible, the smallest tension margin, and the fraction of time
    eq. (18) alone is feasible, with the frame anchors."""
    plt = _pyplot()
    panels = [
        (ws.fraction_feasible, "fraction of time feasible", "RdYlGn", (0, 1)),
        (np.where(np.isfinite(ws.min_margin_N), ws.min_margin_N, np.nan),
         "smallest tension margin (N), poses feasible throughout", "viridis", (None, None)),
        (ws.pinv_fraction_feasible, "fraction of time eq. (18) alone is feasible", "RdYlGn", (0, 1)),
    ]
    if ws.least_clearance_m is not None:  # the interference layer: red below the clearance
        from matplotlib.colors import TwoSlopeNorm

        gap = np.where(np.isfinite(ws.least_clearance_m), ws.least_clearance_m, np.nan)
        top = float(np.nanmax(gap)) if np.isfinite(gap).any() else 1.0
        panels.append((gap, f"least cable clearance (m); red below {ws.clearance_m:g} m", "RdYlGn",
                       TwoSlopeNorm(vcenter=ws.clearance_m, vmin=min(float(np.nanmin(gap)) if np.isfinite(gap).any()
                                                                     else 0.0, ws.clearance_m - 1e-9),
                                    vmax=max(top, ws.clearance_m + 1e-9))))
    fig, axes = plt.subplots(1, len(panels), figsize=(5 * len(panels), 4.8), constrained_layout=True)
    extent = (ws.u[0], ws.u[-1], ws.v[0], ws.v[-1])
    c = scenario.robot.frame_anchors
    i_u, i_v = "xyz".index(ws.axes[0]), "xyz".index(ws.axes[1])
    for ax, (data, title, cmap, scale) in zip(axes, panels):
        limits = {"norm": scale} if not isinstance(scale, tuple) else {"vmin": scale[0], "vmax": scale[1]}
        im = ax.imshow(data.T, origin="lower", extent=extent, cmap=cmap, aspect="equal", interpolation="nearest",
                       **limits)
        ax.plot(c[:, i_u], c[:, i_v], "ks", ms=6, label="frame anchors")
        ax.set_title(title, fontsize=9)
        ax.set_xlabel(f"{ws.axes[0]} in C (m)")
        ax.set_ylabel(f"{ws.axes[1]} in C (m)")
        fig.colorbar(im, ax=ax, shrink=0.8)
    fig.suptitle(f"Workspace under ship motion: {_plain(scenario.name)} ({scenario.base_motion.type}, "
                 f"{ws.n_steps} steps; {ws.fixed['axis']} = {ws.fixed['value_m']:g} m held)", fontsize=10)
    return _save(fig, path)


def plot_operability(op, scenario: Scenario, path: Path, *, workable: str | None = None) -> Path:
    """The operable sea states of an :func:`~marinecdpr.studies.operability.operability` study,
    one panel per heading: Hs by Tp, green where workable, each cell's probability in %.
    ``workable`` says what green means (default: the tensions with the study's margin)."""
    plt = _pyplot()
    k = len(op.headings_deg)
    fig, axes = plt.subplots(1, k, figsize=(6.5 * k, 5.2), squeeze=False, constrained_layout=True)
    from matplotlib.colors import ListedColormap

    cmap = ListedColormap(["#d73027", "#f46d43", "#fdae61", "#fee08b", "#d9ef8b", "#a6d96a", "#66bd63",
                           "#1a9850"])
    for ax, h in zip(axes[0], op.headings_deg):
        grid = op.probability_grid(h)
        image = ax.imshow(grid, origin="lower", cmap=cmap, vmin=0, vmax=1, aspect="auto",
                          extent=(-0.5, op.scatter.tp.size - 0.5, -0.5, op.scatter.hs.size - 0.5))
        for i in range(op.scatter.hs.size):  # the colour's number: the probability of success
            for j in range(op.scatter.tp.size):
                p = grid[i, j]
                if np.isfinite(p):
                    ax.text(j, i, _percent_text(p), ha="center", va="center", fontsize=CELL_FONT_PT[0],
                            color="white" if p < 0.2 or p > 0.8 else "black")
        ax.set_xticks(range(op.scatter.tp.size), [f"{v:g}" for v in op.scatter.tp])
        ax.set_yticks(range(op.scatter.hs.size), [f"{v:g}" for v in op.scatter.hs])
        ax.set_xlabel("Tp (s)")
        ax.set_ylabel("Hs (m)")
        lo, hi = (op.per_heading_interval or {}).get(h, (np.nan, np.nan))
        band = f" ({100 * lo:.1f}-{100 * hi:.1f} %)" if op.results and op.results[0].realisations > 1 else ""
        ax.set_title(f"heading {h:g} deg: operable {100 * op.per_heading[h]:.1f} %{band}", fontsize=10)
    realisations = op.results[0].realisations if op.results else 1
    if realisations > 1:
        fig.colorbar(image, ax=list(axes[0]), shrink=0.8, label=f"probability of success ({realisations} records)")
    workable = workable or f"workable with {op.margin_N:g} N margin"
    numbers = "probability of success, %" + (f" of {realisations} records" if realisations > 1 else "")
    fig.suptitle(f"Operability of {_plain(scenario.name)} (green: {workable}; numbers: {numbers}; "
                 "blank: no sea state)", fontsize=10)
    _fit_cell_numbers(fig, axes[0], op.scatter.tp.size, op.scatter.hs.size)
    return _save(fig, path)


CELL_FONT_PT = (7.0, 13.0)
"""Least and largest size of the numbers in a grid's cells, pt."""


def _fit_cell_numbers(fig, axes, columns: int, rows: int) -> None:
    """Size the numbers in each axes' grid of ``columns`` x ``rows`` cells to the cells as
    laid out (the widest number within 80 % of a cell's width, its height within half a
    cell's), between the sizes of :data:`CELL_FONT_PT`: they were 7 pt in cells of 60 pt."""
    fig.draw_without_rendering()  # the layout: each axes' size on the page
    renderer = fig.canvas.get_renderer()
    for ax in axes:
        if not ax.texts:
            continue
        box = ax.get_window_extent(renderer)
        cell_w, cell_h = box.width / columns, box.height / rows  # pixels
        size = 10.0
        for _ in range(3):  # text extents scale with the size but for the pixels' rounding
            for t in ax.texts:
                t.set_fontsize(size)
            widest = max(t.get_window_extent(renderer).width for t in ax.texts)
            tallest = max(t.get_window_extent(renderer).height for t in ax.texts)
            size = float(np.clip(size * min(0.8 * cell_w / widest, 0.5 * cell_h / tallest), *CELL_FONT_PT))
        for t in ax.texts:
            t.set_fontsize(size)


def _percent_text(p: float) -> str:
    """A probability in [0, 1] as a cell's percent: 100 and 0 only when exact."""
    if p >= 1.0:
        return "100"
    if p <= 0.0:
        return "0"
    return f"{min(max(100 * p, 0.1), 99.9):.3g}"


def _plain_axis(ax, values, *, least_span: float = 1.0) -> None:
    """A linear y axis in plain numbers (no offset, no scientific notation) spanning at
    least ``least_span`` about ``values``' middle: nearly equal values show as one level,
    not as ticks of 0.0004 under a "+1.2878e2"."""
    from matplotlib.ticker import MaxNLocator, ScalarFormatter

    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    formatter = ScalarFormatter(useOffset=False)
    formatter.set_scientific(False)
    ax.yaxis.set_major_formatter(formatter)
    ax.yaxis.set_major_locator(MaxNLocator(nbins=6, steps=[1, 2, 2.5, 5, 10]))
    if v.size:
        lo, hi = float(v.min()), float(v.max())
        if hi - lo < least_span:
            mid = 0.5 * (lo + hi)
            ax.set_ylim(mid - least_span, mid + least_span)


def plot_raos(rao, path: Path, *, title: str, beside=None, beside_label: str = "") -> Path:
    """|RAO| of heave (m/m), roll and pitch (deg/m) over omega, one line per heading; a
    second RAO (``beside``, e.g. the box approximation) dashed in the same colours; the
    legend outside the plots, on the right."""
    plt = _pyplot()
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.6), constrained_layout=True)
    rows = ((2, "heave (m/m)", 1.0), (3, "roll (deg/m)", 180.0 / np.pi), (4, "pitch (deg/m)", 180.0 / np.pi))
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for ax, (dof, label, scale) in zip(axes, rows):
        for j, h in enumerate(rao.heading_deg):
            colour = colours[j % len(colours)]
            ax.plot(rao.omega, scale * np.abs(rao.values[dof, j]), color=colour, lw=1.4, label=f"{h:g} deg")
            if beside is not None and h in beside.heading_deg:
                jb = list(beside.heading_deg).index(h)
                ax.plot(beside.omega, scale * np.abs(beside.values[dof, jb]), color=colour, lw=1.0, ls="--")
        ax.set_xlabel("omega (rad/s)")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    # the legend beside the plots, not over the heave axis's label and lines
    import textwrap

    from matplotlib.lines import Line2D

    handles, labels = axes[0].get_legend_handles_labels()
    if beside is not None:  # the dashed lines' meaning, as one more entry, wrapped narrow
        handles.append(Line2D([], [], color="0.4", lw=1.0, ls="--"))
        labels.append(textwrap.fill(f"dashed: {beside_label}", 24))
    fig.legend(handles, labels, loc="outside right upper", fontsize=8, title="heading", title_fontsize=8)
    fig.suptitle(_plain(title), fontsize=10)
    return _save(fig, path)


def plot_windows(series, windows, path: Path, *, title: str) -> Path:
    """Hs over the series, the operational limit, and the weather windows shaded (those
    long enough for the operation darker); where the series has a wind, a panel below of
    each sample's mean wind, with the wind limit where one was judged."""
    plt = _pyplot()
    if series.wind_m_s is None:
        fig, ax = plt.subplots(figsize=(12, 4.2), constrained_layout=True)
        axes = [ax]
    else:
        fig, axes = plt.subplots(2, 1, figsize=(12, 6.8), sharex=True, constrained_layout=True)
        ax = axes[0]
    shades = {True: 0.35, False: 0.12}
    labels = {True: f"window of at least {windows.duration_h:g} h (the operation fits)",
              False: f"window shorter than {windows.duration_h:g} h"}
    for a, b in windows.windows:
        long_enough = b - a >= windows.duration_h - 1e-12
        # each kind of shade labelled once, for the legend
        ax.axvspan(a, b, color="#1a9850", alpha=shades[long_enough], lw=0, label=labels.pop(long_enough, None))
        for other in axes[1:]:
            other.axvspan(a, b, color="#1a9850", alpha=shades[long_enough], lw=0)
    ax.step(series.t_h, series.hs_m, where="post", color="k", lw=1.0, label="Hs")
    ax.step(series.t_h, windows.limit_m, where="post", color="#d73027", lw=1.0,
            label=f"operational limit (alpha {windows.alpha:g} x design)")
    ax.set_ylabel("Hs (m)")
    if series.wind_m_s is not None:
        wind = axes[1]
        wind.step(series.t_h, series.wind_m_s, where="post", color="#4575b4", lw=1.0, label="mean wind at 10 m")
        if windows.wind_limit_m_s is not None:
            wind.axhline(windows.wind_limit_m_s, color="#d73027", lw=1.0,
                         label=f"operational wind limit {windows.wind_limit_m_s:g} m/s")
        else:
            wind.set_title("the wind is not judged (no wind limit): the windows are Hs's alone", fontsize=9)
        wind.set_ylabel("wind (m/s)")
        wind.legend(loc="upper right", fontsize=8)
    for a in axes:
        a.grid(alpha=0.3)
    axes[-1].set_xlabel("t (h)")
    ax.legend(loc="upper right", fontsize=8)
    ax.set_title(_plain(title), fontsize=10)
    return _save(fig, path)


def plot_control_study(study, prediction, path: Path) -> Path:
    """Closed-loop tracking error and tension margin against the motion sensor's latency,
    a line per prediction and pose source; beside them the ship-motion predictor's error
    against the horizon (:mod:`marinecdpr.studies.control`)."""
    from marinecdpr.studies.control import worst_moving_dof

    plt = _pyplot()
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.2), constrained_layout=True)
    styles = {"none": ("#d73027", "o"), "kinematic": ("#fc8d59", "s"), "ar": ("#1a9850", "^")}
    keys = sorted({(r.prediction, r.pose_from) for r in study.runs}, key=lambda k: (k[1], list(styles).index(k[0])))
    for k, (pred, source) in enumerate(keys):
        runs = sorted((r for r in study.runs if r.prediction == pred and r.pose_from == source),
                      key=lambda r: r.latency_s)
        ms = [1e3 * r.latency_s for r in runs]
        color, marker = styles[pred]
        # each later curve thinner, its markers smaller and hollow-centred: curves that
        # coincide still all show, each as its legend entry draws it
        share = k / max(len(keys) - 1, 1)  # 0 for the first (widest, underneath), 1 for the last
        style = dict(ls="-" if source == "sensor" else "--", color=color, marker=marker, lw=3.0 - 2.2 * share,
                     ms=12.0 - 8.0 * share, mfc="none" if source != "sensor" else color, mew=1.2)
        label = f"{pred}, pose from {source}"
        axes[0].plot(ms, [r.rms_error_m for r in runs], label=label, **style)
        axes[1].plot(ms, [r.headroom_N for r in runs], label=label, **style)
    axes[0].set_yscale("log")
    axes[0].set_ylabel("RMS position error (m)")
    axes[1].set_ylabel("smallest headroom below the tension limit (N)")
    _plain_axis(axes[1], [r.headroom_N for r in study.runs])
    for ax in axes[:2]:
        ax.set_xlabel("motion sensor latency (ms)")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    axes[0].set_title(_plain(f"{study.scenario}: tracking after {study.settle_s:g} s "
                             f"(MRU {study.rate_hz:g} Hz)"), fontsize=10)
    axes[1].set_title("tension headroom", fontsize=10)
    ax = axes[2]
    drawn = False
    for k, (name, err, color) in enumerate((("predictor", prediction.predictor, "#1a9850"),
                                            ("kinematic", prediction.taylor, "#fc8d59"),
                                            ("hold", prediction.hold, "#d73027"))):
        rows = worst_moving_dof(prediction, err)
        ok = np.isfinite(rows) & (rows > 0)
        if ok.any():  # layered as on the left: the predictor's line shows under the kinematic one
            ax.plot(prediction.horizons_s[ok], rows[ok], "-o", color=color, label=name, lw=max(3.0 - k, 1.0),
                    ms=max(9.0 - 2.0 * k, 4.0))
            drawn = True
    if drawn:
        ax.set_xscale("log")
        ax.set_yscale("log")
    else:
        ax.text(0.5, 0.5, "the ship does not move, or the record is too short", ha="center", va="center",
                transform=ax.transAxes, fontsize=9)
    ax.set_xlabel("prediction horizon (s)")
    ax.set_ylabel("RMS error / RMS motion (worst DOF)")
    ax.grid(alpha=0.3)
    if drawn:
        ax.legend(fontsize=8)
    ax.set_title("ship motion prediction", fontsize=10)
    return _save(fig, path)
