"""Hull meshes the mesh tests write: a Wigley hull cut at its stern (a transom) with fuller
sections forward below the waterline, so fore-aft asymmetric (x_B != x_F != 0), in the
formats Capytaine reads (issue 37, item 2)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from marinecdpr.motion.bem import wigley_half_breadth
from marinecdpr.motion.hullmesh import write_gdf

MIRROR = np.array([1.0, -1.0, 1.0])


def cut_wigley(*, length_m: float = 100.0, beam_m: float = 16.0, draught_m: float = 6.0, cut: float = -0.3,
               nx: int = 20, nz: int = 5, tjunctions: bool = False, half: bool = False) -> np.ndarray:
    """The panels, shape (n, 4, 3), each corner's (x, y, z) in m, normals out of the hull.

    Half-breadth y = y_Wigley(x, z) (1 - 0.3 (2x/L)(z/T)) for cut L <= x <= L/2, a flat
    transom at x = cut L. ``half``: the port side only (y >= 0, its transom to y = 0), as a
    file with ISY = 1 holds it. ``tjunctions``: the port panels forward of amidships split
    in two along x (their keel edges meet the other side's whole ones, or each other's
    mirror), and the first column's split in two along z (its edges meet the next column's
    whole ones): the corners added lie on the panels' straight edges, so the surface is
    the same.
    """
    L, B, T = length_m, beam_m, draught_m
    xs = np.linspace(cut * L, L / 2.0, nx + 1)
    zs = np.linspace(-T, 0.0, nz + 1)
    X, Z = np.meshgrid(xs, zs, indexing="ij")
    Y = wigley_half_breadth(X, Z, length_m=L, beam_m=B, draught_m=T) * (1.0 - 0.3 * (2.0 * X / L) * (Z / T))
    pts = np.stack([X, Y, Z], axis=-1)
    port = []
    for i in range(nx):
        for k in range(nz):
            a, b, c, d = pts[i, k], pts[i + 1, k], pts[i + 1, k + 1], pts[i, k + 1]
            if tjunctions and xs[i] >= 0.0:
                m1, m2 = 0.5 * (a + b), 0.5 * (d + c)
                port += [[a, d, m2, m1], [m1, m2, c, b]]
            elif tjunctions and i == 0:
                e, f = 0.5 * (a + d), 0.5 * (b + c)
                port += [[a, e, f, b], [e, d, c, f]]
            else:
                port.append([a, d, c, b])
    transom = []
    for k in range(nz):
        p0, p1 = pts[0, k], pts[0, k + 1]
        s0, s1 = (p0 * np.array([1.0, 0.0, 1.0]), p1 * np.array([1.0, 0.0, 1.0])) if half else (p0 * MIRROR,
                                                                                                p1 * MIRROR)
        q = np.array([p0, p1, s1, s0])
        q = q if np.cross(q[2] - q[0], q[3] - q[1])[0] < 0 else q[::-1]
        if np.all(q[3] == q[0]):  # at the keel, a triangle: its last corner repeated
            q = q[[0, 1, 2, 2]]
        transom.append(q)
    P = np.concatenate([np.array(port), np.array(transom)])
    return P if half else np.concatenate([P, mirrored(np.array(port))])


def mirrored(panels: np.ndarray) -> np.ndarray:
    """Panels mirrored in y = 0, their corners' order reversed (normals still outward), a
    triangle's (its last corner repeated) as Capytaine's mirror turns it: its first three
    reversed, the first of them repeated."""
    tri = np.all(panels[:, 3] == panels[:, 2], axis=1)
    turned = np.where(tri[:, None, None], panels[:, [2, 1, 0, 0]], panels[:, ::-1])
    return turned * MIRROR


def gdf(path: Path, panels: np.ndarray, *, isy: int = 0, isx: int = 0, title: str = "test hull") -> Path:
    """Panels (n, 4, 3) as a GDF file, its symmetry flags ISX ISY."""
    V = panels.reshape(-1, 3)
    path = write_gdf(path, V, np.arange(len(V)).reshape(-1, 4), title=title)
    lines = path.read_text().splitlines()
    lines[2] = f"{isx} {isy}"
    path.write_text("\n".join(lines) + "\n")
    return path


def nemoh(path: Path, panels: np.ndarray, *, symmetric: int) -> Path:
    """Nemoh's mesh file (``2 ISYM``; vertices, ``0``; panels, ``0``)."""
    V = panels.reshape(-1, 3)
    lines = [f"2 {symmetric}"] + [f"{i + 1} {x:.17g} {y:.17g} {z:.17g}" for i, (x, y, z) in enumerate(V)] + ["0 0.0 0.0 0.0"]
    lines += [" ".join(str(4 * i + j + 1) for j in range(4)) for i in range(len(panels))] + ["0 0 0 0"]
    path.write_text("\n".join(lines) + "\n")
    return path


def pnl(path: Path, panels: np.ndarray, *, y_symmetric: int) -> Path:
    """HAMS's PNL file (three title lines; panels, nodes, x- and y-symmetry; nodes; panels)."""
    V = panels.reshape(-1, 3)
    lines = ["    --------------Hull Mesh File---------------", "", "    # Number of Panels, Nodes, X-Symmetry and "
             "Y-Symmetry", f"{len(panels)} {len(V)} 0 {y_symmetric}", "", "    #Start Definition of Node "
             "Coordinates     ! node_number   x   y   z"]
    lines += [f"{i + 1} {x:.17g} {y:.17g} {z:.17g}" for i, (x, y, z) in enumerate(V)]
    lines += ["    #End Definition of Node Coordinates", "", "    #Start Definition of Node Relations"]
    lines += [f"{i + 1} 4 " + " ".join(str(4 * i + j + 1) for j in range(4)) for i in range(len(panels))]
    lines += ["    #End Definition of Node Relations", "", "    --------------End Hull Mesh File---------------"]
    path.write_text("\n".join(lines) + "\n")
    return path


def hst(path: Path, panels: np.ndarray, *, symmetry: int) -> Path:
    """HydroStar's HST file (``SYMMETRY``, ``COORDINATES``, ``PANEL TYPE 0``)."""
    V = panels.reshape(-1, 3)
    lines = [f"SYMMETRY {symmetry}", "COORDINATES"] + [f"{i + 1} {x:.17g} {y:.17g} {z:.17g}" for i, (x, y, z) in enumerate(V)]
    lines += ["ENDCOORDINATES", "PANEL TYPE 0"]
    lines += [" ".join(str(4 * i + j + 1) for j in range(4)) for i in range(len(panels))]
    lines += ["ENDPANEL", "ENDFILE"]
    path.write_text("\n".join(lines) + "\n")
    return path
