"""The ladder's per-body tables over one orbit: the nutation, the truncated series' differences and the
second-order remainder as periodic tables (:class:`TheoryTables`, :class:`PhasedBounds`), built once per body and
read by the span-aware error bounds (:mod:`ephem.sun.bounds`); the whole-orbit truncation bound of an e-order.

Every analytic rung and rung 5 start from the catalogue pole at the pole epoch t0, so a rung's error at t is what
the difference of the two has accumulated since t0: a periodic function of the mean anomaly M (and of the slow
phase φ = θ̄0 + ψ̄), taken relative to its value at t0, plus drifts growing with t - t0. The periodic parts are
bounded by their largest excursion over the mean anomalies the epochs cover (PeriodicTable, from these tables),
the drifts by their rate times the largest |t - t0| (:class:`Window`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..bodies.catalogue import Body
from ..base.memo import bytes_bounded
from ..forced.kinoshita import eccentricity_factor, nutation_coefficients, pole_displacement_sum
from ..forced.precession_nutation import PrecessionNutation, cached_model
from ..forced.second_order import (PhasedSeries, Remainder, SecondOrderTheory, eval_phi, second_order_remainder,
                                   second_order_theory)
from ..orbit.hansen import LAPLACE_LIMIT, hansen_exact, hansen_series
from ..orbit.harmonics import PeriodicTable, harmonic_sum

#: Highest e-power order the ladder tries for rung 2 (a truncated series is cheaper than the
#: exact one only while it has fewer harmonics).
MAX_LADDER_ORDER = 20


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


@bytes_bounded      # a body of the caller's: bounded in bytes with the model (ephem.base.memo)
def cached_theory(body: Body) -> SecondOrderTheory:
    return second_order_theory(cached_model(body))

