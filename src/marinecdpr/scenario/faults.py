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

``winch_brake``: the cable's winch is told to brake at ``at_s``; ``brake_delay_s`` (default 0)
later its brake holds the drum: from then the unstretched length the drum has paid out
stays as it was (elastic or catenary cables on a length-controlled or motor winch).

Its primary and secondary brakes: with ``primary_fails = true`` the brake named by
``brake_delay_s`` does not hold, and the drum is held by a secondary brake, if the scenario
gives one, ``secondary_delay_s`` after ``at_s`` (its delay includes finding the primary
failed); without a secondary, nothing holds the drum. A secondary with a sound primary never
acts (the primary holds first). The brakes the controller commands are not those of this
entry (they hold after ``[simulation.control.safety] brake_delay_s``; a ``brake_failure`` fails
those).

``brake_failure``: from ``at_s`` the primary brake of the cable's winch fails: a brake the
controller commands on it (its reaction's, after ``[simulation.control.safety]
brake_delay_s``) does not hold; a secondary brake, if given, holds the drum
``secondary_delay_s`` after the command (its delay includes finding the primary failed; not
before brake_delay_s); without one, nothing holds it. Elastic or catenary cables on a
length-controlled or motor winch; it may strike a winch that has another fault (the brake
that fault's reaction commands is then the one that fails).

``motor_power_loss``: from ``at_s`` the cable's motor gives no torque (motor winches): the
drum runs under the cable's pull against the drive's inertia and friction
(:func:`~marinecdpr.model.winch.winch_motor_step` with no torque). With ``brake_delay_s``
the fail-safe brake holds the drum that long after the loss; without it, nothing does.

``winch_stall``: from ``at_s`` the cable's motor is stalled at its torque limit (motor
winches): its drive gives its limit ``torque_max_Nm`` (less where its power limit binds),
winding in, whatever its tension loop commands, as a drive whose current loop has failed
saturated. The drum reels in until the cable's pull over the drum balances that torque
(T = G eta tau_max / r_d at rest) and pays out where the pull exceeds it; the drum under
J_eff omega' = tau_max - tau_T(T) - friction (:func:`~marinecdpr.model.winch.winch_motor_step`
with tau_max commanded). No brake acts unless the controller commands it.

``load_cell`` and ``encoder``: the cable's load cell (the controller's measured tension) or its
winch's encoder (the measured length and its rate) goes wrong from ``at_s``, for
``duration_s`` if given (else to the end), in one ``mode``: ``freeze`` (it repeats the reading
it gave at at_s), ``drift`` (it adds ``drift_per_s`` times the time since at_s: N/s, or m/s on
the length), ``dropout`` (it gives NaN: no reading) or ``non_finite`` (it gives +inf).

``mru``: the motion reference unit goes wrong from ``at_s`` (for ``duration_s`` if given), in
one ``mode``: ``freeze`` (its sample eta, eta', eta'' and its time stamp as they were at
at_s: the sample ages), ``drift`` (it adds ``drift_per_s`` times the time since at_s to each
of eta's six displacements: m/s on surge, sway, heave, rad/s on roll, pitch, yaw; its rates
and time stamp sound), ``dropout`` (NaN: the sample and its stamp) or ``non_finite`` (the
sample +inf, its stamp sound). No ``cable``.

``brush_contact_loss``: the brush loses its contact with the hull from ``at_s`` (for
``duration_s`` if given, else to the end): its normal contact force, and with it its drag and
its spin's moment, is zero (a water jet's reaction, ``cleaning.jet_N``, still acts: it is not
a contact). The scenario needs ``[cleaning]``. No ``cable``.

``controller_deadline``: the controller misses its deadline at ``at_s`` for ``steps``
exchanges: its commands of the exchange before are held (closed loop; it computes nothing
in those exchanges, its own state held too). No ``cable``.

A fault acts from the first exchange at or after its time (t_k >= at_s, and for a brake
t_k >= at_s + brake_delay_s).

With no ``[[faults]]`` the prototype has exactly the parts it had before (no fault part is
built) and every number is as without this section.
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field, model_validator

from marinecdpr.scenario.fields import CABLES_MAX, TIME_MAX_S, _KeyedError, _Model, _ranged

__all__ = ["Fault", "FAULT_KINDS", "CABLELESS_FAULTS", "WINCH_FAULTS", "BRAKE_FAULTS", "SENSOR_FAULTS", "SENSOR_MODES", "MAX_FAULTS"]

FAULT_KINDS = ("cable_snap", "winch_brake", "motor_power_loss", "winch_stall", "brake_failure", "load_cell", "encoder",
               "mru", "brush_contact_loss", "controller_deadline")
"""The faults a scenario may list (``kind``)."""
CABLELESS_FAULTS = ("mru", "brush_contact_loss", "controller_deadline")
"""The faults that strike no cable (the ship's motion reference unit, the brush, the controller)."""
WINCH_FAULTS = ("winch_brake", "motor_power_loss", "winch_stall", "brake_failure")
"""The faults of a cable's winch."""
BRAKE_FAULTS = ("winch_brake", "motor_power_loss")
"""The winch faults that take a ``brake_delay_s``."""
SENSOR_FAULTS = ("load_cell", "encoder", "mru")
"""The faults of a cable's sensors."""
SENSOR_MODES = ("freeze", "drift", "dropout", "non_finite")
"""How a sensor goes wrong."""
MAX_FAULTS = 100
"""Most faults one scenario may list."""


class Fault(_Model):
    """One fault: its kind, which cable it strikes (from 1), and from when."""

    kind: Literal[FAULT_KINDS]
    """What fails: "cable_snap" (the cable breaks), "winch_brake" (its winch's brake holds the
    drum), "motor_power_loss" (its winch's motor gives no torque), "winch_stall" (its motor
    stuck at its torque limit), "brake_failure" (its primary brake fails when the controller
    commands it), a sensor ("load_cell", "encoder", "mru"), "brush_contact_loss" or
    "controller_deadline"."""
    cable: Annotated[int, Field(ge=1, le=CABLES_MAX, strict=True)] | None = None
    """Which cable (or its winch, its sensors), counted from 1 in the order of
    ``[[robot.cables]]`` (every kind but mru, brush_contact_loss and controller_deadline)."""
    steps: Annotated[int, Field(ge=1, le=10**7, strict=True)] | None = None
    """controller_deadline: for how many exchanges the controller's commands are held."""
    at_s: _ranged(0.0, TIME_MAX_S, "s", "a time within the run, from its start")
    """When the fault strikes, s from the run's start (at most ``time.duration_s``)."""
    brake_delay_s: _ranged(0.0, 60.0, "s", "a brake that takes a minute holds nothing") | None = None
    """Winch faults: how long after ``at_s`` the brake holds the drum, s (``winch_brake``:
    default 0; ``motor_power_loss``: none, the drum runs free)."""

    secondary_delay_s: _ranged(0.0, 60.0, "s", "a brake that takes a minute holds nothing") | None = None
    """winch_brake: how long after ``at_s`` a secondary brake holds the drum if the primary
    fails; brake_failure: how long after the controller commands the brake; s (none: no
    secondary brake)."""
    primary_fails: Annotated[bool, Field(strict=True)] | None = None
    """winch_brake: true, the primary brake fails to hold (the secondary, if any, holds); none
    or false, it holds."""

    mode: Literal[SENSOR_MODES] | None = None
    """Sensor faults: "freeze", "drift", "dropout" (NaN) or "non_finite" (+inf)."""
    drift_per_s: _ranged(-1e6, 1e6, "per s", "a sensor's drift, N/s or m/s") | None = None
    """A drifting sensor's rate: N/s on a load cell, m/s on an encoder's length, m/s and rad/s
    on the MRU's displacements."""
    duration_s: _ranged(0.0, TIME_MAX_S, "s", "a time within the run", above=True) | None = None
    """A sensor fault's, or a brush_contact_loss's, duration, s (none: to the run's end)."""

    @model_validator(mode="after")
    def _check_delay(self) -> "Fault":
        late = self.kind == "controller_deadline"
        cableless = self.kind in CABLELESS_FAULTS
        if not cableless and self.cable is None:
            raise _KeyedError("cable", "missing: which cable (counted from 1) the fault strikes")
        if late and self.cable is not None:
            raise _KeyedError("cable", "a controller_deadline strikes the controller, not a cable: leave it out")
        if self.kind == "mru" and self.cable is not None:
            raise _KeyedError("cable", "an mru fault strikes the motion reference unit, not a cable: leave it out")
        if self.kind == "brush_contact_loss" and self.cable is not None:
            raise _KeyedError("cable", "a brush_contact_loss strikes the brush, not a cable: leave it out")
        if late and self.steps is None:
            raise _KeyedError("steps", "missing: for how many exchanges the controller's commands are held")
        if not late and self.steps is not None:
            raise _KeyedError("steps", f"is for a controller_deadline, not a {self.kind}")
        if self.kind not in BRAKE_FAULTS and self.brake_delay_s is not None:
            raise _KeyedError("brake_delay_s", f"is for a winch's faults (winch_brake, motor_power_loss), not a "
                                               f"{self.kind}")
        if self.kind not in ("winch_brake", "brake_failure") and self.secondary_delay_s is not None:
            raise _KeyedError("secondary_delay_s", f"is for a secondary brake (winch_brake, brake_failure), not a "
                                                   f"{self.kind}")
        if self.kind != "winch_brake" and self.primary_fails is not None:
            raise _KeyedError("primary_fails", f"is for a winch_brake's primary brake, not a {self.kind}")
        if (self.secondary_delay_s is not None and self.brake_delay_s is not None
                and self.secondary_delay_s < self.brake_delay_s):
            raise _KeyedError("secondary_delay_s", f"{self.secondary_delay_s:g} s is before the primary brake's "
                                                   f"brake_delay_s ({self.brake_delay_s:g} s): the secondary "
                                                   "holds when the primary has failed")
        sensor = self.kind in SENSOR_FAULTS
        for key in ("mode", "duration_s", "drift_per_s"):
            if key == "duration_s" and self.kind == "brush_contact_loss":
                continue
            if not sensor and getattr(self, key) is not None:
                raise _KeyedError(key, f"is for a sensor's faults (load_cell, encoder, mru), not a {self.kind}")
        if sensor and self.mode is None:
            raise _KeyedError("mode", "missing: a sensor fault freezes, drifts, drops out or gives non-finite "
                                      "values (\"freeze\", \"drift\", \"dropout\", \"non_finite\")")
        if self.mode == "drift" and self.drift_per_s is None:
            raise _KeyedError("drift_per_s", "missing: a drifting sensor's rate (N/s or m/s; m/s and rad/s on the mru)")
        if self.mode not in (None, "drift") and self.drift_per_s is not None:
            raise _KeyedError("drift_per_s", f"is for a drifting sensor (mode = \"drift\"), not \"{self.mode}\"")
        return self

    @property
    def on_winch(self) -> bool:
        """A winch's fault (its brake or its motor)."""
        return self.kind in WINCH_FAULTS
