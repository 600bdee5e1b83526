"""A hull from its mesh: reading it (the formats Capytaine reads, their symmetry flags
honoured, refused by its header and size before it is read whole), checking it before any
BEM (closed as a surface: T-junctions pass, holes and gaps do not), its hydrostatics from
the panels, and the project's own meshes written as GDF.

The hydrostatics are exact integrals over the mesh's panels (a quadrilateral as the mean
of its two splits into triangles, :func:`panel_triangles`): with
the wetted surface S below the waterline z = 0 closed by the waterplane W (its lid, at
z = 0, normal +z), the divergence theorem turns every volume and waterplane integral into
one over S alone (Capytaine's own sums take one point per panel, too coarse for GM, a
small difference of large terms):

    V       = int_S z n_z dS                 (the lid, at z = 0, adds nothing)
    z_B V   = int_S z^2 / 2 n_z dS,   x_B V = int_S x^2 / 2 n_x dS   (the lid's n_x is 0)
    A_W     = -int_S n_z dS                  (the closed surface's int n_z is 0)
    int_W y^2 dA = -int_S y^2 n_z dS,   int_W x^2 dA = -int_S x^2 n_z dS,  and so on
    (int_W x dA, int_W y dA, int_W x y dA: the restoring matrix's couplings),

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
           "write_wigley_gdf", "shipped_mesh", "panel_triangles", "MESH_UNITS", "MESH_FORMATS", "SHIPPED_WIGLEY",
           "MAX_MESH_PANELS", "MAX_MESH_BYTES"]

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
        m, in the hull's frame, the mesh's own: x forward, y to port as in the file (its
        mirror images written out), z up from the waterline; the origin is the file's x =
        0, y = 0 on the waterline (S's origin: the RAOs' rotations are about it and the
        waves' phase is taken there).
    triangles : ndarray of int, shape (n_triangles, 3)
        The wetted panels split into triangles (for the integrals; :func:`panel_triangles`).
    mesh : capytaine.Mesh
        The wetted panels as the BEM takes them.
    length_m, beam_m, draught_m : float
        The wetted surface's extents along x and y, and its depth.
    offset_m : tuple of 3 float
        Where the frame's origin lies in the file's coordinates, in its units, less the
        waterline's height: (0, 0, 0), the mesh's own origin.
    hydrostatics : MeshHydrostatics
        Its hydrostatics (:func:`mesh_hydrostatics`), in this frame.
    weights : ndarray, shape (n_triangles,), optional
        The triangles' weights (:func:`panel_triangles`).
    """

    vertices: np.ndarray
    triangles: np.ndarray
    mesh: object
    length_m: float
    beam_m: float
    draught_m: float
    offset_m: tuple = (0.0, 0.0, 0.0)
    hydrostatics: "MeshHydrostatics | None" = None
    weights: "np.ndarray | None" = None

    @property
    def panels(self) -> int:
        return int(self.mesh.nb_faces)


@dataclass(frozen=True)
class MeshHydrostatics:
    """A mesh's hydrostatics (see the module's note). Attributes as
    :class:`~marinecdpr.motion.bem.Hydrostatics` (volume, waterplane, KB above the keel,
    BM and BM_L about the waterplane's centroid), and the centres, m; ``volumes_m3`` the
    three volume integrals int x n_x dS, int y n_y dS, int z n_z dS (equal on a closed
    surface); ``waterplane_moments`` the waterplane's int x dA, int y dA (m^3), int y^2 dA,
    int x^2 dA and int x y dA (m^4), about the frame's origin (what the restoring matrix
    about that origin takes)."""

    volume_m3: float
    waterplane_area_m2: float
    kb_m: float
    bm_m: float
    bml_m: float
    centre_of_buoyancy_m: tuple[float, float, float]
    centre_of_flotation_m: tuple[float, float]
    volumes_m3: tuple[float, float, float] = (math.nan, math.nan, math.nan)
    waterplane_moments: tuple[float, float, float, float, float] = (0.0, 0.0, 0.0, 0.0, 0.0)


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
            "zz": mean2(2, 2), "xy": mean2(0, 1)}


def mesh_hydrostatics(vertices: np.ndarray, triangles: np.ndarray, weights: np.ndarray | None = None
                      ) -> MeshHydrostatics:
    """The hydrostatics of a wetted surface below z = 0, closed up to the waterline, its
    normals (the triangles' right-hand order) pointing out of the hull.

    Parameters
    ----------
    vertices : ndarray, shape (n_vertices, 3)
        m.
    triangles : ndarray of int, shape (n_triangles, 3)
    weights : ndarray, shape (n_triangles,), optional
        Each triangle's weight (default 1; :func:`panel_triangles` gives a quadrilateral's
        two splits 1/2 each).
    """
    P = np.asarray(vertices, dtype=float)[np.asarray(triangles)]
    m = _triangle_integrals(P)
    w = np.ones(len(P)) if weights is None else np.asarray(weights, dtype=float)
    a_x, a_y, a_z = (m["a"][:, k] * w for k in range(3))
    V = float((m["z"] * a_z).sum())  # int z n_z dS
    Vx, Vy = float((m["x"] * a_x).sum()), float((m["y"] * a_y).sum())  # the same volume, if the surface is closed
    z_B = float((0.5 * m["zz"] * a_z).sum()) / V
    x_B = float((0.5 * m["xx"] * a_x).sum()) / V  # int x dV = int x^2 / 2 n_x dS (x's lid term is 0)
    y_B = float((0.5 * m["yy"] * a_y).sum()) / V
    A = -float(a_z.sum())
    Sx, Sy = -float((m["x"] * a_z).sum()), -float((m["y"] * a_z).sum())
    Ixx, Iyy, Ixy = (-float((m[k] * a_z).sum()) for k in ("yy", "xx", "xy"))
    x_F, y_F = Sx / A, Sy / A
    I_T = Ixx - A * y_F**2  # about the centroid's line along x
    I_L = Iyy - A * x_F**2
    keel = float(P[:, :, 2].min())
    return MeshHydrostatics(volume_m3=V, waterplane_area_m2=A, kb_m=z_B - keel, bm_m=I_T / V, bml_m=I_L / V,
                            centre_of_buoyancy_m=(x_B, y_B, z_B), centre_of_flotation_m=(x_F, y_F),
                            volumes_m3=(Vx, Vy, V), waterplane_moments=(Sx, Sy, Ixx, Iyy, Ixy))


def panel_triangles(panels: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Panels as triangles for the integrals: a quadrilateral (a, b, c, d) as both its
    splits, (a, b, c), (a, c, d) and (a, b, d), (b, c, d), each of weight 1/2 (a panel
    that is not flat is no more one split than the other: a hull symmetric fore and aft
    keeps its symmetry whichever corner comes first); a triangle (its last corner
    repeated) as itself, weight 1.

    Returns
    -------
    triangles : ndarray of int, shape (n, 3)
    weights : ndarray, shape (n,)
    """
    panels = np.asarray(panels)
    quad = (panels[:, 3] != panels[:, 2]) & (panels[:, 3] != panels[:, 0])
    q = panels[quad]
    tri = np.concatenate([panels[~quad][:, :3], q[:, [0, 1, 2]], q[:, [0, 2, 3]], q[:, [0, 1, 3]], q[:, [1, 2, 3]]])
    w = np.concatenate([np.ones(int((~quad).sum())), np.full(4 * len(q), 0.5)])
    return tri, w


def faces_to_triangles(faces: np.ndarray) -> np.ndarray:
    """Quadrilaterals (a, b, c, d) as triangles (a, b, c), (a, c, d); a quad whose last corner
    repeats one (Capytaine's triangles) gives one."""
    faces = np.asarray(faces)
    t1 = faces[:, [0, 1, 2]]
    t2 = faces[:, [0, 2, 3]]
    real = (faces[:, 3] != faces[:, 2]) & (faces[:, 3] != faces[:, 0])
    return np.concatenate([t1, t2[real]])


MAX_MESH_PANELS = 50_000
"""Most panels a mesh file may hold, its mirror images counted: a BEM of 33 frequencies
affords some 8 000 below the waterline (:func:`~marinecdpr.planning.budget.check_bem_size`),
and Capytaine's reader checks each panel's shape in Python, about a millisecond a panel; a
file's own count (GDF, PNL, binary STL) is checked before the file is read."""
MAX_MESH_BYTES = 2**25
"""Largest mesh file read, bytes (32 MiB: some 50 000 panels of text at full precision, as
an ASCII STL's triangles)."""
_STL_HEADER_BYTES, _STL_TRIANGLE_BYTES = 84, 50


def _check_mesh_size(path: Path, fmt: str, src: str) -> None:
    """Refuse, in one line and before the reader reads it whole, a mesh file larger than
    :data:`MAX_MESH_BYTES`, one whose header counts more than :data:`MAX_MESH_PANELS`
    panels (GDF's NPAN and PNL's panels and nodes, times two for each symmetry flag; a
    binary STL's triangles), a binary STL whose triangle count disagrees with its size,
    a GDF header that is not one (ISX, ISY not 0 or 1; a higher-order IGDEF)."""
    size = path.stat().st_size
    if size > MAX_MESH_BYTES:
        raise ScenarioError(f"a mesh file of {size / 2**20:.0f} MiB, larger than one can be ({MAX_MESH_BYTES // 2**20} "
                            f"MiB): use a coarser mesh", source=src)
    with open(path, "rb") as fh:
        head = fh.read(4096)
    if fmt == "stl":
        binary = size >= _STL_HEADER_BYTES and not head.lstrip().startswith(b"solid")
        count = int.from_bytes(head[80:84], "little") if len(head) >= _STL_HEADER_BYTES else -1
        if count >= 0 and size == _STL_HEADER_BYTES + _STL_TRIANGLE_BYTES * count:
            binary = True
        if binary:
            want = _STL_HEADER_BYTES + _STL_TRIANGLE_BYTES * count
            if count < 0 or want != size:
                raise ScenarioError(f"a binary STL whose header counts {max(count, 0):,} triangles, which take "
                                    f"{want:,} bytes, but the file has {size:,}: it is cut short or its count is "
                                    "wrong", source=src)
            _check_count(count, "triangles", src)
        return
    if fmt not in ("gdf", "pnl"):
        return
    lines = head.decode("utf-8", errors="replace").splitlines()

    def ints(k: int, n: int) -> list[int]:
        words = lines[k].split() if k < len(lines) else []
        try:
            return [int(w) for w in words[:n]] if len(words) >= n else []
        except ValueError:
            return []

    if fmt == "gdf":
        sym = ints(2, 2)
        npan = ints(3, 1)
        if not sym or not npan:
            raise ScenarioError("not a GDF mesh: its third line should hold ISX ISY and its fourth NPAN (whole "
                                "numbers)", source=src)
        if any(v not in (0, 1) for v in sym):
            raise ScenarioError(f"GDF symmetry flags ISX {sym[0]}, ISY {sym[1]}: expected 0 or 1 each", source=src)
        words = lines[3].split()
        igdef = words[1] if len(words) > 1 else "0"
        if igdef.lstrip("+-").isdigit() and int(igdef) != 0:
            raise ScenarioError(f"a higher-order GDF (IGDEF {int(igdef)}): only flat panels (IGDEF 0 or absent) are "
                                "read", source=src)
        _check_count(npan[0] * 2 ** sum(sym), "panels" + (" with its mirror images" if any(sym) else ""), src)
    else:
        counts = ints(3, 4)
        if not counts:
            raise ScenarioError("not a PNL mesh: its fourth line should hold the numbers of panels and nodes and the "
                                "two symmetry flags (whole numbers)", source=src)
        _check_count(counts[1], "nodes", src)
        _check_count(counts[0] * 2 ** ((counts[2] == 1) + (counts[3] == 1)), "panels", src)


def _check_count(count: int, what: str, src: str) -> None:
    if count > MAX_MESH_PANELS:
        raise ScenarioError(f"its header counts {count:,} {what}, more than a mesh may hold ({MAX_MESH_PANELS:,}; a BEM "
                            "affords some 8,000 below the waterline): use a coarser mesh", source=src)


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
    _check_mesh_size(path, fmt, src)  # by its header and size, before it is read whole
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
    whole = cpt.Mesh(vertices, faces, name=path.stem, auto_check=False)  # its panels checked as it was read
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
    verts, panels = _welded(V, np.asarray(wet.faces), 1e-6 * size)
    _check_closed(verts, panels, size, src)
    tri, weights = panel_triangles(panels)
    hydro = mesh_hydrostatics(verts, tri, weights)
    if hydro.volume_m3 < 0:
        raise ScenarioError(f"its panels' normals point into the hull (the displaced volume comes out "
                            f"{hydro.volume_m3:.4g} m^3): reverse the order of each panel's corners", source=src)
    spread = max(abs(v - hydro.volume_m3) for v in hydro.volumes_m3[:2])
    if not spread <= VOLUME_TOLERANCE * hydro.volume_m3:
        vx, vy, vz = hydro.volumes_m3
        raise ScenarioError(f"the hull is open below the waterline: its volume integrals disagree (int x n_x dS "
                            f"{vx:.6g}, int y n_y dS {vy:.6g}, int z n_z dS {vz:.6g} m^3, by more than "
                            f"{VOLUME_TOLERANCE:.0e}); a BEM needs a closed wetted surface", source=src)
    # the hull's frame is the mesh's own: x and y as in the file, z up from the waterline
    return HullMesh(vertices=verts, triangles=tri, mesh=wet, offset_m=(0.0, 0.0, 0.0), hydrostatics=hydro,
                    weights=weights, **dims)


VOLUME_TOLERANCE = 1e-3
"""How far (relative) a closed surface's three volume integrals may disagree (rounding,
vertices written to a few digits, cracks narrower than :data:`GAP_TOLERANCE`)."""
GAP_TOLERANCE = 1e-4
"""The widest gap between panels a closed surface may have, relative to the hull's largest
dimension (an edge bordering one panel must lie along other panels' edges within it, as
at a T-junction of a low-order mesh)."""


def _welded(vertices: np.ndarray, faces: np.ndarray, tol: float) -> tuple[np.ndarray, np.ndarray]:
    """Panels on shared vertices: vertices closer than ``tol`` made one (an STL repeats them
    per triangle), corners that coincide dropped (a quadrilateral may become a triangle,
    its last corner repeated), panels of no area (at most tol^2) dropped, and fins dropped:
    two panels on the same corners turned opposite ways (the Wigley hull's two sides, each
    with a panel in its plane of symmetry at the ends) cancel in every integral and are no
    part of the surface; so is a sheet left hanging off it.

    Returns
    -------
    vertices : ndarray, shape (n_vertices, 3)
    panels : ndarray of int, shape (n_panels, 4)
        Quadrilaterals, a triangle repeating its last corner.
    """
    keys = np.round(vertices / tol).astype(np.int64)
    _, first, inverse = np.unique(keys, axis=0, return_index=True, return_inverse=True)
    v = vertices[first]
    P = inverse.reshape(-1)[np.asarray(faces)]
    keep = P != np.roll(P, -1, axis=1)  # a corner that differs from the next one
    n = keep.sum(axis=1)
    rows = np.arange(len(P))
    # a quadrilateral with one corner repeated: its three others, in their turn
    cut = np.argmin(keep, axis=1)
    three = P[rows[:, None], (cut[:, None] + 1 + np.arange(3)) % 4]
    P = np.where((n == 3)[:, None], np.concatenate([three, three[:, 2:]], axis=1), P)
    P = P[n >= 3]
    c = v[P]
    area = 0.5 * np.cross(c[:, 2] - c[:, 0], c[:, 3] - c[:, 1])  # a quadrilateral's vector area (a triangle's too)
    P, area = P[np.linalg.norm(area, axis=1) > tol * tol], area[np.linalg.norm(area, axis=1) > tol * tol]
    order = np.sort(P, axis=1)
    _, inverse, counts = np.unique(order, axis=0, return_inverse=True, return_counts=True)
    inverse = inverse.reshape(-1)
    twins = counts[inverse] == 2
    fin = np.zeros(len(P), dtype=bool)
    if twins.any():
        total = np.zeros((len(counts), 3))
        np.add.at(total, inverse[twins], area[twins])
        scale = np.zeros(len(counts))
        np.add.at(scale, inverse[twins], np.linalg.norm(area[twins], axis=1))
        fin = twins & (np.linalg.norm(total, axis=1)[inverse] <= 1e-9 * scale[inverse])
    P = P[~fin]
    # a sheet hanging off the surface: a panel with an edge that borders it alone (below the
    # waterline) and another that three panels share (what is left of a fin whose twin a
    # reader dropped as a duplicate: an STL's triangles on the same corners)
    for _ in range(len(P)):
        edges, owner = _panel_edges(P)
        _, inverse, counts = np.unique(np.sort(edges, axis=1), axis=0, return_inverse=True, return_counts=True)
        n = counts[inverse.reshape(-1)]
        lone = (n == 1) & ~(np.abs(v[edges][:, :, 2]) <= tol).all(axis=1)
        hanging = np.isin(np.arange(len(P)), owner[lone]) & np.isin(np.arange(len(P)), owner[n >= 3])
        if not hanging.any():
            break
        P = P[~hanging]
    return v, P


def _panel_edges(panels: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each panel's edges (a triangle's three, a quadrilateral's four), their corners in the
    panel's turn, and the panel each belongs to."""
    quad = panels[:, 3] != panels[:, 2]
    rows = np.arange(len(panels))
    edges = np.concatenate([panels[:, [0, 1]], panels[:, [1, 2]], panels[quad][:, [2, 3]],
                            np.where(quad[:, None], panels[:, [3, 0]], panels[:, [2, 0]])])
    return edges, np.concatenate([rows, rows, rows[quad], rows])


def _check_closed(vertices: np.ndarray, panels: np.ndarray, size: float, src: str) -> None:
    """The wetted surface is closed up to the waterline, its panels consistently turned.

    As a BEM code sees it, closure is of the surface, not of shared vertices: an edge of
    two panels must be run along in opposite directions by them; an edge of one panel
    (below the waterline) must lie along other panels' edges, run the other way, within
    :data:`GAP_TOLERANCE` of the hull's size (a T-junction: a long edge beside two
    shorter ones); else there is a gap there. The volume integrals are checked too
    (:func:`load_hull_mesh`).
    """
    from scipy.spatial import cKDTree

    edges, _ = _panel_edges(panels)
    key = np.sort(edges, axis=1)
    uniq, inverse, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    inverse = inverse.reshape(-1)
    if (counts > 2).any():
        raise ScenarioError(f"{int((counts > 2).sum())} panel edges are shared by more than two panels: the mesh is "
                            "not one surface", source=src)
    forward = (edges[:, 0] < edges[:, 1]).astype(np.int64)
    sums = np.bincount(inverse, weights=forward, minlength=len(uniq))
    clash = (counts == 2) & (sums != 1)
    if clash.any():
        raise ScenarioError(f"its panels' normals disagree: {int(clash.sum())} edges are run along the same way by "
                            "both their panels (some point into the hull, some out)", source=src)
    tol = 1e-6 * size
    lone = edges[(counts == 1)[inverse]]
    lone = lone[~(np.abs(vertices[lone][:, :, 2]) <= tol).all(axis=1)]  # the waterline's edges border the lid
    if not len(lone):
        return
    gap = GAP_TOLERANCE * size
    A, B = vertices[lone[:, 0]], vertices[lone[:, 1]]
    d = B - A
    length = np.linalg.norm(d, axis=1)
    t = (np.arange(4) + 0.5) / 4.0
    samples = A[:, None, :] + t[None, :, None] * d[:, None, :]  # (m, 4, 3) along each lone edge
    pairs = cKDTree(0.5 * (A + B)).query_pairs(float(length.max()) + gap, output_type="ndarray")
    pairs = np.concatenate([pairs, pairs[:, ::-1]]) if len(pairs) else np.zeros((0, 2), dtype=np.int64)
    i, j = pairs[:, 0], pairs[:, 1]
    # the distance of each sample of edge i from the segment of edge j
    u = np.clip(np.einsum("pkc,pc->pk", samples[i] - A[j][:, None, :], d[j]) / (length[j] ** 2)[:, None], 0.0, 1.0)
    dist = np.linalg.norm(samples[i] - (A[j][:, None, :] + u[:, :, None] * d[j][:, None, :]), axis=2)
    against = np.einsum("pc,pc->p", d[i], d[j]) < 0.0
    near_any = np.full((len(lone), 4), np.inf)
    near_back = np.full((len(lone), 4), np.inf)
    np.minimum.at(near_any, i, dist)
    np.minimum.at(near_back, i[against], dist[against])
    width_any, width_back = near_any.max(axis=1), near_back.max(axis=1)
    open_ = width_any > gap
    if open_.any():
        k = int(np.flatnonzero(open_)[0])
        x = 0.5 * (A[k] + B[k])
        widest = float(np.nanmax(np.where(np.isfinite(width_any[open_]), width_any[open_], np.nan), initial=0.0))
        width = f"gaps up to {widest:.3g} m wide" if widest > 0 else "no panel beside them"
        half = ""
        if (np.abs(np.concatenate([A[open_], B[open_]])[:, 1]) <= tol).all():
            half = (" (all on y = 0: if it is a half hull, its file must say so: GDF's ISY = 1, or Nemoh's, PNL's or "
                    "HST's symmetry flag)")
        raise ScenarioError(f"the hull is open below the waterline: {int(open_.sum())} panel edges border one panel "
                            f"only and lie along no other ({width}, {gap:.3g} m at most), the first at ({x[0]:.4g}, "
                            f"{x[1]:.4g}, {x[2]:.4g}) m{half}; a BEM needs a closed wetted surface", source=src)
    turned = width_back > gap
    if turned.any():
        raise ScenarioError(f"its panels' normals disagree: {int(turned.sum())} edges are run along the same way as "
                            "the panels' edges beside them (some point into the hull, some out)", source=src)


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
