"""The wind's drag on the platform and on the cables (``[wind]``; issue 40, item 1).

The wind at a point is ``U e_w`` in O with ``U = G U(z) + u_g(t)`` (:mod:`marinecdpr.motion.wind`:
U(z) the mean profile at the point's height, G a gust factor, u_g the gust series; e_w the
direction it blows along). The drag acts on the wind relative to the body, u_rel = U e_w - v,
with v the body's velocity in O: the platform moves with the ship and on its cables, and both
motions change the wind it meets (DNV-RP-C205 §5.1: the relative velocity in the drag term).

Platform (DNV-RP-C205 §5.4, 1/2 rho C A U^2, taken on each of P's axes; no moment: the centre
of pressure is taken at the centre of mass)::

    u_P = R_PC^T R_SO^T u_rel,     F_P = 1/2 rho C |u_P| (A_x u_x, A_y u_y, A_z u_z),     f_C = R_PC F_P

so that a wind along one of P's axes meets its projected area: |F| = 1/2 rho C A U^2.

Cable (a cylinder in cross flow: only the wind's component normal to it, u_n = u - (u.e) e with
e its unit direction, drags; per metre)::

    f'(s) = 1/2 rho C_D d |u_n| u_n

over the straight cable of length L, taken at its midpoint (the wind's height and the cable's
velocity there: exact for a wind that does not change along the cable, the midpoint rule
otherwise): F = L f'(mid). The cable's ends share the distributed load; on a straight cable
loaded uniformly each end carries half, so the platform's anchor takes F / 2 (and its moment
about the centre of mass), the frame's anchor the other half (the frame is the ship's: it does
not enter the platform's wrench).

Every vector is in C unless named otherwise (``_O``); units SI; rho the air's density.
"""

from __future__ import annotations

import numpy as np

from functools import lru_cache

from marinecdpr.model.dynamics import absolute_motion
from marinecdpr.motion.basemotion import frame_origin_of
from marinecdpr.motion.ship import ShipMotion
from marinecdpr.motion.wind import GustSeries, gust_series, wind_direction_O, wind_speed_at
from marinecdpr.scenario.wind import AIR_DENSITY_KG_M3

__all__ = ["platform_drag", "cable_drag", "wind_loads", "scenario_gust", "scenario_wind_loads"]


def platform_drag(u_rel_O: np.ndarray, R_SO: np.ndarray, R_PC: np.ndarray, *, rho: float, shape_coefficient: float,
                  area_P: np.ndarray) -> np.ndarray:
    """The wind's drag on the platform, in C.

    Parameters
    ----------
    u_rel_O : ndarray, shape (n_steps, 3)
        The wind relative to the platform, in O, m/s.
    R_SO, R_PC : ndarray, shape (n_steps, 3, 3)
        C's axes in O (the models' ship) and P's in C.
    rho : float
        The air's density, kg/m^3.
    shape_coefficient : float
        C.
    area_P : ndarray, shape (3,)
        The areas projected normal to P's x, y, z, m^2.

    Returns
    -------
    f_C : ndarray, shape (n_steps, 3)
        N, in C (about the centre of mass: no moment).
    """
    u_C = np.einsum("nji,nj->ni", R_SO, u_rel_O)
    u_P = np.einsum("nji,nj->ni", R_PC, u_C)
    speed = np.sqrt(np.einsum("ni,ni->n", u_P, u_P))
    F_P = (0.5 * rho * shape_coefficient) * speed[:, None] * (np.asarray(area_P, dtype=float) * u_P)
    return np.einsum("nij,nj->ni", R_PC, F_P)


def cable_drag(u_rel_O: np.ndarray, e_O: np.ndarray, lengths: np.ndarray, *, rho: float, drag_coefficient: float,
               diameter: float) -> np.ndarray:
    """The wind's whole drag on each straight cable, in O (the distributed load times the length).

    Parameters
    ----------
    u_rel_O : ndarray, shape (n_steps, n_cables, 3)
        The wind relative to each cable's midpoint, in O, m/s.
    e_O : ndarray, shape (n_steps, n_cables, 3)
        Each cable's unit direction, in O.
    lengths : ndarray, shape (n_steps, n_cables)
        L, m.
    rho : float
        kg/m^3.
    drag_coefficient, diameter : float
        C_D and d (m).

    Returns
    -------
    F_O : ndarray, shape (n_steps, n_cables, 3)
        N (the platform's end takes half).
    """
    u_n = u_rel_O - np.einsum("nci,nci->nc", u_rel_O, e_O)[..., None] * e_O
    speed = np.sqrt(np.einsum("nci,nci->nc", u_n, u_n))
    return ((0.5 * rho * drag_coefficient * diameter) * lengths * speed)[..., None] * u_n


def wind_loads(wind, x_PC: np.ndarray, twist: np.ndarray, R_PC: np.ndarray, ship: ShipMotion, *,
               frame_origin_S: np.ndarray, frame_anchors: np.ndarray, platform_anchors: np.ndarray,
               gust: np.ndarray | float = 0.0, gust_factor: float = 1.0, rho: float) -> tuple[np.ndarray, np.ndarray]:
    """The wind's force and moment on the platform (its own drag and its cables' shares), in C.

    Parameters
    ----------
    wind : marinecdpr.scenario.wind.Wind
        The ``[wind]`` section.
    x_PC : ndarray, shape (n_steps, 3)
        The platform's centre of mass in C, m.
    twist : ndarray, shape (n_steps, 6)
        (v_PC, omega_PC) in C, m/s and rad/s.
    R_PC : ndarray, shape (n_steps, 3, 3)
    ship : ShipMotion
        C's motion in O (the models' ship).
    frame_origin_S : ndarray, shape (3,)
        C's origin in the ship's frame, m.
    frame_anchors : ndarray, shape (n_cables, 3)
        Where the straight cables start, in C, m.
    platform_anchors : ndarray, shape (n_cables, 3)
        Their platform anchors in P, m.
    gust : float or ndarray, shape (n_steps,)
        u_g(t), m/s.
    gust_factor : float
        G.
    rho : float
        kg/m^3.

    Returns
    -------
    f_C, m_C : ndarray, shape (n_steps, 3)
        N and N m about the centre of mass, in C: the load on the platform (the disturbance's
        f_r, m_r).
    """
    x_PC = np.asarray(x_PC, dtype=float)
    n = x_PC.shape[0]
    e_w = wind_direction_O(wind.direction_deg)
    gust = np.broadcast_to(np.asarray(gust, dtype=float), (n,))
    zeros6 = np.zeros((n, 6))

    def wind_at(x_O):  # the wind's vector at points x_O (n, 3) in O
        U = gust_factor * wind_speed_at(x_O[:, 2] - wind.sea_level_m, wind.speed_m_s, wind.reference_height_m,
                                        wind.profile_exponent) + gust
        return U[:, None] * e_w

    body = absolute_motion(x_PC, twist, zeros6, ship, frame_origin_S=frame_origin_S)
    f_C = platform_drag(wind_at(body.x_PO_O) - body.v_PO_O, ship.R_SO, R_PC, rho=rho,
                        shape_coefficient=wind.platform_shape_coefficient,
                        area_P=np.asarray(wind.platform_area_m2, dtype=float))
    m_C = np.zeros((n, 3))
    if wind.cable_diameter_m == 0.0:
        return f_C, m_C
    r = np.einsum("nij,cj->nci", R_PC, np.asarray(platform_anchors, dtype=float))  # the anchors from P, in C
    b = x_PC[:, None, :] + r
    chord = b - np.asarray(frame_anchors, dtype=float)[None]
    lengths = np.sqrt(np.einsum("nci,nci->nc", chord, chord))
    e_O = np.einsum("nij,ncj->nci", ship.R_SO, chord / lengths[..., None])
    v_b = twist[:, None, :3] + np.cross(twist[:, None, 3:], r)  # the platform anchors' velocity in C
    u_rel = np.empty(chord.shape)
    for c in range(chord.shape[1]):  # each cable's midpoint: where it is and how fast it moves in O
        mid = absolute_motion(b[:, c] - 0.5 * chord[:, c], np.concatenate([0.5 * v_b[:, c], np.zeros((n, 3))], 1),
                              zeros6, ship, frame_origin_S=frame_origin_S)
        u_rel[:, c] = wind_at(mid.x_PO_O) - mid.v_PO_O
    F_C = np.einsum("nji,ncj->nci", ship.R_SO, cable_drag(u_rel, e_O, lengths, rho=rho,
                                                          drag_coefficient=wind.cable_drag_coefficient,
                                                          diameter=wind.cable_diameter_m))
    half = 0.5 * F_C
    return f_C + half.sum(axis=1), m_C + np.cross(r, half).sum(axis=1)


@lru_cache(maxsize=8)
def _gust(u0: float, z: float, record_s: float, f_max: float, seed: int) -> GustSeries:
    series = gust_series(u0, z, record_s, f_max, seed)
    series.u.flags.writeable = False  # shared by every caller
    return series


def scenario_gust(wind) -> GustSeries | None:
    """The ``[wind]`` section's gust series (:func:`~marinecdpr.motion.wind.gust_series`, the same
    for every caller: made once per section's figures), None with ``gust = "none"``."""
    if wind.gust == "none":
        return None
    return _gust(float(wind.speed_m_s), float(wind.gust_height_m), float(wind.record_s),
                 float(wind.frequency_max_hz), int(wind.seed))


def scenario_wind_loads(scenario, x_PC: np.ndarray, twist: np.ndarray, R_PC: np.ndarray, ship: ShipMotion,
                        t: np.ndarray, *, gust: str = "plan") -> tuple[np.ndarray, np.ndarray]:
    """The scenario's wind on the platform along a motion (:func:`wind_loads` with its robot's
    straight cables from their frame anchors), in C.

    Parameters
    ----------
    scenario : Scenario
        With a ``[wind]`` section.
    x_PC, twist, R_PC, ship
        As :func:`wind_loads`.
    t : ndarray, shape (n_steps,)
        Times, s (the gust's).
    gust : {"plan", "series"}
        "plan": what ``wind.plan_gust`` names (the mean, the series, or the mean times a gust
        factor); "series": the mean plus the gust series (what the plants meet).

    Returns
    -------
    f_C, m_C : ndarray, shape (n_steps, 3)
        N and N m about the centre of mass, in C.
    """
    wind = scenario.wind
    choice = "series" if gust == "series" else wind.plan_gust
    factor, u_g = 1.0, 0.0
    if choice == "series":
        series = scenario_gust(wind)
        u_g = 0.0 if series is None else series.at(t)
    elif choice != "mean":
        factor = float(choice)
    robot = scenario.robot
    return wind_loads(wind, x_PC, twist, R_PC, ship, frame_origin_S=frame_origin_of(scenario),
                      frame_anchors=robot.frame_anchors, platform_anchors=robot.platform_anchors,
                      gust=u_g, gust_factor=factor, rho=AIR_DENSITY_KG_M3)
