"""The choice by tolerance (ephem.theory.choice, issue 39): the model predicted cheapest among those estimated within
the tolerance, on every family, never one predicted dearer than another eligible model; the long-term model's
estimate (a run of its history) is made only when the choice reaches it."""
import math

import pytest

from ephem import api
from ephem.base.budget import Cost, Part
from ephem.base.constants import MAS
from ephem.base.errors import NotApplicableError
from ephem.theory.choice import SAME_ESTIMATE, TIE, Deferred, choose
from ephem.theory.results import Estimate


def _cost(ms: float) -> Cost:
    return Cost((Part("step_days", "a test's work", ms / 1e3, 1.0),))


def _refuse(made):
    raise NotApplicableError("test", f"none within: {len(made)} estimates")


def test_the_cheapest_eligible_wins_and_dearer_deferred_ones_are_not_made():
    made = []

    def deferred(name, total):
        return Deferred(name, None, lambda: made.append(name) or Estimate(name, None, {"x": total * MAS}))

    plan = [Estimate("a", None, {"x": 500 * MAS}), Estimate("b", None, {"x": 90 * MAS}),
            deferred("c", 10.0), Estimate("d", None, {"x": 1 * MAS})]
    price = {"a": 1.0, "b": 3.0, "c": 2.0, "d": 50.0}
    got = choose(plan, lambda e: _cost(price[e.rung]), 100 * MAS, _refuse)
    assert got.chosen.rung == "c" and made == ["c"]         # c (2 ms) before b (3 ms): made, and within
    assert [k.eligible for k in got.candidates] == [False, True, True, True]
    assert "predicted cheapest" in got.reason and "a (500 mas)" in got.reason
    # beyond c's reach, the deferred model is never made
    made.clear()
    price["c"] = 10.0
    got = choose(plan, lambda e: _cost(price[e.rung]), 100 * MAS, _refuse)
    assert got.chosen.rung == "b" and made == [] and got.candidates[2].estimate is None
    assert "not run for an estimate: c" in got.reason


def test_ties_in_cost_go_to_the_more_accurate_and_none_within_refuses():
    plan = [Estimate("a", None, {"x": 90 * MAS}), Estimate("b", None, {"x": 20 * MAS}),
            Estimate("c", None, {"x": 5 * MAS})]
    price = {"a": 1.0, "b": 1.0 * (1.0 + TIE / 2), "c": 1.0 * (1.0 + 2 * TIE)}
    got = choose(plan, lambda e: _cost(price[e.rung]), 100 * MAS, _refuse)
    assert got.chosen.rung == "b" and "ties in predicted cost" in got.reason
    with pytest.raises(NotApplicableError, match="3 estimates"):
        choose(plan, lambda e: _cost(price[e.rung]), 1 * MAS, _refuse)


def test_a_refusal_makes_each_deferred_estimate_once():
    runs = []
    plan = [Estimate("a", None, {"x": 90 * MAS}),
            Deferred("b", None, lambda: runs.append("b") or Estimate("b", None, {"x": 50 * MAS}))]
    with pytest.raises(NotApplicableError, match="2 estimates"):
        choose(plan, lambda e: _cost(1.0 if e.rung == "a" else 2.0), 1 * MAS, _refuse)
    assert runs == ["b"]


def test_ceres_in_2040_at_100_mas_is_served_by_hansen():
    """The issue's example: series e^2 (62.7 mas) was chosen by a fixed order though hansen (61.1 mas) was predicted
    cheaper; now hansen, or a model predicted cheaper still and within the tolerance, answers."""
    ans = api.track("ceres", "2040-01-01", "2040-12-31", 10.0, tolerance_mas=100)
    m = ans["model"]
    assert m["name"] == "hansen" and m["estimated_error_mas"] <= 100
    eligible = m["choice"]["eligible"]
    chosen = next(c for c in eligible if c["chosen"])
    assert all(c["estimated_error_mas"] <= 100 for c in eligible)
    assert all(c["estimated_cpu_ms"] >= chosen["estimated_cpu_ms"] / (1 + TIE) for c in eligible)
    series2 = next(c for c in eligible if c["name"] == "series" and c["order"] == 2 and not c["rotation_scale"])
    # series e^2 sums 4 harmonics where hansen sums 12: over 37 epochs a tie (the kernel's set-up is most of both,
    # data/cost_model.toml), which the more accurate hansen wins
    assert series2["estimated_cpu_ms"] >= chosen["estimated_cpu_ms"] / (1 + TIE)
    assert series2["estimated_error_mas"] > chosen["estimated_error_mas"]


CASES = [(body, span, tol) for body in ("ceres", "vesta", "eros", "steins", "itokawa", "mars", "earth", "moon")
         for span, tol in (((2020.0, 2021.0), 10.0), ((2020.0, 2030.0), 300.0), ((2000.0, 2100.0), 3000.0),
                           ((1950.0, 2050.0), 30000.0))]


@pytest.mark.parametrize("body, span, tolerance", CASES)
def test_no_eligible_model_is_predicted_cheaper_than_the_chosen_one(body, span, tolerance):
    """Over bodies, spans and tolerances: the comparison's chosen model is the track's, it is within the tolerance,
    no eligible model is predicted cheaper beyond the tie band, and none in the band is more accurate; where none is
    within, both refuse."""
    start, stop = (f"{int(y)}-01-01" for y in span)
    step = (span[1] - span[0]) * 365.25 / 40
    table = api.track_models(body, start, stop, step, tolerance_mas=tolerance)
    eligible = [m for m in table["models"] if m["eligible"]]
    try:
        ans = api.track(body, start, stop, step, tolerance_mas=tolerance)
    except NotApplicableError:
        assert table["chosen"] is None and not eligible
        return
    (chosen,) = [m for m in table["models"] if m["chosen"]]
    got = ans["model"]
    assert (chosen["name"], chosen["order"]) == (got["name"], got["order"])
    assert chosen["estimated_error_mas"] == pytest.approx(got["estimated_error_mas"], rel=1e-12)
    assert chosen["estimated_error_mas"] <= tolerance
    cheapest = min(m["estimated_cpu_ms"] for m in eligible)
    assert chosen["estimated_cpu_ms"] <= cheapest * (1.0 + TIE)
    tied = [m for m in eligible if m["estimated_cpu_ms"] <= cheapest * (1.0 + TIE)]
    # the most accurate of the tie, estimates within SAME_ESTIMATE of each other counting as equal
    assert chosen["estimated_error_mas"] <= min(m["estimated_error_mas"] for m in tied) * (1.0 + SAME_ESTIMATE)
    assert math.isfinite(chosen["estimated_cpu_ms"]) and chosen["why"].startswith("chosen: ")


@pytest.mark.parametrize("nudge", [-1e-13, 1e-13])
def test_estimates_equal_but_for_their_last_bits_do_not_decide_a_tie(nudge):
    """Two e-orders past convergence have the same estimate but for bits a CPU's SIMD kernels move: the tie in cost
    then goes to the cheaper, whichever last bit is smaller (the choice must not flip on a last bit)."""
    total = 101.0 * MAS
    plan = [Estimate("a", None, {"x": total}), Estimate("b", None, {"x": total * (1.0 + nudge)})]
    price = {"a": 1.0, "b": 1.0 + TIE / 2}
    got = choose(plan, lambda e: _cost(price[e.rung]), 200 * MAS, _refuse)
    assert got.chosen.rung == "a"


def test_the_candidates_are_the_dataclass_built_in_one_go_and_equal_prices_keep_the_plans_order():
    """choose() sets each Candidate's fields in one go (choice._candidate): the same object the dataclass's own
    __init__ makes (equal, hashed alike, the same repr); and models of equal price are tried in the plan's order (the
    index breaks the tie), so the first of them within the tolerance is the one chosen."""
    from dataclasses import fields

    from ephem.theory.choice import Candidate

    plan = [Estimate("a", None, {"x": 500 * MAS}), Estimate("b", 2, {"x": 80 * MAS}),
            Estimate("c", None, {"x": 80 * MAS}), Estimate("d", None, {"x": 80 * MAS})]
    costs = [_cost(1.0), _cost(3.0), _cost(3.0), None]
    got = choose(plan, costs, 100 * MAS, _refuse)
    assert got.chosen is plan[1]
    for k, p, c in zip(got.candidates, plan, costs):
        ref = Candidate(p.rung, p.order, p.free_wobble, p.rotation_scale, p, c, p.total <= 100 * MAS)
        assert k == ref and hash(k) == hash(ref) and repr(k) == repr(ref)
        assert [getattr(k, f.name) for f in fields(Candidate)] == [getattr(ref, f.name) for f in fields(Candidate)]
