"""The Earth's nutation minus IAU 2000A over 1900-2100: the rigid series and the same series times the IERS 1996
transfer function. The chart of docs/earth.md (docs/charts/earth_nutation_residual.png, .svg, .csv).

A study, not the library (see :mod:`studies`): run from the project root as
``python -m studies.earth_nutation_residual [PREFIX]`` (default ``earth_nutation_residual``; the committed chart:
``docs/charts/earth_nutation_residual``). It prints the rms and max (mas) it drew. The library's side is
:mod:`ephem.earth.lunisolar` (the series, :func:`ephem.earth.lunisolar.residual_vs_iau2000a`) and :mod:`ephem.earth.nonrigid`
(:func:`ephem.earth.nonrigid.non_rigid_series`).
"""
from __future__ import annotations

import sys

import numpy as np

from ephem.base.constants import J2000_JD, JULIAN_YEAR_DAYS, MAS
from ephem.earth.lunisolar import earth_lunisolar, residual_vs_iau2000a
from ephem.earth.nonrigid import non_rigid_series

#: The chart's file prefix when none is given.
DEFAULT_PREFIX = "earth_nutation_residual"


def write_residual_chart(prefix: str, step_days: float = 2.0) -> dict:
    """The residual against IAU 2000A over 1900-2100 of the rigid series (IERS H_d, figure axis,
    0.1 mas cut) and of the same series times the IERS 1996 transfer function
    (:func:`ephem.earth.nonrigid.non_rigid_series`): ``prefix``.csv, .png and .svg. Returns the rms and
    max (mas) it drew."""
    import csv

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    series = earth_lunisolar(hd="iers2010")
    jd = np.arange(2415020.5, 2488069.5 + 0.5 * step_days, step_days)   # 1900-01-01 .. 2100-01-01
    rp, re = (x / MAS for x in residual_vs_iau2000a(series, jd))
    np_, ne = (x / MAS for x in residual_vs_iau2000a(non_rigid_series(series), jd))
    stats = {}
    for key, y in (("psi", rp), ("eps", re), ("psi_nonrigid", np_), ("eps_nonrigid", ne)):
        stats[key + "_rms_mas"] = float(np.sqrt(np.mean(y**2)))
        stats[key + "_max_mas"] = float(np.abs(y).max())
    with open(prefix + ".csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["jd_tdb", "year", "dpsi_minus_iau2000a_mas", "deps_minus_iau2000a_mas",
                    "dpsi_times_iers1996_T_minus_iau2000a_mas", "deps_times_iers1996_T_minus_iau2000a_mas"])
        for j in range(0, jd.size, 5):
            w.writerow([f"{jd[j]:.1f}", f"{2000.0 + (jd[j] - J2000_JD) / JULIAN_YEAR_DAYS:.4f}",
                        f"{rp[j]:.4f}", f"{re[j]:.4f}", f"{np_[j]:.4f}", f"{ne[j]:.4f}"])
    year = 2000.0 + (jd - J2000_JD) / JULIAN_YEAR_DAYS
    fig, axes = plt.subplots(2, 2, figsize=(13, 6), sharex=True)
    panels = ((axes[0, 0], rp, "Δψ", "psi", "rigid", "tab:blue"),
              (axes[1, 0], re, "Δε", "eps", "rigid", "tab:blue"),
              (axes[0, 1], np_, "Δψ", "psi_nonrigid", "rigid × T", "tab:orange"),
              (axes[1, 1], ne, "Δε", "eps_nonrigid", "rigid × T", "tab:orange"))
    for ax, y, label, key, what, colour in panels:
        ax.plot(year, y, lw=0.4, color=colour)
        ax.set_ylabel(f"{label} {what} − IAU 2000A (mas)")
        ax.set_title(f"{label}, {what}: rms {stats[key + '_rms_mas']:.1f} mas, max {stats[key + '_max_mas']:.1f} mas",
                     fontsize=9)
        ax.grid(alpha=0.3)
    for ax in axes[1]:
        ax.set_xlabel("year (TDB)")
    fig.suptitle("Left: first-order rigid-Earth lunisolar nutation (H_d = 0.0032737949, figure axis, 0.1 mas cut) "
                 "minus erfa.nut00a (IAU 2000A).\nRight: the same, plus the precession-nutation coupling, times the "
                 "IERS 1996 transfer function T (elastic mantle, fluid core; ephem.earth.nonrigid)", fontsize=10)
    fig.tight_layout()
    fig.savefig(prefix + ".png", dpi=110)
    fig.savefig(prefix + ".svg")
    plt.close(fig)
    return stats


def main(argv: list[str] | None = None) -> None:
    """``python -m studies.earth_nutation_residual [PREFIX]``: write the chart, print its rms and max (mas)."""
    args = sys.argv[1:] if argv is None else argv
    print(write_residual_chart(args[0] if args else DEFAULT_PREFIX))


if __name__ == "__main__":  # python -m studies.earth_nutation_residual docs/charts/earth_nutation_residual
    main()
