"""Issue 21, item 14: ``clean`` works for a spatial robot (examples/spatial_cube8.toml with
a [cleaning] section): its cables hold the brush on the hull at the preload, and the
cleaned area is the brush's swept footprint in C's x-z plane at ``plane_y_m``."""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

from typer.testing import CliRunner

from marinecdpr.cli.app import app

runner = CliRunner()
EXAMPLES = Path(__file__).resolve().parents[2] / "examples"

CLEANING = '''[trajectory]
type = "coverage"
plane_y_m = 1.0                     # the panel's plane: the frame's middle

[cleaning]
panel_m = [[0.7, 0.7], [1.3, 0.7], [1.3, 1.3], [0.7, 1.3]]
brush = "disc"
brush_diameter_m = 0.2
overlap_m = 0.03
speed_m_s = 0.1
acceleration_m_s2 = 0.3
jerk_m_s3 = 3.0
normal_force_N = [40.0, 80.0]
preload_N = 60.0
friction = 0.4
hull_normal = [0.0, 1.0, 0.0]

'''


def _spatial_cleaning(tmp_path: Path) -> Path:
    text = (EXAMPLES / "spatial_cube8.toml").read_text()
    start, end = text.index("[trajectory]"), text.index("[time]")
    path = tmp_path / "cube8_clean.toml"
    path.write_text(text[:start] + CLEANING + '[time]\nstep_s = 0.001\nduration_s = 45.0\n\n'
                    '[simulation]\nplant = "own"\n', encoding="utf-8")
    return path


def test_clean_works_for_a_spatial_robot(tmp_path):
    out = tmp_path / "out"
    res = runner.invoke(app, ["clean", str(_spatial_cleaning(tmp_path)), "--duration", "1", "--no-compare",
                              "--out", str(out)])
    assert res.exit_code == 0, res.output
    s = json.loads((out / "summary.json").read_text())
    assert s["steps"] == 1001 and s["infeasible_steps"] == 0 and s["controller_verdict"] == "held"
    # the cables hold the brush on at the preload
    assert s["normal_force_min_N"] == s["normal_force_max_N"] == 60.0 and s["normal_force_in_band_pct"] == 100.0
    rows = list(csv.DictReader((out / "clean.csv").open()))
    # on the panel's plane (y = 1 m) and on its path, across the rolling, heaving ship
    assert max(abs(float(r["brush_y_m"]) - 1.0) for r in rows) < 1e-6
    assert s["max_cross_track_error_m"] < 1e-5
    # the first second is a straight stretch from the corner (0.8, 0.8) inset by the brush's
    # radius: the cleaned area is the swept stadium
    xz = [(float(r["brush_x_m"]), float(r["brush_z_m"])) for r in rows]
    assert xz[0] == (0.8, 0.8)
    length = math.dist(xz[0], xz[-1])
    assert 0.05 < length < 0.1 and abs(sum(math.dist(a, b) for a, b in zip(xz, xz[1:])) - length) < 1e-5
    stadium = length * 0.2 + math.pi * 0.1 ** 2
    assert abs(s["coverage_pct"] - 100.0 * stadium / 0.36) < 0.5
    # the report says how the normal force was had: the cables, not a guide
    assert s["robot_dofs"] == "spatial"
    html = (out / "report.html").read_text()
    assert "the cables hold the brush on the hull at the preload" in html and "the guide holds" not in html
