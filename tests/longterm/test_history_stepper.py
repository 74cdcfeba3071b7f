"""The averaged spin's splitting (ephem.longterm.averaged_spin, issue 33) against its reference, scipy's DOP853: the
pole, the obliquity, the precession angle and the estimate's terms of every catalogue body with a shipped N-body
orbit over that orbit's full span; its order on a moving orbit; its exactness on a fixed one; and the cost the
service charges for the shipped spans.

The budget of the comparisons is a tenth of the history's smallest estimate term, the ``nutation`` term (the
others start at zero at the epoch and grow; every epoch's estimate is at least the nutation). The reference is
DOP853 at rtol 5e-12, 1/1000 of the shipped RTOL: over the shipped spans it is within 0.03″ of DOP853 at 5e-13
(Vesta's 0.031″ the largest, measured), which the budget must also cover. Where the neighbouring solutions part
by more than a degree (the history's ``meaningful_years``) the answer says it means nothing and no integrator
agrees with another: Eros' DOP853 at 5e-12 and at 5e-13 part by 67° at −3 Myr. The comparisons stop there."""
import dataclasses
import math
from functools import lru_cache

import numpy as np
import pytest

import ephem.longterm.averaged_spin as sh
from ephem import api
from ephem.base.budget import budget
from ephem.base.constants import ARCSEC
from ephem.bodies.catalogue import get_body
from ephem.families import theory_for
from ephem.longterm.nbody_orbit import shipped_orbit_history
from ephem.orbit.geometry import angle_between

#: the catalogue bodies whose histories integrate the averaged spin along a shipped N-body orbit (the Moon's is its
#: Cassini state, ephem.moon.family)
BODIES = ("earth", "mars", "ceres", "vesta", "eros", "steins", "itokawa")
REFERENCE_RTOL = 5e-12


@lru_cache(maxsize=1)
def _both(name: str):
    """(spin, orbit, years, splitting's history, DOP853's history) over the orbit's shipped span at 1-kyr steps
    (100 years for Itokawa's 40 kyr)."""
    b = get_body(name)
    spin = theory_for(b, b.perturbers).secular_spin()
    orbit = shipped_orbit_history(spin.orbit_body)
    lo, hi = orbit.span_years
    step = 1000.0 if hi - lo > 1e6 else 100.0
    years = np.arange(lo, hi + 0.5 * step, step)
    fast = sh.integrate(spin, orbit, years)
    return spin, orbit, years, fast, _reference(spin, orbit, years)


def _reference(spin, orbit, years):
    """DOP853 at :data:`REFERENCE_RTOL` (ATOL scaled with it)."""
    old = sh.RTOL, sh.ATOL
    try:
        sh.RTOL, sh.ATOL = REFERENCE_RTOL, old[1] * REFERENCE_RTOL / old[0]
        return sh.integrate(spin, orbit, years, method="DOP853")
    finally:
        sh.RTOL, sh.ATOL = old


@pytest.mark.parametrize("name", BODIES)
def test_the_splitting_is_dop853_within_a_tenth_of_the_nutation_term(name):
    """Over the orbit's shipped span, where the history means something: the pole and the obliquity within a
    tenth of the nutation term (Ceres': 0.029″, the smallest; measured at most 1/6 of that budget, Eros' 0.4″
    of 2.7″), the precession angle within it once projected on the sky (times sin ε), and the neighbours'
    terms within twice it (each an envelope of the distance between two solutions, each within the budget)."""
    spin, orbit, years, fast, ref = _both(name)
    tol = spin.nutation / 10.0
    # where the neighbours part by a degree: an epoch on the grid, the same for both (the spread crosses the degree
    # between two epochs by 4.9e-4° or more, Steins' the least: 9 budgets, far beyond rounding)
    assert fast.meaningful_years == ref.meaningful_years
    past, future = fast.meaningful_years
    inside = (years > past) & (years < future)
    assert inside.sum() > 0.25 * years.size            # the comparison covers most of the span (Eros': 1.1 of 4 Myr)
    assert np.max(angle_between(fast.spin[inside], ref.spin[inside])) < tol
    assert np.max(np.abs(fast.obliquity - ref.obliquity)[inside]) < tol
    sky = np.abs(fast.precession_angle - ref.precession_angle) * np.sin(ref.obliquity)
    assert np.max(sky[inside]) < tol
    for terms, ref_terms in ((fast.terms, ref.terms), (fast.obliquity_terms, ref.obliquity_terms)):
        for k in ("precession_constant", "pole"):
            assert np.max(np.abs(terms[k] - ref_terms[k])[inside]) < 2.0 * tol, k


def test_an_epoch_between_samples_and_steps_is_reached_by_a_part_step():
    """Ceres with its pole epoch moved off the orbit's samples (12.345 years) and epochs off the steps (every
    333.3 years, in no order): the part-steps to the epochs and from the epoch to the first sample agree with
    DOP853 as the whole history does (budget above: 0.029″)."""
    b = get_body("ceres")
    spin = dataclasses.replace(theory_for(b, b.perturbers).secular_spin(), epoch_years=12.345)
    orbit = shipped_orbit_history("Ceres")
    rng = np.random.default_rng(33)
    years = rng.permutation(np.concatenate([np.arange(-2.0e5, 1.0e5, 333.3), [12.345, 12.345 + 1e-6]]))
    fast = sh.integrate(spin, orbit, years)
    ref = _reference(spin, orbit, years)
    tol = spin.nutation / 10.0
    assert np.max(angle_between(fast.spin, ref.spin)) < tol
    assert np.max(np.abs(fast.precession_angle - ref.precession_angle) * np.sin(ref.obliquity)) < tol
    # at the epoch itself the mean pole (a step of zero: to rounding, 1e-15 rad), a microyear later moved by the
    # precession's (α cos ε − Ω_gp) sin ε × 1e-6 yr (2.2e-12 rad; the rounding of the unit vectors is 1e-4 of it)
    at = np.flatnonzero(years == 12.345)[0], np.flatnonzero(years == 12.345 + 1e-6)[0]
    pole = spin.mean_pole / np.linalg.norm(spin.mean_pole)
    assert angle_between(fast.spin[at[0]], pole) < 1e-15 and abs(fast.precession_angle[at[0]]) < 1e-15
    alpha, gp = spin.constants(orbit.semi_major_axis_at(12.345), orbit.eccentricity_at(12.345))
    eps = fast.obliquity[at[0]]
    assert angle_between(fast.spin[at[1]], pole) == pytest.approx(
        abs(alpha * math.cos(eps) - gp) * math.sin(eps) * 1e-6, rel=1e-3)


class PrecessingOrbit:
    """An orbit normal inclined ``i`` to the ecliptic whose node regresses uniformly at ``s`` (rad/yr): the one
    mode of a test particle's secular orbit (Ceres': i ≈ 10°, a 22-kyr period)."""

    def __init__(self, inclination: float, s: float):
        self.i, self.s = inclination, s

    def pole_at(self, years):
        node = self.s * np.asarray(years, dtype=float)
        return np.stack([math.sin(self.i) * np.sin(node), -math.sin(self.i) * np.cos(node),
                         np.full(node.shape, math.cos(self.i))], axis=-1)

    def eccentricity_at(self, years):
        return np.full(np.shape(years), 0.1)

    def semi_major_axis_at(self, years):
        return np.full(np.shape(years), 1.0)


def test_the_splitting_is_of_fourth_order_on_a_moving_orbit():
    """Blanes & Moan's S6 is of order 4: halving its step divides its error by 16. Measured on itself (the
    differences between 1, 2, 4 and 8 steps a sample; DOP853 at 1e-13 is not accurate enough to see them: its
    own error is 1e-9), on a fast precession (200″/yr at ε = 23°, 0.48 rad a sample) along an orbit whose normal
    turns 0.027 rad a sample (a 10° orbit's node regressing in 40 kyr), over 100 kyr. Measured ratios 16.07 and
    16.02; bounds [14, 18] leave room for the next order's share (a 2nd-order scheme gives 4, a 3rd-order 8), and
    the differences (3e-9 rad at the finest) stand far above rounding (1e-12 over 6400 steps)."""
    eps = math.radians(23.0)
    spin = sh.SpinConstants("test", 0.0, np.array([0.0, math.sin(eps), math.cos(eps)]), 200.0 * ARCSEC, 0.0,
                            0.0, 1.0, 0.1, 0.0)
    orbit = PrecessingOrbit(math.radians(10.0), -2.0 * math.pi / 40000.0)
    years = np.linspace(0.0, 1.0e5, 101)
    old = sh.RTOL
    sols = []
    try:
        for refine in (1, 2, 4, 8):
            sh.RTOL = 5e-9 / refine**4               # the splitting's steps cut by `refine`
            assert sh.split_steps(np.zeros(1), np.zeros(1))[0] == refine
            sols.append(sh.integrate(spin, orbit, years).spin)
    finally:
        sh.RTOL = old
    gaps = [float(np.max(angle_between(a, b))) for a, b in zip(sols[:-1], sols[1:])]
    assert gaps[-1] > 1e-9
    for coarse, fine in zip(gaps[:-1], gaps[1:]):
        assert 14.0 < coarse / fine < 18.0, gaps


def test_on_a_fixed_orbit_a_step_is_exact():
    """A fixed orbit: the field does not depend on time, flows A and B commute, and the splitting is the
    rotation about n̂ at α cos ε − Ω_gp to rounding (8 turns over 4 Myr in 8000 steps: budget 1e-12 relative,
    1e-12 rad on ε)."""
    eps = math.radians(40.0)
    spin = sh.SpinConstants("test", 0.0, np.array([0.0, math.sin(eps), math.cos(eps)]), 2.0 * ARCSEC, 0.0,
                            0.01 * ARCSEC, 1.0, 0.0, 0.0)

    class Fixed(PrecessingOrbit):
        def pole_at(self, years):
            return np.broadcast_to([0.0, 0.0, 1.0], np.shape(years) + (3,)).copy()

        def eccentricity_at(self, years):
            return np.zeros(np.shape(years))

    years = np.linspace(-3.0e6, 1.0e6, 401)
    h = sh.integrate(spin, Fixed(0.0, 0.0), years)
    rate = (2.0 * math.cos(eps) - 0.01) * ARCSEC
    assert np.max(np.abs(h.obliquity - eps)) < 1e-12
    assert h.precession_angle == pytest.approx(rate * years, rel=1e-12, abs=1e-12)


def test_the_step_count_follows_the_physics_in_powers_of_two():
    """One step per sample while |α| + |Ω_gp| turns less than 0.5 rad in it and the normal less than 0.03 rad;
    beyond, the least power of two that brings both within; exact at a power of two (a sample at twice the limit
    takes two steps, a hair above it four)."""
    limit_rate, limit_turn = sh.SPLIT_RATE_ANGLE, sh.SPLIT_NORMAL_TURN
    rate = np.array([0.0, limit_rate, 2.0 * limit_rate, 2.0 * limit_rate * (1.0 + 1e-15), 0.0, 5.0 * limit_rate])
    turn = np.array([0.0, 0.0, 0.0, 0.0, 3.0 * limit_turn, 33.0 * limit_turn])
    assert sh.split_steps(rate, turn).tolist() == [1, 1, 2, 4, 4, 64]


@pytest.mark.parametrize("name", ("earth", "mars", "ceres", "vesta", "eros", "steins", "moon"))
def test_the_service_budget_serves_every_span_the_shipped_orbits_cover(name):
    """The issue's goal: a 5 s request budget (the service's) now admits the whole shipped span (−3..+1 Myr) at
    1-kyr steps, predicted before the work (benchmarks/bench_history.py compares the prediction with the CPU)."""
    with budget(5.0, 500.0) as bud:
        a = api.history(name, -3.0e6, 1.0e6, 1000.0)
    assert len(a["year"]) == 4001 and bud.spent_cpu_s < 5.0
