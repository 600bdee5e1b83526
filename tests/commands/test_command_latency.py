"""The latency command's contract in the library (:mod:`marinecdpr.commands.latency`): the
count of calls checked as the spec is made, the compile said by the estimate, the command
line's defaults the spec's, a run's figures, and its page (issue 38)."""

from __future__ import annotations

import dataclasses
import json

import pytest
from typer.testing import CliRunner

import marinecdpr
from command_pages import assert_table_is_the_spec, run_page
from marinecdpr.cli.app import app
from marinecdpr.commands import SpecError
from marinecdpr.commands import latency as command
from marinecdpr.commands.latency import LatencySpec

runner = CliRunner()


@pytest.mark.parametrize("calls, said, words", [
    (0, "0", "expected at least 1 call"),
    (-3, "-3", "expected at least 1 call"),
    (10**9, "1,000,000,000", "more than the 10,000,000 calls a measurement may take"),
    (10**12, "1e+12", "more than the 10,000,000 calls"),
    (int("1" * 400), "1e+399", "more than the 10,000,000 calls"),
])
def test_a_count_the_machine_cannot_afford_is_one_error_naming_calls(calls, said, words):
    with pytest.raises(SpecError) as err:
        LatencySpec(calls=calls)
    assert (err.value.field, err.value.flag, err.value.value) == ("calls", "--calls", said)
    assert err.value.detail.startswith(words) and "\n" not in str(err.value)


def test_the_command_line_s_defaults_are_the_spec_s():
    import typer.main

    params = {p.name: p for p in typer.main.get_command(app).commands["latency"].params}
    assert set(params) - {"scenario"} == set(LatencySpec.model_fields)
    for name in LatencySpec.model_fields:
        assert params[name].default == LatencySpec.default(name), name


def test_the_estimate_says_when_the_step_must_be_compiled(monkeypatch):
    import marinecdpr.studies.latency as study

    sc = marinecdpr.load_scenario("paper")
    monkeypatch.setattr(study, "latency_kernels_cached", lambda: False)
    cold = command.estimate(LatencySpec(calls=30), sc)
    assert (cold.scenario, cold.calls, cold.compile_s) == ("paper", 30, study.LATENCY_COMPILE_S)
    monkeypatch.setattr(study, "latency_kernels_cached", lambda: True)
    assert command.estimate(LatencySpec(calls=30), sc).compile_s is None


def test_a_run_s_figures_are_ordered_and_the_command_prints_them_alike():
    """Percentiles of one sample: p50 <= p99 <= max each way; the robot's figures are the
    scenario's; ``--json`` prints the same fields."""
    sc = marinecdpr.load_scenario("paper")
    result = command.run(LatencySpec(calls=300), sc)
    s = result.summary()
    assert s == dataclasses.asdict(result.latency)
    assert (s["scenario"], s["calls"], s["cables"], s["redundancy"]) == ("paper", 300, 4, 4 - 3)
    assert s["method"] == sc.planning.method
    for where in ("python", "compiled"):
        assert 0 < s[f"{where}_p50_us"] <= s[f"{where}_p99_us"] <= s[f"{where}_max_us"]
    res = runner.invoke(app, ["latency", "paper", "--calls", "300", "--json"])
    assert res.exit_code == 0, res.output
    printed = json.loads(res.stdout)
    assert set(printed) == set(s)
    assert {k: printed[k] for k in ("scenario", "method", "cables", "redundancy", "calls")} == \
        {k: s[k] for k in ("scenario", "method", "cables", "redundancy", "calls")}


def test_the_page_runs_as_written_and_lists_the_spec(tmp_path, monkeypatch):
    assert_table_is_the_spec("latency", LatencySpec, {"json": "as_json"})
    ns = run_page("latency", tmp_path, monkeypatch)
    times = ns["times"]
    assert times["calls"] == 500 and times["compiled_p50_us"] <= times["compiled_max_us"]
    assert ns["est"].compile_s is None or ns["est"].compile_s > 0
    assert ns["said"] == "--calls 1,000,000,000"
