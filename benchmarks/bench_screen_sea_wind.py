"""The fast screen with a wind per sea state (issue 40, item 1: ``[wind] with_sea``): its cost
beside one wind for every sea state, and what the wind does to the verdict.

Run:  PYTHONPATH=src .venv/bin/python benchmarks/bench_screen_sea_wind.py

paper_clean's job over the package's illustrative scatter diagram at headings 180, 150 and 90
(102 sea states), its platform given a flat plate's drag (C = 2, faces of 0.03, 0.075 and
0.025 m^2 normal to P's x, y, z; 4 mm cables): the screen (:func:`screen_cells`, the model made
once) without a wind, with one fixed wind (the Pierson-Moskowitz wind of paper_clean's own sea
state, Hs 2 m: 8.9 m/s, in every sea state), and with the Pierson-Moskowitz wind of each sea
state (one linearisation per distinct wind: Hs x heading). Prints the best of 3 wall times,
the distinct winds, and the share of the sea states (by probability) in which the job works.
"""

from __future__ import annotations

import time

from _common import best_of, machine  # benchmarks/_common.py (the script's folder is on sys.path)


def main() -> None:
    import marinecdpr
    from marinecdpr.studies import screen as S
    from marinecdpr.studies.operability import illustrative_scatter_path, read_scatter_csv, scatter_cells, wind_scenario

    print(machine())
    base = marinecdpr.load_scenario("paper_clean")
    drag = {"platform_shape_coefficient": 2.0, "platform_area_m2": [0.03, 0.075, 0.025], "cable_diameter_m": 0.004}
    with_sea = base.with_changes(wind=drag | {"with_sea": "pierson_moskowitz"})
    fixed = wind_scenario(with_sea, (with_sea.wind.speed_m_s, with_sea.wind.direction_deg))
    cells = scatter_cells(read_scatter_csv(illustrative_scatter_path()), (180.0, 150.0, 90.0))
    print(f"{len(cells)} sea states; {len(S.wind_groups(with_sea, cells))} distinct Pierson-Moskowitz winds")
    for name, sc in (("no wind", base), ("one wind (8.9 m/s) in every sea state", fixed),
                     ("each sea state's own wind", with_sea)):
        t0 = time.perf_counter()
        model = S.screen_model(sc)
        build = time.perf_counter() - t0
        result, t = best_of(3, lambda: S.screen_cells(sc, cells, model=model))
        print(f"{name:40s} model {build:6.2f} s, screen {1e3 * t:7.1f} ms, works in {100 * result.share:.2f} % "
              f"({int(result.works.sum())} of {len(cells)} sea states), least margin {result.margin_N.min():.2f} N")


if __name__ == "__main__":
    main()
