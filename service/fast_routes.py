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

Such an endpoint keeps its ``response_model`` for the OpenAPI document, but FastAPI does not apply it to a
``Response``: :func:`projection` sends the answer as ``response_model_exclude_unset=True`` would (the model's keys,
in its order, the answer's only, numbers as the model types them) without validating it again.
"""
from __future__ import annotations

import copy
import enum
import functools
import inspect
import types
import typing
from typing import Any, Callable

import numpy as np
from fastapi import Request
from fastapi.exceptions import RequestValidationError
from fastapi.routing import APIRoute
from pydantic import BaseModel
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


# -- an answer's JSON as its response model would send it, without validating it again ------------------------------

_MISSING = object()
_NUMBERS = (int, float, np.number)      # bool is an int


def _as_float(v):
    """A float field's value as pydantic (lax) gives it: an int, a bool or a numpy number as a Python float."""
    return v if type(v) is float or not isinstance(v, _NUMBERS) else float(v)


def _as_int(v):
    """An int field's value as pydantic (lax) gives it: a bool or a numpy integer as a Python int."""
    return v if type(v) is int or not isinstance(v, (int, np.integer)) else int(v)


def _as_python(v):
    """A union's value (``int | "exact"``): a numpy scalar as its Python value, anything else as it is."""
    return v.item() if isinstance(v, np.generic) else v


def _converter(annotation, where: str) -> Callable[[Any], Any] | None:
    """What a field's value needs to be sent as its annotation says; None: nothing (a string, a bool, a literal...)."""
    origin, args = typing.get_origin(annotation), typing.get_args(annotation)
    if origin is typing.Annotated:
        return _converter(args[0], where)
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return projection(annotation)
    if annotation is float:
        return _as_float
    if annotation is int:
        return _as_int
    if annotation in (str, bool, Any) or origin is typing.Literal or annotation is dict or origin is dict and not args:
        return None
    if origin in (typing.Union, types.UnionType):
        members = [a for a in args if a is not type(None)]
        if len(members) == 1:
            inner = _converter(members[0], where)
            return None if inner is None else (lambda v: None if v is None else inner(v))
        if all(a in (str, bool, int, float) or typing.get_origin(a) is typing.Literal for a in members):
            return _as_python
    if origin is list and len(args) == 1:
        inner = _converter(args[0], where)
        return None if inner is None else (lambda v: [inner(x) for x in v])
    if origin is dict and len(args) == 2 and args[0] is str:
        inner = _converter(args[1], where)
        return None if inner is None else (lambda v: {k: inner(x) for k, x in v.items()})
    raise TypeError(f"{where}: {annotation!r} is not sent by a projection; give it a converter or validate the answer")


@functools.cache
def projection(model: type[BaseModel]) -> Callable[[dict], dict]:
    """The function sending an answer (a dict of the library) as FastAPI does with ``response_model=model,
    response_model_exclude_unset=True``, in ~10 us where pydantic's validation and serialisation take ~20 us: the
    model's fields in its order, those the answer holds only (a nested model's likewise), a key the model does not
    declare dropped, an int or a numpy number where the model says float as a float. It does not validate the answer
    (the library makes it; tests/service/test_precession_route.py holds the two equal over the catalogue). A model
    it would not send the same way (aliases, serialisers, extra keys allowed, a type it has no rule for) is refused
    when the route is built (TypeError), never sent differently."""
    where = model.__name__
    decorators = model.__pydantic_decorators__
    if model.model_config.get("extra") == "allow" or model.model_computed_fields or decorators.field_serializers \
            or decorators.model_serializers:
        raise TypeError(f"{where}: extra keys, computed fields or serialisers are not sent by a projection")
    fields = []
    for name, field in model.model_fields.items():
        if field.alias not in (None, name) or field.serialization_alias not in (None, name) or field.exclude:
            raise TypeError(f"{where}.{name}: an alias or an exclusion is not sent by a projection")
        fields.append((name, _converter(field.annotation, f"{where}.{name}")))
    fields = tuple(fields)

    def project(answer: dict) -> dict:
        if not isinstance(answer, dict):
            return answer
        out = {}
        get = answer.get
        for name, convert in fields:
            v = get(name, _MISSING)
            if v is not _MISSING:
                out[name] = v if convert is None else convert(v)
        return out

    project.__qualname__ = f"projection({where})"
    return project
