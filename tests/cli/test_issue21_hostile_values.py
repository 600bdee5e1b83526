"""Issue 21, items 16, 18 and 15 (readers): bad values and files on the newer commands are one
line and exit 2, never a traceback; every JSON the package writes is strict (no NaN, no
Infinity); the scatter and sea-state readers take the same guards as the other CSV readers."""

import json
import math
import os

import numpy as np
import pytest
from typer.testing import CliRunner

from conftest import one_line_exit_2

from marinecdpr.cli.app import app
from marinecdpr.errors import ScenarioError
from marinecdpr.report.files import json_text, strict_json, write_json
from marinecdpr.studies.operability import read_scatter_csv
from marinecdpr.studies.weather import limit_from_operability, read_sea_state_series

runner = CliRunner()
SERIES = "time_h,hs_m,tp_s\n" + "".join(f"{i},{1.0 if i % 3 else 3.0},8\n" for i in range(12))


# ------------------------------------------------------------------ windows --operability
@pytest.mark.parametrize("limit, words", [
    ({"a": 1}, "limiting_hs_m.180.8: expected a limiting Hs: a finite number >= 0 m or null, got dict"),
    ([1, 2], "limiting_hs_m.180.8: expected a limiting Hs: a finite number >= 0 m or null, got list"),
    ("2", "got str"),
    (True, "got bool"),
    (-1.0, "got -1"),
])
def test_an_operability_limit_that_is_no_number_is_one_line(limit, words, tmp_path):
    series = tmp_path / "s.csv"
    series.write_text(SERIES)
    op = tmp_path / "operability.json"
    op.write_text(json.dumps({"limiting_hs_m": {"180": {"8": limit}}}))
    res = runner.invoke(app, ["windows", str(series), "--duration-h", "2", "--operability", str(op),
                              "--out", str(tmp_path / "o")])
    one_line_exit_2(res, str(op), words)
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("text, words", [
    ('{"limiting_hs_m": {"180": [1, 2]}}', "limiting_hs_m.180: expected an object of Tp (s)"),
    ('{"limiting_hs_m": [1]}', "limiting_hs_m: expected limiting_hs_m"),
    ('[1, 2]', "expected a JSON object with the key limiting_hs_m, got a list"),
    ('{"limiting_hs_m": {"180": {"8": NaN}}}', "NaN is not a JSON number"),
    ('{"limiting_hs_m": {"180": {"x": 2}}}', "the Tp 'x' is not a number of seconds"),
    ('{"limiting_hs_m": ', "line 1, column 19: not JSON"),
    ("[" * 100000 + "]" * 100000, "nested too deep"),
])
def test_an_operability_json_that_is_malformed_is_one_line(text, words, tmp_path):
    series = tmp_path / "s.csv"
    series.write_text(SERIES)
    op = tmp_path / "operability.json"
    op.write_text(text)
    res = runner.invoke(app, ["windows", str(series), "--duration-h", "2", "--operability", str(op),
                              "--out", str(tmp_path / "o")])
    one_line_exit_2(res, str(op), words)


def test_an_operability_json_that_is_a_folder_or_binary_is_one_line(tmp_path):
    series = tmp_path / "s.csv"
    series.write_text(SERIES)
    binary = tmp_path / "b.json"
    binary.write_bytes(b"\x00\x01\x02" * 10)
    for op, words in ((tmp_path, "a folder, not a file"), (binary, "a NUL byte")):
        res = runner.invoke(app, ["windows", str(series), "--duration-h", "2", "--operability", str(op),
                                  "--out", str(tmp_path / "o")])
        one_line_exit_2(res, words)


def test_the_limit_table_still_reads_by_hand():
    tp, hs = limit_from_operability({"limiting_hs_m": {"180": {"10": None, "6": 2}}}, 180.0)
    assert tp.tolist() == [6.0, 10.0] and hs[0] == 2.0 and math.isinf(hs[1])
    with pytest.raises(ScenarioError, match="a Tp appears twice"):
        limit_from_operability({"limiting_hs_m": {"180": {"8": 1.0, "8.0": 2.0}}}, 180.0)


# ------------------------------------------------------------------ CSV readers' guards
@pytest.mark.parametrize("reader, header, row", [
    (read_scatter_csv, "hs_m,tp_s,probability", "1.0,8.0,{}"),
    (read_sea_state_series, "time_h,hs_m,tp_s", "0,1.0,{}"),
])
def test_the_scatter_and_series_readers_take_the_guards(reader, header, row, tmp_path):
    huge = tmp_path / "huge.csv"
    huge.write_text(f"{header}\n{row.format('1' * 200_000)}\n")
    with pytest.raises(ScenarioError, match="row 2: longer than 10000 characters|line 2: longer than 10000"):
        reader(huge)
    long = tmp_path / "long.csv"
    long.write_text(f"{header}\n{row.format('1' * 500)}\n")
    with pytest.raises(ScenarioError, match="field 3: over 100 characters"):
        reader(long)
    with pytest.raises(ScenarioError, match="a folder, not a file"):
        reader(tmp_path)
    binary = tmp_path / "bin.csv"
    binary.write_bytes(b"\x89PNG\r\n\x1a\n\x00\x00")
    with pytest.raises(ScenarioError, match="a control character|a NUL byte"):
        reader(binary)
    if hasattr(os, "mkfifo"):  # a pipe nobody writes: refused at once, not read for ever
        fifo = tmp_path / "fifo.csv"
        os.mkfifo(fifo)
        with pytest.raises(ScenarioError, match="not a regular file"):
            reader(fifo)


def test_the_readers_still_take_bom_and_crlf(tmp_path):
    scatter = tmp_path / "scatter.csv"
    scatter.write_bytes(b"\xef\xbb\xbfhs_m,tp_s,probability\r\n1.0,8.0,0.25\r\n2.0,9.0,0.75\r\n")
    d = read_scatter_csv(scatter)
    assert d.hs.tolist() == [1.0, 2.0] and d.probability.sum() == pytest.approx(1.0)
    series = tmp_path / "series.csv"
    series.write_bytes(b"\xef\xbb\xbf" + SERIES.replace("\n", "\r\n").encode())
    assert read_sea_state_series(series).t_h.size == 12


def test_a_scatter_of_huge_probabilities_is_refused_in_one_line(tmp_path):
    scatter = tmp_path / "scatter.csv"
    scatter.write_text("hs_m,tp_s,probability\n1.0,8.0,1e308\n2.0,9.0,1e308\n")
    with pytest.raises(ScenarioError, match=r"row 2: probability = 1e308 \(column 3\) is not a probability"):
        read_scatter_csv(scatter)
    res = runner.invoke(app, ["operability", "--scatter", str(scatter), "--out", str(tmp_path / "o")])
    one_line_exit_2(res, "is not a probability")
    # a per mille table is still named for what it is
    mille = tmp_path / "mille.csv"
    mille.write_text("hs_m,tp_s,probability\n1.0,8.0,400\n2.0,9.0,600\n")
    with pytest.raises(ScenarioError, match="per mille"):
        read_scatter_csv(mille)


# ------------------------------------------------------------------ non-finite results
@pytest.mark.parametrize("times", [(-1e308, 1e308), (0.0, 1e308)])
def test_a_series_of_absurd_times_is_refused_not_written_as_inf(times, tmp_path):
    series = tmp_path / "s.csv"
    series.write_text(f"time_h,hs_m,tp_s\n{times[0]},1.0,8\n{times[1]},1.0,8\n")
    res = runner.invoke(app, ["windows", str(series), "--duration-h", "2", "--hs-limit", "2",
                              "--out", str(tmp_path / "o")])
    one_line_exit_2(res, "time_h: ", "h is outside -1e+07 .. 1e+07 h")
    assert not (tmp_path / "o").exists()


def test_windows_writes_strict_json(tmp_path):
    series = tmp_path / "s.csv"
    series.write_text("time_h,hs_m,tp_s\n0,3.0,8\n1,3.0,8\n")  # never workable: the mean wait is undefined
    res = runner.invoke(app, ["windows", str(series), "--duration-h", "2", "--hs-limit", "2",
                              "--out", str(tmp_path / "o")])
    assert res.exit_code == 0, res.output
    text = (tmp_path / "o" / "summary.json").read_text()
    s = json.loads(text, parse_constant=lambda c: pytest.fail(f"{c} in summary.json"))
    assert s["mean_wait_h"] is None and s["windows"] == 0


def test_every_json_written_is_strict():
    data = {"a": float("nan"), "b": [1.0, float("inf"), np.float64(-np.inf)], "c": np.array([0.5, np.nan]),
            "d": (np.int64(3), np.float32(2.5)), 4: "x"}
    assert strict_json(data) == {"a": None, "b": [1.0, None, None], "c": [0.5, None], "d": [3, 2.5], "4": "x"}
    text = json_text(data)
    assert "NaN" not in text and "Infinity" not in text
    json.loads(text, parse_constant=lambda c: pytest.fail(c))


def test_write_json_writes_null_for_undefined(tmp_path):
    path = write_json({"headroom_N": float("nan"), "rms": 1.5}, tmp_path / "s.json")
    assert json.loads(path.read_text()) == {"headroom_N": None, "rms": 1.5}


def test_an_operation_that_never_starts_is_never_done_however_many_days():
    from marinecdpr.studies.weather import SeaStateSeries, weather_windows

    s = SeaStateSeries(np.arange(4.0), np.array([1.0, 3.0, 1.0, 1.0]), np.full(4, 8.0))
    w = weather_windows(s, duration_h=1e308, hs_limit_m=2.0)
    assert w.can_start == 0.0
    assert w.finish_probability(1e308) == 0.0 and w.finish_probability(math.inf) == 0.0
    # a 2 h operation starts from t = 0 (wait 2 h) .. 2; from 3 it cannot: done within ever, 3 of 4
    w2 = weather_windows(s, duration_h=2.0, hs_limit_m=2.0)
    assert w2.finish_probability(1e308) == 0.75 and w2.finish_probability(3 / 24) == 0.5


@pytest.mark.parametrize("args, words", [
    (["--hull-area", "1e308"], "--hull-area 1e+308 / --move-time 600: hull_area_m2 must be a positive number of m2 "
                               "up to 1e+06"),
    (["--hull-area", "100", "--move-time", "1e300"], "move_time_s must be a number of seconds from 0 to 1e+06"),
    (["--seas", "--hull-area", "1e9"], "hull_area_m2 must be a positive number of m2 up to 1e+06"),
])
def test_a_hull_estimate_that_would_mean_nothing_is_refused_before_the_job(args, words, tmp_path):
    res = runner.invoke(app, ["clean", *args, "--out", str(tmp_path / "o")])
    one_line_exit_2(res, words)


def test_ship_side_never_overflows():
    from marinecdpr.studies.cleaning import ship_side

    job = {"panel_area_m2": 2.0, "missed_area_m2": 0.5, "job_time_s": 100.0}
    est = ship_side(job, hull_area_m2=1e6, move_time_s=1e6)
    assert est["placements"] == 666667 and math.isfinite(est["hours"])
    with pytest.raises(ValueError, match="up to 1e\\+06"):
        ship_side(job, hull_area_m2=1e308, move_time_s=600.0)
    with pytest.raises(ValueError, match="cleaned nothing"):
        ship_side({"panel_area_m2": 1e-310, "missed_area_m2": 0.0, "job_time_s": 1.0}, hull_area_m2=1e6,
                  move_time_s=0.0)


def test_a_prediction_study_with_too_few_samples_is_undefined_not_nan_in_json():
    """control-study --rate 0.5 on a 12 s run: no forecast after the settling lands in the
    record; the errors are undefined: NaN in the arrays (no 0/0 warning), null in the JSON."""
    import warnings

    from marinecdpr.scenario.loading import load_scenario
    from marinecdpr.studies.control import ship_prediction_error, worst_moving_dof

    sc = load_scenario("paper_sea")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        p = ship_prediction_error(sc, rate_hz=0.5, duration_s=12.0, settle_s=11.0)
    assert p.n_evaluated.tolist() == [0] * p.horizons_s.size
    assert np.isnan(p.model_share).all() and np.isnan(p.predictor).all()
    text = json_text({"model_share": p.model_share, "predictor": worst_moving_dof(p, p.predictor)})
    assert json.loads(text) == {"model_share": [None] * p.horizons_s.size, "predictor": [None] * p.horizons_s.size}
