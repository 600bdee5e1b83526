"""The ``clean`` command: the cleaning job: plan the coverage path over the panel, fly it closed loop in the
    scenario's sea, and measure the cleaned area from the simulated brush; beside it the
    same job in calm water and without the brush's drag. With --seas, in every sea state
    of a scatter diagram: where the job works, and its expected hours.

Options to :class:`~marinecdpr.commands.clean.CleanSpec`, the work to :mod:`marinecdpr.commands.clean`,
the result to lines."""

from __future__ import annotations

import time
from contextlib import ExitStack
from pathlib import Path
from typing import Optional

import typer

from marinecdpr.cli.common import (compile_notice, console, err_console, fail_bypassed, fail_scenario,
                                   fail_spec, figures_option, load, output, percent, plain, run_errors, spec_of,
                                   styled)
from marinecdpr.cli.progress import progress_bar, task_progress
from marinecdpr.cli.seas import print_sea_table
from marinecdpr.commands.base import SpecError
from marinecdpr.commands.clean import CleanSpec
from marinecdpr.errors import ScenarioError


def clean(
    scenario: str = typer.Argument("paper_clean", help="A scenario file with a [cleaning] section, or a built-in name."),
    out: Path = typer.Option(Path("out"), "--out", "-o", help="Folder for clean.csv, the figures, summary.json and "
                             "report.html."),
    plant: Optional[str] = typer.Option(CleanSpec.default("plant"), help="mujoco or own (default: the scenario's)."),
    duration: Optional[float] = typer.Option(CleanSpec.default("duration"),
                                             help="Clean only the first seconds of the path."),
    guarantee: bool = typer.Option(CleanSpec.default("guarantee"), "--guarantee", help="Set the lanes' overlap to "
                                   "twice the brush's p95 cross-track error from a first run, and check it with a "
                                   "second."),
    hull_area: Optional[float] = typer.Option(CleanSpec.default("hull_area"), "--hull-area", help="Estimate a hull of "
                                              "this many m2 (e.g. one side: length x draught), panel after panel."),
    move_time: Optional[float] = typer.Option(CleanSpec.default("move_time"), "--move-time",
                                              help="Seconds to move the frame to its next place (default 600; a "
                                              "crane or rail relocation in [cleaning.surface] times its own moves)."),
    surface: bool = typer.Option(CleanSpec.default("surface"), "--surface", help="Clean the scenario's "
                                 "[cleaning.surface] band of the hull: the frame's placements on the curved surface, "
                                 "and their hours."),
    rail: bool = typer.Option(CleanSpec.default("rail"), "--rail", help="With --surface: clean the band as a strip "
                              "from the stations of the scenario's [ship.carriage] rail, one panel along at a time "
                              "(crane placements where the rail does not reach)."),
    rail_mode: str = typer.Option(CleanSpec.default("rail_mode"), "--rail-mode", help="With --rail: stepped (the "
                                  "carriage steps the frame panel by panel), continuous (it moves without stopping, "
                                  "the platform's path compensating) or fastest (the faster on each stretch)."),
    fly_runs: str = typer.Option(CleanSpec.default("fly_runs"), "--fly-runs", help="With --rail, not stepped: the "
                                 "continuous runs flown closed loop over the horizon: first or all."),
    seas: bool = typer.Option(CleanSpec.default("seas"), "--seas", help="Fly the job in every sea state of a scatter "
                              "diagram (the scenario's sea_state with each Hs, Tp and heading) and say where it works."),
    scatter: Optional[Path] = typer.Option(CleanSpec.default("scatter"), help="With --seas: the scatter diagram CSV "
                                           "(hs_m,tp_s,probability or hs_m,tz_s,probability), or a package "
                                           "diagram's name: illustrative (the default), north_atlantic."),
    headings: str = typer.Option(",".join(f"{h:g}" for h in CleanSpec.default("headings")),
                                 help="With --seas: wave headings, deg, comma-separated."),
    coverage_target: float = typer.Option(CleanSpec.default("coverage_target"), help="With --seas: % of the reachable "
                                          "panel a working job cleans."),
    in_band_target: float = typer.Option(CleanSpec.default("in_band_target"), help="With --seas: % of the time a "
                                         "working job keeps the normal force in band."),
    serial: bool = typer.Option(CleanSpec.default("serial"), "--serial",
                                help="With --seas: run the sea states in this process."),
    workers: Optional[int] = typer.Option(CleanSpec.default("workers"), min=1,
                                          help="With --seas: a local Dask cluster of this many workers."),
    scheduler: Optional[str] = typer.Option(CleanSpec.default("scheduler"),
                                            help="With --seas: a running Dask scheduler at this address."),
    compare: bool = typer.Option(CleanSpec.default("compare"), "--compare/--no-compare", help="Also fly the job in "
                                 "calm water and without the brush's drag, and set the figures side by side."),
    figures: bool = figures_option("coverage.png, cleaning.png (surface.png, sea_states.png) and the report's images"),
) -> None:
    """The cleaning job: plan the coverage path over the panel, fly it closed loop in the
    scenario's sea, and measure the cleaned area from the simulated brush; beside it the
    same job in calm water and without the brush's drag. With --seas, in every sea state
    of a scatter diagram: where the job works, and its expected hours."""
    from marinecdpr.commands import clean as command

    spec = spec_of(CleanSpec, plant=plant, duration=duration, guarantee=guarantee, hull_area=hull_area,
                   move_time=move_time, surface=surface, rail=rail, rail_mode=rail_mode, fly_runs=fly_runs, seas=seas,
                   scatter=scatter, headings=headings, coverage_target=coverage_target, in_band_target=in_band_target,
                   serial=serial, workers=workers, scheduler=scheduler, compare=compare, figures=figures)
    sc = load(scenario, None, None)
    try:  # before any work: no cleaning job, no sea state, a diagram that cannot be read, too big, the executor
        est = command.estimate(spec, sc)
    except SpecError as exc:
        fail_spec(exc)
    except ScenarioError as exc:
        fail_scenario(exc, scenario)
    for line in est.warnings(plain(scenario)):
        err_console.print(styled("warning:", "bold yellow", line), highlight=False, soft_wrap=True)
    if spec.over_seas:
        return _clean_seas(scenario, spec, sc, est, out)
    placed = _tiled(scenario, spec, est) if spec.surface else None
    t0 = time.perf_counter()
    n = est.flown.time.n_steps
    with output(out) as folder:
        compile_notice(spec.plant or sc.simulation.plant)
        # runs one after the other, each planned first: the time left once a run's worth is known
        with task_progress("clean", est.runs * n, "steps", eta_after=n if est.runs > 1 else 0) as update:
            with run_errors(scenario):
                try:
                    result = command.run(spec, sc, estimated=est, progress=update, placed=placed)
                except SpecError as exc:  # a hull estimate from a job that cleaned nothing
                    fail_spec(exc)
        paths = result.write(folder)
    _print_job(result, spec, out, paths, time.perf_counter() - t0)
    fail_bypassed(result.bypassed(), sc, out)


def _tiled(scenario: str, spec: CleanSpec, est):
    """``--surface``: the frame's placements (with ``--rail``, the rail's stations), before the
    job (a missing surface, or one that cannot be tiled, is one line), with its own progress
    once the band's checks pass."""
    from marinecdpr.commands import clean as command

    what = "rail stations" if spec.rail else "surface tiling"
    try:
        with ExitStack() as stack:
            update = []  # the progress starts with the tiling itself, after the band's checks

            def tiled(share: float) -> None:
                if not update:
                    update.append(stack.enter_context(task_progress(what, 100, "%")))
                update[0](round(100 * share))

            return command.tile(spec, est.flown, progress=tiled)
    except ScenarioError as exc:
        fail_scenario(exc, scenario)


def _print_job(result, spec: CleanSpec, out: Path, paths: list[Path], elapsed: float) -> None:
    """The job's findings, its surface, interference and guarantee, and the files written."""
    for sentence in result.findings():
        console.print(plain(sentence), highlight=False, soft_wrap=True)
    if result.surface is not None:
        import numpy as np

        u = result.surface
        frame = np.ptp(result.scenario.robot.frame_anchors, axis=0)  # the frame's extent along C's x and z, m
        all_robots = " by all robots" if u.moves is not None and u.moves.robots > 1 else ""
        console.print(plain(f"surface: {u.surface}: {len(u.placements)} placements of the {frame[0]:.3g} x "
                            f"{frame[2]:.3g} m frame, each cleaning its {u.frame_panel_m[0]:g} x "
                            f"{u.frame_panel_m[1]:g} m panel, {u.area_m2:.4g} m2: "
                            f"{u.hours:.4g} h ({u.cleaning_hours:.4g} h cleaning{all_robots}, {u.moves_said()}; "
                            f"{u.area_rate_m2_h:.3g} m2/h)"
                            + (f"; {len(u.uncleanable)} patches ({u.uncleanable_area_m2:.3g} m2) curved "
                               "beyond the stand-off tolerance" if u.uncleanable else "")),
                      highlight=False, soft_wrap=True)
        if u.moves is not None and u.relocation_cost.total > 0:
            c = u.relocation_cost
            console.print(plain(f"relocation cost: {c.total:.6g} (crane hire {c.crane_hire:.6g}, rail "
                                f"{c.rail:.6g}, carriages {c.carriages:.6g})"), highlight=False, soft_wrap=True)
    if result.strip is not None:
        _print_strip(result.strip)
    f = result.job.figures
    close = f.interference
    if close is not None and close["first"] is not None:
        err_console.print(plain(f"warning: plan: {close['first']}"), highlight=False, soft_wrap=True)
    if spec.guarantee:
        g = f.guarantee
        console.print(plain(f"guarantee: {g.reason}; lanes {g.lane_spacing_m:.4g} m apart; "
                            + (("checked by a second run" if g.second_run else "as flown") if g.checked else
                               f"NOT met: the run's p95 cross-track error is {g.checked_p95_cross_track_error_m:.3g} m")),
                      highlight=False, soft_wrap=True)
    console.print(f"written to {plain(str(out))}/: {', '.join(p.name for p in paths)} ({elapsed:.1f} s)",
                  highlight=False, soft_wrap=True)


def _print_strip(st) -> None:
    """``--rail``: the strip's coverage on the hull, its hours, its stations and its crane stretches."""
    c, parts = st.coverage, st.parts_h()
    partial = (" (a PARTIAL job: each station's and run's coverage is the flown part's)" if st.runs else
               " (a PARTIAL job: each station's coverage is the flown part's)") if st.partial else ""
    runs = f", {len(st.runs)} continuous run{'s' if len(st.runs) != 1 else ''}" if st.runs else ""
    console.print(plain(f"strip: {st.surface}: {st.s_m.size} rail stations{runs} and {len(st.crane)} crane placements, "
                        f"{c.coverage_pct:.2f} % of the strip's {c.area_m2:.4g} m2 on the hull cleaned{partial} "
                        f"({c.overlap_pct:.3g} % of it twice or more), {st.hours:.4g} h ({parts['cleaning_rail']:.4g} "
                        f"h cleaning from the rail, {parts['moves_rail']:.4g} h carriage moves, "
                        f"{parts['cleaning_crane'] + parts['moves_crane']:.4g} h by crane)"), highlight=False,
                  soft_wrap=True)
    if st.s_m.size:
        console.print(plain(f"stations: stand-off {1e3 * st.stand_off_m[:, 0].min():.3g} to "
                            f"{1e3 * st.stand_off_m[:, 1].max():.3g} mm, normal force on the hull "
                            f"{st.force_N[:, 0].min():.4g} to {st.force_N[:, 1].max():.4g} N"
                            + (f"; {int(st.beyond_tolerance.sum())} beyond the tool's stand-off tolerance"
                               if st.beyond_tolerance.any() else "")), highlight=False, soft_wrap=True)
    if st.runs:
        lo = min(r.stand_off_m[0] for r in st.runs)
        hi = max(r.stand_off_m[1] for r in st.runs)
        console.print(plain(f"continuous runs: stand-off {1e3 * lo:.3g} to {1e3 * hi:.3g} mm, normal force on the hull "
                            f"{min(r.force_N[0] for r in st.runs):.4g} to {max(r.force_N[1] for r in st.runs):.4g} N"
                            + (f"; {int(st.run_beyond_tolerance.sum())} beyond the tool's stand-off tolerance"
                               if st.run_beyond_tolerance.any() else "")), highlight=False, soft_wrap=True)
    for j, fl in enumerate(st.flights):
        (f_lo, f_hi), (t_lo, t_hi) = fl.force_range_N, fl.tension_range_N
        which = "continuous run" if len(st.flights) == 1 else f"continuous run {j + 1}"
        console.print(plain(f"{which} flown closed loop ({fl.plant}, {fl.flown_s:.4g} s of its "
                            f"{fl.path_s:.4g} s{', PARTIAL' if fl.partial else ''}): normal force in band "
                            f"{fl.in_band_pct:.4g} % ({f_lo:.4g} to {f_hi:.4g} N on the hull), tracking "
                            f"{1e3 * fl.tracking_m.max():.3g} mm (cross-track {1e3 * fl.cross_track_m.max():.3g} mm), "
                            f"tensions {t_lo:.4g} to {t_hi:.4g} N, {fl.coverage.cleaned_area_m2:.4g} m2 cleaned on the "
                            f"hull ({fl.cleaned_of_planned_pct:.4g} % of the plan's), controller "
                            f"{fl.controller_verdict}"), highlight=False, soft_wrap=True)
    for ch in st.choices:
        other = ("cannot run continuously: " + ch.why_not if ch.continuous_h is None
                 else f"continuous {ch.continuous_h:.4g} h at {100.0 * ch.continuous_speed_m_s:.3g} cm/s")
        console.print(plain(f"rail stretch s = {ch.s_m[0]:.4g} to {ch.s_m[1]:.4g} m: {ch.mode} ({st.mode} asked); "
                            f"stepped {ch.stepped_h:.4g} h, {other}"), highlight=False, soft_wrap=True)
    for part in st.stretches:
        console.print(plain(f"by crane: stations {part.x_m[0]:.4g} to {part.x_m[1]:.4g} m ({part.why}): "
                            f"{part.placements} placements, {part.crane_moves} crane moves, {part.hours:.4g} h"),
                      highlight=False, soft_wrap=True)


def _clean_seas(scenario: str, spec: CleanSpec, sc, est, out: Path) -> None:
    """``clean --seas``: the cleaning job over a scatter diagram."""
    from marinecdpr.commands import clean as command

    if est.executor.note:
        err_console.print(f"note: {est.executor.note}", highlight=False, soft_wrap=True)
    t0 = time.perf_counter()
    with output(out) as folder:
        compile_notice(spec.plant or sc.simulation.plant)
        with progress_bar("sea states") as bar:
            task = bar.add_task("", total=est.cells)
            with run_errors(scenario):
                result = command.run(spec, sc, estimated=est,
                                     progress=lambda d, tot: bar.update(task, completed=d, total=tot))
        paths = result.write(folder)
    cs = result.seas
    print_sea_table(cs.sea, f"cleaning job over the sea states: {plain(sc.name)}", result.executor,
                    time.perf_counter() - t0)
    what = "the hull" if spec.hull_area is not None else "one panel"
    hours = ("no sea state" if cs.expected_hours != cs.expected_hours else
             f"{cs.expected_hours:.3g} h for {what} where it works, {cs.expected_hours_with_weather:.3g} h "
             "waiting for workable seas")
    console.print(plain(f"the job works in {percent(cs.sea.operability)} of the sea states (at least "
                        f"{spec.coverage_target:g} % of the reachable panel cleaned, the normal force in band at least "
                        f"{spec.in_band_target:g} % of the time, tensions within limits); expected {hours}"),
                  highlight=False, soft_wrap=True)
    console.print(f"written to {plain(str(out))}/: {', '.join(p.name for p in paths)}", highlight=False,
                  soft_wrap=True)
