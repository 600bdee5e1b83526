"""The controller missing its deadline as a mode of its part (issue 40, item 2): for the
fault's exchanges its commands of the exchange before are held; before them the run is the
sound one bit for bit."""

from __future__ import annotations

import numpy as np
import pytest

from marinecdpr import ScenarioError
from marinecdpr.prototype.simulation import simulate

from conftest import make_scenario


def paper(faults=()):
    def edit(d):
        d["time"] = {"step_s": 0.001, "duration_s": 1.0}
        d["faults"] = list(faults)
    return make_scenario(edit)


@pytest.mark.parametrize("plant", ["own", "mujoco"])
def test_a_late_controller_holds_its_commands(plant):
    sound = simulate(paper(), run="closed_loop", plant=plant)
    late = simulate(paper([{"kind": "controller_deadline", "at_s": 0.5, "steps": 20}]), run="closed_loop", plant=plant)
    np.testing.assert_array_equal(late.tensions_commanded[:500], sound.tensions_commanded[:500])
    np.testing.assert_array_equal(late.pose[:501], sound.pose[:501])
    np.testing.assert_array_equal(late.tensions_commanded[500:520],
                                  np.broadcast_to(sound.tensions_commanded[499], (20, 4)))
    np.testing.assert_array_equal(late.tensions[500:520], late.tensions_commanded[500:520])  # ideal cables
    assert np.abs(late.tensions_commanded[520] - sound.tensions_commanded[520]).max() > 1e-3
    assert np.abs(late.pose[520:, [0, 2]] - sound.pose[520:, [0, 2]]).max() > 1e-7
    assert late.faults[0] == {"kind": "controller_deadline", "cable": None, "at_s": 0.5, "acted_s": 0.5, "steps": 20}


@pytest.mark.parametrize("fault, key, says", [
    ({"kind": "controller_deadline", "at_s": 0.5}, "faults[1].steps", "missing"),
    ({"kind": "controller_deadline", "at_s": 0.5, "steps": 3, "cable": 1}, "faults[1].cable", "leave it out"),
    ({"kind": "cable_snap", "at_s": 0.5, "cable": 1, "steps": 3}, "faults[1].steps", "is for a controller_deadline"),
])
def test_a_deadline_mistake_is_one_line(fault, key, says):
    with pytest.raises(ScenarioError) as err:
        paper([fault])
    text = str(err.value)
    assert "\n" not in text and key in text and says in text, text
