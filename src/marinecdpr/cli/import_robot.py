"""The ``import`` command: write a scenario from a robot model of CASPR or WireX, saying what it could not carry over."""

from __future__ import annotations

from contextlib import contextmanager
from pathlib import Path
from typing import Optional

import typer

from marinecdpr.cli.common import console, err_console, fail, plain, styled, warn_scale
from marinecdpr.errors import ScenarioError
from marinecdpr.scenario.loading import load_scenario


@contextmanager
def _file_folder(out: Path):
    """The folder of an output file, created if missing (as the commands' output folders are)
    and removed again if the block fails while it is still empty; a path through a file is
    one line, exit 2 (``--out notes.txt/x.toml``: notes.txt is a file, not a folder)."""
    missing = []
    for folder in (out.parent, *out.parent.parents):
        if folder.is_dir():
            break
        if folder.exists() or folder.is_symlink():
            fail(f"--out {out}: {folder} is a file, not a folder")
        missing.append(folder)
    for folder in reversed(missing):
        folder.mkdir()
    try:
        yield
    except BaseException:
        for folder in missing:  # the deepest first; each only while empty
            try:
                folder.rmdir()
            except OSError:
                break
        raise


def import_(
    source: Path = typer.Argument(..., help="A CASPR model's *_bodies.xml or a WireX robot (.wcrfx)."),
    out: Path = typer.Option(..., "--out", "-o", help="The scenario file to write (.toml)."),
    cables: Optional[Path] = typer.Option(None, help="CASPR: the cables file (default: X_cables.xml beside "
                                          "X_bodies.xml)."),
    trajectories: Optional[Path] = typer.Option(None, help="CASPR: the trajectories file (default: "
                                                "X_trajectories.xml beside it, if there)."),
    cable_set: Optional[str] = typer.Option(None, help="CASPR: the cable set (default: the file's default)."),
    trajectory: Optional[str] = typer.Option(None, help="CASPR: the trajectory's id (default: the first)."),
    hold: bool = typer.Option(False, "--hold", help="CASPR: hold the platform at the joint's q_initial, "
                              "whatever trajectories the model has."),
    pulleys: bool = typer.Option(False, "--pulleys", help="WireX: carry over each chain's pulley."),
) -> None:
    """Write a scenario from a robot model of CASPR or WireX, saying what it could not carry over."""
    from marinecdpr.scenario.importing import import_robot, scenario_toml
    from marinecdpr.textfiles import atomic_path

    if out.suffix != ".toml":
        fail(f"--out {out}: expected a scenario file name ending in .toml")
    if out.is_dir():
        fail(f"--out {out}: a folder; expected a scenario file name")
    try:
        imported = import_robot(source, cables=cables, trajectories=trajectories, cable_set=cable_set,
                                trajectory=trajectory, hold=hold, pulleys=pulleys)
        text = scenario_toml(imported)
        with _file_folder(out), atomic_path(out) as tmp:
            tmp.write_text(text, encoding="utf-8")
            load_scenario(tmp)  # reads back as it will be read
    except ScenarioError as exc:
        fail(str(exc))
    except OSError as exc:
        fail(f"--out {out}: cannot write ({exc.strerror or exc})")
    r = imported.data["robot"]
    console.print(plain(f"{out}: '{imported.data['name']}' from {imported.source}, a {r['dofs']} robot with "
                         f"{len(r['cables'])} cables, {r['mass_kg']:g} kg; trajectory "
                         f"{imported.data['trajectory']['type']}"), highlight=False, soft_wrap=True)
    for note in imported.notes:
        console.print(plain(f"note: {note}"), highlight=False, soft_wrap=True)
    # a robot that cannot hold its platform, said at once (a warning: the file is written)
    from marinecdpr.planning.planner import sampled_infeasibility

    try:
        sc = load_scenario(out)
        warn_scale(sc, str(out))
        problem = sampled_infeasibility(sc)
    except ScenarioError as exc:
        problem = f"it cannot be planned as it is: {exc}"
    if problem is not None:
        err_console.print(styled("warning:", "bold yellow", plain(f"{out}: as imported, {problem}")),
                          highlight=False, soft_wrap=True)
