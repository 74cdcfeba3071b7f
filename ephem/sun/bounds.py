"""The ladder's span-aware error bounds and the per-body tables they read.

The tables (:class:`TheoryTables`, :class:`PhasedBounds`): the nutation, the truncated series' differences and
the second-order remainder over one orbit as periodic tables, built once per body; the whole-orbit truncation
bound of an e-order. The bounds over given epochs: the theory terms of rungs 1-4 (nutation omitted, truncation,
second order, higher order; :func:`theory_terms`); the numerical rungs' own error and reach are theirs
(:mod:`ephem.sun.rungs`).

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

from ..base.memo import bytes_bounded
from ..bodies.catalogue import Body
from ..forced.kinoshita import eccentricity_factor, nutation_coefficients, pole_displacement_sum
from ..forced.precession_nutation import PrecessionNutation, cached_model
from ..forced.second_order import (PhasedSeries, Remainder, SecondOrderTheory, eval_phi, second_order_remainder,
                                   second_order_theory)
from ..orbit.hansen import LAPLACE_LIMIT, hansen_exact, hansen_series
from ..orbit.harmonics import FRESH_STEPS, PeriodicTable, harmonic_sum, refined_count
from .geodesic import geodesic_bounds


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
def _grids_kept(tables: TheoryTables) -> tuple:
    """What the tables have filled in (their only growth: the remainder's grids by phase, each a function of its
    key): the pool weighs them again when this changes, not at every request (a walk of ~0.1-0.15 ms)."""
    return tuple(tables.periodic._tables), tuple(tables.rephasing._tables)


@bytes_bounded(grows=_grids_kept)
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


# ----------------------------------------------------------------------------- the bounds over given epochs

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



#: Epochs whose mean pole's phase is within this of the pole epoch's (radians) use the remainder's table at the
#: pole epoch, with the difference times sup |∂P2/∂φ| added (at most 0.4% of P2's size: |∂P2/∂φ| <= 4 sup|P2|).
NEAR_PHASE = 1e-3


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


def mean_rate_harmonics(theory: SecondOrderTheory) -> np.ndarray:
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
    #: what every bound of the window reads, worked out once (read only: a bound that changes one copies it): the
    #: mean rates' φ-harmonics (:func:`mean_rate_harmonics`), rung 4's drift's
    #: (:meth:`~ephem.forced.second_order.Remainder.drift_harmonics`), and (|a|, |(b, c)|) largest over the
    #: window's mean anomalies (``tables.abc.interval_max``)
    rates: np.ndarray
    drift: np.ndarray
    abc: tuple

    @classmethod
    def of(cls, theory: SecondOrderTheory, tables: TheoryTables, window: Window) -> _Drifts:
        T = window.span
        rates, drift = mean_rate_harmonics(theory), tables.remainder.drift_harmonics()
        g_psi, g_eps, d_psi, d_eps = _sup_abs(rates[0]), _sup_abs(rates[1]), _sup_abs(drift[0]), _sup_abs(drift[1])
        # ψ̄ - ψ̇ T = ∫ G_ψ + (K/2) f (cos ε̄ - cos ε̄0), |ε̄ - ε̄0| <= sup|G_ε + d_ε| T
        se = abs(math.sin(theory.obliquity))
        slack = (g_psi + d_psi) * T + theory.first_order_rate * se * (g_eps + d_eps) * T * T / 2.0
        return cls(T, g_psi, g_eps, d_psi, d_eps, slack, rates, drift,
                   tuple(tables.abc.interval_max(*window.mean_anomalies)))


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
    mean = _mean_pole_bound(theory, tables, window, dr, dr.rates, dr.g_eps)
    lo, hi = window.phases(model.precession_rate, dr.slack, from_t0=False)
    turn = min(1.0, max(abs(lo), abs(hi)))
    a, bc = dr.abc
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
    drift = dr.drift
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
    rates, drift = dr.rates, dr.drift
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
    a, bc = dr.abc
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
    _, bc = dr.abc
    geodesic, rephasing = geodesic_bounds(model, dr.rates, tables.weight, bc,
                                          tables.periodic.slope_phi, window.mean_anomalies, window.m0, window.span)
    return {"nutation_omitted": nutation_omitted_bound(tables, window),
            "truncation": truncation_bounds(model, tables, window), "second_order": float(first),
            "higher_order": float(higher), "geodesic": geodesic, "geodesic_rephasing": rephasing}
