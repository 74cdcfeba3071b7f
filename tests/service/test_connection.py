"""The connection around an answer (issue 42): a real uvicorn server on loopback, an httpx client with keep-alive.

* After a 500 (a bug: here a route made to raise), the problem is answered and the client's next request on the same
  keep-alive connection is served; the server used to close the socket without ``Connection: close``, and the next
  request met ECONNRESET (service/unexpected.py).
* A request head over EPHEM_MAX_HEADER_BYTES (1 MB of one header) is refused with 431 problem+json and
  ``Connection: close``, by the server configuration ``make serve`` runs (service/server.py through
  service/gunicorn_conf.py); one under it is served.
"""
from __future__ import annotations

import contextlib
import json
import os
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import httpx
import pytest
import uvicorn

from ephem import api
from service.app import create_app
from service.problems import PROBLEM, TYPE_BASE
from service.server import server_config
from service.settings import Settings

ROOT = Path(__file__).resolve().parents[2]
SETTINGS = Settings(warm_up=False)


@contextlib.contextmanager
def serving(app, **config):
    """``app`` under uvicorn in a thread, on a loopback port of its own; yields the base URL."""
    sock = socket.socket()
    sock.bind(("127.0.0.1", 0))
    server = uvicorn.Server(uvicorn.Config(app, log_level="critical", lifespan="on", **config))
    thread = threading.Thread(target=server.run, kwargs={"sockets": [sock]}, daemon=True)
    thread.start()
    try:
        deadline = time.monotonic() + 30
        while not server.started:
            assert time.monotonic() < deadline and thread.is_alive(), "uvicorn did not start"
            time.sleep(0.02)
        yield f"http://127.0.0.1:{sock.getsockname()[1]}"
    finally:
        server.should_exit = True
        thread.join(10)
        sock.close()


def _local_address(response: httpx.Response):
    """The client side's (address, port) of the connection that carried ``response``."""
    return response.extensions["network_stream"].get_extra_info("client_addr")


#: the production protocol (httptools with the head limit, as service.server.Worker runs it) and uvicorn's h11
PROTOCOLS = {"httptools": server_config(SETTINGS), "h11": {"http": "h11"}}


@pytest.mark.parametrize("protocol", sorted(PROTOCOLS))
def test_an_error_answer_keeps_the_keep_alive_connection(monkeypatch, protocol):
    def failing(*args, **kwargs):
        raise RuntimeError("a bug, made for this test")

    monkeypatch.setattr(api, "precession", failing)
    with serving(create_app(SETTINGS), **PROTOCOLS[protocol]) as base, httpx.Client(base_url=base) as client:
        assert client.get("/healthz").status_code == 200
        first = client.get("/v1/bodies/vesta/precession")
        assert first.status_code == 500 and first.headers["content-type"] == PROBLEM
        problem = first.json()
        assert problem["type"] == TYPE_BASE + "internal" and "RuntimeError" in problem["detail"]
        assert "a bug, made" not in first.text                 # the exception's text stays in the log
        assert first.headers.get("connection", "").lower() != "close"
        assert first.headers.get("cache-control") == "no-store"
        second = client.get("/healthz")         # ECONNRESET here before the fix
        assert second.status_code == 200 and second.json()["status"] == "ok"
        assert _local_address(second) == _local_address(first)     # the same connection
        third = client.get("/v1/bodies/vesta/precession")          # and again: every failure is answered
        assert third.status_code == 500 and _local_address(third) == _local_address(first)


def test_a_head_over_the_limit_is_refused_431_and_one_under_it_served():
    settings = Settings(warm_up=False, max_header_bytes=32_768)
    with serving(create_app(settings), **server_config(settings)) as base:
        with httpx.Client(base_url=base) as client:
            under = client.get("/healthz", headers={"X-Padding": "a" * 30_000})
            assert under.status_code == 200
            again = client.get("/healthz")
            assert again.status_code == 200 and _local_address(again) == _local_address(under)
        for size in (40_000, 1_000_000):        # one read holds the first whole; the second comes in many
            with httpx.Client(base_url=base) as client:
                refused = client.get("/healthz", headers={"X-Padding": "a" * size})
            assert refused.status_code == 431, size
            assert refused.headers["content-type"] == PROBLEM and refused.headers["connection"] == "close"
            assert refused.json()["status"] == 431 and "EPHEM_MAX_HEADER_BYTES" in refused.json()["detail"]
        with httpx.Client(base_url=base) as client:    # the server goes on serving
            assert client.get("/healthz").status_code == 200


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def test_make_serve_s_server_refuses_a_1_mb_header():
    """gunicorn with service/gunicorn_conf.py, as ``make serve`` runs it: its worker class carries the limit."""
    port = _free_port()
    env = dict(os.environ, EPHEM_WARM_UP="0")
    gunicorn = Path(sys.executable).with_name("gunicorn")
    proc = subprocess.Popen([str(gunicorn), "--config", "service/gunicorn_conf.py", "--bind", f"127.0.0.1:{port}",
                             "--workers", "1", "service.app:app"], cwd=ROOT, env=env,
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        base = f"http://127.0.0.1:{port}"
        deadline = time.monotonic() + 60
        while True:
            try:
                if httpx.get(f"{base}/healthz", timeout=2).status_code == 200:
                    break
            except httpx.TransportError:
                pass
            assert time.monotonic() < deadline and proc.poll() is None, "the service did not start"
            time.sleep(0.2)
        refused = httpx.get(f"{base}/healthz", headers={"X-Padding": "a" * 1_000_000}, timeout=10)
        assert refused.status_code == 431 and json.loads(refused.content)["type"] == TYPE_BASE + "http"
        assert httpx.get(f"{base}/healthz", timeout=5).status_code == 200
    finally:
        proc.terminate()
        proc.wait(timeout=30)
