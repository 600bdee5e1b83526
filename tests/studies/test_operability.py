"""Operability over scatter diagrams: calm is workable, rough is not, Dask agrees with serial."""

import copy
import tomllib
from pathlib import Path
from importlib import resources

import numpy as np
import pytest

from marinecdpr import ScenarioError
from marinecdpr.studies.operability import ScatterDiagram, operability, read_scatter_csv
from marinecdpr.scenario.loading import scenario_from_dict

SHORT = dict(duration_s=120.0, step_s=0.05)


def sea_robot(mass_kg=7.6):
    """The paper's robot and circle in paper_sea's seas, with a platform heavy enough
    (7.86 kg is its still-ship limit) that rough seas break the tension limits."""
    data = tomllib.loads((resources.files("marinecdpr.scenario") / "builtin" / "paper_sea.toml").read_text())
    data = copy.deepcopy(data)
    data["robot"]["mass_kg"] = mass_kg
    return scenario_from_dict(data, base_dir=Path(str(resources.files("marinecdpr.scenario") / "builtin")))


def test_calm_seas_are_always_workable():
    calm = ScatterDiagram(np.array([0.01, 0.03, 0.05]), np.array([5.0, 9.0]), np.full((3, 2), 1 / 6))
    op = operability(sea_robot(), calm, headings_deg=(180.0, 90.0), **SHORT)
    assert op.operability == pytest.approx(1.0)
    assert all(r.operable and r.fraction_feasible == 1.0 for r in op.results)


def test_operability_falls_as_hs_grows():
    hs = np.array([0.25, 1.0, 2.0, 4.0, 9.0])
    rough = ScatterDiagram(hs, np.array([7.0, 11.0]), np.full((5, 2), 0.1))
    op = operability(sea_robot(), rough, headings_deg=(90.0,), **SHORT)
    grid = op.operable_grid(90.0)
    assert grid[0].all() and not grid[-1].any()          # calm works, 9 m does not
    for j in range(2):  # the limiting Hs: the largest up to which every cell works (one record
        col = grid[:, j]  # per cell need not fail monotonically in Hs)
        first_fail = np.flatnonzero(col == 0)[0]
        assert op.limiting_hs[90.0][j] == (hs[first_fail - 1] if first_fail > 0 else 0.0)
    assert 0.0 < op.operability < 1.0
    # a margin asks more of the cables: never more workable
    strict = operability(sea_robot(), rough, headings_deg=(90.0,), margin_N=20.0, **SHORT)
    assert strict.operability <= op.operability
    assert all(r.min_margin_N >= 20.0 for r in strict.results if r.operable)


def test_a_sea_states_verdict_does_not_depend_on_the_other_sea_states_asked_for():
    """Issue 12: the record of a sea state is a function of the sea state (and the template's
    seed), not of its place in the request: headings in either order, or a heading alone,
    give every cell the same margin to the bit; another template seed gives another record."""
    diagram = ScatterDiagram(np.array([1.5, 2.5]), np.array([6.0, 10.0]), np.full((2, 2), 0.25))
    a = operability(sea_robot(), diagram, headings_deg=(90.0, 180.0), **SHORT)
    b = operability(sea_robot(), diagram, headings_deg=(180.0, 90.0), **SHORT)
    alone = operability(sea_robot(), diagram, headings_deg=(180.0,), **SHORT)

    def by_state(op):
        return {(r.cell.hs, r.cell.tp, r.cell.heading_deg): (r.operable, r.min_margin_N, r.fraction_feasible)
                for r in op.results}

    assert by_state(a) == by_state(b)
    assert a.per_heading == b.per_heading
    assert {k: v for k, v in by_state(a).items() if k[2] == 180.0} == by_state(alone)
    # the record itself: the same sea state, the same ship motion; another seed, another
    from marinecdpr.motion.basemotion import evaluate_base_motion
    from marinecdpr.studies.operability import Cell, cell_scenario

    def heave(template, index):
        sc = cell_scenario(template, Cell(index, 2.5, 10.0, 180.0, 0.25), 60.0, 0.05)
        return evaluate_base_motion(sc.base_motion, np.linspace(0.0, 60.0, 7)).eta[:, 2]

    other = sea_robot()
    other = other.with_changes(base_motion=other.base_motion.model_dump(exclude_none=True) | {"seed": 99})
    np.testing.assert_array_equal(heave(sea_robot(), 0), heave(sea_robot(), 5))
    assert np.abs(heave(other, 0) - heave(sea_robot(), 0)).max() > 0.05


def test_dask_gives_the_serial_results():
    """A real local cluster (two worker processes): the same verdicts and margins, to the bit."""
    diagram = ScatterDiagram(np.array([0.5, 3.0]), np.array([6.0, 10.0]), np.full((2, 2), 0.25))
    kw = dict(headings_deg=(180.0, 120.0), **SHORT)
    serial = operability(sea_robot(), diagram, executor="serial", **kw)
    seen = []
    parallel = operability(sea_robot(), diagram, executor="dask", workers=2,
                           progress=lambda done, total: seen.append((done, total)), **kw)
    assert [(r.operable, r.fraction_feasible, r.min_margin_N) for r in serial.results] == \
        [(r.operable, r.fraction_feasible, r.min_margin_N) for r in parallel.results]
    assert seen[-1] == (8, 8)
    # and on a scheduler that is already running (--scheduler ADDRESS)
    from dask.distributed import LocalCluster

    with LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        remote = operability(sea_robot(), diagram, executor="dask", scheduler=cluster.scheduler_address, **kw)
    assert [r.min_margin_N for r in remote.results] == [r.min_margin_N for r in serial.results]


def test_scatter_csv(tmp_path):
    good = tmp_path / "s.csv"
    good.write_text("hs_m,tp_s,probability\n1,6,0.3\n2,6,0.1\n1,8,0.6\n")
    d = read_scatter_csv(good)
    np.testing.assert_array_equal(d.hs, [1, 2])
    np.testing.assert_array_equal(d.tp, [6, 8])
    np.testing.assert_allclose(d.probability, [[0.3, 0.6], [0.1, 0.0]])
    for text, message in (("hs,tp,p\n1,2,3\n", "row 1: the header must be hs_m,tp_s,probability"),
                          ("hs_m,tp_s,probability\n1,6,x\n", "row 2: not numbers"),
                          ("hs_m,tp_s,probability\n1,6,0.5\n1,6,0.5\n", "row 3: Hs 1 m, Tp 6 s appears twice"),
                          ("hs_m,tp_s,probability\n-1,6,0.5\n", "row 2: hs_m and tp_s must be positive")):
        bad = tmp_path / "bad.csv"
        bad.write_text(text)
        with pytest.raises(ScenarioError, match=message):
            read_scatter_csv(bad)


def test_operability_needs_a_sea_state(paper):
    with pytest.raises(ScenarioError, match="needs a \\[base_motion\\] of type sea_state"):
        operability(paper, ScatterDiagram(np.array([1.0]), np.array([8.0]), np.ones((1, 1))))


def test_tracking_error_criterion():
    """With max_error_m, a cell also needs the closed loop to hold the platform close."""
    diagram = ScatterDiagram(np.array([0.5, 3.0]), np.array([8.0]), np.full((2, 1), 0.5))
    kw = dict(headings_deg=(90.0,), duration_s=20.0, step_s=0.01)
    loose = operability(sea_robot(5.0), diagram, max_error_m=1.0, **kw)
    assert all(r.operable and 0 < r.max_error_m < 1e-3 for r in loose.results)
    tight = operability(sea_robot(5.0), diagram, max_error_m=1e-12, **kw)
    assert not any(r.operable for r in tight.results)
    assert [r.max_error_m for r in tight.results] == [r.max_error_m for r in loose.results]


def test_operability_over_a_workspace_grid():
    """Judging held poses over the frame: the workable share of the frame shrinks in rough seas."""
    diagram = ScatterDiagram(np.array([0.1, 6.0]), np.array([10.0]), np.full((2, 1), 0.5))
    kw = dict(headings_deg=(90.0,), duration_s=60.0, step_s=0.05, workspace=(12, 8))
    op = operability(sea_robot(5.0), diagram, min_area=0.0, **kw)
    calm, rough = op.results
    assert 0.0 < rough.fraction_feasible < calm.fraction_feasible <= 1.0
    strict = operability(sea_robot(5.0), diagram, min_area=0.5 * (calm.fraction_feasible + rough.fraction_feasible),
                         **kw)
    assert [r.operable for r in strict.results] == [True, False]


def test_wilson_interval_by_hand():
    from marinecdpr.studies.operability import wilson_interval

    lo, hi = wilson_interval(7, 10)  # p = 0.7, z = 1.96: (0.7 + 0.19207) / 1.38415 -+ ...
    assert (lo, hi) == pytest.approx((0.39678, 0.89221), abs=1e-5)
    assert wilson_interval(10, 10) == (pytest.approx(0.72247, abs=1e-5), 1.0)
    assert wilson_interval(0, 10) == (0.0, pytest.approx(0.27753, abs=1e-5))


def test_realisations_give_a_probability_with_its_interval():
    """Each sea state flies several independent records; its probability of success is the
    share that hold, the operability their probability-weighted mean, with intervals that
    hold the estimate; another template seed gives an estimate within the interval."""
    from marinecdpr.studies.operability import Cell, evaluate_cell

    diagram = ScatterDiagram(np.array([1.5, 2.5]), np.array([7.0, 11.0]), np.array([[0.3, 0.2], [0.3, 0.2]]))
    kw = dict(headings_deg=(90.0,), realisations=8, **SHORT)
    op = operability(sea_robot(), diagram, **kw)
    rs = op.results
    assert all(r.realisations == 8 for r in rs)
    assert 0 < sum(r.successes for r in rs) < 8 * len(rs)  # neither all nor none: a real spread
    for r in rs:
        assert r.operable == (r.successes == 8)
        lo, hi = r.interval
        assert lo <= r.success_probability <= hi
    assert op.operability == pytest.approx(sum(r.cell.probability * r.successes / 8 for r in rs), rel=1e-12)
    assert op.interval[0] <= op.operability <= op.interval[1]
    # the same records again, cell by cell: the study and a lone cell agree
    cell = rs[-1].cell
    alone = evaluate_cell(sea_robot(), cell, margin_N=0.0, realisations=8, **SHORT)
    assert (alone.successes, alone.min_margin_N) == (rs[-1].successes, rs[-1].min_margin_N)
    # a second template seed: another set of records, an estimate within the first's interval
    other = sea_robot()
    other = other.with_changes(base_motion=other.base_motion.model_dump(exclude_none=True) | {"seed": 7})
    op2 = operability(other, diagram, **kw)
    assert [r.successes for r in op2.results] != [r.successes for r in rs]
    assert abs(op2.operability - op.operability) <= max(op.operability - op.interval[0],
                                                        op.interval[1] - op.operability)


def test_paper_sea_with_two_template_seeds_agrees_within_its_interval():
    """Issue 12's check, on short records: the default number of realisations, each heading."""
    from marinecdpr.studies.operability import REALISATIONS

    diagram = read_scatter_csv(resources.files("marinecdpr") / "data" / "scatter_illustrative.csv")
    paper_sea = __import__("marinecdpr").load_scenario("paper_sea")
    other = paper_sea.with_changes(base_motion=paper_sea.base_motion.model_dump(exclude_none=True) | {"seed": 11})
    kw = dict(headings_deg=(180.0, 90.0), duration_s=60.0, step_s=0.05)
    a, b = operability(paper_sea, diagram, **kw), operability(other, diagram, **kw)
    assert a.results[0].realisations == REALISATIONS
    for h in (180.0, 90.0):
        lo, hi = a.per_heading_interval[h]
        assert lo <= b.per_heading[h] <= hi and lo <= a.per_heading[h] <= hi
