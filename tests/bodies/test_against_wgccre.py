"""The IAU Working Group on Cartographic Coordinates and Rotational Elements (Archinal et al. 2018, the 2015
report): the catalogue's current poles are its values where no better-measured solution replaced them (with, in
the same test, Eros' H_d from Lara 2014's Table 1 moments)."""
import math

import pytest

from ephem.bodies.catalogue import get_body
from ephem.orbit.geometry import angle_between, unit_vector

# the catalogue stores the report's printed digits; 1e-9 deg is far below the last one (1e-3 deg)
PRINTED = 1e-9


def test_current_poles_are_the_wgccre_values():
    # Archinal et al. (2018) Table 4: Vesta α0 = 309.031, δ0 = 42.235
    assert get_body("vesta").pole.ra_deg == pytest.approx(309.031, abs=PRINTED)
    assert get_body("vesta").pole.dec_deg == pytest.approx(42.235, abs=PRINTED)


def test_ceres_dawn_pole_refines_the_wgccre_one():
    """Ceres' pole is the Dawn CERES18D solution (291.42763, 66.76033 ± 0.0002°), 0.0055° from the report's
    291.418, 66.764, whose digits it refines (half a unit of the report's last digit on the sky: 0.0005° in
    Dec, more than ten σ of Dawn's)."""
    c = get_body("ceres").pole
    dawn = unit_vector(math.radians(c.ra_deg), math.radians(c.dec_deg))
    iau = unit_vector(math.radians(291.418), math.radians(66.764))
    assert math.degrees(float(angle_between(dawn, iau))) == pytest.approx(0.0055, abs=0.0005)
    # Lara (2014) Table 1 (C = 1): H_d = (C − (A+B)/2)/C by another order of 3 operations, a few ε; 1e-12
    assert math.isclose(get_body("eros").hd, 1 - (0.229427 + 0.963754) / 2, rel_tol=1e-12)
