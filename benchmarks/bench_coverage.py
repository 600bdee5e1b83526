"""Coverage-map speed: 600 000 brush samples (10 min at 1 ms) over a 2 m x 1.4 m panel.

Run:  .venv/bin/python benchmarks/bench_coverage.py [--quick]

The path is a boustrophedon of a 0.2 m brush over the panel: 8 horizontal lanes 0.171 m
apart (0.029 m overlap), the brush centre 0.1 m inside the panel's edges, with a tracking
error of 2 mm at 0.15 Hz and 0.5 mm at 1.3 Hz, 0.05 mm of sensor noise, and the brush
lifted (out of its force band) for 2 % of the time, in 20 bursts. A second line times the
worst case for the decimation: 0.3 mm of white noise on every 1 ms sample, so that nearly
every sample moves more than a quarter of a cell and is kept.
A rectangular hole of 0.3 m x 0.2 m is left out. Times ``marinecdpr.studies.coverage.coverage_map``
(default resolution; first call's compile time reported apart) and, side by side, what a
user would write with shapely (if installed): the in-contact stretches as LineStrings,
buffered by half the width, unioned, intersected with the panel less its hole. Both
coverage percentages are printed.
"""

from __future__ import annotations

import argparse
import importlib.util
import time

import numpy as np

from marinecdpr.studies.coverage import DECIMATE_CELLS, coverage_map, decimate_path
from _common import best_of, machine  # benchmarks/_common.py (the script's folder is on sys.path)

PANEL = np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 1.4], [0.0, 1.4]])
HOLE = np.array([[0.8, 0.5], [1.1, 0.5], [1.1, 0.7], [0.8, 0.7]])
WIDTH = 0.2


def boustrophedon(n: int, noise_m: float = 5e-5, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """(n, 2) brush-centre path, m, and (n,) in-contact flags of the benchmark."""
    lanes = np.linspace(0.1, 1.3, 8)
    pts = []
    for k, z in enumerate(lanes):
        xs = (0.1, 1.9) if k % 2 == 0 else (1.9, 0.1)
        pts += [(xs[0], z), (xs[1], z)]
    pts = np.array(pts)
    seg = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    s = np.concatenate([[0.0], np.cumsum(seg)])
    t = np.linspace(0.0, s[-1], n)
    path = np.column_stack([np.interp(t, s, pts[:, 0]), np.interp(t, s, pts[:, 1])])
    rng = np.random.default_rng(seed)
    time_s = np.arange(n) * 1e-3
    for amp, f_hz in ((2e-3, 0.15), (5e-4, 1.3)):       # tracking error from the ship's motion
        path += amp * np.sin(2 * np.pi * f_hz * time_s[:, None] + rng.uniform(0, 2 * np.pi, 2))
    path += rng.normal(0.0, noise_m, path.shape)         # position sensor noise
    contact = np.ones(n, dtype=bool)
    for a in rng.integers(0, n - n // 1000, 20):
        contact[a:a + n // 1000] = False
    return path, contact


def shapely_coverage(path: np.ndarray, contact: np.ndarray) -> float:
    """Coverage, %, the way a user would compute it with shapely."""
    import shapely
    from shapely.geometry import LineString, Point, Polygon

    edges = np.flatnonzero(np.diff(np.concatenate([[0], contact.astype(np.int8), [0]])))
    parts = []
    for a, b in zip(edges[::2], edges[1::2]):
        run = path[a:b]
        geom = Point(run[0]) if len(run) == 1 else LineString(run)
        parts.append(geom.buffer(WIDTH / 2))
    panel = Polygon(PANEL, [HOLE])
    cleaned = shapely.union_all(parts).intersection(panel)
    return 100.0 * cleaned.area / panel.area


def _kept(path: np.ndarray, contact: np.ndarray, h: float) -> int:
    """How many samples coverage_map keeps after decimation (its default tolerances)."""
    return len(decimate_path(path, contact, tol_m=DECIMATE_CELLS * h, max_chord_m=0.05 * WIDTH))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="one repeat")
    args = ap.parse_args()
    repeats = 1 if args.quick else 5
    print(f"machine: {machine()}")
    n = 600_000
    path, contact = boustrophedon(n)
    run = lambda: coverage_map(PANEL, [HOLE], path, contact, width_m=WIDTH)  # noqa: E731
    t0 = time.perf_counter()
    cm = run()
    first = time.perf_counter() - t0
    cm, t = best_of(repeats, run)
    print(f"path: {n:,} samples (1 ms), {np.linalg.norm(np.diff(path, axis=0), axis=1).sum():.1f} m, "
          f"{100 * contact.mean():.1f} % in contact; panel 2 x 1.4 m less a 0.3 x 0.2 m hole; brush {WIDTH} m")
    print(f"raster: {cm.passes.shape[1]} x {cm.passes.shape[0]} cells of {1e3 * cm.resolution_m:.3f} mm; "
          f"{_kept(path, contact, cm.resolution_m):,} samples kept after decimation")
    print(f"  coverage_map          {t:7.3f} s (best of {repeats}; first call {first:.2f} s with compile/cache load)"
          f"   coverage {cm.coverage_pct:.3f} %  overlap {cm.overlap_pct:.2f} % of cleaned")
    noisy, _ = boustrophedon(n, noise_m=3e-4)
    cmn, tn = best_of(repeats, lambda: coverage_map(PANEL, [HOLE], noisy, contact, width_m=WIDTH))
    print(f"  same, 0.3 mm white noise ({_kept(noisy, contact, cmn.resolution_m):,} kept) "
          f"{tn:7.3f} s   coverage {cmn.coverage_pct:.3f} %  overlap {cmn.overlap_pct:.2f} % of cleaned")
    if importlib.util.find_spec("shapely") is None:
        print("  shapely                not installed: no side-by-side figure")
        return
    pct, ts = best_of(1 if args.quick else 2, lambda: shapely_coverage(path, contact))
    print(f"  shapely buffer/union  {ts:7.3f} s   coverage {pct:.3f} %   "
          f"(coverage_map {ts / t:.0f}x faster; difference {cm.coverage_pct - pct:+.3f} points)")


if __name__ == "__main__":
    main()
