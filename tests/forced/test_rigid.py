"""Rung 7, the full rigid body: torque-free checks, the averaged limit, the triaxial 2ω term, the shapes estimates assume."""
import dataclasses
import math

import numpy as np
import pytest

from ephem.bodies.catalogue import get_body
from ephem.orbit.kepler import solve_kepler_scalar
from ephem.forced.precession_nutation import build_model
from ephem.forced.integration import angular_separation, integrate_spin_axis
from ephem.forced.rigid_body import integrate_rigid_body
from ephem.forced.rigid_numerics import (model_moments, quaternion_from_matrix, rotation_matrices, warm_kepler,
                                         worst_case_moments)
from ephem.forced.rotation_scale import SunGeometry
# the synthetic fast rotators and rung 5 against rung 7: the rigid-body study's (not the library's)
from studies.rigid_body import compare_with_averaged, synthetic_model


@pytest.fixture(scope="module")
def vesta():
    return build_model(get_body("Vesta"))


@pytest.fixture(scope="module")
def earth():
    return build_model(get_body("Earth"))


def rotations(model, count):
    return count * 2.0 * math.pi / model.spin_rate


# --------------------------------------------------------------------------- pieces


def test_quaternion_round_trip():
    rng = np.random.default_rng(7)
    q = rng.normal(size=(200, 4))
    q[:4] = np.eye(4)   # exercise every pivot of Shepperd's method
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    mats = rotation_matrices(q)
    # each entry of R is a few roundings of O(1) terms (≲ 3 ulp) and each entry of R Rᵀ sums three products
    # of them: ≲ 8 ε; allow 16 ε (measured 7 ε on the diagonal). (The atol=1e-15 this replaces left
    # np.allclose's default rtol = 1e-5 in force on the diagonal.)
    eps = np.finfo(float).eps
    assert np.allclose(mats @ mats.transpose(0, 2, 1), np.eye(3), rtol=0, atol=16 * eps)
    back = np.array([quaternion_from_matrix(m) for m in mats])
    same = np.minimum(np.linalg.norm(back - q, axis=1), np.linalg.norm(back + q, axis=1))  # q and -q
    assert same.max() < 1e-15 * 10    # Shepperd's method: a square root and ~10 roundings of O(1) values


@pytest.mark.parametrize("e", [0.0, 0.09, 0.28, 0.8])
def test_warm_started_kepler_matches_the_library_solver(e):
    solve = warm_kepler(e, 5.5)
    rng = np.random.default_rng(3)
    for m in 5.5 + np.cumsum(rng.uniform(-0.002, 0.02, 3000)):  # forwards with the steps DOP853 rejects
        c, s = solve(m)
        ecc = solve_kepler_scalar(m, e)
        # M is not reduced: agreement to a few ulp of |M| times dE/dM <= 1/(1 - e)
        tol = 2e-15 * (1.0 + abs(m)) / (1.0 - e)
        assert abs(c - math.cos(ecc)) < tol and abs(s - math.sin(ecc)) < tol


def test_start_is_the_catalogue_pole_and_both_directions_agree(vesta):
    t0 = vesta.pole_epoch
    span = rotations(vesta, 5)
    both = integrate_rigid_body(vesta, [t0 + span, t0 - span, t0], start="aligned")
    start = integrate_spin_axis(vesta, [t0])[0]
    # at t0 both return the catalogue pole through their own frame rotations: a few roundings, 1e-15 = 4.5 ε
    assert angular_separation(both.angular_momentum[2], start) < 1e-15
    assert angular_separation(both.figure_axis[2], start) < 1e-15
    forced = integrate_rigid_body(vesta, [t0])
    assert angular_separation(forced.figure_axis[0], start) < 1e-15     # the forced start moves L, not the C axis
    fwd = integrate_rigid_body(vesta, [t0 + span], start="aligned")
    bwd = integrate_rigid_body(vesta, [t0 - span], start="aligned")
    # the same two integrations (the requested epochs do not change DOP853's steps): equal up to the
    # dense output's rounding, 1e-14 = 45 ε on unit vectors (measured 0)
    assert np.allclose(both.angular_momentum[:2], [fwd.angular_momentum[0], bwd.angular_momentum[0]], rtol=0,
                       atol=1e-14)


# --------------------------------------------------------------------------- (a) torque-free


def test_torque_free_triaxial_conserves_energy_momentum_and_its_direction():
    eros = build_model(get_body("Eros"))
    w = eros.spin_rate
    t = eros.pole_epoch + np.linspace(-rotations(eros, 30), rotations(eros, 60), 181)
    # a large wobble (ω 5% off the C axis), so that every term of Euler's equations works
    tr = integrate_rigid_body(eros, t, initial_omega_body=(0.05 * w, 0.02 * w, w), solar_torque=False)
    energy, norm = tr.energy(), tr.momentum_norm()
    # DOP853 at rtol 1e-12 over 90 rotations (~1500 steps): its global error is not bounded by rtol but
    # grows with the steps. Measured for rtol = 1e-12, 1e-11, 1e-10: energy and |L| drift by <= 3e-3 rtol
    # (bound: rtol), the direction of L by 0.85-1.1 rtol (9.8e-13 here: a bound of rtol sat at 0.98 of it;
    # bound: 10 rtol). A wrong term of Euler's equations moves all three by > 1e-3.
    rtol = 1e-12
    assert np.abs(energy / energy[0] - 1.0).max() < rtol
    assert np.abs(norm / norm[0] - 1.0).max() < rtol
    assert angular_separation(tr.angular_momentum, tr.angular_momentum[0]).max() < 10 * rtol
    # the figure axis does wobble about L: the test is not vacuous
    assert angular_separation(tr.figure_axis, tr.angular_momentum).max() > 0.01


def test_euler_free_wobble_period_of_the_earth(earth):
    # Lara (2014) Table 1: the Earth's A/C = 0.99672. With A = B the body-frame equatorial ω turns
    # at σ = ω (C - A)/A: one wobble every A/(C - A) = 303.9 rotations = 303.0 days. (The classical
    # "~305 sidereal days" uses H = 1/305.5; the observed Chandler period, 433 d, is longer because
    # the Earth is not rigid.)
    A = 0.99672
    w = earth.spin_rate
    sigma = w * (1.0 - A) / A
    period = 2.0 * math.pi / sigma
    assert period == pytest.approx(303.05, abs=0.01)
    t = earth.pole_epoch + np.linspace(0.0, period, 201)
    tr = integrate_rigid_body(earth, t, moments=(A, A, 1.0), initial_omega_body=(1e-3 * w, 0.0, w),
                              solar_torque=False)
    phase = np.unwrap(np.arctan2(tr.omega_body[:, 1], tr.omega_body[:, 0]))
    measured = np.polyfit(t - t[0], phase, 1)[0]
    # DOP853 at rtol 1e-12 over one wobble (304 rotations, ~5000 steps): phase error ≲ steps x rtol = 5e-9 rad
    # of 2π at worst, ~1e-12 relative as measured; 1e-10 is 100 times that
    assert measured == pytest.approx(sigma, rel=1e-10)
    assert phase[-1] - phase[0] == pytest.approx(2.0 * math.pi, rel=1e-10)


# --------------------------------------------------------------------------- (b) the averaged limit


def averaging_errors(base, ratios, moments, span_orbits=0.05):
    """Max relative error (rung 5 - rung 7 L, over the max displacement) of synthetic fast rotators."""
    rel = []
    for r in ratios:
        m = synthetic_model(base, r, 1.0 - 0.5 * (moments[0] + moments[1]))
        span = span_orbits * 2.0 * math.pi / m.mean_motion
        cmp = compare_with_averaged(m, m.pole_epoch + np.linspace(0.0, span, 200), moments)
        rel.append(cmp.relative()[0])
    return np.array(rel)


def test_angular_momentum_converges_to_the_averaged_theory_axisymmetric(vesta):
    # A = B: the torque does not depend on the rotation phase; the only difference is the figure axis's
    # lag behind L, u ~ (A/Cω)|dL/dt|, which changes the torque by a factor 1 + O(u): relative error
    # ~ (A/C)(K/ω) = 3 H_d (A/C) (n/ω)^2, exponent -2 (corrections O(n/ω): ±0.01 over 100..1000).
    ratios = np.array([100.0, 300.0, 1000.0])
    mean = 1.0 - vesta.hd
    rel = averaging_errors(vesta, ratios, (mean, mean, 1.0))
    assert rel[0] < 1e-4                      # 5.5e-5 measured: 3 H_d (A/C)/100² = 4.2e-5
    slopes = np.diff(np.log(rel)) / np.diff(np.log(ratios))
    assert np.all((slopes > -2.1) & (slopes < -1.9)), slopes


def test_angular_momentum_converges_to_the_averaged_theory_triaxial(vesta):
    # B > A: L also circles at 2ω with radius (3/4)(n/ω)^2 (B-A)/C G (absolute, ∝ ρ²) while the
    # forced motion over a fixed span is ∝ K ∝ ρ: relative error exponent -1.
    ratios = np.array([100.0, 300.0, 1000.0])
    rel = averaging_errors(vesta, ratios, model_moments(vesta))
    assert rel[0] < 5e-3                      # 3.0e-3 measured
    slopes = np.diff(np.log(rel)) / np.diff(np.log(ratios))
    assert np.all((slopes > -1.1) & (slopes < -0.9)), slopes


# --------------------------------------------------------------------------- (c) the triaxial 2ω term


def at_solstice(model):
    """The model restarted where (a/r)^3 |sin δ cos δ| peaks, so the 2ω radius is stationary."""
    dpsi0, deps0 = model.nutation_at_pole_epoch
    s0 = model.pole_orbit_frame(dpsi0, model.obliquity + deps0)
    t = model.pole_epoch + np.linspace(0.0, 2.0 * math.pi / model.mean_motion, 4001)
    sun = SunGeometry.at(model, t)
    sd = sun.direction @ s0
    g = sun.torque_strength / (3.0 * model.mean_motion**2) * np.abs(sd) * np.sqrt(1.0 - sd * sd)
    return dataclasses.replace(model, pole_epoch=float(t[np.argmax(g)])), float(g.max())


def two_omega_circle(model, moments):
    """Radius and angular frequency of L - s over two rotations (a circle about its mean)."""
    period = 2.0 * math.pi / model.spin_rate
    t = model.pole_epoch + np.linspace(0.0, 2.0 * period, 257)[:-1]   # whole periods of 2ω
    L = integrate_rigid_body(model, t, moments).angular_momentum_orbit
    s = integrate_spin_axis(model, t) @ model.icrf_from_orbit
    d = L - s
    d -= d.mean(axis=0)
    e1 = np.cross(s[0], [0.0, 0.0, 1.0])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(s[0], e1)
    angle = np.unwrap(np.arctan2(d @ e2, d @ e1))
    return np.linalg.norm(d, axis=1), np.polyfit(t - t[0], angle, 1)[0]


@pytest.mark.parametrize("ratio", [300.0, 1000.0])
def test_triaxial_two_omega_term_has_the_predicted_radius(vesta, ratio):
    # The P₂² torque 3 n² (a/r)^3 (B-A)/2 sin δ cos δ turns at 2ω in the equator: L circles with
    # radius (3/4)(n/ω)^2 (B-A)/C (a/r)^3 |sin δ cos δ|. The averaged theory has no such term.
    base, g = at_solstice(vesta)
    moments = (0.7, 0.9, 1.0)
    model = synthetic_model(base, ratio, 0.2)
    radius, freq = two_omega_circle(model, moments)
    predicted = 0.75 / ratio**2 * 0.2 * g
    assert radius.mean() == pytest.approx(predicted, rel=0.01)        # 0.17% at 300, 0.06% at 1000
    assert radius.max() / radius.min() < 1.01                         # a circle, not a line
    assert freq == pytest.approx(2.0 * model.spin_rate, rel=0.01)     # 2ω - O(n)
    # ∝ B - A at fixed H_d, and absent for A = B
    half, _ = two_omega_circle(model, (0.75, 0.85, 1.0))
    assert half.mean() == pytest.approx(0.5 * radius.mean(), rel=1e-3)
    none, _ = two_omega_circle(model, (0.8, 0.8, 1.0))
    assert none.max() < 1e-3 * radius.mean()


# --------------------------------------------------------------------------- the shape an estimate assumes


def test_worst_case_moments_bound_the_catalogue_shapes():
    # a body known only by H_d is estimated with the worst triaxiality its H_d allows: every piece of the
    # rotation-scale estimate must be at least the catalogue shape's
    from ephem.forced.rotation_scale import error_terms

    for name in ("Vesta", "Eros", "Itokawa", "Mars"):
        model = build_model(get_body(name))
        for axis in ("momentum", "figure"):
            for modelled in ("none", "oppolzer"):
                own = error_terms(model, model_moments(model), 30.0, axis, modelled)
                worst = error_terms(model, worst_case_moments(model.hd), 30.0, axis, modelled)
                assert sum(own.values()) <= sum(worst.values()), (name, axis, modelled)


def test_a_body_outside_the_catalogue_needs_its_moments(vesta):
    stranger = dataclasses.replace(vesta, body="Nobody")
    with pytest.raises(ValueError, match="moments"):
        model_moments(stranger)


