"""The fast screen's normal force in the time domain's own sea record (issue 37, item 3): the record
is a sum of a finite number of wave components of fixed amplitudes and random phases, whose
tails are lighter than the Gaussian's of the same variance; the screen's share of time in band
is the record's, not the Gaussian's."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.special import ndtr

import marinecdpr
from marinecdpr.prototype.parts.brush import normal_force
from marinecdpr.studies import screen as S
from marinecdpr.studies.operability import Cell, cell_scenario


def test_the_record_distribution_is_the_random_phase_sum_s():
    """Five components, as a long-crested 2-minute record's response has about: the series'
    CDF and density against a million draws of the phases (CDF within 3 standard errors; the
    density against the draws' histogram), and lighter tails than the Gaussian's."""
    c = np.array([8.0, 6.0, 5.0, 3.0, 2.0, 1.0, 0.5])
    rng = np.random.default_rng(1)
    X = (c * np.cos(rng.uniform(0.0, 2.0 * np.pi, (1_000_000, c.size)))).sum(axis=1)
    x = np.array([-20.0, -15.0, -10.0, 0.0, 5.0, 10.0, 15.0, 18.0])
    cdf, pdf = S.record_distribution(c, x)
    drawn = np.array([np.mean(X <= v) for v in x])
    np.testing.assert_allclose(cdf, drawn, atol=3.0 * np.sqrt(0.25 / X.size) + 1e-5)
    h = 0.25
    dens = np.array([np.mean(np.abs(X - v) < h) / (2 * h) for v in x])
    np.testing.assert_allclose(pdf, dens, atol=2e-3, rtol=0.03)
    sigma = np.sqrt((c**2).sum() / 2.0)
    assert cdf[1] < 0.99 * ndtr(-15.0 / sigma) and cdf[0] < 0.5 * ndtr(-20.0 / sigma)  # lighter tails


def test_the_normal_force_s_share_out_of_band_is_the_records_not_the_gaussian_s():
    """Beam seas of Hs 4 m, Tp 12 s on paper_clean's platform held at the frame's centre, the band
    2.6 of the force's sigmas either side of the preload: over 250 two-minute records (the
    time domain's records, realisations 0-249) the planned force is out of band 0.52 % of the
    time (+- 0.05 %, measured with 400 records: 0.521 +- 0.040 %), where a Gaussian of the
    same variance gives 0.93 % and the screen, summing the record's components, 0.55 %."""
    pc = marinecdpr.load_scenario("paper_clean")
    x = [0.95, 0.0, 0.7]
    sc = pc.with_changes(trajectory={"type": "line", "start_position_m": x, "end_position_m": x, "duration_s": 1.0},
                         time={"duration_s": 120.0, "step_s": 0.05})
    cell = Cell(0, 4.0, 12.0, 90.0, 1.0)
    run = cell_scenario(sc, cell, 120.0, 0.05)
    C0, _ = S._response_moments(S.screen_model(run, grid=(1, 1)), S._rao_of(run), [cell], run)
    sigma = float(np.sqrt(C0[0, 0, 1, 1]))
    band = [60.0 - 2.6 * sigma, 60.0 + 2.6 * sigma]
    run = run.with_updates("cleaning", normal_force_N=band)
    r = S.screen_cells(run, [cell], model=S.screen_model(run, grid=(1, 1)))
    out = []
    for i in range(250):
        rec = cell_scenario(run, cell, 120.0, 0.05, i)
        F = normal_force(marinecdpr.plan(rec), rec)[:-1]  # one whole period
        out.append(100.0 * np.mean((F < band[0]) | (F > band[1])))
    observed = float(np.mean(out))
    assert 0.3 < observed < 0.8
    assert 100.0 - r.in_band_pct[0] == pytest.approx(observed, abs=0.15)
