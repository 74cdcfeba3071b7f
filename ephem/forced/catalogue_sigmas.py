"""A body's catalogue inputs with their 1-σ: what the forced model reads, in which units, how correlated.

The inputs of :func:`ephem.forced.precession_nutation.build_model` as the catalogue records them (value, unit,
1-σ, source), the caller's overrides of their σ and correlations checked, the correlation matrix, and the σ of
H_d and of any function of the moments (linear propagation). :mod:`ephem.forced.uncertainty` propagates them to
the theory's outputs; the families and the long-term history read the σ themselves.
"""
from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from ..base.errors import InvalidInputError
from ..base.memo import bytes_bounded
from ..base.units import unit_factor
from ..bodies.catalogue import Body


@dataclass(frozen=True)
class CatalogueInput:
    """One input of the model as the catalogue gives it, with the model's unit factor and its step family."""

    key: str
    value: float          # in ``unit``
    unit: str
    factor: float         # model unit per ``unit``
    sigma: float | None   # in ``unit``
    source: str | None
    kind: str             # "a", "e", "angle", "relative": default FD step family



def model_inputs(body: Body) -> list[tuple[str, float, str, str]]:
    """(key, value in model unit, model unit, step kind) of what the model reads, in order."""
    o, p = body.orbit, body.pole
    ecliptic = "pole.lon" in body.values
    out = [("orbit.a", o.a_au, "AU", "a"), ("orbit.e", o.e, "", "e"), ("orbit.i", o.i_deg, "deg", "angle"),
           ("orbit.node", o.node_deg, "deg", "angle"), ("orbit.peri", o.peri_deg, "deg", "angle"),
           ("orbit.mean_anomaly", o.mean_anomaly_deg, "deg", "angle")]
    if ecliptic:
        lon, lat = body.values["pole.lon"], body.values["pole.lat"]
        out += [("pole.lon", lon.value * unit_factor(lon.unit, "deg"), "deg", "angle"),
                ("pole.lat", lat.value * unit_factor(lat.unit, "deg"), "deg", "angle")]
    else:
        out += [("pole.ra", p.ra_deg, "deg", "angle"), ("pole.dec", p.dec_deg, "deg", "angle")]
    out.append(("rotation.period", body.rotation_period_hours, "h", "relative"))
    if body.dynamical_ellipticity is not None:
        out.append(("inertia.dynamical_ellipticity", body.dynamical_ellipticity, "", "relative"))
    else:
        for label, v in zip("ABC", body.moments):
            out.append((f"inertia.{label}", v, "", "relative"))
    return out


def input_sigmas(body: Body) -> dict[str, float | None]:
    """{input key: its catalogue 1-σ, or None where none is published} for the inputs the theory uses: the
    caller's own dict of the pairs kept per body (:func:`_kept_sigmas`)."""
    return dict(_kept_sigmas(body))


@bytes_bounded(key=lambda body: body.with_sigmas())      # the σ too: a body's equality leaves its values out
def _kept_sigmas(body: Body) -> tuple[tuple[str, float | None], ...]:
    """The (input key, catalogue 1-σ or None) pairs of :func:`input_sigmas`: a function of the body alone (its
    catalogue values and their units), kept per body in the byte-bounded caches (:mod:`ephem.base.memo`, ~1 kB),
    since every track of a body with uncertainties asks it (~15 us to read the catalogue's values again)."""
    return tuple((i.key, i.sigma) for i in catalogue_inputs(body, None))


def catalogue_inputs(body: Body, overrides: Mapping[str, float | None] | None) -> list[CatalogueInput]:
    items = []
    for key, model_value, model_unit, kind in model_inputs(body):
        m = body.values.get(key)
        if m is not None:
            unit = m.unit
            factor = 1.0 if key.startswith("inertia.") and key != "inertia.dynamical_ellipticity" \
                else unit_factor(unit, model_unit)
            value, sigma, source = m.value, m.uncertainty, m.source
        else:   # a Body built in code: values in the model's units, no uncertainties
            unit, factor, value, sigma, source = model_unit, 1.0, model_value, None, None
        items.append(CatalogueInput(key, value, unit, factor, sigma, source, kind))
    if overrides:
        known = {i.key for i in items}
        for key, sigma in overrides.items():
            if key not in known:
                raise InvalidInputError("uncertainties", f"{key!r} is not an input of the model for this body; "
                                        f"inputs: {', '.join(sorted(known))}", body.name)
            if sigma is not None and (isinstance(sigma, bool) or not isinstance(sigma, (int, float))
                                      or not math.isfinite(sigma) or sigma < 0):
                raise InvalidInputError("uncertainties", f"{key}: must be a finite number >= 0 or None, "
                                        f"got {sigma!r}", body.name)
        items = [CatalogueInput(i.key, i.value, i.unit, i.factor,
                        (None if overrides[i.key] is None else float(overrides[i.key])) if i.key in overrides
                        else i.sigma, i.source, i.kind) for i in items]
    return items


def correlation_matrix(inputs: list[CatalogueInput], correlations, b: Body) -> np.ndarray:
    """ρ of the inputs: the catalogue's (a record's stated and derived correlations, :attr:`Body.correlations`,
    for the pairs that are inputs of this model), updated by the caller's ``correlations``."""
    n = len(inputs)
    rho = np.eye(n)
    index = {inp.key: j for j, inp in enumerate(inputs)}
    correlations = {**{pair: r for pair, r in b.correlations.items() if all(k in index for k in pair)},
                    **(correlations or {})}
    if not correlations:
        return rho
    body = b.name
    for pair, r in correlations.items():
        if len(pair) != 2 or any(k not in index for k in pair) or pair[0] == pair[1]:
            raise InvalidInputError("correlations", f"{pair!r}: expected two different inputs of "
                                    f"{', '.join(index)}", body)
        if isinstance(r, bool) or not isinstance(r, (int, float)) or not -1.0 <= r <= 1.0:
            raise InvalidInputError("correlations", f"{pair!r}: a correlation must lie in [-1, 1], got {r!r}", body)
        a, b = index[pair[0]], index[pair[1]]
        rho[a, b] = rho[b, a] = float(r)
    if np.linalg.eigvalsh(rho).min() < -1e-10:
        raise InvalidInputError("correlations", "the correlation matrix is not positive semi-definite", body)
    return rho


def moments_function_sigma(b: Body, f) -> float | None:
    """The 1-σ of ``f(A, B, C)`` from the catalogue moments' σ and correlations (linear, central differences a
    millionth of each moment wide); None where a moment ``f`` depends on has no σ (unknown, not zero)."""
    x = list(b.moments)
    keys = ("inertia.A", "inertia.B", "inertia.C")
    grad = []
    for i in range(3):
        h = 1e-6 * abs(x[i])
        xp, xm = list(x), list(x)
        xp[i] += h
        xm[i] -= h
        grad.append((f(*xp) - f(*xm)) / (2.0 * h))
    sig = [b.values[k].uncertainty if k in b.values else None for k in keys]
    if any(g != 0.0 and s is None for g, s in zip(grad, sig)):
        return None
    var = 0.0
    for i in range(3):
        for j in range(3):
            rho = 1.0 if i == j else b.correlations.get((keys[i], keys[j]), b.correlations.get((keys[j], keys[i]), 0.0))
            var += grad[i] * (sig[i] or 0.0) * rho * (sig[j] or 0.0) * grad[j]
    return math.sqrt(max(var, 0.0))


def dynamical_ellipticity_sigma(b: Body) -> float | None:
    """The 1-σ of the H_d the theory uses, from the catalogue: the explicit value's, or the moments' with their
    correlations (:func:`moments_function_sigma`); None where unknown."""
    if b.dynamical_ellipticity is not None:
        m = b.values.get("inertia.dynamical_ellipticity")
        return None if m is None else m.uncertainty
    return moments_function_sigma(b, lambda A, B, C: (C - 0.5 * (A + B)) / C)


def no_uncertainty_reasons(b: Body, keys) -> dict[str, str]:
    """{input key: why it has no σ} for ``keys``: the record's ``no_uncertainty`` reason, or that it gives none."""
    out = {}
    for key in keys:
        m = b.values.get(key)
        out[key] = (m.no_uncertainty if m is not None and m.no_uncertainty
                    else "the body's record gives no sigma for it and no reason")
    return out
