"""What the commands share: the consoles, the one-line failure and its exit codes, the
scenario's loading and warnings, the output folder, and the small printed forms."""

from __future__ import annotations

import enum
from contextlib import contextmanager
from pathlib import Path

import typer
from rich.console import Console
from rich.text import Text

from marinecdpr.errors import InfeasibleError, ScenarioError, SimulationDivergedError
from marinecdpr.scenario.loading import load_scenario
from marinecdpr.textfiles import strip_control

EXIT_BAD_INPUT = 2
EXIT_INFEASIBLE = 3
EXIT_DIVERGED = 4
EXIT_BYPASSED = 5
EXIT_INTERRUPTED = 130


class _State:
    """What the running command's process knows of itself."""

    command: str | None = None
    """The command being run (``plan``, ``simulate``, ...): the kind of run an output folder's
    manifest records (:func:`output`); set as the command group resolves it."""
    interruption_said: bool = False
    """Has a one-line message about an interruption been printed (by :func:`fail`)?"""


state = _State()


class Plant(str, enum.Enum):
    """The virtual prototype's plants (``--plant``)."""

    mujoco = "mujoco"
    own = "own"


# no markup: every text printed reads literally (a user's names and paths, and the library's
# messages: "pip install 'marinecdpr[bench]'"); the few styled words are rich Text (styled)
console = Console(markup=False)
err_console = Console(stderr=True, markup=False)


def styled(word: str, style: str, rest: str) -> Text:
    """``word`` in ``style``, then a space and ``rest`` as it is."""
    return Text.assemble((word, style), " ", rest)


def plain(text: object) -> str:
    """Text from a user (names, paths, messages) for the terminal, read literally: control
    characters (ANSI escapes) removed (the consoles read no markup)."""
    return strip_control(str(text))


def fail(message: str, code: int = EXIT_BAD_INPUT) -> None:
    """``error: message`` on stderr, one line, and exit ``code`` (2: bad input)."""
    state.interruption_said = state.interruption_said or code == EXIT_INTERRUPTED
    err_console.print(styled("error:", "bold red", plain(message)), highlight=False, soft_wrap=True)
    raise typer.Exit(code)


def number(flag: str, value: float | None, *, zero_ok: bool = False, finite_only: bool = False) -> None:
    """Refuse an option's number that is not finite, or (unless ``finite_only``) not positive
    (not negative with ``zero_ok``): one line, exit 2."""
    from marinecdpr.commands.base import finite, positive

    try:
        finite(value) if finite_only else positive(value, zero_ok=zero_ok)
    except ValueError as exc:
        fail(f"{flag} {value:g}: {exc}")


def fail_scenario(exc: ScenarioError, scenario: str) -> None:
    """A scenario's error, prefixed with the scenario given when the error names no file."""
    fail(str(exc) if exc.source else f"{scenario}: {exc}")


def load(scenario: str, duration: float | None, step: float | None):
    """The scenario, with ``--duration`` and ``--step`` (checked: positive, finite) if given."""
    number("--duration", duration)
    number("--step", step)
    try:
        sc = load_scenario(scenario)
        warn_scale(sc, scenario)
        if duration is not None or step is not None:
            sc = sc.with_changes(time={"step_s": sc.time.step_s if step is None else step,
                                       "duration_s": sc.time.duration_s if duration is None else duration})
        return sc
    except ScenarioError as exc:
        fail_scenario(exc, scenario)


@contextmanager
def run_errors(scenario: str):
    """A run's failures as one line each: a bad scenario exits 2, an infeasible plan 3, a
    diverged simulation 4."""
    try:
        yield
    except ScenarioError as exc:
        fail_scenario(exc, scenario)
    except InfeasibleError as exc:
        fail(str(exc), EXIT_INFEASIBLE)
    except SimulationDivergedError as exc:
        fail(str(exc), EXIT_DIVERGED)


def compile_notice(plant: str) -> None:
    """A line on stderr when the simulation's loop must first be compiled (a fresh install);
    every command that flies the virtual prototype calls it before its work."""
    from marinecdpr.prototype.simulation import KERNEL_COMPILE_S, kernels_cached

    if not kernels_cached(plant):
        compiling("the simulation kernels", KERNEL_COMPILE_S)


def compiling(what: str, seconds: float) -> None:
    """The one-line notice that ``what`` is compiled now, once, for about ``seconds``."""
    err_console.print(f"compiling {what}, once (about {seconds:g} s; cached for later runs)...", highlight=False,
                      soft_wrap=True)


@contextmanager
def output(out: Path):
    """The output folder, checked before the work starts and filled all at once at the end
    (see :class:`marinecdpr.report.files.StagedOutput`); a failure writing it is one line, exit 2,
    and so is a folder holding another command's results (a run replaces only its own
    command's files: ``simulate`` then ``plan`` into one folder would lose the report)."""
    from marinecdpr.errors import OutputError
    from marinecdpr.report.files import StagedOutput

    try:
        staged = StagedOutput(out, command=state.command)
    except OutputError as exc:
        fail(f"--out {exc}")
    try:
        with staged as folder:
            yield folder
    except OSError as exc:
        fail(f"--out {out}: could not write the files ({exc.strerror or exc}); the folder keeps what it held")
    except KeyboardInterrupt:
        if staged.committed:  # Ctrl-C as the files went in: they are all there
            fail(f"interrupted; --out {out} holds this run's files, complete", EXIT_INTERRUPTED)
        fail(f"interrupted; --out {out} keeps what it held", EXIT_INTERRUPTED)


def figures_option(what: str):
    """The ``--figures/--no-figures`` option of a command that draws figures (``what``: the
    files): the spec's ``figures``, its default the defaults table's ``"report.figures"``
    (:mod:`marinecdpr.defaults`), read as the command runs."""
    from functools import partial

    from marinecdpr.defaults import get

    return typer.Option(..., "--figures/--no-figures", default_factory=partial(get, "report.figures"),
                        show_default=False,
                        help=f"Draw {what} (the default: marinecdpr.defaults' report.figures). --no-figures: "
                             "the other files the same, no figure drawn.")


def spec_of(cls, **options):
    """The command's spec of the options given; a bad one is one line naming its ``--flag``,
    exit 2 (:class:`~marinecdpr.commands.base.SpecError`)."""
    from marinecdpr.commands.base import SpecError

    try:
        return cls(**options)
    except SpecError as exc:
        fail_spec(exc)


def fail_spec(exc) -> None:
    """A command's :class:`~marinecdpr.commands.base.SpecError` as one line naming its
    ``--flag``, exit 2."""
    fail(f"{exc.flag} {exc.value}: {exc.detail}")


def count(number: object, noun: str) -> str:
    """``1 day``, ``3 days``, ``0.5 days``: the number as given, the noun singular for one."""
    return f"{number} {noun}" + ("" if float(number) == 1.0 else "s")


def interval(interval: tuple[float, float], realisations: int) -> str:
    """' (95 %: lo-hi %)' for a study with several realisations, else ''."""
    if realisations <= 1:
        return ""

    def bound(x: float) -> str:  # the exact ends as 0 and 100, like percent
        return "100" if x >= 1.0 else "0" if x <= 0.0 else f"{100 * x:.1f}"

    return f" (95 %: {bound(interval[0])}-{bound(interval[1])} %)"


def percent(x: float) -> str:
    """For display: 100 % and 0 % only when exact; the JSON keeps the exact values."""
    text = f"{100 * x:.1f}"
    return ("100 %" if x >= 1.0 else "0 %" if x <= 0.0 else "> 99.9 %" if text == "100.0"
            else "< 0.1 %" if text == "0.0" else f"{text} %")


def warn_scale(sc, scenario: str) -> None:
    """Print the scenario's scale warnings on stderr (a warning: the exit code is unchanged)."""
    from marinecdpr.scenario.scale import scale_warnings

    for line in scale_warnings(sc):
        err_console.print(styled("warning:", "bold yellow", f"{plain(scenario)}: {plain(line)}"), highlight=False,
                          soft_wrap=True)


def warn_singular(scenario: str, surveys) -> None:
    """Warn (stderr, exit code unchanged) where J~ loses rank in each survey
    (:class:`~marinecdpr.planning.verdicts.SingularPoses`: along the trajectory, from
    :func:`~marinecdpr.planning.planner.check_trajectory`; over the frame, from
    :func:`~marinecdpr.studies.workspace.singular_poses`); the layout's hint given once."""
    hinted = False
    for survey in surveys:
        line = survey.message(hint=not hinted)
        if line is not None:
            hinted = hinted or survey.scale is not None
            err_console.print(styled("warning:", "bold yellow", f"{plain(scenario)}: {plain(line)}"),
                              highlight=False, soft_wrap=True)


def fail_bypassed(runs: list[tuple[str, int, int]], sc, out: Path) -> None:
    """A failed run for each (name, bypassed steps, steps) whose controller was bypassed:
    one line on stderr, exit 5, after the files (which say so) are written."""
    from marinecdpr.studies.prototype_runs import bypassed_text

    if runs:
        name, fallbacks, steps = runs[0]
        more = f" (and {count(len(runs) - 1, 'more run')})" if len(runs) > 1 else ""
        fail(f"{name}{more}: {bypassed_text(fallbacks, steps, sc.simulation.max_bypassed_share)}; "
              f"see {out / 'summary.json'}", EXIT_BYPASSED)
