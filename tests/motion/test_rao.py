"""RAO tables: interpolation, CSV and Capytaine files, and the box-hull model."""

from __future__ import annotations

import math
import sys

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from marinecdpr.errors import ScenarioError
from marinecdpr.motion.rao import RAO, ROLL_GYRADIUS_OVER_BEAM, box_hull_rao, read_capytaine, read_rao_csv, write_rao_csv

G = 9.81


def small_table() -> RAO:
    """Two headings (0, 90 deg) x two frequencies (0.5, 1.0 rad/s), distinct per DOF."""
    values = np.zeros((6, 2, 2), dtype=complex)
    for j in range(6):
        values[j] = (j + 1) * np.array([[1.0, 2.0j], [3.0, 4.0 + 4.0j]])
    return RAO([0.5, 1.0], [0.0, 90.0], values)


# --------------------------------------------------------------------------- RAO.at


def test_at_interpolates_linearly_in_omega_and_heading():
    rao = small_table()
    # mid-frequency, mid-heading: mean of the four corners, times (j + 1)
    got = rao.at([0.75], 45.0)[:, 0]
    corners = (1.0 + 2.0j + 3.0 + 4.0 + 4.0j) / 4.0
    assert got == pytest.approx(corners * np.arange(1, 7))
    # a quarter of the way in omega at heading 0: 1 + 0.25 (2i - 1)
    assert rao.at([0.625], 0.0)[2, 0] == pytest.approx(3 * (0.75 + 0.5j))


def test_at_wraps_around_360_degrees():
    rao = small_table()
    # 315 deg lies between 90 (weight 45/270) and 360 = 0 (weight 225/270)
    got = rao.at([0.5], 315.0)[0, 0]
    assert got == pytest.approx(1.0 * 225 / 270 + 3.0 * 45 / 270)
    # -45 deg is 315 deg; 405 deg is 45 deg
    assert rao.at([0.5], -45.0)[0, 0] == pytest.approx(got)
    assert rao.at([0.5], 405.0)[0, 0] == pytest.approx(2.0)


def test_at_clamps_below_and_is_zero_above_the_table():
    rao = small_table()
    got = rao.at([0.1, 0.5, 1.0, 1.0000001, 7.0], 0.0)
    assert got[1, 0] == pytest.approx(2.0)  # below: the value at 0.5 rad/s
    assert got[1, 1] == pytest.approx(2.0)
    assert got[1, 2] == pytest.approx(4.0j)  # at the largest omega: its value
    assert np.all(got[:, 3:] == 0.0)


def test_at_with_one_heading_and_one_frequency():
    values = np.zeros((6, 1, 1), dtype=complex)
    values[3, 0, 0] = 0.2 - 0.1j
    rao = RAO([1.0], [180.0], values)
    got = rao.at([0.3, 1.0, 1.5], 17.0)
    assert got[3].tolist() == [0.2 - 0.1j, 0.2 - 0.1j, 0.0]


@settings(max_examples=50, deadline=None)
@given(st.integers(0, 3), st.integers(0, 4), st.integers(-2, 2))
def test_at_reproduces_tabulated_points(ih, io, turns):
    rng = np.random.default_rng(ih * 10 + io)
    heading = np.array([0.0, 45.0, 170.0, 300.0])
    omega = np.array([0.2, 0.4, 0.7, 1.1, 2.0])
    values = rng.normal(size=(6, 4, 5)) + 1j * rng.normal(size=(6, 4, 5))
    rao = RAO(omega, heading, values)
    got = rao.at([omega[io]], heading[ih] + 360.0 * turns)[:, 0]
    np.testing.assert_allclose(got, values[:, ih, io], rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("omega, heading, shape, match", [
    ([1.0, 0.5], [0.0], (6, 1, 2), "increasing"),
    ([0.0, 0.5], [0.0], (6, 1, 2), "> 0"),
    ([0.5, 1.0], [0.0, 360.0], (6, 2, 2), r"\[0, 360\)"),
    ([0.5, 1.0], [90.0, 90.0], (6, 2, 2), "increasing"),
    ([0.5, 1.0], [0.0], (6, 2, 1), "shape"),
])
def test_rao_checks_its_arrays(omega, heading, shape, match):
    with pytest.raises(ValueError, match=match):
        RAO(omega, heading, np.zeros(shape, dtype=complex))


# --------------------------------------------------------------------------- CSV

HEADER = "omega_rad_s,heading_deg,dof,amplitude,phase_deg\n"


def grid_rows(omegas=(0.5,), headings=(0.0,), skip=()):
    lines = []
    for h in headings:
        for w in omegas:
            for d in ("surge", "sway", "heave", "roll", "pitch", "yaw"):
                if (w, h, d) not in skip:
                    lines.append(f"{w},{h},{d},1.0,0.0\n")
    return lines


def test_csv_converts_degrees_and_phases(tmp_path):
    path = tmp_path / "rao.csv"
    rows = grid_rows(omegas=(0.5,), headings=(90.0,))
    rows[2] = "0.5,90.0,heave,0.8,-90\n"  # heave lags a quarter period: -0.8 i
    rows[3] = "0.5,90.0,Roll,2.0,180\n"  # 2 deg/m in anti-phase
    path.write_text(HEADER + "".join(rows))
    rao = read_rao_csv(path)
    assert rao.omega.tolist() == [0.5] and rao.heading_deg.tolist() == [90.0]
    assert rao.values[2, 0, 0] == pytest.approx(-0.8j, abs=1e-15)
    assert rao.values[3, 0, 0] == pytest.approx(-math.radians(2.0), abs=1e-15)
    assert rao.values[0, 0, 0] == pytest.approx(1.0)  # translations stay in m/m
    assert rao.values[5, 0, 0] == pytest.approx(math.radians(1.0))


def test_csv_round_trip_in_any_row_order(tmp_path):
    rng = np.random.default_rng(3)
    values = rng.normal(size=(6, 3, 4)) + 1j * rng.normal(size=(6, 3, 4))
    values[1, 2, 3] = 0.0
    rao = RAO([0.3, 0.61, 1.2, 2.5], [0.0, 135.5, 270.0], values)
    path = tmp_path / "rao.csv"
    write_rao_csv(rao, path)
    lines = path.read_text().splitlines()
    assert lines[0] == HEADER.strip()
    assert len(lines) == 1 + 6 * 3 * 4
    back = read_rao_csv(path)
    np.testing.assert_array_equal(back.omega, rao.omega)
    np.testing.assert_array_equal(back.heading_deg, rao.heading_deg)
    np.testing.assert_allclose(back.values, rao.values, rtol=1e-13, atol=1e-15)
    # shuffled rows, a blank line and a comment read the same
    body = lines[1:]
    rng.shuffle(body)
    path.write_text(lines[0] + "\n# shuffled\n\n" + "\n".join(body) + "\n")
    np.testing.assert_allclose(read_rao_csv(path).values, rao.values, rtol=1e-13, atol=1e-15)


@pytest.mark.parametrize("text, message", [
    ("omega_rad_s,heading_deg,dof,amplitude\n0.5,0,heave,1\n",
     "row 1: the header lacks column 'phase_deg'"),
    (HEADER + "0.5,0,heave,1.0\n", "row 2: 4 fields, but the header has 5"),
    (HEADER + "".join(grid_rows()).replace("pitch", "pich"), r"row 6: unknown dof \(expected one of surge"),
    (HEADER + "".join(grid_rows()).replace("0.5,0.0,roll,1.0", "0.5,0.0,roll,abc"),
     "row 5, column amplitude: not a number"),
    (HEADER + "".join(grid_rows()).replace("0.5,0.0,yaw,1.0,0.0", "0.5,0.0,yaw,1.0,nan"),
     "row 7: phase_deg 'nan' is not a finite number"),
    (HEADER + "".join(grid_rows()).replace("0.5,0.0,sway,1.0", "0.5,0.0,sway,-0.1"),
     "row 3: negative amplitude -0.1"),
    (HEADER + "".join(grid_rows(omegas=(0.5, -1.0))), "omega_rad_s must be > 0; got -1"),
    (HEADER + "".join(grid_rows(headings=(0.0, 360.0))), r"row 8: heading_deg must be in \[0, 360\); got 360"),
    (HEADER + "".join(grid_rows()) + "0.5,0.0,heave,2.0,0.0\n",
     "row 8: duplicate of row 4 .omega 0.5 rad/s, heading 0 deg, dof heave"),
    (HEADER + "".join(grid_rows(omegas=(0.5, 1.0), skip={(1.0, 0.0, "roll")})),
     "row 8: omega 1 rad/s at heading 0 deg lacks dof roll"),
    (HEADER + "".join(grid_rows(omegas=(0.5,), headings=(0.0,)) + grid_rows(omegas=(1.0,), headings=(90.0,))),
     r"row 8: omega 1 rad/s has no rows at heading 0 deg \(the \(omega, heading\) pairs must form a full grid"),
    ("", "empty file"),
    (HEADER, "row 1: no data rows"),
])
def test_csv_errors_name_the_row(tmp_path, text, message):
    path = tmp_path / "bad.csv"
    path.write_text(text)
    with pytest.raises(ScenarioError, match=message) as info:
        read_rao_csv(path)
    assert info.value.source == str(path)
    assert "\n" not in str(info.value)


def test_csv_missing_file(tmp_path):
    with pytest.raises(ScenarioError, match="cannot read the file"):
        read_rao_csv(tmp_path / "nope.csv")


# --------------------------------------------------------------------------- Capytaine

try:
    import h5netcdf  # noqa: F401
    import h5py  # noqa: F401
    import xarray as xr
except ImportError:  # the `bem` extra
    xr = None
needs_bem = pytest.mark.skipif(xr is None, reason="needs the bem extra (xarray, h5netcdf, h5py)")

CAPY_DOFS = ["Surge", "Sway", "Heave", "Roll", "Pitch", "Yaw"]


def capytaine_coords(omega, wave_direction, dofs, freq_dim="omega"):
    """Coordinates as Capytaine's assemble_dataset writes them (omega main, others along it)."""
    omega = np.asarray(omega, dtype=float)
    k = omega**2 / G
    with np.errstate(divide="ignore"):  # omega = 0: infinite period and wavelength
        period, wavelength = 2 * np.pi / omega, 2 * np.pi / k
    coords = {
        freq_dim: (freq_dim, omega if freq_dim == "omega" else period),
        "wave_direction": ("wave_direction", np.asarray(wave_direction, dtype=float),
                           {"long_name": "Wave direction", "units": "rad"}),
        "radiating_dof": ("radiating_dof", list(dofs), {"long_name": "Radiating DOF"}),
        "influenced_dof": ("influenced_dof", list(dofs), {"long_name": "Influenced DOF"}),
        "wavenumber": (freq_dim, k),
        "wavelength": (freq_dim, wavelength),
        "g": G,
        "rho": 1025.0,
        "water_depth": np.inf,
        "forward_speed": 0.0,
    }
    if freq_dim == "omega":
        coords["period"] = ("omega", period)
    else:
        coords["omega"] = (freq_dim, omega)
    return coords


def separate_complex(ds):
    """What capytaine.io.xarray.separate_complex_values does: complex -> leading re/im dim."""
    out = ds.copy()
    for name in list(out.data_vars):
        if np.iscomplexobj(out[name].values):
            da = out[name]
            out[name] = xr.DataArray(np.stack([da.values.real, da.values.imag]),
                                     dims=("complex",) + da.dims)
            out.coords["complex"] = ["re", "im"]
    return out


def save(ds, path):
    separate_complex(ds).to_netcdf(path, engine="h5netcdf")
    return path


@needs_bem
def test_capytaine_rao_variable_is_conjugated_and_headings_in_degrees(tmp_path):
    omega = [0.4, 0.8]
    directions = [np.pi, -np.pi / 2, 0.0, np.pi / 2]  # -> 180, 270, 0, 90 deg
    X = np.zeros((2, 4, 6), dtype=complex)  # (omega, wave_direction, radiating_dof)
    X[:, :, 2] = [[0.8, 0.7, 1.0 + 0.1j, 0.9], [0.3, 0.2, 0.5 - 0.5j, 0.4]]
    X[1, 1, 3] = 0.02 + 0.03j  # roll at 0.8 rad/s, direction -pi/2
    ds = xr.Dataset(coords=capytaine_coords(omega, directions, CAPY_DOFS))
    ds["RAO"] = (("omega", "wave_direction", "radiating_dof"), X)
    rao = read_capytaine(save(ds, tmp_path / "rao.nc"))
    assert rao.omega.tolist() == [0.4, 0.8]
    assert rao.heading_deg.tolist() == [0.0, 90.0, 180.0, 270.0]
    assert rao.values[2, 0, 0] == pytest.approx(1.0 - 0.1j)  # exp(-iwt) -> exp(+iwt)
    assert rao.values[2, 0, 1] == pytest.approx(0.5 + 0.5j)
    assert rao.values[2, 2, 1] == pytest.approx(0.3)
    assert rao.values[3, 3, 1] == pytest.approx(0.02 - 0.03j)
    assert np.count_nonzero(rao.values[3]) == 1


@needs_bem
def test_a_classic_netcdf3_file_reads_as_the_hdf5_one(tmp_path):
    """Capytaine's export_dataset in an environment without netCDF4 or h5netcdf writes a
    classic NETCDF3 file (through SciPy): it reads exactly as the HDF5 one."""
    omega = [0.4, 0.8, 1.2]
    X = np.zeros((3, 2, 6), dtype=complex)
    X[:, 0, 2] = [0.9, 0.6 + 0.2j, 0.1j]
    X[:, 1, 3] = [0.01, 0.05 - 0.02j, 0.003]
    ds = xr.Dataset(coords=capytaine_coords(omega, [np.pi, np.pi / 2], CAPY_DOFS))
    ds["RAO"] = (("omega", "wave_direction", "radiating_dof"), X)
    hdf5 = read_capytaine(save(ds, tmp_path / "rao.nc"))
    separate_complex(ds).to_netcdf(tmp_path / "rao3.nc", engine="scipy")
    assert (tmp_path / "rao3.nc").read_bytes()[:3] == b"CDF"
    classic = read_capytaine(tmp_path / "rao3.nc")
    np.testing.assert_array_equal(classic.omega, hdf5.omega)
    np.testing.assert_array_equal(classic.heading_deg, hdf5.heading_deg)
    np.testing.assert_array_equal(classic.values, hdf5.values)


@needs_bem
def test_capytaine_rao_of_one_selected_direction(tmp_path):
    # capytaine.post_pro.rao(ds, wave_direction=...) keeps the direction as a scalar coordinate
    ds = xr.Dataset(coords=capytaine_coords([0.5, 1.0], [3 * np.pi / 2], ["Roll"]))
    ds = ds.squeeze("wave_direction")
    ds["RAO"] = (("omega", "radiating_dof"), [[0.1j], [0.05 + 0.0j]])
    rao = read_capytaine(save(ds, tmp_path / "one.nc"))
    assert rao.heading_deg.tolist() == [270.0]
    assert rao.values[3, 0].tolist() == [-0.1j, 0.05]


@needs_bem
def test_capytaine_period_as_main_dimension_is_sorted_by_omega(tmp_path):
    omega = np.array([1.2, 0.6, 0.3])  # increasing periods
    X = np.zeros((3, 1, 2), dtype=complex)
    X[:, 0, 0] = [0.1j, 0.2j, 0.3j]  # Heave
    X[:, 0, 1] = [0.01, 0.02, 0.03]  # Pitch
    ds = xr.Dataset(coords=capytaine_coords(omega, [np.pi], ["Heave", "Pitch"], freq_dim="period"))
    ds["RAO"] = (("period", "wave_direction", "radiating_dof"), X)
    rao = read_capytaine(save(ds, tmp_path / "rao.nc"))
    np.testing.assert_allclose(rao.omega, [0.3, 0.6, 1.2])
    np.testing.assert_allclose(rao.values[2, 0], [-0.3j, -0.2j, -0.1j])
    np.testing.assert_allclose(rao.values[4, 0], [0.03, 0.02, 0.01])
    assert np.all(rao.values[[0, 1, 3, 5]] == 0.0)  # DOFs the file lacks


def one_dof_heave_dataset(with_excitation=True):
    """Heave only at omega = 1 rad/s: M + A = 2000 kg, B = 1000 N s/m, K = 4000 N/m,
    F = 1000 + 500i N (FK 800 + 500i, diffraction 200)."""
    ds = xr.Dataset(coords=capytaine_coords([0.0, 1.0], [0.0], ["Heave"]))
    ds["added_mass"] = (("omega", "radiating_dof", "influenced_dof"), [[[700.0]], [[500.0]]])
    ds["radiation_damping"] = (("omega", "radiating_dof", "influenced_dof"), [[[0.0]], [[1000.0]]])
    fk = np.array([[[np.nan + 0j]], [[800.0 + 500.0j]]])
    diff = np.array([[[np.nan + 0j]], [[200.0 + 0.0j]]])
    ds["Froude_Krylov_force"] = (("omega", "wave_direction", "influenced_dof"), fk)
    ds["diffraction_force"] = (("omega", "wave_direction", "influenced_dof"), diff)
    if with_excitation:
        ds["excitation_force"] = ds["Froude_Krylov_force"] + ds["diffraction_force"]
    ds["inertia_matrix"] = (("influenced_dof", "radiating_dof"), [[1500.0]])
    ds["hydrostatic_stiffness"] = (("influenced_dof", "radiating_dof"), [[4000.0]])
    return ds


@needs_bem
@pytest.mark.parametrize("with_excitation", [True, False])
def test_capytaine_rao_from_forces_by_hand(tmp_path, with_excitation):
    # Capytaine: X = F / (-w^2 (M + A) - i w B + K) = (1000 + 500i) / (2000 - 1000i) = 0.3 + 0.4i;
    # ours is its conjugate. (The omega = 0 radiation-only row is dropped.)
    ds = one_dof_heave_dataset(with_excitation)
    rao = read_capytaine(save(ds, tmp_path / "forces.nc"))
    assert rao.omega.tolist() == [1.0]
    assert rao.values[2, 0, 0] == pytest.approx(0.3 - 0.4j, abs=1e-14)
    assert np.all(np.delete(rao.values, 2, axis=0) == 0.0)


@needs_bem
def test_capytaine_coupled_matrices_are_indexed_influenced_by_radiating(tmp_path):
    # Heave and Pitch with a non-symmetric stiffness: H[influenced, radiating] X = F.
    dofs = ["Heave", "Pitch"]
    ds = xr.Dataset(coords=capytaine_coords([0.5], [np.pi], dofs))
    ds["added_mass"] = (("omega", "influenced_dof", "radiating_dof"), [[[10.0, 0.0], [0.0, 20.0]]])
    ds["radiation_damping"] = (("omega", "influenced_dof", "radiating_dof"), [[[4.0, 0.0], [0.0, 0.0]]])
    ds["inertia_matrix"] = (("influenced_dof", "radiating_dof"), [[30.0, 0.0], [0.0, 60.0]])
    ds["hydrostatic_stiffness"] = (("influenced_dof", "radiating_dof"), [[30.0, 5.0], [0.0, 40.0]])
    ds["excitation_force"] = (("omega", "wave_direction", "influenced_dof"), [[[10.0 + 0.0j, 4.0j]]])
    rao = read_capytaine(save(ds, tmp_path / "coupled.nc"))
    # by hand at w = 0.5: H = [[-10 - 2i + 30, 5], [0, -20 + 40]] = [[20 - 2i, 5], [0, 20]]
    # pitch = 4i / 20 = 0.2i; heave = (10 - 5 * 0.2i) / (20 - 2i) = (10 - i) / (2 (10 - i)) = 0.5
    assert rao.heading_deg.tolist() == [180.0]
    assert rao.values[4, 0, 0] == pytest.approx(-0.2j, abs=1e-14)
    assert rao.values[2, 0, 0] == pytest.approx(0.5, abs=1e-14)


@needs_bem
def test_capytaine_complains_in_one_line(tmp_path, monkeypatch):
    ds = one_dof_heave_dataset()
    path = save(ds.drop_vars("inertia_matrix"), tmp_path / "no_mass.nc")
    with pytest.raises(ScenarioError, match="computing it needs inertia_matrix") as info:
        read_capytaine(path)
    assert info.value.source == str(path) and "\n" not in str(info.value)

    moving = ds.assign_coords(forward_speed=2.0)
    with pytest.raises(ScenarioError, match="forward_speed 2 m/s"):
        read_capytaine(save(moving, tmp_path / "moving.nc"))

    two_depths = xr.concat([ds, ds], dim="water_depth").assign_coords(water_depth=[10.0, 20.0])
    with pytest.raises(ScenarioError, match="2 values of 'water_depth'"):
        read_capytaine(save(two_depths, tmp_path / "depths.nc"))

    text = tmp_path / "text.nc"
    text.write_text("not netcdf")
    with pytest.raises(ScenarioError, match="cannot read as a NetCDF file"):
        read_capytaine(text)

    # a repeated wave direction (0 and 2 pi) or frequency: one line naming it, not an IndexError
    twice = xr.Dataset(coords=capytaine_coords([0.5, 1.0], [0.0, 2 * np.pi], ["Heave"]))
    twice["RAO"] = (("omega", "wave_direction", "radiating_dof"), np.ones((2, 2, 1), dtype=complex))
    with pytest.raises(ScenarioError, match="two wave directions give the same heading 0 deg"):
        read_capytaine(save(twice, tmp_path / "directions.nc"))
    twice = xr.Dataset(coords=capytaine_coords([0.5, 0.7, 0.7], [0.0], ["Heave"]))
    twice["RAO"] = (("omega", "wave_direction", "radiating_dof"), np.ones((3, 1, 1), dtype=complex))
    with pytest.raises(ScenarioError, match="omega 0.7 rad/s appears twice"):
        read_capytaine(save(twice, tmp_path / "omega.nc"))

    monkeypatch.setitem(sys.modules, "xarray", None)
    with pytest.raises(ScenarioError, match=r"pip install marinecdpr\[bem\]"):
        read_capytaine(path)


# --------------------------------------------------------------------------- box hull

HULL = dict(length_m=100.0, beam_m=20.0, draught_m=6.0, gm_m=2.0, roll_damping_ratio=0.05)
HEADINGS = np.array([0.0, 30.0, 90.0, 135.0, 180.0, 270.0])


def test_box_hull_long_waves_follow_the_surface():
    w = np.array([0.001, 0.003])
    rao = box_hull_rao(**HULL, omega=w, heading_deg=HEADINGS)
    k = w**2 / G
    beta = np.radians(HEADINGS)[:, None]
    np.testing.assert_allclose(rao.values[2], 1.0, atol=1e-3)  # heave -> 1 in any heading
    slope_x = 1j * k * np.cos(beta)  # pitch (bow down +) follows the slope along x
    np.testing.assert_allclose(rao.values[4], slope_x, rtol=1e-3, atol=1e-12)
    slope_y = -1j * k * np.sin(beta)  # roll (port up +) follows the slope along y
    np.testing.assert_allclose(rao.values[3], slope_y, rtol=1e-3, atol=1e-12)
    assert np.all(rao.values[[0, 1, 5]] == 0.0)  # surge, sway, yaw: not modelled


def test_box_hull_matches_jensen_magnitudes():
    """|heave| = eta |F| and |pitch| = eta |G| of Jensen et al. (2004) at zero speed, C_B = 1."""
    L, B, T = 100.0, 20.0, 6.0
    w = np.array([0.3, 0.55, 0.8, 1.2])
    rao = box_hull_rao(**HULL, omega=w, heading_deg=np.array([150.0]))
    k = w**2 / G
    ke = np.abs(k * np.cos(np.radians(150.0)))
    A = 2 * np.sin(w**2 * B / (2 * G)) * np.exp(-(w**2) * T / G)
    f = np.sqrt((1 - k * T) ** 2 + (A**2 / (k * B)) ** 2)
    eta = 1 / np.sqrt((1 - 2 * k * T) ** 2 + (A**2 / (k * B)) ** 2)
    F = np.exp(-k * T) * f * 2 / (ke * L) * np.sin(ke * L / 2)
    Gp = np.exp(-k * T) * f * 24 / ((ke * L) ** 2 * L) * (np.sin(ke * L / 2) - ke * L / 2 * np.cos(ke * L / 2))
    np.testing.assert_allclose(np.abs(rao.values[2, 0]), eta * np.abs(F), rtol=1e-12)
    np.testing.assert_allclose(np.abs(rao.values[4, 0]), eta * np.abs(Gp), rtol=1e-12)


def test_box_hull_roll_resonance_in_beam_seas():
    wn = math.sqrt(G * HULL["gm_m"]) / (ROLL_GYRADIUS_OVER_BEAM * HULL["beam_m"])
    zeta = HULL["roll_damping_ratio"]
    rao = box_hull_rao(**HULL, omega=np.array([wn]), heading_deg=np.array([90.0, 270.0]))
    k = wn**2 / G
    roll = rao.values[3, :, 0]
    # about slope / (2 zeta): the beam average of the slope takes off 1 %
    assert abs(roll[0]) == pytest.approx(k / (2 * zeta), rel=0.02)
    u = k * HULL["beam_m"] / 2
    exact = k / (2 * zeta) * 3 * (math.sin(u) - u * math.cos(u)) / u**3
    assert roll[0] == pytest.approx(-exact, rel=1e-12)  # 90 deg phase lag behind the slope
    assert roll[1] == pytest.approx(exact, rel=1e-12)  # waves from port: opposite sign


def test_box_hull_no_roll_in_head_or_following_seas_and_no_pitch_in_beam_seas():
    w = np.linspace(0.1, 2.0, 40)
    rao = box_hull_rao(**HULL, omega=w, heading_deg=np.array([0.0, 90.0, 180.0, 270.0]))
    assert np.all(rao.values[3, [0, 2]] == 0.0)
    assert np.all(rao.values[4, [1, 3]] == 0.0)
    assert np.all(np.abs(rao.values[3, 1]) > 0.0)


def test_box_hull_pitch_stiffness_from_gml():
    # the default GM_L is the box's BM_L = L^2 / (12 T); giving it changes nothing
    w = np.array([0.01, 0.4, 0.7])
    base = box_hull_rao(**HULL, omega=w, heading_deg=np.array([180.0]))
    same = box_hull_rao(**HULL, omega=w, heading_deg=np.array([180.0]), gml_m=100.0**2 / 72.0)
    np.testing.assert_allclose(same.values, base.values, rtol=1e-12, atol=1e-15)
    stiff = box_hull_rao(**HULL, omega=w, heading_deg=np.array([180.0]), gml_m=400.0)
    assert stiff.values[4, 0, 0] == pytest.approx(base.values[4, 0, 0], rel=1e-3)  # still the slope
    assert abs(stiff.values[4, 0, 2]) != pytest.approx(abs(base.values[4, 0, 2]), rel=1e-2)


def test_box_hull_checks_its_inputs():
    with pytest.raises(ValueError, match="gm_m"):
        box_hull_rao(**{**HULL, "gm_m": -1.0}, omega=[0.5], heading_deg=[0.0])
    with pytest.raises(ValueError, match="omega"):
        box_hull_rao(**HULL, omega=[0.0, 0.5], heading_deg=[0.0])
