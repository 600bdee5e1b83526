"""Allocator tuning for processes that plan again and again (a controller, a sweep).

A plan allocates tens of megabytes of temporaries. By default glibc returns freed
memory to the operating system at once, so the next call page-faults it back in:
on a virtual machine that can double a call's time. :func:`keep_freed_memory`
asks glibc to keep freed memory for reuse instead.

It also stops NumPy from asking the kernel for transparent huge pages for large arrays
(``madvise(MADV_HUGEPAGE)``, NumPy's default on Linux): where the kernel compacts memory
on such a page fault (``/sys/kernel/mm/transparent_hugepage/defrag`` = ``madvise``, as on
the CI machine), the first touch of a long run's arrays stalls. A 10-minute cleaning job
(588 000 steps; about 1 GB of new arrays) took 15-18 s with the huge pages and 10.6-11.7 s
without (the 2-core CI machine, 2026-12-01); a second run in the same process, on reused
memory, 10.5-12 s either way.

Both change the whole process, so the library never calls this by itself: applications
opt in (the ``marinecdpr`` command does).
"""

from __future__ import annotations

__all__ = ["keep_freed_memory"]

_M_TRIM_THRESHOLD = -1
_M_TOP_PAD = -2
_M_MMAP_THRESHOLD = -3


def keep_freed_memory(*, top_pad_bytes: int = 64 << 20, trim_threshold_bytes: int = 512 << 20) -> bool:
    """Ask glibc's malloc to keep freed memory in the process for reuse, and NumPy not to
    advise huge pages (see the module's note).

    Parameters
    ----------
    top_pad_bytes : int, keyword-only
        Extra memory kept at the top of the heap when it grows, bytes.
    trim_threshold_bytes : int, keyword-only
        Free memory at the top of the heap kept before returning it, bytes.

    Returns
    -------
    bool
        True if the settings took effect; False where the C library is not glibc.
    """
    import ctypes  # here, not with the package: ``import marinecdpr`` stays light
    import ctypes.util

    _no_numpy_huge_pages()
    name = ctypes.util.find_library("c")
    try:
        libc = ctypes.CDLL(name or "libc.so.6")
        mallopt = libc.mallopt
    except (OSError, AttributeError):
        return False
    # the largest mmap threshold glibc accepts on 64-bit systems is 32 MiB
    return bool(
        mallopt(_M_MMAP_THRESHOLD, 32 << 20)
        and mallopt(_M_TRIM_THRESHOLD, int(trim_threshold_bytes))
        and mallopt(_M_TOP_PAD, int(top_pad_bytes))
    )


def _no_numpy_huge_pages() -> None:
    """NumPy's run-time switch of its huge-page advice (the documented alternative is the
    environment variable NUMPY_MADVISE_HUGEPAGE=0, read only at NumPy's import)."""
    import numpy as np

    for module in ("_core", "core"):
        switch = getattr(getattr(getattr(np, module, None), "multiarray", None), "_set_madvise_hugepage", None)
        if switch is not None:
            switch(False)
            return
