"""The moments from what is measured (ephem.bodies.inertia): each method against an independent identity, and the
moments' covariance against a Monte Carlo of the inputs."""
import math

import numpy as np
import pytest

from ephem.base.errors import InvalidInputError
from ephem.bodies.inertia import derive, moments_from_ellipsoid, moments_from_gravity, moments_from_libration

# identities of exact formulas: the budget is double-precision rounding of a few operations
RTOL = 1e-12


def hd(A, B, C):
    return (C - 0.5 * (A + B)) / C


def test_gravity_moments_give_hd_as_j2_over_polar_moment():
    # Vesta-like numbers: H_d = J2 / C-bar and (B - A) / 4 = sqrt(C22^2 + S22^2) are the two identities of eq. 31
    A, B, C = moments_from_gravity(0.4208, 0.0710609, 2.7013816e-3, 8.0388844e-4)
    assert hd(A, B, C) == pytest.approx(0.0710609 / 0.4208, rel=RTOL)
    assert (B - A) / 4.0 == pytest.approx(math.hypot(2.7013816e-3, 8.0388844e-4), rel=1e-10)
    assert C == pytest.approx(0.4208, rel=RTOL)


def test_ellipsoid_moments_give_the_ellipsoids_hd():
    a, b, c = 3.415, 2.85, 2.21
    A, B, C = moments_from_ellipsoid(a, b, c)
    assert hd(A, B, C) == pytest.approx((a * a + b * b - 2 * c * c) / (2 * (a * a + b * b)), rel=RTOL)


def test_libration_ratios_round_trip():
    beta, gamma = 631.0e-6, 227.7e-6
    A, B, C = moments_from_libration(beta, gamma)
    assert (C - A) / B == pytest.approx(beta, rel=1e-10)
    assert (B - A) / C == pytest.approx(gamma, rel=1e-10)


def test_mean_moment_route_has_the_mean_moment():
    d = derive("gravity_and_mean_moment", {"mean_moment": 0.37, "J2": 0.0265, "C22": 1.59e-4, "S22": -1.77e-4}, {})
    assert sum(d.moments) / 3.0 == pytest.approx(0.37, rel=RTOL)


def test_hd_route_equals_polar_moment_route():
    d1 = derive("gravity_and_dynamical_ellipticity", {"dynamical_ellipticity": 0.005380, "J2": 1.9566e-3,
                                                       "C22": -5.46e-5, "S22": 3.13e-5}, {})
    d2 = derive("gravity_and_polar_moment", {"polar_moment": 1.9566e-3 / 0.005380, "J2": 1.9566e-3,
                                              "C22": -5.46e-5, "S22": 3.13e-5}, {})
    np.testing.assert_allclose(d1.moments, d2.moments, rtol=RTOL)


@pytest.mark.parametrize("method,values,sigmas", [
    ("gravity_and_polar_moment", {"polar_moment": 0.4208, "J2": 0.0710609, "C22": 2.70e-3, "S22": 8.04e-4},
     {"polar_moment": 0.003, "J2": 1.4e-8, "C22": 7e-8, "S22": 7e-8}),
    ("uniform_ellipsoid", {"a": 3.415, "b": 2.85, "c": 2.21}, {"a": 0.1, "b": 0.1, "c": 0.1}),
    ("libration", {"beta": 631.0e-6, "gamma": 227.7e-6}, {"beta": 0.003e-6, "gamma": 0.004e-6}),
])
def test_moment_covariance_agrees_with_monte_carlo(method, values, sigmas):
    """The linear covariance against 20 000 samples of the inputs: the sampled σ has a relative standard error
    1/sqrt(2(N-1)) = 0.5 % (4 of them: 2 %), a sampled ρ about (1 - ρ²)/sqrt(N) <= 0.007 (4 of them: 0.03);
    the ellipsoid's moments are quadratic, whose curvature over ±σ (σ/a ≈ 3 %) adds 0.1 % at most."""
    d = derive(method, values, sigmas)
    rng = np.random.default_rng(5)
    keys = list(values)
    n = 20_000
    draws = {k: values[k] + sigmas[k] * rng.standard_normal(n) for k in keys}
    from ephem.bodies.inertia import METHODS
    f = METHODS[method].function
    samples = np.array([f(*(draws[k][i] for k in keys)) for i in range(n)])
    sd = samples.std(axis=0, ddof=1)
    for i in range(3):
        if d.sigma[i] == 0.0:      # a normalisation (C = 1): exactly fixed
            assert sd[i] == pytest.approx(0.0, abs=1e-15)
            continue
        assert sd[i] == pytest.approx(d.sigma[i], rel=0.02)
    with np.errstate(invalid="ignore", divide="ignore"):    # a fixed normalisation has no correlation
        corr = np.corrcoef(samples.T)
    labels = ("inertia.A", "inertia.B", "inertia.C")
    for (a, b), rho in d.correlations.items():
        assert corr[labels.index(a), labels.index(b)] == pytest.approx(rho, abs=0.03)


def test_a_moment_whose_input_has_no_sigma_has_none():
    d = derive("gravity_and_polar_moment", {"polar_moment": 0.3877, "J2": 0.0265, "C22": 1.59e-4, "S22": -1.77e-4},
               {"polar_moment": None, "J2": 5e-8, "C22": 3e-8, "S22": 3e-8})
    assert d.sigma == (None, None, None)        # all three hang on C-bar
    assert d.missing_sigma == ("polar_moment",)
    assert d.correlations == {}


def test_impossible_inputs_are_named():
    with pytest.raises(InvalidInputError, match="derived_from"):
        derive("uniform_ellipsoid", {"a": 1.0, "b": 2.0, "c": 0.5}, {})
    with pytest.raises(InvalidInputError, match="derived_from.method"):
        derive("spherical_cow", {}, {})
    with pytest.raises(InvalidInputError, match="derived_from.J2"):
        derive("gravity_and_polar_moment", {"polar_moment": 0.4}, {})
    with pytest.raises(InvalidInputError, match="not the moments of a rigid body"):
        # a polar moment below J2 + 2q: A < 0
        derive("gravity_and_polar_moment", {"polar_moment": 0.05, "J2": 0.07, "C22": 0.0, "S22": 0.0}, {})
