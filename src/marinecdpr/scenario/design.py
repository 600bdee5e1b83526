"""The design study's file (``marinecdpr design SPEC.toml``): the surface, the ship and its
seas, the targets, the design variables and the catalogues of winches and ropes.

A study designs a planar cable robot like the paper's (frame anchors at the corners of a
W x H frame in the hull's plane, platform anchors at the corners of a w x h platform, four
cables uncrossed or crossed; or five or six, with one or two more from the frame's sides'
middles: :data:`PATTERNS`) for the ``[cleaning.surface]`` of a template scenario, which also gives
the ship (its RAOs and sea-state base motion), the tool's contact (brush, friction, normal
force band) and the frame's place in S. Each variable is a number (held) or ``[lo, hi]``
(searched); the winch and the rope are chosen from the catalogues by name. ``[constraints]``
adds optional constraints (:class:`Constraints`: every single cable's failure survived).
"""

from __future__ import annotations

import re
from typing import Annotated, Any, Literal

from pydantic import AfterValidator, Field, StrictBool, StrictInt, StrictStr, model_validator

from marinecdpr.scenario.cleaning import StandOffTolerance
from marinecdpr.scenario.fields import _KeyedError, _Model, _num, _ranged
from marinecdpr.scenario.relocation import ROBOTS_MAX, Relocation

__all__ = ["DesignSpec", "Winch", "Rope", "Variables", "Constraints", "CONTINUOUS", "PATTERNS", "PATTERN_CABLES",
           "FAILURE_HOLD_S", "POPULATION", "GENERATIONS",
           "SEED_MAX", "STUDY_NAME", "safe_stem", "RAIL_VARIABLES",
           "WINCH_INERTIA_PER_TORQUE"]

POPULATION = (4, 1000)
"""The least and most candidates a generation (the study's ``population`` and ``design --population``)."""
GENERATIONS = (1, 1000)
"""The least and most generations (the study's ``generations`` and ``design --generations``)."""
SEED_MAX = 2**32 - 1
"""The largest seed (the search's random generator takes 32 bits)."""
STUDY_NAME = re.compile(r"\w[\w.-]{0,99}")
"""A study's name: the stem of the files it writes (``designs/NAME_1.toml``): a letter, digit or
underscore, then at most 99 more of those, dots and hyphens; no path separator, no control
character, no space."""


def safe_stem(value: str) -> str:
    """``value`` if it is a safe file stem (:data:`STUDY_NAME`, not ending in a dot), else
    ValueError saying what a name may hold."""
    if not isinstance(value, str) or not STUDY_NAME.fullmatch(value) or value.endswith("."):
        shown = repr(value) if len(value) <= 60 else repr(value[:57]) + "..."
        raise ValueError("must be a file name's stem (the finalists are written as NAME_1.toml): letters, digits, "
                         "'_', '.' and '-', starting with a letter, digit or '_', at most 100 characters, no path "
                         f"separator; got {shown}")
    return value


def _bound(lo: float, hi: float, unit: str, why: str, *, above: bool = False) -> Any:
    """A number in [lo, hi] ((lo, hi] with ``above``), or a pair [low, high] within it with low <= high."""
    one = _ranged(lo, hi, unit, why, above=above)

    def ordered(value):
        if isinstance(value, tuple) and not value[0] <= value[1]:
            raise ValueError(f"must be [low, high] with low <= high, got [{_num(value[0])}, {_num(value[1])}]")
        return value

    return Annotated[one | tuple[one, one], AfterValidator(ordered)]


PATTERNS = ("uncrossed", "crossed", "five_top", "six_top_bottom", "six_sides", "six_double_top", "eight_double")
"""The cable patterns (their cable counts: :data:`PATTERN_CABLES`). Four cables:
``uncrossed``, each frame corner's cable to the platform's same corner (the paper's);
``crossed``, the upper frame corners' cables to the platform's opposite upper corners, the
lower ones' to its opposite lower corners, the two cables of each crossing pair in two planes
``limits.layer_m`` apart (y = +-layer / 2 at both ends), so that they pass each other.
Five and six: the four corners uncrossed and one or two cables more from the middle of a
frame side to the middle of the platform's same side: ``five_top`` the top side's (cable 5);
``six_top_bottom`` the top's and the bottom's (cables 5, 6); ``six_sides`` the aft side's
and the fore side's (cables 5, 6), halfway up the frame. ``six_double_top``: the four corners
uncrossed and the two upper ones doubled, cables 5 and 6 from the frame's upper aft and fore
corners to the platform's same corners beside cables 1 and 2, each pair in two planes
``limits.layer_m`` apart (1 and 2 in y = +layer / 2, 5 and 6 in y = -layer / 2): on a frame
standing up the hull the upper cables carry the weight, and at the panel's fore (aft) end only
the upper fore (aft) corner pulls the platform up and towards that end, so that a cable lost
there leaves the platform unheld unless it is doubled. ``eight_double``: every corner doubled
(cables 1 to 4 in y = +layer / 2, 5 to 8 beside them in y = -layer / 2), still planar: the
lower corners' cables hold the platform's turn at the panel's far corners, where a lost lower
cable leaves it unbalanced."""
PATTERN_CABLES = {"uncrossed": 4, "crossed": 4, "five_top": 5, "six_top_bottom": 6, "six_sides": 6,
                  "six_double_top": 6, "eight_double": 8}
"""Each pattern's number of cables (and winches)."""
FAILURE_HOLD_S = 600.0
"""``[constraints] failure_hold_s``'s default: how long the remaining cables hold the platform
after a cable fails (to park it and take it off the hull; chosen), s."""

CONTINUOUS = ("frame_width_m", "frame_height_m", "platform_width_m", "platform_height_m", "tool_width_m",
              "speed_m_s", "overlap_share")
"""The continuous design variables, in the order candidates list them."""
RAIL_VARIABLES = {"rail_speed_m_s": "speed_m_s", "rail_accel_m_s2": "accel_m_s2", "rail_jerk_m_s3": "jerk_m_s3"}
"""The carriage's limits as design variables (optional, each a number or ``[lo, hi]``), listed
after :data:`CONTINUOUS` where the study gives them, and the ``[relocation.rail]`` figures
each overrides in a candidate that moves by rail."""


class Variables(_Model):
    """``[variables]``: each a number (held) or ``[lo, hi]`` (searched)."""

    frame_width_m: _bound(0.5, 100.0, "m", "a frame along the ship")
    frame_height_m: _bound(0.5, 100.0, "m", "a frame up the hull")
    platform_width_m: _bound(0.05, 10.0, "m", "the platform anchors' spacing along the frame")
    platform_height_m: _bound(0.05, 10.0, "m", "the platform anchors' spacing up the frame")
    tool_width_m: _bound(0.02, 5.0, "m", "the brush's cleaning width")
    speed_m_s: _bound(0.005, 5.0, "m/s", "the tool's travel speed")
    overlap_share: _bound(0.0, 0.5, "", "the lanes' overlap, a share of the tool's width") = 0.15
    rail_speed_m_s: _bound(0.0, 10.0, "m/s", "a carriage on a rail, not a vehicle", above=True) | None = None
    """The carriage's top speed (``[relocation.rail] speed_m_s`` in candidates moved by rail)."""
    rail_accel_m_s2: _bound(0.0, 20.0, "m/s^2", "two g: beyond any carriage's drive", above=True) | None = None
    """The carriage's acceleration (``[relocation.rail] accel_m_s2``; the cables hold the
    platform against it: the constraint ``rail_accel_m_s2``)."""
    rail_jerk_m_s3: _bound(0.0, 1000.0, "m/s^3", "beyond any carriage's drive", above=True) | None = None
    """The carriage's jerk (``[relocation.rail] jerk_m_s3``)."""
    winch: list[StrictStr] | None = None
    """Winch names from ``[[winches]]`` to choose from (default: every one)."""
    rope: list[StrictStr] | None = None
    """Rope names from ``[[ropes]]`` to choose from (default: every one)."""
    pattern: list[StrictStr] | None = Field(default=None, min_length=1)
    """The cable patterns to choose from (:data:`PATTERNS`; default: uncrossed, the paper's)."""
    relocation: list[Literal["fixed", "crane", "rail"]] | None = Field(default=None, min_length=1)
    """How the frame moves between placements, modes to choose from (each with its figures in
    ``[relocation]``; default: ``[relocation]``'s mode)."""
    robots: list[Annotated[StrictInt, Field(ge=1, le=ROBOTS_MAX)]] | None = Field(default=None, min_length=1)
    """How many robots work the side at once, counts to choose from (default:
    ``[relocation]``'s ``robots``, else 1)."""


class Winch(_Model):
    """``[[winches]]``: one winch of the catalogue (one per cable is installed)."""

    name: StrictStr
    torque_N_m: _ranged(0.0, 1e6, "N m", "a winch's rated torque", above=True)
    speed_rad_s: _ranged(0.0, 1e4, "rad/s", "a drum's top speed", above=True)
    power_W: _ranged(0.0, 1e7, "W", "a winch's rated power", above=True)
    drum_radius_m: _ranged(0.0, 5.0, "m", "a drum's radius", above=True)
    mass_kg: _ranged(0.0, 1e5, "kg", "a winch's mass") = 0.0
    cost: _ranged(0.0, 1e9, "", "the user's cost unit") = 0.0
    inertia_kg_m2: _ranged(0.0, 1e5, "kg m^2", "a drum's and motor's inertia at the drum", above=True) | None = None
    """The drum's and the motor's rotating inertia seen at the drum, kg m^2 (the finalists
    fly their winches' dynamics); default :data:`WINCH_INERTIA_PER_TORQUE` x ``torque_N_m``."""

    @property
    def inertia(self) -> float:
        """``inertia_kg_m2``, or its default, kg m^2."""
        return self.inertia_kg_m2 if self.inertia_kg_m2 is not None else WINCH_INERTIA_PER_TORQUE * self.torque_N_m


WINCH_INERTIA_PER_TORQUE = 5.5e-4
"""A catalogue winch's inertia at the drum per newton-metre of its torque, kg m^2 / (N m), where
the catalogue gives none: the built-in paper_as_built's winch (a 200 W motor's 1e-4 kg m^2
rotor through 10:1 and a 1e-3 kg m^2 drum: 0.011 kg m^2 at the drum, for 2 N m x 10 = 20 N m)."""


class Rope(_Model):
    """``[[ropes]]``: one rope of the catalogue."""

    name: StrictStr
    diameter_m: _ranged(0.0, 0.5, "m", "a rope's diameter", above=True)
    ea_N: _ranged(0.0, 1e12, "N", "a rope's axial stiffness EA", above=True)
    weight_N_m: _ranged(0.0, 1e4, "N/m", "a rope's weight per metre")
    breaking_N: _ranged(0.0, 1e9, "N", "a rope's breaking load", above=True)
    safety_factor: _ranged(1.0, 100.0, "", "breaking load over the largest working tension") = 5.0
    cost_per_m: _ranged(0.0, 1e9, "", "the user's cost unit per metre") = 0.0


class Constraints(_Model):
    """``[constraints]``: optional constraints on every candidate."""

    single_cable_failure: StrictBool = False
    """Every single cable's failure survived: with each cable removed in turn, the others
    hold the platform within their limits at the screen's poses over the job, the tool at
    its preload (still or sliding), and (a candidate moved by rail) at the panel's centre while
    the carriage accelerates the frame, with the sea's extreme over ``failure_hold_s`` in every
    sea state the job works in (:func:`~marinecdpr.planning.redundancy.single_failure_margin`).
    A four-cable candidate is left with three cables for three dofs: one set of tensions,
    within the limits only where the load lets it."""
    failure_hold_s: _ranged(0.0, 86400.0, "s", "how long the remaining cables hold the platform",
                            above=True) = FAILURE_HOLD_S
    """How long the remaining cables hold the platform after a failure (the sea's extreme is
    taken over it), s."""


class Targets(_Model):
    """``[targets]``."""

    hours: _ranged(0.0, 1e6, "h", "the whole surface's expected hours", above=True)
    sea_share: _ranged(0.0, 1.0, "", "a share of the sea states, in (0, 1]", above=True)


class Sea(_Model):
    """``[sea]``: where the ship waits."""

    scatter: StrictStr = "illustrative"
    """A scatter diagram CSV (hs_m, tp_s, probability or hs_m, tz_s, probability), or a package
    diagram's name: "illustrative", "north_atlantic" (IACS Rec. 34's North Atlantic table)."""
    headings_deg: list[_ranged(-360.0, 360.0, "deg", "a wave heading")] = Field(default=[180.0, 150.0, 90.0],
                                                                              min_length=1, max_length=36)
    verify: Literal["all", "boundary"] = "all"
    """Which sea states the finalists fly in the time domain: "all", or "boundary": in each
    column of the diagram (one period, one heading) only those about the height where the job
    first fails, found by bisection from the screen's verdicts; the column's lower seas are
    taken to work and its higher ones to fail (the sea's response grows with Hs at one Tp
    and heading). For diagrams of hundreds of sea states."""
    unflown_share: _ranged(0.0, 0.5, "", "a share of the sea states' probability, in [0, 0.5]") = 0.0
    """With ``verify = "boundary"``: the most probability the time domain may leave unjudged.
    The columns of least probability whose sum is at most this are not flown; the time
    domain's share counts their sea states as failing (a lower bound, its expected hours an
    upper bound) and says how much they hold."""


class PlatformMass(_Model):
    """``[platform_mass]``: mass = base + per_tool_width x tool width + per_area x platform area."""

    base_kg: _ranged(0.0, 1e4, "kg", "a platform's bare mass", above=True)
    per_tool_width_kg_m: _ranged(0.0, 1e4, "kg/m", "the tool's mass per metre of width") = 0.0
    per_area_kg_m2: _ranged(0.0, 1e4, "kg/m2", "the platform's mass per square metre") = 0.0


class Limits(_Model):
    """``[limits]``."""

    edge_m: _ranged(0.0, 10.0, "m", "the tool's keep-off from the frame, beyond the platform's half size") = 0.15
    tension_min_N: _ranged(0.0, 1e6, "N", "the least tension a cable keeps taut") = 10.0
    sag_m: _ranged(0.0, 10.0, "m", "the largest sag of the longest span at the least tension", above=True) = 0.05
    stretch_m: _ranged(0.0, 10.0, "m", "the longest span's stretch between the least and largest tension",
                       above=True) = 0.05
    layer_m: _ranged(0.0, 1.0, "m", "the spacing of the planes crossed cables run in", above=True) = 0.05
    clearance_m: _ranged(0.0, 1.0, "m", "the least gap between cables, and between a cable and the platform") = 0.0
    stand_off_tolerance_m: StandOffTolerance | None = None
    """The candidates' tool's stand-off tolerance (its pusher's stroke), which sets how large a
    flat placement of the curved surface may be; default the template's."""


class DesignSpec(_Model):
    """The design study."""

    name: Annotated[StrictStr, AfterValidator(safe_stem)]
    """The study's name, the stem of its finalists' files (:func:`safe_stem`)."""
    description: StrictStr = ""
    scenario: StrictStr
    """The template: a scenario file (relative to the study's folder) or a built-in name, with
    ``[cleaning]`` and its ``surface`` and a ``sea_state`` base motion."""
    move_time_s: _ranged(0.0, 86400.0, "s", "moving the frame to its next placement") = 600.0
    objective: Literal["power", "cost"] = "power"
    """What the hours are traded against: the installed winch power, or the cost of winches and ropes."""
    cost_unit: StrictStr = Field(default="", max_length=16, pattern=r"^[^\x00-\x1f<>&]*$")
    """The unit of the catalogues' costs, as the report labels them (e.g. "EUR"); "" when not given."""
    seed: StrictInt = Field(default=1, ge=0, le=SEED_MAX)
    population: StrictInt = Field(default=24, ge=POPULATION[0], le=POPULATION[1])
    generations: StrictInt = Field(default=10, ge=GENERATIONS[0], le=GENERATIONS[1])
    finalists: StrictInt = Field(default=3, ge=0, le=20)
    plant: Literal["mujoco", "own"] | None = None
    """The plant the finalists fly on, closed loop (default: the template's ``simulation.plant``)."""
    targets: Targets
    sea: Sea = Sea()
    platform_mass: PlatformMass
    limits: Limits = Limits()
    constraints: Constraints = Constraints()
    """Optional constraints (:class:`Constraints`)."""
    relocation: Relocation | None = None
    """How the frame moves between placements and how many robots share the side
    (:class:`~marinecdpr.scenario.relocation.Relocation`, ``[cleaning.surface.relocation]``'s
    fields): the candidates' (default: the template's, else every move ``move_time_s``)."""
    variables: Variables
    winches: list[Winch] = Field(min_length=1)
    ropes: list[Rope] = Field(min_length=1)

    @model_validator(mode="after")
    def _check(self) -> "DesignSpec":
        for key, catalogue in (("winches", self.winches), ("ropes", self.ropes)):
            names = [e.name for e in catalogue]
            for i, name in enumerate(names):
                if name in names[:i]:
                    raise _KeyedError(f"{key}[{i + 1}].name", f"{name!r} is listed twice")
        for key, catalogue in (("winch", self.winches), ("rope", self.ropes)):
            chosen = getattr(self.variables, key)
            if chosen is None:
                continue
            if not chosen:
                raise _KeyedError(f"variables.{key}", "names no entry: list at least one")
            known = [e.name for e in catalogue]
            for i, name in enumerate(chosen):
                if name not in known:
                    raise _KeyedError(f"variables.{key}[{i + 1}]", f"{name!r} is not in the catalogue "
                                                                  f"({', '.join(known)})")
        known = ", ".join(f"{p} ({n} cables)" for p, n in PATTERN_CABLES.items())
        for i, name in enumerate(self.variables.pattern or []):
            if name not in PATTERNS:
                raise _KeyedError(f"variables.pattern[{i + 1}]", f"{name!r} is no cable pattern (the patterns: "
                                                                 f"{known})")
        for key in ("pattern", "relocation", "robots"):
            chosen = getattr(self.variables, key) or []
            for i, value in enumerate(chosen):
                if value in chosen[:i]:
                    raise _KeyedError(f"variables.{key}[{i + 1}]", f"{value!r} is listed twice")
        for key in self.rail_variables:
            if self.relocation is None or self.relocation.rail is None:
                raise _KeyedError(f"variables.{key}", "sets the carriage's limits: give [relocation.rail], whose "
                                                     "figures it overrides in candidates moved by rail")
            if "rail" not in self.choices("relocation"):
                raise _KeyedError(f"variables.{key}", "sets the carriage's limits, but no candidate moves by rail: "
                                                     "list \"rail\" in variables.relocation")
        if self.sea.unflown_share > 0.0 and self.sea.verify != "boundary":
            raise _KeyedError("sea.unflown_share", "leaves columns of the diagram unflown: it needs "
                                                   "[sea] verify = \"boundary\"")
        for i, mode in enumerate(self.variables.relocation or []):
            if mode != "fixed" and getattr(self.relocation, mode, None) is None:
                raise _KeyedError(f"variables.relocation[{i + 1}]", f"{mode!r} needs its figures in "
                                                                   f"[relocation.{mode}]")
            if mode == "crane" or (mode == "rail" and self.relocation.crane is not None):
                if self.relocation.frame_mass_kg is None:
                    raise _KeyedError(f"variables.relocation[{i + 1}]", "a crane lifts the frame: give "
                                                                       "[relocation] frame_mass_kg")
        return self

    @property
    def relocates(self) -> bool:
        """Does the study set the frame's moves or the robots (``[relocation]``, or
        ``relocation`` or ``robots`` among the variables)? Its candidates then carry both."""
        return (self.relocation is not None or self.variables.relocation is not None
                or self.variables.robots is not None)

    def choices(self, key: str) -> list:
        """The catalogue entries a variable ``key`` ("winch" or "rope") chooses from, the
        cable patterns ("pattern"), the relocation modes ("relocation") or the robots' counts
        ("robots")."""
        if key == "pattern":
            return list(self.variables.pattern or ["uncrossed"])
        if key == "relocation":
            return list(self.variables.relocation or [self.relocation.mode if self.relocation else "fixed"])
        if key == "robots":
            return list(self.variables.robots or [self.relocation.robots if self.relocation else 1])
        catalogue = self.winches if key == "winch" else self.ropes
        chosen = getattr(self.variables, key)
        return [e for e in catalogue if chosen is None or e.name in chosen]

    @property
    def rail_variables(self) -> list[str]:
        """The carriage's limits the study makes variables (:data:`RAIL_VARIABLES`' keys it gives)."""
        return [k for k in RAIL_VARIABLES if getattr(self.variables, k) is not None]

    def bounds(self) -> dict[str, tuple[float, float]]:
        """Every continuous variable's [lo, hi] (a held one's lo = hi): :data:`CONTINUOUS`,
        then the carriage's limits the study gives (:attr:`rail_variables`)."""
        out = {}
        for key in (*CONTINUOUS, *self.rail_variables):
            v = getattr(self.variables, key)
            out[key] = (float(v[0]), float(v[1])) if isinstance(v, tuple) else (float(v), float(v))
        return out
