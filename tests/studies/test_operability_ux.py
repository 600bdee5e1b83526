"""The operability command's surprises (issue 8 item 7): which executor runs, "none within
the diagram", scatter files that are not probabilities, and the workspace example."""

import json
import re
import sys
from importlib import resources

import numpy as np
import pytest
from typer.testing import CliRunner

import marinecdpr
from marinecdpr import ScenarioError
from marinecdpr.cli.app import app
from marinecdpr.studies.operability import AUTO_DASK_MIN_STEPS, Cell, CellResult, ScatterDiagram, summarise, choose_executor, operability, read_scatter_csv, study_steps
from marinecdpr.studies.workspace import pose_range, workspace_map

runner = CliRunner()
FAST = ["--duration", "10", "--step", "0.1"]


def _scatter(tmp_path, text, name="scatter.csv"):
    path = tmp_path / name
    path.write_text(text)
    return path


def _no_dask(monkeypatch):
    """Make ``import dask.distributed`` fail, as on a machine without the [dask] extra."""
    monkeypatch.setitem(sys.modules, "dask.distributed", None)


# --- which executor ------------------------------------------------------------------------

def test_auto_runs_serially_and_says_so_when_dask_is_missing(monkeypatch, tmp_path):
    _no_dask(monkeypatch)
    assert choose_executor("auto", 10 * AUTO_DASK_MIN_STEPS) == ("serial", "no dask")
    scatter = _scatter(tmp_path, "hs_m,tp_s,probability\n0.5,7,0.7\n1.5,9,0.3\n")
    res = runner.invoke(app, ["operability", "--scatter", str(scatter), *FAST, "--out", str(tmp_path / "o")])
    assert res.exit_code == 0, res.output
    notes = [line for line in res.stderr.splitlines() if "Dask" in line]
    assert notes == ["note: running the sea states serially: Dask is not installed "
                     "(pip install 'marinecdpr[dask]' to run them in parallel)"]
    assert "serial" in res.stdout
    assert json.loads((tmp_path / "o" / "operability.json").read_text())["cells"] == 2
    # asking for Dask without it is one line, exit 2
    bad = runner.invoke(app, ["operability", "--scatter", str(scatter), *FAST, "--workers", "2",
                              "--out", str(tmp_path / "p")])
    assert bad.exit_code == 2
    assert bad.stderr.strip().count("\n") == 0 and "pip install 'marinecdpr[dask]'" in bad.stderr


def test_auto_is_serial_below_the_measured_crossover():
    default = study_steps(34, duration_s=1200.0, step_s=0.02)          # the default study
    assert default == 34 * 60001
    assert choose_executor("auto", default) == ("serial", "small")
    assert choose_executor("auto", AUTO_DASK_MIN_STEPS - 1) == ("serial", "small")
    assert choose_executor("auto", AUTO_DASK_MIN_STEPS) == ("dask", "large")
    assert choose_executor("auto", 10, scheduler="tcp://127.0.0.1:8786") == ("dask", "scheduler")
    assert choose_executor("serial", 10 ** 12) == ("serial", "asked")
    assert choose_executor("dask", 10) == ("dask", "asked")
    # a workspace grid's poses and a closed-loop flight (~100 planned steps a step) count as work
    assert study_steps(2, duration_s=60.0, step_s=0.02, workspace=(12, 8)) == 2 * 3001 * 96
    assert study_steps(2, duration_s=60.0, step_s=0.02, max_error_m=0.01) == 2 * 3001 * 101
    assert choose_executor("auto", study_steps(34, duration_s=1200.0, step_s=0.02, max_error_m=0.01))[0] == "dask"
    with pytest.raises(ValueError, match="'auto', 'serial' or 'dask'"):
        choose_executor("threads", 10)


def test_serial_and_dask_options_conflict(tmp_path):
    res = runner.invoke(app, ["operability", "--serial", "--workers", "3", *FAST, "--out", str(tmp_path / "o")])
    assert res.exit_code == 2
    assert res.stderr.strip().count("\n") == 0 and "--serial cannot go with --workers" in res.stderr


def test_every_executor_gives_the_same_files(tmp_path):
    """auto (serial here), --serial and --workers 2 (Dask): the same CSV and JSON, byte for byte."""
    scatter = _scatter(tmp_path, "hs_m,tp_s,probability\n0.5,7,0.5\n4.5,9,0.5\n")
    out = {}
    for name, extra in (("auto", []), ("serial", ["--serial"]), ("dask", ["--workers", "2"])):
        res = runner.invoke(app, ["operability", "--scatter", str(scatter), "--headings", "180,90", *FAST,
                                  *extra, "--out", str(tmp_path / name)])
        assert res.exit_code == 0, res.output
        assert ("Dask, 2 workers" in res.stdout) == (name == "dask")
        out[name] = [(tmp_path / name / f).read_bytes() for f in ("operability.csv", "operability.json")]
    assert out["auto"] == out["serial"] == out["dask"]


# --- limiting Hs and percentages ------------------------------------------------------------

def _result(index, hs, tp, ok, p):
    return CellResult(Cell(index, hs, tp, 180.0, p), ok, float(ok), 0.0, 10, successes=int(ok))


def test_limiting_hs_none_within_the_diagram_is_not_the_top_row():
    hs, tp = np.array([1.0, 2.0, 3.0]), np.array([6.0, 8.0, 10.0, 12.0])
    prob = np.array([[0.1, 0.1, 0.1, 0.0], [0.1, 0.1, 0.1, 0.0], [0.1, 0.2, 0.1, 0.0]])
    results = [_result(0, 1.0, 6.0, True, 0.1), _result(1, 1.0, 8.0, True, 0.1), _result(2, 1.0, 10.0, False, 0.1),
               _result(3, 2.0, 6.0, True, 0.1), _result(4, 2.0, 8.0, True, 0.1), _result(5, 2.0, 10.0, False, 0.1),
               _result(6, 3.0, 6.0, True, 0.1), _result(7, 3.0, 8.0, False, 0.2), _result(8, 3.0, 10.0, False, 0.1)]
    op = summarise(ScatterDiagram(hs, tp, prob), (180.0,), results, 0.0)
    lim = op.limiting_hs[180.0]
    assert lim[0] == np.inf            # Tp 6: all three workable, no limit within the diagram (was 3.0)
    assert lim[1] == 2.0               # Tp 8: fails at 3 m
    assert lim[2] == 0.0               # Tp 10: not even 1 m
    assert np.isnan(lim[3])            # Tp 12: no sea state
    assert op.limiting_hs_json() == {"180": {"6": None, "8": 2.0, "10": 0.0}}
    assert op.operability == pytest.approx(0.5)


def test_operability_is_exact_when_everything_works():
    """The default diagram's 34 probabilities sum to 0.9999999999999999 in floating point;
    all workable is 1, written as 1.0 and shown as 100 %."""
    default = read_scatter_csv(str(resources.files("marinecdpr") / "data" / "scatter_illustrative.csv"))
    op = operability(marinecdpr.load_scenario("paper_sea"), default, duration_s=5.0, step_s=0.1)
    assert sum(r.cell.probability for r in op.results) != 1.0      # the float sum is not exact...
    assert op.operability == 1.0 and op.per_heading[180.0] == 1.0   # ...the operability is


def test_terminal_and_json_say_none_within_the_diagram(tmp_path):
    scatter = _scatter(tmp_path, "hs_m,tp_s,probability\n0.5,7,0.7\n1.5,9,0.3\n")
    res = runner.invoke(app, ["operability", "--scatter", str(scatter), "--serial", *FAST,
                              "--out", str(tmp_path / "o")])
    assert res.exit_code == 0, res.output
    assert res.stdout.count("none within the diagram") >= 2     # one per Tp column, plus the legend
    assert "100 %" in res.stdout and "100.0" not in res.stdout and "0.9999" not in res.stdout
    s = json.loads((tmp_path / "o" / "operability.json").read_text())
    assert s["limiting_hs_m"] == {"180": {"7": None, "9": None}}
    assert "null: none within the diagram" in s["limiting_hs_meaning"]
    assert s["operability"] == 1.0


# --- scatter files ----------------------------------------------------------------------------

@pytest.mark.parametrize("rows, message", [
    ("0.5,6,0.6\n1.5,6,0.5\n", "the probabilities (column 3) sum to 1.1, not 1 (within 0.001)"),
    ("0.5,6,60\n1.5,6,40\n", "sum to 100, not 1 (within 0.001); they look like percent: divide them by 100"),
    ("0.5,6,600\n1.5,6,401\n", "sum to 1001, not 1 (within 0.001); they look like per mille: divide them by 1000"),
    ("0.5,6,0.5\n1000,6,0.5\n", "row 3: hs_m and tp_s must be positive and physical: hs_m = 1000 (column 1) "
                                "is outside 0 < Hs <= 30 m"),
    ("0.5,0.5,0.5\n1,6,0.5\n", "row 2: hs_m and tp_s must be positive and physical: tp_s = 0.5 (column 2) "
                               "is outside 1 s <= Tp <= 30 s"),
    ("0.5,6,0.5\n1,45,0.5\n", "tp_s = 45 (column 2) is outside 1 s <= Tp <= 30 s"),
    ("nan,6,0.5\n1,6,0.5\n", "row 2: hs_m and tp_s must be positive and physical: hs_m = nan (column 1)"),
    ("0.5,6,inf\n1,6,0.5\n", "row 2: probability = inf (column 3) must be finite and non-negative"),
    ("0.5,6,-0.1\n1,6,1.1\n", "row 2: probability = -0.1 (column 3) must be finite and non-negative"),
])
def test_scatter_files_that_are_not_probabilities_are_refused(tmp_path, rows, message):
    path = _scatter(tmp_path, "hs_m,tp_s,probability\n" + rows)
    with pytest.raises(ScenarioError, match=re.escape(f"{path}: ") + ".*" + re.escape(message)):
        read_scatter_csv(path)


def test_scatter_errors_are_one_line_exit_2(tmp_path):
    for rows, words in (("0.5,6,0.6\n1.5,6,0.5\n", "sum to 1.1"), ("0.5,6,0.5\n1000,6,0.5\n", "hs_m = 1000")):
        path = _scatter(tmp_path, "hs_m,tp_s,probability\n" + rows)
        res = runner.invoke(app, ["operability", "--scatter", str(path), "--serial", *FAST,
                                  "--out", str(tmp_path / "o")])
        assert res.exit_code == 2
        assert res.stderr.strip().count("\n") == 0
        assert str(path) in res.stderr and words in res.stderr
        assert not (tmp_path / "o" / "operability.json").exists()


def test_scatter_from_a_spreadsheet_bom_and_crlf(tmp_path):
    path = tmp_path / "excel.csv"
    path.write_bytes(b"\xef\xbb\xbfhs_m,tp_s,probability\r\n0.5,6,0.25\r\n1.5,6,0.5\r\n1.5,8,0.2495\r\n\r\n")
    d = read_scatter_csv(path)
    np.testing.assert_array_equal(d.hs, [0.5, 1.5])
    np.testing.assert_array_equal(d.tp, [6.0, 8.0])
    # 0.9995 is within 1e-3 of 1: accepted, rescaled to sum to 1
    np.testing.assert_allclose(d.probability, np.array([[0.25, 0.0], [0.5, 0.2495]]) / 0.9995, rtol=1e-12)
    assert d.probability.sum() == pytest.approx(1.0, abs=1e-15)


# --- the workspace example --------------------------------------------------------------------

def test_the_workspace_grid_is_where_the_platform_fits():
    """The grid spans where the platform's centre can be with its anchors in the frame, so in
    calm water every pose of the README's 12x8 grid is held (before: 28 of 96 never were)."""
    sc = marinecdpr.load_scenario("paper_sea").with_changes(
        base_motion={"type": "still"}, time={"step_s": 0.1, "duration_s": 0.2})
    lo, hi = pose_range(sc)
    np.testing.assert_allclose(lo[[0, 2]], [0.125, 0.15])
    np.testing.assert_allclose(hi[[0, 2]], [1.9 - 0.125, 1.4 - 0.15])
    ws = workspace_map(sc, n=(12, 8))
    assert ws.u[0] > 0.125 and ws.u[-1] < 1.775 and ws.v[0] > 0.15 and ws.v[-1] < 1.25
    assert np.all(ws.fraction_feasible == 1.0)


def test_the_readme_workspace_example_gives_a_real_answer(tmp_path):
    """The README's --workspace 12x8 --min-area 1 on a short record: calm seas keep the whole
    frame, a rough one loses its corners; neither 0 % nor 100 %."""
    scatter = _scatter(tmp_path, "hs_m,tp_s,probability\n0.5,8,0.6\n6.5,10,0.4\n")
    res = runner.invoke(app, ["operability", "--scatter", str(scatter), "--workspace", "12x8", "--min-area", "1",
                              "--duration", "60", "--step", "0.05", "--out", str(tmp_path / "o")])
    assert res.exit_code == 0, res.output
    s = json.loads((tmp_path / "o" / "operability.json").read_text())
    assert s["operability"] == pytest.approx(0.6)
    assert s["limiting_hs_m"]["180"] == {"8": None, "10": 0.0}
    assert "60.0 %" in res.stdout
