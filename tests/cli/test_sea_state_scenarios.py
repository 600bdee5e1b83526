"""Sea-state scenarios end to end: RAO files in scenarios, and the workspace and operability commands."""

import json
import tomllib
from importlib import resources

import numpy as np
import pytest
from typer.testing import CliRunner

import marinecdpr
from marinecdpr.motion.basemotion import rao_from_source as _rao
from marinecdpr.cli.app import app
from marinecdpr.motion.rao import write_rao_csv

runner = CliRunner()


BOX = {"source": "box_hull", "length_m": 100.0, "beam_m": 20.0, "draught_m": 6.0, "gm_m": 2.0,
       "roll_damping_ratio": 0.05}


def test_rao_csv_in_a_scenario_plans_like_the_box_hull(tmp_path):
    sea = marinecdpr.load_scenario("paper_sea").with_changes(time={"step_s": 0.01, "duration_s": 15.0})
    sea = sea.with_changes(base_motion=sea.base_motion.model_dump(exclude_none=True) | {"rao": BOX})
    write_rao_csv(_rao(sea.base_motion.rao.model_dump_json()), tmp_path / "ship_rao.csv")
    text = (resources.files("marinecdpr.scenario") / "builtin" / "paper_sea.toml").read_text()
    start = text.index("[base_motion.rao]")
    end = text.index("[trajectory]")
    (tmp_path / "s.toml").write_text(text[:start] + '[base_motion.rao]\nsource = "csv"\nfile = "ship_rao.csv"\n\n'
                                     + text[end:].replace("step_s = 0.001", "step_s = 0.01"))
    from_csv = marinecdpr.load_scenario(tmp_path / "s.toml")   # relative to the scenario's folder
    a, b = marinecdpr.plan(sea), marinecdpr.plan(from_csv)
    assert a.all_feasible
    np.testing.assert_allclose(b.tensions, a.tensions, rtol=1e-9, atol=1e-9)


def test_sea_state_scenario_simulates():
    sc = marinecdpr.load_scenario("paper_sea")
    res = marinecdpr.simulate(sc, run="closed_loop", plant="own", n_steps=2000)
    assert np.abs(res.pose_error[:, :3]).max() < 1e-5


@pytest.mark.figures
def test_workspace_command(tmp_path):
    res = runner.invoke(app, ["workspace", "paper", "--duration", "1", "--step", "0.05", "--points", "8x6",
                              "--out", str(tmp_path)])
    assert res.exit_code == 0, res.output
    rows = np.genfromtxt(tmp_path / "workspace.csv", delimiter=",", names=True)
    assert rows.size == 48 and set(rows.dtype.names) >= {"x_m", "z_m", "fraction_feasible"}
    assert (tmp_path / "workspace.png").read_bytes()[:4] == b"\x89PNG"
    bad = runner.invoke(app, ["workspace", "--points", "8", "--out", str(tmp_path)])
    assert bad.exit_code == 2 and "--points 8: expected two positive integers" in bad.stderr


@pytest.mark.figures
def test_operability_command(tmp_path):
    scatter = tmp_path / "scatter.csv"
    scatter.write_text("hs_m,tp_s,probability\n0.5,7,0.7\n1.5,9,0.3\n")
    res = runner.invoke(app, ["operability", "--scatter", str(scatter), "--headings", "180,90", "--serial",
                              "--duration", "30", "--step", "0.05", "--out", str(tmp_path / "o")])
    assert res.exit_code == 0, res.output
    s = json.loads((tmp_path / "o" / "operability.json").read_text())
    assert s["operability"] == 1.0 and s["cells"] == 4 and set(s["per_heading"]) == {"180", "90"}
    # every sea state of each Tp is workable: no limit within the diagram (null), not the top row's Hs
    assert s["limiting_hs_m"]["90"] == {"7": None, "9": None}
    assert (tmp_path / "o" / "operability.png").exists()
    bad = runner.invoke(app, ["operability", "paper", "--serial", "--out", str(tmp_path / "p")])
    assert bad.exit_code == 2 and "needs a [base_motion] of type sea_state" in bad.stderr
