"""A cable's breaking load (issue 40, item 4): ``[robot] breaking_load_N`` for every cable and
``[[robot.cables]] breaking_load_N`` for one, optional, in N, above 0 and finite, and not below
that cable's working limit ``tension_max_N``; ``Robot.breaking_load`` the given value, or
where none is given (unknown) the working limit. Every mistake is one line naming the key and
the cable (exit 2 from the CLI)."""

from __future__ import annotations

import math

import numpy as np
import pytest
import tomli_w
from typer.testing import CliRunner

from marinecdpr import ScenarioError
from marinecdpr.cli.app import app
from marinecdpr.scenario.loading import scenario_from_dict

from conftest import paper_dict


def robot_with(robot=None, **cables):
    """paper's robot (T_max 450 N for every cable) with ``robot``'s keys, and ``cable2={...}``
    set on cable 2 (counted from 1)."""
    d = paper_dict()
    d["robot"].update(robot or {})
    for name, keys in cables.items():
        d["robot"]["cables"][int(name.removeprefix("cable")) - 1].update(keys)
    return scenario_from_dict(d, source="robot.toml").robot


def test_without_a_breaking_load_the_working_limit_stands_in():
    """paper gives none: each cable's breaking load is its T_max (450 N; cable 3's own 600 N
    where it has its own), and none is said to be given."""
    r = robot_with(cable3={"tension_max_N": 600.0})
    assert r.breaking_load.tolist() == [450.0, 450.0, 600.0, 450.0] == r.tension_max.tolist()
    assert not r.breaking_load_given.any()


def test_the_robot_s_breaking_load_is_every_cable_s_and_a_cable_s_own_overrides_it():
    r = robot_with({"breaking_load_N": 2000.0}, cable2={"breaking_load_N": 3000.0})
    assert r.breaking_load.tolist() == [2000.0, 3000.0, 2000.0, 2000.0] and r.breaking_load_given.all()
    assert r.tension_max.tolist() == [450.0] * 4  # the working limit is untouched
    # one cable's own and no default: that cable's is given, the others' working limits stand in
    r = robot_with(cable4={"breaking_load_N": 900.0})
    assert r.breaking_load.tolist() == [450.0, 450.0, 450.0, 900.0]
    assert r.breaking_load_given.tolist() == [False, False, False, True]


def test_a_breaking_load_equal_to_the_working_limit_is_taken():
    """A safety factor of 1: the edge of the cross-check passes."""
    assert robot_with({"breaking_load_N": 450.0}).breaking_load.tolist() == [450.0] * 4
    assert robot_with(cable1={"breaking_load_N": 450.0}).breaking_load[0] == 450.0


@pytest.mark.parametrize("robot, cables, key, says", [
    ({"breaking_load_N": 300.0}, {}, "robot.breaking_load_N",
     "must not be below cable 1's tension_max_N (450 N), got 300 N (a working limit is at most the breaking load)"),
    ({}, {"cable2": {"breaking_load_N": 449.0}}, "robot.cables[2].breaking_load_N",
     "must not be below the cable's tension_max_N (450 N), got 449 N (a working limit is at most the breaking load)"),
    # the default against a cable's own, higher working limit: that cable named
    ({"breaking_load_N": 500.0}, {"cable3": {"tension_max_N": 600.0}}, "robot.breaking_load_N",
     "must not be below cable 3's tension_max_N (600 N), got 500 N"),
    # the cable's own against the robot's working limit, which it inherits
    ({"tension_max_N": 800.0}, {"cable4": {"breaking_load_N": 700.0}}, "robot.cables[4].breaking_load_N",
     "must not be below the cable's tension_max_N (800 N), got 700 N"),
    ({"breaking_load_N": 0.0}, {}, "robot.breaking_load_N", "must be above 0 and at most 1e9 N"),
    ({"breaking_load_N": -5.0}, {}, "robot.breaking_load_N", "must be above 0 and at most 1e9 N"),
    ({"breaking_load_N": 2e9}, {}, "robot.breaking_load_N", "got 2e9"),
    ({"breaking_load_N": math.inf}, {}, "robot.breaking_load_N", "must be a finite number above 0"),
    ({}, {"cable1": {"breaking_load_N": math.nan}}, "robot.cables[1].breaking_load_N", "must be a finite number"),
    ({}, {"cable1": {"breaking_load_N": "30 kN"}}, "robot.cables[1].breaking_load_N", "valid number"),
    ({"breaking_load": 3000.0}, {}, "robot.breaking_load", "did you mean 'breaking_load_N'?"),
])
def test_a_bad_breaking_load_is_one_line_naming_the_key_and_cable(robot, cables, key, says):
    with pytest.raises(ScenarioError) as err:
        robot_with(robot, **cables)
    text = str(err.value)
    assert "\n" not in text and f"robot.toml: {key}: " in text and says in text, text


def test_a_cable_s_own_breaking_load_spares_it_the_default_s_check():
    """The default below cable 3's T_max does not stand for cable 3, which has its own."""
    r = robot_with({"breaking_load_N": 500.0}, cable3={"tension_max_N": 600.0, "breaking_load_N": 650.0})
    assert r.breaking_load.tolist() == [500.0, 500.0, 650.0, 500.0]
    np.testing.assert_array_less(r.tension_max, r.breaking_load + 1e-12)


def test_check_refuses_a_breaking_load_below_the_working_limit_in_one_line_exit_2(tmp_path):
    d = paper_dict()
    d["robot"]["cables"][1]["breaking_load_N"] = 100.0
    path = tmp_path / "weak.toml"
    path.write_text(tomli_w.dumps(d))
    res = CliRunner().invoke(app, ["check", str(path)])
    lines = res.output.strip().splitlines()
    assert res.exit_code == 2 and len(lines) == 1, res.output
    assert "robot.cables[2].breaking_load_N: must not be below the cable's tension_max_N (450 N), got 100 N" in lines[0]
