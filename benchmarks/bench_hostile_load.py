"""Load test: hostile requests beside normal traffic, against the service under gunicorn.

The script starts the service itself (``.venv/bin/gunicorn --config service/gunicorn_conf.py --bind
127.0.0.1:<free port> --workers 2 service.app:app``; ``--no-control-socket`` is added so that this
instance does not take over the per-user control socket of another gunicorn on the machine), waits for
``/healthz`` and for every worker's start-up, then runs:

0. a short warm-up of normal traffic (not counted: it fills each worker's memoised models), and one
   solo pass over the hostile requests (each sent once, alone: its status and its latency unloaded);
1. ``clean``: N normal clients (asyncio, one ``httpx.AsyncClient`` each, a new connection per request
   unless ``--keepalive``) looping over
   ``/v1/bodies/vesta/precession``, ``/v1/bodies/ceres/nutation``, a one-year Itokawa track, and the
   README's ``POST /v1/precession-nutation``;
2. ``mixed``: the same normal clients, plus M hostile clients (a separate process, so their client-side
   work does not sit in the normal clients' event loop) looping over the hostile requests below.

Throughout, the gunicorn master's children are sampled every 0.5 s (``/proc/<pid>/status`` VmRSS and
``/proc/<pid>/stat`` CPU time): each worker's largest RSS, and any worker that came or went (a restart,
with the reason gunicorn or the service logged). ``/proc/stat`` gives what the whole machine spent in each
phase, so the CPU taken by other users of the (shared) cores is reported too.

Verdict: the normal requests' p99 in the mixed phase within 2x of the clean phase's; no normal request
answered other than 2xx; no hostile request answered 5xx other than 503 ``busy`` (a large request
refused while another runs, with Retry-After: the designed answer); the workers' largest RSS below the
watchdog's recycle threshold (0.8 x ``EPHEM_WORKER_MEMORY_MB``).

Why a new connection per request: a keep-alive connection stays with the worker that accepted it, so
which worker each client landed on decided the phase's p99 (one worker with 6 of the 8 clients, the
other with 2): the clean phase's p99 ranged 42-110 ms between runs with the same code. New connections
are spread by the kernel over the workers, as a load balancer would.

Every request goes to 127.0.0.1; every loop is bounded in count and time; the server started here is
always stopped (SIGTERM, then SIGKILL of its process group). Writes ``benchmarks/RESULTS_load.md``.

Run: ``.venv/bin/python benchmarks/bench_hostile_load.py`` (about a minute with the defaults); options:
``--duration S`` (each phase), ``--clients N``, ``--hostile M``, ``--workers W``, ``--warmup S``,
``--exclude-hostile NAME,...`` (a diagnostic run without some hostile requests), ``--out FILE``,
``--no-write``, ``--keepalive``, ``--append TITLE`` (add the report to ``--out`` as a section instead of replacing it).
"""
from __future__ import annotations

import argparse
import asyncio
import collections
import contextlib
import copy
import datetime as dt
import json
import math
import multiprocessing as mp
import os
import re
import resource
import shlex
import signal
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))   # run from a checkout: the project's schema and the service benchmark's helpers
from benchmarks.bench_service import machine_info, percentile  # noqa: E402
from service.schemas import UserBody  # noqa: E402
RESULTS = ROOT / "benchmarks" / "RESULTS_load.md"
HOST = "127.0.0.1"

# hard bounds: every loop stops at whichever comes first
SERVER_START_TIMEOUT_S = 120.0
NORMAL_TIMEOUT_S = 30.0          # a normal request slower than this is an error
HOSTILE_TIMEOUT_S = 60.0         # past the service's deadline (20 s) plus its watchdog's grace (10 s)
MAX_REQUESTS_PER_CLIENT = 200_000
MAX_PHASE_S = 600.0
PHASE_END_GRACE_S = 35.0         # in-flight requests at a phase's end: waited for this long, then cancelled
SAMPLE_INTERVAL_S = 0.5

# the POST's documented example (the README's): one source, the schema
EXAMPLE_BODY = UserBody.model_config["json_schema_extra"]["examples"][0]
POST = "/v1/precession-nutation"

NORMAL = [  # (name, method, path, json body)
    ("precession", "GET", "/v1/bodies/vesta/precession", None),
    ("nutation", "GET", "/v1/bodies/ceres/nutation", None),
    ("track", "GET", "/v1/bodies/itokawa/track?start=2030-01-01&stop=2031-01-01&step_days=10", None),
    ("post", "POST", POST, EXAMPLE_BODY),
]


def _with(path: tuple, value) -> dict:
    body = copy.deepcopy(EXAMPLE_BODY)
    node = body
    for key in path[:-1]:
        node = node[key]
    node[path[-1]] = value
    return body


def hostile_requests(max_track_samples: int) -> list[tuple[str, str, str, dict | None, bytes | None]]:
    """(name, method, path, json body, raw body). The track 'at the cap' asks for exactly the largest
    number of epochs the service allows (EPHEM_MAX_TRACK_SAMPLES), the one 'over the cap' for one more."""
    start = 2451545.0
    at_cap = start + (max_track_samples - 1)           # step 1 day: max_track_samples epochs
    over_cap = start + max_track_samples               # one more
    big = b'{"name": "' + b"x" * (1 << 20) + b'"}'       # 1 MiB + a few bytes of JSON
    return [
        ("post a_au=1e-300", "POST", POST, _with(("orbit", "a_au"), 1e-300), None),
        ("post a_au=1e300", "POST", POST, _with(("orbit", "a_au"), 1e300), None),
        ("post e=0.99", "POST", POST, _with(("orbit", "e"), 0.99), None),
        ("post e=0.95", "POST", POST, _with(("orbit", "e"), 0.95), None),
        ("post moments 1e-300", "POST", POST, _with(("moments",), {"A": 1e-300, "B": 1e-300, "C": 2e-300}), None),
        ("post a_au=true", "POST", POST, _with(("orbit", "a_au"), True), None),
        ("free-motion numeric 10^4 d", "GET",
         "/v1/bodies/eros/free-motion?start=2451545&stop=2461545&step_days=10000&method=numeric", None, None),
        ("post track real_orbit 1900-2050", "POST", POST,
         _with(("track",), {"start": "1900-01-01", "stop": "2050-01-01", "step_days": 10, "model": "real_orbit"}),
         None),
        ("track real_orbit 1900-2050", "GET",
         "/v1/bodies/itokawa/track?start=1900-01-01&stop=2050-01-01&step_days=100&model=real_orbit", None, None),
        ("track JD 9999999", "GET", "/v1/bodies/vesta/track?start=9999999&stop=9999999.9&step_days=1", None, None),
        (f"track at cap ({max_track_samples} epochs)", "GET",
         f"/v1/bodies/vesta/track?start={start:.0f}&stop={at_cap:.0f}&step_days=1", None, None),
        (f"track cap+1 ({max_track_samples + 1} epochs)", "GET",
         f"/v1/bodies/vesta/track?start={start:.0f}&stop={over_cap:.0f}&step_days=1", None, None),
        ("post 1 MiB body", "POST", POST, None, big),
    ]


# ----------------------------------------------------------------------------- helpers

def free_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind((HOST, 0))
        return s.getsockname()[1]


def children_of(pid: int) -> list[int]:
    """Direct children of ``pid`` (the gunicorn master's workers)."""
    path = Path(f"/proc/{pid}/task/{pid}/children")
    with contextlib.suppress(OSError):
        return sorted(int(x) for x in path.read_text().split())
    kids = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            with contextlib.suppress(OSError, ValueError, IndexError):
                stat = (entry / "stat").read_text()
                if int(stat.rsplit(")", 1)[1].split()[1]) == pid:
                    kids.append(int(entry.name))
    return sorted(kids)


def rss_kb(pid: int) -> int | None:
    with contextlib.suppress(OSError, ValueError):
        for line in Path(f"/proc/{pid}/status").read_text().splitlines():
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    return None


CLK_TCK = os.sysconf("SC_CLK_TCK")


def cpu_s_of(pid: int) -> float | None:
    """utime + stime of a process, seconds."""
    with contextlib.suppress(OSError, ValueError, IndexError):
        fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
        return (int(fields[11]) + int(fields[12])) / CLK_TCK
    return None


def machine_cpu_s() -> dict[str, float]:
    """CPU seconds of the whole machine since boot, all cores (/proc/stat): total, idle (with iowait),
    steal (taken by the hypervisor), irq (hard and soft interrupts: loopback traffic, not charged to any
    process) and busy (the processes')."""
    with open("/proc/stat") as fh:
        vals = [int(x) for x in fh.readline().split()[1:]] + [0] * 8
    total = sum(vals[:8])          # guest time is already inside user/nice
    idle = vals[3] + vals[4]
    irq = vals[5] + vals[6]
    steal = vals[7]
    return {"total": total / CLK_TCK, "idle": idle / CLK_TCK, "steal": steal / CLK_TCK, "irq": irq / CLK_TCK,
            "busy": (total - idle - irq - steal) / CLK_TCK}


def own_cpu_s() -> float:
    ru = resource.getrusage(resource.RUSAGE_SELF)
    return ru.ru_utime + ru.ru_stime


# ----------------------------------------------------------------------------- the server

class Server:
    """gunicorn started here, in its own session; always stopped by :meth:`stop`."""

    def __init__(self, port: int, workers: int, logdir: Path):
        self.port = port
        self.workers = workers
        self.log_path = logdir / "gunicorn.log"
        self.cmd = [str(ROOT / ".venv" / "bin" / "gunicorn"), "--config", "service/gunicorn_conf.py",
                    "--bind", f"{HOST}:{port}", "--workers", str(workers), "--no-control-socket", "service.app:app"]
        self.proc: subprocess.Popen | None = None

    def start(self) -> None:
        self._log = open(self.log_path, "wb")
        self.proc = subprocess.Popen(self.cmd, cwd=ROOT, stdout=self._log, stderr=subprocess.STDOUT,
                                     stdin=subprocess.DEVNULL, start_new_session=True)

    @property
    def pid(self) -> int:
        return self.proc.pid

    def log_text(self) -> str:
        with contextlib.suppress(OSError):
            return self.log_path.read_text(errors="replace")
        return ""

    def wait_ready(self, timeout_s: float = SERVER_START_TIMEOUT_S) -> float:
        """Until /healthz answers 200 and every worker has finished its start-up; seconds taken."""
        import httpx
        t0 = time.monotonic()
        url = f"http://{HOST}:{self.port}/healthz"
        with httpx.Client(timeout=5.0) as client:
            while time.monotonic() - t0 < timeout_s:
                if self.proc.poll() is not None:
                    raise RuntimeError(f"gunicorn exited with {self.proc.returncode}:\n{self.log_text()[-3000:]}")
                ok = False
                with contextlib.suppress(httpx.HTTPError):
                    ok = client.get(url).status_code == 200
                if ok and self.log_text().count("Application startup complete") >= self.workers:
                    return time.monotonic() - t0
                time.sleep(0.25)
        raise RuntimeError(f"the server was not ready after {timeout_s:.0f} s:\n{self.log_text()[-3000:]}")

    def stop(self) -> None:
        if self.proc is None:
            return
        if self.proc.poll() is None:
            with contextlib.suppress(ProcessLookupError):
                os.kill(self.proc.pid, signal.SIGTERM)
            try:
                self.proc.wait(timeout=30)
            except subprocess.TimeoutExpired:
                pass
        # whatever is left of the group started here (the master's pid is its group id)
        with contextlib.suppress(ProcessLookupError, PermissionError):
            os.killpg(self.proc.pid, signal.SIGKILL)
        with contextlib.suppress(subprocess.TimeoutExpired):
            self.proc.wait(timeout=5)
        self._log.close()


# ----------------------------------------------------------------------------- the clients

async def _one(client, method: str, path: str, body, raw: bytes | None, timeout: float) -> tuple[int | str, float, int]:
    """One request, its answer read to the end and dropped: (status or error name, seconds, bytes)."""
    import httpx
    t = time.perf_counter()
    n = 0
    try:
        kwargs = {"timeout": timeout}
        if body is not None:
            kwargs["json"] = body
        if raw is not None:
            kwargs["content"] = raw
            kwargs["headers"] = {"content-type": "application/json"}
        async with client.stream(method, path, **kwargs) as r:
            head = b""
            async for chunk in r.aiter_raw():
                n += len(chunk)
                if r.status_code >= 500 and len(head) < 4096:
                    head += chunk
            status: int | str = r.status_code
            if r.status_code >= 500:        # which 5xx: a problem's type (busy, deadline, memory, internal)
                with contextlib.suppress(ValueError, AttributeError):
                    status = f"{r.status_code} {json.loads(head)['type'].rsplit('/', 1)[-1]}"
    except httpx.TimeoutException:
        status = "timeout"
    except httpx.HTTPError as exc:
        status = type(exc).__name__
    return status, time.perf_counter() - t, n


async def client_loop(base: str, requests: list, offset: int, t_start: float, t_end: float, timeout: float,
                      out: list, keepalive: bool = False) -> None:
    """One client: the requests in turn (from ``offset``) until ``t_end``, each on a new connection (or
    all on one keep-alive connection)."""
    import httpx
    limits = httpx.Limits(max_connections=1, max_keepalive_connections=1 if keepalive else 0)
    async with httpx.AsyncClient(base_url=base, limits=limits, timeout=timeout) as client:
        delay = t_start - time.monotonic()
        if delay > 0:
            await asyncio.sleep(delay)
        i = offset
        while time.monotonic() < t_end and i - offset < MAX_REQUESTS_PER_CLIENT:
            name, method, path, body, raw = requests[i % len(requests)]
            began = time.monotonic()
            status, secs, nbytes = await _one(client, method, path, body, raw, timeout)
            out.append((name, began, status, secs, nbytes))
            i += 1


async def run_clients(base: str, requests: list, count: int, t_start: float, t_end: float, timeout: float,
                      out: list, keepalive: bool = False) -> None:
    tasks = [asyncio.create_task(client_loop(base, requests, k, t_start, t_end, timeout, out, keepalive))
             for k in range(count)]
    done, pending = await asyncio.wait(tasks, timeout=max(0.0, t_end - time.monotonic()) + PHASE_END_GRACE_S)
    for task in pending:          # bounded: a request still running this long after the phase is abandoned
        task.cancel()
    await asyncio.gather(*tasks, return_exceptions=True)


def hostile_process(base: str, count: int, max_track_samples: int, exclude: list[str], conn,
                    keepalive: bool = False) -> None:
    """The hostile clients, in their own process: waits for (t_start, t_end) on ``conn``, sends the
    requests' records and this process's CPU time back."""
    requests = [r for r in hostile_requests(max_track_samples) if not any(x in r[0] for x in exclude)]
    conn.send("ready")
    if not conn.poll(MAX_PHASE_S * 3):
        return
    msg = conn.recv()
    if msg is None:
        return
    t_start, t_end = msg
    out: list = []
    cpu0 = own_cpu_s()
    # spread the clients over the list, so that they do not all send the same request at once
    step = max(1, len(requests) // max(1, count))
    tasks_offsets = [k * step for k in range(count)]

    async def main():
        import httpx  # noqa: F401  (imported before the phase starts)
        tasks = [asyncio.create_task(client_loop(base, requests, off, t_start, t_end, HOSTILE_TIMEOUT_S, out,
                                                       keepalive))
                 for off in tasks_offsets]
        done, pending = await asyncio.wait(tasks, timeout=max(0.0, t_end - time.monotonic()) + 5.0)
        for task in pending:      # the hostile clients stop with their phase
            task.cancel()
        await asyncio.gather(*tasks, return_exceptions=True)

    asyncio.run(main())
    conn.send((out, own_cpu_s() - cpu0))


async def solo_pass(base: str, requests: list) -> list:
    """Each request once, alone, one after another."""
    import httpx
    rows = []
    async with httpx.AsyncClient(base_url=base, timeout=HOSTILE_TIMEOUT_S) as client:
        for name, method, path, body, raw in requests:
            status, secs, nbytes = await _one(client, method, path, body, raw, HOSTILE_TIMEOUT_S)
            rows.append((name, status, secs, nbytes))
    return rows


def budget_estimate(path: str, max_track_samples: int) -> dict | None:
    """The service's own cost estimate for a GET track (ephem.theory.cost), computed in a child process by asking
    under a zero budget (the estimate is charged before any work, so nothing is computed)."""
    code = f"""
import json, urllib.parse
from ephem import api
from ephem.base.budget import budget, OverBudgetError
q = dict(urllib.parse.parse_qsl(urllib.parse.urlsplit({path!r}).query))
try:
    with budget(1e-12, 1e-12):
        api.track_arrays("vesta", q["start"], q["stop"], float(q["step_days"]), dataset="current",
                         max_samples={max_track_samples})
except OverBudgetError as e:
    print(json.dumps({{"cpu_s": e.cost.cpu_s, "memory_mb": e.cost.memory_mb, "describe": e.cost.describe()}}))
"""
    with contextlib.suppress(subprocess.SubprocessError, ValueError, OSError):
        res = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, timeout=60)
        return json.loads(res.stdout.strip().splitlines()[-1])
    return None


# ----------------------------------------------------------------------------- sampling

class Sampler:
    """Every 0.5 s: the master's children, their RSS and CPU time, tagged with the current phase."""

    def __init__(self, master: int, log_path: Path):
        self.master = master
        self.phase = "start-up"
        self.samples: list[tuple[float, str, dict[int, tuple[int | None, float | None]]]] = []
        self.log_path = log_path
        self.log_pos = 0
        self.log_rest = b""
        self.events: list[tuple[float, str, str]] = []     # (time seen, phase, line): the log's non-access lines

    def sample(self) -> dict:
        kids = children_of(self.master)
        snap = {pid: (rss_kb(pid), cpu_s_of(pid)) for pid in kids}
        now = time.monotonic()
        self.samples.append((now, self.phase, snap))
        self._tail_log(now)
        return snap

    def _tail_log(self, now: float) -> None:
        with contextlib.suppress(OSError):
            with open(self.log_path, "rb") as fh:
                fh.seek(self.log_pos)
                data = fh.read(1 << 24)
                self.log_pos += len(data)
            lines = (self.log_rest + data).split(b"\n")
            self.log_rest = lines.pop()
            for raw in lines:
                line = raw.decode(errors="replace")
                if not ACCESS_LINE.search(line) and len(self.events) < 10_000:
                    self.events.append((now, self.phase, line))

    async def run(self, stop: asyncio.Event) -> None:
        while not stop.is_set():
            self.sample()
            with contextlib.suppress(asyncio.TimeoutError):
                await asyncio.wait_for(stop.wait(), SAMPLE_INTERVAL_S)

    def phase_samples(self, phase: str) -> list:
        return [s for s in self.samples if s[1] == phase]


class PhaseClock:
    """CPU of the machine, the server's workers and the load generator over a phase."""

    def __init__(self):
        self.m0 = machine_cpu_s()
        self.wall0 = time.monotonic()
        self.own0 = own_cpu_s()

    def finish(self, worker_cpu_s: float, hostile_cpu_s: float) -> dict:
        m1 = machine_cpu_s()
        d = {k: m1[k] - self.m0[k] for k in m1}
        wall = time.monotonic() - self.wall0
        loadgen = own_cpu_s() - self.own0 + hostile_cpu_s
        return {"wall_s": wall, "machine_capacity_s": d["total"], "idle_s": d["idle"], "steal_s": d["steal"],
                "irq_s": d["irq"], "machine_busy_s": d["busy"], "workers_cpu_s": worker_cpu_s,
                "loadgen_cpu_s": loadgen, "others_cpu_s": max(0.0, d["busy"] - worker_cpu_s - loadgen)}


def worker_cpu_in(samples: list) -> float:
    """CPU the workers spent between the first and the last sample of a phase (per pid, last - first)."""
    first: dict[int, float] = {}
    last: dict[int, float] = {}
    for _, _, snap in samples:
        for pid, (_, cpu) in snap.items():
            if cpu is None:
                continue
            first.setdefault(pid, cpu)
            last[pid] = cpu
    return sum(last[p] - first[p] for p in last)


def memory_rows(samples: list) -> list[dict]:
    seen: dict[int, list[int]] = collections.OrderedDict()
    for _, _, snap in samples:
        for pid, (rss, _) in snap.items():
            if rss is not None:
                seen.setdefault(pid, []).append(rss)
    return [{"pid": pid, "first_mb": v[0] / 1024, "max_mb": max(v) / 1024, "last_mb": v[-1] / 1024, "n": len(v)}
            for pid, v in seen.items()]


def restarts_in(samples: list, before: set[int]) -> tuple[list[int], list[int], dict[int, float]]:
    """(pids gone, pids new, when each was first seen gone) over a phase, against the workers alive when
    it began."""
    alive = set(before)
    gone, new, gone_at = [], [], {}
    for t, _, snap in samples:
        now = set(snap)
        for pid in sorted(alive - now):
            gone.append(pid)
            gone_at[pid] = t
        new += sorted(now - alive - set(new))
        alive = now
    return gone, new, gone_at


ACCESS_LINE = re.compile(r'"(GET|POST|HEAD|PUT|DELETE|OPTIONS|PATCH) /')
LOG_PID = re.compile(r"^\[[^]]*\] \[(\d+)\]")
#: a worker going away: the start of a restart (the worker stops accepting, then drains its requests)
GOING = re.compile(r"Maximum request limit|Autorestarting worker|past its deadline|after its requests|WORKER TIMEOUT"
                   r"|Shutting down$|MemoryError")
READY = re.compile(r"Application startup complete")

RESTART_PATTERNS = [
    ("max_requests recycle", re.compile(r"Maximum request limit|Autorestarting worker")),
    ("watchdog: deadline overstayed", re.compile(r"past its deadline of .* ending the worker")),
    ("watchdog: memory above ceiling", re.compile(r"holds .* MB after its requests")),
    ("gunicorn: worker timeout", re.compile(r"WORKER TIMEOUT")),
    ("killed by a signal", re.compile(r"was sent SIG(KILL|SEGV|ABRT)")),
    ("worker exited", re.compile(r"exited with code")),
    ("out of memory", re.compile(r"MemoryError")),
    ("traceback", re.compile(r"Traceback \(most recent call last\)")),
    ("worker booted", re.compile(r"Booting worker with pid")),
]


def log_events(text: str) -> dict[str, int]:
    return {name: len(pat.findall(text)) for name, pat in RESTART_PATTERNS if pat.findall(text)}


def degraded_intervals(events: list, samples: list, workers: int) -> list[tuple[float, float | None]]:
    """Intervals during which fewer than ``workers`` workers were serving: from the first sign of one going
    (its log line: the request limit, the watchdog; or its pid gone) until a new worker's 'Application
    startup complete'. ``None`` as an end: still short when the sampling ended."""
    changes: list[tuple[float, str, int]] = []
    for t, _, line in events:
        m = LOG_PID.match(line)
        if m is None:
            continue
        pid = int(m.group(1))
        if READY.search(line):
            changes.append((t, "ready", pid))
        elif GOING.search(line):
            changes.append((t, "going", pid))
    prev: set[int] = set()
    for t, _, snap in samples:
        now = set(snap)
        changes += [(t, "going", pid) for pid in prev - now]
        prev = now
    changes.sort(key=lambda c: c[0])
    ready: set[int] = set()
    going: set[int] = set()
    intervals: list[tuple[float, float | None]] = []
    began: float | None = None
    for t, kind, pid in changes:
        (ready if kind == "ready" else going).add(pid)
        serving = len(ready - going)
        if serving < workers and began is None and ready:
            began = t
        elif serving >= workers and began is not None:
            intervals.append((began, t))
            began = None
    if began is not None:
        intervals.append((began, None))
    return intervals


def restart_windows(intervals: list, lo: float, hi: float) -> list[tuple[float, float]]:
    """The degraded intervals within [lo, hi], widened by the sampling interval on both sides."""
    out = []
    for a, b in intervals:
        a, b = a - SAMPLE_INTERVAL_S, (hi if b is None else b) + SAMPLE_INTERVAL_S
        if b >= lo and a <= hi:
            out.append((max(a, lo), min(b, hi)))
    return out


def overlaps(record, windows) -> bool:
    began, secs = record[1], record[3]
    return any(began <= b and began + secs >= a for a, b in windows)


# ----------------------------------------------------------------------------- the run

def summarise_normal(records: list) -> dict:
    lat = [r[3] * 1e3 for r in records]
    ok = [r for r in records if isinstance(r[2], int) and 200 <= r[2] < 300]
    errors = collections.Counter(str(r[2]) for r in records if r not in ok)
    per = {}
    for name, *_ in NORMAL:
        xs = [r[3] * 1e3 for r in records if r[0] == name]
        per[name] = {"n": len(xs), "p50": percentile(xs, 50), "p99": percentile(xs, 99),
                     "max": max(xs) if xs else math.nan}
    return {"n": len(records), "p50": percentile(lat, 50), "p99": percentile(lat, 99), "p999": percentile(lat, 99.9),
            "max": max(lat) if lat else math.nan, "errors": sum(errors.values()), "error_kinds": dict(errors),
            "per": per}


def summarise_hostile(records: list, requests: list) -> dict:
    hist = collections.Counter(str(r[2]) for r in records)
    per = {}
    for name, *_ in requests:
        rs = [r for r in records if r[0] == name]
        xs = [r[3] * 1e3 for r in rs]
        per[name] = {"n": len(rs), "statuses": dict(collections.Counter(str(r[2]) for r in rs)),
                     "p50": percentile(xs, 50), "max": max(xs) if xs else math.nan,
                     "server_s": sum(xs) / 1e3, "bytes": max((r[4] for r in rs), default=0)}
    return {"n": len(records), "hist": dict(hist), "per": per}


async def run_phases(args, server: Server, hostile_conn, normal_reqs: list, hostile_reqs: list) -> dict:
    base = f"http://{HOST}:{server.port}"
    sampler = Sampler(server.pid, server.log_path)
    stop = asyncio.Event()
    sampling = asyncio.create_task(sampler.run(stop))
    result: dict = {}
    try:
        # warm-up: every worker's memoised models filled by the normal traffic (not counted)
        sampler.phase = "warm-up"
        if args.warmup > 0:
            t0 = time.monotonic()
            await run_clients(base, normal_reqs, args.clients, t0, t0 + args.warmup, NORMAL_TIMEOUT_S, [],
                              args.keepalive)
        sampler.phase = "solo"
        result["solo"] = await solo_pass(base, hostile_reqs)

        befores = {}
        for phase in ("clean", "mixed"):
            await asyncio.sleep(1.0)              # let the previous phase's tail drain
            sampler.phase = phase
            befores[phase] = set(sampler.sample())
            clock = PhaseClock()
            t_start = time.monotonic() + 0.2
            t_end = t_start + args.duration
            if phase == "mixed" and args.hostile > 0:
                hostile_conn.send((t_start, t_end))
            normal: list = []
            await run_clients(base, normal_reqs, args.clients, t_start, t_end, NORMAL_TIMEOUT_S, normal, args.keepalive)
            hostile, hostile_cpu = [], 0.0
            if phase == "mixed" and args.hostile > 0:
                deadline = time.monotonic() + PHASE_END_GRACE_S
                while not hostile_conn.poll(0.1) and time.monotonic() < deadline:
                    await asyncio.sleep(0.1)
                if hostile_conn.poll(0):
                    hostile, hostile_cpu = hostile_conn.recv()
                else:
                    raise RuntimeError("the hostile clients did not report back")
            sampler.sample()
            result[phase] = {
                "t_start": t_start, "t_end": t_end,
                "normal_records": normal, "hostile_records": hostile,
                "normal": summarise_normal(normal),
                "hostile": summarise_hostile(hostile, hostile_reqs) if phase == "mixed" else None,
                "cpu": clock.finish(worker_cpu_in(sampler.phase_samples(phase)), hostile_cpu),
                "loadavg": os.getloadavg(),
                "duration_s": args.duration,
            }
            print(f"  {phase}: {len(normal)} normal requests, p50 {result[phase]['normal']['p50']:.1f} ms, "
                  f"p99 {result[phase]['normal']['p99']:.1f} ms; {len(hostile)} hostile", flush=True)
        # a second after the last phase: a worker that exits at the very end is seen too
        await asyncio.sleep(1.0)
        sampler.sample()
        sampler.phase = "done"
    finally:
        stop.set()
        await sampling
    # workers and the log, over each phase and the second after it (until the next phase begins)
    intervals = degraded_intervals(sampler.events, sampler.samples, args.workers)
    for phase in ("clean", "mixed"):
        r = result[phase]
        samples = sampler.phase_samples(phase)
        gone, new, gone_at = restarts_in(samples, befores[phase])
        events = [e for e in sampler.events if e[1] == phase]
        windows = restart_windows(intervals, samples[0][0], samples[-1][0])
        quiet = [x for x in r["normal_records"] if not overlaps(x, windows)]
        r.update({
            "normal_outside_restarts": summarise_normal(quiet) if windows else None,
            "restart_windows": windows,
            "transport_errors_in_restarts": sum(1 for x in r["normal_records"] + r["hostile_records"]
                                                if not isinstance(x[2], int) and overlaps(x, windows)),
            "memory": memory_rows(samples),
            "restarts": {"gone": gone, "new": new},
            "events": events[:200],
            "log_events": log_events("\n".join(line for _, _, line in events)),
        })
    result["all_samples"] = sampler.samples
    return result


# ----------------------------------------------------------------------------- the report

def fmt_ms(x: float) -> str:
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "—"
    return f"{x:.0f}" if x >= 100 else f"{x:.1f}"


def fmt_bytes(n: float) -> str:
    return f"{n / 1e6:.1f} MB" if n >= 1e6 else f"{n / 1e3:.1f} kB"


def fmt_hist(hist: dict) -> str:
    if not hist:
        return "—"
    return ", ".join(f"{k}: {v}" for k, v in sorted(hist.items()))


def verdict(res: dict, rss_limit_mb: float) -> dict:
    clean, mixed = res["clean"], res["mixed"]
    ratio = mixed["normal"]["p99"] / clean["normal"]["p99"] if clean["normal"]["p99"] > 0 else math.inf
    hostile_hist = mixed["hostile"]["hist"] if mixed["hostile"] else {}
    solo_hist = collections.Counter(str(r[1]) for r in res["solo"])
    n500 = hostile_hist.get("500", 0) + solo_hist.get("500", 0)
    n503 = sum(v for k, v in list(hostile_hist.items()) + list(solo_hist.items()) if k.startswith("503"))
    n5xx = sum(v for k, v in list(hostile_hist.items()) + list(solo_hist.items())
               if k.startswith("5") and k != "503 busy")
    max_rss = max((m["max_mb"] for ph in ("clean", "mixed") for m in res[ph]["memory"]), default=math.nan)
    restarts = any(res[ph]["restarts"]["gone"] or res[ph]["restarts"]["new"] for ph in ("clean", "mixed"))
    normal_errors = clean["normal"]["errors"] + mixed["normal"]["errors"]
    return {"ratio": ratio, "latency_ok": ratio <= 2.0, "n500": n500, "n503": n503, "n5xx": n5xx,
            "normal_errors": normal_errors, "max_rss": max_rss, "memory_ok": max_rss < rss_limit_mb,
            "restarts": restarts,
            "ok": ratio <= 2.0 and n5xx == 0 and normal_errors == 0 and max_rss < rss_limit_mb}


def interpretation(res: dict, v: dict, hostile_reqs: list, estimates: dict, args) -> list[str]:
    lines = []
    clean, mixed = res["clean"], res["mixed"]
    cc, mc = clean["cpu"], mixed["cpu"]
    cap = mc["machine_capacity_s"]
    lines.append(
        f"- Normal p99 went from {fmt_ms(clean['normal']['p99'])} ms (clean) to {fmt_ms(mixed['normal']['p99'])} ms "
        f"(mixed): {v['ratio']:.2f}x, target ≤ 2x: **{'met' if v['latency_ok'] else 'NOT met'}**. Normal throughput "
        f"went from {clean['normal']['n'] / args.duration:.0f} to {mixed['normal']['n'] / args.duration:.0f} req/s.")
    if mixed["hostile"]:
        per = mixed["hostile"]["per"]
        heavy = sorted(per.items(), key=lambda kv: -kv[1]["server_s"])
        total = sum(p["server_s"] for p in per.values()) or 1.0
        name, top = heavy[0]
        lines.append(
            f"- The hostile clients spent {100 * top['server_s'] / total:.0f}% of their time waiting on `{name}` "
            f"(answered {fmt_hist(top['statuses'])}, p50 {fmt_ms(top['p50'])} ms, {fmt_bytes(top['bytes'])} per "
            f"answer).")
        others = [(n, p) for n, p in per.items() if n != name and p["n"]]
        refused = [n for n, p in others if all(k.startswith("4") for k in p["statuses"])]
        solo = {r[0]: r for r in res["solo"]}
        slowest = max((solo[n][2] * 1e3 for n in refused if n in solo), default=math.nan)
        lines.append(f"- {len(refused)} of the other {len(others)} hostile requests were always refused (4xx), alone in "
                     f"at most {fmt_ms(slowest)} ms each, before any heavy work (input checks, the epoch cap, the cost "
                     f"estimate against the budget, the body size).")
        for n, p in others:
            if n not in refused:
                lines.append(f"- `{n}` answered {fmt_hist(p['statuses'])} (p50 {fmt_ms(p['p50'])} ms, "
                             f"{fmt_bytes(p['bytes'])})" + (": the moments are used only through their ratios, so "
                                                               "this is a valid body (C-A)/C = 0.5" if "moments" in n
                                                               else "") + ".")
        for kname, est in estimates.items():
            solo = next((r for r in res["solo"] if r[0] == kname), None)
            if est and solo:
                lines.append(
                    f"- `{kname}` is *admitted*: it is within the epoch cap and the service's own estimate, "
                    f"{est['cpu_s']:.2f} s of one core and {est['memory_mb']:.0f} MB, is within the per-request "
                    f"budget ({args.settings.max_request_cpu_s:g} s, {args.settings.max_request_memory_mb:g} MB); "
                    f"alone it took {solo[2]:.2f} s wall, so the estimate is not too low for one request. The budget "
                    f"is per request, so {args.hostile} hostile clients looping on it would keep {args.workers} "
                    f"workers and 2 cores busy; above {args.settings.heavy_request_cpu_s:g} s "
                    f"(EPHEM_HEAVY_REQUEST_CPU_S) a request is large, and only {args.settings.heavy_slots} large "
                    f"request(s) run at once across the workers (EPHEM_HEAVY_SLOTS): the others answer 503 busy with "
                    f"Retry-After at once.")
    lines.append(
        f"- CPU over the mixed phase ({mc['wall_s']:.1f} s, {cap:.0f} core-s available): server workers "
        f"{mc['workers_cpu_s']:.1f} core-s, load generator {mc['loadgen_cpu_s']:.1f}, other users of the machine "
        f"{mc['others_cpu_s']:.1f}; clean phase: workers {cc['workers_cpu_s']:.1f}, load generator "
        f"{cc['loadgen_cpu_s']:.1f}, others {cc['others_cpu_s']:.1f} (of {cc['machine_capacity_s']:.0f}). The load "
        f"generator and the server share the same 2 cores, so client-side time is inside every latency.")
    lines.append(
        f"- Memory: the workers' largest RSS was {v['max_rss']:.0f} MB, against the watchdog's recycle threshold of "
        f"{args.rss_limit_mb:.0f} MB (0.8 × EPHEM_WORKER_MEMORY_MB) and the address-space ceiling of "
        f"{args.settings.worker_memory_mb:.0f} MB: **{'bounded' if v['memory_ok'] else 'NOT bounded'}**.")
    if v["restarts"]:
        parts = []
        for ph in ("clean", "mixed"):
            r = res[ph]["restarts"]
            if r["gone"] or r["new"]:
                parts.append(f"{ph}: gone {r['gone']}, new {r['new']}, log: {fmt_hist(res[ph]['log_events'])}")
        lines.append("- Worker restarts: " + "; ".join(parts) + ".")
        for ph in ("clean", "mixed"):
            r = res[ph]
            if not r["restart_windows"]:
                continue
            inside = [x for x in r["normal_records"] if overlaps(x, r["restart_windows"])]
            worst = max((x[3] for x in inside), default=0.0) * 1e3
            lines.append(f"  - {ph}: {len(inside)} normal requests were in flight while a worker was being replaced "
                         f"(the slowest {worst:.0f} ms); transport errors (client side) in those windows: "
                         f"{r['transport_errors_in_restarts']}.")
    else:
        lines.append("- No worker restarted in either phase (the master's children kept their pids).")
    if v["n500"]:
        lines.append(f"- **{v['n500']} hostile request(s) answered 500** (see the table above for which).")
    if v["n503"]:
        lines.append(f"- {v['n503']} hostile request(s) answered 503 (by problem type in the tables: busy, a large "
                     f"request already running, is the designed refusal; deadline or memory would mean an estimate "
                     f"was wrong).")
    return lines


def render(res: dict, args, info: dict, server: Server, hostile_reqs: list, estimates: dict, ready_s: float,
           started: dt.datetime) -> str:
    v = verdict(res, args.rss_limit_mb)
    clean, mixed = res["clean"], res["mixed"]
    out = []
    out.append("# Hostile requests beside normal traffic: load test\n")
    out.append(f"Generated by `benchmarks/bench_hostile_load.py` on {started:%Y-%m-%d %H:%M} UTC.\n")
    out.append(f"- command: `{' '.join(shlex.quote(a) for a in args.argv)}`")
    out.append(f"- server: `{' '.join(shlex.quote(os.path.relpath(a, ROOT)) if a.startswith(str(ROOT)) else a for a in server.cmd)}` "
               f"(ready in {ready_s:.1f} s)")
    out.append(f"- machine: nproc {info['nproc']} ({info['cpu']}), Linux {info['kernel']}, Python {info['python']}; "
               f"load average at the start {info['loadavg'][0]:.2f} (the cores are shared with other users, see the "
               f"CPU table)")
    s = args.settings
    out.append(f"- service limits: {s.max_track_samples} epochs per track, {s.max_body_bytes} B per body, "
               f"{s.max_request_cpu_s:g} s CPU and {s.max_request_memory_mb:g} MB per request (estimated, before the "
               f"work), {s.heavy_slots} large request(s) (estimated above {s.heavy_request_cpu_s:g} s) at once, "
               f"{s.request_deadline_s:g} s deadline, {s.worker_memory_mb:g} MB address space per worker")
    out.append(f"- load: {args.clients} normal clients, {args.hostile} hostile clients (mixed phase only, in a separate "
               f"process), {args.duration:g} s per phase after a {args.warmup:g} s warm-up; "
               f"{'one keep-alive connection per client' if args.keepalive else 'a new connection per request'}"
               f"per client; RSS sampled every {SAMPLE_INTERVAL_S} s\n")

    out.append("## Result\n")
    out.append("| phase | normal requests | normal req/s | normal p50 (ms) | normal p99 (ms) | normal max (ms) "
               "| normal non-2xx | hostile requests | hostile statuses | max RSS per worker (MB) | worker restarts |")
    out.append("|---|---:|---:|---:|---:|---:|---:|---:|---|---|---|")
    for ph in ("clean", "mixed"):
        r = res[ph]
        n = r["normal"]
        h = r["hostile"]
        mem = ", ".join(f"{m['max_mb']:.0f} (pid {m['pid']})" for m in r["memory"])
        rs = r["restarts"]
        restart = "none" if not (rs["gone"] or rs["new"]) else f"gone {rs['gone']}, new {rs['new']}"
        out.append(f"| {ph} | {n['n']} | {n['n'] / args.duration:.0f} | {fmt_ms(n['p50'])} | {fmt_ms(n['p99'])} | "
                   f"{fmt_ms(n['max'])} | {n['errors']}{' ' + fmt_hist(n['error_kinds']) if n['errors'] else ''} | "
                   f"{h['n'] if h else 0} | {fmt_hist(h['hist']) if h else '—'} | {mem} | {restart} |")
    out.append("")
    out.append("**Verdict**: " + ("PASS" if v["ok"] else "FAIL") + f" — mixed/clean normal p99 = {v['ratio']:.2f}x "
               f"(target ≤ 2x: {'met' if v['latency_ok'] else '**NOT met**'}); normal non-2xx: {v['normal_errors']}; "
               f"hostile 500: {v['n500']}, 503: {v['n503']}; workers' max RSS {v['max_rss']:.0f} MB "
               f"(< {args.rss_limit_mb:.0f} MB: {'bounded' if v['memory_ok'] else '**NOT bounded**'}); worker restarts: "
               f"{'yes' if v['restarts'] else 'none'}.\n")
    if any(res[ph]["restart_windows"] for ph in ("clean", "mixed")):
        def q(ph):
            r = res[ph]
            return r["normal_outside_restarts"] or r["normal"]
        t_origin = res["clean"]["t_start"]
        wins = "; ".join(f"{ph} {a - t_origin:.1f}–{b - t_origin:.1f} s" for ph in ("clean", "mixed")
                         for a, b in res[ph]["restart_windows"])
        ratio = q("mixed")["p99"] / q("clean")["p99"]
        out.append(f"Fewer than {args.workers} workers were serving at times (a worker being replaced; windows, t from the "
                   f"clean phase's start: {wins}). "
                   f"Leaving out the normal requests in flight during those windows: clean p99 "
                   f"{fmt_ms(q('clean')['p99'])} ms ({q('clean')['n']} requests), mixed p99 {fmt_ms(q('mixed')['p99'])} ms "
                   f"({q('mixed')['n']} requests): {ratio:.2f}x (for attribution only; the verdict above counts "
                   f"every request).\n")

    out.append("## Normal requests by endpoint\n")
    out.append("| request | clean n | clean p50 (ms) | clean p99 (ms) | mixed n | mixed p50 (ms) | mixed p99 (ms) | "
               "p99 mixed/clean |")
    out.append("|---|---:|---:|---:|---:|---:|---:|---:|")
    for name, method, path, _ in NORMAL:
        c, m = clean["normal"]["per"][name], mixed["normal"]["per"][name]
        ratio = m["p99"] / c["p99"] if c["p99"] else math.nan
        label = f"{method} {path}" + (" (README example body)" if method == "POST" else "")
        out.append(f"| `{label}` | {c['n']} | {fmt_ms(c['p50'])} | {fmt_ms(c['p99'])} | {m['n']} | {fmt_ms(m['p50'])} | "
                   f"{fmt_ms(m['p99'])} | {ratio:.2f}x |")
    out.append("")

    out.append("## Hostile requests\n")
    out.append("Solo: each sent once, alone, before the clean phase. Mixed: in the loop of the mixed phase.\n")
    out.append("| request | solo status | solo (ms) | mixed n | mixed statuses | mixed p50 (ms) | mixed max (ms) | "
               "answer size |")
    out.append("|---|---|---:|---:|---|---:|---:|---:|")
    solo = {r[0]: r for r in res["solo"]}
    per = mixed["hostile"]["per"] if mixed["hostile"] else {}
    for name, method, path, body, raw in hostile_reqs:
        so = solo.get(name)
        p = per.get(name, {"n": 0, "statuses": {}, "p50": math.nan, "max": math.nan, "bytes": 0})
        size = max(p["bytes"], so[3] if so else 0)
        size_s = fmt_bytes(size)
        out.append(f"| {name} | {so[1] if so else '—'} | {fmt_ms(so[2] * 1e3) if so else '—'} | {p['n']} | "
                   f"{fmt_hist(p['statuses'])} | {fmt_ms(p['p50'])} | {fmt_ms(p['max'])} | {size_s} |")
    out.append("")
    out.append("<details><summary>the hostile requests exactly</summary>\n")
    for name, method, path, body, raw in hostile_reqs:
        if raw is not None:
            desc = f"{len(raw)} bytes of JSON (`{{\"name\": \"xxx…\"}}`)"
        elif body is not None:
            diff = {k: body[k] for k in body if body[k] != EXAMPLE_BODY.get(k)}
            desc = "the README example body with " + json.dumps(diff)
        else:
            desc = ""
        out.append(f"- {name}: `{method} {path}` {desc}")
    out.append("\n</details>\n")

    out.append("## Workers' memory (VmRSS)\n")
    out.append("| phase | worker pid | RSS at start (MB) | max RSS (MB) | RSS at end (MB) | samples |")
    out.append("|---|---:|---:|---:|---:|---:|")
    for ph in ("clean", "mixed"):
        for m in res[ph]["memory"]:
            out.append(f"| {ph} | {m['pid']} | {m['first_mb']:.0f} | {m['max_mb']:.0f} | {m['last_mb']:.0f} | {m['n']} |")
    out.append("")
    heavy = next((r[0] for r in hostile_reqs if r[0].startswith("track at cap")), None)
    rows = timeline(res, ("clean", "mixed"), heavy)
    if rows:
        out.append("Over time, 2 s bins (t from the clean phase's start; the normal requests by their start; "
                   "RSS: each worker's largest sample in the bin, one column per worker pid):\n")
        out.extend(rows)
        out.append("")

    out.append("## CPU in each phase (core-seconds)\n")
    out.append("Measured from the start of the phase to the end of its last request: the capacity is wall × "
               "cores; 'other processes' is what the machine's processes spent beyond the server's workers and "
               "this load generator (other users of the shared machine); interrupts are the kernel's (loopback "
               "traffic among them); steal is time the hypervisor took.\n")
    out.append("| phase | wall (s) | capacity | idle | steal | interrupts | server workers | load generator | "
               "other processes |")
    out.append("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for ph in ("clean", "mixed"):
        c = res[ph]["cpu"]
        out.append(f"| {ph} | {c['wall_s']:.1f} | {c['machine_capacity_s']:.1f} | {c['idle_s']:.1f} | "
                   f"{c['steal_s']:.1f} | {c['irq_s']:.1f} | {c['workers_cpu_s']:.1f} | {c['loadgen_cpu_s']:.1f} | "
                   f"{c['others_cpu_s']:.1f} |")
    out.append("")
    ev = {ph: res[ph]["log_events"] for ph in ("clean", "mixed")}
    out.append(f"gunicorn/service log events: clean {fmt_hist(ev['clean'])}; mixed {fmt_hist(ev['mixed'])}.\n")
    lines = [(t, ph, line) for ph in ("clean", "mixed") for t, _, line in res[ph]["events"]]
    if lines:
        t_origin = res["clean"]["t_start"]
        out.append("<details><summary>the server's log during the phases (access lines left out; t: when the "
                   "sampler read the line, ±0.5 s)</summary>\n")
        out.append("```")
        out.extend(f"t={t - t_origin:6.1f} {ph:5s} {line}" for t, ph, line in lines[:120])
        out.append("```\n</details>\n")

    out.append("## Interpretation\n")
    out.extend(interpretation(res, v, hostile_reqs, estimates, args))
    out.append("")
    return "\n".join(out)


def timeline(res: dict, phases: tuple, heavy: str | None, bin_s: float = 2.0) -> list[str]:
    """One row per ``bin_s`` of each phase: the normal requests that started in it (count, p99, max), the
    heavy hostile requests running (average number in flight), each worker's largest RSS in it."""
    pids: list[int] = []
    for _, ph, snap in res["all_samples"]:
        if ph in phases:
            for pid in snap:
                if pid not in pids:
                    pids.append(pid)
    if not pids:
        return []
    t_origin = res[phases[0]]["t_start"]
    lines = ["| t (s) | phase | normal started | normal p99 (ms) | normal max (ms) | "
             + (f"`{heavy}` in flight | " if heavy else "") + "worker being replaced | "
             + " | ".join(f"RSS {p} (MB)" for p in pids) + " |",
             "|---:|---|---:|---:|---:|" + ("---:|" if heavy else "") + "---|" + "---:|" * len(pids)]
    for ph in phases:
        r = res[ph]
        t = r["t_start"]
        while t < r["t_end"] - 1e-6:
            t1 = min(t + bin_s, r["t_end"])
            xs = [x[3] * 1e3 for x in r["normal_records"] if t <= x[1] < t1]
            cells = [f"{t - t_origin:.0f}", ph, str(len(xs)), fmt_ms(percentile(xs, 99)), fmt_ms(max(xs) if xs else math.nan)]
            if heavy:
                busy = sum(max(0.0, min(t1, x[1] + x[3]) - max(t, x[1])) for x in r["hostile_records"] if x[0] == heavy)
                cells.append(f"{busy / (t1 - t):.1f}")
            cells.append("yes" if any(a <= t1 and b >= t for a, b in r.get("restart_windows", [])) else "")
            for pid in pids:
                vals = [snap[pid][0] for st, sph, snap in res["all_samples"]
                        if t <= st < t1 and pid in snap and snap[pid][0] is not None]
                cells.append(f"{max(vals) / 1024:.0f}" if vals else "—")
            lines.append("| " + " | ".join(cells) + " |")
            t = t1
    return lines


# ----------------------------------------------------------------------------- main

def parse_args(argv: list[str]) -> argparse.Namespace:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--duration", type=float, default=20.0, help="seconds of each phase (default 20)")
    p.add_argument("--warmup", type=float, default=3.0, help="seconds of normal traffic before, not counted")
    p.add_argument("--clients", type=int, default=8, help="normal clients (default 8)")
    p.add_argument("--hostile", type=int, default=4, help="hostile clients in the mixed phase (default 4)")
    p.add_argument("--workers", type=int, default=2, help="gunicorn workers (default 2)")
    p.add_argument("--exclude-hostile", default="", help="comma-separated substrings: hostile requests to leave out")
    p.add_argument("--out", type=Path, default=RESULTS, help="the Markdown report (default benchmarks/RESULTS_load.md)")
    p.add_argument("--no-write", action="store_true", help="print the report only")
    p.add_argument("--keepalive", action="store_true",
                   help="one keep-alive connection per client (pinned to one worker) instead of one per request")
    p.add_argument("--append", metavar="TITLE", default=None,
                   help="append the report to --out as a section with this title (a diagnostic run), "
                        "instead of replacing the file")
    args = p.parse_args(argv)
    if not (0 < args.duration <= MAX_PHASE_S) or not (0 <= args.warmup <= MAX_PHASE_S):
        p.error(f"--duration must be in (0, {MAX_PHASE_S:g}] and --warmup in [0, {MAX_PHASE_S:g}]")
    if not (1 <= args.clients <= 256 and 0 <= args.hostile <= 256 and 1 <= args.workers <= 16):
        p.error("--clients 1..256, --hostile 0..256, --workers 1..16")
    args.exclude = [x.strip() for x in args.exclude_hostile.split(",") if x.strip()]
    args.argv = [os.path.relpath(sys.argv[0], ROOT) if sys.argv[0] else "bench_hostile_load.py", *argv]
    return args


def main(argv: list[str] | None = None) -> int:
    args = parse_args(sys.argv[1:] if argv is None else argv)
    sys.path.insert(0, str(ROOT))
    from service.settings import Settings
    env = dict(os.environ, EPHEM_SUPERVISED="1")
    old = dict(os.environ)
    os.environ.update(env)
    try:
        args.settings = Settings.from_env()       # what the server will read (the same environment)
    finally:
        os.environ.clear()
        os.environ.update(old)
    args.rss_limit_mb = 0.8 * args.settings.worker_memory_mb
    started = dt.datetime.now(dt.timezone.utc)
    info = machine_info()
    normal_reqs = [(name, method, path, body, None) for name, method, path, body in NORMAL]
    hostile_reqs = [r for r in hostile_requests(args.settings.max_track_samples)
                    if not any(x in r[0] for x in args.exclude)]
    at_cap = [r for r in hostile_reqs if r[0].startswith("track at cap")]
    estimates = {r[0]: budget_estimate(r[2], args.settings.max_track_samples) for r in at_cap}

    port = free_port()
    base = f"http://{HOST}:{port}"
    hostile_proc = None
    parent_conn, child_conn = mp.get_context("spawn").Pipe()
    with tempfile.TemporaryDirectory(prefix="ephem-hostile-") as tmp:
        server = Server(port, args.workers, Path(tmp))
        previous = {sig: signal.getsignal(sig) for sig in (signal.SIGTERM, signal.SIGHUP)}

        def on_signal(signum, frame):
            raise KeyboardInterrupt(f"signal {signum}")
        for sig in previous:
            signal.signal(sig, on_signal)
        try:
            print(f"starting: {' '.join(server.cmd)}", flush=True)
            server.start()
            if args.hostile > 0:
                hostile_proc = mp.get_context("spawn").Process(
                    target=hostile_process, args=(base, args.hostile, args.settings.max_track_samples, args.exclude,
                                                  child_conn, args.keepalive), daemon=True)
                hostile_proc.start()
            ready_s = server.wait_ready()
            print(f"ready in {ready_s:.1f} s; warm-up {args.warmup:g} s, then clean and mixed, {args.duration:g} s each",
                  flush=True)
            if hostile_proc is not None and not parent_conn.poll(60):
                raise RuntimeError("the hostile client process did not start")
            if hostile_proc is not None:
                parent_conn.recv()
            res = asyncio.run(run_phases(args, server, parent_conn, normal_reqs, hostile_reqs))
            res["server_log_tail"] = server.log_text()[-2000:]
        finally:
            if hostile_proc is not None and hostile_proc.is_alive():
                with contextlib.suppress(OSError, BrokenPipeError):
                    parent_conn.send(None)
                hostile_proc.join(5)
                if hostile_proc.is_alive():
                    hostile_proc.kill()
                    hostile_proc.join(5)
            server.stop()
            for sig, handler in previous.items():
                signal.signal(sig, handler)

    report = render(res, args, info, server, hostile_reqs, estimates, ready_s, started)
    print()
    print(report)
    if not args.no_write:
        if args.append is not None and args.out.exists():
            section = report.replace("# Hostile requests beside normal traffic: load test", f"# {args.append}", 1)
            with open(args.out, "a") as fh:
                fh.write("\n---\n\n" + section)
        else:
            args.out.write_text(report)
        print(f"written to {os.path.relpath(args.out, ROOT)}")
    return 0 if verdict(res, args.rss_limit_mb)["ok"] else 1


if __name__ == "__main__":
    sys.exit(main())
