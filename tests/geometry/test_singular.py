"""Issue 21, items 1, 12 and 14: a singular robot through every command, the shortfall's
direction always named, and the infeasibility line's sizing advice.

The fixture robot is the one a user met: a 4 x 3 m frame with platform anchors at
+-0.4 x +-0.3 m, a scaled copy (ratio 0.2) of the frame's, so that every level pose is
singular. Before the fix ``plan`` ended in a traceback from the figures and ``check``
accepted it without a word.
"""

from __future__ import annotations

import re
import shutil
from importlib import resources
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

import marinecdpr
from marinecdpr.cli.app import app
from marinecdpr.geometry.kinematics import cable_kinematics
from marinecdpr.geometry.rotations import matrix_from_euler
from marinecdpr.model.tension import full_rank
from marinecdpr.planning.planner import check_trajectory
from marinecdpr.planning.verdicts import direction_words as _direction
from marinecdpr.scenario.robot import scaled_copy
from marinecdpr.studies.workspace import singular_poses

runner = CliRunner()
BUILTIN = resources.files("marinecdpr.scenario") / "builtin"

ANCHORS = {  # the paper's cables -> the frame-shaped robot's
    "[0.0, 0.0, 1.4]": "[0.0, 0.0, 3.0]", "[1.9, 0.0, 1.4]": "[4.0, 0.0, 3.0]",
    "[1.9, 0.0, 0.0]": "[4.0, 0.0, 0.0]",
    "[-0.125, 0.0, 0.15]": "[-0.4, 0.0, 0.3]", "[0.125, 0.0, 0.15]": "[0.4, 0.0, 0.3]",
    "[0.125, 0.0, -0.15]": "[0.4, 0.0, -0.3]", "[-0.125, 0.0, -0.15]": "[-0.4, 0.0, -0.3]",
}


def _frame_shaped(text: str, extra: dict[str, str]) -> str:
    for old, new in {**ANCHORS, **extra}.items():
        assert old in text, old
        text = text.replace(old, new)
    return text


@pytest.fixture(scope="module")
def singular_files(tmp_path_factory) -> dict[str, Path]:
    """The frame-shaped robot on the paper's ship (circle) and in paper_clean's sea (its
    panel moved into the larger frame), on short horizons."""
    folder = tmp_path_factory.mktemp("singular")
    paper = _frame_shaped((BUILTIN / "paper.toml").read_text(), {
        "center_m = [0.6, 0.0, 0.7]": "center_m = [2.0, 0.0, 1.5]",
        "step_s = 0.001": "step_s = 0.01", "duration_s = 15.0": "duration_s = 1.0"})
    clean = _frame_shaped((BUILTIN / "paper_clean.toml").read_text(), {
        "[[0.3, 0.3], [1.6, 0.3], [1.6, 1.1], [0.3, 1.1]]": "[[1.0, 1.0], [3.0, 1.0], [3.0, 2.0], [1.0, 2.0]]",
        "step_s = 0.001": "step_s = 0.01", "duration_s = 78.0": "duration_s = 1.0"})
    shutil.copy(BUILTIN / "paper_sea_rao.csv", folder / "paper_sea_rao.csv")
    files = {"paper": folder / "singular.toml", "clean": folder / "singular_clean.toml"}
    files["paper"].write_text(paper)
    files["clean"].write_text(clean)
    return files


# ----------------------------------------------------------------- the geometry, worked out
def test_a_scaled_copy_is_found_and_its_cables_meet_at_one_point_at_every_level_pose(singular_files):
    sc = marinecdpr.load_scenario(str(singular_files["paper"]))
    assert scaled_copy(sc.robot) == pytest.approx(0.2, rel=1e-12)
    assert scaled_copy(marinecdpr.load_scenario("paper").robot) is None  # 0.25 x 0.3 on 1.9 x 1.4
    # hand-worked: p_i = s c_i + b with s = 0.2, b = -(0.4, 0, 0.3); level at x, every cable's
    # line passes through q = (x + b) / (1 - s)
    r = sc.robot
    s, b = 0.2, np.array([-0.4, 0.0, -0.3])
    np.testing.assert_allclose(r.platform_anchors, s * r.frame_anchors + b, atol=1e-15)
    rng = np.random.default_rng(5)
    x = np.c_[rng.uniform(1.0, 3.0, 50), np.zeros(50), rng.uniform(0.8, 2.2, 50)]
    for xi in x:
        q = (xi + b) / (1 - s)
        d = r.frame_anchors - (xi + r.platform_anchors)  # along each cable
        to_q = q - r.frame_anchors
        np.testing.assert_allclose(np.cross(d, to_q), 0.0, atol=1e-12)  # q on every cable's line
    # so J~ loses rank at every level pose, and not once the platform tilts
    level = cable_kinematics(x, matrix_from_euler(np.zeros((50, 3))), r.frame_anchors, r.platform_anchors)
    tilted = cable_kinematics(x, matrix_from_euler(np.c_[np.zeros(50), np.full(50, 0.2), np.zeros(50)]),
                              r.frame_anchors, r.platform_anchors)
    assert not full_rank(level.J_tilde[:, :, [0, 2, 4]]).any()
    assert full_rank(tilted.J_tilde[:, :, [0, 2, 4]]).all()


def test_scaled_copy_recovers_any_ratio_and_refuses_a_perturbed_one():
    from marinecdpr.scenario.robot import Robot

    rng = np.random.default_rng(11)
    for _ in range(20):
        frame = rng.uniform(-3.0, 3.0, (8, 3))
        s = rng.choice([-1.0, 1.0]) * rng.uniform(0.05, 0.9)
        platform = s * frame + rng.uniform(-0.5, 0.5, 3)
        cables = [{"frame_anchor_m": list(c), "platform_anchor_m": list(p)} for c, p in zip(frame, platform)]
        robot = Robot(dofs="spatial", mass_kg=5.0, inertia_kg_m2=[0.1, 0.1, 0.1], tension_min_N=10.0,
                      tension_max_N=450.0, cables=cables)
        assert scaled_copy(robot) == pytest.approx(s, rel=1e-9)
        cables[3]["platform_anchor_m"][1] += 1e-3 * abs(s)
        bent = Robot(dofs="spatial", mass_kg=5.0, inertia_kg_m2=[0.1, 0.1, 0.1], tension_min_N=10.0,
                     tension_max_N=450.0, cables=cables)
        assert scaled_copy(bent) is None


def test_full_rank_agrees_with_the_singular_values_over_random_and_rank_deficient_J():
    rng = np.random.default_rng(3)
    for k in (3, 6):
        J = rng.normal(size=(400, 8, k))
        J[::2, :, -1] = J[::2, :, :-1] @ rng.normal(size=k - 1)  # every other step: a dependent column
        # the slow, obvious check: the smallest singular value against the largest
        sv = np.linalg.svd(J, compute_uv=False)
        expected = sv[:, -1] > 1e-5 * sv[:, 0]
        np.testing.assert_array_equal(full_rank(J), expected)
        assert expected.sum() == 200


def test_the_surveys_count_every_singular_pose(singular_files):
    sc = marinecdpr.load_scenario(str(singular_files["paper"]))
    level = singular_poses(sc)
    assert (level.n_poses, level.n_singular, level.level) == (900, 900, True)
    along = check_trajectory(sc)
    assert (along.n_poses, along.n_singular) == (sc.time.n_steps, sc.time.n_steps)
    assert along.first == "t = 0 s (x = 2.38 m, z = 1.5 m, theta_y = 0 deg)"
    # tilted 10 deg about y: no level step on the trajectory, none singular; the level grid still is
    tilted = sc.with_changes(trajectory=sc.trajectory.model_dump() | {"orientation_deg": [0.0, 10.0, 0.0]})
    assert check_trajectory(tilted).n_singular == 0 and check_trajectory(tilted).message() is None
    assert singular_poses(tilted, orientation_deg=(0.0, 10.0, 0.0)).n_singular == 0
    for name in ("paper", "paper_sea", "paper_clean", "paper_elastic", "paper_as_built"):
        good = marinecdpr.load_scenario(name)
        assert singular_poses(good).n_singular == 0, name


# ----------------------------------------------------------------- every command, alike
def _warnings(res) -> list[str]:
    return [line for line in res.stderr.splitlines() if line.startswith("warning:")]


def test_check_warns_once_per_survey_with_the_layouts_hint_once(singular_files):
    res = runner.invoke(app, ["check", str(singular_files["paper"])])
    assert res.exit_code == 0, res.output
    lines = _warnings(res)
    assert len(lines) == 2, res.stderr
    assert "J~ loses rank (a singular pose) at every one of the 900 level poses across the frame" in lines[0]
    assert "a scaled copy (x 0.2) of the frame's" in lines[0] and "another shape (aspect ratio)" in lines[0]
    assert "at every one of the 101 steps of the trajectory, first at t = 0 s (x = 2.38 m" in lines[1]
    assert "scaled copy" not in lines[1]  # said once
    assert res.stderr.count("\n") == 2  # each a single line
    quiet = runner.invoke(app, ["check", "paper"])
    assert quiet.exit_code == 0 and "warning" not in quiet.stderr


@pytest.mark.figures
def test_plan_writes_its_files_and_exits_3_naming_the_singular_pose(singular_files, tmp_path):
    res = runner.invoke(app, ["plan", str(singular_files["paper"]), "--out", str(tmp_path)])
    assert res.exit_code == 3, res.output
    assert res.exception is None or isinstance(res.exception, SystemExit), res.exception
    assert "Traceback" not in res.output and "Traceback" not in res.stderr
    assert re.search(r"singular steps \(J~ loses rank\) +│ +101 of 101", res.stdout)
    assert re.search(r"eq\. 18 tensions \(N\) +│ +none", res.stdout)
    (line,) = [x for x in res.stderr.splitlines() if x.startswith("infeasible:")]
    assert "at 101 of 101 steps, first at t = 0 s (x = 2.38 m, z = 1.5 m, theta_y = 0 deg): J~ loses rank there " \
           "(a singular pose; the platform's anchors are a scaled copy (x 0.2)" in line
    rows = (tmp_path / "plan.csv").read_text().splitlines()
    assert len(rows) == 102 and rows[1].split(",")[10:14] == ["", "", "", ""]  # Tpinv1..4 empty
    assert (tmp_path / "tensions.png").stat().st_size > 10_000


@pytest.mark.parametrize("command,key,extra", [
    ("simulate", "paper", ["--duration", "0.5"]),
    ("clean", "clean", ["--duration", "0.5"]),
    ("control-study", "paper", ["--duration", "1", "--settle", "0", "--latencies", "0", "--predictions", "none",
                                "--pose-from", "sensor"]),
    ("latency", "paper", ["--calls", "10"]),
])
def test_the_flying_commands_stop_with_the_same_line_exit_3(singular_files, tmp_path, command, key, extra):
    out = [] if command == "latency" else ["--out", str(tmp_path / "out")]
    res = runner.invoke(app, [command, str(singular_files[key]), *out, *extra])
    assert res.exit_code == 3, res.output
    assert res.exception is None or isinstance(res.exception, SystemExit), res.exception
    (line,) = [x for x in res.stderr.splitlines() if x.startswith("error:")]
    assert "J~ loses rank there (a singular pose; the platform's anchors are a scaled copy (x 0.2)" in line
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())


def test_workspace_and_operability_warn_before_their_maps(singular_files, tmp_path):
    res = runner.invoke(app, ["workspace", str(singular_files["paper"]), "--points", "4x3", "--duration", "0.2",
                              "--out", str(tmp_path / "ws")])
    assert res.exit_code == 0, res.output
    (line,) = _warnings(res)
    assert "at every one of the 900 level poses across the frame" in line and "scaled copy (x 0.2)" in line
    assert "0 of 12 poses feasible throughout" in res.stdout
    res = runner.invoke(app, ["operability", str(singular_files["clean"]), "--duration", "2", "--step", "0.1",
                              "--realisations", "1", "--serial", "--out", str(tmp_path / "op")])
    assert res.exit_code == 0, res.output
    (line,) = _warnings(res)
    assert "at every one of the 21 steps of the trajectory, first at t = 0 s (x = 1.1 m, z = 1.1 m" in line
    assert "overall 0 %" in res.stdout


# ----------------------------------------------------------------- item 12: a direction, always
def test_a_shortfall_always_names_its_direction():
    assert _direction(np.array([0.0, 1.0]), np.array(["x", "z"])) == "+z"
    assert _direction(np.array([-0.95, 0.312]), np.array(["x", "z"])) == "-x"
    d = np.array([0.77, -0.64]) / np.hypot(0.77, -0.64)
    assert _direction(d, np.array(["x", "z"])) == "+0.77 x, -0.64 z"
    d = np.array([0.6, 0.0, -0.8])
    assert _direction(d, np.array(["x", "y", "z"])) == "+0.6 x, -0.8 z"  # no zero component written


def test_every_shortfall_in_an_infeasibility_line_has_its_direction(singular_files):
    lines = []
    for mass, t_max in ((200.0, 450.0), (5.0, 12.0), (40.0, 60.0)):
        sc = marinecdpr.load_scenario("paper").with_changes(
            robot=marinecdpr.load_scenario("paper").robot.model_dump(exclude_none=True)
            | {"mass_kg": mass, "tension_max_N": t_max}, time={"step_s": 0.05, "duration_s": 15.0})
        lines.append(marinecdpr.plan(sc).infeasibility())
    for line in lines:
        assert line is not None
        shorts = re.findall(r"N(?: m)? of (?:force|moment)(?: \(([^)]*)\))?", line)
        assert shorts and all(s.startswith(("along ", "about ")) for s in shorts), line


# ----------------------------------------------------------------- item 14: sizing advice
def _weak(text: str, half_width: float, t_max: float) -> str:
    """paper_clean's job on a 4 x 3 m frame whose platform anchors sit +-half_width x +-0.05 m
    apart, with a strong pusher: the brush's moment is what the cables lack."""
    text = _frame_shaped(text, {
        "[[0.3, 0.3], [1.6, 0.3], [1.6, 1.1], [0.3, 1.1]]": "[[1.0, 1.0], [3.0, 1.0], [3.0, 2.0], [1.0, 2.0]]",
        "normal_force_N = [40.0, 80.0]": "normal_force_N = [40.0, 300.0]", "preload_N = 60.0": "preload_N = 250.0",
        "tension_max_N = 450.0": f"tension_max_N = {t_max}", "step_s = 0.001": "step_s = 0.02",
        "duration_s = 78.0": "duration_s = 10.0"})
    for sx, sz in (("-", ""), ("", ""), ("", "-"), ("-", "-")):
        text = text.replace(f"[{sx}0.4, 0.0, {sz}0.3]", f"[{sx}{half_width}, 0.0, {sz}0.05]")
    return text


def test_the_moment_short_line_gives_the_range_and_the_change_that_helps(tmp_path):
    shutil.copy(BUILTIN / "paper_sea_rao.csv", tmp_path / "paper_sea_rao.csv")
    text = (BUILTIN / "paper_clean.toml").read_text()

    def planned(half_width: float, t_max: float):
        path = tmp_path / f"weak_{half_width}_{t_max}.toml"
        path.write_text(_weak(text, half_width, t_max))
        return marinecdpr.plan(marinecdpr.load_scenario(str(path)))

    weak = planned(0.1, 100.0)
    line = weak.infeasibility()
    m = re.search(r"with the rest of the wrench held the cables give (-?[\d.]+) to (-?[\d.]+) N m about y there, "
                  r"against (-?[\d.]+) N m needed: spread the platform's anchors wider \(robot.cables "
                  r"platform_anchor_m: the moment grows with their spacing\) or (?:lower robot.tension_min_N \(cables "
                  r"held at their least tension pull the wrong way there\) or )?raise robot.tension_max_N", line)
    assert m, line
    lo, hi, need = map(float, m.groups())
    assert not lo <= need <= hi  # the need outside what the cables give
    # the range checked by brute force: random tensions within the limits that hold the force
    # (to 1 N) never give a moment outside it
    i = int(np.flatnonzero(~weak.feasible)[0])
    r = weak.robot
    kin = cable_kinematics(weak.pose[i:i + 1, :3], matrix_from_euler(weak.pose[i:i + 1, 3:]), r.frame_anchors,
                           r.platform_anchors)
    A = kin.J_tilde[0][:, [0, 2, 4]].T
    # the slow, obvious check: every tension set that holds the force exactly is T0 + N z
    # (N the null space of the force rows); a fine grid of z kept within the limits spans the
    # moments the cables can give
    T0 = np.linalg.lstsq(A[:2], weak.wrench[i, [0, 2]], rcond=None)[0]
    N = np.linalg.svd(A[:2])[2][2:].T
    z = np.stack(np.meshgrid(*[np.linspace(-400.0, 400.0, 1601)] * 2), axis=-1).reshape(-1, 2)
    T = T0 + z @ N.T
    inside = np.all((T >= r.tension_min) & (T <= r.tension_max), axis=1)
    moments = T[inside] @ A[2]
    assert inside.sum() > 1000
    np.testing.assert_allclose([moments.min(), moments.max()], [lo, hi], rtol=0.02, atol=0.02)
    # and the advice is right: wider anchors, or a higher T_max, hold more of the job
    wider, stronger = planned(0.3, 100.0), planned(0.1, 300.0)
    assert wider.feasible.sum() > weak.feasible.sum() and stronger.feasible.sum() > weak.feasible.sum()


# -------------------- formerly tests/test_singular_sets.py

"""Singular sets a grid of poses misses (issue 37, item 9).

The robot: eight cables, a flat plate (every platform anchor at the plate's height). Four
run from a ring of frame anchors at z = 1.95 m to the plate's corners (+-0.3, +-0.2, 0) m;
four, crossed, from the floor and the top to two points on the plate's x axis (+-0.3, 0, 0) m.
Worked by hand: with the plate level at z = 1.95 m the ring's cables are horizontal (u_z = 0)
and the others attach where p_y = 0, so every cable's moment about the plate's centre,
p x u, has x component p_y u_z - p_z u_y = 0: J~'s moment-about-x column vanishes on the
whole plane z = 1.95 m (rank 5), and nowhere else near it. The default survey's grid
(12 points along z from 0 to 3.9 m: 0.3 m apart, starting at 0.3 m) has no point on the plane.
"""


import numpy as np
import pytest
from typer.testing import CliRunner

import marinecdpr
from marinecdpr.cli.app import app
from marinecdpr.geometry.kinematics import cable_kinematics
from marinecdpr.model.tension import full_rank
from marinecdpr.studies.workspace import map_singular_poses, singular_poses, singular_set, workspace_map

runner = CliRunner()

RING = [([0.0, 0.0, 1.95], [-0.3, -0.2, 0.0]), ([4.0, 0.0, 1.95], [0.3, -0.2, 0.0]),
        ([4.0, 3.0, 1.95], [0.3, 0.2, 0.0]), ([0.0, 3.0, 1.95], [-0.3, 0.2, 0.0])]
CROSSED = [([0.0, 0.0, 0.0], [0.3, 0.0, 0.0]), ([4.0, 3.0, 0.0], [-0.3, 0.0, 0.0]),
           ([4.0, 0.0, 3.9], [-0.3, 0.0, 0.0]), ([0.0, 3.0, 3.9], [0.3, 0.0, 0.0])]


def plane_robot_toml() -> str:
    cables = "\n".join(f"[[robot.cables]]\nframe_anchor_m = {c}\nplatform_anchor_m = {p}" for c, p in RING + CROSSED)
    return f'''name = "plane8"
[robot]
dofs = "spatial"
mass_kg = 5.0
inertia_kg_m2 = [0.0667, 0.15, 0.2167]
tension_min_N = 10.0
tension_max_N = 450.0
{cables}

[ship]
frame_origin_m = [0.0, -1.0, 2.0]

[base_motion]
type = "sinusoidal"
[[base_motion.components]]
dof = "roll"
amplitude_deg = 5.0
period_s = 8.0

[trajectory]
type = "waypoints"
[[trajectory.waypoints]]
time_s = 0.0
position_m = [1.5, 1.2, 1.2]
[[trajectory.waypoints]]
time_s = 4.0
position_m = [2.5, 1.8, 2.7]

[time]
duration_s = 0.2
step_s = 0.05
'''


@pytest.fixture(scope="module")
def plane_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("plane") / "plane8.toml"
    path.write_text(plane_robot_toml())
    return path


def test_the_hand_worked_plane_is_singular_and_its_neighbours_are_not(plane_file):
    r = marinecdpr.load_scenario(str(plane_file)).robot
    rng = np.random.default_rng(3)
    x = np.c_[rng.uniform(0.5, 3.5, 40), rng.uniform(0.4, 2.6, 40), np.full(40, 1.95)]
    R = np.broadcast_to(np.eye(3), (40, 3, 3)).copy()
    J = cable_kinematics(x, R, r.frame_anchors, r.platform_anchors).J_tilde
    np.testing.assert_array_equal(J[:, :, 3], 0.0)          # the moment about x: none, by hand
    assert not full_rank(J).any()
    assert np.all(np.linalg.matrix_rank(J) == 5)
    for dz in (-0.1, 0.1):                                   # a step off the plane: full rank
        J = cable_kinematics(x + [0, 0, dz], R, r.frame_anchors, r.platform_anchors).J_tilde
        assert full_rank(J).all()


def test_the_survey_finds_the_plane_between_its_grid_points(plane_file):
    sc = marinecdpr.load_scenario(str(plane_file))
    survey = singular_poses(sc)
    assert survey.n_singular == 0                            # no grid point lies on it
    line = survey.message()
    assert line is not None and "on the plane z = 1.95 m (found between the grid's points" in line
    # the poses the search ends at lie on the plane to the golden section's precision
    axes = [np.linspace(0.0, 4.0, 14)[1:-1], np.linspace(0.0, 3.0, 14)[1:-1], np.linspace(0.0, 3.9, 14)[1:-1]]
    found, text, n_lines = singular_set(sc.robot, axes, np.eye(3), [0, 1, 2])
    assert text == "the plane z = 1.95 m" and n_lines == 3 * 144
    assert found.shape[0] >= 100                             # most of the 144 lines along z cross it
    np.testing.assert_allclose(found[:, 2], 1.95, atol=1e-9)
    assert np.ptp(found[:, 0]) > 2.0 and np.ptp(found[:, 1]) > 1.5  # spread over the plane


@pytest.mark.parametrize("name", ["paper", "paper_clean", "paper_sea"])
def test_no_singular_set_is_found_where_there_is_none(name):
    assert singular_poses(marinecdpr.load_scenario(name)).message() is None


def test_the_workspace_map_names_its_singular_row_and_the_set_between_its_points(plane_file):
    sc = marinecdpr.load_scenario(str(plane_file))
    ws = workspace_map(sc, n=(5, 9))                         # z = 1.95 m is the middle of 9 rows
    assert ws.v[4] == pytest.approx(1.95, abs=1e-12)
    np.testing.assert_array_equal(ws.singular[:, 4], True)
    assert not ws.singular[:, [0, 1, 2, 3, 5, 6, 7, 8]].any()
    assert np.all(ws.min_margin_N[:, 4] == -np.inf)
    line = map_singular_poses(sc, ws).message()
    assert "at 5 of the 45 poses of the map" in line and "(every pose of the row z = 1.95 m)" in line
    ws = workspace_map(sc, n=(5, 8))                         # no row on the plane
    assert not ws.singular.any()
    line = map_singular_poses(sc, ws).message()
    assert "on the line z = 1.95 m (found between the map's points, on 5 of the" in line


def test_workspace_and_check_warn_of_the_plane(plane_file, tmp_path):
    res = runner.invoke(app, ["check", str(plane_file)])
    assert res.exit_code == 0, res.output
    assert "on the plane z = 1.95 m" in res.stderr
    res = runner.invoke(app, ["workspace", str(plane_file), "--points", "4x9", "--duration", "0.1",
                              "--out", str(tmp_path / "ws")])
    assert res.exit_code == 0, res.output
    warnings = [w for w in res.stderr.split("warning:")[1:]]
    assert any("every pose of the row z = 1.95 m" in " ".join(w.split()) for w in warnings), res.stderr
