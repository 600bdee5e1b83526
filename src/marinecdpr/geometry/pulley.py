"""Cable kinematics with a swivelling pulley at each frame anchor, compiled per step and over time series.

The point model (:mod:`.kinematics`, eqs. 2-6) runs every cable straight from a fixed frame
anchor c_i to the platform anchor b_i = x_PC + R_PC p_i. A real frame guides the cable over
a pulley that swivels to follow the platform (Pott's swivelling-pulley model). Per cable,
all vectors in the robot frame C, m:

- a_i: the frame anchor, the point on the pulley's rim where the cable arrives from its
  winch (fixed in C: it lies on the swivel axis);
- z_i (unit): the swivel axis through a_i; the cable arrives at a_i travelling along +z_i
  (winch side behind, before a_i);
- r_i >= 0: the pulley's radius.

The pulley turns about z_i so that its plane holds z_i and b_i. With w = b_i - a_i,

    w_z = w . z_i,     w_k = |w - w_z z_i|,     k_i = (w - w_z z_i) / w_k     (w_k > 0)

k_i points from the axis towards b_i, and the pulley's centre is M_i = a_i + r_i k_i. In
the pulley's plane, coordinates (k, z) relative to a_i: a = (0, 0), M = (r, 0),
b = (w_k, w_z). The cable leaves a travelling along (0, 1), tangent to the circle (a - M
= (-r, 0) is perpendicular to z). Following the rim in that sense it turns clockwise in
(k, z): after wrapping an angle beta its direction of travel is

    t(beta) = (sin beta, cos beta),                     (1)

at the rim point C(beta) = M + r n(beta), n = (-cos beta, sin beta) the outward normal
(beta = 0 gives a), i.e.

    C - a = r (1 - cos beta) k_i + r sin beta z_i.        (2)

The exit point C_i is where the straight free span to b_i leaves the rim: b - C along
+t (the tangent continuing the wrap; the other tangent from b would be run against the
arrival direction). With D = b - M = (w_k - r, w_z), d = |D| > r and l_f the free
span, D = r n + l_f t; since n and t are orthonormal, solving for t gives

    l_f = sqrt(d^2 - r^2) = sqrt((d - r)(d + r)),
    sin beta = t_k = (r D_z + l_f D_k) / d^2,     cos beta = t_z = (l_f D_z - r D_k) / d^2,
    beta = atan2(t_k, t_z)  taken in [0, 2 pi).         (3)

(Equivalently, in polar form: phi_C = atan2(D_z, D_k) + acos(r / d) is the exit point's
angle about M and beta = pi - phi_C mod 2 pi; the tests find C independently, as the
tangent point of Thales' circle on M-b on which the cable turns clockwise.) For b ahead
of a on the arrival line beta -> 0; level with a (w_z = 0), beta = pi/2 + asin(r/d);
behind a beta > pi/2, approaching 2 pi for b just outside the rim just before a. Since
w_k > 0, beta is in (0, 2 pi). The cable's length
from a_i is

    L_i = r_i beta_i + l_f,                                 (4)

its free span's unit vector, from the platform anchor towards the exit point (the
cable pulls the platform along it), u_i = (C_i - b_i) / l_f = -t, and J~'s row keeps the
point model's form (eq. 6) with this u_i:

    J~_i = (u_i^T, ((R_PC p_i) x u_i)^T),     L_i' = -J~_i . (v_PC, omega_PC).   (5)

Why (5): in the plane, b - M = r n(beta) + l_f t(beta) with dn/dbeta = (sin beta, cos beta)
= t and dt/dbeta = (cos beta, -sin beta) = -n. Differentiating (M fixed in the plane),
db = r t dbeta + dl_f t - l_f n dbeta, so t . db = r dbeta + dl_f = dL
(the rate of the wrapped arc cancels the part of the free span's rate due to the exit point
moving round the rim). A displacement of b out of the pulley's plane only swivels the pulley
about z_i, carrying M, C and the whole in-plane picture rigidly: to first order it changes
neither beta nor l_f, and it is perpendicular to t. Hence grad_b L = t = -u_i in 3D, and with
b' = v_PC + omega_PC x (R_PC p_i),

    L' = -u_i . (v_PC + omega_PC x R_PC p_i) = -(u_i . v_PC + ((R_PC p_i) x u_i) . omega_PC),

the projection of the anchor's velocity onto the free span, exactly as for a fixed anchor at
C_i. The cables' wrench on the platform is still J~^T T.

Radius 0 is the point model exactly: :func:`pulley_geometry` calls
:func:`.kinematics.cable_geometry` (L = |b - a|, the same J~ to the bit), with C = a,
l_f = L and beta the limit of (3) as r -> 0, the angle between z_i and b - a (in
[0, pi]); b on the axis is then regular.

Degenerate cables (r > 0) get a status and NaN lengths, angles, exit points and rows:

- ``ON_AXIS`` (1): b on the swivel axis, w_k <= 1e-12 |w| (k_i undefined to round-off; also
  b = a, and for r = 0 b = a, where the point model's length 0 is kept and its row is NaN);
- ``INSIDE`` (2): |b - M| <= r, no tangent from b;
- ``INVALID`` (3): a non-finite input or a negative radius.

The model ignores the cable's collision with the incoming cable or the pulley's fork for
large wraps; beta near 2 pi is geometry, not a feasible cable route.

As in :mod:`.kinematics`, the per-step functions are compiled once
(:func:`pulley_geometry`, one cable, inlined; :func:`pulleys_step`, every cable, written in
place, compiled without numba's runtime so that it cannot allocate) and
:func:`pulley_kinematics` runs them over a series in a compiled loop on time-last buffers
whose views it returns (``docs/conventions.md``, "Array layout").
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

from .kinematics import cable_geometry, length_rate

__all__ = ["PulleyKinematics", "pulley_kinematics", "pulley_geometry", "pulleys_step",
           "REGULAR", "ON_AXIS", "INSIDE", "INVALID"]

REGULAR, ON_AXIS, INSIDE, INVALID = 0, 1, 2, 3
"""Status codes of one cable: see the module's docstring."""

_cache = True
_AXIS_RTOL = 1e-12
"""b is on the swivel axis when its distance from it is at most this times |b - a|."""
_TWO_PI = 2.0 * np.pi
_NAN3 = (np.nan, np.nan, np.nan)
_NAN6 = (np.nan, np.nan, np.nan, np.nan, np.nan, np.nan)


@dataclass(frozen=True)
class PulleyKinematics:
    """Cable geometry with swivelling pulleys over a time series, in C.

    Attributes
    ----------
    lengths : ndarray, shape (n_steps, n_cables)
        L_i = r_i beta_i + l_f, the cable's length from the frame anchor a_i, m.
    free_lengths : ndarray, shape (n_steps, n_cables)
        l_f = |b_i - C_i|, the straight span from the exit point to the platform anchor, m.
    wrap_angles : ndarray, shape (n_steps, n_cables)
        beta_i, the angle the cable wraps round its pulley, rad, in [0, 2 pi) (for r_i = 0,
        the angle between z_i and b_i - a_i).
    exits_C : ndarray, shape (n_steps, n_cables, 3)
        C_i, where the free span leaves the pulley, in C, m (a_i for r_i = 0).
    J_tilde : ndarray, shape (n_steps, n_cables, 6)
        Rows (u_i^T, ((R_PC p_i) x u_i)^T), u_i = (C_i - b_i) / l_f.
    status : ndarray, shape (n_steps, n_cables), int
        0 regular; 1 (ON_AXIS), 2 (INSIDE), 3 (INVALID) with NaN in the other fields (see
        the module's docstring).
    length_rates : ndarray, shape (n_steps, n_cables) or None
        L_i' = -J~_i (v_PC, omega_PC), m/s, when a twist was given.
    """

    lengths: np.ndarray
    free_lengths: np.ndarray
    wrap_angles: np.ndarray
    exits_C: np.ndarray
    J_tilde: np.ndarray
    status: np.ndarray
    length_rates: np.ndarray | None

    @property
    def units(self) -> np.ndarray:
        """u_i, the free spans' unit vectors (platform anchor to exit point), shape (n_steps,
        n_cables, 3) (the first columns of J~)."""
        return self.J_tilde[:, :, :3]


# ------------------------------------------------------------------- one step, compiled


@njit(cache=_cache, inline="always")
def pulley_geometry(x, R_PC, a, z, r, p):
    """One cable over its swivelling pulley at one pose: eqs. (1)-(5) of the module.

    Parameters
    ----------
    x : ndarray, shape (3,)
        x_PC: position of P's origin in C, m.
    R_PC : ndarray, shape (3, 3)
        R_P^C.
    a : ndarray, shape (3,)
        a_i: the frame anchor, where the cable arrives on the pulley's rim, in C, m.
    z : ndarray, shape (3,)
        z_i: the swivel axis, a unit vector in C; the cable arrives at a_i travelling along +z_i.
    r : float
        r_i >= 0: the pulley's radius, m (0: the point model).
    p : ndarray, shape (3,)
        The platform anchor p_i in P, m.

    Returns
    -------
    status : int
        0 regular, 1 ON_AXIS, 2 INSIDE, 3 INVALID.
    length : float
        L_i = r_i beta_i + l_f, m.
    free : float
        l_f = |b_i - C_i|, m.
    beta : float
        The wrap angle, rad, in [0, 2 pi).
    exit : tuple of 3 floats
        C_i in C, m.
    row : tuple of 6 floats
        J~_i = (u_i^T, ((R_PC p_i) x u_i)^T).

    NaN in everything but the status where the status is not 0, except for r = 0 and
    b = a: length 0 and free 0 (the point model's length), exit a, NaN beta and row.
    """
    if r == 0.0:  # the point model, to the bit
        L, row, _ = cable_geometry(x, R_PC, a, p)
        if not np.isfinite(L):
            return INVALID, np.nan, np.nan, np.nan, _NAN3, _NAN6
        if L == 0.0:
            return ON_AXIS, L, L, np.nan, (a[0], a[1], a[2]), row
        # beta's limit r -> 0: the angle between z and t = b - a = -u (u = row[:3])
        c0 = z[1] * row[2] - z[2] * row[1]
        c1 = z[2] * row[0] - z[0] * row[2]
        c2 = z[0] * row[1] - z[1] * row[0]
        beta = np.arctan2(np.sqrt(c0 * c0 + c1 * c1 + c2 * c2),
                          -(z[0] * row[0] + z[1] * row[1] + z[2] * row[2]))
        return REGULAR, L, L, beta, (a[0], a[1], a[2]), row
    # R_PC p_i and w = b - a, b = x + R_PC p_i
    q0 = R_PC[0, 0] * p[0] + R_PC[0, 1] * p[1] + R_PC[0, 2] * p[2]
    q1 = R_PC[1, 0] * p[0] + R_PC[1, 1] * p[1] + R_PC[1, 2] * p[2]
    q2 = R_PC[2, 0] * p[0] + R_PC[2, 1] * p[1] + R_PC[2, 2] * p[2]
    w0 = x[0] + q0 - a[0]
    w1 = x[1] + q1 - a[1]
    w2 = x[2] + q2 - a[2]
    wz = w0 * z[0] + w1 * z[1] + w2 * z[2]  # along the axis
    e0, e1, e2 = w0 - wz * z[0], w1 - wz * z[1], w2 - wz * z[2]  # across it, towards b
    wk = np.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
    wn = np.sqrt(w0 * w0 + w1 * w1 + w2 * w2)
    if not (np.isfinite(wn + wz + z[0] + z[1] + z[2] + r) and r > 0.0):
        return INVALID, np.nan, np.nan, np.nan, _NAN3, _NAN6
    if wk <= _AXIS_RTOL * wn:  # k undefined (also b = a)
        return ON_AXIS, np.nan, np.nan, np.nan, _NAN3, _NAN6
    iwk = 1.0 / wk
    k0, k1, k2 = e0 * iwk, e1 * iwk, e2 * iwk  # k_i; the plane's coordinates of b: (wk, wz)
    Dk = wk - r  # D = b - M in (k, z), M = (r, 0)
    Dz = wz
    d2 = Dk * Dk + Dz * Dz
    d = np.sqrt(d2)
    if not d > r:  # b on or inside the rim: no tangent
        return INSIDE, np.nan, np.nan, np.nan, _NAN3, _NAN6
    lf = np.sqrt((d - r) * (d + r))  # eq. (3), the free span
    id2 = 1.0 / d2
    tk = (r * Dz + lf * Dk) * id2  # t = (sin beta, cos beta): D = r n + l_f t
    tz = (lf * Dz - r * Dk) * id2
    beta = np.arctan2(tk, tz)  # the clockwise turn from (0, 1) to t
    if beta < 0.0:
        beta += _TWO_PI
    # eq. (2): C = a + r (1 - cos beta) k + r sin beta z
    ck, cz = r * (1.0 - tz), r * tk
    C = (a[0] + ck * k0 + cz * z[0], a[1] + ck * k1 + cz * z[1], a[2] + ck * k2 + cz * z[2])
    u0 = -(tk * k0 + tz * z[0])  # u = -t, towards the exit point
    u1 = -(tk * k1 + tz * z[1])
    u2 = -(tk * k2 + tz * z[2])
    row = (u0, u1, u2, q1 * u2 - q2 * u1, q2 * u0 - q0 * u2, q0 * u1 - q1 * u0)  # eq. (5)
    return REGULAR, r * beta + lf, lf, beta, C, row


@njit(cache=_cache, _nrt=False)
def pulleys_step(x, R_PC, a_C, z_C, radius, p_P, lengths, J, exits, wraps, free=None, status=None):
    """Every cable over its pulley at one pose (:func:`pulley_geometry`), written in place.

    Compiled without numba's runtime: it allocates nothing.

    Parameters
    ----------
    x : ndarray, shape (3,)
        x_PC: position of P's origin in C, m.
    R_PC : ndarray, shape (3, 3)
        R_P^C.
    a_C : ndarray, shape (n_cables, 3)
        Frame anchors a_i (on the pulleys' rims, where the cables arrive) in C, m.
    z_C : ndarray, shape (n_cables, 3)
        Swivel axes z_i, unit vectors in C: cable i arrives at a_i travelling along +z_i.
    radius : ndarray, shape (n_cables,)
        Pulley radii r_i >= 0, m (0: the point model for that cable).
    p_P : ndarray, shape (n_cables, 3)
        Platform anchors p_i in P, m.
    lengths : ndarray, shape (n_cables,)
        Written: L_i = r_i beta_i + l_f, m.
    J : ndarray, shape (n_cables, 6)
        Written: J~_i = (u_i^T, ((R_PC p_i) x u_i)^T), u_i the free span's unit vector.
    exits : ndarray, shape (n_cables, 3)
        Written: the exit points C_i in C, m.
    wraps : ndarray, shape (n_cables,)
        Written: the wrap angles beta_i, rad, in [0, 2 pi).
    free : ndarray, shape (n_cables,), optional
        Written if given: the free spans l_f = |b_i - C_i|, m.
    status : int ndarray, shape (n_cables,), optional
        Written if given: each cable's status (0 regular, 1 ON_AXIS, 2 INSIDE, 3 INVALID).

    Returns
    -------
    int
        0 if every cable is regular, else the status of the first cable that is not (its
        outputs are NaN, see :func:`pulley_geometry`).
    """
    first = REGULAR
    for i in range(a_C.shape[0]):
        s, L, lf, beta, C, row = pulley_geometry(x, R_PC, a_C[i], z_C[i], radius[i], p_P[i])
        lengths[i] = L
        wraps[i] = beta
        for c in range(3):
            exits[i, c] = C[c]
        for c in range(6):
            J[i, c] = row[c]
        if free is not None:
            free[i] = lf
        if status is not None:
            status[i] = s
        if first == REGULAR:
            first = s
    return first


# ------------------------------------------------------------- over the steps, compiled


@njit(cache=_cache)
def _pulley_series(xt, Rt, a_C, z_C, radius, p_P, twt, Lt, Ft, Bt, Ct, Jt, St, rates_t):
    """:func:`pulley_geometry` (and :func:`.kinematics.length_rate` where ``twt`` has 6 rows)
    at every step, on time-last, C-contiguous buffers: xt (3, n), Rt (3, 3, n), twt (6 or
    0, n); writes Lt, Ft, Bt, St (m, n), Ct (3, m, n), Jt (6, m, n) and, with a twist,
    rates_t (m, n). Cable by cable, the steps innermost (as kinematics._cables_series)."""
    with_rates = twt.shape[0] == 6
    for i in range(a_C.shape[0]):
        a, z, r, p = a_C[i], z_C[i], radius[i], p_P[i]
        for k in range(xt.shape[1]):
            s, L, lf, beta, C, row = pulley_geometry(xt[:, k], Rt[:, :, k], a, z, r, p)
            Lt[i, k] = L
            Ft[i, k] = lf
            Bt[i, k] = beta
            St[i, k] = s
            for c in range(3):
                Ct[c, i, k] = C[c]
            for c in range(6):
                Jt[c, i, k] = row[c]
            if with_rates:
                rates_t[i, k] = length_rate(row, twt[:, k])


def _time_last(a: np.ndarray) -> np.ndarray:
    """(n_steps, ...) as a C-contiguous (..., n_steps) float array."""
    return np.ascontiguousarray(np.moveaxis(np.asarray(a, dtype=float), 0, -1))


# --------------------------------------------------------------------- over time series


def pulley_kinematics(
    x_PC: np.ndarray,
    R_PC: np.ndarray,
    a_C: np.ndarray,
    z_C: np.ndarray,
    radius: np.ndarray,
    p_P: np.ndarray,
    twist: np.ndarray | None = None,
) -> PulleyKinematics:
    """Cable lengths, exit points, wrap angles, J~ and length rates with swivelling pulleys.

    Parameters
    ----------
    x_PC : ndarray, shape (n_steps, 3)
        Position of P's origin in C, m.
    R_PC : ndarray, shape (n_steps, 3, 3)
        R_P^C.
    a_C : ndarray, shape (n_cables, 3)
        Frame anchors a_i in C, m: the points of the pulleys' rims where the cables arrive
        from their winches (on the swivel axes).
    z_C : ndarray, shape (n_cables, 3)
        Swivel axes z_i in C, unit vectors (within 1e-9): cable i arrives at a_i travelling
        along +z_i.
    radius : float or ndarray, shape (n_cables,)
        Pulley radii r_i >= 0, m. A cable with radius 0 gets the point model's numbers
        (:func:`.kinematics.cable_kinematics` with c_i = a_i) exactly.
    p_P : ndarray, shape (n_cables, 3)
        Platform anchors p_i in P, m.
    twist : ndarray, shape (n_steps, 6), optional
        (v_PC, omega_PC) in C, m/s and rad/s.

    Returns
    -------
    PulleyKinematics
        ``status`` is nonzero, and the other fields NaN, where a platform anchor is on its
        swivel axis or on or inside its pulley (see the module's docstring).

    Raises
    ------
    ValueError
        Shapes that disagree, a non-unit axis, a negative or non-finite radius.
    """
    a_C = np.array(a_C, dtype=float, order="C")
    z_C = np.array(z_C, dtype=float, order="C")
    p_P = np.array(p_P, dtype=float, order="C")
    m = a_C.shape[0] if a_C.ndim == 2 else -1
    if a_C.shape != (m, 3) or z_C.shape != (m, 3) or p_P.shape != (m, 3):
        raise ValueError(f"a_C {a_C.shape}, z_C {z_C.shape} and p_P {p_P.shape} must all be "
                         "(n_cables, 3)")
    radius = np.array(np.broadcast_to(np.asarray(radius, dtype=float), (m,)), order="C")
    if not (np.isfinite(radius).all() and (radius >= 0.0).all()):
        raise ValueError(f"pulley radii must be finite and >= 0 m, got {radius.tolist()}")
    norms = np.linalg.norm(z_C, axis=1)
    if not (np.abs(norms - 1.0) <= 1e-9).all():
        raise ValueError(f"swivel axes z_C must be unit vectors, got norms {norms.tolist()}")
    n = np.shape(x_PC)[0] if np.ndim(x_PC) == 2 else -1
    if np.shape(x_PC) != (n, 3) or np.shape(R_PC) != (n, 3, 3):
        raise ValueError(f"x_PC {np.shape(x_PC)} and R_PC {np.shape(R_PC)} must be (n_steps, 3) "
                         "and (n_steps, 3, 3)")
    xt, Rt = _time_last(x_PC), _time_last(R_PC)
    twt = np.empty((0, n)) if twist is None else _time_last(twist)
    if twist is not None and twt.shape != (6, n):
        raise ValueError(f"twist {np.shape(twist)} must be (n_steps, 6)")
    Lt, Ft, Bt = np.empty((m, n)), np.empty((m, n)), np.empty((m, n))
    St = np.empty((m, n), dtype=np.int64)
    Ct, Jt = np.empty((3, m, n)), np.empty((6, m, n))
    rates_t = np.empty((m if twist is not None else 0, n))
    _pulley_series(xt, Rt, a_C, z_C, radius, p_P, twt, Lt, Ft, Bt, Ct, Jt, St, rates_t)
    return PulleyKinematics(
        lengths=Lt.T,
        free_lengths=Ft.T,
        wrap_angles=Bt.T,
        exits_C=Ct.transpose(2, 1, 0),
        J_tilde=Jt.transpose(2, 1, 0),
        status=St.T,
        length_rates=None if twist is None else rates_t.T,
    )
