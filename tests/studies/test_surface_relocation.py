"""Relocation as a design choice (issue 39, item 4): ``[cleaning.surface.relocation]``, the
frame's moves between placements by crane or along a rail, the robots sharing a band, and
what the moves cost (:mod:`marinecdpr.studies.relocation`, :func:`~marinecdpr.studies.surface.surface_job`,
``clean --surface``). Hand-worked moves and splits on placements laid out by hand; the band
of a scenario checked against the same sums; one-line refusals."""

from __future__ import annotations

import json
import shutil
from importlib import resources
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from marinecdpr.cli.app import app
from marinecdpr.commands import SpecError
from marinecdpr.commands import clean as command
from marinecdpr.commands.clean import CleanSpec
from marinecdpr.errors import ScenarioError
from marinecdpr.geometry.surface import Placement
from marinecdpr.scenario.loading import load_scenario
from marinecdpr.scenario.relocation import Relocation
from marinecdpr.studies.relocation import (
    crane_move_s, plan_moves, rail_move_s, relocation_cost, stretches, turn_radius_m, visit_order,
)
from marinecdpr.studies.surface import surface_job

from conftest import one_line_exit_2

runner = CliRunner()
BUILTIN = Path(str(resources.files("marinecdpr") / "scenario" / "builtin"))

CRANE = dict(rig_s=300.0, lift_m=3.0, hoist_m_s=0.2, travel_m_s=0.5, retension_s=120.0, capacity_kg=1000.0,
             hire_per_h=150.0)
RAIL = dict(speed_m_s=0.3, accel_m_s2=0.3, jerk_m_s3=1.0, settle_s=30.0, cost_per_m=500.0, carriage_cost=20000.0)


def _placement(x0: float, x1: float, z0: float, z1: float, y: float = 10.0, yaw: float = 0.0) -> Placement:
    """A flat patch of x0..x1 by z0..z1, its centre at (mid x, y, mid z), its frame turned by
    ``yaw`` (rad) about S's z."""
    c, s = np.cos(yaw), np.sin(yaw)
    axes = np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]]).T  # columns x, y, z
    return Placement(x_range=(x0, x1), z_range=(z0, z1), centre_S=np.array([0.5 * (x0 + x1), y, 0.5 * (z0 + z1)]),
                     normal_S=axes[:, 1].copy(), axes_S=axes, offset_range_m=(0.0, 0.0), extent_m=(x1 - x0, z1 - z0),
                     area_m2=(x1 - x0) * (z1 - z0))


def _grid() -> list[Placement]:
    """Two columns (stations 0..2 and 2..4 m) of two rows (heights 0..1 and 1..2 m), as the
    tiling lists them: along the ship, then up."""
    return [_placement(0, 2, 0, 1), _placement(0, 2, 1, 2), _placement(2, 4, 0, 1), _placement(2, 4, 1, 2)]


# ------------------------------------------------------------------ moves by hand
def test_a_crane_move_is_worked_by_hand():
    """rig 300 s + 2 x 3 m / 0.2 m/s + 5 m / 0.5 m/s + re-tension 120 s = 460 s."""
    crane = Relocation(mode="crane", frame_mass_kg=200.0, crane=CRANE).crane
    assert crane_move_s(5.0, crane) == pytest.approx(460.0, rel=1e-15)
    np.testing.assert_allclose(crane_move_s([0.0, 1.0], crane), [450.0, 452.0], rtol=1e-15)


def test_a_rail_move_is_the_double_s_closed_form_and_the_settle():
    """Biagiotti & Melchiorri's rest-to-rest move reaching v_max and a_max (h >= v (v / a + a / j)
    = 0.39 m here): T = h / v + v / a + a / j; 1.3 m at 0.3 m/s, 0.3 m/s^2, 1 m/s^3 takes
    4.333 + 1 + 0.3 s, and 30 s settling. Over 0.2 m v_max is not reached but a_max is (the
    peak vp = a/2 (sqrt((a/j)^2 + 4 h / a) - a/j) = 0.204 m/s > a^2 / j = 0.09 m/s): the same
    form with vp, no cruise."""
    rail = Relocation(mode="rail", rail=RAIL).rail
    assert rail_move_s(1.3, rail) == pytest.approx(1.3 / 0.3 + 1.0 + 0.3 + 30.0, rel=1e-14)
    a, j, h = 0.3, 1.0, 0.2
    vp = 0.5 * a * (np.sqrt((a / j) ** 2 + 4 * h / a) - a / j)
    assert vp < 0.3 and vp > a * a / j
    assert rail_move_s(h, rail) == pytest.approx(h / vp + vp / a + a / j + 30.0, rel=1e-12)
    np.testing.assert_allclose(rail_move_s(np.array([1.3, 0.2, 1.3]), rail),
                               [rail_move_s(1.3, rail), rail_move_s(0.2, rail), rail_move_s(1.3, rail)], rtol=0)


def test_the_rail_runs_along_a_row_and_the_crane_lifts_the_frame_to_the_next():
    """Rail mode on 2 x 2 placements: along the lower row (2 m by rail), up to the upper row
    (1 m by crane: the frame's height changes), back along it (2 m by rail)."""
    rel = Relocation(mode="rail", frame_mass_kg=200.0, crane=CRANE, rail=RAIL)
    p = _grid()
    assert list(visit_order(p, "rail")) == [0, 2, 3, 1]
    assert list(visit_order(p, "crane")) == [0, 1, 3, 2]
    assert list(visit_order(p, "fixed")) == [0, 1, 2, 3]
    m = plan_moves(p, np.array([100.0, 200.0, 300.0, 400.0]), rel, 600.0)
    rail_2m = 2.0 / 0.3 + 1.0 + 0.3 + 30.0
    np.testing.assert_allclose(m.move_in_s, [0.0, rail_2m, 300 + 30 + 1.0 / 0.5 + 120, rail_2m], rtol=1e-14)
    assert list(m.kind) == ["", "rail", "crane", "rail"] and (m.count("rail"), m.count("crane")) == (2, 1)
    assert m.robot_seconds(np.array([100.0, 200.0, 300.0, 400.0]))[0] == pytest.approx(
        1000.0 + 2 * rail_2m + 452.0, rel=1e-14)
    # without a crane the jump is refused, naming the placement and why
    with pytest.raises(ScenarioError) as err:
        plan_moves(p, np.ones(4), Relocation(mode="rail", rail=RAIL), 600.0)
    assert ("the rail cannot reach the placement at stations 2 to 4 m, heights 1 to 2 m: it cleans other heights "
            "than the one before it") in str(err.value) and "\n" not in str(err.value)
    assert err.value.key == "cleaning.surface.relocation.rail"


def test_a_turn_sharper_than_the_rail_s_radius_falls_back_to_the_crane():
    """Two placements 2 m apart whose frames' headings differ by 0.1 rad: the side turns with
    a radius of 20 m; a rail of 15 m radius follows it, one of 25 m does not."""
    p = [_placement(0, 2, 0, 1, yaw=0.0), _placement(2, 4, 0, 1, yaw=0.1)]
    centres = np.array([q.centre_S for q in p])
    assert turn_radius_m(centres, np.array([0.0, 0.1]))[0] == pytest.approx(20.0, rel=1e-12)
    job = np.array([10.0, 10.0])
    follows = plan_moves(p, job, Relocation(mode="rail", rail=RAIL | {"min_radius_m": 15.0}), 600.0)
    assert list(follows.kind) == ["", "rail"]
    lifted = plan_moves(p, job, Relocation(mode="rail", frame_mass_kg=1.0, crane=CRANE,
                                           rail=RAIL | {"min_radius_m": 25.0}), 600.0)
    assert list(lifted.kind) == ["", "crane"] and lifted.move_in_s[1] == pytest.approx(450.0 + 2.0 / 0.5)
    with pytest.raises(ScenarioError, match="lies where the side turns sharper than min_radius_m \\(25 m\\)"):
        plan_moves(p, job, Relocation(mode="rail", rail=RAIL | {"min_radius_m": 25.0}), 600.0)


def test_robots_split_the_placements_into_stretches_of_near_equal_time():
    """Cleaning 100, 200, 300, 400 s and fixed moves of 50 s, two robots: each placement's work
    is its cleaning and the mean move (150, 250, 350, 450 s; 1 200 s in all), its midpoint at
    75, 275, 575, 975 s, so robot floor(2 x midpoint / 1 200) = 0, 0, 0, 1: the first robot
    cleans 600 s and moves twice (700 s), the second cleans 400 s; the job takes 700 s (a
    split 2 + 2 would take 750 s)."""
    job = np.array([100.0, 200.0, 300.0, 400.0])
    assert list(stretches(job + 50.0, 2)) == [0, 0, 0, 1]
    assert list(stretches(job + 50.0, 1)) == [0, 0, 0, 0]
    m = plan_moves(_grid(), job, Relocation(mode="fixed", robots=2), 50.0)
    np.testing.assert_array_equal(m.robot, [0, 0, 0, 1])
    np.testing.assert_allclose(m.robot_seconds(job), [700.0, 400.0], rtol=0)
    assert list(m.kind) == ["", "fixed", "fixed", ""]
    # by crane, two robots, each its own crane on hire for the job's hours; by rail, one rail
    # of the band's length and a carriage each
    crane = Relocation(mode="crane", robots=2, frame_mass_kg=1.0, crane=CRANE)
    mc = plan_moves(_grid(), job, crane, 600.0)
    assert relocation_cost(crane, mc, 2.0, 4.0).as_dict() == {"crane_hire": 2 * 150.0 * 2.0, "rail": 0.0, "carriages": 0.0,
                                                    "total": 600.0}
    rail = Relocation(mode="rail", robots=2, rail=RAIL)
    flat = [_placement(2 * k, 2 * k + 2, 0, 1) for k in range(4)]
    mr = plan_moves(flat, job, rail, 600.0)
    assert mr.count("crane") == 0 and relocation_cost(rail, mr, 2.0, 8.0).as_dict() == {
        "crane_hire": 0.0, "rail": 8.0 * 500.0, "carriages": 2 * 20000.0, "total": 44000.0}


# ------------------------------------------------------------------ on a scenario's band
def _scenario_file(tmp_path: Path, relocation: str, band: tuple[str, str] = ("[-5.0, 5.0]", "[0.0, 3.0]")) -> Path:
    """paper_clean.toml on a 10 x 3 m band, with a relocation section, beside its files."""
    for data in BUILTIN.glob("*.csv"):
        shutil.copy(data, tmp_path / data.name)
    text = (BUILTIN / "paper_clean.toml").read_text()
    text = text.replace("stations_m = [-95.0, 95.0]", f"stations_m = {band[0]}")
    text = text.replace("heights_m = [0.0, 11.6]", f"heights_m = {band[1]}")
    assert f"stations_m = {band[0]}" in text
    path = tmp_path / "job.toml"
    path.write_text(text + "\n" + relocation)
    return path


CRANE_TOML = """[cleaning.surface.relocation.crane]
rig_s = 300.0
lift_m = 3.0
hoist_m_s = 0.2
travel_m_s = 0.5
retension_s = 120.0
capacity_kg = 1000.0
hire_per_h = 150.0
"""
RAIL_TOML = """[cleaning.surface.relocation.rail]
speed_m_s = 0.3
accel_m_s2 = 0.3
jerk_m_s3 = 1.0
settle_s = 30.0
cost_per_m = 500.0
carriage_cost = 20000.0
"""


def test_a_band_by_rail_is_its_cleaning_and_its_moves_with_a_crane_between_rows(tmp_path):
    """paper_clean on a 10 x 3 m band by rail, a crane between rows, two robots: every move
    along a row is by rail (its scurve move over the centres' distance and the settle), the
    first of each new row by crane; each robot's hours are its placements' cleaning and its
    moves; the job's the slowest's; costs by the module's rules."""
    plain = load_scenario(str(_scenario_file(tmp_path, "")))
    base = surface_job(plain, move_time_s=600.0)
    sc = load_scenario(str(_scenario_file(tmp_path, "[cleaning.surface.relocation]\nmode = \"rail\"\nrobots = 2\n"
                                                    "frame_mass_kg = 300.0\n" + CRANE_TOML + RAIL_TOML)))
    job = surface_job(sc, move_time_s=600.0)
    assert len(job.placements) == len(base.placements) and np.array_equal(job.job_s, base.job_s)
    m = job.moves
    assert sorted(m.order) == list(range(len(job.placements))) and set(m.robot) == {0, 1}
    rows = {p.z_range for p in job.placements}
    assert len(rows) >= 2
    rel = sc.cleaning.surface.relocation
    for r in (0, 1):
        visits = m.order[m.robot == r]
        centres = np.array([job.placements[i].centre_S for i in visits])
        d = np.linalg.norm(np.diff(centres, axis=0), axis=1)
        z = [job.placements[i].z_range for i in visits]
        same = np.array([a == b for a, b in zip(z[:-1], z[1:])])
        expected = np.where(same, [rail_move_s(v, rel.rail) for v in d], crane_move_s(d, rel.crane))
        np.testing.assert_allclose(m.move_in_s[m.robot == r][1:], expected, rtol=1e-14)
        # a robot's rows are visited once each: one crane move per row change
        assert (~same).sum() == len(set(z)) - 1
        assert job.robot_seconds[r] == pytest.approx(base.job_s[visits].sum() + expected.sum(), rel=1e-14)
    assert job.seconds == job.robot_seconds.max()
    s = job.summary()
    for key, value in base.summary().items():  # every key of today's summary stays
        assert key in s and (key in ("hours", "area_rate_m2_h", "move_time_s") or s[key] == value)
    moved = s["relocation"]
    assert moved["moves"]["rail"] + moved["moves"]["crane"] == len(job.placements) - 2
    assert moved["cost"] == {"crane_hire": 2 * 150.0 * job.hours, "rail": 500.0 * 10.0, "carriages": 40000.0,
                             "total": 2 * 150.0 * job.hours + 45000.0}
    assert moved["move_hours"]["rail"] == pytest.approx(m.move_in_s[m.kind == "rail"].sum() / 3600.0, rel=1e-14)
    clean, turns, moves = job.parts_s()
    assert clean + turns + moves == pytest.approx(job.seconds, rel=1e-14)


def test_a_fixed_section_with_one_robot_gives_today_s_hours(tmp_path):
    """mode = "fixed", one robot: the same placements, hours and moves as without the section."""
    plain = surface_job(load_scenario(str(_scenario_file(tmp_path, ""))), move_time_s=600.0)
    fixed = surface_job(load_scenario(str(_scenario_file(tmp_path, "[cleaning.surface.relocation]\n"
                                                                    "mode = \"fixed\"\n"))), move_time_s=600.0)
    assert fixed.hours == pytest.approx(plain.hours, rel=1e-14) and fixed.move_time_s == 600.0
    assert fixed.moves_said() == plain.moves_said() == "moves of 600 s"
    assert plain.moves is None and "relocation" not in plain.summary()


@pytest.mark.parametrize("section, key, words", [
    ("mode = \"crane\"\n", "cleaning.surface.relocation.crane", "missing: mode = \"crane\" needs the crane's figures"),
    ("mode = \"rail\"\n", "cleaning.surface.relocation.rail", "missing: mode = \"rail\" needs the carriage's figures"),
    ("mode = \"crane\"\n" + CRANE_TOML, "cleaning.surface.relocation.frame_mass_kg",
     "missing: a crane lifts the frame"),
    ("robots = 0\n", "cleaning.surface.relocation.robots", "greater than or equal to 1"),
    ("mode = \"boat\"\n", "cleaning.surface.relocation.mode", "crane"),
    ("mode = \"crane\"\nframe_mass_kg = 100.0\n" + CRANE_TOML.replace("hoist_m_s = 0.2", "hoist_m_s = 0.0"),
     "cleaning.surface.relocation.crane.hoist_m_s", "must be above 0 and at most 10 m/s"),
    ("mode = \"rail\"\n" + RAIL_TOML.replace("settle_s = 30.0", "settle_s = -1.0"),
     "cleaning.surface.relocation.rail.settle_s", "must be between 0 and 86400 s"),
])
def test_a_bad_relocation_section_is_one_line_naming_its_key(tmp_path, section, key, words):
    path = _scenario_file(tmp_path, "[cleaning.surface.relocation]\n" + section)
    with pytest.raises(ScenarioError) as err:
        load_scenario(str(path))
    assert key in str(err.value) and words in str(err.value) and "\n" not in str(err.value)


def test_a_frame_heavier_than_the_crane_is_refused_in_one_line(tmp_path):
    """The crane lifts the frame (its frame_mass_kg) and the platform (paper_clean's 5 kg)."""
    path = _scenario_file(tmp_path, "[cleaning.surface.relocation]\nmode = \"crane\"\nframe_mass_kg = 996.0\n"
                                    + CRANE_TOML)
    with pytest.raises(ScenarioError) as err:
        surface_job(load_scenario(str(path)), move_time_s=600.0)
    assert str(err.value).endswith("cleaning.surface.relocation.crane.capacity_kg: the frame (996 kg) with the "
                                   "platform (5 kg) is heavier than the crane's capacity_kg (1000 kg)")
    res = runner.invoke(app, ["clean", str(path), "--surface", "--duration", "0.1", "--out", str(tmp_path / "o")])
    one_line_exit_2(res, "heavier than the crane's capacity_kg (1000 kg)")
    assert not (tmp_path / "o").exists()
    ok = _scenario_file(tmp_path, "[cleaning.surface.relocation]\nmode = \"crane\"\nframe_mass_kg = 995.0\n"
                                  + CRANE_TOML)
    assert surface_job(load_scenario(str(ok)), move_time_s=600.0).moves.count("crane") > 0


def test_rail_mode_with_a_jump_and_no_crane_is_refused_in_one_line(tmp_path):
    path = _scenario_file(tmp_path, "[cleaning.surface.relocation]\nmode = \"rail\"\n" + RAIL_TOML)
    res = runner.invoke(app, ["clean", str(path), "--surface", "--duration", "0.1", "--out", str(tmp_path / "o")])
    # found once the band is tiled: the tiling's progress lines, then the one error line
    assert res.exit_code == 2 and (res.exception is None or isinstance(res.exception, SystemExit))
    errors = [line for line in res.stderr.splitlines() if not line.startswith("surface tiling:")]
    assert len(errors) == 1 and errors[0].startswith("error: "), res.stderr
    for words in ("cleaning.surface.relocation.rail", "the rail cannot reach the placement at stations 3.75 to 5 m, "
                  "heights 0.7543 to 1.507 m: it cleans other heights", "give [cleaning.surface.relocation.crane]"):
        assert words in errors[0]
    assert not (tmp_path / "o").exists()


def test_move_time_with_a_rail_is_refused_and_without_it_the_rail_times_the_moves(tmp_path):
    path = _scenario_file(tmp_path, "[cleaning.surface.relocation]\nmode = \"rail\"\nframe_mass_kg = 300.0\n"
                                    + CRANE_TOML + RAIL_TOML)
    sc = load_scenario(str(path))
    with pytest.raises(SpecError) as err:
        command.estimate(CleanSpec(surface=True, move_time=300.0), sc)
    line = f"{err.value.flag} {err.value.value}: {err.value.detail}"
    assert line == ("--move-time 300: goes with no [cleaning.surface.relocation] or its mode = \"fixed\"; the "
                    "scenario's mode = \"rail\" times each move by its own figures: leave --move-time out")
    with pytest.raises(SpecError):
        command.tile(CleanSpec(surface=True, move_time=300.0), sc)
    res = runner.invoke(app, ["clean", str(path), "--surface", "--move-time", "300", "--duration", "0.1",
                              "--out", str(tmp_path / "o")])
    one_line_exit_2(res, "--move-time 300: goes with no [cleaning.surface.relocation]")
    assert not (tmp_path / "o").exists()
    assert CleanSpec().move_time is None and CleanSpec().move_time_s == 600.0
    res = runner.invoke(app, ["clean", str(path), "--surface", "--duration", "0.1", "--no-compare", "--plant", "own",
                              "--out", str(tmp_path / "o")], terminal_width=4000)
    assert res.exit_code == 0, res.output
    s = json.loads((tmp_path / "o" / "summary.json").read_text())["surface"]
    job = command.tile(CleanSpec(surface=True), sc)
    assert s["hours"] == job.hours and s["relocation"]["moves"]["rail"] == job.moves.count("rail") > 0
    assert "by rail" in res.stdout and "relocation cost:" in res.stdout
    rows = np.genfromtxt(tmp_path / "o" / "placements.csv", delimiter=",", names=True, comments="#")
    assert rows["move_in_s"].sum() == pytest.approx(job.move_s.sum(), rel=1e-9)
    assert int(rows["by_crane"].sum()) == job.moves.count("crane")


def test_a_rail_move_carries_the_frame_from_where_it_stands():
    """rail_move_scenario: C starts where the frame stood, turned as it stood, and ends the move
    ``distance`` along the frame's x axis laid level in S, its axes unchanged (a straight
    rail), at rest after the double-S move's time; the platform held, the tool off the hull.
    The planned wrench on a still ship, with the carriage at its peak acceleration a along
    the rail: the platform's weight and m a, to 1e-9 N (the hand-worked case)."""
    import marinecdpr
    from marinecdpr.motion.carriage import carriage_motion
    from marinecdpr.motion.rail import scurve_move
    from marinecdpr.motion.ship import frame_axes
    from marinecdpr.scenario.relocation import RailMoves
    from marinecdpr.studies.relocation import rail_move_scenario

    sc = load_scenario("paper_clean").with_updates("ship", frame_origin_m=[10.0, -16.0, 3.0],
                                                   frame_orientation_deg=[-12.0, 2.0, 8.0])
    sc = sc.with_changes(base_motion={"type": "still"})
    rail = RailMoves(speed_m_s=0.3, accel_m_s2=0.3, jerk_m_s3=1.0, settle_s=30.0)
    move = rail_move_scenario(sc, rail, 2.0, hold_C=[0.95, 0.0, 0.7], mass_kg=300.0)
    assert move.cleaning is None and list(move.ship.frame_origin_m) == [0.0, 0.0, 0.0]
    T = scurve_move(2.0, 0.3, 0.3, 1.0).duration_s
    assert move.time.duration_s == pytest.approx(2.0 + T + 5.0, rel=1e-15)
    R = frame_axes([-12.0, 2.0, 8.0])
    level = np.array([R[0, 0], R[1, 0], 0.0]) / np.hypot(R[0, 0], R[1, 0])
    r_S, v_S, a_S, R_SC, _, _ = carriage_motion(move.ship, np.array([0.0, 1.0, 2.0 + T, move.time.duration_s]))
    np.testing.assert_allclose(r_S[0], [10.0, -16.0, 3.0], atol=1e-12)
    np.testing.assert_allclose(r_S[2:], [np.array([10.0, -16.0, 3.0]) + 2.0 * level] * 2, atol=1e-12)
    np.testing.assert_allclose(R_SC, [R] * 4, atol=1e-12)
    assert np.abs(v_S[[0, 2, 3]]).max() < 1e-12
    # the hand-worked wrench while the carriage accelerates at its peak (still ship)
    p = marinecdpr.plan(move)
    t_peak = p.t[np.argmax(np.linalg.norm(carriage_motion(move.ship, p.t)[2], axis=1))]
    k = int(np.flatnonzero(p.t == t_peak)[0])
    a = carriage_motion(move.ship, p.t[k:k + 1])[2][0]
    assert np.linalg.norm(a) == pytest.approx(0.3, rel=1e-6)
    m, g = move.robot.mass_kg, move.environment.gravity_m_s2
    f_C = R.T @ (m * a + m * np.array([0.0, 0.0, g]))  # the cables' and guide's force on P, in C
    np.testing.assert_allclose(p.wrench[k, :3], f_C, atol=1e-9)
    with pytest.raises(ValueError, match="positive"):
        rail_move_scenario(sc, rail, 0.0, hold_C=[0.95, 0.0, 0.7])
