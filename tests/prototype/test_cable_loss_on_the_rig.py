"""A cable that snaps on the virtual prototype's MuJoCo plant (:class:`~marinecdpr.prototype.rig.Rig`),
flown by the controller from a Python loop (:class:`~marinecdpr.control.Controller`): the
rig stops applying the cable's tension and its load cell reads zero from then on (a
test-local fault: the measurement handed to the controller, not a part of the prototype)."""

from __future__ import annotations

import numpy as np
import pytest

from marinecdpr.control import Controller
from marinecdpr.prototype.rig import Rig

from conftest import make_scenario
from test_controller import six_cables

N = 800  # steps: 0.8 s of the paper's circle
K_BREAK = 200


def fly(scenario, cable, *, detect=True):
    """The closed loop on the rig; from K_BREAK on, cable ``cable`` applies nothing and its load
    cell (reading what each cable applied over the last step) reads 0. The platform's largest
    distance from the plan (m) per step, the applied tensions (N) and the controller."""
    data = scenario.model_dump(exclude_none=True)
    sc = scenario.with_changes(
        simulation={**data["simulation"], "control": {**data["simulation"]["control"], "safety": {"detect": detect}}},
        time={"step_s": scenario.time.step_s, "duration_s": N * scenario.time.step_s})
    ctl, rig = Controller(sc), Rig(sc)
    applied = ctl.parts.ref.T[0].copy()
    err, T = np.empty(N), np.empty((N, sc.robot.n_cables))
    for k in range(N):
        x, R, v, w = rig.state()
        cmd = ctl.step(rig.t, x=x, R=R, v=v, w=w, eta=rig.ship(), tensions=applied.copy())
        applied = cmd.T_cmd.copy()
        if k >= K_BREAK:
            applied[cable] = 0.0
        rig.step(applied)
        err[k] = np.abs(x - ctl.parts.ref.x[k]).max()
        T[k] = applied
    return err, T, ctl


@pytest.fixture(scope="module")
def six():
    return make_scenario(six_cables)


def test_a_snapped_cable_is_detected_and_the_other_five_bring_the_platform_back(six):
    """Cable 5 of six snaps at 0.2 s: its load cell reads 0 from the next exchange, the 20th
    such reading (slack_delay_s = 20 ms) loses it, and the other five, its tension
    redistributed, bring the platform back onto the plan (7.5e-5 m at 0.8 s, as before the
    break: 8.0e-5 m); the largest excursion, during the detection's delay, 11.5 mm. Without
    the detection the controller keeps commanding the lost cable, a cable sits at its
    450 N limit and the platform ends 0.24 m off."""
    err, T, ctl = fly(six, 4)
    [d] = ctl.detections
    assert (d.step, d.kind, d.cable) == (K_BREAK + 20, "cable_slack", 4)
    assert ctl.reaction == "go_on"
    assert err[:K_BREAK].max() < 1e-4
    assert err[K_BREAK:].max() < 0.012
    assert err[-1] < 1e-4
    lo, hi = six.robot.tension_min, six.robot.tension_max
    after = T[K_BREAK + 21:]
    assert np.all(after[:, 4] == 0.0)
    others = np.delete(after, 4, axis=1)
    assert np.all(others >= np.delete(lo, 4) - 1e-9) and np.all(others <= np.delete(hi, 4) + 1e-9)
    err_blind, T_blind, blind = fly(six, 4, detect=False)
    assert blind.detections == [] and np.array_equal(err_blind[:K_BREAK + 21], err[:K_BREAK + 21])
    assert err_blind[-1] > 0.2
    assert T_blind.max() == pytest.approx(hi.max())


def test_a_snapped_top_cable_leaves_no_tensions_to_hold_it_the_brakes(six):
    """Cable 1 (top left) of six: the five left cannot hold the platform against gravity within
    their limits, nor stop it: the controller asks every remaining winch's brake."""
    err, T, ctl = fly(six, 0)
    [d] = ctl.detections
    assert (d.step, d.cable) == (K_BREAK + 20, 0)
    assert ctl.reaction == "brake"
    np.testing.assert_array_equal(ctl.command.brake, [0, 1, 1, 1, 1, 1])
