"""A worker's memory for requests (issue 42): the predicted peaks of the requests running in one worker, summed, stay
within EPHEM_WORKER_REQUEST_MEMORY_MB; one that does not fit gets 503 busy naming the memory, one alone over the whole
allowance 422 over-budget; the memory settings agree at start-up; the requests the memory soak found above their
prediction now stay within it."""
from __future__ import annotations

import threading
import time
import tracemalloc

import pytest
from fastapi.testclient import TestClient

from ephem import api
from ephem.base.budget import Cost, Part, budget, charge, checkpoint
from service.app import create_app
from service.guards import MemoryAllowance
from service.problems import PROBLEM
from service.settings import Settings

#: a bound on every wait for another thread (never asserted: a test failing by it hangs no longer than this)
PATIENCE_S = 60.0


def _app(limit_mb: float = 100.0, wait_s: float = 0.0):
    """The service with a route that charges ``mb`` of memory, reaches a checkpoint and, with ``hold``, holds it
    until the test releases it."""
    app = create_app(Settings(warm_up=False, worker_request_memory_mb=limit_mb, max_request_memory_mb=limit_mb,
                              memory_wait_s=wait_s))
    app.state.holding, app.state.release = threading.Event(), threading.Event()

    @app.get("/test/memory")
    def hold(mb: float, hold: bool = False):
        charge(Cost((Part("mb", f"{mb} MB held", 0.0, mb),)))
        checkpoint()
        if hold:
            app.state.holding.set()
            app.state.release.wait(PATIENCE_S)
        return {"mb": mb}

    return app


def _in_thread(client, url: str) -> tuple[threading.Thread, dict]:
    out: dict = {}
    t = threading.Thread(target=lambda: out.setdefault("r", client.get(url)))
    t.start()
    return t, out


def _until(condition) -> None:
    end = time.monotonic() + PATIENCE_S
    while not condition() and time.monotonic() < end:
        time.sleep(0.01)


# ------------------------------------------------------------------ the allowance itself

def test_the_allowance_counts_the_sum_and_gives_it_back():
    a = MemoryAllowance(80.0, wait_s=0.0)
    assert a.take(50.0) and a.held_mb == 50.0
    assert not a.take(40.0)                     # 90 > 80: not counted
    assert a.held_mb == 50.0
    assert a.take(30.0)                         # exactly the limit fits
    a.give_back(50.0)
    assert a.take(40.0) and a.held_mb == pytest.approx(70.0)


# ------------------------------------------------------------------ through the service

def test_requests_whose_predictions_sum_over_the_allowance_get_503_busy_naming_memory():
    app = _app(limit_mb=100.0)
    with TestClient(app) as client:
        holder, out = _in_thread(client, "/test/memory?mb=60&hold=true")
        assert app.state.holding.wait(PATIENCE_S)
        try:
            r = client.get("/test/memory?mb=50")                     # 60 + 50 > 100
            within = client.get("/test/memory?mb=40")                # 60 + 40 = 100: runs
        finally:
            app.state.release.set()
            holder.join(PATIENCE_S)
        after = client.get("/test/memory?mb=50")                     # the holder gave its 60 MB back
    assert r.status_code == 503 and r.headers["content-type"].startswith(PROBLEM)
    body = r.json()
    assert body["type"].endswith("/busy") and "memory" in body["title"] and "MB of memory" in body["detail"]
    assert int(r.headers["Retry-After"]) >= 1
    assert body["estimated_memory_mb"] == pytest.approx(50.0)
    assert body["worker_request_memory_mb"] == 100.0 and body["in_flight_memory_mb"] == pytest.approx(60.0)
    assert "EPHEM_WORKER_REQUEST_MEMORY_MB" in body["detail"]
    assert within.status_code == 200 and out["r"].status_code == 200 and after.status_code == 200
    assert app.state.memory_allowance.held_mb == 0.0                 # every request gave its share back


def test_a_request_that_does_not_fit_waits_for_another_to_finish():
    app = _app(limit_mb=100.0, wait_s=PATIENCE_S)
    allowance = None
    with TestClient(app) as client:
        holder, held = _in_thread(client, "/test/memory?mb=70&hold=true")
        assert app.state.holding.wait(PATIENCE_S)
        allowance = app.state.memory_allowance
        waiter, waited = _in_thread(client, "/test/memory?mb=70")
        _until(lambda: allowance.waiting == 1)
        assert allowance.waiting == 1 and "r" not in waited        # waiting, not refused
        app.state.release.set()
        holder.join(PATIENCE_S)
        waiter.join(PATIENCE_S)
    assert held["r"].status_code == 200 and waited["r"].status_code == 200
    assert allowance.held_mb == 0.0


def test_one_request_over_the_whole_allowance_is_refused_422_with_its_estimate():
    with TestClient(_app(limit_mb=100.0)) as client:
        r = client.get("/test/memory?mb=120")
    body = r.json()
    assert r.status_code == 422 and body["type"].endswith("/over-budget")
    assert body["estimated_memory_mb"] == pytest.approx(120.0) and body["budget_memory_mb"] == 100.0
    assert body["errors"][0]["field"] == "mb"


def test_a_free_motion_is_counted_before_its_series_is_summed():
    # the free motion's charge is followed by a checkpoint (it had none before the series: never counted)
    app = _app(limit_mb=100.0)
    with TestClient(app) as client:
        holder, _ = _in_thread(client, "/test/memory?mb=96&hold=true")
        assert app.state.holding.wait(PATIENCE_S)
        try:
            # 10^4 epochs, ~7 MB predicted: 96 + 7 > 100
            r = client.get("/v1/bodies/mars/free-motion?start=2451545&stop=2461545&step_days=1&method=exact")
        finally:
            app.state.release.set()
            holder.join(PATIENCE_S)
    assert r.status_code == 503, r.status_code
    assert "MB of memory" in r.json()["detail"]


# ------------------------------------------------------------------ the settings agree

def test_the_per_request_memory_follows_the_workers_allowance_and_may_not_exceed_it(monkeypatch):
    monkeypatch.delenv("EPHEM_MAX_REQUEST_MEMORY_MB", raising=False)
    monkeypatch.setenv("EPHEM_WORKER_REQUEST_MEMORY_MB", "200")
    s = Settings.from_env()
    assert s.worker_request_memory_mb == 200.0 and s.max_request_memory_mb == 200.0
    monkeypatch.setenv("EPHEM_MAX_REQUEST_MEMORY_MB", "120")
    assert Settings.from_env().max_request_memory_mb == 120.0
    monkeypatch.setenv("EPHEM_MAX_REQUEST_MEMORY_MB", "500")
    with pytest.raises(SystemExit) as bad:
        Settings.from_env()
    assert "EPHEM_MAX_REQUEST_MEMORY_MB" in str(bad.value) and "EPHEM_WORKER_REQUEST_MEMORY_MB" in str(bad.value)
    with pytest.raises(SystemExit, match="EPHEM_MAX_REQUEST_MEMORY_MB"):
        create_app(Settings(warm_up=False, max_request_memory_mb=500.0))       # the app checks them too
    with pytest.raises(SystemExit, match="EPHEM_WORKER_MEMORY_MB"):
        Settings(worker_request_memory_mb=4000.0, max_request_memory_mb=100.0).check()


def test_the_defaults_keep_a_worker_under_its_400_mb_bound():
    # what a worker keeps after its requests (~320 MB in the memory soak) plus its requests' allowance
    s = Settings()
    assert s.check() is s
    assert s.max_request_memory_mb <= s.worker_request_memory_mb
    assert 320.0 + s.worker_request_memory_mb <= 400.0


# ------------------------------------------------------------------ what the soak found above its prediction

def test_the_moons_nutation_stays_within_a_few_mb():
    # its extremes over a node period were summed at 27,200 epochs at once: 37 MB, charged as 2
    api.nutation("moon")
    tracemalloc.start()
    try:
        api.nutation("moon")
        peak = tracemalloc.get_traced_memory()[1] / 2**20
    finally:
        tracemalloc.stop()
    assert peak < 8.0


def test_a_figures_drawing_is_charged_before_its_data():
    # a PNG at 300 dpi: 4 MB and 8 bytes a pixel of 58 square inches, ~44 MB predicted (18 MB measured)
    with budget(100.0, 20.0):
        with pytest.raises(api.OverBudgetError) as refused:
            api.render_plot("precession", "vesta", "2020-01-01", "2021-01-01", fmt="png", dpi=300)
    assert refused.value.field == "dpi" and refused.value.estimated_memory_mb > 20.0
