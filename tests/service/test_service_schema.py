"""The OpenAPI document states what the service does: its problem+json errors, and the rules it enforces.

The contract run itself (schemathesis, every check, against the app in-process) is
tests/service/test_schemathesis.py; this file checks the document's parts that run relies on.
"""
import copy
import re

import pytest
from fastapi.testclient import TestClient
from hypothesis import given, settings, strategies as st

from ephem.bodies.catalogue import get_body, resolve_perturbers
from ephem.base.constants import JD_RANGE
from ephem.base.errors import InvalidInputError, NotApplicableError
from ephem.base.times import TIME_PATTERN, TIME_PATTERN_ECMA, to_jd_tdb, ut1_span
from service.app import create_app
from service.openapi_rules import BODY_RULES, OPERATION_RULES, PARAMETER_RULES, PERTURBERS_PATTERN
from service.problems import PROBLEM
from service.settings import Settings

app = create_app(Settings(warm_up=False))
SPEC = app.openapi()
OPERATIONS = [(path, method, op) for path, item in SPEC["paths"].items() for method, op in item.items()]


@pytest.fixture(scope="module")
def client():
    with TestClient(app) as c:
        yield c


def test_the_problem_schema_describes_rfc_9457_problems():
    problem = SPEC["components"]["schemas"]["Problem"]
    assert {"type", "title", "status", "detail"} <= set(problem["required"])
    assert {"errors", "known_bodies", "reason"} <= set(problem["properties"])
    field_error = SPEC["components"]["schemas"]["FieldError"]
    assert set(field_error["required"]) == {"field", "reason"}
    assert "HTTPValidationError" not in SPEC["components"]["schemas"]   # FastAPI's shape is never sent


@pytest.mark.parametrize("path, method, op", OPERATIONS, ids=[f"{m.upper()} {p}" for p, m, _ in OPERATIONS])
def test_every_error_response_is_documented_as_problem_json(path, method, op):
    responses = op["responses"]
    errors = {int(code) for code in responses if code[0] in "45"}
    expected = {500} | ({422, 503} if op.get("parameters") or op.get("requestBody") else set()) \
        | ({404} if "{body}" in path else set()) | ({400, 413} if op.get("requestBody") else set())
    assert expected <= errors, (path, method, sorted(errors))
    for code in errors:
        content = responses[str(code)]["content"]
        assert list(content) == [PROBLEM], (path, code)
        assert content[PROBLEM]["schema"] == {"$ref": "#/components/schemas/Problem"}
        assert responses[str(code)]["description"]


def test_an_error_answer_matches_the_problem_schema(client):
    from jsonschema_rs import Draft202012Validator      # schemathesis's validator

    schema = {**SPEC["components"]["schemas"]["Problem"], "$defs": SPEC["components"]["schemas"]}
    schema = _resolve_refs(schema)
    for r in (client.get("/v1/bodies/pallas"), client.get("/v1/bodies/moon/precession?perturbers=sun"),
              client.get("/v1/bodies/vesta/track?start=x&stop=y&step_days=1"), client.delete("/healthz"),
              client.post("/v1/precession-nutation", json={"orbit": {}})):
        assert r.headers["content-type"] == PROBLEM
        Draft202012Validator(schema).validate(r.json())


def _resolve_refs(node):
    if isinstance(node, dict):
        return {k: _resolve_refs(v) for k, v in node.items() if k != "$defs"} if "$ref" not in node else \
            _resolve_refs(SPEC["components"]["schemas"][node["$ref"].rsplit("/", 1)[1]])
    if isinstance(node, list):
        return [_resolve_refs(v) for v in node]
    return node


def test_every_rule_is_stated_where_it_applies():
    for (path, method), keys in OPERATION_RULES.items():
        description = SPEC["paths"][path][method]["description"]
        assert "**Rules**" in description and keys
        for param in SPEC["paths"][path][method].get("parameters", []):
            for key, value in PARAMETER_RULES.get(param["name"], {}).items():
                schema = param["schema"]
                assert any(b.get(key) == value for b in schema.get("anyOf", [schema])), (path, param["name"], key)
    lo, hi = ut1_span()
    assert f"UT1 is accepted from {lo} through {hi}" in SPEC["paths"]["/v1/bodies/{body}/track"]["get"]["description"]
    components = SPEC["components"]["schemas"]
    for (component, field), rules in BODY_RULES.items():
        prop = components[component]["properties"][field]
        for key, value in rules.items():
            assert any(b.get(key) == value for b in prop.get("anyOf", [prop])), (component, field, key)


# ---- the time grammar: the document's pattern is the parser's, so the two cannot disagree

def test_the_documented_time_pattern_is_the_parsers():
    assert JD_RANGE == (0.0, 1e7)      # the pattern's Julian dates (up to 7 digits, not 0) are written for it
    assert TIME_PATTERN_ECMA == re.sub(r"\(\?P<[a-z]+>", "(", TIME_PATTERN)
    assert "(?P<" not in TIME_PATTERN_ECMA and "\\d" not in TIME_PATTERN_ECMA and "\\s" not in TIME_PATTERN_ECMA


@pytest.mark.parametrize("text", ["2020-01-01", "2020-1-1", "2020-01-01T12:00", "2020-01-01 12:00:30.25",
                                  "2020-01-01T12:00:00Z", "2020-01-01T12:00 TDB", "2020-01-01 tt", "2020-01-01 UT1",
                                  "2451545.0", "2451545", "JD2451545.0", "jd 2451545.5", " 2451545 ", ".5"])
def test_the_accepted_forms_match_the_pattern_and_parse(text):
    assert re.fullmatch(TIME_PATTERN_ECMA, text)
    assert 0 < to_jd_tdb(text) < 1e7


@pytest.mark.parametrize("text", ["2020-13-01", "2020-01-01T24:00", "2020-01-01T12:00+01:00", "1e6", "-5", "0",
                                  "10000000", "2451545 TT", "2020-01-01 XYZ", "2020-01-01T12", "\t2020-01-01",
                                  "2020-01-01T00:00Z TDB", "yesterday", "", "２０２０-01-01"])
def test_texts_outside_the_pattern_are_refused(text):
    assert not re.fullmatch(TIME_PATTERN_ECMA, text)
    with pytest.raises(InvalidInputError):
        to_jd_tdb(text, "start")


STATED = re.compile(r"day \d+ is not 1 to \d+ \(|UT1 is supported from")


@settings(max_examples=300)
@given(st.from_regex(TIME_PATTERN_ECMA, fullmatch=True))
def test_a_text_the_pattern_admits_parses_or_breaks_a_stated_rule(text):
    try:
        assert 0 < to_jd_tdb(text, "start") < 1e7
    except InvalidInputError as e:
        assert STATED.search(e.reason), (text, e.reason)


@settings(max_examples=300)
@given(st.text(max_size=40))
def test_a_text_the_pattern_refuses_is_refused(text):
    if re.fullmatch(TIME_PATTERN_ECMA, text):
        return
    with pytest.raises(InvalidInputError):
        to_jd_tdb(text, "start")


@settings(max_examples=200)
@given(st.one_of(st.from_regex(PERTURBERS_PATTERN, fullmatch=True), st.text(max_size=30)))
def test_the_perturbers_pattern_is_what_the_library_takes(text):
    earth = get_body("earth")
    names = [n.strip().lower() for n in text.split(",")]
    try:
        resolve_perturbers(text, earth)
    except InvalidInputError as e:      # a name it does not know, or one given twice (a stated rule)
        assert not re.fullmatch(PERTURBERS_PATTERN, text) or len(set(names)) < len(names), (text, str(e))
    except NotApplicableError:          # a known name the theory cannot take for this body (stated): well formed
        assert re.fullmatch(PERTURBERS_PATTERN, text), text
    else:
        assert re.fullmatch(PERTURBERS_PATTERN, text), text


# ---- the POST body's constraints: the document's bounds are the service's

USER = {"orbit": {"a_au": 2.36, "e": 0.089, "i_deg": 7.14, "node_deg": 103.7, "peri_deg": 151.7,
                  "mean_anomaly_deg": 169.2, "epoch_jd_tdb": 2460200.5},
        "pole": {"ra_deg": 309.03, "dec_deg": 42.23}, "rotation_period_hours": 5.342,
        "moments": {"A": 0.3433, "B": 0.3546, "C": 0.42},
        "track": {"start": "2020-01-01", "stop": "2020-03-01", "step_days": 30}}


@pytest.mark.parametrize("section, field, value", [
    ("orbit", "a_au", 0.0), ("orbit", "e", 1.0), ("orbit", "e", -0.01), ("orbit", "i_deg", 180.5),
    ("orbit", "i_deg", -1.0), ("pole", "dec_deg", 90.5), ("moments", "A", 0.0),
    (None, "rotation_period_hours", 5e-5), ("orbit", "epoch_jd_tdb", 0.0), ("pole", "epoch_jd_tdb", 1e7),
    ("track", "step_days", 0.0), ("track", "start", 0.0), ("track", "stop", 1e7), ("track", "start", "2020-01-01Q"),
])
def test_a_value_outside_a_documented_bound_is_refused_naming_the_field(client, section, field, value):
    body = copy.deepcopy(USER)
    (body[section] if section else body)[field] = value
    r = client.post("/v1/precession-nutation", json=body)
    assert r.status_code == 422, r.text
    assert [e["field"] for e in r.json()["errors"]] == [f"{section}.{field}" if section else field]


@pytest.mark.parametrize("patch", [{"dynamical_ellipticity": 0.0}, {"dynamical_ellipticity": 0.51},
                                   {"moments": None}])
def test_dynamical_ellipticity_bounds_and_the_moments_or_ellipticity_rule(client, patch):
    body = dict(copy.deepcopy(USER), **patch)
    if patch.get("moments", 1) is not None:
        body.pop("moments")
    r = client.post("/v1/precession-nutation", json=body)
    assert r.status_code == 422, r.text
    assert r.json()["errors"][0]["field"] in ("dynamical_ellipticity", "moments")


def test_the_service_takes_its_names_from_the_library():
    """One source of names: a model added to ephem.families, a dataset to data/catalogue, an axis to the
    ladder, or a higher e-order to ephem.forced.precession_nutation is what the service accepts and documents."""
    from ephem.bodies.datasets import available_datasets
    from ephem.base.constants import AXES
    from ephem.forced.precession_nutation import MAX_ORDER
    from ephem.families import MODELS
    from service.app import Axis, Dataset, Rung

    assert [r.value for r in Rung] == list(MODELS)
    assert [a.value for a in Axis] == list(AXES)
    assert [d.value for d in Dataset] == list(available_datasets())
    schema = app.openapi()
    track_in = schema["components"]["schemas"]["UserBody"]["properties"]["order"]
    bounds = [s.get("maximum") for s in track_in.get("anyOf", [track_in]) if "maximum" in s]
    assert bounds == [MAX_ORDER]
    model_out = schema["components"]["schemas"]["ModelInfo"]["properties"]["name"]
    assert model_out["enum"] == list(MODELS)
