"""Astropy at the boundary: ``Time`` and ``Quantity`` in, and out on request.

The numeric core works in plain floats (radians, days, JD TDB); :mod:`ephem.answers.requests` converts at its
edge, as poliastro does. In: any time argument may be an astropy ``Time`` (its TDB Julian date is
used), and any argument whose name carries a unit (``step_days``, ``tolerance_mas``, ``J_arcsec``,
``free_wobble_phase_deg``) may be a ``Quantity`` in any unit convertible to it. Out:
:func:`with_units` turns an answer's unit-named keys into ``Quantity`` (``jd_tdb`` into a TDB
``Time``), which the api functions do when called with ``quantities=True``.
"""
from __future__ import annotations

from .errors import InvalidInputError

#: key suffix -> astropy unit string, longest suffixes first
_SUFFIX_UNITS = (
    ("_arcsec_per_year", "arcsec / yr"), ("_arcsec_per_century", "arcsec / hyr"), ("_mas_per_century", "mas / hyr"),
    ("_deg_per_day", "deg / d"), ("_arcsec", "arcsec"), ("_mas", "mas"),
    ("_deg", "deg"), ("_days", "d"), ("_years", "yr"), ("_hours", "h"), ("_au", "AU"), ("_km", "km"),
    ("_ms", "ms"),
)


#: Exact factors between the units the catalogue writes, so that reading it needs no astropy.units (0.1-0.2 s to
#: import, most of a one-body answer's start-up): the IAU 2012 au, 24 h in a day. Every entry is checked against
#: astropy (tests/base/test_units.py); a pair not here goes through astropy.
_EXACT_FACTORS = {("d", "h"): 24.0, ("h", "d"): 1.0 / 24.0, ("AU", "km"): 149597870.7, ("km", "AU"): 1.0 / 149597870.7,
                  ("deg/yr", "deg/d"): 1.0 / 365.25, ("deg/d", "deg/yr"): 365.25}


def unit_factor(unit: str, target: str) -> float:
    """How many ``target`` in one ``unit`` (astropy unit strings): 1 for the same unit, a fixed factor for the
    pairs the catalogue needs, else astropy's conversion (ValueError or astropy's UnitConversionError for a unit
    that does not convert)."""
    if unit == target:
        return 1.0
    exact = _EXACT_FACTORS.get((unit, target))
    if exact is not None:
        return exact
    from astropy import units as u

    return float((1.0 * u.Unit(unit)).to_value(u.Unit(target)))


def is_quantity(value) -> bool:
    return hasattr(value, "unit") and hasattr(value, "to_value")


def in_unit(value, unit: str, field: str):
    """``value`` in ``unit`` if it is a Quantity (a scalar: its float), else ``value`` unchanged (the caller
    validates plain numbers); a unit that does not convert is an InvalidInputError naming ``field``."""
    if not is_quantity(value):
        return value
    from astropy import units as u

    try:
        converted = value.to_value(u.Unit(unit))
    except u.UnitConversionError:
        raise InvalidInputError(field, f"expected a quantity in {unit}, got one in {value.unit}") from None
    return float(converted) if getattr(converted, "ndim", 0) == 0 else converted


def unit_of(key: str) -> str | None:
    """The astropy unit a key's name states, or None (``*_uncertainty`` keys take their value's unit)."""
    base = key[: -len("_uncertainty")] if key.endswith("_uncertainty") else key
    for suffix, unit in _SUFFIX_UNITS:
        if base.endswith(suffix):
            return unit
    return None


def with_units(answer):
    """A copy of an answer (dict, list, or nested) with every unit-named number or array as a Quantity and
    ``jd_tdb`` / ``*_jd_tdb`` as astropy TDB ``Time``. Dimensionless and text values are left alone."""
    from astropy import units as u
    from astropy.time import Time

    if isinstance(answer, list):
        return [with_units(v) for v in answer]
    if not isinstance(answer, dict):
        return answer
    out = {}
    for key, value in answer.items():
        if isinstance(value, dict) and unit_of(key) is not None:     # e.g. error_terms_mas: {term: mas}
            out[key] = {k: u.Quantity(v, unit_of(key)) for k, v in value.items()}
        elif isinstance(value, (dict, list)) and not (isinstance(value, list) and value
                                                      and isinstance(value[0], (int, float))):
            out[key] = with_units(value)
        elif value is None or isinstance(value, (str, bool)):
            out[key] = value
        elif key == "jd_tdb" or key.endswith("_jd_tdb"):
            out[key] = Time(value, format="jd", scale="tdb")
        elif (unit := unit_of(key)) is not None:
            out[key] = u.Quantity(value, unit)
        else:
            out[key] = value
    return out
