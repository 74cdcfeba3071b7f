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


# --- parsed TOML kept as JSON (ephem.base.disk_cache.parse_toml, issue 33)

def test_every_shipped_toml_reads_back_as_tomllib_parses_it(tmp_path, monkeypatch):
    """Each data file, parsed then read back from the cache in a new process, is the dict tomllib gives (exact: a
    cache must give back what it stored, and JSON's shortest float repr reads back to the same double)."""
    import json
    import os
    import subprocess
    import sys
    import tomllib

    from ephem.base.disk_cache import read_toml
    from ephem.base.paths import data_dir

    monkeypatch.setenv("EPHEM_CACHE_DIR", str(tmp_path))
    files = sorted(data_dir().rglob("*.toml"))
    assert len(files) > 10
    for f in files:
        assert read_toml(f) == tomllib.loads(f.read_text(encoding="utf-8")), f
    code = ("import json, sys; from pathlib import Path; from ephem.base.disk_cache import read_toml; "
            "print(json.dumps([read_toml(Path(p)) for p in sys.argv[1:]]))")
    out = subprocess.run([sys.executable, "-c", code, *map(str, files)], capture_output=True, text=True, check=True,
                         env={**os.environ, "EPHEM_CACHE_DIR": str(tmp_path)}).stdout
    for f, doc in zip(files, json.loads(out)):
        assert doc == tomllib.loads(f.read_text(encoding="utf-8")), f


def test_a_toml_json_cannot_carry_is_parsed_each_time_and_a_damaged_file_again(tmp_path, monkeypatch):
    import datetime

    from ephem.base.disk_cache import parse_toml

    monkeypatch.setenv("EPHEM_CACHE_DIR", str(tmp_path))
    assert parse_toml("when = 2020-01-01\n", "dated") == {"when": datetime.date(2020, 1, 1)}
    assert not list(tmp_path.glob("toml_dated-*"))
    assert parse_toml("x = 1.5\n", "plain") == {"x": 1.5}
    (stored,) = tmp_path.glob("toml_plain-*.json")
    stored.write_text("{not json")
    assert parse_toml("x = 1.5\n", "plain") == {"x": 1.5}
    assert parse_toml("x = 2.5\n", "plain") == {"x": 2.5}          # changed text: a new key, the old file goes
    assert len(list(tmp_path.glob("toml_plain-*.json"))) == 1
