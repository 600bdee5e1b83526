"""`rao --mesh` speed: reading and checking a hull mesh, and the BEM of a 2 000-panel hull.

Run:  .venv/bin/python benchmarks/bench_rao_mesh.py [--quick]

Prints, for the project's Wigley hull (100 x 20 x 6 m) written as GDF at about 2 000 panels
below the waterline (``--quick``: about 700):
  * marinecdpr's load_hull_mesh (Capytaine's reader, then the checks: closed below the
    waterline, normals, a ship's size, and the exact hydrostatics) against Capytaine's
    load_mesh + immersed_part + its own hydrostatics (what a user would call), and the
    two GMs' distance to the closed form's;
  * the run-time estimate `rao --mesh` prints before the BEM, and the BEM's wall time at
    33 frequencies and 4 headings (``--quick``: 8 frequencies).
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

import numpy as np

from _common import best_of, machine  # benchmarks/_common.py (the script's folder is on sys.path)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    args = parser.parse_args()
    import capytaine as cpt

    from marinecdpr.motion.bem import bem_panels, mesh_bem, wigley_hydrostatics
    from marinecdpr.motion.hullmesh import load_hull_mesh, write_wigley_gdf
    from marinecdpr.planning.budget import bem_size

    print(machine(), f"Capytaine {cpt.__version__}")
    L, B, T = 100.0, 20.0, 6.0
    panel = 2.0 if args.quick else 1.15
    n = bem_panels(shape="wigley", length_m=L, beam_m=B, draught_m=T, panel_m=panel)
    folder = Path(tempfile.mkdtemp())
    path = write_wigley_gdf(folder / "wigley.gdf", length_m=L, beam_m=B, draught_m=T, panel_m=panel)
    hull, t_ours = best_of(3, lambda: load_hull_mesh(path))

    def capytaine_alone():
        mesh = cpt.load_mesh(str(path), file_format="gdf").immersed_part()
        body = cpt.FloatingBody(mesh=mesh, dofs=cpt.rigid_body_dofs(), center_of_mass=(0, 0, 7.0 - T))
        return body.compute_hydrostatics()

    hs, t_cpt = best_of(3, capytaine_alone)
    ref = wigley_hydrostatics(L, B, T)
    kg = 7.0
    gm_ref = ref.kb_m + ref.bm_m - kg
    gm_ours = hull.hydrostatics.kb_m + hull.hydrostatics.bm_m - kg
    gm_cpt = float(hs["transversal_metacentric_height"]) if "transversal_metacentric_height" in hs else float("nan")
    print(f"Wigley {L:g} x {B:g} x {T:g} m at {panel:g} m panels: {hull.panels} panels below the waterline "
          f"(estimate {n})")
    print(f"  load and check, marinecdpr (exact hydrostatics): {t_ours * 1e3:8.1f} ms; GM {gm_ours:.4f} m "
          f"(closed form {gm_ref:.4f} m, {100 * (gm_ours / gm_ref - 1):+.2f} %)")
    print(f"  Capytaine load_mesh + compute_hydrostatics:       {t_cpt * 1e3:8.1f} ms; GM {gm_cpt:.4f} m "
          f"({100 * (gm_cpt / gm_ref - 1):+.2f} %)")
    nw, nh = (8, 4) if args.quick else (33, 4)
    size = bem_size(hull.panels, frequencies=nw, headings=nh)
    t0 = time.perf_counter()
    mesh_bem(hull, kg_m=kg, roll_damping_ratio=0.05, omega=np.linspace(0.2, 1.8, nw),
             heading_deg=np.array([90.0, 120.0, 150.0, 180.0]))
    wall = time.perf_counter() - t0
    print(f"  BEM at {nw} frequencies x {nh} headings: estimated {size.seconds:.0f} s, took {wall:.1f} s "
          f"({wall / nw:.2f} s per frequency)")


if __name__ == "__main__":
    main()
