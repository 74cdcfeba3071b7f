"""The harmonic-sum engine (ephem/orbit/harmonics.py): both evaluators against direct sums in long double.

:func:`rounding_bound` and :func:`direct_sums` are shared with tests/forced/test_kinoshita.py (the nutation
series summed by the same engine).
"""
import numpy as np
import pytest

from ephem.orbit.harmonics import (PeriodicTable, evaluate_harmonics, evaluate_harmonics_periodic,
                                   evaluate_harmonics_uniform, harmonic_norms)


def rounding_bound(sin_c, cos_c):
    """Worst-case rounding of the three-term recurrence for O(1) coefficients: each of the
    kmax harmonics carries up to ~kmax ulps, summed over the coefficients' magnitudes."""
    kmax = sin_c.shape[0]
    return 4.0 * kmax**2 * np.finfo(float).eps * (np.abs(sin_c).sum() + np.abs(cos_c).sum())


def direct_sums(x, sin_c, cos_c):
    """Reference sums, one sin/cos per harmonic in long double (k x reaches ~1e3 rad, where
    float64 products alone would carry ~1e-13 of rounding)."""
    x = np.asarray(x, dtype=np.longdouble)
    k = np.arange(1, sin_c.shape[0] + 1, dtype=np.longdouble)[:, None]
    kx = k * x
    return (np.sin(kx).T @ sin_c.astype(np.longdouble) + np.cos(kx).T @ cos_c.astype(np.longdouble)).astype(float)


@pytest.mark.parametrize("kmax", [1, 2, 6, 12, 16, 17, 30])
def test_harmonic_evaluator_matches_direct_sums(kmax):
    # kmax <= 16 uses the power basis of cos x, above it the three-term recurrence
    rng = np.random.default_rng(kmax)
    sin_c = rng.normal(size=(kmax, 2))
    cos_c = rng.normal(size=(kmax, 2))
    x = rng.uniform(-50, 50, size=70001)  # more than one block
    got = evaluate_harmonics(x, np.arange(1, kmax + 1), sin_c, cos_c)
    direct = direct_sums(x, sin_c, cos_c)
    for j in range(2):
        assert np.max(np.abs(got[j] - direct[:, j])) < rounding_bound(sin_c, cos_c)


@pytest.mark.parametrize("kmax, count", [(6, 1), (12, 20000), (30, 9000)])
def test_uniform_grid_evaluator_matches_direct_sums(kmax, count):
    rng = np.random.default_rng(kmax)
    sin_c = rng.normal(size=(kmax, 2))
    cos_c = rng.normal(size=(kmax, 2))
    x0, dx = 2.345678, 0.0173
    got = evaluate_harmonics_uniform(x0, dx, count, np.arange(1, kmax + 1), sin_c, cos_c)
    x = np.longdouble(x0) + np.longdouble(dx) * np.arange(count, dtype=np.longdouble)
    direct = direct_sums(x, sin_c, cos_c)
    for j in range(2):
        assert np.max(np.abs(got[j] - direct[:, j])) < rounding_bound(sin_c, cos_c)


def test_a_column_whose_last_cosine_is_zero_is_summed():
    # the power basis converts each column's Chebyshev series to powers; numpy trims a trailing zero there, and a
    # column of differences (a truncated series against the exact one) often ends in zeros
    rng = np.random.default_rng(3)
    sin_c = rng.normal(size=(6, 3)) * 0.1 ** np.arange(6)[:, None]   # decaying: the power basis is used
    cos_c = rng.normal(size=(6, 3)) * 0.1 ** np.arange(6)[:, None]
    cos_c[4:, 1] = 0.0
    cos_c[:, 2] = 0.0
    x = rng.uniform(-4, 4, size=200)
    got = evaluate_harmonics(x, np.arange(1, 7), sin_c, cos_c)
    direct = direct_sums(x, sin_c, cos_c)
    for j in range(3):
        assert np.max(np.abs(got[j] - direct[:, j])) < rounding_bound(sin_c, cos_c)


@pytest.mark.parametrize("decay", [0.3, 0.8, 0.97])
def test_periodic_table_bounds_the_largest_excursion_over_any_interval(decay):
    # PeriodicTable.interval_max is an upper bound on max |F(x) - ref + slope (x - x0)| over [x_lo, x_hi] (tested
    # against 20001 exact samples of the interval, spaced well below the period of the highest harmonic) and close
    # to it: its interpolation bound keeps within
    # REFINE = 2% of the largest sample for short intervals and TABLE_RESOLUTION of Σ|c_k| for whole periods;
    # the 1e-12 absorbs the rounding of sums of O(1) coefficients
    rng = np.random.default_rng(int(decay * 100))
    kmax = 40
    scale = decay ** np.arange(kmax)[:, None, None]
    sin_c, cos_c = rng.normal(size=(kmax, 2, 2)) * scale, rng.normal(size=(kmax, 2, 2)) * scale
    x0 = 1.3
    table = PeriodicTable.of_harmonics(sin_c, cos_c, x0)
    reach = harmonic_norms(sin_c, cos_c).sum(axis=0)
    k = np.arange(1, kmax + 1)
    flat_s, flat_c = sin_c.reshape(kmax, 4), cos_c.reshape(kmax, 4)

    def exact(x):   # a direct sum in double precision: rounding ~1e-15 of these O(1) sums
        return (np.sin(np.outer(x, k)) @ flat_s + np.cos(np.outer(x, k)) @ flat_c).reshape(-1, 2, 2)

    start = exact([x0])[0]
    for lo, width in [(0.2, 1e-4), (-3.0, 0.05), (5.0, 2.0), (-1.0, 6.0), (2.0, 30.0), (-20.0, 100.0)]:
        for ref, slope in [(None, None), (start, None), (start, rng.normal(size=(2, 2)) * 0.01)]:
            x = np.linspace(lo, lo + width, 20001)
            f = exact(x)
            if ref is not None:
                f = f - ref
            if slope is not None:
                f = f + (x - x0)[:, None, None] * slope
            truth = np.max(np.linalg.norm(f, axis=-1), axis=0)
            bound = table.interval_max(lo, lo + width, ref, slope)
            assert np.all(bound >= truth - 1e-12), (lo, width)
            slack = np.maximum(0.02 * truth, 3e-3 * reach) if width < 2 * np.pi else 3e-3 * reach
            assert np.all(bound <= truth + slack + 1e-12), (lo, width, bound, truth)


@pytest.mark.parametrize("kmax,count", [(1, 3), (7, 64), (40, 81), (300, 4096)])
def test_the_periodic_grid_evaluator_matches_direct_sums(kmax, count):
    # one inverse FFT for a whole period of samples (PeriodicTable's tables, the second-order remainder's grid):
    # the same sums as the direct ones to the recurrence's rounding, whenever the grid has more than 2 kmax points
    rng = np.random.default_rng(kmax)
    sin_c, cos_c = rng.normal(size=(kmax, 3)), rng.normal(size=(kmax, 3))
    x0 = 2.7
    got = evaluate_harmonics_periodic(x0, count, sin_c, cos_c)
    direct = direct_sums(x0 + 2.0 * np.pi * np.arange(count) / count, sin_c, cos_c)
    assert np.max(np.abs(got - direct)) < rounding_bound(sin_c, cos_c)
    with pytest.raises(ValueError, match="alias"):
        evaluate_harmonics_periodic(x0, 2 * kmax, sin_c, cos_c)
