"""Figures drawn at their resolution (issue 10, item 6): every time series thinned to its
pixel columns with every extreme kept, and the main job's figures drawn in two processes
with the same files as in one."""

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
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, env=env, timeout=300)
    assert out.stdout.split() == ["False", "False"], out.stderr
    marinecdpr.simulate(marinecdpr.load_scenario("paper"), run="open_loop", n_steps=10)  # compiled or loaded
    assert kernels_cached("mujoco")
