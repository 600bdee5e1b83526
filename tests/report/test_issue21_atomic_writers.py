"""Issue 21, item 15: the library's CSV writers (ship motion, RAO tables) replace their file
whole, as every other writer does (textfiles.atomic_path): a reader holding the old file, or
a write that fails half-way, never sees a half-written or truncated file."""

import os

import numpy as np
import pytest

from marinecdpr.motion import rao as rao_module
from marinecdpr.motion import recorded
from marinecdpr.motion.rao import box_hull_rao, read_rao_csv, write_rao_csv
from marinecdpr.motion.recorded import read_motion_csv, write_motion_csv


def _motion():
    t = np.arange(0.0, 20.0, 0.1)
    eta = np.zeros((t.size, 6))
    eta[:, 2] = 0.3 * np.sin(0.5 * t)
    eta[:, 3] = 0.02 * np.sin(0.7 * t)
    return t, eta


def _rao():
    return box_hull_rao(length_m=100.0, beam_m=20.0, draught_m=5.0, gm_m=2.0, roll_damping_ratio=0.05,
                        omega=np.linspace(0.2, 1.8, 9), heading_deg=np.array([90.0, 180.0]))


WRITERS = {
    "motion": (lambda path: write_motion_csv(path, *_motion()), recorded, "np", "savetxt"),
    "rao": (lambda path: write_rao_csv(_rao(), path), rao_module, "builtins", "open"),
}


@pytest.mark.parametrize("kind", sorted(WRITERS))
def test_a_writer_replaces_the_file_and_leaves_other_links_alone(kind, tmp_path):
    """Written to a new file and renamed: a hard link to the old file (a reader holding it)
    keeps the old bytes; a writer that opens the target itself truncates them."""
    write, *_ = WRITERS[kind]
    path, held = tmp_path / "table.csv", tmp_path / "held.csv"
    path.write_text("old contents\n")
    os.link(path, held)
    write(path)
    assert held.read_text() == "old contents\n"
    assert path.read_text() != "old contents\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["held.csv", "table.csv"]  # no temporary left


@pytest.mark.parametrize("kind", sorted(WRITERS))
def test_a_write_that_fails_half_way_leaves_the_previous_file(kind, tmp_path, monkeypatch):
    write, module, owner, name = WRITERS[kind]
    path = tmp_path / "table.csv"
    path.write_text("old contents\n")

    class Full(OSError):
        pass

    if kind == "motion":
        real = np.savetxt

        def savetxt(fname, *args, **kwargs):
            with open(fname, "w") as fh:
                fh.write("time_s,x_m\n0,")  # half a file, then the disk is full
            raise Full(28, "No space left on device")

        monkeypatch.setattr(recorded.np, "savetxt", savetxt)
    else:
        import builtins

        real_open = builtins.open

        class Half:
            def __init__(self, fh):
                self.fh = fh

            def __enter__(self):
                return self

            def __exit__(self, *exc):
                self.fh.close()

            def write(self, text):
                self.fh.write(text[:10])
                raise Full(28, "No space left on device")

        monkeypatch.setattr(builtins, "open", lambda f, mode="r", *a, **k: Half(real_open(f, mode, *a, **k))
                            if "w" in mode else real_open(f, mode, *a, **k))
    with pytest.raises(Full):
        write(path)
    monkeypatch.undo()
    assert path.read_text() == "old contents\n"
    assert [p.name for p in tmp_path.iterdir()] == ["table.csv"]


def test_the_written_tables_read_back(tmp_path):
    t, eta = _motion()
    write_motion_csv(tmp_path / "m.csv", t, eta)
    table = np.loadtxt(tmp_path / "m.csv", delimiter=",", skiprows=1)
    np.testing.assert_allclose(table[:, 0], t, rtol=0, atol=0)
    np.testing.assert_allclose(np.radians(table[:, 4]), eta[:, 3], rtol=1e-15)
    assert read_motion_csv(tmp_path / "m.csv").time_range_s == (0.0, t[-1])
    r = _rao()
    write_rao_csv(r, tmp_path / "r.csv", comments=("RAOs from a test", "made by: \x1b[31mme"))
    text = (tmp_path / "r.csv").read_text()
    assert text.startswith("# RAOs from a test\n# made by: [31mme\n")
    np.testing.assert_allclose(read_rao_csv(tmp_path / "r.csv").values, r.values, rtol=1e-12, atol=1e-15)
