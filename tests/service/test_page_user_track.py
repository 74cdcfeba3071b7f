"""A track for a body of one's own (issue 41, what a scientist expects: the own-body form answered precession and
nutation only): the form takes the POST's track object (start, stop, step, tolerance or model, axis), and the page
shows the POST's track, its model and estimate, its first rows, the whole track as a CSV download and its figure;
a bad track field stands at its field as the POST names it.
"""
from __future__ import annotations

import csv
import io
import re
from html.parser import HTMLParser
from urllib.parse import unquote

import pytest
from fastapi.testclient import TestClient

from ephem import api
from service.app import create_app
from service.schemas import UserBody
from service.settings import Settings

USER = {k: v for k, v in UserBody.model_config["json_schema_extra"]["examples"][0].items() if k != "track"}
TRACK = {"start": "2024-01-01", "stop": "2025-01-01", "step_days": 15, "tolerance_mas": 100}


def _query(user: dict, track: dict | None) -> dict:
    q = {"name": user["name"], "rotation_period_hours": str(user["rotation_period_hours"])}
    for group in ("orbit", "pole", "moments"):
        q.update({f"{group}.{k}": str(v) for k, v in user.get(group, {}).items()})
    q.update({f"track.{k}": str(v) for k, v in (track or {}).items()})
    return q


class Track(HTMLParser):
    def __init__(self, text: str):
        super().__init__()
        self.rows: list[list[str]] = []
        self.csv: str | None = None
        self.errors: dict[str, str] = {}
        self._in_track, self._row, self._cell, self._err = False, None, None, None
        self.feed(text)

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "caption":
            self._caption = ""
        if tag == "a" and (a.get("href") or "").startswith("data:text/csv"):
            self.csv = unquote(a["href"].split(",", 1)[1])
        if tag == "tr" and self._in_track:
            self._row = []
        if tag in ("th", "td") and self._row is not None:
            self._cell = ""
        if a.get("class") == "field-error":
            self._err = [a["id"].removesuffix("-error"), ""]

    def handle_endtag(self, tag):
        if tag == "caption":
            self._in_track = "track, the first" in self._caption
            self._caption = None
        elif tag in ("th", "td") and self._cell is not None and self._row is not None:
            self._row.append(self._cell.strip())
            self._cell = None
        elif tag == "tr" and self._row is not None:
            if self._row and not self._row[0].startswith("jd"):
                self.rows.append(self._row)
            self._row = None
        elif tag == "table":
            self._in_track = False
        elif tag == "span" and self._err:
            self.errors[self._err[0]] = self._err[1].strip()
            self._err = None

    def handle_data(self, data):
        if getattr(self, "_caption", None) is not None:
            self._caption += data
        if self._cell is not None:
            self._cell += data
        if self._err:
            self._err[1] += data


@pytest.fixture(scope="module")
def client():
    with TestClient(create_app(Settings(warm_up=False))) as c:
        yield c


def test_the_page_shows_the_posts_track_its_rows_csv_and_figure(client):
    want = client.post("/v1/precession-nutation", json={**USER, "track": TRACK}).json()["track"]
    r = client.get("/my-body", params=_query(USER, TRACK))
    assert r.status_code == 200, r.text[:500]
    page = Track(r.text)
    count = len(want["jd_tdb"])
    assert f"<strong>{want['model']['name']}</strong>" in r.text and f"of {count} epochs" in r.text
    assert len(page.rows) == min(count, 20)
    for row, i in zip(page.rows, range(count)):
        assert float(row[0]) == pytest.approx(want["jd_tdb"][i], rel=5e-13)         # 13 significant digits
        assert float(row[-2]) == pytest.approx(want["pole_ra_deg"][i], rel=5e-10)   # 10
    rows = list(csv.DictReader(io.StringIO(page.csv)))
    assert [k for k in rows[0]] == list(api.TRACK_KEYS) and len(rows) == count
    assert [float(x["pole_dec_deg"]) for x in rows] == want["pole_dec_deg"]          # repr: the same doubles
    figure = r.text.split('id="user-track-chart"', 1)[1].split("</figure>", 1)[0]
    assert '<svg role="img" aria-labelledby="user-track-caption"' in figure and 'id="user-track-caption"' in figure


def test_no_track_without_a_start_and_a_bad_track_field_at_its_field(client):
    r = client.get("/my-body", params=_query(USER, None))
    assert r.status_code == 200 and 'id="user-track"' not in r.text
    bad = {**TRACK, "step_days": -1}
    problem = client.post("/v1/precession-nutation", json={**USER, "track": bad}).json()
    page = Track(client.get("/my-body", params=_query(USER, bad)).text)
    assert page.errors == {e["field"]: e["reason"] for e in problem["errors"]} and "track.step_days" in page.errors
