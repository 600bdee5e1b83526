"""The wind field: the mean speed over height, Frøya's gust spectrum, and a gust series.

All speeds are m/s, heights m above the mean sea surface, frequencies Hz, times s. The wind
blows in O's horizontal plane along :func:`wind_direction_O` (the scenario's ``direction_deg``
is where it comes from); the gust is along the mean wind.

Mean profile (DNV-RP-C205, 2010, §2.3.2.12, power law; alpha = 0.12 for the open sea with
waves, its Table 2-1)::

    U(z) = U_r (max(z, z_min) / z_r) ** alpha

Frøya's spectrum (DNV-RP-C205 §2.3.4, the Frøya model for storm winds over the sea; U0 the
one-hour mean at 10 m, one-sided, m^2/Hz)::

    S(f) = 320 (U0 / 10)^2 (z / 10)^0.45 / (1 + f~^n)^(5 / (3 n)),
    f~   = 172 f (z / 10)^(2/3) (U0 / 10)^(-0.75),    n = 0.468

The series sums the spectrum's harmonics f_k = k / T (k = 1..K, f_K <= f_max) with the
deterministic amplitudes sqrt(2 S(f_k) / T) and random phases (Shinozuka's method)::

    u(t) = sum_k sqrt(2 S(f_k) / T) cos(2 pi f_k t + phi_k)

periodic over T; it is synthesised once by an inverse FFT on a grid 8 times finer than its
highest harmonic's Nyquist step and read at any times by linear interpolation (whole arrays).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["wind_speed_at", "wind_direction_O", "froya_spectrum", "GustSeries", "gust_series", "gust_harmonics",
           "gust_moments", "FROYA_N", "OVERSAMPLING"]

FROYA_N = 0.468
"""The exponent n of Frøya's spectrum."""
OVERSAMPLING = 8
"""The synthesis grid's points per half period of the highest harmonic: linear interpolation
between them keeps sinc^2(1 / 16) = 98.7% of that harmonic's amplitude, more of the lower ones."""


def wind_speed_at(z, speed_ref: float, z_ref: float, alpha: float, z_min: float = 1.0) -> np.ndarray:
    """The mean wind speed at heights ``z`` above the sea (the power law).

    Parameters
    ----------
    z : ndarray, any shape
        Heights above the mean sea surface, m.
    speed_ref : float
        U_r, the mean speed at ``z_ref``, m/s.
    z_ref : float
        The reference height, m (> 0).
    alpha : float
        The power law's exponent.
    z_min : float
        Heights below it take its speed, m.

    Returns
    -------
    ndarray, the shape of z
        U(z), m/s.
    """
    z = np.maximum(np.asarray(z, dtype=float), z_min)
    return speed_ref * (z / z_ref) ** alpha


def wind_direction_O(direction_deg: float) -> np.ndarray:
    """The unit vector the wind blows along, in O, shape (3,): a wind from ``direction_deg``
    (counter-clockwise from O's +x, about z up) blows along -(cos d, sin d, 0)."""
    d = np.radians(direction_deg)
    return -np.array([np.cos(d), np.sin(d), 0.0])


def froya_spectrum(f, u0: float, z: float) -> np.ndarray:
    """Frøya's one-sided gust spectrum S(f) (DNV-RP-C205 §2.3.4), m^2/Hz.

    Parameters
    ----------
    f : ndarray, any shape
        Frequencies, Hz (>= 0).
    u0 : float
        U0, the one-hour mean speed at 10 m, m/s.
    z : float
        The height above the sea, m.

    Returns
    -------
    ndarray, the shape of f
    """
    f = np.asarray(f, dtype=float)
    n = FROYA_N
    f_tilde = 172.0 * f * (z / 10.0) ** (2.0 / 3.0) * (u0 / 10.0) ** -0.75
    return 320.0 * (u0 / 10.0) ** 2 * (z / 10.0) ** 0.45 / (1.0 + f_tilde ** n) ** (5.0 / (3.0 * n))


@dataclass(frozen=True)
class GustSeries:
    """A periodic gust series on a regular grid.

    Attributes
    ----------
    u : ndarray, shape (n_grid,)
        u(j dt), m/s, j = 0..n_grid - 1 (the period is n_grid dt).
    dt : float
        The grid's step, s.
    """

    u: np.ndarray
    dt: float

    @property
    def period_s(self) -> float:
        return self.u.size * self.dt

    def at(self, t) -> np.ndarray:
        """u at times ``t`` (any shape, s), linearly between the grid's points, periodic."""
        t = np.asarray(t, dtype=float)
        s = np.mod(t / self.dt, self.u.size)
        j = np.floor(s).astype(np.int64)
        w = s - j
        j = np.minimum(j, self.u.size - 1)  # s just below n_grid rounds to it
        return (1.0 - w) * self.u[j] + w * self.u[(j + 1) % self.u.size]


def gust_harmonics(u0: float, z: float, record_s: float, f_max: float) -> tuple[np.ndarray, np.ndarray]:
    """The gust series' harmonics: f_k = k / T, k = 1..K (f_K <= ``f_max``), and their
    amplitudes sqrt(2 S(f_k) / T) (Frøya's S; arguments as :func:`gust_series`'s).

    Returns
    -------
    f, amplitude : ndarray, shape (K,)
        Hz, m/s.
    """
    K = max(1, int(np.floor(f_max * record_s + 1e-9)))
    f = np.arange(1, K + 1) / record_s
    return f, np.sqrt(2.0 * froya_spectrum(f, u0, z) / record_s)


def gust_moments(u0: float, z: float, record_s: float, f_max: float) -> tuple[float, float]:
    """The gust series' variance and its rate's, (m/s)^2 and (m/s^2)^2: sum a_k^2 / 2 and
    sum (2 pi f_k)^2 a_k^2 / 2 over its harmonics (:func:`gust_harmonics`; any one record's,
    over its period, whatever its phases)."""
    f, amp = gust_harmonics(u0, z, record_s, f_max)
    half = 0.5 * amp**2
    return float(half.sum()), float(((2.0 * np.pi * f) ** 2 * half).sum())


def gust_series(u0: float, z: float, record_s: float, f_max: float, seed: int) -> GustSeries:
    """A Frøya gust series of period ``record_s`` (the module's sum, by an inverse FFT).

    Parameters
    ----------
    u0 : float
        U0, m/s.
    z : float
        The height above the sea whose spectrum it follows, m.
    record_s : float
        T, its period, s.
    f_max : float
        The highest harmonic, Hz.
    seed : int
        The phases' seed (numpy's default generator: phi_k uniform on [0, 2 pi)).

    Returns
    -------
    GustSeries
    """
    f, amp = gust_harmonics(u0, z, record_s, f_max)
    K = f.size
    phi = np.random.default_rng(seed).uniform(0.0, 2.0 * np.pi, K)
    n_grid = 2 * OVERSAMPLING * K
    coeff = np.zeros(n_grid // 2 + 1, dtype=complex)
    coeff[1:K + 1] = 0.5 * n_grid * amp * np.exp(1j * phi)  # irfft: x_j = (1/N) sum c_k e^{...} (+ conj.)
    return GustSeries(u=np.fft.irfft(coeff, n_grid), dt=record_s / n_grid)
