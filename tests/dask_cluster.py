"""One Dask cluster shared by the tests of a test process (each xdist worker, or the one
process of ``-n 0``) whose claim is that a study's results on Dask are its serial results:
they pass its address as a running scheduler's (``Executor.at(address)``, ``--scheduler``)
instead of each starting a local cluster of its own (~1.5-3 s of CPU each on the suite's two
cores: the cluster's start, then the package, numpy, scipy and numba imported in each new
worker). The tests of a local cluster's own start and teardown (``--workers``), of Ctrl-C
and of a worker killed keep their own clusters.

The cluster is the product's own local cluster (``executor._dask_client``: two worker
processes of one thread, Ctrl-C ignored in them), started in a process of its own, in a
session of its own: the test process's children (``multiprocessing.active_children()``,
which tests/report/test_figures.py checks is empty) and its process group stay as they
were. At the session's end that session is killed, all of it; should the test process die
first, however it dies, its stdin closes and it closes its cluster. A test module uses it
by importing the fixture::

    from dask_cluster import dask_scheduler  # noqa: F401  (a fixture)

    def test_on_dask(dask_scheduler):
        Executor.at(dask_scheduler) ...
"""

from __future__ import annotations

import os
import select
import shutil
import signal
import subprocess
import sys
import tempfile
import time

import pytest

START_TIMEOUT_S = 300.0
"""A hang guard for the cluster's start (a loaded machine takes seconds), not a speed check."""
STOP_TIMEOUT_S = 60.0
"""A hang guard for its processes' end once killed."""

_shared: dict = {"users": 0, "process": None, "address": None, "log": None, "scratch": None}
"""The one cluster of this test process: each module that imports :func:`dask_scheduler`
makes a fixture of its own (pytest caches a fixture per module that defines it), so they
count their users here and the last to end stops it."""


def _start() -> str:
    log = tempfile.TemporaryFile()
    scratch = tempfile.mkdtemp(prefix="marinecdpr-dask-")  # the workers' own folders, gone with them
    process = subprocess.Popen([sys.executable, "-c", _SERVE], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                               stderr=log, start_new_session=True,
                               env=dict(os.environ, DASK_TEMPORARY_DIRECTORY=scratch))
    _shared.update(process=process, log=log, scratch=scratch)
    ready, _, _ = select.select([process.stdout], [], [], START_TIMEOUT_S)
    address = process.stdout.readline().decode().strip() if ready else ""
    if not address.startswith("tcp://"):
        log.seek(0)
        said = log.read().decode(errors="replace")[-4000:]
        _stop()
        raise RuntimeError(f"the shared Dask cluster did not start: {said}")
    _shared["address"] = address
    return address


def _stop() -> None:
    """Its whole session killed at once (a cluster's orderly close took 3-5 s at the suite's
    end, for nothing kept), then waited for, its workers' folders removed."""
    process, log, scratch = _shared["process"], _shared["log"], _shared["scratch"]
    _shared.update(process=None, address=None, log=None, scratch=None)
    if process is None:
        return
    try:
        import psutil

        family = psutil.Process(process.pid).children(recursive=True)
    except Exception:  # psutil missing: the group's kill alone
        family = []
    alive = []
    try:
        os.killpg(process.pid, signal.SIGKILL)  # not waited for yet: the group is still its own
    except ProcessLookupError:
        pass
    process.wait()
    for _ in range(int(STOP_TIMEOUT_S / 0.01)):  # its workers, orphans now: ended (pid 1 reaps them when it will)
        alive = [p for p in family if _running(p)]
        if not alive:
            break
        time.sleep(0.01)
    assert not alive, f"the shared Dask cluster's processes outlived it: {alive}"
    process.stdin.close()
    process.stdout.close()
    log.close()
    shutil.rmtree(scratch, ignore_errors=True)


def _running(process) -> bool:
    """Neither gone nor a zombie (killed, not yet reaped)."""
    import psutil

    try:
        return process.is_running() and process.status() != psutil.STATUS_ZOMBIE
    except psutil.NoSuchProcess:
        return False


@pytest.fixture(scope="session")
def dask_scheduler():
    """The address (``tcp://127.0.0.1:PORT``) of this test process's shared Dask cluster:
    two worker processes of one thread each, as a study's own local cluster."""
    pytest.importorskip("dask.distributed")
    if _shared["process"] is None:
        _start()
    _shared["users"] += 1
    try:
        yield _shared["address"]
    finally:
        _shared["users"] -= 1
        if _shared["users"] == 0:
            _stop()


_SERVE = """
import os, sys
out = os.fdopen(os.dup(1), "w")
os.dup2(2, 1)  # the workers' stdout (none expected) to the log, never to a pipe nobody reads
from marinecdpr.studies.executor import LOCAL_WORKERS, _dask_client

with _dask_client(None, LOCAL_WORKERS) as client:
    print(client.scheduler_info()["address"], file=out, flush=True)
    out.close()
    sys.stdin.buffer.read()  # until the test process closes it, or ends
"""
"""The cluster's process (``python -c``: its workers import no test module): the product's
local cluster of two workers; its address on stdout; closed when stdin ends."""
