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
    (["--length", "40", "--beam", "10", "--draught", "3", "--gm", "1", "--kg", "2"], ("--kg goes with --mesh",)),
    (["--mesh", "x.obj2", "--kg", "2"], ("ending in .obj2",)),
    (["--mesh", "x.gdf", "--kg", "2", "--mesh-units", "yd"], ("--mesh-units yd",)),
])
def test_bad_rao_options_are_one_line(tmp_path, args, words):
    one_line_exit_2(runner.invoke(app, ["rao", *args, "--out", str(tmp_path / "o")]), *words)
