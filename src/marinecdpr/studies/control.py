"""What the motion sensor's latency and the ship-motion prediction cost in tracking
(``marinecdpr control-study``).

:func:`control_study` flies the scenario's plan closed loop on the virtual prototype for
each motion reference unit latency, each way of bringing its samples to the present
(``[simulation.mru] prediction``: none, kinematic, ar) and each pose source (a pose sensor
or the winches' encoders), and measures the tracking error and the tension margin after
the predictor's warm-up; :func:`ship_prediction_error` gives the predictor's error against
the horizon on the scenario's own ship motion.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from typing import Callable, Sequence

import numpy as np

from marinecdpr.control.controller import predictor_options
from marinecdpr.motion.basemotion import frame_ship_motion
from marinecdpr.motion.prediction import PredictionError, prediction_error
from marinecdpr.prototype.simulation import simulate
from marinecdpr.scenario.fields import POSE_SOURCES, PREDICTIONS
from marinecdpr.scenario.schema import Scenario
from marinecdpr.studies.prototype_runs import controller_verdict

__all__ = ["ControlRun", "ControlStudy", "control_study", "ship_prediction_error", "worst_moving_dof",
           "moving_dofs", "PREDICTIONS"]


@dataclass(frozen=True)
class ControlRun:
    """One closed-loop run of the study, judged from ``settle_s`` on.

    Attributes
    ----------
    latency_s : float
        The motion reference unit's latency, s.
    prediction, pose_from : str
    rms_error_m, max_error_m : float
        RMS and largest position error of the platform, m.
    max_angle_error_deg : float
        Largest orientation error, deg.
    headroom_N : float
        The smallest distance of a commanded tension below its upper limit, N.
    slack_margin_N : float
        The smallest distance of a commanded tension above its lower limit, N (0 where the
        tension method holds a cable at its lower limit).
    fallbacks : int
        Steps where the tension problem had no solution within limits (the controller
        bypassed, the plan's tensions fed forward), over the whole run.
    bypassed_share : float
        ``fallbacks`` over the run's steps, 0 to 1.
    controller_verdict : {"held", "bypassed"}
        ``bypassed`` beyond ``[simulation] max_bypassed_share``: the run's figures are the
        plan's, not the controller's
        (:func:`~marinecdpr.studies.prototype_runs.controller_verdict`).
    """

    latency_s: float
    prediction: str
    pose_from: str
    rms_error_m: float
    max_error_m: float
    max_angle_error_deg: float
    headroom_N: float
    slack_margin_N: float
    fallbacks: int
    bypassed_share: float = 0.0
    controller_verdict: str = "held"


@dataclass(frozen=True)
class ControlStudy:
    """The runs of :func:`control_study` with what they share."""

    scenario: str
    rate_hz: float
    duration_s: float
    settle_s: float
    runs: tuple[ControlRun, ...]
    max_bypassed_share: float = 0.01
    """The scenario's ``[simulation] max_bypassed_share``."""
    steps: int = 0
    """Steps of each run."""

    @property
    def bypassed(self) -> tuple[ControlRun, ...]:
        """The runs whose controller was bypassed."""
        return tuple(r for r in self.runs if r.controller_verdict == "bypassed")

    def run(self, latency_s: float, prediction: str, pose_from: str = "sensor") -> ControlRun:
        """The run with these settings (KeyError if the study has none)."""
        for r in self.runs:
            if abs(r.latency_s - latency_s) < 1e-12 and r.prediction == prediction and r.pose_from == pose_from:
                return r
        raise KeyError((latency_s, prediction, pose_from))


def control_study(
    scenario: Scenario,
    *,
    latencies_s: Sequence[float] = (0.0, 0.01, 0.02, 0.05, 0.1),
    predictions: Sequence[str] = PREDICTIONS,
    pose_from: Sequence[str] = POSE_SOURCES,
    rate_hz: float = 100.0,
    duration_s: float = 60.0,
    settle_s: float | None = None,
    plant: str = "own",
    progress: Callable[[int, int], None] | None = None,
) -> ControlStudy:
    """Closed-loop tracking and tension margin against the motion sensor's latency.

    Parameters
    ----------
    scenario : Scenario
        Its ``[simulation.mru]`` gives the unit, biases and the predictor's settings; the
        study sets the rate, the latency, the prediction and the pose source.
    latencies_s : sequence of float
        MRU latencies, s (>= 0).
    predictions : sequence of {"none", "kinematic", "ar"}
    pose_from : sequence of {"sensor", "encoders"}
        Default both, as ``control-study``'s (:class:`~marinecdpr.commands.control_study.ControlStudySpec`).
    rate_hz : float
        The MRU's samples per second.
    duration_s : float
        Each run's length, s (longer than ``settle_s``).
    settle_s : float, optional
        Errors and margins count from this time on, s (default: the predictor's warm-up,
        ``[simulation.mru] ar_warmup_s``, plus one second).
    plant : {"own", "mujoco"}
    progress : callable(done, total), optional

    Returns
    -------
    ControlStudy
    """
    mru = scenario.simulation.mru
    settle = mru.ar_warmup_s + 1.0 if settle_s is None else float(settle_s)
    if not duration_s > settle:
        raise ValueError(f"duration_s ({duration_s:g} s) must be longer than settle_s ({settle:g} s)")
    for p in predictions:
        if p not in PREDICTIONS:
            raise ValueError(f"prediction must be one of {', '.join(PREDICTIONS)}, not {p!r}")
    for s in pose_from:
        if s not in ("sensor", "encoders"):
            raise ValueError(f"pose_from must be 'sensor' or 'encoders', not {s!r}")
    base = scenario.with_changes(time={"step_s": scenario.time.step_s, "duration_s": float(duration_s)})
    lo, hi = scenario.robot.tension_min, scenario.robot.tension_max
    cases = list(itertools.product(pose_from, latencies_s, predictions))
    runs = []
    for i, (source, latency, prediction) in enumerate(cases):
        sc = (base.with_updates("simulation.mru", rate_hz=float(rate_hz), latency_s=float(latency),
                                prediction=prediction)
              .with_updates("simulation.sensors", pose_from=source))
        res = simulate(sc, run="closed_loop", plant=plant)
        judged = res.t >= settle - 1e-9
        err = res.pose_error[judged]
        pos = np.linalg.norm(err[:, :3], axis=1)
        T = res.tensions_commanded[judged]
        verdict = controller_verdict(res, sc)
        runs.append(ControlRun(
            latency_s=float(latency), prediction=prediction, pose_from=source,
            rms_error_m=float(np.sqrt(np.mean(pos * pos))), max_error_m=float(pos.max()),
            max_angle_error_deg=float(np.degrees(np.abs(err[:, 3:]).max())),
            headroom_N=float(np.min(hi - T)), slack_margin_N=float(np.min(T - lo)),
            fallbacks=res.controller_fallbacks, bypassed_share=verdict["controller_bypassed_share"],
            controller_verdict=verdict["controller_verdict"]))
        if progress is not None:
            progress(i + 1, len(cases))
    return ControlStudy(scenario=scenario.name, rate_hz=float(rate_hz), duration_s=float(duration_s),
                        settle_s=settle, runs=tuple(runs), max_bypassed_share=scenario.simulation.max_bypassed_share,
                        steps=base.time.n_steps)


def ship_prediction_error(
    scenario: Scenario,
    *,
    duration_s: float,
    settle_s: float | None = None,
    horizons_s: Sequence[float] = (0.02, 0.1, 0.5, 1.0, 2.0, 5.0),
    rate_hz: float = 100.0,
    latency_s: float = 0.0,
) -> PredictionError:
    """The ship-motion predictor's error against the horizon on the scenario's base motion
    over ``duration_s``, with ``[simulation.mru]``'s predictor settings, beside the
    kinematic extrapolation's and the held sample's
    (:func:`~marinecdpr.motion.prediction.prediction_error`), counted from ``settle_s``
    (default: the predictor's warm-up plus a second).

    Parameters
    ----------
    scenario : Scenario
    duration_s : float
        The record's length, s.
    settle_s : float, optional
        The record's first seconds left out, s.
    horizons_s : sequence of float
        Look-aheads beyond the present, s; those the record is too short to check are left
        out (all of them: the present alone, 0 s).
    rate_hz, latency_s : float
        The MRU's rate (Hz) and latency (s).
    """
    mru = scenario.simulation.mru
    settle = mru.ar_warmup_s + 1.0 if settle_s is None else float(settle_s)
    t = np.arange(0.0, duration_s + 1e-9, 0.01)
    ship = frame_ship_motion(scenario, t)
    # the horizons the record can check (a forecast from after settle_s must land in it)
    fits = [h for h in horizons_s if settle + latency_s + h < t[-1] - 0.02] or [0.0]
    return prediction_error(t, ship.eta, ship.eta_dot, ship.eta_ddot, sample_hz=rate_hz, latency_s=latency_s,
                            horizons_s=np.asarray(fits, dtype=float), discard_s=settle,
                            **predictor_options(mru))


def worst_moving_dof(prediction: PredictionError, err: np.ndarray) -> np.ndarray:
    """The worst DOF's normalised error of eta per horizon, over the DOFs that move (RMS above
    1e-6 of the largest), shape (n_h,); NaN where none was evaluated.

    Parameters
    ----------
    prediction : PredictionError
    err : ndarray, shape (n_h, 3, n_dof)
        ``prediction.predictor``, ``.taylor`` or ``.hold``.
    """
    values = np.where(moving_dofs(prediction) & np.isfinite(err[:, 0, :]), err[:, 0, :], -np.inf).max(axis=1)
    return np.where(np.isfinite(values), values, np.nan)


def moving_dofs(prediction: PredictionError) -> np.ndarray:
    """Which DOFs the record moves in (RMS of eta above 1e-6 of the largest), shape (n_dof,)."""
    rms = prediction.record_rms[0]
    return rms > 1e-6 * max(rms.max(), 1e-300)
