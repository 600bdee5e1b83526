"""Ctrl-C while typer builds the commands (after the imports, before a command runs): one
line and exit 130, not a traceback of typer's Exit (issue 37: seen by the interrupt tests
on a loaded machine, at 2.5 s)."""

import io
import signal
import sys

import pytest
from rich.console import Console

import marinecdpr.cli.app as cli


def test_ctrl_c_as_the_commands_are_built_is_one_line_exit_130(monkeypatch):
    def building():
        raise KeyboardInterrupt  # as inspect.signature works through a command's parameters

    err = io.StringIO()
    monkeypatch.setattr(sys, "unraisablehook", sys.unraisablehook)  # main() sets its own: put back after
    handler = signal.getsignal(signal.SIGINT)
    monkeypatch.setattr(cli, "app", building)
    monkeypatch.setattr(cli, "err_console", Console(file=err, width=200, color_system=None))
    monkeypatch.setattr(cli, "_interruption_said", False)
    try:
        with pytest.raises(SystemExit) as stop:
            cli.main()
    finally:
        signal.signal(signal.SIGINT, handler)  # main() leaves its handler for the interpreter's end
    assert stop.value.code == cli.EXIT_INTERRUPTED
    assert err.getvalue().splitlines() == ["error: interrupted"]
