"""Issue 21, item 6: a run's progress counts the runs it flies, and a --duration beyond the
scenario is said, not silently cut."""

from pathlib import Path
from types import SimpleNamespace

from typer.testing import CliRunner

import marinecdpr.cli.app as cli

runner = CliRunner()


def test_a_duration_beyond_the_scenario_is_one_warning_line(capsys):
    sc = cli._scenario_to_fly("paper", 100.0, "virtual_prototype")
    assert sc.time.duration_s == 15.0
    assert capsys.readouterr().err.strip().splitlines() == [
        "warning: --duration 100: paper lasts 15 s; flying those 15 s"]
    sc = cli._scenario_to_fly("paper", 2.0, "virtual_prototype")
    assert sc.time.duration_s == 2.0 and capsys.readouterr().err == ""


def test_clean_with_a_guarantee_met_at_once_ends_its_progress_on_the_runs_flown(tmp_path, monkeypatch):
    import marinecdpr.report.cleaning as report
    import marinecdpr.studies.cleaning as cleaning

    def guaranteed_job(sc, plant=None, progress=None):  # met by the first run: no second one
        n = sc.time.n_steps
        for k in (n // 2, n):
            progress(k, n)
        return SimpleNamespace(summary={"guarantee": {"reason": "met", "lane_spacing_m": 0.1, "checked": True,
                                                      "second_run": False},
                                        "controller_verdict": "held", "controller_fallbacks": 0, "steps": n})

    monkeypatch.setattr(cleaning, "guaranteed_job", guaranteed_job)
    monkeypatch.setattr(report, "write_cleaning", lambda job, folder: [Path(folder) / "clean.csv"])
    monkeypatch.setattr(report, "cleaning_findings", lambda summary: [])
    monkeypatch.setattr(cli, "_compile_notice", lambda plant: None)
    res = runner.invoke(cli.app, ["clean", "--guarantee", "--no-compare", "--duration", "1", "--out",
                                  str(tmp_path / "o")], terminal_width=2000)
    assert res.exit_code == 0, res.output
    last = [ln for ln in res.stderr.splitlines() if ln.startswith("clean: ")][-1]
    n = cli.load_scenario("paper_clean").time.step_s
    steps = round(1.0 / n) + 1
    assert last.startswith(f"clean: {steps} of {steps} steps in "), last
