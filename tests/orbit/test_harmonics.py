"""The harmonic-sum engine (ephem/orbit/harmonics.py): both evaluators against direct sums in long double.

:func:`rounding_bound` and :func:`direct_sums` are shared with tests/forced/test_kinoshita.py (the nutation
series summed by the same engine).
"""
import numpy as np
import pytest

from ephem.orbit import harmonics
from ephem.orbit.harmonic_grid import evaluate_harmonics_uniform
from ephem.orbit.harmonics import PeriodicTable, evaluate_harmonics, evaluate_harmonics_periodic, harmonic_norms


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


# --- cos and sin without a trigonometric call per angle (the track kernel's, ephem/forced/precession_nutation.py)

def _ulps_from_long_double(x, c, s):
    """Largest error of c, s as cos x, sin x, in units of 2^-53 (half an ulp of 1: the sizes are at most 1)."""
    xl = np.asarray(x, dtype=np.longdouble)
    err = max(float(np.max(np.abs(c - np.cos(xl)))), float(np.max(np.abs(s - np.sin(xl)))))
    return err / 2.0**-53


@pytest.mark.parametrize("lo, hi", [(-7.0, 7.0), (0.0, 1e-3), (3.1, 3.2), (-1e3, 1e3), (-1e5, 1e5),
                                    (-3e5, 3e5), (1.0e5, 1.03e5)])
def test_table_cos_sin_are_within_a_few_ulp(lo, hi):
    # cos_sin_into: a 4096-angle table (each entry within half an ulp) and the Taylor series of the rest (cut below
    # 2^-57), the angle reduced by 2π/4096 in two parts; beyond REDUCE_LIMIT (1.03e5) numpy's. Budget 6 × 2^-53
    # (3 ulp of 1): the table entry, the two series and the two products each round once (numpy's own: 1 × 2^-53)
    x = np.random.default_rng(int(hi)).uniform(lo, hi, 60_001)
    c, s, work = np.empty_like(x), np.empty_like(x), np.empty((4, x.size))
    harmonics.cos_sin_into(x, c, s, work)
    assert _ulps_from_long_double(x, c, s) <= 6.0
    harmonics.cos_sin_into(x[::-1].copy(), c, s, work)      # any order: the same numbers
    c2, s2 = np.empty_like(x), np.empty_like(x)
    harmonics.cos_sin_into(x, c2, s2, work)
    assert np.array_equal(c[::-1], c2) and np.array_equal(s[::-1], s2)


@pytest.mark.parametrize("spread", [0.0, 1e-9, 3.6e-6, 1.1e-4, 1.3e-3, 4e-3, 8.9e-3, 0.00999, 0.05, 0.3])
def test_shifted_cos_sin_are_within_a_few_ulp_on_both_sides_of_each_switch(spread):
    # shift_factors: cos δ, sin δ by their Taylor series with the terms |δ|'s bound needs (the spreads bracket where
    # one more term is taken), composed with cos, sin of the middle angle as the track kernel does: within
    # 6 × 2^-53 of cos x, sin x, so a term switch flipped by a last bit moves them by a few ulp at most
    x = 0.7 + np.linspace(-spread, spread, 20_001)          # the middle one is 0.7
    delta = x - 0.7
    cd, sd, d2 = np.empty_like(x), np.empty_like(x), np.empty_like(x)
    sd = harmonics.shift_factors(delta, spread * (1 + 2.0**-20), cd, sd, d2)
    c = np.cos(0.7) * cd - np.sin(0.7) * sd
    s = np.sin(0.7) * cd + np.cos(0.7) * sd
    assert _ulps_from_long_double(x, c, s) <= 6.0


def test_the_series_leave_out_less_than_their_cut():
    # _series_terms: the first term left out (an alternating series with falling terms bounds the rest by it) is
    # below SHIFT_TRUNCATION, and one term fewer would not be
    import math
    for beta in np.geomspace(1e-10, 0.5, 400):
        n_sin, n_cos = harmonics._series_terms(float(beta))
        first_out = (beta ** (2 * n_sin + 1) / math.factorial(2 * n_sin + 1), beta ** (2 * n_cos) / math.factorial(2 * n_cos))
        assert max(first_out) <= harmonics.SHIFT_TRUNCATION
        if n_sin > 1:
            assert beta ** (2 * n_sin - 1) / math.factorial(2 * n_sin - 1) > harmonics.SHIFT_TRUNCATION
        if n_cos > 1:
            assert beta ** (2 * n_cos - 2) / math.factorial(2 * n_cos - 2) > harmonics.SHIFT_TRUNCATION


def test_non_finite_angles_give_nan_as_numpy():
    x = np.array([0.3, np.nan, np.inf, -np.inf, 1.0])
    c, s = np.empty_like(x), np.empty_like(x)
    with np.errstate(invalid="ignore"):
        harmonics.cos_sin_into(x, c, s, np.empty((4, x.size)))
        assert np.array_equal(np.isnan(c), np.isnan(np.cos(x))) and np.array_equal(np.isnan(s), np.isnan(np.sin(x)))


@pytest.mark.parametrize("extended, budget", [(True, 2.0**-54 + 1e-18), (False, 2.0**-53)])
def test_the_table_entries(extended, budget):
    # in long double (x87: 64-bit mantissa) each entry is the double nearest cos, sin of j 2π/4096 but for the
    # long double angle's 3e-19; where numpy's long double is a plain double (some platforms) the table corrects
    # libm's value at the rounded angle by that rounding: within 2^-53 (an ulp of 1)
    c, s = harmonics._cos_sin_table(extended=extended)
    j = np.arange(c.size, dtype=np.longdouble)
    a = 2 * np.longdouble("3.14159265358979323846264338327950288") * j / c.size
    assert np.max(np.abs(c - np.cos(a))) <= budget and np.max(np.abs(s - np.sin(a))) <= budget


@pytest.mark.parametrize("kmax, count", [(1, 5000), (48, 4097), (49, 4097), (12, 8192), (12, 8193), (3, 0)])
def test_uniform_grid_evaluator_with_its_work_rows(kmax, count):
    # the grid's two routes (UniformHarmonics up to the power basis's 48 harmonics, uniform_cos_sin and the
    # Chebyshev sums beyond; blocks whole or cut): the direct sums, as the test of the Kinoshita series: the grid rounds its angles (a block's
    # start x0 + i dx, |x| <= 62 rad here, a few ulp of it), which harmonic k turns into k times that phase error
    rng = np.random.default_rng(kmax + count)
    sin_c, cos_c = rng.normal(size=(kmax, 2)), rng.normal(size=(kmax, 2))
    x0, dx = -1.234567, 0.0123
    got = evaluate_harmonics_uniform(x0, dx, count, np.arange(1, kmax + 1), sin_c, cos_c)
    x = np.longdouble(x0) + np.longdouble(dx) * np.arange(count, dtype=np.longdouble)
    direct = direct_sums(x, sin_c, cos_c)
    k = np.arange(1, kmax + 1)[:, None]
    phase = 4 * np.spacing(abs(x0) + dx * count) * (k * (np.abs(sin_c) + np.abs(cos_c))).sum(axis=0)
    for j in range(2):
        assert got[j].shape == (count,)
        if count:
            assert np.max(np.abs(got[j] - direct[:, j])) < rounding_bound(sin_c, cos_c) + phase[j]


def test_no_harmonics_sum_to_zero():
    none = np.zeros((0, 2))
    for got in (evaluate_harmonics_uniform(0.3, 0.1, 7, np.arange(1, 1), none, none),
                evaluate_harmonics(np.linspace(0, 1, 7), np.arange(1, 1), none, none)):
        assert all(np.array_equal(g, np.zeros(7)) for g in got)
    sums = harmonics.HarmonicSums(np.arange(1, 1), none, none, 7)
    out = np.ones((2, 7))
    sums.into(np.zeros(7), np.zeros(7), out)
    assert np.array_equal(out, np.zeros((2, 7)))


# --- bounded work whatever the request (moved from tests/service/test_bounded_work.py, issue 43)

def test_the_harmonic_work_table_is_bounded_whatever_the_harmonics():
    # e = 0.99 keeps ~4e4 harmonics: an 8192-epoch block of them would be 5.5 GB
    k = np.arange(1, 42_001)
    _, _, work, block = harmonics._prepare(k, np.zeros((k.size, 2)), np.zeros((k.size, 2)), 10_000)
    assert work.nbytes <= harmonics.BLOCK_BYTES and block >= 1


def test_the_nutation_extremes_need_no_dense_table():
    # one formula (harmonics.series_extrema) for the answers and the uncertainties; checked against a
    # dense grid on a two-term series whose extremes are known in closed form: sin M + 0.5 sin 2M has its
    # maximum 1.299038... (= 3√3/4) at M = π/3; half peak-to-peak the same by symmetry
    half, x_max, x_min = harmonics.series_extrema(np.array([1.0, 0.5]), np.array([0.0, 0.0]))
    assert half == pytest.approx(3.0 * np.sqrt(3.0) / 4.0, rel=1e-14)   # Newton-polished: rounding only
    assert x_max == pytest.approx(np.pi / 3.0, abs=1e-7)                 # a flat maximum: sqrt(eps) in M
