"""The ``import`` command: write a scenario from a robot model of CASPR or WireX, saying what it could not carry over
(:mod:`marinecdpr.commands.import_robot`: the options' spec, the import, the file and the verdict)."""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer

from marinecdpr.cli.common import console, err_console, fail, fail_spec, plain, spec_of, styled, warn_scale
from marinecdpr.commands.base import SpecError
from marinecdpr.commands.import_robot import ImportSpec
from marinecdpr.errors import ScenarioError


def import_(
    source: Path = typer.Argument(..., help="A CASPR model's *_bodies.xml or a WireX robot (.wcrfx)."),
    out: Path = typer.Option(..., "--out", "-o", help="The scenario file to write (.toml)."),
    cables: Optional[Path] = typer.Option(ImportSpec.default("cables"), help="CASPR: the cables file (default: "
                                          "X_cables.xml beside X_bodies.xml)."),
    trajectories: Optional[Path] = typer.Option(ImportSpec.default("trajectories"), help="CASPR: the trajectories "
                                                "file (default: X_trajectories.xml beside it, if there)."),
    cable_set: Optional[str] = typer.Option(ImportSpec.default("cable_set"),
                                            help="CASPR: the cable set (default: the file's default)."),
    trajectory: Optional[str] = typer.Option(ImportSpec.default("trajectory"),
                                             help="CASPR: the trajectory's id (default: the first)."),
    hold: bool = typer.Option(ImportSpec.default("hold"), "--hold", help="CASPR: hold the platform at the joint's "
                              "q_initial, whatever trajectories the model has."),
    pulleys: bool = typer.Option(ImportSpec.default("pulleys"), "--pulleys",
                                 help="WireX: carry over each chain's pulley."),
) -> None:
    """Write a scenario from a robot model of CASPR or WireX, saying what it could not carry over."""
    from marinecdpr.commands import import_robot as command

    spec = spec_of(ImportSpec, cables=cables, trajectories=trajectories, cable_set=cable_set, trajectory=trajectory,
                   hold=hold, pulleys=pulleys)
    try:
        command.check_out(out)  # before any work
        result = command.run(spec, source)
        result.write(out)
    except SpecError as exc:
        fail_spec(exc)
    except ScenarioError as exc:
        fail(str(exc))
    except OSError as exc:
        fail(f"--out {out}: cannot write ({exc.strerror or exc})")
    console.print(plain(f"{out}: '{result.name}' from {result.imported.source}, a {result.dofs} robot with "
                        f"{result.cables} cables, {result.mass_kg:g} kg; trajectory {result.trajectory}"),
                  highlight=False, soft_wrap=True)
    for note in result.imported.notes:
        console.print(plain(f"note: {note}"), highlight=False, soft_wrap=True)
    checked = command.check_written(out)  # a robot that cannot hold its platform, said at once (the file stays)
    if checked.scenario is not None:
        warn_scale(checked.scenario, str(out))
    if checked.problem is not None:
        err_console.print(styled("warning:", "bold yellow", plain(f"{out}: as imported, {checked.problem}")),
                          highlight=False, soft_wrap=True)
