"""The free wobble on spin-axis tracks: the figure axis circles the angular momentum.

Checked against the full rigid body (Euler's equations under the solar torque, started with the
same wobble), and the ladder's choice against the tolerance. The phase against astropy's position angle:
tests/orbit/test_against_astropy.py.
"""
import math

import numpy as np
import pytest
from astropy import units as u
from astropy.coordinates import SkyCoord

from ephem import api
from ephem.bodies.catalogue import get_body
from ephem.base.constants import ARCSEC, MAS
from ephem.base.errors import InvalidInputError, NotApplicableError
from ephem.rotation.free_motion import free_motion, free_wobble_bound, observed_wobble_period_days
from ephem.forced.precession_nutation import cached_model
from ephem.sun.ladder import Ladder
from ephem.forced.integration import angular_separation
from ephem.forced.rigid_body import SunOrbit, integrate_states
from ephem.forced.rigid_numerics import model_moments, quaternion_from_matrix, rotation_matrices
from ephem.forced.rotation_scale import SunGeometry, forced_angular_velocity

J2000 = 2451545.0


def unit(ra_deg, dec_deg):
    ra, dec = np.radians(ra_deg), np.radians(dec_deg)
    return np.stack([np.cos(dec) * np.cos(ra), np.cos(dec) * np.sin(ra), np.sin(dec)], axis=-1)


@pytest.mark.parametrize("name", ["Mars", "Earth", "Eros"])
def test_the_published_amplitude_is_the_largest_offset_over_a_wobble(name):
    # J0 is the angle at ν = 0; energy conservation makes it the largest (ephem.rotation.free_motion.free_wobble_bound)
    body = get_body(name)
    first = free_motion(body, np.array([J2000]))
    t = J2000 + np.linspace(0.0, first.wobble_period_days, 2001)
    opening = free_motion(body, t).wobble_angle
    # the grid starts at ν = 0, where J = J0 (measured: 1-2 ε); elsewhere J is smaller. rel 1e-9 leaves room
    # for a grid that would straddle the maximum (J is stationary there: (π/2000)² x its small variation)
    assert np.max(opening) == pytest.approx(free_wobble_bound(body), rel=1e-9)
    A, B, C = (x / body.moments[2] for x in body.moments)
    j0 = free_wobble_bound(body)
    smallest = math.asin(math.sin(j0) * math.sqrt((1 / B - 1 / C) / (1 / A - 1 / C)))
    assert np.min(opening) == pytest.approx(smallest, rel=1e-6)


def rigid_figure_axis(name, phase_deg, t):
    """The C axis of the full rigid body started at the pole epoch with L along the catalogue pole and the
    C axis J0 away from it at position angle ``phase_deg`` (north through east), L in the b2-b3 plane, on top
    of the forced motion (the forced transverse spin of :func:`ephem.forced.rotation_scale.forced_angular_velocity`
    added, to first order a superposition), so that the body's free wobble is the one asked for."""
    body = get_body(name)
    m = cached_model(body)
    dpsi0, deps0 = m.nutation_at_pole_epoch
    L_orbit = m.pole_orbit_frame(dpsi0, m.obliquity + deps0)
    L_icrf = m.icrf_from_orbit @ L_orbit
    J = free_wobble_bound(body)
    # the C axis: J from L towards position angle phase, built with astropy's offset (an independent route)
    pole = SkyCoord(*np.degrees([math.atan2(L_icrf[1], L_icrf[0]), math.asin(L_icrf[2])]), unit="deg", frame="icrs")
    fig = pole.directional_offset_by(phase_deg * u.deg, J * u.rad)
    f_icrf = unit(fig.ra.deg, fig.dec.deg)
    f_orbit = m.icrf_from_orbit.T @ f_icrf
    b2 = (L_orbit - math.cos(J) * f_orbit) / math.sin(J)
    b2 /= np.linalg.norm(b2)
    b1 = np.cross(b2, f_orbit)
    q0 = quaternion_from_matrix(np.column_stack([b1, b2, f_orbit]))
    A, B, C = moments = model_moments(m)
    L_body = np.array([0.0, math.sin(J), math.cos(J)])       # direction; |L| = C ω
    w0 = m.spin_rate
    omega = L_body * C / np.array([A, B, C])                  # ω_b / ω0
    sun = SunGeometry.at(m, [m.pole_epoch])
    sun_body = rotation_matrices(q0[None])[0].T @ sun.direction[0]
    omega += forced_angular_velocity(moments, w0, sun_body, float(sun.torque_strength[0])) / w0 - [0.0, 0.0, 1.0]
    states, _ = integrate_states(moments, w0, np.concatenate([omega, q0]), m.pole_epoch, t, SunOrbit.from_model(m))
    rot = rotation_matrices(states[:, 3:])
    return rot[:, :, 2] @ m.icrf_from_orbit.T


@pytest.mark.parametrize("name,days,phase", [("Mars", 6.0, 35.0), ("Eros", 2.0, 250.0)])
def test_the_track_with_the_wobble_follows_the_full_rigid_body(name, days, phase):
    t = J2000 + np.linspace(0.0, days, 97)
    ans = api.track(name, t[0], t[-1], t[1] - t[0], model="hansen", free_wobble_phase_deg=phase)
    served = unit(np.array(ans["pole_ra_deg"]), np.array(ans["pole_dec_deg"]))
    truth = rigid_figure_axis(name, phase, np.array(ans["jd_tdb"]))
    error = angular_separation(served, truth)
    assert np.max(error) <= ans["model"]["estimated_error_mas"] * MAS
    without = api.track(name, t[0], t[-1], t[1] - t[0], model="hansen")
    left_out = angular_separation(unit(np.array(without["pole_ra_deg"]), np.array(without["pole_dec_deg"])), truth)
    # the wobble is what the figure axis does: leaving it out costs up to J0, which the estimate then carries
    assert np.max(left_out) > 0.5 * free_wobble_bound(get_body(name))
    assert np.max(left_out) <= without["model"]["estimated_error_mas"] * MAS
    assert np.max(error) < 0.2 * np.max(left_out)


def test_the_ladder_adds_the_wobble_only_when_the_tolerance_needs_it():
    t = J2000 + np.linspace(0.0, 3650.0, 200)
    ladder = Ladder(get_body("mars"), wobble=None)
    loose = ladder.choose(t, 1000 * MAS)
    assert not loose.free_wobble and loose.terms["free_wobble"] == pytest.approx(0.1 * ARCSEC)
    with pytest.raises(NotApplicableError, match="largest term: free_wobble.*free_wobble_phase_deg"):
        ladder.choose(t, 50 * MAS)
    from ephem.rotation.free_motion import make_wobble

    followed = Ladder(get_body("mars"), wobble=make_wobble(get_body("mars"), 10.0))
    assert not followed.choose(t, 1000 * MAS).free_wobble            # not needed: not added
    tight = followed.choose(t, 50 * MAS)
    assert tight.free_wobble and "free_wobble" not in tight.terms and tight.total <= 50 * MAS
    momentum = Ladder(get_body("mars"), axis="angular_momentum").choose(t, 50 * MAS)
    assert "free_wobble" not in momentum.terms and not momentum.free_wobble


def test_the_earths_rigid_wobble_loses_phase_against_the_chandler_wobble():
    # the rigid Earth wobbles in 303 d, the real one in ~433 d: the added wobble is good only near its epoch
    earth = get_body("earth")
    assert observed_wobble_period_days(earth) == 433.0
    # the Earth's default model is the lunisolar one (the Moon and the Sun); the Sun-only ladder alike
    near = api.track(earth, "2020-01-25", "2020-02-05", 0.5, model="lunisolar", free_wobble_phase_deg=0.0,
                     free_wobble_epoch="2020-01-30")["model"]["error_terms_mas"]["free_wobble_model"]
    far = api.track(earth, "2020-01-25", "2022-01-25", 5.0, model="lunisolar", free_wobble_phase_deg=0.0,
                    free_wobble_epoch="2020-01-30")["model"]["error_terms_mas"]["free_wobble_model"]
    near_sun = api.track(earth, "2020-01-25", "2020-02-05", 0.5, model="hansen", free_wobble_phase_deg=0.0,
                         free_wobble_epoch="2020-01-30", perturbers="sun")["model"]["error_terms_mas"]
    # the phase loss is the same; only the transport term (2 J times the pole's motion in 6 days) differs
    assert near_sun["free_wobble_model"] == pytest.approx(near, abs=0.01)
    # 2 J sin(π Δf Δt): Δf = 1/303.15 - 1/433 per day
    df = 1 / free_motion(earth, np.array([J2000])).wobble_period_days - 1 / 433.0
    assert near == pytest.approx(2000.0 * math.sin(math.pi * df * 6.0), rel=0.02)
    assert 2000.0 <= far <= 2000.5      # 726 days: the phase is lost (Δφ > π); plus the transport term
    for perturbers in (None, "sun"):
        with pytest.raises(NotApplicableError, match="following the free wobble does not help"):
            api.track(earth, "2000-01-01", "2020-01-01", 30.0, tolerance_mas=100, free_wobble_phase_deg=0.0,
                      perturbers=perturbers)


def test_a_body_without_a_published_amplitude_says_so():
    ans = api.track("vesta", "2000-01-01", "2001-01-01", 30.0, tolerance_mas=1000)
    assert "free_wobble" not in ans["model"]["error_terms_mas"]
    assert any("no free-wobble amplitude" in w for w in ans["model"]["warnings"])
    with pytest.raises(InvalidInputError, match="free_wobble_J_arcsec"):
        api.track("vesta", "2000-01-01", "2001-01-01", 30.0, free_wobble_phase_deg=0.0)
    ok = api.track("vesta", "2000-01-01", "2001-01-01", 30.0, free_wobble_phase_deg=0.0, free_wobble_J_arcsec=2.0)
    assert ok["model"]["free_wobble"]["J_arcsec"] == 2.0


@pytest.mark.parametrize("kwargs,field", [
    ({"free_wobble_phase_deg": float("nan")}, "free_wobble_phase_deg"),
    ({"free_wobble_phase_deg": 0.0, "free_wobble_J_arcsec": -1.0}, "free_wobble_J_arcsec"),
    ({"free_wobble_phase_deg": 0.0, "free_wobble_J_arcsec": 1e6}, "free_wobble_J_arcsec"),
    ({"free_wobble_J_arcsec": 1.0}, "free_wobble_J_arcsec"),
    ({"free_wobble_epoch": "2020-01-01"}, "free_wobble_epoch"),
    ({"free_wobble_phase_deg": 0.0, "axis": "angular_momentum"}, "free_wobble_phase_deg"),
    ({"axis": "rotation"}, "axis"),
    ({"free_wobble_phase_deg": 0.0, "free_wobble_epoch": "not a date"}, "free_wobble_epoch"),
])
def test_bad_wobble_requests_name_the_field(kwargs, field):
    with pytest.raises(InvalidInputError, match=field):
        api.track("mars", "2000-01-01", "2001-01-01", 30.0, **kwargs)


def test_cli_takes_the_axis_and_the_wobble():
    from typer.testing import CliRunner

    from ephem.cli import app

    runner = CliRunner()
    res = runner.invoke(app, ["track", "mars", "--start", "2000-01-01", "--stop", "2000-01-03", "--step-days", "1",
                              "--tolerance-mas", "50", "--free-wobble-phase-deg", "10", "--format", "csv"])
    assert res.exit_code == 0, res.output
    assert "free wobble" in res.stderr
    refused = runner.invoke(app, ["track", "mars", "--start", "2000-01-01", "--stop", "2000-01-03",
                                  "--step-days", "1", "--tolerance-mas", "50"])
    assert refused.exit_code == 3 and "free_wobble" in refused.stderr
    momentum = runner.invoke(app, ["track", "mars", "--start", "2000-01-01", "--stop", "2000-01-03",
                                   "--step-days", "1", "--tolerance-mas", "50", "--axis", "angular_momentum"])
    assert momentum.exit_code == 0, momentum.output
