"""Shared fixtures: the paper scenario and small scenario builders."""

from __future__ import annotations

import copy
import tempfile
import time
import tomllib
from importlib import resources
from pathlib import Path

import pytest

import marinecdpr
from marinecdpr.scenario.loading import scenario_from_dict


_WARMING: list = []
"""The warm-up's process (gw0) while it runs: :func:`pytest_sessionstart`."""


def _warm_flag(workerinput) -> Path:
    return Path(tempfile.gettempdir()) / f"marinecdpr-warm-{workerinput['testrunuid']}"


def pytest_sessionstart(session):
    """On a cold compile cache, with several xdist workers, the first worker compiles the paper
    robot's planner, controller and both plants' loops before any test starts
    (``prototype.warmup.warm_up``, which compiles them in three processes at once) while the
    other workers wait; then every worker loads them from numba's cache. Without this the
    workers' first tests compiled the same kernels at once, each its own copy: a quarter of the
    suite's compile time on a cold cache was spent twice (numba's compile events, 2026-12-06).
    The warm-up runs in a process of its own, started here, while every worker collects the
    tests (some 12 s each: the warm-up alone left a core idle part of the time); the workers
    wait for it before their first test (:func:`pytest_collection_finish`). A warm cache
    skips it."""
    workerinput = getattr(session.config, "workerinput", None)
    if workerinput is None or int(workerinput.get("workercount", 1)) < 2:
        return
    from marinecdpr.prototype.simulation import kernels_cached

    if kernels_cached("mujoco") and kernels_cached("own"):
        _warm_flag(workerinput).touch()
        return
    if workerinput["workerid"] == "gw0":
        import subprocess
        import sys

        code = ("import marinecdpr\nfrom marinecdpr.prototype.warmup import warm_up\n"
                "warm_up([marinecdpr.load_scenario('paper')], plants=('mujoco', 'own'))\n")
        _WARMING.append(subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.DEVNULL,
                                         stderr=subprocess.DEVNULL))  # a failed warm-up: each test compiles its own


def pytest_collection_finish(session):
    """Wait for the warm-up (:func:`pytest_sessionstart`) before the first test: gw0 for its
    process (then it says so to the others), the other workers for gw0's word."""
    workerinput = getattr(session.config, "workerinput", None)
    if workerinput is None or int(workerinput.get("workercount", 1)) < 2:
        return
    done = _warm_flag(workerinput)
    if workerinput["workerid"] == "gw0":
        try:
            for process in _WARMING:
                process.wait(timeout=900)  # at most 15 minutes; a failed warm-up leaves each test its compile
        finally:
            done.touch()
        return
    for _ in range(3600):  # at most 15 minutes
        if done.exists():
            break
        time.sleep(0.25)


def pytest_sessionfinish(session):
    workerinput = getattr(session.config, "workerinput", None)
    if workerinput is not None and workerinput["workerid"] == "gw0":
        for process in _WARMING:
            process.kill()
        _warm_flag(workerinput).unlink(missing_ok=True)


def paper_dict() -> dict:
    """The built-in paper scenario as nested dicts (a fresh copy to edit)."""
    text = (resources.files("marinecdpr.scenario") / "builtin" / "paper.toml").read_text()
    return copy.deepcopy(tomllib.loads(text))


def make_scenario(edit=None, **sections):
    """The paper scenario with sections replaced and/or an edit function applied."""
    data = paper_dict()
    data.update(sections)
    if edit is not None:
        edit(data)
    return scenario_from_dict(data, source="test")


@pytest.fixture(scope="session")
def paper():
    return marinecdpr.load_scenario("paper")


@pytest.fixture(scope="session")
def paper_plan(paper):
    return marinecdpr.plan(paper)


@pytest.fixture(autouse=True)
def figures_only_where_marked(request):
    """The library's defaults table (:mod:`marinecdpr.defaults`) with ``report.figures`` off
    for each test, so that a command run in this process draws no PNG (most of the suite checks
    numbers, CSVs, JSON and lines); a test marked ``@pytest.mark.figures`` keeps the figures on.
    The table as it was is put back after the test. Commands run as subprocesses keep the
    shipped default (figures on)."""
    from marinecdpr import defaults

    before = dict(defaults.defaults)
    if request.node.get_closest_marker("figures") is None:
        defaults.set_defaults("report", figures=False)
    yield
    defaults.defaults.clear()
    defaults.defaults.update(before)


@pytest.fixture()
def captured_figures(monkeypatch):
    """The figures the report functions draw, by file name, kept open instead of saved (closed
    after the test)."""
    import marinecdpr.report.figures as figures

    figs = {}

    def keep(fig, path, dpi=None):
        figs[Path(path).name] = fig
        return Path(path)

    monkeypatch.setattr(figures, "_save", keep)
    yield figs
    import matplotlib.pyplot as plt

    for fig in figs.values():  # kept open for the test only: closed as _save would
        plt.close(fig)


def one_line_exit_2(res, *words) -> str:
    """A CliRunner result that failed as bad input should: exit 2, no exception but the
    exit, exactly one ``error:`` line on stderr holding each of ``words``; that line."""
    assert res.exit_code == 2, res.output
    assert res.exception is None or isinstance(res.exception, SystemExit), res.exception
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), res.stderr
    for w in words:
        assert w in lines[0], lines[0]
    return lines[0]


class FakeClock:
    """A clock the test sets (``now``, s), for the CLI's progress lines."""

    def __init__(self) -> None:
        self.now = 0.0

    def perf_counter(self) -> float:
        return self.now


@pytest.fixture()
def clock(monkeypatch):
    """The CLI's clock faked and its stderr kept: ``clock.now`` to set, ``clock.out`` to read."""
    import io
    import types

    from rich.console import Console

    import marinecdpr.cli.progress as cli

    fake = FakeClock()
    monkeypatch.setattr(cli, "time", types.SimpleNamespace(perf_counter=fake.perf_counter))
    fake.out = io.StringIO()
    monkeypatch.setattr(cli, "err_console", Console(file=fake.out, width=300, color_system=None))
    return fake


def one_candidate_study(spec, template, cells):
    """A design study of one judged candidate: the spec's variables at their lower bounds, the
    "medium" winch, the "light" rope, uncrossed (feasible, asserted); with the template's baseline."""
    import numpy as np

    from marinecdpr.studies.design import DesignStudy, baseline, evaluate

    x = {k: (v[0] if isinstance(v, tuple) else v) for k, v in spec.bounds().items()}
    x |= {"winch": "medium", "rope": "light", "pattern": "uncrossed"}
    e = evaluate(spec, template, x, cells)
    assert e.feasible, e.reason
    return DesignStudy(spec=spec, evaluations=[e], generation=np.array([0]), front=[0],
                       baseline=baseline(spec, template, cells))


TINY_SEAS = "hs_m,tp_s,probability\n1.0,8.0,0.5\n2.0,9.0,0.5\n"
"""tests/data/tiny_study.toml's scatter diagram: two sea states of half each."""


def tiny_study_folder(folder: Path, study: str | None = None, seas: bytes | str = TINY_SEAS) -> Path:
    """tests/data/tiny_study.toml (or ``study``, its text) beside its own template
    (paper_clean on a 10 x 3 m band), the template's RAO file and its scatter diagram (two
    sea states, one heading): every file it reads in one folder. Returns the study's path."""
    import shutil

    builtin = Path(str(resources.files("marinecdpr") / "scenario" / "builtin"))
    if study is None:
        study = (Path(__file__).parent / "data" / "tiny_study.toml").read_text(encoding="utf-8")
    folder.mkdir(parents=True, exist_ok=True)
    text = (builtin / "paper_clean.toml").read_text()
    for old, new in (("stations_m = [-95.0, 95.0]", "stations_m = [-5.0, 5.0]"),
                     ("heights_m = [0.0, 11.6]", "heights_m = [0.0, 3.0]")):
        assert old in text
        text = text.replace(old, new)
    (folder / "template.toml").write_text(text)
    shutil.copy(builtin / "paper_sea_rao.csv", folder / "paper_sea_rao.csv")
    (folder / "seas.csv").write_bytes(seas.encode() if isinstance(seas, str) else seas)
    (folder / "study.toml").write_text(study)
    return folder / "study.toml"


def judged_once(function, memo: dict):
    """``function`` (the design study's ``evaluate`` or ``baseline``: pure in its arguments)
    answering each set of arguments once: the key is their content (a pydantic model's JSON,
    a dict's sorted JSON, a list's items), the answer kept in ``memo`` for whichever asks the
    same again."""
    import json

    def content(a):
        if hasattr(a, "model_dump_json"):
            return a.model_dump_json()
        if isinstance(a, dict):
            return json.dumps(a, sort_keys=True)
        return tuple(a) if isinstance(a, list | tuple) else a

    def once(*args):
        key = tuple(content(a) for a in args)
        if key not in memo:
            memo[key] = function(*args)
        return memo[key]
    return once
