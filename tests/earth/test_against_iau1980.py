"""The IAU 1980 nutation (Seidelmann 1982): the signs of its solar semi-annual term are those of Kinoshita's
circular-orbit terms (ephem.forced.kinoshita)."""
import math

import numpy as np

from ephem.forced.kinoshita import nutation_series


def test_semiannual_signs_match_the_iau_1980_solar_term():
    # IAU 1980 nutation (Seidelmann 1982), argument 2F - 2D + 2Ω = 2 L_sun: Δψ = -1.3187" sin, Δε = +0.5736" cos.
    # With λ the Sun's longitude from the equinox our circular-orbit terms have the same signs.
    s = nutation_series(1e-4, 0.0172, math.radians(23.44), 0.0, 0.0)
    dpsi, deps = s.evaluate(np.array([math.radians(45.0)]))  # 2λ = 90°: sin = 1
    assert dpsi[0] < 0
    dpsi, deps = s.evaluate(np.array([0.0]))                  # 2λ = 0: cos = 1
    assert deps[0] > 0
