#!/usr/bin/env python3
"""Start `make serve` and `make test` at the same moment on a fresh copy of the project and check
that both get a working .venv (tools/bootstrap_venv.py's lock: one builds, the other waits).

    python3 tools/check_concurrent_bootstrap.py [--dest /tmp/ephem-concurrent] [--test-args ARGS]

The copy (of this work tree, or of --source) is what a fresh clone would hold: the files git
knows of (committed, plus uncommitted and untracked-but-not-ignored ones, so a change can be
checked before it is committed), no .venv.
`make serve PORT=<free loopback port>` is stopped (its process group gets SIGTERM) once it has
answered /healthz. Passes (exit 0) when: /healthz answered 200, pytest ran to its summary line
(`make test`'s own status is reported, not judged: a failing test is not a bootstrap problem),
exactly one of the two built the venv, no log shows a broken install (`ModuleNotFoundError`,
`No module named`, a bootstrap failure), and the venv's stamp is there. Not a pytest test: it
takes minutes and builds a venv. Only loopback is contacted.
"""
from __future__ import annotations

import argparse
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
BROKEN = re.compile(r"ModuleNotFoundError|No module named|bootstrap_venv: failed")


def fresh_copy(source: Path, dest: Path) -> None:
    if dest.exists():
        shutil.rmtree(dest)
    files = subprocess.run(["git", "ls-files", "-z", "--cached", "--others", "--exclude-standard"],
                           cwd=source, check=True, capture_output=True).stdout.decode().split("\0")
    for name in filter(None, files):
        src = source / name
        if src.is_file() and not name.startswith(".venv/"):
            (dest / name).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(src, dest / name)


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def healthz(port: int) -> int | None:
    try:
        with urllib.request.urlopen(f"http://127.0.0.1:{port}/healthz", timeout=2) as r:
            return r.status
    except OSError:
        return None


def stop(proc: subprocess.Popen) -> None:
    if proc.poll() is None:
        os.killpg(proc.pid, signal.SIGTERM)
        try:
            proc.wait(30)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--dest", type=Path, default=Path(os.environ.get("TMPDIR", "/tmp")) / "ephem-concurrent")
    p.add_argument("--source", type=Path, default=ROOT, help="the work tree to copy (default: this one)")
    p.add_argument("--test-args", default="", help="PYTEST_ARGS for make test (default: the whole suite)")
    p.add_argument("--timeout", type=float, default=1200, help="seconds for each of the two")
    a = p.parse_args()

    fresh_copy(a.source.resolve(), a.dest)
    port = free_port()
    logs = {name: open(a.dest / f"{name}.log", "w+") for name in ("serve", "test")}
    cmds = {"serve": ["make", "serve", f"PORT={port}", "HOST=127.0.0.1"],
            "test": ["make", "test", f"PYTEST_ARGS={a.test_args}"]}
    t0 = time.monotonic()
    procs = {name: subprocess.Popen(cmd, cwd=a.dest, stdout=logs[name], stderr=subprocess.STDOUT,
                                    stdin=subprocess.DEVNULL, start_new_session=True)
             for name, cmd in cmds.items()}
    print(f"started {cmds['serve']} and {cmds['test']} in {a.dest}", flush=True)

    served = None
    try:
        deadline = t0 + a.timeout
        while time.monotonic() < deadline and procs["serve"].poll() is None:
            if healthz(port) == 200:
                served = time.monotonic() - t0
                break
            time.sleep(0.5)
    finally:
        stop(procs["serve"])
    print(f"serve: /healthz {'answered 200 after %.0f s' % served if served else 'never answered'}", flush=True)
    try:
        test_rc = procs["test"].wait(max(1.0, t0 + a.timeout - time.monotonic()))
    except subprocess.TimeoutExpired:
        stop(procs["test"])
        test_rc = None
    test_s = time.monotonic() - t0

    text = {}
    for name, f in logs.items():
        f.seek(0)
        text[name] = f.read()
        f.close()
    summary = [ln for ln in text["test"].splitlines() if re.search(r"\b(passed|failed|no tests ran)\b.* in ", ln)]
    print(f"test: make exited {test_rc} after {test_s:.0f} s; pytest: {summary[-1] if summary else 'no summary line'}")
    built = [n for n in text if "creating" in text[n] and "from scratch" in text[n]]
    waited = [n for n in text if "waiting for it to finish" in text[n]]
    print(f"built the venv: {built}; waited for the other: {waited}")
    broken = {n: m.group(0) for n in text if (m := BROKEN.search(text[n]))}
    stamp = (a.dest / ".venv" / ".bootstrap-stamp").exists()
    ok = bool(served) and bool(summary) and len(built) == 1 and not broken and stamp
    if broken:
        print(f"broken install signs: {broken}")
    print(f"stamp present: {stamp}; logs: {a.dest}/serve.log, {a.dest}/test.log")
    print("PASS" if ok else "FAIL")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
