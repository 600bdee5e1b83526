"""Values implausible for the robot's and the ship's own sizes are remarked (issue 37, item 11).

A frame origin of [2000, -1000, 100] m on a 120 m box hull, and a platform inertia a thousand
times a plate's (a 7 m radius of gyration on a 0.6 m plate), had passed `check` and `plan`
without a word. Each is now one warning line (exit code unchanged) from check, plan and
simulate; the shipped scenarios give none.
"""

from __future__ import annotations

import numpy as np
import pytest
from typer.testing import CliRunner

import marinecdpr
from marinecdpr.cli.app import app
from marinecdpr.scenario.scale import hull_box, plausibility_warnings, scale_warnings

from conftest import make_scenario, paper_dict

runner = CliRunner()

SEA = {"type": "sea_state", "hs_m": 1.0, "tp_s": 8.0, "record_s": 120.0,
       "rao": {"source": "box_hull", "length_m": 120.0, "beam_m": 20.0, "draught_m": 6.0, "gm_m": 2.0}}


def _warnings(res) -> list[str]:
    return [" ".join(w.split()) for w in res.stderr.split("warning:")[1:]]


def test_a_frame_origin_far_off_the_box_hull_is_remarked_by_how_far():
    far = make_scenario(base_motion=SEA, ship={"frame_origin_m": [2000.0, -1000.0, 100.0]})
    lo, hi, what = hull_box(far)
    np.testing.assert_array_equal(lo, [-60.0, -10.0, -6.0])   # L/2, B/2, T; a beam above the waterline
    np.testing.assert_array_equal(hi, [60.0, 10.0, 20.0])
    (line,) = plausibility_warnings(far)
    # by hand: x is 2000 - 60 = 1940 m beyond the bow, the most of the three
    assert line.startswith("ship.frame_origin_m = [2000, -1000, 100] m lies 1940 m outside the hull of the box hull "
                           "of [base_motion.rao] (120 x 20 x 6 m)"), line
    # on the hull's side, and hanging a frame's size or 12 m (10 % of L) over it: nothing
    for origin in ([-0.78, 10.0, 2.2], [40.0, -21.9, -6.0], [71.9, 0.0, 0.0]):
        assert plausibility_warnings(make_scenario(base_motion=SEA, ship={"frame_origin_m": origin})) == []
    assert plausibility_warnings(make_scenario(base_motion=SEA, ship={"frame_origin_m": [72.1, 0.0, 0.0]}))
    # no hull size given (the paper's sinusoidal motion): nothing to judge it by
    assert plausibility_warnings(make_scenario(ship={"frame_origin_m": [2000.0, -1000.0, 100.0]})) == []


def test_a_wigley_surface_bounds_the_frame_origin_with_its_flare():
    sc = marinecdpr.load_scenario("paper_clean")
    lo, hi, _ = hull_box(sc)
    # half-breadth (B/2)(1 + flare (z/T)^2) at the band's top 11.6 m: 16 (1 + 0.2 * 1.16^2)
    assert hi[1] == pytest.approx(16.0 * (1.0 + 0.2 * 1.16 ** 2), rel=1e-12)
    assert hi[2] == 11.6 and lo[2] == -10.0
    d = sc.model_dump(exclude_none=True)
    d["ship"]["frame_origin_m"] = [0.0, 0.0, 11.6 + 20.0 + 1.0]   # 21 m over the topside (margin 20 m)
    (line,) = plausibility_warnings(sc.with_changes(ship=d["ship"]))
    assert "lies 21 m outside the hull of [cleaning.surface] (200 x 32 x 10 m)" in line


def test_an_inertia_far_beyond_the_platforms_size_is_remarked():
    # the paper's plate: 5 kg, I = 0.03, 0.03, 0.06 kg m^2, anchors 0.195 m from the centre:
    # k = sqrt(0.06 / 5) = 0.11 m; a thousand times the inertia: 3.46 m, 17.8 times the reach
    heavy = make_scenario(lambda d: d["robot"].update(inertia_kg_m2=[30.0, 30.0, 60.0]))
    (line,) = plausibility_warnings(heavy)
    reach = np.hypot(0.125, 0.15)
    k = np.sqrt(60.0 / 5.0)
    assert line.startswith(f"robot.inertia_kg_m2 gives the 5 kg platform a radius of gyration of {k:.3g} m, "
                           f"{k / reach:.3g} times the {reach:.3g} m from its centre of mass"), line
    # three times the reach passes, a little more does not
    edge = 3.0 * reach
    ok = make_scenario(lambda d: d["robot"].update(inertia_kg_m2=[5.0 * (0.999 * edge) ** 2] * 3))
    assert plausibility_warnings(ok) == []
    bad = make_scenario(lambda d: d["robot"].update(inertia_kg_m2=[5.0 * (1.001 * edge) ** 2] * 3))
    assert len(plausibility_warnings(bad)) == 1


def test_a_platform_heavier_than_steel_of_its_size_is_remarked():
    # the paper's plate reaches 0.195 m: a steel ball of that radius weighs 7850 (4/3) pi r^3 = 244.8 kg
    reach = np.hypot(0.125, 0.15)
    ball = 7850.0 * 4.0 / 3.0 * np.pi * reach ** 3
    assert ball == pytest.approx(244.8, abs=0.1)
    grams = make_scenario(lambda d: d["robot"].update(mass_kg=5000.0, inertia_kg_m2=[30.0, 30.0, 60.0]))
    (line,) = plausibility_warnings(grams)    # (the inertia is plausible at that mass: k = 0.11 m)
    assert line.startswith(f"robot.mass_kg = 5000 kg is {5000.0 / ball:.3g} times a solid steel ball")
    assert plausibility_warnings(make_scenario(lambda d: d["robot"].update(
        mass_kg=0.99 * 3.0 * ball, inertia_kg_m2=[30.0, 30.0, 60.0]))) == []


@pytest.mark.parametrize("name", ["paper", "paper_sea", "paper_clean", "paper_as_built", "paper_elastic",
                                  "examples/spatial_cube8.toml"])
def test_the_shipped_scenarios_are_plausible(name):
    assert scale_warnings(marinecdpr.load_scenario(name)) == []


def test_check_plan_and_simulate_say_so_one_line_each(tmp_path):
    import tomli_w

    data = paper_dict()
    data["ship"]["frame_origin_m"] = [2000.0, -1000.0, 100.0]
    data["robot"]["inertia_kg_m2"] = [30.0, 30.0, 60.0]
    data["base_motion"] = SEA
    data["time"] = {"step_s": 0.01, "duration_s": 0.2}
    path = tmp_path / "units.toml"
    path.write_text(tomli_w.dumps(data))
    for args in (["check", str(path)], ["plan", str(path), "--out", str(tmp_path / "p"), "--allow-infeasible"],
                 ["simulate", str(path), "--out", str(tmp_path / "s"), "--plant", "own"]):
        res = runner.invoke(app, args)
        found = _warnings(res)
        assert sum("ship.frame_origin_m = [2000, -1000, 100] m lies 1940 m outside" in w for w in found) == 1, args
        assert sum("robot.inertia_kg_m2 gives the 5 kg platform a radius of gyration of 3.46 m" in w
                   for w in found) == 1, (args, res.output)
