"""Irregular seas: wave spectra, directional spreading, and the ship motion they cause.

Conventions (see ``docs/conventions.md``, "Sea states"):

* Wave elevation at S's origin, a sum of regular components,
  zeta(t) = sum_k Re(a_k exp(i (omega_k t + eps_k))).
* A response is eta_j(t) = sum_k Re(RAO_j(omega_k, beta_k) a_k exp(i (omega_k t + eps_k)))
  (:mod:`marinecdpr.motion.rao` for the RAO conventions): velocities and accelerations follow
  exactly, multiplying by i omega and -omega^2.
* beta is the direction the waves travel towards, from the ship's +x axis,
  counter-clockwise: 0 following, 90 from starboard, 180 head seas. The ship's own
  yaw is not fed back into beta (first-order seakeeping).
* Spectra are one-sided, S(omega) in m^2 s / rad, with integral Hs^2 / 16.

The record: frequencies on a grid omega_k = k d_omega with d_omega = 2 pi / record_s,
deterministic amplitudes a_k = sqrt(2 S(omega_k) D(theta) d_omega d_theta) and phases
drawn from a seeded generator, so the record repeats only after ``record_s`` and the same
seed always gives the same sea.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

from typing import NamedTuple

import numpy as np

__all__ = [
    "dnv_gamma",
    "dnv_tz_over_tp",
    "TZ_FIT_GAMMA",
    "jonswap",
    "pierson_moskowitz",
    "spread_directions",
    "spreading",
    "SeaRecord",
    "sea_record",
    "synthesize",
    "wave_elevation",
]


FFT_MAX_SAMPLES = 2**18
"""Largest record grid synthesised by inverse FFT (18 series of this many samples)."""


def dnv_gamma(hs: float, tp: float) -> float:
    """JONSWAP peak enhancement factor from DNV-RP-C205 (3.5.5.5), for Tp/sqrt(Hs)."""
    r = tp / math.sqrt(hs)
    if r <= 3.6:
        return 5.0
    if r >= 5.0:
        return 1.0
    return math.exp(5.75 - 1.15 * r)


TZ_FIT_GAMMA = (1.0, 7.0)
"""The range of gamma over which DNV-RP-C205's Tz/Tp fit (:func:`dnv_tz_over_tp`) holds."""


def dnv_tz_over_tp(gamma: float) -> float:
    """The zero-up-crossing period over the peak period of a JONSWAP spectrum, DNV-RP-C205's
    fit (its JONSWAP section): Tz / Tp = 0.6673 + 0.05037 gamma - 0.006230 gamma^2 +
    0.0003341 gamma^3.

    At gamma = 1 (Pierson-Moskowitz) it is 0.7118, the Tp = 1.4049 Tz that DNV-RP-C205 gives
    for that spectrum; at gamma = 3.3, 0.7777.

    Parameters
    ----------
    gamma : float
        Peak enhancement factor, within :data:`TZ_FIT_GAMMA` (the fit's range, 1 to 7).

    Returns
    -------
    float
        Tz / Tp, dimensionless.

    Raises
    ------
    ValueError
        gamma outside 1 to 7, or not finite.
    """
    lo, hi = TZ_FIT_GAMMA
    if not lo <= gamma <= hi:  # False for NaN too
        raise ValueError(f"gamma = {gamma:g} is outside DNV-RP-C205's Tz/Tp fit ({lo:g} <= gamma <= {hi:g})")
    return 0.6673 + 0.05037 * gamma - 0.006230 * gamma**2 + 0.0003341 * gamma**3


def pierson_moskowitz(omega: np.ndarray, hs: float, tp: float) -> np.ndarray:
    """Pierson-Moskowitz spectrum (DNV-RP-C205 3.5.5.1).

    Parameters
    ----------
    omega : ndarray
        Angular frequencies, rad/s.
    hs : float
        Significant wave height, m.
    tp : float
        Peak period, s.

    Returns
    -------
    S : ndarray, like omega
        m^2 s / rad; 0 at omega <= 0.
    """
    omega = np.asarray(omega, dtype=float)
    wp = 2.0 * np.pi / tp
    S = np.zeros_like(omega)
    pos = omega > 0
    w = omega[pos]
    S[pos] = 5.0 / 16.0 * hs**2 * wp**4 * w**-5 * np.exp(-1.25 * (w / wp) ** -4)
    return S


@lru_cache(maxsize=128)
def _jonswap_area(gamma: float) -> float:
    """The JONSWAP shape's zeroth moment over the Pierson-Moskowitz one's (1 at gamma = 1):
    in x = omega / omega_p, int 5 x^-5 exp(-1.25 x^-4) gamma^exp(-(x - 1)^2 / (2 sigma^2)) dx."""
    from scipy.integrate import quad

    def shape(x: float) -> float:
        sigma = 0.07 if x <= 1.0 else 0.09
        return 5.0 * x**-5 * math.exp(-1.25 * x**-4) * gamma ** math.exp(-0.5 * ((x - 1.0) / sigma) ** 2)

    low = quad(shape, 0.05, 1.0, limit=200, epsabs=0.0, epsrel=1e-12)[0]
    high = quad(shape, 1.0, np.inf, limit=200, epsabs=0.0, epsrel=1e-12)[0]
    return low + high


def jonswap(omega: np.ndarray, hs: float, tp: float, gamma: float | None = None) -> np.ndarray:
    """JONSWAP spectrum in the form of DNV-RP-C205 (3.5.5.2), normalised on its exact
    zeroth moment (4 sqrt(m0) = Hs for every gamma).

    S_J = A S_PM gamma^exp(-(omega - omega_p)^2 / (2 sigma^2 omega_p^2)), sigma = 0.07 below
    the peak and 0.09 above it, with A the exact normalisation; DNV's approximation
    A = 1 - 0.287 ln gamma is within 1 % of it for gamma up to 7 and 3.5 % low at 10 (and
    breaks down, A <= 0, from gamma = 32.6).

    Parameters
    ----------
    omega : ndarray
        rad/s.
    hs, tp : float
        m, s.
    gamma : float, optional
        Peak enhancement; default :func:`dnv_gamma` (hs, tp).
    """
    omega = np.asarray(omega, dtype=float)
    gamma = dnv_gamma(hs, tp) if gamma is None else gamma
    wp = 2.0 * np.pi / tp
    sigma = np.where(omega <= wp, 0.07, 0.09)
    peak = gamma ** np.exp(-0.5 * ((omega - wp) / (sigma * wp)) ** 2)
    return pierson_moskowitz(omega, hs, tp) * peak / _jonswap_area(float(gamma))


def spreading(theta: np.ndarray, kind: str, exponent: float) -> np.ndarray:
    """Directional spreading D(theta) about the mean direction (integral 1 over its support).

    Parameters
    ----------
    theta : ndarray
        Direction relative to the mean, rad.
    kind : {"cos2s", "cosn"}
        ``cos2s``: D = Gamma(s+1) / (2 sqrt(pi) Gamma(s+1/2)) cos^2s(theta/2), |theta| <= pi.
        ``cosn`` (DNV-RP-C205 3.5.8): D = Gamma(1+n/2) / (sqrt(pi) Gamma(1/2+n/2)) cos^n(theta),
        |theta| <= pi/2.
    exponent : float
        s or n.
    """
    theta = np.asarray(theta, dtype=float)
    if kind == "cos2s":
        s = exponent
        c = math.exp(math.lgamma(s + 1) - math.lgamma(s + 0.5)) / (2 * math.sqrt(math.pi))
        return np.where(np.abs(theta) <= np.pi, c * np.cos(theta / 2) ** (2 * s), 0.0)
    if kind == "cosn":
        n = exponent
        c = math.exp(math.lgamma(1 + n / 2) - math.lgamma(0.5 + n / 2)) / math.sqrt(math.pi)
        return np.where(np.abs(theta) <= np.pi / 2, c * np.abs(np.cos(theta)) ** n, 0.0)
    raise ValueError(f"unknown spreading {kind!r} (expected cos2s or cosn)")


@dataclass(frozen=True)
class SeaRecord:
    """A sea and the ship's response as sums of regular components.

    Attributes
    ----------
    omega : ndarray, shape (K,)
        Component frequencies, multiples of d_omega = 2 pi / record_s, rad/s.
    record_s : float
        Repeat period, s.
    amplitude : ndarray, shape (K, n_dir)
        Wave amplitudes a_k, m, per direction.
    phase : ndarray, shape (K, n_dir)
        eps_k, rad.
    heading_deg : ndarray, shape (n_dir,)
        Wave directions beta, deg.
    coeff : ndarray, complex, shape (6, K)
        C_jk = sum over directions of RAO_j a e^{i eps}: eta_j(t) = Re sum_k C_jk e^{i omega_k t}.
    """

    omega: np.ndarray
    record_s: float
    amplitude: np.ndarray
    phase: np.ndarray
    heading_deg: np.ndarray
    coeff: np.ndarray

    @property
    def hs_target(self) -> float:
        """4 sqrt(m0) of the discrete spectrum, m."""
        return 4.0 * math.sqrt(0.5 * float(np.sum(self.amplitude**2)))


def spread_directions(kind: str | None, exponent: float, n_directions: int) -> tuple[np.ndarray, np.ndarray]:
    """The directions a spread sea is discretised into, about its mean, and their shares of
    the energy (summing to 1, so Hs is preserved).

    Parameters
    ----------
    kind : {None, "cos2s", "cosn"}
        None: long-crested (one direction).
    exponent : float
        s or n.
    n_directions : int
        Equal bins across the spreading function (odd numbers include the mean).

    Returns
    -------
    rel : ndarray, shape (n_directions,)
        The bins' centres relative to the mean direction, rad.
    weight : ndarray, shape (n_directions,)
    """
    if kind is None or n_directions <= 1:
        return np.zeros(1), np.ones(1)
    half = np.pi if kind == "cos2s" else np.pi / 2
    edges = np.linspace(-half, half, n_directions + 1)
    rel = 0.5 * (edges[1:] + edges[:-1])
    weight = spreading(rel, kind, exponent) * (edges[1] - edges[0])
    weight /= weight.sum()  # the discrete spreading keeps all the energy: Hs is preserved
    return rel, weight


def sea_record(
    *,
    hs: float,
    tp: float,
    heading_deg: float,
    rao,
    spectrum: str = "jonswap",
    gamma: float | None = None,
    spreading_kind: str | None = None,
    spreading_exponent: float = 10.0,
    n_directions: int = 1,
    record_s: float = 1800.0,
    omega_max: float | None = None,
    seed: int = 0,
) -> SeaRecord:
    """Build the components of a sea state and the ship's response coefficients.

    Parameters
    ----------
    hs, tp : float
        Significant wave height (m), peak period (s).
    heading_deg : float
        Mean wave direction beta, deg.
    rao : marinecdpr.motion.rao.RAO
        The ship's RAOs (``rao.at(omega, heading_deg)`` -> complex (6, K)).
    spectrum : {"jonswap", "pierson_moskowitz"}
    gamma : float, optional
        JONSWAP peak enhancement (default from DNV-RP-C205).
    spreading_kind : {None, "cos2s", "cosn"}
        None: long-crested (one direction).
    spreading_exponent : float
        s or n.
    n_directions : int
        Directions across the spreading function (odd numbers include the mean).
    record_s : float
        Repeat period of the record, s.
    omega_max : float, optional
        Highest component frequency, rad/s (default 6 omega_p).
    seed : int
        Seeds the random phases.
    """
    wp = 2.0 * np.pi / tp
    d_omega = 2.0 * np.pi / record_s
    omega_max = 6.0 * wp if omega_max is None else omega_max
    k = np.arange(1, int(omega_max / d_omega) + 1)
    omega = k * d_omega
    if spectrum == "jonswap":
        S = jonswap(omega, hs, tp, gamma)
    elif spectrum == "pierson_moskowitz":
        S = pierson_moskowitz(omega, hs, tp)
    else:
        raise ValueError(f"unknown spectrum {spectrum!r}")
    rel, weight = spread_directions(spreading_kind, spreading_exponent, n_directions)
    # drop components without energy, so the sums stay short
    keep = S > 1e-12 * S.max()
    omega, S = omega[keep], S[keep]
    amplitude = np.sqrt(2.0 * S * d_omega)[:, None] * np.sqrt(weight)[None, :]
    rng = np.random.default_rng(seed)
    phase = rng.uniform(0.0, 2.0 * np.pi, size=amplitude.shape)
    headings = np.mod(heading_deg + np.degrees(rel), 360.0)
    coeff = np.zeros((6, omega.size), dtype=complex)
    for d, beta in enumerate(headings):
        coeff += rao.at(omega, float(beta)) * (amplitude[:, d] * np.exp(1j * phase[:, d]))[None, :]
    return SeaRecord(omega=omega, record_s=float(record_s), amplitude=amplitude, phase=phase, heading_deg=headings,
                     coeff=coeff)


HARMONIC_BLOCK = 2**21
"""Complex samples of e^{i omega t} held at once by the direct sums (32 MiB)."""


def _harmonic(coeff: np.ndarray, omega: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Re sum_k coeff[:, k] e^{i omega_k t} for every t: shape (rows, len(t)), in blocks of
    times sized so that memory stays bounded however many components there are."""
    chunk = max(1, HARMONIC_BLOCK // max(1, omega.size))
    out = np.empty((coeff.shape[0], t.size))
    for i in range(0, t.size, chunk):
        E = np.exp(1j * np.outer(omega, t[i:i + chunk]))
        out[:, i:i + chunk] = (coeff @ E).real
    return out


def _irfft_rows(coeff: np.ndarray, k_index: np.ndarray, m: int, idx: np.ndarray | None = None) -> np.ndarray:
    """Re sum_k coeff[r, k] e^{i omega_k t_n} on the grid t_n = n record_s / m over one
    period (an inverse FFT per row, one row's spectrum in memory at a time); with ``idx``
    only the samples idx (int, taken modulo m): shape (rows, m) or (rows, idx.size)."""
    out = np.empty((coeff.shape[0], m if idx is None else idx.size))
    spec = np.zeros(m // 2 + 1, dtype=complex)
    # irfft computes (1/m) sum over the full spectrum; Re sum_k C e^{i w t} = irfft(C m / 2)
    coeff = coeff * (m / 2.0)
    wrapped = None if idx is None else idx % m
    for r in range(coeff.shape[0]):
        spec[k_index] = coeff[r]
        if wrapped is None:
            out[r] = np.fft.irfft(spec, n=m)
        else:
            np.take(np.fft.irfft(spec, n=m), wrapped, out=out[r])
    return out


@lru_cache(maxsize=2)  # a record's grid can be tens of MB; a plan reuses one at a time
def _grid_record(coeff_bytes: bytes, k_index_bytes: bytes, m: int) -> np.ndarray:
    """eta, eta', eta'' on the grid t_n = n record_s / m over one period, (18, m)."""
    coeff = np.frombuffer(coeff_bytes, dtype=complex).reshape(18, -1)
    return _irfft_rows(coeff, np.frombuffer(k_index_bytes, dtype=np.int64), m)


class ShipCoordinates(NamedTuple):
    """:func:`synthesize`'s result: the ship's eta (n_steps, 6), m and rad, and its first and
    second time derivatives."""

    eta: np.ndarray
    eta_dot: np.ndarray
    eta_ddot: np.ndarray


def synthesize(rec: SeaRecord, t: np.ndarray) -> ShipCoordinates:
    """The ship's coordinates eta and their exact derivatives at times t.

    Times on the record's uniform grid (t = n record_s / m for an integer m up to
    :data:`FFT_MAX_SAMPLES`, or up to twice the number of times asked for) use an inverse FFT
    over one period (computed once per record if m is up to :data:`FFT_MAX_SAMPLES`);
    other times a direct sum. Both are exact.

    Parameters
    ----------
    rec : SeaRecord
    t : ndarray, shape (n_steps,)
        s.

    Returns
    -------
    ShipCoordinates
        eta, eta_dot, eta_ddot : ndarray, shape (n_steps, 6): m and rad, and their first and
        second time derivatives.
    """
    t = np.asarray(t, dtype=float)
    w = rec.omega
    coeff = np.concatenate([rec.coeff, rec.coeff * (1j * w), rec.coeff * (-(w**2))])
    grid = None
    if t.size > 1:
        dt = t[1] - t[0]
        m = int(round(rec.record_s / dt)) if dt > 0 else 0
        # one inverse FFT per record, cached and reused by every chunk of a plan while the
        # record's grid is small (2^18 samples: 38 MB); a larger grid is transformed row
        # by row when the times asked for are at least half as many (a long simulation:
        # the result is about that large anyway); direct sums otherwise
        if (0 < m <= max(FFT_MAX_SAMPLES, 2 * t.size) and abs(m * dt - rec.record_s) < 1e-9 * rec.record_s):
            idx = np.rint(t / dt)
            if np.allclose(idx * dt, t, rtol=0, atol=1e-9 * max(1.0, rec.record_s)):
                k_index = np.rint(w / (2.0 * np.pi / rec.record_s)).astype(np.int64)
                if k_index.max() <= m // 2:
                    idx = idx.astype(np.int64)
                    if m <= FFT_MAX_SAMPLES:
                        grid = _grid_record(coeff.tobytes(), k_index.tobytes(), m)
                        vals = grid[:, idx % m]
                    else:
                        vals = grid = _irfft_rows(coeff, k_index, m, idx)
    if grid is None:
        vals = _harmonic(coeff, w, t)
    return ShipCoordinates(eta=vals[0:6].T, eta_dot=vals[6:12].T, eta_ddot=vals[12:18].T)


def wave_elevation(rec: SeaRecord, t: np.ndarray) -> np.ndarray:
    """Wave elevation at S's origin, shape (n_steps,), m."""
    c = (rec.amplitude * np.exp(1j * rec.phase)).sum(axis=1)
    return _harmonic(c[None, :], rec.omega, np.asarray(t, dtype=float))[0]
