"""The orbit files of ``ephem catalogue import`` (MPCORB, JPL SBDB JSON or CSV), read into records.

docs/catalogue_import.md; each read into
:class:`~ephem.bodies.import_records.ImportedOrbit` records.

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

:func:`detect_format` tells the three apart from the content; :func:`parse_orbits` reads any of them. Every
orbit is validated by the catalogue's own :class:`~ephem.bodies.catalogue.Orbit`, and every error names the
file, the line and the field. Nothing is fetched from the network; every function is pure.
"""
from __future__ import annotations

import datetime as _dt
import json
import math
import re

from .catalogue import Orbit
from ..base.errors import InvalidInputError
from .import_records import (NO_UNCERTAINTY, CatalogueImportError, ImportedOrbit, Value, csv_rows, no_duplicates,
                             number, sigma)

FORMATS = ("mpcorb", "sbdb-json", "sbdb-csv")
#: Gauss' gravitational constant (rad/day): the MPC's mean daily motion n = k a^-3/2
GAUSS_K = 0.01720209895


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
#: Orbit field -> catalogue key (the file's name for a field an Orbit check names: ImportedOrbit.labels)
ORBIT_KEYS = {"a_au": "a", "e": "e", "i_deg": "i", "node_deg": "node", "peri_deg": "peri",
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
        label = labels.get(ORBIT_KEYS.get(key, key), exc.field)
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
            v = number(cut(key), file, lineno, labels[key], name)
            values[key] = Value(v, _UNITS[key], None, NO_UNCERTAINTY)
        values["a"] = Value(values["a"].value, "AU", None,
                            f"MPCORB-layout record {packed!r} ({' '.join(cut('name').split()) or name}), line {lineno}"
                            + (f", orbit reference {ref}" if ref else "") + f"; {NO_UNCERTAINTY}")
        values["epoch"] = Value(julian_day(y, mo, d), "d", None,
                                f"JD TT (MPC packed epoch {epoch_text.strip()} = {y}-{mo:02d}-{d:02d}.0 TT), stored as "
                                "JD TDB: TT - TDB < 2 ms, ignored")
        orbit = _make_orbit(values, name, file, lineno, labels)
        n = number(cut("n"), file, lineno, _MPCORB["n"][2], name)
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
        v = number(str(elements[el]), file, line, labels[key], name)
        unc = sigma(sigmas.get(el), file, line, f"sigma_{el}", name)
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


SBDB_CSV_COLUMNS = ("full_name", "e", "a", "i", "om", "w", "ma", "epoch")


def parse_sbdb_csv(text: str, file: str) -> list[ImportedOrbit]:
    """The orbits of an SBDB query CSV export (see the module's docstring)."""
    def check(header, hline):
        for col in SBDB_CSV_COLUMNS:
            if col not in header:
                raise CatalogueImportError(file, hline, col, f"missing column; an SBDB CSV needs "
                                           f"{','.join(SBDB_CSV_COLUMNS)}")

    header, hline, rows = csv_rows(text, file, check)
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
    no_duplicates([(o.name, o.line) for o in orbits], file)
    return orbits


__all__ = ["FORMATS", "parse_mpcorb", "parse_sbdb_json", "parse_sbdb_csv", "parse_orbits", "detect_format",
           "unpack_epoch", "unpack_designation", "julian_day"]
