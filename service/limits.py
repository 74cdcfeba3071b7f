"""ASGI middleware: refuse request bodies above a size with 413 problem+json."""
from __future__ import annotations

import json

from .problems import PROBLEM, TYPE_BASE


class BodySizeLimit:
    def __init__(self, app, max_bytes: int):
        self.app = app
        self.max_bytes = max_bytes

    async def __call__(self, scope, receive, send):
        if scope["type"] != "http":
            return await self.app(scope, receive, send)
        headers = dict(scope.get("headers") or [])
        declared = headers.get(b"content-length")
        if declared is not None and declared.isdigit() and int(declared) > self.max_bytes:
            return await self._reject(send)
        # Read the body here, before the app: a body over the limit found while the route reads it
        # (a chunked body declares no length) would surface inside FastAPI's body parsing, which turns
        # any error there into a 400. The bodies allowed are small (64 KiB by default), so holding
        # one in memory costs nothing.
        chunks, seen = [], 0
        while True:
            message = await receive()
            if message["type"] != "http.request":       # the client went away: let the app see it
                return await self.app(scope, _replay([message], receive), send)
            body = message.get("body", b"")
            seen += len(body)
            if seen > self.max_bytes:
                return await self._reject(send)
            chunks.append(body)
            if not message.get("more_body", False):
                break
        whole = {"type": "http.request", "body": b"".join(chunks), "more_body": False}
        await self.app(scope, _replay([whole], receive), send)

    async def _reject(self, send):
        body = json.dumps({"type": TYPE_BASE + "too-large", "title": "Request body too large", "status": 413,
                           "detail": f"the request body exceeds {self.max_bytes} bytes "
                                     "(EPHEM_MAX_BODY_BYTES)"}).encode()
        await send({"type": "http.response.start", "status": 413,
                    "headers": [(b"content-type", PROBLEM.encode()), (b"content-length", str(len(body)).encode())]})
        await send({"type": "http.response.body", "body": body})


def _replay(messages: list, receive):
    """A ``receive`` that gives ``messages`` first, then defers to the server's (for the disconnect)."""
    pending = list(messages)

    async def replayed():
        if pending:
            return pending.pop(0)
        return await receive()

    return replayed
