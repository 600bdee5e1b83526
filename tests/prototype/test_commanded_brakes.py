"""The controller's brakes on the prototype's bus (issue 40, item 4's first part): its last
resort (``Command.brake``, the reaction "brake") is a signal the winch parts honour, so that a
drum really holds ``[simulation.control.safety] brake_delay_s`` after the command, on both
plants. Hand-worked: the first brake command is the exchange of the reaction's first
detection (the watch's ``reaction`` escalating to the brakes at once on the four-cable robot),
the hold from that exchange plus the delay in exchanges; a held drum's unstretched length,
read back from each step's tension and length (L0 = L EA / (EA + T)), constant."""

from __future__ import annotations

import numpy as np
import pytest

from marinecdpr.prototype.simulation import simulate

from conftest import make_scenario

EA = 1.0e5


def paper_snapping(delay_s: float | None):
    """The paper's robot and circle with undamped elastic cables (EA 1e5 N) on length-controlled
    winches, cable 1 snapping at 0.5 s, flown closed loop with the watch."""
    def edit(d):
        d["simulation"]["cables"] = {"model": "elastic", "stiffness_EA_N": EA, "damping_N_s_m": 0.0,
                                     "winch": "length"}
        if delay_s is not None:
            d["simulation"].setdefault("control", {})["safety"] = {"brake_delay_s": delay_s}
        d["time"] = {"step_s": 0.001, "duration_s": 1.2}
        d["faults"] = [{"kind": "cable_snap", "cable": 1, "at_s": 0.5}]
    return make_scenario(edit)


@pytest.mark.parametrize("plant,delay_s", [("own", None), ("mujoco", 0.05)])
def test_a_commanded_brake_holds_the_remaining_drums_after_its_delay(plant, delay_s):
    """Cable 1 snaps at 0.5 s; its load cell reads slack for 20 exchanges (slack_delay_s 0.02 s):
    detected at 0.52 s, and on four cables the reaction goes to the brakes there. The three
    remaining drums hold from 0.52 s + the delay (0.2 s by default: 0.72 s; 0.05 s: 0.57 s), their
    unstretched lengths constant from then (1e-12 m) where taut, having moved before (>0.1 mm
    over the 0.3 s before); the snapped cable's drum is not braked."""
    r = simulate(paper_snapping(delay_s), run="closed_loop", plant=plant)
    assert r.reaction == "brake"
    first = r.detections[0]
    assert (first.step, first.cable) == (520, 0)
    held_at = 0.52 + (0.2 if delay_s is None else delay_s)
    assert [c for c, _ in r.brakes_held] == [2, 3, 4]
    np.testing.assert_allclose([t for _, t in r.brakes_held], held_at, rtol=0.0, atol=1e-12)
    k = int(round(held_at / 0.001))
    L0 = np.where(r.tensions > 0.0, r.lengths * EA / (EA + r.tensions), np.nan)
    for c in (1, 2, 3):
        after = L0[k:, c][np.isfinite(L0[k:, c])]
        assert after.size > 0
        np.testing.assert_allclose(after, after[0], rtol=0.0, atol=1e-12)
        before = L0[k - 300:k, c]
        assert np.nanmax(before) - np.nanmin(before) > 1e-4
