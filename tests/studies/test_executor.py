"""One executor for the studies' independent pieces (issue 38, item 2): its rules (``--serial``
alone, at most four workers a core, a scheduler that answers, Dask where Dask is asked for,
``auto`` by size and serial without Dask) and its one ``map``, whose results are the same to
the bit serially and on a local Dask cluster."""

import os
import socket
import sys

import numpy as np
import pytest

from marinecdpr.errors import ScenarioError
from marinecdpr.studies.executor import (AUTO_DASK_MIN_STEPS, LOCAL_WORKERS, NO_DASK_NOTE, WORKERS_PER_CORE,
                                         Executor, ExecutorError)
from marinecdpr.studies.operability import Cell, evaluate_cell
from dask_cluster import dask_scheduler  # noqa: F401  (a fixture: the test process's shared Dask cluster)
from test_operability import sea_robot


def _no_dask(monkeypatch):
    """``import dask.distributed`` fails, as on a machine without the [dask] extra."""
    monkeypatch.setitem(sys.modules, "dask.distributed", None)


@pytest.fixture
def listening():
    """An address where something answers (a TCP socket listening): a scheduler's, to the check."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        s.listen()
        yield f"tcp://127.0.0.1:{s.getsockname()[1]}"


def test_serial_goes_alone():
    for options, option, value in ((dict(workers=3), "workers", 3),
                                   (dict(scheduler="tcp://127.0.0.1:8786"), "scheduler", "tcp://127.0.0.1:8786")):
        with pytest.raises(ExecutorError) as err:
            Executor.choose(serial=True, **options)
        assert (err.value.option, err.value.value) == (option, value)
        assert str(err.value) == f"--{option} {value}: cannot go with --serial (--workers and --scheduler run on Dask)"
    with pytest.raises(ExecutorError, match="--workers 3: cannot go with --serial"):
        Executor(kind="serial", workers=3)
    assert Executor.choose(serial=True, steps=10 * AUTO_DASK_MIN_STEPS) == Executor.serial()


def test_at_most_four_workers_a_core(monkeypatch):
    monkeypatch.setattr(os, "cpu_count", lambda: 2)
    assert WORKERS_PER_CORE == 4
    assert Executor.local(8).workers == 8
    for workers in (9, 10 ** 9):
        with pytest.raises(ExecutorError) as err:
            Executor.local(workers)
        assert str(err.value) == (f"--workers {workers}: more than 4 per core of this machine's 2 gains nothing "
                                  "(each is a process of its own); use at most 8")
    with pytest.raises(ExecutorError, match="--workers 0: expected a positive whole number"):
        Executor.check(workers=0)


def test_a_scheduler_must_answer(listening, monkeypatch):
    ex = Executor.at(listening)
    assert (ex.kind, ex.address, ex.name, ex.describe()) == ("scheduler", listening, "dask", f"Dask at {listening}")
    assert Executor.choose(scheduler=listening, workers=3) == ex   # the scheduler's workers are its own
    with pytest.raises(ExecutorError, match=r"^--scheduler garbage: expected a Dask scheduler address like "
                                            r"tcp://host:8786$"):
        Executor.check(scheduler="garbage")

    def refused(address, timeout):
        assert timeout <= 5.0
        raise ConnectionRefusedError(111, "Connection refused")

    monkeypatch.setattr(socket, "create_connection", refused)
    with pytest.raises(ExecutorError, match=r"^--scheduler tcp://10\.0\.0\.5:8786: no Dask scheduler reachable "
                                            r"there \(connection refused\)$"):
        Executor.at("tcp://10.0.0.5:8786")
    with pytest.raises(ScenarioError):  # one line as the command line gives every ScenarioError
        Executor.choose(scheduler="10.0.0.5:8786")


def test_dask_asked_but_missing_is_refused_and_auto_runs_serially(listening, monkeypatch):
    _no_dask(monkeypatch)
    for make, said in ((lambda: Executor.local(2), "--workers 2"), (lambda: Executor.at(listening),
                                                                    f"--scheduler {listening}")):
        with pytest.raises(ExecutorError) as err:
            make()
        assert str(err.value) == (f"{said}: runs on Dask, which is not installed: pip install 'marinecdpr[dask]' "
                                  "(or leave it out to run serially)")
    big = Executor.auto(10 * AUTO_DASK_MIN_STEPS)
    assert (big.kind, big.why, big.note) == ("serial", "no dask", NO_DASK_NOTE)
    assert "pip install 'marinecdpr[dask]'" in big.note


def test_auto_by_size():
    small = Executor.auto(AUTO_DASK_MIN_STEPS - 1)
    assert (small.kind, small.why, small.note) == ("serial", "small", None)
    large = Executor.auto(AUTO_DASK_MIN_STEPS)
    assert (large.kind, large.workers, large.why, large.describe()) == ("local", LOCAL_WORKERS, "large",
                                                                        "Dask, 2 workers")
    assert Executor.choose(steps=AUTO_DASK_MIN_STEPS) == large
    assert Executor.choose(workers=1, steps=0).describe() == "Dask, 1 worker"


CELLS = [Cell(index=k, hs=hs, tp=tp, heading_deg=h, probability=0.25)
         for k, (hs, tp, h) in enumerate([(3.0, 6.0, 180.0), (0.5, 10.0, 120.0), (3.0, 10.0, 90.0)])]
KW = dict(margin_N=5.0, duration_s=30.0, step_s=0.05, realisations=2)


def test_serial_and_a_dask_cluster_give_the_same_results_to_the_bit(dask_scheduler):
    """On a running Dask cluster of two worker processes (the suite's shared one: a local
    cluster's own start and teardown are test_every_executor_gives_the_same_files' and
    test_a_piece_that_kills_its_workers_is_one_line's)."""
    template = sea_robot()
    serial = Executor.serial().map(evaluate_cell, template, CELLS, KW)
    # against the function called by hand: the executor adds nothing (repr: every float to
    # the bit, and NaN equal to NaN)
    assert repr(serial) == repr([evaluate_cell(template, c, **KW) for c in CELLS])
    seen, each = [], {}
    with Executor.at(dask_scheduler).session() as session:
        on_dask = session.map(evaluate_cell, template, CELLS, KW, progress=lambda d, n: seen.append((d, n)),
                              each=lambda k, r: each.setdefault(k, r))
        again = session.map(evaluate_cell, template, CELLS[::-1], KW)   # the same cluster, another order
        # a piece the cluster forgets (cancelled: a worker or the client's link lost on a loaded
        # machine) is sent again, with the shared template sent anew: the same results
        submit, cancelled = session.client.submit, []

        def forgetful(*args, **kwargs):
            fut = submit(*args, **kwargs)
            if not cancelled:
                cancelled.append(fut)
                session.client.cancel([fut])
            return fut

        session.client.submit = forgetful
        resent = session.map(evaluate_cell, template, CELLS, KW)
        del session.client.submit
    assert len(cancelled) == 1 and repr(resent) == repr(serial)
    assert [r.cell for r in on_dask] == CELLS                          # in the items' order
    assert [(r.operable, r.fraction_feasible, r.min_margin_N, r.successes) for r in on_dask] == \
        [(r.operable, r.fraction_feasible, r.min_margin_N, r.successes) for r in serial]
    assert repr(on_dask) == repr(serial) and repr(again) == repr(serial[::-1])
    assert [r.min_margin_N for r in serial] != [serial[0].min_margin_N] * 3   # the cells differ
    assert all(np.isfinite(r.min_margin_N) for r in serial)
    assert seen == [(1, 3), (2, 3), (3, 3)] and sorted(each) == [0, 1, 2]
    assert all(each[k] is on_dask[k] for k in each)
    # a piece's error reaches the caller as itself
    with pytest.raises(ValueError, match="realisations must be at least 1, got 0"):
        Executor.at(dask_scheduler).map(evaluate_cell, template, CELLS[:1], KW | {"realisations": 0})


def test_a_piece_that_kills_its_workers_is_one_line():
    """A piece of work whose every worker dies (here at once: the scheduler allowed no
    failure) is an ExecutorError of one line naming the workers, not Dask's traceback."""
    pytest.importorskip("dask.distributed")
    import dask

    with dask.config.set({"distributed.scheduler.allowed-failures": 0}):
        with pytest.raises(ExecutorError) as err:
            Executor.local(workers=1).map(lambda template, item: __import__("os")._exit(3), None, [1])
    assert "workers died" in str(err.value) and "\n" not in str(err.value) and err.value.option == "workers"
