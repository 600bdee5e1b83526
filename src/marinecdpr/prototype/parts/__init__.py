"""The virtual prototype's parts, the signals they exchange, and the one loop that wires them.

Like Drake's systems framework, each part of the prototype is a small unit that declares
its parameters and state (one ``NamedTuple`` record of arrays and numbers), the named
signals of the bus it reads and writes (:class:`Signals`), and one compiled step; a part
module registers its record with :func:`part` and says how to build it from a scenario
(its ``build(context)``, called by :mod:`~marinecdpr.prototype.builder`). One exchange
(every ``time.step_s``, 1 ms; the paper's figure 4) calls the active parts' steps in their
declared order (:func:`exchange`), then the plant advances one step with the tensions
and loads on the bus; a plant never reads a part's record, only the bus and, where the
tensions follow the plant's state within the step, the cable part's law
(:func:`cable_tensions`, :func:`mujoco_cables`).

The plants' loops take the parts wired (:func:`wire`, :class:`Wired`): each part's step a C
function compiled once for its record's type (:func:`step_pointer`), its record stored at an
address, and only the cable part typed. A loop is then compiled once per cable law, not once
per combination of parts: a run that adds a camera or a fault compiles its new part's step
(about a second), not the loop (10-30 s each time it was specialised on the parts' tuple).

The parts, in the order of an exchange (``order``):

=====  ==================================  ==========================================
order  part (module)                       writes
=====  ==================================  ==========================================
0      cable geometry (``geometry``)       L, Ldot, J at the true pose
10     pose sensor (``sensors``)           meas.x, R, v, w; its time stamp
11     load cells (``sensors``)            meas.T, cell_noise
12     encoders (``sensors``)              meas.L, meas.Ldot
13     motion reference unit (``sensors``) meas.eta; its time stamp
14     camera (``camera``)                 meas.x fused with its late estimate
20     controller (``controller``)         T_cmd, L0_cmd, fallbacks, brake
30     winch with a lag (``winches``)      L0 (held), T_hold
40     cables (``cables``)                 T_app (held, elastic or catenary); T_winch
                                           (catenary: the tension at the winch end)
45     motor winch (``winches``)           L0 (held and drum), meas.tau, meas.tau_set
46     motor currents (``sensors``)        meas.tau: its noise (motor winches, closed loop)
50     brush contact (``brush``)           f_ext, m_ext
60     carriage drive (``carriage``)       nothing: its force along the rail, recorded
90     log (``log``)                       the run's time series
=====  ==================================  ==========================================

A scenario's ``[[faults]]`` are parts' modes, built only where it lists them (without any,
the parts above, as they are): a cable that snaps wraps the cables' part (``SnappedCables``),
a winch's brake or lost motor the winches' (``BrakedLagWinch``, ``FaultyMotorWinch``), a late
controller the controller's (``LateController``); a load cell's or an encoder's faults are a
part of their own after the sensors (``SensorFaults``, order 13.5): with any fault listed, the
length-controlled and motor winches are built in that mode, so that the brakes the controller
commands as its last resort (``brake``) hold their drums after
``[simulation.control.safety] brake_delay_s``.

A new part is one new module in this package: its record (decorated with :func:`part`),
its compiled step, and its ``build(context)``; nothing in the loop, the plants or another
part changes. Vectors are in the robot frame C unless named otherwise; units are SI.
"""

from __future__ import annotations

import importlib
import pkgutil
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numba import carray, njit, typeof, types
from numba.extending import overload

from marinecdpr.borrowed import (
    borrowed, c_function, call_step, call_stored, data_address, float64_pointer, load, store_in, stored, stored_size,
)
from marinecdpr.control.records import Measurement

__all__ = ["Signals", "PartSpec", "part", "specs", "part_step", "exchange", "cable_tensions", "mujoco_cables",
           "empty_signals", "Wired", "wire", "step_pointer", "law_pointer", "law_tensions", "SIGNALS", "STATE_SIGNALS",
           "PLANT_WRITES", "DIVERGENCE_M", "diverged"]

DIVERGENCE_M = 10.0
"""A run stops as diverged when the platform is this far from its plan."""


class Signals(NamedTuple):
    """The bus: the signals of the current exchange, each written by one part (or by the
    plant), read by any. ``m`` cables.

    x, v, w : (3,) the platform's true position (m), velocity (m/s), angular velocity
        (rad/s) in C, and R : (3, 3) R_PC: the plant's state at t_k (written by the loop).
    L, Ldot : (m,) the cables' lengths (m) and rates (m/s); J : (m, 6) J~, at that pose.
    meas : the controller's measurement (:class:`~marinecdpr.control.records.Measurement`),
        written by the sensors.
    T_cmd, L0_cmd : (m,) the controller's commands (N; m).
    cell_noise : (m,) the load cells' noise on this exchange, N.
    L0 : (m,) the unstretched lengths the winches hold over the step, m; L0_drum : (m,) what
        the drums have paid out now (the encoders' reading), m.
    T_hold : (m,) the tensions tension-controlled winches hold, N.
    T_app : (m,) the tensions the cables apply over the step, N.
    T_winch : (m,) heavy cables: the tension at each cable's winch end over what the drum
        has paid out now (the catenary's T_A, carrying the cable's weight), N.
    f_ext, m_ext : (3,) loads on the platform beyond the known disturbance, held over the
        step, in C about P (a brush's), N and N m.
    fallbacks : (1,) int64 the controller's fallbacks so far.
    brake : (m,) int64 1 where the controller commands a winch's brake (its last resort,
        :attr:`~marinecdpr.control.records.Command.brake`), else 0.
    """

    x: np.ndarray
    R: np.ndarray
    v: np.ndarray
    w: np.ndarray
    L: np.ndarray
    Ldot: np.ndarray
    J: np.ndarray
    meas: Measurement
    T_cmd: np.ndarray
    L0_cmd: np.ndarray
    cell_noise: np.ndarray
    L0: np.ndarray
    L0_drum: np.ndarray
    T_hold: np.ndarray
    T_app: np.ndarray
    T_winch: np.ndarray
    f_ext: np.ndarray
    m_ext: np.ndarray
    fallbacks: np.ndarray
    brake: np.ndarray


SIGNALS = frozenset(Signals._fields) | {f"meas.{f}" for f in Measurement._fields}
"""Every signal a part may read or write: the bus's fields and the measurement's."""
PLANT_WRITES = frozenset({"x", "R", "v", "w"})
"""What the loop writes from the plant's state before the parts step."""
STATE_SIGNALS = frozenset({"L0", "L0_drum", "T_hold", "T_app", "f_ext", "m_ext", "meas.tau", "meas.tau_set"})
"""Signals that hold a value from t = 0 (the builder's context sets them): a part may read
them where no part of the run writes them (e.g. no brush: f_ext stays zero)."""


def empty_signals(meas: Measurement, T_cmd: np.ndarray, L0_cmd: np.ndarray, T_app0: np.ndarray,
                  brake: np.ndarray | None = None) -> Signals:
    """A bus for len(T_cmd) cables around the controller's measurement and commands (the same
    arrays; ``brake`` (m,) int64, the controller's brake flags, zeros where not given), the
    applied tensions starting at ``T_app0`` (m,), N; the other signals zero."""
    m = T_cmd.shape[0]
    return Signals(x=np.zeros(3), R=np.eye(3), v=np.zeros(3), w=np.zeros(3), L=np.zeros(m), Ldot=np.zeros(m),
                   J=np.zeros((m, 6)), meas=meas, T_cmd=T_cmd, L0_cmd=L0_cmd, cell_noise=np.zeros(m),
                   L0=np.zeros(m), L0_drum=np.zeros(m), T_hold=np.zeros(m),
                   T_app=np.array(T_app0, dtype=float), T_winch=np.array(T_app0, dtype=float),
                   f_ext=np.zeros(3), m_ext=np.zeros(3),
                   fallbacks=np.zeros(1, dtype=np.int64),
                   brake=np.zeros(m, dtype=np.int64) if brake is None else brake)


# ----------------------------------------------------------------------- the registry
@dataclass(frozen=True)
class PartSpec:
    """What a part declares: its record, its compiled ``step(k, h, part, bus)``, its place
    in the exchange, the signals it reads and writes, and (cable parts) its tension law in
    the plant (``tensions(part, j, x, R, v, w, L, J, bus, T) -> T``, :func:`cable_tensions`)
    and its inputs to MuJoCo (``mujoco(part, mj, bus)``, :func:`mujoco_cables`)."""

    record: type
    step: object
    order: float
    reads: tuple[str, ...]
    writes: tuple[str, ...]
    tensions: object = None
    mujoco: object = None


_PARTS: dict[type, PartSpec] = {}


def part(*, step, order: float, reads: tuple[str, ...], writes: tuple[str, ...], tensions=None, mujoco=None):
    """Register the decorated record class as a part with its compiled ``step``.

    Raises
    ------
    ValueError
        If a declared signal is not on the bus (:data:`SIGNALS`).
    """
    def register(record: type) -> type:
        unknown = sorted((set(reads) | set(writes)) - SIGNALS)
        if unknown:
            raise ValueError(f"part {record.__name__}: no signal {', '.join(unknown)} on the bus")
        _PARTS[record] = PartSpec(record=record, step=step, order=float(order), reads=tuple(reads),
                                  writes=tuple(writes), tensions=tensions, mujoco=mujoco)
        return record
    return register


def specs() -> dict[type, PartSpec]:
    """Every registered part (the modules of this package imported), by record class."""
    _import_parts()
    return dict(_PARTS)


def part_modules() -> list:
    """This package's part modules (each with a ``build(context)``), imported."""
    _import_parts()
    return [importlib.import_module(f"{__name__}.{name}") for name in _MODULES]


_MODULES: list[str] = []


def _import_parts() -> None:
    if not _MODULES:
        names = sorted(info.name for info in pkgutil.iter_modules(__path__) if not info.name.startswith("_"))
        for name in names:
            importlib.import_module(f"{__name__}.{name}")
        _MODULES.extend(names)


def _spec(ty, what: str) -> PartSpec:
    cls = getattr(ty, "instance_class", None)
    if cls not in _PARTS:
        raise TypeError(f"{what}: {ty} is not a registered part")
    return _PARTS[cls]


# ------------------------------------------------------- the loop's calls, by part type
def part_step(k, h, part, bus):
    """Advance ``part`` one exchange at t_k (compiled code only: each part's own step)."""
    raise NotImplementedError("part_step is called from compiled code")


@overload(part_step, jit_options={"cache": True})
def _part_step(k, h, part, bus):
    step = _spec(part, "part_step").step

    def impl(k, h, part, bus):  # borrowed here, where the compiler can see it: no counting below
        step(k, h, borrowed(part), borrowed(bus))
    return impl


def cable_tensions(cable, j, x, R, v, w, L, J, bus, T):
    """The tensions (m,) the cable part applies at the plant's state (x, R, v, w) at half-step
    row j, with L, J (m,), (m, 6) the cables at that state; T (m,) scratch. May rewrite J's
    rows (a sagging cable pulls along its tangent). Compiled code only."""
    raise NotImplementedError("cable_tensions is called from compiled code")


@overload(cable_tensions, jit_options={"cache": True})
def _cable_tensions(cable, j, x, R, v, w, L, J, bus, T):
    law = _spec(cable, "cable_tensions").tensions

    def impl(cable, j, x, R, v, w, L, J, bus, T):
        return law(borrowed(cable), j, x, R, v, w, L, J, borrowed(bus), T)
    return impl


def mujoco_cables(cable, mj, bus):
    """Write the cable part's inputs to MuJoCo (actuator forces, or tendon springs), before
    mj_step. Compiled code only."""
    raise NotImplementedError("mujoco_cables is called from compiled code")


@overload(mujoco_cables, jit_options={"cache": True})
def _mujoco_cables(cable, mj, bus):
    inputs = _spec(cable, "mujoco_cables").mujoco

    def impl(cable, mj, bus):
        inputs(borrowed(cable), borrowed(mj), borrowed(bus))
    return impl


# ------------------------------------------------ the parts behind pointers: one loop for all
class Wired(NamedTuple):
    """The assembled parts as a plant's compiled loop takes them, whatever they are: each
    part's step a C function (``steps``, (p,) intp addresses, :func:`step_pointer`) and its
    record stored in ``store`` (``records``, (p,) intp addresses; :func:`~marinecdpr.borrowed.store`),
    the bus likewise (``bus_at``), in the exchange's order. The cable part's law, which the
    own plant applies within the step, likewise (``law``, int64 words: [0] the address of
    its C function, :func:`law_pointer`, set where the own plant flies it, else 0; [1] the
    cable part's place in ``steps`` + 1, 0 if it is none of them; [2:] the cable part and
    the bus stored); then the robot's cables (``model``) and the reference positions
    (n_steps, 3) a divergence is measured from, m: one loop compiled serves every
    combination of parts and every cable law (the MuJoCo loop takes the cable part's inputs
    by address beside it: :func:`~marinecdpr.prototype.plants.mujoco_law`).

    ``store`` (int64 words) holds the stored records and the bus, which point into the
    parts' arrays: a Wired is valid while the parts it was made from live
    (:class:`~marinecdpr.prototype.builder.Assembly` keeps both). ``failed`` (2,) int64: the
    exchange k + 1 at which a part's step first raised (a division by zero, ...) and that
    part's place in ``steps`` + 1; zeros while none has."""

    bus: Signals
    steps: np.ndarray
    records: np.ndarray
    bus_at: int
    law: np.ndarray
    model: object
    ref_x: np.ndarray
    store: np.ndarray
    failed: np.ndarray


@njit(cache=True)
def _step_at(k, h, part_at, bus_at, record, bus):
    """A part's step on the record and the bus stored at ``part_at`` and ``bus_at``, of the
    types ``record`` and ``bus`` (type references): compiled once per part type, called
    through its C wrapper (:func:`step_pointer`). Returns 1 where the step raised (caught
    here: a C wrapper would only print it), else 0."""
    try:
        part_step(k, h, load(part_at, record), load(bus_at, bus))
    except Exception:  # noqa: BLE001 - compiled code: the loop stops and says which part
        return 1
    return 0


def step_pointer(record_type, bus_type) -> int:
    """The address of the C function that steps a part of numba type ``record_type`` on a
    bus of ``bus_type``, both stored (:func:`~marinecdpr.borrowed.call_step`): numba's C
    wrapper of :func:`_step_at` compiled for the two types (cached on disk like every
    kernel), found once per type (:func:`~marinecdpr.borrowed.c_function`)."""
    return c_function(_step_at, types.int64(types.int64, types.float64, types.intp, types.intp,
                                            types.TypeRef(record_type), types.TypeRef(bus_type)))


def _words(ty) -> int:
    return -(-stored_size(ty) // 8)


def wire(bus: Signals, parts: tuple, cable, model, ref_x: np.ndarray) -> Wired:
    """The :class:`Wired` form of ``parts`` (a tuple of part records, in the exchange's
    order) on ``bus``; ``cable`` the part whose law the plant applies (its law's address
    left 0: :func:`law_pointer`)."""
    bus_ty = typeof(bus)
    tys = [typeof(p) for p in parts]
    sizes = [_words(ty) for ty in [bus_ty] + tys]
    offsets = np.concatenate([[0], np.cumsum(sizes)]).astype(np.int64)
    words = np.zeros(int(offsets[-1]), dtype=np.int64)
    base = words.ctypes.data
    for value, a, b in zip((bus, *parts), offsets[:-1], offsets[1:]):
        store_in(value, words[a:b])
    steps = np.array([step_pointer(ty, bus_ty) for ty in tys], dtype=np.intp)
    records = np.array([base + 8 * int(a) for a in offsets[1:-1]], dtype=np.intp)
    law = stored((cable, bus), lead=2)
    law[1] = next((i + 1 for i, p in enumerate(parts) if p is cable), 0)
    return Wired(bus=bus, steps=steps, records=records, bus_at=base, law=law, model=model,
                 ref_x=ref_x, store=words, failed=np.zeros(2, dtype=np.int64))


@njit(cache=True)
def _law_at(at, j, x_at, R_at, v_at, w_at, L_at, J_at, T_at, n, pair):
    """:func:`cable_tensions` of the cable part and the bus stored at ``at`` (a pair of the
    type ``pair``, a type reference) with x, R, v, w (3,), (3, 3), L (n,), J (n, 6) and T
    (n,) at their addresses: the tensions written to T. Compiled once per cable law, called
    through its C wrapper (:func:`law_pointer`, :func:`law_tensions`). Returns 1 where the
    law raised, else 0."""
    cable, bus = load(at, pair)
    x = carray(float64_pointer(x_at), (3,))
    R = carray(float64_pointer(R_at), (3, 3))
    v = carray(float64_pointer(v_at), (3,))
    w = carray(float64_pointer(w_at), (3,))
    L = carray(float64_pointer(L_at), (n,))
    J = carray(float64_pointer(J_at), (n, 6))
    T = carray(float64_pointer(T_at), (n,))
    try:
        out = cable_tensions(cable, j, x, R, v, w, L, J, bus, T)
        for i in range(n):  # a law may answer with an array of its own (held tensions: the bus's)
            T[i] = out[i]
    except Exception:  # noqa: BLE001 - through a C wrapper: the loop stops and says which part
        return 1
    return 0


def law_pointer(cable, bus) -> int:
    """The address of the C function that applies the cable part ``cable``'s law on ``bus``
    (:func:`_law_at` for their types: compiled, or read from the disk cache, once per cable
    law; :func:`~marinecdpr.borrowed.c_function`): what :attr:`Wired.law` [0] holds where the
    own plant flies."""
    pair = typeof((cable, bus))
    return c_function(_law_at, types.int64(types.intp, types.int64, types.intp, types.intp, types.intp, types.intp,
                                           types.intp, types.intp, types.intp, types.int64, types.TypeRef(pair)))


@njit(cache=True, inline="always")
def law_tensions(wired, j, x, R, v, w, L, J, T):
    """The cable part's tensions (n,) at the plant's state (x, R, v, w; C-contiguous) at
    half-step row j into T, with L (n,), J (n, 6) the cables there (J may be rewritten:
    :func:`cable_tensions`), through ``wired.law``. Where the law raised, ``wired.failed``
    records it (the exchange j // 2 and the cable part) and T is what it left."""
    law = wired.law
    if call_stored(law[0], (data_address(law) + 16, j, data_address(x), data_address(R), data_address(v),
                            data_address(w), data_address(L), data_address(J), data_address(T), T.shape[0])) != 0:
        if wired.failed[0] == 0:
            wired.failed[0] = j // 2 + 1
            wired.failed[1] = law[1]
    return T


@njit(cache=True)
def exchange(k, h, x, R, v, w, wired):
    """One exchange at t_k from the plant's state (x, R, v, w) in C: the state onto the bus,
    then every part's step in order, each through its pointer (``wired``, :class:`Wired`).
    Returns False, or True where a part's step raised (``wired.failed`` says which; the
    parts after it not stepped)."""
    bus = borrowed(wired.bus)
    for i in range(3):
        bus.x[i] = x[i]
        bus.v[i] = v[i]
        bus.w[i] = w[i]
        for j in range(3):
            bus.R[i, j] = R[i, j]
    for i in range(wired.steps.shape[0]):
        if call_step(wired.steps[i], k, h, wired.records[i], wired.bus_at) != 0:
            if wired.failed[0] == 0:
                wired.failed[0] = k + 1
                wired.failed[1] = i + 1
            return True
    return False


@njit(cache=True)
def diverged(x, ref_x):
    """True if the position is not finite or more than DIVERGENCE_M from the reference."""
    d = 0.0
    for i in range(3):
        if not np.isfinite(x[i]):
            return True
        d = max(d, abs(x[i] - ref_x[i]))
    return d > DIVERGENCE_M
