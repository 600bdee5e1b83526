"""The exceptions marinecdpr raises for a user's mistake or an impossible request.

Each subclasses a built-in exception so callers may catch either. The message is
one line that names what is wrong and where (file, key, time step).
"""

from __future__ import annotations

__all__ = ["MarineCDPRError", "ScenarioError", "InfeasibleError", "SimulationDivergedError", "OutputError"]


class MarineCDPRError(Exception):
    """Base class of every error marinecdpr raises on purpose."""


class ScenarioError(MarineCDPRError, ValueError):
    """A scenario (file or object) is malformed or physically impossible.

    Parameters
    ----------
    message : str
        What is wrong and what was expected.
    source : str, optional
        The file or built-in name the scenario came from.
    key : str, optional
        Dotted key of the offending entry, e.g. ``robot.cables[2].tension_max_N``
        (array entries counted from 1, like the cables).
    """

    def __init__(self, message: str, *, source: str | None = None, key: str | None = None):
        self.source = source
        self.key = key
        self.detail = message
        where = ": ".join(s for s in (source, key) if s)
        super().__init__(f"{where}: {message}" if where else message)


class InfeasibleError(MarineCDPRError, ValueError):
    """The cables cannot hold the platform: no tensions within limits give the wrench."""


class SimulationDivergedError(MarineCDPRError, ArithmeticError):
    """A simulated run left its plan by far or produced a non-finite state."""


class OutputError(MarineCDPRError, OSError):
    """An output folder cannot be created or written."""
