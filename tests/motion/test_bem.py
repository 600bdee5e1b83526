"""Hull RAOs from Capytaine (`marinecdpr rao`): hydrostatics and long waves by hand, the roll
resonance where its natural frequency says, the file the scenario reads, and the box
approximation's error against BEM, measured."""

from __future__ import annotations

import math

import numpy as np
import pytest
from typer.testing import CliRunner

pytest.importorskip("capytaine")

from marinecdpr.cli.app import app  # noqa: E402
from marinecdpr.motion.bem import ROLL_GYRADIUS_DRY_OVER_BEAM, box_hull_bem  # noqa: E402
from marinecdpr.motion.rao import box_hull_rao, read_capytaine  # noqa: E402

runner = CliRunner()
HULL = dict(length_m=100.0, beam_m=20.0, draught_m=6.0, gm_m=2.0)
RHO, G = 1025.0, 9.81


@pytest.fixture(scope="module")
def bem():
    return box_hull_bem(**HULL, roll_damping_ratio=0.05, omega=np.linspace(0.15, 1.2, 22), heading_deg=[90.0, 180.0],
                        panel_m=5.0)


def test_hydrostatics_and_long_waves_by_hand(bem):
    L, B, T, GM = HULL.values()
    C = bem["hydrostatic_stiffness"]
    # heave rho g A_wp and roll rho g V GM, from the mesh
    assert float(C.sel(influenced_dof="Heave", radiating_dof="Heave")) == pytest.approx(RHO * G * L * B, rel=1e-6)
    assert float(C.sel(influenced_dof="Roll", radiating_dof="Roll")) == pytest.approx(RHO * G * L * B * T * GM,
                                                                                       rel=1e-6)
    # in waves far longer than the hull it rides them: heave 1 in head seas, roll the slope in beam seas
    rao = read_capytaine_ds(bem)
    w0 = rao.omega[0]
    k0 = w0 * w0 / G
    assert abs(rao.values[2, rao.heading_deg.tolist().index(180.0), 0]) == pytest.approx(1.0, abs=0.01)
    # roll tends to the wave slope k (rad/m) as omega -> 0; at 0.15 rad/s (a third of the
    # roll frequency, sway coupled) within 30 % of it: not degrees, not the wave height
    assert 0.7 * k0 < abs(rao.values[3, rao.heading_deg.tolist().index(90.0), 0]) < 1.3 * k0


def read_capytaine_ds(ds):
    import tempfile
    from pathlib import Path

    import capytaine as cpt

    with tempfile.TemporaryDirectory() as d:
        path = Path(d) / "rao.nc"
        cpt.export_dataset(str(path), ds)
        return read_capytaine(path)


def test_the_file_reads_back_as_the_conjugate_of_capytaines_rao(bem):
    rao = read_capytaine_ds(bem)
    raw = bem["RAO"].transpose("radiating_dof", "wave_direction", "omega").values
    order = np.argsort(np.degrees(bem["wave_direction"].values) % 360.0)
    np.testing.assert_allclose(rao.values, np.conj(raw[:, order]), rtol=1e-12, atol=1e-15)


def test_roll_peaks_at_its_natural_frequency_and_damping_lowers_it(bem):
    rao = read_capytaine_ds(bem)
    beam = rao.heading_deg.tolist().index(90.0)
    roll = np.abs(rao.values[3, beam])
    C44 = float(bem["hydrostatic_stiffness"].sel(influenced_dof="Roll", radiating_dof="Roll"))
    I44 = float(bem["inertia_matrix"].sel(influenced_dof="Roll", radiating_dof="Roll"))
    A44 = bem["added_mass"].sel(influenced_dof="Roll", radiating_dof="Roll").values
    w = rao.omega
    w_n = math.sqrt(C44 / (I44 + np.interp(0.48, w, A44)))
    assert abs(w[np.argmax(roll)] - w_n) <= (w[1] - w[0])  # on the grid, the nearest point
    # the viscous damping is zeta of critical at w_n: 2 zeta sqrt(C44 (I44 + A44))
    b44 = float(bem["roll_damping"])
    assert b44 == pytest.approx(2 * 0.05 * math.sqrt(C44 * (I44 + np.interp(w_n, w, A44))), rel=0.02)
    assert I44 > (ROLL_GYRADIUS_DRY_OVER_BEAM * HULL["beam_m"]) ** 2 * RHO * 100 * 20 * 6  # + zg^2 shift
    stiffer = box_hull_bem(**HULL, roll_damping_ratio=0.15, omega=w, heading_deg=[90.0], panel_m=5.0)
    assert np.abs(read_capytaine_ds(stiffer).values[3, 0]).max() < 0.6 * roll.max()


def test_the_box_approximation_against_bem_in_numbers(bem):
    """What rao.box_hull_rao's docstring states, on paper_sea's hull (100 x 20 x 6 m, GM 2 m,
    5 % roll damping): heave in head seas within 0.1 m/m of BEM; roll in beam seas peaks
    2.5-5 times BEM's (17.5 against 4.7 deg/m on this grid), so the approximation is a
    pessimistic estimate, not a model of roll."""
    rao = read_capytaine_ds(bem)
    box = box_hull_rao(**HULL, roll_damping_ratio=0.05, omega=rao.omega, heading_deg=rao.heading_deg)
    head, beam = rao.heading_deg.tolist().index(180.0), rao.heading_deg.tolist().index(90.0)
    assert np.abs(np.abs(box.values[2, head]) - np.abs(rao.values[2, head])).max() < 0.1
    ratio = np.abs(box.values[3, beam]).max() / np.abs(rao.values[3, beam]).max()
    assert 2.5 <= ratio <= 5.0


@pytest.mark.figures
def test_the_command_writes_what_the_scenario_reads(tmp_path):
    res = runner.invoke(app, ["rao", "--length", "100", "--beam", "20", "--draught", "6", "--gm", "2", "--panel", "8",
                              "--omega", "0.3:1.2:4", "--headings", "90,180", "--out", str(tmp_path / "r")])
    assert res.exit_code == 0, res.output
    rao = read_capytaine(tmp_path / "r" / "rao.nc")
    assert rao.heading_deg.tolist() == [90.0, 180.0] and rao.omega.size == 4
    assert (tmp_path / "r" / "rao.png").stat().st_size > 10_000
    for args, words in ((["--omega", "1.2:0.3:4"], "--omega 1.2:0.3:4: expected first:last:count"),
                        (["--gm", "30"], "gm_m 30 m is more than KB + BM")):
        bad = runner.invoke(app, ["rao", "--length", "100", "--beam", "20", "--draught", "6", "--gm", "2", *args,
                                  "--out", str(tmp_path / "bad")])
        assert bad.exit_code == 2 and words in bad.stderr and bad.stderr.count("\n") == 1, bad.output


def _shipped():
    from importlib import resources

    from marinecdpr.motion.rao import read_rao_csv

    return read_rao_csv(resources.files("marinecdpr.scenario") / "builtin" / "paper_sea_rao.csv")


SHIPPED_CHECKED = [0, 8, 9, 19, 38]
"""The rows of paper_sea_rao.csv solved afresh here: its first and last frequencies (0.1 and
2 rad/s), the two about the roll peak (0.5 and 0.55; 0.532 rad/s) and one between (1.05).
BEM solves each frequency on its own: a row's numbers are the same in a solve of five as in
the solve of all 39. The whole table, every frequency, is checked by
benchmarks/bench_rao_shipped.py (a 16 s solve on two cores: moved there, issue 37 item 15)."""


def test_the_shipped_paper_sea_table_is_the_bem_solution_it_says_it_is():
    """paper_sea_rao.csv against a fresh solve with the command line its first lines give, at
    the frequencies of :data:`SHIPPED_CHECKED` and every heading: heave, roll and pitch to 1e-6
    of the largest (the CSV keeps 10 digits; BEM's linear algebra may differ in the last bits
    between machines)."""
    shipped = _shipped()
    header = _shipped_header()
    assert "--headings 0,30,60,90,120,150,180,210,240,270,300,330 --omega 0.1:2.0:39 --panel 2.5" in header[1]
    np.testing.assert_allclose(shipped.omega, np.linspace(0.1, 2.0, 39), rtol=1e-9)
    rows = np.array(SHIPPED_CHECKED)
    fresh = read_capytaine_ds(box_hull_bem(**HULL, roll_damping_ratio=0.05, omega=np.linspace(0.1, 2.0, 39)[rows],
                                           heading_deg=np.arange(0.0, 360.0, 30.0), panel_m=2.5))
    np.testing.assert_allclose(shipped.omega[rows], fresh.omega, rtol=1e-9)
    np.testing.assert_array_equal(shipped.heading_deg, fresh.heading_deg)
    for dof in (2, 3, 4):
        scale = np.abs(fresh.values[dof]).max()
        np.testing.assert_allclose(shipped.values[dof][:, rows], fresh.values[dof], rtol=0, atol=1e-6 * scale)
    assert header[0].startswith("# RAOs from BEM: box 100 x 20 x 6 m, GM 2 m")


def _shipped_header() -> list[str]:
    from importlib import resources

    return (resources.files("marinecdpr.scenario") / "builtin" / "paper_sea_rao.csv").read_text().splitlines()[:3]


def test_paper_seas_significant_roll_in_beam_seas_is_bems():
    """Issue 12: in beam seas at Hs 2 m, Tp 8 s (long-crested), paper_sea's significant roll
    4 sqrt(m0) is within 30 % of BEM's; the box approximation's is several times more."""
    import marinecdpr
    from marinecdpr.motion.basemotion import evaluate_base_motion
    from marinecdpr.motion.seastate import jonswap

    w = np.linspace(0.1, 2.0, 2000)
    S = jonswap(w, 2.0, 8.0)

    def significant_deg(rao):
        r = np.abs(rao.at(w, 90.0)[3])
        return float(np.degrees(4.0 * np.sqrt(np.trapezoid(r * r * S, w))))

    bem = significant_deg(_shipped())
    box = significant_deg(box_hull_rao(**HULL, roll_damping_ratio=0.05, omega=w, heading_deg=[90.0]))
    sea = marinecdpr.load_scenario("paper_sea")
    sea = sea.with_changes(base_motion=sea.base_motion.model_dump(exclude_none=True)
                           | {"heading_deg": 90.0, "spreading": "none", "record_s": 1800.0},
                           time={"step_s": 0.1, "duration_s": 1799.9})
    roll = evaluate_base_motion(sea.base_motion, np.arange(18000) * 0.1).eta[:, 3]
    simulated = float(np.degrees(4.0 * roll.std()))
    assert simulated == pytest.approx(bem, rel=0.3)
    assert 1.2 < bem < 3.0 and box > 2.0 * bem


# -------------------- formerly tests/test_hull_mesh_raos.py

"""A hull mesh's RAOs (issue 37, item 2): about the mesh's own origin, with the restoring
matrix's couplings a fore-aft asymmetric hull brings (C35), against Capytaine run
directly; a half hull with its symmetry flag equal to its mirrored full hull."""


from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

pytest.importorskip("capytaine")

from marinecdpr.cli.app import app  # noqa: E402
from marinecdpr.motion.bem import (  # noqa: E402
    PITCH_GYRADIUS_OVER_LENGTH, ROLL_GYRADIUS_DRY_OVER_BEAM, mesh_bem,
)
from marinecdpr.motion.hullmesh import load_hull_mesh, shipped_mesh  # noqa: E402
from tests.mesh_shapes import cut_wigley, gdf, hst, mirrored, nemoh, pnl  # noqa: E402

runner = CliRunner()
RHO, G = 1025.0, 9.81
DOFS = ("Surge", "Sway", "Heave", "Roll", "Pitch", "Yaw")
OMEGA = np.linspace(0.3, 1.2, 5)
HEADINGS = (90.0, 135.0, 180.0)


def _table(path: Path) -> np.ndarray:
    """rao.csv's numbers: omega, heading, amplitude, phase."""
    rows = [ln.split(",") for ln in path.read_text().splitlines() if ln and not ln.startswith("#")][1:]
    return np.array([[float(r[0]), float(r[1]), float(r[3]), float(r[4])] for r in rows])


@pytest.fixture(scope="module")
def asymmetric(tmp_path_factory):
    """The cut Wigley hull (100 x 16 x 6 m, transom at x = -30 m, fuller forward below:
    x_B 5.1 m, x_F 4.3 m) through :func:`mesh_bem` and through Capytaine directly: the same
    mesh file, G above Capytaine's own centre of buoyancy at the same KG (GM 1 m), the mass
    rho V of Capytaine's own volume, the inertia of the same gyradii about G moved to the
    origin as M_O = J^T M_G J (J: the origin's motion to G's), the same viscous roll
    damping, rotations about the mesh's origin."""
    import capytaine as cpt
    import xarray as xr

    path = gdf(tmp_path_factory.mktemp("asym") / "cut_wigley.gdf", cut_wigley())
    hull = load_hull_mesh(path)
    kg = hull.hydrostatics.kb_m + hull.hydrostatics.bm_m - 1.0
    ours = mesh_bem(hull, kg_m=kg, roll_damping_ratio=0.05, omega=OMEGA, heading_deg=HEADINGS)

    mesh = cpt.load_mesh(str(path))
    wet = cpt.FloatingBody(mesh=mesh, dofs=cpt.rigid_body_dofs(rotation_center=(0, 0, 0))).immersed_part()
    V = wet.volume
    x_b, y_b, _ = wet.center_of_buoyancy
    z = wet.mesh.vertices[:, 2]
    L, B = np.ptp(wet.mesh.vertices[:, 0]), np.ptp(wet.mesh.vertices[:, 1])
    r = np.array([x_b, y_b, kg + z.min()])
    m = RHO * V
    skew = np.array([[0.0, -r[2], r[1]], [r[2], 0.0, -r[0]], [-r[1], r[0], 0.0]])
    J = np.block([[np.eye(3), -skew], [np.zeros((3, 3)), np.eye(3)]])
    M_G = np.diag([m, m, m, m * (ROLL_GYRADIUS_DRY_OVER_BEAM * B) ** 2, m * (PITCH_GYRADIUS_OVER_LENGTH * L) ** 2,
                   m * (PITCH_GYRADIUS_OVER_LENGTH * L) ** 2])
    body = cpt.FloatingBody(mesh=mesh, dofs=cpt.rigid_body_dofs(rotation_center=(0, 0, 0)), center_of_mass=tuple(r),
                            mass=m).immersed_part()
    body.inertia_matrix = body.add_dofs_labels_to_matrix(J.T @ M_G @ J)
    body.hydrostatic_stiffness = body.compute_hydrostatic_stiffness(rho=RHO, g=G)
    direct = cpt.BEMSolver().fill_dataset(
        xr.Dataset(coords={"omega": OMEGA, "wave_direction": np.radians(HEADINGS), "radiating_dof": list(body.dofs),
                           "water_depth": [np.inf], "rho": [RHO], "g": [G]}), body, progress_bar=False)
    damping = np.zeros((6, 6))
    damping[3, 3] = float(ours["roll_damping"])
    own = cpt.post_pro.rao(direct, dissipation=body.add_dofs_labels_to_matrix(damping))
    direct["hydrostatic_stiffness"] = (("influenced_dof", "radiating_dof"), ours["hydrostatic_stiffness"].values)
    same = cpt.post_pro.rao(direct, dissipation=body.add_dofs_labels_to_matrix(damping))
    return hull, ours, own, same, body


def _worst(ours, direct, pairs) -> dict:
    """Per (DOF, heading): the largest |RAO| difference over the frequencies, over the
    largest |RAO| there (Capytaine's)."""
    a, b = np.abs(ours["RAO"].values), np.abs(direct.values)  # (omega, direction, dof)
    out = {}
    for dof, heading in pairs:
        k, j = DOFS.index(dof), HEADINGS.index(heading)
        out[dof, heading] = float(np.abs(a[:, j, k] - b[:, j, k]).max() / b[:, j, k].max())
    return out


def test_an_asymmetric_hull_s_heave_and_pitch_agree_with_capytaine_s_own_hydrostatics(asymmetric):
    """Capytaine's own stiffness (its sums over the panels) and its own volume: heave and
    pitch in beam, bow-quartering and head seas within 2 % of their peaks (measured: heave
    0.03 % to 0.09 %, pitch 0.03 % to 0.10 %, and 1.7 % for the small pitch in beam seas).
    Before: the RAOs about a point above the centre of buoyancy, without C35."""
    _, ours, own, _, _ = asymmetric
    worst = _worst(ours, own, [(d, h) for d in ("Heave", "Pitch") for h in HEADINGS])
    assert max(worst.values()) < 0.02, worst


def test_an_asymmetric_hull_s_raos_agree_with_capytaine_given_the_same_inputs(asymmetric):
    """The same stiffness too: every DOF the waves move at each heading within 1 % of its
    peak (measured 0.01 % to 0.50 %; the mass from Capytaine's volume, 0.06 % off ours)."""
    _, ours, _, same, _ = asymmetric
    pairs = [(d, h) for h in (90.0, 135.0) for d in DOFS] + [(d, 180.0) for d in ("Surge", "Heave", "Pitch")]
    worst = _worst(ours, same, pairs)
    assert max(worst.values()) < 0.01, worst


def test_the_restoring_matrix_has_the_heave_pitch_coupling_capytaine_finds(asymmetric):
    """C33, C35 = C53 and C55 about the mesh's origin against Capytaine's own sums (measured
    0.05 %, 0.6 %, 0.15 %; its C44, a small difference of its one-point sums, is 7 % off);
    C35 is 0.043 C33 L here, far from nothing."""
    _, ours, _, _, body = asymmetric
    C = ours["hydrostatic_stiffness"].values
    K = body.hydrostatic_stiffness.values
    for i, j, tol in ((2, 2, 1e-3), (2, 4, 1e-2), (4, 2, 1e-2), (4, 4, 3e-3)):
        assert C[i, j] == pytest.approx(K[i, j], rel=tol), (i, j)
    assert abs(C[2, 4]) > 0.03 * C[2, 2] * 100.0


def _prism(a: float, b1: float, b2: float, depth: float, n: int = 6) -> np.ndarray:
    """A prism with vertical sides, its waterplane the trapezoid 0 <= x <= a, |y| <= w(x) =
    b1 + (b2 - b1) x / a; panels (k, 4, 3) turned out of it."""
    x = np.linspace(0.0, a, n + 1)
    w = b1 + (b2 - b1) * x / a
    panels = []
    for i in range(n):
        p = [(x[i], w[i]), (x[i + 1], w[i + 1])]
        s = [(x[i], -w[i]), (x[i + 1], -w[i + 1])]
        for (x0, y0), (x1, y1) in (p, s):  # the sides
            panels.append([(x0, y0, -depth), (x1, y1, -depth), (x1, y1, 0.0), (x0, y0, 0.0)])
        panels.append([(x[i], -w[i], -depth), (x[i + 1], -w[i + 1], -depth), (x[i + 1], w[i + 1], -depth),
                       (x[i], w[i], -depth)])
    for xe, we in ((0.0, b1), (a, b2)):  # the ends
        panels.append([(xe, -we, -depth), (xe, we, -depth), (xe, we, 0.0), (xe, -we, 0.0)])
    P = np.array(panels, dtype=float)
    inside = np.array([a / 2.0, 0.0, -depth / 2.0])
    normal = np.cross(P[:, 2] - P[:, 0], P[:, 3] - P[:, 1])
    out = np.einsum("ij,ij->i", normal, P.mean(axis=1) - inside) > 0
    return np.where(out[:, None, None], P, P[:, ::-1])


def test_c35_by_hand_on_a_trapezoidal_prism(tmp_path):
    """Waterplane 0 <= x <= a, half-breadth b1 to b2: int x dA = a^2 (b1 + 2 b2) / 3, so
    C35 = C53 = -rho g a^2 (b1 + 2 b2) / 3 (Capytaine's sign: pitch bow down sinks the bow,
    whose buoyancy lifts); C33 = rho g a (b1 + b2); C55 = rho g (a^3 (b1/6 + b2/2) + V (z_B -
    z_G)); C44 = rho g ((2/3) int w^3 dx + V (z_B - z_G)). From `rao --mesh`'s rao.nc, to
    1e-9; Capytaine's own C33 and C35 (exact for these linear integrands) to 1e-9 too."""
    import capytaine as cpt
    import xarray as xr

    a, b1, b2, T, kg = 30.0, 3.0, 6.0, 4.0, 3.0
    path = gdf(tmp_path / "prism.gdf", _prism(a, b1, b2, T))
    res = runner.invoke(app, ["rao", "--mesh", str(path), "--kg", f"{kg}", "--omega", "0.5:1.0:2", "--headings", "180",
                              "--out", str(tmp_path / "o")])
    assert res.exit_code == 0, res.output
    C = xr.open_dataset(tmp_path / "o" / "rao.nc")["hydrostatic_stiffness"].values
    A = a * (b1 + b2)
    V = A * T
    dz = -T / 2.0 - (kg - T)  # z_B - z_G
    int_w3 = a * (b2**4 - b1**4) / (4.0 * (b2 - b1))
    want = {(2, 2): RHO * G * A, (2, 4): -RHO * G * a * a * (b1 + 2.0 * b2) / 3.0,
            (4, 4): RHO * G * (a**3 * (b1 / 6.0 + b2 / 2.0) + V * dz), (3, 3): RHO * G * (2.0 / 3.0 * int_w3 + V * dz)}
    for (i, j), value in want.items():
        assert C[i, j] == pytest.approx(value, rel=1e-9), (i, j)
        assert C[j, i] == pytest.approx(value, rel=1e-9), (j, i)
    assert C[2, 3] == pytest.approx(0.0, abs=1e-9 * C[2, 2] * a) and C[3, 4] == pytest.approx(0.0, abs=1e-9 * C[4, 4])
    body = cpt.FloatingBody(mesh=cpt.load_mesh(str(path)), dofs=cpt.rigid_body_dofs(rotation_center=(0, 0, 0)),
                            center_of_mass=(0.0, 0.0, kg - T), mass=RHO * V).immersed_part()
    K = body.compute_hydrostatic_stiffness(rho=RHO, g=G).values
    assert K[2, 2] == pytest.approx(want[2, 2], rel=1e-9) and K[2, 4] == pytest.approx(want[2, 4], rel=1e-9)


def _half_and_full(tmp_path: Path) -> tuple[np.ndarray, np.ndarray]:
    half = cut_wigley(half=True, tjunctions=True, nx=16, nz=4)
    return half, np.concatenate([half, mirrored(half)])


def test_a_half_hull_with_isy_gives_its_mirrored_full_hull_s_raos(tmp_path):
    """The cut Wigley's port half with T-junctions as a GDF with ISY = 1, and the same
    panels with their mirror images written out (ISY = 0): `rao --mesh` gives the same
    table (measured: equal, bit for bit) and the same hydrostatics.
    Before: both refused as open below the waterline (the T-junctions)."""
    half, full = _half_and_full(tmp_path)
    paths = {"half": gdf(tmp_path / "half.gdf", half, isy=1), "full": gdf(tmp_path / "full.gdf", full)}
    out = {}
    for k, p in paths.items():
        res = runner.invoke(app, ["rao", "--mesh", str(p), "--kg", "5", "--omega", "0.5:1.0:2", "--headings", "150",
                                  "--out", str(tmp_path / k)])
        assert res.exit_code == 0, res.output
        out[k] = (_table(tmp_path / k / "rao.csv"), res.stdout.split("(KG")[0])
    (a, text_a), (b, text_b) = out["half"], out["full"]
    assert text_a == text_b  # the hydrostatics printed
    np.testing.assert_allclose(a[:, 2], b[:, 2], rtol=0, atol=1e-9 * b[:, 2].max())
    np.testing.assert_allclose(a[:, :2], b[:, :2], rtol=0, atol=0)


@pytest.mark.parametrize("writer, flag", [(gdf, "isy"), (nemoh, "symmetric"), (pnl, "y_symmetric"), (hst, "symmetry")])
def test_each_format_s_symmetry_flag_gives_the_full_hull(tmp_path, writer, flag):
    """GDF's ISY, Nemoh's symmetry, PNL's y-symmetry, HST's SYMMETRY 1: the half hull's
    hydrostatics are the full one's (measured: equal to 1e-15)."""
    half, full = _half_and_full(tmp_path)
    want = load_hull_mesh(gdf(tmp_path / "full.gdf", full)).hydrostatics
    ending = {"gdf": "gdf", "nemoh": "dat", "pnl": "pnl", "hst": "hst"}[writer.__name__]
    got = load_hull_mesh(writer(tmp_path / f"half.{ending}", half, **{flag: 1})).hydrostatics
    for k in ("volume_m3", "waterplane_area_m2", "kb_m", "bm_m", "bml_m"):
        assert getattr(got, k) == pytest.approx(getattr(want, k), rel=1e-12), k
    for x, y in zip(got.waterplane_moments + got.centre_of_buoyancy_m, want.waterplane_moments + want.centre_of_buoyancy_m):
        assert x == pytest.approx(y, rel=1e-12, abs=1e-9)


def test_rao_csv_says_about_which_point_and_a_symmetric_hull_has_no_c35(tmp_path):
    """rao.csv's header names the point (the mesh's own origin on the waterline); the
    shipped Wigley hull, symmetric fore and aft, keeps C35 = 0 (to 1e-12 of C33 L) about it
    (a quadrilateral's two splits averaged: one split alone made its x_F 0.12 m)."""
    import xarray as xr

    res = runner.invoke(app, ["rao", "--mesh", str(shipped_mesh()), "--kg", "7", "--omega", "0.4:1.2:2", "--headings",
                              "180", "--out", str(tmp_path / "o")])
    assert res.exit_code == 0, res.output
    head = [ln for ln in (tmp_path / "o" / "rao.csv").read_text().splitlines() if ln.startswith("#")]
    assert any("about the mesh's own origin (x = 0, y = 0 in the file) on the waterline" in ln for ln in head), head
    C = xr.open_dataset(tmp_path / "o" / "rao.nc")["hydrostatic_stiffness"].values
    assert abs(C[2, 4]) <= 1e-12 * C[2, 2] * 100.0


def test_a_quarter_hull_with_isx_and_isy_is_the_whole_shipped_wigley(tmp_path):
    """The shipped Wigley hull (symmetric fore and aft and port and starboard): its panels
    with x >= 0 and y >= 0 as a GDF with ISX = ISY = 1 have the whole mesh's hydrostatics
    (measured: to 1e-15)."""
    from marinecdpr.motion.hullmesh import read_mesh

    v, f = read_mesh(shipped_mesh())
    P = v[f]
    centre = P.mean(axis=1)
    quarter = P[(centre[:, 0] > 0.0) & (centre[:, 1] > 0.0)]
    assert 4 * len(quarter) == len(P)
    want = load_hull_mesh(shipped_mesh()).hydrostatics
    got = load_hull_mesh(gdf(tmp_path / "quarter.gdf", quarter, isx=1, isy=1)).hydrostatics
    for k in ("volume_m3", "waterplane_area_m2", "kb_m", "bm_m", "bml_m"):
        assert getattr(got, k) == pytest.approx(getattr(want, k), rel=1e-12), k
    assert abs(got.waterplane_moments[0]) <= 1e-12 * want.waterplane_area_m2 * 100.0  # no C35


def test_c34_and_c45_by_hand_on_the_prism_turned_and_moved(tmp_path):
    """The trapezoidal prism turned a quarter turn (its waterplane 0 <= y <= a, asymmetric
    port and starboard) and moved c forward: int y dA = a^2 (b1 + 2 b2) / 3, int x dA = c
    A_wp, int x y dA = c int y dA, so C34 = C43 = rho g int y dA, C35 = -rho g c A_wp and
    C45 = C54 = -rho g c int y dA, to 1e-9 (Capytaine's own to 1e-9 too)."""
    import capytaine as cpt
    import xarray as xr

    a, b1, b2, T, kg, c = 30.0, 3.0, 6.0, 4.0, 3.0, 7.0
    P = _prism(a, b1, b2, T)
    P = np.stack([c - P[..., 1], P[..., 0], P[..., 2]], axis=-1)  # (x, y) -> (c - y, x): a turn, and c forward
    path = gdf(tmp_path / "turned.gdf", P)
    res = runner.invoke(app, ["rao", "--mesh", str(path), "--kg", f"{kg}", "--omega", "0.5:1.0:2", "--headings", "90",
                              "--out", str(tmp_path / "o")])
    assert res.exit_code == 0, res.output
    C = xr.open_dataset(tmp_path / "o" / "rao.nc")["hydrostatic_stiffness"].values
    A = a * (b1 + b2)
    int_y = a * a * (b1 + 2.0 * b2) / 3.0
    want = {(2, 3): RHO * G * int_y, (2, 4): -RHO * G * c * A, (3, 4): -RHO * G * c * int_y}
    body = cpt.FloatingBody(mesh=cpt.load_mesh(str(path)), dofs=cpt.rigid_body_dofs(rotation_center=(0, 0, 0)),
                            center_of_mass=(c, a / 2.0, kg - T), mass=RHO * A * T).immersed_part()
    K = body.compute_hydrostatic_stiffness(rho=RHO, g=G).values
    for (i, j), value in want.items():
        assert C[i, j] == pytest.approx(value, rel=1e-9) and C[j, i] == pytest.approx(value, rel=1e-9), (i, j)
        assert K[i, j] == pytest.approx(value, rel=1e-9), (i, j)
