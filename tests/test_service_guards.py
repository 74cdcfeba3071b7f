"""The service's inputs hold at their edges (issue 29): what an over-budget refusal reports, duplicate query
parameters, angles too large to reduce modulo 360 deg, and the model cache's bound in bytes."""
from __future__ import annotations

import re

import pytest
from fastapi.testclient import TestClient

from service.app import create_app
from service.problems import PROBLEM
from service.settings import Settings

USER = {"name": "guarded",
        "orbit": {"a_au": 2.36, "e": 0.089, "i_deg": 7.14, "node_deg": 103.7, "peri_deg": 151.7,
                  "mean_anomaly_deg": 169.2, "epoch_jd_tdb": 2460200.5},
        "pole": {"ra_deg": 309.03, "dec_deg": 42.23, "epoch_jd_tdb": 2451545.0},
        "rotation_period_hours": 5.342, "dynamical_ellipticity": 0.1}


@pytest.fixture(scope="module")
def client():
    with TestClient(create_app(Settings(warm_up=False))) as c:
        yield c


def _user(**changes) -> dict:
    """USER with ``section__key=value`` (or ``key=value``) changed."""
    import copy

    out = copy.deepcopy(USER)
    for key, value in changes.items():
        section, _, field = key.partition("__")
        if field:
            out[section][field] = value
        else:
            out[section] = value
    return out


def _problem(r, status: int, kind: str) -> dict:
    assert r.status_code == status, r.text
    assert r.headers["content-type"].startswith(PROBLEM)
    body = r.json()
    assert body["status"] == status and body["type"].endswith("/" + kind), body
    return body


# ------------------------------------------------------------------ over budget: the fields say what the text says

def _printed_cpu_s(detail: str) -> str:
    found = re.search(r"estimated to need ([0-9.e+-]+) s of one core", detail)
    assert found, detail
    return found.group(1)


def test_an_over_budget_refusal_reports_the_whole_requests_estimate(client):
    # e = 0.95 with a track: the model's part is charged first, then the track's estimates break the budget.
    # The refusal must report the request's estimate (both parts), above the budget, as its text prints it
    # (it reported the refused part alone: "estimated to need 7.82 s" with estimated_cpu_s 4.38 of 5).
    r = client.post("/v1/precession-nutation", json=_user(
        orbit__e=0.95, track={"start": "2020-01-01", "stop": "2030-01-01", "step_days": 1}))
    body = _problem(r, 422, "over-budget")
    assert body["already_charged_cpu_s"] > 0                       # the case: a refusal after an earlier charge
    assert body["estimated_cpu_s"] > body["budget_cpu_s"] == Settings().max_request_cpu_s
    assert _printed_cpu_s(body["detail"]) == f"{body['estimated_cpu_s']:.3g}"
    assert f"{body['already_charged_cpu_s']:.3g} s already charged" in body["detail"]
    # the parts sum to the estimate: the earlier parts as one, named 'request'
    parts = body["estimate"]["parts"]
    assert body["estimate"]["cpu_s"] == pytest.approx(body["estimated_cpu_s"], rel=1e-12)
    assert sum(p["cpu_s"] for p in parts) == pytest.approx(body["estimated_cpu_s"], rel=1e-12)
    assert [p["cpu_s"] for p in parts if p["parameter"] == "request"] == [body["already_charged_cpu_s"]]
    assert body["errors"][0]["field"] == "orbit.e"                 # the refused part still names its parameter


def test_a_single_charge_over_budget_has_nothing_already_charged(client):
    r = client.get("/v1/bodies/itokawa/track?start=1900-01-01&stop=2050-01-01&step_days=100&model=real_orbit")
    body = _problem(r, 422, "over-budget")
    assert body["already_charged_cpu_s"] == 0.0
    assert body["estimated_cpu_s"] > body["budget_cpu_s"]
    assert _printed_cpu_s(body["detail"]) == f"{body['estimated_cpu_s']:.3g}"
    assert "already charged" not in body["detail"]
