"""The check command's contract in the library (:mod:`marinecdpr.commands.check`): no option
but the scenario, the plan's size refused, the checks agreeing with what a plan meets, and its
page (issue 38)."""

from __future__ import annotations

from pathlib import Path

import pytest
from typer.testing import CliRunner

import marinecdpr
from command_pages import assert_table_is_the_spec, run_page
from marinecdpr.cli.app import app
from marinecdpr.commands import SpecError
from marinecdpr.commands import check as command
from marinecdpr.commands import plan
from marinecdpr.commands.check import CheckSpec
from marinecdpr.errors import ScenarioError

runner = CliRunner()
PAPER = Path(marinecdpr.__file__).parent / "scenario" / "builtin" / "paper.toml"


def test_check_takes_no_option_but_the_scenario():
    import typer.main

    with pytest.raises(SpecError) as err:
        CheckSpec(duration=1.0)
    assert str(err.value) == "duration 1: no such option of CheckSpec" and err.value.flag == "--duration"
    params = {p.name for p in typer.main.get_command(app).commands["check"].params}
    assert params - {"scenario"} == set(CheckSpec.model_fields) == set()


def test_a_scenario_too_long_to_plan_fails_its_check():
    sc = marinecdpr.load_scenario("paper").with_changes(time={"step_s": 1e-4, "duration_s": 1e6})
    with pytest.raises(ScenarioError, match="more than the 1,000,000,000 steps") as err:
        command.run(CheckSpec(), sc)
    assert err.value.key == "time.duration_s"


def test_a_trajectory_leaving_the_frame_is_the_command_s_line(tmp_path):
    scen = tmp_path / "far.toml"
    scen.write_text(PAPER.read_text().replace("radius_m = 0.38", "radius_m = 0.9")
                    .replace("center_m = [0.6,", "center_m = [1.0,"))
    with pytest.raises(ScenarioError) as err:
        command.run(CheckSpec(), marinecdpr.load_scenario(scen))
    assert str(err.value).startswith("trajectory: the platform leaves the frame at t = 0.000 s: platform anchor 2")
    res = runner.invoke(app, ["check", str(scen)])  # the command names the scenario given
    assert res.exit_code == 2 and " ".join(res.stderr.split()) == f"error: {scen}: {err.value}"


def test_the_checks_find_what_the_plan_meets(tmp_path):
    """A cable that passes within ``clearance_m`` of a bollard: the check (no dynamics solved)
    names the first step as the plan does, and counts the singular steps as it does."""
    text = PAPER.read_text().replace("tension_max_N = 450.0", "tension_max_N = 450.0\nclearance_m = 0.05", 1)
    scen = tmp_path / "bollard.toml"
    scen.write_text(text.replace("duration_s = 15.0", "duration_s = 0.5") + """
[[obstacles]]
type = "box"
name = "bollard"
center_m = [1.5, 0.0, 1.2]
size_m = [0.1, 0.3, 0.1]
""")
    sc = marinecdpr.load_scenario(scen)
    result = command.run(CheckSpec(), sc)
    planned = plan.run(plan.PlanSpec(), sc, tmp_path / "p")
    assert result.interference is not None and result.interference == planned.interference()
    assert "('bollard', a box)" in result.interference
    assert (result.along.n_poses, result.along.n_singular) == (planned.summary()["steps"], planned.summary()["singular"])
    s = result.summary()
    assert (s["steps"], s["cables"], s["interference"]) == (501, 4, result.interference)
    res = runner.invoke(app, ["check", str(scen)])
    assert res.exit_code == 0 and f"warning: {scen}: {result.interference}" in " ".join(res.stderr.split())


def test_a_coverage_path_cut_short_by_the_scenario_says_so():
    """paper_clean's path (77.77 s) fits its 78 s; cut to 30 s it does not."""
    sc = marinecdpr.load_scenario("paper_clean")
    whole = command.run(CheckSpec(), sc)
    assert not whole.path_cut and whole.path.duration_s == pytest.approx(77.7667, abs=1e-4)
    short = command.run(CheckSpec(), sc.with_changes(time={"step_s": sc.time.step_s, "duration_s": 30.0}))
    assert short.path_cut and short.summary()["coverage"]["cut"] and short.summary()["steps"] == 30001
    assert command.run(CheckSpec(), marinecdpr.load_scenario("paper")).path is None


def test_the_page_runs_as_written_and_lists_the_spec(tmp_path, monkeypatch):
    assert_table_is_the_spec("check", CheckSpec)
    ns = run_page("check", tmp_path, monkeypatch)
    s = ns["summary"]
    assert (s["name"], s["cables"], s["steps"], ns["lanes"]) == ("paper_clean", 4, 78001, 5)
    assert s["coverage"]["lanes"] == 5 and ns["result"].along.n_singular == 0
    assert ns["said"][0] == "time.duration_s" and "use a shorter duration_s" in ns["said"][1]
    assert list(tmp_path.iterdir()) == []  # writes no file
