"""The request budget (ephem.base.budget) in the library, with no service: the estimate is charged before the work
and the charges sum to it; the deadline stops a long computation at its next checkpoint. Moved from
tests/service/test_bounded_work.py (issue 43: the tests mirror the packages)."""
from __future__ import annotations

import pytest

from ephem import api
from ephem.base import budget
from ephem.base.budget import DeadlineExceededError, OverBudgetError
from ephem.bodies.catalogue import Body, Orbit, Pole


def test_the_budget_is_charged_before_the_work_and_sums_the_parts():
    b = Body("x", Orbit(2.36, 0.5, 7.0, 0.0, 0.0, 0.0, 2451545.0), Pole(10.0, 20.0), 5.0, dynamical_ellipticity=0.1)
    c = api.answer_cost(b, order=None, nutation=True)
    assert c.cpu_s > 0 and c.memory_mb > 0
    with budget.budget(cpu_s=c.cpu_s * 0.5, memory_mb=1e6):
        with pytest.raises(OverBudgetError) as info:
            api.nutation(b)
    assert info.value.field == "orbit.e"
    with budget.budget(cpu_s=c.cpu_s * 1.01, memory_mb=1e6) as spent:
        api.nutation(b)
        assert spent.spent_cpu_s == pytest.approx(c.cpu_s, rel=1e-12)   # the same sum, summed again
    # outside a budget (the library, the CLI) nothing is refused
    assert api.nutation(b)["terms"]


def test_the_deadline_stops_an_integration_in_its_loop():
    b = Body("x", Orbit(2.36, 0.3, 7.0, 0.0, 0.0, 0.0, 2451545.0), Pole(10.0, 20.0), 5.0, dynamical_ellipticity=0.1)
    with budget.budget(cpu_s=1e9, memory_mb=1e9, deadline_s=0.0):
        with pytest.raises(DeadlineExceededError):
            api.track(b, 2451545.0, 2451545.0 + 3650.0, 10.0, model="numerical")
