"""``[wind]``: a mean wind with its profile over height, a gust series, and the drag it puts on
the platform and the cables (issue 40, item 1).

The wind is given in the inertial frame O: ``speed_m_s`` is the mean speed U_r at the
reference height ``reference_height_m`` (U10 at 10 m above the mean sea surface; taken as the
one-hour mean, Frøya's U0), ``direction_deg`` the direction it comes FROM, measured in O's
horizontal plane counter-clockwise (about O's z, up) from O's +x: 0 is a wind from +x that
blows towards -x, 90 one from +y. Over height z above the sea (``z_O - sea_level_m``) the mean
speed follows DNV-RP-C205's power law (2010, §2.3.2.12; its Table 2-1 gives alpha = 0.12 for the
open sea with waves)::

    U(z) = U_r (max(z, Z_MIN_M) / z_r) ** alpha

(below :data:`Z_MIN_M` = 1 m, the law's speed at 1 m). The gust u(t), along the mean wind's
direction, is a series of ``gust`` = ``"froya"``'s spectrum (DNV-RP-C205 §2.3.4, the Frøya
model) at ``gust_height_m``, synthesised from ``seed`` (:mod:`marinecdpr.motion.wind`); it is
taken as one gust over the whole robot (fully coherent over its few metres). The air's density
is 1.226 kg/m^3 (DNV-RP-C205 §5.1; :data:`AIR_DENSITY_KG_M3`).

The platform's drag is DNV-RP-C205's 1/2 rho C A U^2 on each of its axes (P): ``platform_shape_
coefficient`` C and ``platform_area_m2`` the projected areas normal to P's x, y and z
(:mod:`marinecdpr.model.wind`). The cables' drag is per metre on their normal component, with
``cable_drag_coefficient`` and ``cable_diameter_m`` (0: no drag on the cables).

The planner's required wrench holds the mean wind (``plan_gust = "mean"``), the series
(``"series"``), or the mean times a gust factor G (a number: the profile's U(z) times G, e.g.
1.4 for a 3 s gust over an hour's mean); the plants always meet the series. No ``[wind]``: no
wind, and every number as without this section.
"""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import BeforeValidator, Field, model_validator

from marinecdpr.scenario.fields import _KeyedError, _Model, _num, _ranged, _ranged_vec3

__all__ = ["Wind", "AIR_DENSITY_KG_M3", "Z_MIN_M", "GUST_FACTOR_RANGE"]

AIR_DENSITY_KG_M3 = 1.226
"""The air's density, kg/m^3 (DNV-RP-C205 §5.1: dry air at 15 deg C at sea level)."""
Z_MIN_M = 1.0
"""Below this height above the sea the profile's speed is its speed at 1 m (the power law
tends to zero at the surface, where waves shelter and the law is not meant)."""
GUST_FACTOR_RANGE = (1.0, 3.0)
"""A gust factor G (a gust's speed over the mean's) the planner may take."""


def _plan_gust(value: Any) -> Any:
    """``"mean"``, ``"series"`` or a gust factor in :data:`GUST_FACTOR_RANGE`; one line otherwise."""
    if value in ("mean", "series"):
        return value
    lo, hi = GUST_FACTOR_RANGE
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        if not lo <= float(value) <= hi:
            raise ValueError(f"a gust factor must be between {_num(lo)} and {_num(hi)} (a gust's speed over the "
                             f"mean's), got {_num(float(value))}")
        return float(value)
    raise ValueError(f"must be \"mean\", \"series\" or a gust factor (a number from {_num(lo)} to {_num(hi)}), "
                     f"got {value!r}")


class Wind(_Model):
    """A mean wind with a power-law profile, a Frøya gust series, and the drag it puts on the
    platform and the cables (see the module's text for the conventions)."""

    speed_m_s: _ranged(0.0, 70.0, "m/s", "beyond a hurricane's mean wind", above=True)
    """U_r: the mean speed at ``reference_height_m`` (the one-hour mean, Frøya's U0), m/s."""
    reference_height_m: _ranged(0.0, 1000.0, "m", "a height above the sea", above=True) = 10.0
    """z_r: where ``speed_m_s`` is measured, above the mean sea surface, m."""
    direction_deg: _ranged(-360.0, 360.0, "deg", "one turn either way") = 0.0
    """The direction the wind comes FROM, in O's horizontal plane, counter-clockwise from O's
    +x, deg (0: from +x, blowing towards -x)."""
    profile_exponent: _ranged(0.0, 0.5, "", "a power law's exponent; DNV-RP-C205 gives 0.12 at sea") = 0.12
    """alpha in U(z) = U_r (z / z_r) ** alpha (0: the same speed at every height)."""
    sea_level_m: _ranged(-1e4, 1e4, "m", "positions on a ship, in metres") = 0.0
    """The mean sea surface's height in O, m: a point's height above the sea is z_O - sea_level_m."""
    gust: Literal["froya", "none"] = "froya"
    """The gust's spectrum: Frøya's (DNV-RP-C205 §2.3.4), or none (the mean wind alone)."""
    gust_height_m: _ranged(0.0, 1000.0, "m", "a height above the sea", above=True) = 10.0
    """The height above the sea whose spectrum the gust series follows, m."""
    seed: Annotated[int, Field(ge=0, strict=True)] = 0
    """The gust's random phases' seed."""
    record_s: _ranged(60.0, 10800.0, "s", "from a minute to three hours") = 3600.0
    """The gust series' period (its frequency step 1 / record_s); it repeats after it, s."""
    frequency_max_hz: _ranged(0.0, 50.0, "Hz", "the gust's highest frequency", above=True) = 2.0
    """The gust's highest harmonic, Hz (the spectrum carries little above 1 Hz)."""
    plan_gust: Annotated[Any, BeforeValidator(_plan_gust)] = "mean"
    """What the planner's required wrench holds: "mean", "series", or a gust factor G (the mean
    profile's speed times G)."""
    platform_shape_coefficient: _ranged(0.0, 3.0, "", "a body's shape coefficient (a flat plate's is 2)",
                                        above=True)
    """C in 1/2 rho C A U^2 (DNV-RP-C205 §5.4)."""
    platform_area_m2: _ranged_vec3(1e3, "m^2", "a platform's projected area", ("x", "y", "z"))
    """The platform's areas projected normal to P's x, y and z, m^2 (each >= 0)."""
    cable_drag_coefficient: _ranged(0.0, 3.0, "", "a cylinder's drag coefficient (1.2 below the "
                                                  "drag crisis)") = 1.2
    """C_D of a cable, a circular cylinder in cross flow."""
    cable_diameter_m: _ranged(0.0, 0.5, "m", "a cable's diameter") = 0.0
    """The cables' diameter, m (0: no drag on the cables)."""

    @model_validator(mode="after")
    def _check_area(self) -> "Wind":
        names = ("x", "y", "z")
        for name, a in zip(names, self.platform_area_m2):
            if a < 0.0:
                raise _KeyedError("platform_area_m2", f"each entry must be >= 0 (a projected area), got "
                                                      f"{name} = {_num(a)}")
        if all(a == 0.0 for a in self.platform_area_m2):
            raise _KeyedError("platform_area_m2", "at least one area must be above 0 (the wind meets the platform)")
        return self
