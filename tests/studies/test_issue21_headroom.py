"""Issue 21, item 8: operability's min_margin_N is the sea state's actual smallest headroom,
not the margin asked for."""

import copy
import tomllib
from importlib import resources
from pathlib import Path

import numpy as np
import pytest

from marinecdpr.model.tension import largest_headroom, pseudo_inverse_tensions
from marinecdpr.scenario.loading import scenario_from_dict
from marinecdpr.studies.operability import ScatterDiagram, operability


def test_largest_headroom_of_two_opposed_cables_by_hand():
    """One DOF, two cables pulling opposite ways: T1 - T2 = f within [10, 110] N. The best
    tensions sit symmetric about the middle: headroom (110 - 10 - |f|) / 2."""
    J = np.array([[[1.0], [-1.0]]] * 3)
    w = np.array([[20.0], [0.0], [-120.0]])
    T_s, _ = pseudo_inverse_tensions(J, w)
    h = largest_headroom(J, T_s, np.array([10.0, 10.0]), np.array([110.0, 110.0]))
    assert h == pytest.approx([40.0, 50.0, -10.0], abs=1e-12)


def _held_at_centre():
    """The paper's robot held level at the frame's centre in a nearly calm sea."""
    root = resources.files("marinecdpr.scenario") / "builtin"
    data = copy.deepcopy(tomllib.loads((root / "paper_sea.toml").read_text()))
    data["trajectory"] = {"type": "line", "start_position_m": [0.95, 0.0, 0.7], "end_position_m": [0.95, 0.0, 0.7],
                          "duration_s": 5.0}
    return scenario_from_dict(data, base_dir=Path(str(root)))


def test_min_margin_is_the_sea_states_headroom_not_the_margin_asked_for():
    """Held level at the centre, the layout is symmetric: T1 = T2 = t_u, T3 = T4 = t_d, the
    null space (1, 1, 1, 1) / 2, and the weight asks t_u - t_d = m g / (2 sin a), a the
    cables' angle to the horizontal (tan a = 0.55 / 0.825). The best tensions centre that
    pair in [10, 450] N: headroom (440 - m g / (2 sin a)) / 2 = 207.9 N, whatever margin."""
    sc = _held_at_centre()
    sin_a = 0.55 / np.hypot(0.825, 0.55)
    expected = (440.0 - 5.0 * 9.8 / (2.0 * sin_a)) / 2.0
    calm = ScatterDiagram(np.array([0.01]), np.array([8.0]), np.ones((1, 1)))
    for margin in (0.0, 20.0):
        op = operability(sc, calm, headings_deg=(180.0,), margin_N=margin, duration_s=5.0, step_s=0.05,
                         realisations=1)
        (r,) = op.results
        assert r.operable
        assert r.min_margin_N == pytest.approx(expected, abs=0.05)  # the sea moves it by less
        assert r.min_margin_N > margin + 100.0


def test_min_margin_on_the_circle_is_the_largest_margin_the_sea_state_allows():
    """paper_sea's circle: the minimum-variance plan puts a cable on its (tightened) lower
    limit, so the planned tensions' distance to the limits was the margin asked for (0 N
    and 5 N here). The sea state's headroom is the same whatever the margin, and it is
    the largest margin that is still workable: a little less works, a little more fails."""
    import sys

    sys.path.insert(0, str(Path(__file__).parent))
    from test_operability import sea_robot

    sea = ScatterDiagram(np.array([1.0]), np.array([8.0]), np.ones((1, 1)))

    def cell(margin):
        op = operability(sea_robot(5.0), sea, headings_deg=(90.0,), margin_N=margin, duration_s=15.0, step_s=0.05)
        return op.results[0]

    free, tight = cell(0.0), cell(5.0)
    assert free.operable and tight.operable
    assert free.min_margin_N == pytest.approx(tight.min_margin_N, abs=1e-9)
    h = free.min_margin_N
    assert h > 15.0  # not 0, not 5
    assert cell(h - 0.5).operable
    assert not cell(h + 0.5).operable
