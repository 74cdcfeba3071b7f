"""Print the SIMD features above numpy's compiled baseline that numpy found on this CPU and would dispatch to,
space-separated: the value of NPY_DISABLE_CPU_FEATURES that holds numpy to its baseline kernels (`.ci/run`
runs the suite a second time with it, so that a last-bit difference between CPUs cannot hide in the suite).

`python tools/numpy_simd_above_baseline.py --check` instead exits 1 if any such feature is still in use (run
under the variable, it proves the setting took effect)."""
from __future__ import annotations

import sys


def dispatched_features() -> list[str]:
    """numpy's dispatch targets (beyond the baseline) that are enabled on this CPU now, in numpy's order."""
    from numpy._core._multiarray_umath import __cpu_dispatch__, __cpu_features__

    return [f for f in __cpu_dispatch__ if __cpu_features__.get(f)]


if __name__ == "__main__":
    found = dispatched_features()
    if "--check" in sys.argv[1:]:
        if found:
            print(f"numpy still dispatches to {' '.join(found)}", file=sys.stderr)
            sys.exit(1)
        print("numpy runs its baseline kernels only")
    else:
        print(" ".join(found))
