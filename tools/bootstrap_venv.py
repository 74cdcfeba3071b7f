#!/usr/bin/env python3
"""Create or update the project's virtualenv (.venv) from the lock, as one locked, idempotent step.

`make serve`, `make test` (and every other target that needs the venv) run this first:

    python3 tools/bootstrap_venv.py [--venv .venv] [--lock constraints.txt] [--extras all,test]

* **One at a time.** The whole check-and-install runs under an exclusive `fcntl.flock` on
  `<venv>/.bootstrap.lock`. Two `make` commands started together (say `make serve` and
  `make test` on a fresh clone) therefore never run `python -m venv` or pip on the same venv at
  once: the second waits for the first and then finds a complete venv. (The lock file lives in
  the venv directory, which is never removed, only emptied, so the lock stays valid; the kernel
  drops the lock when its holder dies, so a crash leaves no stale lock. The `python -m venv` and
  pip children hold it too: a pip left running by a killed bootstrap still keeps others out.)
* **Complete or redone.** A stamp file `<venv>/.bootstrap-stamp`, holding a hash of what was
  installed (the lock file, pyproject.toml, the install command, the Python version), is written
  only after every install step has succeeded. Before touching the venv the script writes
  `<venv>/.bootstrap-incomplete`; if it finds that marker, an earlier run died half-way and the
  venv is emptied and built again from scratch. A stamp that matches means nothing to do
  (~50 ms); one that does not (constraints.txt or pyproject.toml changed) means pip brings the
  venv up to date in place.
* **Pinned.** pip is first set to the version pinned in the lock (`pip==X` there), then the
  project is installed editable with every extra (`all`: the service, the batch engine, the
  figures, the N-body rung) and the `test` one as
  `pip install -c LOCK --build-constraint LOCK -e '.[all,test]'`: every dependency, and the build
  backend used for the editable build (hatchling), at the lock's version.

Needs only Python >= 3.11 (the one that runs it is the one the venv is made from) and pip's
configured index. Without fcntl (not POSIX) it runs unlocked, with a warning.
"""
from __future__ import annotations

import argparse
import hashlib
import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

try:
    import fcntl
except ImportError:  # pragma: no cover - not POSIX
    fcntl = None

ROOT = Path(__file__).resolve().parent.parent
LOCK_NAME = ".bootstrap.lock"
STAMP_NAME = ".bootstrap-stamp"
INCOMPLETE_NAME = ".bootstrap-incomplete"
# pip options for every install; part of the stamp, so changing them reinstalls
PIP_OPTIONS = ["--quiet", "--progress-bar", "off", "--disable-pip-version-check"]


def say(msg: str) -> None:
    print(f"bootstrap_venv: {msg}", file=sys.stderr, flush=True)


def venv_python(env: Path) -> Path:
    return env / ("Scripts/python.exe" if os.name == "nt" else "bin/python")


def pinned_pip(lock: Path) -> str:
    m = re.search(r"^pip==(\S+)", lock.read_text(), re.MULTILINE)
    if not m:
        raise SystemExit(f"bootstrap_venv: {lock} pins no pip version (a line 'pip==X'); run `make lock`")
    return m.group(1)


def install_commands(py: Path, lock: Path, extras: str) -> list[list[str]]:
    target = f".[{extras}]" if extras else "."
    return [
        [str(py), "-m", "pip", "install", *PIP_OPTIONS, f"pip=={pinned_pip(lock)}"],
        [str(py), "-m", "pip", "install", *PIP_OPTIONS, "--constraint", str(lock),
         "--build-constraint", str(lock), "--editable", target],
    ]


def expected_stamp(lock: Path, extras: str) -> str:
    h = hashlib.sha256()
    for part in (lock.read_bytes(), (ROOT / "pyproject.toml").read_bytes(), extras.encode(),
                 repr(PIP_OPTIONS).encode(), sys.version.encode(), sys.platform.encode()):
        h.update(hashlib.sha256(part).digest())
    return h.hexdigest()


def venv_version(env: Path) -> str | None:
    """The Python version recorded in the venv's pyvenv.cfg (None if there is none)."""
    try:
        text = (env / "pyvenv.cfg").read_text()
    except OSError:
        return None
    m = re.search(r"^version(?:_info)?\s*=\s*(\S+)", text, re.MULTILINE)
    return m.group(1) if m else None


def pip_works(py: Path) -> bool:
    try:
        return subprocess.run([str(py), "-c", "import pip._internal, pip._vendor.packaging"],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, timeout=120).returncode == 0
    except (OSError, subprocess.SubprocessError):
        return False


def empty_dir_but_lock(env: Path) -> None:
    """Remove everything in the venv directory but the lock file and the incomplete-marker."""
    for entry in env.iterdir():
        if entry.name in (LOCK_NAME, INCOMPLETE_NAME):
            continue
        if entry.is_dir() and not entry.is_symlink():
            shutil.rmtree(entry)
        else:
            entry.unlink()


def acquire(env: Path):
    """An open file holding the exclusive lock (released when closed or when the process dies)."""
    f = open(env / LOCK_NAME, "a+")
    if fcntl is None:  # pragma: no cover
        say("no fcntl here: running without the lock (do not start two bootstraps at once)")
        return f
    try:
        fcntl.flock(f.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        f.seek(0)
        holder = f.read().strip() or "?"
        say(f"another bootstrap of {env} is running (pid {holder}); waiting for it to finish")
        t0 = time.monotonic()
        fcntl.flock(f.fileno(), fcntl.LOCK_EX)
        say(f"waited {time.monotonic() - t0:.0f} s")
    f.seek(0)
    f.truncate()
    f.write(f"{os.getpid()}\n")
    f.flush()
    return f


def run(cmd: list[str], held) -> None:
    """Run cmd holding the lock too (the child inherits the locked file description): if this
    script is killed alone, a pip still writing into the venv keeps the others waiting."""
    r = subprocess.run(cmd, cwd=ROOT, pass_fds=(held.fileno(),) if fcntl else ())
    if r.returncode:
        raise SystemExit(f"bootstrap_venv: failed ({r.returncode}): {' '.join(cmd)}\n"
                         "bootstrap_venv: the venv is marked incomplete; the next run rebuilds it")


def bootstrap(env: Path, lock: Path, extras: str, fresh: bool) -> None:
    env.mkdir(parents=True, exist_ok=True)
    with acquire(env) as held:
        stamp_file, marker = env / STAMP_NAME, env / INCOMPLETE_NAME
        want = expected_stamp(lock, extras)
        py = venv_python(env)
        have = stamp_file.read_text().strip() if stamp_file.exists() else None
        if not fresh and have == want and py.exists() and not marker.exists():
            say(f"{env} is up to date with {lock.name}")
            return

        mine = ".".join(map(str, sys.version_info[:3]))
        reason = ("asked for a fresh venv" if fresh
                  else "an earlier bootstrap did not finish" if marker.exists()
                  else "no venv yet" if not py.exists()
                  else f"it was made with Python {venv_version(env)}, this is {mine}" if venv_version(env) != mine
                  else "its pip does not work" if not pip_works(py)
                  else None)
        t0 = time.monotonic()
        if reason:
            say(f"creating {env} from scratch ({reason})")
            stamp_file.unlink(missing_ok=True)
            marker.touch()  # before anything is removed: a crash from here on means "rebuild"
            empty_dir_but_lock(env)
            run([sys.executable, "-m", "venv", str(env)], held)
        else:
            why = "its stamp is from another lock or pyproject.toml" if have else "it has no stamp"
            say(f"updating {env} in place ({why})")
            marker.touch()
            stamp_file.unlink(missing_ok=True)

        say(f"installing the project ('.[{extras}]') with the versions of {lock.name}")
        for cmd in install_commands(py, lock, extras):
            run(cmd, held)
        tmp = stamp_file.with_name(STAMP_NAME + ".tmp")
        tmp.write_text(want + "\n")
        os.replace(tmp, stamp_file)  # the stamp appears whole, and only now
        marker.unlink()
        say(f"{env} ready in {time.monotonic() - t0:.0f} s")


def main(argv: list[str] | None = None) -> None:
    if sys.version_info < (3, 11):
        raise SystemExit(f"bootstrap_venv: needs Python >= 3.11, this is {sys.version.split()[0]} "
                         "(run make with PYTHON=python3.11 or newer)")
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--venv", default=".venv", help="the virtualenv directory (relative to the project root)")
    p.add_argument("--lock", default="constraints.txt", help="the lock: a pip constraints file")
    p.add_argument("--extras", default="all,test", help="extras of the project to install ('' for none)")
    p.add_argument("--fresh", action="store_true", help="empty the venv and build it again")
    a = p.parse_args(argv)
    lock = (ROOT / a.lock).resolve()
    if not lock.is_file():
        raise SystemExit(f"bootstrap_venv: no lock file {lock}")
    bootstrap(ROOT / a.venv, lock, a.extras, a.fresh)


if __name__ == "__main__":
    main()
