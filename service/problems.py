"""RFC 9457 problem details (application/problem+json) for every error the service returns."""
from __future__ import annotations

import json

from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import JSONResponse
from starlette.exceptions import HTTPException as StarletteHTTPException

from ephem.errors import EphemError, InvalidInputError, NotApplicableError, UnknownBodyError

PROBLEM = "application/problem+json"
TYPE_BASE = "https://ephem.invalid/problems/"  # stable identifiers, not fetched


def problem(status: int, kind: str, title: str, detail: str, **extra) -> JSONResponse:
    body = {"type": TYPE_BASE + kind, "title": title, "status": status, "detail": detail, **extra}
    return JSONResponse(body, status_code=status, media_type=PROBLEM)


def _field(loc: tuple) -> str:
    parts = [str(p) for p in loc]
    if parts and parts[0] in ("body", "query", "path"):
        parts = parts[1:]
    return ".".join(parts) or "request"


def install(app: FastAPI) -> None:
    @app.exception_handler(UnknownBodyError)
    async def unknown_body(request: Request, exc: UnknownBodyError):
        return problem(404, "unknown-body", "Unknown body", str(exc), known_bodies=exc.known)

    @app.exception_handler(NotApplicableError)
    async def not_applicable(request: Request, exc: NotApplicableError):
        return problem(422, "not-applicable", "Not applicable", str(exc), body=exc.body,
                       reason=exc.reason, spin_orbit_ratio=exc.ratio, min_spin_orbit_ratio=exc.threshold)

    @app.exception_handler(InvalidInputError)
    async def invalid_input(request: Request, exc: InvalidInputError):
        return problem(422, "invalid-input", "Invalid input", str(exc),
                       errors=[{"field": exc.field, "reason": exc.reason}])

    @app.exception_handler(EphemError)
    async def other_ephem(request: Request, exc: EphemError):
        return problem(422, "invalid-input", "Invalid input", str(exc))

    @app.exception_handler(RequestValidationError)
    async def validation(request: Request, exc: RequestValidationError):
        errors = [{"field": _field(tuple(e.get("loc", ()))), "reason": e.get("msg", "invalid")}
                  for e in exc.errors()]
        detail = "; ".join(f"{e['field']}: {e['reason']}" for e in errors)
        return problem(422, "invalid-input", "Invalid input", detail, errors=json.loads(json.dumps(errors, default=str)))

    @app.exception_handler(StarletteHTTPException)
    async def http_error(request: Request, exc: StarletteHTTPException):
        titles = {404: "Not found", 405: "Method not allowed", 413: "Request body too large"}
        return problem(exc.status_code, "http", titles.get(exc.status_code, "HTTP error"), str(exc.detail))

    @app.exception_handler(Exception)
    async def unexpected(request: Request, exc: Exception):  # pragma: no cover - a bug if it ever runs
        return problem(500, "internal", "Internal error", f"{type(exc).__name__}: the server failed on this request")
