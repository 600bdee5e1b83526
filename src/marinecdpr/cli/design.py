"""The ``design`` command: design a robot for a ship: search the frame, platform, winches, rope and tool that clean
    the study's surface in the fewest expected hours for the power installed, in its seas, and
    fly the best through the cleaning job in every sea state."""

from __future__ import annotations

import math
import time
from pathlib import Path
from typing import Optional

import typer

from marinecdpr.cli.common import (EXIT_INTERRUPTED, Plant, compile_notice, console, count, fail, output, plain,
    run_errors)
from marinecdpr.cli.progress import progress_bar, seconds
from marinecdpr.cli.seas import sea_executor, sea_study_options
from marinecdpr.errors import ScenarioError
from marinecdpr.scenario.design import GENERATIONS, POPULATION, SEED_MAX


def design(
    spec: str = typer.Argument("ship_side", help="A design study file (.toml), or a built-in study's name."),
    out: Path = typer.Option(Path("out"), "--out", "-o", help="Folder for candidates.csv, pareto.csv and .png, "
                             "convergence.png, finalists.csv and .png, designs/*.toml, summary.json, report.html "
                             "and the search's journal.jsonl."),
    population: Optional[int] = typer.Option(None, min=POPULATION[0], max=POPULATION[1],
                                             help="Candidates a generation (default: the study's)."),
    generations: Optional[int] = typer.Option(None, min=GENERATIONS[0], max=GENERATIONS[1],
                                              help="Generations (default: the study's)."),
    seed: Optional[int] = typer.Option(None, min=0, max=SEED_MAX, help="The search's seed (default: the study's)."),
    resume: bool = typer.Option(False, "--resume", help="Go on with the search an interrupted run kept in "
                                "OUT/journal.jsonl (the same study, the same seed)."),
    verify: bool = typer.Option(True, "--verify/--no-verify", help="Fly the finalists through the cleaning job in "
                                "every sea state, closed loop (the hours reported beside the screen's)."),
    plant: Plant = typer.Option(None, "--plant", help="The finalists' plant (default: the study's, else the template's)."),
    serial: bool = typer.Option(False, "--serial", help="Judge the candidates and fly the finalists' sea states "
                                "one after another."),
    workers: Optional[int] = typer.Option(None, min=1, help="Local Dask workers for the candidates and the "
                                          "finalists' sea states (default: the candidates here, the sea states on "
                                          "Dask when they are many)."),
    scheduler: Optional[str] = typer.Option(None, help="A running Dask scheduler's address for both."),
) -> None:
    """Design a robot for a ship: search the frame, platform, winches, rope and tool that clean
    the study's surface in the fewest expected hours for the power installed, in its seas, and
    fly the best through the cleaning job in every sea state."""
    from marinecdpr.studies.design import (load_design, read_journal, search, study_cells, study_key, study_path,
                                           study_scatter, with_options)
    from marinecdpr.studies.design import verify as verify_finalists

    path = study_path(spec)
    try:
        import pymoo  # noqa: F401
    except ImportError:
        fail("design needs pymoo: pip install 'marinecdpr[design]'")
    try:
        study_spec, template = load_design(path)
        study_spec = with_options(study_spec, population=population, generations=generations, seed=seed)
        cells = study_cells(study_spec, path.parent)
    except ScenarioError as exc:
        fail(str(exc))
    sea_study_options(",".join(f"{h:g}" for h in study_spec.sea.headings_deg), serial, workers, scheduler)
    n_final = study_spec.finalists if verify else 0
    from marinecdpr.studies.operability import CLOSED_LOOP_STEP_COST

    steps = n_final * len(cells) * template.time.n_steps * CLOSED_LOOP_STEP_COST  # about: each finalist's own
    from marinecdpr.studies.executor import Executor

    executor = sea_executor(serial, workers, scheduler, steps) if n_final else Executor.serial()
    # the candidates: on Dask where --workers or --scheduler asks for it, else one by one
    judges = (Executor.serial() if serial or (workers is None and not scheduler)
              else sea_executor(False, workers, scheduler, 0))
    if resume:  # before the search's first line: a journal that cannot be resumed is one line
        try:
            read_journal(out / "journal.jsonl", study_key(study_spec, template, cells))
        except ScenarioError as exc:
            fail(str(exc))
    t0 = time.perf_counter()
    with output(out) as folder:
        with progress_bar("design", "candidates") as bar:
            task = bar.add_task("", total=study_spec.population * study_spec.generations)

            def progress(done: int, total: int, best: float) -> None:
                bar.update(task, completed=done, total=total,
                           description="best feasible: " + (f"{best:.4g} h" if best < float("inf") else "none yet"))

            journal = out / "journal.jsonl"  # beside the staged files: an interrupted run keeps it
            try:
                with run_errors(spec):
                    study = search(study_spec, template, cells, progress=progress, journal=journal, resume=resume,
                                   executor=judges)
            except KeyboardInterrupt:
                kept = max(len(journal.read_text(encoding="utf-8").splitlines()) - 1, 0) if journal.is_file() else 0
                fail(f"interrupted; {count(kept, 'candidate')} kept in {journal}: rerun with --resume to go on",
                      EXIT_INTERRUPTED)
        checked = []
        if n_final and study.front:
            compile_notice(plant.value if plant is not None else study_spec.plant or template.simulation.plant)
            with progress_bar("finalists", "sea states") as bar:
                task = bar.add_task("", total=min(n_final, len(study.front)) * len(cells))
                with run_errors(spec):
                    checked = verify_finalists(study, template, study_scatter(study_spec, path.parent),
                                               executor=executor,
                                               plant=plant.value if plant is not None else None,
                                               progress=lambda d, tot: bar.update(task, completed=d, total=tot))
        from marinecdpr.report.design import write_design

        paths = [out / p.relative_to(folder) for p in write_design(study, template, folder, checked)]
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
            f"rope {x['rope']}: {e.placements} placements, {e.surface_hours:.4g} h on the surface, works in "
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
    for v in checked:
        console.print(plain(
            f"finalist {v.rank} (candidate {v.index}) in the time domain as built "
            f"({'MuJoCo' if v.plant == 'mujoco' else 'own plant'}, its rope's stretch, motor winches): works in {100 * v.td_share:.1f} % of the "
            f"seas (the screen: {100 * v.screen_share:.1f} %), {v.td_expected_hours:.4g} expected h (the screen: "
            f"{v.screen_expected_hours:.4g} h); verdicts agree in {v.agree} of {len(cells)} sea states, the screen "
            f"passed {v.screen_works_td_fails} the time domain failed"), highlight=False, soft_wrap=True)
    console.print(plain(f"baseline (the template's robot): {b.placements} placements, {b.surface_hours:.4g} h on the "
                         f"surface, works in {100 * b.sea_share:.1f} % of the seas: {b.expected_hours:.4g} expected h"),
                  highlight=False, soft_wrap=True)
    if b.sea_reason:
        console.print(plain(f"  the screen: {b.sea_reason}"), highlight=False, soft_wrap=True)
    console.print("written: " + ", ".join(plain(p) for p in paths if p.parent == out) + ", designs/",
                  highlight=False, soft_wrap=True)
