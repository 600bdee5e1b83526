"""What a new user meets: every scenario and base motion through every command, runs that
leave their plan flagged, reports that compare with the paper only for the paper, output
folders that hold one complete run, file modes, figures and small things."""

from __future__ import annotations

import json
import os
import re
import shutil
import stat
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

import marinecdpr
from marinecdpr.studies.prototype_runs import error_bounds, is_paper_scenario, run_summary
from marinecdpr.motion.basemotion import evaluate_base_motion
from marinecdpr.cli.app import app
from marinecdpr.motion.recorded import write_motion_csv
from marinecdpr.report.figures import length_unit
from marinecdpr.report.files import MANIFEST, atomic_path
from marinecdpr.report.text import beyond_text, error_table
from marinecdpr.prototype.simulation import SimResult, simulate

from conftest import make_scenario, paper_dict

runner = CliRunner()
EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
MAIN_JOB_FILES = {"plan.csv", "sim_open_loop.csv", "sim_closed_loop.csv", "sim_fixed_base_open_loop.csv",
                  "tensions.png", "cable_lengths.png", "tracking.png", "path.png", "summary.json", "report.html"}


def _recorded_scenario(tmp_path: Path) -> Path:
    """The paper's scenario on a recorded copy of its own ship motion."""
    paper = marinecdpr.load_scenario("paper")
    t = np.arange(0.0, 20.0, 0.01)
    ship = evaluate_base_motion(paper.base_motion, t)
    write_motion_csv(tmp_path / "ship.csv", t, ship.eta)
    text = (EXAMPLES / "paper.toml").read_text()
    start, end = text.index("[base_motion]"), text.index("[trajectory]")
    path = tmp_path / "recorded.toml"
    path.write_text(text[:start] + '[base_motion]\ntype = "recorded"\nfile = "ship.csv"\n\n' + text[end:])
    return path


def _still_scenario(tmp_path: Path) -> Path:
    text = (EXAMPLES / "paper.toml").read_text()
    start, end = text.index("[base_motion]"), text.index("[trajectory]")
    path = tmp_path / "still.toml"
    path.write_text(text[:start] + '[base_motion]\ntype = "still"\n\n' + text[end:])
    return path


SCENARIOS = ["paper", "paper_elastic", "paper_sea", "paper_clean", "paper_as_built", "examples/spatial_cube8.toml", "recorded",
             "still", "examples/paper_rail.toml"]


def _source(name: str, tmp_path: Path) -> str:
    if name == "recorded":
        return str(_recorded_scenario(tmp_path))
    if name == "still":
        return str(_still_scenario(tmp_path))
    if name.startswith("examples/"):
        return str(EXAMPLES / name.split("/")[1])
    return name


def test_every_builtin_scenario_is_in_the_list():
    assert set(marinecdpr.builtin_scenarios()) <= set(SCENARIOS)


@pytest.mark.figures
@pytest.mark.parametrize("name", SCENARIOS)
def test_every_scenario_and_base_motion_through_every_command(name, tmp_path):
    """Item 1: simulate crashed on sea-state and recorded motion; every base-motion type
    (still, sinusoidal, sea_state, recorded) and every built-in runs every command."""
    src = _source(name, tmp_path)
    sc = marinecdpr.load_scenario(src)
    res = runner.invoke(app, ["check", src])
    assert res.exit_code == 0, res.output
    res = runner.invoke(app, ["plan", src, "--out", str(tmp_path / "plan")])
    assert res.exit_code == 0, res.output
    rows = np.genfromtxt(tmp_path / "plan" / "plan.csv", delimiter=",", names=True)
    assert rows.size == sc.time.n_steps and np.all(rows["feasible"] == 1)
    res = runner.invoke(app, ["simulate", src, "--duration", "0.3", "--out", str(tmp_path / "sim")])
    assert res.exit_code == 0, res.output
    assert {p.name for p in (tmp_path / "sim").iterdir()} == MAIN_JOB_FILES | {MANIFEST}
    s = json.loads((tmp_path / "sim" / "summary.json").read_text())
    assert s["steps"] == 301 and s["closed_loop"]["within_error_bound"]
    html = (tmp_path / "sim" / "report.html").read_text()
    assert sc.base_motion.type.replace("_", " ") in html
    axes = "xz" if sc.robot.dofs == "planar" else "xy"
    res = runner.invoke(app, ["workspace", src, "--axes", axes, "--points", "3x2", "--duration", "0.2",
                              "--step", "0.1", "--out", str(tmp_path / "ws")])
    assert res.exit_code == 0, res.output
    assert np.genfromtxt(tmp_path / "ws" / "workspace.csv", delimiter=",", names=True).size == 6
    # three sea states of two records each (the package's diagram of 102 with ten records is
    # a study's, not a run's: 170x the cells here)
    scatter = tmp_path / "scatter.csv"
    scatter.write_text("hs_m,tp_s,probability\n0.5,6.0,0.5\n1.0,8.0,0.3\n2.0,10.0,0.2\n")
    res = runner.invoke(app, ["operability", src, "--serial", "--duration", "2", "--step", "0.1", "--scatter",
                              str(scatter), "--realisations", "2", "--out", str(tmp_path / "op")])
    if sc.base_motion.type == "sea_state":
        assert res.exit_code == 0, res.output
        assert json.loads((tmp_path / "op" / "operability.json").read_text())["cells"] == 3
    else:
        assert res.exit_code == 2 and "needs a [base_motion] of type sea_state" in res.stderr
        assert "Traceback" not in res.output
    res = runner.invoke(app, ["latency", src, "--calls", "20", "--json"])
    assert res.exit_code == 0, res.output
    assert json.loads(res.stdout)["cables"] == sc.robot.n_cables
    # every prediction and pose source once (paper's); each other scenario's controller in one run:
    # each combination compiles the loop anew for a scenario's parts (some 20 s each on a cold cache)
    options = (["--predictions", "none,ar", "--pose-from", "sensor,encoders"] if name == "paper"
               else ["--predictions", "none", "--pose-from", "sensor"])
    res = runner.invoke(app, ["control-study", src, "--latencies", "20", *options, "--duration", "0.4", "--settle",
                              "0.1", "--out", str(tmp_path / "cs")])
    assert res.exit_code == 0, res.output
    assert len(json.loads((tmp_path / "cs" / "summary.json").read_text())["runs"]) == (4 if name == "paper" else 1)
    res = runner.invoke(app, ["clean", src, "--duration", "0.5", "--out", str(tmp_path / "clean")])
    if sc.cleaning is not None:
        assert res.exit_code == 0, res.output
        assert {p.name for p in (tmp_path / "clean").iterdir()} == {
            "clean.csv", "coverage.png", "cleaning.png", "summary.json", "report.html", MANIFEST}
    else:
        assert res.exit_code == 2 and "no cleaning job" in res.stderr and len(res.stderr.strip().splitlines()) == 1


# ---------------------------------------------------------------- item 2: tumbling
@pytest.fixture(scope="module")
def cube8_runs(tmp_path_factory):
    out = tmp_path_factory.mktemp("cube8")
    res = runner.invoke(app, ["simulate", str(EXAMPLES / "spatial_cube8.toml"), "--duration", "2.0",
                              "--out", str(out)])
    return res, out


def test_an_open_loop_that_tumbles_is_flagged_everywhere(cube8_runs):
    res, out = cube8_runs
    assert res.exit_code == 0, res.output
    s = json.loads((out / "summary.json").read_text())
    # the frame is a 2 m cube: the default bound is 1% of it
    assert s["error_bound_m"] == pytest.approx(0.02) and s["error_bound_deg"] == 1.0
    assert s["open_loop"]["max_abs_error_rz_deg"] > 90.0          # it turns over about z
    assert not s["open_loop"]["within_error_bound"] and "rz" in s["open_loop"]["beyond_error_bound"]
    assert s["closed_loop"]["within_error_bound"] and s["closed_loop"]["max_abs_error_x_m"] < 1e-5
    assert s["runs_beyond_error_bound"] == ["open_loop", "fixed_base_open_loop"]
    assert "warning: open_loop leaves its plan beyond the error bound" in res.stderr
    html = (out / "report.html").read_text()
    assert "exact but for" not in html and "follows the plan but for" not in html
    assert "Open loop leaves its plan" in html and "<b>NO: x, y, z, rx, ry, rz, cables 1-8</b>" in html
    # why: held tensions make yaw an inverted pendulum (issue 14); the rate is the one the
    # prototype's tumbling shows (tests/model/test_stiffness.py), the report says so
    st = s["stability"]
    assert s["open_loop_growth_rate_1_s"] == st["open_loop_growth_rate_1_s"] > 20.0
    assert st["verdict"] == "unstable" and st["mode"][0] == "rz" and st["winches"] == "tension"
    assert "The open loop is unstable" in html and "a mode in rz" in html


def test_the_papers_open_loop_is_neutral(tmp_path):
    res = runner.invoke(app, ["simulate", "--duration", "1", "--out", str(tmp_path)])
    assert res.exit_code == 0, res.output
    st = json.loads((tmp_path / "summary.json").read_text())["stability"]
    assert st["verdict"] == "neutral" and abs(st["open_loop_growth_rate_1_s"]) < 1e-3
    assert st["e_folding_time_s"] is None


def test_the_error_bound_comes_from_the_frame_the_scenario_or_the_option(paper, tmp_path):
    assert error_bounds(paper) == pytest.approx((0.019, 1.0))  # 1% of the 1.9 m frame
    tight = paper.with_changes(simulation={"max_error_m": 0.002, "max_error_deg": 0.1})
    assert error_bounds(tight) == (0.002, 0.1)
    assert error_bounds(tight, 0.5) == (0.5, 0.1)
    res = runner.invoke(app, ["simulate", "--duration", "0.3", "--max-error", "1e-9", "--out", str(tmp_path)])
    assert res.exit_code == 0, res.output
    s = json.loads((tmp_path / "summary.json").read_text())
    assert s["error_bound_m"] == 1e-9 and s["runs_beyond_error_bound"] == [
        "open_loop", "closed_loop", "fixed_base_open_loop"]
    assert "warning: closed_loop leaves its plan beyond the error bound" in res.stderr


@pytest.fixture(scope="module")
def paper_run(tmp_path_factory):
    """``simulate`` of the paper scenario (the default) for 0.3 s, made once: its result and
    its folder, which the tests read, or copy as the previous run in a folder of their own."""
    out = tmp_path_factory.mktemp("paper_run") / "out"
    res = runner.invoke(app, ["simulate", "--duration", "0.3", "--out", str(out)])
    assert res.exit_code == 0, res.output
    return res, out


def test_paper_open_loop_is_called_exact_only_because_its_numbers_are(paper_run):
    res, out = paper_run
    html = (out / "report.html").read_text()
    s = json.loads((out / "summary.json").read_text())
    assert s["open_loop"]["max_abs_error_x_m"] < 1e-6
    assert "follows the plan but for the hold" in html and "within the bound" in html
    assert "warning" not in res.stderr


# -------------------------------------------------- item 3: the paper only for the paper
def test_the_paper_column_only_for_the_papers_experiment(cube8_runs, paper_run):
    assert is_paper_scenario(marinecdpr.load_scenario("paper"))
    assert is_paper_scenario(marinecdpr.load_scenario("paper_elastic"))   # other cables, same experiment
    assert not is_paper_scenario(marinecdpr.load_scenario("paper_sea"))  # another sea
    res, out = cube8_runs
    s = json.loads((out / "summary.json").read_text())
    html = (out / "report.html").read_text()
    assert "paper_reported" not in s and "Adams" not in html and "Adams" not in res.stdout
    # every controlled DOF of the spatial robot has its row, and the rotation angle is named
    for row in ("x (", "y (", "z (", "rx (deg)", "ry (deg)", "rz (deg)", "rotation angle (deg)"):
        assert f"<th>{row}" in html, row
    res, out = paper_run
    s = json.loads((out / "summary.json").read_text())
    assert s["scenario"] == "paper" and s["paper_reported"]["max_abs_cable_length_error_m"] == 0.15
    assert "max_cable_length_error_m" not in s["paper_reported"]  # one name for one quantity
    assert "paper (Adams, open loop)" in (out / "report.html").read_text()
    assert "theta_y (deg)" in res.stdout and "paper (Adams" in res.stdout


def test_error_table_uses_one_unit_per_row(paper):
    s = {"error_bound_m": 0.019, "error_bound_deg": 1.0,
         "paper_reported": {"max_abs_error_x_m": 0.025, "max_abs_error_z_m": 0.013,
                            "max_abs_error_theta_deg": 0.48, "max_abs_cable_length_error_m": 0.15}}
    for run, e in (("open_loop", 1.4e-7), ("closed_loop", 1.1e-6), ("fixed_base_open_loop", 0.033)):
        s[run] = {"max_abs_error_x_m": e, "max_abs_error_z_m": e / 10, "max_abs_error_theta_deg": 7e-6,
                  "max_abs_cable_length_error_m": [e, 2 * e, e, e], "within_error_bound": e < 0.019,
                  "beyond_error_bound": [] if e < 0.019 else ["x", "cable 2"]}
    from marinecdpr.studies.prototype_runs import PrototypeFigures

    for run in ("open_loop", "closed_loop", "fixed_base_open_loop"):
        s[run] |= {"tension_min_N": 10.0, "tension_max_N": 20.0, "tension_limit_excess_N": 0.0, "rms_error_x_m": 0.0,
                   "rms_error_z_m": 0.0, "controller_fallbacks": 0, "ship_tracking_error": 0.0, "plant": "own"}
    s |= {"scenario": "paper", "steps": 100, "step_s": 0.001, "method": "closed_form", "pinv_tension_min_N": 1.0,
          "opt_tension_min_N": 10.0, "opt_tension_max_N": 20.0, "controller_bypassed_share_max": 0.05,
          "open_loop_growth_rate_1_s": 0.0, "stability": None, "error_budget": {}, "runs_beyond_error_bound": [],
          "runs_controller_bypassed": [], "warnings": []}
    header, rows = error_table(PrototypeFigures.from_json(s), paper)
    assert header[1] == "paper (Adams, open loop)"
    assert rows[0] == ["x (mm)", "25", "0.00014", "0.0011", "33"]
    assert rows[1] == ["z (mm)", "13", "1.4e-05", "0.00011", "3.3"]
    assert rows[3] == ["cable length (mm)", "150", "0.00028", "0.0022", "66"]
    assert rows[4][-1] == "NO: x, cable 2" and rows[4][2] == "yes"
    assert length_unit(3.3e-8) == (1e-9, "nm") and length_unit(0.0) == (1e-9, "nm")
    assert length_unit(2.5e-4) == (1e-6, "µm") and length_unit(1.2) == (1.0, "m")
    assert beyond_text(["x", "cable 1", "cable 2", "cable 3", "cable 5"]) == "x, cables 1-3, 5"


# ------------------------------------------------------------- item 4: output folders
def _main_job(tmp_path, scenario="paper", duration="0.2"):
    return runner.invoke(app, ["simulate", scenario, "--duration", duration, "--out", str(tmp_path)])


def test_a_failed_run_leaves_the_previous_run_whole(tmp_path, monkeypatch, paper_run):
    out = tmp_path / "out"
    shutil.copytree(paper_run[1], out)  # the previous run
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    # a crash while writing the report (a full disk, say): one line, exit 2, nothing changed
    import marinecdpr.report.writers as writers

    def full(*args, **kwargs):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(writers, "write_report_html", full)
    res = _main_job(out, "paper_sea")
    assert res.exit_code == 2 and "Traceback" not in res.output
    lines = res.stderr.strip().splitlines()
    assert lines[-1] == f"error: --out {out}: could not write the files (No space left on device); the folder keeps what it held"
    assert all(ln.startswith("simulate: ") for ln in lines[:-1])  # the progress lines before it
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before


def test_an_interrupted_run_leaves_the_previous_run_whole(tmp_path, monkeypatch, paper_run):
    out = tmp_path / "out"
    shutil.copytree(paper_run[1], out)  # the previous run
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    import marinecdpr.studies.prototype_runs as analysis

    calls = []

    def interrupted(*args, **kwargs):
        calls.append(1)
        if len(calls) == 2:
            raise KeyboardInterrupt
        return simulate(*args, **kwargs)

    monkeypatch.setattr(analysis, "simulate", interrupted)
    res = _main_job(out, "paper_sea")
    assert res.exit_code == 130 and len(calls) == 2
    assert res.stderr.strip().splitlines()[-1] == f"error: interrupted; --out {out} keeps what it held"
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before
    assert json.loads((out / "summary.json").read_text())["scenario"] == "paper"


@pytest.mark.figures
def test_a_new_run_replaces_every_file_of_the_previous_one_and_nothing_else(tmp_path, paper_run):
    out = tmp_path / "out"
    shutil.copytree(paper_run[1], out)  # the previous run, beside a file of the user's
    (out / "notes.txt").write_text("mine")
    main_job = {p.name: p.read_bytes() for p in out.iterdir()}
    # another command into the main job's folder is refused, its files kept (issue 37, item 5: the
    # plan's files replaced the main job's, the report gone without a word)
    res = runner.invoke(app, ["plan", "paper_sea", "--out", str(out)])
    assert res.exit_code == 2, res.output
    assert "holds the results of 'simulate'" in res.stderr
    assert {p.name: p.read_bytes() for p in out.iterdir()} == main_job
    assert (out / "notes.txt").read_text() == "mine"
    # the same command replaces every file of its previous run: no report of one scenario beside
    # another's CSVs
    assert _main_job(out, "paper_sea").exit_code == 0
    assert {p.name for p in out.iterdir()} == set(main_job)
    s = json.loads((out / "summary.json").read_text())
    assert s["scenario"] == "paper_sea" and "paper_sea" in (out / "report.html").read_text()


@pytest.mark.parametrize("command", [["simulate"], ["plan"], ["workspace", "--points", "2x2"],
                                     ["operability", "paper_sea", "--serial"]])
def test_an_output_folder_that_cannot_be_written_fails_before_the_work(command, tmp_path, monkeypatch):
    from marinecdpr.planning import planner
    from marinecdpr.studies import operability, prototype_runs, workspace

    def no_work(*args, **kwargs):
        raise AssertionError("the work started")

    for module, name in ((prototype_runs, "virtual_prototype"), (planner, "plan"),
                         (workspace, "workspace_map"), (operability, "operability")):
        monkeypatch.setattr(module, name, no_work)
    blocker = tmp_path / "a_file"
    blocker.write_text("")
    res = runner.invoke(app, command + ["--out", str(blocker / "out")])
    assert res.exit_code == 2, res.output
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"error: --out {blocker / 'out'}: cannot write there")
    res = runner.invoke(app, command + ["--out", str(blocker)])
    assert res.exit_code == 2 and "exists and is not a folder" in res.stderr


# ---------------------------------------------------------------- item 5: file modes
@pytest.mark.figures
def test_output_files_honour_the_umask(tmp_path):
    old = os.umask(0o022)
    try:
        assert runner.invoke(app, ["plan", "--out", str(tmp_path / "o")]).exit_code == 0
        with atomic_path(tmp_path / "x.txt") as tmp:
            tmp.write_text("x")
    finally:
        os.umask(old)
    for p in [tmp_path / "o" / "plan.csv", tmp_path / "o" / "tensions.png", tmp_path / "x.txt"]:
        assert stat.S_IMODE(p.stat().st_mode) == 0o644, p


# ------------------------------------------------------------------- item 6: figures
def test_error_panels_are_log_scaled_in_units_from_the_data(paper, captured_figures, tmp_path):
    from marinecdpr.report.figures import plot_tracking

    runs = {run: simulate(paper, run=run, n_steps=400) for run in ("open_loop", "closed_loop",
                                                                    "fixed_base_open_loop")}
    figs = captured_figures
    plot_tracking(runs, paper, tmp_path / "tracking.png")
    axes = figs["tracking.png"].axes
    x_err = axes[1]
    assert x_err.get_yscale() == "log"
    largest = max(np.abs(r.pose_error[:, 0]).max() for r in runs.values())
    size, unit = length_unit(largest)
    assert x_err.get_ylabel() == f"|x error| ({unit})" and 1.0 <= largest / size < 1000.0
    # each run is drawn, the open loop under the closed loop with a wider line
    lines = {ln.get_label(): ln for ln in axes[0].get_lines()}
    assert lines["open loop (plan fed forward)"].get_linewidth() > 2 * lines[
        "closed loop (computed torque)"].get_linewidth()
    np.testing.assert_allclose(x_err.get_lines()[1].get_ydata(),  # open loop: the 2nd drawn
                               np.where(np.abs(runs["open_loop"].pose_error[:, 0]) > 0,
                                        np.abs(runs["open_loop"].pose_error[:, 0]) / size, np.nan))


def test_tension_figure_names_infeasible_steps_in_its_legend(captured_figures, tmp_path):
    from marinecdpr.report.figures import plot_tensions

    heavy = make_scenario(lambda d: (d["robot"].update(mass_kg=20.0), d["time"].update(duration_s=4.0)))
    p = marinecdpr.plan(heavy)
    assert 0 < p.feasible.sum() < p.n_steps
    figs = captured_figures
    plot_tensions(p, heavy, tmp_path / "tensions.png")
    labels = [t.get_text() for t in figs["tensions.png"].legends[0].get_texts()]
    assert "infeasible steps" in labels and "cable 1" in labels


def test_a_rounding_excess_is_not_a_tension_outside_its_limits(paper):
    n = 5
    T = np.full((n, 4), 100.0)
    pose = np.zeros((n, 6))
    res = SimResult("open_loop", "own", np.arange(n) * 1e-3, pose, pose, np.ones((n, 4)), np.ones((n, 4)), T, T,
                    0, 0.0)
    T[2, 1] = 450.0 + 7e-15 * 450
    assert run_summary(res, paper)["tension_limit_excess_N"] == 0.0
    T[2, 1] = 450.2
    assert run_summary(res, paper)["tension_limit_excess_N"] == pytest.approx(0.2)


# --------------------------------------------------------------- item 9: small things
def test_version_and_scenario_descriptions():
    res = runner.invoke(app, ["--version"])
    assert res.exit_code == 0 and res.stdout.strip() == f"marinecdpr {marinecdpr.__version__}"
    lines = runner.invoke(app, ["scenarios"]).stdout.strip().splitlines()
    lines = [ln for ln in lines if not ln.startswith("built-in design study ")]  # the built-in studies follow
    assert [ln.split()[0] for ln in lines] == marinecdpr.builtin_scenarios()
    for ln in lines:
        name = ln.split()[0]
        assert ln[len(name):].strip() == marinecdpr.load_scenario(name).description


def test_the_title_says_wall_time_and_progress_shows_when_piped(paper_run):
    res, _ = paper_run
    assert re.search(r"\d+\.\d s wall time\)", res.stdout)
    # not a terminal: plain progress lines, the last of each run saying it is done
    for title in ("open loop (plan fed forward)", "closed loop (computed torque)", "fixed-base plan, open loop"):
        assert re.search(rf"{re.escape(title)}: 301 of 301 steps in ", res.stderr), res.stderr


def test_leaving_the_frame_prints_enough_digits(tmp_path):
    data = paper_dict()
    data["trajectory"] = {"type": "line", "start_position_m": [1.9 - 0.125 + 1.2e-6, 0.0, 0.7],
                          "end_position_m": [0.95, 0.0, 0.7], "duration_s": 1.0}
    data["time"]["duration_s"] = 2.0
    from marinecdpr.errors import ScenarioError
    from marinecdpr.scenario.loading import scenario_from_dict

    with pytest.raises(ScenarioError, match=r"x = 1\.900001 m, outside the frame anchors' range \[0\.0, 1\.9\] m"):
        marinecdpr.plan(scenario_from_dict(data))


def test_a_load_fixed_to_the_platform_turns_with_its_actual_orientation():
    """A platform held 8 deg off its plan by a slow controller, with 50 N pushing along its own
    z axis: the controller knows the load turns with the platform, so the platform stays where
    it is. Turned with the planned orientation instead, the load would push it 7 N sideways
    (1.7 mm in 50 ms)."""
    def edit(d):
        d["base_motion"] = {"type": "still"}
        d["trajectory"] = {"type": "line", "start_position_m": [0.95, 0.0, 0.7],
                           "end_position_m": [0.95, 0.0, 0.7], "duration_s": 1.0}
        d["time"] = {"step_s": 0.001, "duration_s": 0.05}
        d["simulation"] = {"initial_error_deg": [0.0, 8.0, 0.0], "control": {"bandwidth_hz": 0.01}}
        d["disturbance"] = {"frame": "P", "force_N": [0.0, 0.0, 50.0]}

    sc = make_scenario(edit)
    for plant in ("own", "mujoco"):
        r = simulate(sc, run="closed_loop", plant=plant)
        assert r.controller_fallbacks == 0
        assert np.abs(r.pose_error[:, :3]).max() < 1e-8, plant


# -------------------- formerly tests/test_first_scenario.py

"""Writing a first scenario: a robot drawn in millimetres is flagged, an infeasible plan names the
cables at their limits (checked against statics worked out here), and long commands show their
progress when piped."""


import re
import tomllib
from dataclasses import replace
from importlib import resources

import numpy as np
from scipy.optimize import linprog
from typer.testing import CliRunner

import marinecdpr
import marinecdpr.cli.progress
from marinecdpr.cli.app import app
from marinecdpr.scenario.loading import scenario_from_dict

from conftest import make_scenario, paper_dict

runner = CliRunner()


def millimetre_toml() -> str:
    """The paper scenario with every length written in millimetres (a 1.9 km frame), 21 steps."""
    text = (resources.files("marinecdpr.scenario") / "builtin" / "paper.toml").read_text()

    def mm(match: re.Match) -> str:
        return match[1] + "[" + ", ".join(f"{1000 * float(v):.1f}" for v in match[2].split(",")) + "]"

    text = re.sub(r"((?:frame_anchor_m|platform_anchor_m|center_m|frame_origin_m)\s*=\s*)\[([^\]]*)\]",
                  mm, text)
    for old, new in (("radius_m = 0.38", "radius_m = 380.0"), ("step_s = 0.001", "step_s = 0.05"),
                     ("duration_s = 15.0", "duration_s = 1.0")):
        assert old in text
        text = text.replace(old, new)
    return text


def millimetre_dict() -> dict:
    return tomllib.loads(millimetre_toml())


def test_scale_warnings_flag_millimetres_not_metres():
    from marinecdpr.scenario.scale import scale_warnings

    mm = scenario_from_dict(millimetre_dict())
    assert scale_warnings(mm) == [
        "robot size far outside cable-robot scale: the frame anchors span 1900 m (more than 200 m); "
        "the platform anchors span 300 m (more than 50 m); "
        "coordinates look like millimetres: scenario lengths are in metres (divide by 1000)"]
    assert scale_warnings(marinecdpr.load_scenario("paper")) == []
    # a metre frame with its platform anchors in millimetres: the platform is the culprit
    d = paper_dict()
    for cable in d["robot"]["cables"]:
        cable["platform_anchor_m"] = [1000.0 * v for v in cable["platform_anchor_m"]]
    (line,) = scale_warnings(scenario_from_dict(d))
    assert "the platform (300 m) is larger than the frame (1.9 m)" in line
    assert line.endswith("the platform anchors look like millimetres: platform_anchor_m is in metres")


def test_check_warns_on_stderr_and_still_exits_0(tmp_path):
    scen = tmp_path / "mm.toml"
    scen.write_text(millimetre_toml())
    res = runner.invoke(app, ["check", str(scen)])
    assert res.exit_code == 0, res.output
    assert "ok: 'paper', planar robot, 4 cables" in " ".join(res.stdout.split())  # stdout wraps at 80
    assert res.stderr.strip().splitlines() == [
        f"warning: {scen}: robot size far outside cable-robot scale: the frame anchors span 1900 m (more "
        "than 200 m); the platform anchors span 300 m (more than 50 m); coordinates look like millimetres: "
        "scenario lengths are in metres (divide by 1000)"]
    # other commands warn when they load it too; a metre scenario gives no warning
    ws = runner.invoke(app, ["workspace", str(scen), "--points", "2x2", "--out", str(tmp_path / "o")])
    assert ws.exit_code == 0 and "coordinates look like millimetres" in ws.stderr
    ok = runner.invoke(app, ["check", "paper"])
    assert ok.exit_code == 0 and "warning" not in ok.stderr


def heavy_still_paper():
    """The paper robot carrying 200 kg on a still ship: statics alone decides feasibility."""
    return make_scenario(lambda d: (d["robot"].update(mass_kg=200.0),
                                    d.update(base_motion={"type": "still"},
                                             time={"step_s": 0.05, "duration_s": 1.0})))


def test_infeasible_plan_names_the_cables_at_their_limits():
    sc = heavy_still_paper()
    p = marinecdpr.plan(sc)
    msg = p.infeasibility()
    # planar: the controlled DOFs only, the angle named as in plan.csv
    assert "21 of 21 steps, first at t = 0 s (x = 0.98 m, z = 0.7 m, theta_y = 0 deg)" in msg
    assert not re.search(r"\b(y|rx|ry|rz) =", msg)

    # Statics at t = 0, worked out here: the platform sits at (0.98, 0.7) level, its anchors at
    # x + p_i; the cables pull along u_i = (c_i - x - p_i) / |...|. On a still ship the circle's
    # acceleration at t = 0 is -r w^2 along x, so the cables must supply
    # w = (m a_x, m g) in (x, z) and no moment about y.
    r = sc.robot
    x = np.array([0.98, 0.0, 0.7])
    lever = r.platform_anchors
    l = r.frame_anchors - (x + lever)
    u = l / np.linalg.norm(l, axis=1, keepdims=True)
    m_y = np.cross(lever, u)[:, 1]
    omega = 2 * np.pi / 15.0
    w = np.array([-200.0 * 0.38 * omega**2, 200.0 * 9.8, 0.0])
    # the most upward pull within limits (a linear programme): the top cables 1, 2 at T_max and
    # the bottom cables 3, 4 at T_min, and still short of the weight
    up = linprog(-u[:, 2], bounds=list(zip(r.tension_min, r.tension_max)), method="highs")
    np.testing.assert_allclose(up.x, [450.0, 450.0, 10.0, 10.0])
    assert -up.fun < 200.0 * 9.8 - 1400.0
    # these tensions are also the least-squares optimum (KKT: moving any cable off its limit
    # only makes the missing wrench larger), so the message reports this shortfall
    A = np.vstack([u[:, 0], u[:, 2], m_y])
    missing = w - A @ up.x
    grad = A.T @ (A @ up.x - w)
    assert (grad[:2] < 0).all() and (grad[2:] > 0).all()
    force, moment = np.linalg.norm(missing[:2]), abs(missing[2])
    assert (
        f": at best, cables 3, 4 at T_min = 10 N and cables 1, 2 at T_max = 450 N still leave "
        f"{force:.4g} N of force (along +z) and {moment:.4g} N m of moment "
        f"(about {'+' if missing[2] > 0 else '-'}y) short; ") in msg
    assert f"{force:.4g}" == "1472"
    # and what the cables can give along z with the x force and the moment held, worked out
    # here by its own linear programmes, against the weight: the force is short, so the hint
    # is the force's
    span = [sign * linprog(sign * u[:, 2], A_eq=np.vstack([u[:, 0], m_y]), b_eq=[w[0], 0.0],
                           bounds=list(zip(r.tension_min, r.tension_max)), method="highs").fun
            for sign in (1.0, -1.0)]
    assert msg.endswith(
        f"short; with the rest of the wrench held the cables give {span[0]:.4g} to {span[1]:.4g} N along z there, "
        f"against {w[1]:.4g} N needed: raise robot.tension_max_N, or move the frame anchors so that more cables "
        "pull that way (robot.cables frame_anchor_m)")

    # a plan that does not know its robot still gives the controlled DOFs, without the cause
    bare = replace(p, robot=None).infeasibility()
    assert bare.endswith("(x = 0.98 m, z = 0.7 m, theta_y = 0 deg)")


def test_infeasible_messages_for_a_method_that_misses_and_a_spatial_robot():
    sc = make_scenario(lambda d: d.update(time={"step_s": 0.05, "duration_s": 1.0}))
    msg = marinecdpr.plan(sc, method="pseudo_inverse").infeasibility()
    assert msg.endswith("(x = 0.98 m, z = 0.7 m, theta_y = 0 deg): tensions within the limits exist "
                        "there, but the pseudo inverse method did not find them: the minimum variance method does "
                        "(planning.method = \"minimum_variance\", or --method minimum_variance)")
    assert marinecdpr.plan(sc, method="minimum_variance").feasible.all()  # as it says
    cube = marinecdpr.load_scenario("examples/spatial_cube8.toml")
    heavy = cube.with_changes(robot=cube.robot.model_dump(exclude_none=True) | {"mass_kg": 150.0},
                              time={"step_s": 0.05, "duration_s": 0.1})
    msg = marinecdpr.plan(heavy).infeasibility()
    # spatial: all six DOFs; the four lower cables pull down (at T_min), the four upper ones
    # up (at T_max): 4 * 450 N * u_z (1 / sqrt 3 at the centre, minus the platform's offsets)
    # is far below the 1470 N weight
    assert "(x = 1 m, y = 1 m, z = 1 m, rx = 0 deg, ry = 0 deg, rz = 0 deg): at best, cables 1, 2, 3, 4 " \
           "at T_min = 10 N and cables 5, 6, 7, 8 at T_max = 450 N still leave" in msg
    assert re.search(r"still leave \d+(\.\d+)? N of force \(along \+z\) short; with the rest of the wrench held "
                     r"the cables give -?\d+(\.\d+)? to \d+(\.\d+)? N along z there, against \d+ N needed: raise "
                     r"robot.tension_max_N", msg)


def test_piped_workspace_prints_progress_lines(tmp_path, monkeypatch):
    args = ["workspace", "paper", "--duration", "1", "--step", "0.05", "--points", "8x6",
            "--out", str(tmp_path)]
    res = runner.invoke(app, args)
    assert res.exit_code == 0, res.output
    # a short job: a line at once that it has started, and a closing line, with its speed
    first, last = [line for line in res.stderr.splitlines() if line.startswith("workspace:")]
    assert first == "workspace: 0 of 48 poses, started"
    assert re.fullmatch(r"workspace: 48 of 48 poses in \d+\.\d s \([\d,.]+ poses/s( after the first \d+, which "
                        r"took \d+\.\d s with the start-up)?\)", last)
    # without the minimum interval: a line at every tenth of the grid, then the closing line
    monkeypatch.setattr(marinecdpr.cli.progress, "PROGRESS_LINE_MIN_S", 0.0)
    res = runner.invoke(app, args)
    lines = res.stderr.strip().splitlines()
    assert lines.pop(0).startswith("size: paper: 48 poses (8 x 6) x 21 steps")  # before the work
    assert lines.pop(0) == "workspace: 0 of 48 poses, started"
    done = [int(re.match(r"workspace: (\d+) of 48 poses \(\d+%\), \d+\.\d s(, about \d+\.\d s left)?$", line)[1])
            for line in lines[:-1]]
    assert done == [5, 10, 15, 20, 24, 29, 34, 39, 44]
    assert lines[0].startswith("workspace: 5 of 48 poses (10%), ")
    assert lines[-1].startswith("workspace: 48 of 48 poses in ")
