"""Times at the boundary: ISO 8601 (UTC unless a scale is named) or Julian dates (TDB).

Accepted forms (astropy ``Time`` parses them):
- a number or ``"2451545.0"`` or ``"JD2451545.0"``: a Julian date in TDB;
- ``"2020-01-01"``, ``"2020-01-01T12:00:00"``: ISO 8601 in UTC;
- ``"2020-01-01T12:00:00 TDB"`` (or TT, TAI, UTC): ISO 8601 in the named scale;
- an astropy ``Time`` (any scale: its TDB Julian date).
"""
from __future__ import annotations

import math

from .errors import InvalidInputError

_SCALES = ("tdb", "tt", "tai", "utc", "tcb", "tcg", "ut1")


def to_jd_tdb(value, field: str = "time") -> float:
    """Julian date (TDB) of a boundary time; raises InvalidInputError naming ``field``."""
    if isinstance(value, bool):
        raise InvalidInputError(field, f"expected a time, got {value!r}")
    if hasattr(value, "tdb") and hasattr(value, "jd1"):        # an astropy Time
        if not value.isscalar:
            raise InvalidInputError(field, "expected one time, got an array of them")
        import warnings

        from erfa import ErfaWarning

        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ErfaWarning)  # "dubious year": UTC beyond the leap-second table
            tdb = value.tdb
        jd = float(tdb.jd1 + tdb.jd2)
    elif isinstance(value, (int, float)):
        jd = float(value)
    else:
        text = str(value).strip()
        if not text:
            raise InvalidInputError(field, "empty time")
        number = text[2:] if text.upper().startswith("JD") else text
        try:
            jd = float(number)
        except ValueError:
            jd = _parse_iso(text, field)
    if not math.isfinite(jd):
        raise InvalidInputError(field, f"time must be finite, got {value!r}")
    if not 0.0 < jd < 1e7:
        raise InvalidInputError(field, f"Julian date {jd} is outside the supported range (0, 1e7)")
    return jd


def _parse_iso(text: str, field: str) -> float:
    import warnings

    from astropy.time import Time
    from erfa import ErfaWarning

    scale = "utc"
    parts = text.rsplit(None, 1)
    if len(parts) == 2 and parts[1].lower() in _SCALES:
        text, scale = parts[0], parts[1].lower()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ErfaWarning)  # "dubious year" for far dates
            t = Time(text, format="isot" if "T" in text else "iso", scale=scale)
            return float(t.tdb.jd1 + t.tdb.jd2)
    except (ValueError, TypeError) as exc:
        raise InvalidInputError(field, f"cannot parse {text!r} as ISO 8601 or a Julian date ({exc})") from None
