"""The workspace command's contract in the library (:mod:`marinecdpr.commands.workspace`):
its spec checked without the command line, the command line's defaults the spec's, and a
run from Python giving what the command writes (issue 38, item 1)."""

from __future__ import annotations

import csv

import numpy as np
import pytest
from typer.testing import CliRunner

import marinecdpr
from marinecdpr.cli.app import app
from marinecdpr.commands import SpecError
from marinecdpr.commands import workspace as command
from marinecdpr.commands.workspace import WorkspaceSpec
from command_pages import cli_default

runner = CliRunner()


@pytest.mark.parametrize("options, field, words", [
    ({"points": "0x3"}, "points", "points 0x3: expected two positive integers like 30x20"),
    ({"points": (4, -1)}, "points", "expected two positive integers"),
    ({"axes": "xx"}, "axes", "axes xx: expected two different letters of x, y, z"),
    ({"fixed": float("nan")}, "fixed", "fixed nan: expected a finite number"),
    ({"duration": -1.0}, "duration", "duration -1: expected a positive number"),
    ({"step": 0.0}, "step", "step 0: expected a positive number"),
    ({"pionts": "3x3"}, "pionts", "no such option of WorkspaceSpec"),
])
def test_a_bad_option_is_one_error_naming_its_field(options, field, words):
    with pytest.raises(SpecError) as err:
        WorkspaceSpec(**options)
    assert err.value.field == field and err.value.flag == "--" + field
    assert words in str(err.value) and "\n" not in str(err.value)


def test_the_spec_is_frozen_and_takes_a_grid_as_text_or_numbers():
    spec = WorkspaceSpec(points="12x8")
    assert spec.points == (12, 8) == WorkspaceSpec(points=[12, 8]).points
    with pytest.raises(Exception):
        spec.points = (3, 3)


def test_the_command_line_s_defaults_are_the_spec_s():
    """Every option of ``workspace`` but the scenario and --out has the spec's field and default."""
    import typer.main

    params = {p.name: p for p in typer.main.get_command(app).commands["workspace"].params}
    options = set(params) - {"scenario", "out"}
    assert options == set(WorkspaceSpec.model_fields)
    for name in options:
        default = cli_default(params[name])
        spec_default = WorkspaceSpec.default(name)
        assert (WorkspaceSpec(**{name: default}).model_dump()[name] if default is not None else None) == spec_default


def test_the_command_line_names_the_flag_of_a_bad_spec_field(tmp_path):
    res = runner.invoke(app, ["workspace", "paper", "--axes", "xq", "--out", str(tmp_path / "w")])
    assert res.exit_code == 2
    assert res.stderr.strip() == "error: --axes xq: expected two different letters of x, y, z"
    assert not (tmp_path / "w").exists()


def test_a_run_from_python_is_what_the_command_writes(tmp_path):
    """The estimate (the grid's poses times the steps), the run and its summary from Python,
    and the command's workspace.csv: the same feasible fractions, value for value."""
    sc = marinecdpr.load_scenario("paper")
    spec = WorkspaceSpec(points=(5, 4), duration=0.2)
    est = command.estimate(spec, sc)
    assert est.size.poses == 20 and est.size.n_steps == round(0.2 / sc.time.step_s) + 1
    assert est.describe().startswith("size: paper: ")
    result = command.run(spec, sc)
    s = result.summary()
    frac = result.map.fraction_feasible
    assert s["poses"] == int(np.isfinite(frac).sum()) and s["feasible_throughout"] == int((frac == 1.0).sum())
    res = runner.invoke(app, ["workspace", "paper", "--points", "5x4", "--duration", "0.2", "--out", str(tmp_path / "w")])
    assert res.exit_code == 0, res.output
    assert f"{s['feasible_throughout']} of {s['poses']} poses feasible throughout" in res.stdout
    with open(tmp_path / "w" / "workspace.csv") as fh:
        rows = list(csv.DictReader(fh))
    written = np.array([float(r["fraction_feasible"]) for r in rows]).reshape(frac.shape)
    np.testing.assert_array_equal(written, frac)


@pytest.mark.parametrize("command, extra", [(["operability", "paper_sea"], []),
                                            (["rao"], ["--length", "100", "--beam", "20", "--draught", "5", "--gm", "2",
                                                     "--omega", "0.2:1.8:3"])])
@pytest.mark.parametrize("given, words", [
    ("0,360", "a heading is given twice (headings are taken modulo 360 deg)"),
    ("90,450", "expected finite headings between -360 and 360 deg"),
    ("nan", "expected finite headings between -360 and 360 deg"),
])
def test_every_command_reads_headings_by_one_rule(tmp_path, command, extra, given, words):
    """``rao`` took 0 and 360 as one heading and 450 as 90, where ``operability`` and ``clean
    --seas`` refused both: one parse now (:func:`marinecdpr.commands.base.headings`)."""
    from conftest import one_line_exit_2

    res = runner.invoke(app, command + extra + ["--headings", given, "--out", str(tmp_path / "o")])
    one_line_exit_2(res, f"--headings {given}: {words}")
    assert not (tmp_path / "o").exists()


@pytest.mark.figures
def test_the_page_runs_as_written_and_lists_the_spec(tmp_path, monkeypatch):
    from command_pages import assert_table_is_the_spec, run_page

    assert_table_is_the_spec("workspace", WorkspaceSpec)
    ns = run_page("workspace", tmp_path, monkeypatch)
    frac = ns["result"].map.fraction_feasible
    assert frac.shape == (5, 3) and ns["held"] == int((frac == 1.0).sum())
    with open(tmp_path / "out" / "workspace.csv") as fh:
        written = [float(r["fraction_feasible"]) for r in csv.DictReader(fh)]
    np.testing.assert_array_equal(written, frac.ravel())
