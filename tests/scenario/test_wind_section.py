"""The ``[wind]`` section (issue 40, item 1): its keys in SI with their conventions, and every
mistake refused in one line naming the key (exit 2 from the CLI)."""

from __future__ import annotations

import math

import pytest
import tomli_w
from typer.testing import CliRunner

from marinecdpr import ScenarioError
from marinecdpr.cli.app import app
from marinecdpr.scenario.loading import scenario_from_dict

from conftest import paper_dict

WIND = {"speed_m_s": 15.0, "direction_deg": 90.0, "platform_shape_coefficient": 1.5,
        "platform_area_m2": [0.5, 1.0, 0.25], "cable_diameter_m": 0.006}


def with_wind(**changes):
    d = paper_dict()
    d["wind"] = {**WIND, **changes}
    return scenario_from_dict(d, source="wind.toml")


def test_wind_section_reads_with_its_defaults():
    w = with_wind().wind
    assert (w.speed_m_s, w.direction_deg, w.platform_area_m2, w.cable_diameter_m) == (15.0, 90.0, (0.5, 1.0, 0.25),
                                                                                        0.006)
    # the defaults: U10 at 10 m, DNV-RP-C205's open-sea exponent, Frøya's gust, the mean in the plan
    assert (w.reference_height_m, w.profile_exponent, w.gust, w.plan_gust, w.cable_drag_coefficient) == (
        10.0, 0.12, "froya", "mean", 1.2)
    assert with_wind(plan_gust=1.4).wind.plan_gust == 1.4
    assert with_wind(plan_gust="series").wind.plan_gust == "series"
    assert paper_dict().get("wind") is None and scenario_from_dict(paper_dict(), source="x").wind is None


@pytest.mark.parametrize("changes, key, says", [
    ({"speed_m_s": -3.0}, "wind.speed_m_s", "must be above 0 and at most 70 m/s"),
    ({"speed_m_s": math.inf}, "wind.speed_m_s", "finite"),
    ({"plan_gust": 4.0}, "wind.plan_gust", "a gust factor must be between 1 and 3"),
    ({"plan_gust": "peak"}, "wind.plan_gust", "must be \"mean\", \"series\" or a gust factor"),
    ({"platform_area_m2": [0.0, 0.0, 0.0]}, "wind.platform_area_m2", "at least one area must be above 0"),
    ({"platform_area_m2": [-1.0, 0.0, 0.0]}, "wind.platform_area_m2", "got x = -1"),
    ({"profile_exponent": 0.9}, "wind.profile_exponent", "between 0 and 0.5"),
    ({"cable_diameter_m": 2.0}, "wind.cable_diameter_m", "between 0 and 0.5 m"),
    ({"gust": "kaimal"}, "wind.gust", "froya"),
    ({"direction": 3.0}, "wind.direction", "unknown key"),
])
def test_wind_mistake_is_one_line_naming_the_key(changes, key, says):
    with pytest.raises(ScenarioError) as err:
        with_wind(**changes)
    text = str(err.value)
    assert "\n" not in text and f"wind.toml: {key}" in text and says in text, text


def test_wind_missing_shape_coefficient_exits_2_in_one_line(tmp_path):
    d = paper_dict()
    d["wind"] = {"speed_m_s": 10.0, "platform_area_m2": [1.0, 0.0, 0.0]}
    path = tmp_path / "windy.toml"
    path.write_text(tomli_w.dumps(d))
    res = CliRunner().invoke(app, ["check", str(path)])
    assert res.exit_code == 2, res.output
    assert "wind.platform_shape_coefficient: missing" in res.output and "Traceback" not in res.output
