"""Kinoshita's theory of the forced precession and nutation, one perturber on a fixed Keplerian orbit.

References: Kinoshita (1977), Celest. Mech. 15, 277; Petit, Souchay & Lhotka
(2014), A&A 565, A79, eqs. 9-25.

Pure numerics: radians, days, rad/day. Conventions are the paper's: ψ is the
precession in longitude (ψ = -h), ε the obliquity (ε = -I); ψ̇ > 0 is a
retrograde precession (as the Earth's), ψ̇ < 0 a prograde one.

First order in the torque, rotation-averaged, the figure, rotation and
angular-momentum axes taken as one (J = 0), the triaxial P_2^2 term of the
potential dropped (it averages out over a rotation). With λ the Sun's
longitude from the body's equinox, K = 3 n² H_d / ω and (a/r)^3 from the orbit:

    dψ/dt = (K/2) cos ε (a/r)^3 (1 - cos 2λ)
    dε/dt = -(K/2) sin ε (a/r)^3 sin 2λ

Writing λ = θ + ν (θ: equinox to pericentre) and expanding with the Hansen
coefficients of :mod:`ephem.orbit.hansen` (C' = cos 2θ, S' = sin 2θ):

    Δψ = (K/2) cos ε Σ_k [(C0_k - C' C2_k) sin kM - S' S2_k cos kM] / (k n)
    Δε = -(K/2) sin ε Σ_k [S' C2_k sin kM - C' S2_k cos kM] / (k n)

which is the paper's eqs. 20 and 22 with sin I read as sin ε. The paper's
Tables 6 and 8 carry the opposite sign of Δε (see data/errata.toml); the
sign here is the one the numerical integration of the torque confirms.
The series are summed by :mod:`ephem.orbit.harmonics`.
"""
from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..orbit.hansen import hansen_exact, hansen_series
from ..orbit.harmonic_grid import evaluate_harmonics_uniform
from ..orbit.harmonics import evaluate_harmonics, series_extrema


def scaling_factor(n: float, omega: float, hd: float) -> float:
    """K = 3 n² H_d / ω (Petit et al. eq. 10), in the unit of n and ω (rad per time)."""
    return 3.0 * n * n * hd / omega


def eccentricity_factor(e: float, order: int | None = None) -> float:
    """The mean of (a/r)^3 over the orbit, (1 - e²)^(-3/2), or its e-power series to e^order.

    order=4 gives the paper's 1 + 3/2 e² + 15/8 e⁴ (eq. 25).
    """
    if order is None:
        return (1.0 - e * e) ** -1.5
    total, coeff = 0.0, 1.0
    for j in range(order // 2 + 1):
        total += coeff * e ** (2 * j)
        coeff *= (2 * j + 3) / (2 * j + 2)  # binomial series of (1 - x)^(-3/2)
    return total


def precession_rate(K: float, obliquity: float, e: float, order: int | None = None) -> float:
    """Secular rate ψ̇ = (K/2) cos ε (1 - e²)^(-3/2) (Petit et al. eq. 25, exact in e by default); columns of a
    population give a column."""
    rate = 0.5 * K * np.cos(obliquity) * eccentricity_factor(e, order)
    return float(rate) if np.ndim(rate) == 0 else rate


@dataclass(frozen=True)
class NutationSeries:
    """Nutation in longitude and obliquity as harmonics of the mean anomaly M.

        Δψ(M) = Σ_k lon_sin[k] sin kM + lon_cos[k] cos kM
        Δε(M) = Σ_k obl_sin[k] sin kM + obl_cos[k] cos kM

    Coefficients in radians; ``multiple`` the k's; ``mean_motion`` n in rad/day.
    """

    multiple: np.ndarray
    lon_sin: np.ndarray
    lon_cos: np.ndarray
    obl_sin: np.ndarray
    obl_cos: np.ndarray
    mean_motion: float
    order: int | None
    #: what the harmonics dropped below ``min_amplitude`` can move the pole in all (radians, the
    #: :func:`pole_displacement_sum` of the tail :func:`nutation_series` cut)
    dropped: float = 0.0

    @property
    def period_days(self) -> np.ndarray:
        return 2.0 * math.pi / (self.multiple * self.mean_motion)

    def evaluate(self, mean_anomaly) -> tuple[np.ndarray, np.ndarray]:
        """Δψ and Δε (radians) at mean anomalies M (any array shape)."""
        return evaluate_harmonics(mean_anomaly, self.multiple, self._sin_coef, self._cos_coef)

    def evaluate_uniform(self, m_start: float, m_step: float, count: int) -> tuple[np.ndarray, np.ndarray]:
        """Δψ and Δε on the evenly spaced grid M = m_start + j m_step, j = 0..count-1 (faster)."""
        return evaluate_harmonics_uniform(m_start, m_step, count, self.multiple, self._sin_coef, self._cos_coef)

    @property
    def _sin_coef(self) -> np.ndarray:
        return np.stack([self.lon_sin, self.obl_sin], axis=1)

    @property
    def _cos_coef(self) -> np.ndarray:
        return np.stack([self.lon_cos, self.obl_cos], axis=1)

    def semi_peak_to_peak(self) -> tuple[float, float]:
        """Half the peak-to-peak excursion of Δψ and of Δε over one orbit (radians).

        This is what Petit et al. Table 4 lists as "Δψ" and "Δε" (:func:`ephem.orbit.harmonics.series_extrema`).
        """
        if self.multiple.size == 0:  # every term below the amplitude cut
            return 0.0, 0.0
        return (series_extrema(self.lon_sin, self.lon_cos)[0], series_extrema(self.obl_sin, self.obl_cos)[0])


def nutation_coefficients(K: float, n: float, obliquity: float, equinox_to_pericentre: float, k,
                          c0, c2, s2) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The nutation's coefficients from the Hansen coefficients (Petit et al. 2014, eqs. 20 and 22).

    With C' = cos 2θ, S' = sin 2θ (θ = ``equinox_to_pericentre``, ε = ``obliquity``, radians) and
    C0_k, C2_k, S2_k the Hansen coefficients of (a/r)^3, (a/r)^3 cos 2ν and (a/r)^3 sin 2ν
    (:mod:`ephem.orbit.hansen`) at the multiples ``k`` of the mean anomaly:

        lon_sin_k =  (K/2) cos ε (C0_k - C' C2_k) / (k n)     lon_cos_k = -(K/2) cos ε S' S2_k / (k n)
        obl_sin_k = -(K/2) sin ε S' C2_k / (k n)              obl_cos_k =  (K/2) sin ε C' S2_k / (k n)

    so that Δψ = Σ lon_sin_k sin kM + lon_cos_k cos kM and Δε likewise (the sign of Δε is the
    one the integration of the torque confirms, opposite to the paper's Tables 6 and 8: see the
    module docstring). K (:func:`scaling_factor`) and n in one unit of rad per time; the four
    arrays (shaped like ``k``) in radians. No amplitude cut (:func:`nutation_series` applies one). For a
    population, K, n, ε and θ may be columns (N, 1) against rows ``k`` and coefficients (N, kmax).
    """
    cp, sp = np.cos(2.0 * equinox_to_pericentre), np.sin(2.0 * equinox_to_pericentre)
    f_psi = 0.5 * K * np.cos(obliquity) / (k * n)
    f_eps = -0.5 * K * np.sin(obliquity) / (k * n)
    return f_psi * (c0 - cp * c2), -f_psi * sp * s2, f_eps * sp * c2, -f_eps * cp * s2


#: Fixed-point passes of :func:`mean_pole` for a nutation that depends on the mean pole: each pass
#: multiplies the error by ~ the nutation's amplitude (radians), so three leave rounding.
MEAN_POLE_PASSES = 3


def mean_pole(obliquity: float, equinox_to_pericentre: float,
              nutation_at_pole_epoch: Callable[[float, float], tuple[float, float]],
              passes: int = MEAN_POLE_PASSES) -> tuple[float, float, float, float]:
    """The mean pole at the pole epoch t0 from the instantaneous one: (ε̄, θ̄, Δψ(t0), Δε(t0)), radians.

    The catalogue pole is the instantaneous spin axis at t0, the mean pole plus the nutation there:
    ε = ε̄ + Δε(t0), θ = θ̄ + Δψ(t0) (θ the equinox-to-pericentre angle; the instantaneous equinox
    is the mean one moved by Δψ). The nutation itself depends on the mean pole (Petit et al. 2014,
    eqs. 20 and 22, through ε̄ and θ̄: :func:`nutation_coefficients`), so this iterates the fixed point

        ε̄ ← ε - Δε(t0; ε̄, θ̄),    θ̄ ← θ - Δψ(t0; ε̄, θ̄)

    from ε̄ = ε, θ̄ = θ, ``passes`` times. ``nutation_at_pole_epoch(ε̄, θ̄)`` gives (Δψ(t0), Δε(t0))
    in radians for a trial mean pole; the returned Δψ(t0), Δε(t0) are those of the last pass and
    ε̄ = ε - Δε(t0), θ̄ = θ - Δψ(t0) hold exactly, so a track built from that pass's nutation
    starts at the catalogue pole (a caller needing that pass's series keeps it from its callable).
    A nutation independent of the mean pole (the Earth's lunisolar series, built at IAU 2006's
    obliquity) needs ``passes=1``.
    """
    if passes < 1:
        raise ValueError("mean_pole needs at least one pass")
    scalar = np.ndim(obliquity) == 0          # a population's arrays pass through as arrays
    dpsi0 = deps0 = 0.0
    for _ in range(passes):
        dpsi, deps = nutation_at_pole_epoch(obliquity - deps0, equinox_to_pericentre - dpsi0)
        dpsi0, deps0 = (float(dpsi), float(deps)) if scalar else (dpsi, deps)
    return obliquity - deps0, equinox_to_pericentre - dpsi0, dpsi0, deps0


def _four_columns(coefficients):
    """(lon_sin, lon_cos, obl_sin, obl_cos) of a :class:`NutationSeries` (or any object with those
    attributes) or of an array (N, 4) whose columns are these (the lunisolar series' ``coefficients``)."""
    if hasattr(coefficients, "lon_sin"):
        return coefficients.lon_sin, coefficients.lon_cos, coefficients.obl_sin, coefficients.obl_cos
    c = np.asarray(coefficients, dtype=float)
    if c.ndim != 2 or c.shape[1] != 4:
        raise ValueError(f"expected a NutationSeries or an (N, 4) array of (Δψ sin, Δψ cos, Δε sin, Δε cos), "
                         f"got shape {c.shape}")
    return c[:, 0], c[:, 1], c[:, 2], c[:, 3]


def pole_displacements(coefficients, obliquity: float) -> np.ndarray:
    """Per term, the most it can move the pole: |sin ε| sqrt(S_ψ² + C_ψ²) + sqrt(S_ε² + C_ε²).

    A term S sin φ + C cos φ has the amplitude sqrt(S² + C²); a change Δψ of the longitude moves
    the pole by sin ε |Δψ| on the sphere and a change Δε of the obliquity by |Δε|, so their sum
    bounds the pole's displacement by the term (first order in the nutation). ``coefficients``: a
    :class:`NutationSeries` or an (N, 4) array of (Δψ sin, Δψ cos, Δε sin, Δε cos), e.g. the
    lunisolar series' ``coefficients``; the result is in their unit (radians, or mas for those).
    """
    lon_sin, lon_cos, obl_sin, obl_cos = _four_columns(coefficients)
    return abs(math.sin(obliquity)) * np.hypot(lon_sin, lon_cos) + np.hypot(obl_sin, obl_cos)


def pole_displacement_sum(coefficients, obliquity: float) -> float:
    """Σ over the terms of :func:`pole_displacements`: how far the nutation can move the pole from the
    mean pole (in the coefficients' unit)."""
    return float(np.sum(pole_displacements(coefficients, obliquity)))


#: the amplitude (radians; 2 nano-arcseconds) under which the trailing harmonics of a series are dropped
TERM_FLOOR = 1e-14
#: the relative rounding of an exact (FFT) Hansen coefficient and the nutation coefficient made from it, with
#: margin: an FFT of length N rounds to ~ε log2 N (N <= 2^16 here), the coefficient's formula adds a few ε
EXACT_ROUNDING = 64.0 * float(np.finfo(float).eps)


def exact_series_floor(dropped, kept_displacement):
    """The estimate of a series with exact Hansen coefficients (radians; arrays broadcast): the trailing
    harmonics dropped under TERM_FLOOR, twice (they also move the mean pole through the nutation removed at the
    pole epoch), and EXACT_ROUNDING of what the kept terms can move the pole. Never 0 for a real series."""
    return 2.0 * dropped + EXACT_ROUNDING * kept_displacement


def nutation_series(K: float, n: float, obliquity: float, e: float, equinox_to_pericentre: float,
                    order: int | None = None, min_amplitude: float = TERM_FLOOR) -> NutationSeries:
    """Nutation coefficients (Petit et al. eqs. 20, 22; radians).

    K and n in rad/day; ``order`` None for exact Hansen coefficients, else the
    e-power truncation order (the paper's eqs. 23-24 are order 4). Harmonics
    whose four coefficients are all below ``min_amplitude`` (radians; the
    default is 2 nano-arcseconds) are dropped.
    """
    if order is None:
        h = hansen_exact(e)
    else:
        h = hansen_series(order).evaluate(e)
    k = np.asarray(h.k[1:], dtype=float)
    lon_sin, lon_cos, obl_sin, obl_cos = nutation_coefficients(K, n, obliquity, equinox_to_pericentre, k,
                                                               h.c0[1:], h.c2[1:], h.s2[1:])
    big = np.max(np.abs(np.stack([lon_sin, lon_cos, obl_sin, obl_cos])), axis=0) >= min_amplitude
    keep = np.nonzero(big)[0]
    last = keep[-1] + 1 if keep.size else 0
    sl = slice(0, last)
    dropped = pole_displacement_sum(np.column_stack([c[last:] for c in (lon_sin, lon_cos, obl_sin, obl_cos)]),
                                    obliquity)
    return NutationSeries(h.k[1:][sl].astype(int), lon_sin[sl], lon_cos[sl], obl_sin[sl],
                          obl_cos[sl], n, order, dropped)


@dataclass(frozen=True)
class NutationComponents:
    """The nutation split by its dependence on the equinox-to-pericentre angle θ.

    With C' = cos 2θ and S' = sin 2θ (the paper's constants) the first-order series is

        Δψ = cos ε (a(M) - C' b(M) - S' c(M)),    Δε = -sin ε (S' b(M) - C' c(M))

    where a = Σ (K/2kn) C0_k sin kM, b = Σ (K/2kn) C2_k sin kM, c = Σ (K/2kn) S2_k cos kM.
    Holding θ and ε fixed gives :func:`nutation_series`; letting them drift with the
    precession (θ = θ̄0 + ψ̄) is the second-order theory (:mod:`ephem.forced.second_order`).
    Radians; ``mean_motion`` in rad/day.
    """

    multiple: np.ndarray
    sin_coef: np.ndarray  # (kmax, 3): columns a, b, c
    cos_coef: np.ndarray
    mean_motion: float
    order: int | None

    def evaluate(self, mean_anomaly) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """a, b, c (radians) at mean anomalies M."""
        return evaluate_harmonics(mean_anomaly, self.multiple, self.sin_coef, self.cos_coef)

    @staticmethod
    def combine(a, b, c, obliquity, equinox_to_pericentre):
        """Δψ, Δε (radians) from a, b, c and the (possibly time-dependent) ε and θ."""
        cp, sp = np.cos(2.0 * equinox_to_pericentre), np.sin(2.0 * equinox_to_pericentre)
        return np.cos(obliquity) * (a - cp * b - sp * c), -np.sin(obliquity) * (sp * b - cp * c)


def nutation_components(K: float, n: float, e: float, order: int | None = None,
                        min_amplitude: float = 1e-14) -> NutationComponents:
    """The θ-free parts a, b, c of the nutation (see :class:`NutationComponents`).

    Harmonics whose three coefficients are all below ``min_amplitude`` (radians)
    are dropped from the end of the series.
    """
    h = hansen_exact(e) if order is None else hansen_series(order).evaluate(e)
    k = np.asarray(h.k[1:], dtype=float)
    amp = 0.5 * K / (k * n)
    zero = np.zeros_like(k)
    sin_coef = np.stack([amp * h.c0[1:], amp * h.c2[1:], zero], axis=1)
    cos_coef = np.stack([zero, zero, amp * h.s2[1:]], axis=1)
    big = np.nonzero(np.max(np.abs(sin_coef) + np.abs(cos_coef), axis=1) >= min_amplitude)[0]
    last = big[-1] + 1 if big.size else 0
    return NutationComponents(np.asarray(h.k[1:][:last], dtype=int), sin_coef[:last], cos_coef[:last], n, order)
