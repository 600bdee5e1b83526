"""Hostile command lines: options nobody could mean, runs that blow up or mean nothing, and
names that carry markup or escape sequences."""

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
    text = (EXAMPLES / "paper.toml").read_text().replace('name = "paper"', f"name = {json.dumps(name)}")
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

    from marinecdpr.errors import ScenarioError
    from marinecdpr.studies.operability import check_scheduler

    def silent(address, timeout):
        assert timeout <= 5.0
        raise TimeoutError("timed out")

    monkeypatch.setattr(socket, "create_connection", silent)
    with pytest.raises(ScenarioError, match=r"--scheduler tcp://192\.0\.2\.1:8786: no Dask scheduler reachable "
                                            r"there \(no answer within 5 s\)"):
        check_scheduler("tcp://192.0.2.1:8786")


def test_durations_read_as_a_clock_would():
    from marinecdpr.cli.app import _seconds

    assert [_seconds(s) for s in (12.34, 59.94, 59.96, 119.6, 125.0, 3599.5)] == [
        "12.3 s", "59.9 s", "1 min 00 s", "2 min 00 s", "2 min 05 s", "60 min 00 s"]
