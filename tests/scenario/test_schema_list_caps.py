"""A list longer than its cap is named with its cap, not as a 3-vector (issue 37, item 19):
10 000 ``[[obstacles]]`` were refused as "expected 3 numbers [x, y, z], got 10000"."""

from __future__ import annotations

import pytest

from marinecdpr.errors import ScenarioError
from marinecdpr.scenario.loading import scenario_from_dict
from marinecdpr.scenario.obstacles import MAX_OBSTACLES
from tests.conftest import paper_dict


def _boxes(n: int) -> dict:
    d = paper_dict()
    d["robot"]["clearance_m"] = 0.0
    d["obstacles"] = [{"type": "box", "center_m": [0.001 * k, 3.0, 0.5], "size_m": [0.01, 0.01, 0.01]}
                      for k in range(n)]
    return d


@pytest.mark.parametrize("n", [MAX_OBSTACLES + 1, 10_000])
def test_more_obstacles_than_the_cap_are_refused_naming_the_cap(n):
    with pytest.raises(ScenarioError) as err:
        scenario_from_dict(_boxes(n))
    assert err.value.key == "obstacles" and err.value.detail == f"at most {MAX_OBSTACLES} entries, got {n}"


def test_the_cap_s_number_of_obstacles_loads():
    assert len(scenario_from_dict(_boxes(MAX_OBSTACLES)).obstacles) == MAX_OBSTACLES == 1000


@pytest.mark.parametrize("edit, key, detail", [
    (lambda d: d["robot"]["cables"][0].update(frame_anchor_m=[1.0, 2.0, 3.0, 4.0]), "robot.cables[1].frame_anchor_m",
     "expected 3 numbers [x, y, z], got 4"),
    (lambda d: d.update(cleaning={"panel_m": [[0.3, 0.3, 1.0], [1.6, 0.3], [1.6, 1.1]], "brush_diameter_m": 0.2,
                                  "speed_m_s": 0.1, "acceleration_m_s2": 0.3, "jerk_m_s3": 3.0,
                                  "normal_force_N": [40.0, 80.0], "friction": 0.4}),
     "cleaning.panel_m[1]", "expected 2 numbers, got 3"),
])
def test_a_vector_too_long_is_still_named_by_its_size(edit, key, detail):
    d = paper_dict()
    edit(d)
    with pytest.raises(ScenarioError) as err:
        scenario_from_dict(d)
    assert err.value.key == key and err.value.detail == detail
