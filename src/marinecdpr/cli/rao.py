"""The ``rao`` command: a hull's RAOs from the BEM code Capytaine (pip install 'marinecdpr[bem]'): a box or
    Wigley hull of given main dimensions, or a hull mesh (--mesh, with --kg). Writes rao.nc
    ([base_motion.rao] source = "capytaine"), the same table as rao.csv (source = "csv",
    read without the extra) and rao.png, beside the built-in box approximation (of the same
    main dimensions).

Options to :class:`~marinecdpr.commands.rao.RaoSpec`, the work to :mod:`marinecdpr.commands.rao`,
the result to lines."""

from __future__ import annotations

import time
from pathlib import Path
from typing import Optional

import typer

from marinecdpr.cli.common import console, err_console, fail, fail_spec, figures_option, output, plain, spec_of
from marinecdpr.cli.progress import seconds
from marinecdpr.commands.base import SpecError
from marinecdpr.commands.rao import RaoSpec
from marinecdpr.errors import ScenarioError


def rao(
    length: Optional[float] = typer.Option(RaoSpec.default("length"), help="The hull's length, m."),
    beam: Optional[float] = typer.Option(RaoSpec.default("beam"), help="Its beam, m."),
    draught: Optional[float] = typer.Option(RaoSpec.default("draught"), help="Its draught, m."),
    gm: Optional[float] = typer.Option(RaoSpec.default("gm"), help="Its transverse metacentric height GM, m."),
    mesh: Optional[Path] = typer.Option(RaoSpec.default("mesh"), help="A hull mesh instead (GDF, STL, Nemoh, HST, "
                                        "PNL): its RAOs, and its hydrostatics from its panels."),
    kg: Optional[float] = typer.Option(RaoSpec.default("kg"), help="With --mesh: the centre of gravity's height above "
                                       "the keel, m (GM = KB + BM - KG)."),
    mesh_units: str = typer.Option(RaoSpec.default("mesh_units"), help="With --mesh: its length unit: m, cm, mm or "
                                   "ft."),
    waterline: float = typer.Option(RaoSpec.default("waterline"), help="With --mesh: the waterline's z in the mesh, "
                                    "in its units."),
    roll_damping: float = typer.Option(RaoSpec.default("roll_damping"), help="Viscous roll damping, a fraction of "
                                       "critical (BEM has none)."),
    headings: str = typer.Option(",".join(f"{h:g}" for h in RaoSpec.default("headings")),
                                 help="Wave headings, deg, comma-separated."),
    omega: str = typer.Option(RaoSpec.default("omega"), help="Wave frequencies first:last:count, rad/s."),
    panel: Optional[float] = typer.Option(RaoSpec.default("panel"), help="About the panels' size, m (default 2.5; not "
                                          "with --mesh)."),
    hull: Optional[str] = typer.Option(RaoSpec.default("hull"), help="The hull's form: box (default), or wigley (the "
                                       "analytic ship form, fine ends); not with --mesh."),
    out: Path = typer.Option(Path("out"), "--out", "-o", help="Folder for rao.nc and rao.png."),
    figures: bool = figures_option("rao.png"),
) -> None:
    """A hull's RAOs from the BEM code Capytaine (pip install 'marinecdpr[bem]'): a box or
    Wigley hull of given main dimensions, or a hull mesh (--mesh, with --kg). Writes rao.nc
    ([base_motion.rao] source = "capytaine"), the same table as rao.csv (source = "csv",
    read without the extra) and rao.png, beside the built-in box approximation (of the same
    main dimensions)."""
    import numpy as np

    from marinecdpr.commands import rao as command

    spec = spec_of(RaoSpec, length=length, beam=beam, draught=draught, gm=gm, mesh=mesh, kg=kg, mesh_units=mesh_units,
                   waterline=waterline, roll_damping=roll_damping, headings=headings, omega=omega, panel=panel,
                   hull=hull, figures=figures)
    try:  # before any work: a mesh that is no hull, a BEM the machine cannot hold or finish, is one line
        est = command.estimate(spec)
    except (ScenarioError, ValueError) as exc:
        fail(str(exc))
    if spec.mesh is not None:
        h = est.hull
        err_console.print(plain(f"mesh: {spec.mesh}: {h.panels} panels below the waterline, {h.length_m:.4g} x "
                                f"{h.beam_m:.4g} x {h.draught_m:.4g} m; the BEM at {est.size.frequencies} frequencies "
                                f"takes about {seconds(est.size.seconds)}"), highlight=False, soft_wrap=True)
    t0 = time.perf_counter()
    with output(out) as folder:
        try:
            result = command.run(spec, estimated=est)
        except SpecError as exc:  # a mesh the BEM refuses
            fail_spec(exc)
        except (ScenarioError, ValueError) as exc:
            fail(str(exc))
        try:  # a result the tables refuse (not finite, beyond their ranges) is one line, not a traceback
            files = result.write_tables(folder)
        except (ScenarioError, ValueError) as exc:
            fail(f"the BEM's RAOs for {'this mesh' if spec.mesh is not None else 'these dimensions'} cannot be "
                 f"written: {exc}")
    a = result.ds.attrs
    if spec.mesh is not None:
        console.print(plain(f"hydrostatics from the mesh: displacement {a['volume_m3']:.5g} m3, waterplane "
                            f"{a['waterplane_area_m2']:.5g} m2, KB {a['kb_m']:.4g} m, BM {a['bm_m']:.4g} m, GM "
                            f"{a['gm_m']:.4g} m (KG {spec.kg:g} m)"), highlight=False, soft_wrap=True)
    peak = float(np.degrees(np.abs(files.bem.values[3])).max())
    label = "box approximation" if spec.mesh is not None else result.box_label
    console.print(plain(f"{a['hull']}: roll peaks at {peak:.3g} deg/m ({label} "
                        f"{float(np.degrees(np.abs(files.approx.values[3])).max()):.3g}); written to {out}/: "
                        f"{', '.join(p.name for p in files.paths)} ({time.perf_counter() - t0:.1f} s)"),
                  highlight=False, soft_wrap=True)
