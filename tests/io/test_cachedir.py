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


def test_a_cache_reached_through_a_link_in_a_directory_others_can_write_is_refused(tmp_path):
    """Issue 55: the way to the cache is checked, not only where it resolves (before: accepted)."""
    mine = tmp_path / "mine"
    mine.mkdir(mode=0o700)
    shared = tmp_path / "shared"
    shared.mkdir()
    shared.chmod(0o777)  # anyone may replace the link after the check
    (shared / "cache").symlink_to(mine)
    with pytest.raises(UnsafeDirectory, match=rf"since {shared} is writable by its group or by others"):
        private_directory(shared / "cache", "SETTING")
    with pytest.raises(UnsafeDirectory, match=rf"since {shared} is writable"):
        private_directory(shared / "cache" / "sub", "SETTING")  # nothing created through it
    assert not (mine / "sub").exists()


def test_a_link_owned_by_another_user_in_a_sticky_directory_is_refused(tmp_path, monkeypatch):
    sticky = tmp_path / "tmp"
    sticky.mkdir()
    sticky.chmod(0o1777)
    (tmp_path / "mine").mkdir(mode=0o700)
    (sticky / "cache").symlink_to(tmp_path / "mine")
    assert private_directory(sticky / "cache", "SETTING")  # my own link: accepted
    real_lstat = os.lstat

    def others_link(p):  # the link as another user's (the tests run as one user)
        st = real_lstat(p)
        if os.fspath(p) == str(sticky / "cache"):
            return os.stat_result((st.st_mode, st.st_ino, st.st_dev, st.st_nlink, 4242, *tuple(st)[5:]))
        return st

    monkeypatch.setattr(os, "lstat", others_link)
    with pytest.raises(UnsafeDirectory, match=rf"{sticky / 'cache'} is a symbolic link owned by uid 4242"):
        private_directory(sticky / "cache", "SETTING")


def test_the_projects_cache_is_sleighsim_cache_when_set_else_the_users_dot_cache(tmp_path, monkeypatch):
    from sleighsim.io.cachedir import project_cache

    monkeypatch.setenv("SLEIGHSIM_CACHE", str(tmp_path / "c"))
    assert project_cache() == (tmp_path / "c", "SLEIGHSIM_CACHE")
    monkeypatch.delenv("SLEIGHSIM_CACHE")
    monkeypatch.setenv("HOME", str(tmp_path))
    assert project_cache() == (tmp_path / ".cache" / "sleighsim", "~/.cache/sleighsim")
