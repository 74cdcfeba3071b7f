"""A body's interior applied to its forced nutation: the non-rigid series, and what it changes and leaves.

The interior model is the body's (``data/interiors.toml``, :mod:`ephem.bodies.interior`). A body with a liquid
core in a rigid mantle (``form = "fluid_core_resonance"``: Mars) answers each circular component of its rigid
nutation with the transfer function T(σ) = 1 + F σ / (σ − σ_FCN) (:func:`ephem.bodies.interior.apply_fluid_core`);
the harmonic kM of Kinoshita's Sun-only series turns at σ = ±k n in inertial space (the precession's share of the
argument's rate, ψ̇/n ~ 1e-5 for Mars, is left out: it moves T by less than 1e-6). T(0) = 1: the precession is the
torque's (its rate was measured on the real body). The Earth's transfer function is applied by the lunisolar
family (:mod:`ephem.earth.model`); every other body is rigid and says why.

The estimates a served non-rigid answer carries (radians, upper bounds on the pole's displacement over any span,
first order in the nutation: :func:`ephem.forced.kinoshita.pole_displacements`):

* :func:`core_change_bound`: what the core changes, the error a rigid answer makes against the body (every rigid
  rung of such a body carries it as ``interior_rigid``);
* :func:`parameter_bound`: how far the served non-rigid series can move from the true one because F and P_FCN
  are known to their σ only: the largest change over the corners of the 2σ box (F ± 2σ_F, P ± 2σ_P; the change
  is linear in F and monotonic in P away from the resonance, so the corners hold the extremes, with no
  linearisation near the resonance, where the linear σ fails: docs/interiors.md);
* :func:`mantle_bound`: the mantle's elastic and anelastic response, which the single resonance leaves out. No
  published Mars value could be read; the bound scales the Earth's: the IERS 1996 transfer function's
  non-resonant slope |R'| = 0.258 per cycle per sidereal day (data/nonrigid.toml) times Mars' tidal Love number
  over the Earth's, doubled (``mantle_elastic_scale`` in data/interiors.toml), times each component's |σ| in
  cycles per sidereal day of the body.

Each periodic change enters the track relative to the pole epoch (the catalogue pole is where every track starts),
so each bound is twice the change's pole displacement.
"""
from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from ..bodies.catalogue import Body
from ..bodies.interior import FLUID_CORE, Interior, apply_fluid_core, interior_of, transfer_sigma
from .kinoshita import NutationSeries, pole_displacement_sum

#: the number of standard deviations of F and P_FCN the served estimate allows (an upper bound, not a 1σ)
PARAMETER_SIGMAS = 2.0


#: why a body of the user's own is rigid
USER_BODY_RIGID = ("a body of your own has no interior model here (data/interiors.toml describes the catalogue's "
                   "bodies): it is rigid")


def fluid_core(body: Body) -> Interior | None:
    """The catalogue body's interior model when it is a fluid-core resonance (the one the Sun-only answers apply),
    else None (a rigid body, the Earth's own transfer function, or a body of the user's own)."""
    if body.dataset == "user":
        return None
    interior = interior_of(body.name)
    return interior if interior.form == FLUID_CORE else None


def not_applicable(body: Body) -> str | None:
    """Why the non-rigid answer does not apply to the body (None when it does): the body is rigid (the catalogue's
    reason), or its interior is applied elsewhere (the Earth's, by the lunisolar family)."""
    if body.dataset == "user":
        return USER_BODY_RIGID
    interior = interior_of(body.name)
    if interior.form == FLUID_CORE:
        return None
    if interior.model == "rigid":
        return f"the body is rigid in this project: {interior.why}"
    return (f"its interior model ({interior.form}) is applied by its own family, not here: the Sun-only answers "
            "apply a fluid-core resonance only (for the Earth, ask for its Moon and Sun perturbers and "
            "model 'nonrigid')")


def _parameters(interior: Interior) -> tuple[float, float]:
    p = interior.parameters
    return p["fcn_amplitude_factor"].value, p["fcn_period_days"].value


def nonrigid_series(series: NutationSeries, obliquity: float, interior: Interior, F: float | None = None,
                    fcn_period_days: float | None = None) -> NutationSeries:
    """The series with the fluid core's response: each harmonic kM's prograde component times T(+k n), its
    retrograde one times T(−k n). ``F``, ``fcn_period_days`` default to the interior's published values."""
    f0, p0 = _parameters(interior)
    f = f0 if F is None else F
    p = p0 if fcn_period_days is None else fcn_period_days
    nu = np.asarray(series.multiple, dtype=float) * series.mean_motion
    if nu.size == 0:
        return series
    lon_sin, lon_cos, obl_sin, obl_cos = apply_fluid_core(series.lon_sin, series.lon_cos, series.obl_sin,
                                                          series.obl_cos, nu, obliquity, f, p)
    return replace(series, lon_sin=lon_sin, lon_cos=lon_cos, obl_sin=obl_sin, obl_cos=obl_cos)


def series_change(series: NutationSeries, obliquity: float, interior: Interior, F: float | None = None,
                  fcn_period_days: float | None = None) -> NutationSeries:
    """The core's change to the series (non-rigid minus rigid), a series of the same harmonics (radians)."""
    new = nonrigid_series(series, obliquity, interior, F, fcn_period_days)
    return replace(series, lon_sin=new.lon_sin - series.lon_sin, lon_cos=new.lon_cos - series.lon_cos,
                   obl_sin=new.obl_sin - series.obl_sin, obl_cos=new.obl_cos - series.obl_cos, dropped=0.0)


def term_sigmas(series: NutationSeries, obliquity: float, interior: Interior) -> np.ndarray:
    """The 1σ (radians) the core's parameters give each non-rigid term: rows lon_sin, lon_cos, obl_sin, obl_cos,
    |Δψ|, |Δε| (:func:`ephem.bodies.interior.transfer_sigma`, linear; near the resonance an order of magnitude)."""
    p = interior.parameters
    F, P = p["fcn_amplitude_factor"], p["fcn_period_days"]
    nu = np.asarray(series.multiple, dtype=float) * series.mean_motion
    return transfer_sigma(F.value, P.value, F.sigma or 0.0, P.sigma or 0.0, series.lon_sin, series.lon_cos,
                          series.obl_sin, series.obl_cos, nu, obliquity)


def _displacement(a: NutationSeries, obliquity: float) -> float:
    return pole_displacement_sum(np.column_stack([a.lon_sin, a.lon_cos, a.obl_sin, a.obl_cos]), obliquity)


def core_change_bound(series: NutationSeries, obliquity: float, interior: Interior) -> float:
    """What a rigid answer leaves out against the body (radians): twice the core change's pole displacement."""
    return 2.0 * _displacement(series_change(series, obliquity, interior), obliquity)


def parameter_bound(series: NutationSeries, obliquity: float, interior: Interior,
                    sigmas: float = PARAMETER_SIGMAS) -> float:
    """How far the non-rigid series can be from the one of the true F and P_FCN (radians): twice the largest
    pole displacement of (series at a corner of the ``sigmas``-σ box − series at the published values)."""
    p = interior.parameters
    f, per = _parameters(interior)
    sf = p["fcn_amplitude_factor"].sigma or 0.0
    sp = p["fcn_period_days"].sigma or 0.0
    served = nonrigid_series(series, obliquity, interior)
    worst = 0.0
    for df in (-sigmas * sf, sigmas * sf):
        for dp in (-sigmas * sp, sigmas * sp):
            corner = nonrigid_series(series, obliquity, interior, f + df, per + dp)
            diff = replace(series, lon_sin=corner.lon_sin - served.lon_sin, lon_cos=corner.lon_cos - served.lon_cos,
                           obl_sin=corner.obl_sin - served.obl_sin, obl_cos=corner.obl_cos - served.obl_cos)
            worst = max(worst, _displacement(diff, obliquity))
    return 2.0 * worst


def mantle_bound(series: NutationSeries, obliquity: float, interior: Interior, spin_rate: float) -> float:
    """The mantle's elastic response the single resonance leaves out (radians): each harmonic's pole displacement
    times ``mantle_elastic_scale`` × |k n| / ω (its frequency in cycles per sidereal day of the body), twice; 0 for
    an interior that states no such scale."""
    scale = interior.mantle_elastic_scale or 0.0
    relative = scale * np.abs(np.asarray(series.multiple, dtype=float) * series.mean_motion) / abs(spin_rate)
    served = nonrigid_series(series, obliquity, interior)
    scaled = replace(served, lon_sin=served.lon_sin * relative, lon_cos=served.lon_cos * relative,
                     obl_sin=served.obl_sin * relative, obl_cos=served.obl_cos * relative)
    return 2.0 * _displacement(scaled, obliquity)


def interior_terms(series: NutationSeries, obliquity: float, spin_rate: float, body: Body) -> dict:
    """The estimate terms of a body's answers (radians): ``interior_rigid`` for a rigid answer of a body with a
    fluid core, and ``interior_parameters`` and ``interior_mantle`` for its non-rigid answer. Empty for a body
    whose interior the Sun-only answers do not apply."""
    interior = fluid_core(body)
    if interior is None or not math.isfinite(obliquity):
        return {}
    return {"interior_rigid": core_change_bound(series, obliquity, interior),
            "interior_parameters": parameter_bound(series, obliquity, interior),
            "interior_mantle": mantle_bound(series, obliquity, interior, spin_rate)}
