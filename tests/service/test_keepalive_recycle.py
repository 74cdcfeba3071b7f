"""Keep-alive connections end now and then, honestly (issue 42, item 5): a real uvicorn server on loopback with the
protocol ``make serve`` runs (service/server.py through ``server_config``), an httpx client keeping its connection.

After a worker is killed, its clients reconnect to the survivor; unless connections end now and then they stay there
while the replacement serves nothing. The answer to a connection's ``keepalive_max_requests``-th request, or to its
first after ``keepalive_max_s`` seconds, says ``Connection: close`` and the server closes the connection after it;
the client's next request opens a new connection and is served. The rebalancing itself, under load with a worker
killed, is measured by benchmarks/bench_kill_rebalance.py (benchmarks/RESULTS_kill_rebalance.md).
"""
from __future__ import annotations

import time

import httpx
import pytest

from service.app import create_app
from service.server import Worker, server_config
from service.settings import Settings
from tests.service.test_connection import serving as serving_app


def serving(settings: Settings):
    """The app of ``settings`` under uvicorn with make serve's protocol, in a thread on a loopback port of its own
    (tests/service/test_connection.py's server); yields the base URL."""
    return serving_app(create_app(settings), **server_config(settings))


def _note_connection(response: httpx.Response) -> None:
    """A response hook: the client side's (address, port) of the connection carrying ``response``, noted while it
    is open (httpx closes it once a ``Connection: close`` answer is read)."""
    response.client_addr = response.extensions["network_stream"].get_extra_info("client_addr")


def _client(base: str) -> httpx.Client:
    return httpx.Client(base_url=base, event_hooks={"response": [_note_connection]})


def _connection(response: httpx.Response):
    return response.client_addr


def _closes(response: httpx.Response) -> bool:
    return response.headers.get("connection", "").lower() == "close"


def test_the_last_request_a_connection_carries_is_answered_with_connection_close():
    settings = Settings(warm_up=False, keepalive_max_requests=3, keepalive_max_s=3600.0)
    with serving(settings) as base, _client(base) as client:
        first = [client.get("/healthz") for _ in range(3)]
        assert [r.status_code for r in first] == [200, 200, 200]
        assert [_closes(r) for r in first] == [False, False, True]
        assert len({_connection(r) for r in first}) == 1            # one connection carried the three
        after = [client.get("/v1/bodies/vesta/precession") for _ in range(3)]
        assert [r.status_code for r in after] == [200, 200, 200]     # the client reconnected: nothing was lost
        assert _connection(after[0]) != _connection(first[0])
        assert [_closes(r) for r in after] == [False, False, True]   # the new connection counts from one


def test_a_connection_past_its_age_is_closed_with_its_next_answer():
    settings = Settings(warm_up=False, keepalive_max_requests=1000, keepalive_max_s=0.3)
    with serving(settings) as base, _client(base) as client:
        young = client.get("/healthz")
        assert young.status_code == 200 and not _closes(young)
        time.sleep(0.5)                                           # the connection is now older than 0.3 s
        old = client.get("/healthz")
        assert old.status_code == 200 and _closes(old)
        assert _connection(old) == _connection(young)
        fresh = client.get("/healthz")
        assert fresh.status_code == 200 and not _closes(fresh)
        assert _connection(fresh) != _connection(old)


def test_an_error_answer_counts_and_closes_as_any_other():
    settings = Settings(warm_up=False, keepalive_max_requests=2, keepalive_max_s=3600.0)
    with serving(settings) as base, _client(base) as client:
        ok = client.get("/healthz")
        missing = client.get("/v1/bodies/no-such-body/precession")
        assert ok.status_code == 200 and not _closes(ok)
        assert missing.status_code == 404 and _closes(missing)
        assert client.get("/healthz").status_code == 200


@pytest.mark.parametrize("name, env, value", [("keepalive_max_requests", "EPHEM_KEEPALIVE_MAX_REQUESTS", "7"),
                                              ("keepalive_max_s", "EPHEM_KEEPALIVE_MAX_S", "1.5")])
def test_the_bounds_come_from_the_environment_to_the_protocol(monkeypatch, name, env, value):
    monkeypatch.setenv(env, value)
    settings = Settings.from_env()
    assert getattr(settings, name) == type(getattr(Settings, name))(value)
    assert getattr(server_config(settings)["http"], name) == getattr(settings, name)


def test_make_serve_s_worker_carries_the_default_bounds():
    protocol = Worker.CONFIG_KWARGS["http"]
    assert protocol.keepalive_max_requests == Settings.keepalive_max_requests
    assert protocol.keepalive_max_s == Settings.keepalive_max_s
