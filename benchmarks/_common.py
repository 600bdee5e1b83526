"""What the benchmarks share: the line each prints first (which machine, how busy, which
versions, when), the general-solver baseline a user would pick for the tension problem, and
the best-of-n timer."""

from __future__ import annotations

import datetime
import os
import platform
import time

import numpy as np


def machine() -> str:
    """CPU model, cores, memory, load average, Python, numpy, marinecdpr and today's date."""
    import marinecdpr
    from marinecdpr.planning.budget import machine_memory_bytes

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


def quadprog_per_step(J: np.ndarray, w: np.ndarray, target: np.ndarray, lo: np.ndarray, hi: np.ndarray
                      ) -> np.ndarray:
    """min |T - target|^2 s.t. J~^T T = w, lo <= T <= hi, step by step with quadprog (the
    ``test`` extra): the general QP solver a user would call from Python.

    J : (n_steps, n_cables, k); w : (n_steps, k); target, lo, hi : (n_cables,). Returns
    (n_steps, n_cables) tensions, N.
    """
    import quadprog

    n, m, k = J.shape
    G = np.eye(m)
    b_bounds = np.concatenate([lo, -hi])
    eye2 = np.hstack([np.eye(m), -np.eye(m)])
    T = np.empty((n, m))
    for i in range(n):
        C = np.hstack([J[i], eye2])
        T[i] = quadprog.solve_qp(G, target, C, np.concatenate([w[i], b_bounds]), k)[0]
    return T


def best_of(repeats: int, fn):
    """The result of fn() and its smallest wall time over ``repeats`` calls, s."""
    best = float("inf")
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return out, best
