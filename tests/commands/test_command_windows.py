"""The windows command's contract in the library (:mod:`marinecdpr.commands.windows`): its
spec checked without the command line, its inputs read by the estimate, the command line's
defaults the spec's, a run from Python giving the command's files byte for byte, and
docs/commands/windows.md run as written (issue 38, items 1 and 7)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from marinecdpr.cli.app import app
from marinecdpr.commands import SpecError
from marinecdpr.commands import windows as command
from marinecdpr.commands.windows import WindowsSpec
from marinecdpr.errors import ScenarioError

from command_pages import assert_table_is_the_spec, cli_default, options_table, page, run_page

runner = CliRunner()
HS = [1.0, 1.0, 3.0, 1.0, 1.0, 1.0, 3.0, 3.0, 1.0, 1.0]  # hourly; under 2 m at 0-2, 3-6, 8-10 h
WIND = [5.0, 12.0, 20.0, 8.0, 15.0, 10.0, 14.0, 3.0, 9.0, 11.0]  # m/s; over 12 m/s at 4 h within the Hs window 3-6 h


@pytest.fixture()
def series(tmp_path) -> Path:
    path = tmp_path / "s.csv"
    path.write_text("time_h,hs_m,tp_s\n" + "".join(f"{i},{h},8\n" for i, h in enumerate(HS)))
    return path


@pytest.mark.parametrize("options, field, words", [
    ({"duration_h": 0.0, "hs_limit": 2.0}, "duration_h", "duration_h 0: expected a positive number"),
    ({"duration_h": 2.0, "hs_limit": -2.0}, "hs_limit", "hs_limit -2: expected a positive number"),
    ({"duration_h": 2.0, "hs_limit": 2.0, "heading": float("inf")}, "heading", "heading inf: expected a finite number"),
    ({"duration_h": 2.0, "hs_limit": 2.0, "alpha": 1.5}, "alpha", "alpha 1.5: expected a factor in (0, 1]"),
    ({"duration_h": 2.0, "hs_limit": 2.0, "alpha": 0.0}, "alpha", "expected a factor in (0, 1]"),
    ({"duration_h": 2.0, "hs_limit": 2.0, "days": "1,-3"}, "days",
     "days 1,-3: expected positive numbers separated by commas, e.g. 1,3,7"),
    ({"duration_h": 2.0, "hs_limit": 2.0, "days": "x"}, "days", "days x: expected positive numbers"),
    ({"duration_h": 2.0}, "hs_limit", "hs_limit or --operability: give one design limit"),
    ({"duration_h": 2.0, "hs_limit": 2.0, "operability": "op.json"}, "hs_limit",
     "hs_limit 2 with --operability op.json: give one design limit: --hs-limit H or --operability FILE.json, not both"),
    ({"hs_limit": 2.0}, "duration_h", "duration_h not given: the option is required"),
    ({"duration_h": 2.0, "hs_limit": 2.0, "wind_limit": 0.0}, "wind_limit", "wind_limit 0: expected a positive number"),
    ({"duration_h": 2.0, "hs_limit": 2.0, "wind_limit": -12.0}, "wind_limit",
     "wind_limit -12: expected a positive number"),
    ({"duration_h": 2.0, "hs_limit": 2.0, "wind_limit": float("inf")}, "wind_limit",
     "wind_limit inf: expected a finite number"),
    ({"duration_h": 2.0, "hs_limit": 2.0, "wind_limit": float("nan")}, "wind_limit",
     "wind_limit nan: expected a finite number"),
])
def test_a_bad_option_is_one_error_naming_its_field(options, field, words):
    with pytest.raises(SpecError) as err:
        WindowsSpec(**options)
    assert err.value.field == field and err.value.flag == "--" + field.replace("_", "-")
    assert words in str(err.value) and "\n" not in str(err.value)


def test_the_command_line_s_defaults_are_the_spec_s():
    """Every option of ``windows`` but the series and --out has the spec's field and default
    (--duration-h has none: it is required in both)."""
    import typer.main

    params = {p.name: p for p in typer.main.get_command(app).commands["windows"].params}
    options = set(params) - {"series", "out"}
    assert options == set(WindowsSpec.model_fields)
    assert params["duration_h"].required and WindowsSpec.model_fields["duration_h"].is_required()
    for name in options - {"duration_h"}:
        default = cli_default(params[name])
        spec_default = WindowsSpec.default(name)
        given = {"duration_h": 1.0, "hs_limit": 1.0} if name != "hs_limit" else {"duration_h": 1.0,
                                                                                   "operability": "x.json"}
        assert (WindowsSpec(**given, **{name: default}).model_dump()[name] if default is not None else None) \
            == spec_default


def test_the_command_line_names_the_flag_of_a_bad_spec_field(tmp_path):
    from conftest import one_line_exit_2

    res = runner.invoke(app, ["windows", "--duration-h", "2", "--alpha", "1.5", "--out", str(tmp_path / "o")],
                        terminal_width=4000)
    assert one_line_exit_2(res) == "error: --alpha 1.5: expected a factor in (0, 1]"
    res = runner.invoke(app, ["windows", "--duration-h", "2", "--out", str(tmp_path / "o")], terminal_width=4000)
    assert one_line_exit_2(res) == ("error: --hs-limit or --operability: give one design limit: --hs-limit H or "
                                    "--operability FILE.json")
    assert not (tmp_path / "o").exists()


def test_the_estimate_reads_the_series_and_the_limits_at_the_heading(series, tmp_path):
    op = tmp_path / "operability.json"
    op.write_text(json.dumps({"limiting_hs_m": {"180": {"6": 1.5, "8": 2.0}, "90": {"8": 0.5}}}))
    est = command.estimate(WindowsSpec(duration_h=2.0, operability=op), series)
    assert est.series_name == str(series) and est.series.hs_m.tolist() == HS
    np.testing.assert_array_equal(est.table[0], [6.0, 8.0])
    np.testing.assert_array_equal(est.table[1], [1.5, 2.0])
    np.testing.assert_array_equal(command.estimate(WindowsSpec(duration_h=2.0, operability=op, heading=90.0),
                                                   series).table[1], [0.5])
    with pytest.raises(ScenarioError, match="a folder, not a file"):
        command.estimate(WindowsSpec(duration_h=2.0, operability=tmp_path), series)
    with pytest.raises(ScenarioError) as err:
        command.estimate(WindowsSpec(duration_h=2.0, operability=op, heading=150.0), series)
    assert str(op) in str(err.value)
    assert "illustrative" in command.estimate(WindowsSpec(duration_h=2.0, hs_limit=2.0)).series_name


@pytest.mark.figures
def test_a_run_from_python_writes_what_the_command_writes(series, tmp_path):
    """Windows by hand: under 2 m at 0-2, 3-6 and 8-10 h, all at least 2 h long; from each
    hourly start the wait is 0, 2, 1, 0, 0, 3, 2, 1, 0 h and none from 9 h (8-10 h ends with
    the series): 9 of 10 start, a mean wait of 9/9 h; within 0.125 d (3 h: a wait of at most
    1 h) 6 of 10 finish, within a day 9 of 10."""
    spec = WindowsSpec(duration_h=2.0, hs_limit=2.0, days="0.125,1")
    result = command.run(spec, series)
    w = result.windows
    assert w.windows == [(0.0, 2.0), (3.0, 6.0), (8.0, 10.0)]
    np.testing.assert_array_equal(w.wait_h[:9], [0, 2, 1, 0, 0, 3, 2, 1, 0])
    assert np.isnan(w.wait_h[9]) and w.can_start == 0.9 and w.mean_wait_h == pytest.approx(1.0)
    assert result.finish_probability() == {0.125: pytest.approx(0.6), 1.0: pytest.approx(0.9)}
    s = result.summary()
    assert s["windows_long_enough"] == 3 and s["design_limit"] == "Hs 2 m" and s["workable_share"] == 0.7
    assert [p.name for p in result.write(tmp_path / "py")] == ["windows.csv", "summary.json", "windows.png"]
    res = runner.invoke(app, ["windows", str(series), "--duration-h", "2", "--hs-limit", "2", "--days", "0.125,1",
                              "--out", str(tmp_path / "cli")])
    assert res.exit_code == 0, res.output
    for name in ("windows.csv", "summary.json"):
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), name
    assert json.loads((tmp_path / "py" / "summary.json").read_text()) == json.loads(json.dumps(s))


@pytest.mark.figures
def test_the_page_lists_the_spec_s_options_and_defaults():
    """Every option but the required --duration-h with its default; that one said required."""
    assert set(options_table("windows")) == set(WindowsSpec.model_fields) - {"duration_h"}
    for field, default in options_table("windows").items():
        assert default == WindowsSpec.default(field), field
    assert "| `--duration-h` | required | h |" in page("windows")


def test_the_page_runs_as_written(tmp_path, monkeypatch):
    ns = run_page("windows", tmp_path, monkeypatch)
    result = ns["result"]
    sea = result.series
    # each window is a run of samples under 0.8 x 2.5 m, bounded by samples over it
    for a, b in ns["w"].windows:
        inside = (sea.t_h >= a) & (sea.t_h < b)
        assert np.all(sea.hs_m[inside] <= 2.0) and inside.any()
    s = json.loads((tmp_path / "out" / "windows" / "summary.json").read_text())
    assert s["windows_long_enough"] == len(ns["long_enough"]) and s["alpha"] == 0.8
    assert s["finish_within_days_probability"] == {f"{d:g}": p for d, p in ns["finish"].items()}
    finish = list(ns["finish"].values())
    assert finish == sorted(finish) and 0.0 < finish[-1] <= 1.0  # more days, no less likely


# ------------------------------------------------------------------ the wind (issue 40, item 1)
@pytest.fixture()
def windy(tmp_path) -> Path:
    path = tmp_path / "windy.csv"
    path.write_text("time_h,hs_m,tp_s,wind_m_s\n" + "".join(f"{i},{h},8,{u}\n" for i, (h, u) in
                                                            enumerate(zip(HS, WIND))))
    return path


@pytest.mark.figures
def test_a_wind_limit_closes_a_window_in_the_files_and_the_line(windy, tmp_path):
    """By hand: under Hs 2 m and 12 m/s the samples at 0, 1, 3, 5, 8, 9 h are workable (the
    wind, 15 m/s, closes 4 h): windows 0-2, 3-4, 5-6, 8-10, of them 0-2 and 8-10 fit 2 h.
    From t = 0..8 the waits are 0, 7, 6, 5, 4, 3, 2, 1, 0 h (mean 28/9 h), none from 9 h;
    done within 3 h (a wait of at most 1 h) from 0, 7, 8 h: 3 of 10, within a day 9 of 10;
    workable 60 % of the time, 70 % by Hs alone."""
    spec = WindowsSpec(duration_h=2.0, hs_limit=2.0, days="0.125,1", wind_limit=12.0)
    result = command.run(spec, windy)
    w = result.windows
    assert w.windows == [(0.0, 2.0), (3.0, 4.0), (5.0, 6.0), (8.0, 10.0)]
    np.testing.assert_array_equal(w.wait_h[:9], [0, 7, 6, 5, 4, 3, 2, 1, 0])
    assert np.isnan(w.wait_h[9]) and w.mean_wait_h == pytest.approx(28 / 9)
    assert result.finish_probability() == {0.125: pytest.approx(0.3), 1.0: pytest.approx(0.9)}
    assert [p.name for p in result.write(tmp_path / "py")] == ["windows.csv", "summary.json", "windows.png"]
    out = tmp_path / "cli"
    res = runner.invoke(app, ["windows", str(windy), "--duration-h", "2", "--hs-limit", "2", "--days", "0.125,1",
                              "--wind-limit", "12", "--out", str(out)], terminal_width=4000)
    assert res.exit_code == 0, res.output
    for name in ("windows.csv", "summary.json"):
        assert (tmp_path / "py" / name).read_bytes() == (out / name).read_bytes(), name
    rows = np.genfromtxt(out / "windows.csv", delimiter=",", names=True)
    assert rows["start_h"].tolist() == [0.0, 3.0, 5.0, 8.0] and rows["long_enough"].tolist() == [1, 0, 0, 1]
    s = json.loads((out / "summary.json").read_text())
    assert s["wind_limit_m_s"] == 12.0 and s["design_limit"] == "Hs 2 m"
    assert s["workable_share"] == pytest.approx(0.6) and s["workable_share_hs_alone"] == pytest.approx(0.7)
    assert s["windows"] == 4 and s["windows_long_enough"] == 2 and s["mean_wait_h"] == pytest.approx(28 / 9)
    assert s["finish_within_days_probability"] == {"0.125": pytest.approx(0.3), "1": pytest.approx(0.9)}
    line = res.output.strip().splitlines()[-1]
    assert line.startswith("4 windows with Hs within its limit and the wind within 12 m/s (workable 60.0 % of "
                           "the time, 70.0 % by Hs alone), 2 of them 2 h or longer; wait before the operation can "
                           "start: 3.1 h on average"), line
    assert "done within 0.125 days: 30.0 %, 1 day: 90.0 %" in line


def test_without_a_wind_limit_a_series_with_the_wind_gives_the_hs_only_answer(series, windy, tmp_path):
    """The windy series without --wind-limit: windows.csv byte for byte and every number of
    summary.json the Hs-only series' (0-2, 3-6, 8-10 h, mean wait 1 h, 0.6 and 0.9 done); the
    summary says the wind limit is null, the line that the wind is not judged."""
    args = ["--duration-h", "2", "--hs-limit", "2", "--days", "0.125,1"]
    res_hs = runner.invoke(app, ["windows", str(series), *args, "--out", str(tmp_path / "hs")], terminal_width=4000)
    res_wind = runner.invoke(app, ["windows", str(windy), *args, "--out", str(tmp_path / "w")], terminal_width=4000)
    assert res_hs.exit_code == 0 and res_wind.exit_code == 0, res_wind.output
    assert (tmp_path / "hs" / "windows.csv").read_bytes() == (tmp_path / "w" / "windows.csv").read_bytes()
    hs, wind = (json.loads((tmp_path / d / "summary.json").read_text()) for d in ("hs", "w"))
    assert "wind_limit_m_s" not in hs and wind.pop("wind_limit_m_s") is None
    assert "workable_share_hs_alone" not in wind
    for key in set(hs) - {"series", "meaning"}:
        assert wind[key] == hs[key], key
    assert hs["mean_wait_h"] == pytest.approx(1.0) and hs["finish_within_days_probability"] == {
        "0.125": pytest.approx(0.6), "1": pytest.approx(0.9)}
    line_hs, line_wind = (r.output.strip().splitlines()[-1] for r in (res_hs, res_wind))
    assert line_hs.startswith("3 windows, 3 of them 2 h or longer")
    assert line_wind.startswith("3 windows by Hs alone (the series' wind_m_s is read, not judged: no --wind-limit), "
                                "3 of them 2 h or longer")
    assert line_hs.split("; written to")[0].replace("3 windows, ", "") == \
        line_wind.split("; written to")[0].replace(
            "3 windows by Hs alone (the series' wind_m_s is read, not judged: no --wind-limit), ", "")


@pytest.mark.parametrize("limit, words", [
    ("0", "--wind-limit 0: expected a positive number"),
    ("-3", "--wind-limit -3: expected a positive number"),
    ("inf", "--wind-limit inf: expected a finite number"),
    ("nan", "--wind-limit nan: expected a finite number"),
])
def test_a_bad_wind_limit_is_one_line_and_nothing_written(limit, words, windy, tmp_path):
    from conftest import one_line_exit_2

    res = runner.invoke(app, ["windows", str(windy), "--duration-h", "2", "--hs-limit", "2", "--wind-limit", limit,
                              "--out", str(tmp_path / "o")], terminal_width=4000)
    assert one_line_exit_2(res) == f"error: {words}"
    assert not (tmp_path / "o").exists()


def test_a_wind_limit_for_a_series_without_the_wind_is_one_line_and_nothing_written(series, tmp_path):
    from conftest import one_line_exit_2

    res = runner.invoke(app, ["windows", str(series), "--duration-h", "2", "--hs-limit", "2", "--wind-limit", "12",
                              "--out", str(tmp_path / "o")], terminal_width=4000)
    assert one_line_exit_2(res) == (f"error: {series}: --wind-limit 12 m/s needs each sample's wind: the series has "
                                    "no column wind_m_s (add it: the mean wind at 10 m, m/s; or leave --wind-limit "
                                    "out)")
    assert not (tmp_path / "o").exists()
    with pytest.raises(ScenarioError, match="has no column wind_m_s"):
        command.estimate(WindowsSpec(duration_h=2.0, hs_limit=2.0, wind_limit=12.0), series)
    # the illustrative series has no wind either
    with pytest.raises(ScenarioError, match="sea_states_illustrative.csv: --wind-limit 12 m/s needs"):
        command.estimate(WindowsSpec(duration_h=2.0, hs_limit=2.0, wind_limit=12.0))


@pytest.mark.parametrize("value, words", [
    ("-1", "line 6, wind_m_s: expected a finite non-negative number, got -1"),
    ("nan", "line 6, wind_m_s: expected a finite non-negative number, got nan"),
    ("x", "line 6, wind_m_s: expected a number, got 'x'"),
    ("71", "line 6, wind_m_s: 71 m/s is outside 0 .. 70 m/s"),
])
def test_a_bad_wind_in_the_series_is_one_line_naming_row_and_column(value, words, windy, tmp_path):
    """Refused with or without --wind-limit: the column is read either way."""
    from conftest import one_line_exit_2

    lines = windy.read_text().splitlines()
    lines[5] = lines[5].rsplit(",", 1)[0] + "," + value  # the sample at 4 h, line 6 of the file
    windy.write_text("\n".join(lines) + "\n")
    for extra in ([], ["--wind-limit", "12"]):
        res = runner.invoke(app, ["windows", str(windy), "--duration-h", "2", "--hs-limit", "2", *extra,
                                  "--out", str(tmp_path / "o")], terminal_width=4000)
        assert one_line_exit_2(res) == f"error: {windy}: {words}"
        assert not (tmp_path / "o").exists()
