"""Reading text files that may be anything: a scenario names them, and anyone may write a
scenario. RAO tables (:mod:`~marinecdpr.motion.rao`), recorded ship motion
(:mod:`~marinecdpr.motion.recorded`), scatter diagrams and sea-state series
(:mod:`~marinecdpr.studies`), operability summaries and scenarios are read through these
helpers, which refuse what is not a small UTF-8 text table before parsing and whose
messages name the place but never quote the content. Also :func:`strip_control`, for
showing user text, and :func:`atomic_path`, through which every file is written.
"""

from __future__ import annotations

import csv
import itertools
import os
import re
import stat
import tempfile
from contextlib import contextmanager
from os import PathLike
from pathlib import Path
from typing import Callable, Iterator, NoReturn

__all__ = ["MAX_CSV_BYTES", "MAX_LINE_CHARS", "MAX_FIELD_CHARS", "check_file", "read_text", "read_lines",
           "read_csv_records", "long_field", "position", "strip_control", "atomic_path"]

MAX_CSV_BYTES = 256 * 2**20
"""Largest CSV file read, bytes (256 MiB). A dense RAO table (500 frequencies x 360
headings x 6 DOFs) is about 70 MB and a day of ship motion at 20 Hz with 17 digits
about 240 MB; reading takes several times the file's size in memory, so a larger
file is refused before it is read."""
MAX_LINE_CHARS = 10_000
"""Longest line of a CSV file, characters (a table row is under 200)."""
MAX_FIELD_CHARS = 100
"""Longest field of a CSV file, characters (a number with 17 digits is 24)."""

_UTF8_BOM = b"\xef\xbb\xbf"
_CONTROL = re.compile(r"[\x00-\x08\x0b\x0c\x0e-\x1f\x7f]")  # not tab, LF, CR
_SHOWN_CONTROL = re.compile(r"[\x00-\x08\x0b-\x1f\x7f-\x9f]")  # not tab, LF


def strip_control(text: str) -> str:
    """``text`` without control characters (ANSI escape sequences lose their ESC), for showing
    a user's text (a name, a path) on a terminal, in a figure or a page."""
    return _SHOWN_CONTROL.sub("", text)


def check_file(path: str | PathLike, fail: Callable[[str], NoReturn], what: str, max_bytes: int) -> None:
    """Refuse a path that is not a regular file of at most ``max_bytes`` bytes."""
    try:
        st = os.stat(path)
    except OSError as exc:
        fail(f"cannot read the file ({exc.strerror or type(exc).__name__}); expected {what}")
    if stat.S_ISDIR(st.st_mode):
        fail(f"a folder, not a file; expected {what}")
    if not stat.S_ISREG(st.st_mode):
        fail(f"not a regular file (a device, pipe or socket); expected {what}")
    if st.st_size > max_bytes:
        fail(f"{mib(st.st_size)} is larger than {what} can be ({mib(max_bytes)} at most)")


def mib(n: int) -> str:
    return f"{n / 2**20:.0f} MiB"


def position(buf: bytes | str, pos: int, word: str) -> str:
    """``"line L, column C"`` of offset ``pos`` (lines end at LF, CRLF or CR; columns count characters)."""
    lf, cr = (b"\n", b"\r") if isinstance(buf, bytes) else ("\n", "\r")
    line = buf.count(lf, 0, pos) + buf.count(cr, 0, pos) - buf.count(cr + lf, 0, pos) + 1
    start = max(buf.rfind(lf, 0, pos), buf.rfind(cr, 0, pos)) + 1
    head = buf[start:pos]
    width = len(head.decode("utf-8", "replace")) if isinstance(head, bytes) else len(head)
    return f"{word} {line}, column {width + 1}"


def read_text(path: str | PathLike, fail: Callable[[str], NoReturn], what: str, word: str = "line",
              max_bytes: int = MAX_CSV_BYTES) -> str:
    """The text of a small UTF-8 file, its line ends as written.

    Refuses, through ``fail`` with one line that names the place (``word`` L, column C)
    but never quotes the content: a path that is not a regular file (a folder, a device,
    a pipe: checked again once open, and read without blocking), a file over
    ``max_bytes``, UTF-16, NUL bytes or other control characters (binary data) and bytes
    that are not UTF-8. A UTF-8 byte-order mark is dropped. ``what`` says what was
    expected ("a ... file").
    """
    check_file(path, fail, what, max_bytes)
    try:  # non-blocking, and checked again once open: the path may have changed meanwhile
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_BINARY", 0))
        with os.fdopen(fd, "rb") as f:
            if not stat.S_ISREG(os.fstat(f.fileno()).st_mode):
                fail(f"not a regular file; expected {what}")
            data = f.read(max_bytes + 1)  # bounded: /proc files report size 0
    except OSError as exc:
        fail(f"cannot read the file ({exc.strerror or type(exc).__name__}); expected {what}")
    if len(data) > max_bytes:
        fail(f"larger than {what} can be ({mib(max_bytes)} at most)")
    if data.startswith(_UTF8_BOM):
        data = data[len(_UTF8_BOM):]
    elif data.startswith((b"\xff\xfe", b"\xfe\xff")):
        fail(f"UTF-16 text; expected {what} in UTF-8 (in a spreadsheet: save as 'CSV UTF-8')")
    nul = data.find(b"\0")
    if nul >= 0:
        fail(f"{position(data, nul, word)}: a NUL byte, so not text; expected {what}")
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        fail(f"{position(data, exc.start, word)}: not UTF-8 text; expected {what} in UTF-8")
    control = _CONTROL.search(text)
    if control:
        fail(f"{position(text, control.start(), word)}: a control character, so not text; expected {what}")
    return text


def read_lines(path: str | PathLike, fail: Callable[[str], NoReturn], what: str, word: str = "line") -> list[str]:
    """The lines of a small UTF-8 text file, without their line ends.

    Accepts what spreadsheets write: a UTF-8 byte-order mark and LF, CRLF or CR line
    ends. Refuses, through ``fail``, what :func:`read_text` refuses (not a regular
    file, over :data:`MAX_CSV_BYTES`, binary, not UTF-8) and lines over
    :data:`MAX_LINE_CHARS` characters (so that no CSV field reaches the csv module's
    own field limit). ``what`` says what was expected ("a ... file").
    """
    text = read_text(path, fail, what, word)
    lines = text.replace("\r\n", "\n").replace("\r", "\n").split("\n")
    if lines[-1] == "":
        lines.pop()
    if max(map(len, lines), default=0) > MAX_LINE_CHARS:
        i = next(i for i, line in enumerate(lines) if len(line) > MAX_LINE_CHARS)
        fail(f"{word} {i + 1}: longer than {MAX_LINE_CHARS} characters; expected {what}")
    return lines


def read_csv_records(path: str | PathLike, fail: Callable[[str], NoReturn], what: str, word: str = "line", *,
                     one_per_line: bool = False, comments: bool = False) -> list[list[str]]:
    """The CSV records of a small UTF-8 text file read by :func:`read_lines` (its guards),
    ``[]`` for a blank line. Refused through ``fail``: a line the csv module cannot parse
    (``"<word> N: not readable as CSV (...)"``) and, with ``one_per_line``, a quoted field
    spanning lines (so that record k is line k). With ``comments``, a line whose first
    non-blank character is ``#`` is a comment: read as a blank line (``[]``, so that the
    lines keep their numbers), whatever it holds."""
    lines = read_lines(path, fail, what, word)
    if comments:
        lines = ["" if line.lstrip().startswith("#") else line for line in lines]
    reader = csv.reader(lines)
    try:
        records = list(reader)
    except csv.Error as exc:
        fail(f"{word} {reader.line_num}: not readable as CSV ({exc})")
    if one_per_line and reader.line_num != len(records):  # a quoted field with a line break
        reader = csv.reader(lines)
        line = next(reader.line_num for k, _ in enumerate(reader, 1) if reader.line_num != k)
        fail(f"{word} {line}: a quoted field spans lines; expected {what}")
    return records


def long_field(rows: list[list[str]]) -> tuple[int, int] | None:
    """(row index, field index) of the first field over :data:`MAX_FIELD_CHARS` characters."""
    if max(map(len, itertools.chain.from_iterable(rows)), default=0) <= MAX_FIELD_CHARS:
        return None
    return next((i, j) for i, rec in enumerate(rows) for j, c in enumerate(rec) if len(c) > MAX_FIELD_CHARS)


def _file_mode() -> int:
    """The mode a new file gets from open(): 0o666 less the process's umask."""
    mask = os.umask(0)
    os.umask(mask)
    return 0o666 & ~mask


@contextmanager
def atomic_path(path: str | PathLike, suffix: str = "") -> Iterator[Path]:
    """A temporary path in ``path``'s folder, renamed to ``path`` if the block succeeds:
    the file is complete or not there at all (an interrupted or failed write leaves the
    previous file, or none). Every file the package writes goes through this.

    The file ends with the mode ``open()`` would give it (the umask honoured), not the
    temporary file's private 0600.
    """
    path = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=suffix, dir=path.parent)
    os.close(fd)
    try:
        yield Path(tmp)
        os.chmod(tmp, _file_mode())
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)
