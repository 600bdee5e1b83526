"""The prototype with a carriage (issue 39, item 2): on MuJoCo the ship body, on its six driven
joints, moves as C (the ship's motion composed with the carriage's) and carries the frame; the
carriage part records the drive's force along the rail against its limit."""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np
import pytest

import marinecdpr
from marinecdpr.geometry.kinematics import cable_kinematics
from marinecdpr.geometry.rotations import matrix_from_euler
from marinecdpr.motion.basemotion import evaluate_base_motion, frame_ship_motion
from marinecdpr.motion.carriage import carriage_motion
from marinecdpr.prototype.mujoco_model import build_model
from marinecdpr.prototype.simulation import simulate
from marinecdpr.scenario.schema import validated_scenario

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def _rail_in_a_sea(**carriage) -> marinecdpr.Scenario:
    """examples/paper_rail.toml on paper_sea's ship in its seaway, the frame leaning 8 deg on
    the ship (so that the carriage's hinge turns a leaning frame), the carriage's dwell
    shortened so that it moves within a short horizon."""
    sc = marinecdpr.load_scenario(str(EXAMPLES / "paper_rail.toml"))
    data = sc.model_dump(exclude_none=True)
    data["base_motion"] = marinecdpr.load_scenario("paper_sea").model_dump(exclude_none=True)["base_motion"]
    data["ship"]["frame_orientation_deg"] = [8.0, 0.0, 0.0]
    data["ship"]["carriage"].update({"dwell_s": 0.3, "speed_max_m_s": 0.6, "accel_max_m_s2": 0.8,
                                     "jerk_max_m_s3": 4.0, **carriage})
    return validated_scenario(data)


@pytest.fixture(scope="module")
def rail_runs():
    sc = _rail_in_a_sea()
    return sc, {plant: simulate(sc, run="closed_loop", plant=plant, n_steps=2500) for plant in ("mujoco", "own")}


def test_mujoco_s_frame_rides_a_carriage_on_the_ship_and_both_plants_agree(rail_runs):
    """A rail move (the carriage 0.3 s at rest, then accelerating at up to 0.8 m/s^2 into its
    move, 1.03 m in all) in a seaway, closed loop, 2.5 s: the platform's pose in C on MuJoCo
    (the frame on the ship body driven along C's motion) and on the own plant (C's composed
    motion). Measured: 2.1e-8 m and 4.9e-9 deg apart (the issue asks 1e-4 m; the same when
    MuJoCo's frame hung from a carriage body on a ship body); the body within 1.1e-8 of C's
    motion (the carriage's joints were within 1.1e-8 of its trajectory, the ship's within
    1.3e-9 of S's motion)."""
    sc, runs = rail_runs
    a, b = runs["mujoco"], runs["own"]
    r = carriage_motion(sc.ship, a.t)[0]
    assert np.ptp(r[:, 0]) > 1.0  # the carriage moved 1 m and more along the rail
    d = a.pose - b.pose
    assert np.abs(d[:, :3]).max() <= 5e-8
    assert np.degrees(np.abs(d[:, 3:]).max()) <= 2e-8
    assert 0.0 < a.carriage_tracking_error <= 3e-8 and b.carriage_tracking_error == 0.0
    assert a.ship_tracking_error == a.carriage_tracking_error  # one driven body: C


def test_a_carriage_far_from_the_ship_s_origin_on_a_rail_across_its_axes_stays_on_its_trajectory():
    """A straight level rail 80 m forward of S's origin, running across S's x and y (the frame
    yawed 20 deg along it, as a design's frame on a flared side is), in a seaway, closed loop.
    When MuJoCo's carriage was a body on slides on the ship's body, its 80 m arm coupled the
    slides to the ship's hinges: with the ship's inertia of then (1e8 kg m^2) the slides' servo
    saw an effective mass of 1.6e4 kg instead of 1e7 and MuJoCo diverged within 10 ms (a design
    finalist's rail move); the body driven along C's motion has its hinges at C's origin. The
    plants agree as near the origin. Measured: 2.1e-8 m apart (as with the two bodies)."""
    rail = [[80.0, 5.0, 2.2], [80.0 + 3.0 * np.cos(np.radians(20.0)), 5.0 + 3.0 * np.sin(np.radians(20.0)), 2.2]]
    sc = _rail_in_a_sea(rail_m=rail, corner_radius_m=0.0, stations_m=[0.0, 1.0])
    data = sc.model_dump(exclude_none=True)
    data["ship"]["frame_orientation_deg"] = [8.0, 0.0, 20.0]
    sc = validated_scenario(data)
    a, b = (simulate(sc, run="closed_loop", plant=plant, n_steps=1500) for plant in ("mujoco", "own"))
    assert np.ptp(carriage_motion(sc.ship, a.t)[0][:, 1]) > 0.1  # it moved across S's y
    assert np.abs(a.pose[:, :3] - b.pose[:, :3]).max() <= 5e-8
    assert a.carriage_tracking_error <= 3e-8


@pytest.mark.parametrize("rail", [
    {"stations_m": [0.0, 5.0]},  # level, into the bend
    {"stations_m": [4.0]},  # parked in the bend: the frame turned on a fixed carriage
    {"rail_m": [[-0.78, 0.0, 2.2], [5.0, 0.0, 3.0]], "corner_radius_m": 0.0, "stations_m": [0.0, 4.0]},  # rising
])
def test_the_ship_body_on_c_s_coordinates_places_the_frame_where_the_ship_and_the_carriage_do(rail):
    """MuJoCo's ship body with its joints at C's eta (frame_ship_motion's: C's origin in O and
    the Euler angles of R_CO, what the drive steers them along) puts the frame body (leaning 8
    deg) at the ship's pose composed by hand with the carriage's on it (x_S + R_SO r,
    R_SO R_SC), at times through the move and the bend; measured 0 m (C's origin is the
    slides' positions) and 5.6e-16. The
    model has the standing frame's joints: the ship's six, then the platform's."""
    sc = _rail_in_a_sea(**rail)
    mm = build_model(sc)
    model, data = mm.model, mujoco.MjData(mm.model)
    t = np.linspace(0.0, 14.0, 57)
    ship = evaluate_base_motion(sc.base_motion, t)
    r, _, _, R_SC, _, _ = carriage_motion(sc.ship, t)
    C = frame_ship_motion(sc, t)
    if rail["stations_m"] == [0.0, 5.0]:  # the frame turned through the rail's 45 deg bend
        yaw = np.arctan2(R_SC[:, 1, 0], R_SC[:, 0, 0])
        assert np.ptp(yaw) > np.radians(40)
    frame = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, "frame")
    worst_x = worst_R = 0.0
    for k in range(t.size):
        data.qpos[mm.ship_dofs] = C.eta[k, [0, 1, 2, 5, 4, 3]]
        mujoco.mj_kinematics(model, data)
        worst_x = max(worst_x, np.abs(data.xpos[frame] - (ship.x_SO_O[k] + ship.R_SO[k] @ r[k])).max())
        worst_R = max(worst_R, np.abs(data.xmat[frame].reshape(3, 3) - ship.R_SO[k] @ R_SC[k]).max())
    assert worst_x < 1e-14 and worst_R < 1e-14
    names = [mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_JOINT, j) for j in range(model.njnt)]
    assert names[:6] == ["ship_x", "ship_y", "ship_z", "ship_yaw", "ship_pitch", "ship_roll"] and len(names) == 9


HELD = [0.95, 0.0, 0.7]


def _still(mass_kg=40.0, limit=None, duration=4.0) -> marinecdpr.Scenario:
    """The paper's robot on a still ship, its platform held in C, the frame carried 1.5 m along
    a level rail along S's x (jerk-limited: a up to 0.4 m/s^2)."""
    data = marinecdpr.load_scenario("paper").model_dump(exclude_none=True)
    carriage = {"rail_m": [[-0.78, 0.0, 2.2], [99.22, 0.0, 2.2]], "speed_max_m_s": 0.5, "accel_max_m_s2": 0.4,
                "jerk_max_m_s3": 2.0, "stations_m": [0.0, 1.5], "dwell_s": 0.3, "mass_kg": mass_kg}
    if limit is not None:
        carriage["drive_force_max_N"] = limit
    data["ship"] = {"carriage": carriage}
    data["base_motion"] = {"type": "still"}
    data["trajectory"] = {"type": "waypoints", "waypoints": [
        {"time_s": 0.0, "position_m": HELD}, {"time_s": duration, "position_m": HELD}]}
    data["time"] = {"step_s": 0.001, "duration_s": duration}
    return validated_scenario(data)


@pytest.mark.parametrize("plant", ["own", "mujoco"])
def test_the_carriage_part_records_the_drive_force_of_the_held_platform(plant):
    """Still ship, level rail along x, platform held: the drive accelerates the carriage (m_c =
    40 kg) and the platform the cables hold (m_p = 5 kg): F = (m_c + m_p) a. The part's record
    (1) is its equation at the run's logged state, m_c a + sum_i T_i u_i . x from the applied
    tensions and the logged pose (measured 7.9e-16 relative); (2) is (m_c + m_p) a within
    5.7e-3 N of its 18 N peak on both plants: the tensions applied from t_k are the plan's at
    t_k + h/2, which pull the platform's m_p a half a step on (m_p j h / 2 = 5e-3 N at the
    jerk j = 2 m/s^3); (3) is the plan's drive_force within the same 5.7e-3 N."""
    from marinecdpr.motion.rail import carriage_profile
    from marinecdpr.planning.carriage import drive_force

    sc = _still()
    n = 3000
    res = simulate(sc, run="closed_loop", plant=plant, n_steps=n)
    d = res.carriage_drive
    assert d is not None and d.limit_N is None and d.force_N.shape == (n,)
    _, _, a, _ = carriage_profile(np.array([0.0, 1.5]), 0.3, 0.5, 0.4, 2.0, res.t)
    r = sc.robot
    kin = cable_kinematics(res.pose[:, :3], matrix_from_euler(res.pose[:, 3:]), r.frame_anchors, r.platform_anchors)
    by_hand = 40.0 * a + np.einsum("ni,ni->n", kin.units[:, :, 0], res.tensions)
    assert np.abs(d.force_N - by_hand).max() <= 1e-9 * d.peak_N
    assert d.peak_N == pytest.approx(45.0 * 0.4, abs=7e-3)
    assert np.abs(d.force_N - 45.0 * a).max() <= 7e-3
    planned = drive_force(marinecdpr.plan(sc), sc)
    assert np.abs(d.force_N - planned.force_N[:n]).max() <= 7e-3


def test_a_run_whose_carriage_drive_passes_its_limit_says_so_in_one_line_and_exits_3(tmp_path):
    """The same job with a drive of 15 N (the move needs 18 N): simulate writes its files, says
    in one line which run's drive passed its limit, by how much and when, and exits 3, as
    plan does; summary.json gives each run's peak. With 20 N, exit 0."""
    import json

    import tomli_w
    from typer.testing import CliRunner

    from marinecdpr.cli.app import app

    path = tmp_path / "rail.toml"
    path.write_bytes(tomli_w.dumps(_still(limit=15.0, duration=2.5).model_dump(exclude_none=True)).encode())
    res = CliRunner().invoke(app, ["simulate", str(path), "--plant", "own", "--out", str(tmp_path / "out")])
    assert res.exit_code == 3, res.output
    lines = [line for line in res.stderr.splitlines() if not line.startswith("simulate: ") and line.strip()]
    assert len(lines) == 1, res.stderr  # the progress lines, then this one
    assert lines[0].startswith("error: carriage drive: ") and "more than its 15 N" in lines[0]
    assert "18.01 N along the rail at t = 0.5 s" in lines[0]  # a = 0.4 m/s^2 reached 0.2 s into the move
    assert "(and 2 more runs)" in lines[0]
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert set(summary["runs_beyond_carriage_drive"]) == {"open_loop", "closed_loop", "fixed_base_open_loop"}
    assert summary["closed_loop"]["carriage_drive"]["peak_N"] == pytest.approx(18.0, abs=7e-3)
    assert summary["closed_loop"]["carriage_drive"]["limit_N"] == 15.0
    path.write_bytes(tomli_w.dumps(_still(limit=20.0, duration=2.5).model_dump(exclude_none=True)).encode())
    ok = CliRunner().invoke(app, ["simulate", str(path), "--plant", "own", "--out", str(tmp_path / "ok")])
    assert ok.exit_code == 0, ok.output
    assert json.loads((tmp_path / "ok" / "summary.json").read_text())["runs_beyond_carriage_drive"] == []
