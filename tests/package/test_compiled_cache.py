"""Issue 22: numba's cache saves from processes compiling side by side keep every entry.

numba's ``IndexDataCacheFile.save`` reads a function's index, names a new entry's file by
the first free number, and writes both: two processes adding different entries of one
function at once can both take the same number, and the index then points one
signature's entry at the other's data. :func:`marinecdpr.compiled_cache.lock_saves`
(applied when the package is imported) makes each save hold a file lock.
"""

from __future__ import annotations

import multiprocessing
import os

import pytest

import marinecdpr  # noqa: F401 - configures the cache, and with it the lock
from marinecdpr.compiled_cache import lock_saves

WRITERS, SAVES = 4, 40


def _writer(folder: str, who: int, start) -> None:
    from numba.core.caching import IndexDataCacheFile

    cache = IndexDataCacheFile(folder, "kernel", source_stamp=("stamp", 1))
    start.wait()
    for i in range(SAVES):
        cache.save((who, i), f"code of {who}/{i}")


@pytest.mark.skipif(not hasattr(os, "fork"), reason="needs fork")
def test_entries_saved_at_once_by_several_processes_each_keep_their_own_data(tmp_path):
    from numba.core.caching import IndexDataCacheFile

    assert lock_saves()  # idempotent: the package already applied it
    ctx = multiprocessing.get_context("fork")
    start = ctx.Barrier(WRITERS)
    procs = [ctx.Process(target=_writer, args=(str(tmp_path), who, start)) for who in range(WRITERS)]
    for p in procs:
        p.start()
    for p in procs:
        p.join(60)
        assert p.exitcode == 0
    cache = IndexDataCacheFile(str(tmp_path), "kernel", source_stamp=("stamp", 1))
    index = cache._load_index()
    assert len(index) == WRITERS * SAVES
    assert len(set(index.values())) == WRITERS * SAVES  # one data file per entry
    for who in range(WRITERS):
        for i in range(SAVES):
            assert cache.load((who, i)) == f"code of {who}/{i}"


def test_old_versions_cache_folders_go_but_the_newest_and_the_recently_used_stay(tmp_path):
    from marinecdpr.compiled_cache import prune_old_versions

    now = 1.0e9
    day = 86400.0
    ages = {"marinecdpr-a": 5 * day, "marinecdpr-b": 2 * day, "marinecdpr-c": 3 * day,
            "marinecdpr-d": 4 * day, "marinecdpr-e": 0.5 * day}
    for name, age in ages.items():
        folder = tmp_path / name
        (folder / "kernels").mkdir(parents=True)
        (folder / "kernels" / "f.nbi").write_bytes(b"index")
        os.utime(folder, (now - age, now - age))
    (tmp_path / "other").mkdir()  # not a cache folder of this package: never touched
    os.utime(tmp_path / "other", (now - 9 * day, now - 9 * day))
    current = tmp_path / "marinecdpr-new"  # not made yet: the first start of new sources
    removed = prune_old_versions(current, keep=2, unused_s=day, now=now)
    # newest two kept (e: 0.5 day, b: 2 days); of the rest, all unused for over a day
    assert sorted(p.name for p in removed) == ["marinecdpr-a", "marinecdpr-c", "marinecdpr-d"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["marinecdpr-b", "marinecdpr-e", "other"]
    # one written to within the hour stays even beyond the newest two
    os.utime(tmp_path / "marinecdpr-b", (now - 3 * day, now - 3 * day))
    (tmp_path / "marinecdpr-f").mkdir()
    os.utime(tmp_path / "marinecdpr-f", (now - 0.1 * day, now - 0.1 * day))
    (tmp_path / "marinecdpr-g").mkdir()
    os.utime(tmp_path / "marinecdpr-g", (now - 0.01 * day, now - 0.01 * day))
    assert [p.name for p in prune_old_versions(current, keep=1, unused_s=day, now=now)] == ["marinecdpr-b"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["marinecdpr-e", "marinecdpr-f", "marinecdpr-g", "other"]
