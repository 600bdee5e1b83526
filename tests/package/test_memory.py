"""marinecdpr.keep_freed_memory: glibc keeps freed memory, NumPy stops advising huge pages."""

import numpy as np

import marinecdpr


def test_keep_freed_memory_turns_numpys_huge_page_advice_off():
    switch = np._core.multiarray._set_madvise_hugepage
    before = switch(True)
    try:
        assert marinecdpr.keep_freed_memory() is True  # glibc on the CI machine
        assert switch(True) is False  # it was off: the switch returns the previous setting
    finally:
        switch(before)
