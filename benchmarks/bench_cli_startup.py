"""Start-up cost of the CLI: wall and CPU time of a one-body answer in a fresh interpreter.

    .venv/bin/python benchmarks/bench_cli_startup.py                    # ephem precession vesta, 11 runs
    .venv/bin/python benchmarks/bench_cli_startup.py -n 7 -- nutation itokawa --order 4
    .venv/bin/python benchmarks/bench_cli_startup.py --src /tmp/before --src .   # A/B, runs interleaved
    .venv/bin/python benchmarks/bench_cli_startup.py --src /tmp/before --src . --row history-earth   # a named row
    .venv/bin/python benchmarks/bench_cli_startup.py --src /tmp/before --src . --all-rows           # every row

Each run is a new subprocess (``python -m ephem.cli ARGS``, the code the ``ephem`` script runs), so
the time is almost all imports plus one catalogue read. The runs read compiled bytecode, as an installed copy
does (pip compiles at install; a checkout writes it at its first run): the children's ``.pyc`` go to a
temporary ``PYTHONPYCACHEPREFIX`` and ``PYTHONDONTWRITEBYTECODE`` is lifted for them, or every run would compile
~90 modules again (0.15 s here, where the environment sets it). ``python -c "import numpy"`` runs interleaved
with the rest, and each row's ratio to it is printed (issue 33's measure). Prints min and median wall and CPU time per
source tree and the heavy modules the command imported (a second subprocess lists ``sys.modules``
after running it). ``--src DIR`` runs the ``ephem`` package of another checkout (``git worktree`` or
``git archive`` of a commit) with this interpreter; with several, the runs alternate between them so
that the load of a shared machine falls on all alike. ``--row NAME`` runs one of :data:`ROWS`, the commands of
RESULTS_cli.md's tables (repeatable; ``--all-rows``: each in turn). Results: benchmarks/RESULTS_cli.md.
"""
from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path

from machine import tree_env   # benchmarks/machine.py: this directory is first on the path

ROOT = Path(__file__).resolve().parent.parent
HEAVY = ("matplotlib", "scipy.integrate", "scipy", "fastapi", "starlette", "pydantic", "uvicorn",
         "astropy.coordinates", "astropy", "skyfield", "rich")

#: the commands of RESULTS_cli.md's tables: issue 33's one-body answers, and issue 39's 4-Myr history of the Earth
#: (its goal: 0.5 s of CPU, the process's start included)
ROWS = {
    "precession-vesta": ["precession", "vesta"],
    "nutation-earth": ["nutation", "earth"],
    "track-earth": ["track", "earth", "--start", "2000-01-01", "--stop", "2000-04-01", "--step-days", "30"],
    "precession-moon": ["precession", "moon"],
    "history-earth": ["history", "earth", "--start-year", "-3000000", "--stop-year", "1000000", "--step-years", "1000",
                      "--format", "json"],
    "history-earth-table": ["history", "earth", "--start-year", "-3000000", "--stop-year", "1000000", "--step-years",
                            "1000", "--format", "table", "--quiet"],
}

_PROBE = """
import contextlib, io, sys
from ephem.cli import app
with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
    try:
        app(args={args!r}, prog_name="ephem")
    except BaseException:  # SystemExit, or a failure: the modules imported so far are still the answer
        pass
print(" ".join(sorted(sys.modules)))
"""


def _children_cpu() -> float:
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def run_once(args: list[str], src: Path = ROOT, command: list[str] | None = None) -> tuple[float, float]:
    """(wall, CPU) seconds of one ``ephem ARGS`` (or of ``command``) in a fresh interpreter; CPU (user +
    system) is the steadier of the two on a machine others share."""
    cpu0, t0 = _children_cpu(), time.perf_counter()
    proc = subprocess.run(command or [sys.executable, "-m", "ephem.cli", *args], cwd=src, env=tree_env(src),
                          capture_output=True, text=True)
    wall, cpu = time.perf_counter() - t0, _children_cpu() - cpu0
    if proc.returncode not in (0, 2, 3):  # 2, 3: a refusal is an answer too (a usage error is timed as one)
        raise SystemExit(f"ephem {' '.join(args)} failed ({proc.returncode}) in {src}:\n{proc.stderr}")
    return wall, cpu


def heavy_modules(args: list[str], src: Path = ROOT) -> list[str]:
    """The modules of HEAVY (or their submodules) that ``ephem ARGS`` imports."""
    proc = subprocess.run([sys.executable, "-c", _PROBE.format(args=args)], cwd=src, env=tree_env(src),
                          capture_output=True, text=True, check=True)
    loaded = proc.stdout.strip().splitlines()[-1].split()
    return [h for h in HEAVY if any(m == h or m.startswith(h + ".") for m in loaded)]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-n", type=int, default=11, help="runs per source tree (default 11)")
    ap.add_argument("--src", type=Path, action="append", help="a checkout whose ephem package to run (repeatable; "
                    "default: this one)")
    ap.add_argument("--row", action="append", choices=sorted(ROWS), help="a named command of ROWS (repeatable)")
    ap.add_argument("--all-rows", action="store_true", help="every command of ROWS, in turn")
    ap.add_argument("args", nargs="*", help="the ephem command (default: precession vesta)")
    opts = ap.parse_args()
    srcs = [s.resolve() for s in (opts.src or [ROOT])]
    rows = list(ROWS) if opts.all_rows else (opts.row or [])
    for args in [ROWS[r] for r in rows] or [opts.args or ["precession", "vesta"]]:
        measure(args, srcs, opts.n)


def measure(args: list[str], srcs: list[Path], n: int) -> None:
    """Print the table of ``ephem ARGS`` run ``n`` times in each tree of ``srcs``, interleaved with import numpy."""
    numpy_only = [sys.executable, "-c", "import numpy"]
    for src in srcs:
        run_once(args, src)  # warm the OS file cache and write the .pyc files
    run_once(args, ROOT, numpy_only)
    times: dict[Path, list[tuple[float, float]]] = {src: [] for src in srcs}
    reference: list[tuple[float, float]] = []
    for _ in range(n):
        for src in srcs:
            times[src].append(run_once(args, src))
        reference.append(run_once(args, ROOT, numpy_only))
    numpy_wall = min(w for w, _ in reference)
    print(f"ephem {' '.join(args)}: {n} runs each, load average {os.getloadavg()[0]:.1f} "
          f"on {os.cpu_count()} CPUs")
    print(f"python -c 'import numpy': wall min {numpy_wall:.3f} s, median "
          f"{statistics.median(w for w, _ in reference):.3f} s")
    print("| source | wall min (s) | ÷ import numpy | wall median (s) | CPU min (s) | CPU median (s) | heavy modules "
          "imported |")
    print("|---|---|---|---|---|---|---|")
    for src in srcs:
        wall, cpu = zip(*times[src])
        print(f"| {src} | {min(wall):.3f} | {min(wall) / numpy_wall:.1f}x | {statistics.median(wall):.3f} | "
              f"{min(cpu):.3f} | {statistics.median(cpu):.3f} | {', '.join(heavy_modules(args, src)) or '-'} |")


if __name__ == "__main__":
    main()
