"""A WireX robot file (``.wcrfx``, Andreas Pott's toolkit; schema 0.31/0.32) as a scenario.

WireX's conventions, and what they become here:

- ``<chain><base x y z .../>`` is a cable's frame anchor a_i in the world frame K0 and
  ``<chain><platform x y z .../>`` its platform point b_i in the platform frame Kp, m. Here
  K0 is C and Kp is P. WireX's own loader reads only these (and the pulleys' radii and
  orientations, ``a11 .. a33``: row i, column j of the matrix); the platform's mass,
  inertia and centre of gravity it writes but does not read back.
- Force limits: ``<application min_cable_load max_cable_load>`` where given, else the
  winch's ``<cable f_max>`` and the cable's ``minimum_load``, else WireX's own defaults
  (``CRobotData::fmin`` 1 N, ``fmax`` 10 N).
- ``motionpattern`` "3R3T" is a spatial robot. "1R2T" moves in WireX's x-y plane turning
  about z: here turned onto the x-z plane (x, y, z) -> (x, -z, y), a turn about x by
  +90 deg, so WireX's rotation about z is one about -y here.
- A pulley (``--pulleys``): its swivel axis is the z axis of the chain's base matrix, the
  cable arriving along it at the base point, with the chain's ``radius``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from marinecdpr.errors import ScenarioError
from marinecdpr.scenario.importing.common import Imported, held_trajectory, numbers, read_xml

__all__ = ["read_wirex", "FMIN_DEFAULT_N", "FMAX_DEFAULT_N"]

FMIN_DEFAULT_N, FMAX_DEFAULT_N = 1.0, 10.0
"""WireX's force limits when a file gives none (``WireLib/RobotData.cpp``), N."""
HELD_S = 2.0
STEP_S = 0.001
SUSPENDED_DROP = 0.25
"""How far below its anchors a suspended robot's platform is held, as a share of the
frame's largest extent (CoGiRo: 3.7 m below anchors 15 m apart; CASPR holds it 3.4 m below)."""
PLANE_XZ = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])
"""WireX's x-y plane onto ours, x-z: (x, y, z) -> (x, -z, y)."""


def _vector(node, *, source: str, key: str) -> np.ndarray:
    try:
        return np.array(numbers(" ".join(node.get(a) for a in "xyz"), 3, source=source, key=key))
    except TypeError:  # an attribute missing
        raise ScenarioError("expected attributes x, y and z", source=source, key=key) from None


def _matrix(node, *, source: str, key: str) -> np.ndarray:
    names = [f"a{i}{j}" for i in (1, 2, 3) for j in (1, 2, 3)]
    if not all(node.get(n) is not None for n in names):
        return np.eye(3)  # as WireX's reader: all nine or the identity
    return np.array(numbers(" ".join(node.get(n) for n in names), 9, source=source, key=key)).reshape(3, 3)


def _attr(node, name: str, *, source: str, key: str) -> float | None:
    if node is None or node.get(name) is None:
        return None
    return numbers(node.get(name), 1, source=source, key=f"{key}@{name}")[0]


def read_wirex(path: str | Path, *, pulleys: bool = False) -> Imported:
    """A WireX ``.wcrfx`` robot as a scenario (see the module's conventions and
    :func:`~marinecdpr.scenario.importing.import_robot`)."""
    from marinecdpr.scenario.loading import scenario_from_dict

    path = Path(path)
    src = str(path)
    notes: list[str] = []
    top = read_xml(path, "models")
    robots = top.findall("robot")
    if len(robots) != 1:
        raise ScenarioError(f"{len(robots)} <robot> elements: expected one", source=src, key="models")
    robot = robots[0]
    pattern = robot.get("motionpattern", "3R3T")
    if pattern not in ("3R3T", "1R2T"):
        raise ScenarioError(f"motion pattern {pattern!r}: only 3R3T (spatial) and 1R2T (planar) robots are imported",
                            source=src, key="robot@motionpattern")
    planar = pattern == "1R2T"
    chains = robot.findall("./geometry/chain")
    if not chains:
        raise ScenarioError("no <chain>: the robot has no cables", source=src, key="robot.geometry")
    heights = {ch.find(part).get("z") for ch in chains for part in ("base", "platform") if ch.find(part) is not None}
    if not planar and len(chains) < 6 and len(heights) == 1:  # a planar robot marked spatial (2DIPAnema2)
        planar = True
        notes.append(f"marked {pattern}, but its {len(chains)} cables and all its points lie in the plane "
                     f"z = {heights.pop()}: read as a planar robot (1R2T)")
    M = PLANE_XZ if planar else np.eye(3)
    if planar:
        notes.append("WireX's x-y plane is the x-z plane here, its y up: (x, y, z) -> (x, -z, y)")
    cables, dropped = [], []
    for i, chain in enumerate(chains, start=1):
        key = f"robot.geometry.chain[{i}]"
        base, platform = chain.find("base"), chain.find("platform")
        if base is None or platform is None:
            raise ScenarioError("expected a <base> and a <platform>", source=src, key=key)
        a = M @ _vector(base, source=src, key=f"{key}.base")
        b = M @ _vector(platform, source=src, key=f"{key}.platform")
        cable = {"frame_anchor_m": [float(v) for v in a], "platform_anchor_m": [float(v) for v in b]}
        radius = _attr(base, "radius", source=src, key=f"{key}.base")
        radius = 0.1 if radius is None else radius  # WireX's reader's default
        if pulleys and radius > 0.0:
            axis = M @ _matrix(base, source=src, key=f"{key}.base")[:, 2]
            cable.update(pulley_radius_m=radius, pulley_axis=[float(v) for v in axis])
        elif radius > 0.0:
            dropped.append(i)
        cables.append(cable)
    if dropped:
        notes.append(f"the pulleys of chain{'s' if len(dropped) > 1 else ''} {_ranges(dropped)} (radius in <base>) are "
                     "not carried over: WireX's standard kinematics, which its published lengths use, has none "
                     "(--pulleys takes them)")
    body = robot.find("platform")
    mass = _attr(body, "mass", source=src, key="robot.platform")
    if mass is None:
        mass = 25.0
        notes.append("no platform mass: WireX's default, 25 kg")
    tensor = None if body is None else body.find("inertiatensor")
    I = _inertia(tensor, src, notes)
    if planar:
        I = M @ I @ M.T
    cog = None if body is None else body.find("centerofgravity")
    if cog is not None:
        notes.append(f"the centre of gravity ({', '.join(cog.get(a, '?') for a in 'xyz')}) is not carried over: "
                     "WireX's own loader does not read it; the platform frame's origin is its centre of mass")
    lo, hi = _limits(top, robot, src, notes)
    frame = np.array([c["frame_anchor_m"] for c in cables])
    centre = 0.5 * (frame.min(axis=0) + frame.max(axis=0))
    from marinecdpr.scenario.robot import frame_axes

    held = "at the frame's centre"
    if planar:
        centre[1] = 0.0
    elif not frame_axes(frame)[2]:  # a suspended robot: its anchors all near one height
        centre[2] -= SUSPENDED_DROP * float(np.ptp(frame, axis=0).max())
        held = f"{SUSPENDED_DROP:g} of the frame's size below the middle of its anchors (a suspended robot)"
    data = {
        "name": robot.get("name") or path.stem,
        "description": f"Imported from WireX: {path.name}" + (f" ({robot.get('description')})"
                                                                if robot.get("description") else ""),
        "robot": {"dofs": "planar" if planar else "spatial", "mass_kg": mass,
                  "inertia_kg_m2": [[float(v) for v in row] for row in I],
                  "tension_min_N": lo, "tension_max_N": hi, "cables": cables},
        "trajectory": held_trajectory(list(centre), [0.0, 0.0, 0.0], HELD_S),
        "time": {"step_s": STEP_S, "duration_s": HELD_S},
    }
    notes.append(f"a WireX robot file holds no motion: the platform is held level {held} for {HELD_S:g} s")
    notes.append("the ship and its motion are not part of a WireX robot: the frame stands still ([ship] and "
                 "[base_motion] at their defaults)")
    scenario_from_dict(data, source=f"{src} (imported)")
    return Imported(data=data, notes=tuple(notes), source="WireX", files=(src,))


def _inertia(tensor, src: str, notes: list[str]) -> np.ndarray:
    if tensor is None:
        notes.append("no inertia tensor: WireX's default, diag(2, 3, 4) kg m^2")
        return np.diag([2.0, 3.0, 4.0])
    names = ["Ixx", "Ixy", "Ixz", "Iyx", "Iyy", "Iyz", "Izx", "Izy", "Izz"]
    given = {n: _attr(tensor, n, source=src, key="robot.platform.inertiatensor") for n in names}
    if all(v is not None for v in given.values()):
        return np.array([given[n] for n in names]).reshape(3, 3)
    if given["Ixx"] is not None and all(v is None for n, v in given.items() if n != "Ixx"):
        notes.append(f"the inertia tensor gives Ixx only ({given['Ixx']:g} kg m^2): taken as the moment about every "
                     "axis")
        return np.eye(3) * given["Ixx"]
    raise ScenarioError("expected all nine of Ixx .. Izz, or Ixx alone", source=src, key="robot.platform.inertiatensor")


def _limits(top, robot, src: str, notes: list[str]) -> tuple[float, float]:
    app = robot.find("application")
    lo = _attr(app, "min_cable_load", source=src, key="robot.application")
    hi = _attr(app, "max_cable_load", source=src, key="robot.application")
    if lo is not None and hi is not None:
        return lo, hi
    winch = top.find("./winch/cable")
    cable = top.find("cable")
    hi = _attr(winch, "f_max", source=src, key="winch.cable")
    lo = _attr(cable, "minimum_load", source=src, key="cable")
    if hi is not None:
        if lo is None:
            lo = 0.0
            notes.append("no minimum cable load: 0 N")
        return lo, hi
    notes.append(f"no force limits in the file: WireX's defaults, {FMIN_DEFAULT_N:g} N to {FMAX_DEFAULT_N:g} N")
    return FMIN_DEFAULT_N, FMAX_DEFAULT_N


def _ranges(numbers_: list[int]) -> str:
    """1, 2, 3, 5 -> "1-3, 5"."""
    out, start = [], numbers_[0]
    for a, b in zip(numbers_, numbers_[1:] + [None]):
        if b != a + 1:
            out.append(f"{start}" if start == a else f"{start}-{a}")
            start = b
    return ", ".join(out)
