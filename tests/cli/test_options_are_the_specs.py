"""Every command's options are its spec's fields (issue 38, items 1 and 3): the command line
has no option the spec does not hold, the spec no field the command line does not offer, and
each option's default is the field's (the one source). The command's own arguments (the
scenario, ``--out``) are the run's, not the spec's."""

from __future__ import annotations

import importlib

import pytest
import typer

from marinecdpr.cli.app import app

SPECS = {
    "plan": "plan.PlanSpec", "simulate": "simulate.SimulateSpec", "check": "check.CheckSpec",
    "latency": "latency.LatencySpec", "warmup": "warmup.WarmupSpec", "import": "import_robot.ImportSpec",
    "scenarios": "scenarios.ScenariosSpec", "workspace": "workspace.WorkspaceSpec",
    "control-study": "control_study.ControlStudySpec", "operability": "operability.OperabilitySpec",
    "design": "design.DesignCommandSpec", "clean": "clean.CleanSpec", "rao": "rao.RaoSpec",
    "windows": "windows.WindowsSpec", "faults": "faults.FaultsSpec",
}
RUN_ARGUMENTS = {"scenario", "out", "spec", "source", "series", "scenarios_"}
"""Parameters that name what the run reads or writes (a scenario, a study, a model, a
series, the output folder): the run's arguments, not the spec's options."""


def _spec(command: str):
    module, name = SPECS[command].split(".")
    try:
        return getattr(importlib.import_module(f"marinecdpr.commands.{module}"), name)
    except (ImportError, AttributeError):
        pytest.fail(f"{command}: no spec marinecdpr.commands.{SPECS[command]}")


def _field(spec, param) -> str:
    """The spec's field an option maps to: its name, or (where the parameter's name is not
    a field, e.g. ``--json`` as ``as_json``) the field named by its flag."""
    if param.name in spec.model_fields:
        return param.name
    flag = max(param.opts, key=len).lstrip("-").replace("-", "_")
    return flag if flag in spec.model_fields else param.name


BASE = {"rao": dict(length=100.0, beam=20.0, draught=5.0, gm=2.0), "windows": dict(duration_h=6.0, hs_limit=2.0)}
"""Options without which a command's spec cannot be made (a hull's main dimensions, the
operation's duration and one design limit): given, so that each other default can be read."""


@pytest.mark.parametrize("command", sorted(SPECS))
def test_a_command_s_options_are_its_spec_s_fields_with_its_defaults(command):
    click_command = typer.main.get_command(app).commands[command]
    spec = _spec(command)
    options = [p for p in click_command.params if p.name not in RUN_ARGUMENTS and p.name != "help"]
    fields = {_field(spec, p): p for p in options}
    assert set(fields) == set(spec.model_fields), (sorted(fields), sorted(spec.model_fields))
    base = BASE.get(command, {})
    for field, param in fields.items():
        if spec.model_fields[field].is_required():  # required of the command line too
            assert param.required, (command, field)
            continue
        default = param.default() if callable(param.default) else param.default  # read as the command runs
        default = default.value if hasattr(default, "value") else default  # an enum's member
        if field in base:
            assert default == spec.default(field), (command, field, default, spec.default(field))
            continue
        # the command line's default as the spec reads it (text such as "30x20" or "0,10,20") is the spec's own
        assert spec(**base, **{field: default}) == spec(**base), (command, field, default, spec.default(field))
