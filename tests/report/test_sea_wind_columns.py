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
