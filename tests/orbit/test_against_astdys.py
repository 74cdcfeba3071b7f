"""AstDyS synthetic proper elements: Vesta's orbit (ephem.orbit.de421, integrated with the planets) regresses on
the invariable plane (Souami & Souchay 2012) at AstDyS's proper frequency s."""
import math

import numpy as np
import pytest

from ephem.orbit import de421 as E
from ephem.bodies.catalogue import get_body
from ephem.base.constants import ARCSEC
from ephem.orbit.geometry import icrf_to_ecliptic_matrix
from tests.orbit.test_ephemeris import Y1925


def test_vesta_node_regresses_on_the_invariable_plane_at_its_proper_frequency():
    # AstDyS synthetic proper elements of (4) Vesta: s = -39.598 "/yr, sin I_p = 0.111
    # (proper inclination 6.39 deg). The osculating orbit is the proper mode plus a
    # forced one (its osculating inclination to the invariable plane is 5.56 deg, not
    # 6.39): about the invariable pole its node turns at s to within roughly the ratio of
    # the two, ~15 %. Measured over 1925-2025: -40.7 "/yr. Invariable plane: i = 1.578694
    # deg, node 107.582222 deg on the J2000 ecliptic (Souami & Souchay 2012).
    path = E.sun_path(get_body("Vesta"), Y1925, get_body("Vesta").orbit.epoch_jd_tdb)
    jd = np.arange(path.start_jd_tdb, path.stop_jd_tdb, 2.0)
    w = path.orbit_normal(jd) @ icrf_to_ecliptic_matrix().T
    i, node = math.radians(1.578694), math.radians(107.582222)
    z = np.array([math.sin(i) * math.sin(node), -math.sin(i) * math.cos(node), math.cos(i)])
    x = np.cross([0.0, 0.0, 1.0], z)
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    wx, wy = w @ x, w @ y
    years = (jd - jd[0]) / 365.25
    rate = np.polyfit(years, np.unwrap(np.arctan2(wx, -wy)), 1)[0] / ARCSEC
    assert rate == pytest.approx(-39.598, rel=0.15)
