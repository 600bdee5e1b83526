"""Faults: a command killed or interrupted at any point leaves its output folder holding one
complete run (the previous one, or the new one), and a rerun works."""

import json
import os
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


def test_sigkill_at_any_point_leaves_one_complete_run(tmp_path):
    out = tmp_path / "out"
    first = subprocess.run([EXE, "simulate", "paper", "--duration", "0.5", "--out", str(out)],
                           capture_output=True, text=True, timeout=300)
    assert first.returncode == 0, first.stderr
    assert _one_complete_run(out) == "paper"
    seen = set()
    for delay in (0.5, 1.5, 2.5, 3.5, 5.0, 8.0):
        proc = _start(["simulate", "paper_sea", "--duration", "0.3", "--out", str(out)])
        time.sleep(delay)
        proc.kill()
        proc.communicate(timeout=300)
        seen.add(_one_complete_run(out))
    assert seen <= {"paper", "paper_sea"}
    again = subprocess.run([EXE, "simulate", "paper_sea", "--duration", "0.3", "--out", str(out)],
                           capture_output=True, text=True, timeout=300)
    assert again.returncode == 0, again.stderr
    assert _one_complete_run(out) == "paper_sea"
    assert [p.name for p in out.glob(".staging-*")] == []  # the killed runs' staging folders are gone


def test_sigint_is_one_line_exit_130_and_keeps_the_previous_run(tmp_path):
    out = tmp_path / "out"
    first = subprocess.run([EXE, "simulate", "paper", "--duration", "0.5", "--out", str(out)],
                           capture_output=True, text=True, timeout=300)
    assert first.returncode == 0, first.stderr
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


@pytest.mark.parametrize("args", [
    ["plan", "paper"],
    ["simulate", "paper", "--duration", "1"],
    ["workspace", "paper", "--points", "40x30", "--duration", "0.5", "--step", "0.05"],
    ["operability", "paper_sea", "--serial", "--duration", "60", "--step", "0.1"],
])
def test_a_full_disk_is_one_line_and_leaves_the_folder_as_it_was(args, small_disk):
    out = small_disk / "out"
    out.mkdir()
    (out / "keep.txt").write_text("a previous file")
    used = _used(small_disk)
    res = subprocess.run([EXE, *args, "--out", str(out)], capture_output=True, text=True, timeout=300)
    assert res.returncode == 2, res.stderr
    assert "Traceback" not in res.stderr
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
