"""The ``marinecdpr`` command: parses arguments, calls the library, prints.

Exit codes: 0 success; 2 bad input (a scenario, an option, or an output folder that
cannot be written); 3 the cables cannot hold the platform somewhere on the plan
(``plan`` still writes its outputs, complete); 4 a simulation diverged; 5 a closed loop's
controller was bypassed (the plan's tensions fed forward) on more than ``[simulation]
max_bypassed_share`` of its steps (the outputs are written, complete, with the verdict);
130 interrupted (Ctrl-C: the output folder keeps what it held).
"""

from __future__ import annotations

import enum

import math
import os
import signal
import sys

from marinecdpr.starting import catch_while_starting
from marinecdpr.starting import interrupted_while_starting as _interrupted_while_starting

# first, before the heavy imports below (typer, rich, numpy, pydantic: about a second on a
# loaded machine); the package set it already where the console script imported it
catch_while_starting()

import time  # noqa: E402
from contextlib import ExitStack, contextmanager
from pathlib import Path
from typing import Optional

import typer
from rich.console import Console
from rich.markup import escape
from rich.table import Table
from rich.text import Text

from marinecdpr.commands.control_study import ControlStudySpec
from marinecdpr.commands.workspace import WorkspaceSpec
from marinecdpr.errors import InfeasibleError, ScenarioError, SimulationDivergedError
from marinecdpr.memory import keep_freed_memory
from marinecdpr.scenario.design import GENERATIONS, POPULATION, SEED_MAX
from marinecdpr.scenario.fields import TENSION_METHODS
from marinecdpr.scenario.loading import builtin_scenarios, load_scenario
from marinecdpr.textfiles import strip_control

EXIT_BAD_INPUT = 2
EXIT_INFEASIBLE = 3
EXIT_DIVERGED = 4
EXIT_BYPASSED = 5
EXIT_INTERRUPTED = 130

class _OneLineUsage(typer.core.TyperGroup):
    """The command group, its option parser's errors one line (``error: ...``, exit 2) like
    every other bad input, not click's usage box. Asking for help with no arguments still
    shows the help."""

    def parse_args(self, ctx, args):
        with _usage_in_one_line():
            return super().parse_args(ctx, args)

    def invoke(self, ctx):  # a command's own options are parsed as the group invokes it
        with _usage_in_one_line():
            return super().invoke(ctx)

    def get_params(self, ctx):
        return _help_params(super().get_params(ctx))

    def resolve_command(self, ctx, args):
        global _running_command
        name, command, rest = super().resolve_command(ctx, args)
        _running_command = command.name if command is not None else name
        return name, command, rest


_running_command: str | None = None
"""The command being run (``plan``, ``simulate``, ...): the kind of run an output folder's
manifest records (:func:`_output`)."""


class _FlagOption(typer.core.TyperOption):
    """A flag in the help without a type (it takes no value: typer showed ``<bool>``)."""

    def display_type_rich(self, ctx):
        return None if self.is_flag else super().display_type_rich(ctx)


class _Argument(typer.core.TyperArgument):
    """An argument in the usage line as click writes it: ``SCENARIO`` when required,
    ``[SCENARIO]`` when not, a given metavar as it is (typer wrote ``{scenario}`` and
    ``[[SCENARIO]...]...``)."""

    def _usage_display_name(self) -> str:
        if self.metavar is not None:
            return self.metavar
        name = self.name.upper() + ("..." if self.nargs != 1 else "")
        return name if self.required else f"[{name}]"


def _help_params(params: list) -> list:
    """The parameters as the help shows them (:class:`_FlagOption`, :class:`_Argument`)."""
    for param in params:
        if type(param) is typer.core.TyperOption and param.is_flag:
            param.__class__ = _FlagOption
        elif type(param) is typer.core.TyperArgument:
            param.__class__ = _Argument
    return params


class _Command(typer.core.TyperCommand):
    """A command whose help shows its parameters as :func:`_help_params` does."""

    def get_params(self, ctx):
        return _help_params(super().get_params(ctx))


@contextmanager
def _usage_in_one_line():
    # the exceptions of the click typer runs on (recent typers carry their own copy, older ones import click),
    # found through typer's public BadParameter
    errors = sys.modules[typer.BadParameter.__module__]
    try:
        yield
    except getattr(errors, "NoArgsIsHelpError", ()):
        raise
    except errors.UsageError as exc:
        where = exc.ctx.command_path if exc.ctx is not None else "marinecdpr"
        _fail(f"{where}: {' '.join(exc.format_message().split()).rstrip('.')} (see {where} --help)", exc.exit_code)


class Plant(str, enum.Enum):
    """The virtual prototype's plants (``--plant``)."""

    mujoco = "mujoco"
    own = "own"


app = typer.Typer(
    cls=_OneLineUsage,
    add_completion=False,
    no_args_is_help=True,
    help="Cable-driven parallel robots on a moving ship.\n\nExit codes: 0 done; 2 bad input; 3 the cables "
         "cannot hold the platform somewhere on the plan; 4 a simulation diverged; 5 a closed loop's "
         "controller was bypassed (the plan's tensions fed forward) on more than "
         "simulation.max_bypassed_share of its steps (the files are written, with the verdict); 130 interrupted.",
    pretty_exceptions_show_locals=False,
)
# no markup: every text printed reads literally (a user's names and paths, and the library's
# messages: "pip install 'marinecdpr[bench]'"); the few styled words are rich Text (_styled)
console = Console(markup=False)
err_console = Console(stderr=True, markup=False)


def _styled(word: str, style: str, rest: str) -> Text:
    """``word`` in ``style``, then a space and ``rest`` as it is."""
    return Text.assemble((word, style), " ", rest)


def _version(value: bool) -> None:
    if value:
        from marinecdpr import __version__

        console.print(f"marinecdpr {__version__}", highlight=False)
        raise typer.Exit()


@app.callback()
def _options(
    version: bool = typer.Option(False, "--version", callback=_version, is_eager=True,
                                 help="Print the version and exit."),
) -> None:
    """Cable-driven parallel robots on a moving ship."""


def _plain(text: object) -> str:
    """Text from a user (names, paths, messages) for the terminal, read literally: control
    characters (ANSI escapes) removed (the consoles read no markup)."""
    return strip_control(str(text))


_interruption_said = False
"""Has a one-line message about an interruption been printed (by :func:`_fail`)?"""


def _fail(message: str, code: int = EXIT_BAD_INPUT) -> None:
    global _interruption_said
    _interruption_said = _interruption_said or code == EXIT_INTERRUPTED
    err_console.print(_styled("error:", "bold red", _plain(message)), highlight=False, soft_wrap=True)
    raise typer.Exit(code)


def _number(flag: str, value: float | None, *, zero_ok: bool = False, finite_only: bool = False) -> None:
    """Refuse an option's number that is not finite, or (unless ``finite_only``) not positive
    (not negative with ``zero_ok``): one line, exit 2."""
    from marinecdpr.commands.base import finite, positive

    try:
        finite(value) if finite_only else positive(value, zero_ok=zero_ok)
    except ValueError as exc:
        _fail(f"{flag} {value:g}: {exc}")


def _fail_scenario(exc: ScenarioError, scenario: str) -> None:
    """A scenario's error, prefixed with the scenario given when the error names no file."""
    _fail(str(exc) if exc.source else f"{scenario}: {exc}")


@app.command()
def plan(
    scenario: str = typer.Argument("paper", help="A scenario file, or a built-in name."),
    out: Path = typer.Option(Path("out"), "--out", "-o", help="Folder for plan.csv and figures."),
    method: Optional[str] = typer.Option(
        None, help=f"Tension method (default: the scenario's): {', '.join(TENSION_METHODS)}."
    ),
    fixed_base: bool = typer.Option(
        False, "--fixed-base", help="Plan as if the ship were still (the traditional model)."
    ),
    allow_infeasible: bool = typer.Option(
        False, help="Exit 0 even where the cables cannot hold the platform, or come closer than "
                    "robot.clearance_m to each other, the platform or an obstacle."
    ),
) -> None:
    """Plan cable tensions along the scenario's trajectory on its moving ship."""
    from marinecdpr.planning import planner as planning
    from marinecdpr.planning.budget import check_run_size
    from marinecdpr.report.writers import write_plan_stream

    if method is not None and method not in TENSION_METHODS:
        _fail(f"--method {method}: expected one of {', '.join(TENSION_METHODS)}")
    try:
        sc = load_scenario(scenario)
        _warn_scale(sc, scenario)
        check_run_size(sc, "plan_stream")
        with _output(out) as folder:
            # planned, written and drawn in chunks: memory stays flat however long the plan
            pieces = planning.iter_plan(sc, method=method, base_model="fixed" if fixed_base else None,
                                        chunk_steps=planning.DEFAULT_CHUNK_STEPS)
            result = write_plan_stream(pieces, sc, folder / "plan.csv", folder / "tensions.png")
            elapsed = result.planning_s
    except ScenarioError as exc:
        _fail_scenario(exc, scenario)
    csv_path, fig_path = out / "plan.csv", out / "tensions.png"

    table = Table(title=f"plan: {_plain(sc.name)} ({result.method}, {result.base_model} base)")
    table.add_column("quantity")
    table.add_column("value", justify="right")
    table.add_row("steps", f"{result.n_steps} ({elapsed * 1e3:.1f} ms)")
    table.add_row("feasible steps", f"{result.n_feasible} of {result.n_steps}")
    if result.n_singular:
        table.add_row("singular steps (J~ loses rank)", f"{result.n_singular} of {result.n_steps}")
    for name, (lo, hi) in (("eq. 18 tensions (N)", result.pinv_range), ("planned tensions (N)", result.tension_range)):
        table.add_row(name, "none" if math.isnan(lo) else f"{lo:.2f} .. {hi:.2f}")
    if sc.robot.clearance_m is not None:
        table.add_row(f"steps closer than {sc.robot.clearance_m:g} m (interference)",
                      f"{result.n_interfering} of {result.n_steps}")
    table.add_row("written", f"{csv_path}\n{fig_path}")
    console.print(table)
    problem, close = result.infeasibility(), result.interference()
    for label, text in (("infeasible:", problem), ("interference:", close)):
        if text is not None:
            err_console.print(_styled(label, "bold yellow", f"{_plain(sc.name)}: {_plain(text)}"), highlight=False,
                              soft_wrap=True)
    if (problem is not None or close is not None) and not allow_infeasible:
        raise typer.Exit(EXIT_INFEASIBLE)


def _scenario_to_fly(scenario: str, duration: float | None, run: str, *, cleaning: bool = False):
    """The scenario, its first ``duration`` seconds if given, refused in one line (exit 2)
    before any work if it is malformed, has no cleaning job where one is needed, or the
    run would not fit in memory."""
    from marinecdpr.planning.budget import check_run_size

    try:
        sc = load_scenario(scenario)
        _warn_scale(sc, scenario)
        if cleaning and (sc.cleaning is None or sc.trajectory.type != "coverage"):
            raise ScenarioError("no cleaning job: give a [cleaning] section and [trajectory] type = \"coverage\"",
                                source=sc.name, key="cleaning")
        if duration is not None and duration > sc.time.duration_s:
            err_console.print(_styled("warning:", "bold yellow", f"--duration {duration:g}: {_plain(scenario)} lasts "
                                      f"{sc.time.duration_s:g} s; flying those {sc.time.duration_s:g} s"),
                              highlight=False, soft_wrap=True)
        if duration is not None:
            sc = sc.with_changes(time={"step_s": sc.time.step_s, "duration_s": min(duration, sc.time.duration_s)})
        check_run_size(sc, run)  # before any work: too big is one line, exit 2
    except ScenarioError as exc:
        _fail_scenario(exc, scenario)
    return sc


@contextmanager
def _run_errors(scenario: str):
    """A run's failures as one line each: a bad scenario exits 2, an infeasible plan 3, a
    diverged simulation 4."""
    try:
        yield
    except ScenarioError as exc:
        _fail_scenario(exc, scenario)
    except InfeasibleError as exc:
        _fail(str(exc), EXIT_INFEASIBLE)
    except SimulationDivergedError as exc:
        _fail(str(exc), EXIT_DIVERGED)


def _compile_notice(plant: str) -> None:
    """A line on stderr when the simulation's loop must first be compiled (a fresh install);
    every command that flies the virtual prototype calls it before its work."""
    from marinecdpr.prototype.simulation import KERNEL_COMPILE_S, kernels_cached

    if not kernels_cached(plant):
        _compiling("the simulation kernels", KERNEL_COMPILE_S)


def _compiling(what: str, seconds: float) -> None:
    """The one-line notice that ``what`` is compiled now, once, for about ``seconds``."""
    err_console.print(f"compiling {what}, once (about {seconds:g} s; cached for later runs)...", highlight=False,
                      soft_wrap=True)


@app.command()
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
        _fail(f"--plant {plant}: expected mujoco or own")
    _number("--duration", duration)
    _number("--hull-area", hull_area)
    _number("--move-time", move_time, zero_ok=True)
    if surface:
        from marinecdpr.studies.surface import check_move_time

        try:  # a move longer than the cap makes hours that mean nothing (1e308 s: not finite)
            check_move_time(move_time)
        except ScenarioError as exc:
            _fail(f"--move-time {move_time:g}: {exc.detail.split(', got')[0]}")
    if hull_area is not None:
        from marinecdpr.studies.cleaning import check_hull_estimate

        try:  # before the job: an estimate that would mean nothing is one line
            check_hull_estimate(hull_area, move_time)
        except ValueError as exc:
            _fail(f"--hull-area {hull_area:g} / --move-time {move_time:g}: {exc}")
    sc = _scenario_to_fly(scenario, duration, "simulate", cleaning=True)
    if surface:
        if hull_area is not None:
            _fail("--surface and --hull-area: choose one (--surface has the hull's real placements)")
        if seas or scatter is not None:
            _fail("--surface cannot go with --seas yet: its hours are for the scenario's sea")
        from marinecdpr.studies.surface import surface_job

        try:  # before the job: a missing surface, or one that cannot be tiled, is one line
            with ExitStack() as stack:
                update = []  # the progress starts with the tiling itself, after the band's checks

                def tiled(share: float) -> None:
                    if not update:
                        update.append(stack.enter_context(_progress("surface tiling", 100, "%")))
                    update[0](round(100 * share))

                placed = surface_job(sc, move_time_s=move_time, progress=tiled)
        except ScenarioError as exc:
            _fail_scenario(exc, scenario)
    if seas or scatter is not None:
        if guarantee:
            _fail("--guarantee cannot go with --seas: it sets the lanes from one sea state's run")
        for name, value in (("--coverage-target", coverage_target), ("--in-band-target", in_band_target)):
            if not (math.isfinite(value) and 0.0 <= value <= 100.0):
                _fail(f"{name} {value:g}: expected a percentage between 0 and 100")
        heads = _sea_study_options(headings, serial, workers, scheduler)
        from marinecdpr.motion.trajectory import cleaning_path

        path_end = sc.trajectory.start_time_s + cleaning_path(sc.cleaning).duration_s
        if sc.time.duration_s < path_end:  # each sea state's verdict and hours are the part's
            err_console.print(_styled("warning:", "bold yellow", f"{_plain(scenario)}: a PARTIAL job: each sea state "
                                      f"flies the first {sc.time.duration_s:g} s of the {path_end:.4g} s path; its "
                                      "coverage and hours are that part's"), highlight=False, soft_wrap=True)
        return _clean_seas(scenario, sc, _scatter_diagram(scatter), heads, out, plant=plant, hull_area=hull_area,
                           move_time=move_time, coverage_target=coverage_target, in_band_target=in_band_target,
                           serial=serial, workers=workers, scheduler=scheduler)
    t0 = time.perf_counter()
    with _output(out) as folder:
        _compile_notice(plant or sc.simulation.plant)
        runs = (2 if guarantee else 1) + (len(job_variants(sc)) - 1 if compare else 0)
        # runs one after the other, each planned first: the time left once a run's worth is known
        with _progress("clean", runs * sc.time.n_steps, "steps", eta_after=sc.time.n_steps if runs > 1 else 0) \
                as update:
            done = [0]

            def step(k: int, n: int) -> None:  # runs one after the other on one bar
                update(done[0] + k, runs * sc.time.n_steps)
                if k == n:
                    done[0] += n

            with _run_errors(scenario):
                job = (guaranteed_job if guarantee else cleaning_job)(sc, plant=plant, progress=step)
                if compare:
                    job.summary["comparison"] = compare_conditions(job, plant=plant, progress=step)
            update(done[0], done[0])  # the runs that were flown (a guarantee met at once skips its second)
        if hull_area is not None:
            try:
                job.summary["hull"] = ship_side(job.summary, hull_area_m2=hull_area, move_time_s=move_time)
            except ValueError as exc:
                _fail(f"--hull-area: {exc}")
        if surface:
            from marinecdpr.report.cleaning import write_surface

            job.summary["surface"] = placed.summary()
            surface_paths = write_surface(placed, folder)
        paths = write_cleaning(job, folder) + (surface_paths if surface else [])
    for sentence in cleaning_findings(job.summary):
        console.print(_plain(sentence), highlight=False, soft_wrap=True)
    if surface:
        u = job.summary["surface"]
        import numpy as np

        frame = np.ptp(sc.robot.frame_anchors, axis=0)  # the frame's extent along C's x and z, m
        console.print(_plain(f"surface: {u['surface']}: {u['placements']} placements of the {frame[0]:.3g} x "
                             f"{frame[2]:.3g} m frame, each cleaning its {u['frame_panel_m'][0]:g} x "
                             f"{u['frame_panel_m'][1]:g} m panel, {u['area_m2']:.4g} m2: "
                             f"{u['hours']:.4g} h ({u['cleaning_hours']:.4g} h cleaning, moves of {move_time:g} s; "
                             f"{u['area_rate_m2_h']:.3g} m2/h)"
                             + (f"; {u['uncleanable_patches']} patches ({u['uncleanable_area_m2']:.3g} m2) curved "
                                "beyond the stand-off tolerance" if u["uncleanable_patches"] else "")),
                      highlight=False, soft_wrap=True)
    close = job.summary.get("interference")
    if close is not None and close["first"] is not None:
        err_console.print(_plain(f"warning: plan: {close['first']}"), highlight=False, soft_wrap=True)
    if guarantee:
        g = job.summary["guarantee"]
        console.print(_plain(f"guarantee: {g['reason']}; lanes {g['lane_spacing_m']:.4g} m apart; "
                             + (("checked by a second run" if g["second_run"] else "as flown") if g["checked"] else
                                f"NOT met: the run's p95 cross-track error is {g['checked_p95_cross_track_error_m']:.3g} m")),
                      highlight=False, soft_wrap=True)
    console.print(f"written to {_plain(str(out))}/: {', '.join(p.name for p in paths)} "
                  f"({time.perf_counter() - t0:.1f} s)", highlight=False, soft_wrap=True)
    _fail_bypassed(_clean_bypassed(job.summary, sc), sc, out)


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
        _fail_scenario(exc, scenario)
    from marinecdpr.planning.budget import check_run_size

    n_cells = int((diagram.probability > 0).sum()) * len(heads)
    n_workers = workers or 2
    try:  # before any work: every sea state flies the job closed loop
        check_run_size(sc, "operability", cells=n_cells, closed_loop=True, workers=1 if serial else n_workers)
    except ScenarioError as exc:
        _fail_scenario(exc, scenario)
    executor = _sea_executor(serial, workers, scheduler, n_cells * sc.time.n_steps * CLOSED_LOOP_STEP_COST)
    t0 = time.perf_counter()
    with _output(out) as folder:
        _compile_notice(plant or sc.simulation.plant)
        with _progress_bar("sea states") as bar:
            task = bar.add_task("", total=n_cells)
            with _run_errors(scenario):
                cs = cleaning_seas(sc, diagram, headings_deg=heads, coverage_target_pct=coverage_target,
                                   in_band_target_pct=in_band_target, plant=plant, hull_area_m2=hull_area,
                                   move_time_s=move_time, executor=executor, scheduler=scheduler, workers=n_workers,
                                   progress=lambda d, tot: bar.update(task, completed=d, total=tot))
        paths = write_cleaning_seas(cs, sc, folder)
    _print_sea_table(cs.sea, f"cleaning job over the sea states: {_plain(sc.name)}", scheduler, n_workers,
                     time.perf_counter() - t0)
    what = "the hull" if hull_area is not None else "one panel"
    hours = ("no sea state" if cs.expected_hours != cs.expected_hours else
             f"{cs.expected_hours:.3g} h for {what} where it works, {cs.expected_hours_with_weather:.3g} h "
             "waiting for workable seas")
    console.print(_plain(f"the job works in {_percent(cs.sea.operability)} of the sea states (at least "
                         f"{coverage_target:g} % of the reachable panel cleaned, the normal force in band at least "
                         f"{in_band_target:g} % of the time, tensions within limits); expected {hours}"),
                  highlight=False, soft_wrap=True)
    console.print(f"written to {_plain(str(out))}/: {', '.join(p.name for p in paths)}", highlight=False,
                  soft_wrap=True)


@app.command()
def simulate(
    scenario: str = typer.Argument("paper", help="A scenario file, or a built-in name."),
    out: Path = typer.Option(Path("out"), "--out", "-o", help="Folder for the CSVs, figures and report."),
    plant: Optional[str] = typer.Option(None, help="mujoco or own (default: the scenario's)."),
    duration: Optional[float] = typer.Option(None, help="Simulate only the first seconds."),
    max_error: Optional[float] = typer.Option(None, help="Flag runs whose position or cable-length "
                                              "error passes this, m (default: the scenario's, 1% of the frame)."),
) -> None:
    """The main job: plan, fly the plan on the virtual prototype, write the report.

    Runs open loop, closed loop and the fixed-base plan on the moving ship; writes
    plan.csv, sim_<run>.csv, figures like the paper's 5-7, the path, summary.json and
    report.html. Exits 5 (the files written) if the closed loop's controller was bypassed on
    more than simulation.max_bypassed_share of its steps.
    """
    from marinecdpr.studies.prototype_runs import virtual_prototype
    from marinecdpr.report.figures import RUN_TITLES
    from marinecdpr.report.text import beyond_text, error_table, findings
    from marinecdpr.report.writers import write_virtual_prototype
    from marinecdpr.prototype.simulation import RUNS

    if plant is not None and plant not in ("mujoco", "own"):
        _fail(f"--plant {plant}: expected mujoco or own")
    _number("--duration", duration)
    _number("--max-error", max_error)
    sc = _scenario_to_fly(scenario, duration, "virtual_prototype")
    t0 = time.perf_counter()
    with _output(out) as folder:
        _compile_notice(plant or sc.simulation.plant)
        with _progress_bar("simulate", "steps") as bar:
            tasks = {run: bar.add_task(RUN_TITLES[run], total=sc.time.n_steps) for run in RUNS}

            def progress(run: str, done: int, total: int) -> None:
                if run not in tasks:  # after the runs: the error budget's workspace maps, in poses
                    tasks[run] = bar.add_task(RUN_TITLES.get(run, "error budget: workspace maps"), total=total,
                                              unit="poses")
                bar.update(tasks[run], completed=done, total=total)

            with _run_errors(scenario):
                vp = virtual_prototype(sc, plant=plant, max_error_m=max_error, progress=progress)
        paths = write_virtual_prototype(vp, folder)
    elapsed = time.perf_counter() - t0

    s = vp.summary
    header, rows = error_table(s, sc)
    table = Table(title=f"simulate: {_plain(sc.name)} ({s['steps']} steps, plant {vp.results['open_loop'].plant}, "
                        f"{elapsed:.1f} s wall time)")
    for i, h in enumerate(header):
        table.add_column(h, justify="left" if i == 0 else "right")
    for row in rows:
        table.add_row(*row)
    console.print(table)
    for sentence in findings(s, sc, warnings=False):
        console.print(_plain(sentence), highlight=False)
    for run in s["runs_beyond_error_bound"]:
        err_console.print(_plain(f"warning: {run} leaves its plan beyond the error bound "
                                 f"({beyond_text(s[run]['beyond_error_bound'])}): see {out / 'report.html'}"),
                          highlight=False, soft_wrap=True)
    for warning in s["warnings"]:
        err_console.print(_plain(f"warning: {warning}"), highlight=False, soft_wrap=True)
    console.print(_plain(f"written to {out}/: " + ", ".join(p.name for p in paths)), highlight=False)
    _fail_bypassed([(run, vp.results[run].controller_fallbacks, s["steps"]) for run in s["runs_controller_bypassed"]],
                   sc, out)


def _fail_bypassed(runs: list[tuple[str, int, int]], sc, out: Path) -> None:
    """A failed run for each (name, bypassed steps, steps) whose controller was bypassed:
    one line on stderr, exit 5, after the files (which say so) are written."""
    from marinecdpr.studies.prototype_runs import bypassed_text

    if runs:
        name, fallbacks, steps = runs[0]
        more = f" (and {_count(len(runs) - 1, 'more run')})" if len(runs) > 1 else ""
        _fail(f"{name}{more}: {bypassed_text(fallbacks, steps, sc.simulation.max_bypassed_share)}; "
              f"see {out / 'summary.json'}", EXIT_BYPASSED)


@contextmanager
def _output(out: Path):
    """The output folder, checked before the work starts and filled all at once at the end
    (see :class:`marinecdpr.report.files.StagedOutput`); a failure writing it is one line, exit 2,
    and so is a folder holding another command's results (a run replaces only its own
    command's files: ``simulate`` then ``plan`` into one folder would lose the report)."""
    from marinecdpr.errors import OutputError
    from marinecdpr.report.files import StagedOutput

    try:
        staged = StagedOutput(out, command=_running_command)
    except OutputError as exc:
        _fail(f"--out {exc}")
    try:
        with staged as folder:
            yield folder
    except OSError as exc:
        _fail(f"--out {out}: could not write the files ({exc.strerror or exc}); the folder keeps what it held")
    except KeyboardInterrupt:
        if staged.committed:  # Ctrl-C as the files went in: they are all there
            _fail(f"interrupted; --out {out} holds this run's files, complete", EXIT_INTERRUPTED)
        _fail(f"interrupted; --out {out} keeps what it held", EXIT_INTERRUPTED)


PROGRESS_LINE_FRACTION = 0.1
"""Off a terminal, a progress line each time another this much of the work is done..."""
PROGRESS_LINE_EVERY_S = 10.0
"""... or when this long has passed since the last line (and a last line at the end)..."""
PROGRESS_LINE_MIN_S = 1.0
"""... but never sooner than this after the last line (a short job prints only its first
line, which says it has started, and its last)."""
ESTIMATE_MIN_PIECES = 3
"""No estimate of the time left before this many pieces of work have been done after the
first (the first holds a first run's compile, and one or two pieces say little)..."""
ESTIMATE_MIN_SHARE = 0.05
"""... nor before they make this share of the work..."""
ESTIMATE_MIN_S = 1.0
"""... nor before they took this long, s (work that comes in batches done at one moment)."""


def _seconds(s: float) -> str:
    """``12.3 s`` below a minute, else ``2 min 05 s`` (whole seconds, rounded once)."""
    if s < 59.95:
        return f"{s:.1f} s"
    whole = int(round(s))
    return f"{whole // 60} min {whole % 60:02d} s"


class _Pace:
    """A task's pace, measured from the end of its first piece of work (the piece that holds
    a first run's compile, which would swell every estimate), for the time left and the rate."""

    def __init__(self, start: float, eta_after: float = 0.0):
        self.start, self.eta_after = start, eta_after
        self.first: tuple[float, float] | None = None  # (when, done) at the end of the first piece
        self.pieces = 0  # pieces done since the first
        self.last_done = 0.0

    def note(self, done: float, now: float) -> None:
        """Work done so far (``done``, at ``now``)."""
        if self.first is None:
            if done > 0:
                self.first = (now, done)
        elif done > self.last_done:
            self.pieces += 1
        self.last_done = done

    def left_s(self, done: float, total: float | None, now: float) -> float | None:
        """Seconds left at the pace since the first piece; None until it means something:
        :data:`ESTIMATE_MIN_PIECES` pieces since the first, :data:`ESTIMATE_MIN_SHARE` of the
        work and :data:`ESTIMATE_MIN_S` seconds, and more than ``eta_after`` done."""
        if not total or self.first is None or done <= self.eta_after:
            return None
        since, done_then = self.first
        if (self.pieces < ESTIMATE_MIN_PIECES or done - done_then < ESTIMATE_MIN_SHARE * total
                or now - since < ESTIMATE_MIN_S):
            return None
        return (now - since) * (total - done) / (done - done_then)

    def rate(self, done: float, now: float) -> tuple[float, str]:
        """Work per second and what it leaves out: after the first piece where that piece took
        far longer than the pace since (a compile, a start-up), else over the whole time."""
        elapsed = now - self.start
        whole = done / elapsed if elapsed > 0 else float("inf")
        if self.first is None or self.pieces == 0 or now <= self.first[0]:
            return whole, ""
        since, done_then = self.first
        after = (done - done_then) / (now - since)
        first_s = since - self.start
        if first_s > 2.0 * done_then / after + ESTIMATE_MIN_S:
            return after, f" after the first {done_then:g}, which took {_seconds(first_s)} with the start-up"
        return whole, ""


def _rate_text(per_s: float, per: str) -> str:
    return f"{per_s:.3g} {per}/s" if per_s < 100 else f"{per_s:,.0f} {per}/s"


class _PlainProgress:
    """Progress as plain lines on stderr, for pipes and logs; the interface of rich's ``Progress``
    that the commands use (``add_task``, ``update``, a context manager).

    The first task's first line comes at once (the work has started: no silence until the first
    tenth is done); then a line at each tenth of the work or each :data:`PROGRESS_LINE_EVERY_S`,
    with the time left once it can be estimated (:class:`_Pace`), and a last line with the rate."""

    def __init__(self, label: str, unit: str = "", eta_after: float = 0.0):
        self.label, self.unit, self.eta_after = label, unit, eta_after
        self._tasks: list[dict] = []

    def __enter__(self) -> "_PlainProgress":
        return self

    def __exit__(self, exc_type, *_) -> bool:
        if exc_type is None:  # a last line for work that stopped short of its total
            for task in self._tasks:
                if task["done"] > task["printed"] and not task["finished"]:
                    self._line(task, final=True)
        return False

    def add_task(self, description: str = "", total: float | None = None, unit: str | None = None, **_) -> int:
        now = time.perf_counter()
        first = not self._tasks
        self._tasks.append(dict(description=description, total=total, unit=unit, done=0, printed=0, start=now,
                                printed_at=now, finished=False, started=False, pace=None))
        if first:  # at once: the work has begun, and how much there is
            self._line(self._tasks[-1], started=True)
        return len(self._tasks) - 1

    def update(self, task_id: int, *, completed: float | None = None, total: float | None = None,
               advance: float | None = None, **_) -> None:
        task = self._tasks[task_id]
        now = time.perf_counter()
        if not task["started"]:
            # tasks that run one after another: a task's clock starts when the last one finished
            # (a task that runs alongside the others is updated with 0 done at its start)
            ends = [t["ended"] for t in self._tasks if t["finished"]]
            task.update(start=max([task["start"]] + ends), started=True)
            task["pace"] = _Pace(task["start"], self.eta_after)
        if total is not None:
            task["total"] = total
        if completed is not None:
            task["done"] = completed
        if advance is not None:
            task["done"] += advance
        done, total = task["done"], task["total"]
        task["pace"].note(done, now)
        if task["finished"] or done <= task["printed"]:
            return
        tenth = PROGRESS_LINE_FRACTION
        since = now - task["printed_at"]
        if total and done >= total:
            self._line(task, final=True)
        elif since >= PROGRESS_LINE_MIN_S and (
                (total and int(done / total / tenth) > int(task["printed"] / total / tenth))
                or since >= PROGRESS_LINE_EVERY_S):
            self._line(task)

    def _line(self, task: dict, final: bool = False, started: bool = False) -> None:
        now = time.perf_counter()
        elapsed = now - task["start"]
        done, total = task["done"], task["total"]
        name = ": ".join(x for x in (self.label, task["description"]) if x)
        unit = task["unit"] or self.unit
        per = unit or "done"
        unit = f" {unit}" if unit else ""
        of = f"{done:g} of {total:g}{unit}" if total else f"{done:g}{unit}"
        if started:
            text = f"{name}: {of}, started"
        elif final:
            rate = ""
            if elapsed > 0:
                per_s, leaves_out = task["pace"].rate(done, now)
                rate = f" ({_rate_text(per_s, per)}{leaves_out})"
            text = f"{name}: {of} in {_seconds(elapsed)}{rate}"
        else:
            pct = f" ({100 * done / total:.0f}%)" if total else ""
            left_s = task["pace"].left_s(done, total, now)
            left = "" if left_s is None else f", about {_seconds(left_s)} left"
            text = f"{name}: {of}{pct}, {_seconds(elapsed)}{left}"
        err_console.print(_plain(text), highlight=False, soft_wrap=True)
        if not started:
            task.update(printed=done, printed_at=now, finished=final, ended=now)


def _progress_bar(label: str, unit: str = "", eta_after: float = 0.0):
    """Progress on stderr: rich's bar on a terminal, plain lines (:class:`_PlainProgress`) otherwise.

    Use as ``with _progress_bar("workspace", "poses") as bar: task = bar.add_task("", total=n);
    ... bar.update(task, completed=done, total=n)``; several tasks may share it (named by their
    description). :func:`_progress` wraps the one-task case. The time left is said once it
    means something (:class:`_Pace`), and not before more than ``eta_after`` is done (work in
    runs, each with its own start-up: one run's worth).
    """
    if not err_console.is_terminal:
        return _PlainProgress(label, unit, eta_after)
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    paces: dict = {}

    class Bar(Progress):
        """rich's bar, redrawn at each update rather than by a thread of its own: a process with
        no other thread may hand work to a forked copy of itself (:mod:`marinecdpr.forked`)."""

        def update(self, task_id, *args, **kwargs) -> None:
            super().update(task_id, *args, **kwargs)
            task = next(t for t in self.tasks if t.id == task_id)
            pace = paces.setdefault(task_id, _Pace(time.perf_counter(), eta_after))
            pace.note(task.completed, time.perf_counter())
            self.refresh()

    class Left(TextColumn):
        """The time left, from the task's pace (rich's own estimate counts a compile in)."""

        def __init__(self):
            super().__init__("")

        def render(self, task) -> Text:
            pace = paces.get(task.id)
            left = None if pace is None or task.finished else pace.left_s(task.completed, task.total,
                                                                          time.perf_counter())
            return Text("" if left is None else f"about {_seconds(left)} left", style="progress.remaining")

    return Bar(TextColumn(escape(f"{label:<16}")), TextColumn("{task.description}"), BarColumn(),
               MofNCompleteColumn(), TimeElapsedColumn(), Left(), console=err_console, auto_refresh=False)


@contextmanager
def _progress(label: str, total: int, unit: str = "", eta_after: float = 0.0):
    """One job's progress on stderr (see :func:`_progress_bar`); yields ``update(done, total=None)``."""
    with _progress_bar(label, unit, eta_after) as bar:
        task = bar.add_task("", total=total)

        def update(done: int, new_total: int | None = None) -> None:
            bar.update(task, completed=done, total=total if new_total is None else new_total)

        yield update


def _grid(flag: str, text: str, example: str) -> tuple[int, int]:
    """A grid's two positive point counts from ``AxB`` (:func:`~marinecdpr.commands.base.grid`);
    one line, exit 2, otherwise."""
    from marinecdpr.commands.base import grid

    try:
        return grid(text, example=example)
    except ValueError as exc:
        _fail(f"{flag} {text}: {exc}")


@app.command()
def workspace(
    scenario: str = typer.Argument("paper", help="A scenario file, or a built-in name."),
    out: Path = typer.Option(Path("out"), "--out", "-o", help="Folder for workspace.csv and workspace.png."),
    axes: str = typer.Option(WorkspaceSpec.default("axes"), help="Grid plane: two of x, y, z."),
    points: str = typer.Option("x".join(map(str, WorkspaceSpec.default("points"))),
                               help="Grid points along the two axes, e.g. 30x20."),
    fixed: Optional[float] = typer.Option(WorkspaceSpec.default("fixed"),
                                          help="The third coordinate, m (default: mid-frame)."),
    duration: Optional[float] = typer.Option(WorkspaceSpec.default("duration"),
                                             help="Seconds of ship motion per pose (default: the scenario's "
                                             "time.duration_s)."),
    step: Optional[float] = typer.Option(WorkspaceSpec.default("step"),
                                         help="Time step, s (default: the scenario's time.step_s)."),
) -> None:
    """Map where on the frame the platform can be held while the ship moves."""
    from marinecdpr.commands import workspace as command

    spec = _spec(WorkspaceSpec, points=points, axes=axes, fixed=fixed, duration=duration, step=step)
    sc = _load(scenario, None, None)
    try:
        est = command.estimate(spec, sc)  # before any work: too big is one line, exit 2
    except ScenarioError as exc:
        _fail_scenario(exc, scenario)
    _warn_singular(scenario, (est.singular,))
    t0 = time.perf_counter()
    with _output(out) as folder:
        err_console.print(_plain(est.describe()), highlight=False, soft_wrap=True)
        with _progress("workspace", spec.points[0] * spec.points[1], "poses") as update:
            try:
                result = command.run(spec, sc, estimated=est, progress=update)
            except ScenarioError as exc:
                _fail_scenario(exc, scenario)
        elapsed = time.perf_counter() - t0
        paths = [out / p.name for p in result.write(folder)]
    if est.singular.n_singular < est.singular.n_poses:  # (every pose singular is said already)
        _warn_singular(scenario, (result.singular,))  # the map's own grid, and between its points
    s = result.summary()
    clear = ("" if "interference_free" not in s else
             f", {s['interference_free']} free of interference (clearance {s['clearance_m']:g} m), {s['both']} both")
    console.print(f"{_plain(result.scenario.name)}: {s['feasible_throughout']} of {s['poses']} poses feasible "
                  f"throughout{clear} ({s['n_steps']} steps each, {_seconds(elapsed)}); written: "
                  + ", ".join(_plain(p) for p in paths), highlight=False)


def _spec(cls, **options):
    """The command's spec of the options given; a bad one is one line naming its ``--flag``,
    exit 2 (:class:`~marinecdpr.commands.base.SpecError`)."""
    from marinecdpr.commands.base import SpecError

    try:
        return cls(**options)
    except SpecError as exc:
        _fail_spec(exc)


def _fail_spec(exc) -> None:
    """A command's :class:`~marinecdpr.commands.base.SpecError` as one line naming its
    ``--flag``, exit 2."""
    _fail(f"{exc.flag} {exc.value}: {exc.detail}")


@app.command()
def operability(
    scenario: str = typer.Argument("paper_sea", help="A scenario with a sea_state base motion."),
    scatter: Optional[Path] = typer.Option(None, help="Scatter diagram CSV (hs_m,tp_s,probability); "
                                                      "default: the package's illustrative one."),
    headings: str = typer.Option("180", help="Wave headings, deg, comma-separated."),
    margin: float = typer.Option(0.0, help="Tension margin to the limits a workable sea keeps, N."),
    duration: float = typer.Option(1200.0, help="The operation's duration: the length of each record, s."),
    step: float = typer.Option(0.02, help="Time step, s."),
    realisations: int = typer.Option(10, min=1, help="Independent records per sea state: the probability of "
                                     "success is the share that hold."),
    out: Path = typer.Option(Path("out"), "--out", "-o", help="Folder for operability.csv/.json/.png."),
    serial: bool = typer.Option(False, "--serial", help="Run the cells in this process, not on Dask "
                                "(the default for small studies, and without Dask)."),
    workers: Optional[int] = typer.Option(None, min=1, help="Run on a local Dask cluster of this many "
                                          "workers (the default for large studies: 2)."),
    scheduler: Optional[str] = typer.Option(None, help="Run on a running Dask scheduler at this address."),
    max_error: Optional[float] = typer.Option(None, help="Also fly the closed loop in each "
                                              "sea state and require its position error below this, m."),
    workspace_grid: Optional[str] = typer.Option(None, "--workspace", help="Judge a grid of held poses "
                                                 "(e.g. 12x8) instead of the trajectory."),
    min_area: float = typer.Option(1.0, min=0.0, max=1.0, help="With --workspace: share of the frame's "
                                   "poses that must stay feasible."),
) -> None:
    """In which sea states, over a scatter diagram, can the robot work?

    Runs serially for small studies and where Dask is not installed, on a
    local Dask cluster for large ones; --serial, --workers or --scheduler
    choose. Results are the same whichever runs.
    """
    from marinecdpr.planning.budget import check_run_size
    from marinecdpr.studies.operability import Cell, cell_scenario, study_steps
    from marinecdpr.studies.operability import operability as run
    from marinecdpr.report.writers import write_operability

    heads = _sea_study_options(headings, serial, workers, scheduler)
    _number("--margin", margin, zero_ok=True)
    _number("--duration", duration)
    _number("--step", step)
    _number("--max-error", max_error)
    grid = None
    if workspace_grid is not None:
        grid = _grid("--workspace", workspace_grid, "12x8")
    sc = _load(scenario, None, None)
    diagram = _scatter_diagram(scatter)
    n_cells = int((diagram.probability > 0).sum()) * len(heads)
    try:  # the largest cell's run: the highest sea and the shortest period that occur
        tp_min = float(diagram.tp[(diagram.probability > 0).any(axis=0)].min())
        probe = cell_scenario(sc, Cell(index=0, hs=float(diagram.hs.max()), tp=tp_min, heading_deg=heads[0],
                                       probability=1.0), duration, step)
        check_run_size(probe, "operability", cells=n_cells * realisations, grid=grid,
                       closed_loop=max_error is not None, workers=1 if serial else (workers or 2))
        from marinecdpr.planning.planner import check_trajectory
        from marinecdpr.studies.workspace import singular_poses

        # where no sea state can be workable: the robot singular along its path or over the frame
        _warn_singular(scenario, (singular_poses(sc),) if grid is not None else (check_trajectory(probe),))
    except ScenarioError as exc:
        _fail_scenario(exc, scenario)
    executor = _sea_executor(serial, workers, scheduler, study_steps(n_cells * realisations, duration_s=duration,
                                                                     step_s=step, workspace=grid,
                                                                     max_error_m=max_error))
    n_workers = workers or 2
    t0 = time.perf_counter()
    with _output(out) as folder:
        if max_error is not None:  # each cell flies the closed loop on the own plant
            _compile_notice("own")
        with _progress_bar("sea states") as bar:
            task = bar.add_task("", total=n_cells)
            try:
                op = run(sc, diagram, headings_deg=heads, margin_N=margin, duration_s=duration, step_s=step,
                         executor=executor, scheduler=scheduler, workers=n_workers,
                         max_error_m=max_error, workspace=grid, min_area=min_area, realisations=realisations,
                         progress=lambda d, tot: bar.update(task, completed=d, total=tot))
            except ScenarioError as exc:
                _fail_scenario(exc, scenario)
        elapsed = time.perf_counter() - t0
        paths = [out / p.name for p in write_operability(op, sc, folder)]

    _print_sea_table(op, f"operability: {_plain(sc.name)}", scheduler, n_workers, elapsed)
    console.print(f"overall {_percent(op.operability)}{_interval(op.interval, realisations)}, the probability that "
                  f"a {duration:g} s operation succeeds ({_count(realisations, 'record')} "
                  "per sea state); written: " + ", ".join(_plain(p) for p in paths), highlight=False,
                  soft_wrap=True)
    bypassed = sum(r.controller_bypassed for r in op.results)
    if bypassed:
        err_console.print(_plain(f"warning: in {_count(bypassed, 'record')} the closed loop's "
                                 "controller was bypassed (the plan's tensions fed forward) on more than "
                                 f"simulation.max_bypassed_share = {sc.simulation.max_bypassed_share:g} of the steps: "
                                 "counted as failures (operability.csv controller_bypassed)"),
                          highlight=False, soft_wrap=True)


def _count(number: object, noun: str) -> str:
    """``1 day``, ``3 days``, ``0.5 days``: the number as given, the noun singular for one."""
    return f"{number} {noun}" + ("" if float(number) == 1.0 else "s")


def _interval(interval: tuple[float, float], realisations: int) -> str:
    """' (95 %: lo-hi %)' for a study with several realisations, else ''."""
    if realisations <= 1:
        return ""

    def bound(x: float) -> str:  # the exact ends as 0 and 100, like _percent
        return "100" if x >= 1.0 else "0" if x <= 0.0 else f"{100 * x:.1f}"

    return f" (95 %: {bound(interval[0])}-{bound(interval[1])} %)"


def _percent(x: float) -> str:
    """For display: 100 % and 0 % only when exact; the JSON keeps the exact values."""
    text = f"{100 * x:.1f}"
    return ("100 %" if x >= 1.0 else "0 %" if x <= 0.0 else "> 99.9 %" if text == "100.0"
            else "< 0.1 %" if text == "0.0" else f"{text} %")


def _print_sea_table(op, title: str, scheduler: str | None, n_workers: int, elapsed: float) -> None:
    """A sea-state study's table: per heading the workable share and the limiting Hs per Tp."""
    ran = ("serial" if op.executor == "serial" else f"Dask at {scheduler}" if scheduler
           else f"Dask, {_count(n_workers, 'worker')}")
    table = Table(title=title, caption=f"{_count(len(op.results), 'sea state')}, {_plain(ran)}, {elapsed:.1f} s")
    table.add_column("heading (deg)")
    table.add_column("operable", justify="right")
    table.add_column("Tp (s)", justify="right")
    table.add_column("limiting Hs (m)")
    for h in op.headings_deg:
        first = True
        for tp, v in zip(op.scatter.tp, op.limiting_hs[h]):
            if v != v:   # no sea state of this Tp
                continue
            band = _interval((op.per_heading_interval or {}).get(h, (0.0, 1.0)), op.results[0].realisations)
            table.add_row(f"{h:g}" if first else "", _percent(op.per_heading[h]) + band if first else "",
                          f"{tp:g}", "none within the diagram" if math.isinf(v) else f"{v:g}")
            first = False
    console.print(table)
    console.print("limiting Hs: the largest Hs up to which every sea state of that Tp is workable in every "
                  "record (0: not even the smallest; none within the diagram: all are)", highlight=False)


WORKERS_PER_CORE = 4
"""Most local Dask workers per core a sea-state study starts."""


def _headings(text: str, example: str) -> tuple[float, ...]:
    """``--headings``, deg, by the one rule of every command
    (:func:`~marinecdpr.commands.base.headings`); one line, exit 2, otherwise."""
    from marinecdpr.commands.base import headings

    try:
        return headings(text, example=example)
    except ValueError as exc:
        _fail(f"--headings {text}: {exc}")


def _sea_study_options(headings: str, serial: bool, workers: int | None, scheduler: str | None) -> tuple[float, ...]:
    """A sea-state study's headings (deg) from ``--headings``, its executor options checked
    (``--serial`` alone; a ``--scheduler`` that answers)."""
    from marinecdpr.studies.operability import check_scheduler

    if serial and (workers is not None or scheduler):
        _fail("--serial cannot go with --workers or --scheduler (they run the sea states on Dask)")
    cores = os.cpu_count() or 1
    if workers is not None and workers > WORKERS_PER_CORE * cores:
        _fail(f"--workers {workers}: more than {WORKERS_PER_CORE} per core of this machine's {cores} gains nothing "
              f"(each is a process of its own); use at most {WORKERS_PER_CORE * cores}")
    heads = _headings(headings, "180,150")
    if scheduler:
        try:
            check_scheduler(scheduler)
        except ScenarioError as exc:
            _fail(str(exc))
    return heads


def _scatter_diagram(path: Path | None):
    """The scatter diagram of ``--scatter`` (default: the package's illustrative one)."""
    from importlib import resources

    from marinecdpr.studies.operability import read_scatter_csv

    try:
        return read_scatter_csv(path or Path(str(resources.files("marinecdpr") / "data" / "scatter_illustrative.csv")))
    except ScenarioError as exc:
        _fail(str(exc))


def _sea_executor(serial: bool, workers: int | None, scheduler: str | None, steps: int) -> str:
    """What runs a sea-state study's cells ("serial" or "dask") from the options and its size;
    a note when Dask would help but is not installed."""
    from marinecdpr.studies.operability import choose_executor, dask_installed

    asked = "serial" if serial else "dask" if (workers is not None or scheduler) else "auto"
    executor, why = choose_executor(asked, steps, scheduler=scheduler)
    if why == "no dask":
        err_console.print("note: running the sea states serially: Dask is not installed "
                          "(pip install 'marinecdpr[dask]' to run them in parallel)", highlight=False,
                          soft_wrap=True)
    elif executor == "dask" and not dask_installed():
        _fail("--workers and --scheduler run on Dask, which is not installed: pip install 'marinecdpr[dask]' "
              "(or leave them out to run serially)")
    return executor


def _warn_scale(sc, scenario: str) -> None:
    """Print the scenario's scale warnings on stderr (a warning: the exit code is unchanged)."""
    from marinecdpr.scenario.scale import scale_warnings

    for line in scale_warnings(sc):
        err_console.print(_styled("warning:", "bold yellow", f"{_plain(scenario)}: {_plain(line)}"), highlight=False,
                          soft_wrap=True)


def _warn_singular(scenario: str, surveys) -> None:
    """Warn (stderr, exit code unchanged) where J~ loses rank in each survey
    (:class:`~marinecdpr.planning.verdicts.SingularPoses`: along the trajectory, from
    :func:`~marinecdpr.planning.planner.check_trajectory`; over the frame, from
    :func:`~marinecdpr.studies.workspace.singular_poses`); the layout's hint given once."""
    hinted = False
    for survey in surveys:
        line = survey.message(hint=not hinted)
        if line is not None:
            hinted = hinted or survey.scale is not None
            err_console.print(_styled("warning:", "bold yellow", f"{_plain(scenario)}: {_plain(line)}"),
                              highlight=False, soft_wrap=True)


def _load(scenario: str, duration: float | None, step: float | None):
    """The scenario, with ``--duration`` and ``--step`` (checked: positive, finite) if given."""
    _number("--duration", duration)
    _number("--step", step)
    try:
        sc = load_scenario(scenario)
        _warn_scale(sc, scenario)
        if duration is not None or step is not None:
            sc = sc.with_changes(time={"step_s": sc.time.step_s if step is None else step,
                                       "duration_s": sc.time.duration_s if duration is None else duration})
        return sc
    except ScenarioError as exc:
        _fail_scenario(exc, scenario)


@app.command()
def check(scenario: str = typer.Argument(..., help="A scenario file, or a built-in name.")) -> None:
    """Validate a scenario file (keys, units, physics, trajectory inside the frame)."""
    from marinecdpr.planning.budget import check_run_size
    from marinecdpr.planning.planner import check_trajectory

    try:
        sc = load_scenario(scenario)
        _warn_scale(sc, scenario)
        check_run_size(sc, "plan_stream")
        along = check_trajectory(sc)
    except ScenarioError as exc:
        _fail_scenario(exc, scenario)
    from marinecdpr.studies.workspace import singular_poses

    _warn_singular(scenario, (singular_poses(sc), along))  # valid, but the robot is singular there
    from marinecdpr.planning.planner import trajectory_interference

    close = trajectory_interference(sc)  # valid, but the cables come too close there
    if close is not None:
        err_console.print(_plain(f"warning: {scenario}: {close}"), highlight=False, soft_wrap=True)
    r = sc.robot
    console.print(
        f"{_plain(scenario)}: ok: '{_plain(sc.name)}', {r.dofs} robot, {r.n_cables} cables, {r.mass_kg:g} kg; "
        f"base motion {sc.base_motion.type}; trajectory {sc.trajectory.type}; "
        f"{sc.time.n_steps} steps of {sc.time.step_s:g} s; method {sc.planning.method}",
        highlight=False, soft_wrap=True,
    )
    if sc.trajectory.type == "coverage":
        from marinecdpr.motion.trajectory import cleaning_path

        path = cleaning_path(sc.cleaning)
        end = sc.trajectory.start_time_s + path.duration_s
        console.print(f"coverage path: {path.lanes} lanes {path.spacing_m:.4g} m apart at {path.direction_deg:g} deg, "
                      f"{path.length_m:.4g} m, {path.duration_s:.4g} s"
                      + (f" (the pass along the edges {path.boundary_length_m:.4g} m, {path.boundary_duration_s:.4g} s "
                         "of it)" if path.boundary_length_m > 0 else "")
                      + ("" if end <= sc.time.duration_s + 1e-9 else
                         f" (the scenario's {sc.time.duration_s:g} s ends before the path: only part of the panel)"),
                      highlight=False, soft_wrap=True)


MAX_RAO_FREQUENCIES = 2000
"""Most wave frequencies ``rao --omega`` takes (a table of 33 is typical)."""


@app.command()
def rao(
    length: Optional[float] = typer.Option(None, help="The hull's length, m."),
    beam: Optional[float] = typer.Option(None, help="Its beam, m."),
    draught: Optional[float] = typer.Option(None, help="Its draught, m."),
    gm: Optional[float] = typer.Option(None, help="Its transverse metacentric height GM, m."),
    mesh: Optional[Path] = typer.Option(None, help="A hull mesh instead (GDF, STL, Nemoh, HST, PNL): its RAOs, and "
                                        "its hydrostatics from its panels."),
    kg: Optional[float] = typer.Option(None, help="With --mesh: the centre of gravity's height above the keel, m "
                                       "(GM = KB + BM - KG)."),
    mesh_units: str = typer.Option("m", help="With --mesh: its length unit: m, cm, mm or ft."),
    waterline: float = typer.Option(0.0, help="With --mesh: the waterline's z in the mesh, in its units."),
    roll_damping: float = typer.Option(0.05, help="Viscous roll damping, a fraction of critical (BEM has none)."),
    headings: str = typer.Option("90,120,150,180", help="Wave headings, deg, comma-separated."),
    omega: str = typer.Option("0.2:1.8:33", help="Wave frequencies first:last:count, rad/s."),
    panel: Optional[float] = typer.Option(None, help="About the panels' size, m (default 2.5; not with --mesh)."),
    hull: Optional[str] = typer.Option(None, help="The hull's form: box (default), or wigley (the analytic ship form, "
                                       "fine ends); not with --mesh."),
    out: Path = typer.Option(Path("out"), "--out", "-o", help="Folder for rao.nc and rao.png."),
) -> None:
    """A hull's RAOs from the BEM code Capytaine (pip install 'marinecdpr[bem]'): a box or
    Wigley hull of given main dimensions, or a hull mesh (--mesh, with --kg). Writes rao.nc
    ([base_motion.rao] source = "capytaine"), the same table as rao.csv (source = "csv",
    read without the extra) and rao.png, beside the built-in box approximation (of the same
    main dimensions)."""
    import numpy as np

    from marinecdpr import __version__
    from marinecdpr.motion.bem import HULL_SHAPES, hull_bem
    from marinecdpr.report.writers import write_rao

    if mesh is not None:
        given = [f"--{n}" for n, v in (("length", length), ("beam", beam), ("draught", draught), ("gm", gm),
                                       ("panel", panel), ("hull", hull)) if v is not None]
        if given:
            _fail(f"--mesh {mesh}: {', '.join(given)} cannot go with it: the mesh gives the hull "
                  "(its GM from --kg)")
        if kg is None:
            _fail(f"--mesh {mesh}: give --kg, the centre of gravity's height above the keel, m")
        _number("--kg", kg)
    else:
        missing = [f"--{n}" for n, v in (("length", length), ("beam", beam), ("draught", draught), ("gm", gm))
                   if v is None]
        if missing:
            _fail(f"missing {', '.join(missing)}: give the hull's main dimensions and GM, or --mesh FILE --kg KG")
        if kg is not None:
            _fail("--kg goes with --mesh (a box or Wigley hull takes --gm)")
        hull = hull or "box"
        panel = 2.5 if panel is None else panel
        if hull not in HULL_SHAPES:
            _fail(f"--hull {hull}: expected one of {', '.join(HULL_SHAPES)}")
        for name, value in (("--length", length), ("--beam", beam), ("--draught", draught), ("--gm", gm),
                            ("--panel", panel)):
            _number(name, value)
    _number("--roll-damping", roll_damping, zero_ok=True)
    if roll_damping > 1.0:
        _fail(f"--roll-damping {roll_damping:g}: expected a fraction of critical damping from 0 to 1")
    from marinecdpr.planning.budget import check_bem_size

    heads = tuple(sorted(h % 360.0 for h in _headings(headings, "90,180")))
    try:
        first, last, count = omega.split(":")
        first, last, count = float(first), float(last), int(count)
    except ValueError:
        _fail(f"--omega {omega}: expected first:last:count, e.g. 0.2:1.8:33")
    if not (math.isfinite(first) and math.isfinite(last) and 0 < first < last and 2 <= count <= MAX_RAO_FREQUENCIES):
        _fail(f"--omega {omega}: expected first:last:count with 0 < first < last and 2 <= count <= "
              f"{MAX_RAO_FREQUENCIES}")
    w = np.linspace(first, last, count)
    if mesh is not None:
        return _rao_mesh(mesh, kg=kg, units=mesh_units, waterline=waterline, roll_damping=roll_damping, heads=heads,
                         w=w, omega=omega, out=out)
    try:  # before any work: a BEM the machine cannot hold or finish is one line
        check_bem_size(shape=hull, length_m=length, beam_m=beam, draught_m=draught, panel_m=panel,
                       frequencies=count, headings=len(heads))
    except (ScenarioError, ValueError) as exc:
        _fail(str(exc))
    t0 = time.perf_counter()
    with _output(out) as folder:
        try:
            ds = hull_bem(shape=hull, length_m=length, beam_m=beam, draught_m=draught, gm_m=gm,
                          roll_damping_ratio=roll_damping, omega=w, heading_deg=heads, panel_m=panel)
        except (ScenarioError, ValueError) as exc:
            _fail(str(exc))
        made = (f"marinecdpr rao {'' if hull == 'box' else f'--hull {hull} '}--length {length:g} --beam {beam:g} "
                f"--draught {draught:g} --gm {gm:g} "
                f"--roll-damping {roll_damping:g} --headings {','.join(f'{h:g}' for h in heads)} --omega {omega} "
                f"--panel {panel:g} (marinecdpr {__version__})")
        box_label = "box approximation" + ("" if hull == "box" else " of the same main dimensions")
        try:  # a result the tables refuse (not finite, beyond their ranges) is one line, not a traceback
            bem, box, paths = write_rao(ds, folder, made_by=made, box=dict(length_m=length, beam_m=beam,
                                                                            draught_m=draught, gm_m=gm,
                                                                            roll_damping_ratio=roll_damping),
                                        box_label=box_label)
        except (ScenarioError, ValueError) as exc:
            _fail(f"the BEM's RAOs for these dimensions cannot be written: {exc}")
    peak = float(np.degrees(np.abs(bem.values[3])).max())
    console.print(_plain(f"{ds.attrs['hull']}: roll peaks at {peak:.3g} deg/m ({box_label} "
                         f"{float(np.degrees(np.abs(box.values[3])).max()):.3g}); written to {out}/: "
                         f"{', '.join(p.name for p in paths)} ({time.perf_counter() - t0:.1f} s)"),
                  highlight=False, soft_wrap=True)


def _rao_mesh(mesh: Path, *, kg: float, units: str, waterline: float, roll_damping: float, heads: tuple, w,
              omega: str, out: Path) -> None:
    """``rao --mesh``: the mesh read and checked, its size and run time said, then the BEM."""
    import numpy as np

    from marinecdpr import __version__
    from marinecdpr.motion.bem import mesh_bem
    from marinecdpr.motion.hullmesh import load_hull_mesh
    from marinecdpr.planning.budget import check_bem_size
    from marinecdpr.report.writers import write_rao

    try:
        hull = load_hull_mesh(mesh, units=units, waterline_m=waterline)
        size = check_bem_size(panels=hull.panels, frequencies=len(w), headings=len(heads), what=f"the mesh {mesh}")
    except (ScenarioError, ValueError) as exc:
        _fail(str(exc))
    err_console.print(_plain(f"mesh: {mesh}: {hull.panels} panels below the waterline, {hull.length_m:.4g} x "
                             f"{hull.beam_m:.4g} x {hull.draught_m:.4g} m; the BEM at {len(w)} frequencies takes "
                             f"about {_seconds(size.seconds)}"), highlight=False, soft_wrap=True)
    t0 = time.perf_counter()
    with _output(out) as folder:
        try:
            ds = mesh_bem(hull, kg_m=kg, roll_damping_ratio=roll_damping, omega=w, heading_deg=heads,
                          label=f"mesh {mesh.name}")
        except (ScenarioError, ValueError) as exc:
            _fail(f"--mesh {mesh}: {exc}")
        made = (f"marinecdpr rao --mesh {mesh} --kg {kg:g} --mesh-units {units} --waterline {waterline:g} "
                f"--roll-damping {roll_damping:g} --headings {','.join(f'{h:g}' for h in heads)} --omega {omega} "
                f"(marinecdpr {__version__})")
        box = dict(length_m=hull.length_m, beam_m=hull.beam_m, draught_m=hull.draught_m, gm_m=float(ds.attrs["gm_m"]),
                   roll_damping_ratio=roll_damping)
        try:
            bem, approx, paths = write_rao(ds, folder, made_by=made, box=box,
                                           box_label="box approximation of the same main dimensions and GM")
        except (ScenarioError, ValueError) as exc:
            _fail(f"the BEM's RAOs for this mesh cannot be written: {exc}")
    a = ds.attrs
    console.print(_plain(f"hydrostatics from the mesh: displacement {a['volume_m3']:.5g} m3, waterplane "
                         f"{a['waterplane_area_m2']:.5g} m2, KB {a['kb_m']:.4g} m, BM {a['bm_m']:.4g} m, GM "
                         f"{a['gm_m']:.4g} m (KG {kg:g} m)"), highlight=False, soft_wrap=True)
    peak = float(np.degrees(np.abs(bem.values[3])).max())
    console.print(_plain(f"{a['hull']}: roll peaks at {peak:.3g} deg/m (box approximation "
                         f"{float(np.degrees(np.abs(approx.values[3])).max()):.3g}); written to {out}/: "
                         f"{', '.join(p.name for p in paths)} ({time.perf_counter() - t0:.1f} s)"),
                  highlight=False, soft_wrap=True)


@app.command()
def windows(
    series: Optional[Path] = typer.Argument(None, help="Sea-state series CSV (time_h,hs_m,tp_s); default: the "
                                            "package's illustrative, synthetic one."),
    duration_h: float = typer.Option(..., "--duration-h", help="The operation's duration, h."),
    hs_limit: Optional[float] = typer.Option(None, help="A constant design Hs limit, m."),
    operability_json: Optional[Path] = typer.Option(None, "--operability", help="An operability.json: its "
                                                    "limiting Hs per Tp is the design limit."),
    heading: float = typer.Option(180.0, help="With --operability: the heading whose limits apply, deg."),
    alpha: float = typer.Option(1.0, help="DNV-ST-N001's alpha factor for the operation's duration and forecast "
                                "(operational limit = alpha x design limit)."),
    days: str = typer.Option("1,3,7", help="Report the probability of finishing within these many days."),
    out: Path = typer.Option(Path("out"), "--out", "-o", help="Folder for windows.csv, summary.json, windows.png."),
) -> None:
    """Weather windows in a series of sea states: when an operation of --duration-h fits,
    the expected wait before it can start, and the probability it is done within days."""
    from importlib import resources

    from marinecdpr.report.writers import write_windows
    from marinecdpr.studies.weather import (limit_from_operability, read_operability_json, read_sea_state_series,
                                            weather_windows)

    _number("--duration-h", duration_h)
    if (hs_limit is None) == (operability_json is None):
        _fail("give one design limit: --hs-limit H or --operability FILE.json")
    _number("--hs-limit", hs_limit)
    _number("--heading", heading, finite_only=True)
    if not (math.isfinite(alpha) and 0.0 < alpha <= 1.0):
        _fail(f"--alpha {alpha:g}: expected a factor in (0, 1]")
    try:
        day_list = [float(d) for d in days.split(",")]
    except ValueError:
        day_list = []
    if not day_list or not all(math.isfinite(d) and d > 0 for d in day_list):
        _fail(f"--days {days}: expected positive numbers separated by commas, e.g. 1,3,7")
    try:
        path = series or Path(str(resources.files("marinecdpr") / "data" / "sea_states_illustrative.csv"))
        sea = read_sea_state_series(path)
        table = None
        if operability_json is not None:
            if operability_json.is_dir():
                raise ScenarioError("a folder, not a file; expected an operability.json", source=str(operability_json))
            try:
                table = limit_from_operability(read_operability_json(operability_json), heading)
            except ScenarioError as exc:
                raise ScenarioError(exc.detail, source=str(operability_json), key=exc.key) from None
    except ScenarioError as exc:
        _fail(str(exc))
    w = weather_windows(sea, duration_h=duration_h, alpha=alpha, hs_limit_m=hs_limit, limit_table=table)
    limit = (f"Hs {hs_limit:g} m" if hs_limit is not None else
             f"limiting Hs per Tp of {operability_json} at {heading:g} deg")
    with _output(out) as folder:
        summary, paths = write_windows(sea, w, folder, series_name=str(path), design_limit=limit,
                                       days=day_list)
    wait = "never within the series" if w.mean_wait_h != w.mean_wait_h else f"{w.mean_wait_h:.1f} h on average"
    finish = summary["finish_within_days_probability"]
    console.print(_plain(f"{_count(len(w.windows), 'window')}, {summary['windows_long_enough']} of them {duration_h:g} h or "
                         f"longer; wait before the operation can start: {wait} (it can start from "
                         f"{100 * w.can_start:.1f} % of the start times); done within "
                         + ", ".join(f"{_count(d, 'day')}: {100 * p:.1f} %" for d, p in finish.items())
                         + f"; written to {out}/: {', '.join(p.name for p in paths)}"), highlight=False,
                  soft_wrap=True)


@app.command("control-study")
def control_study(
    scenario: str = typer.Argument("paper_sea", help="A scenario file, or a built-in name."),
    latencies: str = typer.Option(",".join(f"{x:g}" for x in ControlStudySpec.default("latencies")), "--latencies",
                                  help="Motion sensor latencies, ms, comma-separated."),
    predictions: str = typer.Option(",".join(ControlStudySpec.default("predictions")), "--predictions",
                                    help="How the controller brings the ship's samples to the present: none, "
                                         "kinematic, ar."),
    pose_from: str = typer.Option(",".join(ControlStudySpec.default("pose_from")), "--pose-from",
                                  help="Pose sources: sensor, encoders."),
    rate: float = typer.Option(ControlStudySpec.default("rate"), "--rate",
                               help="The motion sensor's samples per second, Hz."),
    encoder_resolution: Optional[float] = typer.Option(ControlStudySpec.default("encoder_resolution"),
                                                       "--encoder-resolution",
                                                       help="The encoders' length step, m (default: the scenario's)."),
    duration: float = typer.Option(ControlStudySpec.default("duration"), "--duration", help="Each run's length, s."),
    settle: Optional[float] = typer.Option(ControlStudySpec.default("settle"), "--settle",
                                           help="Errors count from this time on, s (default: the predictor's "
                                                "warm-up and a second)."),
    plant: str = typer.Option(ControlStudySpec.default("plant"), "--plant", help="own or mujoco."),
    out: Path = typer.Option(Path("out"), "--out", "-o", help="Folder for control_study.csv/.png, prediction.csv, "
                                                              "summary.json."),
) -> None:
    """What the ship-motion sensor's latency costs in tracking and tension margin, with the
    ship's motion predicted or not, and the pose from a pose sensor or the winches' encoders;
    and the ship-motion predictor's error against the horizon."""
    from marinecdpr.commands import control_study as command
    from marinecdpr.commands.base import SpecError

    spec = _spec(ControlStudySpec, latencies=latencies, predictions=predictions, pose_from=pose_from, rate=rate,
                 encoder_resolution=encoder_resolution, duration=duration, settle=settle, plant=plant)
    sc = _load(scenario, None, None)
    try:  # before any work: what the scenario cannot take, and runs the machine cannot hold or finish
        est = command.estimate(spec, sc)
    except SpecError as exc:
        _fail_spec(exc)
    with _output(out) as folder:
        _compile_notice(spec.plant)
        with _run_errors(scenario), _progress("closed-loop runs", spec.n_runs, "runs") as bar:
            result = command.run(spec, sc, estimated=est, progress=bar)
        _, paths = result.write(folder)
    name, settle = est.flown.name, result.settle
    console.print(f"{_plain(name)}: MRU {spec.rate:g} Hz, judged from {settle:g} s of {spec.duration:g} s runs",
                  highlight=False)
    for r in result.study.runs:
        console.print(f"  latency {1e3 * r.latency_s:5.1f} ms, {r.prediction:9s}, pose from {r.pose_from:8s}: "
                      f"RMS error {r.rms_error_m:.3g} m, max {r.max_error_m:.3g} m, headroom {r.headroom_N:.4g} N, "
                      f"slack margin {r.slack_margin_N:.4g} N"
                      + (f"; controller BYPASSED at {r.fallbacks} steps" if r.controller_verdict == "bypassed" else ""),
                      highlight=False, soft_wrap=True)
    console.print(_plain(f"written to {out}/: {', '.join(p.name for p in paths)}"), highlight=False, soft_wrap=True)
    _fail_bypassed([(f"latency {1e3 * r.latency_s:g} ms, prediction {r.prediction}, pose from {r.pose_from}",
                     r.fallbacks, result.study.steps) for r in result.study.bypassed], est.flown, out)


@app.command()
def latency(
    scenario: str = typer.Argument("paper", help="A scenario file, or a built-in name."),
    calls: int = typer.Option(20000, "--calls", help="Steps timed from Python and in a compiled loop (1 to "
                              "10,000,000)."),
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object instead of a table."),
) -> None:
    """How long the controller's step takes on this machine: called from Python and inside a
    compiled loop along the scenario's plan, beside one quadprog solve of the same tension
    problem (the bench extra)."""
    import dataclasses

    from marinecdpr.planning.budget import check_latency_calls
    from marinecdpr.report.files import json_text
    from marinecdpr.studies.latency import LATENCY_COMPILE_S, controller_latency, latency_kernels_cached

    try:
        check_latency_calls(calls)  # before any work
    except ScenarioError as exc:
        _fail(str(exc))
    sc = _load(scenario, None, None)
    if not latency_kernels_cached():
        _compiling("the controller's step", LATENCY_COMPILE_S)
    with _run_errors(scenario):
        lat = controller_latency(sc, calls=calls)
    if as_json:
        print(json_text(dataclasses.asdict(lat), indent=None))
        return
    qp = "quadprog not installed (pip install 'marinecdpr[bench]')" if lat.quadprog_p50_us is None else \
        f"{lat.quadprog_p50_us:.2f} us per solve (p50)"
    console.print(f"{_plain(lat.scenario)}: {lat.cables} cables, redundancy {lat.redundancy}, {lat.method}; "
                  f"{lat.calls} calls", highlight=False, soft_wrap=True)
    for where in ("python", "compiled"):
        p50, p99, top = (getattr(lat, f"{where}_{q}_us") for q in ("p50", "p99", "max"))
        console.print(f"  step from {'Python' if where == 'python' else 'a compiled loop'}: p50 {p50:.2f} us, "
                      f"p99 {p99:.2f} us, max {top:.1f} us", highlight=False)
    console.print(f"  quadprog: {qp}", highlight=False)


@app.command()
def warmup(
    scenarios_: list[str] = typer.Argument(None, metavar="[SCENARIO]...",
                                           help="Scenario files or built-in names (default: every built-in)."),
    plant: Plant = typer.Option(None, "--plant", help="Compile for this plant (default: each scenario's)."),
) -> None:
    """Compile the virtual prototype for your scenarios now, once (cached for every later
    run): use it after installing or updating, before a demonstration, a sweep or a timed
    run, so that their first run starts at once."""
    from marinecdpr.prototype.warmup import warm_up

    names = scenarios_ or builtin_scenarios()
    loaded = [_load(name, None, None) for name in names]

    def progress(done: int, total: int, what: str) -> None:
        if done < total:
            err_console.print(f"compiling ({done + 1}/{total}) {_plain(what)}...", highlight=False, soft_wrap=True)

    with _run_errors(", ".join(names)):
        out = warm_up(loaded, plants=(plant.value,) if plant is not None else None, progress=progress)
    console.print(f"compiled for {len(names)} scenario{'s' if len(names) != 1 else ''} "
                  f"({len(out.runs)} runs) in {out.seconds:.1f} s; cached in {_plain(out.cache_dir)}",
                  highlight=False, soft_wrap=True)


@app.command()
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
        _fail("design needs pymoo: pip install 'marinecdpr[design]'")
    try:
        study_spec, template = load_design(path)
        study_spec = with_options(study_spec, population=population, generations=generations, seed=seed)
        cells = study_cells(study_spec, path.parent)
    except ScenarioError as exc:
        _fail(str(exc))
    _sea_study_options(",".join(f"{h:g}" for h in study_spec.sea.headings_deg), serial, workers, scheduler)
    n_final = study_spec.finalists if verify else 0
    from marinecdpr.studies.operability import CLOSED_LOOP_STEP_COST

    steps = n_final * len(cells) * template.time.n_steps * CLOSED_LOOP_STEP_COST  # about: each finalist's own
    executor = _sea_executor(serial, workers, scheduler, steps) if n_final else "serial"
    if resume:  # before the search's first line: a journal that cannot be resumed is one line
        try:
            read_journal(out / "journal.jsonl", study_key(study_spec, template, cells))
        except ScenarioError as exc:
            _fail(str(exc))
    t0 = time.perf_counter()
    with _output(out) as folder:
        with _progress_bar("design", "candidates") as bar:
            task = bar.add_task("", total=study_spec.population * study_spec.generations)

            def progress(done: int, total: int, best: float) -> None:
                bar.update(task, completed=done, total=total,
                           description="best feasible: " + (f"{best:.4g} h" if best < float("inf") else "none yet"))

            journal = out / "journal.jsonl"  # beside the staged files: an interrupted run keeps it
            try:
                with _run_errors(spec):
                    study = search(study_spec, template, cells, progress=progress, journal=journal, resume=resume,
                                   executor="dask" if (workers is not None or scheduler) else "serial",
                                   scheduler=scheduler, workers=workers or 2)
            except KeyboardInterrupt:
                kept = max(len(journal.read_text(encoding="utf-8").splitlines()) - 1, 0) if journal.is_file() else 0
                _fail(f"interrupted; {_count(kept, 'candidate')} kept in {journal}: rerun with --resume to go on",
                      EXIT_INTERRUPTED)
        checked = []
        if n_final and study.front:
            _compile_notice(plant.value if plant is not None else study_spec.plant or template.simulation.plant)
            with _progress_bar("finalists", "sea states") as bar:
                task = bar.add_task("", total=min(n_final, len(study.front)) * len(cells))
                with _run_errors(spec):
                    checked = verify_finalists(study, template, study_scatter(study_spec, path.parent),
                                               executor=executor, workers=workers or 2, scheduler=scheduler,
                                               plant=plant.value if plant is not None else None,
                                               progress=lambda d, tot: bar.update(task, completed=d, total=tot))
        from marinecdpr.report.design import write_design

        paths = [out / p.relative_to(folder) for p in write_design(study, template, folder, checked)]
    ev, b = study.evaluations, study.baseline
    console.print(_plain(f"{study_spec.name}: {_count(len(ev), 'candidate')} ({sum(e.feasible for e in ev)} "
                         f"feasible) over {_count(len(cells), 'sea state')} in "
                         f"{_seconds(time.perf_counter() - t0)}"), highlight=False, soft_wrap=True)
    if study.front:
        e = ev[study.front[0]]
        x = e.x
        console.print(_plain(
            f"best: frame {x['frame_width_m']:.3g} x {x['frame_height_m']:.3g} m, platform {x['platform_width_m']:.3g} x "
            f"{x['platform_height_m']:.3g} m ({e.mass_kg:.3g} kg), cables {x.get('pattern', 'uncrossed')}, tool "
            f"{x['tool_width_m']:.3g} m at "
            f"{x['speed_m_s']:.3g} m/s, winches {x['winch']} ({e.power_kW:g} kW in all, T_max {e.tension_max_N:.4g} N), "
            f"rope {x['rope']}: {e.placements} placements, {e.surface_hours:.4g} h on the surface, works in "
            f"{100 * e.sea_share:.1f} % of the seas: {e.expected_hours:.4g} expected h (target "
            f"{study_spec.targets.hours:g} h: {'met' if e.expected_hours <= study_spec.targets.hours else 'not met'})"),
            highlight=False, soft_wrap=True)
        if e.sea_reason:
            console.print(_plain(f"  the screen: {e.sea_reason}"), highlight=False, soft_wrap=True)
        h = e.hours_breakdown()
        if all(math.isfinite(v) for v in h.values()):
            console.print(_plain(
                f"its {e.expected_hours:.4g} expected h: {h['cleaning']:.3g} h cleaning + {h['turns']:.3g} h turns "
                f"between lanes + {h['moves']:.3g} h moving the frame + {h['weather']:.3g} h waiting for weather; "
                "binding: " + ", ".join(f"{k} ({100 * v:.3g} % left)" for k, v in e.binding())),
                highlight=False, soft_wrap=True)
    else:
        console.print("no feasible candidate: see candidates.csv's margins and reasons", highlight=False)
    for v in checked:
        console.print(_plain(
            f"finalist {v.rank} (candidate {v.index}) in the time domain as built "
            f"({'MuJoCo' if v.plant == 'mujoco' else 'own plant'}, its rope's stretch, motor winches): works in {100 * v.td_share:.1f} % of the "
            f"seas (the screen: {100 * v.screen_share:.1f} %), {v.td_expected_hours:.4g} expected h (the screen: "
            f"{v.screen_expected_hours:.4g} h); verdicts agree in {v.agree} of {len(cells)} sea states, the screen "
            f"passed {v.screen_works_td_fails} the time domain failed"), highlight=False, soft_wrap=True)
    console.print(_plain(f"baseline (the template's robot): {b.placements} placements, {b.surface_hours:.4g} h on the "
                         f"surface, works in {100 * b.sea_share:.1f} % of the seas: {b.expected_hours:.4g} expected h"),
                  highlight=False, soft_wrap=True)
    if b.sea_reason:
        console.print(_plain(f"  the screen: {b.sea_reason}"), highlight=False, soft_wrap=True)
    console.print("written: " + ", ".join(_plain(p) for p in paths if p.parent == out) + ", designs/",
                  highlight=False, soft_wrap=True)


@contextmanager
def _file_folder(out: Path):
    """The folder of an output file, created if missing (as the commands' output folders are)
    and removed again if the block fails while it is still empty; a path through a file is
    one line, exit 2 (``--out notes.txt/x.toml``: notes.txt is a file, not a folder)."""
    missing = []
    for folder in (out.parent, *out.parent.parents):
        if folder.is_dir():
            break
        if folder.exists() or folder.is_symlink():
            _fail(f"--out {out}: {folder} is a file, not a folder")
        missing.append(folder)
    for folder in reversed(missing):
        folder.mkdir()
    try:
        yield
    except BaseException:
        for folder in missing:  # the deepest first; each only while empty
            try:
                folder.rmdir()
            except OSError:
                break
        raise


@app.command("import")
def import_(
    source: Path = typer.Argument(..., help="A CASPR model's *_bodies.xml or a WireX robot (.wcrfx)."),
    out: Path = typer.Option(..., "--out", "-o", help="The scenario file to write (.toml)."),
    cables: Optional[Path] = typer.Option(None, help="CASPR: the cables file (default: X_cables.xml beside "
                                          "X_bodies.xml)."),
    trajectories: Optional[Path] = typer.Option(None, help="CASPR: the trajectories file (default: "
                                                "X_trajectories.xml beside it, if there)."),
    cable_set: Optional[str] = typer.Option(None, help="CASPR: the cable set (default: the file's default)."),
    trajectory: Optional[str] = typer.Option(None, help="CASPR: the trajectory's id (default: the first)."),
    hold: bool = typer.Option(False, "--hold", help="CASPR: hold the platform at the joint's q_initial, "
                              "whatever trajectories the model has."),
    pulleys: bool = typer.Option(False, "--pulleys", help="WireX: carry over each chain's pulley."),
) -> None:
    """Write a scenario from a robot model of CASPR or WireX, saying what it could not carry over."""
    from marinecdpr.scenario.importing import import_robot, scenario_toml
    from marinecdpr.textfiles import atomic_path

    if out.suffix != ".toml":
        _fail(f"--out {out}: expected a scenario file name ending in .toml")
    if out.is_dir():
        _fail(f"--out {out}: a folder; expected a scenario file name")
    try:
        imported = import_robot(source, cables=cables, trajectories=trajectories, cable_set=cable_set,
                                trajectory=trajectory, hold=hold, pulleys=pulleys)
        text = scenario_toml(imported)
        with _file_folder(out), atomic_path(out) as tmp:
            tmp.write_text(text, encoding="utf-8")
            load_scenario(tmp)  # reads back as it will be read
    except ScenarioError as exc:
        _fail(str(exc))
    except OSError as exc:
        _fail(f"--out {out}: cannot write ({exc.strerror or exc})")
    r = imported.data["robot"]
    console.print(_plain(f"{out}: '{imported.data['name']}' from {imported.source}, a {r['dofs']} robot with "
                         f"{len(r['cables'])} cables, {r['mass_kg']:g} kg; trajectory "
                         f"{imported.data['trajectory']['type']}"), highlight=False, soft_wrap=True)
    for note in imported.notes:
        console.print(_plain(f"note: {note}"), highlight=False, soft_wrap=True)
    # a robot that cannot hold its platform, said at once (a warning: the file is written)
    from marinecdpr.planning.planner import sampled_infeasibility

    try:
        sc = load_scenario(out)
        _warn_scale(sc, str(out))
        problem = sampled_infeasibility(sc)
    except ScenarioError as exc:
        problem = f"it cannot be planned as it is: {exc}"
    if problem is not None:
        err_console.print(_styled("warning:", "bold yellow", _plain(f"{out}: as imported, {problem}")),
                          highlight=False, soft_wrap=True)


@app.command()
def scenarios() -> None:
    """List the built-in scenarios and design studies, each with its description."""
    from marinecdpr.studies.design import builtin_studies, load_design, study_path

    names = builtin_scenarios()
    width = max(len(n) for n in names)
    for name in names:
        console.print(_plain(f"{name:<{width}}  {load_scenario(name).description}"), highlight=False,
                      soft_wrap=True)
    for name in builtin_studies():  # after the scenarios, not led by a name: a script that takes each
        # line's first word for a scenario meets no study
        console.print(_plain(f"built-in design study {name} (marinecdpr design {name}): "
                             f"{load_design(study_path(name))[0].description}"), highlight=False, soft_wrap=True)


def _help_read_literally(typer_app: typer.Typer) -> None:
    """Escape rich markup in every command's help (its docstring and its options' help), so
    that typer's help shows it as written: "pip install 'marinecdpr[bem]'", not without "[bem]";
    each docstring's paragraphs rewrapped, and the parameters shown by :class:`_Command`."""
    import inspect

    for command in typer_app.registered_commands:
        doc = command.help if command.help is not None else inspect.getdoc(command.callback)
        if doc:
            # each paragraph one line, for the help to wrap to the terminal (typer kept the
            # docstrings' own breaks after the first paragraph)
            command.help = escape("\n\n".join(" ".join(p.split()) for p in doc.split("\n\n")))
        if command.cls in (None, typer.core.TyperCommand):
            command.cls = _Command
        for parameter in inspect.signature(command.callback).parameters.values():
            info = parameter.default
            if isinstance(info, typer.models.ParameterInfo) and info.help:
                info.help = escape(info.help)


def _interrupted_while_ending(signum, frame) -> None:  # pragma: no cover - timing
    """Ctrl-C once the command has finished (the interpreter shutting down, e.g. a Dask
    cluster's teardown): one line if none was printed, exit 130."""
    if not _interruption_said:
        os.write(2, b"error: interrupted\n")
    os._exit(EXIT_INTERRUPTED)


def _interrupt_thread_soon(thread_id: int) -> None:  # pragma: no cover - a helper thread
    time.sleep(0.02)
    signal.pthread_kill(thread_id, signal.SIGINT)


_swallowed_interrupt = False
"""Set once a Ctrl-C was swallowed (:func:`_redeliver_swallowed_interrupt`): a command that
ends before its redelivery reaches it still exits 130."""


def _redeliver_swallowed_interrupt(unraisable) -> None:
    """``sys.unraisablehook`` while a command runs: a Ctrl-C whose ``KeyboardInterrupt``
    was raised where Python can only report it (a weakref callback, e.g. the import
    system's module locks, or a ``__del__``) is delivered again to the main thread, where
    it interrupts the command; anything else is reported as Python would."""
    global _swallowed_interrupt
    if unraisable.exc_type is not None and issubclass(unraisable.exc_type, KeyboardInterrupt):
        import _thread
        import threading

        _swallowed_interrupt = True  # main() ends with exit 130 if the command ends first
        # from another thread, once this hook has returned (sent from here, the handler
        # would raise at once, inside the hook); _thread's start does not wait for the thread
        _thread.start_new_thread(_interrupt_thread_soon, (threading.main_thread().ident,))
        return
    sys.__unraisablehook__(unraisable)


def main() -> None:
    """Console entry point.

    Ctrl-C is one line on stderr and exit 130 at any moment: while the modules load
    (:func:`_interrupted_while_starting`), while a command runs (``KeyboardInterrupt``,
    delivered again where Python would swallow it (:func:`_redeliver_swallowed_interrupt`):
    the library tidies up, :func:`_output` says what the output folder holds; typer turns
    one raised elsewhere into a silent exit 130, given its line here) and after it.
    """
    if signal.getsignal(signal.SIGINT) is _interrupted_while_starting:
        signal.signal(signal.SIGINT, signal.default_int_handler)
    sys.unraisablehook = _redeliver_swallowed_interrupt
    try:
        keep_freed_memory()
        app()
    except KeyboardInterrupt:  # outside a command (as typer builds the commands): exit here, not
        try:                   # by typer's Exit, which only a running command turns into an exit
            _fail("interrupted", EXIT_INTERRUPTED)
        except typer.Exit:
            raise SystemExit(EXIT_INTERRUPTED) from None
    except SystemExit as exc:
        code = EXIT_INTERRUPTED if _swallowed_interrupt and exc.code in (0, None) else exc.code
        if code == EXIT_INTERRUPTED and not _interruption_said:
            err_console.print(_styled("error:", "bold red", "interrupted"), highlight=False)
        if code != exc.code:  # the Ctrl-C came back only after the command had ended
            raise SystemExit(code) from None
        raise
    finally:
        if signal.getsignal(signal.SIGINT) is signal.default_int_handler:
            signal.signal(signal.SIGINT, _interrupted_while_ending)


_help_read_literally(app)

if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
