"""The documents the page links to, as HTML (service/docs_pages.py, issue 41: "Accuracy" served raw Markdown and its
six charts answered 404): every ``docs/*.md`` renders in the page's layout, its charts answer, its links to other
documents land on a heading that exists, nothing of the Markdown syntax is left, its tables scroll in their box.

Parsed with the standard library's HTMLParser.
"""
from __future__ import annotations

import re
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import urlsplit

import pytest
from fastapi.testclient import TestClient

from service.app import create_app
from service.docs_pages import render, slug
from service.settings import Settings

DOCS = Path(__file__).resolve().parents[2] / "docs"
NAMES = sorted(p.stem for p in DOCS.glob("*.md"))


class Doc(HTMLParser):
    def __init__(self, text: str):
        super().__init__()
        self.ids: set[str] = set()
        self.images: list[dict] = []
        self.links: list[str] = []
        self.tables_in_scroll: list[bool] = []
        self.text: list[str] = []
        self._stack: list[tuple[str, dict]] = []
        self._code = 0
        self.feed(text)

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if "id" in a:
            self.ids.add(a["id"])
        if tag == "img":
            self.images.append(a)
        elif tag == "a" and "href" in a:
            self.links.append(a["href"])
        elif tag == "table":
            self.tables_in_scroll.append(any(t == "div" and "table-scroll" in (x.get("class") or "")
                                             for t, x in self._stack))
        if tag in ("code", "pre"):
            self._code += 1
        if tag not in ("img", "br", "hr", "input", "meta", "link"):
            self._stack.append((tag, a))

    def handle_endtag(self, tag):
        if tag in ("code", "pre"):
            self._code -= 1
        while self._stack:
            if self._stack.pop()[0] == tag:
                break

    def handle_data(self, data):
        if not self._code:
            self.text.append(data)


@pytest.fixture(scope="module")
def client():
    with TestClient(create_app(Settings(warm_up=False))) as c:
        yield c


def test_accuracy_is_html_with_its_six_charts(client):
    r = client.get("/docs/accuracy")
    assert r.status_code == 200 and r.headers["content-type"].startswith("text/html")
    d = Doc(r.text)
    charts = [i for i in d.images if "/docs/charts/" in i["src"]]
    assert len(charts) == 6 and all(i.get("alt") for i in charts), charts
    for img in charts:
        got = client.get(img["src"])
        assert got.status_code == 200 and got.headers["content-type"] == "image/png", img["src"]
    # the data behind each chart is served too
    data = [u for u in d.links if u.startswith("/docs/charts/") and u.endswith(".csv")]
    assert data and all(client.get(u).status_code == 200 for u in data)
    assert "<h1>Speed against accuracy of the fidelity ladder</h1>" in r.text       # the document's own title
    assert "the-rotation-scale-terms" in d.ids
    assert d.tables_in_scroll and all(d.tables_in_scroll)
    # its source is one click away, as written
    assert client.get("/docs/accuracy.md").content == (DOCS / "accuracy.md").read_bytes()


@pytest.mark.parametrize("name", NAMES)
def test_every_document_renders_and_its_links_land(client, name):
    r = client.get(f"/docs/{name}")
    assert r.status_code == 200 and r.headers["content-type"].startswith("text/html"), name
    d = Doc(r.text)
    prose = " ".join(d.text)
    # no Markdown syntax left in the prose: links, images, emphasis markers and table rules are rendered
    assert not re.search(r"\]\((?!\s)[^)]*\)|!\[|\*\*\S|^\|[-:| ]+\|$", prose, re.M), (name, prose[:200])
    for href in d.links:
        parts = urlsplit(href)
        if parts.scheme in ("http", "https", "mailto"):
            continue
        if not parts.path:                               # an anchor of this document
            assert parts.fragment in d.ids, (name, href)
            continue
        got = client.get(parts.path)
        assert got.status_code == 200, (name, href)
        if parts.fragment and got.headers["content-type"].startswith("text/html"):
            assert parts.fragment in Doc(got.text).ids, (name, href)


def test_headings_get_githubs_anchors_and_outside_files_are_named_not_linked():
    seen: dict[str, int] = {}
    assert slug("The free wobble on spin-axis tracks", seen) == "the-free-wobble-on-spin-axis-tracks"
    assert slug("How to read the `model` object", {}) == "how-to-read-the-model-object"
    assert slug("The free wobble on spin-axis tracks", seen) == "the-free-wobble-on-spin-axis-tracks-1"
    title, body = render("# T\n\nSee [the errata](../data/lara/errata.toml) and [moon](moon.md#x).\n")
    assert title == "T" and 'href="/docs/moon#x"' in body and "../data" not in body.split("title=")[0]
    assert '<span class="repo-path"' in body and "the errata</span>" in body


def test_the_documents_are_read_where_EPHEM_DOCS_DIR_says(tmp_path):
    """The Docker image has no repository: it copies docs/ and names it in EPHEM_DOCS_DIR (Dockerfile)."""
    import os
    import subprocess
    import sys
    (tmp_path / "charts").mkdir()
    (tmp_path / "charts" / "c.svg").write_text("<svg xmlns='http://www.w3.org/2000/svg'/>", encoding="utf-8")
    (tmp_path / "note.md").write_text("# A note\n\n![a chart](charts/c.svg)\n", encoding="utf-8")
    code = ("from fastapi.testclient import TestClient\nfrom service.app import create_app\n"
            "from service.settings import Settings\nimport dataclasses\n"
            "c = TestClient(create_app(dataclasses.replace(Settings.from_env(), warm_up=False)))\n"
            "page, chart = c.get('/docs/note'), c.get('/docs/charts/c.svg')\n"
            "print(page.status_code, chart.status_code, '<h1' in page.text and 'A note' in page.text)")
    env = {**os.environ, "EPHEM_DOCS_DIR": str(tmp_path)}
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120,
                         cwd=Path(__file__).resolve().parents[2])
    assert out.returncode == 0, out.stderr
    assert out.stdout.split()[-3:] == ["200", "200", "True"]
