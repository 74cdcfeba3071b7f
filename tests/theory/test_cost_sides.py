"""A span across the pole epoch is priced for the work the code does on each side of it (issue 39).

The second-order mean track, the averaged spin of the long-term model and the rotation averaging's bound all work
from the pole epoch outward, once on each side the epochs reach: the price of a span across it exceeds the
one-sided price by the side units (data/cost_model.toml) times the further sides the code itself takes. The sides
are counted by watching the code work (its integrations, its bounds' calls), so a price that stops following the
code fails here. No timing: benchmarks/bench_calibration.py holds the units to the measured CPU.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from ephem.bodies.catalogue import get_body
from ephem.forced.precession_nutation import cached_model
from ephem.sun.ladder import Ladder
from ephem.theory import cost

J2000 = 2451545.0
YEAR = 365.25
#: prices are sums of the same doubles: their differences agree to rounding (relative 1e-12 of a few ms)
REL = 1e-9


def jd(year: float) -> float:
    return J2000 + (year - 2000.0) * YEAR


@pytest.mark.parametrize("first, last, sides", [(-50, 50, 2), (0, 50, 1), (-50, 0, 1), (30, 40, 1), (-40, -30, 1),
                                                 (0, 0, 1)])
def test_pole_epoch_sides(first, last, sides):
    """Years from the epoch: a span across it reaches two sides; one that starts or ends at it, or lies on one side,
    one (the side the fixed units were measured on)."""
    assert cost.pole_epoch_sides(0.0, float(first), float(last)) == sides


def _mean_track_integrations(theory, t, monkeypatch) -> int:
    """How many DOP853 integrations SecondOrderTheory.mean_track runs for the epochs ``t``."""
    import scipy.integrate
    calls = []
    real = scipy.integrate.solve_ivp
    monkeypatch.setattr(scipy.integrate, "solve_ivp", lambda *a, **k: calls.append(1) or real(*a, **k))
    theory.mean_track(t)
    monkeypatch.setattr(scipy.integrate, "solve_ivp", real)
    return len(calls)


@pytest.mark.parametrize("body, rung", [(body, rung) for body in ("mars", "itokawa", "steins")
                                        for rung in ("second_order", "numerical")] + [("mars", "nonrigid")])
def test_a_span_across_the_pole_epoch_prices_the_mean_track_on_each_side(body, rung, monkeypatch):
    """The rungs that read the second-order mean track (nonrigid: Mars, the body with an interior) pay
    ``second_order_side_s`` for each integration beyond the one a one-sided span of the same epochs takes, as many
    as mean_track runs."""
    b = get_body(body)
    ladder = Ladder(b)
    count = 1000
    # both 20 years from the pole epoch in all (the numerical rungs' orbits, counted on both sides, alike)
    across, one_side = np.linspace(jd(1990), jd(2010), count), np.linspace(jd(2000), jd(2020), count)
    runs_across = _mean_track_integrations(ladder.theory, across, monkeypatch)
    runs_one = _mean_track_integrations(ladder.theory, one_side, monkeypatch)
    assert (runs_across, runs_one) == (2, 1)
    extra = ladder.price(rung, across[0], across[-1], count).cpu_s - ladder.price(rung, one_side[0], one_side[-1],
                                                                                  count).cpu_s
    assert extra == pytest.approx((runs_across - runs_one) * cost.unit("second_order_side_s"), rel=REL)


@pytest.mark.parametrize("body", ["mars", "itokawa", "eros"])
def test_a_span_across_the_pole_epoch_prices_the_rotation_averaging_on_each_side(body, monkeypatch):
    """The estimates pay ``estimates_averaging_side_s`` for each side of the pole epoch beyond the first on which
    rotation_averaging_bound bounds the epochs (its calls of error_terms, counted), the samples apart (spans of more
    than 20 orbits a side, which it does not sample)."""
    from ephem.forced import physics_errors, rotation_scale
    b = get_body(body)
    m = cached_model(b)
    count = 10
    # each side over 20 orbits from the pole epoch: no samples, the fixed work alone
    years = 21.0 * 2 * math.pi / m.mean_motion / YEAR
    across = np.linspace(J2000 - years * YEAR, J2000 + years * YEAR, count)
    one_side = np.linspace(J2000 + years * YEAR, J2000 + 2 * years * YEAR, count)
    for t in (across, one_side):
        assert physics_errors.rotation_averaging_samples(b, t[0], t[-1]) == 0
    calls = []
    real = physics_errors.error_terms
    monkeypatch.setattr(physics_errors, "error_terms", lambda *a, **k: calls.append(1) or real(*a, **k))
    physics_errors.rotation_averaging_bound(b, m, across)
    sides_across = len(calls)
    calls.clear()
    physics_errors.rotation_averaging_bound(b, m, one_side)
    sides_one = len(calls)
    assert (sides_across, sides_one) == (2, 1)
    assert physics_errors.rotation_averaging_sides(b, across[0], across[-1]) == sides_across
    assert physics_errors.rotation_averaging_sides(b, one_side[0], one_side[-1]) == sides_one
    ladder = Ladder(b)
    extra = ladder.price(None, across[0], across[-1], count).cpu_s - ladder.price(None, one_side[0], one_side[-1],
                                                                                  count).cpu_s
    assert extra == pytest.approx((sides_across - sides_one) * cost.unit("estimates_averaging_side_s"), rel=REL)
    assert rotation_scale.MAX_SAMPLED_ORBITS < 21.0


@pytest.mark.parametrize("body", ["steins", "itokawa"])
def test_a_span_across_the_spin_epoch_prices_the_long_term_integration_on_each_side(body, monkeypatch):
    """The long-term model's history pays ``spin_history_side_s`` for each side of the spin's epoch beyond the
    first that averaged_spin.integrate integrates (its splitting's sides, counted), over spans of the same length."""
    from ephem.families import theory_for
    from ephem.longterm import averaged_spin, history
    b = get_body(body)
    spin = theory_for(b, b.perturbers).secular_spin()
    t0 = spin.epoch_years
    spans = {"across": (t0 - 50.0, t0 + 50.0), "one side": (t0 + 30.0, t0 + 130.0)}
    sides = {}
    real = averaged_spin._split_side
    for name, (lo, hi) in spans.items():
        calls = []
        monkeypatch.setattr(averaged_spin, "_split_side", lambda *a, **k: calls.append(1) or real(*a, **k))
        years = np.linspace(lo, hi, 11)
        orbit = history.default_orbit(b, spin.orbit_body, lo, hi).orbit
        averaged_spin.integrate(spin, orbit, years, method="splitting")
        sides[name] = len(calls)
    assert (sides["across"], sides["one side"]) == (2, 1)
    lo, hi = spans["across"]
    choice = history.default_orbit(b, spin.orbit_body, lo, hi)
    across = history.history_cost(spin, choice, lo, hi, 11).cpu_s
    # the same span length on one side (the per-year work alike), the same orbit model's price
    one = history.history_cost(spin, choice, t0, t0 + 100.0, 11).cpu_s
    assert across - one == pytest.approx((sides["across"] - sides["one side"]) * cost.unit("spin_history_side_s"),
                                         rel=REL)
