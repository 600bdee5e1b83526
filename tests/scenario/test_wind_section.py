"""The ``[wind]`` section (issue 40, item 1): its keys in SI with their conventions, and every
mistake refused in one line naming the key (exit 2 from the CLI)."""

from __future__ import annotations

import math
import tomllib
from importlib import resources
from pathlib import Path

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
    d["wind"] = {k: v for k, v in {**WIND, **changes}.items() if v is not None}
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


BUILTIN = Path(str(resources.files("marinecdpr.scenario") / "builtin"))


def _sea_dict():
    """paper_sea's dict: a sea-state base motion (Hs, Tp, heading); read with base_dir=BUILTIN."""
    return tomllib.loads((BUILTIN / "paper_sea.toml").read_text())


def sea_wind(base_motion=None, **changes):
    d = _sea_dict()
    d["base_motion"].update(base_motion or {})
    d["wind"] = {k: v for k, v in {**WIND, **changes}.items() if v is not None}
    return scenario_from_dict(d, source="wind.toml", base_dir=BUILTIN)


def test_the_pierson_moskowitz_wind_by_hand():
    """``with_sea = "pierson_moskowitz"``: Hs = 2 sqrt(a / b) U_19.5^2 / g with Pierson and
    Moskowitz's a = 8.1e-3 and b = 0.74 (Hs g / U^2 = 0.209246, the quoted 0.21 to 0.4 %). At
    Hs 4 m and g 9.81 by hand: U_19.5 = sqrt(9.81 x 4 / 0.209246) = 13.6942 m/s, at 10 m with
    alpha 0.12: x (10 / 19.5)^0.12 = 0.922988, 12.6396 m/s; the waves heading 30 deg (to), the
    wind comes from 210 deg (aligned), 240 with a 30 deg misalignment. The profile's own law
    (motion.wind.wind_speed_at) takes the speed back to 19.5 m."""
    from marinecdpr.motion.wind import wind_speed_at
    from marinecdpr.scenario.wind import PM_HS_COEFFICIENT, pierson_moskowitz_wind

    assert PM_HS_COEFFICIENT == pytest.approx(0.209246, abs=1e-6)
    assert PM_HS_COEFFICIENT == pytest.approx(0.21, rel=4e-3)
    d = _sea_dict()
    d["environment"] = {"gravity_m_s2": 9.81}
    d["base_motion"].update(hs_m=4.0, heading_deg=30.0)
    d["wind"] = {k: v for k, v in {**WIND, "speed_m_s": None, "direction_deg": None,
                                    "with_sea": "pierson_moskowitz"}.items() if v is not None}
    w = scenario_from_dict(d, source="x", base_dir=BUILTIN).wind
    assert w.speed_m_s == pytest.approx(12.6396, abs=1e-4) and w.direction_deg == 210.0
    assert wind_speed_at(19.5, w.speed_m_s, 10.0, 0.12) == pytest.approx(13.6942, abs=1e-4)
    assert pierson_moskowitz_wind(4.0, 9.81, 19.5, 0.12) == pytest.approx(13.6942, abs=1e-4)
    d["wind"]["misalignment_deg"] = 30.0
    assert scenario_from_dict(d, source="x", base_dir=BUILTIN).wind.direction_deg == 240.0


def test_a_wind_that_follows_the_sea_follows_it_through_changes():
    """The scenario's own sea state sets the wind, and so does every copy with another sea
    (``with_updates``: what the studies' cells do): Hs 1 m -> 4 m doubles U (U ~ sqrt(Hs)); the
    waves turned to 90 deg turn the wind to 270. The keys it sets are left out of the
    scenario's dump (read again, they are set again); without ``with_sea`` the dump is as it
    was before these keys existed. With ``"scatter"``, ``speed_m_s`` is the own sea state's."""
    sc = sea_wind({"hs_m": 1.0, "heading_deg": 180.0}, speed_m_s=None, direction_deg=None,
                  with_sea="pierson_moskowitz")
    again = sc.with_updates("base_motion", hs_m=4.0, heading_deg=90.0)
    assert again.wind.speed_m_s == pytest.approx(2.0 * sc.wind.speed_m_s, rel=1e-14)
    assert (sc.wind.direction_deg, again.wind.direction_deg) == (0.0, 270.0)
    dumped = sc.model_dump(exclude_none=True)["wind"]
    assert "speed_m_s" not in dumped and "direction_deg" not in dumped and dumped["with_sea"] == "pierson_moskowitz"
    plain = sea_wind().model_dump(exclude_none=True)["wind"]
    assert "with_sea" not in plain and "misalignment_deg" not in plain and plain["direction_deg"] == 90.0
    scat = sea_wind({"heading_deg": 45.0}, direction_deg=None, with_sea="scatter", misalignment_deg=-90.0).wind
    assert (scat.speed_m_s, scat.direction_deg) == (15.0, 135.0)


@pytest.mark.parametrize("changes, key, says", [
    ({"with_sea": "jonswap"}, "wind.with_sea", "'none', 'scatter' or 'pierson_moskowitz'"),
    ({"with_sea": "pierson_moskowitz", "direction_deg": None}, "wind.speed_m_s",
     "sets it from each sea state's Hs: leave it out"),
    ({"with_sea": "scatter"}, "wind.direction_deg", "sets it from the waves' heading"),
    ({"with_sea": "scatter", "speed_m_s": None, "direction_deg": None}, "wind.speed_m_s",
     "missing: with with_sea = \"scatter\" it is the wind in [base_motion]'s own sea state"),
    ({"misalignment_deg": 20.0}, "wind.misalignment_deg", "is for a wind that follows the sea"),
    ({"speed_m_s": None}, "wind.speed_m_s", "missing: the mean wind speed"),
])
def test_a_wind_with_the_sea_mistake_is_one_line(changes, key, says):
    with pytest.raises(ScenarioError) as err:
        sea_wind(**changes)
    text = str(err.value)
    assert "\n" not in text and f"wind.toml: {key}" in text and says in text, text


def test_a_wind_with_the_sea_needs_a_sea_state():
    """``with_sea`` on a ship that moves in sines (paper's) has no Hs nor heading: one line."""
    with pytest.raises(ScenarioError) as err:
        with_wind(speed_m_s=None, direction_deg=None, with_sea="pierson_moskowitz")
    text = str(err.value)
    assert "\n" not in text and text.startswith("wind.toml: wind.with_sea: a wind that follows the sea state needs "
                                                "a [base_motion] of type \"sea_state\" (its Hs and heading), got "
                                                "\"sinusoidal\""), text
