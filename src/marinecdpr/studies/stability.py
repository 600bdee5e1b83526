"""Is the open loop stable? The linearised open-loop dynamics along a plan
(:func:`marinecdpr.model.stiffness.open_loop_growth_rate`) for the scenario's winches, on
at most a few thousand of the plan's steps (the eigenvalues change smoothly along it)."""

from __future__ import annotations

import math
from types import SimpleNamespace

from marinecdpr.model.stiffness import GrowthRate, open_loop_growth_rate
from marinecdpr.planning.planner import Plan
from marinecdpr.scenario.schema import Scenario

__all__ = ["plan_stability", "stability_summary", "STABILITY_POINTS"]

STABILITY_POINTS = 2000
"""At most this many of the plan's steps are linearised about (evenly spread)."""


def plan_stability(plan: Plan, scenario: Scenario, *, points: int = STABILITY_POINTS) -> GrowthRate:
    """The open loop's fastest growth along the plan, with the scenario's winches: held
    tensions (ideal cables, or tension-controlled winches) or held unstretched lengths
    (elastic cables on length-controlled winches, with their EA and damping).

    Parameters
    ----------
    plan : Plan
    scenario : Scenario
    points : int
        The most steps linearised about, evenly spread over the plan (every step if fewer).
    """
    stride = max(1, math.ceil(plan.n_steps / points))
    view = SimpleNamespace(pose=plan.pose[::stride], twist=plan.twist[::stride], twist_dot=plan.twist_dot[::stride],
                           tensions=plan.tensions[::stride], t=plan.t[::stride], controlled=plan.controlled,
                           base_model=plan.base_model)
    cab = scenario.simulation.cables
    if cab.model != "ideal" and cab.winch == "length":
        return open_loop_growth_rate(view, scenario, "length", EA=cab.stiffness_EA_N, damping=cab.damping_N_s_m)
    return open_loop_growth_rate(view, scenario, "tension")


def stability_summary(g: GrowthRate) -> dict:
    """``summary.json``'s ``stability``: the growth rate, where, the mode and what it means."""
    return {
        "open_loop_growth_rate_1_s": g.rate,
        "winches": g.winches,
        "verdict": g.stability,
        "t_s": g.t,
        "eigenvalue_1_s": [g.eigenvalue.real, g.eigenvalue.imag],
        "mode": list(g.dominant),
        "e_folding_time_s": g.e_folding_time_s if g.stability == "unstable" else None,
        "meaning": "the largest real part of the linearised open-loop dynamics' eigenvalues along the plan "
                   "(held tensions, or held lengths for elastic cables on length-controlled winches): > 0, an "
                   "error grows like exp(rate t) without feedback",
    }
