"""RAOs from a NetCDF file of the BEM code Capytaine (:func:`read_capytaine`): a stored
``RAO`` variable, or the RAO solved from the file's coefficients as Capytaine's
``post_pro.rao`` does, turned to the package's conventions."""

from __future__ import annotations

from os import PathLike
from typing import Any, NamedTuple, NoReturn

import numpy as np

from marinecdpr.errors import ScenarioError
from marinecdpr.motion.rao.table import DOFS, RAO, Fail, out_of_range
from marinecdpr.textfiles import check_file

__all__ = ["read_capytaine", "MAX_NETCDF_BYTES", "NETCDF3_MAGIC"]

MAX_NETCDF_BYTES = 2**30
"""Largest Capytaine NetCDF file read, bytes (1 GiB; an RAO dataset is a few MB, and
the whole file is loaded into memory)."""

_FREQ_DIMS = ("omega", "freq", "period", "wavelength", "wavenumber")
_CAPYTAINE_DOFS = {name: i for i, name in enumerate(DOFS)}  # "Surge" etc., case-insensitive


def read_capytaine(path: str | PathLike) -> RAO:
    """Read RAOs from a NetCDF file exported by the BEM code Capytaine.

    The file is Capytaine's xarray Dataset saved with ``capytaine.export_dataset(path,
    ds)`` (checked with Capytaine 3.0; its older recipe
    ``separate_complex_values(ds).to_netcdf(path)`` fails there on the DOFs' categorical
    coordinates): complex variables are split along a leading ``complex`` dimension with
    coordinates ``"re"``, ``"im"`` (variables stored natively complex are also accepted).
    Both NETCDF4 (HDF5) files and classic NETCDF3 ones (what xarray writes where netCDF4
    and h5netcdf are not installed) are read. Two kinds of file are read:

    * with an ``RAO`` variable (e.g. ``ds["RAO"] = capytaine.post_pro.rao(ds)``),
      dimensions frequency, ``wave_direction`` and ``radiating_dof``;
    * without it: the RAO is computed as Capytaine's ``post_pro.rao`` does, for
      every frequency and wave direction, from ``excitation_force`` (or
      ``Froude_Krylov_force + diffraction_force``; dims frequency,
      ``wave_direction``, ``influenced_dof``), ``added_mass`` and
      ``radiation_damping`` (frequency, ``influenced_dof``, ``radiating_dof``),
      ``hydrostatic_stiffness`` and ``inertia_matrix`` (``influenced_dof``,
      ``radiating_dof``; these two must have been added to the dataset)::

          H = -omega^2 (M + A) - i omega B + K,      H X = F,

      with H indexed [influenced_dof, radiating_dof] (all DOFs of the file in
      the solve, generalised modes included).

    Conversions to the package's conventions (:mod:`marinecdpr.motion.rao`):

    * Capytaine's phasors use ``x(t) = Re(X exp(-i omega t))`` and its incoming
      wave has unit elevation, zero phase, at (0, 0, 0); ours use
      ``exp(+i omega t)``, so ``RAO = conj(X)``.
    * ``wave_direction`` (rad, 0 = waves travelling towards +x, counter-clockwise)
      becomes ``heading_deg`` in [0, 360) -- the same direction, in degrees.
    * DOFs named ``Surge, Sway, Heave, Roll, Pitch, Yaw`` (case-insensitive) fill
      the six rows (rotations in rad/m about Capytaine's rotation centre, which
      should be S's origin); DOFs the file lacks get a zero RAO, other DOFs
      (generalised modes) are dropped.
    * The frequency is the dimension named ``omega``, ``freq`` (Hz),
      ``period`` (s), ``wavelength`` or ``wavenumber`` (the latter two need the
      ``omega`` coordinate Capytaine adds); rows are sorted by omega and
      frequencies 0 and infinity (radiation-only cases) are dropped.
    * Other dimensions (``g``, ``rho``, ``water_depth``, ``body_name``, ...) must
      have a single value. Non-zero ``forward_speed`` is refused (the RAOs here
      are per wave frequency for a ship without way).

    Parameters
    ----------
    path : str or path-like
        The NetCDF file (read with xarray's h5netcdf engine).

    Returns
    -------
    RAO

    Raises
    ------
    ScenarioError
        If xarray or h5netcdf is missing (install the ``bem`` extra), the path
        is not a regular file of at most :data:`MAX_NETCDF_BYTES` bytes, the file
        cannot be read, its content does not have Capytaine's layout, or a
        frequency or RAO is beyond the limits of :func:`read_rao_csv`.
    """
    src = str(path)

    def fail(message: str) -> NoReturn:
        raise ScenarioError(message, source=src)

    xr = _import_xarray(fail)
    check_file(path, fail, "a Capytaine NetCDF file", MAX_NETCDF_BYTES)
    ds = _merge_complex_values(_load_dataset(xr, path, fail), fail)
    _check_forward_speed(ds, fail)
    response = _stored_rao(ds, fail) if "RAO" in ds.data_vars else _computed_rao(ds, fail)
    _check_response(response, fail)
    rows = _rigid_body_rows(response.dofs, fail)
    axes = _sorted_axes(response.omega, response.directions, fail)
    values = _six_dof_values(response.X, rows, axes)
    _check_capytaine_limits(axes, values, fail)
    return RAO(axes.omega, axes.headings, values)


# Steps of read_capytaine, in the order it takes them.


class _Response(NamedTuple):
    """A Capytaine RAO as in the file, at the frequencies in (0, inf).

    ``omega`` (n_w,) rad/s, ``dofs`` the n_dof radiating DOF names, ``X`` complex
    (n_w, n_dir, n_dof) in Capytaine's exp(-i omega t) convention, ``directions``
    (n_dir,) the wave directions, rad.
    """

    omega: np.ndarray
    dofs: list[str]
    X: np.ndarray
    directions: np.ndarray


class _Frequencies(NamedTuple):
    """A variable's frequency dimension ``dim``, ``omega`` (n_w,) rad/s and ``keep`` (n_w,): omega in (0, inf)."""

    dim: str
    omega: np.ndarray
    keep: np.ndarray


class _Terms(NamedTuple):
    """The terms of H X = F: A, B (n_w, n_dof, n_dof), M, K (n_dof, n_dof), F (n_w, n_dir, n_dof).

    Indexed [influenced_dof, radiating_dof]; xarray DataArrays until :func:`_arranged_terms`
    makes them arrays.
    """

    added_mass: Any
    damping: Any
    inertia: Any
    stiffness: Any
    force: Any


class _Axes(NamedTuple):
    """The RAO's axes, sorted: ``omega`` (n_omega,) rad/s, ``headings`` (n_heading,) deg, and the
    orders ``o_order``, ``h_order`` that sort the file's frequencies and directions."""

    omega: np.ndarray
    headings: np.ndarray
    o_order: np.ndarray
    h_order: np.ndarray


def _import_xarray(fail: Fail) -> Any:
    """The xarray module; refuses to go on without it, h5netcdf or h5py (the `bem` extra)."""
    try:
        import h5netcdf  # noqa: F401  (xarray's engine)
        import h5py  # noqa: F401  (h5netcdf's HDF5 backend, an extra since h5netcdf 1.7)
        import xarray as xr
    except ImportError:
        fail("reading a Capytaine file needs xarray, h5netcdf and h5py: install the `bem` extra "
             "(pip install marinecdpr[bem])")
    return xr


NETCDF3_MAGIC = b"CDF"
"""The first bytes of a classic (NETCDF3) file: what xarray writes through SciPy where
netCDF4 and h5netcdf are not installed (Capytaine's ``export_dataset`` then does)."""


def _load_dataset(xr: Any, path: str | PathLike, fail: Fail) -> Any:
    """The file's xarray Dataset, loaded into memory: NETCDF4 (HDF5) through h5netcdf, a
    classic NETCDF3 file through SciPy; refuses a file that is neither."""
    with open(path, "rb") as fh:
        classic = fh.read(3) == NETCDF3_MAGIC
    try:
        with xr.open_dataset(path, engine="scipy" if classic else "h5netcdf") as opened:
            ds = opened.load()
    except Exception as exc:  # h5py/h5netcdf/xarray raise many kinds for a bad file
        first_line = (str(exc).strip().splitlines() or [type(exc).__name__])[0]
        fail(f"cannot read as a NetCDF file: {first_line}")
    return ds


def _check_forward_speed(ds: Any, fail: Fail) -> None:
    """Refuse a non-zero ``forward_speed`` (m/s)."""
    if "forward_speed" in ds.variables:
        speed = np.asarray(ds["forward_speed"].values, dtype=float)
        if np.any(speed != 0.0):
            fail(f"forward_speed {np.max(np.abs(speed)):g} m/s: only zero forward speed is supported")


def _frequencies(ds: Any, da: Any, name: str, fail: Fail) -> _Frequencies:
    """The frequency dimension of variable ``da`` (called ``name``) and its angular frequencies."""
    fdim = _frequency_dim(da, name, fail)
    omega = _omega_values(ds, fdim, fail)
    return _Frequencies(fdim, omega, np.isfinite(omega) & (omega > 0.0))


def _stored_rao(ds: Any, fail: Fail) -> _Response:
    """The RAO of the file's ``RAO`` variable."""
    rao = _with_direction_dim(ds["RAO"])
    freq = _frequencies(ds, rao, "RAO", fail)
    dofs = _labels(rao, "radiating_dof", "RAO", fail)
    X = _arranged(rao, (freq.dim, "wave_direction", "radiating_dof"), "RAO", fail)[freq.keep]
    return _Response(omega=freq.omega[freq.keep], dofs=dofs, X=X, directions=_coordinate(rao, "wave_direction", fail))


def _computed_rao(ds: Any, fail: Fail) -> _Response:
    """The RAO solved from the file's coefficients and excitation force, as Capytaine's ``post_pro.rao``."""
    F_da = _excitation_force(ds, fail)
    freq = _frequencies(ds, F_da, "excitation_force", fail)
    dofs = _labels(ds["added_mass"], "radiating_dof", "added_mass", fail)
    terms = _select_dofs(ds, F_da, dofs, fail)
    X = _solve_rao(freq.omega[freq.keep], _arranged_terms(terms, freq, fail), fail)
    return _Response(omega=freq.omega[freq.keep], dofs=dofs, X=X,
                     directions=_coordinate(terms.force, "wave_direction", fail))


def _excitation_force(ds: Any, fail: Fail) -> Any:
    """The excitation force DataArray (FK + diffraction if need be); refuses a file lacking a needed variable."""
    missing = [v for v in ("added_mass", "radiation_damping", "hydrostatic_stiffness", "inertia_matrix")
               if v not in ds.data_vars]
    if "excitation_force" in ds.data_vars:
        F_da = ds["excitation_force"]
    elif "Froude_Krylov_force" in ds.data_vars and "diffraction_force" in ds.data_vars:
        F_da = ds["Froude_Krylov_force"] + ds["diffraction_force"]
    else:
        F_da = None
        missing.insert(0, "excitation_force (or Froude_Krylov_force and diffraction_force)")
    if missing:
        fail(f"no 'RAO' variable, and computing it needs {', '.join(missing)} in the file")
    return _with_direction_dim(F_da)


def _select_dofs(ds: Any, F_da: Any, dofs: list[str], fail: Fail) -> _Terms:
    """The terms as DataArrays over the radiating DOFs ``dofs``; refuses influenced DOFs that differ."""
    sel = {"influenced_dof": dofs, "radiating_dof": dofs}
    try:
        A = ds["added_mass"].sel(sel)
        B = ds["radiation_damping"].sel(sel)
        M = ds["inertia_matrix"].sel(sel)
        K = ds["hydrostatic_stiffness"].sel(sel)
        F_da = F_da.sel(influenced_dof=dofs)
    except (KeyError, ValueError) as exc:
        fail(f"the radiating and influenced DOFs do not match: {exc}")
    return _Terms(added_mass=A, damping=B, inertia=M, stiffness=K, force=F_da)


def _arranged_terms(terms: _Terms, freq: _Frequencies, fail: Fail) -> _Terms:
    """The terms as arrays in the shapes of :class:`_Terms`, at the kept frequencies."""
    mat = ("influenced_dof", "radiating_dof")
    fdim, keep = freq.dim, freq.keep
    return _Terms(
        added_mass=_arranged(terms.added_mass, (fdim,) + mat, "added_mass", fail)[keep],
        damping=_arranged(terms.damping, (fdim,) + mat, "radiation_damping", fail)[keep],
        inertia=_arranged(terms.inertia, mat, "inertia_matrix", fail),
        stiffness=_arranged(terms.stiffness, mat, "hydrostatic_stiffness", fail),
        force=_arranged(terms.force, (fdim, "wave_direction", "influenced_dof"), "excitation_force", fail)[keep],
    )


def _solve_rao(omega: np.ndarray, terms: _Terms, fail: Fail) -> np.ndarray:
    """X, complex (n_w, n_dir, n_dof), solving H X = F at each omega (n_w,) rad/s; refuses a bad H or F."""
    A, B, M, K, F = terms
    w = omega[:, None, None]
    H = -w**2 * (M + A) - 1j * w * B + K  # Capytaine's rao_transfer_function
    if not (np.all(np.isfinite(H)) and np.all(np.isfinite(F))):
        fail("the added mass, damping, matrices or excitation force are not finite "
             "at a frequency in (0, inf)")
    try:
        X = np.linalg.solve(H[:, None], F[..., None])[..., 0]
    except np.linalg.LinAlgError:
        fail("the matrix -omega^2 (M + A) - i omega B + K is singular at a frequency")
    return X


def _check_response(response: _Response, fail: Fail) -> None:
    """Refuse an RAO without a frequency in (0, inf) or with a value that is not finite."""
    if response.omega.size == 0:
        fail("no frequency in (0, inf)")
    if not np.all(np.isfinite(response.X)):
        bad = np.argwhere(~np.isfinite(response.X))[0]
        fail(f"RAO not finite at omega {response.omega[bad[0]]:g} rad/s")


def _rigid_body_rows(dofs: list[str], fail: Fail) -> list[tuple[int, int]]:
    """(index in ``dofs``, index in :data:`DOFS`) of each rigid-body DOF of the file; refuses none."""
    rows = [(j, _CAPYTAINE_DOFS.get(name.lower())) for j, name in enumerate(dofs)]
    rows = [(j, k) for j, k in rows if k is not None]
    if not rows:
        fail(f"no rigid-body DOF among {', '.join(dofs)} (expected Surge, Sway, Heave, Roll, Pitch, Yaw)")
    return rows


def _sorted_axes(omega: np.ndarray, directions: np.ndarray, fail: Fail) -> _Axes:
    """omega (rad/s) and the headings in [0, 360) deg of the directions (rad), sorted; refuses repeats."""
    headings = np.round(np.mod(np.degrees(directions), 360.0), 10)
    headings[headings >= 360.0] -= 360.0
    h_order = np.argsort(headings, kind="stable")
    o_order = np.argsort(omega, kind="stable")
    headings, omega = headings[h_order], omega[o_order]
    if np.any(np.diff(headings) == 0.0):
        fail(f"two wave directions give the same heading {headings[1:][np.diff(headings) == 0.0][0]:g} deg")
    if np.any(np.diff(omega) == 0.0):
        fail(f"omega {omega[1:][np.diff(omega) == 0.0][0]:g} rad/s appears twice")
    return _Axes(omega=omega, headings=headings, o_order=o_order, h_order=h_order)


def _six_dof_values(X: np.ndarray, rows: list[tuple[int, int]], axes: _Axes) -> np.ndarray:
    """The RAO values, complex (6, n_heading, n_omega), exp(+i omega t): conj(X) sorted, 0 for absent DOFs."""
    X = X[axes.o_order][:, axes.h_order]  # (n_omega, n_heading, n_dof)
    values = np.zeros((6, axes.headings.size, axes.omega.size), dtype=complex)
    for j, k in rows:
        values[k] = np.conj(X[:, :, j]).T  # exp(-i w t) -> exp(+i w t)
    return values


def _check_capytaine_limits(axes: _Axes, values: np.ndarray, fail: Fail) -> None:
    """Refuse a frequency or RAO beyond the limits of :func:`read_rao_csv`."""
    if (problem := out_of_range(axes.omega, axes.headings, values)) is not None:
        fail(problem + (" (potential flow lacks viscous roll damping)" if "roll RAO" in problem else ""))


def _label(x) -> str:
    return x.decode() if isinstance(x, bytes) else str(x)


def _merge_complex_values(ds, fail):
    """Undo Capytaine's ``separate_complex_values``: re/im along ``complex`` -> complex."""
    if "complex" not in ds.dims:
        return ds
    if "complex" in ds.coords:
        labels = [_label(x) for x in np.atleast_1d(ds["complex"].values)]
        if sorted(labels) != ["im", "re"]:
            fail(f"the 'complex' coordinate is {labels}; expected ['re', 'im']")
        i_re, i_im = labels.index("re"), labels.index("im")
    elif ds.sizes["complex"] == 2:
        i_re, i_im = 0, 1
    else:
        fail("the 'complex' dimension must have the two entries 're' and 'im'")
    ds = ds.copy()
    for name in list(ds.data_vars):
        da = ds[name]
        if "complex" in da.dims:
            ds[name] = da.isel(complex=i_re, drop=True) + 1j * da.isel(complex=i_im, drop=True)
    return ds.drop_vars("complex", errors="ignore")


def _with_direction_dim(da):
    """A scalar ``wave_direction`` coordinate (one direction selected) as a dimension of size 1."""
    if "wave_direction" not in da.dims and "wave_direction" in da.coords and da["wave_direction"].ndim == 0:
        return da.expand_dims("wave_direction")
    return da


def _frequency_dim(da, name: str, fail) -> str:
    found = [d for d in _FREQ_DIMS if d in da.dims]
    if len(found) != 1:
        fail(f"{name} must have exactly one frequency dimension among {', '.join(_FREQ_DIMS)}; "
             f"it has dimensions {', '.join(map(str, da.dims))}")
    return found[0]


def _omega_values(ds, fdim: str, fail) -> np.ndarray:
    """Angular frequencies (rad/s) along the frequency dimension ``fdim``."""
    if "omega" in ds.variables and ds["omega"].dims == (fdim,):
        return np.asarray(ds["omega"].values, dtype=float)
    if fdim == "freq":
        return 2.0 * np.pi * np.asarray(ds["freq"].values, dtype=float)
    if fdim == "period":
        with np.errstate(divide="ignore"):
            return 2.0 * np.pi / np.asarray(ds["period"].values, dtype=float)
    fail(f"the frequency dimension is {fdim!r} but the file has no 'omega' coordinate along it")


def _labels(da, dim: str, name: str, fail) -> list[str]:
    if dim not in da.dims:
        fail(f"{name} has no {dim!r} dimension (dimensions {', '.join(map(str, da.dims))})")
    return [_label(x) for x in _coordinate(da, dim, fail)]


def _coordinate(da, dim: str, fail) -> np.ndarray:
    if dim not in da.dims:
        fail(f"no {dim!r} dimension: the file lacks the diffraction (wave) results")
    if dim not in da.coords:
        fail(f"the {dim!r} dimension has no coordinate values")
    return np.asarray(da[dim].values)


def _arranged(da, dims: tuple[str, ...], name: str, fail) -> np.ndarray:
    """``da``'s values with dimensions ``dims``; other dimensions must have one entry."""
    for d in dims:
        if d not in da.dims:
            fail(f"{name} has no {d!r} dimension (dimensions {', '.join(map(str, da.dims))})")
    for d in da.dims:
        if d not in dims:
            if da.sizes[d] != 1:
                fail(f"{name} has {da.sizes[d]} values of {d!r}; export one case per file")
            da = da.isel({d: 0})
    return np.asarray(da.transpose(*dims).values)

