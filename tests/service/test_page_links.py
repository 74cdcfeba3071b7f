"""Every image, link and form of every page type answers (issue 41): each ``<img src>``, each ``<a href>`` to the
service (the API's downloads, the figures, the other pages, the docs) and each form submitted with the values it
shows is requested, and must answer 200 with the media type its URL promises (a figure its image type, a download
its table's type, a page HTML); a download link says a file name whose extension is its format.

Parsed with the standard library's HTMLParser; the service runs in-process (TestClient), nothing leaves it.
"""
from __future__ import annotations

import base64
from html.parser import HTMLParser
from urllib.parse import parse_qs, unquote, urlencode, urlsplit

import pytest
from fastapi.testclient import TestClient

from service.app import create_app
from service.settings import Settings

BASE = "http://testserver"

#: the page types, each with a request a person makes (the Earth's forced-figure track at 10 mas: issue 41's case)
PAGES = ("/", "/?dataset=petit2014", "/bodies/vesta", "/bodies/earth", "/bodies/moon", "/bodies/mars",
         "/bodies/vesta/track",
         "/bodies/earth/track?start=2000-01-01&stop=2030-01-01&step_days=3650&tolerance_mas=10&axis=forced_figure",
         "/bodies/mars/track?start=2030-01-01&stop=2030-03-01&step_days=5&model=hansen&free_wobble_phase_deg=30"
         "&free_wobble_J_arcsec=0.2",
         "/bodies/itokawa/track?start=2030-01-01&stop=2030-06-01&step_days=7&model=series&order=4"
         "&axis=angular_momentum&dataset=petit2014",
         "/bodies/ceres/history", "/bodies/ceres/history?start_year=-20000&stop_year=0&step_years=500",
         "/my-body", "/batch", "/docs/accuracy", "/about")
#: links to another origin a page may carry (not followed: no network here): a paper's DOI
OUTSIDE_LINKS = ("https://doi.org/",)


class Links(HTMLParser):
    """The page's images, links (with their download attribute) and forms (action, method, the values shown)."""

    def __init__(self, html: str):
        super().__init__()
        self.images: list[str] = []
        self.links: list[tuple[str, str | None]] = []
        self.forms: list[dict] = []
        self.ids: list[str] = []
        self._select: str | None = None
        self._first_option: str | None = None
        self.feed(html)

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if "id" in a:
            self.ids.append(a["id"])
        if tag == "img":
            self.images.append(a["src"])
        elif tag == "a" and "href" in a:
            self.links.append((a["href"], a.get("download")))
        elif tag == "form":
            self.forms.append({"action": a.get("action", ""), "method": a.get("method", "get").lower(),
                               "enctype": a.get("enctype"), "values": {}, "files": []})
        elif tag == "input" and self.forms and a.get("name"):
            if a.get("type") == "file":
                self.forms[-1]["files"].append(a["name"])
            elif a.get("type") not in ("checkbox", "radio") or "checked" in a:
                self.forms[-1]["values"][a["name"]] = a.get("value", "")
        elif tag == "select" and self.forms:
            self._select, self._first_option = a.get("name"), None
        elif tag == "option" and self._select:
            value = a.get("value", "")
            if self._first_option is None:
                self._first_option = value
                self.forms[-1]["values"].setdefault(self._select, value)
            if "selected" in a:
                self.forms[-1]["values"][self._select] = value

    def handle_endtag(self, tag):
        if tag == "select":
            self._select = None


@pytest.fixture(scope="module")
def client():
    with TestClient(create_app(Settings(warm_up=False))) as c:
        yield c


def _local(url: str) -> str | None:
    """The service's path and query of a URL on the page, None for another origin or a fragment."""
    if url.startswith(BASE):
        url = url[len(BASE):]
    if not url.startswith("/") or url.startswith("//"):
        return None
    return url


def _expected_type(url: str) -> str:
    """The media type a URL promises: a figure by its extension, a table by its format, the API JSON, else HTML."""
    parts = urlsplit(url)
    fmt = parse_qs(parts.query).get("format", [None])[0]
    by_ext = {".svg": "image/svg+xml", ".png": "image/png", ".css": "text/css", ".js": "text/javascript",
              ".csv": "text/csv", ".json": "application/json"}
    for ext, media in by_ext.items():
        if parts.path.endswith(ext):
            return media
    if fmt in ("csv", "markdown", "latex", "json", "table-json", "ecsv"):
        return {"csv": "text/csv", "markdown": "text/markdown", "latex": "application/x-latex",
                "json": "application/json", "table-json": "application/json", "ecsv": "text/x-ecsv"}[fmt]
    if parts.path.startswith("/v1/") or parts.path == "/openapi.json":
        return "application/json"
    if parts.path.endswith(".md"):
        return "text/markdown"
    return "text/html"


EXTENSIONS = {"text/csv": ".csv", "text/markdown": ".md", "application/x-latex": ".tex",
              "application/json": ".json", "image/svg+xml": ".svg", "image/png": ".png", "text/x-ecsv": ".ecsv"}

_seen: dict[str, tuple[int, str]] = {}


def _get(client, url: str):
    if url not in _seen:
        r = client.get(url)
        _seen[url] = (r.status_code, r.headers.get("content-type", ""), r.headers.get("content-disposition"))
    return _seen[url]


def _check(client, url: str, download: str | None = None) -> None:
    status, media, disposition = _get(client, url)
    want = _expected_type(url)
    assert status == 200 and media.split(";")[0].strip() == want, (url, status, media, want)
    if download is not None and want in EXTENSIONS:
        # the file saved says its format; the API's own filename agrees with the link's
        assert download.endswith(EXTENSIONS[want]), (url, download)
        assert disposition and f'filename="{download}"' in disposition, (url, disposition, download)


@pytest.mark.parametrize("page", PAGES)
def test_every_image_link_and_form_of_a_page_answers(client, page):
    r = client.get(page)
    assert r.status_code == 200 and r.headers["content-type"].startswith("text/html"), (page, r.status_code)
    p = Links(r.text)
    # an id names one element (issue 41: tolerance_mas twice on the body page, model a select and a heading)
    assert len(p.ids) == len(set(p.ids)), sorted({i for i in p.ids if p.ids.count(i) > 1})
    for src in p.images:
        url = _local(src)
        assert url is not None, f"{page}: an image from outside the service: {src}"
        _check(client, url)
    for href, download in p.links:
        if href.startswith("#"):
            continue
        if href.startswith("data:"):
            head, _, payload = href.partition(",")
            assert head.startswith("data:text/csv") and download and download.endswith(".csv"), (page, head)
            assert (base64.b64decode(payload) if head.endswith(";base64") else unquote(payload).encode()), page
            continue
        if href.startswith(OUTSIDE_LINKS):
            continue
        url = _local(href)
        assert url is not None, f"{page}: a link leaves the service: {href}"
        _check(client, url, download)
    for form in p.forms:
        action = _local(form["action"]) or page.split("?")[0]
        if form["method"] == "get":
            url = action + ("?" + urlencode(form["values"]) if form["values"] else "")
            _check(client, url)
        else:
            from tests.service.test_pages import BATCH_CSV
            files = {name: ("bodies.csv", BATCH_CSV, "text/csv") for name in form["files"]}
            got = client.post(action, data=form["values"], files=files)
            assert got.status_code == 200 and got.headers["content-type"].startswith("text/html"), (page, action)


def test_the_track_figure_takes_every_parameter_of_the_track(client):
    """Issue 41: the Earth's forced-figure track at 10 mas has a figure; without its axis the same tolerance cannot
    be met (the free wobble counts), so the figure must be given the track's own parameters."""
    q = {"start": "2000-01-01", "stop": "2030-01-01", "step_days": "3650", "tolerance_mas": "10"}
    assert client.get("/v1/bodies/earth/track.svg", params=q).status_code == 422          # the figure axis: no
    for ext, media in (("svg", "image/svg+xml"), ("png", "image/png")):
        r = client.get(f"/v1/bodies/earth/track.{ext}", params={**q, "axis": "forced_figure"})
        assert r.status_code == 200 and r.headers["content-type"] == media
    # the wobble's phase and amplitude reach the figure too: a bad one is refused at its field
    bad = client.get("/v1/bodies/mars/track.svg", params={"start": "2030-01-01", "stop": "2030-03-01",
                                                          "step_days": "5", "model": "hansen",
                                                          "free_wobble_phase_deg": "30", "free_wobble_J_arcsec": "-1"})
    assert bad.status_code == 422 and [e["field"] for e in bad.json()["errors"]] == ["free_wobble_J_arcsec"]
    # the free wobble's own figure takes no track axis
    wobble = client.get("/v1/bodies/mars/track.svg", params={"start": "2030-01-01", "stop": "2030-02-01",
                                                             "kind": "free-wobble", "axis": "forced_figure"})
    assert wobble.status_code == 422 and [e["field"] for e in wobble.json()["errors"]] == ["axis"]
