"""What the PCK fit's stable choice costs: the kernel of each body written with the greedy step of today
(`ephem.exports.pck_fit._pick`: a shortlist scored exactly, ties within rounding broken by the lowest sideband) and
with the step before issue 29 (the argmax of the downdated scores), interleaved in one process.

    .venv/bin/python benchmarks/bench_pck.py [-n 5]

Prints per body the CPU time of write_pck (min and median over the runs) for both steps and their ratio;
results: benchmarks/RESULTS_pck.md. The two steps may choose different angles (the old one flips with the
CPU), so the angle count of each is printed too: the time per angle is the fair comparison.
"""
from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from ephem.answers import kernels as pck
from ephem.exports import pck_fit

BODIES = ("vesta", "ceres", "eros", "itokawa", "steins", "mars", "earth")
SPAN = ("2020-01-01", "2040-01-01")


def _argmax_pick(ra, dec, available, order_key):
    """The greedy step before issue 29: the largest downdated score, ties to numpy's argmax."""
    s_ra, s_dec = ra.scores(), dec.scores()
    score = np.where((s_ra < 0.0) & (s_dec < 0.0), -1.0, np.maximum(s_ra, 0.0) + np.maximum(s_dec, 0.0))
    score[~available] = -1.0
    i = int(np.argmax(score))
    return None if score[i] <= 0.0 else i


def _run(body: str, pick) -> tuple[float, int]:
    real = pck_fit._pick
    pck_fit._pick = pick
    try:
        t = time.process_time()
        fit = pck.write_pck([body], *SPAN, max_angles=200).bodies[0]
        return time.process_time() - t, len(fit.angles)
    finally:
        pck_fit._pick = real


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-n", type=int, default=5)
    n = ap.parse_args().n
    steps = {"stable": pck_fit._pick, "argmax": _argmax_pick}
    for body in BODIES:
        _run(body, pck_fit._pick)                   # the model, the track and the caches, once
    print("| body | stable: CPU s (min / median), angles | argmax (before): CPU s, angles | ratio of medians |")
    print("|---|---|---|---|")
    for body in BODIES:
        times = {k: [] for k in steps}
        angles = {}
        for _ in range(n):
            for name, step in steps.items():          # interleaved: a shared machine's load falls on both
                dt, angles[name] = _run(body, step)
                times[name].append(dt)
        med = {k: statistics.median(v) for k, v in times.items()}
        print(f"| {body} | {min(times['stable']):.3f} / {med['stable']:.3f}, {angles['stable']} | "
              f"{min(times['argmax']):.3f} / {med['argmax']:.3f}, {angles['argmax']} | "
              f"{med['stable'] / med['argmax']:.2f} |")


if __name__ == "__main__":
    main()
