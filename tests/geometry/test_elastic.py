"""Issue 22, item 3: one elastic-cable law (marinecdpr.geometry.elastic), by hand and
the same bits from numpy and from compiled code."""

import numpy as np
from numba import njit

from marinecdpr.geometry.elastic import axial_stiffness, elastic_tension, stretched_length, unstretched_length


def test_the_law_by_hand():
    # a 2 m cable of EA 1e5 N stretched by 2 mm carries 100 N; 0.5 N s/m at 0.1 m/s adds 0.05 N
    assert abs(elastic_tension(2.002, 2.0, 0.0, 1e5, 0.5) - 100.0) < 1e-9
    assert abs(elastic_tension(2.002, 2.0, 0.1, 1e5, 0.5) - 100.05) < 2e-11  # 2.002 - 2.0 in binary: 1.1e-11 N
    assert elastic_tension(1.999, 2.0, 5.0, 1e5, 0.5) == 0.0       # slack
    assert elastic_tension(2.0001, 2.0, -1.0, 1e5, 100.0) == 0.0   # taut, pushed by the damping: at least 0
    assert abs(unstretched_length(2.002, 100.0, 1e5) - 2.0) < 1e-15
    assert abs(stretched_length(2.0, 100.0, 1e5) - 2.002) < 1e-15
    assert axial_stiffness(2.0, 1e5) == 5e4
    assert unstretched_length(3.0, 250.0, np.inf) == 3.0 and stretched_length(3.0, 250.0, np.inf) == 3.0


def test_tension_and_unstretched_length_invert_each_other_over_random_cables():
    rng = np.random.default_rng(4)
    L = rng.uniform(0.5, 30.0, 1000)
    T = rng.uniform(0.0, 5000.0, 1000)
    EA = rng.uniform(1e4, 1e7, 1000)
    L0 = unstretched_length(L, T, EA)
    back = np.array([elastic_tension(L[i], L0[i], 0.0, EA[i], 0.0) for i in range(1000)])
    np.testing.assert_allclose(back, T, rtol=0, atol=1e-9 * T.max() + 1e-12 * EA.max())
    np.testing.assert_allclose(stretched_length(L0, T, EA), L, rtol=1e-15)
    # the stiffness is the law's derivative: central difference of T(L)
    h = 1e-7 * L0
    fd = np.array([(elastic_tension(L[i] + h[i], L0[i], 0.0, EA[i], 0.0)
                    - elastic_tension(L[i] - h[i], L0[i], 0.0, EA[i], 0.0)) / (2 * h[i]) for i in range(1000)])
    np.testing.assert_allclose(fd, axial_stiffness(L0, EA), rtol=1e-6)


@njit
def _compiled(L, T, EA, out):
    for i in range(L.shape[0]):
        out[0, i] = unstretched_length(L[i], T[i], EA[i])
        out[1, i] = stretched_length(L[i], T[i], EA[i])
        out[2, i] = axial_stiffness(L[i], EA[i])


def test_numpy_and_compiled_callers_get_the_same_bits():
    rng = np.random.default_rng(5)
    L, T, EA = rng.uniform(0.5, 30.0, 500), rng.uniform(0.0, 5000.0, 500), rng.uniform(1e4, 1e7, 500)
    out = np.empty((3, 500))
    _compiled(L, T, EA, out)
    np.testing.assert_array_equal(out[0], unstretched_length(L, T, EA))
    np.testing.assert_array_equal(out[1], stretched_length(L, T, EA))
    np.testing.assert_array_equal(out[2], axial_stiffness(L, EA))
