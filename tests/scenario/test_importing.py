"""Robots from CASPR and WireX (issue 23, item 3): `marinecdpr import`, checked against the
source toolkits' own published numbers and conventions, and run through every command.

The model files under tests/data are the toolkits' own, unchanged (tests/data/*/SOURCE.md:
CASPR darwinlau/CASPR @ a6971eeb, BSD-3-Clause, (c) 2017 Darwin Lau; WireX
gldkhoward/WireX @ 8a0db466, MIT, (c) 2006-2019 Andreas Pott). The WireX reference numbers
are those of wirex-master/Scripts/wcUnitTest.py at that commit, quoted in
tests/data/wirex/SOURCE.md with their line numbers.
"""

from __future__ import annotations

import math
import tomllib
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

import marinecdpr
from marinecdpr.cli.app import app
from marinecdpr.errors import ScenarioError
from marinecdpr.geometry.kinematics import cable_kinematics
from marinecdpr.geometry.rotations import matrix_from_euler
from marinecdpr.model.tension import distribute_tensions
from marinecdpr.scenario.importing import import_robot, scenario_toml
from marinecdpr.scenario.loading import scenario_from_dict
from tests.conftest import one_line_exit_2

runner = CliRunner()
DATA = Path(__file__).resolve().parents[1] / "data"
CASPR = {"IPAnema 1": DATA / "caspr" / "IPAnema_1" / "IPAnema_1_bodies.xml",
         "CoGiRo": DATA / "caspr" / "CoGiRo" / "CoGiRo_bodies.xml",
         "SEGESTA": DATA / "caspr" / "SEGESTA" / "SEGESTA_bodies.xml"}
WIREX = {name: DATA / "wirex" / f"{name}.wcrfx" for name in ("IPAnema", "CoGiRo", "Segesta", "2DIPAnema2")}

# wcUnitTest.py, test_Ikin_inversekinematics (lines 117-124) and _compliance644 (266-274)
LENGTHS_001 = [2.6148040079516472] * 8
LENGTHS_0102 = [2.5882812830138846, 2.433762519228201, 2.659924810967408, 2.8019992862240346,
                2.5882812830138846, 2.433762519228201, 2.659924810967408, 2.8019992862240346]
# wcUnitTest.py, test_Ikin_structureMatrix_compliance644 (lines 248-264): row i = [u_i, (R b_i) x u_i]
STRUCTURE_0102 = [
    [-0.7881678136715315, 0.4790823965454407, 0.3863567714076135, 0.023181406284456807, 0.023181406284456807, 0.018545125027565453],
    [0.7560310364971451, 0.5094991767698152, 0.4108864328788832, 0.024653185972732992, -0.024653185972732992, -0.014791911583639798],
    [0.6917488766649749, -0.6165587813753037, 0.37595047644835594, -0.022557028586901357, -0.022557028586901357, 0.004511405717380269],
    [-0.728051577325381, -0.5852963660851102, 0.35688802810067694, -0.021413281686040616, 0.021413281686040616, -0.00856531267441625],
    [-0.7881678136715315, 0.4790823965454407, -0.3863567714076135, -0.023181406284456807, -0.023181406284456807, 0.018545125027565453],
    [0.7560310364971451, 0.5094991767698152, -0.4108864328788832, -0.024653185972732992, 0.024653185972732992, -0.014791911583639798],
    [0.6917488766649749, -0.6165587813753037, -0.37595047644835594, 0.022557028586901357, 0.022557028586901357, 0.004511405717380269],
    [-0.728051577325381, -0.5852963660851102, -0.35688802810067694, 0.021413281686040616, -0.021413281686040616, -0.00856531267441625]]


@pytest.fixture(scope="module")
def ipanema1():
    return scenario_from_dict(import_robot(WIREX["IPAnema"]).data, source="test").robot


def _kinematics(robot, x):
    return cable_kinematics(np.array([x], dtype=float), np.eye(3)[None], robot.frame_anchors,
                            robot.platform_anchors)


def test_wirex_ipanema1_lengths_and_structure_matrix_are_wirex_s(ipanema1):
    kin = _kinematics(ipanema1, [0.0, 0.0, 1.0])
    np.testing.assert_allclose(kin.lengths[0], LENGTHS_001, rtol=0, atol=1e-15)
    kin = _kinematics(ipanema1, [0.1, 0.2, 1.0])
    np.testing.assert_allclose(kin.lengths[0], LENGTHS_0102, rtol=0, atol=1e-15)
    # WireX's row i is ours: J~_i = (u_i, (R p_i) x u_i), u_i from the platform to the frame
    np.testing.assert_allclose(kin.J_tilde[0], STRUCTURE_0102, rtol=0, atol=1e-15)


def test_wirex_ipanema1_closed_form_tensions_are_wirex_s(ipanema1):
    """test_Irobot_getForceDistribution_referencevalue (wcUnitTest.py lines 200-203): at r = (0, 0, 1),
    w = 0 and WireX's default limits 1 N and 10 N, the closed form (Pott et al. 2009) gives 5.5 N
    for every cable. And at r = (0.1, 0.2, 1) with WireX's wrench (1, 1, 1, 0, 0, 0)
    (test_Ikin_getForceDistribution_consistance, lines 190-198, which checks only the balance):
    WireX's equilibrium is A^T f + w = 0, ours J~^T T = w, so our wrench is -w; its closed form
    f = f_ref - A (A^T A)^-1 (w + A^T f_ref), written out here, equals ours."""
    lo, hi = np.full(8, 1.0), np.full(8, 10.0)
    J = _kinematics(ipanema1, [0.0, 0.0, 1.0]).J_tilde
    sol = distribute_tensions(J, np.zeros((1, 6)), lo, hi, method="closed_form")
    np.testing.assert_allclose(sol.tensions[0], [5.5] * 8, rtol=0, atol=1e-14)
    A = _kinematics(ipanema1, [0.1, 0.2, 1.0]).J_tilde[0]
    w_wirex = np.array([1.0, 1.0, 1.0, 0.0, 0.0, 0.0])
    f_ref = 0.5 * (lo + hi)
    f = f_ref - A @ np.linalg.solve(A.T @ A, w_wirex + A.T @ f_ref)
    sol = distribute_tensions(A[None], -w_wirex[None], lo, hi, method="closed_form")
    assert sol.feasible[0]
    np.testing.assert_allclose(sol.tensions[0], f, rtol=0, atol=1e-13)
    np.testing.assert_allclose(A.T @ sol.tensions[0] + w_wirex, 0.0, atol=1e-13)  # WireX's own check (1e-10)


def test_caspr_and_wirex_ipanema1_import_to_the_same_robot(ipanema1):
    """CASPR's IPAnema 1 has WireX's anchors (both from Pott et al., IPAnema, 2013): the two
    importers, reading two formats, give the same cables; CASPR's limits are its 0 and 720 N."""
    caspr = scenario_from_dict(import_robot(CASPR["IPAnema 1"], hold=True).data, source="test").robot
    np.testing.assert_array_equal(caspr.frame_anchors, ipanema1.frame_anchors)
    np.testing.assert_array_equal(caspr.platform_anchors, ipanema1.platform_anchors)
    assert caspr.mass_kg == 25.0 and caspr.tension_min.tolist() == [0.0] * 8 and caspr.tension_max.tolist() == [720.0] * 8
    np.testing.assert_array_equal(caspr.inertia, np.eye(3) * 14.0)


def _caspr_rotation_by_hand(a, b, c):
    """CASPR's SPATIAL_EULER_XYZ (src/Model/Bodies/Joints/SpatialEulerXYZ.m): Rx(a) Ry(b) Rz(c)."""
    Rx = np.array([[1, 0, 0], [0, math.cos(a), -math.sin(a)], [0, math.sin(a), math.cos(a)]])
    Ry = np.array([[math.cos(b), 0, math.sin(b)], [0, 1, 0], [-math.sin(b), 0, math.cos(b)]])
    Rz = np.array([[math.cos(c), -math.sin(c), 0], [math.sin(c), math.cos(c), 0], [0, 0, 1]])
    return Rx @ Ry @ Rz


def test_caspr_cogiro_poses_put_the_attachments_where_caspr_does():
    """CoGiRo: its centre of mass off the joint (-0.034, -0.013, 0.264) m, attachments given from
    the joint, products of inertia. At every imported waypoint, our pose (centre of mass, SNAME
    angles) puts each platform attachment where CASPR's q does: r + Rx(a) Ry(b) Rz(c) loc,
    read here straight from the XML."""
    imported = import_robot(CASPR["CoGiRo"])
    sc = scenario_from_dict(imported.data, source="test")
    cables = ET.parse(CASPR["CoGiRo"].with_name("CoGiRo_cables.xml")).getroot()
    locs = [np.array(c.findall("./attachments/attachment")[1].findtext("location").split(), dtype=float)
            for c in cables.find("cable_set")]
    traj = ET.parse(CASPR["CoGiRo"].with_name("CoGiRo_trajectories.xml")).getroot().find("joint_trajectories")[0]
    qs = [np.array(p.findtext("q").split(), dtype=float) for p in traj.findall("./points/point")]
    assert len(sc.trajectory.waypoints) == len(qs) >= 2
    for wp, q in zip(sc.trajectory.waypoints, qs):
        R_caspr = _caspr_rotation_by_hand(*q[3:])
        R_ours = matrix_from_euler(np.radians(np.array(wp.orientation_deg)))
        np.testing.assert_allclose(R_ours, R_caspr, rtol=0, atol=1e-11)  # angles kept to 12 digits
        ours = np.asarray(wp.position_m) + sc.robot.platform_anchors @ R_ours.T
        caspr = q[:3] + np.array(locs) @ R_caspr.T
        np.testing.assert_allclose(ours, caspr, rtol=0, atol=1e-10)
    # the inertia is about the centre of mass, as the file gives it (ref="com")
    np.testing.assert_allclose(sc.robot.inertia, [[36.598, -0.453, 3.012], [-0.453, 35.982, -1.539],
                                                  [3.012, -1.539, 25.439]], rtol=0, atol=0)


def test_caspr_inertia_about_the_joint_is_shifted_to_the_centre_of_mass(tmp_path):
    bodies = CASPR["IPAnema 1"].read_text()
    bodies = bodies.replace("<com_location>0.0 0.0 0.0</com_location>", "<com_location>0.1 0.0 0.0</com_location>")
    bodies = bodies.replace('<inertia ref="com">', '<inertia ref="joint">')
    (tmp_path / "X_bodies.xml").write_text(bodies)
    (tmp_path / "X_cables.xml").write_text(CASPR["IPAnema 1"].with_name("IPAnema_1_cables.xml").read_text())
    robot = scenario_from_dict(import_robot(tmp_path / "X_bodies.xml").data, source="test").robot
    # by hand: m d^2 = 25 * 0.01 = 0.25 off the moments about y and z, none about x
    np.testing.assert_allclose(robot.inertia, np.diag([14.0, 13.75, 13.75]), rtol=0, atol=1e-14)
    # attachments were given from the joint: from the centre of mass they sit 0.1 m further back in x
    np.testing.assert_allclose(robot.platform_anchors[0], [-0.16, 0.06, 0.0], rtol=0, atol=1e-15)


# ------------------------------------------------------------------ what the validation now lets through
def test_cables_may_share_a_platform_point_not_a_frame_anchor(ipanema1):
    assert np.array_equal(ipanema1.platform_anchors[0], ipanema1.platform_anchors[4])  # IPAnema 1's pairs
    data = import_robot(WIREX["IPAnema"]).data
    data["robot"]["cables"][4]["frame_anchor_m"] = data["robot"]["cables"][0]["frame_anchor_m"]
    with pytest.raises(ScenarioError, match=r"robot\.cables\[5\]\.frame_anchor_m: same frame anchor as cable 1"):
        scenario_from_dict(data, source="test")


def test_a_suspended_robot_may_hang_below_its_anchors_but_a_degenerate_one_is_refused():
    """CoGiRo's anchors span 0.11 m in height over a 14.6 m frame: the frame's box is not a
    bound on the platform's height (it hangs 3.4 m below); a robot whose platform points all
    coincide is still refused."""
    sc = scenario_from_dict(import_robot(CASPR["CoGiRo"]).data, source="test")
    assert np.ptp(sc.robot.frame_anchors[:, 2]) < 0.12 and sc.trajectory.waypoints[0].position_m[2] < 5.0
    from marinecdpr.planning.planner import check_trajectory

    assert check_trajectory(sc).n_singular == 0
    data = import_robot(CASPR["CoGiRo"]).data
    for c in data["robot"]["cables"]:
        c["platform_anchor_m"] = [0.0, 0.0, 0.0]
    with pytest.raises(ScenarioError, match="platform anchors coincide"):
        scenario_from_dict(data, source="test")


# ------------------------------------------------------------------ through every command
FLYABLE = [("caspr-ipanema1", CASPR["IPAnema 1"], ["--hold"]), ("caspr-cogiro", CASPR["CoGiRo"], []),
           ("caspr-segesta", CASPR["SEGESTA"], []), ("wirex-ipanema", WIREX["IPAnema"], []),
           ("wirex-cogiro", WIREX["CoGiRo"], [])]


@pytest.mark.parametrize("name, source, extra", FLYABLE, ids=[f[0] for f in FLYABLE])
def test_imported_robots_run_through_check_plan_simulate_and_workspace(tmp_path, name, source, extra):
    out = tmp_path / f"{name}.toml"
    res = runner.invoke(app, ["import", str(source), "--out", str(out), *extra])
    assert res.exit_code == 0, res.output
    assert out.read_text().startswith("# Imported from ") and "note: " in res.stdout
    tomllib.loads(out.read_text())
    res = runner.invoke(app, ["check", str(out)])
    assert res.exit_code == 0 and ": ok: " in res.stdout, res.output
    res = runner.invoke(app, ["plan", str(out), "--out", str(tmp_path / "p")])
    assert res.exit_code == 0, res.output  # every step feasible
    sc = marinecdpr.load_scenario(out)
    data = np.loadtxt(tmp_path / "p" / "plan.csv", delimiter=",", skiprows=1)
    n = sc.robot.n_cables
    T = data[:, 7 + 2 * n: 7 + 3 * n]
    assert (T >= sc.robot.tension_min - 1e-6).all() and (T <= sc.robot.tension_max + 1e-6).all()
    res = runner.invoke(app, ["simulate", str(out), "--out", str(tmp_path / "s"), "--duration", "0.05",
                              "--plant", "own"])
    assert res.exit_code == 0, res.output
    res = runner.invoke(app, ["workspace", str(out), "--out", str(tmp_path / "w"), "--points", "4x3",
                              "--duration", "0.02", "--axes", "xy",
                              "--fixed", f"{sc.trajectory.model_dump().get('start_position_m', [0, 0, 1.0])[2]:g}"
                              if sc.trajectory.type == "line" else f"{sc.trajectory.waypoints[0].position_m[2]:g}"])
    assert res.exit_code == 0, res.output


def test_an_infeasible_import_is_a_verdict_not_a_crash(tmp_path):
    """WireX's Segesta carries WireX's default 25 kg platform (the file gives no mass) on its
    0.8 m frame: it imports and checks, and the plan says which cables are at their limits."""
    out = tmp_path / "s.toml"
    res = runner.invoke(app, ["import", str(WIREX["Segesta"]), "--out", str(out)])
    assert res.exit_code == 0
    robot = marinecdpr.load_scenario(out).robot  # its <application>'s limits, 40 N and 1000 N
    assert robot.tension_min.tolist() == [40.0] * 8 and robot.tension_max.tolist() == [1000.0] * 8
    res = runner.invoke(app, ["plan", str(out), "--out", str(tmp_path / "p")])
    assert res.exit_code == 3 and "cannot hold the platform" in res.stderr


def test_a_planar_wirex_robot_marked_spatial_is_read_in_its_plane(tmp_path):
    imported = import_robot(WIREX["2DIPAnema2"])
    assert imported.data["robot"]["dofs"] == "planar" and any("read as a planar robot" in n for n in imported.notes)
    sc = scenario_from_dict(imported.data, source="test")
    # WireX's (x, y, 0) -> our (x, 0, y): chain 2's base (4.946, 3.478, 0)
    np.testing.assert_array_equal(sc.robot.frame_anchors[1], [4.946, 0.0, 3.478])
    assert "y up" in scenario_toml(imported)


def test_wirex_pulleys_are_carried_over_when_asked():
    sc = scenario_from_dict(import_robot(WIREX["IPAnema"], pulleys=True).data, source="test")
    assert sc.robot.pulley_radii.tolist() == [0.1] * 8 and sc.robot.pulley_axes.tolist() == [[0.0, 0.0, 1.0]] * 8


@pytest.mark.parametrize("make, words", [
    (lambda d: (d / "x_bodies.xml").write_text("<bodies_system><links></links>"), ("not valid XML",)),
    (lambda d: (d / "x_bodies.xml").write_text("<robots/>"), ("root element is <robots>",)),
    (lambda d: (d / "x_bodies.xml").write_text(
        CASPR["IPAnema 1"].read_text().replace("SPATIAL_EULER_XYZ", "R_X")), ("joint type 'R_X'",)),
    (lambda d: (d / "x_bodies.xml").write_text(CASPR["IPAnema 1"].read_text()), ("x_cables.xml", "no such file")),
    (lambda d: (d / "x_bodies.xml").write_text(
        CASPR["IPAnema 1"].read_text().replace("<mass>25.0</mass>", "<mass>heavy</mass>")),
     ("links.link_rigid.physical.mass", "expected numbers")),
])
def test_bad_models_are_one_line(tmp_path, make, words):
    make(tmp_path)
    res = runner.invoke(app, ["import", str(tmp_path / "x_bodies.xml"), "--out", str(tmp_path / "o.toml")])
    one_line_exit_2(res, *words)
    assert not (tmp_path / "o.toml").exists()


def test_bad_import_options_are_one_line(tmp_path):
    one_line_exit_2(runner.invoke(app, ["import", str(WIREX["IPAnema"]), "--out", str(tmp_path / "o.txt")]),
                    "ending in .toml")
    one_line_exit_2(runner.invoke(app, ["import", str(WIREX["IPAnema"]), "--out", str(tmp_path / "o.toml"),
                                        "--cable-set", "x"]), "--cable-set is for CASPR")
    one_line_exit_2(runner.invoke(app, ["import", str(CASPR["IPAnema 1"]), "--out", str(tmp_path / "o.toml"),
                                        "--cable-set", "nope"]), "no cable set 'nope'")
    one_line_exit_2(runner.invoke(app, ["import", str(tmp_path / "none.wcrfx"), "--out", str(tmp_path / "o.toml")]),
                    "no such file")


# -------------------- formerly tests/test_import_verdicts.py

"""An import that cannot work says so, and its TOML writes each vector on one line
(issue 37, item 12).

CASPR's IPAnema 1 with its default trajectory, and WireX's Segesta and 2DIPAnema2 held at the
frame's centre, cannot hold their platforms at any step; `import` had reported success
without a word. The model files are the toolkits' own (tests/data/*/SOURCE.md).
"""


import re
import tomllib
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import linprog
from typer.testing import CliRunner

import marinecdpr
from marinecdpr.cli.app import app
from marinecdpr.geometry.kinematics import cable_kinematics
from marinecdpr.geometry.rotations import matrix_from_euler
from marinecdpr.planning.planner import sampled_infeasibility
from marinecdpr.scenario.importing import import_robot, scenario_toml
from marinecdpr.scenario.importing.common import toml_plain as _plain

runner = CliRunner()
DATA = Path(__file__).resolve().parents[1] / "data"
MODELS = {"caspr-ipanema1": DATA / "caspr" / "IPAnema_1" / "IPAnema_1_bodies.xml",
          "caspr-cogiro": DATA / "caspr" / "CoGiRo" / "CoGiRo_bodies.xml",
          "wirex-segesta": DATA / "wirex" / "Segesta.wcrfx",
          "wirex-2dipanema2": DATA / "wirex" / "2DIPAnema2.wcrfx",
          "wirex-ipanema": DATA / "wirex" / "IPAnema.wcrfx"}
CANNOT = {"caspr-ipanema1", "wirex-segesta", "wirex-2dipanema2"}


def _warnings(res) -> list[str]:
    return [" ".join(w.split()) for w in res.stderr.split("warning:")[1:]]


@pytest.mark.parametrize("name", sorted(MODELS))
def test_the_toml_writes_each_vector_on_one_line_and_reads_back_the_same(name):
    imported = import_robot(MODELS[name])
    text = scenario_toml(imported)
    assert tomllib.loads(text.split("\n\n", 1)[1]) == _plain(imported.data)  # the same values
    lines = text.splitlines()
    vectors = [ln for ln in lines if re.match(r"(frame_anchor_m|platform_anchor_m|position_m|start_position_m|"
                                               r"end_position_m|orientation_deg|start_orientation_deg) = ", ln)]
    assert vectors and all(re.fullmatch(r"\w+ = \[-?[\d.e+-]+, -?[\d.e+-]+, -?[\d.e+-]+\]", v) for v in vectors)
    assert not any(re.fullmatch(r"\s*-?[\d.e+-]+,", ln) for ln in lines)  # no number alone on its line
    inertia = [ln for ln in lines if ln.startswith("inertia_kg_m2 = ")]
    assert len(inertia) == 1 and inertia[0].endswith("]")


@pytest.mark.parametrize("name", sorted(MODELS))
def test_import_says_when_the_robot_cannot_hold_its_platform(name, tmp_path):
    out = tmp_path / f"{name}.toml"
    res = runner.invoke(app, ["import", str(MODELS[name]), "--out", str(out)])
    assert res.exit_code == 0, res.output
    assert out.exists()  # written all the same: a warning
    verdicts = [w for w in _warnings(res) if "as imported, the cables cannot hold the platform" in w]
    if name not in CANNOT:
        assert verdicts == [], res.stderr
        return
    (line,) = verdicts
    sc = marinecdpr.load_scenario(str(out))
    n = sc.time.n_steps
    assert f"at 200 of 200 steps planned (spread over its {n})" in line
    weight = sc.robot.mass_kg * sc.environment.gravity_m_s2
    assert f"at rest on a still frame: the wrench is the platform's weight alone, {weight:.4g} N" in line
    # the verdict checked on its own: at the first pose no tensions within the limits hold the
    # platform's weight (a linear programme on J~ there)
    first = re.search(r"first at t = 0 s \(([^;)]*)", line).group(1)
    r = sc.robot
    pose = marinecdpr.plan(sc.with_changes(time={"step_s": sc.time.step_s, "duration_s": sc.time.step_s})).pose[0]
    J = cable_kinematics(pose[None, :3], matrix_from_euler(pose[None, 3:]), r.frame_anchors,
                         r.platform_anchors).J_tilde[0][:, list(r.controlled)]
    w = np.zeros(6)
    w[2] = weight
    res_lp = linprog(np.zeros(r.n_cables), A_eq=J.T, b_eq=w[list(r.controlled)],
                     bounds=list(zip(r.tension_min, r.tension_max)), method="highs")
    assert res_lp.status == 2, first  # infeasible
    if name == "caspr-ipanema1":
        # the reason, by its own linear programmes: with the moments held at the weight's (none),
        # the most upward force the cables give there is 0 N against 245.2 N needed
        A, need = J.T, w[list(r.controlled)]
        ends = [sign * linprog(sign * A[2], A_eq=np.delete(A, 2, axis=0), b_eq=np.delete(need, 2),
                               bounds=list(zip(r.tension_min, r.tension_max)), method="highs").fun
                for sign in (1.0, -1.0)]
        np.testing.assert_allclose(ends, [-895.8, 0.0], atol=0.05)
        assert "the cables give -895.8 to 0 N along z there, against 245.2 N needed" in line
        assert "no change of the tension limits closes it" in line


def test_the_sampled_verdict_agrees_with_the_whole_plan():
    # CoGiRo (CASPR): feasible throughout, by both; Segesta: infeasible at every step, by both
    for name, feasible in (("caspr-cogiro", True), ("wirex-segesta", False)):
        sc = marinecdpr.scenario.loading.scenario_from_dict(import_robot(MODELS[name]).data, source=name)
        whole = marinecdpr.plan(sc)
        assert whole.feasible.all() == feasible and (~whole.feasible).all() == (not feasible)
        assert (sampled_infeasibility(sc) is None) == feasible
