"""ASGI middleware: an unexpected exception becomes a problem+json 500 on a connection that stays open.

Starlette answers an exception no handler takes (a bug) in its outermost layer, ``ServerErrorMiddleware``, with the
app's ``Exception`` handler, and then raises it again "so that the server can log it". uvicorn, seeing an exception
after the response started, closes the socket: the 500 went out with no ``Connection: close``, and the client's next
request on that keep-alive connection met a reset (ECONNRESET: issue 42, 20 of 20 with httpx). This middleware,
installed last (so outside every other), catches the exception first: it logs it with its traceback on uvicorn's
error logger, as uvicorn would, and answers the problem the app's handler gives (``no-store``), then returns, so the
server sees a request that ended and keeps the connection for the next one.

Where the answer had already started (a CSV stream failing halfway), no status can be sent any more: the exception goes
on to the server, which closes the connection, the only honest end of a truncated body. An exception after the answer
was complete is logged and costs the client nothing.
"""
from __future__ import annotations

import logging

from .problems import problem

#: uvicorn's own logger for errors (gunicorn's uvicorn workers route it to the error log)
LOG = logging.getLogger("uvicorn.error")


class UnexpectedErrors:
    """Pure ASGI (no ``BaseHTTPMiddleware``): the 500 problem for an exception no handler took, the connection kept."""

    def __init__(self, app):
        self.app = app

    async def __call__(self, scope, receive, send):
        if scope["type"] != "http":
            return await self.app(scope, receive, send)
        state = {"started": False, "complete": False}

        async def tracked(message):
            if message["type"] == "http.response.start":
                state["started"] = True
            elif message["type"] == "http.response.body" and not message.get("more_body", False):
                state["complete"] = True
            await send(message)

        try:
            await self.app(scope, receive, tracked)
        except Exception as exc:
            LOG.error("unexpected error answering %s %s", scope.get("method"), scope.get("path"), exc_info=exc)
            if state["complete"]:
                return
            if state["started"]:
                raise                       # half an answer sent: the server closes the connection
            response = problem(500, "internal", "Internal error",
                               f"{type(exc).__name__}: the server failed on this request",
                               headers={"Cache-Control": "no-store"})
            await response(scope, receive, send)
