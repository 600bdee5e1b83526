"""The design study's files (``marinecdpr design``): every candidate, the Pareto front and its
figure, the search's convergence, the finalists as ready-to-run scenarios, and the summary."""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from marinecdpr.report.figures import _pyplot, _save
from marinecdpr.report.files import write_json
from marinecdpr.scenario.design import CONTINUOUS
from marinecdpr.studies.design import CONSTRAINTS, candidate_scenario
from marinecdpr.textfiles import atomic_path

__all__ = ["write_design", "design_summary", "drawing_geometry", "CANDIDATE_COLUMNS"]


CANDIDATE_COLUMNS = (["index", "generation", *CONTINUOUS, "winch", "rope", "pattern", "mass_kg", "tension_max_N",
                      "placements", "frame_turn_median_deg", "frame_turn_max_deg", "surface_hours", "sea_share",
                      "expected_hours", "power_kW", "cost"]
                     + [f"margin_{k}" for k in CONSTRAINTS] + ["feasible", "reason"])
"""candidates.csv's and pareto.csv's columns."""


def _row(i: int, gen: int, e) -> list:
    def num(v):
        return "" if v is None or not np.isfinite(v) else f"{v:.10g}"

    return ([i, gen, *(num(e.x[k]) for k in CONTINUOUS), e.x["winch"], e.x["rope"], e.x.get("pattern", "uncrossed"),
             num(e.mass_kg), num(e.tension_max_N), e.placements, *(num(v) for v in e.frame_turn_deg),
             num(e.surface_hours), num(e.sea_share),
             num(e.expected_hours), num(e.power_kW), num(e.cost)]
            + [num(e.margins.get(k, float("nan"))) for k in CONSTRAINTS] + [int(e.feasible), e.reason])


def _write_rows(path: Path, rows: list[list]) -> Path:
    with atomic_path(path) as tmp:
        with open(tmp, "w", encoding="utf-8", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(CANDIDATE_COLUMNS)
            w.writerows(rows)
    return path


def _short(e, objective: str) -> dict:
    keys = ("placements", "surface_hours", "sea_share", "expected_hours", "power_kW", "cost", "tension_max_N",
            "mass_kg", "frame_turn_deg", "sea_reason")
    return {"variables": dict(e.x), **{k: getattr(e, k) for k in keys}, "feasible": e.feasible,
            "objective": e.objective(objective)}


def design_summary(study, verification=None) -> dict:
    """``summary.json``: the study, its best designs by expected hours (the front), the
    baseline, whether the target is met, and the finalists' time-domain figures."""
    spec = study.spec
    ev = study.evaluations
    front = [_short(ev[i], spec.objective) | {"index": i} for i in study.front]
    best = front[0] if front else None
    return {
        "study": spec.name, "objective": spec.objective, "targets": spec.targets.model_dump(),
        "candidates": len(ev), "feasible": int(sum(e.feasible for e in ev)), "seed": spec.seed,
        "population": spec.population, "generations": spec.generations,
        "front": front, "best": best,
        "target_met": bool(best is not None and best["expected_hours"] <= spec.targets.hours),
        "baseline": _short(study.baseline, spec.objective),
        "screen": "expected hours = placements' cleaning and moves / the share of sea states the fast screen "
                  "passes (studies.screen: frequency-domain extremes, conservative)",
        "finalists": [dict(v.__dict__) for v in verification or []],
    }


def write_design(study, template, folder: Path, verification=None) -> list[Path]:
    """``candidates.csv``, ``pareto.csv``, ``pareto.png``, ``convergence.png``,
    ``designs/*.toml`` (the front's best ``finalists`` by expected hours, ready to run),
    ``finalists.csv`` (their time-domain figures beside the screen's, when verified) and
    ``summary.json``."""
    import tomli_w

    from marinecdpr.scenario.importing.common import _plain
    folder = Path(folder)
    spec = study.spec
    ev = study.evaluations
    paths = [_write_rows(folder / "candidates.csv", [_row(i, int(g), e) for i, (e, g) in
                                                    enumerate(zip(ev, study.generation))])]
    paths.append(_write_rows(folder / "pareto.csv", [_row(i, int(study.generation[i]), ev[i]) for i in study.front]))
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(7, 4.5), constrained_layout=True)
    ok = [e for e in ev if e.feasible and np.isfinite(e.expected_hours)]
    bad = [e for e in ev if not (e.feasible and np.isfinite(e.expected_hours))]
    unit = "installed winch power (kW)" if spec.objective == "power" else "cost"
    if bad:
        ax.scatter([e.objective(spec.objective) for e in bad],
                   [min(e.expected_hours, 1e6) if np.isfinite(e.expected_hours) else np.nan for e in bad],
                   s=10, c="0.75", label="infeasible")
    if ok:
        ax.scatter([e.objective(spec.objective) for e in ok], [e.expected_hours for e in ok], s=14, c="tab:blue",
                   label="feasible")
    if study.front:
        f = np.array([[ev[i].objective(spec.objective), ev[i].expected_hours] for i in study.front])
        order = np.argsort(f[:, 0])
        ax.plot(f[order, 0], f[order, 1], "o-", c="tab:red", label="Pareto front")
    ax.axhline(spec.targets.hours, c="k", ls="--", lw=0.8, label=f"target {spec.targets.hours:g} h")
    ax.set_yscale("log")
    ax.set_xlabel(unit)
    ax.set_ylabel("expected hours for the surface")
    ax.set_title(f"{spec.name}: {len(ev)} candidates, {len(ok)} feasible", fontsize=9)
    ax.legend(fontsize=8)
    paths.append(_save(fig, folder / "pareto.png"))
    fig, ax = plt.subplots(figsize=(7, 3.5), constrained_layout=True)
    gens = np.arange(int(study.generation.max()) + 1) if len(ev) else np.zeros(0, dtype=int)
    best, running = [], float("inf")
    for g in gens:
        hours = [e.expected_hours for e, gg in zip(ev, study.generation) if gg == g and e.feasible]
        running = min([running, *hours])
        best.append(running)
    ax.plot(gens, best, "o-")
    ax.axhline(spec.targets.hours, c="k", ls="--", lw=0.8)
    ax.set_xlabel("generation")
    ax.set_ylabel("best feasible expected hours")
    ax.set_yscale("log")
    paths.append(_save(fig, folder / "convergence.png"))
    designs = folder / "designs"
    designs.mkdir(exist_ok=True)
    for rank, i in enumerate(study.front[:spec.finalists], start=1):
        sc = candidate_scenario(spec, template, ev[i].x).with_updates(
            "ship", frame_origin_m=ev[i].frame_origin_m, frame_orientation_deg=ev[i].frame_orientation_deg)
        data = sc.model_dump(exclude_none=True)
        data["name"] = f"{spec.name}_{rank}"
        data["description"] = (f"{spec.name}, finalist {rank}: {ev[i].expected_hours:.4g} expected h, "
                               f"{ev[i].power_kW:g} kW of winches ({ev[i].x['winch']}, {ev[i].x['rope']})")
        head = (f"# Written by `marinecdpr design` ({spec.name}, candidate {i}): run it with `marinecdpr clean "
                f"{spec.name}_{rank}.toml --surface`\n")
        path = designs / f"{spec.name}_{rank}.toml"
        with atomic_path(path) as tmp:
            Path(tmp).write_text(head + tomli_w.dumps(_plain(data)), encoding="utf-8")
        paths.append(path)
    if verification:
        names = ["rank", "index", "surface_hours", "screen_share", "td_share", "screen_expected_hours",
                 "td_expected_hours", "agree", "screen_works_td_fails", "screen_fails_td_works", "plant"]
        path = folder / "finalists.csv"
        with atomic_path(path) as tmp:
            with open(tmp, "w", encoding="utf-8", newline="") as fh:
                w = csv.writer(fh)
                w.writerow(names)
                w.writerows([[getattr(v, k) for k in names] for v in verification])
        paths.append(path)
    summary = design_summary(study, verification)
    paths.append(write_json(summary, folder / "summary.json"))
    drawn = _draw_finalists(study, template, folder / "finalists.png")
    paths.append(drawn)
    paths.append(_report_html(study, summary, verification, {"The Pareto front": folder / "pareto.png",
                                                             "Convergence": folder / "convergence.png",
                                                             "The finalists beside the template's robot": drawn},
                              folder / "report.html"))
    return paths


def drawing_geometry(scenario) -> dict:
    """What a design's drawing shows, in C's x-z plane (m): the frame anchors (4, 2), the
    panel's outline (n, 2), and the platform anchors and cables with the platform's centre
    at each corner of the panel less the brush's offset (the poses the job's path reaches
    first and last): ``platforms`` (4, n_cables, 2) and ``cables`` (4, n_cables, 2, 2)."""
    c = scenario.robot.frame_anchors[:, [0, 2]]
    p = scenario.robot.platform_anchors[:, [0, 2]]
    panel = np.asarray(scenario.cleaning.panel_m, dtype=float)
    offset = np.asarray(scenario.cleaning.brush_offset_m, dtype=float)[[0, 2]]
    lo, hi = panel.min(axis=0), panel.max(axis=0)
    corners = np.array([[lo[0], lo[1]], [hi[0], lo[1]], [hi[0], hi[1]], [lo[0], hi[1]]]) - offset
    platforms = corners[:, None, :] + p[None]
    cables = np.stack([np.broadcast_to(c, platforms.shape), platforms], axis=2)
    return {"frame": c, "panel": panel, "platforms": platforms, "cables": cables}


def _draw_finalists(study, template, path: Path) -> Path:
    """Each finalist (and the template's robot) to one scale: frame, anchors, panel, and the
    platform with its cables at the panel's four corners."""
    spec, ev = study.spec, study.evaluations
    shown = [("the template's robot", template)] + [
        (f"finalist {rank}: {ev[i].expected_hours:.3g} h, {ev[i].power_kW:g} kW", candidate_scenario(spec, template,
                                                                                                      ev[i].x))
        for rank, i in enumerate(study.front[:spec.finalists], start=1)]
    plt = _pyplot()
    fig, axes = plt.subplots(1, len(shown), figsize=(4.2 * len(shown), 3.6), constrained_layout=True, squeeze=False)
    span = max(float(np.ptp(sc.robot.frame_anchors[:, [0, 2]], axis=0).max()) for _, sc in shown)
    for ax, (label, sc) in zip(axes[0], shown):
        g = drawing_geometry(sc)
        ax.fill(*g["panel"].T, color="tab:green", alpha=0.25, label="panel")
        for k in range(4):
            for seg in g["cables"][k]:
                ax.plot(*seg.T, color="tab:red", lw=0.6, alpha=0.6)
            ax.fill(*g["platforms"][k].T, color="tab:blue", alpha=0.5)
        f = g["frame"]
        ax.plot(*np.vstack([f, f[:1]]).T, "k-", lw=1.2)
        ax.plot(*f.T, "ko", ms=4)
        ax.set_aspect("equal")
        ax.set_xlim(-0.05 * span, 1.05 * span)
        ax.set_ylim(-0.05 * span, 1.05 * span)
        ax.set_title(label, fontsize=9)
        ax.set_xlabel("x in C (m)")
    axes[0][0].set_ylabel("z in C (m)")
    return _save(fig, path)


def _report_html(study, summary: dict, verification, figures: dict, path: Path) -> Path:
    """One page: the targets, the front beside the template's robot (the time domain's figures
    where flown), and the figures."""
    import base64
    from html import escape as esc

    spec = study.spec
    td = {v.index: v for v in verification or []}

    def row(label, e, v=None):
        x = e.x
        td_share = f"{100 * v.td_share:.1f} %" if v is not None else "–"
        td_hours = f"{v.td_expected_hours:.4g}" if v is not None else "–"
        return (f"<tr><td>{esc(label)}</td><td>{x['frame_width_m']:.3g} x {x['frame_height_m']:.3g}</td>"
                f"<td>{x['platform_width_m']:.3g} x {x['platform_height_m']:.3g}, {e.mass_kg:.3g} kg</td>"
                f"<td>{x['tool_width_m']:.3g} m at {x['speed_m_s']:.3g} m/s</td><td>{esc(x['winch'])}, "
                f"{esc(x['rope'])}, {esc(x.get('pattern', 'uncrossed'))}</td><td>{'–' if e.power_kW != e.power_kW else f'{e.power_kW:g}'}</td><td>{e.placements}</td><td>{e.surface_hours:.4g}</td>"
                f"<td>{100 * e.sea_share:.1f} %</td><td>{td_share}</td><td>{e.expected_hours:.4g}</td>"
                f"<td>{td_hours}</td></tr>")

    rows = [row("template's robot", study.baseline)] + [
        row(f"front {k}" + (" (finalist)" if i in td else ""), study.evaluations[i], td.get(i))
        for k, i in enumerate(study.front, start=1)]
    imgs = []
    for caption, fig_path in figures.items():
        data = base64.b64encode(Path(fig_path).read_bytes()).decode("ascii")
        imgs.append(f'<figure><img src="data:image/png;base64,{data}" alt="{esc(caption)}">'
                    f"<figcaption>{esc(caption)}</figcaption></figure>")
    best = summary["best"]
    verdict = ("no feasible design" if best is None else
               f"best: {best['expected_hours']:.4g} expected h against the target {spec.targets.hours:g} h: "
               + ("met" if summary["target_met"] else "not met"))
    plants = sorted({v.plant for v in verification or [] if v.plant})
    flown = f" ({' and '.join('MuJoCo' if p == 'mujoco' else 'the own plant' for p in plants)})" if plants else ""
    page = f"""<!doctype html>
<html lang="en"><head><meta charset="utf-8"><title>marinecdpr design: {esc(spec.name)}</title>
<style>
body {{ font-family: system-ui, sans-serif; max-width: 1200px; margin: 2em auto; padding: 0 1em; color: #222; }}
table {{ border-collapse: collapse; margin: 1em 0; font-size: 0.92em; }}
th, td {{ border: 1px solid #ccc; padding: 0.3em 0.6em; text-align: left; }}
thead th {{ background: #f2f2f2; }}
figure {{ margin: 1.5em 0; }} img {{ max-width: 100%; }}
figcaption {{ color: #555; font-size: 0.9em; }}
</style></head><body>
<h1>Design study: {esc(spec.name)}</h1>
<p>{esc(spec.description)}</p>
<p>{len(study.evaluations)} candidates ({summary['feasible']} feasible), seed {spec.seed}; targets: {spec.targets.hours:g} h
for the surface, working in {100 * spec.targets.sea_share:g} % of the sea states. {esc(verdict)}.</p>
<h2>The Pareto front</h2>
<table><thead><tr><th></th><th>frame (m)</th><th>platform</th><th>tool</th><th>winches, rope, cables</th><th>kW</th>
<th>placements</th><th>hours on the surface</th><th>works in (screen)</th><th>(time domain)</th>
<th>expected h (screen)</th><th>(time domain)</th></tr></thead>
<tbody>{''.join(rows)}</tbody></table>
<p>Expected hours: the placements' cleaning and moves over the share of sea states in which the job works.
The screen judges every candidate; the finalists were also flown through the cleaning job in every sea state,
closed loop on the prototype{flown}.</p>
<h2>Figures</h2>
{''.join(imgs)}
</body></html>
"""
    with atomic_path(path) as tmp:
        Path(tmp).write_text(page, encoding="utf-8")
    return path
