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
* ``OUT/part-NNNNN.parquet`` (or ``.csv``, or ``.ecsv`` with a writer for it): one task's answer, written to a temporary file beside it and
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

This module is the engine (:func:`run`: check the settings, then submit one task per partition and collect
them); its parts are beside it: :mod:`ephem.batch.partitions` (the input checked and split),
:mod:`ephem.batch.task` (one partition through the core), :mod:`ephem.batch.manifest` (resume or refuse) and
:mod:`ephem.batch.cluster` (the Dask cluster and its dashboard).
"""
from __future__ import annotations

import contextlib
import dataclasses
import importlib
import inspect
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path

from ..base.errors import EphemError, InvalidInputError
from ..base.extras import require
from .cluster import dashboard, dask_client
from .manifest import locked, prepare
from .partitions import INPUT_DIR, input_format, open_batches, partition_name
from .task import CORE, count_done, known_columns, run_partition
from .. import __version__

#: the formats this package writes itself; others (ECSV) come as ``writers`` from above (ephem.answers.batches)
FORMATS = ("parquet", "csv")
#: a task's retries when it raises (a worker that dies is the scheduler's allowed-failures, also 3)
RETRIES = 3


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


# ------------------------------------------------------------------ the settings: refused before any work

def _history_dict(history) -> dict | None:
    return None if history is None else {k: float(v) for k, v in dataclasses.asdict(history).items()}


def _check_history(history) -> None:
    """The span, refused before any work as every row's history would refuse it (too many epochs, beyond 2e7
    years, a step so small that the count overflows): not in each row of the output, or as a failed task."""
    if history is None:
        return
    importlib.import_module(CORE).history_epochs(history)


# ------------------------------------------------------------------ the engine

def run(input_path: str | Path, out_path: str | Path, *, scheduler: str | None = None, workers: int | None = None,
        partition_rows: int = 50_000, output_format: str = "parquet", history=None,
        progress: Callable[[int, int], None] | None = None, fresh: bool = False,
        log: Callable[[str], None] | None = None,
        writers: Mapping[str, Callable[[dict, str, str], None]] | None = None) -> BatchResult:
    """Answer every body of ``input_path`` (CSV or Parquet, by suffix) into ``out_path/part-NNNNN.<format>``.

    ``scheduler``: the address of an existing dask scheduler (``tcp://host:port``); its workers must import
    ``ephem`` and see ``out_path`` at the same path. Default: a local cluster of ``workers`` (default: the
    cores) single-threaded processes on 127.0.0.1. With ``scheduler``, ``workers`` waits until that many
    workers have joined. ``history``: an :class:`ephem.batch.population.HistorySpec` for the history columns.
    ``progress(done, total)`` is called in the calling thread with the partitions done (skipped ones
    included) once when the tasks start (after the last note) and after each partition; ``log(message)``
    gets the notes (the split, resume, the prediction, the dashboard link). ``fresh`` deletes an earlier batch in ``out_path``.
    ``writers``: more output formats, {format: write(output columns, path, source)}, run on the workers (a
    module-level function: it is pickled by name); ``ephem.api.run_batch`` passes ECSV's.

    Raises :class:`~ephem.base.errors.MissingExtraError` without dask.distributed or pyarrow (the ``batch`` extra),
    :class:`~ephem.base.errors.InvalidInputError` (the field named) before any work for a bad input or
    setting, and :class:`BatchFailed` after the run when partitions failed even after their retries.
    """
    require("batch", "a batch on Dask")
    t0 = time.perf_counter()
    log = log or (lambda message: None)
    path, out = Path(input_path).expanduser().absolute(), Path(out_path).expanduser().absolute()
    writers = dict(writers or {})
    if output_format not in FORMATS + tuple(writers):
        raise InvalidInputError("format", f"must be one of {', '.join(FORMATS + tuple(writers))}, got "
                                f"{output_format!r}")
    if isinstance(partition_rows, bool) or not isinstance(partition_rows, int) or partition_rows < 1:
        raise InvalidInputError("partition_rows", f"must be a positive integer, got {partition_rows!r}")
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 1):
        raise InvalidInputError("workers", f"must be a positive integer, got {workers!r}")
    _check_history(history)
    input_format(path)
    if not path.is_file():
        raise InvalidInputError("input", f"no such file: {path}")
    if out.exists() and not out.is_dir():
        raise InvalidInputError("out", f"{out} is a file: give a directory")
    try:
        core = importlib.import_module(CORE)
    except ImportError as exc:  # pragma: no cover - the core ships with ephem
        raise EphemError(f"the batch core {CORE} cannot be imported: {exc}") from exc
    _, _, reader = open_batches(path, input_format(path), known_columns(core))  # the header, before OUT is made
    with contextlib.suppress(AttributeError):
        reader.close()

    settings = {"partition_rows": partition_rows, "output_format": output_format,
                "history": _history_dict(history), "ephem_version": __version__}
    out.mkdir(parents=True, exist_ok=True)
    with locked(out):
        manifest = prepare(path, out, output_format, known_columns(core), partition_rows, settings, fresh, log)
        if manifest["ignored_columns"]:
            log(f"ignored columns (not in docs/batch_input.md): {', '.join(manifest['ignored_columns'])}")
        total = manifest["partitions"]
        outputs = [out / partition_name(i, output_format) for i in range(total)]
        for stale in out.glob(".part-*.tmp-*"):      # a killed writer's leftovers
            stale.unlink(missing_ok=True)
        todo = [i for i in range(total) if not outputs[i].exists()]
        rows = failed = 0
        for i in set(range(total)) - set(todo):
            r, f = count_done(outputs[i], output_format)
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
            with dask_client(scheduler, workers) as client:
                link = dashboard(client)
                if link:
                    log(f"dashboard: {link}")
                n_workers = max(1, len(client.scheduler_info().get("workers", {})))
                log(f"{len(todo)} partitions, {todo_rows} rows on {n_workers} workers"
                    + _prediction(core, todo_rows, min(partition_rows, manifest["rows"]), history, manifest))
                if progress is not None:    # after the notes: a progress bar is not interrupted by them
                    progress(skipped, total)
                write = writers.get(output_format), f"ephem batch {path}"
                computed, failures, rows, failed = _compute(client, todo, out, outputs, output_format, history,
                                                            progress, total, skipped, rows, failed, write)
    result = BatchResult(partitions=total, partitions_skipped=skipped, rows=rows, rows_failed=failed,
                         seconds=time.perf_counter() - t0, dashboard_link=link, out_path=out, rows_computed=computed)
    if failures:
        raise BatchFailed(failures, result)
    return result


def _prediction(core, rows: int, partition: int, history, manifest: dict) -> str:
    """``core.batch_cost``'s prediction as a note: CPU seconds of the rows, memory of a partition."""
    predict = getattr(core, "batch_cost", None)
    if predict is None:
        return ""
    sigmas = {"sigma_inputs": sum(c.endswith("_sigma") for c in manifest["columns"])} \
        if "sigma_inputs" in inspect.signature(predict).parameters else {}
    total, one = predict(rows, history, **sigmas), predict(partition, history, **sigmas)
    memory = getattr(one, "memory_mb", None)
    return f": predicted {getattr(total, 'cpu_s', total):.3g} s of one core" + \
        (f", {memory:.3g} MB a worker" if memory is not None else "")


def _compute(client, todo, out, outputs, fmt, history, progress, total, done, rows, failed, write):
    """Submit one task per partition and collect them as they finish; (rows computed, failures, rows, failed).
    ``write``: (a writer of ``fmt`` or None, the source its files name)."""
    from distributed import as_completed

    writer, source = write
    futures = {client.submit(run_partition, CORE, str(out / INPUT_DIR / partition_name(i, "parquet")),
                             str(outputs[i]), fmt, history, writer, f"{source}, partition {i}",
                             retries=RETRIES, pure=False): i for i in todo}
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
