"""Issue 21, items 2 and 21: Ctrl-C is one line on stderr and exit 130 at any moment of a
command (while its modules load, while it reads its input, while it works, while it commits
its files), to the command alone or to its whole process group (its Dask workers too), and
it leaves no staging folder behind."""

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

EXE = str(Path(sys.executable).parent / "marinecdpr")


def _default_sigint() -> None:
    # a test run in a shell's background inherits SIGINT ignored: give the command a terminal's default
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _catches_sigint(pid: int) -> bool:
    """Has the process's interpreter installed its SIGINT handler (the C-level catch that
    Python sets up before it runs any of the program's code)?"""
    try:
        status = Path(f"/proc/{pid}/status").read_text()
    except OSError:
        return True  # gone already, or no /proc: nothing to wait for
    caught = next(line for line in status.splitlines() if line.startswith("SigCgt:"))
    return bool(int(caught.split()[1], 16) & (1 << (signal.SIGINT - 1)))


def _interrupt_after(args, delay: float, *, group: bool = False, cwd=None):
    """Run ``marinecdpr args``, send SIGINT ``delay`` s after its interpreter is up (to it
    alone, or to its process group); return (exit code, stderr)."""
    proc = subprocess.Popen([EXE, *args], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=cwd,
                            preexec_fn=_default_sigint, start_new_session=group)
    deadline = time.monotonic() + 60
    while not _catches_sigint(proc.pid) and time.monotonic() < deadline:
        time.sleep(0.002)
    time.sleep(delay)
    if group:
        os.killpg(proc.pid, signal.SIGINT)
    else:
        proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=120)
    return proc.returncode, err


@pytest.mark.parametrize("delay", [0.1, 0.5, 1.0, 2.5, 4.0])
def test_ctrl_c_at_any_moment_is_one_line_and_exit_130(tmp_path, delay):
    # a long workspace map (20 000 poses): still working at 4 s, its first progress line
    # (10 %) far later; an interrupt anywhere from the imports to the work is one line
    out = tmp_path / "out"
    code, err = _interrupt_after(["workspace", "paper", "--points", "200x100", "--out", str(out)], delay)
    assert code == 130, err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert lines[0] in ("error: interrupted", f"error: interrupted; --out {out} keeps what it held"), err
    assert not out.exists()


def test_ctrl_c_that_typer_would_swallow_still_prints_its_line():
    # a KeyboardInterrupt outside the output folder's block (here: while the scenario loads)
    # became typer's silent exit 130
    code = (
        "import signal, sys\n"
        "import marinecdpr.cli.app as app\n"
        "import marinecdpr.scenario.loading as loading\n"
        "def interrupted(*a, **k):\n"
        "    raise KeyboardInterrupt\n"
        "app.load_scenario = interrupted\n"
        "sys.argv = ['marinecdpr', 'check', 'paper']\n"
        "app.main()\n"
    )
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert res.returncode == 130
    assert res.stderr.strip().splitlines() == ["error: interrupted"]
