"""The Wigley hull in `marinecdpr rao`: its hydrostatics in closed form against the integrals
of its form and against Capytaine's mesh, the stiffness the solve uses, long waves and the
roll resonance by hand, and the command's file."""

import math

import numpy as np
import pytest
from scipy import integrate
from typer.testing import CliRunner

pytest.importorskip("capytaine")

from marinecdpr.cli.app import app  # noqa: E402
from marinecdpr.motion.bem import (  # noqa: E402
    PITCH_GYRADIUS_OVER_LENGTH,
    ROLL_GYRADIUS_DRY_OVER_BEAM,
    box_hydrostatics,
    hull_bem,
    wigley_half_breadth,
    wigley_hydrostatics,
    wigley_mesh,
)
from marinecdpr.motion.rao import read_capytaine  # noqa: E402
from test_bem import read_capytaine_ds  # noqa: E402

runner = CliRunner()
L, B, T, GM = 100.0, 20.0, 6.0, 2.0
HULL = dict(length_m=L, beam_m=B, draught_m=T, gm_m=GM)
RHO, G = 1025.0, 9.81
PANEL = 4.0  # 208 panels: the mesh's volume 1.6 % short of the form's


@pytest.fixture(scope="module")
def bem():
    return hull_bem(shape="wigley", **HULL, roll_damping_ratio=0.05, omega=np.linspace(0.15, 1.2, 22),
                    heading_deg=[90.0, 180.0], panel_m=PANEL)


def _half_breadth(x, z):
    return wigley_half_breadth(x, z, length_m=L, beam_m=B, draught_m=T)


def test_the_hydrostatics_are_the_integrals_of_the_form():
    h = wigley_hydrostatics(L, B, T)
    # by hand for 100 x 20 x 6 m: (4/9) L B T, (2/3) L B, 5T/8, (4/105) L B^3, L^3 B / 30
    assert h.volume_m3 == pytest.approx(16000.0 / 3.0, rel=1e-12)
    assert h.waterplane_area_m2 == pytest.approx(4000.0 / 3.0, rel=1e-12)
    assert h.kb_m == pytest.approx(3.75, rel=1e-12)
    assert h.transverse_inertia_m4 == pytest.approx(3.2e6 / 105.0, rel=1e-12)  # 30476.19 m^4
    assert h.longitudinal_inertia_m4 == pytest.approx(2e7 / 30.0, rel=1e-12)  # 666666.7 m^4
    assert h.bm_m == pytest.approx(3 * B * B / (35 * T), rel=1e-12)  # 5.714 m
    assert h.bml_m == pytest.approx(125.0, rel=1e-12)
    # the same numerically from y(x, z), on another hull too (the closed forms' powers of L, B, T)
    for dims in ((L, B, T), (87.0, 11.0, 7.5)):
        ln, bn, tn = dims
        y = lambda x, z: wigley_half_breadth(x, z, length_m=ln, beam_m=bn, draught_m=tn)  # noqa: E731
        hn = wigley_hydrostatics(*dims)
        volume = integrate.dblquad(lambda z, x: 2 * y(x, z), -ln / 2, ln / 2, -tn, 0.0)[0]
        moment = integrate.dblquad(lambda z, x: 2 * z * y(x, z), -ln / 2, ln / 2, -tn, 0.0)[0]
        area = integrate.quad(lambda x: 2 * y(x, 0.0), -ln / 2, ln / 2)[0]
        i_t = integrate.quad(lambda x: 2.0 / 3.0 * y(x, 0.0) ** 3, -ln / 2, ln / 2)[0]
        i_l = integrate.quad(lambda x: x * x * 2 * y(x, 0.0), -ln / 2, ln / 2)[0]
        assert hn.volume_m3 == pytest.approx(volume, rel=1e-9)
        assert hn.kb_m == pytest.approx(tn + moment / volume, rel=1e-9)  # z_B = -3T/8
        assert hn.waterplane_area_m2 == pytest.approx(area, rel=1e-9)
        assert hn.transverse_inertia_m4 == pytest.approx(i_t, rel=1e-9)
        assert hn.longitudinal_inertia_m4 == pytest.approx(i_l, rel=1e-9)
    # the box's are unchanged: B^2 / (12 T) and L^2 / (12 T)
    box = box_hydrostatics(L, B, T)
    assert (box.volume_m3, box.waterplane_area_m2, box.kb_m) == (12000.0, 2000.0, 3.0)
    assert box.bm_m == pytest.approx(400.0 / 72.0, rel=1e-15) and box.bml_m == pytest.approx(1e4 / 72.0, rel=1e-15)


def test_the_mesh_is_the_form_with_its_normals_outward():
    h = wigley_hydrostatics(L, B, T)
    mesh = wigley_mesh(length_m=L, beam_m=B, draught_m=T, panel_m=PANEL)
    assert mesh.nb_faces == 2 * 26 * 4  # ceil(100 / 4) -> even along x, ceil(girth 12.8 m / 4) along z
    # outward normals make Capytaine's volume positive: the three divergence-theorem
    # estimates all within 2 % of (4/9) L B T (the chords fall short of the convex sections)
    for v in mesh.volumes:
        assert v == pytest.approx(h.volume_m3, rel=0.02)
    assert mesh.waterplane_area == pytest.approx(h.waterplane_area_m2, rel=0.002)
    ys, ny = mesh.faces_centers[:, 1], mesh.faces_normals[:, 1]
    assert np.all(ny * np.sign(ys) > 0.25)  # each side's normals point away from the centreplane
    # the vertices lie on the form, both sides, bow to stern and keel to waterline
    x, y, z = mesh.vertices.T
    np.testing.assert_allclose(np.abs(y), _half_breadth(x, z), atol=1e-12)
    assert (x.min(), x.max(), z.min(), z.max(), y.min(), y.max()) == (-50.0, 50.0, -6.0, 0.0, -10.0, 10.0)
    from capytaine import FloatingBody

    buoyancy = FloatingBody(mesh=mesh, center_of_mass=(0.0, 0.0, 0.0)).center_of_buoyancy
    assert buoyancy[2] == pytest.approx(h.kb_m - T, rel=0.02)  # -3T/8 = -2.25 m


def test_the_stiffness_and_inertia_are_the_hand_formulas(bem):
    h = wigley_hydrostatics(L, B, T)
    volume = 4.0 / 9.0 * L * B * T
    kg = 5.0 / 8.0 * T + 3 * B * B / (35 * T) - GM  # KB + BM - GM = 7.464 m
    C = bem["hydrostatic_stiffness"]
    stiffness = {"Heave": RHO * G * 2.0 / 3.0 * L * B,  # 13.407e6 N/m
                 "Roll": RHO * G * volume * GM,  # 107.256e6 N m/rad
                 "Pitch": RHO * G * volume * (5.0 / 8.0 * T + 3 * L * L / (40 * T) - kg)}  # GM_L 121.29 m: 6.504e9
    for dof, value in stiffness.items():
        assert float(C.sel(influenced_dof=dof, radiating_dof=dof)) == pytest.approx(value, rel=1e-9)
    assert stiffness["Pitch"] == pytest.approx(6.50431e9, rel=1e-5)
    assert np.count_nonzero(C.values) == 3
    M = bem["inertia_matrix"]
    mass = RHO * h.volume_m3
    zg = kg - T  # G 1.464 m above the waterline
    assert float(M.sel(influenced_dof="Heave", radiating_dof="Heave")) == pytest.approx(mass, rel=1e-12)
    assert float(M.sel(influenced_dof="Roll", radiating_dof="Roll")) == pytest.approx(
        mass * ((ROLL_GYRADIUS_DRY_OVER_BEAM * B) ** 2 + zg * zg), rel=1e-12)
    assert float(M.sel(influenced_dof="Pitch", radiating_dof="Pitch")) == pytest.approx(
        mass * ((PITCH_GYRADIUS_OVER_LENGTH * L) ** 2 + zg * zg), rel=1e-12)
    assert float(M.sel(influenced_dof="Sway", radiating_dof="Roll")) == pytest.approx(-mass * zg, rel=1e-12)
    assert bem.attrs["hull"].startswith("Wigley hull 100 x 20 x 6 m, GM 2 m, roll damping 0.05 of critical")
    assert "208 panels" in bem.attrs["hull"]


def test_in_long_waves_it_rides_them(bem):
    rao = read_capytaine_ds(bem)
    head, beam = rao.heading_deg.tolist().index(180.0), rao.heading_deg.tolist().index(90.0)
    # at 0.15 rad/s (a 2.7 km wave on a 100 m hull): heave 1, pitch the wave slope k in head seas
    assert abs(rao.values[2, head, 0]) == pytest.approx(1.0, abs=0.01)
    k0 = rao.omega[0] ** 2 / G
    assert abs(rao.values[4, head, 0]) == pytest.approx(k0, rel=0.05)
    # roll in beam seas: the slope within 30 %, as the box's (sway coupled, a third of w_n)
    assert 0.7 * k0 < abs(rao.values[3, beam, 0]) < 1.3 * k0


def test_roll_peaks_at_its_natural_frequency_with_sway_free(bem):
    """The viscous damping is set at w_n = sqrt(C44 / (I44 + A44)) (0.556 rad/s); the peak
    in beam seas is where roll resonates with sway free: the roll inertia less the sway
    coupling's, (I24 + A24)^2 / (m + A22), at 0.586 rad/s (G 1.46 m above the waterline;
    the box's coupling nearly cancels, 0.530 either way)."""
    rao = read_capytaine_ds(bem)
    roll = np.abs(rao.values[3, rao.heading_deg.tolist().index(90.0)])
    w = rao.omega

    def inertia(a, b, at):
        added = bem["added_mass"].sel(influenced_dof=a, radiating_dof=b).values
        return float(bem["inertia_matrix"].sel(influenced_dof=a, radiating_dof=b)) + np.interp(at, w, added)

    C44 = float(bem["hydrostatic_stiffness"].sel(influenced_dof="Roll", radiating_dof="Roll"))
    w_n = w_c = 0.5
    for _ in range(30):
        w_n = math.sqrt(C44 / inertia("Roll", "Roll", w_n))
        w_c = math.sqrt(C44 / (inertia("Roll", "Roll", w_c) - inertia("Sway", "Roll", w_c) ** 2
                               / inertia("Sway", "Sway", w_c)))
    assert w_n == pytest.approx(0.556, abs=0.005) and w_c == pytest.approx(0.586, abs=0.005)
    assert f"(at {w_n:.3g} rad/s)" in bem.attrs["hull"]
    assert abs(w[np.argmax(roll)] - w_c) <= 0.5 * (w[1] - w[0])  # the grid's nearest point (0.60)
    b44 = float(bem["roll_damping"])
    assert b44 == pytest.approx(2 * 0.05 * math.sqrt(C44 * inertia("Roll", "Roll", w_n)), rel=1e-9)
    # its peak on this grid, 11.6 deg/m, is over twice the box's of the same main
    # dimensions (4.7 deg/m, tests/motion/test_bem.py's grid and 5 m panels)
    assert 9.0 < np.degrees(roll.max()) < 14.0


def test_the_command_writes_the_wigley_hull_and_refuses_a_typo(tmp_path):
    args = ["rao", "--length", "100", "--beam", "20", "--draught", "6", "--gm", "2", "--panel", "8",
            "--omega", "0.3:1.2:4", "--headings", "90,180"]
    res = runner.invoke(app, [*args, "--hull", "wigley", "--out", str(tmp_path / "r")])
    assert res.exit_code == 0, res.output
    assert "box approximation of the same main dimensions" in res.stdout
    rao = read_capytaine(tmp_path / "r" / "rao.nc")
    direct = read_capytaine_ds(hull_bem(shape="wigley", **HULL, roll_damping_ratio=0.05, omega=np.linspace(0.3, 1.2, 4),
                            heading_deg=[90.0, 180.0], panel_m=8.0))
    np.testing.assert_allclose(rao.values, direct.values, rtol=1e-10, atol=1e-14)
    import xarray as xr

    with xr.open_dataset(tmp_path / "r" / "rao.nc") as ds:
        heave = float(ds["hydrostatic_stiffness"].sel(influenced_dof="Heave", radiating_dof="Heave"))
    assert heave == pytest.approx(RHO * G * 2.0 / 3.0 * L * B, rel=1e-9)  # not the box's rho g L B
    header = (tmp_path / "r" / "rao.csv").read_text().splitlines()[:2]
    assert header[0].startswith("# RAOs from BEM: Wigley hull 100 x 20 x 6 m, GM 2 m")
    assert header[1].startswith("# made by: marinecdpr rao --hull wigley --length 100 --beam 20")
    bad = runner.invoke(app, [*args, "--hull", "ship", "--out", str(tmp_path / "bad")])
    assert bad.exit_code == 2 and "--hull ship: expected one of box, wigley" in bad.stderr, bad.output
    assert bad.stderr.count("\n") == 1 and not (tmp_path / "bad").exists()
    with pytest.raises(ValueError, match="shape 'ship'"):
        hull_bem(shape="ship", **HULL, roll_damping_ratio=0.05, omega=[0.5], heading_deg=[90.0])
