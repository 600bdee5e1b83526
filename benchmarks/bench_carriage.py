"""A frame carried on a rail against the same job with the frame standing still (issue 39).

Run:  PYTHONPATH=src .venv/bin/python benchmarks/bench_carriage.py

Prints, for the paper's 15 s job on its rolling ship (15 001 steps), with its frame turned
on the ship (leaning 10 deg, so that both sides compose a frame's axes with the ship's) and
without a turn: the plan's time with the frame standing at the rail's start and with the
carriage moving it 4 m along a rail with a bend, and the parts of the carried frame's base
motion (the rail, the carriage's profile, the composition with the ship's motion). The issue
asks the carried plan and closed loop within 1.1x the standing ones; the closed loop (MuJoCo,
the 15 s job) is timed five times each way after a run that compiles, the plans seven times,
standing and carried in turn (the best of each). The models take C's motion in O from one
compiled pass over the time grid (``motion.carriage.carried_frame_motion``: the carriage's
profile, the rail, the frame's yaw and C on S where the carriage moves, the composition with
the ship's motion at every sample); C's motion on S alone (``carriage_motion``, which the
brush, the strip and the 3D view read) is kept per carriage and time grid. The carried plan
is timed again and afresh (``forget_carriage_motions`` before each plan), as are the base
motion and its parts.

Measured (AMD EPYC, 2 cores shared, load average 0.7-1.0, 2026-12-07 19:56-19:58 UTC, three runs
of this script each, at 4948798 and at eecc0a5 (before: C on S as numpy and kept, composed by a
second kernel) in turn; the range and the median):

==================================  ========================  ========================
carried / standing                   before (eecc0a5)          after (4948798)
==================================  ========================  ========================
closed loop, upright frame           1.00-1.03x (1.02x)        0.99-1.03x (0.99x)
closed loop, frame leaning 10 deg    0.95-0.97x (0.96x)        0.95-0.96x (0.96x)
plan afresh (a first plan), upright  1.24-1.30x (1.29x)        1.06-1.15x (1.08x)
plan again, upright                  1.07-1.10x (1.07x)        1.08-1.16x (1.11x)
plan afresh, leaning 10 deg          0.60-0.63x                0.52-0.53x
==================================  ========================  ========================

(The upright standing plan took 7.2-8.8 ms.) The carried frame's base motion is the ship's
(1.15 ms, as the standing frame's) and C's motion in O in one pass, 0.65-0.67 ms: the
composition alone 0.35 ms (some 200 flops a sample, scalar: numba does not vectorise it), C on S
where the carriage moves the rest (5 sines and cosines a sample on the rail's arc). Before, C
on S afresh took 2.1-2.3 ms (the base motion afresh 3.2-3.5 ms: numpy's temporaries and
gathers, its sines and cosines at every sample) and a repeated plan found it kept; now a plan
evaluates it each time, in the pass, for 0.3 ms more than the composition alone (a repeated
plan is 0.04x slower than before, a first one 0.2x faster). A frame standing turned on the ship pays its own composition with LAPACK's
Euler rates (``in_frame_axes``), hence the leaning frame's ratio below 1.
"""

from __future__ import annotations

import numpy as np

from _common import best_of, machine  # benchmarks/_common.py

import marinecdpr
from marinecdpr.motion.basemotion import evaluate_base_motion, frame_ship_motion
from marinecdpr.motion.carriage import (
    carriage_motion, carried_frame_motion, carried_motion, forget_carriage_motions, frame_yaw, rail_of,
)
from marinecdpr.motion.rail import carriage_profile

RAIL = {"rail_m": [[-0.78, 0.0, 2.2], [3.0, 0.0, 2.2], [6.0, 3.0, 2.2]], "corner_radius_m": 2.0,
        "speed_max_m_s": 0.6, "accel_max_m_s2": 0.5, "jerk_max_m_s3": 2.0, "stations_m": [0.0, 4.0], "dwell_s": 2.0}


def in_turn(repeats: int, *fns) -> list[float]:
    """Each of ``fns`` called ``repeats`` times, one after the other in turn (the machine's
    speed drifts by tens of % within minutes: in turn, each meets the same drift); the best
    wall time of each, s."""
    best = [float("inf")] * len(fns)
    for _ in range(repeats):
        for i, fn in enumerate(fns):
            best[i] = min(best[i], best_of(1, fn)[1])
    return best


def main() -> None:
    marinecdpr.keep_freed_memory()  # as the command does: else the plans timed in turn page-fault their memory back
    print(machine())
    paper = marinecdpr.load_scenario("paper")
    t = paper.time.step_s * np.arange(paper.time.n_steps)
    for lean in (0.0, 10.0):
        orientation = [lean, 0.0, 0.0]
        standing = paper.with_changes(ship={"frame_origin_m": [-0.78, 0.0, 2.2], "frame_orientation_deg": orientation})
        carried = paper.with_changes(ship={"carriage": RAIL, "frame_orientation_deg": orientation})
        marinecdpr.plan(standing)
        marinecdpr.plan(carried)
        t_stand, t_carry, t_fresh = in_turn(7, lambda: marinecdpr.plan(standing), lambda: marinecdpr.plan(carried),
                                            lambda: (forget_carriage_motions(), marinecdpr.plan(carried)))
        _, m_stand = best_of(7, lambda: frame_ship_motion(standing, t))
        _, m_carry = best_of(7, lambda: frame_ship_motion(carried, t))
        _, m_fresh = best_of(7, lambda: (forget_carriage_motions(), frame_ship_motion(carried, t)))
        from marinecdpr.prototype.simulation import simulate

        simulate(standing, run="closed_loop", n_steps=50)
        simulate(carried, run="closed_loop", n_steps=50)
        c_stand, c_carry = in_turn(5, lambda: simulate(standing, run="closed_loop"),
                                   lambda: simulate(carried, run="closed_loop"))
        print(f"frame leaning {lean:g} deg: closed loop on MuJoCo standing {c_stand:.2f} s, carried {c_carry:.2f} s "
              f"({c_carry / c_stand:.3f}x)")
        print(f"frame leaning {lean:g} deg: plan standing {t_stand * 1e3:.1f} ms, carried {t_carry * 1e3:.1f} ms "
              f"({t_carry / t_stand:.2f}x), carried afresh {t_fresh * 1e3:.1f} ms ({t_fresh / t_stand:.2f}x); its base "
              f"motion {m_stand * 1e3:.2f} ms standing, {m_carry * 1e3:.2f} ms carried, {m_fresh * 1e3:.2f} ms afresh")
    ship = evaluate_base_motion(paper.base_motion, t)
    c = carried.ship.carriage
    rail = rail_of(carried.ship)
    s, s_dot, s_ddot, _ = carriage_profile(np.array(c.stations_m), c.dwell_s, c.speed_max_m_s, c.accel_max_m_s2,
                                           c.jerk_max_m_s3, t)
    rel = carriage_motion(carried.ship, t)
    parts = {"the ship's motion (evaluate_base_motion)": lambda: evaluate_base_motion(paper.base_motion, t),
             "the carriage's profile": lambda: carriage_profile(np.array(c.stations_m), c.dwell_s, c.speed_max_m_s,
                                                                c.accel_max_m_s2, c.jerk_max_m_s3, t),
             "the rail at s (Rail.at)": lambda: rail.at(s),
             "the frame's yaw": lambda: frame_yaw(rail, s),
             "C's motion on S afresh (carriage_motion, all of the above but the ship)":
                 lambda: (forget_carriage_motions(), carriage_motion(carried.ship, t)),
             "composed with the ship's (carried_motion)": lambda: carried_motion(ship, *rel),
             "all of it in one pass, as the models take it (carried_frame_motion)":
                 lambda: carried_frame_motion(ship, carried.ship, t)}
    for what, f in parts.items():
        _, dt = best_of(7, f)
        print(f"  {what}: {dt * 1e3:.2f} ms for {t.size} steps")


if __name__ == "__main__":
    main()
