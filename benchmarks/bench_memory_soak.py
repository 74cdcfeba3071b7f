"""Memory soak: each worker's resident memory through thousands of varied requests, against the real server.

The script starts the service as ``make serve`` does (``.venv/bin/gunicorn --config service/gunicorn_conf.py
--bind 127.0.0.1:<free port> --workers 2 --no-control-socket service.app:app``) from a source tree (``--src``,
default this checkout: an A/B run serves the "before" tree with its own bytecode and table cache,
``machine.tree_env``), waits for every worker's start-up, and sends a fixed, seeded sequence of mixed requests
from a few concurrent clients, each request on a new connection (the kernel spreads new connections over the
workers' accept, so both workers see the mix):

- ``POST /v1/precession-nutation`` with a body of the client's own, every one different (orbit, pole, period,
  moments drawn afresh; some with a track, some with a history): each is a new key for every per-body cache;
- ``POST /v1/batch`` of a few such bodies;
- tracks of the catalogue's bodies over varied spans (JSON and CSV, some with a tolerance), their models' table;
- histories (JSON) over varied spans;
- nutation tables in every format and layout;
- figures: ``track.png``/``.svg`` of every kind, ``history.png``/``.svg``, ``track/models.svg``/``.png``
  (matplotlib), at varied resolutions;
- the precession and the free motion.

At the start and after each checkpoint (2k, 4k, 8k requests by default) the clients stop, the requests in flight
finish, and each worker's VmRSS is read (``/proc/<pid>/status``) while it is idle; between checkpoints it is
sampled every 0.25 s for the largest value. A worker that was replaced (a recycle by the service's watchdog, or
a crash) shows as a new pid, with the reason from the server's log.

Every request goes to 127.0.0.1; every loop is bounded; the server is always stopped (SIGTERM, then SIGKILL of
its process group). Prints a Markdown section; ``--out FILE`` appends it to a results file.

Run: ``.venv/bin/python benchmarks/bench_memory_soak.py`` (8,000 requests, 1-3 min on 2 shared cores); options:
``--src DIR``, ``--label TEXT``, ``--requests N`` (the last checkpoint), ``--checkpoints 2000,4000,8000``,
``--clients N``, ``--workers W``, ``--seed S``, ``--env NAME=VALUE`` (repeatable: the server's environment),
``--out FILE``, ``--tree-note TEXT`` (what a served tree outside git is). A shorter run: ``--requests 4000
--checkpoints 2000,4000``. Besides the RSS it counts the refusals by reason: 503 for the worker's memory (its
requests' memory admission, service/guards.py), 503 for the large requests' slots, 422 for a request's own memory
budget.
"""
from __future__ import annotations

import argparse
import asyncio
import collections
import contextlib
import datetime as dt
import math
import os
import random
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "benchmarks"))
from machine import machine_info, tree_env  # noqa: E402

HOST = "127.0.0.1"
SERVER_START_TIMEOUT_S = 120.0
REQUEST_TIMEOUT_S = 60.0           # past the service's deadline (20 s) and its watchdog's grace (10 s)
SAMPLE_INTERVAL_S = 0.25
MAX_RUN_S = 1800.0                 # the whole soak stops here, whatever is left
BODIES = ("ceres", "vesta", "eros", "steins", "itokawa", "earth", "moon", "mars")
#: the share of each kind of request in the sequence
MIX = {"post-body": 26, "batch": 4, "track": 15, "track-models": 4, "history": 8, "nutation": 15,
       "precession": 12, "free-motion": 4, "figure-track": 5, "figure-history": 3, "figure-models": 4}


# ----------------------------------------------------------------------------- the requests

def _custom_body(rng: random.Random, k: int) -> dict:
    """A body of the client's own, every value drawn afresh (a new key for every per-body cache)."""
    e = rng.uniform(0.0, 0.35) if rng.random() < 0.85 else rng.uniform(0.35, 0.7)
    body = {"name": f"soak-{k}",
            "orbit": {"a_au": round(rng.uniform(0.9, 4.5), 9), "e": round(e, 9), "i_deg": rng.uniform(0, 35),
                      "node_deg": rng.uniform(0, 360), "peri_deg": rng.uniform(0, 360),
                      "mean_anomaly_deg": rng.uniform(0, 360), "epoch_jd_tdb": 2460200.5},
            "pole": {"ra_deg": rng.uniform(0, 360), "dec_deg": rng.uniform(-85, 85), "epoch_jd_tdb": 2451545.0},
            "rotation_period_hours": rng.uniform(2.5, 40.0)}
    if rng.random() < 0.5:
        c = 1.0
        b = c * (1.0 - rng.uniform(0.02, 0.25))
        a = b * (1.0 - rng.uniform(0.0, 0.15))
        body["moments"] = {"A": a, "B": b, "C": c}
    else:
        body["dynamical_ellipticity"] = rng.uniform(0.01, 0.3)
    r = rng.random()
    if r < 0.35:
        start = 2451545.0 + rng.uniform(0, 15000)
        body["track"] = {"start": start, "stop": start + rng.uniform(100, 3000), "step_days": rng.uniform(2, 40)}
        if rng.random() < 0.4:
            body["track"]["tolerance_mas"] = rng.choice([10.0, 100.0, 1000.0])
    elif r < 0.5:
        lo = -rng.uniform(1e3, 2e5)
        hi = rng.uniform(0, 2e4)
        body["history"] = {"start_year": lo, "stop_year": hi, "step_years": (hi - lo) / rng.uniform(50, 400)}
    if rng.random() < 0.25:
        body["order"] = rng.choice([0, 2, 4, 6])
    return body


def _batch_row(rng: random.Random, k: int) -> dict:
    b = _custom_body(rng, k)
    row = {"name": b["name"], **b["orbit"], "pole_ra_deg": b["pole"]["ra_deg"], "pole_dec_deg": b["pole"]["dec_deg"],
           "rotation_period_hours": b["rotation_period_hours"],
           "dynamical_ellipticity": b.get("dynamical_ellipticity", rng.uniform(0.01, 0.3))}
    return row


def _span(rng: random.Random, days_lo: float, days_hi: float) -> tuple[float, float]:
    start = 2451545.0 + rng.uniform(-20000, 20000)
    return start, start + rng.uniform(days_lo, days_hi)


def soak_requests(n: int, seed: int) -> list[tuple[str, str, str, object]]:
    """``n`` requests (kind, method, path, JSON body or None), drawn with ``seed``: the same sequence each run."""
    rng = random.Random(seed)
    kinds = list(MIX)
    weights = [MIX[k] for k in kinds]
    out = []
    for k in range(n):
        kind = rng.choices(kinds, weights)[0]
        b = rng.choice(BODIES)
        if kind == "post-body":
            out.append((kind, "POST", "/v1/precession-nutation", _custom_body(rng, k)))
        elif kind == "batch":
            out.append((kind, "POST", "/v1/batch", [_batch_row(rng, k * 10 + j) for j in range(rng.randint(2, 6))]))
        elif kind == "track":
            start, stop = _span(rng, 30, 4000)
            q = f"start={start:.4f}&stop={stop:.4f}&step_days={rng.uniform(1, 30):.3f}"
            if rng.random() < 0.4:
                q += f"&tolerance_mas={rng.choice([5, 50, 500, 5000])}"
            if rng.random() < 0.25:
                q += "&format=csv"
            out.append((kind, "GET", f"/v1/bodies/{b}/track?{q}", None))
        elif kind == "track-models":
            start, stop = _span(rng, 30, 3000)
            out.append((kind, "GET", f"/v1/bodies/{b}/track/models?start={start:.4f}&stop={stop:.4f}"
                                     f"&step_days={rng.uniform(2, 30):.3f}&tolerance_mas={rng.choice([10, 100, 1000])}",
                        None))
        elif kind == "history":
            lo, hi = -rng.uniform(1e3, 3e5), rng.uniform(0, 5e4)
            out.append((kind, "GET", f"/v1/bodies/{b}/history?start_year={lo:.1f}&stop_year={hi:.1f}"
                                     f"&step_years={(hi - lo) / rng.uniform(50, 500):.2f}", None))
        elif kind == "nutation":
            fmt = rng.choice(["json", "csv", "markdown", "latex", "table-json"])
            q = f"format={fmt}&layout={rng.choice(['sin-cos', 'amp-period'])}"
            if rng.random() < 0.4 and b not in ("earth", "moon"):
                q += f"&order={rng.randint(0, 12)}"
            out.append((kind, "GET", f"/v1/bodies/{b}/nutation?{q}", None))
        elif kind == "precession":
            q = "" if rng.random() < 0.6 else f"?tolerance_mas={rng.choice([1, 10, 100])}"
            out.append((kind, "GET", f"/v1/bodies/{b}/precession{q}", None))
        elif kind == "free-motion":
            start, stop = _span(rng, 10, 400)
            out.append((kind, "GET", f"/v1/bodies/{b}/free-motion?start={start:.4f}&stop={stop:.4f}"
                                     f"&step_days={rng.uniform(0.5, 5):.3f}", None))
        elif kind == "figure-track":
            start, stop = _span(rng, 200, 5000)
            ext = rng.choice(["png", "svg"])
            plot = rng.choice(["precession", "nutation-loop", "obliquity", "free-wobble"])
            out.append((kind, "GET", f"/v1/bodies/{b}/track.{ext}?start={start:.4f}&stop={stop:.4f}&kind={plot}"
                                     f"&dpi={rng.randint(40, 110)}", None))
        elif kind == "figure-history":
            lo, hi = -rng.uniform(1e3, 3e5), rng.uniform(0, 5e4)
            ext = rng.choice(["png", "svg"])
            out.append((kind, "GET", f"/v1/bodies/{b}/history.{ext}?start_year={lo:.1f}&stop_year={hi:.1f}"
                                     f"&dpi={rng.randint(40, 110)}", None))
        else:   # figure-models
            start, stop = _span(rng, 30, 3000)
            ext = rng.choice(["png", "svg"])
            out.append((kind, "GET", f"/v1/bodies/{b}/track/models.{ext}?start={start:.4f}&stop={stop:.4f}"
                                     f"&step_days={rng.uniform(2, 30):.3f}&tolerance_mas={rng.choice([10, 100])}"
                                     f"&dpi={rng.randint(40, 110)}", None))
    return out


# ----------------------------------------------------------------------------- the server

def free_port() -> int:
    import socket
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind((HOST, 0))
        return s.getsockname()[1]


def children_of(pid: int) -> list[int]:
    """The direct children of ``pid`` (the gunicorn master's workers)."""
    with contextlib.suppress(OSError):
        return sorted(int(x) for x in Path(f"/proc/{pid}/task/{pid}/children").read_text().split())
    return []


def rss_mb(pid: int) -> float | None:
    """VmRSS of ``pid``, MB (2^20 bytes)."""
    with contextlib.suppress(OSError, ValueError):
        for line in Path(f"/proc/{pid}/status").read_text().splitlines():
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024
    return None


def memory_map(pid: int) -> dict[str, float] | None:
    """Where a process's resident memory is, MB (``/proc/<pid>/smaps``): the main heap (``[heap]``: the main arena and
    Python's small-object pools), anonymous mappings (the other malloc arenas, large blocks, thread stacks), files
    (code, shared libraries, data files mapped), and its thread count."""
    out = collections.Counter()
    name = ""
    try:
        with open(f"/proc/{pid}/smaps") as fh:
            for line in fh:
                first = line.split(None, 1)[0]
                if "-" in first and not first.endswith(":"):
                    parts = line.split()
                    name = parts[5] if len(parts) > 5 else ""
                elif first == "Rss:":
                    kb = int(line.split()[1])
                    key = ("heap" if name == "[heap]" else "anonymous" if name == "" or name.startswith("[anon")
                           else "stack" if name.startswith("[stack") else "other" if name.startswith("[") else "files")
                    out[key] += kb / 1024
        for line in Path(f"/proc/{pid}/status").read_text().splitlines():
            if line.startswith("Threads:"):
                out["threads"] = int(line.split()[1])
    except (OSError, ValueError):
        return None
    return dict(out)


class Server:
    """gunicorn serving the tree ``src``, started here in its own session; always stopped by :meth:`stop`."""

    def __init__(self, src: Path, port: int, workers: int, logdir: Path, extra_env: dict,
                 config: str = "service/gunicorn_conf.py"):
        self.src = src
        self.port = port
        self.workers = workers
        self.log_path = logdir / "gunicorn.log"
        self.cmd = [str(ROOT / ".venv" / "bin" / "gunicorn"), "--config", config,
                    "--bind", f"{HOST}:{port}", "--workers", str(workers), "--no-control-socket", "service.app:app"]
        self.env = {**tree_env(src), **extra_env}
        self.proc: subprocess.Popen | None = None

    def start(self) -> None:
        self._log = open(self.log_path, "wb")
        self.proc = subprocess.Popen(self.cmd, cwd=self.src, env=self.env, stdout=self._log,
                                     stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL, start_new_session=True)

    def log_text(self) -> str:
        with contextlib.suppress(OSError):
            return self.log_path.read_text(errors="replace")
        return ""

    def wait_ready(self) -> float:
        import httpx
        t0 = time.monotonic()
        with httpx.Client(timeout=5.0) as client:
            while time.monotonic() - t0 < SERVER_START_TIMEOUT_S:
                if self.proc.poll() is not None:
                    raise RuntimeError(f"gunicorn exited with {self.proc.returncode}:\n{self.log_text()[-3000:]}")
                ok = False
                with contextlib.suppress(httpx.HTTPError):
                    ok = client.get(f"http://{HOST}:{self.port}/healthz").status_code == 200
                if ok and self.log_text().count("Application startup complete") >= self.workers:
                    return time.monotonic() - t0
                time.sleep(0.25)
        raise RuntimeError(f"the server was not ready after {SERVER_START_TIMEOUT_S:.0f} s:\n{self.log_text()[-3000:]}")

    def stop(self) -> None:
        if self.proc is None:
            return
        if self.proc.poll() is None:
            with contextlib.suppress(ProcessLookupError):
                os.kill(self.proc.pid, signal.SIGTERM)
            with contextlib.suppress(subprocess.TimeoutExpired):
                self.proc.wait(timeout=30)
        with contextlib.suppress(ProcessLookupError, PermissionError):
            os.killpg(self.proc.pid, signal.SIGKILL)
        with contextlib.suppress(subprocess.TimeoutExpired):
            self.proc.wait(timeout=5)
        self._log.close()


# ----------------------------------------------------------------------------- the soak

class Soak:
    """The clients, the checkpoints and the RSS samples of one run."""

    def __init__(self, server: Server, requests: list, checkpoints: list[int], clients: int):
        self.server = server
        self.base = f"http://{HOST}:{server.port}"
        self.requests = requests
        self.checkpoints = checkpoints
        self.clients = clients
        self.next = 0
        self.limit = 0
        self.statuses: dict[str, collections.Counter] = collections.defaultdict(collections.Counter)
        self.latency: dict[str, list[float]] = collections.defaultdict(list)
        self.peak: dict[int, float] = {}            # pid -> largest RSS in the current segment
        self.samples: dict[int, list[float]] = collections.defaultdict(list)    # pid -> every RSS sampled under load
        self.seen: list[int] = []                   # every worker pid, in the order first seen
        self.rows: list[dict] = []                  # one per checkpoint
        self.failures: list[str] = []               # the 5xx answers (503s: the first ten): what was asked, what came back
        self.refusals: collections.Counter = collections.Counter()   # refusals by reason (refusal_reason)

    def snapshot(self) -> dict[int, float]:
        snap = {}
        for pid in children_of(self.server.proc.pid):
            mb = rss_mb(pid)
            if mb is not None:
                snap[pid] = mb
                if pid not in self.seen:
                    self.seen.append(pid)
        return snap

    async def sampler(self, stop: asyncio.Event) -> None:
        while not stop.is_set():
            for pid, mb in self.snapshot().items():
                self.peak[pid] = max(self.peak.get(pid, 0.0), mb)
                if self.limit > 0:
                    self.samples[pid].append(mb)
            with contextlib.suppress(asyncio.TimeoutError):
                await asyncio.wait_for(stop.wait(), SAMPLE_INTERVAL_S)

    async def client(self, deadline: float) -> None:
        import httpx
        limits = httpx.Limits(max_connections=1, max_keepalive_connections=0)    # a new connection each request
        async with httpx.AsyncClient(base_url=self.base, limits=limits, timeout=REQUEST_TIMEOUT_S) as c:
            while self.next < self.limit and time.monotonic() < deadline:
                kind, method, path, body = self.requests[self.next]
                self.next += 1
                t = time.perf_counter()
                try:
                    r = await c.request(method, path, json=body)
                    status = str(r.status_code)
                    reason = refusal_reason(r.status_code, r.text)
                    if reason is not None:
                        self.refusals[reason] += 1
                    # every 5xx but a 503 (a refusal that says when to retry) is kept; the first ten 503s with them
                    if r.status_code >= 500 and (r.status_code != 503 or
                                                 sum(" -> 503 " in f for f in self.failures) < 10):
                        self.failures.append(f"{method} {path} {'' if body is None else body} -> {r.status_code} "
                                             f"{r.text[:300]}")
                except httpx.HTTPError as exc:
                    status = type(exc).__name__
                self.latency[kind].append(time.perf_counter() - t)
                self.statuses[kind][status] += 1

    async def run(self) -> float:
        stop = asyncio.Event()
        sampler = asyncio.create_task(self.sampler(stop))
        deadline = time.monotonic() + MAX_RUN_S
        t0 = time.monotonic()
        await asyncio.sleep(1.0)                   # idle after start-up
        snap = self.snapshot()
        self.rows.append({"requests": 0, "t_s": 0.0, "rss": snap, "peak": dict(self.peak),
                          "maps": {pid: memory_map(pid) for pid in snap}})
        for cp in self.checkpoints:
            self.peak = {}
            self.limit = min(cp, len(self.requests))
            await asyncio.gather(*(self.client(deadline) for _ in range(self.clients)))
            await asyncio.sleep(1.0)               # in flight: none; the workers idle (the watchdog's turn)
            snap = self.snapshot()
            self.rows.append({"requests": self.next, "t_s": time.monotonic() - t0, "rss": snap,
                              "peak": dict(self.peak), "maps": {pid: memory_map(pid) for pid in snap}})
            print(f"  {self.next} requests, {time.monotonic() - t0:.0f} s: "
                  + ", ".join(f"{pid}: {mb:.0f} MB" for pid, mb in self.rows[-1]["rss"].items()), flush=True)
        stop.set()
        await sampler
        return time.monotonic() - t0


def refusal_reason(status: int, text: str) -> str | None:
    """Why the service refused a request, from its problem: "503 memory" (the worker's memory for requests was
    taken: service/guards.py's memory admission), "503 heavy" (the large requests' slots were taken), "503 other"
    (deadline, memory ceiling), "422 memory" (the request alone over its memory budget); None for anything else."""
    if status == 503:
        if "/busy" in text:
            return "503 memory" if "MB of memory" in text else "503 heavy"
        return "503 other"
    if status == 422 and "/over-budget" in text and "MB of memory, over the budget" in text:
        return "422 memory"
    return None


def _pct(xs: list[float], q: float) -> float:
    xs = sorted(xs)
    if not xs:
        return math.nan
    pos = (len(xs) - 1) * q / 100.0
    lo, hi = math.floor(pos), math.ceil(pos)
    return xs[lo] + (xs[hi] - xs[lo]) * (pos - lo)


def render(soak: Soak, args, wall_s: float, ready_s: float, started: str) -> str:
    lines = [f"## {args.label}", "",
             f"- run: {started}; served tree: {args.tree_name}; {args.workers} workers, {args.clients} clients, "
             f"a new connection per request, seed {args.seed}; server environment: "
             + (", ".join(f"`{k}={v}`" for k, v in args.env.items()) or "the defaults"),
             *(f"- {line}" for line in machine_info()),
             f"- server ready in {ready_s:.1f} s; {soak.next} requests in {wall_s:.0f} s "
             f"({soak.next / max(wall_s, 1e-9):.0f} req/s overall; the machine is shared: other people's work ran "
             f"on the same 2 cores)", "",
             "RSS of each worker (VmRSS, MB), idle at each checkpoint, and in brackets the largest sampled since "
             "the previous checkpoint (every 0.25 s):", ""]
    pids = soak.seen
    lines.append("| requests | t (s) | " + " | ".join(f"worker {pid}" for pid in pids) + " |")
    lines.append("|---:|---:|" + "---:|" * len(pids))
    for row in soak.rows:
        cells = []
        for pid in pids:
            now = row["rss"].get(pid)
            peak = row["peak"].get(pid)
            cell = "—" if now is None else f"{now:.0f}"
            if peak is not None and row["requests"] > 0:
                cell += f" ({peak:.0f})"
            cells.append(cell)
        lines.append(f"| {row['requests']} | {row['t_s']:.0f} | " + " | ".join(cells) + " |")
    starts = {pid: soak.rows[0]["rss"].get(pid) for pid in pids}
    largest = max((mb for row in soak.rows for mb in [*row["rss"].values(), *row["peak"].values()]), default=0.0)
    replaced = [pid for pid in pids if pid not in soak.rows[-1]["rss"]]
    lines += ["", f"Largest RSS of any worker: **{largest:.0f} MB**; workers replaced during the run: "
              + (", ".join(str(p) for p in replaced) or "none") + "; workers at the start: "
              + ", ".join(f"{pid} {mb:.0f} MB" for pid, mb in starts.items() if mb is not None) + "."]
    lines += ["", f"RSS sampled every {SAMPLE_INTERVAL_S} s while the requests ran (requests in flight included):", "",
              f"| worker | samples | p50 (MB) | p90 | p99 | max | samples above {args.bound_mb:g} MB |",
              "|---:|---:|---:|---:|---:|---:|---:|"]
    for pid in pids:
        xs = soak.samples.get(pid, [])
        if xs:
            above = sum(x > args.bound_mb for x in xs) / len(xs)
            lines.append(f"| {pid} | {len(xs)} | {_pct(xs, 50):.0f} | {_pct(xs, 90):.0f} | {_pct(xs, 99):.0f} | "
                         f"{max(xs):.0f} | {above:.1%} |")
    lines += ["", "Where each worker's resident memory was at each checkpoint (MB, /proc/<pid>/smaps: the main heap, "
              "anonymous mappings — the other malloc arenas, large blocks, thread stacks —, mapped files), and its "
              "threads:", "", "| requests | worker | heap | anonymous | files | threads |",
              "|---:|---:|---:|---:|---:|---:|"]
    for row in soak.rows:
        for pid, m in row.get("maps", {}).items():
            if m:
                lines.append(f"| {row['requests']} | {pid} | {m.get('heap', 0):.0f} | {m.get('anonymous', 0):.0f} | "
                             f"{m.get('files', 0):.0f} | {m.get('threads', 0):.0f} |")
    events = [ln for ln in soak.server.log_text().splitlines()
              if any(w in ln for w in ("restarting", "Booting worker", "WORKER TIMEOUT", "exited", "MemoryError"))]
    if len(events) > args.workers:
        lines += ["", "Server log (workers started, recycled or lost):", "", "```",
                  *events[:40], "```"]
    lines += ["", "| kind | requests | statuses | p50 (ms) | p99 (ms) |", "|---|---:|---|---:|---:|"]
    for kind in MIX:
        st = soak.statuses.get(kind)
        if not st:
            continue
        lat = soak.latency[kind]
        lines.append(f"| {kind} | {sum(st.values())} | " + ", ".join(f"{s}: {n}" for s, n in sorted(st.items()))
                     + f" | {_pct(lat, 50) * 1e3:.0f} | {_pct(lat, 99) * 1e3:.0f} |")
    total = max(soak.next, 1)
    lines += ["", "Refused, by reason (of all the requests sent): "
              + ", ".join(f"{why} {soak.refusals.get(why, 0)} ({soak.refusals.get(why, 0) / total:.2%})"
                          for why in ("503 memory", "503 heavy", "503 other", "422 memory")) + "."]
    if soak.failures:
        lines += ["", "The 5xx answers (of the 503s, the first ten):", "", *(f"- `{f}`" for f in soak.failures)]
    return "\n".join(lines) + "\n"


def parse_args(argv: list[str]) -> argparse.Namespace:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--src", type=Path, default=ROOT, help="the source tree to serve (default: this checkout)")
    p.add_argument("--label", default="memory soak", help="the section's title")
    p.add_argument("--requests", type=int, default=None,
                   help="the last checkpoint (default: the last of --checkpoints)")
    p.add_argument("--checkpoints", default="2000,4000,8000")
    p.add_argument("--clients", type=int, default=4)
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--seed", type=int, default=42)
    p.add_argument("--bound-mb", type=float, default=400.0, help="report the share of RSS samples above this")
    p.add_argument("--env", action="append", default=[], help="NAME=VALUE for the server (repeatable)")
    p.add_argument("--out", type=Path, default=None, help="append the section to this file")
    p.add_argument("--tree-note", default="", help="what the served tree is, when it is not a git checkout")
    args = p.parse_args(argv)
    args.checkpoints = sorted(int(x) for x in args.checkpoints.split(","))
    if args.requests is not None:
        args.checkpoints = [c for c in args.checkpoints if c < args.requests] + [args.requests]
    args.env = dict(kv.split("=", 1) for kv in args.env)
    args.src = args.src.resolve()
    args.tree_name = "this checkout" if args.src == ROOT else f"another tree ({args.src.name})"
    with contextlib.suppress(OSError, subprocess.SubprocessError):
        rev = subprocess.run(["git", "-C", str(args.src), "rev-parse", "--short", "HEAD"], capture_output=True,
                             text=True, timeout=10).stdout.strip()
        dirty = subprocess.run(["git", "-C", str(args.src), "status", "--porcelain", "--untracked-files=no"],
                               capture_output=True, text=True, timeout=10).stdout.strip()
        if rev:
            args.tree_name += f", commit {rev}" + (" with uncommitted changes" if dirty else "")
    if args.tree_note:
        args.tree_name += f", {args.tree_note}"
    return args


def main(argv: list[str] | None = None) -> int:
    args = parse_args(sys.argv[1:] if argv is None else argv)
    started = dt.datetime.now(dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    requests = soak_requests(args.checkpoints[-1], args.seed)
    with tempfile.TemporaryDirectory(prefix="ephem-soak-") as tmp:
        server = Server(args.src, free_port(), args.workers, Path(tmp), {"EPHEM_SUPERVISED": "1", **args.env})
        previous = {sig: signal.getsignal(sig) for sig in (signal.SIGTERM, signal.SIGHUP)}

        def on_signal(signum, frame):
            raise KeyboardInterrupt(f"signal {signum}")
        for sig in previous:
            signal.signal(sig, on_signal)
        try:
            print(f"serving {args.src} ({args.tree_name}): {' '.join(server.cmd)}", flush=True)
            server.start()
            ready_s = server.wait_ready()
            soak = Soak(server, requests, args.checkpoints, args.clients)
            wall_s = asyncio.run(soak.run())
        finally:
            server.stop()
            for sig, handler in previous.items():
                signal.signal(sig, handler)
    report = render(soak, args, wall_s, ready_s, started)
    print()
    print(report)
    if args.out is not None:
        with open(args.out, "a") as fh:
            fh.write("\n" + report)
        print(f"appended to {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
