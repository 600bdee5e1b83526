"""The faults study's files (:mod:`marinecdpr.studies.faults`): ``faults.csv`` (a row per
fault), ``summary.json``, ``faults.png`` (each fault's trajectory in the frame) and
``report.html`` (the table and the figure). Each file written whole or not at all."""

from __future__ import annotations

from dataclasses import asdict
from pathlib import Path

import numpy as np

from marinecdpr.report.figures import _plain, _pyplot, _save
from marinecdpr.report.files import write_json
from marinecdpr.report.page import embedded_figures, render_page
from marinecdpr.report.writers import _write_table
from marinecdpr.scenario.schema import Scenario

__all__ = ["faults_summary", "write_faults", "plot_fault_trajectories", "FAULT_COLUMNS", "fault_label", "sea_label",
           "breaking_load_said"]

FAULT_COLUMNS = ("kind", "cable", "moment", "at_s", "acted_s", "detected", "detection_delay_s", "detection",
                 "reaction", "brakes_held", "max_deviation_m", "max_displacement_m", "max_speed_m_s", "end_deviation_m",
                 "end_speed_m_s", "within_frame",
                 "frame_time_s", "frame_speed_m_s", "frame_energy_J", "hull_speed_m_s", "hull_energy_J",
                 "peak_tension_N", "peak_cable", "working_limit_N", "breaking_N", "static_margin_N", "verdict", "hs_m",
                 "tp_s", "heading_deg")
"""``faults.csv``'s columns (:class:`~marinecdpr.studies.faults.FaultRow`'s fields)."""


def fault_label(row) -> str:
    """``"cable_snap, cable 1, at 12.3 s (highest tension)"``, and ``", Hs 2 m, Tp 8 s"`` where
    flown in a sea state."""
    where = f", cable {row.cable}" if row.cable is not None else ""
    sea = f", Hs {row.hs_m:g} m, Tp {row.tp_s:g} s, {row.heading_deg:g} deg" if np.isfinite(row.hs_m) else ""
    return f"{row.kind}{where}, at {row.at_s:g} s ({row.moment}){sea}"


def sea_label(sea: dict) -> str:
    """``"Hs 2 m, Tp 8 s, heading 150 deg"``."""
    return f"Hs {sea['hs_m']:g} m, Tp {sea['tp_s']:g} s, heading {sea['heading_deg']:g} deg"


def breaking_load_said(robot) -> str:
    """Whether the robot's breaking loads (``breaking_load_N``) are given, or its working
    limits (``tension_max_N``) stand in: "given (breaking_load_N)", "not given: each cable's
    working limit (tension_max_N) stands in", or which cables have one."""
    given = robot.breaking_load_given
    if given.all():
        return "given (breaking_load_N)"
    if not given.any():
        return "not given: each cable's working limit (tension_max_N) stands in"

    def cables(mask):
        idx = np.flatnonzero(mask) + 1
        return ("cable " if idx.size == 1 else "cables ") + ", ".join(str(i) for i in idx)
    return (f"given for {cables(given)} (breaking_load_N); for {cables(~given)} the working limit (tension_max_N) "
            "stands in")


def _cell(v):
    if isinstance(v, bool):
        return int(v)
    if v is None:
        return ""
    if isinstance(v, float) and not np.isfinite(v):
        return ""
    return float(v) if isinstance(v, (float, np.floating)) else v


def _json(v):
    if isinstance(v, float) and not np.isfinite(v):
        return None
    return v


def faults_summary(study, scenario: Scenario) -> dict:
    """``summary.json``'s content: the study's settings, each fault's row, and how many are safe."""
    return {"scenario": scenario.name, "plant": study.plant, "sea_states": [s or None for s in study.seas],
            "after_s": study.after_s,
            "cables": scenario.robot.n_cables, "faults": len(study.rows),
            "safe": sum(r.verdict == "safe" for r in study.rows), "unsafe": len(study.unsafe),
            "breaking_load": breaking_load_said(scenario.robot),
            "verdict_meaning": ("safe: the platform's body stays within the frame's box, does not meet the hull, "
                                "no remaining cable passes its breaking load (breaking_load_N; where not given, its "
                                "working limit tension_max_N stands in), and a fault that acted "
                                "was detected or kept the platform within the error bound, and at the run's end the "
                                "platform is on its plan (within the error bound) or at rest; else the first reason "
                                "it is not"),
            "rows": [{k: _json(v) for k, v in asdict(r).items()} for r in study.rows]}


def plot_fault_trajectories(study, scenario: Scenario, path: Path) -> Path:
    """Each fault's trajectory: the platform's x and z in C over the run, the frame's outline,
    where the fault struck (a dot) and where the run ended (a cross)."""
    plt = _pyplot()
    n = max(len(study.rows), 1)
    cols = min(n, 4)
    rows = int(np.ceil(n / cols))
    fig, axes = plt.subplots(rows, cols, figsize=(3.2 * cols, 2.8 * rows), squeeze=False)
    c = scenario.robot.frame_anchors
    lo, hi = c.min(axis=0), c.max(axis=0)
    h = scenario.time.step_s
    for i, ax in enumerate(axes.flat):
        if i >= len(study.rows):
            ax.axis("off")
            continue
        row, (t, x) = study.rows[i], study.traces[i]
        ax.plot([lo[0], hi[0], hi[0], lo[0], lo[0]], [lo[2], lo[2], hi[2], hi[2], lo[2]], color="0.4", lw=1.0)
        if t.size:
            k = min(int(round(row.acted_s / h)), t.size - 1)
            ax.plot(x[:k + 1, 0], x[:k + 1, 2], color="C0", lw=0.8, label="before")
            ax.plot(x[k:, 0], x[k:, 2], color="C3", lw=1.0, label="after")
            ax.plot(x[k, 0], x[k, 2], "o", color="C3", ms=4)
            ax.plot(x[-1, 0], x[-1, 2], "x", color="k", ms=5)
        sea = f", Hs {row.hs_m:g}" if len(study.seas) > 1 else ""
        ax.set_title(_plain(f"{row.kind}" + (f" {row.cable}" if row.cable else "") + f" @{row.at_s:g} s{sea}: "
                            + ("safe" if row.verdict == "safe" else "NOT safe")), fontsize=8)
        ax.set_aspect("equal", adjustable="datalim")
        ax.tick_params(labelsize=7)
        ax.set_xlabel("x in C, m", fontsize=7)
        ax.set_ylabel("z in C, m", fontsize=7)
    fig.suptitle(_plain(f"{scenario.name}: each fault's trajectory (blue before, red after; frame in grey)"),
                 fontsize=9)
    fig.tight_layout()
    return _save(fig, path)


def write_faults(study, scenario: Scenario, folder: Path, *, figures: bool = True) -> list[Path]:
    """``faults.csv``, ``summary.json``, ``faults.png`` and ``report.html`` in ``folder``;
    without ``figures`` no PNG, and the report says the figure was not drawn."""
    folder = Path(folder)
    rows = [[_cell(getattr(r, c)) for c in FAULT_COLUMNS] for r in study.rows]
    paths = [_write_table(list(FAULT_COLUMNS), rows, folder / "faults.csv")]
    summary = faults_summary(study, scenario)
    paths.append(write_json(summary, folder / "summary.json"))
    figure = plot_fault_trajectories(study, scenario, folder / "faults.png") if figures else None
    if figure is not None:
        paths.append(figure)
    facts = [("robot", f"{scenario.robot.n_cables} cables, {scenario.robot.dofs}"), ("plant", study.plant),
             ("sea states", "; ".join(sea_label(sea) for sea in study.seas) if study.seas[0]
              else scenario.base_motion.type.replace("_", " ")),
             ("flown after each fault", f"{study.after_s:g} s, closed loop with the controller's watch"),
             ("cables' breaking load", breaking_load_said(scenario.robot)),
             ("faults", f"{len(study.rows)}: {len(study.rows) - len(study.unsafe)} safe, {len(study.unsafe)} not")]

    def fmt(v, unit="", digits=3):
        return "–" if v is None or (isinstance(v, float) and not np.isfinite(v)) else f"{v:.{digits}g}{unit}"

    table = [[fault_label(r), "yes, after " + fmt(r.detection_delay_s, " s") if r.detected else "no", r.reaction,
              fmt(r.max_deviation_m, " m"), fmt(r.max_speed_m_s, " m/s"),
              "yes" if r.within_frame else "no",
              fmt(r.frame_speed_m_s, " m/s") + " / " + fmt(r.frame_energy_J, " J"),
              fmt(r.hull_speed_m_s, " m/s") + " / " + fmt(r.hull_energy_J, " J"),
              f"{fmt(r.peak_tension_N, ' N', 4)} (cable {r.peak_cable}) of {fmt(r.working_limit_N, ' N', 4)} / "
              f"{fmt(r.breaking_N, ' N', 4)}",
              fmt(r.static_margin_N, " N", 4), r.verdict] for r in study.rows]
    paths.append(render_page("faults.html", folder / "report.html", name=scenario.name,
                             description=scenario.description, facts=facts, table=table,
                             figures=embedded_figures(None if figure is None else {
                                 "Figure 1: each fault's trajectory in the frame C (x, z)": figure}), view=""))
    return paths
