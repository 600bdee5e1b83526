"""A bad option's value reaches the user as one line naming its ``--flag``, exit 2, nothing
written, for every command that has options (issue 38: the specs' checks, through the thin
command line)."""

from __future__ import annotations

import pytest
from typer.testing import CliRunner

from marinecdpr.cli.app import app

runner = CliRunner()

CASES = [
    (["plan", "--method", "magic"], "--method magic"),
    (["simulate", "--plant", "magic"], "--plant magic"),
    (["clean", "--move-time", "-1"], "--move-time -1"),
    (["workspace", "--points", "3"], "--points 3"),
    (["operability", "--margin", "-1"], "--margin -1"),
    (["rao", "--length", "100", "--beam", "20", "--draught", "5", "--gm", "2", "--omega", "1:0:3"], "--omega 1:0:3"),
    (["windows", "--duration-h", "6", "--hs-limit", "2", "--alpha", "2"], "--alpha 2"),
    (["control-study", "--rate", "-1"], "--rate -1"),
    (["faults", "--kinds", "snap,magic"], "--kinds magic"),
    (["latency", "--calls", "0"], "--calls 0"),
    (["warmup", "paper", "--plant", "magic"], "'--plant'"),
    (["design", "--population", "1"], "'--population'"),
    (["import", "tests/data/caspr/x_bodies.xml", "--out", "robot.txt"], "--out robot.txt"),
]


@pytest.mark.parametrize("args, flag", CASES, ids=[c[0][0] for c in CASES])
def test_a_bad_value_is_one_line_naming_its_flag_and_exit_2(args, flag, tmp_path):
    out = tmp_path / "o"
    extra = [] if args[0] in ("latency", "warmup", "import") else ["--out", str(out)]
    res = runner.invoke(app, args + extra, terminal_width=2000)
    lines = res.stderr.strip().splitlines()
    assert res.exit_code == 2 and len(lines) == 1, (res.exit_code, res.stderr)
    assert lines[0].startswith("error: ") and flag in lines[0], lines[0]
    assert not out.exists()
