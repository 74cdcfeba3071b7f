"""What ``ephem catalogue import`` reads from a user's files: its records, and the error naming where.

docs/catalogue_import.md. The records of an orbit
file (:class:`ImportedOrbit`) and of a pole/period table (:class:`ImportedPole`), each number as read
(:class:`Value`), and the error that names the file, the line and the field (:class:`CatalogueImportError`).

The readers both kinds of file share stand here too: a number and its 1-sigma uncertainty (:func:`number`,
:func:`sigma`), the rows of a CSV (:func:`csv_rows`), a name given twice (:func:`no_duplicates`). The files
are read by :mod:`ephem.bodies.orbit_files` and :mod:`ephem.bodies.pole_table`; the dataset is built by
:mod:`ephem.bodies.importer`.
"""
from __future__ import annotations

import csv
import io
import math
from dataclasses import dataclass, field

from .catalogue import Orbit
from ..base.errors import InvalidInputError

#: the note of an imported value given without an uncertainty
NO_UNCERTAINTY = "no uncertainty given in the import"


class CatalogueImportError(InvalidInputError):
    """A bad import file: the message reads ``FILE:LINE: FIELD: why`` (``FILE: FIELD: why`` without a line)."""

    def __init__(self, file: str, line: int | None, field: str, reason: str, body: str | None = None):
        super().__init__(field, reason, body)
        self.file, self.line = file, line
        where = f"{file}:{line}" if line is not None else file
        self.args = (f"{where}: {field}: {reason}" + (f" (body {body})" if body else ""),)

    def __str__(self) -> str:
        return self.args[0]


@dataclass(frozen=True)
class Value:
    """One imported number, as written to the dataset: value, unit, 1-sigma uncertainty or None, note."""

    value: float
    unit: str
    uncertainty: float | None = None
    note: str | None = None


@dataclass(frozen=True)
class ImportedOrbit:
    """One orbit record: the validated :class:`Orbit`, the values as read, where it was read."""

    name: str
    aliases: tuple[str, ...]
    orbit: Orbit
    values: dict            # catalogue key (a, e, i, node, peri, mean_anomaly, epoch) -> Value
    file: str
    line: int
    labels: dict = field(default_factory=dict, repr=False)   # Orbit field -> the file's name for it


@dataclass(frozen=True)
class ImportedPole:
    """One row of the pole/period table."""

    name: str
    values: dict            # column -> Value (pole_ra_deg, ..., moment_c)
    kind: str
    naif_id: int | None
    file: str
    line: int


def number(text: str, file: str, line: int, label: str, body: str | None = None) -> float:
    """The finite number ``text`` reads as, else :class:`CatalogueImportError` naming ``label``."""
    try:
        value = float(text.strip())
    except ValueError:
        raise CatalogueImportError(file, line, label, f"not a number: {text.strip()!r}", body) from None
    if not math.isfinite(value):
        raise CatalogueImportError(file, line, label, f"must be a finite number, got {text.strip()!r}", body)
    return value


def sigma(text, file: str, line: int, label: str, body: str | None) -> float | None:
    """The 1-sigma uncertainty ``text`` reads as (>= 0), or None for an empty cell."""
    if text is None or str(text).strip() == "":
        return None
    value = number(str(text), file, line, label, body)
    if value < 0:
        raise CatalogueImportError(file, line, label, f"an uncertainty must be >= 0, got {value}", body)
    return value


def csv_rows(text: str, file: str, check_header=None):
    """(header, its line number, [(line number, row)]) of a CSV text; blank lines and lines starting with # are
    skipped; ``check_header(header, line)`` runs before the rows are read."""
    kept = [(k + 1, ln) for k, ln in enumerate(text.splitlines()) if ln.strip() and not ln.lstrip().startswith("#")]
    if not kept:
        raise CatalogueImportError(file, None, "header", "the file has no header line")
    rows = list(csv.reader(io.StringIO("\n".join(ln for _, ln in kept))))
    header = [h.strip() for h in rows[0]]
    dup = sorted({h for h in header if header.count(h) > 1})
    if dup:
        raise CatalogueImportError(file, kept[0][0], "header", f"column {dup[0]!r} appears twice")
    if check_header is not None:
        check_header(header, kept[0][0])
    body = []
    for (lineno, _), row in zip(kept[1:], rows[1:]):
        if len(row) != len(header):
            raise CatalogueImportError(file, lineno, "row", f"{len(row)} fields, the header has {len(header)}")
        body.append((lineno, dict(zip(header, (c.strip() for c in row)))))
    return header, kept[0][0], body


def no_duplicates(named: list[tuple[str, int]], file: str) -> None:
    """:class:`CatalogueImportError` at the second of two (name, line) giving one name (in any case)."""
    seen: dict[str, int] = {}
    for name, line in named:
        if name.lower() in seen:
            raise CatalogueImportError(file, line, "name", f"{name!r} appears twice (also line {seen[name.lower()]})")
        seen[name.lower()] = line


__all__ = ["CatalogueImportError", "ImportedOrbit", "ImportedPole"]
