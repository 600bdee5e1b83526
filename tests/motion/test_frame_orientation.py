"""A frame turned on the ship (``ship.frame_orientation_deg``): leaning with a flared side,
turned with the hull's curve. The models take C's axes for the ship's, so they are given the
ship's motion seen in the frame's axes (:func:`marinecdpr.motion.ship.in_frame_axes`);
checked against the ship itself turned, on the planner and on MuJoCo, and between the plants."""

from __future__ import annotations

import numpy as np
import pytest

import marinecdpr
from marinecdpr.motion.basemotion import frame_origin_of
from marinecdpr.motion.ship import frame_axes, in_frame_axes, ship_motion
from marinecdpr.prototype.parts.brush import normal_force, static_weight_y
from marinecdpr.prototype.simulation import simulate


def _sines(t, rng):
    eta, eta_dot, eta_ddot = (np.zeros((t.size, 6)) for _ in range(3))
    for k in range(6):
        a, w, p = rng.uniform(0.05, 0.3), rng.uniform(0.3, 1.5), rng.uniform(0.0, 6.0)
        eta[:, k] = a * np.sin(w * t + p)
        eta_dot[:, k] = a * w * np.cos(w * t + p)
        eta_ddot[:, k] = -a * w * w * np.sin(w * t + p)
    eta[:, 5] += 3.0  # a heading near 180 deg: the turned frame's yaw crosses it
    return eta, eta_dot, eta_ddot


def test_the_ship_seen_in_the_frame_s_axes():
    """R_S'O = R_SO R_SC, omega and alpha turned by R_SC^T (to 1e-15), and eta' (continuous
    across +-180 deg) has the rates and accelerations its own finite differences give; the
    identity gives the ship back."""
    t = np.linspace(0.0, 20.0, 4001)
    ship = ship_motion(*_sines(t, np.random.default_rng(0)))
    R_SC = frame_axes([-25.0, 5.0, 170.0])
    seen = in_frame_axes(ship, R_SC)
    assert np.abs(seen.R_SO - ship.R_SO @ R_SC).max() < 1e-15 * 10
    assert np.abs(seen.omega_SO_S - ship.omega_SO_S @ R_SC).max() < 1e-15 * 10
    assert np.abs(seen.alpha_SO_S - ship.alpha_SO_S @ R_SC).max() < 1e-15 * 10
    np.testing.assert_array_equal(seen.eta[:, :3], ship.eta[:, :3])
    assert np.abs(np.diff(seen.eta[:, 3:], axis=0)).max() < 0.01  # no jump of 2 pi
    dt = t[1] - t[0]
    for x, dx in ((seen.eta, seen.eta_dot), (seen.eta_dot, seen.eta_ddot)):
        fd = np.gradient(x[:, 3:], dt, axis=0)[2:-2]
        assert np.abs(fd - dx[2:-2, 3:]).max() < 1e-4 * np.abs(dx[:, 3:]).max()
    assert in_frame_axes(ship, np.eye(3)) is ship


def _leaning(sc, roll_deg):
    """The scenario's robot with its frame rolled on a still ship, and the same upright frame
    on a ship that stands rolled: one physics, two descriptions (C at S's origin)."""
    still = {"type": "still"}
    rolled = {"type": "sinusoidal", "components": [{"dof": "roll", "amplitude_deg": 0.0, "offset_deg": roll_deg,
                                                    "period_s": 10.0}]}
    a = sc.with_changes(base_motion=still).with_updates("ship", frame_origin_m=[0.0, 0.0, 0.0],
                                                        frame_orientation_deg=[roll_deg, 0.0, 0.0])
    b = sc.with_changes(base_motion=rolled).with_updates("ship", frame_origin_m=[0.0, 0.0, 0.0])
    return a, b


def test_a_frame_leaning_on_a_still_ship_is_an_upright_frame_on_a_rolled_ship():
    """The paper's circle with the frame rolled 20 deg on a still ship plans as with the frame
    upright on a ship rolled 20 deg: wrench and tensions to 1e-9."""
    a, b = _leaning(marinecdpr.load_scenario("paper"), 20.0)
    pa, pb = marinecdpr.plan(a), marinecdpr.plan(b)
    assert pa.feasible.all() and pb.feasible.all()
    np.testing.assert_allclose(pa.wrench, pb.wrench, rtol=0, atol=1e-9)
    np.testing.assert_allclose(pa.tensions, pb.tensions, rtol=0, atol=1e-9)
    assert np.abs(pa.wrench - marinecdpr.plan(marinecdpr.load_scenario("paper").with_changes(
        base_motion={"type": "still"})).wrench).max() > 1.0  # the lean changes the wrench


def test_mujoco_flies_a_leaning_frame_as_an_upright_one_on_a_rolled_ship():
    """MuJoCo's frame body sits in the turned axes S' of a ship driven along eta': the same
    3 s open loop as the upright frame on a rolled ship, to 1e-6 m."""
    a, b = _leaning(marinecdpr.load_scenario("paper").with_changes(time={"duration_s": 3.0, "step_s": 0.001}), 20.0)
    ra, rb = (simulate(s, run="open_loop", plant="mujoco") for s in (a, b))
    assert np.abs(ra.pose - rb.pose).max() < 1e-6


def test_both_plants_agree_on_a_leaning_turned_frame_in_a_seaway():
    """The paper's circle and ship motion with the frame leaning 25 deg, pitched 3 and turned
    10 deg, 5 m out on the ship: open loop, MuJoCo and the own plant within 1e-4 m, as upright."""
    sc = marinecdpr.load_scenario("paper").with_changes(time={"duration_s": 5.0, "step_s": 0.001}).with_updates(
        "ship", frame_origin_m=[5.0, 3.0, 2.0], frame_orientation_deg=[-25.0, 3.0, 10.0])
    assert np.abs(frame_origin_of(sc) - frame_axes([-25.0, 3.0, 10.0]).T @ [5.0, 3.0, 2.0]).max() < 1e-15
    runs = [simulate(sc, run="open_loop", plant=p) for p in ("mujoco", "own")]
    assert np.abs(runs[0].pose[:, :3] - runs[1].pose[:, :3]).max() <= 1e-4


def test_the_pusher_carries_the_platform_s_weight_on_a_leaning_frame():
    """paper_clean's brush held still on a still ship, the frame leaning out 30 deg (roll -30
    deg: the side flares, C's y, out of the hull, points 30 deg down): the weight pulls the
    platform off the hull, m (R_SC^T (0, 0, -g))_y = m g sin 30 deg = m g / 2 along C's y, and
    the pusher's setpoint carries it: the brush presses with the preload at every step."""
    sc = marinecdpr.load_scenario("paper_clean")
    x = (0.95, 0.0, 0.7)
    held = sc.with_changes(base_motion={"type": "still"},
                           trajectory={"type": "line", "start_position_m": list(x), "end_position_m": list(x),
                                       "duration_s": 1.0},
                           time={"duration_s": 2.0, "step_s": 0.01}).with_updates(
        "ship", frame_orientation_deg=[-30.0, 0.0, 0.0])
    m, g = held.robot.mass_kg, held.environment.gravity_m_s2
    assert static_weight_y(held) == pytest.approx(0.5 * m * g, rel=1e-12)
    p = marinecdpr.plan(held)
    np.testing.assert_allclose(normal_force(p, held), held.cleaning.preload, rtol=0, atol=1e-9)


def test_a_turned_frame_through_the_commands(tmp_path):
    """A scenario file with a turned frame goes through check, plan and simulate (short); an
    angle beyond half a turn is one line naming the key, exit 2."""
    import tomli_w
    from typer.testing import CliRunner

    from marinecdpr.cli.app import app
    from marinecdpr.scenario.importing.common import toml_plain as _plain
    from tests.conftest import one_line_exit_2

    runner = CliRunner()
    data = _plain(marinecdpr.load_scenario("paper").model_dump(exclude_none=True))
    data["ship"]["frame_orientation_deg"] = [-20.0, 2.0, 10.0]
    data["time"]["duration_s"] = 1.0
    good = tmp_path / "turned.toml"
    good.write_text(tomli_w.dumps(data))
    for args in (["check", str(good)], ["plan", str(good), "--out", str(tmp_path / "p")],
                 ["simulate", str(good), "--out", str(tmp_path / "s")]):
        res = runner.invoke(app, args)
        assert res.exit_code == 0, (args, res.output)
    data["ship"]["frame_orientation_deg"] = [0.0, 0.0, 400.0]
    bad = tmp_path / "bad.toml"
    bad.write_text(tomli_w.dumps(data))
    one_line_exit_2(runner.invoke(app, ["check", str(bad)]), "frame_orientation_deg")


def test_euler_angles_from_a_matrix_invert_the_matrix():
    """euler_from_matrix(matrix_from_euler(a)) = a for random angles with |pitch| < 90 deg."""
    from marinecdpr.geometry.rotations import euler_from_matrix, matrix_from_euler

    rng = np.random.default_rng(7)
    a = np.column_stack([rng.uniform(-np.pi, np.pi, 500), rng.uniform(-1.5, 1.5, 500), rng.uniform(-np.pi, np.pi, 500)])
    np.testing.assert_allclose(euler_from_matrix(matrix_from_euler(a)), a, rtol=0, atol=1e-12)
