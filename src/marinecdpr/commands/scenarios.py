"""``scenarios``: the built-in scenarios and design studies, each with its description.

:class:`ScenariosSpec` holds the options (none), :func:`run` reads the list
(:class:`ScenariosResult`); there is nothing to estimate and no file to write."""

from __future__ import annotations

from dataclasses import dataclass

from marinecdpr.commands.base import Spec

__all__ = ["ScenariosSpec", "ScenariosResult", "run"]


class ScenariosSpec(Spec):
    """The options of the list: none."""


@dataclass(frozen=True)
class ScenariosResult:
    """The built-ins: ``scenarios`` and ``studies``, each (name, description), by name."""

    scenarios: tuple[tuple[str, str], ...]
    studies: tuple[tuple[str, str], ...]

    def summary(self) -> dict:
        """``{"scenarios": {name: description}, "studies": {name: description}}``."""
        return {"scenarios": dict(self.scenarios), "studies": dict(self.studies)}


def run(spec: ScenariosSpec) -> ScenariosResult:
    """Each built-in scenario (:func:`~marinecdpr.scenario.loading.builtin_scenarios`) and
    design study (:func:`~marinecdpr.studies.design.builtin_studies`), read for its description."""
    from marinecdpr.scenario.loading import builtin_scenarios, load_scenario
    from marinecdpr.studies.design import builtin_studies, load_design, study_path

    return ScenariosResult(
        scenarios=tuple((name, load_scenario(name).description) for name in builtin_scenarios()),
        studies=tuple((name, load_design(study_path(name))[0].description) for name in builtin_studies()))
