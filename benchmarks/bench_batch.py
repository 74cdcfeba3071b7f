"""Batch answers for populations (issue 19): bodies per second of the vectorised core and of the Dask engine with
1 and 2 workers (the scaling efficiency), the same for histories, memory per worker against the partition size,
and 10^6 bodies end to end.

    python benchmarks/bench_batch.py [--rows 1000000] [--out benchmarks/RESULTS_batch.md]

The population is tools/generate_population.py's (seed 1). Engine runs use a LocalCluster started here (its
address passed as ``scheduler=``), so that the workers' peak memory can be read after the run. Times are wall
clock on this machine; CPU times where said.
"""
from __future__ import annotations

import argparse
import importlib.util
import os
import platform
import resource
import shutil
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent


def _generator():
    spec = importlib.util.spec_from_file_location("generate_population", ROOT / "tools" / "generate_population.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def generate(path: Path, rows: int) -> None:
    import subprocess
    import sys

    subprocess.run([sys.executable, str(ROOT / "tools" / "generate_population.py"), "--count", str(rows), "--out",
                    str(path), "--seed", "1"], check=True, capture_output=True)


def core_throughput(path: Path, rows: int, sigmas: bool = True) -> tuple[float, float]:
    """(bodies/s of CPU, CPU s per body) of ephem.batch.population.evaluate on the first ``rows`` rows, in this process;
    ``sigmas=False`` drops the ``_sigma`` columns (no uncertainties to propagate)."""
    import pyarrow.parquet as pq

    from ephem.batch.population import evaluate

    table = pq.read_table(path).slice(0, rows)
    cols = {name: table.column(name).to_numpy(zero_copy_only=False) for name in table.column_names
            if sigmas or not name.endswith("_sigma")}
    evaluate({k: v[:100] for k, v in cols.items()})                # imports and caches out of the timing
    c = time.process_time()
    evaluate(cols)
    cpu = time.process_time() - c
    return rows / cpu, cpu / rows


def partition_memory(path: Path) -> list[tuple[int, float]]:
    """Peak traced memory (MB) of evaluate for partitions of 10k, 20k and 50k rows."""
    import tracemalloc

    import pyarrow.parquet as pq

    from ephem.batch.population import evaluate

    out = []
    table = pq.read_table(path)
    for rows in (10_000, 20_000, 50_000):
        t = table.slice(0, rows)
        cols = {name: t.column(name).to_numpy(zero_copy_only=False) for name in t.column_names}
        tracemalloc.start()
        evaluate(cols)
        out.append((rows, tracemalloc.get_traced_memory()[1] / 2**20))
        tracemalloc.stop()
    return out


def _peak_rss_mb() -> float:
    """This process's peak resident set (VmHWM, MB): run in each worker."""
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith("VmHWM:"):
            return float(line.split()[1]) / 1024.0
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def engine(path: Path, workers: int, partition_rows: int, history=None) -> tuple[float, int, float]:
    """(wall s, rows, the workers' largest peak RSS in MB) of ephem.batch.distributed.run on a LocalCluster of ``workers``."""
    import logging

    import dask
    from distributed import Client, LocalCluster

    from ephem.batch import distributed as batch

    out = Path(tempfile.mkdtemp(prefix="bench_batch_"))
    with dask.config.set({"distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": None}):
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, host="127.0.0.1",
                               dashboard_address="127.0.0.1:0", silence_logs=logging.ERROR)
    try:
        with Client(cluster) as client:
            t = time.perf_counter()
            result = batch.run(str(path), str(out / "r"), scheduler=cluster.scheduler_address,
                               partition_rows=partition_rows, history=history)
            wall = time.perf_counter() - t
            rss = client.run(_peak_rss_mb)
    finally:
        cluster.close()
        shutil.rmtree(out, ignore_errors=True)
    return wall, result.rows, max(rss.values())


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rows", type=int, default=1_000_000)
    ap.add_argument("--out", default=str(ROOT / "benchmarks" / "RESULTS_batch.md"))
    args = ap.parse_args(argv)
    from ephem.batch.population import HistorySpec

    work = Path(tempfile.mkdtemp(prefix="bench_population_"))
    lines = ["# Batch answers: bodies per second, scaling, memory", "",
             f"Machine: {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}; run "
             f"{time.strftime('%Y-%m-%d')}. `python benchmarks/bench_batch.py` (tools/generate_population.py, "
             "seed 1: 95 % main belt, 5 % near-Earth, the three inertia forms, some sigma columns).", ""]
    try:
        small, big = work / "pop_200k.parquet", work / f"pop_{args.rows}.parquet"
        t = time.perf_counter()
        generate(small, 200_000)
        generate(big, args.rows)
        print(f"generated in {time.perf_counter() - t:.1f} s")
        rate, cpu = core_throughput(small, 100_000, sigmas=False)
        rate_s, cpu_s = core_throughput(small, 100_000)
        lines += ["## The core, in one process", "",
                  f"`ephem.batch.population.evaluate` on 100 000 rows, precession and nutation: **{rate:,.0f} bodies/s** "
                  f"of one core ({cpu * 1e6:.0f} µs of CPU per body; the target is 10^4 bodies/s per core). With "
                  f"the population's sigma columns (30 % of the rows carry 3-4 of them; each costs two more "
                  f"evaluations of its rows): {rate_s:,.0f} bodies/s ({cpu_s * 1e6:.0f} µs per body).", ""]
        lines += ["Peak memory of one partition (tracemalloc), which bounds a worker's: it grows with the partition, "
                  "not with the input.", "", "| partition rows | peak MB | bytes per row |", "|---:|---:|---:|"]
        lines += [f"| {r:,} | {mb:.0f} | {mb * 2**20 / r:,.0f} |" for r, mb in partition_memory(small)] + [""]
        print(lines[-6:])
        rows = {}
        lines += ["## The engine (ephem.batch.distributed.run on a LocalCluster)", "",
                  "| run | workers | partition rows | rows | wall s | bodies/s | workers' peak RSS MB |",
                  "|---|---:|---:|---:|---:|---:|---:|"]
        for workers in (1, 2):
            wall, n, rss = engine(small, workers, 20_000)
            rows[("pn", workers)] = n / wall
            lines.append(f"| precession and nutation | {workers} | 20,000 | {n:,} | {wall:.1f} | {n / wall:,.0f} | "
                         f"{rss:.0f} |")
            print(lines[-1])
        hist = HistorySpec(-1.0e5, 0.0, 1000.0)
        hist_input = work / "pop_40.parquet"
        generate(hist_input, 40)
        for workers in (1, 2):
            wall, n, rss = engine(hist_input, workers, 10, hist)
            rows[("h", workers)] = n / wall
            lines.append(f"| with histories (-100..0 kyr, secular orbit) | {workers} | 10 | {n:,} | {wall:.1f} | "
                         f"{n / wall:.2f} | {rss:.0f} |")
            print(lines[-1])
        wall, n, rss = engine(big, 2, 50_000)
        lines.append(f"| **{n:,} bodies end to end** | 2 | 50,000 | {n:,} | {wall:.1f} | {n / wall:,.0f} | {rss:.0f} |")
        print(lines[-1])
        eff = rows[("pn", 2)] / (2 * rows[("pn", 1)])
        eff_h = rows[("h", 2)] / (2 * rows[("h", 1)])
        lines += ["", f"Scaling: 2 workers give {rows[('pn', 2)] / rows[('pn', 1)]:.2f}x one for precession and "
                  f"nutation (efficiency {eff:.0%}; the target is 1.7x), {rows[('h', 2)] / rows[('h', 1)]:.2f}x for "
                  f"histories (efficiency {eff_h:.0%}). The wall times include the input's split (streaming, in "
                  "the client) and the cluster's start.", ""]
    finally:
        shutil.rmtree(work, ignore_errors=True)
    Path(args.out).write_text("\n".join(lines) + "\n")
    print(f"written: {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
