"""The model's compiled code by subject (issue 38, item 5): dense linear algebra
(``model.linalg``), the rigid body's dynamics (``model.rigid_body``) and the tension
solver (``model.tension_solver``), each function defined once, in the module of its
subject, where the former ``model.kernels`` held all three (and re-exported two of
geometry's)."""

import importlib
import importlib.util
import inspect

import pytest

SUBJECTS = {
    "marinecdpr.model.linalg": {"lu_det_solve", "cholesky", "cholesky_solve", "gram_full_rank", "RCOND"},
    "marinecdpr.model.rigid_body": {"wrench_parts_step", "wrench_step", "forward_step", "forward_solve_step",
                                    "spatial_inertia_step", "wrench_series", "FRAME_CODES",
                                    "RigidBody", "ShipAt"},
    "marinecdpr.model.tension_solver": {"tensions_step", "solve_tensions", "least_distance", "improved_closed_form",
                                        "tension_series", "TensionWork", "METHOD_CODES", "Limits"},
}


def test_the_catch_all_kernels_module_is_gone():
    assert importlib.util.find_spec("marinecdpr.model.kernels") is None


@pytest.mark.parametrize("name", sorted(SUBJECTS))
def test_each_module_defines_what_it_exports(name):
    module = importlib.import_module(name)
    assert SUBJECTS[name] <= set(module.__all__)
    for attr in module.__all__:
        obj = getattr(module, attr)
        fn = getattr(obj, "py_func", obj)  # a numba dispatcher's Python function
        if inspect.isfunction(fn) or inspect.isclass(fn):
            assert fn.__module__ == name, f"{name}.{attr} is {fn.__module__}'s: a re-export"


def test_no_name_is_exported_by_two_subjects():
    exported = [set(importlib.import_module(name).__all__) for name in SUBJECTS]
    assert all(not (a & b) for i, a in enumerate(exported) for b in exported[i + 1:])
