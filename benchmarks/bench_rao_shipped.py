"""The shipped paper_sea_rao.csv is the BEM solution its header says it is, at every one of
its 39 frequencies and 12 headings: heave, roll and pitch to 1e-6 of the largest (the CSV
keeps 10 digits; BEM's linear algebra may differ in the last bits between machines).

Run:  .venv/bin/python benchmarks/bench_rao_shipped.py

Moved here from tests/motion/test_bem.py (issue 37, item 15): the solve of the whole table
(704 panels, 39 frequencies) took 16 s of the suite on two cores; the suite keeps the same
check at five of the frequencies (test_the_shipped_paper_sea_table_is_the_bem_solution_it_says_it_is).
Prints the solve's seconds and the largest difference per DOF; exits non-zero if a check fails.
"""

from __future__ import annotations

import sys
import tempfile
import time
from importlib import resources
from pathlib import Path

import numpy as np

from _common import machine  # benchmarks/_common.py (the script's folder is on sys.path)


def main() -> None:
    import capytaine as cpt

    from marinecdpr.motion.bem import box_hull_bem
    from marinecdpr.motion.rao import read_capytaine, read_rao_csv

    print(f"machine: {machine()}")
    table = resources.files("marinecdpr.scenario") / "builtin" / "paper_sea_rao.csv"
    header = table.read_text().splitlines()[:2]
    ok = ("--headings 0,30,60,90,120,150,180,210,240,270,300,330 --omega 0.1:2.0:39 --panel 2.5" in header[1]
          and header[0].startswith("# RAOs from BEM: box 100 x 20 x 6 m, GM 2 m"))
    shipped = read_rao_csv(table)
    t0 = time.perf_counter()
    ds = box_hull_bem(length_m=100.0, beam_m=20.0, draught_m=6.0, gm_m=2.0, roll_damping_ratio=0.05,
                      omega=np.linspace(0.1, 2.0, 39), heading_deg=np.arange(0.0, 360.0, 30.0), panel_m=2.5)
    t1 = time.perf_counter()
    with tempfile.TemporaryDirectory() as d:
        path = Path(d) / "rao.nc"
        cpt.export_dataset(str(path), ds)
        fresh = read_capytaine(path)
    ok &= bool(np.allclose(shipped.omega, fresh.omega, rtol=1e-9, atol=0.0))
    ok &= bool(np.array_equal(shipped.heading_deg, fresh.heading_deg))
    print(f"BEM of the whole table: {fresh.omega.size} frequencies x {fresh.heading_deg.size} headings, "
          f"{t1 - t0:.1f} s")
    for dof, name in ((2, "heave"), (3, "roll"), (4, "pitch")):
        scale = np.abs(fresh.values[dof]).max()
        worst = float(np.abs(shipped.values[dof] - fresh.values[dof]).max() / scale)
        print(f"{name}: largest difference {worst:.1e} of the largest value")
        ok &= worst <= 1e-6
    print("checks:", "pass" if ok else "FAIL")
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
