"""Benchmark: the cost predictions of ``ephem.theory.cost`` against the measured CPU time and memory.

``ephem.theory.cost`` predicts what a request will cost (CPU seconds of one core, peak MB) from its
parameters, with the unit costs of ``data/cost_model.toml`` (and each family's own predictors and table:
``ephem.earth.costs``, ``data/earth_costs.toml``; ``ephem.moon.costs``); the service refuses a request whose
prediction exceeds its budget (5 s, 500 MB) before running it. This script runs the real library
calls on representative inputs, from small to near that budget, and prints each prediction
against the measurement (ratio measured / predicted: above 1 the prediction was optimistic):

* predictors, one at a time: each function of ``ephem.theory.cost`` (or a family's costs module) that the
  tables calibrate, against the library call it stands for (the Hansen FFT by eccentricity, the e-power
  series by order, the nutation's extremes, the harmonic sums over epochs x harmonics, the
  second-order theory, the spin integration of the numerical rungs, the real orbit by years, the
  free rotation by method, the lunisolar sum, the serialisation of the answer as JSON and CSV);
* requests: ``ephem.api`` entry points run inside ``ephem.base.budget.budget(1e9, 1e9)``; the
  prediction is the budget's ``spent_cpu_s`` afterwards (what the service charges) and the
  largest memory of the costs charged;
* the unit costs these measurements imply on this machine, beside those of the toml.

Measured: CPU = ``time.process_time()`` around the call (the whole process), wall =
``time.perf_counter()``; BLAS runs on one thread unless ``--blas-threads`` says otherwise (as the test
suite does: on shared cores a multi-threaded BLAS busy-waits, and the CPU and even the wall time
of the same call vary several-fold from run to run; ``--blas-threads 0`` measures as the service
runs, with the library's default); the median of several repetitions, each from cold
caches (every ``lru_cache`` a request fills is emptied first, as for the first such request in a
fresh worker; the start-up warm-up of the service, the Earth's lunisolar series, is done once
before). Memory: the ``tracemalloc`` peak above the start of the call (Python objects and numpy
arrays; one extra run, left out for the long integrations, where tracing slows the Python
right-hand sides) and the peak RSS above the RSS at the start (``/proc/self/status`` VmHWM after
resetting it through ``/proc/self/clear_refs``: also memory allocated outside Python, but freed
memory the process reuses does not show). The ratio uses the larger of the two.

The unit costs in data/cost_model.toml and the families' tables are not changed by this script: it reports what it finds.

Run: ``.venv/bin/python benchmarks/bench_cost.py`` (full, about 100 s on 2 shared cores;
writes benchmarks/RESULTS_cost.md), ``--quick`` for a smaller set (about 40 s),
``--out PATH`` to write the report elsewhere. Everything runs offline (DE421 comes with
skyfield-data).
"""
from __future__ import annotations

import argparse
import contextlib
import datetime as dt
import functools
import gc
import math
import os
import platform
import statistics
import sys
import time
import tracemalloc
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))


BLAS_VARS = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")


def _blas_threads_from_argv() -> None:
    """--blas-threads N must act before numpy loads its BLAS: read it from argv first (default 1; 0 leaves
    the environment as it is)."""
    value = "1"
    for i, arg in enumerate(sys.argv):
        if arg.startswith("--blas-threads="):
            value = arg.split("=", 1)[1]
        elif arg == "--blas-threads" and i + 1 < len(sys.argv):
            value = sys.argv[i + 1]
    if value.strip() != "0":
        for var in BLAS_VARS:
            os.environ[var] = value.strip()


if __name__ == "__main__":
    _blas_threads_from_argv()

import numpy as np  # noqa: E402

from ephem import api, host
from ephem.base import budget
from ephem.theory import cost
from ephem.earth import costs as earth_costs, model as earth
from ephem.orbit import de421 as ephemeris
from ephem.rotation import free_motion
from ephem.orbit import hansen
from ephem.sun import bounds as tables, rungs, spectrum
from ephem.rotation import lie_series
from ephem.forced import uncertainty  # noqa: E402
from ephem.bodies.catalogue import Body, Orbit, Pole, get_body  # noqa: E402
from ephem.forced.precession_nutation import build_model, cached_model  # noqa: E402
from ephem.forced.second_order import second_order_theory  # noqa: E402

BUDGET_CPU_S = 5.0
BUDGET_MB = 500.0
#: a measurement below these is small against the budget: an optimistic prediction there is noted, not flagged
SIGNIFICANT_CPU_S = 0.25
SIGNIFICANT_MB = 25.0
J2000 = 2451545.0
J2050 = 2469807.5
MB = 1024.0 * 1024.0

# Why a case may come out optimistic: read from the code, printed with the numbers of any case over 2x.
WHY_MODEL = ("ephem.forced.precession_nutation.build_model iterates the nutation at the pole epoch three times, and each pass calls "
             "kinoshita.nutation_series, which recomputes hansen_exact(e): three FFTs (plus the series' evaluation), "
             "while cost.hansen_build charges one.")
WHY_SERIES = ("hansen.hansen_series(order < 20) cuts the order-20 series (_SHARED_ORDER), which ephem.host.warm_up "
              "builds at the service's start-up (0.1-0.27 s once per process, charged to no request): cold() empties "
              "it with every other cache, so these cases pay that build, which cost.hansen_build(e, order), a cut, "
              "does not charge. Orders above 20 are built on first use and charged (series_s (1 + order)^4).")
WHY_BLOCK = ("harmonics.evaluate_harmonics sums in blocks whose work table is up to BLOCK_BYTES = 32 MB whatever "
             "the epochs: cost.harmonic_work_mb charges it (capped at harmonic_block_mb).")
WHY_CSV = ("service.app._csv_rows formats every float with repr (Python), ~20x slower than orjson: api.track_arrays "
           "charges it with its own unit, serialise_csv_s_per_value (output='csv').")
WHY_PATH = ("Ladder.cost charges cost.orbit_integration over the span from the track to the pole epoch, but "
            "ephemeris.integrate_heliocentric integrates from the orbit's elements' epoch (orbit.epoch_jd_tdb) to "
            "cover that span: up to the whole DE421 span (~150 years) more.")
WHY_LIE = ("the Lie series (sam_series.SamSeriesSolution.propagate) evaluates its order-12 polynomials on complex "
           "arrays over all the epochs at once, many temporaries an epoch, while cost.free_rotation charges "
           "track_bytes_per_epoch (250 B) an epoch.")
WHY_PATH_MB = ("the integration keeps DOP853's dense output of every step (solve_ivp dense_output=True) and the "
               "planets' Chebyshev table over the span while it fits the path: more than path_mb_per_year.")
WHY_SMALL_FIXED = "a fixed cost (set-up arrays, the series' tables) that the per-epoch prediction leaves out."


# ----------------------------------------------------------------------------------------- measuring

def _status_kb(key: str) -> int | None:
    try:
        with open("/proc/self/status") as fh:
            for line in fh:
                if line.startswith(key + ":"):
                    return int(line.split()[1])
    except OSError:
        return None
    return None


def _reset_peak_rss() -> int | None:
    """Reset VmHWM to the present RSS (Linux); return that RSS in kB, or None where unsupported."""
    try:
        with open("/proc/self/clear_refs", "w") as fh:
            fh.write("5")
    except OSError:
        return None
    return _status_kb("VmRSS")


@dataclass
class Measurement:
    cpu: list[float] = field(default_factory=list)
    wall: list[float] = field(default_factory=list)
    rss_mb: list[float] = field(default_factory=list)
    traced_mb: float | None = None

    @property
    def cpu_s(self) -> float:
        return statistics.median(self.cpu)

    @property
    def wall_s(self) -> float:
        return statistics.median(self.wall)

    @property
    def peak_mb(self) -> float:
        """The larger of the traced peak and the RSS growth; NaN when untraced and the RSS did not grow by
        1 MB (the allocator reused memory freed earlier: the measurement says nothing)."""
        rss = max(self.rss_mb) if self.rss_mb else float("nan")
        if self.traced_mb is None:
            return rss if rss >= 1.0 else float("nan")
        return self.traced_mb if math.isnan(rss) else max(rss, self.traced_mb)


def measure(work: Callable[[], object], setup: Callable[[], None] | None, reps: int, trace: bool) -> Measurement:
    """``reps`` timed runs of ``work`` (each after ``setup``), then one traced run for the memory."""
    m = Measurement()
    for _ in range(reps):
        if setup is not None:
            setup()
        gc.collect()
        base_kb = _reset_peak_rss()
        c0, w0 = time.process_time(), time.perf_counter()
        result = work()
        m.cpu.append(time.process_time() - c0)
        m.wall.append(time.perf_counter() - w0)
        peak_kb = _status_kb("VmHWM") if base_kb is not None else None
        if peak_kb is not None:
            m.rss_mb.append(max(0.0, (peak_kb - base_kb) / 1024.0))
        del result
    if trace:
        if setup is not None:
            setup()
        gc.collect()
        tracemalloc.start()
        try:
            result = work()
            m.traced_mb = tracemalloc.get_traced_memory()[1] / MB
            del result
        finally:
            tracemalloc.stop()
    return m


def body_caches() -> list:
    """The caches a request fills for its body (its model, second-order theory, estimate tables, uncertainties,
    real orbit, Hansen coefficients, long-term orbit): empty in a worker that has not yet answered for that body.
    The start-up's (``host.warm_up``: the Earth's lunisolar series, the Moon's libration series, the rational Hansen
    series every e-order is cut from, DE421) are not among them."""
    from ephem.forced import pole_uncertainty
    from ephem.longterm import history as long_term
    from ephem.forced import cassini
    from ephem.sun import family, geodesic
    from ephem.forced import catalogue_sigmas
    return [cached_model, tables.cached_theory, tables.cached_tables, uncertainty.propagated, spectrum.semi_amplitudes,
            pole_uncertainty.cached_pole_sensitivity, ephemeris._cached_path, hansen.hansen_exact,
            geodesic.periodic_excess, long_term._nbody, family.cached_secular_spin, cassini._free_librations,
            *(getattr(m, n) for m, n in ((pole_uncertainty, "_cached_sigma"), (catalogue_sigmas, "_kept_sigmas"))
              if hasattr(m, n))]


def cold() -> None:
    """Empty every cache a request fills (the first such request in a fresh worker): the body's
    (:func:`body_caches`) and the free rotation's and e-power series' built on first use. The start-up
    caches stay: catalogue, DE421 kernel, the Earth's lunisolar series (``host.warm_up``)."""
    for fn in (*body_caches(), free_motion._series, lie_series.sam_normal_form, hansen.hansen_series):
        fn.cache_clear()


@contextlib.contextmanager
def recording_charges(charged: list):
    """Within the block, every cost charged to a budget (not prepaid) is appended to ``charged``: each module of
    the library that took :func:`ephem.base.budget.charge` by name charges through a recorder meanwhile."""
    original = budget.charge

    def recording(c, body=None):
        b = budget.current()
        if b is not None and not b.prepaid:
            charged.append(c)
        return original(c, body)

    patched = [m for name, m in list(sys.modules.items())
               if (name == "ephem" or name.startswith("ephem.")) and m is not None
               and m is not budget and m.__dict__.get("charge") is original]
    for m in patched:
        m.charge = recording
    try:
        yield charged
    finally:
        for m in patched:
            m.charge = original


class Request:
    """Runs an api call inside ``budget(1e9, 1e9)``: the prediction is the budget's ``spent_cpu_s`` and the
    largest memory of the costs charged (each charge is checked against the memory budget on its own)."""

    def __init__(self, call: Callable[[], object]):
        self.call = call
        self.spent_cpu_s = 0.0
        self.memory_mb = 0.0
        self.parts: list[cost.Part] = []

    def __call__(self):
        charged: list[cost.Cost] = []
        with recording_charges(charged), budget.budget(1e9, 1e9) as b:
            out = self.call()
        self.spent_cpu_s = b.spent_cpu_s
        self.memory_mb = max((c.memory_mb for c in charged), default=0.0)
        self.parts = [p for c in charged for p in c.parts]
        return out


# ----------------------------------------------------------------------------------------- inputs

_serial = iter(range(10**9))


def synthetic(e: float, a_au: float = 2.5, hd: float = 0.1, period_hours: float = 6.0,
              orbit_epoch: float = J2000, pole_epoch: float = J2000) -> Body:
    """A user's body (no catalogue uncertainties), named uniquely so that no cache is shared."""
    return Body(f"bench-{next(_serial)}", Orbit(a_au, e, 5.0, 40.0, 70.0, 10.0, orbit_epoch),
                Pole(60.0, 50.0, pole_epoch), period_hours, dynamical_ellipticity=hd)


def grid(n: int, span_days: float, start: float = J2000) -> tuple[float, float, np.ndarray]:
    step = span_days / (n - 1)
    return start, step, start + step * np.arange(n)


@dataclass
class Case:
    group: str              # the predictor (or "request")
    label: str              # the inputs
    predict: Callable[[], tuple[float, float]]    # (cpu s, MB), evaluated after the timed runs
    work: Callable[[], object]
    setup: Callable[[], None] | None = cold
    quick: bool = False
    trace: bool = True
    reps: int | None = None
    note: str = ""
    why: str = ""           # the cause, printed when the case is optimistic by more than 2x
    # filled in
    pred_cpu: float = float("nan")
    pred_mb: float = float("nan")
    m: Measurement | None = None
    error: str | None = None
    extra: dict = field(default_factory=dict)

    @property
    def cpu_ratio(self) -> float:
        return self.m.cpu_s / self.pred_cpu if self.m and self.pred_cpu > 0 else float("nan")

    @property
    def wall_ratio(self) -> float:
        return self.m.wall_s / self.pred_cpu if self.m and self.pred_cpu > 0 else float("nan")

    @property
    def mb_ratio(self) -> float:
        return self.m.peak_mb / self.pred_mb if self.m and self.pred_mb > 0 else float("nan")


    def flag(self) -> str:
        if self.m is None:
            return "error"
        cpu_bad = self.cpu_ratio > 2.0
        mb_bad = self.mb_ratio > 2.0
        sig_cpu = self.m.cpu_s >= SIGNIFICANT_CPU_S
        sig_mb = self.m.peak_mb >= SIGNIFICANT_MB
        out = []
        if cpu_bad:
            out.append("**CPU OPTIMISTIC**" if sig_cpu else "cpu under (small)")
        elif self.cpu_ratio > 1.0:
            out.append("cpu under <=2x")
        if mb_bad:
            out.append("**MB OPTIMISTIC**" if sig_mb else "mb under (small)")
        elif self.mb_ratio > 1.0:
            out.append("mb under <=2x")
        return "; ".join(out) or "ok"


def part(p: cost.Part) -> Callable[[], tuple[float, float]]:
    return lambda: (p.cpu_s, p.memory_mb)


def build_cases() -> list[Case]:
    cases: list[Case] = []
    add = cases.append

    # --- the exact Hansen coefficients: an N-point FFT ----------------------------------------
    for e, quick in ((0.1, False), (0.5, True), (0.9, True), (0.95, False), (0.99, True), (0.995, False)):
        n, _ = cost.harmonics(e, None)
        add(Case("hansen_build (exact FFT)", f"hansen_exact(e={e}), N={n}", part(cost.hansen_build(e, None)),
                 lambda e=e: hansen.hansen_exact(e), None, quick, extra={"N": n, "kind": "fft"}))
    for e, quick in ((0.9, False), (0.99, True)):       # e = 0.995: the precession request below
        n, _ = cost.harmonics(e, None)
        b = synthetic(e)
        add(Case("hansen_build (exact FFT)", f"build_model(e={e}): the whole first-order model, N={n}",
                 part(cost.hansen_build(e, None)), lambda b=b: build_model(b, None), None, quick,
                 extra={"N": n, "kind": "model"}, why=WHY_MODEL))

    # --- the e-power series, built with exact rationals (first use; cached after) -------------
    for order, quick in ((4, True), (20, False), (25, False), (30, True)):
        add(Case("hansen_build (e-power series)", f"hansen_series({order}) cold", part(cost.hansen_build(0.1, order)),
                 lambda o=order: hansen.hansen_series(o), hansen.hansen_series.cache_clear, quick,
                 trace=order <= 20, extra={"order": order}, why=WHY_SERIES))

    # --- the nutation's extremes: 64 K grid points x K harmonics, twice ------------------------
    for e, quick in ((0.5, False), (0.9, True), (0.95, False)):
        b = synthetic(e)
        k = cost.body_harmonics(b)
        m = build_model(b)
        add(Case("half_peak_to_peak", f"semi_peak_to_peak, e={e}, K={k} (the series has "
                                      f"{len(m.nutation.multiple)})", part(cost.half_peak_to_peak(e, None, k)),
                 lambda m=m: m.nutation.semi_peak_to_peak(), None, quick, trace=e < 0.95, reps=2 if e >= 0.95 else None,
                 extra={"K": k, "K_actual": len(m.nutation.multiple)}, why=WHY_BLOCK))

    # --- the estimates' tables of a body (once per body and process) ---------------------------
    for e, quick in ((0.1, True), (0.6, False), (0.9, True), (0.95, False)):
        b = synthetic(e)
        m, th = build_model(b), tables.cached_theory(b)
        add(Case("estimate_tables", f"theory_tables, e={e}", part(cost.estimate_tables(e)),
                 lambda m=m, th=th: tables.theory_tables(m, th), None, quick, trace=e < 0.95,
                 extra={"K": cost.harmonics(e, None)[1]}))

    # --- harmonic sums: the hansen / series tracks on the even grid ------------------------------
    for e, n, quick in ((0.1, 1_000, True), (0.1, 100_000, True), (0.5, 100_000, False), (0.9, 10_000, False),
                        (0.9, 100_000, True), (0.95, 100_000, False)):
        b = synthetic(e)
        m = build_model(b)
        k = len(m.nutation.multiple)
        t0, step, _ = grid(n, 20 * 365.25)
        add(Case("harmonic_sum", f"track_grid, e={e}, {n} epochs x {k} harmonics",
                 part(cost.harmonic_sum(n, k, "step_days", "track")),
                 lambda m=m, t0=t0, step=step, n=n: m.track_grid(t0, step, n), None, quick,
                 reps=2 if n * k > 5e7 else None, trace=n * k <= 1e8, extra={"n": n, "k": k}, why=WHY_BLOCK))
    b = synthetic(0.9)
    m = build_model(b)
    k = len(m.nutation.multiple)
    _, _, t = grid(100_000, 20 * 365.25)
    add(Case("harmonic_sum", f"track at any epochs (ladder estimates, wobble), e=0.9, 100000 x {k}",
             part(cost.harmonic_sum(100_000, k, "step_days", "track")), lambda m=m, t=t: m.track(t), None, False,
             reps=2, extra={"n": 100_000, "k": k}, why=WHY_BLOCK))

    # --- the second-order theory: the theory's build and its track -------------------------------
    for e, n, quick in ((0.1, 100_000, True), (0.9, 10_000, False), (0.9, 100_000, True)):
        b = synthetic(e)
        m = build_model(b)
        k = cost.body_harmonics(b)
        _, _, t = grid(n, 20 * 365.25)
        add(Case("second_order", f"second_order_theory + track, e={e}, {n} epochs, K={k}",
                 part(cost.second_order(n, k)),
                 lambda m=m, t=t: rungs.second_order_track(m, second_order_theory(m), t), None, quick,
                 extra={"n": n, "k": k}, why=WHY_BLOCK))

    # --- the pole epoch's two sides (issue 39): the work done from it outward, once on each side ------------
    # warm (the body's model and theory built), a span across J2000 (1950-2050) against one on one side of it
    # (2000-2050): the second-order mean track, the rotation averaging's bound (the estimates' two calls), the
    # long-term model's averaged spin; and the new estimates' weighing into the byte pool (estimates() against
    # _estimates(), the memo emptied before each)
    from ephem.forced.physics_errors import rotation_averaging_bound, rotation_averaging_sides
    from ephem.families import theory_for
    from ephem.longterm import averaged_spin, history as long_term_history
    from ephem.sun import ladder as ladder_module
    from ephem.forced.rotation_scale import forget_spans

    def new_question():
        """The memos of an identical question emptied: the ladder's estimates for these epochs and the spans' samples
        (each repetition then estimates as a new question about a body already served does)."""
        ladder_module._cached_estimates.cache_clear()
        forget_spans()

    side_cases = (("mars", True), ("steins", False), ("itokawa", True))
    for name, quick in side_cases:
        b = get_body(name)
        th = tables.cached_theory(b)
        m = cached_model(b)
        for label, lo, hi in (("across", 1950.0, 2050.0), ("one side", 2000.0, 2050.0)):
            t = J2000 + (np.linspace(lo, hi, 1000) - 2000.0) * 365.25
            sides = cost.pole_epoch_sides(J2000, t[0], t[-1])
            extra = {"body": name, "side": label}
            add(Case("pole_epoch_sides", f"second-order mean track, {name}, {lo:.0f}-{hi:.0f}, 1000 epochs",
                     part(cost.Part("", "", cost.mean_track(sides), 0.0)), lambda th=th, t=t: th.mean_track(t)(t),
                     None, quick, trace=False, reps=15, extra={**extra, "what": "mean_track"}))
            t10 = t[::111]
            # each side's fixed work (the first one's is in estimates_base_s), and its samples where it takes them
            n_sides = rotation_averaging_sides(b, t10[0], t10[-1])
            samples = ladder_module.rotation_averaging_samples(b, t10[0], t10[-1])
            add(Case("pole_epoch_sides", f"rotation averaging's bound (two calls), {name}, {lo:.0f}-{hi:.0f}"
                     + (f" ({samples} samples)" if samples else ""),
                     part(cost.Part("", "", n_sides * cost.unit("estimates_averaging_side_s")
                                    + samples * cost.unit("estimates_averaging_sample_s"), 0.0)),
                     lambda b=b, m=m, t=t10: [rotation_averaging_bound(b, m, t, "figure", x) for x in ("none", "oppolzer")],
                     forget_spans, quick, trace=False, reps=15,
                     extra={**extra, "what": "averaging", "samples": samples}))
        spin = theory_for(b, b.perturbers).secular_spin()
        t0 = spin.epoch_years
        for label, lo, hi in (("across", t0 - 50.0, t0 + 50.0), ("one side", t0, t0 + 100.0)):
            years = np.linspace(lo, hi, 11)
            orbit = long_term_history.default_orbit(b, spin.orbit_body, lo, hi).orbit
            sides = cost.pole_epoch_sides(t0, lo, hi)
            add(Case("pole_epoch_sides", f"long-term averaged spin, {name}, {lo - t0:+.0f} to {hi - t0:+.0f} years "
                                         "from its epoch, 11 epochs",
                     part(spin.cost(hi - lo, 11, sides)),
                     lambda spin=spin, orbit=orbit, years=years: averaged_spin.integrate(spin, orbit, years), None,
                     quick, trace=False, reps=15, extra={"body": name, "side": label, "what": "spin_history"}))
        lad = ladder_module.Ladder(b)
        t = J2000 + (np.linspace(2030.0, 2040.0, 10) - 2000.0) * 365.25
        lad.estimates(t)
        k = cost.body_harmonics(b)
        samples = ladder_module.rotation_averaging_samples(b, t[0], t[-1])
        for label, work, weighed in (("estimates()", lambda lad=lad, t=t: lad.estimates(t), True),
                                     ("_estimates()", lambda lad=lad, t=t: lad._estimates(t), False)):
            add(Case("pole_epoch_sides", f"every rung's estimates, {name}, 2030-2040, 10 epochs: {label}",
                     part(cost.ladder_estimates(10, k, samples, 1, weighed)), work,
                     new_question, quick, trace=False, reps=15,
                     extra={"body": name, "what": "weighed" if weighed else "unweighed"}))

    # --- the spin axis integrated (numerical, real_orbit rungs) -----------------------------------
    from ephem.forced.integration import integrate_spin_axis
    # tracemalloc slows the Python right-hand side several times: the memory of two is traced, the rest by RSS
    for e, a, years, n, hd, period, quick, trace in ((0.1, 1.0, 50, 1000, 0.1, 6.0, True, True),
                                                     (0.1, 1.0, 300, 1000, 0.1, 6.0, False, False),
                                                     (0.5, 1.0, 100, 1000, 0.1, 6.0, True, False),
                                                     (0.9, 3.0, 150, 1000, 0.1, 6.0, False, False),
                                                     (0.5, 0.5, 20, 1000, 0.3, 77.0, False, False),
                                                     (0.1, 1.0, 10, 100_000, 0.1, 6.0, False, True)):
        b = synthetic(e, a_au=a, hd=hd, period_hours=period)
        m = build_model(b)
        _, _, t = grid(n, years * 365.25)
        orbits = rungs.orbits_in_span(m, t)
        strong = " (strong torque: H_d 0.3, w/n 40)" if hd > 0.1 else ""
        add(Case("spin_integration", f"DOP853, e={e}, {orbits:.0f} orbits, {n} epochs{strong}",
                 part(cost.spin_integration(orbits, e, n)),
                 lambda m=m, t=t: integrate_spin_axis(m, t, rtol=rungs.NUMERICAL_RTOL), None, quick,
                 trace=trace, reps=2,
                 extra={"orbits": orbits, "e": e, "n": n}))

    # --- the real orbit: integrated under the DE421 planets from the elements' epoch --------------
    ito = get_body("itokawa")
    ep = ito.orbit.epoch_jd_tdb
    for years, quick in ((10, True), (50, False), (120, False)):
        lo, hi = ep - years * 365.25, ep
        add(Case("orbit_integration", f"sun_path(Itokawa), {years} years back from its elements' epoch",
                 part(cost.orbit_integration(years * 365.25)),
                 lambda lo=lo, hi=hi: ephemeris.sun_path(ito, lo, hi), ephemeris._cached_path.cache_clear, quick,
                 trace=years <= 10, reps=2, extra={"years": years}, why=WHY_PATH_MB))

    # --- the free rotation -----------------------------------------------------------------------
    eros = get_body("eros")
    rot_per_day = 24.0 / eros.rotation_period_hours
    for method, n, days, quick, warm in (("exact", 1_000, 100.0, True, False), ("exact", 100_000, 1000.0, True, False),
                                         ("series", 10_000, 100.0, True, False), ("series", 100_000, 1000.0, False, True),
                                         ("numeric", 1_000, 22.0, True, False)):   # 1000 rotations: a request below
        _, _, t = grid(n, days)
        rotations = days * rot_per_day
        add(Case("free_rotation", f"{method}{' (series built: warm)' if warm else ''}, {n} epochs, "
                                  f"{rotations:.0f} rotations (Eros)",
                 part(cost.free_rotation(method, n, rotations)),
                 lambda t=t, method=method: free_motion.free_motion(eros, t, None, method),
                 (lambda t=t, m=method: free_motion.free_motion(eros, t[:10], None, m)) if warm else cold,
                 quick, trace=method != "numeric", why=WHY_LIE if method == "series" else WHY_SMALL_FIXED,
                 reps=2 if method == "numeric" else None, extra={"n": n, "method": method, "rotations": rotations,
                                                                  "warm": warm}))

    # --- the Earth's lunisolar series (built at start-up) ----------------------------------------
    earth_body = get_body("earth")
    lm = earth.lunisolar_earth(earth_body, "figure", earth.TRACK_CUT_MAS, earth_body.perturbers)
    for n, quick in ((1_000, True), (10_000, False), (100_000, True)):
        _, _, t = grid(n, 100 * 365.25, 2415021.0)
        add(Case("lunisolar_sum", f"lunisolar track, {n} epochs", part(earth_costs.lunisolar_sum(n)),
                 lambda t=t: lm.track(t), None, quick, extra={"n": n}, why=WHY_SMALL_FIXED))

    # --- serialisation of a track answer (7 columns) ---------------------------------------------
    from service.app import _csv_rows, finite_json
    for n, quick in ((10_000, True), (100_000, True), (1_000_000, False)):
        # the answer is built on first use (not at all when --quick leaves the case out)
        ans = functools.cache(lambda n=n: api.track_arrays(get_body("vesta"), J2000, J2000 + 0.01 * (n - 1), 0.01,
                                                           max_samples=n + 1))
        add(Case("serialised", f"JSON (service finite_json: check + orjson), {n} epochs x 7",
                 part(cost.serialised(n, 7)), lambda ans=ans: finite_json(ans()), ans, quick,
                 extra={"n": n, "fmt": "json"}))
        if n <= 100_000:
            add(Case("serialised", f"CSV (service _csv_rows, streamed), {n} epochs x 7",
                     part(cost.serialised(n, 7, "csv")), lambda ans=ans: "".join(_csv_rows(ans(), "utc")), ans, quick,
                     trace=n <= 10_000, extra={"n": n, "fmt": "csv"}, why=WHY_CSV))

    # --- requests: what the service charges --------------------------------------------------------
    def request(label, call, quick=False, trace=True, reps=None, note="", why=""):
        r = Request(call)
        add(Case("request", label, lambda r=r: (r.spent_cpu_s, r.memory_mb), r, cold, quick, trace, reps, note,
                 why, extra={"request": r}))

    for e, quick in ((0.5, False), (0.9, True), (0.99, True), (0.995, False)):
        request(f"precession, user body e={e}", lambda e=e: api.precession(synthetic(e)), quick,
                reps=2 if e > 0.99 else None, trace=e <= 0.99, why=WHY_MODEL)
    request("precession Vesta (propagates the catalogue's sigmas)", lambda: api.precession("vesta"), True)
    request("precession Vesta, tolerance_mas=1 (truncation bounds)",
            lambda: api.precession("vesta", tolerance_mas=1.0), True, why=WHY_SERIES)
    for e, quick in ((0.9, True), (0.95, False)):
        request(f"nutation, user body e={e}", lambda e=e: api.nutation(synthetic(e)), quick, trace=e < 0.95,
                reps=2 if e >= 0.95 else None, why=WHY_MODEL + " " + WHY_BLOCK)
    request("precession_nutation (POST), user body e=0.9, hansen track 10^4 epochs",
            lambda: api.precession_nutation(synthetic(0.9), track=dict(start=J2000, stop=J2000 + 3652.5,
                                                                        step_days=3652.5 / 9999)), False,
            why=WHY_MODEL + " " + WHY_BLOCK)
    for rung, quick in (("secular", False), ("series", True), ("hansen", True), ("second_order", False),
                        ("numerical", True), ("real_orbit", True), (None, True)):
        what = (f"model={rung}" + (", order=4" if rung == "series" else "") if rung
                else "axis=angular_momentum, tolerance_mas=1000 (the model predicted cheapest within it)")
        request(f"track Eros 2000-2010 daily (3654 epochs), {what}",
                lambda rung=rung: api.track_arrays("eros", J2000, J2000 + 3653, 1.0, model=rung,
                                                   order=4 if rung == "series" else None,
                                                   tolerance_mas=None if rung else 1000.0,
                                                   axis="figure" if rung else "angular_momentum"),
                quick, trace=rung not in ("numerical", "real_orbit", None), reps=2 if rung in ("real_orbit", None)
                else None, why=WHY_SERIES)
    request("track, user body e=0.95, hansen, 10^5 epochs (the service's cap)",
            lambda: api.track_arrays(synthetic(0.95), J2000, J2000 + 3652.5, 3652.5 / 99_999, model="hansen"),
            False, trace=False, reps=2)
    request("track, user body e=0.1, a=0.5 AU, numerical, 480 orbits (170 yr, 6210 epochs)",
            lambda: api.track_arrays(synthetic(0.1, a_au=0.5), J2000, J2000 + 62090.0, 10.0, model="numerical"),
            False, trace=False, reps=2)
    request("track, user body with elements at 1900, pole epoch 2050, real_orbit 2050-2051 daily",
            lambda: api.track_arrays(synthetic(0.2, a_au=2.0, orbit_epoch=2415020.5, pole_epoch=J2050),
                                     J2050, J2050 + 365.0, 1.0, model="real_orbit"),
            True, trace=False, reps=2, why=WHY_PATH)
    request("free_motion Eros exact, 10^5 epochs",
            lambda: api.free_motion_arrays("eros", J2000, J2000 + 1000.0, 0.01, method="exact"), False)
    request("free_motion Eros series, 2x10^5 epochs (admitted: ~4.4 s predicted; the Docker image allows 10^6)",
            lambda: api.free_motion_arrays("eros", J2000, J2000 + 2000.0, 0.01, method="series",
                                           max_samples=200_002), False, trace=False, reps=2, why=WHY_LIE)
    request("free_motion Eros numeric, 1000 epochs over 1000 rotations",
            lambda: api.free_motion_arrays("eros", J2000, J2000 + 219.6, 0.2196, method="numeric"), True,
            trace=False, reps=2)
    from service.app import _csv_rows
    request("track Vesta (hansen) 10^6 epochs as CSV: track_arrays + service _csv_rows (the library's cap; the "
            "service's is 10^5)",
            lambda: "".join(_csv_rows(api.track_arrays("vesta", J2000, J2000 + 9999.99, 0.01,
                                                       max_samples=1_000_001, output="csv"), "utc")),
            False, trace=False, reps=2, why=WHY_CSV)
    request("precession Moon (Cassini state, shipped libration series)", lambda: api.precession("moon"), True)
    for model, quick in (("cassini", True), ("librations", True)):
        request(f"track Moon 1900-2100 daily (73050 epochs), model={model}",
                lambda model=model: api.track_arrays("moon", 2415020.5, 2415020.5 + 73049.0, 1.0, model=model),
                quick, why=WHY_SMALL_FIXED)
    request("track Moon 2000-2020 daily, model=integration (the rigid Moon on its real orbit)",
            lambda: api.track_arrays("moon", J2000, J2000 + 7305.0, 1.0, model="integration"), True, trace=False,
            reps=2)
    request("precession Earth (lunisolar, warm)", lambda: api.precession("earth"), True)
    request("nutation Earth (lunisolar, warm)", lambda: api.nutation("earth"), False)
    for n, quick in ((10_000, False), (100_000, True)):
        step = 100 * 365.25 / (n - 1)
        request(f"track Earth lunisolar, {n} epochs over 100 years",
                lambda step=step: api.track_arrays("earth", 2415021.0, 2415021.0 + 100 * 365.25, step), quick,
                why=WHY_SMALL_FIXED)
    for body, half, quick in (("earth", 1.0e6, True), ("ceres", 1.0e6, True), ("mars", 2.0e6, False),
                              ("moon", 2.0e6, False)):
        request(f"history {body.title()} over {2 * half / 1e6:g} Myr at 1000-yr steps (the shipped N-body orbit)",
                lambda body=body, half=half: api.history(body, -half, half, 1000.0), quick, trace=False, reps=2)
    request("history, user body (Vesta's elements) over 200 kyr, secular orbit",
            lambda: api.history(synthetic(0.09, a_au=2.36), -1.0e5, 1.0e5, 1000.0, orbit_model="secular"), True,
            trace=False, reps=2)
    request("track Ceres 3000-3100 yearly, tolerance_mas=200000 (chooses long_term)",
            lambda: api.track_arrays("ceres", 2816788.0, 2816788.0 + 36525.0, 365.25, tolerance_mas=2e5), True,
            trace=False, reps=2)
    return cases


# ----------------------------------------------------------------------------------------- analysis

def fit_units(cases: list[Case]) -> list[tuple[str, float, float | None, str]]:
    """(unit, toml value, value implied by the measurements, how) for the calibrated unit costs (the shared table's
    and each family's own: data/cost_model.toml, data/earth_costs.toml)."""
    u = {**cost.unit_costs(), **cost.unit_table(earth_costs.TABLE)}
    by = {}
    for c in cases:
        if c.m is not None:
            by.setdefault(c.group, []).append(c)
    rows = []

    def row(key, implied, how):
        rows.append((key, float(u[key]), implied, how))

    fft = [c for c in by.get("hansen_build (exact FFT)", []) if c.extra["kind"] == "fft" and c.extra["N"] >= 4096]
    if fft:
        v = max(c.m.cpu_s / (c.extra["N"] * math.log2(c.extra["N"])) for c in fft)
        row("fft_s_per_n_log_n", v, "largest CPU / (N log2 N) of hansen_exact, N >= 4096")
        mem = [c for c in fft if c.m.traced_mb is not None]
        if mem:
            row("fft_bytes_per_sample", max(c.m.peak_mb * MB / c.extra["N"] for c in mem),
                "largest peak / N of hansen_exact")
    model = [c for c in by.get("hansen_build (exact FFT)", []) if c.extra["kind"] == "model" and c.extra["N"] >= 65536]
    if model:
        v = max((c.m.cpu_s - u["base_s"]) / (c.extra["N"] * math.log2(c.extra["N"])) for c in model)
        rows.append(("(fft_s_per_n_log_n as build_model needs it)", float(u["fft_s_per_n_log_n"]), v,
                     "largest (CPU - base_s) / (N log2 N) of the whole build_model (3 FFTs and the series), "
                     "N >= 65536"))
    ser = [c for c in by.get("hansen_build (e-power series)", []) if c.extra["order"] >= 20]
    if ser:
        row("series_s", max(c.m.cpu_s / (1 + c.extra["order"]) ** 4 for c in ser),
            "largest CPU / (1 + order)^4, orders >= 20")
    def per_epoch_and_harmonic(cs, epoch_key, harmonic_key, what):
        """The per-epoch unit from the few-harmonic cases (their harmonics included: an upper value), the
        per-harmonic unit from the many-harmonic ones after the per-epoch share."""
        few = [c.m.cpu_s / c.extra["n"] for c in cs if c.extra["k"] <= 30 and c.extra["n"] >= 10_000]
        many = [c for c in cs if c.extra["k"] >= 300 and c.extra["n"] >= 10_000]
        epoch = max(few) if few else 0.0
        if few:
            row(epoch_key, epoch, f"largest CPU / epochs of the {what} cases with K <= 30, n >= 10^4")
        if many:
            row(harmonic_key, max((c.m.cpu_s / c.extra["n"] - epoch) / c.extra["k"] for c in many),
                f"largest (CPU / epochs - that) / K of the {what} cases with K >= 300")

    hs = by.get("harmonic_sum", [])
    if hs:
        per_epoch_and_harmonic(hs, "epoch_s", "harmonic_s", "harmonic_sum")
        big = [c.m.peak_mb * MB / c.extra["n"] for c in hs if c.extra["n"] >= 100_000]
        if big:
            row("track_bytes_per_epoch", max(big), "largest peak / epochs, harmonic_sum cases with >= 10^5 epochs")
    hp = by.get("half_peak_to_peak", [])
    if hp:
        row("extrema_harmonic_s", max(c.m.cpu_s / (64.0 * c.extra["K"] ** 2) for c in hp),
            "largest CPU / (64 K^2), K the predicted harmonics (cost.body_harmonics)")
    so = by.get("second_order", [])
    if so:
        per_epoch_and_harmonic(so, "second_order_epoch_s", "second_order_harmonic_s", "second_order")
    sides = by.get("pole_epoch_sides", [])

    def pair(what: str, first: str, second: str, key: str = "side") -> list[tuple[str, float]]:
        """(body, CPU of the ``first`` case less the ``second``'s) of each body's pair of ``what`` cases."""
        got = {}
        for c in sides:
            if c.extra["what"] in what.split("|") and not c.extra.get("samples"):   # a side's fixed work alone
                got.setdefault(c.extra["body"], {})[c.extra.get(key, c.extra["what"])] = c.m.cpu_s
        return [(b, v[first] - v[second]) for b, v in got.items() if first in v and second in v]

    for key, what, first, second, how in (
            ("second_order_side_s", "mean_track", "across", "one side",
             "largest CPU across J2000 (1950-2050) less one side (2000-2050), 1000 epochs"),
            ("estimates_averaging_side_s", "averaging", "across", "one side",
             "largest CPU across J2000 less one side, the bound's two calls (bodies it does not sample there)"),
            ("spin_history_side_s", "spin_history", "across", "one side",
             "largest CPU of the averaged spin across its epoch (-50 to +50 years) less one side (0 to +100)")):
        diffs = pair(what, first, second)
        if diffs:
            row(key, max(d for _, d in diffs), how + " (" + ", ".join(f"{b} {1e3 * d:.2f} ms" for b, d in diffs) + ")")
    weighed = pair("weighed|unweighed", "weighed", "unweighed", key="what")
    if weighed:
        row("estimates_weighed_s", max(d for _, d in weighed), "largest CPU of estimates() less _estimates(), 10 "
            "epochs (" + ", ".join(f"{b} {1e3 * d:.2f} ms" for b, d in weighed) + ")")
    sp = [c for c in by.get("spin_integration", []) if c.extra["n"] <= 1000]
    if sp:
        row("spin_orbit_s", max(c.m.cpu_s * math.sqrt(1.0 - c.extra["e"]) / c.extra["orbits"] for c in sp),
            "largest CPU x sqrt(1 - e) / orbits (1000 epochs)")
    dense = [c for c in by.get("spin_integration", []) if c.extra["n"] > 1000]
    if dense:
        c = dense[0]
        row("dense_output_s", c.m.cpu_s / c.extra["n"],
            f"CPU / epochs of the {c.extra['n']}-epoch integration over {c.extra['orbits']:.0f} orbits "
            "(an upper value: the orbits' share included)")
    oi = by.get("orbit_integration", [])
    if oi:
        row("path_s_per_year", max(c.m.cpu_s / c.extra["years"] for c in oi),
            "largest CPU / years (the base included; the cost per year grows with the span)")
        shortest = min(oi, key=lambda c: c.extra["years"])
        row("path_base_s", shortest.m.cpu_s, f"CPU of the {shortest.extra['years']}-year path, an upper value "
                                             "(DE421 loaded at start-up)")
        mem = [c.m.peak_mb / c.extra["years"] for c in oi if not math.isnan(c.m.peak_mb) and c.extra["years"] >= 50]
        if mem:
            row("path_mb_per_year", max(mem), "largest peak / years, paths of >= 50 years")
    fr = by.get("free_rotation", [])
    for c in fr:
        n, meth = c.extra["n"], c.extra["method"]
        if meth == "exact" and n >= 100_000:
            row("free_exact_epoch_s", c.m.cpu_s / n, f"CPU / epochs, exact, {n} epochs")
        if meth == "series" and c.extra["warm"]:
            row("free_series_epoch_s", c.m.cpu_s / n, f"CPU / epochs, series built, {n} epochs")
        if meth == "series" and not c.extra["warm"]:
            row("free_series_build_s", c.m.cpu_s, f"CPU of the cold call, {n} epochs (build + evaluation)")
    num = [c for c in fr if c.extra["method"] == "numeric"]
    if num:
        row("rigid_s_per_rotation", max(c.m.cpu_s / c.extra["rotations"] for c in num), "largest CPU / rotations")
    ls = [c for c in by.get("lunisolar_sum", []) if c.extra["n"] >= 10_000]
    if ls:
        row("lunisolar_epoch_s", max(c.m.cpu_s / c.extra["n"] for c in ls), "largest CPU / epochs (>= 10^4)")
    req = [c for c in by.get("request", []) if "Earth (lunisolar" in c.label]
    if req:
        row("lunisolar_answer_s", max(c.m.cpu_s for c in req), "largest CPU of the Earth's precession/nutation")
    for fmt in ("json", "csv"):
        s = [c for c in by.get("serialised", []) if c.extra["fmt"] == fmt and c.extra["n"] >= 100_000]
        if s:
            key = cost.SERIALISATIONS[fmt]
            rows.append((f"{key} ({fmt})", float(u[key]),
                         max(c.m.cpu_s / (7 * c.extra["n"]) for c in s), "largest CPU / values (>= 10^5 epochs)"))
    s = [c for c in by.get("serialised", []) if c.extra["fmt"] == "json" and c.extra["n"] >= 100_000]
    if s:
        row("serialised_bytes_per_value", max(c.m.peak_mb * MB / (7 * c.extra["n"]) for c in s),
            "largest peak / values, JSON")
    small = [c.m.cpu_s for c in cases if c.m is not None and c.group == "hansen_build (exact FFT)"
             and c.extra["kind"] == "fft" and c.extra["N"] <= 512]
    if small:
        row("base_s", max(small), "CPU of the smallest hansen_exact (N <= 512)")
    return rows


def g(x: float, digits: int = 3) -> str:
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "-"
    if x == 0:
        return "0"
    return f"{x:.{digits}g}"


def case_table(cases: list[Case]) -> list[str]:
    lines = ["| predictor | inputs | pred CPU s | CPU s | wall s | CPU ratio | wall ratio | pred MB | traced MB "
             "| RSS Δ MB | MB ratio | flag |",
             "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"]
    for c in cases:
        if c.m is None:
            lines.append(f"| {c.group} | {c.label} | {g(c.pred_cpu)} | error: {c.error} | | | | | | | | error |")
            continue
        m = c.m
        rss = max(m.rss_mb) if m.rss_mb else float("nan")
        lines.append(f"| {c.group} | {c.label}{' — ' + c.note if c.note else ''} | {g(c.pred_cpu)} | "
                     f"{g(m.cpu_s)} (min {g(min(m.cpu), 2)}, n={len(m.cpu)}) | {g(m.wall_s)} | {c.cpu_ratio:.2f} | {c.wall_ratio:.2f} | "
                     f"{g(c.pred_mb)} | {g(m.traced_mb) if m.traced_mb is not None else 'not traced'} | {g(rss)} | "
                     f"{'-' if math.isnan(c.mb_ratio) else f'{c.mb_ratio:.2f}'} | {c.flag()} |")
    return lines


UNITS = {
    "hansen_build (exact FFT)": "base_s, fft_s_per_n_log_n, fft_bytes_per_sample",
    "hansen_build (e-power series)": "series_s",
    "half_peak_to_peak": "extrema_harmonic_s",
    "harmonic_sum": "epoch_s, harmonic_s, track_bytes_per_epoch",
    "second_order": "base_s, second_order_epoch_s, second_order_harmonic_s, track_bytes_per_epoch",
    "pole_epoch_sides": "second_order_base_s, second_order_side_s, estimates_averaging_side_s, spin_history_base_s, "
                        "spin_history_side_s, estimates_base_s, estimates_weighed_s (a span across the pole epoch)",
    "spin_integration": "base_s, spin_orbit_s, dense_output_s, track_bytes_per_epoch, spin_bytes_per_orbit",
    "orbit_integration": "path_base_s, path_s_per_year, path_mb_per_year",
    "free_rotation": "base_s, free_exact_epoch_s, free_series_epoch_s, free_series_build_s, rigid_s_per_rotation, "
                     "dense_output_s, track_bytes_per_epoch",
    "lunisolar_sum": "lunisolar_epoch_s, track_bytes_per_epoch",
    "serialised": "serialise_s_per_value, serialise_csv_s_per_value, serialised_bytes_per_value",
    "request": "all (the charged sum: Ladder.cost, api.answer_cost, ...)",
}


def verdicts(cases: list[Case]) -> list[str]:
    groups: dict[str, list[Case]] = {}
    for c in cases:
        if c.m is not None:
            groups.setdefault(c.group, []).append(c)
    lines = ["| predictor | unit costs | cases | CPU ratio range | worst CPU ratio where >= 0.25 s | MB ratio range "
             "| worst MB ratio where >= 25 MB | verdict |", "|---|---|---:|---|---:|---|---:|---|"]
    for name, cs in groups.items():
        cr = [c.cpu_ratio for c in cs if not math.isnan(c.cpu_ratio)]
        mr = [c.mb_ratio for c in cs if not math.isnan(c.mb_ratio)]
        sig_c = [c.cpu_ratio for c in cs if c.m.cpu_s >= SIGNIFICANT_CPU_S and not math.isnan(c.cpu_ratio)]
        sig_m = [c.mb_ratio for c in cs if c.m.peak_mb >= SIGNIFICANT_MB and not math.isnan(c.mb_ratio)]
        worst_c = max(sig_c, default=float("nan"))
        worst_m = max(sig_m, default=float("nan"))
        if (sig_c and worst_c > 2) or (sig_m and worst_m > 2):
            v = "**optimistic > 2x at a significant size**: see findings"
        elif max(cr, default=0) > 2 or max(mr, default=0) > 2:
            v = "upper estimate where it matters; optimistic > 2x only on small inputs (see findings)"
        elif max(cr, default=0) > 1 or max(mr, default=0) > 1:
            v = "within 2x (tolerated)"
        else:
            v = "upper estimate (pessimistic) on every case"
        lines.append(f"| {name} | {UNITS.get(name, '')} | {len(cs)} | {g(min(cr, default=float('nan')), 2)}-{g(max(cr, default=float('nan')), 2)} "
                     f"| {g(worst_c, 2)} | {g(min(mr, default=float('nan')), 2)}-{g(max(mr, default=float('nan')), 2)} "
                     f"| {g(worst_m, 2)} | {v} |")
    return lines


def units_table(rows) -> list[str]:
    lines = ["| unit (data/cost_model.toml) | toml | implied here | toml / implied | from |", "|---|---:|---:|---:|---|"]
    for key, toml, implied, how in rows:
        ratio = toml / implied if implied else float("nan")
        mark = "" if 0.5 <= ratio <= 2.0 else " **(outside 0.5-2)**"
        lines.append(f"| {key} | {g(toml)} | {g(implied)} | {g(ratio, 2)}{mark} | {how} |")
    return lines


def findings(cases: list[Case], unit_rows) -> list[str]:
    """Every case optimistic by more than 2x, with numbers and its cause; then the unit costs outside 0.5-2x the
    measurement, with a proposal (the implied value, the toml's own rule)."""
    out = []
    bad = [c for c in cases if c.m is not None and (c.cpu_ratio > 2.0 or c.mb_ratio > 2.0)]
    for c in bad:
        sig = c.m.cpu_s >= SIGNIFICANT_CPU_S or c.m.peak_mb >= SIGNIFICANT_MB
        what = []
        if c.cpu_ratio > 2.0:
            what.append(f"CPU {g(c.m.cpu_s)} s measured against {g(c.pred_cpu)} s predicted ({c.cpu_ratio:.1f}x)")
        if c.mb_ratio > 2.0:
            what.append(f"memory {g(c.m.peak_mb)} MB against {g(c.pred_mb)} MB ({c.mb_ratio:.1f}x)")
        out.append(f"- {'**significant**' if sig else 'small'} — {c.group}: {c.label}: {'; '.join(what)}.")
        r = c.extra.get("request")
        if r is not None and r.parts:
            top = sorted(r.parts, key=lambda p: -p.cpu_s)[:4]
            out.append("  charged parts: " + "; ".join(f"{p.what} {g(p.cpu_s)} s / {g(p.memory_mb)} MB" for p in top))
        if c.why:
            out.append(f"  why: {c.why}")
    off = [(k, toml, implied) for k, toml, implied, _ in unit_rows if implied and not 0.5 <= toml / implied <= 2.0]
    if off:
        out += ["", "Unit costs outside 0.5-2x what this machine measures (toml / implied), with the value the toml's "
                    "rule (the measurement) gives:", ""]
        for k, toml, implied in off:
            out.append(f"- {k}: toml {g(toml)}, measured {g(implied)} ({implied / toml:.2g}x the toml): "
                       f"proposed {g(implied, 2)}")
    return out


def machine_info() -> list[str]:
    import numpy
    import scipy
    cpu = platform.processor() or "?"
    try:
        with open("/proc/cpuinfo") as fh:
            for line in fh:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    try:
        import orjson
        oj = orjson.__version__
    except Exception:  # pragma: no cover
        oj = "?"
    threads = {k: os.environ.get(k) for k in BLAS_VARS if os.environ.get(k)}
    load = os.getloadavg() if hasattr(os, "getloadavg") else None
    return [f"- date: {dt.datetime.now().astimezone().isoformat(timespec='seconds')}",
            f"- machine: {platform.machine()}, nproc {os.cpu_count()} (usable {len(os.sched_getaffinity(0))}), "
            f"CPU model: {cpu}",
            f"- python {platform.python_version()} ({platform.python_implementation()}), numpy {numpy.__version__}, "
            f"scipy {scipy.__version__}, orjson {oj}",
            f"- BLAS threads: {threads or 'library default (numpy may use every core: CPU can exceed wall)'}",
            f"- load average at the start: {', '.join(f'{x:.2f}' for x in load) if load else '?'}"]


# ----------------------------------------------------------------------------------------- main

def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="a smaller set of inputs (about 40 s)")
    ap.add_argument("--out", default=str(ROOT / "benchmarks" / "RESULTS_cost.md"), help="the Markdown report")
    ap.add_argument("--blas-threads", type=int, default=1,
                    help="BLAS/OpenMP threads (default 1, as the test suite: process CPU is then the CPU of one "
                         "core, without the busy-waiting of idle BLAS threads on shared cores; 0: the environment's "
                         "or the library's default, as the service runs)")
    ap.add_argument("--max-seconds", type=float, default=150.0,
                    help="stop starting new cases after this many seconds (default 150)")
    args = ap.parse_args(argv)
    started = time.perf_counter()

    # start-up, as a service worker: imports, DE421, the Earth's lunisolar series
    c0, w0 = time.process_time(), time.perf_counter()
    ephemeris.kernel()
    kernel_s = time.process_time() - c0
    import scipy.integrate  # noqa: F401
    host.warm_up()
    warm_cpu, warm_wall = time.process_time() - c0, time.perf_counter() - w0

    cases = build_cases()
    if args.quick:
        cases = [c for c in cases if c.quick]
    skipped = []
    for i, c in enumerate(cases, 1):
        if time.perf_counter() - started > args.max_seconds:
            skipped.append(c)
            continue
        reps = c.reps or 3
        if args.quick:
            reps = min(reps, 2)
        try:
            c.m = measure(c.work, c.setup, reps, c.trace)
            c.pred_cpu, c.pred_mb = c.predict()
        except Exception as exc:     # a case that fails is reported, not fatal
            c.error = f"{type(exc).__name__}: {exc}"[:200]
        status = f"ratio {c.cpu_ratio:.2f}" if c.m else c.error
        print(f"[{i}/{len(cases)} {time.perf_counter() - started:5.1f}s] {c.group}: {c.label}: {status}",
              file=sys.stderr, flush=True)
    cases = [c for c in cases if c not in skipped]
    elapsed = time.perf_counter() - started
    cpu_total = time.process_time()

    units = fit_units(cases)
    report = ["# Cost predictions against measurements (`benchmarks/bench_cost.py`)", "",
              f"Mode: {'--quick' if args.quick else 'full'}; run time {elapsed:.0f} s wall, {cpu_total:.0f} s CPU "
              f"(start-up included: DE421 {kernel_s:.2f} s, lunisolar warm-up {warm_cpu:.1f} s CPU / {warm_wall:.1f} s "
              "wall, not charged to any request)." + (f" **{len(skipped)} cases skipped** (over --max-seconds)."
                                                      if skipped else ""), "",
              *machine_info(), "",
              "Ratio = measured / predicted: above 1 the prediction was optimistic. The budget is "
              f"{BUDGET_CPU_S:g} s / {BUDGET_MB:g} MB; an estimate may be pessimistic by a few x, but should not be "
              "optimistic by more than ~2x near it. CPU = process CPU time (BLAS threads as above; median of n cold "
              "runs, each from empty caches), "
              "wall = median wall time; memory = the larger of the tracemalloc peak (one extra run) and the peak "
              "RSS above the start (max over the timed runs); an MB ratio '-' where the run was not traced and the RSS "
              "did not grow (memory freed earlier was reused: no measurement). Flags: 'small' when the measurement is below "
              f"{SIGNIFICANT_CPU_S:g} s and {SIGNIFICANT_MB:g} MB (5% of the budget).", "",
              "data/cost_model.toml's CPU units are the measurement (issue 39: predictions within 0.5-2x, held over "
              "a grid of track requests by benchmarks/bench_calibration.py); this script prints every predictor "
              "against the library call it stands for, from cold caches, and the units the measurements imply "
              "(below); it does not write the toml.", "",
              "## Verdict per predictor", "", *verdicts(cases), "",
              "## Unit costs implied on this machine", "",
              "The toml's CPU units are the measured value: toml / implied should lie within 0.5-2 (its memory "
              "units, about twice the measurement).", "", *units_table(units), "",
              "## Every case", "", *case_table(cases), "",
              "## Cases optimistic by more than 2x", "", *(findings(cases, units) or ["- none"]), ""]
    text = "\n".join(report)
    print(text)
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(text + "\n", encoding="utf-8")
    print(f"\nwritten: {out}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
