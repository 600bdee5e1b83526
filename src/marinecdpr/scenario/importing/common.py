"""What both importers share: the result, XML parsing with one-line errors, numbers read
from attributes and text, the orientation conventions, and the TOML text of a scenario."""

from __future__ import annotations

import re

import math
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from marinecdpr.errors import ScenarioError

__all__ = ["Imported", "scenario_toml", "read_xml", "numbers", "euler_from_matrix",
           "held_trajectory", "toml_plain", "MAX_XML_BYTES"]

MAX_XML_BYTES = 16 * 2**20
"""Largest model file read, bytes (a robot's XML is some kB)."""


@dataclass(frozen=True)
class Imported:
    """A robot read from another toolkit's files.

    Attributes
    ----------
    data : dict
        The scenario as nested dicts (as TOML reads it), validated.
    notes : tuple of str
        What of the source was not carried over, or was carried over by a choice, and why:
        one sentence each.
    source : str
        The toolkit: "CASPR" or "WireX".
    files : tuple of str
        The files read.
    """

    data: dict
    notes: tuple[str, ...]
    source: str
    files: tuple[str, ...]


def read_xml(path: Path, root: str | tuple[str, ...]) -> ET.Element:
    """The root element of an XML file, which must be ``root`` (one of them); refused in one
    line naming the file (unreadable, too large, not XML, another root)."""
    path = Path(path)
    try:
        size = path.stat().st_size
        if size > MAX_XML_BYTES:
            raise ScenarioError(f"larger than a robot model can be ({MAX_XML_BYTES // 2**20} MiB)", source=str(path))
        tree = ET.parse(path)
    except FileNotFoundError:
        raise ScenarioError("no such file", source=str(path)) from None
    except IsADirectoryError:
        raise ScenarioError("a folder, not a file", source=str(path)) from None
    except OSError as exc:
        raise ScenarioError(f"cannot read the file ({exc.strerror or exc})", source=str(path)) from None
    except ET.ParseError as exc:
        raise ScenarioError(f"not valid XML: {exc}", source=str(path)) from None
    names = (root,) if isinstance(root, str) else root
    top = tree.getroot()
    if top.tag not in names:
        raise ScenarioError(f"the root element is <{top.tag}>, expected <{'> or <'.join(names)}>", source=str(path))
    return top


def numbers(text: str | None, count: int | None, *, source: str, key: str) -> list[float]:
    """The finite numbers in a whitespace-separated text (``count`` of them, if given)."""
    parts = (text or "").split()
    try:
        values = [float(p) for p in parts]
    except ValueError:
        raise ScenarioError(f"expected numbers, got {text!r}", source=source, key=key) from None
    if count is not None and len(values) != count:
        raise ScenarioError(f"expected {count} number{'s' if count > 1 else ''}, got {len(values)} ({text!r})",
                            source=source, key=key)
    if not all(math.isfinite(v) for v in values):
        raise ScenarioError(f"expected finite numbers, got {text!r}", source=source, key=key)
    return values


def euler_from_matrix(R: np.ndarray) -> list[float]:
    """Our orientation angles (rx, ry, rz) in degrees, with R = Rz(rz) Ry(ry) Rx(rx) (SNAME),
    of a rotation matrix (C <- P)."""
    rx = math.atan2(R[2, 1], R[2, 2])
    ry = math.asin(min(1.0, max(-1.0, -R[2, 0])))
    rz = math.atan2(R[1, 0], R[0, 0])
    return [_clean(math.degrees(a)) for a in (rx, ry, rz)]


def _clean(x: float) -> float:
    """x rounded to 12 significant digits (a file's numbers, not conversion noise), -0 as 0."""
    y = float(f"{x:.12g}")
    return 0.0 if y == 0.0 else y


def held_trajectory(position: list[float], orientation_deg: list[float], duration_s: float) -> dict:
    """A trajectory that holds the platform at one pose (the model's initial one)."""
    return {"type": "line", "start_position_m": [_clean(v) for v in position],
            "end_position_m": [_clean(v) for v in position], "start_orientation_deg": orientation_deg,
            "duration_s": duration_s}


def scenario_toml(imported: Imported) -> str:
    """The scenario's TOML text, headed by where it came from and the notes as comments."""
    import tomli_w

    head = [f"# Imported from {imported.source} by `marinecdpr import`: {', '.join(imported.files)}"]
    head += [f"# note: {n}" for n in imported.notes]
    return "\n".join(head) + "\n\n" + one_line_arrays(tomli_w.dumps(toml_plain(imported.data)))


ONE_LINE_MAX = 100
"""Longest line a numeric array is written on (a 3-vector, a 3 x 3 inertia tensor)."""
_NUMERIC_ARRAY = re.compile(r"= (\[[-+0-9.eEinfa,\s\[\]]*?\n\])", re.MULTILINE)


def one_line_arrays(text: str) -> str:
    """TOML text with each array of numbers that tomli_w spreads over lines (one number a
    line: a 3-vector over five) written on one line, ``[0.3, 0.0, -0.15]``, where that line is
    at most :data:`ONE_LINE_MAX` characters; nested arrays (a 3 x 3 tensor) alike. The
    numbers' text is kept as tomli_w wrote it, so the values read back the same."""

    def join(match: re.Match) -> str:
        body = re.sub(r"\s+", " ", match.group(1))
        body = re.sub(r",\s*\]", "]", body)
        body = re.sub(r"\[\s+", "[", body)
        line_start = text.rfind("\n", 0, match.start()) + 1
        if match.start() - line_start + 2 + len(body) > ONE_LINE_MAX:
            return match.group(0)
        return "= " + body

    return _NUMERIC_ARRAY.sub(join, text)


def toml_plain(value: Any) -> Any:
    """``value`` with tuples as lists and numpy numbers as Python's, at any depth of dicts
    and lists (tomli_w writes only plain types); other values as they are."""
    if isinstance(value, dict):
        return {k: toml_plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [toml_plain(v) for v in value]
    if isinstance(value, np.generic):
        return value.item()
    return value
