"""The real-orbit rung's peak memory per year of span (issue 42: its memory unit, ``path_mb_per_year`` in
data/cost_model.toml). Each case runs in a fresh process: the peak traced by tracemalloc (numpy's and scipy's arrays
included) and the rise of the process's resident high-water mark (``/proc/self/clear_refs``, then VmHWM) while
(1) the body's real orbit is integrated (``sun_path``, cold: nothing kept), and (2) a whole track from the real orbit
over the same span is answered cold (``api.track(model='real_orbit')``), beside the rung's predicted memory; glibc's
allocator set as in a worker (``service.guards.tune_allocator``), the RSS measured untraced. Prints a
Markdown table. Run: ``.venv/bin/python benchmarks/measure_real_orbit_memory.py``."""
from __future__ import annotations

import json
import subprocess
import sys

CASES = [(body, years) for body in ("vesta", "ceres", "steins", "itokawa") for years in (10, 30, 60, 100)]


def _hwm_mb() -> float:
    with open("/proc/self/status") as fh:
        for line in fh:
            if line.startswith("VmHWM:"):
                return int(line.split()[1]) / 1024
    return 0.0


def _reset_hwm() -> None:
    with open("/proc/self/clear_refs", "w") as fh:
        fh.write("5")


def one(body_name: str, years: float, what: str) -> dict:
    import gc
    import tracemalloc

    from service.guards import tune_allocator
    tune_allocator()            # glibc as in a worker (two arenas, blocks over 256 KiB mapped on their own)

    from ephem import api
    from ephem.bodies.catalogue import get_body
    from ephem.orbit.de421 import sun_path
    from ephem.theory import cost

    body = get_body(body_name)
    start = 2451545.0 - 0.5 * years * 365.25           # centred on J2000, inside DE421 (1899-2053) up to 100 years
    stop = start + years * 365.25
    epochs = (body.pole.epoch_jd_tdb, body.orbit.epoch_jd_tdb, start, stop)
    predicted = cost.orbit_integration(max(epochs) - min(epochs)).memory_mb
    # what a worker loads once, not counted: the imports and tables of a first request, and the real orbit's own
    # (scipy's integrator, DE421's pages, the perturbers' tables) through another body's short real-orbit track
    api.track(body, 2451545.0, 2451545.0 + 30.0, 10.0)
    api.track(get_body("eros" if body_name != "eros" else "vesta"), 2451545.0, 2451545.0 + 365.25, 10.0,
              model="real_orbit", time_scale="tdb")
    def run():
        if what == "path":
            sun_path(body, min(epochs), max(epochs))
        else:
            api.track(body, start, stop, 10.0, model="real_orbit", time_scale="tdb")

    gc.collect()
    _reset_hwm()
    hwm0 = _hwm_mb()
    run()                       # the RSS first, untraced (tracemalloc's own records would count in it)
    hwm = _hwm_mb() - hwm0
    sun_path.__globals__["_PATHS"].clear()
    gc.collect()
    tracemalloc.start()
    run()
    peak = tracemalloc.get_traced_memory()[1] / 2**20
    tracemalloc.stop()
    return {"body": body_name, "years": years, "what": what, "integrated_years": (max(epochs) - min(epochs)) / 365.25,
            "traced_peak_mb": peak, "hwm_rise_mb": hwm, "predicted_mb": predicted}


def main() -> None:
    if len(sys.argv) == 4:
        print(json.dumps(one(sys.argv[1], float(sys.argv[2]), sys.argv[3])))
        return
    print("| body | span (years) | integrated (years) | what | traced peak (MB) | RSS high-water rise (MB) | "
          "traced MB a year | predicted (MB) |")
    print("|---|---:|---:|---|---:|---:|---:|---:|")
    for body, years in CASES:
        for what in ("path", "track"):
            out = subprocess.run([sys.executable, __file__, body, str(years), what], capture_output=True, text=True)
            if out.returncode:
                print(f"| {body} | {years} | | {what} | failed: {out.stderr.strip().splitlines()[-1]} | | | |")
                continue
            r = json.loads(out.stdout.strip().splitlines()[-1])
            print(f"| {body} | {years} | {r['integrated_years']:.1f} | {what} | {r['traced_peak_mb']:.1f} | "
                  f"{r['hwm_rise_mb']:.1f} | {r['traced_peak_mb'] / r['integrated_years']:.2f} | "
                  f"{r['predicted_mb']:.1f} |", flush=True)


if __name__ == "__main__":
    main()
