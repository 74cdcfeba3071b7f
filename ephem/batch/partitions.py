"""A batch's input: its format and columns checked, then split *streaming* into partitions under ``OUT/_input/``.

The input (CSV or Parquet, by suffix; docs/batch_input.md) is read in blocks (``pyarrow.csv.open_csv`` /
``ParquetFile.iter_batches``) and written as ``OUT/_input/part-NNNNN.parquet`` of ``partition_rows`` rows each:
neither the client nor a worker ever holds more than one partition. Every file lands whole (:func:`write_atomic`).
The engine is :mod:`ephem.batch.distributed`; a missing column or an unreadable file raises
:class:`ephem.base.errors.InvalidInputError` naming the field, before any work starts.
"""
from __future__ import annotations

import contextlib
import difflib
import hashlib
import os
import uuid
from collections.abc import Callable
from pathlib import Path

from ..base.errors import InvalidInputError

#: the columns every input must have (``pole_epoch_jd_tdb`` and the ``*_sigma`` columns are optional)
REQUIRED_COLUMNS = ("name", "a_au", "e", "i_deg", "node_deg", "peri_deg", "mean_anomaly_deg", "epoch_jd_tdb",
                    "pole_ra_deg", "pole_dec_deg", "rotation_period_hours")
#: and one of these groups, complete (a row may fill any one of the groups the file has)
INERTIA_GROUPS = (("dynamical_ellipticity",), ("moment_a", "moment_b", "moment_c"),
                  ("axis_a_km", "axis_b_km", "axis_c_km"))
INPUT_SUFFIXES = {".csv": "csv", ".csv.gz": "csv", ".csv.bz2": "csv", ".parquet": "parquet", ".pq": "parquet"}
#: the directory of OUT holding the input's partitions and the manifest
INPUT_DIR = "_input"


def input_format(path: Path) -> str:
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


def open_batches(path: Path, fmt: str, known: tuple[str, ...]):
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

    # every known column as text: a cell that is not a number spoils its row, not the file (see _as_float in
    # ephem.batch.task); a line with too many or too few fields, or text that is not UTF-8, is the file's fault
    # (pyarrow's message names the row); the first block is read here, the others as split_input streams them
    # (which refuses the same way)
    try:
        reader = pacsv.open_csv(
            path, read_options=pacsv.ReadOptions(use_threads=False, block_size=1 << 20),
            convert_options=pacsv.ConvertOptions(include_columns=columns,
                                                 column_types={c: pa.string() for c in columns},
                                                 strings_can_be_null=True, null_values=[""]))
    except (OSError, pa.ArrowException) as exc:
        raise InvalidInputError("input", f"cannot read {path.name} as {fmt}: {exc}") from None
    return columns, ignored, reader


def partition_name(index: int, suffix: str) -> str:
    return f"part-{index:05d}.{suffix}"


def write_atomic(path: Path, write: Callable[[str], None]) -> None:
    """``write(tmp)`` then rename into place: ``path`` exists only complete (a killed writer leaves a dot-file)."""
    tmp = path.with_name(f".{path.name}.tmp-{uuid.uuid4().hex[:12]}")
    try:
        write(str(tmp))
        os.replace(tmp, path)
    finally:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)


def split_input(path: Path, fmt: str, known: tuple[str, ...], partition_rows: int, into: Path,
           ) -> tuple[int, int, list[str], list[str]]:
    """Split the input into ``into/part-NNNNN.parquet`` holding ``partition_rows`` rows each (the last fewer);
    (partitions, rows, columns, ignored columns). At most one partition and one read block in memory."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    columns, ignored, batches = open_batches(path, fmt, known)
    into.mkdir(parents=True, exist_ok=True)
    pending: list[pa.RecordBatch] = []
    held = rows = count = 0

    def flush(table: pa.Table) -> None:
        nonlocal count
        write_atomic(into / partition_name(count, "parquet"), lambda tmp: pq.write_table(table, tmp))
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


def file_sha256(path: Path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 22), b""):
            h.update(block)
    return h.hexdigest()
