"""RFC 9457 problem details (application/problem+json) for every error the service returns."""
from __future__ import annotations

import json
import types
import typing
from collections.abc import Sequence
from typing import Optional

from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import JSONResponse
from pydantic import BaseModel, ConfigDict, Field
from starlette.exceptions import HTTPException as StarletteHTTPException
from starlette.routing import Match

from ephem.api import EphemError, InvalidInputError, NotApplicableError, UnknownBodyError

PROBLEM = "application/problem+json"
TYPE_BASE = "https://ephem.invalid/problems/"  # stable identifiers, not fetched


class FieldError(BaseModel):
    field: str = Field(description="the input's full path: a query or path parameter (step_days, body) or a "
                                   "field of the JSON body (orbit.e, track.step_days, moments.A); 'request' for "
                                   "the body as a whole")
    reason: str = Field(description="what is wrong with it, and what is accepted")


class Problem(BaseModel):
    """An RFC 9457 problem: every error the service returns (4xx, and 500 should a bug ever show)."""
    model_config = ConfigDict(extra="allow", json_schema_extra={"examples": [{
        "type": TYPE_BASE + "invalid-input", "title": "Invalid input", "status": 422,
        "detail": "user body: orbit.e: eccentricity must satisfy 0 <= e < 1 (bound orbit), got 1.2",
        "errors": [{"field": "orbit.e", "reason": "eccentricity must satisfy 0 <= e < 1 (bound orbit), got 1.2"}]}]})
    type: str = Field(description="the kind of problem, a stable identifier (not fetched): " + TYPE_BASE +
                                  "invalid-input, not-applicable, unknown-body, over-budget, busy, too-large, "
                                  "deadline, memory, http or internal")
    title: str = Field(description="short summary of the kind")
    status: int = Field(ge=400, le=599, description="the HTTP status, repeated")
    detail: str = Field(description="what was wrong with this request, naming the field")
    errors: Optional[list[FieldError]] = Field(None, description="invalid-input: one entry per offending field")
    known_bodies: Optional[list[str]] = Field(None, description="unknown-body: the catalogue's bodies")
    body: Optional[str] = Field(None, description="not-applicable: the body")
    reason: Optional[str] = Field(None, description="not-applicable: why the theory does not apply")
    spin_orbit_ratio: Optional[float] = Field(None, description="not-applicable: spin rate over orbital mean "
                                                                "motion, when that decided it")
    min_spin_orbit_ratio: Optional[float] = Field(None, description="not-applicable: the ratio's lower limit")
    estimated_cpu_s: Optional[float] = Field(None, description="over-budget, busy: the whole request's estimated "
                                                               "CPU time, s (the number the detail prints): the "
                                                               "parts charged before the refusal and the refused one")
    already_charged_cpu_s: Optional[float] = Field(None, description="over-budget: of estimated_cpu_s, what the "
                                                                     "request's earlier parts had charged when the "
                                                                     "refused part came (0: none)")
    estimated_memory_mb: Optional[float] = Field(None, description="over-budget, busy (memory): its estimated peak "
                                                                   "memory, MB")
    budget_cpu_s: Optional[float] = Field(None, description="over-budget: the CPU budget of a request, s")
    budget_memory_mb: Optional[float] = Field(None, description="over-budget: the memory budget of a request, MB")
    estimate: Optional[dict] = Field(None, description="over-budget: the estimate, part by part (cpu_s is "
                                                       "estimated_cpu_s, the sum of the parts; the earlier parts "
                                                       "charged appear as one, parameter 'request')")
    deadline_s: Optional[float] = Field(None, description="deadline: the wall-clock deadline of a request, s")
    heavy_request_cpu_s: Optional[float] = Field(None, description="busy: a request estimated above this many "
                                                                   "seconds of CPU is large")
    heavy_slots: Optional[int] = Field(None, description="busy: how many large requests run at once")
    worker_request_memory_mb: Optional[float] = Field(None, description="busy (memory): what the requests running in "
                                                                        "a worker may hold together, MB (predicted)")
    in_flight_memory_mb: Optional[float] = Field(None, description="busy (memory): what the requests running in the "
                                                                   "worker held of it when this one was refused, MB")


def problem(status: int, kind: str, title: str, detail: str, headers: dict | None = None, **extra) -> JSONResponse:
    body = {"type": TYPE_BASE + kind, "title": title, "status": status, "detail": detail, **extra}
    return JSONResponse(body, status_code=status, media_type=PROBLEM, headers=headers)


def _field(loc: tuple) -> str:
    """The full dotted path of a pydantic error location: ('body', 'orbit', 'e') -> 'orbit.e',
    ('body', 'moments', 'A') -> 'moments.A', ('query', 'step_days') -> 'step_days'. Union members
    (pydantic adds the member's type: ('body', 'track', 'start', 'float')) and list indices stay out
    of the way: 'track.start', 'errors[0]'."""
    parts = [p for p in loc]
    if parts and parts[0] in ("body", "query", "path", "header", "cookie"):
        parts = parts[1:]
    out = ""
    for p in parts:
        if isinstance(p, int):
            out += f"[{p}]"
        elif isinstance(p, str) and _is_type_tag(p):
            continue
        else:
            out += ("." if out else "") + str(p)
    return out or "request"


_TYPE_TAGS = {"float", "int", "str", "bool", "none", "list", "dict", "function-after", "function-before",
              "function-wrap", "function-plain", "literal", "union", "tagged-union", "json-or-python"}


def _is_type_tag(part: str) -> bool:
    # pydantic names the union member it tried: 'float', 'str', "literal['a','b']", 'function-after[...]'
    head = part.split("[", 1)[0]
    return head in _TYPE_TAGS or head.startswith("lax-")


_STANDARD = {
    400: "the body is not JSON",
    404: "unknown body: the problem lists the known ones (known_bodies)",
    413: "request body too large (EPHEM_MAX_BODY_BYTES, default 65 536 bytes)",
    422: "invalid input, naming each field in `errors` (type invalid-input), or not applicable, with the reason "
         "(type not-applicable)",
    500: "internal error: a bug, reported as a problem (never a bare 500, never NaN)",
    503: "the request ran past its deadline or the worker's memory ceiling and was stopped (deadline, memory): "
         "ask for less; or it is large and as many large requests as allowed are running (busy): retry after "
         "the Retry-After header's seconds",
}


def document(schema: dict) -> dict:
    """Describe the problem+json error responses in an OpenAPI document, in place.

    Every operation gets 422 and 503 (when it takes input), 404 (when its path names a body), 400 and
    413 (when it takes a JSON body) and 500, each ``application/problem+json`` with the ``Problem`` schema; a
    description a route gave for the status is kept. FastAPI's own ``HTTPValidationError`` (a JSON
    shape the service never sends: validation errors are problems too) is dropped.
    """
    components = schema.setdefault("components", {}).setdefault("schemas", {})
    defs = Problem.model_json_schema(ref_template="#/components/schemas/{model}")
    components.update(defs.pop("$defs", {}))
    components["Problem"] = defs
    content = {PROBLEM: {"schema": {"$ref": "#/components/schemas/Problem"}}}
    for path, item in schema.get("paths", {}).items():
        for method, op in item.items():
            if method not in ("get", "put", "post", "delete", "patch", "head", "options"):
                continue
            responses = op.setdefault("responses", {})
            codes = [500]
            if op.get("parameters") or op.get("requestBody"):
                codes += [422, 503]
            if "{body}" in path:
                codes.append(404)
            if op.get("requestBody"):
                codes += [400, 413]
            codes += [int(c) for c in responses if c[0] in "45" and int(c) not in codes]   # a route's own
            for code in sorted(codes):
                given = responses.get(str(code), {})
                responses[str(code)] = {"description": given.get("description") or _STANDARD.get(code, "an error"),
                                        "content": content}
    text = json.dumps(schema.get("paths", {}))
    for name in ("HTTPValidationError", "ValidationError"):
        if f"#/components/schemas/{name}" not in text:
            components.pop(name, None)
    return schema


#: (method, route path) -> {the library's field name: the request's field path}, for routes whose input
#: nests the library's arguments (the POST's track object): an error names the field as the client wrote it
FIELD_PATHS: dict[tuple[str, str], dict[str, str]] = {}


def _request_field(request: Request, field: str) -> str:
    route = request.scope.get("route")
    paths = FIELD_PATHS.get((request.method, getattr(route, "path", "")), {})
    if field in paths:
        return paths[field]
    head, dot, rest = field.partition(".")
    return paths[head] + dot + rest if dot and head in paths else field


class RepeatedQueryParameterError(InvalidInputError):
    """A query parameter given more than once (``?order=2&order=4``): the client's own name, as written."""


#: how many of a repeated parameter's values the refusal quotes, and how long each may be
_QUOTED_VALUES, _QUOTED_CHARS = 4, 40


def _is_list(annotation) -> bool:
    """Whether a parameter's annotation takes several values (list[str], Optional[list[int]]...)."""
    origin = typing.get_origin(annotation)
    if origin in (typing.Union, types.UnionType, typing.Annotated):
        return any(_is_list(a) for a in typing.get_args(annotation))
    return origin in (list, tuple, set, frozenset) or (isinstance(origin, type) and issubclass(origin, Sequence)
                                                        and origin is not str)


async def single_query_values(request: Request) -> None:
    """An app-wide dependency: each query parameter at most once (``async``: it does no I/O, and a plain function
    would cost every request a hop to the thread pool and back, ~0.1 ms of a worker's CPU). Starlette would hand the route the last of
    ``?order=2&order=4`` and drop the first without a word; the client meant one of them, so the request is
    refused naming the parameter. A parameter the route declares as a list (none does today) may repeat."""
    repeated: dict[str, list[str]] = {}
    seen: dict[str, str] = {}
    for name, value in request.query_params.multi_items():
        if name in seen:
            repeated.setdefault(name, [seen[name]]).append(value)
        else:
            seen[name] = value
    if not repeated:
        return
    dependant = getattr(request.scope.get("route"), "dependant", None)
    lists = {f.alias for f in getattr(dependant, "query_params", ()) if _is_list(f.field_info.annotation)}
    for name, values in repeated.items():
        if name in lists:
            continue
        quoted = "&".join(f"{name}={v[:_QUOTED_CHARS]}{'…' if len(v) > _QUOTED_CHARS else ''}"
                          for v in values[:_QUOTED_VALUES]) + ("&…" if len(values) > _QUOTED_VALUES else "")
        raise RepeatedQueryParameterError(name, f"given {len(values)} times ({quoted}): give each query parameter "
                                          "once (the service will not choose one of them for you)")


def _allowed_methods(request: Request) -> list[str]:
    methods: set[str] = set()
    for route in request.app.router.routes:
        if getattr(route, "methods", None) and route.matches(request.scope)[0] is not Match.NONE:
            methods |= set(route.methods)
    return sorted(methods)


def install(app: FastAPI) -> None:
    @app.exception_handler(UnknownBodyError)
    async def unknown_body(request: Request, exc: UnknownBodyError):
        return problem(404, "unknown-body", "Unknown body", str(exc), known_bodies=exc.known)

    @app.exception_handler(NotApplicableError)
    async def not_applicable(request: Request, exc: NotApplicableError):
        return problem(422, "not-applicable", "Not applicable", str(exc), body=exc.body,
                       reason=exc.reason, spin_orbit_ratio=exc.ratio, min_spin_orbit_ratio=exc.threshold)

    @app.exception_handler(RepeatedQueryParameterError)
    async def repeated_query_parameter(request: Request, exc: RepeatedQueryParameterError):
        # named as the client wrote it: FIELD_PATHS maps the library's names, which this one is not
        return problem(422, "invalid-input", "Invalid input", f"{exc.field}: {exc.reason}",
                       errors=[{"field": exc.field, "reason": exc.reason}])

    @app.exception_handler(InvalidInputError)
    async def invalid_input(request: Request, exc: InvalidInputError):
        field = _request_field(request, exc.field)
        detail = f"{exc.body}: {field}: {exc.reason}" if exc.body else f"{field}: {exc.reason}"
        return problem(422, "invalid-input", "Invalid input", detail, errors=[{"field": field, "reason": exc.reason}])

    @app.exception_handler(EphemError)
    async def other_ephem(request: Request, exc: EphemError):
        return problem(422, "invalid-input", "Invalid input", str(exc))

    @app.exception_handler(RequestValidationError)
    async def validation(request: Request, exc: RequestValidationError):
        merged: dict[str, list[str]] = {}     # a union's members each report: one entry per field
        for e in exc.errors():
            field, reason = _field(tuple(e.get("loc", ()))), e.get("msg", "invalid")
            if e.get("type") == "json_invalid":   # loc is ('body', character position)
                field = "request"
                reason = (f"the body is not valid JSON: {(e.get('ctx') or {}).get('error', 'decode error')} "
                          f"(character {e.get('loc', ('', '?'))[-1]})")
            reasons = merged.setdefault(field, [])
            if reason not in reasons:
                reasons.append(reason)
        errors = [{"field": f, "reason": " or ".join(r)} for f, r in merged.items()]
        detail = "; ".join(f"{e['field']}: {e['reason']}" for e in errors)
        return problem(422, "invalid-input", "Invalid input", detail,
                       errors=json.loads(json.dumps(errors, default=str)))

    @app.exception_handler(StarletteHTTPException)
    async def http_error(request: Request, exc: StarletteHTTPException):
        titles = {400: "Bad request", 404: "Not found", 405: "Method not allowed", 413: "Request body too large"}
        headers = dict(exc.headers) if exc.headers else {}      # keep starlette's headers (Allow, ...)
        if exc.status_code == 405:
            # RFC 9110 15.5.6: Allow lists every method of the resource; starlette names only the first route
            # matching the path (here GET /healthz and HEAD /healthz are two routes)
            headers["Allow"] = ", ".join(_allowed_methods(request)) or headers.get("Allow", "")
        return problem(exc.status_code, "http", titles.get(exc.status_code, "HTTP error"), str(exc.detail),
                       headers=headers or None)

    @app.exception_handler(Exception)
    async def unexpected(request: Request, exc: Exception):  # pragma: no cover - a bug if it ever runs
        return problem(500, "internal", "Internal error", f"{type(exc).__name__}: the server failed on this request")
