"""Faults: a command killed or interrupted at any point leaves its output folder holding one
complete run (the previous one, or the new one), and a rerun works."""

import json
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from marinecdpr.report.files import read_manifest

EXE = str(Path(sys.executable).parent / "marinecdpr")


def _default_sigint() -> None:
    # a test run started in the background of a shell inherits SIGINT ignored, and Python
    # then leaves it ignored: give the command the default a user's terminal gives it
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _start(args, **kw):
    return subprocess.Popen([EXE, *args], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            preexec_fn=_default_sigint, **kw)


def _one_complete_run(folder: Path) -> str:
    """Assert that ``folder`` holds the files of exactly one main-job run; return its scenario."""
    names = {p.name for p in folder.iterdir() if not p.name.startswith(".")}
    listed = set(read_manifest(folder)[1])
    assert names == listed, (names, listed)
    s = json.loads((folder / "summary.json").read_text())
    for name in ("plan.csv", "sim_open_loop.csv", "sim_closed_loop.csv", "sim_fixed_base_open_loop.csv"):
        rows = np.loadtxt(folder / name, delimiter=",", skiprows=1, ndmin=2)
        assert rows.shape[0] == s["steps"], name
    html = (folder / "report.html").read_text()
    assert f"<title>marinecdpr: {s['scenario']}</title>" in html
    return s["scenario"]


@pytest.fixture(scope="module")
def paper_run(tmp_path_factory) -> Path:
    """A complete run of ``simulate paper --duration 0.5``, made once (in this process: the
    run is the tests' starting point, not what they are about): each test copies it into its
    own output folder as the previous run there."""
    from typer.testing import CliRunner

    from marinecdpr.cli.app import app

    out = tmp_path_factory.mktemp("paper_run") / "out"
    first = CliRunner().invoke(app, ["simulate", "paper", "--duration", "0.5", "--out", str(out)])
    assert first.exit_code == 0, first.output
    return out


def test_sigkill_at_any_point_leaves_one_complete_run(tmp_path, paper_run):
    out = tmp_path / "out"
    shutil.copytree(paper_run, out)
    assert _one_complete_run(out) == "paper"
    seen = set()
    # one kill in each phase of a run's writing, found by watching the folder (not by the
    # clock, which a loaded machine stretches): while it starts (no staging folder yet),
    # while it works (its staging folder empty), while it writes its files into the staging
    # folder (the first ones there); the last run below is the whole run to its commit
    for phase in ("starting", "working", "writing"):
        proc = _start(["simulate", "paper_sea", "--duration", "0.3", "--out", str(out)])
        for _ in range(60_000):  # a hang guard by count, not by clock
            stages = list(out.glob(f".staging-{proc.pid}-*"))
            if phase == "starting" or proc.poll() is not None:
                break
            if stages and (phase == "working" or any(stages[0].iterdir())):
                break
            time.sleep(0.005)
        if phase == "starting":
            time.sleep(0.5)
            assert not list(out.glob(f".staging-{proc.pid}-*"))  # still in its imports
        proc.kill()
        proc.communicate(timeout=300)
        assert proc.returncode == -signal.SIGKILL, phase  # killed in that phase, not finished
        seen.add(_one_complete_run(out))
    assert seen == {"paper"}  # a killed run changes nothing
    # the next run, in this process (as paper_run: the kills above needed processes of their own)
    from typer.testing import CliRunner

    from marinecdpr.cli.app import app

    again = CliRunner().invoke(app, ["simulate", "paper_sea", "--duration", "0.3", "--out", str(out)])
    assert again.exit_code == 0, again.output
    assert _one_complete_run(out) == "paper_sea"
    assert [p.name for p in out.glob(".staging-*")] == []  # the killed runs' staging folders are gone


def test_sigint_is_one_line_exit_130_and_keeps_the_previous_run(tmp_path, paper_run):
    out = tmp_path / "out"
    shutil.copytree(paper_run, out)
    assert _one_complete_run(out) == "paper"
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    # a long run, interrupted while it simulates (the first progress line says it has begun)
    proc = _start(["simulate", "paper_sea", "--out", str(out)])
    line = proc.stderr.readline()
    assert line.startswith("simulate: "), line
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=300)
    assert proc.returncode == 130
    lines = [ln for ln in (line + err).splitlines() if not ln.startswith("simulate: ")]
    assert lines == [f"error: interrupted; --out {out} keeps what it held"]
    after = {p.name: p.read_bytes() for p in out.iterdir()}
    assert after == before


@pytest.mark.skipif(os.geteuid() != 0, reason="needs root to make a read-only bind mount")
def test_a_read_only_output_folder_is_one_line_before_the_work(tmp_path):
    out = tmp_path / "ro"
    out.mkdir()
    mounted = subprocess.run(["mount", "--bind", "-o", "ro", str(out), str(out)], capture_output=True)
    if mounted.returncode != 0:
        pytest.skip("bind mounts are not allowed here")
    try:
        subprocess.run(["mount", "-o", "remount,bind,ro", str(out)], capture_output=True)
        import tripwire

        res = tripwire.run_cli("simulate", "paper", "--out", str(out))  # refused before any work
        assert res.returncode == 2 and "Traceback" not in res.stderr
        assert res.stderr.strip().splitlines() == [
            f"error: --out {out}: cannot write there (Read-only file system)"]
    finally:
        subprocess.run(["umount", str(out)], capture_output=True)


@pytest.fixture()
def small_disk(tmp_path):
    """A file system with 16 KiB free: room for a staging folder, not for any run's files."""
    if os.geteuid() != 0:
        pytest.skip("needs root to mount a tmpfs")
    disk = tmp_path / "disk"
    disk.mkdir()
    if subprocess.run(["mount", "-t", "tmpfs", "-o", "size=256k", "tmpfs", str(disk)],
                      capture_output=True).returncode != 0:
        pytest.skip("mounting a tmpfs is not allowed here")
    (disk / "filler").write_bytes(b"\0" * (240 * 1024))
    yield disk
    subprocess.run(["umount", str(disk)], capture_output=True)


def _used(folder: Path) -> str:
    return subprocess.run(["df", "--output=used", str(folder)], capture_output=True, text=True).stdout.split()[-1]


@pytest.mark.figures
@pytest.mark.parametrize("args", [
    ["plan", "paper"],
    ["simulate", "paper", "--duration", "0.3"],
    ["workspace", "paper", "--points", "12x8", "--duration", "0.5", "--step", "0.05"],
    ["operability", "paper_sea", "--serial", "--duration", "10", "--step", "0.1", "--realisations", "2"],
])
def test_a_full_disk_is_one_line_and_leaves_the_folder_as_it_was(args, small_disk):
    """Each command's files outgrow the 16 KiB left (a figure alone does), whatever the size
    of its job; run in this process (the disk is the point here, not the process)."""
    from typer.testing import CliRunner

    from marinecdpr.cli.app import app

    out = small_disk / "out"
    out.mkdir()
    (out / "keep.txt").write_text("a previous file")
    used = _used(small_disk)
    res = CliRunner().invoke(app, [*args, "--out", str(out)])
    assert res.exit_code == 2, res.output
    assert res.exception is None or isinstance(res.exception, SystemExit), res.exception  # no traceback
    assert "Traceback" not in res.output
    last = res.stderr.strip().splitlines()[-1]
    assert last == f"error: --out {out}: could not write the files (No space left on device); the folder keeps what it held"
    assert sorted(p.name for p in out.iterdir()) == ["keep.txt"]
    assert _used(small_disk) == used  # the staging folder and its partial files are gone


def test_sigint_to_operability_on_dask_leaves_no_worker_behind(tmp_path):
    psutil = pytest.importorskip("psutil")
    out = tmp_path / "out"
    proc = _start(["operability", "paper_sea", "--workers", "2", "--duration", "1800", "--step", "0.005", "--realisations", "1",
                   "--headings", "180,150,90", "--out", str(out)])
    children = []
    while len(children) < 3 and proc.poll() is None:  # until the workers are up (and their nannies),
        time.sleep(0.5)                                 # however long a loaded machine takes
        children = psutil.Process(proc.pid).children(recursive=True)
    assert len(children) >= 2, proc.poll()
    time.sleep(2.0)
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=300)
    assert proc.returncode == 130
    assert err.strip().splitlines()[-1] == f"error: interrupted; --out {out} keeps what it held"
    assert "WARNING" not in err and "Traceback" not in err
    _, alive = psutil.wait_procs(children, timeout=300)  # a hang guard, not a speed check
    assert [c.pid for c in alive if c.is_running() and c.status() != psutil.STATUS_ZOMBIE] == []
    assert not out.exists()


# -------------------- formerly tests/test_output_folders.py

"""An output folder holds one command's results: a run of another command into it is refused
(one line naming the command that wrote them, exit 2), never emptied silently; the same command
replaces its own files (issue 37, item 5)."""

from pathlib import Path

import marinecdpr
from typer.testing import CliRunner

from marinecdpr.cli.app import app
from marinecdpr.report.files import MANIFEST, StagedOutput, read_manifest

runner = CliRunner()
PAPER = (Path(marinecdpr.__file__).parent / "scenario" / "builtin" / "paper.toml").read_text()


def _short_paper(folder: Path, seconds: float) -> Path:
    path = folder / f"paper_{seconds:g}.toml"
    path.write_text(PAPER.replace("duration_s = 15.0", f"duration_s = {seconds:g}"))
    return path


def _listing(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir()) if p.is_file()}


def test_plan_into_simulate_s_folder_is_refused_and_keeps_its_files(tmp_path):
    out = tmp_path / "out"
    sim = runner.invoke(app, ["simulate", "paper", "--duration", "0.2", "--out", str(out)])
    assert sim.exit_code == 0, sim.output
    before = _listing(out)
    assert {"report.html", "summary.json", "sim_closed_loop.csv"} <= set(before)
    res = runner.invoke(app, ["plan", str(_short_paper(tmp_path, 0.5)), "--out", str(out)], terminal_width=2000)
    assert res.exit_code == 2, res.output
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"error: --out {out}: holds the results of 'simulate' ("), lines
    assert "give plan another --out" in lines[0]
    assert _listing(out) == before  # every file as simulate wrote it, byte for byte
    assert [p.name for p in out.glob(".staging-*")] == []


@pytest.mark.figures
def test_the_same_command_replaces_its_own_files(tmp_path):
    out = tmp_path / "out"
    (out).mkdir()
    (out / "notes.txt").write_text("mine")
    for seconds, rows in ((1.0, 1001), (0.5, 501)):
        res = runner.invoke(app, ["plan", str(_short_paper(tmp_path, seconds)), "--out", str(out)])
        assert res.exit_code == 0, res.output
        assert len((out / "plan.csv").read_text().splitlines()) == rows + 1  # the header and one row a step
    assert read_manifest(out) == ("plan", ["plan.csv", "tensions.png"])
    assert (out / "notes.txt").read_text() == "mine"  # a file no run wrote is never touched


@pytest.mark.figures
def test_another_command_refused_in_windows_folder_then_free_once_its_files_are_gone(tmp_path):
    out = tmp_path / "out"
    win = runner.invoke(app, ["windows", "--duration-h", "6", "--hs-limit", "2", "--out", str(out)])
    assert win.exit_code == 0, win.output
    written = read_manifest(out)
    assert written[0] == "windows" and "windows.csv" in written[1]
    scen = str(_short_paper(tmp_path, 0.5))
    res = runner.invoke(app, ["plan", scen, "--out", str(out)], terminal_width=2000)
    assert res.exit_code == 2 and "holds the results of 'windows'" in res.stderr
    for name in written[1]:
        (out / name).unlink()  # the user cleared them: the folder is free
    res = runner.invoke(app, ["plan", scen, "--out", str(out)])
    assert res.exit_code == 0, res.output
    assert read_manifest(out) == ("plan", ["plan.csv", "tensions.png"])


def test_a_manifest_naming_no_command_loses_only_the_names_written_again(tmp_path):
    """A folder written before commands were recorded: its files that the new run does not
    write are kept (the manifest said nothing of which command wrote them)."""
    out = tmp_path / "out"
    out.mkdir()
    (out / MANIFEST).write_text("plan.csv\nreport.html\n")
    (out / "plan.csv").write_text("old")
    (out / "report.html").write_text("old report")
    with StagedOutput(out, command="plan") as stage:
        (stage / "plan.csv").write_text("new")
    assert (out / "plan.csv").read_text() == "new"
    assert (out / "report.html").read_text() == "old report"
    assert read_manifest(out) == ("plan", ["plan.csv"])


# -------------------- formerly tests/test_issue21_atomic_writers.py

"""Issue 21, item 15: the library's CSV writers (ship motion, RAO tables) replace their file
whole, as every other writer does (textfiles.atomic_path): a reader holding the old file, or
a write that fails half-way, never sees a half-written or truncated file."""

import os

import numpy as np
import pytest

from marinecdpr.motion import rao as rao_module
from marinecdpr.motion import recorded
from marinecdpr.motion.rao import box_hull_rao, read_rao_csv, write_rao_csv
from marinecdpr.motion.recorded import read_motion_csv, write_motion_csv


def _motion():
    t = np.arange(0.0, 20.0, 0.1)
    eta = np.zeros((t.size, 6))
    eta[:, 2] = 0.3 * np.sin(0.5 * t)
    eta[:, 3] = 0.02 * np.sin(0.7 * t)
    return t, eta


def _rao():
    return box_hull_rao(length_m=100.0, beam_m=20.0, draught_m=5.0, gm_m=2.0, roll_damping_ratio=0.05,
                        omega=np.linspace(0.2, 1.8, 9), heading_deg=np.array([90.0, 180.0]))


WRITERS = {
    "motion": (lambda path: write_motion_csv(path, *_motion()), recorded, "np", "savetxt"),
    "rao": (lambda path: write_rao_csv(_rao(), path), rao_module, "builtins", "open"),
}


@pytest.mark.parametrize("kind", sorted(WRITERS))
def test_a_writer_replaces_the_file_and_leaves_other_links_alone(kind, tmp_path):
    """Written to a new file and renamed: a hard link to the old file (a reader holding it)
    keeps the old bytes; a writer that opens the target itself truncates them."""
    write, *_ = WRITERS[kind]
    path, held = tmp_path / "table.csv", tmp_path / "held.csv"
    path.write_text("old contents\n")
    os.link(path, held)
    write(path)
    assert held.read_text() == "old contents\n"
    assert path.read_text() != "old contents\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["held.csv", "table.csv"]  # no temporary left


@pytest.mark.parametrize("kind", sorted(WRITERS))
def test_a_write_that_fails_half_way_leaves_the_previous_file(kind, tmp_path, monkeypatch):
    write, module, owner, name = WRITERS[kind]
    path = tmp_path / "table.csv"
    path.write_text("old contents\n")

    class Full(OSError):
        pass

    if kind == "motion":
        real = np.savetxt

        def savetxt(fname, *args, **kwargs):
            with open(fname, "w") as fh:
                fh.write("time_s,x_m\n0,")  # half a file, then the disk is full
            raise Full(28, "No space left on device")

        monkeypatch.setattr(recorded.np, "savetxt", savetxt)
    else:
        import builtins

        real_open = builtins.open

        class Half:
            def __init__(self, fh):
                self.fh = fh

            def __enter__(self):
                return self

            def __exit__(self, *exc):
                self.fh.close()

            def write(self, text):
                self.fh.write(text[:10])
                raise Full(28, "No space left on device")

        monkeypatch.setattr(builtins, "open", lambda f, mode="r", *a, **k: Half(real_open(f, mode, *a, **k))
                            if "w" in mode else real_open(f, mode, *a, **k))
    with pytest.raises(Full):
        write(path)
    monkeypatch.undo()
    assert path.read_text() == "old contents\n"
    assert [p.name for p in tmp_path.iterdir()] == ["table.csv"]


def test_the_written_tables_read_back(tmp_path):
    t, eta = _motion()
    write_motion_csv(tmp_path / "m.csv", t, eta)
    table = np.loadtxt(tmp_path / "m.csv", delimiter=",", skiprows=1)
    np.testing.assert_allclose(table[:, 0], t, rtol=0, atol=0)
    np.testing.assert_allclose(np.radians(table[:, 4]), eta[:, 3], rtol=1e-15)
    assert read_motion_csv(tmp_path / "m.csv").time_range_s == (0.0, t[-1])
    r = _rao()
    write_rao_csv(r, tmp_path / "r.csv", comments=("RAOs from a test", "made by: \x1b[31mme"))
    text = (tmp_path / "r.csv").read_text()
    assert text.startswith("# RAOs from a test\n# made by: [31mme\n")
    np.testing.assert_allclose(read_rao_csv(tmp_path / "r.csv").values, r.values, rtol=1e-12, atol=1e-15)
