"""Issue 21's hostile-input sweep: the option parser's own errors (an integer given "abc", a
count below its minimum, an unknown option or command, a missing argument) are one
``error:`` line and exit 2, like every other bad input, not click's usage box; asking for
help still shows the help."""

from __future__ import annotations

import pytest
from typer.testing import CliRunner

from conftest import one_line_exit_2
from marinecdpr.cli.app import app

runner = CliRunner()


@pytest.mark.parametrize("argv,words", [
    (["operability", "--realisations", "0"], ["marinecdpr operability:", "'--realisations'", "greater than or equal to 1",
                                               "(see marinecdpr operability --help)"]),
    (["clean", "--workers", "0"], ["marinecdpr clean:", "'--workers'"]),
    (["operability", "--min-area", "2"], ["'--min-area'", "less than or equal to 1"]),
    (["latency", "--calls", "abc"], ["marinecdpr latency:", "'--calls'", "valid integer"]),
    (["plan", "--bogus"], ["marinecdpr plan:", "No such option: --bogus"]),
    (["bogus"], ["marinecdpr:", "No such command 'bogus' (see marinecdpr --help)"]),
    (["--bogus"], ["No such option: --bogus"]),
    (["check"], ["marinecdpr check:", "Missing argument 'scenario'"]),
])
def test_a_parser_error_is_one_line_exit_2(argv, words):
    res = runner.invoke(app, argv, prog_name="marinecdpr")
    line = one_line_exit_2(res, *words)
    assert "╭" not in res.output and "Usage:" not in res.stderr, line


def test_help_is_still_help():
    for argv in ([], ["--help"], ["plan", "--help"]):
        res = runner.invoke(app, argv, prog_name="marinecdpr")
        assert "Usage: marinecdpr" in res.stdout and "error:" not in res.stderr, argv
