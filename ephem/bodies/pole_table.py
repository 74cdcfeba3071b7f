"""The pole/period table of ``ephem catalogue import``, read into rows.

docs/catalogue_import.md; each row read into
:class:`~ephem.bodies.import_records.ImportedPole` rows.

Pole/period table: CSV with columns ``name, pole_ra_deg, pole_dec_deg, rotation_period_hours`` and either
``dynamical_ellipticity`` or ``moment_a, moment_b, moment_c`` (or both: H_d then overrides the moments, as
in the catalogue), optional ``pole_epoch_jd_tdb`` (default J2000), ``kind``, ``naif_id``, and a
``<column>_sigma`` (1 sigma, same unit) beside any numeric column. Lines starting with ``#`` are comments.

Every error names the file, the line and the column; the values are checked as the catalogue checks them when
the dataset is built (:mod:`ephem.bodies.importer`). The function is pure.
"""
from __future__ import annotations

import re

from .import_records import (NO_UNCERTAINTY, CatalogueImportError, ImportedPole, Value, csv_rows, no_duplicates,
                             number, sigma)

POLE_REQUIRED = ("name", "pole_ra_deg", "pole_dec_deg", "rotation_period_hours")
POLE_NUMERIC = ("pole_ra_deg", "pole_dec_deg", "pole_epoch_jd_tdb", "rotation_period_hours",
                "dynamical_ellipticity", "moment_a", "moment_b", "moment_c")
POLE_OPTIONAL = ("pole_epoch_jd_tdb", "dynamical_ellipticity", "moment_a", "moment_b", "moment_c", "kind", "naif_id")
POLE_UNITS = {"pole_ra_deg": "deg", "pole_dec_deg": "deg", "pole_epoch_jd_tdb": "d", "rotation_period_hours": "h",
              "dynamical_ellipticity": "", "moment_a": "", "moment_b": "", "moment_c": ""}
POLE_COLUMNS = POLE_REQUIRED + POLE_OPTIONAL + tuple(f"{c}_sigma" for c in POLE_NUMERIC if c != "pole_epoch_jd_tdb")
KINDS = ("asteroid", "dwarf_planet", "planet", "moon")   # data/catalogue/SCHEMA.md


def parse_poles(text: str, file: str) -> list[ImportedPole]:
    """The rows of a pole/period table (see the module's docstring)."""
    def check(header, hline):
        for col in POLE_REQUIRED:
            if col not in header:
                raise CatalogueImportError(file, hline, col, "missing column; a pole table needs "
                                           f"{', '.join(POLE_REQUIRED)} and dynamical_ellipticity or moment_a, "
                                           "moment_b, moment_c")
        for col in header:
            if col not in POLE_COLUMNS:
                raise CatalogueImportError(file, hline, col, f"unknown column; known: {', '.join(POLE_COLUMNS)}")
        moments = [c for c in ("moment_a", "moment_b", "moment_c") if c in header]
        if moments and len(moments) != 3:
            raise CatalogueImportError(file, hline, "moment_a, moment_b, moment_c", "give all three columns or none")
        if not moments and "dynamical_ellipticity" not in header:
            raise CatalogueImportError(file, hline, "dynamical_ellipticity", "missing column; give dynamical_ellipticity "
                                       "or moment_a, moment_b, moment_c")
    header, hline, rows = csv_rows(text, file, check)
    out = []
    for lineno, row in rows:
        name = row["name"]
        if not name:
            raise CatalogueImportError(file, lineno, "name", "empty")
        values = {}
        for col in POLE_NUMERIC:
            cell = row.get(col, "")
            if cell == "":
                if col in POLE_REQUIRED:
                    raise CatalogueImportError(file, lineno, col, "empty", name)
                if row.get(f"{col}_sigma"):
                    raise CatalogueImportError(file, lineno, f"{col}_sigma", f"given without {col}", name)
                continue
            v = number(cell, file, lineno, col, name)
            if col == "pole_epoch_jd_tdb":
                values[col] = Value(v, "d", None, "JD TDB")
                continue
            unc = sigma(row.get(f"{col}_sigma"), file, lineno, f"{col}_sigma", name)
            values[col] = Value(v, POLE_UNITS[col], unc, None if unc is not None else NO_UNCERTAINTY)
        given = [c for c in ("moment_a", "moment_b", "moment_c") if c in values]
        if given and len(given) != 3:
            raise CatalogueImportError(file, lineno, "moment_a, moment_b, moment_c", "give all three or none", name)
        if not given and "dynamical_ellipticity" not in values:
            raise CatalogueImportError(file, lineno, "dynamical_ellipticity",
                                       "empty; give dynamical_ellipticity or moment_a, moment_b, moment_c", name)
        kind = row.get("kind") or "asteroid"
        if kind not in KINDS:
            raise CatalogueImportError(file, lineno, "kind", f"must be one of {', '.join(KINDS)}, got {kind!r}", name)
        naif = row.get("naif_id") or None
        if naif is not None:
            if not re.fullmatch(r"-?\d+", naif):
                raise CatalogueImportError(file, lineno, "naif_id", f"must be an integer, got {naif!r}", name)
            naif = int(naif)
        out.append(ImportedPole(name, values, kind, naif, file, lineno))
    if not out:
        raise CatalogueImportError(file, None, "poles", "no rows found")
    no_duplicates([(p.name, p.line) for p in out], file)
    return out


__all__ = ["parse_poles"]
