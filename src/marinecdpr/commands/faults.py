"""``faults``: what each single fault does to the robot at the job's hardest moments.

:class:`FaultsSpec` holds the options (the one source of their defaults), :func:`estimate`
checks them against the scenario (the cables, the fault kinds its winches can have, the
times within the record, the sea state) and sizes the runs, :func:`run` plans the job once
in each sea state and flies every fault closed loop (:func:`~marinecdpr.studies.faults.fault_study`),
:class:`FaultsResult` writes ``faults.csv``, ``summary.json``, ``faults.png`` and
``report.html``."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable

from pydantic import field_validator, model_validator

from marinecdpr.commands.base import BadValue, Estimate, Spec, SpecError, figures_field, finite, plant, positive
from marinecdpr.scenario.faults import CABLELESS_FAULTS, FAULT_KINDS, SENSOR_MODES

if TYPE_CHECKING:
    from marinecdpr.scenario.schema import Scenario

__all__ = ["FaultsSpec", "FaultsEstimate", "FaultsResult", "estimate", "run", "KINDS"]

KINDS = {"snap": "cable_snap", "brake": "winch_brake", "power": "motor_power_loss", "load_cell": "load_cell",
         "encoder": "encoder", "mru": "mru", "stall": "winch_stall", "brush": "brush_contact_loss",
         "deadline": "controller_deadline"}
"""The command line's names of the fault kinds (``[[faults]]``' kind names are taken too)."""


def _kinds(v: Any) -> tuple[str, ...]:
    given = tuple(x.strip() for x in (v.split(",") if isinstance(v, str) else v))
    out = []
    for x in given:
        kind = KINDS.get(x, x)
        if kind not in FAULT_KINDS:
            raise BadValue(x, f"no such fault kind: expected {', '.join(KINDS)}")
        if kind in out:
            raise BadValue(x, "a fault kind given twice")
        out.append(kind)
    if not out:
        raise ValueError("expected at least one fault kind")
    return tuple(out)


def _numbers(v: Any, what: str) -> tuple:
    try:
        return tuple(float(x) for x in (v.split(",") if isinstance(v, str) else v))
    except (TypeError, ValueError):
        raise ValueError(f"expected {what} separated by commas") from None


class FaultsSpec(Spec):
    """The options of a faults study.

    Attributes
    ----------
    kinds : tuple of str
        The faults flown, each on every cable of ``cables`` (``mru``, ``brush``, ``deadline``:
        once): snap (a cable breaks), brake (its winch's brake holds the drum), power (its motor
        loses its power), stall (its motor stalls at its torque limit), load_cell, encoder, mru
        (the sensor fails in ``sensor_mode``; the motion reference unit is the ship's, no
        cable's), brush (the brush loses its contact with the hull), deadline (the controller
        misses its deadline for ``deadline_steps`` exchanges); ``"snap,brake"`` is taken too.
    cables : tuple of int, optional
        Which cables (from 1, as ``[[robot.cables]]`` lists them); default every cable.
    at : tuple of float, optional
        When each fault strikes, s from the job's start; default the job's hardest moments
        (the plan's highest tension and the platform's highest speed).
    after : float
        How long each run goes on after its fault, s.
    duration : float, optional
        The job's first seconds considered (the moments chosen within them), s; default the
        whole job.
    plant : {"mujoco", "own"}, optional
        Default the scenario's.
    hs, tp, heading : tuple of float, optional
        The sea states flown (m, s, deg; ``"1,2"`` is taken too), each list one value or as
        many as the longest (the i-th sea state takes the i-th of each, a single value for
        all): default the scenario's own (a sea_state base motion).
    sensor_mode : {"freeze", "drift", "dropout", "non_finite"}
        How a failing sensor fails.
    drift : float
        A drifting sensor's rate (N/s on a load cell, m/s on an encoder, m/s or rad/s on each of
        the MRU's six displacements).
    brake_delay : float, optional
        A winch fault's brake delay, s (brake: default 0; power: none, the drum runs free).
    deadline_steps : int
        For how many exchanges the controller's commands are held.
    figures : bool
        Draw ``faults.png`` and the report's image (default: the defaults table's ``"report.figures"``,
        :mod:`marinecdpr.defaults`; True as shipped).
    """

    kinds: tuple[str, ...] = ("cable_snap",)
    cables: tuple[int, ...] | None = None
    at: tuple[float, ...] | None = None
    after: float = 3.0
    duration: float | None = None
    plant: str | None = None
    hs: tuple[float, ...] | None = None
    tp: tuple[float, ...] | None = None
    heading: tuple[float, ...] | None = None
    sensor_mode: str = "dropout"
    drift: float = 10.0
    brake_delay: float | None = None
    deadline_steps: int = 50
    figures: bool = figures_field()

    @field_validator("kinds", mode="before")
    @classmethod
    def _kinds(cls, v):
        return _kinds(v)

    @field_validator("cables", mode="before")
    @classmethod
    def _cables(cls, v):
        if v is None:
            return None
        numbers = _numbers(v, "cable numbers (from 1)")
        if not numbers or any(not (x == int(x) and x >= 1) for x in numbers if math.isfinite(x)) or \
                not all(math.isfinite(x) for x in numbers):
            raise ValueError("expected cable numbers from 1, separated by commas")
        if len(set(numbers)) < len(numbers):
            raise ValueError("a cable given twice")
        return tuple(int(x) for x in numbers)

    @field_validator("at", mode="before")
    @classmethod
    def _at(cls, v):
        if v is None:
            return None
        times = _numbers(v, "times in s")
        if not times or not all(math.isfinite(x) and x >= 0 for x in times):
            raise ValueError("expected times >= 0 s, separated by commas")
        return times

    @field_validator("after", "duration")
    @classmethod
    def _positive(cls, v):
        return positive(v)

    @field_validator("hs", "tp", "heading", mode="before")
    @classmethod
    def _seas(cls, v, info):
        if v is None:
            return None
        values = _numbers([v] if isinstance(v, (int, float)) else v, "numbers")
        if not values or not all(math.isfinite(x) for x in values):
            raise ValueError("expected finite numbers separated by commas")
        if info.field_name != "heading" and min(values) <= 0:
            raise ValueError("expected positive numbers")
        return values

    @field_validator("brake_delay")
    @classmethod
    def _delay(cls, v):
        return positive(v, zero_ok=True)

    @field_validator("drift")
    @classmethod
    def _finite(cls, v):
        return finite(v)

    @field_validator("plant")
    @classmethod
    def _plant(cls, v):
        return plant(v)

    @field_validator("sensor_mode")
    @classmethod
    def _mode(cls, v):
        if v not in SENSOR_MODES:
            raise ValueError(f"expected one of {', '.join(SENSOR_MODES)}")
        return v

    @field_validator("deadline_steps")
    @classmethod
    def _steps(cls, v):
        if v < 1:
            raise ValueError("expected at least 1 exchange")
        return v

    @model_validator(mode="after")
    def _together(self):
        n = self.n_seas
        for name in ("hs", "tp", "heading"):
            given = getattr(self, name)
            if given is not None and len(given) not in (1, n):
                raise SpecError(name, ",".join(f"{x:g}" for x in given),
                                f"give one value or as many as the longest of --hs, --tp, --heading ({n})")
        if self.brake_delay is not None and not set(self.kinds) & {"winch_brake", "motor_power_loss"}:
            raise SpecError("brake_delay", self.brake_delay, "is for the winch faults (brake, power): add one to "
                            "--kinds")
        return self


    @property
    def n_seas(self) -> int:
        """Sea states given (0: the scenario's own)."""
        return max([len(v) for v in (self.hs, self.tp, self.heading) if v is not None], default=0)

    def seas(self) -> list[dict]:
        """The sea states given, each ``{"hs_m", "tp_s", "heading_deg"}`` with the keys given."""
        out = []
        for i in range(self.n_seas):
            sea = {}
            for key, v in (("hs_m", self.hs), ("tp_s", self.tp), ("heading_deg", self.heading)):
                if v is not None:
                    sea[key] = v[i] if len(v) > 1 else v[0]
            out.append(sea)
        return out


@dataclass(frozen=True)
class FaultsEstimate(Estimate):
    """:class:`~marinecdpr.commands.base.Estimate` and what will be flown, per sea state (in
    the spec's order; one, the scenario's own, where none is given): ``seas``, each
    (hs_m, tp_s, heading_deg), {} without a sea state; ``flown``, the scenario in that sea
    over the job's considered part; ``plans``, its plan; ``cases``, the faults
    (:class:`~marinecdpr.studies.faults.FaultCase`); and the ``plant``."""

    seas: tuple = ()
    flown: tuple = ()
    plans: tuple = ()
    cases: tuple = ()
    plant: str = "mujoco"

    @property
    def n_cases(self) -> int:
        """Faults flown over every sea state."""
        return sum(len(c) for c in self.cases)


def _in_sea(spec: FaultsSpec, scenario: Scenario, given: dict) -> tuple[Scenario, dict]:
    """The scenario in a sea state ``given`` (keys of its base motion) and the sea flown."""
    from marinecdpr.errors import ScenarioError

    sea = scenario.base_motion
    flags = {"hs_m": "hs", "tp_s": "tp", "heading_deg": "heading"}
    if sea.type != "sea_state":
        if given:
            flag = flags[next(iter(given))]
            raise SpecError(flag, _said(getattr(spec, flag)), f"needs a [base_motion] of type sea_state, not "
                                                              f"{sea.type}")
        return scenario, {}
    if given:
        try:
            scenario = scenario.with_changes(base_motion=sea.model_copy(update=given))
        except ScenarioError as exc:
            key = str(exc.key).rsplit(".", 1)[-1]
            flag = flags.get(key, "hs")
            raise SpecError(flag, given.get(key, _said(getattr(spec, flag))), exc.detail) from None
    b = scenario.base_motion
    return scenario, {"hs_m": b.hs_m, "tp_s": b.tp_s, "heading_deg": b.heading_deg}


def _said(values) -> str:
    return ",".join(f"{x:g}" for x in values) if values is not None else "not given"


def estimate(spec: FaultsSpec, scenario: Scenario) -> FaultsEstimate:
    """The spec against the scenario, the job planned and the moments chosen, before any flight.

    Raises
    ------
    SpecError
        A cable beyond the robot, a fault kind the scenario's winches cannot have, a time beyond
        the record (or too late to fly ``after`` past it), a sea state the scenario cannot take,
        a study too large for the machine.
    InfeasibleError
        The job's plan is not feasible.
    """
    from marinecdpr.errors import ScenarioError
    from marinecdpr.planning.budget import check_run_size
    from marinecdpr.planning.planner import plan as make_plan
    from marinecdpr.studies.faults import EARLIEST_S, FaultCase, fault_entry, hardest_moments

    m = scenario.robot.n_cables
    cables = spec.cables or tuple(range(1, m + 1))
    beyond = [c for c in cables if c > m]
    if beyond:
        raise SpecError("cables", beyond[0], f"the robot has {m} cables (1 to {m})")
    job = scenario.time.duration_s if spec.duration is None else spec.duration
    if spec.duration is not None and spec.duration > scenario.time.duration_s + 1e-9:
        raise SpecError("duration", spec.duration, f"beyond the job's {scenario.time.duration_s:g} s")
    latest = job - spec.after
    if spec.at is not None:
        for t in spec.at:
            if t > latest + 1e-9:
                raise SpecError("at", t, f"beyond the record: the job's {job:g} s less --after {spec.after:g} s "
                                         f"leaves faults up to {latest:g} s")
    elif latest < EARLIEST_S:
        raise SpecError("after", spec.after, f"leaves no moment to strike in the job's {job:g} s (a fault from "
                                             f"{EARLIEST_S:g} s on, flown --after past it)")
    in_seas = [_in_sea(spec, scenario, given) for given in (spec.seas() or [{}])]
    in_seas = [(sc.with_changes(time={"step_s": sc.time.step_s, "duration_s": job}, faults=[]), sea)
               for sc, sea in in_seas]
    first = in_seas[0][0]
    for kind in spec.kinds:  # what the scenario's prototype cannot have, in one line
        probe = fault_entry(FaultCase(kind=kind, cable=cables[0], at_s=0.0, moment="given"),
                            sensor_mode=spec.sensor_mode, drift_per_s=spec.drift, brake_delay_s=spec.brake_delay,
                            deadline_steps=spec.deadline_steps)
        try:
            first.with_changes(faults=[probe])
        except ScenarioError as exc:
            name = next((k for k, v in KINDS.items() if v == kind), kind)
            raise SpecError("kinds", name, exc.detail) from None
    plant_ = spec.plant or first.simulation.plant
    n_cases = sum(1 if k in CABLELESS_FAULTS else len(cables) for k in spec.kinds)  # those flown once
    runs = n_cases * (len(spec.at) if spec.at else 2) * len(in_seas)
    try:
        size = check_run_size(first, "simulate", repeat=max(1, runs))
    except ScenarioError as exc:
        raise SpecError("duration", job, exc.detail) from None
    plans, cases = [], []
    for sc, _ in in_seas:
        plan = make_plan(sc)
        moments = ([("given", t) for t in spec.at] if spec.at is not None
                   else hardest_moments(plan, earliest_s=EARLIEST_S, latest_s=latest))
        plans.append(plan)
        cases.append(tuple(FaultCase(kind=k, cable=None if k in CABLELESS_FAULTS else c, at_s=t, moment=label)
                           for label, t in moments for k in spec.kinds
                           for c in ((None,) if k in CABLELESS_FAULTS else cables)))
    return FaultsEstimate(scenario=first.name, size=size, seas=tuple(sea for _, sea in in_seas),
                          flown=tuple(sc for sc, _ in in_seas), plans=tuple(plans), cases=tuple(cases), plant=plant_)


@dataclass(frozen=True)
class FaultsResult:
    """A faults study (:class:`~marinecdpr.studies.faults.FaultStudy`) and the scenario flown."""

    spec: FaultsSpec
    scenario: Any
    study: Any

    def summary(self) -> dict:
        """``summary.json``'s content (:func:`~marinecdpr.report.faults.faults_summary`)."""
        from marinecdpr.report.faults import faults_summary

        return faults_summary(self.study, self.scenario)

    def write(self, folder: str | Path) -> list[Path]:
        """``faults.csv``, ``summary.json``, ``faults.png`` (with the spec's ``figures``) and
        ``report.html`` in ``folder`` (:func:`~marinecdpr.report.faults.write_faults`)."""
        from marinecdpr.report.faults import write_faults

        folder = Path(folder)
        folder.mkdir(parents=True, exist_ok=True)
        return write_faults(self.study, self.scenario, folder, figures=self.spec.figures)


def run(spec: FaultsSpec, scenario: Scenario, *, estimated: FaultsEstimate | None = None,
        progress: Callable[[int, int], None] | None = None) -> FaultsResult:
    """Every fault of the spec flown closed loop and judged, the spec checked against the
    scenario first (:func:`estimate`) where no estimate is given.

    Parameters
    ----------
    progress : callable(done, total), optional
        Faults flown so far.
    """
    from marinecdpr.studies.faults import combined, fault_study

    est = estimate(spec, scenario) if estimated is None else estimated
    total, done = est.n_cases, 0
    studies = []
    for sea, sc, plan, cases in zip(est.seas, est.flown, est.plans, est.cases):
        def step(d, _n, base=done):
            if progress is not None:
                progress(base + d, total)

        studies.append(fault_study(sc, list(cases), after_s=spec.after, plant=est.plant, plan=plan,
                                   sensor_mode=spec.sensor_mode, drift_per_s=spec.drift,
                                   brake_delay_s=spec.brake_delay, deadline_steps=spec.deadline_steps, sea=sea,
                                   progress=step))
        done += len(cases)
    return FaultsResult(spec=spec, scenario=est.flown[0], study=combined(studies))
