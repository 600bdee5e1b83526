"""The wind field (issue 40, item 1): DNV-RP-C205's power-law profile by hand, and the Frøya
gust series against its formula (the synthesis identity, the variance, Welch's estimate within
its chi-square band)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import signal, stats

from marinecdpr.motion.wind import froya_spectrum, gust_series, wind_direction_O, wind_speed_at


def test_wind_speed_at_height_is_the_power_law_by_hand():
    # U10 = 12 m/s, alpha = 0.12: at 20 m, 12 * 2^0.12; at 2.5 m, 12 * 0.25^0.12; at 0.3 m the 1 m speed
    z = np.array([20.0, 2.5, 10.0, 0.3])
    got = wind_speed_at(z, 12.0, 10.0, 0.12)
    by_hand = np.array([12.0 * 2.0 ** 0.12, 12.0 * 0.25 ** 0.12, 12.0, 12.0 * 0.1 ** 0.12])
    assert np.allclose(got, by_hand, rtol=1e-15, atol=0)
    assert got[0] == pytest.approx(13.0408, abs=1e-4)  # 12 exp(0.12 ln 2) = 12 * 1.086735
    # a reference height of 40 m: U(10) = U40 (1/4)^0.12
    assert wind_speed_at(10.0, 20.0, 40.0, 0.12) == pytest.approx(20.0 * 0.25 ** 0.12, rel=1e-15)


def test_wind_direction_is_where_it_comes_from():
    assert np.allclose(wind_direction_O(0.0), [-1.0, 0.0, 0.0], atol=1e-16)
    assert np.allclose(wind_direction_O(90.0), [0.0, -1.0, 0.0], atol=1e-16)
    assert np.allclose(wind_direction_O(225.0), [np.sqrt(0.5), np.sqrt(0.5), 0.0], atol=1e-15)


def test_froya_spectrum_by_hand():
    # U0 = 20 m/s, z = 10 m, f = 0.1 Hz: f~ = 172 * 0.1 * 2^-0.75 = 10.2268...; S = 320 * 4 / (1 + f~^0.468)^(5/1.404)
    f_t = 17.2 * 2.0 ** -0.75
    by_hand = 1280.0 / (1.0 + f_t ** 0.468) ** (5.0 / 1.404)
    assert froya_spectrum(0.1, 20.0, 10.0) == pytest.approx(by_hand, rel=1e-14)
    assert froya_spectrum(0.0, 10.0, 20.0) == pytest.approx(320.0 * 2.0 ** 0.45, rel=1e-15)  # S(0) at 20 m


def test_gust_series_is_the_sum_of_its_harmonics():
    u0, z, T, f_max, seed = 15.0, 12.0, 600.0, 1.0, 7
    gs = gust_series(u0, z, T, f_max, seed)
    K = int(f_max * T)
    k = np.arange(1, K + 1)
    a = np.sqrt(2.0 * froya_spectrum(k / T, u0, z) / T)
    phi = np.random.default_rng(seed).uniform(0.0, 2.0 * np.pi, K)
    j = np.arange(0, gs.u.size, 97)
    t = j * gs.dt
    direct = np.cos(2.0 * np.pi * np.outer(t, k / T) + phi) @ a  # the slow, obvious sum
    assert np.abs(gs.u[j] - direct).max() < 1e-12 * np.abs(direct).max()
    assert np.array_equal(gs.at(t), gs.u[j])  # the grid's points read back exactly
    assert np.allclose(gs.at(t + T), gs.u[j], rtol=0, atol=1e-12)  # periodic over T
    # its variance is the spectrum's sum over the harmonics, sum S(f_k) / T (Parseval)
    assert np.mean(gs.u ** 2) == pytest.approx(np.sum(froya_spectrum(k / T, u0, z)) / T, rel=1e-12)
    assert abs(gs.u.mean()) < 1e-12


def test_gust_spectrum_is_froyas_within_welchs_band():
    u0, z = 15.0, 10.0
    gs = gust_series(u0, z, 3600.0, 2.0, 3)
    fs = 1.0 / gs.dt
    nperseg = 4096  # 128 s segments, no overlap: independent segments, 2 x 28 degrees of freedom
    f, S_hat = signal.welch(gs.u, fs=fs, window="hann", nperseg=nperseg, noverlap=0, detrend=False)
    n_seg = gs.u.size // nperseg
    nu = 2 * n_seg
    band = (f >= 0.05) & (f <= 1.5)
    ratio = S_hat[band] / froya_spectrum(f[band], u0, z)
    lo, hi = stats.chi2.ppf([1e-4, 1.0 - 1e-4], nu) / nu  # each bin's 99.98% band
    assert lo < ratio.min() and ratio.max() < hi, (ratio.min(), ratio.max(), lo, hi)
    assert np.mean(ratio) == pytest.approx(1.0, abs=0.03)  # and no bias over the ~180 bins
