"""The ``rao`` command: a hull's RAOs from the BEM code Capytaine (pip install 'marinecdpr[bem]'): a box or
    Wigley hull of given main dimensions, or a hull mesh (--mesh, with --kg). Writes rao.nc
    ([base_motion.rao] source = "capytaine"), the same table as rao.csv (source = "csv",
    read without the extra) and rao.png, beside the built-in box approximation (of the same
    main dimensions)."""

from __future__ import annotations

import math
import time
from pathlib import Path
from typing import Optional

import typer

from marinecdpr.cli.common import console, count, err_console, fail, headings_option, number, output, plain
from marinecdpr.cli.progress import seconds
from marinecdpr.errors import ScenarioError


MAX_RAO_FREQUENCIES = 2000
"""Most wave frequencies ``rao --omega`` takes (a table of 33 is typical)."""


def rao(
    length: Optional[float] = typer.Option(None, help="The hull's length, m."),
    beam: Optional[float] = typer.Option(None, help="Its beam, m."),
    draught: Optional[float] = typer.Option(None, help="Its draught, m."),
    gm: Optional[float] = typer.Option(None, help="Its transverse metacentric height GM, m."),
    mesh: Optional[Path] = typer.Option(None, help="A hull mesh instead (GDF, STL, Nemoh, HST, PNL): its RAOs, and "
                                        "its hydrostatics from its panels."),
    kg: Optional[float] = typer.Option(None, help="With --mesh: the centre of gravity's height above the keel, m "
                                       "(GM = KB + BM - KG)."),
    mesh_units: str = typer.Option("m", help="With --mesh: its length unit: m, cm, mm or ft."),
    waterline: float = typer.Option(0.0, help="With --mesh: the waterline's z in the mesh, in its units."),
    roll_damping: float = typer.Option(0.05, help="Viscous roll damping, a fraction of critical (BEM has none)."),
    headings: str = typer.Option("90,120,150,180", help="Wave headings, deg, comma-separated."),
    omega: str = typer.Option("0.2:1.8:33", help="Wave frequencies first:last:count, rad/s."),
    panel: Optional[float] = typer.Option(None, help="About the panels' size, m (default 2.5; not with --mesh)."),
    hull: Optional[str] = typer.Option(None, help="The hull's form: box (default), or wigley (the analytic ship form, "
                                       "fine ends); not with --mesh."),
    out: Path = typer.Option(Path("out"), "--out", "-o", help="Folder for rao.nc and rao.png."),
) -> None:
    """A hull's RAOs from the BEM code Capytaine (pip install 'marinecdpr[bem]'): a box or
    Wigley hull of given main dimensions, or a hull mesh (--mesh, with --kg). Writes rao.nc
    ([base_motion.rao] source = "capytaine"), the same table as rao.csv (source = "csv",
    read without the extra) and rao.png, beside the built-in box approximation (of the same
    main dimensions)."""
    import numpy as np

    from marinecdpr import __version__
    from marinecdpr.motion.bem import HULL_SHAPES, hull_bem
    from marinecdpr.report.writers import write_rao

    if mesh is not None:
        given = [f"--{n}" for n, v in (("length", length), ("beam", beam), ("draught", draught), ("gm", gm),
                                       ("panel", panel), ("hull", hull)) if v is not None]
        if given:
            fail(f"--mesh {mesh}: {', '.join(given)} cannot go with it: the mesh gives the hull "
                  "(its GM from --kg)")
        if kg is None:
            fail(f"--mesh {mesh}: give --kg, the centre of gravity's height above the keel, m")
        number("--kg", kg)
    else:
        missing = [f"--{n}" for n, v in (("length", length), ("beam", beam), ("draught", draught), ("gm", gm))
                   if v is None]
        if missing:
            fail(f"missing {', '.join(missing)}: give the hull's main dimensions and GM, or --mesh FILE --kg KG")
        if kg is not None:
            fail("--kg goes with --mesh (a box or Wigley hull takes --gm)")
        hull = hull or "box"
        panel = 2.5 if panel is None else panel
        if hull not in HULL_SHAPES:
            fail(f"--hull {hull}: expected one of {', '.join(HULL_SHAPES)}")
        for name, value in (("--length", length), ("--beam", beam), ("--draught", draught), ("--gm", gm),
                            ("--panel", panel)):
            number(name, value)
    number("--roll-damping", roll_damping, zero_ok=True)
    if roll_damping > 1.0:
        fail(f"--roll-damping {roll_damping:g}: expected a fraction of critical damping from 0 to 1")
    from marinecdpr.planning.budget import check_bem_size

    heads = tuple(sorted(h % 360.0 for h in headings_option(headings, "90,180")))
    try:
        first, last, count = omega.split(":")
        first, last, count = float(first), float(last), int(count)
    except ValueError:
        fail(f"--omega {omega}: expected first:last:count, e.g. 0.2:1.8:33")
    if not (math.isfinite(first) and math.isfinite(last) and 0 < first < last and 2 <= count <= MAX_RAO_FREQUENCIES):
        fail(f"--omega {omega}: expected first:last:count with 0 < first < last and 2 <= count <= "
              f"{MAX_RAO_FREQUENCIES}")
    w = np.linspace(first, last, count)
    if mesh is not None:
        return _rao_mesh(mesh, kg=kg, units=mesh_units, waterline=waterline, roll_damping=roll_damping, heads=heads,
                         w=w, omega=omega, out=out)
    try:  # before any work: a BEM the machine cannot hold or finish is one line
        check_bem_size(shape=hull, length_m=length, beam_m=beam, draught_m=draught, panel_m=panel,
                       frequencies=count, headings=len(heads))
    except (ScenarioError, ValueError) as exc:
        fail(str(exc))
    t0 = time.perf_counter()
    with output(out) as folder:
        try:
            ds = hull_bem(shape=hull, length_m=length, beam_m=beam, draught_m=draught, gm_m=gm,
                          roll_damping_ratio=roll_damping, omega=w, heading_deg=heads, panel_m=panel)
        except (ScenarioError, ValueError) as exc:
            fail(str(exc))
        made = (f"marinecdpr rao {'' if hull == 'box' else f'--hull {hull} '}--length {length:g} --beam {beam:g} "
                f"--draught {draught:g} --gm {gm:g} "
                f"--roll-damping {roll_damping:g} --headings {','.join(f'{h:g}' for h in heads)} --omega {omega} "
                f"--panel {panel:g} (marinecdpr {__version__})")
        box_label = "box approximation" + ("" if hull == "box" else " of the same main dimensions")
        try:  # a result the tables refuse (not finite, beyond their ranges) is one line, not a traceback
            bem, box, paths = write_rao(ds, folder, made_by=made, box=dict(length_m=length, beam_m=beam,
                                                                            draught_m=draught, gm_m=gm,
                                                                            roll_damping_ratio=roll_damping),
                                        box_label=box_label)
        except (ScenarioError, ValueError) as exc:
            fail(f"the BEM's RAOs for these dimensions cannot be written: {exc}")
    peak = float(np.degrees(np.abs(bem.values[3])).max())
    console.print(plain(f"{ds.attrs['hull']}: roll peaks at {peak:.3g} deg/m ({box_label} "
                         f"{float(np.degrees(np.abs(box.values[3])).max()):.3g}); written to {out}/: "
                         f"{', '.join(p.name for p in paths)} ({time.perf_counter() - t0:.1f} s)"),
                  highlight=False, soft_wrap=True)


def _rao_mesh(mesh: Path, *, kg: float, units: str, waterline: float, roll_damping: float, heads: tuple, w,
              omega: str, out: Path) -> None:
    """``rao --mesh``: the mesh read and checked, its size and run time said, then the BEM."""
    import numpy as np

    from marinecdpr import __version__
    from marinecdpr.motion.bem import mesh_bem
    from marinecdpr.motion.hullmesh import load_hull_mesh
    from marinecdpr.planning.budget import check_bem_size
    from marinecdpr.report.writers import write_rao

    try:
        hull = load_hull_mesh(mesh, units=units, waterline_m=waterline)
        size = check_bem_size(panels=hull.panels, frequencies=len(w), headings=len(heads), what=f"the mesh {mesh}")
    except (ScenarioError, ValueError) as exc:
        fail(str(exc))
    err_console.print(plain(f"mesh: {mesh}: {hull.panels} panels below the waterline, {hull.length_m:.4g} x "
                             f"{hull.beam_m:.4g} x {hull.draught_m:.4g} m; the BEM at {len(w)} frequencies takes "
                             f"about {seconds(size.seconds)}"), highlight=False, soft_wrap=True)
    t0 = time.perf_counter()
    with output(out) as folder:
        try:
            ds = mesh_bem(hull, kg_m=kg, roll_damping_ratio=roll_damping, omega=w, heading_deg=heads,
                          label=f"mesh {mesh.name}")
        except (ScenarioError, ValueError) as exc:
            fail(f"--mesh {mesh}: {exc}")
        made = (f"marinecdpr rao --mesh {mesh} --kg {kg:g} --mesh-units {units} --waterline {waterline:g} "
                f"--roll-damping {roll_damping:g} --headings {','.join(f'{h:g}' for h in heads)} --omega {omega} "
                f"(marinecdpr {__version__})")
        box = dict(length_m=hull.length_m, beam_m=hull.beam_m, draught_m=hull.draught_m, gm_m=float(ds.attrs["gm_m"]),
                   roll_damping_ratio=roll_damping)
        try:
            bem, approx, paths = write_rao(ds, folder, made_by=made, box=box,
                                           box_label="box approximation of the same main dimensions and GM")
        except (ScenarioError, ValueError) as exc:
            fail(f"the BEM's RAOs for this mesh cannot be written: {exc}")
    a = ds.attrs
    console.print(plain(f"hydrostatics from the mesh: displacement {a['volume_m3']:.5g} m3, waterplane "
                         f"{a['waterplane_area_m2']:.5g} m2, KB {a['kb_m']:.4g} m, BM {a['bm_m']:.4g} m, GM "
                         f"{a['gm_m']:.4g} m (KG {kg:g} m)"), highlight=False, soft_wrap=True)
    peak = float(np.degrees(np.abs(bem.values[3])).max())
    console.print(plain(f"{a['hull']}: roll peaks at {peak:.3g} deg/m (box approximation "
                         f"{float(np.degrees(np.abs(approx.values[3])).max()):.3g}); written to {out}/: "
                         f"{', '.join(p.name for p in paths)} ({time.perf_counter() - t0:.1f} s)"),
                  highlight=False, soft_wrap=True)
