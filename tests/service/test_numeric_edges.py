"""Every route at the numeric edges of its inputs (issue 42): a 200 with finite numbers, or a 4xx problem naming the
field; never a 5xx, never NaN or infinity in an answer, never "nan" on a page.

The cases are generated from the service, as the route x media-type matrix (tests/service/test_route_matrix.py) is:

* the routes are the app's route list; each route that takes a number or a time is given a minimal valid request in
  :data:`BASELINES` (a route that takes none is listed in :data:`NO_NUMERIC_INPUT` with the reason), and a route in
  neither fails :func:`test_every_route_with_numeric_input_has_a_baseline`;
* the numeric parameters and their documented limits are read from the OpenAPI document (query parameters, and the
  fields of the JSON bodies through their schemas); the web page's routes, outside the document, take those of the API
  route they mirror (:data:`PAGE_TWINS`);
* each numeric parameter takes, one at a time in the baseline: 0, -0, the smallest subnormal (±5e-324), 1e-300,
  ±1e308, and each documented limit with the doubles just below and above it (an integer's neighbours);
* each time parameter takes JD and ISO forms at the edges (J2000 and the double after it, the ends of the supported
  range), and each span the cases of :data:`SPANS` (start = stop, stop one double after or before start, stop before
  start, the sample cap and one past it; for the histories :data:`YEAR_SPANS`, the issue's spans within a breath of
  J2000 among them).

The values are picked, not drawn (the same cases on every run) and deduplicated. The service is built with a small
track cap (2,000 epochs, a setting the document states) so that a valid edge answers in milliseconds; the whole file
runs in about a minute on one core.
"""
from __future__ import annotations

import csv
import dataclasses
import io
import json
import math
import re
from dataclasses import dataclass, field

import pytest
from fastapi.routing import APIRoute
from fastapi.testclient import TestClient
from starlette.routing import Mount

from service.app import create_app
from service.problems import PROBLEM, TYPE_BASE
from service.settings import Settings

CAP = 2_000
APP = create_app(Settings(warm_up=False, max_track_samples=CAP))
DOC = APP.openapi()
BODY = "vesta"
#: JD 2451545 (J2000) and the doubles either side of it: 2451545 +- 2^-31 d
J2000, ULP = 2451545.0, 2.0 ** -31


@pytest.fixture(scope="module")
def client():
    with TestClient(APP, raise_server_exceptions=False) as c:
        yield c


# ------------------------------------------------------------------ the baselines: a minimal valid request a route

TRACK = {"start": "2020-01-01", "stop": "2020-03-01", "step_days": "30"}
HISTORY = {"start_year": "-400", "stop_year": "0", "step_years": "200"}
PLOT = {"start": "2020-01-01", "stop": "2020-03-01", "step_days": "30", "dpi": "30"}
USER = {"name": "edge-asteroid",
        "orbit": {"a_au": 2.36, "e": 0.089, "i_deg": 7.14, "node_deg": 103.7, "peri_deg": 151.7,
                  "mean_anomaly_deg": 169.2, "epoch_jd_tdb": 2460200.5},
        "pole": {"ra_deg": 309.03, "dec_deg": 42.23, "epoch_jd_tdb": 2451545.0},
        "rotation_period_hours": 5.342, "moments": {"A": 0.3433, "B": 0.3546, "C": 0.42}}
USER_POST = {**USER, "track": {"start": "2020-01-01", "stop": "2020-03-01", "step_days": 30},
             "history": {"start_year": -400, "stop_year": 0, "step_years": 200}}
BATCH_ROW = {"name": "edge-asteroid", **USER["orbit"], "pole_ra_deg": 309.03, "pole_dec_deg": 42.23,
             "rotation_period_hours": 5.342, "moment_a": 0.3433, "moment_b": 0.3546, "moment_c": 0.42,
             "e_sigma": 0.001}
BATCH_POST = {"rows": [BATCH_ROW], "history": {"start_year": -400, "stop_year": 0, "step_years": 200}}


@dataclass(frozen=True)
class Baseline:
    query: dict = field(default_factory=dict)
    json: dict | None = None            # the JSON body
    form: dict | None = None            # a form (the page's batch: with a CSV file)


BASELINES = {
    ("GET", "/v1/bodies/{body}/precession"): Baseline(),
    ("GET", "/v1/bodies/{body}/nutation"): Baseline(),
    ("GET", "/v1/bodies/{body}/track"): Baseline(TRACK),
    ("GET", "/v1/bodies/{body}/track/models"): Baseline(TRACK),
    ("GET", "/v1/bodies/{body}/track/models.png"): Baseline({**TRACK, "dpi": "30"}),
    ("GET", "/v1/bodies/{body}/track/models.svg"): Baseline(TRACK),
    ("GET", "/v1/bodies/{body}/track.png"): Baseline(PLOT),
    ("GET", "/v1/bodies/{body}/track.svg"): Baseline({k: v for k, v in PLOT.items() if k != "dpi"}),
    ("GET", "/v1/bodies/{body}/history"): Baseline(HISTORY),
    ("GET", "/v1/bodies/{body}/history.png"): Baseline({**HISTORY, "dpi": "30"}),
    ("GET", "/v1/bodies/{body}/history.svg"): Baseline(HISTORY),
    ("GET", "/v1/bodies/{body}/free-motion"): Baseline({"start": "2020-01-01", "stop": "2020-01-03",
                                                         "step_days": "0.5", "J_arcsec": "10"}),
    ("POST", "/v1/batch"): Baseline(json=BATCH_POST),
    ("POST", "/v1/precession-nutation"): Baseline(json=USER_POST),
    ("GET", "/bodies/{body}/track"): Baseline(TRACK),
    ("GET", "/bodies/{body}/history"): Baseline(HISTORY),
    ("GET", "/my-body"): Baseline({"name": USER["name"], "rotation_period_hours": "5.342",
                                   **{f"{g}.{k}": str(v) for g in ("orbit", "pole", "moments")
                                      for k, v in USER[g].items()}}),
    ("POST", "/batch"): Baseline(form={"start_year": "-400", "stop_year": "0", "step_years": "200"}),
}
#: the web page's routes (outside the OpenAPI document) and the API operation whose parameters they take
PAGE_TWINS = {("GET", "/bodies/{body}/track"): ("get", "/v1/bodies/{body}/track"),
              ("GET", "/bodies/{body}/history"): ("get", "/v1/bodies/{body}/history"),
              ("GET", "/my-body"): ("post", "/v1/precession-nutation"),
              ("POST", "/batch"): ("post", "/v1/batch")}
#: routes without a number or a time among their inputs, and why
NO_NUMERIC_INPUT = {
    "/healthz": "liveness", "/v1/bodies": "the list", "/v1/bodies/{body}": "a body's record",
    "/openapi.json": "the document", "/docs": "Swagger UI", "/redoc": "ReDoc", "/docs/{name}": "a document",
    "/docs/{name}.md": "a document's source", "/redoc/redoc.standalone.js": "an asset", "/favicon.ico": "an asset",
    "/": "the index", "/bodies/{body}": "a body's page", "/batch": "the batch form (GET)",
    "/batch/template.csv": "the batch template", "/about": "the version, the citation and the sources",
}


# ------------------------------------------------------------------ the edges

def _resolve(schema: dict) -> dict:
    while "$ref" in schema:
        schema = DOC["components"]["schemas"][schema["$ref"].rsplit("/", 1)[-1]]
    return schema


def _numeric(schema: dict) -> dict | None:
    """The number or integer branch of a parameter's schema (through anyOf), or None."""
    schema = _resolve(schema)
    for branch in schema.get("anyOf", [schema]):
        branch = _resolve(branch)
        if branch.get("type") in ("number", "integer"):
            return branch
    return None


def _is_time(schema: dict) -> bool:
    schema = _resolve(schema)
    return any(_resolve(b).get("type") == "string" and "[Jj][Dd]" in _resolve(b).get("pattern", "")
               for b in schema.get("anyOf", [schema]))


COMMON = (0.0, -0.0, 5e-324, -5e-324, 1e-300, 1e308, -1e308)


def edge_values(schema: dict) -> list[str]:
    """The edge values of a numeric schema, as a client writes them (shortest repr), deduplicated in order."""
    values: list = list(COMMON)
    integer = schema.get("type") == "integer"
    for key in ("minimum", "maximum", "exclusiveMinimum", "exclusiveMaximum"):
        if key in schema:
            limit = schema[key]
            values += ([limit - 1, limit, limit + 1] if integer else
                       [math.nextafter(float(limit), -math.inf), float(limit), math.nextafter(float(limit), math.inf)])
    if integer:
        values += [1, -1, 10 ** 30]
    out: list[str] = []
    for v in values:
        text = str(v) if isinstance(v, int) else repr(float(v))
        if text not in out:
            out.append(text)
    return out


#: JD and ISO forms at the edges: J2000 and the double after it, the ends of the supported range (0, 1e7)
TIME_EDGES = ("JD2451545", f"JD{J2000 + ULP!r}", "JD0.0000001", "JD9999999.999999", "JD10000000",
              "2000-01-01T12:00:00 TDB", "2000-01-01T12:00:00.000001 TDB", "0001-01-01", "9999-12-31T23:59:59.999")
#: (start, stop, step_days or None for the baseline's): start = stop, one double apart, the issue's step, stop a
#: double before start, stop before start, a microsecond in ISO, the sample cap and one past it
SPANS = (("JD2451545", "JD2451545", None), ("2000-01-01T12:00:00 TDB", "2000-01-01T12:00:00 TDB", None),
         ("JD2451545", f"JD{J2000 + ULP!r}", repr(ULP)), ("JD2451545", f"JD{J2000 + 4 * ULP!r}", repr(ULP)),
         ("JD2451545", "JD2451545.000000001", "1e-12"), ("JD2451545", "JD2451545.000000001", "3e-10"),
         ("JD2451545", f"JD{J2000 - ULP!r}", None), ("2020-03-01", "2020-01-01", None),
         ("2020-01-01T00:00:00", "2020-01-01T00:00:00.000001", "1e-11"),
         ("2020-01-01", "2020-03-01", repr(60.0 / (CAP - 1))), ("2020-01-01", "2020-03-01", repr(60.0 / CAP)))
#: (start_year, stop_year, step_years or None): start = stop, the issue's spans within a breath of J2000, a subnormal
#: step, stop before start, the longest span (2e7 years) and the double past it
YEAR_SPANS = (("0", "0", "1"), ("-5e-324", "4.2e-90", "500"), ("-4.99e-210", "2.34e-145", None),
              ("0", "1e-322", "5e-324"), ("-1e-300", "1e-300", "1e-301"), ("1000", "1000.0000000001", "1e-14"),
              ("0", "-1", "1"), ("-1e7", "1e7", "2e6"), ("0", repr(math.nextafter(2e7, math.inf)), "2e6"))
#: the steps of the edges that cost real work (a track of CAP epochs, a history over 2e7 years: ~0.1-2.5 s each),
#: asked of the JSON routes only: the figures and the pages draw what those answer
HEAVY_STEPS = (repr(60.0 / (CAP - 1)), "2e6")
HEAVY_ROUTES = (("GET", "/v1/bodies/{body}/track"), ("GET", "/v1/bodies/{body}/history"),
                ("POST", "/v1/precession-nutation"), ("POST", "/v1/batch"))


@dataclass(frozen=True)
class Case:
    method: str
    path: str
    query: tuple = ()
    body: str | None = None             # the JSON text
    form: tuple = ()
    changed: tuple = ()                 # the inputs this case moved to an edge
    body_name: str = BODY               # the catalogue body of a route that names one

    @property
    def id(self) -> str:
        where = self.path.replace("{body}", self.body_name)
        return f"{self.method} {where} " + ",".join(f"{k}={v}" for k, v in self.changed)


def _set_path(doc: dict, path: str, value) -> dict:
    """A copy of ``doc`` with the dotted ``path`` set (made where absent)."""
    out = json.loads(json.dumps(doc))
    node = out
    *parents, last = path.split(".")
    for p in parents:
        node = node.setdefault(p, {})
    node[last] = value
    return out


def _json_value(text: str):
    return int(text) if re.fullmatch(r"-?\d+", text) else float(text)


def _body_fields(schema: dict, prefix: str = "") -> dict[str, dict]:
    """{dotted path: schema} of a JSON body schema's number, integer and time fields."""
    out = {}
    for name, sub in _resolve(schema).get("properties", {}).items():
        path = f"{prefix}{name}"
        number = _numeric(sub)
        if _is_time(sub):               # a time: ISO or JD text, or a JD number
            out[path] = {"time": True}
        elif number is not None:
            out[path] = number
        else:
            branches = [_resolve(b) for b in _resolve(sub).get("anyOf", [sub])]
            for b in branches:
                if b.get("properties"):
                    out.update(_body_fields(b, path + "."))
    return out


def _operation(method: str, path: str) -> dict | None:
    return DOC["paths"].get(path, {}).get(method.lower())


def numeric_inputs(method: str, path: str) -> dict[str, dict]:
    """{the input's name (a query parameter, or a JSON body's dotted path): its schema ({"time": True} for a time)}."""
    twin = PAGE_TWINS.get((method, path))
    op = _operation(*twin) if twin else _operation(method, path)
    if op is None:
        return {}
    out = {}
    for p in op.get("parameters", []):
        if p["in"] != "query":
            continue
        number = _numeric(p["schema"])
        if number is not None:
            out[p["name"]] = number
        elif _is_time(p["schema"]):
            out[p["name"]] = {"time": True}
    body = op.get("requestBody", {}).get("content", {}).get("application/json", {}).get("schema")
    if body is not None and "$ref" in body:
        out.update(_body_fields(body))
    if path == "/v1/batch" or twin == ("post", "/v1/batch"):     # its body's schema is open: the rows' columns
        if path == "/v1/batch":
            out.update({f"rows.{k}": {"type": "number"} for k, v in BATCH_ROW.items() if k != "name"})
            out.update({f"history.{k}": {"type": "number"} for k in BATCH_POST["history"]})
    if twin is not None and path != "/my-body":         # a page takes the API's query parameters it declares
        declared = {p.alias for r in APP.routes if isinstance(r, APIRoute) and r.path == path and method in r.methods
                    for p in list(r.dependant.query_params) + list(r.dependant.body_params)}
        out = {k: v for k, v in out.items() if k in declared}
    if path == "/my-body":                              # its form's fields are the body's, by their dotted paths
        out = {k: v for k, v in out.items() if not k.startswith(("track.", "history."))}
    return out


def _case(method: str, path: str, base: Baseline, changes: dict, inputs: dict) -> Case:
    query = dict(base.query)
    body = None
    form = dict(base.form or {})
    for k, v in changes.items():
        if base.json is not None and k not in _query_names(method, path):
            continue
        if base.form is not None:
            form[k] = v
        elif v is None:
            query.pop(k, None)
        else:
            query[k] = v
    if base.json is not None:
        doc = base.json
        for k, v in changes.items():
            if k in _query_names(method, path):
                continue
            if k.startswith("rows."):
                doc = {**doc, "rows": [_set_path(doc["rows"][0], k[5:], _json_value(v))]}
            else:
                doc = _set_path(doc, k, v if inputs.get(k, {}).get("time") else _json_value(v))
        body = json.dumps(doc)
    return Case(method, path, tuple(sorted(query.items())), body, tuple(sorted(form.items())),
                tuple((k, v) for k, v in changes.items()))


def _query_names(method: str, path: str) -> set[str]:
    op = _operation(method, path)
    return {p["name"] for p in op.get("parameters", []) if p["in"] == "query"} if op else set()


def _span_cases(method: str, path: str, base: Baseline, inputs: dict) -> list[dict]:
    out = []
    for prefix in ("", "track.", "history."):
        if f"{prefix}start" in inputs and f"{prefix}stop" in inputs:
            step = f"{prefix}step_days" if f"{prefix}step_days" in inputs else None
            for start, stop, step_value in SPANS:
                change = {f"{prefix}start": start, f"{prefix}stop": stop}
                if step and step_value is not None:
                    change[step] = step_value
                out.append(change)
        if f"{prefix}start_year" in inputs and f"{prefix}stop_year" in inputs:
            for start, stop, step_value in YEAR_SPANS:
                change = {f"{prefix}start_year": start, f"{prefix}stop_year": stop}
                if f"{prefix}step_years" in inputs:
                    change[f"{prefix}step_years"] = step_value if step_value is not None else "1e-146"
                out.append(change)
    return out


#: the spans of a track and of a history are asked of a body of every family too (the issue's track failed for seven
#: bodies, a track at a body's pole epoch among them): Ceres' pole epoch is J2000
FAMILY_BODIES = ("ceres", "itokawa", "eros", "earth", "moon", "mars")
SPAN_ROUTES = (("GET", "/v1/bodies/{body}/track"), ("GET", "/bodies/{body}/track"),
               ("GET", "/v1/bodies/{body}/history"))


def _cases() -> list[Case]:
    cases, seen = [], set()

    def add(case: Case) -> None:
        key = (case.method, case.path, case.query, case.body, case.form, case.body_name)
        if key not in seen:
            seen.add(key)
            cases.append(case)

    for (method, path), base in BASELINES.items():
        inputs = numeric_inputs(method, path)
        changes = []
        for name, schema in inputs.items():
            values = TIME_EDGES if schema.get("time") else edge_values(schema)
            changes += [{name: v} for v in values]
        spans = [s for s in _span_cases(method, path, base, inputs)
                 if (method, path) in HEAVY_ROUTES or not set(HEAVY_STEPS) & set(s.values())]
        for change in changes + spans:
            add(_case(method, path, base, change, inputs))
        if (method, path) in SPAN_ROUTES:
            for name in FAMILY_BODIES:
                for change in spans:
                    if not set(HEAVY_STEPS) & set(change.values()):     # one body is enough for those
                        add(dataclasses.replace(_case(method, path, base, change, inputs), body_name=name))
    return cases


CASES = _cases()


# ------------------------------------------------------------------ the routes are all here

def _served() -> list[tuple[str, str]]:
    out = []
    for r in APP.routes:
        if isinstance(r, Mount):
            continue                    # files: the static assets, the documents' charts
        out.extend((m, r.path) for m in sorted(getattr(r, "methods", ()) or ()) if m != "HEAD")
    return out


def test_every_route_with_numeric_input_has_a_baseline():
    missing = [(m, p) for m, p in _served()
               if (m, p) not in BASELINES and p not in NO_NUMERIC_INPUT
               and (numeric_inputs(m, p) or _operation(m, p) is None)]
    assert not missing, ("routes with no numeric-edge baseline (add one to BASELINES, or to NO_NUMERIC_INPUT): "
                         f"{missing}")
    for m, p in BASELINES:
        assert (m, p) in _served(), f"a baseline for a route the app does not serve: {m} {p}"
        assert numeric_inputs(m, p), f"{m} {p}: no numeric input found"


def test_the_cases_reach_every_numeric_parameter_and_stay_few():
    """Each numeric input of every baseline route is moved to its edges, and the cases stay within a minute."""
    for (method, path) in BASELINES:
        moved = {k for c in CASES if (c.method, c.path) == (method, path) for k, _ in c.changed}
        assert set(numeric_inputs(method, path)) <= moved, (method, path)
    assert 500 < len(CASES) < 2_500, len(CASES)


# ------------------------------------------------------------------ what an answer must be

NON_FINITE_TEXT = re.compile(r"(?i)(?<![\w.])[-+]?(nan|inf|infinity)(?![\w])")


def _finite_json(text: str):
    def refuse(constant):
        raise AssertionError(f"{constant} in a JSON answer")
    return json.loads(text, parse_constant=refuse)


def _names(case: Case) -> set[str]:
    names = {k for k, _ in case.query} | {k for k, _ in case.form}
    if case.body is not None:
        def walk(node, prefix=""):
            if isinstance(node, dict):
                for k, v in node.items():
                    names.add(prefix + k)
                    walk(v, prefix + k + ".")
            elif isinstance(node, list):
                for v in node:
                    walk(v, prefix)
        doc = json.loads(case.body)
        walk(doc)
        walk({"rows": doc.get("rows", [])} if isinstance(doc, dict) else {})
    return names


def _declared(method: str, path: str) -> set[str]:
    """Every input the operation (or the API operation a page mirrors) declares: its query parameters and its JSON
    body's fields by dotted path (a problem may name one the request left out: the wobble's J it needs)."""
    twin = PAGE_TWINS.get((method, path))
    op = _operation(*twin) if twin else _operation(method, path)
    if op is None:
        return set()
    names = {p["name"] for p in op.get("parameters", []) if p["in"] == "query"}

    def walk(schema, prefix=""):
        for name, sub in _resolve(schema).get("properties", {}).items():
            names.add(prefix + name)
            for b in [_resolve(x) for x in _resolve(sub).get("anyOf", [sub])]:
                walk(b, prefix + name + ".")
            if "items" in _resolve(sub):
                walk(_resolve(sub)["items"], prefix + name + ".")

    body = op.get("requestBody", {}).get("content", {}).get("application/json", {}).get("schema")
    if body is not None:
        walk(body)
        for branch in body.get("oneOf", []):
            walk(branch)
    return names


def _names_a_field(case: Case, problem: dict) -> bool:
    """Whether the problem names one of the request's inputs (a row's column as ``rows[0].a_au``, a body's group as
    ``moments``), or is a not-applicable or over-budget answer, which give the reason and the estimate."""
    if problem["type"] in (TYPE_BASE + "not-applicable", TYPE_BASE + "over-budget"):
        return True
    names = _names(case) | _declared(case.method, case.path)
    fields = [e["field"] for e in problem.get("errors") or []]
    if not fields:
        return any(re.search(rf"\b{re.escape(n)}\b", problem.get("detail", "")) for n in names)
    for f in fields:
        plain = re.sub(r"\[\d+\]", "", f)
        if not (plain in names or any(n.startswith(plain + ".") for n in names)):
            return False
    return True


def check(case: Case, r) -> None:
    assert r.status_code < 500, (case.id, r.status_code, r.text[:400])
    kind = r.headers.get("content-type", "").split(";")[0]
    if r.status_code >= 400:
        if kind == "text/html":                 # a page: the API's problem at its field
            assert not NON_FINITE_TEXT.search(_visible(r.text)), case.id
            return
        assert kind == PROBLEM, (case.id, kind)
        problem = _finite_json(r.text)
        assert _names_a_field(case, problem), (case.id, problem)
        return
    assert r.status_code == 200, (case.id, r.status_code)
    if kind == "application/json":
        _finite_json(r.text)
    elif kind == "text/csv":
        cells = [c for row in csv.reader(io.StringIO(r.text)) for c in row]
        assert not [c for c in cells if NON_FINITE_TEXT.fullmatch(c.strip())], case.id
    elif kind in ("text/html", "image/svg+xml"):
        assert not NON_FINITE_TEXT.search(_visible(r.text)), (case.id, NON_FINITE_TEXT.search(_visible(r.text)))
    elif kind == "image/png":
        assert r.content.startswith(b"\x89PNG\r\n\x1a\n"), case.id
    else:                                   # pragma: no cover - a media type this test does not know
        raise AssertionError(f"{case.id}: {kind}")


def _visible(html: str) -> str:
    """A page's or a drawing's text without its markup, styles and embedded images (words like 'resonance' stay
    words: the pattern wants a non-finite number, not the letters)."""
    html = re.sub(r"(?s)<(style|script)\b.*?</\1>", " ", html)
    html = re.sub(r"data:[\w/+.-]+;base64,[A-Za-z0-9+/=]+", " ", html)
    return re.sub(r"<[^>]+>", " ", html)


def _send(client, case: Case):
    path = case.path.replace("{body}", case.body_name)
    if case.method == "GET":
        return client.get(path, params=list(case.query))
    if case.form:
        csv_text = ",".join(BATCH_ROW) + "\n" + ",".join(str(v) for v in BATCH_ROW.values()) + "\n"
        return client.post(path, data=dict(case.form), files={"file": ("bodies.csv", csv_text, "text/csv")})
    return client.post(path, params=list(case.query), content=case.body,
                       headers={"content-type": "application/json"})


@pytest.mark.parametrize("case", CASES, ids=lambda c: c.id)
def test_numeric_edge(client, case):
    check(case, _send(client, case))
