"""The wind on the virtual prototype (issue 40, item 1): both plants meet the gust series and
agree; flown open loop, a plan that holds the series is followed as in calm air (the plants
apply the very loads the planner computed), one that holds only the mean drifts by the gust."""

from __future__ import annotations

import numpy as np
import pytest

from marinecdpr.prototype.simulation import simulate

from conftest import make_scenario

WIND = {"speed_m_s": 15.0, "direction_deg": 180.0, "platform_shape_coefficient": 1.6,
        "platform_area_m2": [0.3, 0.5, 0.2], "cable_diameter_m": 0.008, "seed": 2}


@pytest.fixture(scope="module")
def runs():
    base = make_scenario().with_changes(time={"step_s": 0.001, "duration_s": 3.0})
    out = {}
    for plan_gust in ("mean", "series"):
        sc = base.with_changes(wind={**WIND, "plan_gust": plan_gust})
        for run in ("open_loop", "closed_loop"):
            for plant in ("mujoco", "own"):
                out[plan_gust, run, plant] = simulate(sc, run=run, plant=plant)
    out["calm"] = simulate(base, run="open_loop", plant="own")
    return out


def error_m(r):
    return np.abs(r.pose[:, [0, 2]] - r.pose_planned[:, [0, 2]]).max()


def test_both_plants_agree_with_wind(runs):
    """Measured (3 s, the paper's ship, a 15 m/s wind with its Frøya gust): open loop 4.9e-6 m
    of a 0.11 m drift, closed loop 3.4e-7 m; MuJoCo holds the wind's mid-step load over each
    step (held at the step's start it lagged by h/2: 3.6e-4 m open loop)."""
    for plan_gust in ("mean", "series"):
        for run, tol in (("open_loop", 1e-5), ("closed_loop", 1e-6)):
            a, b = runs[plan_gust, run, "mujoco"], runs[plan_gust, run, "own"]
            assert np.abs(a.pose[:, :3] - b.pose[:, :3]).max() < tol, (plan_gust, run)
            assert np.degrees(np.abs(a.pose[:, 3:] - b.pose[:, 3:]).max()) < 1e3 * tol
            assert a.ship_tracking_error < 1e-6


def test_plants_meet_the_gust_the_plan_holds(runs):
    """Open loop, no feedback: with the series in the plan the own plant follows it as closely
    as in calm air (2.1e-7 m against 1.5e-7 m): the plant's wind is the planner's, step by
    step; with the mean alone in the plan, the gust pushes the platform 0.11 m off; closed loop
    the controller holds it to 1.7 mm."""
    calm = error_m(runs["calm"])
    assert error_m(runs["series", "open_loop", "own"]) < 2.0 * calm + 1e-7
    drift = error_m(runs["mean", "open_loop", "own"])
    assert 0.05 < drift < 0.2
    assert error_m(runs["mean", "closed_loop", "own"]) < 0.03 * drift
