"""Writing files safely: each file complete or not at all, an output folder one run's files.

Every file is written to a temporary name beside its target and renamed into
place when complete, so an interrupted run never leaves a half-written file; a
command writes all its files into a staging folder first (:class:`StagedOutput`), so
an output folder holds one complete run or the previous one, never a mixture.
"""

from __future__ import annotations

import os
import shutil
import signal
import tempfile
import threading
from contextlib import contextmanager
from pathlib import Path
from typing import Iterator

import numpy as np

from marinecdpr.errors import OutputError
from marinecdpr.textfiles import atomic_path

__all__ = ["StagedOutput", "atomic_path", "write_json", "json_text", "strict_json", "read_manifest"]


MANIFEST = ".marinecdpr-files"
"""Hidden file in an output folder listing the files of the run that wrote it (one name a
line), after a first line ``# command: NAME`` naming the command that wrote them."""

MANIFEST_COMMAND = "# command: "
"""The manifest's first line's start; the command's name follows."""

MAX_NAMES_SAID = 3
"""Most of another command's file names a refusal names."""


def read_manifest(folder: Path) -> tuple[str | None, list[str]]:
    """The command that wrote ``folder``'s files (None: not said, as before issue 37, or no
    manifest) and the names of those files, from the folder's manifest (:data:`MANIFEST`).

    Returns
    -------
    command : str or None
    names : list of str
        As the manifest lists them (files and folders directly in ``folder``).
    """
    try:
        lines = (Path(folder) / MANIFEST).read_text(encoding="utf-8").split("\n")
    except (OSError, UnicodeDecodeError):
        return None, []
    command = None
    if lines and lines[0].startswith(MANIFEST_COMMAND):
        command = lines.pop(0)[len(MANIFEST_COMMAND):].strip() or None
    return command, [line for line in lines if line]


class StagedOutput:
    """An output folder that receives a command's files all at once.

    Construct it before the work starts: it creates ``target`` (if needed) and a hidden
    staging folder inside it, so a folder that cannot be written fails at once. Write
    every file into the path the ``with`` block yields; when the block ends normally
    the files replace those of the previous run (the ones its manifest lists; other
    files in ``target`` are left alone). If the block raises, the staged files are
    deleted and ``target`` keeps the previous run (or, if this created it, is removed
    again while still empty). SIGINT and SIGTERM are held off (delivered after) while the
    files are renamed into place and the staging folder removed, so neither is cut short;
    :attr:`committed` then says whether ``target`` holds the new run.

    ``command`` names the kind of run (the command's name); the manifest records it. A run
    replaces only the files its own command wrote there: a folder still holding another
    command's files is refused at once (the work not started), never emptied silently. A
    folder whose manifest names no command (written before commands were recorded) has its
    listed files overwritten where the new run writes the same names, and the others kept.
    Without ``command`` (library use) the previous run's files are replaced whatever wrote them.

    Raises
    ------
    OutputError
        If ``target`` is not a folder, cannot be written, or holds another command's files.
    """

    def __init__(self, target: Path, command: str | None = None):
        self.target = Path(target)
        self.command = command
        if self.target.exists() and not self.target.is_dir():
            raise OutputError(f"{self.target}: exists and is not a folder")
        self._refuse_another_commands_files()
        self._created = not self.target.exists()
        self.committed = False
        try:
            self.target.mkdir(parents=True, exist_ok=True)
            self.stage = Path(tempfile.mkdtemp(prefix=f".staging-{os.getpid()}-", dir=self.target))
        except OSError as exc:
            raise OutputError(f"{self.target}: cannot write there ({exc.strerror or exc})") from None
        _remove_orphans(self.target)

    def _refuse_another_commands_files(self) -> None:
        if self.command is None or not self.target.is_dir():
            return
        wrote, names = read_manifest(self.target)
        if wrote is None or wrote == self.command:
            return
        present = [n for n in names if "/" not in n and (self.target / n).exists()]
        if present:
            shown = ", ".join(present[:MAX_NAMES_SAID]) + (", ..." if len(present) > MAX_NAMES_SAID else "")
            raise OutputError(f"{self.target}: holds the results of '{wrote}' ({shown}); give {self.command} "
                              "another --out (or delete those files first)")

    def __enter__(self) -> Path:
        return self.stage

    def __exit__(self, exc_type, exc, tb) -> None:
        with _signals_held():  # a Ctrl-C now waits until the folder is tidy
            try:
                if exc_type is None:
                    self._commit()
                    self.committed = True
            finally:
                shutil.rmtree(self.stage, ignore_errors=True)
                if exc_type is not None and self._created:
                    try:
                        self.target.rmdir()  # only while empty
                    except OSError:
                        pass

    def _commit(self) -> None:
        new = sorted(p.name for p in self.stage.iterdir())
        manifest = self.target / MANIFEST
        wrote, listed = read_manifest(self.target)
        old = set(listed)
        if self.command is not None and wrote != self.command:
            # not this command's files (a manifest that names no command, or another's deleted
            # by hand since): overwritten only where this run writes the same names
            old &= set(new)
        for name in sorted(old - set(new)):
            stale = self.target / name
            if "/" not in name and stale.is_file():
                stale.unlink()
            elif "/" not in name and stale.is_dir():  # a folder of files the last run wrote
                shutil.rmtree(stale)
        for name in new:
            if name in old and (self.stage / name).is_dir() and (self.target / name).is_dir():
                shutil.rmtree(self.target / name)  # the last run's folder: replaced whole
            os.replace(self.stage / name, self.target / name)
        with atomic_path(manifest) as tmp:
            head = [] if self.command is None else [MANIFEST_COMMAND + self.command]
            tmp.write_text("\n".join(head + new) + "\n", encoding="utf-8")


def _remove_orphans(folder: Path) -> None:
    """Delete staging folders left in ``folder`` by runs that were killed (their process is gone)."""
    for stage in folder.glob(".staging-*-*"):
        try:
            os.kill(int(stage.name.split("-")[1]), 0)
        except ProcessLookupError:
            shutil.rmtree(stage, ignore_errors=True)
        except (ValueError, OSError):
            pass  # not ours, or a live process of another user


HELD_SIGNALS = (signal.SIGINT, signal.SIGTERM)


@contextmanager
def _signals_held() -> Iterator[None]:
    """Hold SIGINT and SIGTERM off, in the main thread, until the block ends; then deliver
    them (a Ctrl-C raises its KeyboardInterrupt after the block).

    By handlers that note the signals, not the signal mask: the mask is the thread's own,
    and a signal sent to the process goes to any thread that does not block it (NumPy's
    BLAS threads, Dask's), after which Python runs its handler in the main thread anyway.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    caught: list[int] = []
    previous = {}
    for sig in HELD_SIGNALS:
        handler = signal.getsignal(sig)
        if handler is None or handler == signal.SIG_IGN:
            continue  # set outside Python (cannot be put back), or ignored anyway
        previous[sig] = signal.signal(sig, lambda signum, frame: caught.append(signum))
    try:
        yield
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)
        for sig in dict.fromkeys(caught):
            signal.raise_signal(sig)


# ------------------------------------------------------------------ CSV and JSON
def _write_csv(names: list[str], values: np.ndarray, path: Path, int_last: bool = True,
               int_columns: tuple[int, ...] = ()) -> Path:
    path = Path(path)
    with atomic_path(path) as tmp:
        with open(tmp, "w", encoding="utf-8", newline="") as fh:
            fh.write(",".join(names) + "\n")
            if len(values) == 0:
                fh.write("\n")
            _write_rows(fh, _row_format(len(names), int_last, int_columns), values)
    return path


def _row_format(n_columns: int, int_last: bool, int_columns: tuple[int, ...] = ()) -> str:
    """A CSV row's ``%`` format: 10 significant digits; integers (flags) in ``int_columns``
    and, if ``int_last``, in the last column."""
    ints = set(int_columns) | ({n_columns - 1} if int_last else set())
    return ",".join("%d" if i in ints else "%.10g" for i in range(n_columns))


CSV_BLOCK_ROWS = 4096
"""Rows formatted per ``%`` operation when writing a CSV."""


def _write_rows(fh, fmt: str, values: np.ndarray) -> None:
    """Each row of ``values`` as ``fmt % row`` and a newline, NaN left empty.

    A block of rows is formatted by one ``%`` on the row format repeated (the loop over the
    numbers runs in C, not a Python call per row): the same bytes, about 25 % sooner.
    """
    line = fmt + "\n"
    for i in range(0, len(values), CSV_BLOCK_ROWS):
        block = values[i:i + CSV_BLOCK_ROWS]
        fh.write((line * len(block) % tuple(block.ravel().tolist())).replace("nan", ""))


def strict_json(data):
    """``data`` for strict JSON (RFC 8259, which has no NaN or Infinity): every float that
    is not finite becomes None (``null``: the value is undefined, as each summary's
    documentation of the key says), NumPy scalars and arrays become Python numbers and lists,
    tuples lists. Refusing the inputs that would make an infinite result is the commands'
    job; this keeps any file or line of JSON the package writes readable by any parser."""
    if isinstance(data, dict):
        return {str(k): strict_json(v) for k, v in data.items()}
    if isinstance(data, (list, tuple)):
        return [strict_json(v) for v in data]
    if isinstance(data, np.ndarray):
        return strict_json(data.tolist())
    if isinstance(data, np.generic):
        data = data.item()
    if isinstance(data, float) and not np.isfinite(data):
        return None
    return data


def json_text(data, indent: int | None = 2) -> str:
    """``data`` as strict JSON text (:func:`strict_json`; ``allow_nan=False``)."""
    import json

    return json.dumps(strict_json(data), indent=indent, allow_nan=False)


def write_json(data: dict, path: Path) -> Path:
    """Write ``data`` as strict JSON (:func:`json_text`), atomically."""
    path = Path(path)
    with atomic_path(path) as tmp:
        Path(tmp).write_text(json_text(data) + "\n", encoding="utf-8")
    return path
