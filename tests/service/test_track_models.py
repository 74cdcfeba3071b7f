"""GET /v1/bodies/{body}/track/models and its charts (.svg, .png): the library's answer and chart for the same
query, their media types, and the problems for bad input (the field named) and an unknown body (404)."""
from __future__ import annotations

import xml.etree.ElementTree as ET

import pytest
from fastapi.testclient import TestClient

from ephem import api
from service.app import create_app
from service.problems import PROBLEM, TYPE_BASE
from service.settings import Settings

Q = {"start": "2025-01-01", "stop": "2026-01-01", "step_days": "30", "tolerance_mas": "100"}
ROUTES = ("/v1/bodies/vesta/track/models", "/v1/bodies/vesta/track/models.svg", "/v1/bodies/vesta/track/models.png")


@pytest.fixture(scope="module")
def client():
    with TestClient(create_app(Settings(warm_up=False))) as c:
        yield c


def test_the_json_is_the_librarys_answer(client):
    r = client.get(ROUTES[0], params=Q)
    assert r.status_code == 200 and r.headers["content-type"] == "application/json"
    got = r.json()
    want = api.track_models("vesta", Q["start"], Q["stop"], 30.0, tolerance_mas=100.0)
    assert got["chosen"] == want["chosen"] and got["epochs"] == want["epochs"] == 13
    assert [(m["name"], m["order"], m["rotation_scale"]) for m in got["models"]] == \
        [(m["name"], m["order"], m["rotation_scale"]) for m in want["models"]]
    for g, w in zip(got["models"], want["models"]):
        if w["estimated_error_mas"] is not None:
            assert g["estimated_error_mas"] == pytest.approx(w["estimated_error_mas"], rel=1e-12)
    # the track's parameters that apply: axis, perturbers, dataset
    other = client.get(ROUTES[0], params={**Q, "axis": "angular_momentum", "perturbers": "sun",
                                          "dataset": "petit2014"})
    assert other.status_code == 200 and other.json()["dataset"] == "petit2014"


def test_the_charts_are_the_librarys_for_the_same_query(client):
    svg = client.get(ROUTES[1], params=Q)
    assert svg.status_code == 200 and svg.headers["content-type"].startswith("image/svg+xml")
    assert svg.content == api.track_models_chart("vesta", Q["start"], Q["stop"], 30.0, tolerance_mas=100.0)
    root = ET.fromstring(svg.content)
    titled = [g for g in root.iter("{http://www.w3.org/2000/svg}g") if "point" in (g.get("class") or "").split()]
    models = client.get(ROUTES[0], params=Q).json()["models"]
    assert len(titled) == sum(m["available"] and m["estimated_error_mas"] is not None and
                              m["estimated_cpu_ms"] is not None for m in models) > 30
    png = client.get(ROUTES[2], params={**Q, "dpi": "40"})
    assert png.status_code == 200 and png.headers["content-type"] == "image/png"
    assert png.content[:8] == b"\x89PNG\r\n\x1a\n"
    assert png.content == api.track_models_chart("vesta", Q["start"], Q["stop"], 30.0, tolerance_mas=100.0,
                                                 fmt="png", dpi=40)


@pytest.mark.parametrize("route", ROUTES)
@pytest.mark.parametrize("field, value", [("step_days", "0"), ("step_days", "abc"), ("stop", "2024-01-01"),
                                          ("tolerance_mas", "-1"), ("axis", "pole"), ("start", "2025-02-30"),
                                          ("perturbers", "jupiter")])
def test_bad_input_is_a_problem_naming_the_field(client, route, field, value):
    r = client.get(route, params={**Q, field: value})
    assert r.status_code == 422, (field, value, r.text[:300])
    assert r.headers["content-type"].startswith(PROBLEM)
    problem = r.json()
    if problem["type"] == TYPE_BASE + "not-applicable":      # a perturber the theory does not take
        assert field == "perturbers" and "jupiter" in problem["detail"].lower()
    else:
        assert [e["field"] for e in problem["errors"]] == [field], problem


def test_a_png_out_of_its_dpi_range_names_dpi(client):
    problem = client.get(ROUTES[2], params={**Q, "dpi": "1000"}).json()
    assert [e["field"] for e in problem["errors"]] == ["dpi"]


@pytest.mark.parametrize("route", ROUTES)
def test_an_unknown_body_is_404(client, route):
    r = client.get(route.replace("vesta", "vulcan"), params=Q)
    assert r.status_code == 404 and r.headers["content-type"].startswith(PROBLEM)
    assert "vulcan" in r.json()["detail"].lower()


def test_the_routes_are_documented(client):
    doc = client.get("/openapi.json").json()
    op = doc["paths"]["/v1/bodies/{body}/track/models"]["get"]
    assert op["tags"] == ["theory"] and "**Rules**" in op["description"]
    schema = op["responses"]["200"]["content"]["application/json"]["schema"]
    assert schema["$ref"].endswith("/TrackModels")
    entry = doc["components"]["schemas"]["TrackModelEntry"]["properties"]
    assert {"eligible", "why", "estimated_error_mas", "estimated_cpu_ms", "chosen"} <= set(entry)
    for ext, media in (("svg", "image/svg+xml"), ("png", "image/png")):
        chart = doc["paths"][f"/v1/bodies/{{body}}/track/models.{ext}"]["get"]
        assert list(chart["responses"]["200"]["content"]) == [media]
        assert {p["name"] for p in chart["parameters"]} >= {"start", "stop", "step_days", "tolerance_mas", "axis",
                                                            "perturbers", "dataset", "dpi"}
