"""HTTP details: HEAD /healthz, 405 with Allow, the docs pages served offline from the package,
/docs/accuracy and every link of the OpenAPI document, and problem field paths for nested input."""
import re
from html.parser import HTMLParser
from pathlib import Path

import pytest
from fastapi.testclient import TestClient

from service.app import ACCURACY_DOC_CANDIDATES, create_app
from service.settings import Settings

ROOT = Path(__file__).resolve().parents[2]
PROBLEM = "application/problem+json"
USER = {"orbit": {"a_au": 2.36, "e": 0.089, "i_deg": 7.14, "node_deg": 103.7, "peri_deg": 151.7,
                  "mean_anomaly_deg": 169.2, "epoch_jd_tdb": 2460200.5},
        "pole": {"ra_deg": 309.03, "dec_deg": 42.23}, "rotation_period_hours": 5.342,
        "moments": {"A": 0.3433, "B": 0.3546, "C": 0.42},
        "track": {"start": "2020-01-01", "stop": "2021-01-01", "step_days": 30}}


@pytest.fixture(scope="module")
def client():
    with TestClient(create_app(Settings(warm_up=False))) as c:
        yield c


def test_head_healthz_answers_like_get_without_a_body(client):
    get, head = client.get("/healthz"), client.head("/healthz")
    assert get.status_code == head.status_code == 200
    assert head.content == b""
    assert dict(head.headers) == dict(get.headers)
    assert int(head.headers["content-length"]) == len(get.content) > 0


@pytest.mark.parametrize("method, url, allow", [
    ("POST", "/healthz", "GET, HEAD"),
    ("DELETE", "/v1/bodies", "GET"),
    ("PUT", "/v1/bodies/vesta/track", "GET"),
    ("GET", "/v1/precession-nutation", "POST"),
    ("PATCH", "/docs", "GET"),
])
def test_405_is_a_problem_with_an_allow_header(client, method, url, allow):
    r = client.request(method, url)
    assert r.status_code == 405 and r.headers["content-type"] == PROBLEM
    assert r.headers["allow"] == allow
    assert r.json()["status"] == 405


class _Links(HTMLParser):
    def __init__(self):
        super().__init__()
        self.urls = []

    def handle_starttag(self, tag, attrs):
        self.urls += [v for k, v in attrs if k in ("src", "href", "spec-url") and v]


def _referenced(html: str) -> list[str]:
    """Every URL a docs page loads: src/href/spec-url attributes, and the URLs in its inline script
    (Swagger UI's configuration names the document as url: '/openapi.json')."""
    parser = _Links()
    parser.feed(html)
    quoted = re.findall(r"""["'](/[^"'\s]*|(?:https?:)?//[^"'\s]+)["']""", html)
    return sorted(set(parser.urls) | set(quoted))


@pytest.mark.parametrize("page", ["/docs", "/redoc"])
def test_docs_pages_load_nothing_from_outside_the_app(client, page):
    r = client.get(page)
    assert r.status_code == 200 and r.headers["content-type"].startswith("text/html")
    urls = _referenced(r.text)
    external = [u for u in urls if re.match(r"(?:https?:)?//", u)]
    assert external == [], external
    assert "fonts.googleapis" not in r.text and "cdn." not in r.text
    assets = [u for u in urls if u.startswith("/")]
    assert "/openapi.json" in assets and any(u.startswith("/static/") for u in assets), urls
    for url in assets:
        asset = client.get(url)
        assert asset.status_code == 200, url
        assert len(asset.content) > 0, url


def test_the_assets_are_the_vendored_files_with_their_licences():
    static = ROOT / "service" / "static"
    for name in ("swagger-ui/swagger-ui-bundle.js", "swagger-ui/swagger-ui.css", "swagger-ui/LICENSE",
                 "swagger-ui/NOTICE", "redoc/redoc.standalone.js", "redoc/LICENSE", "README.md"):
        assert (static / name).is_file(), name
    readme = (static / "README.md").read_text()
    assert "swagger-ui-dist" in readme and "5." in readme and "redoc" in readme and "2." in readme


def test_swagger_ui_asks_no_online_validator(client):
    assert '"validatorUrl": null' in client.get("/docs").text


def test_docs_accuracy_serves_the_accuracy_documentation(client):
    r = client.get("/docs/accuracy.md")             # the source; /docs/accuracy is it as HTML (tests/service/test_docs_pages.py)
    assert r.status_code == 200 and r.headers["content-type"].startswith("text/markdown")
    assert r.content == (ROOT / "docs" / "accuracy.md").read_bytes()
    assert client.get("/docs/accuracy").headers["content-type"].startswith("text/html")


def test_the_packaged_copy_of_the_accuracy_documentation_is_current():
    packaged, repository = ACCURACY_DOC_CANDIDATES
    assert packaged.read_bytes() == repository.read_bytes(), \
        "docs/accuracy.md changed: cp docs/accuracy.md service/static/accuracy.md (the copy the package serves)"


def _strings(node):
    if isinstance(node, dict):
        for v in node.values():
            yield from _strings(v)
    elif isinstance(node, list):
        for v in node:
            yield from _strings(v)
    elif isinstance(node, str):
        yield node


#: a path of this app in running text: after a space, a bracket or a quote, starting with a letter
_APP_PATH = re.compile(r"""(?:^|(?<=[\s(\["'`]))(/(?:docs|redoc|static|openapi\.json|healthz|v1)[^\s)\]"'`,;]*)""")


def test_every_link_of_the_openapi_document_to_this_app_resolves(client):
    spec = client.get("/openapi.json").json()
    links = set()
    for text in _strings(spec):
        links |= {m.rstrip(".") for m in _APP_PATH.findall(text)}
    assert "/docs/accuracy" in links, links
    for link in sorted(links):
        if "{" in link:              # a route template, as in "GET /v1/bodies/{body}/track": the route exists
            assert link.split("?")[0] in spec["paths"], link
            continue
        r = client.get(link)
        assert r.status_code == 200, (link, r.status_code)


@pytest.mark.parametrize("patch, field", [
    (lambda b: b["orbit"].update(e="round"), "orbit.e"),
    (lambda b: b["orbit"].update(e=1.5), "orbit.e"),
    (lambda b: b["orbit"].pop("a_au"), "orbit.a_au"),
    (lambda b: b["pole"].update(extra=1), "pole.extra"),
    (lambda b: b["moments"].update(A="heavy"), "moments.A"),
    (lambda b: b["moments"].update(A=-1.0), "moments.A"),
    (lambda b: b["moments"].update(A=0.5), "moments"),
    (lambda b: b["track"].update(step_days="daily"), "track.step_days"),
    (lambda b: b["track"].update(step_days=-1), "track.step_days"),
    (lambda b: b["track"].update(start="2020-02-30"), "track.start"),
    (lambda b: b["track"].update(start=[2020]), "track.start"),
    (lambda b: b["track"].update(stop="2019-01-01"), "track.stop"),
    (lambda b: b["track"].update(tolerance_mas=0), "track.tolerance_mas"),
    (lambda b: b["track"].update(axis="spin"), "track.axis"),
    (lambda b: b["track"].update(free_wobble_J_arcsec=10.0), "track.free_wobble_J_arcsec"),
    (lambda b: b.update(order=-1), "order"),
])
def test_a_problem_names_the_full_path_of_a_nested_field(client, patch, field):
    import copy

    body = copy.deepcopy(USER)
    patch(body)
    r = client.post("/v1/precession-nutation", json=body)
    assert r.status_code == 422 and r.headers["content-type"] == PROBLEM, r.text
    problem = r.json()
    assert [e["field"] for e in problem["errors"]] == [field], problem
    assert problem["detail"].split(": ")[0] in (field, "user body")
    assert f"{field}: " in problem["detail"]


def test_a_body_that_is_not_json_is_a_problem_about_the_request(client):
    r = client.post("/v1/precession-nutation", content=b"{not json", headers={"content-type": "application/json"})
    assert r.status_code == 422 and r.headers["content-type"] == PROBLEM
    assert r.json()["errors"][0]["field"] == "request" and "not valid JSON" in r.json()["detail"]
    r = client.post("/v1/precession-nutation", content=b"\xff\xfe", headers={"content-type": "application/json"})
    assert r.status_code in (400, 422) and r.headers["content-type"] == PROBLEM
