"""Every route of the service in every media type it offers, for a body of every theory family (issue 29).

The matrix is read from the service itself, so that nothing new escapes it:

* the routes are the app's route list (``app.routes``: the API, the docs pages, the OpenAPI document, the static
  mount); a route without an entry in :data:`SPECS` fails :func:`test_every_route_has_a_spec` until someone gives
  it arguments, and an entry without a route fails it too;
* the media types are the 200 response's content in the OpenAPI document. Where an operation takes a ``format``
  query parameter, each of its values (read from the parameter's enum) is a case, answered in the media type of
  :data:`FORMAT_MEDIA` (a value not listed there fails), and the values together must reach every documented
  media type; an operation offering several media types without ``format`` is asked for each by ``Accept``.
  The other enumerated parameters that choose what is drawn or followed (:data:`ENUMERATED`: a plot's ``kind``,
  the tables' ``layout``, the track's ``axis``) are crossed in; a request body offered in several media types
  (POST /v1/batch: JSON and CSV) is sent in each. Routes outside the document state their media type here;
* the families are one body of each theory of ``ephem.families.THEORIES`` (a Sun-only main-belt asteroid, a
  Sun-only planet-crosser, the Earth, the Moon, Mars with its free wobble) for the routes that name a body, and
  bodies of the user's own (an asteroid, a synchronous satellite) for the POSTs; a new theory fails
  :func:`test_the_families_cover_every_theory` until a body of it joins :data:`FAMILIES`.

Each case calls the app in-process (FastAPI's TestClient) and asserts 200, the content type, and a body that
parses: JSON loads (no NaN) and validates against the route's response schema in the OpenAPI document, with no
key the schema does not document; CSV has a header of distinct columns and rows of as many cells, none NaN; a
markdown table its header, rule and rows; LaTeX balanced tabulars with rows of as many cells as columns; PNG its
signature and chunks (Pillow verifies it); SVG parses as XML; HTML has its document. Where a family is not
applicable, the case is listed in :data:`NOT_APPLICABLE` and must be the documented 422 ``not-applicable``
problem with its reason, so that a change either way fails here. Spans are short and steps coarse.
"""
from __future__ import annotations

import csv
import io
import itertools
import json
import math
import re
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from html.parser import HTMLParser
from typing import Callable

import jsonschema_rs
import numpy as np
import pytest
from fastapi.routing import APIRoute
from fastapi.testclient import TestClient
from starlette.routing import Mount, Route

from ephem import api
from ephem.bodies.catalogue import Body, Orbit, Pole, get_body
from service.app import create_app
from service.problems import PROBLEM, TYPE_BASE
from service.settings import Settings

APP = create_app(Settings(warm_up=False))
DOC = APP.openapi()


@pytest.fixture(scope="module")
def client():
    with TestClient(APP) as c:
        yield c


# ------------------------------------------------------------------ the families

@dataclass(frozen=True)
class Family:
    body: str | None = None             # a catalogue body, for the routes that name one
    user: dict | None = None            # a body of the user's own, for the POSTs
    published_wobble: bool = True       # a free-wobble amplitude J in the catalogue (Lara 2014, IERS, ...)


USER_ASTEROID = {
    "name": "matrix-asteroid",
    "orbit": {"a_au": 2.36, "e": 0.089, "i_deg": 7.14, "node_deg": 103.7, "peri_deg": 151.7,
              "mean_anomaly_deg": 169.2, "epoch_jd_tdb": 2460200.5},
    "pole": {"ra_deg": 309.03, "dec_deg": 42.23, "epoch_jd_tdb": 2451545.0},
    "rotation_period_hours": 5.342, "moments": {"A": 0.3433, "B": 0.3546, "C": 0.42}}
#: the Moon's mean elements and libration constants (data/catalogue/current.toml): a synchronous satellite of the
#: Earth, whose node regresses on its Laplace plane
_BETA, _GAMMA = 0.0006310213, 0.0002277317
USER_SATELLITE = {
    "name": "matrix-satellite",
    "orbit": {"a_au": 384400.0 / 149597870.7, "e": 0.0549, "i_deg": 5.145, "node_deg": 125.0445479,
              "peri_deg": 318.3085034, "mean_anomaly_deg": 134.9633964, "epoch_jd_tdb": 2451545.0,
              "center": "Earth", "node_rate_deg_per_year": -19.341362891},
    "pole": {"ra_deg": 266.8577, "dec_deg": 65.6411}, "rotation_period_hours": 27.321661 * 24.0,
    "moments": {"A": 1.0, "B": 1.0 + _GAMMA, "C": (1.0 + _GAMMA) * (1.0 + _BETA)}}

FAMILIES = {
    "sun_only": Family("vesta", published_wobble=False),          # the single-perturber ladder, main belt
    "planet_crosser": Family("itokawa", published_wobble=False),  # the same ladder, an orbit crossing the Earth's
    "earth": Family("earth"),                                     # the lunisolar theory
    "moon": Family("moon"),                                       # the synchronous rotator: Cassini state
    "mars": Family("mars"),                                       # the ladder, with its published free wobble
    "user_asteroid": Family(user=USER_ASTEROID, published_wobble=False),
    "user_satellite": Family(user=USER_SATELLITE, published_wobble=False),
}
CATALOGUE = tuple(k for k, f in FAMILIES.items() if f.body is not None)
USERS = tuple(k for k, f in FAMILIES.items() if f.user is not None)


# ------------------------------------------------------------------ what each route is given

@dataclass(frozen=True)
class Case:
    method: str
    path: str
    family: str | None
    variant: tuple[tuple[str, str], ...]     # (parameter, value): the enumerated query parameters, "accept",
    #                                          "content-type" (the request body's media type)

    @property
    def fam(self) -> Family:
        return FAMILIES[self.family]

    @property
    def params(self) -> dict[str, str]:
        return {k: v for k, v in self.variant if k not in ("accept", "content-type")}

    def get(self, key: str, default=None):
        return dict(self.variant).get(key, default)

    @property
    def id(self) -> str:
        form = ",".join(f"{k}={v}" for k, v in self.variant)
        return " ".join(x for x in (self.method, self.path, self.family, form) if x)


def _wobble_j(case: Case, key: str = "J_arcsec") -> dict:
    """The wobble amplitude a request needs when the catalogue gives none (a user of the asteroid would)."""
    return {} if case.fam.published_wobble else {key: 10.0}


def _track_query(case: Case) -> dict:
    q = {"start": "2020-01-01", "stop": "2020-03-01", "step_days": 30}
    if case.family == "mars" and case.get("axis", "figure") == "figure":
        q["free_wobble_phase_deg"] = 30.0             # Mars with its free wobble, of the published amplitude
    return q


def _plot_query(case: Case) -> dict:
    # no step_days: the figure chooses one for its kind (a free-wobble plot samples the wobble's period)
    q = {"start": "2020-01-01", "stop": "2020-04-01", "dpi": 30}
    return {**q, **_wobble_j(case)} if case.get("kind") == "free-wobble" else q


HISTORY = {"start_year": -400, "stop_year": 0}      # within Itokawa's shipped N-body orbit (-500 to 39500)
MODELS_QUERY = {"start": "2020-01-01", "stop": "2020-03-01", "step_days": 30, "tolerance_mas": 1e5}


def _batch_row() -> dict:
    u = USER_ASTEROID
    return {"name": u["name"], **{k: v for k, v in u["orbit"].items()}, "pole_ra_deg": u["pole"]["ra_deg"],
            "pole_dec_deg": u["pole"]["dec_deg"], "rotation_period_hours": u["rotation_period_hours"],
            "moment_a": u["moments"]["A"], "moment_b": u["moments"]["B"], "moment_c": u["moments"]["C"],
            "e_sigma": 0.001}


def _batch_rows() -> list[dict]:
    return [_batch_row(), dict(_batch_row(), name="second", pole_dec_deg=-10.0)]


def _batch_csv() -> str:
    rows = _batch_rows()
    out = io.StringIO()
    writer = csv.DictWriter(out, fieldnames=list(rows[0]))
    writer.writeheader()
    writer.writerows(rows)
    return out.getvalue()


def _batch_body(case: Case):
    if case.get("content-type") == "text/csv":
        return _batch_csv()
    return {"rows": _batch_rows(), "history": {**HISTORY, "step_years": 200}}


def _user_body(case: Case) -> dict:
    track = {"start": "2020-01-01", "stop": "2020-03-01", "step_days": 30}
    return {**case.fam.user, "track": track, "history": {**HISTORY, "step_years": 200}}


@dataclass(frozen=True)
class Spec:
    families: tuple[str, ...] = (None,)                 # (None,): a route that names no body
    query: Callable[[Case], dict] = lambda case: {}
    body: Callable[[Case], object] | None = None        # the request body (JSON, or text for a text/* type)
    url: str | None = None                              # a concrete path (a mount's file)
    media: tuple[str, ...] = ()                         # a route outside the OpenAPI document: its media types
    files: Callable[[Case], dict] | None = None          # a multipart upload (the web page's batch form)


SPECS: dict[tuple[str, str], Spec] = {
    ("GET", "/healthz"): Spec(),
    ("HEAD", "/healthz"): Spec(media=("application/json",)),
    ("GET", "/v1/bodies"): Spec(),
    ("GET", "/v1/bodies/{body}"): Spec(CATALOGUE),
    ("GET", "/v1/bodies/{body}/precession"): Spec(CATALOGUE),
    ("GET", "/v1/bodies/{body}/nutation"): Spec(CATALOGUE),
    ("GET", "/v1/bodies/{body}/track"): Spec(CATALOGUE, _track_query),
    ("GET", "/v1/bodies/{body}/history"): Spec(CATALOGUE, lambda case: {**HISTORY, "step_years": 200}),
    ("GET", "/v1/bodies/{body}/track.png"): Spec(CATALOGUE, _plot_query),
    ("GET", "/v1/bodies/{body}/track.svg"): Spec(CATALOGUE, _plot_query),
    # speed against accuracy: every model's estimate and cost, and its chart (a tolerance, so one may be chosen)
    ("GET", "/v1/bodies/{body}/track/models"): Spec(CATALOGUE, lambda case: MODELS_QUERY),
    ("GET", "/v1/bodies/{body}/track/models.png"): Spec(CATALOGUE, lambda case: {**MODELS_QUERY, "dpi": 30}),
    ("GET", "/v1/bodies/{body}/track/models.svg"): Spec(CATALOGUE, lambda case: MODELS_QUERY),
    ("GET", "/v1/bodies/{body}/history.png"): Spec(CATALOGUE, lambda case: {**HISTORY, "dpi": 30}),
    ("GET", "/v1/bodies/{body}/history.svg"): Spec(CATALOGUE, lambda case: HISTORY),
    ("GET", "/v1/bodies/{body}/free-motion"): Spec(CATALOGUE, lambda case: {
        "start": "2020-01-01", "stop": "2020-01-03", "step_days": 0.5, **_wobble_j(case)}),
    ("POST", "/v1/batch"): Spec(("user_asteroid",), body=_batch_body),
    ("POST", "/v1/precession-nutation"): Spec(USERS, body=_user_body),
    ("GET", "/openapi.json"): Spec(media=("application/json",)),
    ("HEAD", "/openapi.json"): Spec(media=("application/json",)),
    ("GET", "/docs"): Spec(media=("text/html",)),
    ("GET", "/redoc"): Spec(media=("text/html",)),
    # the project's documents as HTML, their Markdown source, their charts and figures (service/docs_pages.py)
    ("GET", "/docs/{name}"): Spec(url="/docs/accuracy", media=("text/html",)),
    ("GET", "/docs/{name}.md"): Spec(url="/docs/accuracy.md", media=("text/markdown",)),
    ("MOUNT", "/docs/charts"): Spec(url="/docs/charts/work_precision.png", media=("image/png",)),
    ("MOUNT", "/docs/figures"): Spec(url="/docs/figures/earth_free_wobble.png", media=("image/png",)),
    # ReDoc's bundle with its CDN logo replaced, and the page's icon (service/docs_pages.py)
    ("GET", "/redoc/redoc.standalone.js"): Spec(media=("text/javascript",)),
    ("GET", "/favicon.ico"): Spec(media=("image/svg+xml",)),
    ("MOUNT", "/static"): Spec(url="/static/swagger-ui/swagger-ui.css", media=("text/css",)),
    # the web page (service/pages.py): every body's page and a track of it, each a whole HTML document
    ("GET", "/"): Spec(media=("text/html",)),
    ("GET", "/bodies/{body}"): Spec(CATALOGUE, media=("text/html",)),
    ("GET", "/bodies/{body}/track"): Spec(CATALOGUE, lambda case: {"start": "2020-01-01", "stop": "2020-03-01",
                                                                   "step_days": 30}, media=("text/html",)),
    ("GET", "/bodies/{body}/history"): Spec(CATALOGUE, lambda case: {**HISTORY, "step_years": 200},
                                            media=("text/html",)),
    ("GET", "/my-body"): Spec(media=("text/html",)),
    ("GET", "/batch"): Spec(media=("text/html",)),
    ("GET", "/batch/template.csv"): Spec(media=("text/csv",)),
    ("GET", "/about"): Spec(media=("text/html",)),
    ("POST", "/batch"): Spec(("user_asteroid",), files=lambda case: {"file": ("bodies.csv", _batch_csv(), "text/csv")},
                             media=("text/html",)),
}

#: the media type of each value a ``format`` query parameter takes
FORMAT_MEDIA = {"json": "application/json", "table-json": "application/json", "csv": "text/csv",
                "markdown": "text/markdown", "latex": "application/x-latex", "ecsv": "text/x-ecsv"}
#: enumerated query parameters crossed into the matrix besides ``format``: what is drawn, the tables' layout,
#: the pole followed
ENUMERATED = ("kind", "layout", "axis")

#: (method, path, family, the variant's items that make it so) -> the reason a 422 not-applicable gives
#: the routes that follow an axis (the track, its figures, the models comparison and its charts)
AXIS_ROUTES = ("/v1/bodies/{body}/track", "/v1/bodies/{body}/track.png", "/v1/bodies/{body}/track.svg",
               "/v1/bodies/{body}/track/models", "/v1/bodies/{body}/track/models.png",
               "/v1/bodies/{body}/track/models.svg")
NOT_APPLICABLE = {
    # a synchronous rotator's theory follows its figure axis and its mean rotation axis (issue 40), not its angular
    # momentum; every other family follows the figure axis, the angular momentum and the forced figure, and the mean
    # rotation axis is a synchronous body's
    **{("GET", path, "moon", (("axis", "angular_momentum"),)): "not angular_momentum" for path in AXIS_ROUTES},
    **{("GET", path, family, (("axis", "mean_rotation"),)): "not mean_rotation"
       for path in AXIS_ROUTES for family in ("sun_only", "planet_crosser", "earth", "mars")},
}


# ------------------------------------------------------------------ the matrix, read from the app

def served_routes() -> list[tuple[str, str]]:
    """(method, path) of every route the app serves; a mount as ("MOUNT", its path)."""
    out = []
    for r in APP.routes:
        if isinstance(r, Mount):
            out.append(("MOUNT", r.path))
        elif isinstance(r, (APIRoute, Route)):
            out.extend((m, r.path) for m in sorted(r.methods))
        else:       # pragma: no cover - a kind of route this file does not know
            out.append((type(r).__name__, getattr(r, "path", "?")))
    return out


def _resolve(schema: dict) -> dict:
    while "$ref" in schema:
        name = schema["$ref"].rsplit("/", 1)[-1]
        schema = DOC["components"]["schemas"][name]
    return schema


def _enum(schema: dict) -> list[str]:
    schema = _resolve(schema)
    for branch in schema.get("anyOf", [schema]):
        branch = _resolve(branch)
        if "enum" in branch:
            return list(branch["enum"])
    return []


def operation(method: str, path: str) -> dict | None:
    return DOC["paths"].get(path, {}).get(method.lower())


def documented_media(method: str, path: str) -> set[str]:
    op = operation(method, path)
    if op is None:
        return set(SPECS[(method, path)].media)
    return set(op["responses"]["200"].get("content", {}))


def variants(method: str, path: str) -> list[tuple[tuple[str, str], ...]]:
    """The enumerated choices of one operation, crossed: format (each media type), the ENUMERATED parameters,
    Accept when several media types come without a format, the request body's media types."""
    op = operation(method, path)
    if op is None:
        return [()]
    axes: list[list[tuple[str, str]]] = []
    params = {p["name"]: p for p in op.get("parameters", []) if p["in"] == "query"}
    for name in ("format",) + ENUMERATED:
        if name in params and _enum(params[name]["schema"]):
            axes.append([(name, v) for v in _enum(params[name]["schema"])])
    media = documented_media(method, path)
    if "format" not in params and len(media) > 1:
        axes.append([("accept", m) for m in sorted(media)])
    request = list(op.get("requestBody", {}).get("content", {}))
    if len(request) > 1:
        axes.append([("content-type", m) for m in request])
    # the free wobble's figure is the torque-free motion: the track's axis does not apply to it (a 422 naming
    # axis, tests/service/test_page_links.py), so it is crossed with the track kinds only
    return [tuple(combo) for combo in itertools.product(*axes)
            if not (("kind", "free-wobble") in combo and any(k == "axis" and v != "figure" for k, v in combo))]


def expected_media(case: Case) -> str:
    if case.get("format") is not None:
        return FORMAT_MEDIA[case.get("format")]
    if case.get("accept") is not None:
        return case.get("accept")
    (only,) = documented_media(case.method, case.path)
    return only


def not_applicable(case: Case) -> str | None:
    for (method, path, family, items), reason in NOT_APPLICABLE.items():
        if (method, path, family) == (case.method, case.path, case.family) and set(items) <= set(case.variant):
            return reason
    return None


CASES = [Case(method, path, family, variant)
         for (method, path), spec in SPECS.items()
         for family in spec.families
         for variant in variants(method, path)]


# ------------------------------------------------------------------ what an answer must be

def _no_nan(text: str):
    def refuse(constant):
        raise AssertionError(f"{constant} in a JSON answer")
    return json.loads(text, parse_constant=refuse)


def _undocumented(instance, schema: dict, where: str = "") -> list[str]:
    """Keys of ``instance`` that its schema (resolved through $ref and anyOf) does not document."""
    schema = _resolve(schema)
    if "anyOf" in schema:
        for branch in schema["anyOf"]:
            if _validator(branch).is_valid(instance):
                return _undocumented(instance, branch, where)
        return [f"{where}: matches no branch"]
    out = []
    if isinstance(instance, dict) and "properties" in schema:
        props = schema["properties"]
        if schema.get("additionalProperties") in (None, False):
            out += [f"{where}.{k}" for k in instance if k not in props]
        for k, v in instance.items():
            if k in props:
                out += _undocumented(v, props[k], f"{where}.{k}")
    elif isinstance(instance, list) and isinstance(schema.get("items"), dict):
        for j, v in enumerate(instance[:3]):
            out += _undocumented(v, schema["items"], f"{where}[{j}]")
    return out


def _validator(schema: dict):
    return jsonschema_rs.Draft202012Validator({**schema, "components": DOC["components"]})


def check_json(case: Case, r) -> None:
    data = _no_nan(r.text)
    op = operation(case.method, case.path)
    if op is None:                                    # /openapi.json
        assert data["openapi"].startswith("3.") and data["paths"], case.id
        return
    schema = op["responses"]["200"]["content"]["application/json"].get("schema") or {}
    assert schema, f"{case.id}: the route documents no schema for its JSON answer"
    errors = [str(e).splitlines()[0] for e in _validator(schema).iter_errors(data)]
    assert not errors, (case.id, errors[:5])
    assert not _undocumented(data, schema), (case.id, _undocumented(data, schema)[:5])


def check_csv(case: Case, r) -> None:
    rows = list(csv.reader(io.StringIO(r.text)))
    header, body = rows[0], [row for row in rows[1:] if row]
    assert all(header) and len(set(header)) == len(header), (case.id, header)
    assert body, f"{case.id}: a header and no rows"
    assert all(len(row) == len(header) for row in body), case.id
    cells = [c for row in body for c in row]
    assert not [c for c in cells if c.strip().lower() in ("nan", "inf", "-inf", "infinity")], case.id
    op = operation(case.method, case.path)          # None for a page's file (the batch template)
    example = op["responses"]["200"]["content"]["text/csv"].get("example", "") if op else ""
    if example:
        assert header[0] == example.split(",", 1)[0], (case.id, header[0])   # the documented first column
    if case.path.endswith("/track"):
        assert header == [api.TRACK_KEYS[0], "utc_iso", *api.TRACK_KEYS[1:]]
        assert all(math.isfinite(float(c)) for row in body for j, c in enumerate(row) if j != 1)
        assert all(re.fullmatch(r"\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d\.\d{3}", row[1]) for row in body)


def check_ecsv(case: Case, r) -> None:
    """astropy reads it: a row at least, every column whose key names a unit a Quantity in it, jd_tdb a TDB Time,
    nothing NaN but where the answer has null (masked); the version and the source in the header."""
    from astropy import units as u
    from astropy.table import QTable
    from astropy.time import Time

    from ephem.base.units import unit_of

    table = QTable.read(r.text, format="ascii.ecsv")
    assert len(table) >= 1 and table.colnames, case.id
    assert table.meta["version"] and table.meta["source"].startswith("http"), case.id
    for key in table.colnames:
        col = table[key]
        assert col.info.description, (case.id, key)
        if key == "jd_tdb":
            assert isinstance(col, Time) and col.scale == "tdb", case.id
        elif unit_of(key) is not None and getattr(col, "dtype", None) is not None and col.dtype.kind == "f":
            assert isinstance(col, u.Quantity) and col.unit == u.Unit(unit_of(key)), (case.id, key)
            values = np.ma.masked_invalid(np.ma.MaskedArray(getattr(col, "unmasked", col).value,
                                                             mask=np.ma.getmaskarray(col)))
            assert not np.isnan(values.filled(0.0)).any(), (case.id, key)


def check_markdown(case: Case, r) -> None:
    text = r.text
    if case.path == "/docs/{name}.md":
        assert re.search(r"^# \S", text, re.M), case.id
        return
    tables = [list(g) for is_row, g in itertools.groupby(text.splitlines(), lambda s: s.startswith("|")) if is_row]
    assert tables, case.id
    for t in tables:
        width = t[0].count("|")
        assert re.fullmatch(r"\|(\s*:?-+:?\s*\|)+", t[1]) and t[1].count("|") == width, (case.id, t[1])
        assert len(t) > 2 and all(row.count("|") == width for row in t[2:]), case.id


def check_latex(case: Case, r) -> None:
    text = r.text
    assert text.count(r"\begin{tabular}") == text.count(r"\end{tabular}") >= 1, case.id
    assert text.count(r"\begin{table}") == text.count(r"\end{table}"), case.id
    for spec, body in re.findall(r"\\begin\{tabular\}\{([^}]*)\}(.*?)\\end\{tabular\}", text, re.S):
        columns = len(re.findall(r"[lcrp]", spec))
        assert r"\toprule" in body and r"\midrule" in body and r"\bottomrule" in body, case.id
        rows = [s for s in body.splitlines() if s.rstrip().endswith(r"\\")]
        assert len(rows) >= 2, case.id                                # the header and a row at least
        assert all(s.count("&") == columns - 1 for s in rows), (case.id, columns)


def check_png(case: Case, r) -> None:
    from PIL import Image

    data = r.content
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and data[12:16] == b"IHDR" and data[-8:-4] == b"IEND", case.id
    with Image.open(io.BytesIO(data)) as im:
        im.verify()
        assert im.size[0] > 0 and im.size[1] > 0


def check_svg(case: Case, r) -> None:
    root = ET.fromstring(r.content)
    assert root.tag.endswith("svg"), (case.id, root.tag)
    assert len(list(root.iter())) > 10, case.id                   # something drawn


def check_html(case: Case, r) -> None:
    class Parse(HTMLParser):
        def __init__(self):
            super().__init__()
            self.tags: set[str] = set()
            self.assets: list[str] = []

        def handle_starttag(self, tag, attrs):
            self.tags.add(tag)
            a = dict(attrs)
            if tag in ("script", "link") and (a.get("src") or a.get("href")):
                self.assets.append(a.get("src") or a.get("href"))
    p = Parse()
    p.feed(r.text)
    p.close()
    assert {"html", "head", "body", "title"} <= p.tags, (case.id, p.tags)
    assert p.assets and all(u.startswith("/") for u in p.assets), (case.id, p.assets)   # served here, offline


def check_css(case: Case, r) -> None:
    assert "{" in r.text and "}" in r.text, case.id


def check_js(case: Case, r) -> None:
    assert "function" in r.text and 'src:"https://' not in r.text, case.id      # nothing fetched from outside


CHECKS = {"application/json": check_json, "text/csv": check_csv, "text/markdown": check_markdown,
          "text/x-ecsv": check_ecsv,
          "application/x-latex": check_latex, "image/png": check_png, "image/svg+xml": check_svg,
          "text/html": check_html, "text/css": check_css, "text/javascript": check_js}


def call(client, case: Case):
    spec = SPECS[(case.method, case.path)]
    url = spec.url or case.path
    if "{body}" in url:
        url = url.replace("{body}", case.fam.body)
    headers = {}
    if case.get("accept"):
        headers["accept"] = case.get("accept")
    kwargs = {"params": {**spec.query(case), **case.params}, "headers": headers}
    if spec.files is not None:
        kwargs["files"] = spec.files(case)
    if spec.body is not None:
        body = spec.body(case)
        if isinstance(body, str):
            headers["content-type"] = case.get("content-type")
            kwargs["content"] = body.encode()
        else:
            kwargs["json"] = body
    method = "GET" if case.method == "MOUNT" else case.method
    return client.request(method, url, **kwargs)


# ------------------------------------------------------------------ the tests

def test_every_route_has_a_spec():
    served = served_routes()
    assert len(served) == len(set(served))
    missing = sorted(set(served) - set(SPECS))
    stale = sorted(set(SPECS) - set(served))
    assert not missing, f"routes without a spec in SPECS (give them arguments): {missing}"
    assert not stale, f"specs of routes the app does not serve: {stale}"


def test_every_documented_operation_is_a_route():
    documented = {(m.upper(), p) for p, item in DOC["paths"].items() for m in item}
    assert documented <= set(served_routes())


def test_every_documented_media_type_is_reached():
    """The format values reach every media type the operation documents, and only those; a value without a
    media type in FORMAT_MEDIA fails here (add it, and a check in CHECKS for a new type)."""
    for (method, path) in SPECS:
        media = documented_media(method, path)
        assert media, (method, path)
        assert media <= set(CHECKS) | ({"application/json"} if method == "HEAD" else set()), \
            f"{method} {path}: no check for {media - set(CHECKS)}"
        formats = {dict(v).get("format") for v in variants(method, path)} - {None}
        if formats:
            unknown = formats - set(FORMAT_MEDIA)
            assert not unknown, f"{method} {path}: format values without a media type: {unknown}"
            assert {FORMAT_MEDIA[f] for f in formats} == media, (method, path)


def test_the_families_cover_every_theory():
    from ephem.families import THEORIES, theory_for

    served = {}
    for key, fam in FAMILIES.items():
        if fam.body is not None:
            body = get_body(fam.body)
        else:       # as POST /v1/precession-nutation builds it
            u = fam.user
            body = Body(u["name"], Orbit(**u["orbit"], body=u["name"]), Pole(**u["pole"], body=u["name"]),
                        u["rotation_period_hours"], moments=tuple(u["moments"].values()))
        served[key] = type(theory_for(body, body.perturbers).inner)
    assert {served[k] for k in CATALOGUE} == set(THEORIES), served
    assert {served[k] for k in USERS} <= set(THEORIES) and len({served[k] for k in USERS}) == len(USERS), served


def test_every_not_applicable_entry_is_a_case():
    for (method, path, family, items) in NOT_APPLICABLE:
        assert any((c.method, c.path, c.family) == (method, path, family) and set(items) <= set(c.variant)
                   for c in CASES), (method, path, family, items)


@pytest.mark.parametrize("case", CASES, ids=[c.id for c in CASES])
def test_route_media_family(client, case):
    r = call(client, case)
    reason = not_applicable(case)
    if reason is not None:
        assert r.status_code == 422, (case.id, r.status_code, r.text[:300])
        assert r.headers["content-type"].startswith(PROBLEM)
        problem = _no_nan(r.text)
        assert problem["type"] == TYPE_BASE + "not-applicable", (case.id, problem)
        assert reason in problem["detail"], (case.id, problem["detail"])
        return
    assert r.status_code == 200, (case.id, r.status_code, r.text[:500])
    media = expected_media(case)
    got = r.headers["content-type"].split(";")[0].strip()
    assert got == media, (case.id, got, media)
    if case.method == "HEAD":
        assert r.content == b"", case.id
        return
    CHECKS[media](case, r)
