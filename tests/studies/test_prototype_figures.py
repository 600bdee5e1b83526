"""The main job's figures as typed records (issue 38, item 4): :class:`PrototypeFigures` and
:class:`RunFigures` hold what ``summary.json`` says, read back to the same record, and their
attributes are the runs' own numbers."""

import json
from pathlib import Path

import numpy as np
import pytest

import marinecdpr
from marinecdpr.report.files import json_text
from marinecdpr.studies.prototype_runs import PrototypeFigures, RunFigures

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def _short(name: str, seconds: float = 0.05):
    sc = marinecdpr.load_scenario(name)
    sc = sc.with_changes(time={"step_s": sc.time.step_s, "duration_s": seconds})
    return marinecdpr.virtual_prototype(sc, plant="own")


@pytest.fixture(scope="module")
def planar():
    return _short("paper")


@pytest.fixture(scope="module")
def spatial():
    return _short(str(EXAMPLES / "spatial_cube8.toml"))


@pytest.mark.parametrize("which", ["planar", "spatial"])
def test_summary_json_reads_back_to_the_same_record(which, request):
    vp = request.getfixturevalue(which)
    text = json_text(vp.summary)
    back = PrototypeFigures.from_json(json.loads(text))
    assert back == vp.figures
    assert json_text(back.to_json()) == text  # the same bytes
    assert list(back.runs) == list(vp.results)


@pytest.mark.parametrize("which", ["planar", "spatial"])
def test_each_run_s_figures_are_its_own_numbers(which, request):
    vp = request.getfixturevalue(which)
    for name, res in vp.results.items():
        f = vp.figures.runs[name]
        err = np.abs(res.pose_error)
        assert f.max_abs_error("x") == err[:, 0].max() and f.max_abs_error("z") == err[:, 2].max()
        assert f.max_abs_cable_length_error_m == tuple(np.abs(res.lengths - res.lengths_planned).max(axis=0))
        assert f.tension_min_N == res.tensions.min() and f.tension_max_N == res.tensions.max()
        assert f.largest_position_error_m == (err[:, :3] if which == "spatial" else err[:, [0, 2]]).max()
        assert f.within_error_bound == (f.beyond_error_bound == ())
        assert (f.controller_verdict is None) == (name != "closed_loop")
    spatial = which == "spatial"
    run = vp.figures.runs["open_loop"]
    if spatial:
        assert run.max_abs_error("rz") == pytest.approx(np.degrees(np.abs(vp.results["open_loop"].pose_error[:, 5]).max()),
                                                        rel=1e-15)
    else:
        with pytest.raises(ValueError, match="no rx error"):
            run.max_abs_error("rx")
    assert vp.figures.runs_controller_bypassed == tuple(
        n for n, r in vp.figures.runs.items() if r.controller_verdict == "bypassed")


def test_a_summary_with_a_wrong_key_is_refused_by_name(planar):
    data = planar.summary
    data["open_loop"] = dict(data["open_loop"], max_error_q_m=1.0)
    with pytest.raises(ValueError, match=r"^a run's figures: unknown key\(s\) max_error_q_m$"):
        PrototypeFigures.from_json(data)
    data = planar.summary
    del data["steps"]
    with pytest.raises(ValueError, match=r"^the main job's figures: missing key\(s\) steps$"):
        PrototypeFigures.from_json(data)
    with pytest.raises(ValueError, match="missing key"):
        RunFigures.from_json({"max_abs_error_x_m": 0.0})
