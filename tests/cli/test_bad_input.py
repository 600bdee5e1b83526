"""Hostile command lines: options nobody could mean, runs that blow up or mean nothing, and
names that carry markup or escape sequences."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from marinecdpr.cli.app import app

runner = CliRunner()
EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
BUILTIN = Path(__file__).resolve().parents[2] / "src" / "marinecdpr" / "scenario" / "builtin"


@pytest.mark.parametrize("args, message", [
    (["simulate", "--duration", "0"], "--duration 0: expected a positive number"),
    (["simulate", "--duration", "-2"], "--duration -2: expected a positive number"),
    (["simulate", "--duration", "nan"], "--duration nan: expected a finite number"),
    (["simulate", "--max-error", "inf"], "--max-error inf: expected a finite number"),
    (["simulate", "--max-error", "0"], "--max-error 0: expected a positive number"),
    (["workspace", "--step", "0"], "--step 0: expected a positive number"),
    (["workspace", "--duration", "0"], "--duration 0: expected a positive number"),
    (["workspace", "--fixed", "nan"], "--fixed nan: expected a finite number"),
    (["workspace", "--points", "0x3"], "--points 0x3: expected two positive integers like 30x20"),
])
def test_options_nobody_could_mean_are_one_line_exit_2(args, message, tmp_path):
    res = runner.invoke(app, args + ["--out", str(tmp_path / "o")])
    assert res.exit_code == 2, res.output
    assert res.stderr.strip().splitlines() == [f"error: {message}"]
    assert not (tmp_path / "o").exists()


def _variant(tmp_path: Path, base: Path, *edits: tuple[str, str]) -> Path:
    text = base.read_text()
    for old, new in edits:
        assert old in text, old
        text = text.replace(old, new)
    path = tmp_path / "variant.toml"
    path.write_text(text)
    return path


def test_a_run_that_blows_up_stops_with_exit_4_naming_run_and_time(tmp_path):
    """Load-cell noise of 10 kN on a tension-controlled winch: the closed loop blows up."""
    sc = _variant(tmp_path, BUILTIN / "paper_elastic.toml", ("tension_N = 1.0", "tension_N = 1e4"))
    res = runner.invoke(app, ["simulate", str(sc), "--duration", "3", "--out", str(tmp_path / "o")])
    assert res.exit_code == 4, res.output
    last = res.stderr.strip().splitlines()[-1]
    assert last.startswith("error: paper_elastic: ") and " diverged at t = " in last
    assert not (tmp_path / "o").exists()


def test_a_bounded_but_meaningless_closed_loop_fails(tmp_path):
    """A 400 Hz controller sampled at 1 kHz: its feedback asks for tensions outside the limits
    and the plan's are fed forward instead; the numbers look fine and mean nothing: a failed
    run (exit 5, issue 21 item 22), its files written with the verdict."""
    sc = _variant(tmp_path, EXAMPLES / "paper.toml", ("bandwidth_hz = 5.0", "bandwidth_hz = 400.0"))
    res = runner.invoke(app, ["simulate", str(sc), "--duration", "0.3", "--out", str(tmp_path / "o")])
    assert res.exit_code == 5, res.output
    s = json.loads((tmp_path / "o" / "summary.json").read_text())
    assert s["closed_loop"]["controller_fallbacks"] > 0.5 * s["steps"]
    assert s["closed_loop"]["controller_verdict"] == "bypassed" and s["runs_controller_bypassed"] == ["closed_loop"]
    assert any(w.startswith("closed_loop: the controller's bandwidth (400 Hz) is above 1/10 of the 1000 Hz "
                            "exchange") for w in s["warnings"])
    assert "warning: closed_loop: the controller's bandwidth (400 Hz)" in res.stderr
    assert res.stderr.strip().splitlines()[-1].startswith(
        f"error: closed_loop: the controller was bypassed at {s['closed_loop']['controller_fallbacks']} of 301 steps")
    html = (tmp_path / "o" / "report.html").read_text()
    assert "so the run shows the plan, not the controller" in html
    # the paper's own 5 Hz controller draws no warning
    ok = runner.invoke(app, ["simulate", "--duration", "0.3", "--out", str(tmp_path / "p")])
    assert ok.exit_code == 0 and "warning" not in ok.stderr
    assert json.loads((tmp_path / "p" / "summary.json").read_text())["warnings"] == []


@pytest.mark.parametrize("name", ["[/]", "[link=https://example.com]x[/link]", "[bold red]loud", r"$\foo$",
                                  "x\x1b[31mred\x1b[0m", "a$b"])
def test_names_are_plain_text_everywhere(name, tmp_path):
    # a 1 s job (the plan's 15 000 steps and its figure are not what this is about)
    text = (EXAMPLES / "paper.toml").read_text().replace('name = "paper"', f"name = {json.dumps(name)}")
    assert "duration_s = 15.0" in text
    text = text.replace("duration_s = 15.0", "duration_s = 1.0")
    sc = tmp_path / "named.toml"
    sc.write_text(text)
    res = runner.invoke(app, ["simulate", str(sc), "--duration", "0.1", "--out", str(tmp_path / "o")])
    assert res.exit_code == 0, res.output
    shown = name.replace("\x1b", "")
    assert f"simulate: {shown} (" in res.stdout.replace("\n", "")
    assert "\x1b" not in res.stdout and "\x1b" not in res.stderr
    html = (tmp_path / "o" / "report.html").read_text()
    assert "\x1b" not in html and "<link" not in html
    res = runner.invoke(app, ["check", str(sc)])
    assert res.exit_code == 0 and f"'{shown}'" in res.stdout
    res = runner.invoke(app, ["plan", str(sc), "--out", str(tmp_path / "p")])
    assert res.exit_code == 0 and f"plan: {shown} (" in res.stdout.replace("\n", "")


@pytest.mark.parametrize("args, message", [
    (["--headings", "nan"], "--headings nan: expected finite headings between -360 and 360 deg"),
    (["--headings", "inf"], "--headings inf: expected finite headings between -360 and 360 deg"),
    (["--headings", "180,180"], "--headings 180,180: a heading is given twice (headings are taken modulo 360 deg)"),
    (["--headings", "90,450"], "--headings 90,450: expected finite headings between -360 and 360 deg"),
    (["--step", "0"], "--step 0: expected a positive number"),
    (["--duration", "0"], "--duration 0: expected a positive number"),
    (["--margin", "nan"], "--margin nan: expected a finite number"),
    (["--margin", "-1"], "--margin -1: expected a non-negative number"),
    (["--scheduler", "garbage"], "--scheduler garbage: expected a Dask scheduler address like tcp://host:8786"),
    (["--scheduler", "tcp://127.0.0.1:1"],
     "--scheduler tcp://127.0.0.1:1: no Dask scheduler reachable there (connection refused)"),
])
def test_operability_options_nobody_could_mean(args, message, tmp_path, monkeypatch):
    import tripwire

    tripwire.arm(monkeypatch)  # refused before any work (not: within 5 s)
    res = runner.invoke(app, ["operability"] + args + ["--out", str(tmp_path / "o")])
    assert res.exit_code == 2, res.output
    assert res.stderr.strip().splitlines() == [f"error: {message}"]
    assert not (tmp_path / "o").exists()


def test_a_scheduler_that_does_not_answer_fails_within_seconds(monkeypatch):
    import socket

    from marinecdpr.studies.executor import Executor, ExecutorError

    def silent(address, timeout):
        assert timeout <= 5.0
        raise TimeoutError("timed out")

    monkeypatch.setattr(socket, "create_connection", silent)
    with pytest.raises(ExecutorError, match=r"--scheduler tcp://192\.0\.2\.1:8786: no Dask scheduler reachable "
                                            r"there \(no answer within 5 s\)"):
        Executor.at("tcp://192.0.2.1:8786")


def test_durations_read_as_a_clock_would():
    from marinecdpr.cli.progress import seconds as _seconds

    assert [_seconds(s) for s in (12.34, 59.94, 59.96, 119.6, 125.0, 3599.5)] == [
        "12.3 s", "59.9 s", "1 min 00 s", "2 min 00 s", "2 min 05 s", "60 min 00 s"]


# -------------------- formerly tests/test_issue21_usage.py

"""Issue 21's hostile-input sweep: the option parser's own errors (an integer given "abc", a
count below its minimum, an unknown option or command, a missing argument) are one
``error:`` line and exit 2, like every other bad input, not click's usage box; asking for
help still shows the help."""


import pytest
from typer.testing import CliRunner

from conftest import one_line_exit_2
from marinecdpr.cli.app import app

runner = CliRunner()


@pytest.mark.parametrize("argv,words", [
    (["operability", "--realisations", "0"], ["marinecdpr operability:", "'--realisations'", "greater than or equal to 1",
                                               "(see marinecdpr operability --help)"]),
    (["clean", "--workers", "0"], ["marinecdpr clean:", "'--workers'"]),
    (["operability", "--min-area", "2"], ["'--min-area'", "less than or equal to 1"]),
    (["latency", "--calls", "abc"], ["marinecdpr latency:", "'--calls'", "valid integer"]),
    (["plan", "--bogus"], ["marinecdpr plan:", "No such option: --bogus"]),
    (["bogus"], ["marinecdpr:", "No such command 'bogus' (see marinecdpr --help)"]),
    (["--bogus"], ["No such option: --bogus"]),
    (["check"], ["marinecdpr check:", "Missing argument 'scenario'"]),
])
def test_a_parser_error_is_one_line_exit_2(argv, words):
    res = runner.invoke(app, argv, prog_name="marinecdpr")
    line = one_line_exit_2(res, *words)
    assert "╭" not in res.output and "Usage:" not in res.stderr, line


def test_help_is_still_help():
    for argv in ([], ["--help"], ["plan", "--help"]):
        res = runner.invoke(app, argv, prog_name="marinecdpr")
        assert "Usage: marinecdpr" in res.stdout and "error:" not in res.stderr, argv


# -------------------- formerly tests/test_issue21_hostile_values.py

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

    from types import SimpleNamespace

    job = SimpleNamespace(panel_area_m2=2.0, missed_area_m2=0.5, job_time_s=100.0)
    est = ship_side(job, hull_area_m2=1e6, move_time_s=1e6)
    assert est["placements"] == 666667 and math.isfinite(est["hours"])
    with pytest.raises(ValueError, match="up to 1e\\+06"):
        ship_side(job, hull_area_m2=1e308, move_time_s=600.0)
    with pytest.raises(ValueError, match="cleaned nothing"):
        ship_side(SimpleNamespace(panel_area_m2=1e-310, missed_area_m2=0.0, job_time_s=1.0), hull_area_m2=1e6,
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


# -------------------- formerly tests/test_issue21_folders.py

"""Issue 21, item 13: a folder given where a file is expected is called a folder (``check``
said "no such file"), for every file a command takes."""

import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from marinecdpr.cli.app import app

runner = CliRunner()
EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


@pytest.mark.parametrize("args, message", [
    (["check", "{d}"], "error: {d}: a folder, not a file; expected a scenario file (.toml) or a built-in name"),
    (["plan", "{d}", "--out", "{o}"], "error: {d}: a folder, not a file; expected a scenario file (.toml) or a "
                                      "built-in name"),
    (["windows", "--duration-h", "2", "--operability", "{d}", "--out", "{o}"],
     "error: {d}: a folder, not a file; expected an operability.json"),
])
def test_a_folder_for_a_file_is_called_a_folder(args, message, tmp_path):
    d = tmp_path / "a_folder"
    d.mkdir()
    out = tmp_path / "o"
    res = runner.invoke(app, [a.format(d=d, o=out) for a in args], terminal_width=2000)
    assert res.exit_code == 2, res.output
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(message.format(d=d)), lines
    assert not out.exists()


def test_a_folder_for_the_rao_table_is_called_a_folder(tmp_path):
    (tmp_path / "rao.csv").mkdir()
    from marinecdpr.scenario.schema import _resolve_file

    class Info:
        context = {"base_dir": tmp_path}

    with pytest.raises(ValueError, match=f"a folder, not a file: {tmp_path / 'rao.csv'}"):
        _resolve_file("rao.csv", Info())


# -------------------- formerly tests/test_issue21_optimised.py

"""Issue 21, item 15: the command's input checks hold under ``python -O`` (they were
``assert`` statements, which -O removes: bad input ran on, or failed with a traceback)."""

import ast
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[2] / "src" / "marinecdpr"


UNDER_O = [
    (["workspace", "paper", "--points", "0x3"], "--points 0x3: expected two positive integers like 30x20"),
    (["workspace", "paper", "--points", "30x20x2"], "--points 30x20x2: expected two positive integers like 30x20"),
    (["operability", "paper_sea", "--workspace", "-1x4"], "--workspace -1x4: expected two positive integers like 12x8"),
    (["windows", "--duration-h", "2", "--hs-limit", "2", "--days", "1,-3"],
     "--days 1,-3: expected positive numbers separated by commas, e.g. 1,3,7"),
]


ASSERTS_GONE = "import sys; sys.stderr.write(f'debug={__debug__}\\n'); assert False, 'asserts are on'"
"""A child's set-up that fails unless the interpreter runs with -O."""


@pytest.fixture(scope="module")
def under_python_O(tmp_path_factory):
    """Each command line of UNDER_O as a process of its own under ``python -O`` (forked from
    one interpreter started with -O: one start and one import of the command line for all),
    and last ``--version`` after :data:`ASSERTS_GONE`: each one's output folder and (exit
    code, stdout, stderr)."""
    from forked import run_forked

    outs = [tmp_path_factory.mktemp("under_O") / "o" for _ in UNDER_O]
    runs = run_forked([("", [*args, "--out", str(out)]) for (args, _), out in zip(UNDER_O, outs)]
                      + [(ASSERTS_GONE, ["--version"])], flags=("-O",))
    return list(zip([*outs, None], runs, strict=True))


@pytest.mark.parametrize("case", range(len(UNDER_O)), ids=[" ".join(args) for args, _ in UNDER_O])
def test_bad_input_under_python_O_is_one_line_exit_2(case, under_python_O):
    message = UNDER_O[case][1]
    out, (code, _, err) = under_python_O[case]
    assert code == 2, err
    assert err.strip().splitlines() == [f"error: {message}"]
    assert not out.exists()


def test_the_commands_above_ran_under_python_O(under_python_O):
    """Their processes ran with the interpreter's -O: an assert in one's set-up did not stop
    it (``__debug__`` false), and the command after it ran."""
    _, (code, out, err) = under_python_O[-1]
    assert code == 0 and err == "debug=False\n", err
    assert out.startswith("marinecdpr ")


def test_no_assert_in_the_package():
    """asserts check nothing under -O: the package checks with if/raise (its validators)."""
    found = [f"{p.relative_to(SRC)}:{node.lineno}" for p in SRC.rglob("*.py")
             for node in ast.walk(ast.parse(p.read_text())) if isinstance(node, ast.Assert)]
    assert found == []
