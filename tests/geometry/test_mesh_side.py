"""A hull mesh's side as a surface y = f(x, z) (:func:`marinecdpr.geometry.surface.mesh_side`):
its binned search against every triangle tested for every point."""

from __future__ import annotations

import numpy as np
import pytest

from marinecdpr.geometry.surface import mesh_side
from marinecdpr.motion.hullmesh import faces_to_triangles, read_mesh, write_wigley_gdf


def _every_triangle(vertices, triangles, side, x, z):
    """The outermost |y| over every triangle facing ``side`` whose x-z projection holds each
    point (the same barycentric test and tolerance), one point at a time."""
    sign = 1.0 if side == "port" else -1.0
    out = np.full(len(x), np.nan)
    for i, (px, pz) in enumerate(zip(x, z)):
        for tri in triangles:
            a, b, c = (np.asarray(vertices[j], dtype=float) for j in tri)
            if sign * np.cross(b - a, c - a)[1] <= 0:
                continue
            det = (b[0] - a[0]) * (c[2] - a[2]) - (c[0] - a[0]) * (b[2] - a[2])
            if abs(det) <= 1e-15:
                continue
            l1 = ((px - a[0]) * (c[2] - a[2]) - (c[0] - a[0]) * (pz - a[2])) / det
            l2 = ((b[0] - a[0]) * (pz - a[2]) - (px - a[0]) * (b[2] - a[2])) / det
            if l1 >= -1e-12 and l2 >= -1e-12 and l1 + l2 <= 1 + 1e-12:
                y = sign * (a[1] + l1 * (b[1] - a[1]) + l2 * (c[1] - a[1]))
                out[i] = y if np.isnan(out[i]) else max(out[i], y)
    return out


@pytest.mark.parametrize("side", ["port", "starboard"])
def test_the_binned_search_finds_what_every_triangle_finds(tmp_path, side):
    """A Wigley hull in 4 m panels, at random points, at its vertices and its edges'
    midpoints (where a point lies on several triangles' boundaries and the tolerance decides):
    the same values, bit for bit, as testing every triangle; NaN off the side."""
    v, faces = read_mesh(write_wigley_gdf(tmp_path / "w.gdf", length_m=60.0, beam_m=12.0, draught_m=5.0, panel_m=4.0))
    tri = faces_to_triangles(faces)
    rng = np.random.default_rng(7)
    mid = 0.5 * (v[tri[:, 0]] + v[tri[:, 1]])
    x = np.concatenate([rng.uniform(-32.0, 32.0, 150), v[::3, 0], mid[::5, 0]])
    z = np.concatenate([rng.uniform(-6.0, 1.0, 150), v[::3, 2], mid[::5, 2]])
    got = mesh_side(v, tri, side=side)(x, z)
    want = _every_triangle(v, tri, side, x, z)
    assert np.array_equal(got, want, equal_nan=True)
    assert np.isnan(got).sum() > 10 and np.isfinite(got).sum() > 100  # both kinds of point were asked


def test_overlapping_triangles_give_the_outermost_and_shapes_are_kept():
    """Two port-facing triangles over the same x-z square at y = 1 and y = 3 (the outer
    wins), one facing starboard at y = 5 (ignored), a degenerate one: by hand."""
    v = np.array([[0, 1, 0], [0, 1, 1], [1, 1, 0],     # port-facing at y = 1
                  [0, 3, 0], [0, 3, 1], [1, 3, 0],     # port-facing at y = 3
                  [0, 5, 0], [1, 5, 0], [0, 5, 1],     # facing starboard
                  [0, 9, 0], [1, 9, 0], [2, 9, 0]], dtype=float)  # no area in x-z
    tri = np.arange(12).reshape(4, 3)
    f = mesh_side(v, tri, side="port")
    X = np.array([[0.2, 0.9], [0.5, np.nan]])
    Z = np.array([[0.2, 0.9], [0.5, 0.0]])
    got = f(X, Z)
    assert got.shape == (2, 2)
    np.testing.assert_array_equal(got, [[3.0, np.nan], [3.0, np.nan]])
    np.testing.assert_array_equal(mesh_side(v, tri, side="starboard")(0.2, 0.2), -5.0)
