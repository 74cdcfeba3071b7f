"""Benchmark: a spin-axis track at 10^6 epochs against one numpy.sin over the same array.

Target (issue 2): a track at 10^6 epochs costs at most 3x one ``numpy.sin`` of 10^6 float64.
Reported: the nutation alone, the angles ψ, Δψ, Δε, ε, and the full track with the pole's RA and
Dec, each at arbitrary epochs and on the even grid the track routes use. Also the import time.

Run: ``make bench`` (or ``.venv/bin/python benchmarks/bench_track.py``). Best of several repeats.
"""
from __future__ import annotations

import statistics
import subprocess
import sys
import time

import numpy as np

from ephem.api import model_for

N = 1_000_000
REPEAT = 15


def best(fn) -> float:
    times = []
    for _ in range(REPEAT):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def import_time() -> tuple[float, float]:
    code = "import time; t=time.perf_counter(); import {mod}; print(time.perf_counter()-t)"
    light = [float(subprocess.check_output([sys.executable, "-c", code.format(mod="ephem")]))
             for _ in range(5)]
    full = [float(subprocess.check_output([sys.executable, "-c", code.format(mod="ephem.forced.precession_nutation, ephem.api")]))
            for _ in range(5)]
    return statistics.median(light), statistics.median(full)


def main() -> None:
    m = model_for("vesta")
    step = 20 * 365.25 / N
    t = m.pole_epoch + step * np.arange(N)
    x = m.mean_anomaly(t)
    sin_t = best(lambda: np.sin(x))
    rows = [
        ("nutation Δψ, Δε (any epochs)", best(lambda: m.nutation_at(t))),
        ("angles ψ, Δψ, Δε, ε (any epochs)", best(lambda: m.angles(t))),
        ("angles ψ, Δψ, Δε, ε (even grid)", best(lambda: m.angles_grid(t[0], step, N))),
        ("track + pole RA/Dec (any epochs)", best(lambda: m.track(t))),
        ("track + pole RA/Dec (even grid)", best(lambda: m.track_grid(t[0], step, N))),
    ]
    light, full = import_time()
    k = len(m.nutation.multiple)
    print(f"epochs: {N:,} over 20 years; Vesta, exact Hansen coefficients, {k} harmonics; best of {REPEAT}")
    print(f"{'numpy.sin of the same array':36s} {sin_t * 1e3:8.2f} ms   1.00x")
    for name, v in rows:
        print(f"{name:36s} {v * 1e3:8.2f} ms  {v / sin_t:5.2f}x")
    print(f"import ephem: {light * 1e3:.0f} ms; import ephem.forced.precession_nutation + ephem.api: {full * 1e3:.0f} ms")


if __name__ == "__main__":
    main()
