"""The library's public answers: plain dicts with the contract's keys and units.

The CLI and the HTTP service both render these; the science stays in
:mod:`ephem.model` and below. Angles in degrees, precession and nutation in
arcseconds, rates per Julian year, times as JD TDB.
"""
from __future__ import annotations

import math
import time
from functools import lru_cache

import numpy as np

from .catalogue import DEFAULT_DATASET, Body, get_body, load_catalogue, load_references
from .constants import ARCSEC, JULIAN_YEAR_DAYS, MAS
from .errors import InvalidInputError
from .hansen import LAPLACE_LIMIT
from .ladder import AXES, RUNGS, Ladder, cached_model, truncation_bound
from .model import MIN_SPIN_ORBIT_RATIO, PrecessionNutation
from .timeparse import to_jd_tdb
from .units import in_unit, with_units

#: Highest e-power order served: the exact-rational series costs ~0.7 s to build at 30 and grows
#: steeply beyond (a request could tie up a worker); exact Hansen coefficients have no such limit.
MAX_ORDER = 30
#: Default cap on the number of epochs in one track.
MAX_TRACK_SAMPLES = 1_000_000
#: Obliquity within this many degrees of 90: ψ̇ ∝ cos ε is small and poorly determined.
NEAR_RIGHT_ANGLE_DEG = 2.0

THEORY = ("Kinoshita (1977) forced precession-nutation in the solar torque, as in Petit, Souchay & Lhotka (2014), "
          "on the fidelity ladder of ephem.ladder")
#: What every rung assumes, and what each drops besides (see :mod:`ephem.ladder`).
ASSUMPTIONS = [
    "rigid body; figure, rotation and angular-momentum axes coincide (free wobble J = 0)",
    "torque averaged over the rotation; triaxial P22 term of the potential dropped",
    "single perturber: the orbit's centre",
]
RUNG_ASSUMPTIONS = {
    "secular": ["no nutation", "fixed Keplerian orbit (osculating elements at their epoch)"],
    "series": ["first order in the torque", "Hansen coefficients truncated at a power of e",
               "fixed Keplerian orbit (osculating elements at their epoch)"],
    "hansen": ["first order in the torque: the equinox drift is not fed back into the nutation phases",
               "fixed Keplerian orbit (osculating elements at their epoch)"],
    "second_order": ["second order in the torque", "fixed Keplerian orbit (osculating elements at their epoch)"],
    "numerical": ["fixed Keplerian orbit (osculating elements at their epoch)"],
    "real_orbit": ["orbit from DE421 (planets) or integrated under the DE421 planets (asteroids)"],
}
#: What each rung of the fidelity ladder drops (see :mod:`ephem.ladder`).
RUNG_DESCRIPTIONS = {
    "secular": "precession only: no nutation",
    "series": "Kinoshita-Cayley nutation, Hansen coefficients as e-power series truncated at e^order",
    "hansen": "Kinoshita-Cayley nutation with exact Hansen coefficients (first order in the torque)",
    "second_order": "second order in the torque: the equinox drift re-phases the nutation, plus the "
                    "second-order mean rates",
    "numerical": "rotation-averaged torque integrated numerically along the fixed Keplerian orbit",
    "real_orbit": "rotation-averaged torque integrated along the real orbit (DE421 and planetary perturbations)",
}


def _order(order: int | None) -> int | None:
    if order is None:
        return None
    if isinstance(order, bool) or not isinstance(order, int) or order < 0 or order > MAX_ORDER:
        raise InvalidInputError("order", f"eccentricity order must be an integer in [0, {MAX_ORDER}] or omitted "
                                f"for exact Hansen coefficients, got {order!r}")
    return order


def resolve_body(body: str | int | Body, dataset: str = DEFAULT_DATASET) -> Body:
    return body if isinstance(body, Body) else get_body(body, dataset)


def model_for(body: str | int | Body, dataset: str = DEFAULT_DATASET, order: int | None = None) -> PrecessionNutation:
    """Validated model of a catalogue body (by name or NAIF id) or of a :class:`Body`."""
    b = resolve_body(body, dataset)
    order = _order(order)
    if order is not None and b.orbit.e > LAPLACE_LIMIT:
        raise InvalidInputError(
            "order", f"e = {b.orbit.e} exceeds the Laplace limit {LAPLACE_LIMIT:.4f}: the e-power series "
            "diverge; omit the order to use exact Hansen coefficients", b.name)
    return cached_model(b, order)


@lru_cache(maxsize=512)
def _semi_amplitudes(body: Body, order: int | None) -> tuple[float, float]:
    return cached_model(body, order).nutation.semi_peak_to_peak()


def _tolerance(tolerance_mas) -> float | None:
    tolerance_mas = in_unit(tolerance_mas, "mas", "tolerance_mas")
    if tolerance_mas is None:
        return None
    if isinstance(tolerance_mas, bool) or not isinstance(tolerance_mas, (int, float)) \
            or not math.isfinite(tolerance_mas) or tolerance_mas <= 0.0:
        raise InvalidInputError("tolerance_mas", f"must be a positive finite number of milliarcseconds, "
                                f"got {tolerance_mas!r}")
    return float(tolerance_mas) * MAS


def _rung(name) -> str | None:
    if name is None:
        return None
    if name not in RUNGS:
        raise InvalidInputError("model", f"unknown model {name!r}; one of {', '.join(RUNGS)}")
    return name


def _order_for_tolerance(b: Body, tolerance: float | None, order: int | None) -> int | None:
    """The lowest e-order whose truncation error is within the tolerance (None: exact coefficients).

    For the rate and the nutation terms (no time span): the truncation bound alone.
    """
    if tolerance is None:
        return order
    if order is not None:
        raise InvalidInputError("order", "give either order or tolerance_mas, not both")
    m = cached_model(b)
    if m.eccentricity < LAPLACE_LIMIT:
        kmax = int(m.nutation.multiple.max()) if m.nutation.multiple.size else 0
        for n in range(0, min(kmax, MAX_ORDER)):
            if truncation_bound(m, n, 0.0) <= tolerance:
                return n
    return None


def _selection_info(name: str, order: int | None, estimate: float | None, cost_ms: float,
                    tolerance: float | None, terms: dict | None = None) -> dict:
    return {"name": name, "order": order, "description": RUNG_DESCRIPTIONS[name],
            "estimated_error_mas": None if estimate is None else estimate / MAS,
            "error_terms_mas": None if terms is None else {k: v / MAS for k, v in terms.items()},
            "tolerance_mas": None if tolerance is None else float(f"{tolerance / MAS:.12g}"), "cost_ms": cost_ms,
            "axis": None, "free_wobble": None}   # tracks only


def model_info(m: PrecessionNutation, b: Body) -> dict:
    warnings = []
    if abs(math.degrees(m.obliquity) - 90.0) < NEAR_RIGHT_ANGLE_DEG:
        warnings.append("obliquity within 2 deg of 90: the precession rate (∝ cos ε) is small and "
                        "dominated by the obliquity's uncertainty")
    if b.hd_from == "dynamical_ellipticity" and b.hd_from_moments is not None \
            and abs(b.hd - b.hd_from_moments) > 1e-4 * b.hd:
        warnings.append(f"dynamical ellipticity {b.hd:.6g} given explicitly; the catalogue moments imply "
                        f"{b.hd_from_moments:.6g} (see data/errata.toml)")
    return {
        "theory": THEORY,
        "eccentricity_order": "exact" if m.order is None else m.order,
        "assumptions": ASSUMPTIONS + RUNG_ASSUMPTIONS["hansen" if m.order is None else "series"],
        "warnings": warnings,
        "spin_orbit_ratio": m.spin_orbit_ratio,
        "min_spin_orbit_ratio": MIN_SPIN_ORBIT_RATIO,
        "pole_epoch_jd_tdb": m.pole_epoch,
        "orbit_epoch_jd_tdb": m.orbit_epoch,
    }


def list_bodies(dataset: str = DEFAULT_DATASET) -> list[dict]:
    cat = load_catalogue(dataset)
    return [{
        "name": b.name, "naif_id": b.naif_id, "kind": b.kind, "dataset": b.dataset,
        "a_au": b.orbit.a_au, "e": b.orbit.e, "orbit_center": b.orbit.center,
        "rotation_period_hours": b.rotation_period_hours,
        "pole_ra_deg": b.pole.ra_deg, "pole_dec_deg": b.pole.dec_deg,
        "dynamical_ellipticity": b.hd,
    } for b in cat.bodies]


def body_record(body: str | int, dataset: str = DEFAULT_DATASET) -> dict:
    """The full catalogue record: every value with unit, uncertainty and resolved source."""
    b = get_body(body, dataset)
    refs = load_references()
    values = {}
    for key, m in b.values.items():
        values[key] = {"value": m.value, "unit": m.unit, "uncertainty": m.uncertainty,
                       "source": m.source, "reference": refs.get(m.source), "note": m.note}
    return {"name": b.name, "naif_id": b.naif_id, "kind": b.kind, "dataset": b.dataset,
            "orbit_center": b.orbit.center, "dynamical_ellipticity": b.hd,
            "dynamical_ellipticity_from": b.hd_from, "values": values}


def precession(body: str | int | Body, dataset: str = DEFAULT_DATASET, order: int | None = None,
               tolerance_mas: float | None = None, quantities: bool = False) -> dict:
    """Obliquity, H_d, K and the precession rate ψ̇ (Petit et al. Table 4 columns).

    ``tolerance_mas`` picks the lowest e-order whose truncated nutation stays within it
    (the rate is then the truncated one); ``model`` reports what was used.
    """
    start = time.perf_counter()
    b = resolve_body(body, dataset)
    tol = _tolerance(tolerance_mas)
    order = _order_for_tolerance(b, tol, _order(order))
    m = model_for(b, dataset, order)
    per_year = JULIAN_YEAR_DAYS / ARCSEC
    ans = {
        "body": b.name, "dataset": b.dataset,
        "obliquity_deg": math.degrees(m.obliquity),
        "dynamical_ellipticity": m.hd,
        "scaling_factor_arcsec_per_year": m.scaling_factor * per_year,
        "precession_rate_arcsec_per_year": m.precession_rate * per_year,
    }
    unc = _propagated(b, order)
    for key in ("obliquity_deg", "dynamical_ellipticity", "scaling_factor_arcsec_per_year",
                "precession_rate_arcsec_per_year"):
        ans[f"{key}_uncertainty"] = unc[f"{key}_uncertainty"]
    ans["uncertainty"] = _uncertainty_summary(unc)
    ans["model"] = model_info(m, b)
    ans["model"].update(_series_selection(b, order, tol, start))
    return with_units(ans) if quantities else ans


@lru_cache(maxsize=256)
def _propagated(b: Body, order: int | None) -> dict:
    """The 1-σ uncertainties of :func:`ephem.uncertainty.propagate`, with 0 (no input of known σ moves the
    value: its σ is unknown, not zero) replaced by None."""
    from .uncertainty import propagate

    def unknown_as_none(d: dict) -> dict:
        return {k: (None if k.endswith("_uncertainty") and v == 0.0 else v) for k, v in d.items()}

    u = unknown_as_none(propagate(b, b.dataset, order))
    u["terms"] = [unknown_as_none(t) for t in u["terms"]]
    return u


def _uncertainty_summary(u: dict) -> dict:
    return {"method": "linear propagation of the catalogue's 1-sigma uncertainties (ephem.uncertainty); they "
                      "cover only the inputs with a published sigma, and null means no such input moves the "
                      "value (its uncertainty is unknown, not zero)",
            "dominant_input": u["dominant_input"], "unpropagated_inputs": list(u["unpropagated_inputs"]),
            "assumptions": list(u["assumptions"])}


def _series_selection(b: Body, order: int | None, tol: float | None, start: float) -> dict:
    estimate = None if order is None else truncation_bound(cached_model(b), order, 0.0)
    return _selection_info("hansen" if order is None else "series", order, estimate or 0.0,
                           1e3 * (time.perf_counter() - start), tol)


def nutation(body: str | int | Body, dataset: str = DEFAULT_DATASET, order: int | None = None,
             tolerance_mas: float | None = None, quantities: bool = False) -> dict:
    """Nutation terms: Δψ = Σ S sin kM + C cos kM (likewise Δε), arcsec.

    ``tolerance_mas`` picks the lowest e-order whose terms move the pole by no more than
    that from the exact-coefficient series (the bound in ``model.estimated_error_mas``).
    """
    start = time.perf_counter()
    b = resolve_body(body, dataset)
    tol = _tolerance(tolerance_mas)
    order = _order_for_tolerance(b, tol, _order(order))
    m = model_for(b, dataset, order)
    s = m.nutation
    periods = s.period_days
    terms = [{
        "multiple": int(k), "period_days": float(p), "period_years": float(p / JULIAN_YEAR_DAYS),
        "longitude_sin_arcsec": float(a / ARCSEC), "longitude_cos_arcsec": float(c / ARCSEC),
        "obliquity_sin_arcsec": float(d / ARCSEC), "obliquity_cos_arcsec": float(f / ARCSEC),
    } for k, p, a, c, d, f in zip(s.multiple, periods, s.lon_sin, s.lon_cos, s.obl_sin, s.obl_cos)]
    unc = _propagated(b, order)
    sin_eps = abs(math.sin(m.obliquity))
    for term, sigma in zip(terms, unc["terms"]):
        if sigma["multiple"] != term["multiple"]:  # pragma: no cover - both come from the same series
            raise RuntimeError("uncertainty terms out of step with the nutation terms")
        term["period_days_uncertainty"] = sigma["period_days_uncertainty"]
        for comp in ("longitude", "obliquity"):
            for part in ("sin", "cos"):
                term[f"{comp}_{part}_arcsec_uncertainty"] = sigma[f"{comp}_{part}_arcsec_uncertainty"]
            # the paper's Amp: (Sin² + Cos²)^½, times sin ε in longitude
            amp = math.hypot(term[f"{comp}_sin_arcsec"], term[f"{comp}_cos_arcsec"])
            term[f"{comp}_amplitude_arcsec"] = amp * (sin_eps if comp == "longitude" else 1.0)
            term[f"{comp}_amplitude_arcsec_uncertainty"] = sigma[f"amplitude_{comp}_arcsec_uncertainty"]
    half_psi, half_eps = _semi_amplitudes(b, m.order)
    ans = {
        "body": b.name, "dataset": b.dataset, "argument": "mean anomaly M",
        "mean_anomaly_at_epoch_deg": math.degrees(m.mean_anomaly_at_epoch) % 360.0,
        "orbit_epoch_jd_tdb": m.orbit_epoch,
        "mean_motion_deg_per_day": math.degrees(m.mean_motion),
        "obliquity_deg": math.degrees(m.obliquity),
        "terms": terms,
        "delta_psi_half_peak_to_peak_arcsec": half_psi / ARCSEC,
        "delta_epsilon_half_peak_to_peak_arcsec": half_eps / ARCSEC,
        "delta_psi_half_peak_to_peak_arcsec_uncertainty": unc["delta_psi_half_peak_to_peak_arcsec_uncertainty"],
        "delta_epsilon_half_peak_to_peak_arcsec_uncertainty": unc["delta_epsilon_half_peak_to_peak_arcsec_uncertainty"],
        "uncertainty": _uncertainty_summary(unc),
        "model": model_info(m, b),
    }
    ans["model"].update(_series_selection(b, order, tol, start))
    return with_units(ans) if quantities else ans


def epoch_grid(start, stop, step_days: float, max_samples: int = MAX_TRACK_SAMPLES) -> tuple[float, float, int]:
    """(first JD TDB, step in days, count) of the evenly spaced epochs from start to stop.

    stop is included when it falls on the grid.
    """
    t0 = to_jd_tdb(start, "start")
    t1 = to_jd_tdb(stop, "stop")
    step_days = in_unit(step_days, "d", "step_days")
    if isinstance(step_days, bool) or not isinstance(step_days, (int, float)) or not math.isfinite(step_days):
        raise InvalidInputError("step_days", f"must be a finite number, got {step_days!r}")
    if step_days <= 0:
        raise InvalidInputError("step_days", f"must be positive, got {step_days}")
    if t1 < t0:
        raise InvalidInputError("stop", f"stop (JD {t1}) is before start (JD {t0})")
    steps = (t1 - t0) / step_days      # inf for a subnormal step: compared before it becomes an int
    if steps + 1 > max_samples:
        raise InvalidInputError("step_days", f"{steps + 1:.3g} samples exceed the cap of {max_samples}; "
                                "use a larger step or a shorter span")
    count = int(math.floor(steps + 1e-9)) + 1
    if count > max_samples:
        raise InvalidInputError("step_days", f"{count} samples exceed the cap of {max_samples}; "
                                "use a larger step or a shorter span")
    return t0, float(step_days), count


TRACK_KEYS = ("jd_tdb", "psi_arcsec", "delta_psi_arcsec", "delta_epsilon_arcsec", "obliquity_deg",
              "pole_ra_deg", "pole_dec_deg")


AXIS_ASSUMPTIONS = {
    "angular_momentum": "the pole served is the angular momentum, which the free wobble does not move",
    "figure": "the pole served is the figure axis, taken as the angular momentum: the free wobble is left "
              "out and counted in the estimate (free_wobble)",
    "figure+wobble": "the pole served is the figure axis: the torque-free rigid-body wobble (given J and phase) "
                     "added about the forced angular momentum",
}


def _wobble_request(b: Body, axis: str, phase_deg, J_arcsec, epoch):
    if phase_deg is None:
        for name, value in (("free_wobble_J_arcsec", J_arcsec), ("free_wobble_epoch", epoch)):
            if value is not None:
                raise InvalidInputError(name, "give the wobble's phase (free_wobble_phase_deg) with it", b.name)
        return None
    if axis != "figure":
        raise InvalidInputError("free_wobble_phase_deg", "the free wobble moves the figure axis, not the "
                                "angular momentum: ask for axis=figure", b.name)
    from .free_motion import make_wobble

    return make_wobble(b, phase_deg, J_arcsec, None if epoch is None else to_jd_tdb(epoch, "free_wobble_epoch"))


def track_arrays(body: str | int | Body, start, stop, step_days: float, dataset: str = DEFAULT_DATASET,
                 order: int | None = None, max_samples: int = MAX_TRACK_SAMPLES,
                 tolerance_mas: float | None = None, model: str | None = None, axis: str = "figure",
                 free_wobble_phase_deg: float | None = None, free_wobble_J_arcsec: float | None = None,
                 free_wobble_epoch=None) -> dict:
    """As :func:`track`, with numpy arrays instead of lists (for streaming and numerical use)."""
    begin = time.perf_counter()
    b = resolve_body(body, dataset)
    t0, step, count = epoch_grid(start, stop, step_days, max_samples)
    order, tol, rung = _order(order), _tolerance(tolerance_mas), _rung(model)
    if axis not in AXES:
        raise InvalidInputError("axis", f"must be one of {', '.join(AXES)}, got {axis!r}", b.name)
    if tol is not None and (order is not None or rung is not None):
        raise InvalidInputError("tolerance_mas", "give a tolerance, or a model and order, not both")
    if rung is None:
        rung = "hansen" if order is None else "series"
    if rung == "series" and order is None:
        raise InvalidInputError("order", "the 'series' model needs an e-order")
    if order is not None and rung != "series":
        raise InvalidInputError("order", f"an e-order applies to the 'series' model, not to {rung!r}")
    m = model_for(b, dataset, order)
    wobble = _wobble_request(b, axis, in_unit(free_wobble_phase_deg, "deg", "free_wobble_phase_deg"),
                             in_unit(free_wobble_J_arcsec, "arcsec", "free_wobble_J_arcsec"), free_wobble_epoch)
    ladder = Ladder(b, axis, wobble)
    t = t0 + step * np.arange(count)
    if tol is not None:
        est = ladder.choose(t, tol)
        rung, order = est.rung, est.order
    else:   # a named rung follows the wobble whenever its phase is given
        est = next((e for e in ladder.estimates(t) if e.rung == rung and e.order == order
                    and e.free_wobble == (wobble is not None)), None)
    if rung in ("hansen", "series"):   # the fast evaluation on an even grid
        tr = cached_model(b, order).track_grid(t0, step, count)
    else:
        tr = ladder.track(rung, t, order)
    with_wobble = wobble is not None and (est is None or est.free_wobble)
    if with_wobble:
        tr = ladder.add_wobble(tr)
    estimate = None if est is None or not est.available else est.total
    info = model_info(m, b)
    info["assumptions"] = [AXIS_ASSUMPTIONS["figure+wobble" if with_wobble else axis]] + ASSUMPTIONS[1:] \
        + RUNG_ASSUMPTIONS[rung]
    if est is not None and "orbit_motion" in est.unestimated:
        info["warnings"].append("the real orbit's departure from the fixed Keplerian one was never measured for "
                                "this body: the error estimate treats the given orbit as exact (see docs/accuracy.md)")
    if est is not None and "free_wobble" in est.unestimated:
        info["warnings"].append("no free-wobble amplitude is published for this body: the estimate takes its "
                                "figure axis to coincide with the angular momentum (a relaxed rotator)")
    if with_wobble:
        info["warnings"].append("the free wobble added is a rigid body's; its amplitude and phase are yours, "
                                "and the estimate does not include their uncertainty")
    info.update(_selection_info(rung, order, estimate, 1e3 * (time.perf_counter() - begin), tol,
                                None if est is None else est.terms))
    info["axis"] = axis
    info["free_wobble"] = None if not with_wobble else {
        "J_arcsec": wobble.J_arcsec, "phase_deg": wobble.phase_deg, "epoch_jd_tdb": wobble.epoch_jd_tdb}
    return {
        "body": b.name, "dataset": b.dataset,
        "jd_tdb": tr.jd_tdb,
        "psi_arcsec": tr.psi / ARCSEC,
        "delta_psi_arcsec": tr.delta_psi / ARCSEC,
        "delta_epsilon_arcsec": tr.delta_epsilon / ARCSEC,
        "obliquity_deg": np.degrees(tr.obliquity),
        # the mean obliquity's 1σ from the catalogue's uncertainties (null: unknown), as in precession()
        "obliquity_deg_uncertainty": _propagated(b, order)["obliquity_deg_uncertainty"],
        "pole_ra_deg": np.degrees(tr.pole_ra),
        "pole_dec_deg": np.degrees(tr.pole_dec),
        "model": info,
    }


def track(body: str | int | Body, start, stop, step_days: float, dataset: str = DEFAULT_DATASET,
          order: int | None = None, max_samples: int = MAX_TRACK_SAMPLES, tolerance_mas: float | None = None,
          model: str | None = None, axis: str = "figure", free_wobble_phase_deg: float | None = None,
          free_wobble_J_arcsec: float | None = None, free_wobble_epoch=None, quantities: bool = False) -> dict:
    """Spin-axis track: ψ, Δψ, Δε (arcsec), obliquity and pole RA/Dec (deg) at each epoch.

    ``tolerance_mas`` lets the fidelity ladder (:mod:`ephem.ladder`) pick the cheapest model
    whose pole is estimated within that many milliarcseconds of the truth at every epoch;
    ``model`` (a rung name) and ``order`` choose one explicitly. The answer's ``model``
    reports ``name``, ``order``, ``estimated_error_mas`` and ``cost_ms``.

    ``axis``: "figure" (default; the body's axis of largest inertia, which circles the angular
    momentum by the free wobble) or "angular_momentum". ``free_wobble_phase_deg`` (the figure
    axis's position angle about the angular momentum at ``free_wobble_epoch``, default the pole
    epoch, from the ICRF north through east, with the angular momentum in the body's b2-b3 plane
    then) lets the track add the free wobble when the tolerance needs it (or always, with a named
    model); ``free_wobble_J_arcsec`` overrides the published amplitude.

    Times may be astropy ``Time``, unit-named arguments ``Quantity`` (:mod:`ephem.units`);
    ``quantities=True`` returns Quantity arrays and a TDB ``Time`` for ``jd_tdb``.
    """
    ans = track_arrays(body, start, stop, step_days, dataset, order, max_samples, tolerance_mas, model, axis,
                       free_wobble_phase_deg, free_wobble_J_arcsec, free_wobble_epoch)
    if quantities:
        return with_units(ans)
    for key in TRACK_KEYS:
        ans[key] = ans[key].tolist()
    return ans


FREE_MOTION_KEYS = ("jd_tdb", "figure_axis_offset_x_arcsec", "figure_axis_offset_y_arcsec",
                    "wobble_angle_J_arcsec", "andoyer_nu_deg")


def free_motion_arrays(body: str | int | Body, start, stop, step_days: float, J_arcsec: float | None = None,
                       method: str = "auto", dataset: str = DEFAULT_DATASET,
                       max_samples: int = MAX_TRACK_SAMPLES) -> dict:
    """The torque-free wobble: the figure axis's offsets from the angular momentum (arcsec) over time,
    the angle J and Andoyer's ν, and the periods (see :mod:`ephem.free_motion`). J defaults to the
    published amplitude (Lara 2014 Table 1: Earth, Moon, Mars, Eros)."""
    from .free_motion import free_motion

    b = resolve_body(body, dataset)
    t0, step, count = epoch_grid(start, stop, step_days, max_samples)
    return free_motion(b, t0 + step * np.arange(count), in_unit(J_arcsec, "arcsec", "J_arcsec"), method)


def free_motion_answer(body: str | int | Body, start, stop, step_days: float, J_arcsec: float | None = None,
                       method: str = "auto", dataset: str = DEFAULT_DATASET, quantities: bool = False) -> dict:
    """As :func:`free_motion_arrays`, with lists (or, with ``quantities=True``, Quantity arrays)."""
    ans = free_motion_arrays(body, start, stop, step_days, J_arcsec, method, dataset)
    if quantities:
        return with_units(ans)
    for key in FREE_MOTION_KEYS:
        ans[key] = np.asarray(ans[key]).tolist()
    return ans
