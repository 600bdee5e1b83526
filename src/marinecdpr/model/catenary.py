"""The elastic catenary (Irvine's equations), compiled: a sagging cable's end forces.

A cable of unstretched length L0 (m), weight w (N/m of unstretched length) and axial
stiffness EA (N) hangs in a vertical plane between the winch end A (the frame anchor) and
the platform end B (the platform anchor). In that plane A is the origin, x is horizontal
from A towards B and z is up (against gravity), and B is at (h, v): h >= 0 the horizontal
distance (m), v the height of B above A (m, negative when B is below A).

Sign conventions. s in [0, L0] is the unstretched (Lagrangian) arc length from A. The
cable's tension force at s, exerted on the part [0, s] by the part beyond, is (H, V(s)):
along the tangent pointing from A towards B, with

    H            > 0, the same everywhere (no horizontal load),                       N
    V(s)         = V_A + w s  (equilibrium of an element, dV/ds = w),                  N
    V_B = V(L0)  = V_A + w L0,  i.e.  V_A = V_B - w L0,                                N
    T(s)         = sqrt(H^2 + V(s)^2),  T_A = T(0),  T_B = T(L0).                       N

So (H, V_B) is the force the platform exerts ON the cable at B; the cable pulls the
platform with -(H, V_B) (towards A horizontally; upwards when V_B < 0), and pulls the frame
anchor with (H, V_A) (towards B horizontally; the winch feels T_A). A platform held by a
cable from above has V_B < 0 and V_A = V_B - w L0 < V_B: the frame end also carries the
cable's weight. (H, V_A)/T_A and (H, V_B)/T_B are the cable's unit tangents at A and B,
pointing from A towards B.

With Hooke's law on the unstretched length (strain T/EA), dx/ds = (H/T)(1 + T/EA) and
dz/ds = (V/T)(1 + T/EA); integrating from A to B gives the elastic catenary of Irvine
(H. M. Irvine, Cable Structures, MIT Press 1981, section 1.3; the same two equations,
here with A as the origin and V_B the vertical force at the far end):

    h = H L0/EA + (H/w) [asinh(V_B/H) - asinh(V_A/H)]                              (I-1)
    v = (V_B L0 - w L0^2/2)/EA + (H/w) [sqrt(1 + (V_B/H)^2) - sqrt(1 + (V_A/H)^2)]
      = L0 V_m/EA + (T_B - T_A)/w,        V_m = (V_A + V_B)/2                      (I-2)

(V_B L0 - w L0^2/2 = L0 V_m.) Consequences used here and in the tests:

- T_B - T_A = w (v - L0 V_m/EA): w times the rise of the unstretched cable (the rise
  minus its elastic part); V_B - V_A = w L0 exactly.
- (I-1, I-2) are the gradient of the complementary energy
  Phi(H, V_B) = int_0^L0 (T + T^2/(2 EA)) ds, which is convex; their Jacobian (the end's
  flexibility, :func:`catenary_geometry`) is symmetric positive definite,

      dh/dH   = L0/EA + (1/w) int V^2/T^3 dV = L0/EA + (1/w)[asinh(V/H) - V/T]_A^B
      dh/dV_B = dv/dH = (1/w)[H/T]_A^B
      dv/dV_B = L0/EA + (1/w)[V/T]_A^B,

  so (H, V_B) is unique for every h > 0, and Newton's method with a line search on
  Phi - h H - v V_B converges robustly; its inverse is the end's stiffness
  d(H, V_B)/d(h, v)
  (:func:`catenary_stiffness`).
- d(h, v)/dL0 at fixed (H, V_B) = (H, V_A)(1/EA + 1/T_A): paying out cable at A.

Every difference in (I-1, I-2) is evaluated without cancellation (``_asinh_span``,
T_B - T_A = w L0 (V_A + V_B)/(T_A + T_B), ...), so a weightless limit (w = 1e-12 N/m)
gives the straight elastic cable to round-off, and w = 0 is allowed (the straight cable,
closed form). EA = inf is the inextensible catenary.

Functions (numba-compiled, no allocation):

- :func:`catenary_forces`: (H, V_B, ...) from (h, v, L0) by Newton's method (the plant);
- :func:`catenary_unstretched_length`: the L0 giving a tension T_B at the platform at
  (h, v) (planning); :func:`catenary_length_from_end_force`: the L0 at which the end force
  (H, V_B) reaches a horizontal distance h, and the height v it then has;
- :func:`catenary_geometry` (I-1, I-2 and their Jacobian), :func:`catenary_stiffness`,
  :func:`catenary_arc_length`, :func:`catenary_sag`;
- :func:`cable_force_3d`: the force on the platform in 3D for frame and platform anchors
  in a frame whose z is up;

and :func:`catenary_series` runs them over (n,) arrays in a compiled loop;
:func:`catenary_drum_stiffness` gives from it each cable's stiffness at its winch.

Status codes: 0 CONVERGED; 1 NOT_CONVERGED (no convergence within max_iter); 2 SLACK (an
equilibrium that is not a spanning cable: with h = 0 a cable longer than the vertical
distance folds into a loop, H = 0 and V_A < 0 < V_B; with w = 0 a cable no longer than the
chord carries no force; the forces written are that equilibrium's); 3 IMPOSSIBLE (no
equilibrium: an inextensible cable (EA = inf) no longer than the chord, a tension below
the least a geometry allows, or invalid arguments; NaN written).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

__all__ = ["CONVERGED", "NOT_CONVERGED", "SLACK", "IMPOSSIBLE",
           "OUT_H", "OUT_VB", "OUT_VA", "OUT_TA", "OUT_TB", "OUT_DIR_A", "OUT_DIR_B", "OUT_L0", "OUT_ITER",
           "N_OUT", "catenary_forces", "catenary_unstretched_length", "catenary_length_from_end_force",
           "catenary_geometry", "catenary_stiffness", "catenary_arc_length", "catenary_sag", "cable_force_3d",
           "CatenarySeries", "catenary_series", "catenary_drum_stiffness"]

CONVERGED, NOT_CONVERGED, SLACK, IMPOSSIBLE = 0, 1, 2, 3
"""Status codes of the compiled solvers (see the module's docstring)."""

OUT_H, OUT_VB, OUT_VA, OUT_TA, OUT_TB, OUT_DIR_A, OUT_DIR_B, OUT_L0, OUT_ITER = 0, 1, 2, 3, 4, 5, 7, 9, 10
"""Layout of the solvers' ``out`` (N_OUT,): H, V_B, V_A, T_A, T_B (N); the unit tangents at A
(out[5:7]) and at B (out[7:9]), (x, z) in the cable's plane, pointing from A towards B;
L0 (m); the iterations taken."""
N_OUT = 11

_cache = True
_jit = dict(cache=_cache, error_model="numpy")  # x/0 gives inf or NaN (the degenerate cables rely on it)
_EPS = 2.220446049250313e-16


# ------------------------------------------------------------------ Irvine's equations


@njit(**_jit)
def _log1p_over(z, w, scale):
    """log1p(z)/w for z = w * scale >= 0, accurate as w -> 0 (scale = z/w, m/N ... any unit)."""
    if z < 1e-8:
        return scale * (1.0 - z * (0.5 - z / 3.0))
    return np.log1p(z) / w


@njit(**_jit)
def _asinh_span(H, Va, Vb, Ta, Tb, L, w):
    """(asinh(Vb/H) - asinh(Va/H)) / w for Vb - Va = w L >= 0, without cancellation, m/N.

    Same signs: asinh(Vb/H) - asinh(Va/H) = log((Vb + Tb)/(Va + Ta)) = log1p(w L (1 + (Va + Vb)
    /(Ta + Tb))/(Va + Ta)) for Va >= 0 (and its mirror for Vb <= 0), using Tb - Ta = w L (Va +
    Vb)/(Ta + Tb). Opposite signs: the two terms add, no cancellation.
    """
    S = Ta + Tb
    if Va >= 0.0:
        scale = L * (1.0 + (Va + Vb) / S) / (Va + Ta)
        return _log1p_over(w * scale, w, scale)
    if Vb <= 0.0:
        scale = L * (1.0 - (Va + Vb) / S) / (Tb - Vb)
        return _log1p_over(w * scale, w, scale)
    return (np.arcsinh(Vb / H) - np.arcsinh(Va / H)) / w


@njit(**_jit)
def _equations(H, VB, L0, w, EA):
    """(I-1, I-2) and their Jacobian at (H, V_B): (h, v, dh/dH, dh/dV_B (= dv/dH), dv/dV_B,
    V_A, T_A, T_B). H > 0 (or H = 0 with V_A, V_B of one sign), w >= 0."""
    VA = VB - w * L0
    TA = np.hypot(H, VA)
    TB = np.hypot(H, VB)
    S = TA + TB
    P = TA * TB
    V2 = VA + VB  # 2 V_m
    c = L0 / EA  # 0 for an inextensible cable
    Dw = _asinh_span(H, VA, VB, TA, TB, L0, w)  # [asinh(V/H)]_A^B / w; inf for H = 0, V_A < 0 < V_B
    h = H * (c + Dw) if H > 0.0 else 0.0  # (I-1)
    v = 0.5 * V2 * c + L0 * V2 / S  # (I-2): L0 V_m/EA + (T_B - T_A)/w
    # T_A T_B - V_A V_B >= 0, without cancellation when V_A V_B > 0
    if VA * VB > 0.0:
        K = H * H * (H * H + VA * VA + VB * VB) / (P + VA * VB)
    else:
        K = P - VA * VB
    sin_span = L0 * (K + H * H) / (S * P)  # [V/T]_A^B / w
    Jhh = c + Dw - sin_span
    Jhv = -H * L0 * V2 / (S * P)  # [H/T]_A^B / w = -H (T_B - T_A)/(w T_A T_B)
    Jvv = c + sin_span
    return h, v, Jhh, Jhv, Jvv, VA, TA, TB


@njit(**_jit)
def catenary_geometry(H, V_B, L0, w, EA, J=None):
    """Irvine's equations (I-1, I-2): the end B's position from the force at B.

    Parameters
    ----------
    H : float
        Horizontal tension, N (> 0; 0 only for a vertical cable with V_A, V_B of one sign).
    V_B : float
        Vertical force the platform exerts on the cable at B (up positive), N.
    L0 : float
        Unstretched length, m.
    w : float
        Weight per unit unstretched length, N/m (>= 0).
    EA : float
        Axial stiffness, N (inf: inextensible).
    J : ndarray, shape (2, 2), optional
        Written if given: d(h, v)/d(H, V_B), m/N, the end's flexibility (symmetric, positive
        definite).

    Returns
    -------
    h, v : float
        B relative to A: horizontal distance and height, m.
    """
    h, v, Jhh, Jhv, Jvv, VA, TA, TB = _equations(H, V_B, L0, w, EA)
    if J is not None:
        J[0, 0], J[0, 1], J[1, 0], J[1, 1] = Jhh, Jhv, Jhv, Jvv
    return h, v


# --------------------------------------------------------------------- the forward solve


@njit(**_jit)
def _write(out, H, VB, VA, TA, TB, L0, iters):
    """The solvers' results into out (N_OUT,); tangents (0, +-1) for a vertical cable."""
    out[OUT_H], out[OUT_VB], out[OUT_VA], out[OUT_TA], out[OUT_TB] = H, VB, VA, TA, TB
    if H > 0.0:
        out[5], out[6], out[7], out[8] = H / TA, VA / TA, H / TB, VB / TB
    else:  # vertical: the cable leaves A upwards if V_A >= 0, reaches B from below if V_B > 0
        out[5], out[6] = 0.0, 1.0 if VA >= 0.0 else -1.0
        out[7], out[8] = 0.0, 1.0 if VB > 0.0 else -1.0
    out[OUT_L0] = L0
    out[OUT_ITER] = iters


@njit(**_jit)
def _write_nan(out, L0):
    for a in range(N_OUT):
        out[a] = np.nan
    out[OUT_L0] = L0
    out[OUT_ITER] = 0.0


@njit(**_jit)
def _log_sinhc(b):
    """log(sinh(b)/b) and its derivative coth(b) - 1/b, for b >= 0."""
    if b < 1e-3:
        x = b * b
        return x / 6.0 - x * x / 180.0, b / 3.0 - b * x / 45.0
    if b < 20.0:
        return np.log(np.sinh(b) / b), 1.0 / np.tanh(b) - 1.0 / b
    return b - np.log(2.0 * b) + np.log1p(-np.exp(-2.0 * b)), 1.0 / np.tanh(b) - 1.0 / b


@njit(**_jit)
def _inextensible(h, v, L, w):
    """The inextensible catenary's (H, V_B) for h > 0, L > hypot(h, v): with beta = w h/(2H),
    sinh(beta)/beta = sqrt(L^2 - v^2)/h and v/L = tanh(mu), V_B = H sinh(mu + beta)."""
    r = np.sqrt((L - v) * (L + v)) / h
    target = np.log(r)
    b = min(np.sqrt(6.0 * max(r - 1.0, 0.0)), 700.0)  # above the root: sinhc(b) >= 1 + b^2/6
    for _ in range(100):  # Newton from above on a convex increasing function: monotone
        q, dq = _log_sinhc(b)
        step = (q - target) / dq if dq > 0.0 else 0.0
        b -= step
        if not (b > 0.0) or abs(step) <= 1e-12 * b:
            break
    b = max(b, 1e-300)
    H = w * h / (2.0 * b)
    mu = np.arctanh(v / L)
    return H, H * np.sinh(mu + b)


@njit(**_jit)
def _initial_guess(h, v, d, L0, w, EA):
    """A starting (H, V_B) for h > 0, w > 0: the shallow (parabolic) elastic cable, or the
    inextensible catenary for a cable heavy compared with its tension."""
    # Shallow cable along the chord, tension T: its stretched length L0 (1 + T/EA) equals the
    # chord plus the parabola's extra length (w h/d)^2 d^3/(24 T^2):
    #     (L0/EA) T^3 + (L0 - d) T^2 - (w h)^2 d/24 = 0,
    # one positive root; Newton from an upper bound (the cubic is convex there) is monotone.
    a = L0 / EA
    b = L0 - d
    c = (w * h) ** 2 * d / 24.0
    if a == 0.0:
        T = np.sqrt(c / b)
    else:
        T = max(0.0, -b / a) + np.cbrt(c / a)
        if b > 0.0:
            T = min(T, np.sqrt(c / b))
        for _ in range(200):
            p = (a * T + b) * T * T - c
            dp = (3.0 * a * T + 2.0 * b) * T
            if not dp > 0.0:
                break
            step = p / dp
            T -= step
            if abs(step) <= 1e-6 * T:
                break
    if w * L0 <= T or L0 <= d:
        return T * h / d, T * v / d + 0.5 * w * L0
    # heavy: the inextensible catenary, lengthened once by its mean tension's stretch
    H, VB = _inextensible(h, v, L0, w)
    Le = L0 * (1.0 + 0.5 * (np.hypot(H, VB) + np.hypot(H, VB - w * L0)) / EA)
    if Le > L0 and Le < 1e3 * L0:
        H, VB = _inextensible(h, v, Le, w)
    return H, VB


@njit(**_jit)
def _newton(h, v, L0, w, EA, H, VB, max_iter, out):
    """Newton's method on (I-1, I-2) from (H, V_B); writes out, returns the status (0 or 1).

    The residual r = (I-1, I-2) - (h, v) is the gradient of the convex F = Phi - h H - v V_B
    (module docstring), so along the Newton step p, F's slope r(t) . p is increasing and
    negative at t = 0. The step (kept to H's factor 0.1..10) is taken if F still falls at
    its end (r . p <= 0) or |r| falls; else F is minimised along p (secant and bisection on
    its slope to 0.1 of the initial slope). A merit on |r| alone crawls along steep cables'
    narrow valleys; this takes the full step there.
    """
    scale = h + abs(v) + L0
    tol = 8.0 * _EPS * scale
    e = _equations(H, VB, L0, w, EA)
    hh, vv, Jhh, Jhv, Jvv, VA, TA, TB = e
    rh, rv = hh - h, vv - v
    rn = np.hypot(rh, rv)
    status = NOT_CONVERGED
    it = 0
    while True:
        if not np.isfinite(rn):
            break
        if rn <= tol:
            status = CONVERGED
            break
        if it >= max_iter:
            break
        it += 1
        det = Jhh * Jvv - Jhv * Jhv
        pH = -(Jvv * rh - Jhv * rv) / det
        pV = -(Jhh * rv - Jhv * rh) / det
        slope0 = rh * pH + rv * pV  # -r^T J^-1 r < 0
        if not (np.isfinite(pH) and np.isfinite(pV) and slope0 < 0.0):
            break
        t = 1.0
        if H + pH < 0.1 * H:
            t = 0.9 * H / -pH
        elif H + pH > 10.0 * H:
            t = 9.0 * H / pH
        e = _equations(H + t * pH, VB + t * pV, L0, w, EA)
        rht, rvt = e[0] - h, e[1] - v
        slope = rht * pH + rvt * pV
        if not (slope <= 0.0 or np.hypot(rht, rvt) < rn):  # past F's minimum along p (or NaN)
            lo, slo, hi, shi = 0.0, slope0, t, slope
            for j in range(60):
                t = lo - slo * (hi - lo) / (shi - slo)  # secant on the slope, every third bisection
                if not (lo < t < hi) or j % 3 == 2:
                    t = 0.5 * (lo + hi)
                e = _equations(H + t * pH, VB + t * pV, L0, w, EA)
                rht, rvt = e[0] - h, e[1] - v
                slope = rht * pH + rvt * pV
                if abs(slope) <= 0.1 * -slope0:
                    break
                if slope < 0.0:
                    lo, slo = t, slope
                else:
                    hi, shi = t, slope
        rnt = np.hypot(rht, rvt)
        if not np.isfinite(rnt):
            break
        small = abs(t * pH) <= 4.0 * _EPS * H and abs(t * pV) <= 4.0 * _EPS * (H + abs(VB))
        H, VB = H + t * pH, VB + t * pV
        hh, vv, Jhh, Jhv, Jvv, VA, TA, TB = e
        rh, rv, rn = rht, rvt, rnt
        if small:  # the step is round-off: converged if the residual is small
            if rn <= 1e-12 * scale:
                status = CONVERGED
            break
    _write(out, H, VB, VA, TA, TB, L0, it)
    return status


@njit(**_jit)
def catenary_forces(h, v, L0, w, EA, guess, out, max_iter=100):
    """The forces at both ends of an elastic catenary from its ends and length (I-1, I-2).

    Solves (I-1, I-2) for (H, V_B) by Newton's method with the analytic Jacobian
    (:func:`catenary_geometry`), a line search on the convex complementary energy whose
    gradient the residual is, and H kept positive; from the warm start ``guess`` if it is
    usable, else from the shallow elastic cable's tension (the chord stretched by the
    tension plus the parabola's extra length) or, for a cable heavy compared with its
    tension, the inextensible catenary; a failed warm start is retried cold. Converges to
    round-off (|residual| <= 8 eps (h + |v| + L0), eps = 2.2e-16), in 2-8 steps for taut
    cables. Closed forms for h = 0 (a vertical cable) and w = 0 (a straight cable). No
    allocation.

    Parameters
    ----------
    h : float
        Horizontal distance from A (winch/frame end) to B (platform end), m, >= 0.
    v : float
        Height of B above A, m (negative: B below A).
    L0 : float
        Unstretched length, m, > 0.
    w : float
        Weight per unit unstretched length, N/m, >= 0 (in water: the submerged weight).
    EA : float
        Axial stiffness, N, > 0 (inf: inextensible).
    guess : ndarray, shape (2,)
        Warm start (H, V_B), N; ignored unless finite with H > 0. May be ``out[:2]`` (read
        before out is written), so a series can warm-start from the last solution.
    out : ndarray, shape (N_OUT,)
        Written (module constants OUT_*): H, V_B, V_A = V_B - w L0, T_A, T_B (N); the unit
        tangents (x, z) at A and at B, from A towards B; L0 (m); the Newton iterations.
        NaN forces for status 3.
    max_iter : int
        Largest number of Newton steps.

    Returns
    -------
    status : int
        0 converged; 1 not converged; 2 slack (h = 0 and the cable folds into a loop below
        its ends: H = 0, V_A < 0 < V_B; or w = 0 and L0 >= the chord: zero forces, the
        chord's direction as tangents); 3 impossible (EA = inf and L0 <= the chord, or
        invalid arguments).
    """
    g0, g1 = guess[0], guess[1]
    if not (h >= 0.0 and np.isfinite(h) and np.isfinite(v) and L0 > 0.0 and np.isfinite(L0)
            and w >= 0.0 and np.isfinite(w) and EA > 0.0):
        _write_nan(out, L0)
        return IMPOSSIBLE
    d = np.hypot(h, v)
    c = L0 / EA
    if w == 0.0:  # a straight cable: T = EA (d - L0)/L0 along the chord
        if d > L0 and c == 0.0:
            _write_nan(out, L0)
            return IMPOSSIBLE
        T = (d - L0) / c if d > L0 else 0.0
        H, V = (T * h / d, T * v / d) if d > 0.0 else (0.0, 0.0)
        _write(out, H, V, V, T, T, L0, 0)
        if T == 0.0 and d > 0.0:
            out[5], out[6], out[7], out[8] = h / d, v / d, h / d, v / d
        elif d == 0.0:
            out[5], out[6], out[7], out[8] = np.nan, np.nan, np.nan, np.nan
        return CONVERGED if T > 0.0 else SLACK
    if h == 0.0:
        # Vertical (H = 0): v = L0 V_m/EA + (|V_B| - |V_A|)/w. Both V_A, V_B >= 0 (hanging up
        # from B) or <= 0 (down from A): v = L0 V_m/EA -+ L0. Opposite signs: a loop,
        # v = V_m (L0/EA + 2/w).
        Vm = v / (c + 2.0 / w)
        status = SLACK
        if not abs(Vm) < 0.5 * w * L0:
            Vm = (v - L0) / c if v > 0.0 else (v + L0) / c
            status = CONVERGED
            if not np.isfinite(Vm):  # inextensible and |v| >= L0
                _write_nan(out, L0)
                return IMPOSSIBLE
        VB, VA = Vm + 0.5 * w * L0, Vm - 0.5 * w * L0
        _write(out, 0.0, VB, VA, abs(VA), abs(VB), L0, 0)
        return status
    if c == 0.0 and L0 <= d:
        _write_nan(out, L0)
        return IMPOSSIBLE
    if np.isfinite(g0) and np.isfinite(g1) and g0 > 0.0:
        status = _newton(h, v, L0, w, EA, g0, g1, max_iter, out)
        if status == CONVERGED:
            return status
    H, VB = _initial_guess(h, v, d, L0, w, EA)
    return _newton(h, v, L0, w, EA, H, VB, max_iter, out)


# ------------------------------------------------------------------ derived quantities


@njit(**_jit)
def catenary_stiffness(H, V_B, L0, w, EA, K):
    """The end B's stiffness d(H, V_B)/d(h, v), and d(H, V_B)/dL0.

    K is the inverse of (I-1, I-2)'s Jacobian d(h, v)/d(H, V_B) (symmetric positive
    definite). The force on the platform is -(H, V_B), so as a spring the platform anchor
    sees d(force)/d(position of B) = -K in the cable's plane (x horizontal towards B, z up).

    Parameters
    ----------
    H, V_B : float
        The solved forces at B (:func:`catenary_forces`), N.
    L0 : float
        Unstretched length, m.
    w : float
        Weight per unit unstretched length, N/m.
    EA : float
        Axial stiffness, N (inf: inextensible).
    K : ndarray, shape (2, 2)
        Written: [[dH/dh, dH/dv], [dV_B/dh, dV_B/dv]], N/m. For a vertical cable (H = 0)
        the horizontal row/column is 1/(dh/dH) with no coupling.

    Returns
    -------
    dH_dL0, dVB_dL0 : float
        d(H, V_B)/dL0 at fixed (h, v): -K (H, V_A) (1/EA + 1/T_A), N/m (paying out cable).
    """
    h, v, Jhh, Jhv, Jvv, VA, TA, TB = _equations(H, V_B, L0, w, EA)
    if H == 0.0:
        K[0, 0], K[0, 1], K[1, 0], K[1, 1] = 1.0 / Jhh, 0.0, 0.0, 1.0 / Jvv
    else:
        det = Jhh * Jvv - Jhv * Jhv
        K[0, 0], K[0, 1], K[1, 0], K[1, 1] = Jvv / det, -Jhv / det, -Jhv / det, Jhh / det
    g = 1.0 / EA + 1.0 / TA  # d(h, v)/dL0 = (H, V_A) g
    return -(K[0, 0] * H + K[0, 1] * VA) * g, -(K[1, 0] * H + K[1, 1] * VA) * g


@njit(**_jit)
def catenary_arc_length(H, V_B, L0, w, EA):
    """The stretched length of the cable, m: L0 + (1/EA) int_0^L0 T ds.

    int T ds = (1/(2w)) [V T + H^2 asinh(V/H)]_A^B, written without cancellation as
    (1/2) (L0 ((V_A + V_B)^2/(2 S) + S/2) + H^2 [asinh(V/H)]_A^B / w), S = T_A + T_B.

    Parameters
    ----------
    H, V_B : float
        Forces at B, N. L0 : float, m. w : float, N/m. EA : float, N (inf: returns L0).
    """
    VA = V_B - w * L0
    TA, TB = np.hypot(H, VA), np.hypot(H, V_B)
    S = TA + TB
    V2 = VA + V_B
    integral = L0 * (V2 * V2 / (2.0 * S) + 0.5 * S)
    if H > 0.0:
        integral += H * H * _asinh_span(H, VA, V_B, TA, TB, L0, w)
    return L0 + 0.5 * integral / EA


@njit(**_jit)
def _point(H, VA, TA, s, w, EA):
    """The cable's point at unstretched arc length s from A: (x, z), m."""
    Vs = VA + w * s
    Ts = np.hypot(H, Vs)
    c = s / EA
    x = H * (c + _asinh_span(H, VA, Vs, TA, Ts, s, w))
    z = 0.5 * (VA + Vs) * c + s * (VA + Vs) / (TA + Ts)
    return x, z


@njit(**_jit)
def catenary_sag(H, V_B, L0, w, EA):
    """The sag, m: the largest vertical distance of the cable below its chord AB.

    It is where the tangent is parallel to the chord, V = H v/h (d/ds of v x/h - z is
    (1/EA + 1/T)(H v/h - V)), at s = (H v/h - V_A)/w. The chord (h, v) is that of the forces
    (I-1, I-2). For a vertical cable (H = 0): the depth of its lowest point below its lower
    end (0 unless it folds into a loop).

    Parameters
    ----------
    H, V_B : float
        Forces at B (:func:`catenary_forces`), N. L0 : float, m. w : float, N/m (> 0; 0
        returns 0). EA : float, N (inf: inextensible).

    Returns
    -------
    float
        Sag, m, >= 0.
    """
    VA = V_B - w * L0
    if w == 0.0:
        return 0.0
    if H == 0.0:
        if VA < 0.0 < V_B:  # the loop's bottom, V = 0 at s = -V_A/w
            v = L0 * (0.5 * (VA + V_B) / EA) + (V_B + VA) / w
            z_low = -VA * VA / (2.0 * w * EA) + VA / w
            return min(0.0, v) - z_low
        return 0.0
    h, v, Jhh, Jhv, Jvv, VA, TA, TB = _equations(H, V_B, L0, w, EA)
    s = min(max((H * v / h - VA) / w, 0.0), L0)
    x, z = _point(H, VA, TA, s, w, EA)
    return max(0.0, v * x / h - z)


# ------------------------------------------------------------------------- the inverses


@njit(**_jit)
def _tension_slope(out, w, EA, K):
    """dT_B/dL0 at fixed (h, v) from out's forces (catenary_stiffness's d(H, V_B)/dL0)."""
    H, VB, TB = out[OUT_H], out[OUT_VB], out[OUT_TB]
    dH, dV = catenary_stiffness(H, VB, out[OUT_L0], w, EA, K)
    return (H * dH + VB * dV) / TB


@njit(**_jit, inline="always")
def _length_residual(h, v, T, w, EA, L, phi):
    """(I-1, I-2) - (h, v) at (H, V_B) = T (cos phi, sin phi) and L0, with what the Jacobian
    in (phi, L0) needs: (rh, rv, H, V_B, Jhh, Jhv, Jvv, V_A, T_A)."""
    H, VB = T * np.cos(phi), T * np.sin(phi)
    hh, vv, Jhh, Jhv, Jvv, VA, TA, TB = _equations(H, VB, L, w, EA)
    return hh - h, vv - v, H, VB, Jhh, Jhv, Jvv, VA, TA


@njit(**_jit)
def _length_newton(h, v, T, w, EA, L, phi, max_iter):
    """Newton's method on (I-1, I-2) - (h, v) in (phi, L0) with (H, V_B) = T (cos phi, sin phi),
    backtracking on |residual|, steps kept to |dphi| <= 0.5 and L0 within a factor 2; returns
    (converged, L0, phi, iterations). h > 0."""
    scale = h + abs(v) + L
    tol = 8.0 * _EPS * scale
    rh, rv, H, VB, Jhh, Jhv, Jvv, VA, TA = _length_residual(h, v, T, w, EA, L, phi)
    rn = np.hypot(rh, rv)
    it = 0
    for it in range(max_iter):
        if not np.isfinite(rn):
            return False, L, phi, it
        if rn <= tol:
            return True, L, phi, it
        g = 1.0 / EA + 1.0 / TA  # d(h, v)/dL0 = (H, V_A) g
        a11, a12 = -VB * Jhh + H * Jhv, H * g  # d(h)/d(phi, L0)
        a21, a22 = -VB * Jhv + H * Jvv, VA * g  # d(v)/d(phi, L0)
        det = a11 * a22 - a12 * a21
        dphi = -(a22 * rh - a12 * rv) / det
        dL = -(a11 * rv - a21 * rh) / det
        if not (np.isfinite(dphi) and np.isfinite(dL)):
            return False, L, phi, it
        if abs(dphi) <= 4.0 * _EPS and abs(dL) <= 4.0 * _EPS * L:
            return rn <= 1e-12 * scale, L, phi, it
        t = 1.0
        if abs(dphi) > 0.5:
            t = 0.5 / abs(dphi)
        if L + t * dL < 0.5 * L:
            t = 0.5 * L / -dL
        elif L + t * dL > 2.0 * L:
            t = L / dL
        accepted = False
        for _ in range(40):
            e = _length_residual(h, v, T, w, EA, L + t * dL, phi + t * dphi)
            rnt = np.hypot(e[0], e[1])
            if rnt < (1.0 - 1e-4 * t) * rn:
                accepted = True
                break
            t *= 0.5
        if not accepted:
            return rn <= 1e-12 * scale, L, phi, it
        L, phi = L + t * dL, phi + t * dphi
        rh, rv, H, VB, Jhh, Jhv, Jvv, VA, TA = e
        rn = rnt
    return False, L, phi, it


@njit(**_jit)
def catenary_unstretched_length(h, v, T_B, w, EA, out, K, max_iter=100):
    """The unstretched length a winch must pay out for a tension T_B at the platform end.

    With B's position (h, v) fixed only one scalar of B's force can be prescribed (the
    catenary then sets its direction); here the tension T_B = |(H, V_B)|, the quantity a
    tension distribution gives. T_B(L0) at fixed (h, v) falls from infinity (L0 -> 0, or
    L0 -> the chord if inextensible) to a least value and rises again as the cable hangs
    deeper; the root on the falling (taut) branch, the shortest L0, is returned.

    From the shallow elastic cable's length (chord plus the parabola's extra length,
    shortened by the stretch at the mean tension), Newton's method on (I-1, I-2) in
    (phi, L0) with (H, V_B) = T_B (cos phi, sin phi) (smooth where T_B(L0) is steep, near
    the taut limit); if that fails or lands on the rising branch, safeguarded Newton with
    bisection on T_B(L0) - T_B (slope from :func:`catenary_stiffness`), each step a
    warm-started :func:`catenary_forces`. A vertical taut cable (h = 0) is a quadratic in
    L0; a vertical inextensible one (EA = inf) is taut at L0 = |v| for any tension. Near the
    taut limit T_B(L0) is steep: the returned T_B matches to ~eps EA/T_B relative, L0 to
    round-off.

    Parameters
    ----------
    h : float
        Horizontal distance A to B, m, >= 0 (h + |v| > 0).
    v : float
        Height of B above A, m.
    T_B : float
        Required tension at the platform end, N, > 0.
    w : float
        Weight per unit unstretched length, N/m, >= 0.
    EA : float
        Axial stiffness, N (inf: inextensible).
    out : ndarray, shape (N_OUT,)
        Written as by :func:`catenary_forces` at the solution; out[OUT_L0] is the L0 sought,
        m; out[OUT_ITER] the outer iterations.
    K : ndarray, shape (2, 2)
        Scratch; written: the stiffness at the solution (:func:`catenary_stiffness`), N/m.
    max_iter : int
        Largest number of outer iterations.

    Returns
    -------
    status : int
        0 converged (2 if the solution is a vertical cable folded into a loop); 1 not
        converged; 3 impossible: T_B below the least tension the geometry allows with this
        cable (or invalid arguments).
    """
    d = np.hypot(h, v)
    if not (h >= 0.0 and np.isfinite(d) and d > 0.0 and T_B > 0.0 and np.isfinite(T_B) and w >= 0.0
            and np.isfinite(w) and EA > 0.0):
        _write_nan(out, np.nan)
        return IMPOSSIBLE
    if w == 0.0:  # straight: L0 (1 + T/EA) = d
        L = d / (1.0 + T_B / EA)
        _write(out, T_B * h / d, T_B * v / d, T_B * v / d, T_B, T_B, L, 0)
        inv = 1.0 / L
        n0, n1 = h / d, v / d  # K = (EA/L0) n n^T + (T/d)(I - n n^T)
        K[0, 0] = EA * inv * n0 * n0 + T_B / d * (1.0 - n0 * n0)
        K[0, 1] = K[1, 0] = (EA * inv - T_B / d) * n0 * n1
        K[1, 1] = EA * inv * n1 * n1 + T_B / d * (1.0 - n1 * n1)
        return CONVERGED
    if h == 0.0 and EA == np.inf:  # a vertical inextensible cable: taut at L0 = |v| for any tension,
        VB = T_B if v > 0.0 else -T_B  # hanging from A (v < 0) or up from B if T_B >= w v
        if v > 0.0 and T_B < w * v:
            _write_nan(out, np.nan)
            return IMPOSSIBLE
        L = abs(v)
        _write(out, 0.0, VB, VB - w * L, abs(VB - w * L), T_B, L, 0)
        K[0, 0], K[0, 1], K[1, 0], K[1, 1] = 0.0, 0.0, 0.0, np.inf
        return CONVERGED
    if h == 0.0:  # vertical, taut: T_B = EA (|v| - L0)/L0 - w L0/2 hanging from A (v < 0), or
        # T_B = EA (v - L0)/L0 + w L0/2 hanging up from B if V_A = T_B - w L0 >= 0: the smaller
        # root of the quadratic in L0 (else the loop: the bracketed search below)
        a = T_B + EA
        disc = a * a - 2.0 * w * EA * v
        L = 2.0 * EA * abs(v) / (a + np.sqrt(disc)) if disc >= 0.0 else np.nan
        if v < 0.0 or T_B - w * L >= 0.0:
            st = catenary_forces(h, v, L, w, EA, out[:2], out)
            _tension_slope(out, w, EA, K)
            return st
    # shallow elastic cable: L0 (1 + T_m/EA) = d + (w h)^2 d/(24 T_m^2), V_m = T_m v/d
    Tm = max(T_B - 0.5 * w * v, 0.5 * T_B)  # mean tension estimate (T_B - T_A ~ w v)
    L = (d + (w * h) ** 2 * d / (24.0 * Tm * Tm)) / (1.0 + Tm / EA)
    if h > 0.0:
        # Newton on (I-1, I-2) in (phi, L0), (H, V_B) = T_B (cos phi, sin phi): smooth near the
        # taut limit where T_B(L0) is steep; kept if on the taut branch (dT_B/dL0 < 0)
        VB = Tm * v / d + 0.5 * w * L
        ok, L1, phi, n = _length_newton(h, v, T_B, w, EA, L, np.arctan2(VB, Tm * h / d), max_iter)
        if ok:
            out[0], out[1] = T_B * np.cos(phi), T_B * np.sin(phi)
            st = catenary_forces(h, v, L1, w, EA, out[:2], out)
            if (st == CONVERGED or st == SLACK) and _tension_slope(out, w, EA, K) < 0.0:
                out[OUT_ITER] = n
                return st
    # fallback: safeguarded Newton and bisection on T_B(L0) - T_B
    lo, hi, beyond = 0.0, np.inf, np.inf  # T_B(lo) > T_B on the taut branch; T_B(hi) < T_B;
    out[0] = np.nan  # beyond: past the least tension with T_B(beyond) > T_B
    status = NOT_CONVERGED
    it = 0
    for it in range(1, max_iter + 1):
        st = catenary_forces(h, v, L, w, EA, out[:2], out)
        if st == NOT_CONVERGED:
            break
        if st == IMPOSSIBLE:  # inextensible, L <= the chord: too short
            lo = L
            right = min(hi, beyond)
            L = 0.5 * (lo + right) if right < np.inf else 2.0 * L
            out[0] = np.nan
            continue
        f = out[OUT_TB] - T_B
        fp = _tension_slope(out, w, EA, K)
        if f > 0.0:
            if fp < 0.0:
                lo = L
            else:
                beyond = min(beyond, L)
        else:
            hi = L
        right = min(hi, beyond)
        Lnew = L - f / fp if fp < 0.0 else np.nan
        newton = lo < Lnew < right
        if not newton:
            Lnew = 0.5 * (lo + right) if right < np.inf else 2.0 * L
        if abs(f) <= 1e-13 * T_B or (newton and abs(Lnew - L) <= 4.0 * _EPS * L) or hi - lo <= 4.0 * _EPS * L:
            status = st  # T_B reached, or L resolved to round-off (T_B(L)'s own round-off can be larger)
            break
        if hi == np.inf and beyond < np.inf and beyond - lo <= 1e-13 * beyond:
            status = IMPOSSIBLE  # bisected onto the least tension, still above T_B
            break
        L = Lnew
    out[OUT_ITER] = it
    return status


@njit(**_jit)
def catenary_length_from_end_force(h, H, V_B, w, EA, max_iter=100):
    """The L0 at which a cable with the force (H, V_B) at B spans the horizontal distance h.

    With the full force at B prescribed the cable's shape from B is fixed, so h (or v) sets
    L0 and the other coordinate follows: (I-1) is increasing in L0 (dh/dL0 = H (1/EA +
    1/T_A)) and is solved by safeguarded Newton; v then comes from (I-2). Inextensible
    (EA = inf) it is explicit: L0 = (V_B - H sinh(asinh(V_B/H) - w h/H))/w.

    Parameters
    ----------
    h : float
        Horizontal distance A to B, m, > 0.
    H : float
        Horizontal force, N, > 0.
    V_B : float
        Vertical force on the cable at B (up positive), N.
    w : float
        Weight per unit unstretched length, N/m, > 0.
    EA : float
        Axial stiffness, N (inf: inextensible).
    max_iter : int
        Largest number of Newton steps.

    Returns
    -------
    status : int
        0 converged, 1 not converged, 3 invalid arguments.
    L0 : float
        Unstretched length, m.
    v : float
        The height of B above A that the cable then has, m.
    """
    if not (h > 0.0 and np.isfinite(h) and H > 0.0 and np.isfinite(H) and np.isfinite(V_B) and w > 0.0
            and np.isfinite(w) and EA > 0.0):
        return IMPOSSIBLE, np.nan, np.nan
    if EA == np.inf:  # asinh(V_A/H) = asinh(V_B/H) - w h/H
        L = (V_B - H * np.sinh(np.arcsinh(V_B / H) - w * h / H)) / w
        return CONVERGED, L, _equations(H, V_B, L, w, EA)[1]
    TB = np.hypot(H, V_B)
    L = h * TB / (H * (1.0 + TB / EA))  # straight along B's tangent
    lo, hi = 0.0, np.inf
    status = NOT_CONVERGED
    for _ in range(max_iter):
        e = _equations(H, V_B, L, w, EA)
        g = e[0] - h
        if g > 0.0:
            hi = L
        else:
            lo = L
        gp = H * (1.0 / EA + 1.0 / e[6])
        Lnew = L - g / gp
        if not lo < Lnew < hi:
            Lnew = 0.5 * (lo + hi) if hi < np.inf else 2.0 * L
        if abs(g) <= 4.0 * _EPS * (h + L):
            status = CONVERGED
            break
        if abs(Lnew - L) <= 4.0 * _EPS * L:
            status = CONVERGED
            L = Lnew
            break
        L = Lnew
    return status, L, _equations(H, V_B, L, w, EA)[1]


# ---------------------------------------------------------------------------------- 3D


@njit(**_jit)
def cable_force_3d(a, b, L0, w, EA, guess, force, out, max_iter=100):
    """A catenary cable's force on the platform in 3D, and the winch's tension.

    The cable hangs in the vertical plane through a and b; e_h is the horizontal unit vector
    from a towards b. The platform anchor b feels -(H e_h + V_B e_z); the frame anchor a
    feels H e_h + V_A e_z (the two sum to the cable's weight, -w L0 e_z).

    Parameters
    ----------
    a : ndarray, shape (3,)
        The frame (winch) anchor, m, in a frame whose z points up, against gravity (rotate
        gravity's direction to -z first, e.g. with R_SO^T in C on a rolling ship).
    b : ndarray, shape (3,)
        The platform anchor, m, same frame.
    L0 : float
        Unstretched length paid out, m.
    w : float
        Weight per unit unstretched length, N/m (the component of gravity along -z).
    EA : float
        Axial stiffness, N (inf: inextensible).
    guess : ndarray, shape (2,)
        Warm start (H, V_B), N (:func:`catenary_forces`); may be ``out[:2]``.
    force : ndarray, shape (3,)
        Written: the cable's force on the platform, N; NaN for status 3.
    out : ndarray, shape (N_OUT,)
        Written as by :func:`catenary_forces`; out[OUT_TA] is the tension at the winch, N.
    max_iter : int
        Largest number of Newton steps.

    Returns
    -------
    status : int
        As :func:`catenary_forces`.
    """
    dx, dy, dz = b[0] - a[0], b[1] - a[1], b[2] - a[2]
    h = np.hypot(dx, dy)
    status = catenary_forces(h, dz, L0, w, EA, guess, out, max_iter)
    H, VB = out[OUT_H], out[OUT_VB]
    ex, ey = (dx / h, dy / h) if h > 0.0 else (0.0, 0.0)
    force[0], force[1], force[2] = -H * ex, -H * ey, -VB
    return status


# -------------------------------------------------------------- over a series, compiled


@njit(**_jit)
def _series(h, v, given, w, EA, inverse, max_iter, out, status, sag, arc, K, dF):
    """catenary_forces (inverse False: given = L0) or catenary_unstretched_length (given =
    T_B) at every step, the forward solve warm-started from the last converged step; also the
    sag, the stretched length, the stiffness and d(H, V_B)/dL0. All arrays (n,) or (n, ...)."""
    for s in range(h.shape[0]):
        row = out[s]
        if inverse:
            st = catenary_unstretched_length(h[s], v[s], given[s], w[s], EA[s], row, K[s], max_iter)
        else:
            if s > 0 and status[s - 1] == CONVERGED:
                row[0], row[1] = out[s - 1, 0], out[s - 1, 1]
            else:
                row[0] = np.nan
            st = catenary_forces(h[s], v[s], given[s], w[s], EA[s], row[:2], row, max_iter)
        status[s] = st
        if st == CONVERGED or st == SLACK:  # degenerate stiffnesses (zero tension) come out NaN/inf
            H, VB, L0 = row[OUT_H], row[OUT_VB], row[OUT_L0]
            sag[s] = catenary_sag(H, VB, L0, w[s], EA[s])
            arc[s] = catenary_arc_length(H, VB, L0, w[s], EA[s])
            dF[s, 0], dF[s, 1] = catenary_stiffness(H, VB, L0, w[s], EA[s], K[s])
        else:
            sag[s] = arc[s] = np.nan
            K[s, :, :] = np.nan
            dF[s, :] = np.nan


@dataclass(frozen=True)
class CatenarySeries:
    """Elastic catenaries over a series, in each cable's vertical plane (x from A towards B,
    z up).

    Attributes
    ----------
    H, V_B, V_A, T_A, T_B : ndarray, shape (n,)
        Horizontal force; vertical force on the cable at B and at A (V_A = V_B - w L0, up
        positive, along the tangent from A towards B); tensions at A (the winch) and B (the
        platform), N. The cable pulls the platform with -(H, V_B).
    dir_A, dir_B : ndarray, shape (n, 2)
        Unit tangents (x, z) at A and B, pointing from A towards B.
    L0 : ndarray, shape (n,)
        Unstretched length (given, or solved for the tension), m.
    status : ndarray, shape (n,), int
        0 converged, 1 not converged, 2 slack, 3 impossible (module docstring).
    iterations : ndarray, shape (n,), int
        Newton (forward) or outer (inverse) iterations.
    sag : ndarray, shape (n,)
        Largest vertical distance below the chord, m (:func:`catenary_sag`).
    arc_length : ndarray, shape (n,)
        Stretched length, m.
    stiffness : ndarray, shape (n, 2, 2)
        d(H, V_B)/d(h, v), N/m (:func:`catenary_stiffness`); NaN where not defined.
    dF_dL0 : ndarray, shape (n, 2)
        d(H, V_B)/dL0 at fixed ends, N/m.
    """

    H: np.ndarray
    V_B: np.ndarray
    V_A: np.ndarray
    T_A: np.ndarray
    T_B: np.ndarray
    dir_A: np.ndarray
    dir_B: np.ndarray
    L0: np.ndarray
    status: np.ndarray
    iterations: np.ndarray
    sag: np.ndarray
    arc_length: np.ndarray
    stiffness: np.ndarray
    dF_dL0: np.ndarray


def catenary_series(h, v, w, EA, *, L0=None, T_B=None, max_iter=100) -> CatenarySeries:
    """Elastic catenaries over (n,) arrays: the forces for lengths L0, or the lengths for
    platform tensions T_B (exactly one of the two), in a compiled loop.

    Parameters
    ----------
    h : array_like, shape (n,) or scalar
        Horizontal distance from the frame anchor A to the platform anchor B, m, >= 0.
    v : array_like, shape (n,) or scalar
        Height of B above A, m.
    w : array_like, shape (n,) or scalar
        Weight per unit unstretched length, N/m.
    EA : array_like, shape (n,) or scalar
        Axial stiffness, N (inf: inextensible).
    L0 : array_like, shape (n,) or scalar, optional
        Unstretched lengths, m: solve for the forces (:func:`catenary_forces`, each step
        warm-started from the last).
    T_B : array_like, shape (n,) or scalar, optional
        Tensions at the platform end, N: solve for L0 (:func:`catenary_unstretched_length`).
    max_iter : int
        Largest number of iterations per step.

    Returns
    -------
    CatenarySeries
        Arrays of the broadcast length n; H, ..., L0 are views of one (n, N_OUT) buffer.
    """
    if (L0 is None) == (T_B is None):
        raise ValueError("give exactly one of L0 (solve for the forces) and T_B (solve for L0)")
    given = L0 if T_B is None else T_B
    arrays = np.broadcast_arrays(*(np.atleast_1d(np.asarray(x, dtype=float)) for x in (h, v, given, w, EA)))
    if arrays[0].ndim != 1:
        raise ValueError(f"h, v, w, EA and L0/T_B must broadcast to shape (n,), got {arrays[0].shape}")
    h_, v_, g_, w_, EA_ = (np.ascontiguousarray(x) for x in arrays)
    n = h_.shape[0]
    out = np.empty((n, N_OUT))
    status = np.empty(n, dtype=np.int64)
    sag, arc = np.empty(n), np.empty(n)
    K, dF = np.full((n, 2, 2), np.nan), np.full((n, 2), np.nan)
    _series(h_, v_, g_, w_, EA_, T_B is not None, int(max_iter), out, status, sag, arc, K, dF)
    return CatenarySeries(H=out[:, OUT_H], V_B=out[:, OUT_VB], V_A=out[:, OUT_VA], T_A=out[:, OUT_TA],
                          T_B=out[:, OUT_TB], dir_A=out[:, OUT_DIR_A:OUT_DIR_A + 2],
                          dir_B=out[:, OUT_DIR_B:OUT_DIR_B + 2], L0=out[:, OUT_L0], status=status,
                          iterations=out[:, OUT_ITER].astype(np.int64), sag=sag, arc_length=arc, stiffness=K,
                          dF_dL0=dF)


def catenary_drum_stiffness(h, v, L0, w, EA) -> np.ndarray:
    """Each cable's stiffness at its winch: -dT_A/dL0 with both ends held, N/m, what a
    winch's tension loop acts on (E A L / L0^2 for a straight cable; less where the cable
    sags: its weight lets it trade length for sag). From :func:`catenary_series`'s
    d(H, V_B)/dL0 and V_A = V_B - w L0::

        dT_A/dL0 = (H dH/dL0 + V_A (dV_B/dL0 - w)) / T_A

    Parameters
    ----------
    h, v : array_like, shape (n,) or scalar
        The platform anchor's horizontal distance from the winch's and its height above it, m.
    L0 : array_like, shape (n,) or scalar
        Unstretched lengths, m.
    w, EA : array_like, shape (n,) or scalar
        Weight per unit unstretched length, N/m; axial stiffness, N.

    Returns
    -------
    ndarray, shape (n,)
        N/m; NaN where the catenary does not converge (status != 0) or is vertical.
    """
    cat = catenary_series(h, v, w, EA, L0=L0)
    w = np.broadcast_to(np.asarray(w, dtype=float), cat.H.shape)
    dH, dVB = cat.dF_dL0[:, 0], cat.dF_dL0[:, 1]
    with np.errstate(invalid="ignore", divide="ignore"):
        k = -(cat.H * dH + cat.V_A * (dVB - w)) / cat.T_A
    return np.where(cat.status == 0, k, np.nan)
