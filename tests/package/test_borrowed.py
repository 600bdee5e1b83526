"""marinecdpr.borrowed: a record's arrays without reference counting, same memory; a record
stored at an address and loaded there."""

from typing import NamedTuple

import numpy as np
from numba import carray, njit, typeof, types

from marinecdpr.borrowed import (
    borrowed, c_function, call_stored, data_address, float64_pointer, load, store, stored, stored_size,
)


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


@njit
def _loaded_sum_and_write(address, k):
    rec = load(address, OUTER)
    total = 0.0
    for i in range(rec.inner.a.shape[0]):
        total += rec.inner.scale * rec.inner.a[i, k]
    rec.b[k] = total
    return total, rec.flag


@njit
def _stored(rec, words):
    store(rec, words)


OUTER = typeof(Outer(Inner(np.zeros((1, 1)), 0.0), np.zeros(1), False))


def test_a_stored_record_is_read_and_written_at_its_address():
    """store() writes the record's struct (arrays borrowed) into words; load() at that address
    reads the caller's arrays and writes reach them. The size by hand: a 2-d array's struct is
    9 words (meminfo, parent, nitems, itemsize, data, 2 shapes, 2 strides), a 1-d one's 7; the
    float 1, the bool 1 byte padded to a word: 9 + 1 + 7 + 1 = 18 words."""
    assert stored_size(OUTER) == 18 * 8
    rng = np.random.default_rng(5)
    a, b = rng.normal(size=(5, 4)), np.zeros(4)
    rec = Outer(Inner(a, 2.5), b, True)
    words = np.zeros(18, dtype=np.int64)
    _stored(rec, words)
    for k in range(4):
        total, flag = _loaded_sum_and_write(words.ctypes.data, k)
        assert flag is True and total == _scaled_sum_and_write(Outer(Inner(a, 2.5), np.zeros(4), True), k)[0]
    by_hand = [0.0] * 4
    for k in range(4):
        for i in range(5):  # the loop's own order of additions
            by_hand[k] += 2.5 * a[i, k]
    np.testing.assert_array_equal(b, by_hand)
    assert words[4] == a.ctypes.data and words[0] == 0  # the data pointer kept, no meminfo


def test_a_stored_typed_list_is_neither_freed_nor_kept():
    """A typed list in a stored record: loading it a thousand times leaves it alive, and the
    store takes no reference (the list's owner frees it as before)."""
    from numba.typed import List

    @njit
    def first_sum(address, ty):
        return load(address, ty)[1][0].sum()

    held = List()
    held.append(np.arange(4.0))
    rec = (np.ones(3), held)
    ty = typeof(rec)
    words = np.zeros(-(-stored_size(ty) // 8), dtype=np.int64)
    _stored(rec, words)
    refs = held._opaque  # the list's meminfo, counted by numba
    for _ in range(1000):
        assert first_sum(words.ctypes.data, ty) == 6.0
    assert held[0].sum() == 6.0 and held._opaque is refs


@njit
def _tuple_sum_and_write(address, k, ty):
    a, scale, b, flag = load(address, ty)
    total = 0.0
    for i in range(a.shape[0]):
        total += scale * a[i, k]
    b[k] = total
    return total, flag


def test_kept_words_keep_the_stored_record_alive_and_then_let_it_go():
    """stored(): the record at the words' address plus the lead, readable after every other
    reference to it is gone; once the words go, so does the record (no cycle, no leak). (A
    plain tuple: stored() compiles its store with numba's disk cache, whose index must not
    name a type of a test module, which another process could not import.)"""
    import gc
    import weakref

    rng = np.random.default_rng(8)
    a = rng.normal(size=(5, 4))
    expected = [2.5 * a[:, k].sum() for k in range(4)]
    rec = (a, 2.5, np.zeros(4), True)
    ty = typeof(rec)
    alive = weakref.ref(a)
    words = stored(rec, lead=1)
    assert words.shape == (1 + 9 + 1 + 7 + 1,) and words[0] == 0
    del rec, a
    gc.collect()
    assert alive() is not None
    for k in range(4):
        total, flag = _tuple_sum_and_write(words.ctypes.data + 8, k, ty)
        assert flag is True and abs(total - expected[k]) < 1e-12

    @njit
    def address(w):
        return data_address(w)

    assert address(words) == words.ctypes.data
    del words
    gc.collect()
    assert alive() is None


@njit
def _weighted_at(at, scale, data_at, n, record):
    """sum_i scale * a[i, 0] * data[i] (data: n floats at data_at) + b[0] of the stored (a, b)."""
    a, b = load(at, record)
    data = carray(float64_pointer(data_at), (n,))
    total = b[0]
    for i in range(n):
        total += scale * a[i, 0] * data[i]
    b[1] = total  # a write through the stored record reaches the caller's array
    return np.int64(total * 1000.0)


def test_a_function_called_by_its_address_gives_its_direct_result():
    """c_function + call_stored: numba's C wrapper of a compiled function, called from compiled
    code with an address, a float, an address and an integer, returns what the function
    called directly returns, and writes where it writes."""
    a = np.arange(1.0, 6.0).reshape(5, 1)
    b = np.array([0.25, 0.0])
    rec = (a, b)
    words = stored(rec, lead=1)
    ty = typeof(rec)
    words[0] = c_function(_weighted_at, types.int64(types.intp, types.float64, types.intp, types.intp,
                                                    types.TypeRef(ty)))
    data = np.array([1.0, -2.0, 0.5, 3.0, 0.125])

    @njit
    def call(w, scale, d):
        return call_stored(w[0], (data_address(w) + 8, scale, data_address(d), d.shape[0]))

    by_hand = 0.25 + 1.5 * (1.0 - 4.0 + 1.5 + 12.0 + 0.625)  # 16.9375
    assert call(words, 1.5, data) == 16937
    assert b[1] == by_hand
    b[1] = 0.0
    assert _weighted_at(words.ctypes.data + 8, 1.5, data.ctypes.data, 5, ty) == 16937 and b[1] == by_hand
