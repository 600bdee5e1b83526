"""``faults``: what each single fault does to the robot at the job's hardest moments.

:class:`FaultsSpec` holds the options (the one source of their defaults), :func:`estimate`
checks them against the scenario (the cables, the fault kinds its winches can have, the
times within the record, the sea state) and sizes the runs, :func:`run` plans the job once
and flies every fault closed loop (:func:`~marinecdpr.studies.faults.fault_study`),
:class:`FaultsResult` writes ``faults.csv``, ``summary.json``, ``faults.png`` and
``report.html``."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable

from pydantic import field_validator, model_validator

from marinecdpr.commands.base import PLANTS, BadValue, Estimate, Spec, SpecError, finite, plant, positive
from marinecdpr.scenario.faults import FAULT_KINDS, SENSOR_MODES

if TYPE_CHECKING:
    from marinecdpr.scenario.schema import Scenario

__all__ = ["FaultsSpec", "FaultsEstimate", "FaultsResult", "estimate", "run", "KINDS"]

KINDS = {"snap": "cable_snap", "brake": "winch_brake", "power": "motor_power_loss", "load_cell": "load_cell",
         "encoder": "encoder", "deadline": "controller_deadline"}
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
        The faults flown, each on every cable of ``cables`` (``deadline``: once): snap (a cable
        breaks), brake (its winch's brake holds the drum), power (its motor loses its power),
        load_cell, encoder (the sensor fails in ``sensor_mode``), deadline (the controller
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
    hs, tp, heading : float, optional
        The sea state flown (m, s, deg): default the scenario's own (a sea_state base motion).
    sensor_mode : {"freeze", "drift", "dropout", "non_finite"}
        How a failing sensor fails.
    drift : float
        A drifting sensor's rate (N/s on a load cell, m/s on an encoder).
    brake_delay : float, optional
        A winch fault's brake delay, s (brake: default 0; power: none, the drum runs free).
    deadline_steps : int
        For how many exchanges the controller's commands are held.
    """

    kinds: tuple[str, ...] = ("cable_snap",)
    cables: tuple[int, ...] | None = None
    at: tuple[float, ...] | None = None
    after: float = 3.0
    duration: float | None = None
    plant: str | None = None
    hs: float | None = None
    tp: float | None = None
    heading: float | None = None
    sensor_mode: str = "dropout"
    drift: float = 10.0
    brake_delay: float | None = None
    deadline_steps: int = 50

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

    @field_validator("after", "duration", "hs", "tp")
    @classmethod
    def _positive(cls, v):
        return positive(v)

    @field_validator("brake_delay")
    @classmethod
    def _delay(cls, v):
        return positive(v, zero_ok=True)

    @field_validator("heading", "drift")
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
        if self.brake_delay is not None and not set(self.kinds) & {"winch_brake", "motor_power_loss"}:
            raise SpecError("brake_delay", self.brake_delay, "is for the winch faults (brake, power): add one to "
                            "--kinds")
        return self


@dataclass(frozen=True)
class FaultsEstimate(Estimate):
    """:class:`~marinecdpr.commands.base.Estimate` and what will be flown: ``flown``, the
    scenario in the spec's sea over the job's considered part; ``plan``, its plan; ``cases``,
    the faults (:class:`~marinecdpr.studies.faults.FaultCase`); ``plant``; ``sea``: the sea
    state (hs_m, tp_s, heading_deg), {} without one."""

    flown: Any = None
    plan: Any = None
    cases: tuple = ()
    plant: str = "mujoco"
    sea: dict = None


def _sea(spec: FaultsSpec, scenario: Scenario) -> tuple[Scenario, dict]:
    given = {k: v for k, v in (("hs_m", spec.hs), ("tp_s", spec.tp), ("heading_deg", spec.heading)) if v is not None}
    sea = scenario.base_motion
    if sea.type != "sea_state":
        if given:
            flag = {"hs_m": "hs", "tp_s": "tp", "heading_deg": "heading"}[next(iter(given))]
            raise SpecError(flag, getattr(spec, flag), f"needs a [base_motion] of type sea_state, not {sea.type}")
        return scenario, {}
    from marinecdpr.errors import ScenarioError

    if given:
        try:
            scenario = scenario.with_changes(base_motion=sea.model_copy(update=given))
        except ScenarioError as exc:
            flag = {"hs_m": "hs", "tp_s": "tp", "heading_deg": "heading"}.get(str(exc.key).rsplit(".", 1)[-1], "hs")
            raise SpecError(flag, getattr(spec, flag), exc.detail) from None
    b = scenario.base_motion
    return scenario, {"hs_m": b.hs_m, "tp_s": b.tp_s, "heading_deg": b.heading_deg}


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
    sc, sea = _sea(spec, scenario)
    job = sc.time.duration_s if spec.duration is None else spec.duration
    if spec.duration is not None and spec.duration > sc.time.duration_s + 1e-9:
        raise SpecError("duration", spec.duration, f"beyond the job's {sc.time.duration_s:g} s")
    latest = job - spec.after
    if spec.at is not None:
        for t in spec.at:
            if t > latest + 1e-9:
                raise SpecError("at", t, f"beyond the record: the job's {job:g} s less --after {spec.after:g} s "
                                         f"leaves faults up to {latest:g} s")
    elif latest < EARLIEST_S:
        raise SpecError("after", spec.after, f"leaves no moment to strike in the job's {job:g} s (a fault from "
                                             f"{EARLIEST_S:g} s on, flown --after past it)")
    sc = sc.with_changes(time={"step_s": sc.time.step_s, "duration_s": job}, faults=[])
    for kind in spec.kinds:  # what the scenario's prototype cannot have, in one line
        probe = fault_entry(FaultCase(kind=kind, cable=cables[0], at_s=0.0, moment="given"),
                            sensor_mode=spec.sensor_mode, drift_per_s=spec.drift, brake_delay_s=spec.brake_delay,
                            deadline_steps=spec.deadline_steps)
        try:
            sc.with_changes(faults=[probe])
        except ScenarioError as exc:
            name = next((k for k, v in KINDS.items() if v == kind), kind)
            raise SpecError("kinds", name, exc.detail) from None
    plant_ = spec.plant or sc.simulation.plant
    n_cases = sum(1 if k == "controller_deadline" else len(cables) for k in spec.kinds)
    try:
        size = check_run_size(sc, "simulate", repeat=max(1, n_cases * (len(spec.at) if spec.at else 2)))
    except ScenarioError as exc:
        raise SpecError("duration", job, exc.detail) from None
    plan = make_plan(sc)
    moments = ([("given", t) for t in spec.at] if spec.at is not None
               else hardest_moments(plan, earliest_s=EARLIEST_S, latest_s=latest))
    cases = tuple(FaultCase(kind=k, cable=None if k == "controller_deadline" else c, at_s=t, moment=label)
                  for label, t in moments for k in spec.kinds
                  for c in ((None,) if k == "controller_deadline" else cables))
    return FaultsEstimate(scenario=sc.name, size=size, flown=sc, plan=plan, cases=cases, plant=plant_, sea=sea)


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
        """``faults.csv``, ``summary.json``, ``faults.png`` and ``report.html`` in ``folder``
        (:func:`~marinecdpr.report.faults.write_faults`)."""
        from marinecdpr.report.faults import write_faults

        folder = Path(folder)
        folder.mkdir(parents=True, exist_ok=True)
        return write_faults(self.study, self.scenario, folder)


def run(spec: FaultsSpec, scenario: Scenario, *, estimated: FaultsEstimate | None = None,
        progress: Callable[[int, int], None] | None = None) -> FaultsResult:
    """Every fault of the spec flown closed loop and judged, the spec checked against the
    scenario first (:func:`estimate`) where no estimate is given.

    Parameters
    ----------
    progress : callable(done, total), optional
        Faults flown so far.
    """
    from marinecdpr.studies.faults import fault_study

    est = estimate(spec, scenario) if estimated is None else estimated
    study = fault_study(est.flown, list(est.cases), after_s=spec.after, plant=est.plant, plan=est.plan,
                        sensor_mode=spec.sensor_mode, drift_per_s=spec.drift, brake_delay_s=spec.brake_delay,
                        deadline_steps=spec.deadline_steps, sea=est.sea, progress=progress)
    return FaultsResult(spec=spec, scenario=est.flown, study=study)

