"""Answers as astropy tables: the one builder of the notebook's ``QTable`` and of the ECSV written out.

The ECSV is what the service and the
CLI write (astropy's Enhanced CSV, ``text/x-ecsv``).

Every table-shaped answer has one: the bodies list (a row per body), precession (one row), nutation (a row per
term), a track and the free motion (a row per epoch), a history (a row per epoch, in years) and a batch (a row
per input row). :func:`to_qtable` recognises the answer by its keys and builds the table:

- each column's unit from its key's suffix (:func:`ephem.base.units.unit_of`: ``_deg`` deg, ``_arcsec`` arcsec,
  ``_mas`` mas, ``_arcsec_per_year`` arcsec / yr, ``_days`` d, ``_years`` yr, ...), so that a column is a
  ``Quantity``; a dimensionless value (the eccentricity, H_d, a multiple) stays a plain column;
- ``jd_tdb`` as an astropy ``Time`` (format jd, scale tdb), which ECSV writes as its Julian date and
  ``QTable.read`` gives back as a ``Time``, to the same bits; the calendar dates beside it (``utc_iso``, ``tt_iso``,
  ``tdb_iso``) as text; a history's ``year`` (Julian years from J2000.0 TDB) as a Quantity in years;
- a description on every column; a value an answer leaves null as a masked entry;
- the answer's metadata in ``table.meta`` (ECSV's YAML header): the model, the estimate, the time scale, the body
  and dataset, the source (the request's URL or command), the version and the citations (the theory, and the
  catalogue's references for the body's values); the answer's other scalars there too.

:func:`to_ecsv` writes that table with astropy (``QTable.write(..., format="ascii.ecsv")``), after charging its cost
(:func:`ephem.theory.cost.serialised`: astropy's writer costs ~1.6 us a value, 50 times JSON's:
benchmarks/RESULTS_calendar.md).
"""
from __future__ import annotations

import io
import math
import re
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

import ephem
from ..base.budget import charge
from ..base.errors import EphemError, InvalidInputError
from ..base.units import unit_of
from ..bodies.catalogue import get_body, load_references
from ..orbit.lunar import DELAUNAY_NAMES
from ..theory import cost

if TYPE_CHECKING:       # astropy.table loads with the first table, not with this module
    from astropy.table import QTable

#: the media type of the ECSV the service answers
ECSV_MEDIA_TYPE = "text/x-ecsv"
#: the kinds of answer a table is made of, as :func:`table_kind` names them
TABLE_KINDS = ("bodies", "precession", "nutation", "track", "free_motion", "history", "batch")
#: the keys of an epoch table that are not per epoch though they are lists (the free motion's A/C, B/C, 1)
_NOT_PER_EPOCH = ("moments_over_C", "perturbers")
#: the columns' descriptions, by key (a key not here is described from its name: :func:`describe`)
DESCRIPTIONS = {
    "jd_tdb": "the epoch, Julian date TDB",
    "utc_iso": "the epoch as a UTC calendar date, ISO 8601, to the millisecond",
    "tt_iso": "the epoch as a TT calendar date, ISO 8601, to the millisecond",
    "tdb_iso": "the epoch as a TDB calendar date, ISO 8601, to the millisecond",
    "year": "Julian years (365.25 d) from J2000.0 TDB; negative is the past",
    "psi_arcsec": "the precession angle psi, with its nutation",
    "delta_psi_arcsec": "the nutation in longitude, delta psi",
    "delta_epsilon_arcsec": "the nutation in obliquity, delta epsilon",
    "obliquity_deg": "the obliquity: the spin axis from the orbit normal",
    "pole_ra_deg": "the spin pole's right ascension, ICRF",
    "pole_dec_deg": "the spin pole's declination, ICRF",
    "pole_uncertainty_deg": "the 1-sigma of the angle between the served and the true pole, from the catalogue's 1-sigma",
    "precession_angle_deg": "the equinox's retrograde turn since the pole epoch, on the J2000 ecliptic, unwrapped",
    "orbit_inclination_deg": "the orbit normal from the J2000 ecliptic pole",
    "estimated_error_deg": "the estimate of the pole's distance from the truth at this epoch",
    "obliquity_error_deg": "the estimate of the obliquity's error alone at this epoch",
    "figure_axis_offset_x_arcsec": "the figure axis from the angular momentum, in the plane normal to it, first axis",
    "figure_axis_offset_y_arcsec": "the figure axis from the angular momentum, second axis",
    "wobble_angle_J_arcsec": "the angle J between the angular momentum and the C axis",
    "andoyer_nu_deg": "Andoyer's angle nu of the angular momentum about the C axis, body frame",
    "name": "the body's name",
    "naif_id": "the body's NAIF id",
    "kind": "the kind of body",
    "dataset": "the catalogue dataset",
    "body": "the body",
    "a_au": "the orbit's semi-major axis",
    "e": "the orbit's eccentricity",
    "orbit_center": "the body the orbit is about",
    "rotation_period_hours": "the sidereal rotation period",
    "dynamical_ellipticity": "H_d = (C - (A+B)/2) / C",
    "scaling_factor_arcsec_per_year": "the scaling factor K of the precession and nutation (Petit et al. 2014)",
    "precession_rate_arcsec_per_year": "the precession rate psi-dot under the torque",
    "geodesic_precession_rate_arcsec_per_year": "the geodesic (de Sitter) precession rate",
    "geodesic_precession_in_rate": "whether the precession rate includes the geodesic precession",
    "observable_precession_rate_arcsec_per_year": "the precession rate radio tracking measures: the torque's less "
                                                  "the geodesic precession",
    "multiple": "k: the term's argument is k times the mean anomaly",
    "period_days": "the term's period (negative: its argument decreases)",
    "period_years": "the term's period, Julian years",
    "longitude_sin_arcsec": "delta psi's coefficient of the sine",
    "longitude_cos_arcsec": "delta psi's coefficient of the cosine",
    "obliquity_sin_arcsec": "delta epsilon's coefficient of the sine",
    "obliquity_cos_arcsec": "delta epsilon's coefficient of the cosine",
    "longitude_amplitude_arcsec": "the amplitude in longitude (the quantity: meta amplitude_quantities)",
    "obliquity_amplitude_arcsec": "the amplitude in obliquity, delta epsilon",
    "model": "the model that answered",
    "estimated_error_mas": "the estimate of the answer's error",
    "error": "why this row has no answer (empty: it has one)",
    "history_error": "why this row has no history (empty: it has one)",
    "obliquity_min_deg": "the smallest obliquity over the history",
    "obliquity_max_deg": "the largest obliquity over the history",
    "obliquity_period_years": "the obliquity's main period over the history",
}
_DELAUNAY_TEXT = {"l": "the Moon's mean anomaly l", "l'": "the Sun's mean anomaly l'",
                  "F": "the Moon's argument of latitude F", "D": "the Moon's elongation from the Sun D",
                  "Omega": "the longitude of the Moon's node Omega"}
_TERM = re.compile(r"nutation_(\d+)_(.+)")
_RATE = re.compile(r"(longitude|obliquity)_(sin|cos)_rate_arcsec_per_century")


def describe(key: str) -> str:
    """A column's description: :data:`DESCRIPTIONS`' or one made from its key (a 1-sigma, a Poisson rate, a
    Delaunay multiplier, a batch's nutation term)."""
    if key in DESCRIPTIONS:
        return DESCRIPTIONS[key]
    if key.endswith("_uncertainty"):
        return f"the 1-sigma of {key[:-len('_uncertainty')]} (empty: unknown)"
    if key in _DELAUNAY_TEXT:
        return f"the term's multiplier of {_DELAUNAY_TEXT[key]}"
    if (m := _RATE.fullmatch(key)) is not None:
        return f"the Poisson rate of the {m[1]} {m[2]} coefficient"
    if (m := _TERM.fullmatch(key)) is not None:
        return f"the nutation term of rank {m[1]} (by the pole displacement it makes): {describe(m[2])}"
    return key.replace("_", " ")


def table_kind(answer) -> str:
    """Which table-shaped answer ``answer`` is (one of :data:`TABLE_KINDS`), from its keys; InvalidInputError
    naming ``answer`` for anything else (a body record, a POST's several answers)."""
    if isinstance(answer, list):
        if answer and all(isinstance(r, dict) and "naif_id" in r for r in answer):
            return "bodies"
    elif isinstance(answer, dict):
        if "rows" in answer and "columns" in answer:
            return "batch"
        for kind, key in (("nutation", "terms"), ("free_motion", "figure_axis_offset_x_arcsec"),
                          ("track", "psi_arcsec"), ("history", "precession_angle_deg"),
                          ("precession", "precession_rate_arcsec_per_year")):
            if key in answer:
                return kind
    raise InvalidInputError("answer", "not a table-shaped answer: give the answer of list_bodies, precession, "
                                      "nutation, track (or track_arrays), free_motion_answer (or _arrays), history "
                                      "or batch")


def to_qtable(answer: Mapping[str, Any] | Sequence[Mapping[str, Any]], *, source: str | None = None) -> QTable:
    """The answer as an astropy ``QTable``: Quantity columns in the units their keys name, ``jd_tdb`` a TDB
    ``Time``, a description on every column and the answer's metadata in ``meta`` (see the module's docstring).

    ``answer``: what :func:`ephem.api.list_bodies`, ``precession``, ``nutation``, ``track`` (or ``track_arrays``),
    ``free_motion_answer`` (or ``free_motion_arrays``), ``history`` or ``batch`` returned, unchanged (with
    ``quantities=True`` too: a Quantity is taken in its key's unit). ``source``:
    where it came from (a URL, a command line), written in ``meta``; default the library's function.
    The same table is what :func:`to_ecsv` writes, and what ``QTable.read(..., format="ascii.ecsv")`` reads back.

    Parameters
    ----------
    answer : dict or list of dict
        An answer of :mod:`ephem.api`, unchanged (the bodies' list is a list of dicts); its keys name their units
        (``_deg``, ``_arcsec``, ``_mas``, ``_days``, ``jd_tdb``...).
    source : str or None
        Where the answer came from, for ``meta["source"]``; None: the library's function that made it.

    Returns
    -------
    astropy.table.QTable
        One row per epoch (a track, a free motion, a history), per nutation term, per body or per batch row:
        Quantity columns in their keys' units (deg, arcsec, mas, d, yr...), ``jd_tdb`` a TDB ``Time``.
        :class:`InvalidInputError` (field ``answer``) for an object that is no table-shaped answer.
    """
    from astropy.table import QTable

    kind = table_kind(answer)
    columns, meta = _BUILDERS[kind](answer)
    table = QTable()
    for key, values in columns:
        table[key] = _column(key, values)
        table[key].info.description = describe(key)
    table.meta.update(_plain(_meta(kind, answer, meta, source)))
    return table


def to_ecsv(answer: Mapping[str, Any] | Sequence[Mapping[str, Any]], *, source: str | None = None) -> str:
    """The answer's :func:`to_qtable` written by astropy as ECSV (``text/x-ecsv``): a YAML header (each column's
    name, unit, type and description; the metadata) and the rows, space-separated, each number as its shortest
    repr (it reads back to the same double). Charges the writing first: rows x columns at the measured unit cost.

    Parameters
    ----------
    answer : dict or list of dict
        An answer of :mod:`ephem.api`, unchanged (as :func:`to_qtable` takes it).
    source : str or None
        Where the answer came from, written in the header's metadata; None: the library's function.

    Returns
    -------
    str
        The ECSV text (``text/x-ecsv``): ``QTable.read(io.StringIO(text), format="ascii.ecsv")`` gives back the
        table with its units.
    """
    table = to_qtable(answer, source=source)
    charge(cost.Cost((cost.serialised(len(table), len(table.colnames), "ecsv"),)), _body_of(answer))
    out = io.StringIO()
    table.write(out, format="ascii.ecsv")
    return out.getvalue()


# --- the columns and the metadata of each kind ---------------------------------------------------------------

def _epoch_columns(answer: dict, epoch_key: str):
    """A track's, a free motion's or a history's per-epoch arrays, in the answer's order; the rest is metadata."""
    n = len(answer[epoch_key])
    columns, meta = [], {}
    for key, value in answer.items():
        per_epoch = isinstance(value, (list, tuple, np.ndarray)) or hasattr(value, "jd1")     # a Time too
        if key not in _NOT_PER_EPOCH and per_epoch and np.ndim(value) == 1 and len(value) == n:
            columns.append((key, value))
        else:
            meta[key] = value
    return columns, meta


def _rows_columns(rows: list[dict], keys=None):
    """Columns of a list of row objects: the keys of every row, in the order they first appear."""
    if keys is None:
        keys = list(dict.fromkeys(k for r in rows for k in r))
    return [(k, [r.get(k) for r in rows]) for k in keys]


def _bodies(answer: list):
    return _rows_columns(answer), {}


def _precession(answer: dict):
    row = {k: v for k, v in answer.items() if not isinstance(v, (dict, list))}
    return _rows_columns([row]), {k: v for k, v in answer.items() if k not in row}


def _nutation(answer: dict):
    rows = []
    for term in answer["terms"]:        # the Delaunay multipliers as five columns, as the CLI's CSV
        row = {k: v for k, v in term.items() if k != "delaunay_multipliers"}
        if term.get("delaunay_multipliers") is not None:
            row = {"multiple": None, **dict(zip(DELAUNAY_NAMES, term["delaunay_multipliers"])), **row}
        rows.append(row)
    return _rows_columns(rows), {k: v for k, v in answer.items() if k != "terms"}


def _batch(answer: dict):
    return _rows_columns(answer["rows"], answer["columns"]), {k: v for k, v in answer.items()
                                                              if k not in ("rows", "columns")}


_BUILDERS = {"bodies": _bodies, "precession": _precession, "nutation": _nutation, "batch": _batch,
             "track": lambda a: _epoch_columns(a, "jd_tdb"), "free_motion": lambda a: _epoch_columns(a, "jd_tdb"),
             "history": lambda a: _epoch_columns(a, "year")}


def _column(key: str, values):
    """One column: a TDB ``Time`` for ``jd_tdb``, text, or numbers with the unit the key names (masked where the
    answer has null)."""
    from astropy import units as u
    from astropy.table import Column, MaskedColumn
    from astropy.time import Time

    if key == "jd_tdb":            # a TDB Time (an answer given with quantities=True holds one already)
        return values.tdb if isinstance(values, Time) else Time(np.asarray(values, dtype=float), format="jd",
                                                                  scale="tdb")
    if isinstance(values, Time):   # another epoch column given as a Time (quantities=True): its JD TDB
        values = values.tdb.jd
    values = values if isinstance(values, np.ndarray) else [_bare(v) for v in values]
    if isinstance(values, u.Quantity):
        values = values.value      # in the unit its key names, as quantities=True makes it
    unit = "yr" if key == "year" else unit_of(key)
    if isinstance(values, np.ndarray):
        data, mask = values, None
    else:
        mask = [v is None for v in values]
        present = [v for v in values if v is not None]
        if not present:                 # nothing known: a numeric column, all masked
            data = np.zeros(len(values))
        elif all(isinstance(v, str) for v in present):
            data = ["" if v is None else v for v in values]
        elif all(isinstance(v, (bool, np.bool_)) for v in present):
            data = [False if v is None else bool(v) for v in values]
        elif all(isinstance(v, (int, np.integer)) and not isinstance(v, bool) for v in present):
            data = np.array([0 if v is None else int(v) for v in values], dtype=np.int64)
        else:
            data = np.array([np.nan if v is None else float(v) for v in values], dtype=float)
        if not any(mask):
            mask = None
    if unit is None or (not isinstance(data, np.ndarray) or data.dtype.kind not in "fi"):
        return Column(data) if mask is None else MaskedColumn(data, mask=mask)
    if mask is None:
        return u.Quantity(np.asarray(data, dtype=float), u.Unit(unit))
    return MaskedColumn(np.asarray(data, dtype=float), mask=mask, unit=unit)


def _meta(kind: str, answer, rest: dict, source: str | None) -> dict:
    """The table's metadata: what the table is, the model and its estimate, the time scale, the source, the
    version and the citations, then the answer's other scalars and objects."""
    model = rest.get("model") if isinstance(rest.get("model"), dict) else None
    meta = {"table": kind, "source": source or f"ephem.api ({kind})", "version": ephem.__version__}
    for key in ("body", "dataset"):
        if isinstance(answer, dict) and isinstance(answer.get(key), str):
            meta[key] = answer[key]
    calendar = next((k for k in (answer if isinstance(answer, dict) else {}) if k.endswith("_iso")), None)
    if calendar is not None:
        meta["time_scale"] = calendar[:-len("_iso")]
        meta["time_scales"] = {"jd_tdb": "tdb", calendar: meta["time_scale"]}
    elif kind == "history":
        meta["time_scale"] = "tdb"       # the years count Julian years of TDB from J2000.0
    if model is not None and "estimated_error_mas" in model:
        meta["estimate"] = {"estimated_error_mas": model.get("estimated_error_mas"),
                            "covers": model.get("estimate_covers"),
                            "what": "the largest distance of the served pole from the truth over the answer, mas"}
    meta["citations"] = _citations(kind, answer, model)
    meta.update({k: v for k, v in rest.items() if k not in meta})
    return meta


def _body_of(answer) -> str | None:
    return answer.get("body") if isinstance(answer, dict) and isinstance(answer.get("body"), str) else None


def _citations(kind: str, answer, model: dict | None) -> list[str]:
    """What the answer rests on: the theory its model names, and the catalogue's references for the values of the
    body (or, for the bodies list, of every body listed); none for a body of the caller's own."""
    out = []
    if model is not None:
        out += [str(model[k]) for k in ("theory", "spin") if model.get(k)]
    if kind == "bodies":
        named = [(r["name"], r["dataset"]) for r in answer]
    elif isinstance(answer, dict) and "body" in answer and "dataset" in answer:
        named = [(answer["body"], answer["dataset"])]
    else:
        named = []
    refs, seen = load_references(), set()
    for name, dataset in named:
        try:
            body = get_body(name, dataset)
        except EphemError:     # a body of the caller's own: not in the catalogue, no references of it
            continue
        for value in body.values.values():
            ref = refs.get(value.source)
            if not ref or value.source in seen:
                continue
            seen.add(value.source)
            out.append(". ".join(str(ref[k]).rstrip(".") for k in ("authors", "year", "title", "journal")
                                 if ref.get(k)) + (f". doi:{ref['doi']}" if ref.get("doi") else ""))
    return out


def _bare(value):
    """A Quantity as its number (in the unit its key names, as ``quantities=True`` makes it), a Time as its JD TDB;
    anything else as it is."""
    if hasattr(value, "jd1") and hasattr(value, "tdb"):
        return value.tdb.jd
    if hasattr(value, "unit") and hasattr(value, "value"):
        return value.value
    return value


def _plain(value):
    """``value`` as YAML's plain types (numpy scalars and arrays as Python's, tuples as lists, keys as text,
    Quantities and Times as their numbers)."""
    value = _bare(value)
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, np.ndarray):
        return [_plain(v) for v in value.tolist()]
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value
