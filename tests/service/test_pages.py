"""The web page (service/pages.py): the numbers are the API's, the URL is the permalink, errors stand at their field,
the controls are labelled and the tables captioned; every request stays on loopback (tests/base's guard).

Parsed with the standard library's HTMLParser (no browser here: the pages need no JavaScript). Numbers on the page
are printed to a stated number of significant digits (12 for the precession values, 10 for a track's), so each is
compared with the API's within half a unit of its last digit.
"""
from __future__ import annotations

import csv
import io
from html.parser import HTMLParser
from urllib.parse import parse_qs, urlsplit

import pytest
from fastapi.testclient import TestClient

from ephem import api
from service.app import create_app
from service.pages import TRACK_ROWS_SHOWN
from service.settings import Settings


class Page(HTMLParser):
    """What the tests read of a page: elements by id with their text, labels, form controls, tables, links,
    images and the inline errors."""

    def __init__(self, html: str):
        super().__init__()
        self.by_id: dict[str, dict] = {}
        self.labels: set[str] = set()
        self.controls: list[dict] = []
        self.tables: list[dict] = []
        self.links: list[str] = []
        self.images: list[dict] = []
        self.errors: dict[str, str] = {}
        self.alerts: list[str] = []
        self._open: list[tuple[str, dict]] = []
        self._text: dict[int, list[str]] = {}
        self.feed(html)

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        self._open.append((tag, a))
        self._text[len(self._open)] = []
        if tag == "label":
            self.labels.add(a.get("for"))
        elif tag in ("input", "select") and a.get("type") != "hidden":
            self.controls.append(a)
        elif tag == "table":
            self.tables.append({"caption": None, "header_scopes": [], "rows": []})
        elif tag == "th" and self.tables:
            self.tables[-1]["header_scopes"].append(a.get("scope"))
        elif tag == "a" and "href" in a:
            self.links.append(a["href"])
        elif tag == "img":
            self.images.append(a)
        if tag in ("input", "img"):          # void elements
            self._close(tag)

    def handle_endtag(self, tag):
        if self._open and self._open[-1][0] == tag:
            self._close(tag)

    def _close(self, tag):
        depth = len(self._open)
        text = " ".join("".join(self._text.pop(depth, [])).split())
        _, a = self._open.pop()
        if self._open:
            self._text[len(self._open)].append(text + " ")
        if "id" in a:
            self.by_id[a["id"]] = {"tag": tag, "text": text, **a}
        if tag == "caption" and self.tables:
            self.tables[-1]["caption"] = text
        if a.get("class") == "field-error":
            self.errors[a["id"].removesuffix("-error")] = text
        if a.get("role") == "alert" and a.get("class") == "problem":
            self.alerts.append(text)

    def handle_data(self, data):
        if self._open:
            self._text[len(self._open)].append(data)


@pytest.fixture(scope="module")
def client():
    with TestClient(create_app(Settings(warm_up=False))) as c:
        yield c


def _page(client, url: str, status: int = 200) -> Page:
    r = client.get(url)
    assert r.status_code == status, (url, r.status_code, r.text[:500])
    assert r.headers["content-type"].startswith("text/html")
    return Page(r.text)


def _accessible(p: Page) -> None:
    """Every control labelled, every table captioned with its headers scoped, every image described."""
    unlabelled = [c.get("id") or c.get("name") for c in p.controls if c.get("id") not in p.labels]
    assert not unlabelled, unlabelled
    for t in p.tables:
        assert t["caption"], t
        assert all(s in ("col", "row") for s in t["header_scopes"]), t
    assert all(img.get("alt") for img in p.images), p.images


def test_the_index_lists_every_body_of_the_catalogue(client):
    p = _page(client, "/")
    names = [b["name"] for b in client.get("/v1/bodies").json()]
    for name in names:
        assert f"/bodies/{name}?dataset=current" in p.links, name
    _accessible(p)
    other = _page(client, "/?dataset=petit2014")
    assert "/bodies/Itokawa?dataset=petit2014" in other.links


@pytest.mark.parametrize("body", ["vesta", "earth", "moon"])
def test_a_body_page_shows_the_apis_precession(client, body):
    p = _page(client, f"/bodies/{body}")
    want = client.get(f"/v1/bodies/{body}/precession").json()
    for key in ("precession_rate_arcsec_per_year", "obliquity_deg", "dynamical_ellipticity",
                "scaling_factor_arcsec_per_year"):
        shown = float(p.by_id[key]["text"])
        assert shown == pytest.approx(want[key], rel=5e-12), key      # printed to 12 significant digits
    _accessible(p)
    # the nutation tables' downloads are the API's, and answer
    downloads = [u for u in p.links if "/nutation?" in u and "format=" in u and "format=ecsv" not in u]
    assert {(parse_qs(urlsplit(u).query)["format"][0], parse_qs(urlsplit(u).query)["layout"][0]) for u in downloads} \
        == {(f, layout) for f in ("csv", "markdown", "latex") for layout in ("sin-cos", "amp-period")}
    for u in downloads:
        assert client.get(urlsplit(u).path + "?" + urlsplit(u).query).status_code == 200


def test_the_body_page_shows_every_nutation_term_and_the_facts_with_their_sources(client):
    p = _page(client, "/bodies/vesta")
    nutation = client.get("/v1/bodies/vesta/nutation").json()
    terms_table = next(t for t in p.tables if "nutation terms" in t["caption"])
    assert f"({len(nutation['terms'])})" in terms_table["caption"]
    facts = next(t for t in p.tables if "catalogue values" in t["caption"])
    assert facts["caption"].startswith("vesta's") or facts["caption"].startswith("Vesta's")


def test_a_track_page_shows_the_apis_track_and_its_model(client):
    q = "start=2020-01-01&stop=2021-01-01&step_days=5&tolerance_mas=1000"
    p = _page(client, f"/bodies/vesta/track?{q}")
    want = client.get(f"/v1/bodies/vesta/track?{q}").json()
    count = len(want["jd_tdb"])
    rows_table = next(t for t in p.tables if "track, the first" in t["caption"])
    assert f"the first {min(count, TRACK_ROWS_SHOWN)} of {count} epochs" in rows_table["caption"]
    # the CSV download is the API's whole track
    csv_url = next(u for u in p.links if "format=csv" in u)
    parts = urlsplit(csv_url)
    rows = list(csv.DictReader(io.StringIO(client.get(parts.path + "?" + parts.query).text)))
    assert len(rows) == count
    assert float(rows[0]["pole_ra_deg"]) == pytest.approx(want["pole_ra_deg"][0], rel=1e-12)
    # the plot is the API's figure of the same track (SVG: it scales with the page)
    (img,) = p.images
    src = urlsplit(img["src"])
    assert src.path == "/v1/bodies/Vesta/track.svg"
    assert parse_qs(src.query) == {k: v for k, v in parse_qs(parts.query).items()       # every parameter but the
                                   if k not in ("format", "time_scale")}                # dates' scale (no figure's)
    r = client.get(src.path + "?" + src.query)
    assert r.status_code == 200 and r.headers["content-type"] == "image/svg+xml"
    _accessible(p)


def test_the_track_pages_first_rows_are_the_apis_numbers(client):
    q = {"start": "2020-01-01", "stop": "2020-06-01", "step_days": "10"}
    r = client.get("/bodies/ceres/track", params=q)
    want = api.track_arrays("ceres", q["start"], q["stop"], 10.0)
    text = r.text
    # the first row's pole RA, printed to 10 significant digits
    assert f"{float(want['pole_ra_deg'][0]):.10g}" in text
    assert f"{float(want['jd_tdb'][0]):.13g}" in text


def test_the_url_is_the_permalink(client):
    """The form's values come back from the URL: reloading or sharing it shows the same request."""
    q = "start=2030-01-01&stop=2030-06-01&step_days=7&model=series&order=4&axis=angular_momentum&dataset=petit2014"
    p = _page(client, f"/bodies/itokawa/track?{q}")
    assert p.by_id["start"]["value"] == "2030-01-01" and p.by_id["stop"]["value"] == "2030-06-01"
    assert p.by_id["step_days"]["value"] == "7" and p.by_id["order"]["value"] == "4"
    snippet_url = next(u for u in p.links if u.startswith("/v1/bodies/Itokawa/track?") and "format=" not in u)
    got = parse_qs(urlsplit(snippet_url).query)
    assert got["model"] == ["series"] and got["axis"] == ["angular_momentum"] and got["dataset"] == ["petit2014"]
    assert got["order"] == ["4"]
    assert client.get(urlsplit(snippet_url).path, params=got).status_code == 200     # the API answers it


def test_an_error_stands_at_its_field_with_the_apis_words(client):
    q = "start=2020-01-01&stop=2021-01-01&step_days=-1"
    p = _page(client, f"/bodies/vesta/track?{q}", status=422)
    problem = client.get(f"/v1/bodies/vesta/track?{q}").json()
    (err,) = problem["errors"]
    assert p.errors == {err["field"]: err["reason"]} and err["field"] == "step_days"
    assert problem["detail"] in p.alerts[0]          # and the whole problem above the form
    assert p.by_id["step_days"].get("aria-invalid") == "true"


def test_a_refusal_shows_the_apis_problem(client):
    p = _page(client, "/bodies/vulcan", status=404)
    assert any("Vulcan" in a or "vulcan" in a for a in p.alerts), p.alerts
    # over the budget: the same problem the API gives (here at the field it names), the estimate in its words
    # (the spin integrated through ~2000 orbits of Itokawa, 1500 years either side of J2000: ~10 s predicted)
    q = "start=1903670&stop=2999420&step_days=1000&model=numerical"
    api_problem = client.get(f"/v1/bodies/itokawa/track?{q}").json()
    assert api_problem["type"].endswith("over-budget")
    page = _page(client, f"/bodies/itokawa/track?{q}", status=api_problem["status"])
    assert page.errors == {e["field"]: e["reason"] for e in api_problem["errors"]}
    assert "estimated" in " ".join(page.errors.values())


def test_the_moons_page_shows_its_cassini_state_and_the_earths_its_lunisolar_terms(client):
    moon = _page(client, "/bodies/moon")
    want = client.get("/v1/bodies/moon/precession").json()["cassini"]
    for key, value in want.items():
        assert float(moon.by_id[f"cassini.{key}"]["text"]) == pytest.approx(value, rel=5e-10), key
    text = client.get("/bodies/earth").text
    earth = Page(text)
    nutation = client.get("/v1/bodies/earth/nutation").json()
    terms = next(t for t in earth.tables if "nutation terms" in t["caption"])
    assert f"({len(nutation['terms'])})" in terms["caption"]
    # each lunisolar term is named by its Delaunay multipliers (l, l', F, D, Omega), as the API gives them
    first = nutation["terms"][0]
    assert f'<th scope="row">{" ".join(str(k) for k in first["delaunay_multipliers"])}</th>' in text


def test_the_track_page_charts_every_model_against_its_cost(client):
    q = {"start": "2020-01-01", "stop": "2025-01-01", "step_days": "10", "tolerance_mas": "100"}
    text = client.get("/bodies/vesta/track", params=q).text
    p = Page(text)
    table = next(t for t in p.tables if "Every model of" in t["caption"])
    want = api.track_models("vesta", q["start"], q["stop"], 10.0, tolerance_mas=100.0)
    assert f"over these {want['epochs']} epochs" in table["caption"]
    assert text.count('<tr class="chosen">') == 1
    (chosen,) = [m for m in want["models"] if m["chosen"]]
    row = text.split('<tr class="chosen">', 1)[1].split("</tr>", 1)[0]
    assert f">{chosen['name']}<" in row and f"{chosen['estimated_error_mas']:.4g}" in row
    assert f"{chosen['estimated_cpu_ms']:.3g}" in row


def test_the_track_page_draws_the_models_chart_inline_with_the_table_folded(client):
    """The chart is the API's SVG of the same query, inline (its points' hover titles kept, no second request),
    described in words; the table is kept, folded in <details> under it."""
    import xml.etree.ElementTree as ET

    q = {"start": "2020-01-01", "stop": "2021-01-01", "step_days": "10", "tolerance_mas": "100"}
    text = client.get("/bodies/vesta/track", params=q).text
    figure = text.split('<figure class="chart" id="models-chart">', 1)[1].split("</figure>", 1)[0]
    inline = ET.fromstring(figure[figure.index("<svg"):figure.index("</svg>") + len("</svg>")])
    api_svg = ET.fromstring(client.get("/v1/bodies/vesta/track/models.svg", params=q).content)
    svg = "{http://www.w3.org/2000/svg}"

    def titles(root):
        return [(g.get("id"), g.get("class"), g.find(f"{svg}title").text) for g in root.iter(f"{svg}g")
                if (g.get("id") or "").startswith("wp-point-")]
    assert titles(inline) == titles(api_svg) and len(titles(inline)) > 30
    assert inline.get("role") == "img" and inline.get("aria-labelledby") == "wp-title wp-desc"
    assert inline.find(f"{svg}desc").text == api_svg.find(f"{svg}desc").text        # its text alternative
    assert inline.get("width") == "100%" and inline.get("viewBox") == api_svg.get("viewBox")
    assert "<figcaption>" in figure and "/track/models.svg?" in figure and "/track/models?" in figure
    details = text.split("<details>", 1)[1].split("</details>", 1)[0]
    assert "Every model of" in details and details.count('<tr class="chosen">') == 1
    assert text.index("</figure>", text.index('id="models-chart"')) < text.index("<details>")
    _accessible(Page(text))


def test_the_track_pages_comparison_table_says_each_models_row_as_the_api(client):
    """Each row of the folded comparison is its model's, in the API's order: its name, e-order, estimate (4
    significant digits) and predicted cost (3), Eligible as the API's rows say (the chart's rule), Chosen, and the
    row marked chosen, or refused where the model is unavailable or not eligible: a model's row never takes another's
    eligibility."""
    import html
    import re

    q = {"start": "2020-01-01", "stop": "2025-01-01", "step_days": "10", "tolerance_mas": "30"}
    text = client.get("/bodies/vesta/track", params=q).text
    details = text.split("<details>", 1)[1].split("</details>", 1)[0]
    body = details.split("<tbody>", 1)[1].split("</tbody>", 1)[0]
    rows = re.findall(r"<tr(?: class=\"(\w+)\")?><th scope=\"row\">([^<]*)</th>(.*?)</tr>", body, flags=re.S)
    want = client.get("/v1/bodies/vesta/track/models", params=q).json()
    eligible = [r["eligible"] for r in api.track_models_rows(want)]
    assert len(rows) == len(want["models"]) > 30
    assert set(eligible) == {True, False}         # the tolerance admits some models and not others
    for (mark, name, cells), m, ok in zip(rows, want["models"], eligible):
        assert name == m["name"]
        tds = [html.unescape(" ".join(x.split())) for x in re.findall(r"<td[^>]*>(.*?)</td>", cells, flags=re.S)]
        assert tds[0] == ("" if m["order"] is None else str(m["order"]))
        if m["available"]:
            error, cpu = float(tds[2]), float(tds[3])
            assert error == pytest.approx(m["estimated_error_mas"], rel=5e-4)      # 4 significant digits
            assert cpu == pytest.approx(m["estimated_cpu_ms"], rel=5e-3)           # 3
        else:
            assert tds[2] == f"not available: {m['why_not']}"
        assert tds[-2:] == ["yes" if ok else "no", "yes" if m["chosen"] else ""]
        assert mark == ("chosen" if m["chosen"] else "refused" if not (m["available"] and ok) else "")


def test_a_history_page_shows_the_apis_history(client):
    q = {"start_year": "-20000", "stop_year": "0", "step_years": "500"}
    text = client.get("/bodies/ceres/history", params=q).text
    p = Page(text)
    want = client.get("/v1/bodies/ceres/history", params=q).json()
    table = next(t for t in p.tables if "history, the first" in t["caption"])
    assert f"of {len(want['year'])} epochs" in table["caption"]
    # the estimate in the unit of the answer's per-epoch estimates (deg), the largest of them
    assert f"{want['obliquity_deg'][0]:.8g}" in text and f"{max(want['estimated_error_deg']):.4g}°" in text
    (img,) = p.images
    src = urlsplit(img["src"])
    r = client.get(src.path + "?" + src.query)
    assert r.status_code == 200 and r.headers["content-type"] == "image/svg+xml"
    _accessible(p)
    # the body page links here through its form
    assert 'action="/bodies/Ceres/history"' in client.get("/bodies/ceres").text


def test_a_history_refused_by_the_api_is_refused_at_its_field(client):
    q = {"start_year": "0", "stop_year": "-100", "step_years": "10"}          # stop before start
    api_problem = client.get("/v1/bodies/ceres/history", params=q).json()
    p = _page(client, "/bodies/ceres/history?" + "&".join(f"{k}={v}" for k, v in q.items()),
              status=api_problem["status"])
    assert p.errors == {e["field"]: e["reason"] for e in api_problem["errors"]}


def test_the_track_page_follows_the_free_wobble_it_is_given(client):
    # a named model adds the wobble whenever its phase is given (the API's rule)
    q = {"start": "2030-01-01", "stop": "2030-03-01", "step_days": "1", "model": "hansen",
         "free_wobble_phase_deg": "30"}
    p = _page(client, "/bodies/mars/track?" + "&".join(f"{k}={v}" for k, v in q.items()))
    want = client.get("/v1/bodies/mars/track", params=q).json()["model"]
    assert p.by_id["free_wobble_phase_deg"]["value"] == "30"
    assert want["free_wobble"]["phase_deg"] == 30.0
    assert f"J = {want['free_wobble']['J_arcsec']:.6g}″" in p.by_id["free-wobble"]["text"]
    plain = _page(client, "/bodies/mars/track?start=2030-01-01&stop=2030-03-01&step_days=1&model=hansen")
    assert "free-wobble" not in plain.by_id


def _my_body_query(user: dict) -> dict:
    q = {"name": user["name"], "rotation_period_hours": str(user["rotation_period_hours"])}
    for group in ("orbit", "pole", "moments"):
        q.update({f"{group}.{k}": str(v) for k, v in user.get(group, {}).items()})
    return q


def test_a_body_of_ones_own_is_the_posts(client):
    """The form's fields are the POST's, validated by the same model; the numbers are the POST's answer."""
    from service.schemas import UserBody

    user = {k: v for k, v in UserBody.model_config["json_schema_extra"]["examples"][0].items() if k != "track"}
    empty = _page(client, "/my-body")                       # the form starts from the POST's example
    assert empty.by_id["orbit.a_au"]["value"] == str(user["orbit"]["a_au"])
    _accessible(empty)
    r = client.get("/my-body", params=_my_body_query(user))
    assert r.status_code == 200, r.text[:500]
    p = Page(r.text)
    want = client.post("/v1/precession-nutation", json=user).json()["precession"]
    for key in ("precession_rate_arcsec_per_year", "obliquity_deg", "dynamical_ellipticity"):
        assert float(p.by_id[key]["text"]) == pytest.approx(want[key], rel=5e-12), key
    _accessible(p)
    # refused as the POST refuses it, at the same field path
    bad = {**user, "orbit": {**user["orbit"], "e": 1.5}}
    problem = client.post("/v1/precession-nutation", json=bad).json()
    r = client.get("/my-body", params=_my_body_query(bad))
    assert r.status_code == problem["status"] == 422
    assert Page(r.text).errors == {e["field"]: e["reason"] for e in problem["errors"]} and "orbit.e" in Page(r.text).errors


BATCH_CSV = ("name,a_au,e,i_deg,node_deg,peri_deg,mean_anomaly_deg,epoch_jd_tdb,pole_ra_deg,pole_dec_deg,"
             "rotation_period_hours,dynamical_ellipticity\n"
             "testa,2.36,0.09,7.1,103.7,151.7,169.2,2460200.5,309.03,42.23,5.342,0.1689\n"
             "testb,2.77,0.08,10.6,80.3,73.6,77.4,2460200.5,291.4,66.8,9.07,0.07\n"
             "broken,2.5,0.1,5,10,20,30,2460200.5,100,20,oops,0.1\n")


def test_a_batch_uploaded_is_the_batch_routes(client):
    """The uploaded CSV answered as POST /v1/batch answers the same CSV; the download holds every row."""
    from urllib.parse import unquote

    form = _page(client, "/batch")
    _accessible(form)
    r = client.post("/batch", files={"file": ("bodies.csv", BATCH_CSV, "text/csv")})
    assert r.status_code == 200, r.text[:500]
    want = client.post("/v1/batch", content=BATCH_CSV.encode(), headers={"content-type": "text/csv"}).json()
    p = Page(r.text)
    _accessible(p)
    href = next(u for u in p.links if u.startswith("data:text/csv"))
    got = list(csv.DictReader(io.StringIO(unquote(href.split(",", 1)[1]))))
    assert [g["name"] for g in got] == [w["name"] for w in want["rows"]] == ["testa", "testb", "broken"]
    for g, w in zip(got, want["rows"]):
        for column in want["columns"]:
            if isinstance(w[column], float):
                assert float(g[column]) == pytest.approx(w[column], rel=1e-15), column
            else:
                assert g[column] == ("" if w[column] is None else str(w[column])), column
    assert "1 with an error" in r.text and want["rows"][2]["error"]


def test_a_malformed_batch_is_refused_at_the_file_with_the_routes_words(client):
    bad = "name,a_au\nr,1,2\n"
    problem = client.post("/v1/batch", content=bad.encode(), headers={"content-type": "text/csv"}).json()
    r = client.post("/batch", files={"file": ("bad.csv", bad, "text/csv")})
    assert r.status_code == problem["status"] == 422
    (err,) = problem["errors"]
    assert Page(r.text).errors == {err["field"]: f"{err['field']}: {err['reason']}"}


def test_the_body_page_shows_the_observable_rate_beside_the_torques(client):
    p = _page(client, "/bodies/mars")
    want = client.get("/v1/bodies/mars/precession").json()
    assert float(p.by_id["observable_precession_rate_arcsec_per_year"]["text"]) == pytest.approx(
        want["observable_precession_rate_arcsec_per_year"], rel=5e-12)
    moon = _page(client, "/bodies/moon").by_id["observable_precession_rate_arcsec_per_year"]
    assert float(moon["text"]) == pytest.approx(client.get("/v1/bodies/moon/precession").json()[
        "precession_rate_arcsec_per_year"], rel=5e-12)
