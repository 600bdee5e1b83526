"""``import``: a scenario from a robot model of CASPR (``*_bodies.xml``, its cables and
trajectories files) or WireX (``.wcrfx``), saying what it could not carry over.

:class:`ImportSpec` holds the options, :func:`estimate` names the toolkit the source is from
(read from its root element, before the import), :func:`run` reads the model
(:class:`ImportResult`), whose :meth:`~ImportResult.write` writes the scenario file; then
:func:`check_written` plans a few of the written scenario's steps, to say at once where its
robot cannot hold its platform. Unlike the other commands, the run's argument is the model
file and the output one ``.toml`` file (``--out``), not a folder. (The module is named
``import_robot``: ``import`` is Python's own word.)"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from marinecdpr.commands.base import Spec, SpecError

if TYPE_CHECKING:
    from marinecdpr.scenario.schema import Scenario

__all__ = ["ImportSpec", "ImportEstimate", "ImportResult", "WrittenCheck", "estimate", "run", "check_out",
           "check_written"]


class ImportSpec(Spec):
    """The options of an import (CASPR's or WireX's; each refused for the other toolkit's
    source, in one line naming the source).

    Attributes
    ----------
    cables : Path, optional
        CASPR: the cables file (default: ``X_cables.xml`` beside ``X_bodies.xml``).
    trajectories : Path, optional
        CASPR: the trajectories file (default: ``X_trajectories.xml`` beside it, if there).
    cable_set : str, optional
        CASPR: the cable set (default: the file's default).
    trajectory : str, optional
        CASPR: the trajectory's id (default: the first).
    hold : bool
        CASPR: hold the platform at the joint's ``q_initial``, whatever trajectories the model has.
    pulleys : bool
        WireX: carry over each chain's pulley (its radius and axis).
    """

    cables: Path | None = None
    trajectories: Path | None = None
    cable_set: str | None = None
    trajectory: str | None = None
    hold: bool = False
    pulleys: bool = False


@dataclass(frozen=True)
class ImportEstimate:
    """What an import will read: ``source``, the model file, and ``toolkit``, ``"CASPR"`` or
    ``"WireX"`` (its root element, ``<bodies_system>`` or ``<models>``)."""

    source: Path
    toolkit: str

    def describe(self) -> str:
        """One line: ``"import: a WireX robot, IPAnema.wcrfx"``."""
        return f"import: a {self.toolkit} {'model' if self.toolkit == 'CASPR' else 'robot'}, {self.source.name}"


def estimate(spec: ImportSpec, source: str | Path) -> ImportEstimate:
    """The toolkit the source is from, read from its root element.

    Raises
    ------
    ScenarioError
        One line naming the file: unreadable, too large, not XML, or neither toolkit's root.
    """
    from marinecdpr.scenario.importing.common import read_xml

    top = read_xml(Path(source), ("bodies_system", "models"))
    return ImportEstimate(source=Path(source), toolkit="CASPR" if top.tag == "bodies_system" else "WireX")


def check_out(out: str | Path) -> Path:
    """``out`` as a scenario file to write: a name ending in ``.toml``, not a folder.

    Raises
    ------
    SpecError
        On ``out`` (the command line's ``--out``), with its words.
    """
    out = Path(out)
    if out.suffix != ".toml":
        raise SpecError("out", out, "expected a scenario file name ending in .toml")
    if out.is_dir():
        raise SpecError("out", out, "a folder; expected a scenario file name")
    return out


@dataclass(frozen=True)
class ImportResult:
    """A robot model read as a scenario.

    Attributes
    ----------
    spec : ImportSpec
    imported : Imported
        The scenario's data (validated), the notes (what was not carried over, one sentence
        each), the toolkit and the files read (:class:`~marinecdpr.scenario.importing.Imported`).
    text : str
        The scenario file's text (TOML, headed by its source and the notes as comments).
    """

    spec: ImportSpec
    imported: Any
    text: str

    @property
    def name(self) -> str:
        """The scenario's name."""
        return self.imported.data["name"]

    @property
    def dofs(self) -> str:
        """The robot's ``planar`` or ``spatial``."""
        return self.imported.data["robot"]["dofs"]

    @property
    def cables(self) -> int:
        """The robot's cables."""
        return len(self.imported.data["robot"]["cables"])

    @property
    def mass_kg(self) -> float:
        """The platform's mass, kg."""
        return self.imported.data["robot"]["mass_kg"]

    @property
    def trajectory(self) -> str:
        """The trajectory's type."""
        return self.imported.data["trajectory"]["type"]

    def summary(self) -> dict:
        """``name``, ``toolkit``, ``files``, the robot's ``dofs``, ``cables`` and ``mass_kg``, the
        ``trajectory``'s type and the ``notes``."""
        return {"name": self.name, "toolkit": self.imported.source, "files": list(self.imported.files),
                "dofs": self.dofs, "cables": self.cables, "mass_kg": self.mass_kg,
                "trajectory": self.trajectory, "notes": list(self.imported.notes)}

    def write(self, out: str | Path) -> list[Path]:
        """The scenario file ``out`` (``.toml``; its folders made where missing, and removed
        again if the write fails), written atomically and read back as it will be read.

        Raises
        ------
        SpecError
            On ``out``: not a ``.toml`` name, a folder, a path through a file.
        ScenarioError
            The file does not read back (a bug: the data were validated).
        OSError
            It cannot be written.
        """
        from marinecdpr.scenario.loading import load_scenario
        from marinecdpr.textfiles import atomic_path

        out = check_out(out)
        missing = []
        for folder in (out.parent, *out.parent.parents):
            if folder.is_dir():
                break
            if folder.exists() or folder.is_symlink():
                raise SpecError("out", out, f"{folder} is a file, not a folder")
            missing.append(folder)
        for folder in reversed(missing):
            folder.mkdir()
        try:
            with atomic_path(out) as tmp:
                tmp.write_text(self.text, encoding="utf-8")
                load_scenario(tmp)  # reads back as it will be read
        except BaseException:
            for folder in missing:  # the deepest first; each only while empty
                try:
                    folder.rmdir()
                except OSError:
                    break
            raise
        return [out]


def run(spec: ImportSpec, source: str | Path, *, estimated: ImportEstimate | None = None) -> ImportResult:
    """Read the model (:func:`~marinecdpr.scenario.importing.import_robot`) and its scenario's
    text (:func:`~marinecdpr.scenario.importing.scenario_toml`); nothing written.

    Parameters
    ----------
    estimated : ImportEstimate, optional
        :func:`estimate`'s, where the caller has it (nothing in it is needed again).

    Raises
    ------
    ScenarioError
        One line naming the file and the element; or an option the source's toolkit does
        not take.
    """
    from marinecdpr.scenario.importing import import_robot, scenario_toml

    imported = import_robot(source, cables=spec.cables, trajectories=spec.trajectories, cable_set=spec.cable_set,
                            trajectory=spec.trajectory, hold=spec.hold, pulleys=spec.pulleys)
    return ImportResult(spec=spec, imported=imported, text=scenario_toml(imported))


@dataclass(frozen=True)
class WrittenCheck:
    """The written scenario, read back (None where it cannot be), and ``problem``: where its
    robot cannot hold its platform, or why it cannot be planned, one line (None if it can)."""

    scenario: Scenario | None
    problem: str | None


def check_written(out: str | Path) -> WrittenCheck:
    """Read the written scenario back and plan a few of its steps
    (:func:`~marinecdpr.planning.planner.sampled_infeasibility`): a robot that cannot hold its
    platform is said at once (a warning: the file stays written)."""
    from marinecdpr.errors import ScenarioError
    from marinecdpr.planning.planner import sampled_infeasibility
    from marinecdpr.scenario.loading import load_scenario

    sc = None
    try:
        sc = load_scenario(out)
        problem = sampled_infeasibility(sc)
    except ScenarioError as exc:
        problem = f"it cannot be planned as it is: {exc}"
    return WrittenCheck(scenario=sc, problem=problem)
