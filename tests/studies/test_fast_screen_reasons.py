"""The fast screen's chance that the tensions break their limits, and why a sea state fails
(issue 37, item 3): every "fails" names what failed, where and in which sea state."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.special import ndtr, ndtri

import marinecdpr
from marinecdpr.model.tension import wrench_faces
from marinecdpr.studies import screen as S
from marinecdpr.studies.operability import Cell


@pytest.fixture(scope="module")
def held():
    """paper_clean's robot held still at the frame's centre, its brush on the hull, for 60 s."""
    sc = marinecdpr.load_scenario("paper_clean")
    return sc.with_changes(trajectory={"type": "line", "start_position_m": [0.95, 0.0, 0.7],
                                       "end_position_m": [0.95, 0.0, 0.7], "duration_s": 1.0},
                           time={"duration_s": 60.0, "step_s": 0.01})


def test_a_robot_too_weak_for_its_platform_fails_on_its_top_cables_even_without_the_sea(held):
    """A 9 kg platform held on T_max = 60 N: at rest the upper cables (1, 2: anchored at the
    frame's top) must carry more than their limit. Every sea state fails on the tensions,
    and the reason names the sea state, top cables at T_max or bottom cables slack, the
    pose and that no sea is needed for it."""
    sc = held.with_updates("robot", mass_kg=9.0, tension_max_N=60.0)
    cells = [Cell(0, 1.0, 8.0, 90.0, 0.7), Cell(1, 3.0, 10.0, 90.0, 0.3)]
    r = S.screen_cells(sc, cells, model=S.screen_model(sc, grid=(1, 1)))
    assert not r.works.any() and not r.tensions_ok.any() and (r.chance == 1.0).all()
    assert r.reasons[0].startswith("Hs 1 m, Tp 8 s, heading 90 deg: tensions: ")
    assert r.reasons[1].startswith("Hs 3 m, Tp 10 s, heading 90 deg: tensions: ")
    for why in r.reasons:
        assert why.endswith("at (0.95, 0.00, 0.70) m in C: even without the sea")
        at_max = {int(w.split()[-1]) for w in why.split(" at T_max")[:-1]}
        slack = {int(w.split()[-1]) for w in why.split(" slack")[:-1]}
        assert at_max | slack and at_max <= {1, 2} and slack <= {3, 4}, why
    assert "normal force" not in r.reasons[0]
    line = S.why_fails(cells, r.works, r.reasons)
    assert line == "every sea state fails (tensions in 2); the mildest: " + r.reasons[0]


def test_a_narrow_band_fails_on_the_normal_force_alone(held):
    """The same robot as built (5 kg, 450 N) in a beam sea of Hs 4 m with a band of 59.5-60.5
    N: its tensions hold, its pusher's force leaves the band, and the reason says so only."""
    sc = held.with_updates("cleaning", normal_force_N=[59.5, 60.5])
    cells = [Cell(0, 4.0, 8.0, 90.0, 1.0)]
    r = S.screen_cells(sc, cells, model=S.screen_model(sc, grid=(1, 1)))
    assert r.tensions_ok[0] and not r.works[0]
    assert r.reasons[0] == ("Hs 4 m, Tp 8 s, heading 90 deg: normal force in band "
                            f"{r.in_band_pct[0]:.1f} % of the time (less {ndtri(1 - S.EXCEEDANCE):.2f} standard deviations of one record's "
                            f"share: {r.in_band_low_pct[0]:.1f} %) < 95 %")


def _chance_by_hand(sc, m, cell):
    """The chance, written out for a pose held all the job (no drop, one start): per facet
    and side, T sqrt(m2 / m0) / 2 pi exp(-z^2 / 2) + Phi(-z), z = the planned still wrench's
    distance to the facet (the tool's loads at the preload) over the sea's sigma along its
    normal."""
    C0, C2 = S._response_moments(m, S._rao_of(sc), [cell], sc)
    c = list(m.controlled)
    f = wrench_faces(m.J, sc.robot.tension_min, sc.robot.tension_max)
    w = m.w0[0] - sc.cleaning.preload * m.tool_n  # the brush still: its load per newton, no friction
    total = 0.0
    for j in range(f.normal.shape[1]):
        n = f.normal[0, j]
        s0, s2 = n @ C0[0, 0][np.ix_(c, c)] @ n, n @ C2[0, 0][np.ix_(c, c)] @ n
        u = n @ (w[c] - f.centre[0])
        for d in (f.half_width[0, j] - u, f.half_width[0, j] + u):
            z = d / np.sqrt(s0)
            total += m.duration_s * np.sqrt(s2 / s0) / (2 * np.pi) * np.exp(-z * z / 2) + ndtr(-z)
    return total


@pytest.mark.parametrize("t_max", [80.0, 86.0])
def test_the_chance_is_rice_s_crossings_over_the_facets_by_hand(held, t_max):
    """Held at one pose, the screen's chance is the sum over the facets of Rice's crossings
    over the job plus a start beyond, from the wrench's moments: by hand, to 1e-9."""
    sc = held.with_updates("robot", tension_max_N=t_max)
    m = S.screen_model(sc, grid=(1, 1))
    cell = Cell(0, 5.0, 10.0, 90.0, 1.0)
    r = S.screen_cells(sc, [cell], model=m)
    by_hand = _chance_by_hand(sc, m, cell)
    assert 1e-6 < by_hand < 1.0
    assert r.chance[0] == pytest.approx(by_hand, rel=1e-9)
    assert r.tensions_ok[0] == (by_hand <= S.EXCEEDANCE)


def test_limits_tightened_by_the_margin_meet_the_exceedance(held):
    """The margin is the tightening at which the chance reaches the exceedance: the screen of
    the robot with every limit tightened by it has that chance (and 0.3 N less tightening
    passes, 0.3 N more fails)."""
    sc = held.with_updates("robot", tension_max_N=110.0)
    cell = Cell(0, 5.0, 10.0, 90.0, 1.0)
    r = S.screen_cells(sc, [cell], model=S.screen_model(sc, grid=(1, 1)))
    M = float(r.margin_N[0])
    assert 0.5 < abs(M) < 40.0

    def tightened(by):
        t = sc.with_updates("robot", tension_min_N=10.0 + by, tension_max_N=110.0 - by)
        return S.screen_cells(t, [cell], model=S.screen_model(t, grid=(1, 1)))

    assert tightened(M).chance[0] == pytest.approx(S.EXCEEDANCE, rel=1e-5)
    assert tightened(M - 0.3).tensions_ok[0] and not tightened(M + 0.3).tensions_ok[0]


def test_why_fails_counts_and_names_the_mildest():
    cells = [Cell(0, 2.5, 8.0, 90.0, 0.1), Cell(1, 0.5, 6.0, 90.0, 0.2), Cell(2, 0.5, 4.0, 90.0, 0.5),
             Cell(3, 1.5, 8.0, 90.0, 0.2)]
    works = np.array([False, False, True, False])
    reasons = ["a: tensions: x", "b: normal force in band 90 %", "", "d: tensions: y; normal force in band 80 %"]
    assert S.why_fails(cells, works, reasons) == ("3 of 4 sea states fail (tensions in 2, normal force in 2); "
                                                  "the mildest: b: normal force in band 90 %")
    assert S.why_fails(cells, np.ones(4, dtype=bool), [""] * 4) == ""


def test_a_design_that_works_in_no_sea_state_says_why(tmp_path):
    """A design study's candidate on winches too weak for it (issue 37: "works in 0.0 % of the
    seas: inf expected h" with no reason): its evaluation names how many sea states fail on
    what, and the mildest one's reason with the frame's placement on the ship."""
    from tests.test_issue24_design import _study, _x
    from marinecdpr.studies.design import evaluate, load_design, study_cells

    path = _study(tmp_path)
    spec, template = load_design(path)
    cells = study_cells(spec, path.parent)
    e = evaluate(spec, template, _x(spec, winch="small"), cells)
    assert e.sea_share == 0.0 and e.expected_hours == float("inf")
    head = "every sea state fails (tensions in 2); the mildest: Hs 1 m, Tp 8 s, heading 90 deg, the frame at ("
    assert e.sea_reason.startswith(head), e.sea_reason
    assert ") m in S (placement 1 of 6): tensions: cable " in e.sea_reason
    assert e.sea_reason.endswith(": even without the sea")
    medium = evaluate(spec, template, _x(spec, winch="medium"), cells)  # Hs 1 m works, Hs 5 m on the band alone
    assert medium.sea_share == 0.6
    assert medium.sea_reason.startswith("1 of 2 sea states fail (normal force in 1); the mildest: Hs 5 m, Tp 10 s, "
                                        "heading 90 deg"), medium.sea_reason
