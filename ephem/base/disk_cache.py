"""Arrays built from shipped data, kept on disk between processes.

Some tables are pure functions of the project's data files and code (the Earth's orbital spectrum: an FFT of the
Moon's and the Sun's orbits on a 5-torus, 1.6 s) and were built again by every process: every CLI call paid for
them. :func:`cached_arrays` keeps them in ``.npz`` files under :func:`cache_dir`, named by a key that hashes
everything the table is made from (:func:`fingerprint`: the data files' and the code files' bytes, the arguments,
numpy's version), so a changed input never reads a stale table: it is built again under a new name, and the old
file of that table is removed.

The directory is ``$EPHEM_CACHE_DIR`` (empty or "off": no disk cache), else ``$XDG_CACHE_HOME/ephem``, else
``~/.cache/ephem``. A directory that cannot be written, or a file that cannot be read (truncated, another format),
is not an error: the table is built as if there were no cache. Files are written to a temporary name and renamed,
so concurrent processes (the service's workers) never read half a file; they are read with ``allow_pickle=False``.
"""
from __future__ import annotations

import hashlib
import json
import math
import os
import re
import sys
import tempfile
import tomllib
import zipfile
from collections.abc import Callable, Iterable
from pathlib import Path

import numpy as np

#: the environment variable naming the cache directory ("" or "off": none)
CACHE_ENV = "EPHEM_CACHE_DIR"


def cache_dir() -> Path | None:
    """Where the tables are kept, or None when the disk cache is off."""
    value = os.environ.get(CACHE_ENV)
    if value is not None:
        return None if value.strip().lower() in ("", "off", "0", "none") else Path(value)
    base = os.environ.get("XDG_CACHE_HOME")
    return (Path(base) if base else Path.home() / ".cache") / "ephem"


def fingerprint(files: Iterable[Path], *parts) -> str:
    """A hex key of the files' bytes, the parts' reprs, and the Python and numpy versions."""
    h = hashlib.sha256()
    for f in files:
        h.update(str(Path(f).name).encode())
        h.update(Path(f).read_bytes())
    h.update(repr(parts).encode())
    h.update(f"{sys.version_info[:2]} numpy {np.__version__}".encode())
    return h.hexdigest()


def cached_arrays(name: str, key: str, build: Callable[[], dict[str, np.ndarray]]) -> dict[str, np.ndarray]:
    """The arrays ``build()`` returns, read from ``<cache_dir>/<name>-<key>.npz`` when a previous process wrote them.

    ``name``: the table's name (letters, digits, "_" and "."); ``key``: :func:`fingerprint` of its inputs. Returns
    a dict of arrays, the same whether read or built."""
    folder = cache_dir()
    path = None if folder is None else folder / f"{name}-{key[:40]}.npz"
    if path is not None:
        try:
            with np.load(path, allow_pickle=False) as stored:
                return {k: stored[k] for k in stored.files}
        except (OSError, ValueError, EOFError, zipfile.BadZipFile):
            pass      # not there, or not readable: build it
    arrays = build()
    if path is not None:
        _write(path, name, lambda fh: np.savez(fh, **arrays))
    return arrays


def _write(path: Path, name: str, save: Callable) -> None:
    """``save(binary file)`` into ``path`` through a temporary name, then the files of ``name`` with other keys
    removed (the same table from inputs that changed since)."""
    tmp = None
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{name}-", suffix=".tmp")
        with os.fdopen(fd, "wb") as fh:
            save(fh)
        os.replace(tmp, path)
        tmp = None
        for old in path.parent.glob(f"{name}-*{path.suffix}"):
            if old != path:
                old.unlink(missing_ok=True)
    except OSError:
        pass          # a read-only or full disk: the table was built, it is just not kept
    finally:
        if tmp is not None:
            Path(tmp).unlink(missing_ok=True)


def parse_toml(text: str, name: str) -> dict:
    """``tomllib.loads(text)``, kept on disk as JSON between processes under a key hashing the text (``name``: the
    file's, letters, digits and "_"). tomllib is pure Python: 3 ms for each 20-kB data file a one-body answer reads,
    where reading the JSON back takes 0.1 ms. A document JSON cannot carry exactly (a TOML date) is parsed every
    time; a missing or unreadable file is parsed again."""
    folder = cache_dir()
    key = hashlib.sha256(text.encode()).hexdigest()[:40]
    name = re.sub(r"[^A-Za-z0-9_]", "_", name)
    path = None if folder is None else folder / f"toml_{name}-{key}.json"
    if path is not None:
        try:
            with open(path, encoding="utf-8") as fh:
                return json.load(fh)
        except (OSError, ValueError):
            pass
    doc = tomllib.loads(text)
    if path is not None and _json_exact(doc):
        _write(path, f"toml_{name}", lambda fh: fh.write(json.dumps(doc).encode()))
    return doc


def read_toml(path: Path) -> dict:
    """:func:`parse_toml` of a file, named by its stem."""
    path = Path(path)
    return parse_toml(path.read_text(encoding="utf-8"), path.stem.replace("-", "_"))


def _json_exact(value) -> bool:
    """Whether JSON gives ``value`` back as it is: dicts of str, lists, str, bool, int and finite floats (JSON's
    float is the shortest repr, which reads back to the same double)."""
    if isinstance(value, dict):
        return all(isinstance(k, str) and _json_exact(v) for k, v in value.items())
    if isinstance(value, list):
        return all(_json_exact(v) for v in value)
    if isinstance(value, float):
        return math.isfinite(value)
    return isinstance(value, (str, bool, int))

