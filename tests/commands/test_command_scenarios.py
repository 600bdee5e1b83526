"""The scenarios command's contract in the library (:mod:`marinecdpr.commands.scenarios`):
the list is the loader's, each description the scenario's own, as the command prints them,
and its page (issue 38)."""

from __future__ import annotations

import pytest
from typer.testing import CliRunner

import marinecdpr
from command_pages import assert_table_is_the_spec, run_page
from marinecdpr.cli.app import app
from marinecdpr.commands import SpecError
from marinecdpr.commands import scenarios as command
from marinecdpr.commands.scenarios import ScenariosSpec

runner = CliRunner()


def test_the_list_is_the_built_ins_with_their_own_descriptions_as_the_command_prints_them():
    import typer.main

    with pytest.raises(SpecError, match="no such option of ScenariosSpec"):
        ScenariosSpec(verbose=True)
    assert {p.name for p in typer.main.get_command(app).commands["scenarios"].params} == set(ScenariosSpec.model_fields)
    result = command.run(ScenariosSpec())
    assert [n for n, _ in result.scenarios] == marinecdpr.builtin_scenarios()
    for name, description in result.scenarios:
        assert description == marinecdpr.load_scenario(name).description
    assert [n for n, _ in result.studies] == ["ship_side"]
    out = runner.invoke(app, ["scenarios"], terminal_width=10000).stdout.splitlines()
    width = max(len(n) for n, _ in result.scenarios)
    assert out == ([f"{n:<{width}}  {d}" for n, d in result.scenarios]
                   + [f"built-in design study {n} (marinecdpr design {n}): {d}" for n, d in result.studies])


def test_the_page_runs_as_written_and_lists_the_spec(tmp_path, monkeypatch):
    assert_table_is_the_spec("scenarios", ScenariosSpec)
    ns = run_page("scenarios", tmp_path, monkeypatch)
    assert ns["names"][0] == "paper" and ns["studies"] == ["ship_side"]
    assert ns["about_paper"] == marinecdpr.load_scenario("paper").description
