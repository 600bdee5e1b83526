"""The ``scenarios`` command: list the built-in scenarios and design studies, each with its description."""

from __future__ import annotations

from marinecdpr.cli.common import console, plain
from marinecdpr.scenario.loading import builtin_scenarios, load_scenario


def scenarios() -> None:
    """List the built-in scenarios and design studies, each with its description."""
    from marinecdpr.studies.design import builtin_studies, load_design, study_path

    names = builtin_scenarios()
    width = max(len(n) for n in names)
    for name in names:
        console.print(plain(f"{name:<{width}}  {load_scenario(name).description}"), highlight=False,
                      soft_wrap=True)
    for name in builtin_studies():  # after the scenarios, not led by a name: a script that takes each
        # line's first word for a scenario meets no study
        console.print(plain(f"built-in design study {name} (marinecdpr design {name}): "
                             f"{load_design(study_path(name))[0].description}"), highlight=False, soft_wrap=True)
