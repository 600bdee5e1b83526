"""The control study's contract (:mod:`marinecdpr.commands.control_study`): its spec
without the command line, the command line's and the study function's defaults the
spec's (``--pose-from`` was ``sensor,encoders`` on the command line and ``sensor`` in
:func:`marinecdpr.studies.control.control_study`: issue 38), and the checks that need the
scenario made before any run."""

from __future__ import annotations

import inspect

import pytest

import marinecdpr
from marinecdpr.cli.app import app
from marinecdpr.commands import SpecError
from marinecdpr.commands import control_study as command
from marinecdpr.commands.control_study import ControlStudySpec
from marinecdpr.studies import control
from command_pages import cli_default


@pytest.mark.parametrize("options, flag, words", [
    ({"predictions": "none,magic"}, "--predictions", "--predictions magic: expected one of none, kinematic, ar"),
    ({"pose_from": ["sensor", "gps"]}, "--pose-from", "--pose-from gps: expected one of sensor, encoders"),
    ({"latencies": "ten"}, "--latencies", "--latencies ten: expected numbers of ms separated by commas"),
    ({"latencies": "20,-5"}, "--latencies", "--latencies 20,-5: latencies must be >= 0 ms"),
    ({"plant": "gazebo"}, "--plant", "--plant gazebo: expected one of own, mujoco"),
    ({"settle": -1.0}, "--settle", "--settle -1: expected a non-negative number"),
    ({"rate": 0.0}, "--rate", "--rate 0: expected a positive number"),
])
def test_a_bad_option_names_its_flag_and_the_part_at_fault(options, flag, words):
    with pytest.raises(SpecError) as err:
        ControlStudySpec(**options)
    assert f"{err.value.flag} {err.value.value}: {err.value.detail}" == words and err.value.flag == flag


def test_the_command_line_s_and_the_study_s_defaults_are_the_spec_s():
    import typer.main

    params = {p.name: p for p in typer.main.get_command(app).commands["control-study"].params}
    assert set(params) - {"scenario", "out"} == set(ControlStudySpec.model_fields)
    for name in ControlStudySpec.model_fields:
        given = cli_default(params[name])
        assert (ControlStudySpec(**{name: given}).model_dump()[name] if given is not None else None) \
            == ControlStudySpec.default(name), name
    study = inspect.signature(control.control_study).parameters
    spec = ControlStudySpec()
    assert tuple(study["latencies_s"].default) == tuple(x / 1e3 for x in spec.latencies)
    assert tuple(study["predictions"].default) == spec.predictions
    assert tuple(study["pose_from"].default) == spec.pose_from
    assert study["rate_hz"].default == spec.rate and study["duration_s"].default == spec.duration
    assert study["plant"].default == spec.plant


def test_the_estimate_checks_the_spec_against_the_scenario():
    """``duration`` beyond the predictor's warm-up and a second (paper_sea's ar_warmup_s),
    and the runs counted: 2 latencies x 1 prediction x 2 sources."""
    sc = marinecdpr.load_scenario("paper_sea")
    warm = sc.simulation.mru.ar_warmup_s
    with pytest.raises(SpecError, match=rf"duration {warm + 1:g}: must be longer than --settle \({warm + 1:g} s"):
        command.estimate(ControlStudySpec(duration=warm + 1.0), sc)
    est = command.estimate(ControlStudySpec(latencies="0,20", predictions="none", duration=warm + 2.0), sc)
    assert est.settle == warm + 1.0 and est.flown.name == sc.name
    assert ControlStudySpec(latencies="0,20", predictions="none").n_runs == 4
    with pytest.raises(SpecError) as err:
        command.estimate(ControlStudySpec(encoder_resolution=-1e-3, duration=warm + 2.0), sc)
    assert err.value.flag == "--encoder-resolution"


@pytest.mark.figures
def test_the_page_runs_as_written_and_lists_the_spec(tmp_path, monkeypatch):
    from command_pages import assert_table_is_the_spec, run_page

    assert_table_is_the_spec("control-study", ControlStudySpec)
    ns = run_page("control-study", tmp_path, monkeypatch)
    rms = ns["rms"]
    assert set(rms) == {0.0, 0.05} and rms[0.05] > rms[0.0] > 0.0  # 50 ms late tracks worse than on time
    written = (tmp_path / "out" / "control_study.csv").read_text().splitlines()
    assert len(written) == 3  # the header and the two runs
