"""The non-rigid Earth's correction to each nutation term: the IERS 1996 transfer function.

A rigid-Earth series (ours, REN-2000) and IAU 2000A differ term by term because the real Earth
has an elastic mantle, a fluid core and oceans. Nutation theory since Wahr (1981) expresses this
as a transfer function T(σ): each prograde or retrograde circular component of frequency σ of
the rigid-Earth nutation is multiplied by T(σ). The function is dominated by the elastic
mantle (a few per cent) and by the free core nutation (FCN), a retrograde resonance about 430
days long in space, which amplifies the retrograde annual nutation by a third.

This module evaluates the published resonance model behind the IERS 1996 nutation series
(Herring's KSV_1996_3, IERS Conventions 1996 ch. 5; the formulation of Mathews, Buffett,
Herring & Shapiro 1991, JGR 96, 8219), with the coefficients printed in that routine
(``data/nonrigid.toml``):

    T(σ) = R + R' (1 + σ_t) + Σ_j N_j / (σ_t - s_j),     σ_t = σ - 1,

σ the component's frequency in space and σ_t in the Earth's frame, in cycles per sidereal day
(prograde positive); N_j, s_j the strengths and frequencies of the RFCN and Chandler
resonances; R, R' the non-resonant part. The routine gives the table, not the formula; this
reading is the resonance expansion the table's columns describe, and it is checked: T(0) = 1
to 7e-5 (the precession is not rescaled), and our rigid terms times T reproduce KSV_1996_3's own
coefficients to 0.02 mas and IAU 2000A's (MHB2000, whose transfer function adds anelasticity
and ocean corrections) to 0.06 mas for every leading term shorter than a year
(tests/earth/test_nonrigid.py, tests/earth/test_against_iau2006.py). Its imaginary part gives the out-of-phase terms, with the routine's
sign convention ("amplitudes defined as ar - ai"): T* multiplies our e^{+iφ} components.

The Earth's non-rigid track rung (``nonrigid``, :class:`ephem.earth.model.NonRigidEarth`) applies it
(:func:`non_rigid_series`), and so does the nutation answer when asked for ``nonrigid`` terms.

Units: coefficients in mas, frequencies in cycles per sidereal day, periods in days.
"""
from __future__ import annotations

import dataclasses
import math
from functools import lru_cache

import numpy as np

from ..base.paths import data_dir
from ..base.errors import InvalidInputError
from ..bodies.interior import circular_parts, from_circular_parts
from .lunisolar import precession_nutation_coupling
from ..base.disk_cache import read_toml


@lru_cache(maxsize=1)
def nonrigid_data() -> dict:
    """Parsed data/nonrigid.toml (transfer-function coefficients and IERS 1996 reference terms)."""
    return read_toml(data_dir() / "nonrigid.toml")


def _coefficients():
    tf = nonrigid_data()["transfer_function"]
    r = complex(*tf["R"])
    rp = complex(*tf["R_prime"])
    res = [(complex(a, b), complex(f, g)) for a, b, f, g in tf["resonances"].values()]
    return r, rp, res


def transfer_function(sigma_cpsd):
    """T(σ) of the IERS 1996 series for circular components of frequency ``sigma_cpsd``.

    ``sigma_cpsd``: frequency in space, cycles per sidereal day, prograde positive (array or
    scalar). Returns complex T with KSV_1996_3's convention (multiply a component written as
    amplitude × e^{-iσt}, or use the conjugate for e^{+iσt}; :func:`non_rigid_term` does).
    """
    sigma = np.asarray(sigma_cpsd, dtype=float)
    if not np.all(np.isfinite(sigma)):
        raise InvalidInputError("sigma_cpsd", "must be finite")
    r, rp, res = _coefficients()
    st = sigma - 1.0
    t = r + rp * (1.0 + st)
    for amplitude, frequency in res:
        t = t + amplitude / (st - frequency)
    return t


def sigma_cpsd(period_days: float) -> float:
    """Frequency in cycles per sidereal day of a term of signed period ``period_days`` (mean solar days)."""
    per_day = nonrigid_data()["transfer_function"]["sidereal_per_solar_day"]
    return (1.0 / period_days) / per_day


def circular_components(longitude_sin, longitude_cos, obliquity_cos, obliquity_sin, sin_eps):
    """(c₊, c₋): Δψ sin ε + iΔε = c₊ e^{iφ} + c₋ e^{-iφ} for Δψ = S sin φ + C cos φ, Δε = E cos φ + F sin φ, as
    complex numbers (:func:`ephem.bodies.interior.circular_parts`, the one home of the decomposition).

    c₊ turns with the term's argument φ: prograde in space when φ increases, retrograde when it
    decreases (the 18.6-yr term, φ = Ω).
    """
    plus, minus = circular_parts(longitude_sin, longitude_cos, obliquity_sin, obliquity_cos, sin_eps)
    return complex(plus), complex(minus)


def from_circular(plus: complex, minus: complex, sin_eps: float):
    """Inverse of :func:`circular_components`: (S, C, E, F) of Δψ and Δε."""
    s, c, f, e = from_circular_parts(np.asarray(plus), np.asarray(minus), sin_eps)
    return float(s), float(c), float(e), float(f)


def non_rigid_term(term: dict, obliquity_rad: float) -> dict:
    """A rigid-Earth term (a ``LunisolarSeries.terms`` entry, mas) times the IERS 1996 T(σ).

    Returns the non-rigid coefficients (``longitude_sin_mas``, ``longitude_cos_mas``,
    ``obliquity_cos_mas``, ``obliquity_sin_mas``), the non-rigid correction of each
    (``…_correction_mas`` = non-rigid − rigid) and the factors Re T of the two components
    (``transfer_prograde``, ``transfer_retrograde``).
    """
    period = float(term["period_days"])
    if not math.isfinite(period) or period == 0.0:
        raise InvalidInputError("period_days", "must be finite and non-zero")
    se = math.sin(obliquity_rad)
    rigid = (term["longitude_sin_mas"], term.get("longitude_cos_mas", 0.0),
             term["obliquity_cos_mas"], term.get("obliquity_sin_mas", 0.0))
    plus, minus = circular_components(*rigid, se)
    sigma = sigma_cpsd(period)
    t_plus, t_minus = complex(transfer_function(sigma)), complex(transfer_function(-sigma))
    values = from_circular(t_plus.conjugate() * plus, t_minus.conjugate() * minus, se)
    keys = ("longitude_sin_mas", "longitude_cos_mas", "obliquity_cos_mas", "obliquity_sin_mas")
    out = dict(zip(keys, (float(v) for v in values)))
    for key, before in zip(keys, rigid):
        out[key.replace("_mas", "_correction_mas")] = out[key] - float(before)
    prograde_is_plus = period > 0.0
    out["transfer_prograde"] = (t_plus if prograde_is_plus else t_minus).real
    out["transfer_retrograde"] = (t_minus if prograde_is_plus else t_plus).real
    return out


def iers1996_terms() -> list:
    """KSV_1996_3's coefficients of the leading terms, mas: psi sin, eps cos, psi cos, eps sin."""
    return [{"delaunay_multipliers": row["delaunay_multipliers"],
             "mas": [v / 1000.0 for v in row["uas"]]} for row in nonrigid_data()["iers1996_term"]]


def non_rigid_series(series, coupling: bool = True):
    """``series`` (an :class:`ephem.earth.lunisolar.LunisolarSeries`) with every term times T(σ).

    ``coupling``: first add the precession–nutation coupling
    (:func:`ephem.earth.lunisolar.precession_nutation_coupling`), the one second-order rigid-Earth
    term above 0.1 mas (+2.9 mas on the 18.6-yr Δψ). The Poisson rates stay rigid. Against
    ``erfa.nut00a`` over 1900-2100 this leaves 1.8 mas rms in Δψ and 1.7 in Δε, against 63 and
    22 for the rigid series (docs/earth.md): what IAU 2000A adds beyond it is mostly the
    planetary nutation.
    """
    coef = np.array(series.coefficients, dtype=float)
    if coupling:
        coef[:, :2] += precession_nutation_coupling(series)
    out = np.empty_like(coef)
    for i, (k, nu) in enumerate(zip(series.multipliers, series.frequencies)):
        term = {"period_days": 2.0 * math.pi / nu, "longitude_sin_mas": coef[i, 0], "longitude_cos_mas": coef[i, 1],
                "obliquity_sin_mas": coef[i, 2], "obliquity_cos_mas": coef[i, 3]}
        nr = non_rigid_term(term, series.obliquity)
        out[i] = (nr["longitude_sin_mas"], nr["longitude_cos_mas"], nr["obliquity_sin_mas"], nr["obliquity_cos_mas"])
    return dataclasses.replace(series, coefficients=out, long_period_terms=[])   # its terms: from ``out``
