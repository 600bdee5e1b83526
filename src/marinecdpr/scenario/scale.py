"""Warnings when a robot's size is far outside cable-robot scale."""

from __future__ import annotations


import numpy as np

from marinecdpr.scenario.schema import Scenario
# ----------------------------------------------------------------------- scale
FRAME_EXTENT_RANGE_M = (0.05, 200.0)
"""Sizes of a cable robot's frame (the box of its frame anchors, largest side) that pass unremarked, m."""
PLATFORM_EXTENT_MAX_M = 50.0
"""Largest platform (the box of its anchors, largest side) that passes unremarked, m."""


def scale_warnings(scenario: Scenario) -> list[str]:
    """One-line warnings when the robot's size is far outside cable-robot scale.

    Lengths in scenarios are in metres; a robot drawn in millimetres (a 4 km frame,
    a 400 m platform) still validates, and only plans badly. This names the sizes
    that look wrong and the likely cause. The frame's size is the largest side of
    the box of its frame anchors; the platform's, of the box of its platform anchors.

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
        return []
    if frame > hi and lo <= frame / 1000 <= hi:
        cause = "coordinates look like millimetres: scenario lengths are in metres (divide by 1000)"
    elif lo <= frame <= hi and platform > PLATFORM_EXTENT_MAX_M and platform / 1000 <= frame:
        cause = "the platform anchors look like millimetres: platform_anchor_m is in metres"
    elif lo <= frame <= hi:
        cause = "platform_anchor_m is measured from the platform's centre of mass (in P), in metres"
    else:
        cause = "scenario lengths are in metres"
    return [f"robot size far outside cable-robot scale: {'; '.join(facts)}; {cause}"]


