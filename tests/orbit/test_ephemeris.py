"""The real Sun direction (ephem.orbit.de421): without planets the Kepler ellipse, the span DE421 covers, the cache.

Against outside references: DE421 through skyfield (tests/orbit/test_against_de421.py), the MPC's elements
(tests/orbit/test_against_mpc.py), AstDyS's proper frequency (tests/orbit/test_against_astdys.py), the IAU 2006 ecliptic
(tests/earth/test_against_iau2006.py). The span constants below are shared with them.
"""
import math

import numpy as np
import pytest

from ephem.orbit import de421 as E
from ephem.bodies.catalogue import get_body
from ephem.base.constants import AU_M, DAY_S, GM_SUN
from ephem.base.errors import NotApplicableError
from ephem.orbit.geometry import icrf_to_ecliptic_matrix
from ephem.orbit.kepler import mean_motion_rad_per_day, orbit_basis, true_anomaly

Y1900, Y1925, Y1950, Y2050 = 2415020.5, 2424151.5, 2433282.5, 2469807.5


def test_without_planet_masses_the_path_is_the_kepler_ellipse():
    orbit = get_body("Vesta").orbit
    gm = GM_SUN * DAY_S**2 / AU_M**3          # the GM ephem.orbit.kepler uses
    r0, v0 = E.elements_to_state(orbit, gm)
    t0 = orbit.epoch_jd_tdb
    states = E.integrate_heliocentric(r0, v0, t0, t0 - 50 * 365.25, t0, gm_scale=0.0, gm_sun=gm,
                                      relativity=False)
    jd = np.linspace(t0 - 50 * 365.25, t0, 2001)
    nu = true_anomaly(math.radians(orbit.mean_anomaly_deg) + mean_motion_rad_per_day(orbit.a_au) * (jd - t0),
                      orbit.e)
    p, q, _ = orbit_basis(*map(math.radians, (orbit.i_deg, orbit.node_deg, orbit.peri_deg)))
    r = orbit.a_au * (1 - orbit.e**2) / (1 + orbit.e * np.cos(nu))
    ecl = (r * np.cos(nu))[:, None] * p + (r * np.sin(nu))[:, None] * q
    ref = ecl @ icrf_to_ecliptic_matrix()          # row-vector form of R^T x
    assert np.linalg.norm(states(jd)[:, :3] - ref, axis=1).max() < 2e-10   # measured 4e-11


@pytest.mark.parametrize("start, stop", [(2400000.5, 2451545.0), (2451545.0, 2480000.5)])
def test_outside_de421_is_not_applicable_and_names_the_span(start, stop):
    with pytest.raises(NotApplicableError, match="1899-07-29 to 2053-10-09") as info:
        E.sun_path(get_body("Vesta"), start, stop)
    assert info.value.body == "Vesta" and "DE421" in str(info.value)


def test_moon_is_not_applicable():
    with pytest.raises(NotApplicableError, match="Earth"):
        E.sun_path(get_body("Moon"), Y1950, Y1950 + 10)


def test_paths_are_cached_and_guard_their_span():
    a = E.sun_path(get_body("Mars"), Y1950 + 0.3, Y1950 + 99.7)
    assert E.sun_path(get_body("Mars"), Y1950, Y1950 + 100) is a       # same whole-day span
    with pytest.raises(ValueError, match="outside"):
        a.position([Y1950 + 101])
    with pytest.raises(ValueError, match="outside"):
        a.position_scalar(Y1950 - 1)
