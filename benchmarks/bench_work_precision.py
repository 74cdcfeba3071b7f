"""What the work-precision chart costs to draw (ephem.exports.work_precision, written by
ephem.answers.figures.models_chart), against its predicted cost (ephem.answers.figures.chart_cost), and the drawing
of its first version (commit 4f3aa5c: minor ticks on every log axis, one FancyArrowPatch a leader, no shared labels)
interleaved with today's in one process.

    .venv/bin/python benchmarks/bench_work_precision.py [-n 7]

For each body (3 to 52 models) and output (SVG; PNG at 100 and 300 dpi): the CPU time (time.process_time) of the
figure and its bytes, min and median over the runs, for today's drawing and the first one, their ratio, and today's
median over the predicted CPU (an upper estimate: under 1). The answers (api.track_models) are made once, outside
the timing. Results: benchmarks/RESULTS_work_precision.md.
"""
from __future__ import annotations

import argparse
import importlib.util
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from machine import machine_info

from ephem import api
from ephem.answers import figures
from ephem.exports import work_precision

ROOT = Path(__file__).resolve().parents[1]
FIRST = "4f3aa5c"
CASES = (("earth", 10.0), ("moon", 20000.0), ("vesta", 100.0), ("ceres", None), ("itokawa", 1000.0))
OUTPUTS = (("svg", 100.0), ("png", 100.0), ("png", 300.0))
SPAN = ("2040-01-01", "2040-12-31", 10.0)


def _first_version():
    """ephem.exports.work_precision as committed first, loaded beside today's (it imports only ephem.base)."""
    source = subprocess.run(["git", "show", f"{FIRST}:ephem/exports/work_precision.py"], cwd=ROOT, check=True,
                            capture_output=True, text=True).stdout
    path = Path(tempfile.mkdtemp()) / "work_precision_first.py"
    path.write_text(source.replace("from ..base.constants", "from ephem.base.constants"))
    spec = importlib.util.spec_from_file_location("work_precision_first", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _draw(module, answer: dict, fmt: str, dpi: float) -> float:
    t = time.process_time()
    data = figures.figure_bytes(module.figure(answer), fmt=fmt, dpi=dpi)
    if fmt == "svg":
        module.svg_with_titles(data.decode("utf-8"), answer)
    return time.process_time() - t


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-n", type=int, default=7)
    n = ap.parse_args().n
    versions = {"today": work_precision, "first": _first_version()}
    answers = {body: api.track_models(body, *SPAN, tolerance_mas=tol) for body, tol in CASES}
    for answer in answers.values():                  # fonts, mathtext and the caches, once
        for module in versions.values():
            _draw(module, answer, "svg", 100.0)
    import matplotlib

    print("\n".join(f"- {line}" for line in machine_info(matplotlib=matplotlib.__version__)))
    print(f"- command: `.venv/bin/python benchmarks/bench_work_precision.py -n {n}`; span {SPAN[0]} to {SPAN[1]}, "
          f"{SPAN[2]:g}-day step\n")
    print("| body | models | output | today: CPU ms (min / median) | first (4f3aa5c): CPU ms (min / median) | "
          "first ÷ today (medians) | predicted CPU ms | today ÷ predicted |")
    print("|---|---:|---|---|---|---:|---:|---:|")
    for body, answer in answers.items():
        for fmt, dpi in OUTPUTS:
            times = {k: [] for k in versions}
            for _ in range(n):
                for name, module in versions.items():      # interleaved: the machine's load falls on both
                    times[name].append(_draw(module, answer, fmt, dpi))
            med = {k: statistics.median(v) for k, v in times.items()}
            predicted = figures.chart_cost(len(answer["models"]), fmt, dpi).cpu_s
            print(f"| {answer['body']} | {len(answer['models'])} | {fmt}{f' {dpi:g} dpi' if fmt == 'png' else ''} | "
                  f"{1e3 * min(times['today']):.0f} / {1e3 * med['today']:.0f} | "
                  f"{1e3 * min(times['first']):.0f} / {1e3 * med['first']:.0f} | {med['first'] / med['today']:.2f} | "
                  f"{1e3 * predicted:.0f} | {med['today'] / predicted:.2f} |")
            sys.stdout.flush()


if __name__ == "__main__":
    main()
