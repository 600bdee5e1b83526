"""A design study's hostile inputs (issue 37, items 14, 16, 17, 19, 20, 21): every file a
study reads is read before any work and refused in one line; the options are capped where
the study file is; a journal is read strictly and keyed by the content of every file the
study reads, not by their paths; a study's name is a file name's stem before it names a
file; a misspelt built-in study is named."""

from __future__ import annotations

import json
import shutil
import tomllib
from importlib import resources
from pathlib import Path

import pytest
from typer.testing import CliRunner

pytest.importorskip("pymoo")

from marinecdpr.cli.app import app  # noqa: E402
from marinecdpr.errors import ScenarioError  # noqa: E402
from marinecdpr.scenario.design import GENERATIONS, POPULATION, SEED_MAX, DesignSpec  # noqa: E402
from marinecdpr.studies.design import (  # noqa: E402
    builtin_studies, load_design, read_journal, search, study_cells, study_key, study_path, with_options,
)
from tests.conftest import one_line_exit_2  # noqa: E402

runner = CliRunner()
BUILTIN = Path(str(resources.files("marinecdpr") / "scenario" / "builtin"))

TEMPLATE_BAND = ("stations_m = [-95.0, 95.0]", "stations_m = [-5.0, 5.0]"), ("heights_m = [0.0, 11.6]",
                                                                             "heights_m = [0.0, 3.0]")

STUDY = (Path(__file__).parents[1] / "data" / "tiny_study.toml").read_text(encoding="utf-8")
SEAS = "hs_m,tp_s,probability\n1.0,8.0,0.5\n2.0,9.0,0.5\n"


def _folder(folder: Path, study: str = STUDY, seas: bytes | str = SEAS) -> Path:
    """A study beside its own template (paper_clean on a 10 x 3 m band), the template's RAO
    file and its scatter diagram: every file it reads in one folder."""
    folder.mkdir(parents=True, exist_ok=True)
    text = (BUILTIN / "paper_clean.toml").read_text()
    for old, new in TEMPLATE_BAND:
        assert old in text
        text = text.replace(old, new)
    (folder / "template.toml").write_text(text)
    shutil.copy(BUILTIN / "paper_sea_rao.csv", folder / "paper_sea_rao.csv")
    (folder / "seas.csv").write_bytes(seas.encode() if isinstance(seas, str) else seas)
    (folder / "study.toml").write_text(study)
    return folder / "study.toml"


@pytest.fixture(scope="module")
def tiny(tmp_path_factory):
    path = _folder(tmp_path_factory.mktemp("tiny"))
    spec, template = load_design(path)
    return path, spec, template, study_cells(spec, path.parent)


@pytest.fixture(scope="module")
def journal(tiny, tmp_path_factory):
    """A finished search's journal of the tiny study (its key line and four candidates)."""
    path, spec, template, cells = tiny
    out = tmp_path_factory.mktemp("journal") / "journal.jsonl"
    search(spec, template, cells, journal=out)
    return out


# ---------------------------------------------------------------- item 16: bad scatter files
BAD_SCATTER = {
    "empty": b"",
    "wrong header": b"a,b,c\n1,8,1\n",
    "NaN": b"hs_m,tp_s,probability\n1.0,8.0,nan\n2.0,9.0,0.5\n",
    "inf": b"hs_m,tp_s,probability\n1.0,8.0,inf\n2.0,9.0,0.5\n",
    "1e308": b"hs_m,tp_s,probability\n1e308,8.0,0.5\n2.0,9.0,0.5\n",
    "zero probabilities": b"hs_m,tp_s,probability\n1.0,8.0,0\n2.0,9.0,0\n",
    "negative probability": b"hs_m,tp_s,probability\n1.0,8.0,-0.5\n2.0,9.0,1.5\n",
    "a short row": b"hs_m,tp_s,probability\n1.0,8.0\n2.0,9.0,1\n",
    "text": b"hs_m,tp_s,probability\n1.0,eight,0.5\n2.0,9.0,0.5\n",
    "non-UTF-8 bytes": b"hs_m,tp_s,probability\n1.0,8.0,0.5\xff\xfe\n2.0,9.0,0.5\n",
    "a NUL": b"hs_m,tp_s,probability\n1.0,8.0\x00,0.5\n2.0,9.0,0.5\n",
    "binary": b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR" * 20,
}


@pytest.mark.parametrize("what", list(BAD_SCATTER))
def test_a_bad_scatter_file_named_by_a_study_is_refused_as_the_study_loads(tmp_path, what):
    """Each bad diagram is one line naming the study, its key and the scatter file, raised as
    the study loads (before any candidate, before the output folder is made)."""
    path = _folder(tmp_path, seas=BAD_SCATTER[what])
    with pytest.raises(ScenarioError) as err:
        load_design(path)
    line = str(err.value)
    assert "\n" not in line and line.startswith(f"{path}: sea.scatter: ") and str(tmp_path / "seas.csv") in line


def test_a_bad_scatter_file_is_one_line_exit_2_and_nothing_written(tmp_path):
    path = _folder(tmp_path, seas=BAD_SCATTER["NaN"])
    res = runner.invoke(app, ["design", str(path), "--no-verify", "--out", str(tmp_path / "o")])
    one_line_exit_2(res, "sea.scatter", "probability = nan")
    assert not (tmp_path / "o").exists()


# ---------------------------------------------------------------- item 16: corrupt journals
def _key_line(journal: Path) -> str:
    return journal.read_text().splitlines()[0]


CORRUPT = {
    "garbage first line": lambda key, cand: "this is no json\n" + cand,
    "a list": lambda key, cand: "[1, 2]\n",
    "null": lambda key, cand: "null\n",
    "the key a number": lambda key, cand: '{"study": 7}\n',
    "a string where a number belongs": lambda key, cand: key + cand.replace('"surface_hours": ', '"surface_hours": '
                                                                            '"x", "was": ', 1) + cand,
    "NaN": lambda key, cand: key + json.dumps(json.loads(cand) | {"sea_share": float("nan")}) + "\n" + cand,
    "an unknown field": lambda key, cand: key + json.dumps(json.loads(cand) | {"extra": 1}) + "\n" + cand,
    "a field missing": lambda key, cand: key + json.dumps({k: v for k, v in json.loads(cand).items()
                                                           if k != "reason"}) + "\n" + cand,
    "x not an object": lambda key, cand: key + json.dumps(json.loads(cand) | {"x": [1, 2]}) + "\n" + cand,
    "a bool for a count": lambda key, cand: key + json.dumps(json.loads(cand) | {"placements": True}) + "\n" + cand,
    "nested too deeply": lambda key, cand: key + "[" * 100_000 + "]" * 100_000 + "\n" + cand,
}


@pytest.mark.parametrize("what", list(CORRUPT))
def test_a_corrupt_journal_is_refused_in_one_line_naming_its_line(tiny, journal, tmp_path, what):
    path, spec, template, cells = tiny
    lines = journal.read_text().splitlines(keepends=True)
    bad = tmp_path / "journal.jsonl"
    bad.write_text(CORRUPT[what](lines[0], lines[1]))
    with pytest.raises(ScenarioError) as err:
        read_journal(bad, study_key(spec, template, cells))
    line = str(err.value)
    assert "\n" not in line and line.startswith(f"--resume: {bad} line ") and "run without --resume" in line


def test_a_journal_of_other_bytes_than_utf_8_is_refused(tiny, tmp_path):
    path, spec, template, cells = tiny
    bad = tmp_path / "journal.jsonl"
    bad.write_bytes(b'{"study": "\xff\xfe"}\n')
    with pytest.raises(ScenarioError, match="not UTF-8 text"):
        read_journal(bad, study_key(spec, template, cells))


def test_the_journal_s_candidates_read_back_as_judged_and_a_cut_last_line_is_skipped(tiny, journal, tmp_path):
    """The strict reading takes every candidate the search wrote, figure for figure (inf and
    NaN as the journal spells them), and skips a last line cut mid-write as a Ctrl-C leaves it."""
    path, spec, template, cells = tiny
    key = study_key(spec, template, cells)
    known = read_journal(journal, key)
    lines = journal.read_text().splitlines()
    assert len(known) == len(lines) - 1 >= 1
    cut = tmp_path / "journal.jsonl"
    cut.write_text("\n".join(lines) + "\n" + lines[1][:40])
    assert read_journal(cut, key).keys() == known.keys()
    for e in known.values():
        assert json.loads(json.dumps(e.x)) == e.x and e.expected_hours == pytest.approx(e.surface_hours / e.sea_share)


# ---------------------------------------------------------------- items 16, 17: the options' caps
@pytest.mark.parametrize("option, value", [("population", POPULATION[1] + 1), ("population", 10**9),
                                           ("population", POPULATION[0] - 1), ("generations", GENERATIONS[1] + 1),
                                           ("generations", 10**9), ("generations", 0), ("seed", SEED_MAX + 1)])
def test_an_option_beyond_the_study_file_s_cap_is_refused_by_the_same_rule(tiny, option, value):
    """The options are validated by the study's own schema (one source for the caps): what
    the study file could not hold, the option cannot set."""
    path, spec, template, cells = tiny
    with pytest.raises(ScenarioError, match=rf"^--{option} {value}: input should be"):
        with_options(spec, **{option: value})
    data = tomllib.loads(STUDY) | {option: value}
    with pytest.raises(ValueError):  # the study file holding the same value is refused too
        DesignSpec.model_validate(data)
    assert with_options(spec, **{option: None}) is spec
    assert getattr(with_options(spec, **{option: 5}), option) == 5


@pytest.mark.parametrize("args", [["--population", "1000000000"], ["--population", "1001"],
                                  ["--generations", "1001"], ["--generations", "1000000000"],
                                  ["--seed", "99999999999999999999"]])
def test_a_design_option_beyond_its_cap_is_one_line_before_any_file(tiny, tmp_path, args):
    path = tiny[0]
    res = runner.invoke(app, ["design", str(path), "--no-verify", *args, "--out", str(tmp_path / "o")])
    one_line_exit_2(res, args[0])
    assert not (tmp_path / "o").exists()


# ---------------------------------------------------------------- item 21: the study's name
@pytest.mark.parametrize("name", ["/tmp/escaped", "a\\u0000b", "../../../escaped", "../../escaped", "a\\nb = 1",
                                  "a/b", "a\\\\b", "", ".", "..", "a b", "x" * 101, "a.", "-a"])
def test_a_study_name_that_is_no_file_stem_is_refused_as_the_study_loads(tmp_path, name):
    path = _folder(tmp_path, study=STUDY.replace('name = "tiny"', f'name = "{name}"'))
    with pytest.raises(ScenarioError) as err:
        load_design(path)
    assert str(err.value).startswith(f"{path}: name: must be a file name's stem") and "\n" not in str(err.value)


@pytest.mark.parametrize("name", ["ship_side", "Schiff_ä-2.0", "x" * 100, "_1"])
def test_a_study_name_that_is_a_file_stem_is_kept(tmp_path, name):
    path = _folder(tmp_path, study=STUDY.replace('name = "tiny"', f'name = "{name}"'))
    assert load_design(path)[0].name == name


def test_an_escaping_name_writes_nothing_anywhere(tmp_path):
    """"../../../escaped" is refused before the output folder or its journal is made: the
    folder around holds the study's files only."""
    folder = tmp_path / "a" / "b"
    path = _folder(folder, study=STUDY.replace('name = "tiny"', 'name = "../../../escaped"'))
    before = sorted(tmp_path.rglob("*"))
    res = runner.invoke(app, ["design", str(path), "--no-verify", "--out", str(folder / "run" / "out")])
    one_line_exit_2(res, "name: must be a file name's stem")
    assert sorted(tmp_path.rglob("*")) == before


# ---------------------------------------------------------------- items 19, 20: the study's key
def test_the_study_key_is_the_content_of_its_files_not_their_paths(tiny, journal, tmp_path):
    """The study's folder copied elsewhere, files identical: the same key, and the journal
    resumes there (the template's RAO file's path differs, its bytes do not)."""
    path, spec, template, cells = tiny
    copy = tmp_path / "copy"
    shutil.copytree(path.parent, copy)
    spec2, template2 = load_design(copy / "study.toml")
    assert template2.base_motion.rao.file != template.base_motion.rao.file
    key = study_key(spec, template, cells)
    assert study_key(spec2, template2, study_cells(spec2, copy)) == key
    assert read_journal(journal, study_key(spec2, template2, study_cells(spec2, copy))).keys() == \
        read_journal(journal, key).keys()


@pytest.mark.parametrize("file, edit", [
    ("paper_sea_rao.csv", "rao"), ("template.toml", "template"), ("seas.csv", "seas"), ("study.toml", "study"),
])
def test_one_digit_changed_in_any_file_the_study_reads_changes_its_key(tiny, journal, tmp_path, file, edit):
    """One digit of the template's RAO file (a heave phase), of the template, of the scatter
    diagram or of the study: another key, and the journal is refused as another study's."""
    path, spec, template, cells = tiny
    copy = tmp_path / "copy"
    shutil.copytree(path.parent, copy)
    target = copy / file
    text = target.read_text()
    old, new = {"rao": (",heave,", None), "template": ("preload_N = 60.0", "preload_N = 61.0"),
                "seas": ("1.0,8.0,0.5", "1.0,8.1,0.5"), "study": ("base_kg = 5.0", "base_kg = 5.1")}[edit]
    if edit == "rao":
        lines = text.splitlines()
        i = next(k for k, ln in enumerate(lines) if old in ln)
        head, _, last = lines[i].rpartition(",")
        lines[i] = f"{head},{float(last) + 1.0!r}"
        target.write_text("\n".join(lines) + "\n")
    else:
        assert old in text
        target.write_text(text.replace(old, new, 1))
    spec2, template2 = load_design(copy / "study.toml")
    key2 = study_key(spec2, template2, study_cells(spec2, copy))
    assert key2 != study_key(spec, template, cells)
    with pytest.raises(ScenarioError, match="is of another study"):
        read_journal(journal, key2)


# ---------------------------------------------------------------- item 14: the built-in studies
def test_a_misspelt_built_in_study_names_the_built_in_studies():
    assert builtin_studies() == ["ship_side"]  # the template beside it is no study
    with pytest.raises(ScenarioError) as err:
        load_design(study_path("ship_sid"))
    assert str(err.value) == ("ship_sid: no such file, and no built-in study of that name (did you mean 'ship_side'? "
                              "built-in studies: ship_side)")
    res = runner.invoke(app, ["design", "ship_sid"])
    one_line_exit_2(res, "did you mean 'ship_side'?")


def test_scenarios_lists_the_built_in_studies_too():
    res = runner.invoke(app, ["scenarios"])
    assert res.exit_code == 0, res.output
    lines = res.stdout.splitlines()
    spec, _ = load_design(study_path("ship_side"))
    assert lines[-1] == f"built-in design study ship_side (marinecdpr design ship_side): {spec.description}"
