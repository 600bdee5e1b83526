"""The cables-as-built error budget (issue 14, item 4): each effect measured on the plan
against point anchors, with hand relations; effects the scenario does not describe are
reported as such, never as zero."""

import numpy as np
import pytest

import marinecdpr
from marinecdpr.studies.error_budget import error_budget

import conftest
from conftest import make_scenario
from test_pulley import with_pulleys

WINCH = dict(drum_radius_m=0.05, gear_ratio=10.0, torque_max_Nm=2.0, speed_max_rad_s=300.0, power_max_W=200.0,
             rotor_inertia_kg_m2=1e-4, drum_inertia_kg_m2=1e-3)


def as_built(data, *, winch=WINCH, weight=0.35, EA=1.0e5):
    with_pulleys(data)
    data["robot"]["cable_weight_N_m"] = weight
    data["robot"]["winch"] = winch
    data["simulation"] = {"cables": {"model": "elastic", "stiffness_EA_N": EA}}


def test_an_ideal_scenario_describes_no_effect():
    effects, report, held = error_budget(marinecdpr.load_scenario("paper"))
    assert report is None and held is None
    for e in effects:
        assert e.length_change_m is None and e.tension_change_N is None
    assert [e.note.split("(")[-1].rstrip(")") for e in effects] == [
        "robot.cables[].pulley_radius_m", "simulation.cables.model = \"elastic\" with EA",
        "robot.cable_weight_N_m", "robot.winch"]


def test_the_paper_robot_as_built():
    sc = make_scenario(as_built)
    p = marinecdpr.plan(sc)
    (pulley, stretch, sag, winch), report, held = error_budget(sc, p, workspace_grid=None)
    point = marinecdpr.plan(make_scenario(lambda d: as_built(d) or [c.update(pulley_radius_m=0.0, pulley_axis=None)
                                                                     for c in d["robot"]["cables"]]))
    assert pulley.length_change_m == pytest.approx(np.abs(p.lengths - point.lengths).max(), rel=1e-12)
    assert 5e-3 < pulley.length_change_m < 15e-3  # a 25 mm pulley on a ~1 m cable bent 60-120 deg
    # the stretch of an elastic cable: L - L0 = T L / (EA + T), at most 450 N x 1.4 m / 1e5 N
    assert stretch.length_change_m == pytest.approx((p.tensions * p.lengths / (1e5 + p.tensions)).max(), rel=1e-12)
    assert stretch.length_change_m < 450 * 1.4 / 1e5
    # sag: the winch holds more than the platform by at most w times the cable's rise
    assert 0 < sag.tension_change_N <= 0.35 * 1.45
    assert 0 < sag.length_change_m < 1e-3
    # a winch strong enough: every step within its limits, peak torque below 2 N m
    assert winch.tension_change_N == pytest.approx(0.0, abs=1e-9) and report.within_limits.all()
    assert np.all(report.peak_torque_Nm <= 2.0 + 1e-12)
    # its peak torque is the largest T r_d / G, the drum's inertia moving it by under 1 %
    assert report.peak_torque_Nm.max() == pytest.approx(p.tensions.max() * 0.05 / 10.0, rel=0.01)


def test_a_weak_winch_is_flagged():
    weak = dict(WINCH, torque_max_Nm=1.0)  # holds 200 N at rest; the plan asks up to ~300
    sc = make_scenario(lambda d: as_built(d, winch=weak))
    (_, _, _, winch), report, _ = error_budget(sc, workspace_grid=None)
    assert winch.tension_change_N > 50.0 and "steps lost to the winches' limits" in winch.note
    # the plan keeps within them; the note says what the plan without them would ask
    assert report.within_limits.all() and np.all(report.peak_torque_Nm <= 1.0 + 1e-12)
    asks = float(winch.note.split("asks up to ")[1].split(" N m")[0])
    assert asks > 1.5


def test_the_workspace_change_of_each_effect():
    """The workspace column against workspace maps made by hand: the point model's held share,
    and each effect's share less it (a weak winch loses much of the frame; stretch and sag
    change no tension, so nothing)."""
    from marinecdpr.studies.workspace import workspace_map

    weak = dict(WINCH, torque_max_Nm=1.0)

    def make_scenario(edit):  # 3 s of the ship's motion at each held pose
        return conftest.make_scenario(lambda d: (edit(d), d["time"].update(duration_s=3.0)))

    sc = make_scenario(lambda d: as_built(d, winch=weak))
    grid = (8, 5)
    (pulley, stretch, sag, winch), _, held = error_budget(sc, workspace_grid=grid)

    def share(s):
        f = workspace_map(s, n=grid).fraction_feasible
        return np.mean(f[np.isfinite(f)] == 1.0)

    point = make_scenario(lambda d: d["simulation"].update(cables={"model": "elastic", "stiffness_EA_N": 1e5}))
    assert held == share(point)
    assert pulley.workspace_change == share(make_scenario(lambda d: (with_pulleys(d), d["simulation"].update(
        cables={"model": "elastic", "stiffness_EA_N": 1e5})))) - held
    w = make_scenario(lambda d: (d["robot"].update(winch=weak),
                                 d["simulation"].update(cables={"model": "elastic", "stiffness_EA_N": 1e5})))
    assert winch.workspace_change == share(w) - held
    assert winch.workspace_change < -0.02 and stretch.workspace_change == 0.0 and sag.workspace_change == 0.0
