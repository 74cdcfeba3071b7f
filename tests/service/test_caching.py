"""Answers that caches can keep (service/caching.py): the ETag of a GET answer is a hash of the request, the
version and the data, known before any work; a matching If-None-Match is a 304 without a body and without the
computation; errors, POST answers and /healthz are never kept."""
from __future__ import annotations

import asyncio
import os
import re
import shutil

import pytest
from fastapi.testclient import TestClient

import ephem
from service import app as service_app
from service import caching
from service.app import create_app
from service.settings import Settings

TAG = re.compile(r'^(W/)?"[0-9a-f]{32}"$')
PRECESSION = "/v1/bodies/vesta/precession"
TRACK_CSV = "/v1/bodies/ceres/track?start=2040-01-01&stop=2040-12-31&step_days=120&format=csv"
TRACK_PNG = "/v1/bodies/vesta/track.png?start=2040-01-01&stop=2041-01-01"
USER = {"orbit": {"a_au": 2.36, "e": 0.089, "i_deg": 7.14, "node_deg": 103.7, "peri_deg": 151.7,
                  "mean_anomaly_deg": 169.2, "epoch_jd_tdb": 2460200.5},
        "pole": {"ra_deg": 309.03, "dec_deg": 42.23}, "rotation_period_hours": 5.342,
        "moments": {"A": 0.3433, "B": 0.3546, "C": 0.42}}


@pytest.fixture(scope="module")
def client():
    with TestClient(create_app(Settings(warm_up=False))) as c:
        yield c


@pytest.fixture
def calls(monkeypatch):
    """How many times each library function the routes call ran (the real function still answers)."""
    counts: dict[str, int] = {}
    for name in ("precession", "track_arrays", "render_plot"):
        real = getattr(service_app.api, name)

        def counted(*args, _real=real, _name=name, **kwargs):
            counts[_name] = counts.get(_name, 0) + 1
            return _real(*args, **kwargs)

        monkeypatch.setattr(service_app.api, name, counted)
    return counts


# ------------------------------------------------------------------ the tag and the caching headers

@pytest.mark.parametrize("url", [PRECESSION, TRACK_CSV, TRACK_PNG, "/v1/bodies",
                                 "/v1/bodies/vesta/nutation?format=markdown", "/", "/bodies/vesta"])
def test_a_get_answer_carries_a_stable_etag_and_cache_control(client, url):
    first, second = client.get(url), client.get(url)
    assert first.status_code == second.status_code == 200
    assert TAG.match(first.headers["etag"]), first.headers["etag"]
    assert first.headers["etag"] == second.headers["etag"]
    assert first.headers["cache-control"] == "public, max-age=86400"


def test_the_etag_is_strong_only_where_the_bytes_repeat(client):
    """JSON and HTML carry the measured cost_ms, so two computations differ in those digits: weak tags. The
    CSV, the tables and the figures are the same bytes each time (the SVG's ids too): strong tags."""
    for url in (TRACK_CSV, TRACK_PNG, TRACK_PNG.replace(".png", ".svg"), "/v1/bodies/vesta/nutation?format=latex"):
        a, b = client.get(url), client.get(url)
        assert a.content == b.content and not a.headers["etag"].startswith("W/"), url
    for url in (PRECESSION, "/bodies/vesta"):
        assert client.get(url).headers["etag"].startswith('W/"'), url


def test_the_parameters_order_and_spelling_do_not_change_the_tag(client):
    tags = {client.get(f"{PRECESSION}?{q}").headers["etag"]
            for q in ("dataset=petit2014&order=4", "order=4&dataset=petit2014", "order=4&dataset=petit%32014")}
    assert len(tags) == 1


def test_a_different_question_has_a_different_tag(client):
    urls = [PRECESSION, f"{PRECESSION}?order=4", f"{PRECESSION}?order=2", f"{PRECESSION}?dataset=petit2014",
            "/v1/bodies/ceres/precession", TRACK_CSV, TRACK_CSV.replace("format=csv", "format=json"), TRACK_PNG,
            TRACK_PNG.replace(".png", ".svg")]
    tags = [client.get(u).headers["etag"].removeprefix("W/") for u in urls]
    assert len(set(tags)) == len(urls), dict(zip(urls, tags))


def test_another_version_has_other_tags(client, monkeypatch):
    before = client.get(PRECESSION).headers["etag"]
    monkeypatch.setattr(ephem, "__version__", ephem.__version__ + ".post1")
    with TestClient(create_app(Settings(warm_up=False))) as other:
        after = other.get(PRECESSION)
    assert after.status_code == 200 and after.headers["etag"] != before
    # the tag is what the version, the data and the request make: a new app of the same version agrees
    monkeypatch.undo()
    with TestClient(create_app(Settings(warm_up=False))) as same:
        assert same.get(PRECESSION).headers["etag"] == before


def test_other_data_give_other_tags(tmp_path):
    """One byte changed in one shipped file changes every tag; a copy of the same files elsewhere does not."""
    root = ephem.api.data_dir()
    copy, changed = tmp_path / "copy", tmp_path / "changed"
    shutil.copytree(root, copy)
    shutil.copytree(root, changed)
    with open(changed / "catalogue" / "current.toml", "ab") as fh:
        fh.write(b"\n")
    scope = {"type": "http", "method": "GET", "path": PRECESSION, "query_string": b"", "headers": []}
    tags = [caching.ConditionalGet(None, 60, "", data_root=r).etag(scope) for r in (root, copy, changed)]
    assert tags[0] == tags[1] != tags[2]
    assert caching.tree_digest(root) == caching.tree_digest(copy) != caching.tree_digest(changed)


def test_an_imported_dataset_changes_the_tags(client, tmp_path, monkeypatch):
    """The library re-reads a user's dataset when its file changes (ephem catalogue import): so does the tag.
    (The directory is found when the service starts: the environment is a running service's own.)"""
    monkeypatch.setenv("EPHEM_USER_CATALOGUE_DIR", str(tmp_path))
    with TestClient(create_app(Settings(warm_up=False))) as fresh:
        assert fresh.get(PRECESSION).headers["etag"] == client.get(PRECESSION).headers["etag"]   # both empty
    client = TestClient(create_app(Settings(warm_up=False)))
    empty = client.get(PRECESSION).headers["etag"]
    mine = tmp_path / "mine.toml"
    mine.write_text('[dataset]\nname = "mine"\n')
    imported = client.get(PRECESSION).headers["etag"]
    mine.write_text('[dataset]\nname = "MINE"\n')          # the same size, other bytes, another time
    st = mine.stat()
    os.utime(mine, ns=(st.st_atime_ns, st.st_mtime_ns + 10**9))
    replaced = client.get(PRECESSION).headers["etag"]
    mine.unlink()
    assert len({empty, imported, replaced}) == 3
    assert client.get(PRECESSION).headers["etag"] == empty


def test_the_pages_tags_follow_the_address_they_print(client):
    """A page prints its curl lines' address, the server's own (or EPHEM_PUBLIC_BASE_URL, a setting the tag hashes),
    never the client's Host header (issue 42): one tag at any Host, another at another server address; the API's
    answers print none, and keep one tag at every address (replicas behind one proxy share them)."""
    assert client.get("/", headers={"host": "a.example"}).headers["etag"] == \
        client.get("/", headers={"host": "b.example"}).headers["etag"]
    with TestClient(client.app, base_url="http://other.example:8000") as other:
        assert other.get("/").headers["etag"] != client.get("/").headers["etag"]
        assert other.get(PRECESSION).headers["etag"] == client.get(PRECESSION).headers["etag"]
    assert client.get(PRECESSION, headers={"host": "a.example"}).headers["etag"] == \
        client.get(PRECESSION, headers={"host": "b.example"}).headers["etag"]


# ------------------------------------------------------------------ 304 before the work

@pytest.mark.parametrize("url, function", [(PRECESSION, "precession"), (TRACK_CSV, "track_arrays"),
                                           (TRACK_PNG, "render_plot")])
def test_a_matching_if_none_match_is_a_304_without_the_computation(client, calls, url, function):
    full = client.get(url)
    assert full.status_code == 200 and calls == {function: 1}
    tag = full.headers["etag"]
    again = client.get(url, headers={"If-None-Match": tag})
    assert again.status_code == 304 and again.content == b""
    assert again.headers["etag"] == tag and again.headers["cache-control"] == full.headers["cache-control"]
    assert "content-length" not in again.headers or again.headers["content-length"] == "0"
    assert calls == {function: 1}, "the 304 ran the computation"


def test_if_none_match_lists_and_weak_comparison(client, calls):
    tag = client.get(PRECESSION).headers["etag"]
    opaque = tag.removeprefix("W/")
    for header in (f'"0123", {tag}', f'W/{opaque}', opaque, f'"a,b", {opaque} , "c"'):
        r = client.get(PRECESSION, headers={"If-None-Match": header})
        assert r.status_code == 304 and r.content == b"", header
    assert calls == {"precession": 1}


def test_a_tag_that_does_not_match_computes_the_answer(client, calls):
    tag = client.get(PRECESSION).headers["etag"]
    other = client.get(PRECESSION, headers={"If-None-Match": '"0123456789abcdef0123456789abcdef"'})
    assert other.status_code == 200 and other.json()["body"] == "Vesta" and other.headers["etag"] == tag
    stale = client.get(f"{PRECESSION}?order=4", headers={"If-None-Match": tag})     # another question's tag
    assert stale.status_code == 200 and stale.headers["etag"] != tag
    assert calls == {"precession": 3}


def test_if_none_match_star_is_a_304_when_there_is_an_answer(client):
    r = client.get(PRECESSION, headers={"If-None-Match": "*"})
    assert r.status_code == 304 and r.content == b"" and TAG.match(r.headers["etag"])
    refused = client.get("/v1/bodies/nobody/precession", headers={"If-None-Match": "*"})
    assert refused.status_code == 404 and "etag" not in refused.headers


# ------------------------------------------------------------------ what is never kept

@pytest.mark.parametrize("url, status", [("/v1/bodies/nobody/precession", 404),
                                         (f"{PRECESSION}?order=-1", 422),
                                         (f"{PRECESSION}?order=2&order=4", 422),
                                         ("/v1/no-such-route", 404)])
def test_errors_carry_no_etag_and_are_not_stored(client, url, status):
    r = client.get(url)
    assert r.status_code == status
    assert "etag" not in r.headers and r.headers["cache-control"] == "no-store"


def test_post_answers_and_healthz_are_not_stored(client):
    post = client.post("/v1/precession-nutation", json=USER)
    assert post.status_code == 200 and "etag" not in post.headers and post.headers["cache-control"] == "no-store"
    for method in ("GET", "HEAD"):
        health = client.request(method, "/healthz", headers={"If-None-Match": "*"})
        assert health.status_code == 200 and "etag" not in health.headers
        assert health.headers["cache-control"] == "no-store"


def test_max_age_is_a_setting_and_zero_asks_to_revalidate(monkeypatch):
    with TestClient(create_app(Settings(warm_up=False, cache_max_age_s=0))) as c:
        r = c.get("/v1/bodies")
        assert r.headers["cache-control"] == "no-cache" and TAG.match(r.headers["etag"])
        assert c.get("/v1/bodies", headers={"If-None-Match": r.headers["etag"]}).status_code == 304
    monkeypatch.setenv("EPHEM_CACHE_MAX_AGE_S", "0")
    assert Settings.from_env().cache_max_age_s == 0
    monkeypatch.setenv("EPHEM_CACHE_MAX_AGE_S", "600")
    assert Settings.from_env().cache_max_age_s == 600
    monkeypatch.setenv("EPHEM_CACHE_MAX_AGE_S", "-1")
    with pytest.raises(SystemExit, match="EPHEM_CACHE_MAX_AGE_S"):
        Settings.from_env()


# ------------------------------------------------------------------ the middleware alone (pure ASGI)

def _run(middleware, method="GET", path="/v1/x", headers=()) -> list[dict]:
    scope = {"type": "http", "method": method, "path": path, "query_string": b"", "root_path": "",
             "headers": [(k.lower().encode(), v.encode()) for k, v in headers]}
    sent = []

    async def receive():
        return {"type": "http.request", "body": b"", "more_body": False}

    async def send(message):
        sent.append(message)

    asyncio.run(middleware(scope, receive, send))
    return sent


def _app(status=200, headers=(), chunks=(b"a", b"b")):
    """An inner application that answers ``status`` in several body messages, as a StreamingResponse does."""
    ran = []

    async def app(scope, receive, send):
        ran.append(scope["method"])
        await send({"type": "http.response.start", "status": status,
                    "headers": [(k.encode(), v.encode()) for k, v in headers]})
        for i, chunk in enumerate(chunks):
            await send({"type": "http.response.body", "body": chunk, "more_body": i < len(chunks) - 1})

    return app, ran


def _headers(message) -> dict:
    return {k.decode(): v.decode() for k, v in message["headers"]}


@pytest.mark.parametrize("status", [503, 500, 413, 307])
def test_a_busy_or_failed_answer_is_not_stored(status):
    app, _ = _app(status, headers=[("content-type", "application/problem+json"), ("etag", '"x"'),
                                   ("cache-control", "public, max-age=5")])
    start = _run(caching.ConditionalGet(app, 60, ""))[0]
    assert start["status"] == status
    assert _headers(start) == {"content-type": "application/problem+json", "cache-control": "no-store"}


def test_a_streamed_answer_the_client_holds_is_not_sent():
    app, ran = _app(headers=[("content-type", "text/csv")])
    middleware = caching.ConditionalGet(app, 60, "")
    full = _run(middleware)
    tag = _headers(full[0])["etag"]
    assert b"".join(m.get("body", b"") for m in full[1:]) == b"ab"
    held = _run(middleware, headers=[("If-None-Match", "*")])      # '*': the route runs, its body is dropped
    assert held[0]["status"] == 304 and _headers(held[0])["etag"] == tag
    assert [m.get("body") for m in held[1:]] == [b""] and held[-1]["more_body"] is False
    assert _run(middleware, headers=[("If-None-Match", tag)])[0]["status"] == 304
    assert ran == ["GET", "GET"]                                     # the exact tag ran nothing


def test_head_gets_the_tag_of_get():
    app, ran = _app(headers=[("content-type", "text/csv")], chunks=(b"",))
    middleware = caching.ConditionalGet(app, 60, "")
    get, head = _headers(_run(middleware)[0]), _headers(_run(middleware, "HEAD")[0])
    assert get["etag"] == head["etag"] and head["cache-control"] == "public, max-age=60"
    assert _run(middleware, "HEAD", headers=[("If-None-Match", get["etag"])])[0]["status"] == 304


def test_a_compressed_answer_names_its_coding_and_varies_on_accept_encoding():
    app, _ = _app(headers=[("content-type", "text/csv"), ("content-encoding", "gzip")])
    middleware = caching.ConditionalGet(app, 60, "")
    start = _headers(_run(middleware, headers=[("Accept-Encoding", "gzip")])[0])
    assert start["etag"].endswith('-gzip"') and start["vary"] == "Accept-Encoding"
    held = _run(middleware, headers=[("Accept-Encoding", "br, gzip"), ("If-None-Match", start["etag"])])
    assert held[0]["status"] == 304 and _headers(held[0])["vary"] == "Accept-Encoding"


def test_the_canonical_query():
    q = caching.canonical_query
    assert q(b"a=1&b=2") == q(b"b=2&a=1") == q(b"b=2&a=%31") != q(b"a=2&b=1")
    assert q(b"a=x+y") == q(b"a=x%20y") and q(b"a=&b=1") != q(b"b=1")
    assert q(b"a=1%26b%3D2") != q(b"a=1&b=2")                        # an encoded & stays a value


def test_the_code_enters_the_tags(tmp_path):
    """A deployment of changed code under the same version must not have caches serve the old answers: the code's
    digest (every source file of the packages, compiled bytecode left out) changes with any source byte."""
    from service.caching import code_digest

    pkg = tmp_path / "pkg"
    (pkg / "__pycache__").mkdir(parents=True)
    (pkg / "mod.py").write_text("X = 1\n")
    (pkg / "page.html").write_text("<p>1</p>\n")
    before = code_digest([pkg])
    (pkg / "__pycache__" / "mod.cpython-311.pyc").write_bytes(b"\x00compiled")
    assert code_digest([pkg]) == before                        # bytecode differs between machines: not hashed
    (pkg / "page.html").write_text("<p>2</p>\n")
    assert code_digest([pkg]) != before
    assert code_digest() == code_digest()                       # the shipped packages: stable within a build
