"""The fidelity ladder: models of rising cost and accuracy, each with an error estimate; a tolerance picks one.

Rungs, cheapest first (names as reported in a track's ``model.name``):

1. ``secular``       ψ = ψ̇ (t - t0), ε = ε̄0: precession only.
2. ``series``        Kinoshita-Cayley nutation with the Hansen coefficients as e-power
                     series truncated at e^N (``order`` N; the paper: 4). Only below the
                     Laplace limit e < 0.6627, where the series converge.
3. ``hansen``        the same with exact Hansen coefficients (the science core's default).
4. ``second_order``  rung 3 with the equinox drift fed back into the phases and the
                     second-order mean rates (:mod:`ephem.forced.second_order`).
5. ``numerical``     the rotation-averaged torque integrated along the Keplerian orbit
                     (:mod:`ephem.forced.integration`).
6. ``real_orbit``    the same along the real, perturbed orbit from DE421
                     (:mod:`ephem.orbit.de421`), inside DE421's span (1899-2053).
7. the full rigid body (:mod:`ephem.forced.rigid_body`): a reference for what rotation averaging
   leaves out, too costly to serve (thousands of rotations per orbit).

Every rung carries an error *estimate*: an upper bound, in radians, on the angle
between its pole and the truth over the requested epochs, as a sum of named terms:

* ``nutation_omitted`` (rung 1): the largest the nutation reaches over the mean anomalies
  the epochs cover; ``truncation`` (rung 2): the largest the difference series (order N
  minus exact) moves the pole from where it was at the pole epoch, with the precession
  rates' difference;
* ``second_order`` (rungs 1-3): what the first-order theory leaves against rung 5 (the
  equinox drift, the second-order mean rates and periodic terms);
* ``higher_order`` (rung 4): what the second-order theory leaves (the second-order periodic
  nutation and the third-order drift, :class:`ephem.forced.second_order.Remainder`), with a
  third-order rest measured against rung 5;

The theory terms (the four above) are span-aware: every rung starts from the catalogue pole, so
each is the largest excursion since the pole epoch of a periodic function of the mean anomaly
over the orbit's part the epochs cover (a table over one orbit per body, no sum over the
epochs), plus drifts growing with the time from the pole epoch (``Window``, ``theory_terms``).
* ``integration`` (rungs 5-6): the ODE tolerance;
* ``orbit_motion`` (rungs 1-5): the fixed Keplerian orbit against the real one: for a catalogue
  body the gap measured between rungs 5 and 6 inside DE421 (``data/orbit_motion/``), beyond it
  extrapolated with the envelopes of ``data/orbit_motion.toml`` (:mod:`ephem.forced.physics_errors`);
* ``rotation_averaging`` (all): what averaging over the rotation leaves out against the full rigid
  body, for the axis followed and the rotation-scale terms the track includes
  (:func:`ephem.forced.rotation_scale.error_terms`);
* ``ephemeris`` (rung 6): the real orbit's own error; ``rounding``: double precision;
* ``free_wobble`` (all, for the figure axis): the published free-wobble amplitude J0 the track
  leaves out, or ``free_wobble_model`` when the track includes the wobble (:mod:`ephem.rotation.free_motion`).

Two poles can be asked for. ``axis="figure"`` (the default) is the body's axis of largest inertia,
the pole a body-fixed frame shows: it circles the angular momentum by the free wobble (amplitude
J0: Earth 1", Mars 0.1", Eros 55", Lara 2014 Table 1), which every rung adds only when the
tolerance needs it and its phase is given (``Wobble``). ``axis="angular_momentum"`` is the axis the
forced theory describes (the analogue of the IAU's celestial intermediate pole, which leaves the
free wobble to polar motion); the free wobble does not move it.

The estimate is a promise about the pole direction against the truth over the requested
epochs; it does not include the catalogue's own uncertainties (a pole known to 0.1° is
still 0.1° uncertain). :meth:`Ladder.choose` takes the cheapest rung whose estimate meets
a tolerance, or refuses naming the best one.

The tests hold each estimate against the next rungs up for many bodies and spans.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace
from functools import cached_property, lru_cache

import numpy as np

from ..theory import cost
from ..base.budget import charge
from ..bodies.catalogue import Body
from ..theory.cost import Cost
from ..base.constants import ARCSEC, J2000_JD, JULIAN_CENTURY_DAYS, JULIAN_YEAR_DAYS, MAS
from ..base.errors import InvalidInputError, NotApplicableError
from ..orbit.hansen import LAPLACE_LIMIT, hansen_exact, hansen_series
from ..orbit.kepler import mean_motion_rad_per_day
from ..base.memo import bytes_bounded
from ..forced.kinoshita import (eccentricity_factor, exact_series_floor, nutation_coefficients, pole_displacement_sum,
                                pole_displacements)
from ..forced.precession_nutation import (MAX_ORDER, MIN_SPIN_ORBIT_RATIO, PrecessionNutation, Track, cached_model,
                                          check_domain, model_for)
from ..rotation.free_motion import Wobble, add_free_wobble, free_wobble_bound, wobble_model_bound
from ..forced import rotation_scale
from ..forced.physics_errors import (ephemeris_bound, orbit_motion_bound, real_orbit_unavailable,
                                     rotation_averaging_bound, sun_path_for)
from ..forced.rigid_body import body_moments
from ..orbit.harmonics import FRESH_STEPS, PeriodicTable, harmonic_sum, refined_count
from ..longterm.averaged_spin import SpinConstants, spin_constants
from ..forced.second_order import (PhasedSeries, Remainder, SecondOrderTheory, eval_phi, second_order_remainder,
                                   second_order_theory)
from ..theory.interface import (COVERS_TRUNCATION, Estimate, SpinAxisTheory, Spectrum, cheapest_within, rate_values,
                                selection_info)
from ..forced.uncertainty import input_sigmas, propagated, summary
from ..forced.describe import ASSUMPTIONS, RUNG_ASSUMPTIONS, model_info
from ..theory.tracks import AXES, ROUNDING, pole_vectors, with_free_wobble

RUNGS = ("secular", "series", "hansen", "second_order", "numerical", "real_orbit")
#: Highest e-power order the ladder tries for rung 2 (a truncated series is cheaper than the
#: exact one only while it has fewer harmonics).
MAX_LADDER_ORDER = 20
#: Relative tolerance of the numerical rungs.
NUMERICAL_RTOL = 1e-12
#: The numerical rungs integrate through every orbit (~5 ms each); beyond this many orbits from the
#: pole epoch a request would tie up a worker for seconds, so they are not offered.
MAX_NUMERICAL_ORBITS = 1000


def _series_coefficients(model: PrecessionNutation, order: int | None, kmax: int):
    """The nutation coefficients (lon_sin, lon_cos, obl_sin, obl_cos) for k = 1..kmax at the model's ε̄, θ̄."""
    h = hansen_exact(model.eccentricity) if order is None else hansen_series(order).evaluate(model.eccentricity)
    out = np.zeros((4, kmax))
    m = min(kmax, len(h.k) - 1)
    k = np.arange(1, m + 1, dtype=float)
    out[:, :m] = nutation_coefficients(model.scaling_factor, model.mean_motion, model.obliquity,
                                       model.equinox_to_pericentre, k,
                                       *(np.asarray(x[1:m + 1]) for x in (h.c0, h.c2, h.s2)))
    return out


def truncation_bound(model: PrecessionNutation, order: int, span_days: float) -> float:
    """Whole-orbit bound (radians) on the pole error of the e^order series against the exact Hansen coefficients.

    Twice the sum of the coefficient differences (the track's error, plus the error it makes in the mean pole
    through the nutation removed at the pole epoch) and the difference of the precession rates over the span,
    whatever the epochs: the bound for the series as a whole, which the rate and nutation-terms answers use
    (:meth:`SunLadder.order_for_tolerance`). The ladder's estimate for given epochs is the tighter
    :func:`truncation_bounds`.
    """
    periodic, drift = _truncation_parts(model, order)
    return periodic + drift * span_days


def _truncation_parts(model: PrecessionNutation, order: int) -> tuple[float, float]:
    """(periodic bound, rate of the secular part) of :func:`truncation_bound`, radians and rad/day."""
    exact = model.nutation
    kmax = max(int(exact.multiple.max()) if exact.multiple.size else 0, order + 3)
    diff = _series_coefficients(model, order, kmax) - _series_coefficients(model, None, kmax)
    rate_diff = 0.5 * model.scaling_factor * abs(math.cos(model.obliquity)) * abs(
        eccentricity_factor(model.eccentricity, order) - eccentricity_factor(model.eccentricity))
    return 2.0 * pole_displacement_sum(diff.T, model.obliquity), abs(math.sin(model.obliquity)) * rate_diff


# --- the theory terms over given epochs -------------------------------------------------------------
#
# Every analytic rung and rung 5 start from the catalogue pole at the pole epoch t0, so a rung's error at t is
# what the difference of the two has accumulated since t0: a periodic function of the mean anomaly M (and of
# the slow phase φ = θ̄0 + ψ̄), taken relative to its value at t0, plus drifts growing with t - t0. The periodic
# parts are bounded by their largest excursion over the mean anomalies the epochs cover (PeriodicTable, from
# tables over one orbit built once per body), the drifts by their rate times the largest |t - t0|.

@dataclass(frozen=True)
class Window:
    """The requested epochs as the theory terms see them: ``lo``, ``hi`` the first and last epoch less the pole
    epoch t0 (days; either sign, t0 need not lie between), ``m0`` the mean anomaly at t0 and ``n`` the mean motion
    (rad/day)."""

    lo: float
    hi: float
    m0: float
    n: float

    @classmethod
    def of(cls, model: PrecessionNutation, t: np.ndarray) -> Window:
        t = np.asarray(t, dtype=float)
        lo, hi = (float(t.min()) - model.pole_epoch, float(t.max()) - model.pole_epoch) if t.size else (0.0, 0.0)
        return cls(lo, hi, float(model.mean_anomaly(model.pole_epoch)), model.mean_motion)

    @property
    def span(self) -> float:
        """Largest |t - t0| (days): the drifts grow from the pole epoch."""
        return max(abs(self.lo), abs(self.hi))

    @property
    def mean_anomalies(self) -> tuple[float, float]:
        """The mean anomalies (radians, unwrapped) of the first and last epoch."""
        return self.m0 + self.n * self.lo, self.m0 + self.n * self.hi

    @property
    def whole_orbits(self) -> bool:
        """Whether the epochs cover a whole orbit (every mean anomaly)."""
        return self.n * (self.hi - self.lo) >= 2.0 * math.pi

    def phases(self, rate: float, slack: float, from_t0: bool) -> tuple[float, float]:
        """Range of rate (t - t0) ± ``slack`` (radians) over the epochs (``from_t0``: and back to t0)."""
        ends = [rate * self.lo, rate * self.hi] + ([0.0] if from_t0 else [])
        return min(ends) - slack, max(ends) + slack


def _pole_weight(model: PrecessionNutation, nutation_reach: float) -> float:
    """The factor w on a longitude difference δψ in the pole displacement sqrt((w δψ)² + δε²): |sin ε| at the
    largest the track's obliquity ε̄0 + Δε reaches (|Δε| <= ``nutation_reach``), at most 1.

    Two poles at (ψ1, ε1), (ψ2, ε2) are apart by sqrt(δε² + sin ε1 sin ε2 δψ²) to second order in δψ, δε.
    """
    return min(1.0, abs(math.sin(model.obliquity)) + nutation_reach)


def _pole_coefficients(lon_sin, lon_cos, obl_sin, obl_cos, weight: float) -> tuple[np.ndarray, np.ndarray]:
    """(sin, cos) coefficient arrays (K, …, 2) of the pole displacement (w Δψ, Δε) of nutation terms."""
    return (np.stack([weight * np.asarray(lon_sin), np.asarray(obl_sin)], axis=-1),
            np.stack([weight * np.asarray(lon_cos), np.asarray(obl_cos)], axis=-1))


def _sup_abs(coef: np.ndarray) -> float:
    """sup over φ of |Σ_j c_j cos 2jφ + s_j sin 2jφ| <= |c0| + Σ_j |(c_j, s_j)| (φ-harmonics as in
    :mod:`ephem.forced.second_order`)."""
    degree = (coef.shape[-1] - 1) // 2
    return abs(float(coef[0])) + sum(float(np.hypot(coef[2 * j - 1], coef[2 * j])) for j in range(1, degree + 1))


def _phi_range_max(coef: np.ndarray, weight: float, lo: float, hi: float) -> float:
    """Upper bound on max over φ in [lo, hi] of |(w V_ψ, V_ε)(φ)|, V given by φ-harmonics ``coef`` (2, 2m+1)
    of :mod:`ephem.forced.second_order` (frequencies up to 2m in φ, period π).

    Samples at most π/64 apart, plus h²/8 sup|V''| with |V''| <= Σ_j (2j)² |coefficient j| (each harmonic's
    second derivative): the interpolation bound of :class:`ephem.orbit.harmonics.PeriodicTable`.
    """
    w = np.array([weight, 1.0])[:, None]
    c = coef * w
    degree = (coef.shape[-1] - 1) // 2
    curvature = sum((2.0 * j) ** 2 * float(np.linalg.norm(c[:, 2 * j - 1:2 * j + 1])) for j in range(1, degree + 1))
    width = min(hi - lo, math.pi)
    count = max(2, math.ceil(width / (math.pi / 64.0)) + 1)
    phi = lo + np.linspace(0.0, width, count)
    v = eval_phi(c[:, None, :], phi[None, :])          # (2, count)
    return float(np.max(np.hypot(v[0], v[1]))) + (width / (count - 1)) ** 2 / 8.0 * curvature


@dataclass(frozen=True)
class PhasedBounds:
    """A :class:`~ephem.forced.second_order.PhasedSeries` as pole displacement (w ψ, ε), with the bounds the estimates
    need (sup over M and φ): ``reach`` |F|, ``slope_phi`` |∂F/∂φ|, ``curvature_phi`` |∂²F/∂φ²| (from the
    φ-harmonics, degree 2 in 2φ: ∂/∂φ multiplies harmonic j by 2j), ``curvature_m`` |∂²F/∂M²| (from the
    M-harmonics: ∂/∂M multiplies harmonic k by k), and ``columns``: the largest |F(M, φ) - ``ref``| over the
    M grid at the phases φ0 + jπ/64 (:data:`REMAINDER_PHASES`)."""

    series: PhasedSeries
    weight: float
    reach: float
    slope_phi: float
    curvature_phi: float
    curvature_m: float
    columns: np.ndarray
    #: tables at the phases asked for (the pole epoch's every time, others for epochs far from it), a few kept
    _tables: dict = field(default_factory=dict, compare=False, repr=False)

    @classmethod
    def of(cls, series: PhasedSeries, weight: float, phi0: float, ref: np.ndarray) -> PhasedBounds:
        wv = np.array([weight, 1.0])
        per_harmonic = np.linalg.norm(series.values * wv[:, None], axis=1)           # (N, 5), over ψ, ε
        pair = [np.hypot(per_harmonic[:, 2 * j - 1], per_harmonic[:, 2 * j]) for j in (1, 2)]
        phases = phi0 + (math.pi / REMAINDER_PHASES) * np.arange(REMAINDER_PHASES)
        grid = eval_phi(series.values[None], phases[:, None, None]) * wv              # (phases, N, 2)
        return cls(series, weight, float(np.max(per_harmonic[:, 0] + pair[0] + pair[1])),
                   float(np.max(2.0 * pair[0] + 4.0 * pair[1])), float(np.max(4.0 * pair[0] + 16.0 * pair[1])),
                   cls._moment(series, wv, 2), np.max(np.linalg.norm(grid - ref, axis=-1), axis=1))

    @staticmethod
    def _moment(series: PhasedSeries, wv: np.ndarray, p: int, phi: float | None = None) -> float:
        """Σ_k k^p |c_k| over the M-harmonics (sup over φ, or at the phase ``phi``), with the tail's: bounds the
        p-th derivative in M."""
        if phi is None:
            size = np.sum(np.sqrt(np.sum((series.sin_coef * wv[:, None]) ** 2 + (series.cos_coef * wv[:, None]) ** 2,
                                         axis=1)), axis=-1)
        else:
            size = np.sqrt(np.sum((eval_phi(series.sin_coef, phi) * wv) ** 2 + (eval_phi(series.cos_coef, phi) * wv) ** 2,
                                  axis=-1))
        k = np.arange(1.0, size.size + 1.0)
        return float(np.sum(k ** p * size)) + float(series.tail[p])

    def derivative_bound(self, phi: float, order: int, x_lo: float | None = None, x_hi: float | None = None) -> float:
        """sup of |d^order F/dM^order| at the phase φ (order 1 or 2) over every M, or over [x_lo, x_hi] (within a
        period): the largest on the grid points there (spectral derivatives of the samples) plus h²/8 times the
        bound on the derivative two orders up (the interpolation bound of :class:`ephem.orbit.harmonics.PeriodicTable`)."""
        grid, margin = self._cached((phi, order), lambda: self._derivative_grid(phi, order))
        if x_lo is None or x_hi - x_lo >= 2.0 * math.pi:
            return float(np.max(grid)) + margin
        n = grid.size
        h = 2.0 * math.pi / n
        start = self.series.start
        j = np.arange(math.floor((x_lo - start) / h), math.ceil((x_hi - start) / h) + 1) % n
        return float(np.max(grid[j])) + margin

    def _cached(self, key, build):
        if key not in self._tables:
            if len(self._tables) >= 16:
                self._tables.pop(next(iter(self._tables)))
            self._tables[key] = build()
        return self._tables[key]

    def _derivative_grid(self, phi: float, order: int) -> tuple[np.ndarray, float]:
        wv = np.array([self.weight, 1.0])
        values = eval_phi(self.series.values, phi) * wv
        n = values.shape[0]
        spec = np.fft.rfft(values, axis=0) * ((1j * np.arange(n // 2 + 1)) ** order)[:, None]
        grid = np.linalg.norm(np.fft.irfft(spec, n=n, axis=0), axis=-1)
        h = 2.0 * math.pi / n
        return grid, h * h / 8.0 * self._moment(self.series, wv, order + 2, phi)

    def table(self, phi: float) -> PeriodicTable:
        """The pole displacement at the phase φ over one orbit (:class:`ephem.orbit.harmonics.PeriodicTable`)."""
        return self._cached(phi, lambda: self._table(phi))

    def _table(self, phi: float) -> PeriodicTable:
        wv = np.array([self.weight, 1.0])
        values, sin_c, cos_c = self.series.at(phi)
        start = self.series.start
        grid, margin = self._cached((phi, 2), lambda: self._derivative_grid(phi, 2))
        return PeriodicTable(start, (values * wv)[:, None, :], np.array([float(np.max(grid)) + margin]),
                             harmonic_sum(sin_c * wv, cos_c * wv, (1, 2), start), float(self.series.tail[0]),
                             grid[:, None], np.array([margin]))

    def orbit_max(self, lo: float, hi: float) -> float:
        """Upper bound on max |F(M, φ) - ref| over every M and φ in φ0 + [lo, hi]: the columns in the range and
        their neighbours, plus the interpolation bounds h²/8 |∂²F/∂φ²| and h²/8 |∂²F/∂M²|
        (:class:`ephem.orbit.harmonics.PeriodicTable`)."""
        h = math.pi / REMAINDER_PHASES
        if hi - lo >= math.pi:
            columns = self.columns
        else:
            columns = self.columns[np.arange(math.floor(lo / h), math.ceil(hi / h) + 1) % REMAINDER_PHASES]
        step_m = 2.0 * math.pi / self.series.values.shape[0]
        return float(np.max(columns)) + h * h / 8.0 * self.curvature_phi + step_m * step_m / 8.0 * self.curvature_m


#: Phases of the remainder's tables (over φ's period π) for windows of whole orbits.
REMAINDER_PHASES = 64
#: Epochs whose mean pole's phase is within this of the pole epoch's (radians) use the remainder's table at the
#: pole epoch, with the difference times sup |∂P2/∂φ| added (at most 0.4% of P2's size: |∂P2/∂φ| <= 4 sup|P2|).
NEAR_PHASE = 1e-3


@dataclass(frozen=True)
class TheoryTables:
    """Per body, what the span-aware theory terms need, built once (radians; M from the pole epoch's).

    ``weight``: :func:`_pole_weight`. ``nutation``: the pole displacement (w Δψ, Δε) of the nutation series
    over one orbit; ``truncation``: the same of the difference series of order N minus exact (one group per
    order below :data:`MAX_LADDER_ORDER`, or None above the Laplace limit) with ``truncation_rates`` (rad/day,
    per order: (K/2) cos ε̄0 (f_N(e) - f(e)), f_N the truncated (1 - e²)^(-3/2)), ``truncation_factors`` f_N and
    ``truncation_reach`` (per order: Σ_k (K/2kn)(|C0_k| + 2 |C2_k, S2_k|) of the series' Hansen coefficients,
    how far its coefficients move per radian of mean pole); ``abc``: the nutation's parts of
    :class:`ephem.forced.kinoshita.NutationComponents`, (a, 0) and the θ-dependent (b, c) as two groups;
    ``remainder``: :class:`ephem.forced.second_order.Remainder`, its P2 and V + ∂P2/∂φ as :class:`PhasedBounds`.
    """

    weight: float
    nutation: PeriodicTable
    truncation: PeriodicTable | None
    truncation_rates: np.ndarray
    truncation_factors: np.ndarray
    truncation_reach: np.ndarray
    abc: PeriodicTable
    remainder: Remainder
    periodic: PhasedBounds
    rephasing: PhasedBounds


def theory_tables(model: PrecessionNutation, theory: SecondOrderTheory) -> TheoryTables:
    """The :class:`TheoryTables` of a model and its second-order theory."""
    m0 = float(model.mean_anomaly(model.pole_epoch))
    series = model.nutation
    w = _pole_weight(model, float(np.sum(np.hypot(series.obl_sin, series.obl_cos))))
    nutation = PeriodicTable.of_harmonics(*(x[:, None, :] for x in _pole_coefficients(
        series.lon_sin, series.lon_cos, series.obl_sin, series.obl_cos, w)), m0)

    truncation, rates, factors, reach = None, np.zeros(0), np.zeros(0), np.zeros(0)
    kx = int(series.multiple.max()) if series.multiple.size else 0
    orders = range(0, min(MAX_LADDER_ORDER, kx)) if model.eccentricity < LAPLACE_LIMIT else range(0)
    if len(orders):
        kmax = max(kx, orders[-1] + 3)
        exact = np.zeros((4, kmax))
        exact[:, :kx] = [series.lon_sin, series.lon_cos, series.obl_sin, series.obl_cos]
        diffs, reach = [], []
        for order in orders:
            diffs.append(_series_coefficients(model, order, kmax) - exact)
            h = hansen_series(order).evaluate(model.eccentricity)
            k = np.arange(1, len(h.k))
            reach.append(float(np.sum(0.5 * model.scaling_factor / (k * model.mean_motion) * (
                np.abs(h.c0[1:]) + 2.0 * np.hypot(h.c2[1:], h.s2[1:])))))
        d = np.stack(diffs, axis=1)                                  # (4, orders, K)
        truncation = PeriodicTable.of_harmonics(*_pole_coefficients(*(x.T for x in d), w), m0)
        factors = np.array([eccentricity_factor(model.eccentricity, order) for order in orders])
        rates = 0.5 * model.scaling_factor * math.cos(model.obliquity) * (
            factors - eccentricity_factor(model.eccentricity))
        reach = np.array(reach)

    comp = theory.components
    a_k, b_k, c_k = comp.sin_coef[:, 0], comp.sin_coef[:, 1], comp.cos_coef[:, 2]
    zero = np.zeros_like(b_k)
    abc = PeriodicTable.of_harmonics(np.stack([np.stack([a_k, zero], -1), np.stack([b_k, zero], -1)], 1),
                                     np.stack([np.stack([zero, zero], -1), np.stack([zero, c_k], -1)], 1), m0)
    rem = second_order_remainder(model.scaling_factor, model.mean_motion, model.eccentricity, theory, m0)
    phi0 = theory.equinox_to_pericentre
    return TheoryTables(w, nutation, truncation, rates, factors, reach, abc, rem,
                        PhasedBounds.of(rem.periodic, w, phi0, rem.start * np.array([w, 1.0])),
                        PhasedBounds.of(rem.rephasing, w, phi0, np.zeros(2)))


# A body's tables are up to a few MB at e = 0.9 (the remainder's grids, 75 MB at e = 0.95), and they keep the
# grids asked of them: kept within the per-body caches' byte budget (ephem.base.memo), weighed again as they grow.
@bytes_bounded(grows=True)
def cached_tables(body: Body) -> TheoryTables:
    """The body's :class:`TheoryTables`, built once and kept while the byte budget of the per-body caches lets
    them (:mod:`ephem.base.memo`): the cost model charges their build only while :func:`tables_built` says no."""
    return theory_tables(cached_model(body), cached_theory(body))


def tables_built(body: Body) -> bool:
    """Whether :func:`cached_tables` holds the body's tables (a request then does not pay for them)."""
    return cached_tables.cached(body)


def nutation_omitted_bound(tables: TheoryTables, window: Window) -> float:
    """Pole error (radians) of rung 1 against rung 3 at the epochs: the nutation it leaves out.

    Rung 1 is the mean pole ψ = ψ̇ (t - t0), ε = ε̄0; rung 3 adds Δψ(t), Δε(t) to it, so the two differ by
    the nutation itself (not relative to t0: rung 1 starts at the mean pole), at most its largest pole
    displacement sqrt((w Δψ)² + Δε²) over the mean anomalies the epochs cover.
    """
    return float(tables.nutation.interval_max(*window.mean_anomalies)[0])


def truncation_bounds(model: PrecessionNutation, tables: TheoryTables, window: Window) -> np.ndarray:
    """Pole error (radians) of each e^N series (N = 0, 1, …) against the exact Hansen coefficients at the epochs.

    Both tracks start from the catalogue pole: each removes its own nutation at t0 to find its mean pole
    (ε̄_N = ε - Δε_N(t0), θ̄_N = θ - Δψ_N(t0)), so with D = Δ_N - Δ the difference series, the longitude and
    obliquity differ at t by

        δψ = D_ψ(t) - D_ψ(t0) + (ψ̇_N - ψ̇)(t - t0),    δε = D_ε(t) - D_ε(t0),
        ψ̇_N - ψ̇ = (K/2) [cos ε̄ (f_N - f) + f_N (cos ε̄_N - cos ε̄)],   cos ε̄_N - cos ε̄ = sin ε̄ δε + O(δε²/2)

    (the "twice" of :func:`truncation_bound` is D(t0)). Their largest pole displacement over the epochs is
    bounded on the samples of the mean anomalies they cover, the drift added to the periodic part
    (:meth:`ephem.orbit.harmonics.PeriodicTable.interval_max`, whose slope leaves the interpolation bound as it is). D is
    computed at the exact mean pole (ε̄, θ̄); the series' own differs from it by δε, δθ with
    s = |δε| + 2 |δθ| <= (|D_ε(t0)| + 2 |D_ψ(t0)|) / (1 - 3R) (R the series' ``truncation_reach``: its
    coefficients move by at most R s), which moves the difference of the periodic parts by at most 2 R s and
    leaves |δε| <= |D_ε(t0)| + R s.
    """
    if tables.truncation is None:
        return np.zeros(0)
    start = tables.truncation.values[0]                       # (orders, 2): (w D_ψ(t0), D_ε(t0))
    d_psi0, d_eps0 = np.abs(start[:, 0]) / tables.weight, np.abs(start[:, 1])
    reach = tables.truncation_reach
    shift = (d_eps0 + 2.0 * d_psi0) / np.maximum(1.0 - 3.0 * reach, 0.5)
    delta_eps = d_eps0 + reach * shift
    half_k_f = 0.5 * model.scaling_factor * tables.truncation_factors
    rate = tables.truncation_rates + half_k_f * math.sin(model.obliquity) * start[:, 1]
    slope = np.stack([tables.weight * rate / model.mean_motion, np.zeros_like(rate)], axis=-1)
    periodic = tables.truncation.interval_max(*window.mean_anomalies, ref=start, slope=slope)
    rest = half_k_f * (abs(math.sin(model.obliquity)) * reach * shift + 0.5 * delta_eps ** 2)
    return periodic + 2.0 * reach * shift + tables.weight * rest * window.span


def _mean_rates(theory: SecondOrderTheory) -> np.ndarray:
    """φ-harmonics (2, 5) of the second-order mean rates (G_ψ, G_ε) at ε̄0 (rad/day)."""
    ce, se = math.cos(theory.obliquity), math.sin(theory.obliquity)
    g = theory.coefficients
    return np.stack([ce * ce * g[0] + se * se * g[1], se * ce * g[2]])


@dataclass(frozen=True)
class _Drifts:
    """The slow parts the rungs 3-4 bounds share (radians, rad/day; T the span, days)."""

    T: float
    g_psi: float     # sup |G_ψ|, sup |G_ε|: the second-order mean rates
    g_eps: float
    d_psi: float     # sup |d_ψ|, sup |d_ε|: rung 4's drift against rung 5
    d_eps: float
    slack: float     # bound on |ψ̄ - ψ̇ (t - t0)| for rung 4's and the torque's mean poles

    @classmethod
    def of(cls, theory: SecondOrderTheory, tables: TheoryTables, window: Window) -> _Drifts:
        T = window.span
        rates, drift = _mean_rates(theory), tables.remainder.drift_harmonics()
        g_psi, g_eps, d_psi, d_eps = _sup_abs(rates[0]), _sup_abs(rates[1]), _sup_abs(drift[0]), _sup_abs(drift[1])
        # ψ̄ - ψ̇ T = ∫ G_ψ + (K/2) f (cos ε̄ - cos ε̄0), |ε̄ - ε̄0| <= sup|G_ε + d_ε| T
        se = abs(math.sin(theory.obliquity))
        slack = (g_psi + d_psi) * T + theory.first_order_rate * se * (g_eps + d_eps) * T * T / 2.0
        return cls(T, g_psi, g_eps, d_psi, d_eps, slack)


def _mean_pole_bound(theory: SecondOrderTheory, tables: TheoryTables, window: Window, drifts: _Drifts,
                     coef: np.ndarray, eps_rate: float, about: float | None = None) -> float:
    """How far a mean pole moving at the extra rates ``coef`` (φ-harmonics (2, m), rad/day, in ψ and ε; |ε rate|
    <= ``eps_rate``) departs over the epochs: T max |(w ψ̇_x, ε̇_x)| over the phases from t0 to the epochs, plus
    w (K/2) f(e) |sin ε̄0| ``eps_rate`` T²/2 (the obliquity's drift changes ψ̇ = (K/2) f(e) cos ε̄). ``about`` a
    phase φ: only what the rates differ from their value there (a caller counts that part with the periodic
    terms). The factor 1 + 2 |δε̄| covers the rates' dependence on ε̄ (through cos²ε, sin²ε, sin ε cos ε)."""
    T = drifts.T
    lo, hi = window.phases(theory.first_order_rate * math.cos(theory.obliquity), drifts.slack, from_t0=True)
    phi0 = theory.equinox_to_pericentre
    if about is not None:
        coef = coef.copy()
        coef[:, 0] -= eval_phi(coef, about)
    return T * _phi_range_max(coef, tables.weight, phi0 + lo, phi0 + hi) * (1.0 + 2.0 * (drifts.g_eps + drifts.d_eps) * T) \
        + tables.weight * theory.first_order_rate * abs(math.sin(theory.obliquity)) * eps_rate * T * T / 2.0


def second_order_bound(model: PrecessionNutation, theory: SecondOrderTheory, tables: TheoryTables,
                       window: Window, drifts: _Drifts | None = None) -> float:
    """Pole distance (radians) between rungs 3 and 4 at the epochs: what the first-order theory leaves to the
    second order (with :func:`higher_order_bound`, a bound on rung 3's error against rung 5).

    Rung 4 is ψ̄(t) + w(φ(t), ε̄(t), M), ε̄(t) + …, rung 3 ψ̇ (t - t0) + w(θ̄0, ε̄0, M), ε̄0 + …, so they differ by

    * the mean pole: ψ̄ - ψ̇ T = ∫ (G_ψ + (K/2) f(e) (cos ε̄ - cos ε̄0)), ε̄ - ε̄0 = ∫ G_ε
      (:func:`_mean_pole_bound`; G: :func:`ephem.forced.second_order.second_order_coefficients`; the factor
      1 + 2 |δε̄| covers G's dependence on ε̄, through cos²ε, sin²ε and sin ε cos ε);
    * the re-phasing: w's θ-dependent part is -cos ε (C' b + S' c) in Δψ and -sin ε (S' b - C' c) in Δε
      (C' = cos 2θ, S' = sin 2θ), so moving θ by Δφ = ψ̄ moves the pole by at most 2 |sin Δφ| w |(b, c)(M)|
      ((C', S') moves by 2 |sin Δφ|, and the two components are its projections on two orthogonal directions);
      ε̄'s drift moves it by at most |ε̄ - ε̄0| (|a| + |(b, c)|) (the derivative of (sin ε cos ε w_ψ, sin ε w_ε)
      in ε is at most |(w_ψ, w_ε)| <= |a| + |(b, c)|), their largest over the mean anomalies of the epochs.
    """
    dr = drifts or _Drifts.of(theory, tables, window)
    mean = _mean_pole_bound(theory, tables, window, dr, _mean_rates(theory), dr.g_eps)
    lo, hi = window.phases(model.precession_rate, dr.slack, from_t0=False)
    turn = min(1.0, max(abs(lo), abs(hi)))
    a, bc = tables.abc.interval_max(*window.mean_anomalies)
    return mean + 2.0 * turn * tables.weight * bc + dr.g_eps * dr.T * (a + bc)


#: The third-order rest of the second-order estimates (the third-order periodic terms u3, the first-order nutation
#: moved by the mean pole's second-order offset, fourth-order drifts), per unit of the small parameter
#: r = (K/n) f(e) and of the size of the second-order parts it corrects. Measured against rung 5 as the least
#: factor that keeps each estimate at or above the error (rungs 3 and 4, 2080 cases: 1040 generated bodies and
#: windows, e 0.001-0.95, ε 0.5-179.5°, H_d 1e-3-0.3, rotation 2 h-10 d, a 0.8-5 AU, 3 days to a century either
#: side of the pole epoch, some not containing it): at most 0.22 for e <= 0.9 (1912 cases), 1.43 at e = 0.95
#: (ε = 178°, r = 0.011); 2 leaves a margin over the largest.
THIRD_ORDER_FACTOR = 2.0


def small_parameter(model: PrecessionNutation) -> float:
    """The small parameter of the perturbation theory: the torque over the orbital rate, (K/n) f(e) (its mean over
    the orbit carries f(e) = (1 - e²)^(-3/2))."""
    return model.scaling_factor / model.mean_motion * eccentricity_factor(model.eccentricity)


def higher_order_bound(model: PrecessionNutation, theory: SecondOrderTheory, tables: TheoryTables,
                       window: Window, drifts: _Drifts | None = None) -> float:
    """Pole error (radians) of rung 4 against rung 5 at the epochs (:class:`ephem.forced.second_order.Remainder`).

    Rung 4 misses the second-order periodic nutation P2 (relative to its value at t0) and drifts at the
    third-order rate d(φ) (:meth:`~ephem.forced.second_order.Remainder.drift_harmonics`):

    * within an orbit, the largest |(w, 1)(P2(M, φ_w) - P2(t0) + d(φ_w)(t - t0))| over the mean anomalies of the
      epochs (:meth:`ephem.orbit.harmonics.PeriodicTable.interval_max`, φ_w the mean pole's mid phase there), plus
      |φ - φ_w| sup |∂P2/∂φ| and what d departs from d(φ_w) (:func:`_mean_pole_bound`);
    * over whole orbits, :meth:`PhasedBounds.orbit_max` (P2 over every M and the phases the mean pole passes)
      plus the drift's :func:`_mean_pole_bound`;
    * P2 is taken at ε̄0 and moves by at most 2 |δε̄| sup |P2| as ε̄ drifts (its ε-dependence is cos²ε, sin²ε,
      sin ε cos ε);
    * the rest, third order in the small parameter r = (K/n) f(e): :data:`THIRD_ORDER_FACTOR` r times the parts'
      sizes (|P2 - P2(t0)| + |d| T, at most the bound above plus 2 |d| T), a constant measured against rung 5.
    """
    dr = drifts or _Drifts.of(theory, tables, window)
    lo, hi = window.phases(model.precession_rate, dr.slack, from_t0=False)
    p2 = tables.periodic
    drift = tables.remainder.drift_harmonics()
    if window.whole_orbits:
        periodic = p2.orbit_max(lo, hi) + _mean_pole_bound(theory, tables, window, dr, drift, dr.d_eps)
    else:
        # the table at the pole epoch's phase when the epochs' phases are that close (no new table), else at theirs
        mid = 0.0 if max(abs(lo), abs(hi)) <= NEAR_PHASE else 0.5 * (lo + hi)
        phi = theory.equinox_to_pericentre + mid
        wv = np.array([tables.weight, 1.0])
        periodic = float(p2.table(phi).interval_max(
            *window.mean_anomalies, ref=(tables.remainder.start * wv)[None],
            slope=(eval_phi(drift, phi) * wv / model.mean_motion)[None])[0]) \
            + max(abs(lo - mid), abs(hi - mid)) * p2.slope_phi \
            + _mean_pole_bound(theory, tables, window, dr, drift, dr.d_eps, about=phi)
    periodic += 2.0 * (dr.g_eps + dr.d_eps) * dr.T * p2.reach
    # the third-order rest scales with the parts' sizes, |P2 - P2(t0)| + |d| T <= the bound + 2 |d| T
    drift_size = dr.T * math.hypot(tables.weight * dr.d_psi, dr.d_eps)
    return periodic + THIRD_ORDER_FACTOR * small_parameter(model) * (periodic + 2.0 * drift_size)


def first_order_bound(model: PrecessionNutation, theory: SecondOrderTheory, tables: TheoryTables,
                      window: Window, drifts: _Drifts | None = None, through_rung4: float | None = None) -> float:
    """Pole error (radians) of rung 3 against rung 5 at the epochs (the ``second_order`` term of rungs 1-3).

    Through rung 4, :func:`second_order_bound` + :func:`higher_order_bound`. But the parts largely cancel while
    the mean pole has turned little: linearised in ψ̄, rung 3 misses P2(t) - P2(t0) + ψ̄(t) V(t) (V = ∂w/∂φ)
    + ∫ (G + d), and P2 holds -∫ (ψ̇ V + G) dt, so over a short span the sum grows as ∫ Df · w dt alone. Directly,
    with V' = V + ∂P2/∂φ (P2 too follows φ = φ0 + ψ̄), the bound is the largest
    |(w, 1)(P2(M) - P2(t0) + (M - M0)/n (ψ̇ V'(M) + G(φ0) + d(φ0)))| at φ0 over the mean
    anomalies of the epochs (the samples of :meth:`ephem.orbit.harmonics.PeriodicTable.samples`; over whole orbits,
    those of the first and the last, as the part linear in M makes each phase's value convex in the orbits' count;
    with the interpolation bound
    h²/8 (|P2''| + |ψ̇/n| (2 |V'_M| + max |M - M0| |V'_MM|))), plus what the linearisation leaves:
    |ψ̄ - ψ̇ T| (2 w |(b, c)| + sup |∂P2/∂φ|) and Φ² (2 w |(b, c)| + sup |∂²P2/∂φ²| / 2) (Φ the largest |ψ̄|; w's
    θ-dependence is through (C', S'), whose curvature is 4), what G and d depart from their values at φ0
    (:func:`_mean_pole_bound`) and the ε̄ terms; and the third-order rest, :data:`THIRD_ORDER_FACTOR` r times the
    sizes of the parts that cancel (the largest of |P2(M) - P2(t0)| + |(M - M0)/n| (|ψ̇ V'| + |G + d|), not what is
    left of their sum). The smaller of the two bounds is taken.
    """
    dr = drifts or _Drifts.of(theory, tables, window)
    if through_rung4 is None:
        through_rung4 = second_order_bound(model, theory, tables, window, dr) + higher_order_bound(
            model, theory, tables, window, dr)
    phi0 = theory.equinox_to_pericentre
    p2, v = tables.periodic, tables.rephasing
    wv = np.array([tables.weight, 1.0])
    m_lo, m_hi = window.mean_anomalies
    p_table, v_table = p2.table(phi0), v.table(phi0)
    rates, drift = _mean_rates(theory), tables.remainder.drift_harmonics()
    mean_rate = (eval_phi(rates, phi0) + eval_phi(drift, phi0)) * wv
    scale = model.precession_rate / model.mean_motion
    reach_m = max(abs(m_lo - window.m0), abs(m_hi - window.m0))
    curvature = p_table.curvature_over(m_lo, m_hi)[0] + abs(scale) * (
        2.0 * v.derivative_bound(phi0, 1, m_lo, m_hi) + reach_m * v_table.curvature_over(m_lo, m_hi)[0])

    def bound(fresh):
        # P2 and V are periodic, the rest linear in M: at one phase, convex in the count of orbits (the first and
        # the last orbit bound the others, PeriodicTable.interval_max); and the parts' sizes, for the third order
        x, p_samples, spacing = p_table.samples(m_lo, m_hi, fresh=fresh, unwrapped=True)
        _, v_samples, _ = v_table.samples(m_lo, m_hi, fresh=fresh, unwrapped=True)
        dx = (x - window.m0)[:, None, None]
        parts = [p_samples - (tables.remainder.start * wv)[None, None], dx * scale * v_samples,
                 dx * mean_rate / model.mean_motion]
        size = float(np.max(sum(np.linalg.norm(part, axis=-1) for part in parts)))
        return float(np.max(np.linalg.norm(sum(parts), axis=-1))), spacing * spacing / 8.0 * curvature, size

    peak, interpolation, size = bound(FRESH_STEPS)
    finer = refined_count(m_hi - m_lo, curvature, peak, interpolation)
    if finer:
        peak, interpolation, size = bound(finer)
    tails = p_table.tail + abs(scale) * reach_m * v_table.tail
    linear = peak + interpolation + tails
    lo, hi = window.phases(model.precession_rate, dr.slack, from_t0=True)
    turn = max(abs(lo), abs(hi))
    a, bc = tables.abc.interval_max(m_lo, m_hi)
    left = dr.slack * (2.0 * tables.weight * bc + p2.slope_phi) + turn * turn * (
        2.0 * tables.weight * bc + 0.5 * p2.curvature_phi) \
        + (dr.g_eps + dr.d_eps) * dr.T * (2.0 * p2.reach + a + bc) \
        + _mean_pole_bound(theory, tables, window, dr, rates, dr.g_eps, about=phi0) \
        + _mean_pole_bound(theory, tables, window, dr, drift, dr.d_eps, about=phi0)
    # the third-order rest scales with the sizes of the parts that cancel, not with what is left of them
    third = THIRD_ORDER_FACTOR * small_parameter(model) * (size + interpolation + tails + left)
    return min(through_rung4, linear + left + third)


def theory_terms(model: PrecessionNutation, theory: SecondOrderTheory, tables: TheoryTables, window: Window) -> dict:
    """The theory terms of rungs 1-4 at the epochs (radians): ``nutation_omitted``, ``truncation`` (an array over
    the e-orders), ``second_order`` (rung 3 against rung 5, :func:`first_order_bound`) and ``higher_order``."""
    dr = _Drifts.of(theory, tables, window)
    higher = higher_order_bound(model, theory, tables, window, dr)
    first = first_order_bound(model, theory, tables, window, dr,
                              second_order_bound(model, theory, tables, window, dr) + higher)
    return {"nutation_omitted": nutation_omitted_bound(tables, window),
            "truncation": truncation_bounds(model, tables, window), "second_order": float(first),
            "higher_order": float(higher)}


def integration_bound(model: PrecessionNutation, span_days: float) -> float:
    """Error of the numerical rungs (radians) at rtol 1e-12.

    Measured against rtol 1e-14: the error per orbit is a few times rtol times the pole's motion
    per orbit, 2π (K/n)(1-e²)^(-3/2) (5e-16 for the Earth, 5e-15 for Itokawa, 1.2e-12 for a
    K/n = 5e-3 body on an e = 0.5 orbit); the bound allows 100 rtol per orbit on that motion
    plus 1e-3 rad, and a floor of 1e-12.
    """
    orbits = abs(span_days) * model.mean_motion / (2.0 * math.pi)
    motion = 2.0 * math.pi * model.scaling_factor / model.mean_motion * eccentricity_factor(model.eccentricity)
    return 1e-12 + orbits * 100.0 * NUMERICAL_RTOL * (motion + 1e-3)


def orbits_in_span(model: PrecessionNutation, t: np.ndarray) -> float:
    """Orbits the numerical rungs integrate through to reach the epochs from the pole epoch."""
    return _span(model, t) * model.mean_motion / (2.0 * math.pi)


# --- evaluating a rung ----------------------------------------------------------------------------

def secular_track(model: PrecessionNutation, jd_tdb) -> Track:
    """Rung 1: the mean pole precessing uniformly, no nutation."""
    t = np.asarray(jd_tdb, dtype=float)
    zero = np.zeros(t.shape)
    psi = model.precession_rate * (t - model.pole_epoch)
    return model.track_from_angles(t, psi, zero, zero, np.full(t.shape, model.obliquity))


def second_order_track(model: PrecessionNutation, theory: SecondOrderTheory, jd_tdb) -> Track:
    """Rung 4: ψ, ε from the second-order theory, in the frame of the orbit and mean equinox at t0."""
    t = np.asarray(jd_tdb, dtype=float)
    psi, dpsi, deps, eps = theory.angles(model.mean_anomaly(t), t)
    return model.track_from_angles(t, psi, dpsi, deps, eps)


def track_from_vectors(model: PrecessionNutation, theory: SecondOrderTheory, jd_tdb, pole_icrf) -> Track:
    """A :class:`Track` from ICRF pole vectors (the numerical rungs).

    ψ and ε are read off the pole in the frame of the orbit and mean equinox at t0; the
    nutation Δψ, Δε is what remains after the second-order theory's mean ψ̄, ε̄.
    """
    t = np.asarray(jd_tdb, dtype=float)
    s = pole_icrf @ model.icrf_from_orbit   # rows: orbit-frame vectors
    psi_bar, eps_bar = theory.mean_track(t)(t)
    raw = np.arctan2(s[:, 0], s[:, 1])
    psi = psi_bar + np.remainder(raw - psi_bar + math.pi, 2.0 * math.pi) - math.pi  # unwrap about ψ̄
    eps = np.arctan2(np.hypot(s[:, 0], s[:, 1]), s[:, 2])
    ra = np.arctan2(pole_icrf[:, 1], pole_icrf[:, 0])
    ra += (ra < 0.0) * (2.0 * math.pi)
    dec = np.arctan2(pole_icrf[:, 2], np.hypot(pole_icrf[:, 0], pole_icrf[:, 1]))
    return Track(t, psi, psi - psi_bar, eps - eps_bar, eps, ra, dec)


# --- the ladder of one body -----------------------------------------------------------------------

@bytes_bounded      # a body of the caller's: bounded in bytes with the model (ephem.base.memo)
def cached_theory(body: Body) -> SecondOrderTheory:
    return second_order_theory(cached_model(body))


def _span(model: PrecessionNutation, t: np.ndarray) -> float:
    """Largest |t - t0| over the epochs (days): the theories' errors grow from the pole epoch."""
    if t.size == 0:
        return 0.0
    return float(max(abs(t.max() - model.pole_epoch), abs(t.min() - model.pole_epoch)))


def numerical_unavailable(model: PrecessionNutation, t: np.ndarray) -> str | None:
    orbits = orbits_in_span(model, t)
    if orbits <= MAX_NUMERICAL_ORBITS:
        return None
    return (f"the numerical rungs integrate through every orbit from the pole epoch and are limited to "
            f"{MAX_NUMERICAL_ORBITS} orbits per request; these epochs need {orbits:.0f}")


@dataclass(frozen=True)
class Ladder:
    """The rungs for one body: estimates, choice by tolerance, and evaluation.

    ``axis`` is the pole followed ("figure" or "angular_momentum"); ``wobble``, for the figure axis, the
    free wobble a track may add when the tolerance needs it (its amplitude and phase)."""

    body: Body
    axis: str = "figure"
    wobble: Wobble | None = None
    #: the A axis's angle (radians) from the orbit's ascending node on the equator at the pole epoch
    #: (:mod:`ephem.forced.rotation_scale`); None: unknown, the semi-diurnal terms stay an error term
    rotation_phase: float | None = None

    def __post_init__(self):
        if self.axis not in AXES:
            raise InvalidInputError("axis", f"must be one of {', '.join(AXES)}, got {self.axis!r}", self.body.name)
        if self.wobble is not None and self.axis != "figure":
            raise InvalidInputError("free_wobble_phase_deg", "the free wobble moves the figure axis, not the "
                                    "angular momentum: ask for axis=figure", self.body.name)

    @property
    def model(self) -> PrecessionNutation:
        return cached_model(self.body)

    @property
    def theory(self) -> SecondOrderTheory:
        return cached_theory(self.body)

    @property
    def rotation_modelled(self) -> str:
        """What of the rotation-scale terms a track that adds them includes (:data:`ephem.forced.rotation_scale.MODELLED`)."""
        return "oppolzer" if self.rotation_phase is None else "all"

    def physics_terms(self, jd_tdb: np.ndarray, modelled: str = "none") -> dict:
        """Error terms every fixed-orbit rung shares: the orbit's motion and rotation averaging, with ``modelled``
        of the rotation-scale terms in the track (the real-orbit rung drops the first). A user's body has no
        measured orbit motion."""
        terms = {"rotation_averaging": rotation_averaging_bound(self.body, self.model, jd_tdb,
                                                                self.axis, modelled)}
        orbit = orbit_motion_bound(self.body, self.model, jd_tdb)
        if orbit is not None:
            terms["orbit_motion"] = orbit
        return terms

    @staticmethod
    def _estimate(rung: str, order: int | None, terms: dict, physics: dict, rotation_scale: str | None = None
                  ) -> Estimate:
        shared = {k: v for k, v in physics.items() if not (rung == "real_orbit" and k == "orbit_motion")}
        missing = () if rung == "real_orbit" or "orbit_motion" in physics else ("orbit_motion",)
        return Estimate(rung, order, {**terms, **shared, "rounding": ROUNDING}, unestimated=missing,
                        rotation_scale=rotation_scale)

    def _with_rotation_scale(self, estimates: list[Estimate], t: np.ndarray) -> list[Estimate]:
        """Each available rung followed by the same rung with the rotation-scale terms added (a little dearer,
        and its ``rotation_averaging`` term is what they leave)."""
        if self.model.hd == 0.0:
            return estimates
        modelled = self.rotation_modelled
        averaging = self.physics_terms(t, modelled)["rotation_averaging"]
        out = []
        for e in estimates:
            out.append(e)
            if e.available and "rotation_averaging" in e.terms:
                out.append(Estimate(e.rung, e.order, {**e.terms, "rotation_averaging": averaging},
                                    unestimated=e.unestimated, rotation_scale=modelled))
        return out

    def estimates(self, jd_tdb) -> list[Estimate]:
        """Every rung's estimate for these epochs, cheapest first (rung 2 once per order)."""
        t = np.atleast_1d(np.asarray(jd_tdb, dtype=float))
        m, th = self.model, self.theory
        T = _span(m, t)
        physics = self.physics_terms(t)
        theory = theory_terms(m, th, cached_tables(self.body), Window.of(m, t))
        higher, second = theory["higher_order"], theory["second_order"]
        out = [self._estimate("secular", None, {"nutation_omitted": theory["nutation_omitted"],
                                                "second_order": second}, physics)]
        if m.eccentricity < LAPLACE_LIMIT:
            for order, truncation in enumerate(theory["truncation"]):
                out.append(self._estimate("series", order, {"truncation": float(truncation),
                                                             "second_order": second}, physics))
        else:
            out.append(Estimate("series", None, {}, available=False, why_not=(
                f"e = {m.eccentricity:.4g} exceeds the Laplace limit {LAPLACE_LIMIT:.4f}: the e-power series "
                "of the Hansen coefficients diverge")))
        out.append(self._estimate("hansen", None, {"second_order": second}, physics))
        out.append(self._estimate("second_order", None, {"higher_order": higher}, physics))
        too_long = numerical_unavailable(m, t)
        if too_long is None:
            out.append(self._estimate("numerical", None, {"integration": integration_bound(m, T)}, physics))
        else:
            out.append(Estimate("numerical", None, {}, available=False, why_not=too_long))
        why = too_long or real_orbit_unavailable(self.body, t)
        if why is None:
            out.append(self._estimate("real_orbit", None, {"integration": integration_bound(m, T),
                                                           "ephemeris": ephemeris_bound(self.body, m, T)}, physics))
        else:
            out.append(Estimate("real_orbit", None, {}, available=False, why_not=why))
        out = self._with_rotation_scale(out, t)
        return self._wobble_estimates(out, t) if self.axis == "figure" else out

    def _wobble_estimates(self, estimates: list[Estimate], t: np.ndarray) -> list[Estimate]:
        """For the figure axis: each rung leaves out the free wobble (its amplitude, a term) and, when the
        wobble's phase is given, follows it at the cost of the wobble model's error (a second estimate)."""
        left_out = free_wobble_bound(self.body) if self.wobble is None else self.wobble.J_arcsec * ARCSEC
        modelled = None
        if self.wobble is not None:
            modelled = wobble_model_bound(self.body, self.wobble, t, pole_vectors(self.model.track(t)),
                                          self._pole_at_wobble_epoch()) + ROUNDING
        # a modelled wobble takes the catalogue pole as L (ephem.rotation.free_motion): the figure axis then carries the
        # whole Oppolzer offset
        averaging = None if modelled is None else rotation_averaging_bound(
            self.body, self.model, t, self.axis, "none", pole="momentum")
        out = []
        for e in estimates:
            if not e.available:
                out.append(e)
                continue
            if left_out is None:
                out.append(Estimate(e.rung, e.order, e.terms, unestimated=e.unestimated + ("free_wobble",),
                                    rotation_scale=e.rotation_scale))
            else:
                out.append(Estimate(e.rung, e.order, {**e.terms, "free_wobble": left_out}, unestimated=e.unestimated,
                                    rotation_scale=e.rotation_scale))
            if modelled is not None and e.rotation_scale is None:    # the two are not combined
                terms = {**e.terms, "free_wobble_model": modelled}
                if "rotation_averaging" in terms:
                    terms["rotation_averaging"] = averaging
                out.append(Estimate(e.rung, e.order, terms, unestimated=e.unestimated, free_wobble=True))
        return out

    def cost(self, rung: str | None, start: float, stop: float, count: int, order: int | None = None,
             free_wobble: bool = False, rotation_scale: bool = False) -> Cost:
        """What a track of ``count`` epochs from ``start`` to ``stop`` (JD TDB) will cost (:mod:`ephem.theory.cost`),
        from the body's parameters alone, before anything is built. ``rung`` None: the estimates that
        choose a rung by tolerance (the chosen rung's own cost is charged once it is known)."""
        b = self.body
        check_domain(b)                       # not applicable: refused before any cost
        e = b.orbit.e
        n = mean_motion_rad_per_day(b.orbit.a_au, b.orbit.center)
        span = max(abs(stop - b.pole.epoch_jd_tdb), abs(start - b.pole.epoch_jd_tdb))
        orbits = span * n / (2.0 * math.pi)
        k = cost.body_harmonics(b)
        build = cost.hansen_build(e, None)
        # every track reports the estimates, which read the body's tables over one orbit (built once per process)
        tables = [] if tables_built(b) else [cost.estimate_tables(e)]
        if rung is None:
            parts = [build, cost.half_peak_to_peak(e, None, k),     # the second-order theory's components
                     cost.harmonic_sum(count, min(k, MAX_LADDER_ORDER + 2), "step_days", "the truncation bounds"),
                     *tables]
            if free_wobble:
                parts.append(cost.free_rotation("exact", count, 0.0))
            return Cost(tuple(parts))
        if rung == "secular":
            parts = [build, cost.harmonic_sum(count, 0, "step_days", "the secular track")]
        elif rung == "series":
            parts = [build, cost.hansen_build(e, order), cost.harmonic_sum(count, order + 2, "step_days", "the track")]
        elif rung == "hansen":
            parts = [build, cost.harmonic_sum(count, k, "step_days", "the track")]
        elif rung == "second_order":
            parts = [build, cost.second_order(count, k)]
        else:   # numerical, real_orbit: the second-order mean track is subtracted from the integrated pole
            parts = [build, cost.second_order(count, k), cost.spin_integration(orbits, e, count)]
            if rung == "real_orbit":   # integrated from the elements' epoch through the pole's and the track's
                epochs_jd = (start, stop, b.pole.epoch_jd_tdb, b.orbit.epoch_jd_tdb)
                parts.append(cost.orbit_integration(max(epochs_jd) - min(epochs_jd)))
        parts += tables
        if free_wobble:
            parts.append(cost.free_rotation("exact", count, 0.0))
        if rotation_scale:   # the rung again from the mean pole, and the closed-form terms at every epoch
            parts += [build, cost.harmonic_sum(count, 8, "step_days", "the rotation-scale terms")]
        return Cost(tuple(parts))

    def choose(self, jd_tdb, tolerance: float) -> Estimate:
        """The cheapest rung whose estimated error over the epochs is within ``tolerance`` (radians).

        Raises :class:`NotApplicableError` when none is, naming the best estimate available.
        """
        if isinstance(tolerance, bool) or not isinstance(tolerance, (int, float)) or not math.isfinite(tolerance) \
                or tolerance <= 0.0:
            raise InvalidInputError("tolerance_mas", f"must be a positive finite number, got {tolerance!r}",
                                    self.body.name)
        return cheapest_within([e for e in self.estimates(jd_tdb) if e.available], tolerance, self.body.name,
                               self.wobble is not None)

    def track(self, rung: str, jd_tdb, order: int | None = None, free_wobble: bool = False,
              rotation_scale: bool = False) -> Track:
        """The pole track of one rung at the epochs (JD TDB); with ``rotation_scale``, with the rotation-scale
        terms added (:meth:`rotation_scale_track`); with ``free_wobble``, the figure axis with the ladder's
        wobble added."""
        t = np.asarray(jd_tdb, dtype=float)
        track = self.rotation_scale_track(rung, t, order) if rotation_scale else self._rung_track(rung, t, order)
        return self.add_wobble(track) if free_wobble else track

    def mean_pole_body(self) -> Body:
        """The body with its pole moved from the figure axis at the pole epoch (the catalogue's pole) to the mean
        angular momentum L̄ there: less the Oppolzer offset, and the semi-diurnal term when the phase is known."""
        m = self.model
        s0 = m.catalogue_pole_orbit[None]
        terms = rotation_scale.rotation_terms(self._moments, m.spin_rate, s0, rotation_scale.SunGeometry.at(
            m, [m.pole_epoch]), None if self.rotation_phase is None else np.array([self.rotation_phase]))
        mean = m.icrf_from_orbit @ rotation_scale.apply(s0, -terms.figure_offset())[0]
        ra = math.degrees(math.atan2(mean[1], mean[0])) % 360.0
        dec = math.degrees(math.atan2(mean[2], math.hypot(mean[0], mean[1])))
        return replace(self.body, pole=replace(self.body.pole, ra_deg=ra, dec_deg=dec))

    @property
    def _moments(self) -> tuple[float, float, float]:
        return body_moments(self.body, self.model)

    def rotation_scale_track(self, rung: str, jd_tdb, order: int | None = None) -> Track:
        """A rung's track with the rotation-scale terms of :mod:`ephem.forced.rotation_scale`: the rung run from the mean
        pole (:meth:`mean_pole_body`), then moved by the figure axis's offset (or, for the angular momentum, by
        its semi-diurnal term) at every epoch."""
        t = np.asarray(jd_tdb, dtype=float)
        mean = Ladder(self.mean_pole_body(), "angular_momentum")._rung_track(rung, t, order)
        m = self.model
        pole = pole_vectors(mean) @ m.icrf_from_orbit
        phase = None
        if self.rotation_phase is not None:
            psi = np.arctan2(pole[:, 0], pole[:, 1])
            phase = rotation_scale.rotation_phase(m, t, self.rotation_phase, psi + np.round(
                (mean.psi - psi) / (2.0 * math.pi)) * 2.0 * math.pi)
        terms = rotation_scale.rotation_terms(self._moments, m.spin_rate, pole, rotation_scale.SunGeometry.at(m, t),
                                              phase)
        offset = terms.figure_offset() if self.axis == "figure" else terms.momentum_offset()
        return with_free_wobble(m, mean, rotation_scale.apply(pole, offset) @ m.icrf_from_orbit.T)

    def add_wobble(self, track: Track) -> Track:
        """A rung's track with the free wobble of the figure axis added (needs the ladder's ``wobble``)."""
        if self.wobble is None:
            raise InvalidInputError("free_wobble_phase_deg", "adding the free wobble needs its phase",
                                    self.body.name)
        figure = add_free_wobble(self.body, self.wobble, track.jd_tdb, pole_vectors(track),
                                 self._pole_at_wobble_epoch())
        return with_free_wobble(self.model, track, figure)

    def _pole_at_wobble_epoch(self) -> np.ndarray:
        # where the phase is counted; it sets only the north/east directions there, so rung 3 serves
        return pole_vectors(self.model.track([self.wobble.epoch_jd_tdb]))[0]

    def _rung_track(self, rung: str, t: np.ndarray, order: int | None) -> Track:
        from ..forced.integration import integrate_spin_axis  # scipy.integrate: 0.35 s to import, only for these rungs

        m = self.model
        if rung == "secular":
            return secular_track(m, t)
        if rung == "series":
            return cached_model(self.body, order).track(t)
        if rung == "hansen":
            return m.track(t)
        if rung == "second_order":
            return second_order_track(m, self.theory, t)
        if rung in ("numerical", "real_orbit"):
            why = numerical_unavailable(m, t)
            if why is not None:
                raise NotApplicableError(self.body.name, why)
        if rung == "numerical":
            return track_from_vectors(m, self.theory, t, integrate_spin_axis(m, t, rtol=NUMERICAL_RTOL))
        if rung == "real_orbit":
            why = real_orbit_unavailable(self.body, t)
            if why is not None:
                raise NotApplicableError(self.body.name, why)
            path = sun_path_for(self.body, t)
            return track_from_vectors(m, self.theory, t, integrate_spin_axis(
                m, t, rtol=NUMERICAL_RTOL, sun=path.position_scalar))
        raise InvalidInputError("model", f"unknown rung {rung!r}; one of {', '.join(RUNGS)}", self.body.name)


# --- the ladder as a theory of the spin axis (ephem.theory.interface) -------------------------------------------

#: What each rung of the fidelity ladder drops (see :mod:`ephem.sun.ladder`).
RUNG_DESCRIPTIONS = {
    "secular": "precession only: no nutation",
    "series": "Kinoshita-Cayley nutation, Hansen coefficients as e-power series truncated at e^order",
    "hansen": "Kinoshita-Cayley nutation with exact Hansen coefficients (first order in the torque)",
    "second_order": "second order in the torque: the equinox drift re-phases the nutation, plus the "
                    "second-order mean rates",
    "numerical": "rotation-averaged torque integrated numerically along the fixed Keplerian orbit",
    "real_orbit": "rotation-averaged torque integrated along the real orbit (DE421 and planetary perturbations)",
}

AXIS_ASSUMPTIONS = {
    "angular_momentum": "the pole served is the angular momentum, which the free wobble does not move",
    "figure": "the pole served is the figure axis, taken as the angular momentum: the free wobble is left "
              "out and counted in the estimate (free_wobble)",
    "figure+wobble": "the pole served is the figure axis: the torque-free rigid-body wobble (given J and phase) "
                     "added about the forced angular momentum",
}


class SunLadder(SpinAxisTheory):
    """The single-perturber ladder (:class:`Ladder`) behind the common interface: a body torqued by the
    centre of its orbit alone, its rungs cheapest first."""

    summary = "the single-perturber ladder (a body torqued by the centre of its orbit)"
    models = RUNGS
    descriptions = RUNG_DESCRIPTIONS
    propagates_uncertainty = True
    models_rotation_scale = True

    @classmethod
    def serves(cls, body: Body, perturbers: tuple[str, ...]) -> bool:
        return tuple(perturbers) == (body.orbit.center,)

    @cached_property
    def ladder(self) -> Ladder:
        return Ladder(self.body, self.axis, self.wobble, self.rotation_phase)   # one per request

    @classmethod
    def how_to_reach(cls, body: Body) -> str:
        return f"pass perturbers={body.orbit.center.lower()} for it (the centre of {body.name}'s orbit alone)"

    def default_model(self, order: int | None) -> str:
        return "hansen" if order is None else "series"

    def check_request(self, model: str | None, order: int | None) -> None:
        rung = model or self.default_model(order)
        if rung == "series" and order is None:
            raise InvalidInputError("order", "the 'series' model needs an e-order")
        if order is not None and rung != "series":
            raise InvalidInputError("order", f"an e-order applies to the 'series' model, not to {rung!r}")
        if order is not None and self.body.orbit.e > LAPLACE_LIMIT:
            model_for(self.body, self.body.dataset, order)     # refuses the diverging series, before any cost

    def choice_cost(self, start: float, stop: float, count: int) -> Cost:
        return self.ladder.cost(None, start, stop, count, free_wobble=self.wobble is not None)

    def track_cost(self, model, order, start, stop, count, free_wobble, rotation_scale=False) -> Cost:
        return self.ladder.cost(model or self.default_model(order), start, stop, count, order, free_wobble,
                                rotation_scale)

    def estimates(self, jd_tdb) -> list[Estimate]:
        return self.ladder.estimates(jd_tdb)

    def named(self, jd_tdb, model, order):
        rung = model or self.default_model(order)
        # a named rung adds the rotation-scale terms when the request gave the rotation phase
        scale = None if self.rotation_phase is None else self.ladder.rotation_modelled
        return next((e for e in self.estimates(jd_tdb) if e.rung == rung and e.order == order
                     and e.free_wobble == (self.wobble is not None) and e.rotation_scale == scale), None)

    def track(self, est, model, order, t0, step, count) -> Track:
        scale = est.rotation_scale is not None if est is not None else self.rotation_phase is not None
        if model in ("hansen", "series") and not scale:   # the fast evaluation on an even grid
            tr = cached_model(self.body, order).track_grid(t0, step, count)
        else:
            tr = self.ladder.track(model, self.grid(t0, step, count), order, rotation_scale=scale)
        if self.wobble is not None and (est is None or est.free_wobble):
            tr = self.ladder.add_wobble(tr)
        return tr

    def track_at(self, model, order, jd_tdb, free_wobble=False) -> Track:
        return self.ladder.track(model or self.default_model(order), jd_tdb, order, free_wobble,
                                 rotation_scale=self.rotation_phase is not None)

    def describe(self, est, model, order, with_wobble) -> dict:
        info = model_info(cached_model(self.body, order), self.body)
        info["assumptions"] = [AXIS_ASSUMPTIONS["figure+wobble" if with_wobble else self.axis]] + ASSUMPTIONS[1:] \
            + RUNG_ASSUMPTIONS[model]
        return info

    def secular_spin(self) -> SpinConstants:
        """The first-order theory's mean pole and precession constant (K/2) f(e) (Petit et al. eq. 25)."""
        m = cached_model(self.body)
        half_psi, half_eps = m.nutation.semi_peak_to_peak()
        return spin_constants(self.body, m.pole_epoch, m.icrf_from_orbit, m.obliquity,
                              0.5 * m.scaling_factor * eccentricity_factor(m.eccentricity), 0.0,
                              math.hypot(half_psi * math.sin(m.obliquity), half_eps),
                              "Kinoshita's first-order theory (Petit et al. 2014 eq. 25): the precession constant "
                              "(K/2)(1 - e^2)^(-3/2), K = 3 n^2 H_d / omega")

    def spectrum(self, aim_mas: float, mid_centuries: float, jd_tdb=None, psi=None) -> Spectrum:
        m = cached_model(self.body)
        if jd_tdb is None:
            return mean_anomaly_spectrum(m, aim_mas, m.precession_rate)
        # ψ̇ as the track has it (the rungs above 'hansen' change the mean rates): ψ = a + ψ̇ t + nutation
        t = np.asarray(jd_tdb, dtype=float)
        mt = m.mean_anomaly(t)
        cols = [np.ones_like(t), t - 0.5 * (t[0] + t[-1])]
        for k in np.unique(m.nutation.multiple):
            cols += [np.sin(k * mt), np.cos(k * mt)]
        psi_dot = float(np.linalg.lstsq(np.array(cols).T, np.asarray(psi, dtype=float), rcond=None)[0][1])
        return mean_anomaly_spectrum(m, aim_mas, psi_dot)

    # --- the precession and nutation answers

    def answer_cost(self, order: int | None, nutation: bool = False, tolerance: bool = False) -> Cost:
        """The Hansen coefficients, the nutation's extremes, and the propagation of the inputs' σ (each input
        with a σ re-evaluates the model twice); ``tolerance``: the truncation bounds of the e-orders."""
        b = self.body
        check_domain(b, order)                   # not applicable (too slow a rotation, e -> 1): before any cost
        e = b.orbit.e
        if order is not None and e > LAPLACE_LIMIT:
            return cost.FREE      # refused by model_for before any work
        build = cost.hansen_build(e, None)
        parts = [build] if order is None else [build, cost.hansen_build(e, order)]
        if nutation:
            parts.append(cost.half_peak_to_peak(e, order, cost.body_harmonics(b, order)))
        if tolerance:
            parts.append(cost.truncation_bounds(e))
        with_sigma = sum(1 for v in input_sigmas(b).values() if v is not None)
        if with_sigma:
            half = cost.half_peak_to_peak(e, order, cost.body_harmonics(b, order))
            parts.append(cost.Part("the catalogue's uncertainties", f"propagating {with_sigma} input uncertainties",
                                   2 * with_sigma * parts[1 if order is not None else 0].cpu_s + 2 * half.cpu_s,
                                   build.memory_mb))
        return Cost(tuple(parts))

    def order_for_tolerance(self, tolerance: float | None, order: int | None) -> int | None:
        """The lowest e-order whose truncation error is within the tolerance (None: exact coefficients); for
        the rate and the nutation terms (no time span): the truncation bound alone."""
        if tolerance is None:
            return order
        if order is not None:
            raise InvalidInputError("order", "give either order or tolerance_mas, not both")
        m = cached_model(self.body)
        if m.eccentricity < LAPLACE_LIMIT:
            kmax = int(m.nutation.multiple.max()) if m.nutation.multiple.size else 0
            for n in range(0, min(kmax, MAX_ORDER)):
                if truncation_bound(m, n, 0.0) <= tolerance:
                    return n
        return None

    def _selection(self, order: int | None, tol: float | None, start: float) -> dict:
        m = cached_model(self.body)
        # never 0 (issue 29): the exact coefficients' own floor, the harmonics dropped under their amplitude cut
        # (twice: they also move the mean pole) and the rounding of every coefficient kept, is part of both
        floor = exact_series_floor(m.nutation.dropped, pole_displacement_sum(m.nutation, m.obliquity))
        estimate = floor + (0.0 if order is None else truncation_bound(m, order, 0.0))
        if tol is not None and estimate > tol:
            raise NotApplicableError(self.body.name, (
                f"no e-order meets the tolerance of {tol / MAS:.6g} mas: the exact Hansen coefficients are good to "
                f"{estimate / MAS:.3g} mas (the harmonics under their amplitude cut and the coefficients' rounding)"))
        return selection_info(self, "hansen" if order is None else "series", order, estimate,
                              1e3 * (time.perf_counter() - start), tol, covers=COVERS_TRUNCATION)

    def precession_answer(self, order: int | None, tolerance: float | None, start: float) -> dict:
        b = self.body
        charge(self.answer_cost(order, tolerance=tolerance is not None), b.name)
        order = self.order_for_tolerance(tolerance, order)
        m = model_for(b, b.dataset, order)
        unc = propagated(b, order)
        ans = rate_values(b, m, unc)
        ans["uncertainty"] = summary(unc)
        ans["model"] = model_info(m, b)
        ans["model"].update(self._selection(order, tolerance, start))
        return ans

    def nutation_answer(self, order: int | None, tolerance: float | None, cut_mas, start: float) -> dict:
        b = self.body
        if cut_mas is not None:
            raise InvalidInputError("cut_mas", "an amplitude cut applies to the lunisolar series (the Earth with the "
                                    "Moon); this series is truncated by e-order (order, tolerance_mas)", b.name)
        charge(self.answer_cost(order, nutation=True, tolerance=tolerance is not None), b.name)
        order = self.order_for_tolerance(tolerance, order)
        m = model_for(b, b.dataset, order)
        s = m.nutation
        terms = [{
            "multiple": int(k), "period_days": float(p), "period_years": float(p / JULIAN_YEAR_DAYS),
            "longitude_sin_arcsec": float(a / ARCSEC), "longitude_cos_arcsec": float(c / ARCSEC),
            "obliquity_sin_arcsec": float(d / ARCSEC), "obliquity_cos_arcsec": float(f / ARCSEC),
        } for k, p, a, c, d, f in zip(s.multiple, s.period_days, s.lon_sin, s.lon_cos, s.obl_sin, s.obl_cos)]
        unc = propagated(b, order)
        sin_eps = abs(math.sin(m.obliquity))
        for term, sigma in zip(terms, unc["terms"]):
            if sigma["multiple"] != term["multiple"]:  # pragma: no cover - both come from the same series
                raise RuntimeError("uncertainty terms out of step with the nutation terms")
            term["period_days_uncertainty"] = sigma["period_days_uncertainty"]
            for comp in ("longitude", "obliquity"):
                for part in ("sin", "cos"):
                    term[f"{comp}_{part}_arcsec_uncertainty"] = sigma[f"{comp}_{part}_arcsec_uncertainty"]
                # the paper's Amp: (Sin² + Cos²)^½, times sin ε in longitude
                amp = math.hypot(term[f"{comp}_sin_arcsec"], term[f"{comp}_cos_arcsec"])
                term[f"{comp}_amplitude_arcsec"] = amp * (sin_eps if comp == "longitude" else 1.0)
                term[f"{comp}_amplitude_arcsec_uncertainty"] = sigma[f"amplitude_{comp}_arcsec_uncertainty"]
        half_psi, half_eps = semi_amplitudes(b, m.order)
        ans = {
            "body": b.name, "dataset": b.dataset, "argument": "mean anomaly M",
            "mean_anomaly_at_epoch_deg": math.degrees(m.mean_anomaly_at_epoch) % 360.0,
            "orbit_epoch_jd_tdb": m.orbit_epoch,
            "mean_motion_deg_per_day": math.degrees(m.mean_motion),
            "obliquity_deg": math.degrees(m.obliquity),
            "terms": terms,
            "delta_psi_half_peak_to_peak_arcsec": half_psi / ARCSEC,
            "delta_epsilon_half_peak_to_peak_arcsec": half_eps / ARCSEC,
            "delta_psi_half_peak_to_peak_arcsec_uncertainty": unc["delta_psi_half_peak_to_peak_arcsec_uncertainty"],
            "delta_epsilon_half_peak_to_peak_arcsec_uncertainty":
                unc["delta_epsilon_half_peak_to_peak_arcsec_uncertainty"],
            "uncertainty": summary(unc),
            "model": model_info(m, b),
        }
        ans["model"].update(self._selection(order, tolerance, start))
        return ans


#: Sidebands ±j ψ̇ a track carries about each harmonic of the mean anomaly (the second-order theory's mixing
#: of the precession into the nutation phases, and the kernel's linear-in-T phases).
TRACK_SIDEBANDS = 3
#: Highest multiple of the mean anomaly in a track's spectrum: beyond the last harmonic of the nutation
#: series that moves the pole by a hundredth of the aim, by HARMONIC_MARGIN (its products with others),
#: at most twice the series' own and MAX_MULTIPLE.
MAX_MULTIPLE = 64
HARMONIC_MARGIN = 4


def mean_anomaly_spectrum(m: PrecessionNutation, aim_mas: float, psi_dot: float) -> Spectrum:
    """Harmonics k = 0..kmax of the mean anomaly (k = 0: the precession alone), with ψ̇ (rad/day)."""
    series = m.nutation
    kmax_series = int(series.multiple.max()) if series.multiple.size else 1
    amp = pole_displacements(series, m.obliquity)
    big = series.multiple[amp > 0.01 * aim_mas * MAS]
    kmax = int(min(MAX_MULTIPLE, 2 * kmax_series, (int(big.max()) if big.size else 1) + HARMONIC_MARGIN))
    ks = np.arange(0, kmax + 1)
    amplitude = np.zeros(ks.size)
    for k, a in zip(series.multiple, amp):
        if k <= kmax:
            amplitude[int(k)] = a
    m_j2000 = float(m.mean_anomaly(J2000_JD))
    return Spectrum(tuple(int(k) for k in ks), np.degrees(ks * m_j2000) % 360.0,
                    np.degrees(ks * m.mean_motion) * JULIAN_CENTURY_DAYS, amplitude,
                    math.degrees(psi_dot * (J2000_JD - m.pole_epoch)) % 360.0,
                    math.degrees(psi_dot) * JULIAN_CENTURY_DAYS, TRACK_SIDEBANDS, "k: multiple of the mean anomaly")


@lru_cache(maxsize=512)
def semi_amplitudes(body: Body, order: int | None) -> tuple[float, float]:
    """Half the peak-to-peak Δψ, Δε (radians) of the body's nutation series (Petit et al. Table 4)."""
    return cached_model(body, order).nutation.semi_peak_to_peak()
