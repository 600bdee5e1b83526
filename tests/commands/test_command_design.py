"""The design command's contract in the library (:mod:`marinecdpr.commands.design`): its spec
checked without the command line, the estimate's refusals (the study, pymoo, the journal a
resume goes on from, the executors) before any work, a tiny seeded search from Python giving
what the command writes, the command line's defaults the spec's, and docs/commands/design.md
run as written (issue 38, items 1 and 2)."""

from __future__ import annotations

import csv
import json
import re
import sys
from pathlib import Path

import pytest
from typer.testing import CliRunner

pytest.importorskip("pymoo")

from marinecdpr.cli.app import app  # noqa: E402
from marinecdpr.commands import SpecError  # noqa: E402
from marinecdpr.commands import design as command  # noqa: E402
from marinecdpr.commands.design import DesignCommandSpec  # noqa: E402
from marinecdpr.errors import ScenarioError  # noqa: E402
from marinecdpr.studies.design import unflown_columns  # noqa: E402
from marinecdpr.studies.executor import Executor  # noqa: E402
from tests.conftest import judged_once, tiny_study_folder  # noqa: E402
from command_pages import cli_default  # noqa: E402

runner = CliRunner()
DOC = Path(__file__).resolve().parents[2] / "docs" / "commands" / "design.md"


@pytest.fixture(scope="module")
def ship_side_judged_once():
    """ship_side's short search (seed 14's four candidates, no finalists), which the page's
    Python and the command line both run: its baseline and each candidate judged once in this
    module, each a pure function of its whole spec, template, candidate and seas (the key:
    their content), the answer handed to whichever asks the same again. The memos, by name."""
    import marinecdpr.studies.design as studies_design

    memo: dict[str, dict] = {"baseline": {}, "evaluate": {}}
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(studies_design, "baseline", judged_once(studies_design.baseline, memo["baseline"]))
        mp.setattr(studies_design, "evaluate", judged_once(studies_design.evaluate, memo["evaluate"]))
        yield memo


@pytest.mark.parametrize("options, field, words", [
    ({"population": 3}, "population", "population 3: input should be greater than or equal to 4"),
    ({"population": 1001}, "population", "population 1001: input should be less than or equal to 1000"),
    ({"generations": 0}, "generations", "generations 0: input should be greater than or equal to 1"),
    ({"seed": 2 ** 32}, "seed", "seed 4294967296: input should be less than or equal to 4294967295"),
    ({"plant": "adams"}, "plant", "plant adams: expected one of mujoco, own"),
    ({"serial": True, "workers": 2}, "workers", "workers 2: cannot go with --serial"),
    ({"workers": 10 ** 6}, "workers", "per core of this machine's"),
    ({"scheduler": "nowhere"}, "scheduler", "scheduler nowhere: expected a Dask scheduler address"),
    ({"populaton": 4}, "populaton", "no such option of DesignCommandSpec"),
])
def test_a_bad_option_is_one_error_naming_its_field(options, field, words):
    with pytest.raises(SpecError) as err:
        DesignCommandSpec(**options)
    assert err.value.field == field and err.value.flag == "--" + field
    assert words in str(err.value) and "\n" not in str(err.value)


def test_the_estimate_reads_the_study_and_chooses_the_executors():
    """ship_side: the North Atlantic's 197 sea states x 3 headings; its finalist flown about
    the boundary of each of the 27 of its 48 columns it flies (``unflown_share``: the 21 least
    likely left; some four seas a column) closed loop are 108 x n_steps x 100 steps, far beyond
    auto's 20 M: a local cluster; the candidates on Dask only where asked."""
    spec = DesignCommandSpec(population=4, generations=2, seed=5)
    est = command.estimate(spec)
    assert (est.study.population, est.study.generations, est.study.seed) == (4, 2, 5)
    assert est.candidates == 8 and len(est.cells) == 591 and est.finalists == est.study.finalists == 1
    assert len(unflown_columns(est.cells, est.study.sea.unflown_share)) == 21 and est.columns_flown == 48 - 21
    assert est.search_executor == Executor.serial()
    assert 4 * 27 * est.template.time.n_steps * 100 >= 20_000_000
    assert (est.verify_executor.kind, est.verify_executor.why) == ("local", "large")
    quiet = command.estimate(DesignCommandSpec(verify=False))
    assert quiet.finalists == 0 and quiet.verify_executor == Executor.serial()
    assert (quiet.study.population, quiet.study.generations) == (24, 10)  # the study's own
    both = command.estimate(DesignCommandSpec(workers=1))
    assert both.search_executor == both.verify_executor == Executor(kind="local", workers=1)
    alone = command.estimate(DesignCommandSpec(serial=True))
    assert alone.search_executor == alone.verify_executor == Executor.serial()


def test_the_estimate_refuses_before_any_work(tmp_path, monkeypatch):
    with pytest.raises(ScenarioError, match="no such file, and no built-in study of that name \\(did you mean "
                                            "'ship_side'"):
        command.estimate(DesignCommandSpec(), "ship_sid")
    with pytest.raises(SpecError) as err:
        command.estimate(DesignCommandSpec(resume=True))
    assert err.value.field == "resume"
    with pytest.raises(ScenarioError, match=f"^--resume: no journal.jsonl in {re.escape(str(tmp_path))} to resume$"):
        command.estimate(DesignCommandSpec(resume=True), journal=tmp_path / "journal.jsonl")
    (tmp_path / "journal.jsonl").write_text('{"study": "another"}\n')
    with pytest.raises(ScenarioError, match="is of another study"):
        command.estimate(DesignCommandSpec(resume=True), journal=tmp_path / "journal.jsonl")
    with pytest.raises(SpecError) as err:
        command.estimate(DesignCommandSpec(scheduler="tcp://127.0.0.1:1", verify=False))
    assert (err.value.field, err.value.detail) == ("scheduler", "no Dask scheduler reachable there "
                                                                "(connection refused)")
    monkeypatch.setitem(sys.modules, "dask.distributed", None)   # as without the [dask] extra
    with pytest.raises(SpecError) as err:
        command.estimate(DesignCommandSpec(workers=2, verify=False))  # the candidates asked on Dask
    assert err.value.field == "workers" and "pip install 'marinecdpr[dask]'" in err.value.detail
    assert command.estimate(DesignCommandSpec()).verify_executor.note is not None   # auto: serial, said
    monkeypatch.setitem(sys.modules, "pymoo", None)
    with pytest.raises(ScenarioError, match="^design needs pymoo: pip install 'marinecdpr\\[design\\]'$"):
        command.estimate(DesignCommandSpec())


def test_a_tiny_seeded_search_from_python_is_what_the_command_writes(tmp_path):
    """Population 4, 1 generation, seed 11, no finalists flown, on tests/data/tiny_study.toml
    (its two sea states at one heading: the Python run and the command's agree on any study;
    the built-in ship_side through the command is
    test_the_built_in_study_runs_through_the_command's): the typed
    result, and the files it writes, equal the command's to the byte (the journal too). (The
    search's later generations are the study's tests': tests/studies/test_design.py.)"""
    study_file = tiny_study_folder(tmp_path / "study")
    spec = DesignCommandSpec(population=4, generations=1, seed=11, verify=False)
    seen = []
    result = command.run(spec, study_file, journal=tmp_path / "py.jsonl",
                         progress=lambda d, n, best: seen.append((d, n)))
    study = result.study
    assert len(study.evaluations) == 4 and list(study.generation) == [0] * 4
    assert seen[-1] == (4, 4) and result.verified == () and result.cells == 2
    s = result.summary()
    assert s["candidates"] == 4 and s["seed"] == 11 and s["verified"] is False
    assert [f["index"] for f in s["front"]] == study.front
    assert study.front and all(study.evaluations[i].feasible for i in study.front)
    written = result.write(tmp_path / "py")
    out = tmp_path / "cli"
    res = runner.invoke(app, ["design", str(study_file), "--population", "4", "--generations", "1", "--seed", "11",
                              "--no-verify", "--out", str(out)])
    assert res.exit_code == 0, res.output
    assert f"tiny: 4 candidates ({s['feasible']} feasible) over 2 sea states" in res.stdout
    for path in written:
        name = path.relative_to(tmp_path / "py")
        if path.suffix in (".csv", ".json", ".toml", ".html"):
            assert path.read_bytes() == (out / name).read_bytes(), name
    assert (tmp_path / "py.jsonl").read_bytes() == (out / "journal.jsonl").read_bytes()
    with open(out / "candidates.csv") as fh:
        hours = [r["expected_hours"] for r in csv.DictReader(fh)]
    from marinecdpr.report.files import json_text

    assert len(hours) == 4 and (out / "summary.json").read_text() == json_text(s) + "\n"


def test_the_command_line_s_defaults_are_the_spec_s():
    """Every option of ``design`` but the study and --out is the spec's field, with its default."""
    import typer.main

    params = {p.name: p for p in typer.main.get_command(app).commands["design"].params}
    options = set(params) - {"spec", "out"}   # the study file is the argument (named spec, as its help says)
    assert options == set(DesignCommandSpec.model_fields)
    for name in options:
        assert cli_default(params[name]) == DesignCommandSpec.default(name), name


def test_the_command_line_names_the_flag_of_a_bad_spec_field(tmp_path):
    res = runner.invoke(app, ["design", "--serial", "--workers", "2", "--out", str(tmp_path / "o")])
    assert res.exit_code == 2
    assert res.stderr.strip() == ("error: --workers 2: cannot go with --serial (--workers and --scheduler run "
                                  "on Dask)")
    assert not (tmp_path / "o").exists()


@pytest.mark.figures
def test_the_page_lists_the_spec_s_options_with_its_defaults():
    rows = re.findall(r"^\| `--([a-z-]+)` \| ([^|]*) \|", DOC.read_text(encoding="utf-8"), flags=re.M)
    table = {flag.replace("-", "_"): said.strip().strip("`") for flag, said in rows}
    assert set(table) == set(DesignCommandSpec.model_fields)
    for field, said in table.items():
        value = None if said == "–" else DesignCommandSpec(**{field: said}).model_dump()[field]
        assert value == DesignCommandSpec.default(field), field


def test_the_built_in_study_runs_through_the_command(tmp_path, ship_side_judged_once):
    """`marinecdpr design` with no study runs ship_side (a short search, no finalists flown;
    seed 14's four candidates, as docs/commands/design.md's, are judged in a third of the time
    of the study's own seed's): its baseline is the paper robot on the surface, 2 660
    placements moved by the study's first relocation choice, the crane: 385.8 h
    (docs/cleaning.md's table). (Its candidates and baseline judged once with the page's
    Python below, the same search.)"""
    out = tmp_path / "o"
    res = runner.invoke(app, ["design", "--population", "4", "--generations", "1", "--seed", "14", "--no-verify",
                              "--out", str(out)])
    assert res.exit_code == 0, res.output
    s = json.loads((out / "summary.json").read_text())
    assert s["study"] == "ship_side" and s["candidates"] == 4
    assert s["baseline"]["placements"] == 2660 and round(s["baseline"]["surface_hours"], 1) == 385.8
    assert "baseline (the template's robot): 2660 placements, 385.8 h on the surface" in res.stdout


def test_the_page_s_python_runs_as_written(tmp_path, monkeypatch, ship_side_judged_once):
    """The page's two blocks as written: the run, then its resume from the journal (the
    search's baseline and candidates judged once with the command line's run above, the same
    search; the resume's baseline so too: its claim is the candidates it takes from the journal)."""
    blocks = re.findall(r"```python\n(.*?)```", DOC.read_text(encoding="utf-8"), flags=re.S)
    assert len(blocks) == 2
    monkeypatch.chdir(tmp_path)
    ns: dict = {}
    exec(compile(blocks[0], str(DOC), "exec"), ns)  # noqa: S102 - the page's own examples
    est, study = ns["est"], ns["study"]
    assert est.candidates == 4 and len(est.cells) == 591                  # as the page's comment says
    assert len(ns["hours"]) == 4 and ns["hours"] == [e.expected_hours for e in study.evaluations]
    if study.front:
        assert ns["best"].expected_hours == min(e.expected_hours for e in study.evaluations
                                                if e.feasible and e.expected_hours == e.expected_hours)
    summary = json.loads((tmp_path / "design_out" / "summary.json").read_text())
    assert summary["candidates"] == 4 and summary["seed"] == 14
    # the resume: every candidate taken from the journal, none judged again, the same study
    import marinecdpr.studies.design as studies_design

    judged = []
    monkeypatch.setattr(studies_design, "evaluate", lambda *a: judged.append(a) or None)
    exec(compile(blocks[1], str(DOC), "exec"), ns)  # noqa: S102
    again = ns["again"].study
    assert judged == [] and [e.x for e in again.evaluations] == [e.x for e in study.evaluations]
    assert [e.expected_hours for e in again.evaluations] == ns["hours"]
    memo = ship_side_judged_once  # one study asked: one baseline, its four candidates each once
    assert len(memo["baseline"]) == 1 and len(memo["evaluate"]) == len({json.dumps(e.x, sort_keys=True)
                                                                          for e in study.evaluations})
