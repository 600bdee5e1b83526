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
