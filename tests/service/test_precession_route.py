"""The precession and nutation routes served in one pass (service/fast_routes.py): the JSON their response models
made (response_model_exclude_unset=True: the schema's keys, in its order, the answer's only, numbers typed by the
schema), the same problems for bad input, the same OpenAPI document, and the work where it was put."""
from __future__ import annotations

import dataclasses
import json
import math
import threading
from typing import Optional

import numpy as np
import pytest
from fastapi.routing import APIRoute
from fastapi.testclient import TestClient
from pydantic import BaseModel, ConfigDict, Field, TypeAdapter

import service.app as service_app
from ephem import api
from service import schemas
from service.fast_routes import OnePassRoute, projection
from service.settings import Settings

ROUTES = {"precession": schemas.Precession, "nutation": schemas.Nutation}


def _settings(**kw) -> Settings:
    return dataclasses.replace(Settings.from_env(), warm_up=False, **kw)


@pytest.fixture(scope="module")
def clients():
    fast = TestClient(service_app.create_app(_settings()))
    mp = pytest.MonkeyPatch()
    mp.setattr(service_app, "OnePassRoute", APIRoute)      # FastAPI's own handling of the parameters
    plain = TestClient(service_app.create_app(_settings()))
    mp.undo()
    return fast, plain


def _queries() -> list[str]:
    out = []
    for ds in api.available_datasets():
        for b in api.list_bodies(dataset=ds):
            name = b["name"].lower()
            extra = ["", "&tolerance_mas=10", "&order=2"] + (["&perturbers=sun", "&perturbers=moon,sun"]
                                                            if name == "earth" else [])
            out += [f"{what}|{name}|dataset={ds}{e}" for what in ROUTES for e in extra]
    return out


def _ordered(text: str):
    """A JSON text as nested lists of (key, value) pairs: the keys' order counts."""
    return json.loads(text, object_pairs_hook=list)


def _same(sent, expected, path="$") -> list[str]:
    """Where ``sent`` differs from ``expected``: a key, its order, a JSON type (1 against 1.0), a string, or a number
    beyond 1e-12 relative (both are the same double; the measured model.cost_ms aside)."""
    if type(sent) is not type(expected):
        return [f"{path}: {sent!r} against {expected!r}"]
    if isinstance(sent, list) and sent and isinstance(sent[0], tuple):
        if [k for k, _ in sent] != [k for k, _ in expected]:
            return [f"{path}: keys {[k for k, _ in sent]} against {[k for k, _ in expected]}"]
        return [d for (k, a), (_, b) in zip(sent, expected) if k != "cost_ms" for d in _same(a, b, f"{path}.{k}")]
    if isinstance(sent, list):
        if len(sent) != len(expected):
            return [f"{path}: {len(sent)} items against {len(expected)}"]
        return [d for i, (a, b) in enumerate(zip(sent, expected)) for d in _same(a, b, f"{path}[{i}]")]
    if isinstance(sent, float):
        return [] if math.isclose(sent, expected, rel_tol=1e-12) else [f"{path}: {sent!r} against {expected!r}"]
    return [] if sent == expected else [f"{path}: {sent!r} against {expected!r}"]


@pytest.mark.parametrize("case", _queries())
def test_the_answer_is_sent_as_its_response_model_sent_it(clients, monkeypatch, case):
    """Every catalogue body of every dataset, with a tolerance, an order, the Earth's perturbers: the route's JSON
    against pydantic's serialisation of the same answer under the schema (what FastAPI sent before)."""
    what, body, query = case.split("|")
    fast, _ = clients
    seen = []
    real = getattr(service_app.api, what)
    monkeypatch.setattr(service_app.api, what, lambda *a, **k: seen.append(real(*a, **k)) or seen[-1])
    r = fast.get(f"/v1/bodies/{body}/{what}?{query}")
    if r.status_code != 200:        # not applicable: a problem, as before (the problems are compared below)
        assert r.status_code == 422 and r.headers["content-type"] == "application/problem+json", r.text
        return
    assert r.headers["content-type"] == "application/json"
    adapter = TypeAdapter(ROUTES[what])
    expected = adapter.dump_json(adapter.validate_python(seen[-1]), exclude_unset=True)
    assert not _same(_ordered(r.text), _ordered(expected)), _same(_ordered(r.text), _ordered(expected))[:5]


#: bad and edge queries: each parameter's type, bounds, enumeration, emptiness, repetition; a body unknown
BAD = ["order=-1", "order=99", "order=1.5", "order=", "tolerance_mas=0", "tolerance_mas=abc", "tolerance_mas=nan",
       "dataset=nope", "format=xml", "order=2&order=4", "perturbers=" + "x" * 101, "perturbers=moon", "unknown=1",
       "format=ecsv", "tolerance_mas=1e-9"]


@pytest.mark.parametrize("what", list(ROUTES))
@pytest.mark.parametrize("query", BAD + ["nonrigid=maybe", "cut_mas=0", "layout=bogus", "format=latex"])
def test_bad_input_gets_the_problems_fastapi_gave(clients, what, query):
    fast, plain = clients
    url = f"/v1/bodies/vesta/{what}?{query}"
    a, b = fast.get(url), plain.get(url)
    assert (a.status_code, a.headers["content-type"]) == (b.status_code, b.headers["content-type"]), (a.text, b.text)
    if a.status_code != 200:
        assert a.json() == b.json()


@pytest.mark.parametrize("what", list(ROUTES))
def test_an_unknown_body_is_a_404_naming_the_known_ones(clients, what):
    r = clients[0].get(f"/v1/bodies/no-such-body/{what}")
    assert r.status_code == 404 and r.headers["content-type"] == "application/problem+json"
    assert "Vesta" in r.text


def test_the_routes_are_served_in_one_pass_and_document_their_schemas(clients):
    fast, plain = clients
    paths = fast.get("/openapi.json").json()["paths"]
    for what, model in ROUTES.items():
        path = f"/v1/bodies/{{body}}/{what}"
        route = next(r for r in fast.app.routes if getattr(r, "path", "") == path)
        assert isinstance(route, OnePassRoute) and route.response_model is model
        assert paths[path] == plain.get("/openapi.json").json()["paths"][path]
        assert paths[path]["get"]["responses"]["200"]["content"]["application/json"]["schema"] != {}


def test_a_precession_runs_on_the_event_loop_and_a_nutation_in_the_thread_pool(monkeypatch):
    """The precession's price (< 5 ms) keeps it on the loop; the nutation is always in the pool (the Moon's terms
    take far longer than predicted)."""
    seen = []
    for what in ROUTES:
        real = getattr(service_app.api, what)
        monkeypatch.setattr(service_app.api, what, lambda *a, _real=real, **k: seen.append(
            threading.current_thread().name) or _real(*a, **k))
    with TestClient(service_app.create_app(_settings(inline_cpu_ms=5.0))) as client:
        for what in ROUTES:
            client.get(f"/v1/bodies/vesta/{what}")             # the body's caches built
        loop = client.portal.call(lambda: threading.current_thread().name)
        seen.clear()
        assert client.get("/v1/bodies/vesta/precession").status_code == 200
        assert seen == [loop]
        seen.clear()
        assert client.get("/v1/bodies/vesta/nutation").status_code == 200
        assert len(seen) == 1 and seen[0] != loop


class _Inner(BaseModel):
    b: float
    a: Optional[int] = None


class _Outer(BaseModel):
    x: float
    n: int
    rates: dict[str, float]
    order: Optional[int | str] = None
    inner: Optional[_Inner] = None
    items: list[_Inner] = Field(default_factory=list)
    absent: Optional[float] = None


def test_a_projection_sends_what_pydantic_sends():
    """Key order (the model's), keys unknown to the model dropped, an unset key left out, ints, bools and numpy
    numbers typed as the model says: against pydantic's own JSON of the same dict."""
    answer = {"items": [{"a": np.int64(2), "b": 3, "c": "dropped"}], "inner": None, "n": True, "x": np.float32(0.1),
              "rates": {"k": 1, "m": np.float64(2.5)}, "order": np.int64(4), "extra": [1, 2]}
    adapter = TypeAdapter(_Outer)
    expected = adapter.dump_json(adapter.validate_python(answer), exclude_unset=True)
    sent = json.dumps(projection(_Outer)(answer), default=lambda v: v.item())
    assert not _same(_ordered(sent), _ordered(expected)), (sent, expected)


def test_a_model_a_projection_would_send_differently_is_refused():
    class Aliased(BaseModel):
        x: float = Field(alias="y")

    class Open(BaseModel):
        model_config = ConfigDict(extra="allow")
        x: float

    class Odd(BaseModel):
        x: set[int]

    for model in (Aliased, Open, Odd):
        with pytest.raises(TypeError):
            projection(model)
