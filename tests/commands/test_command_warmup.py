"""The warmup command's contract in the library (:mod:`marinecdpr.commands.warmup`): its
spec, the runs its estimate lists being those it flies, the command line's defaults the
spec's, and its page (issue 38)."""

from __future__ import annotations

import pytest
from typer.testing import CliRunner

import marinecdpr
from command_pages import assert_table_is_the_spec, run_page
from marinecdpr.cli.app import app
from marinecdpr.commands import SpecError
from marinecdpr.commands import warmup as command
from marinecdpr.commands.warmup import WarmupSpec

runner = CliRunner()


@pytest.mark.parametrize("options, words", [
    ({"plant": "steam"}, "plant steam: expected mujoco or own"),
    ({"plants": "own"}, "plants own: no such option of WarmupSpec"),
])
def test_a_bad_option_is_one_error_naming_its_field(options, words):
    with pytest.raises(SpecError) as err:
        WarmupSpec(**options)
    assert str(err.value) == words and err.value.flag == "--" + next(iter(options))


def test_the_command_line_s_defaults_are_the_spec_s():
    import typer.main

    params = {p.name: p for p in typer.main.get_command(app).commands["warmup"].params}
    assert set(params) - {"scenarios_"} == set(WarmupSpec.model_fields)
    for name in WarmupSpec.model_fields:
        assert params[name].default == WarmupSpec.default(name), name


def test_the_estimate_lists_each_plant_s_runs_and_leaves_mujoco_out_for_catenary_cables():
    paper = marinecdpr.load_scenario("paper")  # MuJoCo
    sag = paper.with_changes(name="sag", simulation=paper.simulation.model_dump()
                             | {"plant": "own", "cables": {"model": "catenary", "stiffness_EA_N": 1e5}},
                             robot=paper.robot.model_dump() | {"cable_weight_N_m": 0.5})
    assert sag.simulation.cables.model == "catenary"
    est = command.estimate(WarmupSpec(), [paper, sag])
    assert est.scenarios == ("paper", "sag")
    assert est.runs == (("paper", "mujoco", "open_loop"), ("paper", "mujoco", "closed_loop"),
                        ("sag", "own", "open_loop"), ("sag", "own", "closed_loop"))
    mujoco = command.estimate(WarmupSpec(plant="mujoco"), [paper, sag])  # catenary: the own plant only
    assert mujoco.runs == est.runs[:2] and mujoco.describe() == "size: 2 scenarios: 2 runs of 3 steps"


def test_a_run_flies_what_the_estimate_lists_and_the_command_says_so():
    paper = marinecdpr.load_scenario("paper")
    spec = WarmupSpec(plant="mujoco")
    est = command.estimate(spec, [paper])
    told = []
    result = command.run(spec, [paper], progress=lambda done, total, what: told.append((done, total, what)))
    s = result.summary()
    assert tuple((r["scenario"], r["plant"], r["run"]) for r in s["runs"]) == est.runs
    assert told == [(0, 2, "paper: mujoco open loop"), (1, 2, "paper: mujoco closed loop"), (2, 2, "done")]
    assert s["seconds"] >= sum(r["seconds"] for r in s["runs"]) > 0
    res = runner.invoke(app, ["warmup", "paper", "--plant", "mujoco"])
    assert res.exit_code == 0, res.output
    assert "compiled for 1 scenario (2 runs) in " in res.stdout and s["cache_dir"] in "".join(res.stdout.split())


def test_the_page_runs_as_written_and_lists_the_spec(tmp_path, monkeypatch):
    assert_table_is_the_spec("warmup", WarmupSpec)
    ns = run_page("warmup", tmp_path, monkeypatch)
    assert ns["est"].describe() == "size: 1 scenario: 2 runs of 3 steps"
    assert ns["said"] == ["paper: mujoco open loop", "paper: mujoco closed loop", "done"]
    assert [r["run"] for r in ns["summary"]["runs"]] == ["open_loop", "closed_loop"]
