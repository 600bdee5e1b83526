"""The design study with the frame's moves and the robots as design choices (issue 39, item
4): a study's ``[relocation]`` and its variables ``relocation = ["crane", "rail"]`` and
``robots = [1, 3]`` (tests/data/tiny_relocation_study.toml), each candidate's hours its
surface job's with those moves and robots, its power and cost its robots' winches and
ropes and the moves' cost; a study without them writes what it wrote before."""

from __future__ import annotations

import csv
import shutil
from importlib import resources
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

pytest.importorskip("pymoo")

from marinecdpr.cli.app import app  # noqa: E402
from marinecdpr.errors import ScenarioError  # noqa: E402
from marinecdpr.report.design import CANDIDATE_COLUMNS, RELOCATION_COLUMNS  # noqa: E402
from marinecdpr.studies.design import (  # noqa: E402
    baseline, candidate_scenario, evaluate, load_design, search, span_sag, study_cells,
)
from marinecdpr.studies.surface import surface_job  # noqa: E402

runner = CliRunner()
BUILTIN = Path(str(resources.files("marinecdpr") / "scenario" / "builtin"))
DATA = Path(__file__).parents[1] / "data"
STUDY = (DATA / "tiny_relocation_study.toml").read_text(encoding="utf-8")


def _folder(folder: Path, study: str = STUDY) -> Path:
    """The study beside its template (paper_clean on a 10 x 3 m band), its RAOs and seas."""
    folder.mkdir(parents=True, exist_ok=True)
    text = (BUILTIN / "paper_clean.toml").read_text()
    text = text.replace("stations_m = [-95.0, 95.0]", "stations_m = [-5.0, 5.0]")
    text = text.replace("heights_m = [0.0, 11.6]", "heights_m = [0.0, 3.0]")
    assert "stations_m = [-5.0, 5.0]" in text and "heights_m = [0.0, 3.0]" in text
    (folder / "template.toml").write_text(text)
    shutil.copy(BUILTIN / "paper_sea_rao.csv", folder / "paper_sea_rao.csv")
    (folder / "seas.csv").write_text("hs_m,tp_s,probability\n1.0,8.0,0.5\n2.0,9.0,0.5\n")
    (folder / "study.toml").write_text(study)
    return folder / "study.toml"


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    path = _folder(tmp_path_factory.mktemp("relocation"))
    spec, template = load_design(path)
    return path, spec, template, study_cells(spec, path.parent)


def _x(spec, **kw) -> dict:
    x = {k: (v[0] if isinstance(v, tuple) else v) for k, v in spec.bounds().items()}
    return x | {"winch": "w", "rope": "r", "pattern": "uncrossed"} | kw


@pytest.mark.parametrize("mode, robots", [("crane", 1), ("rail", 1), ("rail", 3), ("crane", 3)])
def test_a_candidate_s_hours_and_cost_include_its_moves_and_its_robots(study, mode, robots):
    """The candidate's surface hours are its scenario's surface job with the study's crane or
    rail and its robots (the slowest robot's); its power and cost are its robots' four winches
    (1.5 kW, 4 000 each) and four ropes (3 a metre of the frame's diagonal), and its cost the
    moves' too: a crane (where any move is by crane) on hire at 150 an hour for the job, one
    per robot, and with a rail its 10 m (500 a metre) and a carriage per robot (20 000)."""
    _, spec, template, cells = study
    x = _x(spec, relocation=mode, robots=robots)
    e = evaluate(spec, template, x, cells)
    sc = candidate_scenario(spec, template, x)
    rel = sc.cleaning.surface.relocation
    assert (rel.mode, rel.robots, rel.frame_mass_kg, rel.crane.rig_s, rel.rail.settle_s) == (mode, robots, 300.0,
                                                                                            300.0, 30.0)
    job = surface_job(sc, move_time_s=spec.move_time_s, digits=2)
    assert e.surface_hours == job.hours and e.placements == len(job.placements)
    assert (e.rail_moves, e.crane_moves) == (job.moves.count("rail"), job.moves.count("crane"))
    assert e.crane_moves > 0 and (e.rail_moves > 0) == (mode == "rail")
    span, _ = span_sag(0.2, 1.9, 1.4, spec.limits.tension_min_N)
    hire = robots * 150.0 * job.hours
    moves_cost = hire + ((500.0 * 10.0 + robots * 20000.0) if mode == "rail" else 0.0)
    assert e.relocation_cost == pytest.approx(moves_cost, rel=1e-14)
    assert e.cost == pytest.approx(robots * 4 * (4000.0 + 3.0 * span) + moves_cost, rel=1e-14)
    assert e.power_kW == robots * 6.0
    parts = e.hours_breakdown()
    assert parts["cleaning"] + parts["turns"] + parts["moves"] == pytest.approx(e.surface_hours, rel=1e-12)
    if robots == 3:  # each robot on its own stretch: the job is the slowest's, under one robot's
        one = evaluate(spec, template, _x(spec, relocation=mode, robots=1), cells)
        assert e.surface_hours < one.surface_hours and len(job.robot_seconds) == 3
        assert e.surface_hours * 3600.0 == pytest.approx(job.robot_seconds.max(), rel=1e-14)


def test_the_rail_beats_the_crane_on_hours_for_the_same_robot(study):
    """The tiny band's rows by rail (a 1.3 m move in about 36 s) against a crane's 450 s and
    more per move: fewer hours, the same placements and cleaning."""
    _, spec, template, cells = study
    crane = evaluate(spec, template, _x(spec, relocation="crane", robots=1), cells)
    rail = evaluate(spec, template, _x(spec, relocation="rail", robots=1), cells)
    assert crane.placements == rail.placements and crane.cleaning_hours == pytest.approx(rail.cleaning_hours)
    assert rail.move_hours < 0.25 * crane.move_hours


def test_the_search_chooses_the_moves_and_the_robots_and_writes_them(study, tmp_path):
    """The search's candidates carry a mode from ["crane", "rail"] and a count from [1, 3];
    candidates.csv has the relocation's columns after cost and the rail's margin after the
    others; the baseline is judged with the study's first choices."""
    path, spec, template, cells = study
    result = search(spec, template, cells)
    for e in result.evaluations:
        assert e.x["relocation"] in ("crane", "rail") and e.x["robots"] in (1, 3) and type(e.x["robots"]) is int
    b = baseline(spec, template, cells)
    assert b.x["relocation"] == "crane" and b.x["robots"] == 1 and b.crane_moves == b.placements - 1
    res = runner.invoke(app, ["design", str(path), "--no-verify", "--out", str(tmp_path / "o")], terminal_width=4000)
    assert res.exit_code == 0, res.output
    assert ", moved by " in res.stdout and "(the moves cost " in res.stdout
    with open(tmp_path / "o" / "candidates.csv", newline="") as fh:
        rows = list(csv.reader(fh))
    at = CANDIDATE_COLUMNS.index("cost") + 1
    # a candidate may move by rail: the carriage's margin after the others (blank by crane)
    assert rows[0] == (CANDIDATE_COLUMNS[:at] + RELOCATION_COLUMNS + CANDIDATE_COLUMNS[at:-2]
                       + ["margin_rail_accel_m_s2"] + CANDIDATE_COLUMNS[-2:])
    got = {(r[rows[0].index("relocation")], int(r[rows[0].index("robots")])) for r in rows[1:]}
    assert got <= {("crane", 1), ("crane", 3), ("rail", 1), ("rail", 3)} and got


def test_a_study_without_relocation_writes_the_columns_it_wrote(tmp_path):
    """The tiny study without the moves' variables and section: candidates keep their old
    variables and candidates.csv its old columns (the fingerprints of issue 22 stay)."""
    text = (DATA / "tiny_study.toml").read_text(encoding="utf-8")
    path = _folder(tmp_path / "plain", text)
    spec, template = load_design(path)
    assert not spec.relocates
    e = evaluate(spec, template, _x(spec), study_cells(spec, path.parent))
    assert set(e.x) == {*spec.bounds(), "winch", "rope", "pattern"} and e.relocation_cost == 0.0
    job = surface_job(candidate_scenario(spec, template, _x(spec)), move_time_s=600.0, digits=2)
    assert job.moves is None and e.move_hours == (len(job.placements) - 1) * 600.0 / 3600.0
    res = runner.invoke(app, ["design", str(path), "--no-verify", "--out", str(tmp_path / "o")])
    assert res.exit_code == 0, res.output
    with open(tmp_path / "o" / "candidates.csv", newline="") as fh:
        assert next(csv.reader(fh)) == CANDIDATE_COLUMNS


@pytest.mark.parametrize("edit, words", [
    (('relocation = ["crane", "rail"]', 'relocation = ["crane", "boat"]'), "variables.relocation"),
    (("[relocation.rail]", "[relocation.x_rail]"), "relocation.x_rail"),
    (("robots = [1, 3]", "robots = [1, 0]"), "variables.robots"),
    (("robots = [1, 3]", "robots = [3, 3]"), "variables.robots[2]: 3 is listed twice"),
    (("frame_mass_kg = 300.0", "frame_mass_kg = 900.0"), None),
])
def test_a_bad_relocation_in_a_study_is_one_line_naming_the_key(tmp_path, edit, words):
    text = STUDY.replace(*edit)
    assert text != STUDY
    path = _folder(tmp_path, text)
    if words is None:  # 900 kg and the platform: within the crane's 1000 kg; the study loads
        spec, _ = load_design(path)
        assert spec.relocation.frame_mass_kg == 900.0
        return
    with pytest.raises(ScenarioError) as err:
        load_design(path)
    assert words in str(err.value) and "\n" not in str(err.value)


def test_a_mode_without_its_figures_is_refused_as_the_study_loads(tmp_path):
    text = STUDY[:STUDY.index("[relocation.crane]")] + STUDY[STUDY.index("[relocation.rail]"):]
    path = _folder(tmp_path, text)
    with pytest.raises(ScenarioError) as err:
        load_design(path)
    assert "variables.relocation[1]: 'crane' needs its figures in [relocation.crane]" in str(err.value)


def test_a_frame_heavier_than_the_crane_makes_the_candidate_infeasible(study):
    """The study's crane lifts 1 000 kg: a 996 kg frame with the candidate's 5 kg platform is
    infeasible, with the reason."""
    _, spec, template, cells = study
    heavy = spec.model_copy(update={"relocation": spec.relocation.model_copy(update={"frame_mass_kg": 996.0})})
    e = evaluate(heavy, template, _x(spec, relocation="crane", robots=1), cells)
    assert not e.feasible and "heavier than the crane's capacity_kg (1000 kg)" in e.reason
    assert np.isinf(e.expected_hours)


def test_a_template_that_carries_its_frame_on_a_rail_is_refused_in_one_line(tmp_path):
    """The study places the frame itself on the surface; a template with [ship.carriage] is
    refused as the study loads, the rail relocation named (issue 39)."""
    path = _folder(tmp_path)
    template = path.parent / "template.toml"
    text = template.read_text()
    start, end = text.index("[ship]"), text.index("[base_motion]")
    carriage = ('[ship]\n\n[ship.carriage]\nrail_m = [[-5.0, 16.0, 0.0], [5.0, 16.0, 0.0]]\nspeed_max_m_s = 0.3\n'
                'accel_max_m_s2 = 0.3\njerk_max_m_s3 = 1.0\nstations_m = [0.0]\n\n')
    template.write_text(text[:start] + carriage + text[end:])
    with pytest.raises(ScenarioError, match=r"carries its frame on a rail \(\[ship.carriage\]\).*mode = \"rail\""):
        load_design(path)
