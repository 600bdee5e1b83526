"""Component-wise 3-vector algebra on time series (the hot paths' arithmetic).

A vector time series is a list of three 1-D arrays (x, y, z components, each of
shape (n_steps,)), or scalars that broadcast. numpy runs elementwise operations on
long 1-D arrays an order of magnitude faster than on ``(n_steps, 3)`` arrays,
whose inner loops are three long; these helpers keep the hot paths in that form.
Results are packed time-last (:func:`pack`) and returned as ``(n_steps, ...)``
views, so callers see the documented shapes.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

Vec = Sequence  # three components: arrays of shape (n,) or scalars


def comps(a: np.ndarray) -> list[np.ndarray]:
    """Components of an (n, 3) array as three 1-D views."""
    return [a[:, 0], a[:, 1], a[:, 2]]


def cross(a: Vec, b: Vec) -> list:
    return [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]


def dot(a: Vec, b: Vec):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def matvec(R: np.ndarray, v: Vec) -> list:
    """R @ v with R of shape (n, 3, 3) (or (3, 3))."""
    return [R[..., i, 0] * v[0] + R[..., i, 1] * v[1] + R[..., i, 2] * v[2] for i in range(3)]


def pack(parts: Sequence, n: int) -> np.ndarray:
    """Stack components time-last and return the time-first view.

    Parameters
    ----------
    parts : sequence of arrays of shape (n,) or scalars, or nested sequences
        ``parts[i]`` (or ``parts[i][j]``) becomes ``out[:, i]`` (``out[:, i, j]``).
    n : int
        Number of steps.

    Returns
    -------
    out : ndarray, shape (n, len(parts)) or (n, len(parts), len(parts[0]))
        A view of a time-last buffer.
    """
    nested = isinstance(parts[0], (list, tuple))
    shape = (len(parts), len(parts[0])) if nested else (len(parts),)
    buf = np.empty(shape + (n,))
    if nested:
        for i, row in enumerate(parts):
            for j, p in enumerate(row):
                buf[i, j] = p
        return buf.transpose(2, 0, 1)
    for i, p in enumerate(parts):
        buf[i] = p
    return buf.T
