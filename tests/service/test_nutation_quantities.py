"""One name, one quantity (issue 41): the Moon's page and JSON gave its amplitude in longitude as 101.83″ while its
Markdown and LaTeX downloads gave 11,862.52 mas under "Amp (mas)", the same Δψ scaled by sin ε a second time.
Every format names the quantity its amplitude columns hold (the JSON's ``amplitude_quantities``, the CSV's
``amp_of``, the Markdown, LaTeX and page headers), and for every body of the catalogue the formats agree number for
number: the JSON's value exactly in CSV (repr), within half a unit of the last printed digit in Markdown (2 places of
mas), LaTeX and on the page (6 significant digits).
"""
from __future__ import annotations

import csv
import io
import re
from html.parser import HTMLParser

import pytest
from fastapi.testclient import TestClient

from ephem import api
from service.app import create_app
from service.settings import Settings

BODIES = [b["name"] for b in api.list_bodies(dataset="current")]
LATEX = {"Δψ sin ε": r"$\Delta\psi \sin\varepsilon$", "Δψ": r"$\Delta\psi$", "Δε": r"$\Delta\varepsilon$"}


class TermsTable(HTMLParser):
    """The page's nutation terms table (its caption says so): its header cells and its rows of cell texts."""

    def __init__(self, text: str):
        super().__init__()
        self.tables: list[dict] = []
        self._row: list[str] | None = None
        self._cell: str | None = None
        self._caption: str | None = None
        self.feed(text)
        (table,) = [t for t in self.tables if "nutation terms" in t["caption"]]
        self.head, self.rows = table["rows"][0], table["rows"][1:]

    def handle_starttag(self, tag, attrs):
        if tag == "table":
            self.tables.append({"caption": "", "rows": []})
        elif tag == "caption":
            self._caption = ""
        elif tag == "tr":
            self._row = []
        elif tag in ("th", "td"):
            self._cell = ""

    def handle_endtag(self, tag):
        if tag == "caption":
            self.tables[-1]["caption"], self._caption = self._caption, None
        elif tag in ("th", "td") and self._cell is not None:
            self._row.append(" ".join(self._cell.split()))
            self._cell = None
        elif tag == "tr" and self._row is not None:
            self.tables[-1]["rows"].append(self._row)
            self._row = None

    def handle_data(self, data):
        if self._caption is not None:
            self._caption += data
        if self._cell is not None:
            self._cell += data


@pytest.fixture(scope="module")
def client():
    with TestClient(create_app(Settings(warm_up=False))) as c:
        yield c


def _markdown_tables(text: str) -> dict[str, tuple[list[str], list[list[str]]]]:
    """component -> (header cells, rows of cells) of a Markdown download."""
    out, comp = {}, None
    for line in text.splitlines():
        if line.startswith("**"):
            comp = "longitude" if "in longitude" in line else "obliquity"
            out[comp] = ([], [])
        elif line.startswith("|") and comp and not line.startswith("|---"):
            cells = [c.strip() for c in line.strip().strip("|").split("|")]
            if not out[comp][0]:
                out[comp][0].extend(cells)
            elif not set(line) <= set("|-: "):
                out[comp][1].append(cells)
    return out


def _latex_tables(text: str) -> dict[str, tuple[str, list[list[str]]]]:
    out, comp, head = {}, None, False
    for line in text.splitlines():
        if r"\caption" in line:
            comp = "longitude" if "in longitude" in line else "obliquity"
            out[comp] = ("", [])
        elif line == r"\toprule":
            head = True
        elif head:
            out[comp] = (line, [])
            head = False
        elif comp and line.endswith(r"\\") and "&" in line:
            out[comp][1].append([c.strip() for c in line[:-2].split("&")])
    return out


def _value(cell: str) -> float:
    return float(re.split(r" ± | \$\\pm\$ ", cell)[0].replace("−", "-"))


@pytest.mark.parametrize("body", BODIES)
def test_every_format_names_its_amplitude_and_agrees(client, body):
    answer = client.get(f"/v1/bodies/{body}/nutation").json()
    names = answer["amplitude_quantities"]
    assert set(names) == {"longitude_amplitude_arcsec", "obliquity_amplitude_arcsec"}
    assert names["obliquity_amplitude_arcsec"] == "Δε"
    assert names["longitude_amplitude_arcsec"] == ("Δψ" if body == "Moon" else "Δψ sin ε")
    terms = answer["terms"]
    want = {comp: [t[f"{comp}_amplitude_arcsec"] for t in terms] for comp in ("longitude", "obliquity")}
    quantity = {comp: names[f"{comp}_amplitude_arcsec"] for comp in want}

    for layout, key, scale in (("sin-cos", "amp_arcsec", 1.0), ("amp-period", "amp_mas", 1e3)):
        rows = list(csv.DictReader(io.StringIO(client.get(
            f"/v1/bodies/{body}/nutation", params={"format": "csv", "layout": layout}).text)))
        for comp in want:
            mine = [r for r in rows if r["component"] == comp]
            assert {r["amp_of"] for r in mine} == {quantity[comp]}, (layout, comp)
            # repr() reads back to the same double; amp-period's mas are the arcseconds times 1000: one rounding
            assert [float(r[key]) for r in mine] == pytest.approx([a * scale for a in want[comp]], rel=2.3e-16)

        md = _markdown_tables(client.get(f"/v1/bodies/{body}/nutation",
                                         params={"format": "markdown", "layout": layout}).text)
        tex = _latex_tables(client.get(f"/v1/bodies/{body}/nutation",
                                       params={"format": "latex", "layout": layout}).text)
        unit, tex_unit, places = ("″", "$''$", 4) if layout == "sin-cos" else ("mas", "mas", 2)
        for comp in want:
            head, cells = md[comp]
            amp_col = head.index(f"Amp {quantity[comp]} ({unit if unit == 'mas' else chr(34)})")
            got = [_value(row[amp_col]) for row in cells]
            assert got == pytest.approx([a * scale for a in want[comp]], abs=0.51 * 10.0 ** -places), (layout, comp)
            tex_head, tex_rows = tex[comp]
            assert f"Amp {LATEX[quantity[comp]]} ({tex_unit})" in tex_head, (layout, comp, tex_head)
            tex_col = [c.strip() for c in tex_head.removesuffix(r"\\").split("&")].index(
                f"Amp {LATEX[quantity[comp]]} ({tex_unit})")
            assert [_value(r[tex_col]) for r in tex_rows] == pytest.approx(got, abs=0.51 * 10.0 ** -places)

    page = TermsTable(client.get(f"/bodies/{body}").text)
    for comp in want:
        col = page.head.index(f"Amp {quantity[comp]} (″)")
        shown = [float(r[col]) for r in page.rows]
        assert shown == pytest.approx(want[comp], rel=5e-6), comp           # 6 significant digits


def test_the_moons_downloads_no_longer_scale_its_displacement_twice(client):
    """The case of the issue: the Moon's largest term, 101.83″ on the page, is 101,825.6 mas in its download (it
    was 11,862.52 mas, that times sin ε again)."""
    text = client.get("/v1/bodies/moon/nutation", params={"format": "markdown", "layout": "amp-period"}).text
    head, rows = _markdown_tables(text)["longitude"]
    assert head[0] == "Amp Δψ (mas)"
    amp = client.get("/v1/bodies/moon/nutation").json()["terms"][0]["longitude_amplitude_arcsec"]
    assert float(rows[0][0]) == pytest.approx(amp * 1e3, abs=0.006) and amp > 100
