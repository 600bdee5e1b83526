"""The controller a robot runs, called from a plain Python loop, against the virtual
prototype's MuJoCo plant (``marinecdpr.prototype.rig.Rig``) on the built-in sea scenario.

    .venv/bin/python examples/controller_loop.py [seconds]

On a real robot, ``rig.state()`` is the pose sensor (or the winches' encoders: give the
controller ``lengths=``, ``length_rates=``, ``tensions=``), ``rig.ship()`` the motion
reference unit and ``rig.step(T)`` the winches.
"""

import sys

import numpy as np

import marinecdpr
from marinecdpr.control import Controller
from marinecdpr.prototype.rig import Rig


def fly(seconds: float = 5.0, scenario: str = "paper_sea"):
    sc = marinecdpr.load_scenario(scenario)
    sc = sc.with_changes(time={"step_s": sc.time.step_s, "duration_s": seconds})
    ctl = Controller(sc)  # the scenario's plan, gains, tension method
    rig = Rig(sc)
    poses = np.empty((ctl.n_steps, 3))
    for k in range(ctl.n_steps):
        x, R, v, w = rig.state()
        poses[k] = x
        cmd = ctl.step(rig.t, x=x, R=R, v=v, w=w, eta=rig.ship())  # T_cmd (m,), at_limit (m,), flags (3,)
        rig.step(cmd.T_cmd)
    return sc, poses


if __name__ == "__main__":
    seconds = float(sys.argv[1]) if len(sys.argv) > 1 else 5.0
    sc, poses = fly(seconds)
    plan = marinecdpr.plan(sc)
    print(f"{len(poses)} steps; largest position error {np.abs(poses - plan.pose[:, :3]).max():.3g} m")
