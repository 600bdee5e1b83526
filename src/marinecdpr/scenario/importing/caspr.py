"""A CASPR model (Darwin Lau's toolkit, ``data/model_config/models/...``) as a scenario.

CASPR's conventions, and what they become here:

- The platform is link 1 of a ``bodies_system``, on a ``SPATIAL_EULER_XYZ`` joint to the
  ground (link 0): q = (x, y, z, a, b, c), the joint's origin in the ground frame (plus the
  joint's ``parent/location``) and R = Rx(a) Ry(b) Rz(c), radians. Here the ground frame
  is C, P's origin is the centre of mass, and R = Rz(rz) Ry(ry) Rx(rx) in degrees: a
  pose's position is the joint's origin plus R times ``com_location``, its angles those of
  the same R.
- A cable's attachment on link 1 is relative to the joint's origin
  (``attachment_reference="joint"``) or to the centre of mass (``"com"``); here p_i is
  relative to the centre of mass. Its attachment on link 0 is in the ground frame.
- ``inertia ref="joint"`` is about the joint's origin: shifted to the centre of mass
  (parallel axes). The products of inertia are the tensor's off-diagonal entries.
- ``force_min`` and ``force_max`` are each cable's tension limits, N. Gravity is 9.81 m/s^2
  along -z of the ground (CASPR's ``SystemModel.GRAVITY_CONSTANT``).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from marinecdpr.errors import ScenarioError
from marinecdpr.scenario.importing.common import Imported, euler_from_matrix, held_trajectory, numbers, read_xml

__all__ = ["read_caspr", "caspr_rotation", "HELD_S", "STEP_S"]

HELD_S = 2.0
"""How long a model without a trajectory holds its platform at ``q_initial``, s."""
STEP_S = 0.001
"""The imported scenario's time step (1 kHz, as the controller runs), s."""
GRAVITY = 9.81
"""CASPR's gravity, m/s^2."""


def caspr_rotation(a: float, b: float, c: float) -> np.ndarray:
    """CASPR's ``SPATIAL_EULER_XYZ`` orientation Rx(a) Ry(b) Rz(c) (radians), ground <- link."""
    ca, sa, cb, sb, cc, sc = math.cos(a), math.sin(a), math.cos(b), math.sin(b), math.cos(c), math.sin(c)
    Rx = np.array([[1, 0, 0], [0, ca, -sa], [0, sa, ca]])
    Ry = np.array([[cb, 0, sb], [0, 1, 0], [-sb, 0, cb]])
    Rz = np.array([[cc, -sc, 0], [sc, cc, 0], [0, 0, 1]])
    return Rx @ Ry @ Rz


def _text(node, tag: str, *, source: str, key: str):
    child = node.find(tag)
    if child is None:
        raise ScenarioError(f"missing <{tag}>", source=source, key=key)
    return child.text


def _one(node, tag: str, *, source: str, key: str) -> float:
    return numbers(_text(node, tag, source=source, key=f"{key}.{tag}"), 1, source=source, key=f"{key}.{tag}")[0]


def _beside(path: Path, suffix: str) -> Path | None:
    """``X_cables.xml`` beside ``X_bodies.xml`` (None if the name does not say)."""
    if not path.name.endswith("_bodies.xml"):
        return None
    return path.with_name(path.name[: -len("_bodies.xml")] + suffix)


def read_caspr(bodies: str | Path, *, cables: str | Path | None = None, trajectories: str | Path | None = None,
               cable_set: str | None = None, trajectory: str | None = None, hold: bool = False) -> Imported:
    """A CASPR model as a scenario (see the module's conventions and
    :func:`~marinecdpr.scenario.importing.import_robot`)."""
    from marinecdpr.scenario.loading import scenario_from_dict

    bodies = Path(bodies)
    src = str(bodies)
    notes: list[str] = []
    top = read_xml(bodies, "bodies_system")
    links = top.findall("./links/link_rigid")
    if len(links) != 1:
        raise ScenarioError(f"{len(links)} rigid links: a cable robot's platform is one rigid body (link 1 on the "
                            "ground)", source=src, key="links")
    link = links[0]
    key = "links.link_rigid"
    joint = link.find("joint")
    if joint is None:
        raise ScenarioError("missing <joint>", source=src, key=key)
    if joint.get("type") != "SPATIAL_EULER_XYZ":
        raise ScenarioError(f"joint type {joint.get('type')!r}: only a platform free in space "
                            "(SPATIAL_EULER_XYZ) is imported", source=src, key=f"{key}.joint")
    q0 = numbers(joint.get("q_initial", "0 0 0 0 0 0"), 6, source=src, key=f"{key}.joint.q_initial")
    if joint.get("q_min") is not None or joint.get("q_max") is not None:
        notes.append("the joint's q_min and q_max are not carried over: here the frame anchors bound where the "
                     "platform may go")
    physical = link.find("physical")
    if physical is None:
        raise ScenarioError("missing <physical>", source=src, key=key)
    pkey = f"{key}.physical"
    mass = _one(physical, "mass", source=src, key=pkey)
    com = np.array(numbers(_text(physical, "com_location", source=src, key=f"{pkey}.com_location"), 3, source=src,
                           key=f"{pkey}.com_location"))
    inertia = physical.find("inertia")
    if inertia is None:
        raise ScenarioError("missing <inertia>", source=src, key=pkey)
    ikey = f"{pkey}.inertia"
    Ixx, Iyy, Izz, Ixy, Ixz, Iyz = (_one(inertia, t, source=src, key=ikey)
                                    for t in ("Ixx", "Iyy", "Izz", "Ixy", "Ixz", "Iyz"))
    I = np.array([[Ixx, Ixy, Ixz], [Ixy, Iyy, Iyz], [Ixz, Iyz, Izz]])
    ref = inertia.get("ref", "com")
    if ref == "joint":  # about the joint's origin: to the centre of mass (parallel axes)
        I = I - mass * (float(com @ com) * np.eye(3) - np.outer(com, com))
    elif ref != "com":
        raise ScenarioError(f"inertia ref {ref!r}: expected \"com\" or \"joint\"", source=src, key=ikey)
    parent = link.find("parent")
    origin = np.zeros(3)
    if parent is not None:
        if parent.findtext("num", "0").strip() != "0":
            raise ScenarioError("the platform's parent must be the ground (link 0)", source=src, key=f"{key}.parent")
        if parent.find("location") is not None:
            origin = np.array(numbers(parent.findtext("location"), 3, source=src, key=f"{key}.parent.location"))

    cables_path = Path(cables) if cables is not None else _beside(bodies, "_cables.xml")
    if cables_path is None:
        raise ScenarioError("no cables file: name it (--cables), or name the bodies file X_bodies.xml with "
                            "X_cables.xml beside it", source=src)
    cable_list, limits = _cables(cables_path, cable_set, com, notes)
    files = [str(bodies), str(cables_path)]

    robot: dict = {"dofs": "spatial", "mass_kg": mass,
                   "inertia_kg_m2": [[float(v) for v in row] for row in I], "cables": cable_list}
    if len(set(limits)) == 1:  # all alike: the robot's defaults
        robot["tension_min_N"], robot["tension_max_N"] = limits[0]
    else:
        for c, (lo, hi) in zip(cable_list, limits):
            c["tension_min_N"], c["tension_max_N"] = lo, hi

    traj_path = Path(trajectories) if trajectories is not None else _beside(bodies, "_trajectories.xml")
    motion = None
    if hold:
        if trajectories is not None or trajectory is not None:
            raise ScenarioError("--hold holds the platform at q_initial: it takes no trajectory", source=src)
    elif traj_path is not None and (trajectories is not None or traj_path.is_file()):
        motion = _trajectory(traj_path, trajectory, origin, com, notes)
        files.append(str(traj_path))
    elif trajectory is not None:
        raise ScenarioError(f"--trajectory {trajectory}: no trajectories file beside the model (name it with "
                            "--trajectories)", source=src)
    if motion is None:
        R0 = caspr_rotation(*q0[3:])
        motion = (held_trajectory(list(origin + q0[:3] + R0 @ com), euler_from_matrix(R0), HELD_S), HELD_S)
        notes.append(f"{'--hold' if hold else 'no trajectory in the model'}: the platform is held at the joint's "
                     f"q_initial for {HELD_S:g} s")
    data = {
        "name": link.get("name") or bodies.stem.removesuffix("_bodies"),
        "description": f"Imported from CASPR: {bodies.name}",
        "robot": robot,
        "trajectory": motion[0],
        "time": {"step_s": STEP_S, "duration_s": motion[1]},
        "environment": {"gravity_m_s2": GRAVITY},
    }
    notes.append("the ship and its motion are not part of a CASPR model: the frame stands still ([ship] and "
                 "[base_motion] at their defaults)")
    scenario_from_dict(data, source=f"{src} (imported)")  # the robot as this toolkit validates it
    return Imported(data=data, notes=tuple(notes), source="CASPR", files=tuple(files))


def _cables(path: Path, cable_set: str | None, com: np.ndarray, notes: list[str]):
    src = str(path)
    top = read_xml(path, "cables")
    sets = top.findall("cable_set")
    wanted = cable_set or top.get("default_cable_set")
    chosen = [s for s in sets if s.get("id") == wanted] if wanted else sets[:1]
    if not chosen:
        raise ScenarioError(f"no cable set {wanted!r} (the file has {', '.join(repr(s.get('id')) for s in sets) or 'none'})",
                            source=src, key="cable_set")
    others = [s.get("id") for s in sets if s is not chosen[0]]
    if others:
        notes.append(f"cable set {chosen[0].get('id')!r} taken; the file's other sets ({', '.join(map(repr, others))}) "
                     "are not (choose one with --cable-set)")
    cables, limits = [], []
    for i, cable in enumerate(chosen[0], start=1):
        key = f"cable_set[{chosen[0].get('id')}].{cable.tag}[{i}]"
        if cable.tag != "cable_ideal":
            notes.append(f"cable {i} is a {cable.tag} in CASPR: imported as an ideal cable (its own dynamics are "
                         "not carried over; [simulation.cables] sets elastic ones)")
        props = cable.find("properties")
        if props is None:
            raise ScenarioError("missing <properties>", source=src, key=key)
        lo = _one(props, "force_min", source=src, key=f"{key}.properties")
        hi = _one(props, "force_max", source=src, key=f"{key}.properties")
        points = cable.findall("./attachments/attachment")
        ground = [p for p in points if (p.findtext("link") or "").strip() == "0"]
        platform = [p for p in points if (p.findtext("link") or "").strip() == "1"]
        if len(ground) + len(platform) != len(points) or not ground or len(platform) != 1:
            raise ScenarioError("expected attachments on the ground (link 0) and one on the platform (link 1)",
                                source=src, key=f"{key}.attachments")
        if len(ground) > 1:
            notes.append(f"cable {i} runs over {len(ground)} points on the ground: the last, where it leaves for the "
                         "platform, is its frame anchor (the others are not carried over)")
        c = numbers(ground[-1].findtext("location"), 3, source=src, key=f"{key}.attachments.location")
        p = np.array(numbers(platform[0].findtext("location"), 3, source=src, key=f"{key}.attachments.location"))
        reference = cable.get("attachment_reference", "joint")
        if reference == "joint":
            p = p - com  # from the joint's origin to P's, the centre of mass
        elif reference != "com":
            raise ScenarioError(f"attachment_reference {reference!r}: expected \"joint\" or \"com\"", source=src,
                                key=key)
        cables.append({"frame_anchor_m": [float(v) for v in c], "platform_anchor_m": [float(v) for v in p]})
        limits.append((lo, hi))
    if not cables:
        raise ScenarioError("the cable set holds no cables", source=src, key=f"cable_set[{chosen[0].get('id')}]")
    return cables, limits


SPLINES = ("quintic_spline_trajectory", "cubic_spline_trajectory", "linear_spline_trajectory",
           "cubic_spline_average_velocity_trajectory", "parabolic_blend_trajectory")


def _trajectory(path: Path, wanted: str | None, origin: np.ndarray, com: np.ndarray, notes: list[str]):
    src = str(path)
    top = read_xml(path, "trajectories")
    found = [t for t in top.findall("./joint_trajectories/*")]
    if not found:
        if wanted is not None:
            raise ScenarioError(f"no trajectory {wanted!r}: the file holds no joint trajectories", source=src)
        return None
    chosen = [t for t in found if t.get("id") == wanted] if wanted else found[:1]
    if not chosen:
        raise ScenarioError(f"no trajectory {wanted!r} (the file has {', '.join(repr(t.get('id')) for t in found)})",
                            source=src, key="joint_trajectories")
    traj = chosen[0]
    key = f"joint_trajectories.{traj.tag}[{traj.get('id')}]"
    if traj.tag not in SPLINES:
        raise ScenarioError(f"a {traj.tag} is not imported: expected one of {', '.join(SPLINES)}", source=src, key=key)
    if len(found) > 1:
        notes.append(f"trajectory {traj.get('id')!r} taken of the file's {len(found)} (choose one with --trajectory)")
    points = traj.findall("./points/point")
    if len(points) < 2:
        raise ScenarioError(f"{len(points)} point{'s' if len(points) != 1 else ''}: a trajectory needs two",
                            source=src, key=key)
    relative = traj.get("time_definition", "relative") == "relative"
    waypoints, t, moving = [], 0.0, False
    for k, point in enumerate(points, start=1):
        pkey = f"{key}.points.point[{k}]"
        if k > 1:
            if point.get("time") is None:
                raise ScenarioError("missing its time", source=src, key=pkey)
            dt = numbers(point.get("time"), 1, source=src, key=f"{pkey}.time")[0]
            t = t + dt if relative else dt
        q = numbers(point.findtext("q"), 6, source=src, key=f"{pkey}.q")
        for rate in ("q_dot", "q_ddot"):
            if point.find(rate) is not None and any(numbers(point.findtext(rate), 6, source=src, key=f"{pkey}.{rate}")):
                moving = True
        R = caspr_rotation(*q[3:])
        waypoints.append({"time_s": round(t, 12), "position_m": [float(v) for v in origin + q[:3] + R @ com],
                          "orientation_deg": euler_from_matrix(R)})
    if moving or traj.tag != "quintic_spline_trajectory":
        notes.append(f"the {traj.tag}'s points are joined by rest-to-rest quintics here (velocities and "
                     "accelerations at the points 0): between the points the path differs from CASPR's")
    step = traj.get("time_step")
    if step is not None:
        notes.append(f"CASPR's time step ({step} s) is not taken: the scenario steps at {STEP_S:g} s")
    return {"type": "waypoints", "waypoints": waypoints}, waypoints[-1]["time_s"]
