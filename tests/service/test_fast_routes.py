"""The routes served in one pass (service/fast_routes.py) and on the event loop when cheap (service/offload.py):
the same answers and the same problems as FastAPI's own handling, and the work where its price says."""
from __future__ import annotations

import asyncio
import dataclasses
import threading

import pytest
from fastapi import Body, FastAPI, Request
from fastapi.routing import APIRoute
from fastapi.testclient import TestClient
from starlette.responses import JSONResponse

import service.app as service_app
from service import offload
from service.fast_routes import OnePassRoute, one_pass
from service.settings import Settings

TRACK = "/v1/bodies/ceres/track?start=2040-01-01&stop=2040-12-31&step_days=10"

#: bad and edge queries of the track: each parameter's type, bounds, enumeration, absence and emptiness
QUERIES = [
    TRACK,
    TRACK + "&tolerance_mas=100",
    TRACK + "&model=secular&format=csv",
    "/v1/bodies/ceres/track?stop=2040-12-31&step_days=10",                          # start missing
    "/v1/bodies/ceres/track",                                                         # three missing
    TRACK.replace("step_days=10", "step_days=abc"),
    TRACK.replace("step_days=10", "step_days="),
    TRACK + "&tolerance_mas=-1",
    TRACK + "&tolerance_mas=",
    TRACK + "&free_wobble_J_arcsec=4000",
    TRACK + "&free_wobble_J_arcsec=-0.0",
    TRACK + "&axis=bogus",
    TRACK + "&model=bogus&order=1.5",
    TRACK + "&format=xml",
    TRACK + "&order=2&order=4",                                                       # repeated
    TRACK + "&perturbers=" + "x" * 101,                                               # too long
    TRACK + "&unknown=1",                                                             # ignored, as FastAPI does
    TRACK + "&dataset=nope",
    TRACK.replace("ceres", "no-such-body"),
    TRACK + "&rotation_phase_deg=1e308",
]


@pytest.fixture(scope="module")
def clients(monkeypatch_module):
    settings = dataclasses.replace(Settings.from_env(), warm_up=False)
    fast = TestClient(service_app.create_app(settings))
    monkeypatch_module.setattr(service_app, "OnePassRoute", APIRoute)      # FastAPI's own handling of every route
    plain = TestClient(service_app.create_app(settings))
    return fast, plain


@pytest.fixture(scope="module")
def monkeypatch_module():
    mp = pytest.MonkeyPatch()
    yield mp
    mp.undo()


def _comparable(response):
    """The answer less what differs between two runs of one request: the measured cost and the ETag that hashes it."""
    if "json" not in response.headers.get("content-type", ""):
        return response.text
    body = response.json()
    if isinstance(body, dict) and isinstance(body.get("model"), dict):
        body["model"].pop("cost_ms", None)
    return body


@pytest.mark.parametrize("query", QUERIES)
def test_a_one_pass_route_answers_as_fastapi_does(clients, query):
    fast, plain = clients
    a, b = fast.get(query), plain.get(query)
    assert a.status_code == b.status_code, (query, a.text, b.text)
    assert a.headers["content-type"] == b.headers["content-type"]
    assert _comparable(a) == _comparable(b), query


def test_the_track_route_is_served_in_one_pass(clients):
    fast, plain = clients
    track = lambda client: next(r for r in client.app.routes if getattr(r, "path", "") ==   # noqa: E731
                                "/v1/bodies/{body}/track")
    assert isinstance(track(fast), OnePassRoute) and type(track(plain)) is APIRoute
    # the OpenAPI document is FastAPI's own either way
    assert fast.get("/openapi.json").json()["paths"]["/v1/bodies/{body}/track"] == \
        plain.get("/openapi.json").json()["paths"]["/v1/bodies/{body}/track"]


def test_an_endpoint_that_cannot_be_served_in_one_pass_is_refused_at_start_up():
    for declare in (
        lambda app: app.get("/sync")(one_pass(lambda x: JSONResponse({}))),                          # not async
        lambda app: app.post("/body")(one_pass(_async_with_body)),                                  # a JSON body
        lambda app: app.get("/list")(one_pass(_async_with_list)),                                   # several values
    ):
        app = FastAPI()
        app.router.route_class = OnePassRoute
        with pytest.raises(TypeError):
            declare(app)


async def _async_with_body(x: dict = Body(...)):
    return JSONResponse(x)


async def _async_with_list(x: list[int] = None):
    return JSONResponse(x)


def test_a_marked_endpoint_must_return_a_response():
    app = FastAPI()
    app.router.route_class = OnePassRoute

    @app.get("/dict")
    @one_pass
    async def give(n: int = 1):
        return {"n": n}

    with pytest.raises(TypeError, match="must return a Response"):
        TestClient(app).get("/dict")


def test_a_cheap_track_runs_on_the_event_loop_and_a_dear_one_in_the_thread_pool(monkeypatch):
    """The price decides where the work runs: the 37-epoch track (predicted < 1 ms, once its body's caches are
    built) on the loop's thread, a 10^5-epoch one (predicted ~0.2 s) in a worker thread; with inline_cpu_ms=0,
    everything in the thread pool."""
    seen = []
    original = service_app.api.track_arrays

    def spy(*args, **kwargs):
        seen.append(threading.current_thread().name)
        return original(*args, **kwargs)

    monkeypatch.setattr(service_app.api, "track_arrays", spy)
    for inline_ms, queries, expected in (
            (5.0, [TRACK, TRACK], "loop"),
            (5.0, ["/v1/bodies/ceres/track?start=2040-01-01&stop=2140-01-01&step_days=0.5"], "pool"),
            (0.0, [TRACK], "pool")):
        settings = dataclasses.replace(Settings.from_env(), warm_up=False, inline_cpu_ms=inline_ms)
        with TestClient(service_app.create_app(settings)) as client:
            client.get(TRACK)                                         # the body's caches built
            loop_thread = client.portal.call(lambda: threading.current_thread().name)
            for q in queries:
                seen.clear()
                assert client.get(q).status_code == 200
                # the loop's try is refused before the work: one call on the loop at most, the work in the pool
                where = "loop" if seen == [loop_thread] else "pool" if seen[-1] != loop_thread else "?"
                assert where == expected, (inline_ms, q, seen, loop_thread)


def test_compute_outside_a_budget_runs_in_the_thread_pool():
    async def where() -> tuple[str, str]:
        return await offload.compute(5.0, lambda: threading.current_thread().name), threading.current_thread().name
    worker, loop = asyncio.run(where())
    assert worker != loop
