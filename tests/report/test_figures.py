"""Figures drawn at their resolution (issue 10, item 6): every time series thinned to its
pixel columns with every extreme kept, and the main job's figures drawn in two processes
with the same files as in one."""

from __future__ import annotations

import errno
import multiprocessing
import os
import signal
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest

import marinecdpr
import marinecdpr.report.figures as figures
from marinecdpr import forked
import marinecdpr.report.writers as writers
from marinecdpr.report.figures import RUN_TITLES, decimate
from marinecdpr.prototype.simulation import RUNS, SimResult

pytestmark = pytest.mark.figures  # the module is about the figures: drawn in every test

N = 15_001
COLUMNS = 1210  # the 11-inch figures at 110 dpi


def _groups(n: int, columns: int) -> list[np.ndarray]:
    """The samples of each pixel column, as decimate splits them."""
    col = (np.arange(n) * columns) // n
    return np.split(np.arange(n), np.flatnonzero(np.diff(col)) + 1)


def _kept(x_out, y_out) -> dict:
    return dict(zip(x_out.tolist(), y_out.tolist()))


def test_decimation_keeps_every_extreme_first_and_last_and_the_time_order():
    rng = np.random.default_rng(3)
    t = np.arange(N) * 1e-3
    y = np.cumsum(rng.normal(size=N)) + rng.normal(scale=5.0, size=N) * (rng.random(N) < 0.01)  # spikes
    x_out, y_out = decimate(t, y, COLUMNS)
    assert 3 * COLUMNS < x_out.size <= 4 * COLUMNS  # about 4 per column, from 15 001
    assert np.all(np.diff(x_out) > 0)
    kept = _kept(x_out, y_out)
    assert kept[t[0]] == y[0] and kept[t[-1]] == y[-1]
    groups = _groups(N, COLUMNS)
    assert len(groups) == COLUMNS
    for g in groups:
        for i in (g[0], g[np.argmin(y[g])], g[np.argmax(y[g])], g[-1]):
            assert kept[t[i]] == y[i]
    assert y_out.max() == y.max() and y_out.min() == y.min()


def test_decimation_keeps_gaps_and_the_extremes_around_them():
    rng = np.random.default_rng(4)
    t = np.arange(N) * 1e-3
    y = rng.normal(size=N)
    gaps = [(0, 3), (100, 140), (5_000, 5_001), (9_998, 10_030), (N - 7, N)]
    for a, b in gaps:
        y[a:b] = np.nan
    y[7_000:7_300] = np.nan  # whole pixel columns without a number
    gaps.append((7_000, 7_300))
    x_out, y_out = decimate(t, y, COLUMNS)
    assert x_out.size <= 4 * COLUMNS + len(gaps)
    for a, b in gaps:  # a NaN stands between the numbers on either side of each gap
        inside = (x_out >= t[a]) & (x_out <= t[b - 1])
        assert np.isnan(y_out[inside]).any(), (a, b)
    kept = _kept(x_out, y_out)
    for g in _groups(N, COLUMNS):
        finite = g[np.isfinite(y[g])]
        if finite.size:
            for i in (finite[np.argmin(y[finite])], finite[np.argmax(y[finite])]):
                assert kept[t[i]] == y[i]
    assert np.nanmax(y_out) == np.nanmax(y) and np.nanmin(y_out) == np.nanmin(y)


def test_a_short_series_is_drawn_whole_and_several_series_keep_each_ones_extremes():
    t = np.arange(4 * COLUMNS) * 1e-3
    y = np.sin(t)
    x_out, y_out = decimate(t, y, COLUMNS)
    assert x_out is t or np.array_equal(x_out, t)
    np.testing.assert_array_equal(y_out, y)
    # a path: x and z decimated together, the extremes of each kept
    rng = np.random.default_rng(5)
    t = np.arange(N) * 1e-3
    xz = np.column_stack([np.cos(t) + rng.normal(scale=1e-3, size=N), np.sin(t) + rng.normal(scale=1e-3, size=N)])
    x_out, xz_out = decimate(t, xz, 715)
    assert xz_out.shape[1] == 2 and x_out.size <= 6 * 715
    kept = {tt: tuple(v) for tt, v in zip(x_out.tolist(), xz_out.tolist())}
    for g in _groups(N, 715):
        for c in (0, 1):
            for i in (g[np.argmin(xz[g, c])], g[np.argmax(xz[g, c])]):
                assert kept[t[i]] == tuple(xz[i])


# --------------------------------------------------------------- the figures themselves
def _long_runs(scenario, n: int = N) -> dict:
    """Three made-up runs of n steps (what the figures draw, without simulating)."""
    rng = np.random.default_rng(6)
    t = np.arange(n) * 1e-3
    m = scenario.robot.n_cables
    planned = np.zeros((n, 6))
    planned[:, 0], planned[:, 2] = 1.0 + 0.2 * np.sin(t), 0.7 + 0.2 * np.cos(t)
    planned[:, 4] = 0.01 * np.sin(3 * t)
    lengths = 1.0 + 0.1 * np.sin(t[:, None] + np.arange(m))
    runs = {}
    for k, name in enumerate(RUNS):
        noise = 10.0 ** -(k + 2)
        pose = planned + rng.normal(scale=noise, size=(n, 6))
        actual = lengths + rng.normal(scale=noise, size=(n, m))
        pose[::7], actual[::7] = planned[::7], lengths[::7]  # exact steps: zero errors, gaps on the log scale
        runs[name] = SimResult(run=name, plant="mujoco", t=t, pose_planned=planned, pose=pose,
                               lengths_planned=lengths, lengths=actual,
                               tensions_commanded=np.full((n, m), 50.0), tensions=np.full((n, m), 50.0),
                               controller_fallbacks=0, ship_tracking_error=0.0)
    return runs


@pytest.mark.parametrize("figure", ["tracking", "cable_lengths"])
def test_time_series_figures_draw_each_pixel_column_with_its_extremes(figure, paper, captured_figures, tmp_path):
    runs = _long_runs(paper)
    figs = captured_figures
    getattr(figures, f"plot_{figure}")(runs, paper, tmp_path / f"{figure}.png")
    fig = figs[f"{figure}.png"]
    columns = int(np.ceil(fig.get_figwidth() * figures.FIGURE_DPI))
    if figure == "tracking":
        series = [lambda r, planned, i=i: (np.degrees if i >= 3 else np.asarray)(
            (r.pose_planned if planned else r.pose)[:, i]) for i in (0, 2, 4)]
    else:
        series = [lambda r, planned, i=i: (r.lengths_planned if planned else r.lengths)[:, i]
                  for i in range(paper.robot.n_cables)]
    axes = np.reshape(fig.axes, (-1, 2))
    assert len(axes) == len(series)
    for (ax, ax_e), value in zip(axes, series):
        lines = {ln.get_label(): ln for ln in ax.get_lines()}
        for name, res in runs.items():
            line = lines[RUN_TITLES[name]]
            assert len(line.get_xdata()) <= 4 * columns
            assert np.nanmax(line.get_ydata()) == value(res, False).max()
            assert np.nanmin(line.get_ydata()) == value(res, False).min()
        assert ax_e.get_yscale() == "log"
        for ln, res in zip(ax_e.get_lines(), [runs[n] for n in ("fixed_base_open_loop", "open_loop", "closed_loop")]):
            err = np.abs(value(res, False) - value(res, True))
            y = ln.get_ydata()
            assert len(y) <= 4 * columns + N // 7 and np.isnan(y).any()  # the zero errors stay gaps
            scale = err.max() / np.nanmax(y)
            np.testing.assert_allclose(np.nanmin(y) * scale, err[err > 0].min(), rtol=1e-12)


def test_tension_and_path_figures_keep_their_extremes(paper, paper_plan, captured_figures, tmp_path):
    figs = captured_figures
    figures.plot_tensions(paper_plan, paper, tmp_path / "tensions.png")
    fig = figs["tensions.png"]
    columns = int(np.ceil(fig.get_figwidth() * figures.TENSION_FIGURE_DPI))
    for ax, T in zip(fig.axes, (paper_plan.tensions_pinv, paper_plan.tensions)):
        lines = {ln.get_label(): ln for ln in ax.get_lines()}
        for i in range(paper.robot.n_cables):
            y = lines[f"cable {i + 1}"].get_ydata()
            assert len(y) <= 4 * columns < paper_plan.n_steps
            assert y.max() == T[:, i].max() and y.min() == T[:, i].min()
    runs = _long_runs(paper)
    figures.plot_path(runs, paper, tmp_path / "path.png")
    ax = figs["path.png"].axes[0]
    lines = {ln.get_label(): ln for ln in ax.get_lines()}
    for name, res in runs.items():
        line = lines[RUN_TITLES[name]]
        assert len(line.get_xdata()) < N // 2
        assert line.get_xdata().max() == res.pose[:, 0].max() and line.get_ydata().min() == res.pose[:, 2].min()


# ----------------------------------------------------------- drawn in two processes
@pytest.fixture(scope="module")
def short_vp():
    sc = marinecdpr.load_scenario("paper")
    sc = sc.with_changes(time={"step_s": sc.time.step_s, "duration_s": 0.3})
    return marinecdpr.virtual_prototype(sc)


def test_the_main_job_writes_the_same_files_in_one_process_or_two(short_vp, tmp_path, monkeypatch):
    import matplotlib.image

    pids = tmp_path / "pids"
    pids.mkdir()
    real = writers.plot_cable_lengths

    def recorded(*args, **kwargs):
        (pids / str(os.getpid())).touch()
        return real(*args, **kwargs)

    monkeypatch.setattr(writers, "plot_cable_lengths", recorded)
    two = writers.write_virtual_prototype(short_vp, tmp_path / "two")
    if forked.can_fork():
        assert [p.name for p in pids.iterdir()] != [str(os.getpid())]  # drawn by another process
    monkeypatch.setattr(forked, "can_fork", lambda: False)
    one = writers.write_virtual_prototype(short_vp, tmp_path / "one")
    assert [p.name for p in one] == [p.name for p in two]
    for a, b in zip(one, two):
        if a.suffix == ".png":
            np.testing.assert_array_equal(matplotlib.image.imread(a), matplotlib.image.imread(b))
        elif a.suffix != ".html":
            assert a.read_bytes() == b.read_bytes(), a.name
    assert multiprocessing.active_children() == []


def test_a_failure_in_the_second_process_is_raised_here_with_its_errno(short_vp, tmp_path, monkeypatch):
    def full_disk(*args, **kwargs):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(writers, "plot_cable_lengths", full_disk)
    with pytest.raises(OSError) as info:
        writers.write_virtual_prototype(short_vp, tmp_path / "o")
    assert info.value.errno == errno.ENOSPC and info.value.strerror == "No space left on device"
    assert multiprocessing.active_children() == []


def test_an_interrupt_here_ends_the_second_process_at_once(short_vp, tmp_path, monkeypatch):
    monkeypatch.setattr(writers, "plot_cable_lengths", lambda *a, **k: time.sleep(60))

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(writers, "plot_tracking", interrupted)
    started = []

    class Recorded(writers.Forked):
        def __init__(self, fn):
            super().__init__(fn)
            started.append(self)

    monkeypatch.setattr(writers, "Forked", Recorded)
    with pytest.raises(KeyboardInterrupt):
        writers.write_virtual_prototype(short_vp, tmp_path / "o")
    assert multiprocessing.active_children() == []
    # ended, not waited for: the copy was stopped by a signal in its 60 s sleep (not: within 20 s)
    (forked_copy,) = started
    if forked_copy._process is not None:
        assert forked_copy._process.exitcode == -signal.SIGTERM


@pytest.mark.skipif(not forked.can_fork(), reason="figures are drawn in one process here")
def test_the_second_process_dies_with_a_killed_parent(tmp_path):
    script = textwrap.dedent("""
        import sys, time
        from marinecdpr import forked
        f = forked.Forked(lambda: time.sleep(60))
        print(f._process.pid, flush=True)
        time.sleep(60)
    """)
    # a subreaper adopts the orphaned copy and waits for it: how it ended (killed by the
    # parent's death, or its 60 s run out) is read from its status, not from a deadline
    reaper = textwrap.dedent(f"""
        import ctypes, os, signal, subprocess, sys
        if ctypes.CDLL(None, use_errno=True).prctl(36, 1, 0, 0, 0) != 0:  # PR_SET_CHILD_SUBREAPER
            print("no subreaper"); sys.exit()
        parent = subprocess.Popen([sys.executable, "-c", {script!r}], stdout=subprocess.PIPE, text=True)
        child = int(parent.stdout.readline())
        os.kill(child, 0)  # running
        parent.send_signal(signal.SIGKILL)
        parent.wait()
        _, status = os.waitpid(child, 0)  # the orphan is this process's child now
        # killed with its parent (PR_SET_DEATHSIG), or it saw its parent gone as it started (exit 1);
        # not: its 60 s of work done (exit 0)
        killed = os.WIFSIGNALED(status) and os.WTERMSIG(status) == signal.SIGKILL
        print("killed" if killed or (os.WIFEXITED(status) and os.WEXITSTATUS(status) == 1) else f"status {{status}}")
    """)
    out = subprocess.run([sys.executable, "-c", reaper], capture_output=True, text=True, timeout=300)
    if out.stdout.strip() == "no subreaper":
        pytest.skip("prctl(PR_SET_CHILD_SUBREAPER) is not allowed here")
    assert out.stdout.strip() == "killed", (out.stdout, out.stderr[-2000:])


# ------------------------------------------------------------ first run (item 5)
def test_a_cold_kernel_cache_is_told_in_one_line_before_the_work(tmp_path, monkeypatch):
    from typer.testing import CliRunner

    import marinecdpr.cli.app as cli
    import marinecdpr.prototype.simulation as simulation

    runner = CliRunner()
    for cold in (True, False):
        monkeypatch.setattr(simulation, "kernels_cached", lambda plant, cold=cold: not cold)
        res = runner.invoke(cli.app, ["simulate", "--duration", "0.1", "--out", str(tmp_path / str(cold))])
        assert res.exit_code == 0, res.output
        lines = res.stderr.strip().splitlines()
        notices = [ln for ln in lines if ln.startswith("compiling the simulation kernels")]
        assert notices == ([f"compiling the simulation kernels, once (about {simulation.KERNEL_COMPILE_S:g} s; "
                            "cached for later runs)..."] if cold else [])
        assert all(ln.startswith("simulate: ") for ln in lines[1 if cold else 0:])


def test_the_kernel_cache_is_cold_without_an_index_and_warm_once_loaded(tmp_path):
    from marinecdpr.prototype.simulation import kernels_cached

    probe = "from marinecdpr.prototype.simulation import kernels_cached; print(kernels_cached('mujoco'), kernels_cached('own'))"
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path))  # an empty cache: nothing compiled yet
    env.pop("MARINECDPR_CACHE_DIR", None)  # (which would take precedence over NUMBA_CACHE_DIR)
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, env=env, timeout=300)
    assert out.stdout.split() == ["False", "False"], out.stderr
    marinecdpr.simulate(marinecdpr.load_scenario("paper"), run="open_loop", n_steps=10)  # compiled or loaded
    assert kernels_cached("mujoco")


# -------------------- formerly tests/test_issue21_figures.py

"""Issue 21, items 9, 10 and 12 (figures): the reports' words and figures say what they show.

The figures are checked on their matplotlib artists: legend entries drawn as their lines,
legends inside the saved figure, axis formatters without an offset, the numbers in cells.
"""

import re
import sys
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from matplotlib.colors import to_rgba

import marinecdpr
import marinecdpr.report.cleaning as cleaning_report
import marinecdpr.report.figures as figures
from marinecdpr.report.figures import FIGURE_DPI, RUN_TITLES
from marinecdpr.report.text import findings, write_report_html

sys.path.insert(0, str(Path(__file__).parent))


def _within_figure(fig, artist, tmp_path):
    """The artist's box lies inside the figure once saved as the reports save it."""
    fig.savefig(tmp_path / "saved.png", dpi=FIGURE_DPI)
    box = artist.get_window_extent(fig.canvas.get_renderer())
    return box.x0 >= 0 and box.y0 >= 0 and box.x1 <= fig.bbox.width and box.y1 <= fig.bbox.height


def _legend_entries(fig):
    legend = fig.legends[0] if fig.legends else fig.axes[0].get_legend()
    return {t.get_text(): h for t, h in zip(legend.get_texts(), legend.legend_handles)}


# ------------------------------------------------------------------ item 9
@pytest.mark.parametrize("figure", ["cable_lengths", "tracking"])
def test_every_run_is_drawn_as_its_legend_entry_in_both_columns(figure, paper, captured_figures, tmp_path):
    """The closed loop's entry was dashed, its lines solid (a dashed line through a
    decimated zigzag shows solid; the error column was always solid)."""
    runs = _long_runs(paper)
    getattr(figures, f"plot_{figure}")(runs, paper, tmp_path / f"{figure}.png")
    fig = captured_figures[f"{figure}.png"]
    entries = _legend_entries(fig)
    for name in runs:
        handle = entries[RUN_TITLES[name]]
        colour = to_rgba(handle.get_color())
        drawn = [ln for ax in fig.axes for ln in ax.get_lines() if to_rgba(ln.get_color()) == colour]
        assert len(drawn) == len(fig.axes)  # one line per axes, lengths and errors
        for ln in drawn:
            assert ln.get_linestyle() == handle.get_linestyle(), (name, ln.get_linestyle())
            assert ln.get_linewidth() == handle.get_linewidth()


def test_the_path_figures_legend_is_inside_the_figure(paper, captured_figures, tmp_path):
    figures.plot_path(_long_runs(paper), paper, tmp_path / "path.png")
    fig = captured_figures["path.png"]
    assert len(fig.legends) == 1 and len(fig.legends[0].get_texts()) == 6
    assert _within_figure(fig, fig.legends[0], tmp_path)


def _summary(fixed_m, moving_m=1.5e-7, bound_m=0.019):
    from dataclasses import replace

    from marinecdpr.studies.prototype_runs import PrototypeFigures, RunFigures

    run = RunFigures(max_abs_error_x_m=moving_m, max_abs_error_z_m=moving_m, max_abs_cable_length_error_m=(moving_m,) * 4,
                     max_abs_error_theta_deg=1e-6, within_error_bound=True, beyond_error_bound=(),
                     tension_limit_excess_N=0.0, controller_fallbacks=0, tension_min_N=10.0, tension_max_N=20.0,
                     rms_error_x_m=moving_m, rms_error_z_m=moving_m, ship_tracking_error=0.0, plant="own")
    fixed = replace(run, max_abs_error_x_m=fixed_m, within_error_bound=fixed_m <= bound_m,
                    beyond_error_bound=() if fixed_m <= bound_m else ("x",))
    return PrototypeFigures(scenario="paper", steps=100, step_s=0.001, method="closed_form", pinv_tension_min_N=1.0,
                            opt_tension_min_N=10.0, opt_tension_max_N=20.0, error_bound_m=bound_m, error_bound_deg=1.0,
                            controller_bypassed_share_max=0.05, open_loop_growth_rate_1_s=0.0, stability=None,
                            error_budget={}, runs={"open_loop": run, "closed_loop": run, "fixed_base_open_loop": fixed},
                            runs_beyond_error_bound=(), runs_controller_bypassed=(), warnings=())


def test_the_fixed_base_plan_is_measured_against_the_error_bound(paper):
    """Not against the moving-base plan's open-loop residual (the hold of the tensions over a
    step with ideal cables): "219 000 times the moving-base plan's 153 nm" meant nothing."""
    text = " ".join(findings(_summary(0.0335), paper))
    assert "errs by 33.5 mm, 1.76 times the error bound of 19 mm" in text
    assert "times the moving-base plan" not in text and "223 000" not in text
    text = " ".join(findings(_summary(0.0095), paper))
    assert "errs by 9.5 mm, 50 % of the error bound of 19 mm" in text


# short_vp: the fixture above (the same 0.3 s paper run)


def test_the_report_numbers_its_figures_in_page_order_and_names_the_papers(short_vp, tmp_path):
    from marinecdpr.report.writers import write_virtual_prototype

    write_virtual_prototype(short_vp, tmp_path)
    page = (tmp_path / "report.html").read_text()
    captions = re.findall(r"<figcaption>(.*?)</figcaption>", page)
    assert [c.split(":")[0] for c in captions] == ["Figure 1", "Figure 2", "Figure 3", "Figure 4"]
    assert "like the paper&#39;s figure 5" in captions[0] and "like the paper&#39;s figure 7" in captions[2]
    # paper builds nothing beyond point anchors: no table of dashes
    assert "Cables as built" not in page


def test_the_cables_as_built_table_shows_where_something_is_built(short_vp, tmp_path):
    from dataclasses import replace

    f = short_vp.figures
    assert all(e["length_change_m"] is None and e["tension_change_N"] is None for e in f.error_budget.values())
    budget = dict(f.error_budget)
    budget["pulleys"] = {"length_change_m": 0.0012, "tension_change_N": 3.4,
                         "workspace_change": None, "note": "the pulleys' wrap"}
    path = write_report_html(replace(f, error_budget=budget), short_vp.scenario, {}, tmp_path / "report.html")
    page = path.read_text()
    assert "Cables as built" in page and "1.2 mm" in page


# ------------------------------------------------------------------ item 10
@pytest.fixture(scope="module")
def short_clean(tmp_path_factory):
    from marinecdpr.studies.cleaning import cleaning_job

    sc = marinecdpr.load_scenario("paper_clean")
    return cleaning_job(sc.with_changes(time={"step_s": sc.time.step_s, "duration_s": 2.0}))


@pytest.fixture(scope="module")
def short_hull(short_clean):
    from marinecdpr.studies.cleaning import ship_side

    return ship_side(short_clean.figures, hull_area_m2=100.0, move_time_s=600.0)


def test_the_cleaning_report_names_its_figures_in_words_and_units(short_clean, short_hull, tmp_path):
    out = cleaning_report.write_cleaning(short_clean, tmp_path, hull=short_hull)
    page = (tmp_path / "report.html").read_text()
    job = page[page.index("<h2>The job</h2>"):page.index("<ul>")]
    rows = dict(re.findall(r"<tr><th>(.*?)</th><td>(.*?)</td></tr>", job))
    assert not any(re.search(r"_(pct|m|N|s|kJ|m2|m2_h)$", k) for k in rows), rows  # no JSON keys
    s = short_clean.summary
    assert rows["panel cleaned"] == f"{s['coverage_pct']:.2f} %"
    p95 = rows["cross-track error, 95th percentile"]
    value, unit = p95.split()
    assert unit in ("mm", "µm", "nm") and 1.0 <= float(value) < 1000.0
    scale = {"mm": 1e-3, "µm": 1e-6, "nm": 1e-9}[unit]
    assert float(value) * scale == pytest.approx(s["p95_cross_track_error_m"], rel=5e-3)
    assert rows["hull: time"] == f"{short_hull['hours']:.1f} h"  # the hull estimate in the table
    assert "252 placements" in rows["hull"] or f"{short_hull['placements']} placements" in rows["hull"]
    assert "1.2 m, 12.9 s" in page  # the pass along the edges, and what it costs
    assert len(out) == 5


def test_the_cleaning_series_show_the_tension_limits_and_a_colour_per_line(short_clean, tmp_path, monkeypatch):
    figs = {}
    monkeypatch.setattr(cleaning_report, "_save", lambda fig, path, dpi=None: figs.setdefault(Path(path).name, fig))
    cleaning_report.plot_cleaning_series(short_clean, tmp_path / "cleaning.png")
    fig = figs["cleaning.png"]
    tensions, _, tracking = fig.axes
    levels = {float(ln.get_ydata()[0]) for ln in tensions.get_lines() if ln.get_linestyle() == "--"}
    robot = short_clean.scenario.robot
    assert levels == {float(robot.tension_min.min()), float(robot.tension_max.max())}
    cables = {to_rgba(ln.get_color()) for ln in tensions.get_lines() if ln.get_label().startswith("cable")}
    (error,) = tracking.get_lines()
    assert to_rgba(error.get_color()) not in cables
    entries = _legend_entries(fig)
    assert "tension limits" in entries


def test_operability_cells_print_the_probability_of_success(paper, captured_figures, tmp_path):
    """Each cell printed its probability of occurrence over a colour bar of the probability
    of success; the number now is the colour's."""
    op = SimpleNamespace(
        headings_deg=(180.0,), margin_N=0.0, per_heading={180.0: 0.5}, per_heading_interval=None,
        results=[SimpleNamespace(realisations=10)],
        scatter=SimpleNamespace(hs=np.array([1.0, 3.0]), tp=np.array([6.0, 8.0]),
                                probability=np.array([[0.4, 0.3], [0.2, 0.1]])),
        probability_grid=lambda h: np.array([[1.0, 0.7], [0.0, np.nan]]))
    op.scatter.probability[1, 1] = 0.0
    figures.plot_operability(op, paper, tmp_path / "operability.png")
    fig = captured_figures["operability.png"]
    cells = {(round(t.get_position()[0]), round(t.get_position()[1])): t.get_text() for t in fig.axes[0].texts}
    assert cells == {(0, 0): "100", (1, 0): "70", (0, 1): "0"}
    assert "numbers: probability of success" in fig.get_suptitle()


def test_control_study_headroom_axis_reads_plainly_and_coinciding_curves_all_show(tmp_path, captured_figures):
    runs = [SimpleNamespace(prediction=p, pose_from=src, latency_s=lat, rms_error_m=1e-6 * (1 + lat),
                            headroom_N=128.7812 + 1e-4 * lat)
            for p in ("none", "kinematic", "ar") for src in ("sensor", "encoders") for lat in (0.0, 0.02, 0.05)]
    study = SimpleNamespace(runs=runs, scenario="paper_sea", settle_s=11.0, rate_hz=100.0)
    h = np.array([0.1, 1.0])
    err = np.ones((2, 3, 6))
    prediction = SimpleNamespace(horizons_s=h, predictor=err, taylor=err, hold=2 * err)
    import marinecdpr.studies.control as control
    control_moving = control.moving_dofs
    try:
        control.moving_dofs = lambda p: np.ones(6, dtype=bool)
        figures.plot_control_study(study, prediction, tmp_path / "control_study.png")
    finally:
        control.moving_dofs = control_moving
    fig = captured_figures["control_study.png"]
    fig.savefig(tmp_path / "saved.png", dpi=FIGURE_DPI)
    headroom = fig.axes[1]
    assert headroom.yaxis.get_offset_text().get_text() == ""
    ticks = [t for t in headroom.get_yticks() if headroom.get_ylim()[0] <= t <= headroom.get_ylim()[1]]
    assert min(np.diff(ticks)) >= 0.1  # not 0.0004 N
    labels = [t.get_text() for t in headroom.get_yticklabels()]
    assert all("e" not in lab for lab in labels) and any(lab.startswith("128") for lab in labels)
    # curves on the same points: each drawn wider or with larger markers than those on top of it
    for ax in (fig.axes[1], fig.axes[2]):
        lines = ax.get_lines()
        same = [ln for ln in lines if np.allclose(ln.get_ydata(), lines[0].get_ydata())]
        assert len(same) >= 2
        sizes = [(ln.get_linewidth(), ln.get_markersize()) for ln in same]
        assert all(a[0] > b[0] or a[1] > b[1] for a, b in zip(sizes, sizes[1:])), sizes


# ------------------------------------------------------------------ item 12 (figure)
def test_the_windows_shades_are_in_the_legend(captured_figures, tmp_path):
    from marinecdpr.studies.weather import SeaStateSeries, weather_windows

    t = np.arange(48.0)
    hs = np.where((t % 24) < 14, 1.0, 3.0)
    hs[30:34] = 3.0
    series = SeaStateSeries(t_h=t, hs_m=hs, tp_s=np.full(48, 8.0))
    w = weather_windows(series, duration_h=12.0, alpha=1.0, hs_limit_m=2.0)
    figures.plot_windows(series, w, tmp_path / "windows.png", title="t")
    labels = [t.get_text() for t in captured_figures["windows.png"].axes[0].get_legend().get_texts()]
    assert "window of at least 12 h (the operation fits)" in labels
    assert "window shorter than 12 h" in labels


def test_the_windows_figure_draws_each_sample_s_wind_and_the_wind_limit(captured_figures, tmp_path):
    """Issue 40, item 1: a series with the wind gets a panel below Hs's with each sample's wind
    as given and the wind limit where judged; the windows shaded there as above (the wind
    closes 4-5 h: windows 0-4 and 5-8 h)."""
    from marinecdpr.studies.weather import SeaStateSeries, weather_windows

    t = np.arange(8.0)
    wind = np.array([5.0, 6.0, 7.0, 9.0, 15.0, 8.0, 4.0, 0.0])
    series = SeaStateSeries(t_h=t, hs_m=np.ones(8), tp_s=np.full(8, 8.0), wind_m_s=wind)
    w = weather_windows(series, duration_h=3.0, hs_limit_m=2.0, wind_limit_m_s=10.0)
    assert w.windows == [(0.0, 4.0), (5.0, 8.0)]
    figures.plot_windows(series, w, tmp_path / "windows.png", title="t")
    hs_ax, wind_ax = captured_figures["windows.png"].axes[:2]
    drawn = {ln.get_label(): ln for ln in wind_ax.get_lines()}
    np.testing.assert_array_equal(drawn["mean wind at 10 m"].get_ydata(), wind)
    np.testing.assert_array_equal(drawn["operational wind limit 10 m/s"].get_ydata(), [10.0, 10.0])
    spans = [(p.get_x(), p.get_x() + p.get_width()) for p in wind_ax.patches]  # axvspan's rectangles
    assert spans == [(0.0, 4.0), (5.0, 8.0)]
    # without a limit: the wind drawn, no limit line, the panel says it is not judged
    figures.plot_windows(series, weather_windows(series, duration_h=3.0, hs_limit_m=2.0), tmp_path / "windows.png",
                         title="t")
    wind_ax = captured_figures["windows.png"].axes[1]
    assert [ln.get_label() for ln in wind_ax.get_lines()] == ["mean wind at 10 m"]
    assert "not judged" in wind_ax.get_title()


# -------------------- formerly tests/test_operability_figure.py

"""The operability figure's cell numbers (issue 37, item 13): sized to their cells as laid
out (they were 7 pt in cells some 60 pt wide), each inside its cell."""

from types import SimpleNamespace

import numpy as np
import pytest

import marinecdpr.report.figures as figures


def _study(n_hs: int, n_tp: int, headings=(180.0,)):
    rng = np.random.default_rng(3)
    grid = rng.uniform(0.0, 1.0, (n_hs, n_tp))
    grid[0, 0], grid[-1, -1] = 0.999, np.nan  # the widest number ("99.9"), a cell with no sea state
    return SimpleNamespace(
        headings_deg=headings, margin_N=0.0, per_heading={h: 0.5 for h in headings}, per_heading_interval=None,
        results=[SimpleNamespace(realisations=10)],
        scatter=SimpleNamespace(hs=np.arange(1.0, n_hs + 1), tp=np.arange(4.0, 4.0 + 2 * n_tp, 2.0),
                                probability=np.full((n_hs, n_tp), 1.0 / (n_hs * n_tp))),
        probability_grid=lambda h: grid)


@pytest.mark.parametrize("n_hs, n_tp, headings", [(7, 6, (180.0,)), (7, 6, (180.0, 150.0)), (14, 12, (180.0,))])
def test_cell_numbers_fill_their_cells_and_stay_inside(paper, captured_figures, tmp_path, n_hs, n_tp, headings):
    figures.plot_operability(_study(n_hs, n_tp, headings), paper, tmp_path / "operability.png")
    fig = captured_figures["operability.png"]
    fig.draw_without_rendering()
    renderer = fig.canvas.get_renderer()
    for ax in fig.axes[:len(headings)]:
        box = ax.get_window_extent(renderer)
        cell_w, cell_h = box.width / n_tp, box.height / n_hs
        assert len(ax.texts) == n_hs * n_tp - 1
        sizes = {t.get_fontsize() for t in ax.texts}
        assert len(sizes) == 1  # one size in a panel
        size = sizes.pop()
        assert figures.CELL_FONT_PT[0] <= size <= figures.CELL_FONT_PT[1]
        for t in ax.texts:
            e = t.get_window_extent(renderer)
            j, i = t.get_position()
            x0, y0 = box.x0 + j * cell_w, box.y0 + i * cell_h  # its cell's corner
            assert x0 <= e.x0 and e.x1 <= x0 + cell_w and y0 <= e.y0 and e.y1 <= y0 + cell_h
        widest = max(t.get_window_extent(renderer).width for t in ax.texts)
        tallest = max(t.get_window_extent(renderer).height for t in ax.texts)
        # as large as fits: the widest at 80 % of a cell's width or the tallest at half its height (to the
        # pixel: text extents are whole pixels), or the largest size
        assert widest <= 0.8 * cell_w + 1 and tallest <= 0.5 * cell_h + 1
        assert widest >= 0.8 * cell_w - 2 or tallest >= 0.5 * cell_h - 2 or size == figures.CELL_FONT_PT[1]
    if (n_hs, n_tp) == (7, 6):  # the package's illustrative diagram: numbers well above the old 7 pt
        assert size >= 11.0


# -------------------- formerly tests/test_rao_figure.py

"""rao.png: its legend outside the plots (issue 37, item 13: it covered the heave axis's
label and lines)."""


import numpy as np

from marinecdpr.motion.rao import box_hull_rao
from marinecdpr.report import figures


def test_the_rao_figure_s_legend_covers_no_plot(tmp_path, monkeypatch):
    """Each legend's box on the drawn figure overlaps no axes' box, labels and ticks
    included (matplotlib's tight boxes), and lies inside the figure."""
    kept = []
    real_save = figures._save
    monkeypatch.setattr(figures, "_save", lambda fig, path, **kw: (kept.append(fig), real_save(fig, path, **kw))[1])
    omega = np.linspace(0.2, 1.8, 33)
    kw = dict(length_m=100.0, beam_m=20.0, draught_m=6.0, gm_m=1.5, omega=omega, heading_deg=[90, 120, 150, 180])
    bem, box = box_hull_rao(roll_damping_ratio=0.05, **kw), box_hull_rao(roll_damping_ratio=0.1, **kw)
    path = figures.plot_raos(bem, tmp_path / "rao.png", title="RAOs", beside=box,
                             beside_label="box approximation of the same main dimensions and GM")
    assert path.is_file()
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    (fig,) = kept
    FigureCanvasAgg(fig).draw()  # the figure as saved (its own canvas closed with it)
    renderer = fig.canvas.get_renderer()
    legends = list(fig.legends) + [ax.get_legend() for ax in fig.axes if ax.get_legend() is not None]
    assert len(legends) == 1 and len(legends[0].get_texts()) == 5  # 4 headings, the dashed lines
    box_ = legends[0].get_window_extent(renderer)
    for ax in fig.axes:
        assert not box_.overlaps(ax.get_tightbbox(renderer)), ax.get_ylabel()
    assert fig.bbox.contains(box_.x0, box_.y0) and fig.bbox.contains(box_.x1, box_.y1)
