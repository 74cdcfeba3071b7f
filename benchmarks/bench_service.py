"""Benchmark: the HTTP service, in-process and over loopback.

Targets (issue):
- ``GET /v1/bodies/vesta/precession``: p50 under 2 ms in-process;
- a 10^4-epoch ``GET /v1/bodies/vesta/track`` in JSON: under 50 ms in-process (p50);
- at least 1000 requests/s for /precession over loopback with ``uvicorn --workers 2``.

In-process: the ASGI app is driven with ``httpx.AsyncClient(transport=httpx.ASGITransport(app=app))``
after its lifespan has run (no network), sequential requests after a warm-up.

Loopback: ``uvicorn service.app:app --host 127.0.0.1 --port <free> --workers 2`` in a subprocess
(always terminated), loaded by ``wrk`` when it is on PATH, else by a Python load generator
(worker processes, each an asyncio loop with one keep-alive ``httpx.AsyncClient``). Either way
the load generator runs on the same machine and competes with the server for the same cores.
A ``--workers 1`` run is a control (see RESULTS_service.md). Every loop is bounded in count and time.

Run: ``make bench-service`` (or ``.venv/bin/python benchmarks/bench_service.py``); options:
``--loadgen auto|wrk|python|all``, ``--duration S``, ``--connections N``, ``--quick``, ``--profile``.
Writes the table to ``benchmarks/RESULTS_service.md``.
"""
from __future__ import annotations

import argparse
import asyncio
import contextlib
import cProfile
import datetime as dt
import io
import math
import multiprocessing as mp
import os
import platform
import pstats
import re
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
import urllib.request
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
RESULTS = ROOT / "benchmarks" / "RESULTS_service.md"

PRECESSION = "/v1/bodies/vesta/precession"
TRACK = "/v1/bodies/vesta/track?start=2451545.0&stop=2461544.0&step_days=1"
TRACK_EPOCHS = 10_000

PRECESSION_P50_TARGET_MS = 2.0
TRACK_TARGET_MS = 50.0
LOOPBACK_RPS_TARGET = 1000.0

# hard bounds: every loop stops at whichever comes first
IN_PROCESS_BUDGET_S = 120.0
REQUEST_TIMEOUT_S = 30.0
SERVER_START_TIMEOUT_S = 60.0
MAX_LOOPBACK_REQUESTS = 200_000


# ----------------------------------------------------------------------------- helpers

def percentile(values: list[float], q: float) -> float:
    """Linear-interpolated percentile (as numpy's default) of a non-empty list."""
    xs = sorted(values)
    if not xs:
        return math.nan
    pos = (len(xs) - 1) * q / 100.0
    lo, hi = math.floor(pos), math.ceil(pos)
    return xs[lo] + (xs[hi] - xs[lo]) * (pos - lo)


def machine_info() -> dict:
    model = "unknown"
    with contextlib.suppress(OSError):
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    try:
        nproc = subprocess.run(["nproc"], check=False, capture_output=True, text=True, timeout=10).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        nproc = str(len(os.sched_getaffinity(0)))
    versions = {}
    for name in ("fastapi", "starlette", "uvicorn", "httpx", "numpy", "pydantic"):
        with contextlib.suppress(Exception):
            from importlib.metadata import version
            versions[name] = version(name)
    return {"nproc": nproc, "cpu": model, "python": platform.python_version(),
            "platform": platform.platform(), "kernel": platform.release(), "loadavg": os.getloadavg(),
            "date": dt.datetime.now(dt.UTC).strftime("%Y-%m-%d %H:%M UTC"), "versions": versions}


def fmt_ms(x: float | None) -> str:
    return "—" if x is None or (isinstance(x, float) and math.isnan(x)) else f"{x:.2f}"


def fmt_rps(x: float | None) -> str:
    return "—" if x is None else f"{x:,.0f}"


# ----------------------------------------------------------------------------- in-process

async def _in_process(n_precession: int, n_track: int, profile: bool) -> dict:
    import httpx

    from service.app import app

    out: dict = {}
    deadline = time.monotonic() + IN_PROCESS_BUDGET_S
    async with app.router.lifespan_context(app):
        transport = httpx.ASGITransport(app=app)
        async with httpx.AsyncClient(transport=transport, base_url="http://bench", timeout=REQUEST_TIMEOUT_S) as c:
            # check the answers once
            r = await c.get(PRECESSION)
            r.raise_for_status()
            r = await c.get(TRACK)
            r.raise_for_status()
            body = r.json()
            if len(body["jd_tdb"]) != TRACK_EPOCHS:
                raise SystemExit(f"track returned {len(body['jd_tdb'])} epochs, expected {TRACK_EPOCHS}")
            out["track_bytes"] = len(r.content)

            for name, path, n, warm in (("precession", PRECESSION, n_precession, 200),
                                        ("track", TRACK, n_track, 10)):
                for _ in range(warm):
                    (await c.get(path)).raise_for_status()
                lat = []
                for _ in range(n):
                    if time.monotonic() > deadline:
                        break
                    t0 = time.perf_counter()
                    resp = await c.get(path)
                    lat.append(time.perf_counter() - t0)
                    if resp.status_code != 200:
                        raise SystemExit(f"{path}: HTTP {resp.status_code}")
                out[name] = [x * 1e3 for x in lat]

            if profile:
                out["profile"] = await _profile_requests(c)
    return out


async def _profile_requests(c) -> dict:
    """cProfile of requests, on the event loop and in the threadpool where FastAPI runs sync routes."""
    import fastapi.routing

    worker_prof = cProfile.Profile()
    original = fastapi.routing.run_in_threadpool

    async def profiled_run_in_threadpool(func, *args, **kwargs):
        def wrapped(*a, **k):
            worker_prof.enable()
            try:
                return func(*a, **k)
            finally:
                worker_prof.disable()
        return await original(wrapped, *args, **kwargs)

    reports = {}
    fastapi.routing.run_in_threadpool = profiled_run_in_threadpool
    try:
        for name, path, n in (("precession", PRECESSION, 500), ("track", TRACK, 20)):
            worker_prof = cProfile.Profile()
            loop_prof = cProfile.Profile()
            t0 = time.perf_counter()
            loop_prof.enable()
            for _ in range(n):
                (await c.get(path)).raise_for_status()
            loop_prof.disable()
            wall = time.perf_counter() - t0
            buf = io.StringIO()
            stats = pstats.Stats(loop_prof, stream=buf)
            stats.add(worker_prof)
            stats.strip_dirs().sort_stats("tottime").print_stats(15)
            reports[name] = {"n": n, "wall_ms_per_request": wall * 1e3 / n, "text": _trim_pstats(buf.getvalue())}
    finally:
        fastapi.routing.run_in_threadpool = original
    return reports


def _trim_pstats(text: str) -> str:
    lines = text.splitlines()
    for i, line in enumerate(lines):
        if line.strip().startswith("ncalls"):
            return "\n".join(lines[i:]).rstrip()
    return text.rstrip()


def track_breakdown(n: int = 20) -> list[tuple[str, float]]:
    """Median time of each stage of the /track route, called directly (no ASGI)."""
    from fastapi.responses import JSONResponse

    from ephem import api

    def med(fn) -> float:
        ts = []
        for _ in range(n):
            t0 = time.perf_counter()
            fn()
            ts.append(time.perf_counter() - t0)
        return percentile(ts, 50) * 1e3

    arrays = api.track_arrays("vesta", "2451545.0", "2461544.0", 1.0)

    def tolist():
        d = dict(arrays)
        for k in api.TRACK_KEYS:
            d[k] = d[k].tolist()
        return d

    lists = tolist()
    return [
        ("api.track_arrays (model + 10^4 epochs, numpy)", med(lambda: api.track_arrays("vesta", "2451545.0",
                                                                                         "2461544.0", 1.0))),
        ("ndarray.tolist() of the 7 columns", med(tolist)),
        ("JSONResponse(...) = json.dumps + encode", med(lambda: JSONResponse(lists))),
    ]


# ----------------------------------------------------------------------------- loopback server

def free_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def uvicorn_command(port: int, workers: int, extra: list[str]) -> list[str]:
    # the same command line as the Dockerfile's CMD, bar the host and port
    return [sys.executable, "-m", "uvicorn", "service.app:app", "--host", "127.0.0.1", "--port", str(port),
            "--workers", str(workers), *extra]


@contextlib.contextmanager
def running_server(workers: int, extra: list[str]):
    port = free_port()
    cmd = uvicorn_command(port, workers, extra)
    with tempfile.TemporaryFile() as log:
        proc = subprocess.Popen(cmd, cwd=ROOT, stdout=log, stderr=subprocess.STDOUT, start_new_session=True)
        try:
            _wait_healthy(proc, log, f"http://127.0.0.1:{port}")
            yield f"http://127.0.0.1:{port}", " ".join(["python", *cmd[1:]])
        finally:
            stop_server(proc, 15)


def stop_server(proc: subprocess.Popen, timeout: float) -> None:
    """SIGTERM to a server's supervisor (it stops its workers), SIGKILL to its own process group if it hangs past
    ``timeout`` seconds, and to any stray worker of that group after."""
    proc.terminate()
    try:
        proc.wait(timeout=timeout)
    except subprocess.TimeoutExpired:
        with contextlib.suppress(ProcessLookupError):
            os.killpg(proc.pid, signal.SIGKILL)
        proc.wait(timeout=10)
    with contextlib.suppress(ProcessLookupError):  # stray workers, if any: only this server's group
        os.killpg(proc.pid, signal.SIGKILL)


def _wait_healthy(proc: subprocess.Popen, log, base: str) -> None:
    deadline = time.monotonic() + SERVER_START_TIMEOUT_S
    while True:
        if proc.poll() is not None:
            log.seek(0)
            raise SystemExit(f"uvicorn exited with {proc.returncode}:\n{log.read().decode(errors='replace')}")
        try:
            with urllib.request.urlopen(base + "/healthz", timeout=2) as r:
                if r.status == 200:
                    return
        except OSError:
            pass
        if time.monotonic() > deadline:
            raise SystemExit(f"uvicorn did not answer /healthz within {SERVER_START_TIMEOUT_S} s")
        time.sleep(0.2)


# ----------------------------------------------------------------------------- load: wrk

_UNITS = {"us": 1e-3, "ms": 1.0, "s": 1e3, "m": 60e3}
_WRK_STOP = """
-- safety bound on the request count per thread (wrk stops the thread; the run still lasts -d)
local counter = 0
local limit = {limit}
function response(status, headers, body)
  counter = counter + 1
  if counter >= limit then wrk.thread:stop() end
end
"""


def _wrk_ms(text: str) -> float:
    m = re.fullmatch(r"([\d.]+)(us|ms|s|m)", text.strip())
    return float(m.group(1)) * _UNITS[m.group(2)] if m else math.nan


def run_wrk(url: str, connections: int, duration: float, threads: int = 2, lua: str = "") -> dict:
    """Load ``url`` with wrk; ``lua``, when given, is added to its script (e.g. a ``request`` function that varies
    the query of each request: wrk's ``setup``, ``init`` and ``request`` hooks)."""
    threads = max(1, min(threads, connections))
    limit = max(1, MAX_LOOPBACK_REQUESTS // threads)
    with tempfile.NamedTemporaryFile("w", suffix=".lua", delete=False) as f:
        f.write(_WRK_STOP.format(limit=limit) + lua)
        script = f.name
    try:
        cmd = ["wrk", f"-t{threads}", f"-c{connections}", f"-d{max(1, round(duration))}s", "--latency",
               "--timeout", f"{int(REQUEST_TIMEOUT_S)}s", "-s", script, url]
        p = subprocess.run(cmd, check=False, capture_output=True, text=True, timeout=duration + 60)
    finally:
        os.unlink(script)
    out = p.stdout
    if p.returncode != 0:
        raise SystemExit(f"wrk failed ({p.returncode}): {p.stderr}\n{out}")
    res = {"tool": f"wrk -t{threads} -c{connections} -d{max(1, round(duration))}s --latency", "raw": out}
    res["rps"] = float(re.search(r"Requests/sec:\s+([\d.]+)", out).group(1))
    res["requests"] = int(re.search(r"(\d+) requests in", out).group(1))
    for q in ("50", "99"):
        m = re.search(rf"^\s+{q}%\s+(\S+)", out, re.MULTILINE)
        res[f"p{q}"] = _wrk_ms(m.group(1)) if m else math.nan
    m = re.search(r"Non-2xx or 3xx responses:\s+(\d+)", out)
    errors = int(m.group(1)) if m else 0
    m = re.search(r"Socket errors: connect (\d+), read (\d+), write (\d+), timeout (\d+)", out)
    if m:
        errors += sum(int(g) for g in m.groups())
    res["errors"] = errors
    res["capped"] = res["requests"] >= limit * threads
    return res


# ----------------------------------------------------------------------------- load: Python

def _py_worker(url: str, connections: int, t_start: float, t_stop: float, max_requests: int) -> dict:
    """One load-generator process: `connections` keep-alive connections, each sequential."""
    import httpx

    async def main() -> dict:
        lat: list[float] = []
        errors = 0
        done = 0
        last_end = t_start
        limits = httpx.Limits(max_connections=connections, max_keepalive_connections=connections)
        async with httpx.AsyncClient(limits=limits, timeout=REQUEST_TIMEOUT_S) as client:
            async def conn_loop():
                nonlocal errors, done, last_end
                while done < max_requests and time.monotonic() < t_stop:
                    done += 1
                    t0 = time.monotonic()
                    try:
                        r = await client.get(url)
                        ok = r.status_code == 200
                    except httpx.HTTPError:
                        ok = False
                    t1 = time.monotonic()
                    if ok:
                        lat.append((t1 - t0) * 1e3)
                    else:
                        errors += 1
                    last_end = max(last_end, t1)

            # open the connections before the clock starts
            await asyncio.gather(*(client.get(url) for _ in range(connections)))
            await asyncio.sleep(max(0.0, t_start - time.monotonic()))
            await asyncio.gather(*(conn_loop() for _ in range(connections)))
        return {"lat": lat, "errors": errors, "last_end": last_end}

    return asyncio.run(main())


def run_python_load(url: str, connections: int, duration: float, processes: int = 2) -> dict:
    processes = max(1, min(processes, connections))
    per = [connections // processes + (1 if i < connections % processes else 0) for i in range(processes)]
    ctx = mp.get_context("spawn")
    t_start = time.monotonic() + 3.0  # time for the processes to start and connect
    t_stop = t_start + duration
    with ctx.Pool(processes) as pool:
        jobs = [pool.apply_async(_py_worker, (url, c, t_start, t_stop, MAX_LOOPBACK_REQUESTS // processes))
                for c in per]
        results = [j.get(timeout=duration + 60) for j in jobs]
    lat = [x for r in results for x in r["lat"]]
    elapsed = max(r["last_end"] for r in results) - t_start
    return {"tool": f"Python: {processes} processes × asyncio + httpx.AsyncClient, {connections} connections, "
                    f"{duration:g} s",
            "rps": len(lat) / elapsed if elapsed > 0 else math.nan, "requests": len(lat),
            "p50": percentile(lat, 50), "p99": percentile(lat, 99),
            "errors": sum(r["errors"] for r in results),
            "capped": len(lat) >= MAX_LOOPBACK_REQUESTS}


def load(kind: str, url: str, connections: int, duration: float) -> dict:
    return run_wrk(url, connections, duration) if kind == "wrk" else run_python_load(url, connections, duration)


def loopback(kind: str, workers: int, connections: int, duration: float, extra: list[str],
             with_single_connection: bool) -> list[dict]:
    rows = []
    with running_server(workers, extra) as (base, cmd):
        load(kind, base + PRECESSION, connections, min(2.0, duration))  # warm up every worker
        load(kind, base + TRACK, min(connections, 4), min(2.0, duration))
        plan = [(PRECESSION, connections), (TRACK, connections)]
        if with_single_connection:
            plan += [(PRECESSION, 1), (TRACK, 1)]
        for path, conns in plan:
            r = load(kind, base + path, conns, duration)
            r.update(path=path, connections=conns, workers=workers, server=cmd)
            rows.append(r)
    return rows


# ----------------------------------------------------------------------------- report

def verdict(ok: bool | None) -> str:
    return "—" if ok is None else ("**met**" if ok else "**missed**")


def build_report(info: dict, inproc: dict, loop_rows: list[tuple[str, list[dict]]], args, breakdown,
                 command: str) -> str:
    lines = []
    lines.append("# Service benchmark (`benchmarks/bench_service.py`)")
    lines.append("")
    lines.append(f"- command: `{command}`")
    lines.append(f"- date: {info['date']}")
    lines.append(f"- machine: nproc = {info['nproc']}, CPU: {info['cpu']}, {info['platform']}")
    lines.append(f"- Python {info['python']}; " + ", ".join(f"{k} {v}" for k, v in info["versions"].items()))
    lines.append("")
    lines.append("## In-process (ASGI app driven by httpx.ASGITransport, no network, sequential)")
    lines.append("")
    lines.append("| request | n | p50 ms | p99 ms | target | met? |")
    lines.append("|---|---:|---:|---:|---|---|")
    p = inproc["precession"]
    t = inproc["track"]
    p50p, p99p = percentile(p, 50), percentile(p, 99)
    p50t, p99t = percentile(t, 50), percentile(t, 99)
    lines.append(f"| `GET {PRECESSION}` | {len(p)} | {fmt_ms(p50p)} | {fmt_ms(p99p)} | "
                 f"p50 < {PRECESSION_P50_TARGET_MS:g} ms | {verdict(p50p < PRECESSION_P50_TARGET_MS)} |")
    lines.append(f"| `GET /v1/bodies/vesta/track` 10^4 epochs, JSON ({inproc['track_bytes'] / 1e6:.2f} MB) "
                 f"| {len(t)} | {fmt_ms(p50t)} | {fmt_ms(p99t)} | p50 < {TRACK_TARGET_MS:g} ms | "
                 f"{verdict(p50t < TRACK_TARGET_MS)} (p99 {'<' if p99t < TRACK_TARGET_MS else '≥'} "
                 f"{TRACK_TARGET_MS:g} ms) |")
    lines.append("")
    lines.append(f"Track URL: `{TRACK}`.")
    lines.append("")
    if breakdown:
        lines.append("Where the /track time goes (each stage of the route called directly, median of 20):")
        lines.append("")
        lines.append("| stage | ms |")
        lines.append("|---|---:|")
        for name, ms in breakdown:
            lines.append(f"| {name} | {ms:.2f} |")
        lines.append("")
    for name, rep in (inproc.get("profile") or {}).items():
        lines.append(f"cProfile of {rep['n']} in-process `{name}` requests (event loop + threadpool, "
                     f"{rep['wall_ms_per_request']:.2f} ms/request under the profiler), top 15 by own time:")
        lines.append("")
        lines.append("```")
        lines.append(rep["text"])
        lines.append("```")
        lines.append("")
    for kind, rows in loop_rows:
        lines.append(f"## Loopback, load generator: {rows[0]['tool'].split(',')[0] if kind == 'python' else 'wrk'}")
        lines.append("")
        lines.append("The load generator runs on the same machine and competes with the uvicorn workers for the "
                     f"same {info['nproc']} cores; the numbers are a lower bound of what the server does alone.")
        lines.append("")
        lines.append("| server | request | load | requests | req/s | p50 ms | p99 ms | errors | target | met? |")
        lines.append("|---|---|---|---:|---:|---:|---:|---:|---|---|")
        for r in rows:
            target, ok = "", None
            if r["path"] == PRECESSION and r["workers"] == 2 and r["connections"] > 1:
                target, ok = f"≥ {LOOPBACK_RPS_TARGET:g} req/s", r["rps"] >= LOOPBACK_RPS_TARGET
            elif r["path"] == TRACK and r["connections"] == 1:
                target, ok = f"< {TRACK_TARGET_MS:g} ms (p50)", r["p50"] < TRACK_TARGET_MS
            what = "precession" if r["path"] == PRECESSION else "track 10^4"
            lines.append(f"| `--workers {r['workers']}`{' ' + ' '.join(args.uvicorn_arg) if args.uvicorn_arg else ''}"
                         f" | {what} | {r['connections']} conn{'s' if r['connections'] > 1 else ''} | "
                         f"{r['requests']}{' (capped)' if r.get('capped') else ''} | {fmt_rps(r['rps'])} | "
                         f"{fmt_ms(r['p50'])} | {fmt_ms(r['p99'])} | {r['errors']} | {target or '—'} | "
                         f"{verdict(ok)} |")
        lines.append("")
        lines.append(f"Load: `{rows[0]['tool']}` (per row: connections as listed). Server: "
                     f"`{rows[0]['server']}`.")
        lines.append("")
    lines += findings(inproc, loop_rows, breakdown)
    return "\n".join(lines).rstrip() + "\n"


def findings(inproc: dict, loop_rows: list[tuple[str, list[dict]]], breakdown) -> list[str]:
    """Plain-words reading of the numbers above (only what the numbers show)."""
    out = []
    p50_inproc = percentile(inproc["precession"], 50)
    for kind, rows in loop_rows:
        by = {(r["workers"], r["path"], r["connections"]): r for r in rows}
        single = by.get((2, PRECESSION, 1))
        two, one = [by.get((w, PRECESSION, max(r["connections"] for r in rows))) for w in (2, 1)]
        if single and single["p50"] > 30.0 and p50_inproc < 5.0:
            text = (f"- {kind}: with `--workers 2` one keep-alive connection waits {single['p50']:.1f} ms (p50) for "
                    f"a /precession the app answers in {p50_inproc:.2f} ms in-process: the ~40 ms of Nagle's "
                    "algorithm against the client's delayed ACK. uvicorn's multi-process supervisor binds the "
                    "listening socket itself with `proto=0`, so asyncio does not set TCP_NODELAY on the accepted "
                    "connections (uvicorn issue #3149, open); each connection then does at most ~23 requests/s.")
            if two and one:
                text += (f" The `--workers 1` control (asyncio creates the socket, TCP_NODELAY set) does "
                         f"{one['rps']:,.0f} req/s against {two['rps']:,.0f} with `--workers 2`.")
            out.append(text)
    p50_track = percentile(inproc["track"], 50)
    if breakdown:
        enc = breakdown[-1][1]
        out.append(f"- in-process /track: p50 {p50_track:.1f} ms, of which ~{enc:.0f} ms is `json.dumps` of the "
                   f"7 × {TRACK_EPOCHS:,} floats in `JSONResponse`; the numbers themselves take "
                   f"{breakdown[0][1]:.1f} ms and `.tolist()` {breakdown[1][1]:.1f} ms.")
    if out:
        out = ["## Findings", ""] + out + [""]
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--loadgen", choices=("auto", "wrk", "python", "all", "none"), default="auto",
                    help="auto: wrk if on PATH, else Python; all: both; none: in-process only")
    ap.add_argument("--duration", type=float, default=10.0, help="seconds per loopback measurement (default 10)")
    ap.add_argument("--connections", type=int, default=16, help="concurrent keep-alive connections (default 16)")
    ap.add_argument("--precession-requests", type=int, default=2000)
    ap.add_argument("--track-requests", type=int, default=100)
    ap.add_argument("--no-control", action="store_true", help="skip the --workers 1 control run")
    ap.add_argument("--profile", action="store_true", help="cProfile the in-process requests even if targets are met")
    ap.add_argument("--uvicorn-arg", action="append", default=[], help="extra uvicorn argument (repeatable)")
    ap.add_argument("--quick", action="store_true", help="short run (3 s, fewer requests) for a smoke test")
    ap.add_argument("--output", type=Path, default=RESULTS)
    args = ap.parse_args(argv)
    if args.quick:
        args.duration, args.precession_requests, args.track_requests = 3.0, 500, 20
    args.precession_requests = max(1, args.precession_requests)
    args.track_requests = max(1, args.track_requests)
    args.connections = max(1, min(args.connections, 256))
    args.duration = max(1.0, min(args.duration, 120.0))

    os.chdir(ROOT)
    sys.path.insert(0, str(ROOT))
    info = machine_info()
    print(f"machine: nproc={info['nproc']}  CPU: {info['cpu']}  Python {info['python']}  {info['date']}",
          flush=True)

    print("in-process ...", flush=True)
    inproc = asyncio.run(_in_process(args.precession_requests, args.track_requests, profile=False))
    missed = (percentile(inproc["precession"], 50) >= PRECESSION_P50_TARGET_MS
              or percentile(inproc["track"], 50) >= TRACK_TARGET_MS)
    breakdown = None
    if missed or args.profile:
        print("profiling (a target was missed or --profile) ...", flush=True)
        inproc["profile"] = asyncio.run(_in_process(1, 1, profile=True))["profile"]
        breakdown = track_breakdown()

    kinds = {"auto": ["wrk" if shutil.which("wrk") else "python"], "wrk": ["wrk"], "python": ["python"],
             "all": (["wrk"] if shutil.which("wrk") else []) + ["python"], "none": []}[args.loadgen]
    if "wrk" in kinds and not shutil.which("wrk"):
        raise SystemExit("wrk is not on PATH (apt-get install wrk), or use --loadgen python")
    loop_rows = []
    for kind in kinds:
        rows = []
        for workers in ([2] if args.no_control else [2, 1]):
            print(f"loopback: {kind}, uvicorn --workers {workers} ...", flush=True)
            rows += loopback(kind, workers, args.connections, args.duration, args.uvicorn_arg,
                             with_single_connection=(workers == 2))
        loop_rows.append((kind, rows))

    command = " ".join([".venv/bin/python benchmarks/bench_service.py", *(argv if argv is not None else sys.argv[1:])])
    report = build_report(info, inproc, loop_rows, args, breakdown, command.strip())
    print()
    print(report)
    args.output.write_text(report, encoding="utf-8")
    print(f"written to {args.output.relative_to(ROOT) if args.output.is_relative_to(ROOT) else args.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
