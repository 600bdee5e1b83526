"""Reports read typed results, not dict keys (issue 38, item 4): no ``summary["..."]`` read
(nor ``s["..."]``, ``c["..."]``, ``g["..."]``, ``u["..."]`` of a summary dict) in the modules
converted to the typed records; the rest may only shrink.

The records: :class:`~marinecdpr.studies.prototype_runs.PrototypeFigures` and
:class:`~marinecdpr.studies.prototype_runs.RunFigures` (the main job),
:class:`~marinecdpr.studies.design.DesignStudy`'s ``best``, ``feasible``, ``target_met``
(the design study), the cleaning job's figures
(:class:`~marinecdpr.studies.cleaning.CleaningFigures`, its :class:`~marinecdpr.studies.cleaning.Guarantee`)
and :class:`~marinecdpr.studies.surface.SurfaceJob`'s attributes (``clean --surface``)."""

import re
from pathlib import Path

import marinecdpr

PACKAGE = Path(marinecdpr.__file__).parent
READ = re.compile(r"""\b(summary|s|c|g|u)\[["']""")
"""A read of a summary dict by key, as the issue counts them (``summary["..."]``), in
either quote (``s['...']`` in an f-string too)."""

RECORDS = {"studies/prototype_runs.py", "studies/cleaning.py"}
"""The modules that define the records (and build the dicts from them)."""

CONVERTED = ["report/text.py", "report/design.py", "commands/simulate.py", "cli/simulate.py", "studies/cleaning.py",
             "report/cleaning.py", "commands/clean.py", "cli/clean.py", "cli/plan.py", "cli/warmup.py",
             "cli/workspace.py", "cli/check.py", "cli/windows.py", "cli/import_robot.py"]
"""Modules whose readers read the records' attributes: none left."""


def summary_reads(rel: str) -> list[str]:
    """Every summary-dict read by key in ``src/marinecdpr/<rel>``, as ``"rel:line text"``."""
    lines = (PACKAGE / rel).read_text(encoding="utf-8").splitlines()
    return [f"{rel}:{i} {line.strip()}" for i, line in enumerate(lines, 1) if READ.search(line)]


def test_the_pattern_finds_the_reads_it_counts():
    assert READ.search('x = summary["best"]') and READ.search("f(s[\"steps\"])") and READ.search('c["cut"]')
    assert READ.search("f\"{s['coverage_pct']:.2f}\"") and READ.search("summary['x']")
    assert not READ.search("figures.steps") and not READ.search('pos["x"]') and not READ.search("rows[0]")


def test_the_converted_modules_read_no_summary_dict():
    found = [line for rel in CONVERTED for line in summary_reads(rel)]
    assert found == [], "\n".join(found)


def test_the_remaining_reads_only_shrink():
    """Outside the records' modules, no more lines with such a read than :data:`REMAINING`."""
    files = sorted(str(p.relative_to(PACKAGE)) for p in PACKAGE.rglob("*.py"))
    rest = [line for rel in files if rel not in RECORDS for line in summary_reads(rel)]
    assert len(rest) <= REMAINING, "\n".join(rest)


REMAINING = 2
"""Lines the pattern finds outside the records' modules when this test was written, neither of
them a summary: the CASPR and WireX importers' rows of the cable table they build
(``c["tension_min_N"]``, ``c["frame_anchor_m"]``)."""
