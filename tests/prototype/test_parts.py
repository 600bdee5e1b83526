"""The prototype as parts (issue 22, item 1): each part writes only the bus signals it
declares and reads only those it declares; the builder refuses a wiring that does not
connect; a new part (the camera) is one module; the compiled-code cache is keyed by the
compiled sources; borrowed records keep what they do not strip alive."""

import numpy as np
import pytest
from numba import njit
from numba.typed import List

import marinecdpr
from marinecdpr.control.records import Slot
from marinecdpr.prototype import builder
from marinecdpr.control.step import cables_at
from marinecdpr.prototype.parts import SIGNALS, Signals, cable_tensions, law_pointer, law_tensions, specs
from marinecdpr.prototype.simulation import prototype, simulate

from conftest import make_scenario


def _variants():
    paper = marinecdpr.load_scenario("paper")
    heavy = paper.with_updates("robot", cable_weight_N_m=3.5).with_updates("simulation", plant="own").with_updates(
        "simulation.cables", model="catenary", stiffness_EA_N=1e5)
    return {
        "paper": paper,
        "elastic_length": paper.with_updates("simulation.cables", model="elastic", stiffness_EA_N=1e5,
                                             winch="length", winch_time_constant_s=0.01),
        "elastic_tension": marinecdpr.load_scenario("paper_elastic"),
        "motor": marinecdpr.load_scenario("paper_as_built"),
        "catenary": heavy,
        "catenary_motor": heavy.with_updates(  # paper_as_built's winches on the sagging cables
            "robot", winch=marinecdpr.load_scenario("paper_as_built").robot.winch.model_dump()).with_updates(
            "simulation.cables", winch="motor"),
        "clean": marinecdpr.load_scenario("paper_clean"),
        "camera": paper.with_updates("simulation.camera", latency_s=0.01, noise_m=0.001, weight=0.4),
        "motor_currents": marinecdpr.load_scenario("paper_as_built").with_updates(  # the drives' current sensors
            "simulation.noise", motor_torque_N_m=0.04),
        "carriage": paper.with_changes(ship={"carriage": {  # the frame on a rail: the carriage drive's part
            "rail_m": [[-0.78, 0.0, 2.2], [3.0, 0.0, 2.2]], "speed_max_m_s": 0.5, "accel_max_m_s2": 0.4,
            "jerk_max_m_s3": 2.0, "stations_m": [0.0, 1.0], "mass_kg": 40.0}}),
    }


VARIANTS = _variants()


def _signals(bus):
    """Every signal's array (the measurement's by 'meas.x' etc.)."""
    out = {f: getattr(bus, f) for f in Signals._fields if f != "meas"}
    out.update({f"meas.{f}": getattr(bus.meas, f) for f in bus.meas._fields})
    return out


def _fill(bus, rng):
    for name, a in _signals(bus).items():
        if a.dtype.kind == "f":
            a[...] = rng.uniform(0.5, 1.5, a.shape)
    bus.R[:] = np.eye(3)
    bus.meas.R[:] = np.eye(3)


def _arrays(x, ctl=None):
    """Every array a part's record reaches (through records and its typed list: the controller
    part's list holds the prototype's records ``ctl``, whose arrays it shares; read from
    there, since indexing a typed list from Python compiles its getitem for the records'
    type, some 8 s)."""
    if isinstance(x, np.ndarray):
        return [x]
    if isinstance(x, Slot):  # addresses into its own prototype's records: not state to copy
        return []
    if isinstance(x, tuple):
        return [a for item in x for a in _arrays(item, ctl)]
    if isinstance(x, List):
        assert ctl is not None and len(x) == 1
        return _arrays(ctl)
    return []


def _parts(name):
    sc = VARIANTS[name]
    return prototype(sc, "closed_loop", 40)


@pytest.mark.parametrize("name", sorted(VARIANTS))
def test_each_part_writes_only_what_it_declares_and_reads_only_what_it_declares(name):
    proto = _parts(name)
    system = proto.system
    table = specs()
    rng = np.random.default_rng(7)
    for part in system.parts:
        spec = table[type(part)]
        # writes: from random signals, the step changes only declared ones
        _fill(system.bus, rng)
        before = {k: v.copy() for k, v in _signals(system.bus).items()}
        state = [(a, a.copy()) for a in _arrays(part, proto.ctl)]  # its own state, to run it twice from the same one
        spec.step(20, 0.001, part, system.bus)
        changed = {k for k, v in _signals(system.bus).items() if not np.array_equal(v, before[k])}
        assert changed <= set(spec.writes), (type(part).__name__, changed - set(spec.writes))
        after = {k: _signals(system.bus)[k].copy() for k in spec.writes}
        # reads: change every undeclared signal (not the part's own outputs): same outputs
        for k, v in _signals(system.bus).items():
            v[...] = before[k]
            if k not in spec.reads and k not in spec.writes and v.dtype.kind == "f" and k not in ("R", "meas.R"):
                v[...] = before[k] * 1.7 + 0.3
        for a, saved in state:
            a[...] = saved
        spec.step(20, 0.001, part, system.bus)
        for k in spec.writes:
            if k in spec.reads:  # an update in place (a filter, a lag): from the same start it is the same
                continue
            np.testing.assert_array_equal(_signals(system.bus)[k], after[k], err_msg=f"{type(part).__name__}: {k}")


def test_every_declared_signal_is_on_the_bus_and_the_parts_run_in_their_declared_order():
    table = specs()
    assert {"CableGeometry", "PoseSensor", "LoadCells", "Encoders", "Mru", "ControllerPart", "LagWinch",
            "MotorWinch", "CatenaryMotorWinch", "HeldTensions", "ElasticCables", "CatenaryCables", "BrushContact",
            "Camera", "Log"} <= {c.__name__ for c in table}
    for spec in table.values():
        assert set(spec.reads) | set(spec.writes) <= SIGNALS
    for name in VARIANTS:
        orders = [table[type(p)].order for p in _parts(name).system.parts]
        assert orders == sorted(orders)
    motor = [type(p).__name__ for p in _parts("motor").system.parts]
    # the cables' stretch over the drums' length now, then the motors under that tension
    assert motor.index("ElasticCables") < motor.index("MotorWinch")
    heavy = [type(p).__name__ for p in _parts("catenary_motor").system.parts]
    # the catenaries' tensions at both ends over the drums' length now, then the motors
    assert heavy.index("CatenaryCables") < heavy.index("CatenaryMotorWinch") and "MotorWinch" not in heavy
    noisy = [type(p).__name__ for p in _parts("motor_currents").system.parts]
    # the measured currents: the torques the motors gave over this exchange, then their noise
    assert noisy.index("MotorWinch") + 1 == noisy.index("MotorCurrents") and "MotorCurrents" not in motor


def test_a_part_reading_what_no_part_writes_is_refused():
    table = specs()
    by_name = {c.__name__: s for c, s in table.items()}
    with pytest.raises(builder.WiringError, match="HeldTensions reads T_cmd, which no part writes"):
        builder.check_wiring([by_name["HeldTensions"]])
    builder.check_wiring([by_name["HeldTensions"]], given=("T_cmd",))
    builder.check_wiring([by_name["CableGeometry"], by_name["ControllerPart"], by_name["HeldTensions"], by_name["PoseSensor"],
                          by_name["LoadCells"], by_name["Encoders"], by_name["Mru"]])
    with pytest.raises(ValueError, match="no signal speed on the bus"):
        from marinecdpr.prototype.parts import part

        part(step=None, order=1, reads=("speed",), writes=())(type("Odd", (), {}))


def test_the_camera_step_by_hand():
    """d = 3 steps late, weight 0.25: the fused position is 0.75 x_sensor + 0.25 (x(t - 3h)
    + noise + 3 h v_meas); before 3 steps the sensor's alone."""
    from marinecdpr.control.records import empty_measurement
    from marinecdpr.prototype.parts import empty_signals
    from marinecdpr.prototype.parts.camera import Camera, camera_step

    h, d, w = 0.001, 3, 0.25
    noise = np.random.default_rng(3).normal(0.0, 0.01, (10, 3))
    cam = Camera(delay=d, weight=w, noise=noise, history=np.zeros((d + 1, 3)))
    bus = empty_signals(empty_measurement(4), np.zeros(4), np.zeros(4), np.zeros(4))
    truth = np.array([[0.1 * k, 2.0 - 0.05 * k, 0.3 * k * k] for k in range(10)])
    for k in range(10):
        bus.x[:] = truth[k]
        sensor = truth[k] + [0.01, -0.02, 0.03]
        bus.meas.x[:] = sensor
        bus.meas.v[:] = [1.0, -2.0, 0.5]
        camera_step(k, h, cam, bus)
        if k < d:
            np.testing.assert_array_equal(bus.meas.x, sensor)
        else:
            x_cam = truth[k - d] + noise[k] + d * h * np.array([1.0, -2.0, 0.5])
            np.testing.assert_allclose(bus.meas.x, (1 - w) * sensor + w * x_cam, rtol=0, atol=1e-15)


def test_the_camera_in_the_closed_loop_changes_the_tracking_and_nothing_else_when_its_weight_is_zero():
    paper = VARIANTS["paper"]
    base = simulate(paper, run="closed_loop", plant="own", n_steps=600)
    none = simulate(paper.with_updates("simulation.camera", weight=0.0, noise_m=0.0), run="closed_loop",
                    plant="own", n_steps=600)
    # weight 0: (1 - 0) x + 0 x_cam is x exactly: the same run, bit for bit
    np.testing.assert_array_equal(none.pose, base.pose)
    cam = simulate(VARIANTS["camera"], run="closed_loop", plant="own", n_steps=600)
    err, err0 = np.abs(cam.pose_error[:, :3]).max(), np.abs(base.pose_error[:, :3]).max()
    assert err > 10 * err0 and err < 5e-3  # 1 mm of noise at 40 %: sub-millimetre tracking, worse than none


def test_a_camera_with_the_encoders_pose_is_one_line():
    from marinecdpr import ScenarioError

    with pytest.raises(ScenarioError, match=r"simulation\.camera: fuses with a pose sensor's position"):
        make_scenario(lambda d: d["simulation"].update(sensors={"pose_from": "encoders"}, camera={"weight": 0.5}))


def test_the_cache_folder_moves_when_a_compiled_source_changes(tmp_path, monkeypatch):
    from marinecdpr import compiled_cache

    pkg = tmp_path / "pkg"
    (pkg / "sub").mkdir(parents=True)
    (pkg / "a.py").write_text("from numba import njit\n@njit\ndef f(x):\n    return x + 1\n")
    (pkg / "sub" / "b.py").write_text("import numba\n")
    (pkg / "plain.py").write_text("X = 1\n")
    monkeypatch.setattr(compiled_cache, "_PACKAGE", pkg)
    h0 = compiled_cache.source_hash()
    (pkg / "plain.py").write_text("X = 2\n")  # no compiled code: the same folder
    assert compiled_cache.source_hash() == h0
    (pkg / "sub" / "b.py").write_text("import numba  # edited\n")
    h1 = compiled_cache.source_hash()
    assert h1 != h0 and len(h1) == 16
    (pkg / "sub" / "b.py").write_text("import numba\n")
    assert compiled_cache.source_hash() == h0
    assert compiled_cache.cache_dir().name.startswith("marinecdpr-")


def test_a_borrowed_record_keeps_its_list_alive():
    """borrowed() strips the arrays' counting; a typed list in the record keeps its own, so
    a thousand calls do not free it (before the fix, the second call read freed memory)."""
    from marinecdpr.borrowed import borrowed

    @njit
    def total(rec):
        r = borrowed(rec)
        return r[0].sum() + r[1][0].sum()

    held = List()
    held.append(np.arange(4.0))
    rec = (np.ones(3), held)
    for _ in range(1000):
        assert total(rec) == 3.0 + 6.0
    assert held[0].sum() == 6.0


def test_warmup_compiles_the_scenarios_runs_and_says_where_it_caches():
    from typer.testing import CliRunner

    from marinecdpr.cli.app import app
    from marinecdpr.compiled_cache import cache_dir

    res = CliRunner().invoke(app, ["warmup", "paper", "paper_clean", "--plant", "own"])
    assert res.exit_code == 0, res.output
    assert "compiling (1/4) paper: own open loop..." in res.stderr
    assert "compiling (4/4) paper_clean: own closed loop..." in res.stderr
    assert f"compiled for 2 scenarios (4 runs)" in res.stdout and str(cache_dir()) in res.stdout.replace("\n", "")
    # the library call: the runs it flew, in order
    from marinecdpr.prototype.warmup import warm_up

    again = warm_up([VARIANTS["paper"]], plants=("own",))
    assert [r[:3] for r in again.runs] == [("paper", "own", "open_loop"), ("paper", "own", "closed_loop")]


def test_warmup_of_a_missing_scenario_or_plant_is_one_line():
    from typer.testing import CliRunner

    from marinecdpr.cli.app import app

    from conftest import one_line_exit_2

    one_line_exit_2(CliRunner().invoke(app, ["warmup", "no_such_robot"]), "no_such_robot")
    one_line_exit_2(CliRunner().invoke(app, ["warmup", "paper", "--plant", "steam"]), "--plant")


@pytest.mark.parametrize("name", ["clean", "camera", "catenary_motor"])
def test_the_wired_exchange_is_each_part_s_own_step_in_turn(name):
    """The loops' exchange calls each part's step through a pointer on its stored record
    (parts.wire): over 40 exchanges from the same states, it leaves the bus and every part's
    arrays bit for bit as each part's own compiled step called in turn from Python does, on
    a second prototype built alike (its scratch arrays' contents copied from the first's)."""
    from marinecdpr.prototype.parts import exchange

    sc = VARIANTS[name]
    wired, by_hand = prototype(sc, "closed_loop", 40), prototype(sc, "closed_loop", 40)
    for p, q in zip(wired.system.parts, by_hand.system.parts, strict=True):  # scratch (np.empty) alike too
        for a, b in zip(_arrays(p, wired.ctl), _arrays(q, by_hand.ctl), strict=True):
            b[...] = a
    table = specs()
    h = sc.time.step_s
    rng = np.random.default_rng(11)
    for k in range(40):
        x = by_hand.ref.pose[k, :3] + rng.normal(0.0, 1e-3, 3)
        R = np.eye(3)
        v, w = rng.normal(0.0, 0.01, 3), rng.normal(0.0, 0.001, 3)
        exchange(k, h, x, R, v, w, wired.wired)
        bus = by_hand.system.bus
        bus.x[:], bus.R[:], bus.v[:], bus.w[:] = x, R, v, w
        for part in by_hand.system.parts:
            table[type(part)].step(k, h, part, bus)
    for key, a in _signals(wired.system.bus).items():
        np.testing.assert_array_equal(a, _signals(by_hand.system.bus)[key], err_msg=key)
    for p, q in zip(wired.system.parts, by_hand.system.parts):
        for a, b in zip(_arrays(p, wired.ctl), _arrays(q, by_hand.ctl), strict=True):
            np.testing.assert_array_equal(a, b, err_msg=type(p).__name__)
    assert np.abs(wired.get("Log").T_app[:40]).max() > 10.0  # the tensions were logged: the parts ran


def test_the_loops_are_one_type_for_every_part_and_cable_law():
    """What the plants' loops are compiled for (the wired parts, the cable law by its address)
    is one type for every combination of parts and every cable law, so one loop per plant
    serves them all; each cable law is a C function of its own (the same for the same law:
    a camera, a brush, a carriage, a late controller change nothing)."""
    from numba import typeof

    def wired_and_law(sc):
        asm = prototype(sc, "closed_loop", 10)
        return typeof(asm.wired), law_pointer(asm.system.cable, asm.wired.bus)

    paper = VARIANTS["paper"]
    late = paper.with_changes(faults=[{"kind": "controller_deadline", "at_s": 0.001, "steps": 3}])
    snapped = VARIANTS["catenary"].with_changes(faults=[{"kind": "cable_snap", "cable": 2, "at_s": 0.5}])
    every = {n: wired_and_law(VARIANTS[n]) for n in VARIANTS} | {"late": wired_and_law(late),
                                                                  "snapped": wired_and_law(snapped)}
    assert len({ty for ty, _ in every.values()}) == 1
    assert len({every[n][1] for n in ("paper", "camera", "carriage", "clean", "late")}) == 1
    assert every["elastic_length"][1] == every["motor"][1] != every["paper"][1]
    assert len({law for _, law in every.values()}) == 4  # held, elastic, catenary, snapped catenary


@njit
def _law_by_address(wired, j, x, R, v, w, L, J, T):
    return law_tensions(wired, j, x, R, v, w, L, J, T)


@njit
def _law_typed(cable, j, x, R, v, w, L, J, bus, T):
    return cable_tensions(cable, j, x, R, v, w, L, J, bus, T).copy()


@pytest.mark.parametrize("name", ["paper", "elastic_length", "catenary", "snapped"])
def test_the_cable_law_by_its_address_is_the_law_typed(name):
    """Within the own plant's step the cable part's law is called through its C wrapper
    (parts.law_tensions): at random states and held lengths it gives the tensions (and the
    rewritten J~ of a sagging cable) of the law called typed, bit for bit."""
    sc = VARIANTS["catenary" if name == "snapped" else name]
    if name == "snapped":
        sc = sc.with_changes(faults=[{"kind": "cable_snap", "cable": 2, "at_s": 0.0}])
    asm = prototype(sc, "closed_loop", 10)
    wired, cable, bus = asm.wired, asm.system.cable, asm.wired.bus
    if name == "snapped":
        cable.broken[1] = True
    wired.law[0] = law_pointer(cable, bus)
    rng = np.random.default_rng(4)
    m = bus.T_app.shape[0]
    x0 = asm.ref.pose[0, :3]
    for j in range(6):
        x = x0 + rng.uniform(-0.01, 0.01, 3)
        R = np.eye(3)
        v, w = rng.uniform(-0.1, 0.1, 3), rng.uniform(-0.1, 0.1, 3)
        L0 = np.empty(m)
        J = np.empty((m, 6))
        cables_at(x, R, asm.system.model, L0, J)
        bus.L0[:] = L0 * rng.uniform(0.998, 1.0, m)
        bus.T_app[:] = rng.uniform(50.0, 150.0, m)
        J1, J2 = J.copy(), J.copy()
        by_address = _law_by_address(wired, j, x, R, v, w, L0, J1, np.empty(m)).copy()
        typed = _law_typed(cable, j, x, R, v, w, L0, J2, bus, np.empty(m))
        np.testing.assert_array_equal(by_address, typed)
        np.testing.assert_array_equal(J1, J2)
        assert np.all(typed >= 0.0) and typed.max() > 1.0
        if name == "snapped":
            assert typed[1] == 0.0
    assert list(wired.failed) == [0, 0]


def test_a_cable_law_that_raises_is_recorded_as_its_part():
    """Elastic cables over a held length of zero divide by it: through the law's C wrapper the
    error is caught and recorded (the exchange j // 2 + 1, the cable part's place + 1), where
    the own loop stops and the run names the part."""
    from marinecdpr.control.controller import robot_model
    from marinecdpr.control.records import empty_measurement
    from marinecdpr.prototype.parts import empty_signals, wire
    from marinecdpr.prototype.parts.cables import ElasticCables
    from marinecdpr.prototype.parts.camera import Camera

    bus = empty_signals(empty_measurement(4), np.zeros(4), np.zeros(4), np.zeros(4))
    cables = ElasticCables(EA=1e5, damping=0.0, Ldot=np.zeros(4))
    cam = Camera(delay=0, weight=0.5, noise=np.zeros((5, 3)), history=np.zeros((1, 3)))
    wired = wire(bus, (cam, cables), cables, robot_model(VARIANTS["paper"]), np.zeros((5, 3)))
    wired.law[0] = law_pointer(cables, bus)
    z = np.zeros(3)
    L = np.ones(4)
    _law_by_address(wired, 6, z, np.eye(3), z, z, L, np.zeros((4, 6)), np.empty(4))
    assert list(wired.failed) == [4, 2]
    bus.L0[:] = 0.5
    wired.failed[:] = 0
    T = _law_by_address(wired, 6, z, np.eye(3), z, z, L, np.zeros((4, 6)), np.empty(4))
    assert list(wired.failed) == [0, 0] and np.all(T == 1e5 * (1.0 - 0.5) / 0.5)


def test_the_loop_and_the_controller_api_call_one_compiled_step():
    """The prototype's controller part and the deployable Controller (its Python entry point)
    call the same C function for records of one type (control.controller.step_function):
    the controller's step is compiled once for both, and for a second controller of that type."""
    from marinecdpr.control.controller import Controller

    paper = VARIANTS["paper"]
    api = Controller(paper, n_steps=10)
    part = prototype(paper, "closed_loop", 10).get("ControllerPart")
    assert part.step is api._step and part.step is Controller(paper, n_steps=5)._step
    assert part.step.address == api._step.address > 0


@pytest.mark.parametrize("plant", ["own", "mujoco"])
def test_a_part_whose_step_raises_stops_the_run_naming_it(plant, monkeypatch):
    """A part's step that raises in compiled code (here a camera of delay -1: k % (d + 1)
    divides by zero) is caught where the exchange calls it through its pointer: the exchange
    stops there (the parts after it not stepped) and the run says which part failed at which
    time, where numba's C wrapper alone would have printed the error and flown on."""
    from marinecdpr.errors import SimulationDivergedError
    from marinecdpr.prototype.parts import camera

    def bad_camera(context):
        return [camera.Camera(delay=-1, weight=0.5, noise=np.zeros((context.n_steps, 3)), history=np.zeros((1, 3)))]

    monkeypatch.setattr(camera, "build", bad_camera)
    with pytest.raises(SimulationDivergedError,
                       match=r"^paper: closed_loop stopped at t = 0\.000 s: the prototype's Camera part failed in its step"):
        simulate(VARIANTS["paper"], run="closed_loop", plant=plant, n_steps=20)


def test_the_exchange_stops_at_the_part_that_raised():
    from marinecdpr.control.controller import robot_model
    from marinecdpr.control.records import empty_measurement
    from marinecdpr.prototype.parts import empty_signals, exchange, wire
    from marinecdpr.prototype.parts.camera import Camera
    from marinecdpr.prototype.parts.cables import HeldTensions

    def run(delay):
        T_cmd = np.array([10.0, 20.0, 30.0, 40.0])
        bus = empty_signals(empty_measurement(4), T_cmd, np.zeros(4), np.zeros(4))
        held = HeldTensions(from_winch=False)
        cam = Camera(delay=delay, weight=0.5, noise=np.zeros((5, 3)), history=np.zeros((max(delay + 1, 1), 3)))
        wired = wire(bus, (cam, held), held, robot_model(VARIANTS["paper"]), np.zeros((5, 3)))
        z = np.zeros(3)
        return exchange(3, 0.001, z, np.eye(3), z, z, wired), wired

    failed, wired = run(-1)
    assert failed and list(wired.failed) == [4, 1]  # exchange 3 (+1), the first part (+1)
    np.testing.assert_array_equal(wired.bus.T_app, 0.0)  # the held tensions after it not stepped
    failed, wired = run(0)
    assert not failed and list(wired.failed) == [0, 0]
    np.testing.assert_array_equal(wired.bus.T_app, [10.0, 20.0, 30.0, 40.0])
