"""Answers that caches can keep: an ``ETag``, ``Cache-Control`` and ``304 Not Modified`` for every GET answer.

A GET answer of the service (the ``/v1`` routes, the figures, the web pages, the docs) is a pure function of
the request's path and query, the package version and its code, the data the library reads and the service's
settings;
the web pages also print the server's address (their curl lines: the server's own socket, or the configured
EPHEM_PUBLIC_BASE_URL; never the client's Host header). So the
answer's ETag is a hash of those, known from the request alone: a request whose ``If-None-Match`` holds it
gets its ``304`` here, before the route, the budget or any computation, and a reverse proxy or a CDN in front
of several replicas (which compute the same tags: nothing of the process enters them) can keep one copy of
each answer and revalidate it cheaply (docs/api.md, "Caching: ETag, Cache-Control, 304").

- 200 answers to GET (and to HEAD, where a route has it): ``ETag``, ``Cache-Control: public, max-age=N``
  (``EPHEM_CACHE_MAX_AGE_S``; 0 gives ``no-cache``), and ``Vary: Accept-Encoding`` when an inner middleware
  compressed the answer (whose ETag then names the coding: the compressed bytes are another representation).
  The ETag is strong (``"…"``) on the answers that are the same bytes each time (CSV and the other tables,
  PNG, SVG) and weak (``W/"…"``) on JSON and HTML, which carry the computation's measured cost (``cost_ms``):
  two computations of one request differ in those digits and nothing else, equivalent answers (RFC 9110
  8.8.1). If-None-Match compares weakly, so both give the 304.
- Everything else (errors, 503 busy, POST answers, ``/healthz``): ``Cache-Control: no-store`` and no ETag.
- ``/static``: untouched (Starlette's StaticFiles sends its own ETag and Last-Modified, and answers 304 itself).

The media type needs no place of its own in the key: every route chooses it from its path (``track.png``,
``track.svg``) or its query (``format=csv``), never from the ``Accept`` header, so the key holds it already.
The body's name in the path is kept as written (``/v1/bodies/Vesta`` and ``/v1/bodies/vesta`` are two keys,
as they are two URLs to a cache). The query is canonical: its parameters decoded as Starlette decodes them,
sorted, then re-encoded, so ``?a=1&b=2`` and ``?b=2&a=1`` share an ETag.

The data: every file under :func:`ephem.api.data_dir`, hashed once when the middleware is built (the
service's start-up: ~3 MB, a few ms), and the user's imported datasets (:func:`ephem.api.user_catalogue_dir`,
``ephem catalogue import``), which the library re-reads when their files change: their names, sizes and
modification times are looked at on each tagged answer (one directory listing) and their bytes hashed again
when those change. DE421 comes from a pinned package and is the same kernel in every version.

Pure ASGI (no ``BaseHTTPMiddleware``): an answer pays one ``blake2b`` of a short string, one sort of its query
and one directory listing for the user's datasets.
"""
from __future__ import annotations

import dataclasses
import hashlib
import os
import re
from pathlib import Path
from urllib.parse import parse_qsl, quote

from fastapi import FastAPI

import ephem
from ephem import api

from .settings import Settings

#: paths whose answers are never kept (a load balancer's liveness probe must reach a worker)
NO_STORE_PATHS = frozenset({"/healthz"})
#: path prefixes left alone: StaticFiles sends its own validators
UNTOUCHED_PREFIXES = ("/static/",)
#: the API's answers do not print the server's address; every other page may (service/pages.py)
ADDRESS_FREE_PREFIX = "/v1/"
#: settings that change no answer: where the workers' locks live, and how long caches keep the answers
_SETTINGS_OUTSIDE_KEY = frozenset({"lock_dir", "cache_max_age_s"})
#: the headers a 304 keeps (RFC 9110 15.4.5): the validators and the caching fields, not the body's
_KEPT_BY_304 = frozenset({b"etag", b"cache-control", b"vary", b"date", b"expires", b"content-location"})
#: the answer's headers the middleware reads, and those it takes from an answer that is not kept
_INSPECTED = frozenset({b"etag", b"cache-control", b"content-encoding", b"content-type", b"vary"})
_VALIDATORS = frozenset({b"etag", b"cache-control"})
#: one entity-tag of an If-None-Match list: W/ (weak) then the quoted opaque tag (which may hold commas)
_ENTITY_TAG = re.compile(r'(W/)?"([^"]*)"')
#: media types whose answers carry a measured cost (``cost_ms``, the pages' "cost 7.1 ms"): two computations of
#: one request differ in those digits, so their ETag is weak (RFC 9110 8.8.1: equivalent, not byte-identical)
_MEASURED = (b"application/json", b"text/html")
_DIGEST_BYTES = 16
#: the characters a canonical query writes as they are: printable ASCII but the query's own syntax
_RAW = "".join(sorted(set(map(chr, range(0x21, 0x7F))) - set("%&+#")))
_RAW_IN_NAME = _RAW.replace("=", "")


#: the files of the code whose bytes enter every tag: a deployment of changed code under the same version number
#: must not have caches serve the old answers (compiled bytecode is left out: it differs between machines)
CODE_SUFFIXES = (".py", ".html", ".css", ".js", ".toml", ".md")


def code_digest(roots=None) -> bytes:
    """A digest of the library's and the service's code as shipped (:data:`CODE_SUFFIXES` under ``roots``, by
    default the ``ephem`` and ``service`` packages), the same on every replica of one build."""
    h = hashlib.blake2b(digest_size=_DIGEST_BYTES)
    if roots is None:
        roots = (Path(ephem.__file__).resolve().parent, Path(__file__).resolve().parent)
    for root in map(Path, roots):
        for path in sorted(p for p in root.rglob("*") if p.suffix in CODE_SUFFIXES and "__pycache__" not in p.parts
                           and p.is_file()):
            data = path.read_bytes()
            name = f"{root.name}/{path.relative_to(root).as_posix()}".encode()
            h.update(b"%d:%s%d:" % (len(name), name, len(data)))
            h.update(data)
    return h.digest()


def tree_digest(root: Path) -> bytes:
    """A digest of every regular file under ``root``: its path relative to ``root``, its size and its bytes
    (sorted by path, so the order the file system lists them in changes nothing). b"" when ``root`` is None
    or no directory."""
    h = hashlib.blake2b(digest_size=_DIGEST_BYTES)
    if root is None or not Path(root).is_dir():
        return b""
    for path in sorted(p for p in Path(root).rglob("*") if p.is_file()):
        data = path.read_bytes()
        name = path.relative_to(root).as_posix().encode()
        h.update(b"%d:%s%d:" % (len(name), name, len(data)))
        h.update(data)
    return h.digest()


class UserDatasets:
    """The digest of the user's imported datasets (``*.toml`` in :func:`ephem.api.user_catalogue_dir`), kept
    while their names, sizes and modification times stay the same: the library keys its parsed catalogues by
    the same (``ephem.bodies.catalogue.load_catalogue``), so the digest moves whenever an answer can."""

    def __init__(self, where: Path | None):
        #: the directory, found once (from the environment, which a running service keeps)
        self.where = where
        self._signature: tuple | None = None
        self._digest = b""

    def digest(self) -> bytes:
        where = self.where
        if where is None or not os.access(where, os.F_OK):      # the usual case, and no exception raised
            return b""
        try:
            with os.scandir(where) as it:
                entries = sorted((e.name, e.stat()) for e in it if e.name.endswith(".toml") and e.is_file())
        except OSError:                    # no such directory: the usual case
            return b""
        if not entries:
            return b""
        signature = (str(where),) + tuple((n, st.st_size, st.st_mtime_ns, st.st_ino) for n, st in entries)
        if signature != self._signature:
            h = hashlib.blake2b(digest_size=_DIGEST_BYTES)
            for name, _ in entries:
                try:
                    data = (Path(where) / name).read_bytes()
                except OSError:            # replaced between the listing and the read: hash what is there
                    data = b""
                h.update(b"%d:%s%d:" % (len(name.encode()), name.encode(), len(data)))
                h.update(data)
            self._signature, self._digest = signature, h.digest()
        return self._digest


def settings_fingerprint(settings: Settings) -> str:
    """The settings that can change an answer (the pages print the batch limit, the OpenAPI document the
    budget), as text: every field but those in ``_SETTINGS_OUTSIDE_KEY``."""
    return repr(sorted((f.name, getattr(settings, f.name)) for f in dataclasses.fields(settings)
                       if f.name not in _SETTINGS_OUTSIDE_KEY))


def canonical_query(query_string: bytes) -> bytes:
    """The query as a key: its ``name=value`` items sorted, each decoded as Starlette decodes it (``%41`` and
    ``A``, ``+`` and ``%20`` are the same value to a route) and written back with only ``%``, ``&``, ``+``
    (and ``=`` in a name) and what is not printable ASCII encoded. Two queries with the same items give the same
    key, and the key parses back to the items (so two different questions never share one). A query
    without ``%`` or ``+`` is its own decoding: its items are only sorted (the common case, ~1 us). A repeated
    parameter keeps all its values (the service refuses it: a 422 carries no ETag)."""
    if not query_string:
        return b""
    if b"%" not in query_string and b"+" not in query_string:
        return b"&".join(sorted(item for item in query_string.split(b"&") if item))
    pairs = parse_qsl(query_string.decode("latin-1"), keep_blank_values=True)
    return "&".join(sorted(f"{quote(k, _RAW_IN_NAME)}={quote(v, _RAW)}" for k, v in pairs)).encode()


def cache_control(max_age_s: int) -> bytes:
    """The Cache-Control of a kept answer: ``public, max-age=N``, or ``no-cache`` (revalidate every time) at 0."""
    return b"no-cache" if max_age_s <= 0 else b"public, max-age=%d" % max_age_s


def if_none_match(headers) -> tuple[bool, dict[str, str]] | None:
    """The request's If-None-Match (all its fields together): (``*`` given, {opaque tag: the tag as written}),
    or None without the field. The opaque tags are compared without their W/: the weak comparison RFC 9110
    13.1.2 asks for."""
    values = [v.decode("latin-1") for k, v in headers if k == b"if-none-match"]
    if not values:
        return None
    joined = ",".join(values)
    star = any(part.strip() == "*" for part in joined.split(","))
    return star, {m.group(2): m.group(0) for m in _ENTITY_TAG.finditer(joined)}


def _accepted_codings(headers) -> set[str]:
    codings = set()
    for k, v in headers:
        if k == b"accept-encoding":
            codings |= {c.split(";")[0].strip().lower() for c in v.decode("latin-1").split(",") if c.strip()}
    return codings


class ConditionalGet:
    """ASGI middleware: the ETag and Cache-Control of every GET answer, ``no-store`` on everything else, and
    ``304 Not Modified`` for a GET whose If-None-Match holds the answer's ETag, sent before the application
    runs (docs/api.md, "Caching")."""

    def __init__(self, app, max_age_s: int, fingerprint: str, version: str | None = None,
                 data_root: Path | None = None):
        self.app = app
        self.cache_control = cache_control(max_age_s)
        version = ephem.__version__ if version is None else version
        data = tree_digest(api.data_dir() if data_root is None else data_root)
        # what every key shares, hashed once: later keys copy this state and add the request's part
        self._base = hashlib.blake2b(digest_size=_DIGEST_BYTES)
        for part in (version.encode(), code_digest(), data, fingerprint.encode()):
            self._base.update(b"%d:%s" % (len(part), part))
        self.user_datasets = UserDatasets(api.user_catalogue_dir())

    def etag(self, scope) -> str:
        """The opaque tag (without quotes) of the answer to the request ``scope``, from the request alone."""
        h = self._base.copy()
        path = scope["path"].encode("utf-8", "surrogateescape")
        query = canonical_query(scope.get("query_string", b""))
        where = scope.get("root_path", "").encode("utf-8", "surrogateescape")
        if not scope["path"].startswith(ADDRESS_FREE_PREFIX):       # the pages print their curl lines' address:
            server = scope.get("server")       # the server's own (service/pages.py), never the client's Host header
            host = ("%s:%s" % tuple(server)).encode() if server else b""
            where = scope.get("scheme", "http").encode() + b"://" + host + where
        users = self.user_datasets.digest()
        h.update(b"%d:%s%d:%s%d:%s%d:%s" % (len(path), path, len(query), query, len(where), where, len(users), users))
        return h.hexdigest()

    async def __call__(self, scope, receive, send):
        if scope["type"] != "http":
            return await self.app(scope, receive, send)
        path = scope["path"]
        if path.startswith(UNTOUCHED_PREFIXES):
            return await self.app(scope, receive, send)
        method = scope["method"]
        keep = method in ("GET", "HEAD") and path not in NO_STORE_PATHS
        condition = if_none_match(scope.get("headers") or []) if keep else None
        tag = None
        if condition is not None and method == "GET" and not condition[0]:
            # the answer's tag is known now: a match is answered before anything runs (HEAD, which only
            # some routes have, and '*', which needs to know that an answer exists, wait for the route)
            tag = self.etag(scope)
            held = self._held(tag, condition[1], scope)
            if held is not None:         # the tag as the client holds it (W/ or not: as this service sent it)
                headers = [(b"etag", condition[1][held].encode("latin-1")), (b"cache-control", self.cache_control)]
                if held != tag:
                    headers.append((b"vary", b"Accept-Encoding"))
                await send({"type": "http.response.start", "status": 304, "headers": headers})
                await send({"type": "http.response.body", "body": b"", "more_body": False})
                return

        not_modified = False

        async def send_with_validators(message):
            nonlocal not_modified, tag
            kind = message["type"]
            if kind == "http.response.start":
                status = message["status"]
                given = message.get("headers", ())
                if keep and status == 200:
                    found = {k.lower(): v for k, v in given if k.lower() in _INSPECTED}
                    headers = list(given)
                    if b"etag" not in found:
                        tag = tag or self.etag(scope)
                        coding = found.get(b"content-encoding")
                        answer_tag = tag if coding is None else f"{tag}-{coding.decode('latin-1').strip()}"
                        weak = found.get(b"content-type", b"").split(b";")[0].strip() in _MEASURED
                        headers.append((b"etag", (b'W/"%s"' if weak else b'"%s"') % answer_tag.encode()))
                        vary = found.get(b"vary", b"")
                        if coding is not None and b"accept-encoding" not in vary.lower():
                            headers = _drop(headers, b"vary")
                            headers.append((b"vary", vary + b", Accept-Encoding" if vary else b"Accept-Encoding"))
                        if condition is not None and (condition[0] or answer_tag in condition[1]):
                            not_modified = True
                            headers = [(k, v) for k, v in headers if k.lower() in _KEPT_BY_304]
                    if b"cache-control" not in found:
                        headers.append((b"cache-control", self.cache_control))
                    message = {**message, "status": 304 if not_modified else status, "headers": headers}
                else:
                    headers = [(k, v) for k, v in given if k.lower() not in _VALIDATORS]
                    headers.append((b"cache-control", b"no-store"))
                    message = {**message, "headers": headers}
            elif not_modified:         # the body of an answer the client holds: not sent
                if kind == "http.response.body" and message.get("more_body", False):
                    return
                message = {"type": "http.response.body", "body": b"", "more_body": False}
            await send(message)

        await self.app(scope, receive, send_with_validators)

    def _held(self, tag: str, held: dict[str, str], scope) -> str | None:
        """Which of the client's tags is this answer's: its own, or its compressed form for a coding the
        request accepts (an inner middleware compresses the same bytes the same way). None: none is."""
        if tag in held:
            return tag
        prefix = tag + "-"
        variants = [t for t in held if t.startswith(prefix)]
        if variants:
            codings = _accepted_codings(scope.get("headers") or [])
            for t in variants:
                if t[len(prefix):].lower() in codings:
                    return t
        return None


def _drop(headers: list, name: bytes) -> list:
    return [(k, v) for k, v in headers if k.lower() != name]


def install(app: FastAPI, settings: Settings) -> None:
    """Add the middleware to ``app``: called after the other middleware, it runs first (outermost), so a
    304 costs no budget, no routing and no work."""
    app.add_middleware(ConditionalGet, max_age_s=settings.cache_max_age_s, fingerprint=settings_fingerprint(settings))
