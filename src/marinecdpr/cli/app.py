"""The ``marinecdpr`` command: parses arguments, calls the library, prints.

Exit codes: 0 success; 2 bad input (a scenario, an option, or an output folder that
cannot be written); 3 the cables cannot hold the platform somewhere on the plan
(``plan`` still writes its outputs, complete); 4 a simulation diverged; 5 a closed loop's
controller was bypassed (the plan's tensions fed forward) on more than ``[simulation]
max_bypassed_share`` of its steps (the outputs are written, complete, with the verdict);
130 interrupted (Ctrl-C: the output folder keeps what it held).
"""

from __future__ import annotations

import os
import signal
import sys

from marinecdpr.starting import catch_while_starting
from marinecdpr.starting import interrupted_while_starting as _interrupted_while_starting

# first, before the heavy imports below (typer, rich, numpy, pydantic: about a second on a
# loaded machine); the package set it already where the console script imported it
catch_while_starting()


import time  # noqa: E402
from contextlib import contextmanager  # noqa: E402

import typer  # noqa: E402
from rich.markup import escape  # noqa: E402

from marinecdpr.cli import (check, clean, control_study, design, faults, import_robot, latency,  # noqa: E402
                            operability, plan, rao, scenarios, simulate, warmup, windows, workspace)
from marinecdpr.cli.common import EXIT_INTERRUPTED, console, err_console, fail, state, styled  # noqa: E402
from marinecdpr.memory import keep_freed_memory  # noqa: E402


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
        name, command, rest = super().resolve_command(ctx, args)
        state.command = command.name if command is not None else name
        return name, command, rest


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
        fail(f"{where}: {' '.join(exc.format_message().split()).rstrip('.')} (see {where} --help)", exc.exit_code)


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


# the commands, in the order the help lists them: each a plain function of its module
for command, name in ((plan.plan, None), (clean.clean, None), (simulate.simulate, None),
                      (workspace.workspace, None), (operability.operability, None), (faults.faults, None), (check.check, None),
                      (rao.rao, None), (windows.windows, None), (control_study.control_study, "control-study"),
                      (latency.latency, None), (warmup.warmup, None), (design.design, None),
                      (import_robot.import_, "import"), (scenarios.scenarios, None)):
    app.command(name)(command)


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
    if not state.interruption_said:
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
    the library tidies up, :func:`~marinecdpr.cli.common.output` says what the output folder holds; typer turns
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
            fail("interrupted", EXIT_INTERRUPTED)
        except typer.Exit:
            raise SystemExit(EXIT_INTERRUPTED) from None
    except SystemExit as exc:
        code = EXIT_INTERRUPTED if _swallowed_interrupt and exc.code in (0, None) else exc.code
        if code == EXIT_INTERRUPTED and not state.interruption_said:
            err_console.print(styled("error:", "bold red", "interrupted"), highlight=False)
        if code != exc.code:  # the Ctrl-C came back only after the command had ended
            raise SystemExit(code) from None
        raise
    finally:
        if signal.getsignal(signal.SIGINT) is signal.default_int_handler:
            signal.signal(signal.SIGINT, _interrupted_while_ending)


_help_read_literally(app)

if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
