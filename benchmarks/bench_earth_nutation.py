"""Speed against accuracy of the Earth's nutation (Δψ, Δε): our series against ERFA's IAU 2000A and 2000B.

Models, each evaluated on the same epochs (JD TDB, 1900-01-01..2100-01-01):

* ours, rigid: ``earth_lunisolar(cut_mas=c, hd="iers2010", axis="figure").nutation_at(jd)`` for the cuts ``--cuts``;
* ours, non-rigid: ``non_rigid_series(s)`` of the same series (the precession-nutation coupling, then every term
  times the IERS 1996 transfer function; :mod:`ephem.earth.nonrigid`), same terms;
* ``erfa.nut00b(jd, 0.0)`` (IAU 2000B: 77 lunisolar terms and fixed planetary offsets, stated accuracy 1 mas) and
  ``erfa.nut00a(jd, 0.0)`` (IAU 2000A: 678 lunisolar + 687 planetary terms; the reference).
  ERFA takes TT; we pass TDB: TDB - TT < 2 ms, and the run prints the largest change in the pole that 2 ms can
  make (Δψ, Δε move by at most ~0.1 mas/day).

Accuracy: on an even grid (default every 0.25 d over 1900-2100, both ends in), against ``erfa.nut00a`` on the same
grid: the largest pole displacement sin ε |Δψ - Δψ_00a| + |Δε - Δε_00a| (ε = 23.4392794°, the J2000 mean
obliquity), in mas, also over 1995-2050 alone (IAU 2000B's stated span), and the rms and mean of the Δψ and Δε
differences. The mean is a diagnostic (how much of the residual is a constant offset), never added to a model.

Speed: wall time of one call on N epochs (default 10^5, evenly spaced over the window), best of ``--repeat`` warm
calls (each series' first call builds its evaluation plan, a cached property; ``timeit`` with an autorange
warm-up), as a ratio to one ``numpy.sin`` of the same N epochs measured in the same run (best of its repeats at the
start and at the end of the timing) and to ``erfa.nut00b``. Absolute times move with the machine; the ratios less.
Separately, each cut's one-off build, cold, in a fresh process: ``earth_lunisolar`` (the FFT of the orbital
functions, shared by all cuts within a process, and the coefficients), ``non_rigid_series``, and each series'
first call minus a warm one (the evaluation plan).

Run from the project root::

    .venv/bin/python benchmarks/bench_earth_nutation.py            # full: N = 10^5, grid 0.25 d (~1.8 min, 2 cores)
    .venv/bin/python benchmarks/bench_earth_nutation.py --quick    # N = 10^4, grid 2 d, no cold builds (~35 s)

Full mode writes docs/charts/earth_nutation_speed_accuracy.{png,csv}; ``--quick`` writes them under the temporary
directory instead (``--prefix`` to choose, ``--no-write`` for the table only). benchmarks/RESULTS_earth_nutation.md
keeps a full run and its reading. ``--blas-threads`` (default 1, the service's setting; 0 keeps the environment)
acts before numpy loads its BLAS (our series end in one matrix product; ERFA and numpy.sin use one thread).
"""
from __future__ import annotations

import argparse
import csv
import json
import math
import os
import subprocess
import sys
import tempfile
import time
import timeit
from pathlib import Path

from machine import BLAS_VARS, machine_info   # benchmarks/machine.py

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

WINDOW = (2415020.5, 2488069.5)          # 1900-01-01 .. 2100-01-01 TDB
SPAN_2000B = (2449718.5, 2469807.5)      # 1995-01-01 .. 2050-01-01: IAU 2000B's stated 1 mas span
EPS0_DEG = 23.4392794                    # J2000 mean obliquity (84381.406")
TDB_MINUS_TT_MAX_S = 0.002               # |TDB - TT| < 1.7 ms
DEFAULT_PREFIX = ROOT / "docs" / "charts" / "earth_nutation_speed_accuracy"
J2000_JD = 2451545.0
JULIAN_YEAR_DAYS = 365.25


def parse_args(argv=None) -> argparse.Namespace:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--quick", action="store_true",
                   help="N = 10^4 epochs, accuracy grid every 2 d, 3 repeats, no cold builds; writes under the "
                        "temporary directory unless --prefix is given")
    p.add_argument("--cuts", default="10,3,1,0.3,0.1", help="amplitude cuts (mas), comma-separated "
                   "(default %(default)s; 0.1 is the served series')")
    p.add_argument("--n", type=int, default=None, help="epochs per timed call (default 100000; --quick 10000)")
    p.add_argument("--step", type=float, default=None, help="accuracy grid step, days (default 0.25; --quick 2)")
    p.add_argument("--repeat", type=int, default=None, help="best of this many timed calls (default 5; --quick 3)")
    p.add_argument("--no-cold", action="store_true", help="skip the cold-build measurement (fresh processes)")
    p.add_argument("--blas-threads", default="1",
                   help="BLAS threads (default 1, the service's setting; 0 leaves the environment as it is)")
    p.add_argument("--prefix", type=Path, default=None,
                   help="output prefix for .png and .csv (default docs/charts/earth_nutation_speed_accuracy; "
                        "with --quick, the same name under the temporary directory)")
    p.add_argument("--no-write", action="store_true", help="print the table only")
    p.add_argument("--cold-child", type=float, default=None, help=argparse.SUPPRESS)
    args = p.parse_args(argv)
    if args.n is None:
        args.n = 10_000 if args.quick else 100_000
    if args.step is None:
        args.step = 2.0 if args.quick else 0.25
    if args.repeat is None:
        args.repeat = 3 if args.quick else 5
    if args.prefix is None:
        args.prefix = (Path(tempfile.gettempdir()) / (DEFAULT_PREFIX.name + "_quick")) if args.quick else DEFAULT_PREFIX
    if args.quick:
        args.no_cold = True
    return args


def _floats(text: str) -> list[float]:
    return [float(x) for x in text.split(",") if x.strip()]


def best_per_call(fn, repeat: int) -> float:
    """Best wall time of one call (s): ``timeit`` autorange (also the warm-up), then ``repeat`` timings."""
    timer = timeit.Timer(fn)
    number, _ = timer.autorange()
    return min(timer.repeat(repeat=repeat, number=number)) / number


# ----------------------------------------------------------------------------- models

def build_models(cuts):
    """[(key, label, cut, terms, fn(jd) -> (dpsi, deps) radians)], ours then ERFA's."""
    import erfa

    from ephem.earth.lunisolar import earth_lunisolar
    from ephem.earth.nonrigid import non_rigid_series

    models = []
    for cut in cuts:
        s = earth_lunisolar(cut_mas=cut, hd="iers2010", axis="figure")
        nr = non_rigid_series(s)
        n = len(s.multipliers)
        models.append(("rigid", "ours, rigid", cut, n, s.nutation_at))
        models.append(("nonrigid", "ours, rigid × T (IERS 1996)", cut, n, nr.nutation_at))
    models.append(("nut00b", "erfa.nut00b (IAU 2000B)", None, 77, lambda jd: erfa.nut00b(jd, 0.0)))
    models.append(("nut00a", "erfa.nut00a (IAU 2000A)", None, 678 + 687, lambda jd: erfa.nut00a(jd, 0.0)))
    return models


def cold_child(cut: float) -> None:
    """In a fresh process: the one-off build times (s) of one cut, printed as JSON."""
    import numpy as np

    t0 = time.perf_counter()
    from ephem.earth.lunisolar import earth_lunisolar
    from ephem.earth.nonrigid import non_rigid_series
    t1 = time.perf_counter()
    s = earth_lunisolar(cut_mas=cut, hd="iers2010", axis="figure")
    t2 = time.perf_counter()
    nr = non_rigid_series(s)
    t3 = time.perf_counter()
    jd = np.linspace(*WINDOW, 1000)
    out = {"cut": cut, "import_s": t1 - t0, "earth_lunisolar_s": t2 - t1, "non_rigid_series_s": t3 - t2}
    for key, series in (("rigid", s), ("nonrigid", nr)):
        a = time.perf_counter()
        series.nutation_at(jd)
        b = time.perf_counter()
        series.nutation_at(jd)
        c = time.perf_counter()
        out[f"{key}_plan_s"] = (b - a) - (c - b)
    print(json.dumps(out))


def cold_builds(cuts) -> list[dict]:
    rows = []
    for cut in cuts:
        res = subprocess.run([sys.executable, str(Path(__file__).resolve()), "--cold-child", repr(cut)],
                             capture_output=True, text=True, check=True, cwd=ROOT, env=os.environ.copy())
        rows.append(json.loads(res.stdout.strip().splitlines()[-1]))
    return rows


# ----------------------------------------------------------------------------- measurements

def accuracy(models, step: float) -> tuple[list[dict], dict]:
    import numpy as np

    from ephem.base.constants import MAS

    jd = np.arange(WINDOW[0], WINDOW[1] + 0.5 * step, step)
    ref_psi, ref_eps = models[-1][4](jd)
    sin_eps = math.sin(math.radians(EPS0_DEG))
    in_span = (jd >= SPAN_2000B[0]) & (jd <= SPAN_2000B[1])
    year = 2000.0 + (jd - J2000_JD) / JULIAN_YEAR_DAYS
    rows, residuals = [], {}
    for key, label, cut, terms, fn in models:
        dpsi, deps = fn(jd)
        rp, re = (dpsi - ref_psi) / MAS, (deps - ref_eps) / MAS
        pole = sin_eps * np.abs(rp) + np.abs(re)
        mp, me = float(rp.mean()), float(re.mean())
        pole_c = sin_eps * np.abs(rp - mp) + np.abs(re - me)
        i = int(np.argmax(pole))
        rows.append({
            "max_pole_mas": float(pole[i]), "year_of_max": float(year[i]),
            "max_pole_1995_2050_mas": float(pole[in_span].max()),
            "rms_dpsi_mas": float(np.sqrt(np.mean(rp**2))), "rms_deps_mas": float(np.sqrt(np.mean(re**2))),
            "mean_dpsi_mas": mp, "mean_deps_mas": me,
            "rms_dpsi_mean_removed_mas": float(rp.std()), "rms_deps_mean_removed_mas": float(re.std()),
            "max_pole_mean_removed_mas": float(pole_c.max()),
            "max_pole_euclid_mas": float(np.hypot(sin_eps * rp, re).max()),
            "max_pole_euclid_1995_2050_mas": float(np.hypot(sin_eps * rp, re)[in_span].max()),
            "max_abs_dpsi_mas": float(np.abs(rp).max()), "max_abs_deps_mas": float(np.abs(re).max()),
        })
        residuals[(key, cut)] = (rp, re)
    # TDB vs TT: the largest change of the pole over 2 ms, from nut00a's rate on a subgrid (central difference)
    sub = jd[:: max(1, int(round(8.0 / step)))] + 0.37          # every ~8 d, off the grid's phase
    h = 1e-3
    pp, ep = models[-1][4](sub + h)
    pm, em = models[-1][4](sub - h)
    rate = (sin_eps * np.abs(pp - pm) + np.abs(ep - em)) / (2 * h) / MAS          # mas/day
    extra = {"jd": jd, "year": year, "residuals": residuals, "max_pole_rate_mas_per_day": float(rate.max()),
             "tdb_tt_pole_bound_mas": float(rate.max()) * TDB_MINUS_TT_MAX_S / 86400.0, "epochs": jd.size}
    return rows, extra


def speed(models, n: int, repeat: int) -> tuple[list[float], dict]:
    import numpy as np

    jd = np.linspace(*WINDOW, n)
    sin_before = best_per_call(lambda: np.sin(jd), max(repeat, 7))
    times = []
    for key, label, cut, terms, fn in models:
        fn(jd)                                   # the first call builds the series' evaluation plan (cached)
        times.append(best_per_call(lambda: fn(jd), repeat))
        print(f"  timed {label}{'' if cut is None else f', cut {cut:g} mas'}: {times[-1] * 1e3:.2f} ms", flush=True)
    sin_after = best_per_call(lambda: np.sin(jd), max(repeat, 7))
    return times, {"sin_s": min(sin_before, sin_after), "sin_before_s": sin_before, "sin_after_s": sin_after}


def spectral_lines(r, step: float, count: int = 6) -> list[tuple[float, float]]:
    """The ``count`` largest lines of a residual (mean removed, Hann window): (period in days, amplitude mas)."""
    import numpy as np

    x = r - r.mean()
    w = np.hanning(x.size)
    size = 8 * x.size                                   # zero-padded: the peaks' periods to 1/8 of a bin
    spec = np.abs(np.fft.rfft(x * w, size)) * 2.0 / w.sum()
    f = np.fft.rfftfreq(size, step)
    peaks = [i for i in range(1, spec.size - 1) if spec[i] >= spec[i - 1] and spec[i] >= spec[i + 1]]
    peaks.sort(key=lambda i: -spec[i])
    return [(1.0 / f[i], float(spec[i])) for i in peaks[:count]]


def residual_make_up(rp, re, jd, step: float) -> list[str]:
    """Diagnostics of a residual (ours - nut00a, mas): its constant part against what IAU 2000A holds beyond our
    series' reach (the 10,468-yr term, left to the precession, and the planetary nutation's mean, IAU 2000B's fixed
    offsets: published numbers from data/nonrigid.toml, nothing fitted to the model), a linear trend, and the
    largest lines of what is left. Nothing here is added to any model."""
    import numpy as np

    from ephem.earth.nonrigid import nonrigid_data
    from ephem.orbit.lunar import delaunay_arguments

    sin_eps = math.sin(math.radians(EPS0_DEG))
    beyond = nonrigid_data()["beyond_lunisolar"]
    term, offset = beyond["iau2000a_long_period_term"], beyond["iau2000b_planetary_offset_mas"]
    ph = delaunay_arguments(jd) @ np.array(term["delaunay_multipliers"], float)
    lp_psi, lp_eps = term["psi_sin_mas"] * np.sin(ph), term["eps_cos_mas"] * np.cos(ph)
    out = [f"constant part: mean δΔψ {rp.mean():+.2f}, δΔε {re.mean():+.2f} mas; expected from what IAU 2000A "
           f"holds "
           f"and our series leaves out: -(10,468-yr term, mean over the window {lp_psi.mean():+.2f} / "
           f"{lp_eps.mean():+.2f}) - (planetary mean, nut00b's offsets {offset['psi']:+.3f} / {offset['eps']:+.3f}) "
           f"= {-lp_psi.mean() - offset['psi']:+.2f} / {-lp_eps.mean() - offset['eps']:+.2f} mas"]
    t = (jd - J2000_JD) / 36525.0
    pole_raw = sin_eps * np.abs(rp) + np.abs(re)
    cp, ce = rp - rp.mean(), re - re.mean()
    fits = {}
    for name, r in (("psi", rp), ("eps", re)):
        coef = np.polyfit(t, r, 1)
        fits[name] = (coef, r - np.polyval(coef, t))
    pole_c = sin_eps * np.abs(cp) + np.abs(ce)
    pole_l = sin_eps * np.abs(fits["psi"][1]) + np.abs(fits["eps"][1])
    pole_lp = sin_eps * np.abs(rp + lp_psi + offset["psi"]) + np.abs(re + lp_eps + offset["eps"])
    out.append(f"max pole error {pole_raw.max():.2f} mas; means removed {pole_c.max():.2f} (rms δΔψ {cp.std():.2f}, "
               f"δΔε {ce.std():.2f}); constant + linear trend removed {pole_l.max():.2f} (trend "
               f"{fits['psi'][0][0]:+.2f} / {fits['eps'][0][0]:+.2f} mas per century); with the 10,468-yr term and "
               f"nut00b's offsets put back instead of fitted means {pole_lp.max():.2f} mas")
    for name, (coef, r) in (("δΔψ", fits["psi"]), ("δΔε", fits["eps"])):
        lines = ", ".join(f"{p / JULIAN_YEAR_DAYS:.3g} yr: {a:.2f}" for p, a in spectral_lines(r, step))
        out.append(f"largest lines of {name}, constant and trend removed (Hann window, amplitude mas): {lines}")
    return out


# ----------------------------------------------------------------------------- outputs

def model_name(row) -> str:
    if row["model"] == "rigid":
        return f"ours rigid, cut {row['cut_mas']:g} mas"
    if row["model"] == "nonrigid":
        return f"ours rigid×T, cut {row['cut_mas']:g} mas"
    return {"nut00b": "erfa.nut00b (IAU 2000B)", "nut00a": "erfa.nut00a (IAU 2000A, reference)"}[row["model"]]


def write_csv(path: Path, rows, meta) -> None:
    keys = ["model", "cut_mas", "terms", "max_pole_mas", "year_of_max", "max_pole_1995_2050_mas", "rms_dpsi_mas",
            "rms_deps_mas", "mean_dpsi_mas", "mean_deps_mas", "rms_dpsi_mean_removed_mas",
            "rms_deps_mean_removed_mas", "max_pole_mean_removed_mas", "max_pole_euclid_mas",
            "max_pole_euclid_1995_2050_mas", "max_abs_dpsi_mas", "max_abs_deps_mas", "time_per_call_s",
            "time_ratio_to_sin",
            "time_ratio_to_nut00b"]
    with open(path, "w", newline="") as fh:
        fh.write(f"# {meta}\n")
        w = csv.writer(fh)
        w.writerow(keys)
        for r in rows:
            cells = [f"{r[k]:.6g}" for k in keys[3:]]
            if r["model"] == "nut00a":
                cells[1] = ""                       # the reference: no year of a largest error
            w.writerow([r["model"], "" if r["cut_mas"] is None else f"{r['cut_mas']:g}", r["terms"]] + cells)


def write_png(path: Path, rows, n: int, step: float) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(9.5, 6.5))
    style = {"rigid": ("o", "tab:blue", "ours, rigid (first order)"),
             "nonrigid": ("s", "tab:orange", "ours, rigid + coupling, × IERS 1996 T(σ)"),
             "nut00b": ("*", "black", "erfa.nut00b (IAU 2000B)")}
    for key, (marker, colour, label) in style.items():
        pts = [r for r in rows if r["model"] == key]
        xs = [r["time_ratio_to_sin"] for r in pts]
        ys = [r["max_pole_mas"] for r in pts]
        ax.plot(xs, ys, marker=marker, ls="-" if key != "nut00b" else "none", lw=0.8, color=colour,
                ms=11 if key == "nut00b" else 7, label=label)
        if key == "rigid" and pts:      # close together: vertical labels spread above, with leader lines
            order = sorted(pts, key=lambda r: r["time_ratio_to_sin"])
            lo, hi = order[0]["time_ratio_to_sin"] / 1.6, order[-1]["time_ratio_to_sin"] * 1.6
            spots = [lo * (hi / lo) ** (i / max(1, len(order) - 1)) for i in range(len(order))]
            for r, x in zip(order, spots):
                ax.annotate(f"rigid, cut {r['cut_mas']:g} mas ({r['terms']} terms)",
                            (r["time_ratio_to_sin"], r["max_pole_mas"]), xytext=(x, 160.0), rotation=90,
                            ha="center", va="bottom", fontsize=7, color=colour,
                            arrowprops={"arrowstyle": "-", "color": colour, "lw": 0.5, "shrinkA": 0, "shrinkB": 4})
            continue
        for r in pts:
            xy = (r["time_ratio_to_sin"], r["max_pole_mas"])
            if key == "nonrigid":       # to the left: the next cut's point is to the right
                ax.annotate(f"rigid×T, cut {r['cut_mas']:g} mas ({r['terms']} terms)", xy, textcoords="offset points",
                            xytext=(-8, 0), ha="right", va="center", fontsize=7.5, color=colour)
            else:
                ax.annotate(f"IAU 2000B (erfa.nut00b, 77 terms)\n{r['max_pole_mas']:.2f} mas", xy,
                            textcoords="offset points", xytext=(8, 2), fontsize=7.5, color=colour)
    ref = next(r for r in rows if r["model"] == "nut00a")
    ax.axvline(ref["time_ratio_to_sin"], color="tab:green", lw=1.5)
    ax.text(ref["time_ratio_to_sin"], 0.97, "IAU 2000A (reference)\nerfa.nut00a, error 0 by definition",
            transform=ax.get_xaxis_transform(), rotation=90, ha="right", va="top", fontsize=8, color="tab:green")
    ax.axhline(1.0, color="grey", ls="--", lw=1)
    ax.text(0.01, 1.0, "nut00b's stated accuracy (1 mas)", transform=ax.get_yaxis_transform(), ha="left",
            va="top", fontsize=8, color="grey")
    ax.set_xscale("log")
    ax.set_yscale("log")
    xs = [r["time_ratio_to_sin"] for r in rows]
    ax.set_xlim(min(xs) / 5.0, max(xs) * 2.0)
    ax.set_ylim(0.5, 2e3)
    ax.set_xlabel(f"wall time per call on {n:,} epochs / one numpy.sin on the same epochs (ratio, same run)")
    ax.set_ylabel("max pole error vs IAU 2000A, 1900–2100: sin ε₀|δΔψ| + |δΔε| (mas)")
    ax.set_title("Earth nutation (Δψ, Δε): speed against accuracy\n"
                 f"error on a {step:g}-day grid over 1900–2100 against erfa.nut00a; time: best of warm calls",
                 fontsize=10)
    ax.grid(which="both", alpha=0.25)
    ax.legend(loc="center right", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv=None) -> int:
    args = parse_args(argv)
    if args.blas_threads.strip() != "0":
        for var in BLAS_VARS:
            os.environ[var] = args.blas_threads.strip()
    if args.cold_child is not None:
        cold_child(args.cold_child)
        return 0
    t_start = time.perf_counter()
    import erfa

    info = machine_info(pyerfa=erfa.__version__)   # imports numpy after the BLAS variables are set
    for line in info:
        print(line)
    cuts = _floats(args.cuts)

    cold = [] if args.no_cold else cold_builds(cuts)
    models = build_models(cuts)
    print(f"accuracy: every {args.step:g} d over 1900-2100 against erfa.nut00a ...", flush=True)
    acc, extra = accuracy(models, args.step)
    print(f"speed: {args.n:,} epochs, best of {args.repeat} ...", flush=True)
    times, unit = speed(models, args.n, args.repeat)
    t_00b = times[[m[0] for m in models].index("nut00b")]

    rows = []
    for (key, label, cut, terms, fn), a, t in zip(models, acc, times):
        rows.append({"model": key, "cut_mas": cut, "terms": terms, **a, "time_per_call_s": t,
                     "time_ratio_to_sin": t / unit["sin_s"], "time_ratio_to_nut00b": t / t_00b})

    table = ["| model | cut (mas) | terms | max pole err (mas) | (year) | max 1995-2050 | rms δΔψ (mas) "
             "| rms δΔε (mas) | mean δΔψ, δΔε (mas) | max pole err, means removed | time / numpy.sin "
             "| time / nut00b |",
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        cut = "-" if r["cut_mas"] is None else f"{r['cut_mas']:g}"
        name = {"rigid": "ours, rigid", "nonrigid": "ours, rigid × T",
                "nut00b": "erfa.nut00b (IAU 2000B)", "nut00a": "erfa.nut00a (IAU 2000A)"}[r["model"]]
        if r["model"] == "nut00a":
            acc_cells = "0 (reference) | - | 0 | 0 | 0 | 0, 0 | 0"
        else:
            acc_cells = (f"{r['max_pole_mas']:.3g} | {r['year_of_max']:.0f} | {r['max_pole_1995_2050_mas']:.3g} "
                         f"| {r['rms_dpsi_mas']:.3g} | {r['rms_deps_mas']:.3g} "
                         f"| {r['mean_dpsi_mas']:+.2f}, {r['mean_deps_mas']:+.2f} "
                         f"| {r['max_pole_mean_removed_mas']:.3g}")
        table.append(f"| {name} | {cut} | {r['terms']} | {acc_cells} | {r['time_ratio_to_sin']:.3g} "
                     f"| {r['time_ratio_to_nut00b']:.3g} |")
    print()
    print("\n".join(table))
    print()
    print(f"numpy.sin on {args.n:,} epochs: {unit['sin_s'] * 1e3:.3f} ms (best; at the start "
          f"{unit['sin_before_s'] * 1e3:.3f} ms, at the end {unit['sin_after_s'] * 1e3:.3f} ms); "
          f"erfa.nut00b {t_00b * 1e3:.2f} ms; accuracy grid {extra['epochs']:,} epochs")
    print(f"TDB for TT: IAU 2000A's pole moves by at most {extra['max_pole_rate_mas_per_day']:.1f} mas/day, so 2 ms "
          f"of TDB - TT move it by at most {extra['tdb_tt_pole_bound_mas']:.1e} mas")

    b = rows[[m[0] for m in models].index("nut00b")]
    print(f"IAU 2000B's 1 mas against this metric: nut00b's largest sin ε|δΔψ| + |δΔε| is "
          f"{b['max_pole_mas']:.2f} mas (1995-2050: {b['max_pole_1995_2050_mas']:.2f}); as a Euclidean pole offset "
          f"sqrt((sin ε δΔψ)² + δΔε²) "
          f"{b['max_pole_euclid_mas']:.2f} (1995-2050: {b['max_pole_euclid_1995_2050_mas']:.2f}); largest |δΔψ| "
          f"{b['max_abs_dpsi_mas']:.2f}, |δΔε| {b['max_abs_deps_mas']:.2f} mas")

    # what the best of ours leaves: spectral lines of its residual (mean removed); diagnostic only
    ours = [r for r in rows if r["model"] in ("rigid", "nonrigid")]
    best = min(ours, key=lambda r: r["max_pole_mas"])
    rp, re = extra["residuals"][(best["model"], best["cut_mas"])]
    print(f"\nbest of ours: {model_name(best)}: max pole error {best['max_pole_mas']:.2f} mas "
          f"({best['year_of_max']:.0f}; Euclidean {best['max_pole_euclid_mas']:.2f}, 1995-2050 "
          f"{best['max_pole_euclid_1995_2050_mas']:.2f}); mean δΔψ {best['mean_dpsi_mas']:+.2f}, "
          f"mean δΔε {best['mean_deps_mas']:+.2f} mas; "
          f"with the means removed (diagnostic, not a model) {best['max_pole_mean_removed_mas']:.2f} mas max, "
          f"rms {best['rms_dpsi_mean_removed_mas']:.2f} / {best['rms_deps_mean_removed_mas']:.2f} mas")
    for line in residual_make_up(rp, re, extra["jd"], args.step):
        print("  " + line)
    if cold:
        print("\ncold builds, fresh process per cut (s): cut, import, earth_lunisolar, non_rigid_series, "
              "first-call plan rigid, plan rigid×T")
        for c in cold:
            print(f"  {c['cut']:g}: {c['import_s']:.2f}, {c['earth_lunisolar_s']:.2f}, {c['non_rigid_series_s']:.3f}, "
                  f"{c['rigid_plan_s']:.4f}, {c['nonrigid_plan_s']:.4f}")

    if not args.no_write:
        args.prefix.parent.mkdir(parents=True, exist_ok=True)
        meta = (f"benchmarks/bench_earth_nutation.py{' --quick' if args.quick else ''}: N = {args.n} epochs timed, "
                f"best of {args.repeat}; accuracy every {args.step:g} d over 1900-2100 vs erfa.nut00a; "
                f"numpy.sin {unit['sin_s']:.4g} s; {info[0]}; {info[3]}")
        write_csv(args.prefix.with_suffix(".csv"), rows, meta)
        write_png(args.prefix.with_suffix(".png"), rows, args.n, args.step)
        print(f"\nwritten: {args.prefix.with_suffix('.csv')}, {args.prefix.with_suffix('.png')}")
    print(f"total run time {time.perf_counter() - t_start:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
