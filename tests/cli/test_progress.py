"""Progress lines (issue 37, item 8): a first line at once, no estimate of the time left from
too few pieces or from a batch done at one moment, work in runs estimated once a run's worth
is known, and a closing rate that leaves a first piece's compile out (and says so)."""

from __future__ import annotations

import io

from rich.console import Console

import marinecdpr.cli.app as cli


def test_a_first_line_at_once_and_no_estimate_from_a_batch(clock):
    """A design search: 16 candidates, the first four judged at one moment, 2.3 s in (this
    printed nothing for 10 s, then "2 of 16 candidates (12%), 2.3 s, about 0.0 s left")."""
    bar = cli._PlainProgress("design", "candidates")
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
    with cli._progress("clean", 3000, "steps", eta_after=1000) as update:
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
    bar = cli._PlainProgress("simulate", "steps")
    task = bar.add_task("open loop", total=15001)
    for done in list(range(500, 15001, 500)) + [15001]:
        clock.now = 30.0 + (done - 500) / 5000.0
        bar.update(task, completed=done)
    assert clock.out.getvalue().splitlines()[-1] == (
        "simulate: open loop: 15001 of 15001 steps in 32.9 s (5,000 steps/s after the first 500, which took "
        "30.0 s with the start-up)")


def test_the_terminal_bar_shows_no_estimate_from_one_piece(monkeypatch, clock):
    monkeypatch.setattr(cli, "err_console", Console(file=io.StringIO(), width=200, force_terminal=True))
    with cli._progress_bar("design", "candidates") as bar:
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
