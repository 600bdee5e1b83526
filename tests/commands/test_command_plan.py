"""The plan command's contract in the library (:mod:`marinecdpr.commands.plan`): its spec
checked without the command line, its estimate's refusal, the command line's defaults the
spec's, a run from Python writing what the command writes, and its page (issue 38)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

import marinecdpr
from command_pages import assert_table_is_the_spec, cli_default, run_page
from marinecdpr.cli.app import app
from marinecdpr.commands import SpecError
from marinecdpr.commands import plan as command
from marinecdpr.commands.plan import PlanSpec
from marinecdpr.errors import ScenarioError

runner = CliRunner()
PAPER = Path(marinecdpr.__file__).parent / "scenario" / "builtin" / "paper.toml"


def short_paper(tmp_path: Path, seconds: float = 1.0, mass_kg: float = 5.0) -> Path:
    """The paper scenario's first ``seconds``, as a file (with the platform's ``mass_kg``)."""
    path = tmp_path / "short.toml"
    path.write_text(PAPER.read_text().replace("duration_s = 15.0", f"duration_s = {seconds}")
                    .replace("mass_kg = 5.0", f"mass_kg = {mass_kg}"))
    return path


@pytest.mark.parametrize("options, field, words", [
    ({"method": "fastest"}, "method", "method fastest: expected one of pseudo_inverse, minimum_variance, "
                                      "closed_form, improved_closed_form, minimum_norm"),
    ({"fixed_base": "sometimes"}, "fixed_base", "fixed_base sometimes: "),
    ({"allow_infeasible": 3}, "allow_infeasible", "allow_infeasible 3: "),
    ({"methd": "closed_form"}, "methd", "methd closed_form: no such option of PlanSpec"),
])
def test_a_bad_option_is_one_error_naming_its_field(options, field, words):
    with pytest.raises(SpecError) as err:
        PlanSpec(**options)
    assert err.value.field == field and err.value.flag == "--" + field.replace("_", "-")
    assert str(err.value).startswith(words) and "\n" not in str(err.value)


def test_the_command_line_s_defaults_are_the_spec_s():
    """Every option of ``plan`` but the scenario and --out is the spec's field with its default."""
    import typer.main

    params = {p.name: p for p in typer.main.get_command(app).commands["plan"].params}
    assert set(params) - {"scenario", "out"} == set(PlanSpec.model_fields)
    for name in PlanSpec.model_fields:
        assert cli_default(params[name]) == PlanSpec.default(name), name


def test_a_plan_too_long_for_the_machine_is_refused_before_any_work(tmp_path):
    sc = marinecdpr.load_scenario("paper")
    huge = sc.with_changes(time={"step_s": 1e-4, "duration_s": 1e6})  # 10^10 steps
    with pytest.raises(ScenarioError, match="more than the 1,000,000,000 steps") as err:
        command.estimate(PlanSpec(), huge)
    assert err.value.key == "time.duration_s"
    with pytest.raises(ScenarioError, match="more than the 1,000,000,000 steps"):
        command.run(PlanSpec(), huge, tmp_path / "o")
    assert not (tmp_path / "o").exists()
    est = command.estimate(PlanSpec(), sc)
    assert est.size.n_steps == sc.time.n_steps == 15001 and est.describe().startswith("size: paper: 15,001 steps")


@pytest.mark.figures
def test_a_run_from_python_writes_what_the_command_writes(tmp_path):
    """The run's files are the command's, byte for byte; its figures are the CSV's own."""
    scen = short_paper(tmp_path)
    sc = marinecdpr.load_scenario(scen)
    spec = PlanSpec(method="closed_form")
    seen = []
    result = command.run(spec, sc, tmp_path / "py", progress=lambda done, total: seen.append((done, total)))
    assert seen == [(1001, 1001)]  # one chunk
    res = runner.invoke(app, ["plan", str(scen), "--method", "closed_form", "--out", str(tmp_path / "cli")])
    assert res.exit_code == 0, res.output
    for name in command.FILES:
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), name
    data = np.genfromtxt(tmp_path / "py" / "plan.csv", delimiter=",", names=True)
    s = result.summary()
    assert s["steps"] == data.size == 1001 and s["feasible"] == int(data["feasible"].sum()) == 1001
    planned = np.column_stack([data[f"T{i}"] for i in range(1, 5)])
    pinv = np.column_stack([data[f"Tpinv{i}"] for i in range(1, 5)])
    # the CSV's 10 significant digits against the plan's own
    np.testing.assert_allclose(s["tension_range"], (planned.min(), planned.max()), rtol=1e-9)
    np.testing.assert_allclose(s["pinv_range"], (pinv.min(), pinv.max()), rtol=1e-9)
    assert (s["method"], s["base_model"]) == ("closed_form", "moving")
    assert f"{s['feasible']} of {s['steps']}" in res.stdout
    # written again elsewhere: the same bytes, the plan not made again
    again = result.write(tmp_path / "copy")
    assert [p.name for p in again] == list(command.FILES)
    assert all(p.read_bytes() == (tmp_path / "py" / p.name).read_bytes() for p in again)
    assert result.write(tmp_path / "py") == list(result.paths)


def test_the_fixed_base_plan_is_the_plan_on_a_still_ship(tmp_path):
    """``fixed_base`` plans as if the ship were still: the tensions of the moving-base plan
    of the same scenario with its ship held still (``base_motion.type = "still"``), and not
    those of the moving ship."""
    sc = marinecdpr.load_scenario(short_paper(tmp_path))
    fixed = command.run(PlanSpec(fixed_base=True), sc, tmp_path / "f")
    command.run(PlanSpec(), sc.with_changes(base_motion={"type": "still"}), tmp_path / "s")
    command.run(PlanSpec(), sc, tmp_path / "m")
    assert fixed.summary()["base_model"] == "fixed"
    f, s, m = (np.genfromtxt(tmp_path / k / "plan.csv", delimiter=",", names=True) for k in "fsm")
    tensions = [f"T{i}" for i in range(1, 5)]
    for name in tensions + ["L1", "Tpinv1"]:
        np.testing.assert_allclose(f[name], s[name], rtol=1e-9, atol=1e-9)
    assert max(np.abs(f[t] - m[t]).max() for t in tensions) > 0.1  # N: the moving ship's loads


def test_an_infeasible_plan_fails_unless_allowed(tmp_path):
    """A 200 kg platform the paper's cables cannot hold: ``failed`` (the command's exit 3)
    unless ``allow_infeasible``; the files and figures are the same either way."""
    sc = marinecdpr.load_scenario(short_paper(tmp_path, 0.5, mass_kg=200.0))
    strict = command.run(PlanSpec(), sc, tmp_path / "s")
    lenient = command.run(PlanSpec(allow_infeasible=True), sc, tmp_path / "l")
    assert strict.failed and not lenient.failed
    assert strict.summary()["feasible"] == 0 and "501 of 501 steps" in strict.infeasibility()
    assert (tmp_path / "s" / "plan.csv").read_bytes() == (tmp_path / "l" / "plan.csv").read_bytes()


@pytest.mark.figures
def test_the_page_runs_as_written_and_lists_the_spec(tmp_path, monkeypatch):
    assert_table_is_the_spec("plan", PlanSpec)
    ns = run_page("plan", tmp_path, monkeypatch)
    s = ns["figures"]
    assert s["steps"] == 2001 and s["method"] == "minimum_norm"
    data = np.genfromtxt(tmp_path / "out" / "plan.csv", delimiter=",", names=True)
    assert data.size == 2001 and s["feasible"] == int(data["feasible"].sum())
    planned = np.column_stack([data[f"T{i}"] for i in range(1, 5)])
    np.testing.assert_allclose((ns["lowest"], ns["highest"]), (planned.min(), planned.max()), rtol=1e-9)
    assert ns["result"].infeasibility() is None and ns["still"].summary()["base_model"] == "fixed"


def test_the_command_line_names_the_flag_of_a_bad_spec_field(tmp_path):
    from conftest import one_line_exit_2

    res = runner.invoke(app, ["plan", "paper", "--method", "fastest", "--out", str(tmp_path / "o")])
    assert one_line_exit_2(res) == ("error: --method fastest: expected one of pseudo_inverse, minimum_variance, "
                                    "closed_form, improved_closed_form, minimum_norm")
    assert not (tmp_path / "o").exists()
