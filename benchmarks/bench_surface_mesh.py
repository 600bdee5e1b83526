"""A hull mesh's side as the cleaning surface: the binned search against testing every
triangle for every point (numpy broadcasting over (points, triangles), which is what the
toolkit did before and what a user would write), and a surface job on a meshed hull.

Run:  .venv/bin/python benchmarks/bench_surface_mesh.py [--quick]

Prints, for Wigley hulls of 100 x 20 x 6 m in 1 m and 0.5 m panels (5 200 and 20 800
triangles; a real ship's mesh has up to the toolkit's 50 000 panels): points per second of
:func:`~marinecdpr.geometry.surface.mesh_side` and of the every-triangle search over the
same 20 000 points (their values equal bit for bit), and the seconds of paper_clean's
``surface_job`` on the 1 m mesh's band.
"""

from __future__ import annotations

import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from _common import best_of, machine  # benchmarks/_common.py (the script's folder is on sys.path)


def every_triangle(vertices, triangles, side="port"):
    """y = f(x, z) testing every triangle for every point, in chunks of 256 points."""
    sign = 1.0 if side == "port" else -1.0
    P = np.asarray(vertices, dtype=float)[np.asarray(triangles)]
    normal = np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0])
    P = P[sign * normal[:, 1] > 0]
    a, b, c = P[:, 0], P[:, 1], P[:, 2]
    det = (b[:, 0] - a[:, 0]) * (c[:, 2] - a[:, 2]) - (c[:, 0] - a[:, 0]) * (b[:, 2] - a[:, 2])
    ok = np.abs(det) > 1e-15
    a, b, c, det = a[ok], b[ok], c[ok], det[ok]

    def f(x, z):
        out = np.full(x.size, np.nan)
        for i0 in range(0, x.size, 256):
            px, pz = x[i0:i0 + 256, None], z[i0:i0 + 256, None]
            l1 = ((px - a[:, 0]) * (c[:, 2] - a[:, 2]) - (c[:, 0] - a[:, 0]) * (pz - a[:, 2])) / det
            l2 = ((b[:, 0] - a[:, 0]) * (pz - a[:, 2]) - (px - a[:, 0]) * (b[:, 2] - a[:, 2])) / det
            inside = (l1 >= -1e-12) & (l2 >= -1e-12) & (l1 + l2 <= 1 + 1e-12)
            y = sign * (a[:, 1] + l1 * (b[:, 1] - a[:, 1]) + l2 * (c[:, 1] - a[:, 1]))
            y = np.where(inside, y, -np.inf).max(axis=1)
            out[i0:i0 + 256] = np.where(np.isfinite(y), y, np.nan)
        return out

    return f


def main() -> None:
    import marinecdpr
    from marinecdpr.geometry.surface import mesh_side
    from marinecdpr.motion.hullmesh import faces_to_triangles, read_mesh, write_wigley_gdf
    from marinecdpr.studies.surface import surface_job

    print(f"machine: {machine()}")
    quick = "--quick" in sys.argv
    rng = np.random.default_rng(0)
    n = 20_000
    x, z = rng.uniform(-50.0, 50.0, n), rng.uniform(-6.0, 0.0, n)
    with tempfile.TemporaryDirectory() as tmp:
        for panel in (1.0,) if quick else (1.0, 0.5):
            v, faces = read_mesh(write_wigley_gdf(Path(tmp) / "w.gdf", length_m=100.0, beam_m=20.0, draught_m=6.0,
                                                  panel_m=panel))
            tri = faces_to_triangles(faces)
            binned, brute = mesh_side(v, tri), every_triangle(v, tri)
            assert np.array_equal(binned(x, z), brute(x, z), equal_nan=True)
            _, t_b = best_of(3, lambda: binned(x, z))
            _, t_e = best_of(1, lambda: brute(x, z))
            print(f"{len(tri):6d} triangles, {n} points: binned {n / t_b:12,.0f} points/s, "
                  f"every triangle {n / t_e:10,.0f} points/s ({t_e / t_b:.0f}x)")
        gdf = write_wigley_gdf(Path(tmp) / "w1.gdf", length_m=100.0, beam_m=20.0, draught_m=6.0, panel_m=1.0)
        sc = marinecdpr.load_scenario("paper_clean").with_updates(
            "cleaning.surface", form="mesh", mesh=str(gdf), length_m=None, beam_m=None, draught_m=None, flare=None,
            stations_m=[-40.0, 40.0], heights_m=[-5.0, -0.5], stand_off_tolerance_m=0.02)
        t0 = time.perf_counter()
        job = surface_job(sc, move_time_s=600.0, panel_m=(2.0, 1.5))
        print(f"surface_job on the 1 m mesh's band (80 x 4.5 m): {len(job.placements)} placements "
              f"in {time.perf_counter() - t0:.2f} s")


if __name__ == "__main__":
    main()
