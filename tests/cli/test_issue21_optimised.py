"""Issue 21, item 15: the command's input checks hold under ``python -O`` (they were
``assert`` statements, which -O removes: bad input ran on, or failed with a traceback)."""

import ast
import subprocess
import sys
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[2] / "src" / "marinecdpr"


@pytest.mark.parametrize("args, message", [
    (["workspace", "paper", "--points", "0x3"], "--points 0x3: expected two positive integers like 30x20"),
    (["workspace", "paper", "--points", "30x20x2"], "--points 30x20x2: expected two positive integers like 30x20"),
    (["operability", "paper_sea", "--workspace", "-1x4"], "--workspace -1x4: expected two positive integers like 12x8"),
    (["windows", "--duration-h", "2", "--hs-limit", "2", "--days", "1,-3"],
     "--days 1,-3: expected positive numbers separated by commas, e.g. 1,3,7"),
])
def test_bad_input_under_python_O_is_one_line_exit_2(args, message, tmp_path):
    out = tmp_path / "o"
    res = subprocess.run([sys.executable, "-O", "-m", "marinecdpr", *args, "--out", str(out)], capture_output=True,
                         text=True, timeout=300)
    assert res.returncode == 2, res.stderr
    assert res.stderr.strip().splitlines() == [f"error: {message}"]
    assert not out.exists()


def test_no_assert_in_the_package():
    """asserts check nothing under -O: the package checks with if/raise (its validators)."""
    found = [f"{p.relative_to(SRC)}:{node.lineno}" for p in SRC.rglob("*.py")
             for node in ast.walk(ast.parse(p.read_text())) if isinstance(node, ast.Assert)]
    assert found == []
