"""Writing a first scenario: a robot drawn in millimetres is flagged, an infeasible plan names the
cables at their limits (checked against statics worked out here), and long commands show their
progress when piped."""

from __future__ import annotations

import re
import tomllib
from dataclasses import replace
from importlib import resources

import numpy as np
from scipy.optimize import linprog
from typer.testing import CliRunner

import marinecdpr
import marinecdpr.cli.app as cli
from marinecdpr.cli.app import app
from marinecdpr.scenario.loading import scenario_from_dict

from conftest import make_scenario, paper_dict

runner = CliRunner()


def millimetre_toml() -> str:
    """The paper scenario with every length written in millimetres (a 1.9 km frame), 21 steps."""
    text = (resources.files("marinecdpr.scenario") / "builtin" / "paper.toml").read_text()

    def mm(match: re.Match) -> str:
        return match[1] + "[" + ", ".join(f"{1000 * float(v):.1f}" for v in match[2].split(",")) + "]"

    text = re.sub(r"((?:frame_anchor_m|platform_anchor_m|center_m|frame_origin_m)\s*=\s*)\[([^\]]*)\]",
                  mm, text)
    for old, new in (("radius_m = 0.38", "radius_m = 380.0"), ("step_s = 0.001", "step_s = 0.05"),
                     ("duration_s = 15.0", "duration_s = 1.0")):
        assert old in text
        text = text.replace(old, new)
    return text


def millimetre_dict() -> dict:
    return tomllib.loads(millimetre_toml())


def test_scale_warnings_flag_millimetres_not_metres():
    from marinecdpr.scenario.scale import scale_warnings

    mm = scenario_from_dict(millimetre_dict())
    assert scale_warnings(mm) == [
        "robot size far outside cable-robot scale: the frame anchors span 1900 m (more than 200 m); "
        "the platform anchors span 300 m (more than 50 m); "
        "coordinates look like millimetres: scenario lengths are in metres (divide by 1000)"]
    assert scale_warnings(marinecdpr.load_scenario("paper")) == []
    # a metre frame with its platform anchors in millimetres: the platform is the culprit
    d = paper_dict()
    for cable in d["robot"]["cables"]:
        cable["platform_anchor_m"] = [1000.0 * v for v in cable["platform_anchor_m"]]
    (line,) = scale_warnings(scenario_from_dict(d))
    assert "the platform (300 m) is larger than the frame (1.9 m)" in line
    assert line.endswith("the platform anchors look like millimetres: platform_anchor_m is in metres")


def test_check_warns_on_stderr_and_still_exits_0(tmp_path):
    scen = tmp_path / "mm.toml"
    scen.write_text(millimetre_toml())
    res = runner.invoke(app, ["check", str(scen)])
    assert res.exit_code == 0, res.output
    assert "ok: 'paper', planar robot, 4 cables" in " ".join(res.stdout.split())  # stdout wraps at 80
    assert res.stderr.strip().splitlines() == [
        f"warning: {scen}: robot size far outside cable-robot scale: the frame anchors span 1900 m (more "
        "than 200 m); the platform anchors span 300 m (more than 50 m); coordinates look like millimetres: "
        "scenario lengths are in metres (divide by 1000)"]
    # other commands warn when they load it too; a metre scenario gives no warning
    ws = runner.invoke(app, ["workspace", str(scen), "--points", "2x2", "--out", str(tmp_path / "o")])
    assert ws.exit_code == 0 and "coordinates look like millimetres" in ws.stderr
    ok = runner.invoke(app, ["check", "paper"])
    assert ok.exit_code == 0 and "warning" not in ok.stderr


def heavy_still_paper():
    """The paper robot carrying 200 kg on a still ship: statics alone decides feasibility."""
    return make_scenario(lambda d: (d["robot"].update(mass_kg=200.0),
                                    d.update(base_motion={"type": "still"},
                                             time={"step_s": 0.05, "duration_s": 1.0})))


def test_infeasible_plan_names_the_cables_at_their_limits():
    sc = heavy_still_paper()
    p = marinecdpr.plan(sc)
    msg = p.infeasibility()
    # planar: the controlled DOFs only, the angle named as in plan.csv
    assert "21 of 21 steps, first at t = 0 s (x = 0.98 m, z = 0.7 m, theta_y = 0 deg)" in msg
    assert not re.search(r"\b(y|rx|ry|rz) =", msg)

    # Statics at t = 0, worked out here: the platform sits at (0.98, 0.7) level, its anchors at
    # x + p_i; the cables pull along u_i = (c_i - x - p_i) / |...|. On a still ship the circle's
    # acceleration at t = 0 is -r w^2 along x, so the cables must supply
    # w = (m a_x, m g) in (x, z) and no moment about y.
    r = sc.robot
    x = np.array([0.98, 0.0, 0.7])
    lever = r.platform_anchors
    l = r.frame_anchors - (x + lever)
    u = l / np.linalg.norm(l, axis=1, keepdims=True)
    m_y = np.cross(lever, u)[:, 1]
    omega = 2 * np.pi / 15.0
    w = np.array([-200.0 * 0.38 * omega**2, 200.0 * 9.8, 0.0])
    # the most upward pull within limits (a linear programme): the top cables 1, 2 at T_max and
    # the bottom cables 3, 4 at T_min, and still short of the weight
    up = linprog(-u[:, 2], bounds=list(zip(r.tension_min, r.tension_max)), method="highs")
    np.testing.assert_allclose(up.x, [450.0, 450.0, 10.0, 10.0])
    assert -up.fun < 200.0 * 9.8 - 1400.0
    # these tensions are also the least-squares optimum (KKT: moving any cable off its limit
    # only makes the missing wrench larger), so the message reports this shortfall
    A = np.vstack([u[:, 0], u[:, 2], m_y])
    missing = w - A @ up.x
    grad = A.T @ (A @ up.x - w)
    assert (grad[:2] < 0).all() and (grad[2:] > 0).all()
    force, moment = np.linalg.norm(missing[:2]), abs(missing[2])
    assert (
        f": at best, cables 3, 4 at T_min = 10 N and cables 1, 2 at T_max = 450 N still leave "
        f"{force:.4g} N of force (along +z) and {moment:.4g} N m of moment "
        f"(about {'+' if missing[2] > 0 else '-'}y) short; ") in msg
    assert f"{force:.4g}" == "1472"
    # and what the cables can give along z with the x force and the moment held, worked out
    # here by its own linear programmes, against the weight: the force is short, so the hint
    # is the force's
    span = [sign * linprog(sign * u[:, 2], A_eq=np.vstack([u[:, 0], m_y]), b_eq=[w[0], 0.0],
                           bounds=list(zip(r.tension_min, r.tension_max)), method="highs").fun
            for sign in (1.0, -1.0)]
    assert msg.endswith(
        f"short; with the rest of the wrench held the cables give {span[0]:.4g} to {span[1]:.4g} N along z there, "
        f"against {w[1]:.4g} N needed: raise robot.tension_max_N, or move the frame anchors so that more cables "
        "pull that way (robot.cables frame_anchor_m)")

    # a plan that does not know its robot still gives the controlled DOFs, without the cause
    bare = replace(p, robot=None).infeasibility()
    assert bare.endswith("(x = 0.98 m, z = 0.7 m, theta_y = 0 deg)")


def test_infeasible_messages_for_a_method_that_misses_and_a_spatial_robot():
    sc = make_scenario(lambda d: d.update(time={"step_s": 0.05, "duration_s": 1.0}))
    msg = marinecdpr.plan(sc, method="pseudo_inverse").infeasibility()
    assert msg.endswith("(x = 0.98 m, z = 0.7 m, theta_y = 0 deg): tensions within the limits exist "
                        "there, but the pseudo inverse method did not find them: the minimum variance method does "
                        "(planning.method = \"minimum_variance\", or --method minimum_variance)")
    assert marinecdpr.plan(sc, method="minimum_variance").feasible.all()  # as it says
    cube = marinecdpr.load_scenario("examples/spatial_cube8.toml")
    heavy = cube.with_changes(robot=cube.robot.model_dump(exclude_none=True) | {"mass_kg": 150.0},
                              time={"step_s": 0.05, "duration_s": 0.1})
    msg = marinecdpr.plan(heavy).infeasibility()
    # spatial: all six DOFs; the four lower cables pull down (at T_min), the four upper ones
    # up (at T_max): 4 * 450 N * u_z (1 / sqrt 3 at the centre, minus the platform's offsets)
    # is far below the 1470 N weight
    assert "(x = 1 m, y = 1 m, z = 1 m, rx = 0 deg, ry = 0 deg, rz = 0 deg): at best, cables 1, 2, 3, 4 " \
           "at T_min = 10 N and cables 5, 6, 7, 8 at T_max = 450 N still leave" in msg
    assert re.search(r"still leave \d+(\.\d+)? N of force \(along \+z\) short; with the rest of the wrench held "
                     r"the cables give -?\d+(\.\d+)? to \d+(\.\d+)? N along z there, against \d+ N needed: raise "
                     r"robot.tension_max_N", msg)


def test_piped_workspace_prints_progress_lines(tmp_path, monkeypatch):
    args = ["workspace", "paper", "--duration", "1", "--step", "0.05", "--points", "8x6",
            "--out", str(tmp_path)]
    res = runner.invoke(app, args)
    assert res.exit_code == 0, res.output
    # a short job: a line at once that it has started, and a closing line, with its speed
    first, last = [line for line in res.stderr.splitlines() if line.startswith("workspace:")]
    assert first == "workspace: 0 of 48 poses, started"
    assert re.fullmatch(r"workspace: 48 of 48 poses in \d+\.\d s \([\d,.]+ poses/s( after the first \d+, which "
                        r"took \d+\.\d s with the start-up)?\)", last)
    # without the minimum interval: a line at every tenth of the grid, then the closing line
    monkeypatch.setattr(cli, "PROGRESS_LINE_MIN_S", 0.0)
    res = runner.invoke(app, args)
    lines = res.stderr.strip().splitlines()
    assert lines.pop(0).startswith("size: paper: 48 poses (8 x 6) x 21 steps")  # before the work
    assert lines.pop(0) == "workspace: 0 of 48 poses, started"
    done = [int(re.match(r"workspace: (\d+) of 48 poses \(\d+%\), \d+\.\d s(, about \d+\.\d s left)?$", line)[1])
            for line in lines[:-1]]
    assert done == [5, 10, 15, 20, 24, 29, 34, 39, 44]
    assert lines[0].startswith("workspace: 5 of 48 poses (10%), ")
    assert lines[-1].startswith("workspace: 48 of 48 poses in ")
