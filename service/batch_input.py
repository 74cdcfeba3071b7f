"""The rows of a batch as the service receives them: JSON rows, a JSON object, or CSV.

A JSON array of row objects, a JSON object {rows, history}, or
CSV with a header of column names (POST /v1/batch, and the web page's uploaded file). What is not one of these is
refused naming where; the rows' values are ephem.api.batch's to judge."""
from __future__ import annotations

import csv
import io

import orjson

from ephem.api import InvalidInputError

from .json_body import duplicate_reason, first_duplicate


def batch_rows(raw: bytes, content_type: str) -> tuple[list, dict | None]:
    """The rows (and history) of a POST /v1/batch body: a JSON array of row objects, a JSON object {rows, history},
    or CSV (text/csv) with a header of column names. What is not one of these is refused naming where (``body``,
    a key, ``rows[j]`` for a CSV line); the rows' values are ephem.api.batch's to judge."""
    if content_type.split(";")[0].strip().lower() == "text/csv":
        return csv_batch_rows(raw), None
    try:
        doc = orjson.loads(raw)
    except orjson.JSONDecodeError as exc:
        raise InvalidInputError("body", f"not JSON: {exc}") from None
    repeated = first_duplicate(raw)     # orjson keeps the last of a key given twice: the page's upload is refused
    if repeated is not None:
        raise InvalidInputError(repeated[0], duplicate_reason(repeated[1]))
    if isinstance(doc, dict):
        extra = sorted(set(doc) - {"rows", "history"})
        if extra:     # a misspelt "history" would otherwise be dropped without a word
            raise InvalidInputError(extra[0], f"not JSON of a batch: unknown key {extra[0]!r}; the body is an array "
                                    "of rows or {rows, history}")
        return doc.get("rows"), doc.get("history")
    return doc, None


def csv_batch_rows(raw: bytes) -> list[dict]:
    """CSV rows as {column: text}: every line with as many cells as the header (a surplus or a missing cell
    cannot be matched to its column: the request is refused naming the row and its line, as ephem batch refuses
    the file). A cell that is not UTF-8 is its raw bytes, which ephem.api.batch makes its row's error; a UTF-8
    byte-order mark is dropped."""
    why = "not CSV with a header of column names"
    reader = csv.reader(io.StringIO(raw.decode("utf-8-sig", errors="surrogateescape"), newline=""))
    rows: list[dict] = []
    try:
        header = next(reader, None)
        if header is None:
            return rows
        if not all(_utf8(h) for h in header):
            raise InvalidInputError("body", f"{why}: the header line is not UTF-8 text")
        twice = sorted({h for h in header if header.count(h) > 1})
        if twice:
            raise InvalidInputError(twice[0], f"{why}: the header has the column {twice[0]!r} more than once")
        for cells in reader:
            if not cells:       # a blank line
                continue
            if len(cells) != len(header):
                raise InvalidInputError(f"rows[{len(rows)}]", f"{why}: line {reader.line_num} has {len(cells)} "
                                        f"cell{'s' if len(cells) != 1 else ''} for the header's {len(header)} "
                                        "columns")
            rows.append({h: c if _utf8(c) else c.encode("utf-8", "surrogateescape") for h, c in zip(header, cells)})
    except csv.Error as exc:
        raise InvalidInputError(f"rows[{len(rows)}]", f"{why}: line {reader.line_num}: {exc}") from None
    return rows


def _utf8(text: str) -> bool:
    """Whether a cell decoded with surrogateescape was UTF-8 (no escaped byte in it)."""
    try:
        text.encode("utf-8")
    except UnicodeEncodeError:
        return False
    return True
