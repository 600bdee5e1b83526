"""Recorded ship motion from CSV: conventions, round trips, derivatives, bad input."""

from __future__ import annotations

import numpy as np
import pytest

from marinecdpr.errors import ScenarioError
from marinecdpr.motion.recorded import DEFAULT_SMOOTHING_S, MOTION_CSV_COLUMNS, RecordedMotion, flip_z_axis, read_motion_csv, write_motion_csv
from marinecdpr.geometry.rotations import matrix_from_euler

# A 6-DOF sinusoidal ship motion (package convention, m and rad): amplitude,
# period (s) and phase (rad) per DOF, and offsets (yaw near north-west).
AMP = np.array([0.5, 0.4, 1.0, np.radians(8.0), np.radians(4.0), np.radians(5.0)])
PERIOD = np.array([10.0, 11.0, 8.0, 9.0, 7.0, 8.0])
PHASE = np.array([0.0, 0.7, 1.4, 2.1, 2.8, 3.5])
OFFSET = np.array([2.0, -1.0, 0.3, np.radians(1.0), np.radians(-0.5), np.radians(40.0)])
OMEGA = 2.0 * np.pi / PERIOD
DT = 0.05  # 20 Hz


def sinusoid(t):
    """eta, eta', eta'' of the test motion at times t, each shape (n, 6)."""
    ph = OMEGA * np.asarray(t)[:, None] + PHASE
    return (
        OFFSET + AMP * np.sin(ph),
        AMP * OMEGA * np.cos(ph),
        -AMP * OMEGA**2 * np.sin(ph),
    )


def times(duration=60.0, t0=0.0):
    return t0 + DT * np.arange(int(round(duration / DT)) + 1)


def good_rows(n=20):
    """Header and data lines of a valid z-up, degree file."""
    t = times(DT * (n - 1))
    eta = sinusoid(t)[0]
    eta[:, 3:] = np.degrees(eta[:, 3:])
    lines = [",".join(MOTION_CSV_COLUMNS)]
    lines += [",".join(f"{v:.10g}" for v in (ti, *e)) for ti, e in zip(t, eta)]
    return lines


def write_lines(tmp_path, lines, name="motion.csv"):
    p = tmp_path / name
    p.write_text("\n".join(lines) + "\n")
    return p


# --- the z-down convention -------------------------------------------------


def test_z_down_conversion_is_D_R_D_on_rotation_matrices():
    """R_up(flip(angles)) == D R_down(angles) D for random angles (all quadrants)."""
    rng = np.random.default_rng(1)
    eta_down = np.column_stack(
        [
            rng.normal(size=(500, 3)),
            rng.uniform(-np.pi / 2, np.pi / 2, (500, 2)),
            rng.uniform(-np.pi, np.pi, 500),
        ]
    )
    eta_up = flip_z_axis(eta_down)
    D = np.diag([1.0, -1.0, -1.0])
    R_up = matrix_from_euler(eta_up[:, 3:])
    np.testing.assert_allclose(R_up, D @ matrix_from_euler(eta_down[:, 3:]) @ D, atol=1e-14)
    # positions: v_up = D v_down
    np.testing.assert_array_equal(eta_up[:, :3], eta_down[:, :3] @ D)
    np.testing.assert_array_equal(flip_z_axis(eta_up), eta_down)  # an involution


def test_z_down_signs_mean_the_same_physical_motion():
    """Starboard down, bow up, bow to starboard in z-down terms, seen in z-up axes."""
    a = np.radians(10.0)
    stbd, bow = np.array([0.0, -1.0, 0.0]), np.array([1.0, 0.0, 0.0])  # z-up body axes
    roll, pitch, yaw = (matrix_from_euler(flip_z_axis(np.r_[0, 0, 0, e])[3:]) for e in np.eye(3) * a)
    assert (roll @ stbd)[2] < -0.17  # positive NED roll: starboard side goes down
    assert (pitch @ bow)[2] > 0.17  # positive NED pitch: bow goes up
    assert (yaw @ bow)[1] < -0.17  # positive NED yaw: bow turns to starboard (-y in z-up)
    # and heave: 1 m down in z-down is z = -1 m in z-up
    assert flip_z_axis(np.r_[0, 0, 1.0, 0, 0, 0])[2] == -1.0


# --- round trips ---------------------------------------------------------


@pytest.mark.parametrize("z_axis", ["up", "down"])
@pytest.mark.parametrize("angles", ["deg", "rad"])
def test_round_trip(tmp_path, z_axis, angles):
    t = times(30.0, t0=1000.0)
    eta = sinusoid(t)[0]
    p = tmp_path / "m.csv"
    write_motion_csv(p, t, eta, z_axis=z_axis, angles=angles)
    assert p.read_text().splitlines()[0] == ",".join(MOTION_CSV_COLUMNS)
    rec = read_motion_csv(p, z_axis=z_axis, angles=angles)
    np.testing.assert_array_equal(rec.t, t)
    np.testing.assert_allclose(rec.eta, eta, rtol=0, atol=1e-9)


def test_file_holds_the_z_down_values(tmp_path):
    t = times(1.0)
    eta = sinusoid(t)[0]
    p = tmp_path / "m.csv"
    write_motion_csv(p, t, eta, z_axis="down", angles="rad")
    raw = np.loadtxt(p, delimiter=",", skiprows=1)
    np.testing.assert_allclose(raw[:, 1:], eta * [1, -1, -1, 1, -1, -1], atol=1e-15)
    # read as z-up it is the flipped motion
    np.testing.assert_allclose(read_motion_csv(p, angles="rad").eta, flip_z_axis(eta), atol=1e-12)


def test_columns_in_any_order_and_whitespace(tmp_path):
    t = times(1.0)
    eta = sinusoid(t)[0]
    perm = [6, 0, 3, 1, 5, 2, 4]
    cols = np.column_stack([t, eta])[:, perm]
    lines = [", ".join(MOTION_CSV_COLUMNS[j] for j in perm)]
    lines += [" , ".join(repr(float(v)) for v in row) for row in cols]
    rec = read_motion_csv(write_lines(tmp_path, lines + [""]), angles="rad")
    np.testing.assert_allclose(rec.eta, eta, atol=1e-15)


# --- derivatives ---------------------------------------------------------


def test_derivatives_of_noisy_sinusoid():
    """20 Hz record with noise of 1e-4 (m, rad): default smoothing, away from the ends.

    Tolerances, per DOF relative to its own amplitude of the quantity: position
    0.5 %, velocity 2 %, acceleration 5 %, for t more than 2 s (8 tau) from the
    ends. (Achieved over 20 noise seeds: at most 0.34 %, 0.53 % and 1.75 %.)
    """
    rng = np.random.default_rng(7)
    t = times(60.0)
    eta = sinusoid(t)[0] + 1e-4 * rng.standard_normal((t.size, 6))
    rec = RecordedMotion(t, eta)
    assert rec.smoothing_s == DEFAULT_SMOOTHING_S
    tq = np.linspace(2.0, 58.0, 997)  # between samples too
    m = rec.evaluate(tq)
    x, v, a = sinusoid(tq)
    err_x = np.max(np.abs(m.eta - x), axis=0) / AMP
    err_v = np.max(np.abs(m.eta_dot - v), axis=0) / (AMP * OMEGA)
    err_a = np.max(np.abs(m.eta_ddot - a), axis=0) / (AMP * OMEGA**2)
    assert err_x.max() < 0.005, err_x
    assert err_v.max() < 0.02, err_v
    assert err_a.max() < 0.05, err_a
    # the ship kinematics use them: angular velocity from the smoothed rates
    assert m.R_SO.shape == (tq.size, 3, 3) and m.omega_SO_S.shape == (tq.size, 3)


def test_smoothing_s_is_the_half_amplitude_time_scale():
    """Noise-free: amplitude ratio 1/(1 + (w tau)^4) for eta, eta' and eta''."""
    t = times(120.0)
    tau = 0.8
    w = 1.0 / tau * np.array([0.5, 1.0, 1.5])
    eta = np.zeros((t.size, 6))
    eta[:, :3] = np.sin(w * t[:, None])
    rec = RecordedMotion(t, eta, smoothing_s=tau)
    tq = np.linspace(30.0, 90.0, 2001)
    m = rec.evaluate(tq)
    H = 1.0 / (1.0 + (w * tau) ** 4)
    np.testing.assert_allclose(m.eta[:, :3], H * np.sin(w * tq[:, None]), atol=2e-3)
    np.testing.assert_allclose(m.eta_dot[:, :3] / w, H * np.cos(w * tq[:, None]), atol=2e-3)
    np.testing.assert_allclose(m.eta_ddot[:, :3] / w**2, -H * np.sin(w * tq[:, None]), atol=2e-3)


def test_zero_smoothing_interpolates():
    t = times(5.0)
    eta = sinusoid(t)[0]
    m = RecordedMotion(t, eta, smoothing_s=0.0).evaluate(t)
    np.testing.assert_allclose(m.eta, eta, atol=1e-12)


def test_evaluate_outside_the_record_raises():
    t = times(10.0, t0=5.0)
    rec = RecordedMotion(t, sinusoid(t)[0])
    rec.evaluate([5.0, 15.0])  # the ends themselves are fine
    rec.evaluate(15.0 + 1e-12)  # rounding overshoot is clipped
    for bad in ([5.0, 4.9], [15.01], [np.nan]):
        with pytest.raises(ValueError, match=r"5 s <= t <= 15 s"):
            rec.evaluate(bad)
    with pytest.raises(ValueError, match=r"t\[1\] = 4\.9"):
        rec.evaluate([5.0, 4.9])


def test_yaw_wrap_is_unwrapped_silently(tmp_path):
    """Heading swinging across +-180 deg, written wrapped to (-180, 180]."""
    t = times(20.0)
    eta = sinusoid(t)[0]
    eta[:, 5] = np.radians(175.0 + 20.0 * np.sin(0.8 * t))
    wrapped = eta.copy()
    wrapped[:, 5] = np.angle(np.exp(1j * eta[:, 5]))
    assert np.ptp(wrapped[:, 5]) > np.radians(300)  # really crosses the wrap
    for z_axis in ("up", "down"):
        p = tmp_path / f"{z_axis}.csv"
        write_motion_csv(p, t, wrapped, z_axis=z_axis)
        rec = read_motion_csv(p, z_axis=z_axis)
        np.testing.assert_allclose(rec.eta[:, 5], eta[:, 5], atol=1e-9)
        yaw_rate = rec.evaluate(t[40:-40]).eta_dot[:, 5]
        np.testing.assert_allclose(yaw_rate, np.radians(16.0) * np.cos(0.8 * t[40:-40]), atol=2e-3)


def test_record_is_read_only():
    t = times(1.0)
    eta = sinusoid(t)[0]
    rec = RecordedMotion(t, eta)
    assert eta.flags.writeable  # the caller's arrays are untouched
    with pytest.raises(ValueError):
        rec.eta[0, 0] = 1.0


# --- bad input -------------------------------------------------------------


def edit(lines, k, col, value):
    """Replace column col (name) of data line k (1 = first data line)."""
    lines = list(lines)
    cells = lines[k].split(",")
    cells[MOTION_CSV_COLUMNS.index(col)] = value
    lines[k] = ",".join(cells)
    return lines


def bad_header(name):
    def make():
        lines = good_rows()
        lines[0] = lines[0].replace("roll", name)
        return lines

    return make


def extra_column():
    return [ln + (",heading" if i == 0 else ",1") for i, ln in enumerate(good_rows())]


def missing_column():
    return [",".join(ln.split(",")[:-1]) for ln in good_rows()]


def shuffled_time():
    lines = good_rows()
    lines[5], lines[6] = lines[6], lines[5]
    return lines


def jitter():
    lines = good_rows()
    return edit(lines, 8, "time_s", f"{7 * DT + 0.002:.10g}")  # 4 % off


BAD_CASES = {  # name: (lines of the file, the message must match)
    "empty": (lambda: [], "empty"),
    "misnamed": (
        bad_header("roll_deg"),
        r"line 1: .*missing 'roll'; unexpected column 5\).*expected exactly time_s,surge_m",
    ),
    "extra": (extra_column, r"line 1: .*unexpected column 8\b"),
    "missing": (missing_column, r"line 1: .*missing 'yaw'"),
    "repeated": (bad_header("pitch"), r"missing 'roll'; repeated 'pitch'"),
    "short row": (lambda: good_rows()[:4] + ["0.15,1,2"] + good_rows()[5:], r"line 5 has 3 fields; expected 7"),
    "text": (lambda: edit(good_rows(), 3, "heave_m", "abc"), r"line 4, column heave_m: not a number"),
    "empty cell": (
        lambda: edit(good_rows(), 6, "pitch", ""),
        r"line 7, column pitch: an empty field is not a number",
    ),
    "nan": (lambda: edit(good_rows(), 9, "sway_m", "nan"), r"line 10, column sway_m: 'nan' is not a finite"),
    "inf": (lambda: edit(good_rows(), 2, "yaw", "-inf"), r"line 3, column yaw: '-inf' is not a finite"),
    "few samples": (lambda: good_rows(9), r"only 9 samples; .* at least 10"),
    "no data": (lambda: good_rows()[:1], r"no data rows"),
    "time order": (shuffled_time, r"line 7, column time_s: time 0\.2 s does not increase"),
    "repeated time": (lambda: edit(good_rows(), 4, "time_s", "0.1"), r"line 5, column time_s: .*not increase"),
    "jitter": (jitter, r"line 9, column time_s: non-uniform sampling"),
    "roll deg": (lambda: edit(good_rows(), 12, "roll", "181"), r"line 13, column roll: roll exceeds 90 deg"),
    "pitch deg": (lambda: edit(good_rows(), 3, "pitch", "-95"), r"line 4, column pitch: pitch exceeds 90 deg"),
}


@pytest.mark.parametrize("case", sorted(BAD_CASES))
def test_bad_input_names_the_row_and_column(tmp_path, case):
    make, pattern = BAD_CASES[case]
    p = write_lines(tmp_path, make())
    with pytest.raises(ScenarioError, match=pattern) as info:
        read_motion_csv(p)
    assert info.value.source == str(p)
    assert str(info.value).startswith(str(p) + ": ")
    assert "\n" not in str(info.value)


def test_degrees_declared_as_radians(tmp_path):
    p = write_lines(tmp_path, good_rows())  # roll up to 9 deg, written in deg
    pattern = r"line \d+, column roll: roll exceeds pi/2 rad .*is the unit deg\?"
    with pytest.raises(ScenarioError, match=pattern):
        read_motion_csv(p, angles="rad")


def test_bad_arguments():
    with pytest.raises(ValueError, match="z_axis"):
        read_motion_csv("x.csv", z_axis="NED")
    with pytest.raises(ValueError, match="angles"):
        write_motion_csv("x.csv", np.zeros(10), np.zeros((10, 6)), angles="degrees")
    with pytest.raises(ValueError, match="at least 10"):
        RecordedMotion(np.arange(5.0), np.zeros((5, 6)))
    with pytest.raises(ValueError, match="smoothing_s"):
        RecordedMotion(np.arange(10.0), np.zeros((10, 6)), smoothing_s=-1.0)


def test_unreadable_file(tmp_path):
    with pytest.raises(ScenarioError, match="cannot read"):
        read_motion_csv(tmp_path / "nope.csv")


def test_a_scenario_flies_on_recorded_motion_like_on_the_analytic_one(tmp_path):
    """Record the paper's ship motion at 20 Hz, plan from the record: the tensions agree."""
    import sys
    from pathlib import Path

    import numpy as np

    sys.path.insert(0, str(Path(__file__).parents[1]))
    from conftest import make_scenario

    import marinecdpr
    from marinecdpr.motion.basemotion import evaluate_base_motion

    paper = marinecdpr.load_scenario("paper")
    t_rec = np.arange(0.0, 20.0 + 1e-9, 0.05)
    eta = evaluate_base_motion(paper.base_motion, t_rec).eta
    write_motion_csv(tmp_path / "ship.csv", t_rec, eta, z_axis="down", angles="deg")
    rec = make_scenario(lambda d: (d.update(base_motion={"type": "recorded", "file": str(tmp_path / "ship.csv"),
                                                          "z_axis": "down", "start_s": 2.0}),
                                   d["time"].update(duration_s=15.0)))
    shifted = make_scenario(lambda d: [c.update(phase_deg=360.0 * 2.0 / 6.0)
                                       for c in d["base_motion"]["components"]])
    a, b = marinecdpr.plan(rec), marinecdpr.plan(shifted)
    assert a.all_feasible
    np.testing.assert_allclose(a.tensions, b.tensions, atol=0.05)   # N, from smoothed derivatives
    np.testing.assert_allclose(a.C_s, b.C_s, atol=0.05)
