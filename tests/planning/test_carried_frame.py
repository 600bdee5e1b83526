"""Planning for a frame carried on a rail (issue 39, item 1): the carriage's acceleration is a
load the cables hold, worked by hand."""

from __future__ import annotations

import re

import numpy as np
import pytest

import marinecdpr
from marinecdpr.errors import ScenarioError
from marinecdpr.scenario.schema import validated_scenario

HELD = [0.95, 0.0, 0.7]  # the platform's place in C, m, held still


def _carried(carriage: dict, *, base_motion=None, duration=6.0, **ship) -> marinecdpr.Scenario:
    data = marinecdpr.load_scenario("paper").model_dump(exclude_none=True)
    data["ship"] = dict(ship, carriage=carriage)
    data["base_motion"] = base_motion or {"type": "still"}
    data["trajectory"] = {"type": "waypoints", "waypoints": [
        {"time_s": 0.0, "position_m": HELD}, {"time_s": duration, "position_m": HELD}]}
    data["time"] = {"step_s": 0.001, "duration_s": duration}
    return validated_scenario(data)


STRAIGHT = {"rail_m": [[-0.78, 0.0, 2.2], [99.22, 0.0, 2.2]], "speed_max_m_s": 0.5, "accel_max_m_s2": 0.4,
            "jerk_max_m_s3": 2.0, "stations_m": [0.0, 1.5], "dwell_s": 0.5}


def test_a_carriage_accelerating_on_a_still_ship_loads_the_cables_with_the_platform_s_inertia():
    """Still ship, the carriage along S's x, the platform held in C: the cables give the
    platform its weight and m a along x, a the carriage's acceleration (jerk-limited, so a
    ramps 0 -> 0.4 m/s^2 -> 0 -> -0.4 -> 0), and no moment (the platform's centre of mass is
    its origin and it does not turn)."""
    from marinecdpr.motion.rail import carriage_profile

    sc = _carried(STRAIGHT)
    p = marinecdpr.plan(sc)
    m, g = sc.robot.mass_kg, sc.environment.gravity_m_s2
    _, _, a, _ = carriage_profile(np.array([0.0, 1.5]), 0.5, 0.5, 0.4, 2.0, p.t)
    assert a.max() == pytest.approx(0.4, abs=1e-12) and a.min() == pytest.approx(-0.4, abs=1e-12)
    expected = np.zeros((p.t.size, 6))
    expected[:, 0] = m * a  # the cables push the platform along with the frame
    expected[:, 2] = m * g
    assert np.max(np.abs(p.wrench - expected)) < 1e-12  # measured: 0 (the issue asks 1e-9 N)
    assert p.feasible.all()
    # the same plan with the frame standing still at the rail's start: weight only
    still = marinecdpr.plan(_carried(dict(STRAIGHT, stations_m=[0.0])))
    assert np.max(np.abs(still.wrench[:, [0, 1, 3, 4, 5]])) < 1e-12


def test_a_frame_on_a_rail_takes_its_origin_from_the_rail_only():
    with pytest.raises(ScenarioError, match=r"ship.frame_origin_m: the carriage carries C's origin"):
        _carried(STRAIGHT, frame_origin_m=[1.0, 0.0, 0.0])
    with pytest.raises(ScenarioError, match=r"ship.carriage.dwell_s: one time for every station: 2 stations, got 3"):
        _carried(dict(STRAIGHT, dwell_s=[1.0, 2.0, 3.0]))


def test_a_rail_that_cannot_be_built_is_one_line_from_check(tmp_path):
    """A corner whose arc does not fit, a station beyond the rail's end, a U-turn: `check`
    refuses each in one line naming the scenario's key (exit 2), as `plan` does."""
    import tomli_w
    from typer.testing import CliRunner

    from conftest import one_line_exit_2
    from marinecdpr.cli.app import app
    from marinecdpr.planning.planner import check_trajectory

    cases = {"ship.carriage.corner_radius_m": dict(STRAIGHT, rail_m=[[0.0, 0.0, 2.2], [5.0, 0.0, 2.2], [5.0, 5.0, 2.2],
                                                                      [0.0, 5.0, 2.2]], corner_radius_m=3.0),
             "ship.carriage.stations_m": dict(STRAIGHT, stations_m=[0.0, 150.0]),
             "ship.carriage.rail_m[2]": dict(STRAIGHT, rail_m=[[0.0, 0.0, 2.2], [5.0, 0.0, 2.2], [1.0, 0.0, 2.2]])}
    for key, carriage in cases.items():
        sc = _carried(carriage)
        with pytest.raises(ScenarioError, match="^" + re.escape(key) + ": "):
            check_trajectory(sc)
        path = tmp_path / "rail.toml"
        path.write_bytes(tomli_w.dumps(sc.model_dump(exclude_none=True)).encode())
        one_line_exit_2(CliRunner().invoke(app, ["check", str(path)]), key)


def test_the_drive_accelerates_the_carriage_and_the_platform_the_cables_hold():
    """Still ship, a level rail along x, the platform held: the drive's force along the rail
    is (m_c + m_p) a, the carriage's acceleration a worked by the double-S law; on a rail rising
    at an angle b with the carriage at rest, (m_c + m_p) g sin b (the cables hand the platform's
    weight to the frame)."""
    from marinecdpr.motion.rail import carriage_profile
    from marinecdpr.planning.carriage import drive_force

    m_c = 40.0
    sc = _carried(dict(STRAIGHT, mass_kg=m_c, drive_force_max_N=20.0))
    p = marinecdpr.plan(sc)
    d = drive_force(p, sc)
    _, _, a, _ = carriage_profile(np.array([0.0, 1.5]), 0.5, 0.5, 0.4, 2.0, p.t)
    m_p = sc.robot.mass_kg
    assert np.max(np.abs(d.force_N - (m_c + m_p) * a)) < 1e-12  # measured 7.1e-14 N
    assert d.peak_N == pytest.approx(45.0 * 0.4, rel=1e-12) and d.within  # 18 N of its 20 N
    assert not drive_force(p, _carried(dict(STRAIGHT, mass_kg=m_c, drive_force_max_N=15.0))).within
    b = np.radians(5.0)
    rising = dict(STRAIGHT, rail_m=[[-0.78, 0.0, 2.2], [-0.78 + 50.0 * np.cos(b), 0.0, 2.2 + 50.0 * np.sin(b)]],
                  stations_m=[0.0], mass_kg=m_c)
    sc = _carried(rising)
    d = drive_force(marinecdpr.plan(sc), sc)
    g = sc.environment.gravity_m_s2
    assert np.max(np.abs(d.force_N - (m_c + m_p) * g * np.sin(b))) < 1e-12  # measured 7.1e-15 N


def test_a_drive_limit_needs_the_carriage_s_mass():
    with pytest.raises(ScenarioError, match=r"ship.carriage.mass_kg: missing: the drive's force"):
        _carried(dict(STRAIGHT, drive_force_max_N=100.0))


def test_plan_gives_the_carriage_drive_s_peak_and_fails_beyond_its_limit(tmp_path):
    """The plan command, made in chunks, finds the whole plan's peak drive force (the same
    number as drive_force on the whole plan); beyond the drive's limit it says so in one line
    and exits 3, as an infeasible plan does; --allow-infeasible exits 0."""
    import tomli_w
    from typer.testing import CliRunner

    from marinecdpr.cli.app import app
    from marinecdpr.commands import plan as command
    from marinecdpr.planning.carriage import drive_force

    sc = _carried(dict(STRAIGHT, mass_kg=40.0, drive_force_max_N=15.0))
    whole = drive_force(marinecdpr.plan(sc), sc)
    result = command.run(command.PlanSpec(), sc, tmp_path / "py")
    assert result.summary()["carriage_drive"] == {"peak_N": whole.peak_N, "at_s": whole.peak_at_s, "limit_N": 15.0}
    assert result.failed and result.drive_verdict().startswith("the carriage's drive must give 18 N along the rail")
    path = tmp_path / "rail.toml"
    path.write_bytes(tomli_w.dumps(sc.model_dump(exclude_none=True)).encode())
    res = CliRunner().invoke(app, ["plan", str(path), "--out", str(tmp_path / "cli")])
    assert res.exit_code == 3, res.output
    lines = [line for line in res.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("carriage drive: ") and "more than its 15 N" in lines[0]
    assert "carriage drive along the rail (N)" in res.stdout
    ok = CliRunner().invoke(app, ["plan", str(path), "--out", str(tmp_path / "ok"), "--allow-infeasible"])
    assert ok.exit_code == 0, ok.output
