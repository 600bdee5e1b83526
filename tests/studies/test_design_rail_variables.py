"""The carriage's limits as design variables and its accelerations as a load the cables hold
(issue 39, item 4): a study's ``[variables]`` ``rail_speed_m_s``, ``rail_accel_m_s2`` and
``rail_jerk_m_s3`` override ``[relocation.rail]`` in its candidates moved by rail, the
carriage's drive is priced per kilowatt of its peak power (``drive_cost_per_kW``), and a rail
candidate's margin ``rail_accel_m_s2`` is the largest acceleration with which its cables hold
the platform at the panel's centre, less its own (tests/data/tiny_relocation_study.toml with
the variables)."""

from __future__ import annotations

import csv

import numpy as np
import pytest
from typer.testing import CliRunner

pytest.importorskip("pymoo")

from test_design_relocation import STUDY, _folder  # noqa: E402

from marinecdpr.cli.app import app  # noqa: E402
from marinecdpr.geometry.kinematics import cable_kinematics  # noqa: E402
from marinecdpr.model.tension import distribute_tensions, largest_headroom, pseudo_inverse_tensions  # noqa: E402
from marinecdpr.motion.ship import frame_axes  # noqa: E402
from marinecdpr.scenario.relocation import RailMoves  # noqa: E402
from marinecdpr.studies.design import (  # noqa: E402
    candidate_rail, candidate_scenario, evaluate, load_design, rail_held_acceleration, search, study_cells,
)
from marinecdpr.studies.relocation import crane_move_s, rail_move_s  # noqa: E402
from marinecdpr.studies.surface import surface_job  # noqa: E402

runner = CliRunner()

RAIL_VARIABLES = ("robots = [1, 3]                     # one robot, or three each on its own stretch\n"
                  "rail_speed_m_s = [0.2, 0.6]\nrail_accel_m_s2 = [0.2, 1.0]\nrail_jerk_m_s3 = 2.0\n")
STUDY_RAIL = STUDY.replace("robots = [1, 3]                     # one robot, or three each on its own stretch\n",
                           RAIL_VARIABLES).replace("carriage_cost = 20000.0", "carriage_cost = 20000.0\n"
                                                                               "drive_cost_per_kW = 3000.0")
assert STUDY_RAIL.count("rail_accel_m_s2") == 1 and "drive_cost_per_kW" in STUDY_RAIL


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    path = _folder(tmp_path_factory.mktemp("rail_variables"), STUDY_RAIL)
    spec, template = load_design(path)
    return path, spec, template, study_cells(spec, path.parent)


def _x(spec, **kw) -> dict:
    x = {k: (v[0] if isinstance(v, tuple) else v) for k, v in spec.bounds().items()}
    return x | {"winch": "w", "rope": "r", "pattern": "uncrossed", "relocation": "rail", "robots": 1} | kw


def test_a_rail_candidate_s_moves_take_the_double_s_times_at_its_own_carriage(study):
    """A rail candidate at 0.5 m/s, 0.8 m/s^2 and the held 2 m/s^3: each move along a row
    the double-S time over the placements' distance at those figures and the 30 s settle
    (:func:`rail_move_s`), each other by the study's crane; its hours those of the same
    study with [relocation.rail] at those figures and no variables, and fewer than at the
    study's own 0.3 m/s and 0.3 m/s^2."""
    path, spec, template, cells = study
    x = _x(spec, rail_speed_m_s=0.5, rail_accel_m_s2=0.8)
    assert set(spec.bounds()) - set(_x(spec)) == set() and spec.bounds()["rail_jerk_m_s3"] == (2.0, 2.0)
    e = evaluate(spec, template, x, cells)
    sc = candidate_scenario(spec, template, x)
    job = surface_job(sc, move_time_s=spec.move_time_s, digits=2)
    mine = RailMoves(speed_m_s=0.5, accel_m_s2=0.8, jerk_m_s3=2.0, settle_s=30.0)
    order = job.moves.order
    centres = np.array([job.placements[i].centre_S for i in order])
    d = np.linalg.norm(np.diff(centres, axis=0), axis=1)
    kind = job.moves.kind[1:]
    by_hand = np.where(kind == "rail", rail_move_s(d, mine), crane_move_s(d, spec.relocation.crane))
    assert (kind == "rail").sum() > 5 and e.rail_moves == (kind == "rail").sum()
    assert e.move_hours * 3600.0 == pytest.approx(by_hand.sum(), rel=1e-13)
    held = _folder(path.parent.parent / "held_rail", STUDY.replace("speed_m_s = 0.3\naccel_m_s2 = 0.3\njerk_m_s3 = 1.0",
                                                                  "speed_m_s = 0.5\naccel_m_s2 = 0.8\njerk_m_s3 = 2.0"))
    spec_h, template_h = load_design(held)
    x_h = {k: v for k, v in x.items() if not k.startswith("rail_")}
    same = evaluate(spec_h, template_h, x_h, study_cells(spec_h, held.parent))
    assert same.surface_hours == e.surface_hours and same.move_hours == e.move_hours
    study_own = evaluate(spec, template, _x(spec, rail_speed_m_s=0.3, rail_accel_m_s2=0.3, rail_jerk_m_s3=1.0), cells)
    unset = evaluate(spec, template, x_h, cells)  # no carriage variables in x: [relocation.rail]'s figures
    assert unset.move_hours == study_own.move_hours > e.move_hours and study_own.cleaning_hours == e.cleaning_hours


def test_the_carriage_s_drive_costs_per_kilowatt_of_its_peak_power(study):
    """The carriages' cost: per robot, 20 000 and 3 000 a kilowatt of (300 kg frame + 5 kg
    platform) x accel x speed; a crane candidate pays no carriage, its rail variables unused."""
    _, spec, template, cells = study
    for speed, accel, robots in ((0.5, 0.8, 1), (0.2, 1.0, 3)):
        e = evaluate(spec, template, _x(spec, rail_speed_m_s=speed, rail_accel_m_s2=accel, robots=robots), cells)
        job = surface_job(candidate_scenario(spec, template, e.x), move_time_s=spec.move_time_s, digits=2)
        drive = 3000.0 * 305.0 * accel * speed / 1000.0
        assert job.relocation_cost.carriages == pytest.approx(robots * (20000.0 + drive), rel=1e-14)
        assert e.relocation_cost == pytest.approx(robots * 150.0 * job.hours + 500.0 * 10.0
                                                  + robots * (20000.0 + drive), rel=1e-14)
    crane = evaluate(spec, template, _x(spec, relocation="crane", rail_accel_m_s2=1.0), cells)
    assert crane.relocation_cost == pytest.approx(150.0 * crane.surface_hours, rel=1e-14)
    assert "rail_accel_m_s2" not in crane.margins


def _held_wrench(m: float, g: float, a: float, d_C: np.ndarray, up_C: np.ndarray) -> np.ndarray:
    """By hand: the platform held in C while C accelerates at a along d (in C) on a still
    ship: the cables give m (a d + g up), no moment (the platform's mass at its origin,
    not turning)."""
    return np.concatenate([m * (a * d_C + g * up_C), np.zeros(3)])


def test_on_a_still_ship_the_carriage_s_largest_acceleration_puts_a_cable_at_its_limit(study):
    """A still ship, the frame where the screen found the seas hardest (leaning 2.6 deg,
    turned 0.74 deg), the platform held at the panel's centre: the largest acceleration
    along the rail (the frame's x axis laid level) is where the planner's exact tension
    solver first finds no tensions for m (a + g) turned into C: the largest headroom any
    tensions keep there is 0 to 1e-9 N, the solver finds tensions 1e-6 below and none 1e-6
    above; the wrench is m (a + g) by hand to 1e-9 N."""
    _, spec, template, cells = study
    x = _x(spec, rail_accel_m_s2=0.6)
    e = evaluate(spec, template, x, cells)
    sc = candidate_scenario(spec, template, x)
    rail = candidate_rail(spec, x)
    assert rail.accel_m_s2 == 0.6
    a_max = rail_held_acceleration(sc, rail, 1.9, [], e.frame_origin_m, e.frame_orientation_deg)
    R_SC = frame_axes(e.frame_orientation_deg)
    level = np.array([R_SC[0, 0], R_SC[1, 0], 0.0]) / np.hypot(R_SC[0, 0], R_SC[1, 0])
    d_C, up_C = R_SC.T @ level, R_SC.T @ np.array([0.0, 0.0, 1.0])
    panel = np.asarray(sc.cleaning.panel_m)
    hold = np.array([[panel[:, 0].mean(), 0.0, panel[:, 1].mean()]])
    robot = sc.robot
    c = list(robot.controlled)
    J = cable_kinematics(hold, np.eye(3)[None], robot.frame_anchors, robot.platform_anchors,
                         np.zeros((1, 6))).J_tilde[:, :, c]
    from marinecdpr.studies.screen import held_acceleration

    placed = sc.with_updates("ship", frame_origin_m=e.frame_origin_m, frame_orientation_deg=e.frame_orientation_deg)
    h = held_acceleration(placed, [], level, hold_C=hold[0], duration_s=10.0)
    assert h.still_m_s2 == pytest.approx(a_max, rel=1e-14) and h.cells_m_s2.size == 0
    for a in (0.0, 1.0, a_max):
        np.testing.assert_allclose(h.w0 + a * h.per_m_s2, _held_wrench(robot.mass_kg, 9.8, a, d_C, up_C),
                                   rtol=0, atol=1e-9)
    w = _held_wrench(robot.mass_kg, 9.8, a_max, d_C, up_C)[None, c]
    T_s, _ = pseudo_inverse_tensions(J, w)
    assert abs(largest_headroom(J, T_s, robot.tension_min, robot.tension_max)[0]) < 1e-9
    w_minus = _held_wrench(robot.mass_kg, 9.8, -a_max, d_C, up_C)[None, c]
    T_s, _ = pseudo_inverse_tensions(J, w_minus)
    assert largest_headroom(J, T_s, robot.tension_min, robot.tension_max)[0] > -1e-9
    for scale, holds in ((1.0 - 1e-6, True), (1.0 + 1e-6, False)):
        both = np.concatenate([_held_wrench(robot.mass_kg, 9.8, s * scale * a_max, d_C, up_C)[None, c]
                               for s in (1.0, -1.0)])
        sol = distribute_tensions(np.repeat(J, 2, axis=0), both, robot.tension_min, robot.tension_max)
        assert bool(sol.feasible.all()) is holds
    assert 300.0 < a_max < 500.0  # 5 kg on cables of 10 to 1 333 N


def test_a_rail_candidate_s_margin_is_its_largest_acceleration_in_the_seas_it_works_in_less_its_own(study):
    """The margin: the largest acceleration in the sea states the screen passes (the sea's
    extreme over one frame-width move along each facet), below the still ship's, less the
    candidate's 0.6 m/s^2; a crane candidate has none."""
    _, spec, template, cells = study
    x = _x(spec, rail_accel_m_s2=0.6)
    e = evaluate(spec, template, x, cells)
    sc = candidate_scenario(spec, template, x)
    rail = candidate_rail(spec, x)
    assert e.sea_share == 1.0  # both sea states work
    seas = rail_held_acceleration(sc, rail, 1.9, cells, e.frame_origin_m, e.frame_orientation_deg)
    still = rail_held_acceleration(sc, rail, 1.9, [], e.frame_origin_m, e.frame_orientation_deg)
    assert e.margins["rail_accel_m_s2"] == seas - 0.6 and e.slack["rail_accel_m_s2"] == (seas - 0.6) / seas
    assert still - 5.0 < seas < still - 0.5
    one = rail_held_acceleration(sc, rail, 1.9, cells[:1], e.frame_origin_m, e.frame_orientation_deg)
    assert seas < one < still  # the higher sea takes more


def test_a_carriage_accelerating_harder_than_the_cables_hold_fails_naming_the_rail_s_acceleration(tmp_path):
    """A 50 kg platform in a tall narrow frame (1.0 x 2.9 m: steep cables, little to push it
    along the rail with) in a mild sea (Hs 0.2 m): its cables hold it against about 12 m/s^2
    of the carriage's; at 15 m/s^2 the candidate fails on that alone, in one line naming
    the rail's acceleration; at 10 it passes."""
    text = (STUDY_RAIL.replace("base_kg = 5.0", "base_kg = 50.0").replace("frame_width_m = 1.9", "frame_width_m = 1.0")
            .replace("frame_height_m = 1.4", "frame_height_m = 2.9")
            .replace("rail_accel_m_s2 = [0.2, 1.0]", "rail_accel_m_s2 = [1.0, 20.0]"))
    path = _folder(tmp_path / "heavy", text)
    (path.parent / "seas.csv").write_text("hs_m,tp_s,probability\n0.2,8.0,1.0\n")
    spec, template = load_design(path)
    cells = study_cells(spec, path.parent)
    bad = evaluate(spec, template, _x(spec, rail_accel_m_s2=15.0), cells)
    good = evaluate(spec, template, _x(spec, rail_accel_m_s2=10.0), cells)
    limit = 15.0 + bad.margins["rail_accel_m_s2"]
    assert 11.0 < limit < 14.0 and good.margins["rail_accel_m_s2"] == pytest.approx(limit - 10.0, rel=1e-12)
    assert good.feasible and not bad.feasible and bad.sea_share == 1.0
    assert bad.reason.startswith(f"rail_accel_m_s2 short by {15.0 - limit:.3g} (") and "\n" not in bad.reason
    assert "carriage accelerates along the rail" in bad.reason and "accel_m_s2 15 m/s^2" in bad.reason


def test_the_search_through_the_cli_varies_the_carriage_and_writes_its_columns(study, tmp_path):
    """``marinecdpr design`` on the study: candidates.csv carries rail_speed_m_s and
    rail_accel_m_s2 after the continuous variables (blank where moved by crane), within their
    bounds, the jerk held, and margin_rail_accel_m_s2 after the other margins (blank by
    crane); each rail row's cost has its carriage's drive at its own speed and acceleration."""
    path, spec, template, cells = study
    res = runner.invoke(app, ["design", str(path), "--no-verify", "--out", str(tmp_path / "o")], terminal_width=4000)
    assert res.exit_code == 0, res.output
    with open(tmp_path / "o" / "candidates.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    with open(tmp_path / "o" / "candidates.csv", newline="") as fh:
        head = next(csv.reader(fh))
    at = head.index("overlap_share")
    assert head[at + 1:at + 4] == ["rail_speed_m_s", "rail_accel_m_s2", "rail_jerk_m_s3"]
    assert head[-4:] == ["margin_clearance_m", "margin_rail_accel_m_s2", "feasible", "reason"]
    rail = [r for r in rows if r["relocation"] == "rail"]
    crane = [r for r in rows if r["relocation"] == "crane"]
    assert rail and len(rail) + len(crane) == len(rows) == 4
    for r in crane:
        assert r["rail_speed_m_s"] == r["rail_accel_m_s2"] == r["margin_rail_accel_m_s2"] == ""
    for r in rail:
        v, a, robots = float(r["rail_speed_m_s"]), float(r["rail_accel_m_s2"]), int(r["robots"])
        assert 0.2 <= v <= 0.6 and 0.2 <= a <= 1.0 and float(r["rail_jerk_m_s3"]) == 2.0
        assert float(r["margin_rail_accel_m_s2"]) > 100.0
        hours = float(r["surface_hours"])
        moves = robots * 150.0 * hours * (int(r["crane_moves"]) > 0) + 5000.0 + robots * (20000.0 + 3.0 * 305.0 * a * v)
        assert float(r["relocation_cost"]) == pytest.approx(moves, rel=1e-9)
    result = search(spec, template, cells)
    assert len({(e.x["rail_speed_m_s"], e.x["rail_accel_m_s2"]) for e in result.evaluations}) == 4


@pytest.mark.parametrize("edit, words", [
    (lambda s: s.replace("[relocation.rail]", "[relocation.unused]").replace('relocation = ["crane", "rail"]',
                                                                            'relocation = ["crane"]'),
     None),
    (lambda s: s.replace('relocation = ["crane", "rail"]', 'relocation = ["crane"]'),
     "variables.rail_speed_m_s: sets the carriage's limits, but no candidate moves by rail"),
    (lambda s: s.replace("rail_accel_m_s2 = [0.2, 1.0]", "rail_accel_m_s2 = [0.0, 1.0]"), "variables.rail_accel_m_s2"),
    (lambda s: s.replace("rail_accel_m_s2 = [0.2, 1.0]", "rail_accel_m_s2 = [1.0, 0.5]"), "low <= high"),
    (lambda s: s.replace("rail_accel_m_s2 = [0.2, 1.0]", "rail_accel_m_s2 = 25.0"), "variables.rail_accel_m_s2"),
    (lambda s: s.replace("rail_jerk_m_s3 = 2.0", "rail_jerk_m_s3 = \"fast\""), "variables.rail_jerk_m_s3"),
    (lambda s: s.replace("frame_mass_kg = 300.0", "").replace("[relocation.crane]", "[relocation.unused]")
     .replace('relocation = ["crane", "rail"]', 'relocation = ["rail"]'), "frame_mass_kg"),
])
def test_a_bad_carriage_variable_is_one_line_naming_the_key(tmp_path, edit, words):
    """Each refused in one line naming what and where, exit 2: a carriage variable without
    [relocation.rail] or without a rail candidate, an acceleration of 0, a reversed range,
    beyond two g, not a number; a drive priced per kW without the frame's mass."""
    text = edit(STUDY_RAIL)
    if words is None:  # no [relocation.rail] at all: the unused table removed
        text = text[:text.index("[relocation.unused]")] + text[text.index("[[winches]]"):]
        words = "variables.rail_speed_m_s: sets the carriage's limits: give [relocation.rail]"
    path = _folder(tmp_path / "bad", text)
    res = runner.invoke(app, ["design", str(path), "--no-verify", "--out", str(tmp_path / "o")], terminal_width=4000)
    assert res.exit_code == 2, res.output
    said = res.output.strip()
    assert "\n" not in said and "Traceback" not in said and words in said, said
    assert not (tmp_path / "o").exists()
