"""Each request's predicted peak memory against the resident memory it really takes (issue 42: a worker's RSS under
its 400-MB bound through any sequence of requests).

The memory soak (``bench_memory_soak.py``) found workers 150-160 MB above their idle RSS while the requests in flight
were predicted within their 80-MB allowance; its samples are of the whole worker, so they cannot say which requests
take more than predicted. This script asks each request alone: a sample of the soak's own seeded sequence (the same
generator, seed 42), ``PER_KIND`` requests of each kind spread over their sizes (the quantiles of a size proxy: the
epochs, the dpi, a tolerance, the rows), in one fresh process that runs the service's app as a worker does
(``Settings.from_env``, glibc's allocator tuned as ``service.guards.tune_allocator`` does under the supervisor, one
BLAS thread, the app's start-up run), under ``httpx.ASGITransport``. For each request: a garbage collection and the
allocator's freed memory returned, the RSS read, the resident high-water mark reset (``/proc/self/clear_refs``, 5),
the request sent, then the high-water mark read: **the rise = VmHWM after - VmRSS before** (MB, 2^20 bytes), what the
request took above the worker's memory at its start, response included. Beside it the request's prediction, from the
service's DEBUG record (``ephem.service.memory``, service/guards.py): its charged peak (``Budget.peak_memory_mb``) and
what the worker's allowance counted (``admitted``: 0 for a request whose work reached no checkpoint). Each request
twice: **cold** (the first time in the process: a new posted body fills the per-body caches, as every soak POST
does) and **warm** (the same again: a catalogue body's caches kept, as under load).

Beside the sample, :data:`WOBBLE_CASES`: free-wobble figures, the largest under-prediction found. The service's
settings are the defaults (the soak's): a request over its own memory budget is refused 422 before its work, as there.

``--sequence N [--from K]`` measures instead the soak's first N requests in order (from the K-th), each once, as they
come (the per-body caches filled by the earlier ones): the diagnostic that found what the sample alone might miss
(~0.27 s a request: 1,100 in 300 s). ``--env NAME=VALUE`` sets the measured process's environment (another bound),
``--raw FILE`` keeps each measurement as a JSON line.

Linux only (``/proc``). Bounded: the child stops sending after ``--max-s`` (``MAX_RUN_S``, 300 s) and prints what it
measured. Run: ``.venv/bin/python benchmarks/bench_request_memory.py [--per-kind N] [--out FILE]`` (1.5-2.5 min on 2 shared cores).
"""
from __future__ import annotations

import argparse
import collections
import datetime as dt
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path
from urllib.parse import parse_qsl, urlsplit

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "benchmarks"))
sys.path.insert(0, str(ROOT))

SEED = 42
SEQUENCE = 4000                     # the soak's run: the requests sampled from
PER_KIND = 8
MAX_RUN_S = 300.0                   # the child sends no request past this
QUANTILES = (0.0, 0.2, 0.4, 0.6, 0.8, 0.9, 0.97, 1.0)


def _size(kind: str, path: str, body) -> float:
    """A proxy of a request's size, to spread the sample over small and large ones: epochs (or history steps),
    times 5 with a tolerance, times the dpi for a figure; rows for a batch."""
    if kind == "batch":
        return float(len(body))
    if body is not None:
        q = body.get("track") or body.get("history") or {}
    else:
        q = {k: float(v) if v.replace(".", "", 1).replace("-", "", 1).isdigit() else v
             for k, v in parse_qsl(urlsplit(path).query)}
    n = 1.0
    if "step_days" in q:
        n = (float(q["stop"]) - float(q["start"])) / float(q["step_days"])
    elif "step_years" in q:
        n = (float(q["stop_year"]) - float(q["start_year"])) / float(q["step_years"])
    elif "start" in q:
        n = float(q["stop"]) - float(q["start"])
    elif "start_year" in q:
        n = float(q["stop_year"]) - float(q["start_year"])
    if "tolerance_mas" in q:
        n *= 5.0
    if "dpi" in q:
        n *= float(q["dpi"])
    if "order" in q:
        n *= 1.0 + float(q.get("order") or 0)
    return n


#: beside the sample, the free wobble as figures (the soak draws it at its default step: 64 epochs a turn of the figure
#: axis about L, at most 100,000), the largest under-prediction found: the Earth's over 300 days (~300 turns) and 9.2
#: years (~3,400), Mars's over 500 days, the Moon's over 5,000 days (its turn: 27 days), PNG at 30-110 dpi and SVG
WOBBLE = "/v1/bodies/{0}/track.{3}?start={1}&stop={2}&kind=free-wobble&dpi={4}"
WOBBLE_CASES = [("earth", 2448425.8381, 2448725.8381, "png", 46), ("earth", 2448425.8381, 2448725.8381, "png", 110),
                ("earth", 2448425.8381, 2451799.6069, "png", 30), ("earth", 2448425.8381, 2451799.6069, "png", 46),
                ("earth", 2448425.8381, 2451799.6069, "png", 110), ("earth", 2448425.8381, 2451799.6069, "svg", 70),
                ("mars", 2448425.8381, 2448925.8381, "png", 100), ("moon", 2448425.8381, 2453425.8381, "png", 110)]


def sample(per_kind: int) -> list[tuple[str, str, str, object]]:
    from bench_memory_soak import soak_requests
    by_kind: dict[str, list] = {}
    for req in soak_requests(SEQUENCE, SEED):
        by_kind.setdefault(req[0], []).append(req)
    out = []
    qs = QUANTILES if per_kind == len(QUANTILES) else [i / max(1, per_kind - 1) for i in range(per_kind)]
    for kind, reqs in by_kind.items():
        ranked = sorted(reqs, key=lambda r: _size(r[0], r[2], r[3]))
        picked = sorted({round(q * (len(ranked) - 1)) for q in qs})
        out.extend(ranked[i] for i in picked)
    out.extend(("free-wobble figure", "GET", WOBBLE.format(*case), None) for case in WOBBLE_CASES)
    return out


def warmups() -> list[tuple[str, str, str, object]]:
    """One request of each kind from another seed, sent unmeasured first: the imports and tables of a worker's
    first requests (matplotlib, scipy, the catalogue), which a worker loads once."""
    from bench_memory_soak import soak_requests
    seen, out = set(), []
    for req in soak_requests(400, SEED + 1):
        if req[0] not in seen:
            seen.add(req[0])
            out.append(req)
    return out


# ----------------------------------------------------------------------------- the child: one worker's process

def _status(field: str) -> float:
    with open("/proc/self/status") as fh:
        for line in fh:
            if line.startswith(field):
                return int(line.split()[1]) / 1024
    return 0.0


def _reset_hwm() -> None:
    with open("/proc/self/clear_refs", "w") as fh:
        fh.write("5")


def child(requests: list, warm: list, labels: tuple[str, ...] = ("cold", "warm"), max_s: float = MAX_RUN_S) -> None:
    import asyncio
    import gc
    import logging

    from service.guards import release_free_memory, tune_allocator
    tune_allocator()                    # as under the supervisor, before any thread starts

    import httpx

    from service.app import create_app
    from service.settings import Settings

    records: list[logging.LogRecord] = []

    class Keep(logging.Handler):
        def emit(self, record):
            records.append(record)

    mlog = logging.getLogger("ephem.service.memory")
    mlog.setLevel(logging.DEBUG)
    mlog.addHandler(Keep())
    mlog.propagate = False

    settings = Settings.from_env()
    app = create_app(settings)
    t_end = time.monotonic() + max_s

    async def send(client, method, path, body):
        records.clear()
        gc.collect()
        release_free_memory()
        rss0 = _status("VmRSS:")
        _reset_hwm()
        t0 = time.perf_counter()
        r = await client.request(method, path, json=body)
        ms = (time.perf_counter() - t0) * 1e3
        rise = _status("VmHWM:") - rss0
        rec = records[-1] if records else None
        n, status = len(r.content), r.status_code
        del r
        gc.collect()
        release_free_memory()
        kept = _status("VmRSS:") - rss0       # what stays once it is freed: the per-body caches' new entries
        return {"status": status, "rise_mb": rise, "kept_mb": kept, "ms": ms, "bytes": n, "rss0_mb": rss0,
                "peak_mb": getattr(rec, "peak_memory_mb", None), "admitted_mb": getattr(rec, "admitted_memory_mb", None)}

    async def run():
        async with app.router.lifespan_context(app):
            transport = httpx.ASGITransport(app=app)
            async with httpx.AsyncClient(transport=transport, base_url="http://127.0.0.1", timeout=120) as client:
                for kind, method, path, body in warm:
                    await client.request(method, path, json=body)
                for kind, method, path, body in requests:
                    if time.monotonic() > t_end:
                        print(json.dumps({"stopped": True}), flush=True)
                        break
                    res = {"kind": kind, "method": method, "path": path, "body": body}
                    for label in labels:
                        records.clear()
                        r = await send(client, method, path, body)
                        res[label] = r
                    print(json.dumps(res), flush=True)

    asyncio.run(run())


# ----------------------------------------------------------------------------- the parent: the table

def _fmt(x: float | None) -> str:
    return "—" if x is None else f"{x:.1f}"


def describe(res: dict) -> str:
    if res["body"] is None:
        return f"`{res['method']} {res['path']}`"
    b = res["body"]
    if isinstance(b, list):
        return f"`{res['method']} {res['path']}` ({len(b)} rows)"
    extra = {k: b[k] for k in ("track", "history", "order") if k in b}
    return f"`{res['method']} {res['path']}` {json.dumps(extra, separators=(',', ':'))}"


def report(results: list[dict], per_kind: int, stopped: bool, max_s: float = MAX_RUN_S,
           sequence: tuple[int, int] | None = None, env: str = "the defaults") -> str:
    lines = []
    now = dt.datetime.now(dt.timezone.utc)
    try:
        from machine import machine_info
        mi = machine_info()
    except Exception:   # noqa: BLE001 - the header's machine lines are informative only
        mi = None
    what = (f"its requests {sequence[0]} to {sequence[0] + len(results) - 1} in order, each once" if sequence else
            f"{per_kind} a kind over their sizes and the free-wobble figures, each cold then warm")
    lines.append(f"run {now:%Y-%m-%d %H:%M} UTC: {len(results)} requests of the memory soak's sequence (seed "
                 f"{SEED}: {what}), one process")
    lines.append("")
    if mi:
        lines.extend(f"- {x}" for x in (mi if isinstance(mi, list) else [str(mi)]))
        lines.append("")
    lines.append(f"The service's settings: {env}.")
    lines.append("")
    if stopped:
        lines.append(f"**Stopped at {max_s:.0f} s**: the requests after were not measured.")
        lines.append("")
    lines.append("Per kind, MB: the charged peak (`Budget.peak_memory_mb`), what the worker's allowance counted of it "
                 "(`admitted`, 0 without a checkpoint), and the measured rise of the resident high-water mark over "
                 "the RSS at the request's start, cold and warm (`kept`: the RSS after it, freed memory returned, "
                 "less before: the per-body caches' new entries, bounded by EPHEM_MODEL_CACHE_MB); `over` counts the requests whose warm rise exceeds "
                 "what was admitted by more than 2 MB, `worst` the largest rise less admitted (cold or warm).")
    lines.append("")
    lines.append("| kind | n | statuses | charged p50 / max | admitted p50 / max | rise cold p50 / max | "
                 "rise warm p50 / max | over (warm) | worst rise - admitted |")
    lines.append("|---|---:|---|---:|---:|---:|---:|---:|---:|")
    kinds = list(dict.fromkeys(r["kind"] for r in results))
    for kind in kinds:
        rs = [r for r in results if r["kind"] == kind]

        def col(f):
            v = [f(r) or 0.0 for r in rs]
            return f"{statistics.median(v):.1f} / {max(v):.1f}"
        over = sum(1 for r in rs if r["warm"]["rise_mb"] > (r["warm"]["admitted_mb"] or 0.0) + 2.0)
        worst = max(max(r["cold"]["rise_mb"], r["warm"]["rise_mb"]) - (r["warm"]["admitted_mb"] or 0.0) for r in rs)
        statuses = ", ".join(f"{k}: {v}" for k, v in sorted(collections.Counter(r["warm"]["status"] for r in rs).items()))
        lines.append(f"| {kind} | {len(rs)} | {statuses} | {col(lambda r: r['warm']['peak_mb'])} | "
                     f"{col(lambda r: r['warm']['admitted_mb'])} | {col(lambda r: r['cold']['rise_mb'])} | "
                     f"{col(lambda r: r['warm']['rise_mb'])} | {over} | {worst:.1f} |")
    lines.append("")
    lines.append("The largest under-predictions (the rise less what was admitted, the larger of cold and warm):")
    lines.append("")
    lines.append("| kind | request | status | charged | admitted | rise cold | kept cold | rise warm | ms warm | "
                 "answer (kB) |")
    lines.append("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    gap = sorted(results, key=lambda r: -(max(r["cold"]["rise_mb"], r["warm"]["rise_mb"])
                                          - (r["warm"]["admitted_mb"] or 0.0)))
    for r in gap[:15]:
        w, c = r["warm"], r["cold"]
        lines.append(f"| {r['kind']} | {describe(r)} | {c['status']}/{w['status']} | {_fmt(w['peak_mb'])} | "
                     f"{_fmt(w['admitted_mb'])} | {c['rise_mb']:.1f} | {_fmt(c.get('kept_mb'))} | {w['rise_mb']:.1f} | {w['ms']:.0f} | "
                     f"{w['bytes'] / 1e3:.0f} |")
    lines.append("")
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--per-kind", type=int, default=PER_KIND)
    ap.add_argument("--kinds", default="", help="comma-separated kinds to keep (default: all)")
    ap.add_argument("--sequence", type=int, default=0,
                    help="instead of the sample: the soak's first N requests in order, each measured once, as it comes")
    ap.add_argument("--from", dest="first", type=int, default=0, help="--sequence: skip the requests before this one")
    ap.add_argument("--max-s", type=float, default=MAX_RUN_S, help="the child sends no request past this, seconds")
    ap.add_argument("--raw", default="", help="write each request's measurement to this file, a JSON line each")
    ap.add_argument("--env", action="append", default=[], help="NAME=VALUE in the measured process's environment")
    ap.add_argument("--out", default="", help="append the Markdown section to this file")
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.child:
        job = json.load(sys.stdin)
        child(job["requests"], job["warm"], tuple(job["labels"]), job["max_s"])
        return
    from bench_memory_soak import soak_requests
    reqs = soak_requests(args.sequence, SEED)[args.first:] if args.sequence else sample(args.per_kind)
    labels = ("cold",) if args.sequence else ("cold", "warm")
    if args.kinds:
        keep = set(args.kinds.split(","))
        reqs = [r for r in reqs if r[0] in keep]
    for blas in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ.setdefault(blas, "1")  # as service/gunicorn_conf.py sets for its workers (and the header says)
    env = dict(os.environ)
    env.pop("EPHEM_SUPERVISED", None)     # no watchdog: it would trim on its own clock and recycle this process
    env.update(kv.split("=", 1) for kv in args.env)
    job = json.dumps({"requests": reqs, "warm": warmups(), "labels": labels, "max_s": args.max_s})
    t0 = time.monotonic()
    proc = subprocess.run([sys.executable, __file__, "--child"], input=job, capture_output=True, text=True,
                          cwd=ROOT, env=env, timeout=args.max_s + 240)
    results, stopped = [], False
    for line in proc.stdout.splitlines():
        if not line.startswith("{"):
            continue
        d = json.loads(line)
        if d.get("stopped"):
            stopped = True
        else:
            d.setdefault("warm", d["cold"])       # --sequence: measured once
            results.append(d)
    if proc.returncode:
        sys.stderr.write(proc.stderr[-4000:])
    if args.env:
        text_env = ", ".join(args.env)
    else:
        text_env = "the defaults"
    text = report(results, args.per_kind, stopped, args.max_s, (args.first, args.sequence) if args.sequence else None, text_env) + f"\n({time.monotonic() - t0:.0f} s)\n"
    print(text)
    if args.out:
        with open(args.out, "a") as fh:
            fh.write("\n" + text)
    if args.raw:
        Path(args.raw).write_text("\n".join(json.dumps(r) for r in results) + "\n")


if __name__ == "__main__":
    main()
