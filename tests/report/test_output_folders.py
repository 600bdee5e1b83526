"""An output folder holds one command's results: a run of another command into it is refused
(one line naming the command that wrote them, exit 2), never emptied silently; the same command
replaces its own files (issue 37, item 5)."""

from pathlib import Path

import marinecdpr
from typer.testing import CliRunner

from marinecdpr.cli.app import app
from marinecdpr.report.files import MANIFEST, StagedOutput, read_manifest

runner = CliRunner()
PAPER = (Path(marinecdpr.__file__).parent / "scenario" / "builtin" / "paper.toml").read_text()


def _short_paper(folder: Path, seconds: float) -> Path:
    path = folder / f"paper_{seconds:g}.toml"
    path.write_text(PAPER.replace("duration_s = 15.0", f"duration_s = {seconds:g}"))
    return path


def _listing(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir()) if p.is_file()}


def test_plan_into_simulate_s_folder_is_refused_and_keeps_its_files(tmp_path):
    out = tmp_path / "out"
    sim = runner.invoke(app, ["simulate", "paper", "--duration", "0.2", "--out", str(out)])
    assert sim.exit_code == 0, sim.output
    before = _listing(out)
    assert {"report.html", "summary.json", "sim_closed_loop.csv"} <= set(before)
    res = runner.invoke(app, ["plan", str(_short_paper(tmp_path, 0.5)), "--out", str(out)], terminal_width=2000)
    assert res.exit_code == 2, res.output
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"error: --out {out}: holds the results of 'simulate' ("), lines
    assert "give plan another --out" in lines[0]
    assert _listing(out) == before  # every file as simulate wrote it, byte for byte
    assert [p.name for p in out.glob(".staging-*")] == []


def test_the_same_command_replaces_its_own_files(tmp_path):
    out = tmp_path / "out"
    (out).mkdir()
    (out / "notes.txt").write_text("mine")
    for seconds, rows in ((1.0, 1001), (0.5, 501)):
        res = runner.invoke(app, ["plan", str(_short_paper(tmp_path, seconds)), "--out", str(out)])
        assert res.exit_code == 0, res.output
        assert len((out / "plan.csv").read_text().splitlines()) == rows + 1  # the header and one row a step
    assert read_manifest(out) == ("plan", ["plan.csv", "tensions.png"])
    assert (out / "notes.txt").read_text() == "mine"  # a file no run wrote is never touched


def test_another_command_refused_in_windows_folder_then_free_once_its_files_are_gone(tmp_path):
    out = tmp_path / "out"
    win = runner.invoke(app, ["windows", "--duration-h", "6", "--hs-limit", "2", "--out", str(out)])
    assert win.exit_code == 0, win.output
    written = read_manifest(out)
    assert written[0] == "windows" and "windows.csv" in written[1]
    scen = str(_short_paper(tmp_path, 0.5))
    res = runner.invoke(app, ["plan", scen, "--out", str(out)], terminal_width=2000)
    assert res.exit_code == 2 and "holds the results of 'windows'" in res.stderr
    for name in written[1]:
        (out / name).unlink()  # the user cleared them: the folder is free
    res = runner.invoke(app, ["plan", scen, "--out", str(out)])
    assert res.exit_code == 0, res.output
    assert read_manifest(out) == ("plan", ["plan.csv", "tensions.png"])


def test_a_manifest_naming_no_command_loses_only_the_names_written_again(tmp_path):
    """A folder written before commands were recorded: its files that the new run does not
    write are kept (the manifest said nothing of which command wrote them)."""
    out = tmp_path / "out"
    out.mkdir()
    (out / MANIFEST).write_text("plan.csv\nreport.html\n")
    (out / "plan.csv").write_text("old")
    (out / "report.html").write_text("old report")
    with StagedOutput(out, command="plan") as stage:
        (stage / "plan.csv").write_text("new")
    assert (out / "plan.csv").read_text() == "new"
    assert (out / "report.html").read_text() == "old report"
    assert read_manifest(out) == ("plan", ["plan.csv"])
