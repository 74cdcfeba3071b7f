"""Schemathesis (v4) against the ASGI app in-process (no network), every check on.

Each operation runs schemathesis's examples, coverage and fuzzing phases with positive and negative
data. EPHEM_SCHEMATHESIS_EXAMPLES sets the fuzzing examples per operation (default 20: a few seconds
per operation on the 2-core CI machine); before a release, run

    EPHEM_SCHEMATHESIS_EXAMPLES=300 pytest -n0 tests/service/test_schemathesis.py

(EPHEM_SCHEMATHESIS_SEED replays a run). The service is built with a small track cap
(max_track_samples) so that a generated track answers in milliseconds; the cap is a setting the
document states, so the contract tested is the deployed one.

One check is sharpened rather than taken as is: schemathesis's positive_data_acceptance wants every
schema-valid request answered 2xx. Some rules cannot be written in JSON Schema (stop after start, a
real calendar day, tolerance_mas or order, the physics of the body: "not applicable"), so the
service's OpenAPI document states them in each operation's description (service.openapi_rules.OPERATION_RULES).
A schema-valid request may be refused with 422 only for one of those stated rules: the check below
maps each refusal's reason to its rule and fails when the operation does not state it.
"""
import json
import os
import re

import schemathesis
from hypothesis import HealthCheck, settings
from schemathesis.checks import positive_data_acceptance
from schemathesis.config import SchemathesisConfig

from service.app import create_app
from service.openapi_rules import OPERATION_RULES
from service.problems import PROBLEM, TYPE_BASE
from service.settings import Settings

EXAMPLES = int(os.environ.get("EPHEM_SCHEMATHESIS_EXAMPLES", "20"))
SEED = os.environ.get("EPHEM_SCHEMATHESIS_SEED")

app = create_app(Settings(max_track_samples=2_000, warm_up=False))
config = SchemathesisConfig.from_dict({"generation": {"max-examples": EXAMPLES},
                                       **({"seed": int(SEED)} if SEED else {})})
schema = schemathesis.openapi.from_asgi("/openapi.json", app, config=config)

#: a refusal's reason -> the rule (a key of service.app's rule texts) that states it
REASON_RULES = [
    (r"stop \(JD .*\) is before start \(JD", {"grid", "plot"}),
    (r"samples exceed the cap of", {"grid", "plot"}),
    (r"day \d+ is not 1 to \d+ \(", {"times"}),
    (r"UT1 is supported from .* through", {"times"}),
    (r"give either order or tolerance_mas, not both", {"tolerance", "tolerance_model"}),
    (r"give a tolerance, or a model and order, not both", {"tolerance_model"}),
    (r"the 'series' model needs an e-order|an e-order applies to the 'series' model", {"tolerance_model"}),
    (r"exceeds the Laplace limit", {"laplace"}),
    (r"is listed twice", {"perturbers"}),
    (r"an amplitude cut applies to the lunisolar series|give either cut_mas or tolerance_mas", {"cut"}),
    (r"give the wobble's phase|the free wobble moves the figure axis", {"wobble"}),
    (r"give the wobble amplitude J", {"wobble", "free_motion", "plot"}),
    (r"are not combined: give the rotation phase or the wobble's phase|does not model the rotation scale",
     {"wobble"}),
    (r"A = B = C|needs the three principal moments", {"free_motion"}),
    (r"stop equals start|applies to the track kinds|applies to kind free-wobble|aliases the free wobble|"
     r"leaves a single epoch|cannot be drawn within", {"plot"}),
    (r"principal moments must satisfy A <= B <= C|exceeds A\+B|give the principal moments", {"user"}),
    (r"the pericentre a\(1 - e\) = .* lies inside the|lies beyond the .* Hill sphere", {"user"}),
    (r"must be after start|exceeds 2e\+07 years|epochs over \[|epochs exceed the cap of|"
     r"give either an orbit model or a tolerance|must be positive|leaves a single epoch", {"history"}),
    (r"is finer than float64 Julian dates resolve|is within rounding of what float64 Julian dates",
     {"grid", "plot"}),
    (r"a plot needs a time span float64 Julian dates resolve", {"plot"}),
    (r"is finer than float64 years from J2000.0 resolve|is within rounding of what float64 years",
     {"history", "batch"}),
    (r"given \d+ times in one object of the JSON body", {"user", "batch"}),
    (r"expected \{start_year, stop_year, step_years\}|start_year < stop_year and step_years|rows is more than|"
     r"unknown column|no rows: give|expected a list of objects|^not JSON|^not CSV", {"batch"}),
]


def _stated(operation, rules: set[str]) -> bool:
    return bool(rules & set(OPERATION_RULES.get((operation.path, operation.method.lower()), ())))


def _refusal_is_a_stated_rule(case, response) -> str | None:
    """None when a 422 refuses a schema-valid request for a rule its operation states; else why not."""
    if response.headers.get("content-type", [""])[0] != PROBLEM:
        return "not a problem+json answer"
    problem = json.loads(response.content)
    if problem["type"] == TYPE_BASE + "not-applicable":
        return None if _stated(case.operation, {"na"}) else "the operation does not state when it is not applicable"
    if problem["type"] == TYPE_BASE + "over-budget":    # stated for every operation with rules, when budgeted
        description = schema.raw_schema["paths"][case.operation.path][case.operation.method.lower()]["description"]
        return None if "422 over-budget" in description else "the operation does not state its budget"
    reasons = [e["reason"] for e in problem.get("errors") or []] or [problem["detail"]]
    for reason in reasons:
        rules = set().union(*(r for pattern, r in REASON_RULES if re.search(pattern, reason)))
        if not rules or not _stated(case.operation, rules):
            return f"refused for a rule the operation does not state: {reason!r}"
    return None


@schemathesis.check
def positive_data_acceptance_with_stated_rules(ctx, response, case):
    """schemathesis's positive_data_acceptance, which also lets a 422 through for a rule the operation states."""
    try:
        return positive_data_acceptance(ctx, response, case)
    except AssertionError:
        if response.status_code != 422:
            raise
        why = _refusal_is_a_stated_rule(case, response)
        if why is not None:
            raise AssertionError(f"schema-valid request refused: {why}\n{response.content[:600]!r}") from None
        return None


@schema.parametrize()
@settings(max_examples=EXAMPLES, deadline=None, suppress_health_check=list(HealthCheck))
def test_openapi_contract(case):
    case.call_and_validate(excluded_checks=[positive_data_acceptance],
                           additional_checks=[positive_data_acceptance_with_stated_rules])


def _refusal(path, method, problem):
    from types import SimpleNamespace

    case = SimpleNamespace(operation=SimpleNamespace(path=path, method=method))
    response = SimpleNamespace(headers={"content-type": [PROBLEM]}, content=json.dumps(problem).encode())
    return _refusal_is_a_stated_rule(case, response)


def test_the_sharpened_check_lets_through_only_stated_rules():
    invalid = {"type": TYPE_BASE + "invalid-input", "title": "Invalid input", "status": 422}
    track = "/v1/bodies/{body}/track"
    stop = dict(invalid, detail="stop: ...", errors=[{"field": "stop", "reason": "stop (JD 1.0) is before start (JD 2.0)"}])
    assert _refusal(track, "GET", stop) is None
    assert "does not state" in _refusal("/v1/bodies/{body}/precession", "GET", stop)       # not its rule
    typed = dict(invalid, detail="order: ...", errors=[{"field": "order", "reason": "Input should be a valid integer"}])
    assert "does not state" in _refusal(track, "GET", typed)                               # a schema mismatch
    na = {"type": TYPE_BASE + "not-applicable", "title": "Not applicable", "status": 422, "detail": "..."}
    assert _refusal(track, "GET", na) is None
    assert "not applicable" in _refusal("/v1/bodies/{body}", "GET", na)
