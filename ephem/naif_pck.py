"""NAIF SPICE text PCK kernels whose pole reproduces our spin-axis track.

The pole of SPICE's PCK model (NAIF, "PCK Required Reading", section "Orientation models used
by PCK software") is

    RA  = ra0 + ra1 T + ra2 T²  + Σᵢ aᵢ sin θᵢ
    DEC = dec0 + dec1 T + dec2 T² + Σᵢ dᵢ cos θᵢ,     θᵢ = θᵢ₀ + θᵢ₁ T

with T in Julian centuries (TDB) from J2000, angles in degrees; the prime meridian is
W = W0 + W1 d + W2 d² (d in days). Our nutation is periodic in multiples k of the body's
mean anomaly M, which is linear in T, so for each k we write two angles, θ = kM and
θ = kM + 90°: together they carry both the sine and the cosine of kM in RA and in DEC.
The polynomial and the coefficients are a linear least-squares fit to the track served by
:func:`ephem.api.track_arrays` (any rung of the fidelity ladder); the kernel states the
fitting error it reaches (the largest angle between its pole and the track, on epochs between
the fitting samples) beside the model's own estimated error.

The angles go under ``BODYnnn_NUT_PREC_ANGLES`` with nnn the body's own ID for asteroids and
its system barycentre (ID // 100) for a planet, as SPICE looks them up. Frame: our poles are
ICRF; SPICE's J2000 differs from it by the frame bias (~20 mas); as the IAU's kernels do, we
write ICRF poles as J2000 ones. The prime meridian's W0 is 0 (our catalogue has no W0) and W1
comes from the catalogue's rotation period: the pole does not depend on it.
"""
from __future__ import annotations

import datetime as _dt
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .constants import J2000_JD
from .errors import InvalidInputError, NotApplicableError

#: Fitting samples per period of the shortest harmonic kept (well above Nyquist: the fit is exact
#: for a periodic signal, the margin absorbs what the real orbit adds).
SAMPLES_PER_PERIOD = 16
#: Harmonics of M whose pole displacement is below this (degrees, 1 µas) are not written.
SMALLEST_TERM_DEG = 1e-6 / 3600.0
MAX_SAMPLES = 400_000
CHECK_POINTS = 4001


@dataclass(frozen=True)
class PckFit:
    """One body's kernel data and how well it reproduces the track."""

    body: str
    naif_id: int
    angles_id: int
    dataset: str
    model: dict                      # the track's ``model`` object (rung, estimated error, ...)
    start_jd_tdb: float
    stop_jd_tdb: float
    pole_ra: np.ndarray              # [c0, c1, c2] deg, deg/cy, deg/cy²
    pole_dec: np.ndarray
    nut_prec_ra: np.ndarray          # coefficients of sin θᵢ, deg
    nut_prec_dec: np.ndarray         # coefficients of cos θᵢ, deg
    angles: np.ndarray               # (n, 2): θᵢ₀ deg, θᵢ₁ deg/cy
    pm: tuple[float, float, float]   # W0 deg, W1 deg/day, W2
    fit_error_mas: float             # largest angle kernel-track on the check epochs


def _centuries(jd):
    return (np.asarray(jd, dtype=float) - J2000_JD) / 36525.0


def _unit(ra_deg, dec_deg):
    ra, dec = np.radians(ra_deg), np.radians(dec_deg)
    return np.stack([np.cos(dec) * np.cos(ra), np.cos(dec) * np.sin(ra), np.sin(dec)], axis=-1)


def evaluate(fit: PckFit, jd_tdb) -> tuple[np.ndarray, np.ndarray]:
    """RA and Dec (deg) of the kernel's pole at the epochs, by the PCK formulas above."""
    T = _centuries(jd_tdb)
    theta = np.radians(fit.angles[:, 0][:, None] + fit.angles[:, 1][:, None] * T[None, :])
    ra = np.polyval(fit.pole_ra[::-1], T) + fit.nut_prec_ra @ np.sin(theta)
    dec = np.polyval(fit.pole_dec[::-1], T) + fit.nut_prec_dec @ np.cos(theta)
    return ra, dec


def _track(body, t0: float, t1: float, step: float, dataset: str, tolerance_mas, model):
    from . import api

    return api.track_arrays(body, t0, t1, step, dataset, max_samples=MAX_SAMPLES, tolerance_mas=tolerance_mas,
                            model=model)


def fit_body(body, start, stop, dataset: str = "current", tolerance_mas: float | None = None,
             model: str | None = None) -> PckFit:
    """Fit one body's track over [start, stop] (ISO or JD TDB) with the PCK model."""
    from . import api
    from .timeparse import to_jd_tdb

    b = api.resolve_body(body, dataset)
    t0, t1 = to_jd_tdb(start, "start"), to_jd_tdb(stop, "stop")
    if not t1 > t0:
        raise InvalidInputError("stop", f"stop (JD {t1}) must be after start (JD {t0})", b.name)
    if b.naif_id is None:
        raise InvalidInputError("body", "a kernel needs the body's NAIF ID", b.name)
    m = api.model_for(b, dataset)                  # raises NotApplicableError for the Moon
    series = m.nutation
    amp = np.hypot(series.lon_sin, series.lon_cos) * abs(math.sin(m.obliquity)) + np.hypot(series.obl_sin, series.obl_cos)
    keep = series.multiple[np.degrees(amp) > SMALLEST_TERM_DEG].astype(int)
    kmax = int(keep.max()) if keep.size else 0
    period = 2.0 * math.pi / m.mean_motion
    step = min(period / (SAMPLES_PER_PERIOD * max(kmax, 1)), (t1 - t0) / 64.0)
    count = int((t1 - t0) / step) + 1
    if count > MAX_SAMPLES:
        raise InvalidInputError("stop", f"the span needs {count} fitting samples (cap {MAX_SAMPLES}); "
                                "shorten it", b.name)
    ans = _track(b, t0, t1, step, dataset, tolerance_mas, model)
    jd = ans["jd_tdb"]
    T = _centuries(jd)
    ra = np.unwrap(np.radians(ans["pole_ra_deg"]))
    ra = np.degrees(ra)
    dec = ans["pole_dec_deg"]
    # θ = kM and kM + 90°, M = M0 + n (t - t_epoch): θ0 at J2000 and θ1 per century, degrees
    n_deg_cy = math.degrees(m.mean_motion) * 36525.0
    m_j2000 = math.degrees(m.mean_anomaly_at_epoch + m.mean_motion * (J2000_JD - m.orbit_epoch))
    angles = []
    for k in range(1, kmax + 1):
        base = (k * m_j2000) % 360.0
        angles += [(base, k * n_deg_cy), ((base + 90.0) % 360.0, k * n_deg_cy)]
    angles = np.array(angles).reshape(-1, 2)
    theta = np.radians(angles[:, 0][:, None] + angles[:, 1][:, None] * T[None, :])
    poly = np.stack([np.ones_like(T), T, T * T], axis=1)
    # solve in centred, scaled time for conditioning, then map back to powers of T
    ra_coef, ra_nut = _fit(poly, np.sin(theta).T, ra)
    dec_coef, dec_nut = _fit(poly, np.cos(theta).T, dec)
    pm = (0.0, 360.0 / (b.rotation_period_hours / 24.0), 0.0)
    fit = PckFit(b.name, b.naif_id, b.naif_id // 100 if 100 <= b.naif_id <= 999 else b.naif_id, b.dataset,
                 ans["model"], t0, t1, ra_coef, dec_coef, ra_nut, dec_nut, angles, pm, 0.0)
    check = np.linspace(t0, t1, CHECK_POINTS)       # between the fitting samples, not on them
    truth = _track(b, check[0], check[-1], check[1] - check[0], dataset, tolerance_mas, model)
    kra, kdec = evaluate(fit, truth["jd_tdb"])
    got, want = _unit(kra, kdec), _unit(truth["pole_ra_deg"], truth["pole_dec_deg"])
    err = np.arctan2(np.linalg.norm(np.cross(got, want), axis=1), np.einsum("ij,ij->i", got, want))
    fit = PckFit(**{**fit.__dict__, "fit_error_mas": float(np.degrees(err.max()) * 3.6e6)})
    # the kernel's error against the truth is at most the model's estimate plus the fitting error: refuse
    # a kernel beyond the tolerance asked for, or (with none) one the fit spoils by more than the model
    estimate = ans["model"].get("estimated_error_mas")
    limit = estimate if tolerance_mas is None else float(tolerance_mas) - (estimate or 0.0)
    if estimate is not None and fit.fit_error_mas > limit:
        raise NotApplicableError(b.name, (
            f"the PCK model (RA and Dec quadratic in time plus harmonics of M) follows this track only to "
            f"{fit.fit_error_mas:.4g} mas; with the model's own {estimate:.4g} mas that is beyond "
            + ("it" if tolerance_mas is None else f"the tolerance of {tolerance_mas} mas")
            + (" (the pole is near the ICRF pole, where RA is ill-conditioned)" if abs(dec).max() > 80.0 else
               "; shorten the span")))
    return fit


def _fit(poly: np.ndarray, waves: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Least squares y ≈ poly @ c + waves @ a; the columns scaled to unit norm for conditioning."""
    design = np.hstack([poly, waves])
    scale = np.linalg.norm(design, axis=0)
    scale[scale == 0.0] = 1.0
    sol, *_ = np.linalg.lstsq(design / scale, y, rcond=None)
    sol = sol / scale
    return sol[:3], sol[3:]


def _numbers(values) -> str:
    return "( " + "\n    ".join(" ".join(f"{v:.17g}" for v in values[i:i + 4]) for i in range(0, len(values), 4)) + " )"


def _iso(jd: float) -> str:
    from astropy.time import Time

    return Time(jd, format="jd", scale="tdb").isot + " TDB"


def kernel_text(fits: list[PckFit], now: _dt.datetime | None = None) -> str:
    """The text PCK for the fitted bodies."""
    when = (now or _dt.datetime.now(_dt.timezone.utc)).strftime("%Y-%m-%d %H:%M UTC")
    lines = ["KPL/PCK", "", r"\begintext", "",
             "Precession-nutation of the spin axis written by ephem (asteroid precession-nutation service)",
             f"on {when}. Pole: a least-squares fit of ephem's spin-axis track with the PCK model",
             "(RA, DEC quadratic in T plus nutation terms in multiples k of the body's mean anomaly M,",
             "two angles per k, k M and k M + 90 deg, so that both sin and cos of k M appear).",
             "Poles are ICRF, written as J2000 (they differ by the frame bias, about 20 mas), as the",
             "IAU kernels do. W0 = 0 (not modelled: the pole does not depend on W); W1 from the",
             "catalogue's rotation period.", ""]
    for f in fits:
        m = f.model
        est = m.get("estimated_error_mas")
        lines += [f"{f.body} (NAIF ID {f.naif_id}), dataset {f.dataset}:",
                  f"   model        {m.get('name')}" + (f" (order {m['order']})" if m.get("order") is not None else "")
                  + f", axis {m.get('axis')}",
                  f"   estimated error of the model   {est:.4g} mas" if est is not None else
                  "   estimated error of the model   not estimated",
                  f"   fitting error (kernel vs track, max)   {f.fit_error_mas:.4g} mas",
                  f"   error against the true pole   at most {est + f.fit_error_mas:.4g} mas (the two added)"
                  if est is not None else "   error against the true pole   not estimated",
                  f"   valid from   {_iso(f.start_jd_tdb)} (JD {f.start_jd_tdb:.6f} TDB)",
                  f"   valid to     {_iso(f.stop_jd_tdb)} (JD {f.stop_jd_tdb:.6f} TDB)",
                  f"   nutation angles under BODY{f.angles_id}_NUT_PREC_ANGLES ({len(f.angles)} angles)", ""]
    for f in fits:
        n = f.naif_id
        lines += [r"\begindata", "",
                  f"BODY{n}_POLE_RA = {_numbers(f.pole_ra)}",
                  f"BODY{n}_POLE_DEC = {_numbers(f.pole_dec)}",
                  f"BODY{n}_PM = {_numbers(f.pm)}"]
        if len(f.angles):
            lines += [f"BODY{n}_NUT_PREC_RA = {_numbers(f.nut_prec_ra)}",
                      f"BODY{n}_NUT_PREC_DEC = {_numbers(f.nut_prec_dec)}",
                      f"BODY{f.angles_id}_NUT_PREC_ANGLES = {_numbers(f.angles.reshape(-1))}"]
        lines += ["", r"\begintext", ""]
    return "\n".join(lines)


def write_pck(bodies, start, stop, dataset: str = "current", tolerance_mas: float | None = None,
              model: str | None = None) -> tuple[str, list[PckFit]]:
    """Kernel text and fits for one or several bodies over [start, stop]."""
    if isinstance(bodies, (str, int)):
        bodies = [bodies]
    if not bodies:
        raise InvalidInputError("bodies", "name at least one body")
    fits = [fit_body(b, start, stop, dataset, tolerance_mas, model) for b in bodies]
    ids = [f.angles_id for f in fits]
    if len(set(ids)) != len(ids):
        raise InvalidInputError("bodies", "two bodies would share one BODYnnn_NUT_PREC_ANGLES (same system)")
    return kernel_text(fits), fits


def write_pck_file(path, bodies, start, stop, **kwargs) -> list[PckFit]:
    text, fits = write_pck(bodies, start, stop, **kwargs)
    Path(path).write_text(text, encoding="utf-8")
    return fits
