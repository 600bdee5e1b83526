"""A frame carried on a rail against the same job with the frame standing still (issue 39).

Run:  PYTHONPATH=src .venv/bin/python benchmarks/bench_carriage.py

Prints, for the paper's 15 s job on its rolling ship (15 001 steps), with its frame turned
on the ship (leaning 10 deg, so that both sides compose a frame's axes with the ship's) and
without a turn: the plan's time with the frame standing at the rail's start and with the
carriage moving it 4 m along a rail with a bend, and the parts of the carried frame's base
motion (the rail, the carriage's profile, the composition with the ship's motion). The issue
asks the carried plan and closed loop within 1.1x the standing ones; the closed loop (MuJoCo,
the 15 s job) is timed once each way, after a run that compiles. C's motion on S is kept per
carriage and time grid (``motion.carriage.carriage_motion``; a run evaluates one grid for its
plan, its plant, its controller and its drive): the carried plan is timed as a repeated plan
finds it (kept) and afresh (``forget_carriage_motions`` before each plan), and so are the
base motion and C's motion on S.
"""

from __future__ import annotations

import numpy as np

from _common import best_of, machine  # benchmarks/_common.py

import marinecdpr
from marinecdpr.motion.basemotion import evaluate_base_motion, frame_ship_motion
from marinecdpr.motion.carriage import carriage_motion, carried_motion, forget_carriage_motions, frame_yaw, rail_of
from marinecdpr.motion.rail import carriage_profile

RAIL = {"rail_m": [[-0.78, 0.0, 2.2], [3.0, 0.0, 2.2], [6.0, 3.0, 2.2]], "corner_radius_m": 2.0,
        "speed_max_m_s": 0.6, "accel_max_m_s2": 0.5, "jerk_max_m_s3": 2.0, "stations_m": [0.0, 4.0], "dwell_s": 2.0}


def main() -> None:
    print(machine())
    paper = marinecdpr.load_scenario("paper")
    t = paper.time.step_s * np.arange(paper.time.n_steps)
    for lean in (0.0, 10.0):
        orientation = [lean, 0.0, 0.0]
        standing = paper.with_changes(ship={"frame_origin_m": [-0.78, 0.0, 2.2], "frame_orientation_deg": orientation})
        carried = paper.with_changes(ship={"carriage": RAIL, "frame_orientation_deg": orientation})
        marinecdpr.plan(standing)
        marinecdpr.plan(carried)
        _, t_stand = best_of(7, lambda: marinecdpr.plan(standing))
        _, t_carry = best_of(7, lambda: marinecdpr.plan(carried))
        _, t_fresh = best_of(7, lambda: (forget_carriage_motions(), marinecdpr.plan(carried)))
        _, m_stand = best_of(7, lambda: frame_ship_motion(standing, t))
        _, m_carry = best_of(7, lambda: frame_ship_motion(carried, t))
        _, m_fresh = best_of(7, lambda: (forget_carriage_motions(), frame_ship_motion(carried, t)))
        from marinecdpr.prototype.simulation import simulate

        simulate(standing, run="closed_loop", n_steps=50)
        simulate(carried, run="closed_loop", n_steps=50)
        _, c_stand = best_of(2, lambda: simulate(standing, run="closed_loop"))
        _, c_carry = best_of(2, lambda: simulate(carried, run="closed_loop"))
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
             "composed with the ship's (carried_motion)": lambda: carried_motion(ship, *rel)}
    for what, f in parts.items():
        _, dt = best_of(7, f)
        print(f"  {what}: {dt * 1e3:.2f} ms for {t.size} steps")


if __name__ == "__main__":
    main()
