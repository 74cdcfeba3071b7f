"""The spin axis over millions of years: what a history costs, predicted (ephem.theory.cost, charged before the work)
against measured (CPU of one core), for every catalogue body over the shipped span.

    python benchmarks/bench_history.py [--out benchmarks/RESULTS_history.md]

The Earth's lunisolar caches are warmed first, as the service does at start-up. The service's request budget is
5 s of CPU: a prediction above it is refused over HTTP with the estimate (the CLI and the library have no budget).
"""
from __future__ import annotations

import argparse
import platform
import time
from pathlib import Path

from ephem import api
from ephem.base.budget import budget
from ephem.base.errors import EphemError

ROOT = Path(__file__).resolve().parent.parent
CASES = [(body, -3.0e6, 1.0e6, 1000.0) for body in ("earth", "mars", "ceres", "vesta", "eros", "steins", "moon",
                                                      "itokawa")] + [
    ("ceres", -1.0e6, 0.0, 500.0), ("earth", -2.0e5, 2.0e5, 100.0)]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default=str(ROOT / "benchmarks" / "RESULTS_history.md"))
    args = ap.parse_args(argv)
    api.precession("earth")
    rows = []
    for body, lo, hi, step in CASES:
        with budget(1e9, 1e9) as bud:
            t, w = time.process_time(), time.perf_counter()
            try:
                ans = api.history(body, lo, hi, step)
                what = f"{ans['model']['name']} orbit, {len(ans['year'])} epochs"
            except EphemError as exc:
                what = f"refused: {str(exc)[:80]}…"
            cpu, wall = time.process_time() - t, time.perf_counter() - w
        rows.append(f"| {body} | {lo:g} .. {hi:g} | {step:g} | {what} | {bud.spent_cpu_s:.2f} | {cpu:.2f} | {wall:.2f} |")
        print(rows[-1], flush=True)
    text = ["# History cost: predicted against measured", "",
            f"Machine: {platform.machine()}, {platform.python_version()}; run {time.strftime('%Y-%m-%d')}.", "",
            "| body | years from J2000 | step (yr) | answer | predicted CPU (s) | measured CPU (s) | wall (s) |",
            "|---|---|---:|---|---:|---:|---:|", *rows, ""]
    Path(args.out).write_text("\n".join(text))
    print(f"written: {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
