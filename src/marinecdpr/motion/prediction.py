"""Short-horizon prediction of the ship's motion from motion-sensor (MRU) samples, online.

The controller needs the ship's coordinates eta = (surge, sway, heave, roll, pitch, yaw)
(m, rad; :mod:`~marinecdpr.motion.ship`) with eta' and eta'' at the present instant and a
little ahead (feed-forward), but the MRU reports them at 100-200 Hz and 10-100 ms late.
This module predicts them from the sample stream, each DOF on its own, with compiled
functions that allocate nothing, so that a 1 kHz loop can call them every step.

Method
------
**Sub-grid.** Each accepted sample (t_k; eta, eta', eta'') is interpolated onto a fixed
sub-grid t = n delta (absolute multiples of delta = step_s / n_sub, about 10 ms by default)
by the quintic Hermite polynomial (5) between it and the previous sample (it matches eta,
eta', eta'' at both ends; error O(dt^6)), so the MRU rate need not be known, may jitter
and need not divide ``step_s``. Every n_sub-th sub-grid point is a point t_n = n h of the
AR grid, h = step_s: the stream is decimated to h exactly at the grid points.

**AR model, one per DOF**, with an intercept, on y = eta - eta_0 (eta_0: the first sample,
a fixed reference that keeps the regression well scaled)::

    y(t) = sum_{i=1..p} a_i y(t - i h) + c                                     (1)

If (1) holds for every t (it does exactly for a constant plus up to p/2 sinusoids of any
frequencies), differentiating it gives the same recursion, without c, for the derivatives::

    y'(t) = sum_i a_i y'(t - i h),    y''(t) = sum_i a_i y''(t - i h)              (2)

so one set of coefficients, fitted on eta, forecasts all three channels from their own
histories (derived rather than fitted per channel: a third of the fitting cost, and the
measured eta' and eta'' enter the forecast of the derivatives directly).

**Fit: recursive least squares with directional forgetting** (Kulhavy's restricted
exponential forgetting), at every AR grid point t_n, on the regressor
phi = (y_{n-1}, ..., y_{n-p}, s) (s: the DOF's scale, the intercept's regressor) and the
target y_n::

    e = y_n - theta' phi,   u = P phi,   r = phi' u
    theta <- theta + u e / (lambda + r)                                        (3)
    P     <- P - beta u u' / (lambda + r),   beta = 1 - (1 - lambda) / r       (4)

In information form (R = P^-1) this is R <- R - (1 - lambda)/r phi phi' + phi phi': a
fraction (1 - lambda) of the information along phi is forgotten before the sample is
added, and none along the directions the data do not excite. Plain exponential forgetting
(P <- (P - u u'/(lambda + r)) / lambda) would blow P up as lambda^-n along those (a
sinusoid excites 2 of p directions) and the fit with it. The memory along the excited
directions is about 1/(1 - lambda) AR steps (lambda = 0.998, h = 0.25 s: about 2 min of
sea). P starts at p0 / s^2 I, s the RMS of the first regressor: a weak prior (p0 = 1e10),
because the fine structure of a smooth record lies in directions carrying 1e-6-1e-9 of
its variance, which a stronger prior would wash out.

**Forecast, anchored at the latest sample** t_L. The history y(t_L - k h), k = 1..H-1
(H = max(p, 4)), is interpolated from the sub-grid by (5) (the fraction is the same for
every k); y(t_L) is the sample itself; (1) and (2) are iterated to the points t_L + j h,
j = 1, 2, ... (once per sample, on demand, and kept for the next calls). A target
t_L + (j - 1 + s) h, 0 < s <= 1, falls between the points a = j - 1 and b = j (point 0:
the last sample as measured, points < 0: the history), so the shortest horizons are
interpolated between the sample and the first forecast. Each output is interpolated from
its own and higher channels only: a second derivative taken from values would turn a small
error of a forecast value into a large one (a cubic Hermite's scales it by 6/h^2)::

    eta   = H0 y_a + H1 h y'_a + H2 h^2 y''_a + H5 y_b + H4 h y'_b + H3 h^2 y''_b   (5)
            H0 = 1 - 10 s^3 + 15 s^4 - 6 s^5     H5 = 10 s^3 - 15 s^4 + 6 s^5
            H1 = s - 6 s^3 + 8 s^4 - 3 s^5       H4 = -4 s^3 + 7 s^4 - 3 s^5
            H2 = (s^2 - 3 s^3 + 3 s^4 - s^5)/2  H3 = (s^3 - 2 s^4 + s^5)/2
    eta'  = q(s), q of degree 7 with q = y' and dq/ds = h y'' at the points
            a-1, a, b, b+1 (nodes s = -1, 0, 1, 2)                                   (6)
    eta'' = sum_{k=-3..4} L_k(s) y''_{a+k},  L_k the Lagrange basis on nodes -3..4     (7)

At a whole multiple of h the forecast is the AR's own; between, the interpolation adds
at most about (omega h)^6 / 46000 (eta), 1e-5 (omega h)^8 (eta') and 1e-3 (omega h)^8
(eta'') of a component of frequency omega (h = 0.25 s, omega = 1.5 rad/s: 6e-8, 4e-9,
4e-7).

Before the model has fitted ``warmup_fits`` AR steps (and after a gap in the stream, until
the history is full again) the forecast is the kinematic (Taylor) extrapolation::

    eta(t_L + dt) = eta + dt eta' + dt^2/2 eta'',  eta' + dt eta'',  eta''     (8)

also available alone as :func:`taylor_forecast`.

Choosing the parameters: h at most about 1/omega_max of the motion, and p h a good part of
the dominant period: a short span makes the regression ill-conditioned (h = 0.1 s with
p = 12 spans 1.2 s, over which three sinusoids of 6-15 s periods differ by 1e-12 of the
regressors' variance, under the round-off of the RLS; h = 0.25 s, p = 20: 3e-6). For
ship motion (periods 5-20 s): h = 0.25 s, p = 20, lambda = 0.998. On a noise-free
JONSWAP record (Hs 2 m, Tp 8 s, 150 deg, the built-in box hull's BEM RAOs, MRU at 100 Hz)
this predicts eta with an RMS error of 1-4e-4 of the motion's RMS at 1 s, 2-7e-3 at 2 s
and 7-27 % at 5 s (``tests/motion/test_prediction.py``). Sensor noise dominates as soon as there
is any: white noise of 0.1 % of the RMS on every sample gives 1-3 % at 1 s, 1 % noise
5-8 %, no better than the Taylor extrapolation up to 1 s. :func:`prediction_error`
measures a record, with noise if wanted.

Why an AR/RLS and not a Kalman filter on a bank of wave components: the AR needs no
frequencies chosen in advance (a bank must cover the encounter spectrum with enough lines
and cannot follow a line between them exactly), adapts to the sea state by itself through
the forgetting, and costs O(p^2) per DOF per AR step and O(p) per DOF per forecast point.
Its limits: it has no noise model (noise in the samples biases the fit, is amplified by
the AR's iteration and enters the short forecasts through the last sample as it is; a
noisy MRU wants its stream smoothed first, or a Kalman filter), and with the weak prior it
trusts the record's fine structure: a synthetic record made of a finite sum of sinusoids is
far more predictable than the sea.

Records are ``NamedTuple`` of numpy arrays and numbers, so the compiled functions take
them as one typed argument. Times are in s and should stay near the record's origin (an
epoch time in s leaves only about 0.2 microseconds of resolution).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numba import njit

__all__ = [
    "Predictor",
    "make_predictor",
    "predictor_update",
    "predictor_forecast",
    "predictor_ready",
    "taylor_forecast",
    "PredictionError",
    "prediction_error",
]

_cache = True
# The per-step functions are compiled without numba's runtime (_nrt=False): they cannot
# allocate (numba refuses to compile an allocation there), and they skip the reference
# counting of the record's arrays on every call (about 0.2 microseconds per call).

# slots of Predictor.ints
_NEXT = 0  # absolute index n of the next sub-grid point to fill (its time n * sub_s)
_RUN = 1  # consecutive sub-grid points held (since the first sample or the last gap)
_FITS = 2  # RLS steps done
_SAMPLES = 3  # samples accepted
_CACHED = 4  # forecast points computed for the latest sample (-1: history not gathered)
_RESETS = 5  # covariance resets (a numerical safeguard; 0 in normal use)
_N_INTS = 6

MODEL, TAYLOR, NONE = 1, 0, -1
"""What :func:`predictor_forecast` returns: the AR model was used, the Taylor fallback
(warm-up, or a target before the last sample), or nothing (NaN: no sample yet, or a target
beyond ``max_horizon_s``)."""


def _hermite7_basis() -> np.ndarray:
    """C (8, 8): the degree-7 polynomial q(s) = sum_i s^i sum_k C[i, k] v_k that takes the
    values v_0..v_3 at s = -1, 0, 1, 2 and the slopes v_4..v_7 there (used by (6))."""
    nodes = np.array([-1.0, 0.0, 1.0, 2.0])
    k = np.arange(8)
    V = np.zeros((8, 8))
    V[:4] = nodes[:, None] ** k
    V[4:] = k * np.where(k > 0, nodes[:, None], 1.0) ** np.maximum(k - 1, 0)
    return np.linalg.solve(V, np.eye(8))


_H7 = _hermite7_basis()
_L8_NODES = np.arange(-3.0, 5.0)
_L8_DEN = np.array([np.prod([x - y for y in _L8_NODES if y != x]) for x in _L8_NODES])


class Predictor(NamedTuple):
    """The predictor's parameters and state (made by :func:`make_predictor`). n_dof DOFs, AR
    order p, H = max(p, 4) history points, J = ceil(max_horizon_s / step_s) forecast points,
    L = (H + 1) n_sub + 2 sub-grid points held.

    Parameters: step_s (h, s), sub_s (delta = h / n_sub, s), n_sub, order (p), forgetting
    (lambda), p0 (initial covariance times the DOF's variance), warmup_fits (AR steps
    fitted before the model is used), n_ahead (J), n_hist (H), max_gap_s (a longer gap
    between samples restarts the history, s).

    State: ints (6,) int64 counters (the ``_NEXT``, ``_RUN``, ... slots); last_t (1,) the
    last sample's time, s; last (3, n_dof) its eta, eta', eta'' (m or rad, per s, per s^2);
    ref (n_dof,) eta_0, the first sample; scale (n_dof,) s, the RMS of the first regressor
    (0 until the first fit); sub (L, 3, n_dof) the sub-grid ring of y = eta - eta_0, eta',
    eta''; theta (n_dof, p + 1) a_1..a_p and c / s; P (n_dof, p + 1, p + 1) their
    covariance; phi, u (p + 1,), w (3, 6) and wf (4, 8) scratch; traj (H + J + 4, 3, n_dof)
    y, y', y'' at t_L - k h, k = H-1..0, then at the forecast points j = 1..J+3.
    """

    step_s: float
    sub_s: float
    n_sub: int
    order: int
    forgetting: float
    p0: float
    warmup_fits: int
    n_ahead: int
    n_hist: int
    max_gap_s: float
    ints: np.ndarray
    last_t: np.ndarray
    last: np.ndarray
    ref: np.ndarray
    scale: np.ndarray
    sub: np.ndarray
    theta: np.ndarray
    P: np.ndarray
    phi: np.ndarray
    u: np.ndarray
    w: np.ndarray
    wf: np.ndarray
    traj: np.ndarray


def make_predictor(
    *,
    step_s: float,
    order: int,
    forgetting: float,
    n_dof: int = 6,
    sub_steps: int | None = None,
    max_horizon_s: float = 10.0,
    warmup_fits: int | None = None,
    p0: float = 1.0e10,
    max_gap_s: float | None = None,
) -> Predictor:
    """A new predictor, empty (its forecasts are NaN until the first sample).

    Parameters
    ----------
    step_s : float
        h, the AR model's time step, s (> 0): 0.25 s suits ship motion (periods 5-20 s;
        module docstring).  The AR spans order x step_s of history.
    order : int
        p, the AR order (>= 1): at least twice the number of spectral lines to follow
        (20 for a sea).
    forgetting : float
        lambda in (0, 1]: the fit remembers about 1 / (1 - lambda) AR steps along the
        directions the data excite (1: never forgets).
    n_dof : int
        DOFs predicted (6: surge, sway, heave, roll, pitch, yaw).
    sub_steps : int, optional
        n_sub, sub-grid points per AR step (default: the sub-grid about 10 ms).
    max_horizon_s : float
        The longest forecast, s, from the last sample (> 0; forecasts further are NaN).
    warmup_fits : int, optional
        AR steps fitted before the model is used (default 10 (p + 1)); the Taylor
        extrapolation serves until then.
    p0 : float
        Initial covariance P = p0 / s^2 I (> 0; s: the DOF's first RMS): the prior's weight
        is 1 / p0 of one sample's. Smaller regularises more (and blurs the fine structure
        of the fit); at 1e12 the round-off of (4) showed (covariance resets).
    max_gap_s : float, optional
        A gap between samples longer than this (s; default step_s) restarts the history
        (not the fit): Taylor serves until H AR steps of history have arrived again.

    Returns
    -------
    Predictor
    """
    h = float(step_s)
    if not (np.isfinite(h) and h > 0.0):
        raise ValueError(f"step_s must be finite and > 0; got {step_s}")
    if int(order) != order or order < 1:
        raise ValueError(f"order must be an integer >= 1; got {order}")
    if not (0.0 < forgetting <= 1.0):
        raise ValueError(f"forgetting must be in (0, 1]; got {forgetting}")
    if int(n_dof) != n_dof or n_dof < 1:
        raise ValueError(f"n_dof must be an integer >= 1; got {n_dof}")
    if not (np.isfinite(max_horizon_s) and max_horizon_s > 0.0):
        raise ValueError(f"max_horizon_s must be finite and > 0; got {max_horizon_s}")
    if not (np.isfinite(p0) and p0 > 0.0):
        raise ValueError(f"p0 must be finite and > 0; got {p0}")
    p = int(order)
    m = max(1, int(round(h / 0.01))) if sub_steps is None else int(sub_steps)
    if m < 1:
        raise ValueError(f"sub_steps must be >= 1; got {sub_steps}")
    warm = 10 * (p + 1) if warmup_fits is None else int(warmup_fits)
    if warm < 1:
        raise ValueError(f"warmup_fits must be >= 1; got {warmup_fits}")
    gap = h if max_gap_s is None else float(max_gap_s)
    if not gap > 0.0:
        raise ValueError(f"max_gap_s must be > 0; got {max_gap_s}")
    n_ahead = int(math.ceil(max_horizon_s / h - 1e-9))
    n_dof = int(n_dof)
    n_hist = max(p, 4)
    ring = (n_hist + 1) * m + 2
    ints = np.zeros(_N_INTS, dtype=np.int64)
    ints[_CACHED] = -1
    return Predictor(
        step_s=h, sub_s=h / m, n_sub=m, order=p, forgetting=float(forgetting), p0=float(p0),
        warmup_fits=warm, n_ahead=n_ahead, n_hist=n_hist, max_gap_s=gap,
        ints=ints, last_t=np.zeros(1), last=np.zeros((3, n_dof)), ref=np.zeros(n_dof),
        scale=np.zeros(n_dof), sub=np.zeros((ring, 3, n_dof)), theta=np.zeros((n_dof, p + 1)),
        P=np.zeros((n_dof, p + 1, p + 1)), phi=np.zeros(p + 1), u=np.zeros(p + 1),
        w=np.zeros((3, 6)), wf=np.zeros((4, 8)), traj=np.zeros((n_hist + n_ahead + 4, 3, n_dof)),
    )


# --------------------------------------------------------------------------- compiled
@njit(cache=_cache, _nrt=False, inline="always")
def _hermite5_weights(s, w):
    """w (3, 6): the quintic Hermite basis (5) at s in [0, 1] (row 0) and its first and
    second derivatives in s (rows 1, 2), for the values (y_a, y'_a, y''_a, y_b, y'_b, y''_b)
    scaled by (1, D, D^2, 1, D, D^2), D the interval."""
    s2 = s * s
    s3 = s2 * s
    s4 = s3 * s
    s5 = s4 * s
    w[0, 0] = 1.0 - 10.0 * s3 + 15.0 * s4 - 6.0 * s5
    w[0, 1] = s - 6.0 * s3 + 8.0 * s4 - 3.0 * s5
    w[0, 2] = 0.5 * (s2 - 3.0 * s3 + 3.0 * s4 - s5)
    w[0, 3] = 10.0 * s3 - 15.0 * s4 + 6.0 * s5
    w[0, 4] = -4.0 * s3 + 7.0 * s4 - 3.0 * s5
    w[0, 5] = 0.5 * (s3 - 2.0 * s4 + s5)
    w[1, 0] = -30.0 * s2 + 60.0 * s3 - 30.0 * s4
    w[1, 1] = 1.0 - 18.0 * s2 + 32.0 * s3 - 15.0 * s4
    w[1, 2] = s - 4.5 * s2 + 6.0 * s3 - 2.5 * s4
    w[1, 3] = 30.0 * s2 - 60.0 * s3 + 30.0 * s4
    w[1, 4] = -12.0 * s2 + 28.0 * s3 - 15.0 * s4
    w[1, 5] = 1.5 * s2 - 4.0 * s3 + 2.5 * s4
    w[2, 0] = -60.0 * s + 180.0 * s2 - 120.0 * s3
    w[2, 1] = -36.0 * s + 96.0 * s2 - 60.0 * s3
    w[2, 2] = 1.0 - 9.0 * s + 18.0 * s2 - 10.0 * s3
    w[2, 3] = 60.0 * s - 180.0 * s2 + 120.0 * s3
    w[2, 4] = -24.0 * s + 84.0 * s2 - 60.0 * s3
    w[2, 5] = 3.0 * s - 12.0 * s2 + 10.0 * s3


@njit(cache=_cache, _nrt=False, inline="always")
def _hermite5_apply(w, D, ya, yda, ydda, yb, ydb, yddb, rows):
    """(5) with weights w over an interval D: value (rows = 1), and first (2) and second
    (3) derivatives in time; returns the three (unused ones 0)."""
    va = ya
    vda = D * yda
    vdda = D * D * ydda
    vb = yb
    vdb = D * ydb
    vddb = D * D * yddb
    y = w[0, 0] * va + w[0, 1] * vda + w[0, 2] * vdda + w[0, 3] * vb + w[0, 4] * vdb + w[0, 5] * vddb
    yd = 0.0
    ydd = 0.0
    if rows > 1:
        yd = (w[1, 0] * va + w[1, 1] * vda + w[1, 2] * vdda + w[1, 3] * vb + w[1, 4] * vdb
              + w[1, 5] * vddb) / D
    if rows > 2:
        ydd = (w[2, 0] * va + w[2, 1] * vda + w[2, 2] * vdda + w[2, 3] * vb + w[2, 4] * vdb
               + w[2, 5] * vddb) / (D * D)
    return y, yd, ydd


@njit(cache=_cache, _nrt=False)
def taylor_forecast(t_s, eta, eta_d, eta_dd, t_target, out):
    """The kinematic (Taylor) extrapolation of one sample, (8).

    Parameters
    ----------
    t_s : float
        The sample's time, s.
    eta, eta_d, eta_dd : ndarray, shape (n_dof,)
        eta (m, rad), eta' (m/s, rad/s) and eta'' (m/s^2, rad/s^2) at t_s, in the
        frames of :mod:`~marinecdpr.motion.ship`.
    t_target : float
        The time predicted for, s (any; before t_s it extrapolates backwards).
    out : ndarray, shape (3, n_dof)
        Filled with eta + dt eta' + dt^2/2 eta'', eta' + dt eta'', eta'' (dt = t_target - t_s).
    """
    dt = t_target - t_s
    half = 0.5 * dt * dt
    for d in range(eta.shape[0]):
        out[0, d] = eta[d] + dt * eta_d[d] + half * eta_dd[d]
        out[1, d] = eta_d[d] + dt * eta_dd[d]
        out[2, d] = eta_dd[d]


@njit(cache=_cache, _nrt=False)
def _fit(pred, n):
    """One RLS step (3)-(4) per DOF at the AR grid point n (a sub-grid index)."""
    p = pred.order
    m = pred.n_sub
    ring = pred.sub.shape[0]
    lam = pred.forgetting
    phi = pred.phi
    u = pred.u
    k_now = n % ring
    for d in range(pred.ref.shape[0]):
        for i in range(p):
            phi[i] = pred.sub[(n - (i + 1) * m) % ring, 0, d]
        theta = pred.theta[d]
        P = pred.P[d]
        if pred.scale[d] == 0.0:  # the first fit: the DOF's scale and the prior
            ss = 0.0
            for i in range(p):
                ss += phi[i] * phi[i]
            s = math.sqrt(ss / p)
            if not s > 0.0:
                s = 1.0
            pred.scale[d] = s
            _reset_covariance(pred, d)
        phi[p] = pred.scale[d]
        # e = y_n - theta' phi ; u = P phi ; r = phi' u
        e = pred.sub[k_now, 0, d]
        for i in range(p + 1):
            e -= theta[i] * phi[i]
        r = 0.0
        for i in range(p + 1):
            acc = 0.0
            for j in range(p + 1):
                acc += P[i, j] * phi[j]
            u[i] = acc
            r += phi[i] * acc
        if not (r > 0.0 and math.isfinite(r) and math.isfinite(e)):
            _reset_covariance(pred, d)  # P lost its positivity (round-off): start P again
            pred.ints[_RESETS] += 1
            continue
        g = 1.0 / (lam + r)
        # theta <- theta + u e / (lambda + r)                                  (3)
        for i in range(p + 1):
            theta[i] += u[i] * e * g
        # P <- P - beta u u' / (lambda + r), beta = 1 - (1 - lambda) / r       (4)
        c = (1.0 - (1.0 - lam) / r) * g
        for i in range(p + 1):
            ci = c * u[i]
            for j in range(p + 1):
                P[i, j] -= ci * u[j]
    pred.ints[_FITS] += 1


@njit(cache=_cache, _nrt=False)
def _reset_covariance(pred, d):
    P = pred.P[d]
    v = pred.p0 / (pred.scale[d] * pred.scale[d])
    for i in range(P.shape[0]):
        for j in range(P.shape[1]):
            P[i, j] = 0.0
        P[i, i] = v


@njit(cache=_cache, _nrt=False)
def predictor_update(pred, t_s, eta, eta_d, eta_dd):
    """Take one MRU sample.

    Samples not newer than the last one (a repeat, or out of order) and samples with a
    non-finite value are ignored. The sample is interpolated onto the sub-grid; every AR
    grid point it passes is fitted (3)-(4).

    Parameters
    ----------
    pred : Predictor
        Updated in place.
    t_s : float
        The sample's time stamp (when it was measured, not when it arrived), s.
    eta, eta_d, eta_dd : ndarray, shape (n_dof,)
        eta (m, rad), eta' (m/s, rad/s), eta'' (m/s^2, rad/s^2): surge, sway, heave, roll,
        pitch, yaw of S in the frames of :mod:`~marinecdpr.motion.ship` (any coordinates
        work: each DOF is predicted on its own).

    Returns
    -------
    bool
        True if the sample was taken.
    """
    ints = pred.ints
    n_dof = pred.ref.shape[0]
    if not math.isfinite(t_s):
        return False
    if ints[_SAMPLES] > 0 and not t_s > pred.last_t[0]:
        return False
    for d in range(n_dof):
        if not (math.isfinite(eta[d]) and math.isfinite(eta_d[d]) and math.isfinite(eta_dd[d])):
            return False
    delta = pred.sub_s
    if ints[_SAMPLES] == 0:
        for d in range(n_dof):
            pred.ref[d] = eta[d]
        ints[_NEXT] = int(math.floor(t_s / delta)) + 1
        ints[_RUN] = 0
    elif t_s - pred.last_t[0] > pred.max_gap_s:
        ints[_NEXT] = int(math.floor(t_s / delta)) + 1
        ints[_RUN] = 0
    elif ints[_NEXT] * delta <= t_s:  # a sub-grid point passed
        _fill(pred, t_s, eta, eta_d, eta_dd)
    pred.last_t[0] = t_s
    for d in range(n_dof):
        pred.last[0, d] = eta[d]
        pred.last[1, d] = eta_d[d]
        pred.last[2, d] = eta_dd[d]
    ints[_SAMPLES] += 1
    ints[_CACHED] = -1
    return True


@njit(cache=_cache, _nrt=False, inline="always")
def _fill(pred, t_s, eta, eta_d, eta_dd):
    """The sub-grid points in (last_t, t_s]: (5) between the last sample and this one."""
    ints = pred.ints
    ta = pred.last_t[0]
    D = t_s - ta
    delta = pred.sub_s
    ring = pred.sub.shape[0]
    m = pred.n_sub
    p = pred.order
    w = pred.w
    n = ints[_NEXT]
    while n * delta <= t_s:
        s = (n * delta - ta) / D
        if s < 0.0:
            s = 0.0
        _hermite5_weights(s, w)
        k = n % ring
        for d in range(pred.ref.shape[0]):
            y, yd, ydd = _hermite5_apply(
                w, D, pred.last[0, d] - pred.ref[d], pred.last[1, d], pred.last[2, d],
                eta[d] - pred.ref[d], eta_d[d], eta_dd[d], 3)
            pred.sub[k, 0, d] = y
            pred.sub[k, 1, d] = yd
            pred.sub[k, 2, d] = ydd
        ints[_RUN] += 1
        if n % m == 0 and ints[_RUN] > p * m:
            _fit(pred, n)
        n += 1
    ints[_NEXT] = n


@njit(cache=_cache, _nrt=False, inline="always")
def _ready(pred):
    ints = pred.ints
    return (ints[_FITS] >= pred.warmup_fits and ints[_SAMPLES] > 0
            and ints[_RUN] >= (pred.n_hist - 1) * pred.n_sub + 2)


@njit(cache=_cache, _nrt=False)
def predictor_ready(pred):
    """True when :func:`predictor_forecast` uses the model: the warm-up is over and the
    history is full (it is not after a gap in the stream, until H AR steps have arrived)."""
    return _ready(pred)


@njit(cache=_cache, _nrt=False)
def _history(pred):
    """traj[0:H] = y, y', y'' at t_L - k h, k = H-1..0 (k = 0: the last sample; H = n_hist)."""
    nh = pred.n_hist
    m = pred.n_sub
    ring = pred.sub.shape[0]
    delta = pred.sub_s
    traj = pred.traj
    w = pred.w
    n0 = pred.ints[_NEXT] - 1  # the latest sub-grid point, n0 delta <= t_L
    s = (pred.last_t[0] - n0 * delta) / delta
    s = min(max(s, 0.0), 1.0)
    _hermite5_weights(s, w)
    n_dof = pred.ref.shape[0]
    for k in range(1, nh):
        a = (n0 - k * m) % ring
        b = (n0 - k * m + 1) % ring
        row = nh - 1 - k
        for d in range(n_dof):
            y, yd, ydd = _hermite5_apply(
                w, delta, pred.sub[a, 0, d], pred.sub[a, 1, d], pred.sub[a, 2, d],
                pred.sub[b, 0, d], pred.sub[b, 1, d], pred.sub[b, 2, d], 3)
            traj[row, 0, d] = y
            traj[row, 1, d] = yd
            traj[row, 2, d] = ydd
    for d in range(n_dof):
        traj[nh - 1, 0, d] = pred.last[0, d] - pred.ref[d]
        traj[nh - 1, 1, d] = pred.last[1, d]
        traj[nh - 1, 2, d] = pred.last[2, d]
    pred.ints[_CACHED] = 0


@njit(cache=_cache, _nrt=False)
def _extend(pred, j_need):
    """The forecast points up to j_need by iterating (1)-(2)."""
    if pred.ints[_CACHED] < 0:
        _history(pred)
    p = pred.order
    traj = pred.traj
    n_dof = pred.ref.shape[0]
    for j in range(pred.ints[_CACHED] + 1, j_need + 1):
        row = pred.n_hist - 1 + j
        for d in range(n_dof):
            a = pred.theta[d]
            y = a[p] * pred.scale[d]  # c
            yd = 0.0
            ydd = 0.0
            for i in range(p):
                src = row - 1 - i
                y += a[i] * traj[src, 0, d]
                yd += a[i] * traj[src, 1, d]
                ydd += a[i] * traj[src, 2, d]
            traj[row, 0, d] = y
            traj[row, 1, d] = yd
            traj[row, 2, d] = ydd
        pred.ints[_CACHED] = j


@njit(cache=_cache, _nrt=False)
def predictor_forecast(pred, t_target, out):
    """eta, eta', eta'' predicted at an absolute time.

    The AR forecast (1)-(2) from the last sample, interpolated between its points t_L + j h
    by (5)-(7). The points are computed once per sample, when first needed: the first call
    after an update costs the history and the iteration to the target's point (O(p) per
    point and DOF), the next ones only the interpolation.

    Parameters
    ----------
    pred : Predictor
        Read; its forecast cache is extended in place (no allocation).
    t_target : float
        The time predicted for, s, normally >= the last sample's time (the present plus
        the look-ahead; the samples' latency is part of the horizon t_target - t_L).
    out : ndarray, shape (3, n_dof)
        Filled with eta (m, rad), eta' (per s), eta'' (per s^2) at t_target.

    Returns
    -------
    int
        ``MODEL`` (1): the AR forecast; ``TAYLOR`` (0): the Taylor extrapolation (8) of the
        last sample (warm-up, or t_target before it); ``NONE`` (-1): out is NaN (no sample
        yet, or t_target beyond max_horizon_s from the last sample).
    """
    n_dof = pred.ref.shape[0]
    if pred.ints[_SAMPLES] == 0:
        out[:, :] = np.nan
        return NONE
    dt = t_target - pred.last_t[0]
    if not (dt >= 0.0 and _ready(pred)):
        taylor_forecast(pred.last_t[0], pred.last[0], pred.last[1], pred.last[2], t_target, out)
        return TAYLOR
    h = pred.step_s
    q = dt / h
    j = int(math.ceil(q))
    if j < 1:
        j = 1
    if j > pred.n_ahead:
        out[:, :] = np.nan
        return NONE
    s = q - (j - 1)
    if pred.ints[_CACHED] < j + 3:
        _extend(pred, j + 3)
    w = pred.w
    _hermite5_weights(s, w)
    wf = pred.wf
    # eta': the degree-7 polynomial through y' and h y'' at the points j-2 .. j+1   (6)
    for k in range(8):
        acc = _H7[7, k]
        for i in range(6, -1, -1):
            acc = acc * s + _H7[i, k]
        wf[0, k] = acc
    # eta'': the Lagrange polynomial (degree 7) through y'' at the points j-4 .. j+3  (7)
    wf[2, 0] = 1.0
    wf[3, 7] = 1.0
    for k in range(1, 8):
        wf[2, k] = wf[2, k - 1] * (s - _L8_NODES[k - 1])
        wf[3, 7 - k] = wf[3, 8 - k] * (s - _L8_NODES[8 - k])
    for k in range(8):
        wf[1, k] = wf[2, k] * wf[3, k] / _L8_DEN[k]
    traj = pred.traj
    a = pred.n_hist - 2 + j  # point j - 1 (point 0, the last sample: row n_hist - 1)
    b = a + 1
    for d in range(n_dof):
        y, yd, ydd = _hermite5_apply(w, h, traj[a, 0, d], traj[a, 1, d], traj[a, 2, d],
                                     traj[b, 0, d], traj[b, 1, d], traj[b, 2, d], 1)
        out[0, d] = y + pred.ref[d]
        yd = 0.0
        for k in range(4):
            yd += wf[0, k] * traj[a - 1 + k, 1, d] + wf[0, 4 + k] * h * traj[a - 1 + k, 2, d]
        out[1, d] = yd
        ydd = 0.0
        for k in range(8):
            ydd += wf[1, k] * traj[a - 3 + k, 2, d]
        out[2, d] = ydd
    return MODEL


# --------------------------------------------------------------------------- the study
@dataclass(frozen=True)
class PredictionError:
    """RMS prediction errors along a record, per horizon and DOF, normalised.

    Attributes
    ----------
    horizons_s : ndarray, shape (n_h,)
        Look-aheads beyond the present, s; the horizon from the last sample is
        latency_s + horizons_s.
    predictor, taylor, hold : ndarray, shape (n_h, 3, n_dof)
        RMS error of eta, eta', eta'' (axis 1) over the RMS of the record's eta, eta',
        eta'' (about its mean, :attr:`record_rms`): the predictor, the Taylor extrapolation
        (8) of the last sample, and the last sample held. NaN for a DOF that does not move,
        and at a horizon where no forecast was compared (``n_evaluated`` 0: the MRU's
        samples too sparse for the record).
    record_rms : ndarray, shape (3, n_dof)
        The record's RMS about its mean: m, rad (row 0), per s (1), per s^2 (2).
    model_share : ndarray, shape (n_h,)
        The fraction of the evaluations the AR model served (the rest: Taylor, warm-up);
        NaN where none was made.
    n_evaluated : ndarray, shape (n_h,), int
        Forecasts compared (one per MRU sample after ``discard_s``, target within the record).
    sample_hz, latency_s, discard_s : float
        The study's MRU rate (Hz), latency (s) and the record's start left out (s).
    noise_std : ndarray, shape (3, n_dof)
        The white noise added to the samples (m or rad, per s, per s^2; zeros: none).
    resets : int
        Covariance resets of the RLS (a numerical safeguard; 0 in normal use).
    options : dict
        The predictor's options (:func:`make_predictor`).
    """

    horizons_s: np.ndarray
    predictor: np.ndarray
    taylor: np.ndarray
    hold: np.ndarray
    record_rms: np.ndarray
    model_share: np.ndarray
    n_evaluated: np.ndarray
    sample_hz: float
    latency_s: float
    discard_s: float
    noise_std: np.ndarray
    resets: int
    options: dict

    def table(self, dofs=(2, 3, 4), names=("surge", "sway", "heave", "roll", "pitch", "yaw")) -> str:
        """A text table of the normalised errors of eta, eta', eta'' per horizon (rows), for
        some DOFs (columns: predictor, Taylor, hold)."""
        lines = []
        for c, label in enumerate(("eta", "eta'", "eta''")):
            cols = " ".join(f"{names[d] + ' pred/taylor/hold':>29s}" for d in dofs)
            lines.append(f"{label:6s}{'horizon_s':>9s} {cols}")
            for i, hz in enumerate(self.horizons_s):
                cells = " ".join(f"{self.predictor[i, c, d]:9.2e} {self.taylor[i, c, d]:9.2e} "
                                 f"{self.hold[i, c, d]:9.2e}" for d in dofs)
                lines.append(f"{'':6s}{hz:9.3f} {cells}")
        return "\n".join(lines)


@njit(cache=_cache)
def _record_at(rec, t0, dt, t, out, w):
    """eta, eta', eta'' (3, n_dof) at t from the uniform record rec (n, 3, n_dof), by (5);
    w (3, 6) scratch."""
    n = rec.shape[0]
    x = (t - t0) / dt
    i = int(math.floor(x))
    if i < 0:
        i = 0
    if i > n - 2:
        i = n - 2
    _hermite5_weights(x - i, w)
    for d in range(rec.shape[2]):
        y, yd, ydd = _hermite5_apply(w, dt, rec[i, 0, d], rec[i, 1, d], rec[i, 2, d],
                                     rec[i + 1, 0, d], rec[i + 1, 1, d], rec[i + 1, 2, d], 3)
        out[0, d] = y
        out[1, d] = yd
        out[2, d] = ydd


@njit(cache=_cache)
def _record_series(rec, t0, dt, ts):
    out = np.empty((ts.size, 3, rec.shape[2]))
    w = np.empty((3, 6))
    for k in range(ts.size):
        _record_at(rec, t0, dt, ts[k], out[k], w)
    return out


@njit(cache=_cache)
def _study_loop(pred, ts, samples, rec, t0, dt, ahead, t_from, t_end, sse, count, model):
    """Run the predictor along the samples; sse (3 methods, n_h, 3, n_dof) accumulates
    the squared errors of the predictor, Taylor and hold at ts[k] + ahead[i]."""
    n_dof = rec.shape[2]
    out = np.empty((3, n_dof))
    truth = np.empty((3, n_dof))
    w = np.empty((3, 6))
    for k in range(ts.size):
        x = samples[k]
        predictor_update(pred, ts[k], x[0], x[1], x[2])
        if ts[k] < t_from:
            continue
        for i in range(ahead.size):
            tt = ts[k] + ahead[i]
            if tt > t_end:
                continue
            _record_at(rec, t0, dt, tt, truth, w)
            if predictor_forecast(pred, tt, out) == MODEL:
                model[i] += 1
            for c in range(3):
                for d in range(n_dof):
                    e = out[c, d] - truth[c, d]
                    sse[0, i, c, d] += e * e
            taylor_forecast(ts[k], x[0], x[1], x[2], tt, out)
            for c in range(3):
                for d in range(n_dof):
                    e = out[c, d] - truth[c, d]
                    sse[1, i, c, d] += e * e
                    e = x[c, d] - truth[c, d]
                    sse[2, i, c, d] += e * e
            count[i] += 1


def prediction_error(
    t: np.ndarray,
    eta: np.ndarray,
    eta_d: np.ndarray,
    eta_dd: np.ndarray,
    *,
    sample_hz: float,
    latency_s: float,
    horizons_s,
    discard_s: float = 60.0,
    noise_std=None,
    seed: int = 0,
    **options,
) -> PredictionError:
    """How well the predictor forecasts a record, against the horizon.

    The record is sampled by an MRU at ``sample_hz`` (its values between the record's
    points by (5)); each sample reaches the predictor ``latency_s`` after it was taken and
    is used at once to forecast the present plus each horizon, i.e. t_k + latency_s + H.
    The predictor runs causally along the record (compiled, one pass); the Taylor
    extrapolation and the held sample forecast the same instants from the same sample.

    Parameters
    ----------
    t : ndarray, shape (n,)
        The record's times, s, uniformly spaced (finely enough for (5): 10-50 ms).
    eta, eta_d, eta_dd : ndarray, shape (n, n_dof)
        The true eta (m, rad), eta' and eta'' (per s, per s^2) at t, e.g. from
        :func:`marinecdpr.motion.seastate.synthesize`.
    sample_hz : float
        The MRU's rate, Hz (> 0).
    latency_s : float
        The MRU's latency, s (>= 0).
    horizons_s : array_like, shape (n_h,)
        Look-aheads beyond the present, s (>= 0).
    discard_s : float
        The record's first seconds, left out of the errors (the fit's start), s.
    noise_std : array_like, optional
        Standard deviations of white Gaussian noise added to the samples: broadcast to
        (3, n_dof), rows eta (m, rad), eta' (per s), eta'' (per s^2). None: no noise. The
        errors are always against the noise-free record.
    seed : int
        Seeds the noise.
    **options
        :func:`make_predictor` keywords (step_s, order, forgetting required; n_dof from
        eta; max_horizon_s defaults to the longest horizon plus the latency).

    Returns
    -------
    PredictionError
    """
    t = np.asarray(t, dtype=float)
    rec = np.stack([np.asarray(a, dtype=float) for a in (eta, eta_d, eta_dd)], axis=1)  # (n, 3, n_dof)
    if t.ndim != 1 or t.size < 2 or rec.ndim != 3 or rec.shape[0] != t.size:
        raise ValueError("t must be (n,) and eta, eta_d, eta_dd (n, n_dof), n >= 2")
    dt = (t[-1] - t[0]) / (t.size - 1)
    if not (dt > 0.0 and np.allclose(np.diff(t), dt, rtol=1e-6, atol=1e-9)):
        raise ValueError("t must be uniformly spaced and increasing")
    if not (sample_hz > 0.0 and latency_s >= 0.0):
        raise ValueError("sample_hz must be > 0 and latency_s >= 0")
    ahead = latency_s + np.asarray(horizons_s, dtype=float).ravel()
    if ahead.size == 0 or np.any(~np.isfinite(ahead)) or np.any(ahead < latency_s):
        raise ValueError("horizons_s must be finite and >= 0")
    options.setdefault("max_horizon_s", float(ahead.max()) + 1e-6)
    options["n_dof"] = rec.shape[2]
    pred = make_predictor(**options)
    ts = t[0] + np.arange(int(np.floor((t[-1] - t[0]) * sample_hz)) + 1) / sample_hz
    samples = _record_series(rec, t[0], dt, ts)
    noise = np.zeros((3, rec.shape[2])) if noise_std is None else np.broadcast_to(
        np.asarray(noise_std, dtype=float), (3, rec.shape[2])).copy()
    if np.any(~np.isfinite(noise)) or np.any(noise < 0.0):
        raise ValueError("noise_std must be finite and >= 0")
    if np.any(noise > 0.0):
        samples += noise * np.random.default_rng(seed).standard_normal(samples.shape)
    t_from = t[0] + discard_s
    if t_from + ahead.max() > t[-1]:
        raise ValueError("the record is shorter than discard_s plus the longest horizon")
    sse = np.zeros((3, ahead.size, 3, rec.shape[2]))
    count = np.zeros(ahead.size, dtype=np.int64)
    model = np.zeros(ahead.size, dtype=np.int64)
    _study_loop(pred, ts, samples, rec, t[0], dt, ahead, t_from, t[-1], sse, count, model)
    rms = np.sqrt(np.mean((rec - rec.mean(axis=0)) ** 2, axis=0))  # (3, n_dof)
    scale = np.where(rms > 1e-12 * max(float(rms.max()), 1e-300), rms, np.nan)
    evaluated = count > 0  # NaN, said once, where no forecast was compared (no 0/0 warning)
    n = np.where(evaluated, count, 1)
    err = np.where(evaluated[None, :, None, None], np.sqrt(sse / n[None, :, None, None]), np.nan) / scale
    return PredictionError(
        horizons_s=ahead - latency_s, predictor=err[0], taylor=err[1], hold=err[2], record_rms=rms,
        model_share=np.where(evaluated, model / n, np.nan), n_evaluated=count, sample_hz=float(sample_hz),
        latency_s=float(latency_s), discard_s=float(discard_s), noise_std=noise,
        resets=int(pred.ints[_RESETS]), options=dict(options))
