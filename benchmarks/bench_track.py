"""Benchmark: a spin-axis track at 10^6 epochs against one numpy.sin over the same array.

Target (issue 2): the nutation (Δψ, Δε) and the precession angles ψ, ε at 10^6 epochs cost at
most 3x one ``numpy.sin`` of 10^6 float64. The pole direction (RA, Dec) needs sin/cos of ψ and ε
and an atan2 and an arcsin more; its cost is reported separately. Also the import time of ``ephem``.

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
    full = [float(subprocess.check_output([sys.executable, "-c", code.format(mod="ephem.model, ephem.api")]))
            for _ in range(5)]
    return statistics.median(light), statistics.median(full)


def main() -> None:
    m = model_for("vesta")
    t = m.pole_epoch + np.linspace(0.0, 20 * 365.25, N)
    x = m.mean_anomaly(t)
    sin_t = best(lambda: np.sin(x))
    nut_t = best(lambda: m.nutation_at(t))
    ang_t = best(lambda: m.angles(t))
    trk_t = best(lambda: m.track(t))
    light, full = import_time()
    k = len(m.nutation.multiple)
    print(f"epochs: {N:,}; Vesta, exact Hansen coefficients, {k} harmonics")
    print(f"{'numpy.sin (reference)':34s} {sin_t * 1e3:8.2f} ms   1.00x")
    for name, v in (("nutation Δψ, Δε", nut_t), ("angles ψ, Δψ, Δε, ε", ang_t), ("full track incl. pole RA/Dec", trk_t)):
        print(f"{name:34s} {v * 1e3:8.2f} ms  {v / sin_t:5.2f}x")
    print(f"import ephem: {light * 1e3:.0f} ms; import ephem.model + ephem.api: {full * 1e3:.0f} ms")


if __name__ == "__main__":
    main()
