"""The design study's fast screen against the time domain: its speed, and its verdicts on
(design, sea state) pairs beside the closed-loop cleaning job's (`clean --seas`).

Run:  .venv/bin/python benchmarks/bench_screen.py [--quick] [--workers 2] [--plant mujoco] [--td-cache FILE]

Prints
  * the screen's speed: (design, sea state) pairs per second on one core, the model's
    build per design, against one time-domain job (the closed loop on the plant) and the
    plan alone;
  * for each design (paper_clean's robot with a heavier platform, lower T_max, a narrower
    normal-force band) over the package's illustrative scatter diagram in beam seas (34 sea
    states; ``--quick``: 8 of them): the screen's verdict and margin beside the time
    domain's verdict and why, the agreement share, and the errors by kind: "feasible"
    where the time domain fails (which a screen must not say) and "infeasible" where it works.

``--td-cache FILE`` keeps the time domain's verdicts (JSON lines, one per pair) and reads
them back on the next run, so that the screen can be compared again without flying the
closed loops again (the pairs missing from the file are flown and added).
"""

from __future__ import annotations

import argparse
import time
from concurrent.futures import ProcessPoolExecutor
from importlib import resources

import numpy as np

from _common import best_of, machine  # benchmarks/_common.py (the script's folder is on sys.path)

DESIGNS = {  # name: (robot updates, cleaning updates)
    "paper_clean (5 kg, T_max 450 N)": ({}, {}),
    "8 kg platform": ({"mass_kg": 8.0}, {}),
    "11 kg platform": ({"mass_kg": 11.0}, {}),
    "14 kg platform": ({"mass_kg": 14.0}, {}),
    "8 kg, T_max 300 N": ({"mass_kg": 8.0, "tension_max_N": 300.0}, {}),
    "5 kg, force band 52-68 N": ({}, {"normal_force_N": [52.0, 68.0]}),
}


def _design(name: str):
    import marinecdpr

    robot, cleaning = DESIGNS[name]
    sc = marinecdpr.load_scenario("paper_clean")
    if robot:
        sc = sc.with_updates("robot", **robot)
    if cleaning:
        sc = sc.with_updates("cleaning", **cleaning)
    return sc


def _time_domain(args):
    from marinecdpr.studies.cleaning import evaluate_cleaning_cell

    name, cell, plant = args
    r = evaluate_cleaning_cell(_design(name), cell, plant=plant)
    return r.operable, r.reason, r.tension_min_N, r.tension_max_N, r.in_band_pct


def _key(name: str, cell) -> str:
    return f"{name}|{cell.hs:g}|{cell.tp:g}|{cell.heading_deg:g}"


def _read_cache(path, plant: str) -> dict:
    """The cached time-domain verdicts of ``plant`` by pair (none without a file)."""
    import json
    import os

    out = {}
    if path and os.path.isfile(path):
        with open(path, encoding="utf-8") as fh:
            for line in fh:
                r = json.loads(line)
                if r["plant"] == plant:
                    out[r["key"]] = (r["ok"], r["reason"], r["t_lo"], r["t_hi"], r["band"])
    return out


def _append_cache(path: str, plant: str, job, res) -> None:
    import json

    ok, reason, t_lo, t_hi, band = res
    with open(path, "a", encoding="utf-8") as fh:
        fh.write(json.dumps({"key": _key(job[0], job[1]), "plant": plant, "ok": bool(ok), "reason": reason,
                             "t_lo": float(t_lo), "t_hi": float(t_hi), "band": float(band)}) + "\n")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--plant", default="mujoco", choices=("mujoco", "own"))
    parser.add_argument("--td-cache", default=None, help="JSON-lines file of the time domain's verdicts")
    args = parser.parse_args()
    import marinecdpr
    from marinecdpr.studies.cleaning import evaluate_cleaning_cell
    from marinecdpr.studies.operability import read_scatter_csv, scatter_cells
    from marinecdpr.studies.screen import screen_cells, screen_model

    print(machine())
    scatter = read_scatter_csv(str(resources.files("marinecdpr") / "data" / "scatter_illustrative.csv"))
    cells = scatter_cells(scatter, (90.0,))
    if args.quick:
        cells = cells[::4]
    names = list(DESIGNS)

    # speed: the screen over every cell of three headings, one design
    sc = _design(names[0])
    many = scatter_cells(scatter, (180.0, 150.0, 90.0))
    model, t_model = best_of(5, lambda: screen_model(sc))
    screen_cells(sc, many, model=model)
    _, t_screen = best_of(5, lambda: screen_cells(sc, many, model=model))
    td, t_td = best_of(1, lambda: evaluate_cleaning_cell(sc, cells[0], plant=args.plant))
    from marinecdpr.studies.operability import cell_scenario

    _, t_plan = best_of(3, lambda: marinecdpr.plan(cell_scenario(sc, cells[0], sc.time.duration_s, sc.time.step_s)))
    print(f"screen: {len(many)} sea states of paper_clean in {t_screen * 1e3:.1f} ms: "
          f"{len(many) / t_screen:.0f} pairs/s on one core ({t_screen / len(many) * 1e3:.2f} ms a pair); "
          f"its model {t_model * 1e3:.1f} ms per design")
    print(f"time domain: the {sc.time.duration_s:g} s job closed loop on {args.plant}: {t_td:.2f} s a pair "
          f"({t_td / (t_screen / len(many)):.0f}x the screen); the plan alone {t_plan:.2f} s")

    # agreement: every design in every cell
    verdicts = {}
    for name in names:
        d = _design(name)
        verdicts[name] = screen_cells(d, cells, model=screen_model(d))
    jobs = [(name, cell, args.plant) for name in names for cell in cells]
    cached = _read_cache(args.td_cache, args.plant)
    todo = [job for job in jobs if _key(job[0], job[1]) not in cached]
    t0 = time.perf_counter()
    with ProcessPoolExecutor(max_workers=args.workers) as pool:
        for job, res in zip(todo, pool.map(_time_domain, todo)):
            cached[_key(job[0], job[1])] = res
            if args.td_cache:
                _append_cache(args.td_cache, args.plant, job, res)
    wall = time.perf_counter() - t0
    results = [cached[_key(name, cell)] for name, cell, _ in jobs]
    print(f"\n{len(jobs)} pairs ({len(names)} designs x {len(cells)} sea states, beam seas) in the time domain: "
          f"{len(todo)} flown in {wall:.0f} s on {args.workers} processes, {len(jobs) - len(todo)} from the cache")
    print(f"{'design':<28} {'Hs':>4} {'Tp':>4}  {'screen':>7} {'margin N':>9} {'chance':>7} {'band %':>7}  "
          f"{'time domain':<11} why")
    kinds = {"agree": 0, "feasible, fails": 0, "infeasible, works": 0}
    i = 0
    for name in names:
        v = verdicts[name]
        for j, cell in enumerate(cells):
            ok, reason, t_lo, t_hi, band = results[i]
            i += 1
            s_ok = bool(v.works[j])
            kind = "agree" if s_ok == ok else ("feasible, fails" if s_ok else "infeasible, works")
            kinds[kind] += 1
            if kind != "agree" or j % 6 == 0:
                print(f"{name:<28} {cell.hs:4.1f} {cell.tp:4.0f}  {'works' if s_ok else 'fails':>7} "
                      f"{v.margin_N[j]:9.1f} {v.chance[j]:7.3f} {v.in_band_pct[j]:7.2f}  "
                      f"{'works' if ok else 'fails':<11} "
                      f"{reason or f'tensions {t_lo:.1f}-{t_hi:.1f} N, in band {band:.2f} %'}")
                if not s_ok:
                    print(f"{'':<28} the screen: {v.reasons[j]}")
    n = len(jobs)
    print(f"\nagreement {kinds['agree']} of {n} ({100 * kinds['agree'] / n:.1f} %); the screen says "
          f"'works' where the time domain fails: {kinds['feasible, fails']}; 'fails' where it works: "
          f"{kinds['infeasible, works']}")
    td_share = {name: np.mean([results[k * len(cells) + j][0] for j in range(len(cells))])
                for k, name in enumerate(names)}
    for name in names:
        print(f"  {name:<28} works in {100 * verdicts[name].works.mean():5.1f} % of the sea states by the screen, "
              f"{100 * td_share[name]:5.1f} % in the time domain")


if __name__ == "__main__":
    main()
