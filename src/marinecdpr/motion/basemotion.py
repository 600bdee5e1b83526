"""The ship's motion a scenario's ``[base_motion]`` describes, evaluated at given times.

Each source (still, sinusoids, a sea state through RAOs, a recorded file) gives ``eta``
and its first two time derivatives; :func:`~marinecdpr.motion.ship.ship_motion` (where
``eta`` and the frames are defined) turns them into the quantities the dynamics need.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from marinecdpr.errors import ScenarioError
from marinecdpr.motion.carriage import carried_frame_motion
from marinecdpr.motion.ship import (
    ShipMotion, frame_axes, frame_origin_in_axes, in_frame_axes, ship_motion, still_ship,
)
from marinecdpr.scenario.fields import SHIP_DOFS
from marinecdpr.scenario.schema import RecordedMotion, SeaStateMotion, SinusoidalMotion, StillMotion

__all__ = ["evaluate_base_motion", "seen_by_frame", "frame_ship_motion", "fixed_ship_motion", "frame_origin_of",
           "rao_from_source"]


def seen_by_frame(ship: ShipMotion, scenario) -> ShipMotion:
    """A ship motion as the scenario's robot's models take it: seen in the frame's axes
    (:func:`~marinecdpr.motion.ship.in_frame_axes`, where ``ship.frame_orientation_deg``
    turns C on S; the motion itself where it does not)."""
    return in_frame_axes(ship, frame_axes(scenario.ship.frame_orientation_deg)) if scenario.ship.turned else ship


def frame_ship_motion(scenario, t: np.ndarray) -> ShipMotion:
    """The scenario's base motion at times ``t`` as its robot's models take it: seen in the
    frame's axes (:func:`seen_by_frame`), or, for a frame carried on a rail
    (``[ship.carriage]``), the motion of C itself, the ship's composed with the carriage's
    (:func:`~marinecdpr.motion.carriage.carried_frame_motion`; C's origin then at
    :func:`frame_origin_of`'s zero)."""
    ship = evaluate_base_motion(scenario.base_motion, t)
    if scenario.ship.carriage is None:
        return seen_by_frame(ship, scenario)
    return carried_frame_motion(ship, scenario.ship, t)


def frame_origin_of(scenario) -> np.ndarray:
    """C's origin where the models take it, shape (3,), m: in S, or in S' (S's origin, C's
    axes) where the frame is turned on the ship (:func:`~marinecdpr.motion.ship.frame_origin_in_axes`);
    zero for a frame on a carriage, whose own motion the models take."""
    ship = scenario.ship
    if ship.carriage is not None:  # the models take C's own motion (frame_ship_motion)
        return np.zeros(3)
    if not ship.turned:
        return np.asarray(ship.frame_origin_m, dtype=float)
    return frame_origin_in_axes(ship.frame_origin_m, ship.frame_orientation_deg)


def fixed_ship_motion(scenario, t: np.ndarray) -> ShipMotion:
    """The fixed-base model's ship (at rest, S on O) at times ``t`` as the scenario's robot sees
    it: turned by the frame's orientation, so that gravity keeps its direction in C; a frame on
    a carriage still runs along its rail."""
    t = np.asarray(t, dtype=float)
    if scenario.ship.carriage is None:
        return seen_by_frame(still_ship(t.size), scenario)
    return carried_frame_motion(still_ship(t.size), scenario.ship, t)


def evaluate_base_motion(
    config: StillMotion | SinusoidalMotion | SeaStateMotion | RecordedMotion, t: np.ndarray
) -> ShipMotion:
    """The ship's motion a scenario's ``[base_motion]`` describes, at times ``t``.

    Parameters
    ----------
    config : StillMotion, SinusoidalMotion, SeaStateMotion or RecordedMotion
        The scenario's base motion.
    t : ndarray, shape (n_steps,)
        Times, s.
    """
    t = np.asarray(t, dtype=float)
    if isinstance(config, StillMotion):
        return still_ship(t.size)
    if isinstance(config, SeaStateMotion):
        from marinecdpr.motion.seastate import synthesize

        return ship_motion(*synthesize(sea_record_of(config), t))
    if isinstance(config, RecordedMotion):
        rec = _recording(config.model_dump_json())
        t0, t1 = rec.time_range_s
        ask = t + config.start_s
        if t.size and (ask.min() < t0 - 1e-9 or ask.max() > t1 + 1e-9):
            raise ScenarioError(
                f"the scenario needs the record from {ask.min():g} s to {ask.max():g} s, but "
                f"{config.file} covers {t0:g} s to {t1:g} s (shorten time.duration_s or move start_s)",
                key="base_motion")
        return rec.evaluate(ask)
    # time-last buffers (see geometry.vec): one contiguous row per DOF
    eta = np.zeros((6, t.size))
    eta_dot = np.zeros_like(eta)
    eta_ddot = np.zeros_like(eta)
    trig: dict[tuple[float, float], tuple[np.ndarray, np.ndarray]] = {}
    for comp in config.components:
        k = SHIP_DOFS.index(comp.dof)
        w = 2.0 * np.pi / comp.period_s
        key = (w, comp.phase_deg)
        if key not in trig:  # components often share a frequency and phase
            phase = w * t + np.radians(comp.phase_deg)
            trig[key] = (np.sin(phase), np.cos(phase))
        s, c = trig[key]
        eta[k] += comp.offset + comp.amplitude * s
        eta_dot[k] += comp.amplitude * w * c
        eta_ddot[k] -= comp.amplitude * w * w * s
    return ship_motion(eta.T, eta_dot.T, eta_ddot.T)


@lru_cache(maxsize=32)
def rao_from_source(source_json: str):
    """The ship's RAOs (:class:`~marinecdpr.motion.rao.RAO`) a scenario's
    ``[base_motion.rao]`` names, read or made once per source (the last 32 are kept).

    Parameters
    ----------
    source_json : str
        The :class:`~marinecdpr.scenario.schema.RAOSource` as JSON (hashable, for the cache):
        a CSV table, a Capytaine dataset, or the box hull's dimensions (then on 600
        frequencies from 0.02 to 6 rad/s and headings every 5 deg).
    """
    from marinecdpr.motion.rao import box_hull_rao, read_capytaine, read_rao_csv
    from marinecdpr.scenario.schema import RAOSource

    src = RAOSource.model_validate_json(source_json)
    if src.source == "csv":
        return read_rao_csv(src.file)
    if src.source == "capytaine":
        return read_capytaine(src.file)
    return box_hull_rao(length_m=src.length_m, beam_m=src.beam_m, draught_m=src.draught_m,
                        gm_m=src.gm_m, roll_damping_ratio=src.roll_damping_ratio,
                        omega=np.linspace(0.02, 6.0, 600), heading_deg=np.arange(0.0, 360.0, 5.0))


@lru_cache(maxsize=64)
def _sea_record(config_json: str):
    from marinecdpr.motion.seastate import sea_record

    c = SeaStateMotion.model_validate_json(config_json)
    return sea_record(
        hs=c.hs_m, tp=c.tp_s, heading_deg=c.heading_deg, rao=rao_from_source(c.rao.model_dump_json()),
        spectrum=c.spectrum, gamma=c.gamma,
        spreading_kind=None if c.spreading == "none" else c.spreading,
        spreading_exponent=c.spreading_exponent, n_directions=c.n_directions,
        record_s=c.record_s, seed=c.seed,
    )


def sea_record_of(config: SeaStateMotion):
    """The :class:`~marinecdpr.motion.seastate.SeaRecord` of a sea-state base motion (cached)."""
    return _sea_record(config.model_dump_json())


@lru_cache(maxsize=8)
def _recording(config_json: str):
    from marinecdpr.motion.recorded import read_motion_csv

    c = RecordedMotion.model_validate_json(config_json)
    kwargs = {} if c.smoothing_s is None else {"smoothing_s": c.smoothing_s}
    return read_motion_csv(c.file, z_axis=c.z_axis, angles=c.angles, **kwargs)
