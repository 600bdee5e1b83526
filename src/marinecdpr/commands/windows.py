"""``windows``: weather windows in a series of sea states. When an operation of a given
duration fits under the operational Hs limit (alpha times a design limit: a constant Hs, or
an operability study's limiting Hs per Tp) and, with ``wind_limit``, under an operational
limit of the mean wind (the series' ``wind_m_s``), the expected wait before it can start,
and the probability it is done within some days.

:class:`WindowsSpec` holds the options (the one source of their defaults), :func:`estimate`
reads the series and the design limit (the checks before any work), :func:`run` finds the
windows (:class:`WindowsResult`). There is no scenario: the series file (default the
package's illustrative, synthetic one) takes its place."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from pydantic import field_validator, model_validator

from marinecdpr.commands.base import Spec, figures_field, SpecError, finite, positive

if TYPE_CHECKING:
    from marinecdpr.studies.weather import SeaStateSeries, Windows

__all__ = ["WindowsSpec", "WindowsEstimate", "WindowsResult", "estimate", "run", "default_series"]


class WindowsSpec(Spec):
    """The options of a weather-window study.

    Attributes
    ----------
    duration_h : float
        The operation's duration, h (required).
    hs_limit : float, optional
        A constant design Hs limit, m.
    operability : Path, optional
        An ``operability.json``: its limiting Hs per Tp is the design limit (give this or
        ``hs_limit``, one of them).
    heading : float
        With ``operability``: the heading whose limits apply, deg.
    alpha : float
        DNV-ST-N001's alpha factor for the operation's duration and forecast, in (0, 1]
        (operational limit = alpha x design limit).
    days : tuple of float
        Say the probability of finishing within these many days (``"1,3,7"`` is taken too).
    wind_limit : float, optional
        A constant operational limit of the mean wind at 10 m, m/s (positive, finite; alpha
        does not scale it): a sample is workable when its Hs is within the Hs limit and its
        wind (the series' column ``wind_m_s``, which it then needs) within this one. None:
        the series' wind, if it has one, is read and written out, not judged.
    figures : bool
        Draw ``windows.png`` (default: the defaults table's ``"report.figures"``,
        :mod:`marinecdpr.defaults`; True as shipped).
    """

    duration_h: float
    hs_limit: float | None = None
    operability: Path | None = None
    heading: float = 180.0
    alpha: float = 1.0
    days: tuple[float, ...] = (1.0, 3.0, 7.0)
    wind_limit: float | None = None
    figures: bool = figures_field()

    @field_validator("duration_h", "hs_limit", "wind_limit")
    @classmethod
    def _positive(cls, v):
        return positive(v)

    @field_validator("heading")
    @classmethod
    def _heading(cls, v):
        return finite(v)

    @field_validator("alpha")
    @classmethod
    def _alpha(cls, v):
        if not (math.isfinite(v) and 0.0 < v <= 1.0):
            raise ValueError("expected a factor in (0, 1]")
        return v

    @field_validator("days", mode="before")
    @classmethod
    def _days(cls, v):
        try:
            days = tuple(float(d) for d in (v.split(",") if isinstance(v, str) else v))
        except (TypeError, ValueError):
            days = ()
        if not days or not all(math.isfinite(d) and d > 0 for d in days):
            raise ValueError("expected positive numbers separated by commas, e.g. 1,3,7")
        return days

    @model_validator(mode="after")
    def _one_limit(self):
        if self.hs_limit is None and self.operability is None:
            raise SpecError("hs_limit", "or --operability", "give one design limit: --hs-limit H or --operability "
                            "FILE.json")
        if self.hs_limit is not None and self.operability is not None:
            raise SpecError("hs_limit", f"{self.hs_limit:g} with --operability {self.operability}",
                            "give one design limit: --hs-limit H or --operability FILE.json, not both")
        return self

    @property
    def design_limit(self) -> str:
        """The design limit in words (``summary.json``'s ``design_limit``)."""
        if self.hs_limit is not None:
            return f"Hs {self.hs_limit:g} m"
        return f"limiting Hs per Tp of {self.operability} at {self.heading:g} deg"


def default_series() -> Path:
    """The package's illustrative, synthetic sea-state series (``time_h,hs_m,tp_s``, no wind)."""
    from importlib import resources

    return Path(str(resources.files("marinecdpr") / "data" / "sea_states_illustrative.csv"))


@dataclass(frozen=True)
class WindowsEstimate:
    """What the study reads, checked before any work (a windows study is small: no size).

    Attributes
    ----------
    series_name : str
        The series file as named in ``summary.json``.
    series : SeaStateSeries
    table : (tp (k,), hs (k,)), optional
        With ``operability``: its design Hs limit, m, per Tp, s, at the spec's heading.
    """

    series_name: str
    series: SeaStateSeries
    table: Any = None


def estimate(spec: WindowsSpec, series: str | Path | None = None) -> WindowsEstimate:
    """The series (default :func:`default_series`) and, with ``operability``, its limits at
    the spec's heading, read and checked.

    Raises
    ------
    ScenarioError
        One line naming the file: a series or an operability.json that cannot be read, or
        has no limits at the heading; a series without the column ``wind_m_s`` for a spec
        with ``wind_limit``.
    """
    from marinecdpr.errors import ScenarioError
    from marinecdpr.studies.weather import limit_from_operability, read_operability_json, read_sea_state_series

    path = Path(series) if series is not None else default_series()
    sea = read_sea_state_series(path)
    if spec.wind_limit is not None and sea.wind_m_s is None:
        raise ScenarioError(f"--wind-limit {spec.wind_limit:g} m/s needs each sample's wind: the series has no "
                            "column wind_m_s (add it: the mean wind at 10 m, m/s; or leave --wind-limit out)",
                            source=str(path))
    table = None
    if spec.operability is not None:
        if spec.operability.is_dir():
            raise ScenarioError("a folder, not a file; expected an operability.json", source=str(spec.operability))
        try:
            table = limit_from_operability(read_operability_json(spec.operability), spec.heading)
        except ScenarioError as exc:
            raise ScenarioError(exc.detail, source=str(spec.operability), key=exc.key) from None
    return WindowsEstimate(series_name=str(path), series=sea, table=table)


@dataclass(frozen=True)
class WindowsResult:
    """A weather-window study.

    Attributes
    ----------
    spec : WindowsSpec
    series_name : str
    series : SeaStateSeries
    windows : Windows
        The workable samples, the windows, each start time's wait
        (:func:`~marinecdpr.studies.weather.weather_windows`).
    """

    spec: WindowsSpec
    series_name: str
    series: SeaStateSeries
    windows: Windows

    def finish_probability(self) -> dict[float, float]:
        """{days: the probability the operation is done within them}, over the spec's ``days``."""
        return {d: self.windows.finish_probability(d) for d in self.spec.days}

    def summary(self) -> dict:
        """``summary.json``'s content (:func:`~marinecdpr.report.writers.windows_summary`)."""
        from marinecdpr.report.writers import windows_summary

        return windows_summary(self.series, self.windows, series_name=self.series_name,
                               design_limit=self.spec.design_limit, days=list(self.spec.days))

    def write(self, folder: str | Path) -> list[Path]:
        """``windows.csv``, ``summary.json``, ``windows.png`` (with the spec's ``figures``) in
        ``folder`` (:func:`~marinecdpr.report.writers.write_windows`); returns the paths."""
        from marinecdpr.report.writers import write_windows

        Path(folder).mkdir(parents=True, exist_ok=True)
        _, paths = write_windows(self.series, self.windows, Path(folder), series_name=self.series_name,
                                 design_limit=self.spec.design_limit, days=list(self.spec.days),
                                 figures=self.spec.figures)
        return paths


def run(spec: WindowsSpec, series: str | Path | None = None, *,
        estimated: WindowsEstimate | None = None) -> WindowsResult:
    """The weather windows of the series for the spec's operation
    (:func:`~marinecdpr.studies.weather.weather_windows`), the inputs read first
    (:func:`estimate`) unless ``estimated`` is given."""
    from marinecdpr.studies.weather import weather_windows

    est = estimate(spec, series) if estimated is None else estimated
    w = weather_windows(est.series, duration_h=spec.duration_h, alpha=spec.alpha, hs_limit_m=spec.hs_limit,
                        limit_table=est.table, wind_limit_m_s=spec.wind_limit)
    return WindowsResult(spec=spec, series_name=est.series_name, series=est.series, windows=w)
