"""σ shown as they are (issue 41): Vesta's rate read 13.64875 ± 1.02e-9″/yr, a lower bound since C/MR², the pole and
the orbit carry no σ; wherever an answer's uncertainty is incomplete the page shows "≥ σ" and which inputs have
one and which have none, beside the number, as the JSON's ``uncertainty.lower_bounds`` says and the tables' captions
repeat; the body page's reasons for the values without a σ stand once each (six identical orbit notes were one
per element), and a value without a σ or a reason (an epoch) shows "—", never "none: None".
"""
from __future__ import annotations

import re
from html.parser import HTMLParser

import pytest
from fastapi.testclient import TestClient

from ephem import api
from service.app import create_app
from service.settings import Settings

BODIES = [b["name"] for b in api.list_bodies(dataset="current")]
PRECESSION_KEYS = ("precession_rate_arcsec_per_year", "observable_precession_rate_arcsec_per_year", "obliquity_deg",
                   "dynamical_ellipticity", "scaling_factor_arcsec_per_year")


class Cells(HTMLParser):
    """Each element with an id: its text; and the list items of the 'why no σ' notes."""

    def __init__(self, text: str):
        super().__init__()
        self.by_id: dict[str, str] = {}
        self.notes: list[str] = []
        self._open: list[tuple[str | None, list[str]]] = []
        self.feed(text)

    def handle_starttag(self, tag, attrs):
        if tag in ("input", "img", "br", "meta", "link"):
            return
        self._open.append((dict(attrs).get("id"), []))

    def handle_endtag(self, tag):
        if tag in ("input", "img", "br", "meta", "link") or not self._open:
            return
        ident, parts = self._open.pop()
        text = " ".join("".join(parts).split())
        if self._open:
            self._open[-1][1].append(text + " ")
        if ident:
            self.by_id[ident] = text
            if ident.startswith("why-") and ident[4:].isdigit():
                self.notes.append(text)

    def handle_data(self, data):
        if self._open:
            self._open[-1][1].append(data)


@pytest.fixture(scope="module")
def client():
    with TestClient(create_app(Settings(warm_up=False))) as c:
        yield c


@pytest.mark.parametrize("body", BODIES)
def test_a_sigma_that_leaves_inputs_out_says_so_where_it_is_shown(client, body):
    answer = client.get(f"/v1/bodies/{body}/precession").json()
    bounds = answer["uncertainty"]["lower_bounds"]
    page = Cells(client.get(f"/bodies/{body}").text)
    for key in PRECESSION_KEYS:
        if f"{key}_uncertainty" not in page.by_id:
            continue                                     # a row the body's answer has not (the observable rate)
        shown, sigma = page.by_id[f"{key}_uncertainty"], answer[f"{key}_uncertainty"]
        if sigma is None:
            assert shown == "—", (key, shown)
        elif key in bounds:
            assert shown.startswith("≥ ") and bounds[key] in shown, (key, shown)
            assert float(shown[2:].split(",")[0]) == pytest.approx(sigma, rel=5e-3), key       # 3 digits
        else:
            assert float(shown) == pytest.approx(sigma, rel=5e-3) and "≥" not in shown, key
    # an incomplete σ is named as such: bounds only where the answer says some input has none
    if answer["uncertainty"]["complete"]:
        assert not bounds


def test_vestas_rate_is_a_lower_bound_with_its_reason(client):
    answer = client.get("/v1/bodies/vesta/precession").json()
    why = answer["uncertainty"]["lower_bounds"]["precession_rate_arcsec_per_year"]
    assert why == "only the rotation period has a σ; the orbit, the pole and C/MR² have none"
    shown = Cells(client.get("/bodies/vesta").text).by_id["precession_rate_arcsec_per_year_uncertainty"]
    assert shown == f"≥ {answer['precession_rate_arcsec_per_year_uncertainty']:.3g}, {why}"
    # the nutation tables' ± are lower bounds too, and their captions say it
    for fmt in ("markdown", "latex"):
        text = client.get("/v1/bodies/vesta/nutation", params={"format": fmt}).text
        assert "lower bounds (only the rotation period has a" in text, fmt
    # a body whose every input of a value has a σ is not called a lower bound: Mars' H_d is given with its σ
    mars = client.get("/v1/bodies/mars/precession").json()
    assert mars["dynamical_ellipticity_uncertainty"] and "dynamical_ellipticity" not in mars["uncertainty"]["lower_bounds"]


@pytest.mark.parametrize("body", BODIES)
def test_each_reason_for_no_sigma_stands_once(client, body):
    record = client.get(f"/v1/bodies/{body}").json()
    text = client.get(f"/bodies/{body}").text
    assert "none: None" not in text and "None" not in re.sub(r"<[^>]+>", "", text.split('id="facts"')[1]
                                                             .split('id="interior"')[0])
    page = Cells(text)
    reasons = {v["no_uncertainty"] for v in record["values"].values() if v["uncertainty"] is None and
               v["no_uncertainty"]}
    assert len(page.notes) == len(reasons)                             # one line per reason
    for reason in reasons:
        keys = [k for k, v in record["values"].items() if v["no_uncertainty"] == reason and v["uncertainty"] is None]
        (line,) = [n for n in page.notes if n.endswith(" ".join(reason.split()))]
        assert line.replace(" :", ":", 1).startswith(", ".join(keys) + ":"), (line, keys)
