"""Geometry (ephem.orbit.geometry, ephem.orbit.kepler): hand-built limit cases and symmetries.

Against the IERS Conventions and IAU 2006 constants (the frame bias, the obliquity of J2000):
tests/earth/test_against_iau2006.py; against ERFA's frame bias: tests/earth/test_against_erfa.py.
"""
import math

import numpy as np
import pytest

from ephem.base.errors import InvalidInputError
from ephem.orbit.geometry import spin_geometry, unit_vector
from ephem.orbit.kepler import orbit_basis, orbit_normal, solve_kepler, solve_kepler_scalar, true_anomaly


def test_orbit_normal_is_angular_momentum_of_the_kepler_motion():
    i, node, peri = map(math.radians, (10.83, 304.30, 178.9))
    p, q, w = orbit_basis(i, node, peri)
    e = 0.22
    m = np.array([0.3, 0.3001])
    nu = true_anomaly(m, e)
    r = (1 - e * e) / (1 + e * np.cos(nu))
    pos = (r * np.cos(nu))[:, None] * p + (r * np.sin(nu))[:, None] * q
    h = np.cross(pos[0], pos[1] - pos[0])
    assert np.allclose(h / np.linalg.norm(h), w, atol=1e-9)
    # unit vectors from products of sines and cosines (≤ 1 ulp each) and a cross product: ≲ 4 ε = 8.9e-16
    # per component (measured: 0 and 1.4e-17)
    assert np.allclose(orbit_normal(i, node), w, rtol=0, atol=1e-15)
    assert np.allclose(np.cross(p, q), w, rtol=0, atol=1e-15)


@pytest.mark.parametrize("rot_deg", [17.0, 133.0, -61.0])
def test_geometry_is_invariant_under_rotation_about_the_ecliptic_pole(rot_deg):
    s = unit_vector(math.radians(40.0), math.radians(55.0))
    i, node, peri = map(math.radians, (12.0, 80.0, 30.0))
    g1 = spin_geometry(s, i, node, peri)
    r = math.radians(rot_deg)
    rz = np.array([[math.cos(r), -math.sin(r), 0], [math.sin(r), math.cos(r), 0], [0, 0, 1]])
    g2 = spin_geometry(rz @ s, i, node + r, peri)
    # the rotated inputs (a rotation by r and node + r) round differently: a few ε of angles <= π; 1e-13
    assert g2.obliquity == pytest.approx(g1.obliquity, abs=1e-13)
    assert g2.equinox_to_pericentre == pytest.approx(g1.equinox_to_pericentre, abs=1e-13)
    assert np.allclose(g2.equinox, rz @ g1.equinox, atol=1e-13)


def test_equinox_is_where_the_sun_crosses_the_equator_northward():
    s = unit_vector(math.radians(300.0), math.radians(20.0))
    i, node, peri = map(math.radians, (9.0, 40.0, 10.0))
    geo = spin_geometry(s, i, node, peri)
    p, q, w = orbit_basis(i, node, peri)
    # walk the Sun's apparent direction (same sense as the orbital motion) through γ
    for lam, sign in ((-0.01, -1), (0.01, 1)):
        d = math.cos(lam) * geo.equinox + math.sin(lam) * np.cross(w, geo.equinox)
        assert np.sign(np.dot(d, s)) == sign


def test_pole_normal_to_orbit_is_refused():
    with pytest.raises(InvalidInputError, match="pole"):
        spin_geometry(np.array([0.0, 0.0, 1.0]), 0.0, 0.0, 0.0)


@pytest.mark.parametrize("e", [0.0, 0.1, 0.5, 0.9, 0.99])
def test_kepler_solvers(e):
    m = np.linspace(-7, 7, 1001)
    ecc = solve_kepler(m, e)
    resid = ecc - e * np.sin(ecc) - m
    # the residual of values |M| <= 7 (ulp 8.9e-16): 1e-14 is 11 ulp
    assert np.max(np.abs(np.remainder(resid + np.pi, 2 * np.pi) - np.pi)) < 1e-14
    scalar = np.array([solve_kepler_scalar(x, e) for x in m])
    # two solvers, each converged to the root to a few ulp of |E| <= 7 (measured: 1 ulp, 4.4e-16, up to
    # e = 0.99); 1e-13 is 110 ulp, room for the 1/(1 − e cos E) <= 100 by which a residual near pericentre
    # at e = 0.99 would move E
    assert np.max(np.abs(scalar - ecc)) < 1e-13
