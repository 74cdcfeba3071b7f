"""Benchmark: a spin-axis track at 10^6 epochs against one numpy.sin over the same array (issue 33's rows).

    .venv/bin/python benchmarks/bench_track.py                              # this checkout (make bench)
    .venv/bin/python benchmarks/bench_track.py --src /tmp/base33 --src .   # before / after, runs interleaved

Vesta, exact Hansen coefficients, 10^6 epochs over 20 years. Rows: the nutation alone, the angles ψ, Δψ, Δε, ε and
the full track with the pole's RA and Dec, at arbitrary epochs (``m.angles``, ``m.track``) and on the even grid the
track routes use (``m.angles_grid``, ``m.track_grid``), and the plain path ``m.track_from_angles(t, *m.angles(t))``
(numpy's sin, cos and arctan2 at every epoch: the reference the tests hold the fast paths to). Each time is a ratio
to one ``numpy.sin`` of the 10^6 mean anomalies, measured in the same process (issue 33's measure).

Each source tree (``--src DIR``: a checkout, a ``git worktree`` or ``git archive`` of a commit, whose ``ephem``
package runs with this interpreter) is measured in its own subprocess, one per round, and the rounds alternate
between the trees, so the load of a shared machine falls on all alike. A worker times each row best of
``--inner`` calls; the table gives, per tree, the best over the rounds of each row and of numpy.sin and their
ratio, and the median over the rounds of the per-round ratio. For the current checkout the worker also reports
how far each fast row is from the plain path (radians; the pole as a separation on the sky). The goal rows of
issue 33 are marked. Import times as before. Results: benchmarks/RESULTS_track.md.
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

from machine import tree_env   # benchmarks/machine.py: this directory is first on the path

ROOT = Path(__file__).resolve().parent.parent
N = 1_000_000
#: (key, label, goal ratio from issue 33 or None)
ROWS = [
    ("nutation", "nutation Δψ, Δε (any epochs)", None),
    ("angles", "angles ψ, Δψ, Δε, ε (any epochs)", None),
    ("angles_grid", "angles ψ, Δψ, Δε, ε (even grid)", 2.0),
    ("track", "track + pole RA/Dec (any epochs)", 5.0),
    ("track_grid", "track + pole RA/Dec (even grid)", 3.0),
    ("plain", "plain path track_from_angles(angles)", None),
]


def _best(fn, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def _separation(ra1, dec1, ra2, dec2):
    """Angle between two directions, well conditioned at any size (2 asin of half the chord)."""
    import numpy as np

    def vec(ra, dec):
        return np.stack([np.cos(dec) * np.cos(ra), np.cos(dec) * np.sin(ra), np.sin(dec)], axis=-1)

    return 2.0 * np.arcsin(0.5 * np.linalg.norm(vec(ra1, dec1) - vec(ra2, dec2), axis=-1))


def worker(inner: int, check: bool) -> dict:
    """Times of every row and of numpy.sin in this process (seconds), and the fast rows' distance to the plain path."""
    import numpy as np

    from ephem.api import model_for

    m = model_for("vesta")
    step = 20 * 365.25 / N
    t = m.pole_epoch + step * np.arange(N)
    x = m.mean_anomaly(t)
    calls = {
        "nutation": lambda: m.nutation_at(t),
        "angles": lambda: m.angles(t),
        "angles_grid": lambda: m.angles_grid(t[0], step, N),
        "track": lambda: m.track(t),
        "track_grid": lambda: m.track_grid(t[0], step, N),
        "plain": lambda: m.track_from_angles(t, *m.angles(t)),
    }
    out = {"sin": _best(lambda: np.sin(x), 3 * inner), "rows": {}, "harmonics": int(len(m.nutation.multiple)),
           "file": __import__("ephem").__file__}
    for key, fn in calls.items():
        fn()                                           # warm: the model's caches, the allocator
        out["rows"][key] = _best(fn, inner)
    out["sin"] = min(out["sin"], _best(lambda: np.sin(x), 3 * inner))   # the unit, measured around the rows
    if check:
        plain = calls["plain"]()
        grid = m.track_grid(t[0], step, N)
        ref_g = m.track_from_angles(grid.jd_tdb, *m.angles(grid.jd_tdb))
        err = {}
        for key, tr, ref in (("track", calls["track"](), plain), ("track_grid", grid, ref_g)):
            err[key] = {"psi": float(np.max(np.abs(tr.psi - ref.psi))),
                        "eps": float(np.max(np.abs(tr.obliquity - ref.obliquity))),
                        "pole": float(np.max(_separation(tr.pole_ra, tr.pole_dec, ref.pole_ra, ref.pole_dec)))}
        ag = m.angles_grid(t[0], step, N)
        ref_a = m.angles(ag[0])
        err["angles_grid"] = {"psi": float(np.max(np.abs(ag[1] - ref_a[0]))),
                              "eps": float(np.max(np.abs(ag[4] - ref_a[3])))}
        out["error"] = err
    return out


def import_time(env: dict) -> tuple[float, float]:
    code = "import time; t=time.perf_counter(); import {mod}; print(time.perf_counter()-t)"
    light = [float(subprocess.check_output([sys.executable, "-c", code.format(mod="ephem")], env=env, cwd="/"))
             for _ in range(5)]
    full = [float(subprocess.check_output([sys.executable, "-c", code.format(
        mod="ephem.forced.precession_nutation, ephem.api")], env=env, cwd="/")) for _ in range(5)]
    return statistics.median(light), statistics.median(full)


def run_worker(src: Path, inner: int, check: bool) -> dict:
    cmd = [sys.executable, str(Path(__file__).resolve()), "--worker", "--inner", str(inner)] + (["--check"] if check
                                                                                               else [])
    res = json.loads(subprocess.check_output(cmd, env=tree_env(src), cwd="/"))
    if Path(res["file"]).resolve().parent.parent != src.resolve():
        raise RuntimeError(f"{src}: the worker imported {res['file']}")
    return res


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--src", type=Path, action="append",
                    help="a checkout whose ephem package to time (repeatable; default: this one)")
    ap.add_argument("--rounds", type=int, default=5, help="subprocesses per tree, alternating (default 5)")
    ap.add_argument("--inner", type=int, default=5, help="calls per row in a subprocess, best kept (default 5)")
    ap.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--check", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.worker:
        print(json.dumps(worker(args.inner, args.check)))
        return
    sys.path.insert(0, str(ROOT / "benchmarks"))
    from machine import machine_info

    info = machine_info()                              # the load average at the start
    srcs = [p.resolve() for p in (args.src or [ROOT])]
    runs: dict[Path, list[dict]] = {s: [] for s in srcs}
    for r in range(args.rounds):
        for s in srcs:
            runs[s].append(run_worker(s, args.inner, check=(r == 0 and s == ROOT.resolve())))
    for line in info:
        print(line)
    k = runs[srcs[0]][0]["harmonics"]
    print(f"\nVesta, exact Hansen coefficients ({k} harmonics), {N:,} epochs over 20 years; {args.rounds} rounds "
          f"alternating between the trees, best of {args.inner} calls per row in each\n")
    head = "| row | goal |" + "".join(f" {s.name or s} ms | ×sin (best) | ×sin (median) |" for s in srcs)
    print(head)
    print("|" + "---|" * (2 + 3 * len(srcs)))
    sin_best = {s: min(r["sin"] for r in runs[s]) for s in srcs}
    line = "| numpy.sin of the same array | |"
    for s in srcs:
        line += f" {sin_best[s] * 1e3:.2f} | 1.00 | 1.00 |"
    print(line)
    for key, label, goal in ROWS:
        line = f"| {label} | {'≤ %gx' % goal if goal else ''} |"
        for s in srcs:
            best_row = min(r["rows"][key] for r in runs[s])
            median = statistics.median(r["rows"][key] / r["sin"] for r in runs[s])
            line += f" {best_row * 1e3:.2f} | {best_row / sin_best[s]:.2f} | {median:.2f} |"
        print(line)
    for s in srcs:
        err = runs[s][0].get("error")
        if err:
            print(f"\n{s}: largest difference from the plain path (radians; the pole as an angle on the sky): "
                  + "; ".join(f"{key} " + ", ".join(f"{n} {v:.1e}" for n, v in e.items()) for key, e in err.items()))
    for s in srcs:
        light, full = import_time(tree_env(s))
        print(f"{s}: import ephem {light * 1e3:.0f} ms; import ephem.forced.precession_nutation + ephem.api "
              f"{full * 1e3:.0f} ms")


if __name__ == "__main__":
    main()
