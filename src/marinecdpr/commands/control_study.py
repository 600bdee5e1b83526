"""``control-study``: what the ship-motion sensor's latency costs in tracking and tension
margin, with the ship's motion predicted or not and the pose from a pose sensor or the
winches' encoders; and the ship-motion predictor's error against the horizon.

:class:`ControlStudySpec` holds the options (the one source of their defaults),
:func:`estimate` checks them against the scenario and sizes the runs, :func:`run` flies
them (:class:`ControlStudyResult`)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable

from pydantic import field_validator

from marinecdpr.commands.base import BadValue, Estimate, Spec, SpecError, figures_field, positive
from marinecdpr.scenario.fields import POSE_SOURCES, PREDICTIONS

if TYPE_CHECKING:
    from marinecdpr.scenario.schema import Scenario

__all__ = ["ControlStudySpec", "ControlStudyEstimate", "ControlStudyResult", "estimate", "run", "PLANTS"]

PLANTS = ("own", "mujoco")


def _names(v: Any, allowed: tuple[str, ...]) -> tuple[str, ...]:
    given = tuple(x.strip() for x in (v.split(",") if isinstance(v, str) else v))
    bad = [x for x in given if x not in allowed]
    if bad:
        raise BadValue(bad[0], f"expected one of {', '.join(allowed)}")
    return given


class ControlStudySpec(Spec):
    """The options of a control study.

    Attributes
    ----------
    latencies : tuple of float
        Motion sensor latencies, ms (``"0,10,20"`` is taken too), each >= 0.
    predictions : tuple of {"none", "kinematic", "ar"}
    pose_from : tuple of {"sensor", "encoders"}
        Pose sources: a pose sensor, or forward kinematics of the winches' encoders.
    rate : float
        The motion sensor's samples per second, Hz.
    encoder_resolution : float, optional
        The encoders' length step, m (default: the scenario's).
    duration : float
        Each run's length, s.
    settle : float, optional
        Errors count from this time on, s (default: the predictor's warm-up and a second).
    plant : {"own", "mujoco"}
    figures : bool
        Draw ``control_study.png`` (default: the defaults table's ``"report.figures"``,
        :mod:`marinecdpr.defaults`; True as shipped).
    """

    latencies: tuple[float, ...] = (0.0, 10.0, 20.0, 50.0, 100.0)
    predictions: tuple[str, ...] = PREDICTIONS
    pose_from: tuple[str, ...] = POSE_SOURCES
    rate: float = 100.0
    encoder_resolution: float | None = None
    duration: float = 60.0
    settle: float | None = None
    plant: str = "own"
    figures: bool = figures_field()

    @field_validator("latencies", mode="before")
    @classmethod
    def _latencies(cls, v):
        try:
            ms = tuple(float(x) for x in (v.split(",") if isinstance(v, str) else v))
        except (TypeError, ValueError):
            raise ValueError("expected numbers of ms separated by commas") from None
        if any(not (x >= 0.0 and math.isfinite(x)) for x in ms) or not ms:
            raise ValueError("latencies must be >= 0 ms")
        return ms

    @field_validator("predictions", mode="before")
    @classmethod
    def _predictions(cls, v):
        return _names(v, PREDICTIONS)

    @field_validator("pose_from", mode="before")
    @classmethod
    def _pose_from(cls, v):
        return _names(v, POSE_SOURCES)

    @field_validator("plant", mode="before")
    @classmethod
    def _plant(cls, v):
        return _names([v], PLANTS)[0]

    @field_validator("rate", "duration")
    @classmethod
    def _positive(cls, v):
        return positive(v)

    @field_validator("settle")
    @classmethod
    def _settle(cls, v):
        return positive(v, zero_ok=True)

    @property
    def n_runs(self) -> int:
        """Runs flown: every latency with every prediction and pose source."""
        return len(self.latencies) * len(self.predictions) * len(self.pose_from)


@dataclass(frozen=True)
class ControlStudyEstimate(Estimate):
    """:class:`~marinecdpr.commands.base.Estimate` and what the runs will fly: ``flown``, the
    scenario with the spec's encoders; ``settle``, s (the spec's, or the predictor's warm-up
    and a second)."""

    flown: Any = None
    settle: float = 0.0


def estimate(spec: ControlStudySpec, scenario: Scenario) -> ControlStudyEstimate:
    """The spec against the scenario (the encoders' step, ``duration`` beyond ``settle``, the
    motion sensor's rate and latencies) and the runs' size, before any work.

    Raises
    ------
    SpecError
        An option the scenario cannot take, naming it; or runs the machine cannot hold or
        finish (on ``duration``).
    """
    from marinecdpr.errors import ScenarioError
    from marinecdpr.planning.budget import check_run_size

    sc = scenario
    if spec.encoder_resolution is not None:
        try:
            sc = sc.with_updates("simulation.sensors", encoder_resolution_m=spec.encoder_resolution)
        except ScenarioError as exc:
            raise SpecError("encoder_resolution", spec.encoder_resolution, str(exc)) from None
    settle = sc.simulation.mru.ar_warmup_s + 1.0 if spec.settle is None else spec.settle
    if spec.duration <= settle:
        raise SpecError("duration", spec.duration, f"must be longer than --settle ({settle:g} s; default the "
                        "predictor's warm-up and a second)")
    try:  # the MRU's settings as the runs will set them
        sc.with_updates("simulation.mru", rate_hz=spec.rate, latency_s=max(spec.latencies) / 1e3)
    except ScenarioError as exc:
        said = ",".join(f"{x:g}" for x in spec.latencies)
        raise SpecError("rate", f"{spec.rate:g} / --latencies {said}",
                        f"{exc.detail} ({exc.key})" if exc.key else exc.detail) from None
    try:
        size = check_run_size(sc.with_changes(time={"step_s": sc.time.step_s, "duration_s": spec.duration}),
                              "simulate", repeat=spec.n_runs)
    except ScenarioError as exc:
        n = spec.n_runs
        raise SpecError("duration", f"{spec.duration:g} ({n} run{'s' if n != 1 else ''})", exc.detail) from None
    return ControlStudyEstimate(scenario=sc.name, size=size, flown=sc, settle=settle)


@dataclass(frozen=True)
class ControlStudyResult:
    """A control study's runs (:class:`~marinecdpr.studies.control.ControlStudy`) and the
    ship-motion predictor's error against the horizon, with the spec and the settle time
    they were judged from."""

    spec: ControlStudySpec
    settle: float
    study: Any
    prediction: Any

    def write(self, folder: str | Path) -> tuple[dict, list[Path]]:
        """``control_study.csv``, ``prediction.csv``, ``summary.json``, ``control_study.png`` (with
        the spec's ``figures``) (:func:`~marinecdpr.report.writers.write_control_study`): the
        summary and the paths."""
        from marinecdpr.report.writers import write_control_study

        folder = Path(folder)
        folder.mkdir(parents=True, exist_ok=True)  # as the other results' write
        return write_control_study(self.study, self.prediction, folder, figures=self.spec.figures)


def run(spec: ControlStudySpec, scenario: Scenario, *, estimated: ControlStudyEstimate | None = None,
        progress: Callable[[int, int], None] | None = None) -> ControlStudyResult:
    """Every run of the spec (:func:`~marinecdpr.studies.control.control_study`) and the
    predictor's error (:func:`~marinecdpr.studies.control.ship_prediction_error`), the spec
    checked against the scenario first (:func:`estimate`).

    Parameters
    ----------
    estimated : ControlStudyEstimate, optional
        :func:`estimate`'s of this spec and scenario, where the caller has it: not made again.
    progress : callable(done, total), optional
        Runs flown so far.
    """
    from marinecdpr.studies.control import control_study, ship_prediction_error

    est = estimate(spec, scenario) if estimated is None else estimated
    sc = est.flown
    study = control_study(sc, latencies_s=[x / 1e3 for x in spec.latencies], predictions=list(spec.predictions),
                          pose_from=list(spec.pose_from), rate_hz=spec.rate, duration_s=spec.duration,
                          settle_s=est.settle, plant=spec.plant, progress=progress)
    prediction = ship_prediction_error(sc, rate_hz=spec.rate, duration_s=spec.duration, settle_s=est.settle)
    return ControlStudyResult(spec=spec, settle=est.settle, study=study, prediction=prediction)
