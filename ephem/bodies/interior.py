"""The interior model of a body for its forced nutation: rigid, or a transfer function of the circular components.

A non-rigid body answers a forcing of frequency σ differently from a rigid one. Nutation theory writes this as a
transfer function T(σ) multiplying each prograde or retrograde circular component of the rigid nutation
(Wahr 1981; for Mars Dehant, Defraigne & Van Hoolst 2000, PEPI 117, 385). Which model each catalogue body has is
data/interiors.toml (docs/interiors.md): the Earth's is the IERS 1996 resonance formula (data/nonrigid.toml,
:mod:`ephem.earth.nonrigid`), Mars' the single free-core-nutation (FCN) resonance of a liquid core in a rigid
mantle, every other body is rigid, stated so.

Mars (Le Maistre et al. 2023, Nature 619, 733; the form used by Konopliv et al. 2006/2016 and the Tudat toolkit):

    T(σ) = 1 + F σ / (σ − σ_FCN),        σ_FCN = 2π / P_FCN,

σ the component's angular frequency in inertial space (rad/day, prograde positive), P_FCN < 0 the FCN period
(days, retrograde), F the core's amplification factor (dimensionless). T(0) = 1: the precession is unchanged.
T is real: the model has no dissipation.

Circular components. A term Δψ = S sin φ + C cos φ, Δε = E cos φ + F sin φ (our ψ: ψ̇ > 0 is retrograde, as in
:mod:`ephem.forced.kinoshita`) is written

    Δψ sin ε + i Δε = c₊ e^{+iφ} + c₋ e^{−iφ},
    c₊ = (C sin ε + F + i (E − S sin ε)) / 2,    c₋ = (C sin ε − F + i (E + S sin ε)) / 2,

the convention the Earth's transfer function uses too. (Δψ sin ε, Δε) are the pole's displacement
along (∂s/∂ψ / sin ε, ∂s/∂ε), a right-handed pair about the pole s, so c₊ turns about s in the sense of the
rotation when φ increases: it is the prograde component, of frequency σ = +φ̇, and c₋ the retrograde one, σ = −φ̇
(tests/bodies/test_interior.py checks it on a synthesised pole motion). In Konopliv et al.'s variables
(Δε + i Δψ_K sin I, ψ_K = −ψ) the same component is their P = (I + ψ_K sin I)/2, the one they multiply by T(+a).

The decomposition has its one home here (:func:`circular_parts`/:func:`from_circular_parts`, vectorised); the
Earth's transfer function (:mod:`ephem.earth.nonrigid`, above this package) uses it.

Units inside: radians, days, rad/day.
"""
from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np

from ..base.errors import InvalidInputError
from ..base.paths import data_dir
from ..base.disk_cache import read_toml

RIGID = "rigid"
TRANSFER_FUNCTION = "transfer_function"
FLUID_CORE = "fluid_core_resonance"


@dataclass(frozen=True)
class Parameter:
    """A parameter of an interior model: value, 1σ (None when none is published, with the reason) and unit."""

    value: float
    sigma: float | None
    unit: str
    no_uncertainty: str | None = None


@dataclass(frozen=True)
class Interior:
    """The interior model of one body (data/interiors.toml).

    ``model``: "rigid" or "transfer_function"; ``form``: the transfer function's formula ("fluid_core_resonance",
    "iers1996_resonance"; None when rigid); ``parameters``: name -> :class:`Parameter` (for Mars
    ``fcn_amplitude_factor`` and ``fcn_period_days``); ``source``: a key of the file's [references.*];
    ``why``: the reason a body is rigid; ``alternatives``: other published parameter sets, by name;
    ``mantle_elastic_scale``: the stated bound on the mantle's elastic response (None: none stated).
    """

    body: str
    model: str
    form: str | None = None
    parameters: Mapping[str, Parameter] = field(default_factory=dict)
    source: str | None = None
    why: str | None = None
    alternatives: Mapping[str, "Interior"] = field(default_factory=dict)
    left_out: tuple[str, ...] = ()
    parameters_file: str | None = None
    mantle_elastic_scale: float | None = None

    def as_dict(self, nested: bool = True) -> dict:
        """The model as plain data (the body record's ``interior``): model, form, parameters {name: {value, unit,
        uncertainty, no_uncertainty}}, source and its ``reference`` (the file's [references.*] entry, or None),
        why, left_out, parameters_file and, with ``nested``, the alternatives in the same shape without theirs."""
        out = {"model": self.model, "form": self.form,
               "parameters": {name: {"value": p.value, "unit": p.unit,
                                     "uncertainty": None if p.sigma is None else float(p.sigma),
                                     "no_uncertainty": p.no_uncertainty} for name, p in self.parameters.items()},
               "source": self.source, "reference": dict(references()[self.source]) if self.source in references() else None,
               "why": self.why, "left_out": list(self.left_out), "parameters_file": self.parameters_file}
        if nested:
            out["alternatives"] = {key: alt.as_dict(nested=False) for key, alt in self.alternatives.items()}
        return out


@lru_cache(maxsize=1)
def interiors_data() -> dict:
    """Parsed data/interiors.toml."""
    return read_toml(data_dir() / "interiors.toml")


def references() -> dict:
    """The file's [references.*]: key -> {citation, where, status}."""
    return interiors_data().get("references", {})


_UNITS = {"fcn_period_days": "d", "fcn_amplitude_factor": ""}


def _interior(body: str, rec: dict) -> Interior:
    params = {name: Parameter(float(rec[name]), rec.get(f"{name}_uncertainty"), unit, rec.get("no_uncertainty"))
              for name, unit in _UNITS.items() if name in rec}
    alternatives = {key: _interior(body, {"model": rec["model"], "form": rec.get("form"), **alt})
                    for key, alt in rec.get("alternatives", {}).items()}
    return Interior(body, rec["model"], rec.get("form"), params, rec.get("source"), rec.get("why"), alternatives,
                    tuple(rec.get("left_out", ())), rec.get("parameters_file"),
                    None if "mantle_elastic_scale" not in rec else float(rec["mantle_elastic_scale"]))


def interior_of(body_name: str) -> Interior:
    """The interior model of ``body_name`` (case-insensitive, as the catalogue spells it). A body the file does not
    list is rigid, and its ``why`` says so."""
    if not isinstance(body_name, str) or not body_name.strip():
        raise InvalidInputError("body", f"a body name is required, got {body_name!r}")
    doc = interiors_data()
    for name, rec in doc.items():
        if name != "references" and name.lower() == body_name.strip().lower():
            return _interior(name, rec)
    return Interior(body_name.strip(), RIGID, why="not listed in data/interiors.toml: no interior resonance is "
                    "applied, the body is treated as rigid")


def interior_record(body_name: str) -> dict:
    """:meth:`Interior.as_dict` of :func:`interior_of` ``body_name``: what the body answer shows as ``interior``."""
    return interior_of(body_name).as_dict()


def fcn_frequency(fcn_period_days: float) -> float:
    """σ_FCN = 2π / P_FCN (rad/day) of a signed FCN period in days (negative: retrograde)."""
    p = float(fcn_period_days)
    if not math.isfinite(p) or p == 0.0:
        raise InvalidInputError("fcn_period_days", f"must be finite and non-zero, got {fcn_period_days!r}")
    return 2.0 * math.pi / p


def _check_factor(F) -> float:
    f = float(F)
    if not math.isfinite(f):
        raise InvalidInputError("fcn_amplitude_factor", f"must be finite, got {F!r}")
    return f


def fluid_core_transfer(sigma_rad_per_day, F: float, fcn_period_days: float) -> np.ndarray:
    """T(σ) = 1 + F σ / (σ − σ_FCN) of a liquid core in a rigid mantle (Le Maistre et al. 2023's form).

    ``sigma_rad_per_day``: the circular component's frequency in inertial space, rad/day, prograde positive (any
    shape); ``F``: the amplification factor; ``fcn_period_days``: P_FCN in days (negative, retrograde). Returns a
    float array shaped like σ. Raises :class:`InvalidInputError` naming ``sigma_rad_per_day`` for a non-finite σ
    or one at the resonance (σ = σ_FCN), ``fcn_amplitude_factor`` or ``fcn_period_days`` for a bad parameter.
    """
    sigma = np.asarray(sigma_rad_per_day, dtype=float)
    if not np.all(np.isfinite(sigma)):
        raise InvalidInputError("sigma_rad_per_day", "must be finite")
    f = _check_factor(F)
    s0 = fcn_frequency(fcn_period_days)
    gap = sigma - s0
    if np.any(np.abs(gap) <= 1e-12 * abs(s0)):
        raise InvalidInputError("sigma_rad_per_day", f"equals the free core nutation frequency {s0!r} rad/day: "
                                "the resonance's response is infinite there")
    return 1.0 + f * sigma / gap


def circular_parts(lon_sin, lon_cos, obl_sin, obl_cos, sin_eps: float):
    """(c₊, c₋), complex arrays: Δψ sin ε + iΔε = c₊ e^{iφ} + c₋ e^{−iφ} (module docstring)."""
    s, c, f, e = (np.asarray(v, dtype=float) for v in (lon_sin, lon_cos, obl_sin, obl_cos))
    plus = 0.5 * ((sin_eps * c + f) + 1j * (e - sin_eps * s))
    minus = 0.5 * ((sin_eps * c - f) + 1j * (e + sin_eps * s))
    return plus, minus


def from_circular_parts(plus, minus, sin_eps: float):
    """Inverse of :func:`circular_parts`: (lon_sin, lon_cos, obl_sin, obl_cos)."""
    a, b, c, d = plus.real, plus.imag, minus.real, minus.imag
    return (d - b) / sin_eps, (a + c) / sin_eps, a - c, b + d


def _inputs(frequency_rad_per_day, obliquity_rad):
    nu = np.asarray(frequency_rad_per_day, dtype=float)
    if not np.all(np.isfinite(nu)):
        raise InvalidInputError("frequency_rad_per_day", "must be finite")
    eps = float(obliquity_rad)
    se = math.sin(eps) if math.isfinite(eps) else float("nan")
    if not math.isfinite(se) or abs(se) < 1e-12:
        raise InvalidInputError("obliquity_rad", f"must be finite and not a multiple of pi (sin eps divides the "
                                f"longitude), got {obliquity_rad!r}")
    return nu, se


def apply_fluid_core(lon_sin, lon_cos, obl_sin, obl_cos, frequency_rad_per_day, obliquity_rad: float, F: float,
                     fcn_period_days: float):
    """The non-rigid coefficients of rigid nutation terms: each prograde component times T(+φ̇), each retrograde
    one times T(−φ̇).

    Inputs: the rigid coefficients (radians, or any unit: the map is linear) of Δψ = lon_sin sin φ + lon_cos cos φ,
    Δε = obl_sin sin φ + obl_cos cos φ (:class:`ephem.forced.kinoshita.NutationSeries`), the argument's rate φ̇ in
    rad/day (k n for the harmonic kM; a negative rate is allowed, its c₊ is then retrograde), the mean obliquity
    (radians), F and P_FCN (days). Returns (lon_sin, lon_cos, obl_sin, obl_cos) arrays, same unit.
    """
    nu, se = _inputs(frequency_rad_per_day, obliquity_rad)
    plus, minus = circular_parts(lon_sin, lon_cos, obl_sin, obl_cos, se)
    t_plus = fluid_core_transfer(nu, F, fcn_period_days)
    t_minus = fluid_core_transfer(-nu, F, fcn_period_days)
    return from_circular_parts(t_plus * plus, t_minus * minus, se)


def _transfer_derivatives(sigma, F, fcn_period_days):
    """∂T/∂F and ∂T/∂P at σ (analytic): σ/(σ−σ0) and F σ/(σ−σ0)² · dσ0/dP, dσ0/dP = −2π/P²."""
    s0 = fcn_frequency(fcn_period_days)
    gap = sigma - s0
    return sigma / gap, F * sigma / gap**2 * (-2.0 * math.pi / float(fcn_period_days) ** 2)


def _outputs(coeffs):
    """The four coefficients and the two amplitudes |Δψ| = hypot(lon_sin, lon_cos), |Δε| = hypot(obl_sin, obl_cos)."""
    s, c, f, e = coeffs
    return np.stack([s, c, f, e, np.hypot(s, c), np.hypot(f, e)])


def transfer_sigma(F: float, fcn_period_days: float, F_sigma: float, fcn_period_days_sigma: float,
                   lon_sin, lon_cos, obl_sin, obl_cos, frequency_rad_per_day, obliquity_rad: float,
                   method: str = "analytic") -> np.ndarray:
    """1σ of the non-rigid terms from the parameters' 1σ (F and P_FCN independent: no correlation is published).

    Linear propagation σ² = (∂y/∂F σ_F)² + (∂y/∂P σ_P)² for y each of: lon_sin, lon_cos, obl_sin, obl_cos, the
    longitude amplitude hypot(lon_sin, lon_cos) and the obliquity amplitude hypot(obl_sin, obl_cos) of
    :func:`apply_fluid_core`'s output (the rigid terms carry no σ here: this is the core's share). ``method``:
    "analytic" (∂T/∂F = σ/(σ−σ0), ∂T/∂σ0 = Fσ/(σ−σ0)², the coefficients linear in T) or "central" (central
    differences, steps σ_F/100 and σ_P/100; truncation ~1e-4 of the curvature over ±1σ). Returns an array (6, N)
    in the coefficients' unit, rows in the order above.
    """
    if method not in ("analytic", "central"):
        raise InvalidInputError("method", f"must be 'analytic' or 'central', got {method!r}")
    for name, v in (("fcn_amplitude_factor_uncertainty", F_sigma), ("fcn_period_days_uncertainty",
                                                                   fcn_period_days_sigma)):
        if not math.isfinite(float(v)) or float(v) < 0.0:
            raise InvalidInputError(name, f"must be finite and >= 0, got {v!r}")
    nu, se = _inputs(frequency_rad_per_day, obliquity_rad)
    rigid = (lon_sin, lon_cos, obl_sin, obl_cos)
    if method == "central":
        def at(f, p):
            return _outputs(apply_fluid_core(*rigid, nu, obliquity_rad, f, p))
        hf, hp = F_sigma / 100.0, fcn_period_days_sigma / 100.0
        d_f = (at(F + hf, fcn_period_days) - at(F - hf, fcn_period_days)) / (2 * hf) if hf > 0 else 0.0
        d_p = (at(F, fcn_period_days + hp) - at(F, fcn_period_days - hp)) / (2 * hp) if hp > 0 else 0.0
    else:
        plus, minus = circular_parts(*rigid, se)
        dtf_p, dtp_p = _transfer_derivatives(nu, F, fcn_period_days)
        dtf_m, dtp_m = _transfer_derivatives(-nu, F, fcn_period_days)
        y = _outputs(apply_fluid_core(*rigid, nu, obliquity_rad, F, fcn_period_days))
        rows = []
        for dp, dm in ((dtf_p, dtf_m), (dtp_p, dtp_m)):
            ds, dc, df, de = from_circular_parts(dp * plus, dm * minus, se)
            with np.errstate(invalid="ignore", divide="ignore"):
                d_lon = np.where(y[4] > 0, (y[0] * ds + y[1] * dc) / y[4], np.hypot(ds, dc))
                d_obl = np.where(y[5] > 0, (y[2] * df + y[3] * de) / y[5], np.hypot(df, de))
            rows.append(np.stack([ds, dc, df, de, d_lon, d_obl]))
        d_f, d_p = rows
    return np.hypot(np.asarray(d_f) * F_sigma, np.asarray(d_p) * fcn_period_days_sigma)
