"""Catalogues of bodies on a distributed engine (issue 19): ``ephem batch INPUT --out OUT``.

:func:`run` answers a table of bodies (CSV or Parquet, the columns of :data:`ephem.batch.population.INPUT_COLUMNS`,
docs/batch_input.md) with :func:`ephem.batch.population.evaluate`, one task per partition on a ``dask.distributed``
cluster: a local one (one single-threaded worker process per core, every socket on 127.0.0.1) or an existing
one (``scheduler="tcp://host:port"``). docs/batch.md is the user's page.

How the work is laid out in ``OUT``:

* ``OUT/_input/part-NNNNN.parquet``: the input, split *streaming* into partitions of ``partition_rows`` rows
  (``pyarrow.csv.open_csv`` / ``ParquetFile.iter_batches``): neither the client nor a worker ever holds more
  than one partition, whatever the size of the input.
* ``OUT/_input/manifest.json``: what the split was made from (the input's path, size, mtime and SHA-256) and
  with which settings (partition rows, output format, history, ephem's version), written last.
* ``OUT/part-NNNNN.parquet`` (or ``.csv``): one task's answer, written to a temporary file beside it and
  renamed (``os.replace``) into place, so an output file that exists is complete.

A rerun with the same input and settings resumes: the partitions whose output exists are skipped. A changed
input or changed settings is refused with a message saying what changed (``fresh=True``, ``--fresh``, deletes
this engine's files in OUT and starts again): hours of finished partitions are never thrown away silently.

A task that raises is retried (``retries=3``); a worker that dies mid-task (killed, out of memory) costs a
rerun of its task on another worker (the scheduler's ``allowed-failures``, 3 by default), not the job. A
partition that still fails is reported after every other one has finished (:class:`BatchFailed`); the next
run computes only it.

Per-row problems are the core's: ``evaluate`` puts a bad row's reason in its ``error`` column and NaN
elsewhere. This module adds one reason of its own, a cell that is not a number (``e: not a number: 'abc'``).
Problems with the input as a whole (unreadable file, unknown format, a required column missing, a malformed
CSV line) raise :class:`ephem.base.errors.InvalidInputError` naming the field before any work starts.
"""
from __future__ import annotations

import contextlib
import dataclasses
import difflib
import hashlib
import importlib
import json
import os
import shutil
import time
import uuid
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..base.errors import EphemError, InvalidInputError
from .population import spoil_rows
from .. import __version__

#: the module holding ``INPUT_COLUMNS``, ``evaluate`` and ``batch_cost``; the tasks import it by this name
CORE = "ephem.batch.population"

#: the columns every input must have (``pole_epoch_jd_tdb`` and the ``*_sigma`` columns are optional)
REQUIRED_COLUMNS = ("name", "a_au", "e", "i_deg", "node_deg", "peri_deg", "mean_anomaly_deg", "epoch_jd_tdb",
                    "pole_ra_deg", "pole_dec_deg", "rotation_period_hours")
#: and one of these groups, complete (a row may fill any one of the groups the file has)
INERTIA_GROUPS = (("dynamical_ellipticity",), ("moment_a", "moment_b", "moment_c"),
                  ("axis_a_km", "axis_b_km", "axis_c_km"))
FORMATS = ("parquet", "csv")
INPUT_SUFFIXES = {".csv": "csv", ".csv.gz": "csv", ".csv.bz2": "csv", ".parquet": "parquet", ".pq": "parquet"}
MANIFEST_VERSION = "ephem-batch/1"
#: a task's retries when it raises (a worker that dies is the scheduler's allowed-failures, also 3)
RETRIES = 3
_INPUT_DIR = "_input"
_MANIFEST = "manifest.json"
_LOCK = ".lock"


class BatchFailed(EphemError):
    """Some partitions still failed after their retries; ``result`` counts the rest, which are written.

    ``failures`` maps each failed partition's index to the error of its last attempt. A rerun computes only
    the failed partitions."""

    def __init__(self, failures: dict[int, str], result: "BatchResult"):
        self.failures = dict(failures)
        self.result = result
        first = min(failures)
        super().__init__(f"{len(failures)} of {result.partitions} partitions failed after {RETRIES} retries "
                         f"(partition {first}: {failures[first]}); the others are in {result.out_path}: "
                         "run the same command again to compute only the failed ones")


@dataclass(frozen=True)
class BatchResult:
    partitions: int             #: partitions of the input
    partitions_skipped: int     #: found done by an earlier run (resume)
    rows: int                   #: rows answered, skipped partitions included (every input row has one)
    rows_failed: int            #: rows whose ``error`` column is set
    seconds: float              #: wall time of this run, split and cluster start included
    dashboard_link: str | None  #: the scheduler's dashboard, when it serves one (bokeh installed)
    out_path: Path              #: the output directory
    rows_computed: int = 0      #: rows computed by this run (not skipped)


# ------------------------------------------------------------------ input: checks and the streaming split

def _input_format(path: Path) -> str:
    name = path.name.lower()
    for suffix, fmt in sorted(INPUT_SUFFIXES.items(), key=lambda kv: -len(kv[0])):
        if name.endswith(suffix):
            return fmt
    raise InvalidInputError("input", f"unknown format of {path.name!r}: give a "
                            f"{', '.join(INPUT_SUFFIXES)} file")


def _check_columns(names: list[str], known: tuple[str, ...]) -> tuple[list[str], list[str]]:
    """(the known columns present, in the file's order; the ignored ones); a required one missing raises."""
    present = set(names)
    for column in REQUIRED_COLUMNS:
        if column not in present:
            close = difflib.get_close_matches(column, [n for n in names if n not in known], n=1, cutoff=0.4)
            raise InvalidInputError(column, "missing: the input has no such column"
                                    + (f" (is {close[0]!r} meant?)" if close else "")
                                    + "; the columns are listed in docs/batch_input.md")
    if not any(all(c in present for c in group) for group in INERTIA_GROUPS):
        raise InvalidInputError(INERTIA_GROUPS[0][0], "missing: give dynamical_ellipticity, or moment_a, moment_b "
                                "and moment_c, or axis_a_km, axis_b_km and axis_c_km (docs/batch_input.md)")
    duplicated = sorted({n for n in names if names.count(n) > 1})
    if duplicated:
        raise InvalidInputError(duplicated[0], "the input has this column more than once")
    return [n for n in names if n in known], [n for n in names if n not in known]


def _batches(path: Path, fmt: str, known: tuple[str, ...]):
    """(known columns, ignored columns, an iterator of record batches of the known columns), streaming."""
    import pyarrow as pa
    import pyarrow.csv as pacsv
    import pyarrow.parquet as pq

    try:
        if fmt == "parquet":
            pf = pq.ParquetFile(path)
            names = pf.schema_arrow.names
        else:
            with pacsv.open_csv(path) as probe:
                names = probe.schema.names
    except (OSError, pa.ArrowException) as exc:
        raise InvalidInputError("input", f"cannot read {path.name} as {fmt}: {exc}") from None
    columns, ignored = _check_columns(list(names), known)
    if fmt == "parquet":
        return columns, ignored, pf.iter_batches(batch_size=65536, columns=columns)

    # every known column as text: a cell that is not a number spoils its row, not the file (see _as_float);
    # a line with too many or too few fields, or text that is not UTF-8, is the file's fault (pyarrow's message
    # names the row); the first block is read here, the others as _split streams them (which refuses the same way)
    try:
        reader = pacsv.open_csv(
            path, read_options=pacsv.ReadOptions(use_threads=False, block_size=1 << 20),
            convert_options=pacsv.ConvertOptions(include_columns=columns,
                                                 column_types={c: pa.string() for c in columns},
                                                 strings_can_be_null=True, null_values=[""]))
    except (OSError, pa.ArrowException) as exc:
        raise InvalidInputError("input", f"cannot read {path.name} as {fmt}: {exc}") from None
    return columns, ignored, reader


def _partition_name(index: int, suffix: str) -> str:
    return f"part-{index:05d}.{suffix}"


def _write_atomic(path: Path, write: Callable[[str], None]) -> None:
    """``write(tmp)`` then rename into place: ``path`` exists only complete (a killed writer leaves a dot-file)."""
    tmp = path.with_name(f".{path.name}.tmp-{uuid.uuid4().hex[:12]}")
    try:
        write(str(tmp))
        os.replace(tmp, path)
    finally:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)


def _split(path: Path, fmt: str, known: tuple[str, ...], partition_rows: int, into: Path,
           ) -> tuple[int, int, list[str], list[str]]:
    """Split the input into ``into/part-NNNNN.parquet`` holding ``partition_rows`` rows each (the last fewer);
    (partitions, rows, columns, ignored columns). At most one partition and one read block in memory."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    columns, ignored, batches = _batches(path, fmt, known)
    into.mkdir(parents=True, exist_ok=True)
    pending: list[pa.RecordBatch] = []
    held = rows = count = 0

    def flush(table: pa.Table) -> None:
        nonlocal count
        _write_atomic(into / _partition_name(count, "parquet"), lambda tmp: pq.write_table(table, tmp))
        count += 1

    try:
        for batch in batches:
            pending.append(batch)
            held += batch.num_rows
            rows += batch.num_rows
            while held >= partition_rows:
                table = pa.Table.from_batches(pending)
                flush(table.slice(0, partition_rows))
                rest = table.slice(partition_rows)
                pending, held = rest.to_batches(), rest.num_rows
    except pa.ArrowException as exc:
        raise InvalidInputError("input", f"cannot read {path.name} as {fmt}: {exc}") from None
    finally:
        with contextlib.suppress(AttributeError):
            batches.close()
    if held:
        flush(pa.Table.from_batches(pending))
    return count, rows, columns, ignored


def _sha256(path: Path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 22), b""):
            h.update(block)
    return h.hexdigest()


# ------------------------------------------------------------------ one task: a partition through the core

def _as_float(column, name: str) -> tuple[Any, dict[int, str]]:
    """A column as float64 with NaN for a missing cell, and {row: reason} for the cells that are not numbers."""
    import numpy as np
    import pyarrow as pa
    import pyarrow.compute as pc

    if pa.types.is_string(column.type) or pa.types.is_large_string(column.type):
        try:
            values = pc.cast(column, pa.float64())
        except pa.ArrowInvalid:  # some cell is not a number: find which, one by one
            out, bad = np.full(len(column), np.nan), {}
            for i, text in enumerate(column.to_pylist()):
                if text is None:
                    continue
                try:
                    out[i] = float(text)
                except ValueError:
                    bad[i] = f"{name}: not a number: {text[:40]!r}"
            return out, bad
        return values.to_numpy(zero_copy_only=False).astype(np.float64), {}
    if pa.types.is_null(column.type):
        return np.full(len(column), np.nan), {}
    try:
        return pc.cast(column, pa.float64()).to_numpy(zero_copy_only=False).astype(np.float64), {}
    except (pa.ArrowInvalid, pa.ArrowNotImplementedError):
        return np.full(len(column), np.nan), dict.fromkeys(range(len(column)),
                                                           f"{name}: not a number (a {column.type} column)")


def known_columns(core) -> tuple[str, ...]:
    """The columns the core reads: :data:`INPUT_COLUMNS` and a ``<column>_sigma`` for each of its
    ``SIGMA_INPUTS``; the input's other columns are ignored (and named in a note)."""
    sigmas = tuple(f"{c}_sigma" for c in getattr(core, "SIGMA_INPUTS", ()))
    return tuple(core.INPUT_COLUMNS) + tuple(c for c in sigmas if c not in core.INPUT_COLUMNS)


def _core_columns(table) -> tuple[dict[str, Any], dict[int, str]]:
    """The partition's columns as the core's 1-D arrays (names as text, the rest floats with NaN for a missing
    cell; an absent optional column stays absent), and the rows with a cell that is not a number, with why."""
    import numpy as np

    columns: dict[str, Any] = {}
    bad: dict[int, str] = {}
    for name in table.column_names:
        if name == "name":
            columns[name] = np.array(["" if v is None else str(v) for v in table.column(name).to_pylist()],
                                     dtype=object)
        else:
            columns[name], why = _as_float(table.column(name).combine_chunks(), name)
            for row, reason in why.items():
                bad.setdefault(row, reason)
    return columns, bad


def _output_table(result: Mapping[str, Any], n: int, bad: Mapping[int, str], fmt: str):
    """The core's arrays as an Arrow table; the rows in ``bad`` get their reason and NaN/null elsewhere."""
    import numpy as np
    import pyarrow as pa


    arrays, names = [], []
    for key, value in result.items():
        if np.shape(value)[:1] != (n,):
            raise ValueError(f"{CORE}.evaluate gave {key!r} of shape {np.shape(value)} for {n} rows")
    for key, value in spoil_rows(result, bad).items():
        if value.ndim == 2:         # a history column: one value per epoch
            if fmt == "csv":        # CSV has no lists: a column per epoch
                for j in range(value.shape[1]):
                    names.append(f"{key}[{j}]")
                    arrays.append(pa.array(value[:, j], from_pandas=True))
                continue
            flat = pa.array(value.reshape(-1), from_pandas=True)
            arrays.append(pa.FixedSizeListArray.from_arrays(flat, value.shape[1]))
        elif value.dtype.kind == "U":
            arrays.append(pa.array(value, type=pa.string()))
        elif value.dtype.kind in "OS":      # None and NaN are null
            arrays.append(pa.array(value.astype(object), type=pa.string(), from_pandas=True))
        else:
            arrays.append(pa.array(value))
        names.append(key)
    return pa.Table.from_arrays(arrays, names=names)


def _failed_rows(error_column) -> int:
    import pyarrow.compute as pc

    if error_column.null_count == len(error_column):
        return 0
    return int(pc.sum(pc.and_(pc.is_valid(error_column), pc.not_equal(error_column, ""))).as_py() or 0)


def run_partition(core: str, in_path: str, out_path: str, fmt: str, history) -> tuple[int, int]:
    """One task: read the input partition, answer it with ``core.evaluate``, write the output atomically;
    (rows, failed rows). Runs on a worker: everything it needs comes in its arguments."""
    import pyarrow.csv as pacsv
    import pyarrow.parquet as pq

    module = importlib.import_module(core)
    table = pq.read_table(in_path)
    n = table.num_rows
    columns, bad = _core_columns(table)
    del table
    result = module.evaluate(columns, history=history)
    out = _output_table(result, n, bad, fmt)
    if fmt == "parquet":
        _write_atomic(Path(out_path), lambda tmp: pq.write_table(out, tmp))
    else:
        _write_atomic(Path(out_path), lambda tmp: pacsv.write_csv(out, tmp))
    return n, _failed_rows(out.column("error")) if "error" in out.column_names else 0


def _count_done(path: Path, fmt: str) -> tuple[int, int]:
    """(rows, failed rows) of a finished output partition (an earlier run's), reading its error column only."""
    import pyarrow as pa
    import pyarrow.csv as pacsv
    import pyarrow.parquet as pq

    if fmt == "parquet":
        table = pq.read_table(path, columns=["error"])
    else:
        table = pacsv.read_csv(path, convert_options=pacsv.ConvertOptions(
            include_columns=["error"], column_types={"error": pa.string()}, strings_can_be_null=True,
            null_values=[""]))
    return table.num_rows, _failed_rows(table.column("error").combine_chunks())


# ------------------------------------------------------------------ the manifest: resume or refuse

def _history_dict(history) -> dict | None:
    return None if history is None else {k: float(v) for k, v in dataclasses.asdict(history).items()}


def _check_history(history) -> None:
    """The span, refused before any work as every row's history would refuse it (too many epochs, beyond 2e7
    years, a step so small that the count overflows): not in each row of the output, or as a failed task."""
    if history is None:
        return
    importlib.import_module(CORE).history_epochs(history)


def _read_manifest(out: Path) -> dict | None:
    try:
        return json.loads((out / _INPUT_DIR / _MANIFEST).read_text())
    except FileNotFoundError:
        return None
    except (OSError, ValueError) as exc:
        raise InvalidInputError("out", f"{out / _INPUT_DIR / _MANIFEST} is unreadable ({exc}); rerun with "
                                "--fresh (fresh=True) to start again") from None


def _same_input(manifest: dict, path: Path, stat: os.stat_result) -> tuple[bool, str | None]:
    """(whether the manifest's input is this file's content, its SHA-256 if it had to be computed)."""
    had = manifest.get("input", {})
    if had.get("size") != stat.st_size:
        return False, None
    if had.get("mtime_ns") == stat.st_mtime_ns and had.get("path") == str(path):
        return True, None
    digest = _sha256(path)          # touched, copied or moved: the content decides
    return digest == had.get("sha256"), digest


def _differences(manifest: dict, settings: dict) -> list[str]:
    had = manifest.get("settings", {})
    return [f"{k} was {had.get(k)!r}, now {v!r}" for k, v in settings.items() if had.get(k) != v]


def _ours(entry: Path) -> bool:
    name = entry.name
    return name == _INPUT_DIR or (name.startswith(("part-", ".part-")) and (".parquet" in name or ".csv" in name))


def _clear(out: Path) -> None:
    """Delete this engine's files in ``out`` (partitions, outputs, temporaries), nothing else."""
    for entry in out.iterdir():
        if entry.name == _INPUT_DIR:
            for sub in entry.iterdir():
                if sub.name != _LOCK:
                    shutil.rmtree(sub) if sub.is_dir() and not sub.is_symlink() else sub.unlink()
        elif _ours(entry):
            entry.unlink()


@contextlib.contextmanager
def _locked(out: Path):
    """Hold ``OUT/_input/.lock`` for the run: a second run on the same OUT is refused, not interleaved."""
    try:
        import fcntl
    except ImportError:  # pragma: no cover - not POSIX
        yield
        return
    (out / _INPUT_DIR).mkdir(parents=True, exist_ok=True)
    with open(out / _INPUT_DIR / _LOCK, "a+") as f:
        try:
            fcntl.flock(f.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            raise InvalidInputError("out", f"another ephem batch run is writing {out}; wait for it or choose "
                                    "another --out") from None
        yield


def _prepare(path: Path, out: Path, fmt: str, known: tuple[str, ...], partition_rows: int, settings: dict,
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
                   if not (out / _INPUT_DIR / _partition_name(i, "parquet")).exists()]
        if missing:
            raise InvalidInputError("out", f"{out / _INPUT_DIR} lacks input partition {missing[0]} "
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
    log(f"splitting {path.name} into partitions of {partition_rows} rows under {out / _INPUT_DIR}")
    count, rows, columns, ignored = _split(path, _input_format(path), known, partition_rows, out / _INPUT_DIR)
    manifest = {"version": MANIFEST_VERSION,
                "input": {"path": str(path), "size": stat.st_size, "mtime_ns": stat.st_mtime_ns,
                          "sha256": _sha256(path)},
                "settings": settings, "columns": columns, "ignored_columns": ignored, "partitions": count,
                "rows": rows}
    _write_manifest(out, manifest)
    return manifest


def _write_manifest(out: Path, manifest: dict) -> None:
    target = out / _INPUT_DIR / _MANIFEST
    _write_atomic(target, lambda tmp: Path(tmp).write_text(json.dumps(manifest, indent=2) + "\n"))


# ------------------------------------------------------------------ the cluster

def _bokeh() -> bool:
    try:
        import bokeh  # noqa: F401
    except ImportError:
        return False
    return True


@contextlib.contextmanager
def _client(scheduler: str | None, workers: int | None):
    """A dask.distributed Client: on an existing cluster at ``scheduler``, or on a LocalCluster of ``workers``
    single-threaded processes, all bound to 127.0.0.1 (closed on exit)."""
    import logging

    import dask
    from distributed import Client, LocalCluster

    if scheduler is not None:
        try:
            client = Client(scheduler, timeout="20s", set_as_default=True)
        except (OSError, ValueError, TypeError) as exc:
            raise InvalidInputError("scheduler", f"cannot reach a dask scheduler at {scheduler!r}: {exc}") from None
        try:
            if workers is not None:
                try:
                    client.wait_for_workers(workers, timeout=120)
                except TimeoutError:
                    have = len(client.scheduler_info().get("workers", {}))
                    raise InvalidInputError("workers", f"{have} workers joined {scheduler} in 120 s, "
                                            f"{workers} asked for") from None
            yield client
        finally:
            client.close()
        return
    # The scheduler always serves HTTP (its health and metrics routes; with bokeh, the dashboard): on
    # dashboard_address=None it still takes 127.0.0.1:8787, where two runs at once would collide. Port 0:
    # a free loopback port, and the dashboard's familiar 8787 only when there is a dashboard to serve.
    # dask's nannies set MALLOC_TRIM_THRESHOLD_=65536 in a worker's environment (and in this process's): glibc
    # then maps and unmaps every array above 64 KiB afresh, and the core's numpy temporaries of a partition
    # make it 2.4 times slower (20 000 rows: 3.5 s -> 8.5 s, 9.6 s of it in the kernel). None unsets it.
    with dask.config.set({"distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": None}):
        cluster = LocalCluster(n_workers=workers or os.cpu_count() or 1, threads_per_worker=1, processes=True,
                               host="127.0.0.1", dashboard_address="127.0.0.1:8787" if _bokeh() else "127.0.0.1:0",
                               silence_logs=logging.ERROR)
    try:
        with Client(cluster, set_as_default=True) as client:
            yield client
    finally:
        cluster.close()


def _dashboard(client) -> str | None:
    """The dashboard's address, if the scheduler serves one: its HTTP port serves the dashboard only where
    bokeh is installed (else just health and metrics routes). Asked of the scheduler itself, by a function
    sent by value: a remote scheduler need not have ephem."""
    try:
        if not client.run_on_scheduler(lambda: __import__("importlib.util").util.find_spec("bokeh") is not None):
            return None
        return client.dashboard_link or None
    except Exception:  # noqa: BLE001 - no link is no reason to stop the batch
        return None


# ------------------------------------------------------------------ the engine

def run(input_path, out_path, *, scheduler: str | None = None, workers: int | None = None,
        partition_rows: int = 50_000, output_format: str = "parquet", history=None,
        progress: Callable[[int, int], None] | None = None, fresh: bool = False,
        log: Callable[[str], None] | None = None) -> BatchResult:
    """Answer every body of ``input_path`` (CSV or Parquet, by suffix) into ``out_path/part-NNNNN.<format>``.

    ``scheduler``: the address of an existing dask scheduler (``tcp://host:port``); its workers must import
    ``ephem`` and see ``out_path`` at the same path. Default: a local cluster of ``workers`` (default: the
    cores) single-threaded processes on 127.0.0.1. With ``scheduler``, ``workers`` waits until that many
    workers have joined. ``history``: an :class:`ephem.batch.population.HistorySpec` for the history columns.
    ``progress(done, total)`` is called in the calling thread with the partitions done (skipped ones
    included) once when the tasks start (after the last note) and after each partition; ``log(message)``
    gets the notes (the split, resume, the prediction, the dashboard link). ``fresh`` deletes an earlier batch in ``out_path``.

    Raises :class:`~ephem.base.errors.InvalidInputError` (the field named) before any work for a bad input or
    setting, and :class:`BatchFailed` after the run when partitions failed even after their retries.
    """
    t0 = time.perf_counter()
    log = log or (lambda message: None)
    path, out = Path(input_path).expanduser().absolute(), Path(out_path).expanduser().absolute()
    if output_format not in FORMATS:
        raise InvalidInputError("format", f"must be one of {', '.join(FORMATS)}, got {output_format!r}")
    if isinstance(partition_rows, bool) or not isinstance(partition_rows, int) or partition_rows < 1:
        raise InvalidInputError("partition_rows", f"must be a positive integer, got {partition_rows!r}")
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 1):
        raise InvalidInputError("workers", f"must be a positive integer, got {workers!r}")
    _check_history(history)
    _input_format(path)
    if not path.is_file():
        raise InvalidInputError("input", f"no such file: {path}")
    if out.exists() and not out.is_dir():
        raise InvalidInputError("out", f"{out} is a file: give a directory")
    try:
        core = importlib.import_module(CORE)
    except ImportError as exc:  # pragma: no cover - the core ships with ephem
        raise EphemError(f"the batch core {CORE} cannot be imported: {exc}") from exc
    _, _, reader = _batches(path, _input_format(path), known_columns(core))  # the header, before OUT is made
    with contextlib.suppress(AttributeError):
        reader.close()

    settings = {"partition_rows": partition_rows, "output_format": output_format,
                "history": _history_dict(history), "ephem_version": __version__}
    out.mkdir(parents=True, exist_ok=True)
    with _locked(out):
        manifest = _prepare(path, out, output_format, known_columns(core), partition_rows, settings, fresh, log)
        if manifest["ignored_columns"]:
            log(f"ignored columns (not in docs/batch_input.md): {', '.join(manifest['ignored_columns'])}")
        total = manifest["partitions"]
        outputs = [out / _partition_name(i, output_format) for i in range(total)]
        for stale in out.glob(".part-*.tmp-*"):      # a killed writer's leftovers
            stale.unlink(missing_ok=True)
        todo = [i for i in range(total) if not outputs[i].exists()]
        rows = failed = 0
        for i in set(range(total)) - set(todo):
            r, f = _count_done(outputs[i], output_format)
            rows, failed = rows + r, failed + f
        skipped = total - len(todo)
        if skipped:
            log(f"resuming: {skipped} of {total} partitions already done")
        computed, failures, link = 0, {}, None
        if not todo and progress is not None:
            progress(skipped, total)
        if todo:
            last_rows = manifest["rows"] - (total - 1) * partition_rows
            todo_rows = sum(last_rows if i == total - 1 else partition_rows for i in todo)
            with _client(scheduler, workers) as client:
                link = _dashboard(client)
                if link:
                    log(f"dashboard: {link}")
                n_workers = max(1, len(client.scheduler_info().get("workers", {})))
                log(f"{len(todo)} partitions, {todo_rows} rows on {n_workers} workers"
                    + _prediction(core, todo_rows, min(partition_rows, manifest["rows"]), history, manifest))
                if progress is not None:    # after the notes: a progress bar is not interrupted by them
                    progress(skipped, total)
                computed, failures, rows, failed = _compute(client, todo, out, outputs, output_format, history,
                                                            progress, total, skipped, rows, failed)
    result = BatchResult(partitions=total, partitions_skipped=skipped, rows=rows, rows_failed=failed,
                         seconds=time.perf_counter() - t0, dashboard_link=link, out_path=out, rows_computed=computed)
    if failures:
        raise BatchFailed(failures, result)
    return result


def _prediction(core, rows: int, partition: int, history, manifest: dict) -> str:
    """``core.batch_cost``'s prediction as a note: CPU seconds of the rows, memory of a partition."""
    import inspect

    predict = getattr(core, "batch_cost", None)
    if predict is None:
        return ""
    sigmas = {"sigma_inputs": sum(c.endswith("_sigma") for c in manifest["columns"])} \
        if "sigma_inputs" in inspect.signature(predict).parameters else {}
    total, one = predict(rows, history, **sigmas), predict(partition, history, **sigmas)
    memory = getattr(one, "memory_mb", None)
    return f": predicted {getattr(total, 'cpu_s', total):.3g} s of one core" + \
        (f", {memory:.3g} MB a worker" if memory is not None else "")


def _compute(client, todo, out, outputs, fmt, history, progress, total, done, rows, failed):
    """Submit one task per partition and collect them as they finish; (rows computed, failures, rows, failed)."""
    from distributed import as_completed

    futures = {client.submit(run_partition, CORE, str(out / _INPUT_DIR / _partition_name(i, "parquet")),
                             str(outputs[i]), fmt, history, retries=RETRIES, pure=False): i for i in todo}
    computed, failures = 0, {}
    try:
        for future in as_completed(futures):
            i = futures[future]
            try:
                r, f = future.result()
            except Exception as exc:  # noqa: BLE001 - the task's own error (or KilledWorker), reported per partition
                failures[i] = f"{type(exc).__name__}: {exc}"
            else:
                computed, rows, failed = computed + r, rows + r, failed + f
            done += 1
            if progress is not None:
                progress(done, total)
    finally:
        for future in futures:
            future.release()
    return computed, failures, rows, failed
