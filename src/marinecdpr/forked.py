"""Work handed to a forked copy of this process, where that is safe and pays.

The main job uses it to fly one of its runs and to draw two of its figures on the second
core while this process does the rest (:func:`~marinecdpr.studies.prototype_runs.virtual_prototype`,
:func:`~marinecdpr.report.writers.write_virtual_prototype`).
"""

from __future__ import annotations

import os
import signal
import sys
import threading

__all__ = ["can_fork", "Forked"]


def can_fork() -> bool:
    """True where work can go to a forked process, safely and to some gain: on Linux, with
    two CPUs or more, from a process running no other Python thread (one could hold a
    lock the copy would wait for forever) and allowed children (not a daemon, such as a
    pool's worker)."""
    import multiprocessing

    return (sys.platform.startswith("linux") and "fork" in multiprocessing.get_all_start_methods()
            and len(os.sched_getaffinity(0)) >= 2 and threading.active_count() == 1
            and not multiprocessing.current_process().daemon)


class Forked:
    """``fn()`` run in a forked copy of this process while this one goes on (where
    :func:`can_fork`; else by :meth:`result`, here).

    The copy shares this process's state as it is at the fork (data, imports, caches:
    nothing is pickled on the way in); it ignores Ctrl-C (this process handles it and
    ends the copy) and is killed if this process dies. Call :meth:`result` for ``fn``'s
    value or exception (an OSError keeps its errno), and :meth:`stop` in any case.
    """

    def __init__(self, fn):
        self._fn = fn
        self._process = None
        if not can_fork():
            return
        import multiprocessing
        import warnings

        ctx = multiprocessing.get_context("fork")
        self._conn, child_end = ctx.Pipe(duplex=False)
        self._process = ctx.Process(target=_child_main, args=(fn, child_end, os.getpid()), daemon=True)
        with warnings.catch_warnings():
            # Python >= 3.12 warns of fork() in a process with threads; ours are BLAS's idle
            # workers (fork-safe), and the copy only computes and draws
            warnings.filterwarnings("ignore", category=DeprecationWarning, message=".*fork")
            self._process.start()
        child_end.close()

    def result(self):
        if self._process is None:
            return self._fn()
        try:
            ok, value = self._conn.recv()
        except EOFError:  # it died without a word
            self._process.join()
            ok, value = False, RuntimeError(f"the forked process ended with exit code "
                                            f"{self._process.exitcode}")
        self._process.join()
        if not ok:
            raise value
        return value

    def stop(self) -> None:
        """End the copy if it still runs, and wait for it."""
        if self._process is None:
            return
        if self._process.is_alive():
            self._process.terminate()
        self._process.join()
        self._conn.close()


def _child_main(fn, conn, parent: int) -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:  # die with the parent (Linux): a killed command leaves no process drawing
        import ctypes

        ctypes.CDLL(None, use_errno=True).prctl(1, signal.SIGKILL, 0, 0, 0)  # PR_SET_PDEATHSIG
    except (OSError, AttributeError):
        pass
    if os.getppid() != parent:
        os._exit(1)
    try:
        out = (True, fn())
    except BaseException as exc:  # noqa: BLE001 - handed to the parent, which raises it
        out = (False, exc)
    try:
        conn.send(out)
    except Exception as exc:  # noqa: BLE001 - the value or exception does not pickle
        failure = out[1] if not out[0] else exc
        conn.send((False, RuntimeError(f"{type(failure).__name__}: {failure}")))
    conn.close()
