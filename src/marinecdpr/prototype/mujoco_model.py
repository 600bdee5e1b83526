"""A MuJoCo model of any scenario's robot on its ship: the independent virtual prototype.

World frame = O (z up, gravity (0, 0, -g)). Bodies:

``ship``
    A very heavy rigid body (:data:`SHIP_MASS_KG`, isotropic inertia
    :data:`SHIP_INERTIA_KG_M2`; gravity compensated) on six joints in the order
    slide x, slide y, slide z, hinge z (yaw), hinge y (pitch), hinge x (roll): MuJoCo
    applies a body's joints in order, each about the axes left by the previous ones,
    so the ship's orientation is Rz(yaw) Ry(pitch) Rx(roll) = R_SO and its joint
    positions and velocities are the ship coordinates eta and their rates (of S', which has
    S's origin and C's axes, where ``ship.frame_orientation_deg`` turns the frame on the
    ship: :func:`~marinecdpr.motion.ship.in_frame_axes`). The
    simulation drives these joints with generalised forces (feed-forward of the
    analytic motion plus a stiff servo), so the ship has true velocity and
    acceleration; the cables' reaction barely moves a ship this heavy.

    A frame carried on a rail (``[ship.carriage]``): the same body on the same six joints
    moves as C itself, driven along C's composed motion in O (the ship's composed with the
    carriage's, :func:`~marinecdpr.motion.basemotion.frame_ship_motion`, the motion the own
    plant and the planner take): its joints are C's origin in O and the Euler angles of R_CO
    (:func:`~marinecdpr.motion.ship.body_coordinates`). The model then has the standing
    frame's bodies and DOFs (a ship body and a carriage body on four more driven joints cost
    MuJoCo's RK4 a fifth more per step); the carriage's drive force is the carriage part's
    record (:mod:`~marinecdpr.prototype.parts.carriage`), not a joint's.
``frame``
    Robot frame C, fixed to the ship at ``ship.frame_origin_m`` (in S'; at the body's origin
    for a carried frame, :func:`~marinecdpr.motion.basemotion.frame_origin_of`); holds the
    frame anchors.
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

from dataclasses import dataclass

import numpy as np

from marinecdpr.errors import ScenarioError
from marinecdpr.motion.basemotion import frame_origin_of
from marinecdpr.scenario.schema import Scenario

__all__ = ["MujocoModel", "build_model", "SHIP_MASS_KG", "SHIP_INERTIA_KG_M2"]

PULLEY_INLET_M = 0.05
"""How far back along its arrival direction a pulley cable's tendon starts, m."""
SHIP_MASS_KG = 1.0e7
SHIP_INERTIA_KG_M2 = 1.0e8
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
    Ms, Is = SHIP_MASS_KG, SHIP_INERTIA_KG_M2
    frame = f"""      <body name="frame" pos="{_v(frame_origin_of(scenario))}">
{frame_sites}
        <body name="platform" pos="0 0 0">
          {joints}
          <inertial pos="0 0 0" mass="{r.mass_kg:.17g}" fullinertia="{_v(full)}"/>
{plat_sites}
        </body>
      </body>"""
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
    return MujocoModel(model=model, xml=xml, ship_dofs=ship, platform_qpos=qpos, platform_dofs=dofs,
                       platform_body=body, tendon_offset=offset)
