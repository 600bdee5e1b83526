"""The command line: outputs, exit codes, and one-line errors without tracebacks."""

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

import marinecdpr
from marinecdpr.cli.app import app

runner = CliRunner()


@pytest.mark.figures
def test_plan_writes_the_csv_and_figure(tmp_path, paper, paper_plan):
    res = runner.invoke(app, ["plan", "--out", str(tmp_path / "o")])
    assert res.exit_code == 0, res.output
    csv = tmp_path / "o" / "plan.csv"
    header = csv.read_text().splitlines()[0].split(",")
    assert header == (["t", "x", "z", "theta_y"] + [f"L{i}" for i in range(1, 5)]
                      + [f"Tpinv{i}" for i in range(1, 5)] + [f"T{i}" for i in range(1, 5)] + ["feasible"])
    data = np.loadtxt(csv, delimiter=",", skiprows=1)
    assert data.shape == (15001, 17)
    np.testing.assert_allclose(data[:, 4:8], paper_plan.lengths, rtol=1e-9)
    np.testing.assert_allclose(data[:, 12:16], paper_plan.tensions, rtol=1e-9)
    np.testing.assert_allclose(data[:, 1], 0.38 * np.cos(2 * np.pi * data[:, 0] / 15) + 0.6, atol=1e-9)
    assert (tmp_path / "o" / "tensions.png").read_bytes()[:4] == b"\x89PNG"
    assert [p.name for p in (tmp_path / "o").glob(".*")] == [".marinecdpr-files"]  # no temporary files left


def test_infeasible_plan_exits_3_with_complete_files(tmp_path):
    scen = tmp_path / "heavy.toml"
    text = (Path(marinecdpr.__file__).parent / "scenario" / "builtin" / "paper.toml").read_text()
    scen.write_text(text.replace("mass_kg = 5.0", "mass_kg = 200.0").replace("duration_s = 15.0", "duration_s = 0.5"))
    res = runner.invoke(app, ["plan", str(scen), "--out", str(tmp_path / "o")])
    assert res.exit_code == 3
    assert "cannot hold the platform" in res.stderr and "501 of 501 steps" in res.stderr
    rows = (tmp_path / "o" / "plan.csv").read_text().splitlines()
    assert len(rows) == 502 and rows[1].endswith(",,,,0")  # NaN tensions left empty
    ok = runner.invoke(app, ["plan", str(scen), "--out", str(tmp_path / "o"), "--allow-infeasible"])
    assert ok.exit_code == 0


def test_bad_scenario_is_one_line_exit_2(tmp_path):
    scen = tmp_path / "typo.toml"
    text = (Path(marinecdpr.__file__).parent / "scenario" / "builtin" / "paper.toml").read_text()
    scen.write_text(text.replace("mass_kg = 5.0", "mass = 5.0"))
    res = runner.invoke(app, ["plan", str(scen), "--out", str(tmp_path / "o")])
    assert res.exit_code == 2
    assert res.stderr.strip().splitlines() == [
        f"error: {scen}: robot.mass: unknown key; did you mean 'mass_kg'? (expected one of: dofs, "
        "mass_kg, inertia_kg_m2, tension_min_N, tension_max_N, breaking_load_N, cables, cable_weight_N_m, "
        "clearance_m, winch)"]
    assert not (tmp_path / "o").exists()


def test_bad_method_and_trajectory_outside_frame(tmp_path):
    res = runner.invoke(app, ["plan", "--method", "fastest", "--out", str(tmp_path)])
    assert res.exit_code == 2 and "--method fastest: expected one of" in res.stderr
    scen = tmp_path / "far.toml"
    text = (Path(marinecdpr.__file__).parent / "scenario" / "builtin" / "paper.toml").read_text()
    scen.write_text(text.replace("radius_m = 0.38", "radius_m = 0.9").replace("center_m = [0.6,", "center_m = [1.0,"))
    res = runner.invoke(app, ["plan", str(scen), "--out", str(tmp_path / "o")])
    assert res.exit_code == 2
    assert f"{scen}: trajectory: the platform leaves the frame at t = 0.000 s" in res.stderr


def test_check_and_scenarios_commands():
    res = runner.invoke(app, ["check", "paper"])
    assert res.exit_code == 0 and "planar robot, 4 cables, 5 kg" in res.stdout
    lines = runner.invoke(app, ["scenarios"]).stdout.splitlines()
    scenarios = [ln.split()[0] for ln in lines if ln.split()[0] != "built-in"]  # the studies' lines lead so
    assert scenarios == marinecdpr.builtin_scenarios()
    assert [ln.split()[3] for ln in lines if ln.startswith("built-in design study ")] == ["ship_side"]


def test_console_script_prints_no_traceback(tmp_path):
    """The installed command, as a user runs it: a missing file is one line, exit 2."""
    exe = Path(sys.executable).parent / "marinecdpr"
    proc = subprocess.run([str(exe), "plan", str(tmp_path / "missing.toml"), "--out", str(tmp_path)],
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 2
    assert "Traceback" not in proc.stderr and len(proc.stderr.strip().splitlines()) == 1
    assert "missing.toml: no such file" in proc.stderr


def test_check_says_ok_in_one_line_whatever_the_path_s_length(tmp_path):
    """A scenario in a deep folder (as pytest's and a user's paths are): check's verdict is one
    line (it was wrapped at the terminal's width, splitting ': ok: ' from its path)."""
    deep = tmp_path / ("a_long_folder_name_" * 4) / "paper.toml"
    deep.parent.mkdir(parents=True)
    deep.write_text((Path(marinecdpr.__file__).parent / "scenario" / "builtin" / "paper.toml").read_text())
    res = runner.invoke(app, ["check", str(deep)])
    assert res.exit_code == 0, res.output
    first = res.stdout.splitlines()[0]
    assert first.startswith(f"{deep}: ok: 'paper', planar robot, 4 cables, 5 kg; ") and first.endswith(
        "steps of 0.001 s; method minimum_variance"), res.stdout
