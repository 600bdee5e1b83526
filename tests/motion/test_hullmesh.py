"""Hull meshes (issue 23, item 1): `marinecdpr rao --mesh`, the hydrostatics from the panels,
and bad meshes refused in one line before the BEM."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

pytest.importorskip("capytaine")

from marinecdpr.cli.app import app  # noqa: E402
from marinecdpr.errors import ScenarioError  # noqa: E402
from marinecdpr.motion.bem import _box_resolution, box_hydrostatics, wigley_hydrostatics  # noqa: E402
from marinecdpr.motion.hullmesh import (  # noqa: E402
    SHIPPED_WIGLEY, load_hull_mesh, mesh_hydrostatics, shipped_mesh, write_gdf, write_wigley_gdf,
)
from marinecdpr.planning.budget import check_bem_size  # noqa: E402
from tests.conftest import one_line_exit_2  # noqa: E402

runner = CliRunner()
L, B, T = 40.0, 10.0, 3.0


def _table(path: Path) -> np.ndarray:
    """rao.csv's numbers: omega, heading, amplitude, phase (its comment lines and dof names left out)."""
    rows = [ln.split(",") for ln in path.read_text().splitlines() if ln and not ln.startswith("#")][1:]
    return np.array([[float(r[0]), float(r[1]), float(r[3]), float(r[4])] for r in rows])


def _box_mesh():
    import capytaine as cpt

    return cpt.mesh_parallelepiped(size=(L, B, 2 * T), center=(0, 0, 0), resolution=_box_resolution(L, B, T, 2.5),
                                   name="box")


@pytest.fixture()
def box_gdf(tmp_path) -> Path:
    m = _box_mesh()
    return write_gdf(tmp_path / "box.gdf", np.asarray(m.vertices), np.asarray(m.faces), title="box 40 x 10 x 3 m")


def test_a_box_mesh_gives_the_box_command_s_raos(tmp_path, box_gdf):
    """The same panels through `rao --mesh` (hydrostatics from the mesh, G from KG) and through
    `rao` (closed forms, G from GM): KG = KB + BM - GM = 1.5 + 100/36 - 1.5."""
    import xarray as xr

    args = ["--omega", "0.3:1.5:4", "--headings", "90,180", "--roll-damping", "0.05"]
    res = runner.invoke(app, ["rao", "--length", "40", "--beam", "10", "--draught", "3", "--gm", "1.5", *args,
                              "--out", str(tmp_path / "a")])
    assert res.exit_code == 0, res.output
    res = runner.invoke(app, ["rao", "--mesh", str(box_gdf), "--kg", repr(100.0 / 36.0), *args,
                              "--out", str(tmp_path / "b")])
    assert res.exit_code == 0, res.output
    assert "mesh: " in res.stderr and "184 panels below the waterline" in res.stderr  # said before the BEM
    assert "displacement 1200 m3, waterplane 400 m2, KB 1.5 m, BM 2.778 m, GM 1.5 m" in res.stdout
    a, b = xr.open_dataset(tmp_path / "a" / "rao.nc"), xr.open_dataset(tmp_path / "b" / "rao.nc")
    for name in ("RAO", "added_mass", "radiation_damping", "excitation_force", "hydrostatic_stiffness"):
        x, y = np.asarray(a[name].values), np.asarray(b[name].values)
        assert np.abs(x - y).max() <= 1e-6 * np.abs(x).max(), name  # measured: equal, bit for bit
    ca, cb = (_table(tmp_path / k / "rao.csv") for k in "ab")
    np.testing.assert_allclose(cb, ca, rtol=1e-6, atol=0)


def test_mesh_hydrostatics_are_exact_for_a_box_and_within_2_percent_for_the_shipped_wigley():
    m = _box_mesh()
    hull_tri = np.concatenate([np.asarray(m.faces)[:, [0, 1, 2]], np.asarray(m.faces)[:, [0, 2, 3]]])
    wet = m.immersed_part()
    faces = np.asarray(wet.faces)
    tri = np.concatenate([faces[:, [0, 1, 2]], faces[:, [0, 2, 3]]])
    got = mesh_hydrostatics(np.asarray(wet.vertices), tri)
    want = box_hydrostatics(L, B, T)
    for k in ("volume_m3", "waterplane_area_m2", "kb_m", "bm_m", "bml_m"):
        assert getattr(got, k) == pytest.approx(getattr(want, k), rel=1e-13), k
    del hull_tri
    hull = load_hull_mesh(shipped_mesh())
    ref = wigley_hydrostatics(SHIPPED_WIGLEY["length_m"], SHIPPED_WIGLEY["beam_m"], SHIPPED_WIGLEY["draught_m"])
    for k in ("volume_m3", "waterplane_area_m2", "kb_m", "bm_m", "bml_m"):  # measured: -1.7 % .. +1.5 %
        assert getattr(hull.hydrostatics, k) == pytest.approx(getattr(ref, k), rel=0.02), k
    assert hull.panels == 208


def test_the_wigley_mesh_converges_to_the_closed_forms(tmp_path):
    """Panels of 1 m instead of 4 m: each figure within 0.2 % (measured 0.01 % to 0.16 %)."""
    path = write_wigley_gdf(tmp_path / "w.gdf", length_m=100.0, beam_m=20.0, draught_m=6.0, panel_m=1.0)
    hull = load_hull_mesh(path)
    ref = wigley_hydrostatics(100.0, 20.0, 6.0)
    for k in ("volume_m3", "waterplane_area_m2", "kb_m", "bm_m", "bml_m"):
        assert getattr(hull.hydrostatics, k) == pytest.approx(getattr(ref, k), rel=0.002), k


def test_the_shipped_mesh_is_the_one_the_project_writes(tmp_path):
    path = write_wigley_gdf(tmp_path / "w.gdf", **SHIPPED_WIGLEY)
    assert path.read_bytes() == shipped_mesh().read_bytes()


def test_rao_solves_the_shipped_wigley_mesh(tmp_path):
    hull = load_hull_mesh(shipped_mesh())
    kg = 7.0
    res = runner.invoke(app, ["rao", "--mesh", str(shipped_mesh()), "--kg", "7", "--omega", "0.4:1.2:3",
                              "--headings", "90", "--out", str(tmp_path / "o")])
    assert res.exit_code == 0, res.output
    gm = hull.hydrostatics.kb_m + hull.hydrostatics.bm_m - kg
    assert f"GM {gm:.4g} m (KG 7 m)" in res.stdout
    table = _table(tmp_path / "o" / "rao.csv")
    assert np.isfinite(table).all() and table.shape == (3 * 6, 4)  # 3 frequencies, 1 heading, 6 DOFs


def test_an_stl_mesh_reads_as_its_gdf(tmp_path, box_gdf):
    import trimesh

    m = _box_mesh()
    faces = np.asarray(m.faces)
    tri = np.concatenate([faces[:, [0, 1, 2]], faces[:, [0, 2, 3]]])
    trimesh.Trimesh(np.asarray(m.vertices), tri, process=False).export(tmp_path / "box.stl")
    a, b = load_hull_mesh(box_gdf), load_hull_mesh(tmp_path / "box.stl")
    for k in ("volume_m3", "waterplane_area_m2", "kb_m", "bm_m", "bml_m"):
        assert getattr(b.hydrostatics, k) == pytest.approx(getattr(a.hydrostatics, k), rel=1e-6), k  # STL: float32


def _edited(tmp_path, edit) -> Path:
    m = _box_mesh()
    v, f = edit(np.asarray(m.vertices, dtype=float).copy(), np.asarray(m.faces).copy())
    return write_gdf(tmp_path / "bad.gdf", v, f, title="bad")


def _bottom(v, f):
    return np.flatnonzero(v[f][:, :, 2].max(axis=1) < -T + 1e-9)


@pytest.mark.parametrize("edit, words", [
    (lambda v, f: (v, np.delete(f, _bottom(v, f)[:1], axis=0)), ("open below the waterline", "4 panel edges")),
    (lambda v, f: (v, f[:, ::-1]), ("normals point into the hull", "reverse the order")),
    (lambda v, f: (v, np.where(np.arange(len(f))[:, None] % 2 == 0, f[:, ::-1], f)), ("normals disagree",)),
    (lambda v, f: (v * 1000.0, f), ("length below the waterline is 4e+04 m", "--mesh-units")),
    (lambda v, f: (v + np.array([0, 0, 100.0]), f), ("no panel lies below the waterline",)),
])
def test_bad_meshes_are_one_line_before_the_bem(tmp_path, edit, words):
    path = _edited(tmp_path, edit)
    res = runner.invoke(app, ["rao", "--mesh", str(path), "--kg", "2", "--out", str(tmp_path / "o")])
    one_line_exit_2(res, *words)
    assert not (tmp_path / "o").exists()


def test_a_mesh_in_millimetres_reads_with_its_units(tmp_path):
    m = _box_mesh()
    path = write_gdf(tmp_path / "mm.gdf", np.asarray(m.vertices) * 1000.0, np.asarray(m.faces), title="mm")
    hull = load_hull_mesh(path, units="mm")
    assert hull.hydrostatics.volume_m3 == pytest.approx(1200.0, rel=1e-12) and hull.length_m == pytest.approx(40.0)


def test_more_panels_than_a_run_can_afford_are_refused(tmp_path):
    with pytest.raises(ScenarioError, match=r"a BEM of 10,000 panels \(the mesh x\.gdf\) at 33 frequencies .* would "
                                            r"take about .* use a coarser mesh"):
        check_bem_size(panels=10000, frequencies=33, headings=4, what="the mesh x.gdf")
    with pytest.raises(ScenarioError, match=r"a BEM of 30,000 panels .* would need about 58 GB in memory"):
        check_bem_size(panels=30000, frequencies=33, headings=4, what="the mesh x.gdf")
    (tmp_path / "junk.gdf").write_text("not a mesh\n1 2\n")
    one_line_exit_2(runner.invoke(app, ["rao", "--mesh", str(tmp_path / "junk.gdf"), "--kg", "2"]), "junk.gdf")


@pytest.mark.parametrize("args, words", [
    (["--mesh", "x.gdf"], ("give --kg",)),
    (["--mesh", "x.gdf", "--kg", "2", "--length", "40"], ("--length cannot go with it",)),
    (["--length", "40", "--beam", "10"], ("missing --draught, --gm",)),
    (["--length", "40", "--beam", "10", "--draught", "3", "--gm", "1", "--kg", "2"], ("--kg 2: goes with --mesh",)),
    (["--mesh", "x.obj2", "--kg", "2"], ("ending in .obj2",)),
    (["--mesh", "x.gdf", "--kg", "2", "--mesh-units", "yd"], ("--mesh-units yd",)),
])
def test_bad_rao_options_are_one_line(tmp_path, args, words):
    one_line_exit_2(runner.invoke(app, ["rao", *args, "--out", str(tmp_path / "o")]), *words)


# -------------------- formerly tests/test_hull_mesh_closure.py

"""A hull mesh's closure as a property of its surface, and mesh files refused before they
are read whole (issue 37, items 2, 17 and 19): T-junctions of a low-order mesh accepted,
a hole or a gap refused in one line, the shipped Wigley mesh as a binary STL read as its
GDF, a binary STL whose triangle count lies and a file whose header counts millions of
panels refused by their header and size."""


from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

pytest.importorskip("capytaine")

from marinecdpr.cli.app import app  # noqa: E402
from marinecdpr.errors import ScenarioError  # noqa: E402
from marinecdpr.motion.hullmesh import (  # noqa: E402
    GAP_TOLERANCE, MAX_MESH_BYTES, MAX_MESH_PANELS, faces_to_triangles, load_hull_mesh, read_mesh, shipped_mesh,
)
from tests.conftest import one_line_exit_2  # noqa: E402
from tests.mesh_shapes import cut_wigley, gdf  # noqa: E402

runner = CliRunner()
FIGURES = ("volume_m3", "waterplane_area_m2", "kb_m", "bm_m", "bml_m")


def _refused(tmp_path: Path, path: Path, *words: str) -> str:
    res = runner.invoke(app, ["rao", "--mesh", str(path), "--kg", "4", "--out", str(tmp_path / "o")])
    line = one_line_exit_2(res, str(path), *words)
    assert not (tmp_path / "o").exists()
    return line


def test_a_mesh_with_t_junctions_is_accepted_with_the_same_hydrostatics(tmp_path):
    """The cut Wigley hull with T-junctions (panels split along the keel on one side, a
    column split along z): the same surface, so the same hydrostatics (measured: within
    2e-16) and the three volume integrals equal. Before: "open below the waterline: 20 panel edges border one
    panel only"."""
    plain = load_hull_mesh(gdf(tmp_path / "plain.gdf", cut_wigley()))
    joined = load_hull_mesh(gdf(tmp_path / "t.gdf", cut_wigley(tjunctions=True)))
    assert joined.panels > plain.panels
    for k in FIGURES:
        assert getattr(joined.hydrostatics, k) == pytest.approx(getattr(plain.hydrostatics, k), rel=1e-12), k
    v = joined.hydrostatics.volumes_m3
    assert max(v) - min(v) <= 1e-12 * v[2]


def test_an_open_mesh_is_still_refused(tmp_path):
    """One panel below the waterline taken out of the T-junction mesh: its four edges lie
    along no other panel's (a gap half a panel wide), one line naming the place."""
    P = cut_wigley(tjunctions=True)
    centre = P.mean(axis=1)
    k = int(np.argmin(np.hypot(centre[:, 0] + 10.0, centre[:, 2] + 3.0) + 100.0 * (centre[:, 1] < 0)))
    line = _refused(tmp_path, gdf(tmp_path / "hole.gdf", np.delete(P, k, axis=0)), "open below the waterline",
                    "4 panel edges border one panel only")
    assert "a BEM needs a closed wetted surface" in line


def test_a_half_hull_without_its_flag_is_refused_saying_so(tmp_path):
    line = _refused(tmp_path, gdf(tmp_path / "half.gdf", cut_wigley(half=True)), "open below the waterline",
                    "all on y = 0", "ISY = 1")
    assert line.count("error") == 1


@pytest.mark.parametrize("offset, accepted", [(0.2, True), (3.0, False)])
def test_a_gap_is_refused_beyond_the_tolerance_and_not_within_it(tmp_path, offset, accepted):
    """One side's keel forward, where its panels' split edges meet the other side's whole
    ones, lifted off them by a fraction of the gap tolerance (accepted) or by three times
    it (refused, the width said)."""
    P = cut_wigley(tjunctions=True)
    length = 100.0
    gap = GAP_TOLERANCE * length
    # the port side's keel corners forward (x > 0, y = 0, z = -T), where its panels are split
    port = (P[:, :, 1].mean(axis=1) > 0.0)[:, None]
    move = port & (np.abs(P[:, :, 1]) < 1e-12) & (P[:, :, 2] == -6.0) & (P[:, :, 0] > 0.0)
    assert move.sum() >= 40
    P[move, 2] += offset * gap  # lifted off the other side's keel edges
    path = gdf(tmp_path / "gap.gdf", P)
    if accepted:
        assert load_hull_mesh(path).panels > 0
    else:
        _refused(tmp_path, path, "open below the waterline", "gaps up to", "m wide")


def test_the_shipped_wigley_mesh_as_a_binary_stl_reads_as_its_gdf(tmp_path):
    """The same panels as a binary STL (triangles, every vertex repeated, float32): accepted,
    and its hydrostatics those of the GDF (measured: within 3e-8, the STL's float32). Before:
    "open below the waterline: 2 panel edges border one panel only"."""
    import trimesh

    v, f = read_mesh(shipped_mesh())
    tri = faces_to_triangles(f)
    mesh = trimesh.Trimesh(v[tri].reshape(-1, 3), np.arange(3 * len(tri)).reshape(-1, 3), process=False)
    path = tmp_path / "wigley.stl"
    mesh.export(path)
    assert path.stat().st_size == 84 + 50 * len(tri)
    a, b = load_hull_mesh(shipped_mesh()), load_hull_mesh(path)
    for k in FIGURES:
        assert getattr(b.hydrostatics, k) == pytest.approx(getattr(a.hydrostatics, k), rel=1e-6), k
    res = runner.invoke(app, ["rao", "--mesh", str(path), "--kg", "7", "--omega", "0.5:1.0:2", "--headings", "180",
                              "--out", str(tmp_path / "o")])
    assert res.exit_code == 0, res.output


@pytest.mark.parametrize("count", [10, 10**6, 2**32 - 1])
def test_a_binary_stl_whose_triangle_count_lies_is_one_line(tmp_path, count):
    """Before: "reading stl meshes needs another package (No module named
    'charset_normalizer')"."""
    path = tmp_path / "lies.stl"
    body = np.zeros(3 * 50, dtype=np.uint8).tobytes()  # three triangles' bytes
    path.write_bytes(b"\0" * 80 + int(count).to_bytes(4, "little") + body)
    line = _refused(tmp_path, path, "binary STL", f"counts {count:,} triangles", f"{84 + 50 * count:,} bytes",
                    f"the file has {84 + 150:,}")
    assert "charset" not in line and "package" not in line


def _gdf_header(path: Path, npan: int, flags: str = "0 0", extra: str = "") -> Path:
    path.write_text(f"huge\n1.0 9.81\n{flags}\n{npan}{extra}\n" + "0 0 0\n" * 8)
    return path


@pytest.mark.parametrize("npan, flags, words", [
    (2_000_000, "0 0", ("2,000,000 panels",)),
    (30_000, "0 1", ("60,000 panels with its mirror images",)),
    (15_000, "1 1", ("60,000 panels with its mirror images",)),
])
def test_a_mesh_whose_header_counts_too_many_panels_is_refused_before_it_is_read(tmp_path, npan, flags, words):
    """GDF's NPAN (times two per symmetry flag) against MAX_MESH_PANELS: the file holds two
    panels only, so the count is the header's (before: the reader's own complaint, or, for a
    real file, 90 s and more of reading)."""
    assert MAX_MESH_PANELS == 50_000
    _refused(tmp_path, _gdf_header(tmp_path / "huge.gdf", npan, flags), "its header counts", *words,
             "use a coarser mesh")


@pytest.mark.parametrize("lines, words", [
    (("0 2", "1"), ("ISX 0, ISY 2", "expected 0 or 1")),
    (("0 0", "1 1"), ("higher-order GDF (IGDEF 1)",)),
    (("x y", "1"), ("not a GDF mesh", "ISX ISY")),
])
def test_a_gdf_header_that_is_not_one_is_one_line(tmp_path, lines, words):
    path = tmp_path / "bad.gdf"
    path.write_text(f"title\n1.0 9.81\n{lines[0]}\n{lines[1]}\n" + "0 0 0\n" * 4)
    _refused(tmp_path, path, *words)


def test_a_pnl_whose_node_count_says_two_billion_is_refused_by_its_header(tmp_path):
    path = tmp_path / "huge.pnl"
    path.write_text("title\n\n# panels nodes xsym ysym\n1 2000000000 0 0\n\n# nodes\n1 0 0 0\n")
    _refused(tmp_path, path, "2,000,000,000 nodes")


def test_a_mesh_file_larger_than_the_limit_is_refused_by_its_size(tmp_path):
    """A binary STL of two million triangles whose count is right (a sparse file: nothing is
    written, nothing read): refused by its size."""
    n = 2_000_000
    path = tmp_path / "big.stl"
    with open(path, "wb") as fh:
        fh.write(b"\0" * 80 + n.to_bytes(4, "little"))
        fh.truncate(84 + 50 * n)
    assert path.stat().st_size > MAX_MESH_BYTES
    _refused(tmp_path, path, "a mesh file of 95 MiB", "use a coarser mesh")
    with pytest.raises(ScenarioError, match="95 MiB"):  # the surface to clean reads meshes the same way
        read_mesh(path)
