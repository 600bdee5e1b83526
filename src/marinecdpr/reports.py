"""Files a plan and its simulations produce: CSVs, figures like the paper's 5-7, a report.

Every file is written to a temporary name beside its target and renamed into
place when complete, so an interrupted run never leaves a half-written file.
"""

from __future__ import annotations

import os
import tempfile
from contextlib import contextmanager
from pathlib import Path
from typing import Iterator

import numpy as np

from .planning import TWIST_NAMES, Plan
from .scenario import Scenario

__all__ = [
    "atomic_path",
    "plan_columns",
    "write_plan_csv",
    "plot_tensions",
    "write_sim_csv",
    "plot_cable_lengths",
    "plot_tracking",
    "write_json",
    "write_report_html",
    "write_virtual_prototype",
    "write_workspace",
    "write_operability",
]


@contextmanager
def atomic_path(path: Path, suffix: str = "") -> Iterator[Path]:
    """A temporary path in ``path``'s folder, renamed to ``path`` if the block succeeds."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=suffix, dir=path.parent)
    os.close(fd)
    try:
        yield Path(tmp)
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)


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
            fmt = ",".join(["%.10g"] * (len(names) - 1) + ["%d" if int_last else "%.10g"])
            text_rows = (fmt % tuple(row) for row in values)
            fh.write("\n".join(text_rows).replace("nan", ""))
            fh.write("\n")
    return path


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
    for ax, T, title in zip(axes, (plan.tensions_pinv, plan.tensions), titles):
        for i in range(robot.n_cables):
            ax.plot(plan.t, T[:, i], label=f"cable {i + 1}", lw=1.2)
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
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside lower center", ncol=min(8, robot.n_cables + 1), fontsize=9)
    if not plan.all_feasible:
        bad = ~plan.feasible
        axes[1].fill_between(plan.t, 0, 1, where=bad, color="red", alpha=0.15,
                             transform=axes[1].get_xaxis_transform(), label="infeasible")
    axes[1].set_xlabel("t (s)")
    fig.suptitle(f"Cable tensions: {scenario.name}", fontsize=11)
    path = Path(path)
    with atomic_path(path, suffix=path.suffix) as tmp:
        fig.savefig(tmp, dpi=120)
    plt.close(fig)
    return path


# ------------------------------------------------------------------ simulations
RUN_TITLES = {
    "open_loop": "open loop (plan fed forward)",
    "closed_loop": "closed loop (computed torque)",
    "fixed_base_open_loop": "fixed-base plan, open loop",
}
RUN_COLOURS = {"open_loop": "C0", "closed_loop": "C2", "fixed_base_open_loop": "C3"}


def _drawing_order(results: dict):
    """Runs in drawing order: the closed loop, usually the smallest error, last (on top)."""
    order = ["fixed_base_open_loop", "open_loop", "closed_loop"]
    return sorted(results.items(), key=lambda kv: order.index(kv[0]) if kv[0] in order else -1)


def _legend_on_top(fig, ax) -> None:
    handles, labels = ax.get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside lower center", ncol=len(labels), fontsize=9)


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


def _save(fig, path: Path) -> Path:
    import matplotlib.pyplot as plt

    path = Path(path)
    with atomic_path(path, suffix=path.suffix) as tmp:
        fig.savefig(tmp, dpi=110)
    plt.close(fig)
    return path


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _planned_vs_actual(results: dict, rows: list, *, planned_label: str, actual_prefix: str,
                       row_height: float, title: str, path: Path) -> Path:
    """Two columns per row: planned and each run's actual value, and actual minus planned.

    ``rows``: (label, unit, scale, error unit, error scale, value) with ``value(res, planned)``
    the (n_steps,) series of a SimResult (planned or actual).
    """
    plt = _pyplot()
    fig, axes = plt.subplots(len(rows), 2, figsize=(11, row_height * len(rows) + 1.5), sharex=True,
                             squeeze=False, constrained_layout=True)
    first = next(iter(results.values()))
    for (ax, ax_e), (label, unit, k, unit_e, ke, value) in zip(axes, rows):
        for name, res in _drawing_order(results):
            ax.plot(res.t, k * value(res, False), color=RUN_COLOURS.get(name), lw=0.9,
                    label=actual_prefix + RUN_TITLES.get(name, name))
            ax_e.plot(res.t, ke * (value(res, False) - value(res, True)), color=RUN_COLOURS.get(name), lw=0.7)
        ax.plot(first.t, k * value(first, True), "k--", lw=1.0, label=planned_label)
        ax.set_ylabel(f"{label} ({unit})")
        ax_e.set_ylabel(f"{label} error ({unit_e})")
        ax.grid(alpha=0.3)
        ax_e.grid(alpha=0.3)
    _legend_on_top(fig, axes[0, 0])
    axes[-1, 0].set_xlabel("t (s)")
    axes[-1, 1].set_xlabel("t (s)")
    fig.suptitle(title, fontsize=11)
    return _save(fig, path)


def plot_cable_lengths(results: dict, scenario: Scenario, path: Path) -> Path:
    """Like the paper's figure 6: planned and actual cable lengths, and their difference."""
    rows = [(f"L{i + 1}", "m", 1.0, "mm", 1e3,
             lambda res, planned, i=i: (res.lengths_planned if planned else res.lengths)[:, i])
            for i in range(scenario.robot.n_cables)]
    return _planned_vs_actual(results, rows, planned_label="planned (kinematics)", actual_prefix="actual, ",
                              row_height=1.9, path=path,
                              title=f"Cable lengths, planned and on the virtual prototype: {scenario.name}")


def plot_tracking(results: dict, scenario: Scenario, path: Path) -> Path:
    """Like the paper's figure 7: planned and actual pose, and the tracking errors."""
    pose_names, dofs = _pose_names(scenario)
    deg = float(np.degrees(1.0))
    rows = [(name, "deg" if i >= 3 else "m", deg if i >= 3 else 1.0, "deg" if i >= 3 else "mm",
             deg if i >= 3 else 1e3,
             lambda res, planned, i=i: (res.pose_planned if planned else res.pose)[:, i])
            for name, i in zip(pose_names, dofs)]
    return _planned_vs_actual(results, rows, planned_label="planned", actual_prefix="", row_height=2.2,
                              path=path, title=f"Tracking on the virtual prototype: {scenario.name}")


def write_json(data: dict, path: Path) -> Path:
    import json

    path = Path(path)
    with atomic_path(path) as tmp:
        Path(tmp).write_text(json.dumps(data, indent=2) + "\n", encoding="utf-8")
    return path


def write_report_html(summary: dict, scenario: Scenario, figures: dict[str, Path], path: Path) -> Path:
    """One self-contained page: the scenario, every figure, and the paper's errors beside ours."""
    import base64
    import html

    from .analysis import PAPER_REPORTED

    runs = [r for r in ("open_loop", "closed_loop", "fixed_base_open_loop") if r in summary]
    esc = html.escape

    def fmt(v: float, unit: str) -> str:
        if unit == "deg":
            return f"{v:.3g} deg"
        for scale, name in ((1e3, "mm"), (1e6, "µm"), (1e9, "nm")):
            if v * scale >= 1.0 or name == "nm":
                return f"{v * scale:.3g} {name}"
        return f"{v:.3g} m"

    rows = []
    metrics = [("max |error| x", "max_abs_error_x_m", "m"), ("max |error| z", "max_abs_error_z_m", "m"),
               ("max |error| angle", "max_abs_error_theta_deg", "deg")]
    for label, key, unit in metrics:
        cells = "".join(f"<td>{fmt(summary[r][key], unit)}</td>" for r in runs)
        rows.append(f"<tr><th>{label}</th><td>{fmt(PAPER_REPORTED[key], unit)}</td>{cells}</tr>")
    cells = "".join(
        f"<td>{fmt(max(summary[r]['max_abs_cable_length_error_m']), 'm')} (cable "
        f"{int(np.argmax(summary[r]['max_abs_cable_length_error_m'])) + 1})</td>" for r in runs)
    rows.append(f"<tr><th>max |error| cable length</th><td>150 mm (cable 2)</td>{cells}</tr>")
    cells = "".join(f"<td>{summary[r]['tension_min_N']:.1f} .. {summary[r]['tension_max_N']:.1f} N</td>"
                    for r in runs)
    rows.append(f"<tr><th>applied tensions</th><td>–</td>{cells}</tr>")
    cells = "".join(
        "<td>within</td>" if summary[r]["tension_limit_excess_N"] == 0 else
        f"<td><b>outside by {summary[r]['tension_limit_excess_N']:.2f} N</b></td>" for r in runs)
    limits = (f"{scenario.robot.tension_min.min():g} .. {scenario.robot.tension_max.max():g} N")
    rows.append(f"<tr><th>tension limits ({limits})</th><td>–</td>{cells}</tr>")
    head = "".join(f"<th>{esc(RUN_TITLES[r])}</th>" for r in runs)
    sim = scenario.simulation
    r = scenario.robot
    facts = [
        ("robot", f"{r.dofs}, {r.n_cables} cables, {r.mass_kg:g} kg, tensions "
                  f"{r.tension_min.min():g} .. {r.tension_max.max():g} N"),
        ("base motion", scenario.base_motion.type + (
            "" if scenario.base_motion.type == "still" else ": " + ", ".join(
                f"{c.dof} {c.amplitude_deg if c.amplitude_deg is not None else c.amplitude_m:g}"
                f"{' deg' if c.amplitude_deg is not None else ' m'} / {c.period_s:g} s"
                for c in scenario.base_motion.components))),
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
    imgs = []
    for caption, fig_path in figures.items():
        data = base64.b64encode(Path(fig_path).read_bytes()).decode("ascii")
        imgs.append(f'<figure><img src="data:image/png;base64,{data}" alt="{esc(caption)}">'
                    f"<figcaption>{esc(caption)}</figcaption></figure>")
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
<h2>Tracking errors, the paper's and ours</h2>
<table><thead><tr><th></th><th>paper (Adams, open loop)</th>{head}</tr></thead>
<tbody>{''.join(rows)}</tbody></table>
<p>Errors are the largest of actual minus planned over the run. The paper's figures are
from its section 4.2 (open loop on Adams, 1 ms exchange). With ideal cables our plan and
the plant share one model, so open loop is exact but for the 1 ms hold of the tensions;
the <i>fixed-base</i> column is the comparable one: a plan from a model that leaves out
the ship, flown on the moving ship, errs as the paper's Adams run did. With elastic
cables, winch lag and sensor noise, open loop has no damping of its own and noise drives
its oscillations up; the closed loop holds them down.</p>
<h2>Figures</h2>
{''.join(imgs)}
</body></html>
"""
    path = Path(path)
    with atomic_path(path) as tmp:
        Path(tmp).write_text(page, encoding="utf-8")
    return path


def write_virtual_prototype(vp, folder: Path) -> list[Path]:
    """Every file of the main job in ``folder``: plan.csv, sim_<run>.csv, the figures,
    summary.json and report.html. Returns the paths written."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    sc = vp.scenario
    paths = [write_plan_csv(vp.plan, sc, folder / "plan.csv")]
    for name, res in vp.results.items():
        paths.append(write_sim_csv(res, sc, folder / f"sim_{name}.csv"))
    figures = {
        "Figure 5: cable tensions (a) from eq. (18) and (b) after optimisation":
            plot_tensions(vp.plan, sc, folder / "tensions.png"),
        "Figure 6: cable lengths, planned (kinematics) and actual (virtual prototype)":
            plot_cable_lengths(vp.results, sc, folder / "cable_lengths.png"),
        "Figure 7: planned and actual pose, and the tracking errors":
            plot_tracking(vp.results, sc, folder / "tracking.png"),
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
    fig.suptitle(f"Workspace under ship motion: {scenario.name} ({scenario.base_motion.type}, "
                 f"{ws.n_steps} steps; {ws.fixed['axis']} = {ws.fixed['value_m']:g} m held)", fontsize=10)
    return [csv_path, _save(fig, folder / "workspace.png")]


def write_operability(op, scenario: Scenario, folder: Path) -> list[Path]:
    """``operability.csv`` (one row per sea state), ``operability.json`` and ``operability.png``."""
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
        "limiting_hs_m": {f"{h:g}": {f"{tp:g}": (None if np.isnan(v) else float(v))
                                     for tp, v in zip(op.scatter.tp, lim)}
                          for h, lim in op.limiting_hs.items()},
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
    fig.suptitle(f"Operability of {scenario.name} (green: workable with {op.margin_N:g} N margin; "
                 "numbers: probability %)", fontsize=10)
    paths.append(_save(fig, folder / "operability.png"))
    return paths
