"""The commands' words (issue 37, item 14): the help as click writes it (each docstring
paragraph wrapped to the terminal, no type on a flag, SCENARIO and [SCENARIO]... in the usage
line, the defaults of workspace's --duration and --step said); ``import`` creating the folder
of its --out as the other commands do, one line where a part of the path is a file; design
study files take integers where docs/design.md said floats only."""

import re
import shutil
from pathlib import Path

import pytest
from typer.testing import CliRunner

import marinecdpr
from marinecdpr.cli.app import app
from marinecdpr.studies.design import load_design

runner = CliRunner()
ROOT = Path(__file__).resolve().parents[2]
WIREX = ROOT / "tests" / "data" / "wirex" / "IPAnema.wcrfx"
COMMANDS = ["plan", "clean", "simulate", "workspace", "operability", "check", "rao", "windows", "control-study",
            "latency", "warmup", "design", "import", "scenarios"]


def _help(command: str) -> str:
    res = runner.invoke(app, [command, "--help"], prog_name="marinecdpr", env={"COLUMNS": "400"})
    assert res.exit_code == 0, res.output
    return res.stdout


@pytest.mark.parametrize("command", COMMANDS)
def test_no_flag_shows_a_type(command):
    text = _help(command)
    assert "--help" in text and "<bool>" not in text


@pytest.mark.parametrize("command, usage", [("check", "SCENARIO"), ("warmup", "[SCENARIO]..."),
                                            ("simulate", "[SCENARIO]"), ("import", "SOURCE")])
def test_the_usage_line_names_arguments_as_click_does(command, usage):
    line = next(x for x in _help(command).splitlines() if "Usage:" in x)
    assert line.split("Usage: ")[1].strip() == f"marinecdpr {command} [OPTIONS] {usage}"


def test_a_docstring_s_paragraphs_are_wrapped_to_the_terminal():
    text = _help("simulate")
    # one line on a wide terminal: the docstring's own breaks are gone
    assert re.search(r"Runs open loop, closed loop and the fixed-base plan on the moving ship; writes plan\.csv, "
                     r"sim_<run>\.csv, figures like the paper's 5-7, the path, summary\.json and report\.html\. Exits 5",
                     text), text


def test_workspace_says_its_defaults_for_duration_and_step():
    text = " ".join(_help("workspace").split())
    assert "Seconds of ship motion per pose (default: the scenario's time.duration_s)." in text
    assert "Time step, s (default: the scenario's time.step_s)." in text


def test_import_makes_the_folder_of_its_out(tmp_path):
    out = tmp_path / "new" / "deeper" / "ipanema.toml"
    res = runner.invoke(app, ["import", str(WIREX), "--out", str(out)])
    assert res.exit_code == 0, res.output
    sc = marinecdpr.load_scenario(out)
    assert sc.robot.n_cables == 8


@pytest.mark.parametrize("below", ["x.toml", "sub/x.toml"])
def test_import_through_a_file_is_one_line(tmp_path, below):
    (tmp_path / "a_file").write_text("mine")
    out = tmp_path / "a_file" / below
    res = runner.invoke(app, ["import", str(WIREX), "--out", str(out)], terminal_width=2000)
    assert res.exit_code == 2, res.output
    assert res.stderr.strip().splitlines() == [f"error: --out {out}: {tmp_path / 'a_file'} is a file, not a folder"]
    assert (tmp_path / "a_file").read_text() == "mine"


def test_a_design_study_takes_integers_as_its_doc_says(tmp_path):
    designs = Path(marinecdpr.__file__).parent / "data" / "designs"
    for name in ("ship_side_template.toml", "ship_side_rao.csv"):
        shutil.copy(designs / name, tmp_path / name)
    text = (designs / "ship_side.toml").read_text()
    for key, value in (("hours", "12"), ("base_kg", "5"), ("tension_min_N", "100")):
        text, n = re.subn(rf"^{key} = [0-9.]+", f"{key} = {value}", text, flags=re.M)
        assert n == 1, key
    (tmp_path / "ints.toml").write_text(text)
    study, _ = load_design(tmp_path / "ints.toml")
    reference, _ = load_design(designs / "ship_side.toml")
    assert study.model_dump() == reference.model_dump()
    doc = " ".join((ROOT / "docs" / "design.md").read_text().split())
    assert "not `12`" not in doc and "written as TOML integers or floats (`12` or `12.0`)" in doc


# -------------------- formerly tests/test_issue21_final_lines.py

"""Issue 21, item 12 (its words): a command's last line names the folder it wrote to, and
counts of one are singular ("written:" with no folder; "1 days")."""

from pathlib import Path
from types import SimpleNamespace

from typer.testing import CliRunner

from marinecdpr.cli.app import app

runner = CliRunner()


@pytest.mark.figures
def test_windows_names_its_folder_and_says_1_day(tmp_path):
    out = tmp_path / "o"
    res = runner.invoke(app, ["windows", "--duration-h", "6", "--hs-limit", "2.5", "--days", "1,3,0.5",
                              "--out", str(out)], terminal_width=2000)
    assert res.exit_code == 0, res.output
    line = res.output.strip().splitlines()[-1]
    assert "done within 1 day: " in line and ", 3 days: " in line and ", 0.5 days: " in line
    assert "1 days" not in line
    assert line.endswith(f"; written to {out}/: windows.csv, summary.json, windows.png"), line


def test_control_study_names_its_folder(tmp_path, monkeypatch):
    import marinecdpr.report.writers as writers
    import marinecdpr.studies.control as control

    monkeypatch.setattr(control, "control_study", lambda *a, **k: SimpleNamespace(runs=[], bypassed=[]))
    monkeypatch.setattr(control, "ship_prediction_error", lambda *a, **k: None)
    monkeypatch.setattr(writers, "write_control_study",
                        lambda result, prediction, folder, figures=True: (None, [Path(folder) / "control_study.csv"]))
    out = tmp_path / "o"
    res = runner.invoke(app, ["control-study", "paper_sea", "--latencies", "0", "--predictions", "none",
                              "--pose-from", "sensor", "--duration", "20", "--out", str(out)], terminal_width=2000)
    assert res.exit_code == 0, res.output
    assert res.output.strip().splitlines()[-1] == f"written to {out}/: control_study.csv"
