"""Hostile input (issue 9): values nobody could mean and degenerate robots are refused at load
time, in one line naming the key and the allowed range (or the geometric reason)."""

from __future__ import annotations

import copy
import re
import tomllib
from importlib import resources
from pathlib import Path

import pytest
from typer.testing import CliRunner

import marinecdpr
from marinecdpr import ScenarioError
from marinecdpr.cli.app import app
from marinecdpr.scenario.loading import scenario_from_dict

from conftest import paper_dict

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
NAN, INF = float("nan"), float("inf")


def cube_dict() -> dict:
    """examples/spatial_cube8.toml as nested dicts (a fresh copy to edit)."""
    return tomllib.loads((EXAMPLES / "spatial_cube8.toml").read_text())


def sea_dict() -> dict:
    """The built-in paper_sea scenario (JONSWAP, its BEM RAO table) as nested dicts, the
    table's path made absolute."""
    builtin = resources.files("marinecdpr.scenario") / "builtin"
    d = copy.deepcopy(tomllib.loads((builtin / "paper_sea.toml").read_text()))
    d["base_motion"]["rao"]["file"] = str(builtin / d["base_motion"]["rao"]["file"])
    return d


def recorded_dict() -> dict:
    """The paper scenario on a recorded motion (any existing file: read only when used)."""
    d = paper_dict()
    d["base_motion"] = {"type": "recorded", "file": __file__}
    return d


BASES = {"paper": paper_dict, "cube": cube_dict, "sea": sea_dict, "recorded": recorded_dict}


def build(base: str, edit) -> marinecdpr.Scenario:
    data = BASES[base]()
    edit(data)
    return scenario_from_dict(data, source="test")


def at(path: str, value):
    """An edit that sets one dotted key (list entries counted from 1) to value."""
    def edit(d):
        node = d
        *parents, last = path.split(".")
        for part in parents:
            m = re.fullmatch(r"(\w+)\[(\d+)\]", part)
            node = node[m[1]][int(m[2]) - 1] if m else node.setdefault(part, {})
        node[last] = value
    return edit


def each_cable(key: str, fn):
    """An edit that sets key of cable i (from 0) to fn(i, cable)."""
    def edit(d):
        for i, cable in enumerate(d["robot"]["cables"]):
            cable[key] = fn(i, cable)
    return edit


def heave(amplitude):
    return lambda d: d["base_motion"]["components"].append(
        {"dof": "heave", "amplitude_m": amplitude, "period_s": 6.0})


def circle(**kw):
    return lambda d: d["trajectory"].update(kw)


def line(**kw):
    return lambda d: d.update(trajectory={"type": "line", "start_position_m": [0.5, 0.0, 0.5],
                                          "end_position_m": [1.0, 0.0, 0.8], "duration_s": 3.0} | kw)


def waypoints(t2, position=(0.6, 0.0, 0.5)):
    return lambda d: d.update(trajectory={"type": "waypoints", "waypoints": [
        {"time_s": 0.0, "position_m": [0.5, 0.0, 0.5]}, {"time_s": t2, "position_m": list(position)}]})


def cables_along_x(i, cable):
    return [0.25 * i, 0.0, 0.0]


def shrink(factor):
    return lambda i, cable: [factor * v for v in cable["platform_anchor_m"]]


# name: (base scenario, edit, the key, what the message must say)
CASES = {
    # the robot
    "anchor at 1e300 m": ("paper", at("robot.cables[1].frame_anchor_m", [1e300, 0.0, 1.4]),
                          "robot.cables[1].frame_anchor_m", "between -10000 and 10000 m"),
    "platform anchor at -1e12 m": ("cube", at("robot.cables[3].platform_anchor_m", [0.1, -1e12, 0.1]),
                                   "robot.cables[3].platform_anchor_m", "got y = -1e12"),
    "1001 cables": ("cube", lambda d: d["robot"].update(cables=[
        {"frame_anchor_m": [0.002 * i, 0.1 * (i % 7), 0.1 * (i % 11)], "platform_anchor_m": [1e-4 * i, 0.0, 0.01 * (i % 3)]}
        for i in range(1001)]), "robot.cables", "must be between 6 and 1000 cables"),
    "mass of 1e300 kg": ("paper", at("robot.mass_kg", 1e300), "robot.mass_kg",
                         "between 0.001 and 100000 kg"),
    "mass of 1e-12 kg": ("paper", at("robot.mass_kg", 1e-12), "robot.mass_kg", "got 1e-12"),
    "mass of 0 kg": ("cube", at("robot.mass_kg", 0), "robot.mass_kg", "between 0.001 and 100000 kg"),
    "inertia of 1e300": ("paper", at("robot.inertia_kg_m2", [1e300, 1e300, 1e300]), "robot.inertia_kg_m2",
                         "principal moments must be between 5e-8 and 5e8 kg m^2 for a 5 kg platform"),
    "inertia of 1e-300": ("cube", at("robot.inertia_kg_m2", [1e-300, 1e-300, 1e-300]),
                          "robot.inertia_kg_m2", "radii of gyration from 0.0001 to 10000 m"),
    "tension of 1e300 N": ("paper", at("robot.tension_max_N", 1e300), "robot.tension_max_N",
                           "above 0 and at most 1e7 N"),
    "negative tension": ("paper", at("robot.cables[2].tension_min_N", -1.0), "robot.cables[2].tension_min_N",
                         "between 0 and 1e7 N"),
    # the ship and its motion
    "frame origin at 1e300 m": ("paper", at("ship.frame_origin_m", [0.0, 0.0, 1e300]), "ship.frame_origin_m",
                                "between -10000 and 10000 m"),
    "heave of 1e300 m": ("paper", heave(1e300), "base_motion.components[4].amplitude_m", "between 0 and 30 m"),
    "negative heave": ("paper", heave(-1.0), "base_motion.components[4].amplitude_m", "between 0 and 30 m"),
    "roll of 5000 deg": ("paper", at("base_motion.components[1].amplitude_deg", 5000.0),
                         "base_motion.components[1].amplitude_deg", "between 0 and 180 deg"),
    "roll of 120 deg": ("paper", at("base_motion.components[1].amplitude_deg", 120.0),
                        "base_motion.components[1].amplitude_deg", "between 0 and 90 deg for roll"),
    "pitch offset of -100 deg": ("paper", at("base_motion.components[2].offset_deg", -100.0),
                                 "base_motion.components[2].offset_deg", "between -90 and 90 deg for pitch"),
    "yaw of 1000 deg": ("paper", at("base_motion.components[3].amplitude_deg", 1000.0),
                        "base_motion.components[3].amplitude_deg", "between 0 and 180 deg"),
    "period of a microsecond": ("paper", at("base_motion.components[1].period_s", 1e-6),
                                "base_motion.components[1].period_s", "between 0.5 and 3600 s"),
    "period of 1e9 s": ("cube", at("base_motion.components[2].period_s", 1e9),
                        "base_motion.components[2].period_s", "between 0.5 and 3600 s"),
    "phase of 1e300 deg": ("paper", at("base_motion.components[1].phase_deg", 1e300),
                           "base_motion.components[1].phase_deg", "between -360 and 360 deg"),
    "Hs of 1e-300 m": ("sea", at("base_motion.hs_m", 1e-300), "base_motion.hs_m", "between 0.01 and 30 m"),
    "Hs of 1e300 m": ("sea", at("base_motion.hs_m", 1e300), "base_motion.hs_m", "between 0.01 and 30 m"),
    "Tp of 1e9 s": ("sea", at("base_motion.tp_s", 1e9), "base_motion.tp_s", "between 1 and 40 s"),
    "Tp of 1e-3 s": ("sea", at("base_motion.tp_s", 1e-3), "base_motion.tp_s", "between 1 and 40 s"),
    "gamma of 1e300": ("sea", at("base_motion.gamma", 1e300), "base_motion.gamma", "between 1 and 10"),
    "heading of 1e300 deg": ("sea", at("base_motion.heading_deg", 1e300), "base_motion.heading_deg",
                             "between -360 and 360 deg"),
    "spreading exponent of 1e300": ("sea", at("base_motion.spreading_exponent", 1e300),
                                    "base_motion.spreading_exponent", "above 0 and at most 100"),
    "record of 1e12 s": ("sea", at("base_motion.record_s", 1e12), "base_motion.record_s",
                         "between 60 and 10800 s"),
    "record too fine for Tp": ("sea", lambda d: d["base_motion"].update(record_s=10800.0, tp_s=1.0),
                               "base_motion.record_s", "sums 64800 wave frequencies (6 record_s / tp_s), more than 12000: make record_s at most 2000 s"),
    "hull of 1e300 m": ("sea", at("base_motion.rao.length_m", 1e300), "base_motion.rao.length_m",
                        "between 1 and 1000 m"),
    "GM of 0": ("sea", at("base_motion.rao.gm_m", 0.0), "base_motion.rao.gm_m", "between 0.01 and 100 m"),
    "roll damping of 0": ("sea", at("base_motion.rao.roll_damping_ratio", 0.0),
                          "base_motion.rao.roll_damping_ratio", "between 0.01 and 1 "),
    "smoothing of 1e300 s": ("recorded", at("base_motion.smoothing_s", 1e300), "base_motion.smoothing_s",
                             "above 0 and at most 60 s"),
    "record start at 1e12 s": ("recorded", at("base_motion.start_s", 1e12), "base_motion.start_s",
                               "between 0 and 1e6 s"),
    # the trajectory
    "circle of 1e300 m": ("paper", circle(radius_m=1e300), "trajectory.radius_m", "at most 10000 m"),
    "circle in 1e-12 s": ("paper", circle(period_s=1e-12), "trajectory.period_s", "between 0.01 and 1e6 s"),
    "circle centre at 1e300 m": ("paper", circle(center_m=[1e300, 0.0, 0.7]), "trajectory.center_m",
                                 "between -10000 and 10000 m"),
    "tilt of 5000 deg": ("paper", circle(orientation_deg=[0.0, 5000.0, 0.0]), "trajectory.orientation_deg",
                         "between -180 and 180 deg"),
    "line in 1e-12 s": ("paper", line(duration_s=1e-12), "trajectory.duration_s", "between 0.01 and 1e6 s"),
    "line starting at 1e12 s": ("paper", line(start_time_s=1e12), "trajectory.start_time_s",
                                "between 0 and 1e6 s"),
    "line ending after 1e6 s": ("paper", line(start_time_s=9e5, duration_s=2e5), "trajectory.duration_s",
                                "must end by 1e6 s"),
    "waypoint at 1e12 s": ("paper", waypoints(1e12), "trajectory.waypoints[2].time_s", "between 0 and 1e6 s"),
    "waypoints 1 ns apart": ("paper", waypoints(1e-9), "trajectory.waypoints[2].time_s",
                             "by at least 0.01 s"),
    # the rest
    "force of 1e300 N": ("paper", at("disturbance.force_N", [0.0, 0.0, 1e300]), "disturbance.force_N",
                         "between -1e8 and 1e8 N"),
    "moment of -1e300 N m": ("cube", at("disturbance.moment_amplitude_N_m", [-1e300, 0.0, 0.0]),
                             "disturbance.moment_amplitude_N_m", "between -1e9 and 1e9 N m"),
    "disturbance period of 1e-12 s": ("paper", at("disturbance.period_s", 1e-12), "disturbance.period_s",
                                      "between 0.001 and 1e6 s"),
    "step of 1e-12 s": ("paper", at("time.step_s", 1e-12), "time.step_s", "between 1e-5 and 1 s"),
    "step of 0 s": ("cube", at("time.step_s", 0), "time.step_s", "between 1e-5 and 1 s"),
    "step of 10 s": ("paper", at("time.step_s", 10.0), "time.step_s", "between 1e-5 and 1 s"),
    "duration of 1e12 s": ("paper", at("time.duration_s", 1e12), "time.duration_s", "above 0 and at most 1e6 s"),
    "negative duration": ("cube", at("time.duration_s", -1.0), "time.duration_s", "above 0 and at most 1e6 s"),
    "EA of 1e300 N": ("paper", at("simulation.cables", {"model": "elastic", "stiffness_EA_N": 1e300}),
                      "simulation.cables.stiffness_EA_N", "between 1 and 1e10 N"),
    "cable damping of -1": ("paper", at("simulation.cables.damping_N_s_m", -1.0),
                            "simulation.cables.damping_N_s_m", "between 0 and 1e9 N s/m"),
    "winch lag of 1e6 s": ("paper", at("simulation.cables.winch_time_constant_s", 1e6),
                           "simulation.cables.winch_time_constant_s", "between 0 and 60 s"),
    "pose noise of 1e300 m": ("paper", at("simulation.noise.pose_m", 1e300), "simulation.noise.pose_m",
                              "between 0 and 10 m"),
    "negative tension noise": ("paper", at("simulation.noise.tension_N", -1.0), "simulation.noise.tension_N",
                               "between 0 and 1e7 N"),
    "bandwidth of 1e9 Hz": ("paper", at("simulation.control.bandwidth_hz", 1e9),
                            "simulation.control.bandwidth_hz", "between 0.001 and 1000 Hz"),
    "damping ratio of 0": ("paper", at("simulation.control.damping_ratio", 0.0),
                           "simulation.control.damping_ratio", "between 0.01 and 10 "),
    "initial error of 1e300 m": ("paper", at("simulation.initial_error_m", [1e300, 0.0, 0.0]),
                                 "simulation.initial_error_m", "between -100 and 100 m"),
    "initial error of 5000 deg": ("cube", at("simulation.initial_error_deg", [0.0, 0.0, 5000.0]),
                                  "simulation.initial_error_deg", "got rz = 5000"),
    "error bound of 0 m": ("paper", at("simulation.max_error_m", 0.0), "simulation.max_error_m",
                           "above 0 and at most 10000 m"),
    "gravity of 0": ("paper", at("environment.gravity_m_s2", 0.0), "environment.gravity_m_s2",
                     "between 0.1 and 30 m/s^2"),
    "gravity of 1e300": ("cube", at("environment.gravity_m_s2", 1e300), "environment.gravity_m_s2",
                         "between 0.1 and 30 m/s^2"),
    # not numbers at all
    "NaN mass": ("paper", at("robot.mass_kg", NAN), "robot.mass_kg",
                 "must be a finite number between 0.001 and 100000 kg (a platform from 1 g to 100 t), got nan"),
    "infinite period": ("paper", at("base_motion.components[2].period_s", INF),
                        "base_motion.components[2].period_s", "a finite number between 0.5 and 3600 s"),
    "NaN anchor": ("cube", at("robot.cables[8].frame_anchor_m", [0.0, NAN, 2.0]),
                   "robot.cables[8].frame_anchor_m", "a finite number between -10000 and 10000 m"),
    "infinite Hs": ("sea", at("base_motion.hs_m", INF), "base_motion.hs_m", "a finite number between 0.01 and 30 m"),
    "NaN noise": ("paper", at("simulation.noise.ship_angle_deg", NAN), "simulation.noise.ship_angle_deg",
                  "a finite number between 0 and 30 deg"),
    "negative motor torque noise": ("paper", at("simulation.noise.motor_torque_N_m", -0.01),
                                    "simulation.noise.motor_torque_N_m", "between 0 and 1e6 N m"),
    "NaN motor torque noise": ("paper", at("simulation.noise.motor_torque_N_m", NAN),
                               "simulation.noise.motor_torque_N_m", "a finite number between 0 and 1e6 N m"),
    "motor torque noise as a word": ("paper", at("simulation.noise.motor_torque_N_m", "2 %"),
                                     "simulation.noise.motor_torque_N_m", ""),
    "-inf orientation": ("cube", lambda d: d["trajectory"]["waypoints"][1].update(orientation_deg=[0.0, -INF, 0.0]),
                         "trajectory.waypoints[2].orientation_deg", "got ry = -inf"),
    # degenerate geometry
    "planar platform anchors 1 um apart": ("paper", each_cable("platform_anchor_m", shrink(4e-6)),
                                           "robot.cables", "cannot exert a moment on the platform about y"),
    "planar frame anchors at one point": ("paper", each_cable("frame_anchor_m", lambda i, c: [0.9, i, 0.7]),
                                          "robot.cables", "the frame anchors coincide in the x-z plane"),
    "collinear frame anchors": ("cube", each_cable("frame_anchor_m", cables_along_x), "robot.cables",
                                "the frame anchors lie on one line (along x)"),
    "frame anchors at two points 1 um apart": (
        "cube", each_cable("frame_anchor_m", lambda i, c: [2.0 * (i % 2), 2.0 * (i % 2) + 1e-6 * i, 2.0 * (i % 2)]),
        "robot.cables", "the frame anchors lie on one line (along [0.577, 0.577, 0.577], all within 2.45e-6 m"),
    "spatial platform anchors 1 um apart": ("cube", each_cable("platform_anchor_m", shrink(5e-6)),
                                            "robot.cables", "lie within 1.73e-6 m of each other"),
    "collinear platform anchors": ("cube", each_cable("platform_anchor_m", lambda i, c: [0.0, 0.0, 0.03 * i]),
                                   "robot.cables", "the platform anchors lie on one line (along z)"),
}


@pytest.mark.parametrize("name", list(CASES))
def test_a_value_nobody_could_mean_is_refused_with_its_range(name):
    base, edit, key, says = CASES[name]
    with pytest.raises(ScenarioError) as info:
        build(base, edit)
    text = str(info.value)
    assert text.startswith(f"test: {key}: "), text
    assert says in text and "\n" not in text, text
    assert info.value.key == key


@pytest.mark.parametrize("winch, noise, says", [
    ("length", 0.04, "needs motor winches (simulation.cables.winch = \"motor\"), got 0.04 N m"),
    ("motor", 2.0, "must be below the motor's torque limit (robot.winch.torque_max_Nm = 2 N m)"),
])
def test_a_motor_torque_noise_without_a_motor_or_as_large_as_its_torque_is_one_line(winch, noise, says):
    """The noise on a motor's measured torque (issue 40) needs motor winches, and is a sensor's
    standard deviation, below the motor's torque limit (paper_as_built's 2 N m)."""
    data = _builtin("paper_as_built")
    data["simulation"]["cables"]["winch"] = winch
    data["simulation"]["noise"] = {"motor_torque_N_m": noise}
    with pytest.raises(ScenarioError) as err:
        scenario_from_dict(data)
    text = str(err.value)
    assert "\n" not in text and "simulation.noise.motor_torque_N_m" in text and says in text, text
    data["simulation"]["noise"] = {"motor_torque_N_m": 1.99}
    if winch == "motor":
        assert scenario_from_dict(data).simulation.noise.motor_torque_N_m == 1.99


# the edge of a range passes, just beyond it is refused: (base, edit at the edge, edit beyond, the key)
EDGES = {
    "lightest platform": ("paper", lambda d: d["robot"].update(mass_kg=1e-3, inertia_kg_m2=[1e-5, 1e-5, 2e-5]),
                          lambda d: d["robot"].update(mass_kg=0.9e-3, inertia_kg_m2=[1e-5, 1e-5, 2e-5]),
                          "robot.mass_kg"),
    "roll of 90 deg": ("paper", at("base_motion.components[1].amplitude_deg", 90.0),
                       at("base_motion.components[1].amplitude_deg", 90.001), "base_motion.components[1].amplitude_deg"),
    "yaw of 180 deg": ("paper", at("base_motion.components[3].amplitude_deg", 180.0),
                       at("base_motion.components[3].amplitude_deg", 180.5), "base_motion.components[3].amplitude_deg"),
    "periods of 0.5 s and 1 h": ("cube", lambda d: (at("base_motion.components[1].period_s", 0.5)(d),
                                                    at("base_motion.components[2].period_s", 3600.0)(d)),
                                 at("base_motion.components[2].period_s", 3601.0), "base_motion.components[2].period_s"),
    "step of 10 us": ("paper", lambda d: d["time"].update(step_s=1e-5, duration_s=0.01),
                      lambda d: d["time"].update(step_s=0.9e-5, duration_s=0.01), "time.step_s"),
    "Tp of 1 s, Hs of 1 cm": ("sea", lambda d: d["base_motion"].update(tp_s=1.0, hs_m=0.01, record_s=1200.0),
                              lambda d: d["base_motion"].update(tp_s=1.0, hs_m=0.009, record_s=1200.0),
                              "base_motion.hs_m"),
    "gravity of 30 m/s^2": ("cube", at("environment.gravity_m_s2", 30.0), at("environment.gravity_m_s2", 31.0),
                            "environment.gravity_m_s2"),
    "frame 10 km from the ship's origin": ("paper", at("ship.frame_origin_m", [1e4, 0.0, -1e4]),
                                           at("ship.frame_origin_m", [1.0001e4, 0.0, 0.0]), "ship.frame_origin_m"),
    # a suspended planar robot (frame anchors on one line) controls x, z and theta_y; its platform
    # collapsed to 0.1 um does not
    "planar robot hanging from one line": (
        "paper", each_cable("frame_anchor_m", lambda i, c: [0.6 * i, 0.0, 1.4]),
        lambda d: (each_cable("frame_anchor_m", lambda i, c: [0.6 * i, 0.0, 1.4])(d),
                   each_cable("platform_anchor_m", shrink(1e-6))(d)), "robot.cables"),
    # uncrossed cables: singular at the frame's centre only, so a valid (if poor) robot; its frame
    # anchors squeezed onto the line x = y = z are not
    "spatial robot singular at one pose": (
        "cube", each_cable("platform_anchor_m", lambda i, c: [0.1 if v > 1 else -0.1 for v in c["frame_anchor_m"]]),
        each_cable("frame_anchor_m", lambda i, c: [0.25 * i] * 3), "robot.cables"),
}


@pytest.mark.parametrize("name", list(EDGES))
def test_the_edge_of_a_range_passes_and_just_beyond_is_refused(name):
    base, ok, beyond, key = EDGES[name]
    build(base, ok)
    with pytest.raises(ScenarioError) as info:
        build(base, beyond)
    assert info.value.key == key, str(info.value)


def test_shipped_scenarios_stay_valid_and_a_changed_copy_is_checked_too():
    for name in marinecdpr.builtin_scenarios():
        marinecdpr.load_scenario(name)
    cube = marinecdpr.load_scenario(EXAMPLES / "spatial_cube8.toml")
    with pytest.raises(ScenarioError, match=r"^time\.step_s: must be between 1e-5 and 1 s .*, got 1e-12$"):
        cube.with_changes(time={"step_s": 1e-12, "duration_s": 8.0})


runner = CliRunner()


@pytest.mark.parametrize("edit, says", [
    (lambda text: text.replace("mass_kg = 5.0", "mass_kg = 1e300"),
     "robot.mass_kg: must be between 0.001 and 100000 kg (a platform from 1 g to 100 t), got 1e300"),
    (lambda text: re.sub(r"platform_anchor_m( *)= \[([-0-9.]+), ([-0-9.]+), ([-0-9.]+)\]",
                         lambda m: f"platform_anchor_m = [{float(m[2]) * 1e-5}, {float(m[3]) * 1e-5}, "
                                   f"{float(m[4]) * 1e-5}]", text),
     "robot.cables: the platform anchors lie within 3.46e-6 m of each other, less than 0.0001 of the "
     "frame's size (3.46 m): the cables cannot exert a moment on the platform"),
], ids=["mass", "geometry"])
def test_check_refuses_in_one_line_with_exit_2(tmp_path, edit, says):
    scen = tmp_path / "hostile.toml"
    scen.write_text(edit((EXAMPLES / "spatial_cube8.toml").read_text()))
    res = runner.invoke(app, ["check", str(scen)])
    assert res.exit_code == 2, res.output
    assert res.stderr.strip().splitlines() == [f"error: {scen}: {says}"]
    assert "Traceback" not in res.stdout + res.stderr and isinstance(res.exception, SystemExit)


# -------------------- formerly tests/test_issue21_schema_values.py

"""Issue 21, items 19 and 20: unit vectors within a stated tolerance are normalised (not a
traceback deep in the geometry), and the scenario's types are strict (no string read as a
number or a bool)."""

import tomllib
from importlib import resources

import numpy as np
import pytest

from marinecdpr.errors import ScenarioError
from marinecdpr.planning.planner import plan
from marinecdpr.scenario.loading import scenario_from_dict


def _builtin(name: str) -> dict:
    folder = resources.files("marinecdpr.scenario") / "builtin"
    data = tomllib.loads((folder / f"{name}.toml").read_text())
    rao = data.get("base_motion", {}).get("rao")
    if rao is not None and "file" in rao:
        rao["file"] = str(folder / rao["file"])
    return data


def test_a_pulley_axis_a_hair_off_unit_length_is_normalised_and_plans():
    data = _builtin("paper_as_built")
    data["robot"]["cables"][0]["pulley_axis"] = [0.0, 0.0, -(1.0 + 1e-9)]
    data["time"]["duration_s"] = 0.05
    sc = scenario_from_dict(data)
    assert sc.robot.pulley_axes[0].tolist() == [0.0, 0.0, -1.0]  # exactly unit
    reference = scenario_from_dict({**data, "robot": _builtin("paper_as_built")["robot"]})
    # it refused with "swivel axes z_C must be unit vectors" (ValueError, a traceback) before
    assert np.array_equal(plan(sc).tensions, plan(reference).tensions)


def test_a_slanted_axis_within_the_tolerance_comes_out_unit():
    data = _builtin("paper_as_built")
    data["robot"]["cables"][1]["pulley_axis"] = [0.6, 0.0, 0.8 * (1.0 + 3e-7)]
    z = scenario_from_dict(data).robot.pulley_axes[1]
    assert abs(np.linalg.norm(z) - 1.0) < 1e-15
    assert z[0] / z[2] == pytest.approx(0.6 / (0.8 * (1.0 + 3e-7)), rel=1e-15)


def test_an_axis_beyond_the_tolerance_is_one_line_naming_the_key():
    data = _builtin("paper_as_built")
    data["robot"]["cables"][2]["pulley_axis"] = [0.0, 0.0, 1.0 + 1e-5]  # ten times the stated 1e-6
    with pytest.raises(ScenarioError) as err:
        scenario_from_dict(data)
    message = str(err.value)
    assert "\n" not in message and "pulley_axis" in message and "unit vector" in message


def test_a_hull_normal_a_hair_off_unit_length_is_normalised():
    data = _builtin("paper_clean")
    data["cleaning"]["hull_normal"] = [0.0, 1.0 - 5e-7, 0.0]
    assert scenario_from_dict(data).cleaning.hull_normal == (0.0, 1.0, 0.0)


@pytest.mark.parametrize(("key", "value"), [
    ("hull_normal", [0.0, "1.0", 0.0]),   # planned with exit 0 before
    ("boundary_pass", "yes"),             # planned with exit 0 before
    ("boundary_pass", "true"),
    ("boundary_pass", 1),
    ("hull_normal", [0.0, True, 0.0]),
])
def test_a_string_or_bool_for_a_number_or_a_bool_is_refused_naming_the_key(key, value):
    data = _builtin("paper_clean")
    data["cleaning"][key] = value
    with pytest.raises(ScenarioError) as err:
        scenario_from_dict(data)
    message = str(err.value)
    assert "\n" not in message and key in message


# -------------------- formerly tests/test_schema_list_caps.py

"""A list longer than its cap is named with its cap, not as a 3-vector (issue 37, item 19):
10 000 ``[[obstacles]]`` were refused as "expected 3 numbers [x, y, z], got 10000"."""


import pytest

from marinecdpr.errors import ScenarioError
from marinecdpr.scenario.loading import scenario_from_dict
from marinecdpr.scenario.obstacles import MAX_OBSTACLES
from tests.conftest import paper_dict


def _boxes(n: int) -> dict:
    d = paper_dict()
    d["robot"]["clearance_m"] = 0.0
    d["obstacles"] = [{"type": "box", "center_m": [0.001 * k, 3.0, 0.5], "size_m": [0.01, 0.01, 0.01]}
                      for k in range(n)]
    return d


@pytest.mark.parametrize("n", [MAX_OBSTACLES + 1, 10_000])
def test_more_obstacles_than_the_cap_are_refused_naming_the_cap(n):
    with pytest.raises(ScenarioError) as err:
        scenario_from_dict(_boxes(n))
    assert err.value.key == "obstacles" and err.value.detail == f"at most {MAX_OBSTACLES} entries, got {n}"


def test_the_cap_s_number_of_obstacles_loads():
    assert len(scenario_from_dict(_boxes(MAX_OBSTACLES)).obstacles) == MAX_OBSTACLES == 1000


@pytest.mark.parametrize("edit, key, detail", [
    (lambda d: d["robot"]["cables"][0].update(frame_anchor_m=[1.0, 2.0, 3.0, 4.0]), "robot.cables[1].frame_anchor_m",
     "expected 3 numbers [x, y, z], got 4"),
    (lambda d: d.update(cleaning={"panel_m": [[0.3, 0.3, 1.0], [1.6, 0.3], [1.6, 1.1]], "brush_diameter_m": 0.2,
                                  "speed_m_s": 0.1, "acceleration_m_s2": 0.3, "jerk_m_s3": 3.0,
                                  "normal_force_N": [40.0, 80.0], "friction": 0.4}),
     "cleaning.panel_m[1]", "expected 2 numbers, got 3"),
])
def test_a_vector_too_long_is_still_named_by_its_size(edit, key, detail):
    d = paper_dict()
    edit(d)
    with pytest.raises(ScenarioError) as err:
        scenario_from_dict(d)
    assert err.value.key == key and err.value.detail == detail


# -------------------- formerly tests/test_hostile_files.py

"""Hostile input files (issue 9, classes 3 and 7).

A recorded-motion or RAO file named by a scenario may be anything: binary, huge, a
folder, a pipe, /etc/passwd, numbers that overflow. Each is refused with one line
that names the file, the line and column and what was expected, and quotes nothing
from the file. What spreadsheets write (a byte-order mark, CRLF, rows of empty
cells) is read like the clean file. A scenario TOML nested 3000 levels deep, with NUL
bytes or not in UTF-8 is refused in one line too.
"""


import os
import re
import threading
from importlib import resources
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from marinecdpr.cli.app import app
from marinecdpr.errors import ScenarioError
from marinecdpr.motion.rao import RAO, read_capytaine, read_rao_csv, write_rao_csv
from marinecdpr.motion.recorded import MOTION_CSV_COLUMNS, read_motion_csv
from marinecdpr.scenario.loading import load_scenario, scenario_from_dict

from conftest import paper_dict

runner = CliRunner()
EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
SECRET = "s3cr3t"
PASSWD = ("root:x:0:0:root:/root:/bin/bash\ndaemon:x:1:1:daemon:/usr/sbin:/usr/sbin/nologin\n"
          f"alice:{SECRET}:1000:1000:Alice,,,:/home/alice:/bin/bash\n")
ENVIRON = f"HOME=/root\0PATH=/usr/bin\0API_TOKEN={SECRET}\0"
BASHRC = ("# ~/.bashrc: executed by bash(1) for non-login shells.\ncase $- in\n    *i*) ;;\n"
          f"      *) return;;\nesac\nexport API_TOKEN={SECRET}\n")
FILE_LEAKS = ("root", "bash", "daemon", "HOME", "PATH", "API_TOKEN", "esac", SECRET)


# ------------------------------------------------------------------------ clean files
def motion_lines() -> list[str]:
    """Header and 40 rows of a valid motion file (20 Hz, degrees)."""
    t = 0.05 * np.arange(40)
    s = np.sin(2 * np.pi * t / 8)
    eta = np.column_stack([0.1 * s, -0.2 * s, 0.5 * s, 3.0 * s, -2.0 * s, 40.0 + s])
    return [",".join(MOTION_CSV_COLUMNS)] + [",".join(f"{v:.10g}" for v in (ti, *e)) for ti, e in zip(t, eta)]


def rao_lines() -> list[str]:
    """Header and 24 rows of a valid RAO table: headings 0, 90 deg x omega 0.5, 1 rad/s x six DOFs."""
    rows = ["omega_rad_s,heading_deg,dof,amplitude,phase_deg"]
    for h in (0.0, 90.0):
        for w in (0.5, 1.0):
            for k, d in enumerate(("surge", "sway", "heave", "roll", "pitch", "yaw")):
                rows.append(f"{w},{h},{d},{0.5 + 0.1 * k},{10 * k - 20}")
    return rows


def text(lines: list[str], eol: str = "\n") -> bytes:
    return (eol.join(lines) + eol).encode()


def cell(lines: list[str], row: int, col: int, value: str) -> list[str]:
    """``lines`` with field ``col`` (from 0) of line index ``row`` (0 = header) replaced."""
    lines = list(lines)
    fields = lines[row].split(",")
    fields[col] = value
    lines[row] = ",".join(fields)
    return lines


def not_utf8(lines: list[str], row: int) -> bytes:
    """Latin-1 bytes (as a Windows editor writes 'ete' with accents) at the start of a line."""
    raw = [ln.encode() for ln in lines]
    raw[row] = b"\xe9t\xe9" + raw[row]
    return b"\n".join(raw) + b"\n"


def nul(lines: list[str], row: int) -> bytes:
    lines = list(lines)
    lines[row] = lines[row][:2] + "\0" + lines[row][2:]
    return text(lines)


def motion_times_scaled(factor: float) -> bytes:
    lines = motion_lines()
    for i in range(1, len(lines)):
        lines = cell(lines, i, 0, f"{factor * 0.05 * (i - 1):.10g}")
    return text(lines)


# --------------------------------------------------------------- cases: bad content
# name: (make the file's bytes, the message must match, extra strings it must not contain)
MOTION_BAD = {
    "NUL byte": (lambda: nul(motion_lines(), 3), r"line 4, column 3: a NUL byte", ()),
    "200 000-character field": (lambda: text(cell(motion_lines(), 2, 1, "1" * 200_000)),
                                r"line 3: longer than 10000 characters", ()),
    "150-character field": (lambda: text(cell(motion_lines(), 4, 1, SECRET * 25)),
                            r"line 5, field 2: over 100 characters", ()),
    "not UTF-8": (lambda: not_utf8(motion_lines(), 5), r"line 6, column 1: not UTF-8 text", ()),
    "UTF-16": (lambda: "\n".join(motion_lines()).encode("utf-16"), r"UTF-16 text; expected .* UTF-8", ()),
    "ANSI escape": (lambda: text(cell(motion_lines(), 3, 4, "\x1b[2J")), r"line 4, column \d+: a control character",
                    ("\x1b", "[2J")),
    "heave 1e300": (lambda: text(cell(motion_lines(), 3, 3, "1e300")),
                    r"line 4, column heave_m: 1e\+300 m is beyond 1000 m", ()),
    "yaw 1e300": (lambda: text(cell(motion_lines(), 3, 6, "1e300")),
                  r"line 4, column yaw: 1e\+300 deg is beyond 36000 deg", ()),
    "overflow to inf": (lambda: text(cell(motion_lines(), 3, 2, "1e999")),
                        r"line 4, column sway_m: 'inf' is not a finite number", ("1e999",)),
    "-NaN": (lambda: text(cell(motion_lines(), 5, 6, "-NaN")),
             r"line 6, column yaw: 'nan' is not a finite number", ("NaN",)),
    "time in hours": (lambda: motion_times_scaled(1e-5), r"line 3, column time_s: sampling interval 5e-07 s is below",
                      ()),
    "text in a cell": (lambda: text(cell(motion_lines(), 3, 3, SECRET)), r"line 4, column heave_m: not a number$",
                       ()),
    "quoted line break": (lambda: text(cell(motion_lines(), 3, 3, f'"{SECRET}\n1"')),
                          r"line 5: a quoted field spans lines", ()),
    "foreign column": (lambda: text(cell(motion_lines(), 0, 6, SECRET)),
                       r"line 1: wrong columns \(missing 'yaw'; unexpected column 7\)", ()),
    "/etc/passwd": (lambda: PASSWD.encode(),
                    r"line 1: expected a header row with the columns time_s,surge_m,.* \(got 1 other column\)$", ()),
    "/proc/self/environ": (lambda: ENVIRON.encode(), r"line 1, column 11: a NUL byte", ()),
    "~/.bashrc": (lambda: BASHRC.encode(), r"line 1: expected a header row with the columns", ()),
}

RAO_BAD = {
    "NUL byte": (lambda: nul(rao_lines(), 3), r"row 4, column 3: a NUL byte", ()),
    "200 000-character field": (lambda: text(cell(rao_lines(), 2, 3, "1" * 200_000)),
                                r"row 3: longer than 10000 characters", ()),
    "150-character field": (lambda: text(cell(rao_lines(), 4, 3, SECRET * 25)),
                            r"row 5, field 4: over 100 characters", ()),
    "not UTF-8": (lambda: not_utf8(rao_lines(), 5), r"row 6, column 1: not UTF-8 text", ()),
    "UTF-16": (lambda: "\n".join(rao_lines()).encode("utf-16"), r"UTF-16 text; expected .* UTF-8", ()),
    "heave amplitude 1e300": (lambda: text(cell(rao_lines(), 3, 3, "1e300")),
                              r"row 4: heave amplitude 1e\+300 m/m is above 100 m/m", ()),
    "roll amplitude 1e300": (lambda: text(cell(rao_lines(), 4, 3, "1e300")),
                             r"row 5: roll amplitude 1e\+300 deg/m is above 1000 deg/m", ()),
    "omega 1e300": (lambda: text(cell(rao_lines(), 1, 0, "1e300")), r"row 2: omega_rad_s 1e\+300 is above 100 rad/s",
                    ()),
    "phase 1e300": (lambda: text(cell(rao_lines(), 2, 4, "1e300")), r"row 3: phase_deg 1e\+300 is beyond", ()),
    "overflow to inf": (lambda: text(cell(rao_lines(), 3, 3, "1e999")),
                        r"row 4: amplitude 'inf' is not a finite number", ("1e999",)),
    "-NaN": (lambda: text(cell(rao_lines(), 5, 4, "-NaN")), r"row 6: phase_deg 'nan' is not a finite number",
             ("NaN",)),
    "text in a cell": (lambda: text(cell(rao_lines(), 3, 3, SECRET)), r"row 4, column amplitude: not a number$", ()),
    "unknown dof": (lambda: text(cell(rao_lines(), 3, 2, SECRET)), r"row 4: unknown dof \(expected one of surge", ()),
    "/etc/passwd": (lambda: PASSWD.encode(), r"row 1: the header lacks column 'omega_rad_s'", ()),
    "/proc/self/environ": (lambda: ENVIRON.encode(), r"row 1, column 11: a NUL byte", ()),
    "~/.bashrc": (lambda: BASHRC.encode(), r"row 2: the header lacks column 'omega_rad_s'", ()),
}

READERS = {"motion": (read_motion_csv, MOTION_BAD), "rao": (read_rao_csv, RAO_BAD)}
BAD_CONTENT = [(kind, name) for kind, (_, cases) in READERS.items() for name in cases]


def refusal(read, path: Path) -> BaseException | None:
    """What ``read(path)`` raises, or None; a read that blocks (a named pipe) fails the test."""
    box: dict[str, BaseException] = {}

    def run() -> None:
        try:
            read(path)
        except BaseException as exc:  # noqa: BLE001 - handed to the test
            box["exc"] = exc

    worker = threading.Thread(target=run, daemon=True)
    worker.start()
    worker.join(10.0)
    if worker.is_alive():
        os.close(os.open(path, os.O_WRONLY | os.O_NONBLOCK))  # release the blocked open
        worker.join(10.0)
        pytest.fail(f"reading {path.name} blocked")
    return box.get("exc")


def assert_refused(exc: BaseException | None, path: Path, pattern: str, leaks=()) -> str:
    """One ScenarioError line naming the file, matching ``pattern``, quoting nothing from the file."""
    assert isinstance(exc, ScenarioError), repr(exc)
    message = str(exc)
    assert exc.source == str(path) and message.startswith(f"{path}: ")
    assert "\n" not in message and "\r" not in message
    assert re.search(pattern, message), message
    detail = message.removeprefix(f"{path}: ")
    for leak in (*FILE_LEAKS, *leaks):
        assert leak not in detail, f"{leak!r} echoed in {message!r}"
    return message


@pytest.mark.parametrize("kind, name", BAD_CONTENT, ids=[f"{k}: {n}" for k, n in BAD_CONTENT])
def test_bad_content_is_refused_in_one_line_without_echo(tmp_path, kind, name):
    read, cases = READERS[kind]
    make, pattern, leaks = cases[name]
    path = tmp_path / f"{kind}.csv"
    path.write_bytes(make())
    assert_refused(refusal(read, path), path, pattern, leaks)


# --------------------------------------------------------------- cases: bad paths
def folder(tmp_path: Path) -> Path:
    (tmp_path / "folder.csv").mkdir()
    return tmp_path / "folder.csv"


def fifo(tmp_path: Path) -> Path:
    os.mkfifo(tmp_path / "pipe.csv")
    return tmp_path / "pipe.csv"


def huge(tmp_path: Path) -> Path:
    """A 300 MiB file (sparse: costs no disk), larger than any real table."""
    path = tmp_path / "huge.csv"
    with open(path, "wb") as f:
        f.write(text(motion_lines()))
        f.truncate(300 * 2**20)
    return path


BAD_PATHS = {
    "a folder": (folder, r": a folder, not a file; expected a"),
    "a named pipe": (fifo, r": not a regular file \(a device, pipe or socket\)"),
    "300 MiB": (huge, r": 300 MiB is larger than .* \(256 MiB at most\)"),
}


@pytest.mark.parametrize("kind", sorted(READERS))
@pytest.mark.parametrize("name", sorted(BAD_PATHS))
def test_paths_that_are_no_table_are_refused_before_reading(tmp_path, kind, name):
    if name == "a named pipe" and not hasattr(os, "mkfifo"):
        pytest.skip("no named pipes")
    make, pattern = BAD_PATHS[name]
    path = make(tmp_path)
    assert_refused(refusal(READERS[kind][0], path), path, pattern)


def capytaine_file(path: Path, heave: float) -> Path:
    """A Capytaine-style NetCDF file with an RAO variable: heave ``heave`` m/m, nothing else."""
    xr = pytest.importorskip("xarray")
    pytest.importorskip("h5netcdf")
    re_im = np.zeros((2, 2, 1, 6))  # (complex, omega, wave_direction, radiating_dof)
    re_im[0, :, 0, 2] = heave
    ds = xr.Dataset(coords={"complex": ["re", "im"], "omega": [0.5, 1.0], "wave_direction": [np.pi],
                            "radiating_dof": ["Surge", "Sway", "Heave", "Roll", "Pitch", "Yaw"]})
    ds["RAO"] = (("complex", "omega", "wave_direction", "radiating_dof"), re_im)
    ds.to_netcdf(path, engine="h5netcdf")
    return path


CAPYTAINE_BAD = {
    "heave 1e300": (lambda p: capytaine_file(p / "rao.nc", 1e300),
                    r": heave RAO 1e\+300 m/m at omega 0\.5 rad/s, heading 180 deg is above 100 m/m"),
    "a folder": (folder, r": a folder, not a file; expected a Capytaine NetCDF file"),
    "/etc/passwd": (lambda p: (p / "passwd.nc", (p / "passwd.nc").write_text(PASSWD))[0],
                    r": cannot read as a NetCDF file"),
}


@pytest.mark.parametrize("name", sorted(CAPYTAINE_BAD))
def test_capytaine_refuses_what_is_no_ship_response(tmp_path, name):
    assert read_capytaine(capytaine_file(tmp_path / "ok.nc", 1.0)).values[2, 0, 0] == 1.0
    make, pattern = CAPYTAINE_BAD[name]
    path = make(tmp_path)
    with pytest.raises(ScenarioError) as info:
        read_capytaine(path)
    assert_refused(info.value, path, pattern)


def test_write_rao_csv_writes_only_what_read_rao_csv_reads(tmp_path):
    values = np.zeros((6, 1, 2), dtype=complex)
    values[2] = 1.0
    write_rao_csv(RAO([0.5, 1.0], [180.0], values), tmp_path / "ok.csv")
    values[3, 0, 1] = 1e300
    with pytest.raises(ValueError, match=r"roll RAO 1e\+300 rad/m .* read_rao_csv would refuse the file"):
        write_rao_csv(RAO([0.5, 1.0], [180.0], values), tmp_path / "absurd.csv")
    assert not (tmp_path / "absurd.csv").exists()


# ------------------------------------------------------- what spreadsheets write
SPREADSHEET = {
    "BOM + CRLF": lambda lines: b"\xef\xbb\xbf" + text(lines, "\r\n"),
    "CR line ends": lambda lines: text(lines, "\r"),
    "BOM + CRLF + empty rows": lambda lines: b"\xef\xbb\xbf" + text(lines + [",,,,,,"] * 3, "\r\n"),
}


@pytest.mark.parametrize("name", sorted(SPREADSHEET))
def test_what_spreadsheets_write_reads_like_the_clean_file(tmp_path, name):
    (tmp_path / "clean_motion.csv").write_bytes(text(motion_lines()))
    (tmp_path / "sheet_motion.csv").write_bytes(SPREADSHEET[name](motion_lines()))
    (tmp_path / "clean_rao.csv").write_bytes(text(rao_lines()))
    (tmp_path / "sheet_rao.csv").write_bytes(SPREADSHEET[name](rao_lines()))
    clean, sheet = read_motion_csv(tmp_path / "clean_motion.csv"), read_motion_csv(tmp_path / "sheet_motion.csv")
    np.testing.assert_array_equal(sheet.t, clean.t)
    np.testing.assert_array_equal(sheet.eta, clean.eta)
    clean, sheet = read_rao_csv(tmp_path / "clean_rao.csv"), read_rao_csv(tmp_path / "sheet_rao.csv")
    np.testing.assert_array_equal(sheet.omega, clean.omega)
    np.testing.assert_array_equal(sheet.heading_deg, clean.heading_deg)
    np.testing.assert_array_equal(sheet.values, clean.values)


# -------------------------------------------------------------------- scenario TOML
def deep_arrays() -> bytes:
    return ("x = " + "[" * 3000 + "]" * 3000 + "\n").encode() + (EXAMPLES / "paper.toml").read_bytes()


def deep_tables() -> bytes:
    return ("x = " + "{a = " * 3000 + "1" + "}" * 3000 + "\n").encode() + (EXAMPLES / "paper.toml").read_bytes()


SCENARIO_BAD = {
    "3000-deep arrays": (deep_arrays, r": not valid TOML: .*too deeply nested"),
    "3000-deep inline tables": (deep_tables, r": not valid TOML: .*too deeply nested"),
    "NUL byte": (lambda: b'name = "x"\ndescription = "a\0b"\n', r": line 2, column 17: a NUL byte"),
    "not UTF-8": (lambda: b'name = "x"\n\ndescription = "Mar\xeda"\n', r": line 3, column 19: not UTF-8 text"),
}


@pytest.mark.parametrize("name", sorted(SCENARIO_BAD))
def test_bad_scenario_files_are_one_line(tmp_path, name):
    make, pattern = SCENARIO_BAD[name]
    path = tmp_path / "bad.toml"
    path.write_bytes(make())
    with pytest.raises(ScenarioError) as info:
        load_scenario(path)
    assert_refused(info.value, path, pattern)


def test_a_3000_deep_scenario_dict_is_one_line():
    data = paper_dict()
    node: object = 1.0
    for _ in range(3000):
        node = {"a": [node]}
    data["trajectory"]["radius_m"] = node
    with pytest.raises(ScenarioError, match=r"^test: trajectory: too deeply nested") as info:
        scenario_from_dict(data, source="test")
    assert "\n" not in str(info.value)


def test_a_scenario_with_a_bom_and_crlf_reads(tmp_path):
    path = tmp_path / "paper.toml"
    path.write_bytes(b"\xef\xbb\xbf" + (EXAMPLES / "paper.toml").read_bytes().replace(b"\n", b"\r\n"))
    assert load_scenario(path).model_dump() == load_scenario(EXAMPLES / "paper.toml").model_dump()


# ---------------------------------------------------------------- through the CLI
def recorded_scenario(tmp_path: Path, file: str) -> Path:
    text_ = (EXAMPLES / "paper.toml").read_text()
    start, end = text_.index("[base_motion]"), text_.index("[trajectory]")
    path = tmp_path / "recorded.toml"
    path.write_text(text_[:start] + f'[base_motion]\ntype = "recorded"\nfile = "{file}"\n\n' + text_[end:])
    return path


def rao_scenario(tmp_path: Path, file: str) -> Path:
    text_ = (resources.files("marinecdpr.scenario") / "builtin" / "paper_sea.toml").read_text()
    start, end = text_.index("[base_motion.rao]"), text_.index("[trajectory]")
    path = tmp_path / "sea.toml"
    path.write_text(text_[:start] + f'[base_motion.rao]\nsource = "csv"\nfile = "{file}"\n\n' + text_[end:])
    return path


CLI_CASES = [("motion", n) for n in ("/etc/passwd", "NUL byte", "200 000-character field", "not UTF-8",
                                      "heave 1e300", "/proc/self/environ", "~/.bashrc")] + \
            [("rao", n) for n in ("NUL byte", "heave amplitude 1e300", "overflow to inf", "text in a cell")] + \
            [("toml", n) for n in ("3000-deep arrays", "NUL byte")]


@pytest.mark.parametrize("kind, name", CLI_CASES, ids=[f"{k}: {n}" for k, n in CLI_CASES])
def test_check_refuses_a_bad_file_in_one_line(tmp_path, kind, name):
    if kind == "toml":
        make, pattern = SCENARIO_BAD[name]
        bad = scenario = tmp_path / "bad.toml"
        leaks = ()
    else:
        make, pattern, leaks = READERS[kind][1][name]
        bad = (tmp_path / "ship.csv").resolve()
        scenario = (recorded_scenario if kind == "motion" else rao_scenario)(tmp_path, bad.name)
    bad.write_bytes(make())
    res = runner.invoke(app, ["check", str(scenario)])
    assert res.exit_code == 2, (res.exit_code, res.output, res.exception)
    err = res.stderr
    assert err.count("\n") == 1 and err.startswith(f"error: {bad}: "), err
    assert "Traceback" not in err, err
    assert re.search(pattern, err), err
    detail = err.removeprefix(f"error: {bad}: ")
    for leak in (*FILE_LEAKS, *leaks):
        assert leak not in detail, f"{leak!r} echoed in {err!r}"
