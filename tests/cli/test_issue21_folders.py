"""Issue 21, item 13: a folder given where a file is expected is called a folder (``check``
said "no such file"), for every file a command takes."""

import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from marinecdpr.cli.app import app

runner = CliRunner()
EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


@pytest.mark.parametrize("args, message", [
    (["check", "{d}"], "error: {d}: a folder, not a file; expected a scenario file (.toml) or a built-in name"),
    (["plan", "{d}", "--out", "{o}"], "error: {d}: a folder, not a file; expected a scenario file (.toml) or a "
                                      "built-in name"),
    (["windows", "--duration-h", "2", "--operability", "{d}", "--out", "{o}"],
     "error: {d}: a folder, not a file; expected an operability.json"),
])
def test_a_folder_for_a_file_is_called_a_folder(args, message, tmp_path):
    d = tmp_path / "a_folder"
    d.mkdir()
    out = tmp_path / "o"
    res = runner.invoke(app, [a.format(d=d, o=out) for a in args], terminal_width=2000)
    assert res.exit_code == 2, res.output
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(message.format(d=d)), lines
    assert not out.exists()


def test_a_folder_for_the_rao_table_is_called_a_folder(tmp_path):
    (tmp_path / "rao.csv").mkdir()
    from marinecdpr.scenario.schema import _resolve_file

    class Info:
        context = {"base_dir": tmp_path}

    with pytest.raises(ValueError, match=f"a folder, not a file: {tmp_path / 'rao.csv'}"):
        _resolve_file("rao.csv", Info())
