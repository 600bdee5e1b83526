"""Reading scenarios: TOML files and built-in names, with one-line errors."""

from __future__ import annotations

import tomllib
from importlib import resources
from pathlib import Path
from typing import Any

from pydantic import ValidationError

from marinecdpr.errors import ScenarioError
from marinecdpr.scenario.messages import scenario_error
from marinecdpr.scenario.schema import Scenario
# --------------------------------------------------------------------- loading
def builtin_scenarios() -> list[str]:
    """Names of the scenarios shipped with the package."""
    folder = resources.files("marinecdpr.scenario") / "builtin"
    return sorted(p.name[:-5] for p in folder.iterdir() if p.name.endswith(".toml"))


def load_scenario(path_or_name: str | Path = "paper") -> Scenario:
    """Read and validate a scenario from a TOML file or a built-in name.

    Parameters
    ----------
    path_or_name : str or Path
        A path to a ``.toml`` file, or the name of a built-in scenario
        (see :func:`builtin_scenarios`).

    Raises
    ------
    ScenarioError
        One line naming the source, the key and what was expected.
    """
    path = Path(path_or_name)
    if path.is_file():
        source = str(path)
        text = scenario_text(path, source)
    elif str(path_or_name) in builtin_scenarios():
        source = f"built-in scenario '{path_or_name}'"
        builtin = resources.files("marinecdpr.scenario") / "builtin"
        text = (builtin / f"{path_or_name}.toml").read_text(encoding="utf-8")
        path = Path(str(builtin / f"{path_or_name}.toml"))  # its files (an RAO table) lie beside it
    elif path.is_dir():
        raise ScenarioError("a folder, not a file; expected a scenario file (.toml) or a built-in name",
                            source=str(path_or_name))
    else:
        raise ScenarioError(
            f"no such file, and no built-in scenario of that name "
            f"(built-ins: {', '.join(builtin_scenarios())})",
            source=str(path_or_name),
        )
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ScenarioError(f"not valid TOML: {exc}", source=source) from None
    except RecursionError:  # tomllib recurses into nested arrays and inline tables
        raise ScenarioError("not valid TOML: arrays or inline tables too deeply nested "
                            "(a scenario nests a few levels)", source=source) from None
    base_dir = path.parent if path.is_file() else Path.cwd()  # a built-in's own folder, too
    return scenario_from_dict(data, source=source, base_dir=base_dir)


def scenario_text(path: Path, source: str, max_bytes: int = 64 * 2**20) -> str:
    """A scenario file's text: UTF-8 (a byte-order mark dropped), no NUL byte, at most
    ``max_bytes`` (64 MiB).

    Raises
    ------
    ScenarioError
        One line naming ``source`` and what is wrong (unreadable, too large, a NUL byte or
        not UTF-8, with the line).
    """
    from marinecdpr.textfiles import position

    try:
        with path.open("rb") as f:
            raw = f.read(max_bytes + 1)
    except OSError as exc:
        raise ScenarioError(f"cannot read the file ({exc.strerror or exc})", source=source) from None
    if len(raw) > max_bytes:
        raise ScenarioError(f"larger than a scenario file can be ({max_bytes // 2**20} MiB)", source=source)
    raw = raw.removeprefix(b"\xef\xbb\xbf")
    if (nul := raw.find(b"\0")) >= 0:
        raise ScenarioError(f"{position(raw, nul, 'line')}: a NUL byte, so not text; "
                            f"expected a TOML scenario file", source=source)
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise ScenarioError(f"{position(raw, exc.start, 'line')}: not UTF-8 text; "
                            f"expected a TOML scenario file in UTF-8", source=source) from None


def _too_deep(data: Any, limit: int = 32) -> str | None:
    """The top-level key under which tables and lists nest more than ``limit`` deep, or None."""
    for key, value in (data.items() if isinstance(data, dict) else ()):
        stack = [(value, 2)]  # the top-level table is level 1
        while stack:  # not recursive: a deep (or circular) structure ends at the limit
            node, depth = stack.pop()
            if isinstance(node, (dict, list, tuple)):
                if depth > limit:
                    return str(key)
                stack.extend((v, depth + 1) for v in (node.values() if isinstance(node, dict) else node))
    return None


def scenario_from_dict(
    data: dict[str, Any], *, source: str | None = None, base_dir: str | Path | None = None
) -> Scenario:
    """Validate a scenario given as nested dicts (as read from TOML).

    Parameters
    ----------
    base_dir : str or Path, optional
        Folder that relative file paths (RAOs, recorded motion) are taken from;
        default the working folder.
    """
    if (key := _too_deep(data)) is not None:
        raise ScenarioError("too deeply nested (tables or arrays more than 32 levels deep; "
                            "a scenario nests a few)", source=source, key=key)
    try:
        try:
            return Scenario.model_validate(data, context={"base_dir": base_dir or Path.cwd()})
        except ValidationError as exc:
            raise scenario_error(exc, data, source, Scenario) from None
    except RecursionError:  # a backstop: _too_deep should have caught it
        raise ScenarioError("too deeply nested", source=source) from None
