"""JPL DE421 (read through skyfield): the Sun paths and the planetary integrator of
ephem.orbit.de421, and the Moon's and the Sun's positions of ephem.earth.lunisolar, against the positions DE421 gives.

(The integrations of the torque along DE421 positions, ephem.earth.de421_integration.integrate_de421 and the real-orbit rung,
are the library's own independent routes: tests/earth/test_lunisolar.py, tests/forced/test_physics_errors.py.)
"""
import math

import erfa
import numpy as np
import pytest

from ephem.orbit import de421 as E
from ephem.orbit import de421_header as H
from ephem.earth import lunisolar as L
from ephem.base.constants import ARCSEC
from ephem.bodies.catalogue import get_body
from tests.orbit.test_ephemeris import Y1900, Y1950, Y2050

J2000 = 2451545.0


# ----------------------------------------------------------------------------- ephem.orbit.de421

@pytest.mark.parametrize("name, key", [("Earth", "earth"), ("Mars", "mars")])
def test_planet_path_is_skyfields_geometric_sun_vector(name, key):
    path = E.sun_path(get_body(name), Y1900, Y2050)
    assert path.fit_error_rel < E.FIT_TOLERANCE
    eph, ts = E.kernel(), E.timescale()
    jd = np.random.default_rng(7).uniform(Y1900, Y2050, 3000)
    # geometric Sun - planet; .observe() would add light time (~1e-7 rel)
    ref = (eph["sun"] - eph[key]).at(ts.tdb_jd(jd)).position.au.T
    err = np.linalg.norm(path.position(jd) - ref, axis=1) / np.linalg.norm(ref, axis=1)
    assert err.max() < E.FIT_TOLERANCE
    scalar = np.array([path.position_scalar(t) for t in jd[:200]])
    # the same fitted polynomials summed by the scalar and the vector code: a few ulp of |r| <= 1.7 au
    # (ulp 2.2e-16); 1e-14 au = 45 ulp (measured 7e-16)
    assert np.abs(scalar - path.position(jd[:200])).max() < 1e-14


def test_integrator_started_on_de421_mars_follows_de421_mars_for_a_century():
    # Mars as the integrated body, the other planets perturbing, G(M_sun + m_mars)
    # in the central term. The residual is DE421's asteroids, which we omit:
    # 4e-8 au at 10 y, 6.2e-7 au at 100 y (Ceres + Vesta added as perturbers
    # bring it to 1.3e-7). Without the Schwarzschild term it is 1.8e-5 au, with
    # the planet's own mass dropped ~1e-4 au: the bound catches both.
    r0, v0 = E.heliocentric(4, Y1950, velocity=True)
    states = E.integrate_heliocentric(r0[0], v0[0], Y1950, Y1950, Y2050,
                                      perturbers=tuple(p for p in H.PERTURBERS if p != 4),
                                      gm_self=H.GM_DE421[4])
    jd = np.linspace(Y1950, Y2050, 1001)
    err = np.linalg.norm(states(jd)[:, :3] - E.heliocentric(4, jd), axis=1)
    assert err[:101].max() < 1e-7     # first 10 years
    assert err.max() < 1e-6


# ----------------------------------------------------------------------------- ephem.earth.lunisolar

def test_moon_and_sun_follow_de421_to_meeus_accuracy():
    # Meeus (1998, ch. 47) quotes ~10" in longitude and 4" in latitude with all his terms; we drop
    # his three planetary terms (largest 14") and use Kepler for the Sun (planetary terms ~20").
    from ephem.orbit.de421 import barycentric

    jd = np.arange(2447892.5, 2455197.5, 3.7)          # 1990-2010
    a = tuple(L.delaunay_arguments(jd).T)
    rot = np.stack([erfa.ecm06(J2000, x - J2000) for x in jd])   # ICRS -> ecliptic of date
    au_km = 149597870.7
    for name, naif in (("moon", 301), ("sun", 10)):
        v = np.einsum("nij,nj->ni", rot, barycentric(naif, jd) - barycentric(399, jd))
        lam, beta, r = (L.moon_position if name == "moon" else L.sun_position)(a, 0.0)
        dlam = np.remainder(lam - np.arctan2(v[:, 1], v[:, 0]) + math.pi, 2 * math.pi) - math.pi
        rr = np.linalg.norm(v, axis=1)
        dbeta = beta - np.arcsin(v[:, 2] / rr)
        if name == "moon":
            assert np.abs(dlam).max() / ARCSEC < 35.0 and np.sqrt(np.mean(dlam**2)) / ARCSEC < 15.0
            assert np.abs(dbeta).max() / ARCSEC < 10.0
            assert np.abs(r - rr * au_km).max() < 20.0            # km
            assert abs(np.mean(r - rr * au_km)) < 1.0            # the mean distance sets the precession
        else:
            assert np.abs(dlam).max() / ARCSEC < 40.0
            assert np.abs(r / (rr * au_km) - 1).max() < 1.5e-4
