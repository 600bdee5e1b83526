"""Fingerprints of the main jobs' outputs, to show that moving code changes no number.

Runs ``simulate`` on paper, paper_elastic, paper_as_built and examples/spatial_cube8.toml,
``clean paper_clean`` (whole horizons), ``clean --surface``, a two-sea-state ``clean --seas``
and ``operability``, and a small ship_side design study (4 x 2, without its verification) (each as a
subprocess of this checkout), and
prints the SHA-256 of every CSV and of ``summary.json`` with its run-dependent fields
(wall-clock times, versions) taken out. ``--write FILE`` keeps them as JSON; ``--compare
FILE`` runs again and lists every file whose fingerprint differs, and for a CSV the largest
relative difference of its numbers (so a rounding-level change is told from a real one).

Run: ``PYTHONPATH=src .venv/bin/python benchmarks/output_fingerprints.py --write before.json``,
then after the change ``... --compare before.json``. Issue 22 asks for this evidence:
``fingerprints_before_issue22.json`` holds them for main at e89bc1f (2026-12-03, Intel Xeon,
2 cores, Python 3.11.7, numpy 2.4.6, numba 0.68.1, MuJoCo 4.0), where a second run gave the
same 22 fingerprints; compare on the same machine and versions (without the kept outputs,
only which files differ is printed). ``fingerprints_issue22_one_solver.json`` holds them for
main at 4383442 (2026-12-04, same machine and versions): the one tension solver (63af5f6)
changed 17 files at rounding level (issue 22's note explains each); the commits after it,
up to the named results, changed none.
"""

from __future__ import annotations

import argparse
import csv
import hashlib
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
RUNS = {
    "simulate_paper": ["simulate", "paper"],
    "simulate_paper_elastic": ["simulate", "paper_elastic"],
    "simulate_paper_as_built": ["simulate", "paper_as_built"],
    "simulate_spatial_cube8": ["simulate", str(ROOT / "examples" / "spatial_cube8.toml")],
    "clean_paper_clean": ["clean", "paper_clean"],
    "clean_surface": ["clean", "paper_clean", "--surface", "--duration", "0.2", "--no-compare"],
    "clean_seas_small": ["clean", "paper_clean", "--seas", "--serial", "--scatter", "{scatter}", "--duration", "5"],
    "operability_small": ["operability", "paper_sea", "--scatter", "{scatter}", "--serial", "--duration", "10",
                          "--step", "0.1"],
    "design_small": ["design", "ship_side", "--population", "4", "--generations", "2", "--no-verify"],
}
SCATTER = "hs_m,tp_s,probability\n0.5,7,0.7\n1.5,9,0.3\n"
"""The small studies' scatter diagram: two sea states."""
def fingerprint(folder: Path) -> dict[str, str]:
    """SHA-256 of the bytes of every CSV in ``folder`` and of its summary.json (which holds
    no timing or version: the same run gives the same bytes)."""
    paths = sorted(folder.rglob("*.csv")) + sorted(folder.glob("summary.json"))
    return {str(p.relative_to(folder)): hashlib.sha256(p.read_bytes()).hexdigest() for p in paths}


def largest_relative_difference(a: Path, b: Path) -> float:
    """The largest |x - y| / max(|x|, |y|, 1e-300) over the numbers of two CSVs of one shape."""
    worst = 0.0
    with open(a, newline="") as fa, open(b, newline="") as fb:
        for ra, rb in zip(csv.reader(fa), csv.reader(fb)):
            for x, y in zip(ra, rb):
                try:
                    x, y = float(x), float(y)
                except ValueError:
                    continue
                if x != y:
                    worst = max(worst, abs(x - y) / max(abs(x), abs(y), 1e-300))
    return worst


def run_all(keep: Path) -> dict[str, dict[str, str]]:
    result = {}
    scatter = keep / "scatter.csv"
    keep.mkdir(parents=True, exist_ok=True)
    scatter.write_text(SCATTER)
    for name, argv in RUNS.items():
        folder = keep / name
        t0 = time.perf_counter()
        argv = [a.replace("{scatter}", str(scatter)) for a in argv]
        proc = subprocess.run([sys.executable, "-m", "marinecdpr", *argv, "--out", str(folder)],
                              cwd=ROOT, capture_output=True, text=True)
        print(f"{name}: exit {proc.returncode} in {time.perf_counter() - t0:.1f} s", flush=True)
        if proc.returncode != 0:
            print(proc.stderr.strip().splitlines()[-1] if proc.stderr.strip() else "", flush=True)
        result[name] = fingerprint(folder)
    return result


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--write", type=Path, help="Keep the fingerprints (and the outputs beside it) here.")
    parser.add_argument("--compare", type=Path, help="Compare with fingerprints kept by --write.")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        keep = Path(tmp) if args.write is None else args.write.with_suffix(".outputs")
        prints = run_all(keep)
        if args.write is not None:
            args.write.write_text(json.dumps(prints, indent=1, sort_keys=True))
            print(f"written: {args.write} (outputs in {keep})")
        if args.compare is None:
            for run, files in prints.items():
                for name, digest in files.items():
                    print(f"{run}/{name} {digest[:16]}")
            return 0
        before = json.loads(args.compare.read_text())
        old_outputs = args.compare.with_suffix(".outputs")
        differ = 0
        for run in RUNS:
            for name in sorted(set(before.get(run, {})) | set(prints.get(run, {}))):
                if before.get(run, {}).get(name) != prints.get(run, {}).get(name):
                    differ += 1
                    old, new = old_outputs / run / name, keep / run / name
                    detail = ""
                    if name.endswith(".csv") and old.exists() and new.exists():
                        detail = f" (largest relative difference {largest_relative_difference(old, new):.3g})"
                    print(f"differs: {run}/{name}{detail}")
        n = sum(len(v) for v in prints.values())
        print(f"{n - differ} of {n} files bit for bit the same")
        return 1 if differ else 0


if __name__ == "__main__":
    sys.exit(main())
