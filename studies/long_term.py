"""The spin axis over millions of years against the outside references (docs/long_term.md).

A study, not the library (see :mod:`studies`): run from the project root as
``python -m studies.long_term [--out DIR] [--quick]``. For each catalogue body (:data:`BODIES`) it asks
:func:`ephem.api.history` for the averaged spin axis over -3 Myr..+1 Myr at 1000-year steps (the default orbit:
the shipped N-body one) and sets it beside what was published:

- ``long_term_earth_vs_vondrak``: the Earth's mean pole and obliquity against Vondrák, Capitaine & Wallace (2011)
  (``erfa.ltpequ``/``erfa.ltpecl``, the pole carried into the ICRS with the frame bias of ``erfa.ltpb``) over
  ±1, ±10 and ±200 kyr, with our per-epoch estimates (pole and obliquity);
- ``long_term_vs_laskar2004``: the Earth's and Mars' obliquity against La2004 (and Mars' La2003), the
  differences below with our obliquity estimate as an envelope;
- ``long_term_obliquities``: every body's obliquity, where it stops meaning anything, and the published ranges
  of ``data/long_term_references.toml`` as bands;
- ``long_term_summary.csv``: per body the range, the present value, the dominant period, the meaningful span and
  the cost; the comparisons' largest differences per span; Ceres' last maximum; and how the answer moves with the
  inputs (Ceres' precession constant ±2 %, Mars' scaled to La2004's present rate p = 7.597″/yr).

Times are Julian years from J2000.0 TDB (negative: the past), angles in degrees unless a name says otherwise.
"""
from __future__ import annotations

import csv
import math
import time
import tomllib
from dataclasses import replace
from functools import lru_cache
from pathlib import Path

import numpy as np

from ephem.batch.population import crossing_period  # the obliquity period, as the batch answers measure it

from ._command import chart_app

ROOT = Path(__file__).resolve().parent.parent
DATA = ROOT / "data"
BODIES = ("earth", "mars", "ceres", "vesta", "eros", "steins", "moon", "itokawa")
#: (start, stop, step) in Julian years: the full study, and the quick one (for the tests)
FULL_SPAN = (-3.0e6, 1.0e6, 1000.0)
QUICK_SPAN = (-30.0e3, 10.0e3, 1000.0)
#: the Earth against Vondrák et al.: (half-span, step) in years
VONDRAK_SPANS = ((1.0e3, 10.0), (1.0e4, 100.0), (2.0e5, 1000.0))
QUICK_VONDRAK_SPANS = ((1.0e3, 100.0), (1.0e4, 1000.0), (2.0e4, 2000.0))
#: the spans over which the La2004 differences are measured: (label, first year, last year)
LASKAR_SPANS = (("±100 kyr", -1.0e5, 1.0e5), ("past 1 Myr", -1.0e6, 0.0), ("past 3 Myr", -3.0e6, 0.0),
                ("future 1 Myr", 0.0, 1.0e6))
#: La2004's present precession rate of Mars (″/yr; Laskar et al. 2004, IMCCE README)
MARS_LA2004_P_ARCSEC = 7.597
#: Ceres' precession constant scaled by these factors (α ∝ J2 / (C/MR²) at fixed J2: +2 % ⇔ C/MR² −2 %)
CERES_SCALES = (0.98, 1.02)
ARCSEC_PER_RAD = 648_000.0 / math.pi
#: the fewest epochs of the meaningful past over which a period is measured
MIN_PERIOD_SAMPLES = 10
#: the published ranges drawn as bands: body -> [(label, reference key, value key, over)]
PUBLISHED = {
    "ceres": [("Ermakov et al. 2017", "ermakov2017", "obliquity_range_last_3Myr_deg", "last 3 Myr"),
              ("Vaillant et al. 2019", "vaillant2019", "ceres_obliquity_range_minus20_0Myr_deg", "-20..0 Myr")],
    "vesta": [("Vaillant et al. 2019", "vaillant2019", "vesta_obliquity_range_minus20_0Myr_deg", "-20..0 Myr")],
    "mars": [("La2004 (computed)", "laskar2004mars", "obliquity_range_last_3Myr_deg", "last 3 Myr")],
    "earth": [("La2004 (computed)", "laskar2004earth", "obliquity_range_last_1Myr_deg", "last 1 Myr")],
}


# ----------------------------------------------------------------------------- the histories

def span(quick: bool = False) -> tuple[float, float, float]:
    return QUICK_SPAN if quick else FULL_SPAN


@lru_cache(maxsize=4)
def histories(start: float, stop: float, step: float) -> dict[str, dict]:
    """Per body: ``answer`` (the :func:`ephem.api.history` dict) and ``cost_s`` (wall seconds), or ``reason``."""
    from ephem import api
    from ephem.base.errors import EphemError

    out = {}
    for name in BODIES:
        t = time.perf_counter()
        try:
            ans = api.history(name, start, stop, step)
        except EphemError as exc:
            out[name] = {"reason": f"{type(exc).__name__}: {exc}"}
            continue
        out[name] = {"answer": ans, "cost_s": time.perf_counter() - t}
    return out


def spin_constants(name: str):
    """The body's :class:`ephem.longterm.averaged_spin.SpinConstants` (its theory's averaged spin)."""
    from ephem.bodies.catalogue import resolve_body
    from ephem.families import theory_for

    b = resolve_body(name, "current")
    return theory_for(b, b.perturbers).secular_spin()


def scaled_history(name: str, scale: float, years: np.ndarray):
    """The body's spin history (:func:`ephem.longterm.averaged_spin.integrate`) along its shipped N-body orbit, with the
    precession constant of the orbit's centre scaled by ``scale``."""
    from ephem.longterm.nbody_orbit import shipped_orbit_history
    from ephem.longterm.averaged_spin import integrate

    spin = spin_constants(name)
    return integrate(replace(spin, orbit_constant=spin.orbit_constant * scale), shipped_orbit_history(name), years)


def mars_la2004_scale() -> float:
    """The factor on Mars' precession constant that makes its present rate α cos ε₀ − Ω_gp La2004's
    p = 7.597″/yr (ε₀ from the nominal history at J2000)."""
    spin = spin_constants("mars")
    eps0 = float(scaled_history("mars", 1.0, np.array([0.0])).obliquity[0])
    rate = spin.orbit_constant * math.cos(eps0) - spin.geodesic_rate
    return (MARS_LA2004_P_ARCSEC / ARCSEC_PER_RAD + spin.geodesic_rate) / (spin.orbit_constant * math.cos(eps0)) \
        if rate > 0 else float("nan")


def present_rate_arcsec(name: str, scale: float = 1.0) -> float:
    """α cos ε₀ − Ω_gp (″/yr) of the body with its precession constant scaled by ``scale``."""
    spin = spin_constants(name)
    eps0 = float(scaled_history(name, scale, np.array([0.0])).obliquity[0])
    return (spin.orbit_constant * scale * math.cos(eps0) - spin.geodesic_rate) * ARCSEC_PER_RAD


# ----------------------------------------------------------------------------- measures

def dominant_period(years: np.ndarray, values: np.ndarray, pad: int = 16) -> float:
    """The period (years) of the highest peak of the mean- and trend-removed series' zero-padded spectrum
    (Hann window), among periods shorter than a third of the span; NaN for a flat series."""
    y = np.asarray(values, float)
    t = np.asarray(years, float)
    if y.size < 8 or np.ptp(y) < 1e-9:
        return float("nan")
    y = y - np.polyval(np.polyfit(t, y, 1), t)
    n = y.size * pad
    power = np.abs(np.fft.rfft(y * np.hanning(y.size), n)) ** 2
    freq = np.fft.rfftfreq(n, d=float(t[1] - t[0]))
    ok = freq > 3.0 / (t[-1] - t[0])
    if not ok.any():
        return float("nan")
    return float(1.0 / freq[ok][np.argmax(power[ok])])


def last_maximum(years: np.ndarray, values: np.ndarray, before: float = 0.0) -> tuple[float, float]:
    """(year, value) of the last local maximum at or before ``before``, refined by a parabola; NaNs if none."""
    t, y = np.asarray(years, float), np.asarray(values, float)
    i = np.flatnonzero((y[1:-1] > y[:-2]) & (y[1:-1] >= y[2:]) & (t[1:-1] <= before)) + 1
    if not i.size:
        return float("nan"), float("nan")
    k = int(i[-1])
    a, b, c = y[k - 1], y[k], y[k + 1]
    den = a - 2 * b + c
    dx = 0.5 * (a - c) / den if den else 0.0
    return float(t[k] + dx * (t[k + 1] - t[k])), float(b - 0.25 * (a - c) * dx)


def in_span(years: np.ndarray, lo: float, hi: float) -> np.ndarray:
    return (years >= lo - 1e-6) & (years <= hi + 1e-6)


def body_row(name: str, entry: dict) -> dict:
    """The summary row of one body's history."""
    row = {"section": "body", "body": name}
    if "answer" not in entry:
        return {**row, "reason": entry["reason"]}
    a = entry["answer"]
    y, o = np.asarray(a["year"]), np.asarray(a["obliquity_deg"])
    past = in_span(y, y[0], 0.0)
    lo = a["meaningful_from_year"] if a["meaningful_from_year"] is not None else float(y[0])
    hi = a["meaningful_to_year"] if a["meaningful_to_year"] is not None else float(y[-1])
    mean = in_span(y, lo, hi)
    # the period over the meaningful part of the past, where it holds ten 1-kyr samples or more
    window = past & mean
    flat = np.ptp(o) < 1e-6 or window.sum() < MIN_PERIOD_SAMPLES
    period = float("nan") if flat else dominant_period(y[window], o[window])
    period_x = float("nan") if flat else crossing_period(y[window], o[window])
    return {**row, "orbit_model": a["model"]["name"], "present_deg": float(np.interp(0.0, y, o)),
            "past_min_deg": float(o[past].min()), "past_max_deg": float(o[past].max()),
            "all_min_deg": float(o.min()), "all_max_deg": float(o.max()),
            "meaningful_min_deg": float(o[mean].min()), "meaningful_max_deg": float(o[mean].max()),
            "period_fft_yr": period, "period_crossings_yr": period_x,
            "meaningful_from_year": "" if a["meaningful_from_year"] is None else a["meaningful_from_year"],
            "meaningful_to_year": "" if a["meaningful_to_year"] is None else a["meaningful_to_year"],
            "obliquity_error_first_deg": float(a["obliquity_error_deg"][0]),
            "obliquity_error_max_deg": float(np.max(a["obliquity_error_deg"])),
            "pole_error_max_deg": float(np.max(a["estimated_error_deg"])),
            "cost_s": entry["cost_s"], "span": f"[{y[0]:g}, {y[-1]:g}] step {y[1] - y[0]:g}", "reason": ""}


# ----------------------------------------------------------------------------- references

def read_laskar(name: str) -> dict[str, np.ndarray]:
    """A shipped La2004/La2003 file (data/laskar2004/NAME.csv): columns year, eccentricity, obliquity_deg."""
    with open(DATA / "laskar2004" / f"{name}.csv", encoding="utf-8") as fh:
        rows = list(csv.DictReader(line for line in fh if not line.startswith("#")))
    return {k: np.array([float(r[k]) for r in rows]) for k in ("year", "eccentricity", "obliquity_deg")}


@lru_cache(maxsize=1)
def references() -> dict:
    with open(DATA / "long_term_references.toml", "rb") as fh:
        return {r["key"]: r for r in tomllib.load(fh)["reference"]}


def published_ranges(name: str) -> list[dict]:
    """The published ranges of ``name`` (:data:`PUBLISHED`): label, min, max, over, citation."""
    out = []
    for label, key, value, over in PUBLISHED.get(name, ()):
        ref = references()[key]
        v = ref["values"][value]
        out.append({"label": label, "min": float(v["min"]), "max": float(v["max"]), "over": over,
                    "citation": ref["citation"]})
    return out


def vondrak_poles(years: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(equator pole in the ICRS, obliquity in degrees) of Vondrák et al. 2011 at ``years`` from J2000."""
    import erfa

    epj = 2000.0 + np.asarray(years, float)
    eq, ecl = erfa.ltpequ(epj), erfa.ltpecl(epj)
    bias = erfa.ltpb(2000.0)          # at J2000 the precession is the identity: the frame bias ICRS -> J2000
    pole = eq @ bias                  # bias.T @ v per row: the pole in the ICRS
    return pole, np.degrees(_angle(eq, ecl))


def _angle(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    from ephem.orbit.geometry import angle_between  # not at import: the study's --help stays light

    return angle_between(u, v)


def unit_vectors(ra_deg, dec_deg) -> np.ndarray:
    ra, dec = np.radians(ra_deg), np.radians(dec_deg)
    return np.stack((np.cos(dec) * np.cos(ra), np.cos(dec) * np.sin(ra), np.sin(dec)), axis=-1)


# ----------------------------------------------------------------------------- 1. the Earth against Vondrák

def vondrak_comparison(spans=VONDRAK_SPANS) -> tuple[list[dict], list[dict]]:
    """(series rows, one summary row per span): the angle between our mean pole and Vondrák's, our obliquity
    minus theirs, and our estimates (arcsec)."""
    from ephem import api

    series, summary = [], []
    for half, step in spans:
        a = api.history("earth", -half, half, step)
        y = np.asarray(a["year"])
        ref_pole, ref_eps = vondrak_poles(y)
        angle = np.degrees(_angle(unit_vectors(a["pole_ra_deg"], a["pole_dec_deg"]), ref_pole)) * 3600.0
        d_eps = (np.asarray(a["obliquity_deg"]) - ref_eps) * 3600.0
        est, est_eps = np.asarray(a["estimated_error_deg"]) * 3600.0, np.asarray(a["obliquity_error_deg"]) * 3600.0
        # La2004's own obliquity against Vondrák's, where its 1-kyr samples resolve the grid (steps >= 1 kyr)
        la = read_laskar("earth_la2004")
        la_eps = np.interp(y, la["year"], la["obliquity_deg"]) if step >= 1000.0 else None
        label = f"±{half / 1000:g} kyr"
        for i in range(y.size):
            series.append({"section": "series", "span": label, "year": y[i], "pole_angle_arcsec": angle[i],
                           "obliquity_diff_arcsec": d_eps[i], "estimated_error_arcsec": est[i],
                           "obliquity_error_arcsec": est_eps[i],
                           "la2004_minus_vondrak_obliquity_arcsec": "" if la_eps is None else
                           (la_eps[i] - ref_eps[i]) * 3600.0})
        summary.append({"section": "summary", "span": label, "step_years": step,
                        "largest_pole_angle_arcsec": float(angle.max()),
                        "largest_obliquity_diff_arcsec": float(np.abs(d_eps).max()),
                        "largest_estimate_arcsec": float(est.max()),
                        "largest_obliquity_estimate_arcsec": float(est_eps.max()),
                        "largest_la2004_minus_vondrak_obliquity_arcsec": "" if la_eps is None else
                        float(np.abs(la_eps - ref_eps).max()) * 3600.0,
                        "pole_within_estimate": bool(np.all(angle <= est)),
                        "obliquity_within_estimate": bool(np.all(np.abs(d_eps) <= est_eps))})
    return series, summary


def draw_vondrak(series: list[dict], summary: list[dict], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(summary), figsize=(15, 4.6), layout="constrained")
    for ax, s in zip(np.atleast_1d(axes), summary):
        rows = [r for r in series if r["span"] == s["span"]]
        y = np.array([r["year"] for r in rows]) / 1000.0
        for key, label, style in (("pole_angle_arcsec", "pole: ours to Vondrák", "-"),
                                  ("obliquity_diff_arcsec", "|obliquity ours − Vondrák|", "-"),
                                  ("estimated_error_arcsec", "our pole estimate", "--"),
                                  ("obliquity_error_arcsec", "our obliquity estimate", ":")):
            v = np.abs([r[key] for r in rows])
            ax.semilogy(y, np.maximum(v, 1e-4), style, label=label)
        if rows[0]["la2004_minus_vondrak_obliquity_arcsec"] != "":
            v = np.abs([r["la2004_minus_vondrak_obliquity_arcsec"] for r in rows])
            ax.semilogy(y, np.maximum(v, 1e-4), "-", lw=0.8, color="k", alpha=0.6,
                        label="|obliquity La2004 − Vondrák|")
            ax.legend(fontsize=8)
        ax.set_title(f"{s['span']}: pole {s['largest_pole_angle_arcsec']:.3g}″, "
                     f"obliquity {s['largest_obliquity_diff_arcsec']:.3g}″")
        ax.set_xlabel("kyr from J2000")
        ax.grid(True, which="both", alpha=0.3)
    np.atleast_1d(axes)[0].set_ylabel("arcsec")
    np.atleast_1d(axes)[0].legend(fontsize=8)
    fig.suptitle("The Earth's mean pole against Vondrák, Capitaine & Wallace 2011 (erfa.ltpequ / ltpecl)")
    fig.savefig(path, dpi=110)
    plt.close(fig)


def earth_vs_vondrak(out_dir: Path, quick: bool = False) -> list[dict]:
    out_dir.mkdir(parents=True, exist_ok=True)
    series, summary = vondrak_comparison(QUICK_VONDRAK_SPANS if quick else VONDRAK_SPANS)
    write_csv(out_dir / "long_term_earth_vs_vondrak.csv", summary + series)
    draw_vondrak(series, summary, out_dir / "long_term_earth_vs_vondrak.png")
    for s in summary:
        print(f"Earth vs Vondrák {s['span']:>10}: pole {s['largest_pole_angle_arcsec']:10.3f}″ "
              f"(estimate {s['largest_estimate_arcsec']:.3g}″), obliquity {s['largest_obliquity_diff_arcsec']:9.3f}″ "
              f"(estimate {s['largest_obliquity_estimate_arcsec']:.3g}″)"
              + ("" if s["largest_la2004_minus_vondrak_obliquity_arcsec"] == "" else
                 f"; La2004 − Vondrák obliquity {s['largest_la2004_minus_vondrak_obliquity_arcsec']:.1f}″"))
    return summary


# ----------------------------------------------------------------------------- 2. Earth and Mars against La2004

def laskar_comparison(quick: bool = False) -> tuple[list[dict], list[dict]]:
    """(series rows on the La2004 grid within our span, summary rows: largest |difference| per span)."""
    hist = histories(*span(quick))
    series, summary = [], []
    refs = {"earth": {"La2004": read_laskar("earth_la2004")},
            "mars": {"La2004": read_laskar("mars_la2004"), "La2003": read_laskar("mars_la2003")}}
    for name, sources in refs.items():
        a = hist[name]["answer"]
        y, o, err = np.asarray(a["year"]), np.asarray(a["obliquity_deg"]), np.asarray(a["obliquity_error_deg"])
        la = sources["La2004"]
        keep = in_span(la["year"], y[0], y[-1])
        t = la["year"][keep]
        ours, e = np.interp(t, y, o), np.interp(t, y, err)
        ref = la["obliquity_deg"][keep]
        other = np.interp(t, sources["La2003"]["year"], sources["La2003"]["obliquity_deg"]) if "La2003" in sources \
            else None
        for i in range(t.size):
            series.append({"section": "series", "body": name, "year": t[i], "ours_deg": ours[i], "la2004_deg": ref[i],
                           "la2003_deg": "" if other is None else other[i], "ours_minus_la2004_deg": ours[i] - ref[i],
                           "la2004_minus_la2003_deg": "" if other is None else ref[i] - other[i],
                           "obliquity_error_deg": e[i], "la2004_eccentricity": la["eccentricity"][keep][i]})
        for label, lo, hi in LASKAR_SPANS:
            m = in_span(t, lo, hi)
            if not m.any() or t[m][0] > lo + 1e-6 or t[m][-1] < hi - 1e-6:
                continue
            summary.append({"section": "summary", "body": name, "span": label,
                            "largest_ours_minus_la2004_deg": float(np.abs(ours - ref)[m].max()),
                            "largest_la2004_minus_la2003_deg": "" if other is None else
                            float(np.abs(ref - other)[m].max()),
                            "largest_obliquity_error_deg": float(e[m].max()),
                            "within_estimate": bool(np.all(np.abs(ours - ref)[m] <= e[m]))})
    return series, summary


def draw_laskar(series: list[dict], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 2, figsize=(15, 8), sharex="col", layout="constrained",
                             gridspec_kw={"height_ratios": [2, 1.3]})
    for col, name in enumerate(("earth", "mars")):
        rows = [r for r in series if r["body"] == name]
        t = np.array([r["year"] for r in rows]) / 1e6
        ours, ref = np.array([r["ours_deg"] for r in rows]), np.array([r["la2004_deg"] for r in rows])
        err = np.array([r["obliquity_error_deg"] for r in rows])
        top, low = axes[0, col], axes[1, col]
        top.plot(t, ref, lw=0.9, label="La2004", color="k")
        if name == "mars":
            top.plot(t, [r["la2003_deg"] for r in rows], lw=0.7, label="La2003", color="tab:green", alpha=0.8)
        top.plot(t, ours, lw=0.9, label="ours (N-body orbit)", color="tab:red", alpha=0.8)
        top.set_title(f"{name.capitalize()}: obliquity")
        top.set_ylabel("deg")
        top.legend(fontsize=8, loc="upper left")
        low.fill_between(t, -err, err, color="tab:red", alpha=0.15, label="± our obliquity estimate")
        low.plot(t, ours - ref, lw=0.8, color="tab:red", label="ours − La2004")
        if name == "mars":
            low.plot(t, ref - np.array([r["la2003_deg"] for r in rows]), lw=0.7, color="tab:green",
                     label="La2004 − La2003")
        lim = max(float(np.abs(ours - ref).max()), 1e-3) * 1.3
        low.set_ylim(-lim, lim)
        low.set_ylabel("deg")
        low.set_xlabel("Myr from J2000")
        low.legend(fontsize=8, loc="lower left")
        for ax in (top, low):
            ax.grid(True, alpha=0.3)
    fig.suptitle("Obliquity against Laskar et al. 2004 (La2004; Mars also La2003)")
    fig.savefig(path, dpi=110)
    plt.close(fig)


def vs_laskar2004(out_dir: Path, quick: bool = False) -> list[dict]:
    out_dir.mkdir(parents=True, exist_ok=True)
    series, summary = laskar_comparison(quick)
    write_csv(out_dir / "long_term_vs_laskar2004.csv", summary + series)
    draw_laskar(series, out_dir / "long_term_vs_laskar2004.png")
    for s in summary:
        extra = "" if s["largest_la2004_minus_la2003_deg"] == "" else \
            f" (La2004 − La2003 {s['largest_la2004_minus_la2003_deg']:.3f}°)"
        print(f"{s['body']:<6} vs La2004 {s['span']:>13}: {s['largest_ours_minus_la2004_deg']:.4f}° "
              f"(estimate {s['largest_obliquity_error_deg']:.3g}°){extra}")
    return summary


# ----------------------------------------------------------------------------- 3. every body's obliquity

def draw_obliquities(hist: dict, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(4, 2, figsize=(15, 13), layout="constrained")
    for ax, name in zip(axes.ravel(), BODIES):
        entry = hist[name]
        ax.set_title(name.capitalize())
        if "answer" not in entry:
            ax.text(0.5, 0.5, "not applicable:\n" + _wrap(entry["reason"], 80), ha="center", va="center",
                    fontsize=8, transform=ax.transAxes)
            ax.set_axis_off()
            continue
        a = entry["answer"]
        t, o = np.asarray(a["year"]) / 1e6, np.asarray(a["obliquity_deg"])
        err = np.asarray(a["obliquity_error_deg"])
        for i, r in enumerate(published_ranges(name)):
            ax.axhspan(r["min"], r["max"], color=f"C{i + 2}", alpha=0.15,
                       label=f"{r['label']}: {r['min']:g}–{r['max']:g}° ({r['over']})")
        ax.fill_between(t, o - err, o + err, color="tab:blue", alpha=0.2, lw=0, label="± obliquity estimate")
        ax.plot(t, o, lw=0.7, color="tab:blue", label=f"ours ({a['model']['name']} orbit)")
        for edge, side in ((a["meaningful_from_year"], "before"), (a["meaningful_to_year"], "after")):
            if edge is not None:
                lo, hi = (t[0], edge / 1e6) if side == "before" else (edge / 1e6, t[-1])
                ax.axvspan(lo, hi, color="grey", alpha=0.25, hatch="//", lw=0,
                           label="not meaningful (neighbours or orbit part > 1°)" if side == "before" or
                           a["meaningful_from_year"] is None else None)
        lo, hi = float(o.min()), float(o.max())
        bands = [(r["min"], r["max"]) for r in published_ranges(name)]
        lo, hi = min([lo] + [b[0] for b in bands]), max([hi] + [b[1] for b in bands])
        pad = max(0.1 * (hi - lo), 0.05)
        ax.set_ylim(lo - pad, hi + pad)
        ax.set_xlim(t[0], t[-1])
        ax.set_ylabel("obliquity (deg)")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7, loc="best")
    for ax in axes[-1]:
        ax.set_xlabel("Myr from J2000")
    fig.suptitle("Obliquity histories (averaged spin along the shipped N-body orbits), with published ranges")
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _wrap(text: str, width: int) -> str:
    import textwrap

    return "\n".join(textwrap.wrap(text, width)[:8])


def obliquities(out_dir: Path, quick: bool = False) -> list[dict]:
    out_dir.mkdir(parents=True, exist_ok=True)
    hist = histories(*span(quick))
    rows = []
    for name in BODIES:
        entry = hist[name]
        if "answer" not in entry:
            rows.append({"body": name, "reason": entry["reason"]})
            continue
        a = entry["answer"]
        lo = a["meaningful_from_year"] if a["meaningful_from_year"] is not None else -math.inf
        hi = a["meaningful_to_year"] if a["meaningful_to_year"] is not None else math.inf
        for y, o, e in zip(a["year"], a["obliquity_deg"], a["obliquity_error_deg"]):
            rows.append({"body": name, "year": float(y), "obliquity_deg": float(o), "obliquity_error_deg": float(e),
                         "meaningful": bool(lo <= y <= hi), "reason": ""})
    write_csv(out_dir / "long_term_obliquities.csv", rows)
    draw_obliquities(hist, out_dir / "long_term_obliquities.png")
    return rows


# ----------------------------------------------------------------------------- 4. the summary and the inputs

def history_measures(label: str, body: str, h, past_from: float) -> dict:
    """Range, present value and period of a :class:`~ephem.longterm.averaged_spin.SpinHistory` (obliquity in radians)."""
    y, o = h.years, np.degrees(h.obliquity)
    past = in_span(y, past_from, 0.0)
    return {"section": "inputs", "body": body, "case": label, "present_deg": float(np.interp(0.0, y, o)),
            "past_min_deg": float(o[past].min()), "past_max_deg": float(o[past].max()),
            "all_min_deg": float(o.min()), "all_max_deg": float(o.max()),
            "period_fft_yr": dominant_period(y[past], o[past]), "period_crossings_yr": crossing_period(y[past], o[past])}


def inputs_rows(quick: bool = False) -> list[dict]:
    """How Ceres' and Mars' answers move with the precession constant (:data:`CERES_SCALES`, La2004's p)."""
    start, stop, step = span(quick)
    years = start + step * np.arange(int(round((stop - start) / step)) + 1)
    rows = []
    for scale in (1.0,) + CERES_SCALES:
        r = history_measures(f"precession constant × {scale:g}", "ceres", scaled_history("ceres", scale, years), start)
        rows.append({**r, "scale": scale, "present_rate_arcsec_per_yr": present_rate_arcsec("ceres", scale)})
    k = mars_la2004_scale()
    for scale, label in ((1.0, "nominal"), (k, f"La2004 p = {MARS_LA2004_P_ARCSEC}″/yr")):
        r = history_measures(label, "mars", scaled_history("mars", scale, years), start)
        rows.append({**r, "scale": scale, "present_rate_arcsec_per_yr": present_rate_arcsec("mars", scale)})
    la = read_laskar("mars_la2004")
    keep = in_span(la["year"], start, stop)
    for r in rows:
        if r["body"] == "mars":
            h = scaled_history("mars", r["scale"], la["year"][keep])
            diff = np.abs(np.degrees(h.obliquity) - la["obliquity_deg"][keep])
            for label, lo, hi in LASKAR_SPANS:
                m = in_span(la["year"][keep], lo, hi)
                if m.any() and la["year"][keep][m][0] <= lo + 1e-6 and la["year"][keep][m][-1] >= hi - 1e-6:
                    r[f"largest_minus_la2004_deg {label}"] = float(diff[m].max())
            r["largest_minus_la2004_past_deg"] = float(diff[la["year"][keep] <= 0].max())
    return rows


def ceres_maximum(quick: bool = False) -> dict:
    """Ceres' last obliquity maximum before J2000, from a 100-year history over the last 60 kyr."""
    from ephem import api

    a = api.history("ceres", -60.0e3, 0.0, 100.0)
    year, value = last_maximum(np.asarray(a["year"]), np.asarray(a["obliquity_deg"]))
    ref = references()["ermakov2017"]["values"]
    return {"section": "ceres_last_maximum", "body": "ceres", "year": year, "value_deg": value,
            "published_years_before_present": ref["last_maximum_epoch_yr_before_present"]["value"],
            "published_value_deg": ref["last_maximum_obliquity_deg"]["value"]}


def summary(out_dir: Path, quick: bool = False) -> list[dict]:
    out_dir.mkdir(parents=True, exist_ok=True)
    hist = histories(*span(quick))
    rows = [body_row(name, hist[name]) for name in BODIES]
    for r in rows:
        r["published"] = "; ".join(f"{p['label']} {p['min']:g}-{p['max']:g} deg ({p['over']})"
                                   for p in published_ranges(r["body"]))
    extra = inputs_rows(quick) + [ceres_maximum(quick)]
    write_csv(out_dir / "long_term_summary.csv", rows + extra)
    print_summary(rows, extra)
    return rows + extra


def print_summary(rows: list[dict], extra: list[dict]) -> None:
    print(f"{'body':<8} {'orbit':<7} {'present':>8} {'past min':>9} {'past max':>9} {'all min':>8} {'all max':>8} "
          f"{'period (FFT)':>12} {'(crossings)':>11} {'meaningful':>22} {'range there':>13} {'cost':>6}")
    for r in rows:
        if r.get("reason"):
            print(f"{r['body']:<8} not applicable: {r['reason'][:150]}")
            continue
        mf = (f"[{'-inf' if r['meaningful_from_year'] == '' else format(r['meaningful_from_year'], 'g')}, "
              f"{'+inf' if r['meaningful_to_year'] == '' else format(r['meaningful_to_year'], 'g')}]")
        mm = f"{r['meaningful_min_deg']:.2f}-{r['meaningful_max_deg']:.2f}"
        print(f"{r['body']:<8} {r['orbit_model']:<7} {r['present_deg']:8.3f} {r['past_min_deg']:9.3f} "
              f"{r['past_max_deg']:9.3f} {r['all_min_deg']:8.3f} {r['all_max_deg']:8.3f} "
              f"{r['period_fft_yr']:12.0f} {r['period_crossings_yr']:11.0f} {mf:>22} {mm:>13} {r['cost_s']:5.1f}s")
    for r in extra:
        if r["section"] == "inputs":
            print(f"{r['body']:<6} {r['case']:<28} rate {r['present_rate_arcsec_per_yr']:.4f}″/yr: past "
                  f"{r['past_min_deg']:.3f}–{r['past_max_deg']:.3f}°, period {r['period_fft_yr']:.0f} yr "
                  f"(crossings {r['period_crossings_yr']:.0f})"
                  + "".join(f", |ours − La2004| {k.split(' ', 1)[1]} {v:.3f}°" for k, v in r.items()
                            if k.startswith("largest_minus_la2004_deg ")))
        else:
            print(f"Ceres' last maximum: {r['value_deg']:.2f}° at {r['year']:.0f} yr (published: "
                  f"{r['published_value_deg']:g}° {r['published_years_before_present']:g} yr ago)")


# ----------------------------------------------------------------------------- files and the command

def write_csv(path: Path, rows: list[dict]) -> None:
    keys: list[str] = []
    for r in rows:
        keys += [k for k in r if k not in keys]
    with open(path, "w", newline="", encoding="utf-8") as fh:
        w = csv.DictWriter(fh, fieldnames=keys)
        w.writeheader()
        for r in rows:
            w.writerow({k: (repr(float(v)) if isinstance(v, (float, np.floating)) else
                            bool(v) if isinstance(v, np.bool_) else v) for k, v in r.items()})


def read_csv(path: Path) -> list[dict]:
    with open(path, newline="", encoding="utf-8") as fh:
        return list(csv.DictReader(fh))


def tasks(out_dir: Path, quick: bool = False):
    return [("long_term_earth_vs_vondrak", lambda: earth_vs_vondrak(out_dir, quick)),
            ("long_term_vs_laskar2004", lambda: vs_laskar2004(out_dir, quick)),
            ("long_term_obliquities", lambda: obliquities(out_dir, quick)),
            ("long_term_summary", lambda: summary(out_dir, quick))]


def main(out_dir: Path = Path("docs/charts"), quick: bool = False) -> None:
    for _, job in tasks(out_dir, quick):
        job()


app = chart_app(lambda out, quick=False: tasks(out, quick), "docs/long_term.md",
                help="The spin axis over -3..+1 Myr against Vondrák 2011, La2004 and the published ranges.",
                quick_help="-30..+10 kyr and short Vondrák spans (for the tests).")

if __name__ == "__main__":
    app()
