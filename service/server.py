"""The HTTP server's own limits: a request's head (its line and headers) is refused beyond a size, 431.

uvicorn's fast parser (httptools, which ``http="auto"`` picks) holds a request's head in memory however long it is:
a 1 MB header was read and answered 200 (issue 42). :class:`BoundedHttpTools` counts the bytes received while a
head is incomplete and, past ``max_header_bytes`` (``EPHEM_MAX_HEADER_BYTES``, 32 KiB by default, as nginx's four 8 KiB
buffers), answers ``431 Request Header Fields Too Large`` as problem+json with ``Connection: close``, then reads and
drops what the client is still sending for a moment before closing, so that the client reads the answer rather
than a reset. A body does not count: the count stops when the head is complete. The h11 parser, where it is used
instead, is given the same size as ``h11_max_incomplete_event_size`` (its refusal is uvicorn's 400).

It also ends keep-alive connections now and then, so that traffic spreads again over the workers: a connection stays
with the worker that accepted it, and after a worker was killed its clients all reconnected to the survivor and
stayed there while the replacement, started 2-4 s later, served nothing (half the throughput for the rest of a 60-s
run; issue 42, benchmarks/RESULTS_kill_rebalance.md). The answer to a connection's ``keepalive_max_requests``-th
request (``EPHEM_KEEPALIVE_MAX_REQUESTS``), or to its first request after ``keepalive_max_s`` seconds
(``EPHEM_KEEPALIVE_MAX_S``), carries ``Connection: close`` and the connection is closed after it: the client
reconnects, and the kernel hands the new connection to whichever worker accepts first, an idle one sooner. One
count and one clock read per request, in the protocol, which knows its connection (the ASGI app does not).

:class:`Worker` is gunicorn's uvicorn worker with these (``service/gunicorn_conf.py``: ``make serve``, the image);
:func:`server_config` the same keywords for a uvicorn ``Config`` of one's own (the tests' servers).
"""
from __future__ import annotations

import json

from uvicorn_worker import UvicornWorker

from .problems import PROBLEM, TYPE_BASE
from .settings import Settings

try:
    from uvicorn.protocols.http.httptools_impl import HttpToolsProtocol
except ImportError:         # pragma: no cover - httptools is in the lock; without it uvicorn parses with h11
    HttpToolsProtocol = None

#: how long a refused connection keeps reading (and dropping) what its client still sends before it closes, s
LINGER_S = 2.0


def _refusal(limit: int) -> bytes:
    body = json.dumps({"type": TYPE_BASE + "http", "title": "Request header fields too large", "status": 431,
                       "detail": f"the request's line and headers exceed {limit} bytes (EPHEM_MAX_HEADER_BYTES)"},
                      separators=(",", ":")).encode()
    return (b"HTTP/1.1 431 Request Header Fields Too Large\r\ncontent-type: " + PROBLEM.encode()
            + b"\r\ncontent-length: " + str(len(body)).encode() + b"\r\nconnection: close\r\n\r\n" + body)


if HttpToolsProtocol is not None:
    class BoundedHttpTools(HttpToolsProtocol):
        """uvicorn's httptools protocol, refusing a head over :attr:`max_header_bytes` with 431."""

        #: the most bytes of a request's head (its line and headers), counted as received
        max_header_bytes = Settings.max_header_bytes
        #: the requests one connection carries, and its age in seconds after which its next answer closes it
        keepalive_max_requests = Settings.keepalive_max_requests
        keepalive_max_s = Settings.keepalive_max_s

        def __init__(self, *args, **kwargs):
            super().__init__(*args, **kwargs)
            # bytes received while a head is incomplete (bounds what the parser holds), and the head's parsed size
            self._in_head, self._head_bytes, self._parsed, self._refused = True, 0, 0, False
            self._requests, self._opened = 0, self.loop.time()

        def data_received(self, data: bytes) -> None:
            if self._refused:
                return              # the refusal is sent: what still comes is dropped until the close
            if self._in_head:
                self._head_bytes += len(data)
            super().data_received(data)
            if self._in_head and self._head_bytes > self.max_header_bytes and not self._refused \
                    and not self.transport.is_closing():
                self._refuse()

        def on_url(self, url: bytes) -> None:
            self._parsed += len(url)
            super().on_url(url)

        def on_header(self, name: bytes, value: bytes) -> None:
            self._parsed += len(name) + len(value) + 4          # "name: value\r\n"
            super().on_header(name, value)

        def _refuse(self) -> None:
            self._refused = True
            self.transport.write(_refusal(self.max_header_bytes))
            if self.transport.can_write_eof():
                self.transport.write_eof()
            self.loop.call_later(LINGER_S, self.transport.close)

        def on_headers_complete(self) -> None:
            self._in_head = False
            if self._parsed > self.max_header_bytes:     # a whole head over the limit in one read
                self._refuse()
                return                                   # no request cycle: the app never sees it
            before = self.cycle
            super().on_headers_complete()
            self._requests += 1
            if self.cycle is not before and (self._requests >= self.keepalive_max_requests
                                             or self.loop.time() - self._opened >= self.keepalive_max_s):
                self.cycle.keep_alive = False       # uvicorn writes connection: close and closes after the answer

        def on_body(self, body: bytes) -> None:
            if not self._refused:
                super().on_body(body)

        def on_message_complete(self) -> None:
            if self._refused:
                return
            super().on_message_complete()
            self._in_head, self._head_bytes, self._parsed = True, 0, 0
else:                       # pragma: no cover
    BoundedHttpTools = None


def bounded_protocol(max_header_bytes: int, keepalive_max_requests: int = Settings.keepalive_max_requests,
                     keepalive_max_s: float = Settings.keepalive_max_s):
    """The httptools protocol class refusing heads over ``max_header_bytes`` and closing a connection after its
    ``keepalive_max_requests``-th answer or its first after ``keepalive_max_s`` seconds (None without httptools)."""
    if BoundedHttpTools is None:    # pragma: no cover
        return None
    return type("BoundedHttpTools", (BoundedHttpTools,), {"max_header_bytes": int(max_header_bytes),
                                                          "keepalive_max_requests": int(keepalive_max_requests),
                                                          "keepalive_max_s": float(keepalive_max_s)})


def server_config(settings: Settings) -> dict:
    """uvicorn ``Config`` keywords for the limits of ``settings``: the parser, its head size and its connections'
    keep-alive bounds (httptools only: h11 keeps a connection as long as its client does)."""
    protocol = bounded_protocol(settings.max_header_bytes, settings.keepalive_max_requests, settings.keepalive_max_s)
    return {"http": protocol or "h11", "h11_max_incomplete_event_size": settings.max_header_bytes}


class Worker(UvicornWorker):
    """gunicorn's uvicorn worker with the head size limit and the keep-alive bounds of the environment's settings."""

    CONFIG_KWARGS = {"loop": "auto", **server_config(Settings.from_env())}
