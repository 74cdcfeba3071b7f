"""The HTTP service: every route and each error through the test client, a real uvicorn
process over loopback, and a bounded schemathesis run against /openapi.json."""
import csv
import io
import json
import math
import os
import socket
import subprocess
import sys
import time
import urllib.request

import pytest
from fastapi.testclient import TestClient

from ephem import api
from service.app import app, create_app
from service.settings import Settings

from tests.answers.test_api_cli import TERM_KEYS  # the same contract

PROBLEM = "application/problem+json"
USER = {"name": "my-asteroid",
        "orbit": {"a_au": 2.36, "e": 0.089, "i_deg": 7.14, "node_deg": 103.7, "peri_deg": 151.7,
                  "mean_anomaly_deg": 169.2, "epoch_jd_tdb": 2460200.5},
        "pole": {"ra_deg": 309.03, "dec_deg": 42.23, "epoch_jd_tdb": 2451545.0},
        "rotation_period_hours": 5.342,
        "moments": {"A": 0.3433, "B": 0.3546, "C": 0.42},
        "track": {"start": "2020-01-01", "stop": "2030-01-01", "step_days": 10}}


@pytest.fixture(scope="module")
def client():
    with TestClient(app) as c:
        yield c


def _problem(r, status):
    assert r.status_code == status, r.text
    assert r.headers["content-type"].startswith(PROBLEM)
    body = r.json()
    assert body["status"] == status and body["title"] and body["detail"] and body["type"]
    return body


def test_healthz(client):
    assert client.get("/healthz").json()["status"] == "ok"


def test_bodies(client):
    rows = client.get("/v1/bodies").json()
    assert {r["name"] for r in rows} == {"Ceres", "Vesta", "Eros", "Steins", "Itokawa", "Earth", "Moon", "Mars"}
    assert all(r["dataset"] == "current" for r in rows)
    assert client.get("/v1/bodies?dataset=petit2014").json()[0]["dataset"] == "petit2014"


@pytest.mark.parametrize("ref", ["vesta", "VESTA", "2000004"])
def test_body_record_by_name_or_naif_id(client, ref):
    rec = client.get(f"/v1/bodies/{ref}").json()
    assert rec["name"] == "Vesta"
    ra = rec["values"]["pole.ra"]
    assert ra["unit"] == "deg" and ra["source"] and ra["reference"]["year"]


def test_precession_matches_the_library(client):
    r = client.get("/v1/bodies/vesta/precession?dataset=petit2014").json()
    lib = json.loads(json.dumps(api.precession("vesta", dataset="petit2014")))
    assert r["model"].pop("cost_ms") >= 0 and lib["model"].pop("cost_ms") >= 0  # wall time differs per call
    assert r == lib
    assert round(r["precession_rate_arcsec_per_year"], 2) == 13.67
    assert set(r["model"]) >= {"theory", "eccentricity_order", "assumptions", "warnings"}


def test_nutation_json_and_order(client):
    r = client.get("/v1/bodies/ceres/nutation?order=4").json()
    assert [t["multiple"] for t in r["terms"]] == [1, 2, 3, 4, 5, 6]
    assert all(set(t) == TERM_KEYS for t in r["terms"])


@pytest.mark.parametrize("fmt, media", [("csv", "text/csv"), ("markdown", "text/markdown"),
                                        ("latex", "application/x-latex")])
def test_nutation_tables_in_the_paper_layout(client, fmt, media):
    r = client.get(f"/v1/bodies/vesta/nutation?dataset=petit2014&order=4&format={fmt}")
    assert r.status_code == 200 and r.headers["content-type"].startswith(media)
    text = r.text
    if fmt == "csv":
        rows = list(csv.DictReader(io.StringIO(text)))
        first = rows[0]
        assert first["arg"] == "M" and float(first["amp_arcsec"]) == pytest.approx(1.1027, abs=3e-4)  # Table 5
    elif fmt == "markdown":
        assert "| Δψ Sin (\") | Δψ Cos (\") | Amp Δψ sin ε (\") | Period (year) | Arg |" in text and "| 2M |" in text
    else:
        assert text.count(r"\begin{tabular}") == 2 and text.count(r"\end{tabular}") == 2
        assert r"\toprule" in text and r"\bottomrule" in text


def test_track_json_and_streamed_csv(client):
    q = "start=2040-01-01&stop=2041-01-01&step_days=30"
    j = client.get(f"/v1/bodies/ceres/track?{q}").json()
    assert len(j["jd_tdb"]) == 13 and len(j["pole_dec_deg"]) == 13
    r = client.get(f"/v1/bodies/ceres/track?{q}&format=csv")
    assert r.headers["content-type"].startswith("text/csv")
    rows = list(csv.DictReader(io.StringIO(r.text)))
    # the CSV prints shortest round-trip reprs of the same numbers (JD columns may be shortened): abs 1e-12 deg
    assert len(rows) == 13 and float(rows[0]["pole_ra_deg"]) == pytest.approx(j["pole_ra_deg"][0], abs=1e-12)


def test_post_user_body(client):
    r = client.post("/v1/precession-nutation", json=USER)
    assert r.status_code == 200, r.text
    ans = r.json()
    assert set(ans) == {"precession", "nutation", "track"}
    assert ans["precession"]["precession_rate_arcsec_per_year"] > 0
    assert len(ans["track"]["jd_tdb"]) == 366
    hd = dict(USER, dynamical_ellipticity=0.1692, moments=None)
    del hd["track"]
    ans = client.post("/v1/precession-nutation", json=hd).json()
    assert "track" not in ans and ans["precession"]["dynamical_ellipticity"] == 0.1692


def test_unknown_body_is_404_listing_the_known_ones(client):
    body = _problem(client.get("/v1/bodies/pallas/precession"), 404)
    assert "Vesta" in body["known_bodies"] and "Vesta" in body["detail"]


def test_not_applicable_is_422_with_the_reason(client):
    body = _problem(client.get("/v1/bodies/moon/nutation?perturbers=sun"), 422)
    assert body["title"] == "Not applicable" and "orbit's centre" in body["reason"]


@pytest.mark.parametrize("url, field", [
    ("/v1/bodies/vesta/track?start=2020-01-01&stop=2019-01-01&step_days=1", "stop"),
    ("/v1/bodies/vesta/track?start=not-a-date&stop=2021-01-01&step_days=1", "start"),
    ("/v1/bodies/vesta/track?start=2020-01-01&stop=2021-01-01&step_days=-1", "step_days"),
    ("/v1/bodies/vesta/track?start=2020-01-01&stop=2030-01-01&step_days=5e-324", "step_days"),  # found by schemathesis
    ("/v1/bodies/vesta/track.png?start=2020-01-01&stop=2030-01-01&step_days=5e-324", "step_days"),
    ("/v1/bodies/vesta/track?start=2020-01-01&stop=2021-01-01&step_days=nan", "step_days"),
    ("/v1/bodies/vesta/track?start=2020-01-01&stop=2021-01-01", "step_days"),
    ("/v1/bodies/vesta/precession?order=-2", "order"),
    ("/v1/bodies/vesta/precession?dataset=old", "dataset"),
    ("/v1/bodies/vesta/nutation?format=pdf", "format"),
])
def test_bad_queries_are_422_naming_the_field(client, url, field):
    body = _problem(client.get(url), 422)
    assert any(e["field"] == field for e in body["errors"]), body


@pytest.mark.parametrize("patch, field", [
    ({"orbit": dict(USER["orbit"], e=1.2)}, "orbit.e"),
    ({"rotation_period_hours": -5.0}, "rotation_period_hours"),
    ({"moments": {"A": 0.5, "B": 0.3546, "C": 0.42}}, "moments"),   # the POST names its own path
    ({"pole": dict(USER["pole"], dec_deg=95.0)}, "pole.dec_deg"),
    ({"moments": None}, "moments"),
    ({"orbit": dict(USER["orbit"], a_au="far")}, "orbit.a_au"),
    ({"unexpected": 1}, "unexpected"),
])
def test_bad_user_bodies_are_422_naming_the_field(client, patch, field):
    body = _problem(client.post("/v1/precession-nutation", json=dict(USER, **patch)), 422)
    assert any(e["field"] == field for e in body["errors"]), body


def test_nan_in_the_body_is_422(client):
    raw = json.dumps(USER).replace('"e": 0.089', '"e": NaN')
    body = _problem(client.post("/v1/precession-nutation", content=raw,
                                headers={"content-type": "application/json"}), 422)
    assert any(e["field"] == "orbit.e" for e in body["errors"])


def test_unknown_route_is_a_problem(client):
    _problem(client.get("/v2/nothing"), 404)


def test_track_sample_cap_is_configurable():
    small = create_app(Settings(max_track_samples=100, max_body_bytes=65536))
    with TestClient(small) as c:
        body = _problem(c.get("/v1/bodies/vesta/track?start=2020-01-01&stop=2021-01-01&step_days=1"), 422)
        assert "cap of 100" in body["detail"]
        assert c.get("/v1/bodies/vesta/track?start=2020-01-01&stop=2020-03-01&step_days=1").status_code == 200


def test_request_body_size_cap():
    small = create_app(Settings(max_track_samples=1000, max_body_bytes=200))
    with TestClient(small) as c:
        _problem(c.post("/v1/precession-nutation", json=USER), 413)


def _chunked(data: bytes, size: int = 64):
    """The body as a generator: sent chunked, with no Content-Length to check up front."""
    for i in range(0, len(data), size):
        yield data[i:i + size]


def test_a_chunked_body_over_the_cap_is_413_and_one_under_it_is_read_whole():
    body = json.dumps(USER).encode()
    small = create_app(Settings(max_track_samples=1000, max_body_bytes=len(body) - 1, warm_up=False))
    with TestClient(small) as c:
        r = c.post("/v1/precession-nutation", content=_chunked(body), headers={"content-type": "application/json"})
        assert "content-length" not in r.request.headers
        _problem(r, 413)
    fits = create_app(Settings(max_track_samples=1000, max_body_bytes=len(body), warm_up=False))
    with TestClient(fits) as c:
        r = c.post("/v1/precession-nutation", content=_chunked(body), headers={"content-type": "application/json"})
        assert r.status_code == 200, r.text
        assert r.json()["precession"]["body"] == USER["name"]


def test_settings_from_environment(monkeypatch):
    monkeypatch.setenv("EPHEM_MAX_TRACK_SAMPLES", "1234")
    assert Settings.from_env().max_track_samples == 1234
    monkeypatch.setenv("EPHEM_MAX_TRACK_SAMPLES", "lots")
    with pytest.raises(SystemExit, match="EPHEM_MAX_TRACK_SAMPLES"):
        Settings.from_env()


def test_warm_up_setting(monkeypatch):
    monkeypatch.setenv("EPHEM_WARM_UP", "off")
    assert Settings.from_env().warm_up is False
    monkeypatch.setenv("EPHEM_WARM_UP", "1")
    assert Settings.from_env().warm_up is True
    monkeypatch.setenv("EPHEM_WARM_UP", "perhaps")
    with pytest.raises(SystemExit, match="EPHEM_WARM_UP"):
        Settings.from_env()


def test_start_up_builds_the_earths_series():
    # the first Earth request must not build the lunisolar series (1.5 s): start-up does
    from ephem.earth import model as earth
    from ephem.earth import lunisolar

    lunisolar._build.cache_clear()
    earth.lunisolar_earth.cache_clear()
    with TestClient(create_app(Settings(warm_up=False))):
        assert earth.lunisolar_earth.cache_info().currsize == 0
    with TestClient(create_app(Settings())) as c:
        assert earth.lunisolar_earth.cache_info().currsize >= 1 and lunisolar._build.cache_info().currsize >= 1
        built = lunisolar._build.cache_info().misses
        assert c.get("/v1/bodies/earth/nutation").status_code == 200
        assert c.get("/v1/bodies/earth/track?start=2020-01-01&stop=2021-01-01&step_days=10").status_code == 200
        assert lunisolar._build.cache_info().misses == built      # nothing rebuilt for the requests


def test_openapi_has_an_example_for_every_route(client):
    spec = client.get("/openapi.json").json()
    for path, ops in spec["paths"].items():
        for method, op in ops.items():
            content = op.get("responses", {}).get("200", {}).get("content", {})
            has_example = any("example" in v or "examples" in v for v in content.values())
            has_example |= "requestBody" in op  # the POST's body carries its example in the schema
            assert has_example, f"{method.upper()} {path}"


def _free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def test_real_uvicorn_process_over_loopback():
    port = _free_port()
    proc = subprocess.Popen([sys.executable, "-m", "uvicorn", "service.app:app", "--host", "127.0.0.1",
                             "--port", str(port), "--log-level", "warning"],
                            cwd=os.path.dirname(os.path.dirname(os.path.dirname(__file__))))
    try:
        deadline = time.monotonic() + 30
        while True:
            try:
                with urllib.request.urlopen(f"http://127.0.0.1:{port}/healthz", timeout=1) as r:
                    assert json.load(r)["status"] == "ok"
                break
            except OSError:
                if time.monotonic() > deadline or proc.poll() is not None:
                    raise
                time.sleep(0.2)
        with urllib.request.urlopen(f"http://127.0.0.1:{port}/v1/bodies/vesta/precession?dataset=petit2014") as r:
            assert round(json.load(r)["precession_rate_arcsec_per_year"], 2) == 13.67
    finally:
        proc.terminate()
        proc.wait(timeout=10)


def test_non_finite_numbers_are_never_sent():
    import numpy as np
    from service.app import finite_json
    ok = finite_json({"a": np.array([1.0, 2.0]), "b": [0.5], "c": {"d": 3.0}})
    assert ok.status_code == 200 and json.loads(ok.body) == {"a": [1.0, 2.0], "b": [0.5], "c": {"d": 3.0}}
    bad = finite_json({"a": np.array([1.0, np.nan])})
    assert bad.status_code == 500 and bad.media_type == PROBLEM and b"NaN" not in bad.body
    assert finite_json({"x": float("inf")}).status_code == 500
    # anywhere in the nesting, in every float type; the largest finite numbers and the ints pass
    for hidden in ({"m": {"choice": {"eligible": [{"e": 1.0}, {"e": -math.inf}]}}}, {"t": (1, [2.0, (math.nan,)])},
                   {"s": np.float64("nan")}, {"s": [np.float32("inf")]}, {"c": np.array([1 + 1j, complex(1, math.nan)])}):
        assert finite_json(hidden).status_code == 500, hidden
    fine = {"big": [1.7976931348623157e308, -1.7976931348623157e308], "tiny": 5e-324, "n": 2 ** 62,
            "none": None, "flag": True, "text": "nan", "ints": np.arange(3), "f": np.float64(2.5)}
    assert finite_json(fine).status_code == 200


def test_track_with_a_tolerance_reports_the_chosen_model(client):
    q = "start=2000-01-01&stop=2010-01-01&step_days=30"
    loose = client.get(f"/v1/bodies/mars/track?{q}&tolerance_mas=1000").json()["model"]
    # Mars' figure axis wobbles by 0.1" about the angular momentum: 80 mas needs the wobble's phase
    refused = client.get(f"/v1/bodies/mars/track?{q}&tolerance_mas=80")
    assert refused.status_code == 422 and "free_wobble" in refused.text
    # every rigid rung leaves out Mars' liquid core (interior_rigid, 93 mas): 80 mas needs the non-rigid rung, with
    # the wobble followed on the figure axis (49.7 mas) or on the angular momentum (48.8)
    tight = client.get(f"/v1/bodies/mars/track?{q}&tolerance_mas=80&free_wobble_phase_deg=45").json()["model"]
    momentum = client.get(f"/v1/bodies/mars/track?{q}&tolerance_mas=80&axis=angular_momentum").json()["model"]
    assert loose["name"] in ("secular", "series") and tight["name"] == momentum["name"] == "nonrigid"
    assert tight["free_wobble"] == {"J_arcsec": 0.1, "phase_deg": 45.0, "epoch_jd_tdb": 2451545.0}
    assert loose["free_wobble"] is None and momentum["axis"] == "angular_momentum"
    for m in (loose, tight, momentum):
        assert m["estimated_error_mas"] <= m["tolerance_mas"] and m["cost_ms"] > 0
    csv_text = client.get(f"/v1/bodies/mars/track?{q}&tolerance_mas=80&axis=angular_momentum&format=csv").text
    assert csv_text.count("\n") == 123
    explicit = client.get(f"/v1/bodies/mars/track?{q}&model=second_order").json()["model"]
    assert explicit["name"] == "second_order" and explicit["tolerance_mas"] is None


def test_tolerance_on_rates_and_terms_picks_the_order(client):
    coarse = client.get("/v1/bodies/vesta/nutation?tolerance_mas=100").json()
    fine = client.get("/v1/bodies/vesta/nutation?tolerance_mas=0.001").json()
    assert coarse["model"]["order"] < fine["model"]["order"]
    assert len(coarse["terms"]) <= len(fine["terms"])
    assert client.get("/v1/bodies/vesta/precession?tolerance_mas=5").json()["model"]["name"] == "series"


def test_post_track_takes_a_tolerance(client):
    body = dict(USER, track={"start": "2020-01-01", "stop": "2021-01-01", "step_days": 30, "tolerance_mas": 500})
    r = client.post("/v1/precession-nutation", json=body)
    assert r.status_code == 200, r.text
    model = r.json()["track"]["model"]
    assert model["tolerance_mas"] == 500 and model["estimated_error_mas"] <= 500
    assert any("never measured" in w for w in model["warnings"])  # a user's orbit: its motion is unknown


@pytest.mark.parametrize("query, field", [
    ("tolerance_mas=0", "tolerance_mas"), ("tolerance_mas=-3", "tolerance_mas"),
    ("tolerance_mas=nan", "tolerance_mas"), ("model=exact", "model"),
    ("tolerance_mas=10&order=4", "tolerance_mas"), ("model=series", "order"),
])
def test_bad_tolerance_or_model_is_422_naming_the_field(client, query, field):
    body = _problem(client.get(f"/v1/bodies/vesta/track?start=2020-01-01&stop=2021-01-01&step_days=10&{query}"),
                    422)
    assert any(e["field"] == field for e in body["errors"]) or body.get("field") == field, body


def test_unreachable_tolerance_is_422_not_applicable_with_the_best_estimate(client):
    body = _problem(client.get("/v1/bodies/vesta/track?start=2000-01-01&stop=2200-01-01&step_days=365"
                               "&tolerance_mas=1"), 422)
    assert body["title"] == "Not applicable" and "estimated good to" in body["reason"]


def test_a_record_gives_each_missing_sigma_its_reason_and_the_correlations(client):
    """Vesta's pole has no published σ (the record says why); the Moon's moments, derived from lunar laser
    ranging's β and γ, are correlated as their derivation gives them; the JSON is the library's record."""
    vesta = client.get("/v1/bodies/vesta").json()
    assert vesta["values"]["pole.ra"]["uncertainty"] is None and "WGCCRE" in vesta["values"]["pole.ra"]["no_uncertainty"]
    assert vesta["values"]["rotation.period"]["no_uncertainty"] is None
    moon = client.get("/v1/bodies/moon").json()
    assert moon == json.loads(json.dumps(api.body_record("moon")))
    (corr,) = moon["correlations"]
    assert corr["inputs"] == ["inertia.A", "inertia.B"] and 0.5 < corr["value"] < 0.7
