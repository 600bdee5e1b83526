"""Warnings when a robot's size is far outside cable-robot scale, or a value is implausible for
the robot's and the ship's own sizes (a unit slipped: a frame origin in millimetres, an inertia
a thousand times a plate's)."""

from __future__ import annotations


import numpy as np

from marinecdpr.scenario.schema import Scenario
# ----------------------------------------------------------------------- scale
FRAME_EXTENT_RANGE_M = (0.05, 200.0)
"""Sizes of a cable robot's frame (the box of its frame anchors, largest side) that pass unremarked, m."""
PLATFORM_EXTENT_MAX_M = 50.0
"""Largest platform (the box of its anchors, largest side) that passes unremarked, m."""


GYRATION_FACTOR = 3.0
"""How far a platform's largest radius of gyration, sqrt(I_max / m), may pass the distance of its
farthest anchor from its centre of mass before it is remarked (a rigid plate's is below it:
its mass lies within its anchors' reach, give or take the tools it carries)."""
STEEL_BALL_FACTOR = 3.0
"""How many times a solid steel ball's mass (7850 kg/m^3) of the platform anchors' reach a
platform may weigh before it is remarked (a mass in g for kg, or a tonne on a hand-sized plate)."""
HULL_MARGIN_SHARE = 0.1
"""How far outside the hull's box the frame's origin may lie before it is remarked: this share of
the hull's length, or the frame's own size if that is more (a frame may hang over the side)."""


def hull_box(scenario: Scenario) -> tuple[np.ndarray, np.ndarray, str] | None:
    """The box the hull fills in S, where the scenario gives the hull's size: (lo, hi, what).

    S's origin is amidships on the waterline, x forward, z up. The hull spans x in [-L/2, L/2],
    y in [-B/2, B/2] (a Wigley surface's flare widening it above the waterline) and z from the
    keel (-T) to its topside: the surface's highest band where ``[cleaning.surface]`` gives one,
    else a beam's height above the waterline (more than any ship's freeboard). The size comes
    from a ``box_hull`` RAO source (``[base_motion.rao]``) or a Wigley ``[cleaning.surface]``;
    None where neither is given (a mesh or an RAO file: their sizes are not read here).

    Returns
    -------
    lo, hi : ndarray, shape (3,)
        The box's corners in S, m.
    what : str
        Where the size comes from, as a reader would name it.
    """
    hull, what, flare, top = None, None, 0.0, None
    cleaning = scenario.cleaning
    surface = None if cleaning is None else cleaning.surface
    if surface is not None and surface.form == "wigley":
        hull, what = (surface.length_m, surface.beam_m, surface.draught_m), "[cleaning.surface]"
        flare, top = max(surface.flare, 0.0), float(surface.heights_m[1])
    else:
        rao = getattr(scenario.base_motion, "rao", None)
        if rao is not None and rao.source == "box_hull":
            hull, what = (rao.length_m, rao.beam_m, rao.draught_m), "the box hull of [base_motion.rao]"
    if hull is None:
        return None
    L, B, T = (float(v) for v in hull)
    top = B if top is None else max(top, 0.0)
    half = 0.5 * B * (1.0 + flare * (top / T) ** 2)
    return np.array([-0.5 * L, -half, -T]), np.array([0.5 * L, half, top]), f"{what} ({L:g} x {B:g} x {T:g} m)"


def plausibility_warnings(scenario: Scenario) -> list[str]:
    """One-line warnings where a value is implausible for the robot's and the ship's own sizes.

    * The frame's origin in S (``ship.frame_origin_m``, or the first of a carriage's rail
      points, ``ship.carriage.rail_m``) outside the box the hull fills
      (:func:`hull_box`) by more than :data:`HULL_MARGIN_SHARE` of the hull's length or the
      frame's size, whichever is more: the robot is not on that ship (a position in mm, or in
      another ship's axes).
    * The platform's largest radius of gyration sqrt(I_max / m) (I_max the largest principal
      moment of ``robot.inertia_kg_m2``) more than :data:`GYRATION_FACTOR` times its farthest
      anchor's distance from the centre of mass: an inertia in g m^2 for kg m^2, or of another
      body.
    * The platform's mass more than :data:`STEEL_BALL_FACTOR` times a solid steel ball's whose
      radius is its farthest anchor's distance: a mass in g for kg.

    Parameters
    ----------
    scenario : Scenario

    Returns
    -------
    list of str
        Empty where every value looks plausible.
    """
    out = []
    robot = scenario.robot
    box = hull_box(scenario)
    if box is not None:
        lo, hi, what = box
        carriage = scenario.ship.carriage
        places = ([("ship.frame_origin_m", scenario.ship.frame_origin_m)] if carriage is None else
                  [(f"ship.carriage.rail_m[{i}]", p) for i, p in enumerate(carriage.rail_m, start=1)])
        frame = float(np.ptp(robot.frame_anchors, axis=0).max())
        margin = max(HULL_MARGIN_SHARE * float(hi[0] - lo[0]), frame)
        for key, place in places:
            origin = np.asarray(place, dtype=float)
            outside = np.maximum(lo - origin, origin - hi).max()
            if outside > margin:
                out.append(f"{key} = [{', '.join(f'{v:g}' for v in origin)}] m lies {outside:.4g} m outside "
                           f"the hull of {what} (S's origin amidships on the waterline; the hull spans x "
                           f"{lo[0]:g} to {hi[0]:g} m, y {lo[1]:.4g} to {hi[1]:.4g} m, z {lo[2]:g} to {hi[2]:.4g} m): "
                           f"the frame's origin in S is in metres, where the robot stands on this hull")
                break
    reach = float(np.linalg.norm(robot.platform_anchors, axis=1).max())
    moments = np.linalg.eigvalsh(0.5 * (robot.inertia + robot.inertia.T))
    k = float(np.sqrt(max(float(moments.max()), 0.0) / robot.mass_kg))
    if reach > 0.0 and k > GYRATION_FACTOR * reach:
        out.append(f"robot.inertia_kg_m2 gives the {robot.mass_kg:g} kg platform a radius of gyration of {k:.3g} m, "
                   f"{k / reach:.3g} times the {reach:.3g} m from its centre of mass to its farthest anchor (a plate's "
                   f"is less than that distance): the moments are in kg m^2 about the centre of mass, e.g. m s^2 / 6 "
                   f"for a cube of side s")
    ball = 7850.0 * 4.0 / 3.0 * np.pi * reach ** 3
    if reach > 0.0 and robot.mass_kg > STEEL_BALL_FACTOR * ball:
        out.append(f"robot.mass_kg = {robot.mass_kg:g} kg is {robot.mass_kg / ball:.3g} times a solid steel ball "
                   f"as wide as the platform's anchors reach ({reach:.3g} m from its centre of mass, {ball:.3g} kg): "
                   f"the mass is in kg")
    return out


def scale_warnings(scenario: Scenario) -> list[str]:
    """One-line warnings when the robot's size is far outside cable-robot scale.

    Lengths in scenarios are in metres; a robot drawn in millimetres (a 4 km frame,
    a 400 m platform) still validates, and only plans badly. This names the sizes
    that look wrong and the likely cause. The frame's size is the largest side of
    the box of its frame anchors; the platform's, of the box of its platform anchors.
    The values implausible for these sizes follow, one line each
    (:func:`plausibility_warnings`).

    Parameters
    ----------
    scenario : Scenario

    Returns
    -------
    list of str
        Empty when the sizes look like a cable robot's.
    """
    robot = scenario.robot
    frame = float(np.ptp(robot.frame_anchors, axis=0).max())
    platform = float(np.ptp(robot.platform_anchors, axis=0).max())
    lo, hi = FRAME_EXTENT_RANGE_M
    facts = []
    if frame > hi:
        facts.append(f"the frame anchors span {frame:.4g} m (more than {hi:g} m)")
    elif frame < lo:
        facts.append(f"the frame anchors span only {frame:.4g} m (less than {lo * 100:g} cm)")
    if platform > PLATFORM_EXTENT_MAX_M:
        facts.append(f"the platform anchors span {platform:.4g} m (more than {PLATFORM_EXTENT_MAX_M:g} m)")
    if platform > frame:
        facts.append(f"the platform ({platform:.4g} m) is larger than the frame ({frame:.4g} m)")
    if not facts:
        return plausibility_warnings(scenario)
    if frame > hi and lo <= frame / 1000 <= hi:
        cause = "coordinates look like millimetres: scenario lengths are in metres (divide by 1000)"
    elif lo <= frame <= hi and platform > PLATFORM_EXTENT_MAX_M and platform / 1000 <= frame:
        cause = "the platform anchors look like millimetres: platform_anchor_m is in metres"
    elif lo <= frame <= hi:
        cause = "platform_anchor_m is measured from the platform's centre of mass (in P), in metres"
    else:
        cause = "scenario lengths are in metres"
    return [f"robot size far outside cable-robot scale: {'; '.join(facts)}; {cause}"] + plausibility_warnings(scenario)


