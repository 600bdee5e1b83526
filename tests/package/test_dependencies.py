"""The dependencies' edges (issue 21, item 15): pyproject.toml's ranges hold the installed,
tested versions, bound above the packages whose private APIs the code uses, and those
private APIs exist (an upgrade that drops one fails here, not on a user's machine)."""

import ctypes
import glob
import os
import tomllib
from importlib.metadata import version
from pathlib import Path

import numpy as np
import pytest
from packaging.requirements import Requirement

ROOT = Path(__file__).resolve().parents[2]
PROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
REQUIRES = {r.name: r for r in map(Requirement, PROJECT["dependencies"])}


@pytest.mark.parametrize("name", sorted(REQUIRES))
def test_the_installed_version_is_in_the_declared_range(name):
    assert REQUIRES[name].specifier.contains(version(name), prereleases=True), (name, version(name))


@pytest.mark.parametrize("name", ["numba", "llvmlite", "mujoco"])
def test_packages_whose_private_apis_are_used_are_bounded_above(name):
    spec = REQUIRES[name].specifier
    assert any(s.operator in ("<", "<=", "~=", "==") for s in spec), f"{name}{spec} has no upper bound"


def test_numpy_floor_is_numpy_2():
    # np.trapezoid (tests), NumPy 2's scalar reprs and copy semantics
    spec = REQUIRES["numpy"].specifier
    assert not spec.contains("1.26.4") and spec.contains("2.0.0")
    assert hasattr(np, "trapezoid")


def test_every_imported_third_party_package_is_declared():
    # llvmlite is imported directly (studies.latency, prototype.plants), not only through numba
    assert {"numpy", "scipy", "numba", "llvmlite", "mujoco", "pydantic", "matplotlib", "typer", "rich",
            "jinja2"} <= set(REQUIRES)


def test_numba_cache_index_api():
    """prototype.simulation.kernels_cached reads a dispatcher's cache index."""
    from marinecdpr.prototype.plants import own_loop

    index = own_loop._cache._cache_file._load_index()
    assert isinstance(index, dict)


def test_numba_array_meminfo_and_intrinsics():
    """marinecdpr.borrowed nulls an array's meminfo and parent in numba's array struct, through
    numba.core.cgutils and numba.extending.intrinsic; studies.latency reads the cycle counter."""
    from numba import njit
    from numba.core import cgutils

    from marinecdpr.borrowed import borrowed

    assert callable(cgutils.get_null_value) and callable(cgutils.get_or_insert_function)

    @njit
    def total(a, pair):
        b, (c, k) = borrowed(a), borrowed(pair)
        return b.sum() + c.sum() * k

    a = np.arange(5.0)
    assert total(a, (np.ones(3), 2.0)) == 10.0 + 6.0


def test_numba_c_wrappers_of_compiled_functions():
    """prototype.parts.step_pointer takes the address of numba's C wrapper of a compiled
    function (as numba's first-class functions do): Dispatcher.get_compile_result, the
    function descriptor's wrapper name and the library's pointer to it; called through
    borrowed.call_step it returns what the function does."""
    from numba import njit, types

    from marinecdpr.borrowed import call_step

    @njit
    def step(k, h, part_at, bus_at, a, b):
        return k * 1000 + int(h * 10) + part_at - bus_at

    ref = types.TypeRef(types.float64)
    cres = step.get_compile_result(types.int64(types.int64, types.float64, types.intp, types.intp, ref, ref))
    address = cres.library.get_pointer_to_function(cres.fndesc.llvm_cfunc_wrapper_name)
    assert isinstance(address, int) and address > 0

    @njit
    def call(address):
        return call_step(address, 7, 0.5, 30, 4)

    assert call(address) == 7000 + 5 + 26


def test_mujoco_private_addresses_and_library():
    """prototype.plants calls MuJoCo's C mj_step from compiled code: the library beside the
    Python package, and the models' and data's addresses."""
    import mujoco

    from marinecdpr.prototype.plants import mujoco_library

    libs = glob.glob(os.path.join(os.path.dirname(mujoco.__file__), "libmujoco.so*"))
    assert libs, "libmujoco.so not beside the mujoco package"
    assert hasattr(ctypes.CDLL(libs[0]), "mj_step")
    model = mujoco.MjModel.from_xml_string("<mujoco><worldbody><body><freejoint/><geom size='0.1'/></body>"
                                           "</worldbody></mujoco>")
    data = mujoco.MjData(model)
    assert isinstance(model._address, int) and isinstance(data._address, int)
    assert model._address != 0 and data._address != 0
    assert mujoco_library() is True
