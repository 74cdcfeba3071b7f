"""The free-motion methods (exact, Lara's series, numeric): cost against accuracy, and where the series fails.

A study, not the library (see :mod:`studies`): run from the project root as
``python -m studies.free_motion [--out DIR] [--quick]`` (default ``--out docs/charts``).
:func:`tasks` lists the jobs (label, zero-argument callable), as in :mod:`studies.accuracy`.
Each writes one chart into ``out_dir`` as PNG (150 dpi) and SVG, with the plotted numbers as CSV:

1. ``free_motion_work_precision``: the error of the body-frame angular momentum direction (the
   largest angle over ~1000 epochs spread over three wobble periods, radians) against the CPU time
   of one evaluation of all those epochs, for the exact Euler-Poinsot solution (construction of the
   :class:`~ephem.rotation.euler_poinsot.FreeRotation` included), Lara's series truncated at orders
   N = 1, 2, 4, 8, 12 (``SamSeriesSolution.propagate(..., upto=N)``; the one-off build of the series,
   ~0.1-0.5 s, *excluded*: it is cached per body) and DOP853 on Euler's equations at rtol 1e-8, 1e-10,
   1e-12. The reference is the exact solution; the exact point itself is plotted at its difference from
   DOP853 at rtol 1e-13 (an upper bound of its error, open star). One panel per (body, J): Eros-like
   moments (β ≈ 0.978) and Earth-like ones (β ≈ 3e-4), J = 1″, 1°, 10°, 30°.
2. ``free_motion_series_failure``: the series error at fixed orders (8 and 16) against J, from 1″ up to
   the separatrix along ν = 0 (L in the B-C plane, the product's initial state; the sweep stops where
   :attr:`FreeRotation.mode` stops being short-axis, which along ν = 0 is J = 90°), for the Eros and
   Earth moments, with the product's switch δ = 2 sin²(J/2) = ``SERIES_MAX_DELTA`` as a vertical line;
   and against β from 0 to 0.995 for synthetic moments C/A − 1 = α(1 + β), C/B − 1 = α(1 − β) at
   fixed α, at two J (below and above the switch). A series that cannot be evaluated (the inverse
   transformation diverges, or overflow) is marked at the top of the panel.

Time unit: days, with M = C ω and ω from the catalogue rotation period (moments normalised by C).
CPU times are ``time.process_time`` (one thread), best of a few repeats after a warm-up call.
``quick=True`` makes small versions in a second or two (for the tests).
"""
from __future__ import annotations

import csv
import math
import time
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from functools import partial
from pathlib import Path

import numpy as np

from ephem.bodies.catalogue import get_body
from ephem.base.constants import ARCSEC
from ephem.rotation.free_motion import SERIES_MAX_DELTA

from ._command import chart_app
from .accuracy import chart_job, new_figure as _figure, save_chart

#: Errors below this (radians) are drawn at it (an exact zero has no place on a log axis).
ERROR_FLOOR = 1e-20
#: Where a failed series (no convergence, overflow) is drawn (radians: the largest possible angle).
FAIL_LEVEL = math.pi
#: The product's switch, as an angle: δ = 2 sin²(J/2) = SERIES_MAX_DELTA.
SWITCH_J_DEG = math.degrees(2.0 * math.asin(math.sqrt(0.5 * SERIES_MAX_DELTA)))


@dataclass(frozen=True)
class Settings:
    bodies: tuple[str, ...]
    j_arcsec: tuple[float, ...]
    epochs: int
    wobbles: float
    orders: tuple[int, ...]
    rtols: tuple[float, ...]
    ref_rtol: float
    repeats: int
    fail_orders: tuple[int, ...]
    fail_bodies: tuple[str, ...]
    fail_j_deg: tuple[float, ...]
    fail_epochs: int
    alpha: float
    betas: tuple[float, ...]
    beta_j_deg: tuple[float, ...]


FULL = Settings(
    bodies=("Eros", "Earth"), j_arcsec=(1.0, 3600.0, 36000.0, 108000.0), epochs=1000, wobbles=3.0,
    orders=(1, 2, 4, 8, 12), rtols=(1e-8, 1e-10, 1e-12), ref_rtol=1e-13, repeats=3,
    fail_orders=(8, 16), fail_bodies=("Eros", "Earth"),
    fail_j_deg=(1 / 3600, 10 / 3600, 60 / 3600, 0.1, 0.3, 1.0, 2.0, 5.0, 10.0, 15.0, 20.0, 25.0, 30.0, 35.0,
                40.0, 45.0, 50.0, 55.0, 60.0, 65.0, 70.0, 75.0, 80.0, 85.0, 89.0, 89.9),
    fail_epochs=300, alpha=0.5,
    betas=(0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 0.95, 0.978, 0.99, 0.995),
    beta_j_deg=(20.0, 40.0),
)
QUICK = Settings(
    bodies=("Eros",), j_arcsec=(1.0, 36000.0), epochs=100, wobbles=1.0,
    orders=(1, 2, 4, 8), rtols=(1e-8, 1e-10), ref_rtol=1e-13, repeats=1,
    fail_orders=(8,), fail_bodies=("Eros",), fail_j_deg=(1 / 3600, 1.0, 10.0, 30.0, 60.0, 89.0),
    fail_epochs=60, alpha=0.5, betas=(0.0, 0.5, 0.9, 0.99), beta_j_deg=(20.0,),
)


# --------------------------------------------------------------------------- the computations

def _moments_of(name: str) -> tuple[float, float, float]:
    a, b, c = get_body(name).moments
    return a / c, b / c, 1.0


def _omega(name: str) -> float:
    return get_body(name).spin_rate_rad_per_day


def synthetic_moments(alpha: float, beta: float) -> tuple[float, float, float]:
    """(A, B, C)/C with C/A − 1 = α(1 + β) and C/B − 1 = α(1 − β) (Lara 2014 eq. 2)."""
    return 1.0 / (1.0 + alpha * (1.0 + beta)), 1.0 / (1.0 + alpha * (1.0 - beta)), 1.0


def _initial(M: float, J: float) -> np.ndarray:
    return np.array([0.0, M * math.sin(J), M * math.cos(J)])   # ν = 0, as ephem.rotation.free_motion


def direction_error(m: np.ndarray, ref: np.ndarray) -> float:
    """Largest angle (rad) between the rows of m and ref; NaN if m is not finite."""
    if not np.all(np.isfinite(m)):
        return math.nan
    cross = np.linalg.norm(np.cross(m, ref), axis=1)
    return float(np.arctan2(cross, np.einsum("ij,ij->i", m, ref)).max())


def _numeric(moments, L0: np.ndarray, t: np.ndarray, rtol: float) -> np.ndarray:
    """Body-frame angular momentum by Euler's equations, DOP853 (atol scaled by |L|)."""
    from scipy.integrate import solve_ivp

    A, B, C = moments

    def rhs(_, m):
        w1, w2, w3 = m[0] / A, m[1] / B, m[2] / C
        return [m[1] * w3 - m[2] * w2, m[2] * w1 - m[0] * w3, m[0] * w2 - m[1] * w1]

    M = float(np.linalg.norm(L0))
    sol = solve_ivp(rhs, (t[0], t[-1]), L0, method="DOP853", t_eval=t, rtol=rtol, atol=rtol * M * 1e-3)
    return sol.y.T


def _cpu(fn, repeats: int):
    """(result, best CPU seconds) after a warm-up call."""
    out = fn()
    best = math.inf
    for _ in range(repeats):
        start = time.process_time()
        fn()
        best = min(best, time.process_time() - start)
    return out, best


def _series(moments, order: int):
    from ephem.rotation.sam_series import SamSeriesSolution

    return SamSeriesSolution(moments, order)


def _series_error(sol, L0: np.ndarray, t: np.ndarray, upto: int, ref: np.ndarray) -> float:
    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore", RuntimeWarning)
        try:
            m, _ = sol.propagate(L0, t, upto=upto)
        except (RuntimeError, OverflowError, ZeroDivisionError, ValueError):
            return math.nan
    return direction_error(m, ref)


def _exact_momentum(moments, L0: np.ndarray, t: np.ndarray) -> np.ndarray:
    from ephem.rotation.euler_poinsot import FreeRotation

    return FreeRotation.from_body_momentum(moments, L0).body_momentum(t)


def work_precision_rows(s: Settings) -> list[dict]:
    from ephem.rotation.euler_poinsot import FreeRotation

    rows = []
    for name in s.bodies:
        moments, omega = _moments_of(name), _omega(name)
        sol = _series(moments, max(s.orders))     # built once per body: its cost is not counted
        for j_arcsec in s.j_arcsec:
            J = j_arcsec * ARCSEC
            L0 = _initial(omega, J)
            fr = FreeRotation.from_body_momentum(moments, L0)
            t = np.linspace(0.0, s.wobbles * fr.wobble_period, s.epochs)
            ref, cpu = _cpu(partial(_exact_momentum, moments, L0, t), s.repeats)
            check = direction_error(_numeric(moments, L0, t, s.ref_rtol), ref)
            base = {"body": name, "J_arcsec": j_arcsec, "J_deg": j_arcsec / 3600.0, "mode": fr.mode,
                    "delta": 2.0 * math.sin(0.5 * J) ** 2, "wobble_period_days": fr.wobble_period,
                    "span_days": float(t[-1]), "epochs": s.epochs, "reference_check_rad": check}
            rows.append({**base, "method": "exact", "parameter": "", "cpu_ms": 1e3 * cpu, "error_rad": check})
            for n in s.orders:
                _, cpu = _cpu(partial(sol.propagate, L0, t, upto=n), s.repeats)
                rows.append({**base, "method": "series", "parameter": n, "cpu_ms": 1e3 * cpu,
                             "error_rad": _series_error(sol, L0, t, n, ref)})
            for rtol in s.rtols:
                m, cpu = _cpu(partial(_numeric, moments, L0, t, rtol), s.repeats)
                rows.append({**base, "method": "numeric", "parameter": rtol, "cpu_ms": 1e3 * cpu,
                             "error_rad": direction_error(m, ref)})
    return rows


def _failure_case(sols: dict, moments, omega: float, J: float, s: Settings, extra: dict) -> list[dict]:
    from ephem.rotation.euler_poinsot import FreeRotation

    L0 = _initial(omega, J)
    fr = FreeRotation.from_body_momentum(moments, L0)
    if fr.mode != "short-axis":
        return []
    t = np.linspace(0.0, 3.0 * fr.wobble_period, s.fail_epochs)
    ref = fr.body_momentum(t)
    rows = []
    for n in s.fail_orders:
        sol = sols[n]
        err = _series_error(sol, L0, t, n, ref)
        try:
            with np.errstate(all="ignore"):
                mean = sol.mean_elements(L0, upto=n)
            delta_series = mean.L / (mean.G * math.sqrt(1.0 - sol.params.beta ** 2))
        except (RuntimeError, OverflowError, ValueError):
            delta_series = math.nan
        rows.append({**extra, "J_deg": math.degrees(J), "order": n, "mode": fr.mode,
                     "delta": 2.0 * math.sin(0.5 * J) ** 2, "delta_series": delta_series,
                     "error_rad": err, "failed": int(not math.isfinite(err))})
    return rows


def series_failure_rows(s: Settings) -> list[dict]:
    rows = []
    top = max(s.fail_orders)
    for name in s.fail_bodies:
        moments, omega = _moments_of(name), _omega(name)
        full = _series(moments, top)
        sols = {n: full for n in s.fail_orders}
        beta = full.params.beta
        for jd in s.fail_j_deg:
            rows += _failure_case(sols, moments, omega, math.radians(jd), s,
                                  {"sweep": "J", "moments": name, "alpha": full.params.alpha, "beta": beta})
    for beta in s.betas:
        moments = synthetic_moments(s.alpha, beta)
        full = _series(moments, top)
        sols = {n: full for n in s.fail_orders}
        for jd in s.beta_j_deg:
            rows += _failure_case(sols, moments, 1.0, math.radians(jd), s,
                                  {"sweep": "beta", "moments": f"alpha={s.alpha:g}", "alpha": s.alpha, "beta": beta})
    return rows


# --------------------------------------------------------------------------- files

def read_csv(path: Path) -> list[dict]:
    """Rows of a chart's CSV as dicts of strings (for the docs and the tests)."""
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def _write_csv(path: Path, rows: list[dict]) -> None:
    keys = list(rows[0])
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=keys, lineterminator="\n")
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})


def _save(fig, out_dir: Path, stem: str) -> None:
    save_chart(fig, out_dir, stem, salt="ephem-free-motion")


def _floor(e: float) -> float:
    return FAIL_LEVEL if not math.isfinite(e) else max(e, ERROR_FLOOR)


def _j_label(j_arcsec: float) -> str:
    return f'J = {j_arcsec:g}″' if j_arcsec < 60 else f"J = {j_arcsec / 3600:g}°"


def work_precision(out_dir: Path, s: Settings) -> None:
    rows = work_precision_rows(s)
    _write_csv(out_dir / "free_motion_work_precision.csv", rows)
    nb, nj = len(s.bodies), len(s.j_arcsec)
    fig = _figure(3.1 * nj + 0.6, 3.0 * nb + 0.9)
    axes = fig.subplots(nb, nj, squeeze=False, sharex=True, sharey=True)
    for i, name in enumerate(s.bodies):
        for k, j in enumerate(s.j_arcsec):
            ax = axes[i][k]
            sel = [r for r in rows if r["body"] == name and r["J_arcsec"] == j]
            ser = [r for r in sel if r["method"] == "series"]
            num = [r for r in sel if r["method"] == "numeric"]
            ex = next(r for r in sel if r["method"] == "exact")
            ax.plot([r["cpu_ms"] for r in ser], [_floor(r["error_rad"]) for r in ser], "s-", color="tab:blue",
                    label="series, order N (build excluded)")
            for r in ser:
                ax.annotate(f"{r['parameter']}", (r["cpu_ms"], _floor(r["error_rad"])), textcoords="offset points",
                            xytext=(4, 3), fontsize=7, color="tab:blue")
            ax.plot([r["cpu_ms"] for r in num], [_floor(r["error_rad"]) for r in num], "v-", color="tab:red",
                    label="numeric DOP853, rtol")
            for r in num:
                ax.annotate(f"{r['parameter']:.0e}", (r["cpu_ms"], _floor(r["error_rad"])),
                            textcoords="offset points", xytext=(4, -9), fontsize=7, color="tab:red")
            ax.plot([ex["cpu_ms"]], [_floor(ex["error_rad"])], "*", mfc="none", mec="black", ms=11,
                    label=f"exact (vs DOP853 rtol {s.ref_rtol:.0e})")
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.set_ylim(ERROR_FLOOR / 3, 10.0)
            ax.grid(True, which="major", alpha=0.3)
            mode = sel[0]["mode"]
            ax.set_title(f"{name}, {_j_label(j)} (δ={sel[0]['delta']:.2g}, {mode})", fontsize=9)
            if k == 0:
                ax.set_ylabel("max angle error of L in body frame (rad)")
            if i == nb - 1:
                ax.set_xlabel(f"CPU ms per {s.epochs} epochs")
    axes[0][0].legend(fontsize=7, loc="upper right")
    fig.suptitle(f"Free motion: cost against accuracy ({s.epochs} epochs over {s.wobbles:g} wobble periods; "
                 "reference: exact Euler-Poinsot)", fontsize=10)
    _save(fig, out_dir, "free_motion_work_precision")


def series_failure(out_dir: Path, s: Settings) -> None:
    rows = series_failure_rows(s)
    _write_csv(out_dir / "free_motion_series_failure.csv", rows)
    fig = _figure(11.0, 4.3)
    ax_j, ax_b = fig.subplots(1, 2)
    colours = {"Eros": "tab:orange", "Earth": "tab:green"}
    styles = dict(zip(s.fail_orders, ("o-", "s--", "^:")))
    for name in s.fail_bodies:
        for n in s.fail_orders:
            sel = [r for r in rows if r["sweep"] == "J" and r["moments"] == name and r["order"] == n]
            beta = sel[0]["beta"]
            ok = [r for r in sel if not r["failed"]]
            ax_j.plot([r["J_deg"] for r in ok], [_floor(r["error_rad"]) for r in ok], styles[n],
                      color=colours.get(name, "tab:purple"), ms=4, label=f"{name} (β={beta:.3g}), N={n}")
            bad = [r for r in sel if r["failed"]]
            if bad:
                ax_j.plot([r["J_deg"] for r in bad], [FAIL_LEVEL] * len(bad), "x", color=colours.get(name), ms=7)
    ax_j.axvline(SWITCH_J_DEG, color="black", lw=1)
    ax_j.text(SWITCH_J_DEG * 0.93, 1e-17, f"auto switch\nδ = {SERIES_MAX_DELTA:g}\n(J = {SWITCH_J_DEG:.1f}°)",
              ha="right", fontsize=7)
    ax_j.axhline(FAIL_LEVEL, color="0.6", lw=0.6, ls=":")
    ax_j.set_xscale("log")
    ax_j.set_yscale("log")
    ax_j.set_ylim(ERROR_FLOOR / 3, 30.0)
    ax_j.set_xlabel("J (deg), ν = 0; separatrix at 90°")
    ax_j.set_ylabel("max angle error of L in body frame (rad)")
    ax_j.set_title("Series error against J (× at top: series could not be evaluated)", fontsize=9)
    ax_j.legend(fontsize=7, loc="upper left")
    ax_j.grid(True, alpha=0.3)
    jcols = ("tab:blue", "tab:red", "tab:purple")
    for jc, jd in zip(jcols, s.beta_j_deg):
        for n in s.fail_orders:
            sel = [r for r in rows if r["sweep"] == "beta" and r["J_deg"] == _j_key(jd) and r["order"] == n]
            ok = [r for r in sel if not r["failed"]]
            ax_b.plot([r["beta"] for r in ok], [_floor(r["error_rad"]) for r in ok], styles[n], color=jc, ms=4,
                      label=f"J = {jd:g}° ({'below' if jd <= SWITCH_J_DEG else 'above'} switch), N={n}")
            bad = [r for r in sel if r["failed"]]
            if bad:
                ax_b.plot([r["beta"] for r in bad], [FAIL_LEVEL] * len(bad), "x", color=jc, ms=7)
    eros_beta = _series(_moments_of("Eros"), 1).params.beta
    ax_b.axvline(eros_beta, color="tab:orange", lw=0.8, ls="--")
    ax_b.text(eros_beta - 0.01, 1e-17, f"Eros β = {eros_beta:.3f}", rotation=90, ha="right", fontsize=7)
    ax_b.axhline(FAIL_LEVEL, color="0.6", lw=0.6, ls=":")
    ax_b.set_yscale("log")
    ax_b.set_ylim(ERROR_FLOOR / 3, 30.0)
    ax_b.set_xlim(-0.02, 1.0)
    ax_b.set_xlabel(f"β (synthetic moments, α = {s.alpha:g})")
    ax_b.set_title("Series error against triaxiality β (the auto switch ignores β)", fontsize=9)
    ax_b.legend(fontsize=7, loc="upper left")
    ax_b.grid(True, alpha=0.3)
    fig.suptitle("Where Lara's short-axis series fails (3 wobble periods; reference: exact Euler-Poinsot)",
                 fontsize=10)
    _save(fig, out_dir, "free_motion_series_failure")


def _j_key(jd: float) -> float:
    """J in degrees as stored in the rows (through radians and back)."""
    return math.degrees(math.radians(jd))


def tasks(out_dir: Path, quick: bool = False) -> list[tuple[str, Callable[[], None]]]:
    """The chart jobs, as (label, zero-argument callable); each writes its chart and CSV into ``out_dir``."""
    out_dir = Path(out_dir)
    s = QUICK if quick else FULL
    run = partial(chart_job, out_dir=out_dir, settings=s)
    return [
        (f"free-motion work-precision ({', '.join(s.bodies)}; {len(s.j_arcsec)} J)", run(work_precision)),
        (f"where the series fails (orders {', '.join(map(str, s.fail_orders))})", run(series_failure)),
    ]


app = chart_app(lambda out, quick=False: tasks(out, quick=quick), "docs/free_motion.md",
                "Cost against accuracy of the torque-free solutions (exact, series, numeric); see docs/free_motion.md.",
                "Small versions in seconds.")

if __name__ == "__main__":  # python -m studies.free_motion [--out DIR] [--quick]
    app(prog_name="python -m studies.free_motion")
