"""Issue 21, item 3: no test depends on the machine's speed. Timings belong in benchmarks/;
a test checks the property a timing stood for (work refused before it started:
:mod:`tripwire`; a process ended rather than waited for: its exit status)."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

TESTS = Path(__file__).resolve().parents[1]
CLOCKS = {"perf_counter", "perf_counter_ns", "monotonic", "monotonic_ns", "time", "time_ns", "process_time"}


def _clock_names(tree: ast.AST) -> set[str]:
    """Names assigned from a clock read (``t0 = time.perf_counter()``, ``deadline = time.monotonic() + 10``)."""
    names = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Assign) and _reads_clock(node.value):
            names |= {t.id for t in node.targets if isinstance(t, ast.Name)}
    return names


def _reads_clock(node: ast.AST, names: frozenset[str] = frozenset()) -> bool:
    for sub in ast.walk(node):
        if isinstance(sub, ast.Call) and isinstance(sub.func, ast.Attribute) and sub.func.attr in CLOCKS \
                and isinstance(sub.func.value, ast.Name) and sub.func.value.id == "time":
            return True
        if isinstance(sub, ast.Name) and (sub.id in names or sub.id in ("elapsed", "wall", "took")):
            return True
    return False


def timed_checks(source: str) -> list[int]:
    """Lines of ``source`` whose assertion or loop condition reads a clock (directly, or a
    name assigned from one, or one named ``elapsed``)."""
    tree = ast.parse(source)
    names = frozenset(_clock_names(tree))
    lines = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Assert) and _reads_clock(node.test, names):
            lines.append(node.lineno)
        elif isinstance(node, ast.While) and _reads_clock(node.test, names):
            lines.append(node.lineno)
    return sorted(lines)


def test_the_finder_finds_timed_assertions():
    assert timed_checks("import time\nt0 = time.perf_counter()\nf()\nassert time.perf_counter() - t0 < 5\n") == [4]
    assert timed_checks("def f(elapsed):\n    assert elapsed < 5.0\n") == [2]
    assert timed_checks("import time\ndeadline = time.monotonic() + 10\nwhile time.monotonic() < deadline:\n"
                        "    pass\n") == [3]
    assert timed_checks("assert code == 2 and len(lines) == 1\nwhile proc.poll() is None:\n    pass\n") == []


@pytest.mark.parametrize("path", sorted(p for p in TESTS.rglob("*.py") if "data" not in p.relative_to(TESTS).parts),
                         ids=lambda p: p.name)
def test_no_test_asserts_on_the_time_taken(path):
    assert timed_checks(path.read_text()) == [], f"{path.name}: a check on the time taken (move it to benchmarks/)"
