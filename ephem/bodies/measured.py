"""A catalogue value as published, and the values a body record's tables give.

A value table of ``data/catalogue/*.toml`` (format: ``SCHEMA.md`` there) is ``{value, unit, source[,
uncertainty | no_uncertainty, note]}``: :func:`measured` reads it as a :class:`Measured` (its 1-sigma
uncertainty, or the reason the source gives none), :func:`convert` turns it into the unit a field name states
(astropy, at load time). The values derived from others stand here too: the rotation period from a published
rate W' (:func:`rotation_period`), the moments of inertia from what is measured (:func:`derived_moments`,
:mod:`ephem.bodies.inertia`), and the correlations a source states (:func:`stated_correlations`).

Used by :mod:`ephem.bodies.catalogue`, which builds the records; a bad value raises
:class:`~ephem.base.errors.InvalidInputError` naming the body and the field.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from ..base.errors import InvalidInputError
from ..base.units import unit_factor
from .inertia import METHODS, derive


@dataclass(frozen=True)
class Measured:
    """A catalogue value as published: value, unit, 1-sigma uncertainty, source key; ``no_uncertainty``: why the
    source gives no σ (the record says so rather than inventing one)."""

    value: float
    unit: str
    source: str
    uncertainty: float | None = None
    note: str | None = None
    no_uncertainty: str | None = None


def check_finite(body: str | None, name: str, value: float) -> None:
    """``value`` a finite number (a bool is not one), else :class:`InvalidInputError` naming ``name``."""
    if not isinstance(value, (int, float)) or isinstance(value, bool) or not math.isfinite(value):
        raise InvalidInputError(name, f"must be a finite number, got {value!r}", body)


def measured(raw: dict, where: str, body: str, default_reason: str | None = None) -> Measured:
    """A value table as a :class:`Measured`; ``default_reason``: the section's ``no_uncertainty`` (why its values
    have no σ), for the values that give neither a σ nor a reason of their own."""
    if not isinstance(raw, dict) or "value" not in raw:
        raise InvalidInputError(where, "expected a table {value, unit, source[, uncertainty | no_uncertainty, "
                                "note]}", body)
    if "source" not in raw:
        raise InvalidInputError(where, "every value needs a source key", body)
    check_finite(body, where, raw["value"])
    unc = raw.get("uncertainty")
    if unc is not None:
        check_finite(body, f"{where}.uncertainty", unc)
        if unc < 0:
            raise InvalidInputError(f"{where}.uncertainty", f"must be >= 0, got {unc}", body)
    reason = raw.get("no_uncertainty")
    if reason is None and unc is None:
        reason = default_reason
    if reason is not None:
        if not isinstance(reason, str) or not reason.strip():
            raise InvalidInputError(f"{where}.no_uncertainty", "must be the reason no sigma is given (a non-empty "
                                    "string)", body)
        if unc is not None:
            raise InvalidInputError(f"{where}.no_uncertainty", "a value with an uncertainty needs no reason for "
                                    "lacking one: give one of the two", body)
    return Measured(float(raw["value"]), str(raw.get("unit", "")), str(raw["source"]),
                    None if unc is None else float(unc), raw.get("note"), reason)


def convert(m: Measured, target: str, where: str, body: str) -> float:
    try:
        return float(m.value * unit_factor(m.unit, target))
    except ValueError as exc:     # astropy's UnitConversionError is a ValueError
        raise InvalidInputError(where, f"cannot convert unit {m.unit!r} to {target!r}: {exc}", body) from None


def section_reason(section: dict, where: str, name: str) -> str | None:
    """A section's ``no_uncertainty``: the reason its values without a σ of their own have none."""
    reason = section.get("no_uncertainty")
    if reason is not None and (not isinstance(reason, str) or not reason.strip()):
        raise InvalidInputError(f"{where}.no_uncertainty", "must be the reason the section's values have no sigma "
                                "(a non-empty string)", name)
    return reason


def rotation_period(rotation: dict, values: dict, name: str, get) -> float:
    """The rotation period (h): ``rotation.period`` as given, or derived from the rate W' that rotation models
    publish (``rotation.rate``, deg/d): P = 360°/W', σ_P = P σ_W/W'."""
    if "rate" not in rotation:
        return get("rotation", "period", "h")
    if "period" in rotation:
        raise InvalidInputError("rotation", "give the period or the rate W', not both", name)
    rate = get("rotation", "rate", "deg/d")
    if rate <= 0.0:
        raise InvalidInputError("rotation.rate", f"must be positive (the pole is the right-hand spin axis), got "
                                f"{rate}", name)
    m = values["rotation.rate"]
    period = 360.0 / rate * 24.0
    per_unit = convert(Measured(1.0, m.unit, m.source), "deg/d", "rotation.rate", name)
    sigma = None if m.uncertainty is None else period * m.uncertainty * per_unit / rate
    values["rotation.period"] = Measured(period, "h", m.source, sigma, f"derived: 360 deg / W' with W' = {m.value:.12g} "
                                         f"{m.unit} (rotation.rate)", m.no_uncertainty)
    return period


def derived_moments(spec: dict, values: dict, correlations: dict, name: str) -> tuple[float, float, float]:
    """A, B, C from what was measured (:mod:`ephem.bodies.inertia`), stored as ``inertia.A`` … with their 1-σ, and
    their correlations added to ``correlations``."""

    where = "inertia.derived_from"
    if not isinstance(spec, dict):
        raise InvalidInputError(where, "expected a table {method = ..., <inputs> = {value, unit, source, ...}}", name)
    method = spec.get("method")
    m = METHODS.get(method)
    if m is None:
        raise InvalidInputError(f"{where}.method", f"must be one of {', '.join(METHODS)}, got {method!r}", name)
    unknown = sorted(set(spec) - set(m.inputs) - {"method", "note", "no_uncertainty"})
    if unknown:
        raise InvalidInputError(where, f"unknown inputs {', '.join(unknown)} for method {method!r} (it takes "
                                f"{', '.join(m.inputs)})", name)
    given, sigmas = {}, {}
    for key in m.inputs:
        if key not in spec:
            raise InvalidInputError(f"{where}.{key}", f"missing: method {method!r} needs {', '.join(m.inputs)}", name)
        meas = measured(spec[key], f"{where}.{key}", name, section_reason(spec, where, name))
        values[f"{where}.{key}"] = meas
        scale = convert(Measured(1.0, meas.unit, meas.source), m.input_unit, f"{where}.{key}", name)
        given[key] = meas.value * scale
        sigmas[key] = None if meas.uncertainty is None else meas.uncertainty * scale
    d = derive(method, given, sigmas, name)
    first = values[f"{where}.{m.inputs[0]}"]
    missing = "; ".join(f"{k}: {values[f'{where}.{k}'].no_uncertainty or 'no reason given'}" for k in d.missing_sigma)
    for label, value, sigma in zip("ABC", d.moments, d.sigma):
        values[f"inertia.{label}"] = Measured(
            value, d.unit, first.source, sigma, f"derived by {method} from {', '.join(m.inputs)} ({m.description})",
            None if sigma is not None else f"derived from inputs without a published sigma ({missing})")
    correlations.update(d.correlations)
    return d.moments


def stated_correlations(entries, values: dict, name: str) -> dict:
    """``[[body.correlation]]`` entries {inputs = [key, key], value = ρ, source = key} as {(key, key): ρ}."""
    out = {}
    if not isinstance(entries, list):
        raise InvalidInputError("correlation", "expected an array of tables [[body.correlation]]", name)
    for n, entry in enumerate(entries):
        where = f"correlation[{n}]"
        keys = entry.get("inputs") if isinstance(entry, dict) else None
        if not isinstance(keys, list) or len(keys) != 2 or keys[0] == keys[1]:
            raise InvalidInputError(f"{where}.inputs", f"expected two different value keys, got {keys!r}", name)
        for k in keys:
            if k not in values or values[k].uncertainty is None:
                raise InvalidInputError(f"{where}.inputs", f"{k!r} is not a value of this record with an "
                                        f"uncertainty", name)
        rho = entry.get("value")
        if isinstance(rho, bool) or not isinstance(rho, (int, float)) or not -1.0 <= rho <= 1.0:
            raise InvalidInputError(f"{where}.value", f"a correlation must lie in [-1, 1], got {rho!r}", name)
        if "source" not in entry:
            raise InvalidInputError(f"{where}.source", "every correlation needs a source key", name)
        out[(keys[0], keys[1])] = float(rho)
    return out
