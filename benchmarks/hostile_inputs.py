"""A hostile-input sweep over every command: bad values of every option and bad files, each
run as a subprocess with a short horizon, each outcome classified clean or unclean.

Clean is one of:

* ``ok``: exit 0, no traceback, every JSON it wrote (and ``latency --json``'s line) strict
  JSON (no NaN or Infinity) and no ``inf``/``nan`` in its CSVs;
* ``refused``: exit 2, 3, 4, 5 or 130, no traceback, exactly one ``error:`` line on stderr
  and it is the last (warnings and progress lines before it are allowed), and no staging
  folder or half-written file left in the output folder;
* ``usage``: exit 2 from the option parser itself in click's "Usage: ... Error" box, no
  traceback. Since the parser's errors are one ``error:`` line too (an integer option given
  "abc", a count below its minimum: ``cli.app._OneLineUsage``), they count as ``refused``,
  and this class stays empty.

Anything else is unclean: ``traceback``, ``exit N`` (another exit code), ``stderr`` (not
one error line), ``json`` (non-strict or non-finite output), ``staging`` (leftovers, or a
design journal left by a refused run), ``outside`` (a file written outside the output
folder: a study named ``../../../escaped``), ``refused valid`` (a case marked valid
refused: ``--resume`` from a copy of the run's folder), ``accepted invalid`` (a case marked
invalid run: ``--resume`` after the template's RAO file changed), ``message`` (refused with
the wrong reason: 10 000 obstacles as "expected 3 numbers"), or ``timeout`` (over
``--timeout`` s, times the command's and the case's factor; a first run's compile is
warmed up first, see ``--no-warm``).

Since issue 37 the sweep covers ``design`` (a small study of its own: bad scatter
diagrams, options beyond the study file's caps, names that are no file stem, corrupt or
stale journals with ``--resume``), ``clean --surface`` (``--move-time``, bands too large or
impossible) and ``[[obstacles]]`` (1 000, 1 001 and 10 000 boxes through ``check``): run
``--only design,"clean --surface",obstacles`` for those alone.

Run: ``PYTHONPATH=src .venv/bin/python benchmarks/hostile_inputs.py [--jobs 2] [--only rao,latency]
[--timeout 20] [--list]``. It prints the counts per class and lists the unclean cases.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

FLOATS = ["inf", "-inf", "nan", "-1", "0", "1e308", "-1e308", "1e-320", "abc", ""]
INTS = ["0", "-1", "9223372036854775807", "1" * 31, "abc", "1.5"]
LISTS = ["inf", "nan", "", ",", "a,b", "1e308", "1,1,1", "-1"]
NAMES = ["", "nonexistent_builtin", "[bold]x[/]", "\x1b[31mred"]


@dataclass
class Case:
    command: str
    what: str
    argv: list[str]
    files: dict[str, bytes] = field(default_factory=dict)  # name -> content, made in the case's folder
    out: str = "out"  # the output folder, in the case's folder
    expect: str = ""  # "ok": a refusal is unclean (valid input); "refused": exit 0 is unclean (invalid input)
    message: str = ""  # a pattern a refusal's error line must hold (the right reason)
    before: object = None  # callable(folder, argv): runs first (an earlier run, a file changed after it)
    slow: float = 1.0  # times --timeout this case may take


@dataclass
class Outcome:
    case: Case
    kind: str  # ok, refused, usage, or an unclean class
    detail: str = ""
    seconds: float = 0.0

    @property
    def clean(self) -> bool:
        return self.kind in ("ok", "refused", "usage")


# ------------------------------------------------------------------ files
SCATTER_OK = b"hs_m,tp_s,probability\n1.0,8.0,0.5\n2.0,9.0,0.5\n"
SERIES_OK = b"time_h,hs_m,tp_s\n" + b"".join(f"{i},{1.0 if i % 4 else 3.0},8\n".encode() for i in range(48))
OPERABILITY_OK = json.dumps({"limiting_hs_m": {"180": {"8": 2.0, "9": None}}}).encode()


def bad_csv_files(header: bytes, row: bytes) -> dict[str, bytes]:
    """Bad versions of a CSV with ``header`` and a good ``row`` (its last field replaced)."""
    head, _, _ = row.rpartition(b",")
    return {
        "empty": b"",
        "binary": b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR" * 20,
        "huge_field": header + b"\n" + head + b"," + b"1" * 200_000 + b"\n",
        "long_field": header + b"\n" + head + b"," + b"1" * 500 + b"\n",
        "wrong_columns": b"a,b,c\n1,2,3\n4,5,6\n",
        "nan": header + b"\n" + head + b",nan\n" + row + b"\n",
        "inf": header + b"\n" + head + b",inf\n" + row + b"\n",
        "huge": header + b"\n" + head + b",1e308\n" + row.replace(b"1.0,", b"1e308,", 1) + b"\n",
        "utf16": (header + b"\n" + row + b"\n").decode().encode("utf-16"),
        "header_only": header + b"\n",
    }


def with_bom_crlf(text: bytes) -> bytes:
    return b"\xef\xbb\xbf" + text.replace(b"\n", b"\r\n")


# ------------------------------------------------------------------ the cases
SHORT = {  # each command's short horizon: a valid run takes seconds (once compiled)
    "plan": ["plan", "paper"],
    "check": ["check", "paper"],
    "simulate": ["simulate", "paper", "--duration", "0.05"],
    "workspace": ["workspace", "paper", "--points", "2x2", "--duration", "0.1"],
    "operability": ["operability", "paper_sea", "--scatter", "@scatter.csv", "--duration", "2", "--step", "0.05",
                    "--realisations", "1", "--serial"],
    "clean": ["clean", "paper_clean", "--duration", "0.1", "--no-compare", "--plant", "own"],
    "clean --seas": ["clean", "paper_clean", "--seas", "--scatter", "@scatter.csv", "--duration", "0.1",
                     "--serial", "--plant", "own"],
    "rao": ["rao", "--length", "100", "--beam", "20", "--draught", "5", "--gm", "2", "--panel", "12",
            "--omega", "0.5:1.0:2", "--headings", "180"],
    "windows": ["windows", "@series.csv", "--duration-h", "2", "--hs-limit", "2"],
    "control-study": ["control-study", "paper_sea", "--duration", "11.5", "--settle", "11", "--latencies", "0",
                      "--predictions", "none", "--pose-from", "sensor"],
    "latency": ["latency", "paper", "--calls", "200"],
    "scenarios": ["scenarios"],
}

OPTIONS = {  # option -> kind of value, per command
    "plan": {"--method": "name"},
    "simulate": {"--duration": "float", "--max-error": "float", "--plant": "name"},
    "workspace": {"--points": "grid", "--axes": "name", "--fixed": "float", "--duration": "float", "--step": "float"},
    "operability": {"--headings": "list", "--margin": "float", "--duration": "float", "--step": "float",
                    "--realisations": "int", "--workers": "int", "--workspace": "grid", "--min-area": "float",
                    "--max-error": "float", "--scheduler": "name"},
    "clean": {"--duration": "float", "--hull-area": "float", "--move-time": "float", "--plant": "name"},
    "clean --seas": {"--headings": "list", "--coverage-target": "float", "--in-band-target": "float",
                     "--workers": "int"},
    "rao": {"--length": "float", "--beam": "float", "--draught": "float", "--gm": "float", "--roll-damping": "float",
            "--headings": "list", "--omega": "list", "--panel": "float", "--hull": "name"},
    "windows": {"--duration-h": "float", "--hs-limit": "float", "--heading": "float", "--alpha": "float",
                "--days": "list"},
    "control-study": {"--latencies": "list", "--predictions": "list", "--pose-from": "list", "--rate": "float",
                      "--encoder-resolution": "float", "--duration": "float", "--settle": "float", "--plant": "name"},
    "latency": {"--calls": "int"},
}
VALUES = {"float": FLOATS, "int": INTS, "list": LISTS, "name": NAMES, "grid": ["0x3", "3x0", "1e9x1e9",
                                                                                "100000x100000", "x", "-2x2", "2"]}
EXTRA = {  # values beyond the generic ones, per option
    ("rao", "--beam"): ["1e5"], ("rao", "--panel"): ["0.1", "1e-3"], ("rao", "--omega"): ["0.2:1.8:99999999999"],
    ("latency", "--calls"): ["1000000000", "1000000000000"], ("control-study", "--rate"): ["0.5", "1e9"],
    ("control-study", "--duration"): ["1e7"], ("operability", "--workers"): ["1000"],
}


def set_option(argv: list[str], flag: str, value: str) -> list[str]:
    """``argv`` with ``flag value`` (replacing the flag's value if it has one)."""
    out = list(argv)
    if flag in out:
        out[out.index(flag) + 1] = value
    else:
        out += [flag, value]
    return out


def cases() -> list[Case]:
    found: list[Case] = []
    scatter = {"scatter.csv": SCATTER_OK}
    series = {"series.csv": SERIES_OK}
    for command, argv in SHORT.items():
        files = scatter if "@scatter.csv" in argv else series if "@series.csv" in argv else {}
        found.append(Case(command, "the short run itself", argv, dict(files)))
        for flag, kind in OPTIONS.get(command, {}).items():
            for value in VALUES[kind] + EXTRA.get((command, flag), []):
                found.append(Case(command, f"{flag} {value!r}", set_option(argv, flag, value), dict(files)))
    # scenarios that are not scenario files
    for command in ("plan", "check", "simulate", "workspace", "operability", "clean", "control-study", "latency"):
        argv = SHORT[command]
        files = scatter if "@scatter.csv" in argv else {}
        for what, content in (("missing file", None), ("a folder", "DIR"), ("empty file", b""),
                              ("binary file", b"\x00\x01\x02\xff" * 64), ("not TOML", b"[robot\nx = = 1\n")):
            spec = dict(files)
            if content is not None:
                spec["scenario.toml"] = content if content != "DIR" else b"DIR"
            found.append(Case(command, f"scenario: {what}", [argv[0], "@scenario.toml", *argv[2:]], spec))
    # scatter diagrams and series
    for command in ("operability", "clean --seas"):
        for what, content in bad_csv_files(b"hs_m,tp_s,probability", b"1.0,8.0,0.5").items():
            found.append(Case(command, f"scatter: {what}", SHORT[command], {"scatter.csv": content}))
        found.append(Case(command, "scatter: BOM and CRLF (valid)", SHORT[command],
                          {"scatter.csv": with_bom_crlf(SCATTER_OK)}))
        found.append(Case(command, "scatter: a folder", SHORT[command], {"scatter.csv": b"DIR"}))
        found.append(Case(command, "scatter: missing", SHORT[command], {}))
    for what, content in bad_csv_files(b"time_h,hs_m,tp_s", b"0,1.0,8").items():
        found.append(Case("windows", f"series: {what}", SHORT["windows"], {"series.csv": content}))
    found += [
        Case("windows", "series: BOM and CRLF (valid)", SHORT["windows"], {"series.csv": with_bom_crlf(SERIES_OK)}),
        Case("windows", "series: times +-1e308", SHORT["windows"],
             {"series.csv": b"time_h,hs_m,tp_s\n-1e308,1.0,8\n1e308,1.0,8\n"}),
        Case("windows", "series: a folder", SHORT["windows"], {"series.csv": b"DIR"}),
        Case("windows", "series: missing", SHORT["windows"], {}),
        Case("windows", "series: never workable (valid)", SHORT["windows"],
             {"series.csv": b"time_h,hs_m,tp_s\n0,3.0,8\n1,3.0,8\n"}),
    ]
    windows_op = ["windows", "@series.csv", "--duration-h", "2", "--operability", "@op.json"]
    for what, content in (("valid", OPERABILITY_OK), ("empty", b""), ("binary", b"\x00\xff" * 50),
                          ("not JSON", b"{"), ("a list", b"[1, 2]"),
                          ("limit an object", b'{"limiting_hs_m": {"180": {"8": {"a": 1}}}}'),
                          ("limit a list", b'{"limiting_hs_m": {"180": {"8": [1, 2]}}}'),
                          ("limit NaN", b'{"limiting_hs_m": {"180": {"8": NaN}}}'),
                          ("table a list", b'{"limiting_hs_m": {"180": [1]}}'),
                          ("deep", b"[" * 100000 + b"]" * 100000), ("a folder", b"DIR")):
        found.append(Case("windows", f"--operability: {what}", windows_op, {"series.csv": SERIES_OK,
                                                                            "op.json": content}))
    found.append(Case("windows", "--operability: missing", windows_op, {"series.csv": SERIES_OK}))
    # output folders that cannot be written
    for command in ("plan", "windows", "rao"):
        argv = SHORT[command]
        files = series if "@series.csv" in argv else {}
        found.append(Case(command, "--out is a file", argv + ["--out", "@afile"], {**files, "afile": b"x"}))
    return found + design_cases() + surface_cases() + obstacle_cases()


# ------------------------------------------------------------------ design, [cleaning.surface], [[obstacles]]
BUILTIN = ROOT / "src" / "marinecdpr" / "scenario" / "builtin"


def _template(band: str = "stations_m = [-5.0, 5.0]\nheights_m = [0.0, 3.0]") -> bytes:
    """paper_clean with a small band of its surface (a design run judges it in seconds)."""
    text = (BUILTIN / "paper_clean.toml").read_text(encoding="utf-8")
    text = re.sub(r"stations_m = \[[^\]]*\]", band.split("\n")[0], text)
    return re.sub(r"heights_m = \[[^\]]*\]", band.split("\n")[1], text).encode()


STUDY = (Path(__file__).resolve().parents[1] / "tests" / "data" / "tiny_study.toml").read_text(encoding="utf-8")
"""A tiny design study, shared with the tests."""


def study_files(study: str = STUDY, seas: bytes = SCATTER_OK, prefix: str = "") -> dict[str, bytes]:
    return {prefix + "study.toml": study.encode(), prefix + "template.toml": _template(),
            prefix + "paper_sea_rao.csv": (BUILTIN / "paper_sea_rao.csv").read_bytes(), prefix + "seas.csv": seas}


DESIGN = ["design", "@study.toml", "--no-verify"]


def _run_first(folder: Path, argv: list[str]) -> None:
    """The valid run, into the same output folder (what --resume takes)."""
    first = [a for a in argv if a != "--resume"]
    env = dict(os.environ, COLUMNS="200", PYTHONPATH=os.environ.get("PYTHONPATH", str(ROOT / "src")))
    subprocess.run([sys.executable, "-m", "marinecdpr", *first], cwd=folder, env=env, capture_output=True,
                   stdin=subprocess.DEVNULL, timeout=600)


def _journal_edit(edit):
    def before(folder: Path, argv: list[str]) -> None:
        _run_first(folder, argv)
        journal = folder / "out" / "journal.jsonl"
        lines = journal.read_text(encoding="utf-8").splitlines()
        journal.write_text("\n".join(edit(lines)) + "\n", encoding="utf-8")
    return before


def _copied(folder: Path, argv: list[str]) -> None:
    """A run in orig/, then orig/ copied whole to copy/ (the resumed run's)."""
    import shutil

    orig = folder / "orig"
    orig.mkdir()
    for name in ("study.toml", "template.toml", "paper_sea_rao.csv", "seas.csv"):
        (folder / name).rename(orig / name)
    _run_first(orig, ["design", str(orig / "study.toml"), "--no-verify", "--out", str(orig / "out")])
    shutil.copytree(orig, folder / "copy")


def _rao_digit_changed(folder: Path, argv: list[str]) -> None:
    _run_first(folder, argv)
    rao = folder / "paper_sea_rao.csv"
    lines = rao.read_text(encoding="utf-8").splitlines()
    i = next(k for k, ln in enumerate(lines) if ln and ln[0].isdigit() and ",heave," in ln)
    head, _, last = lines[i].rpartition(",")
    lines[i] = head + "," + str(float(last) + 1.0)  # one digit of a heave phase
    rao.write_text("\n".join(lines) + "\n", encoding="utf-8")


def design_cases() -> list[Case]:
    found = [Case("design", "the short run itself", DESIGN, study_files(), expect="ok")]
    bad = bad_csv_files(b"hs_m,tp_s,probability", b"1.0,8.0,0.5")
    bad |= {"zero probabilities": b"hs_m,tp_s,probability\n1.0,8.0,0\n2.0,9.0,0\n",
            "negative probability": b"hs_m,tp_s,probability\n1.0,8.0,-0.5\n2.0,9.0,1.5\n",
            "short row": b"hs_m,tp_s,probability\n1.0,8.0\n2.0,9.0,1\n",
            "text": b"hs_m,tp_s,probability\n1.0,eight,0.5\n2.0,9.0,0.5\n",
            "not UTF-8": b"hs_m,tp_s,probability\n1.0,8.0,0.5\xff\xfe\n2.0,9.0,0.5\n",
            "a NUL": b"hs_m,tp_s,probability\n1.0,8.0\x00,0.5\n2.0,9.0,0.5\n"}
    for what, content in bad.items():
        found.append(Case("design", f"scatter: {what}", DESIGN, study_files(seas=content)))
    for flag, values in (("--population", ["1001", "1000000000", "3"]), ("--generations", ["1001", "1000000000", "0"]),
                         ("--seed", ["99999999999999999999", "4294967296"])):
        for v in values:
            found.append(Case("design", f"{flag} {v}", DESIGN + [flag, v], study_files()))
    for what, name in (("absolute path", "/tmp/hostile_escaped"), ("a NUL", "a\\u0000b"),
                       ("../../../escaped", "../../../escaped"), ("../../escaped", "../../escaped"),
                       ("a newline", "a\\nb = 1"), ("a/b", "a/b"), ("empty", ""), ("a dot", ".")):
        found.append(Case("design", f"name: {what}", DESIGN, study_files(STUDY.replace('"tiny"', f'"{name}"', 1)),
                          out="run/deep/out"))
    resume = DESIGN + ["--resume"]
    for what, content in (("garbage first line", b"this is no json\n"), ("a list", b"[1, 2]\n"),
                          ("null", b"null\n"), ("not UTF-8", b'{"study": "\xff\xfe"}\n'),
                          ("a folder", b"DIR")):
        found.append(Case("design", f"--resume, journal: {what}", resume,
                          study_files() | {"out/journal.jsonl": content}))

    def number_as_text(lines):
        return lines[:1] + [ln.replace('"surface_hours": ', '"surface_hours": "x", "_": ', 1) for ln in lines[1:]]

    def nan(lines):
        return lines[:1] + [re.sub(r'"sea_share": [^,]+', '"sea_share": NaN', ln, count=1) for ln in lines[1:]]

    for what, edit in (("a string where a number belongs", number_as_text), ("NaN", nan)):
        found.append(Case("design", f"--resume, journal: {what}", resume, study_files(), before=_journal_edit(edit),
                          slow=2.0))
    found.append(Case("design", "--resume from a copy of the run folder (valid)",
                      ["design", "@copy/study.toml", "--no-verify", "--resume"], study_files(), out="copy/out",
                      before=_copied, expect="ok", slow=2.0))
    found.append(Case("design", "--resume after one digit of the RAO file changed", resume, study_files(),
                      before=_rao_digit_changed, expect="refused", slow=2.0))
    found.append(Case("design", "a built-in study misspelt", ["design", "ship_sid", "--no-verify"], {},
                      message="ship_side"))
    return found


SURFACE = ["clean", "@job.toml", "--surface", "--duration", "0.1", "--no-compare", "--plant", "own"]


def _surface(**changes: str) -> dict[str, bytes]:
    text = (BUILTIN / "paper_clean.toml").read_text(encoding="utf-8")
    for key, value in changes.items():
        text = re.sub(rf"^{key} = .*$", f"{key} = {value}", text, count=1, flags=re.MULTILINE)
    return {"job.toml": text.encode(), "paper_sea_rao.csv": (BUILTIN / "paper_sea_rao.csv").read_bytes()}


def surface_cases() -> list[Case]:
    found = [Case("clean --surface", "the short run itself", SURFACE, _surface(), expect="ok")]
    for v in FLOATS + ["1e6", "1e7"]:
        found.append(Case("clean --surface", f"--move-time {v!r}", SURFACE + ["--move-time", v], _surface()))
    for what, changes in (("heights_m = [0, 200]", {"heights_m": "[0.0, 200.0]"}),
                          ("heights_m = [0, 1e4]", {"heights_m": "[0.0, 10000.0]"}),
                          ("stand_off_tolerance_m = 1e-9", {"stand_off_tolerance_m": "1e-9"}),
                          ("stand_off_tolerance_m = 1e-3 (nothing cleanable)", {"stand_off_tolerance_m": "1e-3",
                                                                                 "flare": "1.0",
                                                                                 "beam_m": "200.0"}),
                          ("flare = -1, heights to 2 draughts (the side crosses the centreline)",
                           {"flare": "-1.0", "heights_m": "[0.0, 20.0]"}),
                          ("stations_m a metre", {"stations_m": "[0.0, 1.0]"})):
        found.append(Case("clean --surface", what, SURFACE, _surface(**changes)))
    found.append(Case("clean --surface", "beam_m = 200", SURFACE, _surface(beam_m="200.0"), slow=6.0))
    return found


def _obstacles(n: int) -> bytes:
    text = (BUILTIN / "paper.toml").read_text(encoding="utf-8").replace("[robot]\n", "[robot]\nclearance_m = 0.0\n", 1)
    box = '[[obstacles]]\ntype = "box"\ncenter_m = [{x:.3f}, 3.0, 0.5]\nsize_m = [0.01, 0.01, 0.01]\n'
    return (text + "\n" + "".join(box.format(x=0.001 * k) for k in range(n))).encode()


def obstacle_cases() -> list[Case]:
    return [Case("obstacles", f"{n} boxes", ["check", "@obstacles.toml"], {"obstacles.toml": _obstacles(n)},
                 message="" if n <= 1000 else r"obstacles.*at most 1000", expect="ok" if n <= 1000 else "")
            for n in (1000, 1001, 10_000)]


# ------------------------------------------------------------------ running and judging
TRACEBACK = re.compile(r"Traceback \(most recent call last\)|^\w+(Error|Exception): |Exception ignored in",
                       re.MULTILINE)
USAGE = re.compile(r"^Usage: ", re.MULTILINE)


def prepare(case: Case, folder: Path) -> list[str]:
    for name, content in case.files.items():
        path = folder / name
        path.parent.mkdir(parents=True, exist_ok=True)
        if content == b"DIR":
            path.mkdir()
        else:
            path.write_bytes(content)
    argv = [str(folder / a[1:]) if a.startswith("@") else a for a in case.argv]
    if case.command not in ("check", "latency", "scenarios", "obstacles") and "--out" not in argv:
        argv += ["--out", str(folder / case.out)]
    return argv


def files_in(folder: Path) -> set[Path]:
    return {p for p in folder.rglob("*") if p.is_file()}


ESCAPED = Path(tempfile.gettempdir())
"""Where a study named by an absolute path (``/tmp/hostile_escaped``) would write."""


def strict(text: str) -> None:
    def constant(name: str):
        raise ValueError(f"{name} in JSON")

    json.loads(text, parse_constant=constant)


def judge(case: Case, rc: int, stdout: str, stderr: str, folder: Path, new_files=()) -> tuple[str, str]:
    kind, detail = _judge(case, rc, stdout, stderr, folder, new_files)
    if kind == "refused" and case.expect == "ok":
        return "refused valid", detail
    if kind == "ok" and case.expect == "refused":
        return "accepted invalid", stdout.strip()[-200:]
    if kind == "refused" and case.message and not re.search(case.message, detail):
        return "message", detail
    return kind, detail


def _judge(case: Case, rc: int, stdout: str, stderr: str, folder: Path, new_files=()) -> tuple[str, str]:
    if TRACEBACK.search(stderr) or TRACEBACK.search(stdout):
        first = next((ln for ln in stderr.splitlines()[::-1] if "Error" in ln), stderr.strip()[-200:])
        return "traceback", first.strip()[:200]
    out = folder / case.out
    outside = [str(p.relative_to(folder)) if p.is_relative_to(folder) else str(p) for p in new_files
               if not p.is_relative_to(out)]
    if outside:
        return "outside", ", ".join(outside)[:200]
    if rc != 0 and out.is_dir() and (out / "journal.jsonl").is_file() and "--resume" not in case.argv:
        return "staging", "journal.jsonl left by a refused run"
    leftovers = [p.name for p in out.glob(".staging-*")] + [p.name for p in out.glob(".*.*") if p.is_file()
                                                             and p.name != ".marinecdpr-files"] if out.is_dir() else []
    if leftovers:
        return "staging", ", ".join(leftovers)
    if rc == 0:
        if case.command == "latency" and "--json" in case.argv:
            try:
                strict(stdout)
            except ValueError as exc:
                return "json", f"stdout: {exc}"
        for path in sorted(out.rglob("*.json")) if out.is_dir() else []:
            try:
                strict(path.read_text(encoding="utf-8"))
            except ValueError as exc:
                return "json", f"{path.name}: {exc}"
        for path in sorted(out.rglob("*.csv")) if out.is_dir() else []:
            text = path.read_text(encoding="utf-8", errors="replace")
            if re.search(r"(^|,)-?(inf|nan|infinity)(,|$)", text, re.IGNORECASE | re.MULTILINE):
                return "json", f"{path.name}: a non-finite number"
        return "ok", ""
    if rc == 2 and USAGE.search(stderr):
        return "usage", stderr.strip().splitlines()[-2][:200] if len(stderr.strip().splitlines()) > 1 else ""
    if rc not in (2, 3, 4, 5, 130):
        return f"exit {rc}", stderr.strip()[-200:]
    lines = [ln for ln in stderr.strip().splitlines() if ln.strip()]
    errors = [ln for ln in lines if ln.startswith("error:")]
    if len(errors) != 1 or lines[-1] != errors[0]:
        return "stderr", " | ".join(lines[-3:])[:300]
    return "refused", errors[0][:200]


SLOW = {"latency": 3.0, "control-study": 3.0, "clean --seas": 3.0, "clean": 2.0, "simulate": 2.0, "operability": 2.0,
        "clean --surface": 2.0, "design": 2.0}
"""Commands whose valid short run takes longer than a refusal (numba's typed lists compile
on every run, Dask or the sea states start): their cases get this many times ``--timeout``."""


def run(case: Case, timeout: float) -> Outcome:
    with tempfile.TemporaryDirectory(prefix="hostile-") as tmp:
        folder = Path(tmp)
        argv = prepare(case, folder)
        env = dict(os.environ, COLUMNS="200", PYTHONPATH=os.environ.get("PYTHONPATH", str(ROOT / "src")))
        if case.before is not None:
            case.before(folder, argv)
        t0 = time.perf_counter()
        timeout *= SLOW.get(case.command, 1.0) * case.slow
        seen = files_in(folder) | set(ESCAPED.glob("hostile_escaped*"))
        try:
            proc = subprocess.run([sys.executable, "-m", "marinecdpr", *argv], cwd=folder, env=env,
                                  capture_output=True, text=True, errors="replace", timeout=timeout,
                                  stdin=subprocess.DEVNULL)
        except subprocess.TimeoutExpired:
            return Outcome(case, "timeout", f"over {timeout:g} s", time.perf_counter() - t0)
        escaped = set(ESCAPED.glob("hostile_escaped*")) - seen
        for p in escaped:
            p.unlink() if p.is_file() else None
        kind, detail = judge(case, proc.returncode, proc.stdout, proc.stderr, folder,
                             (files_in(folder) - seen) | escaped)
        return Outcome(case, kind, detail, time.perf_counter() - t0)


def warm_up(timeout: float) -> None:
    """The first runs compile their loops (a minute or more): once, before the sweep."""
    for argv in (SHORT["simulate"], SHORT["clean"], SHORT["control-study"], SHORT["latency"]):
        case = Case(argv[0], "warm-up", argv)
        outcome = run(case, timeout)
        print(f"warm-up {' '.join(argv)}: {outcome.kind} in {outcome.seconds:.0f} s", flush=True)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--jobs", type=int, default=2, help="cases run at once (default 2)")
    ap.add_argument("--timeout", type=float, default=20.0, help="seconds a case may take (default 20)")
    ap.add_argument("--only", default="", help="commands to sweep, comma-separated (default: all)")
    ap.add_argument("--limit", type=int, default=0, help="at most this many cases (a quick check)")
    ap.add_argument("--no-warm", action="store_true", help="skip the warm-up compile runs")
    ap.add_argument("--list", action="store_true", help="list the cases and exit")
    args = ap.parse_args()
    todo = cases()
    if args.only:
        wanted = {c.strip() for c in args.only.split(",")}
        todo = [c for c in todo if c.command in wanted]
    if args.limit:
        todo = todo[:args.limit]
    if args.list:
        for c in todo:
            print(f"{c.command:14s} {c.what}")
        return 0
    sys.path.insert(0, str(ROOT / "benchmarks"))
    from _common import machine

    print(f"machine: {machine()}", flush=True)
    if not args.no_warm:
        warm_up(max(args.timeout, 900.0))
    t0 = time.perf_counter()
    with ThreadPoolExecutor(max_workers=max(args.jobs, 1)) as pool:
        outcomes = list(pool.map(lambda c: run(c, args.timeout), todo))
    counts: dict[str, int] = {}
    for o in outcomes:
        counts[o.kind] = counts.get(o.kind, 0) + 1
    clean = sum(o.clean for o in outcomes)
    print(f"\n{len(outcomes)} cases in {time.perf_counter() - t0:.0f} s: {clean} clean "
          f"({100 * clean / max(len(outcomes), 1):.1f} %)")
    for kind in sorted(counts, key=lambda k: (k not in ("ok", "refused", "usage"), k)):
        print(f"  {kind:10s} {counts[kind]}")
    unclean = [o for o in outcomes if not o.clean]
    if unclean:
        print("\nunclean:")
        for o in unclean:
            print(f"  [{o.kind}] {o.case.command}: {o.case.what}: {o.detail}")
    return 0 if not unclean else 1


if __name__ == "__main__":
    sys.exit(main())
