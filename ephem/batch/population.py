"""Precession and nutation of a population of bodies at once: the single-perturber theory vectorised over bodies.

A partition of a catalogue of bodies (one row per body: :data:`INPUT_COLUMNS`) goes through Kinoshita's first-order
theory with exact Hansen coefficients, the model the single-body answers serve by default (``hansen``:
:func:`ephem.forced.precession_nutation.build_model` with ``order=None``), with numpy broadcasting over the bodies: no Python loop per
body. Each step is the single-body one applied to columns (the same functions: ``kinoshita.scaling_factor``,
``geometry.spin_angles``, ``hansen.hansen_exact_many`` grouped by FFT length, ``kinoshita.nutation_coefficients``,
the mean pole's fixed point ``kinoshita.mean_pole`` on the nutation's θ-free sums, made once per row,
``kinoshita.precession_rate``), so the outputs equal
``ephem.answers.requests.precession`` / ``ephem.answers.requests.nutation`` for the same body (tests/batch/test_population.py).

A row the theory cannot take (a missing or impossible value, a slow rotator, an orbit too eccentric for the
Fourier series, a pole normal to the orbit) gets its reason in ``error``, named by its column as the catalogue
names a field, and NaN in the numbers; the other rows are untouched. ``*_sigma`` columns are propagated linearly
(the inputs independent) to ``*_uncertainty`` outputs: forward-mode derivatives through the theory
(:mod:`ephem.batch.tangents`; central differences of σ/100 for the eccentricity, which moves the Hansen
coefficients). With a
:class:`HistorySpec`, each row's obliquity is integrated over the span (the averaged spin equation along the
secular orbit, as :func:`ephem.answers.requests.history` with ``orbit_model="secular"``: a loop per body, seconds each).

Units: angles in degrees at the columns, radians inside; rates in arcsec per Julian year; periods in days.
"""
from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from ..bodies.catalogue import Body, MAX_ANGLE_DEG, MIN_ROTATION_PERIOD_HOURS, Orbit, Pole, spin_rate_rad_per_day
from ..base.centres import CENTER_HILL_AU, CENTER_RADIUS_AU
from ..base.constants import ARCSEC, J2000_JD, JD_RANGE, JULIAN_YEAR_DAYS, MAS
from ..orbit.geometry import icrf_to_ecliptic_matrix, spin_angles, unit_vector
from ..orbit.hansen import exact_available, fft_lengths, hansen_exact_many
from ..bodies.inertia import hd_of_moments, moments_from_ellipsoid
from ..orbit.kepler import mean_motion_rad_per_day
from ..forced.kinoshita import (TERM_FLOOR, exact_series_floor, mean_pole, nutation_coefficients,
                                eccentricity_factor, precession_rate, scaling_factor)
from ..forced.precession_nutation import MIN_SPIN_ORBIT_RATIO
from ..base.budget import prepaid
from ..base.errors import EphemError, InvalidInputError
from ..longterm.averaged_spin import steps_per_sample
from ..longterm.history import MAX_HISTORY_SAMPLES, history_grid, spin_axis_history
from ..sun.family import SunLadder
from ..theory import cost
from .rows import spoil_rows  # noqa: F401 - the core's, re-exported (ephem.answers.batches: pop.spoil_rows)
from .tangents import INERTIA_INPUTS, MEAN_ANOMALY_INPUTS, forward, geometry, hypot, nutation_sums, rowdot

#: The input columns: name -> (unit, meaning). Required: name, the orbit, the pole, the period and one of the
#: three inertia forms (dynamical_ellipticity, else the moments, else the ellipsoid's semi-axes).
INPUT_COLUMNS = {
    "name": ("", "the body's name (any text)"),
    "a_au": ("AU", "osculating heliocentric semi-major axis, ecliptic and equinox J2000"),
    "e": ("", "eccentricity, 0 <= e < 1"),
    "i_deg": ("deg", "inclination to the J2000 ecliptic, 0..180"),
    "node_deg": ("deg", "longitude of the ascending node"),
    "peri_deg": ("deg", "argument of pericentre"),
    "mean_anomaly_deg": ("deg", "mean anomaly at epoch_jd_tdb"),
    "epoch_jd_tdb": ("d", "the elements' epoch, JD TDB"),
    "pole_ra_deg": ("deg", "the spin pole's right ascension, ICRF (the positive, right-hand pole)"),
    "pole_dec_deg": ("deg", "the spin pole's declination, ICRF"),
    "pole_epoch_jd_tdb": ("d", "optional: the pole's epoch, JD TDB (default J2000.0)"),
    "rotation_period_hours": ("h", "sidereal rotation period"),
    "dynamical_ellipticity": ("", "H_d = (C - (A+B)/2)/C, in (0, 0.5]"),
    "moment_a": ("", "principal moment A (any common normalisation), A <= B <= C"),
    "moment_b": ("", "principal moment B"),
    "moment_c": ("", "principal moment C"),
    "axis_a_km": ("km", "semi-axis a of a uniform-density ellipsoid, a >= b >= c"),
    "axis_b_km": ("km", "semi-axis b"),
    "axis_c_km": ("km", "semi-axis c"),
}
REQUIRED = ("name", "a_au", "e", "i_deg", "node_deg", "peri_deg", "mean_anomaly_deg", "epoch_jd_tdb",
            "pole_ra_deg", "pole_dec_deg", "rotation_period_hours")
#: the numeric inputs that may carry a ``<column>_sigma`` (1σ, the column's unit)
SIGMA_INPUTS = tuple(c for c in INPUT_COLUMNS if c not in ("name", "epoch_jd_tdb", "pole_epoch_jd_tdb"))
#: how many of the largest nutation terms (by the pole displacement each can make) the outputs list
LEADING_TERMS = 3
#: the values whose 1σ the outputs carry when the inputs have ``_sigma`` columns
UNCERTAIN = ("obliquity_deg", "dynamical_ellipticity", "scaling_factor_arcsec_per_year",
             "precession_rate_arcsec_per_year")
#: central-difference step, a fraction of each input's σ (as :data:`ephem.forced.uncertainty.STEP_FRACTION`)
STEP_FRACTION = 0.01
MODEL = "hansen"
#: how many nutation coefficients (rows x harmonics) the theory works on at once: 2^15 float64 (256 kB) per array
CHUNK_ELEMENTS = 1 << 15


def _term_columns() -> tuple[str, ...]:
    return tuple(f"nutation_{j}_{what}" for j in range(1, LEADING_TERMS + 1)
                 for what in ("multiple", "period_days", "longitude_amplitude_arcsec", "obliquity_amplitude_arcsec"))


HISTORY_COLUMNS = ("obliquity_min_deg", "obliquity_max_deg", "obliquity_period_years", "history_error")
OUTPUT_COLUMNS = (("name",) + UNCERTAIN + _term_columns() + ("model", "estimated_error_mas")
                  + tuple(f"{k}_uncertainty" for k in UNCERTAIN) + ("error",))


@dataclass(frozen=True)
class HistorySpec:
    """The span of the obliquity history asked for each row: Julian years from J2000.0 TDB."""

    start_year: float
    stop_year: float
    step_years: float


# --------------------------------------------------------------------------- inputs and their checks

def _floats(columns: Mapping, key: str, n: int) -> np.ndarray:
    """A numeric column as floats (NaN where absent, empty or not a number)."""
    if key not in columns:
        return np.full(n, np.nan)
    col = np.asarray(columns[key])
    if col.dtype.kind in "fiub":
        return col.astype(float)
    out = np.full(n, np.nan)
    for j, v in enumerate(col):            # text columns (CSV read as strings): parse, NaN where not a number
        try:
            out[j] = float(v)
        except (TypeError, ValueError):
            pass
    return out


def _numbers(columns: Mapping, n_rows: int) -> dict[str, np.ndarray]:
    """The numeric inputs as float columns (NaN where absent or not a number), the pole's epoch J2000.0 where
    the row gives none."""
    x = {key: _floats(columns, key, n_rows) for key in INPUT_COLUMNS if key != "name"}
    x["pole_epoch_jd_tdb"] = np.where(np.isfinite(x["pole_epoch_jd_tdb"]), x["pole_epoch_jd_tdb"], J2000_JD)
    return x


class _Errors:
    """The first reason found for each row (later checks do not overwrite it)."""

    def __init__(self, n: int):
        self.reason = np.full(n, "", dtype=object)
        self._free = np.ones(n, dtype=bool)      # the rows without a reason (cheaper than comparing the text)

    def add(self, bad: np.ndarray, message) -> None:
        new = np.asarray(bad) & self._free
        for j in np.nonzero(new)[0]:       # only the bad rows are formatted
            self.reason[j] = message(j) if callable(message) else message
            self._free[j] = not self.reason[j]

    @property
    def ok(self) -> np.ndarray:
        return self._free.copy()


def _inertia(x: dict, errors: _Errors) -> np.ndarray:
    """H_d per row from the first inertia form the row gives (dynamical_ellipticity, else the moments, else the
    ellipsoid's semi-axes), with the catalogue's checks."""
    hd = np.full(x["a_au"].shape, np.nan)
    given = np.isfinite(x["dynamical_ellipticity"])
    errors.add(given & ~((x["dynamical_ellipticity"] > 0.0) & (x["dynamical_ellipticity"] <= 0.5)),
               lambda j: f"dynamical_ellipticity: must lie in (0, 0.5], got {x['dynamical_ellipticity'][j]:.10g}")
    hd[given] = x["dynamical_ellipticity"][given]
    A, B, C = x["moment_a"], x["moment_b"], x["moment_c"]
    moments = ~given & np.isfinite(A) & np.isfinite(B) & np.isfinite(C)
    with np.errstate(invalid="ignore", divide="ignore"):
        errors.add(moments & ~((A > 0.0) & (A <= B) & (B <= C) & (C <= A + B)),
                   lambda j: f"moment_a, moment_b, moment_c: must satisfy 0 < A <= B <= C <= A + B, got "
                             f"{A[j]:.10g}, {B[j]:.10g}, {C[j]:.10g}")
        hd = np.where(moments, hd_of_moments(A, B, C), hd)
    a, b, c = x["axis_a_km"], x["axis_b_km"], x["axis_c_km"]
    axes = ~given & ~moments & np.isfinite(a) & np.isfinite(b) & np.isfinite(c)
    errors.add(axes & ~((a >= b) & (b >= c) & (c > 0.0)),
               lambda j: f"axis_a_km, axis_b_km, axis_c_km: must satisfy a >= b >= c > 0, got {a[j]:.10g}, {b[j]:.10g}, "
                         f"{c[j]:.10g}")
    with np.errstate(invalid="ignore", divide="ignore"):
        hd = np.where(axes, hd_of_moments(*moments_from_ellipsoid(a, b, c)), hd)
    errors.add(~given & ~moments & ~axes, "inertia: give dynamical_ellipticity, or moment_a, moment_b and "
                                          "moment_c, or axis_a_km, axis_b_km and axis_c_km")
    return hd


def _check(x: dict, errors: _Errors) -> None:
    """The catalogue's checks of a body (ephem.bodies.catalogue.Orbit, Pole, Body), per row and by column name."""
    for key in REQUIRED[1:]:
        errors.add(~np.isfinite(x[key]), f"{key}: missing or not a finite number")
    a, e, i = x["a_au"], x["e"], x["i_deg"]
    with np.errstate(invalid="ignore"):
        errors.add(~(a > 0.0), lambda j: f"a_au: semi-major axis must be positive, got {a[j]:.10g}")
        errors.add(~((e >= 0.0) & (e < 1.0)), lambda j: f"e: eccentricity must satisfy 0 <= e < 1 (a bound orbit), "
                                                        f"got {e[j]:.10g}")
        errors.add(~((i >= 0.0) & (i <= 180.0)), lambda j: f"i_deg: inclination must lie in [0, 180] deg, got {i[j]:.10g}")
        errors.add(a * (1.0 - e) <= CENTER_RADIUS_AU["Sun"],
                   lambda j: f"a_au: the pericentre a(1 - e) = {a[j] * (1 - e[j]):.6g} AU lies inside the Sun")
        errors.add(a > CENTER_HILL_AU["Sun"], lambda j: f"a_au: a = {a[j]:.6g} AU is not bound to the Sun")
        for key in ("node_deg", "peri_deg", "mean_anomaly_deg", "pole_ra_deg"):    # as catalogue.check_angle
            errors.add(np.abs(x[key]) > MAX_ANGLE_DEG,
                       lambda j, key=key: f"{key}: an angle must lie within ±{MAX_ANGLE_DEG:g} deg: beyond it its "
                                          "remainder modulo 360 deg loses the digits the answer needs; reduce it "
                                          f"modulo 360, got {float(x[key][j])!r}")
        errors.add(~(np.abs(x["pole_dec_deg"]) <= 90.0),
                   lambda j: f"pole_dec_deg: declination must lie in [-90, 90] deg, got {x['pole_dec_deg'][j]:.10g}")
        errors.add(~(x["rotation_period_hours"] >= MIN_ROTATION_PERIOD_HOURS),
                   lambda j: f"rotation_period_hours: must be at least {MIN_ROTATION_PERIOD_HOURS:g} h, got "
                             f"{x['rotation_period_hours'][j]:.10g}")
        lo, hi = JD_RANGE
        for key in ("epoch_jd_tdb", "pole_epoch_jd_tdb"):
            errors.add(~((x[key] > lo) & (x[key] < hi)),
                       lambda j, key=key: f"{key}: Julian date {x[key][j]} is outside ({lo:g}, {hi:g})")
        errors.add(~exact_available(np.where(errors.ok, e, 0.0)),
                   lambda j: f"e: not applicable: e = {e[j]:.6g} is too close to 1 for the Fourier series of the "
                             f"solar torque in the mean anomaly")


# --------------------------------------------------------------------------- the theory over columns

def _theory(x: dict, ok: np.ndarray, errors: _Errors | None, state: dict | None = None) -> dict:
    """The outputs for the rows ``ok`` of the inputs ``x`` (columns of floats, radians where the model wants
    them converted here); the others NaN. ``errors``: where a row's theory-level reason goes (None: a perturbed
    evaluation of the uncertainties, whose rejected rows are only NaN). ``state`` (:func:`_sigma_state`): where
    the mean pole's sums go for the uncertainties' derivatives (:func:`ephem.batch.tangents.forward`)."""
    n_rows = ok.size
    out = {k: np.full(n_rows, np.nan) for k in UNCERTAIN + ("_estimate",)}
    terms = {k: np.full(n_rows, np.nan) for k in _term_columns()}
    rows = np.nonzero(ok)[0]
    if rows.size == 0:
        return {**out, **terms}
    hd = x["_hd"][rows]
    n = mean_motion_rad_per_day(x["a_au"][rows])
    omega = spin_rate_rad_per_day(x["rotation_period_hours"][rows])
    slow = omega / n < MIN_SPIN_ORBIT_RATIO
    K = scaling_factor(n, omega, hd)
    s_ecl = unit_vector(np.radians(x["pole_ra_deg"][rows]), np.radians(x["pole_dec_deg"][rows])) @ \
        icrf_to_ecliptic_matrix().T
    eps, theta, _, _ = spin_angles(s_ecl, np.radians(x["i_deg"][rows]), np.radians(x["node_deg"][rows]),
                                   np.radians(x["peri_deg"][rows]))
    normal = ~np.isfinite(theta)
    if errors is not None:
        errors.add(_scatter(rows, slow, n_rows),
                   lambda j: f"rotation_period_hours: not applicable: the rotation is too slow for the theory, which "
                             f"averages the torque over it (needs omega/n >= {MIN_SPIN_ORBIT_RATIO:g})")
        errors.add(_scatter(rows, normal & ~slow, n_rows),
                   "pole_ra_deg, pole_dec_deg: the spin axis is normal to the orbit (obliquity 0 or 180 deg): the "
                   "equinox is undefined")
    good = ~slow & ~normal
    rows, hd, n, K, eps, theta = rows[good], hd[good], n[good], K[good], eps[good], theta[good]
    e = x["e"][rows]
    m_t0 = np.radians(x["mean_anomaly_deg"][rows]) + n * (x["pole_epoch_jd_tdb"][rows] - x["epoch_jd_tdb"][rows])
    per_year = JULIAN_YEAR_DAYS / ARCSEC
    for group, k, c0_group, c2_group, s2_group in hansen_exact_many(e):
        kk = k[1:].astype(float)
        # the group's rows in chunks of CHUNK_ELEMENTS coefficients: the (rows, k) temporaries then stay in the cache
        # (4-5x faster than whole groups); every number is the same (the work is row by row)
        step = max(1, CHUNK_ELEMENTS // kk.size)
        for start in range(0, group.size, step):
            g = group[start:start + step]
            c0, c2, s2 = (h[start:start + step, 1:] for h in (c0_group, c2_group, s2_group))
            phase = np.outer(m_t0[g], kk)
            skm, ckm = np.sin(phase), np.cos(phase)
            # the nutation at the pole epoch from its θ-free sums A, B, C (tangents.nutation_sums): the sums of
            # nutation_coefficients regrouped (a few 1e-16 relative), made once; the mean pole's passes are then
            # numbers per row
            sk, ck = skm / kk, ckm / kk
            sums = (rowdot(c0, sk), rowdot(c2, sk), rowdot(s2, ck))
            cg = 0.5 * K[g] / n[g]
            last = {}

            def nutation_at_pole_epoch(eps_trial, theta_trial):
                last["pole"] = eps_trial, theta_trial
                return nutation_sums(cg, eps_trial, theta_trial, *sums)

            eps_mean = mean_pole(eps[g], theta[g], nutation_at_pole_epoch)[0]
            # the series of the last pass (the mean pole it was made at), as the single-body model keeps it
            eps_trial, theta_trial = last["pole"]
            lon_s, lon_c, obl_s, obl_c = nutation_coefficients(K[g, None], n[g, None], eps_trial[:, None],
                                                               theta_trial[:, None], kk, c0, c2, s2)
            target = rows[g]
            out["obliquity_deg"][target] = np.degrees(eps_mean)
            out["dynamical_ellipticity"][target] = hd[g]
            out["scaling_factor_arcsec_per_year"][target] = K[g] * per_year
            out["precession_rate_arcsec_per_year"][target] = precession_rate(K[g], eps_mean, e[g], None) * per_year
            out["_estimate"][target] = _terms_and_floor(terms, target, kk, n[g], eps_mean, lon_s, lon_c, obl_s,
                                                        obl_c)
            if state is not None:       # for the uncertainties' derivatives (tangents.forward): the sums, and in M
                state["sums"][target] = np.stack(sums, axis=-1)
                want = state["m_rows"][target]
                if want.any():
                    state["dsums"][target[want]] = np.stack([rowdot(c0[want], ckm[want]), rowdot(
                        c2[want], ckm[want]), -rowdot(s2[want], skm[want])], axis=-1)
    return {**out, **terms}


def _terms_and_floor(terms: dict, target, k, n, eps, lon_s, lon_c, obl_s, obl_c) -> np.ndarray:
    """The :data:`LEADING_TERMS` largest terms of each row by the pole displacement each can make
    (``kinoshita.pole_displacements``: |sin ε| |Δψ| + |Δε|), with the paper's amplitudes (Table 5's Amp: in
    longitude (Sin² + Cos²)^½ sin ε, in obliquity (Sin² + Cos²)^½), in arcsec, and periods in days; returns each
    row's estimate as the single-body answer gives it (:func:`kinoshita.exact_series_floor`, radians): the
    trailing harmonics whose four coefficients are under TERM_FLOOR (which the single-body series drops), and
    the rounding of the others."""
    lon, obl = hypot(lon_s, lon_c) * np.abs(np.sin(eps))[:, None], hypot(obl_s, obl_c)
    disp = lon + obl
    # the first LEADING_TERMS of a stable sort by decreasing displacement: the largest, ties to the lowest k
    # (argmax takes the first), NaN last, as np.argsort(-disp, kind="stable") orders them
    score = np.where(np.isnan(disp), -1.0, disp)
    pick = np.arange(disp.shape[0])
    for j in range(min(LEADING_TERMS, disp.shape[1])):
        col = np.argmax(score, axis=1)
        score[pick, col] = -np.inf
        terms[f"nutation_{j + 1}_multiple"][target] = k[col]
        terms[f"nutation_{j + 1}_period_days"][target] = 2.0 * math.pi / (k[col] * n)
        terms[f"nutation_{j + 1}_longitude_amplitude_arcsec"][target] = lon[pick, col] / ARCSEC
        terms[f"nutation_{j + 1}_obliquity_amplitude_arcsec"][target] = obl[pick, col] / ARCSEC
    big = np.maximum(np.maximum(np.abs(lon_s), np.abs(lon_c)), np.maximum(np.abs(obl_s), np.abs(obl_c))) >= TERM_FLOOR
    width = big.shape[1]
    last = np.where(big.any(axis=1), width - np.argmax(big[:, ::-1], axis=1), 0)
    tail = np.where(np.arange(width)[None, :] >= last[:, None], disp, 0.0).sum(axis=1)
    return exact_series_floor(tail, disp.sum(axis=1) - tail)


def _scatter(rows: np.ndarray, mask: np.ndarray, n_rows: int) -> np.ndarray:
    full = np.zeros(n_rows, dtype=bool)
    full[rows[mask]] = True
    return full


# --------------------------------------------------------------------------- the public entry

def evaluate(columns: Mapping, history: HistorySpec | None = None) -> dict[str, np.ndarray]:
    """The outputs (:data:`OUTPUT_COLUMNS`, plus :data:`HISTORY_COLUMNS` with ``history``) of a partition.

    ``columns``: {column: 1-D array} of one partition (:data:`INPUT_COLUMNS`, optional ``<column>_sigma``; text
    columns are parsed, absent or unparsable numbers are NaN). Returns 1-D arrays of the same length; a row the
    theory cannot take has its reason in ``error`` and NaN in the numbers.
    """
    names = np.asarray(columns.get("name", []), dtype=object)
    n_rows = len(names) if "name" in columns else len(next(iter(columns.values()), []))
    names = np.array(["" if v is None else v if isinstance(v, str) else str(v) for v in names], dtype=object) \
        if "name" in columns else names
    x = _numbers(columns, n_rows)
    errors = _Errors(n_rows)
    if "name" not in columns:
        names = np.full(n_rows, "", dtype=object)
    errors.add(np.array([not isinstance(v, str) or not v for v in names], dtype=bool).reshape(n_rows),
               "name: missing (every body needs a name)")
    # extreme inputs (axes of 1e200 km) overflow on their way to an error: the row's checks catch what is not
    # finite; numpy's warnings about it are not the caller's business
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        _check(x, errors)
        x["_hd"] = _inertia(x, errors)
        errors.add(~np.isfinite(x["_hd"]), "inertia: H_d is not a finite number for these values")
        state = _sigma_state(columns, n_rows) if sigma_inputs(columns) else None
        result = _theory(x, errors.ok, errors, state)
        errors.add(~np.all([np.isfinite(result[k]) for k in UNCERTAIN], axis=0),
                   "the theory's values are not finite numbers for these inputs")
        result.update(_uncertainties(columns, x, errors.ok, state))
    bad = ~errors.ok
    for key in UNCERTAIN + _term_columns():
        result[key][bad] = np.nan
    out = {"name": names.astype(str)}
    out.update({k: result[k] for k in UNCERTAIN + _term_columns()})
    out["model"] = np.where(bad, "", MODEL)
    # the single-body answer's estimate of this model, the truncation alone (model.estimate_covers): exact Hansen
    # coefficients' floor, never 0 (issue 29); the first-order theory's own error is a track's (docs/accuracy.md)
    out["estimated_error_mas"] = np.where(bad, np.nan, result["_estimate"] / MAS)
    out.update({f"{k}_uncertainty": result[f"{k}_uncertainty"] for k in UNCERTAIN})
    out["error"] = errors.reason.astype(str)
    if history is not None:
        out.update(_histories(columns, x, errors.ok, history))
    return out


def _uncertainties(columns: Mapping, x: dict, ok: np.ndarray, state: dict) -> dict:
    """Linear 1σ of :data:`UNCERTAIN` from the ``<column>_sigma`` columns given, the inputs independent: σ_out² =
    Σ (∂out/∂in σ_in)². The derivatives are forward-mode through the theory (:func:`ephem.batch.tangents.forward`:
    exact, the rows not evaluated again), but for :data:`DIFFERENCED_INPUTS` (central differences of
    :data:`STEP_FRACTION` σ). NaN where a row has no σ, or where a step of σ/100 leaves the theory's domain
    (e ± σ/100 beyond [0, 1), a pole stepped onto the orbit normal: the σ is unknown rather than a guess; the
    derivatives are checked at the same steps, :func:`_outside`)."""
    n_rows = ok.size
    var = {k: np.zeros(n_rows) for k in UNCERTAIN}
    any_sigma, unknown = np.zeros(n_rows, dtype=bool), np.zeros(n_rows, dtype=bool)
    for key in SIGMA_INPUTS:
        sigma = _floats(columns, f"{key}_sigma", n_rows) if f"{key}_sigma" in columns else np.full(n_rows, np.nan)
        has = ok & np.isfinite(sigma) & (sigma > 0.0)
        if not has.any():
            continue
        any_sigma |= has
        rows = np.nonzero(has)[0]
        if key in DIFFERENCED_INPUTS:
            h = np.where(has, STEP_FRACTION * sigma, 0.0)
            ends = []
            for sign in (1.0, -1.0):
                moved = dict(x)
                moved[key] = x[key] + sign * h
                inside = _Errors(n_rows)
                _check(moved, inside)
                moved["_hd"] = _inertia(moved, inside) if key in INERTIA_INPUTS else x["_hd"]
                unknown |= has & ~inside.ok
                ends.append(_theory(moved, has & inside.ok, None))
            with np.errstate(invalid="ignore"):
                slopes = {k: (ends[0][k][rows] - ends[1][k][rows]) / (2.0 * h[rows]) for k in UNCERTAIN}
        else:
            unknown[rows] |= _outside(x, rows, key, STEP_FRACTION * sigma[rows])
            per_year = (1.0, 1.0, JULIAN_YEAR_DAYS / ARCSEC, JULIAN_YEAR_DAYS / ARCSEC)     # K, ψ̇ in rad/day
            slopes = {k: d * unit for k, d, unit in zip(UNCERTAIN, forward(
                {k: v[rows] for k, v in x.items()}, state["sums"][rows], state["dsums"][rows], key), per_year)}
        for k in UNCERTAIN:
            term = slopes[k] * sigma[rows]
            unknown[rows[~np.isfinite(term)]] = True
            var[k][rows] += np.where(np.isfinite(term), term, 0.0) ** 2
    return {f"{k}_uncertainty": np.where(any_sigma & ~unknown, np.sqrt(var[k]), np.nan) for k in UNCERTAIN}


def _sigma_state(columns: Mapping, n_rows: int) -> dict:
    """Where :func:`_theory` leaves the mean pole's sums A, B, C per row (and their derivatives in M for the rows
    with a σ of a or of the mean anomaly, which move M(t0)) for :func:`ephem.batch.tangents.forward`."""
    m_rows = np.zeros(n_rows, dtype=bool)
    for key in MEAN_ANOMALY_INPUTS:
        sigma = _floats(columns, f"{key}_sigma", n_rows)
        m_rows |= np.isfinite(sigma) & (sigma > 0.0)
    return {"sums": np.full((n_rows, 3), np.nan), "dsums": np.full((n_rows, 3), np.nan), "m_rows": m_rows}


#: the inputs whose σ goes by central differences: they move the Hansen coefficients (a new FFT per step)
DIFFERENCED_INPUTS = ("e",)


def _outside(x: dict, rows: np.ndarray, key: str, h: np.ndarray) -> np.ndarray:
    """Whether ``key`` stepped by ± ``h`` takes each of ``rows`` out of the theory's domain, as a central
    difference's evaluations find it: the row's checks, a slow rotation, a pole on the orbit normal; or h = 0 (a σ
    whose hundredth underflows: no step to take)."""
    sub = {k: v[rows] for k, v in x.items()}
    out = h == 0.0
    for sign in (1.0, -1.0):
        moved = dict(sub)
        moved[key] = sub[key] + sign * h
        inside = _Errors(rows.size)
        _check(moved, inside)
        if key in INERTIA_INPUTS:
            out |= ~np.isfinite(_inertia(moved, inside))
        out |= ~inside.ok
        if key in ("a_au", "rotation_period_hours"):      # the other checks pass as the row's own did
            n = mean_motion_rad_per_day(moved["a_au"])
            out |= spin_rate_rad_per_day(moved["rotation_period_hours"]) / n < MIN_SPIN_ORBIT_RATIO
        elif key in ("pole_ra_deg", "pole_dec_deg", "i_deg", "node_deg", "peri_deg"):
            out |= ~np.isfinite(geometry(moved)[1])
    return out


def _histories(columns: Mapping, x: dict, ok: np.ndarray, spec: HistorySpec) -> dict:
    """Each good row's obliquity range and dominant period over the span (ephem.longterm.history.spin_axis_history,
    as ephem.answers.requests.history serves it, on the secular orbit)."""

    n_rows = ok.size
    out = {k: np.full(n_rows, np.nan) for k in HISTORY_COLUMNS[:3]}
    reason = np.full(n_rows, "", dtype=object)
    names = np.asarray(columns.get("name", [""] * n_rows), dtype=object)
    for j in np.nonzero(ok)[0]:          # an integration per body: seconds each, the loop is the work
        try:
            body = Body(name=str(names[j]), orbit=Orbit(x["a_au"][j], x["e"][j], x["i_deg"][j], x["node_deg"][j],
                                                         x["peri_deg"][j], x["mean_anomaly_deg"][j],
                                                         x["epoch_jd_tdb"][j], body=str(names[j])),
                        pole=Pole(x["pole_ra_deg"][j], x["pole_dec_deg"][j], x["pole_epoch_jd_tdb"][j]),
                        rotation_period_hours=x["rotation_period_hours"][j],
                        dynamical_ellipticity=float(x["_hd"][j]))
            with prepaid():          # batch_cost charged every history before the first
                # the rows are fast rotators about the Sun (omega/n >= MIN_SPIN_ORBIT_RATIO, checked above): the
                # single-perturber family is the one ephem.families.theory_for gives them
                h = spin_axis_history(body, SunLadder(body, body.perturbers), spec.start_year, spec.stop_year,
                                      spec.step_years, orbit_model="secular")
        except EphemError as exc:
            reason[j] = f"history: {exc}"
            continue
        eps = np.degrees(h.history.obliquity)
        out["obliquity_min_deg"][j], out["obliquity_max_deg"][j] = eps.min(), eps.max()
        out["obliquity_period_years"][j] = crossing_period(h.years, eps)
    return {**out, "history_error": reason.astype(str)}


def batch_cost(rows: int, history: HistorySpec | None = None, sigma_inputs: int = 0, columns: Mapping | None = None):
    """What :func:`evaluate` will cost for ``rows`` bodies (:class:`ephem.base.budget.Cost`, before the work).

    With the partition's ``columns``, each row costs what it asks for, by the single-body formulas of
    :mod:`ephem.theory.cost`: the exact Hansen coefficients of its own eccentricity, an FFT whose length grows like
    (1 - e²)^(-3/2) (128 points at e = 0.1, 262 144 at 0.99: 0.19 s a row), grouped as :func:`evaluate` groups
    them (:func:`ephem.theory.cost.population`); with ``history``, its integration from its pole's epoch through the span
    (:func:`ephem.theory.cost.spin_history`, as :func:`ephem.longterm.history.history_cost` counts it) and the first-order model
    and nutation extremes its secular spin reads (:func:`ephem.theory.cost.hansen_build`,
    :func:`ephem.theory.cost.half_peak_to_peak`: seconds a row at e = 0.95). A row the checks refuse costs its fixed part
    only. Without ``columns`` (``ephem batch``'s note, made before any partition is read), every row is priced at
    the low eccentricities of a main-belt population, which the fixed part covers.
    """

    ok = x = None
    groups = []
    if columns is not None:
        x, ok = _screened(columns, rows)
        good = np.nonzero(ok)[0]
        counts = fft_lengths(x["e"][good])
        for n in np.unique(counts):
            members = good[counts == n]
            worst = int(members[np.argmax(x["e"][members])])    # the row whose eccentricity sets the group's K
            groups.append((members.size, int(n), cost.harmonics(float(x["e"][worst]), None)[1], f"rows[{worst}].e"))
    total = cost.population(rows, sigma_inputs, groups, None if columns is None else
                            sum(f"{k}_sigma" in columns for k in DIFFERENCED_INPUTS))
    if history is None or not rows:
        return total
    epochs = history_epochs(history)
    lo, hi = min(history.start_year, history.stop_year), max(history.start_year, history.stop_year)
    # the integration's length is set by the end of the span farther from the pole's epoch: that field is named
    far = "start_year" if -lo > hi else "stop_year"     # (from J2000.0 until a row's pole says otherwise)
    if columns is None:     # the pole at J2000.0
        span = max(hi, 0.0) - min(lo, 0.0)
        one = cost.spin_history(span, epochs)
        return total + cost.Cost((cost.Part(far, f"{rows} histories, each integrated over {span:.4g} years",
                                            rows * one.cpu_s, one.memory_mb),))
    # each history integrates from its pole's epoch to the farthest end of the span (ephem.longterm.history.history_cost),
    # after its secular spin has built the row's first-order model and its nutation's extremes (the large step of
    # an eccentric row): the rows one after another, so the CPU adds up and the memory is the largest row's
    spin_cpu = model_cpu = spin_mb = model_mb = 0.0
    costliest, costliest_cpu, widest = "rows", -1.0, 0.0
    for j in np.nonzero(ok)[0]:
        t0 = (x["pole_epoch_jd_tdb"][j] - J2000_JD) / JULIAN_YEAR_DAYS
        span = max(hi, t0) - min(lo, t0)
        if span > widest:
            far = "start_year" if t0 - lo > hi - t0 else "stop_year"
        (e, a, hd), w = (float(x[c][j]) for c in ("e", "a_au", "_hd")), spin_rate_rad_per_day(float(x["rotation_period_hours"][j]))
        # the splitting's steps from the row's precession constant α = (K/2) (1 - e²)^(-3/2), rad/yr
        alpha = 0.5 * scaling_factor(mean_motion_rad_per_day(a), w, hd) * eccentricity_factor(e) * JULIAN_YEAR_DAYS
        spin, k = cost.spin_history(span, epochs, steps_per_sample(alpha)), cost.spin_harmonics(e, a, hd, w)
        model = cost.Cost((cost.hansen_build(e, None), cost.half_peak_to_peak(e, None, k)))
        spin_cpu, model_cpu = spin_cpu + spin.cpu_s, model_cpu + model.cpu_s
        spin_mb, model_mb = max(spin_mb, spin.memory_mb), max(model_mb, model.memory_mb)
        widest = max(widest, span)
        if model.cpu_s > costliest_cpu:
            costliest, costliest_cpu = f"rows[{j}].e", model.cpu_s
    count = int(np.count_nonzero(ok))
    return total + cost.Cost((
        cost.Part(far, f"{count} histories, each integrated over up to {widest:.4g} years from its pole's epoch",
                  spin_cpu, spin_mb),
        cost.Part(costliest, f"the first-order model and nutation extremes of {count} bodies (their secular spin)",
                  model_cpu, model_mb)))


def history_epochs(spec: HistorySpec) -> int:
    """The epochs of every row's history over ``spec``, validated as each history validates them
    (:func:`ephem.longterm.history.history_grid`, each field named in its error), so that a bad span is refused once,
    before any row, instead of in every row."""

    try:
        return int(history_grid(spec.start_year, spec.stop_year, spec.step_years).size)
    except OverflowError:   # a step so small that the count of epochs is not even a finite number
        raise InvalidInputError("step_years", f"gives more than {MAX_HISTORY_SAMPLES} epochs over "
                                f"[{spec.start_year:g}, {spec.stop_year:g}] (a step of {spec.step_years!r} years)"
                                ) from None


def _screened(columns: Mapping, n_rows: int) -> tuple[dict[str, np.ndarray], np.ndarray]:
    """The numeric inputs (with ``_hd``, H_d from the row's inertia form) and the rows that pass the checks:
    those that reach the theory (what :func:`batch_cost` prices)."""
    x = _numbers(columns, n_rows)
    errors = _Errors(n_rows)
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        _check(x, errors)
        x["_hd"] = _inertia(x, errors)
    return x, errors.ok & np.isfinite(x["_hd"])


def sigma_inputs(columns: Mapping) -> int:
    """How many inputs carry a ``_sigma`` column (each costs two more evaluations)."""
    return sum(1 for key in SIGMA_INPUTS if f"{key}_sigma" in columns)


def crossing_period(years: np.ndarray, values: np.ndarray) -> float:
    """The mean period (years) from the crossings of the series' mean, interpolated linearly: twice the mean gap
    between crossings; NaN with fewer than three."""
    y = np.asarray(values, float) - float(np.mean(values))
    t = np.asarray(years, float)
    idx = np.flatnonzero(np.signbit(y[:-1]) != np.signbit(y[1:]))
    if idx.size < 3:
        return float("nan")
    tc = t[idx] - y[idx] * (t[idx + 1] - t[idx]) / (y[idx + 1] - y[idx])
    return float(2.0 * (tc[-1] - tc[0]) / (tc.size - 1))
