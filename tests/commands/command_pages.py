"""The command pages (``docs/commands/<command>.md``) as the tests read them: their python
blocks, run as written in a folder of their own, and their table of options, checked
against the command's spec."""

from __future__ import annotations

import ast
import re
from pathlib import Path

PAGES = Path(__file__).resolve().parents[2] / "docs" / "commands"


def cli_default(param) -> object:
    """A command line option's default as the command reads it when it runs (a default read
    from the library's defaults table, ``--figures``, is a function click calls then)."""
    return param.default() if callable(param.default) else param.default


def page(command: str) -> str:
    """``docs/commands/<command>.md``'s text."""
    return (PAGES / f"{command}.md").read_text(encoding="utf-8")


def run_page(command: str, folder: Path, monkeypatch) -> dict:
    """Run the page's ```python blocks in order, in one namespace, with ``folder`` as the
    working folder; the namespace."""
    text = page(command)
    blocks = re.findall(r"```python\n(.*?)```", text, flags=re.S)
    assert blocks, f"docs/commands/{command}.md has no python block"
    monkeypatch.chdir(folder)
    ns: dict = {}
    for block in blocks:
        exec(compile(block, str(PAGES / f"{command}.md"), "exec"), ns)  # noqa: S102 - the page's own example
    return ns


def options_table(command: str, fields: dict[str, str] | None = None) -> dict[str, object]:
    """The page's table of options: each row's field (its ```--flag``` as the spec's field,
    or as ``fields`` maps a flag) and its default (the second column, a Python literal in
    backticks)."""
    rows = {}
    for line in page(command).splitlines():
        m = re.match(r"\|\s*`--([a-z-]+)`\s*\|\s*`([^`]*)`\s*\|", line)
        if m:
            field = (fields or {}).get(m.group(1), m.group(1).replace("-", "_"))
            assert field not in rows, f"--{m.group(1)} is listed twice"
            rows[field] = ast.literal_eval(m.group(2))
    return rows


def assert_table_is_the_spec(command: str, spec_class, fields: dict[str, str] | None = None) -> None:
    """The page lists exactly the spec's fields, each with the spec's default (``fields``:
    a flag whose field is not its name, e.g. ``{"json": "as_json"}``)."""
    rows = options_table(command, fields)
    assert set(rows) == set(spec_class.model_fields), (sorted(rows), sorted(spec_class.model_fields))
    for field, default in rows.items():
        assert default == spec_class.default(field), (field, default, spec_class.default(field))
