"""POST /v1/batch: a few bodies at once over HTTP, as JSON rows or CSV, within the request's limits."""
import fcntl
import os

import numpy as np
import pytest
from fastapi.testclient import TestClient

from ephem import api
from ephem.theory import cost
from ephem.orbit import hansen
from ephem.batch import population
from ephem.bodies.catalogue import Body, Orbit, Pole
from service.app import create_app
from service.settings import Settings
from tests.service.test_bounded_work import _problem  # one home for the problem+json check

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
    ([dict(ROW, colour=3)], "rows[0].colour"),             # a column no body has
    ({"rows": [ROW], "history": {"start_year": 0}}, "history.stop_year"),
    ({"rows": [ROW], "history": {"start_year": 0, "stop_year": -5, "step_years": 1}}, "history.stop_year"),
    ([], "rows"),
    ({"rows": "x"}, "rows"),
    ([ROW, 5], "rows[1]"),                                 # a row that is not an object
    ([ROW, [1, 2]], "rows[1]"),
    (5, "rows"),
    ({"rows": [ROW], "histroy": {}}, "histroy"),           # a misspelt key is not dropped without a word
    ({"rows": [ROW], "history": "x"}, "history"),
    ({"rows": [ROW], "history": {"start_year": 0, "stop_year": 10, "step_years": 1, "x": 1}}, "history.x"),
    ({"rows": [ROW], "history": {"start_year": True, "stop_year": 10, "step_years": 1}}, "history.start_year"),
    # a step so small that the count of epochs is not a finite number (int() of it raised: a 500)
    ({"rows": [ROW], "history": {"start_year": 0, "stop_year": 10, "step_years": 5e-324}}, "history.step_years"),
])
def test_bad_requests_name_the_field(client, payload, field):
    r = client.post("/v1/batch", json=payload)
    assert r.status_code == 422
    assert r.json()["errors"][0]["field"] == field


def test_too_many_rows_say_to_use_the_cli(client):
    r = client.post("/v1/batch", json=[ROW] * 6)
    assert "ephem batch" in r.json()["detail"]


def test_a_history_over_the_budget_is_refused_before_the_work(client):
    """Five histories over 20 Myr (the longest span): the predicted spin integrations alone (ephem.theory.cost.
    spin_history, 1.6 s a row since the splitting of issue 33) pass the 5 s budget: refused before the work."""
    assert 5 * cost.spin_history(2e7, 20_001).cpu_s > 5.0
    r = client.post("/v1/batch?start_year=-2e7&stop_year=0&step_years=1000", json=[ROW] * 5)
    assert r.status_code == 422 and r.json()["type"].endswith("over-budget")


def test_not_json_nor_csv_is_a_clear_error(client):
    r = client.post("/v1/batch", content=b"{not json", headers={"content-type": "application/json"})
    assert r.status_code == 422 and r.json()["errors"][0]["field"] == "body"


# --- malformed bodies (issue 29): each a 422 naming where, or its row's error; never a 500

CSV_HEADER = ",".join(ROW)
CSV_LINE = ",".join(str(v) for v in ROW.values())


def _csv(client, text):
    return client.post("/v1/batch", content=text if isinstance(text, bytes) else text.encode(),
                       headers={"content-type": "text/csv"})



@pytest.mark.parametrize("text, field, says", [
    # csv.DictReader put the surplus cells under a None key, and sorting the columns with it was a 500
    ("name,a_au\nr,1,2\n", "rows[0]", "line 2 has 3 cells for the header's 2 columns"),
    (f"{CSV_HEADER}\n{CSV_LINE}\n{CSV_LINE},9\n", "rows[1]", "line 3 has 13 cells for the header's 12 columns"),
    (f"{CSV_HEADER}\n{CSV_LINE}\nw,2.36\n", "rows[1]", "line 3 has 2 cells for the header's 12 columns"),
])
def test_a_csv_line_with_surplus_or_missing_cells_is_refused_naming_its_row(client, text, field, says):
    """A cell too many or too few cannot be matched to its column: the request is refused, as ephem batch
    refuses such a file, naming the row and its line."""
    error = _problem(_csv(client, text), 422, "invalid-input")["errors"][0]
    assert error["field"] == field and says in error["reason"]


def test_a_csv_cell_that_is_not_utf8_is_its_rows_error(client):
    cells = [str(v).encode() for v in ROW.values()]
    cells[list(ROW).index("i_deg")] = b"7.\xff1"
    r = _csv(client, f"{CSV_HEADER}\n{CSV_LINE}\n".encode() + b",".join(cells) + b"\n")
    assert r.status_code == 200, r.text
    good, bad = r.json()["rows"]
    assert good["error"] == "" and good == client.post("/v1/batch", json=[ROW]).json()["rows"][0]
    assert bad["error"].startswith("i_deg: not UTF-8 text")
    assert all(v in (None, "") for k, v in bad.items() if k not in ("name", "error"))


@pytest.mark.parametrize("text, field", [
    (b"\xffname,a_au\nr,1\n", "body"),                                     # the header is not UTF-8
    (f"name,{CSV_HEADER}\nx,{CSV_LINE}\n".encode(), "name"),               # a column twice: which one holds?
])
def test_a_csv_header_that_cannot_name_the_columns_is_refused(client, text, field):
    assert _problem(_csv(client, text), 422, "invalid-input")["errors"][0]["field"] == field


def test_a_utf8_byte_order_mark_is_not_part_of_the_first_column(client):
    r = _csv(client, b"\xef\xbb\xbf" + f"{CSV_HEADER}\n{CSV_LINE}\n".encode())
    assert r.status_code == 200 and r.json()["rows"][0]["error"] == ""


@pytest.mark.parametrize("cell, reason", [
    ({"e": True}, "e: not a number: a boolean (true)"),       # float(True) was 1.0: an answer for a value never given
    ({"e": [0.1]}, "e: not a number: an array"),        # two alike rows made a 2-D column of lists
    ({"e": "abc"}, "e: not a number: 'abc'"),           # ephem batch's reason for the same cell
    ({"name": {"a": 1}}, "name: not text: an object"),
])
def test_a_json_cell_of_the_wrong_kind_is_its_rows_error(client, cell, reason):
    r = client.post("/v1/batch", json=[ROW, dict(ROW, **cell), dict(ROW, **cell)])
    assert r.status_code == 200, r.text
    good, bad, again = r.json()["rows"]
    assert good["error"] == "" and bad["error"] == again["error"] == reason
    assert all(v in (None, "") for k, v in bad.items() if k not in ("name", "error"))


def test_history_errors_name_the_query_parameter_the_client_wrote(client):
    error = _problem(client.post("/v1/batch?start_year=0", json=[ROW]), 422, "invalid-input")["errors"][0]
    assert error["field"] == "stop_year" and "missing" in error["reason"]


# --- what a batch costs (issue 29): each row at its own eccentricity, charged before the work

E99 = dict(ROW, name="eccentric", e=0.99)


def _single_body(row: dict) -> Body:
    return Body(name=row["name"], orbit=Orbit(*(row[k] for k in ("a_au", "e", "i_deg", "node_deg", "peri_deg",
                                                                  "mean_anomaly_deg", "epoch_jd_tdb")),
                                              body=row["name"]),
                pole=Pole(row["pole_ra_deg"], row["pole_dec_deg"]), rotation_period_hours=row["rotation_period_hours"],
                dynamical_ellipticity=row["dynamical_ellipticity"])


def _no_work(*args, **kwargs):
    raise AssertionError("a refused batch computed its rows")


def test_two_hundred_eccentric_rows_are_refused_at_once_with_their_estimate(tmp_path, monkeypatch):
    """200 rows at e = 0.99 were estimated at 0.04 s and ran to the 20 s deadline (503). Each row's Hansen
    coefficients are a 262 144-point FFT, which the single-body precession answer prices at 0.19 s: the batch, priced
    row by row with the same formula, is over the budget and refused before any row is computed."""
    settings = Settings(warm_up=False, lock_dir=str(tmp_path))
    assert settings.max_batch_rows == 200
    monkeypatch.setattr(population, "evaluate", _no_work)
    with TestClient(create_app(settings), raise_server_exceptions=False) as c:
        body = _problem(c.post("/v1/batch", json=[E99] * 200), 422, "over-budget")
    assert body["errors"][0]["field"] == "rows[0].e"
    assert body["estimated_cpu_s"] > body["budget_cpu_s"] == settings.max_request_cpu_s
    # an upper bound of the work: at least the single-body estimate of the same body's precession, per row
    one = api.answer_cost(_single_body(E99), order=None).cpu_s
    assert one >= cost.hansen_fft_s(hansen.fft_length(0.99, None)) > 0.1
    assert body["estimated_cpu_s"] >= 200 * one


def test_the_estimate_prices_every_fft_the_rows_make(monkeypatch):
    """The estimate against the work it predicts, counted rather than timed: every Kepler-and-FFT pass evaluate
    makes (rows x N samples, recorded), priced at the single-body formula, is within the estimate's Hansen parts,
    the sigma's extra evaluations included; a row the checks refuse makes none and costs none."""
    made = []
    sample = hansen._sample_functions

    def counted(e, N):
        made.append((np.size(e), N))
        return sample(e, N)

    monkeypatch.setattr(hansen, "_sample_functions", counted)
    rows = [dict(ROW, name=f"r{j}", e=e) for j, e in enumerate([0.05, 0.3, 0.3, 0.9, 0.97, 0.97])]
    rows += [dict(ROW, name="sigma", e=0.9, e_sigma=1e-3), dict(ROW, name="unbound", e=1.5)]
    columns = {k: np.array([r.get(k) for r in rows], dtype=object) for k in set().union(*rows)}
    estimate = population.batch_cost(len(rows), None, population.sigma_inputs(columns), columns)
    out = population.evaluate(columns)
    assert list(out["error"][:-1]) == [""] * 7 and out["error"][-1].startswith("e: eccentricity")
    assert sum(count for count, _ in made) == 7 + 2     # each good row once, the sigma row twice more
    priced = sum(p.cpu_s for p in estimate.parts if p.parameter.startswith("rows["))
    assert sum(count * cost.hansen_fft_s(N) for count, N in made) <= priced
    # the row at e = 0.97 sets the estimate's largest part, named by its path
    assert estimate.largest().parameter == "rows[4].e"


def test_a_large_batch_takes_the_slot_for_large_work(tmp_path, monkeypatch):
    """Five rows at e = 0.97 (65 536-point FFTs, ~0.24 s estimated: above the 0.1 s threshold) were priced as cheap,
    and four such batches ran at once past the slot for large work. Now such a batch needs the slot like any large
    request: it finds it taken by another worker's request (503 busy, before any row), while a full batch of
    ordinary rows is not rationed; with the slot free it runs holding it."""
    settings = Settings(warm_up=False, heavy_slots=1, lock_dir=str(tmp_path))
    heavy = [dict(ROW, name=f"h{j}", e=0.97) for j in range(5)]
    lock = str(tmp_path / "heavy-0.lock")
    held = os.open(lock, os.O_RDWR | os.O_CREAT, 0o600)
    fcntl.flock(held, fcntl.LOCK_EX)     # another worker's large request (flock: any other open file conflicts)
    try:
        with TestClient(create_app(settings), raise_server_exceptions=False) as c:
            with monkeypatch.context() as m:
                m.setattr(population, "evaluate", _no_work)
                r = c.post("/v1/batch", json=heavy)
            body = _problem(r, 503, "busy")
            assert body["estimated_cpu_s"] > body["heavy_request_cpu_s"] == settings.heavy_request_cpu_s
            assert int(r.headers["retry-after"]) >= 1
            ordinary = c.post("/v1/batch", json=[ROW] * settings.max_batch_rows)
            assert ordinary.status_code == 200, ordinary.text
            os.close(held)
            held = None
            evaluate = population.evaluate

            def in_the_slot(*args, **kwargs):
                probe = os.open(lock, os.O_RDWR)
                try:
                    with pytest.raises(BlockingIOError):
                        fcntl.flock(probe, fcntl.LOCK_EX | fcntl.LOCK_NB)
                finally:
                    os.close(probe)
                return evaluate(*args, **kwargs)

            monkeypatch.setattr(population, "evaluate", in_the_slot)
            r = c.post("/v1/batch", json=heavy)
            assert r.status_code == 200, r.text
            assert [row["error"] for row in r.json()["rows"]] == [""] * 5
    finally:
        if held is not None:
            os.close(held)


def test_a_history_row_is_priced_with_the_model_its_secular_spin_builds(client, monkeypatch):
    """Three histories at e = 0.95 were estimated at 0.05 s and took 6-13 s: each row's secular spin builds the body's
    first-order model and its nutation's extremes over one orbit, which the single-body nutation answer prices at
    seconds. Priced so, they are over the budget."""
    monkeypatch.setattr(population, "evaluate", _no_work)
    row = dict(ROW, e=0.95)
    body = _problem(client.post("/v1/batch?start_year=-1000&stop_year=0&step_years=100", json=[row] * 3), 422,
                    "over-budget")
    assert body["errors"][0]["field"] == "rows[0].e"
    assert body["estimated_cpu_s"] >= 3 * api.answer_cost(_single_body(row), order=None, nutation=True).cpu_s


def test_a_history_is_priced_from_its_poles_epoch(client, monkeypatch):
    """1000 years 15 million years ago: each history integrates from its pole's epoch (J2000.0) through the span, as
    ephem.longterm.history.history_cost counts it, so 15 million years a row, not the thousand asked for; the end of
    the span that sets it is named as the client wrote it."""
    monkeypatch.setattr(population, "evaluate", _no_work)
    span = {"start_year": -15_000_000, "stop_year": -14_999_000, "step_years": 100}
    # 15 million years a row pass the 5 s budget in five rows, where the thousand asked for would not
    assert 5 * cost.spin_history(15_000_000, 11).cpu_s > 5.0 > 5 * cost.spin_history(1_000, 11).cpu_s
    body = _problem(client.post("/v1/batch?start_year=-15000000&stop_year=-14999000&step_years=100",
                                json=[ROW] * 5), 422, "over-budget")
    assert body["errors"][0]["field"] == "start_year"
    assert body["estimated_cpu_s"] >= 5 * cost.spin_history(15_000_000, 11).cpu_s
    body = _problem(client.post("/v1/batch", json={"rows": [ROW] * 5, "history": span}), 422, "over-budget")
    assert body["errors"][0]["field"] == "history.start_year"
