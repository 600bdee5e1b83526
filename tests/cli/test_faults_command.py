"""``marinecdpr faults`` on the command line: every built-in scenario through it at a short
horizon (its files, its table's rows the summary's, each verdict a real one), and a bad
option or one the scenario cannot take as one line, exit 2, nothing written."""

from __future__ import annotations

import csv
import json

import pytest
from typer.testing import CliRunner

import marinecdpr
from marinecdpr.cli.app import app
from marinecdpr.report.files import MANIFEST

runner = CliRunner()
FILES = {"faults.csv", "summary.json", "faults.png", "report.html", MANIFEST}


@pytest.mark.figures
@pytest.mark.parametrize("name", sorted(marinecdpr.builtin_scenarios()))
def test_every_builtin_scenario_through_the_command(name, tmp_path):
    """Each built-in's cables 1 and 2 snapping at its hardest moments within its first 1.2 s,
    flown 0.5 s on: the four files; a CSV row per fault (2 cables x 1 or 2 moments), the same
    rows in summary.json, each snap detected (its load cell reads 0: slack_delay_s, 0.02 s) or
    the run lost, each verdict "safe" or a reason, and the report's table holding them."""
    out = tmp_path / "f"
    res = runner.invoke(app, ["faults", name, "--cables", "1,2", "--duration", "1.2", "--after", "0.5",
                              "--out", str(out)])
    assert res.exit_code == 0, res.output
    assert {p.name for p in out.iterdir()} == FILES
    rows = list(csv.DictReader((out / "faults.csv").open()))
    summary = json.loads((out / "summary.json").read_text())
    assert len(rows) == summary["faults"] == len(summary["rows"]) and len(rows) in (2, 4)
    assert summary["safe"] + summary["unsafe"] == len(rows)
    html = (out / "report.html").read_text()
    for row, kept in zip(rows, summary["rows"]):
        assert row["kind"] == kept["kind"] == "cable_snap" and int(row["cable"]) == kept["cable"]
        assert row["verdict"] == kept["verdict"] and row["verdict"] in html.replace("&#39;", "'")
        assert kept["verdict"] == "safe" or kept["verdict"].startswith(("leaves", "meets", "cable", "undetected",
                                                                         "neither", "the platform is lost"))
        if kept["detected"]:
            assert kept["detection_delay_s"] == pytest.approx(0.02, abs=1e-9)
            assert kept["detection"].startswith("cable_slack")
        assert 0.1 <= kept["at_s"] <= 0.7 + 1e-9


@pytest.mark.parametrize("args, line", [
    (["--cables", "5"], "error: --cables 5: the robot has 4 cables (1 to 4)"),
    (["--kinds", "snap,quake"], "error: --kinds quake: no such fault kind: expected snap, brake, power, load_cell, "
                                "encoder, mru, stall, brush, deadline"),
    (["--at", "100"], "error: --at 100: beyond the record: the job's 78 s less --after 3 s leaves faults up to 75 s"),
    (["--kinds", "brake"], "error: --kinds brake: a winch_brake needs a winch that pays out the cable"),
])
def test_a_bad_option_is_one_line_exit_2_nothing_written(args, line, tmp_path):
    out = tmp_path / "f"
    res = runner.invoke(app, ["faults", "paper_clean", *args, "--out", str(out)], terminal_width=2000)
    lines = res.stderr.strip().splitlines()
    assert res.exit_code == 2 and len(lines) == 1, res.stderr
    assert lines[0].startswith(line), lines[0]
    assert "Traceback" not in res.output and not out.exists()


def test_another_command_s_folder_is_refused(tmp_path):
    out = tmp_path / "p"
    assert runner.invoke(app, ["plan", "paper", "--out", str(out)]).exit_code == 0
    res = runner.invoke(app, ["faults", "paper_clean", "--duration", "1", "--after", "0.5", "--out", str(out)],
                        terminal_width=2000)
    assert res.exit_code == 2 and len(res.stderr.strip().splitlines()) == 1 and "plan" in res.stderr
    assert not (out / "faults.csv").exists()
