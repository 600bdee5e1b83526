"""The faults command's contract (:mod:`marinecdpr.commands.faults`): its spec without the
command line (one line naming the option at fault), and the checks that need the scenario
made before any flight (a cable beyond the robot, a fault its winches cannot have, a time
beyond the record), then the moments and cases it will fly."""

from __future__ import annotations

import numpy as np
import pytest

import marinecdpr
from marinecdpr.commands import SpecError
from marinecdpr.commands import faults as command
from marinecdpr.commands.faults import FaultsSpec


@pytest.mark.parametrize("options, words", [
    ({"kinds": "snap,magic"}, "--kinds magic: no such fault kind: expected snap, brake, power, load_cell, encoder, "
                              "mru, stall, brush, deadline"),
    ({"kinds": "snap,cable_snap"}, "--kinds cable_snap: a fault kind given twice"),
    ({"cables": "1,0"}, "--cables 1,0: expected cable numbers from 1, separated by commas"),
    ({"cables": "2,2"}, "--cables 2,2: a cable given twice"),
    ({"at": "3,-1"}, "--at 3,-1: expected times >= 0 s, separated by commas"),
    ({"after": 0.0}, "--after 0: expected a positive number"),
    ({"sensor_mode": "melt"}, "--sensor-mode melt: expected one of freeze, drift, dropout, non_finite"),
    ({"plant": "gazebo"}, "--plant gazebo: expected mujoco or own"),
    ({"brake_delay": 0.1}, "--brake-delay 0.1: is for the winch faults (brake, power): add one to --kinds"),
    ({"deadline_steps": 0}, "--deadline-steps 0: expected at least 1 exchange"),
])
def test_a_bad_option_is_one_line_naming_its_flag(options, words):
    with pytest.raises(SpecError) as err:
        FaultsSpec(**options)
    assert f"{err.value.flag} {err.value.value}: {err.value.detail}" == words


@pytest.fixture(scope="module")
def clean4():
    sc = marinecdpr.load_scenario("paper_clean")
    return sc.with_changes(time={"step_s": sc.time.step_s, "duration_s": 2.0})


@pytest.mark.parametrize("options, words", [
    ({"cables": (2, 5)}, "--cables 5: the robot has 4 cables (1 to 4)"),
    ({"at": (0.5, 1.5)}, "--at 1.5: beyond the record: the job's 2 s less --after 1 s leaves faults up to 1 s"),
    ({"after": 1.95}, "--after 1.95: leaves no moment to strike in the job's 2 s"),
    ({"kinds": "power"}, "--kinds power: a motor_power_loss needs motor winches"),
    ({"kinds": "snap,stall"}, "--kinds stall: a winch_stall needs motor winches"),
    ({"duration": 5.0}, "--duration 5: beyond the job's 2 s"),
    ({"hs": "1,31"}, "--hs 31: "),
])
def test_the_estimate_refuses_what_the_scenario_cannot_take(clean4, options, words):
    spec = FaultsSpec(**{"after": 1.0, **options})
    with pytest.raises(SpecError) as err:
        command.estimate(spec, clean4)
    said = f"{err.value.flag} {err.value.value}: {err.value.detail}"
    assert said.startswith(words) and "\n" not in said, said


def test_the_estimate_flies_each_cable_at_each_moment_and_a_deadline_once(clean4):
    """Four kinds (snap on cables 1 and 3; the MRU, the brush and the controller's deadline, no
    cable's, once) at two given times: (2 + 1 + 1 + 1) x 2 cases, in the order moment, kind, cable; the sea
    the scenario's own. Two sea states given (--hs 1,1.5 with one --tp): each flown with its
    own plan and moments."""
    est = command.estimate(FaultsSpec(kinds="snap,mru,brush,deadline", cables="1,3", at="0.2,0.6", after=1.0), clean4)
    [cases] = est.cases
    assert [(c.kind, c.cable, c.at_s) for c in cases] == [
        ("cable_snap", 1, 0.2), ("cable_snap", 3, 0.2), ("mru", None, 0.2), ("brush_contact_loss", None, 0.2),
        ("controller_deadline", None, 0.2),
        ("cable_snap", 1, 0.6), ("cable_snap", 3, 0.6), ("mru", None, 0.6), ("brush_contact_loss", None, 0.6),
        ("controller_deadline", None, 0.6)]
    assert est.seas == ({"hs_m": 2.0, "tp_s": 8.0, "heading_deg": 150.0},) and est.plant == "mujoco"
    est = command.estimate(FaultsSpec(hs="1,1.5", tp=6.0, after=1.0, plant="own"), clean4)
    assert est.seas == ({"hs_m": 1.0, "tp_s": 6.0, "heading_deg": 150.0},
                        {"hs_m": 1.5, "tp_s": 6.0, "heading_deg": 150.0}) and est.plant == "own"
    assert [sc.base_motion.hs_m for sc in est.flown] == [1.0, 1.5] and est.flown[1].faults == []
    assert not np.array_equal(est.plans[0].tensions, est.plans[1].tensions)
    for cases in est.cases:
        assert {c.moment for c in cases} <= {"highest tension", "highest speed"} and len(cases) % 4 == 0


def test_sea_states_given_as_lists_go_together_or_not_at_all():
    with pytest.raises(SpecError) as err:
        FaultsSpec(hs="1,2,3", tp="6,7")
    assert (err.value.flag, err.value.value) == ("--tp", "6,7")
    assert err.value.detail == "give one value or as many as the longest of --hs, --tp, --heading (3)"
    assert FaultsSpec(hs="1,2", heading=90.0).seas() == [{"hs_m": 1.0, "heading_deg": 90.0},
                                                         {"hs_m": 2.0, "heading_deg": 90.0}]


def test_a_sea_state_on_a_scenario_without_one_is_refused():
    with pytest.raises(SpecError, match="^hs 1: needs a \\[base_motion\\] of type sea_state, not sinusoidal$") \
            as err:
        command.estimate(FaultsSpec(hs=1.0), marinecdpr.load_scenario("paper"))
    assert err.value.flag == "--hs"


@pytest.mark.figures
def test_the_page_runs_as_written_and_lists_the_spec(tmp_path, monkeypatch):
    """docs/commands/faults.md: its example flies cable 1 of paper_clean snapping at the two
    moments of its first 2 s, each leaving the frame (four cables); its table is the spec."""
    from command_pages import assert_table_is_the_spec, run_page

    ns = run_page("faults", tmp_path, monkeypatch)
    assert len(ns["verdicts"]) == 2 and all(v.startswith("leaves the frame") for v in ns["verdicts"])
    assert {p.name for p in ns["files"]} == {"faults.csv", "summary.json", "faults.png", "report.html"}
    assert_table_is_the_spec("faults", FaultsSpec)
