"""ephem.base.disk_cache: a table built once is read back as written, a changed input builds it again (and the
stale file goes), an unreadable file or an unwritable directory is not an error, and "off" keeps nothing; the
Earth's orbital spectrum read from the cache is the one built."""
import copy

import numpy as np
import pytest

from ephem.base import disk_cache
from ephem.base.disk_cache import cached_arrays, fingerprint


@pytest.fixture
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv(disk_cache.CACHE_ENV, str(tmp_path / "cache"))
    return tmp_path / "cache"


def _builder(calls, value=1.0):
    def build():
        calls.append(1)
        return {"a": np.arange(5.0) * value, "k": np.array([[1, -2], [3, 4]])}
    return build


def test_built_once_then_read_as_written(cache):
    calls = []
    first = cached_arrays("table", "abc", _builder(calls))
    second = cached_arrays("table", "abc", _builder(calls))
    assert len(calls) == 1
    for name in first:           # a storage round trip: the same bytes
        np.testing.assert_array_equal(first[name], second[name])
        assert first[name].dtype == second[name].dtype
    assert [p.name for p in cache.glob("*.npz")] == ["table-abc.npz"]


def test_a_changed_key_builds_again_and_removes_the_stale_file(cache):
    calls = []
    cached_arrays("table", "old", _builder(calls))
    new = cached_arrays("table", "new", _builder(calls, 2.0))
    assert len(calls) == 2 and new["a"][1] == 2.0
    assert sorted(p.name for p in cache.glob("*.npz")) == ["table-new.npz"]
    cached_arrays("other", "old", _builder(calls))          # another table keeps its own file
    assert sorted(p.name for p in cache.glob("*.npz")) == ["other-old.npz", "table-new.npz"]


def test_a_damaged_file_is_built_again(cache):
    calls = []
    cached_arrays("table", "abc", _builder(calls))
    (cache / "table-abc.npz").write_bytes(b"not a zip")
    again = cached_arrays("table", "abc", _builder(calls))
    assert len(calls) == 2 and again["a"][4] == 4.0


def test_off_and_unwritable(tmp_path, monkeypatch):
    calls = []
    monkeypatch.setenv(disk_cache.CACHE_ENV, "off")
    cached_arrays("table", "abc", _builder(calls))
    cached_arrays("table", "abc", _builder(calls))
    assert len(calls) == 2
    blocker = tmp_path / "a_file"
    blocker.write_text("x")
    monkeypatch.setenv(disk_cache.CACHE_ENV, str(blocker / "cache"))     # a directory that cannot be made
    assert cached_arrays("table", "abc", _builder(calls))["a"][2] == 2.0


def test_the_key_follows_files_and_parts(tmp_path):
    f = tmp_path / "data.toml"
    f.write_text("a = 1")
    k1 = fingerprint([f], 1.0)
    assert fingerprint([f], 1.0) == k1 and fingerprint([f], 2.0) != k1
    f.write_text("a = 2")
    assert fingerprint([f], 1.0) != k1


def test_the_earths_orbital_spectrum_read_back_is_the_one_built(cache, monkeypatch):
    """Built fresh (the FFT) against read from the cache by a later call: the same spectrum (a storage round trip);
    and data changed in memory (as a test may patch it) makes another key, never the stored table."""
    from ephem.earth import lunisolar as L
    from ephem.orbit import lunar

    L.orbital_spectrum.cache_clear()
    try:
        built = L.orbital_spectrum(("moon",), 0.0)
        assert len(list(cache.glob("orbital_spectrum_moon_t0_*.npz"))) == 1
        L.orbital_spectrum.cache_clear()
        read = L.orbital_spectrum(("moon",), 0.0)
        np.testing.assert_array_equal(built.multipliers, read.multipliers)
        np.testing.assert_array_equal(built.cos_, read.cos_)
        direct = L._build_spectrum(("moon",), 0.0, L.DEFAULT_GRID, 1e-14)
        np.testing.assert_allclose(read.cos_, direct.cos_, rtol=0, atol=1e-15 * np.abs(direct.cos_).max())
        data = copy.deepcopy(lunar.lunisolar_data())
        data["moon"]["semi_major_axis_km"] = data["moon"].get("semi_major_axis_km", 384400.0) * 1.0001
        monkeypatch.setattr(lunar, "lunisolar_data", lambda: data)
        L.orbital_spectrum.cache_clear()
        L.orbital_spectrum(("moon",), 0.0)
        assert len(list(cache.glob("orbital_spectrum_moon_t0_*.npz"))) == 1     # rebuilt under another key
        monkeypatch.undo()
        monkeypatch.setenv(disk_cache.CACHE_ENV, str(cache))
        L.orbital_spectrum.cache_clear()
        again = L.orbital_spectrum(("moon",), 0.0)
        np.testing.assert_array_equal(again.cos_, built.cos_)
    finally:
        L.orbital_spectrum.cache_clear()
