"""The rao command's contract in the library (:mod:`marinecdpr.commands.rao`): its spec and
its rules on options that go together checked without the command line, the command line's
defaults the spec's, runs from Python (a box, and the same box as a mesh) giving the
command's files, and docs/commands/rao.md run as written (issue 38, items 1 and 7). The
solves need Capytaine and skip without it."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from marinecdpr.cli.app import app
from marinecdpr.commands import SpecError
from marinecdpr.commands import rao as command
from marinecdpr.commands.rao import MAX_RAO_FREQUENCIES, RaoSpec

from command_pages import assert_table_is_the_spec, cli_default, options_table, page, run_page

runner = CliRunner()
BOX = {"length": 40.0, "beam": 10.0, "draught": 3.0, "gm": 1.0}
STAMPS = ("start_of_computation", "creation_of_dataset")  # Capytaine's clock in rao.nc


@pytest.mark.parametrize("options, field, words", [
    (BOX | {"length": -40.0}, "length", "length -40: expected a positive number"),
    (BOX | {"panel": 0.0}, "panel", "panel 0: expected a positive number"),
    (BOX | {"roll_damping": 1.5}, "roll_damping", "roll_damping 1.5: expected a fraction of critical damping from "
                                                  "0 to 1"),
    (BOX | {"roll_damping": -0.1}, "roll_damping", "expected a non-negative number"),
    (BOX | {"hull": "catamaran"}, "hull", "hull catamaran: expected one of box, wigley"),
    (BOX | {"headings": "0,360"}, "headings", "a heading is given twice"),
    (BOX | {"omega": "0.2:1.8"}, "omega", "omega 0.2:1.8: expected first:last:count, e.g. 0.2:1.8:33"),
    (BOX | {"omega": "1.8:0.2:33"}, "omega", "expected first:last:count with 0 < first < last and 2 <= count <= 2000"),
    (BOX | {"omega": f"0.2:1.8:{MAX_RAO_FREQUENCIES + 1}"}, "omega", "2 <= count <= 2000"),
    (BOX | {"waterline": float("nan")}, "waterline", "waterline nan: expected a finite number"),
])
def test_a_bad_option_is_one_error_naming_its_field(options, field, words):
    with pytest.raises(SpecError) as err:
        RaoSpec(**options)
    assert err.value.field == field and err.value.flag == "--" + field.replace("_", "-")
    assert words in str(err.value) and "\n" not in str(err.value)


@pytest.mark.parametrize("options, line", [
    ({"mesh": "x.gdf"}, "--mesh x.gdf: give --kg, the centre of gravity's height above the keel, m"),
    ({"mesh": "x.gdf", "kg": 2.0, "length": 40.0, "hull": "box"},
     "--mesh x.gdf: --length, --hull cannot go with it: the mesh gives the hull (its GM from --kg)"),
    ({"length": 40.0, "beam": 10.0}, "--draught not given: give the hull's main dimensions and GM (missing --draught, "
                                     "--gm), or --mesh FILE --kg KG"),
    ({}, "--length not given: give the hull's main dimensions and GM (missing --length, --beam, --draught, --gm)"),
    (BOX | {"kg": 2.0}, "--kg 2: goes with --mesh (a box or Wigley hull takes --gm)"),
])
def test_options_that_do_not_go_together_name_the_option_to_change(options, line):
    with pytest.raises(SpecError) as err:
        RaoSpec(**options)
    assert f"{err.value.flag} {err.value.value}: {err.value.detail}".startswith(line)


def test_the_spec_keeps_headings_modulo_360_in_order_and_the_frequencies_evenly():
    from marinecdpr.motion.bem import HULL_SHAPES

    spec = RaoSpec(**BOX, headings="180,-90,-269.5", omega=(0.2, 1.0, 5))
    assert spec.headings == (90.5, 180.0, 270.0)
    assert spec.omega == "0.2:1:5" and spec.frequencies.tolist() == [0.2, 0.4, 0.6000000000000001, 0.8, 1.0]
    assert (spec.shape, spec.panel_m) == ("box", 2.5) and RaoSpec(**BOX, hull="wigley").shape == "wigley"
    assert set(HULL_SHAPES) == {"box", "wigley"}
    assert RaoSpec(mesh="x.gdf", kg=2.0).mesh == Path("x.gdf")


def test_the_command_line_s_defaults_are_the_spec_s():
    """Every option of ``rao`` but --out has the spec's field and default."""
    import typer.main

    params = {p.name: p for p in typer.main.get_command(app).commands["rao"].params}
    options = set(params) - {"out"}
    assert options == set(RaoSpec.model_fields)
    for name in options:
        default = cli_default(params[name])
        spec_default = RaoSpec.default(name)
        given = {} if name in ("mesh", "kg") else BOX
        if default is None:
            assert spec_default is None, name
        else:
            assert RaoSpec(**given | {name: default}).model_dump()[name] == spec_default, name


def test_the_command_line_names_the_flag_of_a_bad_spec_field(tmp_path):
    from conftest import one_line_exit_2

    res = runner.invoke(app, ["rao", "--length", "40", "--beam", "10", "--draught", "3", "--gm", "1", "--omega", "1:2",
                              "--out", str(tmp_path / "o")], terminal_width=4000)
    assert one_line_exit_2(res) == "error: --omega 1:2: expected first:last:count, e.g. 0.2:1.8:33"
    res = runner.invoke(app, ["rao", "--length", "40", "--out", str(tmp_path / "o")], terminal_width=4000)
    assert one_line_exit_2(res) == ("error: --beam not given: give the hull's main dimensions and GM (missing --beam, "
                                    "--draught, --gm), or --mesh FILE --kg KG")
    assert not (tmp_path / "o").exists()


def _same_nc(a: Path, b: Path) -> None:
    """rao.nc's content equal: every variable, coordinate and attribute but Capytaine's clock."""
    import xarray as xr

    x, y = xr.open_dataset(a), xr.open_dataset(b)
    for ds in (x, y):
        for stamp in STAMPS:
            ds.attrs.pop(stamp)
    assert x.identical(y)


@pytest.mark.figures
def test_a_run_from_python_writes_what_the_command_writes(tmp_path):
    pytest.importorskip("capytaine")
    spec = RaoSpec(**BOX, panel=5.0, omega="0.3:1.2:3", headings="90,180")
    est = command.estimate(spec)
    assert (est.size.frequencies, est.size.headings) == (3, 2) and est.hull is None
    result = command.run(spec, estimated=est)
    assert result.ds["RAO"].shape[:2] == (3, 2) and result.box_label == "box approximation"
    files = result.write_tables(tmp_path / "py")
    assert [p.name for p in files.paths] == ["rao.nc", "rao.csv", "rao.png"]
    res = runner.invoke(app, ["rao", "--length", "40", "--beam", "10", "--draught", "3", "--gm", "1", "--panel", "5",
                              "--omega", "0.3:1.2:3", "--headings", "90,180", "--out", str(tmp_path / "cli")],
                        terminal_width=4000)
    assert res.exit_code == 0, res.output
    assert (tmp_path / "py" / "rao.csv").read_bytes() == (tmp_path / "cli" / "rao.csv").read_bytes()
    _same_nc(tmp_path / "py" / "rao.nc", tmp_path / "cli" / "rao.nc")
    peak = float(np.degrees(np.abs(files.bem.values[3])).max())
    assert f"roll peaks at {peak:.3g} deg/m" in res.stdout
    assert result.made_by.startswith("marinecdpr rao --length 40 --beam 10 --draught 3 --gm 1 --roll-damping 0.05 "
                                     "--headings 90,180 --omega 0.3:1.2:3 --panel 5 (marinecdpr ")


def test_the_box_as_a_mesh_from_python_gives_the_box_s_raos(tmp_path):
    """The same panels through ``mesh`` (hydrostatics from the panels, G from KG) and as a box
    (closed forms, G from GM): KG = KB + BM - GM = 1.5 + 100/36 - 1; the command's files are
    the run's."""
    cpt = pytest.importorskip("capytaine")
    from marinecdpr.motion.bem import _box_resolution
    from marinecdpr.motion.hullmesh import write_gdf

    m = cpt.mesh_parallelepiped(size=(40.0, 10.0, 6.0), center=(0, 0, 0), resolution=_box_resolution(40, 10, 3, 5.0),
                                name="box")
    gdf = write_gdf(tmp_path / "box.gdf", np.asarray(m.vertices), np.asarray(m.faces), title="box 40 x 10 x 3 m")
    kg = 1.5 + 100.0 / 36.0 - 1.0
    common = dict(omega="0.3:1.2:3", headings="90,180")
    spec = RaoSpec(mesh=gdf, kg=kg, **common)
    est = command.estimate(spec)
    assert est.hull.hydrostatics.volume_m3 == pytest.approx(1200.0, rel=1e-12) and est.size.panels == est.hull.panels
    mesh = command.run(spec, estimated=est)
    box = command.run(RaoSpec(**BOX, panel=5.0, **common))
    assert float(mesh.ds.attrs["gm_m"]) == pytest.approx(1.0, rel=1e-12)
    x, y = np.asarray(box.ds["RAO"].values), np.asarray(mesh.ds["RAO"].values)
    assert np.abs(x - y).max() <= 1e-6 * np.abs(x).max()
    assert mesh.box == dict(length_m=est.hull.length_m, beam_m=est.hull.beam_m, draught_m=est.hull.draught_m,
                            gm_m=float(mesh.ds.attrs["gm_m"]), roll_damping_ratio=0.05)
    mesh.write(tmp_path / "py")
    res = runner.invoke(app, ["rao", "--mesh", str(gdf), "--kg", repr(kg), "--omega", "0.3:1.2:3", "--headings",
                              "90,180", "--out", str(tmp_path / "cli")], terminal_width=4000)
    assert res.exit_code == 0, res.output
    assert (tmp_path / "py" / "rao.csv").read_bytes() == (tmp_path / "cli" / "rao.csv").read_bytes()
    _same_nc(tmp_path / "py" / "rao.nc", tmp_path / "cli" / "rao.nc")


@pytest.mark.figures
def test_the_page_lists_the_spec_s_options_and_defaults():
    assert_table_is_the_spec("rao", RaoSpec)


@pytest.mark.figures
def test_the_page_runs_as_written(tmp_path, monkeypatch):
    pytest.importorskip("capytaine")
    ns = run_page("rao", tmp_path, monkeypatch)
    result, files = ns["result"], ns["files"]
    assert result.spec.headings == (90.0, 180.0) and ns["panels"] > 0
    # long waves: the hull heaves with the water, about 1 m/m at the lowest frequency
    assert ns["heave"].shape == (3, 2) and ns["heave"][0] == pytest.approx([1.0, 1.0], abs=0.05)
    assert [p.name for p in files.paths] == ["rao.nc", "rao.csv", "rao.png"]
    assert (tmp_path / "out" / "rao" / "rao.csv").stat().st_size > 0
    assert ns["roll_peak"] == float(np.degrees(np.abs(files.bem.values[3])).max()) > 0.0
