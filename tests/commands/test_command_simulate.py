"""The simulate command's contract in the library (:mod:`marinecdpr.commands.simulate`): its
spec checked without the command line, the estimate's cut to ``duration`` and refusal, the
command line's defaults the spec's, a run from Python writing what the command writes, and
its page (issue 38)."""

from __future__ import annotations

import json

import numpy as np
import pytest
from typer.testing import CliRunner

import marinecdpr
from command_pages import assert_table_is_the_spec, cli_default, run_page
from marinecdpr.cli.app import app
from marinecdpr.commands import SpecError
from marinecdpr.commands import simulate as command
from marinecdpr.commands.simulate import SimulateSpec
from marinecdpr.errors import ScenarioError

runner = CliRunner()
RUNS = ("open_loop", "closed_loop", "fixed_base_open_loop")


@pytest.mark.parametrize("options, field, words", [
    ({"plant": "gazebo"}, "plant", "plant gazebo: expected mujoco or own"),
    ({"duration": -1.0}, "duration", "duration -1: expected a positive number"),
    ({"duration": 0.0}, "duration", "duration 0: expected a positive number"),
    ({"max_error": float("nan")}, "max_error", "max_error nan: expected a finite number"),
    ({"max_error": float("inf")}, "max_error", "max_error inf: expected a finite number"),
    ({"steps": 3}, "steps", "steps 3: no such option of SimulateSpec"),
])
def test_a_bad_option_is_one_error_naming_its_field(options, field, words):
    with pytest.raises(SpecError) as err:
        SimulateSpec(**options)
    assert err.value.field == field and err.value.flag == "--" + field.replace("_", "-")
    assert str(err.value) == words


def test_the_command_line_s_defaults_are_the_spec_s():
    """Every option of ``simulate`` but the scenario and --out is the spec's field with its default."""
    import typer.main

    params = {p.name: p for p in typer.main.get_command(app).commands["simulate"].params}
    assert set(params) - {"scenario", "out"} == set(SimulateSpec.model_fields)
    for name in SimulateSpec.model_fields:
        assert cli_default(params[name]) == SimulateSpec.default(name), name


def test_the_estimate_flies_the_first_seconds_and_says_when_the_scenario_is_shorter():
    sc = marinecdpr.load_scenario("paper")  # 15 s of 1 ms steps
    est = command.estimate(SimulateSpec(duration=2.0), sc)
    assert est.flown.time.duration_s == 2.0 and est.flown.time.n_steps == 2001 and est.warnings() == ()
    assert est.size.n_steps == 2001 and est.size.runs == 3
    assert est.describe().startswith("size: paper: 2,001 steps x 3 runs = 6,003 plan steps")
    long = command.estimate(SimulateSpec(duration=100.0), sc)
    assert long.flown.time.duration_s == 15.0 and long.cut == command.DurationCut(given=100.0, lasts=15.0)
    assert long.warnings() == ("--duration 100: paper lasts 15 s; flying those 15 s",)
    assert long.warnings("my/paper.toml") == ("--duration 100: my/paper.toml lasts 15 s; flying those 15 s",)
    whole = command.estimate(SimulateSpec(), sc)
    assert whole.flown is sc and whole.cut is None and whole.size.n_steps == 15001


def test_a_run_too_large_for_the_machine_is_refused_before_any_work():
    sc = marinecdpr.load_scenario("paper").with_changes(time={"step_s": 1e-4, "duration_s": 1e6})
    with pytest.raises(ScenarioError, match="would need about .* in memory") as err:
        command.estimate(SimulateSpec(), sc)
    assert err.value.key == "time.duration_s"
    flown = []
    with pytest.raises(ScenarioError, match="would need about"):
        command.run(SimulateSpec(), sc, progress=lambda *a: flown.append(a))
    assert flown == []


def test_a_run_from_python_writes_what_the_command_writes(tmp_path):
    """The first second of the paper scenario from Python and by the command: the same CSVs
    byte for byte, the same summary.json; the summary's errors are the CSV's own."""
    sc = marinecdpr.load_scenario("paper")
    seen: dict = {}
    result = command.run(SimulateSpec(duration=1.0), sc, progress=lambda run, done, total: seen.update({run: (done, total)}))
    assert seen == {run: (1001, 1001) for run in RUNS}
    assert result.scenario.time.n_steps == 1001 and result.plant == "mujoco" and result.bypassed() == []
    paths = result.write(tmp_path / "py")
    res = runner.invoke(app, ["simulate", "paper", "--duration", "1", "--out", str(tmp_path / "cli")])
    assert res.exit_code == 0, res.output
    assert ": " + ", ".join(p.name for p in paths) in " ".join(res.stdout.split())  # the command's list
    for name in ["plan.csv"] + [f"sim_{run}.csv" for run in RUNS]:
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), name
    s = result.summary()
    assert json.loads((tmp_path / "cli" / "summary.json").read_text()) == json.loads(json.dumps(s))
    for run in RUNS:
        sim = np.genfromtxt(tmp_path / "py" / f"sim_{run}.csv", delimiter=",", names=True)
        for q in ("x", "z"):  # the CSV's 10 significant digits of positions near 1 m
            assert s[run][f"max_abs_error_{q}_m"] == pytest.approx(np.abs(sim[q] - sim[f"{q}_plan"]).max(), abs=2e-10)
        tensions = np.column_stack([sim[f"T{i}"] for i in range(1, 5)])
        assert s[run]["tension_max_N"] == pytest.approx(tensions.max(), rel=1e-9)


def test_a_bypassed_controller_is_the_result_s_verdict():
    """400 Hz of bandwidth and a 10 mm initial error: the closed loop's controller is
    bypassed at every step (the command's exit 5), and only the closed loop has one."""
    sc = (marinecdpr.load_scenario("paper").with_updates("simulation.control", bandwidth_hz=400.0)
          .with_updates("simulation", initial_error_m=[0.01, 0.0, 0.0]))
    result = command.run(SimulateSpec(duration=0.2), sc)
    s = result.summary()
    assert result.bypassed() == [("closed_loop", s["closed_loop"]["controller_fallbacks"], 201)]
    assert s["closed_loop"]["controller_fallbacks"] > 0.01 * 201 and s["runs_controller_bypassed"] == ["closed_loop"]


@pytest.mark.figures
def test_the_page_runs_as_written_and_lists_the_spec(tmp_path, monkeypatch):
    assert_table_is_the_spec("simulate", SimulateSpec)
    ns = run_page("simulate", tmp_path, monkeypatch)
    closed, figures = ns["closed"], ns["figures"]
    summary = figures.to_json()
    assert closed.t.size == 1001 and figures.steps == 1001
    assert ns["error_mm"] == pytest.approx(1e3 * np.abs(closed.pose[:, 0] - closed.pose_planned[:, 0]).max(), rel=1e-12)
    assert json.loads((tmp_path / "out" / "summary.json").read_text()) == json.loads(json.dumps(summary))
    assert [p.name for p in ns["files"]][-2:] == ["summary.json", "report.html"]
    assert ns["said"] == ("--duration 100: paper lasts 15 s; flying those 15 s",)


def test_the_command_says_the_cut_before_it_refuses_a_run_too_large(tmp_path):
    """A --duration beyond a scenario too large to fly: the warning, then the refusal, as
    before the contract (the estimate raised before its warnings could be read)."""
    from marinecdpr.commands.simulate import duration_cut

    paper = marinecdpr.load_scenario("paper")
    scen = tmp_path / "long.toml"
    from pathlib import Path

    text = (Path(marinecdpr.__file__).parent / "scenario" / "builtin" / "paper.toml").read_text()
    scen.write_text(text.replace("duration_s = 15.0", "duration_s = 1e6").replace("step_s = 0.001", "step_s = 1e-4"))
    res = runner.invoke(app, ["simulate", str(scen), "--duration", "2e6", "--out", str(tmp_path / "o")])
    lines = [" ".join(ln.split()) for ln in res.stderr.strip().splitlines()]
    assert res.exit_code == 2 and len(lines) == 2, res.stderr
    assert lines[0] == f"warning: --duration 2e+06: {scen} lasts 1e+06 s; flying those 1e+06 s"
    assert lines[1].startswith(f"error: {scen}: time.duration_s: simulating 1e+10 steps")
    assert not (tmp_path / "o").exists()
    assert duration_cut(paper, 15.0) is None and duration_cut(paper, None) is None
    assert duration_cut(paper, 15.5) == command.DurationCut(given=15.5, lasts=15.0)


@pytest.mark.parametrize("args, words", [
    (["--plant", "gazebo"], "--plant gazebo: expected mujoco or own"),
    (["--duration", "-1"], "--duration -1: expected a positive number"),
    (["--max-error", "inf"], "--max-error inf: expected a finite number"),
])
def test_the_command_line_names_the_flag_of_a_bad_spec_field(tmp_path, args, words):
    from conftest import one_line_exit_2

    res = runner.invoke(app, ["simulate", "paper", *args, "--out", str(tmp_path / "o")])
    assert one_line_exit_2(res, words) == f"error: {words}"
    assert not (tmp_path / "o").exists()
