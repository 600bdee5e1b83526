"""Hostile input files (issue 9, classes 3 and 7).

A recorded-motion or RAO file named by a scenario may be anything: binary, huge, a
folder, a pipe, /etc/passwd, numbers that overflow. Each is refused with one line
that names the file, the line and column and what was expected, and quotes nothing
from the file. What spreadsheets write (a byte-order mark, CRLF, rows of empty
cells) is read like the clean file. A scenario TOML nested 3000 levels deep, with NUL
bytes or not in UTF-8 is refused in one line too.
"""

from __future__ import annotations

import os
import re
import threading
from importlib import resources
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from marinecdpr.cli.app import app
from marinecdpr.errors import ScenarioError
from marinecdpr.motion.rao import RAO, read_capytaine, read_rao_csv, write_rao_csv
from marinecdpr.motion.recorded import MOTION_CSV_COLUMNS, read_motion_csv
from marinecdpr.scenario.loading import load_scenario, scenario_from_dict

from conftest import paper_dict

runner = CliRunner()
EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
SECRET = "s3cr3t"
PASSWD = ("root:x:0:0:root:/root:/bin/bash\ndaemon:x:1:1:daemon:/usr/sbin:/usr/sbin/nologin\n"
          f"alice:{SECRET}:1000:1000:Alice,,,:/home/alice:/bin/bash\n")
ENVIRON = f"HOME=/root\0PATH=/usr/bin\0API_TOKEN={SECRET}\0"
BASHRC = ("# ~/.bashrc: executed by bash(1) for non-login shells.\ncase $- in\n    *i*) ;;\n"
          f"      *) return;;\nesac\nexport API_TOKEN={SECRET}\n")
FILE_LEAKS = ("root", "bash", "daemon", "HOME", "PATH", "API_TOKEN", "esac", SECRET)


# ------------------------------------------------------------------------ clean files
def motion_lines() -> list[str]:
    """Header and 40 rows of a valid motion file (20 Hz, degrees)."""
    t = 0.05 * np.arange(40)
    s = np.sin(2 * np.pi * t / 8)
    eta = np.column_stack([0.1 * s, -0.2 * s, 0.5 * s, 3.0 * s, -2.0 * s, 40.0 + s])
    return [",".join(MOTION_CSV_COLUMNS)] + [",".join(f"{v:.10g}" for v in (ti, *e)) for ti, e in zip(t, eta)]


def rao_lines() -> list[str]:
    """Header and 24 rows of a valid RAO table: headings 0, 90 deg x omega 0.5, 1 rad/s x six DOFs."""
    rows = ["omega_rad_s,heading_deg,dof,amplitude,phase_deg"]
    for h in (0.0, 90.0):
        for w in (0.5, 1.0):
            for k, d in enumerate(("surge", "sway", "heave", "roll", "pitch", "yaw")):
                rows.append(f"{w},{h},{d},{0.5 + 0.1 * k},{10 * k - 20}")
    return rows


def text(lines: list[str], eol: str = "\n") -> bytes:
    return (eol.join(lines) + eol).encode()


def cell(lines: list[str], row: int, col: int, value: str) -> list[str]:
    """``lines`` with field ``col`` (from 0) of line index ``row`` (0 = header) replaced."""
    lines = list(lines)
    fields = lines[row].split(",")
    fields[col] = value
    lines[row] = ",".join(fields)
    return lines


def not_utf8(lines: list[str], row: int) -> bytes:
    """Latin-1 bytes (as a Windows editor writes 'ete' with accents) at the start of a line."""
    raw = [ln.encode() for ln in lines]
    raw[row] = b"\xe9t\xe9" + raw[row]
    return b"\n".join(raw) + b"\n"


def nul(lines: list[str], row: int) -> bytes:
    lines = list(lines)
    lines[row] = lines[row][:2] + "\0" + lines[row][2:]
    return text(lines)


def motion_times_scaled(factor: float) -> bytes:
    lines = motion_lines()
    for i in range(1, len(lines)):
        lines = cell(lines, i, 0, f"{factor * 0.05 * (i - 1):.10g}")
    return text(lines)


# --------------------------------------------------------------- cases: bad content
# name: (make the file's bytes, the message must match, extra strings it must not contain)
MOTION_BAD = {
    "NUL byte": (lambda: nul(motion_lines(), 3), r"line 4, column 3: a NUL byte", ()),
    "200 000-character field": (lambda: text(cell(motion_lines(), 2, 1, "1" * 200_000)),
                                r"line 3: longer than 10000 characters", ()),
    "150-character field": (lambda: text(cell(motion_lines(), 4, 1, SECRET * 25)),
                            r"line 5, field 2: over 100 characters", ()),
    "not UTF-8": (lambda: not_utf8(motion_lines(), 5), r"line 6, column 1: not UTF-8 text", ()),
    "UTF-16": (lambda: "\n".join(motion_lines()).encode("utf-16"), r"UTF-16 text; expected .* UTF-8", ()),
    "ANSI escape": (lambda: text(cell(motion_lines(), 3, 4, "\x1b[2J")), r"line 4, column \d+: a control character",
                    ("\x1b", "[2J")),
    "heave 1e300": (lambda: text(cell(motion_lines(), 3, 3, "1e300")),
                    r"line 4, column heave_m: 1e\+300 m is beyond 1000 m", ()),
    "yaw 1e300": (lambda: text(cell(motion_lines(), 3, 6, "1e300")),
                  r"line 4, column yaw: 1e\+300 deg is beyond 36000 deg", ()),
    "overflow to inf": (lambda: text(cell(motion_lines(), 3, 2, "1e999")),
                        r"line 4, column sway_m: 'inf' is not a finite number", ("1e999",)),
    "-NaN": (lambda: text(cell(motion_lines(), 5, 6, "-NaN")),
             r"line 6, column yaw: 'nan' is not a finite number", ("NaN",)),
    "time in hours": (lambda: motion_times_scaled(1e-5), r"line 3, column time_s: sampling interval 5e-07 s is below",
                      ()),
    "text in a cell": (lambda: text(cell(motion_lines(), 3, 3, SECRET)), r"line 4, column heave_m: not a number$",
                       ()),
    "quoted line break": (lambda: text(cell(motion_lines(), 3, 3, f'"{SECRET}\n1"')),
                          r"line 5: a quoted field spans lines", ()),
    "foreign column": (lambda: text(cell(motion_lines(), 0, 6, SECRET)),
                       r"line 1: wrong columns \(missing 'yaw'; unexpected column 7\)", ()),
    "/etc/passwd": (lambda: PASSWD.encode(),
                    r"line 1: expected a header row with the columns time_s,surge_m,.* \(got 1 other column\)$", ()),
    "/proc/self/environ": (lambda: ENVIRON.encode(), r"line 1, column 11: a NUL byte", ()),
    "~/.bashrc": (lambda: BASHRC.encode(), r"line 1: expected a header row with the columns", ()),
}

RAO_BAD = {
    "NUL byte": (lambda: nul(rao_lines(), 3), r"row 4, column 3: a NUL byte", ()),
    "200 000-character field": (lambda: text(cell(rao_lines(), 2, 3, "1" * 200_000)),
                                r"row 3: longer than 10000 characters", ()),
    "150-character field": (lambda: text(cell(rao_lines(), 4, 3, SECRET * 25)),
                            r"row 5, field 4: over 100 characters", ()),
    "not UTF-8": (lambda: not_utf8(rao_lines(), 5), r"row 6, column 1: not UTF-8 text", ()),
    "UTF-16": (lambda: "\n".join(rao_lines()).encode("utf-16"), r"UTF-16 text; expected .* UTF-8", ()),
    "heave amplitude 1e300": (lambda: text(cell(rao_lines(), 3, 3, "1e300")),
                              r"row 4: heave amplitude 1e\+300 m/m is above 100 m/m", ()),
    "roll amplitude 1e300": (lambda: text(cell(rao_lines(), 4, 3, "1e300")),
                             r"row 5: roll amplitude 1e\+300 deg/m is above 1000 deg/m", ()),
    "omega 1e300": (lambda: text(cell(rao_lines(), 1, 0, "1e300")), r"row 2: omega_rad_s 1e\+300 is above 100 rad/s",
                    ()),
    "phase 1e300": (lambda: text(cell(rao_lines(), 2, 4, "1e300")), r"row 3: phase_deg 1e\+300 is beyond", ()),
    "overflow to inf": (lambda: text(cell(rao_lines(), 3, 3, "1e999")),
                        r"row 4: amplitude 'inf' is not a finite number", ("1e999",)),
    "-NaN": (lambda: text(cell(rao_lines(), 5, 4, "-NaN")), r"row 6: phase_deg 'nan' is not a finite number",
             ("NaN",)),
    "text in a cell": (lambda: text(cell(rao_lines(), 3, 3, SECRET)), r"row 4, column amplitude: not a number$", ()),
    "unknown dof": (lambda: text(cell(rao_lines(), 3, 2, SECRET)), r"row 4: unknown dof \(expected one of surge", ()),
    "/etc/passwd": (lambda: PASSWD.encode(), r"row 1: the header lacks column 'omega_rad_s'", ()),
    "/proc/self/environ": (lambda: ENVIRON.encode(), r"row 1, column 11: a NUL byte", ()),
    "~/.bashrc": (lambda: BASHRC.encode(), r"row 2: the header lacks column 'omega_rad_s'", ()),
}

READERS = {"motion": (read_motion_csv, MOTION_BAD), "rao": (read_rao_csv, RAO_BAD)}
BAD_CONTENT = [(kind, name) for kind, (_, cases) in READERS.items() for name in cases]


def refusal(read, path: Path) -> BaseException | None:
    """What ``read(path)`` raises, or None; a read that blocks (a named pipe) fails the test."""
    box: dict[str, BaseException] = {}

    def run() -> None:
        try:
            read(path)
        except BaseException as exc:  # noqa: BLE001 - handed to the test
            box["exc"] = exc

    worker = threading.Thread(target=run, daemon=True)
    worker.start()
    worker.join(10.0)
    if worker.is_alive():
        os.close(os.open(path, os.O_WRONLY | os.O_NONBLOCK))  # release the blocked open
        worker.join(10.0)
        pytest.fail(f"reading {path.name} blocked")
    return box.get("exc")


def assert_refused(exc: BaseException | None, path: Path, pattern: str, leaks=()) -> str:
    """One ScenarioError line naming the file, matching ``pattern``, quoting nothing from the file."""
    assert isinstance(exc, ScenarioError), repr(exc)
    message = str(exc)
    assert exc.source == str(path) and message.startswith(f"{path}: ")
    assert "\n" not in message and "\r" not in message
    assert re.search(pattern, message), message
    detail = message.removeprefix(f"{path}: ")
    for leak in (*FILE_LEAKS, *leaks):
        assert leak not in detail, f"{leak!r} echoed in {message!r}"
    return message


@pytest.mark.parametrize("kind, name", BAD_CONTENT, ids=[f"{k}: {n}" for k, n in BAD_CONTENT])
def test_bad_content_is_refused_in_one_line_without_echo(tmp_path, kind, name):
    read, cases = READERS[kind]
    make, pattern, leaks = cases[name]
    path = tmp_path / f"{kind}.csv"
    path.write_bytes(make())
    assert_refused(refusal(read, path), path, pattern, leaks)


# --------------------------------------------------------------- cases: bad paths
def folder(tmp_path: Path) -> Path:
    (tmp_path / "folder.csv").mkdir()
    return tmp_path / "folder.csv"


def fifo(tmp_path: Path) -> Path:
    os.mkfifo(tmp_path / "pipe.csv")
    return tmp_path / "pipe.csv"


def huge(tmp_path: Path) -> Path:
    """A 300 MiB file (sparse: costs no disk), larger than any real table."""
    path = tmp_path / "huge.csv"
    with open(path, "wb") as f:
        f.write(text(motion_lines()))
        f.truncate(300 * 2**20)
    return path


BAD_PATHS = {
    "a folder": (folder, r": a folder, not a file; expected a"),
    "a named pipe": (fifo, r": not a regular file \(a device, pipe or socket\)"),
    "300 MiB": (huge, r": 300 MiB is larger than .* \(256 MiB at most\)"),
}


@pytest.mark.parametrize("kind", sorted(READERS))
@pytest.mark.parametrize("name", sorted(BAD_PATHS))
def test_paths_that_are_no_table_are_refused_before_reading(tmp_path, kind, name):
    if name == "a named pipe" and not hasattr(os, "mkfifo"):
        pytest.skip("no named pipes")
    make, pattern = BAD_PATHS[name]
    path = make(tmp_path)
    assert_refused(refusal(READERS[kind][0], path), path, pattern)


def capytaine_file(path: Path, heave: float) -> Path:
    """A Capytaine-style NetCDF file with an RAO variable: heave ``heave`` m/m, nothing else."""
    xr = pytest.importorskip("xarray")
    pytest.importorskip("h5netcdf")
    re_im = np.zeros((2, 2, 1, 6))  # (complex, omega, wave_direction, radiating_dof)
    re_im[0, :, 0, 2] = heave
    ds = xr.Dataset(coords={"complex": ["re", "im"], "omega": [0.5, 1.0], "wave_direction": [np.pi],
                            "radiating_dof": ["Surge", "Sway", "Heave", "Roll", "Pitch", "Yaw"]})
    ds["RAO"] = (("complex", "omega", "wave_direction", "radiating_dof"), re_im)
    ds.to_netcdf(path, engine="h5netcdf")
    return path


CAPYTAINE_BAD = {
    "heave 1e300": (lambda p: capytaine_file(p / "rao.nc", 1e300),
                    r": heave RAO 1e\+300 m/m at omega 0\.5 rad/s, heading 180 deg is above 100 m/m"),
    "a folder": (folder, r": a folder, not a file; expected a Capytaine NetCDF file"),
    "/etc/passwd": (lambda p: (p / "passwd.nc", (p / "passwd.nc").write_text(PASSWD))[0],
                    r": cannot read as a NetCDF file"),
}


@pytest.mark.parametrize("name", sorted(CAPYTAINE_BAD))
def test_capytaine_refuses_what_is_no_ship_response(tmp_path, name):
    assert read_capytaine(capytaine_file(tmp_path / "ok.nc", 1.0)).values[2, 0, 0] == 1.0
    make, pattern = CAPYTAINE_BAD[name]
    path = make(tmp_path)
    with pytest.raises(ScenarioError) as info:
        read_capytaine(path)
    assert_refused(info.value, path, pattern)


def test_write_rao_csv_writes_only_what_read_rao_csv_reads(tmp_path):
    values = np.zeros((6, 1, 2), dtype=complex)
    values[2] = 1.0
    write_rao_csv(RAO([0.5, 1.0], [180.0], values), tmp_path / "ok.csv")
    values[3, 0, 1] = 1e300
    with pytest.raises(ValueError, match=r"roll RAO 1e\+300 rad/m .* read_rao_csv would refuse the file"):
        write_rao_csv(RAO([0.5, 1.0], [180.0], values), tmp_path / "absurd.csv")
    assert not (tmp_path / "absurd.csv").exists()


# ------------------------------------------------------- what spreadsheets write
SPREADSHEET = {
    "BOM + CRLF": lambda lines: b"\xef\xbb\xbf" + text(lines, "\r\n"),
    "CR line ends": lambda lines: text(lines, "\r"),
    "BOM + CRLF + empty rows": lambda lines: b"\xef\xbb\xbf" + text(lines + [",,,,,,"] * 3, "\r\n"),
}


@pytest.mark.parametrize("name", sorted(SPREADSHEET))
def test_what_spreadsheets_write_reads_like_the_clean_file(tmp_path, name):
    (tmp_path / "clean_motion.csv").write_bytes(text(motion_lines()))
    (tmp_path / "sheet_motion.csv").write_bytes(SPREADSHEET[name](motion_lines()))
    (tmp_path / "clean_rao.csv").write_bytes(text(rao_lines()))
    (tmp_path / "sheet_rao.csv").write_bytes(SPREADSHEET[name](rao_lines()))
    clean, sheet = read_motion_csv(tmp_path / "clean_motion.csv"), read_motion_csv(tmp_path / "sheet_motion.csv")
    np.testing.assert_array_equal(sheet.t, clean.t)
    np.testing.assert_array_equal(sheet.eta, clean.eta)
    clean, sheet = read_rao_csv(tmp_path / "clean_rao.csv"), read_rao_csv(tmp_path / "sheet_rao.csv")
    np.testing.assert_array_equal(sheet.omega, clean.omega)
    np.testing.assert_array_equal(sheet.heading_deg, clean.heading_deg)
    np.testing.assert_array_equal(sheet.values, clean.values)


# -------------------------------------------------------------------- scenario TOML
def deep_arrays() -> bytes:
    return ("x = " + "[" * 3000 + "]" * 3000 + "\n").encode() + (EXAMPLES / "paper.toml").read_bytes()


def deep_tables() -> bytes:
    return ("x = " + "{a = " * 3000 + "1" + "}" * 3000 + "\n").encode() + (EXAMPLES / "paper.toml").read_bytes()


SCENARIO_BAD = {
    "3000-deep arrays": (deep_arrays, r": not valid TOML: .*too deeply nested"),
    "3000-deep inline tables": (deep_tables, r": not valid TOML: .*too deeply nested"),
    "NUL byte": (lambda: b'name = "x"\ndescription = "a\0b"\n', r": line 2, column 17: a NUL byte"),
    "not UTF-8": (lambda: b'name = "x"\n\ndescription = "Mar\xeda"\n', r": line 3, column 19: not UTF-8 text"),
}


@pytest.mark.parametrize("name", sorted(SCENARIO_BAD))
def test_bad_scenario_files_are_one_line(tmp_path, name):
    make, pattern = SCENARIO_BAD[name]
    path = tmp_path / "bad.toml"
    path.write_bytes(make())
    with pytest.raises(ScenarioError) as info:
        load_scenario(path)
    assert_refused(info.value, path, pattern)


def test_a_3000_deep_scenario_dict_is_one_line():
    data = paper_dict()
    node: object = 1.0
    for _ in range(3000):
        node = {"a": [node]}
    data["trajectory"]["radius_m"] = node
    with pytest.raises(ScenarioError, match=r"^test: trajectory: too deeply nested") as info:
        scenario_from_dict(data, source="test")
    assert "\n" not in str(info.value)


def test_a_scenario_with_a_bom_and_crlf_reads(tmp_path):
    path = tmp_path / "paper.toml"
    path.write_bytes(b"\xef\xbb\xbf" + (EXAMPLES / "paper.toml").read_bytes().replace(b"\n", b"\r\n"))
    assert load_scenario(path).model_dump() == load_scenario(EXAMPLES / "paper.toml").model_dump()


# ---------------------------------------------------------------- through the CLI
def recorded_scenario(tmp_path: Path, file: str) -> Path:
    text_ = (EXAMPLES / "paper.toml").read_text()
    start, end = text_.index("[base_motion]"), text_.index("[trajectory]")
    path = tmp_path / "recorded.toml"
    path.write_text(text_[:start] + f'[base_motion]\ntype = "recorded"\nfile = "{file}"\n\n' + text_[end:])
    return path


def rao_scenario(tmp_path: Path, file: str) -> Path:
    text_ = (resources.files("marinecdpr.scenario") / "builtin" / "paper_sea.toml").read_text()
    start, end = text_.index("[base_motion.rao]"), text_.index("[trajectory]")
    path = tmp_path / "sea.toml"
    path.write_text(text_[:start] + f'[base_motion.rao]\nsource = "csv"\nfile = "{file}"\n\n' + text_[end:])
    return path


CLI_CASES = [("motion", n) for n in ("/etc/passwd", "NUL byte", "200 000-character field", "not UTF-8",
                                      "heave 1e300", "/proc/self/environ", "~/.bashrc")] + \
            [("rao", n) for n in ("NUL byte", "heave amplitude 1e300", "overflow to inf", "text in a cell")] + \
            [("toml", n) for n in ("3000-deep arrays", "NUL byte")]


@pytest.mark.parametrize("kind, name", CLI_CASES, ids=[f"{k}: {n}" for k, n in CLI_CASES])
def test_check_refuses_a_bad_file_in_one_line(tmp_path, kind, name):
    if kind == "toml":
        make, pattern = SCENARIO_BAD[name]
        bad = scenario = tmp_path / "bad.toml"
        leaks = ()
    else:
        make, pattern, leaks = READERS[kind][1][name]
        bad = (tmp_path / "ship.csv").resolve()
        scenario = (recorded_scenario if kind == "motion" else rao_scenario)(tmp_path, bad.name)
    bad.write_bytes(make())
    res = runner.invoke(app, ["check", str(scenario)])
    assert res.exit_code == 2, (res.exit_code, res.output, res.exception)
    err = res.stderr
    assert err.count("\n") == 1 and err.startswith(f"error: {bad}: "), err
    assert "Traceback" not in err, err
    assert re.search(pattern, err), err
    detail = err.removeprefix(f"error: {bad}: ")
    for leak in (*FILE_LEAKS, *leaks):
        assert leak not in detail, f"{leak!r} echoed in {err!r}"
