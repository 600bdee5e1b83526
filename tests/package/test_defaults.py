"""The library's defaults table (marinecdpr.defaults): a wrong key or value refused in one
clear line, nothing set then; a spec's ``figures`` and the command line's ``--figures`` read
their default from it when made or run; a block's values undone after it."""

from __future__ import annotations

import importlib

import pytest
from typer.testing import CliRunner

from marinecdpr import defaults
from marinecdpr.cli.app import app
from marinecdpr.commands.workspace import WorkspaceSpec

FIGURE_SPECS = ["plan.PlanSpec", "simulate.SimulateSpec", "workspace.WorkspaceSpec", "operability.OperabilitySpec",
                "clean.CleanSpec", "control_study.ControlStudySpec", "windows.WindowsSpec", "rao.RaoSpec",
                "design.DesignCommandSpec", "faults.FaultsSpec"]
"""Every command that draws figures, by its spec."""
BASE = {"WindowsSpec": dict(duration_h=6.0, hs_limit=2.0),
        "RaoSpec": dict(length=100.0, beam=20.0, draught=5.0, gm=2.0)}
"""Options without which a spec cannot be made."""


def _spec(name: str):
    module, cls = name.split(".")
    return getattr(importlib.import_module(f"marinecdpr.commands.{module}"), cls)


@pytest.mark.parametrize("call, words", [
    (lambda: defaults.set_defaults("report", figure=False), "no key 'report.figure'; the keys are report.figures"),
    (lambda: defaults.set_defaults("reports", figures=False), "no key 'reports.figures'"),
    (lambda: defaults.get("report.png"), "no key 'report.png'"),
    (lambda: defaults.set_defaults("report", figures="no"), "report.figures = 'no': expected bool"),
    (lambda: defaults.set_defaults("report", figures=0), "report.figures = 0: expected bool"),
])
def test_a_wrong_key_or_value_is_one_line_naming_it(call, words):
    before = dict(defaults.defaults)
    with pytest.raises(defaults.DefaultsError) as err:
        call()
    said = str(err.value)
    assert said.startswith("marinecdpr defaults: ") and words in said and "\n" not in said, said
    assert isinstance(err.value, KeyError) and isinstance(err.value, ValueError)
    assert defaults.defaults == before  # nothing set


def test_a_wrong_key_in_a_block_sets_nothing_and_runs_nothing():
    before = dict(defaults.defaults)
    ran = []
    with pytest.raises(defaults.DefaultsError, match="no key 'report.dpi'"):
        with defaults.defaults_set({"report.figures": not before["report.figures"], "report.dpi": 100}):
            ran.append(True)
    assert not ran and defaults.defaults == before


def test_set_reset_and_a_block_undone_whatever_happens_in_it():
    defaults.set_defaults("report", figures=False)
    assert defaults.get("report.figures") is False
    defaults.reset_defaults()
    assert defaults.defaults == dict(defaults.SHIPPED) == {"report.figures": True}
    with pytest.raises(RuntimeError):
        with defaults.defaults_set({"report.figures": False}):
            assert defaults.get("report.figures") is False
            raise RuntimeError
    assert defaults.get("report.figures") is True


@pytest.mark.parametrize("name", FIGURE_SPECS)
def test_every_figure_drawing_spec_reads_its_default_from_the_table_when_made(name):
    spec = _spec(name)
    base = BASE.get(spec.__name__, {})
    for value in (True, False):
        with defaults.defaults_set({"report.figures": value}):
            assert spec.default("figures") is value
            assert spec(**base).figures is value
            assert spec(**base, figures=not value).figures is (not value)  # given, it is the spec's
    made = spec(**base, figures=True)
    with defaults.defaults_set({"report.figures": False}):
        assert made.figures is True  # read when made, not when used


def test_the_command_line_s_default_is_the_table_s_as_it_runs(tmp_path):
    args = ["workspace", "paper", "--points", "3x2", "--duration", "0.1"]
    runner = CliRunner()
    for value, png in ((True, True), (False, False)):
        with defaults.defaults_set({"report.figures": value}):
            assert WorkspaceSpec().figures is value
            out = tmp_path / f"table_{value}"
            res = runner.invoke(app, args + ["--out", str(out)])
            assert res.exit_code == 0, res.output
            assert (out / "workspace.csv").is_file() and (out / "workspace.png").is_file() is png
    with defaults.defaults_set({"report.figures": False}):  # the option over the table
        res = runner.invoke(app, args + ["--figures", "--out", str(tmp_path / "asked")])
        assert res.exit_code == 0 and (tmp_path / "asked" / "workspace.png").is_file()
