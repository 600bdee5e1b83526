"""The cleaning job's files: clean.csv, coverage.png, cleaning.png, summary.json, report.html."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from marinecdpr.report.figures import (
    FIGURE_DPI, _figure_columns, _legend_below, _plain, _pyplot, _save, decimate, length_unit, plot_operability,
)
from marinecdpr.report.files import _write_csv, write_json
from marinecdpr.report.text import _fmt_length, describe_base_motion
from marinecdpr.report.view3d import view_section

if TYPE_CHECKING:
    from marinecdpr.studies.cleaning import CleaningFigures

__all__ = ["CLEAN_COLUMNS", "write_cleaning", "plot_coverage", "plot_cleaning_series", "cleaning_findings",
           "SEA_STATE_COLUMNS", "write_cleaning_seas", "cleaning_seas_summary"]

CLEAN_COLUMNS = ("t", "brush_x_m", "brush_y_m", "brush_z_m", "brush_x_planned_m", "brush_z_planned_m",
                 "normal_force_N", "in_band", "cross_track_error_m")
"""The first columns of clean.csv; the cable tensions T1..Tn follow."""


def write_clean_csv(job, path: Path) -> Path:
    """One row per step: time (s), the brush's centre in C actual (x, y, z) and planned
    (x, z), m, the normal force (N), in band (1/0), the cross-track error (m), the applied
    tensions T1..Tn (N)."""
    res = job.result
    m = res.tensions.shape[1]
    names = list(CLEAN_COLUMNS) + [f"T{i}" for i in range(1, m + 1)]
    values = np.column_stack([res.t, job.brush, job.brush_planned[:, [0, 2]], job.normal_force,
                              job.in_band.astype(float), job.cross_track, res.tensions])
    return _write_csv(names, values, path, int_last=False, int_columns=(CLEAN_COLUMNS.index("in_band"),))


def plot_coverage(job, path: Path) -> Path:
    """A map of the panel: cleaned once, twice or more, missed; the panel and holes outlined,
    the brush's actual path drawn thin."""
    plt = _pyplot()
    from matplotlib.colors import ListedColormap

    cov, cleaning = job.coverage, job.scenario.cleaning
    shown = np.where(cov.passes < 0, np.nan, np.minimum(cov.passes, 2))
    width = max(float(np.ptp(cov.x)), 1e-3)
    height = max(float(np.ptp(cov.z)), 1e-3)
    fig, ax = plt.subplots(figsize=(9.0, min(9.0, max(3.5, 8.0 * height / width)) + 1.2))
    cmap = ListedColormap(["#d73027", "#91cf60", "#1a9850"])
    h = cov.resolution_m
    ax.imshow(shown, origin="lower", cmap=cmap, vmin=-0.5, vmax=2.5, interpolation="nearest",
              extent=(cov.x[0] - h / 2, cov.x[-1] + h / 2, cov.z[0] - h / 2, cov.z[-1] + h / 2))
    for poly in [cleaning.panel_m] + list(cleaning.holes_m):
        p = np.asarray(poly + [poly[0]])
        ax.plot(p[:, 0], p[:, 1], "k-", lw=1.0)
    ax.plot(job.brush[:, 0], job.brush[:, 2], color="k", lw=0.4, alpha=0.5, label="brush centre (actual)")
    for colour, label in (("#d73027", "missed"), ("#91cf60", "cleaned once"), ("#1a9850", "cleaned twice or more")):
        ax.fill_between([], [], color=colour, label=label)
    s = job.figures
    ax.set_title(f"{s.coverage_pct:.2f} % of the panel cleaned ({s.reachable_coverage_pct:.2f} % of what a "
                 f"round brush can reach), {s.overlap_pct:.1f} % overlap", fontsize=10)
    ax.set_xlabel("x in C (m)")
    ax.set_ylabel("z in C (m)")
    ax.set_aspect("equal")
    _legend_below(fig, ax, max_columns=4, wspace=0.2)
    fig.suptitle(f"Coverage of the panel: {_plain(job.scenario.name)}", fontsize=11)
    return _save(fig, path)


CROSS_TRACK_COLOUR = "#762a83"
"""The cross-track error's line in cleaning.png: dark purple, in no cable's colour (tab10's)."""


def plot_cleaning_series(job, path: Path) -> Path:
    """Over time: the cable tensions, the normal force within its band, the cross-track error."""
    plt = _pyplot()
    res, cleaning = job.result, job.scenario.cleaning
    fig, axes = plt.subplots(3, 1, figsize=(11, 8.5), sharex=True)
    columns = _figure_columns(fig, FIGURE_DPI)
    for i in range(res.tensions.shape[1]):
        axes[0].plot(*decimate(res.t, res.tensions[:, i], columns), lw=1.0, label=f"cable {i + 1}")
    robot = job.scenario.robot
    for j, v in enumerate(np.unique(np.concatenate([robot.tension_min, robot.tension_max]))):
        axes[0].axhline(v, color="k", ls="--", lw=0.8, label="tension limits" if j == 0 else None)
    axes[0].set_ylabel("tension (N)")
    lo, hi = cleaning.band_N
    axes[1].plot(*decimate(res.t, job.normal_force, columns), color="k", lw=1.0, label="normal force")
    axes[1].axhspan(lo, hi, color="#1a9850", alpha=0.15, label="band")
    axes[1].set_ylabel("normal force (N)")
    size, unit = length_unit(float(job.cross_track.max()) if job.cross_track.size else 0.0)
    # a colour of its own: the cables take the colour cycle (tab10), the normal force black
    axes[2].plot(*decimate(res.t, job.cross_track / size, columns), color=CROSS_TRACK_COLOUR, lw=1.0,
                 label="cross-track error")
    axes[2].set_ylabel(f"cross-track error ({unit})")
    axes[2].set_xlabel("t (s)")
    for ax in axes:
        ax.grid(alpha=0.3)
    _legend_below(fig, axes, max_columns=8, hspace=0.15)
    fig.suptitle(f"Tensions, normal force and tracking while cleaning: {_plain(job.scenario.name)}", fontsize=11)
    return _save(fig, path)


def cleaning_findings(figures: CleaningFigures, *, hull: dict | None = None,
                      comparison: dict | None = None) -> list[str]:
    """What the numbers say, in sentences written from them: the job's ``figures``, with the
    ``hull`` estimate (:func:`~marinecdpr.studies.cleaning.ship_side`) and the ``comparison``
    (:func:`~marinecdpr.studies.cleaning.compare_conditions`) where made."""
    s = figures
    out = [f"The brush cleaned {s.coverage_pct:.2f} % of the {s.panel_area_m2:.3g} m2 panel "
           f"({s.reachable_coverage_pct:.2f} % of the {s.reachable_area_m2:.3g} m2 a round brush of "
           f"{s.brush_width_m:g} m can reach); {s.missed_area_m2:.3g} m2 missed.",
           _path_sentence(s),
           f"The normal force stayed within its band {s.normal_force_in_band_pct:.2f} % of the time "
           f"(contact lost {s.contact_lost_s:.2f} s).",
           f"Tensions {s.tension_min_N:.1f} .. {s.tension_max_N:.1f} N; {s.infeasible_steps} infeasible "
           f"steps in the plan; cross-track error at most {_length(s.max_cross_track_error_m)} "
           f"(95 % below {_length(s.p95_cross_track_error_m)}); winches {s.winch_energy_kJ:.3g} kJ."]
    if s.controller_verdict == "bypassed":
        from marinecdpr.studies.prototype_runs import bypassed_text

        out.insert(0, "The job FAILED: " + bypassed_text(s.controller_fallbacks, s.steps,
                                                         s.controller_bypassed_share_max) + ".")
    if hull is not None:
        out.append(f"A hull of {hull['hull_area_m2']:g} m2 takes {hull['placements']} placements of the frame: "
                   f"{hull['hours']:.1f} h with {hull['move_time_s']:g} s per move ({hull['area_rate_m2_h']:.3g} m2/h)"
                   + (f", estimated from the partial run's first {s.job_time_s:.1f} s." if s.partial else "."))
    cmp = comparison or {}
    here = cmp.get("as asked")
    if here and "calm water" in cmp:
        calm = cmp["calm water"]
        out.append(f"The sea: in calm water the brush would clean {calm['coverage_pct']:.2f} % of the panel (here "
                   f"{here['coverage_pct']:.2f} %), with the normal force {_span(calm, 'normal_force')} (here "
                   f"{_span(here, 'normal_force')}) and the tensions {_span(calm, 'tension')} (here "
                   f"{_span(here, 'tension')}); cross-track error at most {_length(calm['max_cross_track_error_m'])} "
                   f"(here {_length(here['max_cross_track_error_m'])}).")
    if here and "no brush drag" in cmp:
        free = cmp["no brush drag"]
        out.append(f"The brush: without its drag (friction and jet 0, the same preload) the tensions would span "
                   f"{_span(free, 'tension')} (with it {_span(here, 'tension')}), the cross-track error at most "
                   f"{_length(free['max_cross_track_error_m'])} (with it {_length(here['max_cross_track_error_m'])}) "
                   f"and the winches {free['winch_energy_kJ']:.3g} kJ (with it {here['winch_energy_kJ']:.3g} kJ).")
    out.append("Model: the brush's drag and moment on the prototype follow its simulated velocity; "
               + ("the cables hold the brush on the hull at the preload, the normal force (a spatial robot's "
                  "cables control the platform along the normal)." if s.robot_dofs == "spatial" else
                  "the normal force is the pusher's preload plus the platform's inertia and weight along the hull "
                  "normal from the plan (the guide holds the platform along the normal)."))
    return out


def _path_sentence(s: CleaningFigures) -> str:
    """The path and the rate; for a partial run (``partial``: the run ended before the path)
    the part flown, labelled, beside the whole path's length and time."""
    if not s.partial:
        return (f"{s.lanes} lanes {s.lane_spacing_m:.3g} m apart, {s.path_length_m:.3g} m of path in "
                f"{s.job_time_s:.1f} s: {s.area_rate_m2_h:.3g} m2/h"
                + (f"; the pass along the edges the lanes leave takes {s.boundary_pass_length_m:.3g} m and "
                   f"{s.boundary_pass_time_s:.1f} s of it." if s.boundary_pass_length_m > 0 else "."))
    edges = ""
    if s.boundary_pass_length_m > 0:
        edges = (f"; {s.boundary_pass_flown_m:.3g} m of it along the edges (of the pass's "
                 f"{s.boundary_pass_length_m:.3g} m)" if s.boundary_pass_flown_m > 0 else
                 f"; the pass along the edges ({s.boundary_pass_length_m:.3g} m) not reached")
    return (f"A PARTIAL run: {s.path_flown_m:.3g} m of the {s.path_length_m:.3g} m path ({s.lanes} lanes "
            f"{s.lane_spacing_m:.3g} m apart, {s.path_duration_s:.1f} s) flown in the first "
            f"{s.job_time_s:.1f} s: {s.area_rate_m2_h:.3g} m2/h over the part flown, not the whole job's"
            f"{edges}.")


def _length(v: float) -> str:
    """A length for a sentence, in the unit its size reads in (mm, µm, nm)."""
    return _fmt_length(v) if v > 0 else "0 mm"


def _span(figures: dict, what: str) -> str:
    return f"{figures[what + '_min_N']:.1f} .. {figures[what + '_max_N']:.1f} N"


def _pct(v: float) -> str:
    return f"{v:.2f} %"


FIGURES = {
    "coverage_pct": ("panel cleaned", _pct),
    "reachable_coverage_pct": ("of what a round brush can reach, cleaned", _pct),
    "missed_area_m2": ("area missed", lambda v: f"{v:.3g} m²"),
    "overlap_pct": ("overlap: of the area cleaned, cleaned twice or more", lambda v: f"{v:.1f} %"),
    "area_rate_m2_h": ("area rate", lambda v: f"{v:.3g} m²/h"),
    "normal_force_in_band_pct": ("normal force within its band, of the time", _pct),
    "normal_force_min_N": ("smallest normal force", lambda v: f"{v:.1f} N"),
    "normal_force_max_N": ("largest normal force", lambda v: f"{v:.1f} N"),
    "contact_lost_s": ("normal force out of band for", lambda v: f"{v:.2f} s"),
    "tension_min_N": ("smallest cable tension", lambda v: f"{v:.1f} N"),
    "tension_max_N": ("largest cable tension", lambda v: f"{v:.1f} N"),
    "max_cross_track_error_m": ("largest cross-track error", _length),
    "p95_cross_track_error_m": ("cross-track error, 95th percentile", _length),
    "winch_energy_kJ": ("winch energy, sum of |T L'| dt", lambda v: f"{v:.3g} kJ"),
    "controller_fallbacks": ("steps the controller was bypassed (the plan's tensions fed forward)",
                             lambda v: f"{v:d}"),
    "controller_bypassed_share": ("controller bypassed, of the steps", lambda v: f"{100.0 * v:.3g} %"),
}
"""The job's figures as the report shows them: ``summary.json`` key -> (name, value with its unit)."""


def _figure_row(key: str, value: float) -> tuple[str, str]:
    name, fmt = FIGURES[key]
    return name, fmt(value)


def _comparison_rows(comparison: dict) -> tuple[list[str], list[tuple[str, list[str]]]]:
    """The job beside calm water and without the brush's drag: the variants' names, and a row
    per figure (its name, its value in each variant)."""
    names = list(comparison)
    return names, [(FIGURES[k][0], [_figure_row(k, comparison[n][k])[1] for n in names])
                   for k in (comparison[names[0]] if names else ())]


def write_cleaning_html(job, figures: dict | None, path: Path, *, hull: dict | None = None,
                        comparison: dict | None = None) -> Path:
    """The job's page (:func:`~marinecdpr.report.page.render_page`): the scenario, the job's
    figures (``job.figures``), what they say, the ``hull`` estimate and the job beside calm
    water and without the brush's drag (``comparison``) where made, the figures (``figures``:
    caption to PNG; None: the page says they were not drawn) and the robot on the ship in 3D."""
    from markupsafe import Markup

    from marinecdpr.report.page import embedded_figures, render_page

    sc, s = job.scenario, job.figures
    c = sc.cleaning
    facts = [("robot", f"{sc.robot.dofs}, {sc.robot.n_cables} cables, {sc.robot.mass_kg:g} kg"),
             ("base motion", describe_base_motion(sc.base_motion)),
             ("brush", f"{c.brush}, {c.brush_diameter_m:g} m, friction {c.friction:g}, preload {c.preload:g} N, "
                       f"band {c.band_N[0]:g} .. {c.band_N[1]:g} N"),
             ("path", f"{s.lanes} lanes, spacing {s.lane_spacing_m:.3g} m, {s.path_length_m:.3g} m, "
                      f"{s.path_duration_s:.1f} s at up to {c.speed_m_s:g} m/s"),
             ("pass along the edges", f"{s.boundary_pass_length_m:.3g} m, {s.boundary_pass_time_s:.1f} s of "
                                      "the path" if s.boundary_pass_length_m > 0 else "none")]
    table = [_figure_row(k, getattr(s, k)) for k in FIGURES]
    if s.partial:  # the run ended before the path: its figures are the part flown's
        table = [(f"{name} (over the part flown)", value) if name == FIGURES["area_rate_m2_h"][0] else (name, value)
                 for name, value in table]
        table.insert(5, ("job time (a PARTIAL run)", f"{s.job_time_s:.1f} s of the path's "
                                                     f"{s.path_duration_s:.1f} s"))
        table.insert(6, ("path flown", f"{s.path_flown_m:.3g} m of {s.path_length_m:.3g} m"))
    else:
        table.insert(5, ("job time", f"{s.job_time_s:.1f} s"))
    table.append(("controller", "BYPASSED: a failed run" if s.controller_verdict == "bypassed" else "held"))
    if hull is not None:
        table += [("hull", f"{hull['hull_area_m2']:g} m², {hull['placements']} placements of the frame, "
                           f"{hull['move_time_s']:g} s per move"),
                  ("hull: time", f"{hull['hours']:.1f} h"),
                  ("hull: area rate, moves included", f"{hull['area_rate_m2_h']:.3g} m²/h")]
    variants, rows = _comparison_rows(comparison or {})
    return render_page("clean.html", path, name=sc.name, description=sc.description, facts=facts, numbers=table,
                       notes=cleaning_findings(s, hull=hull, comparison=comparison), variants=variants,
                       comparison=rows,
                       figures=embedded_figures(figures), view=Markup(view_section(sc, job.plan)))


def write_cleaning(job, folder: Path, *, hull: dict | None = None, comparison: dict | None = None,
                   summary: dict | None = None, figures: bool = True) -> list[Path]:
    """Every file of the cleaning job in ``folder``, with the ``hull`` estimate and the
    ``comparison`` where made; ``summary.json`` holds ``summary`` (default ``job.summary``).
    Without ``figures`` no PNG is drawn and the report says so. Returns the paths written."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    paths = [write_clean_csv(job, folder / "clean.csv")]
    drawn = None
    if figures:
        drawn = {"Figure 1: coverage of the panel from the simulated brush":
                     plot_coverage(job, folder / "coverage.png"),
                 "Figure 2: tensions, normal force and cross-track error":
                     plot_cleaning_series(job, folder / "cleaning.png")}
        paths += list(drawn.values())
    paths.append(write_json(job.summary if summary is None else summary, folder / "summary.json"))
    paths.append(write_cleaning_html(job, drawn, folder / "report.html", hull=hull, comparison=comparison))
    return paths


SEA_STATE_COLUMNS = ("heading_deg", "hs_m", "tp_s", "probability", "works", "coverage_pct", "reachable_coverage_pct",
                     "normal_force_in_band_pct", "tension_min_N", "tension_max_N", "job_time_s", "hours")
"""The columns of sea_states.csv (``clean --scatter``), one row per sea state and heading."""


def _number_or_none(x: float) -> float | None:
    return float(x) if np.isfinite(x) else None


def cleaning_seas_summary(cs, scenario) -> dict:
    """``summary.json`` of the cleaning job over a scatter diagram
    (:func:`~marinecdpr.studies.cleaning.cleaning_seas`): the share of sea states the job
    works in, per heading, the limiting Hs, the expected hours, and why each failing sea
    state fails."""
    from marinecdpr.studies.operability import LIMITING_HS_MEANING

    return {
        "scenario": scenario.name,
        "what_works": (f"the plan's tensions within limits at every step, the closed loop's controller not bypassed "
                       f"(on at most simulation.max_bypassed_share of the steps), "
                       f"at least {cs.coverage_target_pct:g} % of the reachable panel cleaned and the normal "
                       f"force in band at least {cs.in_band_target_pct:g} % of the time"),
        "coverage_target_pct": cs.coverage_target_pct,
        "in_band_target_pct": cs.in_band_target_pct,
        "operability": cs.sea.operability,
        "per_heading": {f"{h:g}": v for h, v in cs.sea.per_heading.items()},
        "limiting_hs_m": cs.sea.limiting_hs_json(),
        "limiting_hs_meaning": LIMITING_HS_MEANING,
        "hours_for": "the hull" if cs.hull_area_m2 is not None else "one panel",
        "hull_area_m2": cs.hull_area_m2,
        "expected_hours": _number_or_none(cs.expected_hours),
        "expected_hours_meaning": "hours of the job averaged over the sea states it works in, by probability",
        "expected_hours_with_weather": _number_or_none(cs.expected_hours_with_weather),
        "expected_hours_with_weather_meaning": "expected_hours / operability: calendar hours when the work waits "
                                               "for workable sea states",
        "sea_states": len(cs.sea.results),
        "steps_per_sea_state": int(scenario.time.n_steps),
        "not_working": [{"heading_deg": r.cell.heading_deg, "hs_m": r.cell.hs, "tp_s": r.cell.tp, "reason": r.reason}
                        for r in cs.sea.results if not r.operable],
    }


def write_cleaning_seas(cs, scenario, folder: Path, *, figures: bool = True) -> list[Path]:
    """The cleaning job over a scatter diagram (:func:`~marinecdpr.studies.cleaning.cleaning_seas`):
    ``sea_states.csv`` (one row per sea state: its verdict and figures; empty cells where
    the job could not be flown), ``summary.json`` (the share of sea states the job works
    in, per heading, the limiting Hs, the expected hours, and why each failing sea state
    fails) and, with ``figures``, ``sea_states.png`` (the workable sea states, one panel per heading). A wind
    that follows the sea state (``[wind] with_sea``) adds each sea state's wind to the CSV:
    ``wind_m_s`` and ``wind_direction_deg``."""
    from marinecdpr.studies.operability import cell_winds

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    rows = [[r.cell.heading_deg, r.cell.hs, r.cell.tp, r.cell.probability, float(r.operable), r.coverage_pct,
             r.reachable_coverage_pct, r.in_band_pct, r.tension_min_N, r.tension_max_N, r.job_time_s, r.hours]
            for r in cs.sea.results]
    names = list(SEA_STATE_COLUMNS)
    values = np.array(rows, dtype=float).reshape(-1, len(SEA_STATE_COLUMNS))
    winds = cell_winds(scenario, [r.cell for r in cs.sea.results])
    if winds is not None and len(rows):
        names += ["wind_m_s", "wind_direction_deg"]
        values = np.column_stack([values, winds])
    paths = [_write_csv(names, values, folder / "sea_states.csv", int_last=False,
                        int_columns=(SEA_STATE_COLUMNS.index("works"),))]
    paths.append(write_json(cleaning_seas_summary(cs, scenario), folder / "summary.json"))
    if not figures:
        return paths
    paths.append(plot_operability(cs.sea, scenario, folder / "sea_states.png", workable=(
        f"the cleaning job works: >= {cs.coverage_target_pct:g} % of reach cleaned, force in band "
        f">= {cs.in_band_target_pct:g} % of the time")))
    return paths


def write_surface(sj, folder: Path, *, figures: bool = True) -> list[Path]:
    """``placements.csv`` (one row per frame placement on ``[cleaning.surface]``: its patch's
    stations and heights, the plane's centre and normal in S, the surface's offsets from the
    plane, the patch's extent in the plane, its area and cleaning time; the patches too curved
    for the tolerance last, with ``cleanable`` 0 and no cleaning time, 0 s) and, with
    ``figures``, ``surface.png`` (the side, x along the ship and z up, each placement coloured by its minutes, and by its
    stand-off deviation). With ``[cleaning.surface.relocation]`` each row also says which robot
    visits it (``robot``, from 1), its place in that robot's visits (``visit``, from 1), the
    move into it (``move_in_s``, 0 at a robot's first) and whether a crane made it
    (``by_crane``); the patches too curved have 0 there.

    Parameters
    ----------
    sj : marinecdpr.studies.surface.SurfaceJob
    """
    folder = Path(folder)
    names = ["x0_m", "x1_m", "z0_m", "z1_m", "centre_x_m", "centre_y_m", "centre_z_m", "normal_x", "normal_y",
             "normal_z", "offset_min_m", "offset_max_m", "extent_x_m", "extent_z_m", "area_m2", "job_s", "cleanable"]
    def row(p, job_s: float, cleanable: float) -> list:
        return [*p.x_range, *p.z_range, *p.centre_S, *p.normal_S, *p.offset_range_m, *p.extent_m, p.area_m2, job_s,
                cleanable]

    rows = [row(p, t, 1.0) for p, t in zip(sj.placements, sj.job_s)] + [row(p, 0.0, 0.0) for p in sj.uncleanable]
    if sj.moves is not None:  # with [cleaning.surface.relocation]: who visits each placement, when, and how
        m, n = sj.moves, len(sj.placements)
        extra = np.zeros((len(rows), 4))
        first = np.concatenate([[0], np.flatnonzero(np.diff(m.robot)) + 1])
        visit = np.arange(n) - first[np.searchsorted(first, np.arange(n), side="right") - 1]
        extra[m.order] = np.column_stack([m.robot + 1, visit + 1, m.move_in_s, m.kind == "crane"])
        names = names[:-1] + ["robot", "visit", "move_in_s", "by_crane", "cleanable"]
        rows = [r[:-1] + list(e) + r[-1:] for r, e in zip(rows, extra)]
    csv = _write_csv(names, np.array(rows, dtype=float).reshape(-1, len(names)), folder / "placements.csv",
                     int_last=True)
    if not figures:
        return [csv]
    plt = _pyplot()
    from matplotlib.collections import PatchCollection
    from matplotlib.patches import Rectangle

    fig, axes = plt.subplots(2, 1, figsize=(12, 6.4), constrained_layout=True, sharex=True)
    for ax, values, label, cmap in ((axes[0], sj.job_s / 60.0, "cleaning time per placement (min)", "viridis"),
                                    (axes[1], np.array([p.deviation_m for p in sj.placements]) * 1e3,
                                     "stand-off deviation from the frame's plane (mm)", "magma")):
        rects = [Rectangle((p.x_range[0], p.z_range[0]), p.x_range[1] - p.x_range[0], p.z_range[1] - p.z_range[0])
                 for p in sj.placements]
        coll = PatchCollection(rects, cmap=cmap, edgecolor="white", linewidth=0.2)
        coll.set_array(np.asarray(values, dtype=float))
        ax.add_collection(coll)
        if sj.uncleanable:
            ax.add_collection(PatchCollection(
                [Rectangle((p.x_range[0], p.z_range[0]), p.x_range[1] - p.x_range[0], p.z_range[1] - p.z_range[0])
                 for p in sj.uncleanable], facecolor="0.6", edgecolor="none"))
        ax.autoscale_view()
        ax.set_ylabel("z in S (m)")
        fig.colorbar(coll, ax=ax, label=label, shrink=0.9)
    axes[1].set_xlabel("x in S (m, from amidships)")
    fig.suptitle(_plain(f"{len(sj.placements)} placements of the frame, each cleaning its {sj.frame_panel_m[0]:g} x "
                        f"{sj.frame_panel_m[1]:g} m panel: {sj.hours:.4g} h ({sj.moves_said()}); "
                        f"{sj.surface}"), fontsize=9)
    return [csv, _save(fig, folder / "surface.png")]


STRIP_COLUMNS = ("visit", "s_m", "origin_x_m", "origin_y_m", "origin_z_m", "roll_deg", "pitch_deg", "yaw_deg",
                 "clean_s", "move_in_s", "hours", "coverage_pct", "stand_off_min_m", "stand_off_max_m",
                 "normal_force_min_N", "normal_force_max_N", "in_band_pct", "beyond_tolerance", "by_crane")
"""``stations.csv``'s columns (:func:`write_strip`)."""
STRETCH_COLUMNS = ("stretch", "s_start_m", "s_end_m", "stations", "stepped_h", "continuous_h", "continuous_speed_m_s",
                   "continuous")
"""``stretches.csv``'s columns (:func:`write_strip`): each followed stretch of the rail, its hours
stepped and continuous (empty where it cannot run continuously), and the mode taken (1 continuous)."""


def write_strip(strip, folder: Path) -> list[Path]:
    """``stations.csv``: one row per visit of a strip cleaned from a rail
    (:class:`~marinecdpr.studies.strip.RailStrip`), in the order made: its place in the
    visits (from 1), the rail station's arc length (empty for a crane placement), the frame's
    pose in S (C's origin, m; roll, pitch, yaw, deg; a crane placement's plane centre and
    axes, mirrored to a starboard side), its cleaning, the move into it and their hours, the share of its panel's footprint
    on the hull it cleaned, the hull's stand-off from the frame's plane under the brush, the
    normal force on the hull, the share of the steps in band (empty for crane placements:
    they are tiled as ``clean --surface`` tiles them), whether the stand-off passes the
    tool's tolerance, and whether a crane made the move into it; a continuous run's row is
    its first station's, its cleaning the whole run's. ``stretches.csv``: each followed stretch
    of the rail, its hours either way and the mode taken (:data:`STRETCH_COLUMNS`). With
    continuous runs flown (:attr:`~marinecdpr.studies.strip.RailStrip.flights`),
    ``continuous_flight.csv`` the first's, ``continuous_flight_2.csv``, ... the others': a row
    per step (:func:`flight_columns`)."""
    from marinecdpr.geometry.rotations import euler_from_matrix

    rows = []
    beyond = strip.beyond_tolerance
    nan = float("nan")
    n = strip.s_m.size
    run_beyond = strip.run_beyond_tolerance
    for i, (v, move, crane) in enumerate(zip(strip.visits, strip.move_in_s, strip.by_crane)):
        if v >= n:  # a continuous run: its first station, its whole run
            r = strip.runs[v - n]
            pose = np.degrees(euler_from_matrix(r.axes_S))
            rows.append([i + 1, r.s_m[0], *r.origin_S, *pose, r.duration_s, move, (r.duration_s + move) / 3600.0,
                         strip.coverage.station_pct[v], *r.stand_off_m, *r.force_N, r.in_band_pct,
                         float(run_beyond[v - n]), float(crane)])
        elif v >= 0:
            pose = np.degrees(euler_from_matrix(strip.axes_S[v]))
            rows.append([i + 1, strip.s_m[v], *strip.origin_S[v], *pose, strip.clean_s, move,
                         (strip.clean_s + move) / 3600.0, strip.coverage.station_pct[v], *strip.stand_off_m[v],
                         *strip.force_N[v], strip.in_band_pct[v], float(beyond[v]), float(crane)])
        else:
            p, t = strip.crane[-1 - v], strip.crane_s[-1 - v]
            pose = np.degrees(euler_from_matrix(np.asarray(p.axes_S, dtype=float)))
            mirror = np.array([1.0, strip.side_sign, 1.0])  # a starboard side's placements are tiled as |y|
            rows.append([i + 1, nan, *(np.asarray(p.centre_S) * mirror), *(pose * mirror), t, move, (t + move) / 3600.0, nan, *p.offset_range_m,
                         nan, nan, nan, float(p.deviation_m > strip.tolerance_m), float(crane)])
    values = np.array(rows, dtype=float).reshape(-1, len(STRIP_COLUMNS))
    stretches = np.array([[c.stretch + 1, *c.s_m, c.stations, c.stepped_h,
                           nan if c.continuous_h is None else c.continuous_h,
                           nan if c.continuous_speed_m_s is None else c.continuous_speed_m_s,
                           float(c.mode == "continuous")] for c in strip.choices], dtype=float)
    tail = [_write_csv(list(STRETCH_COLUMNS), stretches.reshape(-1, len(STRETCH_COLUMNS)),
                       Path(folder) / "stretches.csv", int_last=True, int_columns=(0, 3))]
    for j, flight in enumerate(strip.flights):
        tail.append(_write_flight(flight, Path(folder) / ("continuous_flight.csv" if j == 0
                                                          else f"continuous_flight_{j + 1}.csv")))
    return [_write_csv(list(STRIP_COLUMNS), values, Path(folder) / "stations.csv", int_last=True,
                       int_columns=(0, STRIP_COLUMNS.index("beyond_tolerance")))] + tail


def flight_columns(n_cables: int) -> list[str]:
    """``continuous_flight.csv``'s columns: the time; the flown and planned brush's contact on the
    hull in the run's first C (x, z; the panel on the ship), m; the hull's stand-off under the
    flown brush, m; its normal force on the hull, N; whether it cleans (1/0); its distance from
    the planned brush and the part across its travel, m; the cables' tensions, N."""
    return (["t_s", "hull_x_m", "hull_z_m", "planned_hull_x_m", "planned_hull_z_m", "stand_off_m", "normal_force_N",
             "in_band", "tracking_error_m", "cross_track_error_m"] + [f"T{i + 1}_N" for i in range(n_cables)])


def _write_flight(flight, path: Path) -> Path:
    """``continuous_flight.csv`` (at ``path``) of a :class:`~marinecdpr.studies.strip.RunFlight`."""
    h, p = flight.hull, flight.planned
    values = np.column_stack([flight.t, h.on_ship[:, 0], h.on_ship[:, 2], p.on_ship[:, 0], p.on_ship[:, 2],
                              h.stand_off_m, h.force_N, h.contact.astype(float), flight.tracking_m,
                              flight.cross_track_m, flight.tensions])
    return _write_csv(flight_columns(flight.tensions.shape[1]), values, path, int_last=False, int_columns=(7,))
