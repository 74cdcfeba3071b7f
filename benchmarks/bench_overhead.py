"""Benchmark: the service's overhead near the framework's floor (issue 39, part 3), before and after in one run.

    .venv/bin/python benchmarks/bench_overhead.py          # make bench-overhead; ~3 minutes
    .venv/bin/python benchmarks/bench_overhead.py --quick  # a smoke run (~1.5 minutes)

Two code trees: "before" (``--before``, default 8e7d8db, the state before issue 39's overhead work, checked out by
``git worktree add`` into a temporary directory and removed at the end) and "after" (this working tree, with its
uncommitted changes). Every child process runs its tree's ``ephem`` and ``service`` (the tree first on PYTHONPATH,
its directory as the working directory; ``machine.tree_env``: compiled bytecode and a table cache per tree), and
the parent checks that each child imported them from there. The measurements, all ratios within this one run:

1. HTTP throughput over loopback: the tree's service under gunicorn as ``make serve`` starts it (``gunicorn
   --config service/gunicorn_conf.py --bind 127.0.0.1:PORT --workers 2 service.app:app``: two uvicorn workers),
   loaded with ``--connections`` (50) keep-alive connections for ``--duration`` seconds per request by the load
   generator of ``bench_service.py`` (``wrk`` when on PATH, else its Python generator; neither sends
   ``If-None-Match``, so every answer is computed, never a 304). Requests: ``/healthz``, the precession of
   Vesta, Ceres' 37-epoch track and the same with ``tolerance_mas=100``; each as requests/s and as a % of
   /healthz's in the same server run, and the CPU time the two workers spent per request (their
   utime + stime from /proc over the load, divided by the requests answered). The server runs alternate
   between the trees (before, after, before, after: ``--rounds``); the table gives medians over the rounds.
2. In-process warm CPU per call (``time.process_time``, median of many, one BLAS thread as under gunicorn) of
   ``api.track_arrays('ceres', '2040-01-01', '2040-12-31', 10.0, model='hansen')``, the same with
   ``tolerance_mas=100`` and ``api.precession('vesta')``, in a subprocess per tree and round.
3. The page's track view against its API answer plus the models chart: the ASGI app in-process
   (``httpx.ASGITransport``, no network), warm median wall time of the page ``GET /bodies/ceres/track?...``,
   ``GET /v1/bodies/ceres/track?...`` and ``GET /v1/bodies/ceres/track/models.svg?...`` (same parameters);
   page / (API + chart). A tree without the chart route (404) reports it missing.
4. The framework's floor for the track route (this tree only; ``--no-floor`` skips it): in-process wall time of
   /healthz, of the track route with ``api.track_arrays`` replaced by its precomputed answer (what FastAPI,
   the middleware, the dependency and the JSON encoding cost around the science), single pieces timed alone,
   and a cProfile of the stubbed route grouped by layer.

Every loop is bounded in count and time; servers are always terminated (SIGTERM, then SIGKILL to their process
group). Writes benchmarks/RESULTS_overhead.md.
"""
from __future__ import annotations

import argparse
import contextlib
import inspect
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
RESULTS = ROOT / "benchmarks" / "RESULTS_overhead.md"
BEFORE = "8e7d8db"

QUERY = "start=2040-01-01&stop=2040-12-31&step_days=10"
TRACK_EPOCHS = 37
#: (key, label, path): the HTTP rows, /healthz first (the others are a % of it)
URLS = [
    ("healthz", "GET /healthz", "/healthz"),
    ("precession", "GET /v1/bodies/vesta/precession", "/v1/bodies/vesta/precession"),
    ("track", "GET /v1/bodies/ceres/track (37 epochs)", f"/v1/bodies/ceres/track?{QUERY}"),
    ("track_tol", "… the same with tolerance_mas=100", f"/v1/bodies/ceres/track?{QUERY}&tolerance_mas=100"),
]
#: a new question each request (wrk only): the same tracks, each request's start moved by its own 1e-8 d (~1 ms), so
#: that nothing kept for an identical question (the ladder's estimates, the pole's 1-sigma, kept per epochs) answers
#: it; still 37 epochs. (key, label, path without the start)
NEW_QUESTION = [
    ("track_new", "the 37-epoch track, a new question each request",
     "/v1/bodies/ceres/track?stop=2040-12-31&step_days=10"),
    ("track_tol_new", "… the same with tolerance_mas=100",
     "/v1/bodies/ceres/track?stop=2040-12-31&step_days=10&tolerance_mas=100"),
]
NEW_QUESTION_JD0 = 2466154.5008        # 2040-01-01 UTC as a TDB Julian date, near enough
_NEW_QUESTION_LUA = """
local next_id = 1
function setup(thread)
  thread:set("id", next_id)
  next_id = next_id + 1
end
local n = 0
function request()
  n = n + 1
  return wrk.format(nil, string.format("PATH&start=JD%.8f", JD0 + (id * 1000000 + n) * 1e-8))
end
"""
#: issue 39's goals: % of /healthz's requests/s
HTTP_GOALS_PCT = {"precession": 50.0, "track": 33.0, "track_tol": 33.0}
CPU_GOAL_MS = {"hansen": 1.0}
#: the issue's own measurement before the work (req/s, same route set)
ISSUE_BEFORE = "healthz 2,553 req/s, precession 1,320 (52 %), 37-epoch track 111 (4.3 %)"
CPU_ROWS = [
    ("hansen", "api.track_arrays('ceres', 2040-01-01 … 2040-12-31, 10 d, model='hansen')"),
    ("tol100", "api.track_arrays(… the same, tolerance_mas=100)"),
    ("precession", "api.precession('vesta')"),
    ("hansen_new", "api.track_arrays('ceres', JD0 + k·1e-8 d … 2040-12-31, 10 d, model='hansen'): a new question "
                   "each call"),
    ("tol100_new", "api.track_arrays(… the same, tolerance_mas=100): a new question each call"),
]
PAGE_CANDIDATES = (f"/bodies/ceres/track?{QUERY}", f"/track?body=ceres&{QUERY}")
API_TRACK = f"/v1/bodies/ceres/track?{QUERY}"
CHART = f"/v1/bodies/ceres/track/models.svg?{QUERY}"

SERVER_START_TIMEOUT_S = 90.0
CHILD_TIMEOUT_S = 240.0
CHILD_BUDGET_S = 8.0       # each in-process child stops sampling after this long, whatever its count


# ----------------------------------------------------------------------------- children (run in one tree)

def _median_ms(xs: list[float]) -> float:
    return statistics.median(xs) * 1e3 if xs else float("nan")


def _where() -> dict:
    import ephem
    import service
    return {"ephem": str(Path(ephem.__file__).resolve()), "service": str(Path(service.__file__).resolve())}


_STARTS = iter(range(1, 10**9))


def _next_start() -> str:
    """A start never asked before in this process (the new-question rows): JD0 + k·1e-8 d."""
    return f"JD{NEW_QUESTION_JD0 + next(_STARTS) * 1e-8:.8f}"


def child_cpu(n: int) -> dict:
    """Warm CPU per call of the three library calls, interleaved (n each after a warm-up)."""
    from ephem import api

    calls = {
        "hansen": lambda: api.track_arrays("ceres", "2040-01-01", "2040-12-31", 10.0, model="hansen"),
        "tol100": lambda: api.track_arrays("ceres", "2040-01-01", "2040-12-31", 10.0, tolerance_mas=100.0),
        "precession": lambda: api.precession("vesta"),
        "hansen_new": lambda: api.track_arrays("ceres", _next_start(), "2040-12-31", 10.0, model="hansen"),
        "tol100_new": lambda: api.track_arrays("ceres", _next_start(), "2040-12-31", 10.0, tolerance_mas=100.0),
    }
    epochs = len(calls["hansen"]()["jd_tdb"])
    if epochs != TRACK_EPOCHS:
        raise SystemExit(f"the track has {epochs} epochs, expected {TRACK_EPOCHS}")
    for _ in range(10):
        for fn in calls.values():
            fn()
    out: dict = {k: [] for k in calls}
    deadline = time.monotonic() + CHILD_BUDGET_S
    for _ in range(n):
        if time.monotonic() > deadline:
            break
        for key, fn in calls.items():
            t0 = time.process_time()
            fn()
            out[key].append(time.process_time() - t0)
    return {"samples": out, "where": _where()}


async def _asgi_client(app):
    import httpx
    return httpx.AsyncClient(transport=httpx.ASGITransport(app=app), base_url="http://bench", timeout=60.0)


def child_asgi(n: int) -> dict:
    """Warm wall time of the page's track view, the API's track and the models chart, in-process."""
    import asyncio

    from service.app import app

    async def main() -> dict:
        async with app.router.lifespan_context(app), await _asgi_client(app) as c:
            status = {}
            page = None
            for path in PAGE_CANDIDATES:
                r = await c.get(path)
                status[path] = r.status_code
                if r.status_code != 404:
                    page = path
                    break
            urls = {"page": page, "api": API_TRACK, "chart": CHART}
            for key in ("api", "chart"):
                status[urls[key]] = (await c.get(urls[key])).status_code
            ok = {k: u for k, u in urls.items() if u is not None and status.get(u) == 200}
            for _ in range(2):
                for u in ok.values():
                    (await c.get(u)).raise_for_status()
            samples: dict = {k: [] for k in ok}
            cpu: dict = {k: [] for k in ok}
            deadline = time.monotonic() + CHILD_BUDGET_S
            for _ in range(n):
                if time.monotonic() > deadline:
                    break
                for key, u in ok.items():     # interleaved: a slower spell of the machine falls on all three
                    c0, t0 = time.process_time(), time.perf_counter()
                    r = await c.get(u)
                    samples[key].append(time.perf_counter() - t0)
                    cpu[key].append(time.process_time() - c0)     # every thread of the process: the pool's too
                    r.raise_for_status()
            return {"samples": samples, "cpu": cpu, "urls": urls, "status": status}

    out = asyncio.run(main())
    out["where"] = _where()
    return out


def child_floor(n: int) -> dict:
    """The framework's floor for the track route: wall times in-process with the science precomputed, pieces
    timed alone, and a cProfile of the stubbed route grouped by layer (ms per request, under the profiler)."""
    import asyncio
    import cProfile
    import pstats

    import anyio.to_thread

    import ephem.api as api
    from service.app import app

    track_url = URLS[2][2]
    out: dict = {"wall_ms": {}, "cpu_ms": {}, "pieces_us": {}}

    def med_us(fn, reps: int = 3000) -> float:
        for _ in range(100):
            fn()
        ts = []
        for _ in range(reps):
            t0 = time.perf_counter()
            fn()
            ts.append(time.perf_counter() - t0)
        return statistics.median(ts) * 1e6

    async def timed(c, url: str, wall: list, cpu: list) -> None:
        """One request: its wall time and the process's CPU time (the event loop and the worker threads)."""
        t0, c0 = time.perf_counter(), time.process_time()
        r = await c.get(url)
        wall.append(time.perf_counter() - t0)
        cpu.append(time.process_time() - c0)
        r.raise_for_status()

    async def measure(c, url: str, reps: int, key: str | None = None) -> None:
        wall, cpu = [], []
        for _ in range(reps):
            await timed(c, url, wall, cpu)
        if key:
            out["wall_ms"][key], out["cpu_ms"][key] = _median_ms(wall), _median_ms(cpu)

    async def bare(scope, receive, send):        # the least an ASGI app can do: the test client's own cost
        await send({"type": "http.response.start", "status": 200, "headers": [(b"content-type", b"application/json")]})
        await send({"type": "http.response.body", "body": b"{}"})

    real = api.track_arrays
    answer = real("ceres", "2040-01-01", "2040-12-31", 10.0)
    calls = {"stub": 0}

    def stub(*args, **kwargs):
        calls["stub"] += 1
        return dict(answer)

    async def main() -> None:
        async with app.router.lifespan_context(app), await _asgi_client(app) as c:
            for _ in range(20):
                (await c.get(track_url)).raise_for_status()
            async with await _asgi_client(bare) as b:
                await measure(b, "/", 50)
                await measure(b, "/", n, "bare")
            await measure(c, "/healthz", n, "healthz")
            # the route as served and with the science stubbed, alternately (a drifting load falls on both)
            served: tuple = ([], [])
            stubbed: tuple = ([], [])
            for _ in range(n):
                for fn, (wall, cpu) in ((real, served), (stub, stubbed)):
                    api.track_arrays = fn
                    await timed(c, track_url, wall, cpu)
            api.track_arrays = real
            for key, (wall, cpu) in (("track", served), ("track_stub", stubbed)):
                out["wall_ms"][key], out["cpu_ms"][key] = _median_ms(wall), _median_ms(cpu)
            out["stub_used"] = calls["stub"] > 0
            api.track_arrays = stub
            try:
                # pieces alone
                hop = []
                for _ in range(n):
                    t0 = time.perf_counter()
                    await anyio.to_thread.run_sync(lambda: None)
                    hop.append(time.perf_counter() - t0)
                out["pieces_us"]["thread-pool hop (anyio.to_thread.run_sync of a no-op)"] = statistics.median(hop) * 1e6
                out["pieces_us"].update(_pieces(med_us, answer, app))

                # cProfile of the stubbed route, the event loop and the worker threads, each on its own thread's
                # CPU clock: a wall clock would charge a layer the time its thread waits for the GIL
                loop_prof, thread_prof = cProfile.Profile(time.thread_time), cProfile.Profile(time.thread_time)
                original = anyio.to_thread.run_sync

                async def profiled(func, *args, **kwargs):
                    def wrapped(*a):
                        thread_prof.enable()
                        try:
                            return func(*a)
                        finally:
                            thread_prof.disable()
                    return await original(wrapped, *args, **kwargs)

                anyio.to_thread.run_sync = profiled
                reps = max(50, n // 10)
                try:
                    t0 = time.perf_counter()
                    loop_prof.enable()
                    for _ in range(reps):
                        (await c.get(track_url)).raise_for_status()
                    loop_prof.disable()
                    out["profiled_ms"] = (time.perf_counter() - t0) * 1e3 / reps
                finally:
                    anyio.to_thread.run_sync = original
            finally:
                api.track_arrays = real
        stats = pstats.Stats(loop_prof)
        thread_prof.create_stats()
        if thread_prof.stats:          # a route answered on the event loop (service/offload.py) makes no hop
            stats.add(thread_prof)
        out["layers"] = _layers(stats, reps)

    asyncio.run(main())
    out["where"] = _where()
    return out


def _pieces(med_us, answer: dict, app) -> dict:
    """Single pieces of a request, each timed alone (µs, median); a piece a tree does not have is left out."""
    out = {}
    with contextlib.suppress(Exception):
        from fastapi.dependencies.utils import request_params_to_args
        from starlette.datastructures import QueryParams
        route = next(r for r in app.routes if getattr(r, "path", None) == "/v1/bodies/{body}/track"
                     and "GET" in getattr(r, "methods", ()))
        fields, given = route.dependant.query_params, QueryParams(QUERY)
        values, errors = request_params_to_args(fields, given)
        if not errors:
            out[f"FastAPI: request_params_to_args, the track route's {len(fields)} query parameters "
                f"({len(given)} given)"] = med_us(lambda: request_params_to_args(fields, given))
    with contextlib.suppress(Exception):
        from service.settings import Settings

        from ephem.host import budget
        s = Settings.from_env()

        def enter_budget():
            with budget(s.max_request_cpu_s, s.max_request_memory_mb, s.request_deadline_s, admit=None):
                pass
        out["service/guards.py: the request's budget() (enter + exit)"] = med_us(enter_budget)
    with contextlib.suppress(Exception):
        from service import guards
        wd = guards.Watchdog(3600.0, 60.0, 1e9)
        scope = {"method": "GET", "path": "/v1/bodies/ceres/track"}
        out["service/guards.py: Watchdog enter + leave (under gunicorn), with its RSS read"] = med_us(
            lambda: wd.leave(wd.enter(scope)))
        out["service/guards.py: resident_mb() alone (/proc/self/statm)"] = med_us(guards.resident_mb)
    with contextlib.suppress(Exception):
        from service import guards
        out["service/guards.py: peak_resident_mb() alone (getrusage)"] = med_us(guards.peak_resident_mb)
    with contextlib.suppress(Exception):
        from starlette.requests import Request

        from service import problems
        scope = {"type": "http", "method": "GET", "path": "/v1/bodies/ceres/track", "headers": [],
                 "query_string": QUERY.encode()}
        def run_dependency():
            # a coroutine since issue 39 (no thread-pool hop), a plain function before: run it to its end either way
            result = problems.single_query_values(Request(scope))
            if inspect.iscoroutine(result):
                with contextlib.suppress(StopIteration):
                    result.send(None)

        out["service/problems.py: single_query_values(request), called directly"] = med_us(run_dependency)
    with contextlib.suppress(Exception):
        from service.app import finite_json
        out["service/app.py: finite_json(answer) (finiteness walk + orjson)"] = med_us(
            lambda: finite_json(dict(answer)))
        import orjson
        out["orjson.dumps(answer) alone"] = med_us(lambda: orjson.dumps(answer, option=orjson.OPT_SERIALIZE_NUMPY))
    return out


#: the layers of a request, each the cumulative time of one function (path suffix, name) in the profile
_LAYER_FUNCS = {
    "app": ("fastapi/applications.py", "__call__"),
    "client": ("httpx/_client.py", "get"),
    "guards": ("service/guards.py", "__call__"),
    "limits": ("service/limits.py", "__call__"),
    "exceptions_mw": ("starlette/middleware/exceptions.py", "__call__"),
    "router": ("starlette/routing.py", "__call__"),
    "solve": ("fastapi/dependencies/utils.py", "solve_dependencies"),
    "params": ("fastapi/dependencies/utils.py", "request_params_to_args"),
    "sqv": ("service/problems.py", "single_query_values"),
    "one_pass": ("service/fast_routes.py", "handler"),
    "hop": ("anyio/_backends/_asyncio.py", "run_sync_in_worker_thread"),
    "endpoint": ("service/app.py", "track"),
    "finite_json": ("service/app.py", "finite_json"),
    "all_finite": ("service/app.py", "_all_finite"),
    "orjson": ("~", "<built-in method orjson.dumps>"),
    "serialize": ("fastapi/routing.py", "serialize_response"),
}


def _layers(stats, reps: int) -> list[tuple[str, float]]:
    cum: dict[str, float] = {}
    for (filename, _line, name), (_cc, _nc, _tt, ct, _callers) in stats.stats.items():
        for key, (suffix, fname) in _LAYER_FUNCS.items():
            if name == fname and filename.replace("\\", "/").endswith(suffix):
                cum[key] = cum.get(key, 0.0) + ct
    ms = {k: v * 1e3 / reps for k, v in cum.items()}
    g = ms.get

    def diff(a, b):
        return None if g(a) is None or g(b) is None else max(0.0, g(a) - g(b))
    rows = [
        ("the whole app (FastAPI.__call__, on the event loop)", g("app")),
        ("… middleware outside service/guards.py (Starlette's, FastAPI's, the service's added after it)",
         diff("app", "guards")),
        ("… service/guards.py RequestBudget (its own time)", diff("guards", "limits")),
        ("… service/limits.py BodySizeLimit (its own time)", diff("limits", "exceptions_mw")),
        ("… routing (Starlette's router, route matching)", g("router")),
        ("… FastAPI's solve_dependencies (query parsing and validation, the dependency)", g("solve")),
        ("… … request_params_to_args (the route's query parameters validated)", g("params")),
        ("… the route served in one pass (service/fast_routes.py: its parameters, the dependency, the route)",
         g("one_pass")),
        ("… … the parameters and the dependency (one pass)", diff("one_pass", "endpoint")),
        ("… … service/problems.py single_query_values", g("sqv")),
        ("… thread-pool hops, event-loop side", g("hop")),
        ("… the route's body with the answer precomputed (service/app.py track; on the event loop when cheap)",
         g("endpoint")),
        ("… … finite_json: the finiteness walk + orjson", g("finite_json")),
        ("… … … _all_finite (the finiteness walk)", g("all_finite")),
        ("… … … orjson.dumps", g("orjson")),
        ("the test client (httpx, outside the app)", diff("client", "app")),
    ]
    return [(label, v) for label, v in rows if v is not None]


# ----------------------------------------------------------------------------- parent: trees and children

@contextlib.contextmanager
def before_tree(commit: str):
    """``git worktree add`` of ``commit`` into a temporary directory, removed (and pruned) at the end."""
    tmp = Path(tempfile.mkdtemp(prefix="ephem_overhead_"))
    tree = tmp / "before"
    subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--detach", "--quiet", str(tree), commit], check=True)
    try:
        yield tree
    finally:
        subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force", str(tree)], check=False)
        subprocess.run(["git", "-C", str(ROOT), "worktree", "prune"], check=False)
        shutil.rmtree(tmp, ignore_errors=True)


def child_env(tree: Path, **extra: str) -> dict:
    from machine import tree_env
    env = tree_env(tree)
    for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
        env.setdefault(var, "1")      # one BLAS thread, as each gunicorn worker has
    env.update(extra)
    return env


def run_child(tree: Path, mode: str, n: int, **extra_env: str) -> dict:
    cmd = [sys.executable, str(Path(__file__).resolve()), "--child", mode, "--child-n", str(n)]
    p = subprocess.run(cmd, cwd=tree, env=child_env(tree, **extra_env), capture_output=True, text=True,
                       timeout=CHILD_TIMEOUT_S)
    if p.returncode != 0:
        raise SystemExit(f"child {mode} in {tree} failed ({p.returncode}):\n{p.stderr[-4000:]}")
    out = json.loads(p.stdout.strip().splitlines()[-1])
    for what, path in out["where"].items():
        if not Path(path).is_relative_to(tree.resolve()):
            raise SystemExit(f"child {mode} of {tree} imported {what} from {path}, not from the tree")
    return out


# ----------------------------------------------------------------------------- parent: the HTTP server

def _gunicorn() -> str:
    for cand in (ROOT / ".venv" / "bin" / "gunicorn", Path(sys.executable).parent / "gunicorn"):
        if cand.exists():
            return str(cand)
    found = shutil.which("gunicorn")
    if not found:
        raise SystemExit("gunicorn not found in the venv (make venv)")
    return found


def _proc_stat(pid: int) -> list[str] | None:
    try:
        return Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    except OSError:
        return None


def worker_pids(master: int) -> list[int]:
    """The master's children (the workers), from /proc."""
    pids = []
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            fields = _proc_stat(int(entry))
            if fields and int(fields[1]) == master:
                pids.append(int(entry))
    return pids


def cpu_s(pids: list[int]) -> float:
    """utime + stime of the processes (all their threads), seconds."""
    total = 0
    for pid in pids:
        fields = _proc_stat(pid)
        if fields:
            total += int(fields[11]) + int(fields[12])
    return total / os.sysconf("SC_CLK_TCK")


@contextlib.contextmanager
def gunicorn_server(tree: Path, workers: int):
    """The tree's service as ``make serve`` runs it, on a free loopback port; always terminated."""
    import bench_service as bs

    port = bs.free_port()
    cmd = [_gunicorn(), "--config", "service/gunicorn_conf.py", "--bind", f"127.0.0.1:{port}",
           "--workers", str(workers), "service.app:app"]
    with tempfile.TemporaryFile() as log:
        proc = subprocess.Popen(cmd, cwd=tree, env=child_env(tree), stdout=log, stderr=subprocess.STDOUT,
                                start_new_session=True)
        try:
            base = f"http://127.0.0.1:{port}"
            bs._wait_healthy(proc, log, base)
            # /healthz answered by one worker: wait until every worker has run its start-up (warm-up included)
            deadline = time.monotonic() + SERVER_START_TIMEOUT_S
            while True:
                log.seek(0)
                if log.read().count(b"Application startup complete") >= workers:
                    break
                if time.monotonic() > deadline or proc.poll() is not None:
                    log.seek(0)
                    raise SystemExit(f"gunicorn workers did not start:\n{log.read()[-4000:].decode(errors='replace')}")
                time.sleep(0.2)
            pids = worker_pids(proc.pid)
            if len(pids) != workers:
                raise SystemExit(f"gunicorn has {len(pids)} workers, expected {workers}")
            yield base, pids, " ".join(["gunicorn", *cmd[1:]])
        finally:
            bs.stop_server(proc, 30)


def http_run(tree: Path, kind: str, connections: int, duration: float, warm_s: float) -> dict:
    """One server run of a tree: every URL warmed, then loaded in turn; req/s and the workers' CPU per request."""
    import urllib.request

    import bench_service as bs

    rows = {}
    with gunicorn_server(tree, 2) as (base, pids, command):
        with urllib.request.urlopen(base + URLS[2][2], timeout=30) as r:    # what the answers carry
            headers = {k.lower(): v for k, v in r.headers.items()}
            epochs = len(json.loads(r.read())["jd_tdb"])
        if epochs != TRACK_EPOCHS:
            raise SystemExit(f"{tree}: the track has {epochs} epochs, expected {TRACK_EPOCHS}")
        for _key, _label, path in URLS:
            bs.load(kind, base + path, connections, warm_s)
        loads = [(key, lambda p=path: bs.load(kind, base + p, connections, duration)) for key, _l, path in URLS]
        if kind == "wrk":
            loads += [(key, lambda p=path: bs.run_wrk(base + p, connections, duration, lua=_NEW_QUESTION_LUA.replace(
                "PATH", p).replace("JD0", repr(NEW_QUESTION_JD0)))) for key, _l, path in NEW_QUESTION]
        for key, run in loads:
            c0 = cpu_s(pids)
            res = run()
            cpu = cpu_s(pids) - c0
            res.pop("raw", None)
            res["worker_cpu_ms_per_request"] = cpu * 1e3 / res["requests"] if res["requests"] else float("nan")
            rows[key] = res
    return {"rows": rows, "server": command, "etag": "etag" in headers,
            "cache_control": headers.get("cache-control")}


# ----------------------------------------------------------------------------- parent: report

def _med(xs) -> float:
    xs = [x for x in xs if x is not None and x == x]
    return statistics.median(xs) if xs else float("nan")


def _f(x: float, digits: int = 2) -> str:
    return "—" if x is None or x != x else f"{x:,.{digits}f}"


def _met(ok: bool | None) -> str:
    return "—" if ok is None else ("**met**" if ok else "**not met**")


def report(info: list[str], meta: dict, http: dict, cpu: dict, asgi: dict, floor: dict | None, args) -> str:
    L = ["# Overhead near the framework's floor (`benchmarks/bench_overhead.py`, issue 39 part 3)", ""]
    L += [f"- {line}" for line in info]
    L += [f"- before: `{meta['before']}` (a `git worktree` of it); after: the working tree at `{meta['after']}`"
          f"{meta['dirty']}",
          f"- command: `{meta['command']}`; {meta['elapsed_s']:.0f} s in all", ""]
    L += ["How to reproduce: `make bench-overhead` (or `.venv/bin/python benchmarks/bench_overhead.py`; `--quick` for",
          "a smoke run, `--before COMMIT` for another baseline). Every number below comes from this one run; the "
          "trees alternate (before, after, before, after), medians over the rounds.", ""]

    if http:
        runs = http["runs"]
        L += [f"## 1. HTTP throughput: gunicorn, 2 uvicorn workers, {args.connections} keep-alive connections, "
              f"{args.duration:g} s a request", ""]
        L += [f"Server: `{runs['after'][0]['server']}`, started in each tree's directory. Load: "
              f"`{runs['after'][0]['rows']['healthz']['tool']}` (no `If-None-Match`), on the same "
              f"{os.cpu_count()} cores as the workers. {args.rounds} server runs per tree. The issue's "
              f"measurement before the work: {ISSUE_BEFORE}.", ""]
        L += ["| request | req/s before | req/s after | after ÷ before | % of /healthz before | % of /healthz after "
              "| worker CPU ms/request before | after | /healthz's CPU ÷ this, before | after | goal | met (after) |",
              "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---|"]
        measured = [row for row in URLS + NEW_QUESTION if all(row[0] in r["rows"] for t in runs for r in runs[t])]
        for key, label, _path in measured:
            rps = {t: _med(r["rows"][key]["rps"] for r in runs[t]) for t in runs}
            pct = {t: _med(100 * r["rows"][key]["rps"] / r["rows"]["healthz"]["rps"] for r in runs[t]) for t in runs}
            cpu_ms = {t: _med(r["rows"][key]["worker_cpu_ms_per_request"] for r in runs[t]) for t in runs}
            by_cpu = {t: _med(100 * r["rows"]["healthz"]["worker_cpu_ms_per_request"]
                              / r["rows"][key]["worker_cpu_ms_per_request"] for r in runs[t]) for t in runs}
            goal = HTTP_GOALS_PCT.get(key)
            L.append(f"| {label} | {_f(rps['before'], 0)} | {_f(rps['after'], 0)} | {_f(rps['after'] / rps['before'])}"
                     f" | {_f(pct['before'], 1)} % | {_f(pct['after'], 1)} % | {_f(cpu_ms['before'], 3)} | "
                     f"{_f(cpu_ms['after'], 3)} | {_f(by_cpu['before'], 1)} % | {_f(by_cpu['after'], 1)} % | "
                     f"{'≥ %g %% of /healthz' % goal if goal else '—'} | "
                     f"{_met(pct['after'] >= goal) if goal else '—'} |")
        L += ["", "Each server run (req/s, p50 / p99 latency ms, errors = non-2xx/3xx + socket errors):", "",
              "| tree | round | " + " | ".join(k for k, _l, _p in measured) + " |",
              "|---|---:|" + "---|" * len(measured)]
        for i in range(args.rounds):
            for t in ("before", "after"):
                r = runs[t][i]["rows"]
                L.append(f"| {t} | {i + 1} | " + " | ".join(
                    f"{_f(r[k]['rps'], 0)} ({_f(r[k]['p50'], 1)} / {_f(r[k]['p99'], 1)}; {r[k]['errors']})"
                    for k, _l, _p in measured) + " |")
        etag = {t: any(r["etag"] for r in runs[t]) for t in runs}
        L += ["", "The track answer carries an ETag: " + ", ".join(f"{t} {'yes' if etag[t] else 'no'}" for t in etag)
              + " (measured as computed 200s either way: the load generator sends no `If-None-Match`). Worker CPU "
              "is the utime + stime of both workers over the load, from /proc (10 ms ticks), per request answered; "
              "it includes HTTP parsing, the access log line and the framework, not the load generator. /healthz's "
              "CPU ÷ a request's is what its % of /healthz would be if the workers alone used the cores: it moves "
              "less than req/s when other work shares the machine. The goals are judged on req/s, as the issue "
              "states them. The rows \"a new question each request\" (wrk only) move each request's start by "
              "its own 1e-8 d, so that nothing the service keeps for an identical question answers them: what a "
              "stream of different small tracks costs.", ""]

    if cpu:
        L += ["## 2. In-process warm CPU per call (`time.process_time`, median)", ""]
        L += ["| call | n per tree | before ms | after ms | before ÷ after | goal | met (after) |",
              "|---|---:|---:|---:|---:|---|---|"]
        for key, label in CPU_ROWS:
            b, a = (_median_ms(cpu[t][key]) for t in ("before", "after"))
            goal = CPU_GOAL_MS.get(key)
            L.append(f"| `{label}` | {len(cpu['after'][key])} | {_f(b, 3)} | {_f(a, 3)} | {_f(b / a)} | "
                     f"{'≤ %g ms' % goal if goal else '—'} | {_met(a <= goal) if goal else '—'} |")
        L.append("")

    if asgi:
        L += ["## 3. The page's track view against its API answer plus the models chart (in-process, warm medians "
              "of the process's CPU time, every thread, and of the wall time; the three requests interleaved)", ""]
        L += ["| request | before CPU ms | after CPU ms | before wall ms | after wall ms |", "|---|---:|---:|---:|---:|"]
        names = {"page": "the page", "api": "the API's track", "chart": "the models chart"}
        meds = {t: {k: _median_ms(v) for k, v in asgi[t]["samples"].items()} for t in asgi}
        cpus = {t: {k: _median_ms(v) for k, v in asgi[t].get("cpu", {}).items() if v} for t in asgi}
        for key in ("page", "api", "chart"):
            cells = []
            for table in (cpus, meds):
                for t in ("before", "after"):
                    url = asgi[t]["urls"].get(key)
                    st = asgi[t]["status"].get(url) if url else None
                    cells.append(_f(table[t][key], 2) if key in table[t] else f"missing (HTTP {st})" if st
                                 else "missing")
            url = asgi["after"]["urls"].get(key) or asgi["before"]["urls"].get(key)
            L.append(f"| {names[key]}: `GET {url}` | {' | '.join(cells)} |")
        ratio, alone = [], []
        for table in (cpus, meds):
            for t in ("before", "after"):
                m = table[t]
                ratio.append(_f(m["page"] / (m["api"] + m["chart"])) if {"page", "api", "chart"} <= m.keys()
                             else "— (no chart route)" if "chart" not in m else "—")
                alone.append(_f(m["page"] / m["api"]) if {"page", "api"} <= m.keys() else "—")
        n = {t: ", ".join(f"{k} {len(v)}" for k, v in asgi[t]["samples"].items()) for t in ("before", "after")}
        L += [f"| **page ÷ (API + chart)** | {' | '.join(ratio)} |",
              f"| page ÷ API alone | {' | '.join(alone)} |", "",
              f"Samples: before {n['before']}; after {n['after']} (each child samples for at most "
              f"{CHILD_BUDGET_S:g} s).",
              ""]

    if floor:
        w, c = floor["wall_ms"], floor["cpu_ms"]
        L += ["## 4. The framework's floor for the track route (after tree, in-process)", ""]
        L += ["Medians per request: wall time, and the process's CPU time (event loop and worker threads; it does "
              "not count the waits for a core on a busy machine).", "",
              "| what | wall ms | CPU ms |", "|---|---:|---:|"]
        rows = [("bare", "a bare ASGI app (the test client's own cost)"), ("healthz", "`GET /healthz`"),
                ("track_stub", "the 37-epoch track route, `api.track_arrays` replaced by its precomputed answer"
                 + ("" if floor["stub_used"] else " (**the route no longer calls it: not a floor**)")),
                ("track", "the 37-epoch track route as served (alternating with the row above)")]
        L += [f"| {label} | {_f(w[k], 3)} | {_f(c[k], 3)} |" for k, label in rows]
        L.append("")
        L += ["Pieces timed alone (µs, median):", "", "| piece | µs |", "|---|---:|"]
        L += [f"| {k} | {_f(v, 1)} |" for k, v in floor["pieces_us"].items()]
        L += ["", f"cProfile of the stubbed track route ({floor['profiled_ms']:.2f} ms a request under the profiler, "
              f"{c['track_stub']:.2f} ms of CPU without; the profiler inflates Python-heavy layers most, so read the "
              "shares, not the absolute ms): cumulative CPU ms per request of each layer (each thread's own CPU clock, "
              "so waits for the GIL or a thread count nowhere).", "",
              "| layer | CPU ms/request (profiled) | share of the app |", "|---|---:|---:|"]
        app_ms = dict(floor["layers"]).get("the whole app (FastAPI.__call__, on the event loop)")
        for label, v in floor["layers"]:
            share = f"{100 * v / app_ms:.0f} %" if app_ms and not label.startswith("the test client") else "—"
            L.append(f"| {label} | {v:.3f} | {share} |")
        L += [""] + _floor_reading(floor, cpu) + [""]
    return "\n".join(L).rstrip() + "\n"


def _floor_reading(floor: dict, cpu: dict) -> list[str]:
    """What section 4's numbers say, in words (only what they show)."""
    c, p = floor["cpu_ms"], floor["pieces_us"]
    hop = p.get("thread-pool hop (anyio.to_thread.run_sync of a no-op)")
    fj = p.get("service/app.py: finite_json(answer) (finiteness walk + orjson)")
    oj = p.get("orjson.dumps(answer) alone")
    out = [f"Reading: in-process, the app's own CPU for the track route (the science stubbed, less the test client) is "
           f"{c['track_stub'] - c['bare']:.2f} ms against {c['healthz'] - c['bare']:.2f} ms for /healthz; the science "
           f"adds {c['track'] - c['track_stub']:.2f} ms"
           + (f" (the library call alone, section 2: {_median_ms(cpu['after']['hansen']):.2f} ms of CPU)."
              if cpu.get("after", {}).get("hansen") else ".")]
    if hop is not None:
        out.append(f"Each thread-pool hop costs ~{hop:.0f} µs of wall time: the track route makes two, one for the "
                   "sync route and one for the app-wide sync dependency `single_query_values` (every route pays the "
                   "latter; as an `async def` it would run on the event loop, as FastAPI runs async dependencies).")
    if fj is not None and oj is not None:
        out.append(f"`finite_json` takes {fj:.0f} µs, of which orjson {oj:.0f} µs: the rest is the recursive "
                   "finiteness walk over the answer's nested dicts and lists.")
    return out


# ----------------------------------------------------------------------------- main

def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--before", default=BEFORE, help=f"the baseline commit (default {BEFORE})")
    ap.add_argument("--duration", type=float, default=5.0, help="seconds of load per request and server run (5)")
    ap.add_argument("--warm", type=float, default=1.0, help="seconds of warm-up load per request (1)")
    ap.add_argument("--connections", type=int, default=50)
    ap.add_argument("--rounds", type=int, default=2, help="server runs per tree, alternating (2: A B A B)")
    ap.add_argument("--loadgen", choices=("auto", "wrk", "python"), default="auto")
    ap.add_argument("--cpu-n", type=int, default=100, help="samples per call and child (one child per tree and round)")
    ap.add_argument("--asgi-n", type=int, default=30, help="samples per URL and tree (split over the rounds)")
    ap.add_argument("--floor-n", type=int, default=400, help="samples of the floor's wall times")
    ap.add_argument("--no-http", action="store_true")
    ap.add_argument("--no-floor", action="store_true")
    ap.add_argument("--quick", action="store_true", help="smoke run: 2 s loads, 1 round, fewer samples")
    ap.add_argument("--output", type=Path, default=RESULTS)
    ap.add_argument("--child", choices=("cpu", "asgi", "floor"), help=argparse.SUPPRESS)
    ap.add_argument("--child-n", type=int, default=0, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)

    if args.child:
        fn = {"cpu": child_cpu, "asgi": child_asgi, "floor": child_floor}[args.child]
        print(json.dumps(fn(max(1, min(args.child_n, 100_000)))))
        return 0

    if args.quick:
        args.duration, args.warm, args.rounds, args.cpu_n, args.asgi_n, args.floor_n = 2.0, 0.5, 1, 40, 15, 300
    args.duration = max(1.0, min(args.duration, 60.0))
    args.rounds = max(1, min(args.rounds, 10))
    args.connections = max(1, min(args.connections, 256))
    t_start = time.monotonic()
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    from importlib.metadata import version

    from machine import machine_info

    versions = {}
    for name in ("fastapi", "starlette", "pydantic", "uvicorn", "uvicorn-worker", "gunicorn", "httpx", "orjson"):
        with contextlib.suppress(Exception):
            versions[name] = version(name)
    kind = {"auto": "wrk" if shutil.which("wrk") else "python", "wrk": "wrk", "python": "python"}[args.loadgen]
    if kind == "wrk":
        if not shutil.which("wrk"):
            raise SystemExit("wrk is not on PATH (apt-get install wrk), or use --loadgen python")
        p = subprocess.run(["wrk", "-v"], capture_output=True, text=True, check=False)
        versions["wrk"] = ((p.stdout or p.stderr).split() or ["?", "?"])[1]
    info = machine_info(**versions)
    print("\n".join(info), flush=True)
    after_rev = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"], capture_output=True,
                               text=True, check=True).stdout.strip()
    dirty = subprocess.run(["git", "-C", str(ROOT), "status", "--porcelain", "--untracked-files=no"],
                           capture_output=True, text=True, check=True).stdout.splitlines()
    meta = {"before": args.before, "after": after_rev,
            "dirty": f" with {len(dirty)} changed tracked files not yet committed" if dirty else "",
            "command": " ".join([".venv/bin/python benchmarks/bench_overhead.py",
                                 *(argv if argv is not None else sys.argv[1:])]).strip()}

    http: dict = {}
    cpu: dict = {"before": {}, "after": {}}
    asgi: dict = {}
    floor = None
    with before_tree(args.before) as before:
        trees = {"before": before, "after": ROOT}
        if not args.no_http:
            runs: dict = {"before": [], "after": []}
            for i in range(args.rounds):
                for t, tree in trees.items():
                    print(f"HTTP round {i + 1}/{args.rounds}: {t} ({kind}) ... [{time.monotonic() - t_start:.0f} s]",
                          flush=True)
                    r = http_run(tree, kind, args.connections, args.duration, args.warm)
                    print("   " + ", ".join(f"{k} {v['rps']:,.0f} req/s" for k, v in r["rows"].items()), flush=True)
                    runs[t].append(r)
            http = {"runs": runs}
        for i in range(args.rounds):
            for t, tree in trees.items():
                print(f"in-process CPU, round {i + 1}: {t} ... [{time.monotonic() - t_start:.0f} s]", flush=True)
                out = run_child(tree, "cpu", max(1, args.cpu_n // args.rounds))
                for k, v in out["samples"].items():
                    cpu[t].setdefault(k, []).extend(v)
        for i in range(args.rounds):
            for t, tree in trees.items():
                print(f"in-process page / API / chart, round {i + 1}: {t} ... [{time.monotonic() - t_start:.0f} s]",
                      flush=True)
                out = run_child(tree, "asgi", max(1, args.asgi_n // args.rounds), EPHEM_WARM_UP="0")
                prev = asgi.setdefault(t, {"samples": {}, "cpu": {}, "urls": out["urls"], "status": out["status"]})
                for k, v in out["samples"].items():
                    prev["samples"].setdefault(k, []).extend(v)
                for k, v in out.get("cpu", {}).items():
                    prev["cpu"].setdefault(k, []).extend(v)
        if not args.no_floor:
            print(f"the framework's floor (after tree) ... [{time.monotonic() - t_start:.0f} s]", flush=True)
            floor = run_child(ROOT, "floor", args.floor_n, EPHEM_WARM_UP="0")
    meta["elapsed_s"] = time.monotonic() - t_start
    text = report(info, meta, http, cpu, asgi, floor, args)
    print()
    print(text)
    args.output.write_text(text, encoding="utf-8")
    print(f"written to {args.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
