"""The harmonic-sum engine (ephem/harmonics.py): both evaluators against direct sums in long double.

:func:`rounding_bound` and :func:`direct_sums` are shared with tests/test_kinoshita.py (the nutation
series summed by the same engine).
"""
import numpy as np
import pytest

from ephem.harmonics import evaluate_harmonics, evaluate_harmonics_uniform


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
