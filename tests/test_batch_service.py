"""POST /v1/batch: a few bodies at once over HTTP, as JSON rows or CSV, within the request's limits."""
import pytest
from fastapi.testclient import TestClient

from ephem import api
from service.app import create_app
from service.settings import Settings

ROW = {"name": "testa", "a_au": 2.36, "e": 0.09, "i_deg": 7.1, "node_deg": 103.7, "peri_deg": 151.7,
       "mean_anomaly_deg": 169.2, "epoch_jd_tdb": 2460200.5, "pole_ra_deg": 309.03, "pole_dec_deg": 42.23,
       "rotation_period_hours": 5.342, "dynamical_ellipticity": 0.1689}


@pytest.fixture(scope="module")
def client():
    return TestClient(create_app(Settings(warm_up=False, max_batch_rows=5)))


def test_json_rows_are_the_librarys_answer_and_a_bad_row_spoils_nothing(client):
    rows = [ROW, dict(ROW, name="bad", e=1.5), dict(ROW, name="other", pole_dec_deg=-10.0)]
    r = client.post("/v1/batch", json=rows)
    assert r.status_code == 200
    body = r.json()
    assert body == {**api.batch(rows), "columns": body["columns"]}
    assert body["rows"][1]["error"].startswith("e: eccentricity must satisfy 0 <= e < 1")
    assert body["rows"][1]["precession_rate_arcsec_per_year"] is None
    assert body["rows"][0]["error"] == body["rows"][2]["error"] == ""


def test_csv_gives_the_same_rows(client):
    header = ",".join(ROW)
    line = ",".join(str(v) for v in ROW.values())
    r = client.post("/v1/batch", content=f"{header}\n{line}\n", headers={"content-type": "text/csv"})
    assert r.status_code == 200
    # CSV carries the decimal strings of the same numbers: the same floats, the same answer
    assert r.json()["rows"] == client.post("/v1/batch", json=[ROW]).json()["rows"]


@pytest.mark.parametrize("payload, field", [
    ([ROW] * 6, "rows"),                                   # over this service's max_batch_rows (5)
    ([dict(ROW, colour=3)], "rows[0]"),                    # a column no body has
    ({"rows": [ROW], "history": {"start_year": 0}}, "history"),
    ({"rows": [ROW], "history": {"start_year": 0, "stop_year": -5, "step_years": 1}}, "history"),
    ([], "rows"),
    ({"rows": "x"}, "rows"),
])
def test_bad_requests_name_the_field(client, payload, field):
    r = client.post("/v1/batch", json=payload)
    assert r.status_code == 422
    assert r.json()["errors"][0]["field"] == field


def test_too_many_rows_say_to_use_the_cli(client):
    r = client.post("/v1/batch", json=[ROW] * 6)
    assert "ephem batch" in r.json()["detail"]


def test_a_history_over_the_budget_is_refused_before_the_work(client):
    """Five histories over 10 Myr: 5 x (2.5e-6 s x 1e7 yr) = 125 s of predicted CPU against the 5 s budget."""
    r = client.post("/v1/batch?start_year=-1e7&stop_year=0&step_years=1000", json=[ROW] * 5)
    assert r.status_code == 422 and r.json()["type"].endswith("over-budget")


def test_not_json_nor_csv_is_a_clear_error(client):
    r = client.post("/v1/batch", content=b"{not json", headers={"content-type": "application/json"})
    assert r.status_code == 422 and r.json()["errors"][0]["field"] == "body"
