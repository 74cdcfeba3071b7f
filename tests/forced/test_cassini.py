"""The Cassini state of a synchronous rotator (ephem.forced.cassini): each formula against an independent route (a direct
average of the torque, a limit, a symmetry), and the Moon's derived inclination and free-libration periods against
their published values."""
import math

import numpy as np
import pytest

from ephem.forced.cassini import (SynchronousOrbit, cassini_state, free_librations, longitude_hansen_factor,
                                precession_constant)
from ephem.bodies.catalogue import get_body
from ephem.base.errors import NotApplicableError
from ephem.moon.model import synchronous_orbit

MOON = get_body("moon")
# lunar laser ranging's moments: beta = (C-A)/B = 631.486e-6, gamma = (B-A)/C = 227.871e-6 (Williams et al. 2014,
# DE430 lunar solution; Rambaux & Williams 2011 use the same to 1e-9): A, B with C = 1
BETA, GAMMA = 631.486e-6, 227.871e-6
A_LLR = (1.0 - BETA * GAMMA) / (1.0 + BETA)
LLR = (A_LLR, A_LLR + GAMMA, 1.0)


def _orbit(**kw):
    o = synchronous_orbit(MOON)
    return SynchronousOrbit(**{**o.__dict__, **kw})


def test_the_averaged_torque_is_the_direct_average():
    """P(θ) from <u·I·u>'s closed form against the torque u × (I u) averaged over the orbit numerically, the body's
    long axis locked to the primary (the module docstring's geometry), at a large obliquity where B − A's
    (1 − cos θ) term shows."""
    A, B, C = 0.7, 0.85, 1.0
    theta = math.radians(40.0)
    k = np.array([0.0, 0.0, 1.0])
    x = np.array([1.0, 0.0, 0.0])
    c = np.array([0.0, -math.sin(theta), math.cos(theta)])      # c = cos θ k − sin θ y
    cx = np.cross(c, x)
    lam = np.linspace(0.0, 2.0 * math.pi, 4096, endpoint=False)
    u = np.outer(np.cos(lam), x) + np.outer(np.sin(lam), np.cross(k, x))
    a = np.outer(np.cos(lam), x) + np.outer(np.sin(lam), cx)
    b = np.cross(c, a)
    Iu = A * (u * a).sum(1)[:, None] * a + B * (u * b).sum(1)[:, None] * b + C * (u @ c)[:, None] * c
    torque = 3.0 * np.cross(u, Iu).mean(0)       # g = 1: (3 GM/r³) u × I u
    # dc/dt = torque / (C n) = P (c × k) with n = 1, g = 1, e = 0
    orbit = SynchronousOrbit(1.0, 0.0, 0.1, 0.0, -0.01, 0.0, 0.0, 0.0, 2451545.0, 1.0)
    expected = precession_constant(orbit, (A, B, C), theta) * np.cross(c, k)
    # trapezoid rule on a trigonometric polynomial of degree 4: exact to rounding (1e-15 of the torque)
    np.testing.assert_allclose(torque / C, expected, atol=1e-13)


def test_without_b_minus_a_and_at_small_obliquity_it_feels_c_minus_a():
    """Limits: the primary stays on the long axis, so P(θ → 0) = (3g/2n)(C − A)/C, whatever B; a fast rotator
    would feel C − (A + B)/2 instead."""
    o = SynchronousOrbit(1.0, 0.0, 0.1, 0.0, -0.01, 0.0, 0.0, 0.0, 2451545.0, 1.0)
    for B in (0.7, 0.9):
        assert precession_constant(o, (0.7, B, 1.0), 1e-9) == pytest.approx(1.5 * 0.3, rel=1e-15)


def test_the_balance_holds_at_the_root_and_its_sides():
    o = synchronous_orbit(MOON)
    s = cassini_state(o, MOON.moments)
    n, w = o.mean_motion, abs(o.node_rate)
    lhs = n * (s.precession_constant * math.sin(s.obliquity)
               + s.sun_precession_constant * math.cos(s.equator_inclination) * math.sin(s.equator_inclination))
    rhs = w * (n + w * math.cos(s.equator_inclination)) * math.sin(s.equator_inclination)
    assert lhs == pytest.approx(rhs, rel=1e-12)          # bisection to 1e-15 rad in I: 1e-13 relative
    assert s.obliquity == pytest.approx(o.inclination + s.equator_inclination, abs=1e-15)


@pytest.mark.parametrize("moments", ["catalogue", "llr"])
def test_the_bisection_finds_brents_root(moments):
    """The library's bisection (no scipy.optimize at start-up) against scipy's brentq on the same balance and
    bracket: the same root to 2e-15 rad (both stop at 1e-15)."""
    from scipy.optimize import brentq

    from ephem.forced.cassini import _balance

    o = synchronous_orbit(MOON)
    m = MOON.moments if moments == "catalogue" else LLR
    ref = brentq(lambda x: _balance(o, m, x), 1e-12, 0.5 * math.pi - o.inclination, xtol=1e-15,
                 rtol=4.0 * 2.220446049250313e-16, maxiter=200)
    assert cassini_state(o, m).equator_inclination == pytest.approx(ref, abs=2e-15)


def test_the_moons_equator_inclination_is_derived_within_the_budget():
    """I from the balance against the observed mean inclination of the lunar equator, 1°32′32.7″ = 1.54242°
    (Meeus 1998 ch. 53, from the IAU/Eckhardt libration theory). Budget 1 % of I (0.015°): the theory is first
    order in the orbit's departures from a uniformly precessing ellipse. Its largest omissions: the Sun's
    perturbation of the orbit (the mean motion and mean distance relation, O(m²), m = n_sun/n = 0.075:
    0.56 % in g, 0.7 % in I, as dI/I ≈ 1.28 dP/P here) and the optical libration's (B − A) 2e² (0.2 % of P,
    0.26 % in I)."""
    observed = 1.54242
    for moments in (MOON.moments, LLR):
        s = cassini_state(synchronous_orbit(MOON), moments)
        assert math.degrees(s.equator_inclination) == pytest.approx(observed, rel=0.01)


def test_a_cassini_state_needs_a_regressing_node_and_an_oblate_body():
    o = synchronous_orbit(MOON)
    with pytest.raises(NotApplicableError, match="regress"):
        cassini_state(_orbit(node_rate=-o.node_rate), MOON.moments)
    with pytest.raises(NotApplicableError, match="0 < A <= B < C"):
        cassini_state(o, (1.0, 1.0, 1.0))
    with pytest.raises(NotApplicableError, match="i = 0"):
        cassini_state(_orbit(inclination=0.0), MOON.moments)


def test_the_hansen_factor_is_its_series():
    # 1 − 5e²/2 + 13e⁴/16: the next term is O(e⁶) (~3e-8 at e = 0.0549), so 1e-7 holds with margin
    e = 0.0549
    assert longitude_hansen_factor(e) == pytest.approx(1 - 2.5 * e**2 + 13 / 16 * e**4, abs=1e-7)
    assert longitude_hansen_factor(0.0) == pytest.approx(1.0, abs=1e-15)


def test_the_free_librations_against_lunar_laser_ranging():
    """The three free modes from β and γ (LLR moments) against the periods Rambaux & Williams (2011, CMDA 109, 85)
    found in DE421's librations: longitude 1056.13 d, latitude 8822.88 d (in the node's frame), wobble 27257.27 d.
    Budget 2 %: the modes are linearised on a circular orbit (the longitude mode's e² by H(e) only) without the
    Sun's perturbation of the orbit; the omitted terms are O(e²) with coefficients up to ~7 (2 %) and O(m²)
    (0.6 %)."""
    free = free_librations(synchronous_orbit(MOON), LLR)
    assert free.longitude_days == pytest.approx(1056.13, rel=0.02)
    assert free.latitude_days == pytest.approx(8822.88, rel=0.02)
    assert free.wobble_days == pytest.approx(27257.27, rel=0.02)


def test_the_latitude_mode_is_the_free_precession_seen_from_the_node():
    """Two routes to the free libration in latitude: the Jacobian of the averaged spin equation in the node's frame,
    and the roll-yaw pair's fast root (the free precession in space) less the node's regression. They agree to
    the averaged theory's O(Ω̇/n) (0.4 %) and O(I) geometry (cos I, 0.04 %): 1 %."""
    o = synchronous_orbit(MOON)
    free = free_librations(o, LLR)
    node_days = 2.0 * math.pi / abs(o.node_rate)
    from_space = 1.0 / (1.0 / node_days - 1.0 / free.precession_space_days)
    assert free.latitude_days == pytest.approx(from_space, rel=0.01)
