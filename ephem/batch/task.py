"""One task of a batch: an input partition through the core (:data:`CORE`), its answer written atomically.

:func:`run_partition` runs on a worker: everything it needs comes in its arguments. Per-row problems are the
core's (``evaluate`` puts a bad row's reason in its ``error`` column and NaN elsewhere); a task adds one reason of
its own, a cell that is not a number (``e: not a number: 'abc'``). :func:`count_done` reads back an output an
earlier run finished (resume). The engine is :mod:`ephem.batch.distributed`.
"""
from __future__ import annotations

import importlib
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from .partitions import write_atomic
from .rows import spoil_rows

#: the module holding ``INPUT_COLUMNS``, ``evaluate`` and ``batch_cost``; the tasks import it by this name
CORE = "ephem.batch.population"


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


def run_partition(core: str, in_path: str, out_path: str, fmt: str, history, write=None,
                  source: str = "") -> tuple[int, int]:
    """One task: read the input partition, answer it with ``core.evaluate``, write the output atomically;
    (rows, failed rows). Runs on a worker: everything it needs comes in its arguments. ``write(output columns,
    path, source)`` writes a format this package does not (ECSV: ephem.answers.batches.write_ecsv_partition)."""
    import pyarrow.csv as pacsv
    import pyarrow.parquet as pq

    module = importlib.import_module(core)
    table = pq.read_table(in_path)
    n = table.num_rows
    columns, bad = _core_columns(table)
    del table
    result = module.evaluate(columns, history=history)
    if write is not None:
        result = spoil_rows(result, bad)
        write_atomic(Path(out_path), lambda tmp: write(result, tmp, source))
        errors = result.get("error", ())
        return n, sum(1 for e in errors if isinstance(e, str) and e)
    out = _output_table(result, n, bad, fmt)
    if fmt == "parquet":
        write_atomic(Path(out_path), lambda tmp: pq.write_table(out, tmp))
    else:
        write_atomic(Path(out_path), lambda tmp: pacsv.write_csv(out, tmp))
    return n, _failed_rows(out.column("error")) if "error" in out.column_names else 0


def count_done(path: Path, fmt: str) -> tuple[int, int]:
    """(rows, failed rows) of a finished output partition (an earlier run's), reading its error column only."""
    import pyarrow as pa
    import pyarrow.csv as pacsv
    import pyarrow.parquet as pq

    if fmt == "ecsv":       # an ECSV partition (ephem.answers.batches.write_ecsv_partition): astropy reads it
        from astropy.table import Table

        error = Table.read(path, format="ascii.ecsv")["error"]     # whole: its masked Quantities span columns
        return len(error), sum(1 for e in error.tolist() if isinstance(e, str) and e)
    if fmt == "parquet":
        table = pq.read_table(path, columns=["error"])
    else:
        table = pacsv.read_csv(path, convert_options=pacsv.ConvertOptions(
            include_columns=["error"], column_types={"error": pa.string()}, strings_can_be_null=True,
            null_values=[""]))
    return table.num_rows, _failed_rows(table.column("error").combine_chunks())
