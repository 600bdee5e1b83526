"""Issue 21, item 5: a first run's compile. Every command that compiles says so in one line
before it (when numba's cache is cold); progress estimates leave the compile out (the rate
clock starts once the first piece of work, which holds the compile, is done); no silence
of tens of seconds (the error budget's workspace maps after ``simulate``'s runs)."""

from __future__ import annotations

import re

import pytest
from typer.testing import CliRunner

import marinecdpr.cli.app as cli
import marinecdpr.prototype.simulation as simulation
import marinecdpr.studies.latency as latency

runner = CliRunner()
NOTICE = f"compiling the simulation kernels, once (about {simulation.KERNEL_COMPILE_S:g} s; cached for later runs)..."


def test_the_estimate_leaves_the_first_pieces_compile_out(clock):
    bar = cli._PlainProgress("simulate", "steps")
    task = bar.add_task("open loop", total=100)
    clock.now = 75.0  # the first piece: a 75 s compile and a moment's work
    bar.update(task, completed=1)
    for done in range(2, 11):  # then 0.2 s a step
        clock.now = 75.0 + 0.2 * (done - 1)
        bar.update(task, completed=done)
    # no estimate from the first piece alone; then 9 steps in 1.8 s since it: 90 steps left
    # take 18 s (counting the compile, 768 s: "about 12 min 48 s left")
    assert clock.out.getvalue().splitlines() == [
        "simulate: open loop: 0 of 100 steps, started",  # at once (issue 37, item 8)
        "simulate: open loop: 1 of 100 steps (1%), 1 min 15 s",
        "simulate: open loop: 10 of 100 steps (10%), 1 min 17 s, about 18.0 s left"]


def test_no_estimate_before_three_pieces_after_the_first(clock):
    """Issue 37, item 8: one or two pieces after the first say too little (this said "about
    5 min 08 s left" after one, "2 min 42 s" after two); from the third, 3 runs in 23 s."""
    bar = cli._PlainProgress("control-study", "runs")
    task = bar.add_task("", total=30)
    clock.now = 400.0  # 7 min: the compile and the first run
    bar.update(task, completed=1)  # a line (10 s have passed), with no estimate from one piece
    clock.now = 411.0
    bar.update(task, completed=2)
    clock.now = 412.0
    bar.update(task, completed=3)
    clock.now = 423.0
    bar.update(task, completed=4)  # 3 runs in 23 s since the first: 26 left take 199.3 s
    lines = clock.out.getvalue().splitlines()
    assert lines == ["control-study: 0 of 30 runs, started",
                     "control-study: 1 of 30 runs (3%), 6 min 40 s",
                     "control-study: 2 of 30 runs (7%), 6 min 51 s",
                     "control-study: 3 of 30 runs (10%), 6 min 52 s",
                     "control-study: 4 of 30 runs (13%), 7 min 03 s, about 3 min 19 s left"]


def _cold(monkeypatch, cold: bool) -> None:
    monkeypatch.setattr(simulation, "kernels_cached", lambda plant: not cold)
    monkeypatch.setattr(latency, "latency_kernels_cached", lambda: not cold)


@pytest.fixture(scope="module")
def one_cell(tmp_path_factory):
    path = tmp_path_factory.mktemp("scatter") / "one.csv"
    path.write_text("hs_m,tp_s,probability\n1.0,8.0,1.0\n")
    return path


COMMANDS = {
    "simulate": ["simulate", "paper", "--plant", "own", "--duration", "0.05"],
    "clean": ["clean", "paper_clean", "--plant", "own", "--duration", "0.05", "--no-compare"],
    "control-study": ["control-study", "paper_sea", "--latencies", "0", "--predictions", "none", "--pose-from",
                      "sensor", "--duration", "0.2", "--settle", "0"],
    "operability --max-error": ["operability", "paper_sea", "--serial", "--duration", "0.2", "--step", "0.01",
                                "--realisations", "1", "--max-error", "0.5"],
}


@pytest.mark.parametrize("name", list(COMMANDS))
@pytest.mark.parametrize("cold", [True, False])
def test_every_command_that_compiles_the_simulation_says_so_first(name, cold, tmp_path, monkeypatch, one_cell):
    _cold(monkeypatch, cold)
    args = COMMANDS[name] + (["--scatter", str(one_cell)] if name.startswith("operability") else [])
    res = runner.invoke(cli.app, args + ["--out", str(tmp_path / "o")])
    assert res.exit_code in (0, 3), res.output
    lines = res.stderr.strip().splitlines()
    assert [ln for ln in lines if ln.startswith("compiling ")] == ([NOTICE] if cold else [])
    if cold:
        work = [i for i, ln in enumerate(lines) if re.match(r"(simulate|clean|closed-loop runs|sea states)", ln)]
        assert lines.index(NOTICE) < min(work, default=len(lines))  # before the work's first line


@pytest.mark.parametrize("cold", [True, False])
def test_latency_says_it_compiles_the_controllers_step(cold, monkeypatch):
    _cold(monkeypatch, cold)
    res = runner.invoke(cli.app, ["latency", "paper", "--calls", "20"])
    assert res.exit_code == 0, res.output
    notice = (f"compiling the controller's step, once (about {latency.LATENCY_COMPILE_S:g} s; cached for later "
              "runs)...")
    assert res.stderr.strip().splitlines() == ([notice] if cold else [])


def test_the_deciders_read_numbas_cache():
    # warm in this process once a step has been compiled or loaded
    runner.invoke(cli.app, ["latency", "paper", "--calls", "5"])
    assert latency.latency_kernels_cached()
    assert simulation.compiled_cached() is True  # nothing to compile
    assert simulation.compiled_cached(object()) is True  # not a dispatcher: unsure, so no notice


def test_simulate_tells_the_error_budgets_maps_after_its_runs(tmp_path):
    res = runner.invoke(cli.app, ["simulate", "paper_as_built", "--plant", "own", "--duration", "0.1",
                                  "--out", str(tmp_path / "o")])
    assert res.exit_code == 0, res.output
    lines = res.stderr.strip().splitlines()
    maps = [ln for ln in lines if ln.startswith("simulate: error budget: workspace maps: ")]
    # three 16 x 10 maps (point anchors; with the pulleys; with the winches) on one count
    assert maps and re.fullmatch(r"simulate: error budget: workspace maps: 480 of 480 poses in \d+\.\d s "
                                 r"\([\d,.]+ poses/s\)", maps[-1]), lines
    runs = [i for i, ln in enumerate(lines) if ln.startswith("simulate: ") and "error budget" not in ln]
    assert max(runs) < lines.index(maps[0])  # after the runs
