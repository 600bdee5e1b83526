"""Issue 21, item 11: the terminal shows text as written: rich markup ate bracketed words
("pip install 'marinecdpr[bench]'" lost its "[bench]"; rao's and clean's help lost "[bem]"
and "[cleaning]")."""

import inspect
import re

import pytest
import typer
from typer.testing import CliRunner

from marinecdpr.cli import app as cli
from marinecdpr.cli import common

runner = CliRunner()
BRACKETED = re.compile(r"\[[a-z][a-z_.]*\]")
COMMANDS = {(c.name or c.callback.__name__.replace("_", "-")): c for c in cli.app.registered_commands}


def _source_help(command) -> str:
    texts = [inspect.getdoc(command.callback) or ""]
    for parameter in inspect.signature(command.callback).parameters.values():
        if isinstance(parameter.default, typer.models.ParameterInfo) and parameter.default.help:
            texts.append(parameter.default.help)
    return "\n".join(texts)


def test_some_help_has_bracketed_words():
    assert {"rao", "clean"} <= {name for name, c in COMMANDS.items() if BRACKETED.search(_source_help(c))}


@pytest.mark.parametrize("name", sorted(COMMANDS))
def test_every_bracketed_word_of_a_commands_help_is_shown(name):
    res = runner.invoke(cli.app, [name, "--help"], terminal_width=2000)
    assert res.exit_code == 0, res.output
    shown = " ".join(res.output.replace("│", " ").split())
    for word in sorted(set(BRACKETED.findall(_source_help(COMMANDS[name])))):
        assert word in shown, (name, word)


def test_a_message_with_brackets_is_printed_as_written(monkeypatch):
    import marinecdpr.studies.latency as latency

    fake = latency.Latency(scenario="robot [v2]", method="closed_form", cables=8, redundancy=2, calls=10,
                           python_p50_us=1.0, python_p99_us=2.0, python_max_us=3.0, compiled_p50_us=0.5,
                           compiled_p99_us=0.6, compiled_max_us=0.7,
                           **{f: None for f in latency.Latency.__dataclass_fields__ if f.startswith("quadprog")})
    monkeypatch.setattr(latency, "controller_latency", lambda sc, calls: fake)
    res = runner.invoke(cli.app, ["latency", "paper", "--calls", "10"])
    assert res.exit_code == 0, res.output
    assert "  quadprog: quadprog not installed (pip install 'marinecdpr[bench]')" in res.output.splitlines()
    lines = [line for line in res.output.splitlines() if not line.startswith("compiling ")]  # a cold cache says so
    assert lines[0].startswith("robot [v2]: 8 cables")


def test_styled_prefixes_keep_the_message_literal(capsys):
    with pytest.raises(typer.Exit):
        common.fail("pip install 'marinecdpr[bem]' [bold]x[/bold] \\[y]")
    assert capsys.readouterr().err.strip() == "error: pip install 'marinecdpr[bem]' [bold]x[/bold] \\[y]"
