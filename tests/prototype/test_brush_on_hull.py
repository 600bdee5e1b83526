"""The brush part where its path is held on the ship while the carriage moves (``trajectory.on_hull``,
:class:`~marinecdpr.prototype.parts.brush.BrushOnHull`): it slides over the hull with the
carriage's velocity added. Its compiled step against the planner's array functions
(:func:`~marinecdpr.planning.planner.twist_on_hull`, :func:`~marinecdpr.model.brush.cleaning_loads`)
at states off the plan."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from numba import njit

import marinecdpr
from marinecdpr.geometry.rotations import matrix_from_euler
from marinecdpr.model.brush import cleaning_loads
from marinecdpr.motion.carriage import rail_of
from marinecdpr.planning.planner import twist_on_hull
from marinecdpr.prototype.parts import part_step
from marinecdpr.prototype.simulation import prototype
from marinecdpr.studies.strip import run_scenario

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "rail_strip.toml"
N = 600


@njit
def _brush_loads(part, bus, x, v, w, R, h, f, m):
    """The part's f_ext, m_ext (n, 3) at each exchange, the platform at x, v, w (n, 3), R (n, 3, 3)."""
    for k in range(f.shape[0]):
        for i in range(3):
            bus.x[i] = x[k, i]
            bus.v[i] = v[k, i]
            bus.w[i] = w[k, i]
            for j in range(3):
                bus.R[i, j] = R[k, i, j]
        part_step(k, h, part, bus)
        for i in range(3):
            f[k, i] = bus.f_ext[i]
            m[k, i] = bus.m_ext[i]


def test_the_brush_slides_over_the_hull_with_the_carriage():
    """examples/rail_strip.toml's path held on the ship, the carriage running at once at 0.1 m/s
    along its bent rail (its yaw turning through the bends: omega_CS too), the platform off its
    plan (0.05 m/s, 0.1 rad/s about, 1 cm, 0.05 rad): the part's loads plus the plan's it takes
    off are the brush's at the platform's twist relative to the hull, by the planner's array
    functions, to 1e-10 N (the compiled step and numpy's order their sums apart); without the
    carriage's velocity they would differ by the drag's turn (over 10 N)."""
    sc = marinecdpr.load_scenario(str(EXAMPLE))
    sc = run_scenario(sc, 0.0, rail_of(sc.ship).length_m, dwell_s=0.0, speed_m_s=0.1)
    sc = sc.with_updates("time", duration_s=N * sc.time.step_s)
    proto = prototype(sc, "open_loop", N, include=lambda name: name == "brush", given=("x", "R", "v", "w"))
    part = proto.get("BrushOnHull")
    h = sc.time.step_s
    t = np.arange(N) * h
    rng = np.random.default_rng(5)
    ref = proto.ref
    x = ref.pose[:N, :3] + rng.normal(0.0, 0.01, (N, 3))
    v = ref.twist[:N, :3] + rng.normal(0.0, 0.05, (N, 3))
    w = ref.twist[:N, 3:] + rng.normal(0.0, 0.1, (N, 3))
    R = matrix_from_euler(ref.pose[:N, 3:] + rng.normal(0.0, 0.05, (N, 3)))
    f, m = np.empty((N, 3)), np.empty((N, 3))
    _brush_loads(part, proto.system.bus, x, v, w, np.ascontiguousarray(R), h, f, m)
    twist = np.column_stack([v, w])
    f_hull, m_hull = cleaning_loads(sc.cleaning, twist_on_hull(sc, x, twist, t), R, part.F_n)
    np.testing.assert_allclose(f + part.f_plan, f_hull, rtol=0, atol=1e-10)
    np.testing.assert_allclose(m + part.m_plan, m_hull, rtol=0, atol=1e-10)
    f_C, _ = cleaning_loads(sc.cleaning, twist, R, part.F_n)
    assert np.abs(f_C - f_hull).max() > 10.0
