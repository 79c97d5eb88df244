"""Cache directories: created private, refused when another user owns or can write them."""

import os
import stat

import pytest

from sleighsim.io.cachedir import UnsafeDirectory, private_directory


def mode(path):
    return stat.S_IMODE(path.stat().st_mode)


def test_a_missing_cache_directory_is_created_0700(tmp_path):
    path = private_directory(tmp_path / "a" / "cache", "SETTING")
    assert path == tmp_path / "a" / "cache" and mode(path) == 0o700


@pytest.mark.parametrize("bits", [0o777, 0o707, 0o1777])
def test_a_cache_directory_others_can_write_is_refused_with_the_reason(tmp_path, bits):
    cache = tmp_path / "cache"
    cache.mkdir()
    cache.chmod(bits)
    with pytest.raises(UnsafeDirectory, match=rf"^SETTING {cache}: refused as a cache, since {cache} is writable by "
                                              rf"its group or by others \(mode {bits:04o}\)"):
        private_directory(cache, "SETTING")


def test_a_cache_directory_owned_by_another_user_is_refused(tmp_path, monkeypatch):
    cache = tmp_path / "cache"
    cache.mkdir(mode=0o700)
    other = cache.stat().st_uid + 4242
    monkeypatch.setattr(os, "geteuid", lambda: other)
    with pytest.raises(UnsafeDirectory, match=rf"{cache} is owned by uid {cache.stat().st_uid}, not by you"):
        private_directory(cache, "SETTING")


def test_a_parent_others_can_write_is_refused_unless_sticky(tmp_path):
    """Whoever can write the parent can replace the cache after it is checked; /tmp's sticky bit stops that."""
    parent = tmp_path / "shared"
    parent.mkdir()
    parent.chmod(0o777)
    with pytest.raises(UnsafeDirectory, match=rf"since {parent} is writable by its group or by others"):
        private_directory(parent / "cache", "SETTING")
    parent.chmod(0o1777)
    assert mode(private_directory(parent / "cache", "SETTING")) == 0o700
