"""JSON request bodies with a key given twice in one object are refused, 422 naming the key (issue 42).

Python's and orjson's parsers keep the last of ``{"name": "x", "name": "y"}`` without a word, as Starlette keeps the
last of a repeated query parameter; the client meant one of them, and the service refuses to choose, as it refuses
``?order=2&order=4`` (service/problems.py). :func:`first_duplicate` finds the first such key and its path as the
errors name fields (``name``, ``orbit.e``, ``rows[3].name``); :class:`UniqueJsonKeys` checks every JSON body
(``application/json``, ``*+json``, or a body sent without a content type, which FastAPI may read as JSON) before any
route reads it. A body that is not JSON at all passes on: its route says what is wrong with it.
"""
from __future__ import annotations

import json

from .problems import problem


class _Repeated(dict):
    """An object of the document in which ``key`` was given ``count`` times."""

    key: str
    count: int


def _pairs(pairs: list) -> dict:
    out = dict(pairs)
    if len(out) == len(pairs):
        return out
    seen: dict[str, int] = {}
    for k, _ in pairs:
        seen[k] = seen.get(k, 0) + 1
    key = next(k for k, _ in pairs if seen[k] > 1)
    marked = _Repeated(out)
    marked.key, marked.count = key, seen[key]
    return marked


def _field(path: str, key: str) -> str:
    return f"{path}.{key}" if path else key


def _find(doc, path: str = "") -> tuple[str, int] | None:
    """(the path of the first key given twice, how many times), depth first in document order; None if none."""
    if isinstance(doc, _Repeated):
        return _field(path, doc.key), doc.count
    if isinstance(doc, dict):
        items = doc.items()
        return next((found for k, v in items if (found := _find(v, _field(path, k))) is not None), None)
    if isinstance(doc, list):
        return next((found for j, v in enumerate(doc) if (found := _find(v, f"{path}[{j}]")) is not None), None)
    return None


def first_duplicate(raw: bytes) -> tuple[str, int] | None:
    """The path of the first key given more than once in an object of the JSON text ``raw`` and how many times
    (``("orbit.e", 2)``); None when every key is given once, or when ``raw`` is not JSON."""
    if b'"' not in raw:
        return None
    try:
        doc = json.loads(raw, object_pairs_hook=_pairs)
    except (ValueError, RecursionError):
        return None
    return _find(doc)


def duplicate_reason(count: int) -> str:
    return (f"given {count} times in one object of the JSON body: give each key once (the service will not choose "
            "one of them for you)")


def _is_json(content_type: bytes | None) -> bool:
    if content_type is None:
        return True
    kind = content_type.split(b";", 1)[0].strip().lower()
    return kind == b"application/json" or (kind.startswith(b"application/") and kind.endswith(b"+json"))


class UniqueJsonKeys:
    """Pure ASGI: a JSON request body with a key given twice in one object is answered 422 (invalid-input, the key's
    path in ``errors``) before the route. Installed inside :class:`service.limits.BodySizeLimit`, which has read the
    body whole and bounded it."""

    def __init__(self, app):
        self.app = app

    async def __call__(self, scope, receive, send):
        if scope["type"] != "http" or scope["method"] not in ("POST", "PUT", "PATCH"):
            return await self.app(scope, receive, send)
        content_type = next((v for k, v in scope.get("headers") or () if k == b"content-type"), None)
        if not _is_json(content_type):
            return await self.app(scope, receive, send)
        messages, chunks = [], []
        while True:
            message = await receive()
            messages.append(message)
            if message["type"] != "http.request":
                break
            chunks.append(message.get("body", b""))
            if not message.get("more_body", False):
                break
        found = first_duplicate(b"".join(chunks))
        if found is not None:
            field, count = found
            reason = duplicate_reason(count)
            refusal = problem(422, "invalid-input", "Invalid input", f"{field}: {reason}",
                              errors=[{"field": field, "reason": reason}])
            return await refusal(scope, receive, send)
        pending = list(messages)

        async def replayed():
            return pending.pop(0) if pending else await receive()

        await self.app(scope, replayed, send)
