"""Bring your own data: a dataset built from a user's orbit file and pole/period table (docs/catalogue_import.md).

Orbit files, in the formats users already have (heliocentric osculating elements, ecliptic and equinox J2000):

* ``mpcorb``: the Minor Planet Center's MPCORB.DAT one-line layout (also NEA.txt and the MPC's other
  exports in that layout), read by columns as the MPC documents them
  (minorplanetcenter.net/iau/info/MPOrbitFormat.html; the same column slices as
  ``skyfield.data.mpc``, whose parser needs pandas, which ephem does without). A header ending in a line
  of dashes (MPCORB.DAT's) is skipped. Epochs are the packed ``.0 TT`` epochs of the MPC; they are
  stored as JD TDB, TT - TDB being below 2 ms.
* ``sbdb-json``: the JSON of JPL's SBDB API (``sbdb.api?sstr=...``; one object or a list of them):
  ``object.fullname`` and ``orbit.epoch`` (JD TDB) with ``orbit.elements`` e, a, i, om, w, ma (their
  ``sigma`` becomes the uncertainty).
* ``sbdb-csv``: the CSV export of the SBDB query (``sbdb_query.api``) with columns
  ``full_name,e,a,i,om,w,ma,epoch`` (epoch as JD TDB) and optional ``sigma_e, sigma_a, sigma_i, sigma_om,
  sigma_w, sigma_ma``; other columns are ignored.

Pole/period table: CSV with columns ``name, pole_ra_deg, pole_dec_deg, rotation_period_hours`` and either
``dynamical_ellipticity`` or ``moment_a, moment_b, moment_c`` (or both: H_d then overrides the moments, as
in the catalogue), optional ``pole_epoch_jd_tdb`` (default J2000), ``kind``, ``naif_id``, and a
``<column>_sigma`` (1 sigma, same unit) beside any numeric column. Lines starting with ``#`` are comments.

Bodies are joined by name, case-insensitively (an MPC record also answers to its number and its full
readable designation, "(1) Ceres"). Every body is validated by the catalogue's own checks
(:func:`ephem.bodies.catalogue.parse_catalogue` on the TOML written), and every error names the file, the line and
the field (:class:`CatalogueImportError`). Nothing is fetched from the network.

Everything but :func:`import_catalogue` (which reads the two files and writes the dataset) is a pure function
of its arguments.
"""
from __future__ import annotations

import csv
import datetime as _dt
import hashlib
import io
import json
import math
import os
import re
from dataclasses import dataclass, field
from pathlib import Path

from .catalogue import Catalogue, Orbit, load_catalogue, parse_catalogue
from .datasets import DATASET_NAME, shipped_datasets, user_catalogue_dir
from ..base.errors import InvalidInputError

FORMATS = ("mpcorb", "sbdb-json", "sbdb-csv")
NO_UNCERTAINTY = "no uncertainty given in the import"
#: Gauss' gravitational constant (rad/day): the MPC's mean daily motion n = k a^-3/2
GAUSS_K = 0.01720209895


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


def _number(text: str, file: str, line: int, label: str, body: str | None = None) -> float:
    try:
        value = float(text.strip())
    except ValueError:
        raise CatalogueImportError(file, line, label, f"not a number: {text.strip()!r}", body) from None
    if not math.isfinite(value):
        raise CatalogueImportError(file, line, label, f"must be a finite number, got {text.strip()!r}", body)
    return value


def _sigma(text, file: str, line: int, label: str, body: str | None) -> float | None:
    if text is None or str(text).strip() == "":
        return None
    value = _number(str(text), file, line, label, body)
    if value < 0:
        raise CatalogueImportError(file, line, label, f"an uncertainty must be >= 0, got {value}", body)
    return value


def julian_day(year: int, month: int, day: float) -> float:
    """Julian day of a Gregorian calendar date at 0h plus ``day``'s fraction (Meeus 1998, eq. 7.1)."""
    if month <= 2:
        year, month = year - 1, month + 12
    a = year // 100
    b = 2 - a + a // 4
    return math.floor(365.25 * (year + 4716)) + math.floor(30.6001 * (month + 1)) + day + b - 1524.5


_CENTURIES = {"I": 1800, "J": 1900, "K": 2000}


def _packed_digit(c: str) -> int:
    """1-9, then A = 10 ... V = 31 (the MPC's packed months and days)."""
    if c.isdigit() and c != "0":
        return int(c)
    if "A" <= c <= "V":
        return ord(c) - ord("A") + 10
    raise ValueError(c)


def unpack_epoch(packed: str) -> tuple[int, int, int]:
    """(year, month, day) of an MPC packed epoch: ``K25BL`` = 2025 Nov 21 (.0 TT). ValueError if malformed."""
    packed = packed.strip()
    if len(packed) != 5 or packed[0] not in _CENTURIES or not packed[1:3].isdigit():
        raise ValueError(packed)
    year = _CENTURIES[packed[0]] + int(packed[1:3])
    month, day = _packed_digit(packed[3]), _packed_digit(packed[4])
    if not 1 <= month <= 12:
        raise ValueError(packed)
    try:
        _dt.date(year, month, day)
    except ValueError:
        raise ValueError(packed) from None
    return year, month, day


def _cycle(two: str) -> int:
    first = two[0]
    tens = int(first) if first.isdigit() else (ord(first) - ord("A") + 10 if first.isupper()
                                               else ord(first) - ord("a") + 36)
    return tens * 10 + int(two[1])


def unpack_designation(packed: str) -> str:
    """The readable form of an MPC packed designation: ``00001`` -> "1", ``A0345`` -> "100345",
    ``K07Tf8A`` -> "2007 TA418"; anything else is returned stripped."""
    p = packed.strip()
    try:
        if re.fullmatch(r"[0-9A-Za-z]\d{4}", p):
            head = p[0]
            hi = int(head) if head.isdigit() else (ord(head) - ord("A") + 10 if head.isupper()
                                                   else ord(head) - ord("a") + 36)
            return str(hi * 10000 + int(p[1:]))
        if re.fullmatch(r"[IJK]\d{2}[A-Z][0-9A-Za-z]\d[A-Z]", p):
            year = _CENTURIES[p[0]] + int(p[1:3])
            n = _cycle(p[4:6])
            return f"{year} {p[3]}{p[6]}{n if n else ''}"
    except (ValueError, KeyError):
        pass
    return p


# ----------------------------------------------------------------------------------------- orbit files

#: MPCORB fields: (key, 1-based first column, last column, label)
MPCORB_FIELDS = (
    ("designation_packed", 1, 7, "designation (columns 1-7)"),
    ("epoch_packed", 21, 25, "epoch (columns 21-25)"),
    ("mean_anomaly", 27, 35, "mean anomaly (columns 27-35)"),
    ("peri", 38, 46, "argument of perihelion (columns 38-46)"),
    ("node", 49, 57, "longitude of the ascending node (columns 49-57)"),
    ("i", 60, 68, "inclination (columns 60-68)"),
    ("e", 71, 79, "eccentricity (columns 71-79)"),
    ("n", 81, 91, "mean daily motion (columns 81-91)"),
    ("a", 93, 103, "semi-major axis (columns 93-103)"),
    ("reference", 108, 116, "reference (columns 108-116)"),
    ("name", 167, 194, "readable designation (columns 167-194)"),
)
_MPCORB = {k: (a, b, label) for k, a, b, label in MPCORB_FIELDS}
#: columns that separate the fields of the elements and must be blank (1-based)
_MPCORB_BLANKS = (8, 20, 26, 36, 37, 47, 48, 58, 59, 69, 70, 80, 92)
_ORBIT_KEYS = {"a_au": "a", "e": "e", "i_deg": "i", "node_deg": "node", "peri_deg": "peri",
               "mean_anomaly_deg": "mean_anomaly", "epoch_jd_tdb": "epoch"}
_UNITS = {"a": "AU", "e": "", "i": "deg", "node": "deg", "peri": "deg", "mean_anomaly": "deg", "epoch": "d"}


def _make_orbit(values: dict, name: str, file: str, line: int, labels: dict) -> Orbit:
    """The validated :class:`Orbit` of ``values`` (catalogue keys); an error names the file's field."""
    try:
        return Orbit(a_au=values["a"].value, e=values["e"].value, i_deg=values["i"].value,
                     node_deg=values["node"].value, peri_deg=values["peri"].value,
                     mean_anomaly_deg=values["mean_anomaly"].value, epoch_jd_tdb=values["epoch"].value, body=name)
    except InvalidInputError as exc:
        key = exc.field.removeprefix("orbit.")
        label = labels.get(_ORBIT_KEYS.get(key, key), exc.field)
        raise CatalogueImportError(file, line, label, exc.reason, name) from None


def _mpc_name(readable: str, packed: str) -> tuple[str, tuple[str, ...]]:
    """Display name and aliases of an MPC record: "(1) Ceres" -> "Ceres" (aliases "(1) Ceres", "1")."""
    readable = " ".join(readable.split())
    # a record copied with its spaces squashed has the date of last observation (YYYYMMDD) in these columns
    readable = re.sub(r"\s+\d{8}$", "", readable)
    unpacked = unpack_designation(packed)
    m = re.fullmatch(r"\((\d+)\)\s*(.*)", readable)
    if m:
        number, rest = m.group(1), m.group(2).strip()
        name = rest or number
        return name, tuple(dict.fromkeys([name, readable, number, packed.strip()]))
    name = readable or unpacked
    return name, tuple(dict.fromkeys([name, unpacked, packed.strip()]))


def parse_mpcorb(text: str, file: str) -> list[ImportedOrbit]:
    """The orbits of an MPCORB-layout file (see the module's docstring)."""
    lines = text.splitlines()
    start = 0
    for k, ln in enumerate(lines[:200]):
        if re.fullmatch(r"-{20,}\s*", ln):       # MPCORB.DAT's header ends in a line of dashes
            start = k + 1
            break
    out = []
    for k in range(start, len(lines)):
        raw, lineno = lines[k].rstrip("\r\n"), k + 1
        if not raw.strip() or raw.lstrip().startswith("#"):
            continue
        if len(raw) < 103:
            raise CatalogueImportError(file, lineno, "line", f"{len(raw)} characters: too short for the MPCORB layout "
                                       "(the elements end at column 103)")
        for col in _MPCORB_BLANKS:
            if raw[col - 1] != " ":
                raise CatalogueImportError(file, lineno, f"column {col}", f"should be blank in the MPCORB layout, "
                                           f"found {raw[col - 1]!r}: are the columns aligned as the MPC's?")

        def cut(key: str) -> str:
            a, b, _ = _MPCORB[key]
            return raw[a - 1:b]

        packed = cut("designation_packed").strip()
        if not packed:
            raise CatalogueImportError(file, lineno, _MPCORB["designation_packed"][2], "empty")
        name, aliases = _mpc_name(cut("name"), packed)
        labels = {key: _MPCORB[key][2] for key in ("a", "e", "i", "node", "peri", "mean_anomaly")}
        labels["epoch"] = _MPCORB["epoch_packed"][2]
        epoch_text = cut("epoch_packed")
        try:
            y, mo, d = unpack_epoch(epoch_text)
        except ValueError:
            raise CatalogueImportError(file, lineno, labels["epoch"], f"not an MPC packed epoch: {epoch_text.strip()!r} "
                                       "(expected e.g. K25BL = 2025 Nov 21)", name) from None
        ref = cut("reference").strip()
        values = {}
        for key in ("a", "e", "i", "node", "peri", "mean_anomaly"):
            v = _number(cut(key), file, lineno, labels[key], name)
            values[key] = Value(v, _UNITS[key], None, NO_UNCERTAINTY)
        values["a"] = Value(values["a"].value, "AU", None,
                            f"MPCORB-layout record {packed!r} ({' '.join(cut('name').split()) or name}), line {lineno}"
                            + (f", orbit reference {ref}" if ref else "") + f"; {NO_UNCERTAINTY}")
        values["epoch"] = Value(julian_day(y, mo, d), "d", None,
                                f"JD TT (MPC packed epoch {epoch_text.strip()} = {y}-{mo:02d}-{d:02d}.0 TT), stored as "
                                "JD TDB: TT - TDB < 2 ms, ignored")
        orbit = _make_orbit(values, name, file, lineno, labels)
        n = _number(cut("n"), file, lineno, _MPCORB["n"][2], name)
        n_kepler = math.degrees(GAUSS_K / orbit.a_au ** 1.5)
        if abs(n - n_kepler) > 1e-3 * n_kepler:
            raise CatalogueImportError(file, lineno, _MPCORB["n"][2],
                                       f"n = {n} deg/d does not follow from a = {orbit.a_au} AU (Kepler's third law: "
                                       f"{n_kepler:.8f} deg/d): are the columns aligned as the MPC's?", name)
        out.append(ImportedOrbit(name, aliases, orbit, values, file, lineno, labels))
    if not out:
        raise CatalogueImportError(file, None, "orbits", "no orbit records found")
    return out


def _sbdb_name(fullname: str) -> tuple[str, tuple[str, ...]]:
    """"1 Ceres (A801 AA)" -> "Ceres" (aliases the full name, "1 Ceres", "1", "A801 AA"); "(2015 AB)" -> "2015 AB"."""
    full = " ".join(str(fullname).split())
    m = re.fullmatch(r"(\d+)\s+(.+?)(?:\s+\(([^()]+)\))?", full)
    if m:
        number, name, prov = m.groups()
        return name, tuple(dict.fromkeys(x for x in (name, full, f"{number} {name}", number, prov) if x))
    m = re.fullmatch(r"\(([^()]+)\)", full)
    if m:
        return m.group(1), (m.group(1), full)
    return full, (full,)


#: SBDB element names -> catalogue keys
SBDB_ELEMENTS = {"a": "a", "e": "e", "i": "i", "om": "node", "w": "peri", "ma": "mean_anomaly"}


def _sbdb_record(name: str, aliases, elements: dict, sigmas: dict, epoch_text, file: str, line: int,
                 labels: dict, epoch_label: str, what: str) -> ImportedOrbit:
    values = {}
    for el, key in SBDB_ELEMENTS.items():
        v = _number(str(elements[el]), file, line, labels[key], name)
        unc = _sigma(sigmas.get(el), file, line, f"sigma_{el}", name)
        values[key] = Value(v, _UNITS[key], unc, None if unc is not None else NO_UNCERTAINTY)
    try:
        jd = float(str(epoch_text).strip())
        if not math.isfinite(jd):
            raise ValueError
    except ValueError:
        raise CatalogueImportError(file, line, epoch_label, f"not a Julian date (TDB): {str(epoch_text).strip()!r}",
                                   name) from None
    values["epoch"] = Value(jd, "d", None, f"JD TDB ({what}, {file} line {line})")
    orbit = _make_orbit(values, name, file, line, labels)
    return ImportedOrbit(name, tuple(aliases), orbit, values, file, line, labels)


def parse_sbdb_json(text: str, file: str) -> list[ImportedOrbit]:
    """The orbits of SBDB API JSON (one object or a list of them). Lines are those of each object's start."""
    try:
        doc = json.loads(text)
    except json.JSONDecodeError as exc:
        raise CatalogueImportError(file, exc.lineno, "json", f"not valid JSON: {exc.msg}") from None
    records = doc if isinstance(doc, list) else [doc]
    # line of each record: where its "object" key appears (good enough to find it in the file)
    starts = [m.start() for m in re.finditer(r'"object"\s*:', text)]
    out = []
    for k, rec in enumerate(records):
        line = text.count("\n", 0, starts[k]) + 1 if k < len(starts) else None
        where = f"[{k}]." if isinstance(doc, list) else ""
        if not isinstance(rec, dict):
            raise CatalogueImportError(file, line, f"{where}".rstrip(".") or "json", "expected an SBDB API object")
        if "message" in rec and "orbit" not in rec:
            raise CatalogueImportError(file, line, f"{where}message", f"the SBDB answered no orbit: {rec['message']!r}")
        obj, orb = rec.get("object"), rec.get("orbit")
        if not isinstance(obj, dict) or not obj.get("fullname"):
            raise CatalogueImportError(file, line, f"{where}object.fullname", "missing")
        name, aliases = _sbdb_name(obj["fullname"])
        aliases = tuple(dict.fromkeys([*aliases, *(str(obj[k]) for k in ("shortname", "des") if obj.get(k))]))
        if not isinstance(orb, dict):
            raise CatalogueImportError(file, line, f"{where}orbit", "missing", name)
        equinox = orb.get("equinox")
        if equinox not in (None, "J2000"):
            raise CatalogueImportError(file, line, f"{where}orbit.equinox", f"must be J2000, got {equinox!r}", name)
        elements, sigmas = {}, {}
        for el in orb.get("elements") or []:
            if isinstance(el, dict) and el.get("name") in SBDB_ELEMENTS:
                elements[el["name"]] = el.get("value")
                sigmas[el["name"]] = el.get("sigma")
        for el in SBDB_ELEMENTS:
            if elements.get(el) is None:
                raise CatalogueImportError(file, line, f"{where}orbit.elements.{el}", "missing", name)
        if orb.get("epoch") is None:
            raise CatalogueImportError(file, line, f"{where}orbit.epoch", "missing", name)
        labels = {key: f"{where}orbit.elements.{el}" for el, key in SBDB_ELEMENTS.items()}
        labels["epoch"] = f"{where}orbit.epoch"
        what = "SBDB API orbit" + (f" solution {orb['orbit_id']}" if orb.get("orbit_id") else "")
        out.append(_sbdb_record(name, aliases, elements, sigmas, orb["epoch"], file, line, labels,
                                labels["epoch"], what))
    if not out:
        raise CatalogueImportError(file, None, "orbits", "no orbit records found")
    return out


def _csv_rows(text: str, file: str, check_header=None):
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


SBDB_CSV_COLUMNS = ("full_name", "e", "a", "i", "om", "w", "ma", "epoch")


def parse_sbdb_csv(text: str, file: str) -> list[ImportedOrbit]:
    """The orbits of an SBDB query CSV export (see the module's docstring)."""
    def check(header, hline):
        for col in SBDB_CSV_COLUMNS:
            if col not in header:
                raise CatalogueImportError(file, hline, col, f"missing column; an SBDB CSV needs "
                                           f"{','.join(SBDB_CSV_COLUMNS)}")

    header, hline, rows = _csv_rows(text, file, check)
    out = []
    labels = {key: el for el, key in SBDB_ELEMENTS.items()}
    labels["epoch"] = "epoch"
    for lineno, row in rows:
        if not row["full_name"]:
            raise CatalogueImportError(file, lineno, "full_name", "empty")
        name, aliases = _sbdb_name(row["full_name"])
        for col in SBDB_CSV_COLUMNS[1:]:
            if row[col] == "":
                raise CatalogueImportError(file, lineno, col, "empty", name)
        sigmas = {el: row.get(f"sigma_{el}") for el in SBDB_ELEMENTS}
        out.append(_sbdb_record(name, aliases, {el: row[el] for el in SBDB_ELEMENTS}, sigmas, row["epoch"], file,
                                lineno, labels, "epoch", "SBDB query export"))
    if not out:
        raise CatalogueImportError(file, None, "orbits", "no orbit records found")
    return out


def detect_format(text: str, file: str) -> str:
    """The orbit file's format, from its content: JSON, a CSV with a full_name column, else MPCORB."""
    stripped = text.lstrip()
    if stripped.startswith(("{", "[")):
        return "sbdb-json"
    first = next((ln for ln in text.splitlines() if ln.strip() and not ln.lstrip().startswith("#")), "")
    if "full_name" in [c.strip().strip('"') for c in first.split(",")]:
        return "sbdb-csv"
    return "mpcorb"


def parse_orbits(text: str, file: str, fmt: str | None = None) -> list[ImportedOrbit]:
    """The orbits of ``text`` (the contents of ``file``) in format ``fmt`` (:data:`FORMATS`; None: detected)."""
    fmt = fmt or detect_format(text, file)
    if fmt not in FORMATS:
        raise InvalidInputError("format", f"must be one of {', '.join(FORMATS)}, got {fmt!r}")
    parser = {"mpcorb": parse_mpcorb, "sbdb-json": parse_sbdb_json, "sbdb-csv": parse_sbdb_csv}[fmt]
    orbits = parser(text, file)
    _no_duplicates([(o.name, o.line) for o in orbits], file)
    return orbits


def _no_duplicates(named: list[tuple[str, int]], file: str) -> None:
    seen: dict[str, int] = {}
    for name, line in named:
        if name.lower() in seen:
            raise CatalogueImportError(file, line, "name", f"{name!r} appears twice (also line {seen[name.lower()]})")
        seen[name.lower()] = line


# ------------------------------------------------------------------------------------------ pole table

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
    header, hline, rows = _csv_rows(text, file, check)
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
            v = _number(cell, file, lineno, col, name)
            if col == "pole_epoch_jd_tdb":
                values[col] = Value(v, "d", None, "JD TDB")
                continue
            unc = _sigma(row.get(f"{col}_sigma"), file, lineno, f"{col}_sigma", name)
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
    _no_duplicates([(p.name, p.line) for p in out], file)
    return out


# ------------------------------------------------------------------------------------ the dataset text

@dataclass(frozen=True)
class SourceFile:
    """An imported file as the dataset records it: its name, SHA-256, role and format."""

    key: str
    file: str
    sha256: str
    role: str
    format: str


def source_file(role: str, path: str | Path, data: bytes, fmt: str) -> SourceFile:
    name = Path(path).name
    return SourceFile(f"import:{role}:{name}", name, hashlib.sha256(data).hexdigest(), role, fmt)


def _toml_str(s: str) -> str:
    return json.dumps(s, ensure_ascii=False)     # a JSON string is a TOML basic string


def _toml_value(v: Value, source: str, extra_note: str | None = None) -> str:
    parts = [f"value = {v.value!r}", f"unit = {_toml_str(v.unit)}"]
    if v.uncertainty is not None:
        parts.append(f"uncertainty = {v.uncertainty!r}")
    parts.append(f"source = {_toml_str(source)}")
    note = "; ".join(x for x in (v.note, extra_note) if x)
    if note:
        parts.append(f"note = {_toml_str(note)}")
    return "{ " + ", ".join(parts) + " }"


def _body_toml(o: ImportedOrbit, p: ImportedPole, osrc: SourceFile, psrc: SourceFile) -> str:
    lines = ["[[body]]", f"name = {_toml_str(o.name)}"]
    if p.naif_id is not None:
        lines.append(f"naif_id = {p.naif_id}")
    lines += [f"kind = {_toml_str(p.kind)}", "", "[body.orbit]", 'center = "Sun"']
    for key in ("epoch", "a", "e", "i", "node", "peri", "mean_anomaly"):
        lines.append(f"{key} = {_toml_value(o.values[key], osrc.key)}")
    pv = p.values
    lines += ["", "[body.pole]", 'frame = "icrf"']
    if "pole_epoch_jd_tdb" in pv:
        lines.append(f"epoch = {_toml_value(pv['pole_epoch_jd_tdb'], psrc.key)}")
    lines.append(f"ra = {_toml_value(pv['pole_ra_deg'], psrc.key, f'{psrc.file} line {p.line}')}")
    lines.append(f"dec = {_toml_value(pv['pole_dec_deg'], psrc.key)}")
    lines += ["", "[body.rotation]", f"period = {_toml_value(pv['rotation_period_hours'], psrc.key)}",
              "", "[body.inertia]"]
    for col, key in (("moment_a", "A"), ("moment_b", "B"), ("moment_c", "C"),
                     ("dynamical_ellipticity", "dynamical_ellipticity")):
        if col in pv:
            lines.append(f"{key} = {_toml_value(pv[col], psrc.key)}")
    return "\n".join(lines) + "\n"


#: catalogue fields -> the pole table's columns (for errors the catalogue's checks raise)
_POLE_FIELDS = {"pole.ra": "pole_ra_deg", "pole.ra_deg": "pole_ra_deg", "pole.dec": "pole_dec_deg",
                "pole.dec_deg": "pole_dec_deg", "pole.epoch": "pole_epoch_jd_tdb",
                "pole.epoch_jd_tdb": "pole_epoch_jd_tdb", "rotation.period": "rotation_period_hours",
                "rotation_period_hours": "rotation_period_hours", "inertia.A": "moment_a", "moments.A": "moment_a",
                "inertia.B": "moment_b", "moments.B": "moment_b", "inertia.C": "moment_c", "moments.C": "moment_c",
                "inertia": "moment_a, moment_b, moment_c", "moments": "moment_a, moment_b, moment_c",
                "inertia.dynamical_ellipticity": "dynamical_ellipticity",
                "dynamical_ellipticity": "dynamical_ellipticity"}


def _match(orbits: list[ImportedOrbit], poles: list[ImportedPole], orbit_file: str, pole_file: str,
           skip_unmatched: bool) -> tuple[list[tuple[ImportedOrbit, ImportedPole]], list[str]]:
    index: dict[str, ImportedOrbit] = {}
    for o in orbits:
        for alias in o.aliases:
            index.setdefault(" ".join(alias.split()).lower(), o)
    pairs, used, skipped = [], set(), []
    for p in poles:
        o = index.get(" ".join(p.name.split()).lower())
        if o is None:
            if not skip_unmatched:
                raise CatalogueImportError(pole_file, p.line, "name", f"{p.name!r} has no orbit in {orbit_file} "
                                           "(names match case-insensitively; give --skip-unmatched to leave it out)")
            skipped.append(f"{p.name} ({pole_file} line {p.line}: no orbit)")
            continue
        if id(o) in used:
            raise CatalogueImportError(pole_file, p.line, "name", f"{p.name!r} names the orbit of {o.name!r} "
                                       f"({orbit_file} line {o.line}) that another row already took")
        used.add(id(o))
        pairs.append((o, p))
    for o in orbits:
        if id(o) not in used:
            if not skip_unmatched:
                raise CatalogueImportError(orbit_file, o.line, "name", f"{o.name!r} has no row in {pole_file} "
                                           "(names match case-insensitively; give --skip-unmatched to leave it out)")
            skipped.append(f"{o.name} ({orbit_file} line {o.line}: no pole)")
    if not pairs:
        raise CatalogueImportError(pole_file, None, "name", f"no body of {pole_file} has an orbit in {orbit_file}")
    return pairs, skipped


def check_dataset_name(name: str) -> None:
    """A name a user dataset may take: a plain file name, not a shipped dataset's (any case)."""
    if not isinstance(name, str) or not re.fullmatch(DATASET_NAME, name):
        raise InvalidInputError("name", f"a dataset name is a letter or digit then letters, digits, '_' or '-' "
                                f"(at most 64), got {name!r}")
    shipped = shipped_datasets()
    if name.lower() in (s.lower() for s in shipped):
        raise InvalidInputError("name", f"{name!r} is a shipped dataset ({', '.join(shipped)}): an imported dataset "
                                "may not shadow it; choose another name")


@dataclass(frozen=True)
class BuiltDataset:
    """The dataset's TOML text, the catalogue it parses to, the bodies left out (``--skip-unmatched``)."""

    name: str
    text: str
    catalogue: Catalogue
    skipped: tuple[str, ...]


def build_dataset(name: str, orbits: list[ImportedOrbit], poles: list[ImportedPole], orbit_src: SourceFile,
                  pole_src: SourceFile, skip_unmatched: bool = False, today: str | None = None) -> BuiltDataset:
    """The dataset TOML of the joined bodies, validated by :func:`ephem.bodies.catalogue.parse_catalogue`."""
    check_dataset_name(name)
    today = today or _dt.date.today().isoformat()
    pairs, skipped = _match(orbits, poles, orbit_src.file, pole_src.file, skip_unmatched)
    records = []
    for o, p in pairs:
        rec = _body_toml(o, p, orbit_src, pole_src)
        try:
            parse_catalogue(rec, name)
        except InvalidInputError as exc:
            if exc.field.startswith("orbit."):
                key = exc.field.removeprefix("orbit.")
                raise CatalogueImportError(o.file, o.line, o.labels.get(_ORBIT_KEYS.get(key, key), exc.field),
                                           exc.reason, o.name) from None
            raise CatalogueImportError(p.file, p.line, _POLE_FIELDS.get(exc.field, exc.field), exc.reason,
                                       o.name) from None
        records.append(rec)
    desc = (f"Imported on {today} by `ephem catalogue import` from {orbit_src.file} ({orbit_src.format}, sha256 "
            f"{orbit_src.sha256}) and {pole_src.file} (sha256 {pole_src.sha256}). Orbits: heliocentric osculating "
            "elements, ecliptic and equinox J2000" + (", MPC epochs in TT stored as TDB (TT - TDB < 2 ms)"
                                                      if orbit_src.format == "mpcorb" else ", epochs JD TDB")
            + ". Values without an uncertainty in the files carry the note 'no uncertainty given in the import'.")
    head = ["# Written by `ephem catalogue import` (ephem/bodies/importer.py); format: data/catalogue/SCHEMA.md.",
            "# The source keys name the imported files; [dataset.sources] records their SHA-256.", "",
            "[dataset]", f"name = {_toml_str(name)}", f"description = {_toml_str(desc)}",
            f"imported = {_toml_str(today)}"]
    if skipped:
        head.append(f"skipped = [{', '.join(_toml_str(s) for s in skipped)}]")
    for src in (orbit_src, pole_src):
        head += ["", f"[dataset.sources.{_toml_str(src.key)}]", f"file = {_toml_str(src.file)}",
                 f"sha256 = {_toml_str(src.sha256)}", f"role = {_toml_str(src.role)}",
                 f"format = {_toml_str(src.format)}", f"imported = {_toml_str(today)}"]
    text = "\n".join(head) + "\n\n" + "\n".join(records)
    catalogue = parse_catalogue(text, name)          # the whole dataset, as load_catalogue will read it
    return BuiltDataset(name, text, catalogue, tuple(skipped))


# ------------------------------------------------------------------------------------- files in, file out

@dataclass(frozen=True)
class ImportResult:
    path: Path
    catalogue: Catalogue
    skipped: tuple[str, ...]
    replaced: bool


def _read(path: Path, role: str) -> bytes:
    try:
        return path.read_bytes()
    except OSError as exc:
        raise InvalidInputError(role, f"cannot read {path}: {exc.strerror or exc}") from None


def _decode(data: bytes, path: Path) -> str:
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError:
        return data.decode("latin-1")      # MPC files are ASCII; a stray byte in a name should not stop the import


def import_catalogue(orbits: str | Path, poles: str | Path, name: str, fmt: str | None = None,
                     skip_unmatched: bool = False, force: bool = False, directory: str | Path | None = None,
                     today: str | None = None) -> ImportResult:
    """Read ``orbits`` and ``poles``, build and validate the dataset ``name``, and write it to ``directory``
    (default :func:`ephem.bodies.datasets.user_catalogue_dir`) as ``NAME.toml``; then ``load_catalogue(name)`` and
    every ``dataset=name`` see it (the catalogue cache is keyed by the file's modification time, and is cleared
    here as well). An existing dataset of that name is replaced only with ``force``."""
    check_dataset_name(name)
    if fmt is not None and fmt not in FORMATS:
        raise InvalidInputError("format", f"must be one of {', '.join(FORMATS)}, got {fmt!r}")
    target_dir = Path(directory) if directory is not None else user_catalogue_dir()
    if target_dir is None:
        raise InvalidInputError("name", "no user catalogue directory: set EPHEM_USER_CATALOGUE_DIR")
    target = target_dir / f"{name}.toml"
    existing = [p for p in (target_dir.glob("*.toml") if target_dir.is_dir() else ())
                if p.stem.lower() == name.lower()]
    if existing and not force:
        raise InvalidInputError("name", f"a dataset {existing[0].stem!r} already exists ({existing[0]}); give --force "
                                "to replace it")
    opath, ppath = Path(orbits), Path(poles)
    odata, pdata = _read(opath, "orbits"), _read(ppath, "poles")
    otext = _decode(odata, opath)
    fmt = fmt or detect_format(otext, opath.name)
    parsed_orbits = parse_orbits(otext, opath.name, fmt)
    parsed_poles = parse_poles(_decode(pdata, ppath), ppath.name)
    built = build_dataset(name, parsed_orbits, parsed_poles, source_file("orbits", opath, odata, fmt),
                          source_file("poles", ppath, pdata, "poles-csv"), skip_unmatched, today)
    target_dir.mkdir(parents=True, exist_ok=True)
    tmp = target_dir / f".{name}.toml.tmp{os.getpid()}"
    tmp.write_text(built.text, encoding="utf-8")
    for old in existing:
        if old.name != target.name:
            old.unlink()
    os.replace(tmp, target)
    load_catalogue.cache_clear()
    return ImportResult(target, built.catalogue, built.skipped, bool(existing))


__all__ = ["FORMATS", "CatalogueImportError", "ImportedOrbit", "ImportedPole", "BuiltDataset", "ImportResult",
           "parse_mpcorb", "parse_sbdb_json", "parse_sbdb_csv", "parse_orbits", "parse_poles", "detect_format",
           "build_dataset", "import_catalogue", "check_dataset_name", "unpack_epoch", "unpack_designation",
           "julian_day"]
