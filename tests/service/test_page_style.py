"""The pages' look (issue 41, "a look that reads as a reference work"), on the parsed HTML and the stylesheet's text:
every page links the project's one stylesheet (and no other); the stylesheet right-aligns class ``num`` in a
monospace font, marks the chosen model and the refusals, has a dark scheme and a print style, and fetches nothing;
every number in a table carries ``num`` (and only numbers do), and a header of its column or row names its unit;
the chosen model's row is marked ``chosen``, each model outside the tolerance or not available ``refused``, a batch
row with an error ``refused``, and a not-applicable problem ``refusal`` (an input error is not).

The browser's side (computed alignment and font, the print media) is tests/service/test_browser_style.py.
"""
from __future__ import annotations

import re
from html.parser import HTMLParser

import pytest
from fastapi.testclient import TestClient

from service.app import create_app
from service.settings import Settings
from tests.service.test_page_user_track import TRACK, USER, _query
from tests.service.test_pages import BATCH_CSV

STYLESHEET = "/static/page/page.css"
#: a number as the page prints it (the ``num`` filter: ``%g``), with the page's minus sign if any
NUMBER = re.compile(r"^[-+−]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$")
#: what else a ``num`` cell may hold: nothing, "—" (no value), a lower bound "≥ 1e-9, why", a pointer "none (2)",
#: an ISO 8601 date beside its Julian date (digits that line up as well)
NUM_CELL = re.compile(r"^(|—|≥ ?[-+]?[\d.]+(e[-+]?\d+)?\b.*|none \(\d+\)|[-+]?\d{4,}-\d\d-\d\dT\d\d:\d\d:\d\d(\.\d+)?)$")
#: a unit named in a header (its text, "_" read as a space): the API's unit suffixes and the page's own words
UNIT = re.compile(r"\b(deg|arcsec|mas|days?|d|au|AU|h|hours|ms|km|yr|years?|jd|dimensionless)\b|″")
#: the API's keys without a unit suffix (its convention: a key without a unit is a pure number)
DIMENSIONLESS_KEYS = re.compile(r"^(dynamical_ellipticity|nutation_\d+_multiple)$")

EARTH_TRACK = ("/bodies/earth/track?start=2000-01-01&stop=2030-01-01&step_days=3650&tolerance_mas=10"
               "&axis=forced_figure")
#: no model meets 1 mas over two centuries of Vesta: a 422 not-applicable shown on the track page
REFUSED_TRACK = "/bodies/vesta/track?start=2000-01-01&stop=2200-01-01&step_days=365&tolerance_mas=1"
PAGES = {"index": "/", "body": "/bodies/vesta", "moon": "/bodies/moon", "track": EARTH_TRACK,
         "history": "/bodies/ceres/history?start_year=-20000&stop_year=0&step_years=500", "batch": "/batch",
         "my-body": "/my-body", "about": "/about", "accuracy": "/docs/accuracy", "refused": REFUSED_TRACK,
         "invalid": "/bodies/vesta/track?start=2020-01-01&stop=2021-01-01&step_days=-1",
         "unknown body": "/bodies/vulcan"}
DOCUMENTS = {"accuracy"}


class Tables(HTMLParser):
    """The stylesheets a page links, its tables (each row's cells: tag, classes, text, colspan; each row's
    classes; the header row) and the classes of its problem paragraphs."""

    def __init__(self, html: str):
        super().__init__()
        self.stylesheets: list[str] = []
        self.tables: list[dict] = []
        self.problems: list[set[str]] = []
        self._cell: dict | None = None
        self._section: str | None = None
        self.feed(html)

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        classes = set((a.get("class") or "").split())
        if tag == "link" and "stylesheet" in (a.get("rel") or "").split():
            self.stylesheets.append(a.get("href"))
        elif tag == "table":
            self.tables.append({"head": [], "rows": []})
        elif tag in ("thead", "tbody") and self.tables:
            self._section = tag
        elif tag == "tr" and self.tables and self._section == "tbody":
            self.tables[-1]["rows"].append({"classes": classes, "cells": []})
        elif tag in ("td", "th") and self.tables and self._section:
            self._cell = {"tag": tag, "classes": classes, "text": "", "span": int(a.get("colspan", 1)),
                          "scope": a.get("scope")}
        elif "problem" in classes:
            self.problems.append(classes)

    def handle_endtag(self, tag):
        if tag in ("td", "th") and self._cell is not None:
            cell, self._cell = self._cell, None
            cell["text"] = " ".join(cell["text"].split())
            if self._section == "thead":
                self.tables[-1]["head"].append(cell)
            elif self.tables[-1]["rows"]:
                self.tables[-1]["rows"][-1]["cells"].append(cell)
        elif tag in ("thead", "tbody"):
            self._section = None

    def handle_data(self, data):
        if self._cell is not None:
            self._cell["text"] += data


def _columns(cells: list[dict]) -> list[dict]:
    """The cells of a row by column (a cell spanning two columns stands in both)."""
    return [c for c in cells for _ in range(c["span"])]


def _pages_own_tables(pages: dict) -> list:
    """The pages whose tables the templates write (a document's tables are its Markdown's, headers and all: their
    number cells take class num as they are rendered, tested with the rest)."""
    return [(name, page) for name, page in pages.items() if name not in DOCUMENTS]


@pytest.fixture(scope="module")
def client():
    with TestClient(create_app(Settings(warm_up=False))) as c:
        yield c


@pytest.fixture(scope="module")
def pages(client) -> dict[str, Tables]:
    got = {name: client.get(path) for name, path in PAGES.items()}
    got["batch answered"] = client.post("/batch", files={"file": ("bodies.csv", BATCH_CSV, "text/csv")})
    got["my-body track"] = client.get("/my-body", params=_query(USER, TRACK))
    for name, r in got.items():
        assert r.headers["content-type"].startswith("text/html"), (name, r.status_code)
    return {name: Tables(r.text) for name, r in got.items()}


@pytest.fixture(scope="module")
def css(client) -> str:
    r = client.get(STYLESHEET)
    assert r.status_code == 200 and r.headers["content-type"].startswith("text/css")
    return re.sub(r"/\*.*?\*/", "", r.text, flags=re.S)


def _rules(css: str) -> dict[str, str]:
    """Each selector's declarations, '@media X' blocks as 'X selector' (every selector of a group its own key)."""
    out: dict[str, str] = {}

    def walk(text: str, prefix: str):
        i = 0
        while True:
            m = re.compile(r"([^{}]+)\{").search(text, i)
            if not m:
                return
            head, depth, j = m.group(1).strip(), 1, m.end()
            while depth:
                depth += {"{": 1, "}": -1}.get(text[j], 0)
                j += 1
            body = text[m.end():j - 1]
            if head.startswith("@media"):
                walk(body, prefix + head.removeprefix("@media").strip() + " ")
            else:
                for selector in head.split(","):
                    key = prefix + " ".join(selector.split())
                    out[key] = out.get(key, "") + body
            i = j

    walk(css, "")
    return out


def test_every_page_links_the_one_stylesheet(pages):
    for name, page in pages.items():
        assert page.stylesheets == [STYLESHEET], (name, page.stylesheets)


def test_the_stylesheet_is_the_projects_own_and_fetches_nothing(css):
    assert "@import" not in css and not re.search(r"url\(", css), "the stylesheet loads nothing else"
    assert not re.search(r"https?:", css)


def test_the_stylesheet_right_aligns_numbers_in_monospace_and_marks_the_choices(css):
    rules = _rules(css)
    num = rules[".num"]
    assert re.search(r"text-align:\s*right", num) and "tabular-nums" in num
    family = re.search(r"font-family:\s*var\((--\w+)\)", num).group(1)
    assert re.search(rf"{family}:[^;]*\bmonospace\s*;", rules[":root"]), "the font list ends in monospace"
    body_family = re.search(r"font-family:\s*var\((--\w+)\)", rules["body"]).group(1)
    assert re.search(rf"{body_family}:\s*system-ui\b[^;]*sans-serif\s*;", rules[":root"])
    assert re.search(r"max-width:\s*70ch", rules["p"]), "prose at a measure of about 70 characters"
    for selector in ("tr.chosen > td", "tr.refused > td", ".problem.refusal"):
        assert re.search(r"background:\s*var\(", rules[selector]), selector
    assert re.search(r"color:", rules["tr.refused > td"]) and re.search(r"font-weight:\s*700", rules["tr.chosen > td"])


def test_the_stylesheet_has_a_dark_scheme_and_a_print_style(css):
    rules = _rules(css)
    light, dark = rules[":root"], rules["(prefers-color-scheme: dark) :root"]
    assert "color-scheme: light dark" in light
    names = set(re.findall(r"(--[\w-]+):\s*#", light))
    assert names and names == set(re.findall(r"(--[\w-]+):\s*#", dark)), "the dark scheme sets every colour"
    for hidden in ("header", "nav", "form", "button"):
        assert re.search(r"display:\s*none", rules[f"print {hidden}"]), hidden
    printed = rules["print :root"]
    assert re.search(r"--fg:\s*#000\b", printed) and re.search(r"--bg:\s*#fff\b", printed), "black on white"
    assert "break-inside: avoid" in rules["print table"] and "table-header-group" in rules["print thead"]
    assert 'attr(href)' in rules['print a[href*="/v1/"]::after'], "an API link's address printed after it"


def test_every_number_in_a_table_is_a_num_cell_and_only_numbers_are(pages):
    numbers = 0
    for name, page in pages.items():
        for table in page.tables:
            for row in table["rows"]:
                for cell in row["cells"]:
                    text, is_num = cell["text"], "num" in cell["classes"]
                    if NUMBER.match(text):
                        assert is_num, (name, cell)
                        numbers += 1
                    elif is_num:
                        assert NUM_CELL.match(text), (name, cell)
    assert numbers > 500                  # the pages' tables do hold numbers: the check bites


def test_every_number_has_its_unit_in_a_header(pages):
    """A number's unit stands in its column's header, its row's header, or its row's Unit cell (the body page's
    catalogue values); a pure number is said to be one (dimensionless, or an API key without a unit suffix)."""
    checked = 0
    for name, page in _pages_own_tables(pages):
        for table in page.tables:
            head = _columns(table["head"])
            headers = [h["text"] for h in head]
            for row in table["rows"]:
                cells = _columns(row["cells"])
                row_header = " ".join(c["text"] for c in cells if c["scope"] == "row")
                unit_cell = cells[headers.index("Unit")]["text"] if "Unit" in headers else ""
                for i, cell in enumerate(cells):
                    if not (NUMBER.match(cell["text"]) and cell["tag"] == "td"):
                        continue
                    column = headers[i] if i < len(headers) else ""
                    said = " ".join((column, row_header, unit_cell)).replace("_", " ")
                    assert UNIT.search(said) or DIMENSIONLESS_KEYS.match(column), (name, column, row_header)
                    checked += 1
    assert checked > 500


def test_a_column_of_numbers_has_a_num_header(pages):
    """The header of a column whose every cell is a number is aligned with it (class num)."""
    for name, page in _pages_own_tables(pages):
        for table in page.tables:
            head = _columns(table["head"])
            rows = [_columns(r["cells"]) for r in table["rows"]]
            for i, h in enumerate(head):
                column = [r[i] for r in rows if i < len(r)]
                if column and all(NUMBER.match(c["text"]) for c in column):
                    assert "num" in h["classes"], (name, h["text"])


def test_the_chosen_model_and_the_refused_ones_are_marked(pages):
    (models,) = [t for t in pages["track"].tables if [h["text"] for h in t["head"]][-2:] == ["Eligible", "Chosen"]]
    head = [h["text"] for h in models["head"]]
    kinds = []
    for row in models["rows"]:
        cells = {h: c["text"] for h, c in zip(head, _columns(row["cells"]))}
        chosen, eligible = cells["Chosen"] == "yes", cells["Eligible"] == "yes"
        available = "not available" not in " ".join(c["text"] for c in row["cells"])
        want = {"chosen"} if chosen else (set() if eligible and available else {"refused"})
        assert row["classes"] == want, (cells, row["classes"])
        kinds.append(frozenset(want))
    assert {frozenset({"chosen"}), frozenset({"refused"})} <= set(kinds)     # Earth at 10 mas: both kinds shown


def test_a_batch_row_with_an_error_is_refused(pages):
    (table,) = pages["batch answered"].tables
    marked = {row["cells"][0]["text"]: row["classes"] for row in table["rows"]}
    assert marked == {"testa": set(), "testb": set(), "broken": {"refused"}}


def test_a_not_applicable_problem_is_a_refusal_and_an_input_error_is_not(pages):
    assert pages["refused"].problems == [{"problem", "refusal"}]
    assert pages["invalid"].problems and all("refusal" not in p for p in pages["invalid"].problems)
    assert pages["unknown body"].problems and all("refusal" not in p for p in pages["unknown body"].problems)
