"""Routes whose parameters are validated in one pass: FastAPI's own fields, without its per-request analysis.

FastAPI reads a route's query parameters one by one and, for each, works out again on every request what its
declaration says (is it a sequence, a model, which aliases): ~150 us for the track's 14 parameters, as much as the
physics of a 37-epoch track (``benchmarks/RESULTS_overhead.md``). :class:`OnePassRoute` does that analysis once,
when the route is built, and on each request validates each given value with FastAPI's own field (the same
``ModelField.validate``: the same types, bounds, enums, defaults and error entries, so the same 422 problems), then
calls the endpoint. The declaration, and so the OpenAPI document, is FastAPI's, unchanged.

It applies to the endpoints marked :func:`one_pass` whose parameters are path and query parameters of one value
each (no body, header, cookie or list parameter), whose dependencies take only the request, and which return a
``Response`` themselves; any other route is FastAPI's (a marked endpoint that does not qualify is an error at
start-up, so a change of its signature cannot silently lose the fast path's checks).
"""
from __future__ import annotations

import copy
import enum
import inspect
from typing import Any, Callable

from fastapi import Request
from fastapi.exceptions import RequestValidationError
from fastapi.routing import APIRoute
from pydantic_core import PydanticUndefined
from starlette.responses import Response

_MARK = "__ephem_one_pass__"
#: defaults handed to the endpoint as they are (any other is copied per request, as FastAPI does)
_IMMUTABLE = frozenset((type(None), str, int, float, bool))


def one_pass(endpoint: Callable) -> Callable:
    """Mark an endpoint to be served by :class:`OnePassRoute` (it must return a ``Response``)."""
    setattr(endpoint, _MARK, True)
    return endpoint


def _request_only(call: Callable) -> bool:
    params = list(inspect.signature(call).parameters.values())
    return len(params) == 1 and params[0].annotation in (Request, "Request")


class OnePassRoute(APIRoute):
    """An ``APIRoute`` whose marked endpoints are served by :meth:`one_pass_handler` (the others as FastAPI does)."""

    def get_route_handler(self):
        if not getattr(self.endpoint, _MARK, False):
            return super().get_route_handler()
        return self.one_pass_handler()

    def one_pass_handler(self):
        d = self.dependant
        where = f"{sorted(self.methods or ())} {self.path}"
        if d.body_params or d.header_params or d.cookie_params:
            raise TypeError(f"{where}: only path and query parameters are served in one pass")
        for sub in d.dependencies:
            if sub.call is None or not inspect.iscoroutinefunction(sub.call) or not _request_only(sub.call):
                raise TypeError(f"{where}: its dependency {sub.call!r} must be an async function of the request alone")
        if not inspect.iscoroutinefunction(d.call):
            raise TypeError(f"{where}: the endpoint must be async (it chooses where its work runs)")
        fields = []
        for kind, group in (("path", d.path_params), ("query", d.query_params)):
            for f in group:
                if f.field_info.annotation in (list, tuple, set) or getattr(f.field_info.annotation, "__origin__", None) \
                        in (list, tuple, set):
                    raise TypeError(f"{where}: {f.alias} takes several values; not served in one pass")
                default = PydanticUndefined if f.field_info.is_required() else f.field_info.get_default(
                    call_default_factory=True)
                fields.append((kind, f.alias, f.name, f, default, bool(f.field_info.validate_default)))
        dependencies = [sub.call for sub in d.dependencies]
        request_name = d.request_param_name
        endpoint = d.call

        async def handler(request: Request) -> Response:
            for dependency in dependencies:
                await dependency(request)
            given = {"path": request.path_params, "query": request.query_params}
            values: dict[str, Any] = {}
            errors: list = []
            for kind, alias, name, field, default, validate_default in fields:
                raw = given[kind].get(alias)
                loc = (kind, alias)
                if raw is None:
                    if default is PydanticUndefined:
                        errors.append({"type": "missing", "loc": loc, "msg": "Field required", "input": None})
                        continue
                    if not validate_default:
                        values[name] = default if type(default) in _IMMUTABLE or isinstance(default, enum.Enum) \
                            else copy.deepcopy(default)
                        continue
                    raw = default
                value, errs = field.validate(raw, values, loc=loc)
                if errs:
                    errors.extend(errs)
                else:
                    values[name] = value
            if errors:
                raise RequestValidationError(errors)
            if request_name is not None:
                values[request_name] = request
            response = await endpoint(**values)
            if not isinstance(response, Response):
                raise TypeError(f"{where}: an endpoint served in one pass must return a Response")
            return response

        return handler
