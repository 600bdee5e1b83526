"""Robots from the field's toolkits as marinecdpr scenarios: CASPR's XML models and WireX's
``.wcrfx`` robots (``marinecdpr import``).

- :mod:`.common` the result (:class:`Imported`), XML reading with one-line errors, the
  conventions shared by both, and the scenario's TOML text;
- :mod:`.caspr`  a CASPR model: ``*_bodies.xml`` (one rigid platform), ``*_cables.xml`` and
  its ``*_trajectories.xml`` where given;
- :mod:`.wirex`  a WireX robot file (``.wcrfx``).

Each importer gives a validated scenario's data and says, one sentence each, what of the
source it did not carry over and why.
"""

from __future__ import annotations

from pathlib import Path

from marinecdpr.errors import ScenarioError
from marinecdpr.scenario.importing.common import Imported, read_xml, scenario_toml

__all__ = ["Imported", "import_robot", "scenario_toml"]


def import_robot(path: str | Path, *, cables: str | Path | None = None, trajectories: str | Path | None = None,
                 cable_set: str | None = None, trajectory: str | None = None, hold: bool = False,
                 pulleys: bool = False) -> Imported:
    """A robot from a CASPR model or a WireX robot file, as a validated scenario.

    Parameters
    ----------
    path : str or Path
        A CASPR ``*_bodies.xml`` (its ``*_cables.xml`` and ``*_trajectories.xml`` are taken
        from beside it unless given) or a WireX ``.wcrfx``, told apart by their root element.
    cables, trajectories : str or Path, optional
        CASPR: the cables and trajectories files.
    cable_set, trajectory : str, optional
        CASPR: the cable set (default the file's ``default_cable_set``) and the trajectory's
        id (default the first; none: the platform held at ``q_initial``).
    hold : bool
        CASPR: hold the platform at ``q_initial`` whatever trajectories the model has.
    pulleys : bool
        WireX: carry over each chain's pulley (its radius and axis); off by default, as
        WireX's standard kinematics, which its published lengths use, has none.

    Raises
    ------
    ScenarioError
        One line naming the file and the element.
    """
    path = Path(path)
    top = read_xml(path, ("bodies_system", "models"))
    if top.tag == "bodies_system":
        from marinecdpr.scenario.importing.caspr import read_caspr

        if pulleys:
            raise ScenarioError("--pulleys is for WireX robots: CASPR's cables carry no pulleys", source=str(path))
        return read_caspr(path, cables=cables, trajectories=trajectories, cable_set=cable_set,
                          trajectory=trajectory, hold=hold)
    from marinecdpr.scenario.importing.wirex import read_wirex

    for name, value in (("--cables", cables), ("--trajectories", trajectories), ("--cable-set", cable_set),
                        ("--trajectory", trajectory), ("--hold", hold or None)):
        if value is not None:
            raise ScenarioError(f"{name} is for CASPR models: a WireX robot file holds its cables", source=str(path))
    return read_wirex(path, pulleys=pulleys)
