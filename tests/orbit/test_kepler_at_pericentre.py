"""Kepler's equation at the pericentre (M = 0) for the eccentricities where Newton's iterate settled on a subnormal
E whose residual E (1 - e) could never pass the relative stop test: the solver raised, and a batch partition with
one such row failed whole (found for e = 0.82365 and 0.9161, 3 of 20 000 random e in [0.3, 0.9])."""
from __future__ import annotations

import numpy as np
import pytest

from ephem.orbit.kepler import _solve_kepler_many, solve_kepler_scalar


@pytest.mark.parametrize("e", [0.82365, 0.9161])
def test_the_pericentre_converges_to_zero(e):
    m = np.array([0.0, 1e-310, 1e-300, 1e-12, 0.5])
    E = _solve_kepler_many(m, e)
    # E - e sin E = M to a few ulp of E, and E(0) within a subnormal of 0
    assert abs(E[0]) < 1e-300
    assert np.all(np.abs(E - e * np.sin(E) - m) <= 8 * np.finfo(float).eps * np.abs(E) + 1e-300)
    assert abs(solve_kepler_scalar(0.0, e)) < 1e-300


def test_twenty_thousand_eccentricities_at_the_pericentre():
    e = np.random.default_rng(7).uniform(0.3, 0.9, 20_000)
    E = _solve_kepler_many(np.zeros_like(e), e)
    assert np.all(np.abs(E) < 1e-300)
