"""Mars' liquid core on the Sun ladder: the ``nonrigid`` rung against the rigid ``second_order`` one, both against the
IAU WGCCRE 2015 pole, and what the core costs. The chart docs/charts/mars_nonrigid.png and its numbers,
docs/charts/mars_nonrigid.csv.

A study, not the library (see :mod:`studies`): run from the project root as
``python -m studies.mars_core_chart [--prefix PREFIX] [--years Y] [--step D] [--n N] [--repeat R]`` (default: the
committed chart, 2000-2040 every 2 days, 10^4 timed epochs, best of 7). Both tracks come from
``Ladder(get_body("mars"), axis="angular_momentum").track(rung, jd)`` (:mod:`ephem.sun.ladder`; the core:
:mod:`ephem.forced.interior_response`, F and P_FCN of data/interiors.toml).

Panels:

1. the angle (mas) between the ``nonrigid`` pole and the rigid ``second_order`` pole, with the ladder's estimate
   terms (``Ladder.estimates`` over the same epochs, without the rotation-scale terms): ``interior_rigid`` (what
   the rigid rungs say they leave out for the core) and ``interior_parameters`` (the ``nonrigid`` rung's 2σ of F
   and P_FCN);
2. each pole's angle from the WGCCRE 2015 Mars pole (Archinal et al. 2018, as in NAIF's pck00011.tpc; evaluated by
   :func:`ephem.exports.pck_fit.iau_orientation`, the library's copy used to place W0), *after* a quadratic in
   time is fitted to and removed from each pole's east and north offsets from WGCCRE's (separately for each
   pole). The catalogue pole is WGCCRE's J2000 value rounded to 1e-5° (9 mas) and the two precession rates
   differ: a trend of tens of mas over 40 years that is not what this panel is about. What is left is the
   periodic part, where WGCCRE's annual to quater-annual terms carry the core (tests/forced/
   test_against_mars_nutation_models.py) and the rigid pole misses the semi-annual term by ~19 mas;
3. the cost: the wall time of one ``Ladder.track`` call on N epochs (default 10^4, evenly over the window), best of
   ``--repeat`` warm calls (``timeit`` autorange), as a ratio to one ``numpy.sin`` of the same N-epoch array measured
   in the same run (best of its repeats at the start and at the end of the timing). Absolute times move with the
   machine; the ratio less.

The CSV has one row per epoch: ``jd_tdb``, ``year``, the plotted series (mas) and, repeated on every row, the
constants drawn (the two estimate terms, mas, and the two cost ratios). It prints a short summary and
:func:`write_chart` returns it.
"""
from __future__ import annotations

import argparse
import csv
import math
import os
import sys
import timeit
from pathlib import Path

# one BLAS thread, the service's setting, before numpy loads its BLAS (an explicit setting in the environment wins)
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import numpy as np  # noqa: E402

from ephem.base.constants import J2000_JD, JULIAN_YEAR_DAYS, MAS  # noqa: E402
from ephem.bodies.catalogue import get_body  # noqa: E402
from ephem.exports.pck_fit import iau_orientation  # noqa: E402
from ephem.sun.ladder import Ladder  # noqa: E402
from ephem.theory.tracks import pole_vectors  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
#: The committed chart's prefix (.png and .csv).
DEFAULT_PREFIX = ROOT / "docs" / "charts" / "mars_nonrigid"
MARS_NAIF_ID = 499
RUNGS = ("second_order", "nonrigid")


def wgccre_vectors(jd_tdb: np.ndarray) -> np.ndarray:
    """ICRF unit vectors (N, 3) of the WGCCRE 2015 Mars pole (:func:`ephem.exports.pck_fit.iau_orientation`)."""
    ra, dec = np.radians(np.array([iau_orientation(MARS_NAIF_ID, float(t))[:2] for t in jd_tdb])).T
    return np.stack([np.cos(dec) * np.cos(ra), np.cos(dec) * np.sin(ra), np.sin(dec)], axis=-1)


def angle_mas(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The angle (mas) between rows of unit vectors (atan2 of |a × b| and a · b: exact at small angles)."""
    return np.arctan2(np.linalg.norm(np.cross(a, b), axis=-1), np.sum(a * b, axis=-1)) / MAS


def east_north_mas(v: np.ndarray, ref: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The offsets (mas) of the unit vectors ``v`` from ``ref``, along ``ref``'s local east and north."""
    ra = np.arctan2(ref[:, 1], ref[:, 0])
    dec = np.arctan2(ref[:, 2], np.hypot(ref[:, 0], ref[:, 1]))
    east = np.stack([-np.sin(ra), np.cos(ra), np.zeros_like(ra)], axis=-1)
    north = np.stack([-np.sin(dec) * np.cos(ra), -np.sin(dec) * np.sin(ra), np.cos(dec)], axis=-1)
    return np.sum(v * east, axis=-1) / MAS, np.sum(v * north, axis=-1) / MAS


def detrended(jd: np.ndarray, y: np.ndarray) -> np.ndarray:
    """``y`` less its least-squares quadratic in time."""
    x = (jd - jd.mean()) / max(float(np.ptp(jd)), 1.0)
    return y - np.polyval(np.polyfit(x, y, 2), x)


def best_per_call(fn, repeat: int) -> float:
    """Best wall time of one call (s): ``timeit`` autorange (also the warm-up), then ``repeat`` timings."""
    timer = timeit.Timer(fn)
    number, _ = timer.autorange()
    return min(timer.repeat(repeat=repeat, number=number)) / number


def measure_cost(ladder: Ladder, start: float, stop: float, n: int, repeat: int) -> dict:
    """Seconds per call of ``numpy.sin`` and of each rung's track on ``n`` epochs, and the rungs' ratios to it."""
    x = np.linspace(start, stop, n)
    sin_before = best_per_call(lambda: np.sin(x), repeat)
    track = {rung: best_per_call(lambda rung=rung: ladder.track(rung, x), repeat) for rung in RUNGS}
    sin_s = min(sin_before, best_per_call(lambda: np.sin(x), repeat))
    out = {"n": n, "repeat": repeat, "sin_s": sin_s}
    for rung in RUNGS:
        out[f"{rung}_s"] = track[rung]
        out[f"{rung}_ratio"] = track[rung] / sin_s
    return out


def write_chart(prefix: str | Path = DEFAULT_PREFIX, years: float = 40.0, step_days: float = 2.0,
                n_timed: int = 10_000, repeat: int = 7, start_jd: float = J2000_JD) -> dict:
    """Write ``prefix``.png and ``prefix``.csv over ``years`` from ``start_jd`` every ``step_days``; return the
    summary (mas, and the cost ratios)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    prefix = Path(prefix)
    ladder = Ladder(get_body("mars"), axis="angular_momentum")
    stop_jd = start_jd + years * JULIAN_YEAR_DAYS
    jd = np.arange(start_jd, stop_jd + 0.5 * step_days, step_days)
    year = 2000.0 + (jd - J2000_JD) / JULIAN_YEAR_DAYS

    tracks = {rung: ladder.track(rung, jd) for rung in RUNGS}
    vec = {rung: pole_vectors(tr) for rung, tr in tracks.items()}
    core_mas = angle_mas(vec["nonrigid"], vec["second_order"])

    est = {e.rung: e for e in ladder.estimates(jd) if e.rotation_scale is None and e.order is None}
    interior_rigid_mas = est["second_order"].terms["interior_rigid"] / MAS
    interior_parameters_mas = est["nonrigid"].terms["interior_parameters"] / MAS

    ref = wgccre_vectors(jd)
    raw_vs_wgccre, vs_wgccre, en = {}, {}, {}
    for rung in RUNGS:
        raw_vs_wgccre[rung] = angle_mas(vec[rung], ref)
        e, n = (detrended(jd, y) for y in east_north_mas(vec[rung], ref))
        en[rung] = (e, n)
        vs_wgccre[rung] = np.hypot(e, n)

    cost = measure_cost(ladder, float(jd[0]), float(jd[-1]), n_timed, repeat)

    summary = {
        "span": f"{year[0]:.2f}-{year[-1]:.2f} every {step_days:g} d ({jd.size} epochs)",
        "nonrigid_vs_rigid_max_mas": float(core_mas.max()),
        "interior_rigid_estimate_mas": float(interior_rigid_mas),
        "interior_parameters_estimate_mas": float(interior_parameters_mas),
    }
    for rung in RUNGS:
        summary[f"{rung}_vs_wgccre_raw_max_mas"] = float(raw_vs_wgccre[rung].max())
        summary[f"{rung}_vs_wgccre_detrended_max_mas"] = float(vs_wgccre[rung].max())
        summary[f"{rung}_vs_wgccre_detrended_rms_mas"] = float(np.sqrt(np.mean(vs_wgccre[rung] ** 2)))
    summary.update({"cost_epochs": n_timed, "numpy_sin_ns_per_epoch": cost["sin_s"] / n_timed * 1e9,
                    "second_order_ratio_to_sin": cost["second_order_ratio"],
                    "nonrigid_ratio_to_sin": cost["nonrigid_ratio"]})

    # ---- CSV
    prefix.parent.mkdir(parents=True, exist_ok=True)
    with open(prefix.with_suffix(".csv"), "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["jd_tdb", "year", "nonrigid_vs_rigid_mas",
                    "rigid_vs_wgccre_detrended_mas", "nonrigid_vs_wgccre_detrended_mas",
                    "rigid_minus_wgccre_east_detrended_mas", "rigid_minus_wgccre_north_detrended_mas",
                    "nonrigid_minus_wgccre_east_detrended_mas", "nonrigid_minus_wgccre_north_detrended_mas",
                    "rigid_vs_wgccre_raw_mas", "nonrigid_vs_wgccre_raw_mas",
                    "interior_rigid_estimate_mas", "interior_parameters_estimate_mas",
                    "second_order_time_over_numpy_sin", "nonrigid_time_over_numpy_sin"])
        for j in range(jd.size):
            w.writerow([f"{jd[j]:.1f}", f"{year[j]:.4f}", f"{core_mas[j]:.4f}",
                        f"{vs_wgccre['second_order'][j]:.4f}", f"{vs_wgccre['nonrigid'][j]:.4f}",
                        f"{en['second_order'][0][j]:.4f}", f"{en['second_order'][1][j]:.4f}",
                        f"{en['nonrigid'][0][j]:.4f}", f"{en['nonrigid'][1][j]:.4f}",
                        f"{raw_vs_wgccre['second_order'][j]:.4f}", f"{raw_vs_wgccre['nonrigid'][j]:.4f}",
                        f"{interior_rigid_mas:.4f}", f"{interior_parameters_mas:.4f}",
                        f"{cost['second_order_ratio']:.2f}", f"{cost['nonrigid_ratio']:.2f}"])

    # ---- chart
    fig, axes = plt.subplots(3, 1, figsize=(12, 10.5), gridspec_kw={"height_ratios": [1.0, 1.0, 0.55]})
    ax = axes[0]
    ax.plot(year, core_mas, lw=0.8, color="tab:orange", label="nonrigid vs second_order (rigid)")
    ax.axhline(interior_rigid_mas, color="tab:blue", ls="--", lw=1.0,
               label=f"rigid rungs' estimate term interior_rigid: {interior_rigid_mas:.1f} mas")
    ax.axhline(interior_parameters_mas, color="tab:red", ls=":", lw=1.2,
               label=f"nonrigid's estimate term interior_parameters (2σ of F, P_FCN): {interior_parameters_mas:.1f} mas")
    ax.set_ylabel("angle between the poles (mas)")
    ax.set_ylim(0, 1.1 * max(interior_rigid_mas, float(core_mas.max())))
    ax.set_title(f"What Mars' liquid core moves (F = 0.0615, P_FCN = −243 d): the nonrigid pole against the rigid "
                 f"second-order pole, max {core_mas.max():.1f} mas\n(zero at J2000, the pole epoch, and once a "
                 f"Mars year after: the core's change is counted from the catalogue pole)", fontsize=10)
    ax.legend(fontsize=8, loc="upper right", framealpha=0.9)
    ax.grid(alpha=0.3)

    ax = axes[1]
    for rung, colour, label in (("second_order", "tab:blue", "second_order (rigid)"),
                                ("nonrigid", "tab:orange", "nonrigid (with the core)")):
        ax.plot(year, vs_wgccre[rung], lw=0.8, color=colour,
                label=f"{label}: rms {summary[f'{rung}_vs_wgccre_detrended_rms_mas']:.1f}, "
                      f"max {summary[f'{rung}_vs_wgccre_detrended_max_mas']:.1f} mas")
    ax.set_ylabel("angle from WGCCRE 2015,\nquadratic trend removed (mas)")
    ax.set_title("Against the IAU WGCCRE 2015 Mars pole (pck00011), periodic part only: a quadratic in east and north "
                 "offsets removed from each pole,\nsince the catalogue pole's 1e-5° rounding (9 mas) and the "
                 "precession-rate difference are not the point (before removal: max "
                 f"{summary['second_order_vs_wgccre_raw_max_mas']:.0f} and "
                 f"{summary['nonrigid_vs_wgccre_raw_max_mas']:.0f} mas)", fontsize=10)
    ax.legend(fontsize=8, loc="upper right", framealpha=0.9)
    ax.grid(alpha=0.3)
    for a in axes[:2]:
        a.set_xlim(year[0], year[-1])
    axes[1].set_xlabel("year (TDB)")

    ax = axes[2]
    labels = ["numpy.sin", "second_order", "nonrigid"]
    ratios = [1.0, cost["second_order_ratio"], cost["nonrigid_ratio"]]
    bars = ax.barh(labels, ratios, color=["0.6", "tab:blue", "tab:orange"])
    for bar, r, s in zip(bars, ratios, (cost["sin_s"], cost["second_order_s"], cost["nonrigid_s"])):
        ax.text(bar.get_width(), bar.get_y() + bar.get_height() / 2,
                f"  {r:.1f} × numpy.sin  ({s / n_timed * 1e9:.1f} ns/epoch)", va="center", fontsize=9)
    ax.set_xlim(0, 1.45 * max(ratios))
    ax.invert_yaxis()
    ax.set_xlabel("time per epoch / numpy.sin's per epoch")
    ax.set_title(f"Cost: one Ladder.track call on {n_timed} epochs, best of {repeat} warm calls, over one numpy.sin of "
                 f"the same array in the same run; the core adds "
                 f"{100 * (cost['nonrigid_ratio'] / cost['second_order_ratio'] - 1):+.0f}%", fontsize=10)
    ax.grid(alpha=0.3, axis="x")
    fig.tight_layout()
    fig.savefig(prefix.with_suffix(".png"), dpi=110)
    plt.close(fig)
    return summary


def main(argv: list[str] | None = None) -> dict:
    """``python -m studies.mars_core_chart``: write the chart and its CSV, print the summary."""
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--prefix", type=Path, default=DEFAULT_PREFIX,
                   help="output prefix for .png and .csv (default docs/charts/mars_nonrigid)")
    p.add_argument("--years", type=float, default=40.0, help="span from J2000, years (default %(default)s)")
    p.add_argument("--step", type=float, default=2.0, help="grid step, days (default %(default)s)")
    p.add_argument("--n", type=int, default=10_000, help="epochs per timed call (default %(default)s)")
    p.add_argument("--repeat", type=int, default=7, help="best of this many timed calls (default %(default)s)")
    args = p.parse_args(sys.argv[1:] if argv is None else argv)
    s = write_chart(args.prefix, args.years, args.step, args.n, args.repeat)
    print(f"Mars, {s['span']}; wrote {args.prefix}.png and .csv")
    print(f"  nonrigid vs second_order: max {s['nonrigid_vs_rigid_max_mas']:.2f} mas "
          f"(estimate terms: interior_rigid {s['interior_rigid_estimate_mas']:.2f}, "
          f"interior_parameters {s['interior_parameters_estimate_mas']:.2f} mas)")
    for rung in RUNGS:
        print(f"  {rung:12s} vs WGCCRE 2015: raw max {s[f'{rung}_vs_wgccre_raw_max_mas']:.2f} mas; quadratic removed: "
              f"max {s[f'{rung}_vs_wgccre_detrended_max_mas']:.2f}, rms {s[f'{rung}_vs_wgccre_detrended_rms_mas']:.2f} mas")
    print(f"  cost at {s['cost_epochs']} epochs (numpy.sin {s['numpy_sin_ns_per_epoch']:.2f} ns/epoch): "
          f"second_order {s['second_order_ratio_to_sin']:.1f} x, nonrigid {s['nonrigid_ratio_to_sin']:.1f} x numpy.sin")
    return s


if __name__ == "__main__":  # python -m studies.mars_core_chart
    main()
