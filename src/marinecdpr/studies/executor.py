"""What runs a study's independent pieces (sea states, candidates): one :class:`Executor`.

An executor is serial (this process, one piece after another), a local Dask cluster of a
few worker processes started for the work and torn down after it, or a running Dask
scheduler's address. It checks its options when it is made (:meth:`Executor.choose`:
``--serial`` alone; at most :data:`WORKERS_PER_CORE` workers per core; a scheduler that
answers; Dask installed where Dask is asked for; ``auto`` serial below
:data:`AUTO_DASK_MIN_STEPS` or without Dask) and runs the work with one method,
:meth:`Executor.map`, whose results are in the pieces' order and the same, bit for bit,
whichever executor runs them (each piece is computed from its own arguments alone). A
cluster's start, its Ctrl-C and its teardown are here and nowhere else::

    from marinecdpr.studies.executor import Executor

    ex = Executor.local(workers=2)            # or Executor.serial(), Executor.at("tcp://10.0.0.5:8786")
    squares = ex.map(pow, 2, [1, 2, 3])       # [2, 4, 8]: pow(2, item) for each item

Work that maps many times over one cluster (a search's generations) opens a
:meth:`Executor.session` and maps in it.
"""

from __future__ import annotations

import logging
import os
import signal
import threading
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Any, Callable, Iterator, Sequence

from marinecdpr.errors import ScenarioError
from marinecdpr.memory import keep_freed_memory

__all__ = ["Executor", "ExecutorError", "Session", "dask_installed", "LOCAL_WORKERS", "WORKERS_PER_CORE",
           "AUTO_DASK_MIN_STEPS", "SCHEDULER_TIMEOUT_S", "KINDS"]

KINDS = ("serial", "local", "scheduler")
"""An executor's kinds: this process, a local Dask cluster, a running Dask scheduler."""
LOCAL_WORKERS = 2
"""The local Dask cluster's worker processes where none are asked for."""
WORKERS_PER_CORE = 4
"""Most local Dask workers per core a study starts (more gains nothing: each is a process)."""
SCHEDULER_TIMEOUT_S = 5.0
"""How long a Dask scheduler's address may take to answer before it counts as unreachable."""

# A local Dask cluster costs ~1.3 s to start and to import the package in its workers, and
# on a 2-core machine its two workers plan at only ~1.3x the speed of one process (the
# plans are memory-bound; the client and scheduler share the cores). Measured with
# `benchmarks/bench_operability.py --crossover` on the 2-core CI machine (2026-12-01;
# paper_sea, 20-min records at 50 Hz; each run a fresh process, Dask's start included;
# fastest of 3-5 runs, serial s vs 2-worker Dask s):
#      0.48 M steps (16 cells x 600 s)              0.57 vs  2.10
#      2.04 M steps (the default study, 34 cells)   1.41 vs  2.07
#      2.59 M steps (9 cells x 60 s x 12x8 poses)   1.94 vs  2.37
#      6.00 M steps (100 cells)                     4.20 vs  3.98   <- crossover, quiet machine
#      9.80 M steps (34 cells x 60 s x 12x8 poses)  7.77 vs  5.76
#     13.5  M steps (225 cells)                     9.46 vs  7.33
#     24.0  M steps (400 cells)                    16.37 vs 12.27
# Beyond that crossover Dask saves ~25 %. While other work shares the two cores, Dask
# loses far longer (2.16 M steps: 3.2 s vs 7.9 s; 10.4 M: 15.1 s vs 17.9 s; 13.5 M: 9.5 s
# vs 14.3 s) and wins again from ~20 M steps (24 M: 16.4 s vs 13.9 s). Auto therefore
# starts Dask at 20 M steps (~15 s serially), where it is faster busy or not.
FORGOTTEN_RETRIES = 2
"""How many times a session sends again the pieces of work a Dask cluster cancelled (forgot:
a worker lost, or the client's link to the scheduler timed out on a loaded machine)."""

LOCAL_CLUSTER_CONFIG = {"distributed.worker.profile.enabled": False}
"""Dask configuration set while a local cluster starts (its workers keep it): no sampling
profiler in the workers. Each worker's profiler walks its running piece's stack every
10 ms, for the dashboard's profile, which nobody reads during a study. Without it a 2-worker
study took less CPU, the command and its workers together (interleaved pairs of fresh runs,
--workers 2, on the 2-core machine shared with other work, 2026-12-07; the same files to the
byte): operability paper_sea --duration 120 --headings 180,90, 1.8-4.7 s less of ~30 s in 4
of 5 pairs, 0.8 s more in one (mean -2.1 s, -7 %); clean paper_clean --seas over 4 sea states
of 10 s, 0.6-2.0 s less of ~12 s in 5 of 5 pairs (-7 %). Wall times drifted too much on the
shared machine to tell."""

AUTO_DASK_MIN_STEPS = 20_000_000
""":meth:`Executor.auto` runs serially below this many time steps of work in all (a
sea-state study's cells x steps per cell, :func:`~marinecdpr.studies.operability.study_steps`),
on a local Dask cluster from it."""

NO_DASK_NOTE = ("running the sea states serially: Dask is not installed "
                "(pip install 'marinecdpr[dask]' to run them in parallel)")
""":attr:`Executor.note` where ``auto`` would have run on Dask but Dask is not installed."""


class ExecutorError(ScenarioError):
    """An executor's option is wrong: one line, ``"--{option} {value}: {detail}"`` (a
    :class:`~marinecdpr.errors.ScenarioError`, as a request the machine cannot run).

    Attributes
    ----------
    option : str
        ``serial``, ``workers`` or ``scheduler`` (a command's option, a spec's field).
    value : object
        The value as given.
    detail : str
        What is wrong and what was expected.
    """

    def __init__(self, option: str, value: object, detail: str):
        super().__init__(f"--{option} {value}: {detail}")
        self.option, self.value, self.detail = option, value, detail


def dask_installed() -> bool:
    """Is ``dask.distributed`` importable?"""
    try:
        import dask.distributed  # noqa: F401
    except ImportError:
        return False
    return True


def _cores() -> int:
    return os.cpu_count() or 1


def _check_workers(workers: int) -> None:
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise ExecutorError("workers", workers, "expected a positive whole number of worker processes")
    cores = _cores()
    if workers > WORKERS_PER_CORE * cores:
        raise ExecutorError("workers", workers, f"more than {WORKERS_PER_CORE} per core of this machine's {cores} "
                            f"gains nothing (each is a process of its own); use at most {WORKERS_PER_CORE * cores}")


def _shown(address: str) -> str:
    return address.encode("ascii", "backslashreplace").decode()[:200]


def _host_port(address: str) -> tuple[str, int]:
    """A scheduler address's host and port; ExecutorError where it is no ``tcp://host:port``."""
    from urllib.parse import urlsplit

    where = address if "://" in address else f"tcp://{address}"
    try:
        parts = urlsplit(where)
        host, port = parts.hostname, parts.port
    except ValueError:
        parts, host, port = None, None, None
    if parts is None or parts.scheme != "tcp" or not host or port is None or parts.path not in ("", "/"):
        raise ExecutorError("scheduler", _shown(address), "expected a Dask scheduler address like tcp://host:8786")
    return host, port


def _check_answers(address: str, timeout_s: float = SCHEDULER_TIMEOUT_S) -> None:
    """Refuse a scheduler that does not answer within ``timeout_s`` (one line naming it)."""
    import socket

    host, port = _host_port(address)
    try:
        with socket.create_connection((host, port), timeout=timeout_s):
            pass
    except OSError as exc:
        reason = (f"no answer within {timeout_s:g} s" if isinstance(exc, TimeoutError)
                  else (exc.strerror or type(exc).__name__).lower())
        raise ExecutorError("scheduler", _shown(address), f"no Dask scheduler reachable there ({reason})") from None


def _require_dask(option: str, value: object) -> None:
    if not dask_installed():
        raise ExecutorError(option, value, "runs on Dask, which is not installed: pip install 'marinecdpr[dask]' "
                            "(or leave it out to run serially)")


@dataclass(frozen=True)
class Executor:
    """What runs a study's pieces. Make one with :meth:`serial`, :meth:`local`, :meth:`at`,
    :meth:`auto` or :meth:`choose` (which check what they are given); run work with
    :meth:`map`.

    Attributes
    ----------
    kind : {"serial", "local", "scheduler"}
    workers : int
        Processes: 1 serially, the local cluster's workers; 0 on a scheduler (its own).
    address : str, optional
        The scheduler's (``kind == "scheduler"``).
    why : str
        How it was chosen: "asked", or :meth:`auto`'s "no dask", "small", "large".
    """

    kind: str = "serial"
    workers: int = 1
    address: str | None = None
    why: str = "asked"

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ValueError(f"an executor's kind is one of {', '.join(KINDS)}, not {self.kind!r}")
        if self.kind == "serial" and (self.workers != 1 or self.address is not None):
            raise ExecutorError("workers" if self.address is None else "scheduler",
                                self.workers if self.address is None else self.address,
                                "cannot go with --serial (--workers and --scheduler run on Dask)")
        if self.kind == "local":
            if self.address is not None:
                raise ExecutorError("scheduler", self.address, "a local cluster has no scheduler's address")
            _check_workers(self.workers)
        if self.kind == "scheduler":
            if not self.address:
                raise ExecutorError("scheduler", self.address, "expected a Dask scheduler address like tcp://host:8786")
            if self.workers != 0:
                raise ExecutorError("workers", self.workers, "cannot go with --scheduler (its workers are its own)")

    # --- making one ----------------------------------------------------------------------

    @classmethod
    def serial(cls) -> Executor:
        """In this process, one piece after another."""
        return cls()

    @classmethod
    def local(cls, workers: int = LOCAL_WORKERS, *, why: str = "asked") -> Executor:
        """A local Dask cluster of ``workers`` processes, started for each :meth:`map` (or
        :meth:`session`) and torn down after it.

        Raises
        ------
        ExecutorError
            More than :data:`WORKERS_PER_CORE` workers per core, or Dask not installed.
        """
        _check_workers(workers)
        _require_dask("workers", workers)
        return cls(kind="local", workers=int(workers), why=why)

    @classmethod
    def at(cls, address: str) -> Executor:
        """A running Dask scheduler at ``address`` (``tcp://host:port`` or ``host:port``).

        Raises
        ------
        ExecutorError
            A malformed address, one where no scheduler answers within
            :data:`SCHEDULER_TIMEOUT_S`, or Dask not installed.
        """
        _check_answers(address)
        _require_dask("scheduler", _shown(address))
        return cls(kind="scheduler", workers=0, address=address)

    @classmethod
    def auto(cls, steps: int) -> Executor:
        """By the work's size: serially below :data:`AUTO_DASK_MIN_STEPS` steps ("small") or
        where Dask is not installed ("no dask": :attr:`note` says so), else a local cluster
        of :data:`LOCAL_WORKERS` ("large")."""
        if not dask_installed():
            return cls(why="no dask")
        if steps < AUTO_DASK_MIN_STEPS:
            return cls(why="small")
        return cls.local(LOCAL_WORKERS, why="large")

    @staticmethod
    def check(*, serial: bool = False, workers: int | None = None, scheduler: str | None = None) -> None:
        """The options' own rules, nothing asked of the machine's network or packages:
        ``serial`` alone, ``workers`` within :data:`WORKERS_PER_CORE` per core, a
        ``scheduler`` address of the right form.

        Raises
        ------
        ExecutorError
            Naming ``workers`` or ``scheduler`` where ``serial`` is given with it.
        """
        if serial and workers is not None:
            raise ExecutorError("workers", workers, "cannot go with --serial (--workers and --scheduler run on Dask)")
        if serial and scheduler:
            raise ExecutorError("scheduler", _shown(scheduler),
                                "cannot go with --serial (--workers and --scheduler run on Dask)")
        if workers is not None:
            _check_workers(workers)
        if scheduler:
            _host_port(scheduler)

    @classmethod
    def choose(cls, *, serial: bool = False, workers: int | None = None, scheduler: str | None = None,
               steps: int = 0) -> Executor:
        """A command's ``--serial``, ``--workers`` and ``--scheduler`` as an executor:
        serial; on the scheduler (``--workers`` then unused, as the scheduler's workers
        are its own); a local cluster of ``workers``; else :meth:`auto` by ``steps``.

        Raises
        ------
        ExecutorError
            :meth:`check`'s, :meth:`at`'s and :meth:`local`'s refusals.
        """
        cls.check(serial=serial, workers=workers, scheduler=scheduler)
        if serial:
            return cls.serial()
        if scheduler:
            return cls.at(scheduler)
        if workers is not None:
            return cls.local(workers)
        return cls.auto(steps)

    # --- what it is -----------------------------------------------------------------------

    @property
    def name(self) -> str:
        """"serial" or "dask" (what a study's result records)."""
        return "serial" if self.kind == "serial" else "dask"

    @property
    def note(self) -> str | None:
        """A line for the user where the choice needs one (Dask would have helped but is
        not installed), else None."""
        return NO_DASK_NOTE if self.why == "no dask" else None

    def describe(self) -> str:
        """``serial``, ``Dask, 2 workers`` or ``Dask at ADDRESS``."""
        if self.kind == "serial":
            return "serial"
        if self.kind == "scheduler":
            return f"Dask at {self.address}"
        return f"Dask, {self.workers} worker" + ("" if self.workers == 1 else "s")

    # --- running --------------------------------------------------------------------------

    def map(self, evaluate: Callable, template: Any, items: Sequence, kwargs: dict | None = None, *,
            progress: Callable[[int, int], None] | None = None,
            each: Callable[[int, Any], None] | None = None) -> list:
        """``evaluate(template, item, **kwargs)`` for every item, in the items' order.

        Parameters
        ----------
        evaluate : callable
            A module-level function (Dask's workers import it by name).
        template : object
            Shared by every piece: sent once to each worker.
        items : sequence
        kwargs : dict, optional
        progress : callable(done, total), optional
            After each piece, in the order they finish.
        each : callable(index, result), optional
            Each piece's result as it finishes (``index`` into ``items``).

        Raises
        ------
        KeyboardInterrupt
            Ctrl-C, after the cluster this started is torn down (quietly).
        """
        with self.session() as session:
            return session.map(evaluate, template, items, kwargs, progress=progress, each=each)

    @contextmanager
    def session(self) -> Iterator[Session]:
        """The executor held open for several :meth:`Session.map` calls (one cluster for a
        search's generations); torn down when the block ends, also on Ctrl-C or an error."""
        if self.kind == "serial":
            yield Session(None)
            return
        with _dask_client(self.address, self.workers) as client:
            yield Session(client)


class Session:
    """An :class:`Executor` held open: :meth:`map` as many times as the work needs."""

    def __init__(self, client) -> None:
        self.client = client
        self._shared: dict[int, tuple[Any, Any]] = {}

    def _share(self, obj: Any):
        """``obj`` on every worker, sent once a session (kept by identity)."""
        if id(obj) not in self._shared:
            # in a list: Dask scatters a list's (or tuple's) elements one by one
            self._shared[id(obj)] = (obj, self.client.scatter([obj], broadcast=True)[0])
        return self._shared[id(obj)][1]

    def map(self, evaluate: Callable, template: Any, items: Sequence, kwargs: dict | None = None, *,
            progress: Callable[[int, int], None] | None = None,
            each: Callable[[int, Any], None] | None = None) -> list:
        """As :meth:`Executor.map`, in this session."""
        kwargs = kwargs or {}
        items = list(items)
        total = len(items)
        results: list = [None] * total
        if self.client is None:
            for k, item in enumerate(items):
                results[k] = evaluate(template, item, **kwargs)
                if each is not None:
                    each(k, results[k])
                if progress is not None:
                    progress(k + 1, total)
            return results
        from concurrent.futures import CancelledError

        from dask.distributed import as_completed
        from distributed import KilledWorker

        todo, done = list(range(total)), 0
        for attempt in range(1, FORGOTTEN_RETRIES + 2):
            shared = self._share(template)
            futures = {self.client.submit(evaluate, shared, items[k], pure=False, **kwargs): k for k in todo}
            lost = []
            for fut in as_completed(futures):
                k = futures[fut]
                try:
                    results[k] = fut.result()
                except CancelledError:  # the cluster forgot it (a worker or the client's link lost under load)
                    lost.append(k)
                    continue
                except KilledWorker:  # every worker that took it died: one line, not Dask's traceback
                    raise ExecutorError("workers", len(self.client.scheduler_info().get("workers", {})),
                                        "the Dask workers died running a piece of work (out of memory, or killed): "
                                        "fewer workers, or a less loaded machine") from None
                done += 1
                if each is not None:
                    each(k, results[k])
                if progress is not None:
                    progress(done, total)
            if not lost:
                return results
            todo = sorted(lost)
            self._shared.clear()  # what was scattered may be gone with them: sent anew
        raise ExecutorError("workers", len(self.client.scheduler_info().get("workers", {})),
                            f"the Dask cluster dropped {len(todo)} of {total} pieces of work {FORGOTTEN_RETRIES + 1} "
                            "times (cancelled: a worker lost, or the client's link to the scheduler): fewer workers, "
                            "or a less loaded machine")


@contextmanager
def _sigint_deferred():
    """Ctrl-C (SIGINT) held back until the block ends, then raised as KeyboardInterrupt: a
    local cluster interrupted while it starts leaves Dask's own half-built state to fail
    noisily at exit. Only in the main thread (elsewhere the block runs as it is).

    Both a handler (as ``report.files`` holds its signals) and the signal mask: the
    handler holds a Ctrl-C whichever thread the signal reaches; the mask is inherited by
    the threads the block starts (the cluster's) and by the worker processes they start,
    so a Ctrl-C to the whole process group does not stop a worker while it starts (it
    printed its traceback, and its nanny's "failed to start").
    The workers ignore Ctrl-C from then on (:mod:`.dask_worker`). An error the block
    raises after a Ctrl-C is its consequence: the Ctrl-C is raised instead."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    caught = []
    previous = signal.signal(signal.SIGINT, lambda signum, frame: caught.append(signum))
    mask = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    try:
        try:
            yield
        finally:
            signal.pthread_sigmask(signal.SIG_SETMASK, mask)  # a held Ctrl-C reaches the handler now
    except BaseException:
        signal.signal(signal.SIGINT, previous)
        if caught:
            raise KeyboardInterrupt from None
        raise
    signal.signal(signal.SIGINT, previous)
    if caught:
        raise KeyboardInterrupt


@contextmanager
def _dask_client(scheduler: str | None, workers: int):
    """A Dask client for a study's work: on the ``scheduler`` at that address, or on a local
    cluster of ``workers`` processes started here and torn down at the end (also on Ctrl-C
    or an error, quietly: what its scheduler logs then is no news, the error raised says
    what happened).

    Raises
    ------
    ScenarioError
        Dask is not installed (an executor made while it was).
    """
    try:
        import dask
        from dask.distributed import Client, LocalCluster
    except ImportError:
        raise ScenarioError("Dask is not installed: pip install 'marinecdpr[dask]'") from None
    cluster = None
    if scheduler:
        _check_answers(scheduler)  # still there: one line, not Dask's own error 20 s later
        client = Client(scheduler, timeout="20s")
    else:
        # what workers log when their scheduler goes away (Ctrl-C) is no news; a piece that
        # fails raises its error here, through its future
        from multiprocessing import resource_tracker

        # started first, here: the thread that starts it is left with SIGINT unblocked, and
        # the workers that thread would start with it (see _sigint_deferred)
        resource_tracker.ensure_running()
        with _sigint_deferred(), dask.config.set(LOCAL_CLUSTER_CONFIG):  # the nannies pass it to their workers
            # the scheduler's HTTP server on a free port (None still binds 8787: two studies at
            # once, as the suite's two workers run them, printed distributed's "port in use")
            cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                   dashboard_address=":0", silence_logs=logging.CRITICAL,
                                   preload=[f"{__package__}.dask_worker"])  # Ctrl-C is ours to handle
            try:
                client = Client(cluster)
            except BaseException:
                cluster.close()
                raise
    stopped = False
    try:
        # Dask's nanny starts workers with MALLOC_TRIM_THRESHOLD_=65536: every piece would
        # page-fault its memory back in; the workers keep it instead (see marinecdpr.memory)
        client.run(keep_freed_memory)
        yield client
    except BaseException:
        # stopped (Ctrl-C) or failed: our own cluster is torn down mid-work, and what its
        # scheduler logs then (comms closed while it reports a result) is no news; the
        # error raised says what happened
        stopped = cluster is not None
        raise
    finally:
        if stopped:
            logging.disable(logging.CRITICAL)
        try:
            client.close()
            if cluster is not None:
                cluster.close()
        finally:
            if stopped:
                logging.disable(logging.NOTSET)
