"""The forms, downloads and history of the web page as issue 41 found them wanting, each with its regression test:

- every error of a submission shows, each at its field (one did); "(at the field marked below)" only where one is
  marked (the moments' order marked nothing), after a space; a longitude (RA 500°) is read modulo 360 as the API
  reads it and the page says so, a latitude (Dec 500°) is refused as the API refuses it, and each label states its
  angle's rule; the batch form without a file answers its page, not the framework's JSON; the batch page links its
  column specification and a template CSV that the batch answers without a row error;
- a download is saved under a name that says the body, the table, the layout and the format;
- the page has an icon; ReDoc loads no logo from a CDN;
- the history page links its CSV, states the span of the shipped N-body orbit, says where a request fell back to
  the secular orbit, and gives the estimated error in one unit (degrees, as the answer's per-epoch estimates).

Parsed with the standard library's HTMLParser; the service in-process (TestClient).
"""
from __future__ import annotations

import csv
import io
import re
from html.parser import HTMLParser
from urllib.parse import urlsplit

import pytest
from fastapi.testclient import TestClient

from ephem import api
from service.app import create_app
from service.docs_pages import REDOC_JS
from service.schemas import UserBody
from service.settings import Settings


class Form(HTMLParser):
    """Errors at their fields (by id), the alert's text and items, the invalid controls, links, labels, paragraphs
    by id."""

    def __init__(self, text: str):
        super().__init__()
        self.errors: dict[str, str] = {}
        self.alert: list[str] = []
        self.alert_items: list[str] = []
        self.invalid: dict[str, str] = {}
        self.links: list[tuple[str, str | None, str]] = []
        self.labels: dict[str, str] = {}
        self.by_id: dict[str, str] = {}
        self._stack: list[tuple[str, dict, list[str]]] = []
        self.feed(text)

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag in ("input", "select", "textarea") and a.get("aria-invalid") == "true":
            self.invalid[a.get("id")] = a.get("aria-describedby")
        if tag in ("input", "img", "meta", "link", "br"):
            return
        self._stack.append((tag, a, []))

    def handle_endtag(self, tag):
        if not self._stack or tag in ("input", "img", "meta", "link", "br"):
            return
        t, a, parts = self._stack.pop()
        text = " ".join("".join(parts).split())
        if self._stack:
            self._stack[-1][2].append(text + " ")
        if a.get("class") == "field-error":
            self.errors[a["id"].removesuffix("-error")] = text
        if a.get("class") == "problem":
            self.alert.append(text)
        if t == "li" and any(x[1].get("class") == "problem" for x in self._stack):
            self.alert_items.append(text)
        if t == "a":
            self.links.append((a.get("href"), a.get("download"), text))
        if t == "label":
            self.labels[a.get("for")] = text
        if "id" in a:
            self.by_id[a["id"]] = text

    def handle_data(self, data):
        if self._stack:
            self._stack[-1][2].append(data)


@pytest.fixture(scope="module")
def client():
    with TestClient(create_app(Settings(warm_up=False))) as c:
        yield c


EXAMPLE = {k: v for k, v in UserBody.model_config["json_schema_extra"]["examples"][0].items() if k != "track"}


def _query(user: dict) -> dict:
    q = {"name": user["name"], "rotation_period_hours": str(user["rotation_period_hours"])}
    for group in ("orbit", "pole", "moments"):
        q.update({f"{group}.{k}": str(v) for k, v in user.get(group, {}).items()})
    return q


# ------------------------------------------------------------------------------------------------ forms

def test_every_error_of_a_track_submission_shows_each_at_its_field(client):
    q = {"start": "2020-01-01", "stop": "2021-01-01", "step_days": "abc", "tolerance_mas": "-1", "order": "x"}
    problem = client.get("/v1/bodies/vesta/track", params=q).json()
    assert len(problem["errors"]) == 3                          # the API names all three
    r = client.get("/bodies/vesta/track", params=q)
    page = Form(r.text)
    assert r.status_code == 422
    assert page.errors == {e["field"]: e["reason"] for e in problem["errors"]}
    assert set(page.invalid) == {"step_days", "tolerance_mas", "order"}
    assert "3 fields to correct, each marked below" in page.alert[0] and len(page.alert_items) == 3


def test_every_error_of_a_history_submission_shows(client):
    q = {"start_year": "abc", "stop_year": "x", "step_years": "100"}
    problem = client.get("/v1/bodies/ceres/history", params=q).json()
    page = Form(client.get("/bodies/ceres/history", params=q).text)
    assert page.errors == {e["field"]: e["reason"] for e in problem["errors"]} and len(page.errors) == 2


def test_a_body_of_ones_own_shows_every_error_and_marks_the_moments(client):
    bad = {**EXAMPLE, "orbit": {**EXAMPLE["orbit"], "e": 1.5}, "pole": {**EXAMPLE["pole"], "dec_deg": 500},
           "moments": {"A": 1.0, "B": 0.5, "C": 0.9}}
    # the POST stops at the first; the page checks the orbit, the pole and the body each: all three
    first = client.post("/v1/precession-nutation", json=bad).json()["errors"]
    r = client.get("/my-body", params=_query(bad))
    page = Form(r.text)
    assert r.status_code == 422 and set(page.errors) == {"orbit.e", "pole.dec_deg", "moments"}
    assert {e["field"]: e["reason"] for e in first}.items() <= page.errors.items()
    # the moments' error stands at their fieldset and marks each of its fields
    assert {page.invalid[f"moments.{m}"] for m in "ABC"} == {"moments-error"}
    # one moments error alone: "at the field marked below", after a space, with the field marked
    alone = {**EXAMPLE, "moments": {"A": 1.0, "B": 0.5, "C": 0.9}}
    one = Form(client.get("/my-body", params=_query(alone)).text)
    assert one.errors == {"moments": client.post("/v1/precession-nutation", json=alone).json()["errors"][0]["reason"]}
    assert one.alert[0].endswith(" (at the field marked below)") and "C=0.9(" not in one.alert[0]


def test_no_field_marked_no_field_promised(client):
    page = Form(client.get("/bodies/vulcan/track").text)
    assert page.alert and "marked below" not in page.alert[0] and not page.errors


def test_every_angle_follows_the_apis_rule_and_says_it(client):
    ra = {**EXAMPLE, "pole": {**EXAMPLE["pole"], "ra_deg": 500.0}}
    dec = {**EXAMPLE, "pole": {**EXAMPLE["pole"], "dec_deg": 500.0}}
    same = {**EXAMPLE, "pole": {**EXAMPLE["pole"], "ra_deg": 140.0}}
    for user in (ra, dec):                                       # the page answers as the POST does
        assert client.get("/my-body", params=_query(user)).status_code == \
            client.post("/v1/precession-nutation", json=user).status_code
    page = Form(client.get("/my-body", params=_query(ra)).text)
    assert "pole.ra_deg 500.0 is 140°" in page.by_id["turned"]                  # read modulo 360, and said
    want = client.post("/v1/precession-nutation", json=same).json()["precession"]
    assert float(page.by_id["precession_rate_arcsec_per_year"]) == pytest.approx(
        want["precession_rate_arcsec_per_year"], rel=5e-12)
    assert Form(client.get("/my-body", params=_query(dec)).text).errors["pole.dec_deg"]
    labels = Form(client.get("/my-body").text).labels
    for turning in ("pole.ra_deg", "orbit.node_deg", "orbit.peri_deg", "orbit.mean_anomaly_deg"):
        assert "taken modulo 360" in labels[turning], turning
    assert "−90 to 90" in labels["pole.dec_deg"] and "0 to 180" in labels["orbit.i_deg"]


def test_the_batch_form_without_a_file_answers_its_page(client):
    r = client.post("/batch", data={"start_year": ""})
    assert r.status_code == 422 and r.headers["content-type"].startswith("text/html")
    page = Form(r.text)
    assert "file" in page.errors and page.invalid.get("file") is not None
    assert "marked below" in page.alert[0]


def test_the_batch_page_links_its_specification_and_a_template_the_batch_answers(client):
    page = Form(client.get("/batch").text)
    hrefs = {href: (download, text) for href, download, text in page.links}
    spec = client.get("/docs/batch_input")
    assert "/docs/batch_input" in hrefs and spec.status_code == 200 and "pole_ra_deg" in spec.text
    template_url = next(h for h in hrefs if h.endswith(".csv"))
    r = client.get(template_url)
    assert r.status_code == 200 and r.headers["content-type"].startswith("text/csv")
    assert r.headers["content-disposition"] == f'attachment; filename="{hrefs[template_url][0]}"'
    rows = list(csv.DictReader(io.StringIO(r.text)))
    assert len(rows) == 3                                        # one per form of the inertia
    answer = client.post("/v1/batch", content=r.content, headers={"content-type": "text/csv"}).json()
    assert [row["error"] for row in answer["rows"]] == ["", "", ""]
    page = client.post("/batch", files={"file": ("bodies_template.csv", r.text, "text/csv")})
    assert page.status_code == 200 and "with an error" not in page.text


# ------------------------------------------------------------------------------------------------ downloads

def test_each_download_is_saved_under_a_name_of_its_own(client):
    names = {}
    for fmt, ext in (("csv", "csv"), ("markdown", "md"), ("latex", "tex"), ("table-json", "json")):
        for layout in ("sin-cos", "amp-period"):
            r = client.get("/v1/bodies/vesta/nutation", params={"format": fmt, "layout": layout})
            (name,) = re.findall(r'filename="([^"]+)"', r.headers["content-disposition"])
            assert name.startswith("vesta_current_nutation_" + layout) and name.endswith("." + ext), name
            names[(fmt, layout)] = name
    assert len(set(names.values())) == len(names)           # markdown and latex, sin-cos and amp-period differ
    track = client.get("/v1/bodies/ceres/track", params={"start": "2020-01-01", "stop": "2020-03-01",
                                                          "step_days": "10", "format": "csv"})
    assert track.headers["content-disposition"] == 'attachment; filename="ceres_current_track.csv"'
    body = Form(client.get("/bodies/vesta").text)
    downloads = [(href, download) for href, download, _ in body.links if "/nutation?" in (href or "") and "format=" in href]
    assert len(downloads) == 7 and all(d for _, d in downloads)        # 3 formats x 2 layouts, and the ECSV
    assert len({d for _, d in downloads}) == 7


def test_the_page_has_an_icon_and_redoc_loads_no_logo_from_a_cdn(client):
    icon = client.get("/favicon.ico")
    assert icon.status_code == 200 and icon.headers["content-type"] == "image/svg+xml" and b"<svg" in icon.content
    assert '<link rel="icon" href="/static/page/favicon.svg"' in client.get("/").text
    assert client.get("/static/page/favicon.svg").status_code == 200
    redoc = client.get("/redoc").text
    (src,) = re.findall(r'<script src="([^"]+)"', redoc)
    js = client.get(src)
    assert js.status_code == 200 and js.headers["content-type"].startswith("text/javascript")
    assert b"cdn.redoc.ly/redoc/logo-mini.svg" in REDOC_JS.read_bytes()           # the vendored file, verbatim
    assert b"cdn.redoc.ly" not in js.content and not re.search(rb'src:"https?://', js.content)


# ------------------------------------------------------------------------------------------------ history

def test_the_history_page_links_its_csv_with_every_epoch(client):
    q = {"start_year": "-20000", "stop_year": "0", "step_years": "500"}
    page = Form(client.get("/bodies/ceres/history", params=q).text)
    (href, download, _) = next(link for link in page.links if "format=csv" in (link[0] or ""))
    parts = urlsplit(href)
    r = client.get(parts.path + "?" + parts.query)
    assert r.status_code == 200 and r.headers["content-type"].startswith("text/csv")
    assert r.headers["content-disposition"] == f'attachment; filename="{download}"' == \
        'attachment; filename="ceres_current_history.csv"'
    rows = list(csv.DictReader(io.StringIO(r.text)))
    want = client.get("/v1/bodies/ceres/history", params=q).json()
    assert len(rows) == len(want["year"])
    for key in ("year", "obliquity_deg", "estimated_error_deg", "obliquity_error_deg"):
        assert [float(x[key]) for x in rows] == want[key], key         # repr(): the same doubles


def test_the_history_states_the_n_body_span_and_its_fallback(client):
    lo, hi = api.shipped_orbit_span("ceres")
    for url in ("/bodies/ceres", "/bodies/ceres/history"):
        text = " ".join(re.sub(r"<[^>]+>", " ", client.get(url).text).split())
        assert f"covers {lo:.6g} to {hi:.6g} years" in text, url
    within = Form(client.get("/bodies/ceres/history", params={"start_year": "-20000", "stop_year": "0",
                                                               "step_years": "500"}).text)
    assert "fallback" not in within.by_id
    q = {"start_year": "-10000000", "stop_year": "0", "step_years": "100000"}
    model = client.get("/v1/bodies/ceres/history", params=q).json()["model"]
    assert model["name"] == "secular"
    why_not = next(c["why_not"] for c in model["candidates"] if c["name"] == "nbody")
    beyond = Form(client.get("/bodies/ceres/history", params=q).text)
    assert beyond.by_id["fallback"].startswith("Not the N-body orbit") and why_not in beyond.by_id["fallback"]
    # asked for by name, the secular orbit is no fallback
    named = Form(client.get("/bodies/ceres/history", params={**q, "orbit_model": "secular"}).text)
    assert "fallback" not in named.by_id


def test_the_histories_error_is_in_one_unit(client):
    q = {"start_year": "-20000", "stop_year": "0", "step_years": "500"}
    want = client.get("/v1/bodies/ceres/history", params=q).json()
    page = Form(client.get("/bodies/ceres/history", params=q).text)
    model = page.by_id["history-model"]
    sentence = client.get("/bodies/ceres/history", params=q).text.split("Estimated error:", 1)[1].split(".", 2)
    text = re.sub(r"<[^>]+>", "", ".".join(sentence[:2]))
    assert f"{max(want['estimated_error_deg']):.4g}°" in text and " mas" not in text.split("tolerance")[0]
    assert model                                                     # the section is there
    svg = client.get("/v1/bodies/ceres/history.svg", params=q).text
    title = re.search(r"estimated error ([^<]*?)\(pole\)", svg)
    assert title and "°" in title.group(1) and "″" not in title.group(1) and "mas" not in title.group(1)
