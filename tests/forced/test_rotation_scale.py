"""The rotation-scale terms (ephem.forced.rotation_scale) against the integrated full rigid body (ephem.forced.rigid_body).

The reference is our own integration of Euler's equations and the attitude under the solar
gravity-gradient torque (DOP853 at rtol 1e-12, direction errors ~1e-14 rad a year), started in the
forced state so that it carries no free wobble. The averaged pole is rung 5 (the rotation-averaged
torque integrated along the same Keplerian orbit).
"""
from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from ephem.forced import rotation_scale as rs
from ephem.bodies.catalogue import Body, Pole, get_body
from ephem.base.constants import MAS
from ephem.forced.precession_nutation import cached_model
from ephem.forced.integration import angular_separation, integrate_spin_axis
from ephem.forced.rigid_body import integrate_rigid_body
from ephem.orbit.relativity import geodesic_angle
from ephem.forced.rigid_numerics import normalised_moments, rotation_matrices
from studies.rotation_scale import compare, generated_population, true_error
from studies.rung_choice import issue_bodies


def make_body(a=1.3241, e=0.2801, period_h=12.132, moments=(0.06, 0.16, 0.19), ra=90.0, dec=21.56, name="test"):
    """An Itokawa-like body (the issue's orbit and period, Itokawa's printed moments) with a chosen pole."""
    ito = get_body("itokawa")
    return Body(name=name, orbit=replace(ito.orbit, a_au=a, e=e, i_deg=0.0),
                pole=Pole(ra, dec, ito.pole.epoch_jd_tdb), rotation_period_hours=period_h, moments=moments)


@pytest.fixture(scope="module")
def near_right_angle():
    """The Itokawa-like body at 92° obliquity over a fifth of an orbit (223 rotations, 0.4 s)."""
    b = make_body()
    return b, compare(b, 0.2 * 2.0 * math.pi / cached_model(b).mean_motion, 0.3)


def test_amplitudes_are_the_published_first_order_forms():
    # the issue's integration-derived forms: radius g|s·u||s×u|(B-A)/(4Cω²) of L's semi-diurnal circle and
    # g|s·u||s×u|(C(A+B)-2AB)/(2C²ω²) of the Oppolzer offset, checked on random geometry
    rng = np.random.default_rng(3)
    s = rng.normal(size=(50, 3))
    s /= np.linalg.norm(s, axis=1, keepdims=True)
    lam = rng.uniform(0, 2 * math.pi, 50)
    u = np.stack([np.cos(lam), np.sin(lam), np.zeros(50)], axis=-1)
    g = rng.uniform(1e-6, 1e-4, 50)
    A, B, C, w = 0.5, 0.8, 1.1, 6.0
    terms = rs.rotation_terms((A, B, C), w, s, rs.SunGeometry(np.zeros(50), u, g), rng.uniform(0, 6, 50))
    z = np.abs(np.sum(s * u, axis=1))
    perp = np.linalg.norm(np.cross(s, u), axis=1)
    # 1e-12 relative: a few roundings in the products
    np.testing.assert_allclose(np.linalg.norm(terms.semi_diurnal, axis=1), g * z * perp * (B - A) / (4 * C * w * w),
                               rtol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(terms.oppolzer, axis=1),
                               g * z * perp * (C * (A + B) - 2 * A * B) / (2 * C * C * w * w), rtol=1e-12)
    # both lie in the equator of s (they move the pole, not along it)
    assert np.abs(np.sum(terms.oppolzer * s, axis=1)).max() < 1e-12 * np.abs(terms.oppolzer).max()
    assert np.abs(np.sum(terms.semi_diurnal * s, axis=1)).max() < 1e-12 * np.abs(terms.semi_diurnal).max()


def test_the_terms_remove_almost_all_of_the_averaging_error(near_right_angle):
    _, r = near_right_angle
    # measured: L 169 -> 0.25 mas and the figure axis 382 -> 1.6 mas over one orbit; 92 -> 0.2 and
    # 200 -> 1.1 mas over this fifth. The bounds leave a factor ~5 on the measured ratios.
    assert r["momentum_bare"] > 50 * MAS and r["figure_bare"] > 100 * MAS     # a real effect to remove
    assert r["momentum_all"] < 0.01 * r["momentum_bare"]
    assert r["figure_all"] < 0.03 * r["figure_bare"]
    # without the phase the semi-diurnal terms remain: the error is of their size, not of the offset's
    radius = r["terms"].semi_diurnal_radius.max()
    # (R(t) + R(t0) <= 2R; 10% for the next order)
    assert r["figure_oppolzer"] < 2.2 * radius and r["figure_oppolzer"] < r["figure_bare"]


def test_the_phase_model_follows_the_long_axis(near_right_angle):
    # φ(t) = φ0 + ω τ + cos ε Δψ against the integrated A axis's angle from the node (measured 1.1e-3 rad over
    # an orbit: the semi-diurnal terms move by 2 R δφ, 0.2 mas for R = 90 mas)
    _, r = near_right_angle
    rig = r["rigid"]
    e1, e2 = rs.equator_basis(rig.figure_axis_orbit)
    a_axis = rotation_matrices(rig.quaternion)[:, :, 0]
    measured = np.arctan2(np.sum(a_axis * e2, axis=1), np.sum(a_axis * e1, axis=1))
    gap = np.remainder(measured - r["phase"] + math.pi, 2 * math.pi) - math.pi
    assert np.abs(gap).max() < 5e-3


def test_the_forced_start_leaves_no_free_wobble():
    # started with ω along the C axis the body wobbles freely by about the forced offset; started in the forced
    # state the closed form follows it 20x better (measured 40x)
    b = make_body()
    span = 0.05 * 2.0 * math.pi / cached_model(b).mean_motion
    forced, aligned = compare(b, span, 1.0, "forced"), compare(b, span, 1.0, "aligned")
    assert aligned["figure_all"] > 20 * forced["figure_all"]


def test_the_forced_start_keeps_the_catalogue_spin_rate():
    # the (B - A) torque makes the spin rate oscillate at 2ω by g (B - A)/(4 C ω) about its mean. Started at ω
    # exactly (aligned), the mean is off by the oscillation's value at the start, which the forced start adds:
    # the integrated aligned body's mean must show that offset, and the forced body's mean must not
    b = make_body(a=1.0, e=0.1, period_h=24 * 365.25 / 30, moments=(0.5, 0.8, 1.0), ra=270.0, dec=36.56)  # ε ≈ 30°
    m = cached_model(b)
    period = 2.0 * math.pi / m.spin_rate
    t = m.pole_epoch + np.linspace(0.0, 20 * period, 20 * 64 + 1)
    for angle in (0.3, 1.2):
        offset = {}
        for start in ("forced", "aligned"):
            w3 = integrate_rigid_body(m, t, b.moments, angle, start=start).omega_body[:-1, 2]   # whole rotations
            offset[start] = w3.mean() / m.spin_rate - 1.0
        sun = rs.SunGeometry.at(m, [m.pole_epoch])
        q0 = integrate_rigid_body(m, [m.pole_epoch], b.moments, angle).quaternion[0]
        sun_body = rotation_matrices(q0[None])[0].T @ sun.direction[0]
        oscillation = rs.forced_angular_velocity(normalised_moments(b.moments), m.spin_rate, sun_body,
                                                 float(sun.torque_strength[0]))[2] / m.spin_rate - 1.0
        assert abs(oscillation) > 3e-5          # starts where the oscillation is large (g (B - A)/(4 C ω²) = 8e-5)
        # the Sun turns the oscillation's phase by 2ν̇ over 20 rotations (4% of a turn at ω/n = 30): 10%
        assert offset["aligned"] == pytest.approx(-oscillation, rel=0.1)
        assert abs(offset["forced"]) < 0.1 * abs(oscillation)


#: The issue's requests (studies.rotation_scale.issue_bodies) at 20 mas: (span, step in days). Before issue 15 every
#: one was refused, the best rung estimated at 53.4, 47.7 / 134 and 117 mas (for these spans, commit 93e801e); the
#: rigid body shows the bare averaged track off by at most ~11 (figure) and 3.5 mas (L) for the Itokawa-like body,
#: 58 and 9.7 for the Eros-like and 37 and 16.6 for the 4-hour rotator (the issue's integrations), so 20 mas is what
#: the rotation-scale terms make possible for all three.
ISSUE_REQUESTS = {"itokawa-like": ("2000-01-01", "2020-01-01", 365.25), "eros-like": ("2000-01-01", "2002-01-01", 5.0),
                  "4h-e0.75": ("2000-01-01", "2002-01-01", 5.0)}


def turn_about(v: np.ndarray, axis: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """Unit vectors ``v`` (N, 3) turned by ``angle`` (N,) about the unit ``axis`` (Rodrigues' formula)."""
    c, s = np.cos(angle)[:, None], np.sin(angle)[:, None]
    return v * c + np.cross(axis, v) * s + axis * (v @ axis)[:, None] * (1.0 - c)


@pytest.mark.parametrize("name", ISSUE_REQUESTS)
def test_the_issue_s_requests_are_served_within_their_tolerance_of_the_rigid_body(name):
    from ephem import api
    from ephem.forced.rigid_numerics import body_moments

    b = issue_bodies()[name]
    m = cached_model(b)
    answers = {axis: api.track(b, *ISSUE_REQUESTS[name], tolerance_mas=20.0, axis=axis)
               for axis in ("figure", "angular_momentum")}
    t = np.array(answers["figure"]["jd_tdb"])
    # the independent reference: the full rigid body from the forced start (DOP853 at 1e-10: at 1e-12 the
    # Itokawa-like figure axis moves by 0.0006 mas, measured), with the shape the estimate assumes
    rig = integrate_rigid_body(m, t, moments=body_moments(b, m), rtol=1e-10, atol=1e-12)
    # the rigid body integrates the torque alone; the served track carries the geodesic precession too, a rotation
    # about the orbit normal by ephem.orbit.relativity's instantaneous angle (what is left, the equinox's re-phasing,
    # is in the estimate's geodesic term)
    turned = geodesic_angle(m.geodesic_rate, m.mean_motion, m.eccentricity, m.mean_anomaly(t),
                            float(m.mean_anomaly(m.pole_epoch)))
    normal = m.icrf_from_orbit[:, 2]
    for axis, ans in answers.items():
        assert ans["model"]["estimated_error_mas"] <= 20.0
        ra, dec = np.radians(ans["pole_ra_deg"]), np.radians(ans["pole_dec_deg"])
        served = np.stack([np.cos(dec) * np.cos(ra), np.cos(dec) * np.sin(ra), np.sin(dec)], axis=-1)
        truth = turn_about(rig.figure_axis if axis == "figure" else rig.angular_momentum, normal, turned)
        error = angular_separation(served, truth)
        # the estimate is a bound: the served pole within it of the rigid body (and so within the tolerance)
        assert error.max() <= ans["model"]["estimated_error_mas"] * MAS, (axis, error.max() / MAS, ans["model"])


#: Below this (radians) a truth is rounding, not error: the ladder's own rounding term (ephem.base.constants.ROUNDING); the
#: rigid reference's integration error is ~1e-14 rad (rtol 1e-12 against 1e-13, measured).
ROUNDING = 1e-12


@pytest.mark.parametrize("seed", [11, 12])
def test_error_terms_are_close_bounds_of_the_rigid_body_on_a_generated_population(seed):
    # issue 15: across the extremes (e to 0.9, obliquities near 0°, 90° and 180°, spans of 1% of an orbit to a few
    # orbits) the estimate is never exceeded, its median is within 3x of the truth and its worst within 10x, for
    # every variant of the track and both axes. Measured on the 160-case population of studies.rotation_scale
    # (docs/accuracy.md): medians 1.05-2.5x, worst 5.6x.
    ratios = {}
    for case in generated_population(6, seed):
        b, span, phase0 = case.body(), case.span_days(), case.phase
        r = compare(b, span, phase0)
        m = cached_model(b)
        for modelled in rs.MODELLED:
            for axis in ("figure", "momentum"):
                bound = sum(rs.error_terms(m, b.moments, span, axis, modelled).values())
                true = true_error(r, axis, modelled)
                # never exceeded (+ the rounding floor every served estimate carries)
                assert true <= bound + ROUNDING, (case, modelled, axis, true / MAS, bound / MAS)
                if true > ROUNDING:
                    ratios.setdefault((modelled, axis), []).append(bound / true)
        # the rotation phase model stays within its estimate's allowance (what the "all" track's phase piece takes)
        nut = m.nutation
        moved = float(np.sum(np.hypot(nut.lon_sin, nut.lon_cos)) + np.sum(np.hypot(nut.obl_sin, nut.obl_cos))) \
            + abs(m.precession_rate * span)
        assert r["phase_error"] <= rs.PHASE_FACTOR * moved, (case, r["phase_error"], moved)
    for key, q in ratios.items():
        assert np.median(q) <= 3.0 and max(q) <= 10.0, (key, np.median(q), max(q))


def test_the_forced_start_s_rates_against_their_analytic_forms():
    # λ̇ and d(g p²)/dt enter the forced start's spin oscillation; checked against the Kepler-orbit derivatives:
    # ν̇ = n (1 + e cos ν)²/(1 - e²)^(3/2), u̇ = ν̇ W × u, dg/dν = -3 g e sin ν/(1 + e cos ν), ż = s·u̇
    from ephem.orbit.kepler import true_anomaly

    for e, ra, dec in ((0.0, 90.0, 21.56), (0.6, 270.0, 36.56), (0.9, 10.0, -40.0)):
        b = make_body(e=e, ra=ra, dec=dec)
        m = cached_model(b)
        s = m.catalogue_pole_orbit
        for t in m.pole_epoch + np.array([0.0, 100.0, 317.0]):
            nu = float(true_anomaly(m.mean_anomaly(np.array([t])), e)[0])
            nu_dot = m.mean_motion * (1 + e * math.cos(nu)) ** 2 / (1 - e * e) ** 1.5
            sun = rs.SunGeometry.at(m, [t])
            u, g = sun.direction[0], float(sun.torque_strength[0])
            u_dot = nu_dot * np.cross([0.0, 0.0, 1.0], u)
            z, z_dot = float(s @ u), float(s @ u_dot)
            azimuth = float(np.cross(u, u_dot) @ s) / (1 - z * z)
            g_dot = -3 * g * e * math.sin(nu) / (1 + e * math.cos(nu)) * nu_dot
            # the first is the same algebra by another route (1e-12 relative); the second a central difference,
            # whose error (h²/6 times the third derivative) is < 1e-8 of the rate for h = 1e-4 of the pericentre
            # passage: 1e-6 relative leaves room for the rounding of g over 2h
            assert rs.sun_azimuth_rate(m, s, t) == pytest.approx(azimuth, rel=1e-12, abs=1e-15 * nu_dot)
            assert rs.forcing_amplitude_rate(m, s, t) == pytest.approx(g_dot * (1 - z * z) - 2 * g * z * z_dot,
                                                                       rel=1e-6, abs=1e-9 * g * nu_dot)


def test_error_terms_refuse_unknown_options():
    m = cached_model(make_body())
    with pytest.raises(ValueError, match="axis"):
        rs.error_terms(m, (0.5, 0.8, 1.0), 10.0, "rotation")
    with pytest.raises(ValueError, match="modelled"):
        rs.error_terms(m, (0.5, 0.8, 1.0), 10.0, "figure", "some")


def test_the_rotation_phase_at_the_interfaces():
    from fastapi.testclient import TestClient

    from ephem import api
    from ephem.base.errors import InvalidInputError
    from service.app import app

    q = dict(start="2020-01-01", stop="2020-01-03", step_days=0.25)
    ans = api.track("eros", **q, model="numerical", rotation_phase_deg=30.0)
    assert ans["model"]["rotation_scale"] == {"modelled": "all", "rotation_phase_deg": 30.0}
    bare = api.track("eros", **q, model="numerical")
    assert bare["model"]["rotation_scale"] is None
    # the served figure axis moves by the closed-form terms: Eros' offset is tens of mas, far above rounding
    gap = np.hypot(np.subtract(ans["pole_dec_deg"], bare["pole_dec_deg"]),
                   np.subtract(ans["pole_ra_deg"], bare["pole_ra_deg"]) * np.cos(np.radians(bare["pole_dec_deg"])))
    assert gap.max() * 3.6e6 > 1.0
    for bad, why in ((dict(rotation_phase_deg=float("nan")), "finite"),
                     (dict(rotation_phase_deg=10.0, free_wobble_phase_deg=5.0, free_wobble_J_arcsec=0.1), "not combined")):
        with pytest.raises(InvalidInputError, match=why) as err:
            api.track("eros", **q, **bad)
        assert err.value.field == "rotation_phase_deg"
    with pytest.raises(InvalidInputError, match="does not model the rotation scale"):
        api.track("earth", **q, rotation_phase_deg=10.0)
    r = TestClient(app).get("/v1/bodies/eros/track", params={**q, "model": "numerical", "rotation_phase_deg": 30.0})
    assert r.status_code == 200 and r.json()["model"]["rotation_scale"]["modelled"] == "all"


def test_error_terms_share_one_sampling_of_a_span_and_keep_no_model_alive():
    """Every (axis, modelled, pole) variant of a span reads one sampling of it (span_samples, kept for the next few
    asks): each variant's terms equal those of a sampling made afresh for it (to 1e-15 relative: the same
    operations), the second ask does not sample again, and a model the process drops is not held by what is kept."""
    import gc
    import weakref

    b = make_body()
    model = cached_model(b)
    moments = normalised_moments(b.moments)
    variants = [("figure", "none", "figure"), ("momentum", "none", "figure"), ("figure", "oppolzer", "figure"),
                ("momentum", "all", "figure"), ("figure", "none", "momentum"), ("momentum", "none", "momentum")]
    for span in (0.0, 3.5, -40.0, 400.0, 1e5):          # short, both sides of t0, and beyond the sampled orbits
        kept = [rs.error_terms(model, moments, span, *v) for v in variants]
        samples = rs.span_samples(model, moments, span)
        assert rs.span_samples(model, moments, span) is samples          # asked again: not sampled again
        for v, terms in zip(variants, kept):
            rs._samples.clear()
            fresh = rs.error_terms(model, moments, span, *v)
            assert fresh.keys() == terms.keys()
            for k in terms:
                assert terms[k] == pytest.approx(fresh[k], rel=1e-15, abs=0.0), (span, v, k)
    other = replace(model)            # an equal model, another object: kept apart, and not kept alive
    assert rs.span_samples(other, moments, 3.5) is not rs.span_samples(model, moments, 3.5)
    ref = weakref.ref(other)
    del other
    gc.collect()
    assert ref() is None
    assert len(rs._samples) <= rs._SAMPLES_KEPT
