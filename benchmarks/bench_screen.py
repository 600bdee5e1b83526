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

``--records N`` also plans each pair the two disagree on over N records of its sea state (the
time domain's own, realisation 0, and N - 1 more) and judges each as the time domain judges the
plan (tensions within the limits at every step, the normal force in band for the target share
of the time): the share of records that fail beside the screen's chance. The screen judges the
sea state (it says "works" where at most ``exceedance`` of its records would fail), the time
domain one record of it: a "fails" where the records fail more often than that is the screen
right about the sea state and the one record lucky, and no screen of the sea state agrees there.

``--sea-records N`` judges every pair's sea state, not one record of it: each pair is planned over
N records (the time domain's own first) and judged as the time domain judges the plan; the
sea state fails where its failing records are more than the screen's ``exceedance`` allows at
95 % confidence (a one-sided binomial test: k failing of N with P(K >= k | exceedance) < 5 %),
and works otherwise. The screen's verdicts are compared with that, beside the one-record table;
the counts go in ``--td-cache`` too (as the plant "records-N").

``--td-cache FILE`` keeps the time domain's verdicts (JSON lines, one per pair) and reads
them back on the next run, so that the screen can be compared again without flying the
closed loops again (the pairs missing from the file are flown and added).
"""

from __future__ import annotations

import argparse
import os
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


def _records(args):
    """How many of the pair's first ``n`` records fail as the time domain judges the plan:
    (tensions out of their limits at some step, the normal force in band less than the
    target share of the time)."""
    import marinecdpr
    from marinecdpr.prototype.parts.brush import normal_force
    from marinecdpr.studies.cleaning import IN_BAND_TARGET_PCT
    from marinecdpr.studies.operability import cell_scenario

    name, cell, n = args
    sc = _design(name)
    lo, hi = sc.cleaning.band_N
    tol = 1e-9 * max(hi, 1.0)
    tensions = band = 0
    for r in range(n):
        run = cell_scenario(sc, cell, sc.time.duration_s, sc.time.step_s, r)
        p = marinecdpr.plan(run)
        if not p.feasible.all():
            tensions += 1
            continue
        F = normal_force(p, run)[:-1]
        band += 100.0 * np.mean((F >= lo - tol) & (F <= hi + tol)) < IN_BAND_TARGET_PCT
    return tensions, band


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
    parser.add_argument("--records", type=int, default=0, help="plan each disagreeing pair over this many records")
    parser.add_argument("--sea-records", type=int, default=0,
                        help="judge every pair's sea state over this many planned records")
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
    if args.records:
        _by_records(args, names, cells, verdicts, results)
    if args.sea_records:
        _by_sea_state(args, names, cells, verdicts, results)
    td_share = {name: np.mean([results[k * len(cells) + j][0] for j in range(len(cells))])
                for k, name in enumerate(names)}
    for name in names:
        print(f"  {name:<28} works in {100 * verdicts[name].works.mean():5.1f} % of the sea states by the screen, "
              f"{100 * td_share[name]:5.1f} % in the time domain")


def _by_records(args, names, cells, verdicts, results) -> None:
    """The pairs the screen and the time domain disagree on, planned over ``args.records``
    records each: how often the records fail beside the screen's chance."""
    pairs = [(k, j) for k, name in enumerate(names) for j in range(len(cells))
             if bool(verdicts[name].works[j]) != results[k * len(cells) + j][0]]
    jobs = [(names[k], cells[j], args.records) for k, j in pairs]
    t0 = time.perf_counter()
    with ProcessPoolExecutor(max_workers=args.workers) as pool:
        counts = list(pool.map(_records, jobs))
    print(f"\nthe {len(pairs)} pairs they disagree on, each planned over {args.records} records of its sea state "
          f"(the time domain's own first; {time.perf_counter() - t0:.0f} s):")
    print(f"{'design':<28} {'Hs':>4} {'Tp':>4}  {'screen':>7} {'chance':>7} {'band %':>7} {'low %':>7}  "
          f"{'records failing (tensions, band)':<34} the time domain's record")
    exceed = {name: verdicts[name].exceedance for name in names}
    right = none = 0
    for (k, j), (t_f, b_f) in zip(pairs, counts):
        name, v = names[k], verdicts[names[k]]
        failing = t_f + b_f
        right += failing > exceed[name] * args.records
        none += failing == 0
        print(f"{name:<28} {cells[j].hs:4.1f} {cells[j].tp:4.0f}  {'works' if v.works[j] else 'fails':>7} "
              f"{v.chance[j]:7.3f} {v.in_band_pct[j]:7.2f} {v.in_band_low_pct[j]:7.2f}  "
              f"{f'{failing} of {args.records} ({t_f}, {b_f})':<34} "
              f"{'works' if results[k * len(cells) + j][0] else 'fails'}")
    n = len(names) * len(cells)
    agree = n - len(pairs)
    print(f"of the {len(pairs)}: {right} with more than the exceedance of their records failing (the screen right about "
          f"the sea state, the one record lucky), {none} with none of {args.records} failing; a screen that knew "
          f"each sea state's chance would agree with the one record on at most {agree + len(pairs) - right} of {n} "
          f"({100 * (agree + len(pairs) - right) / n:.1f} %)")


def _by_sea_state(args, names, cells, verdicts, results) -> None:
    """Every pair's sea state judged over ``args.sea_records`` planned records, against the screen."""
    import json

    from scipy.stats import binom

    n_rec = args.sea_records
    plant = f"records-{n_rec}"
    cached = {}
    if args.td_cache and os.path.isfile(args.td_cache):
        with open(args.td_cache, encoding="utf-8") as fh:
            for line in fh:
                r = json.loads(line)
                if r["plant"] == plant:
                    cached[r["key"]] = (r["tensions"], r["band"])
    jobs = [(name, cell, n_rec) for name in names for cell in cells if _key(name, cell) not in cached]
    t0 = time.perf_counter()
    with ProcessPoolExecutor(max_workers=args.workers) as pool:
        for job, res in zip(jobs, pool.map(_records, jobs)):
            cached[_key(job[0], job[1])] = res
            if args.td_cache:
                with open(args.td_cache, "a", encoding="utf-8") as fh:
                    fh.write(json.dumps({"key": _key(job[0], job[1]), "plant": plant, "tensions": int(res[0]),
                                         "band": int(res[1])}) + "\n")
    print(f"\nevery pair's sea state over {n_rec} planned records ({len(jobs)} pairs planned in "
          f"{time.perf_counter() - t0:.0f} s, {len(names) * len(cells) - len(jobs)} from the cache):")
    kinds = {"agree": 0, "feasible, fails": 0, "infeasible, works": 0}
    strict = {"agree": 0, "feasible, fails": 0, "infeasible, works": 0}
    for k, name in enumerate(names):
        v = verdicts[name]
        # fails: more failing records than the exceedance allows at 95 % (one-sided binomial)
        k_crit = next(k_ for k_ in range(n_rec + 1) if binom.sf(k_ - 1, n_rec, v.exceedance) < 0.05)
        for j, cell in enumerate(cells):
            t_f, b_f = cached[_key(name, cell)]
            failing = t_f + b_f
            s_ok = bool(v.works[j])
            for table, ok in ((kinds, failing < k_crit), (strict, failing == 0)):
                table["agree" if s_ok == ok else ("feasible, fails" if s_ok else "infeasible, works")] += 1
            if s_ok != (failing < k_crit):
                print(f"  {name:<28} {cell.hs:4.1f} {cell.tp:4.0f}  screen {'works' if s_ok else 'fails':<6} "
                      f"chance {v.chance[j]:6.3f}  {failing} of {n_rec} records fail ({t_f} tensions, {b_f} band); "
                      f"the one closed-loop record {'works' if results[k * len(cells) + j][0] else 'fails'}")
    n = len(names) * len(cells)
    print(f"against the sea state (fails from {k_crit} failing records of {n_rec}): agreement {kinds['agree']} of {n} "
          f"({100 * kinds['agree'] / n:.1f} %); 'works' where the sea state fails: {kinds['feasible, fails']}; "
          f"'fails' where it works: {kinds['infeasible, works']}")
    print(f"against the strict rule (fails if any of {n_rec} fails): agreement {strict['agree']} of {n} "
          f"({100 * strict['agree'] / n:.1f} %); 'works' where a record fails: {strict['feasible, fails']}; "
          f"'fails' where none fails: {strict['infeasible, works']}")


if __name__ == "__main__":
    main()
