"""The ``scenarios`` command: list the built-in scenarios and design studies, each with its description
(:mod:`marinecdpr.commands.scenarios`)."""

from __future__ import annotations

from marinecdpr.cli.common import console, plain
from marinecdpr.commands.scenarios import ScenariosSpec


def scenarios() -> None:
    """List the built-in scenarios and design studies, each with its description."""
    from marinecdpr.commands import scenarios as command

    result = command.run(ScenariosSpec())
    width = max(len(n) for n, _ in result.scenarios)
    for name, description in result.scenarios:
        console.print(plain(f"{name:<{width}}  {description}"), highlight=False, soft_wrap=True)
    for name, description in result.studies:  # after the scenarios, not led by a name: a script that takes
        # each line's first word for a scenario meets no study
        console.print(plain(f"built-in design study {name} (marinecdpr design {name}): {description}"),
                      highlight=False, soft_wrap=True)
