"""marinecdpr: cable-driven parallel robots on a moving ship.

The public entry points are :func:`load_scenario` and :func:`plan`; the numerical
layers (:mod:`~marinecdpr.kinematics`, :mod:`~marinecdpr.dynamics`,
:mod:`~marinecdpr.tension`) are pure functions on arrays shaped ``(n_steps, ...)``.
"""

from .errors import InfeasibleError, MarineCDPRError, ScenarioError
from .memory import keep_freed_memory
from .planning import Plan, iter_plan, plan
from .scenario import Scenario, builtin_scenarios, load_scenario

__all__ = [
    "load_scenario",
    "builtin_scenarios",
    "plan",
    "iter_plan",
    "Plan",
    "Scenario",
    "MarineCDPRError",
    "ScenarioError",
    "InfeasibleError",
    "keep_freed_memory",
    "simulate",
    "virtual_prototype",
    "SimResult",
]

_LAZY = {"simulate": "simulation", "SimResult": "simulation", "virtual_prototype": "analysis"}


def __getattr__(name: str):
    """The simulation layer (numba, MuJoCo) loads on first use, not with the package."""
    if name in _LAZY:
        import importlib

        return getattr(importlib.import_module(f".{_LAZY[name]}", __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")

__version__ = "0.1.0"
