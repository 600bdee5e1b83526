"""The design study's files (``marinecdpr design``): every candidate, the Pareto front and its
figure, the search's convergence, the finalists as ready-to-run scenarios, and the summary."""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from marinecdpr.report.figures import _pyplot, _save
from marinecdpr.report.files import write_json
from marinecdpr.textfiles import atomic_path

__all__ = ["write_design", "design_summary", "CANDIDATE_COLUMNS"]


def _columns() -> list[str]:
    from marinecdpr.scenario.design import CONTINUOUS
    from marinecdpr.studies.design import CONSTRAINTS

    return (["index", "generation", *CONTINUOUS, "winch", "rope", "mass_kg", "tension_max_N", "placements",
             "surface_hours", "sea_share", "expected_hours", "power_kW", "cost"]
            + [f"margin_{k}" for k in CONSTRAINTS] + ["feasible", "reason"])


CANDIDATE_COLUMNS = _columns()
"""candidates.csv's and pareto.csv's columns."""


def _row(i: int, gen: int, e) -> list:
    from marinecdpr.scenario.design import CONTINUOUS
    from marinecdpr.studies.design import CONSTRAINTS

    def num(v):
        return "" if v is None or not np.isfinite(v) else f"{v:.10g}"

    return ([i, gen, *(num(e.x[k]) for k in CONTINUOUS), e.x["winch"], e.x["rope"], num(e.mass_kg),
             num(e.tension_max_N), e.placements, num(e.surface_hours), num(e.sea_share), num(e.expected_hours),
             num(e.power_kW), num(e.cost)] + [num(e.margins.get(k, float("nan"))) for k in CONSTRAINTS]
            + [int(e.feasible), e.reason])


def _write_rows(path: Path, rows: list[list]) -> Path:
    with atomic_path(path) as tmp:
        with open(tmp, "w", encoding="utf-8", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(CANDIDATE_COLUMNS)
            w.writerows(rows)
    return path


def _short(e, objective: str) -> dict:
    keys = ("placements", "surface_hours", "sea_share", "expected_hours", "power_kW", "cost", "tension_max_N",
            "mass_kg")
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
    from marinecdpr.studies.design import candidate_scenario

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
        sc = candidate_scenario(spec, template, ev[i].x)
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
                 "td_expected_hours", "agree", "screen_works_td_fails", "screen_fails_td_works"]
        path = folder / "finalists.csv"
        with atomic_path(path) as tmp:
            with open(tmp, "w", encoding="utf-8", newline="") as fh:
                w = csv.writer(fh)
                w.writerow(names)
                w.writerows([[getattr(v, k) for k in names] for v in verification])
        paths.append(path)
    paths.append(write_json(design_summary(study, verification), folder / "summary.json"))
    return paths
