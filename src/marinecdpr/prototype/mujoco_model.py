"""A MuJoCo model of any scenario's robot on its ship: the independent virtual prototype.

World frame = O (z up, gravity (0, 0, -g)). Bodies:

``ship``
    A very heavy rigid body (:data:`SHIP_MASS_KG`, isotropic inertia
    :data:`SHIP_INERTIA_KG_M2`, more with a carriage far from S's origin: :func:`ship_inertia`;
    gravity compensated) on six joints in the order
    slide x, slide y, slide z, hinge z (yaw), hinge y (pitch), hinge x (roll): MuJoCo
    applies a body's joints in order, each about the axes left by the previous ones,
    so the ship's orientation is Rz(yaw) Ry(pitch) Rx(roll) = R_SO and its joint
    positions and velocities are the ship coordinates eta and their rates (of S', which has
    S's origin and C's axes, where ``ship.frame_orientation_deg`` turns the frame on the
    ship: :func:`~marinecdpr.motion.ship.in_frame_axes`). The
    simulation drives these joints with generalised forces (feed-forward of the
    analytic motion plus a stiff servo), so the ship has true velocity and
    acceleration; the cables' reaction barely moves a ship this heavy.
``frame``
    Robot frame C, fixed to the ship at ``ship.frame_origin_m`` (in S'); holds the frame anchors.
``carriage`` (a frame carried on a rail, ``[ship.carriage]``)
    Then the ship body moves as S itself (its joints are S's eta) and the frame hangs from
    a carriage body on it: as heavy as the ship (:data:`CARRIAGE_MASS_KG`, isotropic
    :data:`CARRIAGE_INERTIA_KG_M2`, gravity compensated), on joints relative to the ship in
    the order slide x, slide y, slide z, hinge z (all along S's axes), so that its joint
    positions are C's origin in S and the frame's yaw from its start
    (:func:`~marinecdpr.motion.carriage.carriage_joints`); a coordinate the carriage's moves
    do not change (:func:`carriage_coordinates`: a level rail's z, a straight rail's yaw) is
    no joint but the body's constant place (each joint costs MuJoCo's RK4 about 0.7 us a
    step). The ``frame`` body sits on it turned by the frame's lean at the rail's start
    (R_SC0, ``ship.frame_orientation_deg``).
    The simulation drives the carriage's joints as it drives the ship's (exact feed-forward
    of the two bodies' motion and a stiff servo), so C moves as the composed motion the
    own plant takes (:func:`~marinecdpr.motion.basemotion.frame_ship_motion`).
``platform``
    The platform, origin at its centre of mass: slide x, slide z, hinge y relative to
    C for a planar robot; slide x, y, z and a ball joint for a spatial one.

Each cable is a spatial tendon from its frame anchor to its platform anchor, pulled by
a motor with gear -1, so ``ctrl = tension`` (N) shortens the cable. A cable over a pulley
(planar robots: the pulley's plane is the robot's) runs from a site :data:`PULLEY_INLET_M`
back along its arrival direction, round a cylinder of the pulley's radius (MuJoCo finds
the wrap and the exit point itself), to the platform anchor: its tendon is that much
longer than the planner's length (``MujocoModel.tendon_offset``).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from marinecdpr.errors import ScenarioError
from marinecdpr.geometry.rotations import quaternion_from_matrix
from marinecdpr.motion.basemotion import frame_origin_of
from marinecdpr.motion.ship import frame_axes
from marinecdpr.scenario.schema import Scenario

__all__ = ["MujocoModel", "build_model", "SHIP_MASS_KG", "SHIP_INERTIA_KG_M2", "CARRIAGE_MASS_KG",
           "CARRIAGE_INERTIA_KG_M2", "CARRIAGE_JOINTS", "CARRIAGE_REACH_SHARE", "carriage_coordinates", "ship_inertia"]

PULLEY_INLET_M = 0.05
"""How far back along its arrival direction a pulley cable's tendon starts, m."""
SHIP_MASS_KG = 1.0e7
SHIP_INERTIA_KG_M2 = 1.0e8
CARRIAGE_MASS_KG = SHIP_MASS_KG
"""MuJoCo's carriage body: as heavy as the ship, so that the cables' pull barely moves it off
its trajectory (its servo's error ~ pull / (mass (2 pi 10 Hz)^2), 1e-8 m for 500 N); the
drive's real force is the carriage part's record (:mod:`~marinecdpr.prototype.parts.carriage`)."""
CARRIAGE_INERTIA_KG_M2 = SHIP_INERTIA_KG_M2
CARRIAGE_REACH_SHARE = 0.1
"""With a carriage, the ship's inertia is at least the carriage's mass at its farthest reach
from S's origin over this share, squared (:func:`ship_inertia`)."""
CARRIAGE_JOINTS = ("carriage_x", "carriage_y", "carriage_z", "carriage_yaw")
INTEGRATORS = {"RK4": "RK4", "Euler": "Euler", "implicitfast": "implicitfast"}


@dataclass(frozen=True)
class MujocoModel:
    """A compiled model and where its pieces are.

    Attributes
    ----------
    model : mujoco.MjModel
    xml : str
        The MJCF it was compiled from.
    ship_dofs : ndarray of int, shape (6,)
        DOF addresses of (x, y, z, yaw, pitch, roll).
    platform_qpos, platform_dofs : ndarray of int
        qpos and DOF addresses of the platform's joints (planar: x, z, theta_y;
        spatial: x, y, z then the ball's quaternion w, x, y, z / angular velocity).
    platform_body : int
    tendon_offset : ndarray, shape (n_cables,)
        The tendons' length beyond the cables' (a pulley cable's inlet), m.
    """

    model: object
    xml: str
    ship_dofs: np.ndarray
    platform_qpos: np.ndarray
    platform_dofs: np.ndarray
    platform_body: int
    tendon_offset: np.ndarray
    carriage_dofs: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=int))
    """DOF addresses of the carriage's joints on the ship; empty without a carriage."""
    carriage_coords: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=int))
    """Which of the carriage's (x, y, z, yaw) on S (0..3) those joints are, in order."""
    ship_inertia_kg_m2: float = SHIP_INERTIA_KG_M2
    """The ship body's isotropic inertia (:func:`ship_inertia`), kg m^2."""


def ship_inertia(scenario: Scenario) -> float:
    """The ship body's isotropic inertia, kg m^2: :data:`SHIP_INERTIA_KG_M2`, or with a
    carriage at least CARRIAGE_MASS_KG (r / CARRIAGE_REACH_SHARE)^2, r the rail's farthest
    point from S's origin.

    The ship's and the carriage's servos act on each joint as if it moved its own body alone;
    a carriage of the ship's mass r from the ship's hinges adds M r^2 to what they turn, so
    that a force on a carriage slide across r also turns the ship: the slide's effective mass
    1 / (1/M_c + 1/M_s + r^2/I_s) falls to I_s / r^2 (1.4e4 kg at 85 m) and its stiff servo,
    tuned for M_c, is unstable under RK4. With I_s >= M_c (r / 0.1)^2 that mass stays above
    M_c / 2.01.
    """
    carriage = scenario.ship.carriage
    if carriage is None:
        return SHIP_INERTIA_KG_M2
    reach = float(np.linalg.norm(np.asarray(carriage.rail_m, dtype=float), axis=1).max())
    return max(SHIP_INERTIA_KG_M2, CARRIAGE_MASS_KG * (reach / CARRIAGE_REACH_SHARE) ** 2)


def _v(x) -> str:
    return " ".join(f"{float(a):.17g}" for a in np.ravel(x))


def _pulley_side(a: np.ndarray, z: np.ndarray, towards: np.ndarray) -> np.ndarray:
    """The unit vector across the arrival direction z, in the x-z plane, towards a point."""
    k = np.array([-z[2], 0.0, z[0]])
    return k if k @ (towards - a) >= 0 else -k


TRIANGLE_MARGIN = 1e-12
"""How far, relative to the largest, MuJoCo's principal moments are lifted off the triangle
inequality's edge (:func:`_compilable_inertia`)."""


def _compilable_inertia(I: np.ndarray) -> np.ndarray:
    """The inertia (3, 3) MuJoCo compiles: the scenario's, unless its principal moments fall
    short of the triangle inequality, A + B < C, by a rounding error (a flat plate's lie on
    its edge A + B = C, which the scenario accepts within 1e-9 of C and MuJoCo refuses
    below it): there the two smaller moments are raised together until A + B = C (1 +
    :data:`TRIANGLE_MARGIN`). C, the moment about the plate's normal (a planar robot's only
    one), is kept; an inertia MuJoCo compiles as it is (the paper's 0.03 + 0.03 = 0.06) is
    returned as it is."""
    eig, V = np.linalg.eigh(I)
    if eig[0] + eig[1] >= eig[2]:
        return I
    short = eig[2] * (1.0 + TRIANGLE_MARGIN) - eig[0] - eig[1]
    eig = eig + np.array([0.5 * short, 0.5 * short, 0.0])
    return (V * eig) @ V.T


def build_xml(scenario: Scenario) -> str:
    """The MJCF text of the scenario's virtual prototype (see the module docstring)."""
    r = scenario.robot
    if r.has_pulleys and r.dofs != "planar":
        raise ScenarioError(f"{scenario.name}: the MuJoCo plant models pulleys of planar robots only (a spatial "
                            "robot's pulleys swivel): use simulation.plant = \"own\"")
    I = _compilable_inertia(r.inertia)
    full = [I[0, 0], I[1, 1], I[2, 2], I[0, 1], I[0, 2], I[1, 2]]
    step = scenario.time.step_s
    g = scenario.environment.gravity_m_s2
    integ = INTEGRATORS[scenario.simulation.integrator]
    frame_sites = "\n".join(
        f'        <site name="c{i}" pos="{_v(c)}" size="0.01"/>' for i, c in enumerate(r.frame_anchors, 1))
    plat_sites = "\n".join(
        f'          <site name="p{i}" pos="{_v(p)}" size="0.01"/>' for i, p in enumerate(r.platform_anchors, 1))
    if r.dofs == "planar":
        joints = ('<joint name="px" type="slide" axis="1 0 0"/>'
                  '<joint name="pz" type="slide" axis="0 0 1"/>'
                  '<joint name="pry" type="hinge" axis="0 1 0"/>')
    else:
        joints = ('<joint name="px" type="slide" axis="1 0 0"/>'
                  '<joint name="py" type="slide" axis="0 1 0"/>'
                  '<joint name="pz" type="slide" axis="0 0 1"/>'
                  '<joint name="pball" type="ball"/>')
    pulleys, tendons = [], []
    for i, (c, z, rad) in enumerate(zip(r.frame_anchors, r.pulley_axes, r.pulley_radii), 1):
        if rad == 0.0:
            tendons.append(f'    <spatial name="cable{i}" width="0.003"><site site="c{i}"/><site site="p{i}"/></spatial>')
            continue
        # the pulley's centre: r from the anchor, across the arrival direction towards the
        # platform (planar: in the x-z plane, on the side of the frame's centre)
        k = _pulley_side(c, z, r.frame_anchors.mean(axis=0))
        M = c + rad * k
        pulleys.append(f'        <site name="in{i}" pos="{_v(c - PULLEY_INLET_M * z)}" size="0.005"/>\n'
                       f'        <site name="side{i}" pos="{_v(c - rad * k)}" size="0.002"/>\n'
                       f'        <geom name="pulley{i}" type="cylinder" size="{rad:.17g} 0.005" pos="{_v(M)}" '
                       f'zaxis="0 1 0" contype="0" conaffinity="0"/>')
        tendons.append(f'    <spatial name="cable{i}" width="0.003"><site site="in{i}"/>'
                       f'<geom geom="pulley{i}" sidesite="side{i}"/><site site="p{i}"/></spatial>')
    tendons = "\n".join(tendons)
    frame_sites += "".join("\n" + x for x in pulleys)
    motors = "\n".join(f'    <motor name="T{i}" tendon="cable{i}" gear="-1"/>'
                       for i in range(1, r.n_cables + 1))
    Ms, Is = SHIP_MASS_KG, ship_inertia(scenario)
    frame = f"""      <body name="frame" pos="{_v(frame_origin_of(scenario))}">
{frame_sites}
        <body name="platform" pos="0 0 0">
          {joints}
          <inertial pos="0 0 0" mass="{r.mass_kg:.17g}" fullinertia="{_v(full)}"/>
{plat_sites}
        </body>
      </body>"""
    if scenario.ship.carriage is not None:
        frame = _carried(frame, scenario)
    return f"""<mujoco model="{scenario.name}">
  <compiler angle="radian" autolimits="true"/>
  <option timestep="{step:.17g}" gravity="0 0 {-g:.17g}" integrator="{integ}">
    <flag contact="disable"/>
  </option>
  <worldbody>
    <body name="ship" gravcomp="1">
      <joint name="ship_x" type="slide" axis="1 0 0"/>
      <joint name="ship_y" type="slide" axis="0 1 0"/>
      <joint name="ship_z" type="slide" axis="0 0 1"/>
      <joint name="ship_yaw" type="hinge" axis="0 0 1"/>
      <joint name="ship_pitch" type="hinge" axis="0 1 0"/>
      <joint name="ship_roll" type="hinge" axis="1 0 0"/>
      <inertial pos="0 0 0" mass="{Ms:.17g}" diaginertia="{Is:.17g} {Is:.17g} {Is:.17g}"/>
{frame}
    </body>
  </worldbody>
  <tendon>
{tendons}
  </tendon>
  <actuator>
{motors}
  </actuator>
</mujoco>
"""


def carriage_coordinates(scenario: Scenario) -> tuple[np.ndarray, np.ndarray]:
    """Which of the carriage's coordinates on S, (x, y, z, yaw) (:func:`~marinecdpr.motion.carriage.carriage_joints`),
    its moves change, and their values at the start.

    A position coordinate changes only if the rail's points differ in it (its arcs lie in
    the planes of its corners), the yaw only if the rail bends; none if the carriage has
    one place to be.

    Returns
    -------
    moving : ndarray of int
        The indices (0..3) of those that change, in order: MuJoCo's carriage joints.
    start : ndarray, shape (4,)
        All four at t = 0, m and rad (the others' constant values).
    """
    from marinecdpr.motion.carriage import carriage_joints, rail_of

    c = scenario.ship.carriage
    start = carriage_joints(scenario.ship, np.zeros(1))[0][0]
    if np.ptp(c.stations_m) == 0:
        return np.zeros(0, dtype=int), start
    points = np.asarray(c.rail_m, dtype=float)
    _, _, turn_a, turn_b = rail_of(scenario.ship).bends
    moving = [i for i in range(3) if np.ptp(points[:, i]) > 0] + ([3] if np.any(turn_a != turn_b) else [])
    return np.array(moving, dtype=int), start


def _carried(frame: str, scenario: Scenario) -> str:
    """The frame's body hung from the carriage's (see the module docstring), turned on it by
    the frame's lean at the rail's start (and its yaw there, where the yaw is no joint)."""
    Mc, Ic = CARRIAGE_MASS_KG, CARRIAGE_INERTIA_KG_M2
    axes = ("1 0 0", "0 1 0", "0 0 1")
    moving, start = carriage_coordinates(scenario)
    joints = "".join(f'\n        <joint name="{CARRIAGE_JOINTS[i]}" type="{"hinge" if i == 3 else "slide"}" '
                     f'axis="{axes[min(i, 2)]}"/>' for i in moving)
    place = np.where(np.isin(np.arange(3), moving), 0.0, start[:3])
    R = frame_axes(scenario.ship.frame_orientation_deg)
    if 3 not in moving and start[3] != 0.0:
        c, s = np.cos(start[3]), np.sin(start[3])
        R = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]) @ R
    quat = quaternion_from_matrix(R)
    frame = frame.replace('<body name="frame" pos="0 0 0">', f'<body name="frame" pos="0 0 0" quat="{_v(quat)}">', 1)
    return (f'      <body name="carriage" pos="{_v(place)}" gravcomp="1">{joints}\n'
            f'        <inertial pos="0 0 0" mass="{Mc:.17g}" diaginertia="{Ic:.17g} {Ic:.17g} {Ic:.17g}"/>\n'
            f'{frame}\n      </body>')


def quiet_mujoco_log() -> None:
    """Keep MuJoCo's warnings out of the user's folder and terminal.

    MuJoCo's default log appends each warning ("... The simulation is unstable") to
    ``MUJOCO_LOG.TXT`` in the working directory and prints it on stdout. The prototype
    reads the same warnings from ``mjData.warning`` and reports a diverged run itself
    (exit 4, one line), so the log is switched off for the process.
    """
    import mujoco

    config = mujoco.MjLogConfig.get()
    if config.logto_file or config.logto_console:
        config.logto_file = False
        config.logto_console = False
        mujoco.MjLogConfig.set(config)


def build_model(scenario: Scenario) -> MujocoModel:
    """Compile the scenario's MuJoCo model."""
    import mujoco

    quiet_mujoco_log()
    xml = build_xml(scenario)
    model = mujoco.MjModel.from_xml_string(xml)
    jid = lambda name: mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, name)  # noqa: E731
    ship = np.array([model.jnt_dofadr[jid(f"ship_{n}")] for n in ("x", "y", "z", "yaw", "pitch", "roll")])
    names = ("px", "pz", "pry") if scenario.robot.dofs == "planar" else ("px", "py", "pz", "pball")
    qpos = np.concatenate([np.arange(model.jnt_qposadr[jid(n)],
                                     model.jnt_qposadr[jid(n)] + (4 if n == "pball" else 1)) for n in names])
    dofs = np.concatenate([np.arange(model.jnt_dofadr[jid(n)],
                                     model.jnt_dofadr[jid(n)] + (3 if n == "pball" else 1)) for n in names])
    body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, "platform")
    offset = np.where(scenario.robot.pulley_radii > 0, PULLEY_INLET_M, 0.0)
    coords = carriage_coordinates(scenario)[0] if scenario.ship.carriage is not None else np.zeros(0, dtype=int)
    carriage = np.array([model.jnt_dofadr[jid(CARRIAGE_JOINTS[i])] for i in coords], dtype=int)
    return MujocoModel(model=model, xml=xml, ship_dofs=ship, platform_qpos=qpos, platform_dofs=dofs,
                       platform_body=body, tendon_offset=offset, carriage_dofs=carriage, carriage_coords=coords,
                       ship_inertia_kg_m2=ship_inertia(scenario))
