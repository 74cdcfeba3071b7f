"""The batch answer: precession and nutation of many bodies of the caller's at once, synchronously.

From rows of columns (:mod:`ephem.batch.population`), with the checks that name each bad cell's path."""
from __future__ import annotations

import json
import math
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from ..base.budget import OverBudgetError, charge, checkpoint
from ..base.errors import InvalidInputError
from ..batch import distributed
from ..batch import population as pop
from ..exports.qtable import to_ecsv
from ..longterm.history import MAX_HISTORY_SAMPLES, MAX_SPAN_YEARS
from .results import BatchAnswer

#: the most rows :func:`batch` takes in one call (the service's is EPHEM_MAX_BATCH_ROWS); a catalogue streams through
#: ``ephem batch`` (ephem.batch.distributed, on Dask) instead
MAX_BATCH_ROWS = 100_000


def batch(rows: list[dict], *, history: dict | None = None, max_rows: int = MAX_BATCH_ROWS,
          history_path: str = "history.") -> BatchAnswer:
    """Precession and nutation of several bodies of the caller's at once, synchronously (:mod:`ephem.batch.population`).

    A bad row has its reason in ``error`` and nulls, the others are unaffected; a cell that is not a number (or not
    text, for ``name``) is its row's ``error``, as in ``ephem batch``. The cost is charged before the work, each row at
    its own eccentricity (:func:`ephem.batch.population.batch_cost`), and a batch above the service's threshold for large
    work takes its turn before any row is computed.

    Parameters
    ----------
    rows : list of dict
        One {column: value} per body (docs/batch_input.md: the orbit, the pole, the period, one inertia form,
        optional ``_sigma`` columns; angles in degrees, the period in hours).
    history : dict, optional
        {start_year, stop_year, step_years} (Julian years from J2000.0 TDB): adds each body's obliquity range (deg) and
        period (yr) over it.
    max_rows : int
        The most rows taken (default :data:`MAX_BATCH_ROWS`; the service's is EPHEM_MAX_BATCH_ROWS).
    history_path : str
        The prefix of the history's errors (``history.`` + the key; the service passes "" when the client gave them as
        query parameters).

    Returns
    -------
    BatchAnswer
        A dict: ``rows`` (one {output column: value} per input row, in order: docs/batch.md, units in the column
        names), ``columns`` (the output columns, in order) and ``model``. ``.to_qtable()``: a row per body.

    Raises
    ------
    InvalidInputError
        Naming its path (``rows[3]``, ``rows[0].colour``, ``history.step_years``), for a malformed request: rows not a
        list of objects, an unknown column, a bad history.
    OverBudgetError
        When the batch's predicted cost exceeds the budget in force.
    """
    if not isinstance(rows, list):
        raise InvalidInputError("rows", "expected a list of objects, one per body, with the columns of "
                                f"docs/batch_input.md, got {_json_kind(rows)}")
    for j, r in enumerate(rows):
        if not isinstance(r, dict):
            raise InvalidInputError(f"rows[{j}]", "expected a list of objects, one per body, with the columns of "
                                    f"docs/batch_input.md: this row is {_json_kind(r)}")
    if not rows:
        raise InvalidInputError("rows", "no rows: give at least one body")
    if len(rows) > max_rows:
        raise InvalidInputError("rows", f"{len(rows)} rows is more than {max_rows} in one request; run "
                                f"`ephem batch INPUT --out OUTPUT` (ephem.batch.distributed.run) for a catalogue")
    known = set(pop.INPUT_COLUMNS) | {f"{k}_sigma" for k in pop.SIGMA_INPUTS}
    for j, r in enumerate(rows):
        unknown = sorted((k for k in r if k not in known), key=str)
        if unknown:
            raise InvalidInputError(f"rows[{j}].{unknown[0]}", f"unknown column(s) {', '.join(map(repr, unknown))}; "
                                    "the columns are those of docs/batch_input.md")
    spec = None if history is None else _batch_history(history, history_path)
    columns, bad = _batch_columns(rows, pop)
    try:
        charge(pop.batch_cost(len(rows), spec, pop.sigma_inputs(columns), columns))
    except OverBudgetError as exc:
        if exc.field in _HISTORY_KEYS:      # a history's span: named where the client wrote it
            raise exc.within(history_path) from None
        raise
    checkpoint()    # the whole batch is charged: a large one takes its turn (or is refused busy) before any row
    out = pop.spoil_rows(pop.evaluate(columns, spec), bad)     # a cell that is not a number spoils its row only
    return BatchAnswer(batch_answer(out))


def batch_answer(out: Mapping) -> dict:
    """The batch answer ({columns, rows, model}) from the core's output columns.

    From :func:`ephem.batch.population.evaluate`, bad rows spoiled: one row object per row, NaN as null, a nutation
    multiple as an integer. :func:`batch` returns it and ``ephem batch --format ecsv`` writes it per partition
    (:func:`write_ecsv_partition`).

    Parameters
    ----------
    out : Mapping
        {output column: array}, one value per row (units in the column names).

    Returns
    -------
    dict
        ``columns`` (in order), ``rows`` (one {column: value} each) and ``model``.
    """
    def plain(key, v):
        if isinstance(v, (float, np.floating)):
            return None if not math.isfinite(v) else int(v) if key.endswith("_multiple") else float(v)
        if isinstance(v, np.integer):
            return int(v)
        return str(v) if isinstance(v, np.str_) else v

    names = list(out)
    n = len(out[names[0]]) if names else 0
    return {"columns": names, "rows": [{k: plain(k, out[k][j]) for k in names} for j in range(n)],
            "model": {"name": pop.MODEL, "theory": "Kinoshita's first-order theory with exact Hansen coefficients, "
                      "vectorised over the bodies (ephem.batch.population); each row equals the single-body answer",
                      "leading_terms": pop.LEADING_TERMS}}


def write_ecsv_partition(out: Mapping, path: str, source: str) -> None:
    """One partition of ``ephem batch --format ecsv``, written as POST /v1/batch's ECSV.

    The same answer (:func:`batch_answer`) through :func:`ephem.exports.qtable.to_ecsv`: units from the column names,
    descriptions, the model and ``source`` in the YAML header. Runs on a dask worker (the engine,
    :mod:`ephem.batch.distributed`, gets it from :func:`run_batch`: the batch package sits below the exports and cannot
    import it).

    Parameters
    ----------
    out : Mapping
        The core's output columns of the partition, one value per row.
    path : str
        The file written.
    source : str
        The input and the partition, written in the header.

    Returns
    -------
    None
    """
    flat = [k for k, v in out.items() if np.ndim(v) != 1]
    if flat:
        raise ValueError(f"ECSV takes one value per row and column; {flat[0]!r} has {np.ndim(out[flat[0]])} dimensions")
    Path(path).write_text(to_ecsv(batch_answer(out), source=source), encoding="utf-8")


def run_batch(input_path, out_path, **options):
    """:func:`ephem.batch.distributed.run` with ECSV among its output formats: a catalogue on Dask.

    Each body of ``input_path`` answered into ``out_path/part-NNNNN.<format>`` (``output_format="ecsv"``: each partition
    written by :func:`write_ecsv_partition`); what ``ephem.api.run_batch`` and ``ephem batch`` call.

    Parameters
    ----------
    input_path : str or Path
        The input table, CSV or Parquet (by suffix), with the columns of docs/batch_input.md.
    out_path : str or Path
        The output folder.
    scheduler : str, optional
        The address of an existing dask scheduler (``tcp://host:port``); default a local cluster.
    workers : int, optional
        The local cluster's processes (default: the cores); with ``scheduler``, how many workers to wait for.
    partition_rows : int
        Rows per partition (default 50 000).
    output_format : str
        "parquet" (default), "csv" or "ecsv".
    history : HistorySpec, optional
        The history columns' span (:class:`ephem.batch.population.HistorySpec`, Julian years).
    progress : callable, optional
        ``progress(done, total)``, called with the partitions done.
    fresh : bool
        Delete an earlier batch in ``out_path`` first (default: resume it).
    log : callable, optional
        ``log(message)`` gets the notes (the split, resume, the prediction, the dashboard link).
    writers : mapping, optional
        More output formats, {format: write(output columns, path, source)}; default ECSV's.
    **options
        The keywords above, passed to :func:`ephem.batch.distributed.run`.

    Returns
    -------
    BatchResult
        The partitions written, skipped and failed, the rows, the time taken.

    Raises
    ------
    MissingExtraError
        Without dask.distributed or pyarrow (the ``batch`` extra).
    InvalidInputError
        Naming the field, before any work, for a bad input or setting.
    BatchFailed
        After the run, when partitions failed even after their retries.
    """
    options.setdefault("writers", {"ecsv": write_ecsv_partition})
    return distributed.run(input_path, out_path, **options)


run_batch.__wrapped__ = distributed.run       # inspect.signature and help() show the engine's parameters


#: the keys of a batch's history, all three required
_HISTORY_KEYS = ("start_year", "stop_year", "step_years")


def _batch_history(history, path: str):
    """The batch's :class:`ephem.batch.population.HistorySpec`, validated once as every row's history would be
    (:func:`ephem.batch.population.history_epochs`); errors name ``path`` + the key (``history.step_years``)."""
    if not isinstance(history, dict):
        raise InvalidInputError(path.rstrip(".") or "history", "expected {start_year, stop_year, step_years}, "
                                f"numbers, got {_json_kind(history)}")
    for key in list(history) + list(_HISTORY_KEYS):
        if key not in _HISTORY_KEYS:
            raise InvalidInputError(f"{path}{key}", "unknown key: expected {start_year, stop_year, step_years}")
        if history.get(key) is None:
            raise InvalidInputError(f"{path}{key}", "missing: expected {start_year, stop_year, step_years}, numbers")
    spec = pop.HistorySpec(*(history[k] for k in _HISTORY_KEYS))
    try:
        pop.history_epochs(spec)
    except InvalidInputError as exc:
        # the batch's rule in the reason too: the OpenAPI document states it in these words
        raise InvalidInputError(f"{path}{exc.field}", f"{exc.reason} (start_year < stop_year and step_years > 0, "
                                f"finite numbers, within {MAX_SPAN_YEARS:.3g} years and {MAX_HISTORY_SAMPLES} "
                                "epochs)") from None
    return pop.HistorySpec(*(float(history[k]) for k in _HISTORY_KEYS))


def _batch_columns(rows: list[dict], pop) -> tuple[dict, dict[int, str]]:
    """The rows as the population's columns (name as text, the rest floats, NaN where a cell is absent or
    empty) and {row: reason} for the cells that are not numbers (or not text, for name): ``ephem batch``'s reason
    (``i_deg: not a number: 'abc'``), the row's error."""
    n = len(rows)
    keys = sorted({k for r in rows for k in r} | set(pop.REQUIRED))   # every row counted, absent values missing
    columns, bad = {}, {}
    for key in keys:
        col = np.full(n, "", dtype=object) if key == "name" else np.full(n, np.nan)
        for j, r in enumerate(rows):
            v = r.get(key)
            if v is None or v == "":
                continue
            try:
                col[j] = _batch_cell(key, v)
            except ValueError as exc:
                bad.setdefault(j, f"{key}: {exc}")
        columns[key] = col
    return columns, bad


def _batch_cell(key: str, v):
    """A cell's value: text for name, else a float; ValueError (the reason) for what is neither."""
    if isinstance(v, bytes):        # the service's CSV reader gives the raw bytes of a cell that is not UTF-8
        raise ValueError(f"not UTF-8 text: {v[:40]!r}")
    if key == "name":
        if isinstance(v, str):
            return v
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            return str(v)     # a number as a name (an asteroid's number) is its text
        raise ValueError(f"not text: {_json_kind(v)}")
    if isinstance(v, bool) or not isinstance(v, (int, float, str)):
        raise ValueError(f"not a number: {_json_kind(v)}")
    try:
        return float(v)
    except (ValueError, OverflowError):
        raise ValueError(f"not a number: {str(v)[:40]!r}") from None


def _json_kind(v) -> str:
    """What a JSON value is, for an error message: its kind, and its JSON text when short."""
    kind = {bool: "a boolean", dict: "an object", list: "an array", str: "a string", type(None): "null"}.get(
        type(v), "a number" if isinstance(v, (int, float)) else type(v).__name__)
    if v is None or isinstance(v, (dict, list)):
        return kind
    try:
        text = json.dumps(v)
    except (TypeError, ValueError):     # not a JSON value (a library caller's object)
        text = repr(v)
    return f"{kind} ({text})" if len(text) <= 40 else kind
