"""The requests of issue 42, each answered as it should be: a 200 with finite numbers where the input is valid, a 422
problem naming the field where it is not; the Host header never reaches a page; a JSON key given twice is refused.
(The connection kept after a 500 and the 1 MB header: tests/service/test_connection.py; every route at every
numeric edge: tests/service/test_numeric_edges.py.)"""
from __future__ import annotations

import json
import math
import re

import pytest
from fastapi.testclient import TestClient

from service.app import create_app
from service.problems import PROBLEM, TYPE_BASE
from service.settings import Settings

APP = create_app(Settings(warm_up=False))
NEAR_ZERO = {"start_year": "-5e-324", "stop_year": "4.2e-90", "step_years": "500"}
SUB_RESOLUTION = "start=JD2451545&stop=JD2451545.000000001"
#: the smallest step Julian dates near J2000 resolve: 2^-31 d (IEEE 754 doubles in [2^21, 2^22)), 40.2 µs
SMALLEST = "4.657e-10 d (40.2 µs)"
USER = {"name": "issue-42",
        "orbit": {"a_au": 2.36, "e": 0.089, "i_deg": 7.14, "node_deg": 103.7, "peri_deg": 151.7,
                  "mean_anomaly_deg": 169.2, "epoch_jd_tdb": 2460200.5},
        "pole": {"ra_deg": 309.03, "dec_deg": 42.23, "epoch_jd_tdb": 2451545.0},
        "rotation_period_hours": 5.342, "moments": {"A": 0.3433, "B": 0.3546, "C": 0.42}}
ROW = {"name": "issue-42", **USER["orbit"], "pole_ra_deg": 309.03, "pole_dec_deg": 42.23,
       "rotation_period_hours": 5.342, "moment_a": 0.3433, "moment_b": 0.3546, "moment_c": 0.42}
NON_FINITE = re.compile(r"(?i)(?<![\w.])[-+]?(nan|inf|infinity)(?![\w])")


@pytest.fixture(scope="module")
def client():
    with TestClient(APP, raise_server_exceptions=False) as c:
        yield c


def _finite(text: str):
    def refuse(constant):
        raise AssertionError(f"{constant} in a JSON answer")
    return json.loads(text, parse_constant=refuse)


def _page_text(html: str) -> str:
    return re.sub(r"<[^>]+>", " ", re.sub(r"(?s)<style\b.*?</style>", " ", html))


def _invalid(r, field: str) -> str:
    assert r.status_code == 422 and r.headers["content-type"] == PROBLEM, (r.status_code, r.text[:300])
    problem = r.json()
    assert problem["type"] == TYPE_BASE + "invalid-input"
    (error,) = problem["errors"]
    assert error["field"] == field, problem
    return error["reason"]


# ------------------------------------------------------------------ 1. a history over a near-zero span

def _catalogue(client) -> list[str]:
    return [b["name"] for b in client.get("/v1/bodies").json()]


def test_a_history_over_a_near_zero_span_is_its_epoch_at_j2000_for_every_body(client):
    """Was a 500 for every body but the Moon (the orbit's spline: "x must be strictly increasing"); the span is
    shorter than the step, so the history is its one epoch, start_year = -5e-324, which is J2000.0."""
    for name in _catalogue(client):
        r = client.get(f"/v1/bodies/{name}/history", params=NEAR_ZERO)
        if r.status_code == 422:        # a body no orbit model serves: said so, with the reason
            assert r.json()["type"] == TYPE_BASE + "not-applicable", (name, r.text[:300])
            continue
        assert r.status_code == 200, (name, r.status_code, r.text[:300])
        ans = _finite(r.text)
        assert ans["year"] == [-5e-324], name
        assert 0.0 <= ans["obliquity_deg"][0] <= 180.0 and math.isfinite(ans["estimated_error_deg"][0]), name


def test_the_near_zero_history_s_figure_and_page(client):
    r = client.get("/v1/bodies/Eros/history.png",
                   params={"start_year": "-4.99e-210", "stop_year": "2.34e-145", "dpi": "299"})
    assert r.status_code == 200 and r.content.startswith(b"\x89PNG\r\n\x1a\n")
    svg = client.get("/v1/bodies/Eros/history.svg", params={"start_year": "-4.99e-210", "stop_year": "2.34e-145"})
    assert svg.status_code == 200 and "years since -4.99e-210" in svg.text      # the axis: not 0.000...0
    page = client.get("/bodies/vesta/history", params=NEAR_ZERO)
    assert page.status_code == 200 and not NON_FINITE.search(_page_text(page.text))


def test_the_near_zero_history_in_the_posts_and_the_batch_form(client):
    r = client.post("/v1/precession-nutation", json={**USER, "history": {k: float(v) for k, v in NEAR_ZERO.items()}})
    assert r.status_code == 200, r.text[:300]
    assert _finite(r.text)["history"]["year"] == [-5e-324]
    r = client.post("/v1/batch", json={"rows": [ROW], "history": {k: float(v) for k, v in NEAR_ZERO.items()}})
    assert r.status_code == 200, r.text[:300]
    _finite(r.text)
    csv_text = ",".join(ROW) + "\n" + ",".join(str(v) for v in ROW.values()) + "\n"
    page = client.post("/batch", data=NEAR_ZERO, files={"file": ("bodies.csv", csv_text, "text/csv")})
    assert page.status_code == 200 and not NON_FINITE.search(_page_text(page.text))


# ------------------------------------------------------------------ 2. a track step below a Julian date's resolution

@pytest.mark.parametrize("body", ["ceres", "vesta", "eros", "itokawa", "mars", "earth", "moon"])
def test_a_track_step_below_the_dates_resolution_is_refused_naming_the_smallest_step(client, body):
    """Was a 500 ("non-finite values") for every step from 1e-12 to 3e-10 d, seven bodies."""
    for step in ("1e-12", "1e-11", "1e-10", "3e-10"):
        reason = _invalid(client.get(f"/v1/bodies/{body}/track?{SUB_RESOLUTION}&step_days={step}"), "step_days")
        assert f"the smallest step these dates resolve is {SMALLEST}" in reason


def test_the_sub_resolution_track_in_csv_and_on_the_page(client):
    """The CSV answered 200 with 932 rows, many epochs repeated; the page showed "nan mas"."""
    _invalid(client.get(f"/v1/bodies/ceres/track?{SUB_RESOLUTION}&step_days=1e-12&format=csv"), "step_days")
    page = client.get(f"/bodies/ceres/track?{SUB_RESOLUTION}&step_days=1e-12")
    assert page.status_code == 422 and SMALLEST.split(" (")[0] in page.text
    assert not NON_FINITE.search(_page_text(page.text))
    r = client.post("/v1/precession-nutation", json={**USER, "track": {"start": "JD2451545",
                                                                       "stop": "JD2451545.000000001",
                                                                       "step_days": 1e-12}})
    _invalid(r, "track.step_days")


def test_a_track_at_ceres_pole_epoch_is_finite_on_the_page_and_in_the_api(client):
    """A track whose epochs all sit at Ceres' pole epoch (J2000): the estimate was 0/0 there ("nan mas")."""
    q = "start=JD2451545&stop=JD2451545&step_days=1"
    ans = _finite(client.get(f"/v1/bodies/ceres/track?{q}").text)
    assert ans["jd_tdb"] == [2451545.0] and math.isfinite(ans["model"]["estimated_error_mas"])
    page = client.get(f"/bodies/ceres/track?{q}")
    assert page.status_code == 200 and not NON_FINITE.search(_page_text(page.text))
    assert re.search(r"\d mas", _page_text(page.text))


# ------------------------------------------------------------------ 6. the Host header, JSON keys given twice

TRACK_PAGE = "/bodies/vesta/track?start=2020-01-01&stop=2020-03-01&step_days=30"


def test_the_host_header_never_reaches_a_page(client):
    for path in (TRACK_PAGE, "/bodies/vesta/history?start_year=-400&stop_year=0&step_years=200", "/bodies/vesta"):
        r = client.get(path, headers={"Host": "evil.example"})
        assert r.status_code == 200 and "evil.example" not in r.text, path
    text = client.get(TRACK_PAGE, headers={"Host": "evil.example"}).text
    assert 'href="/v1/bodies/Vesta/track?start=2020-01-01' in text          # the link: relative
    assert "curl -s &#39;http://testserver/v1/bodies/Vesta/track?" in text   # the server's own address


def test_a_public_base_url_is_the_pages_api_address():
    app = create_app(Settings(warm_up=False, public_base_url="https://ephem.example.org/pn"))
    with TestClient(app) as c:
        text = c.get(TRACK_PAGE, headers={"Host": "evil.example"}).text
    assert "evil.example" not in text
    assert 'href="https://ephem.example.org/pn/v1/bodies/Vesta/track?start=2020-01-01' in text
    assert "curl -s &#39;https://ephem.example.org/pn/v1/bodies/Vesta/track?" in text


def test_the_public_base_url_setting_is_checked(monkeypatch):
    monkeypatch.setenv("EPHEM_PUBLIC_BASE_URL", "https://ephem.example.org/")
    assert Settings.from_env().public_base_url == "https://ephem.example.org"
    monkeypatch.setenv("EPHEM_PUBLIC_BASE_URL", "ephem.example.org")
    with pytest.raises(SystemExit, match="EPHEM_PUBLIC_BASE_URL"):
        Settings.from_env()


def _post_text(client, path: str, text: str):
    return client.post(path, content=text, headers={"content-type": "application/json"})


@pytest.mark.parametrize("path, text, field", [
    ("/v1/precession-nutation", json.dumps(USER)[:-1] + ', "name": "y"}', "name"),
    ("/v1/precession-nutation", json.dumps(USER).replace('"e": 0.089', '"e": 0.089, "e": 0.5'), "orbit.e"),
    ("/v1/precession-nutation", json.dumps({**USER, "track": {"start": "2020-01-01", "stop": "2020-03-01"}})
     .replace('"stop": "2020-03-01"', '"stop": "2020-03-01", "step_days": 1, "step_days": 30'), "track.step_days"),
    ("/v1/batch", json.dumps({"rows": [ROW]}).replace('"a_au": 2.36', '"a_au": 2.36, "a_au": 3'), "rows[0].a_au"),
    ("/v1/batch", '{"rows": [], "rows": []}', "rows"),
])
def test_a_json_key_given_twice_is_refused_naming_it(client, path, text, field):
    """Was taken silently (the last one), while a repeated query parameter is a 422."""
    reason = _invalid(_post_text(client, path, text), field)
    assert "given 2 times" in reason and "give each key once" in reason


def test_a_json_body_with_each_key_once_is_served_and_a_repeated_query_parameter_still_refused(client):
    assert _post_text(client, "/v1/precession-nutation", json.dumps(USER)).status_code == 200
    assert _post_text(client, "/v1/precession-nutation", json.dumps([USER, USER])).status_code == 422
    _invalid(client.get("/v1/bodies/vesta/precession?order=2&order=4"), "order")


def test_the_batch_page_refuses_an_uploaded_json_with_a_key_twice(client):
    from service.batch_input import batch_rows
    from ephem.api import InvalidInputError

    with pytest.raises(InvalidInputError) as err:
        batch_rows(b'[{"name": "a", "name": "b"}]', "application/json")
    assert err.value.field == "[0].name"


def test_a_posted_bodys_history_on_a_scattered_orbit_is_a_422_naming_it(client):
    """The memory soak's one 500 (seed 42, request 7401): a posted Jupiter-crossing body (perihelion 2.0, aphelion
    6.1 AU) with a history. Its on-demand N-body orbit was scattered (a = 4.0 -> 7.1 AU within 1,000 years), the
    history's spline of e crossed 1 and the answer held NaN. Now a 422 saying why."""
    body = {"name": "soak-7401", "orbit": {"a_au": 4.064802494, "e": 0.507698445, "i_deg": 9.97891453313951,
                                           "node_deg": 23.515563533894444, "peri_deg": 37.958507408822506,
                                           "mean_anomaly_deg": 334.9514680266173, "epoch_jd_tdb": 2460200.5},
            "pole": {"ra_deg": 315.63613037056706, "dec_deg": 27.667951838710735, "epoch_jd_tdb": 2451545.0},
            "rotation_period_hours": 31.566677021654233, "dynamical_ellipticity": 0.023180429027110455,
            "history": {"start_year": -1500.0, "stop_year": 500.0, "step_years": 50.0}}
    r = client.post("/v1/precession-nutation", json=body)
    assert r.status_code == 422, r.text
    assert "scattered" in r.json()["detail"]
    body["history"] = None
    assert client.post("/v1/precession-nutation", json=body).status_code == 200    # the body itself is fine
