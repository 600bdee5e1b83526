"""Issue 21, items 19 and 20: unit vectors within a stated tolerance are normalised (not a
traceback deep in the geometry), and the scenario's types are strict (no string read as a
number or a bool)."""

import tomllib
from importlib import resources

import numpy as np
import pytest

from marinecdpr.errors import ScenarioError
from marinecdpr.planning.planner import plan
from marinecdpr.scenario.loading import scenario_from_dict


def _builtin(name: str) -> dict:
    folder = resources.files("marinecdpr.scenario") / "builtin"
    data = tomllib.loads((folder / f"{name}.toml").read_text())
    rao = data.get("base_motion", {}).get("rao")
    if rao is not None and "file" in rao:
        rao["file"] = str(folder / rao["file"])
    return data


def test_a_pulley_axis_a_hair_off_unit_length_is_normalised_and_plans():
    data = _builtin("paper_as_built")
    data["robot"]["cables"][0]["pulley_axis"] = [0.0, 0.0, -(1.0 + 1e-9)]
    data["time"]["duration_s"] = 0.05
    sc = scenario_from_dict(data)
    assert sc.robot.pulley_axes[0].tolist() == [0.0, 0.0, -1.0]  # exactly unit
    reference = scenario_from_dict({**data, "robot": _builtin("paper_as_built")["robot"]})
    # it refused with "swivel axes z_C must be unit vectors" (ValueError, a traceback) before
    assert np.array_equal(plan(sc).tensions, plan(reference).tensions)


def test_a_slanted_axis_within_the_tolerance_comes_out_unit():
    data = _builtin("paper_as_built")
    data["robot"]["cables"][1]["pulley_axis"] = [0.6, 0.0, 0.8 * (1.0 + 3e-7)]
    z = scenario_from_dict(data).robot.pulley_axes[1]
    assert abs(np.linalg.norm(z) - 1.0) < 1e-15
    assert z[0] / z[2] == pytest.approx(0.6 / (0.8 * (1.0 + 3e-7)), rel=1e-15)


def test_an_axis_beyond_the_tolerance_is_one_line_naming_the_key():
    data = _builtin("paper_as_built")
    data["robot"]["cables"][2]["pulley_axis"] = [0.0, 0.0, 1.0 + 1e-5]  # ten times the stated 1e-6
    with pytest.raises(ScenarioError) as err:
        scenario_from_dict(data)
    message = str(err.value)
    assert "\n" not in message and "pulley_axis" in message and "unit vector" in message


def test_a_hull_normal_a_hair_off_unit_length_is_normalised():
    data = _builtin("paper_clean")
    data["cleaning"]["hull_normal"] = [0.0, 1.0 - 5e-7, 0.0]
    assert scenario_from_dict(data).cleaning.hull_normal == (0.0, 1.0, 0.0)


@pytest.mark.parametrize(("key", "value"), [
    ("hull_normal", [0.0, "1.0", 0.0]),   # planned with exit 0 before
    ("boundary_pass", "yes"),             # planned with exit 0 before
    ("boundary_pass", "true"),
    ("boundary_pass", 1),
    ("hull_normal", [0.0, True, 0.0]),
])
def test_a_string_or_bool_for_a_number_or_a_bool_is_refused_naming_the_key(key, value):
    data = _builtin("paper_clean")
    data["cleaning"][key] = value
    with pytest.raises(ScenarioError) as err:
        scenario_from_dict(data)
    message = str(err.value)
    assert "\n" not in message and key in message
