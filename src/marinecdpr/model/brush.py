"""Loads a cleaning brush in contact with the hull puts on the platform.

The brush is a tool fixed to the platform, its contact face centred at ``offset_P`` (in
P). It presses on the hull with a normal force F_n >= 0 (whatever holds it there: a
pusher, a guide, a force-controlled cable) and moves over the hull with the velocity
v_rel of its centre relative to the hull. Frames as in ``docs/conventions.md``: every
vector is in C, which is fixed to the ship (so "relative to the hull" is "relative to
C"); n_C is the unit hull normal, pointing **from the hull towards the robot**.

The wrench ON THE PLATFORM, force f (N) and moment m (N m) about P's origin (the
platform's centre of mass), both in C, is

    v_t    = v_rel - (v_rel . n_C) n_C                              tangential velocity
    f_fric = -mu F_n v_t / sqrt(|v_t|^2 + v_smooth^2)              friction
    f_norm = +F_n n_C                                               the hull pushes the brush back
    f_jet  = +jet_N n_C                                             water-jet reaction
    f      = f_fric + f_norm + f_jet
    m_disc = -spin (2/3) mu F_n R n_C   (kind 0, one disc)          brush reaction moment
           = 0                          (kind 1, counter-rotating pair)
    m      = (R_PC offset_P) x f + m_disc

Sign conventions:

- **Friction** opposes the sliding velocity; at |v_t| >> v_smooth its magnitude is
  mu F_n, and it goes smoothly through zero with slope mu F_n / v_smooth (a regularised
  Coulomb law, so that an integrator sees no discontinuity). The normal part of v_rel
  does not enter.
- **Normal reaction** +F_n n_C: the hull pushes the brush away from itself, towards the
  robot. This is the reaction to the pressing force, and the force the cables or the
  pusher must overcome to keep the brush on the hull.
- **Jet** +jet_N n_C: a water jet aimed at the hull throws water towards the hull
  (along -n_C), so its reaction pushes the tool AWAY from the hull, along +n_C. jet_N >= 0
  is such a jet's thrust; give a negative jet_N for a thruster that presses the tool onto
  the hull (its water thrown away from the hull). The jet does not load the contact: the
  friction is mu F_n with F_n the contact force alone.
- **Disc moment**: ``spin = +1`` means the disc turns, relative to the platform, in the
  right-handed sense about n_C (counter-clockwise seen from the robot, looking at the
  hull). The hull's friction opposes that rotation; under uniform pressure over a disc
  of radius R it makes the moment -(2/3) mu F_n R n_C on the disc, which the motor
  passes to the platform. A counter-rotating pair (kind 1) cancels it.
- The forces act at the brush centre R_PC offset_P from P (their moment about P is
  r x f). The model, as in the project's notes, superposes the translational friction
  (full mu F_n against the sliding) and the disc's spin moment: an upper bound on each.

The model is written once per step (:func:`brush_wrench_step`, compiled and inlined
into its callers, like the kernels of :mod:`~marinecdpr.model.kernels`);
:func:`brush_wrench` runs it over a time series in a compiled loop.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

__all__ = [
    "BrushParams",
    "KIND_DISC",
    "KIND_PAIR",
    "brush_params",
    "brush_wrench_step",
    "brush_wrench",
    "brush_wrench_series",
    "brush_velocity_step",
    "brush_velocity",
    "brush_velocity_series",
]

KIND_DISC = 0
"""``BrushParams.kind`` of a single disc brush (reaction moment about the normal)."""
KIND_PAIR = 1
"""``BrushParams.kind`` of a counter-rotating pair (no net moment about the normal)."""

_cache = True


class BrushParams(NamedTuple):
    """A brush's parameters (SI units).

    Build it with :func:`brush_params` (checks the values and gives the field types the
    compiled functions expect: floats, an int ``kind`` and a float64 (3,) ``offset_P``).
    """

    mu: float
    """Friction coefficient brush-on-hull (-), >= 0 (0.3-0.6 for brush on antifouling paint)."""
    radius_m: float
    """Disc radius R (m), >= 0: the spin moment's lever, (2/3) R under uniform pressure."""
    kind: int
    """0 (:data:`KIND_DISC`) single disc; 1 (:data:`KIND_PAIR`) counter-rotating pair."""
    spin: float
    """+1 or -1: the disc's rotation sense about n_C relative to the platform (+1 right-handed)."""
    v_smooth_m_s: float
    """Speed (m/s) below which friction is smoothed through zero, > 0 (e.g. 1e-3)."""
    jet_N: float
    """Water-jet reaction (N) along +n_C (away from the hull); negative presses onto the hull."""
    offset_P: np.ndarray
    """Brush centre (contact face) in P, shape (3,), m."""


def brush_params(mu: float, radius_m: float, kind: int = KIND_DISC, spin: float = 1.0,
                 v_smooth_m_s: float = 1e-3, jet_N: float = 0.0,
                 offset_P=(0.0, 0.0, 0.0)) -> BrushParams:
    """Checked :class:`BrushParams` with the field types the compiled functions take.

    Raises ValueError for a negative or non-finite ``mu`` or ``radius_m``, a ``kind``
    other than 0 or 1, a ``spin`` other than +1 or -1, ``v_smooth_m_s`` <= 0, a non-finite
    ``jet_N`` or an ``offset_P`` that is not 3 finite numbers.
    """
    mu, radius_m, v_smooth_m_s, jet_N = float(mu), float(radius_m), float(v_smooth_m_s), float(jet_N)
    if not (np.isfinite(mu) and mu >= 0.0):
        raise ValueError(f"brush: mu must be a finite number >= 0, got {mu}")
    if not (np.isfinite(radius_m) and radius_m >= 0.0):
        raise ValueError(f"brush: radius_m must be a finite number >= 0, got {radius_m}")
    if kind not in (KIND_DISC, KIND_PAIR) or isinstance(kind, bool):
        raise ValueError(f"brush: kind must be 0 (disc) or 1 (counter-rotating pair), got {kind!r}")
    if spin not in (1, -1) or isinstance(spin, bool):
        raise ValueError(f"brush: spin must be +1 or -1, got {spin!r}")
    if not (np.isfinite(v_smooth_m_s) and v_smooth_m_s > 0.0):
        raise ValueError(f"brush: v_smooth_m_s must be a finite number > 0, got {v_smooth_m_s}")
    if not np.isfinite(jet_N):
        raise ValueError(f"brush: jet_N must be finite, got {jet_N}")
    offset = np.array(offset_P, dtype=float)
    if offset.shape != (3,) or not np.all(np.isfinite(offset)):
        raise ValueError(f"brush: offset_P must be 3 finite numbers (m), got {offset_P!r}")
    return BrushParams(mu=mu, radius_m=radius_m, kind=int(kind), spin=float(spin), v_smooth_m_s=v_smooth_m_s,
                       jet_N=jet_N,
                       offset_P=np.ascontiguousarray(offset))


def _checked(params: BrushParams) -> BrushParams:
    """``params`` through :func:`brush_params` (one compiled type, checked values)."""
    return brush_params(*params)


# ------------------------------------------------------------------------------ one step


@njit(cache=_cache, inline="always")
def brush_wrench_step(v_rel_C, n_C, F_n, R_PC, params, f_out, m_out):
    """The brush's force and moment on the platform at one step (see the module's equations).

    Parameters
    ----------
    v_rel_C : ndarray, shape (3,)
        Velocity of the brush centre relative to the hull, in C (m/s).
    n_C : ndarray, shape (3,)
        Unit hull normal in C, from the hull towards the robot (not normalised here).
    F_n : float
        Normal contact force pressing the brush on the hull (N), >= 0 (not checked here).
    R_PC : ndarray, shape (3, 3)
        The platform's orientation, P to C.
    params : BrushParams
        As built by :func:`brush_params`.
    f_out, m_out : ndarray, shape (3,)
        Written: force (N) and moment about P's origin (N m) on the platform, in C.
    """
    n0, n1, n2 = n_C[0], n_C[1], n_C[2]
    v0, v1, v2 = v_rel_C[0], v_rel_C[1], v_rel_C[2]
    vn = v0 * n0 + v1 * n1 + v2 * n2
    t0, t1, t2 = v0 - vn * n0, v1 - vn * n1, v2 - vn * n2
    vs = params.v_smooth_m_s
    c = -params.mu * F_n / np.sqrt(t0 * t0 + t1 * t1 + t2 * t2 + vs * vs)
    fn = F_n + params.jet_N
    f0, f1, f2 = c * t0 + fn * n0, c * t1 + fn * n1, c * t2 + fn * n2
    p = params.offset_P
    r0 = R_PC[0, 0] * p[0] + R_PC[0, 1] * p[1] + R_PC[0, 2] * p[2]
    r1 = R_PC[1, 0] * p[0] + R_PC[1, 1] * p[1] + R_PC[1, 2] * p[2]
    r2 = R_PC[2, 0] * p[0] + R_PC[2, 1] * p[1] + R_PC[2, 2] * p[2]
    md = 0.0
    if params.kind == 0:
        md = -params.spin * (2.0 / 3.0) * params.mu * F_n * params.radius_m
    f_out[0], f_out[1], f_out[2] = f0, f1, f2
    m_out[0] = r1 * f2 - r2 * f1 + md * n0
    m_out[1] = r2 * f0 - r0 * f2 + md * n1
    m_out[2] = r0 * f1 - r1 * f0 + md * n2


@njit(cache=_cache, inline="always")
def brush_velocity_step(v_PC, omega_PC, R_PC, offset_P, out):
    """Velocity of the brush centre relative to C at one step: v + omega x (R_PC offset_P).

    v_PC, omega_PC (3,): the platform's twist relative to C, in C (m/s, rad/s); R_PC (3, 3);
    offset_P (3,): the brush centre in P (m). Writes out (3,), m/s in C.
    """
    p = offset_P
    r0 = R_PC[0, 0] * p[0] + R_PC[0, 1] * p[1] + R_PC[0, 2] * p[2]
    r1 = R_PC[1, 0] * p[0] + R_PC[1, 1] * p[1] + R_PC[1, 2] * p[2]
    r2 = R_PC[2, 0] * p[0] + R_PC[2, 1] * p[1] + R_PC[2, 2] * p[2]
    w0, w1, w2 = omega_PC[0], omega_PC[1], omega_PC[2]
    out[0] = v_PC[0] + w1 * r2 - w2 * r1
    out[1] = v_PC[1] + w2 * r0 - w0 * r2
    out[2] = v_PC[2] + w0 * r1 - w1 * r0


# --------------------------------------------------------------------- compiled loops
# Time-last, C-contiguous buffers (as rigid_body's *_series): step k gets views of column k.


@njit(cache=_cache)
def brush_wrench_series(vt, nt, Fn, Rt, params, ft, mt):
    """:func:`brush_wrench_step` at every step.

    vt, nt (3, n): v_rel and n_C; Fn (n,); Rt (3, 3, n): R_PC. Writes ft, mt (3, n).
    """
    for k in range(vt.shape[1]):
        brush_wrench_step(vt[:, k], nt[:, k], Fn[k], Rt[:, :, k], params, ft[:, k], mt[:, k])


@njit(cache=_cache)
def brush_velocity_series(vt, wt, Rt, offset_P, out):
    """:func:`brush_velocity_step` at every step: vt, wt (3, n); Rt (3, 3, n). Writes out (3, n)."""
    for k in range(vt.shape[1]):
        brush_velocity_step(vt[:, k], wt[:, k], Rt[:, :, k], offset_P, out[:, k])


# ---------------------------------------------------------------- over time series


def _series(a, tail: tuple[int, ...], n: int | None, name: str) -> np.ndarray:
    """``a`` shaped (n, *tail), or tail alone (the same every step), as a C-contiguous
    time-last float buffer (*tail, n)."""
    a = np.asarray(a, dtype=float)
    if n is None:
        n = a.shape[0] if a.ndim == len(tail) + 1 else None
    if a.shape == tail and n is not None:
        a = np.broadcast_to(a, (n,) + tail)
    if n is None or a.shape != (n,) + tail:
        want = f"({'n_steps' if n is None else n}, {', '.join(map(str, tail))})".replace(", )", ")")
        raise ValueError(f"brush: {name} must have shape {want} or {tail}, got {a.shape}")
    return np.ascontiguousarray(np.moveaxis(a, 0, -1))


def brush_wrench(v_rel_C, n_C, F_n, R_PC, params: BrushParams) -> tuple[np.ndarray, np.ndarray]:
    """The brush's force and moment on the platform over a time series.

    Runs :func:`brush_wrench_step` (the module's equations) in a compiled loop.

    Parameters
    ----------
    v_rel_C : ndarray, shape (n_steps, 3)
        Velocity of the brush centre relative to the hull (= relative to C), in C, m/s
        (:func:`brush_velocity`).
    n_C : ndarray, shape (n_steps, 3) or (3,)
        Unit hull normal in C, from the hull towards the robot (|n_C| = 1 to 1e-9).
    F_n : float or ndarray, shape (n_steps,)
        Normal contact force pressing the brush on the hull, N, >= 0.
    R_PC : ndarray, shape (n_steps, 3, 3) or (3, 3)
        The platform's orientation, P to C.
    params : BrushParams
        Checked and converted by :func:`brush_params`.

    Returns
    -------
    f, m : ndarray, shape (n_steps, 3)
        Force (N) and moment about P's origin, the platform's centre of mass (N m), that
        the brush applies to the platform, in C. Views of time-last buffers.

    Raises
    ------
    ValueError
        For a shape that does not fit, a negative F_n, a non-unit n_C or bad params.
    """
    vt = _series(v_rel_C, (3,), None, "v_rel_C")
    n = vt.shape[1]
    nt = _series(n_C, (3,), n, "n_C")
    Fn = _series(F_n, (), n, "F_n")
    Rt = _series(R_PC, (3, 3), n, "R_PC")
    if np.any(Fn < 0.0):
        k = int(np.argmax(Fn < 0.0))
        raise ValueError(f"brush: F_n must be >= 0 (the brush cannot pull on the hull), "
                         f"got {Fn[k]} at step {k}")
    bad = np.abs(np.sqrt(np.sum(nt * nt, axis=0)) - 1.0) > 1e-9
    if np.any(bad):
        k = int(np.argmax(bad))
        raise ValueError(f"brush: n_C must be a unit vector, |n_C| = {np.linalg.norm(nt[:, k])} "
                         f"at step {k}")
    ft, mt = np.empty((3, n)), np.empty((3, n))
    brush_wrench_series(vt, nt, Fn, Rt, _checked(params), ft, mt)
    return ft.T, mt.T


def brush_velocity(v_PC, omega_PC, R_PC, offset_P) -> np.ndarray:
    """Velocity of the brush centre relative to C (the hull): v_PC + omega_PC x (R_PC offset_P).

    Parameters
    ----------
    v_PC, omega_PC : ndarray, shape (n_steps, 3)
        The platform's twist relative to C, in C (the pose's ``twist`` split), m/s, rad/s.
    R_PC : ndarray, shape (n_steps, 3, 3) or (3, 3)
    offset_P : ndarray, shape (3,)
        The brush centre in P, m.

    Returns
    -------
    ndarray, shape (n_steps, 3)
        m/s in C; a view of a time-last buffer.
    """
    vt = _series(v_PC, (3,), None, "v_PC")
    n = vt.shape[1]
    wt = _series(omega_PC, (3,), n, "omega_PC")
    Rt = _series(R_PC, (3, 3), n, "R_PC")
    p = np.asarray(offset_P, dtype=float)
    if p.shape != (3,):
        raise ValueError(f"brush: offset_P must have shape (3,), got {p.shape}")
    out = np.empty((3, n))
    brush_velocity_series(vt, wt, Rt, np.ascontiguousarray(p), out)
    return out.T


def cleaning_brush(cleaning) -> BrushParams:
    """The :class:`BrushParams` of a scenario's ``[cleaning]`` section."""
    return brush_params(cleaning.friction, 0.5 * cleaning.brush_diameter_m,
                        KIND_DISC if cleaning.brush == "disc" else KIND_PAIR, jet_N=cleaning.jet_N,
                        offset_P=cleaning.brush_offset_m)


def cleaning_loads(cleaning, twist: np.ndarray, R_PC: np.ndarray, F_n) -> tuple[np.ndarray, np.ndarray]:
    """The brush's force and moment on the platform, about P's origin, in C, for a platform
    moving with ``twist`` (n_steps, 6) = (v_PC, omega_PC) in C and orientation ``R_PC``
    (n_steps, 3, 3), the brush pressed on the hull with ``F_n`` (scalar or (n_steps,)), N.

    Returns
    -------
    f, m : ndarray, shape (n_steps, 3)
        N and N m, in C.
    """
    params = cleaning_brush(cleaning)
    twist = np.asarray(twist, dtype=float)
    v_rel = brush_velocity(twist[:, :3], twist[:, 3:], R_PC, params.offset_P)
    return brush_wrench(v_rel, np.asarray(cleaning.hull_normal, dtype=float), F_n, R_PC, params)
