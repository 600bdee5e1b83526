"""A hull from its mesh: reading it (the formats Capytaine reads), checking it before any
BEM, its hydrostatics from the panels, and the project's own meshes written as GDF.

The hydrostatics are exact integrals over the mesh's panels (split into triangles): with
the wetted surface S below the waterline z = 0 closed by the waterplane W (its lid, at
z = 0, normal +z), the divergence theorem turns every volume and waterplane integral into
one over S alone (Capytaine's own sums take one point per panel, too coarse for GM, a
small difference of large terms):

    V       = int_S z n_z dS                 (the lid, at z = 0, adds nothing)
    z_B V   = int_S z^2 / 2 n_z dS,   x_B V = int_S x^2 / 2 n_x dS   (the lid's n_x is 0)
    A_W     = -int_S n_z dS                  (the closed surface's int n_z is 0)
    int_W y^2 dA = -int_S y^2 n_z dS,   int_W x^2 dA = -int_S x^2 n_z dS,  and so on,

with n pointing out of the hull, into the water. Over a flat triangle each integrand is
a polynomial of degree at most 2 in its coordinates, integrated exactly by the vertices'
sums below.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from marinecdpr.errors import ScenarioError

__all__ = ["HullMesh", "read_mesh", "faces_to_triangles", "load_hull_mesh", "mesh_hydrostatics", "write_gdf",
           "write_wigley_gdf", "shipped_mesh", "MESH_UNITS", "MESH_FORMATS", "SHIPPED_WIGLEY"]

MESH_UNITS = {"m": 1.0, "cm": 0.01, "mm": 0.001, "ft": 0.3048}
"""The length units a mesh may be in, and their metres."""
MESH_FORMATS = {".gdf": "gdf", ".stl": "stl", ".dat": "nemoh", ".mar": "nemoh", ".hst": "hst", ".pnl": "pnl"}
"""File endings and the format Capytaine reads them as (STL through trimesh)."""
SHIPPED_WIGLEY = {"length_m": 100.0, "beam_m": 20.0, "draught_m": 6.0, "panel_m": 4.0}
"""The Wigley hull the package ships as a mesh (``data/meshes/wigley_100x20x6.gdf``, 208
panels below the waterline), as :func:`write_wigley_gdf` writes it."""
SHIP_RANGES = {"length_m": (1.0, 1000.0), "beam_m": (0.5, 200.0), "draught_m": (0.1, 50.0)}
"""What a ship's main dimensions can be (those of ``[base_motion.rao]``)."""


@dataclass(frozen=True)
class HullMesh:
    """A hull's wetted surface, checked: below the waterline z = 0, closed, normals outward.

    Attributes
    ----------
    vertices : ndarray, shape (n_vertices, 3)
        m, in the hull's frame: x forward, y to port, z up, the waterline at z = 0, the
        origin above the centre of buoyancy.
    triangles : ndarray of int, shape (n_triangles, 3)
        The wetted panels split into triangles (for the integrals).
    mesh : capytaine.Mesh
        The wetted panels as the BEM takes them.
    length_m, beam_m, draught_m : float
        The wetted surface's extents along x and y, and its depth.
    offset_m : tuple of 3 float
        Where the frame's origin (on the waterline above the centre of buoyancy) lies in
        the file's coordinates, in its units, less the waterline's height.
    hydrostatics : MeshHydrostatics
        Its hydrostatics (:func:`mesh_hydrostatics`), in this frame.
    """

    vertices: np.ndarray
    triangles: np.ndarray
    mesh: object
    length_m: float
    beam_m: float
    draught_m: float
    offset_m: tuple = (0.0, 0.0, 0.0)
    hydrostatics: "MeshHydrostatics | None" = None

    @property
    def panels(self) -> int:
        return int(self.mesh.nb_faces)


@dataclass(frozen=True)
class MeshHydrostatics:
    """A mesh's hydrostatics (see the module's note). Attributes as
    :class:`~marinecdpr.motion.bem.Hydrostatics` (volume, waterplane, KB above the keel,
    BM and BM_L about the waterplane's centroid), and the centres, m."""

    volume_m3: float
    waterplane_area_m2: float
    kb_m: float
    bm_m: float
    bml_m: float
    centre_of_buoyancy_m: tuple[float, float, float]
    centre_of_flotation_m: tuple[float, float]


def _triangle_integrals(P: np.ndarray) -> dict[str, np.ndarray]:
    """Per triangle (P: (n, 3, 3) vertices), the area vector a = (v1 - v0) x (v2 - v0) / 2
    and the exact means over the triangle of the monomials used (a flat triangle's mean of
    a linear function is the vertices' mean; of a quadratic u w, (sum u_i w_i + sum_i u_i
    sum_j w_j) / 12)."""
    a = 0.5 * np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0])

    def mean1(k):
        return P[:, :, k].mean(axis=1)

    def mean2(k, m):
        u, w = P[:, :, k], P[:, :, m]
        return ((u * w).sum(axis=1) + u.sum(axis=1) * w.sum(axis=1)) / 12.0

    return {"a": a, "x": mean1(0), "y": mean1(1), "z": mean1(2), "xx": mean2(0, 0), "yy": mean2(1, 1),
            "zz": mean2(2, 2)}


def mesh_hydrostatics(vertices: np.ndarray, triangles: np.ndarray) -> MeshHydrostatics:
    """The hydrostatics of a wetted surface below z = 0, closed up to the waterline, its
    normals (the triangles' right-hand order) pointing out of the hull.

    Parameters
    ----------
    vertices : ndarray, shape (n_vertices, 3)
        m.
    triangles : ndarray of int, shape (n_triangles, 3)
    """
    P = np.asarray(vertices, dtype=float)[np.asarray(triangles)]
    m = _triangle_integrals(P)
    a_x, a_z = m["a"][:, 0], m["a"][:, 2]
    V = float((m["z"] * a_z).sum())  # int z n_z dS
    z_B = float((0.5 * m["zz"] * a_z).sum()) / V
    x_B = float((0.5 * m["xx"] * a_x).sum()) / V  # int x dV = int x^2 / 2 n_x dS (x's lid term is 0)
    a_y = m["a"][:, 1]
    y_B = float((0.5 * m["yy"] * a_y).sum()) / V
    A = -float(a_z.sum())
    x_F, y_F = -float((m["x"] * a_z).sum()) / A, -float((m["y"] * a_z).sum()) / A
    I_T = -float((m["yy"] * a_z).sum()) - A * y_F**2  # about the centroid's line along x
    I_L = -float((m["xx"] * a_z).sum()) - A * x_F**2
    keel = float(P[:, :, 2].min())
    return MeshHydrostatics(volume_m3=V, waterplane_area_m2=A, kb_m=z_B - keel, bm_m=I_T / V, bml_m=I_L / V,
                            centre_of_buoyancy_m=(x_B, y_B, z_B), centre_of_flotation_m=(x_F, y_F))


def faces_to_triangles(faces: np.ndarray) -> np.ndarray:
    """Quadrilaterals (a, b, c, d) as triangles (a, b, c), (a, c, d); a quad whose last corner
    repeats one (Capytaine's triangles) gives one."""
    faces = np.asarray(faces)
    t1 = faces[:, [0, 1, 2]]
    t2 = faces[:, [0, 2, 3]]
    real = (faces[:, 3] != faces[:, 2]) & (faces[:, 3] != faces[:, 0])
    return np.concatenate([t1, t2[real]])


def _merged(vertices: np.ndarray, triangles: np.ndarray, tol: float) -> tuple[np.ndarray, np.ndarray]:
    """Vertices closer than ``tol`` made one (so the panels' edges can be matched), and
    triangles that collapse (of area at most tol^2) dropped."""
    keys = np.round(vertices / tol).astype(np.int64)
    _, first, inverse = np.unique(keys, axis=0, return_index=True, return_inverse=True)
    tri = inverse.reshape(-1)[triangles]
    v = vertices[first]
    P = v[tri]
    area = 0.5 * np.linalg.norm(np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0]), axis=1)
    # a triangle of no area (corners on one line, as where a Wigley hull's sides meet at its
    # keel and stem) bounds nothing and adds nothing to the integrals
    tri = tri[area > tol * tol]
    # two triangles on the same corners turned opposite ways are a fin of no thickness (the
    # Wigley hull's two sides, each with a panel in its plane of symmetry at the ends): they
    # cancel in every integral and are not part of the surface
    order = np.sort(tri, axis=1)
    _, inverse, counts = np.unique(order, axis=0, return_inverse=True, return_counts=True)
    inverse = inverse.reshape(-1)
    turn = _orientation(tri)
    twins = counts[inverse] == 2
    opposite = np.zeros(len(tri), dtype=bool)
    if twins.any():
        total = np.bincount(inverse[twins], weights=turn[twins], minlength=len(counts))
        opposite = twins & (total[inverse] == 0)
    return v, tri[~opposite]


def _orientation(tri: np.ndarray) -> np.ndarray:
    """+1 where a triangle's corners are an even turn of their sorted order, -1 otherwise."""
    a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
    even = ((a < b) & (b < c)) | ((b < c) & (c < a)) | ((c < a) & (a < b))
    return np.where(even, 1.0, -1.0)


def read_mesh(path: str | Path, *, units: str = "m", waterline_m: float = 0.0, file_format: str | None = None
              ) -> tuple[np.ndarray, np.ndarray]:
    """A mesh file's vertices in metres, its waterline at z = 0, and its faces (all of them,
    above the waterline too): what :func:`load_hull_mesh` checks, and what a surface to clean
    is read from.

    Returns
    -------
    vertices : ndarray, shape (n_vertices, 3)
        m.
    faces : ndarray of int, shape (n_faces, 4)
        Capytaine's: quadrilaterals, a triangle repeating a corner.

    Raises
    ------
    ScenarioError
        One line: an unknown unit or ending, no such file, a file the reader cannot parse,
        vertices that are not finite.
    """
    from marinecdpr.motion.bem import _capytaine

    cpt, _ = _capytaine()
    path = Path(path)
    src = str(path)
    if units not in MESH_UNITS:
        raise ScenarioError(f"--mesh-units {units}: expected one of {', '.join(MESH_UNITS)}", source=src)
    if not math.isfinite(waterline_m):
        raise ScenarioError(f"--waterline {waterline_m}: expected a finite height", source=src)
    fmt = file_format or MESH_FORMATS.get(path.suffix.lower())
    if fmt is None:
        raise ScenarioError(f"a mesh file ending in {path.suffix or '(nothing)'}: expected one of "
                            f"{', '.join(MESH_FORMATS)} (or name the format)", source=src)
    if not path.is_file():
        raise ScenarioError("no such file" if not path.exists() else "not a file", source=src)
    try:
        mesh = cpt.load_mesh(str(path), file_format=fmt)
    except ImportError as exc:  # STL without trimesh
        raise ScenarioError(f"reading {fmt} meshes needs another package ({exc})", source=src) from None
    except Exception as exc:  # a file the reader cannot parse: its own message, in one line
        text = " ".join(str(exc).split()) or type(exc).__name__
        raise ScenarioError(f"not a {fmt} mesh Capytaine can read: {text[:200]}", source=src) from None
    mesh = mesh.merged() if hasattr(mesh, "merged") else mesh
    scale = MESH_UNITS[units]
    vertices = (np.asarray(mesh.vertices, dtype=float) - np.array([0.0, 0.0, waterline_m])) * scale
    faces = np.asarray(mesh.faces)
    if not np.isfinite(vertices).all():
        raise ScenarioError("the mesh has vertices that are not finite numbers", source=src)
    return vertices, faces


def load_hull_mesh(path: str | Path, *, units: str = "m", waterline_m: float = 0.0, file_format: str | None = None,
                   max_panels: int | None = None) -> HullMesh:
    """A hull mesh from a file, in metres with its waterline at z = 0, checked before any BEM.

    Parameters
    ----------
    path : str or Path
        A mesh Capytaine reads (:data:`MESH_FORMATS`: GDF, STL, Nemoh, HST, PNL).
    units : str
        The mesh's length unit (:data:`MESH_UNITS`).
    waterline_m : float
        The waterline's z in the mesh, in its units.
    file_format : str, optional
        Capytaine's name of the format (default: from the file's ending).
    max_panels : int, optional
        The most wetted panels the run may have (checked before the mesh is clipped further).

    Raises
    ------
    ScenarioError
        One line, naming the file: unreadable; nothing below the waterline; dimensions no
        ship has (wrong units); open below the waterline (edges of one panel); normals that
        point into the hull or disagree; more panels than the run can afford.
    """
    from marinecdpr.motion.bem import _capytaine

    cpt, _ = _capytaine()
    path = Path(path)
    src = str(path)
    vertices, faces = read_mesh(path, units=units, waterline_m=waterline_m, file_format=file_format)
    scale = MESH_UNITS[units]
    whole = cpt.Mesh(vertices, faces, name=path.stem)
    wet = whole.immersed_part()
    if wet.nb_faces == 0:
        raise ScenarioError(f"no panel lies below the waterline (z = {waterline_m:g} {units} in the mesh): give "
                            "--waterline", source=src)
    if max_panels is not None and wet.nb_faces > max_panels:
        raise ScenarioError(f"{wet.nb_faces} panels below the waterline, more than the run can afford ({max_panels}): "
                            "coarsen the mesh", source=src)
    V = np.asarray(wet.vertices, dtype=float)
    lo, hi = V.min(axis=0), V.max(axis=0)
    dims = {"length_m": float(hi[0] - lo[0]), "beam_m": float(hi[1] - lo[1]), "draught_m": float(-lo[2])}
    for name, value in dims.items():
        lo_r, hi_r = SHIP_RANGES[name]
        if not lo_r <= value <= hi_r:
            what = name.removesuffix("_m")
            raise ScenarioError(f"its {what} below the waterline is {value:.4g} m in {units}, no ship's (a "
                                f"{what} from {lo_r:g} to {hi_r:g} m): are its units right (--mesh-units) and "
                                "its waterline (--waterline)?", source=src)
    size = max(dims.values())
    tri = faces_to_triangles(np.asarray(wet.faces))
    verts, tri = _merged(V, tri, 1e-6 * size)
    _check_closed(verts, tri, size, src)
    hydro = mesh_hydrostatics(verts, tri)
    if hydro.volume_m3 < 0:
        raise ScenarioError(f"its panels' normals point into the hull (the displaced volume comes out "
                            f"{hydro.volume_m3:.4g} m^3): reverse the order of each panel's corners", source=src)
    # the hull's frame: its origin on the waterline above the centre of buoyancy
    shift = np.array([hydro.centre_of_buoyancy_m[0], hydro.centre_of_buoyancy_m[1], 0.0])
    wet = cpt.Mesh(np.asarray(wet.vertices, dtype=float) - shift, np.asarray(wet.faces), name=path.stem)
    verts = verts - shift
    return HullMesh(vertices=verts, triangles=tri, mesh=wet, offset_m=tuple(float(v) for v in shift / scale),
                    hydrostatics=mesh_hydrostatics(verts, tri), **dims)


def _check_closed(vertices: np.ndarray, triangles: np.ndarray, size: float, src: str) -> None:
    """Every edge below the waterline is shared by two panels that run along it in opposite
    directions (a closed, consistently oriented surface); edges on the waterline border one."""
    edges = np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]])
    key = np.sort(edges, axis=1)
    uniq, inverse, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    on_waterline = (np.abs(vertices[uniq][:, :, 2]) <= 1e-6 * size).all(axis=1)
    open_ = (counts == 1) & ~on_waterline
    if open_.any():
        k = int(np.flatnonzero(open_)[0])
        x = vertices[uniq[k]].mean(axis=0)
        raise ScenarioError(f"the hull is open below the waterline: {int(open_.sum())} panel edges border one panel "
                            f"only, the first at ({x[0]:.4g}, {x[1]:.4g}, {x[2]:.4g}) m; a BEM needs a closed wetted "
                            "surface", source=src)
    if (counts > 2).any():
        raise ScenarioError(f"{int((counts > 2).sum())} panel edges are shared by more than two panels: the mesh is "
                            "not one surface", source=src)
    # the two panels along an interior edge run along it in opposite directions
    forward = (edges[:, 0] < edges[:, 1]).astype(np.int64)
    twice = counts[inverse.reshape(-1)] == 2
    sums = np.bincount(inverse.reshape(-1)[twice], weights=forward[twice], minlength=len(uniq))
    clash = (counts == 2) & (sums != 1)
    if clash.any():
        raise ScenarioError(f"its panels' normals disagree: {int(clash.sum())} edges are run along the same way by "
                            "both their panels (some point into the hull, some out)", source=src)


def write_gdf(path: str | Path, vertices: np.ndarray, faces: np.ndarray, *, title: str, gravity: float = 9.81) -> Path:
    """A mesh as a WAMIT GDF file (ULEN 1, no symmetry, one vertex per line, quadrilaterals;
    a triangle repeats its last corner), written atomically.

    Parameters
    ----------
    vertices : ndarray, shape (n_vertices, 3)
        m.
    faces : ndarray of int, shape (n_faces, 4)
        Each panel's corners, their order turning its normal out of the hull.
    title : str
        The header line.
    """
    from marinecdpr.textfiles import atomic_path

    path = Path(path)
    V = np.asarray(vertices, dtype=float)[np.asarray(faces)]
    lines = [title.replace("\n", " "), f"1.0 {gravity:.17g}", "0 0", str(len(V))]
    lines += [" ".join(f"{c:.17g}" for c in corner) for panel in V for corner in panel]
    with atomic_path(path) as tmp:
        tmp.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def write_wigley_gdf(path: str | Path, *, length_m: float, beam_m: float, draught_m: float, panel_m: float) -> Path:
    """The project's Wigley hull (:func:`~marinecdpr.motion.bem.wigley_mesh`) as a GDF file: how
    the shipped mesh was made (``SHIPPED_WIGLEY``)."""
    from marinecdpr.motion.bem import wigley_mesh

    mesh = wigley_mesh(length_m=length_m, beam_m=beam_m, draught_m=draught_m, panel_m=panel_m)
    title = (f"Wigley hull {length_m:g} x {beam_m:g} x {draught_m:g} m, {panel_m:g} m panels, written by "
             "marinecdpr.motion.hullmesh.write_wigley_gdf")
    return write_gdf(path, np.asarray(mesh.vertices), np.asarray(mesh.faces), title=title)


def shipped_mesh() -> Path:
    """The path of the package's Wigley hull mesh (GDF)."""
    from importlib import resources

    return Path(str(resources.files("marinecdpr") / "data" / "meshes" / "wigley_100x20x6.gdf"))
