"""Winches as built: what a cable's motion and tension ask of a winch's motor, the tensions
a winch can give at each step, and the winch's dynamics as a part of the virtual prototype.

A winch is a drum of radius r_d (m) driven through a gearbox of ratio G (motor turns per
drum turn) and efficiency eta_g by a motor with a torque limit tau_max (N m), a speed
limit omega_max (rad/s) and a power limit P_max (W), all at the motor; the rotor's inertia
J_m (kg m^2) is on the motor side, the drum's J_d (kg m^2) on the drum side, the friction
(Coulomb tau_c, N m, and viscous b, N m s/rad) on the motor side.

Sign conventions
----------------
- L' > 0: the cable **pays out** (lengthens); L' < 0: the winch **winds in**.
- The motor's angle, speed omega_m, acceleration alpha_m and torque tau_m are positive in
  the **winding-in** sense: the sense that hauls the cable in and that holds its tension.
  The drum turns theta_d' = -L' / r_d, the motor G times faster::

      omega_m = -G L'  / r_d                                     (rad/s)
      alpha_m = -G L'' / r_d                                     (rad/s^2)

  (reeling in at 1 m/s on a 0.05 m drum through G = 10: omega_m = +200 rad/s).
- T >= 0 is the cable's tension, N. It pulls the drum in the pay-out sense, so a motor at
  rest holds it with tau_m = T r_d / G > 0.
- P = tau_m omega_m is the motor shaft's mechanical power, W: > 0 **motoring** (winding in
  under tension: the drive gives energy to the cable), < 0 **generating** (paying out under
  tension: the cable drives the motor, which brakes).

Torque balance, reflected to the motor::

    J_eff alpha_m = tau_m - tau_T - b omega_m - tau_c sgn(omega_m)
    J_eff         = J_m + J_d / G^2
    tau_T         = (T r_d / G) / eta_g   if (T r_d / G) omega_m >= 0   motoring, and at rest
                  = (T r_d / G) eta_g     otherwise                      generating

so the torque the motor must give to hold T while the cable moves with L', L'' is::

    tau_m = tau_T + J_eff alpha_m + b omega_m + tau_c sgn(omega_m)

The gearbox's losses act on the tension's torque only (the drum's inertia and the friction
are lumped at the motor without them). At rest (omega_m = 0) the gearbox is taken as
motoring, the conservative case for holding and starting to haul in (a real gearbox holds
with anything between eta_g and 1 / eta_g of T r_d / G), and the Coulomb friction as
opposing the motion about to start, sgn(alpha_m) (0 at rest without acceleration).

The limits, with the power limit both ways (the drive's rating bounds the energy it gives
and the energy it must absorb)::

    |omega_m| <= omega_max,    |tau_m| <= tau_max,    |tau_m omega_m| <= P_max
    <=>  |tau_m| <= tau_lim(omega_m) = min(tau_max, P_max / |omega_m|)

Functions over time series (numpy; arrays (n_steps, m), one column per cable; a single
:class:`WinchParams` shared by every cable or one per cable):

- :func:`winch_motor_state`    motor speed, torque and power per step and cable;
- :func:`winch_tension_bounds` the tensions [T_lo, T_hi] each winch can hold at each step,
  within the cable's [T_min, T_max], and where it cannot follow at all;
- :func:`winch_report`         per winch: peak torque, speed, power and the energy;
- :func:`length_accelerations` L'' from a plan's L' (the :class:`~marinecdpr.planning.Plan`
  holds ``length_rates`` but no accelerations).

For a plan: ``winch_report(plan.tensions, plan.length_rates,
length_accelerations(plan.length_rates, dt), dt, params)``.

The prototype part (compiled, no allocation): a :class:`WinchDrive` record of the winches'
parameters (one per cable), tension-loop gains and state, built by :func:`winch_drive`;
:func:`tension_control_step` computes the motor torque from the commanded tension,
:func:`winch_motor_step` integrates the motor one step under the cable's tension with the
torque, power and speed limits, :func:`winch_dynamics_step` does both.
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from typing import NamedTuple, Sequence

import numpy as np
from numba import njit

__all__ = [
    "WinchParams",
    "MotorState",
    "TensionBounds",
    "WinchReport",
    "winch_motor_state",
    "winch_tension_bounds",
    "winch_report",
    "length_accelerations",
    "WinchDrive",
    "winch_drive",
    "tension_loop_damping",
    "tension_control_step",
    "winch_motor_step",
    "winch_dynamics_step",
    "FREE",
    "TORQUE_LIMITED",
    "SPEED_LIMITED",
    "OVERSPEED",
]

_cache = True

FREE, TORQUE_LIMITED, SPEED_LIMITED, OVERSPEED = 0, 1, 2, 3
"""Codes of :attr:`WinchDrive.limited` after a step: 0 the commanded torque acted; 1 it was
cut to the torque or power limit; 2 the speed limiter cut it to hold |omega_m| at
omega_max; 3 even the limited torque could not hold the speed (the cable drives the motor
past omega_max)."""


# ------------------------------------------------------------------------- parameters


@dataclass(frozen=True)
class WinchParams:
    """One winch's design (SI units). The values are checked on construction.

    Attributes
    ----------
    drum_radius_m : float
        r_d, m, > 0 (the radius to the cable's centre on the drum).
    gear_ratio : float
        G, motor turns per drum turn, > 0.
    torque_max_Nm : float
        tau_max, the motor's torque limit, N m at the motor, > 0 (inf: none).
    speed_max_rad_s : float
        omega_max, the motor's speed limit, rad/s, > 0 (inf: none).
    power_max_W : float
        P_max, the limit on |tau_m omega_m|, W, > 0 (inf: none).
    rotor_inertia_kg_m2 : float
        J_m, the motor's rotor (and anything turning at motor speed), kg m^2, >= 0.
    drum_inertia_kg_m2 : float
        J_d, the drum (and anything turning at drum speed), kg m^2, >= 0.
    gear_efficiency : float
        eta_g, in (0, 1].
    coulomb_friction_Nm : float
        tau_c, at the motor, N m, >= 0.
    viscous_friction_Nm_s : float
        b, at the motor, N m per rad/s, >= 0.
    """

    drum_radius_m: float
    gear_ratio: float
    torque_max_Nm: float
    speed_max_rad_s: float
    power_max_W: float
    rotor_inertia_kg_m2: float = 0.0
    drum_inertia_kg_m2: float = 0.0
    gear_efficiency: float = 1.0
    coulomb_friction_Nm: float = 0.0
    viscous_friction_Nm_s: float = 0.0

    def __post_init__(self):
        for f in fields(self):
            value = getattr(self, f.name)
            if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
                raise ValueError(f"winch: {f.name} must be a number, got {value!r}")
            object.__setattr__(self, f.name, float(value))
        positive = ("drum_radius_m", "gear_ratio")
        limits = ("torque_max_Nm", "speed_max_rad_s", "power_max_W")
        non_negative = ("rotor_inertia_kg_m2", "drum_inertia_kg_m2", "coulomb_friction_Nm",
                        "viscous_friction_Nm_s")
        for name in positive:
            v = getattr(self, name)
            if not (np.isfinite(v) and v > 0.0):
                raise ValueError(f"winch: {name} must be a finite number > 0, got {v}")
        for name in limits:
            v = getattr(self, name)
            if not v > 0.0:  # also NaN; inf allowed: no limit
                raise ValueError(f"winch: {name} must be > 0 (inf for no limit), got {v}")
        for name in non_negative:
            v = getattr(self, name)
            if not (np.isfinite(v) and v >= 0.0):
                raise ValueError(f"winch: {name} must be a finite number >= 0, got {v}")
        eta = self.gear_efficiency
        if not (0.0 < eta <= 1.0):
            raise ValueError(f"winch: gear_efficiency must be in (0, 1], got {eta}")

    @property
    def inertia_kg_m2(self) -> float:
        """J_eff = J_m + J_d / G^2, kg m^2 at the motor."""
        return self.rotor_inertia_kg_m2 + self.drum_inertia_kg_m2 / self.gear_ratio**2

    @property
    def line_speed_max_m_s(self) -> float:
        """The fastest the cable can move, omega_max r_d / G, m/s."""
        return self.speed_max_rad_s * self.drum_radius_m / self.gear_ratio

    @property
    def holding_tension_N(self) -> float:
        """The largest tension held at rest without acceleration, tau_max G eta_g / r_d, N
        (the gearbox taken as motoring, the Coulomb friction as not helping)."""
        return self.torque_max_Nm * self.gear_ratio * self.gear_efficiency / self.drum_radius_m


_NAMES = ("r", "G", "eta", "tau_max", "omega_max", "P_max", "J", "b", "tau_c")


class _Arrays(NamedTuple):
    """Parameters as arrays: 0-d (one winch for all cables) or (m,) (one per cable)."""

    r: np.ndarray
    G: np.ndarray
    eta: np.ndarray
    tau_max: np.ndarray
    omega_max: np.ndarray
    P_max: np.ndarray
    J: np.ndarray
    b: np.ndarray
    tau_c: np.ndarray


def _values(p: WinchParams) -> tuple[float, ...]:
    return (p.drum_radius_m, p.gear_ratio, p.gear_efficiency, p.torque_max_Nm, p.speed_max_rad_s,
            p.power_max_W, p.inertia_kg_m2, p.viscous_friction_Nm_s, p.coulomb_friction_Nm)


def _arrays(params: WinchParams | Sequence[WinchParams], m: int | None = None) -> _Arrays:
    """The parameters as arrays over the cables: 0-d for a shared winch (or (m,) if m is
    given), (m,) for one per cable. Raises ValueError for a count that is not m."""
    if isinstance(params, WinchParams):
        values = np.array(_values(params), dtype=float)
        if m is not None:
            values = np.repeat(values[:, None], m, axis=1)
        return _Arrays(*values)
    params = list(params)
    if not params or not all(isinstance(p, WinchParams) for p in params):
        raise ValueError("winch: params must be a WinchParams or a sequence of them, one per cable")
    if m is not None and len(params) != m:
        raise ValueError(f"winch: {len(params)} WinchParams given for {m} cables")
    return _Arrays(*np.array([_values(p) for p in params], dtype=float).T.copy())


def _series(*arrays, params, names):
    """Broadcast the series to (n_steps, m) (a 1-d series is one step), checking the cables."""
    out = [np.asarray(a, dtype=float) for a in arrays]
    for name, a in zip(names, out):
        if a.ndim > 2:
            raise ValueError(f"winch: {name} must be (n_steps, m) or (m,), got shape {a.shape}")
    try:
        out = np.broadcast_arrays(*[np.atleast_2d(a) for a in out])
    except ValueError:
        shapes = ", ".join(f"{n} {a.shape}" for n, a in zip(names, out))
        raise ValueError(f"winch: the series' shapes disagree: {shapes}") from None
    m = out[0].shape[1]
    p = _arrays(params)
    if p.r.ndim == 1 and p.r.size != m:
        raise ValueError(f"winch: {p.r.size} WinchParams given for {m} cables")
    return out, p


# --------------------------------------------------------------------- the equations


def _motor_motion(L_dot, L_ddot, p):
    """omega_m = -G L' / r_d, alpha_m = -G L'' / r_d (rad/s, rad/s^2; winding in > 0)."""
    return -p.G * L_dot / p.r + 0.0, -p.G * L_ddot / p.r + 0.0  # + 0.0: no -0.0 at rest


def _friction_sign(omega, alpha):
    """sgn(omega_m), or at rest sgn(alpha_m): friction opposes the motion (about to start)."""
    return np.where(omega != 0.0, np.sign(omega), np.sign(alpha))


def _tension_torque(T, omega, p):
    """tau_T: the tension's torque at the motor, efficiency applied by the power's direction."""
    load = T * p.r / p.G  # T r_d / G
    return np.where(load * omega >= 0.0, load / p.eta, load * p.eta)


def _tension_from_torque(a, omega, p):
    """The tension whose tau_T is a (the inverse of :func:`_tension_torque`, monotone)."""
    load = np.where(a * omega >= 0.0, a * p.eta, a / p.eta)  # motoring: a = load / eta
    return load * p.G / p.r


@dataclass(frozen=True)
class MotorState:
    """What the motion and tension ask of the motors; arrays (n_steps, m).

    Attributes
    ----------
    speed_rad_s : omega_m, rad/s, positive winding in.
    acceleration_rad_s2 : alpha_m, rad/s^2, positive winding in.
    torque_Nm : tau_m, N m at the motor, positive winding in (holding the tension).
    power_W : tau_m omega_m, W, mechanical at the shaft; > 0 motoring, < 0 generating.
    """

    speed_rad_s: np.ndarray
    acceleration_rad_s2: np.ndarray
    torque_Nm: np.ndarray
    power_W: np.ndarray


def winch_motor_state(T, L_dot, L_ddot, params: WinchParams | Sequence[WinchParams]) -> MotorState:
    """The motor speed, torque and power that holding tension T while the cable moves needs.

    Parameters
    ----------
    T : array_like, shape (n_steps, m) or (m,)
        Cable tensions, N (NaN propagates: an infeasible plan's steps).
    L_dot : array_like, shape (n_steps, m) or (m,)
        Cable length rates L', m/s; > 0 paying out, < 0 winding in.
    L_ddot : array_like, shape (n_steps, m) or (m,)
        Cable length accelerations L'', m/s^2 (:func:`length_accelerations` from L').
    params : WinchParams, or a sequence of m of them
        One winch design shared by every cable, or one per cable (column).

    Returns
    -------
    MotorState
        Arrays (n_steps, m) (a 1-d input is one step): speed, acceleration, torque, power.
    """
    (T, L_dot, L_ddot), p = _series(T, L_dot, L_ddot, params=params, names=("T", "L_dot", "L_ddot"))
    omega, alpha = _motor_motion(L_dot, L_ddot, p)
    # tau_m = tau_T + J_eff alpha_m + b omega_m + tau_c sgn(omega_m)
    tau = (_tension_torque(T, omega, p) + p.J * alpha + p.b * omega
           + p.tau_c * _friction_sign(omega, alpha))
    return MotorState(speed_rad_s=omega, acceleration_rad_s2=alpha, torque_Nm=tau, power_W=tau * omega)


@dataclass(frozen=True)
class TensionBounds:
    """The tensions the winches can hold; arrays (n_steps, m).

    Attributes
    ----------
    lower_N, upper_N : T_lo, T_hi, N: the winch's range at that speed and acceleration
        intersected with the cable's [T_min, T_max]. Where ``empty``, lower_N > upper_N.
    winch_lower_N, winch_upper_N : the winch's own range (before the intersection), N;
        the lower end is usually negative (the motor could push) and is cut by T_min.
    overspeed : bool: |omega_m| > omega_max, the winch cannot follow the cable at all.
    empty : bool: no tension within [T_min, T_max] is in the winch's range (or a NaN).
    flag : overspeed | empty: steps at which the winch cannot do what is asked.
    """

    lower_N: np.ndarray
    upper_N: np.ndarray
    winch_lower_N: np.ndarray
    winch_upper_N: np.ndarray
    overspeed: np.ndarray
    empty: np.ndarray
    flag: np.ndarray

    @property
    def all_ok(self) -> bool:
        return not bool(self.flag.any())


def winch_tension_bounds(L_dot, L_ddot, params: WinchParams | Sequence[WinchParams], T_min=0.0,
                         T_max=np.inf) -> TensionBounds:
    """The tension range [T_lo, T_hi] each winch can hold at each step of the cable's motion.

    The motor's torque must stay within tau_lim = min(tau_max, P_max / |omega_m|); with
    c = J_eff alpha_m + b omega_m + tau_c sgn(omega_m) the tension's torque at the motor must
    lie in [-tau_lim - c, tau_lim - c], which gives T through the gearbox (efficiency by the
    power's direction, :func:`winch_motor_state`)::

        T_hi = T(tau_T = tau_lim - c),   T_lo = T(tau_T = -tau_lim - c)
        T(a) = a eta_g G / r_d   if a omega_m >= 0 (motoring, and at rest)
             = a G / (eta_g r_d) otherwise (generating)

    A winch that must wind in fast (tau_lim = P_max / |omega_m| falls) and accelerate the
    winding (c > 0) has less tension to give; one paying out under tension (generating)
    holds more. The range is then intersected with [T_min, T_max].

    Parameters
    ----------
    L_dot : array_like, shape (n_steps, m) or (m,)
        Cable length rates L', m/s; > 0 paying out.
    L_ddot : array_like, shape (n_steps, m) or (m,)
        Cable length accelerations L'', m/s^2.
    params : WinchParams, or a sequence of m of them
    T_min, T_max : float or array_like broadcastable to (n_steps, m)
        The cable's tension limits, N (a robot's ``tension_min``, ``tension_max``, shape (m,)).

    Returns
    -------
    TensionBounds
        Arrays (n_steps, m). At the bound, |tau_m| = tau_max or |tau_m omega_m| = P_max
        (whichever is smaller) unless T_min or T_max cut it.
    """
    (L_dot, L_ddot, T_min, T_max), p = _series(L_dot, L_ddot, T_min, T_max, params=params,
                                               names=("L_dot", "L_ddot", "T_min", "T_max"))
    omega, alpha = _motor_motion(L_dot, L_ddot, p)
    speed = np.abs(omega)
    with np.errstate(divide="ignore"):
        tau_lim = np.where(speed > 0.0, np.minimum(p.tau_max, p.P_max / speed), p.tau_max)
    c = p.J * alpha + p.b * omega + p.tau_c * _friction_sign(omega, alpha)
    T_hi = _tension_from_torque(tau_lim - c, omega, p)
    T_lo = _tension_from_torque(-tau_lim - c, omega, p)
    lower, upper = np.maximum(T_lo, T_min), np.minimum(T_hi, T_max)
    overspeed = speed > p.omega_max
    empty = ~(lower <= upper)  # NaN too
    return TensionBounds(lower_N=lower, upper_N=upper, winch_lower_N=T_lo, winch_upper_N=T_hi,
                         overspeed=overspeed, empty=empty, flag=overspeed | empty)


@dataclass(frozen=True)
class WinchReport:
    """Per winch over a series; arrays (m,).

    Attributes
    ----------
    peak_torque_Nm : max |tau_m|, N m.
    peak_speed_rad_s : max |omega_m|, rad/s.
    peak_power_W : max |tau_m omega_m|, W (motoring or generating).
    energy_positive_J : sum of max(P, 0) dt, J: what the drive gives (motoring) when it
        cannot take energy back.
    energy_net_J : sum of P dt, J: motoring less generated (a drive that recovers it all).
    within_limits : bool: every step within tau_max, omega_max and P_max (to 1e-12 relative).
    NaN (and within_limits False) for a winch with a NaN input at any step.
    """

    peak_torque_Nm: np.ndarray
    peak_speed_rad_s: np.ndarray
    peak_power_W: np.ndarray
    energy_positive_J: np.ndarray
    energy_net_J: np.ndarray
    within_limits: np.ndarray


def winch_report(T, L_dot, L_ddot, dt: float, params: WinchParams | Sequence[WinchParams]) -> WinchReport:
    """Peak torque, speed and power and the energy of each winch over a series.

    The energy is the sum over the steps of P_k dt: each step's power held over its step
    (the prototype's zero-order hold, as ``studies.cleaning``'s winch energy), so n_steps
    samples span n_steps dt seconds.

    Parameters
    ----------
    T : array_like, shape (n_steps, m)
        Cable tensions, N.
    L_dot : array_like, shape (n_steps, m)
        Cable length rates L', m/s; > 0 paying out.
    L_ddot : array_like, shape (n_steps, m)
        Cable length accelerations L'', m/s^2.
    dt : float
        Time step, s, > 0.
    params : WinchParams, or a sequence of m of them

    Returns
    -------
    WinchReport
    """
    dt = float(dt)
    if not (np.isfinite(dt) and dt > 0.0):
        raise ValueError(f"winch: dt must be a finite number > 0, got {dt}")
    state = winch_motor_state(T, L_dot, L_ddot, params)
    m = state.power_W.shape[1]
    p = _arrays(params, m)
    P = state.power_W
    peak_torque = np.max(np.abs(state.torque_Nm), axis=0)
    peak_speed = np.max(np.abs(state.speed_rad_s), axis=0)
    peak_power = np.max(np.abs(P), axis=0)
    tol = 1.0 + 1e-12
    within = (peak_torque <= p.tau_max * tol) & (peak_speed <= p.omega_max * tol) & (peak_power <= p.P_max * tol)
    return WinchReport(peak_torque_Nm=peak_torque, peak_speed_rad_s=peak_speed, peak_power_W=peak_power,
                       energy_positive_J=np.sum(np.maximum(P, 0.0), axis=0) * dt,  # NaN propagates
                       energy_net_J=np.sum(P, axis=0) * dt, within_limits=within)


def length_accelerations(length_rates, dt: float) -> np.ndarray:
    """L'' from a series of L' by second-order finite differences (central inside).

    Parameters
    ----------
    length_rates : array_like, shape (n_steps, m)
        L', m/s (a plan's ``length_rates``), at t_k = k dt.
    dt : float
        Time step, s.

    Returns
    -------
    ndarray, shape (n_steps, m)
        L'', m/s^2; zeros for a single step.
    """
    Ld = np.asarray(length_rates, dtype=float)
    if Ld.shape[0] < 2:
        return np.zeros_like(Ld)
    return np.gradient(Ld, float(dt), axis=0, edge_order=2 if Ld.shape[0] > 2 else 1)


# --------------------------------------------------------------- the prototype's part


class WinchDrive(NamedTuple):
    """The winches of the virtual prototype, one per cable: parameters, tension-loop gains and
    state, each an array (m,). Build it with :func:`winch_drive`.

    Parameters (from :class:`WinchParams`): r (drum radius, m), G (-), eta (-), tau_max (N m),
    omega_max (rad/s), P_max (W), J (J_eff, kg m^2), b (N m s/rad), tau_c (N m).
    Gains of :func:`tension_control_step`: k_T (-), k_w (N m s/rad).
    State: omega (motor speed, rad/s, winding in > 0); L0 (the unstretched length paid out,
    m); tau (the torque that acted over the last step, N m; the command between
    :func:`tension_control_step` and :func:`winch_motor_step`); limited (int, the last step's
    :data:`FREE` / :data:`TORQUE_LIMITED` / :data:`SPEED_LIMITED` / :data:`OVERSPEED`).
    """

    r: np.ndarray
    G: np.ndarray
    eta: np.ndarray
    tau_max: np.ndarray
    omega_max: np.ndarray
    P_max: np.ndarray
    J: np.ndarray
    b: np.ndarray
    tau_c: np.ndarray
    k_T: np.ndarray
    k_w: np.ndarray
    omega: np.ndarray
    L0: np.ndarray
    tau: np.ndarray
    limited: np.ndarray


def tension_loop_damping(params: WinchParams, stiffness_N_m, zeta: float = 0.7, k_T: float = 1.0):
    """The speed gain k_w that gives the tension loop the damping ratio zeta on a cable of
    stiffness k (EA / L, N/m) held at its far end, without friction and with eta_g = 1::

        J_eff omega_m' = (r_d / G) (1 + k_T) (T_cmd - T) - k_w omega_m,   T' = k (r_d / G) omega_m
        => T'' + (k_w / J_eff) T' + w_n^2 (T - T_cmd) = 0,  w_n^2 = k (r_d/G)^2 (1 + k_T) / J_eff
        => k_w = 2 zeta (r_d / G) sqrt(k (1 + k_T) J_eff)              (N m s/rad)

    Parameters
    ----------
    params : WinchParams
    stiffness_N_m : float or ndarray (m,)
        The cable's axial stiffness k = EA / L0, N/m.
    zeta : float
        Damping ratio, > 0.
    k_T : float
        The tension error's gain of :func:`tension_control_step`, >= 0.
    """
    r_G = params.drum_radius_m / params.gear_ratio
    return 2.0 * zeta * r_G * np.sqrt(np.asarray(stiffness_N_m, dtype=float) * (1.0 + k_T) * params.inertia_kg_m2)


def winch_drive(params: WinchParams | Sequence[WinchParams], m: int, L0, omega0=0.0, k_T=1.0,
                k_w=0.0) -> WinchDrive:
    """A :class:`WinchDrive` for m cables, with the field types the compiled steps take.

    Parameters
    ----------
    params : WinchParams, or a sequence of m of them
        J_eff must be > 0 (the motor's dynamics are integrated).
    m : int
        Number of cables.
    L0 : float or array_like (m,)
        Unstretched lengths paid out at the start, m.
    omega0 : float or array_like (m,)
        Motor speeds at the start, rad/s (winding in > 0), e.g. -G L'(0) / r_d.
    k_T : float or array_like (m,)
        Gain on the tension error, dimensionless (torque k_T (r_d/G) (T_cmd - T)), >= 0.
    k_w : float or array_like (m,)
        Gain on the speed error, N m s/rad (torque k_w (omega_ref - omega_m)), >= 0;
        :func:`tension_loop_damping` chooses one.
    """
    p = _arrays(params, int(m))
    if not np.all(p.J > 0.0):
        raise ValueError("winch: the drive's inertia J_m + J_d / G^2 must be > 0 to integrate its dynamics")

    def column(x, name, lo=-np.inf):
        a = np.array(np.broadcast_to(np.asarray(x, dtype=float), (int(m),)), dtype=float)
        if not (np.all(np.isfinite(a)) and np.all(a >= lo)):
            raise ValueError(f"winch: {name} must be finite{' and >= 0' if lo == 0 else ''}, got {x!r}")
        return a

    return WinchDrive(*(np.ascontiguousarray(a, dtype=float) for a in p),
                      column(k_T, "k_T", 0.0), column(k_w, "k_w", 0.0), column(omega0, "omega0"),
                      column(L0, "L0"), np.zeros(int(m)), np.zeros(int(m), dtype=np.int64))


@njit(cache=_cache, inline="always")
def _load_torque(T, omega, r, G, eta):
    """tau_T = (T r_d / G) / eta_g motoring (and at rest), (T r_d / G) eta_g generating, N m."""
    load = T * r / G
    return load / eta if load * omega >= 0.0 else load * eta


@njit(cache=_cache, inline="always")
def tension_control_step(drive, T_cmd, T, Ldot_ref, Lddot_ref):
    """The tension loop: the motor torque for the commanded tension, written to ``drive.tau``.

    Feed-forward of the commanded tension's torque, of the inertia and of the friction at
    the reference motion, feedback on the tension and speed errors (motor side, N m)::

        omega_ref = -G L'_ref / r_d,   alpha_ref = -G L''_ref / r_d
        tau_cmd   = tau_T(T_cmd, omega_ref) + J_eff alpha_ref + b omega_ref + tau_c sgn(omega_ref)
                    + k_T (r_d / G) (T_cmd - T) + k_w (omega_ref - omega_m)

    At rest on a held cable the tension settles on T_cmd (no friction; within
    tau_c G / (r_d (1 / eta_g + k_T)) of it with Coulomb friction).

    Parameters
    ----------
    drive : WinchDrive
        ``drive.tau`` (m,) is written; ``drive.omega`` is read.
    T_cmd : ndarray, shape (m,)
        Commanded tensions, N.
    T : ndarray, shape (m,)
        Measured tensions (load cells), N.
    Ldot_ref, Lddot_ref : ndarray, shape (m,)
        The cables' planned L' (m/s) and L'' (m/s^2): the motion the winch is to follow.
    """
    for i in range(drive.omega.shape[0]):
        r, G = drive.r[i], drive.G[i]
        w_ref = -G * Ldot_ref[i] / r
        a_ref = -G * Lddot_ref[i] / r
        drive.tau[i] = (_load_torque(T_cmd[i], w_ref, r, G, drive.eta[i]) + drive.J[i] * a_ref
                        + drive.b[i] * w_ref + drive.tau_c[i] * np.sign(w_ref)
                        + drive.k_T[i] * r / G * (T_cmd[i] - T[i])
                        + drive.k_w[i] * (w_ref - drive.omega[i]))


@njit(cache=_cache, inline="always")
def winch_motor_step(drive, tau_cmd, T, h):
    """Advance the motors one step of h under the cables' tensions T with torques tau_cmd.

    For each winch, with omega = omega_m at the step's start and everything held over it::

        tau_lim = min(tau_max, P_max / |omega|)                  (tau_max at rest)
        tau     = clip(tau_cmd, -tau_lim, tau_lim)
        u       = tau - tau_T(T, omega) - tau_c s                s = sgn(omega), see below
        J_eff omega' = u - b omega      exact over the step for u held:
        omega+  = omega + (u - b omega) h_b / J_eff,     h_b = J_eff (1 - exp(-b h / J_eff)) / b
                                                               (= h for b = 0)
        L0+     = L0 - (r_d / G) h omega+                semi-implicit Euler: the new speed

    Coulomb friction: moving, s = sgn(omega), and a speed that would change sign within the
    step stops at 0 instead (the friction stops it; the next step breaks away); at rest the
    motor sticks while |tau - tau_T| <= tau_c, else s = sgn(tau - tau_T). The speed limiter:
    if |omega+| would exceed omega_max, the torque is cut to the one that lands it on
    +-omega_max (within +-tau_lim; if that cannot, the speed passes omega_max: OVERSPEED).
    The power limit uses the speed at the step's start.

    Parameters
    ----------
    drive : WinchDrive
        Parameters read; ``omega``, ``L0``, ``tau`` (the torque that acted, N m) and
        ``limited`` written.
    tau_cmd : ndarray, shape (m,)
        Commanded motor torques, N m (winding in > 0); may be ``drive.tau`` itself.
    T : ndarray, shape (m,)
        The cables' tensions over the step, N (from the cable model, e.g. an elastic
        cable's stretch over ``drive.L0``).
    h : float
        Step, s.

    Returns
    -------
    int
        The number of winches whose torque was limited (``limited`` != FREE).
    """
    n_limited = 0
    for i in range(drive.omega.shape[0]):
        r, G, J, b, tau_c = drive.r[i], drive.G[i], drive.J[i], drive.b[i], drive.tau_c[i]
        w = drive.omega[i]
        lim = drive.tau_max[i]
        if w != 0.0:
            lim = min(lim, drive.P_max[i] / abs(w))
        tau = tau_cmd[i]
        code = FREE
        if tau > lim:
            tau, code = lim, TORQUE_LIMITED
        elif tau < -lim:
            tau, code = -lim, TORQUE_LIMITED
        tau_T = _load_torque(T[i], w, r, G, drive.eta[i])
        h_b = h if b == 0.0 else -np.expm1(-b * h / J) * J / b
        drive_torque = tau - tau_T
        stuck = False
        if w != 0.0:
            s = np.sign(w)
        elif drive_torque > tau_c:
            s = 1.0
        elif drive_torque < -tau_c:
            s = -1.0
        else:
            s, stuck = 0.0, True
        if stuck:
            w_new = 0.0
        else:
            w_new = w + (drive_torque - tau_c * s - b * w) * h_b / J
            if tau_c > 0.0 and w * w_new < 0.0:
                w_new = 0.0
        w_max = drive.omega_max[i]
        if abs(w_new) > w_max:
            target = w_max if w_new > 0.0 else -w_max
            if s == 0.0:
                s = np.sign(target)
            tau_star = tau_T + tau_c * s + b * w + (target - w) * J / h_b
            if tau_star >= -lim and tau_star <= lim:
                tau, w_new, code = tau_star, target, SPEED_LIMITED
            else:
                tau = lim if tau_star > lim else -lim
                w_new = w + (tau - tau_T - tau_c * s - b * w) * h_b / J
                code = SPEED_LIMITED if abs(w_new) <= w_max else OVERSPEED
        drive.omega[i] = w_new
        drive.L0[i] -= r / G * h * w_new
        drive.tau[i] = tau
        drive.limited[i] = code
        if code != FREE:
            n_limited += 1
    return n_limited


@njit(cache=_cache, inline="always")
def winch_dynamics_step(drive, T_cmd, T, Ldot_ref, Lddot_ref, h):
    """One step of the tension-controlled winches: :func:`tension_control_step` then
    :func:`winch_motor_step` (no allocation).

    Parameters
    ----------
    drive : WinchDrive
        State advanced in place.
    T_cmd : ndarray, shape (m,)
        Commanded tensions, N.
    T : ndarray, shape (m,)
        The cables' tensions at the step's start (measured, and the load over the step), N.
    Ldot_ref, Lddot_ref : ndarray, shape (m,)
        The cables' planned L' (m/s) and L'' (m/s^2).
    h : float
        Step, s.

    Returns
    -------
    int
        The number of winches limited this step (see :func:`winch_motor_step`).
    """
    tension_control_step(drive, T_cmd, T, Ldot_ref, Lddot_ref)
    return winch_motor_step(drive, drive.tau, T, h)
