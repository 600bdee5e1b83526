"""Hull RAOs from the boundary-element code Capytaine (the ``bem`` extra).

:func:`hull_bem` builds a hull from its main dimensions, a box or a Wigley hull, solves
the radiation and diffraction problems with Capytaine at the wave frequencies and
directions asked for, adds a viscous roll damping (BEM knows none: a fraction of the
critical damping at the roll natural frequency, the added inertia included) and returns
Capytaine's dataset with an ``RAO`` variable: what ``capytaine.export_dataset`` writes
and ``[base_motion.rao] source = "capytaine"`` reads (:func:`~marinecdpr.motion.rao.read_capytaine`).
:func:`box_hull_bem` is the box's.

The hulls, of length L, beam B and draught T (their immersed part, panels about
``panel_m`` across), rotations about S's origin on the waterline amidships:

* ``"box"``: a box, volume L B T, waterplane L B, KB = T/2, BM = B^2 / (12 T),
  BM_L = L^2 / (12 T).
* ``"wigley"``: the classic analytic ship form, half-breadth
  y(x, z) = (B/2) (1 - (2x/L)^2) (1 - (z/T)^2) for |x| <= L/2, -T <= z <= 0: fine ends
  (zero breadth at bow, stern and keel), no lid. Volume (4/9) L B T, waterplane
  (2/3) L B, centre of buoyancy 3T/8 below the waterline (KB = 5T/8), waterplane
  inertias I_T = (4/105) L B^3 and I_L = L^3 B / 30, so BM = 3 B^2 / (35 T) and
  BM_L = 3 L^2 / (40 T) (:func:`wigley_hydrostatics`; the mesh: :func:`wigley_mesh`).

Both: mass rho V, centre of gravity on the centreline at the height that gives the
transverse metacentric height GM (KG = KB + BM - GM), dry radii of gyration 0.35 B in
roll and 0.25 L in pitch and yaw (:data:`ROLL_GYRADIUS_DRY_OVER_BEAM`,
:data:`PITCH_GYRADIUS_OVER_LENGTH`), and the hull's exact hydrostatic stiffness
(rho g A_wp in heave, rho g V GM in roll, rho g V GM_L in pitch) in place of Capytaine's
sums over the mesh: those take the waterplane's inertia at the panels' centres, and GM
is a small difference of large terms.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np

from marinecdpr.errors import ScenarioError
from marinecdpr.motion.rao import check_positive

__all__ = ["hull_bem", "box_hull_bem", "mesh_bem", "bem_panels", "restoring_matrix", "rigid_body_inertia", "HULL_SHAPES", "Hydrostatics", "box_hydrostatics", "wigley_hydrostatics",
           "wigley_half_breadth", "wigley_mesh", "ROLL_GYRADIUS_DRY_OVER_BEAM", "PITCH_GYRADIUS_OVER_LENGTH"]

HULL_SHAPES = ("box", "wigley")
"""The hull shapes :func:`hull_bem` builds."""
ROLL_GYRADIUS_DRY_OVER_BEAM = 0.35
"""A ship's dry roll radius of gyration over its beam (0.3-0.4; the added inertia comes
from the BEM solution)."""
PITCH_GYRADIUS_OVER_LENGTH = 0.25
"""A ship's pitch (and yaw) radius of gyration over its length."""
ROLL_DAMPING_MAX = 1.0
"""Largest viscous roll damping :func:`hull_bem` adds, a fraction of critical (a ship's is
some 0.02-0.2; the box approximation's ``roll_damping_ratio`` has the same bound)."""


def _capytaine():
    try:
        import capytaine as cpt
        import xarray as xr
    except ImportError:
        raise ScenarioError("computing RAOs with BEM needs Capytaine: pip install 'marinecdpr[bem]'") from None
    logging.getLogger("capytaine").setLevel(logging.ERROR)  # its progress and irregular-frequency notes
    return cpt, xr


@dataclass(frozen=True)
class Hydrostatics:
    """A hull's hydrostatics at its draught, upright.

    Attributes
    ----------
    volume_m3 : float
        Displaced volume V, m^3.
    waterplane_area_m2 : float
        Waterplane area A_wp, m^2.
    kb_m : float
        Height of the centre of buoyancy above the keel, m.
    bm_m, bml_m : float
        Transverse and longitudinal metacentric radii I_T / V and I_L / V, m.
    """

    volume_m3: float
    waterplane_area_m2: float
    kb_m: float
    bm_m: float
    bml_m: float

    @property
    def transverse_inertia_m4(self) -> float:
        """The waterplane's second moment of area about the centreline, I_T, m^4."""
        return self.bm_m * self.volume_m3

    @property
    def longitudinal_inertia_m4(self) -> float:
        """The waterplane's second moment of area about the transverse axis amidships, I_L, m^4."""
        return self.bml_m * self.volume_m3


def box_hydrostatics(length_m: float, beam_m: float, draught_m: float) -> Hydrostatics:
    """A box's hydrostatics: V = L B T, A_wp = L B, KB = T/2, BM = B^2 / (12 T), BM_L = L^2 / (12 T).

    Parameters
    ----------
    length_m, beam_m, draught_m : float
        L, B, T, m (> 0).

    Returns
    -------
    Hydrostatics
    """
    L, B, T = float(length_m), float(beam_m), float(draught_m)
    return Hydrostatics(volume_m3=L * B * T, waterplane_area_m2=L * B, kb_m=T / 2.0, bm_m=B * B / (12.0 * T),
                        bml_m=L * L / (12.0 * T))


def wigley_hydrostatics(length_m: float, beam_m: float, draught_m: float) -> Hydrostatics:
    """A Wigley hull's hydrostatics (:func:`wigley_half_breadth`), from the integrals in closed form.

    With xi = 2x/L and zeta = z/T, y = (B/2) (1 - xi^2) (1 - zeta^2) separates:
    V = int 2y dx dz = B (2L/3) (2T/3) = (4/9) L B T; A_wp = int 2y(x, 0) dx = (2/3) L B;
    the centre of buoyancy z_B = int z (1 - zeta^2) dz / int (1 - zeta^2) dz
    = (-T^2/4) / (2T/3) = -3T/8, so KB = 5T/8;
    I_T = int (2/3) y(x, 0)^3 dx = (B^3/12) (L/2) int (1 - xi^2)^3 dxi = (4/105) L B^3;
    I_L = int x^2 2y(x, 0) dx = B (L/2)^3 int xi^2 (1 - xi^2) dxi = L^3 B / 30.

    Parameters
    ----------
    length_m, beam_m, draught_m : float
        L, B, T, m (> 0).

    Returns
    -------
    Hydrostatics
    """
    L, B, T = float(length_m), float(beam_m), float(draught_m)
    volume = 4.0 / 9.0 * L * B * T
    return Hydrostatics(volume_m3=volume, waterplane_area_m2=2.0 / 3.0 * L * B, kb_m=5.0 / 8.0 * T,
                        bm_m=4.0 / 105.0 * L * B**3 / volume, bml_m=L**3 * B / 30.0 / volume)


def wigley_half_breadth(x, z, *, length_m: float, beam_m: float, draught_m: float) -> np.ndarray:
    """The Wigley hull's half-breadth y(x, z) = (B/2) (1 - (2x/L)^2) (1 - (z/T)^2).

    Parameters
    ----------
    x : array_like, shape (...)
        Longitudinal position from amidships, m (|x| <= L/2 on the hull).
    z : array_like, shape (...), broadcastable with ``x``
        Height above the waterline, m (-T <= z <= 0 on the hull).
    length_m, beam_m, draught_m : float
        L, B, T, m (> 0).

    Returns
    -------
    numpy.ndarray, shape (...)
        The half-breadth, m (zero at bow, stern and keel).
    """
    xi = 2.0 * np.asarray(x, dtype=float) / length_m
    zeta = np.asarray(z, dtype=float) / draught_m
    return 0.5 * beam_m * (1.0 - xi * xi) * (1.0 - zeta * zeta)


def _wigley_grid(L: float, B: float, T: float, panel_m: float) -> tuple[int, int]:
    """(n_x, n_z) of :func:`wigley_mesh`: n_x = ceil(L / panel_m) rounded up to even (a
    station amidships), n_z = ceil(girth / panel_m), at least 2."""
    fine = np.linspace(-T, 0.0, 2001)
    section = wigley_half_breadth(0.0, fine, length_m=L, beam_m=B, draught_m=T)
    girth = float(np.sum(np.hypot(np.diff(fine), np.diff(section))))
    return 2 * _cells(L / 2.0, panel_m, 1), _cells(girth, panel_m)


def _cells(extent: float, panel_m: float, least: int = 2) -> int:
    """Panels of about ``panel_m`` across ``extent``, at least ``least`` (counted up to 1e12:
    a denormal panel's ratio is infinite; any such hull is refused by its size)."""
    return max(least, math.ceil(min(extent / panel_m, 1e12)))


def _box_resolution(L: float, B: float, T: float, panel_m: float) -> tuple[int, int, int]:
    """Panels along the length, beam and height of the box about the waterline (2 T high)."""
    return tuple(_cells(x, panel_m) for x in (L, B, 2.0 * T))


def bem_panels(*, shape: str, length_m: float, beam_m: float, draught_m: float, panel_m: float) -> int:
    """How many panels :func:`hull_bem`'s immersed hull has, from arithmetic alone (no mesh
    is built, Capytaine need not be installed): what sizes the BEM's memory and time
    (:func:`marinecdpr.planning.budget.check_bem_size`).

    Parameters
    ----------
    shape : {"box", "wigley"}
    length_m, beam_m, draught_m : float
        L, B, T, m (> 0).
    panel_m : float
        About the panels' size, m (> 0).

    Returns
    -------
    int
        Box: the bottom's n_x n_y and the four sides' 2 (n_x + n_y) rows below the
        waterline (n_z / 2 for an even n_z; the clipped middle row adds one for an odd
        n_z). Wigley: 2 n_x n_z (:func:`wigley_mesh`).
    """
    if shape not in HULL_SHAPES:
        raise ValueError(f"shape {shape!r}: expected one of {', '.join(HULL_SHAPES)}")
    check_positive(length_m=length_m, beam_m=beam_m, draught_m=draught_m, panel_m=panel_m)
    L, B, T = float(length_m), float(beam_m), float(draught_m)
    if shape == "box":
        nx, ny, nz = _box_resolution(L, B, T, panel_m)
        return nx * ny + 2 * (nx + ny) * (nz // 2 + (nz % 2) * 2)
    nx, nz = _wigley_grid(L, B, T, panel_m)
    return 2 * nx * nz


def wigley_mesh(*, length_m: float, beam_m: float, draught_m: float, panel_m: float):
    """The Wigley hull's wetted surface as a Capytaine mesh (normals outward, into the water).

    Quadrilaterals on both sides over a uniform grid of x and z, as many along z as panels
    of ``panel_m`` along the midship section's girth: equal steps in z crowd the section's
    nodes towards the waterline, where it curves most (the chords cut the volume short:
    by 1.6 % on 100 x 20 x 6 m with panels of 4 m, 208 of them). The sides meet at bow,
    stern and keel, where the breadth is zero, so the surface is closed but for the
    waterplane (no lid).

    Parameters
    ----------
    length_m, beam_m, draught_m : float
        L, B, T, m (> 0).
    panel_m : float
        About the panels' size, m (> 0).

    Returns
    -------
    capytaine.Mesh
        2 n_x n_z panels: n_x = ceil(L / panel_m), rounded up to even (a station amidships),
        and n_z = ceil(girth / panel_m), at least 2.
    """
    cpt, _ = _capytaine()
    L, B, T = float(length_m), float(beam_m), float(draught_m)
    nx, nz = _wigley_grid(L, B, T, panel_m)
    X, Z = np.meshgrid(np.linspace(-L / 2.0, L / 2.0, nx + 1), np.linspace(-T, 0.0, nz + 1), indexing="ij")
    Y = wigley_half_breadth(X, Z, length_m=L, beam_m=B, draught_m=T)
    side = np.stack([X, Y, Z], axis=-1).reshape(-1, 3)  # the port (+y) side
    vertices = np.concatenate([side, side * np.array([1.0, -1.0, 1.0])])
    node = np.arange((nx + 1) * (nz + 1)).reshape(nx + 1, nz + 1)
    a, b = node[:-1, :-1].ravel(), node[1:, :-1].ravel()  # (x, z), (x + dx, z)
    c, d = node[1:, 1:].ravel(), node[:-1, 1:].ravel()  # (x + dx, z + dz), (x, z + dz)
    # the order of a face's corners sets its normal's side: on +y, a-d-c-b turns outward;
    # on -y, mirrored, the opposite order does
    faces = np.concatenate([np.stack([a, d, c, b], axis=1), np.stack([a, b, c, d], axis=1) + len(side)])
    return cpt.Mesh(vertices, faces, name="wigley")  # merges the sides' shared nodes


def hull_bem(
    *,
    shape: str = "box",
    length_m: float,
    beam_m: float,
    draught_m: float,
    gm_m: float,
    roll_damping_ratio: float,
    omega: np.ndarray,
    heading_deg: np.ndarray,
    panel_m: float = 2.5,
    rho: float = 1025.0,
    g: float = 9.81,
):
    """A box or Wigley hull's RAOs from Capytaine (see the module's note for the bodies).

    Parameters
    ----------
    shape : {"box", "wigley"}
        The hull's form (:data:`HULL_SHAPES`).
    length_m, beam_m, draught_m : float
        L, B, T, m (> 0).
    gm_m : float
        Transverse metacentric height, m (> 0, and less than KB + BM).
    roll_damping_ratio : float
        Viscous roll damping over critical, added to the radiation damping (0 to
        :data:`ROLL_DAMPING_MAX`).
    omega : array_like, shape (n_omega,)
        Wave angular frequencies, rad/s (> 0).
    heading_deg : array_like, shape (n_heading,)
        Directions the waves travel towards, from S's +x, counter-clockwise, deg.
    panel_m : float
        About the panels' size, m.
    rho, g : float
        Water density (kg/m^3) and gravity (m/s^2).

    Returns
    -------
    xarray.Dataset
        Capytaine's dataset with ``inertia_matrix``, ``hydrostatic_stiffness``, the
        viscous ``roll_damping`` (N m s/rad) and ``RAO`` (its convention: exp(-i omega
        t), rotations in rad/m), attributes naming the hull.
    """
    if shape not in HULL_SHAPES:
        raise ValueError(f"shape {shape!r}: expected one of {', '.join(HULL_SHAPES)}")
    cpt, xr = _capytaine()
    L, B, T, GM = float(length_m), float(beam_m), float(draught_m), float(gm_m)
    check_positive(length_m=L, beam_m=B, draught_m=T, gm_m=GM, panel_m=panel_m, rho=rho, g=g)
    if not (math.isfinite(roll_damping_ratio) and 0.0 <= roll_damping_ratio <= ROLL_DAMPING_MAX):
        raise ValueError(f"roll_damping_ratio must be a fraction of critical damping from 0 to {ROLL_DAMPING_MAX:g}, "
                         f"got {roll_damping_ratio:g}")
    hydro = (box_hydrostatics if shape == "box" else wigley_hydrostatics)(L, B, T)
    KB, BM = hydro.kb_m, hydro.bm_m
    KG = KB + BM - GM
    if KG <= 0:
        raise ValueError(f"gm_m {GM:g} m is more than KB + BM = {KB + BM:.3g} m: no centre of gravity gives it")
    omega = np.asarray(omega, dtype=float)
    heading = np.asarray(heading_deg, dtype=float)
    if shape == "box":
        size = (L, B, 2.0 * T)  # a box about the waterline; its immersed half is the hull
        resolution = _box_resolution(L, B, T, panel_m)
        mesh = cpt.mesh_parallelepiped(size=size, center=(0.0, 0.0, 0.0), resolution=resolution, name="box")
    else:
        mesh = wigley_mesh(length_m=L, beam_m=B, draught_m=T, panel_m=panel_m)
    name = "box" if shape == "box" else "Wigley hull"
    return _solve(cpt, xr, mesh, hydro, shape, L, B, T, GM, KG, roll_damping_ratio, omega, heading, rho, g,
                  f"{name} {L:g} x {B:g} x {T:g} m, GM {GM:g} m")


def mesh_bem(hull, *, kg_m: float, roll_damping_ratio: float, omega: np.ndarray, heading_deg: np.ndarray,
             rho: float = 1025.0, g: float = 9.81, label: str = "mesh"):
    """A hull mesh's RAOs from Capytaine (:func:`hull_bem`'s solve), its hydrostatics from the
    mesh's panels (``hull.hydrostatics``: :func:`~marinecdpr.motion.hullmesh.mesh_hydrostatics`) and its centre of
    gravity KG above the keel: GM = KB + BM - KG.

    Parameters
    ----------
    hull : marinecdpr.motion.hullmesh.HullMesh
        The wetted surface, checked (:func:`~marinecdpr.motion.hullmesh.load_hull_mesh`),
        in the mesh's own frame: the RAOs are about its origin on the waterline
        (:data:`MESH_REFERENCE_POINT`), G above the centre of buoyancy, KG above the keel,
        the restoring matrix about the origin with its heave-roll-pitch couplings
        (:func:`restoring_matrix`).
    kg_m : float
        KG, m (> 0, below KB + BM: a stable hull).
    label : str
        How the dataset's ``hull`` attribute names it (the file).

    Returns
    -------
    xarray.Dataset
        As :func:`hull_bem`'s, with the mesh's hydrostatics as attributes.
    """
    cpt, xr = _capytaine()
    check_positive(kg_m=kg_m, rho=rho, g=g)
    if not (math.isfinite(roll_damping_ratio) and 0.0 <= roll_damping_ratio <= ROLL_DAMPING_MAX):
        raise ValueError(f"roll_damping_ratio must be a fraction of critical damping from 0 to {ROLL_DAMPING_MAX:g}, "
                         f"got {roll_damping_ratio:g}")
    omega, heading = np.asarray(omega, dtype=float), np.asarray(heading_deg, dtype=float)
    mh = hull.hydrostatics
    hydro = Hydrostatics(volume_m3=mh.volume_m3, waterplane_area_m2=mh.waterplane_area_m2, kb_m=mh.kb_m,
                         bm_m=mh.bm_m, bml_m=mh.bml_m)
    GM = hydro.kb_m + hydro.bm_m - float(kg_m)
    if GM <= 0:
        raise ValueError(f"KG {kg_m:g} m is at or above the metacentre (KB + BM = {hydro.kb_m + hydro.bm_m:.4g} m "
                         f"from the mesh): the hull would capsize")
    V = mh.volume_m3
    Sx, Sy, Syy, Sxx, Sxy = mh.waterplane_moments  # int x, y, y^2, x^2, x y dA about the origin
    # about the mesh's origin on the waterline: G above B (x_G = x_B, y_G = y_B), the
    # metacentric heights about the origin's axes, and the couplings
    stiffness = restoring_matrix(rho=rho, g=g, waterplane_area_m2=mh.waterplane_area_m2, volume_m3=V,
                                 gm_m=mh.kb_m + Syy / V - float(kg_m), gml_m=mh.kb_m + Sxx / V - float(kg_m),
                                 int_x_dA=Sx, int_y_dA=Sy, int_xy_dA=Sxy)
    x_B, y_B, _ = mh.centre_of_buoyancy_m
    ds = _solve(cpt, xr, hull.mesh, hydro, "mesh", hull.length_m, hull.beam_m, hull.draught_m, GM, float(kg_m),
                roll_damping_ratio, omega, heading, rho, g,
                f"{label} ({hull.length_m:.4g} x {hull.beam_m:.4g} x {hull.draught_m:.4g} m), KG {kg_m:g} m, "
                f"GM {GM:.4g} m", stiffness=stiffness, g_xy=(x_B, y_B))
    ds.attrs.update(volume_m3=hydro.volume_m3, waterplane_area_m2=hydro.waterplane_area_m2, kb_m=hydro.kb_m,
                    bm_m=hydro.bm_m, bml_m=hydro.bml_m, gm_m=GM, centre_of_buoyancy_m=list(mh.centre_of_buoyancy_m),
                    centre_of_flotation_m=list(mh.centre_of_flotation_m), reference_point=MESH_REFERENCE_POINT)
    return ds


MESH_REFERENCE_POINT = ("the mesh's own origin (x = 0, y = 0 in the file) on the waterline: the rotations are about "
                        "it, the translations are its own, the waves' phase is taken there (S's origin)")
"""About which point :func:`mesh_bem`'s RAOs are given (in the dataset's attributes and
``rao.csv``'s header)."""


def restoring_matrix(*, rho: float, g: float, waterplane_area_m2: float, volume_m3: float, gm_m: float, gml_m: float,
                     int_x_dA: float = 0.0, int_y_dA: float = 0.0, int_xy_dA: float = 0.0) -> np.ndarray:
    """A floating hull's hydrostatic restoring matrix about a point O on the waterline, its
    centre of gravity G above its centre of buoyancy (as Capytaine's rigid-body terms,
    ``FloatingBody.compute_hydrostatic_stiffness``, with exact integrals):

        C33 = rho g A_wp,  C34 = C43 = rho g int y dA,  C35 = C53 = -rho g int x dA,
        C44 = rho g V GM_O,  C55 = rho g V GM_L,O,  C45 = C54 = -rho g int x y dA,

    the waterplane's integrals and the metacentric heights about O's axes (GM_O = KB +
    int y^2 dA / V - KG, GM_L,O = KB + int x^2 dA / V - KG); the yaw terms vanish with G
    above B. A hull symmetric fore and aft (int x dA = 0) about its midship has no
    heave-pitch coupling; a real ship's has.

    Parameters
    ----------
    rho, g : float
        kg/m^3, m/s^2.
    waterplane_area_m2, volume_m3 : float
        A_wp and V.
    gm_m, gml_m : float
        GM_O and GM_L,O, m.
    int_x_dA, int_y_dA : float
        The waterplane's first moments about O, m^3.
    int_xy_dA : float
        Its product of area about O, m^4.

    Returns
    -------
    ndarray, shape (6, 6)
        DOFs (surge, sway, heave, roll, pitch, yaw); N/m, N, N m/rad.
    """
    C = np.zeros((6, 6))
    C[2, 2] = rho * g * waterplane_area_m2
    C[3, 3] = rho * g * volume_m3 * gm_m
    C[4, 4] = rho * g * volume_m3 * gml_m
    C[2, 3] = C[3, 2] = rho * g * int_y_dA
    C[2, 4] = C[4, 2] = -rho * g * int_x_dA
    C[3, 4] = C[4, 3] = -rho * g * int_xy_dA
    return C


def rigid_body_inertia(mass_kg: float, gyradii_m: tuple[float, float, float], cog_m: tuple[float, float, float]
                       ) -> np.ndarray:
    """A rigid body's 6 x 6 inertia about a point O, its principal radii of gyration about G
    along the axes and G at ``cog_m`` from O: M = [[m I, -m [r]x], [m [r]x, I_G + m (|r|^2 I
    - r r^T)]].

    Parameters
    ----------
    mass_kg : float
    gyradii_m : tuple of 3 float
        About G along x, y, z, m.
    cog_m : tuple of 3 float
        r, G from O, m.

    Returns
    -------
    ndarray, shape (6, 6)
        kg, kg m, kg m^2.
    """
    m = float(mass_kg)
    x, y, z = (float(c) for c in cog_m)
    kx, ky, kz = (float(k) for k in gyradii_m)
    M = np.diag([m, m, m, m * (kx * kx + (y * y + z * z)), m * (ky * ky + (x * x + z * z)),
                 m * (kz * kz + (x * x + y * y))])
    M[0, 4] = M[4, 0] = m * z
    M[1, 3] = M[3, 1] = -m * z
    for (i, j), v in {(0, 5): -m * y, (1, 5): m * x, (2, 3): m * y, (2, 4): -m * x, (3, 4): -m * x * y,
                      (3, 5): -m * x * z, (4, 5): -m * y * z}.items():
        if v != 0.0:
            M[i, j] = M[j, i] = v
    return M


def _solve(cpt, xr, mesh, hydro: Hydrostatics, shape: str, L: float, B: float, T: float, GM: float, KG: float,
           roll_damping_ratio: float, omega: np.ndarray, heading: np.ndarray, rho: float, g: float, what: str,
           stiffness: np.ndarray | None = None, g_xy: tuple[float, float] = (0.0, 0.0)):
    """The BEM and the RAOs of a hull mesh with its hydrostatics (:func:`hull_bem`'s steps),
    about the origin on the waterline; G at ``g_xy`` and KG above the keel; ``stiffness``
    the restoring matrix about the origin (default: the hull's, G above the origin)."""
    if not (omega.ndim == 1 and omega.size >= 1 and np.all(np.isfinite(omega)) and np.all(omega > 0)):
        raise ValueError("omega must be finite wave frequencies > 0 rad/s")
    if not (heading.ndim == 1 and heading.size >= 1 and np.all(np.isfinite(heading))):
        raise ValueError("heading_deg must be finite wave headings, deg")
    directions = np.radians(heading)
    KB = hydro.kb_m
    volume = hydro.volume_m3
    mass = rho * volume
    zg = KG - T
    body = cpt.FloatingBody(mesh=mesh, dofs=cpt.rigid_body_dofs(rotation_center=(0.0, 0.0, 0.0)),
                            center_of_mass=(g_xy[0], g_xy[1], zg), mass=mass, name=shape).immersed_part()
    # about the rotation centre on the waterline: the gyradii are about G
    inertia = rigid_body_inertia(mass, (ROLL_GYRADIUS_DRY_OVER_BEAM * B, PITCH_GYRADIUS_OVER_LENGTH * L,
                                        PITCH_GYRADIUS_OVER_LENGTH * L), (g_xy[0], g_xy[1], zg))
    dofs = list(body.dofs)
    body.inertia_matrix = body.add_dofs_labels_to_matrix(inertia)
    # the hull's hydrostatics exactly: Capytaine's sums over the mesh take the waterplane's
    # inertia at the panels' centres, which with four panels across a 20 m beam made a box's
    # 2 m GM 1.65 m (GM is a small difference of large terms)
    if stiffness is None:
        stiffness = restoring_matrix(rho=rho, g=g, waterplane_area_m2=hydro.waterplane_area_m2, volume_m3=volume,
                                     gm_m=GM, gml_m=KB + hydro.bml_m - KG)
    body.hydrostatic_stiffness = body.add_dofs_labels_to_matrix(stiffness)
    problems = cpt.BEMSolver().fill_dataset(
        xr.Dataset(coords={"omega": omega, "wave_direction": directions, "radiating_dof": dofs,
                           "water_depth": [np.inf], "rho": [rho], "g": [g]}),
        body, progress_bar=False)
    C44 = float(problems["hydrostatic_stiffness"].sel(influenced_dof="Roll", radiating_dof="Roll"))
    I44 = inertia[3, 3]
    A44 = problems["added_mass"].sel(influenced_dof="Roll", radiating_dof="Roll").values
    w_n = math.sqrt(C44 / I44)
    for _ in range(20):  # the roll natural frequency with the added inertia at that frequency
        w_n = math.sqrt(C44 / (I44 + float(np.interp(w_n, omega, A44))))
    b44 = 2.0 * roll_damping_ratio * math.sqrt(C44 * (I44 + float(np.interp(w_n, omega, A44))))
    dissipation = np.zeros((len(dofs), len(dofs)))
    dissipation[dofs.index("Roll"), dofs.index("Roll")] = b44
    problems["RAO"] = cpt.post_pro.rao(problems, dissipation=body.add_dofs_labels_to_matrix(dissipation))
    problems["roll_damping"] = b44
    problems.attrs.update(hull=f"{what}, roll damping {roll_damping_ratio:g} "
                               f"of critical (at {w_n:.3g} rad/s), {body.mesh.nb_faces} panels, Capytaine "
                               f"{cpt.__version__}")
    return problems


def box_hull_bem(**kwargs):
    """A box hull's RAOs from Capytaine: :func:`hull_bem` with ``shape="box"`` (the same
    keyword arguments otherwise: ``length_m``, ``beam_m``, ``draught_m``, ``gm_m``,
    ``roll_damping_ratio``, ``omega``, ``heading_deg``, ``panel_m``, ``rho``, ``g``).

    Returns
    -------
    xarray.Dataset
        As :func:`hull_bem`'s.
    """
    return hull_bem(shape="box", **kwargs)
