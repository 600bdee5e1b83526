"""Allocator tuning for processes that plan again and again (a controller, a sweep).

A plan allocates tens of megabytes of temporaries. By default glibc returns freed
memory to the operating system at once, so the next call page-faults it back in:
on a virtual machine that can double a call's time. :func:`keep_freed_memory`
asks glibc to keep freed memory for reuse instead. It changes the whole process's
allocator, so the library never calls it by itself: applications opt in (the
``marinecdpr`` command does).
"""

from __future__ import annotations

import ctypes
import ctypes.util

__all__ = ["keep_freed_memory"]

_M_TRIM_THRESHOLD = -1
_M_TOP_PAD = -2
_M_MMAP_THRESHOLD = -3


def keep_freed_memory(*, top_pad_bytes: int = 64 << 20, trim_threshold_bytes: int = 512 << 20) -> bool:
    """Ask glibc's malloc to keep freed memory in the process for reuse.

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
