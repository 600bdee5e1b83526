"""The ``warmup`` command: compile the virtual prototype for your scenarios now, once (cached for every later
    run): use it after installing or updating, before a demonstration, a sweep or a timed
    run, so that their first run starts at once (:mod:`marinecdpr.commands.warmup`)."""

from __future__ import annotations

import typer

from marinecdpr.cli.common import Plant, console, err_console, load, plain, run_errors, spec_of
from marinecdpr.commands.warmup import WarmupSpec
from marinecdpr.scenario.loading import builtin_scenarios


def warmup(
    scenarios_: list[str] = typer.Argument(None, metavar="[SCENARIO]...",
                                           help="Scenario files or built-in names (default: every built-in)."),
    plant: Plant = typer.Option(WarmupSpec.default("plant"), "--plant",
                                help="Compile for this plant (default: each scenario's)."),
) -> None:
    """Compile the virtual prototype for your scenarios now, once (cached for every later
    run): use it after installing or updating, before a demonstration, a sweep or a timed
    run, so that their first run starts at once."""
    from marinecdpr.commands import warmup as command

    spec = spec_of(WarmupSpec, plant=None if plant is None else plant.value)
    names = scenarios_ or builtin_scenarios()
    loaded = [load(name, None, None) for name in names]

    def progress(done: int, total: int, what: str) -> None:
        if done < total:
            err_console.print(f"compiling ({done + 1}/{total}) {plain(what)}...", highlight=False, soft_wrap=True)

    with run_errors(", ".join(names)):
        result = command.run(spec, loaded, progress=progress)
    warm = result.warm
    console.print(f"compiled for {len(names)} scenario{'s' if len(names) != 1 else ''} "
                  f"({len(warm.runs)} runs) in {warm.seconds:.1f} s; cached in {plain(warm.cache_dir)}",
                  highlight=False, soft_wrap=True)
