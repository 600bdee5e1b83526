"""A pydantic validation error as one line naming the key: the messages of scenario files."""

from __future__ import annotations

import difflib
from typing import Any

from pydantic import BaseModel, ValidationError

from marinecdpr.errors import ScenarioError
from marinecdpr.scenario.fields import _KeyedError

__all__ = ["scenario_error"]


def scenario_error(exc: ValidationError, data: Any, source: str | None, root: type[BaseModel]) -> ScenarioError:
    """The first validation error of the model ``root`` as one line: the dotted key (entries
    counted from 1), what was expected, and a suggestion for a misspelt key."""
    # a misspelt key explains the "missing" error that comes with it: report it first
    errors = sorted(exc.errors(), key=lambda e: e["type"] != "extra_forbidden")
    err = errors[0]
    loc = list(err["loc"])
    kind = err["type"]
    message = err["msg"].removeprefix("Value error, ")
    ctx = err.get("ctx") or {}
    if kind == "too_long" and ctx.get("field_type") != "Tuple":
        # a list longer than its cap (obstacles, polygons' points, headings): the cap, not a vector's size
        message = f"at most {ctx.get('max_length')} entries, got {ctx.get('actual_length')}"
    elif kind == "too_long" and ctx.get("max_length") != 3:
        message = f"expected {ctx.get('max_length')} numbers, got {ctx.get('actual_length')}"
    elif (kind == "missing" and loc and isinstance(loc[-1], int)) or kind in ("too_long", "tuple_type"):
        # a 3-vector with the wrong number of entries: name the vector, not its element
        if isinstance(loc[-1], int):
            loc.pop()
        value = _lookup(data, loc)
        got = f"{len(value)}" if isinstance(value, list) else repr(value)
        message = f"expected 3 numbers [x, y, z], got {got}"
    elif kind == "extra_forbidden":
        message = "unknown key" + _suggest(root, err["loc"], data)
    elif kind == "missing":
        message = "missing"
    elif kind in ("union_tag_invalid", "union_tag_not_found"):
        loc.append("type")
        got = _lookup(data, loc)
        message = (f"expected one of {_union_tags(root, loc[:-1])}"
                   + (" (missing)" if got is None else f" (got {got!r})"))
    elif kind not in ("value_error", "assertion_error") and "input" in err:
        shown = repr(err["input"])
        message += f" (got {shown if len(shown) <= 60 else shown[:57] + '...'})"
    key_parts: list[str] = []
    for part in _strip_tags(data, loc):
        if isinstance(part, int):
            key_parts[-1] += f"[{part + 1}]"
        else:
            key_parts.append(str(part))
    error_obj = (err.get("ctx") or {}).get("error")
    if isinstance(error_obj, _KeyedError):
        key_parts.append(error_obj.key)
    # the field a misspelt key was meant to be is reported missing too: not another problem
    others = [e for e in errors[1:] if not (
        kind == "extra_forbidden" and e["type"] == "missing" and f"'{e['loc'][-1]}'?" in message)]
    if others:
        message += f" (and {len(others)} more problem{'s' if len(others) > 1 else ''})"
    return ScenarioError(message, source=source, key=".".join(key_parts) or None)


def _union_tags(root: type[BaseModel], loc: list) -> str:
    """The ``type`` values a union field at ``loc`` accepts, quoted."""
    model: Any = root
    for part in loc:
        fields = getattr(model, "model_fields", {})
        if isinstance(part, str) and part in fields:
            model = fields[part].annotation
    tags: list[str] = []
    stack = [model]
    while stack:
        ann = stack.pop()
        if isinstance(ann, type) and issubclass(ann, BaseModel):
            tag = ann.model_fields.get("type")
            tags += list(getattr(tag.annotation, "__args__", ())) if tag else []
        else:
            stack.extend(getattr(ann, "__args__", ()))
            if hasattr(ann, "__metadata__"):
                stack.append(ann.__origin__)
    return ", ".join(f"'{t}'" for t in sorted(set(tags)))


def _strip_tags(data: Any, loc: list) -> list:
    """The location without the tags ("circle") pydantic inserts after a union field."""
    out: list = []
    node: Any = data
    after_field = False
    for part in loc:
        if isinstance(part, int):
            node = node[part] if isinstance(node, list) and part < len(node) else None
            after_field = True  # a list's item may be a union too (``[[obstacles]]``)
        elif after_field and isinstance(node, dict) and node.get("type") == part:
            after_field = False  # the tag: skip it, once
            continue
        else:
            node = node.get(part) if isinstance(node, dict) else None
            after_field = True
        out.append(part)
    return out


def _lookup(data: Any, loc: list) -> Any:
    """The raw value at a pydantic location; None if absent."""
    node = data
    for part in _strip_tags(data, loc):
        if isinstance(part, int):
            node = node[part] if isinstance(node, list) and part < len(node) else None
        else:
            node = node.get(part) if isinstance(node, dict) else None
    return node


def _suggest(root: type[BaseModel], loc: tuple, data: Any) -> str:
    """'; did you mean X? (expected one of: ...)' for a misspelt key."""
    model: Any = root
    node: Any = data
    for part in _strip_tags(data, list(loc[:-1])):
        if isinstance(part, int):
            node = node[part] if isinstance(node, list) and part < len(node) else None
            continue
        node = node.get(part) if isinstance(node, dict) else None
        model = _field_model(model.model_fields[part].annotation, node)
    fields = list(getattr(model, "model_fields", {}))
    close = difflib.get_close_matches(str(loc[-1]), fields, n=1, cutoff=0.5)
    hint = f"; did you mean '{close[0]}'?" if close else ""
    return f"{hint} (expected one of: {', '.join(fields)})" if fields else hint


def _field_model(annotation: Any, node: Any) -> Any:
    """The model class a field holds (through lists, unions and Annotated), picked by "type"."""
    candidates, stack = [], [annotation]
    while stack:
        ann = stack.pop()
        if isinstance(ann, type) and issubclass(ann, BaseModel):
            candidates.append(ann)
        else:
            stack.extend(getattr(ann, "__args__", ()))
            if getattr(ann, "__origin__", None) is not None and hasattr(ann, "__metadata__"):
                stack.append(ann.__origin__)
    if isinstance(node, dict):
        for cand in candidates:
            tag = cand.model_fields.get("type")
            if tag is not None and node.get("type") in getattr(tag.annotation, "__args__", ()):
                return cand
    return candidates[0] if candidates else None
