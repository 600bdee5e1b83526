"""The design study's files (``marinecdpr design``): every candidate, the Pareto front and its
figure, the search's convergence, the finalists as ready-to-run scenarios, and the summary."""

from __future__ import annotations

import dataclasses

import csv
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from marinecdpr.report.figures import _plain, _pyplot, _save
from marinecdpr.report.files import write_json
from marinecdpr.scenario.design import CONTINUOUS
from marinecdpr.studies.design import CONSTRAINTS, candidate_scenario, study_constraints
from marinecdpr.textfiles import atomic_path

__all__ = ["write_design", "design_summary", "DrawingGeometry", "drawing_geometry",
           "pareto_figure", "convergence_figure",
           "finalists_figure", "objective_label", "CANDIDATE_COLUMNS", "FINALIST_COLUMNS", "BREAKDOWN", "safety_text"]


_HEAD = ["index", "generation"]
_AFTER = ["winch", "rope", "pattern", "mass_kg", "tension_max_N", "placements", "frame_turn_median_deg",
          "frame_turn_max_deg", "surface_hours", "sea_share", "expected_hours", "power_kW", "cost"]
CANDIDATE_COLUMNS = (_HEAD + [*CONTINUOUS] + _AFTER + [f"margin_{k}" for k in CONSTRAINTS] + ["feasible", "reason"])
"""candidates.csv's and pareto.csv's columns."""
RELOCATION_COLUMNS = ["relocation", "robots", "relocation_cost", "rail_moves", "crane_moves"]
"""The columns a study that sets the frame's moves or the robots (``[relocation]``, or
``relocation``/``robots`` among its variables) adds after ``cost``."""


@dataclass(frozen=True)
class _Layout:
    """What a study's candidates.csv holds beyond :data:`CANDIDATE_COLUMNS`: the relocation's
    columns (:data:`RELOCATION_COLUMNS`, after ``cost``), the carriage's limits it makes
    variables (after the continuous variables; blank in a candidate moved otherwise) and its
    constraints (:func:`~marinecdpr.studies.design.study_constraints`: ``margin_rail_accel_m_s2``
    where a candidate may move by rail)."""

    relocates: bool = False
    rail: tuple = ()
    constraints: tuple = CONSTRAINTS


def _layout(spec) -> _Layout:
    return _Layout(relocates=spec.relocates, rail=tuple(spec.rail_variables), constraints=study_constraints(spec))


def _columns(layout: _Layout = _Layout()) -> list[str]:
    return (_HEAD + [*CONTINUOUS, *layout.rail] + _AFTER + (RELOCATION_COLUMNS if layout.relocates else [])
            + [f"margin_{k}" for k in layout.constraints] + ["feasible", "reason"])


def _row(i: int, gen: int, e, layout: _Layout = _Layout()) -> list:
    def num(v):
        return "" if v is None or not np.isfinite(v) else f"{v:.10g}"

    moved = ([e.x.get("relocation", ""), e.x.get("robots", ""), num(e.relocation_cost), e.rail_moves, e.crane_moves]
             if layout.relocates else [])
    on_rail = e.x.get("relocation") == "rail"
    rail = [num(e.x[k]) if on_rail and k in e.x else "" for k in layout.rail]
    return ([i, gen, *(num(e.x[k]) for k in CONTINUOUS), *rail, e.x["winch"], e.x["rope"],
             e.x.get("pattern", "uncrossed"),
             num(e.mass_kg), num(e.tension_max_N), e.placements, *(num(v) for v in e.frame_turn_deg),
             num(e.surface_hours), num(e.sea_share),
             num(e.expected_hours), num(e.power_kW), num(e.cost)] + moved
            + [num(e.margins.get(k, float("nan"))) for k in layout.constraints] + [int(e.feasible), e.reason])


def _write_rows(path: Path, rows: list[list], layout: _Layout = _Layout()) -> Path:
    with atomic_path(path) as tmp:
        with open(tmp, "w", encoding="utf-8", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(_columns(layout))
            w.writerows(rows)
    return path


BREAKDOWN = (("cleaning", "cleaning"), ("turns", "turns between lanes"), ("moves", "moving the frame"),
             ("weather", "waiting for weather"))
"""The parts of a design's expected hours (:meth:`~marinecdpr.studies.design.Evaluation.hours_breakdown`)
and how the report names them."""


def objective_label(spec) -> str:
    """The second objective as an axis or column label, with its unit."""
    if spec.objective == "power":
        return "installed winch power (kW)"
    from marinecdpr.scenario.design import PATTERN_CABLES

    unit = spec.cost_unit or "the catalogue's units"
    counts = sorted({PATTERN_CABLES[p] for p in spec.choices("pattern")})
    gear = (f"{counts[0]} winches and {counts[0]} ropes" if len(counts) == 1
            else f"{', '.join(str(n) for n in counts[:-1])} or {counts[-1]} winches and ropes (one a cable)")
    if spec.relocates:
        return f"cost of each robot's {gear}, and of the moves ({unit})"
    return f"cost of {gear} ({unit})"


def _finite(v):
    return v if not isinstance(v, float) or np.isfinite(v) else None


def _short(e, objective: str) -> dict:
    keys = ("placements", "surface_hours", "sea_share", "expected_hours", "power_kW", "cost", "tension_max_N",
            "mass_kg", "frame_turn_deg", "sea_reason")
    moved = ({"relocation": {"cost": e.relocation_cost, "rail_moves": e.rail_moves, "crane_moves": e.crane_moves}}
             if "relocation" in e.x or e.relocation_cost or e.rail_moves or e.crane_moves else {})
    return {"variables": dict(e.x), **{k: getattr(e, k) for k in keys}, "feasible": e.feasible,
            "objective": e.objective(objective),
            "hours": {k: _finite(v) for k, v in e.hours_breakdown().items()},
            "binding": [{"constraint": k, "margin": _finite(float(e.margins[k])), "slack": v}
                        for k, v in e.binding()]} | moved


def rail_move_text(v) -> str:
    """A rail finalist's move in the time domain, as a sentence."""
    m = v.rail_move
    said = (f"Finalist {v.rank}'s frame carried {m.distance_m:.3g} m along its rail ({m.move_s:.3g} s) in "
            f"Hs {m.hs:g} m, Tp {m.tp:.3g} s, heading {m.heading_deg:g} deg, the platform held: ")
    if not m.works:
        return said + f"fails: {m.reason}."
    return said + (f"the cables between {m.tension_min_N:.4g} and {m.tension_max_N:.4g} N, the platform within "
                   f"{1000 * m.excursion_m:.3g} mm of its place, the drive's force up to {m.drive_force_N:.3g} N.")


def design_summary(study, verification=None) -> dict:
    """``summary.json``: the study, its best designs by expected hours (the front), each with
    its hours in parts (``hours``: cleaning, turns, moves, weather) and its binding
    constraints (``binding``: the margins nearest their limit, slack = margin / capacity),
    the baseline, whether the target is met, and the finalists' time-domain figures
    (``verified`` false: none was flown)."""
    spec = study.spec
    ev = study.evaluations
    front = [_short(ev[i], spec.objective) | {"index": i} for i in study.front]
    return {
        "study": spec.name, "objective": spec.objective, "objective_label": objective_label(spec),
        "targets": spec.targets.model_dump(),
        "candidates": len(ev), "feasible": study.feasible, "seed": spec.seed,
        "population": spec.population, "generations": spec.generations,
        "front": front, "best": front[0] if front else None,
        "target_met": study.target_met,
        "baseline": _short(study.baseline, spec.objective),
        "screen": "expected hours = placements' cleaning and moves / the share of sea states the fast screen "
                  "passes (studies.screen: frequency-domain extremes, conservative)",
        "verified": bool(verification),
        "finalists": [dataclasses.asdict(v) for v in verification or []],
    } | ({"constraints": spec.constraints.model_dump(), "safety": safety_text(study)}
         if spec.constraints.single_cable_failure else {})


FINALIST_COLUMNS = ["rank", "index", "winch", "rope", "power_kW", "cost", "surface_hours", "cleaning_hours",
                    "turn_hours", "move_hours", "weather_hours", "expected_hours", "binding_1", "slack_1",
                    "binding_2", "slack_2", "screen_share", "td_share", "screen_expected_hours", "td_expected_hours",
                    "td_weather_hours", "agree", "screen_works_td_fails", "screen_fails_td_works", "plant"]
"""finalists.csv's columns: the screen's hours in parts, the two binding constraints, and
(where flown, else empty) the time domain's."""


def _finalist_rows(study, verification) -> list[list]:
    def num(v):
        return "" if v is None or (isinstance(v, float) and not np.isfinite(v)) else (
            f"{v:.10g}" if isinstance(v, float) else v)

    td = {v.index: v for v in verification or []}
    rows = []
    for rank, i in enumerate(study.front[:study.spec.finalists], start=1):
        e, v = study.evaluations[i], td.get(i)
        b = e.binding() + [("", float("nan"))] * 2
        h = e.hours_breakdown()
        flown = ([v.screen_share, v.td_share, v.screen_expected_hours, v.td_expected_hours,
                  v.td_expected_hours - v.surface_hours, v.agree, v.screen_works_td_fails, v.screen_fails_td_works,
                  v.plant] if v is not None else [None] * 9)
        rows.append([num(c) for c in [rank, i, e.x["winch"], e.x["rope"], e.power_kW, e.cost, e.surface_hours,
                                      h["cleaning"], h["turns"], h["moves"], h["weather"], e.expected_hours,
                                      b[0][0], b[0][1], b[1][0], b[1][1], *flown]])
    return rows


def _plain_log(axis) -> None:
    """A log axis labelled with plain numbers (40, not 4x10^1) at its decades and, within a
    decade or two, at 2 and 5 times them (and 3 and 7 within one)."""
    from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

    lo, hi = axis.get_view_interval()
    plain = FuncFormatter(lambda v, _: f"{v:g}")
    axis.set_major_formatter(plain)
    span = hi / max(lo, 1e-300)
    if span <= 10.0:  # within a decade: mark 1, 2, 3, 5 and 7 in each
        axis.set_major_locator(LogLocator(base=10.0, subs=(1.0, 2.0, 3.0, 5.0, 7.0)))
    elif span < 100.0:  # a decade or two: 1, 2 and 5
        axis.set_major_locator(LogLocator(base=10.0, subs=(1.0, 2.0, 5.0)))
    axis.set_minor_formatter(NullFormatter())


def _spread(values) -> float:
    """The relative spread (max - min) / max of positive values (0 for fewer than two)."""
    v = np.asarray([x for x in values if np.isfinite(x)], dtype=float)
    return float(np.ptp(v) / np.abs(v).max()) if v.size > 1 and np.abs(v).max() > 0 else 0.0


TRADE_OFF_SPREAD = 0.01
"""A front whose objectives each spread by less than this share of their largest value is
drawn as one design, not a trade-off (its figure says so)."""


def pareto_figure(study):
    """pareto.png's figure: every candidate by its expected hours against its installed power
    (or cost, with its unit) on a log hours axis labelled with plain numbers; the infeasible
    ones drawn (grey: a constraint not met, at their hours; a cross along the top: works in
    no sea state or cannot be built, so no hours); the front; the target. A front whose
    objectives spread by less than :data:`TRADE_OFF_SPREAD` is said to be one design."""
    spec, ev = study.spec, study.evaluations
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(7, 4.5), constrained_layout=True)
    ok = [e for e in ev if e.feasible and np.isfinite(e.expected_hours)]
    short = [e for e in ev if not e.feasible and np.isfinite(e.expected_hours)]
    none = [e for e in ev if not np.isfinite(e.expected_hours) and np.isfinite(e.objective(spec.objective))]
    hours = [e.expected_hours for e in ok + short] + [spec.targets.hours]
    lo, hi = min(hours), max(hours)
    if short:
        ax.scatter([e.objective(spec.objective) for e in short], [e.expected_hours for e in short], s=12, c="0.6",
                   marker="s", label=f"infeasible: a constraint not met ({len(short)})")
    if ok:
        ax.scatter([e.objective(spec.objective) for e in ok], [e.expected_hours for e in ok], s=14, c="tab:blue",
                   label=f"feasible ({len(ok)})")
    if none:
        ax.scatter([e.objective(spec.objective) for e in none], [0.97] * len(none), s=18, c="0.4", marker="x",
                   transform=ax.get_xaxis_transform(), clip_on=False,
                   label=f"infeasible: no hours (works in no sea state, or cannot be built) ({len(none)})")
    note = ""
    if study.front:
        f = np.array([[ev[i].objective(spec.objective), ev[i].expected_hours] for i in study.front])
        order = np.argsort(f[:, 0])
        ax.plot(f[order, 0], f[order, 1], "o-", c="tab:red", label=f"Pareto front ({len(study.front)})")
        ds, dh = _spread(f[:, 0]), _spread(f[:, 1])
        if len(study.front) > 1 and ds < TRADE_OFF_SPREAD and dh < TRADE_OFF_SPREAD:
            note = (f"\nthe front's designs differ by {100 * dh:.2g} % in hours and {100 * ds:.2g} % in "
                    f"{'power' if spec.objective == 'power' else 'cost'}: no trade-off")
    ax.axhline(spec.targets.hours, c="k", ls="--", lw=0.8, label=f"target {spec.targets.hours:g} h")
    ax.set_yscale("log")
    ax.set_ylim(lo / 1.3, hi * 1.3 * (1.25 if none else 1.0))
    xs = [e.objective(spec.objective) for e in ok + short + none]
    if xs:
        ax.set_xlim(0.0, 1.08 * max(xs))  # from zero: the installed power's (or cost's) share is read off
    _plain_log(ax.yaxis)
    ax.set_xlabel(_plain(objective_label(spec)))
    ax.set_ylabel("expected hours for the surface")
    ax.set_title(_plain(f"{spec.name}: {_count(len(ev), 'candidate')}, {len(ok)} feasible{note}"), fontsize=9)
    ax.legend(fontsize=7, loc="upper right")
    return fig


def convergence_figure(study):
    """convergence.png's figure: the best feasible expected hours after each generation
    (whole generations on the axis), a log axis labelled with plain numbers."""
    from matplotlib.ticker import MaxNLocator

    spec, ev = study.spec, study.evaluations
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(7, 3.5), constrained_layout=True)
    gens = np.arange(int(study.generation.max()) + 1) if len(ev) else np.zeros(0, dtype=int)
    best, running = [], float("inf")
    for g in gens:
        hours = [e.expected_hours for e, gg in zip(ev, study.generation) if gg == g and e.feasible]
        running = min([running, *hours])
        best.append(running)
    shown = [b for b in best if np.isfinite(b)]
    ax.plot(gens, best, "o-", label="best feasible so far")
    ax.axhline(spec.targets.hours, c="k", ls="--", lw=0.8, label=f"target {spec.targets.hours:g} h")
    ax.set_xlabel("generation")
    ax.set_xlim(-0.5, max(len(gens), 1) - 0.5)
    ax.xaxis.set_major_locator(MaxNLocator(integer=True, min_n_ticks=1))
    ax.set_ylabel("best feasible expected hours")
    ax.set_yscale("log")
    top = [*shown, spec.targets.hours]
    ax.set_ylim(min(top) / 1.3, max(top) * 1.3)
    _plain_log(ax.yaxis)
    ax.legend(fontsize=8)
    return fig


def _count(n: int, word: str) -> str:
    """"1 candidate", "2 candidates"."""
    return f"{n} {word}" + ("" if n == 1 else "s")


def write_design(study, template, folder: Path, verification=None, *, figures: bool = True) -> list[Path]:
    """``candidates.csv``, ``pareto.csv``, ``pareto.png``, ``convergence.png``,
    ``designs/*.toml`` (the front's best ``finalists`` by expected hours, as built and ready
    to run: :func:`~marinecdpr.studies.design.as_built`), ``finalists.csv`` (their hours in
    parts, binding constraints and, when verified, their time-domain figures beside the
    screen's), ``summary.json``, ``finalists.png`` and ``report.html``. Without ``figures``
    no PNG is drawn and the report says so; the other files are the same."""
    import tomli_w

    from marinecdpr.scenario.importing.common import toml_plain
    from marinecdpr.studies.design import as_built
    folder = Path(folder)
    spec = study.spec
    ev = study.evaluations
    layout = _layout(spec)
    paths = [_write_rows(folder / "candidates.csv", [_row(i, int(g), e, layout) for i, (e, g) in
                                                    enumerate(zip(ev, study.generation))], layout)]
    paths.append(_write_rows(folder / "pareto.csv", [_row(i, int(study.generation[i]), ev[i], layout)
                                                     for i in study.front], layout))
    if figures:
        paths.append(_save(pareto_figure(study), folder / "pareto.png"))
        paths.append(_save(convergence_figure(study), folder / "convergence.png"))
    designs = folder / "designs"
    designs.mkdir(exist_ok=True)
    plant = next((v.plant for v in verification or [] if v.plant), None)
    for rank, i in enumerate(study.front[:spec.finalists], start=1):
        data = as_built(spec, template, ev[i], plant).model_dump(exclude_none=True)
        data["name"] = f"{spec.name}_{rank}"
        data["description"] = f"{spec.name}, finalist {rank}: " + data["description"].split(": ", 1)[1]
        head = (f"# Written by `marinecdpr design` ({spec.name}, candidate {i}): run it with `marinecdpr clean "
                f"{spec.name}_{rank}.toml --surface`\n# As built: the rope's weight (robot.cable_weight_N_m) and "
                f"EA (simulation.cables), the winches' torque, speed, power and drum ([robot.winch], motor "
                f"winches); robot.tension_max_N the smaller of the rope's breaking load over its safety factor and "
                f"the winch's torque over its drum, robot.breaking_load_N the rope's breaking load\n")
        path = designs / f"{spec.name}_{rank}.toml"
        with atomic_path(path) as tmp:
            Path(tmp).write_text(head + tomli_w.dumps(toml_plain(data)), encoding="utf-8")
        paths.append(path)
    if study.front and spec.finalists:
        path = folder / "finalists.csv"
        with atomic_path(path) as tmp:
            with open(tmp, "w", encoding="utf-8", newline="") as fh:
                w = csv.writer(fh)
                w.writerow(FINALIST_COLUMNS)
                w.writerows(_finalist_rows(study, verification))
        paths.append(path)
    paths.append(write_json(design_summary(study, verification), folder / "summary.json"))
    shown = None
    if figures:
        drawn = _draw_finalists(study, template, folder / "finalists.png")
        paths.append(drawn)
        shown = {"The Pareto front": folder / "pareto.png", "Convergence": folder / "convergence.png",
                 "The finalists beside the template's robot": drawn}
    paths.append(_report_html(study, verification, shown, folder / "report.html"))
    return paths


@dataclass(frozen=True)
class DrawingGeometry:
    """What a design's drawing shows, in C's x-z plane (m): the frame anchors ``frame``
    (n_cables, 2), the panel's outline ``panel`` (n, 2), and the platform anchors
    ``platforms`` (4, n_cables, 2) and cables ``cables`` (4, n_cables, 2, 2) with the
    platform's centre at each corner of the panel less the brush's offset."""

    frame: np.ndarray
    panel: np.ndarray
    platforms: np.ndarray
    cables: np.ndarray


def drawing_geometry(scenario) -> DrawingGeometry:
    """What a design's drawing shows (:class:`DrawingGeometry`), the platform at the four
    corners of the panel (the poses the job's path reaches first and last)."""
    c = scenario.robot.frame_anchors[:, [0, 2]]
    p = scenario.robot.platform_anchors[:, [0, 2]]
    panel = np.asarray(scenario.cleaning.panel_m, dtype=float)
    offset = np.asarray(scenario.cleaning.brush_offset_m, dtype=float)[[0, 2]]
    lo, hi = panel.min(axis=0), panel.max(axis=0)
    corners = np.array([[lo[0], lo[1]], [hi[0], lo[1]], [hi[0], hi[1]], [lo[0], hi[1]]]) - offset
    platforms = corners[:, None, :] + p[None]
    cables = np.stack([np.broadcast_to(c, platforms.shape), platforms], axis=2)
    return DrawingGeometry(frame=c, panel=panel, platforms=platforms, cables=cables)


def finalists_figure(study, template):
    """finalists.png's figure: each finalist (and the template's robot) to one scale: frame,
    anchors, panel, and the platform with its cables at the panel's four corners, with a
    legend."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    spec, ev = study.spec, study.evaluations
    shown = [("the template's robot", template)] + [
        (f"finalist {rank}: {ev[i].expected_hours:.3g} h, {ev[i].objective(spec.objective):g} "
         + ("kW" if spec.objective == "power" else spec.cost_unit or "cost"), candidate_scenario(spec, template,
                                                                                              ev[i].x))
        for rank, i in enumerate(study.front[:spec.finalists], start=1)]
    plt = _pyplot()
    fig, axes = plt.subplots(1, len(shown), figsize=(4.2 * len(shown), 4.0), constrained_layout=True, squeeze=False)
    span = max(float(np.ptp(sc.robot.frame_anchors[:, [0, 2]], axis=0).max()) for _, sc in shown)
    for ax, (label, sc) in zip(axes[0], shown):
        g = drawing_geometry(sc)
        ax.fill(*g.panel.T, color="tab:green", alpha=0.25)
        for k in range(4):
            for seg in g.cables[k]:
                ax.plot(*seg.T, color="tab:red", lw=0.6, alpha=0.6)
            ax.fill(*g.platforms[k].T, color="tab:blue", alpha=0.5)
        f = g.frame
        ax.plot(*np.vstack([f, f[:1]]).T, "k-", lw=1.2)
        ax.plot(*f.T, "ko", ms=4)
        ax.set_aspect("equal")
        ax.set_xlim(-0.05 * span, 1.05 * span)
        ax.set_ylim(-0.05 * span, 1.05 * span)
        ax.set_title(_plain(label), fontsize=9)
        ax.set_xlabel("x in C (m)")
    axes[0][0].set_ylabel("z in C (m)")
    handles = [Line2D([], [], color="k", marker="o", ms=4, lw=1.2, label="frame and its anchors"),
               Patch(color="tab:green", alpha=0.25, label="panel the tool cleans"),
               Patch(color="tab:blue", alpha=0.5, label="platform at the panel's four corners"),
               Line2D([], [], color="tab:red", lw=0.6, label="cables there")]
    fig.legend(handles=handles, loc="outside lower center", ncols=4, fontsize=8)
    return fig


def _draw_finalists(study, template, path: Path) -> Path:
    return _save(finalists_figure(study, template), path)


def safety_text(study) -> str:
    """With ``[constraints] single_cable_failure``, what it asks and how many candidates it
    refused (those short on it, and those short on it alone), by cable count; else ""."""
    from marinecdpr.studies.design import FAILURE_CONSTRAINT, cable_count

    spec = study.spec
    if not spec.constraints.single_cable_failure:
        return ""
    short = [e for e in study.evaluations if not e.margins.get(FAILURE_CONSTRAINT, 0.0) >= 0.0]
    alone = [e for e in short if all(v >= 0.0 for k, v in e.margins.items() if k != FAILURE_CONSTRAINT)]
    counts = sorted({cable_count(e.x) for e in study.evaluations})
    by = "; ".join(f"{n} cables: {sum(cable_count(e.x) == n for e in short)} of "
                   f"{sum(cable_count(e.x) == n for e in study.evaluations)} short" for n in counts)
    return (f"Every feasible design survives each single cable's failure: with any one cable gone, the others hold "
            f"the platform within their limits at the screen's poses over the job, the brush at its preload, in "
            f"every sea state the design works in, the sea's extreme taken over {spec.constraints.failure_hold_s:g} s "
            f"(the constraint {FAILURE_CONSTRAINT}, N of tension to spare). It refused {len(short)} of "
            f"{len(study.evaluations)} candidates ({len(alone)} on it alone; {by}).")


def _report_html(study, verification, figures: dict | None, path: Path) -> Path:
    """One page: the targets, the front beside the template's robot (its second objective
    with its unit, its hours in parts, its binding constraints, the time domain's figures
    where flown), and the figures (None: the page says they were not drawn). Says whether
    the finalists were flown."""
    from marinecdpr.report.page import embedded_figures, render_page

    spec = study.spec
    td = {v.index: v for v in verification or []}
    power = spec.objective == "power"

    def hours(e):
        h = e.hours_breakdown()
        if not all(np.isfinite(v) for v in h.values()):
            return "–"
        return " + ".join(f"{h[k]:.3g} {name}" for k, name in BREAKDOWN)

    def binding(e):
        b = e.binding()
        return ", ".join(f"{k} ({100 * v:.3g} % left)" for k, v in b) if b else "–"

    def row(label, e, v=None):
        x = e.x
        obj = e.objective(spec.objective)
        return [label, f"{x['frame_width_m']:.3g} x {x['frame_height_m']:.3g}",
                f"{x['platform_width_m']:.3g} x {x['platform_height_m']:.3g}, {e.mass_kg:.3g} kg",
                f"{x['tool_width_m']:.3g} m at {x['speed_m_s']:.3g} m/s",
                f"{x['winch']}, {x['rope']}, {x.get('pattern', 'uncrossed')}",
                "–" if obj != obj else (f"{obj:g}" if power else f"{obj:.6g}"), e.placements,
                f"{e.surface_hours:.4g}", f"{100 * e.sea_share:.1f} %",
                f"{100 * v.td_share:.1f} %" if v is not None else "–", f"{e.expected_hours:.4g}",
                f"{v.td_expected_hours:.4g}" if v is not None else "–", hours(e), binding(e)]

    rows = [row("template's robot", study.baseline)] + [
        row(f"front {k}" + (" (finalist, flown)" if i in td else ""), study.evaluations[i], td.get(i))
        for k, i in enumerate(study.front, start=1)]
    best = study.best
    verdict = ("no feasible design" if best is None else
               f"best: {best.expected_hours:.4g} expected h against the target {spec.targets.hours:g} h: "
               + ("met" if study.target_met else "not met"))
    limits = ""
    if study.front:
        e = study.evaluations[study.front[0]]
        h = e.hours_breakdown()
        if all(np.isfinite(v) for v in h.values()):
            parts = ", ".join(f"{name} {h[k]:.3g} h" for k, name in BREAKDOWN)
            top = max(BREAKDOWN, key=lambda kn: h[kn[0]])
            limits = (f"What limits the best design: of its {e.expected_hours:.4g} expected h, {top[1]} takes "
                      f"{h[top[0]]:.3g} h ({parts}); its binding constraints: {binding(e)}.")
    plants = sorted({v.plant for v in verification or [] if v.plant})
    if verification:
        where = ("in every sea state" if spec.sea.verify == "all" else
                 "in the sea states about each column's boundary (one period, one heading: bisected from the "
                 "screen's verdicts to the height where the job first fails; the column's lower seas taken to work "
                 "and its higher ones to fail; a sea state whose plan fails judged by its plan, not flown; " +
                 ", ".join(f"{v.flown} judged for finalist {v.rank} ({v.planned_only} by the plan alone"
                           + (f"; {v.unjudged} of the least likely columns, {100 * v.unjudged_share:.2f} % of the "
                              "probability, not flown and counted as failing" if v.unjudged else "") + ")"
                           for v in verification) + ")")
        flown = (f"The finalists were also flown as built (their rope's weight and stretch, their winches' "
                 f"dynamics and limits) through the cleaning job {where}, closed loop on the prototype "
                 f"({' and '.join('MuJoCo' if p == 'mujoco' else 'the own plant' for p in plants)}): the time "
                 "domain's columns." + "".join(" " + rail_move_text(v) for v in verification if v.rail_move))
    else:
        flown = ("The finalists were not flown in the time domain (--no-verify, or no finalist): every figure is "
                 "the screen's.")
    safety = safety_text(study)
    if safety:
        flown = safety + " " + flown
    return render_page("design.html", path, spec=spec, candidates=_count(len(study.evaluations), "candidate"),
                       feasible=study.feasible, verdict=verdict, limits=limits or None,
                       objective=objective_label(spec), rows=rows, flown=flown, figures=embedded_figures(figures),
                       view="")
