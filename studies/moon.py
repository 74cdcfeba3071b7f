"""The Moon's pole against the IAU model (WGCCRE, as NAIF's pck00011 has it) over 1900-2100.

A study, not the library (see :mod:`studies`): run from the project root as
``python -m studies.moon [--out DIR] [--quick]``. For each model of the Moon's ladder (``cassini``, the bare
Cassini state; ``librations``, plus the forced physical librations; ``integration``, the full rigid Moon) and
for the model a tolerance picks (:data:`TOLERANCE_MAS`), it asks :func:`ephem.api.track_arrays` for the pole on
a daily grid and measures its angle from the IAU pole (:mod:`studies.wgccre_moon`): the largest and the rms,
and its components in the ecliptic of date, across the node line (the pole's distance from the ecliptic pole,
ΔI) and along it (sin I Δλ). A reference row, :func:`cassini_circle`, is always there: the bare Cassini
circle built here (a fixed I about the ecliptic pole of date, at the node of date plus 90°), independent of
the library; it stood in for the route before the route existed.

The decomposition (:func:`fit_terms`) fits each pole's α and δ, as the IAU did, with a quadratic in T and a
sine and a cosine of each E argument, and sets the amplitudes beside the IAU's: E1, E2 and E10 (Ω, 2Ω, 3Ω)
are the Cassini circle and its projection on the sky; E3, E4, E6, E7 and E13 the physical librations; a term
is reproduced as far as the tangent-plane vector of ours minus the IAU's is small against the IAU's.

It writes ``moon_vs_wgccre.png`` and ``moon_vs_wgccre.csv`` (one ``summary`` row per model, one ``term`` row
per model and E argument) and returns the summary rows. The page: docs/moon.md.
"""
from __future__ import annotations

import csv
import math
import time
from pathlib import Path

import numpy as np

from . import wgccre_moon as iau
from ._command import chart_app

#: 1900-01-01 and 2100-01-01, 0h TDB (JD)
START_JD, STOP_JD = 2415020.5, 2488069.5
STEP_DAYS = 1.0
#: The ladder's models, cheapest first.
MODELS = ("cassini", "librations", "integration")
#: The IAU model's own error (arcsec): NAIF's lunar frame kernel moon_de440_220930.tf measures IAU_MOON against
#: the DE440 mean Earth frame over 2000-2040, an amplitude of about 0.0051° (155 m; the 2009 report says about
#: 150 m, 17.8″), from the truncated libration series.
IAU_ERROR_ARCSEC = 0.0051 * 3600.0
#: The tolerance of the "by tolerance" row: the IAU model's own error (which of our models is as good).
TOLERANCE_MAS = IAU_ERROR_ARCSEC * 1000.0
#: The reference circle's inclination to the ecliptic of date (deg): the IAU series' E1 amplitudes, 1.5419°
#: in δ and 3.8787° cos δ0 = 1.5440° in α, averaged.
CIRCLE_I_DEG = 1.543
#: The pole's E arguments fitted (E11, 273-year period, is a quadratic over 200 years, and the IAU has it in
#: W alone: left out of the pole fit).
FIT_TERMS = tuple(i for i in range(1, 14) if i != 11)
#: The IAU's terms by kind.
NODE_TERMS, LIBRATION_TERMS = (1, 2, 10), (3, 4, 6, 7, 13)
ARCSEC = math.pi / 648_000.0


def grid(quick: bool = False) -> tuple[float, float, float]:
    """(start JD, stop JD, step days): 1900-2100 daily, or 1990-2010 every 5 days with ``quick``."""
    return (2447892.5, 2455197.5, 5.0) if quick else (START_JD, STOP_JD, STEP_DAYS)


def _jd(start: float, stop: float, step: float) -> np.ndarray:
    return start + step * np.arange(int(math.floor((stop - start) / step + 1e-9)) + 1)


def ecliptic_of_date(jd_tdb: np.ndarray) -> np.ndarray:
    """ICRF → mean ecliptic and equinox of date (IAU 2006, erfa.ecm06), (N, 3, 3). TT for TDB: < 2 ms."""
    import erfa

    return erfa.ecm06(np.asarray(jd_tdb, dtype=float), 0.0)


def cassini_circle(jd_tdb: np.ndarray, inclination_deg: float = CIRCLE_I_DEG) -> np.ndarray:
    """The bare Cassini state, built here: the pole at ``inclination_deg`` from the ecliptic pole of date, at
    ecliptic longitude Ω + 90°, Ω the Moon's mean node of date (IERS 2003, erfa.faom03). ICRF unit vectors."""
    import erfa

    jd = np.asarray(jd_tdb, dtype=float)
    node = erfa.faom03((jd - iau.J2000_JD) / iau.DAYS_PER_CENTURY)
    lam, inc = node + 0.5 * math.pi, math.radians(inclination_deg)
    v = np.stack((math.sin(inc) * np.cos(lam), math.sin(inc) * np.sin(lam), np.full_like(lam, math.cos(inc))), -1)
    return np.einsum("nji,nj->ni", ecliptic_of_date(jd), v)


def route_pole(start: float, stop: float, step: float, **request) -> tuple[np.ndarray, np.ndarray, dict]:
    """The library's Moon pole, its mean rotation axis (the IAU's is the mean-Earth frame's pole) unless the request
    names another: (JD TDB, ICRF unit vectors, the answer's ``model`` object)."""
    from ephem import api

    ans = api.track_arrays("moon", start, stop, step, **{"axis": "mean_rotation", **request})
    return np.asarray(ans["jd_tdb"]), iau.unit_vectors(ans["pole_ra_deg"], ans["pole_dec_deg"]), ans["model"]


def poles(start: float, stop: float, step: float, tolerance_mas: float = TOLERANCE_MAS) -> list[dict]:
    """One entry per row: label, the model served, JD, vectors, wall time, or the reason there is none."""
    from ephem.base.errors import EphemError

    jd = _jd(start, stop, step)
    out = []
    requests = [(name, {"model": name}) for name in MODELS]
    requests.append((f"by tolerance ({tolerance_mas:.0f} mas)", {"tolerance_mas": tolerance_mas}))
    for label, request in requests:
        t = time.perf_counter()
        try:
            jd_r, vec, model = route_pole(start, stop, step, **request)
        except EphemError as exc:
            out.append({"label": label, "served": "", "reason": f"{type(exc).__name__}: {exc}"[:200]})
            continue
        out.append({"label": label, "served": model.get("name", ""), "jd": jd_r, "vec": vec,
                    "estimate_mas": model.get("estimated_error_mas"), "wall_s": time.perf_counter() - t})
    t = time.perf_counter()
    out.append({"label": f"reference circle (I = {CIRCLE_I_DEG}°)", "served": "studies.moon.cassini_circle",
                "jd": jd, "vec": cassini_circle(jd), "estimate_mas": None, "wall_s": time.perf_counter() - t})
    return out


def components(jd: np.ndarray, ours: np.ndarray, ref: np.ndarray) -> dict[str, np.ndarray]:
    """The angle from ``ref`` to ``ours`` (arcsec) and its components in the ecliptic of date: ΔI (the
    distance from the ecliptic pole, across the node line) and sin I Δλ (along the node line)."""
    angle = np.arctan2(np.linalg.norm(np.cross(ours, ref), axis=-1), np.sum(ours * ref, axis=-1))
    rot = ecliptic_of_date(jd)
    a, b = np.einsum("nij,nj->ni", rot, ours), np.einsum("nij,nj->ni", rot, ref)
    inc_a, inc_b = np.arccos(np.clip(a[:, 2], -1, 1)), np.arccos(np.clip(b[:, 2], -1, 1))
    dlam = np.angle(np.exp(1j * (np.arctan2(a[:, 1], a[:, 0]) - np.arctan2(b[:, 1], b[:, 0]))))
    return {"angle": angle / ARCSEC, "across": (inc_a - inc_b) / ARCSEC, "along": np.sin(inc_b) * dlam / ARCSEC}


def radec(vec: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(α, δ) in degrees of ICRF unit vectors, α in [0, 360)."""
    return np.mod(np.degrees(np.arctan2(vec[..., 1], vec[..., 0])), 360.0), np.degrees(np.arcsin(vec[..., 2]))


def fit_terms(jd: np.ndarray, vec: np.ndarray, terms=FIT_TERMS) -> dict:
    """Least squares of the pole's α and δ (deg) on 1, T, T², sin E_i, cos E_i: the coefficients per term
    ({i: (α_sin, α_cos, δ_sin, δ_cos)} in degrees) and the rms of what is left (arcsec, in α cos δ and δ)."""
    t = (jd - iau.J2000_JD) / iau.DAYS_PER_CENTURY
    e = iau.e_arguments(jd)
    cols = [np.ones_like(t), t, t * t]
    for i in terms:
        cols += [np.sin(e[i - 1]), np.cos(e[i - 1])]
    basis = np.stack(cols, axis=1)
    ra, dec = radec(vec)
    coef, *_ = np.linalg.lstsq(basis, np.stack((ra, dec), axis=1), rcond=None)
    resid = np.stack((ra, dec), axis=1) - basis @ coef
    cosd = math.cos(math.radians(float(np.mean(dec))))
    out = {i: (coef[3 + 2 * k, 0], coef[4 + 2 * k, 0], coef[3 + 2 * k, 1], coef[4 + 2 * k, 1])
           for k, i in enumerate(terms)}
    return {"terms": out, "poly_ra": coef[:3, 0], "poly_dec": coef[:3, 1], "cos_dec": cosd,
            "resid_rms_arcsec": float(np.sqrt(np.mean((resid[:, 0] * cosd) ** 2 + resid[:, 1] ** 2))) * 3600.0}


def iau_terms(terms=FIT_TERMS) -> dict[int, tuple[float, float, float, float]]:
    """The IAU's own amplitudes in the same layout: (α on sin, α on cos = 0, δ on sin = 0, δ on cos)."""
    m = iau.load()
    return {i: (m.nut_prec_ra[i - 1], 0.0, 0.0, m.nut_prec_dec[i - 1]) for i in terms}


def _amplitude(coef, cos_dec: float) -> float:
    """The largest displacement over a cycle (degrees) of a term a_s sin E + a_c cos E in α and b_s sin E + b_c
    cos E in δ, on the sky (α scaled by cos δ): the largest singular value of [[a_s, a_c], [b_s, b_c]]; a circle's
    radius, a line's half-length."""
    a_s, a_c, b_s, b_c = coef
    return float(np.linalg.norm(np.array([[a_s * cos_dec, a_c * cos_dec], [b_s, b_c]]), 2))


def term_rows(label: str, fit: dict) -> list[dict]:
    """Per E argument: the IAU's amplitude, ours, and how much of the IAU's term ours reproduces (1 − the
    amplitude of ours minus the IAU's over the IAU's)."""
    ref, cosd = iau_terms(tuple(fit["terms"])), fit["cos_dec"]
    rows = []
    for i, ours in fit["terms"].items():
        size, miss = _amplitude(ref[i], cosd), _amplitude(np.subtract(ours, ref[i]), cosd)
        rows.append({"section": "term", "model": label, "term": f"E{i}",
                     "kind": "node" if i in NODE_TERMS else "libration" if i in LIBRATION_TERMS else "other",
                     "iau_ra_sin_deg": ref[i][0], "iau_dec_cos_deg": ref[i][3],
                     "ours_ra_sin_deg": ours[0], "ours_ra_cos_deg": ours[1], "ours_dec_sin_deg": ours[2],
                     "ours_dec_cos_deg": ours[3], "iau_amplitude_arcsec": size * 3600.0,
                     "ours_amplitude_arcsec": _amplitude(ours, cosd) * 3600.0, "miss_arcsec": miss * 3600.0,
                     "reproduced": (1.0 - miss / size) if size > 0 else ""})
    return rows


def compare(entries: list[dict]) -> tuple[list[dict], list[dict], dict]:
    """The summary rows, the term rows and the series for the chart."""
    summary, terms, series = [], [], {}
    for ent in entries:
        row = {"section": "summary", "model": ent["label"], "served": ent["served"]}
        if "vec" not in ent:
            summary.append({**row, "reason": ent["reason"]})
            continue
        jd = ent["jd"]
        c = components(jd, ent["vec"], iau.pole_vectors(jd))
        fit = fit_terms(jd, ent["vec"])
        series[ent["label"]] = (jd, c)
        summary.append({**row, "samples": jd.size, "largest_arcsec": float(c["angle"].max()),
                        "rms_arcsec": float(np.sqrt(np.mean(c["angle"] ** 2))),
                        "across_mean_arcsec": float(c["across"].mean()),
                        "across_rms_arcsec": float(np.sqrt(np.mean(c["across"] ** 2))),
                        "along_mean_arcsec": float(c["along"].mean()),
                        "along_rms_arcsec": float(np.sqrt(np.mean(c["along"] ** 2))),
                        "fit_resid_rms_arcsec": fit["resid_rms_arcsec"],
                        "estimated_error_mas": "" if ent["estimate_mas"] is None else ent["estimate_mas"],
                        "wall_s": ent["wall_s"], "reason": ""})
        terms += term_rows(ent["label"], fit)
    return summary, terms, series


def write_csv(path: Path, rows: list[dict]) -> None:
    keys = list(dict.fromkeys(k for r in rows for k in r))
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, keys, restval="")
        w.writeheader()
        w.writerows(rows)


def draw(series: dict, terms: list[dict], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig = plt.figure(figsize=(16, 8.5), layout="constrained")
    gs = fig.add_gridspec(3, 3, width_ratios=(2.0, 1.2, 1.1))
    keys = ("angle", "across", "along")
    ylabels = ("angle from the IAU pole (″)", "ΔI, across the node line (″)", "sin I Δλ, along the node line (″)")
    colours = dict(zip(series, plt.rcParams["axes.prop_cycle"].by_key()["color"]))
    order = sorted(series, key=lambda label: label.startswith("reference"), reverse=True)   # the reference below
    for col, (lo, hi, title) in enumerate(((1899.0, 2101.0, "1900-2100"), (2000.0, 2001.0, "2000, one year"))):
        axes = [fig.add_subplot(gs[k, col]) for k in range(3)]
        for label in order:
            jd, c = series[label]
            year = 2000.0 + (jd - iau.J2000_JD) / 365.25
            sel = (year >= lo) & (year <= hi)
            for ax, key in zip(axes, keys):
                ax.plot(year[sel], c[key][sel], lw=0.3 if col == 0 else 0.9, color=colours[label],
                        label=label if key == "angle" else None)
        for ax, ylabel in zip(axes, ylabels):
            ax.set_xlim(lo, hi)
            ax.grid(alpha=0.3)
            if col == 0:
                ax.set_ylabel(ylabel)
        axes[0].set_title(title, fontsize=9)
        axes[2].set_xlabel("year (TDB)")
        if col == 0:
            leg = axes[0].legend(fontsize=8, loc="upper right")
            for line in leg.get_lines():
                line.set_linewidth(2.0)
    bar = fig.add_subplot(gs[:, 2])
    labels = list(series)
    names = list(dict.fromkeys(r["term"] for r in terms))
    iau_size = {r["term"]: r["iau_amplitude_arcsec"] for r in terms}
    y = np.arange(len(names))
    h = 0.8 / (len(labels) + 1)
    bar.barh(y, [iau_size[n] for n in names], h, color="black", label="IAU (pck00011)")
    for k, label in enumerate(labels):
        size = {r["term"]: r["ours_amplitude_arcsec"] for r in terms if r["model"] == label}
        bar.barh(y + (k + 1) * h, [size[n] for n in names], h, color=colours[label], label=label)
    bar.set_yticks(y + 0.4 - h / 2, names)
    bar.invert_yaxis()
    bar.set_xscale("symlog", linthresh=1.0)
    bar.set_xlabel("term amplitude on the sky (″)")
    bar.set_title("the pole's E terms: IAU and ours (fitted)", fontsize=9)
    bar.legend(fontsize=7, loc="lower right")
    bar.grid(alpha=0.3, axis="x")
    fig.suptitle("The Moon's pole minus the IAU model (WGCCRE 2009 series, NAIF pck00011), ICRF; "
                 "components in the ecliptic of date", fontsize=11)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def chart(out_dir: Path, quick: bool = False) -> list[dict]:
    out_dir.mkdir(parents=True, exist_ok=True)
    summary, terms, series = compare(poles(*grid(quick)))
    write_csv(out_dir / "moon_vs_wgccre.csv", summary + terms)
    draw(series, terms, out_dir / "moon_vs_wgccre.png")
    for r in summary:
        what = (f"largest {r['largest_arcsec']:.1f}″, rms {r['rms_arcsec']:.1f}″" if "largest_arcsec" in r
                else r["reason"])
        print(f"{r['model']:<34} {r['served'] or '-':<28} {what}")
    return summary


def tasks(out_dir: Path, quick: bool = False):
    return [("moon_vs_wgccre", lambda: chart(out_dir, quick))]


app = chart_app(lambda out, quick=False: tasks(out, quick), "docs/moon.md",
                help="The Moon's pole per model against the IAU (WGCCRE, pck00011) model over 1900-2100.",
                quick_help="1990-2010 every 5 days (for the tests).")

if __name__ == "__main__":
    app()
