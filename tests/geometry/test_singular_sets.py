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

from __future__ import annotations

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
