"""What every command's contract shares: the specification's base (:class:`Spec`), the one
error a bad option raises (:class:`SpecError`), the run's estimate (:class:`Estimate`), the
scenario's time from a spec (:func:`with_time`) and the checks several specs share."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from pydantic import BaseModel, ConfigDict, Field, ValidationError

from marinecdpr.errors import MarineCDPRError

if TYPE_CHECKING:  # the command line builds its options from the specs: nothing heavy at import
    from marinecdpr.planning.budget import RunSize
    from marinecdpr.scenario.schema import Scenario

__all__ = ["Spec", "SpecError", "BadValue", "Estimate", "with_time", "positive", "finite", "grid", "headings", "PLANTS",
           "plant", "figures_field"]


class SpecError(MarineCDPRError, ValueError):
    """A command's option is wrong. One line, ``"{field} {value}: {what}"``.

    Attributes
    ----------
    field : str
        The specification's field (the command line's ``--field`` with ``_`` as ``-``).
    value : str
        The value as given.
    detail : str
        What is wrong and what was expected.
    """

    def __init__(self, field: str, value: object, detail: str):
        self.field, self.value, self.detail = field, _said(value), detail
        super().__init__(f"{field} {self.value}: {detail}")

    @property
    def flag(self) -> str:
        """The command line's option for :attr:`field`."""
        return "--" + self.field.replace("_", "-")


def _said(value: object) -> str:
    """A value as the message gives it: a float as %g (5, not 5.0), else as given."""
    return f"{value:g}" if isinstance(value, float) else str(value)


class BadValue(ValueError):
    """A validator's error about a part of its field's value (``--predictions none,magic``
    names ``magic``): ``value`` is what the message shows."""

    def __init__(self, value: object, message: str):
        self.value = value
        super().__init__(message)


class Spec(BaseModel):
    """A command's options: frozen, unknown fields refused, each validator's message one
    line. Build one with keywords (``WorkspaceSpec(points=(12, 8))``); a bad value raises
    :class:`SpecError` naming the first field at fault. A rule on options that go together
    (a ``model_validator(mode="after")``) raises :class:`SpecError` itself, naming the field
    the user should change (``SpecError("hull_area", 5e3, "cannot go with --surface")``)."""

    model_config = ConfigDict(frozen=True, extra="forbid", arbitrary_types_allowed=True)

    def __init__(self, **options: Any) -> None:
        try:
            super().__init__(**options)
        except ValidationError as exc:
            err = exc.errors()[0]
            cause = (err.get("ctx") or {}).get("error")
            if isinstance(cause, SpecError):  # a rule on options that go together names its own field
                raise cause from None
            field = str(err["loc"][0]) if err["loc"] else "options"
            message = err["msg"].removeprefix("Value error, ")
            if err["type"] == "extra_forbidden":
                message = f"no such option of {type(self).__name__}"
            value = cause.value if isinstance(cause, BadValue) else options.get(field, err.get("input"))
            if err["type"] == "missing":  # a field without a default, not given
                value, message = "not given", "the option is required"
            raise SpecError(field, value, message[:1].lower() + message[1:]) from None

    @classmethod
    def default(cls, field: str) -> Any:
        """A field's default (the command line shows and uses the same); one read from the
        library's defaults table (:mod:`marinecdpr.defaults`) as the table holds it now."""
        return cls.model_fields[field].get_default(call_default_factory=True)


def figures_field() -> Any:
    """A spec's ``figures`` field (``figures: bool = figures_field()``): draw the command's
    figures (its PNG files and the report's images), or not (every other file the same byte
    for byte; the report says the figures were not drawn). Its default is the defaults
    table's ``"report.figures"`` (:mod:`marinecdpr.defaults`, True as shipped), read when
    the spec is made."""
    from functools import partial

    from marinecdpr.defaults import get

    return Field(default_factory=partial(get, "report.figures"))


def positive(value: float | None, *, zero_ok: bool = False) -> float | None:
    """A finite positive number (non-negative with ``zero_ok``), or None; else ValueError
    with the command line's words."""
    if value is None:
        return None
    if not math.isfinite(value):
        raise ValueError("expected a finite number")
    if value < 0 or (value == 0 and not zero_ok):
        raise ValueError(f"expected a {'non-negative' if zero_ok else 'positive'} number")
    return value


PLANTS = ("mujoco", "own")
"""The virtual prototype's plants."""


def plant(value: str | None) -> str | None:
    """A plant's name (:data:`PLANTS`), or None (the scenario's); else ValueError with the
    command line's words."""
    if value is not None and value not in PLANTS:
        raise ValueError(f"expected {' or '.join(PLANTS)}")
    return value


def finite(value: float | None) -> float | None:
    """A finite number, or None; else ValueError."""
    if value is not None and not math.isfinite(value):
        raise ValueError("expected a finite number")
    return value


def with_time(spec: Spec, scenario: Scenario) -> Scenario:
    """The scenario with a spec's ``duration`` and ``step`` (s; fields a spec that changes the
    scenario's time declares) where given."""
    if spec.duration is None and spec.step is None:
        return scenario
    return scenario.with_changes(time={"step_s": scenario.time.step_s if spec.step is None else spec.step,
                                       "duration_s": scenario.time.duration_s if spec.duration is None
                                       else spec.duration})


@dataclass(frozen=True)
class Estimate:
    """What a run will take, known before it starts.

    Attributes
    ----------
    scenario : str
        The scenario's name.
    size : RunSize
        Steps, records, memory (:class:`~marinecdpr.planning.budget.RunSize`).
    grid : tuple of int, optional
        A map's points along its two axes.
    """

    scenario: str
    size: RunSize
    grid: tuple[int, int] | None = None

    def describe(self) -> str:
        """One line: ``"size: NAME: ..."``, as the command line prints it before the work."""
        from marinecdpr.planning.budget import describe_run

        return f"size: {self.scenario}: {describe_run(self.size, self.grid)}"


def grid(value: str | tuple | list, *, example: str = "30x20") -> tuple[int, int]:
    """A grid's two positive point counts from ``"30x20"`` or two numbers; ValueError with
    the command line's words otherwise (``example``: the option's own)."""
    try:
        n = tuple(int(k) for k in (value.lower().split("x") if isinstance(value, str) else value))
    except (TypeError, ValueError):
        n = ()
    if len(n) != 2 or min(n) <= 0:
        raise ValueError(f"expected two positive integers like {example}")
    return n


def headings(value: str | tuple | list, *, example: str = "180,150") -> tuple[float, ...]:
    """Wave headings, deg, from ``"180,150"`` or numbers: each finite, within -360 to 360 deg,
    none given twice (headings are taken modulo 360 deg: 0 and 360 are one). ValueError with
    the command line's words otherwise; ``example`` is the command's own default."""
    try:
        heads = tuple(float(h) for h in (value.split(",") if isinstance(value, str) else value))
    except (TypeError, ValueError):
        raise ValueError(f"expected numbers separated by commas, e.g. {example}") from None
    if not heads or not all(math.isfinite(h) and -360.0 <= h <= 360.0 for h in heads):
        raise ValueError("expected finite headings between -360 and 360 deg")
    if len({h % 360.0 for h in heads}) < len(heads):
        raise ValueError("a heading is given twice (headings are taken modulo 360 deg)")
    return heads
