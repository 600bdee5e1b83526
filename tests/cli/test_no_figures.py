"""``--no-figures``: every command that draws figures writes, without them, exactly the files
of the run with them but the PNGs, each byte for byte the same (the report aside, which says
in words that the figures were not drawn, the folder's manifest, which lists the files
written, and Capytaine's rao.nc, which holds the times it was made: its content is compared);
its printed lines name no PNG."""

from __future__ import annotations

import hashlib
from importlib import resources
from pathlib import Path

import pytest
from typer.testing import CliRunner

from conftest import tiny_study_folder
import marinecdpr.cli.common as common
from marinecdpr.cli.app import app
from marinecdpr.report.files import MANIFEST
from marinecdpr.report.page import NOT_DRAWN

runner = CliRunner()

SCATTER = "hs_m,tp_s,probability\n0.5,7,0.7\n1.5,9,0.3\n"


def _short_paper(folder: Path) -> str:
    text = (resources.files("marinecdpr.scenario") / "builtin" / "paper.toml").read_text()
    path = folder / "paper_short.toml"
    path.write_text(text.replace("duration_s = 15.0", "duration_s = 0.5"))
    return str(path)


def _scatter(folder: Path) -> str:
    path = folder / "seas.csv"
    path.write_text(SCATTER)
    return str(path)


RUNS = {  # each command's arguments for a short run (a folder of the test's for its inputs)
    "plan": lambda d: ["plan", _short_paper(d)],
    "simulate": lambda d: ["simulate", "paper", "--duration", "0.2"],
    "workspace": lambda d: ["workspace", "paper", "--points", "4x3", "--duration", "0.2"],
    "operability": lambda d: ["operability", "--scatter", _scatter(d), "--serial", "--duration", "10", "--step", "0.1"],
    "clean": lambda d: ["clean", "paper_clean", "--duration", "0.2", "--no-compare"],
    "clean --surface": lambda d: ["clean", "paper_clean", "--surface", "--duration", "0.2", "--no-compare"],
    "clean --seas": lambda d: ["clean", "paper_clean", "--seas", "--serial", "--scatter", _scatter(d),
                               "--duration", "0.2"],
    "control-study": lambda d: ["control-study", "paper_sea", "--latencies", "0", "--predictions", "none",
                                "--pose-from", "sensor", "--duration", "0.2", "--settle", "0"],
    "windows": lambda d: ["windows", "--duration-h", "6", "--hs-limit", "2"],
    "rao": lambda d: ["rao", "--length", "40", "--beam", "10", "--draught", "3", "--gm", "1.5", "--omega",
                      "0.3:1.5:4", "--headings", "90,180"],
    "design": lambda d: ["design", str(tiny_study_folder(d / "study")), "--population", "4", "--generations", "1",
                         "--no-verify"],
    "faults": lambda d: ["faults", "paper", "--cables", "1", "--duration", "1.2", "--after", "0.5"],
}
REPORTS = {"simulate", "clean", "clean --surface", "design", "faults"}
"""The runs whose folder holds a report.html."""


def _same_dataset(a: Path, b: Path) -> bool:
    """Two of Capytaine's files hold the same dataset, the times they were made aside."""
    import xarray as xr

    with xr.open_dataset(a) as x, xr.open_dataset(b) as y:
        for ds in (x, y):
            for clock in ("start_of_computation", "creation_of_dataset"):
                ds.attrs.pop(clock, None)
        return x.identical(y)


def _files(folder: Path) -> dict[str, str]:
    """Every file under ``folder`` (by its path there) and the SHA-256 of its bytes."""
    return {str(p.relative_to(folder)): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(folder.rglob("*")) if p.is_file()}


@pytest.mark.parametrize("run", sorted(RUNS))
def test_without_figures_the_same_files_but_the_pngs(run, tmp_path, monkeypatch):
    if run == "rao":
        pytest.importorskip("capytaine")
    monkeypatch.setattr(common.console, "width", 4000)  # the lines unwrapped, the table's cells whole
    argv = RUNS[run](tmp_path)
    drawn, bare = tmp_path / "drawn", tmp_path / "bare"
    with_figures = runner.invoke(app, argv + ["--figures", "--out", str(drawn)], terminal_width=4000)
    assert with_figures.exit_code == 0, with_figures.output
    without = runner.invoke(app, argv + ["--no-figures", "--out", str(bare)], terminal_width=4000)
    assert without.exit_code == 0, without.output

    a, b = _files(drawn), _files(bare)
    pngs = {name for name in a if name.endswith(".png")}
    assert pngs, sorted(a)  # the run with figures draws some
    assert set(b) == set(a) - pngs, (sorted(a), sorted(b))
    kept = {MANIFEST, "report.html"}
    for name in set(b) - kept:
        if name.endswith(".nc"):
            assert _same_dataset(drawn / name, bare / name), f"{run}: {name} differs without the figures"
            continue
        assert a[name] == b[name], f"{run}: {name} differs without the figures"
    listed = (drawn / MANIFEST).read_text(encoding="utf-8").splitlines()
    assert (bare / MANIFEST).read_text(encoding="utf-8").splitlines() == [n for n in listed if n not in pngs]
    if run in REPORTS:
        page, bare_page = (drawn / "report.html").read_text(), (bare / "report.html").read_text()
        assert "<img" in page and NOT_DRAWN not in page
        assert "<img" not in bare_page and NOT_DRAWN in bare_page and "--no-figures" in bare_page
    assert ".png" not in without.stdout, without.stdout  # the lines name only the files written
    assert ".png" in with_figures.stdout, with_figures.stdout
