"""The library's defaults: one table read by the library and the command line.

A few choices have a default that a user (or a test suite) may want to change once for
every call rather than in each one, like python-control's ``control.config.defaults``.
They live in one table, :data:`defaults`, keyed ``"<package>.<what>"``; the commands' specs
read it when a spec is made (a field's default), and the command line takes the spec's
default, so both follow the table. Change it with :func:`set_defaults` (validated: a wrong
key or a value of the wrong type is refused), undo with :func:`reset_defaults`, or for a
block with :func:`defaults_set`.

===================  =======  ==========================================================
key                  shipped  meaning
===================  =======  ==========================================================
``report.figures``   True     The commands draw their figures (PNG files, and the
                              report's images); False: every other file is written, the
                              same byte for byte, and the report says the figures were
                              not drawn (``--figures/--no-figures``, a spec's ``figures``).
===================  =======  ==========================================================

Examples
--------
>>> from marinecdpr import defaults
>>> defaults.set_defaults("report", figures=False)     # no figures from now on
>>> defaults.get("report.figures")
False
>>> defaults.reset_defaults()
>>> with defaults.defaults_set({"report.figures": False}):
...     pass                                           # no figures within the block

This module is the package's lowest layer: it imports nothing of the package.
"""

from __future__ import annotations

from contextlib import contextmanager
from typing import Any, Iterator, Mapping

__all__ = ["SHIPPED", "defaults", "get", "set_defaults", "reset_defaults", "defaults_set", "DefaultsError"]

SHIPPED: Mapping[str, Any] = {
    "report.figures": True,
}
"""Each key's default as shipped (the table's values after :func:`reset_defaults`)."""

defaults: dict[str, Any] = dict(SHIPPED)
"""The table in force: read it (or :func:`get` a key); change it with :func:`set_defaults`
(which checks what it is given), not by assigning to it."""


class DefaultsError(ValueError, KeyError):
    """A key the table does not hold, or a value of the wrong type for its key: one line
    naming both (``str(err)`` is the line itself, not a KeyError's quoted repr)."""

    def __str__(self) -> str:
        return str(self.args[0]) if self.args else ""


def _checked(key: str, value: Any) -> Any:
    """``value`` for ``key``, or :class:`DefaultsError` naming what is wrong."""
    if key not in SHIPPED:
        raise DefaultsError(f"marinecdpr defaults: no key {key!r}; the keys are {', '.join(sorted(SHIPPED))}")
    kind = type(SHIPPED[key])
    if type(value) is not kind:  # a bool is a bool (not 0 or 1, nor "no")
        raise DefaultsError(f"marinecdpr defaults: {key} = {value!r}: expected {kind.__name__}")
    return value


def get(key: str) -> Any:
    """The value in force for ``key`` (:class:`DefaultsError` for a key the table lacks)."""
    if key not in SHIPPED:
        _checked(key, None)
    return defaults[key]


def set_defaults(module: str, **keywords: Any) -> None:
    """Set defaults in the table, each checked first (nothing is set if one is wrong).

    Parameters
    ----------
    module : str
        The keys' first part: ``set_defaults("report", figures=False)`` sets
        ``"report.figures"``.
    **keywords
        The keys (after ``module``) and their values.

    Raises
    ------
    DefaultsError
        A key the table does not hold, or a value of the wrong type: one line naming it.
    """
    _update({f"{module}.{k}": v for k, v in keywords.items()})


def _update(values: Mapping[str, Any]) -> None:
    """Whole keys' values into the table, all checked before any is set."""
    defaults.update({k: _checked(k, v) for k, v in values.items()})


def reset_defaults() -> None:
    """Every key back to its shipped value (:data:`SHIPPED`)."""
    defaults.clear()
    defaults.update(SHIPPED)


@contextmanager
def defaults_set(values: Mapping[str, Any]) -> Iterator[None]:
    """A block with ``values`` (whole keys: ``{"report.figures": False}``) in force; the
    table as it was afterwards, whatever happens in the block.

    Raises
    ------
    DefaultsError
        A wrong key or value, before the block runs.
    """
    before = dict(defaults)
    _update(values)
    try:
        yield
    finally:
        defaults.clear()
        defaults.update(before)
