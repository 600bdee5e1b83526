"""The faults study's files (:mod:`marinecdpr.report.faults`) read both limits of the cable a
fault loads most (issue 40, item 4): ``faults.csv``'s ``working_limit_N`` (the robot's
``tension_max_N``) beside its ``breaking_N`` (``breaking_load_N``), and the report and
``summary.json`` say whether the breaking loads were given or the working limits stand in.
Flown: paper_elastic's snap of cable 1 at 1 s on length-controlled winches (the faults study's
own case, test_faults_study.py), its peak read back from the files against the study's row."""

from __future__ import annotations

import csv
import html
import json

import pytest

import marinecdpr
from marinecdpr.report.faults import FAULT_COLUMNS, breaking_load_said, write_faults
from marinecdpr.studies.faults import FaultCase, fault_study


@pytest.fixture(scope="module")
def elastic():
    sc = marinecdpr.load_scenario("paper_elastic").with_updates("simulation.cables", winch="length")
    sc = sc.with_changes(time={"step_s": sc.time.step_s, "duration_s": 2.0})
    return sc, marinecdpr.plan(sc)


def written(sc, plan, folder):
    study = fault_study(sc, [FaultCase("cable_snap", 1, 1.0, "given")], after_s=1.0, plant="own", plan=plan)
    write_faults(study, sc, folder)
    (row,) = csv.DictReader((folder / "faults.csv").open())
    return study.rows[0], row, json.loads((folder / "summary.json").read_text()), \
        html.unescape((folder / "report.html").read_text())


@pytest.mark.parametrize("robot, breaking, said", [
    ({}, 450.0, "not given: each cable's working limit (tension_max_N) stands in"),
    ({"breaking_load_N": 2000.0}, 2000.0, "given (breaking_load_N)"),
])
def test_the_files_hold_the_working_limit_beside_the_breaking_load(elastic, tmp_path, robot, breaking, said):
    sc, plan = elastic
    sc = sc.with_updates("robot", **robot) if robot else sc
    r, row, summary, page = written(sc, plan, tmp_path)
    assert list(row) == list(FAULT_COLUMNS)
    assert list(row)[list(row).index("peak_cable") + 1:list(row).index("static_margin_N")] == ["working_limit_N",
                                                                                                 "breaking_N"]
    assert float(row["peak_tension_N"]) == pytest.approx(r.peak_tension_N, rel=1e-9) and r.peak_tension_N > 450.0
    assert int(row["peak_cable"]) == r.peak_cable
    assert float(row["working_limit_N"]) == 450.0 and float(row["breaking_N"]) == breaking
    assert summary["breaking_load"] == said and summary["rows"][0]["working_limit_N"] == 450.0
    assert summary["rows"][0]["breaking_N"] == breaking and summary["rows"][0]["verdict"] == row["verdict"]
    assert said in page
    assert f"{r.peak_tension_N:.4g} N (cable {r.peak_cable}) of 450 N / {breaking:.4g} N" in page


def test_some_cables_given_a_breaking_load_are_named(elastic):
    sc, _ = elastic
    cables = [c.model_dump(exclude_none=True) for c in sc.robot.cables]
    cables[3]["breaking_load_N"] = 900.0
    assert breaking_load_said(sc.with_updates("robot", cables=cables).robot) == (
        "given for cable 4 (breaking_load_N); for cables 1, 2, 3 the working limit (tension_max_N) stands in")
    cables[0]["breaking_load_N"] = 900.0
    assert breaking_load_said(sc.with_updates("robot", cables=cables).robot) == (
        "given for cables 1, 4 (breaking_load_N); for cables 2, 3 the working limit (tension_max_N) stands in")
