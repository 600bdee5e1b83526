"""``[[faults]]``: what fails on the robot during a run, and when (issue 40, item 2).

Each entry is one fault of the virtual prototype, a part (or a part's mode) that acts from
``at_s`` on; the controller is not told (detecting it is the controller's job)::

    [[faults]]
    kind = "cable_snap"   # the cable breaks: from at_s its force is zero
    cable = 2             # which cable, counted from 1 as [[robot.cables]] lists them
    at_s = 12.5           # from when, s from the run's start

``cable_snap``: from the first exchange at or after ``at_s`` (t_k >= at_s) the cable pulls no
more, on every cable model (ideal, elastic, catenary; within the plant's step too) and on
both plants (on MuJoCo its tendon's motor and spring stop acting). What the cable's winch
does with no load is its own model's (a motor winch's drum runs free of the cable's pull).

With no ``[[faults]]`` the prototype has exactly the parts it had before (no fault part is
built) and every number is as without this section.
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field

from marinecdpr.scenario.fields import CABLES_MAX, TIME_MAX_S, _Model, _ranged

__all__ = ["Fault", "FAULT_KINDS", "MAX_FAULTS"]

FAULT_KINDS = ("cable_snap",)
"""The faults a scenario may list (``kind``)."""
MAX_FAULTS = 100
"""Most faults one scenario may list."""


class Fault(_Model):
    """One fault: its kind, which cable it strikes (from 1), and from when."""

    kind: Literal[FAULT_KINDS]
    """What fails: "cable_snap" (the cable breaks; its force is zero from ``at_s``)."""
    cable: Annotated[int, Field(ge=1, le=CABLES_MAX, strict=True)]
    """Which cable, counted from 1 in the order of ``[[robot.cables]]``."""
    at_s: _ranged(0.0, TIME_MAX_S, "s", "a time within the run, from its start")
    """When the fault strikes, s from the run's start (at most ``time.duration_s``)."""
