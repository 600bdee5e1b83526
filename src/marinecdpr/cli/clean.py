"""The ``clean`` command: the cleaning job: plan the coverage path over the panel, fly it closed loop in the
    scenario's sea, and measure the cleaned area from the simulated brush; beside it the
    same job in calm water and without the brush's drag. With --seas, in every sea state
    of a scatter diagram: where the job works, and its expected hours."""

from __future__ import annotations

import math
import time
from contextlib import ExitStack
from pathlib import Path
from typing import Optional

import typer

from marinecdpr.cli.common import (compile_notice, console, err_console, fail, fail_bypassed, fail_scenario, number,
    output, percent, plain, run_errors, scenario_to_fly, styled)
from marinecdpr.cli.progress import progress_bar, task_progress
from marinecdpr.cli.seas import print_sea_table, scatter_diagram, sea_executor, sea_study_options
from marinecdpr.errors import ScenarioError


def clean(
    scenario: str = typer.Argument("paper_clean", help="A scenario file with a [cleaning] section, or a built-in name."),
    out: Path = typer.Option(Path("out"), "--out", "-o", help="Folder for clean.csv, the figures, summary.json and "
                             "report.html."),
    plant: Optional[str] = typer.Option(None, help="mujoco or own (default: the scenario's)."),
    duration: Optional[float] = typer.Option(None, help="Clean only the first seconds of the path."),
    guarantee: bool = typer.Option(False, "--guarantee", help="Set the lanes' overlap to twice the brush's "
                                   "p95 cross-track error from a first run, and check it with a second."),
    hull_area: Optional[float] = typer.Option(None, "--hull-area", help="Estimate a hull of this many m2 (e.g. "
                                              "one side: length x draught), panel after panel."),
    move_time: float = typer.Option(600.0, "--move-time", help="Seconds to move the frame to its next place."),
    surface: bool = typer.Option(False, "--surface", help="Clean the scenario's [cleaning.surface] band of the hull: "
                                 "the frame's placements on the curved surface, and their hours."),
    seas: bool = typer.Option(False, "--seas", help="Fly the job in every sea state of a scatter diagram (the "
                              "scenario's sea_state with each Hs, Tp and heading) and say where it works."),
    scatter: Optional[Path] = typer.Option(None, help="With --seas: the scatter diagram CSV (hs_m,tp_s,"
                                           "probability); default: the package's illustrative one."),
    headings: str = typer.Option("180", help="With --seas: wave headings, deg, comma-separated."),
    coverage_target: float = typer.Option(99.0, help="With --seas: % of the reachable panel a working job cleans."),
    in_band_target: float = typer.Option(95.0, help="With --seas: % of the time a working job keeps the normal "
                                         "force in band."),
    serial: bool = typer.Option(False, "--serial", help="With --seas: run the sea states in this process."),
    workers: Optional[int] = typer.Option(None, min=1, help="With --seas: a local Dask cluster of this many workers."),
    scheduler: Optional[str] = typer.Option(None, help="With --seas: a running Dask scheduler at this address."),
    compare: bool = typer.Option(True, "--compare/--no-compare", help="Also fly the job in calm water and without "
                                 "the brush's drag, and set the figures side by side."),
) -> None:
    """The cleaning job: plan the coverage path over the panel, fly it closed loop in the
    scenario's sea, and measure the cleaned area from the simulated brush; beside it the
    same job in calm water and without the brush's drag. With --seas, in every sea state
    of a scatter diagram: where the job works, and its expected hours."""
    from marinecdpr.report.cleaning import cleaning_findings, write_cleaning
    from marinecdpr.studies.cleaning import cleaning_job, compare_conditions, guaranteed_job, job_variants, ship_side

    if plant is not None and plant not in ("mujoco", "own"):
        fail(f"--plant {plant}: expected mujoco or own")
    number("--duration", duration)
    number("--hull-area", hull_area)
    number("--move-time", move_time, zero_ok=True)
    if surface:
        from marinecdpr.studies.surface import check_move_time

        try:  # a move longer than the cap makes hours that mean nothing (1e308 s: not finite)
            check_move_time(move_time)
        except ScenarioError as exc:
            fail(f"--move-time {move_time:g}: {exc.detail.split(', got')[0]}")
    if hull_area is not None:
        from marinecdpr.studies.cleaning import check_hull_estimate

        try:  # before the job: an estimate that would mean nothing is one line
            check_hull_estimate(hull_area, move_time)
        except ValueError as exc:
            fail(f"--hull-area {hull_area:g} / --move-time {move_time:g}: {exc}")
    sc = scenario_to_fly(scenario, duration, "simulate", cleaning=True)
    if surface:
        if hull_area is not None:
            fail("--surface and --hull-area: choose one (--surface has the hull's real placements)")
        if seas or scatter is not None:
            fail("--surface cannot go with --seas yet: its hours are for the scenario's sea")
        from marinecdpr.studies.surface import surface_job

        try:  # before the job: a missing surface, or one that cannot be tiled, is one line
            with ExitStack() as stack:
                update = []  # the progress starts with the tiling itself, after the band's checks

                def tiled(share: float) -> None:
                    if not update:
                        update.append(stack.enter_context(task_progress("surface tiling", 100, "%")))
                    update[0](round(100 * share))

                placed = surface_job(sc, move_time_s=move_time, progress=tiled)
        except ScenarioError as exc:
            fail_scenario(exc, scenario)
    if seas or scatter is not None:
        if guarantee:
            fail("--guarantee cannot go with --seas: it sets the lanes from one sea state's run")
        for name, value in (("--coverage-target", coverage_target), ("--in-band-target", in_band_target)):
            if not (math.isfinite(value) and 0.0 <= value <= 100.0):
                fail(f"{name} {value:g}: expected a percentage between 0 and 100")
        heads = sea_study_options(headings, serial, workers, scheduler)
        from marinecdpr.motion.trajectory import cleaning_path

        path_end = sc.trajectory.start_time_s + cleaning_path(sc.cleaning).duration_s
        if sc.time.duration_s < path_end:  # each sea state's verdict and hours are the part's
            err_console.print(styled("warning:", "bold yellow", f"{plain(scenario)}: a PARTIAL job: each sea state "
                                      f"flies the first {sc.time.duration_s:g} s of the {path_end:.4g} s path; its "
                                      "coverage and hours are that part's"), highlight=False, soft_wrap=True)
        return _clean_seas(scenario, sc, scatter_diagram(scatter), heads, out, plant=plant, hull_area=hull_area,
                           move_time=move_time, coverage_target=coverage_target, in_band_target=in_band_target,
                           serial=serial, workers=workers, scheduler=scheduler)
    t0 = time.perf_counter()
    with output(out) as folder:
        compile_notice(plant or sc.simulation.plant)
        runs = (2 if guarantee else 1) + (len(job_variants(sc)) - 1 if compare else 0)
        # runs one after the other, each planned first: the time left once a run's worth is known
        with task_progress("clean", runs * sc.time.n_steps, "steps", eta_after=sc.time.n_steps if runs > 1 else 0) \
                as update:
            done = [0]

            def step(k: int, n: int) -> None:  # runs one after the other on one bar
                update(done[0] + k, runs * sc.time.n_steps)
                if k == n:
                    done[0] += n

            with run_errors(scenario):
                job = (guaranteed_job if guarantee else cleaning_job)(sc, plant=plant, progress=step)
                if compare:
                    job.summary["comparison"] = compare_conditions(job, plant=plant, progress=step)
            update(done[0], done[0])  # the runs that were flown (a guarantee met at once skips its second)
        if hull_area is not None:
            try:
                job.summary["hull"] = ship_side(job.summary, hull_area_m2=hull_area, move_time_s=move_time)
            except ValueError as exc:
                fail(f"--hull-area: {exc}")
        if surface:
            from marinecdpr.report.cleaning import write_surface

            job.summary["surface"] = placed.summary()
            surface_paths = write_surface(placed, folder)
        paths = write_cleaning(job, folder) + (surface_paths if surface else [])
    for sentence in cleaning_findings(job.summary):
        console.print(plain(sentence), highlight=False, soft_wrap=True)
    if surface:
        u = job.summary["surface"]
        import numpy as np

        frame = np.ptp(sc.robot.frame_anchors, axis=0)  # the frame's extent along C's x and z, m
        console.print(plain(f"surface: {u['surface']}: {u['placements']} placements of the {frame[0]:.3g} x "
                             f"{frame[2]:.3g} m frame, each cleaning its {u['frame_panel_m'][0]:g} x "
                             f"{u['frame_panel_m'][1]:g} m panel, {u['area_m2']:.4g} m2: "
                             f"{u['hours']:.4g} h ({u['cleaning_hours']:.4g} h cleaning, moves of {move_time:g} s; "
                             f"{u['area_rate_m2_h']:.3g} m2/h)"
                             + (f"; {u['uncleanable_patches']} patches ({u['uncleanable_area_m2']:.3g} m2) curved "
                                "beyond the stand-off tolerance" if u["uncleanable_patches"] else "")),
                      highlight=False, soft_wrap=True)
    close = job.summary.get("interference")
    if close is not None and close["first"] is not None:
        err_console.print(plain(f"warning: plan: {close['first']}"), highlight=False, soft_wrap=True)
    if guarantee:
        g = job.summary["guarantee"]
        console.print(plain(f"guarantee: {g['reason']}; lanes {g['lane_spacing_m']:.4g} m apart; "
                             + (("checked by a second run" if g["second_run"] else "as flown") if g["checked"] else
                                f"NOT met: the run's p95 cross-track error is {g['checked_p95_cross_track_error_m']:.3g} m")),
                      highlight=False, soft_wrap=True)
    console.print(f"written to {plain(str(out))}/: {', '.join(p.name for p in paths)} "
                  f"({time.perf_counter() - t0:.1f} s)", highlight=False, soft_wrap=True)
    fail_bypassed(_clean_bypassed(job.summary, sc), sc, out)


def _clean_bypassed(s: dict, sc) -> list[tuple[str, int, int]]:
    """The cleaning job's closed loops whose controller was bypassed: (name, bypassed steps,
    steps) of the job, the guarantee's first run and the compared variants."""
    share = sc.simulation.max_bypassed_share
    runs = [("the cleaning job", s["controller_fallbacks"], s["steps"])] if s["controller_verdict"] == "bypassed" else []
    g = s.get("guarantee")
    if g is not None and g["second_run"] and g["first_run_controller_verdict"] == "bypassed":
        runs.append(("the guarantee's first run", g["first_run_controller_fallbacks"], s["steps"]))
    for name, figures in s.get("comparison", {}).items():
        if name != "as asked" and figures["controller_bypassed_share"] > share:
            runs.append((f"the job in {name}" if name == "calm water" else f"the job with {name}",
                         figures["controller_fallbacks"], s["steps"]))
    return runs


def _clean_seas(scenario: str, sc, diagram, heads, out: Path, *, plant, hull_area, move_time, coverage_target,
                in_band_target, serial, workers, scheduler) -> None:
    """``clean --seas``: the cleaning job over a scatter diagram."""
    from marinecdpr.report.cleaning import write_cleaning_seas
    from marinecdpr.studies.cleaning import cleaning_seas
    from marinecdpr.studies.operability import CLOSED_LOOP_STEP_COST, check_sea_state

    try:
        check_sea_state(sc)
    except ScenarioError as exc:
        fail_scenario(exc, scenario)
    from marinecdpr.planning.budget import check_run_size

    n_cells = int((diagram.probability > 0).sum()) * len(heads)
    from marinecdpr.studies.executor import LOCAL_WORKERS

    try:  # before any work: every sea state flies the job closed loop
        check_run_size(sc, "operability", cells=n_cells, closed_loop=True,
                       workers=1 if serial else (workers or LOCAL_WORKERS))
    except ScenarioError as exc:
        fail_scenario(exc, scenario)
    executor = sea_executor(serial, workers, scheduler, n_cells * sc.time.n_steps * CLOSED_LOOP_STEP_COST)
    t0 = time.perf_counter()
    with output(out) as folder:
        compile_notice(plant or sc.simulation.plant)
        with progress_bar("sea states") as bar:
            task = bar.add_task("", total=n_cells)
            with run_errors(scenario):
                cs = cleaning_seas(sc, diagram, headings_deg=heads, coverage_target_pct=coverage_target,
                                   in_band_target_pct=in_band_target, plant=plant, hull_area_m2=hull_area,
                                   move_time_s=move_time, executor=executor,
                                   progress=lambda d, tot: bar.update(task, completed=d, total=tot))
        paths = write_cleaning_seas(cs, sc, folder)
    print_sea_table(cs.sea, f"cleaning job over the sea states: {plain(sc.name)}", executor,
                     time.perf_counter() - t0)
    what = "the hull" if hull_area is not None else "one panel"
    hours = ("no sea state" if cs.expected_hours != cs.expected_hours else
             f"{cs.expected_hours:.3g} h for {what} where it works, {cs.expected_hours_with_weather:.3g} h "
             "waiting for workable seas")
    console.print(plain(f"the job works in {percent(cs.sea.operability)} of the sea states (at least "
                         f"{coverage_target:g} % of the reachable panel cleaned, the normal force in band at least "
                         f"{in_band_target:g} % of the time, tensions within limits); expected {hours}"),
                  highlight=False, soft_wrap=True)
    console.print(f"written to {plain(str(out))}/: {', '.join(p.name for p in paths)}", highlight=False,
                  soft_wrap=True)
