"""Geometry against ERFA, hand-built limit cases and symmetries."""
import math

import erfa
import numpy as np
import pytest

from ephem.constants import MAS
from ephem.errors import InvalidInputError
from ephem.geometry import (icrf_to_ecliptic, icrf_to_ecliptic_matrix, lon_lat, signed_angle, spin_geometry,
                            unit_vector)
from ephem.kepler import orbit_basis, orbit_normal, solve_kepler, solve_kepler_scalar, true_anomaly


def _rotation(axis: int, angle: float) -> np.ndarray:
    """R_axis(angle) of the IERS Conventions: a rotation of the coordinate axes (positive anticlockwise)."""
    c, s = math.cos(angle), math.sin(angle)
    i, j = [(1, 2), (2, 0), (0, 1)][axis - 1]
    r = np.eye(3)
    r[i, i] = r[j, j] = c
    r[i, j], r[j, i] = s, -s
    return r


def test_ecliptic_matrix_is_the_frame_bias_then_the_j2000_obliquity():
    # independent of ERFA: built from the published constants. Frame bias B = R1(-eta0) R2(xi0) R3(dalpha0)
    # with xi0 = -16.6170 mas, eta0 = -6.8192 mas, dalpha0 = -14.6 mas (IERS Conventions 2010, eq. 5.21 and
    # sec. 5.5.4), then the ecliptic of J2000 by R1(eps0), eps0 = 84381.406" (IAU 2006, Capitaine et al. 2003)
    arcsec = math.pi / 180 / 3600
    bias = _rotation(1, 6.8192e-3 * arcsec) @ _rotation(2, -16.6170e-3 * arcsec) @ _rotation(3, -14.60e-3 * arcsec)
    expected = _rotation(1, 84381.406 * arcsec) @ bias
    # budget: dalpha0 is printed to 0.01 mas (half a unit: 2.4e-11 rad), xi0 and eta0 to 0.1 uas; the
    # second-order bias products (~1e-14) are inside that (measured: 9.5e-13). 5e-11 rad still catches
    # a missing frame bias (~1e-7 rad) or the obliquity of date instead of J2000's
    assert np.max(np.abs(icrf_to_ecliptic_matrix() - expected)) < 5e-11
    assert np.max(np.abs(_rotation(1, 84381.406 * arcsec) - expected)) > 5e-8     # the bias is resolved


def test_icrf_pole_in_ecliptic_is_at_the_j2000_obliquity():
    # IAU 2006 obliquity at J2000: 84381.406 arcsec (Capitaine et al. 2003), frame bias ~ 20 mas
    lon, lat = lon_lat(icrf_to_ecliptic(0.0, math.pi / 2))
    eps0 = 84381.406 / 3600.0
    assert math.degrees(lat) == pytest.approx(90.0 - eps0, abs=30 * MAS * 180 / math.pi)
    assert math.degrees(lon) == pytest.approx(90.0, abs=1e-4)


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


def test_paper_eq26_sign_slip():
    """Erratum: Petit et al. eq. 26 prints z = (sin i sin Ω, cos Ω sin i, cos i).

    The orbit normal must be orthogonal to the line of nodes (cos Ω, sin Ω, 0);
    the printed vector is not (unless sin 2Ω = 0), ours is.
    """
    i, node = math.radians(7.14), math.radians(103.7)
    nodes = np.array([math.cos(node), math.sin(node), 0.0])
    printed = np.array([math.sin(i) * math.sin(node), math.cos(node) * math.sin(i), math.cos(i)])
    assert abs(np.dot(printed, nodes)) > 0.02
    assert abs(np.dot(orbit_normal(i, node), nodes)) < 1e-15   # a 3-term dot product of unit vectors: ≲ 3 ε


def test_earth_equinox_and_obliquity():
    # Earth: spin axis = mean pole of J2000 (the ICRF pole moved by ERFA's frame bias), orbit in
    # the ecliptic (i = 0): the equinox is +x of the ecliptic (the vernal point) and the obliquity
    # is the IAU 2006 obliquity at J2000, 84381.406 arcsec.
    rb, _, _ = erfa.bp06(2451545.0, 0.0)
    s = icrf_to_ecliptic_matrix() @ rb[2]
    geo = spin_geometry(s, 0.0, 0.0, math.radians(102.94))
    assert math.degrees(geo.obliquity) * 3600 == pytest.approx(84381.406, abs=1e-6)
    assert np.allclose(geo.equinox, [1, 0, 0], rtol=0, atol=1e-12)   # rounding of the bias rotation: ~1e-16
    # longitude of perihelion 102.94 deg counted from the vernal point, signed
    assert math.degrees(geo.equinox_to_pericentre) == pytest.approx(102.94, abs=1e-10)


def test_icrf_pole_differs_from_the_mean_pole_by_the_frame_bias():
    # the ICRF pole sits ~17 mas from the J2000 mean pole (IERS Conventions 2010, ξ0 = -16.617 mas,
    # η0 = -6.819 mas), which moves the equinox along the ecliptic by ξ0 / sin ε0 ≈ 42 mas
    s = icrf_to_ecliptic(0.0, math.pi / 2)
    geo = spin_geometry(s, 0.0, 0.0, 0.0)
    shift_mas = math.degrees(math.atan2(geo.equinox[1], geo.equinox[0])) * 3.6e6
    assert abs(shift_mas) == pytest.approx(16.617 / math.sin(math.radians(84381.406 / 3600)), rel=0.02)


def test_signed_angle_keeps_the_sign_that_arccos_loses():
    z = np.array([0.0, 0.0, 1.0])
    a = np.array([1.0, 0.0, 0.0])
    b = unit_vector(math.radians(-40.0), 0.0)
    assert math.degrees(signed_angle(a, b, z)) == pytest.approx(-40.0, abs=1e-12)
    assert math.degrees(math.acos(np.dot(a, b))) == pytest.approx(40.0)  # what eq. 29 would give


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
