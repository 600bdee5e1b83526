"""A cleaning job cut short (``clean --duration``, a scenario ending before its path) reports
the part flown, labelled as partial: the path flown in the time flown, not the whole path's
length beside the short time (issue 37, item 6)."""

import json

import numpy as np
import pytest
from typer.testing import CliRunner

import marinecdpr
from marinecdpr.cli.app import app
from marinecdpr.motion.trajectory import cleaning_path

runner = CliRunner()


def _flown_slowly(path, t_end: float, n: int = 400001) -> tuple[float, float]:
    """The distance travelled by ``t_end`` as the integral of the path's speed, and of it the
    part on the boundary pass's segments (its time windows from the vertices' times)."""
    t = np.linspace(0.0, t_end, n)
    speed = np.linalg.norm(path.evaluate(t)[1], axis=1)
    on_edge = np.zeros(n, dtype=bool)
    for i in np.flatnonzero(path.boundary_segment):
        on_edge |= (t >= path.vertex_time_s[i]) & (t <= path.vertex_time_s[i + 1])
    return float(np.trapezoid(speed, t)), float(np.trapezoid(np.where(on_edge, speed, 0.0), t))


@pytest.mark.parametrize("t_end", [0.0, 3.0, 15.0, 40.0, 77.0])
def test_the_path_flown_is_the_integral_of_the_speed(t_end):
    path = cleaning_path(marinecdpr.load_scenario("paper_clean").cleaning)
    length, edge = path.flown(t_end)
    slow_length, slow_edge = _flown_slowly(path, t_end)
    assert length == pytest.approx(slow_length, abs=1e-6)
    assert edge == pytest.approx(slow_edge, abs=2e-4)  # the windows' ends on the sampled grid
    assert path.flown(path.duration_s + 5.0) == pytest.approx((path.length_m, path.boundary_length_m), rel=1e-12)


def test_clean_for_15_s_reports_the_path_flown_in_15_s(tmp_path):
    out = tmp_path / "o"
    res = runner.invoke(app, ["clean", "--duration", "15", "--no-compare", "--out", str(out)], terminal_width=4000)
    assert res.exit_code == 0, res.output
    s = json.loads((out / "summary.json").read_text())
    path = cleaning_path(marinecdpr.load_scenario("paper_clean").cleaning)
    length, edge = _flown_slowly(path, 15.001)  # 15 001 steps of 1 ms: to t = 15.001 s
    assert s["partial"] is True and s["path_flown_s"] == pytest.approx(15.001, abs=1e-9)
    assert s["path_flown_m"] == pytest.approx(length, abs=1e-6)  # 1.435 m, not the whole path's 7.3 m
    assert s["boundary_pass_flown_m"] == pytest.approx(edge, abs=2e-4)  # up the first side, 0.6 m
    assert s["path_length_m"] == pytest.approx(path.length_m)  # the whole path's, beside it
    line = next(x for x in res.stdout.splitlines() if "of path" in x or "path (" in x)
    assert line.startswith(f"A PARTIAL run: {length:.3g} m of the {path.length_m:.3g} m path")
    assert "flown in the first 15.0 s" in line and f"{s['boundary_pass_flown_m']:.3g} m of it along the edges" in line
    assert f"{path.boundary_duration_s:.1f} s" not in line  # not the whole edge pass's time
    html = (out / "report.html").read_text()
    assert "job time (a PARTIAL run)" in html and "area rate (over the part flown)" in html


def test_a_whole_run_is_not_partial():
    sc = marinecdpr.load_scenario("paper_clean")
    path = cleaning_path(sc.cleaning)
    assert sc.time.duration_s >= path.duration_s  # the built-in job flies its whole path
    from marinecdpr.report.cleaning import cleaning_findings

    s = {"coverage_pct": 99.0, "panel_area_m2": 1.04, "reachable_coverage_pct": 99.9, "reachable_area_m2": 1.03,
         "brush_width_m": 0.2, "missed_area_m2": 0.01, "lanes": 5, "lane_spacing_m": 0.15, "path_length_m": 7.3,
         "job_time_s": 77.8, "area_rate_m2_h": 47.7, "boundary_pass_length_m": 1.2, "boundary_pass_time_s": 12.9,
         "partial": False, "normal_force_in_band_pct": 100.0, "contact_lost_s": 0.0, "tension_min_N": 50.0,
         "tension_max_N": 300.0, "infeasible_steps": 0, "max_cross_track_error_m": 1e-5,
         "p95_cross_track_error_m": 1e-6, "winch_energy_kJ": 1.0}
    assert cleaning_findings(s)[1] == ("5 lanes 0.15 m apart, 7.3 m of path in 77.8 s: 47.7 m2/h; the pass along "
                                       "the edges the lanes leave takes 1.2 m and 12.9 s of it.")


def test_clean_seas_on_part_of_the_path_says_so(tmp_path):
    """The sibling in ``clean --seas``: a sea state judged on the first second of the path
    (its coverage and hours the part's) is said to be a partial job."""
    csv = tmp_path / "one.csv"
    csv.write_text("hs_m,tp_s,probability\n0.5,6,1.0\n")
    res = runner.invoke(app, ["clean", "paper_clean", "--seas", "--scatter", str(csv), "--duration", "1",
                              "--coverage-target", "0", "--serial", "--out", str(tmp_path / "o")],
                        terminal_width=4000)
    assert res.exit_code == 0, res.output
    path = cleaning_path(marinecdpr.load_scenario("paper_clean").cleaning)
    assert (f"warning: paper_clean: a PARTIAL job: each sea state flies the first 1 s of the {path.duration_s:.4g} s "
            "path; its coverage and hours are that part's") in res.stderr.splitlines()
