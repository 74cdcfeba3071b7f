"""Kepler's equation's E - sin E (ephem.orbit.kepler._e_minus_sin) takes its series below |E| = 1 and sin above, for
each point alone: an array of points all on one side skips the other side's work, and gives what each point gives
alone (the same operations: to the last bit; compared here at 1e-15 relative, below a unit in the last place)."""
from __future__ import annotations

import numpy as np
import pytest

from ephem.orbit import kepler


@pytest.mark.parametrize("points", [[0.3, 2.0, -0.9, -1.0, 1e-8, 3.1], [0.3, -0.7, 1e-300], [1.5, -2.5, 1.0], [0.0]])
def test_e_minus_sin_of_an_array_is_that_of_each_point(points):
    E = np.array(points)
    together = kepler._e_minus_sin(E)
    alone = np.array([kepler._e_minus_sin(np.array([x]))[0] for x in points])
    np.testing.assert_allclose(together, alone, rtol=1e-15, atol=0.0)
    # against the direct form where it does not cancel, and its first Taylor term where it does
    big = np.abs(E) >= 1.0
    np.testing.assert_allclose(together[big], E[big] - np.sin(E[big]), rtol=1e-15)
    tiny = (np.abs(E) < 1e-4) & (E != 0.0)
    np.testing.assert_allclose(together[tiny], E[tiny] ** 3 / 6.0, rtol=1e-8)


def test_solve_kepler_meets_its_equation_either_side_of_unit_eccentric_anomaly():
    for e in (0.0785, 0.5, 0.95):
        M = np.array([1e-9, 0.2, 0.9, 2.0, 3.0, -2.9])
        E = kepler.solve_kepler(M, e)
        np.testing.assert_allclose(E - e * np.sin(E), M, rtol=1e-13, atol=1e-15)
        np.testing.assert_allclose([kepler.solve_kepler(np.array([m]), e)[0] for m in M], E, rtol=1e-15, atol=0.0)
