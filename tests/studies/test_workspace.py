"""The workspace map against statics computed independently (a linear feasibility problem)."""

from __future__ import annotations

import numpy as np
from scipy.optimize import linprog

from marinecdpr.geometry.kinematics import cable_kinematics
from marinecdpr.studies.workspace import workspace_map

from conftest import make_scenario


def _statically_feasible(sc, x, z):
    """Is there T in [T_min, T_max] with J~^T T = (0, m g, 0) at this pose? (LP, HiGHS)"""
    r = sc.robot
    J = cable_kinematics(np.array([[x, 0.0, z]]), np.eye(3)[None], r.frame_anchors, r.platform_anchors).J_tilde[0]
    A = J[:, [0, 2, 4]].T
    w = np.array([0.0, r.mass_kg * sc.environment.gravity_m_s2, 0.0])
    res = linprog(np.zeros(r.n_cables), A_eq=A, b_eq=w, bounds=list(zip(r.tension_min, r.tension_max)),
                  method="highs")
    return res.status == 0


def test_on_a_still_ship_the_map_is_static_feasibility():
    # a heavy platform makes the feasible region a strict part of the frame
    sc = make_scenario(lambda d: (d.update(base_motion={"type": "still"}, time={"step_s": 0.1, "duration_s": 0.3}),
                                  d["robot"].update(mass_kg=40.0)))
    ws = workspace_map(sc, n=(14, 10))
    inside = np.isfinite(ws.fraction_feasible)
    assert inside.sum() > 60
    expected = np.array([[_statically_feasible(sc, u, v) for v in ws.v] for u in ws.u])
    np.testing.assert_array_equal(ws.fraction_feasible[inside] == 1.0, expected[inside])
    assert 0 < expected[inside].sum() < inside.sum()   # the test discriminates
    assert set(np.unique(ws.fraction_feasible[inside])) <= {0.0, 1.0}  # still: all or nothing


def test_ship_motion_shrinks_the_workspace(paper):
    sc = paper.with_changes(time={"step_s": 0.02, "duration_s": 6.0})
    moving = workspace_map(sc, n=(12, 8))
    still = workspace_map(sc.with_changes(base_motion={"type": "still"}), n=(12, 8))
    ok_m = np.nan_to_num(moving.fraction_feasible) == 1.0
    ok_s = np.nan_to_num(still.fraction_feasible) == 1.0
    assert np.all(ok_s[ok_m])                        # what works at sea works in port
    both = ok_m & ok_s
    assert np.all(moving.min_margin_N[both] <= still.min_margin_N[both] + 1e-9)


# -------------------- formerly tests/test_issue21_workspace_sea.py

"""Issue 21, item 4: ``workspace`` in a sea state evaluated the ship's motion (a sum over
the sea record's wave components) once per held pose: paper_sea's default map took 21 min.
The ship's motion is the same for every held pose: it is evaluated once per chunk of the
time series, the map is the one the per-pose plans give, and the run's size is estimated
and printed before it starts."""


import re

import numpy as np
import pytest
from typer.testing import CliRunner

import marinecdpr
from marinecdpr.cli.app import app
from marinecdpr.errors import ScenarioError
from marinecdpr.motion import seastate
from marinecdpr.planning.planner import DEFAULT_CHUNK_STEPS, iter_plan
from marinecdpr.studies import workspace as W

runner = CliRunner()


def per_pose_map(scenario, n, chunk_steps):
    """The map as it was made before: every held pose planned on its own (iter_plan), the
    ship's motion evaluated again for each; the slow, obvious reference."""
    fit_lo, fit_hi = W.pose_range(scenario)
    grid = [np.linspace(fit_lo[i], fit_hi[i], k + 2)[1:-1] for i, k in zip((0, 2), n)]
    frac, margin, pinv = (np.full(n, np.nan) for _ in range(3))
    lo_T, hi_T = scenario.robot.tension_min, scenario.robot.tension_max
    steps = scenario.time.n_steps
    for a, u in enumerate(grid[0]):
        for b, v in enumerate(grid[1]):
            held = scenario.with_changes(trajectory={
                "type": "line", "start_position_m": [float(u), 0.0, float(v)],
                "end_position_m": [float(u), 0.0, float(v)], "start_orientation_deg": [0.0, 0.0, 0.0],
                "duration_s": 1.0})
            try:
                ok = pinv_ok = 0
                worst = np.inf
                for piece in iter_plan(held, chunk_steps=chunk_steps):
                    ok += int(piece.feasible.sum())
                    with np.errstate(invalid="ignore"):
                        pinv_ok += int(np.all((piece.tensions_pinv >= lo_T) & (piece.tensions_pinv <= hi_T),
                                              axis=1).sum())
                    m = W.tension_margin(piece.tensions, lo_T, hi_T)
                    worst = min(worst, float(np.nanmin(m)) if np.isfinite(m).any() else np.inf)
                frac[a, b], pinv[a, b] = ok / steps, pinv_ok / steps
                margin[a, b] = max(worst, 0.0) if ok == steps else -np.inf
            except ScenarioError:
                pass
    return frac, margin, pinv


@pytest.fixture()
def synth_calls(monkeypatch):
    calls = []
    real = seastate.synthesize

    def counting(rec, t):
        calls.append(np.asarray(t).size)
        return real(rec, t)

    monkeypatch.setattr(seastate, "synthesize", counting)
    return calls


@pytest.fixture(scope="module")
def short_sea():
    sc = marinecdpr.load_scenario("paper_sea")
    # a heavier platform: some poses infeasible, some steps of some poses too
    return sc.with_changes(time={"step_s": 0.002, "duration_s": 1.0}).with_updates("robot", mass_kg=30.0)


def test_the_sea_state_is_summed_once_per_chunk_not_once_per_pose(short_sea, synth_calls):
    ws = W.workspace_map(short_sea, n=(4, 3))
    assert synth_calls == [short_sea.time.n_steps]  # one chunk, one sum (it was 12: one per pose)
    assert np.isfinite(ws.fraction_feasible).all()


@pytest.mark.parametrize("chunk_steps", [DEFAULT_CHUNK_STEPS, 128])
def test_the_map_is_the_per_pose_plans_map_bit_for_bit(short_sea, chunk_steps, monkeypatch, synth_calls):
    monkeypatch.setattr(W, "DEFAULT_CHUNK_STEPS", chunk_steps)
    ws = W.workspace_map(short_sea, n=(4, 3))
    chunks = -(-short_sea.time.n_steps // chunk_steps)
    assert len(synth_calls) == chunks
    frac, margin, pinv = per_pose_map(short_sea, (4, 3), chunk_steps)
    np.testing.assert_array_equal(ws.fraction_feasible, frac)
    np.testing.assert_array_equal(ws.min_margin_N, margin)
    np.testing.assert_array_equal(ws.pinv_fraction_feasible, pinv)
    # the case is not trivial: poses held throughout, poses lost, and poses lost at some steps only
    assert (frac == 1.0).any() and (frac < 1.0).any() and np.isinf(margin).any()


def test_poses_outside_the_frame_stay_out_of_every_chunk(monkeypatch):
    sc = marinecdpr.load_scenario("paper_sea").with_changes(time={"step_s": 0.01, "duration_s": 1.0})
    robot = sc.robot.model_dump(exclude_none=True)
    for cable in robot["cables"]:  # a platform 2 m wide in a 1.9 m frame: no held pose fits
        x, y, z = cable["platform_anchor_m"]
        cable["platform_anchor_m"] = [8.0 * x, y, z]
    wide = sc.with_changes(robot=robot)
    monkeypatch.setattr(W, "DEFAULT_CHUNK_STEPS", 16)  # 7 chunks
    planned = []
    real = W.plan_at
    monkeypatch.setattr(W, "plan_at", lambda *a, **k: planned.append(1) or real(*a, **k))
    ws = W.workspace_map(wide, n=(3, 2))
    assert np.isnan(ws.fraction_feasible).all() and np.isnan(ws.min_margin_N).all()
    assert len(planned) == 6  # each pose refused in the first chunk, not tried in the other six
    frac, margin, pinv = per_pose_map(wide, (3, 2), 16)
    assert np.isnan(frac).all() and np.isnan(margin).all() and np.isnan(pinv).all()


def test_the_estimate_counts_the_sea_state_once():
    from marinecdpr.planning.budget import estimate_run

    sea = marinecdpr.load_scenario("paper_sea")
    size = estimate_run(sea, "workspace", grid=(30, 20))
    # 15 001 steps off the record's FFT grid: summed directly, once (not 600 times)
    assert size.poses == 600 and size.wave_samples == sea.time.n_steps
    assert size.steps == 600 * 15001


def test_workspace_prints_its_size_before_it_starts(tmp_path):
    res = runner.invoke(app, ["workspace", "paper_sea", "--points", "3x2", "--duration", "0.5",
                              "--out", str(tmp_path / "o")])
    assert res.exit_code == 0, res.output
    lines = res.stderr.strip().splitlines()
    assert re.fullmatch(r"size: paper_sea: 6 poses \(3 x 2\) x 501 steps = 3,006 plan steps, about \d+ MB in "
                        r"memory; the sea state's 1,350 wave components summed at 501 times", lines[0]), lines
    assert lines[-1].startswith("workspace: 6 of 6 poses in ")  # the work's own line comes after it
