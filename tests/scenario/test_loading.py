"""Scenario validation: every mistake is one line naming the key; good files load."""

import numpy as np
import pytest

import marinecdpr
from marinecdpr import ScenarioError

from conftest import make_scenario, paper_dict


def test_paper_scenario_reads_as_the_model_notes_say(paper):
    r = paper.robot
    np.testing.assert_array_equal(r.frame_anchors, [[0, 0, 1.4], [1.9, 0, 1.4], [1.9, 0, 0], [0, 0, 0]])
    np.testing.assert_array_equal(r.platform_anchors[0], [-0.125, 0, 0.15])
    np.testing.assert_array_equal(r.inertia, np.diag([0.03, 0.03, 0.06]))
    np.testing.assert_array_equal(r.tension_min, 10.0)
    np.testing.assert_array_equal(r.tension_max, 450.0)
    assert paper.time.n_steps == 15001 and paper.ship.frame_origin_m == (-0.78, 0.0, 2.2)
    # x_PO(0) = x_CS + x_PC(0) = [0.2, 0, 2.9] m with the ship level (MODEL_NOTES)
    p = marinecdpr.plan(paper.with_changes(time={"step_s": 0.001, "duration_s": 0.001}))
    np.testing.assert_allclose(np.asarray(paper.ship.frame_origin_m) + p.pose[0, :3], [0.2, 0, 2.9])


CASES = {
    "unknown key": (lambda d: d["robot"].update(mass=5.0),
                    "robot.mass: unknown key; did you mean 'mass_kg'?"),
    "wrong shape": (lambda d: d["robot"]["cables"][2].update(frame_anchor_m=[1.9, 0.0]),
                    "robot.cables[3].frame_anchor_m: expected 3 numbers [x, y, z], got 2"),
    "non-number": (lambda d: d["robot"].update(mass_kg="5"),
                   "robot.mass_kg: Input should be a valid number (got '5')"),
    "negative mass": (lambda d: d["robot"].update(mass_kg=-5.0),
                      "robot.mass_kg: must be between 0.001 and 100000 kg"),
    "asymmetric inertia": (lambda d: d["robot"].update(inertia_kg_m2=[[0.03, 0.01, 0], [0, 0.03, 0], [0, 0, 0.06]]),
                           "robot.inertia_kg_m2: inertia matrix is not symmetric"),
    "indefinite inertia": (lambda d: d["robot"].update(inertia_kg_m2=[0.03, -0.03, 0.06]),
                           "robot.inertia_kg_m2: inertia is not positive definite"),
    "unphysical inertia": (lambda d: d["robot"].update(inertia_kg_m2=[0.01, 0.01, 0.06]),
                           "robot.inertia_kg_m2: no rigid body has this inertia"),
    "inertia of text": (lambda d: d["robot"].update(inertia_kg_m2="abc"),
                        "robot.inertia_kg_m2: expected 3 principal moments or a 3x3 matrix of numbers, got 'abc'"),
    "vector of text": (lambda d: d["robot"]["cables"][0].update(frame_anchor_m=[0, "a", 1]),
                       "robot.cables[1].frame_anchor_m[2]: Input should be a valid number (got 'a')"),
    "T_min >= T_max": (lambda d: d["robot"]["cables"][1].update(tension_min_N=500.0),
                       "robot.cables[2]: tension_min_N (500) must be below tension_max_N (450)"),
    "too few cables": (lambda d: d["robot"].update(cables=d["robot"]["cables"][:2]),
                       "robot.cables: 2 cables cannot control the 3 degrees of freedom"),
    "shared anchor": (lambda d: d["robot"]["cables"][3].update(frame_anchor_m=[1.9, 0.0, 0.0]),
                      "robot.cables[4].frame_anchor_m: same frame anchor as cable 3"),
    "wrong unit": (lambda d: d["base_motion"]["components"][0].update(amplitude_m=6.0),
                   "base_motion.components[1].amplitude_m: roll is an angle: give amplitude_deg"),
    "unknown type": (lambda d: d["trajectory"].update(type="spiral"),
                     "trajectory.type: expected one of 'circle', 'coverage', 'line', 'waypoints' (got 'spiral')"),
    "misspelt key": (lambda d: d.update(trajectory=dict(type="line", start_position_m=[0.5, 0, 0.5],
                                                        end_position_m=[1, 0, 1], duraton_s=3.0)),
                     "trajectory.duraton_s: unknown key; did you mean 'duration_s'?"),
    "planar rotation": (lambda d: d["trajectory"].update(orientation_deg=[5.0, 0.0, 0.0]),
                        "trajectory.orientation_deg: a planar robot turns only about y"),
    "not finite": (lambda d: d["time"].update(step_s=float("nan")),
                   "time.step_s: must be a finite number between 1e-5 and 1 s"),
    "waypoint times": (lambda d: d.update(trajectory=dict(type="waypoints", waypoints=[
        dict(time_s=0.0, position_m=[0.5, 0, 0.5]), dict(time_s=0.0, position_m=[0.6, 0, 0.5])])),
                       "trajectory.waypoints[2].time_s: must be later than waypoint 1's"),
    "missing section": (lambda d: d.pop("time"), "time: missing"),
}


@pytest.mark.parametrize("name", list(CASES))
def test_bad_input_names_file_and_key(name):
    edit, expected = CASES[name]
    with pytest.raises(ScenarioError) as info:
        make_scenario(edit)
    text = str(info.value)
    assert text.startswith("test: " + expected), text
    assert "\n" not in text and isinstance(info.value, ValueError)


def test_trajectory_leaving_the_frame_is_named_at_plan_time():
    # centre x 1.0 + radius 0.9 puts P at x = 1.9 m at t = 0, anchor 2 at 1.9 + 0.125 m
    sc = make_scenario(lambda d: d["trajectory"].update(center_m=[1.0, 0.0, 0.7], radius_m=0.9))
    with pytest.raises(ScenarioError, match=r"trajectory: the platform leaves the frame at t = 0\.000 s: "
                                            r"platform anchor 2 is at x = 2\.025 m"):
        marinecdpr.plan(sc)


def test_files_and_builtin_names(tmp_path):
    assert "paper" in marinecdpr.builtin_scenarios()
    with pytest.raises(ScenarioError, match="no such file, and no built-in scenario"):
        marinecdpr.load_scenario(tmp_path / "nope.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text("[robot\nmass_kg = 5")
    with pytest.raises(ScenarioError, match=r"bad\.toml: not valid TOML"):
        marinecdpr.load_scenario(bad)


def test_robot_level_limits_are_defaults_per_cable_overrides():
    sc = make_scenario(lambda d: d["robot"]["cables"][0].update(tension_max_N=300.0))
    np.testing.assert_array_equal(sc.robot.tension_max, [300.0, 450.0, 450.0, 450.0])
    data = paper_dict()
    del data["robot"]["tension_min_N"]
    with pytest.raises(ScenarioError, match=r"robot\.cables\[1\]\.tension_min_N: missing"):
        make_scenario(lambda d: d.update(robot=data["robot"]))


def test_the_example_file_is_the_builtin_paper_scenario():
    from importlib import resources
    from pathlib import Path

    example = Path(__file__).resolve().parents[2] / "examples" / "paper.toml"
    assert example.read_text() == (resources.files("marinecdpr.scenario") / "builtin" / "paper.toml").read_text()


def test_with_updates_changes_one_subsection_and_keeps_the_rest(paper):
    sc = paper.with_updates("simulation.mru", latency_s=0.02, prediction="ar")
    assert sc.simulation.mru.latency_s == 0.02 and sc.simulation.mru.prediction == "ar"
    assert sc.simulation.mru.rate_hz == paper.simulation.mru.rate_hz
    assert sc.simulation.control == paper.simulation.control and sc.robot == paper.robot
    # None removes a key: its default applies
    sc = paper.with_updates("robot", winch=dict(drum_radius_m=0.05, gear_ratio=10.0, torque_max_Nm=2.0,
                                                speed_max_rad_s=300.0, power_max_W=200.0))
    assert sc.robot.winch.gear_ratio == 10.0
    assert sc.with_updates("robot", winch=None).robot.winch is None
    # a bad value is one line naming the key, as from a file
    with pytest.raises(ScenarioError, match=r"simulation\.mru\.latency_s"):
        paper.with_updates("simulation.mru", latency_s=-1.0)
