"""The ``[[faults]]`` section (issue 40, item 2): a fault's kind, its cable counted from 1 and
its time, and every mistake refused in one line naming the entry and the key (exit 2 from
the CLI)."""

from __future__ import annotations

import math

import pytest
import tomli_w
from typer.testing import CliRunner

from marinecdpr import ScenarioError
from marinecdpr.cli.app import app
from marinecdpr.scenario.loading import scenario_from_dict

from conftest import paper_dict

SNAP = {"kind": "cable_snap", "cable": 2, "at_s": 7.5}


def with_faults(*faults):
    d = paper_dict()
    d["faults"] = list(faults)
    return scenario_from_dict(d, source="faults.toml")


def test_faults_read_as_listed_and_default_to_none():
    s = with_faults(SNAP, {**SNAP, "cable": 4, "at_s": 15.0})
    assert [(f.kind, f.cable, f.at_s) for f in s.faults] == [("cable_snap", 2, 7.5), ("cable_snap", 4, 15.0)]
    assert scenario_from_dict(paper_dict(), source="x").faults == []


@pytest.mark.parametrize("faults, key, says", [
    ([{**SNAP, "kind": "snap"}], "faults[1].kind", "'cable_snap'"),
    ([{**SNAP, "cable": 5}], "faults[1].cable", "the robot has 4 cables (counted from 1), got 5"),
    ([{**SNAP, "cable": 0}], "faults[1].cable", "greater than or equal to 1"),
    ([{**SNAP, "cable": 2.0}], "faults[1].cable", "valid integer"),
    ([SNAP, {**SNAP, "at_s": 15.5}], "faults[2].at_s", "15.5 s is beyond the run's end (time.duration_s = 15 s)"),
    ([{**SNAP, "at_s": -1.0}], "faults[1].at_s", "between 0 and 1e6 s"),
    ([{**SNAP, "at_s": math.nan}], "faults[1].at_s", "finite"),
    ([{**SNAP, "lasting_s": 3.0}], "faults[1].lasting_s", "unknown key"),
    ([{**SNAP, "duration_s": 3.0}], "faults[1].duration_s", "is for a sensor's faults (load_cell, encoder, mru), not a "
                                                            "cable_snap"),
    ([{"kind": "cable_snap", "at_s": 1.0}], "faults[1].cable", "missing"),
    ([SNAP, {**SNAP, "at_s": 9.0}], "faults[2].cable", "cable 2 snaps once: it is listed twice"),
])
def test_fault_mistake_is_one_line_naming_the_key(faults, key, says):
    with pytest.raises(ScenarioError) as err:
        with_faults(*faults)
    text = str(err.value)
    assert "\n" not in text and f"faults.toml: {key}" in text and says in text, text


def test_fault_beyond_the_robot_exits_2_in_one_line(tmp_path):
    d = paper_dict()
    d["faults"] = [{**SNAP, "cable": 9}]
    path = tmp_path / "broken.toml"
    path.write_text(tomli_w.dumps(d))
    res = CliRunner().invoke(app, ["check", str(path)])
    assert res.exit_code == 2, res.output
    assert "faults[1].cable: the robot has 4 cables" in res.output and "Traceback" not in res.output
