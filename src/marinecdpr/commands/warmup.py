"""``warmup``: compile the virtual prototype for some scenarios now, once (cached on disk for
every later run), so that a demonstration, a sweep's workers or a timed run start at once.

:class:`WarmupSpec` holds the options, :func:`estimate` lists the runs that will be flown
(a few steps each, open and closed loop on each plant), :func:`run` flies them
(:class:`WarmupResult`). Unlike the other commands, these take a sequence of scenarios (the
command's default: every built-in, :func:`~marinecdpr.scenario.loading.builtin_scenarios`).
The command writes no file but the compiled cache."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Callable, Sequence

from pydantic import field_validator

from marinecdpr.commands.base import PLANTS, Spec, plant

if TYPE_CHECKING:
    from marinecdpr.scenario.schema import Scenario

__all__ = ["WarmupSpec", "WarmupEstimate", "WarmupResult", "estimate", "run", "PLANTS"]


class WarmupSpec(Spec):
    """The options of a warm-up.

    Attributes
    ----------
    plant : {"mujoco", "own"}, optional
        Compile for this plant (default: each scenario's ``simulation.plant``). MuJoCo is
        left out for a scenario of catenary cables, which only the own plant flies.
    """

    plant: str | None = None

    @field_validator("plant")
    @classmethod
    def _plant(cls, v):
        return plant(v)


@dataclass(frozen=True)
class WarmupEstimate:
    """The runs a warm-up will fly, in order.

    Attributes
    ----------
    scenarios : tuple of str
        The scenarios' names.
    runs : tuple of (str, str, str)
        (scenario, plant, run) each, run ``open_loop`` or ``closed_loop``
        (:func:`~marinecdpr.prototype.warmup.warmup_jobs`).
    """

    scenarios: tuple[str, ...]
    runs: tuple[tuple[str, str, str], ...]

    def describe(self) -> str:
        """One line: ``"size: 2 scenarios: 4 runs of 3 steps"``."""
        from marinecdpr.prototype.warmup import WARMUP_STEPS

        n, k = len(self.scenarios), len(self.runs)
        return (f"size: {n} scenario{'s' if n != 1 else ''}: {k} run{'s' if k != 1 else ''} of "
                f"{WARMUP_STEPS} steps")


def _plants(spec: WarmupSpec) -> tuple[str, ...] | None:
    return None if spec.plant is None else (spec.plant,)


def estimate(spec: WarmupSpec, scenarios: Sequence[Scenario]) -> WarmupEstimate:
    """The runs that will be flown, before any."""
    from marinecdpr.prototype.warmup import warmup_jobs

    return WarmupEstimate(scenarios=tuple(sc.name for sc in scenarios),
                          runs=tuple((sc.name, plant, r) for sc, plant, r in warmup_jobs(scenarios, plants=_plants(spec))))


@dataclass(frozen=True)
class WarmupResult:
    """What a warm-up did (:class:`~marinecdpr.prototype.warmup.WarmUp`: each run flown and
    its seconds, compiling or loading from the cache; the cache's folder), with the spec and
    the scenarios' names."""

    spec: WarmupSpec
    scenarios: tuple[str, ...]
    warm: Any

    def summary(self) -> dict:
        """``scenarios`` (names), ``runs`` (each ``scenario``, ``plant``, ``run`` and ``seconds``),
        ``seconds`` (the whole, s) and ``cache_dir``."""
        return {"scenarios": list(self.scenarios),
                "runs": [{"scenario": sc, "plant": plant, "run": r, "seconds": s} for sc, plant, r, s in self.warm.runs],
                "seconds": self.warm.seconds, "cache_dir": self.warm.cache_dir}


def run(spec: WarmupSpec, scenarios: Sequence[Scenario], *, estimated: WarmupEstimate | None = None,
        progress: Callable[[int, int, str], None] | None = None) -> WarmupResult:
    """Fly a few steps of each scenario, open and closed loop, on its plant (or the spec's),
    compiling what is not cached yet (:func:`~marinecdpr.prototype.warmup.warm_up`).

    Parameters
    ----------
    estimated : WarmupEstimate, optional
        :func:`estimate`'s, where the caller has it (nothing in it is needed again).
    progress : callable(done, total, what), optional
        Called before each run (``what``: ``"paper: mujoco open loop"``) and at the end
        (``done == total``, ``"done"``).

    Raises
    ------
    ScenarioError, SimulationDivergedError
    """
    from marinecdpr.prototype.warmup import warm_up

    warm = warm_up(list(scenarios), plants=_plants(spec), progress=progress)
    return WarmupResult(spec=spec, scenarios=tuple(sc.name for sc in scenarios), warm=warm)
