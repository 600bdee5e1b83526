"""marinecdpr: cable-driven parallel robots on a moving ship.

The public entry points are :func:`load_scenario`, :func:`plan`, :func:`iter_plan`,
:func:`simulate` and :func:`virtual_prototype`. The layers, each a subpackage that imports
only the ones before it: geometry -> scenario -> motion -> model -> planning -> prototype
-> studies -> report -> cli (README, "Layout"). The numerical functions
(:func:`~marinecdpr.geometry.kinematics.cable_kinematics`,
:func:`~marinecdpr.model.dynamics.wrench_terms`,
:func:`~marinecdpr.model.tension.distribute_tensions`, ...) are pure functions on arrays
shaped ``(n_steps, ...)``.
"""

from marinecdpr.starting import catch_while_starting as _catch_while_starting

_catch_while_starting()  # first: a Ctrl-C while the command starts is one line (marinecdpr.starting)

from marinecdpr.compiled_cache import configure as _configure_cache  # noqa: E402

_configure_cache()  # before any compiled module loads: a cache folder per version of the sources

from marinecdpr.errors import InfeasibleError, MarineCDPRError, ScenarioError  # noqa: E402
from marinecdpr.memory import keep_freed_memory  # noqa: E402

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

_LAZY = {"load_scenario": "scenario.loading", "builtin_scenarios": "scenario.loading",
         "Scenario": "scenario.schema", "plan": "planning.planner", "iter_plan": "planning.planner",
         "Plan": "planning.planner", "simulate": "prototype.simulation", "SimResult": "prototype.simulation",
         "virtual_prototype": "studies.prototype_runs"}


def __getattr__(name: str):
    """The layers (pydantic, numba, MuJoCo) load on first use, not with the package: the
    ``marinecdpr`` command catches Ctrl-C before it imports them (:mod:`marinecdpr.cli.app`)."""
    if name in _LAZY:
        import importlib

        return getattr(importlib.import_module(f".{_LAZY[name]}", __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")

__version__ = "0.1.0"
