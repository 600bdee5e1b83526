"""Issue 22, item 3: one implementation of every tension method and one rank test.

The compiled solver (:func:`marinecdpr.model.kernels.solve_tensions`) is what planning
(:func:`~marinecdpr.model.tension.distribute_tensions`), the workspace, the studies and the
closed loop (:func:`~marinecdpr.model.kernels.tensions_step`) run. Checked here against the
former numpy implementation, kept in ``tests/tension_reference.py`` (the paper's formulas:
adjugate, signed minors, the clipped lambda of eq. 20), and at the rank test's threshold,
where the three rank tests there used to be let a plan be feasible at a pose the loop
called singular.
"""

import numpy as np
import pytest

from marinecdpr.model import tension_solver as K
from marinecdpr.model.tension import EXACT_METHODS, distribute_tensions, full_rank, pseudo_inverse_tensions
from tension_reference import reference_distribute_tensions, reference_full_rank, reference_pseudo_inverse
from test_tension import random_problem

EXACT_R01 = [(4, 3), (7, 6), (3, 3), (6, 6)]


CASES = ([(shape, method) for shape in EXACT_R01 + [(6, 3), (8, 6)] for method in ("pseudo_inverse", "closed_form")]
         + [(shape, method) for shape in EXACT_R01 for method in ("minimum_variance", "minimum_norm")])
"""The exact methods' numpy formulas hold for r <= 1 (quadprog checks r > 1: test_compiled_qp.py)."""


@pytest.mark.parametrize(("shape", "method"), CASES)
def test_every_method_equals_the_numpy_formulas(shape, method):
    """Same steps feasible, and tensions within 1e-13 cond(J~) T_max of each other: the
    rounding of two ways of solving one system (measured: at most 5.7e-14 cond(J~) T_max,
    2.4e-13 T_max on 4 x 3 robots, 1.7e-9 T_max on the worst-conditioned random 6 x 6),
    over 20 x 200 random steps, half of them made by tensions within limits."""
    m, k = shape
    feasible = 0
    for seed in range(20):
        J, w, lo, hi = random_problem(seed, 200, m, k, 150.0)
        T_in = lo + np.random.default_rng(seed).uniform(0.3, 0.7, (100, m)) * (hi - lo)
        w[:100] = np.einsum("nia,ni->na", J[:100], T_in)  # half the steps made by tensions within limits
        ours = distribute_tensions(J, w, lo, hi, method=method)
        ref = reference_distribute_tensions(J, w, lo, hi, method=method)
        np.testing.assert_array_equal(ours.feasible, ref.feasible)
        f = ours.feasible
        gap = np.abs(ours.tensions[f] - ref.tensions[f]).max(axis=1)
        assert (gap <= 1e-13 * np.linalg.cond(J[f]) * hi.max()).all()
        feasible += int(ours.feasible.sum())
    assert feasible > 250  # the comparison is not between two NaN arrays


def test_pseudo_inverse_equals_the_numpy_formula_with_no_limits():
    for m, k in [(4, 3), (8, 6), (3, 3)]:
        J, w, _, _ = random_problem(7, 500, m, k, 150.0)
        T, ok = pseudo_inverse_tensions(J, w)
        T_ref, ok_ref = reference_pseudo_inverse(J, w)
        np.testing.assert_array_equal(ok, ok_ref)
        gap = np.abs(T - T_ref).max(axis=1)
        assert (gap <= 1e-13 * np.linalg.cond(J) * np.abs(T_ref).max()).all()
        np.testing.assert_allclose(np.einsum("nia,ni->na", J, T), w, rtol=0, atol=1e-11 * np.abs(w).max())


def near_singular(ratios, seed=3, m=4, k=3):
    """J~ (n, m, k) with singular values (1, ..., 1, sqrt(ratio)): the eigenvalues of J~^T J~
    have lambda_min / lambda_max = ratio exactly (to rounding), in random orientations."""
    rng = np.random.default_rng(seed)
    J = np.empty((len(ratios), m, k))
    for i, q in enumerate(ratios):
        U = np.linalg.qr(rng.normal(size=(m, m)))[0][:, :k]
        V = np.linalg.qr(rng.normal(size=(k, k)))[0]
        s = np.ones(k)
        s[-1] = np.sqrt(q)
        J[i] = U @ np.diag(s) @ V.T
    return J


def old_rank_tests(J):
    """The two rank tests planning and the loop used before (4 x 3): the planner's
    det G > 1e-12 (trace / 3)^3 and the loop's |det G| > 1e-12 (max G_aa)^3."""
    G = np.einsum("nia,nib->nab", J, J)
    det = np.linalg.det(G)
    plan = det > 1e-12 * (np.trace(G, axis1=1, axis2=2) / 3) ** 3
    loop = np.abs(det) > 1e-12 * np.diagonal(G, axis1=1, axis2=2).max(axis=1) ** 3
    return plan, loop


def test_plan_and_loop_agree_at_every_near_singular_pose():
    """Across lambda_min / lambda_max from 1e-13 to 1e-11: the old tests disagreed (a plan
    feasible where the loop fell back to the plan's tensions); now the plan, the loop and
    full_rank give one answer, that of the eigenvalues, and the same bits of tension."""
    ratios = np.geomspace(1e-13, 1e-11, 801)
    J = near_singular(ratios)
    plan_old, loop_old = old_rank_tests(J)
    assert (plan_old & ~loop_old).sum() > 50  # the bug: feasible in the plan, singular in the loop
    lo, hi = np.full(4, 10.0), np.full(4, 450.0)
    T0 = np.array([100.0, 200.0, 300.0, 150.0])
    w = np.einsum("nia,i->na", J, T0)  # made by tensions within limits: feasible where full rank
    ok = full_rank(J)
    clear = np.abs(ratios / 1e-12 - 1.0) > 1e-3  # eigenvalues to rounding: 1e-4 relative at 1e-12
    np.testing.assert_array_equal(ok[clear], ratios[clear] > 1e-12)
    np.testing.assert_array_equal(ok[clear], reference_full_rank(J)[clear])
    J6, w6, T = np.zeros((4, 6)), np.zeros(6), np.empty(4)
    dofs = np.array([0, 2, 4])
    work = K.tension_work(4, 3)
    for method, code in K.METHOD_CODES.items():
        sol = distribute_tensions(J, w, lo, hi, method=method)
        if method in ("closed_form", "minimum_variance", "improved_closed_form"):  # T0 is their closed form
            np.testing.assert_array_equal(sol.feasible, ok)
        for i in range(len(ratios)):
            J6[:, dofs] = J[i]
            w6[dofs] = w[i]
            if K.tensions_step(J6, w6, dofs, lo, hi, code, T, work):
                assert sol.feasible[i]
                np.testing.assert_array_equal(T, sol.tensions[i])
            elif sol.feasible[i]:
                # where the compiled step gives up, the plan's exact fallback (issue 37, item 10)
                # may find tensions, which the loop then takes from the plan: they must hold
                assert method in EXACT_METHODS
                Ti = sol.tensions[i]
                assert np.all(Ti >= lo - 1e-6) and np.all(Ti <= hi + 1e-6)
                np.testing.assert_allclose(np.einsum("ia,i->a", J[i], Ti), w[i], atol=1e-6 * np.abs(w[i]).max())
            else:
                assert np.isnan(sol.tensions[i]).all()

