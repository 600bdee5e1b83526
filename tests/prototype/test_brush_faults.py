"""The brush losing its contact with the hull as a mode of the brush's part (issue 40, item 2):
over the fault's window its normal force is zero, so that it presses and drags nothing and the
platform meets the known loads without the brush's (the part's f_ext, m_ext cancel the plan's
brush loads the plant applies; a water jet's reaction, not a contact, still acts); outside the
window the part is as without the fault. Hand-worked on the compiled step. And the part where
its path is held on the ship while the carriage moves (``trajectory.on_hull``, issue 39, item 3:
:class:`~marinecdpr.prototype.parts.brush.BrushOnHull`): it slides over the hull with the
carriage's velocity added, its compiled step against the planner's array functions."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from numba import njit

import marinecdpr
from marinecdpr import ScenarioError
from marinecdpr.geometry.rotations import matrix_from_euler
from marinecdpr.model.brush import cleaning_loads
from marinecdpr.motion.carriage import rail_of
from marinecdpr.planning.planner import twist_on_hull
from marinecdpr.prototype.parts import part_step
from marinecdpr.prototype.parts.brush import normal_force
from marinecdpr.prototype.simulation import prototype
from marinecdpr.studies.strip import run_scenario

from conftest import make_scenario

H, N, JET = 0.001, 400, 3.0
EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "rail_strip.toml"


@njit
def _brush_loads(part, bus, x_dot, w, R, f, m, x=None):
    """The part's f_ext, m_ext (n, 3) at each exchange with the platform moving at x_dot, w
    (n, 3) and turned R (n, 3, 3) (and, given, at x (n, 3))."""
    for k in range(f.shape[0]):
        for i in range(3):
            if x is not None:
                bus.x[i] = x[k, i]
            bus.v[i] = x_dot[k, i]
            bus.w[i] = w[k, i]
            for j in range(3):
                bus.R[i, j] = R[k, i, j]
        part_step(k, H, part, bus)
        for i in range(3):
            f[k, i] = bus.f_ext[i]
            m[k, i] = bus.m_ext[i]


def test_a_brush_that_loses_contact_presses_and_drags_nothing_in_its_window():
    """paper_clean's brush (a 0.2 m disc at 0.4 friction) with a 3 N water jet, its contact lost
    from 0.1 s for 0.15 s: the exchanges 100 .. 249 have F_n = 0 and the part's loads are the
    jet's alone less the plan's (f = jet n - f_plan, m = r x (jet n) - m_plan, r the brush's
    offset turned into C: by hand, to 1e-12); before and after they are the sound part's, bit
    for bit (the sound brush in the window pressing with the plan's 60 N and more, dragging at
    0.4 of it to 1.4 %, its loads up to 57 N from the lost one's)."""
    clean = marinecdpr.load_scenario("paper_clean")
    sc = clean.with_changes(
        time={"step_s": H, "duration_s": N * H}, cleaning=clean.cleaning.model_dump(exclude_none=True) | {"jet_N": JET},
        faults=[{"kind": "brush_contact_loss", "at_s": 0.1, "duration_s": 0.15}])
    proto = prototype(sc, "open_loop", N, include=lambda name: name == "brush", given=("R", "v", "w"))
    part = proto.get("BrushContact")
    sound_F = normal_force(proto.ref, sc)[:N]
    assert sound_F.min() > 55.0
    np.testing.assert_array_equal(part.F_n[100:250], 0.0)
    np.testing.assert_array_equal(np.delete(part.F_n, np.s_[100:250]), np.delete(sound_F, np.s_[100:250]))
    sound = part._replace(F_n=np.ascontiguousarray(sound_F))
    rng = np.random.default_rng(3)  # the platform off its plan: 0.05 m/s and 0.1 rad/s about
    x_dot = proto.ref.twist[:N, :3] + rng.normal(0.0, 0.05, (N, 3))
    w = proto.ref.twist[:N, 3:] + rng.normal(0.0, 0.1, (N, 3))
    c, s_ = np.cos(0.05), np.sin(0.05)
    R = np.broadcast_to(np.array([[c, 0.0, s_], [0.0, 1.0, 0.0], [-s_, 0.0, c]]), (N, 3, 3)).copy()
    out = {}
    for name, p in (("lost", part), ("sound", sound)):
        f, m = np.empty((N, 3)), np.empty((N, 3))
        _brush_loads(p, proto.system.bus, x_dot, w, R, f, m)
        out[name] = f, m
    (f, m), (f_s, m_s) = out["lost"], out["sound"]
    win = slice(100, 250)
    n_C = np.array(sc.cleaning.hull_normal, dtype=float)
    jet_f = JET * n_C
    r = R[0] @ np.asarray(part.params.offset_P)
    np.testing.assert_allclose(f[win], jet_f - part.f_plan[win], rtol=0.0, atol=1e-12)
    np.testing.assert_allclose(m[win], np.cross(r, jet_f) - part.m_plan[win], rtol=0.0, atol=1e-12)
    outside = np.r_[0:100, 250:N]
    np.testing.assert_array_equal(f[outside], f_s[outside])
    np.testing.assert_array_equal(m[outside], m_s[outside])
    drag = np.linalg.norm((f_s + part.f_plan)[win] - (f_s + part.f_plan)[win] @ n_C[:, None] * n_C, axis=1)
    np.testing.assert_allclose(drag, 0.4 * sound_F[win], rtol=0.02)  # the sound brush's drag there (1.4 %: the smoothing)
    assert np.abs(f_s[win] - f[win]).max() > 20.0


@pytest.mark.parametrize("fault, key, says", [
    ({"kind": "brush_contact_loss", "at_s": 0.5, "cable": 1}, "faults[1].cable", "leave it out"),
    ({"kind": "brush_contact_loss", "at_s": 0.5, "mode": "freeze"}, "faults[1].mode", "is for a sensor's faults"),
    ({"kind": "brush_contact_loss", "at_s": 0.5, "duration_s": -1.0}, "faults[1].duration_s", ""),
])
def test_a_brush_fault_mistake_is_one_line(fault, key, says):
    with pytest.raises(ScenarioError) as err:
        marinecdpr.load_scenario("paper_clean").with_changes(faults=[fault])
    text = str(err.value)
    assert "\n" not in text and key in text and says in text, text


def test_a_brush_fault_without_a_brush_is_refused_in_one_line():
    def edit(d):
        d["faults"] = [{"kind": "brush_contact_loss", "at_s": 0.5}]
    with pytest.raises(ScenarioError) as err:
        make_scenario(edit)
    text = str(err.value)
    assert "\n" not in text and "faults[1].kind" in text and "no [cleaning]" in text, text


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
    t = np.arange(N) * sc.time.step_s
    rng = np.random.default_rng(5)
    ref = proto.ref
    x = ref.pose[:N, :3] + rng.normal(0.0, 0.01, (N, 3))
    v = ref.twist[:N, :3] + rng.normal(0.0, 0.05, (N, 3))
    w = ref.twist[:N, 3:] + rng.normal(0.0, 0.1, (N, 3))
    R = matrix_from_euler(ref.pose[:N, 3:] + rng.normal(0.0, 0.05, (N, 3)))
    f, m = np.empty((N, 3)), np.empty((N, 3))
    _brush_loads(part, proto.system.bus, v, w, np.ascontiguousarray(R), f, m, x)
    twist = np.column_stack([v, w])
    f_hull, m_hull = cleaning_loads(sc.cleaning, twist_on_hull(sc, x, twist, t), R, part.brush.F_n)
    np.testing.assert_allclose(f + part.brush.f_plan, f_hull, rtol=0, atol=1e-10)
    np.testing.assert_allclose(m + part.brush.m_plan, m_hull, rtol=0, atol=1e-10)
    f_C, _ = cleaning_loads(sc.cleaning, twist, R, part.brush.F_n)
    assert np.abs(f_C - f_hull).max() > 10.0
