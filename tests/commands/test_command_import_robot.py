"""The import command's contract in the library (:mod:`marinecdpr.commands.import_robot`):
its spec, the toolkit told from the root element, the scenario file written as the command
writes it, the verdict on the written robot, and its page (issue 38)."""

from __future__ import annotations

from pathlib import Path

import pytest
from typer.testing import CliRunner

import marinecdpr
from command_pages import assert_table_is_the_spec, run_page
from marinecdpr.cli.app import app
from marinecdpr.commands import SpecError
from marinecdpr.commands import import_robot as command
from marinecdpr.commands.import_robot import ImportSpec
from marinecdpr.errors import ScenarioError

runner = CliRunner()
DATA = Path(__file__).resolve().parents[1] / "data"
IPANEMA_WIREX = DATA / "wirex" / "IPAnema.wcrfx"
SEGESTA_WIREX = DATA / "wirex" / "Segesta.wcrfx"
IPANEMA_CASPR = DATA / "caspr" / "IPAnema_1" / "IPAnema_1_bodies.xml"


@pytest.mark.parametrize("options, words", [
    ({"hold": "sometimes"}, "hold sometimes: "),
    ({"cable_set": 3}, "cable_set 3: "),
    ({"out": "x.toml"}, "out x.toml: no such option of ImportSpec"),
])
def test_a_bad_option_is_one_error_naming_its_field(options, words):
    with pytest.raises(SpecError) as err:
        ImportSpec(**options)
    field = next(iter(options))
    assert err.value.field == field and err.value.flag == "--" + field.replace("_", "-")
    assert str(err.value).startswith(words) and "\n" not in str(err.value)


def test_the_command_line_s_defaults_are_the_spec_s():
    import typer.main

    params = {p.name: p for p in typer.main.get_command(app).commands["import"].params}
    assert set(params) - {"source", "out"} == set(ImportSpec.model_fields)
    for name in ImportSpec.model_fields:
        assert params[name].default == ImportSpec.default(name), name


def test_the_scenario_file_must_be_a_toml_name_and_not_a_folder(tmp_path):
    for out, words in ((tmp_path / "o.txt", "expected a scenario file name ending in .toml"),
                       (tmp_path, None)):
        if words is None:
            (tmp_path / "d.toml").mkdir()
            out, words = tmp_path / "d.toml", "a folder; expected a scenario file name"
        with pytest.raises(SpecError) as err:
            command.check_out(out)
        assert str(err.value) == f"out {out}: {words}" and err.value.flag == "--out"
        res = runner.invoke(app, ["import", str(IPANEMA_WIREX), "--out", str(out)])
        assert res.exit_code == 2 and " ".join(res.stderr.split()) == f"error: --out {out}: {words}"


def test_the_estimate_tells_the_toolkits_apart_by_the_root_element(tmp_path):
    assert command.estimate(ImportSpec(), IPANEMA_WIREX).toolkit == "WireX"
    est = command.estimate(ImportSpec(), IPANEMA_CASPR)
    assert est.toolkit == "CASPR" and est.describe() == "import: a CASPR model, IPAnema_1_bodies.xml"
    (tmp_path / "x.xml").write_text("<robots/>")
    with pytest.raises(ScenarioError, match="root element is <robots>"):
        command.estimate(ImportSpec(), tmp_path / "x.xml")


def test_a_run_writes_what_the_command_writes(tmp_path):
    """A CASPR model held at q_initial: the same file byte for byte, and the summary the
    command's first line; a CASPR option on a WireX robot is the importer's one line."""
    spec = ImportSpec(hold=True)
    result = command.run(spec, IPANEMA_CASPR)
    written = result.write(tmp_path / "new" / "deeper" / "py.toml")  # its folders made
    assert written == [tmp_path / "new" / "deeper" / "py.toml"]
    res = runner.invoke(app, ["import", str(IPANEMA_CASPR), "--hold", "--out", str(tmp_path / "cli.toml")])
    assert res.exit_code == 0, res.output
    assert written[0].read_bytes() == (tmp_path / "cli.toml").read_bytes() == result.text.encode()
    s = result.summary()
    said = " ".join(res.stdout.split())
    assert f"'{s['name']}' from {s['toolkit']}, a {s['dofs']} robot with {s['cables']} cables, {s['mass_kg']:g} kg" in said
    assert all(f"note: {' '.join(n.split())}" in said for n in s["notes"]) and s["toolkit"] == "CASPR"
    sc = marinecdpr.load_scenario(written[0])
    assert sc.robot.n_cables == s["cables"] and sc.robot.mass_kg == s["mass_kg"]
    with pytest.raises(ScenarioError, match="--cable-set is for CASPR models"):
        command.run(ImportSpec(cable_set="x"), IPANEMA_WIREX)


def test_a_path_through_a_file_is_refused_and_leaves_no_folder(tmp_path):
    result = command.run(ImportSpec(), IPANEMA_WIREX)
    (tmp_path / "notes.txt").write_text("")
    with pytest.raises(SpecError) as err:
        result.write(tmp_path / "notes.txt" / "x.toml")
    assert err.value.detail == f"{tmp_path / 'notes.txt'} is a file, not a folder"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["notes.txt"]


def test_the_written_robot_s_verdict_is_planned_at_once(tmp_path):
    """WireX's Segesta carries a 25 kg platform it cannot hold; IPAnema holds it."""
    for source, holds in ((SEGESTA_WIREX, False), (IPANEMA_WIREX, True)):
        out = command.run(ImportSpec(), source).write(tmp_path / f"{source.stem}.toml")[0]
        checked = command.check_written(out)
        assert checked.scenario is not None and checked.scenario.robot.n_cables == 8
        assert (checked.problem is None) == holds
    assert "cannot hold the platform within their tension limits at 200 of 200 steps" in \
        command.check_written(tmp_path / "Segesta.toml").problem


def test_the_page_runs_as_written_and_lists_the_spec(tmp_path, monkeypatch):
    assert_table_is_the_spec("import", ImportSpec)
    ns = run_page("import", tmp_path, monkeypatch)
    assert ns["est"].toolkit == "WireX" and ns["summary"]["cables"] == 8 and ns["problem"] is None
    assert (tmp_path / "robots" / "ipanema.toml").read_text() == ns["result"].text
    assert ns["sc"].robot.mass_kg == ns["summary"]["mass_kg"] == 25.0
