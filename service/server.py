"""The HTTP server's own limits: a request's head (its line and headers) is refused beyond a size, 431.

uvicorn's fast parser (httptools, which ``http="auto"`` picks) holds a request's head in memory however long it is:
a 1 MB header was read and answered 200 (issue 42). :class:`BoundedHttpTools` counts the bytes received while a
head is incomplete and, past ``max_header_bytes`` (``EPHEM_MAX_HEADER_BYTES``, 32 KiB by default, as nginx's four 8 KiB
buffers), answers ``431 Request Header Fields Too Large`` as problem+json with ``Connection: close``, then reads and
drops what the client is still sending for a moment before closing, so that the client reads the answer rather
than a reset. A body does not count: the count stops when the head is complete. The h11 parser, where it is used
instead, is given the same size as ``h11_max_incomplete_event_size`` (its refusal is uvicorn's 400).

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

        def __init__(self, *args, **kwargs):
            super().__init__(*args, **kwargs)
            # bytes received while a head is incomplete (bounds what the parser holds), and the head's parsed size
            self._in_head, self._head_bytes, self._parsed, self._refused = True, 0, 0, False

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
            super().on_headers_complete()

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


def bounded_protocol(max_header_bytes: int):
    """The httptools protocol class refusing heads over ``max_header_bytes`` (None without httptools)."""
    if BoundedHttpTools is None:    # pragma: no cover
        return None
    return type("BoundedHttpTools", (BoundedHttpTools,), {"max_header_bytes": int(max_header_bytes)})


def server_config(settings: Settings) -> dict:
    """uvicorn ``Config`` keywords for the limits of ``settings``: the parser and its head size."""
    protocol = bounded_protocol(settings.max_header_bytes)
    return {"http": protocol or "h11", "h11_max_incomplete_event_size": settings.max_header_bytes}


class Worker(UvicornWorker):
    """gunicorn's uvicorn worker with the head size limit of the environment's settings."""

    CONFIG_KWARGS = {"loop": "auto", **server_config(Settings.from_env())}
