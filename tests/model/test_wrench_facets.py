"""The facets of the wrenches that tensions within limits give (issue 37, item 3): the set is
a zonotope, and its facets' headrooms are the linear programme's headroom."""

from __future__ import annotations

import numpy as np
import pytest

from marinecdpr.model.tension import largest_headroom, pseudo_inverse_tensions, wrench_faces


@pytest.mark.parametrize("m,k", [(4, 3), (3, 2), (5, 3), (8, 6), (7, 6)])
def test_the_facets_headroom_is_the_linear_programme_s(m, k):
    """min_f (h_f - |n_f . (w - c)|) / s_f, capped at the narrowest range's half, equals
    largest_headroom (closed form for one degree of redundancy, vertices or HiGHS beyond) for
    random structure matrices, limits and wrenches, feasible or not."""
    rng = np.random.default_rng(m * 10 + k)
    J = rng.normal(size=(300, m, k))
    w = rng.normal(size=(300, k)) * 2.0
    lo = rng.uniform(1.0, 5.0, size=m)
    hi = lo + rng.uniform(5.0, 20.0, size=m)
    T_s, _ = pseudo_inverse_tensions(J, w)
    ref = largest_headroom(J, T_s, lo, hi)
    f = wrench_faces(J, lo, hi)
    u = np.einsum("nfk,nk->nf", f.normal, w - f.centre)
    h = np.minimum(((f.half_width - np.abs(u)) / f.per_newton).min(axis=1), ((hi - lo) / 2).min())
    np.testing.assert_allclose(h, ref, rtol=0, atol=1e-10 * np.abs(ref).max())
    assert (ref < 0).any() and (ref > 0).any()


def test_a_square_of_four_cables_by_hand():
    """Two cables along +x and -x, two along +z and -z (k = 2, T in [10, 110] N): the set is the
    square [-100, 100]^2 about 0. The wrench (60, -30) N lies 40 N inside the +x facet (cables
    1 and 2 at their limits there); tightening every limit by M moves that facet in by 2 M,
    so its headroom is 20 N: T_1 = 110 - M, T_2 = 10 + M give 100 - 2 M = 60."""
    J = np.array([[[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [0.0, -1.0]]])
    f = wrench_faces(J, np.full(4, 10.0), np.full(4, 110.0))
    np.testing.assert_allclose(f.centre[0], [0.0, 0.0], atol=1e-12)
    facet = np.flatnonzero(np.abs(f.normal[0, :, 0]) > 0.5)  # normals along x: cables 3 or 4 free
    assert set(f.free[facet, 0].tolist()) == {2, 3}
    np.testing.assert_allclose(f.half_width[0, facet], 100.0, rtol=1e-12)
    np.testing.assert_allclose(f.per_newton[0, facet], 2.0, rtol=1e-12)
    u = f.normal[0] @ np.array([60.0, -30.0])
    head = (f.half_width[0] - np.abs(u)) / f.per_newton[0]
    assert head.min() == pytest.approx(20.0, rel=1e-12)  # (100 - 60) / 2: each x cable gives 20 N
