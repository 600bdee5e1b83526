"""The virtual prototype's MuJoCo plant on its own: a test rig for a controller that runs in
the user's own loop (:class:`~marinecdpr.control.Controller`, or their own).

:class:`Rig` holds the scenario's robot on its ship in MuJoCo, the ship moved along its
motion as :func:`~marinecdpr.prototype.simulation.simulate` moves it; the caller reads the
platform's state and the ship's motion, and applies cable tensions for one step at a time.
The cables apply the tensions given (ideal cables; tension-controlled winches); a cleaning
brush's contact is not modelled here. Flying the scenario's closed loop through a rig
from Python gives the same motion as ``simulate(run="closed_loop", plant="mujoco")``
without sensor noise (a test checks it), one Python call per step.
"""

from __future__ import annotations

import numpy as np

from marinecdpr.compiled_cache import bound
from marinecdpr.errors import SimulationDivergedError
from marinecdpr.prototype.parts import diverged
from marinecdpr.prototype.plants import _mujoco_inputs, _mujoco_state, mujoco_law
from marinecdpr.scenario.schema import Scenario

__all__ = ["Rig"]


class Rig:
    """The scenario's robot and ship in MuJoCo, stepped by the caller.

    Parameters
    ----------
    scenario : Scenario
        Its cables are taken as ideal (the tensions given act).
    n_steps : int, optional
        Steps the rig can run (default: the scenario's).

    Attributes
    ----------
    step_s : float
        h, s. n_steps : int.
    """

    def __init__(self, scenario: Scenario, *, n_steps: int | None = None) -> None:
        import mujoco

        from marinecdpr.prototype.mujoco_model import build_model
        from marinecdpr.prototype.simulation import _initial_state, _mujoco_plant, _ship_drive, prototype

        self.scenario = scenario.with_updates("simulation", cables={"model": "ideal"})
        sc = self.scenario
        h = self.step_s = sc.time.step_s
        n = self.n_steps = sc.time.n_steps if n_steps is None else min(n_steps, sc.time.n_steps)
        # the simulation's builder with only the cables: ideal, they apply the bus's T_app
        # (the caller's tensions); no brush
        proto = prototype(sc, "open_loop", n, include=lambda name: name == "cables", given=("T_cmd",), brush=False)
        ship_h, ref = proto.ship_h, proto.ref
        self._eta = np.ascontiguousarray(np.stack([ship_h.eta, ship_h.eta_dot, ship_h.eta_ddot], axis=1)[0:2 * n:2])
        self._plan_x = np.ascontiguousarray(ref.pose[:n, :3])
        self._system = proto.system
        mm = build_model(sc)
        self._model = mm.model
        self._data = mujoco.MjData(mm.model)
        self._drive = _ship_drive(ship_h, proto.held, n, carried=sc.ship.carriage is not None)
        self._mj = _mujoco_plant(sc, mm.model, self._data, mm, _initial_state(sc, ref), self._drive)
        self._mj_step = mujoco.mj_step
        # the records' types found once, not at every step (compiled_cache.bound)
        self._read = bound(_mujoco_state, self._mj)
        self._law = mujoco_law(self._system.cable, self._mj, self._system.bus)
        self._write = bound(_mujoco_inputs, self._mj, self._drive, self._law, self._system.bus)
        self.k = 0

    def state(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """The platform's true x, R_PC, v, w in C now (copies): m, -, m/s, rad/s."""
        x, R, v, w = self._read()
        return x.copy(), R.copy(), v.copy(), w.copy()

    def ship(self) -> np.ndarray:
        """The ship's true eta, eta', eta'' now, shape (3, 6) (m, rad): what an ideal motion
        reference unit reports."""
        return self._eta[self.k]

    @property
    def t(self) -> float:
        """The time now, s."""
        return self.k * self.step_s

    def step(self, tensions: np.ndarray) -> None:
        """Apply the cable tensions (m,) (N) over one step and advance.

        Raises
        ------
        SimulationDivergedError
            If the platform is more than 10 m from its plan or its state is not finite.
        IndexError
            Past the rig's last step.
        """
        k = self.k
        if k >= self.n_steps:
            raise IndexError(f"the rig has run its {self.n_steps} steps")
        x, R, _, _ = self._read()
        if diverged(x, self._plan_x[k]):
            raise SimulationDivergedError(f"{self.scenario.name}: the rig diverged at t = {self.t:.3f} s")
        self._system.bus.T_app[:] = tensions
        if self._write(k, R) != 0:
            raise SimulationDivergedError(f"{self.scenario.name}: the rig's cables failed to write MuJoCo's inputs "
                                          f"at t = {self.t:.3f} s")
        self._mj_step(self._model, self._data)
        self.k = k + 1
