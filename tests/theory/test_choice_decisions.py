"""Every decision a tolerance makes beside the track's model (issue 43) is ephem.theory.choice.decide over the
family's own priced candidates: the Sun's e-order of the rate and the nutation terms, the amplitude cut of the Earth's
and the Moon's nutation terms. Over their real candidates, each bound made here for all of them: the candidate chosen
meets the tolerance, no eligible candidate is priced cheaper beyond the tie, none tied with it is bounded tighter,
none is chosen when none meets it, and no bound dearer than the tie is made. (The track's model: test_choice.py;
a history's orbit model: tests/longterm/test_history_choice.py.)"""
import math

import numpy as np
import pytest

from ephem.base.constants import MAS
from ephem.bodies.catalogue import get_body
from ephem.earth.estimates import cut_candidates as earth_cuts, cut_for_tolerance as earth_cut
from ephem.earth.model import lunisolar_earth
from ephem.families import theory_for
from ephem.moon.family import cut_candidates as moon_cuts
from ephem.orbit.lunar import MIN_CUT_MAS
from ephem.theory.choice import SAME_ESTIMATE, Candidates, Decision, cheapest, decide

#: tolerances, mas: from below every candidate's reach to above all of them
TOLERANCES_MAS = (1e-4, 3e-3, 0.05, 0.7, 9.0, 120.0, 2e3, 4e4, 1e6)


def _sun(name: str):
    return theory_for(get_body(name), ("Sun",)).inner


def _moon_series():
    return theory_for(get_body("Moon"), ("Earth", "Sun")).inner.model.series


def _all_bounds(c: Candidates) -> list:
    return list(c.bound) if isinstance(c.bound, np.ndarray) else [c.bound(i) for i in range(len(c.values))]


def _check(c: Candidates, tolerance: float, d: Decision | None = None) -> None:
    """The decision's properties (``d``, else :func:`decide`'s), against every candidate's bound made here."""
    bounds = _all_bounds(c)
    costs = [None if x is None or (isinstance(x, float) and math.isnan(x)) else float(x) for x in c.costs]
    eligible = [i for i, (b, k) in enumerate(zip(bounds, costs)) if k is not None and b is not None and b <= tolerance]
    d = decide(c, tolerance) if d is None else d
    if not eligible:
        assert d.best is None
        return
    best = d.best
    assert best in eligible, "the chosen candidate meets the tolerance"
    cheapest_cost = min(costs[i] for i in eligible)
    assert costs[best] <= cheapest_cost * (1.0 + c.tie), "no eligible candidate is priced cheaper beyond the tie"
    tied = [i for i in eligible if costs[i] <= cheapest_cost * (1.0 + c.tie)]
    assert all(bounds[best] <= bounds[i] * (1.0 + SAME_ESTIMATE) for i in tied), "a tie goes to the tighter bound"
    if not isinstance(c.bound, np.ndarray):     # no dearer candidate's bound made
        assert all(costs[i] <= cheapest_cost * (1.0 + c.tie) or bounds[i] is None or bounds[i] > tolerance
                   or i not in d.bounds for i in range(len(costs)))
        assert all(costs[i] <= costs[d.first] * (1.0 + c.tie) for i in d.bounds)


@pytest.mark.parametrize("name", ["Ceres", "Vesta", "Eros", "Steins", "Itokawa", "Mars"])
@pytest.mark.parametrize("tolerance_mas", TOLERANCES_MAS)
def test_the_suns_e_order(name, tolerance_mas):
    family = _sun(name)
    c = family.order_candidates()
    _check(c, tolerance_mas * MAS)
    # the answer's order is the decision's: the lowest e-order within the tolerance, else the exact coefficients
    order = family.order_for_tolerance(tolerance_mas * MAS, None)
    within = [n for n, b in zip(c.values, _all_bounds(c)) if n is not None and b <= tolerance_mas * MAS]
    assert order == (min(within) if within else None)


@pytest.mark.parametrize("tolerance_mas", TOLERANCES_MAS)
def test_the_earths_cut(tolerance_mas):
    c = earth_cuts(lunisolar_earth(get_body("Earth")))
    _check(c, tolerance_mas * MAS)
    # the array decision and the one made candidate by candidate agree
    lazy = Candidates(c.values, list(c.costs), lambda i: float(c.bound[i]), tie=c.tie)
    assert decide(lazy, tolerance_mas * MAS).best == decide(c, tolerance_mas * MAS).best
    if tolerance_mas >= 1.0:        # above the smallest cut served's omitted terms: the answer's cut is the decision's
        assert earth_cut(lunisolar_earth(get_body("Earth")), tolerance_mas * MAS) == pytest.approx(
            max(cheapest(c, tolerance_mas * MAS), MIN_CUT_MAS), rel=1e-12)


@pytest.mark.parametrize("tolerance_mas", TOLERANCES_MAS)
def test_the_moons_cut(tolerance_mas):
    c = moon_cuts(_moon_series())
    _check(c, tolerance_mas * MAS)


def test_the_checks_fail_on_a_decision_for_a_dearer_candidate():
    """The property checks can fail: a rule that took the most accurate eligible candidate breaks them."""
    c = Candidates(["a", "b", "c"], [1.0, 2.0, 3.0], np.array([5.0, 2.0, 1.0]), tie=0.0)
    assert cheapest(c, 6.0) == "a" and cheapest(c, 2.5) == "b" and cheapest(c, 0.5) is None
    _check(c, 6.0)
    with pytest.raises(AssertionError, match="priced cheaper"):
        _check(c, 6.0, Decision(2, 2, dict(enumerate(c.bound.tolist())), (0, 1, 2)))
    tied = Candidates(["a", "b"], [1.0, 1.005], lambda i: (5.0, 2.0)[i], tie=0.01)
    assert cheapest(tied, 6.0) == "b"           # within the tie: the tighter bound
    with pytest.raises(AssertionError, match="tighter bound"):
        _check(tied, 6.0, Decision(0, 0, {0: 5.0, 1: 2.0}, (0, 1)))
