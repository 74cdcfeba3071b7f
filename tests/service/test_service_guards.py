"""The service's inputs hold at their edges (issue 29): what an over-budget refusal reports, duplicate query
parameters, angles too large to reduce modulo 360 deg, and the model cache's bound in bytes."""
from __future__ import annotations

import gc
import re
import tracemalloc
from typing import Annotated

import pytest
from fastapi import Depends, FastAPI, Query
from fastapi.testclient import TestClient

from ephem.base import memo
from ephem.bodies.catalogue import MAX_ANGLE_DEG, Orbit, Pole
from ephem.base.errors import InvalidInputError
from service import problems
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


def test_an_over_budget_refusal_reports_the_whole_requests_estimate():
    # e = 0.95 with a track: the model's part is charged first, then the track's estimates break the budget (set
    # just above the model's part). The refusal must report the request's estimate (both parts), above the budget,
    # as its text prints it (it reported the refused part alone: "estimated to need 7.82 s" with estimated_cpu_s 4.38).
    from ephem import api
    from ephem.bodies.catalogue import Body
    o, p = USER["orbit"], USER["pole"]
    b = Body(USER["name"], Orbit(o["a_au"], 0.95, o["i_deg"], o["node_deg"], o["peri_deg"], o["mean_anomaly_deg"],
                                 o["epoch_jd_tdb"]), Pole(p["ra_deg"], p["dec_deg"], p["epoch_jd_tdb"]),
             USER["rotation_period_hours"], dynamical_ellipticity=USER["dynamical_ellipticity"])
    settings = Settings(warm_up=False, max_request_cpu_s=round(1.05 * api.answer_cost(b, order=None,
                                                                                      nutation=True).cpu_s, 3),
                        max_request_memory_mb=2048.0, worker_request_memory_mb=2048.0,
                        worker_rss_mb=2400.0)     # refused for its CPU
    with TestClient(create_app(settings)) as client:
        r = client.post("/v1/precession-nutation", json=_user(
            orbit__e=0.95, track={"start": "2020-01-01", "stop": "2030-01-01", "step_days": 1}))
    body = _problem(r, 422, "over-budget")
    assert body["already_charged_cpu_s"] > 0                       # the case: a refusal after an earlier charge
    assert body["estimated_cpu_s"] > body["budget_cpu_s"] == settings.max_request_cpu_s
    assert _printed_cpu_s(body["detail"]) == f"{body['estimated_cpu_s']:.3g}"
    assert f"{body['already_charged_cpu_s']:.3g} s already charged" in body["detail"]
    # the parts sum to the estimate: the earlier parts as one, named 'request'
    parts = body["estimate"]["parts"]
    assert body["estimate"]["cpu_s"] == pytest.approx(body["estimated_cpu_s"], rel=1e-12)
    assert sum(p["cpu_s"] for p in parts) == pytest.approx(body["estimated_cpu_s"], rel=1e-12)
    assert [p["cpu_s"] for p in parts if p["parameter"] == "request"] == [body["already_charged_cpu_s"]]
    assert body["errors"][0]["field"] == "orbit.e"                 # the refused part still names its parameter


def test_a_single_charge_over_budget_has_nothing_already_charged():
    # the real orbit over 150 years: ~3.5 s predicted (benchmarks/RESULTS_calibration.md), over a budget of 2 s
    with TestClient(create_app(Settings(warm_up=False, max_request_cpu_s=2.0, max_request_memory_mb=2048.0,
                                        worker_request_memory_mb=2048.0, worker_rss_mb=2400.0))) as client:
        # refused for its CPU
        r = client.get("/v1/bodies/itokawa/track?start=1900-01-01&stop=2050-01-01&step_days=100&model=real_orbit")
    body = _problem(r, 422, "over-budget")
    assert body["already_charged_cpu_s"] == 0.0
    assert body["estimated_cpu_s"] > body["budget_cpu_s"]
    assert _printed_cpu_s(body["detail"]) == f"{body['estimated_cpu_s']:.3g}"
    assert "already charged" not in body["detail"]


# ------------------------------------------------------------------ angles too large to reduce modulo 360 deg

BODY_ANGLES = [("pole", "ra_deg"), ("orbit", "node_deg"), ("orbit", "peri_deg"), ("orbit", "mean_anomaly_deg")]


@pytest.mark.parametrize("section, key", BODY_ANGLES)
@pytest.mark.parametrize("value", [1e308, -1e300, 2.0 * MAX_ANGLE_DEG])
def test_an_angle_with_no_digits_left_modulo_360_is_refused_naming_its_path(client, section, key, value):
    body = _problem(client.post("/v1/precession-nutation", json=_user(**{f"{section}__{key}": value})), 422,
                    "invalid-input")
    assert body["errors"] == [{"field": f"{section}.{key}", "reason": body["errors"][0]["reason"]}]
    assert "modulo 360" in body["errors"][0]["reason"] and f"{MAX_ANGLE_DEG:g}" in body["errors"][0]["reason"]


@pytest.mark.parametrize("section, key", BODY_ANGLES)
def test_many_turns_within_the_bound_are_the_same_angle(client, section, key):
    """An angle of a thousand turns more is accepted and gives the answer of the angle itself (the bound refuses
    only what cannot be reduced: 360 000 deg is exact in a double, so only the trigonometry's rounding differs)."""
    ref = client.post("/v1/precession-nutation", json=USER).json()
    turned = _user(**{f"{section}__{key}": USER[section][key] + 1000 * 360.0})
    got = client.post("/v1/precession-nutation", json=turned)
    assert got.status_code == 200, got.text
    for k in ("obliquity_deg", "precession_rate_arcsec_per_year"):
        assert got.json()["precession"][k] == pytest.approx(ref["precession"][k], rel=1e-9)


@pytest.mark.parametrize("key", ["free_wobble_phase_deg", "rotation_phase_deg"])
def test_a_phase_with_no_digits_left_is_refused_in_the_query_and_the_post(client, key):
    q = {"start": "2020-01-01", "stop": "2020-02-01", "step_days": 10, key: 1e300}
    body = _problem(client.get("/v1/bodies/mars/track", params=q), 422, "invalid-input")
    assert body["errors"][0]["field"] == key and "modulo 360" in body["errors"][0]["reason"]
    track = {"start": "2020-01-01", "stop": "2020-02-01", "step_days": 10, key: -1e300}
    if key == "free_wobble_phase_deg":
        track["free_wobble_J_arcsec"] = 1.0       # a body of one's own has no published wobble amplitude
    user = _user(track=track, moments={"A": 0.3433, "B": 0.3546, "C": 0.42})
    del user["dynamical_ellipticity"]
    body = _problem(client.post("/v1/precession-nutation", json=user), 422, "invalid-input")
    assert body["errors"][0]["field"] == f"track.{key}"          # the full path, as the client wrote it
    assert client.get("/v1/bodies/mars/track", params={**q, key: 720.5}).status_code == 200


def test_the_library_and_a_batch_row_refuse_it_too():
    from ephem import api

    with pytest.raises(InvalidInputError) as info:
        Pole(1e308, 10.0)
    assert info.value.field == "pole.ra_deg"
    with pytest.raises(InvalidInputError) as info:
        Orbit(2.36, 0.1, 7.0, 0.0, -1e300, 0.0, 2451545.0)
    assert info.value.field == "orbit.peri_deg"
    with pytest.raises(InvalidInputError) as info:
        Pole.from_ecliptic(1e308, 10.0)
    assert info.value.field == "pole.lon"
    row = {"name": "r", "a_au": 2.36, "e": 0.09, "i_deg": 7.1, "node_deg": 103.7, "peri_deg": 151.7,
           "mean_anomaly_deg": 169.2, "epoch_jd_tdb": 2460200.5, "pole_ra_deg": 309.0, "pole_dec_deg": 42.2,
           "rotation_period_hours": 5.342, "dynamical_ellipticity": 0.1}
    rows = api.batch([dict(row, pole_ra_deg=1e308), dict(row, mean_anomaly_deg=-1e300), row])["rows"]
    assert rows[0]["error"].startswith("pole_ra_deg: an angle must lie within")
    assert rows[1]["error"].startswith("mean_anomaly_deg: an angle must lie within")
    assert rows[0]["obliquity_deg"] is None and rows[2]["error"] == ""


def test_the_bound_is_stated_in_the_openapi_document(client):
    doc = client.get("/openapi.json").json()
    schemas = doc["components"]["schemas"]
    for section, key in BODY_ANGLES:
        prop = schemas["PoleIn" if section == "pole" else "OrbitIn"]["properties"][key]
        assert (prop["minimum"], prop["maximum"]) == (-MAX_ANGLE_DEG, MAX_ANGLE_DEG)
    for key in ("free_wobble_phase_deg", "rotation_phase_deg"):
        number = next(b for b in schemas["TrackIn"]["properties"][key]["anyOf"] if b.get("type") == "number")
        assert number["maximum"] == MAX_ANGLE_DEG
        param = next(p for p in doc["paths"]["/v1/bodies/{body}/track"]["get"]["parameters"] if p["name"] == key)
        number = next(b for b in param["schema"]["anyOf"] if b.get("type") == "number")
        assert number["minimum"] == -MAX_ANGLE_DEG


# ------------------------------------------------------------------ a query parameter given twice

def _api_routes(app):
    """(method, path) of every route the app serves through FastAPI (the API, the docs pages)."""
    from fastapi.routing import APIRoute

    return [(m, r.path) for r in app.routes if isinstance(r, APIRoute) for m in sorted(r.methods)]


def test_a_repeated_query_parameter_is_refused_naming_it(client):
    # the last value won without a word: ?order=2&order=4 answered order 4
    body = _problem(client.get("/v1/bodies/vesta/precession?order=2&order=4"), 422, "invalid-input")
    assert [e["field"] for e in body["errors"]] == ["order"]
    assert "order=2&order=4" in body["errors"][0]["reason"] and "given 2 times" in body["errors"][0]["reason"]
    assert client.get("/v1/bodies/vesta/precession?order=4").status_code == 200


@pytest.mark.parametrize("query, field", [
    ("order=abc&order=4", "order"),                   # refused as repeated before either value is read
    ("or%64er=2&order=4", "order"),                   # the names as decoded, as the route would see them
    ("dataset=current&dataset=current", "dataset"),   # even the same value twice
    ("order=4&colour=1&colour=2", "colour"),          # a parameter no route takes
])
def test_the_repeated_name_is_the_one_named(client, query, field):
    body = _problem(client.get(f"/v1/bodies/vesta/nutation?{query}"), 422, "invalid-input")
    assert body["errors"][0]["field"] == field


def test_every_route_refuses_a_repeated_parameter(client):
    """Each route the app serves, read from its route list (a new route is covered by itself), with its first
    query parameter (or any name) given twice: 422 naming it, before its own checks or its work."""
    doc = client.get("/openapi.json").json()
    routes = _api_routes(client.app)
    assert ("GET", "/v1/bodies/{body}/track") in routes and ("POST", "/v1/batch") in routes
    for method, path in routes:
        op = doc["paths"].get(path, {}).get(method.lower(), {})
        names = [p["name"] for p in op.get("parameters", []) if p["in"] == "query"] or ["anything"]
        url = path.replace("{body}", "vesta") + f"?{names[0]}=1&{names[0]}=2"
        r = client.request(method, url, json=USER if method == "POST" else None)
        if method == "HEAD":
            assert r.status_code == 422, (method, path)      # a HEAD answer has no body to name it in
            continue
        body = _problem(r, 422, "invalid-input")
        assert body["errors"][0]["field"] == names[0], (method, path, body)


def test_a_parameter_a_route_takes_as_a_list_may_repeat():
    """The exception, with a route of its own (no route of the service takes a list today)."""
    app = FastAPI(dependencies=[Depends(problems.single_query_values)])
    problems.install(app)

    @app.get("/t")
    def t(tag: Annotated[list[str] | None, Query()] = None, n: int = 0):
        return {"tag": tag, "n": n}

    c = TestClient(app)
    assert c.get("/t?tag=a&tag=b&n=1").json() == {"tag": ["a", "b"], "n": 1}
    assert _problem(c.get("/t?tag=a&n=1&n=2"), 422, "invalid-input")["errors"][0]["field"] == "n"


def test_the_rule_is_stated_in_the_openapi_document(client):
    assert "?order=2&order=4) is a 422" in client.get("/openapi.json").json()["info"]["description"]


# ------------------------------------------------------------------ the per-body caches, bounded in bytes

def test_the_model_caches_stay_within_their_byte_budget_for_many_distinct_bodies(monkeypatch):
    """A client sending distinct eccentric bodies with a track: each left ~1 MB per body in the worker (its
    ladder tables, model, theory, uncertainties), kept by count (512 models, 128 tables). Bounded in bytes,
    the caches hold at most their budget, by their own accounting and by what the process allocated."""
    budget_mb = 2.0
    previous = memo.budget_mb()
    stored: list[int] = []
    put = memo.POOL.put
    monkeypatch.setattr(memo.POOL, "put", lambda key, value, grows=False: (stored.append(memo.sizeof(value)),
                                                                           put(key, value, grows)))
    try:
        with TestClient(create_app(Settings(warm_up=False, model_cache_mb=budget_mb))) as c:
            assert memo.budget_mb() == budget_mb
            # one body first, not counted: what the first request of a process loads once (the modules a family
            # imports when it first answers, the DE421 kernel's span) is not kept per body
            _post_ok(c, _user(orbit__e=0.3, pole__ra_deg=3.0,
                              track={"start": "2020-01-01", "stop": "2020-03-01", "step_days": 30}))
            memo.POOL.clear()
            gc.collect()
            tracemalloc.start()
            base = tracemalloc.get_traced_memory()[0]
            for k in range(8):
                user = _user(orbit__e=0.3, pole__ra_deg=10.0 + 7.0 * k,
                             track={"start": "2020-01-01", "stop": "2020-03-01", "step_days": 30})
                _post_ok(c, user)
                assert memo.POOL.nbytes <= budget_mb * 2**20, k
            gc.collect()
            growth = tracemalloc.get_traced_memory()[0] - base
            tracemalloc.stop()
    finally:
        memo.set_budget_mb(previous)
    assert sum(stored) > 3 * budget_mb * 2**20            # unbounded, the caches would have held this much
    assert growth < (budget_mb + 1.0) * 2**20, growth / 2**20    # 1 MB for the small caches keyed by body


def _post_ok(c, user):
    r = c.post("/v1/precession-nutation", json=user)
    assert r.status_code == 200, r.text
    return r


def test_the_budget_is_a_setting(monkeypatch):
    monkeypatch.setenv("EPHEM_MODEL_CACHE_MB", "16")
    assert Settings.from_env().model_cache_mb == 16.0
    monkeypatch.setenv("EPHEM_MODEL_CACHE_MB", "-1")
    with pytest.raises(SystemExit, match="EPHEM_MODEL_CACHE_MB"):
        Settings.from_env()
