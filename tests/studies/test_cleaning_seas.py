"""The cleaning job over a scatter diagram (`clean --seas`): per sea state the same job as
`cleaning_job`, verdicts and expected hours summed by hand, independent of the request's
order, the same on Dask."""

import json
import math

import numpy as np
import pytest
from typer.testing import CliRunner

import marinecdpr
from marinecdpr.cli.app import app
from marinecdpr.errors import ScenarioError
from marinecdpr.motion.trajectory import cleaning_path
from marinecdpr.studies.cleaning import cleaning_job, cleaning_seas, evaluate_cleaning_cell, ship_side
from marinecdpr.studies.operability import Cell, ScatterDiagram, cell_scenario

runner = CliRunner()
# calm seas work; in 14 m, 10 s beam seas the ship's motion pushes the brush out of its force band
DIAGRAM = ScatterDiagram(np.array([0.1, 1.0, 14.0]), np.array([8.0, 10.0]),
                         np.array([[0.2, 0.1], [0.3, 0.2], [0.0, 0.2]]))


@pytest.fixture(scope="module")
def small():
    """paper_clean on a 0.3 m x 0.3 m panel: two lanes, the whole path in a few seconds."""
    sc = marinecdpr.load_scenario("paper_clean")
    sc = sc.with_changes(cleaning=sc.cleaning.model_dump(exclude_none=True)
                         | {"panel_m": [[0.8, 0.5], [1.1, 0.5], [1.1, 0.8], [0.8, 0.8]]})
    return sc.with_changes(time={"step_s": 0.001, "duration_s": math.ceil(cleaning_path(sc.cleaning).duration_s)})


def test_a_sea_state_is_the_cleaning_job_in_that_sea(small):
    cell = Cell(3, 1.0, 8.0, 150.0, 0.2)
    r = evaluate_cleaning_cell(small, cell, coverage_target_pct=90.0, in_band_target_pct=95.0)
    job = cleaning_job(cell_scenario(small, cell, small.time.duration_s, small.time.step_s))
    s = job.summary
    assert (r.coverage_pct, r.reachable_coverage_pct, r.in_band_pct, r.tension_min_N, r.tension_max_N,
            r.job_time_s) == (s["coverage_pct"], s["reachable_coverage_pct"], s["normal_force_in_band_pct"],
                              s["tension_min_N"], s["tension_max_N"], s["job_time_s"])
    assert r.operable and r.reason == "" and r.hours == s["job_time_s"] / 3600.0
    hull = evaluate_cleaning_cell(small, cell, coverage_target_pct=90.0, hull_area_m2=50.0, move_time_s=300.0)
    assert hull.hours == ship_side(s, hull_area_m2=50.0, move_time_s=300.0)["hours"]
    strict = evaluate_cleaning_cell(small, cell, coverage_target_pct=100.0, in_band_target_pct=100.0)
    assert not strict.operable and "reachable coverage" in strict.reason
    rough = evaluate_cleaning_cell(small, Cell(0, 14.0, 10.0, 90.0, 0.2))
    assert not rough.operable and "normal force in band" in rough.reason and rough.in_band_pct < 95.0
    # a job that cannot be flown: limits no tension distribution meets
    tight = small.with_changes(robot=small.robot.model_dump(exclude_none=True) | {"tension_max_N": 60.0})
    none = evaluate_cleaning_cell(tight, cell)
    assert not none.operable and "tensions within the limits" in none.reason and math.isnan(none.hours)


def test_over_a_scatter_diagram_the_share_and_hours_sum_by_hand(small):
    cs = cleaning_seas(small, DIAGRAM, headings_deg=(180.0, 90.0), coverage_target_pct=90.0)
    rs = cs.sea.results
    assert len(rs) == 2 * 5  # the cell of probability 0 is not flown
    works = [r for r in rs if r.operable]
    assert all(r.operable for r in rs if r.cell.hs == 0.1)  # calm works
    assert not [r for r in rs if (r.cell.hs, r.cell.heading_deg) == (14.0, 90.0)][0].operable
    assert 0 < len(works) < len(rs)
    for h in (180.0, 90.0):
        mine = [r for r in rs if r.cell.heading_deg == h]
        assert cs.sea.per_heading[h] == pytest.approx(sum(r.cell.probability for r in mine if r.operable)
                                                      / sum(r.cell.probability for r in mine), rel=1e-12)
    assert cs.sea.operability == pytest.approx(np.mean(list(cs.sea.per_heading.values())), rel=1e-12)
    p = np.array([r.cell.probability for r in works])
    assert cs.expected_hours == pytest.approx(np.sum(p * [r.hours for r in works]) / p.sum(), rel=1e-12)
    assert cs.expected_hours_with_weather == pytest.approx(cs.expected_hours / cs.sea.operability, rel=1e-12)
    # the same sea states asked in another order: the same verdicts and figures
    again = cleaning_seas(small, DIAGRAM, headings_deg=(90.0, 180.0), coverage_target_pct=90.0)
    key = lambda r: (r.cell.hs, r.cell.tp, r.cell.heading_deg)  # noqa: E731
    assert {key(r): (r.operable, r.coverage_pct, r.tension_max_N) for r in rs} == \
        {key(r): (r.operable, r.coverage_pct, r.tension_max_N) for r in again.sea.results}


def test_on_dask_the_cleaning_job_gives_the_serial_results(small):
    diagram = ScatterDiagram(np.array([0.5, 2.0]), np.array([6.0]), np.array([[0.5], [0.5]]))
    sc = small.with_changes(time={"duration_s": 2.0})
    serial = cleaning_seas(sc, diagram, executor="serial")
    dask = cleaning_seas(sc, diagram, executor="dask", workers=2)
    assert dask.sea.executor == "dask"
    assert [(r.operable, r.coverage_pct, r.tension_min_N, r.tension_max_N) for r in serial.sea.results] == \
        [(r.operable, r.coverage_pct, r.tension_min_N, r.tension_max_N) for r in dask.sea.results]


def test_cleaning_seas_needs_a_sea_state_and_a_cleaning_job(small):
    with pytest.raises(ScenarioError, match="sea_state"):
        cleaning_seas(small.with_changes(base_motion={"type": "still"}), DIAGRAM)
    with pytest.raises(ScenarioError, match="no cleaning job"):
        cleaning_seas(marinecdpr.load_scenario("paper_sea"), DIAGRAM)


def test_clean_seas_writes_what_it_found_and_refuses_bad_options(small, tmp_path):
    csv = tmp_path / "diagram.csv"
    csv.write_text("hs_m,tp_s,probability\n0.5,6,0.6\n10,14,0.4\n")
    out = tmp_path / "out"
    res = runner.invoke(app, ["clean", "paper_clean", "--seas", "--scatter", str(csv), "--duration", "1",
                              "--coverage-target", "0", "--headings", "180,90", "--serial", "--out", str(out)])
    assert res.exit_code == 0, res.output
    summary = json.loads((out / "summary.json").read_text())
    rows = np.genfromtxt(out / "sea_states.csv", delimiter=",", names=True)
    assert rows.size == 4 and sorted(p.name for p in out.iterdir() if not p.name.startswith(".")) == ["sea_states.csv", "sea_states.png",
                                                                         "summary.json"]
    # the summary's share is the CSV's verdicts weighted by probability, headings equally likely
    share = np.mean([np.sum(rows["probability"][rows["heading_deg"] == h] * rows["works"][rows["heading_deg"] == h])
                     for h in (180.0, 90.0)])
    assert summary["operability"] == pytest.approx(share, rel=1e-9)
    failing = rows[rows["works"] == 0]
    assert [(c["heading_deg"], c["hs_m"], c["tp_s"]) for c in summary["not_working"]] == \
        [(float(r["heading_deg"]), float(r["hs_m"]), float(r["tp_s"])) for r in failing]
    for args, words in ((["--guarantee"], "--guarantee cannot go with --seas"),
                        (["--coverage-target", "120"], "--coverage-target 120: expected a percentage"),
                        (["--serial", "--workers", "2"], "--serial cannot go with --workers")):
        res = runner.invoke(app, ["clean", "paper_clean", "--seas", "--duration", "1", *args, "--out", str(out)])
        assert res.exit_code == 2 and words in res.stderr and res.stderr.count("\n") == 1, res.output
