"""A wind per sea state in the sea-state studies (issue 40, item 1): the scatter diagram's wind
columns, each cell's wind in its scenario (the column, or the Pierson-Moskowitz relation at
the cell's Hs, from the cell's waves' heading), and every mistake refused in one line."""

from __future__ import annotations

import copy
import tomllib
from importlib import resources
from pathlib import Path

import numpy as np
import pytest
import tomli_w
from typer.testing import CliRunner

from marinecdpr import ScenarioError
from marinecdpr.cli.app import app
from marinecdpr.scenario.loading import scenario_from_dict
from marinecdpr.studies.operability import (Cell, cell_scenario, cell_wind, evaluate_cell, read_scatter_csv,
                                            scatter_cells, wind_scenario)

BUILTIN = Path(str(resources.files("marinecdpr.scenario") / "builtin"))
WIND = {"platform_shape_coefficient": 1.5, "platform_area_m2": [0.3, 0.4, 0.2], "cable_diameter_m": 0.006}


def sea_dict(**wind):
    """paper_sea (the paper's robot on its circle, in seas through RAOs) with a [wind]."""
    d = copy.deepcopy(tomllib.loads((BUILTIN / "paper_sea.toml").read_text()))
    d["base_motion"]["rao"]["file"] = str(BUILTIN / d["base_motion"]["rao"]["file"])
    if wind:
        d["wind"] = WIND | wind
    return d


def sea_scenario(**wind):
    return scenario_from_dict(sea_dict(**wind), source="sea.toml")


def test_the_scatter_s_wind_columns_reach_each_cell_s_scenario(tmp_path):
    """A diagram with ``wind_m_s`` and ``wind_misalignment_deg`` (in either order after the
    probability): each cell's wind is read into the grid and the cells; with ``with_sea =
    "scatter"`` a cell's scenario flies its column's speed, from the heading + 180 + the
    misalignment (heading 90: the wind from 270, less 20: 250 deg); without the columns the
    cells carry no wind."""
    path = tmp_path / "windy.csv"
    path.write_text("hs_m,tp_s,probability,wind_misalignment_deg,wind_m_s\n1,6,0.3,0,7.5\n2,6,0.1,-20,11\n"
                    "1,8,0.6,15,8.25\n")
    d = read_scatter_csv(path)
    np.testing.assert_array_equal(d.wind_m_s, [[7.5, 8.25], [11.0, np.nan]])
    np.testing.assert_array_equal(d.wind_misalignment_deg, [[0.0, 15.0], [-20.0, np.nan]])
    cells = scatter_cells(d, (90.0,))
    assert [(c.hs, c.tp, c.wind_m_s, c.wind_misalignment_deg) for c in cells] == [
        (1.0, 6.0, 7.5, 0.0), (1.0, 8.0, 8.25, 15.0), (2.0, 6.0, 11.0, -20.0)]
    template = sea_scenario(speed_m_s=5.0, with_sea="scatter")
    run = cell_scenario(template, cells[2], 60.0, 0.05)
    assert (run.wind.speed_m_s, run.wind.direction_deg, run.base_motion.hs_m) == (11.0, 250.0, 2.0)
    assert cell_wind(template, cells[1]) == (8.25, 285.0)
    plain = tmp_path / "plain.csv"
    plain.write_text("hs_m,tp_s,probability\n1,6,1\n")
    p = read_scatter_csv(plain)
    assert p.wind_m_s is None and p.wind_misalignment_deg is None
    assert scatter_cells(p, (180.0,))[0].wind_m_s is None


def test_each_cell_flies_its_own_wind_and_its_plan_is_that_wind_s():
    """The Pierson-Moskowitz wind in two cells of paper_sea's robot (Hs 1.5 and 3 m, head seas:
    7.736 and 10.941 m/s at 10 m at g = 9.8, from 0 deg): each cell's verdict and smallest headroom are
    bit for bit those of the scenario with that wind fixed (:func:`wind_scenario`), and
    the wind moves the headroom from the no-wind study's."""
    template = sea_scenario(with_sea="pierson_moskowitz")
    still = sea_scenario()
    for hs, u in ((1.5, 7.736), (3.0, 10.941)):
        cell = Cell(0, hs, 8.0, 180.0, 1.0)
        wind = cell_wind(template, cell)
        assert wind[0] == pytest.approx(u, abs=5e-3) and wind[1] == 0.0
        kw = dict(margin_N=0.0, duration_s=60.0, step_s=0.05)
        with_sea = evaluate_cell(template, cell, **kw)
        fixed = evaluate_cell(wind_scenario(template, wind), cell, **kw)
        assert (with_sea.operable, with_sea.min_margin_N, with_sea.fraction_feasible) == (
            fixed.operable, fixed.min_margin_N, fixed.fraction_feasible)
        assert abs(with_sea.min_margin_N - evaluate_cell(still, cell, **kw).min_margin_N) > 0.1


@pytest.mark.parametrize("text, says", [
    ("hs_m,tp_s,probability,wind_speed\n1,6,1,5\n", "row 1: the header must be hs_m,tp_s,probability or "
                                                     "hs_m,tz_s,probability, optionally followed by wind_m_s"),
    ("hs_m,tp_s,probability,wind_m_s,wind_m_s\n1,6,1,5,5\n", "(each once)"),
    ("hs_m,tp_s,probability,wind_m_s\n1,6,1,0\n", "row 2: wind_m_s = 0 (column 4) must be above 0 and at most 70"),
    ("hs_m,tp_s,probability,wind_m_s\n1,6,1,nan\n", "row 2: wind_m_s = nan (column 4) must be above 0"),
    ("hs_m,tp_s,probability,wind_misalignment_deg\n1,6,1,400\n",
     "row 2: wind_misalignment_deg = 400 (column 4) must be within -360 to 360 deg"),
    ("hs_m,tp_s,probability,wind_m_s\n1,6,1\n", "row 2: expected 4 values, got 3"),
])
def test_a_wrong_wind_column_is_one_line(tmp_path, text, says):
    path = tmp_path / "s.csv"
    path.write_text(text)
    with pytest.raises(ScenarioError) as err:
        read_scatter_csv(path)
    assert "\n" not in str(err.value) and says in str(err.value), str(err.value)


def test_a_scatter_wind_without_its_column_or_given_twice_is_one_line():
    template = sea_scenario(speed_m_s=5.0, with_sea="scatter")
    with pytest.raises(ScenarioError, match=r"^wind.with_sea: with_sea = \"scatter\" takes each sea state's wind "
                                            r"from the scatter diagram's wind_m_s column, which this diagram does "
                                            r"not have"):
        cell_scenario(template, Cell(0, 1.0, 6.0, 180.0, 1.0), 60.0, 0.05)
    twice = sea_scenario(with_sea="pierson_moskowitz", misalignment_deg=10.0)
    with pytest.raises(ScenarioError, match=r"^wind.misalignment_deg: the misalignment is given twice"):
        cell_scenario(twice, Cell(0, 1.0, 6.0, 180.0, 1.0, wind_misalignment_deg=5.0), 60.0, 0.05)


def test_operability_with_a_scatter_wind_and_no_column_exits_2_in_one_line(tmp_path):
    path = tmp_path / "windy.toml"
    path.write_text(tomli_w.dumps(sea_dict(speed_m_s=5.0, with_sea="scatter")))
    res = CliRunner().invoke(app, ["operability", str(path), "--duration", "60"])
    assert res.exit_code == 2, res.output
    lines = [line for line in res.output.splitlines() if line.strip()]
    assert len(lines) == 1 and "wind.with_sea: with_sea = \"scatter\" takes each sea state's wind" in lines[0], \
        res.output


def test_clean_seas_with_a_scatter_wind_and_no_column_exits_2_in_one_line(tmp_path):
    """``clean --seas`` refuses before any work (the estimate) a scatter diagram that a
    ``with_sea = "scatter"`` wind cannot follow."""
    d = tomllib.loads((BUILTIN / "paper_clean.toml").read_text())
    d["base_motion"]["rao"]["file"] = str(BUILTIN / d["base_motion"]["rao"]["file"])
    d["wind"] = WIND | {"speed_m_s": 5.0, "with_sea": "scatter"}
    path = tmp_path / "windy_clean.toml"
    path.write_text(tomli_w.dumps(d))
    res = CliRunner().invoke(app, ["clean", str(path), "--seas", "--duration", "1", "--out", str(tmp_path / "o")])
    assert res.exit_code == 2, res.output
    lines = [line for line in res.output.splitlines() if line.strip()]
    assert len(lines) == 1 and "wind.with_sea: with_sea = \"scatter\" takes each sea state's wind" in lines[0], \
        res.output
    assert not (tmp_path / "o").exists()


def test_each_record_meets_a_gust_of_its_own():
    """Where the wind follows the sea, a sea state's records each meet their own gust phases
    (two realisations: series correlated below 0.2 over the record), seeded apart from the
    sea's (with [wind] seed = the sea's seed, the gust's seed is not the record's sea seed),
    and the same record gets the same gust again."""
    from marinecdpr.model.wind import scenario_gust

    template = sea_scenario(with_sea="pierson_moskowitz", record_s=600.0, seed=1)
    assert template.wind.seed == template.base_motion.seed == 1
    cell = Cell(0, 2.0, 8.0, 180.0, 1.0)
    runs = [cell_scenario(template, cell, 60.0, 0.05, r) for r in (0, 1, 0)]
    assert runs[0].wind.seed != runs[1].wind.seed and runs[0].wind.seed == runs[2].wind.seed
    assert runs[0].wind.seed != runs[0].base_motion.seed
    t = np.arange(0.0, 600.0, 0.25)
    u0, u1 = (scenario_gust(r.wind).at(t) for r in runs[:2])
    assert abs(np.corrcoef(u0, u1)[0, 1]) < 0.2
