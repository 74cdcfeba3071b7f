"""Bring your own data: a dataset built from a user's orbit file and pole/period table (docs/catalogue_import.md).

The orbit file is read by :mod:`ephem.bodies.orbit_files` (MPCORB, SBDB JSON, SBDB CSV), the pole/period
table by :mod:`ephem.bodies.pole_table`, into the records of :mod:`ephem.bodies.import_records`; here the two
are joined, written as a dataset's TOML and validated, and the file is written.

Bodies are joined by name, case-insensitively (an MPC record also answers to its number and its full
readable designation, "(1) Ceres"). Every body is validated by the catalogue's own checks
(:func:`ephem.bodies.catalogue.parse_catalogue` on the TOML written), and every error names the file, the line and
the field (:class:`~ephem.bodies.import_records.CatalogueImportError`). Nothing is fetched from the network.

Everything but :func:`import_catalogue` (which reads the two files and writes the dataset) is a pure function
of its arguments.
"""
from __future__ import annotations

import datetime as _dt
import hashlib
import json
import os
import re
from dataclasses import dataclass
from pathlib import Path

from .catalogue import Catalogue, load_catalogue, parse_catalogue
from .datasets import DATASET_NAME, shipped_datasets, user_catalogue_dir
from ..base.errors import InvalidInputError
from .import_records import CatalogueImportError, ImportedOrbit, ImportedPole, Value
from .orbit_files import FORMATS, ORBIT_KEYS, detect_format, parse_orbits
from .pole_table import parse_poles


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
                raise CatalogueImportError(o.file, o.line, o.labels.get(ORBIT_KEYS.get(key, key), exc.field),
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
    here as well). An existing dataset of that name is replaced only with ``force``.

    Parameters
    ----------
    orbits : str or Path
        The orbit file: MPCORB, an SBDB JSON answer or an SBDB CSV export (a in au, angles in degrees, epochs as
        the file gives them).
    poles : str or Path
        The pole/period table (CSV): each body's name, spin pole (``pole_ra_deg``, ``pole_dec_deg``: degrees,
        ICRF), rotation period (hours) and what else the table may give (docs/catalogue_import.md).
    name : str
        The dataset's name: a letter or digit, then letters, digits, "_" or "-" (at most 64), not a shipped
        dataset's (any case).
    fmt : str or None
        The orbit file's format, "mpcorb", "sbdb-json" or "sbdb-csv"; None: detected from its content and name.
    skip_unmatched : bool
        Skip the bodies found in one file but not the other (listed in the result) instead of refusing the import.
    force : bool
        Replace an existing dataset of that name.
    directory : str, Path or None
        Where to write ``NAME.toml``; None: :func:`ephem.bodies.datasets.user_catalogue_dir`.
    today : str or None
        The import's date written in the dataset (ISO 8601, ``YYYY-MM-DD``); None: today's (a test fixes it).

    Returns
    -------
    ImportResult
        The file written (``path``), the dataset as loaded (``catalogue``), the bodies skipped (``skipped``) and
        whether a dataset was replaced (``replaced``).
    """
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


__all__ = ["BuiltDataset", "ImportResult", "build_dataset", "import_catalogue", "check_dataset_name"]
