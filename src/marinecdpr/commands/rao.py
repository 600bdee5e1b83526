"""``rao``: a hull's RAOs from the BEM code Capytaine (the ``bem`` extra): a box or Wigley
hull of given main dimensions and GM, or a hull mesh with its centre of gravity's height
(``mesh``, ``kg``), beside the built-in box approximation of the same main dimensions.

:class:`RaoSpec` holds the options (the one source of their defaults and of the rules on
which go together), :func:`estimate` sizes the BEM (and reads and checks the mesh) before
any work, :func:`run` solves it (:class:`RaoResult`). There is no scenario: the spec gives
the hull."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from pydantic import field_validator, model_validator

from marinecdpr.commands.base import Spec, SpecError, figures_field, finite, headings, positive

if TYPE_CHECKING:
    import numpy as np

    from marinecdpr.planning.budget import BemSize

__all__ = ["RaoSpec", "RaoEstimate", "RaoResult", "estimate", "run", "MAX_RAO_FREQUENCIES", "DEFAULT_PANEL_M"]

MAX_RAO_FREQUENCIES = 2000
"""Most wave frequencies ``rao --omega`` takes (a table of 33 is typical)."""
DEFAULT_PANEL_M = 2.5
"""About the panels' size of a box or Wigley hull where ``panel`` is not given, m."""
_HULL_DIMENSIONS = ("length", "beam", "draught", "gm")


class RaoSpec(Spec):
    """The options of a BEM run.

    Attributes
    ----------
    length, beam, draught : float, optional
        A box or Wigley hull's main dimensions, m (all three, with ``gm``; not with ``mesh``).
    gm : float, optional
        Its transverse metacentric height GM, m.
    mesh : Path, optional
        A hull mesh instead (GDF, STL, Nemoh, HST, PNL): its RAOs, and its hydrostatics from
        its panels (with ``kg``).
    kg : float, optional
        With ``mesh``: the centre of gravity's height above the keel, m (GM = KB + BM - KG).
    mesh_units : str
        With ``mesh``: its length unit, m, cm, mm or ft.
    waterline : float
        With ``mesh``: the waterline's z in the mesh, in its units.
    roll_damping : float
        Viscous roll damping, a fraction of critical from 0 to 1 (BEM has none).
    headings : tuple of float
        Wave headings, deg (``"90,180"`` is taken too); kept modulo 360 deg, in increasing order.
    omega : str
        Wave frequencies ``first:last:count``, rad/s: ``count`` evenly from ``first`` to
        ``last`` (a tuple ``(first, last, count)`` is taken too); 0 < first < last,
        2 <= count <= :data:`MAX_RAO_FREQUENCIES`.
    panel : float, optional
        About the panels' size, m (default :data:`DEFAULT_PANEL_M`; not with ``mesh``).
    hull : {"box", "wigley"}, optional
        The hull's form (default box; not with ``mesh``).
    figures : bool
        Draw ``rao.png`` (default: the defaults table's ``"report.figures"``,
        :mod:`marinecdpr.defaults`; True as shipped).
    """

    length: float | None = None
    beam: float | None = None
    draught: float | None = None
    gm: float | None = None
    mesh: Path | None = None
    kg: float | None = None
    mesh_units: str = "m"
    waterline: float = 0.0
    roll_damping: float = 0.05
    headings: tuple[float, ...] = (90.0, 120.0, 150.0, 180.0)
    omega: str = "0.2:1.8:33"
    panel: float | None = None
    hull: str | None = None
    figures: bool = figures_field()

    @field_validator("length", "beam", "draught", "gm", "kg", "panel")
    @classmethod
    def _positive(cls, v):
        return positive(v)

    @field_validator("waterline")
    @classmethod
    def _waterline(cls, v):
        return finite(v)

    @field_validator("roll_damping")
    @classmethod
    def _roll_damping(cls, v):
        positive(v, zero_ok=True)
        if v > 1.0:
            raise ValueError("expected a fraction of critical damping from 0 to 1")
        return v

    @field_validator("headings", mode="before")
    @classmethod
    def _headings(cls, v):
        return tuple(sorted(h % 360.0 for h in headings(v, example="90,180")))

    @field_validator("omega", mode="before")
    @classmethod
    def _omega(cls, v):
        if isinstance(v, (tuple, list)) and len(v) == 3:
            v = f"{v[0]:g}:{v[1]:g}:{v[2]}"
        try:
            first, last, count = str(v).split(":")
            first, last, count = float(first), float(last), int(count)
        except ValueError:
            raise ValueError("expected first:last:count, e.g. 0.2:1.8:33") from None
        if not (math.isfinite(first) and math.isfinite(last) and 0 < first < last
                and 2 <= count <= MAX_RAO_FREQUENCIES):
            raise ValueError(f"expected first:last:count with 0 < first < last and 2 <= count <= "
                             f"{MAX_RAO_FREQUENCIES}")
        return str(v)

    @field_validator("hull")
    @classmethod
    def _hull(cls, v):
        from marinecdpr.motion.bem import HULL_SHAPES

        if v is not None and v not in HULL_SHAPES:
            raise ValueError(f"expected one of {', '.join(HULL_SHAPES)}")
        return v

    @model_validator(mode="after")
    def _together(self):
        if self.mesh is not None:
            given = [f"--{n}" for n in (*_HULL_DIMENSIONS, "panel", "hull") if getattr(self, n) is not None]
            if given:
                raise SpecError("mesh", self.mesh, f"{', '.join(given)} cannot go with it: the mesh gives the hull "
                                "(its GM from --kg)")
            if self.kg is None:
                raise SpecError("mesh", self.mesh, "give --kg, the centre of gravity's height above the keel, m")
            return self
        missing = [n for n in _HULL_DIMENSIONS if getattr(self, n) is None]
        if missing:
            raise SpecError(missing[0], "not given", "give the hull's main dimensions and GM (missing "
                            f"{', '.join('--' + n for n in missing)}), or --mesh FILE --kg KG")
        if self.kg is not None:
            raise SpecError("kg", self.kg, "goes with --mesh (a box or Wigley hull takes --gm)")
        return self

    @property
    def frequencies(self) -> np.ndarray:
        """The wave frequencies solved, rad/s, shape (count,)."""
        import numpy as np

        first, last, count = self.omega.split(":")
        return np.linspace(float(first), float(last), int(count))

    @property
    def shape(self) -> str:
        """The hull's form without a mesh: ``hull``, default box."""
        return self.hull or "box"

    @property
    def panel_m(self) -> float:
        """The panels' size without a mesh, m: ``panel``, default :data:`DEFAULT_PANEL_M`."""
        return DEFAULT_PANEL_M if self.panel is None else self.panel


@dataclass(frozen=True)
class RaoEstimate:
    """What the BEM will take, known before it starts.

    Attributes
    ----------
    size : BemSize
        Panels, frequencies, headings, memory and seconds (:func:`~marinecdpr.planning.budget.check_bem_size`).
    hull : HullMesh, optional
        With ``mesh``: the wetted surface read and checked (:func:`~marinecdpr.motion.hullmesh.load_hull_mesh`).
    """

    size: BemSize
    hull: Any = None


def estimate(spec: RaoSpec) -> RaoEstimate:
    """The BEM's size, refused where the machine cannot hold or finish it; with ``mesh`` the
    mesh read and checked first.

    Raises
    ------
    ScenarioError, ValueError
        One line: a mesh that cannot be read or is no hull, or a BEM too big.
    """
    from marinecdpr.planning.budget import check_bem_size

    heads = len(spec.headings)
    count = len(spec.frequencies)
    if spec.mesh is not None:
        from marinecdpr.motion.hullmesh import load_hull_mesh

        hull = load_hull_mesh(spec.mesh, units=spec.mesh_units, waterline_m=spec.waterline)
        size = check_bem_size(panels=hull.panels, frequencies=count, headings=heads, what=f"the mesh {spec.mesh}")
        return RaoEstimate(size=size, hull=hull)
    size = check_bem_size(shape=spec.shape, length_m=spec.length, beam_m=spec.beam, draught_m=spec.draught,
                          panel_m=spec.panel_m, frequencies=count, headings=heads)
    return RaoEstimate(size=size)


@dataclass(frozen=True)
class RaoResult:
    """A BEM run's RAOs.

    Attributes
    ----------
    spec : RaoSpec
    ds : xarray.Dataset
        Capytaine's dataset (:func:`~marinecdpr.motion.bem.hull_bem`, :func:`~marinecdpr.motion.bem.mesh_bem`):
        ``RAO``, the matrices, attributes naming the hull (with a mesh, its hydrostatics).
    hull : HullMesh, optional
        With ``mesh``: the wetted surface solved.
    """

    spec: RaoSpec
    ds: Any
    hull: Any = None

    @property
    def made_by(self) -> str:
        """The command that makes these RAOs (``rao.csv``'s first lines say it)."""
        from marinecdpr import __version__

        s = self.spec
        heads = ",".join(f"{h:g}" for h in s.headings)
        if s.mesh is not None:
            return (f"marinecdpr rao --mesh {s.mesh} --kg {s.kg:g} --mesh-units {s.mesh_units} --waterline "
                    f"{s.waterline:g} --roll-damping {s.roll_damping:g} --headings {heads} --omega {s.omega} "
                    f"(marinecdpr {__version__})")
        return (f"marinecdpr rao {'' if s.shape == 'box' else f'--hull {s.shape} '}--length {s.length:g} --beam "
                f"{s.beam:g} --draught {s.draught:g} --gm {s.gm:g} --roll-damping {s.roll_damping:g} --headings "
                f"{heads} --omega {s.omega} --panel {s.panel_m:g} (marinecdpr {__version__})")

    @property
    def box(self) -> dict:
        """The box approximation's main dimensions, GM and roll damping (:func:`~marinecdpr.motion.rao.box_hull_rao`'s
        arguments): the spec's, or the mesh's with the GM its hydrostatics give."""
        s = self.spec
        if self.hull is not None:
            return dict(length_m=self.hull.length_m, beam_m=self.hull.beam_m, draught_m=self.hull.draught_m,
                        gm_m=float(self.ds.attrs["gm_m"]), roll_damping_ratio=s.roll_damping)
        return dict(length_m=s.length, beam_m=s.beam, draught_m=s.draught, gm_m=s.gm, roll_damping_ratio=s.roll_damping)

    @property
    def box_label(self) -> str:
        """The box approximation's name in rao.png's legend."""
        if self.hull is not None:
            return "box approximation of the same main dimensions and GM"
        return "box approximation" + ("" if self.spec.shape == "box" else " of the same main dimensions")

    def write_tables(self, folder: str | Path):
        """``rao.nc``, ``rao.csv`` and ``rao.png`` (with the spec's ``figures``) in ``folder``
        (:func:`~marinecdpr.report.writers.write_rao`):
        its :class:`~marinecdpr.report.writers.RaoFiles`, the RAOs read back from rao.nc as a
        scenario reads them (``bem``), the box approximation (``approx``) and the paths.

        Raises
        ------
        ScenarioError, ValueError
            RAOs the tables refuse (not finite, beyond their ranges).
        """
        from marinecdpr.report.writers import write_rao

        Path(folder).mkdir(parents=True, exist_ok=True)
        return write_rao(self.ds, Path(folder), made_by=self.made_by, box=self.box, box_label=self.box_label,
                         figures=self.spec.figures)

    def write(self, folder: str | Path) -> list[Path]:
        """:meth:`write_tables`'s paths."""
        return self.write_tables(folder).paths


def run(spec: RaoSpec, *, estimated: RaoEstimate | None = None) -> RaoResult:
    """The BEM (:func:`~marinecdpr.motion.bem.hull_bem`, or with ``mesh``
    :func:`~marinecdpr.motion.bem.mesh_bem`), its size checked first (:func:`estimate`)
    unless ``estimated`` is given.

    Raises
    ------
    ScenarioError, ValueError
        A hull the BEM refuses (a GM no centre of gravity gives, ...).
    SpecError
        With ``mesh``: a mesh whose solve is refused (on ``mesh``).
    """
    from marinecdpr.errors import ScenarioError
    from marinecdpr.motion.bem import hull_bem, mesh_bem

    est = estimate(spec) if estimated is None else estimated
    if spec.mesh is not None:
        try:
            ds = mesh_bem(est.hull, kg_m=spec.kg, roll_damping_ratio=spec.roll_damping, omega=spec.frequencies,
                          heading_deg=spec.headings, label=f"mesh {spec.mesh.name}")
        except (ScenarioError, ValueError) as exc:
            raise SpecError("mesh", spec.mesh, str(exc)) from None
        return RaoResult(spec=spec, ds=ds, hull=est.hull)
    ds = hull_bem(shape=spec.shape, length_m=spec.length, beam_m=spec.beam, draught_m=spec.draught, gm_m=spec.gm,
                  roll_damping_ratio=spec.roll_damping, omega=spec.frequencies, heading_deg=spec.headings,
                  panel_m=spec.panel_m)
    return RaoResult(spec=spec, ds=ds)
