"""The operability command's contract in the library (:mod:`marinecdpr.commands.operability`):
its spec checked without the command line (the executor's options among its fields), the
estimate's refusals before any work, a run from Python giving what the command writes, the
command line's defaults the spec's, and docs/commands/operability.md run as written
(issue 38, items 1 and 2)."""

from __future__ import annotations

import csv
import json
import re
import sys
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

import marinecdpr
from marinecdpr.cli.app import app
from marinecdpr.commands import SpecError
from marinecdpr.commands import operability as command
from marinecdpr.commands.operability import OperabilitySpec
from marinecdpr.errors import ScenarioError
from marinecdpr.studies.executor import NO_DASK_NOTE, Executor
from marinecdpr.studies.operability import REALISATIONS, study_steps
from command_pages import cli_default

runner = CliRunner()
DOC = Path(__file__).resolve().parents[2] / "docs" / "commands" / "operability.md"
SCATTER = "hs_m,tp_s,probability\n0.5,7,0.5\n2.5,9,0.3\n4,7,0.2\n"


@pytest.fixture
def scatter(tmp_path):
    path = tmp_path / "scatter.csv"
    path.write_text(SCATTER)
    return path


@pytest.mark.parametrize("options, field, words", [
    ({"headings": "180,540"}, "headings", "headings 180,540: expected finite headings between -360 and 360 deg"),
    ({"headings": "180,-180"}, "headings", "a heading is given twice"),
    ({"margin": -1.0}, "margin", "margin -1: expected a non-negative number"),
    ({"duration": 0.0}, "duration", "duration 0: expected a positive number"),
    ({"step": float("inf")}, "step", "step inf: expected a finite number"),
    ({"max_error": -0.1}, "max_error", "max_error -0.1: expected a positive number"),
    ({"realisations": 0}, "realisations", "realisations 0: expected at least 1 record per sea state"),
    ({"workspace": "12x0"}, "workspace", "workspace 12x0: expected two positive integers like 12x8"),
    ({"min_area": 1.5}, "min_area", "min_area 1.5: expected a share between 0 and 1"),
    ({"workers": 0}, "workers", "workers 0: expected a positive whole number of worker processes"),
    ({"scheduler": "udp://h:1"}, "scheduler", "scheduler udp://h:1: expected a Dask scheduler address like "
                                             "tcp://host:8786"),
    ({"serial": True, "workers": 2}, "workers", "workers 2: cannot go with --serial (--workers and --scheduler "
                                                "run on Dask)"),
    ({"serial": True, "scheduler": "tcp://h:8786"}, "scheduler", "scheduler tcp://h:8786: cannot go with --serial"),
    ({"heading": "180"}, "heading", "no such option of OperabilitySpec"),
])
def test_a_bad_option_is_one_error_naming_its_field(options, field, words):
    with pytest.raises(SpecError) as err:
        OperabilitySpec(**options)
    assert err.value.field == field and err.value.flag == "--" + field.replace("_", "-")
    assert words in str(err.value) and "\n" not in str(err.value)


def test_too_many_workers_for_the_machine(monkeypatch):
    import os

    monkeypatch.setattr(os, "cpu_count", lambda: 2)
    assert OperabilitySpec(workers=8).workers == 8
    with pytest.raises(SpecError, match=r"^workers 9: more than 4 per core of this machine's 2 gains nothing "
                                        r"\(each is a process of its own\); use at most 8$"):
        OperabilitySpec(workers=9)


def test_the_estimate_sizes_the_study_by_its_largest_sea_state_and_chooses_the_executor(scatter):
    sc = marinecdpr.load_scenario("paper_sea")
    spec = OperabilitySpec(scatter=scatter, headings="180,90,0", duration=30.0, step=0.1, realisations=3)
    est = command.estimate(spec, sc)
    assert est.cells == 3 * 3 and est.size.n_steps == 301
    assert est.size.poses == 9 * 3                               # every record of every sea state
    assert est.steps == study_steps(27, duration_s=30.0, step_s=0.1) == 27 * 301
    assert est.executor == Executor(kind="serial", why="small") and est.executor.note is None
    np.testing.assert_array_equal(est.scatter.hs, [0.5, 2.5, 4.0])
    assert est.singular.n_singular == 0
    # the executor's options and the machine: the spec's fields, the estimate's executor
    assert command.estimate(spec.model_copy(update={"serial": True}), sc).executor == Executor.serial()
    local = command.estimate(OperabilitySpec(scatter=scatter, duration=30.0, step=0.1, workers=1), sc).executor
    assert (local.kind, local.workers, local.describe()) == ("local", 1, "Dask, 1 worker")


def test_the_estimate_refuses_before_any_work(scatter, tmp_path, monkeypatch):
    import tripwire

    sc = marinecdpr.load_scenario("paper_sea")
    tripwire.arm(monkeypatch)
    with pytest.raises(ScenarioError, match="operability needs a \\[base_motion\\] of type sea_state"):
        command.estimate(OperabilitySpec(scatter=scatter), marinecdpr.load_scenario("paper"))
    with pytest.raises(ScenarioError, match="more than the 1,000,000,000 steps a run can finish in sane time"):
        command.estimate(OperabilitySpec(headings=tuple(range(0, 360, 2))), sc)
    bad = tmp_path / "bad.csv"
    bad.write_text("hs_m,tp_s,probability\n1,6,50\n2,6,50\n")
    with pytest.raises(ScenarioError, match=f"^{re.escape(str(bad))}: the probabilities .* look like percent"):
        command.estimate(OperabilitySpec(scatter=bad), sc)
    with pytest.raises(SpecError) as err:
        command.estimate(OperabilitySpec(scatter=scatter, scheduler="tcp://127.0.0.1:1"), sc)
    assert (err.value.field, err.value.detail) == ("scheduler", "no Dask scheduler reachable there "
                                                                "(connection refused)")
    monkeypatch.setitem(sys.modules, "dask.distributed", None)  # as without the [dask] extra
    with pytest.raises(SpecError) as err:
        command.estimate(OperabilitySpec(scatter=scatter, workers=2), sc)
    assert err.value.field == "workers" and "pip install 'marinecdpr[dask]'" in err.value.detail
    monkeypatch.undo()  # the singular poses' check evaluates the ship's motion
    monkeypatch.setitem(sys.modules, "dask.distributed", None)
    big = command.estimate(OperabilitySpec(scatter=scatter, duration=1200.0, max_error=0.1), sc)
    assert big.steps >= 20_000_000 and big.executor.why == "no dask" and big.executor.note == NO_DASK_NOTE


@pytest.mark.figures
def test_a_run_from_python_is_what_the_command_writes(scatter, tmp_path):
    """The typed result's sea states and summary, and the command's operability.csv and .json:
    the same, value for value."""
    sc = marinecdpr.load_scenario("paper_sea")
    spec = OperabilitySpec(scatter=scatter, headings="180,90", duration=8.0, step=0.1, realisations=2, margin=20.0,
                           serial=True)
    result = command.run(spec, sc)
    op = result.operability
    assert result.executor == Executor.serial() and op.executor == "serial"
    assert len(op.results) == 6 and all(r.realisations == 2 and r.n_steps == 81 for r in op.results)
    out = tmp_path / "o"
    res = runner.invoke(app, ["operability", "paper_sea", "--scatter", str(scatter), "--headings", "180,90",
                              "--duration", "8", "--step", "0.1", "--realisations", "2", "--margin", "20", "--serial",
                              "--out", str(out)])
    assert res.exit_code == 0, res.output
    with open(out / "operability.csv") as fh:
        rows = list(csv.DictReader(fh))
    assert [(float(r["heading_deg"]), float(r["hs_m"]), float(r["tp_s"]), int(r["successes"]),
             r["min_margin_N"]) for r in rows] == \
        [(c.cell.heading_deg, c.cell.hs, c.cell.tp, c.successes, "%.10g" % c.min_margin_N) for c in op.results]
    assert len({r["min_margin_N"] for r in rows}) == 6 and 0 < sum(c.successes for c in op.results) < 12
    from marinecdpr.report.files import json_text

    assert (out / "operability.json").read_text() == json_text(result.summary()) + "\n"
    # and written from Python: the same files
    written = result.write(tmp_path / "py")
    assert sorted(p.name for p in written) == ["operability.csv", "operability.json", "operability.png"]
    assert (tmp_path / "py" / "operability.csv").read_bytes() == (out / "operability.csv").read_bytes()


def test_the_command_line_s_defaults_are_the_spec_s():
    """Every option of ``operability`` but the scenario and --out is the spec's field, with its default."""
    import typer.main

    params = {p.name: p for p in typer.main.get_command(app).commands["operability"].params}
    options = set(params) - {"scenario", "out"}
    assert options == set(OperabilitySpec.model_fields)
    for name in options:
        default = cli_default(params[name])
        spec_default = OperabilitySpec.default(name)
        assert (OperabilitySpec(**{name: default}).model_dump()[name] if default is not None else None) == spec_default
    assert OperabilitySpec.default("realisations") == REALISATIONS


def test_the_command_line_names_the_flag_of_a_bad_spec_field(tmp_path):
    res = runner.invoke(app, ["operability", "--min-area", "0.5", "--workspace", "3x", "--out", str(tmp_path / "o")])
    assert res.exit_code == 2
    assert res.stderr.strip() == "error: --workspace 3x: expected two positive integers like 12x8"
    assert not (tmp_path / "o").exists()


def _table(doc: str) -> dict[str, str]:
    """The page's options table: flag -> default as written (``–`` for none)."""
    rows = re.findall(r"^\| `--([a-z-]+)` \| ([^|]*) \|", doc, flags=re.M)
    return {flag.replace("-", "_"): default.strip().strip("`") for flag, default in rows}


@pytest.mark.figures
def test_the_page_lists_the_spec_s_options_with_its_defaults():
    table = _table(DOC.read_text(encoding="utf-8"))
    assert set(table) == set(OperabilitySpec.model_fields)
    for field, said in table.items():
        value = None if said == "–" else OperabilitySpec(**{field: said}).model_dump()[field]
        assert value == OperabilitySpec.default(field), field


def test_the_page_s_python_runs_as_written(tmp_path, monkeypatch):
    blocks = re.findall(r"```python\n(.*?)```", DOC.read_text(encoding="utf-8"), flags=re.S)
    assert len(blocks) == 2
    monkeypatch.chdir(tmp_path)
    ns: dict = {}
    for block in blocks:
        exec(compile(block, str(DOC), "exec"), ns)  # noqa: S102 - the page's own examples
    est, op = ns["est"], ns["op"]
    assert est.cells == 68 and est.executor.describe() == "serial"   # as the page's comment says
    assert len(op.results) == 68 and ns["share"] == op.operability
    assert 0.0 <= ns["low"] <= op.operability <= ns["high"] <= 1.0
    assert ns["hardest"].min_margin_N == min(r.min_margin_N for r in op.results)
    summary = json.loads((tmp_path / "out" / "operability.json").read_text())
    assert summary["operability"] == op.operability and summary["cells"] == 68
    # the second example: one record a sea state at one heading, the first example's heading 180 again
    calm = ns["calm"]
    first = {(r.cell.hs, r.cell.tp): r.min_margin_N for r in op.results if r.cell.heading_deg == 180.0}
    assert len(calm.results) == 34
    # a sea state's first record is the same whatever else is asked: its headroom is at least the
    # two-record verdict's (the smaller of its two records)
    assert all(r.min_margin_N >= first[(r.cell.hs, r.cell.tp)] for r in calm.results)
