"""Benchmark: what the calendar dates beside jd_tdb and the ECSV tables cost (issue 41), as ratios within one run.

    .venv/bin/python benchmarks/bench_calendar.py            # ~1 minute; writes benchmarks/RESULTS_calendar.md
    .venv/bin/python benchmarks/bench_calendar.py --quick    # a smoke run

In this process, one BLAS thread, CPU time (``time.process_time``) of each call, median over ``--rounds`` rounds
whose calls alternate, so the load of a shared machine falls on all alike:

1. A 10^5-epoch track (Ceres, 1-day step, the hansen model; Vesta, 0.1-day step) as before the dates
   (``api.track_arrays(..., time_scale=None)``, the path the figures and kernels still take) and with them
   (``time_scale="utc"``, every answer's default), alone and with its JSON (``service.app.finite_json``: the finite
   check and orjson, what the route sends): the ratio with / without is what the dates cost a track.
2. The dates alone (``api.calendar_dates`` of the 10^5 epochs) in UTC, TT and TDB, per epoch (the unit cost
   ``calendar_epoch_s`` of data/cost_model.toml), and ERFA's full ``dtdb`` over the same epochs (what TDB - TT would
   cost without the USNO series).
3. ECSV against JSON: a 10^4-epoch track written by ``api.to_ecsv`` (astropy's writer) and by ``finite_json``, per
   value (``serialise_ecsv_s_per_value``), and the ratio.
"""
from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
from pathlib import Path

from machine import BLAS_VARS, machine_info

for _var in BLAS_VARS:
    os.environ.setdefault(_var, "1")

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
RESULTS = ROOT / "benchmarks" / "RESULTS_calendar.md"
EPOCHS = 100_000
#: (label, body, start, step days) of the 10^5-epoch tracks
TRACKS = [("Ceres, 1 d", "ceres", "2000-01-01", 1.0), ("Vesta, 0.1 d", "vesta", "2020-01-01", 0.1)]


def cpu(fn) -> tuple[float, object]:
    t0 = time.process_time()
    out = fn()
    return time.process_time() - t0, out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=7)
    parser.add_argument("--quick", action="store_true", help="3 rounds")
    args = parser.parse_args()
    rounds = 3 if args.quick else args.rounds

    import erfa
    import numpy as np

    from ephem import api
    from service.app import finite_json

    times: dict[str, list[float]] = {}

    def record(key: str, fn):
        spent, out = cpu(fn)
        times.setdefault(key, []).append(spent)
        return out

    for _, body, start, step in TRACKS:          # warm: the body's model, its estimates, the caches
        api.track_arrays(body, start, api.epoch_grid(start, start, 1.0)[0] + 10 * step, step)
    jd = None
    for _ in range(rounds):
        for label, body, start, step in TRACKS:
            stop = api.epoch_grid(start, start, 1.0)[0] + (EPOCHS - 1) * step
            for scale in (None, "utc"):
                ans = record(f"{label}|{scale}", lambda: api.track_arrays(body, start, stop, step, time_scale=scale))
                record(f"{label}|{scale}|json", lambda: finite_json(ans))
                assert len(ans["jd_tdb"]) == EPOCHS
                jd = ans["jd_tdb"]
        for scale in api.CALENDAR_SCALES:
            record(f"dates|{scale}", lambda: api.calendar_dates(jd, scale))
        record("dtdb", lambda: erfa.dtdb(jd, 0.0, 0.0, 0.0, 0.0, 0.0))
        small = api.track_arrays("ceres", "2040-01-01", 2466154.5 + 9999.0, 1.0)
        record("ecsv", lambda: api.to_ecsv(small))
        record("json_small", lambda: finite_json(small))
    med = {k: statistics.median(v) for k, v in times.items()}

    lines = ["# The calendar dates and the ECSV tables: their cost (issue 41)", "",
             "`.venv/bin/python benchmarks/bench_calendar.py` (" + __doc__.split("\n\n")[2].strip().split(".")[0]
             + "; see the script's docstring).", "", "```", *machine_info(), f"rounds: {rounds}", "```", "",
             f"## A track of {EPOCHS:,} epochs, without and with its dates (CPU ms, median of {rounds})", "",
             "| track | without dates | with dates (utc) | ratio | + JSON without | + JSON with | ratio |",
             "|---|---:|---:|---:|---:|---:|---:|"]
    for label, *_ in TRACKS:
        a, b = med[f"{label}|None"], med[f"{label}|utc"]
        aj, bj = a + med[f"{label}|None|json"], b + med[f"{label}|utc|json"]
        lines.append(f"| {label} | {1e3 * a:.0f} | {1e3 * b:.0f} | {b / a:.2f} | {1e3 * aj:.0f} | {1e3 * bj:.0f} "
                     f"| {bj / aj:.2f} |")
    lines += ["", f"## The dates alone, {EPOCHS:,} epochs (CPU)", "", "| what | ms | us an epoch |", "|---|---:|---:|"]
    for scale in api.CALENDAR_SCALES:
        lines.append(f"| calendar_dates, {scale} | {1e3 * med[f'dates|{scale}']:.1f} | "
                     f"{1e6 * med[f'dates|{scale}'] / EPOCHS:.2f} |")
    lines.append(f"| ERFA's full dtdb (TDB - TT alone, not used) | {1e3 * med['dtdb']:.0f} | "
                 f"{1e6 * med['dtdb'] / EPOCHS:.2f} |")
    values = 10_000 * 9      # the ECSV's columns: jd_tdb, utc_iso, six angles, the pole's 1-sigma
    lines += ["", "## ECSV against JSON, a track of 10,000 epochs (9 columns)", "",
              "| writer | ms | us a value |", "|---|---:|---:|",
              f"| api.to_ecsv (astropy) | {1e3 * med['ecsv']:.0f} | {1e6 * med['ecsv'] / values:.2f} |",
              f"| finite_json (orjson) | {1e3 * med['json_small']:.1f} | {1e6 * med['json_small'] / values:.3f} |",
              "", f"ECSV / JSON: {med['ecsv'] / med['json_small']:.0f}x.", ""]
    RESULTS.write_text("\n".join(lines) + "\n", encoding="utf-8")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
