"""Hull RAOs from the boundary-element code Capytaine (the ``bem`` extra).

:func:`box_hull_bem` builds a box-shaped hull from its main dimensions, solves the
radiation and diffraction problems with Capytaine at the wave frequencies and
directions asked for, adds a viscous roll damping (BEM knows none: a fraction of the
critical damping at the roll natural frequency, the added inertia included) and returns
Capytaine's dataset with an ``RAO`` variable: what ``capytaine.export_dataset`` writes
and ``[base_motion.rao] source = "capytaine"`` reads (:func:`~marinecdpr.motion.rao.read_capytaine`).

The body: a box of length L, beam B and draught T (its immersed part, panels about
``panel_m`` across), rotations about S's origin on the waterline amidships, mass
rho L B T, centre of gravity on the centreline at the height that gives the
transverse metacentric height GM (KG = T/2 + B^2 / (12 T) - GM), dry radii of
gyration 0.35 B in roll and 0.25 L in pitch and yaw (:data:`ROLL_GYRADIUS_DRY_OVER_BEAM`,
:data:`PITCH_GYRADIUS_OVER_LENGTH`); the box's exact hydrostatic stiffness (rho g L B in
heave, rho g V GM in roll, rho g V GM_L in pitch).
"""

from __future__ import annotations

import logging
import math

import numpy as np

from marinecdpr.errors import ScenarioError
from marinecdpr.motion.rao import check_positive

__all__ = ["box_hull_bem", "ROLL_GYRADIUS_DRY_OVER_BEAM", "PITCH_GYRADIUS_OVER_LENGTH"]

ROLL_GYRADIUS_DRY_OVER_BEAM = 0.35
"""A ship's dry roll radius of gyration over its beam (0.3-0.4; the added inertia comes
from the BEM solution)."""
PITCH_GYRADIUS_OVER_LENGTH = 0.25
"""A ship's pitch (and yaw) radius of gyration over its length."""


def _capytaine():
    try:
        import capytaine as cpt
        import xarray as xr
    except ImportError:
        raise ScenarioError("computing RAOs with BEM needs Capytaine: pip install 'marinecdpr[bem]'") from None
    logging.getLogger("capytaine").setLevel(logging.ERROR)  # its progress and irregular-frequency notes
    return cpt, xr


def box_hull_bem(
    *,
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
    """A box hull's RAOs from Capytaine (see the module's note for the body).

    Parameters
    ----------
    length_m, beam_m, draught_m : float
        L, B, T, m (> 0).
    gm_m : float
        Transverse metacentric height, m (> 0, and less than KB + BM).
    roll_damping_ratio : float
        Viscous roll damping over critical, added to the radiation damping (>= 0).
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
    cpt, xr = _capytaine()
    L, B, T, GM = float(length_m), float(beam_m), float(draught_m), float(gm_m)
    check_positive(length_m=L, beam_m=B, draught_m=T, gm_m=GM, panel_m=panel_m, rho=rho, g=g)
    if not (math.isfinite(roll_damping_ratio) and roll_damping_ratio >= 0):
        raise ValueError(f"roll_damping_ratio must be finite and >= 0, got {roll_damping_ratio}")
    KB, BM = T / 2.0, B * B / (12.0 * T)
    KG = KB + BM - GM
    if KG <= 0:
        raise ValueError(f"gm_m {GM:g} m is more than KB + BM = {KB + BM:.3g} m: no centre of gravity gives it")
    omega = np.asarray(omega, dtype=float)
    directions = np.radians(np.asarray(heading_deg, dtype=float))
    size = (L, B, 2.0 * T)  # a box about the waterline; its immersed half is the hull
    resolution = tuple(max(2, math.ceil(s / panel_m)) for s in size)
    mesh = cpt.mesh_parallelepiped(size=size, center=(0.0, 0.0, 0.0), resolution=resolution, name="box")
    mass = rho * L * B * T
    body = cpt.FloatingBody(mesh=mesh, dofs=cpt.rigid_body_dofs(rotation_center=(0.0, 0.0, 0.0)),
                            center_of_mass=(0.0, 0.0, KG - T), mass=mass, name="box").immersed_part()
    k44 = (ROLL_GYRADIUS_DRY_OVER_BEAM * B) ** 2
    k55 = (PITCH_GYRADIUS_OVER_LENGTH * L) ** 2
    zg = KG - T
    # about the rotation centre on the waterline: the gyradii are about G, shifted by zg
    inertia = np.diag([mass, mass, mass, mass * (k44 + zg * zg), mass * (k55 + zg * zg), mass * k55])
    inertia[0, 4] = inertia[4, 0] = mass * zg  # surge-pitch coupling of a raised or lowered G
    inertia[1, 3] = inertia[3, 1] = -mass * zg
    dofs = list(body.dofs)
    body.inertia_matrix = body.add_dofs_labels_to_matrix(inertia)
    # the box's hydrostatics exactly: Capytaine's sums over the mesh take the waterplane's
    # inertia at the panels' centres, which with four panels across a 20 m beam made a 2 m
    # GM 1.65 m (GM is a small difference of large terms)
    volume = L * B * T
    gml = KB + L * L / (12.0 * T) - KG
    stiffness = np.zeros((6, 6))
    stiffness[2, 2] = rho * g * L * B
    stiffness[3, 3] = rho * g * volume * GM
    stiffness[4, 4] = rho * g * volume * gml
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
    problems.attrs.update(hull=f"box {L:g} x {B:g} x {T:g} m, GM {GM:g} m, roll damping {roll_damping_ratio:g} "
                               f"of critical (at {w_n:.3g} rad/s), {body.mesh.nb_faces} panels, Capytaine "
                               f"{cpt.__version__}")
    return problems
