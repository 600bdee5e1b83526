"""Ship (base) motion as time series: the 6-DOF record and its exact derivatives.

The ship's generalised coordinates are ``eta = (x, y, z, roll, pitch, yaw)``:
the position of S's origin in O (surge, sway, heave; m) and the SNAME Euler
angles of R_SO = R_S^O = Rz(yaw) Ry(pitch) Rx(roll) (rad). Every source of base
motion (sinusoids here; sea spectra and records later) produces ``eta`` and its
first two time derivatives; :func:`ship_motion` turns them into the quantities the
dynamics need.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from .errors import ScenarioError
from .rotations import euler_kinematics
from .scenario import SHIP_DOFS, RecordedMotion, SeaStateMotion, SinusoidalMotion, StillMotion

__all__ = ["ShipMotion", "ship_motion", "evaluate_base_motion", "still_ship"]


@dataclass(frozen=True)
class ShipMotion:
    """The ship's motion over a time series (all arrays share ``n_steps``).

    Attributes
    ----------
    eta, eta_dot, eta_ddot : ndarray, shape (n_steps, 6)
        ``(x, y, z, roll, pitch, yaw)`` of S in O (m, rad) and derivatives.
    R_SO : ndarray, shape (n_steps, 3, 3)
        R_S^O: maps S-frame vectors to O.
    omega_SO_S : ndarray, shape (n_steps, 3)
        Ship angular velocity omega_SO expressed in S, rad/s.
    alpha_SO_S : ndarray, shape (n_steps, 3)
        Ship angular acceleration expressed in S, rad/s^2.
    """

    eta: np.ndarray
    eta_dot: np.ndarray
    eta_ddot: np.ndarray
    R_SO: np.ndarray
    omega_SO_S: np.ndarray
    alpha_SO_S: np.ndarray

    @property
    def x_SO_O(self) -> np.ndarray:
        """Position of S's origin in O, shape (n_steps, 3), m."""
        return self.eta[:, :3]

    @property
    def a_SO_O(self) -> np.ndarray:
        """Acceleration of S's origin in O, shape (n_steps, 3), m/s^2."""
        return self.eta_ddot[:, :3]

    @property
    def is_still(self) -> bool:
        return not (np.any(self.eta) or np.any(self.eta_dot) or np.any(self.eta_ddot))


def ship_motion(eta: np.ndarray, eta_dot: np.ndarray, eta_ddot: np.ndarray) -> ShipMotion:
    """Rotation, angular velocity and acceleration of the ship from its coordinates.

    Parameters
    ----------
    eta, eta_dot, eta_ddot : ndarray, shape (n_steps, 6)
        ``(x, y, z, roll, pitch, yaw)`` of S in O in m and rad, and their first
        and second time derivatives.

    Returns
    -------
    ShipMotion
    """
    eta = np.asarray(eta, dtype=float)
    eta_dot = np.asarray(eta_dot, dtype=float)
    eta_ddot = np.asarray(eta_ddot, dtype=float)
    R, omega, alpha = euler_kinematics(eta[:, 3:], eta_dot[:, 3:], eta_ddot[:, 3:])
    return ShipMotion(eta, eta_dot, eta_ddot, R, omega, alpha)


def still_ship(n_steps: int) -> ShipMotion:
    """A ship at rest with S on O, for ``n_steps`` samples (the fixed-base model)."""
    z = np.zeros((n_steps, 6))
    return ship_motion(z, z, z)


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
        from .seastate import synthesize

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
    # time-last buffers (see _vec): one contiguous row per DOF
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
def _rao(source_json: str):
    from .rao import box_hull_rao, read_capytaine, read_rao_csv
    from .scenario import RAOSource

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
    from .seastate import sea_record

    c = SeaStateMotion.model_validate_json(config_json)
    return sea_record(
        hs=c.hs_m, tp=c.tp_s, heading_deg=c.heading_deg, rao=_rao(c.rao.model_dump_json()),
        spectrum=c.spectrum, gamma=c.gamma,
        spreading_kind=None if c.spreading == "none" else c.spreading,
        spreading_exponent=c.spreading_exponent, n_directions=c.n_directions,
        record_s=c.record_s, seed=c.seed,
    )


def sea_record_of(config: SeaStateMotion):
    """The :class:`~marinecdpr.seastate.SeaRecord` of a sea-state base motion (cached)."""
    return _sea_record(config.model_dump_json())


@lru_cache(maxsize=8)
def _recording(config_json: str):
    from .recorded import read_motion_csv

    c = RecordedMotion.model_validate_json(config_json)
    kwargs = {} if c.smoothing_s is None else {"smoothing_s": c.smoothing_s}
    return read_motion_csv(c.file, z_axis=c.z_axis, angles=c.angles, **kwargs)
