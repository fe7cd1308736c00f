"""The cache folder of compiled libraries stays within its bound and keeps what sso did
not write."""

import os
import time

from sso._solvers.library_cache import ABANDONED_BUILD_S, mark_used, prune

KB = 1024


def _library(folder, name, size, age_s):
    path = folder / name
    path.write_bytes(b"\0" * size)
    moment = time.time() - age_s
    os.utime(path, (moment, moment))
    return path


def test_the_least_recently_used_libraries_go_first_down_to_the_bound(tmp_path):
    oldest = _library(tmp_path, "sso-lm-a.so", 100 * KB, 300)
    older = _library(tmp_path, "sso-lm-b.so", 100 * KB, 200)
    recent = _library(tmp_path, "sso-lm-c.so", 100 * KB, 100)
    built = _library(tmp_path, "sso-lm-d.so", 100 * KB, 0)
    # 400 kB against a bound of 250 kB: the two least recently used go.
    assert sorted(prune(tmp_path, built, 250 * KB)) == [oldest, older]
    assert sorted(tmp_path.iterdir()) == [recent, built]


def test_a_load_marks_a_library_used_so_it_outlives_newer_unused_ones(tmp_path):
    loaded = _library(tmp_path, "sso-lm-a.so", 100 * KB, 300)
    unused = _library(tmp_path, "sso-lm-b.so", 100 * KB, 200)
    built = _library(tmp_path, "sso-lm-c.so", 100 * KB, 0)
    mark_used(loaded)
    assert prune(tmp_path, built, 250 * KB) == [unused]


def test_the_library_just_built_stays_even_alone_over_the_bound(tmp_path):
    older = _library(tmp_path, "sso-lm-a.so", 100 * KB, 100)
    # An older modification time than the other's: the build is kept all the same.
    built = _library(tmp_path, "sso-lm-b.so", 300 * KB, 500)
    assert prune(tmp_path, built, 200 * KB) == [older]
    assert list(tmp_path.iterdir()) == [built]


def test_files_sso_did_not_write_are_never_removed(tmp_path):
    built = _library(tmp_path, "sso-lm-new.so", 10 * KB, 0)
    theirs = [_library(tmp_path, name, 500 * KB, 10 * ABANDONED_BUILD_S)
              for name in ("notes.txt", "other-lib.so", "sso-lm-a.so.bak", "sso-lm-b.c")]
    (tmp_path / "sso-lm-folder.so").mkdir()
    (tmp_path / "sso-lm-link.so").symlink_to(theirs[0])
    assert prune(tmp_path, built, 0) == []
    assert all(path.exists() for path in theirs)
    assert (tmp_path / "sso-lm-folder.so").is_dir()
    assert (tmp_path / "sso-lm-link.so").is_symlink()


def test_a_partial_build_goes_only_once_abandoned(tmp_path):
    built = _library(tmp_path, "sso-lm-a.so", 10 * KB, 0)
    abandoned = _library(tmp_path, ".building-x1.so", 10 * KB, ABANDONED_BUILD_S + 60)
    under_way = _library(tmp_path, ".building-x2.so", 10 * KB, 5)
    assert prune(tmp_path, built, 100 * KB) == [abandoned]
    assert under_way.exists()
