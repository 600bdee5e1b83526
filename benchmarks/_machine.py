"""The line every benchmark prints first: which machine, how busy, which versions, when."""

from __future__ import annotations

import datetime
import os
import platform

import numpy as np


def machine() -> str:
    """CPU model, cores, memory, load average, Python, numpy, marinecdpr and today's date."""
    import marinecdpr
    from marinecdpr.budget import machine_memory_bytes

    cpu = "unknown CPU"
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next((ln.split(":", 1)[1].strip() for ln in f if ln.startswith("model name")), cpu)
    except OSError:
        pass
    load = f", load average {os.getloadavg()[0]:.1f}" if hasattr(os, "getloadavg") else ""
    return (f"{cpu}, {os.cpu_count()} cores, {machine_memory_bytes() / 2**30:.0f} GiB{load}, "
            f"Python {platform.python_version()}, numpy {np.__version__}, marinecdpr {marinecdpr.__version__}, "
            f"{datetime.date.today().isoformat()}")
