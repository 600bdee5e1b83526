"""A frame carried on the ship (issue 39, item 1): C's motion in O, the ship's composed with
the carriage's, against finite differences of the composed pose."""

from __future__ import annotations

import numpy as np
import pytest

from marinecdpr.geometry.rotations import euler_kinematics
from marinecdpr.motion.carriage import carried_motion
from marinecdpr.motion.ship import body_coordinates, ship_motion

# the ship: every DOF a sinusoid (amplitude, period s, phase rad); angles in rad
SHIP = [(0.8, 9.0, 0.3), (0.5, 11.0, 1.1), (1.2, 8.0, 2.0), (0.15, 10.0, 0.4), (0.06, 7.0, 2.5), (0.05, 13.0, 0.9)]


def _ship_eta(t, k=0):
    """The ship's eta at times t, or its k-th derivative, shape (n, 6)."""
    out = np.zeros((t.size, 6))
    for dof, (amp, period, phase) in enumerate(SHIP):
        w = 2 * np.pi / period
        arg = w * t + phase
        out[:, dof] = amp * w ** k * [np.sin, np.cos, lambda x: -np.sin(x), lambda x: -np.cos(x)][k % 4](arg)
    return out


def _carriage(t, k=0):
    """C on S: its origin along a curved, rising path, and its yaw turning, with k-th derivatives
    (k = 0, 1, 2) as (r, psi)."""
    r = np.stack([[3.0 * t + 0.4 * np.sin(0.9 * t), 2.0 * np.cos(0.5 * t) + 5.0, 0.3 * np.sin(0.7 * t) - 2.0],
                  [3.0 + 0.36 * np.cos(0.9 * t), -1.0 * np.sin(0.5 * t), 0.21 * np.cos(0.7 * t)],
                  [-0.324 * np.sin(0.9 * t), -0.5 * np.cos(0.5 * t), -0.147 * np.sin(0.7 * t)]][k], axis=1)
    psi = [0.3 * np.sin(0.6 * t) + 0.1 * t, 0.18 * np.cos(0.6 * t) + 0.1, -0.108 * np.sin(0.6 * t)][k]
    return r, psi


R0 = euler_kinematics(np.radians([8.0, -12.0, 20.0])).R  # the frame's lean at the start


def _rz(psi):
    c, s = np.cos(psi), np.sin(psi)
    R = np.zeros(psi.shape + (3, 3))
    R[..., 0, 0], R[..., 0, 1], R[..., 1, 0], R[..., 1, 1], R[..., 2, 2] = c, -s, s, c, 1.0
    return R


def _pose(t):
    """C's pose in O by composing the poses directly: x_OC, R_OC."""
    ship = ship_motion(_ship_eta(t), _ship_eta(t, 1), _ship_eta(t, 2))
    r, psi = _carriage(t)
    R_SC = _rz(psi) @ R0
    return ship.eta[:, :3] + np.einsum("nij,nj->ni", ship.R_SO, r), ship.R_SO @ R_SC


# sixth-order central differences: error ~ h^6 f^(7), round-off ~ eps / h (measured: 2-4e-12
# relative for each derivative below)
FD = {1: (np.array([-1, 9, -45, 0, 45, -9, 1]) / 60.0, 1)}


def _fd(f, t, h, order):
    w, p = FD[order]
    return sum(wk * f(t + (k - 3) * h) for k, wk in enumerate(w) if wk) / h ** p


def _composed(t):
    ship = ship_motion(_ship_eta(t), _ship_eta(t, 1), _ship_eta(t, 2))
    (r, psi), (v, dpsi), (a, ddpsi) = _carriage(t), _carriage(t, 1), _carriage(t, 2)
    R_SC = _rz(psi) @ R0
    z_C = R_SC[:, 2, :]
    return carried_motion(ship, r, v, a, R_SC, z_C * dpsi[:, None], z_C * ddpsi[:, None])


def test_the_composed_motion_is_the_derivative_of_the_composed_pose():
    t = np.linspace(0.0, 30.0, 41)
    m = _composed(t)
    x, R = _pose(t)
    # the pose itself (ship_motion rebuilds R_OC from eta's Euler angles)
    assert np.max(np.abs(m.eta[:, :3] - x)) <= 1e-15 * np.max(np.abs(x))
    assert np.max(np.abs(m.R_SO - R)) < 2e-15
    h = 1e-3
    v_fd = _fd(lambda s: _pose(s)[0], t, h, 1)
    a_fd = _fd(lambda s: _composed(s).eta_dot[:, :3], t, h, 1)  # of the velocity just checked
    assert np.max(np.abs(m.eta_dot[:, :3] - v_fd)) <= 2e-11 * np.max(np.abs(v_fd))
    assert np.max(np.abs(m.eta_ddot[:, :3] - a_fd)) <= 2e-11 * np.max(np.abs(a_fd))
    # angular velocity in C: R^T dR/dt = [omega x]
    dR = _fd(lambda s: _pose(s)[1], t, h, 1)
    W = np.einsum("nji,njk->nik", R, dR)
    w_fd = np.stack([W[:, 2, 1], W[:, 0, 2], W[:, 1, 0]], axis=1)
    assert np.max(np.abs(W + W.transpose(0, 2, 1))) < 1e-9  # skew: a rotation's rate
    assert np.max(np.abs(m.omega_SO_S - w_fd)) <= 2e-11 * np.max(np.abs(w_fd))
    # angular acceleration in C: d/dt (R omega_C) = R alpha_C
    Rw = lambda s: np.einsum("nij,nj->ni", _pose(s)[1], _composed(s).omega_SO_S)  # noqa: E731
    alpha_fd = np.einsum("nji,nj->ni", R, _fd(Rw, t, h, 1))
    assert np.max(np.abs(m.alpha_SO_S - alpha_fd)) <= 2e-11 * np.max(np.abs(alpha_fd))


def test_a_carriage_at_rest_on_a_still_ship_is_a_frame_standing_there():
    """A carriage that does not move gives C's place composed with the ship's, and a still ship
    with a moving carriage gives the carriage's own motion."""
    t = np.linspace(0.0, 5.0, 7)
    z = np.zeros((t.size, 3))
    r = np.tile([4.0, -2.0, 1.5], (t.size, 1))
    ship = ship_motion(_ship_eta(t), _ship_eta(t, 1), _ship_eta(t, 2))
    m = carried_motion(ship, r, z, z, np.broadcast_to(R0, (t.size, 3, 3)), z, z)
    # a point fixed on the ship: its acceleration is a_S + alpha x r + omega x (omega x r), in O
    w, al = ship.omega_SO_S, ship.alpha_SO_S
    a_rigid = ship.eta_ddot[:, :3] + np.einsum("nij,nj->ni", ship.R_SO, np.cross(al, r) + np.cross(w, np.cross(w, r)))
    assert np.allclose(m.eta_ddot[:, :3], a_rigid, rtol=0, atol=1e-13)
    assert np.allclose(m.omega_SO_S, w @ R0, rtol=0, atol=1e-15)
    still = ship_motion(np.zeros((t.size, 6)), np.zeros((t.size, 6)), np.zeros((t.size, 6)))
    (rc, psi), (vc, dpsi), (ac, ddpsi) = _carriage(t), _carriage(t, 1), _carriage(t, 2)
    R_SC = _rz(psi) @ R0
    m = carried_motion(still, rc, vc, ac, R_SC, R_SC[:, 2, :] * dpsi[:, None], R_SC[:, 2, :] * ddpsi[:, None])
    assert np.array_equal(m.eta_ddot[:, :3], ac)
    assert np.allclose(m.eta[:, 5] - m.eta[0, 5], psi - psi[0], rtol=0, atol=1e-12)  # yaw turns with the rail


def test_the_frame_s_yaw_follows_the_rail_and_turns_smoothly_through_its_bends():
    """On straight pieces the yaw is the rail's heading (from the start's); through a bend it
    turns by the bend's change of heading with continuous first and second derivatives, which
    central differences of the yaw confirm."""
    from marinecdpr.motion.carriage import frame_yaw
    from marinecdpr.motion.rail import check_rail

    # an L on the deck, then a rise along a sheer line turning back: two bends
    rail = check_rail(np.array([[0.0, 0.0, 0.0], [10.0, 0.0, 0.0], [10.0, 10.0, 1.0], [4.0, 14.0, 1.5]]), 2.0)
    a, b, psi_a, psi_b = rail.bends
    s = np.linspace(0.0, rail.length_m, 2001)
    yaw, dyaw, ddyaw = frame_yaw(rail, s)
    heading = rail.at(s).heading - rail.at(np.zeros(1)).heading[0]
    straight = np.ones(s.size, bool)
    for a_k, b_k in zip(a, b):
        straight &= (s <= a_k) | (s >= b_k)
    assert np.max(np.abs(yaw[straight] - heading[straight])) < 1e-14
    assert np.max(np.abs(dyaw[straight])) == 0.0 and np.max(np.abs(ddyaw[straight])) == 0.0
    # the first bend turns by a right angle: the yaw at its middle is half of it (S(1/2) = 1/2)
    mid = frame_yaw(rail, np.array([0.5 * (a[0] + b[0])]))
    assert mid[0][0] == pytest.approx(0.5 * (psi_b[0] - psi_a[0]), abs=1e-15)
    assert psi_b[0] - psi_a[0] == pytest.approx(np.pi / 2, abs=1e-14)
    h = 1e-4
    for f, df in ((lambda x: frame_yaw(rail, x)[0], dyaw), (lambda x: frame_yaw(rail, x)[1], ddyaw)):
        inner = (s > h) & (s < rail.length_m - h)
        fd = (f(s[inner] + h) - f(s[inner] - h)) / (2 * h)
        assert np.max(np.abs(fd - df[inner])) < 1e-7 * np.max(np.abs(df))  # measured 1.4e-8, 2.7e-8 (h^2)
    # continuity: the derivatives vanish on both sides of every join
    for x in np.concatenate([a, b]):
        _, d1, d2 = frame_yaw(rail, np.array([x - 1e-9, x + 1e-9]))
        assert np.max(np.abs(d1)) < 1e-12 and np.max(np.abs(d2)) < 1e-6


def _rail_scenario(yaw_deg=0.0, **carriage):
    import marinecdpr

    rail = {"rail_m": [[-0.78, 0.0, 2.2], [3.0, 0.0, 2.2], [6.0, 3.0, 2.2]], "corner_radius_m": 2.0,
            "speed_max_m_s": 0.6, "accel_max_m_s2": 0.5, "jerk_max_m_s3": 2.0, "stations_m": [2.5, 4.0],
            "dwell_s": 0.2} | carriage
    paper = marinecdpr.load_scenario("paper")  # the paper's rolling, pitching, yawing ship
    return paper.with_changes(ship={"carriage": rail, "frame_orientation_deg": [10.0, 0.0, yaw_deg]},
                              time={"step_s": 0.001, "duration_s": 3.0})


def test_a_carried_frame_s_motion_is_the_composition_its_euler_angles_derived_only_when_asked(monkeypatch):
    """The models take C's rotation, angular velocity and acceleration as composed; the Euler
    angles of R_OC and their rates (two batched solves, which took most of a carried plan's
    time, now E's inverse written out) are derived only when something asks for eta (MuJoCo's
    ship, the MRU), and give the same motion back; the same as LAPACK's solves to 3.4e-16 of
    the largest."""
    import marinecdpr
    from marinecdpr.motion.basemotion import evaluate_base_motion, frame_ship_motion
    from marinecdpr.motion.carriage import carriage_motion

    sc = _rail_scenario()
    t = sc.time.step_s * np.arange(sc.time.n_steps)

    def no_rates(*args, **kwargs):
        raise AssertionError("the Euler rates were derived")

    import marinecdpr.motion.ship as ship_module

    monkeypatch.setattr(ship_module, "_euler_rates", no_rates)
    m = frame_ship_motion(sc, t)
    p = marinecdpr.plan(sc)  # needs no Euler angles of C
    ship = evaluate_base_motion(sc.base_motion, t)
    r, v, a, R_SC, w_CS, al_CS = carriage_motion(sc.ship, t)
    assert np.max(np.abs(m.R_SO - ship.R_SO @ R_SC)) < 1e-15  # measured: 2.2e-16
    w = np.einsum("nji,nj->ni", R_SC, ship.omega_SO_S) + w_CS
    assert np.max(np.abs(m.omega_SO_S - w)) <= 1e-15 * np.max(np.abs(w))
    assert p.feasible.all()
    monkeypatch.undo()
    back = ship_motion(m.eta, m.eta_dot, m.eta_ddot)  # as MuJoCo's ship is driven
    assert np.max(np.abs(back.R_SO - m.R_SO)) < 1e-15
    for got, want in ((back.omega_SO_S, m.omega_SO_S), (back.alpha_SO_S, m.alpha_SO_S)):
        assert np.max(np.abs(got - want)) <= 1e-14 * np.max(np.abs(want))
    solved = body_coordinates(m.x_SO_O, m.v_SO_O, m.a_SO_O, m.R_SO, m.omega_SO_S, m.alpha_SO_S)  # LAPACK's
    for got, want in zip((m.eta, m.eta_dot, m.eta_ddot), solved):
        assert np.max(np.abs(got - want)) <= 2e-15 * np.max(np.abs(want))


def test_a_chunk_of_a_carried_motion_takes_its_euler_angles_from_the_whole_series():
    """Turning the frame through yaw = 180 deg on S: eta's yaw is unwrapped over the whole
    series, and a chunk (as a long plan takes its pieces) asked for eta later gets the whole
    series' rows, not angles unwrapped from its own start."""
    from marinecdpr.motion.basemotion import frame_ship_motion

    sc = _rail_scenario(170.0, stations_m=[2.9, 4.5], speed_max_m_s=1.0, accel_max_m_s2=1.0, jerk_max_m_s3=5.0)
    t = sc.time.step_s * np.arange(sc.time.n_steps)
    whole = frame_ship_motion(sc, t)
    rows = slice(2000, None)
    chunk = frame_ship_motion(sc, t).take(rows)  # a fresh motion: its eta not yet derived
    assert whole.eta[0, 5] < np.pi - 0.1 and whole.eta[-1, 5] > np.pi + 0.5  # it does cross 180 deg
    for got, want in ((chunk.eta, whole.eta), (chunk.eta_dot, whole.eta_dot), (chunk.eta_ddot, whole.eta_ddot)):
        assert np.array_equal(got, want[rows])


def test_the_kept_carriage_motion_is_its_own_carriage_s_and_read_only():
    """C's motion on S is kept per carriage and time grid: the same again, another carriage's
    or another grid's its own, and the kept arrays cannot be written."""
    from marinecdpr.motion.carriage import carriage_motion, forget_carriage_motions

    sc = _rail_scenario()
    t = sc.time.step_s * np.arange(sc.time.n_steps)
    first = carriage_motion(sc.ship, t)
    forget_carriage_motions()
    fresh = carriage_motion(sc.ship, t)
    for other in (carriage_motion(_rail_scenario(stations_m=[2.5, 3.5]).ship, t), carriage_motion(sc.ship, t[:-1]),
                  carriage_motion(_rail_scenario(dwell_s=0.3).ship, t)):
        assert other[0].shape != first[0].shape or np.max(np.abs(other[0] - first[0])) > 0.01
    again = carriage_motion(sc.ship, t)
    for a, b, c in zip(first, again, fresh):
        assert np.array_equal(a, b) and np.array_equal(a, c) and c is not a
        with pytest.raises(ValueError, match="read-only"):
            a[0] = 0.0


@pytest.mark.parametrize("case", range(6))
def test_the_one_pass_carried_motion_is_the_series_composition_to_the_bit(case):
    """``carried_frame_motion`` (the carriage's profile, the rail, the yaw, C on S and the
    composition in one compiled pass, C on S once for a run of rest) against the series it
    fuses, ``carried_motion(ship, *carriage_motion(...))``: random rails (straight pieces and
    arcs, rising), stations (back and forth, repeated, the ends), dwells, the frame leaning 10
    deg at any yaw, on a moving ship and a still one, at times in order, reversed and
    shuffled: every array the same to the bit; and the same refusal of times before 0 or NaN
    (a ship's motion of another length refused in one line). The frame's yaw, summed over the
    bends sample by sample, is numpy's sums of whole arrays, to the bit."""
    from marinecdpr.motion.basemotion import evaluate_base_motion
    from marinecdpr.motion.carriage import carriage_motion, carried_frame_motion, frame_yaw, rail_of
    from marinecdpr.motion.rail import RailError
    from marinecdpr.motion.ship import still_ship

    rng = np.random.default_rng(1000 + case)
    n_points = int(rng.integers(2, 6))
    heading = np.cumsum(rng.uniform(-1.2, 1.2, n_points - 1))
    steps = rng.uniform(2.0, 5.0, n_points - 1)
    points = np.zeros((n_points, 3))
    points[1:, 0] = np.cumsum(steps * np.cos(heading))
    points[1:, 1] = np.cumsum(steps * np.sin(heading))
    points[1:, 2] = np.cumsum(rng.uniform(-0.3, 0.3, n_points - 1))
    probe = _rail_scenario(rail_m=points.tolist(), corner_radius_m=0.5, stations_m=[0.0])
    length = rail_of(probe.ship).length_m
    n_st = int(rng.integers(2, 5))
    stations = rng.uniform(0.0, length, n_st).tolist()
    if case % 2:
        stations += [stations[-1], 0.0, length]  # a repeated station, the rail's two ends
    dwell = rng.uniform(0.0, 0.4, len(stations)).tolist() if case % 3 else 0.25
    sc = _rail_scenario(yaw_deg=float(rng.uniform(-180, 180)), rail_m=points.tolist(), corner_radius_m=0.5,
                        stations_m=stations, dwell_s=dwell, speed_max_m_s=float(rng.uniform(0.5, 3.0)),
                        accel_max_m_s2=float(rng.uniform(0.5, 3.0)), jerk_max_m_s3=float(rng.uniform(1.0, 10.0)))
    t = np.arange(6000) * 0.004
    for times in (t, t[::-1].copy(), rng.permutation(t)):
        for ship in (evaluate_base_motion(sc.base_motion, times), still_ship(times.size)):
            fused = carried_frame_motion(ship, sc.ship, times)
            series = carried_motion(ship, *carriage_motion(sc.ship, times))
            for name in ("x_SO_O", "v_SO_O", "a_SO_O", "R_SO", "omega_SO_S", "alpha_SO_S"):
                assert np.array_equal(getattr(fused, name), getattr(series, name)), name
    assert np.ptp(carriage_motion(sc.ship, t)[0], axis=0).max() > 0.1  # the carriage did move
    rail = rail_of(sc.ship)  # the yaw's sums over the bends, as whole arrays
    a, b, psi_a, psi_b = rail.bends
    s = np.concatenate([rng.uniform(0.0, rail.length_m, 2000), a, b, [0.0, rail.length_m]])
    u = np.clip((s[:, None] - a) / (b - a), 0.0, 1.0)
    d, w = psi_b - psi_a, b - a
    whole = [np.zeros(s.size) for _ in range(3)]
    for k in range(a.size):  # in the bends' order, as the sums are taken
        whole[0] += d[k] * u[:, k] ** 2 * u[:, k] * (10.0 + u[:, k] * (6.0 * u[:, k] - 15.0))
        whole[1] += d[k] / w[k] * 30.0 * u[:, k] ** 2 * (1.0 + u[:, k] * (u[:, k] - 2.0))
        whole[2] += d[k] / (w[k] * w[k]) * 60.0 * u[:, k] * (1.0 + u[:, k] * (2.0 * u[:, k] - 3.0))
    for got, want in zip(frame_yaw(rail, s), whole):
        assert np.array_equal(got, want)
    for bad in (np.array([0.0, -1.0]), np.array([0.0, np.nan])):
        with pytest.raises(RailError) as fused_error:
            carried_frame_motion(still_ship(2), sc.ship, bad)
        with pytest.raises(RailError) as series_error:
            carriage_motion(sc.ship, bad)
        assert str(fused_error.value) == str(series_error.value)
    with pytest.raises(ValueError, match="the ship's motion has 2 samples and t 3: give one a time"):
        carried_frame_motion(still_ship(2), sc.ship, np.array([0.0, 1.0, 2.0]))
