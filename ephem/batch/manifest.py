"""A batch's manifest: resume the work in OUT, or refuse it when the input or the settings changed.

``OUT/_input/manifest.json`` says what the partitions were made from (the input's path, size, mtime and SHA-256)
and with which settings (partition rows, output format, history, ephem's version); it is written last. A rerun
with the same input and settings resumes; a changed input or changed settings is refused with a message saying
what changed, unless ``fresh`` deletes this engine's files in OUT. ``OUT/_input/.lock`` keeps a second run off
the same OUT. The engine is :mod:`ephem.batch.distributed`.
"""
from __future__ import annotations

import contextlib
import json
import os
import shutil
from collections.abc import Callable
from pathlib import Path

from ..base.errors import InvalidInputError
from .partitions import INPUT_DIR, file_sha256, input_format, partition_name, split_input, write_atomic

MANIFEST_VERSION = "ephem-batch/1"
_MANIFEST = "manifest.json"
_LOCK = ".lock"


def _read_manifest(out: Path) -> dict | None:
    try:
        return json.loads((out / INPUT_DIR / _MANIFEST).read_text())
    except FileNotFoundError:
        return None
    except (OSError, ValueError) as exc:
        raise InvalidInputError("out", f"{out / INPUT_DIR / _MANIFEST} is unreadable ({exc}); rerun with "
                                "--fresh (fresh=True) to start again") from None


def _same_input(manifest: dict, path: Path, stat: os.stat_result) -> tuple[bool, str | None]:
    """(whether the manifest's input is this file's content, its SHA-256 if it had to be computed)."""
    had = manifest.get("input", {})
    if had.get("size") != stat.st_size:
        return False, None
    if had.get("mtime_ns") == stat.st_mtime_ns and had.get("path") == str(path):
        return True, None
    digest = file_sha256(path)          # touched, copied or moved: the content decides
    return digest == had.get("sha256"), digest


def _differences(manifest: dict, settings: dict) -> list[str]:
    had = manifest.get("settings", {})
    return [f"{k} was {had.get(k)!r}, now {v!r}" for k, v in settings.items() if had.get(k) != v]


def _ours(entry: Path) -> bool:
    name = entry.name
    return name == INPUT_DIR or (name.startswith(("part-", ".part-")) and (".parquet" in name or ".csv" in name or ".ecsv" in name))


def _clear(out: Path) -> None:
    """Delete this engine's files in ``out`` (partitions, outputs, temporaries), nothing else."""
    for entry in out.iterdir():
        if entry.name == INPUT_DIR:
            for sub in entry.iterdir():
                if sub.name != _LOCK:
                    shutil.rmtree(sub) if sub.is_dir() and not sub.is_symlink() else sub.unlink()
        elif _ours(entry):
            entry.unlink()


@contextlib.contextmanager
def locked(out: Path):
    """Hold ``OUT/_input/.lock`` for the run: a second run on the same OUT is refused, not interleaved."""
    try:
        import fcntl
    except ImportError:  # pragma: no cover - not POSIX
        yield
        return
    (out / INPUT_DIR).mkdir(parents=True, exist_ok=True)
    with open(out / INPUT_DIR / _LOCK, "a+") as f:
        try:
            fcntl.flock(f.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            raise InvalidInputError("out", f"another ephem batch run is writing {out}; wait for it or choose "
                                    "another --out") from None
        yield


def prepare(path: Path, out: Path, fmt: str, known: tuple[str, ...], partition_rows: int, settings: dict,
             fresh: bool, log: Callable[[str], None]) -> dict:
    """The manifest of a split matching the input and settings: the existing one (resume) or a new split."""
    stat = path.stat()
    manifest = _read_manifest(out)
    if manifest is not None and fresh:
        _clear(out)
        manifest = None
    if manifest is not None:
        same, digest = _same_input(manifest, path, stat)
        changed = ([] if same else [f"the input {path} is not the file the partitions were made from "
                                    f"({manifest.get('input', {}).get('path')}, {manifest.get('input', {}).get('size')} "
                                    "bytes)"]) + _differences(manifest, settings)
        if changed:
            raise InvalidInputError("out", f"{out} holds the work of another batch: {'; '.join(changed)}. Rerun "
                                    "with --fresh (fresh=True) to delete it and start again, or choose another --out")
        missing = [i for i in range(manifest["partitions"])
                   if not (out / INPUT_DIR / partition_name(i, "parquet")).exists()]
        if missing:
            raise InvalidInputError("out", f"{out / INPUT_DIR} lacks input partition {missing[0]} "
                                    f"({len(missing)} missing); rerun with --fresh (fresh=True)")
        if digest is not None or manifest["input"].get("path") != str(path):   # remember the new mtime
            manifest["input"].update(path=str(path), mtime_ns=stat.st_mtime_ns)
            _write_manifest(out, manifest)
        return manifest
    # a new split; an interrupted split (partitions but no manifest) is redone
    stray = [e.name for e in out.iterdir() if not _ours(e)] if out.exists() else []
    if stray:
        raise InvalidInputError("out", f"{out} is not empty and holds no batch ({stray[0]!r}…): give a new or "
                                "empty directory")
    if out.exists():
        _clear(out)
    log(f"splitting {path.name} into partitions of {partition_rows} rows under {out / INPUT_DIR}")
    count, rows, columns, ignored = split_input(path, input_format(path), known, partition_rows, out / INPUT_DIR)
    manifest = {"version": MANIFEST_VERSION,
                "input": {"path": str(path), "size": stat.st_size, "mtime_ns": stat.st_mtime_ns,
                          "sha256": file_sha256(path)},
                "settings": settings, "columns": columns, "ignored_columns": ignored, "partitions": count,
                "rows": rows}
    _write_manifest(out, manifest)
    return manifest


def _write_manifest(out: Path, manifest: dict) -> None:
    target = out / INPUT_DIR / _MANIFEST
    write_atomic(target, lambda tmp: Path(tmp).write_text(json.dumps(manifest, indent=2) + "\n"))
