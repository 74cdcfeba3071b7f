"""The service's tables as astropy's ECSV and its dates as people read them (issue 41).

Every table route answers ``format=ecsv`` (``text/x-ecsv``, saved under a name that says body, dataset and table):
``QTable.read`` of the text gives Quantity columns in the units the keys name, ``jd_tdb`` as a TDB ``Time``, and the
same numbers as the route's JSON for the same query (one ulp: a double's repr reads back to itself;
tests/exports/test_qtable.py's check). Every track and free motion carries its calendar dates beside ``jd_tdb`` in the
scale ``time_scale`` names (utc by default), in JSON, CSV (one header line) and ECSV.
"""
from __future__ import annotations

import csv
import io

import pytest
from fastapi.testclient import TestClient

from service.app import create_app
from service.settings import Settings
from tests.exports.test_qtable import USER_ROWS, check_read_back


@pytest.fixture(scope="module")
def client():
    with TestClient(create_app(Settings(warm_up=False))) as c:
        yield c


TRACK = {"start": "2040-01-01", "stop": "2040-03-01", "step_days": 20}
HISTORY = {"start_year": -1000, "stop_year": 0, "step_years": 250}
#: (path, query, the saved file's name)
ROUTES = [
    ("/v1/bodies", {}, "bodies_current.ecsv"),
    ("/v1/bodies", {"dataset": "petit2014"}, "bodies_petit2014.ecsv"),
    ("/v1/bodies/vesta/precession", {}, "vesta_current_precession.ecsv"),
    ("/v1/bodies/earth/precession", {}, "earth_current_precession.ecsv"),
    ("/v1/bodies/moon/precession", {}, "moon_current_precession.ecsv"),
    ("/v1/bodies/vesta/nutation", {"order": 4}, "vesta_current_nutation.ecsv"),
    ("/v1/bodies/earth/nutation", {}, "earth_current_nutation.ecsv"),
    ("/v1/bodies/ceres/track", TRACK, "ceres_current_track.ecsv"),
    ("/v1/bodies/ceres/track", {**TRACK, "time_scale": "tt"}, "ceres_current_track.ecsv"),
    ("/v1/bodies/mars/track", {**TRACK, "time_scale": "tdb", "free_wobble_phase_deg": 30}, "mars_current_track.ecsv"),
    ("/v1/bodies/ceres/history", HISTORY, "ceres_current_history.ecsv"),
    ("/v1/bodies/mars/free-motion", {"start": "2030-01-01", "stop": "2030-01-03", "step_days": 0.5},
     "mars_current_free-motion.ecsv"),
]


@pytest.mark.parametrize("path, query, name", ROUTES, ids=[f"{p}?{q}" for p, q, _ in ROUTES])
def test_every_table_route_answers_ecsv_that_astropy_reads_as_its_json(client, path, query, name):
    answer = client.get(path, params=query)
    assert answer.status_code == 200, answer.text[:300]
    r = client.get(path, params={**query, "format": "ecsv"})
    assert r.status_code == 200, r.text[:300]
    assert r.headers["content-type"] == "text/x-ecsv; charset=utf-8"
    assert r.headers["content-disposition"] == f'attachment; filename="{name}"'
    check_read_back(r.text, answer.json(), source=str(r.url), ordered=False)


@pytest.mark.parametrize("content", ["json", "csv"])
def test_the_batch_answers_ecsv_as_its_json(client, content):
    if content == "json":
        kwargs = {"json": USER_ROWS}
    else:
        out = io.StringIO()
        writer = csv.DictWriter(out, fieldnames=sorted({k for r in USER_ROWS for k in r}))
        writer.writeheader()
        writer.writerows(USER_ROWS)
        kwargs = {"content": out.getvalue().encode(), "headers": {"content-type": "text/csv"}}
    answer = client.post("/v1/batch", **kwargs)
    assert answer.status_code == 200, answer.text[:300]
    r = client.post("/v1/batch", params={"format": "ecsv"}, **kwargs)
    assert r.status_code == 200, r.text[:300]
    assert r.headers["content-disposition"] == 'attachment; filename="batch.ecsv"'
    table = check_read_back(r.text, answer.json(), source=str(r.url))
    assert table["error"][1].startswith("e:")               # the unbound row: its reason, nulls elsewhere


@pytest.mark.parametrize("scale", ["utc", "tt", "tdb"])
def test_a_track_shows_its_dates_in_the_scale_asked(client, scale):
    track = client.get("/v1/bodies/ceres/track", params={**TRACK, "time_scale": scale}).json()
    keys = list(track)
    assert keys[keys.index("jd_tdb") + 1] == f"{scale}_iso"          # beside jd_tdb
    assert not {"utc_iso", "tt_iso", "tdb_iso"} - {f"{scale}_iso"} & set(keys)
    first = {"utc": "2040-01-01T00:00:00.000", "tt": "2040-01-01T00:01:09.184", "tdb": "2040-01-01T00:01:09.184"}
    assert track[f"{scale}_iso"][0] == first[scale]             # TT = UTC + 69.184 s; TDB - TT < 2 ms
    assert len(track[f"{scale}_iso"]) == len(track["jd_tdb"])


def test_the_track_csv_keeps_one_header_line_with_the_dates(client):
    r = client.get("/v1/bodies/ceres/track", params={**TRACK, "format": "csv", "time_scale": "tt"})
    rows = list(csv.reader(io.StringIO(r.text)))
    assert rows[0][:2] == ["jd_tdb", "tt_iso"] and len(rows) == 1 + 4
    json_track = client.get("/v1/bodies/ceres/track", params={**TRACK, "time_scale": "tt"}).json()
    assert [row[1] for row in rows[1:]] == json_track["tt_iso"]
    assert [float(row[0]) for row in rows[1:]] == json_track["jd_tdb"]      # repr round trip: the same doubles


def test_the_free_motion_shows_its_dates(client):
    ans = client.get("/v1/bodies/mars/free-motion", params={"start": "2030-01-01", "stop": "2030-01-02",
                                                            "step_days": 0.5, "time_scale": "utc"}).json()
    assert ans["utc_iso"] == ["2030-01-01T00:00:00.000", "2030-01-01T12:00:00.000", "2030-01-02T00:00:00.000"]


def test_a_posted_body_s_track_takes_a_time_scale(client):
    from tests.service.test_route_matrix import USER_ASTEROID

    body = {**USER_ASTEROID, "track": {**TRACK, "time_scale": "tt"}}
    ans = client.post("/v1/precession-nutation", json=body).json()
    assert ans["track"]["tt_iso"][0] == "2040-01-01T00:01:09.184" and "utc_iso" not in ans["track"]


@pytest.mark.parametrize("path", ["/v1/bodies/ceres/track", "/v1/bodies/mars/free-motion"])
def test_another_time_scale_is_refused_naming_it(client, path):
    r = client.get(path, params={**TRACK, "step_days": 30, "time_scale": "ut1"})
    assert r.status_code == 422
    assert [e["field"] for e in r.json()["errors"]] == ["time_scale"]


def test_the_openapi_document_offers_ecsv_and_the_time_scale(client):
    doc = client.get("/openapi.json").json()
    for path, method in [("/v1/bodies", "get"), ("/v1/bodies/{body}/precession", "get"),
                         ("/v1/bodies/{body}/nutation", "get"), ("/v1/bodies/{body}/track", "get"),
                         ("/v1/bodies/{body}/history", "get"), ("/v1/bodies/{body}/free-motion", "get"),
                         ("/v1/batch", "post")]:
        op = doc["paths"][path][method]
        assert "text/x-ecsv" in op["responses"]["200"]["content"], path
    track = {p["name"]: p for p in doc["paths"]["/v1/bodies/{body}/track"]["get"]["parameters"]}
    assert "time_scale" in track
    assert {"utc_iso", "tt_iso", "tdb_iso"} <= set(doc["components"]["schemas"]["Track"]["properties"])


# ------------------------------------------------------------------ the page

def _links(html: str) -> dict[str, str]:
    """{href: download name} of the page's download links."""
    from html.parser import HTMLParser

    found = {}

    class Parse(HTMLParser):
        def handle_starttag(self, tag, attrs):
            a = dict(attrs)
            if tag == "a" and a.get("download"):
                found[a["href"]] = a["download"]
    Parse().feed(html)
    return found


def test_the_track_page_chooses_the_dates_scale_and_offers_ecsv(client):
    from html import unescape

    html = client.get("/bodies/ceres/track", params={**TRACK, "time_scale": "tt"}).text
    assert '<select id="time_scale" name="time_scale">' in html
    assert '<option value="tt" selected>TT</option>' in html and '<option value="utc">UTC</option>' in html
    assert ">tt_iso</th>" in html and "2040-01-01T00:01:09.184" in html       # the column beside jd_tdb
    (ecsv,) = [(h, d) for h, d in _links(html).items() if "format=ecsv" in h]
    assert ecsv[1] == "ceres_current_track.ecsv"
    r = client.get(unescape(ecsv[0]))
    assert r.status_code == 200 and r.headers["content-type"].startswith("text/x-ecsv")
    assert r.text.count("tt_iso") >= 1 and "2040-01-01T00:01:09.184" in r.text      # the page's scale


@pytest.mark.parametrize("page, names", [
    ("/bodies/vesta", {"vesta_current_precession.ecsv", "vesta_current_nutation.ecsv"}),
    ("/bodies/ceres/history?start_year=-1000&stop_year=0&step_years=250", {"ceres_current_history.ecsv"})])
def test_the_pages_offer_their_tables_as_ecsv(client, page, names):
    from html import unescape

    links = {d: h for h, d in _links(client.get(page).text).items() if d.endswith(".ecsv")}
    assert set(links) == names
    for href in links.values():
        r = client.get(unescape(href))
        assert r.status_code == 200 and r.headers["content-type"].startswith("text/x-ecsv"), href


def test_the_history_page_says_its_years_are_julian_years_of_tdb(client):
    html = client.get("/bodies/ceres/history", params=HISTORY).text
    assert "Julian years of 365.25 days from J2000.0 TDB" in html


def test_the_batch_page_offers_its_answers_as_ecsv(client):
    from urllib.parse import unquote

    from astropy.table import QTable

    out = io.StringIO()
    writer = csv.DictWriter(out, fieldnames=sorted({k for r in USER_ROWS for k in r}))
    writer.writeheader()
    writer.writerows(USER_ROWS)
    html = client.post("/batch", files={"file": ("bodies.csv", out.getvalue(), "text/csv")}).text
    (href, name), = [(h, d) for h, d in _links(html).items() if d.endswith(".ecsv")]
    assert name == "bodies_batch_answers.ecsv" and href.startswith("data:text/x-ecsv;charset=utf-8,")
    table = QTable.read(unquote(href.partition(",")[2]), format="ascii.ecsv")
    assert list(table["name"]) == ["my-asteroid", "unbound"] and str(table["obliquity_deg"].unit) == "deg"
