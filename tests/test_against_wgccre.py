"""The IAU Working Group on Cartographic Coordinates and Rotational Elements (Archinal et al. 2018, the 2015
report): the catalogue's current poles are its values (with, in the same test, Eros' H_d from Lara 2014's
Table 1 moments)."""
import math

from ephem.catalogue import get_body


def test_current_poles_are_the_wgccre_values():
    # Archinal et al. (2018) Table 4: Vesta α0 = 309.031, δ0 = 42.235; Ceres 291.418, 66.764
    assert (get_body("vesta").pole.ra_deg, get_body("vesta").pole.dec_deg) == (309.031, 42.235)
    assert (get_body("ceres").pole.ra_deg, get_body("ceres").pole.dec_deg) == (291.418, 66.764)
    # Lara (2014) Table 1 (C = 1): H_d = (C − (A+B)/2)/C by another order of 3 operations, a few ε; 1e-12
    assert math.isclose(get_body("eros").hd, 1 - (0.229427 + 0.963754) / 2, rel_tol=1e-12)
