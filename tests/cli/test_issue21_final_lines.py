"""Issue 21, item 12 (its words): a command's last line names the folder it wrote to, and
counts of one are singular ("written:" with no folder; "1 days")."""

from pathlib import Path
from types import SimpleNamespace

from typer.testing import CliRunner

from marinecdpr.cli.app import app

runner = CliRunner()


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
                        lambda result, prediction, folder: (None, [Path(folder) / "control_study.csv"]))
    out = tmp_path / "o"
    res = runner.invoke(app, ["control-study", "paper_sea", "--latencies", "0", "--predictions", "none",
                              "--pose-from", "sensor", "--duration", "20", "--out", str(out)], terminal_width=2000)
    assert res.exit_code == 0, res.output
    assert res.output.strip().splitlines()[-1] == f"written to {out}/: control_study.csv"
