"""How big a run is, before it runs: memory and work of a command on a scenario.

A scenario with a tiny ``time.step_s``, a huge ``time.duration_s`` or sea-state
``record_s``, or a workspace grid of billions of poses validates, and then fails
deep inside NumPy with a ``MemoryError`` (or runs for years). :func:`check_run_size`
refuses such a run up front, in one line with its estimated size, from arithmetic on
the scenario alone (nothing is allocated).

The estimates follow how each command allocates (bytes per time step of the arrays it
holds, see :func:`estimate_run`), and were checked against measured peaks on the
``paper`` scenario (4 cables; per time step, above the process's baseline):

========================  ===========  ==========
command                   estimated    measured
========================  ===========  ==========
``plan()`` in memory      457 B        463 B
``simulate()``, one run   2.6 kB       2.5 kB
``marinecdpr simulate``   4.0 kB       3.4 kB
========================  ===========  ==========

``marinecdpr plan`` and :func:`~marinecdpr.iter_plan` stream in chunks: their memory
does not grow with the duration, only their time does.
"""

from __future__ import annotations

import os
from dataclasses import dataclass

from marinecdpr.errors import ScenarioError
from marinecdpr.scenario.schema import Scenario, SeaStateMotion

__all__ = [
    "RunSize",
    "COMMANDS",
    "MEMORY_FRACTION",
    "MAX_STEPS",
    "MAX_WAVE_WORK",
    "machine_memory_bytes",
    "estimate_run",
    "check_run_size",
    "human_bytes",
    "describe_run",
    "BemSize",
    "estimate_bem",
    "check_bem_size",
    "MAX_BEM_S",
    "MAX_LATENCY_CALLS",
    "check_latency_calls",
]

COMMANDS = ("plan", "plan_stream", "simulate", "virtual_prototype", "workspace", "operability")
"""What :func:`estimate_run` sizes: ``plan`` (:func:`~marinecdpr.plan`, the whole plan in
memory), ``plan_stream`` (:func:`~marinecdpr.iter_plan` and ``marinecdpr plan``: chunks),
``simulate`` (one :func:`~marinecdpr.simulate` run), ``virtual_prototype`` (the plan, three
runs and their files: ``marinecdpr simulate``), ``workspace`` (a grid of held poses,
each streamed) and ``operability`` (sea states, each streamed; a closed-loop flight per
cell with ``closed_loop``)."""

MEMORY_FRACTION = 0.75
"""A run may use at most this share of the machine's memory (the estimates err high by up
to about 20 %, and the machine runs other things)."""
MAX_STEPS = 10**9
"""Most time steps (over every pose, cell and run) a command may take: a billion plan steps
is minutes of planning and hours of writing plan.csv; simulating them, days."""
MAX_WAVE_WORK = 10**11
"""Most wave components x time samples a run may sum directly (sea states off the FFT
grid): about 10^7 a second, so this is hours."""
FALLBACK_MEMORY_BYTES = 8 * 2**30
"""The machine's memory when neither /proc/meminfo nor sysconf tells it."""
FINE_STEP_S = 1e-4
"""A time step finer than this is blamed before the duration (no cable robot needs 10 kHz)."""

# ---------------------------------------------------------------- bytes per step
F8 = 8  # one float64
BASE_BYTES = 300 * 10**6
"""The process itself: Python, NumPy, SciPy, Matplotlib (and MuJoCo, numba for simulations)."""
CHUNK_STEPS = 16384  # planning.DEFAULT_CHUNK_STEPS, without importing the planning chain
HARMONIC_CHUNK = 4096  # seastate._harmonic's block of times
FFT_MAX_SAMPLES = 2**18  # seastate.FFT_MAX_SAMPLES


def _plan_row(m: int, k: int, extra: int = 0) -> int:
    """A Plan's arrays per step: t; pose, twist, twist_dot, wrench, C_s, F_s (6 each);
    lengths, length_rates, tensions_pinv, tensions (m each); feasible (1 byte); reaction;
    ``extra`` more arrays of m (:func:`_extra_columns`)."""
    return F8 * (1 + 6 * 6 + (4 + extra) * m + (6 - k)) + 1


def _extra_columns(robot) -> int:
    """A Plan's optional arrays of m per step: with winches length_accelerations,
    tension_lower, tension_upper and winch_limit (counted as 8 bytes); with heavy cables
    sag_lengths and winch_tensions."""
    return (4 if robot.winch is not None else 0) + (2 if robot.cable_weight_N_m > 0.0 else 0)


def _chunk_row(m: int) -> int:
    """Temporaries of one planned chunk per step (kinematics, J~, wrench terms, solver)."""
    return 1000 + 250 * m


def _sim_row(m: int, k: int, extra: int = 0) -> int:
    """One simulate() run per step: the plan at t and the mid-step plan (each with its t);
    the ship's motion (eta and derivatives, R, omega, alpha: 33 numbers) and the
    disturbance (raw and in C: 12) on the half-step grid; the mid-step rotation; sensor
    noise and the noisy ship (12 + 18 + m); loads at t (6); the logs (6 + 3 m); MuJoCo's
    ship drive (feed-forward, targets, axes, loads in O: about 50)."""
    plans = 2 * (_plan_row(m, k, extra) + F8)
    half_grid = 2 * F8 * (1 + 33 + 12)
    run = F8 * (9 + 12 + 18 + m + 6 + 6 + 3 * m + 50)
    return plans + half_grid + run


def _result_row(m: int) -> int:
    """A SimResult kept per step (its own arrays: t, pose, lengths, tensions, commanded)."""
    return F8 * (1 + 6 + 3 * m)


def _csv_row(columns: int) -> int:
    """Writing a CSV of the whole run at once: values (8 B) and text twice (~12 chars each)."""
    return columns * (F8 + 2 * 12)


POSE_BYTES = 3 * F8 + 2 * F8 + _csv_row(5) + 4 * F8
"""A workspace grid pose: three maps, its coordinates, its CSV row, the figure's images."""


# ---------------------------------------------------------------------- machine
def machine_memory_bytes() -> int:
    """The memory this process may use: the machine's total (/proc/meminfo, else sysconf),
    or a smaller cgroup limit; :data:`FALLBACK_MEMORY_BYTES` if none can be read."""
    total = None
    try:
        with open("/proc/meminfo", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("MemTotal:"):
                    total = int(line.split()[1]) * 1024
                    break
    except (OSError, ValueError, IndexError):
        pass
    if total is None:
        try:
            total = int(os.sysconf("SC_PAGE_SIZE")) * int(os.sysconf("SC_PHYS_PAGES"))
        except (AttributeError, ValueError, OSError):
            total = None
    for path in ("/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory/memory.limit_in_bytes"):
        try:
            with open(path, encoding="ascii") as fh:
                limit = int(fh.read().strip())
        except (OSError, ValueError):
            continue
        if limit > 0 and (total is None or limit < total):
            total = limit
    return int(total) if total and total > 0 else FALLBACK_MEMORY_BYTES


def human_bytes(n: float) -> str:
    """``2.4 TB``, ``15 GB``, ``400 GB``: decimal units, a decimal below 10."""
    for unit in ("B", "kB", "MB", "GB", "TB", "PB", "EB", "ZB", "YB"):
        if unit == "YB" and abs(n) >= 999.5:
            return f"{n:.3g} YB"
        if abs(n) < 999.5 or unit == "YB":
            return f"{n:.1f} {unit}" if abs(n) < 9.95 and unit != "B" else f"{n:.0f} {unit}"
        n /= 1000.0
    raise AssertionError("unreachable")  # pragma: no cover


def _gib(n: float) -> str:
    return f"{n / 2**30:.0f} GiB" if n >= 10 * 2**30 else f"{n / 2**30:.2g} GiB"


def _count(n: float) -> str:
    """Exact below ten billion (``1,000,000,001``), else ``3e+12`` (``1e+400`` for an integer
    beyond floats)."""
    if n < 10**10:
        return f"{int(n):,}"
    try:
        return f"{float(n):.3g}"
    except OverflowError:
        return f"1e+{len(str(int(n))) - 1}"


# ---------------------------------------------------------------------- estimate
@dataclass(frozen=True)
class RunSize:
    """What a run would take.

    Attributes
    ----------
    command : str
        One of :data:`COMMANDS`.
    n_steps : int
        Time steps of one record (one pose, one cell).
    n_cables : int
    poses : int
        Records of ``n_steps``: workspace poses, operability cells x poses; else 1.
    runs : int
        Passes over each record (3 for the virtual prototype, 2 for operability with a
        closed-loop flight); else 1.
    memory_bytes : int
        Estimated peak memory.
    series_bytes, sea_bytes, pose_bytes : int
        Its parts growing with the steps, with the sea-state record, with the poses.
    wave_components : int
        Sea-state components summed (0 without a sea state).
    wave_samples : int
        Times at which they are summed directly (0 where an inverse FFT serves).
    """

    command: str
    n_steps: int
    n_cables: int
    poses: int
    runs: int
    memory_bytes: int
    series_bytes: int
    sea_bytes: int
    pose_bytes: int
    wave_components: int
    wave_samples: int

    @property
    def steps(self) -> int:
        """Time steps over every pose and run."""
        return self.n_steps * self.poses * self.runs

    @property
    def work(self) -> int:
        """Steps x cables."""
        return self.steps * self.n_cables

    @property
    def wave_work(self) -> int:
        """Wave components x samples summed directly."""
        return self.wave_components * self.wave_samples


def _wave_components(sea: SeaStateMotion) -> tuple[int, int]:
    """Components of the record (seastate.sea_record: omega up to 6 omega_p in steps of
    2 pi / record_s) and its directions."""
    k = int(6.0 * sea.record_s / sea.tp_s)
    return k, 1 if sea.spreading == "none" else int(sea.n_directions)


def _uses_fft(record_s: float, dt: float, per_call: int) -> bool:
    """Does seastate.synthesize serve ``per_call`` times spaced ``dt`` from an inverse FFT?"""
    if dt <= 0:
        return False
    m = round(record_s / dt)
    return 0 < m <= max(FFT_MAX_SAMPLES, 2 * per_call) and abs(m * dt - record_s) < 1e-9 * record_s


def ship_at_once(scenario: Scenario, n_steps: int, dt: float, chunk_steps: int) -> bool:
    """Does a plan of ``n_steps`` spaced ``dt`` evaluate the ship's motion at every step at
    once rather than chunk by chunk? For a sea state whose record grid at that spacing is
    too large to cache (more than seastate.FFT_MAX_SAMPLES samples) but no more than twice
    the run's steps: one inverse FFT then serves every step, where each chunk would sum the record's
    components directly (the ship's motion, SHIP_ROW bytes a step, is held meanwhile)."""
    sea = scenario.base_motion
    if not isinstance(sea, SeaStateMotion) or n_steps <= chunk_steps or dt <= 0:
        return False
    return FFT_MAX_SAMPLES < round(sea.record_s / dt) <= 2 * n_steps


SHIP_ROW = F8 * (3 * 6 + 9 + 3 + 3)
"""A ShipMotion's bytes per step: eta and two derivatives, R_SO, omega and alpha."""


def _sea(scenario: Scenario, per_call: int, total: int, dt: float) -> tuple[int, int, int]:
    """(bytes, components, samples summed directly) of the ship's motion in a sea state,
    sampled ``total`` times spaced ``dt``, at most ``per_call`` at once."""
    sea = scenario.base_motion
    if not isinstance(sea, SeaStateMotion):
        return 0, 0, 0
    k, n_dir = _wave_components(sea)
    # spectrum and phases over every component; RAOs per direction; 18 response rows
    record = k * (1200 + 16 * n_dir)
    if _uses_fft(sea.record_s, dt, per_call):
        m = round(sea.record_s / dt)
        if m <= FFT_MAX_SAMPLES:
            return record + 3 * 144 * m, k, 0  # the spectrum and the grid (cached)
        return record + 144 * per_call + 4 * F8 * m, k, 0  # the result; one row's spectrum and samples
    # direct sums: exp(i omega t) over a block of times, complex (with its float and complex temporaries)
    block = k * min(per_call, HARMONIC_CHUNK) * (8 + 16 + 16)
    return record + block, k, total


def estimate_run(
    scenario: Scenario,
    command: str = "plan",
    *,
    n_steps: int | None = None,
    grid: tuple[int, int] | None = None,
    cells: int = 1,
    closed_loop: bool = False,
    workers: int = 1,
    chunk_steps: int = CHUNK_STEPS,
    repeat: int = 1,
) -> RunSize:
    """The memory and work of ``command`` on ``scenario`` (arithmetic only).

    Parameters
    ----------
    scenario : Scenario
    command : str
        One of :data:`COMMANDS`.
    n_steps : int, optional
        Steps of the record (default the scenario's; ``simulate(n_steps=...)`` may use fewer).
    grid : (int, int), optional
        Workspace grid points (``workspace``; ``operability`` with ``--workspace``).
    cells : int
        Sea states (``operability``).
    closed_loop : bool
        ``operability`` also flies the closed loop in each cell.
    workers : int
        Processes running cells at once (``operability``), each with its own
        :data:`BASE_BYTES`.
    chunk_steps : int
        Steps planned at once.
    repeat : int
        Runs of the command one after another (``control-study``'s closed-loop runs): the
        steps multiply, the memory does not.

    Returns
    -------
    RunSize
    """
    if command not in COMMANDS:
        raise ValueError(f"command must be one of {', '.join(COMMANDS)}, not {command!r}")
    robot = scenario.robot
    m, k, w = robot.n_cables, len(robot.controlled), _extra_columns(robot)
    n = scenario.time.n_steps if n_steps is None else int(n_steps)
    h = scenario.time.step_s
    poses = grid[0] * grid[1] if grid is not None else 1
    chunk = min(n, chunk_steps)
    working = chunk * (_chunk_row(m) + _plan_row(m, k, w))  # one chunk planned, and its Plan
    runs = 1
    pose_bytes = 0
    if command == "plan":
        series = n * (_plan_row(m, k, w) + F8)
        if ship_at_once(scenario, n, h, chunk_steps):
            series += n * SHIP_ROW
            sea = _sea(scenario, n, n, h)
        else:
            sea = _sea(scenario, chunk, n, h)
    elif command == "plan_stream":
        series = 0
        working += chunk * _csv_row(2 + 6 + (3 + w) * m)  # the chunk's CSV text (at most w more columns of m)
        sea = _sea(scenario, chunk, n, h)
    elif command == "simulate":
        series = n * _sim_row(m, k, w)
        sea = _sea(scenario, 2 * n + 1, 2 * n + 1, h / 2)
    elif command == "virtual_prototype":
        runs = 3
        # the plan kept, three results kept, a run without its own reference, the largest CSV
        series = n * (3 * _result_row(m) + _sim_row(m, k, w) + _csv_row(1 + 12 + 4 * m))
        sea = _sea(scenario, 2 * n + 1, 2 * n + 1, h / 2)
    elif command == "workspace":
        # the ship's motion of a chunk, shared by every held pose: evaluated once per chunk
        series = 0
        working += chunk * SHIP_ROW
        pose_bytes = poses * POSE_BYTES
        sea = _sea(scenario, chunk, n, h)
    else:  # operability
        poses *= max(int(cells), 1)
        runs = 2 if closed_loop else 1
        per_cell = _sea(scenario, chunk, n, h)
        flight = n * _sim_row(m, k, w) if closed_loop else 0
        series = max(int(workers), 1) * flight
        pose_bytes = poses * POSE_BYTES
        fly = _sea(scenario, 2 * n + 1, 2 * n + 1, h / 2) if closed_loop else (0, 0, 0)
        # a cell's held poses share its ship's motion (workspace_map): summed once per cell
        wave_samples = (per_cell[2] + fly[2]) * max(int(cells), 1)
        working += chunk * SHIP_ROW if grid is not None else 0
        sea = (max(int(workers), 1) * max(per_cell[0], fly[0]), per_cell[1], wave_samples)
        working *= max(int(workers), 1)
        # each worker is a process of its own: its Python, NumPy, SciPy and numba
        working += (max(int(workers), 1) - 1) * BASE_BYTES
    sea_bytes, components, samples = sea
    runs *= max(int(repeat), 1)
    samples *= max(int(repeat), 1)
    memory = BASE_BYTES + working + series + sea_bytes + pose_bytes
    return RunSize(command=command, n_steps=n, n_cables=m, poses=poses, runs=runs, memory_bytes=int(memory),
                   series_bytes=int(series), sea_bytes=int(sea_bytes), pose_bytes=int(pose_bytes),
                   wave_components=int(components), wave_samples=int(samples))


def describe_run(size: RunSize, grid: tuple[int, int] | None = None) -> str:
    """One line saying how big a run is, for the terminal before it starts, e.g.
    ``600 poses (30 x 20) x 15,001 steps = 9,000,600 plan steps, about 564 MB in memory; the
    sea state's 1,350 wave components summed at 15,001 times``."""
    text = f"{_count(size.n_steps)} steps"
    if size.poses > 1 or grid is not None:
        shape = f" ({grid[0]} x {grid[1]})" if grid is not None else ""
        text = f"{_count(size.poses)} pose{'s' if size.poses != 1 else ''}{shape} x {text}"
    if size.runs > 1:
        text += f" x {size.runs} runs"
    if size.steps != size.n_steps:
        text += f" = {_count(size.steps)} plan steps"
    text += f", about {human_bytes(size.memory_bytes)} in memory"
    if size.wave_samples:
        text += (f"; the sea state's {_count(size.wave_components)} wave components summed at "
                 f"{_count(size.wave_samples)} times")
    elif size.wave_components:
        text += f"; the sea state's {_count(size.wave_components)} wave components by inverse FFT"
    return text


# ------------------------------------------------------------------------ check
_VERBS = {"plan": "planning", "plan_stream": "planning", "simulate": "simulating",
          "virtual_prototype": "simulating", "workspace": "holding", "operability": "judging"}


def _time_key(scenario: Scenario) -> tuple[str, str]:
    if scenario.time.step_s < FINE_STEP_S:
        return "time.step_s", "use a longer step_s or a shorter duration_s"
    return "time.duration_s", "use a shorter duration_s or a longer step_s"


def _steps_text(size: RunSize, scenario: Scenario) -> str:
    t = scenario.time
    text = f"{_count(size.n_steps)} steps of {t.step_s:g} s over {t.duration_s:g} s"
    if size.command == "virtual_prototype":
        text += " (the plan and three runs)"
    return text


def check_run_size(
    scenario: Scenario,
    command: str = "plan",
    *,
    memory_bytes: int | None = None,
    **kwargs,
) -> RunSize:
    """Refuse a run that would not fit in memory or finish in sane time.

    Parameters
    ----------
    scenario : Scenario
    command : str
        One of :data:`COMMANDS`.
    memory_bytes : int, optional
        The machine's memory (default :func:`machine_memory_bytes`); a run may use
        :data:`MEMORY_FRACTION` of it.
    **kwargs
        As :func:`estimate_run` (``n_steps``, ``grid``, ``cells``, ``closed_loop``, ``workers``,
        ``repeat``).

    Returns
    -------
    RunSize
        The estimate, when the run fits.

    Raises
    ------
    ScenarioError
        One line: what is too big, its estimated size and what to change; ``key`` names
        the scenario key to change (``time.step_s``, ``time.duration_s``,
        ``base_motion.record_s``), None for a workspace grid.
    """
    size = estimate_run(scenario, command, **kwargs)
    total = machine_memory_bytes() if memory_bytes is None else int(memory_bytes)
    limit = MEMORY_FRACTION * total
    verb = _VERBS[command]
    grid = kwargs.get("grid")
    if size.memory_bytes > limit:
        need = (f"would need about {human_bytes(size.memory_bytes)} in memory (this machine: {_gib(total)}, "
                f"a run may use {MEMORY_FRACTION:.0%})")
        workers = int(kwargs.get("workers", 1))
        if workers > 1 and estimate_run(scenario, command, **(kwargs | {"workers": 1})).memory_bytes <= limit:
            raise ScenarioError(f"{verb} on {_count(workers)} workers at once {need}; use fewer workers")
        part = max(("series", size.series_bytes), ("sea", size.sea_bytes), ("poses", size.pose_bytes),
                   key=lambda p: p[1])[0]
        if part == "sea":
            sea = scenario.base_motion
            raise ScenarioError(
                f"a {sea.record_s:g} s sea-state record of {_count(size.wave_components)} wave components "
                f"{need}; use a shorter record_s", key="base_motion.record_s")
        if part == "poses":
            what = f"{_count(size.poses)} poses"
            if grid is not None:
                what += f" ({grid[0]} x {grid[1]}{' per sea state' if command == 'operability' else ''})"
            raise ScenarioError(f"{verb} {what} {need}; use fewer grid points")
        key, hint = _time_key(scenario)
        raise ScenarioError(f"{verb} {_steps_text(size, scenario)} {need}; {hint}", key=key)
    if size.steps > MAX_STEPS:
        key, hint = _time_key(scenario)
        if size.poses > 1:
            what = f"{_count(size.poses)} {'sea states and poses' if command == 'operability' else 'poses'}"
            if grid is not None:
                what += f" ({grid[0]} x {grid[1]}{' per sea state' if command == 'operability' else ''})"
            what += f" x {_count(size.n_steps)} steps"
            if size.n_steps * size.runs <= MAX_STEPS:  # the poses make it too big
                key = None
                hint = "use fewer grid points" if command == "workspace" else "use fewer sea states or grid points"
                hint += ", or fewer steps"
        else:
            what = _steps_text(size, scenario)
        total_text = " is" if size.steps == size.n_steps else f" is {_count(size.steps)} steps in all,"
        raise ScenarioError(f"{verb} {what}{total_text} more than the {_count(MAX_STEPS)} steps a run can "
                            f"finish in sane time; {hint}", key=key)
    if size.wave_work > MAX_WAVE_WORK:
        raise ScenarioError(
            f"summing {_count(size.wave_components)} wave components at {_count(size.wave_samples)} times "
            f"({size.wave_work:.3g} component-samples) is more than the {MAX_WAVE_WORK:.0e} a run can finish "
            f"in sane time; use a shorter record_s or fewer steps", key="base_motion.record_s")
    return size


# ------------------------------------------------------------------ BEM (marinecdpr rao)
BEM_MATRIX_BYTES = 64
"""Capytaine's memory per panel pair: its influence matrices S and K (complex, 16 B each),
K's LU factors and the Green function's temporaries. Measured: 422 MB above the
process's baseline for 2829 panels (53 B a pair; Capytaine 3.0, its default engine)."""
BEM_PAIR_S = 5e-7
"""Seconds per panel pair and wave frequency to build the matrices..."""
BEM_LU_S = 1e-10
"""... per panel cubed and frequency to factor them..."""
BEM_SOLVE_S = 2e-8
"""... and per panel pair, frequency and problem (six radiating DOFs and a diffraction
problem per heading) to solve. Measured on the 2-core CI machine, loaded: 2829 panels
took 4.8 s a frequency (this model says 6.3 s); the estimate errs high."""
MAX_BEM_S = 3600.0
"""Longest BEM run ``marinecdpr rao`` starts, by the estimate, s: an hour."""


@dataclass(frozen=True)
class BemSize:
    """What a BEM run would take: ``panels`` of the immersed hull, ``frequencies`` and
    ``headings`` solved, estimated peak ``memory_bytes`` and ``seconds``."""

    panels: int
    frequencies: int
    headings: int
    memory_bytes: float
    seconds: float


def estimate_bem(*, shape: str, length_m: float, beam_m: float, draught_m: float, panel_m: float,
                 frequencies: int, headings: int) -> BemSize:
    """The memory and time of :func:`~marinecdpr.motion.bem.hull_bem` (arithmetic only: the
    panels from :func:`~marinecdpr.motion.bem.bem_panels`, dense matrices of every panel
    pair, factored once per frequency)."""
    from marinecdpr.motion.bem import bem_panels

    n = bem_panels(shape=shape, length_m=length_m, beam_m=beam_m, draught_m=draught_m, panel_m=panel_m)
    return bem_size(n, frequencies=frequencies, headings=headings)


def bem_size(panels: int, *, frequencies: int, headings: int) -> BemSize:
    """The memory and time of a BEM of ``panels`` panels (dense matrices of every panel pair,
    factored once per frequency)."""
    n = int(panels)
    pairs = float(n) * float(n)
    per_frequency = BEM_PAIR_S * pairs + BEM_LU_S * pairs * n + BEM_SOLVE_S * pairs * (6 + headings)
    return BemSize(panels=n, frequencies=int(frequencies), headings=int(headings),
                   memory_bytes=BASE_BYTES + BEM_MATRIX_BYTES * pairs,
                   seconds=frequencies * per_frequency)


def _duration(s: float) -> str:
    """``40 s``, ``12 min``, ``3.5 h``, ``2e+05 days``."""
    if s < 120:
        return f"{s:.0f} s"
    if s < 7200:
        return f"{s / 60:.0f} min"
    if s < 4 * 86400:
        return f"{s / 3600:.1f} h"
    return f"{s / 86400:.3g} days"


def check_bem_size(*, memory_bytes: int | None = None, max_seconds: float = MAX_BEM_S, **hull) -> BemSize:
    """Refuse a BEM run that would not fit in memory or would take more than ``max_seconds``.

    Parameters
    ----------
    memory_bytes : int, optional
        The machine's memory (default :func:`machine_memory_bytes`); a run may use
        :data:`MEMORY_FRACTION` of it.
    max_seconds : float
        The longest run started (default :data:`MAX_BEM_S`).
    **hull
        As :func:`estimate_bem`.

    Returns
    -------
    BemSize
        The estimate, when the run fits.

    Raises
    ------
    ScenarioError
        One line: the panels, the estimated memory or time and what to change (a larger
        ``--panel``, fewer frequencies).
    """
    if "panels" in hull:  # a mesh's: its panels counted
        size = bem_size(hull["panels"], frequencies=hull["frequencies"], headings=hull["headings"])
        what = f"a BEM of {_count(size.panels)} panels ({hull.get('what', 'a mesh')})"
        coarser = "a coarser mesh"
    else:
        size = estimate_bem(**hull)
        what = (f"a BEM of {_count(size.panels)} panels ({hull['shape']} hull of {hull['length_m']:g} x "
                f"{hull['beam_m']:g} x {hull['draught_m']:g} m at {hull['panel_m']:g} m panels)")
        coarser = "a larger --panel"
    total = machine_memory_bytes() if memory_bytes is None else int(memory_bytes)
    if size.memory_bytes > MEMORY_FRACTION * total:
        raise ScenarioError(f"{what} would need about {human_bytes(size.memory_bytes)} in memory (this machine: "
                            f"{_gib(total)}, a run may use {MEMORY_FRACTION:.0%}); use {coarser}")
    if size.seconds > max_seconds:
        raise ScenarioError(f"{what} at {size.frequencies} frequencies and {size.headings} heading"
                            f"{'s' if size.headings != 1 else ''} would take about {_duration(size.seconds)}, "
                            f"more than the {_duration(max_seconds)} a run may take; use {coarser} or "
                            "fewer --omega frequencies")
    return size


# ------------------------------------------------------------------ marinecdpr latency
LATENCY_CALL_BYTES = 3 * F8
"""Memory per timed call: its cycle count and its two times (compiled, from Python)."""
MAX_LATENCY_CALLS = 10**7
"""Most steps ``marinecdpr latency`` times each way: from Python a step took 4.9 us (p50,
``paper``, the 2-core CI machine, loaded) and more on larger robots, so ten million are
minutes; the percentiles settle long before."""


def check_latency_calls(calls: int, *, memory_bytes: int | None = None) -> None:
    """Refuse a latency measurement of more than :data:`MAX_LATENCY_CALLS` calls, or one
    whose per-call records would not fit in memory (ScenarioError, one line naming
    ``--calls``; ValueError-compatible)."""
    if calls < 1:
        raise ScenarioError(f"--calls {calls}: expected at least 1 call")
    if calls > MAX_LATENCY_CALLS:
        raise ScenarioError(f"--calls {_count(calls)}: more than the {_count(MAX_LATENCY_CALLS)} calls a measurement "
                            "may take (a step takes microseconds from Python, so that is minutes; the percentiles "
                            "settle within 10^5 calls)")
    total = machine_memory_bytes() if memory_bytes is None else int(memory_bytes)
    need = BASE_BYTES + LATENCY_CALL_BYTES * calls
    if need > MEMORY_FRACTION * total:
        raise ScenarioError(f"--calls {_count(calls)}: timing them would need about {human_bytes(need)} in memory "
                            f"(this machine: {_gib(total)}, a run may use {MEMORY_FRACTION:.0%}); use fewer")
