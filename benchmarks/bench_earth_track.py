"""Benchmark: the Earth's lunisolar series and track, before and after the term-product evaluation.

"Before" is the direct route the library used until now, reproduced here (``direct_nutation_at``: per block of
4096 epochs, φ = a @ k, then sin φ and cos φ of every term and epoch and four matrix-vector products per
axis); "after" is :meth:`ephem.earth.lunisolar.LunisolarSeries.nutation_at` (:class:`ephem.earth.lunisolar.TermProducts`).
Both run in the same process on the same epochs: an even grid over the track's accepted window 1900-2100.

Measured: the series evaluation (Δψ, Δε) at 10^4, 10^5 and 3.6 x 10^5 epochs, for the served series
(0.1 mas cut) and optionally finer cuts, and the whole ``ephem.api.track("earth", ...)`` at 3.6 x 10^5 epochs
(the library's cap is 10^6; the service caps a track at 10^5, also measured), "before" with the direct route
patched in. CPU = process CPU time (all threads), best of ``--repeat``; wall likewise. Also the largest
|after - before| over the epochs (radians).

Run: ``.venv/bin/python benchmarks/bench_earth_track.py`` (writes benchmarks/RESULTS_earth_track.md;
``--no-write`` only prints). ``--blas-threads`` (default 1, the service's setting; 0 keeps the environment)
acts before numpy loads its BLAS.
"""
from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

from machine import BLAS_VARS, machine_info   # benchmarks/machine.py

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

WINDOW = (2415020.5, 2488069.5)          # 1900-01-01 .. 2100-01-01 TDB (ephem.earth.estimates.window())
TRACK_STEP = 0.2                         # days: 3.6 x 10^5 epochs span 197 years
DEFAULT_OUTPUT = ROOT / "benchmarks" / "RESULTS_earth_track.md"


def parse_args(argv=None) -> argparse.Namespace:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--sizes", default="10000,100000,360000",
                   help="epoch counts of the series evaluation, comma-separated (default %(default)s)")
    p.add_argument("--cuts", default="0.1,0.001",
                   help="amplitude cuts (mas) of the series measured; the first is the served track's "
                        "(default %(default)s)")
    p.add_argument("--track-sizes", default="100000,360000",
                   help="epoch counts of the whole api.track, comma-separated (default %(default)s)")
    p.add_argument("--repeat", type=int, default=3, help="best of this many runs (default %(default)s)")
    p.add_argument("--blas-threads", default="1",
                   help="BLAS threads (default 1, the service's setting; 0 leaves the environment as it is)")
    p.add_argument("--output", type=Path, default=DEFAULT_OUTPUT, help="results file (default %(default)s)")
    p.add_argument("--append", action="store_true",
                   help="add this run to the results file as a further section (e.g. another BLAS setting)")
    p.add_argument("--no-write", action="store_true", help="print the table only")
    return p.parse_args(argv)


def _ints(text: str) -> list[int]:
    return [int(float(x)) for x in text.split(",") if x.strip()]


def _floats(text: str) -> list[float]:
    return [float(x) for x in text.split(",") if x.strip()]


def direct_nutation_at(series, jd_tdb):
    """The evaluation before this change (ephem/earth/lunisolar.py until then), verbatim in its arithmetic."""
    import numpy as np

    from ephem.base.budget import checkpoint
    from ephem.base.constants import MAS
    from ephem.orbit.lunar import centuries, delaunay_arguments

    jd = np.asarray(jd_tdb, dtype=float)
    flat = jd.ravel()
    dpsi = np.empty(flat.size)
    deps = np.empty(flat.size)
    kf = series.multipliers.T.astype(float)
    k, r = series.coefficients, series.rates
    for start in range(0, flat.size, 4096):
        checkpoint()
        sl = slice(start, start + 4096)
        a, t = delaunay_arguments(flat[sl]), centuries(flat[sl])
        phase = a @ kf
        s, c = np.sin(phase), np.cos(phase)
        dpsi[sl] = (s @ k[:, 0] + c @ k[:, 1] + t * (s @ r[:, 0] + c @ r[:, 1])) * MAS
        deps[sl] = (s @ k[:, 2] + c @ k[:, 3] + t * (s @ r[:, 2] + c @ r[:, 3])) * MAS
    return dpsi.reshape(jd.shape), deps.reshape(jd.shape)


def best_of(fn, repeat: int):
    """(best CPU s, best wall s, last result)."""
    cpu, wall, out = float("inf"), float("inf"), None
    for _ in range(repeat):
        c0, w0 = time.process_time(), time.perf_counter()
        out = fn()
        cpu = min(cpu, time.process_time() - c0)
        wall = min(wall, time.perf_counter() - w0)
    return cpu, wall, out


def main(argv=None) -> int:
    args = parse_args(argv)
    if args.blas_threads.strip() != "0":
        for var in BLAS_VARS:
            os.environ[var] = args.blas_threads.strip()
    info = machine_info()           # imports numpy after the BLAS variables are set

    import numpy as np
    from unittest import mock

    from ephem import api
    from ephem.base.constants import J2000_JD
    from ephem.earth import lunisolar as L

    sizes, cuts, track_sizes = _ints(args.sizes), _floats(args.cuts), _ints(args.track_sizes)
    rows = []
    for cut in cuts:
        series = L.earth_lunisolar(cut_mas=cut)
        n = len(series.multipliers)
        series.nutation_at(np.array([J2000_JD]))          # build the evaluation plan once (cached)
        for size in sizes:
            jd = np.linspace(*WINDOW, size)
            b_cpu, b_wall, before = best_of(lambda: direct_nutation_at(series, jd), args.repeat)
            a_cpu, a_wall, after = best_of(lambda: series.nutation_at(jd), args.repeat)
            diff = max(float(np.max(np.abs(after[0] - before[0]))), float(np.max(np.abs(after[1] - before[1]))))
            rows.append((f"series Δψ, Δε ({n} terms, cut {cut:g} mas)", size, b_cpu, a_cpu, b_wall, a_wall, diff))
            print(rows[-1], flush=True)

    api.track("earth", WINDOW[0], WINDOW[0] + 10.0, 1.0)                # warm-up: the served series, DE421
    for size in track_sizes:
        step = TRACK_STEP
        stop = WINDOW[0] + step * (size - 1)
        if stop > WINDOW[1]:
            raise SystemExit(f"{size} epochs at {step} d leave the window 1900-2100")
        run = lambda: api.track_arrays("earth", WINDOW[0], stop, step)   # noqa: E731 (arrays: the lists' cost apart)
        with mock.patch.object(L.LunisolarSeries, "nutation_at", direct_nutation_at):
            b_cpu, b_wall, before = best_of(run, args.repeat)
        a_cpu, a_wall, after = best_of(run, args.repeat)
        count = len(after["jd_tdb"])
        diff = max(float(np.max(np.abs(after[k] - before[k]))) for k in ("delta_psi_arcsec", "delta_epsilon_arcsec"))
        rows.append((f"api.track_arrays('earth'), step {step:g} d", count, b_cpu, a_cpu, b_wall, a_wall,
                     diff * L.ARCSEC))
        lists = lambda: api.track("earth", WINDOW[0], stop, step)       # noqa: E731
        with mock.patch.object(L.LunisolarSeries, "nutation_at", direct_nutation_at):
            b_cpu, b_wall, _ = best_of(lists, args.repeat)
        a_cpu, a_wall, _ = best_of(lists, args.repeat)
        rows.append((f"api.track('earth') (lists), step {step:g} d", count, b_cpu, a_cpu, b_wall, a_wall, None))
        print(rows[-2], rows[-1], flush=True)

    table = ["| what | epochs | CPU before (s) | CPU after (s) | speed-up | wall before (s) | wall after (s) "
             "| max abs(after - before) (rad) |",
             "|---|---:|---:|---:|---:|---:|---:|---:|"]
    for what, size, b_cpu, a_cpu, b_wall, a_wall, diff in rows:
        d = "-" if diff is None else f"{diff:.1e}"
        table.append(f"| {what} | {size:,} | {b_cpu:.3f} | {a_cpu:.3f} | {b_cpu / a_cpu:.1f}x | {b_wall:.3f} "
                     f"| {a_wall:.3f} | {d} |")
    blas = os.environ.get(BLAS_VARS[0], "unset (BLAS's own default: one thread per core)")
    heading = [] if args.append else [
        "# The Earth's lunisolar track: direct sum against term products (`benchmarks/bench_earth_track.py`)",
        "",
        "Before: the direct route (sin and cos of every term's argument at every epoch, blocks of 4096; reproduced "
        "in the script). After: `LunisolarSeries.nutation_at` with `TermProducts` (e^{ia} of the five Delaunay "
        "arguments, their powers, the terms' products on a prefix tree, one matrix product). The track rows time "
        "the whole request (series, pole, error estimate; `track` also the conversion to lists) with the direct "
        "route patched in for 'before'. The last column: the largest difference of Δψ, Δε between the two routes "
        "(the stated budget, ephem/earth/lunisolar.py TermProducts: at most 1.9e-18 rad in Δψ and 1.0e-18 in Δε for "
        "the served series, 8.9e-18 and 4.6e-18 for 414 terms). The series and DE421 are loaded before the timing "
        "(the series' build, ~1.6 s once per process, is not part of this change); the service caps a track at "
        "10^5 epochs, the library at 10^6. CPU = process CPU time, all threads.",
    ]
    text = "\n".join([
        *heading,
        "",
        f"## BLAS threads: {blas}",
        "",
        *[f"- {line}" for line in info],
        f"- best of {args.repeat}; epochs: an even grid over 1900-01-01..2100-01-01 TDB (the track's window); "
        "the tracks from 1900-01-01",
        "",
        *table,
        "",
    ])
    print()
    print("\n".join(table))
    if not args.no_write:
        if args.append and args.output.exists():
            text = args.output.read_text() + text
        args.output.write_text(text)
        print(f"\nwritten: {args.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
