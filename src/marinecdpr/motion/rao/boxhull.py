"""RAOs of a box-shaped hull at zero speed, in closed form (:func:`box_hull_rao`): a first,
pessimistic look when no BEM data are at hand."""

from __future__ import annotations

import math

import numpy as np

from marinecdpr.motion.rao.table import RAO

__all__ = ["box_hull_rao", "check_positive", "ROLL_GYRADIUS_OVER_BEAM"]

ROLL_GYRADIUS_OVER_BEAM = 0.4
"""The box hull's roll radius of gyration over its beam, added inertia included."""


def _sincos_deg(deg: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """sin and cos of angles in degrees, exactly 0 and +-1 at multiples of 90 deg."""
    r = np.radians(deg)
    s, c = np.sin(r), np.cos(r)
    quarter = np.mod(deg, 90.0) == 0.0
    q = np.mod(np.round(deg / 90.0), 4).astype(int)
    s = np.where(quarter, np.array([0.0, 1.0, 0.0, -1.0])[q], s)
    c = np.where(quarter, np.array([1.0, 0.0, -1.0, 0.0])[q], c)
    return s, c


def _slope_factor(u: np.ndarray) -> np.ndarray:
    """3 (sin u - u cos u) / u^3: the waterplane-averaged slope of a wave, -> 1 as u -> 0."""
    u = np.abs(u)
    small = u < 1e-2
    us = np.where(small, 1.0, u)
    exact = 3.0 * (np.sin(us) - us * np.cos(us)) / us**3
    u2 = u * u
    series = 1.0 - u2 / 10.0 + u2 * u2 / 280.0
    return np.where(small, series, exact)


def check_positive(**params: float) -> None:
    """Refuse a parameter that is not a finite number > 0 (ValueError naming it)."""
    for key, value in params.items():
        if not (np.isfinite(value) and value > 0.0):
            raise ValueError(f"{key} must be finite and > 0; got {value}")


def box_hull_rao(
    *,
    length_m: float,
    beam_m: float,
    draught_m: float,
    gm_m: float,
    roll_damping_ratio: float,
    omega: np.ndarray,
    heading_deg: np.ndarray,
    gml_m: float | None = None,
    rho: float = 1025.0,
    g: float = 9.81,
) -> RAO:
    """RAOs of a box-shaped hull at zero speed in deep water: an approximation.

    A quick estimate for when no BEM data are at hand. Heave and pitch follow the
    closed-form expressions of Jensen, Mansour & Olsen (2004), "Estimation of ship
    motions using closed-form expressions", Ocean Engineering 31, 61-85, for zero
    speed (alpha = 1) and block coefficient 1, written as complex RAOs; roll is a
    damped one-DOF oscillator excited by the wave slope; **surge, sway and yaw are
    zero**. S's origin is the box's centre on the waterline.

    With k = omega^2/g, k_x = k cos(beta), k_y = k sin(beta), u = k_x L/2 and

        kappa = exp(-k T)                       (Smith correction)
        A     = 2 sin(k B/2) exp(-k T)          (2D radiated-wave amplitude ratio)
        D     = A^2 / (k B)                     (heave damping over stiffness, omega b/c)
        P     = 1 - k T + i D,   Q = 1 - 2 k T + i D

    (strip theory for a uniformly loaded box with sectional added mass equal to
    its mass, damping b = rho g^2 A^2 / omega^3, stiffness c = rho g B):

        heave = kappa P / Q * sin(u) / u
        pitch = kappa (P + delta) / (Q + delta) * i k_x R(u),
                R(u) = 3 (sin u - u cos u) / u^3,
                delta = 12 T GM_L / L^2 - 1
        roll  = -i k_y R(k_y B/2) / (1 - r^2 + 2 i zeta r),
                r = omega / omega_roll,  omega_roll = sqrt(g GM) / (0.4 B)

    The magnitudes of heave and pitch are Jensen et al.'s eta |F| and eta |G|
    (their eqs. for F, G, f and eta at zero speed); the phases follow from the same
    strip-theory equations in this module's time convention. ``gml_m = None``
    gives delta = 0, the paper's pitch stiffness rho g B L^3/12 (GM_L = L^2/(12 T),
    the box's BM_L); a given GM_L sets the pitch stiffness to rho g LBT GM_L, added
    to both sides so that pitch still follows the wave slope in long waves.

    Roll: a one-DOF oscillator with restoring rho g LBT GM and inertia including
    the added inertia through the radius of gyration 0.4 B
    (:data:`ROLL_GYRADIUS_OVER_BEAM`, as in the IMO roll-period estimate
    T = 2 C B / sqrt(GM), C ~ 0.4), damping ratio zeta as given, excited by the
    wave slope k sin(beta) averaged over the beam (R, which makes roll fall off
    in waves shorter than the beam). No depth (Smith) reduction is applied to
    roll, which errs on the large side by up to a factor exp(k T). So roll is zero
    in head and following seas, follows the slope in long beam waves
    (-> -i k sin(beta)), and peaks at about slope / (2 zeta) at omega_roll in beam
    seas.

    Limits: no coupling, no forward speed, no viscous heave/pitch damping, no
    beam-wise reduction of heave; realistic only for omega below a few times the
    natural frequencies and for ship-like proportions.

    Error against BEM (Capytaine via :func:`marinecdpr.motion.bem.box_hull_bem`, the same
    box: 100 x 20 x 6 m, GM 2 m, 5 % roll damping; ``tests/test_bem.py``): heave in head
    seas within 0.1 m/m (0.04-0.10 near 0.8 rad/s, where the box's heave cancels and
    BEM's does not); in beam seas heave up to 0.75 m/m too high (no reduction across the
    beam); **roll in beam seas peaks 2.5-5 times too high** (17.5 against 4.7 deg/m at
    0.05 rad/s resolution) and stays several times too high in short waves (about 2 against
    0.3 deg/m at 1 rad/s). Use it for a first, pessimistic look; use BEM RAOs
    (``marinecdpr rao``) for any operability figure.

    Parameters
    ----------
    length_m, beam_m, draught_m : float
        Box length L, beam B and draught T, m (> 0).
    gm_m : float
        Transverse metacentric height GM, m (> 0).
    roll_damping_ratio : float
        Roll damping over critical damping zeta (> 0).
    omega : array_like, shape (n_omega,)
        Wave angular frequencies, rad/s, strictly increasing, > 0.
    heading_deg : array_like, shape (n_heading,)
        Wave headings beta (travel direction from S's +x, CCW), deg, strictly
        increasing in [0, 360).
    gml_m : float, optional
        Longitudinal metacentric height GM_L, m (> 0). Default: L^2 / (12 T).
    rho : float
        Water density, kg/m^3 (> 0; it cancels out of these ratios).
    g : float
        Gravitational acceleration, m/s^2.

    Returns
    -------
    RAO
    """
    L, B, T = float(length_m), float(beam_m), float(draught_m)
    params = {"length_m": L, "beam_m": B, "draught_m": T, "gm_m": gm_m,
              "roll_damping_ratio": roll_damping_ratio, "rho": rho, "g": g}
    if gml_m is not None:
        params["gml_m"] = gml_m
    check_positive(**params)
    zeta = float(roll_damping_ratio)
    w = np.asarray(omega, dtype=float)
    beta = np.asarray(heading_deg, dtype=float)
    if w.ndim != 1 or beta.ndim != 1:
        raise ValueError("omega and heading_deg must be 1-D arrays")
    if np.any(w <= 0.0):
        raise ValueError("omega must be > 0 rad/s")
    sin_b, cos_b = _sincos_deg(beta)
    k = (w * w / g)[None, :]  # (1, n_omega)
    kx = k * cos_b[:, None]  # (n_heading, n_omega)
    ky = k * sin_b[:, None]
    kappa = np.exp(-k * T)
    A = 2.0 * np.sin(0.5 * k * B) * kappa
    D = A * A / (k * B)
    P = 1.0 - k * T + 1j * D
    Q = 1.0 - 2.0 * k * T + 1j * D
    u = 0.5 * kx * L
    delta = 0.0 if gml_m is None else 12.0 * T * float(gml_m) / L**2 - 1.0
    heave = kappa * P / Q * np.sinc(u / np.pi)
    pitch = kappa * (P + delta) / (Q + delta) * 1j * kx * _slope_factor(u)
    omega_roll = math.sqrt(g * float(gm_m)) / (ROLL_GYRADIUS_OVER_BEAM * B)
    r = w[None, :] / omega_roll
    roll = -1j * ky * _slope_factor(0.5 * ky * B) / (1.0 - r * r + 2j * zeta * r)
    values = np.zeros((6, beta.size, w.size), dtype=complex)
    values[2], values[3], values[4] = heave, roll, pitch
    return RAO(w, beta, values)
