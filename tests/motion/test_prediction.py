"""The ship-motion predictor (marinecdpr.motion.prediction): exact on sinusoids, accurate on a
JONSWAP sea, deaf to repeated samples, and the Taylor extrapolation exact on a quadratic."""

from __future__ import annotations

from importlib import resources

import numpy as np
import pytest
from numba import njit

from marinecdpr.motion import prediction as P
from marinecdpr.motion.rao import read_rao_csv
from marinecdpr.motion.seastate import sea_record, synthesize

MRU_HZ = 100.0
T0 = 0.00373  # the MRU's clock is not on the AR grid


@njit(cache=True)
def _feed(pred, ts, eta, eta_d, eta_dd):
    taken = 0
    for k in range(ts.size):
        taken += P.predictor_update(pred, ts[k], eta[k], eta_d[k], eta_dd[k])
    return taken


def _sines(t, comps, offset=None):
    """eta, eta', eta'' (n, 6) of sums of sinusoids: comps = [(dof, amplitude, omega, phase)]."""
    t = np.atleast_1d(np.asarray(t, dtype=float))
    eta = np.zeros((t.size, 6)) + (0.0 if offset is None else offset)
    eta_d = np.zeros((t.size, 6))
    eta_dd = np.zeros((t.size, 6))
    for d, A, w, ph in comps:
        eta[:, d] += A * np.sin(w * t + ph)
        eta_d[:, d] += A * w * np.cos(w * t + ph)
        eta_dd[:, d] -= A * w * w * np.sin(w * t + ph)
    return eta, eta_d, eta_dd


def _errors(pred, comps, offset, horizons):
    """|forecast - truth| (n_h, 3, 6) at the last sample's time + horizons."""
    out = np.empty((3, 6))
    errs = []
    for H in horizons:
        t = pred.last_t[0] + H
        assert P.predictor_forecast(pred, t, out) == P.MODEL
        truth = np.stack([x[0] for x in _sines(t, comps, offset)])
        errs.append(np.abs(out - truth))
    return np.array(errs)


def _fitted(comps, duration_s, offset=None, **options):
    pred = P.make_predictor(**options)
    ts = T0 + np.arange(0.0, duration_s, 1.0 / MRU_HZ)
    assert _feed(pred, ts, *_sines(ts, comps, offset)) == ts.size
    assert P.predictor_ready(pred)
    return pred


# one sinusoid per DOF (frequencies off any grid, 0.43-1.23 rad/s); yaw about a heading
SINGLE = [(2, 1.3, 0.8765, 0.4), (3, 0.05, 1.2345, 2.0), (4, 0.02, 0.4321, -1.0), (5, 0.01, 0.6543, 0.3)]
YAW0 = np.array([0.0, 0.0, 0.0, 0.0, 0.0, 0.7])


def _scale(comps):
    """The amplitudes of eta, eta', eta'' per DOF (3, 6) (a sum's: the sum of them)."""
    amp = np.zeros((3, 6))
    for d, A, w, _ in comps:
        amp[:, d] += [A, A * w, A * w * w]
    return amp


def test_single_sinusoid_exact():
    amp = _scale(SINGLE)
    moving = amp[0] > 0
    options = dict(step_s=0.25, order=8, forgetting=0.998)
    for duration in (40.0, 240.0):
        pred = _fitted(SINGLE, duration, YAW0, **options)
        # 1 s and 3 s: whole AR steps; 0.02, 1.37, 2.9 s: interpolated between them
        err = _errors(pred, SINGLE, YAW0, [1.0, 3.0, 0.02, 1.37, 2.9])
        rel = err[:, :, moving] / amp[:, moving]
        assert rel[:2].max() < 1e-8, rel[:2].max()  # eta, eta', eta'' at 1 s and 3 s
        assert rel.max() < 1e-6, rel.max()
        assert err[:, :, ~moving].max() < 1e-12  # still DOFs stay still
        assert pred.ints[P._RESETS] == 0


def test_single_sinusoid_converges_with_the_fit():
    # with a stronger prior (p0 = 1e6) the fit visibly converges: a longer record, a smaller error
    amp = _scale(SINGLE)
    moving = amp[0] > 0
    rel = []
    for duration in (30.0, 120.0, 480.0):
        pred = _fitted(SINGLE, duration, YAW0, step_s=0.25, order=8, forgetting=0.998, p0=1e6)
        err = _errors(pred, SINGLE, YAW0, [1.0, 3.0])
        rel.append((err[:, :, moving] / amp[:, moving]).max())
    assert rel[0] < 1e-6 and rel[1] < rel[0] / 3 and rel[2] < rel[1] / 2, rel


@pytest.mark.parametrize("comps, order", [
    ([(2, 1.0, 0.7373, 0.3), (2, 0.5, 1.111, 1.0)], 8),
    ([(2, 1.0, 0.7373, 0.3), (2, 0.5, 1.111, 1.0), (2, 0.3, 0.4321, 2.0)], 12),
])
def test_sum_of_sinusoids(comps, order):
    assert order >= 2 * len(comps)
    # roll: the same lines, scaled, about an offset
    comps = comps + [(3, 0.02 * A, w, ph + 1.0) for _, A, w, ph in comps]
    offset = np.array([0.0, 0.0, 0.0, 0.05, 0.0, 0.0])
    amp = _scale(comps)
    pred = _fitted(comps, 300.0, offset, step_s=0.25, order=order, forgetting=0.998)
    err = _errors(pred, comps, offset, [0.02, 0.5, 1.0, 1.37, 3.0])
    rel = err[:, :, 2:4] / amp[:, 2:4]
    assert rel.max() < 1e-5, rel.max()


@pytest.fixture(scope="module")
def jonswap_study():
    """Hs 2 m, Tp 8 s, waves towards 150 deg, the built-in box hull's BEM RAOs (6 DOFs move),
    600 s at 100 Hz, no latency."""
    rao = read_rao_csv(resources.files("marinecdpr.scenario") / "builtin" / "paper_sea_rao.csv")
    rec = sea_record(hs=2.0, tp=8.0, heading_deg=150.0, rao=rao, seed=3)
    t = np.arange(0.0, 600.0, 0.01)
    eta, eta_d, eta_dd = synthesize(rec, t)
    horizons = [0.02, 0.1, 0.5, 1.0, 2.0, 5.0]
    return P.prediction_error(t, eta, eta_d, eta_dd, sample_hz=MRU_HZ, latency_s=0.0,
                              horizons_s=horizons, discard_s=120.0,
                              step_s=0.25, order=20, forgetting=0.998)


def test_jonswap_error_against_horizon(jonswap_study):
    r = jonswap_study
    assert np.all(r.model_share == 1.0) and r.resets == 0
    assert np.all(np.isfinite(r.predictor))
    pred, taylor, hold = r.predictor, r.taylor, r.hold
    # eta's error grows with the horizon, every DOF
    assert np.all(np.diff(pred[:, 0], axis=0) > 0.0)
    i1, i2 = 3, 4  # 1 s, 2 s
    assert pred[i1, 0].max() < 0.1, pred[i1, 0]
    assert pred[i1].max() < 0.1  # eta' and eta'' too
    # at 1-2 s it beats the Taylor extrapolation and holding the sample, every channel
    for i in (i1, i2):
        assert np.all(pred[i] < 0.1 * taylor[i]), (pred[i] / taylor[i]).max()
        assert np.all(pred[i] < 0.1 * hold[i]), (pred[i] / hold[i]).max()
    # at 20 ms both beat holding the sample by a large factor (eta, eta'; Taylor's eta'' is held)
    assert np.all(taylor[0, :2] < hold[0, :2] / 50), (taylor[0, :2] / hold[0, :2]).max()
    assert np.all(pred[0] < hold[0] / 1000), (pred[0] / hold[0]).max()


def test_repeated_samples_change_nothing():
    comps = [(2, 1.3, 0.8765, 0.4), (3, 0.05, 1.2345, 2.0)]
    ts = T0 + np.arange(0.0, 40.0, 1.0 / MRU_HZ)
    eta, eta_d, eta_dd = _sines(ts, comps)
    options = dict(step_s=0.25, order=8, forgetting=0.998, warmup_fits=20)
    once = P.make_predictor(**options)
    _feed(once, ts, eta, eta_d, eta_dd)
    twice = P.make_predictor(**options)
    rep = np.repeat(np.arange(ts.size), 2)  # every sample given twice, then an old one again
    rep = np.insert(rep, 1000, 500)
    first = np.r_[True, rep[1:] > np.maximum.accumulate(rep)[:-1]]
    junk = 1.0 + eta[rep]  # a repeat's values are ignored, whatever they are
    taken = _feed(twice, ts[rep], np.where(first[:, None], eta[rep], junk), eta_d[rep], eta_dd[rep])
    assert taken == ts.size
    out1, out2 = np.empty((3, 6)), np.empty((3, 6))
    for H in (0.0, 0.05, 1.0, 2.5):
        assert P.predictor_forecast(once, ts[-1] + H, out1) == P.MODEL
        assert P.predictor_forecast(twice, ts[-1] + H, out2) == P.MODEL
        assert np.array_equal(out1, out2)
    for name in ("ints", "last_t", "last", "ref", "scale", "sub", "theta", "P", "traj"):
        assert np.array_equal(getattr(once, name), getattr(twice, name)), name


def test_taylor_exact_on_a_quadratic():
    rng = np.random.default_rng(1)
    a, b, c = rng.normal(size=(3, 6)) * [[2.0], [1.0], [0.5]]
    t_s, t_target = 1.7, 4.3

    def q(t):
        return np.stack([a + b * t + c * t * t, b + 2.0 * c * t, 2.0 * c])

    out = np.empty((3, 6))
    x = q(t_s)
    P.taylor_forecast(t_s, x[0], x[1], x[2], t_target, out)
    np.testing.assert_allclose(out, q(t_target), rtol=1e-12, atol=1e-12)


def test_warm_up_and_range():
    pred = P.make_predictor(step_s=0.25, order=8, forgetting=0.998, max_horizon_s=4.0)
    out = np.empty((3, 6))
    assert P.predictor_forecast(pred, 1.0, out) == P.NONE and np.isnan(out).all()
    comps = [(2, 1.3, 0.8765, 0.4)]
    ts = T0 + np.arange(0.0, 10.0, 1.0 / MRU_HZ)
    _feed(pred, ts, *_sines(ts, comps))
    assert not P.predictor_ready(pred)  # 10 (p + 1) = 90 AR steps: 22.5 s
    ref = np.empty((3, 6))
    assert P.predictor_forecast(pred, ts[-1] + 0.3, out) == P.TAYLOR
    P.taylor_forecast(ts[-1], pred.last[0], pred.last[1], pred.last[2], ts[-1] + 0.3, ref)
    assert np.array_equal(out, ref)
    ts2 = ts[-1] + np.arange(1.0, 3000.0) / MRU_HZ
    _feed(pred, ts2, *_sines(ts2, comps))
    assert P.predictor_ready(pred)
    assert P.predictor_forecast(pred, ts2[-1] + 4.0, out) == P.MODEL
    assert P.predictor_forecast(pred, ts2[-1] + 4.01, out) == P.NONE and np.isnan(out).all()
    # a gap longer than a step restarts the history: Taylor until H steps have come again
    ts3 = ts2[-1] + 1.0 + np.arange(0.0, 5.0, 1.0 / MRU_HZ)
    _feed(pred, ts3[:100], *_sines(ts3[:100], comps))
    assert not P.predictor_ready(pred)
    _feed(pred, ts3[100:], *_sines(ts3[100:], comps))
    assert P.predictor_ready(pred)


def test_per_step_functions_cannot_allocate():
    # compiled without numba's runtime: an allocation in them would not compile
    for f in (P.predictor_update, P.predictor_forecast, P.predictor_ready, P.taylor_forecast):
        assert f.targetoptions.get("_nrt") is False
