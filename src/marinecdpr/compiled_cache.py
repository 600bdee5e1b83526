"""Where numba caches this package's machine code: a folder named by a hash of the compiled
sources, so that an edit of any of them can never serve stale code.

numba checks only the time stamp of the file that defines a cached function, not of the
files its compiled callees come from: after an edit of a callee (or of a part the loop
calls), a caller's cache would still hold the old code. Here every cache entry lives in
``<base>/marinecdpr-<hash>``, the hash over the bytes of every module of the package that
uses numba (and the package's version): any edit of one moves every entry to a new,
empty folder. ``<base>`` is ``$MARINECDPR_CACHE_DIR``, else ``$NUMBA_CACHE_DIR``, else the
package's ``__pycache__`` where it can be written (numba's own default place), else the
user's cache folder (``$XDG_CACHE_HOME`` or ``~/.cache``) ``/marinecdpr``.

:func:`configure` runs when the package is imported, before any compiled module loads;
on the first start of new sources it removes the folders of old ones that have gone
unused (:func:`prune_old_versions`).
It also makes numba's saves of cache entries take a file lock (:func:`lock_saves`): where
processes compile side by side (:func:`~marinecdpr.prototype.warmup.compile_apart`), two of
them adding different entries of one function at once would otherwise both name their
entry's file by the same free number, and the index could end up pointing one signature's
entry at the other's machine code.
:func:`entry_point` and :func:`bound` find a compiled function's machine code once for
arguments it is called with many times.
"""

from __future__ import annotations

import hashlib
import os
import sys
from pathlib import Path

__all__ = ["configure", "cache_dir", "source_hash", "entry_point", "bound", "lock_saves", "prune_old_versions"]

_PACKAGE = Path(__file__).resolve().parent
_configured: list[str] = []


def source_hash() -> str:
    """16 hex digits over the package's compiled sources: every ``.py`` file under the
    package that mentions numba, in path order, with its relative path."""
    digest = hashlib.sha256()
    for path in sorted(_sources()):
        data = path.read_bytes()
        if b"numba" in data:
            digest.update(str(path.relative_to(_PACKAGE)).encode() + b"\0" + data + b"\0")
    return digest.hexdigest()[:16]


def _sources() -> list[Path]:
    """The package's ``.py`` files, without descending into ``__pycache__`` (where numba's
    cache folders hold thousands of files: walking them made every start slower)."""
    found = []
    for folder, subfolders, files in os.walk(_PACKAGE):
        subfolders[:] = [d for d in subfolders if d != "__pycache__"]
        found += [Path(folder) / f for f in files if f.endswith(".py")]
    return found


def _base() -> Path:
    for var in ("MARINECDPR_CACHE_DIR", "NUMBA_CACHE_DIR"):
        value = os.environ.get(var)
        if value:
            if var == "NUMBA_CACHE_DIR" and Path(value).name.startswith("marinecdpr-"):
                return Path(value).parent  # set by the process that started this one
            return Path(value)
    beside = _PACKAGE / "__pycache__"  # beside the package, as numba's own default, where it can write
    try:
        beside.mkdir(exist_ok=True)
        if os.access(beside, os.W_OK):
            return beside
    except OSError:
        pass
    home = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(home) / "marinecdpr"


def cache_dir() -> Path:
    """The folder this package's compiled code is cached in (see the module's docstring)."""
    if _configured:
        return Path(_configured[0])
    return _base() / f"marinecdpr-{source_hash()}"


def configure() -> Path:
    """Point numba's cache at :func:`cache_dir` (through ``NUMBA_CACHE_DIR`` before numba is
    imported, or numba's config after); returns the folder. Idempotent."""
    if _configured:
        return Path(_configured[0])
    folder = _base() / f"marinecdpr-{source_hash()}"
    if not folder.exists():  # the first start of these sources: the folders of old ones may go
        prune_old_versions(folder)
    os.environ["NUMBA_CACHE_DIR"] = str(folder)
    if "numba" in sys.modules:
        from numba.core import config

        config.CACHE_DIR = str(folder)
    _configured.append(str(folder))
    lock_saves()
    return folder


KEEP_VERSIONS = 2
"""Cache folders of other source versions :func:`prune_old_versions` always keeps (the newest)."""
UNUSED_S = 86400.0
"""How long another version's cache folder must have gone unwritten before it may go, s."""


def prune_old_versions(current: Path, *, keep: int = KEEP_VERSIONS, unused_s: float = UNUSED_S,
                       now: float | None = None) -> list[Path]:
    """Remove the cache folders of other source versions beside ``current``
    (``marinecdpr-<hash>``, about 75 MB each): every edit of a compiled source moves the
    cache to a new folder, and the old ones would pile up. The ``keep`` newest (by their
    last write) stay, and so does any written to within ``unused_s`` seconds (a run of
    another checkout may still use it). Removing a folder a process still reads costs it
    only a compile. :func:`configure` calls this when it first makes a folder. Returns the
    folders removed."""
    import shutil
    import time

    now = time.time() if now is None else now
    try:
        others = [p for p in current.parent.glob("marinecdpr-*") if p.is_dir() and p.name != current.name]
        others.sort(key=lambda p: p.stat().st_mtime, reverse=True)
    except OSError:
        return []
    removed = []
    for folder in others[keep:]:
        try:
            if now - folder.stat().st_mtime < unused_s:
                continue
        except OSError:
            continue
        shutil.rmtree(folder, ignore_errors=True)
        removed.append(folder)
    return removed


def lock_saves() -> bool:
    """Make numba's cache saves hold an exclusive lock on a file of the entry's folder
    (``fcntl.flock``) while it reads the index, adds its entry and writes it, so that saves
    from processes compiling at once come one after the other, each reading the index as
    the last one left it. Idempotent; False where it cannot be done (no ``fcntl``: Windows,
    where nothing here compiles side by side; or numba's cache internals changed)."""
    try:
        import fcntl

        from numba.core.caching import IndexDataCacheFile
    except ImportError:
        return False
    save = getattr(IndexDataCacheFile, "save", None)
    if save is None or not hasattr(IndexDataCacheFile, "_load_index"):
        return False
    if getattr(save, "_marinecdpr_locked", False):
        return True

    def locked_save(self, key, data):
        folder = getattr(self, "_cache_path", None)
        if folder is None:
            return save(self, key, data)
        os.makedirs(folder, exist_ok=True)
        with open(os.path.join(folder, ".marinecdpr-save.lock"), "a") as lock:
            fcntl.flock(lock, fcntl.LOCK_EX)
            try:
                return save(self, key, data)
            finally:
                fcntl.flock(lock, fcntl.LOCK_UN)

    locked_save._marinecdpr_locked = True
    locked_save.__doc__ = save.__doc__
    IndexDataCacheFile.save = locked_save
    return True


def entry_point(dispatcher, args: tuple):
    """``dispatcher``'s machine code for the types of ``args`` (compiled, or loaded from the
    cache, as a plain call would), to call without numba's dispatch: the dispatcher types
    every argument at each call to pick the machine code, which for a record of records
    such as the prototype's (about 170 arrays) costs milliseconds a call, as much as a
    500-step block of the loop. The entry point converts no argument: each call must pass
    the types of ``args`` (ints stay ints, arrays keep their dtype and layout). Where
    numba's internals have changed, the dispatcher itself."""
    try:
        return dispatcher.compile(tuple(dispatcher.typeof_pyval(a) for a in args))
    except (AttributeError, KeyError, TypeError):  # a private numba API: dispatch each call
        return dispatcher


def bound(dispatcher, *tail):
    """``dispatcher`` with its trailing arguments ``tail`` bound: ``call(*head)`` runs
    ``dispatcher(*head, *tail)`` through its :func:`entry_point`, found at the first call.
    ``head`` must keep the first call's types; ``tail`` is held as it is, not copied."""
    entry = None

    def call(*head):
        nonlocal entry
        if entry is None:
            entry = entry_point(dispatcher, (*head, *tail))
        return entry(*head, *tail)

    return call
