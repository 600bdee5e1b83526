"""``latency``: how long the controller's step takes on this machine, called from Python and
inside a compiled loop along the scenario's plan, beside one quadprog solve of the same
tension problem (where quadprog is installed).

:class:`LatencySpec` holds the options, :func:`estimate` says whether the step must first
be compiled, :func:`run` times it (:class:`LatencyResult`). The command writes no file: it
prints a table, or :meth:`LatencyResult.summary` as one JSON object."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from pydantic import field_validator

from marinecdpr.commands.base import BadValue, Spec

if TYPE_CHECKING:
    from marinecdpr.scenario.schema import Scenario

__all__ = ["LatencySpec", "LatencyEstimate", "LatencyResult", "estimate", "run"]


class LatencySpec(Spec):
    """The options of a latency measurement.

    Attributes
    ----------
    calls : int
        Steps timed each way (from Python, and in a compiled loop), 1 to
        :data:`~marinecdpr.planning.budget.MAX_LATENCY_CALLS`, and no more than memory holds
        (:func:`~marinecdpr.planning.budget.check_latency_calls`: it depends on the calls
        alone, so it is checked here, as the spec is made).
    as_json : bool
        Print :meth:`LatencyResult.summary` as one JSON object instead of a table (the command
        line's ``--json``; the field is not named ``json``, which pydantic's models keep).
    """

    calls: int = 20000
    as_json: bool = False

    @field_validator("calls")
    @classmethod
    def _calls(cls, v):
        from marinecdpr.errors import ScenarioError
        from marinecdpr.planning.budget import check_latency_calls

        try:
            check_latency_calls(v)
        except ScenarioError as exc:  # "--calls 1e+12: more than ...": the count as said, and the words
            said, _, detail = exc.detail.removeprefix("--calls ").partition(": ")
            raise BadValue(said, detail) from None
        return v


@dataclass(frozen=True)
class LatencyEstimate:
    """What timing the step will take, known before it starts.

    Attributes
    ----------
    scenario : str
    calls : int
        Steps timed each way.
    compile_s : float or None
        About how long the step and its timed loop must first be compiled, s
        (:data:`~marinecdpr.studies.latency.LATENCY_COMPILE_S`); None where they are cached.
    """

    scenario: str
    calls: int
    compile_s: float | None

    def describe(self) -> str:
        """One line: ``"size: NAME: 20,000 calls each way"``."""
        return f"size: {self.scenario}: {self.calls:,} calls each way"


def estimate(spec: LatencySpec, scenario: Scenario) -> LatencyEstimate:
    """The calls timed and whether the step must first be compiled (no work done)."""
    from marinecdpr.studies.latency import LATENCY_COMPILE_S, latency_kernels_cached

    return LatencyEstimate(scenario=scenario.name, calls=spec.calls,
                           compile_s=None if latency_kernels_cached() else LATENCY_COMPILE_S)


@dataclass(frozen=True)
class LatencyResult:
    """The controller step's times (:class:`~marinecdpr.studies.latency.Latency`: percentiles,
    microseconds), with the spec."""

    spec: LatencySpec
    latency: Any

    def summary(self) -> dict:
        """What ``--json`` prints: the scenario, method, cables, redundancy, calls and each
        percentile, us (``quadprog_p50_us`` None without quadprog)."""
        import dataclasses

        return dataclasses.asdict(self.latency)


def run(spec: LatencySpec, scenario: Scenario, *, estimated: LatencyEstimate | None = None) -> LatencyResult:
    """Time the scenario's controller step (:func:`~marinecdpr.studies.latency.controller_latency`),
    compiling it first where it is not cached.

    Parameters
    ----------
    estimated : LatencyEstimate, optional
        :func:`estimate`'s, where the caller has it (nothing in it is needed again).

    Raises
    ------
    ScenarioError, InfeasibleError
        The scenario cannot be planned for the controller's reference.
    """
    from marinecdpr.studies.latency import controller_latency

    return LatencyResult(spec=spec, latency=controller_latency(scenario, calls=spec.calls))
