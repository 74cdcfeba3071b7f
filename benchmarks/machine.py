"""What the benchmarks print about the machine they ran on: the lines at the head of a results file.

Imported by the benchmark scripts run as ``python benchmarks/bench_*.py`` (this directory is then first on the
path). numpy is imported inside :func:`machine_info`, so a script can set its BLAS variables before calling it.
"""
from __future__ import annotations

import datetime as _dt
import os
import platform
import tempfile
from pathlib import Path

#: the thread-count variables of the BLAS libraries numpy may load
BLAS_VARS = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")


def _cpu_model() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return "unknown"


def _simd() -> str:
    try:
        from numpy._core._multiarray_umath import __cpu_baseline__, __cpu_dispatch__, __cpu_features__
    except ImportError:
        return "unknown"
    enabled = ",".join(f for f in __cpu_dispatch__ if __cpu_features__.get(f)) or "none"
    return f"baseline {','.join(__cpu_baseline__)}; dispatch enabled {enabled}"


def machine_info(**versions: str) -> list[str]:
    """Date, machine, CPU, Python and numpy (with its SIMD path), the ``versions`` given (name -> version), the BLAS
    threads and the load average at the start."""
    import numpy as np

    usable = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    load = ", ".join(f"{x:.2f}" for x in os.getloadavg()) if hasattr(os, "getloadavg") else "n/a"
    more = "".join(f", {name} {v}" for name, v in versions.items())
    return [
        f"date: {_dt.datetime.now(_dt.timezone.utc).isoformat(timespec='seconds')}",
        f"machine: {platform.machine()}, nproc {os.cpu_count()} (usable {usable}), CPU model: {_cpu_model()}",
        f"python {platform.python_version()} ({platform.python_implementation()}), numpy {np.__version__}{more}",
        f"numpy SIMD: {_simd()}; NPY_DISABLE_CPU_FEATURES={os.environ.get('NPY_DISABLE_CPU_FEATURES', 'unset')}",
        f"BLAS threads: { {v: os.environ.get(v, 'unset') for v in BLAS_VARS} }",
        f"load average at the start: {load}",
    ]


#: where the children of :func:`tree_env` keep their bytecode and tables (one directory per benchmark run)
_SCRATCH = None


def tree_env(src: Path) -> dict:
    """The environment of a child process that runs the ``ephem`` package of the checkout ``src`` (an A/B
    benchmark's "before" or "after"): ``src`` first on PYTHONPATH; compiled bytecode, as an installed copy reads
    it (a temporary PYTHONPYCACHEPREFIX, PYTHONDONTWRITEBYTECODE lifted: some environments set it, and every run
    would compile ~90 modules again); and the tree's own table cache (ephem.base.disk_cache: two versions of the
    code make two keys for one table name, and interleaved runs sharing a directory would replace each other's
    file at every run)."""
    global _SCRATCH
    if _SCRATCH is None:
        _SCRATCH = tempfile.mkdtemp(prefix="ephem_bench_")
    env = dict(os.environ)
    env["PYTHONPATH"] = str(src) + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    env["PYTHONPYCACHEPREFIX"] = os.path.join(_SCRATCH, "pyc")
    env["EPHEM_CACHE_DIR"] = os.path.join(_SCRATCH, "tables", str(abs(hash(str(Path(src).resolve())))))
    return env
