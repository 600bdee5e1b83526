"""The winches' limits in the planner (issue 14, item 2): each step's tensions within what
each winch can give at the cable's motion, the plan unchanged where those limits do not
bind, the steps a winch cannot follow flagged and named."""

import numpy as np
import pytest

import marinecdpr
from marinecdpr.model.winch import WinchParams, length_accelerations, winch_tension_bounds
from marinecdpr.planning.planner import WINCH_NO_TENSION, WINCH_OVERSPEED

from conftest import make_scenario

WINCH = dict(drum_radius_m=0.05, gear_ratio=10.0, torque_max_Nm=2.0, speed_max_rad_s=300.0, power_max_W=200.0,
             rotor_inertia_kg_m2=1e-4, drum_inertia_kg_m2=1e-3, coulomb_friction_Nm=0.02,
             viscous_friction_Nm_s=1e-4, gear_efficiency=0.9)


def with_winch(**changes):
    return make_scenario(lambda d: d["robot"].__setitem__("winch", dict(WINCH, **changes)))


@pytest.fixture(scope="module")
def free_plan():
    return marinecdpr.plan(marinecdpr.load_scenario("paper"))


def test_length_accelerations_are_the_derivative_of_the_rates(free_plan):
    """L'' (central differences of L' 0.1 ms apart) against the plan's own L' differenced on
    its 1 ms grid: they agree to the grid's O(dt^2) error, and chunking changes nothing."""
    sc = with_winch()
    p = marinecdpr.plan(sc)
    grid = length_accelerations(p.length_rates, sc.time.step_s)
    scale = np.abs(p.winch.length_accelerations).max()
    assert scale > 0.05
    np.testing.assert_allclose(p.winch.length_accelerations[1:-1], grid[1:-1], atol=1e-5 * scale)
    chunked = marinecdpr.plan(sc, chunk_steps=777)
    for name in ("length_accelerations", "lower", "upper", "limit"):
        np.testing.assert_array_equal(getattr(chunked.winch, name), getattr(p.winch, name))
    np.testing.assert_array_equal(chunked.tensions, p.tensions)


def test_a_strong_winch_changes_nothing(free_plan):
    p = marinecdpr.plan(with_winch())
    np.testing.assert_array_equal(p.tensions, free_plan.tensions)
    assert p.all_feasible and not p.winch.limit.any()
    # the bounds are the winch's at the plan's motion, cut by the cable's limits
    b = winch_tension_bounds(p.length_rates, p.winch.length_accelerations, WinchParams(**WINCH), 10.0, 450.0)
    np.testing.assert_array_equal(p.winch.lower, b.lower_N)
    np.testing.assert_array_equal(p.winch.upper, b.upper_N)
    # at rest the most a winch holds is tau_max G eta / r_d less friction: (2 - 0.02) 10 0.9 / 0.05 = 356.4 N
    still = np.flatnonzero(np.all(p.length_rates == 0.0, axis=1))
    if still.size:
        assert p.winch.upper[still[0]] == pytest.approx(356.4, rel=1e-12)


@pytest.mark.parametrize("method", ["minimum_variance", "improved_closed_form"])
def test_a_weak_winch_bounds_the_plan(free_plan, method):
    """A 1.5 N m motor holds 266 N at rest; the paper asks up to ~330 N. Every step is within
    the winch's range; steps where it does not bind keep the free plan's tensions, the rest
    are solved anew within it (the wrench still made)."""
    sc = with_winch(torque_max_Nm=1.5)
    p = marinecdpr.plan(sc, method=method)
    free = free_plan if method == "minimum_variance" else marinecdpr.plan(marinecdpr.load_scenario("paper"),
                                                                          method=method)
    assert free.all_feasible
    # minimum variance is exact; the improved closed form (a heuristic) may miss a few steps
    ok = p.feasible
    assert ok.all() if method == "minimum_variance" else ok.mean() > 0.9
    tol = 1e-9 * 450
    assert np.all(p.tensions[ok] >= p.winch.lower[ok] - tol) and np.all(p.tensions[ok] <= p.winch.upper[ok] + tol)
    inside = np.all((free.tensions >= p.winch.lower - tol) & (free.tensions <= p.winch.upper + tol), axis=1)
    assert 0 < inside.sum() < p.n_steps and ok[inside].all()
    np.testing.assert_allclose(p.tensions[inside], free.tensions[inside], rtol=0, atol=1e-9)
    moved = ok & ~inside
    assert np.abs(p.tensions[moved] - free.tensions[moved]).max() > 10.0
    from marinecdpr.geometry.kinematics import cable_kinematics
    from marinecdpr.geometry.rotations import matrix_from_euler
    kin = cable_kinematics(p.pose[ok, :3], matrix_from_euler(p.pose[ok, 3:]), sc.robot.frame_anchors,
                           sc.robot.platform_anchors)
    c = list(sc.robot.controlled)
    np.testing.assert_allclose(np.einsum("nmk,nm->nk", kin.J_tilde[:, :, c], p.tensions[ok]), p.wrench[ok][:, c],
                               atol=1e-8)


def test_a_weaker_winch_loses_steps_and_says_why():
    """A 1 N m motor holds 176 N at rest: some steps have no tensions within its range."""
    p = marinecdpr.plan(with_winch(torque_max_Nm=1.0))
    assert 0 < p.feasible.sum() < p.n_steps
    assert not (p.winch.limit == WINCH_OVERSPEED).any()
    msg = p.infeasibility()
    assert "its winch's most" in msg and "short" in msg


def test_an_overspeed_is_named():
    """A motor limited to 20 rad/s turns a 50 mm drum at 10:1 at 0.1 m/s; the paper's cables
    move up to ~0.16 m/s."""
    sc = with_winch(speed_max_rad_s=20.0)
    p = marinecdpr.plan(sc)
    over = np.abs(p.length_rates) * 10.0 / 0.05 > 20.0
    np.testing.assert_array_equal(p.winch.limit == WINCH_OVERSPEED, over)
    np.testing.assert_array_equal(p.feasible, ~over.any(axis=1) & p.feasible)
    assert not p.feasible[over.any(axis=1)].any()
    msg = p.infeasibility()
    assert "faster than its motor can turn (robot.winch.speed_max_rad_s)" in msg
    first = np.flatnonzero(over.any(axis=1))[0]
    assert f"t = {p.t[first]:.4g} s" in msg
    assert not (p.winch.limit == WINCH_NO_TENSION).any()


def test_the_cli_refuses_a_plan_a_winch_cannot_follow(tmp_path):
    import subprocess
    import sys
    import tomllib
    from importlib import resources

    text = (resources.files("marinecdpr.scenario") / "builtin" / "paper.toml").read_text()
    text += ("\n[robot.winch]\ndrum_radius_m = 0.05\ngear_ratio = 10\ntorque_max_Nm = 2\n"
             "speed_max_rad_s = 20\npower_max_W = 200\n")
    tomllib.loads(text)
    f = tmp_path / "slow.toml"
    f.write_text(text)
    r = subprocess.run([sys.executable, "-m", "marinecdpr.cli", "plan", str(f), "--out", str(tmp_path / "o")],
                       capture_output=True, text=True)
    assert r.returncode != 0
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and "winch" in lines[0] and "speed_max_rad_s" in lines[0], r.stderr


def test_plan_csv_has_the_winches_bounds_and_the_sag(tmp_path):
    """plan.csv gains Tlo/Thi with winches and sag/Twinch with heavy cables, the plan's own
    values; written in pieces it is the same file byte for byte."""
    from marinecdpr.report.writers import plan_csv_writer, write_plan_csv

    sc = marinecdpr.load_scenario("paper_as_built")
    p = marinecdpr.plan(sc)
    path = write_plan_csv(p, sc, tmp_path / "plan.csv")
    rows = np.genfromtxt(path, delimiter=",", names=True)
    for prefix, values in (("Tlo", p.winch.lower), ("Thi", p.winch.upper), ("sag", p.sag.lengths),
                           ("Twinch", p.sag.winch_tensions)):
        got = np.column_stack([rows[f"{prefix}{i}"] for i in range(1, 5)])
        np.testing.assert_allclose(got, values, rtol=1e-9, atol=1e-12)
    assert rows.dtype.names[-1] == "feasible"
    with plan_csv_writer(sc, tmp_path / "pieces.csv") as write:
        for piece in marinecdpr.iter_plan(sc, chunk_steps=4000):
            write(piece)
    assert (tmp_path / "pieces.csv").read_bytes() == path.read_bytes()
