"""Progress lines (issue 37, item 8): a first line at once, no estimate of the time left from
too few pieces or from a batch done at one moment, work in runs estimated once a run's worth
is known, and a closing rate that leaves a first piece's compile out (and says so)."""

from __future__ import annotations

import io

from rich.console import Console

import marinecdpr.cli.progress as cli


def test_a_first_line_at_once_and_no_estimate_from_a_batch(clock):
    """A design search: 16 candidates, the first four judged at one moment, 2.3 s in (this
    printed nothing for 10 s, then "2 of 16 candidates (12%), 2.3 s, about 0.0 s left")."""
    bar = cli.PlainProgress("design", "candidates")
    task = bar.add_task("", total=16)
    assert clock.out.getvalue().splitlines() == ["design: 0 of 16 candidates, started"]
    clock.now = 2.3
    for done in range(1, 5):
        bar.update(task, completed=done)
    clock.now = 4.4  # the second generation: one candidate every 0.7 s
    for done in range(5, 9):
        clock.now += 0.7
        bar.update(task, completed=done)
    assert clock.out.getvalue().splitlines()[1:] == [
        "design: 2 of 16 candidates (12%), 2.3 s",  # the batch: no estimate
        "design: 5 of 16 candidates (31%), 5.1 s, about 7.7 s left",  # 4 in 2.8 s since the first: 11 left
        "design: 7 of 16 candidates (44%), 6.5 s, about 6.3 s left",  # 6 in 4.2 s: 9 left
    ]


def test_work_in_runs_is_estimated_once_a_run_s_worth_is_known(clock):
    """clean: three runs of 1000 steps, each planned for 3 s first, then 1000 steps/s (this
    said "about 0.5 s left" at 11 %: the first run's pace, without the next runs' plans)."""
    with cli.task_progress("clean", 3000, "steps", eta_after=1000) as update:
        t = 0.0
        for run in range(3):
            t += 3.0  # its plan
            for done in range(100, 1001, 100):
                clock.now = t + done / 1000.0
                update(1000 * run + done)
            t += 1.0
    lines = clock.out.getvalue().splitlines()
    assert lines[0] == "clean: 0 of 3000 steps, started"
    estimates = {line.split(" of ")[0]: line.split(", about ")[1] for line in lines if "left" in line}
    # none before the first run is done; after it, its 4 s (less the first piece) set the pace
    assert min(int(k.split()[-1]) for k in estimates) > 1000
    assert estimates["clean: 1100"] == "7.6 s left"  # 1000 steps in 3.9 s since the first piece
    assert lines[-1] == ("clean: 3000 of 3000 steps in 12.0 s (326 steps/s after the first 100, which took 3.1 s "
                         "with the start-up)")


def test_the_closing_rate_leaves_the_compile_out(clock):
    """simulate's first run: its first 500 steps take a 30 s compile, then 5000 steps/s (this
    said "(478 steps/s)", the compile counted in)."""
    bar = cli.PlainProgress("simulate", "steps")
    task = bar.add_task("open loop", total=15001)
    for done in list(range(500, 15001, 500)) + [15001]:
        clock.now = 30.0 + (done - 500) / 5000.0
        bar.update(task, completed=done)
    assert clock.out.getvalue().splitlines()[-1] == (
        "simulate: open loop: 15001 of 15001 steps in 32.9 s (5,000 steps/s after the first 500, which took "
        "30.0 s with the start-up)")


def test_the_terminal_bar_shows_no_estimate_from_one_piece(monkeypatch, clock):
    monkeypatch.setattr(cli, "err_console", Console(file=io.StringIO(), width=200, force_terminal=True))
    with cli.progress_bar("design", "candidates") as bar:
        task = bar.add_task("", total=16)
        clock.now = 2.3
        bar.update(task, completed=1)
        bar.update(task, completed=2)
        left = bar.columns[-1]
        assert left.render(bar.tasks[0]).plain == ""
        for done in range(3, 7):
            clock.now += 0.5
            bar.update(task, completed=done)
        # 5 candidates in 2.0 s since the first: 10 left take 4.0 s
        assert left.render(bar.tasks[0]).plain == "about 4.0 s left"


# -------------------- formerly tests/test_issue21_first_run.py

"""Issue 21, item 5: a first run's compile. Every command that compiles says so in one line
before it (when numba's cache is cold); progress estimates leave the compile out (the rate
clock starts once the first piece of work, which holds the compile, is done); no silence
of tens of seconds (the error budget's workspace maps after ``simulate``'s runs)."""


import re

import pytest
from typer.testing import CliRunner

import marinecdpr.cli.progress as cli
import marinecdpr.prototype.simulation as simulation
from marinecdpr.cli.app import app
import marinecdpr.studies.latency as latency

runner = CliRunner()
NOTICE = f"compiling the simulation kernels, once (about {simulation.KERNEL_COMPILE_S:g} s; cached for later runs)..."


def test_the_estimate_leaves_the_first_pieces_compile_out(clock):
    bar = cli.PlainProgress("simulate", "steps")
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
    bar = cli.PlainProgress("control-study", "runs")
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
    res = runner.invoke(app, args + ["--out", str(tmp_path / "o")])
    assert res.exit_code in (0, 3), res.output
    lines = res.stderr.strip().splitlines()
    assert [ln for ln in lines if ln.startswith("compiling ")] == ([NOTICE] if cold else [])
    if cold:
        work = [i for i, ln in enumerate(lines) if re.match(r"(simulate|clean|closed-loop runs|sea states)", ln)]
        assert lines.index(NOTICE) < min(work, default=len(lines))  # before the work's first line


@pytest.mark.parametrize("cold", [True, False])
def test_latency_says_it_compiles_the_controllers_step(cold, monkeypatch):
    _cold(monkeypatch, cold)
    res = runner.invoke(app, ["latency", "paper", "--calls", "20"])
    assert res.exit_code == 0, res.output
    notice = (f"compiling the controller's step, once (about {latency.LATENCY_COMPILE_S:g} s; cached for later "
              "runs)...")
    assert res.stderr.strip().splitlines() == ([notice] if cold else [])


def test_the_deciders_read_numbas_cache():
    # warm in this process once a step has been compiled or loaded
    runner.invoke(app, ["latency", "paper", "--calls", "5"])
    assert latency.latency_kernels_cached()
    assert simulation.compiled_cached() is True  # nothing to compile
    assert simulation.compiled_cached(object()) is True  # not a dispatcher: unsure, so no notice


def test_simulate_tells_the_error_budgets_maps_after_its_runs(tmp_path):
    res = runner.invoke(app, ["simulate", "paper_as_built", "--plant", "own", "--duration", "0.1",
                                  "--out", str(tmp_path / "o")])
    assert res.exit_code == 0, res.output
    lines = res.stderr.strip().splitlines()
    maps = [ln for ln in lines if ln.startswith("simulate: error budget: workspace maps: ")]
    # three 16 x 10 maps (point anchors; with the pulleys; with the winches) on one count
    assert maps and re.fullmatch(r"simulate: error budget: workspace maps: 480 of 480 poses in \d+\.\d s "
                                 r"\([\d,.]+ poses/s\)", maps[-1]), lines
    runs = [i for i, ln in enumerate(lines) if ln.startswith("simulate: ") and "error budget" not in ln]
    assert max(runs) < lines.index(maps[0])  # after the runs


# -------------------- formerly tests/test_issue21_durations.py

"""Issue 21, item 6: a run's progress counts the runs it flies, and a --duration beyond the
scenario is said, not silently cut."""

from pathlib import Path
from types import SimpleNamespace

from typer.testing import CliRunner

import marinecdpr.cli.clean
from marinecdpr.cli.app import app
from marinecdpr.scenario.loading import load_scenario

runner = CliRunner()


def test_clean_with_a_guarantee_met_at_once_ends_its_progress_on_the_runs_flown(tmp_path, monkeypatch):
    import marinecdpr.report.cleaning as report
    import marinecdpr.studies.cleaning as cleaning

    def guaranteed_job(sc, plant=None, progress=None):  # met by the first run: no second one
        n = sc.time.n_steps
        for k in (n // 2, n):
            progress(k, n)
        guarantee = SimpleNamespace(reason="met", lane_spacing_m=0.1, checked=True, second_run=False)
        return SimpleNamespace(figures=SimpleNamespace(guarantee=guarantee, interference=None, controller_verdict="held",
                                                       controller_fallbacks=0, steps=n), summary={})

    monkeypatch.setattr(cleaning, "guaranteed_job", guaranteed_job)
    monkeypatch.setattr(report, "write_cleaning", lambda job, folder, **kwargs: [Path(folder) / "clean.csv"])
    monkeypatch.setattr(report, "cleaning_findings", lambda figures, **kwargs: [])
    monkeypatch.setattr(marinecdpr.cli.clean, "compile_notice", lambda plant: None)
    res = runner.invoke(app, ["clean", "--guarantee", "--no-compare", "--duration", "1", "--out",
                                  str(tmp_path / "o")], terminal_width=2000)
    assert res.exit_code == 0, res.output
    last = [ln for ln in res.stderr.splitlines() if ln.startswith("clean: ")][-1]
    n = load_scenario("paper_clean").time.step_s
    steps = round(1.0 / n) + 1
    assert last.startswith(f"clean: {steps} of {steps} steps in "), last
