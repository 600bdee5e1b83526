"""Checks of single numbers the motion layer's functions take, each returning the cleaned value
(pytransform3d's ``check_*`` style) or raising the caller's error class with one line naming
the argument."""

from __future__ import annotations

import numpy as np

from marinecdpr.errors import ScenarioError

__all__ = ["check_finite", "check_positive"]


def check_finite(value, name: str, *, error: type[ScenarioError] = ScenarioError) -> float:
    """``value`` as a finite float, else ``error`` keyed ``name``."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise error(f"must be a number, got {value!r}", key=name) from None
    if not np.isfinite(v):
        raise error(f"must be finite, got {v!r}", key=name)
    return v


def check_positive(value, name: str, *, error: type[ScenarioError] = ScenarioError) -> float:
    """``value`` as a finite float above 0, else ``error`` keyed ``name``."""
    v = check_finite(value, name, error=error)
    if v <= 0.0:
        raise error(f"must be > 0, got {v!r}", key=name)
    return v
