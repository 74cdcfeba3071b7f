"""Load benchmark, kill -9 run: how soon keep-alive traffic comes back to both workers after one is killed.

The script starts the service as ``make serve`` does (gunicorn, ``service/gunicorn_conf.py``, 2 uvicorn workers on
127.0.0.1) from a source tree (``--src``, default this checkout), loads it with ``wrk`` (50 keep-alive connections,
2 threads, 30 s on ``GET /v1/bodies/vesta/precession``), and at 10 s kills one worker with SIGKILL. gunicorn's
master starts a replacement; the question is when the replacement serves its share again. A keep-alive
connection stays with the worker that accepted it: the killed worker's clients reconnect at once and all land on
the survivor (the replacement is still importing), and unless the server closes connections now and then they
stay there for the rest of the run.

Which worker answered each request: the benchmark serves the tree through a small gunicorn configuration of its
own (in a temporary directory) that runs the tree's ``service/gunicorn_conf.py`` and then sets a default response
header ``x-bench-worker: <pid>`` in each worker's uvicorn configuration (``post_worker_init``): uvicorn writes it
with its ``date`` and ``server`` headers, so the service's code path is the same as without it. wrk's Lua
``response`` hook counts the answers per wall-clock second and per pid; the script also samples the master's
children every 0.1 s and its log (the replacement's ``Application startup complete``).

Reported: requests per second per worker, the replacement's start (spawned, ready, first answer), and the
rebalancing time: from the kill to the first second from which on each of the two live workers answers at least
a quarter of every second's requests until the end of the run (goal: <= 5 s).

Every request goes to 127.0.0.1; the server is always stopped (SIGTERM, then SIGKILL of its process group).
Prints a Markdown section; ``--out FILE`` appends it to a results file.

Run: ``.venv/bin/python benchmarks/bench_kill_rebalance.py`` (~40 s); options: ``--src DIR``, ``--label TEXT``,
``--duration S``, ``--kill-at S``, ``--no-kill`` (a control run), ``--connections N``, ``--threads T``,
``--path URL``, ``--env NAME=VALUE`` (repeatable: the server's environment), ``--out FILE``.
"""
from __future__ import annotations

import argparse
import collections
import contextlib
import datetime as dt
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "benchmarks"))
from bench_memory_soak import HOST, Server, children_of, free_port  # noqa: E402
from machine import machine_info  # noqa: E402

HEADER = "x-bench-worker"
#: a live worker "serves" in a second when it answers at least this share of that second's requests
FAIR_SHARE = 0.25

#: the benchmark's gunicorn configuration: the tree's own, then the header naming the worker (instrumentation only)
CONFIG = f'''
exec(compile(open("service/gunicorn_conf.py").read(), "service/gunicorn_conf.py", "exec"))
_tree_post_worker_init = globals().get("post_worker_init")


def post_worker_init(worker):
    if _tree_post_worker_init is not None:
        _tree_post_worker_init(worker)
    worker.config.headers.append(("{HEADER}", str(worker.pid)))    # a uvicorn default header: no ASGI work
'''

#: wrk's script: each answer counted by (wall-clock second, worker pid); the counts printed at the end
LUA = f'''
counts = {{}}
local threads = {{}}

function setup(thread)
  table.insert(threads, thread)
end

function response(status, headers, body)
  local pid = headers["{HEADER}"] or "none"
  local key = os.time() .. " " .. pid .. " " .. (status < 400 and "ok" or "err")
  counts[key] = (counts[key] or 0) + 1
end

function done(summary, latency, requests)
  for _, t in ipairs(threads) do
    for key, n in pairs(t:get("counts")) do
      io.write("COUNT ", key, " ", n, "\\n")
    end
  end
end
'''


def sample(master: int, server: Server, stop: threading.Event, out: dict) -> None:
    """Every 0.1 s: the master's children (when each pid was first and last seen) and the log's start-up lines."""
    seen_ready: set[int] = set()
    while not stop.is_set():
        now = time.time()
        for pid in children_of(master):
            out["first_seen"].setdefault(pid, now)
            out["last_seen"][pid] = now
        for m in re.finditer(r"\[(\d+)\] \[INFO\] Application startup complete", server.log_text()):
            pid = int(m.group(1))
            if pid not in seen_ready:
                seen_ready.add(pid)
                out["ready"].setdefault(pid, now)
        stop.wait(0.1)


def run(args) -> dict:
    wrk = shutil.which("wrk")
    if wrk is None:
        raise SystemExit("wrk is not on PATH (Debian: apt-get install wrk)")
    with tempfile.TemporaryDirectory(prefix="ephem-kill-") as tmp:
        conf = Path(tmp) / "bench_gunicorn_conf.py"
        conf.write_text(CONFIG)
        lua = Path(tmp) / "count.lua"
        lua.write_text(LUA)
        server = Server(args.src, free_port(), 2, Path(tmp), {"EPHEM_SUPERVISED": "1", **args.env}, config=str(conf))
        res = {"first_seen": {}, "last_seen": {}, "ready": {}}
        stop = threading.Event()
        try:
            print(f"serving {args.src}: {' '.join(server.cmd)}", flush=True)
            server.start()
            res["ready_s"] = server.wait_ready()
            sampler = threading.Thread(target=sample, args=(server.proc.pid, server, stop, res), daemon=True)
            sampler.start()
            cmd = [wrk, f"-t{args.threads}", f"-c{args.connections}", f"-d{args.duration}s", "--latency",
                   "-s", str(lua), f"http://{HOST}:{server.port}{args.path}"]
            res["cmd"] = " ".join(["wrk", *cmd[1:-2], lua.name, f"http://{HOST}:<port>{args.path}"])
            print("load:", res["cmd"], flush=True)
            res["t0"] = time.time()
            proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
            time.sleep(args.kill_at)
            victims = children_of(server.proc.pid)
            if args.no_kill:
                res.update(victim=victims[0], survivor=victims[1], kill_t=time.time() + 3600)
                out, _ = proc.communicate(timeout=args.duration + 60)
                res["wrk"] = out
                return res
            res["victim"] = victims[0]
            res["survivor"] = victims[1] if len(victims) > 1 else None
            res["kill_t"] = time.time()
            os.kill(res["victim"], signal.SIGKILL)
            print(f"killed worker {res['victim']} at {res['kill_t'] - res['t0']:.1f} s", flush=True)
            out, _ = proc.communicate(timeout=args.duration + 60)
            res["wrk"] = out
        finally:
            stop.set()
            server.stop()
    return res


def analyse(res: dict, args) -> dict:
    counts: dict[int, collections.Counter] = collections.defaultdict(collections.Counter)     # second -> pid -> n
    errors = collections.Counter()
    for line in res["wrk"].splitlines():
        if line.startswith("COUNT "):
            _, sec, pid, kind, n = line.split()
            if kind == "ok":
                counts[int(sec)][pid] += int(n)
            else:
                errors[int(sec)] += int(n)
    t0 = int(res["t0"])
    secs = sorted(s for s in counts if s >= t0)
    if secs:
        secs = secs[1:-1] if len(secs) > 2 else secs       # the first and last seconds are partial
    kill_sec = res["kill_t"]
    victim, survivor = str(res["victim"]), str(res["survivor"])
    replacement = next((p for p, t in sorted(res["first_seen"].items(), key=lambda kv: kv[1])
                        if t > res["kill_t"] - 0.5 and p not in (res["victim"], res["survivor"])), None)
    rep = str(replacement)
    rows = []
    for s in secs:
        c = counts[s]
        total = sum(c.values())
        rows.append({"t": s - res["t0"], "sec": s, "total": total, "victim": c.get(victim, 0),
                     "survivor": c.get(survivor, 0), "replacement": c.get(rep, 0), "errors": errors.get(s, 0)})
    # rebalanced: the first second after the kill in which both live workers each answer >= FAIR_SHARE of it
    after = [r for r in rows if r["sec"] >= kill_sec]
    balanced_from = next((r for r in after if r["total"] > 0
                          and min(r["survivor"], r["replacement"]) >= FAIR_SHARE * r["total"]), None)
    rest = [] if balanced_from is None else [r for r in after if r["sec"] >= balanced_from["sec"]]
    first_answer = next((r for r in after if r["replacement"] > 0), None)
    before = [r["total"] for r in rows if r["sec"] + 1 <= kill_sec]
    last = [r["total"] for r in rows[-10:]]
    summary = {"rows": rows, "replacement": replacement,
               "spawned_s": res["first_seen"].get(replacement, float("nan")) - res["kill_t"] if replacement else None,
               "ready_s": res["ready"].get(replacement, float("nan")) - res["kill_t"] if replacement else None,
               # the end of the (whole, wall-clock) second in which it happened, from the kill: an upper bound
               "first_answer_s": None if first_answer is None else first_answer["sec"] + 1 - res["kill_t"],
               "balanced_s": None if balanced_from is None else balanced_from["sec"] + 1 - res["kill_t"],
               "replacement_share": (sum(r["replacement"] for r in rest) / max(1, sum(r["total"] for r in rest))
                                     if rest else 0.0),
               "seconds_after": len(rest),
               "seconds_unfair": sum(1 for r in rest if min(r["survivor"], r["replacement"]) < FAIR_SHARE * r["total"]),
               "rps_before": sum(before) / len(before) if before else float("nan"),
               "rps_last10": sum(last) / len(last) if last else float("nan")}
    return summary


def render(res: dict, s: dict, args, started: str) -> str:
    def fmt(x):
        return "—" if x is None else f"{x:+.1f} s"
    tail = [ln for ln in res["wrk"].splitlines() if not ln.startswith("COUNT ")]
    lines = [f"## {args.label}", "",
             f"- run: {started}; served tree: {args.tree_name}; server environment: "
             + (", ".join(f"`{k}={v}`" for k, v in args.env.items()) or "the defaults"),
             *(f"- {line}" for line in machine_info()),
             "- the machine is shared: other people's work ran on the same 2 cores; wrk ran there too",
             f"- load: `{res['cmd']}`; "
             + ("no worker killed (a control run)" if args.no_kill else
                f"worker {res['victim']} killed (SIGKILL) at {res['kill_t'] - res['t0']:.1f} s; survivor "
                f"{res['survivor']}, replacement {s['replacement']}"), "",
             *([f"Throughput {s['rps_last10']:,.0f} req/s over the last 10 s; worker {res['victim']} answered "
                f"{sum(r['victim'] for r in s['rows']) / max(1, sum(r['total'] for r in s['rows'])):.0%} of the "
                "requests."] if args.no_kill else []),
             "" if args.no_kill else
             f"**Both workers serve again within {fmt(s['balanced_s'])} of the kill** (by the end of the first "
             f"second in which the survivor and the replacement each answer >= {FAIR_SHARE:.0%} of the requests; "
             "goal <= 5 s; "
             + ("never within the run" if s["balanced_s"] is None else
                f"from then to the end the replacement answered {s['replacement_share']:.0%} of the requests, and "
                f"{s['seconds_unfair']} of those {s['seconds_after']} seconds had a worker under {FAIR_SHARE:.0%}")
             + "). The replacement: "
             f"spawned {fmt(s['spawned_s'])}, ready (its `Application startup complete`) {fmt(s['ready_s'])}, "
             f"its first answers within {fmt(s['first_answer_s'])}. Throughput: "
             f"{s['rps_before']:,.0f} req/s before the kill, {s['rps_last10']:,.0f} req/s over the last 10 s.", "",
             "| t (s) | total req/s | killed worker | survivor | replacement | errors |",
             "|---:|---:|---:|---:|---:|---:|"]
    for r in s["rows"]:
        mark = " ← kill" if r["sec"] <= res["kill_t"] < r["sec"] + 1 else ""
        lines.append(f"| {r['t']:.0f}{mark} | {r['total']} | {r['victim']} | {r['survivor']} | {r['replacement']} | "
                     f"{r['errors']} |")
    lines += ["", "wrk's summary:", "", "```", *[ln for ln in tail if ln.strip()][:30], "```"]
    return "\n".join(lines) + "\n"


def parse_args(argv: list[str]) -> argparse.Namespace:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--src", type=Path, default=ROOT)
    p.add_argument("--label", default="kill -9 under keep-alive load")
    p.add_argument("--duration", type=int, default=30)
    p.add_argument("--kill-at", type=float, default=10.0)
    p.add_argument("--no-kill", action="store_true", help="a control run: no worker killed")
    p.add_argument("--connections", type=int, default=50)
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--path", default="/v1/bodies/vesta/precession")
    p.add_argument("--env", action="append", default=[])
    p.add_argument("--out", type=Path, default=None)
    args = p.parse_args(argv)
    args.env = dict(kv.split("=", 1) for kv in args.env)
    args.src = args.src.resolve()
    args.tree_name = "this checkout" if args.src == ROOT else f"another tree ({args.src.name})"
    with contextlib.suppress(OSError, subprocess.SubprocessError):
        rev = subprocess.run(["git", "-C", str(args.src), "rev-parse", "--short", "HEAD"], capture_output=True,
                             text=True, timeout=10).stdout.strip()
        dirty = subprocess.run(["git", "-C", str(args.src), "status", "--porcelain", "--untracked-files=no"],
                               capture_output=True, text=True, timeout=10).stdout.strip()
        args.tree_name += f", commit {rev}" + (" with uncommitted changes" if dirty else "")
    return args


def main(argv: list[str] | None = None) -> int:
    args = parse_args(sys.argv[1:] if argv is None else argv)
    started = dt.datetime.now(dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    res = run(args)
    s = analyse(res, args)
    report = render(res, s, args, started)
    print()
    print(report)
    if args.out is not None:
        with open(args.out, "a") as fh:
            fh.write("\n" + report)
        print(f"appended to {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
