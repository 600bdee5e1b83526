"""Cables as built in the virtual prototype (issue 14): the own plant's steps per second with
ideal, straight elastic, motor-winch and catenary cables on the paper's robot; one
catenary solve (the plant makes 16 a step: 4 cables x 4 RK4 stages) beside scipy's root
finder on Irvine's equations, what a user would otherwise call; and eight cables' lengths
and J~ over swivelling pulleys in a compiled loop beside point anchors.

Run:  .venv/bin/python benchmarks/bench_cables.py [--steps N] [--repeats R]

Prints the machine line, then per cable model the best and worst of the repeats (the
machine may be shared), after a first run that compiles.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from numba import njit
from scipy.optimize import root

import marinecdpr
from marinecdpr.geometry.kinematics import cables_step
from marinecdpr.geometry.pulley import pulleys_step
from marinecdpr.geometry.rotations import matrix_from_euler
from marinecdpr.model.catenary import N_OUT, catenary_forces
from marinecdpr.prototype.simulation import simulate

from _common import machine

WINCH = dict(drum_radius_m=0.05, gear_ratio=10.0, torque_max_Nm=2.0, speed_max_rad_s=300.0, power_max_W=200.0,
             rotor_inertia_kg_m2=1e-4, drum_inertia_kg_m2=1e-3)
MODELS = {
    "ideal": ({}, {"model": "ideal"}),
    "elastic, length winch": ({}, {"model": "elastic", "stiffness_EA_N": 1e5}),
    "elastic, motor winch": ({"winch": WINCH}, {"model": "elastic", "stiffness_EA_N": 1e5, "winch": "motor"}),
    "catenary, length winch": ({"cable_weight_N_m": 0.35}, {"model": "catenary", "stiffness_EA_N": 1e5}),
}


def _scenario(robot: dict, cables: dict):
    return (marinecdpr.load_scenario("paper").with_updates("robot", **robot)
            .with_updates("simulation", plant="own", cables=cables))


def _irvine(x, h, v, L0, w, EA):
    """Irvine's (I-1, I-2) residual in (H, V_B), for scipy."""
    H, VB = x
    VA = VB - w * L0
    return [H * L0 / EA + H / w * (np.arcsinh(VB / H) - np.arcsinh(VA / H)) - h,
            (VB * L0 - w * L0 * L0 / 2) / EA + H / w * (np.hypot(1, VB / H) - np.hypot(1, VA / H)) - v]


@njit
def _pulley_loop(n, x, R, a, z, r, p, L, J, C, B):
    bad = 0
    for k in range(n):
        x[0] = 0.5 + 1e-7 * k
        bad += pulleys_step(x, R, a, z, r, p, L, J, C, B) != 0
    return bad


@njit
def _point_loop(n, x, R, a, p, L, J):
    for k in range(n):
        x[0] = 0.5 + 1e-7 * k
        cables_step(x, R, a, p, L, J)


def _cables_per_step(repeats: int) -> tuple[float, float]:
    """ns per step of eight spatial cables over pulleys (radii 1-10 cm) and from points."""
    rng = np.random.default_rng(5)
    a = rng.uniform(-4.5, 4.5, size=(8, 3))
    z = rng.normal(size=(8, 3))
    z /= np.linalg.norm(z, axis=1, keepdims=True)
    r, p = rng.uniform(0.01, 0.1, size=8), rng.uniform(-0.3, 0.3, size=(8, 3))
    x, R = np.zeros(3), matrix_from_euler(np.array([[0.1, -0.2, 0.3]]))[0]
    L, J, C, B = np.empty(8), np.empty((8, 6)), np.empty((8, 3)), np.empty(8)
    _pulley_loop(10, x, R, a, z, r, p, L, J, C, B)
    _point_loop(10, x, R, a, p, L, J)
    n, best = 200_000, [np.inf, np.inf]
    for _ in range(repeats):
        t0 = time.perf_counter()
        assert _pulley_loop(n, x, R, a, z, r, p, L, J, C, B) == 0
        t1 = time.perf_counter()
        _point_loop(n, x, R, a, p, L, J)
        t2 = time.perf_counter()
        best = [min(best[0], (t1 - t0) / n), min(best[1], (t2 - t1) / n)]
    return best[0] * 1e9, best[1] * 1e9


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=15001)
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args()
    print(machine())
    print(f"own plant, closed loop, paper robot, {args.steps} steps of 1 ms (steps/s: best / worst of "
          f"{args.repeats})")
    for label, (robot, cables) in MODELS.items():
        sc = _scenario(robot, cables)
        ref = marinecdpr.plan(sc)
        simulate(sc, run="closed_loop", reference=ref, n_steps=100)  # compiles
        rates = []
        for _ in range(args.repeats):
            t0 = time.perf_counter()
            simulate(sc, run="closed_loop", reference=ref, n_steps=args.steps)
            rates.append(args.steps / (time.perf_counter() - t0))
        print(f"  {label:24s} {max(rates):9,.0f} / {min(rates):9,.0f}")
    # one catenary: a 1.2 m span of the paper's rope at ~50 N, warm-started as the plant does
    h, v, w, EA = 1.0, -0.6, 0.35, 1e5
    L0 = np.hypot(h, v) * (1 - 50 / EA) + 1e-4
    out = np.empty(N_OUT)
    catenary_forces(h, v, L0, w, EA, np.full(2, np.nan), out, 100)
    guess = out[:2].copy()
    n = 20000
    best = np.inf
    for _ in range(args.repeats):
        t0 = time.perf_counter()
        for _ in range(n):
            catenary_forces(h, v, L0, w, EA, guess, out, 100)
        best = min(best, (time.perf_counter() - t0) / n)
    ref = root(_irvine, guess * 1.01, args=(h, v, L0, w, EA))
    assert ref.success and np.allclose(ref.x, out[:2], rtol=1e-8)
    m = 500
    best_scipy = np.inf
    for _ in range(args.repeats):
        t0 = time.perf_counter()
        for _ in range(m):
            root(_irvine, guess * 1.01, args=(h, v, L0, w, EA))
        best_scipy = min(best_scipy, (time.perf_counter() - t0) / m)
    print(f"one catenary (H, V_B) from (h, v, L0), warm-started: catenary_forces from Python "
          f"{best * 1e6:.2f} us (inside the plant's loop it is also compiled); scipy.optimize.root on "
          f"Irvine's equations {best_scipy * 1e6:.0f} us")
    pulleys_ns, points_ns = _cables_per_step(args.repeats)
    print(f"eight spatial cables' lengths and J~ in a compiled loop: over pulleys {pulleys_ns:.0f} ns a step, "
          f"from points {points_ns:.0f} ns")


if __name__ == "__main__":
    main()
