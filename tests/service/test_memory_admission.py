"""A worker's memory for requests (issue 42): the predicted peaks of the requests running in one worker, summed, stay
within EPHEM_WORKER_REQUEST_MEMORY_MB; one that does not fit gets 503 busy naming the memory, one alone over the whole
allowance 422 over-budget; the memory settings agree at start-up; the requests the memory soak found above their
prediction now stay within it."""
from __future__ import annotations

import threading
import time
import tracemalloc
from contextlib import contextmanager

import pytest
from fastapi.testclient import TestClient

from ephem import api
from ephem.base.budget import Cost, Part, budget, charge, checkpoint
from service.app import create_app
from service import guards
from service.guards import TRIM_AFTER_REQUEST_MB, MemoryAllowance
from service.problems import PROBLEM
from service.settings import KEPT_FIXED_MB, RSS_SLACK_MB, Settings

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


@contextmanager
def _held(app, client, mb: float):
    """A request holding ``mb`` MB of the allowance, in a thread, until the block ends (then released and joined):
    yields its dict, whose ``"r"`` is its response once it has ended."""
    holder, out = _in_thread(client, f"/test/memory?mb={mb:g}&hold=true")
    assert app.state.holding.wait(PATIENCE_S)
    try:
        yield out
    finally:
        app.state.release.set()
        holder.join(PATIENCE_S)


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
        with _held(app, client, 60) as out:
            r = client.get("/test/memory?mb=50")                     # 60 + 50 > 100
            within = client.get("/test/memory?mb=40")                # 60 + 40 = 100: runs
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
        with _held(app, client, 96):
            # 10^4 epochs, ~7 MB predicted: 96 + 7 > 100
            r = client.get("/v1/bodies/mars/free-motion?start=2451545&stop=2461545&step_days=1&method=exact")
    assert r.status_code == 503, r.status_code
    assert "MB of memory" in r.json()["detail"]


# ------------------------------------------------------------------ the settings agree

def test_the_per_request_memory_follows_the_workers_allowance_and_may_not_exceed_it(monkeypatch):
    monkeypatch.delenv("EPHEM_MAX_REQUEST_MEMORY_MB", raising=False)
    monkeypatch.delenv("EPHEM_MODEL_CACHE_MB", raising=False)
    monkeypatch.setenv("EPHEM_WORKER_RSS_MB", "600")           # room for 200 MB in flight (see below)
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
        Settings(worker_request_memory_mb=4000.0, max_request_memory_mb=100.0, worker_rss_mb=5000.0).check()


def test_the_defaults_keep_a_worker_under_its_400_mb_bound():
    # what a worker keeps besides its caches (256 MB measured), the caches, the requests in flight and the slack
    s = Settings()
    assert s.check() is s
    assert s.worker_rss_mb == 400.0
    assert s.max_request_memory_mb <= s.worker_request_memory_mb
    assert KEPT_FIXED_MB + s.model_cache_mb + s.worker_request_memory_mb + RSS_SLACK_MB <= 400.0
    assert s.worker_keep_mb + s.worker_request_memory_mb + RSS_SLACK_MB <= 400.0


@pytest.mark.parametrize("bound_mb", [290.0, 320.0, 400.0, 433.3, 512.0, 2048.0])
def test_the_memory_settings_follow_the_bound_and_sum_within_it(monkeypatch, bound_mb):
    for name in ("EPHEM_WORKER_REQUEST_MEMORY_MB", "EPHEM_MAX_REQUEST_MEMORY_MB", "EPHEM_MODEL_CACHE_MB"):
        monkeypatch.delenv(name, raising=False)
    monkeypatch.setenv("EPHEM_WORKER_RSS_MB", str(bound_mb))
    s = Settings.from_env()                                      # checked
    assert s == Settings(worker_rss_mb=bound_mb)                 # the same derivation from the environment and in code
    assert s.worker_request_memory_mb > 0 and s.model_cache_mb > 0
    assert s.max_request_memory_mb == s.worker_request_memory_mb
    assert KEPT_FIXED_MB + s.model_cache_mb + s.worker_request_memory_mb + RSS_SLACK_MB <= bound_mb
    assert bound_mb - 0.2 < KEPT_FIXED_MB + s.model_cache_mb + s.worker_request_memory_mb + RSS_SLACK_MB  # all used
    # what an idle worker may keep holds its own memory and full caches: it is not recycled for what it must keep
    assert s.worker_keep_mb >= KEPT_FIXED_MB + s.model_cache_mb


def test_settings_that_do_not_fit_the_bound_are_refused_at_start_up(monkeypatch):
    with pytest.raises(SystemExit, match="EPHEM_WORKER_RSS_MB"):
        Settings(worker_rss_mb=280.0).check()                    # under what a worker keeps and the slack
    with pytest.raises(SystemExit, match="EPHEM_WORKER_REQUEST_MEMORY_MB"):
        Settings(worker_request_memory_mb=150.0).check()         # 256 + 150 + 32 > 400 with no caches left
    with pytest.raises(SystemExit, match="EPHEM_MODEL_CACHE_MB"):
        Settings(model_cache_mb=64.0, worker_request_memory_mb=80.0).check()     # the old defaults: 432 MB
    with pytest.raises(SystemExit, match="EPHEM_WORKER_RSS_MB"):
        create_app(Settings(warm_up=False, model_cache_mb=64.0, worker_request_memory_mb=80.0))   # checked there too
    # one of the two set, the other is the rest of the room
    assert Settings(model_cache_mb=64.0).check().worker_request_memory_mb == pytest.approx(48.0)
    assert Settings(worker_rss_mb=432.0, model_cache_mb=64.0).check().worker_request_memory_mb == pytest.approx(80.0)
    assert Settings(worker_request_memory_mb=100.0).check().model_cache_mb == pytest.approx(12.0)


# ------------------------------------------------------------------ the freed memory returned after a large request

def _counting_trims(monkeypatch, app):
    """Replaces the allocator's trim by a counter that also notes what the worker's requests held of their allowance
    when it ran."""
    trims: list[float] = []
    monkeypatch.setattr(guards, "release_free_memory", lambda: trims.append(app.state.memory_allowance.held_mb))
    return trims


def test_a_large_request_returns_its_freed_memory_as_it_ends_and_a_small_one_does_not(monkeypatch):
    app = _app(limit_mb=100.0)
    trims = _counting_trims(monkeypatch, app)
    with TestClient(app) as client:                              # not supervised: no watchdog trimming each second
        small = 0.5 * TRIM_AFTER_REQUEST_MB
        assert client.get(f"/test/memory?mb={small}").status_code == 200
        assert trims == []
        assert client.get(f"/test/memory?mb={TRIM_AFTER_REQUEST_MB}").status_code == 200   # at it: not above
        assert trims == []
        large = 10.0 * TRIM_AFTER_REQUEST_MB
        assert client.get(f"/test/memory?mb={large}").status_code == 200
        assert len(trims) == 1
        # returned before its share was given back: the next request admitted finds the memory returned
        assert trims[0] == pytest.approx(large)
        assert app.state.memory_allowance.held_mb == 0.0
        assert client.get(f"/test/memory?mb={small}").status_code == 200
        assert len(trims) == 1


def test_a_large_request_refused_after_its_charge_returns_its_memory_too(monkeypatch):
    # a request charged above the threshold and then refused (503 busy at its checkpoint) may have allocated
    # before its charge; it is trimmed after like any other
    app = _app(limit_mb=100.0)
    trims = _counting_trims(monkeypatch, app)
    with TestClient(app) as client:
        with _held(app, client, 60) as out:
            r = client.get("/test/memory?mb=50")                     # 60 + 50 > 100: refused at its checkpoint
    assert r.status_code == 503 and out["r"].status_code == 200
    assert len(trims) == 2                                           # the refused one and the holder


# ------------------------------------------------------------------ what the soak found# ------------------------------------------------------------------ what the soak found above its prediction

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
