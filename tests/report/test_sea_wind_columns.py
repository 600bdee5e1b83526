"""operability.csv's wind per sea state (issue 40, item 1): with ``[wind] with_sea`` each row
says the wind its sea state flew; without, the file is as before."""

from __future__ import annotations

import csv

import numpy as np
import pytest

from marinecdpr.report.writers import write_operability
from marinecdpr.scenario.wind import pierson_moskowitz_wind
from marinecdpr.studies.operability import ScatterDiagram, operability

from test_sea_wind import sea_scenario


def test_operability_csv_says_each_sea_state_s_wind(tmp_path):
    """Two heights and two headings of the Pierson-Moskowitz wind: each row's ``wind_m_s`` is
    the relation at its Hs (g = 9.8, to the CSV's 10 digits), ``wind_direction_deg`` its
    heading + 180 mod 360; the same study without a wind has no such columns."""
    scatter = ScatterDiagram(np.array([1.0, 2.5]), np.array([8.0]), np.array([[0.5], [0.5]]))
    kw = dict(headings_deg=(180.0, 90.0), duration_s=20.0, step_s=0.1, realisations=1)
    template = sea_scenario(with_sea="pierson_moskowitz")
    write_operability(operability(template, scatter, **kw), template, tmp_path / "wind")
    rows = list(csv.DictReader(open(tmp_path / "wind" / "operability.csv")))
    assert len(rows) == 4
    for r in rows:
        hs, heading = float(r["hs_m"]), float(r["heading_deg"])
        assert float(r["wind_m_s"]) == pytest.approx(pierson_moskowitz_wind(hs, 9.8, 10.0, 0.12), rel=1e-9)
        assert float(r["wind_direction_deg"]) == (heading + 180.0) % 360.0
    still = sea_scenario()
    write_operability(operability(still, scatter, **kw), still, tmp_path / "still")
    header = open(tmp_path / "still" / "operability.csv").readline().strip().split(",")
    assert "wind_m_s" not in header and header[-1] == "controller_bypassed"


def test_clean_seas_sea_states_csv_says_each_sea_state_s_wind(tmp_path):
    """``clean --seas`` (1 s of paper_clean's job in two sea states, heading 90): sea_states.csv
    names each sea state's Pierson-Moskowitz wind, from 270 deg."""
    import tomllib

    import tomli_w
    from typer.testing import CliRunner

    from marinecdpr.cli.app import app
    from test_sea_wind import BUILTIN, WIND

    d = tomllib.loads((BUILTIN / "paper_clean.toml").read_text())
    d["base_motion"]["rao"]["file"] = str(BUILTIN / d["base_motion"]["rao"]["file"])
    d["wind"] = WIND | {"with_sea": "pierson_moskowitz"}
    (tmp_path / "pm.toml").write_text(tomli_w.dumps(d))
    (tmp_path / "s.csv").write_text("hs_m,tp_s,probability\n1,8,0.5\n3,8,0.5\n")
    res = CliRunner().invoke(app, ["clean", str(tmp_path / "pm.toml"), "--seas", "--scatter", str(tmp_path / "s.csv"),
                                   "--headings", "90", "--duration", "1", "--serial", "--out", str(tmp_path / "o")])
    assert res.exit_code == 0, res.output
    rows = list(csv.DictReader(open(tmp_path / "o" / "sea_states.csv")))
    assert [float(r["hs_m"]) for r in rows] == [1.0, 3.0]
    for r in rows:
        assert float(r["wind_m_s"]) == pytest.approx(pierson_moskowitz_wind(float(r["hs_m"]), 9.8, 10.0, 0.12),
                                                     rel=1e-9)
        assert float(r["wind_direction_deg"]) == 270.0
