"""marinecdpr.borrowed: a record's arrays without reference counting, same memory."""

from typing import NamedTuple

import numpy as np
from numba import njit

from marinecdpr.borrowed import borrowed


class Inner(NamedTuple):
    a: np.ndarray
    scale: float


class Outer(NamedTuple):
    inner: Inner
    b: np.ndarray
    flag: bool


@njit
def _scaled_sum_and_write(rec, k):
    rec = borrowed(rec)
    total = 0.0
    for i in range(rec.inner.a.shape[0]):  # reads through the borrowed views
        total += rec.inner.scale * rec.inner.a[i, k]
    rec.b[k] = total  # writes reach the caller's array
    return total, rec.flag


def test_borrowed_record_reads_and_writes_the_callers_memory():
    rng = np.random.default_rng(3)
    a = rng.normal(size=(5, 4))
    b = np.zeros(4)
    rec = Outer(Inner(a, 2.5), b, True)
    for k in range(4):
        total, flag = _scaled_sum_and_write(rec, k)
        assert flag is True
        assert abs(total - 2.5 * a[:, k].sum()) < 1e-12
    np.testing.assert_allclose(b, 2.5 * a.sum(axis=0), rtol=1e-14)


def test_borrowed_arrays_leave_the_owners_alive_and_intact():
    """Borrowing neither frees nor keeps anything: after many calls the caller's arrays are
    whole and Python still owns them alone."""
    import sys

    a = np.arange(12.0).reshape(3, 4)
    b = np.zeros(4)
    rec = Outer(Inner(a, 1.0), b, False)
    before = sys.getrefcount(a), sys.getrefcount(b)
    for _ in range(1000):
        _scaled_sum_and_write(rec, 1)
    assert (sys.getrefcount(a), sys.getrefcount(b)) == before
    np.testing.assert_array_equal(a, np.arange(12.0).reshape(3, 4))
    assert b[1] == 1.0 + 5.0 + 9.0
