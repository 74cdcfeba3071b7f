"""What the analytic rungs leave of the geodesic (de Sitter) precession: the ladder's ``geodesic`` error term.

Every track turns the torque's solution about the orbit normal by the orbit-averaged geodesic rate Ω_gp
(:mod:`ephem.orbit.relativity`, ``PrecessionNutation.track_rate``). The numerical rungs integrate the
instantaneous rate instead (:mod:`ephem.forced.integration`), which along a Keplerian orbit is

    Ω(t) = (3/2) (G M / c²) h / r³ = Ω_gp (a/r)³ (1 − e²)^(3/2),

so the angle turned since pericentre is (Ω_gp / n) (ν + e sin ν) (with h/r² = ν̇ and 1/r = (1 + e cos ν)/p).
Against the uniform Ω_gp t, the analytic rungs 1-3 leave (rung 4 adds the periodic part, so leaves the second):

* the periodic part g(M) = (Ω_gp / n)(ν + e sin ν − M) (the "geodesic nutation"): the pole, at the angle ε
  from the orbit normal, moves by sin ε |g(M) − g(M0)|, its largest over the mean anomalies the epochs cover
  (sampled, with the slope bound |g'| <= (Ω_gp / n)((1 + e)³ / (1 − e²)^(3/2) + 1) times half the spacing;
  over whole orbits, 2 max |g|, :func:`periodic_excess`);
* the re-phasing: the geodesic rotation moves the equinox by δφ = Ω_gp (t − t0) more than the torque's
  precession, which the rotated torque solution holds fixed. The first-order nutation depends on φ through
  (cos 2φ, sin 2φ), so it moves by at most 2 |sin δφ| w |(b, c)| (as in
  :func:`ephem.sun.bounds.second_order_bound`); the second-order periodic terms by δφ sup |∂P2/∂φ|; the
  second-order mean rates G(φ) by sup |∂G/∂φ| δφ over the span, integrated: sup |∂G/∂φ| Ω_gp T²/2.

For the asteroids this is a few micro-arcseconds to 2 mas (Itokawa: the periodic part, e = 0.28); the
geodesic precession itself (Ω_gp T: 10 mas per year for Itokawa) is in every track. Radians, days.
"""
from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from ..orbit.relativity import geodesic_periodic

#: Samples of the eccentric anomaly over one orbit for max |ν + e sin ν − M|: the function is smooth in E (its
#: derivative in E is at most 2 (1 + e)/(1 − e) + 1); the margin below covers what the grid misses.
_E_SAMPLES = 65536
#: Samples of the mean anomaly over a window shorter than an orbit.
_M_SAMPLES = 1024


@lru_cache(maxsize=256)
def periodic_excess(e: float) -> float:
    """max over one orbit of |ν + e sin ν − M| (radians), e in [0, 1): the geodesic angle's departure from its
    uniform mean, per unit Ω_gp / n."""
    ecc = np.linspace(0.0, 2.0 * math.pi, _E_SAMPLES, endpoint=False)
    x = geodesic_periodic(e, ecc - e * np.sin(ecc))
    slope = 2.0 * (1.0 + e) / max(1.0 - e, 1e-12) + 1.0
    return float(np.max(np.abs(x))) + slope * (math.pi / _E_SAMPLES)


def periodic_reach(e: float, m_lo: float, m_hi: float, m0: float) -> float:
    """max of |g(M) − g(M0)| per unit Ω_gp / n (g = ν + e sin ν − M) over the mean anomalies [m_lo, m_hi]
    (radians, unwrapped): sampled, plus the slope bound times half the spacing; 2 :func:`periodic_excess` over
    a whole orbit or more."""
    if m_hi - m_lo >= 2.0 * math.pi:
        return 2.0 * periodic_excess(e)
    m = np.linspace(m_lo, m_hi, _M_SAMPLES)
    ref = float(geodesic_periodic(e, np.array([m0]))[0])
    slope = (1.0 + e) ** 3 / max(1.0 - e * e, 1e-24) ** 1.5 + 1.0
    sampled = float(np.max(np.abs(geodesic_periodic(e, m) - ref)))
    return min(2.0 * periodic_excess(e), sampled + slope * 0.5 * (m_hi - m_lo) / (_M_SAMPLES - 1))


def geodesic_bounds(model, rate_harmonics: np.ndarray, weight: float, bc: float,
                    slope_phi: float, mean_anomalies: tuple[float, float], m0: float, span_days: float
                    ) -> tuple[float, float]:
    """The ``geodesic`` term (radians) over the epochs of rungs 1-3, and of rung 4, which adds the periodic part
    exactly (:func:`ephem.orbit.relativity.geodesic_angle`) and leaves only the re-phasing (module docstring).

    ``model`` a :class:`ephem.forced.precession_nutation.PrecessionNutation` (read by its attributes: this module
    sits below it in the import stack); ``rate_harmonics``: the second-order mean rates' φ-harmonics (2, 5) (:func:`ephem.sun.bounds.mean_rate_harmonics`);
    ``weight`` the pole weight on longitudes, ``bc`` the largest |(b, c)| of the θ-dependent nutation and
    ``slope_phi`` the largest |∂P2/∂φ| over the epochs (:class:`ephem.sun.bounds.TheoryTables`); ``mean_anomalies``
    those of the first and last epoch (unwrapped), ``m0`` the pole epoch's, ``span_days`` the largest |t − t0|."""
    omega = abs(model.geodesic_rate)
    if omega == 0.0:
        return 0.0, 0.0
    sin_eps = abs(math.sin(model.obliquity))
    periodic = sin_eps * omega / model.mean_motion * periodic_reach(model.eccentricity, *mean_anomalies, m0)
    shift = omega * span_days
    rephasing = 2.0 * min(1.0, shift) * weight * bc + shift * slope_phi
    # ∂G/∂φ of the mean rates (φ-harmonics c0, c1, s1, c2, s2 of 2φ, 4φ): at most 2|c1, s1| + 4|c2, s2|
    slope = 2.0 * np.abs(rate_harmonics[:, 1:3]).sum(axis=1) + 4.0 * np.abs(rate_harmonics[:, 3:5]).sum(axis=1)
    mean_rates = math.hypot(weight * slope[0], slope[1]) * omega * span_days * span_days / 2.0
    return periodic + rephasing + mean_rates, rephasing + mean_rates
