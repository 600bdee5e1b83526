"""Design a robot for a ship (``marinecdpr design``): the frame, platform, winches, rope and
tool that clean a hull surface in the fewest expected hours for the power (or cost)
installed, in the seas where the ship waits.

Each candidate is a scenario built from the study's template (:func:`candidate_scenario`)
and judged by the toolkit's own models (:func:`evaluate`):

- **hours on the surface**: the frame's placements on ``[cleaning.surface]`` for the
  candidate's panel, each placement's coverage path with its tool, and the moves between
  them (:func:`~marinecdpr.studies.surface.surface_job`, paths timed to the centimetre);
- **the sea's share**: the probability, over the scatter diagram and headings, that the job
  holds, by the fast screen (:func:`~marinecdpr.studies.screen.screen_cells`: tensions within
  limits over the whole panel under the sea's motion, the normal force in band) with the
  frame at the band's ends and middle, at its top and bottom, each placed and turned as
  the surface places it (:func:`frame_placements`: the ship moves most at its ends and at
  the top of its side, a flared side leans the frame most at the top amidships), the job
  working only where it works at all of them;
- **expected hours** = hours on the surface / the sea's share (the job waits for the seas it
  works in);
- **constraints**, each a margin that must not be negative: the sea's share against the
  target; the winch's drum speed against the tool's speed (a cable never runs faster than
  the platform); the winch's power against the largest tension at that speed (its torque
  sets T_max with the rope's breaking load over its safety factor); the longest span's sag
  at the least tension w L^2 / (8 T_min) and its stretch between the limits (T_max - T_min)
  L / EA against the study's limits; a panel at least as wide as the tool; no cable nearer
  another cable, or the platform's body, than the rope's diameter and ``limits.clearance_m``
  anywhere on the job's path (:func:`clearance`: crossed cables pass each other in their
  two planes); with ``[constraints] single_cable_failure``, every single cable's failure
  survived (:data:`FAILURE_CONSTRAINT`).

The cables: four (uncrossed or crossed), five or six (the corners and one or two sides'
middles, or the upper corners doubled) or eight (every corner doubled), by ``[variables]
pattern`` (:func:`cable_pattern`); each cable its own winch and rope, in the power and the cost.

The search (:func:`search`) is NSGA-II over the mixed variables (pymoo), with a seed.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np
from scipy.fft import next_fast_len

from marinecdpr.errors import ScenarioError
from marinecdpr.scenario.cleaning import Cleaning
from marinecdpr.scenario.design import CONTINUOUS, PATTERN_CABLES, RAIL_VARIABLES, DesignSpec
from marinecdpr.scenario.schema import Safety, Scenario, validated_scenario
from marinecdpr.studies.executor import Executor

__all__ = ["Evaluation", "DesignStudy", "Verification", "load_design", "candidate_scenario", "evaluate", "search",
           "frame_placements", "screen_surface", "verify", "pareto_mask", "cable_pattern", "clearance", "frame_turns",
           "study_cells", "study_scatter", "read_journal", "study_key", "builtin_studies", "study_path", "with_options",
           "CONSTRAINTS", "CAPACITIES", "as_built", "span_sag", "SAG_SHARE", "relocation_of", "RAIL_CONSTRAINT",
           "study_constraints", "candidate_rail", "rail_held_acceleration", "FAILURE_CONSTRAINT", "cable_count",
           "rail_single_failure", "sea_columns", "column_boundary", "unflown_columns", "fly_boundary"]

CONSTRAINTS = ("sea_share", "winch_speed_m_s", "winch_power_W", "sag_m", "stretch_m", "panel_m", "clearance_m")
"""The constraint margins each candidate reports (>= 0 to be feasible), in candidates.csv's order."""

CAPACITIES = {"sea_share": "the share of sea states that work", "winch_speed_m_s": "the drum's top speed",
              "winch_power_W": "the winch's rated power", "sag_m": "limits.sag_m", "stretch_m": "limits.stretch_m",
              "panel_m": "the panel's smaller side", "clearance_m": "the least gap measured",
              "rail_accel_m_s2": "the carriage's largest acceleration the cables hold (a candidate moved by rail)",
              "single_cable_failure_N": "half the narrowest tension range (the margin's cap)"}
"""What each margin's slack (:attr:`Evaluation.slack`) is a share of: slack = margin / capacity."""
RAIL_CONSTRAINT = "rail_accel_m_s2"
"""The constraint a candidate moved by rail adds (after :data:`CONSTRAINTS`): the largest
acceleration of the carriage with which the cables hold the platform at the panel's centre in
the sea states the candidate works in (:func:`~marinecdpr.studies.screen.held_acceleration`),
less its ``accel_m_s2``; its capacity that largest acceleration."""


FAILURE_CONSTRAINT = "single_cable_failure_N"
"""The constraint ``[constraints] single_cable_failure`` adds: with each cable removed in turn,
the least margin by which the remaining cables hold the platform within their limits over the
screen's poses at every placement (:func:`~marinecdpr.studies.screen.single_failure_cells`)
and, for a candidate moved by rail, at the panel's centre while its carriage moves the frame
(:func:`rail_single_failure`), in the sea states the job works in (on a ship at rest where it
works in none), the sea's extreme over ``failure_hold_s``, N; its capacity half the narrowest
tension range."""


def study_constraints(spec: DesignSpec) -> tuple[str, ...]:
    """The constraints a study's candidates report: :data:`CONSTRAINTS`,
    :data:`RAIL_CONSTRAINT` where any candidate may move by rail (a candidate moved otherwise
    has no such margin: nothing to hold), and :data:`FAILURE_CONSTRAINT` with
    ``[constraints] single_cable_failure``."""
    return (CONSTRAINTS + ((RAIL_CONSTRAINT,) if "rail" in spec.choices("relocation") else ())
            + ((FAILURE_CONSTRAINT,) if spec.constraints.single_cable_failure else ()))


def cable_count(x: dict) -> int:
    """How many cables (and winches) a candidate's pattern has (four where it names none, or
    names the template's own)."""
    return PATTERN_CABLES.get(x.get("pattern", "uncrossed"), 4)

SAG_SHARE = 0.01
"""A finalist flies sagging (catenary) cables where its longest span's sag at the least
tension exceeds this share of the span (:func:`as_built`): a shallow cable's tangent leaves
its chord by about 4 sag / span at its ends (2.3 deg at 1 %), so the straight cable then
misses a sideways pull of 4 % of the tension (the half of the cable's weight the platform
carries, w L / 2 = 4 (sag / L) T_min)."""


def span_sag(weight_N_m: float, width_m: float, height_m: float, tension_min_N: float) -> tuple[float, float]:
    """A W x H frame's longest span (its diagonal, m) and that span's sag at the least
    tension, w L^2 / (8 T_min) (a shallow catenary's, m), for a rope of weight w (N/m).

    Returns
    -------
    span, sag : float
        m, m.
    """
    span = float(np.hypot(width_m, height_m))
    return span, weight_N_m * span**2 / (8.0 * max(tension_min_N, 1e-9))


def _designs_folder() -> Path:
    from importlib import resources

    return Path(str(resources.files("marinecdpr") / "data" / "designs"))


def builtin_studies() -> list[str]:
    """The names of the design studies shipped with the package (``marinecdpr design NAME``):
    the TOML files of its ``data/designs`` folder that are studies (with ``[variables]``), not
    their templates."""
    import tomllib

    names = []
    for p in sorted(_designs_folder().glob("*.toml")):
        try:
            if "variables" in tomllib.loads(p.read_text(encoding="utf-8")):
                names.append(p.stem)
        except (OSError, ValueError):  # pragma: no cover - the package's own files
            continue
    return names


def study_path(name_or_path: str | Path) -> Path:
    """A design study file, or a built-in study's file by its name (:func:`builtin_studies`)
    where no file of that name is there."""
    path = Path(name_or_path)
    if not path.exists() and str(name_or_path) in builtin_studies():
        return _designs_folder() / f"{name_or_path}.toml"
    return path


def load_design(path: str | Path) -> tuple[DesignSpec, Scenario]:
    """A design study file and its template scenario, validated, and every file it reads
    read: the template's (its RAOs, its surface's mesh) and the scatter diagram.

    Raises
    ------
    ScenarioError
        One line naming the file and the key: no such file (the built-in studies listed),
        unreadable TOML, an unknown or missing key, a name that is no file name, a bound with
        low > high, a catalogue entry without a field, a target outside its range, a template
        without ``[cleaning.surface]`` or a sea-state base motion, a surface band too large to
        tile (:data:`~marinecdpr.studies.surface.MAX_SURFACE_PATCHES`), a bad scatter diagram.
    """
    import difflib
    import tomllib

    from pydantic import ValidationError

    from marinecdpr.scenario.loading import scenario_text, builtin_scenarios, load_scenario
    from marinecdpr.scenario.messages import scenario_error
    from marinecdpr.studies.operability import BUILTIN_SCATTERS
    from marinecdpr.studies.surface import surface_patches

    path = Path(path)
    src = str(path)
    if path.is_dir():
        raise ScenarioError("a folder, not a file; expected a design study file (.toml) or a built-in study's name",
                            source=src)
    if not path.is_file():
        known = builtin_studies()
        close = difflib.get_close_matches(src, known, n=1)
        raise ScenarioError("no such file, and no built-in study of that name ("
                            + (f"did you mean {close[0]!r}? " if close else "")
                            + f"built-in studies: {', '.join(known)})", source=src)
    try:
        data = tomllib.loads(scenario_text(path, src))
    except tomllib.TOMLDecodeError as exc:
        raise ScenarioError(f"not valid TOML: {exc}", source=src) from None
    except RecursionError:  # tomllib recurses into nested arrays and inline tables
        raise ScenarioError("not valid TOML: arrays or inline tables too deeply nested", source=src) from None
    try:
        spec = DesignSpec.model_validate(data)
    except ValidationError as exc:
        raise scenario_error(exc, data, src, DesignSpec) from None
    name = spec.scenario
    template_path = name if name in builtin_scenarios() else str((path.parent / name).resolve())
    template = load_scenario(template_path)
    if template.cleaning is None or template.cleaning.surface is None:
        raise ScenarioError(f"the template {name!r} has no [cleaning.surface]: the study designs for a surface",
                            source=src, key="scenario")
    if template.base_motion.type != "sea_state":
        raise ScenarioError(f"the template {name!r} has no sea-state base motion: the study needs its RAOs",
                            source=src, key="scenario")
    if template.robot.dofs != "planar":
        raise ScenarioError(f"the template {name!r} is a spatial robot: the study designs planar robots",
                            source=src, key="scenario")
    if template.ship.carriage is not None:
        raise ScenarioError(f"the template {name!r} carries its frame on a rail ([ship.carriage]): the study places "
                            "the frame itself on the surface; leave the carriage out and give [relocation] "
                            "mode = \"rail\" for moves along a rail", source=src, key="scenario")
    try:  # the template's own robot is judged too (the baseline): its band must be one a run may tile
        surface_patches(template)
    except ScenarioError as exc:
        raise ScenarioError(f"the template {name!r}: {exc}", source=src, key="scenario") from None
    if spec.sea.scatter not in BUILTIN_SCATTERS and not (path.parent / spec.sea.scatter).is_file():
        raise ScenarioError(f"no such file: {path.parent / spec.sea.scatter} (the package's diagrams: "
                            f"{', '.join(BUILTIN_SCATTERS)})", source=src, key="sea.scatter")
    try:  # read now: a bad diagram (or one the template's wind cannot follow) is one line before any work
        from marinecdpr.studies.operability import check_sea_wind

        check_sea_wind(template, study_scatter(spec, path.parent, template))
    except ScenarioError as exc:
        raise ScenarioError(str(exc), source=src, key="sea.scatter") from None
    return spec, template


def with_options(spec: DesignSpec, **options) -> DesignSpec:
    """The study with the given fields (``population``, ``generations``, ``seed``: the
    command's options; None leaves the study's) validated as the study file's own are.

    Raises
    ------
    ScenarioError
        A value the study file could not hold, named as its option (``--population 1001:
        ...``).
    """
    from pydantic import ValidationError

    changes = {k: v for k, v in options.items() if v is not None}
    if not changes:
        return spec
    data = spec.model_dump()
    try:
        return DesignSpec.model_validate(data | changes)
    except ValidationError as exc:
        err = exc.errors()[0]
        key = str(err["loc"][0]) if err["loc"] else "?"
        message = err["msg"].removeprefix("Value error, ")
        raise ScenarioError(f"--{key} {changes.get(key, '')}: {message[:1].lower()}{message[1:]}") from None


def study_scatter(spec: DesignSpec, folder: Path | None = None, template: Scenario | None = None):
    """The study's scatter diagram (:class:`~marinecdpr.studies.operability.ScatterDiagram`):
    a package diagram by its name, else the file relative to ``folder``. A diagram in Tz
    becomes Tp at the template's spectrum
    (:func:`~marinecdpr.studies.operability.tz_conversion_gamma`; Pierson-Moskowitz without
    a template)."""
    from marinecdpr.studies.operability import read_scatter_csv, scatter_path, tz_conversion_gamma

    gamma = 1.0 if template is None else tz_conversion_gamma(template)
    return read_scatter_csv(scatter_path(spec.sea.scatter, Path(folder or ".")), gamma=gamma)


def study_cells(spec: DesignSpec, folder: Path | None = None, template: Scenario | None = None) -> list:
    """The sea states of the study: its scatter diagram at each heading (equally likely)."""
    from marinecdpr.studies.operability import scatter_cells

    return scatter_cells(study_scatter(spec, folder, template), tuple(float(h) for h in spec.sea.headings_deg))


@dataclass(frozen=True)
class Evaluation:
    """One candidate, judged.

    Attributes
    ----------
    x : dict
        Its variables: the continuous ones (:data:`~marinecdpr.scenario.design.CONTINUOUS`),
        "winch" and "rope" by name, and "pattern".
    feasible : bool
        Every constraint margin >= 0.
    reason : str
        Why not ("" if feasible).
    placements : int
    surface_hours : float
        The placements' cleaning and moves, h.
    sea_share : float
        The probability that the job works in the seas.
    expected_hours : float
        surface_hours / sea_share (inf where no sea state works).
    power_kW : float
        The winches' rated power (one a cable, :func:`cable_count`).
    cost : float
        A winch and a span of rope (the frame's diagonal) a cable.
    tension_max_N : float
    mass_kg : float
    margins : dict
        :data:`CONSTRAINTS`' margins, a candidate moved by rail :data:`RAIL_CONSTRAINT`'s
        (:func:`rail_held_acceleration` less its ``accel_m_s2``), and with ``[constraints]
        single_cable_failure`` :data:`FAILURE_CONSTRAINT`'s.
    frame_origin_m : list of float
        The placement (C's origin in S) where the screen's share is least: where the
        finalists are flown.
    frame_orientation_deg : list of float
        The frame's orientation in S there (roll, pitch, yaw, deg: ``ship.frame_orientation_deg``).
    frame_turn_deg : list of float
        The median and the largest angle by which the surface turns the placements' frames
        from S's axes (:func:`frame_turns`), deg. The screen judges the frame at the band's
        placements in their own orientation (:func:`frame_placements`).
    sea_reason : str
        Why the screen fails the sea states it fails ("" where it passes them all): how many
        fail on what, and the mildest one's reason (:func:`~marinecdpr.studies.screen.why_fails`).
    cleaning_hours, turn_hours, move_hours : float
        The parts of ``surface_hours``: the brush on its lanes and boundary pass, stepping
        between lanes (:func:`~marinecdpr.studies.surface.turn_time`), and moving the frame
        between placements, h (NaN where not judged).
    slack : dict
        Each margin of ``margins`` as a share of what it is taken from (:data:`CAPACITIES`):
        1 unused, 0 binding, negative short.
    relocation_cost : float
        With a relocation (``[relocation]``, or the template's): what the moves cost
        (crane hire, rail, carriages and their drives), included in ``cost``
        (:func:`~marinecdpr.studies.relocation.relocation_cost`).
    rail_moves, crane_moves : int
        With a relocation: the moves made along the rail and by crane.
    """

    x: dict
    feasible: bool
    reason: str
    placements: int
    surface_hours: float
    sea_share: float
    expected_hours: float
    power_kW: float
    cost: float
    tension_max_N: float
    mass_kg: float
    margins: dict = field(default_factory=dict)
    frame_origin_m: list = field(default_factory=list)
    frame_orientation_deg: list = field(default_factory=lambda: [0.0, 0.0, 0.0])
    frame_turn_deg: list = field(default_factory=lambda: [0.0, 0.0])
    sea_reason: str = ""
    cleaning_hours: float = float("nan")
    turn_hours: float = float("nan")
    move_hours: float = float("nan")
    slack: dict = field(default_factory=dict)
    relocation_cost: float = 0.0
    rail_moves: int = 0
    crane_moves: int = 0

    def objective(self, kind: str) -> float:
        """The second objective: installed power (kW) or cost."""
        return self.power_kW if kind == "power" else self.cost

    @property
    def weather_hours(self) -> float:
        """Waiting for weather: expected_hours - surface_hours, h (inf where no sea state works)."""
        return self.expected_hours - self.surface_hours

    def hours_breakdown(self) -> dict:
        """The expected hours' parts, h: ``cleaning``, ``turns``, ``moves`` and ``weather``
        (waiting for the seas the job works in); they sum to ``expected_hours``."""
        return {"cleaning": self.cleaning_hours, "turns": self.turn_hours, "moves": self.move_hours,
                "weather": self.weather_hours}

    def binding(self, n: int = 2) -> list[tuple[str, float]]:
        """The ``n`` constraints nearest their limit: (name, slack) by slack, least first."""
        known = [(k, float(v)) for k, v in self.slack.items() if np.isfinite(v)]
        return sorted(known, key=lambda kv: kv[1])[:n]


def frame_turns(placements) -> np.ndarray:
    """The angle of the rotation from S's axes to each placement's frame axes (its
    ``axes_S``: the flare leans a frame out of the vertical, the hull's curve towards the bow
    or stern turns it off the ship's length), shape (n_placements,), deg."""
    R = np.array([p.axes_S for p in placements]).reshape(-1, 3, 3)
    cos = 0.5 * (np.trace(R, axis1=1, axis2=2) - 1.0)
    return np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))


def _turn_summary(placements) -> list[float]:
    turns = frame_turns(placements)
    return [float(np.median(turns)), float(turns.max())] if turns.size else [0.0, 0.0]


def _plate_inertia(mass: float, w: float, h: float) -> list[float]:
    """A uniform plate w (along x) by h (along z) in the frame's plane: principal moments, kg m^2."""
    return [mass * h * h / 12.0, mass * (w * w + h * h) / 12.0, mass * w * w / 12.0]


SIDE_MIDDLES = {"top": ([0.5, 1.0], [0.0, 0.5]), "bottom": ([0.5, 0.0], [0.0, -0.5]),
                "aft": ([0.0, 0.5], [-0.5, 0.0]), "fore": ([1.0, 0.5], [0.5, 0.0])}
"""A side's middle on the frame (x / W, z / H) and on the platform (x / w, z / h)."""
PATTERN_SIDES = {"five_top": ("top",), "six_top_bottom": ("top", "bottom"), "six_sides": ("aft", "fore")}
"""The sides whose middles the five- and six-cable patterns add cables from, in cable order."""


def cable_pattern(pattern: str, W: float, H: float, w: float, h: float, layer_m: float
                  ) -> tuple[list[list[float]], list[list[float]]]:
    """The cables' frame anchors (in C, the frame's lower aft corner at the origin) and
    platform anchors (in P) of a W x H frame and a w x h platform, m
    (:data:`~marinecdpr.scenario.design.PATTERNS`): cables 1 to 4 from the frame's upper aft,
    upper fore, lower fore and lower aft corners; crossed, cables 1 and 3 run in the plane
    y = +layer / 2 and 2 and 4 in y = -layer / 2; five and six cables, the corners uncrossed
    and cables 5 (and 6) from the middle of a frame side to the middle of the platform's same
    side (:data:`PATTERN_SIDES`: ``five_top`` the top's, ``six_top_bottom`` the top's and the
    bottom's, ``six_sides`` the aft side's and the fore side's); ``six_double_top``, cables 5
    and 6 beside 1 and 2 (the upper corners doubled), 1 and 2 in the plane y = +layer / 2 and
    5 and 6 in y = -layer / 2; ``eight_double``, every corner doubled, cables 5 to 8 beside 1
    to 4 (1 to 4 in y = +layer / 2, 5 to 8 in y = -layer / 2)."""
    frame = [[0.0, 0.0, H], [W, 0.0, H], [W, 0.0, 0.0], [0.0, 0.0, 0.0]]
    corners = [[-w / 2, 0.0, h / 2], [w / 2, 0.0, h / 2], [w / 2, 0.0, -h / 2], [-w / 2, 0.0, -h / 2]]
    if pattern in PATTERN_SIDES:
        for side in PATTERN_SIDES[pattern]:
            (fx, fz), (px, pz) = SIDE_MIDDLES[side]
            frame.append([fx * W, 0.0, fz * H])
            corners.append([px * w, 0.0, pz * h])
        return frame, corners
    doubled = {"six_double_top": 2, "eight_double": 4}.get(pattern, 0)
    if doubled:  # the first corners doubled, each pair in the planes y = +-layer / 2
        frame += [[c[0], -0.5 * layer_m, c[2]] for c in frame[:doubled]]
        corners += [[p[0], -0.5 * layer_m, p[2]] for p in corners[:doubled]]
        for k in range(doubled):
            frame[k] = [frame[k][0], 0.5 * layer_m, frame[k][2]]
            corners[k] = [corners[k][0], 0.5 * layer_m, corners[k][2]]
        return frame, corners
    if pattern == "uncrossed":
        return frame, corners
    platform = [corners[1], corners[0], corners[3], corners[2]]  # each to the opposite corner of its side
    for k, y in enumerate((0.5 * layer_m, -0.5 * layer_m, 0.5 * layer_m, -0.5 * layer_m)):
        frame[k] = [frame[k][0], y, frame[k][2]]
        platform[k] = [platform[k][0], y, platform[k][2]]
    return frame, platform


def clearance(sc: Scenario, *, step_s: float = 1.0) -> float:
    """The least distance between two cables (those not sharing an end), or between a cable
    and the platform's body, over the job's path sampled every ``step_s``, m
    (:func:`~marinecdpr.planning.interference.pose_clearances`)."""
    from marinecdpr.motion.trajectory import evaluate_trajectory
    from marinecdpr.planning.interference import pose_clearances

    t = np.arange(0.0, sc.time.duration_s + 1e-9, step_s)
    path = evaluate_trajectory(sc.trajectory, t, sc.cleaning, sc.ship)
    c = pose_clearances(sc.robot, [], path.x_PC_C, path.R_PC)
    return float(min(c.cable_cable.min(initial=np.inf), c.cable_platform.min(initial=np.inf)))


def candidate_scenario(spec: DesignSpec, template: Scenario, x: dict) -> Scenario:
    """The template with the candidate's robot and tool: frame anchors at the corners of the
    W x H frame and platform anchors at the corners of the w x h platform, the cables
    uncrossed (the paper's), crossed, or five to eight with the sides' middles or doubled
    corners (:func:`cable_pattern`), mass from ``[platform_mass]``
    and a uniform plate's inertia, T_min from ``[limits]`` and T_max the smaller of the
    rope's breaking load over its safety factor and the winch's torque over its drum's radius,
    each cable's breaking load (``robot.breaking_load_N``) the rope's;
    the panel the frame's inner rectangle inset by the platform's half size and
    ``limits.edge_m``; the tool's width, speed and overlap; the time the panel's coverage
    path takes; where the study sets them (:func:`relocation_of`), the frame's moves and the
    robots (``cleaning.surface.relocation``).

    Raises
    ------
    ScenarioError
        The candidate is not a valid scenario (its message says why).
    """
    W, H = x["frame_width_m"], x["frame_height_m"]
    w, h = x["platform_width_m"], x["platform_height_m"]
    winch = next(e for e in spec.winches if e.name == x["winch"])
    rope = next(e for e in spec.ropes if e.name == x["rope"])
    pm = spec.platform_mass
    mass = pm.base_kg + pm.per_tool_width_kg_m * x["tool_width_m"] + pm.per_area_kg_m2 * w * h
    t_max = min(rope.breaking_N / rope.safety_factor, winch.torque_N_m / winch.drum_radius_m)
    frame, platform = cable_pattern(x.get("pattern", "uncrossed"), W, H, w, h, spec.limits.layer_m)
    edge = spec.limits.edge_m
    x0, x1, z0, z1 = w / 2 + edge, W - w / 2 - edge, h / 2 + edge, H - h / 2 - edge
    if x1 - x0 <= x["tool_width_m"] or z1 - z0 <= x["tool_width_m"]:
        raise ScenarioError(f"the panel ({max(x1 - x0, 0):.3g} x {max(z1 - z0, 0):.3g} m inside the frame, less "
                            f"the platform and the edge) is no wider than the tool ({x['tool_width_m']:.3g} m)")
    robot = template.robot.model_dump(exclude_none=True)
    robot.update(mass_kg=mass, inertia_kg_m2=_plate_inertia(mass, w, h), tension_min_N=spec.limits.tension_min_N,
                 tension_max_N=t_max, breaking_load_N=rope.breaking_N,
                 cables=[{"frame_anchor_m": c, "platform_anchor_m": p} for c, p in zip(frame, platform)])
    cleaning = template.cleaning.model_dump(exclude_none=True)
    cleaning.update(panel_m=[[x0, z0], [x1, z0], [x1, z1], [x0, z1]], holes_m=[], brush_diameter_m=x["tool_width_m"],
                    overlap_m=x["overlap_share"] * x["tool_width_m"], speed_m_s=x["speed_m_s"])
    if spec.limits.stand_off_tolerance_m is not None:
        cleaning["surface"] = dict(cleaning["surface"], stand_off_tolerance_m=spec.limits.stand_off_tolerance_m)
    relocation = relocation_of(spec, x)
    if relocation is not None:
        cleaning["surface"] = dict(cleaning["surface"], relocation=relocation)
    duration = _path_time(Cleaning.model_validate(cleaning))
    data = template.model_dump(exclude_none=True)
    # a record no shorter than the job, a whole number of steps long and that number a fast
    # FFT length: the sea is then synthesised by one inverse FFT, not by direct sums
    step = float(data["time"]["step_s"])
    record = max(float(data["base_motion"]["record_s"]),
                 step * next_fast_len(int(np.ceil(duration / step - 1e-9)), real=True))
    data.update(robot=robot, cleaning=cleaning, name=f"{spec.name}_candidate",
                time=dict(data["time"], duration_s=duration),
                base_motion=dict(data["base_motion"], record_s=record))
    return validated_scenario(data)


def as_built(spec: DesignSpec, template: Scenario, e: Evaluation, plant: str | None = None) -> Scenario:
    """A candidate's scenario as it would be built and flown: :func:`candidate_scenario`'s
    robot with its rope and winches, the frame where the screen found the seas hardest
    (``e.frame_origin_m``, turned by ``e.frame_orientation_deg``):

    - the rope: its weight per metre (``robot.cable_weight_N_m``: the plan's sag), its EA
      (elastic cables, ``simulation.cables.stiffness_EA_N``) and its breaking load over its
      safety factor in ``robot.tension_max_N`` (with the winch's torque over its drum), and
      its breaking load in ``robot.breaking_load_N`` (what ``faults`` judges a cable's peak
      against);
    - the winches (``[robot.winch]``, ``simulation.cables.winch = "motor"``): the catalogue's
      torque, speed and power at the drum (``gear_ratio`` 1), its drum's radius and inertia
      (:attr:`~marinecdpr.scenario.design.Winch.inertia`): the plan keeps within what each
      winch can give, and the closed loop flies each motor's dynamics and limits;
    - on ``plant`` (default the study's, else the template's).

    The cables are elastic; they sag (``simulation.cables.model = "catenary"``: each an
    elastic catenary in the true vertical over what its motor winch's drum pays out, the
    drum under the catenary's tension at the winch end) where the span asks for it: where
    the longest span's sag at the least tension (:func:`span_sag`, the frame's diagonal at
    ``limits.tension_min_N``) exceeds :data:`SAG_SHARE` (1 %) of the span. Sagging cables fly
    on the own plant whatever ``plant`` says (MuJoCo's tendons are straight), and stay
    straight where the template takes the pose from the encoders (their kinematics knows
    straight cables only); the description says which. Below 1 % the straight elastic
    cables leave out the sag that the study's ``limits.sag_m`` bounds (ship_side's
    finalists: at most 0.94 %, its steel rope's longest feasible span).

    Raises
    ------
    ScenarioError
        The candidate is not a valid scenario.
    """
    winch = next(w for w in spec.winches if w.name == e.x["winch"])
    rope = next(r for r in spec.ropes if r.name == e.x["rope"])
    data = candidate_scenario(spec, template, e.x).model_dump(exclude_none=True)
    data["robot"].update(cable_weight_N_m=rope.weight_N_m,
                         winch={"drum_radius_m": winch.drum_radius_m, "gear_ratio": 1.0,
                                "torque_max_Nm": winch.torque_N_m, "speed_max_rad_s": winch.speed_rad_s,
                                "power_max_W": winch.power_W, "drum_inertia_kg_m2": winch.inertia})
    sim = data.setdefault("simulation", {})
    sim["plant"] = plant or spec.plant or template.simulation.plant
    span, sag = span_sag(rope.weight_N_m, e.x["frame_width_m"], e.x["frame_height_m"], spec.limits.tension_min_N)
    sags = sag > SAG_SHARE * span
    straight = sags and template.simulation.sensors.pose_from == "encoders"
    model = "catenary" if sags and not straight else "elastic"
    if model == "catenary":
        sim["plant"] = "own"
    sim["cables"] = dict(sim.get("cables", {}), model=model, stiffness_EA_N=rope.ea_N, winch="motor")
    data["ship"] = dict(data.get("ship", {}), frame_origin_m=[float(v) for v in e.frame_origin_m],
                        frame_orientation_deg=[float(v) for v in e.frame_orientation_deg])
    data["description"] = (f"{spec.name}: {e.expected_hours:.4g} expected h; winches {winch.name} "
                           f"({winch.torque_N_m:g} N m, {winch.speed_rad_s:g} rad/s, {winch.power_W:g} W, drum "
                           f"{winch.drum_radius_m:g} m), rope {rope.name} (EA {rope.ea_N:g} N, "
                           f"{rope.weight_N_m:g} N/m, breaking {rope.breaking_N:g} N over {rope.safety_factor:g}); "
                       f"{_cables_said(model, straight, sag, span)}")
    return validated_scenario(data)


def _cables_said(model: str, straight: bool, sag: float, span: float) -> str:
    """How :func:`as_built`'s description names its cables' model and why."""
    share = f"{sag * 1000:.3g} mm of sag at the least tension over the {span:.3g} m span ({100 * sag / span:.2g} %)"
    if model == "catenary":
        return f"sagging cables on the own plant: {share}"
    if straight:
        return f"straight cables though {share}: the encoders' pose knows no sag"
    return f"straight cables: {share}"


def frame_placements(template: Scenario, width_m: float, height_m: float) -> tuple[np.ndarray, np.ndarray]:
    """Where a W x H frame stands on the surface at the band's ends and middle, at its top
    and bottom (its centre inset by half the frame from the band's ends and edges, or at the
    band's middle where the frame is larger), placed as ``clean --surface`` places it: on
    the plane fitted to the surface over the frame's patch
    (:func:`~marinecdpr.geometry.surface.fit_placement`), its y axis the plane's normal out
    of the hull, its x along the ship, its centre the plane's.

    Returns
    -------
    origins : ndarray, shape (n, 3)
        C's origin (the frame's lower aft corner) in S, m, at n = 6 places (fewer where the
        band is no larger than the frame): the ship's motion differs most at the band's ends
        (pitch) and at the top of the side (roll).
    orientations : ndarray, shape (n, 3)
        C's axes in S as ``ship.frame_orientation_deg`` (roll, pitch, yaw), deg: a flared
        side leans the frame most at its top amidships, the hull's curve turns it towards
        the ends.
    """
    from marinecdpr.geometry.rotations import euler_from_matrix
    from marinecdpr.geometry.surface import fit_placement
    from marinecdpr.studies.surface import surface_function

    surface = template.cleaning.surface
    f, _ = surface_function(surface)
    (a, b), (lo, hi) = surface.stations_m, surface.heights_m
    xs = [a + width_m / 2, 0.5 * (a + b), b - width_m / 2] if b - a > width_m else [0.5 * (a + b)]
    zs = [lo + height_m / 2, hi - height_m / 2] if hi - lo > height_m else [0.5 * (lo + hi)]
    places = [(x, z) for x in xs for z in zs]
    origins, orientations = np.empty((len(places), 3)), np.empty((len(places), 3))
    for k, (x, z) in enumerate(places):
        p = fit_placement(f, (x - width_m / 2, x + width_m / 2), (z - height_m / 2, z + height_m / 2))
        R, centre = p.axes_S.copy(), p.centre_S.copy()  # the port side's (f gives |y|)
        if surface.side != "port":  # mirrored: y out of the hull is -y, x = y cross z runs aft
            centre[1] = -centre[1]
            R[1, :] = -R[1, :]
            R[:, 0] = np.cross(R[:, 1], R[:, 2])
        origins[k] = centre - R @ np.array([width_m / 2, 0.0, height_m / 2])
        orientations[k] = np.degrees(euler_from_matrix(R))  # R = Rz Ry Rx
    return origins, orientations


def screen_surface(sc: Scenario, cells: list, origins: np.ndarray, orientations: np.ndarray, *,
                   failure_hold_s: float | None = None):
    """The screen of the scenario's job with its frame at each of ``origins`` (n, 3) in S,
    turned by ``orientations`` (n, 3) deg: the job works in a sea state only where it works
    at every one of them. Returns the share that works, the works per sea state, the origin
    and orientation whose own share is the least, and why the failing sea states fail
    (:func:`~marinecdpr.studies.screen.why_fails`, each at the first placement it fails at).

    With ``failure_hold_s``, a sixth: each cable removed in turn at every placement
    (:func:`~marinecdpr.studies.screen.single_failure_cells`), a
    :class:`~marinecdpr.studies.screen.FailureScreen` holding each sea state's, pose's and
    cable's least margin over the placements (its poses the screen's, the same at each)."""
    from marinecdpr.studies.screen import (FailureScreen, at_origin, screen_cells, screen_model, single_failure_cells,
                                           why_fails)

    works = np.ones(len(cells), dtype=bool)
    reasons = [""] * len(cells)
    worst, least = 0, np.inf
    model = None
    failure = None
    for k, (origin, angles) in enumerate(zip(origins, orientations)):
        placed = sc.with_updates("ship", frame_origin_m=[float(v) for v in origin],
                                 frame_orientation_deg=[float(v) for v in angles])
        model = screen_model(placed) if model is None else at_origin(model, placed)  # the path once
        if failure_hold_s is not None:
            f = single_failure_cells(placed, cells, hold_s=failure_hold_s, model=model)
            failure = f if failure is None else FailureScreen(
                margin_N=np.minimum(failure.margin_N, f.margin_N), still_N=np.minimum(failure.still_N, f.still_N),
                pose=f.pose)
        r = screen_cells(placed, cells, model=model)
        for i in np.flatnonzero(works & ~r.works):
            sea, why = r.reasons[i].split(": ", 1)
            reasons[i] = (f"{sea}, the frame at {'(' + ', '.join(f'{v:.3g}' for v in origin) + ')'} m in S "
                          f"(placement {k + 1} of {len(origins)}): {why}")
        works &= r.works
        if r.share < least:
            worst, least = k, r.share
    p = np.array([c.probability for c in cells], dtype=float)
    out = (float(p[works].sum() / p.sum()) if p.sum() > 0 else 0.0, works, origins[worst], orientations[worst],
           why_fails(cells, works, reasons))
    return out if failure_hold_s is None else out + (failure,)


def evaluate(spec: DesignSpec, template: Scenario, x: dict, cells: list) -> Evaluation:
    """Judge one candidate (the module's objective and constraints).

    Parameters
    ----------
    x : dict
        The continuous variables by name, "winch" and "rope" by catalogue name, "pattern".
    cells : list of Cell
        The study's sea states (:func:`study_cells`).
    """
    from marinecdpr.studies.surface import surface_job

    winch = next(e for e in spec.winches if e.name == x["winch"])
    rope = next(e for e in spec.ropes if e.name == x["rope"])
    W, H = x["frame_width_m"], x["frame_height_m"]
    span, sag = span_sag(rope.weight_N_m, W, H, spec.limits.tension_min_N)
    n_cables = float(cable_count(x))
    power_kW = n_cables * winch.power_W / 1000.0
    cost = n_cables * (winch.cost + rope.cost_per_m * span)
    robots = _robots(template, x)
    if robots != 1:  # each robot its own winches and ropes
        power_kW, cost = robots * power_kW, robots * cost
    nan = float("nan")
    try:
        sc = candidate_scenario(spec, template, x)
    except ScenarioError as exc:
        return Evaluation(x=dict(x), feasible=False, reason=str(exc), placements=0, surface_hours=nan, sea_share=0.0,
                          expected_hours=float("inf"), power_kW=power_kW, cost=cost, tension_max_N=nan, mass_kg=nan,
                          margins={k: nan for k in CONSTRAINTS} | {"panel_m": -1.0})
    robot = sc.robot
    t_min, t_max = float(robot.tension_min[0]), float(robot.tension_max[0])
    try:  # no patch limit: a candidate's panel is the study's to choose (its template's band is checked at load)
        job = surface_job(sc, move_time_s=spec.move_time_s, digits=2, max_patches=None)
    except ScenarioError as exc:  # no patch flat enough for its panel: no hours, infeasible
        return Evaluation(x=dict(x), feasible=False, reason=str(exc), placements=0, surface_hours=nan, sea_share=0.0,
                          expected_hours=float("inf"), power_kW=power_kW, cost=cost, tension_max_N=t_max,
                          mass_kg=robot.mass_kg, margins={k: nan for k in CONSTRAINTS})
    safety = spec.constraints
    screened = screen_surface(sc, cells, *frame_placements(template, W, H),
                              failure_hold_s=safety.failure_hold_s if safety.single_cable_failure else None)
    share, works, worst, turned, why = screened[:5]
    panel = np.asarray(sc.cleaning.panel_m)
    margins = {
        "sea_share": share - spec.targets.sea_share,
        "winch_speed_m_s": winch.speed_rad_s * winch.drum_radius_m - x["speed_m_s"],
        "winch_power_W": winch.power_W - t_max * x["speed_m_s"],
        "sag_m": spec.limits.sag_m - sag,
        "stretch_m": spec.limits.stretch_m - (t_max - t_min) * span / rope.ea_N,
        "panel_m": float(min(np.ptp(panel[:, 0]), np.ptp(panel[:, 1]))) - x["tool_width_m"],
        "clearance_m": clearance(sc) - rope.diameter_m - spec.limits.clearance_m,
    }
    capacity = {"sea_share": share, "winch_speed_m_s": winch.speed_rad_s * winch.drum_radius_m,
                "winch_power_W": winch.power_W, "sag_m": spec.limits.sag_m, "stretch_m": spec.limits.stretch_m,
                "panel_m": float(min(np.ptp(panel[:, 0]), np.ptp(panel[:, 1]))),
                "clearance_m": margins["clearance_m"] + rope.diameter_m + spec.limits.clearance_m}
    rail = candidate_rail(spec, x)
    said = {}
    if rail is not None:  # the carriage's accelerations: a load the cables hold
        held = rail_held_acceleration(sc, rail, float(W), [c for c, ok in zip(cells, works) if ok], worst, turned)
        margins[RAIL_CONSTRAINT] = held - rail.accel_m_s2
        capacity[RAIL_CONSTRAINT] = held
        said[RAIL_CONSTRAINT] = (f" (the cables hold the platform at the panel's centre while the carriage "
                                 f"accelerates along the rail at +-{held:.3g} m/s^2 at most in the seas the job "
                                 f"works in, not at the rail's accel_m_s2 {rail.accel_m_s2:.3g} m/s^2)")
    if safety.single_cable_failure:  # each cable removed in turn, in the seas the job works in
        least, cell, pose, cable = screened[5].least(works)
        at, cells_at, moving = screened[5].pose[pose], cells, ""
        if rail is not None:  # and while the carriage moves the frame, the platform held at the panel's centre
            working = [c for c, ok in zip(cells, works) if ok]
            moved = rail_single_failure(sc, rail, float(W), working, worst, turned, safety.failure_hold_s)
            if moved is not None:
                m, c_m, p_m, i_m = moved.least(np.ones(len(working), dtype=bool) if working else None)
                if m < least:
                    least, cell, cable, at, cells_at = m, c_m, i_m, moved.pose[p_m], working
                    moving = f" while the carriage accelerates at +-{rail.accel_m_s2:.3g} m/s^2 along the rail"
        margins[FAILURE_CONSTRAINT] = least
        capacity[FAILURE_CONSTRAINT] = float(np.min(robot.tension_max - robot.tension_min)) / 2.0
        sea = cells_at[cell] if cell >= 0 else None
        where = ("on a ship at rest (no sea state works)" if sea is None else
                 f"in Hs {sea.hs:g} m, Tp {sea.tp:g} s, heading {sea.heading_deg:g} deg")
        said[FAILURE_CONSTRAINT] = (f" (cable {cable + 1} of {robot.n_cables} "
                                    f"gone, the others cannot hold the platform at "
                                    + "(" + ", ".join(f"{v:.2f}" for v in at[[0, 2]]) + f") m in C{moving} "
                                    + f"{where}"
                                    + (": they lose rank)" if not np.isfinite(least) else ")"))
    short = [k for k, v in margins.items() if not v >= 0.0]
    expected = job.hours / share if share > 0 else float("inf")
    moved = _relocation_figures(job)
    cost = cost + moved["relocation_cost"] if moved else cost
    return Evaluation(x=dict(x), feasible=not short,
                      reason=", ".join(f"{k} short by {-margins[k]:.3g}{said.get(k, '')}" for k in short),
                      placements=len(job.placements), surface_hours=job.hours, sea_share=share, **moved,
                      expected_hours=expected, power_kW=power_kW, cost=cost, tension_max_N=t_max,
                      mass_kg=robot.mass_kg, margins=margins, frame_origin_m=[float(v) for v in worst],
                      frame_orientation_deg=[float(v) for v in turned], frame_turn_deg=_turn_summary(job.placements),
                      sea_reason=why, **_breakdown(job), slack=_slack(margins, capacity))


def rail_held_acceleration(sc: Scenario, rail, width_m: float, cells: list, origin_S, orientation_deg) -> float:
    """The largest acceleration of a candidate's carriage (m/s^2) with which its cables hold
    the platform at the panel's centre (where :func:`fly_rail_move` holds it), the frame at
    ``origin_S`` turned by ``orientation_deg`` (the screen's hardest placement), the rail
    along the frame's x axis laid level (as :func:`~marinecdpr.studies.relocation.rail_move_scenario`
    lays it), in every one of ``cells`` (the sea states the candidate works in; none: a ship
    at rest), the sea's extreme taken over one move of a frame's width at the rail's limits
    (:func:`~marinecdpr.studies.screen.held_acceleration`)."""
    from marinecdpr.motion.rail import scurve_move
    from marinecdpr.studies.relocation import level_rail_S
    from marinecdpr.studies.screen import held_acceleration

    level = level_rail_S(orientation_deg)
    if level is None:  # no level rail along a frame standing on its side
        return float("-inf")
    hold = rail_hold_C(sc)
    placed = sc.with_updates("ship", frame_origin_m=[float(v) for v in origin_S],
                             frame_orientation_deg=[float(v) for v in orientation_deg])
    move_s = float(scurve_move(width_m, rail.speed_m_s, rail.accel_m_s2, rail.jerk_m_s3).duration_s)
    held = held_acceleration(placed, cells, level, hold_C=hold, duration_s=move_s)
    return float(held.cells_m_s2.min()) if len(cells) else held.still_m_s2


def rail_single_failure(sc: Scenario, rail, width_m: float, cells: list, origin_S, orientation_deg, hold_s: float):
    """Each cable removed in turn while a candidate's carriage moves its frame one frame's
    width along the rail (:func:`rail_held_acceleration`'s move, the platform held at the
    panel's centre, the carriage accelerating at +- its ``accel_m_s2``), in each of ``cells``
    (the sea states the candidate works in), the sea's extreme over ``hold_s``
    (:func:`~marinecdpr.studies.screen.held_single_failure`); None where no level rail runs
    along the frame (the rail's own margin then fails the candidate)."""
    from marinecdpr.motion.rail import scurve_move
    from marinecdpr.studies.relocation import level_rail_S
    from marinecdpr.studies.screen import held_single_failure

    level = level_rail_S(orientation_deg)
    if level is None:
        return None
    placed = sc.with_updates("ship", frame_origin_m=[float(v) for v in origin_S],
                             frame_orientation_deg=[float(v) for v in orientation_deg])
    move_s = float(scurve_move(width_m, rail.speed_m_s, rail.accel_m_s2, rail.jerk_m_s3).duration_s)
    return held_single_failure(placed, cells, level, hold_C=rail_hold_C(sc), accel_m_s2=rail.accel_m_s2,
                               duration_s=move_s, hold_s=hold_s)


def _breakdown(job) -> dict:
    """A surface job's hours in parts (:meth:`Evaluation.hours_breakdown`): with robots, the
    slowest robot's."""
    if job.moves is not None:
        clean, turns, moves = job.parts_s()
        return {"cleaning_hours": clean / 3600.0, "turn_hours": turns / 3600.0, "move_hours": moves / 3600.0}
    turns = float(job.turn_s.sum()) / 3600.0
    return {"cleaning_hours": float(job.job_s.sum()) / 3600.0 - turns, "turn_hours": turns,
            "move_hours": max(len(job.placements) - 1, 0) * job.move_time_s / 3600.0}


def _relocation_figures(job) -> dict:
    """A surface job's relocation in :class:`Evaluation`'s fields (none without
    ``[cleaning.surface.relocation]``)."""
    if job.moves is None:
        return {}
    return {"relocation_cost": job.relocation_cost.total, "rail_moves": job.moves.count("rail"),
            "crane_moves": job.moves.count("crane")}


def relocation_of(spec: DesignSpec, x: dict) -> dict | None:
    """The candidate's ``cleaning.surface.relocation``: the study's ``[relocation]`` with the
    candidate's ``relocation`` (mode) and ``robots``; None where the study sets neither (the
    template's own, if any, stays)."""
    if not spec.relocates:
        return None
    base = spec.relocation.model_dump(exclude_none=True) if spec.relocation is not None else {}
    mode = x.get("relocation", spec.choices("relocation")[0])
    if mode == "rail" and any(k in x for k in RAIL_VARIABLES):  # the candidate's carriage
        base["rail"] = base["rail"] | {field: float(x[k]) for k, field in RAIL_VARIABLES.items() if k in x}
    return base | {"mode": mode, "robots": int(x.get("robots", spec.choices("robots")[0]))}


def candidate_rail(spec: DesignSpec, x: dict):
    """The carriage's limits of a candidate moved by rail (``[relocation.rail]`` with the
    candidate's ``rail_speed_m_s``, ``rail_accel_m_s2``, ``rail_jerk_m_s3``), a
    :class:`~marinecdpr.scenario.relocation.RailMoves`; None for a candidate moved otherwise."""
    from marinecdpr.scenario.relocation import Relocation

    relocation = relocation_of(spec, x)
    if relocation is None or relocation["mode"] != "rail":
        return None
    return Relocation.model_validate(relocation).rail


def _robots(template: Scenario, x: dict) -> int:
    """How many robots the candidate puts on the side: its ``robots``, else the template's."""
    if "robots" in x:
        return int(x["robots"])
    relocation = template.cleaning.surface.relocation
    return relocation.robots if relocation is not None else 1


def _slack(margins: dict, capacity: dict) -> dict:
    """Each margin over its capacity (:data:`CAPACITIES`); -inf where nothing is available."""
    out = {}
    for k, m in margins.items():
        c = capacity.get(k, float("nan"))
        out[k] = float(m / c) if c > 0 and np.isfinite(m) else (float("-inf") if m < 0 else float("nan"))
    return out


def pareto_mask(f: np.ndarray) -> np.ndarray:
    """Which rows of the objectives f (n, m) (to minimise) no other row dominates."""
    f = np.asarray(f, dtype=float)
    keep = np.ones(len(f), dtype=bool)
    for i in range(len(f)):
        dominated = np.all(f <= f[i], axis=1) & np.any(f < f[i], axis=1)
        keep[i] = not dominated.any()
    return keep


@dataclass(frozen=True)
class DesignStudy:
    """A search's result.

    Attributes
    ----------
    spec : DesignSpec
    evaluations : list of Evaluation
        Every candidate, in the order evaluated.
    generation : ndarray of int, shape (n,)
        Each one's generation.
    front : list of int
        Indices of the feasible candidates no other feasible one beats on both objectives,
        by expected hours.
    baseline : Evaluation
        The template's own robot, judged the same way.
    """

    spec: DesignSpec
    evaluations: list
    generation: np.ndarray
    front: list
    baseline: Evaluation

    @property
    def feasible(self) -> int:
        """How many candidates are feasible."""
        return int(sum(e.feasible for e in self.evaluations))

    @property
    def best(self) -> Evaluation | None:
        """The front's first (the fewest expected hours), or None if no candidate is feasible."""
        return self.evaluations[self.front[0]] if self.front else None

    @property
    def target_met(self) -> bool:
        """Whether the best design's expected hours are within the target's."""
        best = self.best
        return bool(best is not None and best.expected_hours <= self.spec.targets.hours)


TEMPLATE_OWN = "the template's"
"""The baseline's winch and rope: its own (its T_max), not the catalogue's."""


def template_x(spec: DesignSpec, template: Scenario) -> dict:
    """The template's own robot's variables (its frame, platform, tool; its own winches and
    rope, :data:`TEMPLATE_OWN`)."""
    c = template.robot.frame_anchors
    p = template.robot.platform_anchors
    cl = template.cleaning
    return {"frame_width_m": float(np.ptp(c[:, 0])), "frame_height_m": float(np.ptp(c[:, 2])),
            "platform_width_m": float(np.ptp(p[:, 0])), "platform_height_m": float(np.ptp(p[:, 2])),
            "tool_width_m": float(cl.brush_diameter_m), "speed_m_s": float(cl.speed_m_s),
            "overlap_share": float(cl.overlap_m / cl.brush_diameter_m),
            "winch": TEMPLATE_OWN, "rope": TEMPLATE_OWN, "pattern": TEMPLATE_OWN} | (
        {"relocation": spec.choices("relocation")[0], "robots": spec.choices("robots")[0]} if spec.relocates else {})


def baseline(spec: DesignSpec, template: Scenario, cells: list) -> Evaluation:
    """The template's robot as it is (its own mass, limits and panel), judged as a candidate is."""
    from marinecdpr.studies.surface import surface_job

    x = template_x(spec, template)
    relocation = relocation_of(spec, x)
    if relocation is not None:  # judged with the study's moves and robots, as a candidate is
        template = template.with_updates("cleaning.surface", relocation=relocation)
    job = surface_job(template, move_time_s=spec.move_time_s, digits=2)
    run = template.with_changes(time=dict(template.time.model_dump(), duration_s=_path_time(template.cleaning)))
    share, _, worst, turned, why = screen_surface(run, cells, *frame_placements(template, x["frame_width_m"],
                                                                           x["frame_height_m"]))
    return Evaluation(x=x, feasible=share >= spec.targets.sea_share, reason="", placements=len(job.placements),
                      surface_hours=job.hours, sea_share=share,
                      expected_hours=job.hours / share if share > 0 else float("inf"),
                      power_kW=float("nan"), cost=float("nan"),
                      tension_max_N=float(template.robot.tension_max.max()), mass_kg=template.robot.mass_kg,
                      margins={"sea_share": share - spec.targets.sea_share}, frame_origin_m=[float(v) for v in worst],
                      frame_orientation_deg=[float(v) for v in turned], frame_turn_deg=_turn_summary(job.placements),
                      sea_reason=why, **_breakdown(job), slack=_slack({"sea_share": share - spec.targets.sea_share},
                                                      {"sea_share": share}), **_relocation_figures(job))


def _path_time(cleaning: Cleaning) -> float:
    """How long the coverage path of a ``[cleaning]`` takes, s."""
    from marinecdpr.motion.trajectory import cleaning_path

    return float(cleaning_path(cleaning).duration_s)


def study_key(spec: DesignSpec, template: Scenario, cells: list) -> str:
    """What a journal's candidates were judged under, by content: the study, its template
    with each file it reads (its RAOs, its surface's mesh) by the SHA-256 of its bytes (not
    by its path: a copy of the study's folder resumes; a file changed since does not), and
    its sea states (the scatter diagram's cells at each heading); not what only the
    finalists' flights read (``finalists``, ``plant``, ``[sea] verify`` and
    ``unflown_share``). A study whose candidates
    may move by rail keys its constraints too (since the carriage's ``rail_accel_m_s2``): a
    journal judged without that margin does not resume."""
    import hashlib
    import json

    def by_content(value):
        if isinstance(value, dict):
            return {k: by_content(v) for k, v in value.items()}
        if isinstance(value, (list, tuple)):
            return [by_content(v) for v in value]
        if isinstance(value, str) and Path(value).is_absolute() and Path(value).is_file():
            digest = hashlib.sha256()
            with open(value, "rb") as f:
                for block in iter(lambda: f.read(2**20), b""):
                    digest.update(block)
            return f"sha256:{digest.hexdigest()}"
        return value

    study, scenario = spec.model_dump(mode="json"), template.model_dump(mode="json")
    for key in ("finalists", "plant"):  # the finalists' flights judge no candidate
        study.pop(key, None)
    for key in ("verify", "unflown_share"):
        study["sea"].pop(key, None)
    # the relocation's keys where unset, as before they were known: an older journal still resumes
    for node, key in ((study, "relocation"), (study["variables"], "relocation"), (study["variables"], "robots"),
                      (((scenario.get("cleaning") or {}).get("surface") or {}), "relocation")):
        if key in node and node[key] is None:
            del node[key]
    safety = study.pop("constraints")  # [constraints]: only where it changes the candidates, as before it was known
    if spec.constraints.single_cable_failure:
        study["safety"] = safety
    if not scenario.get("faults"):  # no [[faults]]: the key as before faults were known
        scenario.pop("faults", None)
    for node in (scenario["robot"], *scenario["robot"]["cables"]):  # no breaking load: as before it was known
        if node.get("breaking_load_N", 0) is None:
            del node["breaking_load_N"]
    watch, shipped = scenario["simulation"]["control"]["safety"], Safety.model_fields
    for key in ("current_fraction", "current_delay_s"):  # the motors' current watch as shipped: as before it was
        if watch.get(key) == shipped[key].default:
            del watch[key]
    noise = scenario["simulation"]["noise"]
    if noise.get("motor_torque_N_m") == 0.0:  # no noise on the motors' currents: as before it was known
        del noise["motor_torque_N_m"]
    for key in RAIL_VARIABLES:  # the carriage's limits as variables, where unset: as before they were known
        if study["variables"].get(key, 0) is None:
            del study["variables"][key]
    if "rail" in spec.choices("relocation"):  # rail candidates judged by the carriage's margin since: a new key
        study["constraints"] = list(study_constraints(spec))
    for node in (study.get("relocation"), ((scenario.get("cleaning") or {}).get("surface") or {}).get("relocation")):
        rail = (node or {}).get("rail") or {}
        if rail.get("drive_cost_per_kW") == 0.0:
            del rail["drive_cost_per_kW"]
    # a cell without a wind of its own (the scatter's columns): the key as before cells could have one
    cells_key = [{k: v for k, v in c.__dict__.items() if not (k.startswith("wind_") and v is None)} for c in cells]
    text = json.dumps([study, by_content(scenario), cells_key], sort_keys=True, default=repr)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def _candidate_key(x: dict) -> str:
    return repr(sorted(x.items()))


def _to_json(e: Evaluation) -> dict:
    def num(v):
        return v if not isinstance(v, float) or np.isfinite(v) else repr(v)  # inf, nan as text

    return {k: ({m: num(v) for m, v in val.items()} if isinstance(val, dict) else num(val))
            for k, val in e.__dict__.items()}


_NON_FINITE = {"inf": float("inf"), "-inf": float("-inf"), "nan": float("nan")}


def _number(key: str, v) -> float:
    """A journal's number: a JSON number, or "inf", "-inf", "nan" as :func:`_to_json` writes them."""
    if isinstance(v, str) and v in _NON_FINITE:
        return _NON_FINITE[v]
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        raise ValueError(f"{key}: expected a number, got {v!r:.40}")
    return float(v) if isinstance(v, float) else v


def _from_json(d) -> Evaluation:
    """An :class:`Evaluation` from a journal's line (parsed), every field checked
    (ValueError naming the first that is wrong)."""
    from dataclasses import MISSING, fields

    if not isinstance(d, dict):
        raise ValueError(f"expected a candidate (an object), got {type(d).__name__}")
    known = {f.name: f for f in fields(Evaluation)}
    for k in d:
        if k not in known:
            raise ValueError(f"unknown field {k!r:.40}")
    for name, f in known.items():
        if name not in d and f.default is MISSING and f.default_factory is MISSING:
            raise ValueError(f"{name}: missing")
    x = d["x"]
    if not isinstance(x, dict) or set(CONTINUOUS) - set(x):
        raise ValueError("x: expected the candidate's variables")
    out = {"x": {k: (_number(f"x.{k}", v) if k in CONTINUOUS or k in RAIL_VARIABLES else v) for k, v in x.items()}}
    for k in ("winch", "rope", "pattern", "relocation"):
        if k in x and not isinstance(x[k], str):
            raise ValueError(f"x.{k}: expected a name, got {x[k]!r:.40}")
    if "robots" in x and (isinstance(x["robots"], bool) or not isinstance(x["robots"], int) or x["robots"] < 1):
        raise ValueError(f"x.robots: expected a count, got {x['robots']!r:.40}")
    if not isinstance(d["feasible"], bool):
        raise ValueError(f"feasible: expected true or false, got {d['feasible']!r:.40}")
    if not isinstance(d["reason"], str):
        raise ValueError(f"reason: expected text, got {d['reason']!r:.40}")
    if isinstance(d["placements"], bool) or not isinstance(d["placements"], int) or d["placements"] < 0:
        raise ValueError(f"placements: expected a count, got {d['placements']!r:.40}")
    out |= {k: d[k] for k in ("feasible", "reason", "placements")}
    if not isinstance(d.get("sea_reason", ""), str):
        raise ValueError(f"sea_reason: expected text, got {d['sea_reason']!r:.40}")
    out["sea_reason"] = d.get("sea_reason", "")
    for k in ("surface_hours", "sea_share", "expected_hours", "power_kW", "cost", "tension_max_N", "mass_kg"):
        out[k] = _number(k, d[k])
    for k in ("cleaning_hours", "turn_hours", "move_hours", "relocation_cost"):
        if k in d:
            out[k] = _number(k, d[k])
    for k in ("rail_moves", "crane_moves"):
        if k in d:
            if isinstance(d[k], bool) or not isinstance(d[k], int) or d[k] < 0:
                raise ValueError(f"{k}: expected a count, got {d[k]!r:.40}")
            out[k] = d[k]
    for k in ("margins", "slack"):
        if k in d:
            if not isinstance(d[k], dict):
                raise ValueError(f"{k}: expected an object")
            out[k] = {str(m): _number(f"{k}.{m}", v) for m, v in d[k].items()}
    for k in ("frame_origin_m", "frame_orientation_deg", "frame_turn_deg"):
        if k in d:
            if not isinstance(d[k], list):
                raise ValueError(f"{k}: expected a list of numbers")
            out[k] = [_number(k, v) for v in d[k]]
    return Evaluation(**out)


def _json_line(line: str):
    """A journal line's JSON: strict (no NaN or Infinity: the journal writes them as text)."""
    import json

    def constant(name: str):
        raise ValueError(f"{name} is not a number the journal writes")

    try:
        return json.loads(line, parse_constant=constant)
    except RecursionError:
        raise ValueError("nested too deeply") from None


def read_journal(path: Path, key: str) -> dict:
    """The candidates a journal holds, by their variables (a cut last line, as a Ctrl-C may
    leave, is skipped).

    Raises
    ------
    ScenarioError
        No journal there, one that is not a journal (not UTF-8 text, a first line without its
        study's key, a line that is no candidate: the line named), or one of another study
        (or of this study's file, template or seas since changed).
    """
    path = Path(path)
    again = "run without --resume to start anew"
    if not path.is_file():
        raise ScenarioError(f"--resume: no {path.name} in {path.parent} to resume")
    try:
        lines = path.read_text(encoding="utf-8").splitlines()
    except UnicodeDecodeError:
        raise ScenarioError(f"--resume: {path} is not a journal of candidates (not UTF-8 text): {again}") from None
    except OSError as exc:
        raise ScenarioError(f"--resume: {path} cannot be read ({exc.strerror or exc})") from None
    try:
        head = _json_line(lines[0]) if lines else None
    except ValueError:
        head = None
    if not isinstance(head, dict) or not isinstance(head.get("study"), str):
        raise ScenarioError(f"--resume: {path} line 1 is not a journal's first line (its study's key): {again}")
    if head["study"] != key:
        raise ScenarioError(f"--resume: {path} is of another study, or this study's file, template, the files they "
                            f"read or the seas changed since: {again}")
    known = {}
    for i, line in enumerate(lines[1:], start=2):
        try:
            e = _from_json(_json_line(line))
        except ValueError as exc:
            if i == len(lines) and not line.endswith("}"):  # a cut last line: the candidate is judged again
                continue
            raise ScenarioError(f"--resume: {path} line {i} is no candidate ({exc}): {again}") from None
        known[_candidate_key(e.x)] = e
    return known


def _judge(shared: tuple, x: dict) -> Evaluation:
    """:func:`evaluate` of one candidate, with the study's ``(spec, template, cells)``
    shared by every candidate (what an executor sends each worker once)."""
    spec, template, cells = shared
    return evaluate(spec, template, x, cells)


def search(spec: DesignSpec, template: Scenario, cells: list, *,
           progress: Callable[[int, int, float], None] | None = None, journal: Path | None = None,
           resume: bool = False, executor: Executor | None = None) -> DesignStudy:
    """NSGA-II (pymoo) over the spec's variables: ``population`` candidates a generation for
    ``generations`` generations from ``seed`` (the same seed, the same candidates); the held
    variables stay at their value, the winch and rope are choices.

    Parameters
    ----------
    progress : callable(done, total, best_hours), optional
        Called after each candidate with the best feasible expected hours so far.
    journal : Path, optional
        A file each candidate is added to as a line of JSON as soon as it is judged (so an
        interrupted search keeps them); started anew unless ``resume``.
    resume : bool
        Take the journal's candidates instead of judging them again: the same seed asks for
        the same candidates, so the search goes on where it stopped.
    executor : Executor, optional
        What judges a generation's candidates (:class:`~marinecdpr.studies.executor.Executor`;
        default serial: one by one, each counted as it is judged); one session (one local
        cluster) for the whole search. The same candidates and results whichever runs.
    """
    import json

    from pymoo.algorithms.moo.nsga2 import RankAndCrowding
    from pymoo.core.mixed import MixedVariableGA
    from pymoo.core.problem import Problem
    from pymoo.core.variable import Choice, Real
    from pymoo.optimize import minimize

    executor = executor or Executor.serial()
    key = study_key(spec, template, cells)
    known = read_journal(journal, key) if resume and journal is not None else {}
    sink = None
    if journal is not None:
        sink = open(journal, "a" if resume else "w", encoding="utf-8")
        if not resume:
            sink.write(json.dumps({"study": key}) + "\n")
            sink.flush()
    bounds = spec.bounds()
    constraints = study_constraints(spec)
    free = {k: Real(bounds=b) for k, b in bounds.items() if b[0] < b[1]}
    choices = {k: [e.name for e in spec.choices(k)] for k in ("winch", "rope")}
    choices["pattern"] = spec.choices("pattern")
    if spec.relocates:
        choices["relocation"] = spec.choices("relocation")
        choices["robots"] = spec.choices("robots")
    for k, names in choices.items():
        if len(names) > 1:
            free[k] = Choice(options=names)
    evaluations: list[Evaluation] = []
    generations: list[int] = []
    total = spec.population * spec.generations
    best = [float("inf")]

    def full(xd: dict) -> dict:
        x = {k: (float(xd[k]) if k in xd else bounds[k][0]) for k in bounds}
        for k, names in choices.items():
            x[k] = (int if k == "robots" else str)(xd[k]) if k in xd else names[0]
        return x

    def judged(x: dict, e: Evaluation) -> None:
        known[_candidate_key(x)] = e
        if sink is not None:  # at once: an interrupted search keeps it
            sink.write(json.dumps(_to_json(e)) + "\n")
            sink.flush()

    def taken(e: Evaluation) -> None:
        evaluations.append(e)
        generations.append((len(evaluations) - 1) // spec.population)
        if e.feasible:
            best[0] = min(best[0], e.expected_hours)
        if progress is not None:
            progress(len(evaluations), total, best[0])

    shared = (spec, template, cells)

    def judge_all(xs: list[dict], session) -> None:
        """Judge the candidates not yet known (each once), in the session, each kept in the
        journal as it is judged."""
        todo = list({_candidate_key(x): x for x in xs if _candidate_key(x) not in known}.values())
        session.map(_judge, shared, todo, each=lambda k, e: judged(todo[k], e))

    class Study(Problem):
        def __init__(self, session):
            super().__init__(vars=free, n_obj=2, n_ieq_constr=len(constraints))
            self.session = session

        def _evaluate(self, X, out, *args, **kwargs):
            xs = [full(xd) for xd in X]
            if executor.kind == "serial":  # one by one, each counted as it is judged
                for x in xs:
                    judge_all([x], self.session)
                    taken(known[_candidate_key(x)])
            else:
                judge_all(xs, self.session)
                for x in xs:
                    taken(known[_candidate_key(x)])
            es = [known[_candidate_key(x)] for x in xs]
            out["F"] = np.array([[e.expected_hours if np.isfinite(e.expected_hours) else 1e9,
                                  e.objective(spec.objective)] for e in es])
            # a margin a candidate does not have (the rail's, moved by crane) binds nothing
            out["G"] = np.array([[-(m if np.isfinite(m) else -1e9) for m in (e.margins.get(k, 0.0) for k in constraints)]
                                 for e in es])

    try:
        with executor.session() as session:
            if not free:  # nothing to search: the one candidate
                Study(session)._evaluate(np.array([{}], dtype=object), {})
            else:
                algorithm = MixedVariableGA(pop_size=spec.population, survival=RankAndCrowding())
                minimize(Study(session), algorithm, termination=("n_evals", total), seed=spec.seed, verbose=False)
    finally:
        if sink is not None:
            sink.close()
    ok = [i for i, e in enumerate(evaluations) if e.feasible and np.isfinite(e.expected_hours)]
    front = []
    if ok:
        f = np.array([[evaluations[i].expected_hours, evaluations[i].objective(spec.objective)] for i in ok])
        front = sorted((ok[j] for j in np.flatnonzero(pareto_mask(f))), key=lambda i: evaluations[i].expected_hours)
    return DesignStudy(spec=spec, evaluations=evaluations, generation=np.array(generations), front=front,
                       baseline=baseline(spec, template, cells))


@dataclass(frozen=True)
class Verification:
    """A finalist flown through the cleaning job in every sea state of the study, closed loop
    on the prototype (:func:`~marinecdpr.studies.cleaning.cleaning_seas`), beside the screen.

    Attributes
    ----------
    index : int
        The candidate's index in the study.
    rank : int
        Its place among the finalists (1: the fewest expected hours by the screen).
    surface_hours : float
    screen_share, td_share : float
        The probability that the job works, by the screen and in the time domain.
    screen_expected_hours, td_expected_hours : float
        surface_hours over each share (inf where it works in no sea state).
    agree : int
        Sea states where the two verdicts agree.
    screen_works_td_fails, screen_fails_td_works : int
        The two kinds of disagreement (a conservative screen has none of the first).
    reasons : list of str
        Why the time domain failed, per failing sea state ("Hs, Tp, heading: why").
    plant : str
        The plant flown ("mujoco" or "own").
    screen_reasons : list of str
        Why the screen failed, per sea state it fails (:attr:`~marinecdpr.studies.screen.ScreenResult.reasons`).
    """

    index: int
    rank: int
    surface_hours: float
    screen_share: float
    td_share: float
    screen_expected_hours: float
    td_expected_hours: float
    agree: int
    screen_works_td_fails: int
    screen_fails_td_works: int
    reasons: list
    plant: str = ""
    screen_reasons: list = field(default_factory=list)
    flown: int = 0
    """How many sea states were judged in the time domain (all of them, or with ``[sea] verify =
    "boundary"`` those about each column's boundary; the rest taken as the column's boundary
    says)."""
    planned_only: int = 0
    """Of those, how many failed in their plan and were not flown (``verify = "boundary"``:
    :func:`~marinecdpr.studies.cleaning.evaluate_cleaning_cell`'s ``plan_first``)."""
    unjudged: int = 0
    """Sea states left unjudged (``[sea] unflown_share``: the columns of least probability):
    counted as failing in ``td_share``, and in neither ``agree`` nor the disagreements."""
    unjudged_share: float = 0.0
    """Their probability: the time domain's share is at most ``td_share`` plus it."""
    rail_move: "RailMoveCheck | None" = None
    """A finalist on a rail: its frame carried along the rail in the time domain
    (:func:`fly_rail_move`); None for other moves, or where no sea state works."""


@dataclass(frozen=True)
class RailMoveCheck:
    """A rail finalist's frame carried one frame's width along its rail, the platform held and
    the tool off the hull, closed loop on the prototype as built, in the highest sea the time
    domain passed (its record's seed the cleaning job's there).

    Attributes
    ----------
    hs, tp, heading_deg : float
        The sea state, m, s, deg.
    distance_m, move_s : float
        The move along the rail, m, and its double-S time at the rail's limits, s.
    tension_min_N, tension_max_N : float
        The cables' least and largest tension over the run, N (nan where it did not fly).
    excursion_m : float
        The platform's largest distance from where it is held, m.
    drive_force_N : float
        The carriage drive's largest force along the rail (the plan's), N.
    works : bool
    reason : str
        Why not, or "".
    """

    hs: float
    tp: float
    heading_deg: float
    distance_m: float
    move_s: float
    tension_min_N: float
    tension_max_N: float
    excursion_m: float
    drive_force_N: float
    works: bool
    reason: str = ""


def rail_hold_C(sc: Scenario) -> list[float]:
    """Where the platform is held while the carriage moves the frame along its rail: the
    cleaning panel's centre (its corners' mean) in C, m."""
    panel = np.asarray(sc.cleaning.panel_m, dtype=float)
    return [float(panel[:, 0].mean()), 0.0, float(panel[:, 1].mean())]


def fly_rail_move(spec: DesignSpec, sc: Scenario, e: "Evaluation", cell) -> RailMoveCheck:
    """Fly a rail finalist's move (:class:`RailMoveCheck`): ``sc`` its scenario as built
    (:func:`as_built`), ``cell`` the sea state."""
    from marinecdpr.errors import InfeasibleError, SimulationDivergedError
    from marinecdpr.motion.rail import scurve_move
    from marinecdpr.planning.carriage import drive_force
    from marinecdpr.planning.planner import plan
    from marinecdpr.prototype.simulation import simulate
    from marinecdpr.studies.operability import cell_scenario
    from marinecdpr.studies.prototype_runs import bypassed_text, controller_verdict
    from marinecdpr.studies.relocation import rail_move_scenario

    rail = candidate_rail(spec, e.x)
    distance = float(e.x["frame_width_m"])
    hold = rail_hold_C(sc)
    move = rail_move_scenario(sc, rail, distance, hold_C=hold, mass_kg=spec.relocation.frame_mass_kg)
    move = cell_scenario(move, cell, move.time.duration_s, move.time.step_s)
    nan = float("nan")
    fig = dict(hs=cell.hs, tp=cell.tp, heading_deg=cell.heading_deg, distance_m=distance,
               move_s=float(scurve_move(distance, rail.speed_m_s, rail.accel_m_s2, rail.jerk_m_s3).duration_s))
    try:
        p = plan(move)
        res = simulate(move, run="closed_loop", reference=p)
    except InfeasibleError:
        return RailMoveCheck(**fig, tension_min_N=nan, tension_max_N=nan, excursion_m=nan, drive_force_N=nan,
                             works=False, reason="no tensions within the limits at some step of the move's plan")
    except SimulationDivergedError:
        return RailMoveCheck(**fig, tension_min_N=nan, tension_max_N=nan, excursion_m=nan, drive_force_N=nan,
                             works=False, reason="the closed loop diverged")
    verdict = controller_verdict(res, move)
    held = verdict.get("controller_verdict") != "bypassed"
    return RailMoveCheck(**fig, tension_min_N=float(res.tensions.min()), tension_max_N=float(res.tensions.max()),
                         excursion_m=float(np.linalg.norm(res.pose[:, :3] - np.asarray(hold), axis=1).max()),
                         drive_force_N=drive_force(p, move).peak_N, works=held,
                         reason="" if held else bypassed_text(res.controller_fallbacks, res.t.size,
                                                              move.simulation.max_bypassed_share))


def sea_columns(cells: list) -> list[list[int]]:
    """The scatter diagram's columns: the indices of the cells of one peak period and one
    heading, each column by growing Hs; columns in the order of their first cell."""
    columns: dict[tuple[float, float], list[int]] = {}
    for i, c in enumerate(cells):
        columns.setdefault((c.tp, c.heading_deg), []).append(i)
    return [sorted(col, key=lambda i: cells[i].hs) for col in columns.values()]


def column_boundary(verdicts: dict[int, bool], n: int) -> tuple[int, int]:
    """Where a column's job first fails, from the verdicts of the places flown so far
    (``verdicts``: place in the column by growing Hs -> works): ``(lo, hi)``, ``hi`` the
    lowest place flown that fails (``n`` if none), ``lo`` the highest flown below it that
    works (-1 if none). The column is settled when ``hi == lo + 1``.

    >>> column_boundary({3: True, 4: False, 9: True}, 12)
    (3, 4)
    """
    hi = min((j for j, ok in verdicts.items() if not ok), default=n)
    lo = max((j for j, ok in verdicts.items() if ok and j < hi), default=-1)
    return lo, hi


def unflown_columns(cells: list, share: float) -> set[int]:
    """The columns (:func:`sea_columns`' indices) of least probability whose sum is at most
    ``share`` of the cells' whole: those :func:`fly_boundary` leaves unflown
    (``[sea] unflown_share``); the empty set for 0."""
    p = np.array([c.probability for c in cells], dtype=float)
    mass = np.array([p[col].sum() for col in sea_columns(cells)]) / max(p.sum(), 1e-300)
    order = np.argsort(mass, kind="stable")
    within = np.cumsum(mass[order]) <= share * (1.0 + 1e-12)
    return {int(k) for k in order[within]}


def fly_boundary(session, template: Scenario, cells: list, screen_works: np.ndarray, kwargs: dict,
                 progress: Callable[[int], None] | None = None, *, skip: set[int] = frozenset()
                 ) -> tuple[np.ndarray, dict]:
    """The time domain's verdict in every sea state, flying only those about each column's
    boundary (:func:`sea_columns`): first the sea just above the highest of the column's
    lowest seas the screen passes (the top sea where it passes them all); where that fails,
    the screen's highest pass next (a conservative screen's pass: the time domain should pass
    it too); then by bisection (all columns' next seas at once on the ``session``) until each
    column is settled (:func:`column_boundary`). A column's seas below its first failure are
    taken to work and those above it to fail; the seas flown keep their own verdicts. A pass
    costs a whole flight and a failure mostly its plan alone (``plan_first``), so the screen's
    own pass is flown only where the sea above it fails: were it to pass there, the sea below
    would be taken to work.

    Parameters
    ----------
    session : Session
        An :class:`~marinecdpr.studies.executor.Executor`'s session.
    screen_works : ndarray of bool, shape (n_cells,)
    kwargs : dict
        :func:`~marinecdpr.studies.cleaning.evaluate_cleaning_cell`'s options.
    progress : callable(n_flown), optional
    skip : set of int
        Columns (:func:`sea_columns`' indices) not flown (:func:`unflown_columns`): their sea
        states' ``works`` are False.

    Returns
    -------
    works : ndarray of bool, shape (n_cells,)
    flown : dict
        Cell index -> its :class:`~marinecdpr.studies.cleaning.CleaningCellResult`.
    """
    from marinecdpr.studies.cleaning import evaluate_cleaning_cell

    columns = sea_columns(cells)
    verdicts: list[dict[int, bool]] = [{} for _ in columns]
    flown: dict[int, object] = {}
    guess = []  # the screen's last pass of each column's lowest seas (-1: none)
    for col in columns:
        ok = screen_works[col]
        guess.append(int(np.argmin(ok)) - 1 if not ok.all() else len(col) - 1)
    probes = [(k, min(s + 1, len(col) - 1)) for k, (s, col) in enumerate(zip(guess, columns)) if k not in skip]
    while probes:
        before = len(flown)
        results = session.map(evaluate_cleaning_cell, template, [cells[columns[k][j]] for k, j in probes], kwargs,
                              progress=None if progress is None else (lambda d, _t: progress(before + d)))
        for (k, j), r in zip(probes, results):
            verdicts[k][j] = bool(r.operable)
            flown[columns[k][j]] = r
        probes = []
        for k, col in enumerate(columns):
            lo, hi = column_boundary(verdicts[k], len(col))
            if hi > lo + 1 and k not in skip:
                probes.append((k, guess[k] if hi == guess[k] + 1 and lo < guess[k] else (lo + hi) // 2))
    works = np.zeros(len(cells), dtype=bool)
    for k, col in enumerate(columns):
        if k in skip:
            continue
        lo, hi = column_boundary(verdicts[k], len(col))
        for j, i in enumerate(col):
            works[i] = verdicts[k][j] if j in verdicts[k] else j < hi
    return works, flown


def verify(study: DesignStudy, template: Scenario, scatter, *, executor: Executor | None = None,
           plant: str | None = None,
           progress: Callable[[int, int], None] | None = None) -> list[Verification]:
    """Fly the study's best ``finalists`` (the front by expected hours) through the cleaning
    job in every sea state of its scatter diagram and headings, closed loop (``plant``), on
    the ``executor`` (:class:`~marinecdpr.studies.executor.Executor`, default serial) as
    ``clean --seas`` does, as built (:func:`as_built`: the rope's weight
    and stretch, the winches' dynamics and limits) at the placement where the screen found
    the seas hardest; the time-domain share and hours beside the screen's there. With
    ``[sea] verify = "boundary"`` only the seas about each column's boundary fly
    (:func:`fly_boundary`), and with ``[sea] unflown_share`` not those of the columns of least
    probability (:func:`unflown_columns`: left unjudged, counted as failing in the time
    domain's share). A finalist on a rail also flies a move of its frame along the rail
    in the highest sea flown that works (:func:`fly_rail_move`). There a sea state whose
    plan already fails (its tensions, or its normal force's share of time in band: a flown
    job takes both from its plan) is judged by its plan and not flown (``plan_first``).

    Parameters
    ----------
    plant : {"mujoco", "own"}, optional
        Default: the study's ``plant``, else the template's; a finalist with sagging cables
        flies on the own plant (:func:`as_built`), and its :attr:`Verification.plant` says so.
    progress : callable(done, total), optional
        Sea states flown over all finalists.
    """
    from marinecdpr.studies.cleaning import COVERAGE_TARGET_PCT, IN_BAND_TARGET_PCT, NOT_FLOWN, cleaning_seas
    from marinecdpr.studies.operability import scatter_cells
    from marinecdpr.studies.screen import screen_cells

    spec = study.spec
    heads = tuple(float(h) for h in spec.sea.headings_deg)
    cells = scatter_cells(scatter, heads)
    plant = plant or spec.plant or template.simulation.plant
    chosen = study.front[:spec.finalists]
    total = len(chosen) * len(cells)
    boundary = spec.sea.verify == "boundary"
    weight = np.array([c.probability / len(heads) for c in cells])
    columns = sea_columns(cells)
    skip = unflown_columns(cells, spec.sea.unflown_share) if boundary else set()
    judged = np.ones(len(cells), dtype=bool)
    for k in skip:
        judged[columns[k]] = False
    flying = len(columns) - len(skip)
    if boundary:  # about two seas per column and finalist first; more as the bisections ask
        total = 2 * len(chosen) * flying
    executor = executor or Executor.serial()
    out = []
    done_before = 0
    for rank, i in enumerate(chosen, start=1):
        e = study.evaluations[i]
        sc = as_built(spec, template, e, plant)
        flown = sc.simulation.plant  # the own plant for sagging cables
        screened = screen_cells(sc, cells)  # at the placement flown
        works = screened.works
        if boundary:
            kwargs = dict(coverage_target_pct=COVERAGE_TARGET_PCT, in_band_target_pct=IN_BAND_TARGET_PCT,
                          plant=flown, hull_area_m2=None, move_time_s=600.0, plan_first=True)

            def seen(n, before=done_before, left=len(chosen) - rank):
                nonlocal total
                total = max(total, before + n + 2 * left * flying)
                progress(before + n, total)

            with executor.session() as session:
                td, results = fly_boundary(session, sc, cells, works, kwargs, None if progress is None else seen,
                                           skip=skip)
            done_before += len(results)
            share = float(weight[td].sum())
            failed = [results[j] for j in sorted(results) if not results[j].operable]
            n_flown = len(results)
            planned_only = sum(r.reason.endswith(NOT_FLOWN) for r in results.values())
        else:
            done = (rank - 1) * len(cells)
            cs = cleaning_seas(sc, scatter, headings_deg=heads, plant=flown, executor=executor,
                               progress=None if progress is None else (lambda d, _t, done=done: progress(done + d, total)))
            td = np.array([r.operable for r in cs.sea.results], dtype=bool)
            share = cs.sea.operability
            failed = [r for r in cs.sea.results if not r.operable]
            n_flown, planned_only = len(cells), 0
        rail_move = None
        hardest = max((j for j in (results if boundary else range(len(cells))) if td[j]),
                      key=lambda j: (cells[j].hs, -j), default=None)  # the highest sea flown that works
        if e.x.get("relocation") == "rail" and hardest is not None:
            rail_move = fly_rail_move(spec, sc, e, cells[hardest])
        out.append(Verification(
            index=i, rank=rank, surface_hours=e.surface_hours, screen_share=screened.share, td_share=share,
            screen_expected_hours=e.expected_hours,
            td_expected_hours=e.surface_hours / share if share > 0 else float("inf"),
            agree=int((judged & (works == td)).sum()), screen_works_td_fails=int((judged & works & ~td).sum()),
            screen_fails_td_works=int((judged & ~works & td).sum()),
            unjudged=int((~judged).sum()), unjudged_share=float(weight[~judged].sum()),
            reasons=[f"Hs {r.cell.hs:g} m, Tp {r.cell.tp:g} s, heading {r.cell.heading_deg:g} deg: {r.reason}"
                     for r in failed], plant=flown,
            screen_reasons=[why for why in screened.reasons if why], flown=n_flown, planned_only=planned_only,
            rail_move=rail_move))
    return out
