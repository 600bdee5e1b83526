"""The ``design`` command: design a robot for a ship: search the frame, platform, winches, rope and tool that clean
    the study's surface in the fewest expected hours for the power installed, in its seas, and
    fly the best through the cleaning job in every sea state. Options ->
    :class:`~marinecdpr.commands.design.DesignCommandSpec`; the estimate, the search, the
    finalists' flights and the files are :mod:`marinecdpr.commands.design`'s."""

from __future__ import annotations

import math
import time
from pathlib import Path
from typing import Optional

import typer

from marinecdpr.cli.common import (EXIT_INTERRUPTED, Plant, compile_notice, console, count, err_console, fail,
    fail_spec, figures_option, output, plain, run_errors, spec_of)
from marinecdpr.cli.progress import progress_bar, seconds
from marinecdpr.commands.base import SpecError
from marinecdpr.commands.design import JOURNAL, DesignCommandSpec
from marinecdpr.errors import ScenarioError
from marinecdpr.scenario.design import GENERATIONS, POPULATION, SEED_MAX

_default = DesignCommandSpec.default


def design(
    spec: str = typer.Argument("ship_side", help="A design study file (.toml), or a built-in study's name."),
    out: Path = typer.Option(Path("out"), "--out", "-o", help="Folder for candidates.csv, pareto.csv and .png, "
                             "convergence.png, finalists.csv and .png, designs/*.toml, summary.json, report.html "
                             "and the search's journal.jsonl."),
    population: Optional[int] = typer.Option(_default("population"), min=POPULATION[0], max=POPULATION[1],
                                             help="Candidates a generation (default: the study's)."),
    generations: Optional[int] = typer.Option(_default("generations"), min=GENERATIONS[0], max=GENERATIONS[1],
                                              help="Generations (default: the study's)."),
    seed: Optional[int] = typer.Option(_default("seed"), min=0, max=SEED_MAX,
                                       help="The search's seed (default: the study's)."),
    resume: bool = typer.Option(_default("resume"), "--resume", help="Go on with the search an interrupted run kept "
                                "in OUT/journal.jsonl (the same study, the same seed)."),
    verify: bool = typer.Option(_default("verify"), "--verify/--no-verify", help="Fly the finalists through the "
                                "cleaning job in every sea state, closed loop (the hours reported beside the "
                                "screen's)."),
    plant: Plant = typer.Option(_default("plant"), "--plant", help="The finalists' plant (default: the study's, else "
                                "the template's)."),
    serial: bool = typer.Option(_default("serial"), "--serial", help="Judge the candidates and fly the finalists' sea "
                                "states one after another."),
    workers: Optional[int] = typer.Option(_default("workers"), min=1, help="Local Dask workers for the candidates and "
                                          "the finalists' sea states (default: the candidates here, the sea states on "
                                          "Dask when they are many)."),
    scheduler: Optional[str] = typer.Option(_default("scheduler"), help="A running Dask scheduler's address for both."),
    figures: bool = figures_option("pareto.png, convergence.png, finalists.png and the report's images"),
) -> None:
    """Design a robot for a ship: search the frame, platform, winches, rope and tool that clean
    the study's surface in the fewest expected hours for the power installed, in its seas, and
    fly the best through the cleaning job in every sea state."""
    from marinecdpr.commands import design as command

    options = spec_of(DesignCommandSpec, population=population, generations=generations, seed=seed, resume=resume,
                      verify=verify, plant=plant, serial=serial, workers=workers, scheduler=scheduler,
                      figures=figures)
    journal = out / JOURNAL  # beside the staged files: an interrupted run keeps it
    try:  # before any work: the study, the executors, the journal a --resume goes on from
        est = command.estimate(options, spec, journal=journal)
    except SpecError as exc:
        fail_spec(exc)
    except ScenarioError as exc:
        fail(str(exc))
    if est.verify_executor.note:
        err_console.print(f"note: {est.verify_executor.note}", highlight=False, soft_wrap=True)
    study_spec, template, cells = est.study, est.template, est.cells
    t0 = time.perf_counter()
    with output(out) as folder:
        with progress_bar("design", "candidates") as bar:
            task = bar.add_task("", total=est.candidates)

            def progress(done: int, total: int, best: float) -> None:
                bar.update(task, completed=done, total=total,
                           description="best feasible: " + (f"{best:.4g} h" if best < float("inf") else "none yet"))

            try:
                with run_errors(spec):
                    study = command.search(options, est, progress=progress)
            except KeyboardInterrupt:
                kept = max(len(journal.read_text(encoding="utf-8").splitlines()) - 1, 0) if journal.is_file() else 0
                fail(f"interrupted; {count(kept, 'candidate')} kept in {journal}: rerun with --resume to go on",
                     EXIT_INTERRUPTED)
        checked = []
        if est.finalists and study.front:
            compile_notice(options.plant or study_spec.plant or template.simulation.plant)
            with progress_bar("finalists", "sea states") as bar:
                n = min(est.finalists, len(study.front))  # about each column's boundary: two seas each, first
                task = bar.add_task("", total=n * (len(cells) if study_spec.sea.verify == "all"
                                                   else 2 * est.columns_flown))
                with run_errors(spec):
                    checked = command.verify(options, est, study,
                                             progress=lambda d, tot: bar.update(task, completed=d, total=tot))
        result = command.DesignResult(study=study, template=template, verified=tuple(checked), cells=len(cells),
                                      figures=options.figures)
        paths = [out / p.relative_to(folder) for p in result.write(folder)]
    ev, b = study.evaluations, study.baseline
    console.print(plain(f"{study_spec.name}: {count(len(ev), 'candidate')} ({sum(e.feasible for e in ev)} "
                         f"feasible) over {count(len(cells), 'sea state')} in "
                         f"{seconds(time.perf_counter() - t0)}"), highlight=False, soft_wrap=True)
    if study.front:
        e = ev[study.front[0]]
        x = e.x
        console.print(plain(
            f"best: frame {x['frame_width_m']:.3g} x {x['frame_height_m']:.3g} m, platform {x['platform_width_m']:.3g} x "
            f"{x['platform_height_m']:.3g} m ({e.mass_kg:.3g} kg), cables {x.get('pattern', 'uncrossed')}, tool "
            f"{x['tool_width_m']:.3g} m at "
            f"{x['speed_m_s']:.3g} m/s, winches {x['winch']} ({e.power_kW:g} kW in all, T_max {e.tension_max_N:.4g} N), "
            f"rope {x['rope']}"
            + (f", moved by {x['relocation']}, {x['robots']} robot{'s' if x['robots'] != 1 else ''} "
               f"(the moves cost {e.relocation_cost:.6g})" if "relocation" in x else "")
            + (f", the carriage at {x.get('rail_speed_m_s', rail.speed_m_s):.3g} m/s, "
               f"{x.get('rail_accel_m_s2', rail.accel_m_s2):.3g} m/s^2, {x.get('rail_jerk_m_s3', rail.jerk_m_s3):.3g} "
               f"m/s^3" if x.get("relocation") == "rail" and (rail := study_spec.relocation.rail) is not None else "")
            + f": {e.placements} placements, {e.surface_hours:.4g} h on the surface, works in "
            f"{100 * e.sea_share:.1f} % of the seas: {e.expected_hours:.4g} expected h (target "
            f"{study_spec.targets.hours:g} h: {'met' if e.expected_hours <= study_spec.targets.hours else 'not met'})"),
            highlight=False, soft_wrap=True)
        if e.sea_reason:
            console.print(plain(f"  the screen: {e.sea_reason}"), highlight=False, soft_wrap=True)
        h = e.hours_breakdown()
        if all(math.isfinite(v) for v in h.values()):
            console.print(plain(
                f"its {e.expected_hours:.4g} expected h: {h['cleaning']:.3g} h cleaning + {h['turns']:.3g} h turns "
                f"between lanes + {h['moves']:.3g} h moving the frame + {h['weather']:.3g} h waiting for weather; "
                "binding: " + ", ".join(f"{k} ({100 * v:.3g} % left)" for k, v in e.binding())),
                highlight=False, soft_wrap=True)
    else:
        console.print("no feasible candidate: see candidates.csv's margins and reasons", highlight=False)
    if study_spec.constraints.single_cable_failure:
        from marinecdpr.report.design import safety_text

        console.print(plain(safety_text(study)), highlight=False, soft_wrap=True)
    for v in checked:
        console.print(plain(
            f"finalist {v.rank} (candidate {v.index}) in the time domain as built "
            f"({'MuJoCo' if v.plant == 'mujoco' else 'own plant'}, its rope's stretch, motor winches): works in {100 * v.td_share:.1f} % of the "
            f"seas (the screen: {100 * v.screen_share:.1f} %), {v.td_expected_hours:.4g} expected h (the screen: "
            f"{v.screen_expected_hours:.4g} h); verdicts agree in {v.agree} of {len(cells) - v.unjudged} sea states, the screen "
            f"passed {v.screen_works_td_fails} the time domain failed"
            + (f" ({v.flown} judged about each column's boundary, {v.planned_only} of them failing in their plan "
               f"and not flown; the rest taken from it)" if v.flown < len(cells) else "")
            + (f"; {v.unjudged} sea states of the least likely columns ({100 * v.unjudged_share:.2f} % of the "
               f"probability, [sea] unflown_share) not flown, counted as failing: at most "
               f"{100 * (v.td_share + v.unjudged_share):.1f} %" if v.unjudged else "")),
            highlight=False, soft_wrap=True)
        if v.rail_move is not None:
            from marinecdpr.report.design import rail_move_text

            console.print(plain(rail_move_text(v)), highlight=False, soft_wrap=True)
    console.print(plain(f"baseline (the template's robot): {b.placements} placements, {b.surface_hours:.4g} h on the "
                         f"surface, works in {100 * b.sea_share:.1f} % of the seas: {b.expected_hours:.4g} expected h"),
                  highlight=False, soft_wrap=True)
    if b.sea_reason:
        console.print(plain(f"  the screen: {b.sea_reason}"), highlight=False, soft_wrap=True)
    console.print("written: " + ", ".join(plain(p) for p in paths if p.parent == out) + ", designs/",
                  highlight=False, soft_wrap=True)
