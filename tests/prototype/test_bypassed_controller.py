"""Issue 21, item 22: a closed loop whose controller was bypassed (its feedback's tensions
outside the limits, the plan's fed forward instead) on more than a small share of its
steps is a failed run: exit code 5, a verdict in summary.json and the report, in every
command that flies a closed loop."""

from __future__ import annotations

import json
import tomllib
from importlib import resources
from pathlib import Path

import pytest
from typer.testing import CliRunner

from marinecdpr.cli.app import app

EXIT_BYPASSED = 5  # README "Exit codes"
from marinecdpr.scenario.loading import scenario_from_dict

runner = CliRunner()


def _toml(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, list):
        return "[" + ", ".join(_toml(v) for v in value) + "]"
    return repr(value)


def _dump(data: dict, prefix: str = "") -> str:
    """A nested dict as TOML (the scenarios' subset: tables, arrays of tables, scalars, lists)."""
    lines, tables = [], []
    for key, value in data.items():
        if isinstance(value, dict):
            tables.append((key, value))
        elif isinstance(value, list) and value and isinstance(value[0], dict):
            for item in value:
                tables.append((f"[{key}]", item))
        else:
            lines.append(f"{key} = {_toml(value)}")
    out = "\n".join(lines) + "\n"
    for key, value in tables:
        if key.startswith("["):
            name = f"{prefix}{key[1:-1]}"
            out += f"\n[[{name}]]\n" + _dump(value, name + ".")
        else:
            name = f"{prefix}{key}"
            out += f"\n[{name}]\n" + _dump(value, name + ".")
    return out


def _builtin(name: str) -> dict:
    folder = resources.files("marinecdpr.scenario") / "builtin"
    data = tomllib.loads((folder / f"{name}.toml").read_text())
    rao = data.get("base_motion", {}).get("rao")
    if rao is not None and "file" in rao:  # the copy is read from elsewhere
        rao["file"] = str(folder / rao["file"])
    return data


def _scenario_file(tmp_path: Path, case: str, base: str = "paper", **simulation) -> Path:
    """The built-in ``base`` on the own plant with one of the issue's two bypassed closed loops
    (``"bandwidth"``: 400 Hz with a 10 mm initial error; ``"noise"``: 1e4 N of load-cell noise
    on elastic cables and tension-controlled winches), or ``"normal"``."""
    data = _builtin(base)
    sim = data.setdefault("simulation", {})
    sim["plant"] = "own"
    if case == "bandwidth":
        sim.setdefault("control", {})["bandwidth_hz"] = 400.0
        sim["initial_error_m"] = [0.01, 0.0, 0.0]
    elif case == "noise":
        sim["cables"] = {"model": "elastic", "stiffness_EA_N": 1e5, "winch": "tension"}
        sim.setdefault("noise", {})["tension_N"] = 1e4
        # such a load cell is a faulty sensor: the controller's watch would detect it (the
        # encoders jump with the winches' wild tensions at step 1) and brake; the loop without it
        sim.setdefault("control", {})["safety"] = {"detect": False}
    sim.update(simulation)
    path = tmp_path / f"{base}_{case}.toml"
    path.write_text(_dump(data), encoding="utf-8")
    scenario_from_dict(tomllib.loads(path.read_text()), source=str(path))  # it is valid
    return path


@pytest.mark.parametrize("case", ["bandwidth", "noise"])
def test_simulate_fails_when_the_controller_was_bypassed(tmp_path, case):
    scenario = _scenario_file(tmp_path, case)
    out = tmp_path / "out"
    res = runner.invoke(app, ["simulate", str(scenario), "--duration", "0.2", "--out", str(out)])
    assert res.exit_code == EXIT_BYPASSED, res.output
    # the files are written, complete, and say so
    s = json.loads((out / "summary.json").read_text())
    c = s["closed_loop"]
    assert c["controller_verdict"] == "bypassed"
    assert c["controller_fallbacks"] >= 199 and s["steps"] == 201
    assert c["controller_bypassed_share"] == pytest.approx(c["controller_fallbacks"] / 201)
    assert s["controller_bypassed_share_max"] == 0.01
    assert s["runs_controller_bypassed"] == ["closed_loop"]
    for run in ("open_loop", "fixed_base_open_loop"):  # no controller to bypass
        assert "controller_verdict" not in s[run]
    html = (out / "report.html").read_text()
    assert "the controller was bypassed at" in html and "BYPASSED" in html
    # one line on stderr naming the run, the share and the key, no traceback
    lines = [ln for ln in res.stderr.splitlines() if ln.startswith("error:")]
    assert len(lines) == 1 and "Traceback" not in res.output
    assert "closed_loop" in lines[0] and "simulation.max_bypassed_share" in lines[0]
    assert f"{c['controller_fallbacks']} of 201 steps" in lines[0]


def test_a_normal_closed_loop_passes_with_no_bypassed_steps(tmp_path):
    scenario = _scenario_file(tmp_path, "normal")
    out = tmp_path / "out"
    res = runner.invoke(app, ["simulate", str(scenario), "--duration", "0.2", "--out", str(out)])
    assert res.exit_code == 0, res.output
    s = json.loads((out / "summary.json").read_text())
    assert s["closed_loop"]["controller_fallbacks"] == 0
    assert s["closed_loop"]["controller_bypassed_share"] == 0.0
    assert s["closed_loop"]["controller_verdict"] == "held"
    assert s["runs_controller_bypassed"] == []
    assert "BYPASSED" not in (out / "report.html").read_text()


def test_the_share_is_configurable(tmp_path):
    # a threshold of 1 (every step may be bypassed) lets the same run pass, flagged held
    scenario = _scenario_file(tmp_path, "bandwidth", max_bypassed_share=1.0)
    out = tmp_path / "out"
    res = runner.invoke(app, ["simulate", str(scenario), "--duration", "0.2", "--out", str(out)])
    assert res.exit_code == 0, res.output
    s = json.loads((out / "summary.json").read_text())
    assert s["closed_loop"]["controller_verdict"] == "held" and s["closed_loop"]["controller_fallbacks"] > 190


def test_the_share_is_a_number_between_0_and_1(tmp_path):
    from marinecdpr.errors import ScenarioError

    data = _builtin("paper")
    data["simulation"]["max_bypassed_share"] = 1.5
    with pytest.raises(ScenarioError, match=r"simulation\.max_bypassed_share.*between 0 and 1"):
        scenario_from_dict(data, source="test")


def test_clean_fails_when_the_controller_was_bypassed(tmp_path):
    scenario = _scenario_file(tmp_path, "bandwidth", base="paper_clean")
    out = tmp_path / "out"
    res = runner.invoke(app, ["clean", str(scenario), "--duration", "0.2", "--no-compare", "--out", str(out)])
    assert res.exit_code == EXIT_BYPASSED, res.output
    s = json.loads((out / "summary.json").read_text())
    assert s["controller_verdict"] == "bypassed" and s["controller_bypassed_share"] > 0.99
    assert s["controller_bypassed_share_max"] == 0.01
    assert "the controller was bypassed at" in (out / "report.html").read_text()
    lines = [ln for ln in res.stderr.splitlines() if ln.startswith("error:")]
    assert len(lines) == 1 and "simulation.max_bypassed_share" in lines[0]


def test_clean_passes_with_a_held_controller(tmp_path):
    scenario = _scenario_file(tmp_path, "normal", base="paper_clean")
    out = tmp_path / "out"
    res = runner.invoke(app, ["clean", str(scenario), "--duration", "0.2", "--no-compare", "--out", str(out)])
    assert res.exit_code == 0, res.output
    s = json.loads((out / "summary.json").read_text())
    assert s["controller_fallbacks"] == 0 and s["controller_verdict"] == "held"


def test_clean_fails_when_a_compared_run_was_bypassed(tmp_path):
    # calm water and no brush drag fly the same controller: a bypassed one fails the command too
    scenario = _scenario_file(tmp_path, "bandwidth", base="paper_clean")
    out = tmp_path / "out"
    res = runner.invoke(app, ["clean", str(scenario), "--duration", "0.2", "--out", str(out)])
    assert res.exit_code == EXIT_BYPASSED, res.output
    s = json.loads((out / "summary.json").read_text())
    assert set(s["comparison"]) == {"as asked", "calm water", "no brush drag"}
    assert min(v["controller_bypassed_share"] for v in s["comparison"].values()) > 0.99
    (line,) = [ln for ln in res.stderr.splitlines() if ln.startswith("error:")]
    assert line.startswith("error: the cleaning job (and 2 more runs): the controller was bypassed at")


def test_control_study_fails_when_a_run_was_bypassed(tmp_path):
    scenario = _scenario_file(tmp_path, "bandwidth", base="paper_sea")
    out = tmp_path / "out"
    res = runner.invoke(app, ["control-study", str(scenario), "--latencies", "0", "--predictions", "none",
                              "--pose-from", "sensor", "--duration", "0.2", "--settle", "0", "--out", str(out)])
    assert res.exit_code == EXIT_BYPASSED, res.output
    s = json.loads((out / "summary.json").read_text())
    (run,) = s["runs"]
    assert run["controller_verdict"] == "bypassed" and run["bypassed_share"] > 0.99
    assert s["controller_bypassed_share_max"] == 0.01
    assert "controller_verdict" in (out / "control_study.csv").read_text().splitlines()[0]
    assert "BYPASSED" in res.stdout
    lines = [ln for ln in res.stderr.splitlines() if ln.startswith("error:")]
    assert len(lines) == 1 and "simulation.max_bypassed_share" in lines[0]


def test_control_study_passes_with_held_runs(tmp_path):
    scenario = _scenario_file(tmp_path, "normal", base="paper_sea")
    out = tmp_path / "out"
    res = runner.invoke(app, ["control-study", str(scenario), "--latencies", "0", "--predictions", "none",
                              "--pose-from", "sensor", "--duration", "0.2", "--settle", "0", "--out", str(out)])
    assert res.exit_code == 0, res.output
    (run,) = json.loads((out / "summary.json").read_text())["runs"]
    assert run["fallbacks"] == 0 and run["controller_verdict"] == "held"


def test_operability_with_max_error_counts_a_bypassed_controller_as_a_failure():
    from marinecdpr.studies.operability import Cell, evaluate_cell

    def sea(case: str):
        data = _builtin("paper_sea")
        if case == "bandwidth":
            data["simulation"].setdefault("control", {})["bandwidth_hz"] = 400.0
            data["simulation"]["initial_error_m"] = [0.01, 0.0, 0.0]
        return scenario_from_dict(data, source="test")

    cell = Cell(0, 1.0, 8.0, 180.0, 1.0)
    kwargs = dict(margin_N=0.0, duration_s=0.2, step_s=0.001, max_error_m=1.0)
    held = evaluate_cell(sea("normal"), cell, **kwargs)
    assert held.operable and held.controller_bypassed == 0
    bypassed = evaluate_cell(sea("bandwidth"), cell, **kwargs)
    # its error is within 1 m, but the controller never ran: not workable
    assert bypassed.max_error_m < 1.0
    assert not bypassed.operable and bypassed.successes == 0 and bypassed.controller_bypassed == 1


def test_operability_cli_counts_and_says_the_bypassed_records(tmp_path):
    scenario = _scenario_file(tmp_path, "bandwidth", base="paper_sea")
    scatter = tmp_path / "scatter.csv"
    scatter.write_text("hs_m,tp_s,probability\n1.0,8.0,1.0\n", encoding="utf-8")
    out = tmp_path / "out"
    res = runner.invoke(app, ["operability", str(scenario), "--scatter", str(scatter), "--duration", "0.2",
                              "--step", "0.001", "--realisations", "2", "--max-error", "1", "--serial",
                              "--out", str(out)])
    assert res.exit_code == 0, res.output  # a study: the sea state fails, the command does not
    header, row = (out / "operability.csv").read_text().splitlines()[:2]
    cells = dict(zip(header.split(","), row.split(",")))
    assert cells["controller_bypassed"] == "2" and cells["successes"] == "0" and cells["operable"] == "0"
    assert json.loads((out / "operability.json").read_text())["realisations_controller_bypassed"] == 2
    assert "in 2 records the closed loop's controller was bypassed" in res.stderr
