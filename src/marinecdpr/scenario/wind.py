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

**A wind that follows the sea state** (``with_sea``; the sea-state studies: operability,
``clean --seas``, the design study's screen and its time-domain verification). The scenario's
``[base_motion]`` must then be a ``sea_state``; each sea state (the scenario's own, and each
cell of a scatter diagram in a study) sets the wind's speed and direction:

- ``with_sea = "pierson_moskowitz"``: the fully developed sea's relation between Hs and the
  wind at 19.5 m above the sea, from Pierson and Moskowitz's spectrum (W. J. Pierson Jr. and
  L. Moskowitz, "A proposed spectral form for fully developed wind seas based on the similarity
  theory of S. A. Kitaigorodskii", J. Geophys. Res. 69(24), 5181-5190, 1964):
  S(omega) = a g^2 omega^-5 exp(-b (g / (U_19.5 omega))^4), a = 8.1e-3, b = 0.74, whose
  m0 = a U_19.5^4 / (4 b g^2) gives Hs = 4 sqrt(m0) = 2 sqrt(a / b) U_19.5^2 / g
  = 0.2092 U_19.5^2 / g (the "0.21" usually quoted), so
  U_19.5 = sqrt(g Hs / 0.2092) (:func:`pierson_moskowitz_wind`), g the scenario's
  ``environment.gravity_m_s2``; taken to ``reference_height_m`` by the profile's power law
  (U_r = U_19.5 (z_r / 19.5) ** alpha) and used as the mean speed ``speed_m_s`` (only Hs
  enters: the fully developed sea's own peak period is not imposed, each cell keeps its Tp).
  ``speed_m_s`` is then left out.
- ``with_sea = "scatter"``: each cell's speed U_r at ``reference_height_m`` is the scatter
  diagram's column ``wind_m_s`` (a study refuses a diagram without it); ``speed_m_s`` is the
  wind in the scenario's own sea state (what ``plan`` and ``simulate`` fly). A column
  ``wind_misalignment_deg``, where present, is each cell's ``misalignment_deg``.

The direction: the waves' ``heading_deg`` is where they travel TO, counter-clockwise from the
ship's +x; ``direction_deg`` is where the wind comes FROM in O. O's x is taken along the
ship's mean heading (O is the ship's mean position and heading: the ship's frame S turns from
O only by its motion's roll, pitch and yaw), so both are measured from the same axis, and the
wind comes from ``direction_deg = heading_deg + 180 + misalignment_deg`` (mod 360):
``misalignment_deg = 0`` (the default) is a wind blowing the way the waves travel (a wind
sea); ``direction_deg`` is then left out. In a study each record meets a gust of its own
(``seed`` with the sea state and the realisation:
:func:`marinecdpr.studies.operability.gust_seed`).
"""

from __future__ import annotations

import math
from typing import Annotated, Any, Literal

from pydantic import BeforeValidator, Field, model_serializer, model_validator

from marinecdpr.scenario.fields import _KeyedError, _Model, _num, _ranged, _ranged_vec3

__all__ = ["Wind", "AIR_DENSITY_KG_M3", "Z_MIN_M", "GUST_FACTOR_RANGE", "WITH_SEA", "PM_ALPHA", "PM_BETA",
           "PM_HEIGHT_M", "PM_HS_COEFFICIENT", "SPEED_MAX_M_S", "pierson_moskowitz_wind", "sea_direction_deg",
           "sea_wind"]

AIR_DENSITY_KG_M3 = 1.226
"""The air's density, kg/m^3 (DNV-RP-C205 §5.1: dry air at 15 deg C at sea level)."""
Z_MIN_M = 1.0
"""Below this height above the sea the profile's speed is its speed at 1 m (the power law
tends to zero at the surface, where waves shelter and the law is not meant)."""
GUST_FACTOR_RANGE = (1.0, 3.0)
"""A gust factor G (a gust's speed over the mean's) the planner may take."""
SPEED_MAX_M_S = 70.0
"""The largest mean speed a wind may have, m/s (beyond a hurricane's mean wind)."""
WITH_SEA = ("none", "scatter", "pierson_moskowitz")
"""What a wind follows: nothing (its own ``speed_m_s`` and ``direction_deg``), a scatter
diagram's ``wind_m_s`` column, or the Pierson-Moskowitz fully developed sea."""
PM_ALPHA = 8.1e-3
"""Pierson and Moskowitz's (1964) spectrum's constant a (Phillips' constant)."""
PM_BETA = 0.74
"""Their spectrum's b: S = a g^2 omega^-5 exp(-b (omega_0 / omega)^4), omega_0 = g / U_19.5."""
PM_HEIGHT_M = 19.5
"""The height of their wind speeds above the sea, m (the weather ships' anemometers)."""
PM_HS_COEFFICIENT = 2.0 * math.sqrt(PM_ALPHA / PM_BETA)
"""Hs g / U_19.5^2 of the fully developed sea: 2 sqrt(a / b) = 0.20925 (4 sqrt(m0) with
m0 = a U^4 / (4 b g^2), the spectrum's integral)."""


def pierson_moskowitz_wind(hs_m: float, gravity_m_s2: float, reference_height_m: float,
                           profile_exponent: float) -> float:
    """The mean wind at ``reference_height_m`` over a fully developed sea of significant height
    ``hs_m`` (Pierson and Moskowitz, 1964): U_19.5 = sqrt(g Hs / :data:`PM_HS_COEFFICIENT`),
    taken to the reference height by the power law (U_r = U_19.5 (z_r / 19.5) ** alpha, the
    profile :func:`marinecdpr.motion.wind.wind_speed_at` follows), m/s."""
    u195 = math.sqrt(gravity_m_s2 * hs_m / PM_HS_COEFFICIENT)
    return u195 * (reference_height_m / PM_HEIGHT_M) ** profile_exponent


def sea_direction_deg(heading_deg: float, misalignment_deg: float) -> float:
    """Where the wind comes FROM in O, deg in [0, 360): ``heading_deg + 180 + misalignment_deg``
    (the waves travel TO ``heading_deg``; O's x along the ship's mean heading)."""
    return float((heading_deg + 180.0 + misalignment_deg) % 360.0)


def sea_wind(wind: "Wind", *, hs_m: float, heading_deg: float, gravity_m_s2: float, speed_m_s: float | None = None,
             misalignment_deg: float | None = None) -> tuple[float, float]:
    """A wind that follows the sea (``wind.with_sea`` not "none") in one sea state: its mean
    speed at the reference height (m/s) and the direction it comes from in O (deg).

    Parameters
    ----------
    wind : Wind
    hs_m, heading_deg : float
        The sea state's Hs (m) and the waves' heading (deg, where they travel to).
    gravity_m_s2 : float
        g, for the Pierson-Moskowitz relation.
    speed_m_s : float, optional
        With ``with_sea = "scatter"``: the cell's ``wind_m_s`` (None: the wind's own
        ``speed_m_s``, the scenario's own sea state's).
    misalignment_deg : float, optional
        The cell's ``wind_misalignment_deg`` (None: the wind's own ``misalignment_deg``).
    """
    if wind.with_sea == "pierson_moskowitz":
        speed = pierson_moskowitz_wind(hs_m, gravity_m_s2, wind.reference_height_m, wind.profile_exponent)
    else:
        speed = float(wind.speed_m_s if speed_m_s is None else speed_m_s)
    mis = wind.misalignment_deg if misalignment_deg is None else misalignment_deg
    return speed, sea_direction_deg(heading_deg, mis)


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

    speed_m_s: _ranged(0.0, SPEED_MAX_M_S, "m/s", "beyond a hurricane's mean wind", above=True) | None = None
    """U_r: the mean speed at ``reference_height_m`` (the one-hour mean, Frøya's U0), m/s
    (required unless ``with_sea = "pierson_moskowitz"``, which sets it)."""
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
    with_sea: Literal["none", "scatter", "pierson_moskowitz"] = "none"
    """What the wind follows in each sea state (:data:`WITH_SEA`; the module's text)."""
    misalignment_deg: _ranged(-360.0, 360.0, "deg", "one turn either way") = 0.0
    """With ``with_sea``: where the wind comes from less where the waves come from,
    counter-clockwise about z up, deg (0: the wind blows the way the waves travel)."""

    @model_validator(mode="after")
    def _check_sea(self) -> "Wind":
        given = self.model_fields_set
        if self.with_sea == "none":
            if self.speed_m_s is None:
                raise _KeyedError("speed_m_s", "missing: the mean wind speed at reference_height_m, m/s (or "
                                                "with_sea = \"pierson_moskowitz\" or \"scatter\")")
            if self.misalignment_deg != 0.0:
                raise _KeyedError("misalignment_deg", "is for a wind that follows the sea (with_sea = "
                                                       "\"pierson_moskowitz\" or \"scatter\"); without it give "
                                                       "direction_deg")
            return self
        if "direction_deg" in given:
            raise _KeyedError("direction_deg", f"with_sea = \"{self.with_sea}\" sets it from the waves' heading "
                                               "(heading_deg + 180 + misalignment_deg): leave it out, or give "
                                               "misalignment_deg")
        if self.with_sea == "pierson_moskowitz" and "speed_m_s" in given:
            raise _KeyedError("speed_m_s", "with_sea = \"pierson_moskowitz\" sets it from each sea state's Hs: "
                                           "leave it out (or use with_sea = \"scatter\" or \"none\")")
        if self.with_sea == "scatter" and self.speed_m_s is None:
            raise _KeyedError("speed_m_s", "missing: with with_sea = \"scatter\" it is the wind in [base_motion]'s "
                                           "own sea state (plan, simulate), m/s; a study takes each cell's from the "
                                           "scatter diagram's wind_m_s column")
        return self

    @model_serializer(mode="wrap")
    def _dump(self, handler):
        """What the section was given: the keys with_sea sets (direction_deg, and speed_m_s
        with "pierson_moskowitz") are left out, set again from the sea state on reading; with
        ``with_sea = "none"`` the section as before it had these keys."""
        data = handler(self)
        if isinstance(data, dict):
            if self.with_sea == "none":
                data.pop("with_sea", None)
                data.pop("misalignment_deg", None)
            else:
                data.pop("direction_deg", None)
                if self.with_sea == "pierson_moskowitz":
                    data.pop("speed_m_s", None)
        return data

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
