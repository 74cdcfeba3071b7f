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
import os
import sys
import tempfile
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
        _write(path, name, arrays)
    return arrays


def _write(path: Path, name: str, arrays: dict[str, np.ndarray]) -> None:
    tmp = None
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{name}-", suffix=".tmp")
        with os.fdopen(fd, "wb") as fh:
            np.savez(fh, **arrays)
        os.replace(tmp, path)
        tmp = None
        for old in path.parent.glob(f"{name}-*.npz"):      # the same table from inputs that changed since
            if old != path:
                old.unlink(missing_ok=True)
    except OSError:
        pass          # a read-only or full disk: the table was built, it is just not kept
    finally:
        if tmp is not None:
            Path(tmp).unlink(missing_ok=True)
